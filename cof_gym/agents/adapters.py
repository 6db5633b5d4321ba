"""Action adapters: how a learned policy's output becomes the environment's action.

The interface that made PPO learn now lives in the environment: ``action_type="relative"`` (and
``observation_type="history"``), :mod:`cof_gym.task.actions`, which RL Zoo and ``cof-gym train`` select
through ``env_kwargs`` (``cof_gym/agents/hyperparams/ppo.yml``). What is left here is the agent side
of the same code, for an env built with the default (absolute, window) interface, e.g. an evaluation
suite's:

- ``"relative"`` (alias ``"incremental"``, the name of the former agent-side adapter): the policy acts
  through :class:`cof_gym.task.actions.RelativeActions`, its decoded command re-encoded as an absolute
  action. :func:`wrap` returns the env unchanged when it already has the relative action type.
- :class:`AgentSideInterface`: a policy trained on any action/observation type acting in a default env;
  it keeps the episode's :class:`~cof_gym.task.interface.Memory` from the window observations exactly
  as the env does, so a "history" observation built here equals the env's bit for bit, and the relative
  action decodes to the env's command up to float32 rounding of the re-encoded action.

The former ``incremental`` semantics (linear DC steps of 6 % of max, estimate = CoA x (1 + 0.5 a))
are gone: the relative type's log-steps are scale-free across CoF 0.02-0.6 and its first step from
zero cannot slip.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from cof_gym.task.actions import ActionContext, RelativeActions, get_action_type
from cof_gym.task.interface import (
    HISTORY_OBSERVATION_NAMES, OBSERVATION_NAMES, Memory, MotorLimits, encode_action, get_observation_type,
    window_reading,
)

RELATIVE = RelativeActions()
ESTIMATE_CORRECTION = RELATIVE.estimate_log_range
STOP_THRESHOLD = RELATIVE.stop_threshold
ADAPTERS = ("absolute", "relative", "incremental")
_COA = OBSERVATION_NAMES.index("coa_measured")
_BEST = HISTORY_OBSERVATION_NAMES.index("best_coa")


def incremental_to_env(raw: np.ndarray, observation: np.ndarray, limits: MotorLimits) -> np.ndarray:
    """Stateless: the absolute env action for the relative policy output ``raw`` given the last
    observation (its DC torque; the best measured CoA of a "history" observation, or else the window's
    measured CoA). Prefer :class:`AgentSideInterface`, which remembers the best CoA like the env."""
    a = np.clip(np.asarray(raw, dtype=np.float64).reshape(-1), -1.0, 1.0)
    obs = np.asarray(observation, dtype=np.float64).reshape(-1)
    best = float(obs[_BEST]) if obs.shape[0] == len(HISTORY_OBSERVATION_NAMES) else max(float(obs[_COA]), 0.0)
    context = ActionContext(window_reading(obs, "dc_torque", limits), best)
    d = RELATIVE.decode(context, a, limits)
    return encode_action(d.drive.dc_torque_nm, d.drive.amplitude_nm, d.drive.frequency_hz, d.cof_estimate, d.stop,
                         limits)


class AgentSideInterface:
    """A policy's action/observation types applied on the agent's side of a default (absolute, window)
    env. Call :meth:`reset` with the reset observation, then per step :meth:`to_env` (policy action ->
    env action) and :meth:`observe` (env observation -> policy observation)."""

    def __init__(self, limits: MotorLimits, action_type: str = "relative", observation_type: str = "window") -> None:
        self.limits = limits
        self.actions = get_action_type(action_type)
        self.observations = get_observation_type(observation_type)
        self.memory = Memory()
        self.dc_torque_nm = 0.0
        self.windows = 0

    def reset(self, observation: np.ndarray) -> np.ndarray:
        self.memory = Memory()
        self.dc_torque_nm = 0.0
        self.windows = 0
        return self.observe(observation)

    def observe(self, observation: np.ndarray) -> np.ndarray:
        window = np.asarray(observation, dtype=np.float32)[:len(OBSERVATION_NAMES)]
        self.memory.push(window, driven=self.windows > 0)
        return self.observations.encode(window, self.memory)

    def to_env(self, raw: np.ndarray) -> np.ndarray:
        a = np.clip(np.asarray(raw, dtype=np.float64).reshape(-1), -1.0, 1.0)
        d = self.actions.decode(ActionContext.of(self.dc_torque_nm, self.memory), a, self.limits)
        action = encode_action(d.drive.dc_torque_nm, d.drive.amplitude_nm, d.drive.frequency_hz, d.cof_estimate,
                               d.stop, self.limits)
        self.dc_torque_nm = d.drive.dc_torque_nm
        self.windows += 1
        return action


class IncrementalActions(gym.Wrapper):
    """Training-time wrapper: the policy acts through the relative action type on an absolute env."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        self._interface = AgentSideInterface(env.unwrapped.limits, "relative", "window")

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        self._interface.reset(obs)
        return obs, info

    def step(self, action):
        out = self.env.step(self._interface.to_env(action))
        self._interface.observe(out[0])
        return out


RelativeActionsWrapper = IncrementalActions


def wrap(env: gym.Env, adapter: str) -> gym.Env:
    if adapter == "absolute":
        return env
    if adapter in ("relative", "incremental"):
        task = getattr(env.unwrapped, "task", None)
        if getattr(task, "action_type", "absolute") == "relative":
            return env  # the env already decodes relative actions
        return IncrementalActions(env)
    raise ValueError(f"action adapter must be one of {list(ADAPTERS)}, got {adapter!r}")
