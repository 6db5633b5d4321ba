"""The registered ids in the RL libraries users pick, and the Gymnasium conventions those rely on:
an unknown constructor argument name is a TypeError worded as Python's (torchrl drops ``frameskip`` on
it), info holds no None, the spec carries the horizon, the env stays usable after a failed reset under
gym.make's default wrappers, and the batched vector env autoresets in Gymnasium's modes. The clients:
torchrl's ``GymEnv`` and ``GymWrapper`` over ``gym.make_vec`` (``info_layout="flat"`` with same-step
autoreset, or the nested default with autoreset disabled), tianshou's PPO on its Dummy and Subproc
vector envs (each skipped where the library is not installed)."""

from __future__ import annotations

import functools

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.task.info_layout import FLAT_CODES, FLAT_SEPARATOR, decode_flat, flatten_info

IDS = (cof_gym.WAGON_ENV_ID, cof_gym.HALF_WHEELSET_ENV_ID)
SHORT = {"max_windows": 3, "window_s": 0.5}
QUIET = np.array([-1.0, -1.0, -1.0, 0.0, -1.0], dtype=np.float32)  # no DC torque, smallest modulation


def _walk(info: dict, path: str = ""):
    for key, value in info.items():
        if isinstance(value, dict):
            yield from _walk(value, f"{path}{key}.")
        else:
            yield f"{path}{key}", value


@pytest.mark.parametrize("env_id", IDS)
def test_unknown_argument_name_is_a_python_type_error(env_id: str) -> None:
    with pytest.raises(TypeError, match="unexpected keyword argument 'frameskip'"):
        gym.make(env_id, frameskip=1)
    with pytest.raises(ValueError, match="window_s"):
        gym.make(env_id, window_s=-1.0)  # a wrong value stays a ValueError


def test_env_usable_after_a_failed_reset_under_gym_make() -> None:
    env = gym.make(cof_gym.WAGON_ENV_ID)  # gym.make's default wrappers
    with pytest.raises(ValueError, match="cof"):
        env.reset(options={"cof": 5})
    obs, _ = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(QUIET)
    assert np.isfinite(obs).all() and np.isfinite(reward)


@pytest.mark.parametrize("env_id", IDS)
def test_info_holds_no_none_and_errors_appear_when_scored(env_id: str) -> None:
    env = gym.make(env_id, **SHORT, cof=0.3)
    _, info = env.reset(seed=1)
    infos = [info]
    done = False
    while not done:
        *_, terminated, truncated, info = env.step(QUIET)
        infos.append(info)
        done = terminated or truncated
    for i in infos:
        assert not [k for k, v in _walk(i) if v is None]
    assert all("relative_error" not in i and "log_error" not in i for i in infos[:-1])
    assert {"relative_error", "log_error"} <= set(infos[-1])


@pytest.mark.parametrize("env_id", IDS)
def test_spec_carries_the_horizon_and_time_limit_agrees_with_the_task(env_id: str) -> None:
    env = gym.make(env_id, window_s=0.5)
    assert env.spec.max_episode_steps == env.unwrapped.task.max_windows
    env.reset(seed=0, options={"cof": 0.3})
    steps = 0
    while True:
        *_, terminated, truncated, info = env.step(QUIET)
        steps += 1
        if terminated or truncated:
            break
    assert (steps, truncated, "relative_error" in info) == (env.spec.max_episode_steps, True, True)
    wrapped = gym.wrappers.TimeAwareObservation(gym.make(env_id, **SHORT))  # reads the spec's horizon
    assert wrapped.reset(seed=0)[0].shape == (env.observation_space.shape[0] + 1,)


@pytest.mark.parametrize("mode", [gym.vector.AutoresetMode.SAME_STEP, gym.vector.AutoresetMode.NEXT_STEP])
def test_vector_env_autoreset_modes_match_the_sync_vector_env(mode) -> None:
    kw = dict(SHORT)
    batched = gym.make_vec(cof_gym.HALF_WHEELSET_ENV_ID, 2, vectorization_mode="vector_entry_point",
                           autoreset_mode=mode, **kw)
    sync = gym.make_vec(cof_gym.HALF_WHEELSET_ENV_ID, 2, vectorization_mode="sync",
                        vector_kwargs={"autoreset_mode": mode}, **kw)
    assert batched.metadata["autoreset_mode"] == mode
    for a, b in zip(batched.reset(seed=3), sync.reset(seed=3)):
        np.testing.assert_array_equal(a, b) if isinstance(a, np.ndarray) else None
    actions = np.stack([QUIET, QUIET])
    ended = 0
    for _ in range(5):  # through a reset
        out_a, out_b = batched.step(actions), sync.step(actions)
        for x, y in zip(out_a[:4], out_b[:4]):
            np.testing.assert_array_equal(x, y)
        assert ("final_obs" in out_a[4]) == ("final_obs" in out_b[4])
        ended += int(out_a[3].any())
    assert ended >= 1


def test_vector_env_refuses_an_unknown_autoreset_mode_in_one_line() -> None:
    with pytest.raises(ValueError, match="autoreset_mode must be one of") as err:
        gym.make_vec(cof_gym.HALF_WHEELSET_ENV_ID, 2, vectorization_mode="vector_entry_point",
                     autoreset_mode="bogus")
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("env_id", IDS)
def test_torchrl_gym_env_passes_check_env_specs(env_id: str) -> None:
    pytest.importorskip("torchrl")
    from torchrl.envs import GymEnv
    from torchrl.envs.utils import check_env_specs

    env = GymEnv(env_id, **SHORT)
    check_env_specs(env)
    rollout = env.rollout(4)
    assert rollout["next", "observation"].shape[-1] == env.observation_spec["observation"].shape[-1]


# ---------------------------------------------------------------- info layouts
@pytest.mark.parametrize("env_id", IDS)
def test_flat_info_layout_holds_the_nested_numbers_under_joined_keys(env_id: str) -> None:
    flat_env = gym.make(env_id, **SHORT, info_layout="flat")
    nested_env = gym.make(env_id, **SHORT)
    key_sets = set()
    for seed in range(4):  # several episodes (families, conditions, load cases drawn)
        (_, flat), (_, nested) = flat_env.reset(seed=seed), nested_env.reset(seed=seed)
        infos = [(flat, nested)]
        done = False
        while not done:
            *_, terminated, truncated, flat = flat_env.step(QUIET)
            *_, _, _, nested = nested_env.step(QUIET)
            infos.append((flat, nested))
            done = terminated or truncated
        for flat, nested in infos:
            assert flat == flatten_info(nested)
            assert all(isinstance(v, (bool, int, float)) and np.isfinite(v) for v in flat.values()), flat
            assert "ground_truth/creep_law" not in flat and "creep_law" in nested["ground_truth"]
            for key in FLAT_CODES:
                group, name = key.split(FLAT_SEPARATOR)
                assert decode_flat(key, flat[key]) == nested[group][name]
            assert flat["measurement/phase_lag_deg"] == nested["measurement"]["phase_lag_deg"]
        assert all("log_error" not in f for f, _ in infos[:-1]) and "log_error" in infos[-1][0]
        key_sets.add(frozenset(infos[0][0]))  # a reset's keys
        key_sets.add(frozenset(infos[-1][0]))  # a scored step's keys
    assert len(key_sets) == 2  # the same keys in every episode


def test_info_layout_value_is_checked() -> None:
    with pytest.raises(ValueError, match="info_layout must be one of"):
        gym.make(cof_gym.WAGON_ENV_ID, info_layout="flattened")
    with pytest.raises(ValueError, match="info_layout"):
        gym.make_vec(cof_gym.WAGON_ENV_ID, 2, vectorization_mode="vector_entry_point", info_layout=None)


# ---------------------------------------------------------------- torchrl over gym.make_vec
def _make_vec(env_id: str, mode: str, autoreset, **kwargs):
    vector = {"autoreset_mode": autoreset} if mode == "vector_entry_point" else \
        {"vector_kwargs": {"autoreset_mode": autoreset}}
    return gym.make_vec(env_id, 2, vectorization_mode=mode, **SHORT, **vector, **kwargs)


def _rollout_through_resets(env) -> None:
    from torchrl.envs.utils import check_env_specs

    check_env_specs(env)
    env.set_seed(0)
    rollout = env.rollout(8, break_when_any_done=False)  # the horizon is 3 steps: >= 2 resets per sub-env
    assert rollout.batch_size == (2, 8)
    assert (rollout["next", "done"].squeeze(-1).sum(-1) >= 2).all()
    assert rollout["next", "observation"].isfinite().all()
    return rollout


@pytest.mark.parametrize("mode", ["vector_entry_point", "sync"])
@pytest.mark.parametrize("env_id", IDS)
def test_torchrl_gym_wrapper_over_make_vec_reads_the_flat_info(env_id: str, mode: str) -> None:
    pytest.importorskip("torchrl")
    from torchrl.envs import GymWrapper

    env = GymWrapper(_make_vec(env_id, mode, gym.vector.AutoresetMode.SAME_STEP, info_layout="flat"))
    rollout = _rollout_through_resets(env)
    cof = rollout["next", "ground_truth/cof"]  # the info, read into the rollout
    assert ((cof >= 0.02) & (cof <= 0.6)).all()


@pytest.mark.parametrize("mode", ["vector_entry_point", "sync"])
def test_torchrl_gym_wrapper_over_make_vec_with_autoreset_disabled_takes_the_nested_info(mode: str) -> None:
    """torchrl's preferred autoreset mode for vector envs is DISABLED (it resets sub-envs itself, and
    reads no info): the nested default works there."""
    pytest.importorskip("torchrl")
    from torchrl.envs import GymWrapper

    for env_id in IDS:
        _rollout_through_resets(GymWrapper(_make_vec(env_id, mode, gym.vector.AutoresetMode.DISABLED)))


# ---------------------------------------------------------------- tianshou
@pytest.mark.parametrize(("env_id", "venv", "info_layout"), [
    (cof_gym.WAGON_ENV_ID, "DummyVectorEnv", "nested"),
    (cof_gym.HALF_WHEELSET_ENV_ID, "SubprocVectorEnv", "flat"),
])
def test_tianshou_ppo_trains_an_epoch_of_512_steps_on_two_envs(env_id: str, venv: str, info_layout: str) -> None:
    """tianshou 2's low-level API (Algorithm + OnPolicyTrainerParams); its trainer raises
    MalformedBufferError on a NaN anywhere in the buffer, info included."""
    numba = pytest.importorskip("numba")
    jit = numba.config.DISABLE_JIT
    numba.config.DISABLE_JIT = True  # tianshou's @njit helpers (GAE, buffer indices) decorated as plain Python:
    try:  # compiling them took 15 of this test's 23 s on 2 cores; the arithmetic is the same either way
        pytest.importorskip("tianshou", minversion="2.0")
        from tianshou import env as tianshou_env
        from tianshou.algorithm import PPO
        from tianshou.algorithm.modelfree.reinforce import ProbabilisticActorPolicy
        from tianshou.algorithm.optim import AdamOptimizerFactory
        from tianshou.data import Collector, VectorReplayBuffer
        from tianshou.trainer import OnPolicyTrainerParams
        from tianshou.utils.net.common import Net
        from tianshou.utils.net.continuous import ContinuousActorProbabilistic, ContinuousCritic
    finally:
        numba.config.DISABLE_JIT = jit
    import torch
    from torch.distributions import Independent, Normal

    # 8 windows of 0.2 s: the cost of 512 steps is mostly resets (the ground truth's creep-curve peak)
    # "cof_gym:" imports cof_gym first: a spawned worker (torchrl sets spawn as the default) has not
    make = functools.partial(gym.make, f"cof_gym:{env_id}", max_windows=8, window_s=0.2, info_layout=info_layout)
    probe = make()
    probe.reset(seed=0)  # models built and code compiled before the workers fork
    obs_space, act_space = probe.observation_space, probe.action_space
    probe.close()
    envs = getattr(tianshou_env, venv)([make, make])
    envs.seed([0, 1])
    torch.manual_seed(0)
    threads = torch.get_num_threads()
    torch.set_num_threads(1)  # a 32-unit MLP: threads only contend with the envs
    actor = ContinuousActorProbabilistic(preprocess_net=Net(state_shape=obs_space.shape, hidden_sizes=(32, 32)),
                                         action_shape=act_space.shape, unbounded=True)
    with torch.no_grad():  # a cautious start (small DC torque, stop rarely drawn): episodes last, resets are few
        actor.mu.model[-1].bias[[0, 4]] = -2.0
    critic = ContinuousCritic(preprocess_net=Net(state_shape=obs_space.shape, hidden_sizes=(32, 32)))

    def gaussian(loc_scale):
        loc, scale = loc_scale
        return Independent(Normal(loc, scale), 1)

    policy = ProbabilisticActorPolicy(actor=actor, dist_fn=gaussian, action_space=act_space,
                                      observation_space=obs_space, action_scaling=False)  # the space is [-1, 1]
    algorithm = PPO(policy=policy, critic=critic, optim=AdamOptimizerFactory(lr=3e-4))
    collector = Collector(algorithm, envs, VectorReplayBuffer(2048, len(envs)), raise_on_nan_in_buffer=True)
    try:
        stats = algorithm.run_training(OnPolicyTrainerParams(
            training_collector=collector, test_collector=None, max_epochs=1, epoch_num_steps=512,
            collection_step_num_env_steps=512, batch_size=256, update_step_num_repetitions=2,
            verbose=False, show_progress=False))
        assert stats.train_step == 512 and stats.update_step == 1
        collector.collect(n_step=64)  # the trained policy, and the info as the buffer stores it
    finally:
        envs.close()
        torch.set_num_threads(threads)
    buffer = collector.buffer
    info = buffer.info[buffer.sample_indices(0)]
    cof = info["ground_truth/cof"] if info_layout == "flat" else info.ground_truth.cof
    assert len(cof) == 64 and ((cof >= 0.02) & (cof <= 0.6)).all()
    assert not buffer.hasnull()
