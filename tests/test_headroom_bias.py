"""experiments/headroom_bias.py: the networks' signed headroom error on held-apart climbs; bad input exits 2 with
one line naming the option."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator.training import collect

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "experiments" / "headroom_bias.py"
SHIPPED = ROOT / "cof_gym" / "agents" / "policies" / "interrogator"


@pytest.mark.parametrize("args, option", [
    (["--networks", "shipped", "--climbs", "x.npz"], "--networks"),
    (["--networks", f"a={SHIPPED}", f"a={SHIPPED}", "--climbs", "x.npz"], "--networks"),
    (["--networks", f"a={SCRIPT.parent}", "--climbs", "x.npz"], "--networks"),
    (["--networks", f"a={SHIPPED}", "--climbs", "/nonexistent.npz"], "--climbs"),
    (["--networks", f"a={SHIPPED}", "--climbs", "x.npz", "--caution", "11"], "--caution"),
    (["--networks", f"a={SHIPPED}", "--climbs", "x.npz", "--caution", "nan"], "--caution"),
])
def test_bad_input_exits_2_naming_the_option(args, option, experiment_exit):
    code, last = experiment_exit("headroom_bias", args)
    assert code == 2 and last.startswith("headroom_bias.py: error: ") and option in last


def test_band_errors_are_the_bias_and_the_share_of_bounds_above_the_truth(monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPT.parent))
    from headroom_bias import BANDS, band_errors

    truth = np.array([0.0, 0.015625, 0.125, 0.25, 0.375])  # binary fractions: every difference exact
    mean = truth + np.array([0.5, -0.25, 0.125, 0.25, 0.0])  # binary fractions: exact sums
    std = np.full(5, 0.125)
    rows = band_errors(mean, std, truth, caution=2.0)
    assert len(rows) == len(BANDS)
    assert rows[0] == (2, 0.125, 0.5)  # mean - 0.25 above the truth only for the first window
    assert rows[1] == (1, 0.125, 0.0)
    assert rows[2] == (2, 0.125, 0.0)
    assert band_errors(mean, std, truth, caution=0.0)[2] == (2, 0.125, 0.5)
    empty = band_errors(mean[:1], std[:1], truth[:1], caution=2.0)[2]
    assert empty[0] == 0 and np.isnan(empty[1]) and np.isnan(empty[2])


def test_the_table_scores_every_network_on_every_file(tmp_path):
    data = collect(cof_gym.WAGON_ENV_ID, [{}], 10, first_seed=2_000_700)
    data.save(tmp_path / "climbs_a.npz")
    data.subset(data.episode < 9).save(tmp_path / "climbs_short.npz")
    out = tmp_path / "bias.md"
    done = subprocess.run([sys.executable, str(SCRIPT), "--networks", f"shipped={SHIPPED}",
                           f"guard={SHIPPED / 'guard_0'}", "--climbs", str(tmp_path / "climbs_a.npz"),
                           "--out", str(out)], capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert done.returncode == 0, done.stderr
    rows = [line for line in out.read_text().splitlines() if line.startswith("| a |")]
    assert [row.split(" | ")[1] for row in rows] == ["shipped", "guard"]
    held_windows = int((data.episode == 9).sum())
    counts = [int(cell.split(" / ")[0]) for cell in rows[0].strip("| ").split(" | ")[2:]]
    assert 0 < sum(counts) <= held_windows  # only the tenth climb's windows, those within the bands
    short = subprocess.run([sys.executable, str(SCRIPT), "--networks", f"shipped={SHIPPED}", "--climbs",
                            str(tmp_path / "climbs_short.npz")], capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert short.returncode == 2 and "--climbs" in short.stderr and "fewer than ten climbs" in short.stderr
