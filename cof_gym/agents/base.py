"""The one small interface every agent implements: observation (and info) in, action out."""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np


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
