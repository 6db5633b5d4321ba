"""Published v2 numbers never change: fixed-seed trajectories of both v2 ids (``tests/golden/make_v2_golden.py``:
the creep-law families drawn and a user's table, drawn and given sensor errors, the counter torque, the half
wheelset, two tones, relative actions with the history observation, stops, horizons and macro-slips) equal
the ones the generator wrote at the commit whose v2 numbers are published (``tests/golden/v2_summary.json``).

Tolerances, as for v1 (``tests/test_v1_golden.py``): the physics is deterministic for one MuJoCo build, and what
may differ across CPUs and BLAS kernels is the lock-in's linear solve, a few ulps of float64. The float32
observations take that as at most a rounding flip of their last bits: 1e-6 relative (8 float32 ulps) plus an
absolute 1e-6 for values that are ~0. Every float64 reading and truth downstream of a solve is held to the same
1e-6 relative, with an absolute floor of 1e-9 of the largest magnitude the field takes in the episode (a value
that is ~0 by cancellation carries the rounding of its operands' scale). The reward is held to 1e-9: its terms read
a solve only through the estimate (a relative action's factor on the best measured CoA, a few float64 ulps) and the
comfort filters' design (scipy's tf2zpk, LAPACK's roots: as many ulps), each a few 1e-16 of the term, far below it.

A standard error is such a cancellation too: the scatter of what the fit leaves of the signal. With little noise
that residual is ~1e-6 of the signal, so a fit that moves by ~1e-11 of itself moves the SE by ~1e-6 of itself (on a
second machine in session 57, with the physics identical to the bit: the phase lag and the amplitude ratio by up to
1.6e-11, the phase SE by up to 3.5e-6). An SE is therefore held to
the tolerance of the quantity it qualifies: a phase's SE in degrees to 1e-6 of 90 deg, as the observation holds it
(SE / 90 within an absolute 1e-6), and the CoA bins' SE to 1e-6 of the largest CoA crest the episode reaches."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

GOLDEN = Path(__file__).parent / "golden"
sys.path.insert(0, str(GOLDEN))
from make_v2_golden import CASES, trajectory  # noqa: E402

EXPECTED = json.loads((GOLDEN / "v2_summary.json").read_text())


def absolute_floor(key: str, want: list[dict]) -> float:
    """A field's absolute tolerance (module docstring): an SE's from the quantity it qualifies, else 1e-9 of the
    field's largest magnitude."""
    if key.endswith("_se_deg"):
        return 1e-6 * 90.0
    if key == "coa_cycle_bin_se":
        return 1e-6 * max(abs(row["coa_cycle_max"]) for row in want)
    return 1e-9 * max(abs(row[key]) for row in want)


# entries the env added after the golden file was written: the encoder lag of the ground truth (session 59) and the
# encoder's pulses and runout (session 83), with the value every drawn episode has (no case fixes them), a new
# reading (session 59), any finite number, and the rotation lock-in's ripple (session 85), not read by the plain
# lock-in of every case; each must be there, and the rest must be what the golden file holds
ADDED_SINCE_GOLDEN = {"encoder_lag_s": 0.0, "encoder_pulses_per_rev": 0, "encoder_runout": 0.0,
                      "phase_lag_se_corrected_deg": None, "rotation_ripple_rad_s": 0.0,
                      "rotation_ripple_phase_se_deg": 180.0}


def without_added(got: list[dict], want: list[dict]) -> list[dict]:
    """``got`` less the entries of :data:`ADDED_SINCE_GOLDEN` that ``want`` lacks, each checked for its value."""
    out = []
    for g, w in zip(got, want):
        added = {key: value for key, value in ADDED_SINCE_GOLDEN.items() if key not in w and key in g}
        assert all(np.isfinite(g[key]) if value is None else g[key] == value for key, value in added.items()), added
        out.append({key: value for key, value in g.items() if key not in added})
    return out


def assert_fields_close(got: list[dict], want: list[dict]) -> None:
    """Every field of every window within 1e-6 relative, or its absolute floor (:func:`absolute_floor`)."""
    got = without_added(got, want)
    assert [sorted(g) for g in got] == [sorted(w) for w in want]
    for key in want[0]:
        w = np.array([row[key] for row in want])
        g = np.array([row[key] for row in got])
        np.testing.assert_allclose(g, w, rtol=1e-6, atol=absolute_floor(key, want), err_msg=key)


def test_every_case_is_in_the_golden_file_and_every_ending_is_pinned() -> None:
    assert sorted(CASES) == sorted(EXPECTED)
    last = [case["ended"][-1] for case in EXPECTED.values()]  # (terminated, truncated, macro-slip) of each last window
    assert [True, False, False] in last and [False, True, False] in last and [True, False, True] in last


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_v2_trajectory_unchanged(name: str) -> None:
    assert_trajectory_unchanged(trajectory(*CASES[name]), EXPECTED[name])


def assert_trajectory_unchanged(got: dict, want: dict) -> None:
    """A case's trajectory as its golden file holds it, within the module docstring's tolerances."""
    assert got["ended"] == want["ended"]  # the same windows, ended alike (stop, horizon, macro-slip)
    np.testing.assert_allclose(got["reset_obs"], want["reset_obs"], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(got["obs"], want["obs"], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(got["reward"], want["reward"], rtol=1e-9, atol=1e-12)
    assert_fields_close([got["ground_truth"]], [want["ground_truth"]])
    assert_fields_close(got["step_truth"], want["step_truth"])
    assert_fields_close(got["measurement"], want["measurement"])
