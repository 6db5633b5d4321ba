"""Scripted staircase agents: the paper's rule (an oracle reproduction) and a practical version.

Observation indices follow :data:`cof_gym.envs.spaces.OBSERVATION_NAMES`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cof_gym.analysis.theory import paper_schedule
from cof_gym.envs.spaces import OBSERVATION_NAMES, MotorLimits, encode_action

PHASE = OBSERVATION_NAMES.index("phase_lag")
PHASE_SE = OBSERVATION_NAMES.index("phase_lag_se")
COA = OBSERVATION_NAMES.index("coa_measured")


def limits_of(env) -> MotorLimits:
    """The motor limits of a (possibly wrapped) environment."""
    return env.unwrapped.limits


@dataclass
class PaperStaircase:
    """The paper's procedure: DC torque in percent of the *true* saturation torque (1 %, then +10 %,
    +5 % from 50 %, +3 % from 70 %, +1 % from 90 %), 345 N m at 5 Hz; stop when the phase turns
    positive (from negative, as in the paper's wagon) and report the measured CoA; if it never turns
    positive, the last step's CoA is reported. It reads the ground truth (the saturation torque), so it is
    a reproduction of the paper, labelled as an oracle."""

    limits: MotorLimits
    amplitude_nm: float = 345.0
    frequency_hz: float = 5.0
    name: str = "staircase-paper"
    oracle: bool = True
    _schedule: np.ndarray = field(default_factory=paper_schedule, repr=False)
    _step: int = 0
    _seen_negative: bool = False

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self._step = 0
        self._seen_negative = False

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        m_sat = info["ground_truth"]["saturation_torque_nm"]
        coa = float(observation[COA])
        turned_positive = self._step > 0 and self._seen_negative and observation[PHASE] > 0.0
        self._seen_negative |= self._step > 0 and observation[PHASE] <= 0.0
        if turned_positive or self._step >= len(self._schedule):
            return encode_action(info["ground_truth"]["torque_fraction"] * m_sat, self.amplitude_nm, self.frequency_hz,
                                 coa, True, self.limits)
        frac = self._schedule[self._step]
        self._step += 1
        return encode_action(frac * m_sat, self.amplitude_nm, self.frequency_hz, coa, False, self.limits)


@dataclass
class PracticalStaircase:
    """A staircase that knows no ground truth.

    The reset window (no DC torque) gives the phase baseline. The DC torque climbs in absolute steps
    (``first_step_nm``), refined as the phase rises above the baseline (the creep slope falls): the
    step halves when the rise exceeds 2, 5, 10 and 20 deg. The modulation amplitude is scaled to the
    torque level (``amplitude_ratio`` x DC, within the drive's limits), so that it stays small-signal
    at low friction. It stops when the rise exceeds ``stop_rise_deg`` (near the creep-curve peak) or
    when the measured CoA stops increasing with the torque (past the peak), and reports the largest
    measured CoA as the CoF.
    """

    limits: MotorLimits
    first_step_nm: float = 3000.0
    frequency_hz: float = 5.0
    amplitude_ratio: float = 0.03
    min_amplitude_nm: float = 30.0
    refine_at_deg: tuple[float, ...] = (2.0, 5.0, 10.0, 20.0)
    stop_rise_deg: float = 30.0
    max_phase_se_deg: float = 3.0  # a noisier window (transient, noise) is repeated, up to max_repeats
    max_repeats: int = 2
    name: str = "staircase"
    oracle: bool = False
    _baseline: float = 0.0
    _dc: float = 0.0
    _best_coa: float = 0.0
    _last_coa: float = 0.0
    _repeats: int = 0

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self._baseline = float(observation[PHASE]) * 90.0
        self._dc = 0.0
        self._best_coa = 0.0
        self._last_coa = float(observation[COA])
        self._repeats = 0

    def _amplitude(self, dc: float) -> float:
        return max(self.min_amplitude_nm, self.amplitude_ratio * dc)

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        rise = float(observation[PHASE]) * 90.0 - self._baseline
        coa = float(observation[COA])
        if float(observation[PHASE_SE]) * 90.0 > self.max_phase_se_deg and self._repeats < self.max_repeats:
            self._repeats += 1  # unreliable window: measure again at the same torque
            return encode_action(self._dc, self._amplitude(self._dc), self.frequency_hz, self._best_coa, False,
                                 self.limits)
        self._repeats = 0
        past_peak = self._dc > 0 and coa < self._last_coa - 0.002
        self._best_coa = max(self._best_coa, coa)
        self._last_coa = coa
        if rise > self.stop_rise_deg or past_peak or self._dc >= self.limits.max_dc_torque_nm:
            return encode_action(self._dc, self._amplitude(self._dc), self.frequency_hz, self._best_coa, True,
                                 self.limits)
        step = self.first_step_nm * 0.5 ** sum(rise > r for r in self.refine_at_deg)
        self._dc = min(self._dc + step, self.limits.max_dc_torque_nm)
        return encode_action(self._dc, self._amplitude(self._dc), self.frequency_hz, self._best_coa, False, self.limits)
