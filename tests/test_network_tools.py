"""experiments/pool_ensembles.py: two ensembles pooled are one ensemble of all their members, whose mean is the
members' mean (the count-weighted mean of the two ensembles' means); experiments/match_creep_threshold.py: the
candidate's threshold (or its noise exponent) is exceeded as often as the reference's; Dataset.noise_ratios reads each
climb's ratio from its first windows, as the climb does."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR
from cof_gym.agents.interrogator.networks import FilterEnsemble

ROOT = Path(__file__).resolve().parents[1]
GUARD = SHIPPED_INTERROGATOR / "guard_0"


def test_pooled_members_are_copied_in_order_and_predict_their_mean(tmp_path: Path) -> None:
    out = tmp_path / "pool"
    run = subprocess.run([sys.executable, str(ROOT / "experiments" / "pool_ensembles.py"), "--out", str(out),
                          str(SHIPPED_INTERROGATOR), str(GUARD)], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    filter_, guard = FilterEnsemble.load(SHIPPED_INTERROGATOR), FilterEnsemble.load(GUARD)
    sources = sorted(SHIPPED_INTERROGATOR.glob("member_*.npz")) + sorted(GUARD.glob("member_*.npz"))
    pooled_files = [out / f"member_{k}.npz" for k in range(len(sources))]
    assert sorted(out.iterdir()) == sorted(pooled_files)
    assert all(p.read_bytes() == s.read_bytes() for p, s in zip(pooled_files, sources))
    pooled = FilterEnsemble.load(out)
    x = np.random.default_rng(3).normal(size=(4, len(filter_.members[0].feature_names)))
    weights = np.array([len(filter_.members), len(guard.members)]) / len(sources)
    expected = weights[0] * filter_.predict(x)[0] + weights[1] * guard.predict(x)[0]
    # the same float64 member outputs averaged in another grouping: ten terms, a few roundings of the largest apart
    largest = max(np.abs(m(x)[0]).max() for m in pooled.members)
    np.testing.assert_allclose(pooled.predict(x)[0], expected, rtol=0, atol=1e-13 * (1.0 + largest))
    assert f"{len(sources)} members ({len(filter_.members)} + {len(guard.members)})" in run.stdout


def test_the_matched_creep_threshold_is_the_candidates_quantile_at_the_references_trigger_share() -> None:
    sys.path.insert(0, str(ROOT / "experiments"))
    from match_creep_threshold import matched_threshold

    # half the reference's stds exceed 0.08; the candidate's median (its 0.5 quantile) is exceeded as often
    share, threshold = matched_threshold(np.array([0.05, 0.07, 0.09, 0.11]), np.array([1.0, 2.0, 3.0, 4.0, 5.0]), 0.08)
    assert (share, threshold) == (0.5, 3.0)
    share, threshold = matched_threshold(np.array([0.09, 0.1]), np.array([0.2, 0.4]), 0.08)  # always: its minimum
    assert (share, threshold) == (1.0, 0.2)


def test_the_matched_noise_exponent_makes_the_candidate_creep_as_often_on_noisy_climbs() -> None:
    sys.path.insert(0, str(ROOT / "experiments"))
    from match_creep_threshold import matched_exponent

    ratio = np.array([1.0, 2.0, 4.0, 4.0])
    reference = np.array([0.05, 0.2, 0.3, 0.5])  # above 0.08 r^1 (0.08, 0.16, 0.32, 0.32): 2 of 4
    candidate = np.array([0.5, 0.5, 0.5, 0.5])  # above 0.1 r^e where r^e < 5: all four at e = 1, two up to log2 5
    share, at_reference, exponent = matched_exponent(reference, candidate, ratio, 0.08, 1.0, 0.1)
    assert (share, at_reference) == (0.5, 1.0)
    # the largest exponent at which the candidate creeps as often (r = 2 stops creeping at log2 5), to the bisection's
    # tolerance
    assert abs(exponent - np.log(5.0) / np.log(2.0)) < 2e-6
    assert np.mean(candidate > 0.1 * ratio ** (exponent - 2e-6)) == share
    assert np.mean(candidate > 0.1 * ratio ** (exponent + 2e-6)) < share


def test_a_datasets_noise_ratios_are_each_climbs_first_windows_ratio() -> None:
    from dataclasses import astuple

    from cof_gym.agents.interrogator import ClimbParameters, Reading
    from cof_gym.agents.interrogator.training import Dataset

    def reading(se_deg: float) -> tuple:  # lock-in noise: radians(se) x compliance x amplitude / (2 pi f)
        return astuple(Reading(se_deg, se_deg, 2.0 * np.pi, 0.2, 0.01, 1000.0, 180.0 / np.pi, 1.0, 10.0, 1.0))

    rows = [reading(se) for se in (1.0, 3.0, 2.0, 40.0, 0.5, 0.5, 0.5)]  # climb 0: four windows, climb 1: three
    data = Dataset(np.array(rows), np.zeros(7, bool), np.zeros((7, 2)), np.array([0, 0, 0, 0, 1, 1, 1]))
    climb = ClimbParameters(noise_reference_nms=0.5)
    ratios = data.noise_ratios(climb)
    # climb 0: the median of its first three windows' noise (2 N m s) over 0.5, the fourth window not read; climb 1:
    # 0.5 N m s, a ratio of 1 (never below)
    np.testing.assert_allclose(ratios, [4.0] * 4 + [1.0] * 3, rtol=1e-12)
    assert (data.noise_ratios(ClimbParameters()) == 1.0).all()  # no reference: 1


def test_a_pool_read_within_generations_averages_each_generations_mean_and_variance(tmp_path: Path) -> None:
    out = tmp_path / "pool"
    run = subprocess.run([sys.executable, str(ROOT / "experiments" / "pool_ensembles.py"), "--within-generations",
                          "--out", str(out), str(SHIPPED_INTERROGATOR), str(GUARD)], capture_output=True, text=True,
                         cwd=ROOT)
    assert run.returncode == 0, run.stderr
    filter_, guard = FilterEnsemble.load(SHIPPED_INTERROGATOR), FilterEnsemble.load(GUARD)
    pooled = FilterEnsemble.load(out)
    assert pooled.generations == (len(filter_.members), len(guard.members))
    x = np.random.default_rng(5).normal(size=(4, len(filter_.members[0].feature_names)))
    (mean_f, std_f, spread_f), (mean_g, std_g, spread_g) = filter_.predict_with_spread(x), guard.predict_with_spread(x)
    mean, std, spread = pooled.predict_with_spread(x)
    # the same float64 member outputs, grouped as each generation's own prediction: a few roundings apart
    largest = max(np.abs(m(x)[0]).max() for m in pooled.members)
    np.testing.assert_allclose(mean, (mean_f + mean_g) / 2, rtol=0, atol=1e-13 * (1.0 + largest))
    np.testing.assert_allclose(std ** 2, (std_f ** 2 + std_g ** 2) / 2, rtol=1e-12)
    np.testing.assert_allclose(spread ** 2, (spread_f ** 2 + spread_g ** 2) / 2, rtol=1e-12, atol=1e-300)
    # read as one generation, the generations' disagreement adds to the variance: never below the within reading
    _, std_all, _ = FilterEnsemble(pooled.members).predict_with_spread(x)
    assert (std_all >= std * (1 - 1e-12)).all()


def test_generations_must_count_every_member() -> None:
    members = FilterEnsemble.load(GUARD).members
    for bad in ((len(members) - 1,), (0, len(members)), (True, len(members) - 1)):
        with pytest.raises(ValueError, match="generations"):
            FilterEnsemble(members, bad)


def test_a_within_generations_pool_keeps_its_reading_in_an_assembled_policy_and_its_digest(tmp_path: Path,
                                                                                           monkeypatch) -> None:
    monkeypatch.syspath_prepend(str(ROOT / "experiments"))
    from assemble_policy import assemble
    from train_estimator import policy_digest

    from cof_gym.agents.interrogator.networks import GENERATIONS_FILE

    pool = tmp_path / "pool"
    run = subprocess.run([sys.executable, str(ROOT / "experiments" / "pool_ensembles.py"), "--within-generations",
                          "--out", str(pool), str(SHIPPED_INTERROGATOR), str(GUARD)], capture_output=True, text=True,
                         cwd=ROOT)
    assert run.returncode == 0, run.stderr
    assemble(pool, [pool], SHIPPED_INTERROGATOR, tmp_path / "policy")
    for directory in (tmp_path / "policy", tmp_path / "policy" / "guard_0"):
        assert FilterEnsemble.load(directory).generations == FilterEnsemble.load(pool).generations
    within = policy_digest(tmp_path / "policy")
    for directory in (tmp_path / "policy", tmp_path / "policy" / "guard_0"):
        (directory / GENERATIONS_FILE).unlink()
    assert policy_digest(tmp_path / "policy") != within  # the reading steers: the digest covers it
