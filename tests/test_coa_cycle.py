"""The measured CoA's synchronous average over the modulation cycle (``coa_cycle_max``, ``coa_cycle_min``,
``coa_cycle_bin_se``): the arithmetic of the bins, the force balance of the half wheelset, the physical
bound it never exceeds, and what the sensors' systematic errors do to it."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import cof_gym  # noqa: F401  (registers the ids)
from cof_gym.measurement.synchronous_average import bin_sums, cycle_extremes
from cof_gym.physics.native.layout import PHASE_BINS
from cof_gym.physics.vehicle import HalfWheelsetParameters
from cof_gym.task.interface import encode_action
from exact_sensors import QUIET

P = HalfWheelsetParameters()
R, N, J = P.wheel_radius_m, P.normal_load_n, P.spin_inertia_kg_m2
HALF = "CofGym/HalfWheelset-v2"
# a bin of width 2 pi / B averages a sine over it: at the crest's bin sin(pi / B) / (pi / B) of the amplitude
BIN_AVERAGE = math.sin(math.pi / PHASE_BINS) / (math.pi / PHASE_BINS)


def test_a_sine_sampled_densely_gives_its_crest_and_trough_averaged_over_one_bin() -> None:
    theta = np.linspace(-math.pi, math.pi, 64 * 4000, endpoint=False) + math.pi / (64 * 4000)
    extremes = cycle_extremes(*bin_sums(theta, 0.2 + 0.05 * np.sin(theta), PHASE_BINS))
    # the sum over a bin is a midpoint rule of the sine's integral: error ~ (bin / samples)^2 / 24 of it
    assert extremes.maximum == pytest.approx(0.2 + 0.05 * BIN_AVERAGE, abs=1e-9)
    assert extremes.minimum == pytest.approx(0.2 - 0.05 * BIN_AVERAGE, abs=1e-9)


def test_the_bin_standard_error_is_the_pooled_within_bin_spread() -> None:
    counts, sums, squares = np.array([2.0, 0.0, 3.0]), np.array([1.0 + 3.0, 0.0, 5.0 + 5.0 + 8.0]), \
        np.array([1.0 + 9.0, 0.0, 25.0 + 25.0 + 64.0])
    extremes = cycle_extremes(counts, sums, squares)
    within = (1.0 - 2.0) ** 2 + (3.0 - 2.0) ** 2 + 2 * (5.0 - 6.0) ** 2 + (8.0 - 6.0) ** 2  # 8
    assert (extremes.maximum, extremes.minimum) == (6.0, 2.0)  # the empty bin is skipped
    assert extremes.bin_se == pytest.approx(math.sqrt(within / (5 - 2) / 2.5), rel=1e-12)
    with pytest.raises(ValueError, match="no bin"):
        cycle_extremes(np.zeros(4), np.zeros(4), np.zeros(4))


def _window(env, dc: float, amp: float, frequency: float = 5.0) -> tuple[dict, bool]:
    limits = env.unwrapped.limits
    _, _, terminated, _, info = env.step(encode_action(dc, amp, frequency, 0.3, False, limits))
    return info, bool(terminated)


@pytest.mark.parametrize("fraction", [0.2, 0.5])
def test_far_below_the_peak_its_swing_is_the_force_balance_of_the_torque_and_the_wheels_inertia(fraction: float) -> None:
    """With the speed held, ``J dOmega/dt = T - R F``: the force's fundamental is ``(T~ - j w J Omega~) / R``
    from the torque's and the speed's lock-ins. A sinusoidal CoA's largest and smallest bin means are
    ``mean +- a c`` with ``c`` between BIN_AVERAGE cos(pi / B) (its crest on a bin's edge) and BIN_AVERAGE."""
    env = gym.make(HALF, cof=0.3, speed_m_s=10.0, **QUIET)
    env.reset(seed=1)
    info, _ = _window(env, fraction * R * N * 0.3, 200.0)
    m = info["measurement"]
    w = 2 * math.pi * 5.0
    lag = math.radians(m["phase_lag_deg"])
    force = (m["torque_amplitude_nm"] - 1j * w * J * m["omega_amplitude_rad_s"] * complex(math.cos(lag), -math.sin(lag))) / R
    coa_amplitude = abs(force) / N
    half_swing = (m["coa_cycle_max"] - m["coa_cycle_min"]) / 2
    # the curve's curvature over the swing (a CoA swing of ~0.2 % of the CoF) adds well under 1 % of it
    assert BIN_AVERAGE * math.cos(math.pi / PHASE_BINS) * 0.99 < half_swing / coa_amplitude < BIN_AVERAGE * 1.01
    assert m["coa_cycle_min"] < m["coa_measured"] < m["coa_cycle_max"]
    assert m["coa_cycle_bin_se"] > 0.0
    env.close()


@pytest.mark.parametrize("curve", ["dry", "wet", "low_adhesion"])
def test_its_crest_never_reads_more_adhesion_than_the_physics_has(curve: str) -> None:
    """Noise off, a 40 % modulation climbed to a runaway: every window's crest stays below the CoF (the
    largest adhesion of the simulation, within the ground truth's own 0.3 %) and, once the torque's crest
    passes the saturation torque, it reads the CoF closer than the window's mean does."""
    env = gym.make("CofGym/TorqueInterrogation-v2", max_windows=30, **QUIET)
    _, info = env.reset(seed=5, options={"creep_law": curve})
    cof, m_sat = info["ground_truth"]["cof"], info["ground_truth"]["saturation_torque_nm"]
    crests_past = []
    for fraction in np.arange(0.3, 1.3, 0.05):
        info, terminated = _window(env, fraction * m_sat, 0.4 * fraction * m_sat)
        m = info["measurement"]
        assert m["coa_cycle_max"] <= cof * 1.003
        assert m["coa_cycle_min"] <= m["coa_measured"] <= m["coa_cycle_max"]
        if terminated:
            break
        if 1.4 * fraction > 1.0:
            crests_past.append(cof / m["coa_cycle_max"] < cof / m["coa_measured"])
    assert crests_past and all(crests_past)
    env.close()


def test_the_force_gain_error_scales_it() -> None:
    readings = []
    for gain_error in (0.0, 0.04):
        env = gym.make(HALF, cof=0.3, speed_m_s=10.0, **{**QUIET, "force_gain_error": gain_error, "noise_level": 1.0})
        env.reset(seed=1)
        readings.append(_window(env, 0.6 * R * N * 0.3, 600.0)[0]["measurement"])
        env.close()
    clean, biased = readings
    for key in ("coa_cycle_max", "coa_cycle_min", "coa_cycle_bin_se"):
        assert biased[key] == pytest.approx(1.04 * clean[key], rel=1e-12)
