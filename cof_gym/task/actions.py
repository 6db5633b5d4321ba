"""Action types: how the agent's ``Box(-1, 1, (5,))`` action becomes a drive command, an estimate and a
stop request (highway-env style: the env option ``action_type`` picks one; every type has the same
space, so a policy's shape does not depend on it).

Each type has ``space()``, ``decode(context, action, limits) -> DecodedAction`` and the inverse
``encode(context, dc, amplitude, frequency, estimate, stop, limits)`` for scripted agents. The
:class:`ActionContext` is what a type may read of the episode so far: the DC torque now applied and the
best measured CoA (both known on board; the env keeps them in :class:`cof_gym.task.Episode`, an agent can
keep them from its own commands and the observations).

- ``"absolute"`` (default, :class:`AbsoluteActions`): DC torque linear 0...max, amplitude, frequency and
  estimate logarithmic, stop > 0 (:func:`~cof_gym.task.interface.decode_action`).
- ``"relative"`` (:class:`RelativeActions`): scale-free across the CoF range. The DC torque moves by a
  log-step from the current level, ``dc' = max(dc, floor) x exp(max_log_step x a0)`` (at most x1.65 or
  /1.65 per window), ``floor = floor_fraction x max`` (0.3 %: the first step from zero, amplitude
  included, stays below the smallest saturation torque in range, ~1.1 % of max); the amplitude is a
  fraction of the new DC level, logarithmic 1 %...30 % (within the drive's 20...3000 N m); frequency
  as in ``absolute``; the estimate is a factor on the best measured CoA so far,
  ``max(best_coa, 0.01) x exp(0.5 a3)`` (x0.61...x1.65, within 0.01...1); stop needs ``a4 > 0.5``. A
  random policy thus holds a sensible estimate and explores torque ramps rather than jumps, and the
  same action means the same relative change at CoF 0.02 and 0.6.
- ``"identified"`` (:class:`IdentifiedActions`): the relative torque, amplitude and frequency, and the
  estimate a factor ``exp(0.05 a3)`` (x0.95...x1.05) on the peak of the creep-curve fit of the climb
  so far (:mod:`cof_gym.task.creep_fit`; the best measured CoA before 3 points): the policy
  decides how to climb and when to stop, and corrects the fit by a few percent.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from gymnasium import spaces

from cof_gym.task.creep_fit import ClimbRecord
from cof_gym.physics.simulation import DriveCommand
from cof_gym.task.interface import (
    DecodedAction, Memory, MotorLimits, _log_map, _log_unmap, action_space, decode_action, encode_action,
)


@dataclass(frozen=True)
class ActionContext:
    """What an action type reads of the episode: the DC torque now applied (N m), the best (largest)
    measured CoA so far (0 before any) and the climb whose creep-curve fit gives the fitted peak."""

    dc_torque_nm: float = 0.0
    best_coa: float = 0.0
    climb: ClimbRecord | None = None

    @classmethod
    def of(cls, dc_torque_nm: float, memory: Memory) -> "ActionContext":
        """The context of an episode whose :class:`~cof_gym.task.interface.Memory` is ``memory``."""
        return cls(dc_torque_nm, memory.best_coa, memory.climb)

    @property
    def fitted_peak(self) -> float:
        """The fit's peak CoA (:mod:`cof_gym.task.creep_fit`); 0 before a fit (< 3 points)."""
        fit = self.climb.fit if self.climb is not None else None
        return fit.estimate if fit is not None else 0.0


class ActionType(Protocol):
    name: str

    def space(self) -> spaces.Box: ...

    def decode(self, context: ActionContext, a: np.ndarray, limits: MotorLimits) -> DecodedAction: ...

    def encode(self, context: ActionContext, dc_torque_nm: float, amplitude_nm: float, frequency_hz: float,
               cof_estimate: float, stop: bool, limits: MotorLimits) -> np.ndarray: ...


@dataclass(frozen=True)
class AbsoluteActions:
    """The v1 interface (the context is not used)."""

    name: str = "absolute"

    def space(self) -> spaces.Box:
        return action_space()

    def decode(self, context: ActionContext, a: np.ndarray, limits: MotorLimits) -> DecodedAction:
        return decode_action(a, limits)

    def encode(self, context: ActionContext, dc_torque_nm: float, amplitude_nm: float, frequency_hz: float,
               cof_estimate: float, stop: bool, limits: MotorLimits) -> np.ndarray:
        return encode_action(dc_torque_nm, amplitude_nm, frequency_hz, cof_estimate, stop, limits)


@dataclass(frozen=True)
class RelativeActions:
    """DC torque as a log-step from the current level, amplitude as a fraction of the DC level, the
    estimate as a factor on the best measured CoA (see the module docstring)."""

    name: str = "relative"
    floor_fraction: float = 0.003  # of the drive's max DC torque: the level a step from zero starts at
    max_log_step: float = 0.5  # |ln(dc' / dc)| <= 0.5 per window
    min_amplitude_ratio: float = 0.01  # amplitude / DC level
    max_amplitude_ratio: float = 0.3
    estimate_log_range: float = 0.5  # |ln(estimate / best_coa)| <= 0.5
    stop_threshold: float = 0.5

    def space(self) -> spaces.Box:
        return action_space()

    def floor_nm(self, limits: MotorLimits) -> float:
        return self.floor_fraction * limits.max_dc_torque_nm

    def decode(self, context: ActionContext, a: np.ndarray, limits: MotorLimits) -> DecodedAction:
        floor = self.floor_nm(limits)
        dc = min(max(context.dc_torque_nm, floor) * math.exp(self.max_log_step * float(a[0])), limits.max_dc_torque_nm)
        ratio = _log_map(float(a[1]), self.min_amplitude_ratio, self.max_amplitude_ratio)
        amp = min(max(ratio * max(dc, floor), limits.min_amplitude_nm), limits.max_amplitude_nm)
        freq = _log_map(float(a[2]), limits.min_frequency_hz, limits.max_frequency_hz)
        est = self._base(context, limits) * math.exp(self.estimate_log_range * float(a[3]))
        est = limits.clip_estimate(est)
        return DecodedAction(DriveCommand(dc, amp, freq), float(est), bool(a[4] > self.stop_threshold))

    def encode(self, context: ActionContext, dc_torque_nm: float, amplitude_nm: float, frequency_hz: float,
               cof_estimate: float, stop: bool, limits: MotorLimits) -> np.ndarray:
        """The action whose decode is closest to the request (clipped to what one window can do)."""
        floor = self.floor_nm(limits)
        level = max(context.dc_torque_nm, floor)
        a0 = math.log(dc_torque_nm / level) / self.max_log_step if dc_torque_nm > 0 else -1.0
        a1 = _log_unmap(amplitude_nm / max(dc_torque_nm, floor), self.min_amplitude_ratio, self.max_amplitude_ratio)
        a2 = _log_unmap(frequency_hz, limits.min_frequency_hz, limits.max_frequency_hz)
        est = limits.clip_estimate(cof_estimate)
        a3 = math.log(est / self._base(context, limits)) / self.estimate_log_range
        a4 = 1.0 if stop else -1.0
        return np.clip(np.array([a0, a1, a2, a3, a4]), -1.0, 1.0).astype(np.float32)

    def _base(self, context: ActionContext, limits: MotorLimits) -> float:
        """What the estimate is a factor on: the best measured CoA."""
        return _within_estimate_range(context.best_coa, limits)


@dataclass(frozen=True)
class IdentifiedActions(RelativeActions):
    """The relative torque, amplitude and frequency actions, with the estimate a factor within
    x0.95...x1.05 on the climb's fitted peak (:attr:`ActionContext.fitted_peak`; the best measured CoA
    before a fit): a residual on the model-based identification, for a policy that decides how to climb
    and when to stop and corrects the fit by a few percent."""

    name: str = "identified"
    estimate_log_range: float = 0.05

    def _base(self, context: ActionContext, limits: MotorLimits) -> float:
        fitted = context.fitted_peak
        return _within_estimate_range(fitted if fitted > 0 else context.best_coa, limits)


def _within_estimate_range(coa: float, limits: MotorLimits) -> float:
    coa = coa if math.isfinite(coa) else 0.0
    return limits.clip_estimate(coa)


ACTION_TYPES: dict[str, ActionType] = {"absolute": AbsoluteActions(), "relative": RelativeActions(),
                                       "identified": IdentifiedActions()}


def get_action_type(name: str) -> ActionType:
    try:
        return ACTION_TYPES[name]
    except (KeyError, TypeError):
        raise ValueError(f"action_type must be one of {list(ACTION_TYPES)}, got {name!r}") from None
