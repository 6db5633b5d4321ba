"""Action adapters: how a learned policy's output becomes the environment's action.

``incremental`` (the shipped PPO policy's): the policy moves the DC torque by at most
``DC_STEP_FRACTION`` of the drive's maximum per window and reports its CoF estimate as a correction of
the measured adhesion, ``estimate = CoA x (1 + 0.5 a)``; stop needs ``a > 0.5``. A random initial
policy then already holds a sensible estimate (the measured CoA) and explores torque ramps instead of
jumps, which is what made PPO learn at all here (with the absolute interface it collapsed to stopping
at once). The environment's own interface is unchanged: the adapter is part of the agent.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from cof_gym.task.interface import OBSERVATION_NAMES, MotorLimits, decode_action, encode_action

DC_STEP_FRACTION = 0.06
ESTIMATE_CORRECTION = 0.5
STOP_THRESHOLD = 0.5
ADAPTERS = ("absolute", "incremental")
_DC = OBSERVATION_NAMES.index("dc_torque")
_COA = OBSERVATION_NAMES.index("coa_measured")


def incremental_to_env(raw: np.ndarray, observation: np.ndarray, limits: MotorLimits) -> np.ndarray:
    """The environment action for the policy output ``raw`` given the last observation."""
    a = np.clip(np.asarray(raw, dtype=np.float64).reshape(-1), -1.0, 1.0)
    decoded = decode_action(a, limits)  # amplitude and frequency keep the env's mapping
    dc = float(observation[_DC]) * limits.max_dc_torque_nm + a[0] * DC_STEP_FRACTION * limits.max_dc_torque_nm
    dc = min(max(dc, 0.0), limits.max_dc_torque_nm)
    estimate = max(float(observation[_COA]), 0.0) * (1.0 + ESTIMATE_CORRECTION * a[3])
    return encode_action(dc, decoded.drive.amplitude_nm, decoded.drive.frequency_hz,
                         min(estimate, limits.max_cof_estimate), bool(a[4] > STOP_THRESHOLD), limits)


class IncrementalActions(gym.Wrapper):
    """Training-time wrapper: the policy acts through :func:`incremental_to_env`."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        self._limits: MotorLimits = env.unwrapped.limits
        self._obs: np.ndarray | None = None

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        self._obs = obs
        return obs, info

    def step(self, action):
        out = self.env.step(incremental_to_env(action, self._obs, self._limits))
        self._obs = out[0]
        return out


def wrap(env: gym.Env, adapter: str) -> gym.Env:
    if adapter == "absolute":
        return env
    if adapter == "incremental":
        return IncrementalActions(env)
    raise ValueError(f"action adapter must be one of {list(ADAPTERS)}, got {adapter!r}")
