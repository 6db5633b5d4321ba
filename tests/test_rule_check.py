"""experiments/rule_check.py: a candidate's runaways, paired error and return CIs checked against a rule's
conditions; exit 0 where they hold, 1 where they fail, 2 (one line) for a records file it cannot judge."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"
sys.path.insert(0, str(EXPERIMENTS))
from paired_comparison import paired  # noqa: E402
from rule_check import Conditions, check  # noqa: E402

ERRORS = np.random.default_rng(7).uniform(0.0, 0.3, 60)


def records(setting: str, errors: np.ndarray, slips: dict[str, set[int]] | None = None) -> list[dict]:
    """One setting's episodes on two grids (family, steep), each error's return its negative (a runaway: -10
    more), ``slips``: the runaway episodes per grid."""
    slips = slips or {}
    return [{"setting": setting, "grid": grid, "config": {}, "episode": i, "error": float(e),
             "macro_slip": i in slips.get(grid, set()),
             "episode_return": -float(e) - (10.0 if i in slips.get(grid, set()) else 0.0)}
            for grid in ("family", "steep") for i, e in enumerate(errors)]


DISPLAYED = 5e-5 + 1e-12  # a return shown with 4 decimals: half its last digit, and the sums' rounding


def shown_returns(failure: str) -> tuple[float, float]:
    """The (candidate, baseline) mean returns a failed --gain condition shows."""
    match = re.fullmatch(r"all: mean return (\S+) not above (\S+)", failure)
    assert match, failure
    return float(match[1]), float(match[2])


def judged(base: list[dict], candidate: list[dict], conditions: Conditions) -> list[str]:
    return check([paired(base, base[0]["setting"])], [paired(candidate, candidate[0]["setting"])], conditions)[1]


def test_the_same_episodes_meet_every_condition_but_a_gain() -> None:
    base, same = records("base", ERRORS), records("same", ERRORS)
    assert judged(base, same, Conditions(errors=True, returns=True)) == []
    (failed,) = judged(base, same, Conditions(gain=True))
    assert shown_returns(failed) == pytest.approx((-np.mean(ERRORS),) * 2, abs=DISPLAYED)


def test_no_loss_holds_for_the_same_episodes_and_fails_for_a_lower_mean_return() -> None:
    base = records("base", ERRORS)
    assert judged(base, records("same", ERRORS), Conditions(no_loss=True)) == []
    (failed,) = judged(base, records("worse", ERRORS * 1.01), Conditions(no_loss=True))
    assert failed.startswith("all: mean return") and " below " in failed
    assert judged(base, records("better", ERRORS * 0.99), Conditions(no_loss=True)) == []


def test_a_gated_candidates_climbs_are_counted_with_those_that_ended_otherwise() -> None:
    base = paired(records("base", ERRORS), "base")
    gated = records("gated", ERRORS, {"steep": {3}})
    for r in gated:
        r["gated"] = r["episode"] in (3, 4)
        r["ended"], r["peak_torque_fraction"] = "macro-slip" if r["macro_slip"] else "headroom", 1.0
    base_records = records("base", ERRORS)
    for r in base_records:
        r["ended"], r["peak_torque_fraction"] = "headroom", 1.0
    lines, _ = check([paired(base_records, "base")], [paired(gated, "gated")], Conditions(more_runaways=1))
    assert lines[-1] == f"- gated: 4 of {2 * len(ERRORS)} climbs in the candidate's plays; 1 ended otherwise than " \
        "the baseline's"
    assert not any(line.startswith("- gated") for line in check([base], [base], Conditions())[0])


def test_a_family_runaway_fails_unless_the_strict_grid_is_another_and_the_total_allows_it() -> None:
    base, more = records("base", ERRORS), records("more", ERRORS, {"family": {3}})
    failed = judged(base, more, Conditions())
    assert [f.split(":")[0] for f in failed] == ["family", "all"]
    assert judged(base, more, Conditions(more_runaways=1, strict_grid="steep")) == []
    assert judged(base, records("steep", ERRORS, {"steep": {3}}), Conditions(more_runaways=1)) == []


def test_doubled_errors_fail_the_error_and_return_conditions_on_every_grid() -> None:
    failed = judged(records("base", ERRORS), records("doubled", 2.0 * ERRORS), Conditions(errors=True, returns=True))
    for grid in ("family", "steep"):
        assert any(f.startswith(f"{grid}: median higher") for f in failed)
        assert any(f.startswith(f"{grid}: P90 higher") for f in failed)
        assert any(f.startswith(f"{grid}: return lower") for f in failed)
    assert judged(records("base", ERRORS), records("halved", ERRORS / 2), Conditions(errors=True, returns=True,
                                                                                        gain=True)) == []


def test_the_command_exits_0_where_the_conditions_hold_1_where_they_fail_and_2_for_two_settings(tmp_path: Path) -> None:
    files = {}
    for name, recs in {"base": records("base", ERRORS), "halved": records("halved", ERRORS / 2),
                       "both": records("a", ERRORS) + records("b", ERRORS)}.items():
        files[name] = tmp_path / f"{name}.json"
        files[name].write_text(json.dumps(recs))

    def run(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, str(EXPERIMENTS / "rule_check.py"), *map(str, args)],
                              capture_output=True, text=True)

    held = run(files["base"], files["halved"], "--errors", "--returns", "--gain", "--out", tmp_path / "v.md")
    assert held.returncode == 0 and held.stdout.endswith("\nholds\n"), held.stderr
    assert (tmp_path / "v.md").read_text().endswith("\nholds\n")
    failed = run(files["halved"], files["base"], "--errors")
    assert failed.returncode == 1 and failed.stdout.endswith("\nfails\n") and "- fails: family: median" in failed.stdout
    two = run(files["both"], files["base"])
    assert two.returncode == 2 and two.stderr.count("\n") == 1 and "holds 2 settings" in two.stderr
    both = run(files["base"], files["halved"], "--gain", "--no-loss")
    assert both.returncode == 2 and "--no-loss" in both.stderr and both.stdout == ""
    grid = run(files["base"], files["halved"], "--strict-grid", "procedural")
    assert grid.returncode == 2 and "--strict-grid" in grid.stderr and grid.stdout == ""


def test_pairs_of_plays_count_their_runaways_and_returns_together() -> None:
    base = paired(records("base", ERRORS), "base")
    steep = paired(records("steep", ERRORS, {"steep": {3}}), "steep")
    better = paired(records("better", ERRORS / 2), "better")
    assert check([base], [steep], Conditions(more_runaways=1))[1] == []  # one play: one more allowed
    lines, failed = check([base, base], [steep, steep], Conditions(more_runaways=1))
    assert failed == ["all: 2 runaways against 0 (at most 1 more)"]
    assert lines[0].startswith("- 1, family: ") and lines[2].startswith("- 2, family: ")
    # the mean return over both plays' 240 episodes: -0.75 x mean error - 10 / 240 against -mean error
    expected = -0.75 * float(np.mean(ERRORS)) - 10.0 / 240.0
    gained = expected > -float(np.mean(ERRORS))
    failed = check([base, base], [steep, better], Conditions(more_runaways=1, gain=True))[1]
    assert len(failed) == (0 if gained else 1)
    if failed:
        assert shown_returns(failed[0]) == pytest.approx((expected, -np.mean(ERRORS)), abs=DISPLAYED)
    assert check([base, base], [better, better], Conditions(gain=True))[1] == []


def test_an_odd_number_of_files_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "base.json"
    path.write_text(json.dumps(records("base", ERRORS)))
    run = subprocess.run([sys.executable, str(EXPERIMENTS / "rule_check.py"), str(path), str(path), str(path)],
                         capture_output=True, text=True)
    assert run.returncode == 2 and "in pairs" in run.stderr and run.stderr.count("\n") == 1


def test_fewer_runaways_needs_strictly_fewer_and_error_grid_checks_that_grid_alone() -> None:
    base = records("base", ERRORS, {"steep": {3, 4}})
    fewer = records("fewer", ERRORS, {"steep": {3}})
    assert judged(base, fewer, Conditions(fewer_runaways=True)) == []
    assert judged(base, base, Conditions(fewer_runaways=True)) == ["all: 2 runaways against 2 (strictly fewer needed)"]
    # doubled errors on the steep grid alone: --errors fails there, --error-grid family passes
    worse_steep = [{**r, "error": 2.0 * r["error"]} if r["grid"] == "steep" else r for r in records("w", ERRORS)]
    assert {f.split(":")[0] for f in judged(records("base", ERRORS), worse_steep, Conditions(errors=True))} == {"steep"}
    assert judged(records("base", ERRORS), worse_steep, Conditions(errors=True, error_grid="family")) == []


def test_error_grid_needs_errors_and_a_grid_the_records_have(tmp_path: Path) -> None:
    path = tmp_path / "base.json"
    path.write_text(json.dumps(records("base", ERRORS)))
    for args, said in ((["--error-grid", "family"], "needs --errors"),
                       (["--errors", "--error-grid", "procedural"], "no grid 'procedural'"),
                       (["--fewer-runaways", "--more-runaways", "1"], "not allowed with")):
        run = subprocess.run([sys.executable, str(EXPERIMENTS / "rule_check.py"), str(path), str(path), *args],
                             capture_output=True, text=True)
        assert run.returncode == 2 and said in run.stderr and run.stderr.count("\n") == 1, run.stderr


def with_climbs(recs: list[dict], peak: float = 1.0, moved: int | None = None) -> list[dict]:
    """``recs`` with where each climb ended (its stop) at the peak torque ``peak`` (``moved``: that episode's
    peak torque 1 % higher on every grid)."""
    return [{**r, "ended": "stop", "peak_torque_fraction": peak * (1.01 if r["episode"] == moved else 1.0)}
            for r in recs]


def test_same_climbs_holds_for_an_estimate_only_change_and_fails_on_one_climb_that_moved() -> None:
    base = with_climbs(records("base", ERRORS))
    estimate_only = with_climbs(records("halved", ERRORS / 2))
    assert judged(base, estimate_only, Conditions(same_climbs=True, errors=True, gain=True)) == []
    failed = judged(base, with_climbs(records("moved", ERRORS / 2), moved=4), Conditions(same_climbs=True))
    assert failed == [f"{grid}: 1 climbs ended otherwise than the baseline's (the same climbs needed)"
                      for grid in ("family", "steep")]
    assert judged(base, with_climbs(records("moved", ERRORS / 2), moved=4), Conditions()) == []  # not asked


def test_same_climbs_on_records_without_the_climb_fields_is_a_usage_error(tmp_path: Path) -> None:
    path = tmp_path / "bare.json"
    path.write_text(json.dumps(records("base", ERRORS)))
    run = subprocess.run([sys.executable, str(EXPERIMENTS / "rule_check.py"), str(path), str(path), "--same-climbs"],
                         capture_output=True, text=True)
    assert run.returncode == 2 and "has no 'ended'" in run.stderr and "Traceback" not in run.stderr


def test_discordant_climbs_count_each_play_alone_and_the_sign_test_is_the_exact_binomial_tail() -> None:
    base = records("base", ERRORS, {"steep": {1, 2, 6}})
    candidate = records("candidate", ERRORS, {"steep": {2, 3, 4}, "family": {5, 7}})
    lines, failed = check([paired(base, "base")], [paired(candidate, "candidate")], Conditions(discordant=True))
    # 2 alone in the baseline's (1, 6), 4 in the candidate's (3, 4, family 5, 7): P(X >= 4 | 6 flips) = 22/64,
    # 0.34375, shown 0.344 (a quarter of the last digit from a rounding boundary)
    assert lines[-1] == ("- discordant climbs: 2 ran away in the baseline's play alone, 4 in the candidate's alone "
                         "(one-sided exact sign test p = 0.344)")
    assert [line.rsplit("; ", 1)[1] for line in lines[:2]] == ["ran away alone 0 / 2", "ran away alone 2 / 2"]
    assert [f.split(":")[0] for f in failed] == ["family", "all"]  # information only: the conditions are unchanged
    assert not any("discordant" in line for line in check([paired(base, "base")], [paired(candidate, "candidate")],
                                                           Conditions())[0])


def test_family_wise_cis_are_wider_by_the_number_of_intervals_read_and_pass_a_lone_95_percent_excess() -> None:
    noise = np.random.default_rng(11).normal(size=ERRORS.size)
    noise = (noise - noise.mean()) / noise.std(ddof=1)
    # errors 0.05 x (noise + 0.31) higher: the return's paired difference has a t statistic of 0.31 sqrt(60) = 2.4,
    # between the 95 % CI's 1.96 and the 2.81 of five pairs' simultaneous ones (10 intervals, 0.25 % in each tail)
    worse = records("worse", ERRORS + 0.05 * (noise + 2.4 / np.sqrt(ERRORS.size)))
    bases, candidates = [paired(records("base", ERRORS), "base")] * 5, [paired(worse, "worse")] * 5
    _, failed = check(bases, candidates, Conditions(returns=True))
    assert len(failed) == 10 and all("return lower with a CI wholly below zero" in f for f in failed)
    lines, failed = check(bases, candidates, Conditions(returns=True, family_wise=True))
    assert failed == []
    assert lines[0] == "- family-wise: 10 intervals, each leaving 0.25 % out on either side (20000 resamples)"
    # the grid lines print the 95 % CIs either way
    assert lines[1:] == check(bases, candidates, Conditions(returns=True))[0]
    # errors doubled stay beyond any simultaneous CI
    _, failed = check(bases, [paired(records("doubled", 2.0 * ERRORS), "doubled")] * 5,
                      Conditions(errors=True, returns=True, family_wise=True))
    assert failed and all("a family-wise CI wholly" in f for f in failed)


def test_the_sign_test_condition_rejects_five_climbs_alone_of_five_and_not_four_of_four() -> None:
    base = records("base", ERRORS)
    slips = lambda n: records("candidate", ERRORS, {"steep": set(range(n))})  # noqa: E731
    # P(X >= 4 | 4 flips) = 1/16 = 0.0625: not below 0.05; P(X >= 5 | 5) = 1/32 = 0.03125: below
    assert judged(base, slips(4), Conditions(more_runaways=10, sign_test=True)) == []
    (failed,) = judged(base, slips(5), Conditions(more_runaways=10, sign_test=True))
    assert failed == "all: the candidate runs away more often by the one-sided sign test (p = 0.031 < 0.05)"
    assert judged(base, slips(5), Conditions(more_runaways=10)) == []  # without it, the total's bound alone
