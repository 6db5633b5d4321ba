"""The Gymnasium environments: API checkers, spawn/pickle, determinism, scenario overrides, bad input,
episode end, reward bookkeeping, rendering and a PPO smoke run (every registered ``CofGym/`` id)."""

from __future__ import annotations

import math
import multiprocessing
import os
import pickle
import re
import subprocess
import sys
import warnings
from contextlib import contextmanager
from pathlib import Path

import gymnasium as gym
import numpy as np

import pytest
from gymnasium.utils.env_checker import check_env as gym_check_env

import cof_gym
from cof_gym.task.interface import OBSERVATION_NAMES
from cof_gym.task.task import DEFAULT_MAX_WINDOWS

WAGON = "CofGym/TorqueInterrogation-v1"
HALF = "CofGym/HalfWheelset-v1"
ENV_IDS = sorted(env_id for env_id in gym.registry if env_id.startswith("CofGym/"))
SHORT = {"max_windows": 4, "window_s": 0.5}  # short horizons keep the module fast
ACTION_NAMES = ("dc_torque", "amplitude", "frequency", "cof_estimate", "stop")  # the docstring's table
ESTIMATE_RANGE = (0.01, 1.0)  # the docstring's logarithmic estimate range
REWARD_KEYS = ("reward_error", "reward_slip", "reward_comfort", "reward_time")
QUIET = np.array([-1.0, -1.0, 0.0, 0.0, -1.0], dtype=np.float32)  # no DC torque, smallest amplitude, no stop


def estimate_of(action_value: float) -> float:
    """The CoF estimate an action component maps to (logarithmic over ESTIMATE_RANGE)."""
    lo, hi = ESTIMATE_RANGE
    return math.exp(math.log(lo) + (float(np.float32(action_value)) + 1.0) / 2.0 * math.log(hi / lo))

# gymnasium's check_env always warns when it is given a wrapped env (it recommends env.unwrapped):
# a property of the checker, not of the environment, so it is the one message allowed for made envs.
WRAPPED_NOTICE = "is different from the unwrapped version"
# render_mode='human' without a display warns once and returns None by design (see the render tests).
HUMAN_NO_DISPLAY = "needs a display"


def display_available() -> bool:
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


@contextmanager
def no_warnings(allowed: tuple[str, ...] = ()):
    """Fail if any warning other than those containing one of ``allowed`` is emitted inside."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield caught
    unexpected = [f"{w.category.__name__}: {w.message} ({w.filename}:{w.lineno})" for w in caught
                  if not any(a in str(w.message) for a in allowed)]
    assert not unexpected, "unexpected warnings:\n" + "\n".join(unexpected)


def assert_same(a, b, path: str = "") -> None:
    """Recursive exact equality of nested dicts / sequences / arrays / numbers (NaN == NaN)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), f"{path}: keys {sorted(a)} != {sorted(b)}"
        for k in a:
            assert_same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, (list, tuple)):
        assert isinstance(b, (list, tuple)) and len(a) == len(b), f"{path}: {a!r} != {b!r}"
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{path}[{i}]")
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a_arr, b_arr = np.asarray(a), np.asarray(b)
        assert a_arr.dtype == b_arr.dtype and a_arr.shape == b_arr.shape, f"{path}: {a_arr.dtype}{a_arr.shape} != {b_arr.dtype}{b_arr.shape}"
        assert np.array_equal(a_arr, b_arr, equal_nan=a_arr.dtype.kind in "fc"), f"{path}: {a_arr} != {b_arr}"
    elif isinstance(a, float) and isinstance(b, float) and math.isnan(a):
        assert math.isnan(b), f"{path}: nan != {b!r}"
    else:
        assert type(a) is type(b) and a == b, f"{path}: {a!r} != {b!r}"


def rollout(env: gym.Env, seed: int, *, allow_stop: bool = False, options: dict | None = None,
            max_steps: int = 50) -> list[tuple]:
    """reset(seed) then seeded uniform random actions until the episode ends; every returned item."""
    obs, info = env.reset(seed=seed, options=options)
    steps: list[tuple] = [(obs, info)]
    rng = np.random.default_rng(10_000 + seed)
    for _ in range(max_steps):
        action = rng.uniform(-1.0, 1.0, size=5).astype(np.float32)
        if not allow_stop:
            action[4] = -1.0
        obs, reward, terminated, truncated, info = env.step(action)
        steps.append((obs, reward, terminated, truncated, info))
        if terminated or truncated:
            return steps
    raise AssertionError(f"episode did not end within {max_steps} steps")


def make_pair(env_id: str, seed: int, **kwargs) -> tuple[gym.Env, gym.Env]:
    envs = (gym.make(env_id, **{**SHORT, **kwargs}), gym.make(env_id, **{**SHORT, **kwargs}))
    for env in envs:
        env.reset(seed=seed)
    return envs


def test_both_ids_registered() -> None:
    assert ENV_IDS == sorted(cof_gym.ENV_IDS)
    for env_id in ENV_IDS:
        assert gym.spec(env_id).entry_point == "cof_gym.envs.torque_interrogation:TorqueInterrogationEnv"


# ------------------------------------------------------------------------------------ 1. checkers
# gymnasium's check_env renders every declared render mode. 'human' without a display warns once and
# returns None by design, so without a display the render part is skipped here
# (skip_render_check=True) and rendering is tested separately below (test_check_env_render_modes,
# test_rgb_array_frame, test_render_human_without_display).
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_gymnasium_check_env_unwrapped(env_id: str) -> None:
    env = gym.make(env_id).unwrapped
    with no_warnings():
        gym_check_env(env, skip_render_check=not display_available())
    env.close()


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_gymnasium_check_env_made(env_id: str) -> None:
    env = gym.make(env_id)
    with no_warnings(allowed=(WRAPPED_NOTICE,)):
        gym_check_env(env, skip_render_check=not display_available())
    env.close()


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_sb3_check_env(env_id: str) -> None:
    from stable_baselines3.common.env_checker import check_env as sb3_check_env

    env = gym.make(env_id)
    with no_warnings():
        sb3_check_env(env, warn=True)
    env.close()


def test_spaces_are_what_the_docstring_says() -> None:
    for env_id in ENV_IDS:
        env = gym.make(env_id)
        assert env.action_space == gym.spaces.Box(-1.0, 1.0, (5,), np.float32)
        assert env.observation_space == gym.spaces.Box(-1000.0, 1000.0, (len(OBSERVATION_NAMES),), np.float32)
        assert env.unwrapped.metadata["render_modes"] == ["human", "rgb_array"]
        assert isinstance(env.unwrapped.metadata["render_fps"], int)


# ------------------------------------------------------------------------------ 2. spawn, pickle
# Runs in a freshly spawned interpreter via the builtin exec (picklable by reference), so the child
# imports neither this module nor cof_gym: the "module:Id" form must import cof_gym itself.
SPAWN_CHILD = """
import sys
preloaded = "cof_gym" in sys.modules
try:
    import gymnasium as gym
    import numpy as np
    env = gym.make("cof_gym:CofGym/TorqueInterrogation-v1", max_windows=2, window_s=0.5)
    obs0, _ = env.reset(seed=0)
    obs1, reward, terminated, truncated, _ = env.step(np.array([0.0, 0.0, 0.0, 0.0, -1.0], np.float32))
    queue.put(("ok", preloaded, obs0, obs1, reward, "cof_gym" in sys.modules))
except BaseException as exc:
    import traceback
    queue.put(("error", traceback.format_exc()))
"""


def test_make_in_spawned_subprocess() -> None:
    ctx = multiprocessing.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=exec, args=(SPAWN_CHILD, {"queue": queue}))
    proc.start()
    try:
        result = queue.get(timeout=120)
        proc.join(timeout=60)
    finally:
        if proc.is_alive():
            proc.kill()
            proc.join()
    assert result[0] == "ok", result[1]
    _, preloaded, obs0, obs1, reward, imported = result
    assert not preloaded, "the spawned child had cof_gym imported already: the test proves nothing"
    assert imported
    for obs in (obs0, obs1):
        assert obs.shape == (len(OBSERVATION_NAMES),) and obs.dtype == np.float32 and np.isfinite(obs).all()
    assert math.isfinite(reward)
    assert proc.exitcode == 0
    # and the child's episode is the one this process produces (cross-process determinism)
    env = gym.make(WAGON, max_windows=2, window_s=0.5)
    assert_same(env.reset(seed=0)[0], obs0)
    step = env.step(np.array([0.0, 0.0, 0.0, 0.0, -1.0], np.float32))
    assert_same((step[0], step[1]), (obs1, reward))


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_pickle_roundtrip(env_id: str) -> None:
    env = gym.make(env_id, cof=0.25, **SHORT)
    env.reset(seed=3)
    env.step(QUIET)
    clone = pickle.loads(pickle.dumps(env))
    assert clone.unwrapped.task.max_windows == 4 and clone.unwrapped.task.window_s == 0.5
    assert clone.unwrapped.task.fixed == {"cof": 0.25}
    action = np.array([-0.6, 0.3, -0.2, 0.1, -1.0], np.float32)
    for _ in range(2):  # same results twice: the clone is independent of the original
        assert_same(env.reset(seed=7), clone.reset(seed=7))
        assert_same(env.step(action), clone.step(action))


# --------------------------------------------------------------------------------- 3. determinism
@pytest.mark.parametrize("allow_stop", [False, True])
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_same_seed_same_episode(env_id: str, allow_stop: bool) -> None:
    a, b = gym.make(env_id, **SHORT), gym.make(env_id, **SHORT)
    for seed in (0, 1, 2):
        assert_same(rollout(a, seed, allow_stop=allow_stop), rollout(b, seed, allow_stop=allow_stop))


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_different_seed_different_scenario(env_id: str) -> None:
    env = gym.make(env_id, **SHORT)
    obs1, info1 = env.reset(seed=1)
    obs2, info2 = env.reset(seed=2)
    assert info1["ground_truth"]["cof"] != info2["ground_truth"]["cof"]
    assert info1["ground_truth"]["speed_m_s"] != info2["ground_truth"]["speed_m_s"]
    assert not np.array_equal(obs1, obs2)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_reset_same_seed_on_one_env_reproduces(env_id: str) -> None:
    env = gym.make(env_id, **SHORT)
    first = rollout(env, 5)
    rollout(env, 6)  # another scenario (possibly another load case) in between
    assert_same(first, rollout(env, 5))
    # unseeded resets continue the seeded stream identically
    other = gym.make(env_id, **SHORT)
    env.reset(seed=9)
    other.reset(seed=9)
    assert_same(env.reset(), other.reset())


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_returned_arrays_are_not_shared(env_id: str) -> None:
    """Mutating what step/reset returned must not change the env (no shared buffers)."""
    a, b = make_pair(env_id, seed=4)
    obs_a, _, _, _, info_a = a.step(QUIET)
    obs_b, *_ = b.step(QUIET)
    obs_a[:] = 123.0
    info_a["ground_truth"]["cof"] = -1.0
    info_a["measurement"].clear()
    next_a, next_b = a.step(QUIET), b.step(QUIET)
    assert_same(next_a, next_b)
    assert not np.shares_memory(next_a[0], obs_a)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_the_task_owns_the_horizon(env_id: str) -> None:
    """The spec carries the task's horizon: the env truncates itself after max_windows windows, at the
    same step as gym.make's TimeLimit."""
    env = gym.make(env_id, window_s=0.5)
    assert env.spec.max_episode_steps == env.unwrapped.task.max_windows == DEFAULT_MAX_WINDOWS
    env.reset(seed=0, options={"cof": 0.3})
    for i in range(1, DEFAULT_MAX_WINDOWS + 1):
        _, _, terminated, truncated, info = env.step(QUIET)
        assert not terminated
        assert truncated == (i == DEFAULT_MAX_WINDOWS)
    assert info["relative_error"] == pytest.approx(abs(estimate_of(0.0) - 0.3) / 0.3)
    with pytest.raises(RuntimeError, match="reset"):
        env.step(QUIET)  # the episode has ended


def test_make_with_longer_max_windows_scores_at_its_horizon() -> None:
    """A longer max_windows moves the TimeLimit with it (make_kwargs adds max_episode_steps)."""
    from cof_gym.envs.torque_interrogation import make_kwargs

    env = gym.make(HALF, **make_kwargs({"max_windows": 40, "window_s": 0.5}))
    env.reset(seed=0, options={"cof": 0.3})
    for i in range(1, 41):
        _, _, terminated, truncated, info = env.step(QUIET)
        if terminated or truncated:
            break
    assert (i, truncated) == (40, True)
    assert "relative_error" in info


# ---------------------------------------------------------------------------- 4. scenario overrides
FIXED = {"cof": 0.3, "condition": "wet", "speed_m_s": 20.0, "load_case": "empty", "noise_level": 0.0,
         "motor_lag_s": 0.0}


def fixed_for(env_id: str) -> dict:
    # the half wheelset is the paper's laden wheel: "laden" is its only load case
    return {**FIXED, "load_case": "laden"} if "HalfWheelset" in env_id else dict(FIXED)


def assert_ground_truth(info: dict, expected: dict) -> None:
    gt = info["ground_truth"]
    for key, value in expected.items():
        assert gt[key] == value, f"ground_truth[{key!r}] = {gt[key]!r}, expected {value!r}"


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_constructor_kwargs_fix_the_scenario(env_id: str) -> None:
    fixed = fixed_for(env_id)
    env = gym.make(env_id, **SHORT, **fixed)
    for seed in (0, 1, 2):
        _, info = env.reset(seed=seed)
        assert_ground_truth(info, fixed)
        _, _, _, _, info = env.step(QUIET)
        assert_ground_truth(info, fixed)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_reset_options_fix_the_scenario(env_id: str) -> None:
    fixed = fixed_for(env_id)
    env = gym.make(env_id, **SHORT)
    for seed in (0, 1):
        _, info = env.reset(seed=seed, options=fixed)
        assert_ground_truth(info, fixed)
    # options override constructor kwargs for one episode only
    env = gym.make(env_id, **SHORT, cof=0.3)
    _, info = env.reset(seed=0, options={"cof": 0.2, "speed_m_s": 10.0})
    assert_ground_truth(info, {"cof": 0.2, "speed_m_s": 10.0})
    _, info = env.reset(seed=0)
    assert info["ground_truth"]["cof"] == 0.3 and info["ground_truth"]["speed_m_s"] != 10.0


def test_fixing_one_field_leaves_the_other_draws_unchanged() -> None:
    free, pinned = gym.make(WAGON, **SHORT), gym.make(WAGON, **SHORT, cof=0.3)
    for seed in (0, 1, 2, 3):
        gt_free = free.reset(seed=seed)[1]["ground_truth"]
        gt_pinned = pinned.reset(seed=seed)[1]["ground_truth"]
        for key in ("condition", "speed_m_s", "load_case", "noise_level", "motor_lag_s"):
            assert gt_free[key] == gt_pinned[key], key


def test_wagon_load_cases_both_reachable() -> None:
    env = gym.make(WAGON, **SHORT)
    seen = {env.reset(seed=s)[1]["ground_truth"]["load_case"] for s in range(12)}
    assert seen == {"empty", "laden"}


BAD_KWARGS = [
    ("cof", -1.0), ("cof", 0.0), ("cof", math.nan), ("speed_m_s", 0.0), ("speed_m_s", math.inf),
    ("condition", "icy"), ("load_case", "x"), ("noise_level", -1.0), ("window_s", 0.0), ("max_windows", 0),
    ("max_windows", 2.5), ("w_error", -1.0), ("w_slip", math.nan), ("macro_slip_creepage", 0.0),
    ("vehicle", "bus"), ("render_mode", "ascii"),
]


@pytest.mark.parametrize(("field", "value"), BAD_KWARGS, ids=[f"{f}={v!r}" for f, v in BAD_KWARGS])
def test_invalid_constructor_kwarg_raises_naming_the_field(field: str, value) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # gym.make's own warning about an undeclared render mode
        unknown_name = field == "macro_slip_creepage"  # not an argument: a TypeError, as Python's
        with pytest.raises(TypeError if unknown_name else ValueError, match=re.escape(field)):
            gym.make(HALF, **{field: value})


BAD_OPTIONS = [("cof", -1.0), ("speed_m_s", 0.0), ("condition", "icy"), ("load_case", "x"),
               ("noise_level", -1.0), ("motor_lag_s", -1.0), ("motor_lag_s", math.nan)]


@pytest.mark.parametrize(("field", "value"), BAD_OPTIONS, ids=[f"{f}={v!r}" for f, v in BAD_OPTIONS])
def test_invalid_reset_option_raises_naming_the_field(field: str, value) -> None:
    env = gym.make(WAGON, **SHORT)
    # a valid reset first: gymnasium 1.4's PassiveEnvChecker breaks (TypeError on the first step) when
    # the very first reset raises, which is not the env's doing
    env.reset(seed=1)
    with pytest.raises(ValueError, match=re.escape(field)):
        env.reset(seed=0, options={field: value})
    # the env stays usable after the rejected reset
    obs, _ = env.reset(seed=0)
    assert np.isfinite(env.step(QUIET)[0]).all() and np.isfinite(obs).all()


def test_unknown_kwarg_and_option_raise_naming_them() -> None:
    """A wrong constructor argument name is a TypeError (as Python's); a wrong reset option a ValueError."""
    with pytest.raises(TypeError, match="friction"):
        gym.make(HALF, friction=0.3)
    env = gym.make(HALF, **SHORT)
    with pytest.raises(ValueError, match="friction"):
        env.reset(seed=0, options={"friction": 0.3})


@pytest.mark.parametrize("value", [-1.0, 2.0, math.nan])
def test_invalid_motor_lag_kwarg_raises_at_construction(value: float) -> None:
    with pytest.raises(ValueError, match="motor_lag_s"):
        gym.make(HALF, motor_lag_s=value)


def test_half_wheelset_refuses_the_empty_load_case() -> None:
    """The half wheelset has the laden load only: an empty one is refused, naming load_case (never played laden)."""
    with pytest.raises(ValueError, match=r"load_case must be one of \['laden'\]"):
        gym.make(HALF, **SHORT, load_case="empty")


# ------------------------------------------------------------------------------------ 5. bad input
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf], ids=["nan", "inf", "-inf"])
@pytest.mark.parametrize("index", range(5), ids=ACTION_NAMES)
def test_non_finite_action_raises_naming_the_component(index: int, bad: float) -> None:
    a, b = make_pair(HALF, seed=2)
    action = QUIET.copy()
    action[index] = bad
    with pytest.raises(ValueError, match=ACTION_NAMES[index]) as exc:
        a.step(action)
    for other in set(ACTION_NAMES) - {ACTION_NAMES[index]}:
        assert f"'{other}'" not in str(exc.value)
    # the rejected action left no trace: the env continues like an untouched twin
    assert_same(a.step(QUIET), b.step(QUIET))


def test_several_non_finite_components_are_all_named() -> None:
    env = gym.make(HALF, **SHORT)
    env.reset(seed=0)
    with pytest.raises(ValueError) as exc:
        env.step(np.array([math.nan, 0.0, math.inf, 0.0, -math.inf]))
    for name in ("dc_torque", "frequency", "stop"):
        assert name in str(exc.value)


@pytest.mark.parametrize("shape", [(4,), (6,), (5, 2)])
def test_wrong_action_shape_raises(shape: tuple) -> None:
    env = gym.make(HALF, **SHORT)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(shape, np.float32))


@pytest.mark.parametrize("sign", [1.0, -1.0], ids=["high", "low"])
@pytest.mark.parametrize("index", range(5), ids=ACTION_NAMES)
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_out_of_range_action_is_clipped(env_id: str, index: int, sign: float) -> None:
    base = np.array([-0.5, 0.1, 0.2, 0.3, -0.5], np.float32)
    for outside in (5.0, 1e6):
        a, b = make_pair(env_id, seed=11)
        wild, clipped = base.copy(), base.copy()
        wild[index], clipped[index] = sign * outside, sign
        assert_same(a.step(wild), b.step(clipped))


@pytest.mark.parametrize("env_id", ENV_IDS)
@pytest.mark.parametrize("estimate_action", [-0.5, -0.25, 0.0, 0.2])
def test_stop_terminates_and_scores_the_estimate(env_id: str, estimate_action: float) -> None:
    cof = 0.3
    env = gym.make(env_id, **SHORT, cof=cof)
    env.reset(seed=1)
    env.step(QUIET)
    action = QUIET.copy()
    action[3], action[4] = estimate_action, 1.0
    _, reward, terminated, truncated, info = env.step(action)
    estimate = estimate_of(estimate_action)
    assert terminated and not truncated and not info["macro_slip"]
    assert info["cof_estimate"] == pytest.approx(estimate, rel=1e-12, abs=1e-15)
    assert info["relative_error"] == pytest.approx(abs(estimate - cof) / cof, rel=1e-9, abs=1e-12)
    assert info["log_error"] == pytest.approx(abs(math.log(estimate / cof)), rel=1e-9, abs=1e-12)
    assert info["reward_error"] == pytest.approx(-10.0 * abs(math.log(estimate / cof)), rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_a_stop_runs_no_window(env_id: str) -> None:
    """Stopping scores the estimate at once: no time, slip or comfort cost, the simulation does not
    advance, and the observation is the last window's."""
    env = gym.make(env_id, **SHORT, cof=0.3)
    env.reset(seed=1)
    obs, _, _, _, window_info = env.step(QUIET)
    time_before = env.unwrapped._sim.data.time
    stop = np.array([1.0, 1.0, 0.0, 0.0, 1.0], np.float32)  # full DC torque with the stop: never applied
    obs2, reward, terminated, truncated, info = env.step(stop)
    assert terminated and not truncated and not info["macro_slip"]
    assert env.unwrapped._sim.data.time == time_before and np.array_equal(obs, obs2)
    assert (info["reward_time"], info["reward_slip"], info["reward_comfort"]) == (0.0, 0.0, 0.0)
    assert reward == info["reward_error"] == pytest.approx(-10.0 * abs(math.log(estimate_of(0.0) / 0.3)))
    # the elapsed time does not grow, and the readings are the last window's (the docstring: sums skip such a step)
    assert info["elapsed_s"] == window_info["elapsed_s"] == SHORT["window_s"]
    assert info["measurement"] == window_info["measurement"]


def test_stop_threshold_is_strictly_positive() -> None:
    env = gym.make(HALF, **SHORT)
    env.reset(seed=0)
    action = QUIET.copy()
    action[4] = 0.0
    assert not env.step(action)[2]
    action[4] = 1e-6
    assert env.step(action)[2]


def test_scored_error_is_symmetric_in_ratio_and_not_capped() -> None:
    """A factor k over costs what a factor k under costs, and a larger factor always costs more."""
    costs = {}
    for estimate_action in (-1.0, -0.5, 0.5, 1.0):  # estimates 0.01, 0.0316, 0.316, 1.0 for CoF 0.1
        env = gym.make(HALF, **SHORT, cof=0.1)
        env.reset(seed=0)
        action = QUIET.copy()
        action[3], action[4] = estimate_action, 1.0
        _, _, terminated, _, info = env.step(action)
        assert terminated
        costs[estimate_action] = info["reward_error"]
    assert costs[-1.0] == pytest.approx(costs[1.0], rel=1e-6) == pytest.approx(-10.0 * math.log(10.0), rel=1e-6)
    assert costs[-0.5] == pytest.approx(costs[0.5], rel=1e-6)
    assert costs[1.0] < costs[0.5] < 0.0


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_truncation_scores_the_last_estimate(env_id: str) -> None:
    cof = 0.3
    env = gym.make(env_id, **SHORT, cof=cof)
    env.reset(seed=2)
    estimates = [-0.9, 0.5, -0.4, 0.05]
    for i, e in enumerate(estimates, start=1):
        action = QUIET.copy()
        action[3] = e
        _, _, terminated, truncated, info = env.step(action)
        assert not terminated
        assert truncated == (i == len(estimates))
        if i < len(estimates):
            assert "relative_error" not in info and "log_error" not in info and info["reward_error"] == 0.0
    last = estimate_of(estimates[-1])
    assert info["relative_error"] == pytest.approx(abs(last - cof) / cof, rel=1e-9)
    assert info["reward_error"] == pytest.approx(-10.0 * abs(math.log(last / cof)), rel=1e-9)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_saturating_drive_ends_in_macro_slip(env_id: str) -> None:
    full_dc = np.array([1.0, -1.0, 0.0, 0.0, -1.0], np.float32)
    results = {}
    for penalty in (5.0, 0.0):
        env = gym.make(env_id, **SHORT, cof=0.05, macro_slip_penalty=penalty)
        env.reset(seed=0)
        for _ in range(SHORT["max_windows"]):
            _, reward, terminated, truncated, info = env.step(full_dc)
            if terminated or truncated:
                break
        results[penalty] = (reward, info)
        assert info["macro_slip"] and terminated and not truncated and not info["diverged"]
        assert reward < 0.0
        assert info["reward_error"] == pytest.approx(-10.0 * abs(math.log(estimate_of(0.0) / 0.05)))  # scored
        assert info["reward_slip"] <= -penalty
        gt = info["ground_truth"]
        assert gt["max_abs_creepage"] > gt["macro_slip_creepage"] > gt["peak_creepage"]
        assert reward == pytest.approx(sum(info[k] for k in REWARD_KEYS), rel=1e-12)
    # the penalty is exactly the difference between the two otherwise identical episodes
    assert results[5.0][0] - results[0.0][0] == pytest.approx(-5.0, rel=1e-9)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_reward_terms_sum_to_the_reward(env_id: str) -> None:
    env = gym.make(env_id, **SHORT)
    weights = env.unwrapped.task.reward
    for seed in range(6):
        steps = rollout(env, seed, allow_stop=seed % 2 == 1)
        elapsed = [step[-1]["elapsed_s"] for step in steps]  # a step that ran a window took window_s
        for item, before in zip(steps[1:], elapsed):
            obs, reward, _, _, info = item
            assert isinstance(reward, float) and math.isfinite(reward)
            assert env.observation_space.contains(obs)
            terms = {k: v for k, v in info.items() if k.startswith("reward_")}
            assert set(terms) == set(REWARD_KEYS)
            assert all(v <= 0.0 for v in terms.values()), terms
            assert reward == pytest.approx(sum(terms.values()), rel=1e-12, abs=1e-12)
            cost = info["cost"]
            assert cost["slip"] >= 0.0 and cost["discomfort"] >= 0.0
            penalty = weights.macro_slip_penalty if info["macro_slip"] else 0.0
            assert info["reward_slip"] == pytest.approx(-weights.w_slip * cost["slip"] - penalty, rel=1e-12, abs=1e-12)
            assert info["reward_comfort"] == pytest.approx(-weights.w_comfort * cost["discomfort"], rel=1e-12, abs=1e-12)
            window_run = info["elapsed_s"] > before  # read from the clock, not from the term under test
            assert window_run == (info["elapsed_s"] == pytest.approx(before + SHORT["window_s"], rel=1e-12))
            assert info["reward_time"] == pytest.approx(-weights.w_time * SHORT["window_s"] * window_run, rel=1e-12)


# ------------------------------------------------------------------------------------ 6. rendering
GL_PROBE = """
import mujoco
m = mujoco.MjModel.from_xml_string('<mujoco><worldbody><light pos="0 0 2"/><geom size=".1"/></worldbody></mujoco>')
r = mujoco.Renderer(m, 32, 32)
r.update_scene(mujoco.MjData(m))
assert r.render().shape == (32, 32, 3)
"""


def gl_environ(backend: str) -> dict:
    """This process's environment for a child rendering with ``backend`` (mujoco sets
    PYOPENGL_PLATFORM on import, which would pin the child to this process's backend)."""
    env = {k: v for k, v in os.environ.items() if k != "PYOPENGL_PLATFORM"}
    return {**env, "MUJOCO_GL": backend}


@pytest.fixture(scope="module")
def gl_backend() -> str:
    """The first MuJoCo GL backend (egl, then osmesa) that can render in a fresh process."""
    errors = []
    for backend in ("egl", "osmesa"):
        proc = subprocess.run([sys.executable, "-c", GL_PROBE], env=gl_environ(backend),
                              capture_output=True, text=True, timeout=120)
        if proc.returncode == 0:
            return backend
        errors.append(f"MUJOCO_GL={backend}: {proc.stderr.strip().splitlines()[-1:] }")
    pytest.skip("no MuJoCo GL backend can initialise: " + "; ".join(errors))


def render_frame(env_id: str, width: int, height: int) -> tuple[np.ndarray, float]:
    """An rgb_array frame after reset and one step, and the fraction of its pixels that show the vehicle
    (a segmentation render through the env's own renderer and camera: geoms of any body but the world)."""
    import mujoco

    env = gym.make(env_id, render_mode="rgb_array", width=width, height=height, **SHORT)
    env.reset(seed=0)
    env.step(np.array([0.0, 0.0, 0.0, 0.0, -1.0], np.float32))
    frame = env.render()
    model = env.unwrapped._sim.model
    renderer = env.unwrapped._renderers[id(model)]
    renderer.enable_segmentation_rendering()
    try:
        seg = env.render()
    finally:
        renderer.disable_segmentation_rendering()
    env.close()
    ids, types = seg[..., 0], seg[..., 1]
    geom = (types == mujoco.mjtObj.mjOBJ_GEOM) & (ids >= 0)
    vehicle = np.zeros_like(geom)
    vehicle[geom] = model.geom_bodyid[ids[geom]] != 0
    return frame, float(vehicle.mean())


def rendered(env_id: str, gl_backend: str, tmp_path: Path, width: int, height: int) -> tuple[np.ndarray, float]:
    if os.environ.get("MUJOCO_GL") == gl_backend:
        return render_frame(env_id, width, height)
    # this process is bound to another backend: render in a child using the working one
    out = tmp_path / "frame.npz"
    code = (f"import sys, numpy as np; sys.path[:0] = [{str(Path(__file__).parent)!r}]; "
            f"from test_envs import render_frame; "
            f"frame, fraction = render_frame({env_id!r}, {width}, {height}); "
            f"np.savez({str(out)!r}, frame=frame, fraction=fraction)")
    proc = subprocess.run([sys.executable, "-c", code], env=gl_environ(gl_backend),
                          capture_output=True, text=True, timeout=120, cwd=Path(__file__).parents[1])
    assert proc.returncode == 0, proc.stderr
    with np.load(out) as data:
        return data["frame"], float(data["fraction"])


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_rgb_array_frame(env_id: str, gl_backend: str, tmp_path: Path) -> None:
    width, height = 160, 96  # not the defaults, and not square (catches swapped dimensions)
    frame, _ = rendered(env_id, gl_backend, tmp_path, width, height)
    assert isinstance(frame, np.ndarray)
    assert frame.shape == (height, width, 3) and frame.dtype == np.uint8
    assert float(frame.std()) > 1.0, "blank frame"


@pytest.mark.parametrize("env_id", [
    WAGON,
    HALF,
])
def test_rendered_frame_shows_the_vehicle(env_id: str, gl_backend: str, tmp_path: Path) -> None:
    _, vehicle_fraction = rendered(env_id, gl_backend, tmp_path, 160, 96)
    assert vehicle_fraction > 0.01, f"the vehicle covers {vehicle_fraction:.1%} of the frame"


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_check_env_render_modes(env_id: str, gl_backend: str) -> None:
    """gymnasium's render checks of every declared mode; without a display the only warning is the
    documented one of render_mode='human'."""
    if os.environ.get("MUJOCO_GL") != gl_backend:
        pytest.skip(f"this process uses MUJOCO_GL={os.environ.get('MUJOCO_GL')!r}, which cannot render")
    allowed = () if display_available() else (HUMAN_NO_DISPLAY,)
    env = gym.make(env_id, render_mode="rgb_array").unwrapped
    with no_warnings(allowed=allowed):
        gym_check_env(env)
    env.close()


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_render_human_without_display(env_id: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    env = gym.make(env_id, render_mode="human", **SHORT)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        env.reset(seed=0)  # reset and step render in human mode
        first = env.render()
        second = env.render()
        obs, *_ = env.step(QUIET)
    assert first is None and second is None
    messages = [str(w.message) for w in caught]
    assert len(messages) == 1 and HUMAN_NO_DISPLAY in messages[0], messages
    assert np.isfinite(obs).all()
    env.close()


class FakeViewer:
    """mujoco.viewer's passive handle as the env uses it: the (model, data) it was launched on, syncs, close."""

    launched: list["FakeViewer"] = []

    def __init__(self, model, data) -> None:
        self.model, self.data, self.syncs, self.closed = model, data, 0, False
        FakeViewer.launched.append(self)

    def sync(self) -> None:
        self.syncs += 1

    def close(self) -> None:
        self.closed = True


def test_the_human_viewer_shows_each_episode_on_its_own_load_cases_model(monkeypatch: pytest.MonkeyPatch) -> None:
    """In render_mode='human' reset renders as well as step (as gymnasium's MuJoCo envs do), and an episode on
    the other load case (another model and data) gets a viewer of its own: the one launched on the first episode
    kept syncing that episode's data, a frozen picture."""
    import mujoco.viewer

    from cof_gym.envs import torque_interrogation

    monkeypatch.setattr(torque_interrogation, "display_available", lambda: True)
    monkeypatch.setattr(mujoco.viewer, "launch_passive", FakeViewer)
    FakeViewer.launched = []
    env = gym.make(cof_gym.WAGON_ENV_ID, render_mode="human", **SHORT)
    env.reset(seed=0, options={"load_case": "empty"})
    first = FakeViewer.launched[-1]
    assert first.syncs == 1 and first.data is env.unwrapped._sim.data
    env.step(QUIET)
    assert first.syncs == 2 and len(FakeViewer.launched) == 1
    env.reset(seed=1, options={"load_case": "laden"})
    second = FakeViewer.launched[-1]
    assert first.closed and second is not first and second.data is env.unwrapped._sim.data
    assert second.model is not first.model
    env.close()
    assert second.closed


def test_rgb_array_builds_one_renderer_per_load_case(monkeypatch: pytest.MonkeyPatch) -> None:
    """A renderer is built once per model (about a second each): episodes alternating the load case built one
    at every switch and closed none of them; close() closes them all."""
    import mujoco

    built = []

    class FakeRenderer:
        def __init__(self, model, height: int, width: int) -> None:
            self.model, self.closed = model, False
            built.append(self)

        def update_scene(self, data, camera: str) -> None:
            pass

        def render(self) -> np.ndarray:
            return np.zeros((2, 2, 3), np.uint8)

        def close(self) -> None:
            self.closed = True

    monkeypatch.setattr(mujoco, "Renderer", FakeRenderer)
    env = gym.make(cof_gym.WAGON_ENV_ID, render_mode="rgb_array", **SHORT)
    for seed, load_case in enumerate(("empty", "laden") * 3):
        env.reset(seed=seed, options={"load_case": load_case})
        env.render()
        assert built[-1 if load_case == "laden" else 0].model is env.unwrapped._sim.model
    assert len(built) == 2
    env.close()
    assert all(r.closed for r in built)


def test_an_episode_cut_unscored_at_the_registered_time_limit_is_a_warning() -> None:
    """gym.make(id, max_windows=N) with N above the id's registered TimeLimit (30) truncates every episode at
    step 30, before the task's horizon scores the estimate: the next reset warns once, naming the fix; with
    max_episode_steps=N the episode runs to its horizon and is scored, with no warning."""
    limit = gym.spec(HALF).max_episode_steps
    kwargs = {"max_windows": limit + 2, "window_s": 0.2}
    env = gym.make(HALF, **kwargs)
    env.reset(seed=0)
    for _ in range(limit):
        _, _, terminated, truncated, info = env.step(QUIET)
    assert truncated and not terminated and "relative_error" not in info
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        env.reset(seed=1)
        env.reset(seed=2)  # once an env
    messages = [str(w.message) for w in caught]
    assert len(messages) == 1, messages
    assert f"ended unscored at step {limit}" in messages[0]
    assert f"max_windows={limit + 2}, max_episode_steps={limit + 2}" in messages[0]
    env = gym.make(HALF, max_episode_steps=limit + 2, **kwargs)
    env.reset(seed=0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(limit + 2):
            _, _, terminated, truncated, info = env.step(QUIET)
        env.reset(seed=1)
    assert truncated and "relative_error" in info and not caught


# --------------------------------------------------------------------------------------- 7. PPO
def test_ppo_smoke() -> None:
    from stable_baselines3 import PPO

    env = gym.make(HALF, max_windows=5)
    model = PPO("MlpPolicy", env, n_steps=100, batch_size=50, n_epochs=1, seed=0, device="cpu")
    model.learn(200)
    assert model.num_timesteps == 200
    obs, _ = env.reset(seed=0)
    action, _ = model.predict(obs, deterministic=True)
    assert env.action_space.contains(action)


@pytest.mark.parametrize("env_id", [WAGON, HALF])
def test_a_diverging_simulation_ends_the_episode_without_a_crash(env_id: str, tmp_path: Path,
                                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # MuJoCo's warning writes MUJOCO_LOG.TXT into the working directory
    env = gym.make(env_id)
    obs, _ = env.reset(seed=0)
    env.unwrapped._sim.data.qvel[:] = np.nan  # a blown-up state, as an unstable integration would leave
    obs2, reward, terminated, truncated, info = env.step(env.action_space.sample() * 0)
    assert info["diverged"] and terminated and not truncated
    assert np.isfinite(obs2).all() and np.isfinite(reward)
    assert reward <= -env.unwrapped.task.reward.macro_slip_penalty
    obs3, _ = env.reset(seed=1)  # the env recovers on reset
    assert np.isfinite(obs3).all()
    _, _, _, _, info = env.step(env.action_space.sample() * 0)
    assert not info["diverged"]
