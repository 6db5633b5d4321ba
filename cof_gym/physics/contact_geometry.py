"""Wheel-rail contact patch geometry: Hertz semi-axes, Kalker's c11, Polach's creep constant.

Units are SI throughout (m, N, Pa). The longitudinal semi-axis ``a`` lies along the rolling
direction, the lateral semi-axis ``b`` across the rail, as in Kalker's and Polach's notation.

References
----------
K. L. Johnson, *Contact Mechanics*, CUP 1985, ch. 4 (Hertz elliptic contact).
J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990, table E3 (c11 for
nu = 0, 0.25, 0.5; interpolated in nu as documented in :func:`kalker_c11`).
O. Polach, Wear 258 (2005) 992-1000 (creep-force law).
"""

from __future__ import annotations

import math
from functools import lru_cache
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from cof_gym.validation import check_number

__all__ = [
    "ContactGeometry",
    "hertz_semi_axes",
    "kalker_c11",
    "creep_stiffness_constant",
    "KALKER_C11_A_OVER_B",
    "KALKER_C11_B_OVER_A",
    "KALKER_C11_POISSON",
]


MAX_MODULUS_PA = 1e13  # a modulus accepted up to this: about 8 times diamond's (1.2 TPa), far beyond any wheel or rail


@dataclass(frozen=True)
class ContactGeometry:
    """Wheel and rail geometry and (identical) material of both bodies.

    Attributes
    ----------
    wheel_radius_m:
        Wheel rolling radius in m (curvature in the rolling direction). The wheel's transverse
        profile is taken as flat (conical tread).
    rail_crown_radius_m:
        Rail head crown radius in m (curvature across the rail).
    youngs_modulus_pa:
        Young's modulus E of wheel and rail steel in Pa.
    poisson_ratio:
        Poisson's ratio nu, in (0, 0.5).
    shear_modulus_pa:
        Shear modulus G in Pa, used by Polach's creep constant (kept independent of E and nu
        because the literature quotes G ~ 80 GPa directly).
    """

    wheel_radius_m: float = 0.46
    rail_crown_radius_m: float = 0.30
    youngs_modulus_pa: float = 210e9
    poisson_ratio: float = 0.3
    shear_modulus_pa: float = 80e9

    def __post_init__(self) -> None:
        for name, unit in (("wheel_radius_m", " m"), ("rail_crown_radius_m", " m")):
            check_number(name, getattr(self, name), 0.0, math.inf, low_open=True, unit=unit)
        for name in ("youngs_modulus_pa", "shear_modulus_pa"):  # steel's 210 and 80 GPa; 1e300 overflowed the curve
            check_number(name, getattr(self, name), 0.0, MAX_MODULUS_PA, low_open=True, unit=" Pa")
        check_number("poisson_ratio", self.poisson_ratio, 0.0, 0.5, low_open=True, high_open=True)
        ratio = self.aspect_ratio
        if not 0.1 <= ratio <= 10.0:  # Kalker's c11 table: named here, not as an a_over_b the caller never gave
            raise ValueError(f"wheel_radius_m={self.wheel_radius_m:g} and rail_crown_radius_m="
                             f"{self.rail_crown_radius_m:g} give a contact ellipse with a/b = {ratio:.3g}, outside "
                             "[0.1, 10] where Kalker's creepage coefficients are tabulated")

    @property
    def curvature_sums(self) -> tuple[float, float]:
        """Hertz's curvature sums (1/m): A = 1/(2 R_wheel) in the rolling direction, B = 1/(2 R_crown) laterally (a
        flat wheel tread profile)."""
        return 1.0 / (2.0 * self.wheel_radius_m), 1.0 / (2.0 * self.rail_crown_radius_m)

    @property
    def eccentricity_squared(self) -> float:
        """e^2 of the contact ellipse, 1 - (minor / major)^2: a property of the radii alone (Hertz)."""
        small, large = sorted(self.curvature_sums)
        return _eccentricity_squared(large / small)

    @property
    def aspect_ratio(self) -> float:
        """The contact ellipse's a/b (rolling over lateral semi-axis); the major axis lies along the smaller sum."""
        elongation = 1.0 / math.sqrt(1.0 - self.eccentricity_squared)
        curv_roll, curv_lat = self.curvature_sums
        return elongation if curv_roll <= curv_lat else 1.0 / elongation

    @property
    def reduced_modulus_pa(self) -> float:
        """Contact modulus E* = E / (2 (1 - nu^2)) in Pa for two identical bodies."""
        return self.youngs_modulus_pa / (2.0 * (1.0 - self.poisson_ratio**2))


def _check_load(normal_load_n: float) -> float:
    return check_number("normal_load_n", normal_load_n, 0.0, math.inf, low_open=True, unit=" N")


@lru_cache(maxsize=256)  # a pure function of the radii: every geometry of the same radii solves it once
def _eccentricity_squared(curvature_ratio: float) -> float:
    """Solve Hertz's relation between the contact ellipse and the curvatures (Johnson, Contact Mechanics, 1985,
    ch. 4, elliptical contact) for m = e^2 given the ratio (large/small) of curvature sums.

    With the gap z = A' x^2 + B' y^2, A' <= B', the contact ellipse has its major semi-axis along
    x and  B'/A' = [(a/b)^2 E(e) - K(e)] / [K(e) - E(e)],  (a/b)^2 = 1 / (1 - e^2).
    """
    if curvature_ratio <= 1.0 + 1e-12:
        return 0.0  # circular contact

    def residual(m: float) -> float:
        k, e = ellipk(m), ellipe(m)
        return (e / (1.0 - m) - k) / (k - e) - curvature_ratio

    # residual -> 0 as m -> 0 (ratio -> 1) and -> +inf as m -> 1; bracket in (0, 1).
    return float(brentq(residual, 1e-12, 1.0 - 1e-15, xtol=1e-15, rtol=1e-14, maxiter=500))


_DEFAULT_GEOMETRY = ContactGeometry()  # (made once the ellipse's relation above is defined)


def hertz_semi_axes(
    normal_load_n: float, geometry: ContactGeometry = _DEFAULT_GEOMETRY
) -> tuple[float, float]:
    """Hertz contact ellipse semi-axes ``(a, b)`` in m; ``a`` along the rolling direction.

    Exact elliptic Hertz solution (Johnson ch. 4) for identical materials: curvature sums
    A = 1/(2 R_wheel) in the rolling direction and B = 1/(2 R_crown) laterally (flat wheel
    tread profile), E* = E / (2 (1 - nu^2)). The major semi-axis lies along the smaller curvature
    sum, so with R_wheel > R_crown the ellipse is elongated in the rolling direction (a > b).

    Parameters
    ----------
    normal_load_n:
        Wheel normal load Q in N, > 0.
    geometry:
        Radii and material constants.
    """
    q = _check_load(normal_load_n)
    curv_roll, curv_lat = geometry.curvature_sums
    curv_small = min(curv_roll, curv_lat)
    m = geometry.eccentricity_squared
    e_star = geometry.reduced_modulus_pa

    if m == 0.0:
        # circular: a^3 = 3 P R / (4 E*), with 1/R = A + B = 2 A
        radius = (3.0 * q / (4.0 * e_star * 2.0 * curv_small)) ** (1.0 / 3.0)
        major = minor = radius
    else:
        # A' = (p0/E*) (b / (e^2 a^2)) [K - E] and P = (2/3) pi a b p0
        #  =>  a^3 = 3 P (K - E) / (2 pi A' E* e^2)
        k, e = ellipk(m), ellipe(m)
        major = (3.0 * q * (k - e) / (2.0 * math.pi * curv_small * e_star * m)) ** (1.0 / 3.0)
        minor = major * math.sqrt(1.0 - m)

    if not (0.0 < minor <= major < math.inf):  # a load or modulus at the edge of the floats under- or overflows
        raise ValueError(f"the Hertz contact ellipse of normal_load_n={q:g} N on this geometry (E*={e_star:g} Pa) is "
                         f"not representable (semi-axes {major:g}, {minor:g} m): give a physical load and modulus")
    if curv_roll <= curv_lat:
        return float(major), float(minor)  # major axis along the rolling direction
    return float(minor), float(major)


# Kalker (1990) table E3, c11 for Poisson's ratio nu = 0, 0.25 and 0.5 (the table's three columns).
KALKER_C11_POISSON: tuple[float, float, float] = (0.0, 0.25, 0.5)
#: (a/b, (c11 at nu = 0, 0.25, 0.5)) for a/b <= 1
KALKER_C11_A_OVER_B: tuple[tuple[float, tuple[float, float, float]], ...] = (
    (0.1, (2.51, 3.31, 4.85)),
    (0.2, (2.59, 3.37, 4.81)),
    (0.3, (2.68, 3.44, 4.80)),
    (0.4, (2.78, 3.53, 4.82)),
    (0.5, (2.88, 3.62, 4.83)),
    (0.6, (2.98, 3.72, 4.91)),
    (0.7, (3.09, 3.81, 4.97)),
    (0.8, (3.19, 3.91, 5.05)),
    (0.9, (3.29, 4.01, 5.12)),
    (1.0, (3.40, 4.12, 5.20)),
)
#: (b/a, (c11 at nu = 0, 0.25, 0.5)) for a/b >= 1 (b/a = 1 is the circular contact)
KALKER_C11_B_OVER_A: tuple[tuple[float, tuple[float, float, float]], ...] = (
    (1.0, (3.40, 4.12, 5.20)),
    (0.9, (3.51, 4.22, 5.30)),
    (0.8, (3.65, 4.36, 5.42)),
    (0.7, (3.82, 4.54, 5.58)),
    (0.6, (4.06, 4.78, 5.80)),
    (0.5, (4.37, 5.10, 6.11)),
    (0.4, (4.84, 5.57, 6.57)),
    (0.3, (5.57, 6.34, 7.34)),
    (0.2, (6.96, 7.78, 8.82)),
    (0.1, (10.7, 11.7, 12.9)),
)


def _table_rows(a_over_b: float) -> np.ndarray:
    """c11 at the table's three Poisson ratios, linear in the table's own variable (a/b or b/a)."""
    table, x = (KALKER_C11_A_OVER_B, a_over_b) if a_over_b <= 1.0 else (KALKER_C11_B_OVER_A[::-1], 1.0 / a_over_b)
    xs = np.array([row[0] for row in table])
    cs = np.array([row[1] for row in table])  # (rows, 3)
    return np.array([np.interp(x, xs, cs[:, k]) for k in range(cs.shape[1])])


def kalker_c11(a_over_b: float, poisson_ratio: float = _DEFAULT_GEOMETRY.poisson_ratio) -> float:
    """Kalker's longitudinal creepage coefficient c11 (dimensionless) for a semi-axis ratio a/b and
    Poisson's ratio nu.

    Kalker (1990) table E3 gives c11 for nu = 0, 0.25 and 0.5. The table is interpolated linearly in
    its own variable (a/b for a/b <= 1, b/a for a/b > 1) in each nu column, then in nu by the
    parabola through the three columns *of 1/c11*: Kalker's thin-strip asymptote
    c11 = pi^2 / (4 (1 - nu)) (a/b -> 0) is exactly linear in nu as 1/c11, and the same scheme is
    used by Vollebregt and Kalker's CONTACT program (``linrol``). Exact at the table's points.
    For the default nu = 0.3 and the paper's 100 kN contact (a/b = 1.33) this gives c11 = 4.62,
    4 % above the nu = 0.25 column (4.45).

    Raises ``ValueError`` for a/b outside [0.1, 10] or nu outside [0, 0.5].
    """
    g = check_number("a_over_b", a_over_b, 0.1, 10.0)
    nu = check_number("poisson_ratio", poisson_ratio, 0.0, 0.5)
    inverse = 1.0 / _table_rows(g)
    n0, n1, n2 = KALKER_C11_POISSON
    weights = ((nu - n1) * (nu - n2) / ((n0 - n1) * (n0 - n2)),
               (nu - n0) * (nu - n2) / ((n1 - n0) * (n1 - n2)),
               (nu - n0) * (nu - n1) / ((n2 - n0) * (n2 - n1)))
    return float(1.0 / np.dot(weights, inverse))


def creep_stiffness_constant(
    normal_load_n: float, geometry: ContactGeometry = _DEFAULT_GEOMETRY
) -> float:
    """Polach's creep constant C = G pi a b c11 / (4 Q) (dimensionless, per unit creepage).

    Polach's gradient of tangential stress is eps = C |s| / mu, with s the longitudinal
    creepage and mu the friction coefficient. a, b from :func:`hertz_semi_axes`, c11 from
    :func:`kalker_c11` at ``geometry.poisson_ratio``, G = ``geometry.shear_modulus_pa``.
    """
    q = _check_load(normal_load_n)
    a, b = hertz_semi_axes(q, geometry)
    c11 = kalker_c11(a / b, geometry.poisson_ratio)
    return geometry.shear_modulus_pa * math.pi * a * b * c11 / (4.0 * q)
