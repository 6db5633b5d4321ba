"""The registered ids in the RL libraries users pick, and the Gymnasium conventions those rely on:
an unknown constructor argument name is a TypeError worded as Python's (torchrl drops ``frameskip`` on
it), info holds no None, the spec carries the horizon, the env stays usable after a failed reset under
gym.make's default wrappers, and the batched vector env autoresets in Gymnasium's modes."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import cof_gym

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
