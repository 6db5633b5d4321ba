"""Behaviour of the wheel-rail contact geometry (Hertz ellipse, Kalker c11, Polach's C)."""

from __future__ import annotations

import dataclasses
import math

import pytest

from cof_gym.physics.contact_geometry import (
    KALKER_C11_A_OVER_B,
    KALKER_C11_B_OVER_A,
    KALKER_C11_POISSON,
    ContactGeometry,
    creep_stiffness_constant,
    hertz_semi_axes,
    kalker_c11,
)


@pytest.mark.parametrize(
    ("load_n", "a_mm", "b_mm"),
    [(50e3, 5.7, 4.3), (100e3, 7.2, 5.4)],  # Hertz (Johnson 1985, Contact Mechanics, ch. 4): R 0.46 m on a 0.30 m crown
)
def test_hertz_semi_axes_match_design_values(load_n: float, a_mm: float, b_mm: float) -> None:
    a, b = hertz_semi_axes(load_n)
    assert a * 1e3 == pytest.approx(a_mm, rel=0.03)
    assert b * 1e3 == pytest.approx(b_mm, rel=0.03)


def test_ellipse_is_longer_along_rolling_direction() -> None:
    a, b = hertz_semi_axes(100e3)
    assert a > b
    assert a / b == pytest.approx(1.33, abs=0.02)


def test_semi_axes_scale_with_cube_root_of_load() -> None:
    a1, b1 = hertz_semi_axes(50e3)
    a8, b8 = hertz_semi_axes(400e3)
    assert a8 / a1 == pytest.approx(2.0, rel=1e-9)
    assert b8 / b1 == pytest.approx(2.0, rel=1e-9)


def test_equal_curvatures_give_circular_hertz_contact() -> None:
    geom = ContactGeometry(wheel_radius_m=0.46, rail_crown_radius_m=0.46)
    a, b = hertz_semi_axes(100e3, geom)
    # sphere-equivalent radius R = 0.46 m: a^3 = 3 Q R / (4 E*)
    expected = (3 * 100e3 * 0.46 / (4 * geom.reduced_modulus_pa)) ** (1 / 3)
    assert a == pytest.approx(expected, rel=1e-9)
    assert b == pytest.approx(expected, rel=1e-9)
    # nearly equal curvatures approach the circular result continuously
    a2, b2 = hertz_semi_axes(100e3, dataclasses.replace(geom, rail_crown_radius_m=0.4599))
    assert a2 == pytest.approx(expected, rel=1e-3)
    assert b2 == pytest.approx(expected, rel=1e-3)


def test_swapping_radii_swaps_axes() -> None:
    a, b = hertz_semi_axes(100e3, ContactGeometry(wheel_radius_m=0.46, rail_crown_radius_m=0.30))
    a2, b2 = hertz_semi_axes(100e3, ContactGeometry(wheel_radius_m=0.30, rail_crown_radius_m=0.46))
    assert (a2, b2) == pytest.approx((b, a), rel=1e-9)


@pytest.mark.parametrize("load", [0.0, -1.0, math.nan, math.inf])
def test_bad_load_is_rejected(load: float) -> None:
    with pytest.raises(ValueError, match=r"normal_load_n.*> 0"):
        hertz_semi_axes(load)
    with pytest.raises(ValueError, match=r"normal_load_n.*> 0"):
        creep_stiffness_constant(load)


@pytest.mark.parametrize(
    ("field", "value", "pattern"),
    [
        ("wheel_radius_m", 0.0, r"wheel_radius_m.*> 0"),
        ("rail_crown_radius_m", -0.3, r"rail_crown_radius_m.*> 0"),
        ("youngs_modulus_pa", 0.0, r"youngs_modulus_pa.*in \(0, 1e\+13\] Pa"),
        ("shear_modulus_pa", -1.0, r"shear_modulus_pa.*in \(0, 1e\+13\] Pa"),
        ("youngs_modulus_pa", 1e308, r"youngs_modulus_pa.*in \(0, 1e\+13\] Pa"),
        ("poisson_ratio", 0.0, r"poisson_ratio.*\(0, 0\.5\)"),
        ("poisson_ratio", 0.5, r"poisson_ratio.*\(0, 0\.5\)"),
    ],
)
def test_geometry_validation_names_field(field: str, value: float, pattern: str) -> None:
    with pytest.raises(ValueError, match=pattern):
        ContactGeometry(**{field: value})


def test_geometry_is_frozen() -> None:
    with pytest.raises(dataclasses.FrozenInstanceError):
        ContactGeometry().wheel_radius_m = 0.5  # type: ignore[misc]


def test_c11_at_design_ratio() -> None:
    # DESIGN value for the nu = 0.25 column: c11 ~ 4.45 at b/a ~ 0.75
    assert kalker_c11(1 / 0.75, 0.25) == pytest.approx(4.45, abs=0.01)


def test_c11_uses_the_hertz_poisson_ratio() -> None:
    """The default is the Hertz solution's nu (0.3), between the table's 0.25 and 0.5 columns."""
    g = 1 / 0.75
    assert kalker_c11(g) == kalker_c11(g, ContactGeometry().poisson_ratio)
    assert kalker_c11(g, 0.25) < kalker_c11(g) < kalker_c11(g, 0.5)
    assert kalker_c11(g) == pytest.approx(4.62, abs=0.01)


def test_c11_nu_interpolation_follows_kalker_thin_strip_asymptote() -> None:
    """1/c11 is interpolated in nu; at a/b -> 0 Kalker's c11 = pi^2 / (4 (1 - nu)) is linear in nu as
    1/c11, so the interpolation at a/b = 0.1 tracks the asymptote's nu-dependence."""
    ratio = kalker_c11(0.1, 0.3) / kalker_c11(0.1, 0.0)
    assert ratio == pytest.approx(1.0 / (1.0 - 0.3), rel=0.02)


def test_c11_reproduces_table_points_exactly() -> None:
    for nu_index, nu in enumerate(KALKER_C11_POISSON):
        for g, row in KALKER_C11_A_OVER_B:
            assert kalker_c11(g, nu) == pytest.approx(row[nu_index], abs=1e-12)
        for b_over_a, row in KALKER_C11_B_OVER_A:
            assert kalker_c11(1 / b_over_a, nu) == pytest.approx(row[nu_index], abs=1e-12)
    assert kalker_c11(0.1, 0.25) == pytest.approx(3.31, abs=1e-12)
    assert kalker_c11(10.0, 0.25) == pytest.approx(11.7, abs=1e-12)


def test_c11_is_linear_in_table_variable() -> None:
    # midway in b/a between 0.8 and 0.7 (a/b = 1/0.75), not midway in a/b
    assert kalker_c11(1 / 0.75, 0.25) == pytest.approx((4.36 + 4.54) / 2, abs=1e-12)
    assert kalker_c11(0.45, 0.25) == pytest.approx((3.53 + 3.62) / 2, abs=1e-12)


@pytest.mark.parametrize("nu", [0.0, 0.25, 0.3])  # Kalker's nu = 0.5 column dips slightly below a/b 0.4
def test_c11_increases_with_a_over_b(nu: float) -> None:
    grid = [0.1 + 0.05 * i for i in range(int((10 - 0.1) / 0.05) + 1)]
    values = [kalker_c11(min(g, 10.0), nu) for g in grid]
    assert all(v2 >= v1 for v1, v2 in zip(values, values[1:]))


@pytest.mark.parametrize("nu", [-0.01, 0.51, math.nan])
def test_c11_bad_poisson_ratio_is_rejected(nu: float) -> None:
    with pytest.raises(ValueError, match=r"poisson_ratio.*\[0, 0\.5\]"):
        kalker_c11(1.0, nu)


@pytest.mark.parametrize("g", [0.09, 10.01, 0.0, -1.0, math.nan])
def test_c11_out_of_range_is_rejected(g: float) -> None:
    with pytest.raises(ValueError, match=r"a_over_b.*\[0\.1, 10\]"):
        kalker_c11(g)


def test_creep_constant_at_paper_load() -> None:
    c = creep_stiffness_constant(100e3)
    assert 105 <= c <= 115
    a, b = hertz_semi_axes(100e3)
    assert c == pytest.approx(80e9 * math.pi * a * b * kalker_c11(a / b, 0.3) / (4 * 100e3), rel=1e-12)


def test_creep_constant_falls_with_load() -> None:
    # a b ~ Q^(2/3) at fixed a/b, so C ~ Q^(-1/3)
    ratio = creep_stiffness_constant(50e3) / creep_stiffness_constant(100e3)
    assert ratio == pytest.approx(2 ** (1 / 3), rel=1e-9)


def test_a_contact_ellipse_that_under_or_overflows_is_refused_not_returned_as_zero() -> None:
    """(0, 0) semi-axes divided by zero further on (the creep stiffness) where the load or modulus is at the edge of
    the floats."""
    from cof_gym.physics.contact_geometry import ContactGeometry, hertz_semi_axes

    with pytest.raises(ValueError, match="contact ellipse .* is not representable"):
        hertz_semi_axes(1e-320, ContactGeometry())  # (a modulus of 1e308 Pa is refused by the geometry itself)


def test_a_geometry_outside_kalkers_table_is_refused_naming_its_radii() -> None:
    """It was refused later as 'a_over_b must be in [0.1, 10]', a name the caller never gave."""
    from cof_gym.physics.contact_geometry import ContactGeometry, hertz_semi_axes

    geometry = ContactGeometry(rail_crown_radius_m=0.9)
    a, b = hertz_semi_axes(1e5, geometry)
    assert geometry.aspect_ratio == pytest.approx(a / b, rel=1e-12) and geometry.aspect_ratio < 1.0
    with pytest.raises(ValueError, match=r"wheel_radius_m=100 and rail_crown_radius_m=0.3 give a contact ellipse"):
        ContactGeometry(wheel_radius_m=100.0)
