"""experiments/paired_comparison.py: paired differences of a setting against the baseline over the same
episodes, with bootstrap CIs; a bad records file or baseline exits 2 with one line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
from paired_comparison import differences, paired, table  # noqa: E402


def records(settings: dict[str, np.ndarray], slips=()) -> list[dict]:
    """Episodes of one grid in two vehicle configurations, one error array per setting."""
    out = []
    for setting, errors in settings.items():
        for i, e in enumerate(errors):
            config = {} if i % 2 else {"counter_torque": True}
            out.append({"setting": setting, "grid": "family", "config": config, "episode": i // 2, "error": float(e),
                        "macro_slip": i in slips, "episode_return": -float(e)})
    return out


def test_the_same_errors_differ_by_nothing_and_halved_errors_by_half_their_statistics():
    errors = np.random.default_rng(1).uniform(0.0, 0.3, 40)
    recs = records({"shipped": errors, "same": errors, "halved": errors / 2})
    base = paired(recs, "shipped")["family"]
    same = differences(base, paired(recs, "same")["family"])
    assert same == {**{k: (0.0, 0.0, 0.0) for k in ("median", "P90", "return")}, "lower_error": (50.0, 50.0, 50.0)}
    d = differences(base, paired(recs, "halved")["family"])
    assert d["median"][0] == pytest.approx(-50.0 * np.median(errors), abs=1e-9)
    assert d["P90"][0] == pytest.approx(-50.0 * np.percentile(errors, 90), abs=1e-9)
    assert d["median"][2] < 0.0 and d["P90"][2] < 0.0  # every resample: halved errors have a lower median and P90
    assert d["return"][0] == pytest.approx(np.mean(errors) / 2, abs=1e-12) and d["return"][1] > 0.0
    assert d["lower_error"] == (100.0, 100.0, 100.0)  # lower in every episode, so in every resample


def test_the_table_names_every_setting_against_the_baseline_and_refuses_unpaired_episodes():
    errors = np.linspace(0.01, 0.2, 20)
    text = table(records({"shipped": errors, "candidate": errors * 1.1}, slips=(3,)))
    assert "| candidate | family | 20 |" in text and "| 1 -> 1 |" in text and "| shipped | family" not in text
    with pytest.raises(ValueError, match="--baseline"):
        table(records({"shipped": errors}), baseline="nowhere")
    short = [r for r in records({"shipped": errors, "candidate": errors}) if not (r["setting"] == "candidate" and r["episode"] == 0)]
    with pytest.raises(ValueError, match="same episodes"):
        table(short)


def test_settings_limits_the_table_to_the_settings_named():
    errors = np.linspace(0.01, 0.2, 20)
    recs = records({"shipped": errors, "other": errors * 0.9, "candidate": errors * 1.1})
    text = table(recs, compared=["candidate"])
    assert "| candidate | family |" in text and "| other |" not in text
    assert text == table([r for r in recs if r["setting"] != "other"])
    with pytest.raises(ValueError, match="--settings: no setting 'nowhere'"):
        table(recs, compared=["nowhere"])


@pytest.mark.parametrize("content, option", [("[]", "records"), ('[{"x": 1}]', "records"), ("{", "records")])
def test_a_bad_records_file_exits_2_naming_it(tmp_path: Path, content: str, option: str, experiment_exit) -> None:
    path = tmp_path / "records.json"
    path.write_text(content)
    code, last = experiment_exit("paired_comparison", [str(path)])
    assert code == 2 and last.startswith(f"paired_comparison.py: error: {option}")


def test_a_missing_baseline_exits_2_naming_the_option(tmp_path: Path, experiment_exit) -> None:
    path = tmp_path / "records.json"
    path.write_text(json.dumps(records({"shipped": np.ones(4)})))
    code, last = experiment_exit("paired_comparison", [str(path), "--baseline", "other"])
    assert code == 2 and last.startswith("paired_comparison.py: error: --baseline")


def test_an_unknown_setting_exits_2_naming_the_option(tmp_path: Path, experiment_exit) -> None:
    path = tmp_path / "records.json"
    path.write_text(json.dumps(records({"shipped": np.ones(4), "candidate": np.ones(4)})))
    code, last = experiment_exit("paired_comparison", [str(path), "--settings", "other"])
    assert code == 2 and last.startswith("paired_comparison.py: error: --settings")


def run_command(*args) -> subprocess.CompletedProcess:
    """``python experiments/paired_comparison.py ARGS``."""
    script = Path(__file__).resolve().parents[1] / "experiments" / "paired_comparison.py"
    return subprocess.run([sys.executable, str(script), *map(str, args)], capture_output=True, text=True, timeout=120)


def test_the_command_prints_and_writes_the_table(tmp_path: Path) -> None:
    path, out = tmp_path / "records.json", tmp_path / "paired.md"
    path.write_text(json.dumps(records({"shipped": np.linspace(0.0, 0.1, 10), "candidate": np.linspace(0.0, 0.2, 10)})))
    done = run_command(path, "--out", out)
    assert done.returncode == 0, done.stderr
    assert "| candidate | family | 10 |" in done.stdout and done.stdout in out.read_text()


def test_several_files_are_paired_together_and_a_setting_in_two_is_refused(tmp_path: Path, experiment_exit) -> None:
    """The baseline from one file and a candidate from another compare as if one command wrote both."""
    errors = np.linspace(0.0, 0.1, 10)
    one, two = tmp_path / "shipped.json", tmp_path / "candidate.json"
    one.write_text(json.dumps(records({"shipped": errors})))
    two.write_text(json.dumps(records({"candidate": errors / 2})))
    both = tmp_path / "both.json"
    both.write_text(json.dumps(records({"shipped": errors, "candidate": errors / 2})))
    split, joined = run_command(one, two), run_command(both)
    assert split.returncode == 0, split.stderr
    assert split.stdout == joined.stdout
    code, last = experiment_exit("paired_comparison", [str(one), str(one)])
    assert code == 2 and last.startswith("paired_comparison.py: error: records:") and "also in an earlier file" in last


@pytest.mark.parametrize("field, value, message", [
    ("error", float("nan"), r"error must be a finite number >= 0"),
    ("error", True, r"error must be a number >= 0"),
    ("error", -0.5, r"error must be a finite number >= 0"),
    ("error", "0.1", r"error must be a number >= 0"),
    ("macro_slip", 1, r"macro_slip must be a bool"),
    ("episode_return", float("inf"), r"episode_return must be a finite number, got inf"),
    ("grid", None, r"grid must be a grid's name"),  # the keys every table pairs the episodes by
    ("config", "x", r"config must be an object of env arguments"),
    ("episode", -1, r"episode must be an integer >= 0"),
])
def test_a_records_file_with_a_number_no_table_can_read_is_refused_naming_the_episode_and_field(tmp_path, field,
                                                                                                 value, message):
    """A NaN error would pass every comparison (a NaN is above no bound); a bool would count as 1 or 0."""
    from paired_comparison import read_records

    episodes = [{"setting": "a", "grid": "family", "config": {}, "episode": i, "error": 0.1, "macro_slip": False,
                 "episode_return": -1.0} for i in range(3)]
    episodes[1][field] = value
    path = tmp_path / "records.json"
    path.write_text(json.dumps(episodes))
    with pytest.raises(ValueError, match=f"episode 1: {message}"):
        read_records(path, set())
    episodes[1][field] = {"error": 0.2, "macro_slip": True, "episode_return": -2.0, "grid": "steep",
                          "config": {"counter_torque": True}, "episode": 1}[field]
    path.write_text(json.dumps(episodes))
    assert len(read_records(path, set())) == 3
