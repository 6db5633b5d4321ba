"""A model-based interrogator: fits the creep law's family to windows measured below the peak and
extrapolates the peak (the CoF) with a confidence interval.

**What it knows.** No ground truth: only the observations (measured CoA, measured creepage, measured
speed) and the creep law's *family*: the fit of :mod:`cof_gym.task.creep_fit` (Polach shapes
with free peak CoA and peak creepage, profile-likelihood interval), on the points of its climb
(:class:`~cof_gym.task.creep_fit.ClimbRecord`).

**The climb.** The staircase's scale-free steps (:class:`~cof_gym.agents.staircase.ElasticityClimb`:
a first step below the saturation torque of CoF 0.02 on the empty wagon; growth from the measured
elasticity ``d ln s / d ln CoA``), further capped by the fitted peak once the interval has closed.

**The stop.** When the interval is narrower than ``ci_tolerance`` (relative half-width) with at least
``min_windows`` windows on the climb and the last creepage above ``min_stop_creepage`` (well above the
sensor noise), it reports the fitted peak; as fall-backs, when the measured
elasticity exceeds ``stop_elasticity`` (the CoA within a few percent of the peak), when the CoA falls
although the torque rose, or at the drive's limit. With ``knee_jump_deg`` also at a stop that does not read the
creepage: the phase rule's jump test (:func:`~cof_gym.agents.phase_rule.knee_seen`, the lag of a window over the
previous one's by more than ``knee_jump_deg`` beyond :attr:`PhaseRule.margin_se` standard errors, after
:attr:`PhaseRule.baseline_windows` driven windows), reporting there the fit's estimate, or with
``knee_low_factor`` the low end of its interval (the best CoA measured, where there is no fit) times that factor: a
lag that jumps says the peak is near, whatever the fit extrapolates (``experiments/select_model_based.py`` chose both
for ``model-based-zeroed`` on validation only).
:attr:`ModelBasedAgent.interval` holds the last fit's ``(low, estimate, high)``.

**Accuracy against intrusiveness** (validation seeds 1000-1059 of the default v1 suite, not the
reporting seeds): ``ci_tolerance`` 0.04 (default) median 0.4 % / P90 1.4 % error at a mean peak torque
of ~96 % of the saturation torque; 0.08: 0.9 % / 2.5 % at 93 %; 0.15: 1.4 % / 5.4 % at 89 % (the
paper's outlook: the CoF at lower applied torque). No macro-slip in any of them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cof_gym.agents.base import check_parameters
from cof_gym.agents.phase_rule import UNKNOWN_SE_DEG, PhaseRule, knee_seen, phase_of
from cof_gym.agents.staircase import COA, MIN_STOP_CREEPAGE, STOP_ELASTICITY, ElasticityClimb, peak_fraction
from cof_gym.task.creep_fit import ELASTICITY_SPAN, POLACH, SHAPE_FAMILIES, ClimbRecord
from cof_gym.task.interface import MotorLimits, window_reading


@dataclass
class ModelBasedAgent:
    """Creep-curve identification below the peak, reported with a confidence interval (see the module
    docstring). Knows no ground truth."""

    limits: MotorLimits
    climb: ElasticityClimb = field(default_factory=ElasticityClimb)
    ci_tolerance: float = 0.04
    min_windows: int = 4
    stop_elasticity: float = STOP_ELASTICITY
    min_stop_creepage: float = MIN_STOP_CREEPAGE
    min_span: float = ELASTICITY_SPAN
    max_ratio: float = 4.0
    shape_families: tuple[str, ...] = (POLACH,)  # the creep-law families its fit reads (creep_fit.family_shapes)
    knee_jump_deg: float | None = None  # the phase rule's jump test as a stop too, deg (None: none)
    knee_low_factor: float | None = None  # at a jump stop: the interval's low end times this (None: the fit's estimate)
    corrected_se: bool = False  # the jump test reads the lag's SE for an autocorrelated speed residual (phase_of)
    name: str = "model-based"
    oracle: bool = False
    interval: tuple[float, float, float] | None = None
    _dc: float = 0.0  # the applied DC torque, N m
    _climb: ClimbRecord = field(default_factory=ClimbRecord)
    _estimate: float = 0.0
    _phase: tuple[float, float] = (0.0, UNKNOWN_SE_DEG)  # the last window's lag and its SE, deg
    _driven: int = 0  # driven windows read

    def __post_init__(self) -> None:
        # every numeric parameter as its default is (these > 0): a clear error, not a NaN action
        check_parameters(self, positive=("ci_tolerance", "stop_elasticity", "min_span", "max_ratio"))
        if not self.shape_families or set(self.shape_families) - set(SHAPE_FAMILIES):  # refused now, not mid-fit
            raise ValueError(f"ModelBasedAgent.shape_families must be a non-empty subset of {list(SHAPE_FAMILIES)}, "
                             f"got {self.shape_families!r}")

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self._dc = 0.0
        self._climb = ClimbRecord(max_ratio=self.max_ratio, families=self.shape_families)
        self._estimate = 0.0
        self.interval = None
        self._phase = phase_of(observation, info, self.corrected_se)
        self._driven = 0

    def _knee(self, observation: np.ndarray, info: dict[str, Any]) -> bool:
        """Whether the window just read passes the phase rule's jump test (never without ``knee_jump_deg``); keeps
        its lag for the next window's test."""
        previous, self._phase = self._phase, phase_of(observation, info, self.corrected_se)
        if self._dc <= 0.0:
            return False
        self._driven += 1
        return self.knee_jump_deg is not None and self._driven > PhaseRule.baseline_windows and bool(knee_seen(
            *self._phase, *previous, 0.0, 0.0, self.knee_jump_deg, math.inf, PhaseRule.margin_se, PhaseRule.max_se_deg))

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        coa = float(observation[COA])
        creepage = window_reading(observation, "creepage_measured")
        # the DC torque the drive applied in this window (the observation's, so that the agent follows
        # the applied level even when it was not its own command, e.g. perturbed demonstrations)
        self._dc = window_reading(observation, "dc_torque", self.limits)
        climb = self._climb
        falling = self._dc > 0 and climb.add(coa, creepage, window_reading(observation, "speed"), self._dc)
        knee = self._knee(observation, info)
        e = climb.elasticity(self.min_span)
        fit = climb.fit
        best = climb.best_coa
        if fit is not None:
            self.interval = (fit.low, fit.estimate, fit.high)
            self._estimate = fit.estimate
        elif best > 0:
            self._estimate = best
        # an interval only counts once the creepage is well above the sensor noise (every peak in range
        # lies above 1 % creepage; at 0.3 % the knee has begun on every curve)
        points = len(climb.positive_points)
        informative = fit is not None and points >= self.min_windows and creepage >= self.min_stop_creepage
        narrow = informative and fit.half_width <= self.ci_tolerance
        near_peak = e >= self.stop_elasticity and creepage >= self.min_stop_creepage
        stop = narrow or near_peak or falling or knee or self._dc >= self.limits.max_dc_torque_nm
        if stop and near_peak and fit is not None and not narrow:
            # the fit disagrees with the curve's own flattening: trust the measured peak region
            self._estimate = max(best, best / max(peak_fraction(e), 1e-3))
        elif knee and not narrow and self.knee_low_factor is not None:
            # the lag says the peak is near: the fit's low end (at least the best CoA measured)
            self._estimate = (fit.low if fit is not None else best) * self.knee_low_factor
        if not stop:
            cap = max(fit.estimate / max(coa, 1e-9) - 1.0, 0.0) if climb.closed() else None
            self._dc = self.climb.next_dc(self._dc, e, self.limits, room_cap=cap)
        return self.climb.command(self._dc, self._estimate, stop, self.limits)
