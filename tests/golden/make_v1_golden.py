"""Writes ``v1_summary.json``: a fixed-seed summary of the v1 environments that
``tests/test_v1_golden.py`` compares every later version of the code with (published v1 numbers must
never change). Run from the commit whose numbers are published::

    python tests/golden/make_v1_golden.py tests/golden/v1_summary.json
"""

from __future__ import annotations

import json
import sys

import gymnasium as gym
import numpy as np

import cof_gym  # noqa: F401  (registers the ids)

IDS = ("CofGym/TorqueInterrogation-v1", "CofGym/HalfWheelset-v1")
SEEDS = (0, 1, 2)
# a fixed climb in the absolute action type: DC torque, amplitude, frequency, estimate, stop
ACTIONS = [(-1.0 + 0.06 * k, -0.8 + 0.2 * (k % 2), -0.6, -0.5 + 0.1 * k, -1.0) for k in range(5)]


def summary() -> dict:
    out = {}
    for env_id in IDS:
        env = gym.make(env_id, max_windows=len(ACTIONS))
        for seed in SEEDS:
            obs, info = env.reset(seed=seed)
            rows = {"reset_obs": obs.tolist(), "cof": info["ground_truth"]["cof"],
                    "saturation_torque_nm": info["ground_truth"]["saturation_torque_nm"],
                    "obs": [], "reward": []}
            for action in ACTIONS:
                obs, reward, terminated, truncated, info = env.step(np.array(action, dtype=np.float32))
                rows["obs"].append(obs.tolist())
                rows["reward"].append(float(reward))
                if terminated or truncated:
                    break
            out[f"{env_id}/seed{seed}"] = rows
        env.close()
    return out


if __name__ == "__main__":
    with open(sys.argv[1], "w") as f:
        json.dump(summary(), f, indent=1)
