"""Task v3 (``CofGym/TorqueInterrogationInService-v3``): v2's draws, and a train's speed probe (pulses, runout, lag)
on a track of drawn irregularity, each drawn after v2's fields so that every v2 field of a seed is v2's."""

from __future__ import annotations

import argparse
import json
from dataclasses import asdict, replace

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents import registry
from cof_gym.agents.interrogator import FilterEnsemble, LearnedInterrogator
from cof_gym.agents.phase_rule import IN_SERVICE_PARAMETERS, PhaseRule
from cof_gym.commands.suites import SUITE_NAMES, make_suite
from cof_gym.envs.torque_interrogation import NARROWING, default_ranges
from cof_gym.task import V2_RANGES, V3_RANGES, ScenarioRanges
from cof_gym.task.scenarios import SCENARIO_KEYS, TASK_VERSION_RANGES, draw_scenario, outside_draws
from interrogator_helpers import random_network  # tests/ is on sys.path (pytest rootdir)
from test_vector_env import assert_batched_plays_as_sync

IN_SERVICE = cof_gym.WAGON_IN_SERVICE_ENV_ID
V3_FIELDS = ("encoder_pulses_per_rev", "encoder_runout", "encoder_lag_s", "track_irregularity")
V2_FIELDS = tuple(key for key in SCENARIO_KEYS if key not in V3_FIELDS)


def drawn(ranges: ScenarioRanges, seed: int, fixed: dict | None = None) -> dict:
    return draw_scenario(np.random.default_rng(seed), ranges, fixed or {}).to_dict()


def test_v3_draws_each_seeds_v2_scenario_and_adds_the_probe_and_the_track() -> None:
    v2 = [drawn(V2_RANGES, seed) for seed in range(60)]
    v3 = [drawn(V3_RANGES, seed) for seed in range(60)]
    assert [{k: d[k] for k in V2_FIELDS} for d in v3] == [{k: d[k] for k in V2_FIELDS} for d in v2]
    assert all((d["encoder_pulses_per_rev"], d["encoder_runout"], d["encoder_lag_s"], d["track_irregularity"])
               == (0, 0.0, 0.0, "smooth") for d in v2)
    pulses = [d["encoder_pulses_per_rev"] for d in v3]
    assert all(type(p) is int and 60 <= p <= 300 for p in pulses) and len(set(pulses)) > 40
    assert all(0.0 <= d["encoder_runout"] <= 0.001 and 0.0 <= d["encoder_lag_s"] <= 0.005 for d in v3)
    assert {d["track_irregularity"] for d in v3} == {"ore_low", "ore_high"}


def test_fixing_a_probe_field_moves_no_other_draw() -> None:
    for field, value in (("encoder_lag_s", 0.002), ("encoder_pulses_per_rev", 100), ("track_irregularity", "smooth")):
        free, fixed = drawn(V3_RANGES, 5), drawn(V3_RANGES, 5, {field: value})
        assert fixed[field] == value and {k: v for k, v in fixed.items() if k != field} == {
            k: v for k, v in free.items() if k != field}


def test_the_in_service_id_plays_task_v3() -> None:
    """Its spec names task version 3 and its draws are V3_RANGES; a reset's truth holds v2's scenario of the seed and
    the probe and the track it drew; every version's draws come from one table."""
    assert cof_gym.WAGON_IN_SERVICE_ENV_ID in cof_gym.ENV_IDS and gym.spec(IN_SERVICE).kwargs["task_version"] == 3
    assert [default_ranges(v) for v in (1, 2, 3)] == [TASK_VERSION_RANGES[v] for v in (1, 2, 3)]
    assert default_ranges(3) == V3_RANGES and default_ranges(2) == V2_RANGES
    assert sorted(NARROWING) == sorted(TASK_VERSION_RANGES)  # every version's refusal names how to narrow it
    with pytest.raises(ValueError, match=r"task_version must be an integer in \[1, 3\]"):
        default_ranges(4)
    in_service, v2 = gym.make(IN_SERVICE), gym.make(cof_gym.WAGON_ENV_ID)
    assert in_service.unwrapped.task.ranges == V3_RANGES
    for seed in (0, 3):
        truth, truth_v2 = in_service.reset(seed=seed)[1]["ground_truth"], v2.reset(seed=seed)[1]["ground_truth"]
        assert {k: truth[k] for k in V2_FIELDS} == {k: truth_v2[k] for k in V2_FIELDS}
        assert truth["encoder_pulses_per_rev"] >= 60 and truth["track_irregularity"] in ("ore_low", "ore_high")
    in_service.close()
    v2.close()


@pytest.mark.parametrize("field, value, match", [
    ("encoder_pulses_per_rev", (0, 50), r"ranges\.encoder_pulses_per_rev must be \(0, 0\) .* \[8, 10000\]"),
    ("encoder_pulses_per_rev", (300, 60), r"ranges\.encoder_pulses_per_rev .* min <= max, got \(300, 60\)"),
    ("encoder_pulses_per_rev", (60.0, 300), r"ranges\.encoder_pulses_per_rev .* integers"),
    ("encoder_pulses_per_rev", (60, 20000), r"ranges\.encoder_pulses_per_rev"),
    ("encoder_runout", (0.0, 0.02), r"ranges\.encoder_runout\[1\] must be a finite number in \[0, 0\.01\]"),
    ("encoder_lag_s", (0.0, 0.1), r"ranges\.encoder_lag_s\[1\] must be a finite number in \[0, 0\.05\]"),
    ("encoder_lag_s", (0.003, 0.001), r"ranges\.encoder_lag_s must satisfy min <= max"),
    ("track_irregularities", ("gravel",), r"ranges\.track_irregularities must be a non-empty subset of"),
    ("track_irregularities", (), r"ranges\.track_irregularities must be a non-empty subset of"),
])
def test_bad_probe_and_track_ranges_are_refused_naming_the_field(field, value, match) -> None:
    with pytest.raises(ValueError, match=match):
        replace(V3_RANGES, **{field: value})


def test_ranges_of_another_task_version_are_refused_and_narrowed_v3_draws_are_played() -> None:
    with pytest.raises(ValueError, match=r"ranges: draws creep-law .* a continuous encoder on a level track, but "
                                         r"task_version is 3 .*V3_RANGES.*make the -v2 id \(task_version=2\)"):
        gym.make(IN_SERVICE, ranges=V2_RANGES)
    with pytest.raises(ValueError, match=r"task_version is 2 .*V2_RANGES.*make the -v3 id \(task_version=3\)"):
        gym.make(cof_gym.WAGON_ENV_ID, ranges=V3_RANGES)
    with pytest.raises(ValueError, match=r"task_version is 1 .*cof_gym\.task\.ScenarioRanges\(\.\.\.\)"):
        gym.make(cof_gym.WAGON_V1_ENV_ID, ranges=replace(ScenarioRanges(), encoder_lag_s=(0.0, 0.001)))
    narrowed = replace(V3_RANGES, encoder_pulses_per_rev=(100, 100), track_irregularities=("ore_low",))
    env = gym.make(IN_SERVICE, ranges=narrowed)
    truth = env.reset(seed=2)[1]["ground_truth"]
    assert (truth["encoder_pulses_per_rev"], truth["track_irregularity"]) == (100, "ore_low")
    env.close()
    spec_json = json.loads(json.dumps(asdict(V3_RANGES)))  # lists where the fields are tuples, as a spec's JSON
    assert ScenarioRanges.from_mapping(spec_json) == V3_RANGES


def test_outside_draws_reads_the_probe_and_the_track_of_the_ranges() -> None:
    options = {"encoder_pulses_per_rev": 30, "encoder_lag_s": 0.01, "encoder_runout": 0.002,
               "track_irregularity": "smooth"}
    assert outside_draws(options, V3_RANGES) == {
        "encoder_pulses_per_rev": "30, drawn: 60-300", "encoder_lag_s": "0.01, drawn: 0-0.005",
        "encoder_runout": "0.002, drawn: 0-0.001", "track_irregularity": "'smooth', drawn: 'ore_low', 'ore_high'"}
    assert outside_draws({"encoder_pulses_per_rev": 0}, V3_RANGES) == {"encoder_pulses_per_rev": "0, drawn: 60-300"}
    inside = {"encoder_pulses_per_rev": 100, "encoder_runout": 0.0005, "encoder_lag_s": 0.002,
              "track_irregularity": "ore_high"}
    assert outside_draws(inside, V3_RANGES) == {}
    assert outside_draws({"encoder_lag_s": 0.002}, V2_RANGES) == {"encoder_lag_s": "0.002, drawn: 0"}


def test_the_in_service_suite_plays_the_default_seeds_on_task_v3_and_the_learned_agent_says_it_is_out() -> None:
    assert "in-service" in SUITE_NAMES
    suite, default = make_suite("in-service", 3, 7), make_suite("default", 3, 7)
    assert suite.env_id == IN_SERVICE and suite.env_kwargs == {}
    assert list(suite.episodes) == list(default.episodes) == [(7, {}), (8, {}), (9, {})]
    env = gym.make(IN_SERVICE)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(),)),
                                trained_on=(cof_gym.WAGON_ENV_ID, ({},)))
    note = agent.distribution_note(suite.env_id, suite.env_kwargs, [o for _, o in suite.episodes])
    assert f"env {IN_SERVICE} (trained: {cof_gym.WAGON_ENV_ID})" in note and "out of its training distribution" in note
    env.close()


def test_the_batched_env_plays_task_v3_as_single_envs_do() -> None:
    """The vector env (mujoco.batch) draws and lays the probe and the track as gymnasium's SyncVectorEnv of single
    envs does, bit for bit."""
    assert_batched_plays_as_sync({}, env_id=IN_SERVICE)


def test_the_phase_rule_chosen_for_v3_is_registered_beside_the_default_list() -> None:
    """``phase-rule-in-service`` is the phase rule with the parameters select_phase_rule.py --in-service chose, every
    other one the v2 rule's; the default suite (v2) does not play it."""
    assert "phase-rule-in-service" in registry.AGENTS and "phase-rule-in-service" not in registry.default_agents()
    env = gym.make(IN_SERVICE)
    agent = registry.make_agent("phase-rule-in-service+plain", env)
    assert isinstance(agent, PhaseRule) and agent.name == "phase-rule-in-service+plain"  # as its factory builds it
    assert {key: getattr(agent, key) for key in IN_SERVICE_PARAMETERS} == IN_SERVICE_PARAMETERS
    v2_rule = PhaseRule(env.unwrapped.limits)
    assert agent.baseline_windows == v2_rule.baseline_windows and agent.min_amplitude_nm == v2_rule.min_amplitude_nm
    env.close()


def test_the_interrogator_fitted_on_v3_is_registered_beside_the_default_list_and_knows_its_task() -> None:
    """``interrogator-in-service`` plays its own package (networks fitted on the v3 wagon's climbs, its manifest saying
    so) under its registry name; on the in-service suite it is in its training distribution, on the v2 default suite
    it says it is not; the default suite (v2) does not play it."""
    from cof_gym.agents.policy_files import SHIPPED_INTERROGATOR_IN_SERVICE

    assert "interrogator-in-service" in registry.AGENTS and "interrogator-in-service" not in registry.default_agents()
    assert "interrogator-in-service" in registry.default_agents(IN_SERVICE)
    manifest = json.loads((SHIPPED_INTERROGATOR_IN_SERVICE / "manifest.json").read_text())
    assert manifest["trained_on"]["env_id"] == IN_SERVICE
    env = gym.make(IN_SERVICE)
    agent = registry.make_agent("interrogator-in-service", env)
    assert isinstance(agent, LearnedInterrogator) and agent.name == "interrogator-in-service"
    assert agent.trained_on[0] == IN_SERVICE and len(agent.guards) == len(manifest["guards"])
    in_service, v2 = make_suite("in-service", 3, 0), make_suite("default", 3, 0)
    assert agent.distribution_note(in_service.env_id, in_service.env_kwargs, [o for _, o in in_service.episodes]) is None
    note = agent.distribution_note(v2.env_id, v2.env_kwargs, [o for _, o in v2.episodes])
    assert f"env {cof_gym.WAGON_ENV_ID} (trained: {IN_SERVICE})" in note
    env.close()


@pytest.mark.parametrize("suite, env, added", [("in-service", None, ["phase-rule-in-service", "interrogator-in-service"]),
                                               ("default", IN_SERVICE, ["phase-rule-in-service",
                                                                        "interrogator-in-service"]),
                                               ("default", None, []), ("paper", None, [])])
def test_without_agents_a_suite_played_on_v3_adds_the_agents_fitted_for_it(suite, env, added) -> None:
    """``cof-gym evaluate`` without ``--agents`` plays the default list, and on a suite played on the v3 id (its own or
    through ``--env``) the agents chosen or fitted for task v3 as well, in the registry's order; on a v2 suite the
    default list alone."""
    from cof_gym.commands.evaluate import add_arguments, prepare

    parser = argparse.ArgumentParser()
    add_arguments(parser)
    args = parser.parse_args(["--suite", suite, "--episodes", "2", *(["--env", env] if env else [])])
    specs, played, _ = prepare(args)
    assert specs == [n for n in registry.AGENTS if n in registry.default_agents() or n in added]
    assert played.env_id == (env or (IN_SERVICE if suite == "in-service" else cof_gym.WAGON_ENV_ID))
