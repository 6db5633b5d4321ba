"""The saturation oracle: what the physics allows when the saturation torque is known.

It reads ``info["ground_truth"]["saturation_torque_nm"]`` (an oracle: ``cof-gym evaluate`` hands the
ground truth only to agents marked so), steps the DC torque through ``levels`` (fractions of it) with a
small modulation, holding the last level for a second window (near the peak the creepage settles
slowly), and reports the CoA measured in that window. Its error is the
floor set by the sensors and by holding just below the peak (about 1 %), and its return the best a
measurement of that kind can earn: a reference for the learned and the non-learned agents.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from cof_gym.task.interface import OBSERVATION_NAMES, MotorLimits, encode_action

COA = OBSERVATION_NAMES.index("coa_measured")


@dataclass
class SaturationOracle:
    """Step to ``levels[-1]`` x the true saturation torque, measure there, report the CoA."""

    limits: MotorLimits
    levels: tuple[float, ...] = (0.5, 0.9, 0.995, 0.995)
    amplitude_fraction: float = 0.01  # of the saturation torque: the hold plus the modulation stays below it
    frequency_hz: float = 5.0
    name: str = "oracle"
    oracle: bool = True
    _window: int = 0

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self._window = 0

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        m_sat = float(info["ground_truth"]["saturation_torque_nm"])
        stop = self._window >= len(self.levels)  # the last hold has been measured
        level = self.levels[min(self._window, len(self.levels) - 1)]
        self._window += 1
        return encode_action(level * m_sat, self.amplitude_fraction * m_sat, self.frequency_hz,
                             float(observation[COA]), stop, self.limits)
