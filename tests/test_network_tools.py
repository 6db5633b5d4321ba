"""experiments/pool_ensembles.py: two ensembles pooled are one ensemble of all their members, whose mean is the
members' mean (the count-weighted mean of the two ensembles' means); experiments/match_creep_threshold.py: the
candidate's threshold is exceeded as often as the reference's."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR
from cof_gym.agents.interrogator.networks import FilterEnsemble

ROOT = Path(__file__).resolve().parents[1]
GUARD = SHIPPED_INTERROGATOR / "guard_0"


def test_pooled_members_are_copied_in_order_and_predict_their_mean(tmp_path: Path) -> None:
    out = tmp_path / "pool"
    run = subprocess.run([sys.executable, str(ROOT / "experiments" / "pool_ensembles.py"), "--out", str(out),
                          str(SHIPPED_INTERROGATOR), str(GUARD)], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    filter_, guard = FilterEnsemble.load(SHIPPED_INTERROGATOR), FilterEnsemble.load(GUARD)
    sources = sorted(SHIPPED_INTERROGATOR.glob("member_*.npz")) + sorted(GUARD.glob("member_*.npz"))
    pooled_files = [out / f"member_{k}.npz" for k in range(len(sources))]
    assert sorted(out.iterdir()) == sorted(pooled_files)
    assert all(p.read_bytes() == s.read_bytes() for p, s in zip(pooled_files, sources))
    pooled = FilterEnsemble.load(out)
    x = np.random.default_rng(3).normal(size=(4, len(filter_.members[0].feature_names)))
    weights = np.array([len(filter_.members), len(guard.members)]) / len(sources)
    expected = weights[0] * filter_.predict(x)[0] + weights[1] * guard.predict(x)[0]
    # the same float64 member outputs averaged in another grouping: ten terms, a few roundings of the largest apart
    largest = max(np.abs(m(x)[0]).max() for m in pooled.members)
    np.testing.assert_allclose(pooled.predict(x)[0], expected, rtol=0, atol=1e-13 * (1.0 + largest))
    assert f"{len(sources)} members ({len(filter_.members)} + {len(guard.members)})" in run.stdout


def test_the_matched_creep_threshold_is_the_candidates_quantile_at_the_references_trigger_share() -> None:
    sys.path.insert(0, str(ROOT / "experiments"))
    from match_creep_threshold import matched_threshold

    # half the reference's stds exceed 0.08; the candidate's median (its 0.5 quantile) is exceeded as often
    share, threshold = matched_threshold(np.array([0.05, 0.07, 0.09, 0.11]), np.array([1.0, 2.0, 3.0, 4.0, 5.0]), 0.08)
    assert (share, threshold) == (0.5, 3.0)
    share, threshold = matched_threshold(np.array([0.09, 0.1]), np.array([0.2, 0.4]), 0.08)  # always: its minimum
    assert (share, threshold) == (1.0, 0.2)
