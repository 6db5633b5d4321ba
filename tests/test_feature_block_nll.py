"""experiments/feature_block_nll.py: a member per feature-block set, scored on held-out training climbs;
bad input exits 2 with one line naming the option."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator.training import collect

SCRIPT = Path(__file__).resolve().parents[1] / "experiments" / "feature_block_nll.py"


@pytest.mark.parametrize("args, option", [(["--climbs", "x.npz", "--blocks", "harmonics"], "--blocks"),
                                          (["--climbs", "x.npz", "--holdout", "0.9"], "--holdout"),
                                          (["--climbs", "/nonexistent.npz"], "--climbs"),
                                          (["--climbs", str(SCRIPT), "--epochs", "0"], "--epochs")])
def test_bad_input_exits_2_naming_the_option(args, option, experiment_exit):
    code, last = experiment_exit("feature_block_nll", args)
    assert code == 2 and last.startswith("feature_block_nll.py: error: ") and option in last


def test_a_member_per_block_set_is_scored_on_whole_held_out_climbs(tmp_path, monkeypatch):
    data = collect(cof_gym.WAGON_ENV_ID, [{}], 6, first_seed=2_000_700)
    data.save(tmp_path / "climbs.npz")
    monkeypatch.syspath_prepend(str(SCRIPT.parent))
    from feature_block_nll import split_episodes

    held = split_episodes(data, 0.34, seed=0)
    for episode in np.unique(data.episode):  # a climb is held out whole or not at all
        assert len(set(held[data.episode == episode])) == 1
    assert len(np.unique(data.episode[held])) == 2
    out = tmp_path / "nll.md"
    done = subprocess.run([sys.executable, str(SCRIPT), "--climbs", str(tmp_path / "climbs.npz"), "--blocks", "none",
                           "climb_fit", "--holdout", "0.34", "--epochs", "2", "--out", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    rows = [line for line in out.read_text().splitlines() if line.startswith("| none, ") or line.startswith("| climb_fit, ")]
    assert [r.split(",")[0] for r in rows] == ["| none"] * 5 + ["| climb_fit"] * 5
    all_rows = [r for r in rows if ", all |" in r]
    for row in all_rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert int(cells[1]) == held.sum() and all(math.isfinite(float(c)) for c in cells[2:])
