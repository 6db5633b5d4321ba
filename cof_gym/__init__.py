"""cof_gym: torque-modulation measurement of the wheel-rail coefficient of friction as a MuJoCo +
Gymnasium learning problem.

Importing the package registers ``CofGym/TorqueInterrogation-v1`` (the wagon) and
``CofGym/HalfWheelset-v1`` (the paper's Sect. 2 model)."""

from __future__ import annotations

import os
import sys

# headless rendering: without a display, MuJoCo's default GLFW context cannot start
if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym  # noqa: E402

__version__ = "0.2.0"

WAGON_ENV_ID = "CofGym/TorqueInterrogation-v1"
HALF_WHEELSET_ENV_ID = "CofGym/HalfWheelset-v1"
ENV_IDS = (WAGON_ENV_ID, HALF_WHEELSET_ENV_ID)
_VEHICLES = {WAGON_ENV_ID: "wagon", HALF_WHEELSET_ENV_ID: "half_wheelset"}


def _register() -> None:
    # no max_episode_steps: the task owns the horizon (max_windows) and truncates the episode itself
    for env_id, vehicle in _VEHICLES.items():
        if env_id in gym.registry:
            continue
        gym.register(
            id=env_id,
            entry_point="cof_gym.envs.torque_interrogation:TorqueInterrogationEnv",
            vector_entry_point="cof_gym.envs.vector:TorqueInterrogationVectorEnv",
            kwargs={"vehicle": vehicle},
        )


_register()
