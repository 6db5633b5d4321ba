"""The measured creepage's modulation (``info["measurement"]["creepage_modulation_*"]``): a lock-in of the
creepage the sensors read, ``R omega / v - 1``. On the half wheelset, whose rolling speed is held, that
creepage is the wheelset speed scaled by ``R / v``: the same lag behind the torque and ``R / v`` times its
amplitude; a systematic error scales it by the creepage gain and leaves its lag; two tones read tone 1's
from the joint fit."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import cof_gym  # noqa: F401  (registers the ids)
from cof_gym.physics.models import HALF_WHEELSET_ARMATURE_KG
from cof_gym.physics.vehicle import HalfWheelsetParameters
from cof_gym.task.excitation import encode_extra_tones
from cof_gym.task.interface import encode_action
from cof_gym.task.sensors import SensorErrors
from exact_sensors import QUIET

P = HalfWheelsetParameters()
R, N = P.wheel_radius_m, P.normal_load_n
HALF = "CofGym/HalfWheelset-v2"
# the lock-in's least squares is linear in its signal: R omega / v - 1 with v held gives R / v times omega's
# coefficients up to rounding (a few ulps of sums over ~10^3 samples)
LINEAR_RTOL = 1e-9


def held_speed_tolerance(cof: float, speed: float, freq: float) -> float:
    """The creepage amplitude a not quite held speed adds: the creep force (at most CoF x N) swings the
    1e12-kg carrier by at most ``CoF N / (m w)`` m/s at the modulation, ``/ v`` in creepage."""
    return cof * N / (HALF_WHEELSET_ARMATURE_KG * 2 * math.pi * freq * speed)


def _step(env, dc: float, amp: float, extra_tones: tuple[tuple[float, float], ...] = ()) -> dict:
    """One window at DC ``dc`` with a 5 Hz modulation of ``amp`` (N m), extra tones as (Hz, weight)."""
    task = env.unwrapped.task
    action = task.actions.encode(env.unwrapped.episode.action_context, dc, amp, 5.0, 0.3, False, task.limits)
    action = np.concatenate([action, encode_extra_tones(list(extra_tones))]).astype(np.float32)
    _, _, terminated, truncated, info = env.step(action)
    assert not (terminated or truncated)
    return info["measurement"]


@pytest.mark.parametrize("fraction", [0.3, 0.9])
def test_on_the_half_wheelset_it_is_the_speed_scaled_by_r_over_v(fraction: float) -> None:
    speed = 10.0
    env = gym.make(HALF, cof=0.3, speed_m_s=speed, **QUIET)
    env.reset(seed=1)
    m = _step(env, fraction * R * N * 0.3, 300.0)
    assert m["creepage_modulation_amplitude"] == pytest.approx(R / speed * m["omega_amplitude_rad_s"],
                                                               abs=held_speed_tolerance(0.3, speed, 5.0))
    assert m["creepage_modulation_lag_deg"] == pytest.approx(m["phase_lag_deg"], abs=1e-6)
    assert 0.0 < m["creepage_modulation_lag_se_deg"] < 180.0
    env.close()


def test_its_swing_per_torque_grows_towards_the_peak() -> None:
    """The creep curve flattens towards its peak: the same torque modulation moves the creepage more."""
    env = gym.make(HALF, cof=0.3, speed_m_s=10.0, **QUIET)
    env.reset(seed=1)
    swings = [(m := _step(env, f * R * N * 0.3, 300.0))["creepage_modulation_amplitude"] / m["torque_amplitude_nm"]
              for f in (0.3, 0.6, 0.9)]
    assert swings[0] < swings[1] < swings[2]
    env.close()


def test_a_systematic_error_scales_its_amplitude_and_keeps_its_lag() -> None:
    errors = dict(speed_sensor_error=0.02, wheel_radius_error=-0.005)
    readings = []
    for extra in ({}, errors):
        env = gym.make(HALF, cof=0.3, speed_m_s=10.0, **{**QUIET, **extra})
        env.reset(seed=1)
        readings.append(_step(env, 0.7 * R * N * 0.3, 300.0))
        env.close()
    clean, biased = readings
    gain = 1.0 + SensorErrors(**errors).creepage_offset
    assert biased["creepage_modulation_amplitude"] == pytest.approx(gain * clean["creepage_modulation_amplitude"],
                                                                    rel=LINEAR_RTOL)
    assert biased["creepage_modulation_lag_deg"] == clean["creepage_modulation_lag_deg"]


def test_two_tones_read_tone_one_from_the_joint_fit() -> None:
    env = gym.make(HALF, excitation="multitone", tones=2, cof=0.3, speed_m_s=10.0, **QUIET)
    env.reset(seed=1)
    m = _step(env, 0.7 * R * N * 0.3, 300.0, ((13.0, 1.0),))
    assert m["creepage_modulation_lag_deg"] == pytest.approx(m["tone1_phase_lag_deg"], abs=1e-6)
    assert m["creepage_modulation_amplitude"] == pytest.approx(R / 10.0 * m["tone1_omega_amplitude_rad_s"],
                                                               abs=held_speed_tolerance(0.3, 10.0, 5.0))
    env.close()


def test_sensor_noise_gives_it_a_standard_error_and_never_nan() -> None:
    env = gym.make("CofGym/TorqueInterrogation-v2", max_windows=3)
    env.reset(seed=4, options={"speed_m_s": 6.0, "noise_level": 1.0})
    lim = env.unwrapped.limits
    _, _, _, _, info = env.step(encode_action(0.05 * lim.max_dc_torque_nm, 0.02 * lim.max_dc_torque_nm, 5.0, 0.1,
                                              False, lim))
    m = info["measurement"]
    values = [m[k] for k in ("creepage_modulation_amplitude", "creepage_modulation_lag_deg",
                             "creepage_modulation_lag_se_deg")]
    assert all(math.isfinite(v) for v in values) and values[2] > 0.0
    env.close()
