"""The learned interrogator with a two-tone excitation: the action it sends, the readings it takes of
tone 2, the features and files of its filter, and the env ``cof-gym evaluate`` makes for it."""

from __future__ import annotations

import dataclasses

import csv
import json
import math
from dataclasses import asdict

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator import (
    FEATURE_NAMES, TWO_TONE_ENV_OPTIONS, ClimbParameters, EpisodeFeatures, FilterEnsemble, FilterNetwork,
    LearnedInterrogator, Reading, feature_names, interrogator_for,
)
from cof_gym.agents.interrogator.training import ClimbDraws, Dataset, FitSettings, collect, fit_member
from cof_gym.commands.evaluate import evaluate
from cof_gym.commands.suites import make_suite
from cof_gym.commands.watch import WatchRequest, play
from cof_gym.task.excitation import Excitation, encode_extra_tones

TWO_TONES = ClimbParameters(amplitude_ratio=0.3, tone2_frequency_hz=14.0, tone2_weight=0.8)


@pytest.fixture(scope="module")
def two_tone_data() -> Dataset:
    return collect(cof_gym.WAGON_ENV_ID, [{}, {"counter_torque": True}], 6, first_seed=2_100_000,
                   draws=ClimbDraws(tone2_hz=(10.0, 20.0)))


@pytest.fixture(scope="module")
def two_tone_member(two_tone_data) -> FilterNetwork:
    return fit_member(two_tone_data, seed=0, settings=FitSettings(hidden=(8,), epochs=5, batch_size=64))


@pytest.mark.parametrize("frequency_hz, weight", [(14.0, 0.8), (1.0, 0.0), (20.0, 2.0), (9.0, 1.0)])
def test_extra_tone_encoding_is_the_decoders_inverse(frequency_hz, weight):
    excitation = Excitation("multitone", tones=2)
    base = cof_gym.physics.simulation.DriveCommand(1000.0, 300.0, 5.0)  # tone 2 kept 2 / T = 3.3 Hz away
    drive = excitation.drive(base, encode_extra_tones([(frequency_hz, weight)]))
    (a1, f1), (a2, f2) = drive.tones
    assert f2 == pytest.approx(frequency_hz, rel=1e-6)
    assert a2 / 300.0 == pytest.approx(weight / (1.0 + weight), abs=1e-6)
    assert a1 + a2 == pytest.approx(300.0, rel=1e-12)


def test_two_tone_climb_needs_its_env_and_reads_tone_2():
    env = gym.make(cof_gym.WAGON_ENV_ID, **TWO_TONE_ENV_OPTIONS)
    limits = env.unwrapped.limits
    obs, info = env.reset(seed=3)
    action = TWO_TONES.action(2000.0, 0.2, False, limits)
    assert action.shape == env.action_space.shape == (7,)
    obs, _, _, _, info = env.step(action)
    m = info["measurement"]
    r = Reading.of(obs, limits, info)
    assert r.tone2_frequency_hz == pytest.approx(14.0, rel=1e-6)
    assert r.tone2_amplitude_nm == pytest.approx(0.3 * 2000.0 * 0.8 / 1.8, rel=1e-4)
    assert r.tone2_phase_deg == pytest.approx(m["tone2_phase_lag_deg"], abs=1e-4)  # float32 observation
    assert r.phase_deg == pytest.approx(m["tone1_phase_lag_deg"], abs=1e-4)
    sine = gym.make(cof_gym.WAGON_ENV_ID)
    obs, info = sine.reset(seed=3)
    assert Reading.of(obs, limits, info).tone2_frequency_hz == 0.0  # a sine reads no tone 2
    agent = LearnedInterrogator(limits, FilterEnsemble((FilterNetwork(*_zeros(feature_names(("tone2",)))),)), params=TWO_TONES)
    with pytest.raises(ValueError, match="excitation"):
        agent.reset(obs, info)


def _zeros(names):
    n = len(names)
    return np.zeros(n), np.ones(n), (np.zeros((n, 4)),), (np.zeros(4),), names


def test_features_files_and_ensemble_agree_on_the_tones(two_tone_data, two_tone_member, tmp_path):
    assert two_tone_data.tones == 2
    assert two_tone_data.features.shape[1] == len(feature_names(("tone2",))) == len(FEATURE_NAMES) + 11
    assert np.all(np.isfinite(two_tone_data.features))
    two_tone_member.save(tmp_path / "member_0.npz")
    loaded = FilterNetwork.load(tmp_path / "member_0.npz")
    assert loaded.tones == 2 and loaded.feature_names == feature_names(("tone2",))
    one = FilterNetwork(*_zeros(feature_names()))
    with pytest.raises(ValueError, match="different features"):
        FilterEnsemble((loaded, one))
    with pytest.raises(ValueError, match="networks read"):
        LearnedInterrogator(gym.make(cof_gym.WAGON_ENV_ID).unwrapped.limits, FilterEnsemble((one,)), params=TWO_TONES)
    with pytest.raises(ValueError, match="two-tone readings"):
        EpisodeFeatures(False, blocks=("tone2",)).push(Reading(10.0, 1.0, 0.5, 0.1, 0.01, 1000.0, 100.0, 5.0, 20.0, 1.0))
    mixed = Dataset.concatenate([two_tone_data, collect(cof_gym.WAGON_ENV_ID, [{}], 1, first_seed=2_100_100)])
    with pytest.raises(ValueError, match="mixes"):
        mixed.tones


def test_older_datasets_load_with_the_later_reading_fields_defaulted(two_tone_data, tmp_path):
    sine = collect(cof_gym.WAGON_ENV_ID, [{}], 2, first_seed=2_100_200)
    old = 10  # the reading fields before tone 2's
    np.savez(tmp_path / "old.npz", readings=sine.readings[:, :old], counter_torque=sine.counter_torque,
             targets=sine.targets, episode=sine.episode,
             reading_fields=np.asarray([f for f in Reading.__dataclass_fields__][:old]))
    loaded = Dataset.load(tmp_path / "old.npz")
    np.testing.assert_array_equal(loaded.readings[:, :old], sine.readings[:, :old])
    defaults = [f.default for f in dataclasses.fields(Reading)[old:]]
    np.testing.assert_array_equal(loaded.readings[:, old:], np.broadcast_to(defaults, (len(sine.readings), len(defaults))))
    np.testing.assert_array_equal(loaded.features, sine.features)  # the default features read none of them


def test_evaluate_plays_a_two_tone_interrogator_in_its_own_env_on_the_same_scenarios(two_tone_member, tmp_path):
    run = tmp_path / "two_tone"
    run.mkdir()
    two_tone_member.save(run / "member_0.npz")
    (run / "manifest.json").write_text(json.dumps({"climb": asdict(TWO_TONES)}))
    suite = make_suite("default", 2, 0)
    result = evaluate(["phase-rule", f"interrogator:{run}"], suite, tmp_path / "out", 0, quiet=True, windows=True)
    with open(tmp_path / "out" / "episodes.csv") as fh:
        rows = list(csv.DictReader(fh))
    with open(tmp_path / "out" / "windows.csv") as fh:  # the multitone env's steps, as the sine env's
        steps = list(csv.DictReader(fh))
    assert len(steps) == sum(int(row["steps"]) for row in rows)
    assert {s["agent"] for s in steps} == {row["agent"] for row in rows}
    by_agent = {}
    for row in rows:
        by_agent.setdefault(row["agent"], []).append((row["seed"], row["cof"]))
    assert len(by_agent) == 2
    first, second = by_agent.values()
    assert first == second  # the same scenarios and ground truth for both agents
    assert result["suite"] == suite.name
    env = gym.make(cof_gym.WAGON_ENV_ID)
    assert interrogator_for(env, run).env_options == TWO_TONE_ENV_OPTIONS
    assert all(math.isfinite(float(r["relative_error"])) for r in rows)
    record, recorder = play(WatchRequest(f"interrogator:{run}", False, cof_gym.WAGON_ENV_ID, suite.episodes[0][0],
                                         tmp_path / "v.mp4", 10, 320, 1.0))  # cof-gym watch's episode
    recorder.close()
    assert record.cof == float(by_agent[f"interrogator:{run.name}"][0][1])
