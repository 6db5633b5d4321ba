"""The learned interrogator's networks (cof_gym/agents/interrogator/networks.py): files, the ensemble's std, pooling."""

from __future__ import annotations

import numpy as np
import pytest

from cof_gym.agents.interrogator import FEATURE_NAMES, FilterEnsemble, FilterNetwork, pooled_correction
from interrogator_helpers import random_network

def test_network_round_trip_and_feature_check(tmp_path):
    net = random_network()
    net.save(tmp_path / "member_0.npz")
    loaded = FilterNetwork.load(tmp_path / "member_0.npz")
    x = np.random.default_rng(1).normal(size=(5, len(FEATURE_NAMES)))
    for a, b in zip(net(x), loaded(x)):
        np.testing.assert_array_equal(a, b)
    np.savez(tmp_path / "member_1.npz", feature_names=np.asarray(["other"]), feature_mean=np.zeros(1))
    with pytest.raises(ValueError, match="other features"):
        FilterNetwork.load(tmp_path / "member_1.npz")


def test_ensemble_std_combines_spread_and_predicted_variance():
    a, b = random_network(0), random_network(1)
    x = np.random.default_rng(2).normal(size=(4, len(FEATURE_NAMES)))
    mean, std = FilterEnsemble((a, b)).predict(x)
    (ma, la), (mb, lb) = a(x), b(x)
    np.testing.assert_allclose(mean, (ma + mb) / 2, rtol=1e-12)
    np.testing.assert_allclose(std**2, ((ma - mb) / 2) ** 2 + (np.exp(la) + np.exp(lb)) / 2, rtol=1e-12)
    same_mean, same_std, spread = FilterEnsemble((a, b)).predict_with_spread(x)
    np.testing.assert_array_equal(same_mean, mean)
    np.testing.assert_array_equal(same_std, std)
    np.testing.assert_allclose(spread, np.abs(ma - mb) / 2, rtol=1e-12)  # the members' disagreement alone
    assert not FilterEnsemble((a, a)).predict_with_spread(x)[2].any()  # identical members: no spread


def test_pooled_correction_is_the_inverse_variance_mean():
    assert pooled_correction([(0.2, 0.1), (0.5, 0.2)]) == pytest.approx((0.2 / 0.01 + 0.5 / 0.04) / 125.0, rel=1e-12)
    assert pooled_correction([(0.3, 0.05)]) == 0.3
    with pytest.raises(ValueError, match="no predictions"):
        pooled_correction([])


@pytest.mark.parametrize("damage, message", [
    (lambda a: a.pop("w0"), r"no b0|no w0"),
    (lambda a: a.update(w0=a["w0"][:-1]), r"w0 must be \("),
    (lambda a: a.update(feature_std=np.zeros_like(a["feature_std"])), "feature_std must be finite and > 0"),
    (lambda a: a.update(b0=np.full_like(a["b0"], np.nan)), "must be finite"),
])
def test_a_damaged_network_file_is_refused_when_loaded_not_mid_episode(tmp_path, damage, message):
    """Before session 59 these loaded and failed inside an episode (a matmul shape error, a division by zero)."""
    random_network().save(tmp_path / "member_0.npz")
    with np.load(tmp_path / "member_0.npz") as z:
        arrays = {k: z[k] for k in z.files}
    damage(arrays)
    np.savez(tmp_path / "member_0.npz", **arrays)
    with pytest.raises(ValueError, match=message):
        FilterNetwork.load(tmp_path / "member_0.npz")


@pytest.mark.parametrize("content", [b"garbage", b"PK\x03\x04 truncated", np.arange(3)])
def test_a_file_that_is_no_npz_archive_is_refused_in_our_words(tmp_path, content):
    """numpy's own words for garbage speak of pickled data and allow_pickle; a bare .npy array has no files."""
    path = tmp_path / "member_0.npz"
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        with open(path, "wb") as f:
            np.save(f, content)
    with pytest.raises(ValueError, match=r"member_0\.npz: not an interrogator network \((not a readable \.npz archive|"
                                         r"a single array, not an \.npz archive)\)"):
        FilterNetwork.load(path)
