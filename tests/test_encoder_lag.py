"""The encoder's speed-signal lag (``encoder_lag_s``): a first-order filter on the wheelset-speed reading, in the
native measurement chain, that moves every phase the lock-in reads and nothing the physics does."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.physics.models import DEFAULT_TIMESTEP_S
from cof_gym.task.scenarios import ENCODER_LAG_MAX_S, V2_RANGES, outside_draws

FREQUENCY_HZ = 5.0
QUIET = {"noise_level": 0.0, "motor_lag_s": 0.0, "cof": 0.3, "condition": "dry", "speed_m_s": 10.0}


def windows(env_id: str, encoder_lag_s: float, steps: int = 2) -> list[dict]:
    """The readings of ``steps`` windows at a low DC torque and a small 5 Hz modulation (absolute actions)."""
    env = gym.make(env_id, action_type="absolute")
    env.reset(seed=3, options={**QUIET, "encoder_lag_s": encoder_lag_s})
    frequency = 2.0 * math.log(FREQUENCY_HZ) / math.log(20.0) - 1.0  # the action that decodes to 5 Hz
    action = np.array([-0.9, -0.6, frequency, 0.0, -1.0], dtype=np.float32)
    out = [dict(env.step(action)[4]["measurement"]) for _ in range(steps)]
    env.close()
    return out


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
