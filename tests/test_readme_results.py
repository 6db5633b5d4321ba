"""experiments/readme_results.py: the README's targets and held-out overview are computed from the
evaluate summaries as stated (the learned agent against the agents that do not read the truth), and
every block lands in the document that holds it."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
from readme_results import (DOCUMENTS, GENERATED, SOURCES, at_a_glance, edge_suites, fill,  # noqa: E402
                            heldout_overview, heldout_peak_creepage, heldout_shapes, horizon, horizon_by_condition,
                            horizon_ends, paired_targets, paper_setting, peak_creepage, rate_interval, slip_failed,
                            slip_rates, targets, targets_count, with_horizon)


def _summary(path: Path, agents: dict[str, tuple[bool, float, float, int]], episodes: int = 50,
             peak_torque: float = 0.85) -> Path:
    """agents: name -> (oracle, median, P90, macro-slips); every agent's mean peak torque ``peak_torque``."""
    summary = {name: {"oracle": oracle, "episodes": episodes, "median_error": {"value": med},
                      "p90_error": {"value": p90}, "macro_slip_events": {"value": slips},
                      "peak_torque_fraction": {"value": peak_torque},
                      # a macro-slip counted as a failed measurement: the median moves by the share of them
                      "median_error_slip_failed": {"value": med + slips / episodes}}
               for name, (oracle, med, p90, slips) in agents.items()}
    path.write_text(json.dumps({"summary": summary}))
    return path


def test_targets_compare_with_the_best_agent_that_does_not_read_the_truth(tmp_path):
    path = _summary(tmp_path / "a.json", {"oracle": (True, 0.001, 0.002, 0), "learned": (False, 0.025, 0.09, 0),
                                          "rule": (False, 0.05, 0.08, 0), "fit": (False, 0.03, 0.2, 3)})
    rows = targets({"suite": path}, learned="learned").splitlines()[2:]
    met = {row.split(" | ")[1]: row.endswith("| met |") for row in rows}
    assert met == {"median <= 3 %": True, "P90 <= 8 %": False, "<= 1 macro-slip per 100 episodes": True,
                   "median below every non-oracle agent's": True, "P90 below every non-oracle agent's": False,
                   "no more macro-slips than the best non-oracle agent": True,
                   "stretch: median <= 5 % committed at <= 90 % of M_sat (mean peak torque)": True}
    assert "2.5 % vs fit 3.0 %" in rows[3] and "9.0 % vs rule 8.0 %" in rows[4]  # the oracle is never the rival
    late = _summary(tmp_path / "b.json", {"learned": (False, 0.025, 0.09, 0), "rule": (False, 0.05, 0.08, 0)},
                    peak_torque=0.95)
    assert targets({"suite": late}, learned="learned").splitlines()[-1].endswith("2.5 % at 95.0 % | **not met** |")
    assert targets({"suite": tmp_path / "missing.json"}, learned="learned") is None


def test_targets_count_counts_the_rows_met_and_the_misses_off_the_first_suite(tmp_path):
    # the first suite (the default one) misses its P90 rows (2 of 7); the grid misses those and its median rows (4)
    first = _summary(tmp_path / "a.json", {"learned": (False, 0.025, 0.09, 0), "rule": (False, 0.05, 0.08, 0)})
    grid = _summary(tmp_path / "b.json", {"learned": (False, 0.035, 0.09, 0), "rule": (False, 0.03, 0.08, 0)})
    assert targets_count({"default": first, "grid": grid}, learned="learned") == (
        "8 of the 14 target rows are met; of the 6 it misses, 4 are on the held-out grids.")
    assert targets_count({"default": tmp_path / "missing.json"}, learned="learned") is None


def test_at_a_glance_puts_the_learned_agent_first_and_sums_the_grids_macro_slips(tmp_path):
    first = _summary(tmp_path / "a.json", {"oracle": (True, 0.001, 0.002, 0), "rule": (False, 0.05, 0.08, 3),
                                           "learned": (False, 0.025, 0.09, 0)})
    grids = {name: _summary(tmp_path / f"{name}.json", {"oracle": (True, 0.001, 0.002, 0), "rule": (False, m, 0.3, k),
                                                        "learned": (False, m / 2, 0.2, k // 2)}, episodes=72)
             for name, m, k in (("g1", 0.05, 9), ("g2", 0.1, 4))}
    rows = at_a_glance({"default": first, **grids}, learned="learned").splitlines()
    assert rows[0].startswith("| agent (no ground truth) | default suite: median / P90 / macro-slips (50) | "
                              "2 held-out grids: macro-slips (144) |")
    assert rows[0].endswith("| held-out grids: median with a macro-slip counted as 100 %, lowest - highest |")
    # failed-measurement medians: learned 2.5 + 4/72 and 5.0 + 2/72 %; rule 5.0 + 9/72 and 10.0 + 4/72 %
    assert rows[2:4] == ["| learned | 2.5 % / 9.0 % / 0 | 6 | 2.5 - 5.0 % | 7.8 - 8.1 % |",
                         "| rule | 5.0 % / 8.0 % / 3 | 13 | 5.0 - 10.0 % | 15.6 - 17.5 % |"]
    assert rows[-1] == "14 of the 21 target rows are met; of the 7 it misses, 5 are on the held-out grids."
    assert at_a_glance({"default": first, "g": tmp_path / "missing.json"}, learned="learned") is None


def test_heldout_overview_names_the_best_other_agent_per_column(tmp_path):
    out = tmp_path / "grid"
    out.mkdir()
    _summary(out / "summary.json", {"oracle": (True, 0.001, 0.002, 0), "learned": (False, 0.04, 0.3, 5),
                                     "rule": (False, 0.06, 0.25, 7), "fit": (False, 0.05, 0.5, 2)}, episodes=72)
    rows = heldout_overview({"grid": ("v2 a held-out grid", out)}, learned="learned").splitlines()
    assert rows[2] == "| a held-out grid (72) | 4.0 % / 30.0 % / 5 | fit 5.0 % | rule 25.0 % | fit 2 |"



def test_heldout_shapes_sets_each_shape_beside_the_fewest_macro_slips_of_the_others(tmp_path):
    out = tmp_path / "grid"
    out.mkdir()
    path = _summary(out / "summary.json", {"oracle": (True, 0.001, 0.002, 0), "learned": (False, 0.04, 0.3, 5),
                                            "rule": (False, 0.06, 0.25, 7), "fit": (False, 0.05, 0.5, 2)})
    data = json.loads(path.read_text())
    slips = {"oracle": (0, 0), "learned": (4, 1), "rule": (3, 4), "fit": (3, 9)}  # agent -> (cliff, knee)
    for agent, (cliff, knee) in slips.items():
        data["summary"][agent]["breakdown"] = {
            "dry (25)": {"episodes": 25, "median_error": 0.5, "macro_slip_events": 0},  # not a note: left out
            "note cliff": {"episodes": 18, "median_error": 0.021, "macro_slip_events": cliff},
            "note knee": {"episodes": 18, "median_error": 0.1, "macro_slip_events": knee}}
    path.write_text(json.dumps(data))
    rows = heldout_shapes({"grid": ("v2 a held-out grid", out)}, learned="learned").splitlines()
    assert rows[2:] == ["| a held-out grid | cliff (18) | 4 | 2.1 % | rule, fit 3 |",  # ties: both, never the oracle
                        "| a held-out grid | knee (18) | 1 | 10.0 % | rule 4 |"]
    assert heldout_shapes({"grid": ("g", tmp_path / "missing")}, learned="learned") is None


def test_horizon_by_condition_counts_the_learned_agents_horizon_ends_per_condition(tmp_path):
    out = tmp_path / "run"
    out.mkdir()
    rows = [("learned", "dry", "horizon", "0.04"), ("learned", "dry", "horizon", "-0.08"),
            ("learned", "dry", "stop", "0.5"), ("learned", "wet", "stop", "0.01"),
            ("rule", "wet", "horizon", "0.3")]  # another agent's: not counted
    (out / "episodes.csv").write_text("agent,condition,ended,relative_error\n"
                                      + "".join(",".join(r) + "\n" for r in rows))
    table = horizon_by_condition({"s": ("a suite", out)}, learned="learned").splitlines()
    assert table[2:] == ["| a suite | dry | 3 | 2 | 6.0 % |", "| a suite | wet | 1 | 0 | - |"]  # |errors|' median
    assert horizon_by_condition({"s": ("a suite", tmp_path / "missing")}, learned="learned") is None

def test_slip_failed_compares_each_measure_with_the_lowest_other_and_says_ties(tmp_path):
    path = _summary(tmp_path / "a.json", {"oracle": (True, 0.001, 0.002, 0), "learned": (False, 0.04, 0.3, 5),
                                          "rule": (False, 0.06, 0.25, 7), "fit": (False, 0.05, 0.5, 2)}, episodes=72)
    assert slip_failed({"suite": path}, learned="learned") is None  # a summary from before the metrics
    summary = json.loads(path.read_text())
    failed = {"oracle": (0.001, 0.002), "learned": (0.05, 1.0), "rule": (0.2, 1.0), "fit": (0.04, 1.0)}
    for name, (med, p90) in failed.items():
        summary["summary"][name] |= {"median_error_slip_failed": {"value": med}, "p90_error_slip_failed": {"value": p90}}
    path.write_text(json.dumps(summary))
    rows = slip_failed({"suite": path}, learned="learned").splitlines()
    # the oracle is never the rival; of equal rivals the first is named
    assert rows[2] == "| suite | 5.0 % / 100.0 % (72) | fit 4.0 % | rule 100.0 % | no | tied |"


def test_horizon_rows_read_each_run_where_the_evaluate_command_writes_it(tmp_path):
    agents = {"learned": (False, 0.04, 0.3, 5), "phase-rule": (False, 0.06, 0.25, 7), "robust-model": (False, 0.05, 0.5, 2)}
    suites = {"default": ("v2 default suite", tmp_path / "d30"), "v2_heldout_grid": ("v2 held-out grid", tmp_path / "h30")}
    runs = [tmp_path / "d30", tmp_path / "h30", *(with_horizon("default", w, tmp_path) for w in (45, 60)),
            with_horizon("v2_heldout_grid", 60, tmp_path)]
    assert runs[-1] == tmp_path / "out" / "evaluate-v2_heldout_grid-max_windows=60"
    for k, out in enumerate(runs):
        out.mkdir(parents=True)
        path = _summary(out / "summary.json", agents, episodes=72)
        summary = json.loads(path.read_text())
        summary["summary"]["learned"]["breakdown"] = {"ended: horizon": {"episodes": k}}
        path.write_text(json.dumps(summary))
    rows = horizon(suites, learned="learned", root=tmp_path).splitlines()
    assert [row.split(" | ")[:2] for row in rows[2:]] == [["| v2 default suite", "30"], ["| v2 default suite", "45"],
                                                           ["| v2 default suite", "60"], ["| v2 held-out grid", "30"],
                                                           ["| v2 held-out grid", "60"]]
    assert rows[4] == "| v2 default suite | 60 | 4.0 % / 30.0 % / 5 (72) | 3 | 6.0 % / 25.0 % / 7 | 5.0 % / 50.0 % / 2 |"
    assert rows[5].split(" | ")[3] == "1"  # the held-out grid's 30-step run
    (runs[-1] / "summary.json").unlink()
    assert horizon(suites, learned="learned", root=tmp_path) is None


def _with_breakdown(path: Path, agent: str, groups: dict[str, tuple[int, float, float, int, float]]) -> None:
    """Give ``agent`` breakdown groups: name -> (episodes, median, P90, macro-slips, mean peak torque)."""
    summary = json.loads(path.read_text())
    summary["summary"][agent]["breakdown"] = {
        name: {"episodes": n, "median_error": med, "p90_error": p90, "macro_slip_events": slips,
               "peak_torque_fraction": peak} for name, (n, med, p90, slips, peak) in groups.items()}
    path.write_text(json.dumps(summary))


def test_horizon_ends_set_the_horizon_group_beside_the_stop_group_and_mark_a_suite_without_one(tmp_path):
    suites = {}
    for name, groups in (("a", {"ended: horizon": (20, 0.12, 0.3, 0, 0.75), "ended: stop": (40, 0.015, 0.05, 0, 1.1)}),
                         ("b", {"ended: stop": (60, 0.02, 0.06, 0, 1.1)})):
        (tmp_path / name).mkdir()
        _summary(tmp_path / name / "summary.json", {"learned": (False, 0.04, 0.3, 0)}, episodes=60)
        _with_breakdown(tmp_path / name / "summary.json", "learned", groups)
        suites[name] = (f"suite {name}", tmp_path / name)
    rows = horizon_ends(suites, learned="learned").splitlines()
    assert rows[2] == "| suite a | 60 | 20 | 75.0 | 12.0 % / 30.0 % | 1.5 % |"
    assert rows[3] == "| suite b | 60 | 0 | - | - | 2.0 % |"
    assert horizon_ends({"c": ("suite c", tmp_path / "missing")}, learned="learned") is None


def test_peak_creepage_rows_follow_the_learned_agents_groups_for_every_agent_named(tmp_path):
    path = _summary(tmp_path / "s.json", {"learned": (False, 0.04, 0.3, 0), "rule": (False, 0.06, 0.25, 7)})
    groups = {"dry": (50, 0.1, 0.2, 0, 0.9), "peak creepage < 1 %": (30, 0.01, 0.05, 0, 1.0),
              "peak creepage 4+ %": (20, 0.08, 0.3, 0, 0.8)}
    _with_breakdown(path, "learned", groups)
    _with_breakdown(path, "rule", {name: (n, 2 * med, 2 * p90, 3, peak)
                                   for name, (n, med, p90, _, peak) in groups.items()})
    rows = peak_creepage(path, learned="learned", agents=("rule",)).splitlines()
    assert rows[0] == "| peak creepage (episodes) | learned | rule |"
    assert rows[2:] == ["| < 1 % (30) | 1.0 % / 5.0 % / 0 | 2.0 % / 10.0 % / 3 |",
                        "| 4+ % (20) | 8.0 % / 30.0 % / 0 | 16.0 % / 60.0 % / 3 |"]
    assert peak_creepage(path, learned="learned", agents=("rule", "absent")) is None


def test_heldout_peak_creepage_sums_each_agents_macro_slips_over_the_grids_in_band_order(tmp_path):
    runs = {}
    grids = ({"peak creepage 2-4 %": (10, 0.02, 0.1, 1, 1.0), "peak creepage < 1 %": (20, 0.02, 0.1, 4, 1.0)},
             {"peak creepage < 1 %": (30, 0.02, 0.1, 5, 1.0)})  # the second grid has no curve peaking at 2-4 %
    for k, groups in enumerate(grids):
        out = tmp_path / f"grid{k}"
        out.mkdir()
        path = _summary(out / "summary.json", {"learned": (False, 0.04, 0.3, 5 + 4 * (1 - k)),
                                               "rule": (False, 0.06, 0.25, 20)}, episodes=30)
        _with_breakdown(path, "learned", groups)
        _with_breakdown(path, "rule", {g: (n, med, p90, 2 * slips, peak) for g, (n, med, p90, slips, peak)
                                       in groups.items()})
        runs[f"grid{k}"] = (f"grid {k}", out)
    rows = heldout_peak_creepage(runs, learned="learned", agents=("rule",)).splitlines()
    assert rows[0] == "| peak creepage (episodes) | learned | rule |"
    assert rows[2:] == ["| < 1 % (50) | 9 | 18 |", "| 2-4 % (10) | 1 | 2 |", "| all (60) | 14 | 40 |"]
    assert heldout_peak_creepage(runs, learned="learned", agents=("rule", "absent")) is None


def test_paired_targets_pair_the_learned_agent_with_the_best_others_over_the_same_episodes(tmp_path):
    """Each suite's row: the agents with the lowest other median and P90 (as the targets name them), the learned
    agent's paired differences against them (the point values those of the episodes), its share of lower errors."""
    import csv

    import numpy as np

    errors = {"learned": np.array([0.01, 0.02, 0.05, 0.2]), "rule": np.array([0.02, 0.01, 0.04, 0.1]),
              "other": np.array([0.05, 0.06, 0.07, 0.3])}
    out = tmp_path / "run"
    out.mkdir()
    path = _summary(out / "summary.json", {a: (False, float(np.median(e)), float(np.percentile(e, 90)), 0)
                                           for a, e in errors.items()}, episodes=4)
    with open(out / "episodes.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=["agent", "episode", "relative_error", "episode_return"])
        writer.writeheader()
        for agent, e in errors.items():
            writer.writerows({"agent": agent, "episode": i, "relative_error": v, "episode_return": -v}
                             for i, v in reversed(list(enumerate(e))))  # any row order: paired by episode
    row = paired_targets({"suite": path}, learned="learned").splitlines()[2].split(" | ")
    median = 100 * (np.median(errors["learned"]) - np.median(errors["rule"]))
    p90 = 100 * (np.percentile(errors["learned"], 90) - np.percentile(errors["rule"], 90))
    lower = 100 * np.mean(errors["learned"] < errors["rule"])  # no ties here
    assert row[1] == "rule" and row[2].startswith(f"{median:+.1f} [") and row[3].startswith(f"{lower:.0f} [")
    assert row[4] == "rule" and row[5].startswith(f"{p90:+.1f} [")
    (out / "episodes.csv").unlink()
    assert paired_targets({"suite": path}, learned="learned") is None


def test_a_rate_interval_is_exact_where_its_bounds_have_a_closed_form():
    """Clopper-Pearson: with no event the upper bound is 1 - (tail)^(1/n), with every trial an event the lower bound
    is tail^(1/n); the interval holds the observed rate and narrows as the trials grow."""
    for n in (1, 10, 60, 480):
        assert rate_interval(0, n) == (0.0, pytest.approx(1.0 - 0.025 ** (1.0 / n), rel=1e-9))
        assert rate_interval(n, n) == (pytest.approx(0.025 ** (1.0 / n), rel=1e-9), 1.0)
    low, high = rate_interval(3, 48)
    assert low < 3 / 48 < high and high - low > rate_interval(30, 480)[1] - rate_interval(30, 480)[0]
    for events, trials in ((3, 2), (-1, 5), (0, 0)):  # beta quantiles of such gave (nan, nan)
        with pytest.raises(ValueError, match="0 <= events <= trials"):
            rate_interval(events, trials)


def test_the_interquartile_mean_refuses_a_nan_which_a_sort_would_put_last():
    from ppo_seeds import iqm

    assert iqm(np.array([4.0, 1.0, 3.0, 2.0])) == 2.5
    with pytest.raises(ValueError, match="none of them NaN"):
        iqm(np.array([0.01, 0.02, 0.03, np.nan]))


def test_slip_rates_say_below_above_or_cannot_tell_against_one_per_hundred(tmp_path):
    rows = {}
    for name, slips, n in (("none", 0, 60), ("many", 12, 72), ("none_long", 0, 600)):
        path = _summary(tmp_path / f"{name}.json", {"learned": (False, 0.02, 0.08, slips)}, episodes=n)
        rows[name] = slip_rates({name: path}, learned="learned").splitlines()[2]
    assert rows["none"].endswith("| 0 (60) | 0.0 [0.0, 6.0] | cannot tell |")
    assert rows["many"].endswith("| shown above |") and rows["none_long"].endswith("| shown below |")
    assert slip_rates({"x": tmp_path / "missing.json"}, learned="learned") is None


def test_edge_suites_give_the_learned_agents_peak_torque_and_interval_coverage_beside_the_others(tmp_path):
    path = _summary(tmp_path / "s.json", {"learned": (False, 0.3, 0.8, 6), "rule": (False, 0.25, 0.85, 9)}, episodes=48,
                    peak_torque=0.5)
    summary = json.loads(path.read_text())
    summary["summary"]["learned"]["interval"] = {"coverage": {"value": 0.4375}}
    path.write_text(json.dumps(summary))
    rows = edge_suites({"edge": path}, learned="learned", agents=("rule",)).splitlines()
    assert rows[2] == "| edge (48) | 30.0 % / 80.0 % / 6 | 50.0 | 43.8 % | 25.0 % / 85.0 % / 9 |"
    assert edge_suites({"edge": path}, learned="learned", agents=("rule", "absent")) is None


def test_paper_setting_gives_every_agent_its_horizon_endings_peak_torque_and_time(tmp_path):
    path = _summary(tmp_path / "s.json", {"oracle": (True, 0.015, 0.015, 0), "learned": (False, 0.035, 0.075, 0)},
                    episodes=5, peak_torque=0.915)
    _with_breakdown(path, "learned", {"ended: horizon": (4, 0.05, 0.08, 0, 0.9), "ended: stop": (1, 0.001, 0.001, 0, 1.1)})
    _with_breakdown(path, "oracle", {"ended: stop": (5, 0.015, 0.015, 0, 0.995)})
    summary = json.loads(path.read_text())
    for agent, seconds in (("oracle", 4.0), ("learned", 27.64)):
        summary["summary"][agent]["measurement_time_s"] = {"value": seconds}
    path.write_text(json.dumps(summary))
    rows = paper_setting(path, learned="learned").splitlines()
    assert rows[2:] == ["| oracle (oracle, 5) | 1.5 % / 1.5 % / 0 | 0 | 91.5 | 4.0 |",
                        "| learned (5) | 3.5 % / 7.5 % / 0 | 4 | 91.5 | 27.6 |"]
    assert paper_setting(tmp_path / "missing.json", learned="learned") is None


def test_a_block_is_filled_in_the_document_that_holds_it_and_nowhere_else(tmp_path, capsys):
    a, b = tmp_path / "a.md", tmp_path / "b.md"
    texts = {a: "x\n<!-- results:one:begin -->\nold\n<!-- results:one:end -->\n", b: "no blocks\n"}
    fill(texts, "one", "new", "src")
    assert texts[a] == "x\n<!-- results:one:begin -->\nnew\n<!-- results:one:end -->\n" and texts[b] == "no blocks\n"
    fill(texts, "one", None, "src")  # a missing source leaves the block as it is
    fill(texts, "two", "new", "src")
    assert "new" in texts[a] and "no document has a results:two block" in capsys.readouterr().out


def test_every_result_block_has_exactly_one_place_in_the_shipped_documents():
    text = "".join(doc.read_text() for doc in DOCUMENTS)
    for name in [*SOURCES, *GENERATED]:
        assert text.count(f"<!-- results:{name}:begin -->") == 1, name
        assert text.count(f"<!-- results:{name}:end -->") == 1, name
