"""experiments/frontier.py: each candidate's runaways against its accuracy and return, and which lie on the frontier
(no other with as few runaways and as low a P90, one of them lower); plays joined by + pooled."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"
sys.path.insert(0, str(EXPERIMENTS))
from frontier import Point, beaten_by, on_frontier, point, read_group, table  # noqa: E402

ERRORS = np.linspace(0.0, 0.2, 21)  # median 0.1, P90 0.18 (numpy's linear interpolation)


def records(setting: str, scale: float = 1.0, slips: int = 0, grids: tuple[str, ...] = ("family", "steep")) -> list[dict]:
    """One setting's episodes on ``grids``, its errors ``ERRORS x scale``, the first ``slips`` steep ones runaways
    (their return 10 lower)."""
    return [{"setting": setting, "grid": grid, "config": {}, "episode": i, "error": float(scale * e),
             "macro_slip": grid == "steep" and i < slips,
             "episode_return": -float(scale * e) - (10.0 if grid == "steep" and i < slips else 0.0)}
            for grid in grids for i, e in enumerate(ERRORS)]


def test_a_points_totals_are_its_runaways_and_its_grids_median_and_p90() -> None:
    p = point("a", "s", records("s", 2.0, slips=3), "family")
    assert (p.episodes, p.runaways) == (42, 3)
    assert p.grid_median == pytest.approx(0.2) and p.grid_p90 == pytest.approx(0.36)
    assert p.mean_return == pytest.approx(-0.2 - 30.0 / 42)
    with pytest.raises(ValueError, match="no episode on the grid 'procedural'"):
        point("a", "s", records("s"), "procedural")


def test_the_frontier_keeps_what_no_other_point_beats_on_both() -> None:
    def at(runaways: int, p90: float) -> Point:
        return Point(f"{runaways}-{p90}", "", 10, runaways, 0.0, p90, 0.0, 0.0, 0.0)
    points = [at(1, 0.5), at(2, 0.3), at(3, 0.3), at(2, 0.6), at(5, 0.1)]
    assert on_frontier(points) == [True, True, False, False, True]
    assert on_frontier([at(2, 0.3), at(2, 0.3)]) == [True, True]  # ties beat neither


def test_plays_joined_by_plus_pool_their_kth_settings(tmp_path: Path) -> None:
    draws, noisy = tmp_path / "records_x_validation.json", tmp_path / "records_x_noise_level.json"
    draws.write_text(json.dumps(records("a") + records("b", slips=1)))
    noisy.write_text(json.dumps(records("a", 3.0, slips=2) + records("b", slips=4)))
    first, second = read_group(f"{draws}+{noisy}", "family")
    assert (first.label, first.setting, first.episodes, first.runaways) == ("x_validation [1]", "a", 84, 2)
    assert (second.label, second.runaways) == ("x_validation [2]", 5)
    assert first.grid_median == pytest.approx(float(np.median(np.concatenate([ERRORS, 3.0 * ERRORS]))))
    noisy.write_text(json.dumps(records("a")))
    with pytest.raises(ValueError, match="different numbers of settings"):
        read_group(f"{draws}+{noisy}", "family")


def test_the_command_writes_the_table_and_the_figure_and_marks_the_shipped_play(tmp_path: Path) -> None:
    files = []
    for name, scale, slips in (("shipped", 1.0, 2), ("safer", 2.0, 0), ("worse", 2.0, 3)):
        files.append(tmp_path / f"records_{name}.json")
        files[-1].write_text(json.dumps(records(name, scale, slips)))
    run = subprocess.run([sys.executable, str(EXPERIMENTS / "frontier.py"), *map(str, files), "--shipped",
                          str(files[0]), "--out", str(tmp_path / "f.md"), "--figure", str(tmp_path / "f.png")],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    rows = [line for line in run.stdout.splitlines() if line.startswith("| ") and not line.startswith("| play")]
    assert [r.split(" | ")[0] for r in rows] == ["| safer", "| **shipped** (shipped)", "| worse"]
    assert [r.split(" | ")[5] for r in rows] == ["0: on the frontier", "0: on the frontier", "2"]
    assert (tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG"
    assert (tmp_path / "f.md").read_text().endswith(run.stdout)


def test_a_reference_is_counted_against_the_candidates_and_never_joins_their_frontier() -> None:
    def at(label: str, runaways: int, p90: float) -> Point:
        return Point(label, label, 10, runaways, 0.0, p90, 0.0, 0.0, 0.0)
    candidates = [at("a", 1, 0.5), at("b", 3, 0.2)]
    reference = at("rule", 4, 0.3)  # beaten by b alone; it would beat nothing
    assert beaten_by(reference, candidates) == 1
    rows = table(candidates, "family", None, [reference]).splitlines()[2:]
    assert [r.split(" | ")[0] for r in rows] == ["| a", "| b", "| rule (hand-built)"]
    assert [r.split(" | ")[5] for r in rows] == ["0: on the frontier", "0: on the frontier", "1"]
    assert table(candidates, "family", None, [at("far", 0, 0.1)]).count("| 0 |") == 1  # beats both, shown as 0


def test_scripted_plays_records_a_hand_built_agent_as_crest_tradeoff_records_the_candidates(tmp_path: Path) -> None:
    from scripted_plays import play

    grid = json.loads((EXPERIMENTS / "suites" / "v2_validation_grid.json").read_text())
    small = tmp_path / "two.json"
    small.write_text(json.dumps({**grid, "episodes": grid["episodes"][:2]}))
    rows = play(("phase-rule", "family", small, {"counter_torque": True}, {"noise_level": 2.0}))
    assert [(r["setting"], r["grid"], r["config"], r["episode"]) for r in rows] == [
        ("phase-rule", "family", {"counter_torque": True}, k) for k in range(2)]
    for r in rows:
        assert 0.0 <= r["error"] and isinstance(r["macro_slip"], bool) and np.isfinite(r["episode_return"])
        assert r["signed_error"] is None or abs(abs(r["signed_error"]) - r["error"]) < 1e-12
    assert play(("phase-rule", "family", small, {"counter_torque": True}, {"noise_level": 2.0})) == rows  # seeded


def test_target_rows_read_issue_16s_targets_and_count_them_per_grid_and_play() -> None:
    from frontier import targets_met
    from selection import target_rows

    assert target_rows(3.0, 8.0, 1, 100) == [True, True, True]  # each target at its bound is met
    assert target_rows(3.1, 8.1, 2, 100) == [False, False, False]
    assert target_rows(2.0, 9.0, 3, 72, [(2.5, 9.0, 3), (4.0, 12.0, 5)]) == [True, False, False, True, False, True]
    candidate = point("c", "c", records("c", 0.1, slips=0), "family")  # median 1 %, P90 1.8 %, no runaway
    rival = point("r", "r", records("r", 1.0, slips=1), "family")
    assert targets_met(candidate, []) == (6, 6)  # two grids x three absolute rows
    assert targets_met(candidate, [rival]) == (12, 12)
    assert targets_met(rival, [candidate]) == (2, 12)  # its family grid's runaways alone (absolute and relative)


def test_rows_list_what_parts_a_candidate_from_the_shipped_agent_and_need_references(tmp_path: Path) -> None:
    from frontier import differing_rows, play_names

    assert play_names(["shipped_confirmation34", "shipped_torque_confirmation15"]) == [
        "confirmation34", "torque_confirmation15"]
    assert play_names(["shipped_validation"]) == ["shipped_validation"]  # one play: its label
    shipped = point("shipped", "s", records("s", 0.5, slips=2), "family")  # median 5 %, P90 9 %
    better = point("better", "b", records("b", 0.25, slips=2), "family")  # median 2.5 %, P90 4.5 %
    rival = point("rival", "r", records("r", 0.4, slips=5), "family")  # median 4 %, P90 7.2 %
    lines = differing_rows([shipped, better], "shipped", [rival], ["validation"]).splitlines()
    assert lines[0] == "| play | grid | target row | against | shipped | better |"
    body = [line.split(" | ") for line in lines[2:]]
    assert [(b[1], b[2]) for b in body] == [("family", "median <= 3 %"), ("family", "P90 <= 8 %"),
                                            ("family", "median below every hand-built agent's"),
                                            ("family", "P90 below every hand-built agent's"),
                                            ("steep", "median <= 3 %"), ("steep", "P90 <= 8 %"),
                                            ("steep", "median below every hand-built agent's"),
                                            ("steep", "P90 below every hand-built agent's")]
    assert body[2][3:] == ["4.0 %", "5.0 %", "2.5 % (met) |"]
    assert "no row parts them" in differing_rows([shipped], "shipped", [rival], ["validation"])
    files = [tmp_path / f"records_{n}_validation.json" for n in ("shipped", "better")]
    for f, (name, scale) in zip(files, (("s", 0.5), ("b", 0.25))):
        f.write_text(json.dumps(records(name, scale, slips=2)))
    command = [sys.executable, str(EXPERIMENTS / "frontier.py"), *map(str, files), "--rows"]
    run = subprocess.run(command, capture_output=True, text=True)
    assert run.returncode == 2 and "--rows: needs --references and --shipped" in run.stderr
    assert "Traceback" not in run.stderr


def test_rows_on_a_grid_no_reference_played_read_the_absolute_targets_alone() -> None:
    from frontier import differing_rows

    shipped = point("shipped", "s", records("s", 0.5, grids=("family", "steep")), "family")  # 5 %, 9 %
    better = point("better", "b", records("b", 0.25, grids=("family", "steep")), "family")  # 2.5 %, 4.5 %
    rival = point("rival", "r", records("r", 0.4, grids=("family",)), "family")  # no steep episode
    steep = [line for line in differing_rows([shipped, better], "shipped", [rival], ["v"]).splitlines()
             if line.startswith("| v | steep")]
    assert [line.split(" | ")[2] for line in steep] == ["median <= 3 %", "P90 <= 8 %"]


def test_endings_count_the_horizon_endings_and_the_slow_probes_runaways() -> None:
    rows = records("s", slips=3)
    for i, r in enumerate(rows):  # two runaways in the slow probe, one elsewhere; five climbs ran to the horizon
        r["ended"] = ("macro-slip, slow probe" if i in (21, 22) else "macro-slip" if r["macro_slip"]
                      else "horizon" if i < 5 else "headroom")
    p = point("a", "s", rows, "family")
    with_endings, plain = table([p], "family", "a", endings=True), table([p], "family", "a")
    header, rule, row = with_endings.splitlines()
    assert "| ended at the horizon | runaways in the slow probe |" in header
    assert rule.count("---") == header.count("|") - 1 == 10
    assert "| -0.8143 | 5 | 2 |" in row  # the mean return (-0.1 - 30 / 42), then the two counts
    assert "ended at the horizon" not in plain and plain.splitlines()[1].count("---") == 8
    unread = point("b", "s", records("s"), "family")  # records without "ended": nothing counted
    assert "| 0 | 0 |" in table([unread], "family", None, endings=True).splitlines()[2]


def test_the_figure_names_each_point_once_and_no_candidate_where_only_the_shipped_agent_is_played(tmp_path) -> None:
    from frontier import REFERENCE_MARKERS, figure

    assert len(set(REFERENCE_MARKERS)) == len(REFERENCE_MARKERS)  # a marker of its own for each of that many
    shipped = point("shipped_validation", "s", records("s", slips=1), "family")
    references = [point(f"ref{i}_validation", f"ref{i}", records(f"ref{i}", 0.5, slips=10 + i), "family")
                  for i in range(len(REFERENCE_MARKERS))]
    labels = figure([shipped], "family", "shipped_validation", tmp_path / "f.png", references)
    assert labels == ["shipped", *(f"ref{i}" for i in range(len(REFERENCE_MARKERS)))]
    assert (tmp_path / "f.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    candidate = point("c_validation", "c", records("c", 1.5), "family")
    assert figure([shipped, candidate], "family", "shipped_validation", tmp_path / "g.png")[0] == "candidate"
