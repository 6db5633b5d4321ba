"""Vertical track irregularity: the rail's vertical profile under the wheels, drawn from a published spectrum.

A real track is not level: its vertical profile (the rail's height along the track) varies by millimetres over
wavelengths of metres to tens of metres, and a wheelset rolling over it at speed ``v`` is excited at ``v /
wavelength``. The wheel loads then vary, and with them the saturation torque under a climb and the creep force a
modulation reads. cof_gym draws a profile per episode (where a scenario asks for one, and in every v3 draw; no v1 or
v2 draw does) and the native callback evaluates it at every wheelset's position every physics step: the track
spring's rest height is raised by the profile, ``N = k (z_rest + z_t(x) - z) - c (z' - v dz_t/dx)``.

Spectrum (one-sided, in the spatial angular frequency ``Omega`` in rad/m, m^2 / (rad/m)), the vertical-profile
form of ORE B176's reference spectra for European track, as used for European and German high-speed lines::

    S_v(Omega) = A_v Omega_c^2 / ((Omega^2 + Omega_r^2) (Omega^2 + Omega_c^2))

with ``Omega_c`` 0.8246 rad/m, ``Omega_r`` 0.0206 rad/m and ``A_v`` 4.032e-7 m rad for low irregularity (good
track) or 1.080e-6 m rad for high irregularity (ORE B176, "Bogies with steered or steering wheelsets", Report 1,
Utrecht 1989). The coefficients are as commonly reproduced from that report (the same in several independent
public implementations of railway dynamics); cof_gym has not read the report itself (unverified). The profile holds the
wavelengths 1-80 m (``WAVELENGTH_RANGE_M``; the usual band of such simulations): its standard deviation is about
2.1 mm (low) and 3.4 mm (high), most of it in the longest waves.

Synthesis: the band is split into ``MAX_TRACK_WAVES`` intervals equally spaced in log wavenumber, each a cosine
``a_k cos(Omega_k x + phi_k)`` at the interval's geometric centre with a phase drawn uniformly, and an amplitude
``a_k = sqrt(2 int S_v)`` over the interval (the closed-form integral below), so that the profile's variance is the
spectrum's integral over the band exactly, whatever the number of waves (Shinozuka's spectral representation).
Evaluating the 32 cosines under four wheelsets costs the wagon about a third of its physics steps per second
(``cof-gym bench``'s row "ratio native on a track of high vertical irregularity / level track": 0.63-0.82 over six
runs in session 82 on a busy machine, 0.70 in the median); a level track costs nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping

import numpy as np

from cof_gym.physics.native.layout import MAX_TRACK_WAVES  # cosines of a profile (the layout holds them)

WAVELENGTH_RANGE_M = (1.0, 80.0)


@dataclass(frozen=True)
class TrackSpectrum:
    """A vertical-profile spectrum of the form above: ``a_v`` (m rad), ``omega_c`` and ``omega_r`` (rad/m)."""

    a_v: float
    omega_c: float = 0.8246
    omega_r: float = 0.0206

    def density(self, omega: np.ndarray | float) -> np.ndarray:
        """S_v at the spatial angular frequency ``omega`` (rad/m), m^2 / (rad/m)."""
        w2 = np.square(omega)
        return self.a_v * self.omega_c**2 / ((w2 + self.omega_r**2) * (w2 + self.omega_c**2))

    def integral(self, low: float, high: float) -> float:
        """The integral of S_v over [low, high] rad/m (m^2), in closed form: the partial fractions
        ``A Oc^2 / (Oc^2 - Or^2) (1 / (O^2 + Or^2) - 1 / (O^2 + Oc^2))`` integrate to arctangents."""
        def antiderivative(w: float) -> float:
            return math.atan(w / self.omega_r) / self.omega_r - math.atan(w / self.omega_c) / self.omega_c
        scale = self.a_v * self.omega_c**2 / (self.omega_c**2 - self.omega_r**2)
        return scale * (antiderivative(high) - antiderivative(low))


# the track classes a scenario may name (``track_irregularity``), each a spectrum; "smooth" (no profile) is the
# default and what every v1 and v2 draw runs on
TRACK_SPECTRA: Mapping[str, TrackSpectrum] = MappingProxyType({
    "ore_low": TrackSpectrum(a_v=4.032e-7),
    "ore_high": TrackSpectrum(a_v=1.080e-6),
})
SMOOTH = "smooth"
TRACK_CLASSES: tuple[str, ...] = (SMOOTH, *TRACK_SPECTRA)


@dataclass(frozen=True)
class TrackProfile:
    """A drawn vertical profile ``z_t(x) = sum_k a_k cos(Omega_k x + phi_k)``: amplitudes (m), wavenumbers (rad/m)
    and phases (rad), one entry per cosine. Empty: a smooth track."""

    amplitudes_m: tuple[float, ...] = ()
    wavenumbers_rad_m: tuple[float, ...] = ()
    phases_rad: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        n = len(self.amplitudes_m)
        if not (len(self.wavenumbers_rad_m) == len(self.phases_rad) == n <= MAX_TRACK_WAVES):
            raise ValueError(f"a track profile needs as many amplitudes, wavenumbers and phases, at most "
                             f"{MAX_TRACK_WAVES}, got {n}, {len(self.wavenumbers_rad_m)} and {len(self.phases_rad)}")
        values = (*self.amplitudes_m, *self.wavenumbers_rad_m, *self.phases_rad)
        if not all(math.isfinite(v) for v in values) or min(self.amplitudes_m, default=0.0) < 0.0:
            raise ValueError("a track profile's amplitudes must be finite and >= 0, its wavenumbers and phases finite")

    def height_m(self, x_m: np.ndarray | float) -> np.ndarray:
        """The profile's height at ``x_m`` (m): what the native callback adds to the track spring's rest height."""
        x = np.asarray(x_m, dtype=np.float64)[..., None]
        return np.sum(np.array(self.amplitudes_m) * np.cos(np.array(self.wavenumbers_rad_m) * x
                                                          + np.array(self.phases_rad)), axis=-1)

    def standard_deviation_m(self) -> float:
        """The profile's standard deviation over a long track (m): sqrt(sum a_k^2 / 2)."""
        return math.sqrt(0.5 * sum(a * a for a in self.amplitudes_m))


def draw_profile(track_class: str, rng: np.random.Generator) -> TrackProfile:
    """A profile of ``track_class`` (one of :data:`TRACK_CLASSES`) with phases drawn from ``rng``; a smooth track
    draws nothing (so that ``rng`` moves only where a profile is asked for)."""
    if track_class not in TRACK_CLASSES:
        raise ValueError(f"track_irregularity must be one of {list(TRACK_CLASSES)}, got {track_class!r}")
    if track_class == SMOOTH:
        return TrackProfile()
    spectrum = TRACK_SPECTRA[track_class]
    low, high = (2.0 * math.pi / wavelength for wavelength in WAVELENGTH_RANGE_M[::-1])
    edges = np.geomspace(low, high, MAX_TRACK_WAVES + 1)
    amplitudes = [math.sqrt(2.0 * spectrum.integral(a, b)) for a, b in zip(edges[:-1], edges[1:])]
    centres = np.sqrt(edges[:-1] * edges[1:])
    phases = rng.uniform(0.0, 2.0 * math.pi, size=MAX_TRACK_WAVES)
    return TrackProfile(tuple(amplitudes), tuple(float(w) for w in centres), tuple(float(p) for p in phases))
