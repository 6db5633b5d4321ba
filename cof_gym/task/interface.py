"""The agent's side of the task: action decoding and observation encoding (with the matching decode).

Only sensor readings reach the agent: :data:`SENSOR_FIELDS` lists the parts of a window's
measurement a train's sensors give (the rest of :class:`~cof_gym.physics.simulation.WindowMeasurement`
is ground truth, reported under ``info["ground_truth"]``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Callable

import numpy as np
from gymnasium import spaces

from cof_gym.measurement.sine_fit import NO_SE_DEG
from cof_gym.task.creep_fit import ELASTICITY_SPAN, ClimbRecord
from cof_gym.physics.simulation import COA_CYCLE_FIELDS, DriveCommand, WindowMeasurement
from cof_gym.validation import check_number

ACTION_NAMES = ("dc_torque", "amplitude", "frequency", "cof_estimate", "stop")
OBSERVATION_NAMES = (
    "phase_lag", "phase_lag_se", "compliance", "coa_measured", "creepage_measured", "dc_torque", "amplitude",
    "frequency", "speed", "wd_rms", "jerk_rms", "normal_load", "elapsed", "cof_estimate",
)
OBS_BOUND = 1e3  # observations are clipped to +-OBS_BOUND (they are O(1) in normal operation)
CREEPAGE_SCALE = 10.0  # observation = measured creepage x 10
PHASE_SCALE_DEG = 90.0  # observation = phase lag (and its standard error) / 90 deg
SPEED_SCALE_M_S = 40.0
JERK_SCALE_M_S3 = 10.0
WD_SCALE_M_S2 = 0.01

# What a train's sensors measure in a window (encoder, speed sensor, force sensors or an observer, the
# drive's torque, a car-body accelerometer); info["measurement"] holds these (and, with a multi-tone excitation, each
# tone's tone<k>_* readings).
SENSOR_FIELDS = (
    "phase_lag_deg", "phase_lag_se_deg", "amplitude_ratio", "torque_amplitude_nm", "omega_amplitude_rad_s",
    "coa_measured", "creepage_measured", "speed_measured_m_s", "normal_load_measured_n",
    "tangential_force_measured_n", "torque_mean_nm", "torque_peak_nm", "wd_rms_m_s2", "jerk_rms_m_s3",
    "wd_peak_m_s2", "samples", "creepage_modulation_amplitude", "creepage_modulation_lag_deg",
    "creepage_modulation_lag_se_deg", *COA_CYCLE_FIELDS, "phase_lag_se_corrected_deg", "rotation_ripple_rad_s",
    "rotation_ripple_phase_se_deg",
)


@dataclass(frozen=True)
class MotorLimits:
    """What the traction drive can do (N m, Hz) and the range of the reported estimate."""

    max_dc_torque_nm: float
    wheel_radius_m: float = 0.46  # of the driven wheelset: tractive force = torque / radius
    min_amplitude_nm: float = 20.0
    max_amplitude_nm: float = 3000.0
    min_frequency_hz: float = 1.0
    max_frequency_hz: float = 20.0
    min_cof_estimate: float = 0.01
    max_cof_estimate: float = 1.0

    def __post_init__(self) -> None:
        # every limit a finite positive number (stored as checked: Python floats), each minimum below its maximum
        for f in fields(self):
            object.__setattr__(self, f.name, check_number(f"MotorLimits.{f.name}", getattr(self, f.name), 0.0,
                                                          math.inf, low_open=True, high_open=True))
        for low, high in (("min_amplitude_nm", "max_amplitude_nm"), ("min_frequency_hz", "max_frequency_hz"),
                          ("min_cof_estimate", "max_cof_estimate")):
            if not getattr(self, low) < getattr(self, high):
                raise ValueError(f"MotorLimits.{low} must be below {high}, got {getattr(self, low)} and "
                                 f"{getattr(self, high)}")

    def clip_estimate(self, cof: float) -> float:
        """A CoF estimate within the range the action reports, [min_cof_estimate, max_cof_estimate]."""
        return min(max(cof, self.min_cof_estimate), self.max_cof_estimate)


def action_space() -> spaces.Box:
    return spaces.Box(-1.0, 1.0, shape=(len(ACTION_NAMES),), dtype=np.float32)


def observation_space() -> spaces.Box:
    return spaces.Box(-OBS_BOUND, OBS_BOUND, shape=(len(OBSERVATION_NAMES),), dtype=np.float32)


def check_action(action, names: tuple[str, ...] = ACTION_NAMES) -> np.ndarray:
    """A real, finite action of shape (5,) (``(len(names),)``: the multi-tone excitation appends
    components): anything else raises ``ValueError`` naming the problem (shape, dtype, or the
    non-finite components); values are clipped to [-1, 1]."""
    a = np.asarray(action)
    if a.shape != (len(names),):
        raise ValueError(f"action must have shape ({len(names)},) {names}, got shape {a.shape}")
    if a.dtype.kind not in "fiu":
        raise ValueError(f"action must be a real (float or int) array in [-1, 1], got dtype {a.dtype}")
    a = a.astype(np.float64)
    bad = [names[i] for i in np.flatnonzero(~np.isfinite(a))]
    if bad:
        raise ValueError(f"action component(s) {bad} are not finite (NaN/inf); allowed range [-1, 1]")
    return np.clip(a, -1.0, 1.0)


def _log_map(x: float, low: float, high: float) -> float:
    return math.exp(math.log(low) + (x + 1.0) / 2.0 * (math.log(high) - math.log(low)))


def _log_unmap(v: float, low: float, high: float) -> float:
    v = min(max(v, low), high)
    return 2.0 * (math.log(v) - math.log(low)) / (math.log(high) - math.log(low)) - 1.0


@dataclass(frozen=True)
class DecodedAction:
    drive: DriveCommand
    cof_estimate: float
    stop: bool


def decode_action(a: np.ndarray, limits: MotorLimits) -> DecodedAction:
    """[-1, 1]^5 -> DC torque (linear, 0...max), amplitude, frequency and CoF estimate (logarithmic)
    and stop (> 0)."""
    dc = (a[0] + 1.0) / 2.0 * limits.max_dc_torque_nm
    amp = _log_map(a[1], limits.min_amplitude_nm, limits.max_amplitude_nm)
    freq = _log_map(a[2], limits.min_frequency_hz, limits.max_frequency_hz)
    est = _log_map(a[3], limits.min_cof_estimate, limits.max_cof_estimate)
    return DecodedAction(DriveCommand(dc, amp, freq), float(est), bool(a[4] > 0.0))


def encode_action(dc_torque_nm: float, amplitude_nm: float, frequency_hz: float, cof_estimate: float, stop: bool,
                  limits: MotorLimits) -> np.ndarray:
    """Inverse of :func:`decode_action` (for scripted agents), clipped to the limits. A value that is not a finite
    number (``stop``: not a bool) is a ``ValueError`` naming it: an agent's NaN never reaches the env as an action."""
    for name, value in (("dc_torque_nm", dc_torque_nm), ("amplitude_nm", amplitude_nm),
                        ("frequency_hz", frequency_hz), ("cof_estimate", cof_estimate)):
        check_number(name, value, -math.inf, math.inf)
    if not isinstance(stop, (bool, np.bool_)):
        raise ValueError(f"stop must be a bool (True or False), got {stop!r} ({type(stop).__name__})")
    a = np.array([
        2.0 * dc_torque_nm / limits.max_dc_torque_nm - 1.0,
        _log_unmap(amplitude_nm, limits.min_amplitude_nm, limits.max_amplitude_nm),
        _log_unmap(frequency_hz, limits.min_frequency_hz, limits.max_frequency_hz),
        _log_unmap(cof_estimate, limits.min_cof_estimate, limits.max_cof_estimate),
        1.0 if stop else -1.0,
    ])
    return np.clip(a, -1.0, 1.0).astype(np.float32)


@dataclass(frozen=True)
class ObservationScales:
    """The vehicle constants the observation is scaled with (known on board)."""

    limits: MotorLimits
    spin_inertia_kg_m2: float  # of the driven wheelset
    static_contact_load_n: float
    horizon_s: float


def encode_observation(m: WindowMeasurement, drive: DriveCommand, scales: ObservationScales, elapsed_s: float,
                       cof_estimate: float) -> np.ndarray:
    """Only what a train measures, scaled to O(1). ``compliance`` is the speed/torque amplitude ratio
    times Iw*wm: 1 for a free wheel, ~0 when the creep force holds the wheel (far from the peak)."""
    lim = scales.limits
    wm = 2 * math.pi * drive.frequency_hz
    obs = np.array([
        m.phase_lag_deg / PHASE_SCALE_DEG,
        min(m.phase_lag_se_deg, NO_SE_DEG) / PHASE_SCALE_DEG,
        m.amplitude_ratio * scales.spin_inertia_kg_m2 * wm,
        m.coa_measured,
        m.creepage_measured * CREEPAGE_SCALE,
        drive.dc_torque_nm / lim.max_dc_torque_nm,
        drive.total_amplitude_nm / lim.max_amplitude_nm,
        drive.frequency_hz / lim.max_frequency_hz,
        m.speed_measured_m_s / SPEED_SCALE_M_S,
        m.wd_rms_m_s2 / WD_SCALE_M_S2,
        m.jerk_rms_m_s3 / JERK_SCALE_M_S3,
        m.normal_load_measured_n / scales.static_contact_load_n,
        elapsed_s / scales.horizon_s,
        cof_estimate / lim.max_cof_estimate,
    ], dtype=np.float64)
    return np.nan_to_num(np.clip(obs, -OBS_BOUND, OBS_BOUND), nan=0.0).astype(np.float32)


# each window reading an agent decodes with the drive's limits alone, back to physical units from its observation
# value (the inverse of encode_observation's scaling; normal_load and elapsed need the vehicle's ObservationScales)
_UNSCALE: dict[str, Callable[[float, MotorLimits | None], float]] = {
    "phase_lag": lambda v, limits: v * PHASE_SCALE_DEG,
    "phase_lag_se": lambda v, limits: v * PHASE_SCALE_DEG,
    "compliance": lambda v, limits: v,
    "coa_measured": lambda v, limits: v,
    "creepage_measured": lambda v, limits: v / CREEPAGE_SCALE,
    "dc_torque": lambda v, limits: v * limits.max_dc_torque_nm,
    "amplitude": lambda v, limits: v * limits.max_amplitude_nm,
    "frequency": lambda v, limits: v * limits.max_frequency_hz,
    "speed": lambda v, limits: v * SPEED_SCALE_M_S,
    "wd_rms": lambda v, limits: v * WD_SCALE_M_S2,
    "jerk_rms": lambda v, limits: v * JERK_SCALE_M_S3,
    "cof_estimate": lambda v, limits: v * limits.max_cof_estimate,
}
_INDEX = {name: i for i, name in enumerate(OBSERVATION_NAMES)}
LIMITS_READINGS = ("dc_torque", "amplitude", "frequency", "cof_estimate")  # the readings scaled by MotorLimits


def window_reading(observation: np.ndarray, name: str, limits: MotorLimits | None = None) -> float:
    """One reading of a window observation (any observation type: the window's values come first) in physical
    units: phase lag and its SE in deg, creepage, torques in N m, frequency in Hz, speed in m/s, the body's
    accelerations in m/s^2 and m/s^3 (:data:`LIMITS_READINGS` need the drive's ``limits``)."""
    if name not in _UNSCALE:
        raise ValueError(f"window_reading: name must be one of {sorted(_UNSCALE)}, got {name!r}")
    if limits is None and name in LIMITS_READINGS:
        raise ValueError(f"window_reading: {name!r} is scaled by the drive's limits: pass limits=MotorLimits(...)")
    return _UNSCALE[name](float(observation[_INDEX[name]]), limits)


@dataclass(frozen=True)
class DecodedObservation:
    """An observation in physical units (the inverse of :func:`encode_observation`)."""

    phase_lag_deg: float
    phase_lag_se_deg: float
    compliance: float
    coa_measured: float
    creepage_measured: float
    dc_torque_nm: float
    amplitude_nm: float
    frequency_hz: float
    speed_m_s: float
    wd_rms_m_s2: float
    jerk_rms_m_s3: float
    normal_load_n: float
    elapsed_s: float
    cof_estimate: float


def decode_observation(obs: np.ndarray, scales: ObservationScales) -> DecodedObservation:
    """Physical units back from an observation vector (for scripted agents); another shape is a ``ValueError``."""
    o = np.asarray(obs, dtype=np.float64)
    if o.shape != (len(OBSERVATION_NAMES),):
        raise ValueError(f"a window observation has shape ({len(OBSERVATION_NAMES)},), got {o.shape}")
    vehicle = {"normal_load": scales.static_contact_load_n, "elapsed": scales.horizon_s}  # scaled by the vehicle
    readings = (float(o[i]) * vehicle[name] if name in vehicle else window_reading(o, name, scales.limits)
                for i, name in enumerate(OBSERVATION_NAMES))
    return DecodedObservation(*readings)  # its fields are the observation's, in its order


# ---------------------------------------------------------------------------------------------------------
# Observation types (env option ``observation_type``): "window" (the 14 values above, default),
# "history" (those plus a fixed-size running summary of the episode, from the same sensor readings) and
# "identification" (the history plus the creep-curve fit of the climb so far).

HISTORY_WINDOWS = 3  # K: the previous windows a "history" observation repeats
HISTORY_SUMMARY_NAMES = ("baseline_phase_lag", "baseline_compliance", "best_coa")
HISTORY_WINDOW_NAMES = ("coa_measured", "creepage_measured", "phase_lag", "dc_torque")  # per previous window
HISTORY_OBSERVATION_NAMES = OBSERVATION_NAMES + HISTORY_SUMMARY_NAMES + tuple(
    f"{name}_{k}" for k in range(1, HISTORY_WINDOWS + 1) for name in HISTORY_WINDOW_NAMES)
_WINDOW_INDEX = tuple(_INDEX[n] for n in HISTORY_WINDOW_NAMES)
_PHASE, _COMPLIANCE, _COA, _DC = (_INDEX[n] for n in ("phase_lag", "compliance", "coa_measured", "dc_torque"))


@dataclass
class Memory:
    """What an episode remembers of its windows, kept from the encoded (sensor-only) window observations:
    the baseline (the first window the agent drove; until then the reset window), the best measured
    CoA, the last ``HISTORY_WINDOWS + 1`` windows (newest first, the current one included) and the
    climb (:class:`~cof_gym.task.creep_fit.ClimbRecord`: the driven windows with a DC torque,
    for the creep-curve fit). An agent can keep the same memory from the observations it is given."""

    baseline: np.ndarray | None = None
    baseline_driven: bool = False
    best_coa: float = 0.0
    recent: list[np.ndarray] = field(default_factory=list)
    climb: ClimbRecord = field(default_factory=ClimbRecord)

    def push(self, window: np.ndarray, driven: bool) -> None:
        """Record one window's observation (``driven``: measured with the agent's drive, not the reset's)."""
        window = np.asarray(window, dtype=np.float32)
        if self.baseline is None or (driven and not self.baseline_driven):
            self.baseline = window
            self.baseline_driven = driven
        coa = float(window[_COA])
        if math.isfinite(coa):
            self.best_coa = max(self.best_coa, coa)
        self.recent = [window] + self.recent[:HISTORY_WINDOWS]
        if driven and window[_DC] > 0:
            self.climb.add(coa, window_reading(window, "creepage_measured"), window_reading(window, "speed"),
                           float(window[_DC]))


@dataclass(frozen=True)
class WindowObservation:
    """The last window only (:data:`OBSERVATION_NAMES`)."""

    name: str = "window"
    names: tuple[str, ...] = OBSERVATION_NAMES

    def space(self) -> spaces.Box:
        return observation_space()

    def encode(self, window: np.ndarray, memory: Memory) -> np.ndarray:
        return window


@dataclass(frozen=True)
class HistoryObservation:
    """The last window, then the summary (the baseline's phase lag and compliance, the best measured CoA)
    and, for each of the previous ``HISTORY_WINDOWS`` windows (newest first; the oldest window known
    repeats until there are enough), its measured CoA, creepage, phase lag and DC torque, all in the
    window observation's units (:data:`HISTORY_OBSERVATION_NAMES`)."""

    name: str = "history"
    names: tuple[str, ...] = HISTORY_OBSERVATION_NAMES

    def space(self) -> spaces.Box:
        return spaces.Box(-OBS_BOUND, OBS_BOUND, shape=(len(self.names),), dtype=np.float32)

    def encode(self, window: np.ndarray, memory: Memory) -> np.ndarray:
        recent = memory.recent[1:]
        previous = [recent[min(k, len(recent) - 1)] if recent else window for k in range(HISTORY_WINDOWS)]
        base = memory.baseline if memory.baseline is not None else window
        summary = [base[_PHASE], base[_COMPLIANCE], min(memory.best_coa, OBS_BOUND)]
        parts = [np.asarray(window, dtype=np.float32), np.asarray(summary, dtype=np.float32)]
        parts += [np.asarray(w, dtype=np.float32)[list(_WINDOW_INDEX)] for w in previous]
        return np.concatenate(parts).astype(np.float32)


IDENTIFICATION_NAMES = (
    "fit_available", "fit_peak_ratio", "fit_low_ratio", "fit_high_ratio", "fit_half_width", "load_fraction",
    "log_elasticity", "climb_points", "falling",
)
IDENTIFICATION_OBSERVATION_NAMES = HISTORY_OBSERVATION_NAMES + IDENTIFICATION_NAMES
CLIMB_POINTS_SCALE = 10.0


def identification_features(window: np.ndarray, climb: ClimbRecord) -> np.ndarray:
    """The creep-curve fit of the climb, scale-free (:data:`IDENTIFICATION_NAMES`): whether a fit exists
    (>= 3 points), its peak, low and high ends as ``ln(value / best CoA)``, its relative half-width, the
    last window's CoA as a fraction of the fitted peak (of the best CoA before a fit), ``ln`` of the
    measured elasticity ``d ln s / d ln CoA`` (0 on the linear part), the climb's points / 10, and
    whether the last window's CoA fell (past the peak)."""
    fit, best = climb.fit, climb.best_coa
    coa = float(window[_COA])
    if fit is None or best <= 0:
        ratios, half_width, reference = (0.0, 0.0, 0.0), 0.0, best
    else:
        ratios = tuple(math.log(v / best) for v in (fit.estimate, fit.low, fit.high))
        half_width, reference = fit.half_width, fit.estimate
    values = [float(fit is not None), *ratios, half_width, coa / reference if reference > 0 else 0.0,
              math.log(climb.elasticity(ELASTICITY_SPAN)), len(climb.points) / CLIMB_POINTS_SCALE,
              float(climb.falling)]
    return np.clip(np.nan_to_num(np.asarray(values), nan=0.0), -OBS_BOUND, OBS_BOUND).astype(np.float32)


@dataclass(frozen=True)
class IdentificationObservation:
    """The "history" observation followed by :func:`identification_features`
    (:data:`IDENTIFICATION_OBSERVATION_NAMES`): what the model-based agent decides from, for a policy
    to decide when and how to climb and when to stop."""

    name: str = "identification"
    names: tuple[str, ...] = IDENTIFICATION_OBSERVATION_NAMES

    def space(self) -> spaces.Box:
        return spaces.Box(-OBS_BOUND, OBS_BOUND, shape=(len(self.names),), dtype=np.float32)

    def encode(self, window: np.ndarray, memory: Memory) -> np.ndarray:
        history = HistoryObservation().encode(window, memory)
        return np.concatenate([history, identification_features(window, memory.climb)]).astype(np.float32)


OBSERVATION_TYPES = {"window": WindowObservation(), "history": HistoryObservation(),
                     "identification": IdentificationObservation()}


def get_observation_type(name: str):
    try:
        return OBSERVATION_TYPES[name]
    except (KeyError, TypeError):
        raise ValueError(f"observation_type must be one of {list(OBSERVATION_TYPES)}, got {name!r}") from None


@dataclass(frozen=True)
class DecodedHistory:
    """A "history" observation in physical units (the inverse of :meth:`HistoryObservation.encode`)."""

    window: DecodedObservation
    baseline_phase_lag_deg: float
    baseline_compliance: float
    best_coa: float
    previous: tuple[dict[str, float], ...]  # newest first: coa_measured, creepage_measured, phase_lag_deg, dc_torque_nm


def decode_history(obs: np.ndarray, scales: ObservationScales) -> DecodedHistory:
    """Physical units back from a "history" observation (for scripted agents)."""
    o = np.asarray(obs, dtype=np.float64)
    if o.shape != (len(HISTORY_OBSERVATION_NAMES),):
        raise ValueError(f"a history observation has shape ({len(HISTORY_OBSERVATION_NAMES)},), got {o.shape}")
    n, s = len(OBSERVATION_NAMES), len(HISTORY_SUMMARY_NAMES)
    w = len(HISTORY_WINDOW_NAMES)
    keys = ("coa_measured", "creepage_measured", "phase_lag_deg", "dc_torque_nm")  # of HISTORY_WINDOW_NAMES
    previous = tuple({key: _UNSCALE[name](float(o[i + k]), scales.limits)
                      for k, (name, key) in enumerate(zip(HISTORY_WINDOW_NAMES, keys))}
                     for i in range(n + s, n + s + w * HISTORY_WINDOWS, w))
    return DecodedHistory(decode_observation(o[:n], scales),
                          baseline_phase_lag_deg=_UNSCALE["phase_lag"](float(o[n]), None),
                          baseline_compliance=float(o[n + 1]), best_coa=float(o[n + 2]), previous=previous)
