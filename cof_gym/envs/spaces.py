"""Action rescaling and observation encoding, shared by the single and the vector environments."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces

from cof_gym.physics.simulation import DriveCommand, WindowMeasurement

ACTION_NAMES = ("dc_torque", "amplitude", "frequency", "cof_estimate", "stop")
OBSERVATION_NAMES = (
    "phase_lag", "phase_lag_se", "compliance", "coa_measured", "dc_torque", "amplitude", "frequency",
    "speed", "wd_rms", "jerk_rms", "normal_load", "elapsed", "cof_estimate",
)


OBS_BOUND = 1e3  # observations are clipped to +-OBS_BOUND (they are O(1) in normal operation)


@dataclass(frozen=True)
class MotorLimits:
    """What the traction drive can do (N m, Hz). ``max_dc_torque_nm`` is set per vehicle."""

    max_dc_torque_nm: float
    min_amplitude_nm: float = 20.0
    max_amplitude_nm: float = 3000.0
    min_frequency_hz: float = 1.0
    max_frequency_hz: float = 20.0
    max_cof_estimate: float = 0.8

    def __post_init__(self) -> None:
        if not (0 < self.min_amplitude_nm < self.max_amplitude_nm and 0 < self.min_frequency_hz < self.max_frequency_hz
                and self.max_dc_torque_nm > 0 and self.max_cof_estimate > 0):
            raise ValueError(f"motor limits must be positive with min < max, got {self!r}")


def action_space() -> spaces.Box:
    return spaces.Box(-1.0, 1.0, shape=(len(ACTION_NAMES),), dtype=np.float32)


def observation_space() -> spaces.Box:
    return spaces.Box(-OBS_BOUND, OBS_BOUND, shape=(len(OBSERVATION_NAMES),), dtype=np.float32)


def check_action(action) -> np.ndarray:
    """Non-finite components raise ValueError naming them; the rest is clipped to [-1, 1]."""
    a = np.asarray(action, dtype=np.float64).reshape(-1)
    if a.shape != (len(ACTION_NAMES),):
        raise ValueError(f"action must have shape ({len(ACTION_NAMES)},) {ACTION_NAMES}, got {np.shape(action)}")
    bad = [ACTION_NAMES[i] for i in np.flatnonzero(~np.isfinite(a))]
    if bad:
        raise ValueError(f"action component(s) {bad} are not finite (NaN/inf); allowed range [-1, 1]")
    return np.clip(a, -1.0, 1.0)


def _log_map(x: float, low: float, high: float) -> float:
    return math.exp(math.log(low) + (x + 1.0) / 2.0 * (math.log(high) - math.log(low)))


def _log_unmap(v: float, low: float, high: float) -> float:
    return 2.0 * (math.log(v) - math.log(low)) / (math.log(high) - math.log(low)) - 1.0


@dataclass(frozen=True)
class DecodedAction:
    drive: DriveCommand
    cof_estimate: float
    stop: bool


def decode_action(a: np.ndarray, limits: MotorLimits) -> DecodedAction:
    """[-1, 1]^5 -> DC torque (linear, 0...max), amplitude and frequency (logarithmic), CoF estimate
    (linear, 0...max_cof_estimate) and stop (> 0)."""
    dc = (a[0] + 1.0) / 2.0 * limits.max_dc_torque_nm
    amp = _log_map(a[1], limits.min_amplitude_nm, limits.max_amplitude_nm)
    freq = _log_map(a[2], limits.min_frequency_hz, limits.max_frequency_hz)
    est = (a[3] + 1.0) / 2.0 * limits.max_cof_estimate
    return DecodedAction(DriveCommand(dc, amp, freq), float(est), bool(a[4] > 0.0))


def encode_action(dc_torque_nm: float, amplitude_nm: float, frequency_hz: float, cof_estimate: float, stop: bool,
                  limits: MotorLimits) -> np.ndarray:
    """Inverse of :func:`decode_action` (for scripted agents), clipped to the limits."""
    amp = min(max(amplitude_nm, limits.min_amplitude_nm), limits.max_amplitude_nm)
    freq = min(max(frequency_hz, limits.min_frequency_hz), limits.max_frequency_hz)
    a = np.array([
        2.0 * dc_torque_nm / limits.max_dc_torque_nm - 1.0,
        _log_unmap(amp, limits.min_amplitude_nm, limits.max_amplitude_nm),
        _log_unmap(freq, limits.min_frequency_hz, limits.max_frequency_hz),
        2.0 * cof_estimate / limits.max_cof_estimate - 1.0,
        1.0 if stop else -1.0,
    ])
    return np.clip(a, -1.0, 1.0).astype(np.float32)


def encode_observation(m: WindowMeasurement, drive: DriveCommand, limits: MotorLimits, spin_inertia: float,
                       nominal_contact_load_n: float, elapsed_s: float, horizon_s: float,
                       cof_estimate: float) -> np.ndarray:
    """Only what a train measures, scaled to O(1). ``compliance`` is the speed/torque amplitude ratio
    times Iw*wm: 1 for a free wheel, ~0 when the creep force holds the wheel (far from the peak)."""
    wm = 2 * math.pi * drive.frequency_hz
    obs = np.array([
        m.phase_lag_deg / 90.0,
        min(m.phase_lag_se_deg, 180.0) / 90.0,
        m.amplitude_ratio * spin_inertia * wm,
        m.coa_measured,
        drive.dc_torque_nm / limits.max_dc_torque_nm,
        drive.amplitude_nm / limits.max_amplitude_nm,
        drive.frequency_hz / limits.max_frequency_hz,
        m.speed_measured_m_s / 40.0,
        m.wd_rms_m_s2,
        m.jerk_rms_m_s3 / 10.0,
        m.normal_load_n / nominal_contact_load_n,
        elapsed_s / horizon_s,
        cof_estimate / limits.max_cof_estimate,
    ], dtype=np.float64)
    return np.nan_to_num(np.clip(obs, -OBS_BOUND, OBS_BOUND), nan=0.0).astype(np.float32)
