"""The reward's optimum is an accurate measurement: on fixed seeds of the default suite the mean return
ranks the saturation oracle above the practical staircase above a constant guess with an immediate stop,
each by a clear margin (paired over the same scenarios), and the paper's rule reaches the issue's
accuracy on v1."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.oracle import SaturationOracle
from cof_gym.agents.staircase import PaperStaircase, PracticalStaircase
from cof_gym.task import encode_action

SEEDS = range(30)


class ConstantGuess:
    """Reports 0.11 (the CoF range's geometric middle) and stops at once: measures nothing."""

    name, oracle = "guess", False

    def __init__(self, limits) -> None:
        self.limits = limits

    def reset(self, observation, info) -> None:
        pass

    def act(self, observation, info) -> np.ndarray:
        return encode_action(0.0, 100.0, 5.0, 0.11, True, self.limits)


def play(env, agent, seeds) -> tuple[np.ndarray, np.ndarray, int]:
    returns, errors, slips = [], [], 0
    for seed in seeds:
        obs, info = env.reset(seed=seed)
        agent.reset(obs, info)
        total = 0.0
        while True:
            obs, reward, terminated, truncated, info = env.step(agent.act(obs, info))
            total += reward
            if terminated or truncated:
                break
        returns.append(total)
        errors.append(info["relative_error"])
        slips += info["macro_slip"]
    return np.array(returns), np.array(errors), slips


@pytest.fixture(scope="module")
def results():
    env = gym.make(cof_gym.WAGON_V1_ENV_ID)
    limits = env.unwrapped.limits
    return {agent.name: play(env, agent, SEEDS)
            for agent in (SaturationOracle(limits), PracticalStaircase(limits), ConstantGuess(limits))}


def _clearly_above(a: np.ndarray, b: np.ndarray, margin: float) -> None:
    diff = a - b  # paired: the same scenarios and sensor-noise streams
    se = diff.std(ddof=1) / np.sqrt(diff.size)
    assert diff.mean() - 2.0 * se > 0.0 and diff.mean() > margin, (diff.mean(), se)


def test_mean_return_ranks_oracle_above_staircase_above_guessing(results) -> None:
    oracle, staircase, guess = results["oracle"][0], results["staircase"][0], results["guess"][0]
    _clearly_above(oracle, staircase, margin=0.1)
    _clearly_above(staircase, guess, margin=2.0)


def test_the_ranking_follows_accuracy(results) -> None:
    medians = {name: float(np.median(r[1])) for name, r in results.items()}
    assert medians["oracle"] < 0.02 and medians["staircase"] < 0.05 < 0.3 < medians["guess"]
    assert results["oracle"][2] == 0 and results["staircase"][2] == 0


def test_the_paper_rule_reaches_its_accuracy_on_v1() -> None:
    """`cof-gym evaluate --agents staircase-paper`'s acceptance on the default suite: median <= 2.5 %, no
    macro-slip (60 episodes, seed 0)."""
    env = gym.make(cof_gym.WAGON_V1_ENV_ID)
    _, errors, slips = play(env, PaperStaircase(env.unwrapped.limits), range(60))
    assert np.median(errors) <= 0.025 and slips == 0
