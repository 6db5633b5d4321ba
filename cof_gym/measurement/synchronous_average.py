"""Synchronous (phase-binned) average of a signal over the modulation cycle, from per-bin sums.

The native step adds every sample of the window's measurement span to the bin of the modulation's
phase it was taken at (``PHASE_BINS`` equal bins of tone 1's phase). Averaging the samples of a bin
over the window's cycles keeps the shape of the cycle and divides the sensor noise by the square root
of the samples in the bin: the classic synchronous (time-domain) average of vibration analysis
(Braun, "The synchronous (time domain) average revisited", Mech. Syst. Signal Process. 25 (2011)
1087-1102), here with the phase known from the drive instead of a tachometer.

For the measured CoA it gives what a window's mean and a lock-in's fundamental cannot: the *crest* of
the adhesion over the cycle. When the torque's crest drives the contact past the creep curve's peak,
the crest of the adhesion is clipped at the peak, i.e. at the CoF, while the mean stays below it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class CycleExtremes:
    """The largest and smallest phase-bin means of a signal, and the standard error of one bin's mean
    (pooled within-bin spread over the bins' samples; 0 when no bin holds two samples)."""

    maximum: float
    minimum: float
    bin_se: float


def cycle_extremes(counts: np.ndarray, sums: np.ndarray, sums_of_squares: np.ndarray) -> CycleExtremes:
    """:class:`CycleExtremes` from the per-bin sample counts, sums and sums of squares (bins without a
    sample are skipped; ValueError if every bin is empty)."""
    counts = np.asarray(counts, float)
    filled = counts > 0
    if not filled.any():
        raise ValueError("synchronous average: no bin holds a sample")
    n = counts[filled]
    means = np.asarray(sums, float)[filled] / n
    within = np.maximum(np.asarray(sums_of_squares, float)[filled] - n * means * means, 0.0)
    dof = float(n.sum() - n.size)
    se = math.sqrt(float(within.sum()) / dof / float(n.mean())) if dof > 0 else 0.0
    return CycleExtremes(float(means.max()), float(means.min()), se)


def bin_sums(phase_rad: np.ndarray, y: np.ndarray, bins: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The per-bin counts, sums and sums of squares the native step accumulates, from sample arrays
    (bin ``k`` is centred on the phase ``-pi + 2 pi k / bins``, so that with an even number of bins one
    bin is centred on the torque's crest, ``pi / 2``, and one on its trough; tests, analysis)."""
    wrapped = np.arctan2(np.sin(phase_rad), np.cos(phase_rad))
    index = np.floor((wrapped + math.pi) * (bins / (2.0 * math.pi)) + 0.5).astype(int) % bins
    y = np.asarray(y, float)
    return (np.bincount(index, minlength=bins).astype(float), np.bincount(index, y, minlength=bins),
            np.bincount(index, y * y, minlength=bins))
