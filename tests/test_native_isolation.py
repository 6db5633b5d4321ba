"""The process-global native callback keeps every simulation's state in its own userdata.

Simulations of different models interleaved in one process, foreign MuJoCo models, mujoco.batch rows
and seeded sensor noise must all behave exactly as if each simulation were alone.
"""

from __future__ import annotations

import dataclasses
import math

import mujoco
import mujoco.batch
import numpy as np
import pytest

from cof_gym.physics.creep import OperatingConditions
from cof_gym.physics.models import BuiltModel, build_half_wheelset, build_wagon
from cof_gym.physics.native import layout
from cof_gym.physics.native.build import install_callback
from cof_gym.physics.simulation import (
    DriveCommand,
    Scenario,
    SensorNoise,
    Simulation,
    WindowMeasurement,
    begin_window,
    initial_state,
    initial_userdata,
    read_window,
)
from cof_gym.physics.vehicle import wagon_parameters

SPEED = 10.0


def _scenario(built: BuiltModel, cof: float, **kwargs) -> Scenario:
    op = OperatingConditions(cof=cof, condition="dry", wheel_load_n=built.nominal_wheel_load_n, speed_m_s=SPEED)
    return Scenario(op, **kwargs)


def _windows(built: BuiltModel, cof: float) -> list[tuple[DriveCommand, float, float, float]]:
    """(drive, duration, settle, ramp) for a short staircase with a change of modulation."""
    m_sat = built.saturation_torque_per_cof * cof
    return [
        (DriveCommand(0.3 * m_sat, 345.0, 5.0), 0.5, 0.2, 0.2),
        (DriveCommand(0.8 * m_sat, 345.0, 5.0), 0.5, 0.2, 0.2),
        (DriveCommand(0.9 * m_sat, 200.0, 8.0), 0.5, 0.2, 0.1),
    ]


def _assert_no_nan(m: WindowMeasurement) -> None:
    values = dataclasses.astuple(m)
    assert all(math.isfinite(v) for v in values), m  # NaN would make == fail for the wrong reason


# ------------------------------------------------------------------ two models, one process


def test_interleaved_models_are_bit_identical_to_alone() -> None:
    half_cof, wagon_cof = 0.3, 0.45

    def fresh():
        half = build_half_wheelset()
        wagon = build_wagon(wagon_parameters("laden"))
        sh, sw = Simulation(half), Simulation(wagon)
        sh.reset(_scenario(half, half_cof))
        sw.reset(_scenario(wagon, wagon_cof, noise=SensorNoise(0.01, 0.01, 0.01), seed=3))
        return sh, sw

    # each alone
    alone_h, _ = fresh()
    meas_h = [alone_h.run_window(d, dur, settle, ramp) for d, dur, settle, ramp in _windows(alone_h.built, half_cof)]
    _, alone_w = fresh()
    meas_w = [alone_w.run_window(d, dur, settle, ramp) for d, dur, settle, ramp in _windows(alone_w.built, wagon_cof)]

    # interleaved window by window
    sh, sw = fresh()
    inter_h, inter_w = [], []
    for wh, ww in zip(_windows(sh.built, half_cof), _windows(sw.built, wagon_cof)):
        inter_h.append(sh.run_window(*wh))
        inter_w.append(sw.run_window(*ww))

    for a, b in zip(meas_h + meas_w, inter_h + inter_w):
        _assert_no_nan(a)
        assert a == b
    for alone, inter in ((alone_h, sh), (alone_w, sw)):
        assert np.array_equal(alone.data.qpos, inter.data.qpos)
        assert np.array_equal(alone.data.qvel, inter.data.qvel)
        assert np.array_equal(alone.data.userdata, inter.data.userdata)
    # the two runs are genuinely different simulations (not a degenerate shared state)
    assert meas_h[-1].coa_true != pytest.approx(meas_w[-1].coa_true, rel=1e-3)
    assert meas_h[-1].coa_true == pytest.approx(0.9 * half_cof, rel=1e-2)


# ------------------------------------------------------------------ foreign models

FOREIGN_XML = """
<mujoco>
  <size nuserdata="{nuserdata}"/>
  <option timestep="0.002"/>
  <worldbody>
    <body name="box" pos="0 0 2">
      <freejoint/>
      <geom type="box" size="0.1 0.2 0.3" mass="2" contype="0" conaffinity="0"/>
      <body name="flap" pos="0.2 0 0">
        <joint name="hinge" type="hinge" axis="0 1 0" stiffness="40" damping="0.5" springref="0.3"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="0.3" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def _foreign_model(nuserdata: int) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(FOREIGN_XML.format(nuserdata=nuserdata))


def _foreign_userdata(kind: str, n: int) -> np.ndarray:
    if kind == "zeros":
        return np.zeros(n)
    if kind == "wagon-marked":  # a wagon's own userdata, marker and all: its bodies and dofs lie past this model's
        wagon = build_wagon(wagon_parameters("laden"))
        return initial_userdata(wagon, _scenario(wagon, 0.3))
    # plausible-looking numbers everywhere except the marker
    ud = np.random.default_rng(0).uniform(-1.0, 5.0, n)
    ud[layout.index("MAGIC")] = 0.0
    ud[layout.index("N_CONTACTS")] = 1.0
    return ud


def _foreign_trajectory(model: mujoco.MjModel, ud0: np.ndarray, partner: Simulation | None, nstep: int = 400):
    data = mujoco.MjData(model)
    data.qvel[:] = [0.5, -0.2, 1.0, 0.3, 0.7, -0.4, 2.0]
    if model.nuserdata:
        data.userdata[:] = ud0
    qpos, passive = [], []
    for _ in range(nstep):
        mujoco.mj_step(model, data)
        if partner is not None:  # a cof_gym simulation stepped in between, through the same callback
            mujoco.mj_step(partner.model, partner.data)
        qpos.append(data.qpos.copy())
        passive.append(data.qfrc_passive.copy())
    return np.array(qpos), np.array(passive), data.userdata.copy()


@pytest.mark.parametrize(
    ("nuserdata", "kind"),
    [(0, "zeros"), (300, "zeros"), (layout.SIZE, "zeros"), (layout.SIZE, "unmarked"), (layout.SIZE, "wagon-marked")],
    ids=["nuserdata0", "nuserdata300", "nuserdataSIZE", "unmarked-garbage", "marked-indices-outside-the-model"],
)
def test_foreign_model_is_untouched_by_the_callback(nuserdata: int, kind: str) -> None:
    install_callback()
    assert mujoco.get_mjcb_passive() is not None
    model = _foreign_model(nuserdata)
    ud0 = _foreign_userdata(kind, nuserdata)

    half = build_half_wheelset()
    partner = Simulation(half)
    op = OperatingConditions(cof=0.3, wheel_load_n=half.nominal_wheel_load_n, speed_m_s=SPEED)
    partner.reset(Scenario(op))
    begin_window(partner.data.userdata, partner.data.time, DriveCommand(0.5 * 0.46 * 100e3 * 0.3, 345.0, 5.0),
                 0.1, 0.0)
    with_cb = _foreign_trajectory(model, ud0, partner)
    # the callback really was active for the partner while the foreign model stepped
    assert partner.data.userdata[layout.index("N_SAMPLES")] > 0
    assert abs(partner.data.userdata[layout.index("LAST_COA")]) > 0.01

    try:
        mujoco.set_mjcb_passive(None)
        without_cb = _foreign_trajectory(model, ud0, None)
    finally:
        install_callback()
    assert mujoco.get_mjcb_passive() is not None

    for a, b in zip(with_cb, without_cb):
        assert np.array_equal(a, b)
    np.testing.assert_array_equal(with_cb[2], ud0)  # userdata not written
    # sanity: the foreign body fell under gravity and its spring acted (passive forces non-zero)
    assert with_cb[0][-1, 2] < 2.0 - 0.5 * 9.81 * 0.7**2 + 1.0
    assert np.abs(with_cb[1]).max() > 0.1


def test_a_built_model_refuses_indices_outside_it() -> None:
    """Every body, dof and qpos index the callback will read lies in the model: one outside is refused, naming it."""
    half = build_half_wheelset()
    contact = half.contacts[0]
    with pytest.raises(ValueError, match=r"contacts\[0\]\.wheel_body must be an integer in \[1, 2\], got 3"):
        dataclasses.replace(half, contacts=[dataclasses.replace(contact, wheel_body=half.model.nbody)])
    with pytest.raises(ValueError, match=r"contacts\[0\]\.z_dof must be an integer in \[0, 1\], got -1"):
        dataclasses.replace(half, contacts=[dataclasses.replace(contact, z_qpos=0)])
    with pytest.raises(ValueError, match=r"measured_contact must be an integer in \[0, 0\], got 1"):
        dataclasses.replace(half, measured_contact=1)
    with pytest.raises(ValueError, match=r"contacts: 1 to 4 contacts, got 5"):
        dataclasses.replace(half, contacts=[contact] * 5)


def test_reinstalled_callback_drives_cof_gym_again() -> None:
    built = build_half_wheelset()
    op = OperatingConditions(cof=0.3, wheel_load_n=built.nominal_wheel_load_n, speed_m_s=SPEED)
    drive = DriveCommand(0.5 * built.saturation_torque_per_cof * 0.3, 345.0, 5.0)
    results = []
    for toggle in (False, True):
        if toggle:
            mujoco.set_mjcb_passive(None)
            install_callback()
        sim = Simulation(built)
        sim.reset(Scenario(op))
        results.append(sim.run_window(drive, 0.6, 0.2, 0.1))  # 2 modulation periods measured
    assert results[0] == results[1]
    assert results[1].coa_true == pytest.approx(0.15, rel=2e-3)


# ------------------------------------------------------------------ mujoco.batch


def test_batch_rows_are_bit_identical_to_single_simulations() -> None:
    built = build_wagon(wagon_parameters("laden"))
    cofs = (0.1, 0.2, 0.35, 0.5)
    scenarios = [
        _scenario(built, cof, noise=SensorNoise(0.01, 0.01, 0.01) if k % 2 else SensorNoise(), seed=10 + k,
                  motor_lag_s=0.01 * k)
        for k, cof in enumerate(cofs)
    ]
    drives = [
        [DriveCommand(f * built.saturation_torque_per_cof * cof, 345.0 + 50 * k, 5.0 + k)
         for f in (0.6, 0.9)]
        for k, cof in enumerate(cofs)
    ]
    nstep = 600

    singles = [Simulation(built) for _ in cofs]
    for sim, sc in zip(singles, scenarios):
        sim.reset(sc)  # initial_state + initial_userdata + mj_forward

    batch = mujoco.batch.Batch(built.model, nsim=len(cofs), nthread=2)
    qpos, qvel, ud, time = (batch.bind(name) for name in ("qpos", "qvel", "userdata", "time"))
    for k, sc in enumerate(scenarios):
        initial_state(built, sc.op.speed_m_s, qpos[k], qvel[k])
        ud[k] = initial_userdata(built, sc)
    batch.forward()
    assert np.array_equal(ud, np.array([s.data.userdata for s in singles]))

    for window in range(2):
        for k, sim in enumerate(singles):
            begin_window(sim.data.userdata, sim.data.time, drives[k][window], 0.2, 0.2)
            begin_window(ud[k], float(time[k]), drives[k][window], 0.2, 0.2)
        batch.step(nstep=nstep)
        for sim in singles:
            mujoco.mj_step(sim.model, sim.data, nstep)
        for k, sim in enumerate(singles):
            assert time[k] == sim.data.time
            assert np.array_equal(qpos[k], sim.data.qpos), f"row {k}, window {window}"
            assert np.array_equal(qvel[k], sim.data.qvel), f"row {k}, window {window}"
            assert np.array_equal(ud[k], sim.data.userdata), f"row {k}, window {window}"
            assert read_window(np.array(ud[k])) == read_window(sim.data.userdata)

    # the rows really are different simulations
    coas = [read_window(np.array(ud[k])).coa_true for k in range(len(cofs))]
    np.testing.assert_allclose(coas, [0.9 * c for c in cofs], rtol=0.02)


# ------------------------------------------------------------------ seeded sensor noise


def _noisy_run(seed: int):
    built = build_half_wheelset()
    sim = Simulation(built)
    sim.reset(_scenario(built, 0.3, noise=SensorNoise(omega_rad_s=0.05, force_relative=0.02, speed_m_s=0.05),
                        seed=seed))
    drive = DriveCommand(0.7 * built.saturation_torque_per_cof * 0.3, 345.0, 5.0)
    m = sim.run_window(drive, 1.0, 0.3, 0.2)
    return m, sim.data.qpos.copy(), sim.data.qvel.copy()


def test_sensor_noise_is_reproducible_per_seed() -> None:
    a, qa, va = _noisy_run(7)
    b, qb, vb = _noisy_run(7)
    c, qc, vc = _noisy_run(8)
    _assert_no_nan(a)
    assert a == b
    assert a != c
    for field in ("phase_lag_deg", "coa_measured", "speed_measured_m_s", "omega_amplitude_rad_s"):
        assert getattr(a, field) != getattr(c, field), field
    # noise is on the sensors only: the physics (and the true adhesion) does not depend on the seed
    assert np.array_equal(qa, qc) and np.array_equal(va, vc)
    assert a.coa_true == c.coa_true
    assert a.coa_measured != a.coa_true


def test_a_window_puts_the_callback_back_where_something_replaced_it() -> None:
    """MuJoCo's passive callback is process-global: where another library (or a user) replaced or cleared it after
    an env was made, the next reset and window install cof_gym's again (with a warning for a replaced one) instead of
    reading windows that accumulated nothing ('window too short')."""
    import warnings

    import gymnasium as gym

    import cof_gym

    env = gym.make(cof_gym.HALF_WHEELSET_ENV_ID)
    env.reset(seed=0)
    mujoco.set_mjcb_passive(None)  # cleared: reinstalled silently
    obs, *_ = env.step(env.action_space.sample())
    assert np.isfinite(obs).all()
    mujoco.set_mjcb_passive(lambda m, d: None)  # replaced: reinstalled, and said so
    with pytest.warns(RuntimeWarning, match="replaces the mjcb_passive callback"):
        env.reset(seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # in place now: the window installs nothing more
        obs, *_ = env.step(env.action_space.sample())
    assert np.isfinite(obs).all()
    env.close()
