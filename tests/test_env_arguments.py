"""Strict arguments: booleans are booleans, numbers are finite real numbers, options of the wrong type
get a ValueError naming field, type and range; numpy scalars are stored as the Python numbers they hold;
actions of the wrong shape or dtype are refused; the timestep range is stable; an env whose reset failed
refuses to step."""

from __future__ import annotations

import json
import math
import re
from dataclasses import replace

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.physics.contact_geometry import ContactGeometry
from cof_gym.physics.creep import OperatingConditions
from cof_gym.physics.creep_laws import PolachShape
from cof_gym.physics.simulation import DriveCommand
from cof_gym.task.scenarios import V2_RANGES, ScenarioRanges, draw_scenario
from cof_gym.task.task import TIMESTEP_RANGE_S, InterrogationTask
from cof_gym.validation import check_bool, check_int, check_number

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
    ("window_s", "1"), ("window_s", True), ("window_s", np.True_), ("max_windows", 3.0), ("max_windows", True),
    ("max_windows", np.True_), ("w_error", -1.0), ("w_time", float("inf")), ("width", 8), ("ranges", "x"),
    ("timestep", 5e-3), ("macro_slip_ratio", 1.0), ("macro_slip_ratio", 0.5), ("macro_slip_floor", -1.0),
    ("macro_slip_floor", np.False_), ("vehicle", "tram"), ("render_mode", "video"),
])
@pytest.mark.filterwarnings("ignore:.*render_mode='video' that is not in the possible render_modes")  # gym.make's
def test_bad_constructor_arguments_raise_naming_them(field: str, value) -> None:
    with pytest.raises(ValueError, match=f"^{field} must be"):  # the argument's own name, first
        gym.make(WAGON, **{field: value})


@pytest.mark.parametrize("low,high,low_open,high_open,bad,allowed", [
    (0.0, math.inf, True, False, 0.0, "> 0"),
    (0.0, math.inf, False, False, -1.0, ">= 0"),
    (-math.inf, 1.0, False, True, 1.0, "< 1"),
    (-math.inf, 1.0, False, False, 2.0, "<= 1"),
    (-math.inf, math.inf, False, False, math.inf, ""),
    (0.0, 1.0, True, True, 1.0, "in (0, 1)"),
])
def test_a_range_with_an_infinite_end_is_written_as_its_bound(low, high, low_open, high_open, bad, allowed) -> None:
    """An open side is no bound at all (never "in [0, inf]"), and an infinite value still fails: only finite pass."""
    with pytest.raises(ValueError, match=re.escape(f"x must be a finite number{' ' + allowed if allowed else ''} "
                                                   f"N, got {bad!r}")):
        check_number("x", bad, low, high, low_open=low_open, high_open=high_open, unit=" N")
    with pytest.raises(ValueError, match=re.escape(f"x must be a number{' ' + allowed if allowed else ''} N, got '1'")):
        check_number("x", "1", low, high, low_open=low_open, high_open=high_open, unit=" N")


@pytest.mark.parametrize("make, message", [
    (lambda: OperatingConditions(cof=True), "cof must be a number in [0.001, 1.5], got True (bool)"),
    (lambda: OperatingConditions(cof=0.3, speed_m_s=-1.0), "speed_m_s must be a finite number > 0 m/s, got -1.0"),
    (lambda: PolachShape(k_adhesion=1.0, k_slip="0.4", friction_ratio=0.4, friction_decay_s_per_m=0.6),
     "k_slip must be a number in (0, 100], got '0.4' (str)"),
    (lambda: ContactGeometry(poisson_ratio=0.5), "poisson_ratio must be a finite number in (0, 0.5), got 0.5"),
    (lambda: DriveCommand(1000.0, float("nan"), 5.0), "amplitude_nm must be a finite number >= 0 N m, got nan"),
    # a numpy bool, written as the installed numpy writes it
    (lambda: DriveCommand(1000.0, 100.0, np.True_), "frequency_hz must be a number in [0.1, 100] Hz, got "),
])
def test_the_physics_layer_checks_its_arguments_as_the_env_does(make, message: str) -> None:
    """One check for every layer (cof_gym.validation): a bool, a string or a NaN built straight into the physics
    is refused with the field, the range and the value, as at the env's door."""
    with pytest.raises(ValueError, match="^" + re.escape(message)):
        make()


def test_numpy_booleans_are_booleans_and_never_numbers() -> None:
    assert check_bool("x", np.True_) is True and check_bool("x", np.False_) is False
    for check in (lambda v: check_number("x", v, 0.0, 2.0), lambda v: check_int("x", v, 0, 2)):
        for value in (True, np.True_, np.False_):
            with pytest.raises(ValueError, match="x must be"):
                check(value)
    task = gym.make(WAGON, counter_torque=np.True_, shaping=np.False_, traction_balance=np.False_).unwrapped.task
    assert (task.counter_torque, task.shaping, task.traction_balance) == (True, False, False)
    assert all(type(v) is bool for v in (task.counter_torque, task.shaping, task.traction_balance))


@pytest.mark.parametrize("env_id", [HALF, cof_gym.HALF_WHEELSET_V1_ENV_ID])
@pytest.mark.parametrize("value", [True, np.True_])
def test_counter_torque_needs_a_second_wheelset(env_id: str, value) -> None:
    """The half wheelset has no other wheelset to take the counter torque: refused, as traction_balance is."""
    with pytest.raises(ValueError, match=r"^counter_torque=True needs the wagon"):
        gym.make(env_id, counter_torque=value)
    with pytest.raises(ValueError, match=r"^counter_torque=True needs the wagon"):
        gym.make_vec(env_id, num_envs=1, vectorization_mode="vector_entry_point", counter_torque=value)
    assert gym.make(env_id, counter_torque=False).unwrapped.task.counter_torque is False


def _run(**kwargs):
    """Reset and one scored step (max_windows=1) of the half wheelset: observations, reward, info, task."""
    env = gym.make(HALF, max_windows=1, **kwargs)
    obs, info0 = env.reset(seed=3)
    obs1, reward, terminated, truncated, info = env.step(np.array([-0.5, 0.1, 0.0, 0.0, -1.0], np.float32))
    assert (terminated or truncated) and info["scored"]
    return obs.tobytes() + obs1.tobytes(), reward, (info0, info), env.unwrapped.task


def test_numpy_scalars_compute_as_the_python_numbers_they_hold() -> None:
    """np.float32(0.3) is stored as float(np.float32(0.3)): the same episode, bit for bit, and a JSON info;
    a numpy int as the int. (Stored unconverted, a float32 made settle_s 0.120000005 and other rewards.)"""
    numpy_args = {"window_s": np.float32(0.3), "settle_fraction": np.float32(0.4), "ramp_fraction": np.float16(0.25),
                  "timestep": np.float32(1e-3), "w_error": np.float32(10.1), "w_slip": np.float32(1.5),
                  "w_comfort": np.float32(0.05), "w_time": np.float32(0.02), "macro_slip_penalty": np.float32(10.0),
                  "macro_slip_ratio": np.float32(2.5), "macro_slip_floor": np.float32(0.03),
                  "tones": np.int32(3), "width": np.int64(64), "task_version": np.int64(2)}
    a_obs, a_reward, a_infos, task = _run(**numpy_args)
    b_obs, b_reward, b_infos, _ = _run(**{k: v.item() for k, v in numpy_args.items()})
    assert a_obs == b_obs and np.float64(a_reward).tobytes() == np.float64(b_reward).tobytes()
    assert json.dumps(a_infos) == json.dumps(b_infos)  # JSON-ready, and the same numbers
    for name in ("window_s", "settle_fraction", "ramp_fraction", "timestep"):
        assert type(getattr(task, name)) is float and getattr(task, name) == float(numpy_args[name])
    for name in ("w_error", "w_slip", "w_comfort", "w_time", "macro_slip_penalty"):
        assert type(getattr(task.reward, name)) is float
    assert type(task.macro_slip.ratio) is float and type(task.macro_slip.floor) is float
    assert type(task.tones) is int and type(task.signal.tones) is int
    assert task.settle_s == float(np.float32(0.4)) * float(np.float32(0.3))
    horizon = InterrogationTask(max_windows=np.int16(7)).max_windows
    assert type(horizon) is int and horizon == 7


def test_python_numbers_are_stored_unchanged() -> None:
    task = InterrogationTask(window_s=0.3, settle_fraction=0.1 + 0.2, max_windows=5)
    assert task.window_s == 0.3 and task.settle_fraction == 0.1 + 0.2 and type(task.max_windows) is int
    ranges = ScenarioRanges(speed_m_s=(5.5, 39.0))
    assert ranges.speed_m_s == (5.5, 39.0) and ranges.cof["wet"] == (0.05, 0.25)


def test_ranges_of_another_task_version_are_refused_not_quietly_used() -> None:
    """v1 ranges on a -v2 id would drop its creep-law families and sensor errors without a word."""
    v1_ranges, v2_ranges = ScenarioRanges(speed_m_s=(10.0, 20.0)), replace(V2_RANGES, speed_m_s=(10.0, 20.0))
    with pytest.raises(ValueError, match=r"ranges: .* task_version is 2 .*V2_RANGES"):
        gym.make(WAGON, ranges=v1_ranges)
    with pytest.raises(ValueError, match=r"ranges: .* task_version is 1"):
        gym.make(cof_gym.WAGON_V1_ENV_ID, ranges=v2_ranges)
    env = gym.make(WAGON, ranges=v2_ranges, **SHORT)  # the v2 draws, narrowed: families and sensor errors kept
    truths = [env.reset(seed=seed)[1]["ground_truth"] for seed in range(12)]
    assert {t["creep_family"] for t in truths} == set(V2_RANGES.creep_families)
    assert all(10.0 <= t["speed_m_s"] <= 20.0 for t in truths) and len({t["speed_sensor_error"] for t in truths}) == 12
    assert gym.make(cof_gym.WAGON_V1_ENV_ID, ranges=v1_ranges).unwrapped.task.ranges == v1_ranges


def test_numpy_scalars_in_the_ranges_draw_as_the_python_numbers_they_hold() -> None:
    f32 = np.float32
    as_numpy = ScenarioRanges(cof={"dry": (f32(0.15), f32(0.55))}, conditions=("dry",), speed_m_s=(f32(5), f32(40)),
                              noise_level=[f32(0.0), f32(1.0)], motor_lag_s=(f32(0.0), f32(0.03)),
                              sensor_error_scale=f32(1.0))
    as_python = ScenarioRanges(cof={"dry": (float(f32(0.15)), float(f32(0.55)))}, conditions=("dry",),
                               speed_m_s=(5.0, 40.0), noise_level=(0.0, 1.0), motor_lag_s=(0.0, float(f32(0.03))),
                               sensor_error_scale=1.0)
    assert as_numpy.cof == as_python.cof and as_numpy.speed_m_s == as_python.speed_m_s
    a = draw_scenario(np.random.default_rng(1), as_numpy, {}).to_dict()
    b = draw_scenario(np.random.default_rng(1), as_python, {}).to_dict()
    assert all(type(a[k]) is type(b[k]) for k in a) and json.dumps(a) == json.dumps(b)
    assert type(a["cof"]) is float  # (a float32 range drew a float32 CoF)


@pytest.mark.parametrize("options", ["dry", "", [], 0, ["cof"]])
def test_reset_options_must_be_a_dict(options) -> None:
    env = gym.make(WAGON, **SHORT)
    with pytest.raises(ValueError, match="options must be a dict"):
        env.reset(seed=0, options=options)


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


@pytest.mark.parametrize("seed", [True, False, -1, 1.5, "3", np.float64(2.0)])
def test_a_bad_reset_seed_is_refused_naming_it(seed):
    """Gymnasium alone would take True as seed 1 (the vector env refuses it): the single env refuses it too."""
    import gymnasium as gym

    import cof_gym

    env = gym.make(cof_gym.WAGON_ENV_ID)
    with pytest.raises(ValueError, match="seed must be None or an int >= 0"):
        env.reset(seed=seed)
    assert np.array_equal(env.reset(seed=np.int64(3))[0], env.reset(seed=3)[0])  # a numpy integer is the int it holds
    env.close()


def test_motor_limits_encode_action_and_decode_observation_refuse_what_would_turn_into_nan_or_true() -> None:
    """For scripted agents: an infinite limit made every DC torque encode to -1; a NaN went on as an action
    component; stop="no" was a stop; a short observation vector failed with an IndexError, a long one decoded."""
    from cof_gym.task.interface import (OBSERVATION_NAMES, MotorLimits, ObservationScales, decode_observation,
                                        encode_action)

    for args, fragment in (((math.inf,), "MotorLimits.max_dc_torque_nm must be a finite number > 0"),
                           (("1e4",), "MotorLimits.max_dc_torque_nm must be a number > 0"),
                           ((1e4, 0.46, 30.0, 20.0), "MotorLimits.min_amplitude_nm must be below max_amplitude_nm")):
        with pytest.raises(ValueError, match=re.escape(fragment)):
            MotorLimits(*args)
    limits = MotorLimits(1e4)
    assert type(MotorLimits(np.float32(1e4)).max_dc_torque_nm) is float
    for args, fragment in (((math.nan, 100.0, 5.0, 0.2, False), "dc_torque_nm must be a finite number"),
                           ((1e3, 100.0, 5.0, math.inf, False), "cof_estimate must be a finite number"),
                           ((1e3, 100.0, 5.0, 0.2, "no"), "stop must be a bool"),
                           ((1e3, 100.0, 5.0, 0.2, 1), "stop must be a bool")):
        with pytest.raises(ValueError, match=fragment):
            encode_action(*args, limits)
    assert encode_action(1e3, 100.0, 5.0, 0.2, np.bool_(True), limits)[4] == 1.0
    scales = ObservationScales(limits, 116.0, 1e5, 30.0)
    for length in (5, len(OBSERVATION_NAMES) + 6):
        with pytest.raises(ValueError, match=rf"a window observation has shape \({len(OBSERVATION_NAMES)},\)"):
            decode_observation(np.zeros(length), scales)


def test_the_env_make_task_and_the_task_dataclasses_default_every_argument_alike() -> None:
    """An env argument's default is written in the env's signature (its documented API), make_task's and the task's
    dataclasses (InterrogationTask, Reward, MacroSlipLimit): the four must agree, so that gym.make(id) and a task
    built from its parts are the same task."""
    import dataclasses
    import inspect

    from cof_gym.envs.torque_interrogation import TorqueInterrogationEnv, make_task
    from cof_gym.task.reward import MacroSlipLimit, Reward

    def defaults(function) -> dict:
        return {name: p.default for name, p in inspect.signature(function).parameters.items()
                if p.default is not inspect.Parameter.empty}

    def field_defaults(cls, rename=lambda name: name) -> dict:
        return {rename(f.name): f.default for f in dataclasses.fields(cls) if f.default is not dataclasses.MISSING}

    env, task = defaults(TorqueInterrogationEnv.__init__), defaults(make_task)
    assert {k: v for k, v in env.items() if k not in ("render_mode", "width", "height")} == task
    parts = {**field_defaults(InterrogationTask), **field_defaults(Reward),
             **field_defaults(MacroSlipLimit, lambda name: f"macro_slip_{name}")}
    shared = set(task) & set(parts)
    assert {"window_s", "max_windows", "w_error", "macro_slip_penalty", "macro_slip_ratio", "tones"} <= shared
    assert {k: task[k] for k in shared} == {k: parts[k] for k in shared}


def test_the_cruise_control_and_the_models_refuse_gains_and_steps_their_native_loop_cannot_take() -> None:
    """The cruise control's acceleration feedback acts one step late in the native loop, which diverges once kd nears
    the car body's mass: held below MAX_KD_MASS_RATIO (the default 0.5 passes); a model's step must sample the
    comfort filters above 200 Hz, so 5 ms is refused as 'timestep', not as a filter's sample rate."""
    from cof_gym.physics.models import build_half_wheelset
    from cof_gym.physics.simulation import MAX_KD_MASS_RATIO, CruiseControl

    assert CruiseControl().kd_mass_ratio == 0.5 < MAX_KD_MASS_RATIO
    for bad in ({"kd_mass_ratio": 0.9}, {"kd_mass_ratio": -0.1}, {"bandwidth_hz": 0.0}, {"integral_hz": math.nan}):
        with pytest.raises(ValueError, match=f"CruiseControl.{next(iter(bad))}"):
            CruiseControl(**bad)
    with pytest.raises(ValueError, match="timestep must be a finite number in"):
        build_half_wheelset(timestep=5e-3)


def test_window_reading_and_decode_observation_give_back_what_the_sensors_measured() -> None:
    """The readings an agent decodes (window_reading, decode_observation) are the window's sensor readings in
    info["measurement"] to the float32 observation's rounding (a relative 2**-24 of each, the scaling a factor
    exact to float64), the two decoders alike to the bit; an unknown name or a limit-scaled reading without the
    limits is a ValueError naming it."""
    import gymnasium as gym

    import cof_gym
    from cof_gym.task.interface import decode_observation, encode_action, window_reading

    env = gym.make(cof_gym.WAGON_ENV_ID)
    obs, info = env.reset(seed=3)
    task = env.unwrapped.task
    limits = task.limits
    obs, _, _, _, info = env.step(encode_action(0.2 * limits.max_dc_torque_nm, 400.0, 4.0, 0.2, False, limits))
    decoded = decode_observation(obs, task.scales(env.unwrapped.episode.built))
    m = info["measurement"]
    for name, field_name, measured in (("phase_lag", "phase_lag_deg", m["phase_lag_deg"]),
                                       ("phase_lag_se", "phase_lag_se_deg", m["phase_lag_se_deg"]),
                                       ("coa_measured", "coa_measured", m["coa_measured"]),
                                       ("creepage_measured", "creepage_measured", m["creepage_measured"]),
                                       ("speed", "speed_m_s", m["speed_measured_m_s"]),
                                       ("wd_rms", "wd_rms_m_s2", m["wd_rms_m_s2"]),
                                       ("jerk_rms", "jerk_rms_m_s3", m["jerk_rms_m_s3"]),
                                       ("dc_torque", "dc_torque_nm", 0.2 * limits.max_dc_torque_nm),
                                       ("frequency", "frequency_hz", 4.0)):
        reading = window_reading(obs, name, limits)
        assert reading == getattr(decoded, field_name), name
        assert reading == pytest.approx(measured, rel=2.0 ** -23, abs=1e-300), name
    assert decoded.normal_load_n == pytest.approx(m["normal_load_measured_n"], rel=2.0 ** -23)
    with pytest.raises(ValueError, match=r"window_reading: name must be one of .*'creepage_measured'.*got 'creep'"):
        window_reading(obs, "creep")
    with pytest.raises(ValueError, match=r"'dc_torque' is scaled by the drive's limits: pass limits="):
        window_reading(obs, "dc_torque")
    env.close()


def test_a_spec_with_ranges_comes_back_from_its_json_as_the_same_env() -> None:
    """EnvSpec.to_json writes ScenarioRanges as a dict of lists: gym.make of the spec read back refused it ("ranges
    must be a ScenarioRanges"); it now makes the same draws. A mapping with a field the ranges lack names it."""
    import dataclasses

    import gymnasium as gym
    from gymnasium.envs.registration import EnvSpec

    import cof_gym
    from cof_gym.task import V2_RANGES

    env = gym.make(cof_gym.WAGON_ENV_ID, ranges=dataclasses.replace(V2_RANGES, speed_m_s=(10.0, 20.0)))
    again = gym.make(EnvSpec.from_json(env.spec.to_json()))
    assert again.unwrapped.task.ranges == env.unwrapped.task.ranges
    assert env.reset(seed=4)[0].tobytes() == again.reset(seed=4)[0].tobytes()
    with pytest.raises(ValueError, match=r"ranges: unknown field\(s\) \['speed'\]; allowed: \['cof', "):
        gym.make(cof_gym.WAGON_ENV_ID, ranges={"speed": [10.0, 20.0]})


@pytest.mark.parametrize("lag_s", [1e-20, 1e-13])
def test_a_drive_lag_far_below_a_step_runs_as_no_lag(lag_s: float) -> None:
    """A motor_lag_s of 1e-20 s diverged the first window (SimulationDiverged from reset): the callback divided the
    torque's rounding error by it. Below MIN_MOTOR_LAG_S (1e-12 s) it runs as none, window for window."""
    import gymnasium as gym

    import cof_gym

    runs = []
    for lag in (lag_s, 0.0):
        env = gym.make(cof_gym.HALF_WHEELSET_ENV_ID, max_windows=3, window_s=0.5)
        obs, _ = env.reset(seed=3, options={"motor_lag_s": lag})
        steps = [env.step(np.array([-0.9, -1.0, 0.0, 0.0, -1.0], np.float32)) for _ in range(2)]
        assert not any(info["diverged"] for *_, info in steps)
        runs.append([obs.tobytes(), *(o.tobytes() for o, *_ in steps)])
    assert runs[0] == runs[1]


def test_a_fixed_creep_law_is_played_where_it_has_a_peak() -> None:
    """A Polach law with a peak at 5 m/s and none at 20 or 40 m/s passed evaluate's check (one reset) and stopped
    the run with a NoPeakError at the first episode drawn faster. A draw where a fixed law has no peak is drawn
    again: every episode has a CoF, at a speed where the curve peaks; with the speed, load and CoF fixed where it
    has none, the reset is one ValueError naming the speed."""
    import gymnasium as gym

    import cof_gym
    from cof_gym.physics.creep import NoPeakError

    law = {"polach": {"k_adhesion": 1.0, "k_slip": 0.05, "friction_ratio": 0.9, "friction_decay_s_per_m": 1.0}}
    env = gym.make(cof_gym.WAGON_ENV_ID)
    speeds = []
    for seed in range(8):
        _, info = env.reset(seed=seed, options={"creep_law": law})
        truth = info["ground_truth"]
        assert 0.0 < truth["cof"] and 0.0 < truth["peak_creepage"] < 2.0
        speeds.append(env.unwrapped.episode.scenario.speed_m_s)
    assert max(speeds) < 20.0  # no peak at 20 m/s: such draws were drawn again
    with pytest.raises(NoPeakError, match=r"no maximum below creepage .* at speed_m_s=30\.0 .*"
                                          r"fix speed_m_s, load_case and cof where the curve has a peak"):
        env.reset(seed=0, options={"creep_law": law, "speed_m_s": 30.0})
    with pytest.raises(NoPeakError, match=r"at speed_m_s=30\.0 .*steeply with the slip velocity$"):
        env.reset(seed=0, options={"creep_law": law, "speed_m_s": 30.0, "load_case": "laden", "cof": 0.3,
                                   "condition": "dry"})
