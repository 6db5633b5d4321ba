"""The model-based agent: safe first step, fitted peak with an interval that covers the CoF, determinism."""

from __future__ import annotations


import numpy as np
import pytest

import cof_gym
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.agents.model_based import ModelBasedAgent
from cof_gym.task.creep_fit import SHAPE_FAMILIES, SHAPE_GRID, SHE_RISE, creep_shapes, family_shapes, fit_peak
from cof_gym.agents.registry import make_agent
from cof_gym.agents.staircase import limits_of
from cof_gym.agents.runaway import RunawayEstimate

WORST = {"noise_level": 3.0, "motor_lag_s": 0.1}
ENV_ID = cof_gym.WAGON_V1_ENV_ID  # the wagon of the conftest's env fixture


def test_registered_as_a_non_oracle(env) -> None:
    agent = make_agent("model-based", env)  # it reports the runaway estimate between its stops (rule 24)
    assert isinstance(agent, RunawayEstimate) and isinstance(agent.agent, ModelBasedAgent)
    assert agent.name == "model-based" and not agent.oracle


@pytest.mark.parametrize("options", [
    {"cof": 0.5, "condition": "dry", "load_case": "laden", "speed_m_s": 30.0},
    {"cof": 0.2, "condition": "dry", "load_case": "empty", "speed_m_s": 7.0},
    {"cof": 0.15, "condition": "wet", "load_case": "laden", "speed_m_s": 18.0},
    {"cof": 0.04, "condition": "low_adhesion", "load_case": "empty", "speed_m_s": 25.0},
])
def test_fitted_peak_is_within_3_percent_and_its_interval_covers_the_cof(env, options) -> None:
    """Full sensor noise: no macro-slip, the reported peak within 3 % and the last interval covering
    the CoF (with 0.5 % slack for the grid of the fit)."""
    agent = ModelBasedAgent(limits_of(env))
    rec = run_episode(env, agent, 21, {**options, "noise_level": 1.0}, 0)
    assert not rec.macro_slip and rec.steps < 30
    assert rec.relative_error < 0.03, (options, rec.estimate)
    low, estimate, high = agent.interval
    assert low <= estimate <= high
    assert low * 0.995 <= rec.cof <= high * 1.005, (options, agent.interval)


def test_fit_on_an_exact_curve_recovers_its_peak_and_stays_open_on_a_line() -> None:
    """Points of a library shape scaled to peak 0.3 at creepage 0.02 up to 85 % of the peak: the fit
    finds 0.3 inside its interval, which narrows with a point at 95 %; points on a straight line (far below any knee) leave it open."""

    shape = creep_shapes()[5]
    u = np.array([0.2, 0.4, 0.6, 0.75, 0.85])
    s = 0.02 * np.interp(u, SHAPE_GRID, shape)
    fit = fit_peak(0.3 * u, s, speed_m_s=25.0)
    assert fit.estimate == pytest.approx(0.3, rel=0.02) and fit.low <= 0.3 <= fit.high
    closer = fit_peak(0.3 * np.append(u, 0.95), 0.02 * np.interp(np.append(u, 0.95), SHAPE_GRID, shape), 25.0)
    assert closer.low <= 0.3 <= closer.high and closer.half_width < 0.5 * fit.half_width
    line = fit_peak(np.array([0.01, 0.02, 0.03, 0.04]), np.array([1e-4, 2e-4, 3e-4, 4e-4]), speed_m_s=25.0)
    assert line.high > 2.0 * 0.04 and line.half_width > 0.3


def test_the_shen_hedrick_elkins_branch_is_the_laws_own_and_its_fit_finds_its_peak() -> None:
    """The family's branch, s / s_peak = 1 - (1 - CoA / CoF)^(1/3), is the inverse of Shen-Hedrick-Elkins'
    x - x^2/3 + x^3/27 at x = 3 s / s_peak; points of that curve (peak 0.3 at creepage 0.01, up to 85 % of it) are
    found within the peak grid's step (the 160 peaks from 1 to 4 x the best CoA: 0.9 % apart) by a fit that reads
    the family, where Polach's library alone misses them by more."""
    x = 3.0 * SHE_RISE
    assert np.allclose(x - x ** 2 / 3 + x ** 3 / 27, SHAPE_GRID, atol=1e-12)
    u = np.array([0.2, 0.4, 0.6, 0.75, 0.85])
    s = 0.01 * (1.0 - (1.0 - u) ** (1.0 / 3.0))
    step = (4.0 * SHAPE_GRID[-1]) ** (1.0 / 159)  # the ratio between neighbouring peaks of the grid
    fit = fit_peak(0.3 * u, s, speed_m_s=20.0, families=SHAPE_FAMILIES)
    assert abs(np.log(fit.estimate / 0.3)) <= np.log(step) and fit.low <= 0.3 <= fit.high
    polach = fit_peak(0.3 * u, s, speed_m_s=20.0)
    assert abs(np.log(polach.estimate / 0.3)) > np.log(step)
    with pytest.raises(ValueError, match="families must be a non-empty subset"):
        family_shapes(("kalker",))


def test_a_fit_that_reads_the_cycles_swing_finds_the_peak_a_large_modulation_hides() -> None:
    """Windows modulated by +-35 % of their CoA on a Shen-Hedrick-Elkins curve: each window's mean creepage is the
    cycle mean of the curve's, above its value at the mean CoA. A fit of the mean points reads the bend as a lower
    peak; with the swing (``fit_peak(..., swing=)``) the peak is found within two steps of the fit's geometric grid of
    peak CoAs (0.9 % each; the 16-phase cycle mean against this 256-phase one moves it by less than a step)."""
    from cof_gym.task.creep_fit import SHEN_HEDRICK_ELKINS, SHAPE_GRID, fit_peak

    cof, s_peak = 0.3, 0.012
    phases = np.sin(2 * np.pi * (np.arange(256) + 0.5) / 256)
    coa = np.linspace(0.1, 0.7, 12) * cof
    swing = 0.35 * coa  # crests at most 0.945 x the CoF: on the rising branch
    creepage = np.array([np.mean(s_peak * (1 - (1 - (c + a * phases) / cof) ** (1 / 3))) for c, a in zip(coa, swing)])
    step = (4.0 * SHAPE_GRID[-1]) ** (1 / 159) - 1  # fit_peak's grid: 160 peak CoAs from the best CoA / 0.999 to 4 x it
    quiet = {"families": (SHEN_HEDRICK_ELKINS,), "creepage_noise": 1e-6, "relative_noise": 1e-3}
    assert abs(fit_peak(coa, creepage, 20.0, swing=swing, **quiet).estimate / cof - 1) < 2 * step
    assert fit_peak(coa, creepage, 20.0, **quiet).estimate / cof - 1 < -5 * step
