"""experiments/knee_twins.py: a far-peaking creep curve as a table, its near twin, and what an agent tells apart."""

from __future__ import annotations

import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"
sys.path.insert(0, str(EXPERIMENTS))
import knee_twins as kt  # noqa: E402

import cof_gym  # noqa: E402
from cof_gym.agents import registry  # noqa: E402
from cof_gym.commands.suites import make_suite  # noqa: E402
from cof_gym.physics.creep import OperatingConditions, creep_curve  # noqa: E402
from cof_gym.physics.creep_laws import TableShape, creep_law_from_spec  # noqa: E402
from cof_gym.task.ground_truth import ground_truth  # noqa: E402

FAR, DIPPING = 4, 52  # default-suite episodes: a Polach curve peaking at 5.1 % creepage; one with a dip before its peak


@pytest.fixture(scope="module")
def env():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    yield env
    env.close()


def _truth(env, episode: int) -> dict:
    seed, options = make_suite("default", 60, 0).episodes[episode]
    return env.reset(seed=seed, options=options)[1]["ground_truth"]


def test_the_far_curve_is_the_ground_truths_curve_at_its_knots_and_peaks_at_its_peak_creepage(env):
    truth = _truth(env, FAR)
    table = kt.tabulated_curve(env, truth)
    TableShape(tuple(table["creepage"]), tuple(table["adhesion_ratio"]))  # the env's own validation
    peak = table["adhesion_ratio"].index(1.0)
    assert table["creepage"][peak] == truth["peak_creepage"] >= 0.04
    task = env.unwrapped.task
    shape = creep_law_from_spec(truth["creep_law"])
    _, load = ground_truth(task.model(truth["load_case"]), task.balanced, truth["cof"], shape, truth["speed_m_s"])
    op = OperatingConditions(truth["cof"], shape, load, truth["speed_m_s"])
    knots = np.array(table["creepage"][1:peak])  # the same native curve, divided by the CoF
    np.testing.assert_array_equal(np.array(table["adhesion_ratio"][1:peak]), creep_curve(knots, op)[0] / truth["cof"])
    assert kt.tabulated_curve(env, _truth(env, DIPPING)) is None  # a dip before the peak: no table holds it


@pytest.mark.parametrize("ratio", [1.25, 1.5])
def test_the_near_twin_has_the_same_force_up_to_its_top_and_peaks_ratio_times_lower(env, ratio):
    far = kt.tabulated_curve(env, _truth(env, FAR))
    near = kt.near_twin(far, ratio)
    TableShape(tuple(near["creepage"]), tuple(near["adhesion_ratio"]))
    shared = int(np.argmax(np.array(far["adhesion_ratio"]) >= 1.0 / ratio))  # the far curve's points below the top
    assert near["creepage"][:shared] == far["creepage"][:shared]
    # force = CoF x ratio: the twin's (CoF / R) x (ratio x R) is the far curve's, at every shared point
    np.testing.assert_allclose(np.divide(near["adhesion_ratio"][:shared], ratio), far["adhesion_ratio"][:shared],
                               rtol=1e-12, atol=0)
    assert max(near["adhesion_ratio"]) == 1.0 and np.all(np.diff(near["adhesion_ratio"][:near["adhesion_ratio"].index(1.0) + 1]) > 0)
    with pytest.raises(ValueError, match="ratio"):
        kt.near_twin(far, 1.0)


def test_the_phase_rule_drives_both_alike_and_reports_one_estimate_for_two_cofs(env):
    """It stops at the far curve's knee, below the twin's top: one estimate for CoFs 1.5 apart, so more than
    8 % off on at least one of them (1.5 > 1.08 / 0.92)."""
    seed, options = make_suite("default", 60, 0).episodes[FAR]
    pair_options = kt.pair_options(env, seed, options, 1.5, 0.04)
    assert pair_options[1]["cof"] == pytest.approx(pair_options[0]["cof"] / 1.5, rel=1e-15)
    pair = kt.play_pair(env, kt.ActionLog(registry.make_agent("phase-rule", env)), seed, pair_options, FAR)
    assert pair["alike"] and not (pair["far"].macro_slip or pair["near"].macro_slip)
    assert pair["near"].estimate == pytest.approx(pair["far"].estimate, rel=1e-6)
    assert max(pair["far"].relative_error, pair["near"].relative_error) > 0.08
    assert kt.pair_options(env, seed, options, 1.5, 0.2) is None  # peaks below 20 % creepage: not a far curve


@pytest.mark.parametrize("args, option", [(["--ratio", "1"], "--ratio"), (["--tolerance", "0"], "--tolerance"),
                                          (["--min-peak-creepage", "1"], "--min-peak-creepage"),
                                          (["--agents", "oracle"], "--agents"), (["--suite", "no/such.json"], "--suite")])
def test_bad_options_exit_2_naming_the_option(args, option, tmp_path, experiment_exit):
    code, last = experiment_exit("knee_twins", [*args, "--out", str(tmp_path / "t.md")])
    assert code == 2 and option in last
    assert not (tmp_path / "t.md").exists()
