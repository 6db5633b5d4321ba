"""cof_gym.agents.zeroed: the creepage zeroed at the reset window (no torque, no creep) is the true creepage up to the
observation's float32 rounding, and the agents that read it measure with a creepage offset as they do without one."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.registry import make_agent
from cof_gym.agents.zeroed import CREEPAGE, CreepageZeroed
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.task.interface import CREEPAGE_SCALE

# the creep curve's own scenario, no noise, no gain error: only the creepage's offset differs between the episodes
QUIET = {"noise_level": 0.0, "motor_lag_s": 0.0, "cof": 0.3, "condition": "dry", "creep_law": "dry", "speed_m_s": 20.0,
         "force_gain_error": 0.0, "torque_gain_error": 0.0}
OFFSETS = ({"speed_sensor_error": 0.015, "wheel_radius_error": -0.005},  # creepage offset about -2 %
           {"speed_sensor_error": -0.015, "wheel_radius_error": 0.005})  # about +2 %


@pytest.fixture(scope="module")
def env():
    environment = gym.make(cof_gym.WAGON_ENV_ID)
    yield environment
    environment.close()


def test_the_zeroed_creepage_is_the_true_creepage_up_to_the_observations_rounding(env):
    agent = make_agent("model-based-zeroed", env)
    zeroed = agent.agent  # inside the runaway estimate and the crest ceiling it is registered with
    assert isinstance(zeroed, CreepageZeroed) and agent.name == "model-based-zeroed" and not agent.oracle
    obs, info = env.reset(seed=3, options={**QUIET, **OFFSETS[0]})
    agent.reset(obs, info)
    assert zeroed.offset == pytest.approx(info["ground_truth"]["creepage_offset"], abs=1e-6)
    # each creepage is a float32 of at most 0.5 (x 10): two roundings of half a spacing, and the division's
    bound = 3 * float(np.spacing(np.float32(0.5))) / CREEPAGE_SCALE
    for _ in range(6):
        obs, _, terminated, truncated, info = env.step(agent.act(obs, info))
        true = info["ground_truth"]["creepage_mean"]
        assert abs(zeroed.zeroed(obs)[CREEPAGE] / CREEPAGE_SCALE - true) <= bound
        assert not (terminated or truncated)


@pytest.mark.parametrize("name", ["staircase", "model-based"])
def test_a_zeroed_agent_measures_with_a_creepage_offset_as_without_one_where_the_plain_one_runs_away(env, name):
    plain, zeroed = make_agent(name, env), make_agent(f"{name}-zeroed", env)
    reference = run_episode(env, zeroed, 3, {**QUIET, "speed_sensor_error": 0.0, "wheel_radius_error": 0.0}, 0)
    assert not reference.macro_slip
    for errors in OFFSETS:
        with_offset = run_episode(env, zeroed, 3, {**QUIET, **errors}, 0)
        assert not with_offset.macro_slip and with_offset.estimate == pytest.approx(reference.estimate, rel=1e-3)
        assert run_episode(env, plain, 3, {**QUIET, **errors}, 0).macro_slip


def _actions(env, name: str, seed: int) -> list[np.ndarray]:
    """Every action of the registered agent ``name`` in the default v2 episode ``seed``."""
    agent = make_agent(name, env)
    obs, info = env.reset(seed=seed)
    agent.reset(obs, info)
    out = []
    while True:
        out.append(agent.act(obs, info))
        obs, _, terminated, truncated, info = env.step(out[-1])
        if terminated or truncated:
            return out


@pytest.mark.parametrize("seed", [209, 211])
def test_the_jump_test_only_adds_a_stop(env, seed):
    """model-based-zeroed-knee is model-based-zeroed with one more stop: the same actions up to its own stop, which
    comes no later (seed 209: the lag jumps at the fifth window, where the fit's interval is still wide; 211: it never
    jumps, and the two episodes are the same)."""
    plain, knee = _actions(env, "model-based-zeroed", seed), _actions(env, "model-based-zeroed-knee", seed)
    assert len(knee) <= len(plain)
    assert all(np.array_equal(a, b) for a, b in zip(plain[:len(knee) - 1], knee[:len(knee) - 1]))
    assert (len(knee) < len(plain)) == (seed == 209)
    if seed == 211:
        assert all(np.array_equal(a, b) for a, b in zip(plain, knee))


def test_the_ar1_knee_agent_reads_the_lags_se_for_a_correlated_residual():
    """model-based-zeroed-knee-ar1's jump test reads phase_lag_se_corrected_deg: a 6 deg jump is beyond 2 deg plus two
    SEs of 0.5 deg (the white-noise SE a smoothed encoder's lock-in reports) but within two SEs of 5 deg (the SE for
    its correlated residual), so the knee agent stops there and the ar1 variant does not."""
    from cof_gym.agents.model_based import ModelBasedAgent
    from cof_gym.agents.phase_rule import CORRECTED_SE
    from cof_gym.task.interface import OBSERVATION_NAMES, PHASE_SCALE_DEG, MotorLimits

    PHASE, PHASE_SE = OBSERVATION_NAMES.index("phase_lag"), OBSERVATION_NAMES.index("phase_lag_se")

    def window(lag_deg: float) -> tuple[np.ndarray, dict]:
        obs = np.zeros(14, dtype=np.float32)
        obs[PHASE], obs[PHASE_SE] = lag_deg / PHASE_SCALE_DEG, 0.5 / PHASE_SCALE_DEG
        return obs, {"measurement": {CORRECTED_SE: 5.0}}

    seen = {}
    for corrected in (False, True):
        agent = ModelBasedAgent(MotorLimits(max_dc_torque_nm=10_000.0), knee_jump_deg=2.0, corrected_se=corrected)
        agent.reset(*window(0.0))
        agent._dc = 1_000.0  # driven windows from here on
        seen[corrected] = [agent._knee(*window(lag)) for lag in (0.0, 0.0, 0.0, 6.0)]
    assert seen == {False: [False, False, False, True], True: [False, False, False, False]}
    registered = make_agent("model-based-zeroed-knee-ar1", gym.make(cof_gym.WAGON_ENV_ID))
    assert registered.name == "model-based-zeroed-knee-ar1"
