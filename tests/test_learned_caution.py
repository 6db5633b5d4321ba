"""Rule 104's caution policy (experiments/learned_caution.py): at a zero action the steered climb is the shipped one
action for action, the action scales the caution as documented, and the training env is seeded and reads no truth."""

from __future__ import annotations

import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator import load_interrogator

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
from learned_caution import STATE_SIZE, CautionEnv, CautionSteered, caution_at, climb_state  # noqa: E402


class Recorder:
    """An agent's actions over an episode."""

    def __init__(self, agent) -> None:
        self.agent, self.actions = agent, []

    def reset(self, observation, info) -> None:
        self.agent.reset(observation, info)

    def act(self, observation, info):
        self.actions.append(np.array(self.agent.act(observation, info)))
        return self.actions[-1]


def _actions(env, agent, seed: int) -> list[np.ndarray]:
    from cof_gym.commands.evaluate_episodes import run_episode

    recorder = Recorder(agent)
    recorder.name = "recorder"
    run_episode(env, recorder, seed, {}, 0)
    return recorder.actions


@pytest.mark.parametrize("seed", [0, 2])
def test_at_a_zero_action_the_steered_climb_is_the_shipped_one(seed: int) -> None:
    env = gym.make(cof_gym.WAGON_ENV_ID)
    shipped = _actions(env, load_interrogator(env), seed)
    steered = _actions(env, CautionSteered(load_interrogator(env), lambda state: 0.0), seed)
    assert len(shipped) > 5 and len(steered) == len(shipped)
    assert all(np.array_equal(a, b) for a, b in zip(shipped, steered))


def test_a_bolder_or_more_cautious_action_steers_another_climb() -> None:
    env = gym.make(cof_gym.WAGON_ENV_ID)
    shipped = _actions(env, load_interrogator(env), 0)
    cautious = _actions(env, CautionSteered(load_interrogator(env), lambda state: 1.0), 0)
    assert any(not np.array_equal(a, b) for a, b in zip(shipped, cautious))


def test_the_action_scales_the_caution_within_a_factor_of_two() -> None:
    env = gym.make(cof_gym.WAGON_ENV_ID)
    base = load_interrogator(env).params
    assert caution_at(base, 0.0) is base
    assert caution_at(base, 1.0).caution == pytest.approx(2.0 * base.caution, rel=1e-12)
    assert caution_at(base, -1.0).caution == pytest.approx(0.5 * base.caution, rel=1e-12)
    assert caution_at(base, 7.0) == caution_at(base, 1.0)  # clipped to the action space
    assert caution_at(base, 1.0).creep_log_step == base.creep_log_step  # nothing else moves


def test_the_training_env_is_seeded_and_its_state_is_the_climbs() -> None:
    env = CautionEnv()
    first, _ = env.reset(seed=3)
    again, _ = env.reset(seed=3)
    assert first.shape == (STATE_SIZE,) and env.observation_space.contains(first)
    assert np.array_equal(first, again)
    state, reward, terminated, truncated, info = env.step(np.zeros(1, dtype=np.float32))
    assert np.all(np.isfinite(state)) and np.isfinite(reward) and info == {}
    assert np.array_equal(state, climb_state(env.agent))
    env.close()


def _records(path: Path, errors: list[float], slips: list[bool] | None = None) -> str:
    import json

    slips = slips or [False] * len(errors)
    path.write_text(json.dumps([{"grid": "family", "config": {}, "episode": k, "error": e, "macro_slip": s,
                                 "episode_return": -10 * e} for k, (e, s) in enumerate(zip(errors, slips))]))
    return str(path)


def test_the_seed_report_pools_seeds_by_climb_and_refuses_other_episodes(tmp_path: Path) -> None:
    from learned_caution import seed_report

    base = _records(tmp_path / "base.json", [0.01, 0.02, 0.03, 0.04])
    seeds = [_records(tmp_path / f"s{k}.json", [0.01 * k, 0.02, 0.03, 0.04], [k == 1, False, False, False])
             for k in (1, 2)]
    text = seed_report(seeds, base)
    assert "| 1 of 4 |" in text and "Over 2 seeds x 4 climbs" in text
    # the middle half of the 8 errors (0.01, 0.02, 0.02, 0.02, 0.03, 0.03, 0.04, 0.04): 0.02 0.02 0.03 0.03
    assert "IQM of the relative error 2.5 %" in text
    other = _records(tmp_path / "other.json", [0.01, 0.02, 0.03])
    with pytest.raises(ValueError, match="same episodes"):
        seed_report([other], base)
