"""Scripted staircase agents: the paper's rule (an oracle reproduction) and a practical version.

Observation indices follow :data:`cof_gym.task.interface.OBSERVATION_NAMES`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cof_gym.analysis.theory import paper_schedule
from cof_gym.task.interface import OBSERVATION_NAMES, MotorLimits, encode_action

PHASE = OBSERVATION_NAMES.index("phase_lag")
PHASE_SE = OBSERVATION_NAMES.index("phase_lag_se")
COA = OBSERVATION_NAMES.index("coa_measured")
COMPLIANCE = OBSERVATION_NAMES.index("compliance")


def compliance_angle_deg(observation: np.ndarray) -> float:
    """The Eq. 3 angle read from the amplitude ratio: for the half wheelset
    |Omega/M| Iw wm = 1/|j + N R^2 k/(v wm Iw)| = sin(phi_Eq3), so asin(compliance) rises to 90 deg at
    the creep-curve peak like the phase, but is not shifted by the vehicle's speed oscillation."""
    return float(np.degrees(np.arcsin(np.clip(observation[COMPLIANCE], 0.0, 1.0))))


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
    """A staircase that knows no ground truth, scale-free across the CoF range.

    The DC torque climbs in *multiplicative* steps from ``first_fraction`` of the drive's maximum (below
    the saturation torque of the lowest CoF in range, so the first step never slips): it grows by
    ``growth`` per window while the interrogation angle stays near its baseline (the first loaded
    window), and the growth shrinks towards 1 as the angle rises (the creep slope falls near the
    peak): ``growth ** (1 / 2 ** n)`` with n the number of ``refine_at_deg`` thresholds the rise
    exceeds. The angle
    is read from the amplitude ratio (:func:`compliance_angle_deg`): without the paper's counter torque
    the train's own speed oscillation shifts the phase, not the ratio. The modulation amplitude is
    ``amplitude_ratio`` x DC (at least ``min_amplitude_nm``), small-signal at every friction level. It
    stops when the angle exceeds ``stop_angle_deg`` (near the peak; 90 deg at the peak), when the measured CoA falls twice
    although the torque rose (past the peak), or at the drive's limit, and reports the largest
    measured CoA. A window whose phase standard error exceeds ``max_phase_se_deg`` (a transient, sensor
    noise) is measured again at the same torque.
    """

    limits: MotorLimits
    first_fraction: float = 0.005
    growth: float = 1.35
    frequency_hz: float = 5.0
    amplitude_ratio: float = 0.04
    min_amplitude_nm: float = 60.0
    refine_at_deg: tuple[float, ...] = (3.0, 6.0, 10.0, 15.0, 22.0)  # rise above the baseline angle
    stop_angle_deg: float = 68.0
    max_phase_se_deg: float = 4.0
    max_repeats: int = 1
    name: str = "staircase"
    oracle: bool = False
    _baseline: float | None = None
    _dc: float = 0.0
    _best_coa: float = 0.0
    _last_coa: float = 0.0
    _repeats: int = 0
    _falls: int = 0

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self._baseline = None  # the angle of the first loaded window, with this agent's own amplitude
        self._dc = 0.0
        self._best_coa = 0.0
        self._last_coa = float(observation[COA])
        self._repeats = 0
        self._falls = 0

    def _amplitude(self, dc: float) -> float:
        return max(self.min_amplitude_nm, self.amplitude_ratio * dc)

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        angle = compliance_angle_deg(observation)
        se = float(observation[PHASE_SE]) * 90.0
        if self._dc > 0 and self._baseline is None:
            self._baseline = angle
        rise = angle - self._baseline if self._baseline is not None else 0.0
        coa = float(observation[COA])
        if se > self.max_phase_se_deg and self._repeats < self.max_repeats:
            self._repeats += 1  # unreliable window (transient, noise): measure again at the same torque
            return self._command(False)
        self._repeats = 0
        # past the peak: the CoA falls although the torque rose (twice, to ignore one noisy window)
        falling = self._dc > 0 and coa < self._last_coa * 0.995
        self._falls = self._falls + 1 if falling else 0
        self._best_coa = max(self._best_coa, coa) if self._dc > 0 else 0.0
        self._last_coa = coa
        near_peak = angle > self.stop_angle_deg and se < self.max_phase_se_deg
        if near_peak or self._falls >= 2 or self._dc >= self.limits.max_dc_torque_nm:
            return self._command(True)
        if self._dc == 0.0:
            self._dc = self.first_fraction * self.limits.max_dc_torque_nm
        else:
            refinements = sum(rise > r for r in self.refine_at_deg)
            self._dc = min(self._dc * self.growth ** (0.5 ** refinements), self.limits.max_dc_torque_nm)
        return self._command(False)

    def _command(self, stop: bool) -> np.ndarray:
        estimate = max(self._best_coa, self.limits.min_cof_estimate)
        return encode_action(self._dc, self._amplitude(self._dc), self.frequency_hz, estimate, stop, self.limits)
