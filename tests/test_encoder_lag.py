"""The encoder's speed-signal lag (``encoder_lag_s``): a first-order filter on the wheelset-speed reading, in the
native measurement chain, that moves every phase the lock-in reads and nothing the physics does; and the lag's SE
for the correlated residual such a smoothed signal leaves (``phase_lag_se_corrected_deg``) with the two agents that
read it."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents import registry
from cof_gym.measurement.sine_fit import (basis, colored_noise_factor, fit_from_sums, fit_tones_from_sums,
                                         lag1_correlation, packed_sums, sums, tone_basis)
from cof_gym.physics.models import DEFAULT_TIMESTEP_S
from cof_gym.task.scenarios import ENCODER_LAG_MAX_S, V2_RANGES, outside_draws
from held_windows import FREQUENCY_HZ, QUIET, held_action, held_windows  # tests/ is on sys.path (pytest rootdir)

QUIET_10 = {**QUIET, "speed_m_s": 10.0}


def windows(env_id: str, encoder_lag_s: float, steps: int = 2) -> list[dict]:
    """The readings of ``steps`` windows at a low DC torque and a small 5 Hz modulation (absolute actions)."""
    return held_windows(env_id, {**QUIET_10, "encoder_lag_s": encoder_lag_s}, steps)


def filter_response(encoder_lag_s: float) -> complex:
    """The native filter's response at 5 Hz: ``y_n = y_(n-1) + a ((x_n + x_(n-1)) / 2 - y_(n-1))``,
    ``a = 1 - exp(-dt / tau)``."""
    a = 1.0 - math.exp(-DEFAULT_TIMESTEP_S / encoder_lag_s)
    z1 = np.exp(-2j * math.pi * FREQUENCY_HZ * DEFAULT_TIMESTEP_S)  # one step's delay
    return a * (1.0 + z1) / 2.0 / (1.0 - (1.0 - a) * z1)


@pytest.mark.parametrize("encoder_lag_s", [0.002, 0.01, ENCODER_LAG_MAX_S])
def test_the_lag_adds_the_filters_phase_and_gain_at_the_modulation(encoder_lag_s):
    """On the half wheelset (small signal) the lock-in's lag grows by the filter's phase at 5 Hz and its compliance
    shrinks by the filter's gain. The fit sees the filter's exact response at the fundamental; what else the
    filtered signal holds (the wheel's harmonics, each filtered at its own frequency, and the settled remains of the
    ramp's transient) leaks into the fit at the 1e-5-1e-6 level of the fundamental here: the tolerances are 10x
    that (0.01 deg = 1.7e-4 rad)."""
    plain, lagged = windows(cof_gym.HALF_WHEELSET_ENV_ID, 0.0)[-1], windows(cof_gym.HALF_WHEELSET_ENV_ID,
                                                                            encoder_lag_s)[-1]
    response = filter_response(encoder_lag_s)
    assert lagged["phase_lag_deg"] - plain["phase_lag_deg"] == pytest.approx(-math.degrees(np.angle(response)),
                                                                          abs=0.01)
    assert lagged["amplitude_ratio"] / plain["amplitude_ratio"] == pytest.approx(abs(response), rel=1e-4)
    # the continuous first-order lag it discretises, atan(w tau): the discrete filter delays by tau + dt^2 / (12 tau)
    # at low frequency (the averaged input's dt / 2 cancels the update's -dt / 2), held here to twice that
    w, dt = 2 * math.pi * FREQUENCY_HZ, DEFAULT_TIMESTEP_S
    assert -math.degrees(np.angle(response)) == pytest.approx(math.degrees(math.atan(w * encoder_lag_s)),
                                                              abs=math.degrees(w * dt**2 / (6 * encoder_lag_s)))


def test_the_lag_changes_what_the_encoder_reads_and_nothing_the_wagon_does():
    """Same seed, same actions: every physical quantity of the wagon's windows is equal to the bit, the lock-in's
    lag is not."""
    plain, lagged = windows(cof_gym.WAGON_ENV_ID, 0.0, 3), windows(cof_gym.WAGON_ENV_ID, 0.01, 3)
    physical = ("torque_mean_nm", "torque_peak_nm", "torque_amplitude_nm", "coa_measured", "speed_measured_m_s",
                "tangential_force_measured_n", "normal_load_measured_n", "coa_cycle_max", "wd_rms_m_s2")
    for a, b in zip(plain, lagged):
        assert all(a[name] == b[name] for name in physical)
        assert a["omega_amplitude_rad_s"] != b["omega_amplitude_rad_s"]
        assert b["phase_lag_deg"] - a["phase_lag_deg"] > 10.0  # atan(2 pi 5 x 0.01) = 17.4 deg on the half wheelset


@pytest.mark.parametrize("value", [-0.001, ENCODER_LAG_MAX_S * 1.01, math.nan, math.inf, True, "0.01"])
def test_a_bad_lag_is_refused_naming_the_field_and_its_range(value):
    env = gym.make(cof_gym.WAGON_ENV_ID)
    with pytest.raises(ValueError, match=r"encoder_lag_s must be .*\[0, 0\.05\] s"):
        env.reset(seed=0, options={"encoder_lag_s": value})
    env.close()


def test_no_draw_gives_a_lag_so_a_lagged_episode_is_outside_the_draws():
    assert "encoder_lag_s" in outside_draws({"encoder_lag_s": 0.01}, V2_RANGES)
    assert "encoder_lag_s" not in outside_draws({"encoder_lag_s": 0.0}, V2_RANGES)


def lag1_sums(theta: np.ndarray, tau: np.ndarray, y: np.ndarray) -> tuple:
    """The lag-1 cross sums the native chain accumulates, from the samples."""
    b = basis(theta, tau)
    return (float(y[1:] @ y[:-1]), b[1:].T @ y[:-1], b[:-1].T @ y[1:], b[1:].T @ b[:-1])


@pytest.mark.parametrize("rho", [0.0, 0.6, 0.95])
def test_the_residuals_lag1_correlation_from_sums_is_the_samples(rho):
    """From the running sums, the correlation of consecutive residuals of the fit equals the one computed from the
    residuals themselves: the same numbers in another order, and the sums' cancellation (terms of y^2 n ~ 2e3,
    residual sums ~ 1) costs ~1e-13 of it, held to 1e-9."""
    rng = np.random.default_rng(1)
    n = 600
    tau = np.arange(n) * 1e-3
    theta = 2 * math.pi * FREQUENCY_HZ * tau + 0.3
    noise = np.zeros(n)
    for i in range(1, n):
        noise[i] = rho * noise[i - 1] + 0.05 * rng.standard_normal()
    y = 1.7 * np.sin(theta + 0.4) + 2.0 + 0.3 * tau + noise
    btb, bty, yty, count = sums(theta, tau, y)
    residual = y - basis(theta, tau) @ np.linalg.lstsq(basis(theta, tau), y, rcond=None)[0]
    direct = (residual[1:] @ residual[:-1] / (n - 1)) / (residual @ residual / n)
    lag1 = [np.ravel(v) if np.ndim(v) else v for v in lag1_sums(theta, tau, y)]
    got = lag1_correlation(btb, bty, yty, count, *lag1)
    assert got == pytest.approx(direct, abs=1e-9)
    # the fit's own coefficients (as the window reads them) are the ones solved here again: the same number, exactly
    assert lag1_correlation(btb, bty, yty, count, *lag1, fit_from_sums(btb, bty, yty, count).coefficients) == got
    assert abs(got - rho) < 0.15  # the estimate of the process's own correlation over 600 samples


def test_a_joint_fits_lag1_correlation_from_sums_is_the_samples():
    """The rotation lock-in's joint basis (a tone, the first two harmonics of a rotation angle, offset, drift): the
    correlation from its sums (packed B'B, and the np x np lag-1 cross sums the native chain keeps) equals the
    residuals' own, as for one tone (the same cancellation bound, held to 1e-9), and the joint fit's coefficients
    (every tone's :attr:`SineFit.coefficients`) give exactly the number solved there again."""
    rng = np.random.default_rng(2)
    n = 600
    tau = np.arange(n) * 1e-3
    theta = 2 * math.pi * FREQUENCY_HZ * tau + 0.3
    phi = 21.7 * tau + 0.1  # the wheel's angle at 10 m/s
    noise = np.zeros(n)
    for i in range(1, n):
        noise[i] = 0.8 * noise[i - 1] + 0.05 * rng.standard_normal()
    y = 1.7 * np.sin(theta + 0.4) + 0.2 * np.cos(phi - 0.5) + 2.0 + 0.3 * tau + noise
    b = tone_basis(np.stack([theta, phi, 2.0 * phi]), tau)
    btb, bty, yty, count = packed_sums(b, y)
    residual = y - b @ np.linalg.lstsq(b, y, rcond=None)[0]
    direct = (residual[1:] @ residual[:-1] / (n - 1)) / (residual @ residual / n)
    lag1 = (float(y[1:] @ y[:-1]), b[1:].T @ y[:-1], b[:-1].T @ y[1:], np.ravel(b[1:].T @ b[:-1]))
    got = lag1_correlation(btb, bty, yty, count, *lag1)
    assert got == pytest.approx(direct, abs=1e-9)
    tone = fit_tones_from_sums(btb, bty, yty, count, 3)[0]
    assert lag1_correlation(btb, bty, yty, count, *lag1, tone.coefficients) == got


def test_the_factor_is_one_for_a_white_residual_and_the_ar1_spectrum_otherwise():
    assert colored_noise_factor(0.0, 0.03) == 1.0
    rho, step = 0.9, 0.03
    spectrum = 1.0 / abs(1.0 - rho * np.exp(-1j * step)) ** 2  # AR(1) density over its white equivalent's ...
    assert colored_noise_factor(rho, step) ** 2 == pytest.approx(spectrum * (1.0 - rho**2), rel=1e-12)  # ... variance


@pytest.mark.parametrize("lock_in", ["plain", "rotation"])
def test_the_corrected_se_follows_the_lags_scatter_where_the_white_one_understates_it(lock_in):
    """40 seeds of one half-wheelset window with the noise at full scale: without a lag both SEs match the scatter of
    the lag over the seeds; with a 10 ms encoder lag the white SE falls to a fifth of it (the smoothed noise leaves a
    correlated residual) and the corrected one stays with it; the same for the rotation lock-in's joint fit (its
    own residual's lag-1 sums). Bounds: the scatter of 40 draws is known to ~11 % (1 / sqrt(2 x 39)), the SEs'
    medians to a few %; measured 0.84-0.89 and 0.18 (plain)."""
    for encoder_lag_s in (0.0, 0.01):
        lags, white, corrected = [], [], []
        env = gym.make(cof_gym.HALF_WHEELSET_ENV_ID, action_type="absolute", lock_in=lock_in)
        action = held_action(env, dc=-0.5, amplitude=0.6)
        for seed in range(40):
            env.reset(seed=seed, options={**QUIET_10, "noise_level": 1.0, "encoder_lag_s": encoder_lag_s})
            m = env.step(action)[4]["measurement"]
            lags.append(m["phase_lag_deg"])
            white.append(m["phase_lag_se_deg"])
            corrected.append(m["phase_lag_se_corrected_deg"])
        env.close()
        scatter = float(np.std(lags, ddof=1))
        assert 0.6 < np.median(corrected) / scatter < 1.5
        if encoder_lag_s:
            assert np.median(white) / scatter < 0.35


def test_the_ar1_variants_are_the_validation_chosen_agents_reading_the_corrected_se():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    for name, plain in (("phase-rule-ar1", "phase-rule"), ("robust-model-ar1", "robust-model")):
        agent, reference = registry.make_agent(name + "+plain", env), registry.make_agent(plain + "+plain", env)
        assert agent.corrected_se and not reference.corrected_se and agent.name == f"{name}+plain"
        assert {**vars(agent), "corrected_se": False, "name": reference.name} == vars(reference)
        assert name not in registry.default_agents()
    env.close()


def reset_window(encoder_lag_s: float, seed: int = 3) -> tuple[np.ndarray, dict]:
    """The reset observation and info of a wagon episode (the drawn noise) with this encoder lag."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    observation, info = env.reset(seed=seed, options={"encoder_lag_s": encoder_lag_s})
    env.close()
    return observation, info


def test_the_reset_window_reads_a_smoothed_speed_signal_from_its_noise_colour():
    """The reset window's corrected SE over its white one: about 1 as drawn (0.89-1.10 over 40 seeds, session 65),
    2.7-3.2 with a 2 ms lag and 4.3-5.5 with 10 ms; a window without the corrected SE reads none."""
    from cof_gym.agents.phase_rule import smoothed_speed_signal

    for seed in (3, 4, 5):
        assert not smoothed_speed_signal(*reset_window(0.0, seed))
        assert smoothed_speed_signal(*reset_window(0.002, seed)) and smoothed_speed_signal(*reset_window(0.01, seed))
    observation, info = reset_window(0.01)
    assert not smoothed_speed_signal(observation, {}) and not smoothed_speed_signal(observation, None)


@pytest.mark.parametrize("name, plain", [("phase-rule-gated", "phase-rule"), ("robust-model-gated", "robust-model")])
def test_the_gated_variants_play_the_original_as_drawn_and_the_ar1_variant_with_a_smoothed_encoder(name, plain):
    """Same seed, same episode: the gated agent's record is the white-SE original's with a sharp encoder and the
    ar1 variant's with a 5 ms lag, field for field but the agent's name (seed 1: an episode where the two SEs lead
    the original and the ar1 variant to different stops under the lag)."""
    from dataclasses import asdict

    from cof_gym.commands.evaluate_episodes import run_episode

    env = gym.make(cof_gym.WAGON_ENV_ID)

    def play(spec: str, encoder_lag_s: float) -> dict:
        return asdict(run_episode(env, registry.make_agent(spec, env), 1, {"encoder_lag_s": encoder_lag_s}, 0))

    assert {**play(name, 0.0), "agent": plain} == play(plain, 0.0)
    gated = play(name, 0.005)
    assert {**gated, "agent": f"{plain}-ar1"} == play(f"{plain}-ar1", 0.005)
    assert {**gated, "agent": plain} != play(plain, 0.005)
    env.close()
    assert name not in registry.default_agents()
