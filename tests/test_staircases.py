"""The practical staircase: safe first step at any CoF in range, accurate near-peak estimate, determinism."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import cof_gym
from cof_gym.agents.base import agent_view
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.agents.model_based import ModelBasedAgent
from cof_gym.agents.staircase import (
    ELASTICITY, PEAK_FRACTION_MAX, PEAK_FRACTION_MEDIAN, PracticalStaircase, limits_of, peak_fraction,
)
from cof_gym.task.interface import decode_action

WORST = {"noise_level": 3.0, "motor_lag_s": 0.1}  # the most sensor noise and motor lag the env accepts
ENV_ID = cof_gym.WAGON_V1_ENV_ID  # the wagon of the conftest's env fixture


@pytest.mark.parametrize("agent_class", [PracticalStaircase, ModelBasedAgent])
@pytest.mark.parametrize("condition", ["dry", "wet", "low_adhesion", "dry_kalker"])
def test_first_step_never_slips_at_the_lowest_cof(env, condition: str, agent_class) -> None:
    """CoF 0.02 (the envelope's bottom), both loads, 5 and 40 m/s, the worst noise and lag: the first
    torque step of either scale-free agent stays below half the saturation torque and the window ends
    without macro-slip."""
    agent = agent_class(limits_of(env))
    for load_case, speed in itertools.product(("empty", "laden"), (5.0, 40.0)):
        options = {"cof": 0.02, "condition": condition, "load_case": load_case, "speed_m_s": speed, **WORST}
        obs, info = env.reset(seed=7, options=options)
        agent.reset(obs, agent_view(info, False))
        action = agent.act(obs, agent_view(info, False))
        decoded = decode_action(action, limits_of(env))
        assert not decoded.stop
        assert decoded.drive.dc_torque_nm < 0.5 * info["ground_truth"]["saturation_torque_nm"], options
        _, _, terminated, _, info = env.step(action)
        assert not info["macro_slip"] and not terminated, options


@pytest.mark.parametrize("options", [
    {"cof": 0.55, "condition": "dry", "load_case": "laden", "speed_m_s": 35.0},
    {"cof": 0.18, "condition": "dry", "load_case": "empty", "speed_m_s": 8.0},
    {"cof": 0.12, "condition": "wet", "load_case": "laden", "speed_m_s": 20.0},
    {"cof": 0.03, "condition": "low_adhesion", "load_case": "empty", "speed_m_s": 30.0},
])
def test_climbs_to_the_peak_without_slipping_and_reports_the_cof(env, options) -> None:
    """Full sensor noise: no macro-slip, the estimate within 5 % of the CoF, inside the horizon."""
    rec = run_episode(env, PracticalStaircase(limits_of(env)), 11, {**options, "noise_level": 1.0}, 0)
    assert not rec.macro_slip
    assert rec.relative_error < 0.05, (options, rec.estimate)
    assert rec.steps < 30  # stopped by its own rule, not truncated


@pytest.mark.parametrize("agent_class", [PracticalStaircase, ModelBasedAgent])
def test_same_seed_same_actions(env, agent_class) -> None:
    def actions() -> list[np.ndarray]:
        agent = agent_class(limits_of(env))
        obs, info = env.reset(seed=3)
        agent.reset(obs, agent_view(info, False))
        out = []
        while True:
            a = agent.act(obs, agent_view(info, False))
            out.append(a)
            obs, _, terminated, truncated, info = env.step(a)
            if terminated or truncated:
                return out

    a, b = actions(), actions()
    assert len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b))


def test_peak_fraction_table_is_monotonic() -> None:
    assert len(ELASTICITY) == len(PEAK_FRACTION_MEDIAN) == len(PEAK_FRACTION_MAX)
    for table in (PEAK_FRACTION_MEDIAN, PEAK_FRACTION_MAX):
        assert all(b > a for a, b in zip(table, table[1:]))
    assert all(m <= x for m, x in zip(PEAK_FRACTION_MEDIAN, PEAK_FRACTION_MAX))
    assert peak_fraction(0.5) == 0.0 and peak_fraction(1e9) == pytest.approx(PEAK_FRACTION_MEDIAN[-1])


def test_the_table_bounds_the_creep_curves_it_claims_to() -> None:
    """At each elasticity the CoA / CoF of a few steady Polach curves lies inside the table's band."""
    from cof_gym.physics.creep import OperatingConditions, creep_curve, creep_peak

    for condition, cof, speed, load in [("dry", 0.6, 40.0, 110e3), ("wet", 0.05, 5.0, 55e3),
                                        ("low_adhesion", 0.02, 15.0, 110e3)]:
        op = OperatingConditions(cof=cof, condition=condition, wheel_load_n=load, speed_m_s=speed)
        peak = creep_peak(op)
        s = np.geomspace(1e-6, peak.creepage, 2000)
        coa, slope = creep_curve(s, op)
        e = (coa / s) / slope
        for x in (1.25, 2.0, 5.0, 15.0):
            frac = coa[np.argmax(e > x)] / peak.coa
            assert frac <= peak_fraction(x, PEAK_FRACTION_MAX) + 0.005, (condition, x, frac)
            assert frac >= peak_fraction(x) - 0.15, (condition, x, frac)  # the band is ~0.3 wide at e = 2
