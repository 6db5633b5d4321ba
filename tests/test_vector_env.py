"""The batched vector env (one mujoco.batch.Batch) against N single envs, and its SB3 adapter."""

from __future__ import annotations

import os
import warnings

import gymnasium as gym
import numpy as np

from cof_gym.task.interface import OBSERVATION_NAMES
import pytest
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

import cof_gym  # noqa: F401  (registers the ids)
from cof_gym.envs.vector import TorqueInterrogationVectorEnv

ENV_ID = "CofGym/TorqueInterrogation-v1"


def same(x, y) -> bool:
    """Bit-identical, recursively (NaN equals NaN; dtypes and types must match)."""
    if isinstance(x, dict):
        return isinstance(y, dict) and x.keys() == y.keys() and all(same(x[k], y[k]) for k in x)
    if isinstance(x, (tuple, list)):
        return type(x) is type(y) and len(x) == len(y) and all(same(a, b) for a, b in zip(x, y))
    if isinstance(x, np.ndarray):
        if not (isinstance(y, np.ndarray) and x.dtype == y.dtype and x.shape == y.shape):
            return False
        if x.dtype == object:
            return all(same(a, b) for a, b in zip(x.ravel(), y.ravel()))
        return x.tobytes() == y.tobytes()
    if isinstance(x, (float, np.floating)) and isinstance(y, (float, np.floating)):
        return type(x) is type(y) and np.float64(x).tobytes() == np.float64(y).tobytes()
    return type(x) is type(y) and x == y


def first_difference(x, y, path: str = "") -> str:
    if isinstance(x, dict) and isinstance(y, dict):
        for k in sorted(set(x) | set(y), key=str):
            if k not in x or k not in y:
                return f"{path}{k}: missing on one side"
            d = first_difference(x[k], y[k], f"{path}{k}.")
            if d:
                return d
        return ""
    if isinstance(x, (tuple, list)) and isinstance(y, (tuple, list)) and len(x) == len(y):
        for k, (a, b) in enumerate(zip(x, y)):
            d = first_difference(a, b, f"{path}[{k}].")
            if d:
                return d
        return ""
    return "" if same(x, y) else f"{path}: {x!r} != {y!r}"


def make_pair(n: int, env_id: str = ENV_ID, **kwargs):
    batched = gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point", **kwargs)
    kwargs.pop("num_threads", None)
    sync = gym.make_vec(env_id, num_envs=n, vectorization_mode="sync", **kwargs)
    return batched, sync


def assert_batched_plays_as_sync(options: dict, steps: int = 2, env_id: str = ENV_ID, **kwargs) -> None:
    """Two envs of the batched vector env of ``env_id`` reset with ``options`` and stepped ``steps`` times at a small
    DC torque give every observation, reward, flag and info that gymnasium's SyncVectorEnv of single envs gives, bit
    for bit."""
    batched, sync = make_pair(2, env_id, **kwargs)
    try:
        a, b = batched.reset(seed=5, options=dict(options)), sync.reset(seed=5, options=dict(options))
        assert same(a, b), first_difference(a, b)
        actions = np.tile(np.array([-0.9, 0.0, 0.0, 0.0, -1.0], np.float32), (2, 1))
        for step in range(steps):
            a, b = batched.step(actions), sync.step(actions)
            assert same(a, b), f"step {step}: {first_difference(a, b)}"
    finally:
        batched.close()
        sync.close()


def test_make_vec_returns_the_batched_env_with_gymnasium_spaces():
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point")
    single = gym.make(ENV_ID)
    try:
        assert isinstance(envs, TorqueInterrogationVectorEnv)
        assert envs.num_envs == 2 and envs.num_threads == min(2, os.cpu_count())
        assert envs.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
        assert envs.spec is not None and envs.spec.id == ENV_ID
        assert envs.max_episode_steps == single.spec.max_episode_steps
        assert envs.single_action_space == single.action_space
        assert envs.single_observation_space == single.observation_space
        assert envs.action_space == batch_space(single.action_space, 2)
        assert envs.observation_space == batch_space(single.observation_space, 2)
        assert envs.action_space.shape == (2, 5) and envs.action_space.dtype == np.float32
        obs, info = envs.reset(seed=0)
        assert obs.shape == (2, len(OBSERVATION_NAMES)) and obs.dtype == np.float32 and envs.observation_space.contains(obs)
        assert info["_diverged"].all() and not info["diverged"].any()
        t_reset = envs._time.copy()
        with pytest.raises(ValueError, match="not finite"):  # checked before any simulation moves
            envs.step(np.full((2, 5), np.nan, dtype=np.float32))
        assert np.array_equal(envs._time, t_reset)
        # gymnasium's vector wrappers accept it (they check the autoreset mode)
        wrapped = gym.wrappers.vector.RecordEpisodeStatistics(envs)
        envs.action_space.seed(0)
        out = wrapped.step(envs.action_space.sample())
        assert envs.observation_space.contains(out[0]) and out[1].dtype == np.float64
    finally:
        envs.close()
        single.close()


def test_bit_identical_to_single_envs_with_autoreset_and_load_cases():
    """N=3 vs gymnasium's SyncVectorEnv of gym.make envs (seeded seed+i, next-step autoreset): every
    observation, reward, flag and info, through terminations, truncations, autoresets, a masked
    reset with a fixed load case, and both load cases."""
    n = 3
    batched, sync = make_pair(n, max_windows=4)
    try:
        assert same(batched.reset(seed=123), sync.reset(seed=123))
        batched.action_space.seed(5)
        rng = np.random.default_rng(5)
        ends = truncations = autoresets = 0
        ended = np.zeros(n, dtype=bool)
        load_cases = set()
        for t in range(24):
            if t == 12:  # masked reset with an option, in the middle of episodes
                mask = np.array([True, False, True])
                opts = {"load_case": "empty", "reset_mask": mask}
                a, b = batched.reset(options=dict(opts)), sync.reset(options=dict(opts))
                assert same(a, b), first_difference(a, b)
                ended[mask] = False
            actions = batched.action_space.sample()
            actions[:, 0] = np.minimum(actions[:, 0], -0.98)  # mostly below saturation: episodes run on
            actions[:, 4] = np.where(rng.random(n) < 0.15, 1.0, -1.0)
            a, b = batched.step(actions), sync.step(actions)
            assert same(a, b), f"step {t}: {first_difference(a, b)}"
            ends += int(np.sum(a[2] | a[3]))
            truncations += int(np.sum(a[3]))
            autoresets += int(np.sum(ended))
            assert np.all(a[1][ended] == 0.0) and not np.any(a[2][ended] | a[3][ended])
            ended = a[2] | a[3]
            load_cases |= set(s.load_case for s in batched.get_attr("scenario"))
            # scalar info entries, explicitly
            for key in ("diverged", "cof_estimate", "elapsed_s", "reward_slip", "reward_error"):
                if key in a[4]:
                    assert same(a[4][key], b[4][key]) and same(a[4]["_" + key], b[4]["_" + key])
        assert ends >= 3 and truncations >= 1 and autoresets >= 3
        assert load_cases == {"empty", "laden"}
    finally:
        batched.close()
        sync.close()


def test_thread_count_does_not_change_results():
    runs = []
    for threads in (1, 2):
        envs = gym.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point", num_threads=threads,
                            max_windows=5)
        assert envs.num_threads == threads
        envs.action_space.seed(9)
        trace = [envs.reset(seed=42)]
        for t in range(15):
            actions = envs.action_space.sample()
            actions[:, 0] = np.minimum(actions[:, 0], 0.0)
            actions[:, 4] = -1.0 if t % 4 else 1.0
            trace.append(envs.step(actions))
        envs.close()
        runs.append(trace)
    assert same(runs[0], runs[1]), first_difference(runs[0], runs[1])


def test_half_wheelset_vector_matches_single():
    batched, sync = make_pair(2, vehicle="half_wheelset")
    try:
        assert same(batched.reset(seed=3), sync.reset(seed=3))
        batched.action_space.seed(3)
        for t in range(5):
            actions = batched.action_space.sample()
            a, b = batched.step(actions), sync.step(actions)
            assert same(a, b), f"step {t}: {first_difference(a, b)}"
    finally:
        batched.close()
        sync.close()


def test_a_corrupted_simulation_diverges_alone_and_autoresets(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo's warning writes MUJOCO_LOG.TXT into the working directory
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", cof=0.4, speed_m_s=20.0)
    try:
        envs.reset(seed=0)
        envs._qvel[1, 3] = np.nan  # MuJoCo warns, auto-resets that simulation; the env reports divergence
        actions = np.tile(np.array([-0.8, 0.0, 0.0, 0.0, -1.0], np.float32), (2, 1))
        obs, reward, terminated, truncated, info = envs.step(actions)
        assert info["diverged"].tolist() == [False, True] and terminated.tolist() == [False, True]
        assert np.isfinite(obs).all() and np.isfinite(reward).all()
        obs, reward, terminated, _, info = envs.step(actions)  # sub-env 1 autoresets
        assert reward[1] == 0.0 and not terminated.any() and not info["diverged"].any() and np.isfinite(obs).all()
        obs, reward, terminated, _, info = envs.step(actions)
        assert not terminated.any() and not info["diverged"].any() and np.isfinite(obs).all()
    finally:
        envs.close()


@pytest.mark.parametrize("field,value", [
    ("num_envs", True), ("num_envs", 0), ("num_envs", 2.0), ("num_envs", 4097), ("num_envs", "2"),
    ("num_threads", True), ("num_threads", np.True_), ("num_threads", 0), ("num_threads", 2**40), ("num_threads", 1.0),
    ("max_episode_steps", True), ("max_episode_steps", 0), ("max_episode_steps", 1.5), ("max_episode_steps", "3"),
])
def test_bad_vector_arguments_raise_naming_them(field, value):
    """Ints, not bools (True was taken as 1), in their ranges (2**40 threads was a pybind TypeError)."""
    kwargs = {"num_envs": 1, field: value}
    with pytest.raises(ValueError, match=f"^{field} must be an integer in \\[1, "):
        gym.make_vec(ENV_ID, vectorization_mode="vector_entry_point", **kwargs)


@pytest.mark.parametrize("value", [-1, np.int8(-1)])
def test_max_episode_steps_minus_one_applies_no_time_limit_as_gym_make_does(value):
    single = gym.make(ENV_ID, max_episode_steps=-1)
    envs = gym.make_vec(ENV_ID, num_envs=1, vectorization_mode="vector_entry_point", max_episode_steps=value)
    try:
        assert envs.max_episode_steps is None and "TimeLimit" not in str(single)
    finally:
        envs.close()
        single.close()


def test_numpy_integer_vector_arguments_are_stored_as_ints():
    envs = gym.make_vec(ENV_ID, num_envs=np.int64(2), vectorization_mode="vector_entry_point",
                        num_threads=np.int32(1), max_episode_steps=np.int16(5), max_windows=5)
    try:
        assert (envs.num_envs, envs.num_threads, envs.max_episode_steps) == (2, 1, 5)
        assert all(type(v) is int for v in (envs.num_envs, envs.num_threads, envs.max_episode_steps))
    finally:
        envs.close()


@pytest.fixture(scope="module")
def pair_env():
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", max_windows=2, window_s=0.5)
    yield envs
    envs.close()


@pytest.mark.parametrize("seed,fragment", [
    ("3", r"^seed must be None, an int >= 0"), (1.5, r"^seed must be None, an int >= 0"),
    (True, r"^seed must be None, an int >= 0"), (-1, r"^seed must be None, an int >= 0"),
    (np.float64(3.0), r"^seed must be None, an int >= 0"), ({0: 1, 1: 2}, r"^seed must be None, an int >= 0"),
    ([0, "1"], r"^seed\[1\] must be an int >= 0 or None"), ([1.5, 2], r"^seed\[0\] must be an int >= 0 or None"),
    ([0, True], r"^seed\[1\] must be an int >= 0 or None"), ([0, -2], r"^seed\[1\] must be an int >= 0 or None"),
    ([0], "must match num_envs=2"),
])
def test_a_bad_seed_is_one_value_error_naming_it(pair_env, seed, fragment):
    with pytest.raises(ValueError, match=fragment):
        pair_env.reset(seed=seed)


@pytest.mark.parametrize("options", ["dry", ["cof"], 5, ("cof", 0.3)])
def test_reset_options_must_be_a_mapping(pair_env, options):
    """(A string was read as a dict's items: "dictionary update sequence element #0".)"""
    with pytest.raises(ValueError, match=r"^options must be a dict"):
        pair_env.reset(seed=0, options=options)


def test_numpy_integer_seeds_seed_as_the_ints_they_hold(pair_env):
    expected = pair_env.reset(seed=3)[0]
    for seed in (np.int64(3), [3, 4], (np.int32(3), np.uint8(4)), np.array([3, 4])):
        assert pair_env.reset(seed=seed)[0].tobytes() == expected.tobytes()
    first = pair_env.reset(seed=[3, None])[0]  # None: that sub-env draws unseeded (its stream goes on)
    assert first[0].tobytes() == expected[0].tobytes()


def test_a_closed_vector_env_refuses_reset_and_step_as_gymnasiums_do():
    """(It failed with "'NoneType' object has no attribute 'reset'".)"""
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", max_windows=2, window_s=0.5)
    envs.reset(seed=0)
    envs.close()
    envs.close()  # twice is fine
    with pytest.raises(gym.error.ClosedEnvironmentError, match="the vector env is closed"):
        envs.reset(seed=0)
    with pytest.raises(gym.error.ClosedEnvironmentError, match="the vector env is closed"):
        envs.step(np.zeros(envs.action_space.shape, np.float32))


def test_get_attr_reads_the_episodes_and_names_their_fields_for_any_other_name(pair_env):
    pair_env.reset(seed=0)
    assert [s.load_case for s in pair_env.get_attr("scenario")] == [e.scenario.load_case for e in pair_env.episodes]
    with pytest.raises(AttributeError, match=r"'np_random' is none of its fields \['scenario', 'truth'"):
        pair_env.get_attr("np_random")


def test_a_time_limit_below_the_tasks_horizon_is_a_warning():
    """make_vec passes the id's registered TimeLimit (30) unless given one: a max_windows beyond it would end
    every episode unscored."""
    with pytest.warns(UserWarning, match=r"max_episode_steps=30 .* max_windows=40 scores its estimate: pass "
                                         r"max_episode_steps=40"):
        gym.make_vec(cof_gym.WAGON_ENV_ID, num_envs=1, vectorization_mode="vector_entry_point", max_windows=40).close()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gym.make_vec(cof_gym.WAGON_ENV_ID, num_envs=1, vectorization_mode="vector_entry_point", max_windows=40,
                     max_episode_steps=40).close()
