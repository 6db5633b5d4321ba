"""Scripted staircase agents: the paper's rule (an oracle reproduction) and a practical version.

Observation indices follow :data:`cof_gym.task.interface.OBSERVATION_NAMES`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cof_gym.agents.base import check_parameters
from cof_gym.analysis.theory import PAPER_AMPLITUDE_NM, PAPER_FREQUENCY_HZ, paper_schedule
from cof_gym.task.creep_fit import coa_fell, elasticity_between
from cof_gym.task.interface import OBSERVATION_NAMES, MotorLimits, encode_action, window_reading

PHASE = OBSERVATION_NAMES.index("phase_lag")
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
    amplitude_nm: float = PAPER_AMPLITUDE_NM
    frequency_hz: float = PAPER_FREQUENCY_HZ
    name: str = "staircase-paper"
    oracle: bool = True
    _schedule: np.ndarray = field(default_factory=paper_schedule, repr=False)
    _step: int = 0
    _seen_negative: bool = False

    def __post_init__(self) -> None:
        # every numeric parameter as its default is (these > 0): a clear error, not a NaN action
        check_parameters(self, positive=("amplitude_nm", "frequency_hz"))

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


# How far below the creep-curve peak a point of the rising branch lies, read from the local log-slope
# (elasticity) e = d ln(creepage) / d ln(CoA): 1 on the linear part, infinite at the peak. Steady
# Polach curves of every default condition (dry, wet, low adhesion), CoF over each condition's range,
# 5-40 m/s and both wheel loads give CoA / CoF within the [min, max] band below for each e (computed
# with cof_gym.physics.creep; scale-free: neither the CoF nor the condition has to be known).
ELASTICITY = (1.0, 1.1, 1.25, 1.5, 2.0, 3.0, 5.0, 8.0, 15.0, 40.0)
PEAK_FRACTION_MEDIAN = (0.0, 0.270, 0.396, 0.507, 0.619, 0.719, 0.860, 0.955, 0.987, 0.998)
PEAK_FRACTION_MAX = (0.30, 0.373, 0.535, 0.667, 0.787, 0.877, 0.935, 0.970, 0.993, 0.999)
# the elasticity climbs' stop near the peak (StaircaseAgent, ModelBasedAgent): e at least this, at a creepage of at
# least MIN_STOP_CREEPAGE (every peak in range lies above 1 %: a large e at a tiny creepage is sensor noise)
STOP_ELASTICITY = 10.0
MIN_STOP_CREEPAGE = 0.003


def peak_fraction(elasticity: float, table: tuple[float, ...] = PEAK_FRACTION_MEDIAN) -> float:
    """CoA / CoF on the rising branch where the creep curve's elasticity is ``elasticity``."""
    return float(np.interp(np.log(max(elasticity, 1.0)), np.log(ELASTICITY), table))


@dataclass(frozen=True)
class ElasticityClimb:
    """The climb of the scale-free agents (the practical staircase and the model-based agent).

    The DC torque starts at ``first_fraction`` of the drive's maximum (below the saturation torque of
    the lowest CoF in range on the empty wagon, so the first step never slips) and grows by
    ``safety`` x the largest step that keeps the CoA below the peak on the worst curve of the band at
    the measured elasticity (``1 / max_fraction(e) - 1``), within [``min_growth``, ``max_growth``].
    The modulation amplitude is ``amplitude_ratio`` x DC (at least ``min_amplitude_nm``)."""

    first_fraction: float = 0.005
    max_growth: float = 1.5
    min_growth: float = 1.01
    safety: float = 0.5
    frequency_hz: float = 5.0
    amplitude_ratio: float = 0.02
    min_amplitude_nm: float = 40.0

    def __post_init__(self) -> None:
        # every numeric parameter as its default is (these > 0): a clear error, not a NaN action
        check_parameters(self, positive=("first_fraction", "max_growth", "min_growth", "safety", "frequency_hz",
                                       "amplitude_ratio", "min_amplitude_nm"))

    def first_dc(self, limits: MotorLimits) -> float:
        """The first DC torque (N m) of a climb: ``first_fraction`` of the drive's maximum, below the
        saturation torque of the lowest CoF in range on the empty wagon (shared by every climbing agent)."""
        return self.first_fraction * limits.max_dc_torque_nm

    def next_dc(self, dc: float, elasticity: float, limits: MotorLimits, room_cap: float | None = None) -> float:
        """The next DC torque (N m) after ``dc`` at the measured ``elasticity``; ``room_cap`` bounds
        the relative step further (e.g. a fitted peak)."""
        if dc == 0.0:
            return self.first_dc(limits)
        room = 1.0 / peak_fraction(elasticity, PEAK_FRACTION_MAX) - 1.0
        if room_cap is not None:
            room = min(room, room_cap)
        growth = min(max(1.0 + self.safety * room, self.min_growth), self.max_growth)
        return min(dc * growth, limits.max_dc_torque_nm)

    def command(self, dc: float, estimate: float, stop: bool, limits: MotorLimits) -> np.ndarray:
        """The absolute env action for this DC torque, its modulation and the estimate."""
        estimate = limits.clip_estimate(estimate)
        amplitude = max(self.min_amplitude_nm, self.amplitude_ratio * dc)
        return encode_action(dc, amplitude, self.frequency_hz, estimate, stop, limits)


@dataclass
class PracticalStaircase:
    """A staircase that knows no ground truth, scale-free across the CoF range and conditions.

    It reads the creep curve through the measured CoA and creepage of its own windows: the local
    elasticity ``e = d ln(creepage) / d ln(CoA)`` (between the last two windows of the climb) is 1 on the linear part and grows without bound at the peak, and at a given ``e``
    every Polach curve in the default conditions lies within a narrow band of CoA / CoF
    (:data:`PEAK_FRACTION_MEDIAN`, :data:`PEAK_FRACTION_MAX`). So:

    * the DC torque climbs in multiplicative steps (:class:`ElasticityClimb`): big steps on the
      linear part, small ones near the knee, whatever the condition, and a first step that never
      slips;
    * it stops when ``e`` exceeds ``stop_elasticity`` (CoA within a few percent of the peak) at a
      creepage of at least ``min_stop_creepage`` (every peak in range lies above 1 %: a large ``e``
      at a tiny creepage is sensor noise), when the CoA falls although the torque rose (past the
      peak), or at the drive's limit;
    * it reports the measured CoA divided by the median CoA / CoF at the measured ``e`` (never less
      than the largest CoA it measured).

    The modulation amplitude is small: the method does not need a large one, and a small one keeps
    the modulation from brushing the peak. The compliance angle is not used: at high speed and low adhesion the amplitude ratio saturates (angle
    90 deg) at 70-80 % of the saturation torque, long before the peak.
    """

    limits: MotorLimits
    climb: ElasticityClimb = field(default_factory=ElasticityClimb)
    stop_elasticity: float = STOP_ELASTICITY
    min_stop_creepage: float = MIN_STOP_CREEPAGE
    name: str = "staircase"
    oracle: bool = False
    _dc: float = 0.0
    _best_coa: float = 0.0
    _estimate: float = 0.0
    _points: list = field(default_factory=list)
    _falls: int = 0

    def __post_init__(self) -> None:
        # every numeric parameter as its default is (these > 0): a clear error, not a NaN action
        check_parameters(self, positive=("stop_elasticity",))

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self._dc = 0.0
        self._best_coa = 0.0
        self._estimate = 0.0
        self._points = []
        self._falls = 0

    def elasticity(self) -> float:
        """d ln s / d ln CoA between the last two windows of the climb (1 with fewer than two, or when
        the CoA barely moved)."""
        if len(self._points) < 2:
            return 1.0
        return elasticity_between(self._points[-2], self._points[-1])

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        coa = float(observation[COA])
        creepage = window_reading(observation, "creepage_measured")
        if self._dc > 0:
            falling = bool(self._points) and coa_fell(coa, self._points[-1][0])
            self._falls = self._falls + 1 if falling else 0
            self._points.append((coa, creepage))
            self._best_coa = max(self._best_coa, coa)
        e = self.elasticity()
        if self._dc > 0:
            self._estimate = max(self._best_coa, coa / max(peak_fraction(e), 1e-3)) if e >= 2.0 else self._best_coa
        near_peak = e >= self.stop_elasticity and creepage >= self.min_stop_creepage
        stop = near_peak or self._falls >= 1 or self._dc >= self.limits.max_dc_torque_nm
        if not stop:
            self._dc = self.climb.next_dc(self._dc, e, self.limits)
        return self.climb.command(self._dc, self._estimate, stop, self.limits)
