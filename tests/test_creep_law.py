"""Polach creep law (native, through ctypes): CoF = curve maximum, shape, slope, validation."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from cof_gym.physics.contact_geometry import creep_stiffness_constant
from cof_gym.physics.creep import (
    CONDITIONS,
    OperatingConditions,
    PolachShape,
    creep_curve,
    creep_peak,
)

COFS = (0.02, 0.1, 0.4, 0.6)
SPEEDS = (2.0, 10.0, 40.0)
GRID = list(itertools.product(sorted(CONDITIONS), COFS, SPEEDS))


def _ids(grid) -> list[str]:
    return [f"{c}-cof{cof}-v{v:g}" for c, cof, v in grid]


@pytest.mark.parametrize(("condition", "cof", "speed"), GRID, ids=_ids(GRID))
def test_peak_of_creep_curve_equals_cof(condition: str, cof: float, speed: float) -> None:
    op = OperatingConditions(cof=cof, condition=condition, wheel_load_n=100e3, speed_m_s=speed)
    peak = creep_peak(op)
    assert peak.coa == pytest.approx(cof, rel=1e-6)

    # independent of creep_peak's own optimiser: a dense scan of the curve never exceeds the CoF,
    # gets within 1e-6 of it, and the analytic slope vanishes at the reported peak creepage
    s = np.concatenate([np.geomspace(1e-7, 5.0, 4000),
                        peak.creepage * np.linspace(0.98, 1.02, 2001)])
    coa, slope = creep_curve(s, op)
    assert coa.max() <= cof * (1 + 1e-9)
    assert coa.max() >= cof * (1 - 1e-6)
    initial_slope = creep_curve(1e-9, op)[1][0]
    assert abs(creep_curve(peak.creepage, op)[1][0]) < 1e-4 * initial_slope


@pytest.mark.parametrize(("condition", "cof", "speed"), GRID, ids=_ids(GRID))
def test_falling_friction_mu0_above_cof(condition: str, cof: float, speed: float) -> None:
    op = OperatingConditions(cof=cof, condition=condition, speed_m_s=speed)
    mu0 = op.law().mu0
    assert mu0 > cof
    # the curve falls just past the peak and stays below the CoF far beyond it (it may rise again
    # towards A mu0 < CoF at large creepage: Polach's atan term keeps growing as mu levels off)
    peak = creep_peak(op)
    assert creep_curve(1.5 * peak.creepage, op)[1][0] < 0.0
    far = creep_curve(np.geomspace(2.0, 1e3, 200) * peak.creepage, op)[0]
    assert far.max() < cof


def test_a_curve_peaking_above_mu0_is_calibrated_with_mu0_below_the_cof() -> None:
    """k_slip > k_adhesion: the atan (slip) term outgrows the adhesion term, the curve peaks above mu0,
    so mu0 < CoF (the calibration's bracket reaches below the CoF); the peak is still the CoF."""
    cof = 0.2
    op = OperatingConditions(cof=cof, condition=PolachShape(0.1, 1.0, 0.4, 0.6), speed_m_s=10.0)
    assert op.law().mu0 < cof
    peak = creep_peak(op)
    assert peak.coa == pytest.approx(cof, rel=1e-6)
    coa, _ = creep_curve(np.geomspace(1e-7, 5.0, 4000), op)
    assert cof * (1 - 1e-6) <= coa.max() <= cof * (1 + 1e-9)


@pytest.mark.parametrize("condition", sorted(CONDITIONS))
def test_curve_is_odd_in_creepage(condition: str) -> None:
    op = OperatingConditions(cof=0.3, condition=condition, speed_m_s=10.0)
    s = np.concatenate([np.geomspace(1e-6, 1.0, 60), [0.0]])
    coa_pos, slope_pos = creep_curve(s, op)
    coa_neg, slope_neg = creep_curve(-s, op)
    np.testing.assert_array_equal(coa_neg, -coa_pos)
    np.testing.assert_array_equal(slope_neg, slope_pos)  # the derivative of an odd function is even
    assert coa_pos[-1] == 0.0
    assert np.all(coa_pos[:-1] > 0.0)


@pytest.mark.parametrize("condition", sorted(CONDITIONS))
@pytest.mark.parametrize("cof", (0.05, 0.4))
@pytest.mark.parametrize("load", (50e3, 100e3))
def test_initial_slope_is_polach_linear_limit(condition: str, cof: float, load: float) -> None:
    """s -> 0: CoA -> (2/pi)(kA + kS) C s, independent of mu (and so of CoF and speed)."""
    shape = CONDITIONS[condition]
    expected = 2.0 / math.pi * (shape.k_adhesion + shape.k_slip) * creep_stiffness_constant(load)
    for speed in (2.0, 40.0):
        op = OperatingConditions(cof=cof, condition=condition, wheel_load_n=load, speed_m_s=speed)
        s = 1e-9
        coa, slope = creep_curve(s, op)
        assert slope[0] == pytest.approx(expected, rel=1e-3)
        assert coa[0] / s == pytest.approx(expected, rel=1e-3)


@pytest.mark.parametrize("condition", sorted(CONDITIONS))
@pytest.mark.parametrize("speed", SPEEDS)
@pytest.mark.parametrize("ratio", (0.05, 0.3, 0.7, 0.9, 1.5, 3.0, 10.0))
def test_analytic_slope_matches_finite_difference(condition: str, speed: float, ratio: float) -> None:
    """dCoA/ds returned by the native law vs a central difference of CoA, before and past the peak."""
    op = OperatingConditions(cof=0.3, condition=condition, speed_m_s=speed)
    s = ratio * creep_peak(op).creepage
    h = 1e-4 * s
    coa, slope = creep_curve(np.array([s - h, s, s + h]), op)
    fd = (coa[2] - coa[0]) / (2 * h)
    assert slope[1] == pytest.approx(fd, rel=1e-5)
    if 1.0 < ratio <= 3.0:
        assert slope[1] < 0.0  # falling branch just past the peak
    elif ratio < 1.0:
        assert slope[1] > 0.0


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"cof": 0.0}, "cof"),
        ({"cof": -0.1}, "cof"),
        ({"cof": float("nan")}, "cof"),
        ({"cof": 0.3, "speed_m_s": 0.0}, "speed_m_s"),
        ({"cof": 0.3, "speed_m_s": -5.0}, "speed_m_s"),
        ({"cof": 0.3, "wheel_load_n": -100e3}, "wheel_load_n"),
        ({"cof": 0.3, "wheel_load_n": 0.0}, "wheel_load_n"),
        ({"cof": 0.3, "condition": "icy"}, "condition"),
    ],
    ids=["cof0", "cof-neg", "cof-nan", "speed0", "speed-neg", "load-neg", "load0", "condition"],
)
def test_operating_conditions_reject_bad_values(kwargs: dict, field: str) -> None:
    with pytest.raises(ValueError, match=rf"\b{field}\b"):
        OperatingConditions(**kwargs)


@pytest.mark.parametrize("ratio", (1.0, 1.5, float("nan"), -0.1))
def test_polach_shape_rejects_friction_ratio_without_peak(ratio: float) -> None:
    with pytest.raises(ValueError, match=r"friction_ratio"):
        PolachShape(1.0, 0.4, ratio, 0.6)


def test_polach_shape_accepts_valid_custom_shape() -> None:
    shape = PolachShape(0.5, 0.2, 0.3, 0.4)
    op = OperatingConditions(cof=0.25, condition=shape)
    assert creep_peak(op).coa == pytest.approx(0.25, rel=1e-6)


@pytest.mark.parametrize(
    ("condition", "cof", "speed"),
    [("low_adhesion", 0.6, 80.0), ("dry", 1.0, 80.0), ("wet", 1.5, 40.0)],
)
def test_conditions_without_a_peak_are_refused(condition: str, cof: float, speed: float) -> None:
    """Far past the task's speeds and CoFs a preset's curve has no maximum below creepage 2: refused, never a CoF
    that is not the curve's maximum."""
    with pytest.raises(ValueError, match="no maximum below creepage 2"):
        creep_peak(OperatingConditions(cof=cof, condition=condition, speed_m_s=speed))


@pytest.mark.parametrize(
    ("condition", "cof", "speed"),
    [("low_adhesion", 0.1, 40.0), ("dry", 0.6, 40.0), ("wet", 0.25, 40.0), ("dry_kalker", 0.6, 40.0),
     ("low_adhesion", 0.02, 5.0)],
)
def test_accepted_conditions_have_a_true_peak(condition: str, cof: float, speed: float) -> None:
    """At the ends of each condition's CoF range and the task's speeds the CoF is the curve's maximum (the documented
    meaning), an interior one."""
    op = OperatingConditions(cof=cof, condition=condition, speed_m_s=speed)
    peak = creep_peak(op)
    s = np.geomspace(1e-6, 1e3, 20000)
    coa, _ = creep_curve(s, op)
    assert coa.max() <= cof * (1 + 1e-6)
    assert peak.coa == pytest.approx(cof, rel=1e-9)
    assert peak.creepage < 1.0  # an interior maximum, not the scan's edge at s = 2


def test_operating_conditions_hold_the_documented_cof_range() -> None:
    """Below 1e-3 (COF_RANGE) the curve's slopes underflow towards NaN; the check said (0, 1.5]."""
    from cof_gym.physics.creep import COF_RANGE, OperatingConditions

    assert OperatingConditions(cof=COF_RANGE[0]).cof == COF_RANGE[0]
    with pytest.raises(ValueError, match=r"cof must be a finite number in \[0.001, 1.5\]"):
        OperatingConditions(cof=1e-300)


def test_a_creepage_that_is_not_finite_and_a_draw_without_a_generator_are_refused() -> None:
    """Polach and Shen-Hedrick-Elkins answered a NaN creepage with NaN, a table with its end value."""
    import numpy as np

    from cof_gym.physics.creep import OperatingConditions, creep_curve
    from cof_gym.physics.creep_laws import draw_shape

    for creepage in (np.nan, np.inf, -np.inf):
        with pytest.raises(ValueError, match="creepage must be finite"):
            creep_curve([0.01, creepage], OperatingConditions(cof=0.3))
    for rng in (None, 0):
        with pytest.raises(ValueError, match="rng must be a numpy Generator"):
            draw_shape(rng, "polach", "dry")


def test_the_stiffest_shape_and_contact_accepted_give_finite_curves_and_stiffer_ones_are_refused() -> None:
    """kA = 1e200 or G = 1e300 overflowed (k eps)^2 into NaN slopes; at the accepted bounds, even at the lowest CoF,
    every CoA and slope is finite."""
    import numpy as np

    from cof_gym.physics.contact_geometry import MAX_MODULUS_PA, ContactGeometry
    from cof_gym.physics.creep import COF_RANGE, OperatingConditions, creep_curve
    from cof_gym.physics.creep_laws import MAX_REDUCTION_FACTOR, PolachShape

    stiffest = OperatingConditions(
        cof=COF_RANGE[0], condition=PolachShape(MAX_REDUCTION_FACTOR, MAX_REDUCTION_FACTOR, 0.4, 0.6),
        geometry=ContactGeometry(youngs_modulus_pa=MAX_MODULUS_PA, shear_modulus_pa=MAX_MODULUS_PA))
    coa, slope = creep_curve(np.geomspace(1e-9, 2.0, 200), stiffest)
    assert np.isfinite(coa).all() and np.isfinite(slope).all()
    with pytest.raises(ValueError, match=r"k_adhesion must be a finite number in \(0, 100\]"):
        PolachShape(1e200, 1.0, 0.4, 0.6)
    with pytest.raises(ValueError, match=r"shear_modulus_pa must be a finite number in \(0, 1e\+13\] Pa"):
        ContactGeometry(shear_modulus_pa=1e300)
