"""Bad command lines of the experiment scripts: one usage line naming the option (exit code 2), checked
before any simulation and before any output is created (experiments/script_checks.py and each script's
argument types). Every script parses with :class:`cof_gym.commands.args.Parser`: an error is the single
line ``SCRIPT.py: error: MESSAGE (see SCRIPT.py --help)``, no usage block."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import pytest

from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"
sys.path.insert(0, str(EXPERIMENTS))

# {dir}: an existing directory, {file}: an existing plain file, {text}: a file that is no climbs file or model,
# {corrupt}: a zip file that is no model, {new}: a path that does not exist (inside tmp_path), {SHIPPED}: the shipped
# interrogator's directory (read, never written)
CASES = [
    ("assemble_policy", ["--filter", "{dir}", "--out", "{new}"], "--filter"),
    ("assemble_policy", ["--filter", "{SHIPPED}", "--guards", "{dir}", "--out", "{new}"], "--guards"),
    ("assemble_policy", ["--filter", "{SHIPPED}", "--climb-from", "{dir}", "--out", "{new}"], "--climb-from"),
    ("assemble_policy", ["--filter", "{SHIPPED}", "--out", "{file}"], "--out"),
    ("assemble_policy", ["--into", "{SHIPPED}", "--filter", "{SHIPPED}"], "--filter"),
    ("assemble_policy", ["--into", "{SHIPPED}", "--climb-from", "{SHIPPED}"], "--climb-from"),
    ("assemble_policy", ["--into", "{dir}", "--smoothed-filter", "{SHIPPED}"], "--into"),  # no policy directory
    ("assemble_policy", ["--into", "{SHIPPED}"], "--into"),  # nothing to add
    ("assemble_policy", ["--guards", "{SHIPPED}"], "--filter"),
    ("assemble_policy", ["--filter", "{SHIPPED}", "--out", "{SHIPPED}"], "--out"),
    ("assemble_policy", ["--filter", "{SHIPPED}", "--smoothed-guards", "{SHIPPED}", "--out", "{new}"],
     "--smoothed-guards"),
    ("assemble_policy", ["--filter", "{SHIPPED}", "--smoothed-filter", "{dir}", "--out", "{new}"], "--smoothed-filter"),
    ("assemble_policy", ["--filter", "{SHIPPED}", "--smoothed-set", "caution=2", "--out", "{new}"], "--smoothed-set"),
    ("assemble_policy", ["--filter", "{SHIPPED}", "--smoothed-filter", "{SHIPPED}", "--smoothed-set", "caution=-1",
                         "--out", "{new}"], "--smoothed-set"),
    ("assemble_policy", ["--filter", "{SHIPPED}", "--smoothed-filter", "{SHIPPED}", "--smoothed-guards", "{SHIPPED}",
                         "--out", "{new}"], "--smoothed-guards"),
    ("crest_tradeoff", ["--workers", "0"], "--workers"),
    ("crest_tradeoff", ["--workers", "-1"], "--workers"),
    ("crest_tradeoff", ["--out", "{dir}"], "--out"),
    ("crest_tradeoff", ["--out", "{file}/t.md"], "--out"),
    ("crest_tradeoff", ["--records", "{dir}", "--out", "{new}/t.md"], "--records"),
    ("crest_tradeoff", ["--caution-policy", "{new}.zip", "--out", "{new}/t.md"], "--caution-policy"),
    ("crest_tradeoff", ["--caution-policy", "{file}+{new}.zip", "--out", "{new}/t.md"], "--caution-policy"),
    ("learned_caution", ["--seeds", "0", "-1", "--out", "{new}"], "--seeds"),
    ("learned_caution", ["--timesteps", "0", "--out", "{new}"], "--timesteps"),
    ("learned_caution", ["--out", "{file}"], "--out"),
    ("learned_caution", ["--report", "{new}.json", "--baseline", "{file}", "--out", "{new}/t.md"], "--report"),
    ("learned_caution", ["--report", "{file}", "--out", "{new}/t.md"], "--report"),
    ("learned_caution", ["--baseline", "{file}", "--out", "{new}"], "--baseline"),
    ("learned_caution", ["--report", "{file}", "--baseline", "{file}", "--out", "{dir}"], "--out"),
    ("learned_caution", ["--export", "{new}.zip", "--into", "{SHIPPED}"], "--export"),
    ("learned_caution", ["--export", "{file}"], "--export"),
    ("learned_caution", ["--export", "{file}", "--into", "{dir}"], "--into"),
    ("learned_caution", ["--seeds", "0"], "--out"),
    ("learned_caution", ["--paired", "{new}.zip"], "--paired"),
    ("learned_caution", ["--paired", "{corrupt}"], "--paired"),  # loaded before any episode: not a model
    ("learned_caution", ["--export", "{corrupt}", "--into", "{SHIPPED}"], "--export"),
    ("crest_tradeoff", ["--caution-policy", "{corrupt}", "--out", "{new}/t.md"], "--caution-policy"),
    ("learned_caution", ["--paired", "{file}", "--episodes", "0"], "--episodes"),
    ("learned_caution", ["--cost-budget", "1.5", "--out", "{new}"], "--cost-budget"),
    ("learned_caution", ["--cost-budget", "nan", "--out", "{new}"], "--cost-budget"),
    ("learned_caution", ["--paired", "--cost-budget", "0.1"], "--cost-budget"),  # read by training only
    ("learned_caution", ["--paired", "--timesteps", "100"], "--timesteps"),
    ("learned_caution", ["--paired", "--out", "{new}"], "--out"),
    ("learned_caution", ["--export", "{file}", "--into", "{SHIPPED}", "--seeds", "1"], "--seeds"),
    ("learned_caution", ["--report", "{file}", "--baseline", "{file}", "--episodes", "5", "--out", "{new}/t.md"],
     "--episodes"),
    ("validation_plays", [], "NAME"),
    ("validation_plays", ["a b"], "NAME"),
    ("validation_plays", ["c", "--caution-policy", "{file}+{new}.zip"], "--caution-policy"),
    ("validation_plays", ["--hand-built", "c"], "--hand-built"),
    ("validation_plays", ["c", "--confirmation", "confirmation999", "torque_confirmation", "extremes_confirmation"],
     "--confirmation"),
    ("validation_plays", ["c", "--confirmation", "confirmation", "confirmation", "extremes_confirmation"],
     "--confirmation"),  # a set of another kind in the torque set's place
    ("validation_plays", ["c", "--print", "--set", "nope=1"], "--set: expected NAME=VALUE with NAME a climb"),
    ("validation_plays", ["c", "--print", "--set", "caution=-1"], "--set: caution: caution must be"),  # printed
    ("validation_plays", ["c", "--more-encoder-lags", "0"], "--more-encoder-lags"),
    ("validation_plays", ["c", "--more-encoder-lags", "nan"], "--more-encoder-lags"),
    ("validation_plays", ["c", "--only", "encoder_lag_s"], "--only"),  # not asked for without --encoder-lag
    ("select_phase_rule", ["--workers", "0"], "--workers"),
    ("select_phase_rule", ["--out", "{dir}"], "--out"),
    ("select_phase_rule", ["--in-service", "--markdown", "{dir}"], "--markdown"),
    ("select_phase_rule", ["--in-service", "--workers", "0"], "--workers"),
    ("select_rotation_margin", ["--workers", "0"], "--workers"),
    ("select_rotation_margin", ["--gate", "--out", "{dir}"], "--out"),
    ("select_robust_model", ["--workers", "-1"], "--workers"),
    ("select_robust_model", ["--out", "{dir}"], "--out"),
    ("feature_block_nll", ["--climbs", "{text}", "--out", "{new}/t.md"], "--climbs"),
    ("feature_block_nll", ["--climbs", "{corrupt}", "--out", "{new}/t.md"], "--climbs"),
    ("feature_block_nll", ["--climbs", "{text}", "--seed", "-1", "--out", "{new}/t.md"], "--seed"),
    ("feature_block_nll", ["--climbs", "{text}", "--out", "{dir}"], "--out"),
    ("train_estimator", ["--seeds", "-1", "--out", "{new}"], "--seeds"),
    ("train_estimator", ["--workers", "0", "--out", "{new}"], "--workers"),
    ("train_estimator", ["--out", "{file}"], "--out"),
    ("train_interrogator", ["--seeds", "0", "-1", "--out", "{new}"], "--seeds"),
    ("train_interrogator", ["--seeds", "0", "3", "0", "--out", "{new}"], "--seeds: 0 given more than once"),
    ("train_estimator", ["--seeds", "1", "1", "--out", "{new}"], "--seeds: 1 given more than once"),
    ("learned_caution", ["--seeds", "2", "2", "--out", "{new}"], "--seeds: 2 given more than once"),
    ("learned_caution", ["--seeds", "4294967296", "--out", "{new}"], "--seeds"),
    ("train_interrogator", ["--climbs", "torque_wide=\u00b2", "--out", "{new}"], "--climbs"),  # a digit int() refuses
    ("make_grids", ["--bogus"], "--bogus"),  # no options: nothing is generated or written
    ("readme_results", ["--bogus"], "--bogus"),  # no options: --help and a stray option rewrite no document
    # a key given twice (the last value won); an estimate source that reads networks the agent lacks (a worker's
    # traceback mid-play)
    ("assemble_policy", ["--filter", "{SHIPPED}", "--smoothed-filter", "{SHIPPED}", "--smoothed-set", "caution=1",
                         "caution=2", "--out", "{new}"], "--smoothed-set: caution given more than once"),
    ("train_estimator", ["--set", "caution=1", "caution=2", "--out", "{new}"], "--set: caution given more than once"),
    ("train_estimator", ["--set", "estimate_from=estimator", "--out", "{new}"], "--set: estimate_from='estimator'"),
    ("crest_tradeoff", ["--set", "estimate_from=estimator", "--out", "{new}/t.md"], "(give --estimators)"),
    # agents: at least one, each once, a model that exists (named as --agents, not --suite)
    *[(script, ["--agents", agents, "--out", "{new}/t.md"], fragment)
      for script in ("knee_twins", "indistinguishable_peaks", "sensor_sensitivity")
      for agents, fragment in ((",", "--agents: give at least one agent"),
                               ("phase-rule,phase-rule", "--agents: phase-rule given more than once"),
                               ("sb3:{new}.zip", "--agents: sb3:"))],
    ("scripted_plays", ["--agents", "phase-rule", "phase-rule", "--records", "{new}/r_{{agent}}.json"],
     "--agents: phase-rule given more than once"),
    ("own_window_fit", ["--first-seed", "9223372036854775800", "--out", "{new}/t.md"],
     "--first-seed: the last draw's seed"),
    ("shadow_reading", ["--first-seed", "99999999999999999999999", "--out", "{new}/t.md"], "--first-seed"),
    ("pool_ensembles", ["{SHIPPED}", "{SHIPPED}", "--out", "{new}"], "given more than once"),
    ("frontier", ["{text}+"], "an empty file name"),  # it read '.' and said 'Is a directory
    ("train_interrogator", ["--report-only", "--climbs", "env=5", "--out", "{new}"], "--climbs would be ignored"),
    ("train_interrogator", ["--ship", "--fit-only", "--out", "{new}"], "--ship: not with --fit-only"),
    ("train_interrogator", ["--epochs", "0", "--out", "{new}"], "--epochs"),
    ("train_interrogator", ["--epochs", "0", "--report-only", "--out", "{new}"], "--epochs"),
    ("train_interrogator", ["--workers", "0", "--out", "{new}"], "--workers"),
    ("train_interrogator", ["--torque-balance-lag", "95", "--out", "{new}"], "--torque-balance-lag"),
    ("train_interrogator", ["--torque-balance-lag", "nan", "--out", "{new}"], "--torque-balance-lag"),
    ("train_interrogator", ["--out", "{file}"], "--out"),
    ("train_interrogator", ["--env", "CofGym/TorqueInterrogation-v1", "--out", "{new}"], "--env"),
    ("train_interrogator", ["--report-only", "--out", "{file}"], "--out"),
    ("track_lag_spread", ["--windows", "2"], "--windows must be at least 3"),
    ("track_lag_spread", ["--frequencies", "25"], "--frequencies"),
    ("track_lag_spread", ["--ratios", "0"], "--ratios"),
    ("track_lag_spread", ["--tracks", "bumpy"], "--tracks"),
    ("track_lag_spread", ["--out", "{dir}"], "--out"),
    ("learning_curve", ["--run", "{file}", "--out", "{new}/t.md"], "--run"),
    ("learning_curve", ["--run", "{new}", "--out", "{dir}"], "--out"),
    ("learning_curve", ["--run", "{new}", "--workers", "0", "--out", "{new}/t.md"], "--workers"),
    ("learning_curve", ["--run", "{new}", "--seed", "-1", "--out", "{new}/t.md"], "--seed"),
    ("lag_near_peak", ["--suite", "{new}.json"], "--suite"),
    ("lag_near_peak", ["--suite", "{text}"], "--suite"),
    ("lag_near_peak", ["--env", "CartPole-v1"], "--env"),
    ("lag_near_peak", ["--levels", "nan"], "--levels"),
    ("lag_near_peak", ["--levels", "0.5", "-1"], "--levels"),
    ("lag_near_peak", ["--levels", "2"], "--levels"),
    ("lag_near_peak", ["--levels", "0"], "--levels"),
    ("lag_near_peak", ["--frequency", "nan"], "--frequency"),
    ("lag_near_peak", ["--frequency", "0"], "--frequency"),
    ("lag_near_peak", ["--frequency", "21"], "--frequency"),
    ("lag_near_peak", ["--amplitude-ratio", "-1"], "--amplitude-ratio"),
    ("lag_near_peak", ["--amplitude-ratio", "0"], "--amplitude-ratio"),
    ("lag_near_peak", ["--amplitude-ratio", "inf"], "--amplitude-ratio"),
    ("lag_near_peak", ["--summary", "--out", "{dir}"], "--out"),
    ("ppo_seeds", ["--runs", "{new}", "--out", "{new}"], "--runs"),
    ("ppo_seeds", ["--runs", "{dir}", "--out", "{new}"], "--runs"),
    ("ppo_seeds", ["--runs", "{run_corrupt}", "--out", "{new}"], "--runs"),
    ("ppo_seeds", ["--runs", "{run_corrupt}", "--out", "{file}"], "--out"),
    ("ppo_seeds", ["--runs", "{run_corrupt}", "--jobs", "0", "--out", "{new}"], "--jobs"),
    ("zoo_eval", ["{new}.zip"], "model"),
    ("zoo_eval", ["{corrupt}"], "model"),
    ("zoo_eval", ["{text}"], "model"),
    ("zoo_eval", ["{corrupt}", "--episodes", "0"], "--episodes"),
    ("noise_reading", ["--episodes", "1", "--out", "{dir}"], "--out"),
    ("noise_reading", ["--episodes", "1", "--out", "{file}/t.md"], "--out"),
    ("torque_balance", ["--threshold-deg", "91"], "--threshold-deg"),
    ("torque_balance", ["--threshold-deg", "nan"], "--threshold-deg"),
    ("torque_balance", ["--suites", "{new}"], "--suites"),
    ("torque_balance", ["--suites", "{text}"], "--suites"),
    ("torque_balance", ["--out", "{dir}"], "--out"),
    ("indistinguishable_peaks", ["--out", "{dir}"], "--out"),
    ("knee_twins", ["--out", "{dir}"], "--out"),
    ("paired_comparison", ["{text}", "--out", "{dir}"], "--out"),
    ("estimate_interval", ["--coverage", "1"], "--coverage must be a finite number in (0, 1), got 1"),
    ("estimate_interval", ["--coverage", "nan"], "--coverage must be a finite number in (0, 1), got nan"),
    ("estimate_interval", ["--lower-coverage", "0"], "--lower-coverage"),
    ("estimate_interval", ["--workers", "0"], "--workers"),
    ("estimate_interval", ["--out", "{dir}"], "--out"),
    ("estimate_interval", ["--policy", "{dir}"], "--policy"),
    ("sensor_sensitivity", ["--agents", "oracle,nope"], "--agents"),
    ("sensor_sensitivity", ["--workers", "0"], "--workers"),
    ("sensor_sensitivity", ["--out", "{dir}"], "--out"),
    ("runaways_by_option", ["{text}", "--option", "torque_gain_error", "--edges", "nan"], "--edges"),
    ("runaways_by_option", ["{text}", "--option", "torque_gain_error", "--edges", "0.1", "0.05"], "--edges"),
    ("runaways_by_option", ["{text}", "--grids", "validation_torque", "--option", "nope", "--edges", "0.1"], "--option"),
    ("runaways_by_option", ["{text}", "--grids", "nope", "--option", "torque_gain_error", "--edges", "0.1"], "--grids"),
    ("runaways_by_option", ["{text}", "--grids", "validation_torque", "--option", "torque_gain_error", "--edges", "0.1"],
     "records"),
    ("runaways_by_option", ["{text}", "--option", "torque_gain_error", "--edges", "0.1", "--out", "{dir}"], "--out"),
    ("rule_check", ["{text}", "{text}"], "records"),
    ("rule_check", ["{text}", "{text}", "--more-runaways", "-1"], "--more-runaways"),
    ("rule_check", ["{text}", "{text}", "--out", "{dir}"], "--out"),
    ("rule_check", ["{text}", "{text}", "--family-wise"], "--family-wise"),
    ("frontier", ["{text}"], "records"),
    ("frontier", ["{new}"], "records"),
    ("frontier", ["{text}", "--figure", "{file}"], "--figure"),
    ("frontier", ["{text}", "--shipped", "{file}"], "--shipped"),
    ("frontier", ["{text}", "{text}"], "records"),
    ("frontier", ["{text}", "--out", "{dir}"], "--out"),
    ("frontier", ["{text}", "--references", "{text}"], "records"),
    ("frontier", ["{text}", "--rows"], "--rows"),
    ("scripted_plays", ["--agents", "oracle", "--records", "{new}"], "--agents"),
    ("scripted_plays", ["--agents", "nope", "--records", "{new}"], "--agents"),
    ("scripted_plays", ["--agents", "phase-rule", "robust-model", "--records", "{new}"], "--records"),
    ("scripted_plays", ["--agents", "phase-rule", "--records", "{dir}"], "--records"),
    ("scripted_plays", ["--agents", "phase-rule", "--records", "{new}", "--grids", "nope"], "--grids"),
    ("pool_ensembles", ["{SHIPPED}", "--out", "{new}"], "DIR"),
    ("pool_ensembles", ["{SHIPPED}", "{dir}", "--out", "{new}"], "DIR"),
    ("pool_ensembles", ["{SHIPPED}", "{text}", "--out", "{new}"], "DIR"),
    ("pool_ensembles", ["{SHIPPED}", "{SHIPPED}", "--out", "{file}"], "--out"),
    ("pool_ensembles", ["{SHIPPED}", "{SHIPPED}", "--out", "{SHIPPED}"], "--out"),
    ("match_creep_threshold", ["--reference", "{dir}", "--candidate", "{SHIPPED}", "--climbs", "{file}"],
     "--reference"),
    ("match_creep_threshold", ["--reference", "{SHIPPED}", "--candidate", "{new}", "--climbs", "{file}"],
     "--candidate"),
    ("match_creep_threshold", ["--reference", "{SHIPPED}", "--candidate", "{SHIPPED}", "--climbs", "{text}"],
     "--climbs"),
    ("match_creep_threshold", ["--reference", "{SHIPPED}", "--candidate", "{SHIPPED}", "--climbs", "{file}",
                               "--threshold", "0"], "--threshold"),
    ("match_creep_threshold", ["--reference", "{SHIPPED}", "--candidate", "{SHIPPED}", "--climbs", "{file}",
                               "--near", "nan"], "--near"),
    ("match_creep_threshold", ["--reference", "{SHIPPED}", "--candidate", "{SHIPPED}", "--climbs", "{file}",
                               "--candidate-threshold", "-0.1"], "--candidate-threshold"),
    ("match_creep_threshold", ["--reference", "{SHIPPED}", "--candidate", "{SHIPPED}", "--climbs", "{file}",
                               "--candidate-threshold", "0.09", "--exponent", "5"], "--exponent"),
    ("match_creep_threshold", ["--reference", "{SHIPPED}", "--candidate", "{SHIPPED}", "--climbs", "{file}",
                               "--candidate-threshold", "0.09", "--min-ratio", "0.5"], "--min-ratio"),
    ("match_creep_threshold", ["--reference", "{SHIPPED}", "--candidate", "{SHIPPED}", "--climbs", "{file}",
                               "--exponent", "0.7"], "--exponent"),
    ("peak_creepage_records", ["--suite", "{file}", "--records", "{text}"], "--suite"),
    ("peak_creepage_records", ["--suite", str(EXPERIMENTS / "suites" / "v2_validation_grid.json"), "--records",
                               "{text}"], "records"),
    ("peak_creepage_records", ["--suite", "{file}", "--records", "{text}", "--out", "{dir}"], "--out"),
]


@pytest.mark.parametrize("script, args, option", CASES, ids=[f"{s}{' '.join(a)}" for s, a, _ in CASES])
def test_a_bad_option_exits_2_naming_it_before_any_output(script: str, args: list[str], option: str, tmp_path: Path,
                                                          experiment_exit) -> None:
    (tmp_path / "dir").mkdir()
    (tmp_path / "file").write_text("a file\n")
    (tmp_path / "text").write_text('{"not": "climbs"}\n')
    (tmp_path / "corrupt.zip").write_bytes(b"PK\x03\x04garbage")
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "model.zip").write_bytes(b"PK\x03\x04garbage")
    names = {"dir": tmp_path / "dir", "file": tmp_path / "file", "text": tmp_path / "text",
             "corrupt": tmp_path / "corrupt.zip", "run_corrupt": tmp_path / "run", "new": tmp_path / "new",
             "SHIPPED": SHIPPED_INTERROGATOR}
    before = sorted(tmp_path.rglob("*"))
    code, last = experiment_exit(script, [a.format(**{k: str(v) for k, v in names.items()}) for a in args])
    assert code == 2
    assert last.startswith(f"{script}.py: error: ") and option in last, last  # the one line (experiment_exit)
    assert sorted(tmp_path.rglob("*")) == before  # nothing created, not even --out's directory


# every experiments script with a command line (a main() that adds arguments), found rather than listed so
# that a new script is checked too
SCRIPTS = sorted(path.stem for path in EXPERIMENTS.glob("*.py")
                 if "def main(" in (text := path.read_text()) and ".add_argument(" in text)
# what a script requires, so that the unknown option (not a missing argument) is the error; plain paths,
# never read: the command line is refused before anything is opened
REQUIRED = {"assemble_policy": ["--filter", "f", "--out", "o"], "feature_block_nll": ["--climbs", "climbs.npz"],
            "paired_comparison": ["records.jsonl"],
            "runaways_by_option": ["records.json", "--option", "x", "--edges", "0"],
            "ppo_seeds": ["--runs", "run"], "zoo_eval": ["model.zip"], "rule_check": ["base.json", "candidate.json"],
            "frontier": ["records.json"], "scripted_plays": ["--agents", "phase-rule", "--records", "r.json"],
            "learned_caution": ["--out", "o"], "headroom_bias": ["--networks", "a=n", "--climbs", "c.npz"],
            "encoder_lag_reading": ["--sharp", "a.npz", "--lagged", "b.npz"],
            "pool_ensembles": ["a", "b", "--out", "o"],
            "match_creep_threshold": ["--reference", "r", "--candidate", "c", "--climbs", "c.npz"],
            "noise_colour_reading": ["c.npz"], "peak_creepage_records": ["--suite", "s.json", "--records", "r.json"]}


def test_every_script_parses_with_the_one_line_parser() -> None:
    assert len(SCRIPTS) >= 15, SCRIPTS
    for script in SCRIPTS:
        text = (EXPERIMENTS / f"{script}.py").read_text()
        assert "argparse.ArgumentParser(" not in text and " Parser(" in text, script


@pytest.mark.parametrize("script", SCRIPTS)
def test_an_unknown_option_is_one_line_exit_2_and_help_exits_0(script: str, tmp_path: Path, monkeypatch,
                                                               capsys, experiment_exit) -> None:
    """The unknown option and --help through the script's main(), in-process (a subprocess per script would
    import numpy, gymnasium and torch again: about 2 s each; the real command line of crest_tradeoff.py,
    learning_curve.py, train_interrogator.py and trace_climb.py is checked in a subprocess by their own tests)."""
    monkeypatch.chdir(tmp_path)
    code, line = experiment_exit(script, ["--no-such-option", *REQUIRED.get(script, [])])  # one stderr line
    assert code == 2
    assert line == f"{script}.py: error: unrecognized arguments: --no-such-option (see {script}.py --help)"
    assert list(tmp_path.iterdir()) == []  # nothing written

    module = importlib.import_module(script)  # experiment_exit put experiments/ on the path
    monkeypatch.setattr(sys, "argv", [str(EXPERIMENTS / f"{script}.py"), "--help"])
    with pytest.raises(SystemExit) as exit_:
        module.main()
    assert exit_.value.code == 0
    out, err = capsys.readouterr()
    assert out.startswith(f"usage: {script}.py ") and err == ""


def test_the_robust_model_selection_reads_its_grid_from_any_directory(tmp_path: Path, monkeypatch) -> None:
    import select_robust_model

    monkeypatch.chdir(tmp_path)
    assert len(select_robust_model.episodes(quick=True)) > 0


def test_runaways_by_option_counts_each_setting_per_band_of_the_grid_files_values() -> None:
    """Each episode falls in the band of its grid file's option value (its magnitude with ``absolute``), and a band
    counts that setting's macro-slips among its episodes."""
    import runaways_by_option as rbo
    from crest_tradeoff import GRID_SETS

    values = rbo.option_values(rbo.grid_episodes(GRID_SETS["validation_torque"]), "torque_gain_error")
    gains = values["family"][:6]
    records = [{"setting": s, "grid": "family", "config": {}, "episode": i, "macro_slip": s == "b" and i % 2 == 0}
               for s in ("a", "b") for i in range(6)]
    text = rbo.table(records, values, "torque_gain_error", [0.05], absolute=True)
    low = [i for i, g in enumerate(gains) if abs(g) < 0.05]
    row_b = [line for line in text.splitlines() if line.startswith("| b |")][0]
    slips_low = sum(i % 2 == 0 for i in low)
    assert f"| {slips_low} of {len(low)} | {3 - slips_low} of {6 - len(low)} | 3 of 6 |" in row_b, text
    assert "| a | 0 of" in text and "| 0 of 6 |" in text


def test_peak_creepage_records_bins_each_settings_episodes_by_their_curves_peak() -> None:
    """Each record falls in the band of its own episode's peak creepage in its configuration; a band's row counts
    its climbs, their median error and macro-slips, and how they ended; empty bands are left out."""
    import peak_creepage_records as pcr

    plain, counter = pcr._config({"config": {}}), pcr._config({"config": {"counter_torque": True}})
    peaks = {(plain, 0): 0.005, (plain, 1): 0.05, (counter, 0): 0.05, (counter, 1): 0.05}
    records = [{"setting": "a", "config": config, "episode": i, "error": error, "macro_slip": slip,
                "peak_torque_fraction": 0.5, "ended": ended, "signed_error": -error}
               for config, i, error, slip, ended in [({}, 0, 0.1, True, "macro-slip"), ({}, 1, 0.2, False, "horizon"),
                                                     ({"counter_torque": True}, 0, 0.4, False, "horizon"),
                                                     ({"counter_torque": True}, 1, 0.6, False, "headroom")]]
    rows = pcr.table(records, peaks).splitlines()[2:]
    assert rows == ["| a | peak creepage < 1 % | 1 | 10.0 % | 10.0 % | -10.0 % | 1 | 50.0 % | macro-slip 1 |",
                    "| a | peak creepage 4+ % | 3 | 40.0 % | 56.0 % | -40.0 % | 0 | 50.0 % | "
                    "horizon 2, headroom 1 |"], rows


def test_own_window_fit_keeps_the_rising_windows_and_tables_each_ending() -> None:
    """A window whose CoA fell under a torque that did not (ClimbRecord's rule) and one with no positive creepage are
    left out of the fit, a CoA that fell under a lowered torque is kept; the table has a row per ending and one for
    all, over the episodes that had a fit."""
    import own_window_fit as owf

    windows = [(0.05, 0.001, 20.0, 0.02, 100.0), (0.10, 0.002, 20.0, 0.04, 200.0), (0.09, 0.003, 20.0, 0.04, 210.0),
               (0.12, -0.001, 20.0, 0.05, 250.0), (0.13, 0.004, 20.0, 0.05, 260.0), (0.125, 0.004, 20.0, 0.05, 240.0)]
    assert owf.rising_windows(windows) == [windows[0], windows[1], windows[4], windows[5]]
    rows = [{"ended": "stop", "learned": 0.01, "fit_mean": -0.1, "fit_swing": 0.02},
            {"ended": "horizon", "learned": -0.05, "fit_mean": 0.2, "fit_swing": -0.04},
            {"ended": "macro-slip", "learned": 0.3}]
    lines = owf.table(rows).splitlines()
    assert lines[2] == "| stop | 1 | 1.0% / 1.0% | 10.0% / 10.0% | 2.0% / 2.0% |"
    assert lines[3] == "| horizon | 1 | 5.0% / 5.0% | 20.0% / 20.0% | 4.0% / 4.0% |"
    assert lines[4].startswith("| all | 2 |")
    assert lines[-1].startswith("3 episodes, 1 of them macro-slips; 1 with fewer than three")


def test_shadow_reading_tables_each_ending_with_where_the_shadow_would_have_stopped() -> None:
    """Per ending: both estimates' median / P90, the median of every window's headroom std, and the climbs where the
    shadow's cautious headroom closed before the host's stop with the median utilisation there (None: it never did)."""
    import shadow_reading as sr

    rows = [{"ended": "stop", "host": 0.01, "shadow": -0.02, "stds": [0.1, 0.3], "early": 0.6},
            {"ended": "stop", "host": -0.03, "shadow": 0.04, "stds": [0.2], "early": None},
            {"ended": "macro-slip", "host": 0.05, "shadow": 0.0, "stds": [0.5], "early": 0.9}]
    lines = sr.table(rows, "host").splitlines()
    assert lines[2].startswith("| stop | 2 | ") and lines[2].endswith(" | 0.20 | 1, 60% |")
    assert lines[3].startswith("| macro-slip | 1 | 5.0% / 5.0% | 0.0% / 0.0% | 0.50 | 1, 90% |")
    assert lines[4].startswith("| all | 3 |") and len(lines) == 5  # no climb ended at the horizon: no row


def test_ppo_seeds_refuses_a_run_trained_on_another_env_than_its_v1_grids(tmp_path: Path, experiment_exit) -> None:
    """ppo_seeds.py selects on v1 grids: a run that `cof-gym train` made on its default v2 id is named, with the flag
    that trains the recipe's env, before anything is played."""
    import json
    import shutil

    import cof_gym
    from cof_gym.agents.registry import SHIPPED_PPO

    run = tmp_path / "run"
    run.mkdir()
    for name in ("model.zip", "vecnormalize.pkl"):
        shutil.copyfile(SHIPPED_PPO / name, run / name)
    meta = json.loads((SHIPPED_PPO / "train_meta.json").read_text())
    (run / "train_meta.json").write_text(json.dumps({**meta, "env_id": cof_gym.WAGON_ENV_ID}))
    code, last = experiment_exit("ppo_seeds", ["--runs", str(run), "--out", str(tmp_path / "new")])
    assert code == 2
    assert last.startswith("ppo_seeds.py: error: --runs: ") and f"was trained on {cof_gym.WAGON_ENV_ID}" in last, last
    assert "cof-gym train --env CofGym/TorqueInterrogation-v1" in last
    assert not (tmp_path / "new").exists()
