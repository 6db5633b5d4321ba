"""experiments/encoder_lag_reading.py: each climb's weighted first-window phase and the AUC that separates lagged
climbs from sharp ones; bad input exits 2 with one line naming the option."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from interrogator_helpers import climbs_reading

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "experiments" / "encoder_lag_reading.py"


def climbs(phase: list[float], se: list[float], episode: list[int]):
    """A climbs file's windows with only the phase, its standard error and the episode set."""
    return climbs_reading(episode, phase_deg=phase, se_deg=se)


def test_the_first_windows_phase_is_their_inverse_variance_mean_per_climb(monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPT.parent))
    from encoder_lag_reading import SE_FLOOR_DEG, first_windows_phase

    # climb 0: phases 10, 40 with standard errors 1, 2 (weights 1, 1/4), a third window beyond k = 2; climb 1: one
    # window whose standard error lies below the floor
    data = climbs([10.0, 40.0, 90.0, 5.0], [1.0, 2.0, 1.0, SE_FLOOR_DEG / 4], [0, 0, 0, 1])
    np.testing.assert_allclose(first_windows_phase(data, 2), [(10.0 + 40.0 / 4) / 1.25, 5.0], rtol=1e-15)
    np.testing.assert_allclose(first_windows_phase(data, 1), [10.0, 5.0], rtol=1e-15)


def test_the_auc_is_the_share_of_pairs_a_lagged_climb_reads_more_ties_half(monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPT.parent))
    from encoder_lag_reading import auc

    assert auc(np.array([3.0, 4.0]), np.array([1.0, 2.0])) == 1.0
    assert auc(np.array([1.0, 2.0]), np.array([1.0, 2.0])) == 0.5
    assert auc(np.array([2.0]), np.array([1.0, 2.0, 3.0])) == 0.5  # one above, one tie (a half), one below


@pytest.mark.parametrize("args, option", [
    (["--sharp", "/nonexistent.npz", "--lagged", "/nonexistent.npz"], "--sharp"),
    (["--sharp", "a.npz", "--lagged", "b.npz", "--windows", "0"], "--windows"),
    (["--lagged", "b.npz"], "--sharp"),
])
def test_bad_input_exits_2_naming_the_option(args, option, experiment_exit):
    code, last = experiment_exit("encoder_lag_reading", args)
    assert code == 2 and last.startswith("encoder_lag_reading.py: error: ") and option in last
