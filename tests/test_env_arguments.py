"""Strict arguments: booleans are booleans, numbers are finite real numbers, options of the wrong type
get a ValueError naming field, type and range; actions of the wrong shape or dtype are refused; the
timestep range is stable; an env whose reset failed refuses to step."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.task.task import TIMESTEP_RANGE_S

WAGON, HALF = cof_gym.WAGON_ENV_ID, cof_gym.HALF_WHEELSET_ENV_ID
SHORT = {"max_windows": 3, "window_s": 0.5}


@pytest.mark.parametrize("field", ["counter_torque", "shaping", "traction_balance"])
@pytest.mark.parametrize("value", ["false", "True", 0, 1, 1.0, "no"])
def test_string_and_number_booleans_are_refused(field: str, value) -> None:
    with pytest.raises(ValueError, match=f"{field} must be a bool"):
        gym.make(WAGON, **{field: value})


@pytest.mark.parametrize("field,value,fragment", [
    ("cof", "0.3", "cof must be a number"),
    ("cof", True, "cof must be a number"),
    ("cof", float("nan"), "cof must be a finite number"),
    ("cof", 0.9, r"cof must be a finite number in \[0.02, 0.6\]"),
    pytest.param("cof", 10**400, r"cof must be a finite number in \[0.02, 0.6\], got 1000", id="cof-int-beyond-float"),
    pytest.param("speed_m_s", -10**400, r"speed_m_s must be a finite number in \[5, 40\] m/s, got -1000",
                 id="speed-int-beyond-float"),
    ("speed_m_s", 2.0, r"speed_m_s must be a finite number in \[5, 40\] m/s"),
    ("noise_level", 1e9, r"noise_level must be a finite number in \[0, 3\]"),
    ("motor_lag_s", -0.1, "motor_lag_s must be a finite number"),
    ("condition", "icy", "condition must be one of"),
    ("condition", 3, "condition must be one of"),
    ("load_case", "half", "load_case must be one of"),
])
def test_wrong_typed_or_out_of_range_options_name_the_field(field: str, value, fragment: str) -> None:
    env = gym.make(WAGON, **SHORT)
    with pytest.raises(ValueError, match=fragment):
        env.reset(seed=0, options={field: value})
    with pytest.raises(ValueError, match=fragment):
        gym.make(WAGON, **{field: value})


@pytest.mark.parametrize("field,value", [
    ("window_s", "1"), ("window_s", True), ("max_windows", 3.0), ("max_windows", True), ("w_error", -1.0),
    ("w_time", float("inf")), ("width", 8), ("ranges", "x"), ("timestep", 5e-3), ("macro_slip_ratio", 1.0),
    ("vehicle", "tram"), ("render_mode", "video"),
])
def test_bad_constructor_arguments_raise_naming_them(field: str, value) -> None:
    with pytest.raises(ValueError, match=field if field not in ("w_error", "w_time", "macro_slip_ratio") else
                       {"w_error": "w_error", "w_time": "w_time", "macro_slip_ratio": "macro_slip ratio"}[field]):
        gym.make(WAGON, **{field: value})


@pytest.mark.parametrize("action", [
    np.zeros((1, 5), np.float32), np.zeros((5, 1), np.float32), np.zeros(4, np.float32),
    np.zeros(5, bool), np.zeros(5, complex), np.array(["0"] * 5), [0.0, 0.0, 0.0, 0.0, float("nan")],
])
def test_wrong_action_shapes_and_dtypes_are_refused(action) -> None:
    env = gym.make(WAGON, **SHORT)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action"):
        env.step(action)


def test_a_failed_reset_leaves_an_env_that_refuses_to_step() -> None:
    env = gym.make(WAGON, **SHORT)
    env.reset(seed=0)
    env.step(np.zeros(5, np.float32))
    with pytest.raises(ValueError, match="cof"):
        env.reset(seed=1, options={"cof": "0.3"})
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(5, np.float32))
    env.reset(seed=1)  # and a good reset recovers
    env.step(np.zeros(5, np.float32))


@pytest.mark.parametrize("env_id", [WAGON, HALF])
def test_the_largest_allowed_timestep_is_stable(env_id: str) -> None:
    """At the top of the timestep range the simulation neither diverges nor reports a spurious
    macro-slip, at the stiffest contact (dry, high CoF, low speed) and the softest."""
    for options in ({"cof": 0.6, "condition": "dry", "speed_m_s": 5.0, "load_case": "laden"},
                    {"cof": 0.02, "condition": "low_adhesion", "speed_m_s": 40.0, "load_case": "laden"}):
        env = gym.make(env_id, timestep=TIMESTEP_RANGE_S[1], **SHORT)
        env.reset(seed=0, options=options)
        for _ in range(2):
            _, reward, terminated, _, info = env.step(np.array([-1.0, 0.0, 0.0, 0.0, -1.0], np.float32))
            assert not terminated and not info["diverged"] and not info["macro_slip"] and np.isfinite(reward)
