"""experiments/track_lag_spread.py: one row per track, frequency and modulation ratio, each reading the spread of the
lags a held DC's windows read and the lock-in's SE, from the same episodes on every track."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import gymnasium as gym

import cof_gym
from cof_gym.commands.suites import make_suite

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
from track_lag_spread import lag_spread, table  # noqa: E402


def test_the_table_has_a_row_per_setting_and_a_level_track_reads_as_its_own_episode():
    suite = make_suite("in-service", 1, 0)
    env = gym.make(cof_gym.WAGON_IN_SERVICE_ENV_ID)
    rows = table(env, list(suite.episodes), ["smooth", "ore_high"], [5.0], [0.4], 0.5, 3)
    seed, options = suite.episodes[0]
    smooth = lag_spread(env, seed, {**options, "track_irregularity": "smooth"}, 0.5, 0.4, 5.0, 3)
    env.close()
    assert len(rows) == 2 + 2 and rows[2].startswith("| smooth | 5 | 0.4 |") and rows[3].startswith("| ore_high |")
    cells = [float(c) for c in rows[2].strip("| ").split(" | ")[3:]]
    assert all(math.isfinite(c) for c in cells) and cells[1] > 0 and cells[2] > 0
    # one episode: the row is that episode's own reading, as lag_spread gives it (rounded as printed)
    assert cells[:3] == [round(smooth[0], 1), round(smooth[1], 2), round(smooth[2], 2)]
