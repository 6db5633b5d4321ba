"""The helpers the validation-only selections share (experiments/selection.py)."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
from selection import best_per_group, error_summary, group_line  # noqa: E402


def test_error_summary_counts_slips_and_takes_percentiles():
    s = error_summary([0.0, 0.1, 0.2, 0.3, 0.4], [False, True, False, True, False])
    assert s == {"median": 0.2, "p90": pytest.approx(0.36), "macro_slips": 2, "episodes": 5}


def test_error_summary_rejects_no_episodes():
    with pytest.raises(ValueError, match="no episodes"):
        error_summary([], [])


def test_best_per_group_takes_the_first_ranked_row_of_each_group():
    ranked = [{"params": {"a": 2, "b": 1}, "macro_slips": 0, "median": 0.01, "p90": 0.02},
              {"params": {"a": 1, "b": 2}, "macro_slips": 0, "median": 0.02, "p90": 0.03},
              {"params": {"a": 1, "b": 1}, "macro_slips": 1, "median": 0.01, "p90": 0.02}]
    best = best_per_group(ranked, [{"a": 1}, {"a": 2}])
    assert best == [ranked[1], ranked[0]]
    assert group_line({"a": 1}, best[0]) == '  {"a": 1}: 0 / 2.0% / 3.0% with {"b": 2}'
    with pytest.raises(ValueError, match="no row"):
        best_per_group(ranked, [{"a": 3}])
