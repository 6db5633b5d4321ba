"""Wheel-rail creep laws: operating conditions, calibration to the CoF and analysis entry points.

The law is a member of a family (:mod:`cof_gym.physics.creep_laws`: Polach, Shen-Hedrick-Elkins,
tabulated). The force itself is computed by one C function per family (dispatched by
``cofgym_creep_force`` in ``native/cofgym_native.c``) that the MuJoCo callback calls every physics
step; :func:`creep_curve` calls the very same function through ctypes, so plots and analysis can
never drift from the simulation.

**What ``cof`` means.** Polach's friction ``mu`` falls with the slip velocity
(``mu = mu0 [(1 - A) exp(-B w) + A]``), so the steady creep curve peaks below ``mu0``. In cof_gym,
*the coefficient of friction (CoF) is the maximum of the steady creep curve CoA(s) at the current
speed and load* (for a curve without a falling branch, its supremum, reached at a finite creepage
in every family here): what a slip test on that track would measure, and the value the
torque-modulation method reads at the peak. ``mu0`` is derived from it (:func:`mu0_for_cof`).

Presets (:data:`cof_gym.physics.creep_laws.CONDITIONS`, points of the Polach family; Polach 2005,
Wear 258:992-1000, as widely cited; "unverified" against the original table):

=============== ===== ===== ===== ========= ===========================================
condition        kA    kS    A     B (s/m)   note
=============== ===== ===== ===== ========= ===========================================
dry             1.00  0.40  0.40  0.60      Polach's dry set
wet             0.30  0.10  0.40  0.20      Polach's wet set
low_adhesion    0.10  0.05  0.45  0.20      leaf layer: cof_gym's choice (unverified), a
                                            flatter initial slope than wet
dry_kalker      1.00  1.00  0.40  0.60      dry, with Kalker's unreduced initial slope
                                            (kA + kS = 2: dF/ds at s = 0 is Kalker's linear
                                            theory, G a b c11 / Q per unit CoA, as a
                                            Kalker-table or FASTSIM contact gives; Polach
                                            2005 Sect. 2 reduces it by (kA + kS)/2 < 1 to
                                            fit measurements); A, B as dry. cof_gym's
                                            choice: the creep-curve shape under which the
                                            paper's ~94 % zero crossing is reproduced
=============== ===== ===== ===== ========= ===========================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from cof_gym.physics.contact_geometry import ContactGeometry, hertz_semi_axes, kalker_c11
from cof_gym.physics.creep_laws import (  # noqa: F401  (re-exported: the shapes and presets live there)
    CONDITIONS,
    FAMILIES,
    MAX_CREEPAGE,
    CreepPeak,
    CreepShape,
    PolachShape,
    ShenHedrickElkinsShape,
    TableShape,
    creep_law_from_spec,
    draw_shape,
    law_vector,
)
from cof_gym.physics.native import layout
from cof_gym.physics.native.build import native
from cof_gym.validation import check_number

COF_RANGE = (1e-3, 1.5)
"""Accepted CoF values (the environments draw from 0.02-0.6)."""


def shape_of(condition: str | CreepShape) -> CreepShape:
    """The creep-curve shape of a named condition (a Polach preset), or a shape of any family as is."""
    if isinstance(condition, CreepShape):
        return condition
    if not isinstance(condition, str) or condition not in CONDITIONS:
        raise ValueError(f"condition must be one of {sorted(CONDITIONS)} or a creep-law shape, got {condition!r}")
    return CONDITIONS[condition]


@dataclass(frozen=True)
class ContactPatch:
    """Contact-patch constants the native law scales with load: a*b at a reference wheel load
    (m^2), that load (N) and Kalker's c11."""

    ab_ref_m2: float
    q_ref_n: float
    c11: float

    @classmethod
    def at_load(cls, wheel_load_n: float, geometry: ContactGeometry = ContactGeometry()) -> "ContactPatch":
        a, b = hertz_semi_axes(wheel_load_n, geometry)
        return cls(a * b, wheel_load_n, kalker_c11(a / b, geometry.poisson_ratio))

    def vector(self) -> np.ndarray:
        values = {"AB_REF": self.ab_ref_m2, "Q_REF": self.q_ref_n, "C11": self.c11}
        return np.array([values[f] for f in layout.CONTACT_LAW_FIELDS], dtype=np.float64)


@dataclass(frozen=True)
class CreepLaw:
    """A complete creep law: shape (any family), friction level mu0 and the shear modulus (Pa)."""

    shape: CreepShape
    mu0: float
    shear_modulus_pa: float = 80e9

    def vector(self) -> np.ndarray:
        """The native law block (``layout.LAW_FIELDS``)."""
        return law_vector(self.shape, self.mu0, self.shear_modulus_pa)


def _ptr(a: np.ndarray):
    import ctypes

    return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


def _curve(law: CreepLaw, patch: ContactPatch, wheel_load_n: float, speed_m_s: float,
           creepage: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s = np.ascontiguousarray(creepage, dtype=np.float64)
    coa, slope = np.empty_like(s), np.empty_like(s)
    lv, pv = law.vector(), patch.vector()
    native().cofgym_creep_curve(_ptr(lv), _ptr(pv), wheel_load_n, speed_m_s, _ptr(s), s.size,
                                _ptr(coa), _ptr(slope))
    return coa, slope


def _coa_at(law: CreepLaw, patch: ContactPatch, wheel_load_n: float, speed_m_s: float, s: float) -> float:
    return float(_curve(law, patch, wheel_load_n, speed_m_s, np.array([s]))[0][0])


def _first_reach(law: CreepLaw, patch: ContactPatch, wheel_load_n: float, speed_m_s: float, level: float,
                 lo: float, hi: float) -> float:
    """Smallest creepage in (lo, hi] where the curve reaches ``level`` (CoA(lo) < level <= CoA(hi)),
    by bisection to adjacent doubles."""
    while True:
        mid = 0.5 * (lo + hi)
        if not (lo < mid < hi):
            return hi
        if _coa_at(law, patch, wheel_load_n, speed_m_s, mid) >= level:
            hi = mid
        else:
            lo = mid


class NoPeakError(ValueError):
    """The steady creep curve has no maximum (and no plateau) below :data:`MAX_CREEPAGE`: its CoF is
    undefined at that speed and load."""


def _peak(law: CreepLaw, patch: ContactPatch, wheel_load_n: float, speed_m_s: float) -> CreepPeak:
    """Where the curve first reaches its maximum: closed form where the family has one, the start of
    a plateau (a curve that saturates, e.g. Shen-Hedrick-Elkins with constant friction) by
    bisection, else an interior maximum by a bounded search around the densest scan's best point."""
    exact = law.shape.exact_peak(law.mu0)
    if exact is not None:
        return exact
    grid = np.geomspace(1e-6, MAX_CREEPAGE, 600)
    coa, _ = _curve(law, patch, wheel_load_n, speed_m_s, grid)
    i = int(np.argmax(coa))
    if i >= grid.size - 2 or not coa[i] > 0.0:  # rising to the scan's edge, or no adhesion at all (zero, NaN)
        raise NoPeakError(
            f"the creep curve has no maximum below creepage {MAX_CREEPAGE} at speed_m_s={speed_m_s} for this "
            "condition and load, so its CoF (the curve's maximum) is undefined there: play it at another speed, "
            "load or CoF, or a curve whose friction falls more steeply with the slip velocity"
        )
    if coa[i + 1] == coa[i]:  # saturated: the maximum is held from its first point on
        below = float(grid[i - 1]) if i > 0 else 0.0  # CoA(0) = 0 < coa[i]: never wrap round to grid[-1]
        return CreepPeak(_first_reach(law, patch, wheel_load_n, speed_m_s, float(coa[i]), below, float(grid[i])),
                         float(coa[i]))
    lo, hi = np.log(grid[max(i - 1, 0)]), np.log(grid[min(i + 1, grid.size - 1)])
    res = minimize_scalar(
        lambda x: -_curve(law, patch, wheel_load_n, speed_m_s, np.array([np.exp(x)]))[0][0],
        bounds=(lo, hi), method="bounded", options={"xatol": 1e-10},
    )
    return CreepPeak(float(np.exp(res.x)), float(-res.fun))


@dataclass(frozen=True)
class OperatingConditions:
    """CoF, condition (a preset name or a creep-curve shape of any family), wheel load (N, per wheel)
    and speed (m/s), validated."""

    cof: float
    condition: str | CreepShape = "dry"
    wheel_load_n: float = 100e3
    speed_m_s: float = 10.0
    geometry: ContactGeometry = field(default_factory=ContactGeometry)

    def __post_init__(self) -> None:
        check_number("cof", self.cof, *COF_RANGE)
        check_number("wheel_load_n", self.wheel_load_n, 0.0, math.inf, low_open=True, unit=" N")
        check_number("speed_m_s", self.speed_m_s, 0.0, math.inf, low_open=True, unit=" m/s")
        shape_of(self.condition)

    @property
    def patch(self) -> ContactPatch:
        return _patch_cached(self.wheel_load_n, self.geometry)

    def law(self) -> CreepLaw:
        """The creep law whose steady-curve maximum (supremum) at this speed and load equals ``cof``."""
        return CreepLaw(shape_of(self.condition), mu0_for_cof(self), self.geometry.shear_modulus_pa)


@lru_cache(maxsize=256)
def _patch_cached(wheel_load_n: float, geometry: ContactGeometry) -> ContactPatch:
    return ContactPatch.at_load(wheel_load_n, geometry)


def mu0_for_cof(op: OperatingConditions) -> float:
    """The friction level mu0 such that the steady creep curve's maximum (the supremum, for a curve
    without a falling branch) at this speed and load equals ``op.cof``: exactly ``cof`` where the
    maximum is mu0 itself (a table, constant friction), else solved."""
    return _mu0_cached(op.cof, shape_of(op.condition), op.wheel_load_n, op.speed_m_s, op.geometry)


@lru_cache(maxsize=4096)
def _mu0_cached(cof: float, shape: CreepShape, load: float, speed: float, geometry: ContactGeometry) -> float:
    if shape.max_is_mu0():
        return cof
    patch = _patch_cached(load, geometry)

    def excess(mu0: float) -> float:
        return _peak(CreepLaw(shape, mu0, geometry.shear_modulus_pa), patch, load, speed).coa - cof

    hi = shape.mu0_upper(cof)
    while excess(hi) < 0.0:
        hi *= 2.0
    lo = cof  # mu0 >= cof for every curve that peaks at or below mu0 (the bracket is then exactly [cof, hi])
    while excess(lo) > 0.0:  # a curve that peaks above mu0 (e.g. Polach with k_slip > k_adhesion): mu0 < cof
        lo *= 0.5
    return float(brentq(excess, lo, hi, xtol=1e-12, rtol=1e-10))


def creep_curve(creepage: np.ndarray | float, op: OperatingConditions) -> tuple[np.ndarray, np.ndarray]:
    """Steady creep curve: adhesion CoA (tangential/normal force) and its slope dCoA/ds at the given
    longitudinal creepages s = (R Omega - v)/v. Same native code as the simulation. A creepage that is not finite is
    a ``ValueError`` (the families answered it differently: NaN for Polach and Shen-Hedrick-Elkins, the table's end
    for a table)."""
    s = np.atleast_1d(np.asarray(creepage, dtype=np.float64))
    if not np.isfinite(s).all():
        bad = int(np.flatnonzero(~np.isfinite(s))[0])
        raise ValueError(f"creepage must be finite, got {float(s[bad])} at index {bad}")
    return _curve(op.law(), op.patch, op.wheel_load_n, op.speed_m_s, s)


def creep_peak(op: OperatingConditions) -> CreepPeak:
    """Creepage where the creep curve first reaches its maximum, and the adhesion there (``op.cof``).
    For a curve that saturates (no falling branch) that creepage is where the supremum is reached,
    e.g. 3 mu / (k C_K) for Shen-Hedrick-Elkins with constant friction: the macro-slip reference."""
    return _peak(op.law(), op.patch, op.wheel_load_n, op.speed_m_s)


def has_maximum(op: OperatingConditions) -> bool:
    """Whether the curve of ``op`` has a maximum (or reaches its supremum) below creepage
    ``MAX_CREEPAGE`` once calibrated, so that its CoF is defined (an ``accept`` for
    :func:`draw_shape`)."""
    try:
        creep_peak(op)
    except ValueError:
        return False
    return True


def creepage_at_coa(coa: float, op: OperatingConditions) -> float:
    """Creepage on the rising branch where the steady curve delivers adhesion ``coa`` (< cof)."""
    peak = creep_peak(op)
    check_number("coa", coa, 0.0, peak.coa, high_open=True, unit=" (below the peak)")
    if coa == 0.0:
        return 0.0
    law, patch = op.law(), op.patch
    f = lambda s: _curve(law, patch, op.wheel_load_n, op.speed_m_s, np.array([s]))[0][0] - coa
    return float(brentq(f, 0.0, peak.creepage, xtol=1e-15, rtol=1e-12))

