"""The measured creepage zeroed at coasting: an agent that reads the creepage, given it with the systematic offset
the reset window shows taken out.

A train reads the creepage as ``R_assumed omega / v_reference - 1``. A wheel radius or a reference speed that is off
by a fraction of a percent (v2's ``wheel_radius_error``, ``speed_sensor_error``) makes that reading
``s_m = d + s (1 + d)`` with ``d = (1 + e_R) / (1 + e_v) - 1``
(:attr:`cof_gym.task.sensors.SensorErrors.creepage_offset`): an offset as large as a creep curve's peak creepage,
and a scale that differs from 1 by as much. Where no torque acts the true creepage is zero, so a window driven without
torque reads ``d`` itself, up to the encoder's noise: the same correction a wheel-slide protection makes for the
wheels' diameter differences, which its standard asks it to handle (EN 15595:2018, clause 5.1.6 "Wheel diameter
differences"). The env's reset window is such a window: its DC torque is zero. :class:`CreepageZeroed` keeps the
creepage that window read, ``d``, and hands the agent every later reading as ``(s_m - d) / (1 + d)``, the true
creepage up to the noise of two windows; everything else the agent reads, and everything it does, is its own.

**A stop that does not trust the creepage alone** (``model-based-zeroed-knee``, session 74): the zeroed model-based
agent that also stops on the phase rule's jump test, its jump and what it reports there chosen by
``experiments/select_model_based.py`` on validation only (the 192 episodes of ``select_robust_model.py``; ranked by
macro-slips, then median + P90, as the phase rule and the robust model were chosen), 17 settings:

| knee jump | reported at a jump stop | median | P90 | macro-slips |
|---|---|---|---|---|
| none (``model-based-zeroed``) | | 1.0 % | 11.8 % | 26 |
| 2 deg (chosen) | the fit's estimate | 3.0 % | 30.4 % | 16 |
| 4 deg | the fit's estimate | 2.8 % | 29.7 % | 17 |
| 6 deg | the fit's estimate | 2.1 % | 29.0 % | 17 |
| 8 deg | the fit's estimate | 1.9 % | 28.7 % | 19 |
| 2 deg | the interval's low end x 1.05 | 3.6 % | 30.9 % | 16 |

A lag that jumps stops ten of the 26 runaways before the peak, and stops other climbs there too, while the fit's
interval is still wide: the trade between a runaway and a larger error that every stop short of the peak meets. Both
agents are in the default list.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cof_gym.agents.base import AgentWrapper
from cof_gym.task.interface import CREEPAGE_SCALE, OBSERVATION_NAMES, MotorLimits, window_reading

CREEPAGE = OBSERVATION_NAMES.index("creepage_measured")
SUFFIX = "zeroed"  # the agent's name is the wrapped agent's + "-zeroed"


@dataclass
class CreepageZeroed(AgentWrapper):
    """``agent`` (reading the window observation, :data:`~cof_gym.task.interface.OBSERVATION_NAMES`) given every
    creepage with the reset window's reading, the offset, taken out (see the module docstring)."""

    agent: Any
    name: str = ""
    offset: float = field(default=0.0, init=False)  # the reset window's creepage reading (the offset d)

    def __post_init__(self) -> None:
        self.name = self.name or f"{self.agent.name}-{SUFFIX}"
        self._wrap()

    def zeroed(self, observation: np.ndarray) -> np.ndarray:
        """``observation`` with its creepage as ``(s_m - offset) / (1 + offset)`` (a copy)."""
        out = np.array(observation, dtype=np.float32, copy=True)
        measured = window_reading(observation, "creepage_measured")
        out[CREEPAGE] = (measured - self.offset) / (1.0 + self.offset) * CREEPAGE_SCALE
        return out

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self.offset = window_reading(observation, "creepage_measured")
        self.agent.reset(self.zeroed(observation), info)

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        return self.agent.act(self.zeroed(observation), info)


def staircase_zeroed(limits: MotorLimits) -> CreepageZeroed:
    """The practical staircase reading the zeroed creepage."""
    from cof_gym.agents.staircase import PracticalStaircase

    return CreepageZeroed(PracticalStaircase(limits))


KNEE_JUMP_DEG = 2.0  # model-based-zeroed-knee's jump (deg; select_model_based.py, the table above)


def model_based_zeroed(limits: MotorLimits, knee_jump_deg: float | None = None,
                       knee_low_factor: float | None = None, corrected_se: bool = False) -> CreepageZeroed:
    """The model-based agent reading the zeroed creepage, its fit reading both of v2's analytic families (Polach's and
    Shen-Hedrick-Elkins', :data:`~cof_gym.task.creep_fit.SHAPE_FAMILIES`): the model-based agent as an engineer who
    knows the families a train meets builds it; ``knee_jump_deg``, ``knee_low_factor``, ``corrected_se``: the phase
    rule's jump test as a stop too, what it reports there and the lag's SE it reads
    (:class:`~cof_gym.agents.model_based.ModelBasedAgent`)."""
    from cof_gym.agents.model_based import ModelBasedAgent
    from cof_gym.task.creep_fit import SHAPE_FAMILIES

    return CreepageZeroed(ModelBasedAgent(limits, shape_families=SHAPE_FAMILIES, knee_jump_deg=knee_jump_deg,
                                          knee_low_factor=knee_low_factor, corrected_se=corrected_se))


def model_based_zeroed_knee(limits: MotorLimits, corrected_se: bool = False) -> CreepageZeroed:
    """:func:`model_based_zeroed` that also stops on the phase rule's jump test of :data:`KNEE_JUMP_DEG`, reporting the
    fit's estimate there (validation-chosen; the module docstring); with ``corrected_se`` the test reads the lag's SE
    for an autocorrelated speed residual (``model-based-zeroed-knee-ar1``, as ``phase-rule-ar1``; every other setting
    as chosen)."""
    agent = model_based_zeroed(limits, knee_jump_deg=KNEE_JUMP_DEG, corrected_se=corrected_se)
    agent.name = f"{agent.name}-knee" + ("-ar1" if corrected_se else "")
    return agent


def model_based_zeroed_knee_ar1(limits: MotorLimits) -> CreepageZeroed:
    """:func:`model_based_zeroed_knee` reading the lag's SE for an autocorrelated speed residual."""
    return model_based_zeroed_knee(limits, corrected_se=True)
