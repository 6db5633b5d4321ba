"""cof_gym: torque-modulation measurement of the wheel-rail coefficient of friction as a MuJoCo +
Gymnasium learning problem.

Importing the package registers ``CofGym/TorqueInterrogation-v0`` (the wagon) and
``CofGym/HalfWheelset-v0`` (the paper's Sect. 2 model)."""

from __future__ import annotations

import os
import sys

# headless rendering: without a display, MuJoCo's default GLFW context cannot start
if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym  # noqa: E402

__version__ = "0.1.0"

DEFAULT_MAX_WINDOWS = 30
ENV_IDS = ("CofGym/TorqueInterrogation-v0", "CofGym/HalfWheelset-v0")
WAGON_ENV_ID = "CofGym/TorqueInterrogation-v0"
HALF_WHEELSET_ENV_ID = "CofGym/HalfWheelset-v0"


def _register() -> None:
    for env_id, vehicle in zip(ENV_IDS, ("wagon", "half_wheelset")):
        if env_id in gym.registry:
            continue
        gym.register(
            id=env_id,
            entry_point="cof_gym.envs.torque_interrogation:TorqueInterrogationEnv",
            vector_entry_point="cof_gym.envs.vector:TorqueInterrogationVectorEnv",
            max_episode_steps=DEFAULT_MAX_WINDOWS,
            kwargs={"vehicle": vehicle},
        )


_register()
