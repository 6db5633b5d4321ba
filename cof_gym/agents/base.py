"""The one small interface every agent implements: observation (and info) in, action out."""

from __future__ import annotations

from collections import Counter
from typing import Any, Iterable, Mapping, Protocol, runtime_checkable

import numpy as np

from cof_gym.task.scenarios import ScenarioRanges, outside_draws


@runtime_checkable
class Agent(Protocol):
    """A measurement policy. ``info`` is the environment's info dict; only agents labelled as oracles
    may read ``info["ground_truth"]``."""

    name: str
    oracle: bool

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        """Start an episode from the reset observation."""

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        """The action (float32, shape (5,), in [-1, 1]) for the next window."""


def agent_view(info: dict[str, Any], oracle: bool) -> dict[str, Any]:
    """The info dict an agent receives: without ``ground_truth`` unless the agent is an oracle."""
    if oracle:
        return info
    return {k: v for k, v in info.items() if k != "ground_truth"}


def registered_ranges(env_id: str, env_kwargs: Mapping[str, Any] | None = None) -> ScenarioRanges:
    """The scenario draws of a registered env id made with ``env_kwargs`` (its ``ranges`` kwarg, else
    the default draws of its task version)."""
    import gymnasium as gym

    from cof_gym.envs.torque_interrogation import default_ranges

    kwargs = {**gym.spec(env_id).kwargs, **(env_kwargs or {})}
    return kwargs["ranges"] if kwargs.get("ranges") is not None else default_ranges(kwargs.get("task_version", 2))


def outside_training_note(name: str, ranges: ScenarioRanges, episodes: Iterable[Mapping[str, Any]]) -> str | None:
    """A line counting the episodes (their ``reset`` options) that lie outside the scenario draws
    ``ranges`` an agent was trained on, per field with an example; None when every episode lies inside."""
    episodes = list(episodes)
    counts: Counter[str] = Counter()
    example: dict[str, str] = {}
    outside = 0
    for options in episodes:
        why = outside_draws(options, ranges)
        outside += bool(why)
        counts.update(why.keys())
        for field_name, reason in why.items():
            example.setdefault(field_name, reason)
    if not outside:
        return None
    fields_text = "; ".join(f"{f} in {n} (e.g. {example[f]})" for f, n in counts.most_common())
    return (f"{name}: {outside} of {len(episodes)} episodes lie outside the scenario draws it was trained on, "
            f"out of its training distribution: {fields_text}")
