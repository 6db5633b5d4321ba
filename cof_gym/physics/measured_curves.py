"""A creep curve measured as (creepage, CoA) points (a twin-disc test, a test train's traction run) as the env's
tabulated creep law (:class:`~cof_gym.physics.creep_laws.TableShape`) and its CoF.

A table must rise strictly from (0, 0) to its maximum, exactly 1 (the adhesion ratio CoA / CoF); measured points
scatter, repeat a creepage and dip on the way up. :func:`measured_table` makes them one:

1. points at the same creepage are averaged; a point at (0, 0) is dropped (it is put first anyway), a creepage below
   0, a CoA below 0 or a CoA above 0 at creepage 0 refused, as are fewer than two points left;
2. the rising branch, every point up to the largest CoA measured, is replaced by its least-squares non-decreasing fit
   (isotonic regression by pooling adjacent violators: Barlow, Bartholomew, Bremner and Brunk 1972, *Statistical
   inference under order restrictions*, Wiley; Best and Chakravarti 1990, Mathematical Programming 47:425-439), and
   each run of equal fitted values becomes one point at its mean creepage, so that the branch rises strictly; a
   first run fitted at CoA 0 (points that read no creep force above creepage 0) is dropped, the table's (0, 0)
   standing for it, and a curve left with fewer than two points is refused;
3. the CoF is the fit's maximum (the rising branch's last point, ratio exactly 1); the points past the peak keep their
   measured CoA over that CoF, at most 1. Where the points scatter about a flat top, the fit's maximum lies above the
   curve's by about the scatter (the largest of several noisy readings): smooth such data first, or give the CoF;
4. a curve with more points than the native table holds (:data:`~cof_gym.physics.native.layout.MAX_TABLE_POINTS`,
   (0, 0) included) keeps points evenly spread over its index, the peak always among them, on each branch in
   proportion to its points; a creepage past :data:`~cof_gym.physics.creep_laws.MAX_CREEPAGE` is refused.

The CoF is the measured curve's, at the speed and load it was measured at; the env scales the table to whatever CoF
an episode fixes (``cof``).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from cof_gym.physics.creep_laws import MAX_CREEPAGE, TableShape
from cof_gym.physics.native import layout


def isotonic_fit(values: Sequence[float]) -> np.ndarray:
    """The least-squares non-decreasing sequence nearest to ``values`` (equal weights): pool adjacent violators,
    every run that falls replaced by its mean."""
    sums: list[float] = []
    counts: list[int] = []
    for v in values:
        sums.append(float(v))
        counts.append(1)
        while len(sums) > 1 and sums[-2] / counts[-2] > sums[-1] / counts[-1]:
            s, c = sums.pop(), counts.pop()
            sums[-1] += s
            counts[-1] += c
    return np.concatenate([np.full(c, s / c) for s, c in zip(sums, counts)])


def _averaged(creepage: Sequence[float], coa: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """The points sorted by creepage, those at one creepage averaged, (0, 0) dropped (ValueError for a bad point)."""
    given = {"creepage": creepage, "CoA": coa}
    raw = {name: np.asarray(values) for name, values in given.items()}
    for name, values in raw.items():  # numbers only: True is no creepage, "0.1" no CoA
        mixed_bool = (isinstance(given[name], (list, tuple))
                      and any(isinstance(v, (bool, np.bool_)) for v in given[name]))
        if values.ndim != 1 or values.dtype.kind not in "iuf" or mixed_bool:
            raise ValueError(f"a measured {name} must be a flat sequence of numbers, got {values.dtype.name} values of "
                             f"shape {values.shape}")
    s, a = raw["creepage"].astype(float), raw["CoA"].astype(float)
    if s.shape != a.shape:
        raise ValueError(f"a measured creep curve needs one CoA per creepage, got {s.size} creepages and {a.size} CoAs")
    for name, values in (("creepage", s), ("CoA", a)):
        bad = np.flatnonzero(~np.isfinite(values) | (values < 0))
        if len(bad):
            raise ValueError(f"a measured {name} must be finite and >= 0, got {float(values[bad[0]])!r} at point "
                             f"{bad[0]}")
    if (bad := np.flatnonzero((s == 0) & (a > 0))).size:
        raise ValueError(f"a measured CoA at creepage 0 must be 0 (no creep, no creep force), got {float(a[bad[0]])!r} "
                         f"at point {bad[0]}")
    if s.max(initial=0.0) > MAX_CREEPAGE:
        raise ValueError(f"a measured creepage must be at most {MAX_CREEPAGE:g}, got {float(s.max())!r}")
    s, a = s[s > 0], a[s > 0]
    if len(s) < 2:
        raise ValueError(f"a measured creep curve needs two or more points at creepages above 0, got {len(s)}")
    unique, inverse = np.unique(s, return_inverse=True)
    return unique, np.bincount(inverse, weights=a) / np.bincount(inverse)


def _runs_merged(s: np.ndarray, fitted: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each run of equal fitted values as one point at its mean creepage."""
    starts = np.flatnonzero(np.r_[True, np.diff(fitted) > 0])
    counts = np.diff(np.r_[starts, len(s)])
    return np.add.reduceat(s, starts) / counts, fitted[starts]


def _spread(n: int, keep: int) -> np.ndarray:
    """``min(keep, n)`` indices of ``n`` evenly spread, the first (and with two or more, the last) among them."""
    return np.arange(n) if keep >= n else np.round(np.linspace(0, n - 1, keep)).astype(int)


def measured_table(creepage: Sequence[float], coa: Sequence[float]) -> tuple[TableShape, float]:
    """The table shape and the CoF of a measured creep curve (see the module docstring); ValueError naming the
    point at fault."""
    s, a = _averaged(creepage, coa)
    peak = int(np.argmax(a))
    rise_s, rise_ratio = _runs_merged(s[:peak + 1], isotonic_fit(a[:peak + 1]))
    cof = float(rise_ratio[-1])
    if cof <= 0.0:
        raise ValueError("a measured creep curve must have a CoA above 0")
    rise_ratio = rise_ratio / cof
    rise_ratio[-1] = 1.0
    if rise_ratio[0] == 0.0:  # the curve's points at CoA 0 (after the fit) above creepage 0: the table's (0, 0) says it
        rise_s, rise_ratio = rise_s[1:], rise_ratio[1:]
    fall_s, fall_ratio = s[peak + 1:], np.minimum(a[peak + 1:] / cof, 1.0)
    if len(rise_s) + len(fall_s) < 2:
        raise ValueError(f"a measured creep curve needs two or more points after its fit (a CoA above 0 up to the "
                         f"peak, runs of equal CoA merged), got {len(rise_s) + len(fall_s)}")
    room = layout.MAX_TABLE_POINTS - 1  # (0, 0) first
    if len(rise_s) + len(fall_s) > room:  # the rising branch keeps its first point and its peak
        rise_keep = min(len(rise_s), max(2, round(room * len(rise_s) / (len(rise_s) + len(fall_s)))))
        keep_rise, keep_fall = _spread(len(rise_s), rise_keep), _spread(len(fall_s), room - rise_keep)
        rise_s, rise_ratio, fall_s, fall_ratio = (rise_s[keep_rise], rise_ratio[keep_rise], fall_s[keep_fall],
                                                  fall_ratio[keep_fall])
    try:
        table = TableShape(tuple(np.r_[0.0, rise_s, fall_s]), tuple(np.r_[0.0, rise_ratio, fall_ratio]))
    except ValueError as e:  # e.g. points so close that a slope overflows
        raise ValueError(f"a measured creep curve's fitted points are not a table the env accepts: {e}") from None
    return table, cof
