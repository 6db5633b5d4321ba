"""Reward of the torque-interrogation task: estimate error against slip, discomfort and time.

    reward = - w_error   * |estimate - CoF| / CoF        (only when the estimate is scored)
             - w_slip    * slip_cost
             - w_comfort * discomfort
             - w_time    * window duration (s)

    slip_cost   = time past the creep-curve peak / window
                  + 100 * energy dissipated past the peak / (N v T)
                  + 10 * frictional energy in all contacts / (N v T)
    discomfort  = Wd-weighted RMS car-body acceleration (m/s^2) + 0.1 * RMS jerk (m/s^3)

N v T (contact load x speed x window) makes the energies dimensionless (a mean CoA x creepage).
Macro-slip ends the episode with ``macro_slip_penalty`` and the estimate scored as ``error_cap``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cof_gym.physics.simulation import WindowMeasurement


@dataclass(frozen=True)
class RewardWeights:
    w_error: float = 10.0
    w_slip: float = 1.0
    w_comfort: float = 1.0
    w_time: float = 0.02
    macro_slip_penalty: float = 5.0
    error_cap: float = 1.0  # relative error at which the error term saturates

    def __post_init__(self) -> None:
        for name, value in self.__dict__.items():
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")


def slip_cost(m: WindowMeasurement, contact_load_n: float, speed_m_s: float, window_s: float) -> float:
    scale = max(contact_load_n * speed_m_s * window_s, 1e-9)
    return (m.time_past_peak_s / window_s + 100.0 * m.energy_past_peak_j / scale
            + 10.0 * m.friction_energy_j / scale)


def discomfort(m: WindowMeasurement) -> float:
    return m.wd_rms_m_s2 + 0.1 * m.jerk_rms_m_s3


def relative_error(estimate: float, cof: float, cap: float) -> float:
    return min(abs(estimate - cof) / cof, cap)


def reward_terms(weights: RewardWeights, m: WindowMeasurement, contact_load_n: float, speed_m_s: float,
                 window_s: float, scored_error: float | None, macro_slip: bool) -> dict[str, float]:
    """The weighted terms (each <= 0) of one step's reward."""
    err = weights.error_cap if macro_slip else scored_error
    return {
        "reward_error": -weights.w_error * err if err is not None else 0.0,
        "reward_slip": -weights.w_slip * slip_cost(m, contact_load_n, speed_m_s, window_s)
        - (weights.macro_slip_penalty if macro_slip else 0.0),
        "reward_comfort": -weights.w_comfort * discomfort(m),
        "reward_time": -weights.w_time * window_s,
    }
