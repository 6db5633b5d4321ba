"""The learned interrogator (cof_gym/agents/interrogator/): what it reads, its files, its guards and
estimators, and where it says it is out of its training distribution."""

from __future__ import annotations

import json
import math
from dataclasses import asdict
import subprocess
from dataclasses import replace
import sys

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.commands.suites import make_suite
from cof_gym.task.scenarios import V2_RANGES
from cof_gym.agents import registry
from cof_gym.agents.interrogator import (
    TARGET_NAMES, ClimbParameters, FilterEnsemble, FilterNetwork, LearnedInterrogator, feature_names,
    interrogator_for, pooled_correction,
)
from cof_gym.commands.evaluate_episodes import run_episode
from interrogator_helpers import SHIPPED, constant_network, play, random_network

def test_blind_to_a_creepage_offset_and_to_ground_truth():
    """A constant creepage offset (a speed-sensor bias) changes nothing but float rounding; the agent
    is not an oracle and is given no info."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(3), random_network(4))))
    a, _ = play(agent, 5)
    b, _ = play(agent, 5, perturb_creepage=0.2)  # observation units: a creepage offset of 0.02
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-4)  # float32 observations: the difference of two offset values rounds
    assert agent.oracle is False


def test_distribution_note_names_untrained_settings():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(),)),
                                trained_on=(cof_gym.WAGON_ENV_ID, ({}, {"counter_torque": True})))
    assert agent.distribution_note(cof_gym.WAGON_ENV_ID, {}) is None
    assert agent.distribution_note(cof_gym.WAGON_ENV_ID, {"counter_torque": True, "max_windows": 20}) is None
    # a longer horizon than its training climbs had: its slow probe climbs on past where any of them went
    assert "max_windows=60 (its training climbs had a horizon of 30)" in agent.distribution_note(
        cof_gym.WAGON_ENV_ID, {"max_windows": 60})
    # every way at once: the horizon and an episode no training draw gives
    both = agent.distribution_note(cof_gym.WAGON_ENV_ID, {"max_windows": 60}, [{"noise_level": 3.0}])
    assert "max_windows=60" in both and "1 of 1 episodes lie outside" in both and both.count("; ") >= 1
    assert "out of its training distribution" in agent.distribution_note(cof_gym.WAGON_V1_ENV_ID, {})
    # the rotation lock-in reads other numbers from the same speed than the ones its networks were fitted on
    assert "lock_in='rotation' (trained: 'default')" in agent.distribution_note(cof_gym.WAGON_ENV_ID,
                                                                                 {"lock_in": "rotation"})
    assert agent.distribution_note(cof_gym.WAGON_ENV_ID, {"lock_in": "plain"}) is None
    assert "traction_balance" in agent.distribution_note(cof_gym.WAGON_ENV_ID, {"traction_balance": False})


def test_distribution_note_reads_constructor_defaults_and_scenario_fields_as_the_env_does():
    """An argument equal to the env's default is the env made without it (no note); scenario fields given
    as constructor arguments fix every episode's scenario, so they count as its options (an episode's own
    option over them, as in the env)."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(),)),
                                trained_on=(cof_gym.WAGON_ENV_ID, ({}, {"counter_torque": True})))
    for defaults in ({"counter_torque": False}, {"vehicle": "wagon", "window_s": 1.0, "traction_balance": None}):
        assert agent.distribution_note(cof_gym.WAGON_ENV_ID, defaults, [{}]) is None, defaults
    assert "counter_torque=0" in agent.distribution_note(cof_gym.WAGON_ENV_ID, {"counter_torque": 0})  # 0 is no False
    kwargs = {"noise_level": 3.0, "speed_sensor_error": 0.05, "motor_lag_s": 0.1}
    note = agent.distribution_note(cof_gym.WAGON_ENV_ID, kwargs, [{}, {"cof": 0.3}])
    assert note.startswith("interrogator: 2 of 2 episodes") and "noise_level in 2 (e.g. 3, drawn: 0-1)" in note
    assert "motor_lag_s in 2" in note and "speed_sensor_error in 2" in note
    inside = {"noise_level": 0.5, "speed_sensor_error": 0.0, "motor_lag_s": 0.01}
    assert agent.distribution_note(cof_gym.WAGON_ENV_ID, kwargs, [inside, {**inside, "noise_level": None}]) == (
        "interrogator: 1 of 2 episodes lie outside the scenario draws it was trained on, out of its training "
        "distribution: noise_level in 1 (e.g. 3, drawn: 0-1)")  # None: the constructor's value stays


def test_distribution_note_counts_episodes_beyond_the_training_draws(env):
    """The held-out grid (tables, larger sensor errors) lies wholly outside the v2 draws; the paper suite
    has one CoF below the dry draws; the default suite's seeded draws lie inside."""
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(),)),
                                trained_on=(cof_gym.WAGON_ENV_ID, ({}, {"counter_torque": True})))
    heldout = make_suite("experiments/suites/v2_heldout_grid.json", 60, 0)
    note = agent.distribution_note(heldout.env_id, heldout.env_kwargs, [o for _, o in heldout.episodes])
    assert note.startswith(f"interrogator: {len(heldout.episodes)} of {len(heldout.episodes)} episodes")
    assert "creep_law in 48 (e.g. 'table'" in note and "out of its training distribution" in note
    paper = make_suite("paper", 5, 0)
    note = agent.distribution_note(paper.env_id, paper.env_kwargs, [o for _, o in paper.episodes])
    assert "1 of 5 episodes" in note and "cof in 1 (e.g. 0.1, drawn: 0.15-0.6)" in note
    default = make_suite("default", 60, 0)
    assert agent.distribution_note(default.env_id, default.env_kwargs, [o for _, o in default.episodes]) is None
    ranges = replace(V2_RANGES, speed_m_s=(10.0, 20.0))
    assert "ranges" in agent.distribution_note(cof_gym.WAGON_ENV_ID, {"ranges": ranges})


def test_bad_directory_is_one_line_and_exit_2(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "cof_gym.cli", "evaluate", "--agents", f"interrogator:{tmp_path}",
                           "--episodes", "1", "--out", str(tmp_path / "out")], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and "member_" in proc.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_shipped_interrogator_is_a_default_agent_and_measures():
    assert "interrogator" in registry.default_agents()
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = registry.make_agent("interrogator", env)
    assert agent.distribution_note(cof_gym.WAGON_ENV_ID, {}) is None
    # the recipe's guards: the one that learns the shipped climb (session 30) and the probing guard (session 31)
    assert len(agent.guards) == 2 and all(len(g.members) == 5 for g in agent.guards)
    records = [run_episode(env, agent, seed, {}, i) for i, seed in enumerate((11, 12, 13))]
    assert not any(r.macro_slip for r in records)
    assert all(r.scored and r.relative_error < 0.5 for r in records)


def test_the_estimate_source_does_not_change_the_climb():
    """Both estimate sources see the same windows: the actions differ only in the estimate component."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    ensemble = FilterEnsemble((random_network(5), random_network(6)))
    a, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble, params=ClimbParameters(estimate_from="filter")), 8)
    b, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble, params=ClimbParameters(estimate_from="best_coa")), 8)
    estimate = 3  # ACTION_NAMES index of cof_estimate
    np.testing.assert_array_equal(np.delete(a, estimate, axis=1), np.delete(b, estimate, axis=1))


def test_a_guard_like_the_filter_or_bolder_leaves_the_climb_unchanged():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    ensemble = FilterEnsemble((random_network(5), random_network(6)))
    alone, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble), 8)
    twin, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble, guards=(ensemble,)), 8)
    bold, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble, guards=(FilterEnsemble((constant_network(5.0, 0.0),)),)), 8)
    np.testing.assert_array_equal(twin, alone)
    np.testing.assert_array_equal(bold, alone)


def test_a_cautious_guard_stops_the_climb_and_the_estimate_stays_the_filters():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    primary = FilterEnsemble((constant_network(1.0, 0.2),))  # far from the peak: it would step on
    guard = FilterEnsemble((constant_network(-0.5, -0.4),))  # past the target: no step
    free = LearnedInterrogator(limits, primary)
    actions, _ = play(free, 8)
    assert len(actions) > 3 and free.stop_reason != "headroom"
    guarded = LearnedInterrogator(limits, primary, guards=(guard,))
    actions, info = play(guarded, 8)
    assert len(actions) == 2 and guarded.stop_reason == "headroom"  # the first window, then the stop
    coa = guarded.features.readings[-1].coa
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(0.2), rel=1e-6)  # the filter's correction


def test_guard_cautions_give_each_guard_its_own_caution_and_the_climbs_caution_changes_nothing():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    ensemble = FilterEnsemble((random_network(5), random_network(6)))
    params = ClimbParameters(caution=2.0, guard_cautions=[1.0, 3.0])
    assert params.guard_cautions == (1.0, 3.0) and params.guard_caution(1) == 3.0
    assert ClimbParameters(**json.loads(json.dumps(asdict(params)))) == params  # a manifest's list reads back
    assert ClimbParameters(caution=2.0).guard_caution(1) == 2.0
    agent = LearnedInterrogator(limits, ensemble, params=params, guards=(ensemble, ensemble))
    column = lambda v: np.array([[v, 0.0]])  # noqa: E731 (headroom, correction) outputs
    guard = (column(0.9), column(0.1), column(0.0))
    # the filter: 1.0 - 2 x 0.1 = 0.8; guard 0: 0.9 - 1 x 0.1 = 0.8, not lower; guard 1: 0.9 - 3 x 0.1 = 0.6
    steering = agent._steering_headroom(params, column(1.0), column(0.1), column(0.0), [guard, guard])
    assert steering == pytest.approx((0.6, 0.1, 0.0, 3.0), abs=1e-15)
    assert params.mean_headroom(steering[0], 0.1, 0.0, steering[3]) == pytest.approx(0.9, abs=1e-15)  # the guard's mean
    with pytest.raises(ValueError, match="guard_cautions names 2 caution.*1 guard"):
        LearnedInterrogator(limits, ensemble, params=params, guards=(ensemble,))
    primary = FilterEnsemble((constant_network(1.0, 0.2),))  # far from the peak and sure of it: steps on
    unsure = (FilterEnsemble((constant_network(0.5, 0.2, log_variance=-2.0),)),)  # std e^-1: 0.5 - 2 x 0.37 < 0
    climbs = {cautions: play(LearnedInterrogator(limits, primary, params=replace(params, guard_cautions=cautions),
                                                 guards=unsure), 8)[0] for cautions in (None, (2.0,), (0.0,))}
    np.testing.assert_array_equal(climbs[(2.0,)], climbs[None])  # the climb's own caution: nothing changes
    assert len(climbs[None]) == 2 and len(climbs[(0.0,)]) > 3  # the unsure guard stops it, or not at caution 0


@pytest.mark.parametrize("source", ["guard", "pooled", "pooled_at_headroom"])
def test_the_guarded_estimates_read_the_guards_correction_and_leave_the_climb_alone(source):
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    primary = FilterEnsemble((constant_network(1.0, 0.2, log_variance=-6.0),))
    guard = FilterEnsemble((constant_network(5.0, -0.1, log_variance=-4.0),))  # bolder: it never steers
    shipped_like = LearnedInterrogator(limits, primary, guards=(guard,))
    reference, _ = play(shipped_like, 8)
    agent = LearnedInterrogator(limits, primary, params=ClimbParameters(estimate_from=source), guards=(guard,))
    actions, info = play(agent, 8)
    estimate = 3  # ACTION_NAMES index of cof_estimate
    np.testing.assert_array_equal(np.delete(actions, estimate, axis=1), np.delete(reference, estimate, axis=1))
    coa = agent.features.readings[-1].coa
    # each member's std is exp(log_variance / 2): e^-3 for the filter, e^-2 for the guard
    pooled = pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0))])
    correction = {"guard": -0.1, "pooled": pooled, "pooled_at_headroom": 0.2}[source]  # not a headroom stop here
    assert agent.stop_reason != "headroom"
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(correction), rel=1e-6)
    assert agent.candidate_estimates(1.0)["filter"] == pytest.approx(coa * math.exp(0.2), rel=1e-12)


def test_the_pooled_estimate_at_a_headroom_stop_and_the_filters_before_it():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    primary = FilterEnsemble((constant_network(1.0, 0.2, log_variance=-6.0),))
    guard = FilterEnsemble((constant_network(-0.5, -0.1, log_variance=-4.0),))  # past the target: it stops the climb
    agent = LearnedInterrogator(env.unwrapped.limits, primary, params=ClimbParameters(estimate_from="pooled_at_headroom"),
                                guards=(guard,))
    actions, info = play(agent, 8)
    assert len(actions) == 2 and agent.stop_reason == "headroom"
    coa = agent.features.readings[-1].coa
    pooled = pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0))])
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(pooled), rel=1e-6)


def test_a_guarded_estimate_without_guards_names_the_field():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    with pytest.raises(ValueError, match="estimate_from"):
        LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(5),)),
                            params=ClimbParameters(estimate_from="pooled"))


@pytest.mark.parametrize("role", ["guards", "estimators"])
def test_the_guards_and_estimators_pool_needs_both(role):
    """``guard_estimator_pooled`` reads the guards' and the estimators' corrections: without either, the error
    names the field and the missing role."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    present = {"guards": (FilterEnsemble((random_network(6),)),), "estimators": (FilterEnsemble((random_network(7),)),)}
    del present[role]
    with pytest.raises(ValueError, match=f"estimate_from='guard_estimator_pooled'.*no {role}"):
        LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(5),)),
                            params=ClimbParameters(estimate_from="guard_estimator_pooled"), **present)


@pytest.mark.parametrize("source", ["estimator", "estimator_pooled", "guard_estimator_pooled"])
def test_the_estimators_corrections_change_the_estimate_and_never_the_climb(source):
    """An estimator never steers: every action component but the estimate is byte-identical with and without
    it, even where its predicted headroom would stop the climb at once; the estimate reads its correction
    alone, pooled with the filter's and the guards', or with the guards' alone (inverse-variance)."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    primary = FilterEnsemble((constant_network(1.0, 0.2, log_variance=-6.0),))
    guard = FilterEnsemble((constant_network(5.0, -0.1, log_variance=-4.0),))
    estimator = FilterEnsemble((constant_network(-0.5, 0.05, log_variance=-5.0),))  # it would stop: it must not
    reference, _ = play(LearnedInterrogator(limits, primary, guards=(guard,)), 8)
    agent = LearnedInterrogator(limits, primary, params=ClimbParameters(estimate_from=source), guards=(guard,),
                                estimators=(estimator,))
    actions, info = play(agent, 8)
    estimate = 3  # ACTION_NAMES index of cof_estimate
    np.testing.assert_array_equal(np.delete(actions, estimate, axis=1), np.delete(reference, estimate, axis=1))
    coa = agent.features.readings[-1].coa
    pooled = pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0)), (0.05, math.exp(-2.5))])
    guarded = pooled_correction([(-0.1, math.exp(-2.0)), (0.05, math.exp(-2.5))])
    correction = {"estimator": 0.05, "estimator_pooled": pooled, "guard_estimator_pooled": guarded}[source]
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(correction), rel=1e-6)
    assert agent.candidate_estimates(1.0)["pooled"] == pytest.approx(
        coa * math.exp(pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0))])), rel=1e-12)


@pytest.mark.parametrize("source", ["estimator_pooled_at_headroom", "estimator_at_headroom"])
def test_the_estimators_read_at_a_headroom_stop_and_the_filters_before_it(source):
    """At a headroom stop the estimators' corrections, pooled with the filter's and the guard's or alone
    (inverse-variance); at any other stop the filter's."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    primary = FilterEnsemble((constant_network(1.0, 0.2, log_variance=-6.0),))
    guard = FilterEnsemble((constant_network(-0.5, -0.1, log_variance=-4.0),))  # past the target: it stops the climb
    estimators = tuple(FilterEnsemble((constant_network(5.0, c, log_variance=-5.0),)) for c in (0.3, 0.4))
    agent = LearnedInterrogator(env.unwrapped.limits, primary, guards=(guard,), estimators=estimators,
                                params=ClimbParameters(estimate_from=source))
    actions, info = play(agent, 8)
    assert len(actions) == 2 and agent.stop_reason == "headroom"
    coa = agent.features.readings[-1].coa
    theirs = [(0.3, math.exp(-2.5)), (0.4, math.exp(-2.5))]
    pooled = pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0)), *theirs])
    correction = pooled if source == "estimator_pooled_at_headroom" else pooled_correction(theirs)
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(correction), rel=1e-6)
    free = LearnedInterrogator(env.unwrapped.limits, primary, estimators=estimators,  # no guard: no headroom stop
                               params=ClimbParameters(estimate_from=source))
    _, info = play(free, 8)
    assert free.stop_reason != "headroom"
    assert info["cof_estimate"] == pytest.approx(free.features.readings[-1].coa * math.exp(0.2), rel=1e-6)


def test_an_estimators_estimate_without_estimators_names_the_field(tmp_path):
    env = gym.make(cof_gym.WAGON_ENV_ID)
    with pytest.raises(ValueError, match="estimate_from='estimator'.*no estimators"):
        LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(5),)),
                            params=ClimbParameters(estimate_from="estimator"))
    run = tmp_path / "run"
    (run / "est").mkdir(parents=True)
    random_network(1).save(run / "member_0.npz")
    constant_network(0.0, 0.1).save(run / "est" / "member_0.npz")
    (run / "manifest.json").write_text('{"estimators": ["est"], "climb": {"estimate_from": "estimator"}}')
    agent = interrogator_for(env, run)
    assert len(agent.estimators) == 1 and not agent.guards and agent.params.estimate_from == "estimator"
    assert not interrogator_for(env, run, params=ClimbParameters(), estimators=[]).estimators


def test_guards_come_from_the_manifest_and_must_drive_the_climbs_tones(tmp_path):
    env = gym.make(cof_gym.WAGON_ENV_ID)
    run, guard_dir = tmp_path / "run", tmp_path / "run" / "guard"
    guard_dir.mkdir(parents=True)
    random_network(1).save(run / "member_0.npz")
    constant_network(-0.5, 0.0).save(guard_dir / "member_0.npz")
    assert not interrogator_for(env, run).guards
    (run / "manifest.json").write_text('{"guards": ["guard"]}')
    agent = interrogator_for(env, run)
    assert len(agent.guards) == 1 and agent.guards[0].members[0].biases[-1][0] == -0.5
    assert not interrogator_for(env, run, guards=[]).guards
    names = feature_names(("tone2",))
    two_tone = FilterNetwork(np.zeros(len(names)), np.ones(len(names)), (np.zeros((len(names), 2 * len(TARGET_NAMES))),),
                             (np.zeros(2 * len(TARGET_NAMES)),), names)
    with pytest.raises(ValueError, match="guard reads another excitation"):
        LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(1),)),
                            guards=(FilterEnsemble((two_tone,)),))


@pytest.mark.parametrize("text, fragment", [("{bad", "manifest.json is not JSON"),
                                            ("[1, 2]", "manifest.json must hold a JSON object")])
def test_a_broken_manifest_is_refused_naming_the_file(tmp_path, text, fragment):
    from cof_gym.agents.interrogator.agent import read_manifest

    (tmp_path / "manifest.json").write_text(text)
    with pytest.raises(ValueError, match=fragment):
        read_manifest(tmp_path)
    assert read_manifest(tmp_path / "no_such_directory") == {}
