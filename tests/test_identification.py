"""Creep-curve identification as an env interface: the climb record and its fit
(cof_gym.task.creep_fit), the "identification" observation, the "identified" action type, and
the behaviour-cloning demonstrations built on them."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import cof_gym  # noqa: F401  (registers the ids)
from cof_gym.agents.adapters import AgentSideInterface
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.agents.model_based import ModelBasedAgent
from cof_gym.agents.pretrain import collect_demonstrations, discounted_returns
from cof_gym.task.creep_fit import ClimbRecord, fit_peak
from cof_gym.task.actions import ActionContext, IdentifiedActions
from cof_gym.task.task import DEFAULT_MAX_WINDOWS
from cof_gym.task.interface import IDENTIFICATION_NAMES, IDENTIFICATION_OBSERVATION_NAMES, OBSERVATION_NAMES
from test_vector_env import same  # tests/ is on sys.path (pytest rootdir)

ENV_ID = "CofGym/TorqueInterrogation-v1"
IDENT = {"action_type": "identified", "observation_type": "identification"}


def test_climb_record_keeps_the_rising_branch_and_fits_it() -> None:
    climb = ClimbRecord()
    for dc, (coa, s) in enumerate(((0.02, 4e-4), (0.04, 9e-4), (0.06, 1.6e-3), (0.07, 2.4e-3))):
        assert not climb.add(coa, s, 20.0, dc)
    assert climb.add(0.065, 5e-3, 20.0, 4) and climb.falling  # the CoA fell as the torque rose: past the peak
    assert len(climb.points) == 4 and climb.best_coa == 0.07
    assert not climb.add(0.05, 1.2e-3, 20.0, 2.5)  # the torque was lowered: still the rising branch
    assert len(climb.points) == 5 and climb.best_coa == 0.07
    c, s = np.array(climb.points).T
    assert climb.fit == fit_peak(c, s, 20.0)
    assert climb.fit.estimate > 0.07 and climb.fit.low <= climb.fit.estimate <= climb.fit.high
    assert ClimbRecord().fit is None and ClimbRecord().elasticity() == 1.0


def test_identified_estimate_is_a_small_factor_on_the_fitted_peak() -> None:
    limits = gym.make(ENV_ID).unwrapped.limits
    act = IdentifiedActions()
    climb = ClimbRecord()
    for dc, (coa, s) in enumerate(((0.02, 4e-4), (0.04, 9e-4))):
        climb.add(coa, s, 20.0, dc)
    ctx = ActionContext(1000.0, 0.04, climb)
    assert ctx.fitted_peak == 0.0  # two points: no fit, the estimate is a factor on the best CoA
    assert act.decode(ctx, np.zeros(5), limits).cof_estimate == pytest.approx(0.04)
    climb.add(0.06, 1.6e-3, 20.0, 2)
    ctx = ActionContext(1000.0, 0.06, climb)
    peak = climb.fit.estimate
    for a3 in (-1.0, 0.0, 0.4, 1.0):
        a = np.array([0.0, 0.0, 0.0, a3, -1.0])
        d = act.decode(ctx, a, limits)
        assert d.cof_estimate == pytest.approx(peak * math.exp(0.05 * a3))
        back = act.encode(ctx, d.drive.dc_torque_nm, d.drive.amplitude_nm, d.drive.frequency_hz, d.cof_estimate,
                          d.stop, limits)
        np.testing.assert_allclose(back[:4], a[:4], atol=1e-5)


def test_identification_observation_is_sensor_only_and_rebuilt_by_the_agent() -> None:
    """The 38 values follow from the window observations alone: AgentSideInterface on a default env rebuilds them
    from its float32 observations, bit for bit at the reset, and the identified actions drive the same commands up
    to the plain env's float32 action.

    After a step the two sides are not bit-identical, and the tolerances say by how much they may differ: the agent
    re-encodes each identified action as the plain env's absolute action (float32, through its log maps), so the
    plain env applies the identified env's commands (decoded in float64) to within their last float32 bits, and each
    window's physics carries that on (the plain env's observation against the identified env's: rtol 2e-4); both
    sides then fit their own float32 readings of the climb, and the 38 values compound it (2e-3, with 1e-4 for
    values near zero). Over 20 seeds of this test's random actions the largest difference was 0.14 of the first
    tolerance and 0.01 of the second (session 82)."""
    assert IDENTIFICATION_OBSERVATION_NAMES[-len(IDENTIFICATION_NAMES):] == IDENTIFICATION_NAMES
    ident = gym.make(ENV_ID, **IDENT)
    plain = gym.make(ENV_ID)
    rng = np.random.default_rng(3)
    for seed in (0, 1):
        oi, _ = ident.reset(seed=seed)
        op, _ = plain.reset(seed=seed)
        agent = AgentSideInterface(plain.unwrapped.limits, "identified", "identification")
        assert oi.shape == (38,) and same(agent.reset(op), oi)
        for t in range(10):
            a = np.array([rng.uniform(0.2, 1.0), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), -1.0],
                         np.float32)
            before = ident.unwrapped.episode.action_context.fitted_peak  # the estimate's base when decoded
            oi, _, ti, tri, _ = ident.step(a)
            op, _, tp, trp, _ = plain.step(agent.to_env(a))
            np.testing.assert_allclose(op, oi[:len(OBSERVATION_NAMES)], rtol=2e-4, atol=1e-6)
            assert (ti, tri) == (tp, trp)
            if ident.unwrapped.episode.memory.climb.fit is not None:
                assert oi[IDENTIFICATION_OBSERVATION_NAMES.index("fit_available")] == 1.0
            if before > 0:
                assert ident.unwrapped.episode.estimate == pytest.approx(before * math.exp(0.05 * a[3]), rel=1e-6)
            np.testing.assert_allclose(agent.observe(op), oi, rtol=2e-3, atol=1e-4)
            if ti or tri:
                break


def test_the_model_based_agent_through_the_identified_interface_is_the_model_based_agent() -> None:
    """The model-based estimate is the identified action's a3 = 0: re-encoded through the env's
    interface, the agent gives the same estimates (within 0.2 %) and episode lengths, so a cloned policy starts from
    the model-based baseline."""
    plain, ident = gym.make(ENV_ID), gym.make(ENV_ID, **IDENT)
    limits = plain.unwrapped.limits
    for seed in (2, 5):
        record = run_episode(plain, ModelBasedAgent(limits), seed, {}, 0)
        obs, act, ret = collect_demonstrations(ENV_ID, IDENT, 1, seed)
        steps = record.steps
        assert obs.shape == (steps, 38) and act.shape == (steps, 5) and np.all(np.abs(act) <= 1.0)
        assert np.abs(act[:, 3]).max() < 1e-3  # the estimate is the fitted peak
        assert act[-1, 4] > 0.5 and np.all(act[:-1, 4] < 0.5)
        ident.reset(seed=seed)
        for a in act:
            _, reward, *_ , info = ident.step(a)
        # the relative first step reaches 0.495 % of max, not the climb's 0.5 %: the torques of the two
        # runs differ by ~1 %, the fitted peaks by < 0.2 %
        assert info["cof_estimate"] == pytest.approx(record.estimate, rel=2e-3)
        assert ret[-1] == pytest.approx(reward)


def test_discounted_returns() -> None:
    np.testing.assert_allclose(discounted_returns(np.array([1.0, 0.0, 2.0]), 0.5), [1.5, 1.0, 2.0])


def test_the_shipped_policy_interrogates_and_stops_by_itself() -> None:
    """The shipped PPO policy (cof_gym/agents/policies/ppo_wagon, trained on the identified interface)
    climbs, stops before the horizon without a macro-slip and reports the CoF within a few percent on
    draws of the default distribution it was not selected on."""
    from cof_gym.agents.registry import SHIPPED_PPO, shipped_ppo_available

    if not shipped_ppo_available():
        pytest.skip("no shipped policy")
    from cof_gym.agents.sb3_policy import SB3Agent

    agent = SB3Agent.load(SHIPPED_PPO)
    env = gym.make(ENV_ID)
    errors = []
    for seed in range(20_000, 20_006):
        rec = run_episode(env, agent, seed, {}, 0)
        # fewer windows than the horizon: the episode terminated, by the policy's own stop
        assert rec.scored and not rec.macro_slip and 3 <= rec.steps < DEFAULT_MAX_WINDOWS, (seed, rec.steps, rec.macro_slip)
        errors.append(rec.relative_error)
    assert np.median(errors) < 0.02 and max(errors) < 0.06, errors
