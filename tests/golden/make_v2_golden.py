"""Writes ``v2_summary.json``: fixed-seed trajectories of the v2 environments that ``tests/test_v2_golden.py``
compares every later version of the code with (published v2 numbers must never change). Run from the commit
whose numbers are published::

    python tests/golden/make_v2_golden.py tests/golden/v2_summary.json

(written in session 42, at a commit whose ``cof-gym evaluate`` default suite, v2, is byte-identical in
``summary.json``, ``summary.md`` and ``episodes.csv`` to the published one).

Each case is an env (id and constructor arguments), a seed, reset options and a fixed climb of raw actions,
chosen to pass through what the v2 task adds to v1: both creep-law families the env draws and a tabulated
curve of the user's, the systematic sensor errors (drawn and given), the counter torque, the half wheelset,
the two-tone excitation, the relative actions with the history observation, and a climb run past the peak
into a macro-slip. Per window it keeps the observation, the reward, whether the episode ended, the sensor
readings (``info["measurement"]``) and the truth's numbers (``info["ground_truth"]``).
"""

from __future__ import annotations

import json
import sys
from typing import Any

import gymnasium as gym
import numpy as np

import cof_gym  # noqa: F401  (registers the ids)

WAGON, HALF = "CofGym/TorqueInterrogation-v2", "CofGym/HalfWheelset-v2"
# a fixed climb of raw actions: the DC torque from 0.5 % to 6 % of the drive's maximum in the absolute action
# type (``2 f - 1``), amplitude, frequency, estimate, stop (a two-tone env appends tone 2's frequency and share)
DC_FRACTIONS = (0.005, 0.01, 0.02, 0.03, 0.045, 0.06)
CLIMB = [(2 * f - 1, -0.2, -0.6, -0.5 + 0.1 * k, -1.0) for k, f in enumerate(DC_FRACTIONS)]
TONE2 = (0.3, 0.0)
TABLE = {"creepage": [0, 0.002, 0.005, 0.01, 0.02], "adhesion_ratio": [0, 0.5, 0.85, 1.0, 0.9]}
STOP_AT = 3  # the window whose action asks to stop, in the cases that stop
CASES = {  # name -> (env id, constructor arguments, seed, reset options, stop at STOP_AT)
    "wagon/she/seed0": (WAGON, {}, 0, None, False),
    "wagon/polach/seed3": (WAGON, {}, 3, None, False),
    "wagon/counter_torque/seed4": (WAGON, {"counter_torque": True}, 4, None, False),
    "wagon/table/seed1": (WAGON, {}, 1, {"creep_law": {"table": TABLE}, "cof": 0.2, "speed_sensor_error": 0.01},
                          False),
    "wagon/two_tone/seed5": (WAGON, {"excitation": "multitone", "tones": 2}, 5, None, False),
    "wagon/relative_history/seed6": (WAGON, {"action_type": "relative", "observation_type": "history"}, 6, None,
                                     False),
    "wagon/stop/seed7": (WAGON, {}, 7, None, True),
    "half_wheelset/she/seed0": (HALF, {}, 0, None, False),
    "half_wheelset/polach/seed3": (HALF, {}, 3, None, True),
}


def numbers(mapping: dict[str, Any]) -> dict[str, float]:
    """The real numbers of ``mapping`` (booleans and nested dicts left out), as floats."""
    return {k: float(v) for k, v in sorted(mapping.items())
            if isinstance(v, (int, float, np.floating, np.integer)) and not isinstance(v, bool)}


def trajectory(env_id: str, env_kwargs: dict, seed: int, options: dict | None, stops: bool) -> dict:
    env = gym.make(env_id, max_windows=len(CLIMB), **env_kwargs)
    obs, info = env.reset(seed=seed, options=options)
    rows: dict[str, Any] = {"reset_obs": obs.tolist(), "ground_truth": numbers(info["ground_truth"]),
                            "obs": [], "reward": [], "ended": [], "measurement": [], "step_truth": []}
    extra = TONE2 * ((env.action_space.shape[0] - len(CLIMB[0])) // len(TONE2))
    for k, action in enumerate(CLIMB):
        if stops and k == STOP_AT:
            action = action[:-1] + (1.0,)
        obs, reward, terminated, truncated, info = env.step(np.array(action + extra, dtype=np.float32))
        rows["obs"].append(obs.tolist())
        rows["reward"].append(float(reward))
        rows["ended"].append([bool(terminated), bool(truncated), bool(info["macro_slip"])])
        rows["measurement"].append(numbers(info["measurement"]))
        rows["step_truth"].append(numbers(info["ground_truth"]))
        if terminated or truncated:
            break
    env.close()
    return rows


def summary() -> dict:
    return {name: trajectory(*case) for name, case in CASES.items()}


if __name__ == "__main__":
    with open(sys.argv[1], "w") as f:
        json.dump(summary(), f, indent=1)
