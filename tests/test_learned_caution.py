"""Rule 104's caution policy (experiments/learned_caution.py): at a zero action the steered climb is the shipped one
action for action, the action scales the caution as documented, and the training env is seeded and reads no truth."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator import cautioned, load_interrogator

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
from learned_caution import STATE_SIZE, CautionEnv, lagrangian, steered  # noqa: E402


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
    zero = _actions(env, steered(load_interrogator(env), lambda state: 0.0), seed)
    assert len(shipped) > 5 and len(zero) == len(shipped)
    assert all(np.array_equal(a, b) for a, b in zip(shipped, zero))


def test_a_bolder_or_more_cautious_action_steers_another_climb() -> None:
    env = gym.make(cof_gym.WAGON_ENV_ID)
    shipped = _actions(env, load_interrogator(env), 0)
    cautious = _actions(env, steered(load_interrogator(env), lambda state: 1.0), 0)
    assert any(not np.array_equal(a, b) for a, b in zip(shipped, cautious))


def test_the_action_scales_the_caution_within_a_factor_of_two() -> None:
    env = gym.make(cof_gym.WAGON_ENV_ID)
    base = load_interrogator(env).params
    assert cautioned(base, 0.0) is base
    assert cautioned(base, 1.0).caution == pytest.approx(2.0 * base.caution, rel=1e-12)
    assert cautioned(base, -1.0).caution == pytest.approx(0.5 * base.caution, rel=1e-12)
    assert cautioned(base, 7.0) == cautioned(base, 1.0)  # clipped to the action space
    assert cautioned(base, 1.0).creep_log_step == base.creep_log_step  # nothing else moves


def test_the_training_env_is_seeded_and_its_state_is_the_climbs() -> None:
    env = CautionEnv()
    first, _ = env.reset(seed=3)
    again, _ = env.reset(seed=3)
    assert first.shape == (STATE_SIZE,) and env.observation_space.contains(first)
    assert np.array_equal(first, again)
    state, reward, terminated, truncated, info = env.step(np.zeros(1, dtype=np.float32))
    assert np.all(np.isfinite(state)) and np.isfinite(reward) and info == {"cost": 0.0}  # no runaway at the start
    assert np.array_equal(state, env.agent.climb_state())
    env.close()


def _records(path: Path, errors: list[float], slips: list[bool] | None = None) -> str:
    import json

    slips = slips or [False] * len(errors)
    path.write_text(json.dumps([{"setting": path.stem, "grid": "family", "config": {}, "episode": k, "error": e,
                                 "macro_slip": s, "episode_return": -10 * e}
                                for k, (e, s) in enumerate(zip(errors, slips))]))
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


def _constant_policy(action: float):
    from cof_gym.agents.interrogator import CautionPolicy

    zeros = np.zeros((4, STATE_SIZE), dtype=np.float32)
    return CautionPolicy(((zeros, np.zeros(4, dtype=np.float32)),),
                         (np.zeros((1, 4), dtype=np.float32), np.array([action], dtype=np.float32)))


def test_each_decision_reads_the_climb_as_it_stood_before_the_window() -> None:
    """The policy sees the decisions before the window it steers: none at the first decision (zeros, 29 of 30 windows
    left), the first decision's at the second; a policy directory's network (a constant here) steers as a callable."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    seen = []
    agent = steered(load_interrogator(env), lambda state: seen.append(state.copy()) or -0.5)
    actions = _actions(env, agent, 0)
    assert len(seen) == len(agent.decisions) and np.all(seen[0][:6] == 0.0)
    assert seen[0][7] == pytest.approx(29 / 30) and seen[1][0] == np.float32(agent.decisions[0].filter_headroom)
    own = load_interrogator(env)
    own.caution_policy = _constant_policy(-0.5)
    assert [np.array_equal(a, b) for a, b in zip(actions, _actions(env, own, 0))] == [True] * len(actions)
    assert any(not np.array_equal(a, b) for a, b in zip(actions, _actions(env, load_interrogator(env), 0)))


def test_the_caution_policy_is_a_clipped_tanh_network_saved_and_loaded_alike(tmp_path: Path) -> None:
    from cof_gym.agents.interrogator import CautionPolicy

    rng = np.random.default_rng(0)
    hidden = ((rng.normal(size=(3, STATE_SIZE)).astype(np.float32), rng.normal(size=3).astype(np.float32)),)
    policy = CautionPolicy(hidden, (rng.normal(size=(1, 3)).astype(np.float32), np.array([0.1], dtype=np.float32)))
    state = rng.normal(size=STATE_SIZE).astype(np.float32)
    expected = float((policy.output[0] @ np.tanh(hidden[0][0] @ state + hidden[0][1]) + policy.output[1])[0])
    assert policy(state) == pytest.approx(float(np.clip(expected, -1.0, 1.0)), abs=1e-6)  # float32 sums of 9 terms
    assert _constant_policy(3.0)(state) == 1.0 and _constant_policy(-3.0)(state) == -1.0
    policy.save(tmp_path / "p.npz")
    assert CautionPolicy.load(tmp_path / "p.npz")(state) == policy(state)


def test_an_exported_model_is_read_by_the_agent_and_acts_as_it_was_trained(tmp_path: Path, monkeypatch) -> None:
    """``learned_caution.py --export MODEL --into DIR``: the policy directory's agent carries the model's
    deterministic policy (float32 arithmetic in another summation order: within 1e-6 of stable-baselines3's)."""
    import shutil

    from stable_baselines3 import PPO

    import learned_caution
    from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR, interrogator_for

    env = CautionEnv()
    model = PPO("MlpPolicy", env, n_steps=32, batch_size=32, seed=0, device="cpu",
                policy_kwargs={"net_arch": [16, 16], "log_std_init": -1.0})
    (tmp_path / "seed_0").mkdir()
    model.save(tmp_path / "seed_0" / "model.zip")
    policy_dir = tmp_path / "policy"
    shutil.copytree(SHIPPED_INTERROGATOR, policy_dir)
    monkeypatch.setattr(sys, "argv", ["learned_caution.py", "--export", str(tmp_path / "seed_0" / "model.zip"),
                                      "--into", str(policy_dir)])
    learned_caution.main()
    agent = interrogator_for(gym.make(cof_gym.WAGON_ENV_ID), policy_dir)
    assert agent.caution_policy is not None
    states = np.random.default_rng(1).normal(size=(50, STATE_SIZE)).astype(np.float32)
    ours = [agent.caution_policy(s) for s in states]
    theirs = [float(model.predict(s, deterministic=True)[0][0]) for s in states]
    assert np.allclose(ours, theirs, rtol=0, atol=1e-6)
    env.close()


class _RunawayWhenPositive(gym.Env):
    """One-window episodes of reward 1 whose wheel runs away (cost 1) when the action is positive."""

    observation_space = gym.spaces.Box(-1.0, 1.0, (1,), np.float32)
    action_space = gym.spaces.Box(-1.0, 1.0, (1,), np.float32)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return np.zeros(1, np.float32), {}

    def step(self, action):
        return np.zeros(1, np.float32), 1.0, True, False, {"cost": float(action[0] > 0)}


def test_ppo_lagrangian_prices_runaways_and_moves_its_multiplier_by_dual_ascent() -> None:
    from stable_baselines3.common.vec_env import DummyVecEnv

    envs, callback = lagrangian(DummyVecEnv([_RunawayWhenPositive]), budget=0.25, step=10.0)
    envs.reset()

    def rollout(actions: list[float]) -> list[float]:
        rewards = [float(envs.step(np.array([[a]], np.float32))[1][0]) for a in actions]
        callback.on_rollout_end()
        return rewards

    assert rollout([1, -1, 1, -1]) == [1.0, 1.0, 1.0, 1.0]  # the multiplier starts at 0
    assert envs.multiplier == pytest.approx(10.0 * (0.5 - 0.25))  # 2 runaways in 4 episodes against 0.25
    assert rollout([1, -1, -1, -1]) == [1.0 - 2.5, 1.0, 1.0, 1.0]  # a runaway now costs the multiplier
    assert envs.multiplier == pytest.approx(2.5 + 10.0 * (0.25 - 0.25))
    rollout([-1, -1, -1, -1])
    assert envs.multiplier == 0.0  # 2.5 - 2.5
    rollout([-1, -1, -1, -1])
    assert envs.multiplier == 0.0  # never below zero
    assert [h["runaway_rate"] for h in callback.history] == [0.5, 0.25, 0.0, 0.0]


def test_models_joined_by_plus_act_by_their_mean_action(tmp_path: Path) -> None:
    """``--caution-policy A+B``: the ensemble's action is the mean of its members' deterministic actions."""
    from stable_baselines3 import PPO

    from learned_caution import ppo_policy

    env = CautionEnv()
    paths = []
    for seed in (0, 1):
        model = PPO("MlpPolicy", env, n_steps=32, batch_size=32, seed=seed, device="cpu",
                    policy_kwargs={"net_arch": [16, 16], "log_std_init": -1.0})
        paths.append(tmp_path / f"seed_{seed}.zip")
        model.save(paths[-1])
    members = [ppo_policy(path) for path in paths]
    ensemble = ppo_policy(Path(f"{paths[0]}+{paths[1]}"))
    states = np.random.default_rng(2).normal(size=(20, STATE_SIZE)).astype(np.float32)
    assert any(members[0](s) != members[1](s) for s in states)  # two different policies
    for s in states:
        assert ensemble(s) == pytest.approx(0.5 * (members[0](s) + members[1](s)), rel=0, abs=1e-7)
    env.close()


def test_paired_without_a_model_plays_the_shipped_climb_and_counts_its_runaways(monkeypatch, capsys) -> None:
    import learned_caution

    monkeypatch.setattr(sys, "argv", ["learned_caution.py", "--paired", "--episodes", "1"])
    learned_caution.main()
    line = capsys.readouterr().out
    assert line.startswith("2 training-draw episodes: the shipped climb's mean return -")  # one per configuration
    runaways = re.fullmatch(r".*, (\d+) runaways", line.rstrip())
    assert runaways is not None and int(runaways.group(1)) <= 2
