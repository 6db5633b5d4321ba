"""Evaluation suites: which environment, and which seeded scenarios every agent meets."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

PAPER_COFS = (0.1, 0.2, 0.3, 0.4, 0.5)


@dataclass(frozen=True)
class Suite:
    """An env id with kwargs and a list of episodes: (reset seed, reset options). The same list is
    played by every agent, so every agent meets the same scenarios (CoF, condition, speed, load,
    noise, motor lag) and the same sensor-noise streams."""

    name: str
    env_id: str
    env_kwargs: dict[str, Any]
    episodes: list[tuple[int, dict[str, Any]]] = field(default_factory=list)


def default_suite(n_episodes: int, seed: int) -> Suite:
    """The wagon env's default scenario distribution (CoF 0.02-0.6, all conditions, 5-40 m/s, empty
    and laden, noise and motor lag drawn), ``n_episodes`` seeded draws."""
    return Suite("default", "CofGym/TorqueInterrogation-v0", {}, [(seed + i, {}) for i in range(n_episodes)])


def paper_suite(n_episodes: int, seed: int) -> Suite:
    """The paper's setting: laden wagon with the opposite torque on the bogie, dry, 10 m/s, no noise
    or lag, CoF 0.1...0.5 (cycled over ``n_episodes``)."""
    fixed = {"condition": "dry", "speed_m_s": 10.0, "load_case": "laden", "noise_level": 0.0, "motor_lag_s": 0.0}
    episodes = [(seed + i, {**fixed, "cof": PAPER_COFS[i % len(PAPER_COFS)]}) for i in range(n_episodes)]
    return Suite("paper", "CofGym/TorqueInterrogation-v0", {"counter_torque": True}, episodes)


def file_suite(path: Path, n_episodes: int, seed: int) -> Suite:
    """A JSON file: ``{"env_id": ..., "env_kwargs": {...}, "episodes": [{"seed": 1, "options": {...}}, ...]}``;
    without "episodes", ``n_episodes`` draws with ``"options"`` (fixed fields) applied to each."""
    spec = json.loads(Path(path).read_text())
    env_id = spec.get("env_id", "CofGym/TorqueInterrogation-v0")
    if "episodes" in spec:
        episodes = [(int(e.get("seed", seed + i)), dict(e.get("options", {}))) for i, e in enumerate(spec["episodes"])]
    else:
        episodes = [(seed + i, dict(spec.get("options", {}))) for i in range(n_episodes)]
    return Suite(Path(path).stem, env_id, dict(spec.get("env_kwargs", {})), episodes)


def make_suite(name: str, n_episodes: int, seed: int) -> Suite:
    if name == "default":
        return default_suite(n_episodes, seed)
    if name == "paper":
        return paper_suite(n_episodes, seed)
    if Path(name).is_file():
        return file_suite(Path(name), n_episodes, seed)
    raise ValueError(f"suite must be 'default', 'paper' or a JSON file path, got {name!r}")
