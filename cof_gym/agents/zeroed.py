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
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cof_gym.agents.base import AgentWrapper
from cof_gym.task.interface import CREEPAGE_SCALE, OBSERVATION_NAMES, MotorLimits

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
        measured = float(observation[CREEPAGE]) / CREEPAGE_SCALE
        out[CREEPAGE] = (measured - self.offset) / (1.0 + self.offset) * CREEPAGE_SCALE
        return out

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self.offset = float(observation[CREEPAGE]) / CREEPAGE_SCALE
        self.agent.reset(self.zeroed(observation), info)

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        return self.agent.act(self.zeroed(observation), info)


def staircase_zeroed(limits: MotorLimits) -> CreepageZeroed:
    """The practical staircase reading the zeroed creepage."""
    from cof_gym.agents.staircase import PracticalStaircase

    return CreepageZeroed(PracticalStaircase(limits))


def model_based_zeroed(limits: MotorLimits) -> CreepageZeroed:
    """The model-based agent reading the zeroed creepage, its fit reading both of v2's analytic families (Polach's and
    Shen-Hedrick-Elkins', :data:`~cof_gym.task.creep_fit.SHAPE_FAMILIES`): the model-based agent as an engineer who
    knows the families a train meets builds it."""
    from cof_gym.agents.model_based import ModelBasedAgent
    from cof_gym.task.creep_fit import SHAPE_FAMILIES

    return CreepageZeroed(ModelBasedAgent(limits, shape_families=SHAPE_FAMILIES))
