"""Behaviour of the ISO 2631-1 Wd weighting filters and the EN 12299 comfort index."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal

from cof_gym.measurement.comfort import (
    band_limiting_sos,
    comfort_label,
    en12299_comfort_index,
    wd_gain,
    wd_weighting_sos,
    weighted_rms,
)

FS = 1000.0


def test_wd_gain_at_5_hz() -> None:
    assert wd_gain(5.0) == pytest.approx(0.41, abs=0.02)


@pytest.mark.parametrize(("f", "expected"), [(1.0, 1.011), (2.0, 0.890), (4.0, 0.512), (8.0, 0.253)])
def test_wd_gain_follows_iso_shape(f: float, expected: float) -> None:
    # ISO 2631-1 table values of Wd (shape check; tolerance 2 %)
    assert wd_gain(f) == pytest.approx(expected, rel=0.02)


@pytest.mark.parametrize("make_sos", [wd_weighting_sos, band_limiting_sos])
@pytest.mark.parametrize("fs", [250.0, 1000.0, 5000.0])
def test_sos_format_and_stability(make_sos, fs: float) -> None:
    sos = make_sos(fs)
    assert sos.ndim == 2 and sos.shape[1] == 6
    assert np.all(np.isfinite(sos))
    np.testing.assert_array_equal(sos[:, 3], 1.0)
    _, poles, _ = signal.sos2zpk(sos)
    assert np.all(np.abs(poles) < 1.0)


def _steady_state_gain(sos: np.ndarray, f: float, fs: float, seconds: float = 20.0) -> float:
    t = np.arange(int(seconds * fs)) / fs
    y = signal.sosfilt(sos, np.sin(2 * np.pi * f * t))
    tail = y[len(y) // 2 :]  # after the 0.4 Hz high-pass transient has decayed
    return float(np.sqrt(2 * np.mean(tail**2)))


def test_discrete_wd_gain_at_5_hz_matches_analog() -> None:
    measured = _steady_state_gain(wd_weighting_sos(FS), 5.0, FS)
    assert measured == pytest.approx(wd_gain(5.0), rel=0.02)


def test_band_limiting_passes_mid_band_and_blocks_dc() -> None:
    sos = band_limiting_sos(FS)
    assert _steady_state_gain(sos, 5.0, FS) == pytest.approx(1.0, rel=0.01)
    y = signal.sosfilt(sos, np.ones(int(30 * FS)))
    assert abs(y[-1]) < 1e-3


def test_weighted_rms_of_5_hz_sine() -> None:
    t = np.arange(int(20 * FS)) / FS
    rms = weighted_rms(np.sin(2 * np.pi * 5.0 * t), FS)
    assert rms == pytest.approx(0.41 / math.sqrt(2), rel=0.03)
    assert rms == pytest.approx(wd_gain(5.0) / math.sqrt(2), rel=0.01)


def test_weighted_rms_band_option_and_linearity() -> None:
    t = np.arange(int(20 * FS)) / FS
    x = np.sin(2 * np.pi * 5.0 * t)
    assert weighted_rms(x, FS, weighting="band") == pytest.approx(1 / math.sqrt(2), rel=0.01)
    assert weighted_rms(3 * x, FS) == pytest.approx(3 * weighted_rms(x, FS), rel=1e-12)


def test_weighted_rms_rejects_bad_input() -> None:
    with pytest.raises(ValueError, match="weighting"):
        weighted_rms(np.zeros(10), FS, weighting="wk")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="acceleration"):
        weighted_rms(np.zeros((2, 2)), FS)


@pytest.mark.parametrize("fs", [200.0, 100.0, 0.0, -1000.0, math.nan])
@pytest.mark.parametrize("make_sos", [wd_weighting_sos, band_limiting_sos])
def test_sample_rate_must_exceed_twice_band_limit(make_sos, fs: float) -> None:
    with pytest.raises(ValueError, match=r"sample_rate_hz.*> 200"):
        make_sos(fs)


def test_comfort_index() -> None:
    assert en12299_comfort_index(0.0, 0.0, 0.0) == 0.0
    assert en12299_comfort_index(0.1, 0.2, 0.2) == pytest.approx(6 * 0.3)
    with pytest.raises(ValueError, match="ay_p95"):
        en12299_comfort_index(0.1, -0.1, 0.1)


@pytest.mark.parametrize(
    ("n_mv", "label"),
    [
        (0.0, "very comfortable"),
        (0.99, "very comfortable"),
        (1.0, "comfortable"),
        (1.99, "comfortable"),
        (2.0, "medium"),
        (3.99, "medium"),
        (4.0, "uncomfortable"),
        (4.99, "uncomfortable"),
        (5.0, "very uncomfortable"),
        (12.0, "very uncomfortable"),
    ],
)
def test_comfort_label_scale(n_mv: float, label: str) -> None:
    assert comfort_label(n_mv) == label


def test_comfort_label_rejects_negative() -> None:
    with pytest.raises(ValueError, match="n_mv"):
        comfort_label(-0.1)
