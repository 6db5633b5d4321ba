"""The saturation oracle: what the physics allows when the saturation torque is known.

It reads ``info["ground_truth"]["saturation_torque_nm"]`` (an oracle: ``cof-gym evaluate`` hands the
ground truth only to agents marked so), steps the DC torque through ``levels`` (fractions of it) with a
small modulation, holding the last level for a second window (near the peak the creepage settles
slowly), and reports the CoA measured in that window. Every level plus the modulation stays below the
saturation torque (checked at construction): a crest past the peak lets the wheel run away on a creep
curve that falls steeply after it (with a hold at 99.5 % and a 1 % modulation, i.e. a crest at 100.5 %,
it did in 23 of the 54 episodes of ``experiments/suites/v2_validation_steep_grid.json``; with the hold
at 98.5 % in none). Its error is the floor set by the sensors and by holding just below the peak
(about 1.5 %), and its return the best a measurement of that kind can earn: a reference for the
learned and the non-learned agents.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from cof_gym.task.interface import OBSERVATION_NAMES, MotorLimits, encode_action
from cof_gym.validation import check_number

COA = OBSERVATION_NAMES.index("coa_measured")


@dataclass
class SaturationOracle:
    """Step to ``levels[-1]`` x the true saturation torque, measure there, report the CoA."""

    limits: MotorLimits
    levels: tuple[float, ...] = (0.5, 0.9, 0.985, 0.985)
    amplitude_fraction: float = 0.01  # of the saturation torque: the hold plus the modulation stays below it
    frequency_hz: float = 5.0
    name: str = "oracle"
    oracle: bool = True
    _window: int = 0

    def __post_init__(self) -> None:
        check_number("amplitude_fraction", self.amplitude_fraction, 0.0, 1.0, low_open=True)
        if not self.levels or not all(0.0 < level < 1.0 - self.amplitude_fraction for level in self.levels):
            raise ValueError(f"levels must lie in (0, 1 - amplitude_fraction = {1.0 - self.amplitude_fraction:g}) "
                             f"so that the crest stays below the saturation torque, got {self.levels!r}")

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self._window = 0

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        m_sat = float(info["ground_truth"]["saturation_torque_nm"])
        stop = self._window >= len(self.levels)  # the last hold has been measured
        level = self.levels[min(self._window, len(self.levels) - 1)]
        self._window += 1
        return encode_action(level * m_sat, self.amplitude_fraction * m_sat, self.frequency_hz,
                             float(observation[COA]), stop, self.limits)
