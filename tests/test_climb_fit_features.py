"""The climb_fit feature block (cof_gym/agents/interrogator/features.py): regressions over the climb's newest
windows. Each is checked against a creep curve whose answer is known in closed form; the tolerances are
those of a least-squares solve on a handful of numbers of order one (1e-9)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from cof_gym.agents.interrogator import (
    CLIMB_FIT_FEATURE_NAMES, CLIMB_FIT_WINDOWS, FEATURE_NAMES, FLEXIBILITY_CLIP, PEAK_GAP_CLIP, EpisodeFeatures,
    Reading, blocks_of, feature_names, fitted_flexibility, fitted_peak_gap, slope_fall, slope_from_compliance,
    slope_from_phase,
)

FREQUENCY_HZ = 5.0


def reading(dc_nm: float, slope_hz: float, coa: float, creepage: float = 0.001) -> Reading:
    """A window whose phase gives the local slope ``slope_from_phase`` = ``slope_hz`` (``f cot(phase)``)
    and whose compliance gives the same slope from ``slope_from_compliance``."""
    phase = math.degrees(math.atan(FREQUENCY_HZ / slope_hz))
    compliance = 1.0 / math.sqrt(1.0 + (slope_hz / FREQUENCY_HZ) ** 2)
    return Reading(phase, 0.5, compliance, coa, creepage, dc_nm, 0.4 * dc_nm, FREQUENCY_HZ, 20.0, 1.0)


def test_the_slope_fall_is_the_power_of_a_slope_that_falls_as_a_power_of_the_torque():
    """``k = K DC^-p``: ``-d ln k / d ln DC`` is ``p`` from the phase and from the compliance alike."""
    torques = 1000.0 * np.exp(0.05 * np.arange(6))
    readings = [reading(m, 40.0 * (m / 1000.0) ** -2.5, 0.1) for m in torques]
    assert slope_fall(readings, slope_from_phase) == pytest.approx(2.5, abs=1e-9)
    assert slope_fall(readings, slope_from_compliance) == pytest.approx(2.5, abs=1e-9)
    flat = [reading(m, 40.0, 0.1) for m in torques]  # the linear part: the slope does not fall
    assert slope_fall(flat, slope_from_phase) == pytest.approx(0.0, abs=1e-9)
    held = [reading(1000.0, 40.0 - k, 0.1) for k in range(4)]  # one torque: no line
    assert slope_fall(held, slope_from_phase) == 0.0


def test_the_fitted_peak_gap_is_the_quadratic_peaks_intercept():
    """Near a smooth maximum ``mu = mu_peak - c k^2``: every window on that law gives the gap
    ``ln(mu_peak / mu_now)`` exactly, whatever the unknown scale of ``k``; a slope that does not fall
    as the CoA rises reads the clip (far from the peak)."""
    mu_peak, c = 0.3, 2e-5
    slopes = [60.0, 50.0, 42.0, 35.0, 30.0]
    readings = [reading(1000.0 * (1 + i), k, mu_peak - c * k**2) for i, k in enumerate(slopes)]
    expected = math.log(mu_peak / (mu_peak - c * slopes[-1] ** 2))
    assert fitted_peak_gap(readings, slope_from_phase) == pytest.approx(expected, abs=1e-9)
    assert fitted_peak_gap(readings, slope_from_compliance) == pytest.approx(expected, abs=1e-9)
    rising_slope = [reading(1000.0 * (1 + i), 30.0 + 5 * i, 0.1 + 0.01 * i) for i in range(5)]
    assert fitted_peak_gap(rising_slope, slope_from_phase) == PEAK_GAP_CLIP


def test_the_fitted_flexibility_is_offset_free_and_scale_free_in_the_creepage():
    """On a line ``s = s0 + a mu`` the fitted flexibility equals the chord's (0); a curve that flattens
    reads more; a creepage offset changes nothing, a creepage scale error changes nothing."""
    coas = [0.05, 0.08, 0.11, 0.14, 0.17]
    line = [reading(1000.0 * (1 + i), 40.0, mu, 0.002 + 0.01 * mu) for i, mu in enumerate(coas)]
    assert fitted_flexibility(line[2:], line[0]) == pytest.approx(0.0, abs=1e-9)
    bent = [reading(1000.0 * (1 + i), 40.0, mu, 0.002 + 0.01 * mu + 0.5 * mu**2) for i, mu in enumerate(coas)]
    value = fitted_flexibility(bent[2:], bent[0])
    assert value > 0.1
    moved = [replace(r, creepage=1.02 * r.creepage + 0.004) for r in bent]  # a scale error and an offset
    assert fitted_flexibility(moved[2:], moved[0]) == pytest.approx(value, abs=1e-9)
    falling = [replace(r, creepage=0.01 - 0.001 * i) for i, r in enumerate(bent)]  # CoA up, creepage down
    assert fitted_flexibility(falling[3:], falling[0]) == 0.0  # no positive chord: no reading
    receding = [replace(r, creepage=0.012 - 0.001 * i) for i, r in enumerate(bent)][2:]  # above the first, falling
    assert fitted_flexibility(receding, bent[0]) == FLEXIBILITY_CLIP  # a CoA rise without a creepage rise


def test_the_block_regresses_over_the_newest_windows_only_and_names_itself():
    """The block appends its names; only the newest CLIMB_FIT_WINDOWS windows enter it (a window
    older than those changes nothing but the base features' own first-window terms)."""
    assert blocks_of(feature_names(("climb_fit",))) == ("climb_fit",)
    assert feature_names(("cycle_crest", "climb_fit"))[-len(CLIMB_FIT_FEATURE_NAMES):] == CLIMB_FIT_FEATURE_NAMES
    torques = 1000.0 * np.exp(0.05 * np.arange(CLIMB_FIT_WINDOWS + 3))
    slopes = 40.0 * (torques / 1000.0) ** -1.5
    windows = [reading(m, k, 0.1 + 0.001 * i) for i, (m, k) in enumerate(zip(torques, slopes))]
    features = EpisodeFeatures(False, blocks=("climb_fit",))
    for w in windows:
        features.push(w)
    block = features.vector()[len(FEATURE_NAMES):]
    assert block.shape == (len(CLIMB_FIT_FEATURE_NAMES),)
    names = dict(zip(CLIMB_FIT_FEATURE_NAMES, block))
    assert names["fit_slope_fall_phase"] == pytest.approx(1.5, abs=1e-9)
    assert names["fit_phase_residual"] == pytest.approx(0.0, abs=1e-9)
    assert names["fit_windows"] == 1.0
    other_start = EpisodeFeatures(False, blocks=("climb_fit",))
    for w in [replace(windows[0], phase_deg=30.0)] + windows[1:]:
        other_start.push(w)
    other = other_start.vector()[len(FEATURE_NAMES):]
    drop = CLIMB_FIT_FEATURE_NAMES.index("fit_flexibility")  # reads the first window's chord by design
    np.testing.assert_allclose(np.delete(other, drop), np.delete(block, drop), rtol=0, atol=1e-12)
    first = EpisodeFeatures(False, blocks=("climb_fit",))
    first.push(windows[0])
    assert np.all(np.isfinite(first.vector()))  # one window: no line, finite defaults
