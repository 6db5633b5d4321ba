"""Write the two scenario grids that the README's agent results use (run from the repository root):

- ``suites/validation_grid.json``: model selection (e.g. which PPO seed or checkpoint ships). Never
  used for the reported numbers.
- ``suites/heldout_grid.json``: reporting only. Its CoF values, speeds and noise draws differ from the
  validation grid's and from the default suite's seeds; nothing is tuned on it.

Each grid crosses every condition, CoF values at off-round fractions of that condition's range, speeds
across 5-40 m/s and both load cases, with full sensor noise and a motor lag; the ranges come from
``cof_gym.task.scenarios`` (one source of truth)."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import cof_gym
from cof_gym.task.scenarios import COF_BY_CONDITION, DEFAULT_CONDITIONS

GRIDS = {
    # name: (CoF fractions of the condition's range, speeds m/s, first seed, description)
    "validation_grid": ((0.07, 0.31, 0.56, 0.81, 0.97), (6.5, 17.0, 29.0, 38.5), 50_000,
                        "model selection only (never reported)"),
    "heldout_grid": ((0.13, 0.42, 0.68, 0.91), (8.0, 21.5, 34.0), 90_000,
                     "reporting only (nothing is tuned on it)"),
}


def grid(fractions, speeds, first_seed: int, description: str) -> dict:
    episodes = []
    combos = itertools.product(DEFAULT_CONDITIONS, fractions, speeds, ("empty", "laden"))
    for k, (condition, fraction, speed, load_case) in enumerate(combos):
        lo, hi = COF_BY_CONDITION[condition]
        options = {"condition": condition, "cof": round(lo + fraction * (hi - lo), 4), "speed_m_s": speed,
                   "load_case": load_case, "noise_level": 1.0, "motor_lag_s": 0.02}
        episodes.append({"seed": first_seed + k, "options": options})
    return {"env_id": cof_gym.WAGON_ENV_ID, "env_kwargs": {}, "description": description, "episodes": episodes}


def main() -> None:
    out = Path(__file__).resolve().parent / "suites"
    for name, spec in GRIDS.items():
        path = out / f"{name}.json"
        path.write_text(json.dumps(grid(*spec), indent=1) + "\n")
        print(f"{path}: {len(grid(*spec)['episodes'])} episodes")


if __name__ == "__main__":
    main()
