"""Published v1 numbers never change: a fixed-seed summary of both v1 ids (a fixed action climb, three
seeds: reset and step observations, rewards, the ground truth) equals the one the v1 release wrote
(``tests/golden/v1_summary.json``, from ``tests/golden/make_v1_golden.py`` at the v1 commit).

Tolerances: the physics is deterministic for one MuJoCo build; what may differ across CPUs and BLAS
kernels is the sine fit's linear solve (a few ulps of float64), which reaches the float32
observations as at most a rounding flip of the last bits: 1e-6 relative (8 float32 ulps) plus an
absolute 1e-6 for values that are ~0. The ground truth's CoF, the seeded draw, is held to 1e-12 (a few float64 ulps
of its scaling); the saturation torque (the CoF times the static load transfer's balance) and the reward (its terms
reach a solve only through the estimate and the comfort filters' design, a few float64 ulps of a term) to 1e-9,
orders of magnitude above those ulps and below any change of the physics."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

GOLDEN = Path(__file__).parent / "golden"
sys.path.insert(0, str(GOLDEN))
from make_v1_golden import summary  # noqa: E402

EXPECTED = json.loads((GOLDEN / "v1_summary.json").read_text())


@pytest.fixture(scope="module")
def current() -> dict:
    return summary()


@pytest.mark.parametrize("key", sorted(EXPECTED))
def test_v1_summary_unchanged(current, key):
    want, got = EXPECTED[key], current[key]
    assert got["cof"] == pytest.approx(want["cof"], rel=1e-12)
    assert got["saturation_torque_nm"] == pytest.approx(want["saturation_torque_nm"], rel=1e-9)
    np.testing.assert_allclose(got["reset_obs"], want["reset_obs"], rtol=1e-6, atol=1e-6)
    assert len(got["obs"]) == len(want["obs"])
    np.testing.assert_allclose(got["obs"], want["obs"], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(got["reward"], want["reward"], rtol=1e-9, atol=1e-12)
