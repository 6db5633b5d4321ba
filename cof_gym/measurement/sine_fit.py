"""Known-frequency least-squares sine fit (IEEE Std 1057 three-parameter fit, plus a linear drift
term) from running sums, as accumulated inside the native physics step (a lock-in).

Model: ``y(t) = c0 cos(theta) + c1 sin(theta) + c2 + c3 tau = amp sin(theta + phase) + DC + drift``
with ``theta`` the modulation phase and ``tau`` the time since the window's start. The DC level is
removed by ``c2``; ``c3`` absorbs a slow drift of the operating point (e.g. the cruise control still
settling), which otherwise leaks into the phase. For a stationary signal it reduces to IEEE 1057's
three-parameter fit. The standard error of the phase follows from the residual variance and the
delta method (Cramer-Rao: var >= 2 sigma^2 / (n amp^2)).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

N_BASIS = 4


def unpack_symmetric(btb: np.ndarray, size: int = N_BASIS) -> np.ndarray:
    """``size`` x ``size`` symmetric matrix from its packed upper triangle (row-major, as the native
    sums; 10 entries for the single-tone basis)."""
    out = np.empty((size, size))
    k = 0
    for i in range(size):
        for j in range(i, size):
            out[i, j] = out[j, i] = btb[k]
            k += 1
    return out


def _solve_scaled(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(coefficients, their unit-variance covariance, the unit-diagonal matrix) of ``a x = b``, the
    basis scaled to unit diagonal first (the drift column is in seconds and ill-scaled otherwise)."""
    scale = 1.0 / np.sqrt(np.maximum(np.diag(a), 1e-300))
    a_s = a * np.outer(scale, scale)
    cov_s = np.linalg.pinv(a_s)
    return scale * (cov_s @ (b * scale)), cov_s * np.outer(scale, scale), a_s


def coefficient_covariance(a: np.ndarray) -> np.ndarray:
    """The unit-variance covariance of the coefficients of a basis whose normal matrix B'B is ``a``, as the fits
    solve it (the basis scaled to unit diagonal first)."""
    return _solve_scaled(a, np.zeros(len(a)))[1]


@dataclass(frozen=True)
class SineFit:
    amplitude: float
    phase_rad: float  # y ~ amplitude sin(theta + phase)
    phase_se_rad: float
    offset: float
    drift_per_s: float
    residual_rms: float
    # the fit's coefficients as solved, for what reads its residual (lag1_correlation): the single-tone fit's
    # (c0, c1, c2, c3), or the joint fit's whole vector (every tone of it holds the same)
    coefficients: tuple[float, ...] = field(default=(), repr=False, compare=False)


def fit_from_sums(btb: np.ndarray, bty: np.ndarray, yty: float, n: float) -> SineFit:
    """Solve the normal equations accumulated as B'B (10 entries), B'y (4) and y'y over n samples."""
    if n <= N_BASIS:
        raise ValueError(f"sine fit needs more than {N_BASIS} samples, got {n:g}")
    a = unpack_symmetric(np.asarray(btb, dtype=np.float64))
    b = np.asarray(bty, dtype=np.float64)
    coef, cov_unit, _ = _solve_scaled(a, b)
    rss = max(float(yty - coef @ b), 0.0)
    sigma2 = rss / (n - N_BASIS)
    c0, c1 = coef[0], coef[1]
    amp2 = c0 * c0 + c1 * c1
    amplitude = float(np.sqrt(amp2))
    if amp2 > 0.0:
        grad = np.array([c1, -c0]) / amp2  # d atan2(c0, c1) / d(c0, c1)
        var = sigma2 * float(grad @ cov_unit[:2, :2] @ grad)
        phase_se = float(np.sqrt(max(var, 0.0)))
    else:
        phase_se = float(np.pi)
    return SineFit(amplitude, float(np.arctan2(c0, c1)), phase_se, float(coef[2]), float(coef[3]),
                   float(np.sqrt(rss / n)), tuple(float(c) for c in coef))


def lag1_correlation(btb: np.ndarray, bty: np.ndarray, yty: float, n: float, yy1: float, by_prev: np.ndarray,
                     prev_by: np.ndarray, bb: np.ndarray, coefficients: tuple[float, ...] = ()) -> float:
    """The lag-1 autocorrelation of the fit's residual ``r_n = y_n - b_n' c`` over consecutive samples, from the fit's
    sums and the lag-1 cross sums ``sum y_n y_(n-1)``, ``sum b_n y_(n-1)``, ``sum b_(n-1) y_n`` and ``sum b_n
    b_(n-1)'`` (``size`` x ``size`` entries, row-major; ``size`` the basis's columns, ``len(bty)``: 4 for one tone):
    ``(sum r_n r_(n-1) / (n - 1)) / (sum r_n^2 / n)``, within [-0.999, 0.999]; 0 where the fit leaves no residual.
    ``coefficients``: the fit's as :func:`fit_from_sums` (or :func:`fit_tones_from_sums`) solved them from the same
    sums (:attr:`SineFit.coefficients`), not solved again; empty: solved here."""
    bty = np.asarray(bty, dtype=np.float64)
    size = len(bty)
    coef = (np.array(coefficients, dtype=np.float64) if coefficients else
            _solve_scaled(unpack_symmetric(np.asarray(btb, dtype=np.float64), size), bty)[0])
    rss = float(yty - coef @ bty)
    if not rss > 0.0 or n < 2:
        return 0.0
    cross = float(yy1 - coef @ by_prev - coef @ prev_by + coef @ np.reshape(bb, (size, size)) @ coef)
    return float(np.clip((cross / (n - 1)) / (rss / n), -0.999, 0.999))


def colored_noise_factor(rho: float, omega_step_rad: float) -> float:
    """How many times the white-noise standard error understates a coefficient's at the angular frequency ``w`` when
    the residual is first-order autoregressive with lag-1 correlation ``rho`` (``omega_step_rad`` = ``w dt``): the
    square root of the residual's spectral density at ``w`` over its white equivalent, ``sqrt((1 - rho^2) /
    (1 - 2 rho cos(w dt) + rho^2))`` (1 at ``rho`` = 0; below 1 for a negative ``rho``). The fit's coefficients at
    ``w`` are sums over the window weighted by ``cos`` and ``sin`` at ``w``, so their variance is the residual's
    density there (the AR(1) spectrum: Priestley, *Spectral Analysis and Time Series*, 1981)."""
    return float(np.sqrt((1.0 - rho * rho) / (1.0 - 2.0 * rho * np.cos(omega_step_rad) + rho * rho)))


# a window whose noise colour (noise_colour) is above this reads a smoothed speed signal: white sensor noise reads
# about 1, the native chain's first-order smoothing of 2 ms already about 3 (colored_noise_factor at 5 Hz of its
# lag-1 correlation (1 + exp(-dt / tau)) / 2). The least 0.1 step above the colour of every sharp-encoder training
# climb of the learned interrogator (at most 2.58, on nearly noiseless sensors, where the wheel's own response
# colours the residual; experiments/noise_colour_reading.py, docs/interrogator.md "A smoothed encoder read from the
# speed residual's colour")
SMOOTHED_NOISE_COLOUR = 2.6
NO_SE_DEG = 180.0  # a lag's standard error of no information (pi)


def noise_colour(se_white_deg: float, se_corrected_deg: float) -> float:
    """How many times the speed residual's correlation widens a lag's standard error: the SE for a first-order
    autoregressive residual (``se_corrected_deg``: :func:`colored_noise_factor` of the residual's lag-1 correlation
    times the white one) over the white-noise SE ``se_white_deg``. About 1 for white sensor noise, several times that
    for a smoothed speed signal (a smoothing correlates successive samples); 0 where either SE is not in (0, 180)
    deg (not read, or a fit of no information)."""
    if not (0.0 < se_white_deg < NO_SE_DEG and 0.0 < se_corrected_deg < NO_SE_DEG):
        return 0.0
    return se_corrected_deg / se_white_deg


def basis(theta: np.ndarray, tau: np.ndarray) -> np.ndarray:
    return np.stack([np.cos(theta), np.sin(theta), np.ones_like(theta), tau], axis=1)


def packed_sums(bm: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, int]:
    """B'B (packed upper triangle, row-major), B'y, y'y and n of a basis matrix ``bm`` (n, size)."""
    full = bm.T @ bm
    size = bm.shape[1]
    btb = np.array([full[i, j] for i in range(size) for j in range(i, size)])
    y = np.asarray(y, float)
    return btb, bm.T @ y, float(y @ y), y.size


def sums(theta: np.ndarray, tau: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, int]:
    """The sums the native step accumulates, from sample arrays (tests, offline analysis)."""
    return packed_sums(basis(np.asarray(theta, float), np.asarray(tau, float)), y)


def fit_samples(theta: np.ndarray, tau: np.ndarray, y: np.ndarray) -> SineFit:
    """Fit sample arrays with the same solver as the native sums."""
    return fit_from_sums(*sums(theta, tau, y))


def wrap_deg(angle_deg: float) -> float:
    """Wrap to (-180, 180]."""
    w = (angle_deg + 180.0) % 360.0 - 180.0
    return 180.0 if w == -180.0 else w


# a joint normal matrix whose scaled condition number exceeds this cannot separate its tones: their
# phases are reported with the standard error of no information (pi)
MAX_CONDITION = 1e10


def fit_tones_from_sums(btb: np.ndarray, bty: np.ndarray, yty: float, n: float, ntones: int) -> tuple[SineFit, ...]:
    """Joint least-squares fit of ``ntones`` known-frequency sines plus offset and drift, from the sums
    over the basis ``[cos th_1, sin th_1, ..., cos th_K, sin th_K, 1, tau]`` (B'B packed upper triangle,
    B'y, y'y over n samples), as :func:`fit_from_sums` does for one tone. One :class:`SineFit` per tone
    (offset, drift and residual shared). Each tone's phase standard error comes from the joint covariance,
    so tones that are close in frequency (less than ~2 / T apart over a window of T s) get large errors;
    an ill-conditioned system (:data:`MAX_CONDITION`, e.g. two tones at one frequency) gives pi."""
    size = 2 * ntones + 2
    if ntones < 1:
        raise ValueError(f"ntones must be >= 1, got {ntones}")
    if n <= size:
        raise ValueError(f"a {ntones}-tone fit needs more than {size} samples, got {n:g}")
    a = unpack_symmetric(np.asarray(btb, dtype=np.float64), size)
    b = np.asarray(bty, dtype=np.float64)[:size]
    coef, cov_unit, a_s = _solve_scaled(a, b)
    eig = np.linalg.eigvalsh(a_s)
    separable = eig[0] > eig[-1] / MAX_CONDITION
    rss = max(float(yty - coef @ b), 0.0)
    sigma2 = rss / (n - size)
    fits = []
    for k in range(ntones):
        c0, c1 = coef[2 * k], coef[2 * k + 1]
        amp2 = c0 * c0 + c1 * c1
        if amp2 > 0.0 and separable:
            grad = np.array([c1, -c0]) / amp2
            var = sigma2 * float(grad @ cov_unit[2 * k:2 * k + 2, 2 * k:2 * k + 2] @ grad)
            phase_se = min(float(np.sqrt(max(var, 0.0))), float(np.pi))
        else:
            phase_se = float(np.pi)
        fits.append(SineFit(float(np.sqrt(amp2)), float(np.arctan2(c0, c1)), phase_se, float(coef[-2]),
                            float(coef[-1]), float(np.sqrt(rss / n)), tuple(float(c) for c in coef)))
    return tuple(fits)


def tone_basis(thetas: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """The joint basis for phases ``thetas`` of shape (K, n) and drift time ``tau`` (n,)."""
    thetas = np.atleast_2d(np.asarray(thetas, float))
    cols = [f(th) for th in thetas for f in (np.cos, np.sin)]
    return np.stack([*cols, np.ones_like(tau), tau], axis=1)


def tone_sums(thetas: np.ndarray, tau: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, int]:
    """The sums the native step accumulates for the joint fit, from sample arrays (tests, analysis)."""
    return packed_sums(tone_basis(thetas, np.asarray(tau, float)), y)
