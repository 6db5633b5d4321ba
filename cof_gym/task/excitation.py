"""The interrogation signal (env option ``excitation``): one sine (default) or a multi-tone torque whose
tones are measured each with its own lock-in (GitHub issue 16: "other interrogation signals ... to
estimate CoF at lower magnitudes of applied torque").

``"sine"``: ``M = Mc + M0 sin(2 pi f t)``, the 5-component action and the observation type's observation
unchanged (bit-identical to not passing the option).

``"multitone"`` with ``tones`` = K in {2, 3}: ``M = Mc + sum_k a_k sin(2 pi f_k t)``. The action grows by 2
components per extra tone k = 2...K, appended after the 5 of the action type, decoded the same way for
every action type (the action type decodes the first 5: its amplitude is the TOTAL amplitude
``A = sum_k a_k``, its frequency tone 1's ``f_1``):

- ``frequency_k``: logarithmic over the drive's frequency range (1...20 Hz), as tone 1's;
- ``share_k``: a weight ``w_k = 1 + a`` in [0, 2] (tone 1's weight is 1), and ``a_k = A w_k / (1 + sum_j w_j)``:
  ``a = 0`` splits the amplitude equally, ``-1`` silences the tone (all of it on the others), ``+1`` gives
  it twice tone 1's share. Every ``a_k >= 0`` and they sum to ``A``.

A window of measured length ``T = window_s - settle_s`` resolves tones about ``1 / T`` apart; the fit of
closer tones is ill-conditioned (large errors). The decode therefore moves an extra tone that is closer
than :func:`min_separation_hz` ``= 2 / T`` to tone 1 or to an earlier extra tone to the nearest frequency
in range that keeps that distance (tone 1 is never moved; the drive actually applied is in
``info["measurement"]["tone<k>_frequency_hz"]``). :class:`Excitation` refuses, at construction, a window
too short for K tones to fit in the range that way. Second-order intermodulation is not avoided:
the creep curve's curvature mixes tones, so a tone at ``f_i + f_j``, ``|f_i - f_j|`` or ``2 f_i`` of
others picks up a small distortion product (it grows with the modulation depth; pick such frequencies
apart when it matters).

The observation appends ``[phase_lag_k / 90, phase_lag_se_k / 90, compliance_k]`` for k = 1...K (the
window observation's scales; ``compliance_k = amplitude ratio_k x Iw x 2 pi f_k``) after whatever the
observation type produces; a silent tone reads lag 0, SE 180 deg (2.0) and compliance 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cof_gym.measurement.sine_fit import NO_SE_DEG
from cof_gym.physics.simulation import MAX_TONES, DriveCommand, WindowMeasurement, tone_field
from cof_gym.task.interface import PHASE_SCALE_DEG, MotorLimits, _log_map, _log_unmap
from cof_gym.validation import check_choice, check_int

EXCITATIONS = ("sine", "multitone")
TONES_RANGE = (2, MAX_TONES)
TONE_OBSERVATION_NAMES = ("phase_lag", "phase_lag_se", "compliance")
TONE_ACTION_NAMES = ("frequency", "share")
BASELINE_EXTRA_FREQUENCIES_HZ = (11.0, 17.0)  # the reset window's extra tones (tone 1 at 5 Hz as the sine's)
RESOLUTION_FACTOR = 2.0  # tones are kept >= RESOLUTION_FACTOR / T apart


def min_separation_hz(measured_s: float) -> float:
    """The smallest distance kept between tones over a measured span of ``measured_s`` seconds."""
    return RESOLUTION_FACTOR / measured_s


def encode_extra_tones(tones: list[tuple[float, float]], min_frequency_hz: float = MotorLimits.min_frequency_hz,
                       max_frequency_hz: float = MotorLimits.max_frequency_hz) -> np.ndarray:
    """The action components appended for extra tones given as ``(frequency_hz, weight)`` pairs (weight
    ``w_k`` in [0, 2], tone 1's being 1): the inverse of :meth:`Excitation.drive`'s decoding."""
    out = []
    for frequency_hz, weight in tones:
        out += [_log_unmap(frequency_hz, min_frequency_hz, max_frequency_hz), min(max(weight, 0.0), 2.0) - 1.0]
    return np.asarray(out, dtype=np.float32)


def separate(frequencies: list[float], separation_hz: float, low: float, high: float) -> list[float]:
    """The frequencies, each extra one (index >= 1) moved, if needed, to the nearest frequency in
    [low, high] at least ``separation_hz`` from every earlier one (the first is kept)."""
    placed = [frequencies[0]]
    for f in frequencies[1:]:
        candidates = [f, low, high] + [p + s for p in placed for s in (-separation_hz, separation_hz)]
        valid = [c for c in candidates if low - 1e-12 <= c <= high + 1e-12
                 and all(abs(c - p) >= separation_hz * (1 - 1e-12) for p in placed)]
        best = min(valid, key=lambda c: (abs(c - f), c)) if valid else f  # Excitation makes valid non-empty
        placed.append(min(max(best, low), high))
    return placed


@dataclass(frozen=True)
class Excitation:
    """The env's ``excitation`` and ``tones`` options (see the module docstring)."""

    kind: str = "sine"
    tones: int = 2
    measured_s: float = 0.6  # window_s - settle_s: the span each tone is fitted over
    min_frequency_hz: float = MotorLimits.min_frequency_hz  # the drive's range, as tone 1's
    max_frequency_hz: float = MotorLimits.max_frequency_hz

    def __post_init__(self) -> None:
        check_choice("excitation", self.kind, EXCITATIONS)
        object.__setattr__(self, "tones", check_int("tones", self.tones, *TONES_RANGE))  # stored as a Python int
        if self.multitone:
            span = self.max_frequency_hz - self.min_frequency_hz
            need = 2 * (self.tones - 1) * self.separation_hz
            if need > span:
                raise ValueError(
                    f"tones={self.tones} needs a measured span (window_s x (1 - settle_fraction)) of at least "
                    f"{2 * (self.tones - 1) * RESOLUTION_FACTOR / span:.3g} s to keep the tones "
                    f"{RESOLUTION_FACTOR:g} / T apart in {self.min_frequency_hz:g}-{self.max_frequency_hz:g} Hz, "
                    f"got {self.measured_s:.3g} s; lengthen window_s, lower settle_fraction or use fewer tones")

    @property
    def multitone(self) -> bool:
        return self.kind == "multitone"

    @property
    def n_tones(self) -> int:
        return self.tones if self.multitone else 1

    @property
    def separation_hz(self) -> float:
        return min_separation_hz(self.measured_s)

    @property
    def action_names(self) -> tuple[str, ...]:
        """The components appended to the action type's 5."""
        return tuple(f"{name}_{k}" for k in range(2, self.n_tones + 1) for name in TONE_ACTION_NAMES)

    @property
    def observation_names(self) -> tuple[str, ...]:
        """The components appended to the observation type's observation."""
        if not self.multitone:
            return ()
        return tuple(f"tone{k}_{name}" for k in range(1, self.n_tones + 1) for name in TONE_OBSERVATION_NAMES)

    def drive(self, base: DriveCommand, extra: np.ndarray) -> DriveCommand:
        """The drive of an action: ``base`` as the action type decoded it (its amplitude the total), and
        the appended components ``extra`` (in [-1, 1], 2 per extra tone)."""
        if not self.multitone:
            return base
        extra = np.asarray(extra, dtype=np.float64)
        freqs = [base.frequency_hz] + [_log_map(float(extra[2 * i]), self.min_frequency_hz, self.max_frequency_hz)
                                       for i in range(self.tones - 1)]
        weights = [1.0] + [1.0 + float(extra[2 * i + 1]) for i in range(self.tones - 1)]
        return self._split(base, freqs, weights)

    def baseline(self, base: DriveCommand) -> DriveCommand:
        """The reset window's drive: ``base``'s total amplitude split equally over tone 1 at ``base``'s
        frequency and the extra tones at :data:`BASELINE_EXTRA_FREQUENCIES_HZ` (kept apart as any drive)."""
        if not self.multitone:
            return base
        freqs = [base.frequency_hz, *BASELINE_EXTRA_FREQUENCIES_HZ[:self.tones - 1]]
        return self._split(base, freqs, [1.0] * self.tones)

    def _split(self, base: DriveCommand, freqs: list[float], weights: list[float]) -> DriveCommand:
        freqs = separate(freqs, self.separation_hz, self.min_frequency_hz, self.max_frequency_hz)
        total, wsum = base.amplitude_nm, sum(weights)
        amps = [total * w / wsum for w in weights]
        return DriveCommand(base.dc_torque_nm, amps[0], freqs[0], tuple(zip(amps[1:], freqs[1:])))

    def features(self, m: WindowMeasurement, drive: DriveCommand, spin_inertia_kg_m2: float) -> np.ndarray:
        """``[phase_lag_k / 90, phase_lag_se_k / 90, compliance_k]`` per tone (float64, finite)."""
        out = []
        for k, (_, freq) in enumerate(drive.tones[:self.n_tones], start=1):
            wm = 2 * math.pi * freq
            out += [getattr(m, tone_field(k, "phase_lag_deg")) / PHASE_SCALE_DEG,
                    min(getattr(m, tone_field(k, "phase_lag_se_deg")), NO_SE_DEG) / PHASE_SCALE_DEG,
                    getattr(m, tone_field(k, "amplitude_ratio")) * spin_inertia_kg_m2 * wm]
        # a drive with fewer tones (never, in the env): silent tones
        out += [0.0, NO_SE_DEG / PHASE_SCALE_DEG, 0.0] * (self.n_tones - len(drive.tones))
        return np.nan_to_num(np.asarray(out, dtype=np.float64), nan=0.0, posinf=0.0, neginf=0.0)

    def measurement_info(self, m: WindowMeasurement, drive: DriveCommand) -> dict[str, float]:
        """Per-tone entries for ``info["measurement"]`` (numbers only): ``tone<k>_frequency_hz``,
        ``tone<k>_amplitude_nm`` (commanded) and the fit's lag, SE, amplitude ratio and amplitudes."""
        if not self.multitone:
            return {}
        info: dict[str, float] = {}
        tones = drive.tones
        for k in range(1, self.n_tones + 1):
            amp, freq = tones[k - 1] if k <= len(tones) else (0.0, 0.0)
            info[f"tone{k}_frequency_hz"] = float(freq)
            info[f"tone{k}_amplitude_nm"] = float(amp)
            for name in ("phase_lag_deg", "phase_lag_se_deg", "amplitude_ratio", "torque_amplitude_nm",
                         "omega_amplitude_rad_s"):
                info[tone_field(k, name)] = float(getattr(m, tone_field(k, name)))
        return info
