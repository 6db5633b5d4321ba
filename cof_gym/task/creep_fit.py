"""Creep-curve identification from windows measured below the peak: the creep law's family fitted to
measured (CoA, creepage) points, its peak (the CoF) extrapolated with a confidence interval.

**The family.** Polach's law with falling friction (:mod:`cof_gym.physics.creep`), as a library of
normalised rising branches ``CoA / CoF = g(s / s_peak)`` computed once per process for the published
condition presets (dry, wet, low adhesion, dry with Kalker's slope) over the CoF envelope, 5-40 m/s
and both wheel loads. Each shape is fitted with two free scales, the peak CoA ``P`` (the CoF) and the
peak creepage ``s_peak``, so neither the CoF, the condition, the contact stiffness nor the
falling-friction decay of the episode has to be known; the shapes only fix how a Polach curve bends
on its way to the peak. (Polach, "Creep forces in simulations of traction vehicles running on
adhesion limit", Wear 258, 2005; the "indirect" estimation that the phase-lag method is contrasted with.)

**The fit.** The CoA is measured precisely (force sensors averaged over a window), the creepage less
so (encoder noise ~ 2.5e-3 / v at full sensor noise, plus a few percent of transient): so the fit is in
creepage, ``s_i = s_peak g^-1(CoA_i / P)``, weighted least squares with
``sigma_i = creepage_noise / v + relative_noise * s_i``. For each shape and each ``P`` on a grid,
``s_peak`` is linear (closed form); the profile ``chi2(P) = min over shapes and s_peak`` gives the
best ``P`` and a confidence interval ``{P : chi2(P) <= chi2_min + delta_chi2 * max(1, chi2_min / dof)}``
(the interval widens when the residuals are larger than the assumed noise), never narrower than
``model_floor`` either side (the library holds the family, not the episode's exact curve: near the
peak the statistical interval alone covers the truth in only ~70 % of fits on validation seeds). Far
below the peak the data are a straight line that any ``P`` above the largest measured CoA fits: the
interval is open (up to ``max_ratio`` x the largest CoA). Windows modulated by a large fraction of their torque
(``swing``: each window's CoA half swing over its cycle) are fitted by the cycle mean of each shape's creepage, since
their mean creepage lies above the curve's value at their mean CoA.

:class:`ClimbRecord` keeps the points of one climb (a window counts when it was driven with a DC
torque and its CoA did not fall) and its latest fit; the model-based agent and the env's
"identification" observation type both use it, so they see the same fit.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from cof_gym.physics.creep_laws import PolachShape, ShenHedrickElkinsShape

SHAPE_CONDITIONS = ("dry", "wet", "low_adhesion", "dry_kalker")
SHAPE_COFS = (0.02, 0.05, 0.1, 0.2, 0.35, 0.6)
SHAPE_SPEEDS_M_S = (5.0, 12.0, 25.0, 40.0)
SHAPE_WHEEL_LOADS_N = (55e3, 115e3)
SHAPE_GRID = np.linspace(0.0, 0.999, 200)  # CoA / CoF on the rising branch
# the speed index of each row of creep_shapes() (the fit uses the shapes of the two nearest speeds)
SHAPE_SPEED_INDEX = np.array([i for _, _, i, _ in itertools.product(SHAPE_CONDITIONS, SHAPE_COFS,
                                                                    range(len(SHAPE_SPEEDS_M_S)),
                                                                    SHAPE_WHEEL_LOADS_N)])


@lru_cache(maxsize=1)
def creep_shapes() -> np.ndarray:
    """Normalised rising branches of Polach's law: row j holds ``s / s_peak`` at ``CoA / CoF =
    SHAPE_GRID`` for one (condition, CoF, speed, wheel load) of the family (computed once, ~1 s)."""
    from cof_gym.physics.creep import OperatingConditions, creep_curve, creep_peak

    rows = []
    for cond, cof, speed, load in itertools.product(SHAPE_CONDITIONS, SHAPE_COFS, SHAPE_SPEEDS_M_S,
                                                    SHAPE_WHEEL_LOADS_N):
        op = OperatingConditions(cof=cof, condition=cond, wheel_load_n=load, speed_m_s=speed)
        peak = creep_peak(op)
        s = np.concatenate([[0.0], np.geomspace(peak.creepage * 1e-4, peak.creepage, 600)])
        coa, _ = creep_curve(s, op)
        y = np.maximum.accumulate(np.asarray(coa) / peak.coa)
        rows.append(np.interp(SHAPE_GRID, y, s / peak.creepage))
    return np.asarray(rows)


POLACH = PolachShape.family  # the families a fit may read, by their creep-law family names
SHEN_HEDRICK_ELKINS = ShenHedrickElkinsShape.family
SHAPE_FAMILIES = (POLACH, SHEN_HEDRICK_ELKINS)
# Shen-Hedrick-Elkins at constant friction (v2's draws of that family): F / (mu N) = x - x^2/3 + x^3/27 = 1 - (1 - u)^3
# with u = x / 3 = s / s_peak, whatever the stiffness, speed or load; so s / s_peak = 1 - (1 - CoA / CoF)^(1/3): one
# normalised rising branch, the same at every speed
SHE_RISE = 1.0 - (1.0 - SHAPE_GRID) ** (1.0 / 3.0)


@lru_cache(maxsize=None)
def family_shapes(families: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
    """The normalised rising branches of ``families`` (rows, as :func:`creep_shapes`) and each row's speed index:
    Polach's library, and the Shen-Hedrick-Elkins branch once for every speed of it (computed once per tuple; read,
    never written)."""
    unknown = set(families) - set(SHAPE_FAMILIES)
    if not families or unknown:
        raise ValueError(f"families must be a non-empty subset of {list(SHAPE_FAMILIES)}, got {list(families)}")
    rows, speeds = [], []
    if POLACH in families:
        rows.append(creep_shapes())
        speeds.append(SHAPE_SPEED_INDEX)
    if SHEN_HEDRICK_ELKINS in families:
        rows.append(np.tile(SHE_RISE, (len(SHAPE_SPEEDS_M_S), 1)))
        speeds.append(np.arange(len(SHAPE_SPEEDS_M_S)))
    return np.concatenate(rows), np.concatenate(speeds)


@dataclass(frozen=True)
class PeakFit:
    low: float
    estimate: float
    high: float
    chi2: float
    points: int

    @property
    def half_width(self) -> float:
        """Relative half-width of the interval (in log, ~ relative for narrow intervals)."""
        return 0.5 * float(np.log(self.high / self.low))


CYCLE_POINTS = 16  # phases of a modulation cycle averaged where a fit reads each window's CoA swing


def inverse_shapes(shapes: np.ndarray, u: np.ndarray) -> np.ndarray:
    """``g_j^-1(u)`` for every shape row ``j`` of ``shapes`` (on :data:`SHAPE_GRID`) at every ``u`` (CoA over the peak
    CoA, any shape; odd in ``u``, clipped at the grid's end), by linear interpolation: shape ``(J, *u.shape)``."""
    a = np.abs(u)
    pos = np.clip(a / SHAPE_GRID[-1] * (len(SHAPE_GRID) - 1), 0.0, len(SHAPE_GRID) - 1 - 1e-9)
    lo = pos.astype(int)
    frac = pos - lo
    return np.sign(u) * (shapes[:, lo] * (1 - frac) + shapes[:, lo + 1] * frac)


def fit_peak(coa: np.ndarray, creepage: np.ndarray, speed_m_s: float, creepage_noise: float = 2.5e-3,
             relative_noise: float = 0.01, delta_chi2: float = 4.0, max_ratio: float = 4.0,
             grid_points: int = 160, model_floor: float = 0.015, families: tuple[str, ...] = (POLACH,),
             swing: np.ndarray | None = None) -> PeakFit:
    """Fit every shape of ``families`` (:func:`family_shapes`; Polach's library of :func:`creep_shapes` alone by
    default) to measured (CoA, creepage) points with free peak CoA and peak creepage; the profile over the peak CoA
    gives the estimate and its interval (see the module docstring). With ``swing`` (each window's CoA half swing over
    its modulation cycle) a window's creepage is the cycle mean of the shape's over that swing (a large modulation
    reads the curve's bend, not its value at the mean CoA)."""
    c = np.asarray(coa, dtype=float)
    s = np.asarray(creepage, dtype=float)
    shapes, speed_index = family_shapes(tuple(families))
    near = np.argsort(np.abs(np.log(np.asarray(SHAPE_SPEEDS_M_S) / max(speed_m_s, 1.0))))[:2]
    shapes = shapes[np.isin(speed_index, near)]
    c_max = float(c.max())
    ratios = np.geomspace(1.0 / SHAPE_GRID[-1] * 1.0001, max_ratio, grid_points)
    peaks = c_max * ratios
    sigma = creepage_noise / max(speed_m_s, 1.0) + relative_noise * np.abs(s)
    w = 1.0 / sigma ** 2
    if swing is None:
        x = inverse_shapes(shapes, c[None, :] / peaks[:, None])  # x[j, p, i] = g_j^-1(c_i / P_p): (J, P, n)
    else:  # the mean over the cycle's phases of g_j^-1 at the CoA of each phase
        phase = np.sin(2.0 * np.pi * (np.arange(CYCLE_POINTS) + 0.5) / CYCLE_POINTS)
        cycle = c[:, None] + np.asarray(swing, dtype=float)[:, None] * phase[None, :]  # (n, K)
        x = inverse_shapes(shapes, cycle[None, :, :] / peaks[:, None, None]).mean(axis=-1)
    sxx = np.einsum("jpi,i->jp", x * x, w)
    sxs = np.einsum("jpi,i->jp", x, w * s)
    s_peak = np.where(sxx > 0, sxs / np.maximum(sxx, 1e-300), 0.0)
    chi2 = np.einsum("jpi,i->jp", (s[None, None, :] - s_peak[..., None] * x) ** 2, w)
    chi2 = np.where(s_peak > 0, chi2, np.inf)
    profile = chi2.min(axis=0)
    best = int(np.argmin(profile))
    chi2_min = float(profile[best])
    dof = max(len(c) - 2, 1)
    inside = profile <= chi2_min + delta_chi2 * max(1.0, chi2_min / dof)
    est = float(peaks[best])
    low = min(float(peaks[inside].min()), est * (1.0 - model_floor))
    high = max(float(peaks[inside].max()), est * (1.0 + model_floor))
    return PeakFit(low, est, high, chi2_min, len(c))


def elasticity_between(lower: tuple[float, float], upper: tuple[float, float]) -> float:
    """d ln(creepage) / d ln(CoA) between two (CoA, creepage) points of the climb; 1 (the linear part)
    when either is not positive or the CoA barely moved."""
    (c1, s1), (c2, s2) = lower, upper
    if min(c1, c2, s1, s2) <= 0 or c2 <= c1 * 1.002:
        return 1.0
    return float(max(np.log(s2 / s1) / np.log(c2 / c1), 1.0))


FALL_TOLERANCE = 0.995  # a window whose CoA is below 0.995 x the previous point's has passed the peak


def coa_fell(coa: float, previous: float) -> bool:
    """Whether the measured CoA fell from ``previous`` to ``coa`` (below ``FALL_TOLERANCE`` x it): the stop
    rule every climbing agent shares, since past the creep curve's peak the CoA falls although the torque
    rose."""
    return coa < previous * FALL_TOLERANCE
MIN_FIT_POINTS = 3
ELASTICITY_SPAN = 0.03  # the elasticity's baseline: back to a point >= 3 % lower in CoA


@dataclass
class ClimbRecord:
    """The (CoA, creepage) points of one climb, the measured speeds, and the latest peak fit.

    :meth:`add` records a driven window; one whose CoA fell below ``FALL_TOLERANCE`` x the previous
    point's although the DC torque did not fall is not recorded (past the peak: off the rising branch
    the family describes) and :attr:`falling` is set. The fit is computed on demand (:attr:`fit`)."""

    points: list[tuple[float, float]] = field(default_factory=list)
    speeds: list[float] = field(default_factory=list)
    falling: bool = False
    max_ratio: float = 4.0
    families: tuple[str, ...] = (POLACH,)  # the creep-law families the fit reads (:func:`family_shapes`)
    _last_dc: float = 0.0
    _fit: PeakFit | None = None
    _fitted_points: int = 0

    def add(self, coa: float, creepage: float, speed_m_s: float, dc_torque: float) -> bool:
        """Record one driven window (measured CoA, creepage, speed in m/s, and the applied DC torque in
        any fixed unit); returns ``falling``: the CoA fell although the torque did not (past the peak).
        A window whose torque was lowered is still on the rising branch and is recorded."""
        self.falling = bool(self.points) and coa_fell(coa, self.points[-1][0]) and dc_torque >= self._last_dc
        if not self.falling:
            self.points.append((coa, creepage))
            self.speeds.append(speed_m_s)
        self._last_dc = dc_torque
        return self.falling

    @property
    def fit(self) -> PeakFit | None:
        """The peak fit to the climb's positive points (None with fewer than ``MIN_FIT_POINTS``),
        computed when first asked for after a point was added."""
        if self._fitted_points != len(self.points):
            self._fitted_points = len(self.points)
            positive = self.positive_points
            if len(positive) >= MIN_FIT_POINTS:
                c, s = np.array(positive).T
                self._fit = fit_peak(c, s, float(np.median(self.speeds)), max_ratio=self.max_ratio,
                                     families=self.families)
        return self._fit

    @property
    def positive_points(self) -> list[tuple[float, float]]:
        return [(c, s) for c, s in self.points if c > 0 and s > 0]

    @property
    def best_coa(self) -> float:
        """The largest positive measured CoA of the climb (0 before any)."""
        return max((c for c, _ in self.positive_points), default=0.0)

    def elasticity(self, min_span: float = 0.0) -> float:
        """d ln s / d ln CoA from the last point back to the latest one at least ``min_span`` lower in
        CoA (a longer baseline than one small step near the peak, where creepage noise would dominate);
        1 with fewer than two points."""
        if len(self.points) < 2:
            return 1.0
        upper = self.points[-1]
        lower = self.points[-2]
        for point in reversed(self.points[:-1]):
            lower = point
            if point[0] <= upper[0] / (1.0 + min_span):
                break
        return elasticity_between(lower, upper)

    def closed(self) -> bool:
        """Whether the fit's interval has closed (bounded well below ``max_ratio`` x the best CoA)."""
        return self.fit is not None and self.fit.high < 0.9 * self.max_ratio * self.best_coa
