"""Helpers the learned interrogator's test modules share: networks of known outputs, an episode played by an agent."""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import cof_gym
from cof_gym.agents.interrogator import FEATURE_NAMES, SHIPPED_INTERROGATOR, TARGET_NAMES, FilterNetwork, Reading
from cof_gym.task.interface import OBSERVATION_NAMES

SHIPPED = (SHIPPED_INTERROGATOR / "manifest.json").is_file()
CREEPAGE = OBSERVATION_NAMES.index("creepage_measured")


def random_network(seed: int = 0, width: int = 8, names: tuple[str, ...] = FEATURE_NAMES) -> FilterNetwork:
    """A member of random weights that reads the features ``names`` (:func:`feature_names` of its blocks)."""
    rng = np.random.default_rng(seed)
    n = len(names)
    shapes = [(n, width), (width, 2 * len(TARGET_NAMES))]
    return FilterNetwork(np.zeros(n), np.ones(n), tuple(rng.normal(0, 0.3, s) for s in shapes),
                         tuple(rng.normal(0, 0.1, s[1]) for s in shapes), names)


def play(agent, seed: int, env_kwargs: dict | None = None, perturb_creepage: float = 0.0):
    env = gym.make(cof_gym.WAGON_ENV_ID, **(env_kwargs or {}))
    obs, info = env.reset(seed=seed)
    agent.reset(obs, {})
    actions = []
    while True:
        seen = obs.copy()
        seen[CREEPAGE] += perturb_creepage
        action = agent.act(seen, {})
        actions.append(action)
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            return np.asarray(actions), info


def window_reading(phase_deg: float, se_deg: float) -> Reading:
    """A driven window with this lag and standard error (the rest does not enter the knee test)."""
    return Reading(phase_deg=phase_deg, se_deg=se_deg, compliance=1e-4, coa=0.05, creepage=0.0, dc_nm=4000.0,
                   amplitude_nm=1600.0, frequency_hz=5.0, speed_m_s=10.0, normal_load=1.0)


def constant_network(headroom: float, correction: float, log_variance: float = -6.0) -> FilterNetwork:
    """A member whose prediction is the same whatever it reads (its last layer is a bias alone)."""
    n, width = len(FEATURE_NAMES), 4
    weights = (np.zeros((n, width)), np.zeros((width, 2 * len(TARGET_NAMES))))
    return FilterNetwork(np.zeros(n), np.ones(n), weights,
                         (np.zeros(width), np.array([headroom, correction, log_variance, log_variance])))


def climbs_reading(episode: list[int], **columns: list[float]):
    """A climbs file's windows (:class:`~cof_gym.agents.interrogator.training.Dataset`) with only these reading
    fields set (the rest 0) and each window's episode."""
    from cof_gym.agents.interrogator.training import READING_FIELDS, Dataset

    rows = np.zeros((len(episode), len(READING_FIELDS)))
    for name, values in columns.items():
        rows[:, READING_FIELDS.index(name)] = values
    return Dataset(rows, np.zeros(len(episode), bool), np.zeros((len(episode), 2)), np.array(episode))
