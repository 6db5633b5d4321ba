"""Property tests: arbitrary action sequences (huge, infinite, NaN, subnormal components; float32 or
float64; arrays or lists) through both registered environments."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np

from cof_gym.task.interface import OBSERVATION_NAMES
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cof_gym

ENV_IDS = sorted(env_id for env_id in gym.registry if env_id.startswith("CofGym/"))
ACTION_NAMES = ("dc_torque", "amplitude", "frequency", "cof_estimate", "stop")
SHORT = {"max_windows": 3, "window_s": 0.5}

# built once per module; every example resets them with a seed drawn by hypothesis
ENVS = {env_id: gym.make(env_id, **SHORT) for env_id in ENV_IDS}
TWINS = {env_id: gym.make(env_id, **SHORT) for env_id in ENV_IDS}
for _env in (*ENVS.values(), *TWINS.values()):
    _env.reset(seed=0)  # gymnasium's passive checker runs on the first reset; keep it out of the examples

SPECIAL = [math.nan, math.inf, -math.inf, 1e6, -1e6, 5e-324, -5e-324, 1e-45, -1e-45, 1.0, -1.0, 0.0, -0.0,
           1.0000001, -1.0000001, 1e300, -1e300]
component = st.one_of(
    st.floats(-1.0, 1.0),
    st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True),
    st.sampled_from(SPECIAL),
)
finite_component = st.one_of(
    st.floats(-1.0, 1.0),
    st.floats(allow_nan=False, allow_infinity=False, allow_subnormal=True),
    st.sampled_from([v for v in SPECIAL if math.isfinite(v)]),
)
seeds = st.integers(0, 2**31 - 1)
kinds = st.sampled_from(["float32", "float64", "list"])


def as_action(values: list[float], kind: str):
    """The action as the agent passes it; float32 casts of huge values overflow to inf on purpose."""
    if kind == "list":
        return list(values)
    with np.errstate(over="ignore"):
        return np.asarray(values, dtype=np.float64).astype(kind)


def check_obs(env: gym.Env, obs) -> None:
    assert isinstance(obs, np.ndarray) and obs.dtype == np.float32 and obs.shape == (len(OBSERVATION_NAMES),)
    assert np.isfinite(obs).all(), obs
    assert env.observation_space.contains(obs), obs


@pytest.mark.parametrize("env_id", ENV_IDS)
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=seeds, kind=kinds,
       actions=st.lists(st.lists(component, min_size=5, max_size=5), min_size=1, max_size=6))
def test_arbitrary_actions_only_non_finite_raise(env_id: str, seed: int, kind: str, actions: list) -> None:
    env = ENVS[env_id]
    obs, info = env.reset(seed=seed)
    check_obs(env, obs)
    for values in actions:
        action = as_action(values, kind)
        bad = [name for name, v in zip(ACTION_NAMES, np.asarray(action, dtype=np.float64)) if not math.isfinite(v)]
        if bad:
            with pytest.raises(ValueError) as exc:
                env.step(action)
            for name in bad:
                assert name in str(exc.value), (name, str(exc.value))
            continue
        obs, reward, terminated, truncated, info = env.step(action)
        check_obs(env, obs)
        assert isinstance(reward, float) and math.isfinite(reward)
        assert isinstance(terminated, bool) and isinstance(truncated, bool)
        assert not info["diverged"]
        assert all(math.isfinite(info[k]) for k in ("reward_error", "reward_slip", "reward_comfort", "reward_time"))
        if terminated or truncated:
            obs, info = env.reset()
            check_obs(env, obs)


@pytest.mark.parametrize("env_id", ENV_IDS)
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=seeds,
       actions=st.lists(st.lists(finite_component, min_size=5, max_size=5), min_size=1, max_size=4))
def test_finite_actions_act_like_their_clipped_values(env_id: str, seed: int, actions: list) -> None:
    env, twin = ENVS[env_id], TWINS[env_id]
    env.reset(seed=seed)
    twin.reset(seed=seed)
    for values in actions:
        raw = np.asarray(values, dtype=np.float64)
        got = env.step(raw)
        want = twin.step(np.clip(raw, -1.0, 1.0))
        np.testing.assert_array_equal(got[0], want[0])
        assert got[1:4] == want[1:4]
        assert got[4]["cof_estimate"] == want[4]["cof_estimate"]
        if got[2] or got[3]:
            break


def test_registry_matches_package() -> None:
    assert ENV_IDS == sorted(cof_gym.ENV_IDS)
