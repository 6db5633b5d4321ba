"""Published v3 numbers never change: fixed-seed trajectories of ``CofGym/TorqueInterrogationInService-v3``
(``tests/golden/make_v3_golden.py``: the speed probe and the track drawn, a fixed probe on a smooth track, the counter
torque, the rotation lock-in, a stop, a horizon and a macro-slip) equal the ones the generator wrote when task v3 was
added (``tests/golden/v3_summary.json``), within the v2 golden test's tolerances (``tests/test_v2_golden.py``'s
docstring: the track's cosines and the pulses' timing are float64 arithmetic of the same kind as the physics')."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

GOLDEN = Path(__file__).parent / "golden"
sys.path.insert(0, str(GOLDEN))
sys.path.insert(0, str(Path(__file__).parent))
from make_v3_golden import CASES  # noqa: E402
from make_v2_golden import trajectory  # noqa: E402
from test_v2_golden import assert_trajectory_unchanged  # noqa: E402

EXPECTED = json.loads((GOLDEN / "v3_summary.json").read_text())


def test_every_case_is_in_the_golden_file_and_every_ending_is_pinned() -> None:
    assert sorted(CASES) == sorted(EXPECTED)
    last = [case["ended"][-1] for case in EXPECTED.values()]  # (terminated, truncated, macro-slip) of each last window
    assert [True, False, False] in last and [False, True, False] in last and [True, False, True] in last


def test_the_cases_draw_the_probe_and_the_track() -> None:
    """Every drawn case reads a pulse encoder with a runout and a lag (what v3 adds), the fixed one its own probe."""
    truths = {name: case["ground_truth"] for name, case in EXPECTED.items()}
    assert all(60 <= t["encoder_pulses_per_rev"] <= 300 and 0 < t["encoder_runout"] <= 0.001
               and 0 < t["encoder_lag_s"] <= 0.005 for name, t in truths.items() if "fixed" not in name)
    fixed = truths["in_service/fixed_probe_smooth/seed6"]
    assert fixed["encoder_pulses_per_rev"] == 100 and fixed["encoder_runout"] == 0.0005


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_v3_trajectory_unchanged(name: str) -> None:
    assert_trajectory_unchanged(trajectory(*CASES[name]), EXPECTED[name])
