"""What a wheel that runs away measures, reported by an agent between its stops.

The env scores the estimate of a window that is not a stop only if the wheel runs away in it (a
macro-slip: the episode ends there). Such a runaway is itself a measurement of the CoF: the creep
curve's peak lies above the best crest bound ``c`` the climb has survived (the crest of the measured CoA's
synchronous average over the modulation cycle less one phase bin's standard error,
``info["measurement"]["coa_cycle_max"] - ["coa_cycle_bin_se"]``: no creep curve lets the crest exceed
its peak) and below what the coming window's torque crest demands, about ``c rho`` for ``rho`` the ratio
of that crest to the crest of the window that read ``c`` (commanded torques, DC + amplitude: the torque
gain error cancels). :class:`RunawayBracket` reports the bracket's geometric middle ``c sqrt(rho)``, whose
largest log error over the bracket is the smallest.

:class:`RunawayEstimate` gives any single-tone agent that estimate between its stops (``cof-gym evaluate
--agents NAME+runaway``; the staircase, the model-based agent and the robust model report it under their
own names, rule 24 in docs/interrogator.md): its torques, its stops and the estimate it reports at a stop stay its own, so
no macro-slip changes and no estimate of an episode that does not run away. The learned interrogator
reports it itself (``ClimbParameters.runaway_estimate``, rule 23 in docs/interrogator.md).

Once the crest has *fallen* from one window to the next under a rising torque crest, it has reached the
peak, and the best crest plus one bin's standard error bounds the CoF from above (:class:`CrestCeiling`).
The learned interrogator caps every estimate there (``ClimbParameters.crest_ceiling``, rule 28);
``NAME+ceiling`` is the agent as registered with that cap too (its stops' estimates included), which no
torque of its climb changes either.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from cof_gym.agents.base import AgentWrapper
from cof_gym.task.interface import MotorLimits, decode_action, encode_action
from cof_gym.validation import check_number

MODIFIER = "runaway"  # the agent-name suffix ``+runaway`` of the registry
CEILING_MODIFIER = "ceiling"  # ``+ceiling``: the agent as registered with the crest ceiling too


def crest_lower_bound(crest: float, bin_se: float) -> float:
    """A lower bound on the CoF from one window: the measured CoA's cycle crest less one phase bin's
    standard error (the crest never exceeds the creep curve's peak), at least 0."""
    return max(crest - bin_se, 0.0)


def crest_bound(measurement: Mapping[str, Any]) -> float:
    """:func:`crest_lower_bound` of one window's readings (``info["measurement"]``; 0 where the window has
    no such reading)."""
    return crest_lower_bound(float(measurement.get("coa_cycle_max", 0.0)),
                             float(measurement.get("coa_cycle_bin_se", 0.0)))


@dataclass
class RunawayBracket:
    """The CoF a wheel that runs away in the coming window would show: above the best crest bound the
    climb has survived, below the adhesion the coming window's torque crest demands (that bound scaled by
    the ratio of the two windows' commanded torque crests, DC + amplitude in N m)."""

    crest_bound: float = 0.0  # the climb's best crest bound (CoA; 0: none read yet)
    crest_torque_nm: float = 0.0  # the commanded torque crest of the window that read it

    def observe(self, bound: float, crest_torque_nm: float) -> None:
        """Take a driven window's crest bound and its commanded torque crest (N m)."""
        if bound > self.crest_bound:
            self.crest_bound, self.crest_torque_nm = bound, crest_torque_nm

    def estimate(self, next_crest_torque_nm: float) -> float | None:
        """``c sqrt(rho)``: the geometric middle of ``[c, c rho]`` for the best crest bound ``c`` and the
        coming window's crest over that window's, ``rho`` (at least 1); None before a crest was read."""
        if self.crest_bound <= 0.0 or self.crest_torque_nm <= 0.0:
            return None
        return self.crest_bound * math.sqrt(max(next_crest_torque_nm / self.crest_torque_nm, 1.0))


@dataclass
class CrestCeiling:
    """An upper bound on the CoF once the modulation's crest has reached the creep curve's peak: the first
    time a driven window's crest (the measured CoA's cycle crest, ``coa_cycle_max``) is below the previous
    window's while its commanded torque crest (DC + amplitude, N m) is above it, more torque gave less
    adhesion at the crest, which no creep curve does below its peak. From then on the CoF is at most the
    climb's best crest plus one phase bin's standard error of the window that read it (rule 28 in
    docs/interrogator.md); the crest floor is the same crest less that error.

    With ``fall_z`` > 0 a fall counts only where it exceeds ``fall_z`` standard errors of the difference of
    the two crests (``sqrt(se_1^2 + se_2^2)``, each window's bin standard error): the sensors' noise moves a
    crest by about its bin's error, and a noisier force reading (a larger ``noise_level``) lets a crest that
    still rises read lower than the last one far below the peak."""

    fall_z: float = 0.0  # the standard errors of the two crests' difference a fall must exceed (0: any fall)
    best_crest: float = 0.0  # the largest crest read so far (CoA; 0: none)
    best_crest_se: float = 0.0  # the standard error of one phase bin in the window that read it
    reached: bool = False  # whether the crest has fallen under a rising torque crest
    _last_crest: float = 0.0
    _last_se: float = 0.0
    _last_torque_nm: float = 0.0

    def __post_init__(self) -> None:
        check_number("fall_z", self.fall_z, 0.0, 10.0)

    def observe(self, crest: float, bin_se: float, crest_torque_nm: float, fall_z: float | None = None) -> None:
        """Take a driven window's crest and bin standard error (CoA; crest 0: not read) and its commanded
        torque crest (N m); ``fall_z``: this window's margin in place of the field's (e.g. 0 where the climb
        expects the peak)."""
        if crest <= 0.0:
            return
        margin = self.fall_z if fall_z is None else fall_z
        if self._last_crest > 0.0 and crest_torque_nm > self._last_torque_nm and self._fell(crest, bin_se, margin):
            self.reached = True
        if crest > self.best_crest:
            self.best_crest, self.best_crest_se = crest, bin_se
        self._last_crest, self._last_se, self._last_torque_nm = crest, bin_se, crest_torque_nm

    def _fell(self, crest: float, bin_se: float, fall_z: float) -> bool:
        """Whether ``crest`` lies below the last window's by more than ``fall_z`` standard errors of their
        difference (any amount with ``fall_z`` 0)."""
        return crest < self._last_crest - fall_z * math.hypot(bin_se, self._last_se)

    @property
    def bound(self) -> float | None:
        """The upper bound on the CoF (CoA), None until the crest has fallen under a rising torque crest."""
        return self.best_crest + self.best_crest_se if self.reached else None


@dataclass
class RunawayEstimate(AgentWrapper):
    """``agent`` (a single-tone agent acting with absolute actions) that reports, with ``bracket``, in every
    action that is not a stop, :class:`RunawayBracket`'s estimate instead of its own, and with ``ceiling``
    every estimate (a stop's too) at most :class:`CrestCeiling`'s bound once the crest has fallen under a
    rising torque crest; every other component of its action is the agent's."""

    agent: Any
    limits: MotorLimits
    name: str | None = None  # default: the agent's name + "+runaway" (+ "+ceiling" with the ceiling alone)
    bracket: bool = True
    ceiling: bool = False
    _bracket: RunawayBracket = field(default_factory=RunawayBracket, repr=False)
    _ceiling: CrestCeiling = field(default_factory=CrestCeiling, repr=False)
    _crest_nm: float = 0.0  # the commanded torque crest of the window the last action drives (0: none yet)

    def __post_init__(self) -> None:
        if not (self.bracket or self.ceiling):
            raise ValueError("a RunawayEstimate reports the bracket, the ceiling or both: got neither")
        self.name = self.name or f"{self.agent.name}+{MODIFIER if self.bracket else CEILING_MODIFIER}"
        self._wrap()  # distribution_note, env_options, ...: the agent's

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self.agent.reset(observation, info)
        self._bracket = RunawayBracket()
        self._ceiling = CrestCeiling()
        self._crest_nm = 0.0

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        if self._crest_nm > 0.0:
            measurement = info.get("measurement", {})
            self._bracket.observe(crest_bound(measurement), self._crest_nm)
            self._ceiling.observe(float(measurement.get("coa_cycle_max", 0.0)),
                                  float(measurement.get("coa_cycle_bin_se", 0.0)), self._crest_nm)
        action = np.array(self.agent.act(observation, info), dtype=np.float32)
        if action.shape != (5,):
            raise ValueError(f"{self.name}: the runaway estimate wraps single-tone agents (an action of 5 "
                             f"values), got an action of shape {action.shape}")
        command = decode_action(action, self.limits)
        drive = command.drive
        self._crest_nm = drive.dc_torque_nm + drive.amplitude_nm
        estimate = None if command.stop or not self.bracket else self._bracket.estimate(self._crest_nm)
        bound = self._ceiling.bound if self.ceiling else None
        reported = command.cof_estimate if estimate is None else estimate
        if bound is not None and reported > bound:
            estimate = bound  # only where the ceiling binds: an agent's estimate it leaves is not re-encoded
        if estimate is not None:
            action[3] = encode_action(drive.dc_torque_nm, drive.amplitude_nm, drive.frequency_hz, estimate, False,
                                      self.limits)[3]
        return action
