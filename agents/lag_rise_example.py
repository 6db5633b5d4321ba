"""An agent of your own, as ``cof-gym evaluate`` and ``cof-gym watch`` play it without registering it:

    cof-gym evaluate --agents phase-rule,py:agents/lag_rise_example.py:LagRise --out out/evaluate-lag-rise

The paper's principle in a few lines (an example of the agent protocol, not a tuned method): raise the DC torque by
a fixed factor every window with a sine of a tenth of it on top, and stop once the phase lag of the wheelset speed
has risen ``stop_rise_deg`` above the first window's, the lag climbing towards 90 deg as the operating point nears the
creep curve's peak; report the largest adhesion (CoA) measured so far. It reads only the observation (sensor
readings, :data:`cof_gym.task.interface.OBSERVATION_NAMES`, each in physical units by
:func:`cof_gym.task.interface.window_reading`) and builds its action with
:func:`cof_gym.task.interface.encode_action`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from cof_gym.task.interface import MotorLimits, encode_action, window_reading


class LagRise:
    """DC steps of ``step_factor`` from ``first_fraction`` of the drive's maximum, stop on a lag rise."""

    name = "lag-rise"
    oracle = False

    def __init__(self, limits: MotorLimits, first_fraction: float = 0.01, step_factor: float = 1.15,
                 stop_rise_deg: float = 30.0, frequency_hz: float = 5.0) -> None:
        self.limits, self.first_fraction, self.step_factor = limits, first_fraction, step_factor
        self.stop_rise_deg, self.frequency_hz = stop_rise_deg, frequency_hz

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self.dc_nm = self.first_fraction * self.limits.max_dc_torque_nm
        self.first_lag_deg: float | None = None  # read from the first driven window
        self.best_coa = self.limits.min_cof_estimate

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        lag_deg, coa = window_reading(observation, "phase_lag"), window_reading(observation, "coa_measured")
        driven = info.get("elapsed_s", 0.0) > 0.0  # the reset window drives no torque
        if driven:
            self.best_coa = max(self.best_coa, coa)
            if self.first_lag_deg is None:
                self.first_lag_deg = lag_deg
            self.dc_nm *= self.step_factor
        stop = self.first_lag_deg is not None and lag_deg - self.first_lag_deg >= self.stop_rise_deg
        stop = stop or self.dc_nm >= self.limits.max_dc_torque_nm
        return encode_action(self.dc_nm, 0.1 * self.dc_nm, self.frequency_hz, self.best_coa, stop, self.limits)
