"""ISO 2631-1 frequency weighting Wd as discrete filters, and the EN 12299 mean comfort index.

Filters are built from the analog prototypes of ISO 2631-1:1997 (Annex A, the frequency weightings):

    Hh = s^2 / (s^2 + sqrt2 w1 s + w1^2)                 band limit, high-pass, f1 = 0.4 Hz
    Hl = w2^2 / (s^2 + sqrt2 w2 s + w2^2)                band limit, low-pass, f2 = 100 Hz
    Ht = (1 + s/w3) / (1 + s/(Q4 w4) + s^2/w4^2)         a-v transition, f3 = f4 = 2 Hz, Q4 = 0.63

Wd (horizontal) = Hh Hl Ht (no upward step Hs). They are discretised with the plain bilinear
transform, without frequency pre-warping: the 100 Hz corner shifts by ~3 % at 1 kHz sampling
and the response below ~20 Hz (where the 5 Hz modulation lives) is within ~0.1 % of the analog one.
Second-order sections use the scipy.signal layout ``[b0, b1, b2, a0, a1, a2]`` with a0 == 1.

Accelerations are in m/s^2, frequencies in Hz.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from scipy import signal

from cof_gym.validation import check_number

__all__ = [
    "WD_F1_HZ",
    "WD_F2_HZ",
    "WD_F3_HZ",
    "WD_F4_HZ",
    "WD_Q4",
    "wd_weighting_sos",
    "band_limiting_sos",
    "wd_gain",
    "weighted_rms",
    "en12299_comfort_index",
    "comfort_label",
]

WD_F1_HZ = 0.4  #: band-limiting high-pass corner, Hz
WD_F2_HZ = 100.0  #: band-limiting low-pass corner, Hz
WD_F3_HZ = 2.0  #: a-v transition zero, Hz
WD_F4_HZ = 2.0  #: a-v transition pole pair, Hz
WD_Q4 = 0.63  #: a-v transition pole quality factor

_SQRT2 = math.sqrt(2.0)


def _band_limiting_tf() -> tuple[np.ndarray, np.ndarray]:
    """Analog Hh*Hl as (numerator, denominator) polynomials in s (highest power first)."""
    w1 = 2.0 * math.pi * WD_F1_HZ
    w2 = 2.0 * math.pi * WD_F2_HZ
    num = np.polymul([1.0, 0.0, 0.0], [w2**2])
    den = np.polymul([1.0, _SQRT2 * w1, w1**2], [1.0, _SQRT2 * w2, w2**2])
    return num, den


def _wd_tf() -> tuple[np.ndarray, np.ndarray]:
    """Analog Wd = Hh*Hl*Ht as (numerator, denominator) polynomials in s."""
    w3 = 2.0 * math.pi * WD_F3_HZ
    w4 = 2.0 * math.pi * WD_F4_HZ
    num_b, den_b = _band_limiting_tf()
    num_t = [1.0 / w3, 1.0]
    den_t = [1.0 / w4**2, 1.0 / (WD_Q4 * w4), 1.0]
    return np.polymul(num_b, num_t), np.polymul(den_b, den_t)


def _check_rate(sample_rate_hz: float) -> float:
    return check_number("sample_rate_hz", sample_rate_hz, 2.0 * WD_F2_HZ, math.inf, low_open=True,
                        unit=f" Hz (the {WD_F2_HZ:g} Hz band limit must lie below Nyquist)")


def _to_sos(num: np.ndarray, den: np.ndarray, fs: float) -> np.ndarray:
    z, p, k = signal.tf2zpk(num, den)
    zd, pd, kd = signal.bilinear_zpk(z, p, k, fs)
    return np.ascontiguousarray(signal.zpk2sos(zd, pd, kd), dtype=np.float64)


def wd_weighting_sos(sample_rate_hz: float) -> np.ndarray:
    """ISO 2631-1 Wd weighting (Hh Hl Ht) as discrete second-order sections, shape (n, 6).

    Plain bilinear transform (no pre-warping) at ``sample_rate_hz`` (Hz, must be > 200 Hz).
    Input and output in m/s^2.
    """
    fs = _check_rate(sample_rate_hz)
    return _to_sos(*_wd_tf(), fs)


def band_limiting_sos(sample_rate_hz: float) -> np.ndarray:
    """ISO 2631-1 band limiting Hh Hl (0.4-100 Hz) only, as second-order sections, shape (n, 6).

    Used e.g. before differentiating acceleration into jerk. ``sample_rate_hz`` in Hz, > 200.
    """
    fs = _check_rate(sample_rate_hz)
    return _to_sos(*_band_limiting_tf(), fs)


def wd_gain(frequency_hz: float) -> float:
    """Analog Wd magnitude |Wd(j 2 pi f)| (dimensionless) at ``frequency_hz`` (Hz, >= 0)."""
    f = check_number("frequency_hz", frequency_hz, 0.0, math.inf, unit=" Hz")
    num, den = _wd_tf()
    s = 2j * math.pi * f
    return float(abs(np.polyval(num, s) / np.polyval(den, s)))


def weighted_rms(
    acceleration: np.ndarray,
    sample_rate_hz: float,
    weighting: Literal["wd", "band"] = "wd",
) -> float:
    """RMS (m/s^2) of ``acceleration`` (1-D, m/s^2) after the ISO 2631-1 weighting.

    Reference array implementation (scipy.signal.sosfilt from zero initial state, RMS over the
    whole record, start-up transient included as in ISO 2631-1). ``weighting`` is ``"wd"``
    (Hh Hl Ht) or ``"band"`` (Hh Hl only).
    """
    x = np.asarray(acceleration, dtype=np.float64)
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"acceleration must be a non-empty 1-D array, got shape {x.shape}")
    if weighting == "wd":
        sos = wd_weighting_sos(sample_rate_hz)
    elif weighting == "band":
        sos = band_limiting_sos(sample_rate_hz)
    else:
        raise ValueError(f"weighting must be 'wd' or 'band', got {weighting!r}")
    y = signal.sosfilt(sos, x)
    return float(np.sqrt(np.mean(y * y)))


def en12299_comfort_index(ax_p95: float, ay_p95: float, az_p95: float) -> float:
    """EN 12299 simplified mean comfort N_MV = 6 sqrt(ax^2 + ay^2 + az^2) (dimensionless).

    Inputs are the 95th percentiles (m/s^2) of the 5 s weighted RMS accelerations: Wd on the
    longitudinal x and lateral y axes, Wb on the vertical z axis.
    """
    values = (ax_p95, ay_p95, az_p95)
    for name, v in zip(("ax_p95", "ay_p95", "az_p95"), values):
        check_number(name, v, 0.0, math.inf, unit=" m/s^2")
    return 6.0 * math.sqrt(sum(float(v) ** 2 for v in values))


def comfort_label(n_mv: float) -> str:
    """Verbal EN 12299 comfort class of a mean comfort index N_MV.

    Scale (EN 12299's comfort scale as commonly quoted; unverified against the standard's text): N_MV < 1
    "very comfortable", 1 <= N_MV < 2 "comfortable", 2 <= N_MV < 4 "medium", 4 <= N_MV < 5 "uncomfortable",
    N_MV >= 5 "very uncomfortable".
    """
    n = check_number("n_mv", n_mv, 0.0, math.inf)
    if n < 1.0:
        return "very comfortable"
    if n < 2.0:
        return "comfortable"
    if n < 4.0:
        return "medium"
    if n < 5.0:
        return "uncomfortable"
    return "very uncomfortable"
