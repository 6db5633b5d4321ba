"""experiments/learning_curve.py: a size's member is the recipe's member for that many climbs, every row
is scored on the same held-apart windows, and bad input exits 2 with one line before any climb is
collected."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator.training import FitSettings, collect, fit_member, nll

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"
sys.path.insert(0, str(EXPERIMENTS))
from learning_curve import table  # noqa: E402
from train_interrogator import CONFIGS, split  # noqa: E402


def test_each_size_is_the_recipes_member_scored_on_the_windows_held_apart(tmp_path: Path) -> None:
    data = collect(cof_gym.WAGON_ENV_ID, CONFIGS, 20, first_seed=5_000_000)
    member = fit_member(split(data.subset(data.episode < 10))[0], 0, FitSettings(epochs=2))
    member.save(tmp_path / "member_0.npz")
    text = table(data, [10, 20], 0, [tmp_path], epochs=2)
    rows = [line for line in text.splitlines() if line.startswith("| ") and not line.startswith("| networks")]
    assert [r.split(" | ")[1] for r in rows] == ["first 10", "first 20", "-"]
    held = split(data)[1]
    assert set(np.unique(held.episode)) == {9, 19}
    # the member fitted on the first 10 climbs (the recipe's env=10) and the saved copy score alike
    first, saved = rows[0].split(" | ")[2:6], rows[2].split(" | ")[2:6]
    assert first == saved == [f"{nll(member, held)[c]:.3f}" for c in
                              ("headroom_rmse", "headroom_nll", "correction_rmse", "correction_nll")]


@pytest.mark.parametrize("args, option", [(["--sizes", "9000"], "--sizes"), (["--sizes", "0"], "--sizes"),
                                          (["--ensembles", "no/such/run"], "--ensembles"),
                                          (["--climbs", "nothing=5"], "--climbs"), (["--epochs", "0"], "--epochs")])
def test_bad_options_exit_2_naming_the_option(args: list[str], option: str, tmp_path: Path, experiment_exit) -> None:
    code, last = experiment_exit("learning_curve", ["--run", str(tmp_path / "run"), *args, "--out", str(tmp_path / "t.md")])
    assert code == 2 and option in last
    assert not (tmp_path / "run").exists() and not (tmp_path / "t.md").exists()


def test_a_bad_option_on_the_command_line_exits_2_naming_it(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, str(EXPERIMENTS / "learning_curve.py"), "--run", str(tmp_path / "run"),
                           "--sizes", "0", "--out", str(tmp_path / "t.md")], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("learning_curve.py: error: --sizes"), done.stderr
