"""The robust-model agent: registered as a non-oracle, reads no ground truth and no creepage (the v2
sensors' creepage carries a systematic offset as large as the peak creepage), reproduces a seeded
episode, and on a few fixed v2 episodes stops without a macro-slip within a loose accuracy bound."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from cof_gym.agents.registry import make_agent
from cof_gym.agents.robust_model import RobustModel
from cof_gym.agents.staircase import limits_of
from cof_gym.agents.base import agent_view
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.task.interface import OBSERVATION_NAMES, decode_action
from cof_gym.agents.runaway import RunawayEstimate

CREEPAGE = OBSERVATION_NAMES.index("creepage_measured")


def test_registered_without_ground_truth(env) -> None:
    agent = make_agent("robust-model", env)  # it reports the runaway estimate between its stops (rule 24)
    assert isinstance(agent, RunawayEstimate) and isinstance(agent.agent, RobustModel)
    assert not agent.oracle and agent.name == "robust-model"


def _wrong_truth(info: dict) -> dict:
    """The evaluator's info with every ground-truth number replaced by a wrong one."""
    out = copy.deepcopy(info)
    gt = out.get("ground_truth", {})
    for k, v in gt.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            gt[k] = 3.0 * v + 1.0
    return out


@pytest.mark.parametrize("garbage", [np.nan, 123.0, -7.5])
def test_reads_no_creepage_and_no_ground_truth(env, garbage: float) -> None:
    """An agent given the true observations and the evaluator's full info, and a twin given the
    creepage entry replaced by garbage and a wrong ground truth, command exactly the same actions."""
    limits = limits_of(env)
    seen, blind = RobustModel(limits), RobustModel(limits)
    obs, info = env.reset(seed=5)

    def garbled(o: np.ndarray) -> np.ndarray:
        o = o.copy()
        o[CREEPAGE] = garbage
        return o

    seen.reset(obs, agent_view(info, True))
    blind.reset(garbled(obs), _wrong_truth(info))
    for _ in range(40):
        a, b = seen.act(obs, agent_view(info, True)), blind.act(garbled(obs), _wrong_truth(info))
        np.testing.assert_array_equal(a, b)
        if decode_action(a, limits).stop:
            break
        obs, _, terminated, truncated, info = env.step(a)
        if terminated or truncated:
            break


def test_seeded_episode_reproduces(env) -> None:
    first = run_episode(env, make_agent("robust-model", env), 7, {}, 0)
    second = run_episode(env, make_agent("robust-model", env), 7, {}, 0)
    assert first == second


@pytest.mark.parametrize("seed", [100001, 100002, 100004])
def test_stops_without_macro_slip_near_the_cof(env, seed: int) -> None:
    """A few fixed v2 episodes (validation seeds, one of each law family among them): the agent
    stops by itself, without a macro-slip, and within 40 %: the knee is bracketed between two probe
    crests, and a rounded (Polach) curve's phase rises at 70-80 % of its peak, so an underestimate of
    up to ~30 % is what the design allows; an overshoot is capped by the bracket (25 % steps)."""
    record = run_episode(env, make_agent("robust-model", env), seed, {}, 0)
    assert not record.macro_slip
    assert record.scored
    assert record.relative_error < 0.4, record
