"""The env's action types ("absolute", "relative", "identified") and observation types ("window", "history",
"identification")."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from dataclasses import astuple
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import cof_gym  # noqa: F401  (registers the ids)
from cof_gym.agents.adapters import AgentSideInterface, wrap
from cof_gym.envs.torque_interrogation import make_task
from cof_gym.task.actions import AbsoluteActions, ActionContext, RelativeActions
from cof_gym.task.ground_truth import max_saturation_torque_nm
from cof_gym.task.interface import (
    HISTORY_OBSERVATION_NAMES, HISTORY_WINDOWS, OBSERVATION_NAMES, SENSOR_FIELDS, decode_action, decode_history,
)
from cof_gym.task.scenarios import COF_ENVELOPE
from test_vector_env import first_difference, make_pair, same  # tests/ is on sys.path (pytest rootdir)

ENV_ID = "CofGym/TorqueInterrogation-v1"
ROOT = Path(__file__).resolve().parents[1]
OPTIONS = [("absolute", "window"), ("relative", "window"), ("absolute", "history"), ("relative", "history"),
           ("identified", "identification")]
OBSERVATION_SIZES = {"window": 14, "history": 29, "identification": 38}
REL = RelativeActions()


def test_relative_decode_encode_round_trip() -> None:
    limits = make_task().limits
    rng = np.random.default_rng(0)
    for _ in range(200):
        ctx = ActionContext(float(rng.uniform(0.005, 0.5)) * limits.max_dc_torque_nm, float(rng.uniform(0.02, 0.6)))
        a = rng.uniform(-1, 1, 5)
        a[4] = rng.choice([-1.0, 1.0])
        d = REL.decode(ctx, a, limits)
        back = REL.encode(ctx, d.drive.dc_torque_nm, d.drive.amplitude_nm, d.drive.frequency_hz, d.cof_estimate,
                          d.stop, limits)
        assert back.dtype == np.float32 and back.shape == (5,)
        d2 = REL.decode(ctx, back, limits)
        assert d2.stop == d.stop
        for x, y in ((d.drive.dc_torque_nm, d2.drive.dc_torque_nm), (d.drive.amplitude_nm, d2.drive.amplitude_nm),
                     (d.drive.frequency_hz, d2.drive.frequency_hz), (d.cof_estimate, d2.cof_estimate)):
            assert y == pytest.approx(x, rel=1e-5)
        unclipped = (d.drive.dc_torque_nm < limits.max_dc_torque_nm
                     and limits.min_amplitude_nm < d.drive.amplitude_nm < limits.max_amplitude_nm
                     and limits.min_cof_estimate < d.cof_estimate < limits.max_cof_estimate)
        if unclipped:
            np.testing.assert_allclose(back[:4], a[:4], atol=1e-5)
    # the absolute type is the v1 mapping
    a = rng.uniform(-1, 1, 5)
    assert AbsoluteActions().decode(ActionContext(123.0, 0.3), a, limits) == decode_action(a, limits)


def test_relative_steps_are_scale_free() -> None:
    """The same action is the same relative change of DC torque, amplitude ratio and estimate at low and
    high friction."""
    limits = make_task().limits
    a = np.array([0.6, 0.2, 0.0, -0.4, -1.0])
    low, high = ActionContext(0.01 * limits.max_dc_torque_nm, 0.03), ActionContext(0.3 * limits.max_dc_torque_nm, 0.45)
    dl, dh = REL.decode(low, a, limits), REL.decode(high, a, limits)
    assert dl.drive.dc_torque_nm / low.dc_torque_nm == pytest.approx(dh.drive.dc_torque_nm / high.dc_torque_nm)
    assert dl.drive.dc_torque_nm / low.dc_torque_nm == pytest.approx(math.exp(0.3))
    assert dl.drive.amplitude_nm / dl.drive.dc_torque_nm == pytest.approx(dh.drive.amplitude_nm / dh.drive.dc_torque_nm)
    assert dl.cof_estimate / low.best_coa == pytest.approx(dh.cof_estimate / high.best_coa)
    assert dl.cof_estimate / low.best_coa == pytest.approx(math.exp(-0.2))
    # one window moves the torque by at most exp(0.5) either way; stop needs a4 > 0.5
    for a0 in (-1.0, 1.0):
        d = REL.decode(high, np.array([a0, 0, 0, 0, 0.5]), limits)
        assert d.drive.dc_torque_nm / high.dc_torque_nm == pytest.approx(math.exp(0.5 * a0)) and not d.stop
    assert REL.decode(high, np.array([0, 0, 0, 0, 0.51]), limits).stop


@pytest.mark.parametrize("kwargs", [{}, {"counter_torque": True}, {"vehicle": "half_wheelset"}])
def test_first_relative_step_from_zero_stays_below_the_smallest_saturation_torque(kwargs) -> None:
    task = make_task(action_type="relative", **kwargs)
    limits = task.limits
    smallest = min(max_saturation_torque_nm(task.model(lc), task.balanced, COF_ENVELOPE[0])
                   for lc in task.ranges.load_cases)
    d = task.actions.decode(ActionContext(0.0, 0.0), np.ones(5), limits)  # the largest step, largest amplitude
    assert d.drive.dc_torque_nm + d.drive.amplitude_nm < 0.75 * smallest
    # and on the env: the first full step at the lowest CoF in range does not slip
    env = gym.make(ENV_ID, action_type="relative", cof=COF_ENVELOPE[0], condition="low_adhesion",
                   load_case=task.ranges.load_cases[0], **kwargs)
    env.reset(seed=0)
    _, _, terminated, _, info = env.step(np.array([1.0, 1.0, 0.0, 0.0, -1.0], np.float32))
    assert not terminated and not info["macro_slip"] and info["ground_truth"]["peak_torque_fraction"] < 0.75


def test_history_observation_is_fixed_size_and_sensor_only() -> None:
    """The "history" observation has a fixed shape from the reset on and is a function of the window
    observations alone: an agent that sees only those (AgentSideInterface) rebuilds it bit for bit."""
    assert len(HISTORY_OBSERVATION_NAMES) == len(OBSERVATION_NAMES) + 3 + 4 * HISTORY_WINDOWS == 29
    truth_keys = set(gym.make(ENV_ID).reset(seed=0)[1]["ground_truth"])
    assert not truth_keys & set(HISTORY_OBSERVATION_NAMES) and "coa_measured" in SENSOR_FIELDS
    hist = gym.make(ENV_ID, observation_type="history", action_type="relative")
    win = gym.make(ENV_ID, observation_type="window", action_type="relative")
    rng = np.random.default_rng(1)
    for seed in (0, 1):
        oh, _ = hist.reset(seed=seed)
        ow, _ = win.reset(seed=seed)
        agent = AgentSideInterface(hist.unwrapped.limits, "relative", "history")
        assert oh.shape == (29,) and hist.observation_space.contains(oh)
        assert same(agent.reset(ow), oh)
        for t in range(8):
            a = rng.uniform(-1, 1, 5).astype(np.float32)
            a[4] = -1.0
            oh, _, th, trh, _ = hist.step(a)
            ow, _, tw, trw, _ = win.step(a)
            agent.windows += 1
            assert oh.shape == (29,) and same(oh[:14], ow) and (th, trh) == (tw, trw)
            assert same(agent.observe(ow), oh), t
            if th or trh:
                break
        best = max(w[OBSERVATION_NAMES.index("coa_measured")] for w in agent.memory.recent)
        assert decode_history(oh, hist.unwrapped.task.scales(hist.unwrapped.episode.built)).best_coa >= best


def test_agent_side_relative_actions_match_the_env() -> None:
    """The adapter's alias: a policy acting relative through AgentSideInterface on a default env drives
    the same commands as the env's own relative action type (up to float32 rounding)."""
    rel = gym.make(ENV_ID, action_type="relative", cof=0.3, condition="dry")
    absolute = gym.make(ENV_ID, cof=0.3, condition="dry")
    wrapped = wrap(gym.make(ENV_ID, cof=0.3, condition="dry"), "incremental")
    assert wrap(rel, "incremental") is rel
    o1, _ = rel.reset(seed=4)
    o2, _ = absolute.reset(seed=4)
    wrapped.reset(seed=4)
    agent = AgentSideInterface(absolute.unwrapped.limits)
    agent.reset(o2)
    for t in range(6):
        a = np.array([0.8, 0.3, -0.2, 0.1 * t, -1.0], np.float32)
        o1, *_ = rel.step(a)
        o2, *_ = absolute.step(agent.to_env(a))
        agent.observe(o2)
        wrapped.step(a)
        d1, d2, d3 = rel.unwrapped.episode.drive, absolute.unwrapped.episode.drive, wrapped.unwrapped.episode.drive
        for x, y, z in zip(astuple(d1), astuple(d2), astuple(d3)):
            assert y == pytest.approx(x, rel=1e-4) and z == pytest.approx(x, rel=1e-4)
        assert absolute.unwrapped.episode.estimate == pytest.approx(rel.unwrapped.episode.estimate, rel=1e-4)


@pytest.mark.parametrize("action_type,observation_type", OPTIONS[1:])
def test_vector_env_bit_identical_with_the_options(action_type, observation_type) -> None:
    batched, sync = make_pair(2, max_windows=5, action_type=action_type, observation_type=observation_type)
    try:
        assert batched.single_observation_space == sync.single_observation_space
        assert same(batched.reset(seed=7), sync.reset(seed=7))
        batched.action_space.seed(7)
        for t in range(8):
            actions = batched.action_space.sample()
            actions[:, 4] = -1.0 if t % 3 else 1.0
            a, b = batched.step(actions), sync.step(actions)
            assert same(a, b), f"step {t}: {first_difference(a, b)}"
    finally:
        batched.close()
        sync.close()


@pytest.mark.parametrize("action_type,observation_type", OPTIONS)
def test_check_env_with_each_option(action_type, observation_type) -> None:
    import warnings

    from gymnasium.utils.env_checker import check_env
    from stable_baselines3.common.env_checker import check_env as sb3_check_env

    env = gym.make(ENV_ID, action_type=action_type, observation_type=observation_type, max_windows=3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped, skip_render_check=True)
        sb3_check_env(env.unwrapped, warn=True)
    assert env.observation_space.shape == (OBSERVATION_SIZES[observation_type],)


def test_bad_option_values_raise() -> None:
    with pytest.raises(ValueError, match="action_type"):
        gym.make(ENV_ID, action_type="incremental")
    with pytest.raises(ValueError, match="observation_type"):
        gym.make(ENV_ID, observation_type="stack")
    env = gym.make(ENV_ID)  # the defaults are v1's interface
    assert env.unwrapped.task.action_type == "absolute" and env.observation_space.shape == (14,)


@pytest.mark.skipif(os.environ.get("COF_GYM_SKIP_ZOO") == "1", reason="COF_GYM_SKIP_ZOO=1")
def test_rl_zoo_trains_the_registered_id_with_the_shipped_hyperparameters(tmp_path: Path) -> None:
    """RL Zoo's own entry point on the registered id with ppo.yml (the identified actions and the
    identification observation through its env_kwargs), for 128 steps (2 envs x 1 rollout of 64)."""
    pytest.importorskip("rl_zoo3")
    cmd = [sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", ENV_ID, "--gym-packages", "cof_gym",
           "--conf-file", str(ROOT / "cof_gym/agents/hyperparams/ppo.yml"), "-n", "128", "--eval-freq", "-1",
           "--seed", "0", "--log-folder", str(tmp_path), "--device", "cpu",
           "--hyperparams", "n_steps:64", "batch_size:32", "n_epochs:2"]
    out = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stdout[-2000:] + out.stderr[-2000:]
    assert "'action_type': 'identified'" in out.stdout
    run_dir = tmp_path / "ppo" / "CofGym-TorqueInterrogation-v1_1"
    assert (run_dir / "CofGym-TorqueInterrogation-v1.zip").is_file()
    assert (run_dir / "CofGym-TorqueInterrogation-v1" / "vecnormalize.pkl").is_file()
    # the run directory plays as it was trained: the env id and the interface from RL Zoo's args.yml and config.yml
    from cof_gym.agents.sb3_policy import SB3Agent

    agent = SB3Agent.load(run_dir)
    assert agent.env_id == ENV_ID and agent.vec_normalize is not None and agent.interface is not None
    assert agent.trained_on == (ENV_ID, {"shaping": False, "action_type": "identified",
                                         "observation_type": "identification"})
    env = gym.make(ENV_ID)
    obs, info = env.reset(seed=2)
    agent.reset(obs, info)
    assert env.action_space.contains(agent.act(obs, info))
    env.close()
