"""cof_gym: torque-modulation measurement of the wheel-rail coefficient of friction as a MuJoCo +
Gymnasium learning problem.

Importing the package registers ``CofGym/TorqueInterrogation-v2`` (the wagon) and
``CofGym/HalfWheelset-v2`` (the paper's Sect. 2 model), the realistic task (creep-law families,
systematic sensor errors), their v1 predecessors, kept as published, and
``CofGym/TorqueInterrogationInService-v3``: task v3, the wagon with a train's speed probe (pulses, runout,
lag) and track irregularity drawn as well. Its name is its own, so that Gymnasium does not call the -v2
ids, on which the shipped agents were trained, out of date; its version is the task's."""

from __future__ import annotations

import os
import sys

# headless rendering: without a display, MuJoCo's default GLFW context cannot start
if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym  # noqa: E402

__version__ = "0.2.0"

WAGON_ENV_ID = "CofGym/TorqueInterrogation-v2"
WAGON_IN_SERVICE_ENV_ID = "CofGym/TorqueInterrogationInService-v3"
HALF_WHEELSET_ENV_ID = "CofGym/HalfWheelset-v2"
WAGON_V1_ENV_ID = "CofGym/TorqueInterrogation-v1"
HALF_WHEELSET_V1_ENV_ID = "CofGym/HalfWheelset-v1"
ENV_IDS = (WAGON_ENV_ID, HALF_WHEELSET_ENV_ID, WAGON_V1_ENV_ID, HALF_WHEELSET_V1_ENV_ID,
           WAGON_IN_SERVICE_ENV_ID)
# id -> (vehicle, task version): v2 draws creep-law families and systematic sensor errors; v1 stays as
# published (the Polach presets, unbiased sensors); v3 also draws a train's speed probe and track, the wagon only (the
# half wheelset rides on no track spring, so a track's profile would not reach it)
_IDS = {WAGON_ENV_ID: ("wagon", 2), HALF_WHEELSET_ENV_ID: ("half_wheelset", 2),
        WAGON_IN_SERVICE_ENV_ID: ("wagon", 3),
        WAGON_V1_ENV_ID: ("wagon", 1), HALF_WHEELSET_V1_ENV_ID: ("half_wheelset", 1)}


# The task's default horizon (max_windows) in steps, carried by the spec: gym.make's TimeLimit ends an
# episode at the same step as the task, which scores the estimate there. A different max_windows moves the
# TimeLimit only with max_episode_steps (cof_gym.envs.torque_interrogation.make_kwargs does both).
MAX_EPISODE_STEPS = 30


# Gymnasium's notice on making an id whose newer version exists: a v1 id is a deliberate choice here (published
# results), so the notice would be a stray second line on stderr (the CLI's and every training worker's)
OUT_OF_DATE_NOTICE = r".*is out of date\. You should consider upgrading"


def ignore_out_of_date_notice() -> None:
    """Silence Gymnasium's out-of-date notice for this process (each subprocess worker calls it too)."""
    import warnings

    warnings.filterwarnings("ignore", message=OUT_OF_DATE_NOTICE)


def _register() -> None:
    # disable_env_checker: gymnasium's PassiveEnvChecker leaves the env failing every step after a first
    # reset() that raised; gymnasium's check_env runs on the env in tests/test_action_types.py
    for env_id, (vehicle, version) in _IDS.items():
        if env_id in gym.registry:
            continue
        gym.register(
            id=env_id,
            entry_point="cof_gym.envs.torque_interrogation:TorqueInterrogationEnv",
            vector_entry_point="cof_gym.envs.vector:TorqueInterrogationVectorEnv",
            kwargs={"vehicle": vehicle, "task_version": version},
            max_episode_steps=MAX_EPISODE_STEPS,
            disable_env_checker=True,
        )


_register()
