"""Reward and constraints of the torque-interrogation task, as swappable objects.

    reward = - w_error   * |ln(estimate / CoF)|           (when the estimate is scored)
             - w_slip    * slip_cost                      (operating past the creep-curve peak)
             - w_comfort * discomfort                     (what the passengers feel)
             - w_time    * window duration (s)            (measurement time)
             - macro_slip_penalty                         (when the wheel runs away)

    slip_cost   = time any wheel spent past the creep-curve peak / window
                  + 100 * energy dissipated there / (N v T)
    discomfort  = Wd RMS car-body acceleration (ISO 2631-1) / (0.01 m/s^2)

**Why these terms.** The error is ``|ln(estimate / CoF)|``: symmetric in ratio (a factor 2 over costs
what a factor 2 under costs, ~ the relative error when small) and never capped, so no guess is ever
cheaper than a measurement of the same slip and comfort cost, and at equal slip, comfort and time a
lower error always earns more. Ordinary traction below the peak costs nothing (it is what the train
does anyway); only operating past the peak (wear, noise, the start of a wheel spin) is a slip cost.
The comfort reference 0.01 m/s^2 is ~1/30 of ISO 2631-1's "not uncomfortable" bound of 0.315 m/s^2:
the interrogation must stay far below what a passenger would notice.

**What each weight trades** (defaults): ``w_error`` 10: one percent of error is worth 0.1, i.e. five
one-second windows (``w_time`` 0.02 per s); ``w_comfort`` 0.05: the paper's 345 N m at 5 Hz on the
laden wagon (~0.005 m/s^2 Wd) costs ~0.025 per window, about a quarter percent of error, while a
3 kN m modulation costs ~10x that; ``w_slip`` 1: a whole window past the peak costs 1 plus its energy
term, as much as ten percent of error (a log error of 0.1); ``macro_slip_penalty`` 10: a wheel spin costs
as much as an estimate off by a factor e (a log error of 1, i.e. -63 % or +172 %) on top of its slip cost;
an estimate at the far end of the CoF envelope (0.6 for 0.02, ln 30 = 3.4) loses more, 34.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cof_gym.physics.simulation import WindowMeasurement
from cof_gym.validation import check_number

COMFORT_REFERENCE_M_S2 = 0.01
# a step's reward terms (info["reward_*"], in this order; their sum is the reward), the potential-based shaping term
# added with ``shaping``, and the unweighted costs (info["cost"])
REWARD_TERMS = ("reward_error", "reward_slip", "reward_comfort", "reward_time")
SHAPING_TERM = "reward_shaping"
COST_TERMS = ("slip", "discomfort", "macro_slip")
NO_COSTS = dict.fromkeys(COST_TERMS, 0.0)  # a step that runs no window
PAST_PEAK_ENERGY_WEIGHT = 100.0


def log_error(estimate: float, cof: float) -> float:
    """|ln(estimate / cof)|: the scored error (estimate and cof > 0)."""
    return abs(math.log(estimate / cof))


def relative_error(estimate: float, cof: float) -> float:
    """|estimate / cof - 1| (reported beside the log error; not what the reward uses)."""
    return abs(estimate / cof - 1.0)


def slip_cost(m: WindowMeasurement, contact_load_n: float, speed_m_s: float, window_s: float) -> float:
    """Time share past the creep-curve peak + its dissipated energy over N v T (dimensionless)."""
    scale = max(contact_load_n * speed_m_s * window_s, 1e-9)
    return m.time_past_peak_s / window_s + PAST_PEAK_ENERGY_WEIGHT * m.energy_past_peak_j / scale


def discomfort(m: WindowMeasurement) -> float:
    """ISO 2631-1 Wd RMS car-body acceleration over the window, in units of COMFORT_REFERENCE_M_S2
    (the RMS jerk is reported in ``info["measurement"]`` but not priced: ISO 2631-1's comfort measure
    is the weighted acceleration)."""
    return m.wd_rms_m_s2 / COMFORT_REFERENCE_M_S2


@dataclass(frozen=True)
class Reward:
    """The reward's weights and its terms (every term <= 0; see the module docstring)."""

    w_error: float = 10.0
    w_slip: float = 1.0
    w_comfort: float = 0.05
    w_time: float = 0.02
    macro_slip_penalty: float = 10.0

    def __post_init__(self) -> None:
        for name in ("w_error", "w_slip", "w_comfort", "w_time", "macro_slip_penalty"):  # stored as checked (floats)
            object.__setattr__(self, name, check_number(name, getattr(self, name), 0.0, 1e6))

    def terms(self, m: WindowMeasurement, contact_load_n: float, speed_m_s: float, window_s: float,
              scored_log_error: float | None, macro_slip: bool) -> dict[str, float]:
        """The weighted terms of one step's reward."""
        return dict(zip(REWARD_TERMS, (
            -self.w_error * scored_log_error if scored_log_error is not None else 0.0,
            -self.w_slip * slip_cost(m, contact_load_n, speed_m_s, window_s)
            - (self.macro_slip_penalty if macro_slip else 0.0),
            -self.w_comfort * discomfort(m),
            -self.w_time * window_s,
        )))

    def terms_without_window(self, scored_log_error: float) -> dict[str, float]:
        """The terms of a step that runs no window (a stop): only the scored error."""
        return {**dict.fromkeys(REWARD_TERMS, 0.0), "reward_error": -self.w_error * scored_log_error}


@dataclass(frozen=True)
class MacroSlipLimit:
    """Macro-slip: any wheel's creepage beyond ``max(ratio x s_peak, s_peak + floor)``, i.e. well
    past the creep-curve peak on its falling branch (twice the peak creepage, and at least two points
    of creepage beyond it: a modulation that brushes the peak is not a wheel spin). Never below the
    peak, whatever the condition."""

    ratio: float = 2.0
    floor: float = 0.02

    def __post_init__(self) -> None:
        # named as the environment's arguments; stored as checked (floats)
        object.__setattr__(self, "ratio", check_number("macro_slip_ratio", self.ratio, 1.0, 100.0, low_open=True))
        object.__setattr__(self, "floor", check_number("macro_slip_floor", self.floor, 0.0, 1.0))

    def limit(self, peak_creepage: float) -> float:
        return max(self.ratio * peak_creepage, peak_creepage + self.floor)

    def violated(self, m: WindowMeasurement, peak_creepage: float) -> bool:
        return m.max_abs_creepage > self.limit(peak_creepage)
