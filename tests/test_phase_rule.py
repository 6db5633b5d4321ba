"""The practical phase rule: reads no ground truth and no creepage, a first step that never slips, DC
steps below the probe, determinism, a sane estimate on a sharp-knee curve and no macro-slip on a few v2
episodes."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from cof_gym.agents.phase_rule import PAPER_CORRECTION, PhaseRule
from cof_gym.agents.registry import make_agent
from cof_gym.agents.runaway import RunawayEstimate
from cof_gym.agents.staircase import ElasticityClimb, limits_of
from cof_gym.agents.base import agent_view
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.task.interface import OBSERVATION_NAMES, decode_action

CREEPAGE = OBSERVATION_NAMES.index("creepage_measured")
WORST = {"noise_level": 3.0, "motor_lag_s": 0.1}  # the most sensor noise and motor lag the env accepts


def test_registered_without_ground_truth(env) -> None:
    agent = make_agent("phase-rule", env)  # its estimates capped at the crest ceiling (rule 29)
    assert isinstance(agent, RunawayEstimate) and isinstance(agent.agent, PhaseRule)
    assert (agent.bracket, agent.ceiling) == (False, True) and not agent.oracle and agent.name == "phase-rule"


@pytest.mark.parametrize("garbage", [np.nan, 123.0, -7.5])
def test_reads_no_creepage_and_no_ground_truth(env, garbage: float) -> None:
    """An agent given the true observations and the evaluator's info and a twin given the creepage
    entry replaced by garbage and an empty info command exactly the same actions all episode."""
    limits = limits_of(env)
    seen, blind = PhaseRule(limits), PhaseRule(limits)
    obs, info = env.reset(seed=3, options={"noise_level": 1.0})

    def garbled(o: np.ndarray) -> np.ndarray:
        o = o.copy()
        o[CREEPAGE] = garbage
        return o

    seen.reset(obs, agent_view(info, True))
    blind.reset(garbled(obs), {})
    for _ in range(40):
        a, b = seen.act(obs, agent_view(info, True)), blind.act(garbled(obs), {})
        np.testing.assert_array_equal(a, b)
        obs, _, terminated, truncated, info = env.step(a)
        if terminated or truncated:
            break


@pytest.mark.parametrize("condition", ["dry", "wet", "low_adhesion"])
def test_first_step_never_slips_at_the_lowest_cof(env, condition: str) -> None:
    """CoF 0.02, both loads, 5 and 40 m/s, the worst noise and lag: the first step (the practical
    staircase's, shared) stays below half the saturation torque (its crest, the probe, below 70 %), and the
    window ends without macro-slip."""
    limits = limits_of(env)
    agent = PhaseRule(limits)
    for load_case, speed in itertools.product(("empty", "laden"), (5.0, 40.0)):
        options = {"cof": 0.02, "condition": condition, "load_case": load_case, "speed_m_s": speed, **WORST}
        obs, info = env.reset(seed=7, options=options)
        agent.reset(obs, {})
        action = agent.act(obs, {})
        decoded = decode_action(action, limits)
        assert not decoded.stop
        assert decoded.drive.dc_torque_nm == pytest.approx(ElasticityClimb().first_dc(limits), rel=1e-3)
        m_sat = info["ground_truth"]["saturation_torque_nm"]
        assert decoded.drive.dc_torque_nm < 0.5 * m_sat, options
        assert decoded.drive.dc_torque_nm + decoded.drive.amplitude_nm < 0.7 * m_sat, options
        _, _, terminated, _, info = env.step(action)
        assert not info["macro_slip"] and not terminated, options


def test_deterministic(env) -> None:
    a = run_episode(env, PhaseRule(limits_of(env)), 21, {}, 0)
    b = run_episode(env, PhaseRule(limits_of(env)), 21, {}, 0)
    assert a == b


def test_correction_scales_the_estimate(env) -> None:
    plain = run_episode(env, PhaseRule(limits_of(env), correction=1.0), 5, {"noise_level": 0.5}, 0)
    corrected = run_episode(env, PhaseRule(limits_of(env), correction=PAPER_CORRECTION), 5, {"noise_level": 0.5}, 0)
    assert corrected.steps == plain.steps
    assert corrected.estimate == pytest.approx(plain.estimate * PAPER_CORRECTION, rel=1e-3)


def test_dc_steps_stay_below_the_probe(env) -> None:
    """Each DC step is smaller than the modulation amplitude of the window before (the next DC lies
    below the crest that was probed), also where the amplitude is at the drive's maximum."""
    limits = limits_of(env)
    agent = PhaseRule(limits)
    dc = agent.climb.first_dc(limits)
    while dc < limits.max_dc_torque_nm:
        amp = agent.amplitude(dc)
        nxt = agent.next_dc(dc, amp)
        assert dc < nxt <= dc + agent.probe_step * amp < dc + amp, (dc, amp, nxt)
        dc = nxt


SHARP_KNEE = {"shen_hedrick_elkins": {"k_stiffness": 0.3, "friction_ratio": 1.0, "friction_decay_s_per_m": 0.0}}


@pytest.mark.parametrize("options", [
    {"cof": 0.2, "condition": "wet", "load_case": "laden", "speed_m_s": 6.0, "creep_law": SHARP_KNEE},
    {"cof": 0.5, "condition": "dry", "load_case": "empty", "speed_m_s": 7.0, "creep_law": SHARP_KNEE},
    {"cof": 0.06, "condition": "low_adhesion", "load_case": "laden", "speed_m_s": 18.0, "creep_law": SHARP_KNEE},
    {"cof": 0.2, "condition": "wet", "load_case": "empty", "speed_m_s": 15.0},
])
def test_stops_with_a_sane_estimate(env, options) -> None:
    """Sharp knees (a Shen-Hedrick-Elkins curve, no falling branch: the phase stays flat until the
    crest touches the peak) and a default wet curve, moderate noise: stops by its own rule inside the
    horizon without macro-slip, the estimate within 25 % of the CoF."""
    agent = PhaseRule(limits_of(env))
    rec = run_episode(env, agent, 11, {**options, "noise_level": 0.3}, 0)
    assert not rec.macro_slip
    assert agent.stop_reason in ("phase", "falling"), agent.stop_reason
    assert 0.75 * rec.cof < rec.estimate < 1.25 * rec.cof, (options, rec.estimate, rec.cof)


def test_no_macro_slip_on_a_small_set(env) -> None:
    """Ten default v2 draws (seeds outside the default suite and the validation set)."""
    slips = [run_episode(env, PhaseRule(limits_of(env)), seed, {}, 0).macro_slip for seed in range(500000, 500010)]
    assert not any(slips)
