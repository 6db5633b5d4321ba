"""The multi-tone excitation (env option ``excitation="multitone"``, :mod:`cof_gym.task.excitation`): every
tone measured by its own lock-in matches the paper's Eq. 3 at its frequency on the half wheelset, the
default sine is bit-identical to not passing the option, the spaces are what the docstring says, bad
values name the field, and a silent extra tone leaves tone 1's phase where the sine puts it."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import cof_gym  # noqa: F401  (registers the ids)
from cof_gym.analysis.theory import creep_slope_at_torque, phase_eq3_deg
from cof_gym.measurement.sine_fit import fit_samples, fit_tones_from_sums, tone_sums
from cof_gym.physics.simulation import FREQUENCY_RANGE_HZ, DriveCommand
from cof_gym.physics.vehicle import HalfWheelsetParameters
from cof_gym.task.excitation import Excitation, separate
from cof_gym.task.interface import _log_unmap
from exact_sensors import QUIET

P = HalfWheelsetParameters()
IW, R, N = P.spin_inertia_kg_m2, P.wheel_radius_m, P.normal_load_n
HALF = "CofGym/HalfWheelset-v2"
WAGON = "CofGym/TorqueInterrogation-v1"
# the half wheelset's Eq. 3 window (tests/test_half_wheelset_eq3.py): 2 s, 1 s settling, 0.5 s DC ramp
EQ3_WINDOW = dict(window_s=2.0, settle_fraction=0.5, ramp_fraction=0.25)


def _action(env, dc: float, total_amp: float, freqs: tuple[float, ...], shares: tuple[float, ...] = ()) -> np.ndarray:
    """Absolute action: DC, total amplitude, tone 1's frequency, then (frequency, share) per extra tone."""
    task = env.unwrapped.task
    lim = task.limits
    base = task.actions.encode(env.unwrapped.episode.action_context, dc, total_amp, freqs[0], 0.3, False, lim)
    extra = []
    for k, f in enumerate(freqs[1:]):
        extra += [_log_unmap(f, lim.min_frequency_hz, lim.max_frequency_hz), shares[k] if shares else 0.0]
    return np.concatenate([base, np.asarray(extra, dtype=np.float32)]).astype(np.float32)


def _eq3_tolerance(phi_eq3: float, se: float) -> float:
    """tests/test_half_wheelset_eq3.py's model tolerance (max(0.2 deg, 5 %): small-signal Eq. 3 against the
    nonlinear simulation) plus 3 standard errors of the tone's fit."""
    return max(0.2, 0.05 * phi_eq3) + 3.0 * se


# tone sets without second-order coincidences (no tone at f_i + f_j, |f_i - f_j| or 2 f_i of the others)
TONE_SETS = {2: (5.0, 13.0), 3: (3.0, 7.0, 17.0)}


@pytest.mark.parametrize("tones", [2, 3])
def test_each_tone_matches_eq3_on_the_half_wheelset(tones: int) -> None:
    """CoF 0.3, 345 N m split equally over the tones, DC at 30, 70 and 90 % of saturation: each tone's lag
    is Eq. 3 at that tone's frequency and its amplitude ratio 1 / |j w Iw + N R^2 k / v|."""
    cof, total = 0.3, 345.0
    env = gym.make(HALF, excitation="multitone", tones=tones, cof=cof, speed_m_s=10.0, **EQ3_WINDOW, **QUIET)
    env.reset(seed=3)
    freqs = TONE_SETS[tones]
    op = env.unwrapped.episode.physics.op
    assert op.wheel_load_n == pytest.approx(N)
    for frac in (0.3, 0.7, 0.9):
        _, _, terminated, truncated, info = env.step(_action(env, frac * R * N * cof, total, freqs))
        assert not (terminated or truncated)
        drive = env.unwrapped.episode.drive
        assert [f for _, f in drive.tones] == pytest.approx(list(freqs))  # far enough apart: not moved
        assert sum(a for a, _ in drive.tones) == pytest.approx(total)
        slope = creep_slope_at_torque(drive.dc_torque_nm, R, N, op)
        meas = info["measurement"]
        for k, f in enumerate(freqs, start=1):
            wm = 2 * math.pi * f
            phi = phase_eq3_deg(IW, wm, op.speed_m_s, N, R, slope)
            lag, se = meas[f"tone{k}_phase_lag_deg"], meas[f"tone{k}_phase_lag_se_deg"]
            assert abs(lag - phi) <= _eq3_tolerance(phi, se), (frac, k, f, lag, phi, se)
            ratio = 1.0 / math.hypot(wm * IW, N * R**2 * slope / op.speed_m_s)
            rel_tol = 0.05 + 3.0 * math.radians(se)
            assert meas[f"tone{k}_amplitude_ratio"] == pytest.approx(ratio, rel=rel_tol), (frac, k)
    env.close()


def test_joint_fit_recovers_each_tone_within_its_standard_error() -> None:
    """The joint fit on synthetic tones with white noise: every phase within 4 SE of the truth, and the
    reported SE the Cramer-Rao value sqrt(2 / n) sigma / amplitude within 20 %."""
    rng = np.random.default_rng(0)
    t = np.arange(600) * 1e-3
    freqs, amps, phases = np.array([3.0, 7.0, 17.0]), np.array([1.0, 0.5, 2.0]), np.array([0.2, -1.0, 2.5])
    th = 2 * np.pi * freqs[:, None] * t[None] + np.array([0.4, 1.3, -0.7])[:, None]
    sigma = 0.05
    y = (amps[:, None] * np.sin(th + phases[:, None])).sum(0) + 3.0 + 0.2 * t + sigma * rng.standard_normal(t.size)
    fits = fit_tones_from_sums(*tone_sums(th, t, y), 3)
    for fit, a, p in zip(fits, amps, phases):
        assert abs(fit.phase_rad - p) <= 4 * fit.phase_se_rad
        assert fit.amplitude == pytest.approx(a, abs=4 * sigma * math.sqrt(2 / t.size))
        assert fit.phase_se_rad == pytest.approx(math.sqrt(2 / t.size) * sigma / a, rel=0.2)
    # two tones at one frequency cannot be separated: no information (pi), never NaN
    same = np.array([th[0], th[0]])
    fits = fit_tones_from_sums(*tone_sums(same, t, y), 2)
    assert all(f.phase_se_rad == pytest.approx(math.pi) for f in fits)
    assert all(np.isfinite([f.amplitude, f.phase_rad]).all() for f in fits)


def _episode(env_id: str, actions: list[np.ndarray], seed: int, **kwargs) -> tuple[list, list, list]:
    env = gym.make(env_id, **kwargs)
    obs, info = env.reset(seed=seed)
    observations, rewards, infos = [obs], [], [info]
    for a in actions:
        obs, reward, terminated, truncated, info = env.step(a)
        observations.append(obs)
        rewards.append(reward)
        infos.append(info)
        if terminated or truncated:
            break
    env.close()
    return observations, rewards, infos


def test_sine_default_is_bit_identical_to_no_option() -> None:
    actions = [np.array([-0.9 + 0.1 * i, 0.2, -0.3 + 0.05 * i, 0.0, -1.0], dtype=np.float32) for i in range(4)]
    for env_id in (WAGON, HALF):
        plain = _episode(env_id, actions, seed=7, max_windows=4)
        sine = _episode(env_id, actions, seed=7, max_windows=4, excitation="sine", tones=3)
        for a, b in zip(plain[0], sine[0]):
            assert a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b)
        assert plain[1] == sine[1]
        assert [i["measurement"] for i in plain[2]] == [i["measurement"] for i in sine[2]]
        assert not any(k.startswith("tone") for k in plain[2][-1]["measurement"])
    assert DriveCommand(1.0, 2.0, 3.0) == DriveCommand(1.0, 2.0, 3.0, ())


@pytest.mark.parametrize("observation_type", ["window", "history", "identification"])
@pytest.mark.parametrize("tones", [2, 3])
def test_spaces_have_the_documented_shapes(tones: int, observation_type: str) -> None:
    base = {"window": 14, "history": 29, "identification": 38}[observation_type]
    env = gym.make(WAGON, excitation="multitone", tones=tones, observation_type=observation_type)
    assert env.action_space.shape == (5 + 2 * (tones - 1),)
    assert env.observation_space.shape == (base + 3 * tones,)
    task = env.unwrapped.task
    assert len(task.action_names) == env.action_space.shape[0]
    assert task.observation_names[-3 * tones:] == tuple(
        f"tone{k}_{n}" for k in range(1, tones + 1) for n in ("phase_lag", "phase_lag_se", "compliance"))
    obs, info = env.reset(seed=0)
    assert obs.shape == env.observation_space.shape and np.isfinite(obs).all()
    for k in range(1, tones + 1):
        for name in ("frequency_hz", "amplitude_nm", "phase_lag_deg", "phase_lag_se_deg", "amplitude_ratio"):
            value = info["measurement"][f"tone{k}_{name}"]
            assert isinstance(value, float) and math.isfinite(value)
    env.close()


@pytest.mark.parametrize("action_type", ["absolute", "relative", "identified"])
def test_check_env_passes(action_type: str) -> None:
    env = gym.make(HALF, excitation="multitone", tones=3, action_type=action_type, max_windows=5)
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


def test_vector_env_matches_single_env() -> None:
    """The batched vector env runs the same userdata functions: same observations as single envs."""
    kwargs = dict(excitation="multitone", tones=3, max_windows=3)
    vec = gym.make_vec(HALF, num_envs=2, vectorization_mode="vector_entry_point", **kwargs)
    rng = np.random.default_rng(1)
    actions = [np.clip(rng.normal(0, 0.5, (2, 9)), -1, 1).astype(np.float32) for _ in range(2)]
    for a in actions:
        a[:, 0], a[:, 4] = -0.95, -1.0  # a small DC torque (no macro-slip), no stop
    vobs = [vec.reset(seed=11)[0]] + [vec.step(a)[0] for a in actions]
    vec.close()
    for i in range(2):
        single = _episode(HALF, [a[i] for a in actions], seed=11 + i, **kwargs)[0]
        assert len(single) == len(vobs)
        np.testing.assert_array_equal(np.stack(single), np.stack([o[i] for o in vobs]))


@pytest.mark.parametrize(("kwargs", "field"), [
    ({"excitation": "chirp"}, "excitation"),
    ({"excitation": None}, "excitation"),
    ({"excitation": "multitone", "tones": 4}, "tones"),
    ({"excitation": "multitone", "tones": 1}, "tones"),
    ({"excitation": "multitone", "tones": 2.0}, "tones"),
    ({"excitation": "multitone", "tones": True}, "tones"),
    ({"excitation": "sine", "tones": 7}, "tones"),
    ({"excitation": "multitone", "tones": 3, "window_s": 0.5}, "tones"),  # 0.3 s measured: 3 tones do not fit
])
def test_bad_values_raise_naming_the_field(kwargs: dict, field: str) -> None:
    with pytest.raises(ValueError, match=field):
        gym.make(WAGON, **kwargs)


def test_bad_actions_and_drives_raise_naming_the_problem() -> None:
    env = gym.make(WAGON, excitation="multitone", tones=2)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"shape \(7,\)"):
        env.step(np.zeros(5, dtype=np.float32))
    with pytest.raises(ValueError, match="share_2"):
        env.step(np.array([0, 0, 0, 0, -1, 0, np.nan], dtype=np.float32))
    env.close()
    for bad in (((10.0, 200.0),), ((-1.0, 5.0),), ((1.0, 2.0),) * 3, ((1.0,),), 5.0):
        with pytest.raises(ValueError, match="extra_tones"):
            DriveCommand(0.0, 10.0, 5.0, bad)
    low, high = FREQUENCY_RANGE_HZ
    for bad, message in ((((10.0, 200.0),), rf"extra_tones\[0\]\.frequency_hz must .* in \[{low:g}, {high:g}\] Hz"),
                         (((1.0, 5.0), (float("nan"), 6.0)), r"extra_tones\[1\]\.amplitude_nm must .* >= 0 N m"),
                         (((True, 5.0),), r"extra_tones\[0\]\.amplitude_nm must"),
                         ((("1", 5.0),), r"extra_tones\[0\]\.amplitude_nm must")):
        with pytest.raises(ValueError, match=message):
            DriveCommand(0.0, 10.0, 5.0, bad)


def test_close_tones_are_moved_apart() -> None:
    """Tones closer than 2 / T are moved to the nearest frequency in range that keeps 2 / T from every
    earlier tone (tone 1 stays); the amplitudes follow the documented shares."""
    ex = Excitation("multitone", 3, measured_s=0.6)  # 2 / T = 3.33 Hz
    sep = ex.separation_hz
    assert separate([5.0, 6.0, 5.5], sep, 1.0, 20.0) == pytest.approx([5.0, 5.0 + sep, 5.0 - sep])
    assert separate([19.0, 19.5, 18.0], sep, 1.0, 20.0) == pytest.approx([19.0, 19.0 - sep, 19.0 - 2 * sep])
    drive = ex.drive(DriveCommand(100.0, 300.0, 5.0), np.array([-1.0, 0.0, -1.0, 1.0]))
    (a1, f1), (a2, f2), (a3, f3) = drive.tones
    assert f1 == 5.0 and abs(f2 - f1) >= sep - 1e-9 and min(abs(f3 - f1), abs(f3 - f2)) >= sep - 1e-9
    assert (a1, a2, a3) == pytest.approx((300.0 / 4, 300.0 / 4, 300.0 / 2))  # weights 1, 1, 2
    silent = ex.drive(DriveCommand(100.0, 300.0, 5.0), np.array([0.0, -1.0, 0.5, -1.0]))
    assert [a for a, _ in silent.tones] == pytest.approx([300.0, 0.0, 0.0])


def test_silent_extra_tone_gives_the_sine_phase_within_se() -> None:
    """A 2-tone drive with tone 2's share at 0 applies the sine's torque (only the reset windows differ:
    the multi-tone baseline splits its 100 N m over the tones); tone 1's lag from the joint fit equals the
    sine's single-tone lag within their standard errors, and the silent tone reads lag 0, SE 180 deg,
    compliance 0 (never NaN). Sensor noise on, so that the SE means something."""
    kwargs = dict(cof=0.2, speed_m_s=20.0, load_case="laden", noise_level=1.0, max_windows=3)
    freqs = (6.0, 13.0)
    sine_env = gym.make(WAGON, **kwargs)
    multi_env = gym.make(WAGON, excitation="multitone", tones=2, **kwargs)
    sine_env.reset(seed=5)
    multi_env.reset(seed=5)
    lim = sine_env.unwrapped.task.limits
    for frac in (0.2, 0.5):
        dc = frac * lim.max_dc_torque_nm * 0.2 / 0.6
        a_sine = _action(sine_env, dc, 600.0, freqs[:1])
        a_multi = _action(multi_env, dc, 600.0, freqs, shares=(-1.0,))
        np.testing.assert_array_equal(a_multi[:5], a_sine)
        obs_s, r_s, *_, info_s = sine_env.step(a_sine)
        obs_m, r_m, *_, info_m = multi_env.step(a_multi)
        ms, mm = info_s["measurement"], info_m["measurement"]
        assert mm["coa_measured"] == pytest.approx(ms["coa_measured"], rel=1e-3)
        assert mm["tone1_amplitude_nm"] == pytest.approx(600.0, rel=1e-6) and mm["torque_amplitude_nm"] == pytest.approx(ms["torque_amplitude_nm"], rel=1e-3)
        se = math.hypot(ms["phase_lag_se_deg"], mm["tone1_phase_lag_se_deg"])
        assert 0.0 < se < 5.0
        assert abs(mm["tone1_phase_lag_deg"] - ms["phase_lag_deg"]) <= 3.0 * se
        assert mm["tone1_phase_lag_deg"] == mm["phase_lag_deg"]
        assert (mm["tone2_amplitude_nm"], mm["tone2_phase_lag_deg"], mm["tone2_phase_lag_se_deg"]) == (0.0, 0.0, 180.0)
        np.testing.assert_array_equal(obs_m[-3:], np.array([0.0, 2.0, 0.0], dtype=np.float32))
        np.testing.assert_allclose(obs_m[5:8], obs_s[5:8])  # the same drive (total amplitude as the sine's)
        assert np.isfinite(obs_m).all()
    sine_env.close()
    multi_env.close()


def test_single_tone_fit_unchanged_by_the_joint_fit_module() -> None:
    """The single-tone fit (fit_from_sums) still fits a lone sine exactly (the 4-basis path is kept)."""
    t = np.arange(500) * 1e-3
    th = 2 * np.pi * 5.0 * t
    fit = fit_samples(th, t, 2.0 * np.sin(th + 0.3) + 1.0)
    assert fit.amplitude == pytest.approx(2.0) and fit.phase_rad == pytest.approx(0.3)
