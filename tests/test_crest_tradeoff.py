"""experiments/crest_tradeoff.py's command line: bad input exits 2 with one line naming the option,
before any episode is played."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from cof_gym.commands.suites import scenario_option

SCRIPT = Path(__file__).resolve().parent.parent / "experiments" / "crest_tradeoff.py"
SHIPPED = Path(__file__).resolve().parent.parent / "cof_gym" / "agents" / "policies" / "interrogator"


@pytest.mark.parametrize("args, option", [(["--cautions", "-1"], "--cautions"), (["--targets", "1.5"], "--targets"),
                                          (["--run", "no/such/run"], "--run"),
                                          (["--spread-cautions", "nan"], "--spread-cautions"),
                                          (["--guards", "no/such/guard"], "--guards"),
                                          (["--estimators", "no/such/estimator"], "--estimators"),
                                          (["--return-digits", "9"], "--return-digits"),
                                          (["--own-climb", "--targets", "0.1"], "--targets"),
                                          (["--own-climb", "--cautions", "2"], "--cautions"),
                                          (["--grids", "heldout"], "--grids"),
                                          (["--crest-fractions", "-0.5"], "--crest-fractions"),
                                          (["--crest-fractions", "abc"], "--crest-fractions"),
                                          (["--own-climb", "--crest-fractions", "1"], "--crest-fractions"),
                                          (["--crest-once-crept"], "--crest-once-crept"),
                                          (["--set", "no_such_field=1"], "--set"),
                                          (["--set", "creep_log_step=0.5"], "--set"),
                                          (["--set", "creep_sticky=maybe"], "--set"),
                                          (["--own-climb", "--set", "caution=2"], "--set"),
                                          (["--guards-only"], "--guards-only"),
                                          (["--guards", str(SHIPPED / "guard_0"), "--guards-only", "--set",
                                            "guard_cautions=[2, 3]"], "--set: guard_cautions names 2"),
                                          (["--guards", str(SHIPPED / "guard_0"), "--set", "guard_cautions=[2]"],
                                           "--guards-only"),
                                          (["--set", "ceiling_fall_z=-1"], "--set: ceiling_fall_z"),
                                          (["--scenario", "noise_level=4"], "--scenario"),
                                          (["--scenario", "no_such_field=1"], "--scenario"),
                                          (["--scenario", "noise_level"], "--scenario"),
                                          (["--scenario", "motor_lag_s=null"], "--scenario")])
def test_bad_options_exit_2_naming_the_option(args: list[str], option: str, tmp_path: Path, experiment_exit) -> None:
    code, last = experiment_exit("crest_tradeoff", [*args, "--out", str(tmp_path / "t.md")])
    assert code == 2 and option in last
    assert not (tmp_path / "t.md").exists()


def test_a_bad_option_on_the_command_line_exits_2_naming_it(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, str(SCRIPT), "--cautions", "-1", "--out", str(tmp_path / "t.md")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("crest_tradeoff.py: error: --cautions"), done.stderr
    assert not (tmp_path / "t.md").exists()


def test_own_climb_needs_each_runs_manifest(tmp_path: Path) -> None:
    run = tmp_path / "run"
    run.mkdir()
    (run / "member_0.npz").write_bytes((SHIPPED / "member_0.npz").read_bytes())
    done = subprocess.run([sys.executable, str(SCRIPT), "--own-climb", "--run", str(run), "--out", str(tmp_path / "t.md")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1, done.stderr
    assert done.stderr.startswith("crest_tradeoff.py: error: --run: no manifest.json"), done.stderr
    assert not (tmp_path / "t.md").exists()


def test_own_climb_labels_a_run_by_what_its_climb_changes(tmp_path: Path) -> None:
    sys.path.insert(0, str(SCRIPT.parent))
    from crest_tradeoff import climb_settings, row_variants

    shipped = json.loads((SHIPPED / "manifest.json").read_text())["climb"]
    (tmp_path / "manifest.json").write_text(json.dumps({"climb": {**shipped, "max_log_step": 0.25}}))
    [(label, climb)] = climb_settings(SHIPPED, shipped, [0.3], None, None, True)
    assert label.startswith(f"{SHIPPED} (the shipped climb") and climb == shipped
    [(label, climb)] = climb_settings(tmp_path, shipped, [0.3], None, None, True)
    assert label == f"{tmp_path} (max_log_step 0.25)" and climb == {**shipped, "max_log_step": 0.25}
    # a run whose manifest names guards plays with them (table: guards None) and says so
    (tmp_path / "manifest.json").write_text(json.dumps({"climb": shipped, "guards": ["guard_0"]}))
    [(label, _)] = climb_settings(tmp_path, shipped, [0.3], None, None, True)
    assert label == f"{tmp_path} (the shipped climb; guards guard_0)"
    # without it: the shipped climb at each target and caution
    rows = climb_settings(tmp_path, shipped, [0.1, 0.3], [1.5], None, False)
    assert [(c["target_headroom"], c["caution"], c["max_log_step"]) for _, c in rows] == [
        (0.1, 1.5, shipped["max_log_step"]), (0.3, 1.5, shipped["max_log_step"])]
    # crest fractions: each row with each cap (None: uncapped), the manifest's default when not given
    rows = [climb for variant in row_variants(None, [None, 0.5])
            for _, climb in climb_settings(tmp_path, {**shipped, **variant}, [0.1], None, None, False)]
    assert [c["crest_fraction"] for c in rows] == [None, 0.5]
    assert all(c.get("crest_fraction") == shipped.get("crest_fraction") for variant in row_variants()
               for _, c in climb_settings(tmp_path, {**shipped, **variant}, [0.1], None, None, False))
    # --set values and crest caps combine, each cap from the first slow probe on with crest_once_crept
    assert row_variants({"creep_log_step": [0.02, 0.045]}, [1.0], True) == [
        {"creep_log_step": 0.02, "crest_fraction": 1.0, "crest_once_crept": True},
        {"creep_log_step": 0.045, "crest_fraction": 1.0, "crest_once_crept": True}]


def test_how_the_climbs_ended_is_one_row_per_reason_with_its_errors() -> None:
    sys.path.insert(0, str(SCRIPT.parent))
    from crest_tradeoff import Played, _ends

    runs = [Played(0.02, False, -1.0, "headroom", 1.1, None, -0.02), Played(0.04, False, -1.2, "headroom", 1.2, None, 0.04),
            Played(0.30, False, -3.0, "horizon", 0.8, None, -0.30), Played(1.0, True, -11.0, "macro-slip", 1.3)]
    rows = _ends("caution 2, target 0.1, ", "family", runs)
    assert rows == ["| caution 2, target 0.1, family | headroom | 2 of 4 | 3.0 % | 3.8 % | +1.0 % | 115 % |",
                    "| caution 2, target 0.1, family | horizon | 1 of 4 | 30.0 % | 30.0 % | -30.0 % | 80 % |",
                    "| caution 2, target 0.1, family | macro-slip | 1 of 4 | 100.0 % | 100.0 % | - | 130 % |"]


def test_set_items_are_climb_parameters_with_json_values() -> None:
    sys.path.insert(0, str(SCRIPT.parent))
    from crest_tradeoff import climb_setting

    assert climb_setting("creep_log_step=0.05") == ("creep_log_step", 0.05)
    assert climb_setting("creep_sticky=false") == ("creep_sticky", False)
    assert climb_setting("creep_until=null") == ("creep_until", None)


def test_a_row_without_guards_reports_the_filters_estimate_unless_set() -> None:
    sys.path.insert(0, str(SCRIPT.parent))
    from crest_tradeoff import unguarded_estimate

    shipped = json.loads((SHIPPED / "manifest.json").read_text())["climb"]
    guarded = {**shipped, "estimate_from": "pooled_at_headroom"}
    assert unguarded_estimate(guarded, [], None)["estimate_from"] == "filter"
    assert unguarded_estimate(guarded, ["g"], None) == guarded  # with guards: as shipped
    assert unguarded_estimate(guarded, None, None) == guarded  # the run's manifest names its guards
    assert unguarded_estimate(guarded, [], {"estimate_from": ["pooled_at_headroom"]}) == guarded  # --set: as named
    assert unguarded_estimate({**shipped, "estimate_from": "best_coa"}, [], None)["estimate_from"] == "best_coa"


def test_records_hold_every_episode_and_each_sources_error(tmp_path: Path) -> None:
    """--records (here through ``table(records=...)``): one dict per episode and configuration, whose reported
    error is its estimate source's (the shipped manifest's) as recomputed from the agent's
    candidates; they differ only by the float32 action that carries the estimate (log-mapped over a
    factor of 100 or less: a relative rounding of at most ln(100) / 2 x 2^-24 < 1.4e-7)."""
    sys.path.insert(0, str(SCRIPT.parent))
    from crest_tradeoff import CONFIGS, table

    suite = json.loads((SCRIPT.parent / "suites" / "v2_validation_grid.json").read_text())
    tiny = tmp_path / "tiny.json"
    tiny.write_text(json.dumps({**suite, "episodes": suite["episodes"][:2]}))
    records: list = []
    text = table([0.1], 1, guards=[SHIPPED / "guard_0"], grids={"tiny": tiny}, guards_only=True, records=records)
    source = json.loads((SHIPPED / "manifest.json").read_text())["climb"]["estimate_from"]
    assert text.count("\n") == 3 and len(records) == 2 * len(CONFIGS)
    assert [(r["config"], r["episode"]) for r in records] == [(c, i) for c in CONFIGS for i in range(2)]
    for r in records:
        assert set(r["source_errors"]) == {"filter", "best_coa", "guard", "pooled", "pooled_at_headroom"}
        assert r["error"] == pytest.approx(r["source_errors"][source], abs=1e-6)
        signed = r["signed_error"]  # None: unscored, the error counted as 1
        assert (r["error"] == 1.0) if signed is None else abs(signed) == pytest.approx(r["error"], abs=1e-12)


def test_a_scenario_option_is_played_in_every_episode_and_said_above_the_table(tmp_path: Path) -> None:
    """``--scenario`` (here ``table(scenario=...)``) sets reset options over every episode's own: the same two
    episodes with a drive lag of 0.1 s instead of the grid's 0.02 s play other climbs (the env reads the
    option: the records differ), and the table says so in its first line."""
    sys.path.insert(0, str(SCRIPT.parent))
    from crest_tradeoff import table

    suite = json.loads((SCRIPT.parent / "suites" / "v2_validation_grid.json").read_text())
    tiny = tmp_path / "tiny.json"
    tiny.write_text(json.dumps({**suite, "episodes": suite["episodes"][:2]}))
    plain, slow = [], []
    table([0.1], 1, guards=[SHIPPED / "guard_0"], grids={"tiny": tiny}, guards_only=True, records=plain)
    text = table([0.1], 1, guards=[SHIPPED / "guard_0"], grids={"tiny": tiny}, guards_only=True, records=slow,
                 scenario=dict([scenario_option("motor_lag_s=0.1")]))
    assert text.splitlines()[0] == "Every episode with motor_lag_s 0.1 over its own options."
    assert len(plain) == len(slow) and [r["error"] for r in plain] != [r["error"] for r in slow]


def test_other_networks_than_the_shipped_are_named_in_the_table_and_the_records(tmp_path: Path) -> None:
    """``--run`` with one directory that is not the shipped agent's (here a copy of its filter): the table's first
    column and every record's setting name it, so that paired_comparison.py can tell its rows from the shipped
    agent's with the same guards and climb; the shipped agent alone keeps its unnamed row."""
    sys.path.insert(0, str(SCRIPT.parent))
    import shutil

    from crest_tradeoff import table

    suite = json.loads((SCRIPT.parent / "suites" / "v2_validation_grid.json").read_text())
    tiny = tmp_path / "tiny.json"
    tiny.write_text(json.dumps({**suite, "episodes": suite["episodes"][:1]}))
    other = tmp_path / "other"
    other.mkdir()
    for member in SHIPPED.glob("member_*.npz"):
        shutil.copy(member, other)
    shipped_records, other_records = [], []
    shipped_text = table([0.1], 1, guards=[SHIPPED / "guard_0"], grids={"tiny": tiny}, guards_only=True,
                         records=shipped_records)
    other_text = table([0.1], 1, networks=[other], guards=[SHIPPED / "guard_0"], grids={"tiny": tiny},
                       guards_only=True, records=other_records)
    assert shipped_text.startswith("| caution |") and other_text.startswith("| networks |")
    assert {r["setting"] for r in other_records} == {f"{other}, " + shipped_records[0]["setting"]}
    # the same networks and climb: the same episodes
    assert [r["error"] for r in other_records] == [r["error"] for r in shipped_records]
