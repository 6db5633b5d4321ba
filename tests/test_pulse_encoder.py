"""The wheelset-speed encoder as a pulse generator (cof_gym.physics.encoder): the period method's reading, the
target wheel's runout, the delay the pulses add to every lag the lock-in reads, and an encoder that no draw gives."""

from __future__ import annotations

import math

import gymnasium as gym
import mujoco
import numpy as np
import pytest

import cof_gym
from cof_gym.physics.creep import OperatingConditions
from cof_gym.physics.encoder import PULSES_PER_REV_RANGE, RUNOUT_MAX, PulseEncoder
from cof_gym.physics.models import DEFAULT_TIMESTEP_S, build_half_wheelset
from cof_gym.physics import simulation
from cof_gym.physics.native.layout import OFFSETS
from cof_gym.physics.simulation import Scenario, Simulation
from cof_gym.task.scenarios import V2_RANGES, outside_draws
from held_windows import FREQUENCY_HZ, QUIET, held_windows  # tests/ is on sys.path (pytest rootdir)
from test_track_irregularity import play  # tests/ is on sys.path (pytest rootdir)
from test_vector_env import assert_batched_plays_as_sync, same

SPEED_M_S = 10.0
STEPS = 3000  # 3 s at 1 kHz: 65 rad of a 0.46 m wheel at 10 m/s
SETTLED = 100  # the first 0.1 s left out: a pulse encoder reads from its second pulse


def steady_readings(encoder: PulseEncoder) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The encoder's reading, the wheel's spin rate and its angle since the reset (the hinge joint's, not the
    encoder's own integration), step by step, on the half wheelset rolling at 10 m/s without torque (a spin rate
    steady to its last bits). Each row's reading was taken at the step's start, the angle at its end's start
    (the next callback's time)."""
    built = build_half_wheelset()
    sim = Simulation(built)
    op = OperatingConditions(cof=0.3, condition="dry", wheel_load_n=built.nominal_wheel_load_n, speed_m_s=SPEED_M_S)
    sim.reset(Scenario(op=op, encoder=encoder))
    dof, _ = built.spin_dofs[0]
    qadr = int(built.model.jnt_qposadr[list(built.model.jnt_dofadr).index(dof)])
    start = float(sim.data.qpos[qadr])
    readings, spins, angles = [], [], []
    for _ in range(STEPS):
        angles.append(float(sim.data.qpos[qadr]) - start)
        mujoco.mj_step(sim.model, sim.data)
        readings.append(float(sim.data.userdata[OFFSETS["ENCODER_READING"]]))
        spins.append(float(sim.data.qvel[dof]))
    return np.array(readings)[SETTLED:], np.array(spins)[SETTLED:], np.array(angles)[SETTLED:]


def first_harmonic(relative: np.ndarray, angle: np.ndarray) -> tuple[float, float]:
    """Amplitude and lag (rad of the wheel's angle) of ``relative``'s once-per-revolution part: the least-squares
    fit of ``a + b cos(angle) + c sin(angle)``."""
    basis = np.column_stack([np.ones_like(angle), np.cos(angle), np.sin(angle)])
    _, b, c = np.linalg.lstsq(basis, relative, rcond=None)[0]
    return math.hypot(b, c), math.atan2(c, b)


def test_pulses_on_a_steady_wheel_read_its_spin_rate():
    """One pitch over the interval between two pulses is the spin rate where the spin is steady. The pulses' times
    carry the angle's rounding (65 rad x 2^-52 over a pitch of 0.063 rad: about 1e-13 of an interval); held to
    1e-9."""
    readings, spins, _ = steady_readings(PulseEncoder(pulses_per_rev=100))
    assert np.ptp(spins) < 1e-12 * spins.mean()
    assert np.max(np.abs(readings / spins - 1.0)) < 1e-9


def test_runout_reads_a_ripple_at_the_wheels_rotation():
    """Without pulses a runout ``e`` reads ``omega (1 + e cos theta)`` at the wheel's angle: the fitted
    once-per-revolution part is ``e`` with no lag (the encoder's trapezoid angle is the hinge's to rounding)."""
    e = 0.001
    readings, spins, angles = steady_readings(PulseEncoder(runout=e))
    relative = readings / spins - 1.0
    assert np.max(np.abs(relative - e * np.cos(angles))) < 1e-9
    amplitude, lag = first_harmonic(relative, angles)
    assert amplitude == pytest.approx(e, rel=1e-6)
    assert abs(lag) < 1e-6


@pytest.mark.parametrize("pulses", [60, 100])
def test_pulses_average_the_ripple_over_a_pitch_and_read_it_about_a_pitch_late(pulses):
    """With pulses the reading is the ripple's mean over the last pitch ``p`` (a gain ``sin(p/2) / (p/2)`` and a lag
    of ``p/2`` in the wheel's angle), held until the next pulse: on average another ``p/2`` late, and a gain of
    ``sin(p/2) / (p/2)`` again where the hold is uniform over the pitch. The 1 kHz steps sample the hold at most
    ``omega dt / 2`` from uniform (0.011 rad at 10 m/s): the lag is within that of ``p``, and the gain between
    the two bounds."""
    e, pitch = 0.005, 2.0 * math.pi / pulses
    readings, spins, angles = steady_readings(PulseEncoder(pulses_per_rev=pulses, runout=e))
    amplitude, lag = first_harmonic(readings / spins - 1.0, angles)
    sinc = math.sin(pitch / 2) / (pitch / 2)
    # the ripple's second harmonic (e^2 / 2 of the apparent angle's rate) is what the bounds leave room for
    assert e * sinc**2 - e**2 <= amplitude <= e * sinc + e**2
    assert lag == pytest.approx(pitch, abs=spins.mean() * DEFAULT_TIMESTEP_S / 2)


def last_window(speed_m_s: float, **options) -> dict:
    """The readings of the third window at a low DC torque and a small 5 Hz modulation on the half wheelset."""
    return held_windows(cof_gym.HALF_WHEELSET_ENV_ID, {**QUIET, "speed_m_s": speed_m_s, **options}, 3)[-1]


@pytest.mark.parametrize("speed_m_s, pulses", [(10.0, 100), (5.0, 60)])
def test_the_pulses_add_about_one_interval_to_every_lag_the_lock_in_reads(speed_m_s, pulses):
    """The lag between torque and speed grows by ``360 f T_p`` (deg), ``T_p`` the interval between pulses (5.2 deg
    with 100 pulses at 10 m/s, 17 deg with 60 at 5 m/s), within the hold's sampling (``360 f dt / 2``, 0.9 deg). The
    compliance shrinks by the interval's averaging, ``sinc(w T_p / 2)``, and by the hold's: a mean of phasors
    ``exp(-i w u)`` over holds ``u`` within ``[0, T_p + dt]``, at least ``cos(w (T_p + dt) / 2)`` in magnitude. The
    creepage's window mean, a mean of the same speed, moves by the lag's effect on a 5 Hz line only (a few 1e-6)."""
    plain = last_window(speed_m_s)
    pulsed = last_window(speed_m_s, encoder_pulses_per_rev=pulses)
    interval = PulseEncoder(pulses).pulse_interval_s(speed_m_s / build_half_wheelset().wheel_radius_m)
    assert pulsed["phase_lag_deg"] - plain["phase_lag_deg"] == pytest.approx(
        360.0 * FREQUENCY_HZ * interval, abs=360.0 * FREQUENCY_HZ * DEFAULT_TIMESTEP_S / 2)
    w = 2.0 * math.pi * FREQUENCY_HZ
    averaging = math.sin(w * interval / 2) / (w * interval / 2)
    assert averaging * math.cos(w * (interval + DEFAULT_TIMESTEP_S) / 2) <= (
        pulsed["amplitude_ratio"] / plain["amplitude_ratio"]) <= 1.0
    assert pulsed["creepage_measured"] == pytest.approx(plain["creepage_measured"], abs=1e-5)


def test_no_pulses_and_no_runout_is_the_default_and_an_encoder_moves_no_other_draw():
    """``encoder_pulses_per_rev=0`` and ``encoder_runout=0`` play the episode the default plays, bit for bit; a
    pulse encoder changes the readings, not the physics nor any drawn field: the episode's truth is the default's
    but for the paper's ``creep_phase_lag_deg`` (the true creepage's lag behind the speed the *encoder* reads, which
    an encoder lag moves too)."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    default = play(env, 4, {})
    assert default[1]["encoder_pulses_per_rev"] == 0 and default[1]["encoder_runout"] == 0.0
    assert same(play(env, 4, {"encoder_pulses_per_rev": 0, "encoder_runout": 0.0}), default)
    options = {"encoder_pulses_per_rev": 100, "encoder_runout": 0.0005}
    pulsed = play(env, 4, options)
    assert {k: pulsed[1][k] for k in options} == options
    apart = (*options, "creep_phase_lag_deg")
    assert same({k: v for k, v in pulsed[1].items() if k not in apart},
                {k: v for k, v in default[1].items() if k not in apart})
    assert pulsed[4]["phase_lag_deg"] != default[4]["phase_lag_deg"]
    env.close()


@pytest.mark.parametrize("lock_in", ["plain", "rotation"])
def test_the_batched_env_reads_the_same_pulses(lock_in):
    """The vector env (mujoco.batch) plays a pulse encoder with runout, read by either lock-in, bit for bit as
    gymnasium's SyncVectorEnv of single envs does (every observation, reward, flag and info)."""
    assert_batched_plays_as_sync({"encoder_pulses_per_rev": 80, "encoder_runout": 0.001}, lock_in=lock_in)


@pytest.mark.parametrize("name, value, match", [
    ("encoder_pulses_per_rev", PULSES_PER_REV_RANGE[0] - 1, r"encoder_pulses_per_rev must be 0 \(a continuous "
                                                            r"reading\) or an integer in \[8, 10000\], got 7"),
    ("encoder_pulses_per_rev", PULSES_PER_REV_RANGE[1] + 1, r"encoder_pulses_per_rev .* got 10001"),
    ("encoder_pulses_per_rev", 100.0, r"encoder_pulses_per_rev .* got 100\.0 \(float\)"),
    ("encoder_pulses_per_rev", True, r"encoder_pulses_per_rev .* got True \(bool\)"),
    ("encoder_pulses_per_rev", -1, r"encoder_pulses_per_rev .* got -1"),
    ("encoder_runout", -1e-4, r"encoder_runout must be a finite number in \[0, 0\.01\], got -0\.0001"),
    ("encoder_runout", 2 * RUNOUT_MAX, r"encoder_runout must be a finite number in \[0, 0\.01\]"),
    ("encoder_runout", math.nan, r"encoder_runout must be a finite number"),
])
def test_a_bad_encoder_is_refused_naming_the_field_and_its_range(name, value, match):
    env = gym.make(cof_gym.HALF_WHEELSET_ENV_ID)
    with pytest.raises(ValueError, match=match):
        env.reset(seed=0, options={name: value})
    env.close()


def test_an_encoder_with_pulses_or_runout_is_outside_the_v2_draws():
    assert outside_draws({"encoder_pulses_per_rev": 100, "encoder_runout": 0.001}, V2_RANGES) == {
        "encoder_pulses_per_rev": "100, drawn: 0 (a continuous reading)",
        "encoder_runout": "0.001, drawn: 0"}
    assert outside_draws({"encoder_pulses_per_rev": 0, "encoder_runout": 0.0}, V2_RANGES) == {}


def tone_lags(lock_in: str, speed_m_s: float, tones: int = 1, **options) -> list[float]:
    """Each tone's lag (deg) in the third window on the half wheelset: one 5 Hz tone, or three at 3, 7 and 17 Hz
    (test_multitone's set without second-order coincidences) at a low DC torque."""
    kwargs = {"excitation": "multitone", "tones": tones} if tones > 1 else {}
    info = held_windows(cof_gym.HALF_WHEELSET_ENV_ID, {**QUIET, "speed_m_s": speed_m_s, **options}, 3,
                        (FREQUENCY_HZ,) if tones == 1 else (3.0, 7.0, 17.0), lock_in=lock_in, **kwargs)[-1]
    if tones == 1:
        return [info["phase_lag_deg"]]
    return [info[f"tone{k}_phase_lag_deg"] for k in range(1, tones + 1)]


@pytest.mark.parametrize("tones, speed_m_s, pulses, runout", [(1, 10.0, 100, 0.002), (1, 10.0, 60, 0.01),
                                                                (1, 10.0, 0, 0.001), (3, 14.0, 100, 0.002)])
def test_the_rotation_lock_in_takes_a_runouts_ripple_out_of_every_tones_lag(tones, speed_m_s, pulses, runout):
    """A runout's ripple (0.02-0.2 rad/s at 10 m/s, 10-100 times a small modulation's response) turns the plain
    lock-in's lag by tens of degrees; the rotation lock-in, which also fits the first two harmonics of the angle the
    encoder counts (the reading's ripple is a function of the pulse count, to the runout's third order), reads the
    lag the pulses alone give. What it cannot take out is the ripple's product with the modulation's own speed
    response, sidebands of relative size ``e / 2`` at the tone's frequency plus and minus the rotation's: within
    ``e`` rad of the lag (0.11-0.57 deg here)."""
    without = tone_lags("plain", speed_m_s, tones, encoder_pulses_per_rev=pulses)
    plain = tone_lags("plain", speed_m_s, tones, encoder_pulses_per_rev=pulses, encoder_runout=runout)
    rotation = tone_lags("rotation", speed_m_s, tones, encoder_pulses_per_rev=pulses, encoder_runout=runout)
    assert max(abs(p - w) for p, w in zip(plain, without)) > 10.0
    assert rotation == pytest.approx(without, abs=math.degrees(runout))


def test_the_rotation_lock_in_reads_no_ripple_where_there_is_none_and_a_bad_one_is_refused():
    """Without runout the rotation pairs fit what is left of the plain fit's residual, within the lag's own
    standard error; ``lock_in`` takes only the names it documents."""
    plain, rotation = tone_lags("plain", 10.0), tone_lags("rotation", 10.0)
    assert rotation == pytest.approx(plain, abs=0.05)
    with pytest.raises(ValueError, match=r"lock_in must be one of \['plain', 'rotation'\], got 'sync'"):
        gym.make(cof_gym.HALF_WHEELSET_ENV_ID, lock_in="sync")


def noisy_window(lock_in: str, speed_m_s: float) -> dict:
    """A half-wheelset window with the drawn noise at full scale, a 5 Hz modulation, the continuous encoder."""
    return held_windows(cof_gym.HALF_WHEELSET_ENV_ID, {**QUIET, "noise_level": 1.0, "speed_m_s": speed_m_s}, 1,
                        dc=-0.5, amplitude=0.6, lock_in=lock_in)[0]


@pytest.mark.parametrize("harmonic", [1, 2])
def test_a_rotation_harmonic_at_the_modulations_frequency_is_left_out_not_fitted(harmonic, monkeypatch):
    """Where the wheel turns at 5 Hz (14.45 m/s) or at half that (7.23 m/s), that harmonic of the counted angle and the
    tone are nearly one regressor over the window: fitted together, the tone's lag carries almost no information
    (its SE more than ten times the plain lock-in's: 88 and 180 deg here, against 5 and 10). The
    rotation lock-in leaves out a harmonic that would raise a tone's coefficient variance more than
    MAX_ROTATION_INFLATION (2) times, so its lag's SE stays within sqrt(2) of the plain lock-in's, whichever other
    harmonic it keeps."""
    speed = FREQUENCY_HZ / harmonic * 2.0 * math.pi * build_half_wheelset().wheel_radius_m
    plain, rotation = noisy_window("plain", speed), noisy_window("rotation", speed)
    assert rotation["phase_lag_se_deg"] <= math.sqrt(2.0) * plain["phase_lag_se_deg"] < 90.0
    monkeypatch.setattr(simulation, "MAX_ROTATION_INFLATION", math.inf)
    assert noisy_window("rotation", speed)["phase_lag_se_deg"] > 10.0 * plain["phase_lag_se_deg"]


@pytest.mark.parametrize("pulses, speed_m_s", [(0, 10.0), (100, 10.0), (0, 20.0)])
def test_the_rotation_lock_in_reads_the_runouts_ripple_where_it_tells_it_from_the_tone(pulses, speed_m_s):
    """``rotation_ripple_rad_s``: the first harmonic of the counted angle in the speed reads the runout's ripple, ``e``
    times the spin rate (``omega (1 + e cos theta)``; the period method averages it over a pitch, sinc(pi / 100) = 1 -
    1.6e-4), its phase to within a degree; the spin rate is ``v / r`` to the creepage at this low DC torque (< 1e-3).
    The plain lock-in reads none (0 and an SE of 180), nor does the rotation lock-in where it leaves the harmonic out
    (the wheel turning at the tone's 5 Hz)."""
    runout = 0.002
    options = {**QUIET, "speed_m_s": speed_m_s, "encoder_pulses_per_rev": pulses, "encoder_runout": runout}
    m = held_windows(cof_gym.HALF_WHEELSET_ENV_ID, options, 1, lock_in="rotation")[0]
    wheel_radius = build_half_wheelset().wheel_radius_m
    assert m["rotation_ripple_rad_s"] == pytest.approx(runout * speed_m_s / wheel_radius, rel=2e-3)
    assert m["rotation_ripple_phase_se_deg"] < 1.0
    plain = held_windows(cof_gym.HALF_WHEELSET_ENV_ID, options, 1)[0]
    coincident = {**options, "speed_m_s": FREQUENCY_HZ * 2.0 * math.pi * wheel_radius}
    left_out = held_windows(cof_gym.HALF_WHEELSET_ENV_ID, coincident, 1, lock_in="rotation")[0]
    for unread in (plain, left_out):
        assert (unread["rotation_ripple_rad_s"], unread["rotation_ripple_phase_se_deg"]) == (0.0, 180.0)
