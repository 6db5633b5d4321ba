"""A simulation = a built model + an ``MjData`` whose ``userdata`` carries cof_gym's state.

The functions on userdata rows (:func:`initial_userdata`, :func:`begin_window`,
:func:`read_window`) work on any ``(SIZE,)`` float array, so the single :class:`Simulation` and the
batched vector environment (rows of a ``mujoco.batch.Batch``) share them.

One measurement window is one ``mujoco.mj_step(model, data, nstep)`` call: the native callback
applies the forces and accumulates every sum the window's measurement needs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import mujoco
import numpy as np

from cof_gym.measurement.comfort import band_limiting_sos, wd_weighting_sos
from cof_gym.measurement.sine_fit import (NO_SE_DEG, SineFit, coefficient_covariance, colored_noise_factor,
                                         fit_from_sums, fit_tones_from_sums, lag1_correlation, unpack_symmetric,
                                         wrap_deg)
from cof_gym.measurement.synchronous_average import cycle_extremes
from cof_gym.physics.creep import OperatingConditions, creep_peak
from cof_gym.physics.encoder import PulseEncoder
from cof_gym.physics.models import BuiltModel
from cof_gym.physics.native import layout
from cof_gym.physics.native.build import install_callback
from cof_gym.physics.track import TrackProfile
from cof_gym.validation import check_choice, check_number

I = layout.OFFSETS
MIN_SPEED_M_S = 0.1  # creepage denominator floor (only reached when a wheel stands still)


@dataclass(frozen=True)
class SensorNoise:
    """Standard deviations of the on-board sensors (zero: ideal, as in the paper)."""

    omega_rad_s: float = 0.0  # encoder-derived wheelset speed
    force_relative: float = 0.0  # contact-force sensors (tangential and normal, each)
    speed_m_s: float = 0.0  # train speed

    def __post_init__(self) -> None:
        for name in ("omega_rad_s", "force_relative", "speed_m_s"):
            check_number(f"noise {name}", getattr(self, name), 0.0, math.inf)


# the acceleration feedback's bound: the one-step-late feedback of the native step diverges once kd reaches the car
# body's mass, about 0.72 of the empty wagon's whole mass (0.85 laden); 0.6 keeps a margin above the default 0.5
MAX_KD_MASS_RATIO = 0.6


@dataclass(frozen=True)
class CruiseControl:
    """PI speed control with acceleration feedback on the car body:
    F = kp (v_set - v) + ki int(v_set - v) dt - kd a.

    The gains scale with the vehicle mass m: ``bandwidth_hz`` sets kp = 2 pi f m, ``integral_hz``
    ki = 2 pi f_i kp (the integral action removes the steady speed error under a steady traction
    force) and ``kd_mass_ratio`` kd = ratio * m (an acceleration feedback that adds apparent mass).
    The continuous loop (m + kd) s^2 + kp s + ki is stable for any positive gains; the native step feeds back
    the previous step's acceleration, a loop that is unstable once kd nears the car body's own mass (at a ratio
    of about 0.72 of the whole vehicle's mass, empty), so ``kd_mass_ratio`` is held below
    :data:`MAX_KD_MASS_RATIO` (the env's default 0.5)."""

    bandwidth_hz: float = 0.5
    integral_hz: float = 0.1
    kd_mass_ratio: float = 0.5

    def __post_init__(self) -> None:
        check_number("CruiseControl.bandwidth_hz", self.bandwidth_hz, 0.0, math.inf, low_open=True, high_open=True,
                     unit=" Hz")
        check_number("CruiseControl.integral_hz", self.integral_hz, 0.0, math.inf, high_open=True, unit=" Hz")
        check_number("CruiseControl.kd_mass_ratio", self.kd_mass_ratio, 0.0, MAX_KD_MASS_RATIO)

    def gains(self, mass_kg: float) -> tuple[float, float, float]:
        """(kp N s/m, ki N/m, kd kg) for a vehicle of ``mass_kg``."""
        kp = 2 * math.pi * self.bandwidth_hz * mass_kg
        return kp, 2 * math.pi * self.integral_hz * kp, self.kd_mass_ratio * mass_kg


FREQUENCY_RANGE_HZ = (0.1, 100.0)
MAX_TONES = layout.MAX_TONES


@dataclass(frozen=True)
class DriveCommand:
    """Traction torque M = Mc + M0 sin(theta) + sum_k a_k sin(theta_k), dtheta/dt = 2 pi f,
    dtheta_k/dt = 2 pi f_k (N m, N m, Hz).

    ``extra_tones`` (default none: the single tone) holds up to ``MAX_TONES - 1`` further tones as
    ``(amplitude_nm, frequency_hz)`` pairs, each phase-continuous across windows as the first tone; a
    window with extra tones fits every tone jointly (:func:`read_window`)."""

    dc_torque_nm: float
    amplitude_nm: float
    frequency_hz: float
    extra_tones: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        check_number("dc_torque_nm", self.dc_torque_nm, -math.inf, math.inf, unit=" N m")
        check_number("amplitude_nm", self.amplitude_nm, 0.0, math.inf, unit=" N m")
        check_number("frequency_hz", self.frequency_hz, *FREQUENCY_RANGE_HZ, unit=" Hz")
        if self.extra_tones:  # () stays the very object it is (the single-tone default)
            object.__setattr__(self, "extra_tones", _check_tones(self.extra_tones))

    @property
    def tones(self) -> tuple[tuple[float, float], ...]:
        """Every tone as (amplitude N m, frequency Hz), the first one first."""
        return ((self.amplitude_nm, self.frequency_hz), *self.extra_tones)

    @property
    def total_amplitude_nm(self) -> float:
        """The sum of the tones' amplitudes (the single tone's amplitude without extra tones)."""
        if not self.extra_tones:
            return self.amplitude_nm
        return self.amplitude_nm + sum(a for a, _ in self.extra_tones)


def _check_tones(tones) -> tuple[tuple[float, float], ...]:
    """``extra_tones`` as (amplitude_nm, frequency_hz) float pairs, each number checked by
    :func:`~cof_gym.validation.check_number` (named ``extra_tones[k].amplitude_nm`` / ``.frequency_hz``)."""
    allowed = f"a sequence of at most {MAX_TONES - 1} (amplitude_nm, frequency_hz) pairs"
    try:
        pairs = tuple(tuple(t) for t in tones)
    except TypeError:
        raise ValueError(f"extra_tones must be {allowed}, got {tones!r}") from None
    if len(pairs) > MAX_TONES - 1 or any(len(p) != 2 for p in pairs):
        raise ValueError(f"extra_tones must be {allowed}, got {tones!r}")
    return tuple((check_number(f"extra_tones[{k}].amplitude_nm", amp, 0.0, math.inf, unit=" N m"),
                  check_number(f"extra_tones[{k}].frequency_hz", freq, *FREQUENCY_RANGE_HZ, unit=" Hz"))
                 for k, (amp, freq) in enumerate(pairs))


@dataclass(frozen=True)
class Scenario:
    """Everything drawn per episode: operating conditions plus sensor noise, the drive's torque lag (s; one below
    :data:`MIN_MOTOR_LAG_S` runs as none), the encoder's speed-signal lag (s; both first-order time constants), the
    track's profile and the encoder's pulses."""

    op: OperatingConditions
    noise: SensorNoise = field(default_factory=SensorNoise)
    motor_lag_s: float = 0.0
    cruise: CruiseControl = field(default_factory=CruiseControl)
    traction_balance: bool = False  # the rest of the train cancels the DC part of the torque
    seed: int = 0
    encoder_lag_s: float = 0.0
    track: TrackProfile = field(default_factory=TrackProfile)  # the rail's vertical profile (none: a smooth track)
    encoder: PulseEncoder = field(default_factory=PulseEncoder)  # the speed probe's pulses (none: continuous)
    lock_in: str = "plain"  # the speed's lock-in (LOCK_INS)

    def __post_init__(self) -> None:
        for name in ("motor_lag_s", "encoder_lag_s"):
            check_number(name, getattr(self, name), 0.0, 1.0, unit=" s")
        check_choice("lock_in", self.lock_in, LOCK_INS)


# The lock-in's basis for the speed (and the creepage) readings: "plain" fits [cos, sin] of each tone, an offset and a
# drift; "rotation" also fits [cos, sin] of the angle the encoder counts and of twice it, which takes a
# once-per-revolution ripple of the reading (a target wheel's runout, cof_gym.physics.encoder) and the period method's
# second-order term of it out of every tone's fit: the tones' readings come from the joint fit (as with several tones),
# the lag's SE for a correlated residual (one tone) from the joint fit's residual. A harmonic the window cannot tell
# from a tone (MAX_ROTATION_INFLATION) is left out of that window's fit, its ripple leaking in as the plain fit's does
LOCK_INS = ("plain", "rotation")


# A drive lag (s) below this runs as none: its first-order response completes within a step to the last bit
# (exp(-dt / tau) is 0), and the callback's torque rate, the rounding left in (command - torque) over tau, overflowed
# from about 1e-17 s (a diverged step); ms-scale lags, as drawn, are untouched
MIN_MOTOR_LAG_S = 1e-12


def initial_userdata(built: BuiltModel, scenario: Scenario) -> np.ndarray:
    """A fresh userdata row for one simulation of ``built`` in ``scenario``."""
    op = scenario.op
    # op.wheel_load_n is the load at which the law's CoF is defined (the static load, or the driven
    # wheel's load at saturation); the contacts scale the law with their actual load every step
    if not (0.5 <= op.wheel_load_n / built.nominal_wheel_load_n <= 2.0):
        raise ValueError(
            f"scenario wheel_load_n ({op.wheel_load_n:g} N) must be within 0.5-2 x the model's static wheel load "
            f"({built.nominal_wheel_load_n:g} N); build the model for that load case"
        )
    ud = np.zeros(layout.SIZE)
    ud[I["MAGIC"]] = layout.MAGIC
    ud[I["N_CONTACTS"]] = len(built.contacts)
    ud[I["MEASURED_CONTACT"]] = built.measured_contact
    ud[I["CARBODY_X_DOF"]] = built.carbody_x_dof
    ud[I["MIN_SPEED"]] = MIN_SPEED_M_S
    ud[I["TIMESTEP_S"]] = built.model.opt.timestep
    for k, contact in enumerate(built.contacts):
        for name, value in contact.values().items():
            ud[I[f"C{k}_{name}"]] = value
    law = op.law()
    for name, value in zip(layout.LAW_FIELDS, law.vector()):
        ud[I[name]] = value
    ud[I["S_PEAK"]] = creep_peak(op).creepage
    ud[I["MOD_OMEGA"]] = 2 * math.pi * 5.0
    ud[I["MOTOR_TAU"]] = scenario.motor_lag_s if scenario.motor_lag_s >= MIN_MOTOR_LAG_S else 0.0
    ud[I["ENCODER_TAU"]] = scenario.encoder_lag_s
    ud[I["ENCODER_PULSES"]] = scenario.encoder.pulses_per_rev
    ud[I["ENCODER_RUNOUT"]] = scenario.encoder.runout
    ud[I["LOCK_IN_ROTATION"]] = 1.0 if scenario.lock_in == "rotation" else 0.0
    track = scenario.track
    ud[I["TRACK_N_WAVES"]] = len(track.amplitudes_m)
    for prefix, values in (("AMP", track.amplitudes_m), ("WAVENUMBER", track.wavenumbers_rad_m),
                           ("PHASE", track.phases_rad)):
        ud[I[f"TRACK_{prefix}_0"]:I[f"TRACK_{prefix}_0"] + len(values)] = values
    kp, ki, kd = scenario.cruise.gains(built.total_mass_kg)
    ud[I["CRUISE_SPEED"]], ud[I["CRUISE_KP"]], ud[I["CRUISE_KI"]], ud[I["CRUISE_KD"]] = op.speed_m_s, kp, ki, kd
    if scenario.traction_balance:
        ud[I["BALANCE_PER_NM"]] = 1.0 / built.wheel_radius_m  # tractive force of one N m at the rail
    ud[I["CARBODY_PREV_VEL"]] = op.speed_m_s
    ud[I["NOISE_OMEGA"]] = scenario.noise.omega_rad_s
    ud[I["NOISE_FORCE"]] = scenario.noise.force_relative
    ud[I["NOISE_SPEED"]] = scenario.noise.speed_m_s
    seeds = np.random.default_rng(scenario.seed).integers(1, 2**32, size=2)
    ud[I["RNG_STATE0"]], ud[I["RNG_STATE1"]] = float(seeds[0]), float(seeds[1])
    ud[I["LAST_TIME"]] = -1.0
    fs = 1.0 / built.model.opt.timestep
    for prefix, sos, cap in (("WD", wd_weighting_sos(fs), layout.MAX_WD_SECTIONS),
                             ("BAND", band_limiting_sos(fs), layout.MAX_BAND_SECTIONS)):
        if len(sos) > cap:
            raise ValueError(f"{prefix} filter has {len(sos)} sections, the layout holds {cap}")
        coeffs = np.concatenate([row[[0, 1, 2, 4, 5]] for row in sos])
        ud[I[f"{prefix}_SOS_0"]: I[f"{prefix}_SOS_0"] + coeffs.size] = coeffs
        ud[I[f"{prefix}_NSECT"]] = len(sos)
    return ud


def initial_state(built: BuiltModel, speed_m_s: float, qpos: np.ndarray, qvel: np.ndarray) -> None:
    """Nominal geometry (the static equilibrium), every body at ``speed_m_s``, wheels rolling."""
    qpos[:] = built.model.qpos0
    qvel[:] = 0.0
    qvel[built.x_dofs] = speed_m_s
    for dof, radius in built.spin_dofs:
        qvel[dof] = speed_m_s / radius


def dc_torque_at(ud: np.ndarray, t: float) -> float:
    """The DC torque the native drive applies at time t (same ramp as the C code)."""
    dur = ud[I["RAMP_DURATION"]]
    start, target = ud[I["TORQUE_DC_START"]], ud[I["TORQUE_DC_TARGET"]]
    frac = (t - ud[I["RAMP_START_TIME"]]) / dur if dur > 0 else 1.0
    return float(target if frac >= 1 else start if frac <= 0 else start + (target - start) * frac)


def begin_window(ud: np.ndarray, t: float, drive: DriveCommand, ramp_s: float, settle_s: float) -> None:
    """Command a new drive at time ``t`` (DC ramped over ``ramp_s``, modulation phase continuous)
    and restart the accumulators, which sum from ``t + settle_s`` on."""
    ud[I["TORQUE_DC_START"]] = dc_torque_at(ud, t)
    ud[I["TORQUE_DC_TARGET"]] = drive.dc_torque_nm
    ud[I["RAMP_START_TIME"]] = t
    ud[I["RAMP_DURATION"]] = ramp_s
    ud[I["TORQUE_AMPLITUDE"]] = drive.amplitude_nm
    since = t - ud[I["TIME_BASE"]]
    theta = ud[I["THETA_BASE"]] + ud[I["MOD_OMEGA"]] * since
    ud[I["THETA_BASE"]] = math.fmod(theta, 2 * math.pi)
    ud[I["TIME_BASE"]] = t
    ud[I["MOD_OMEGA"]] = 2 * math.pi * drive.frequency_hz
    # further tones: phase continuous as the first (a tone's phase advances while it is unused too)
    extra = drive.extra_tones
    ud[I["N_TONES"]] = 1 + len(extra)
    for k in range(2, MAX_TONES + 1):
        theta_k = ud[I[f"TONE{k}_THETA_BASE"]] + ud[I[f"TONE{k}_OMEGA"]] * since
        ud[I[f"TONE{k}_THETA_BASE"]] = math.fmod(theta_k, 2 * math.pi)
        amp, freq = extra[k - 2] if k - 2 < len(extra) else (0.0, 0.0)
        ud[I[f"TONE{k}_AMPLITUDE"]] = amp
        ud[I[f"TONE{k}_OMEGA"]] = 2 * math.pi * freq
    ud[I["ACC_START_TIME"]] = t + settle_s
    ud[layout.ACC_FIRST: layout.ACC_FIRST + layout.ACC_COUNT] = 0.0


@dataclass(frozen=True)
class WindowMeasurement:
    """What one window measured. Phases in degrees; a positive lag means the wheelset speed lags the
    torque (the paper's phase difference). Forces in N, torques in N m, accelerations in m/s^2."""

    phase_lag_deg: float
    phase_lag_se_deg: float
    amplitude_ratio: float  # wheelset speed amplitude / torque amplitude, rad/s per N m
    torque_amplitude_nm: float
    omega_amplitude_rad_s: float
    creep_phase_lag_deg: float  # phi_v: lag of the creepage behind the wheelset speed
    creepage_amplitude: float
    coa_measured: float  # mean tangential/normal force of the driven wheelset, with sensor noise
    coa_true: float
    creepage_mean: float
    creepage_measured: float  # mean of R omega / v - 1 from the noisy encoder and speed sensor
    speed_measured_m_s: float
    normal_load_n: float
    normal_load_measured_n: float
    tangential_force_n: float
    tangential_force_measured_n: float
    torque_mean_nm: float
    torque_peak_nm: float
    wd_rms_m_s2: float  # ISO 2631-1 Wd-weighted RMS car-body longitudinal acceleration (whole window)
    jerk_rms_m_s3: float
    wd_peak_m_s2: float
    friction_energy_j: float
    time_past_peak_s: float
    energy_past_peak_j: float
    max_abs_creepage: float
    samples: int
    # per tone k = 1...MAX_TONES (tone 1 the DriveCommand's own sine; tones beyond n_tones: lag 0, SE 180,
    # ratio 0). With extra tones the fields above (phase lag, its SE, the amplitudes and their ratio, the
    # creepage's lag and amplitude) are tone 1's from the joint fit; a single tone fills tone 1 with them.
    n_tones: int = 1
    tone1_phase_lag_deg: float = 0.0
    tone1_phase_lag_se_deg: float = NO_SE_DEG
    tone1_amplitude_ratio: float = 0.0  # rad/s per N m
    tone1_torque_amplitude_nm: float = 0.0
    tone1_omega_amplitude_rad_s: float = 0.0
    tone2_phase_lag_deg: float = 0.0
    tone2_phase_lag_se_deg: float = NO_SE_DEG
    tone2_amplitude_ratio: float = 0.0
    tone2_torque_amplitude_nm: float = 0.0
    tone2_omega_amplitude_rad_s: float = 0.0
    tone3_phase_lag_deg: float = 0.0
    tone3_phase_lag_se_deg: float = NO_SE_DEG
    tone3_amplitude_ratio: float = 0.0
    tone3_torque_amplitude_nm: float = 0.0
    tone3_omega_amplitude_rad_s: float = 0.0
    # the measured creepage's modulation at tone 1 (a sensor reading: R omega / v - 1 from the noisy encoder
    # and speed sensor, the creepage's systematic offset gone with its DC level, its scale error kept):
    # its amplitude, its lag behind the torque (deg) and that lag's standard error (180: not modulated)
    creepage_modulation_amplitude: float = 0.0
    creepage_modulation_lag_deg: float = 0.0
    creepage_modulation_lag_se_deg: float = NO_SE_DEG
    # the measured CoA's synchronous average over tone 1's cycle (PHASE_BINS phase bins, each averaged over
    # the window's cycles): its largest and smallest bin means (the crest and trough of the adhesion the
    # force sensors read) and the standard error of one bin's mean
    coa_cycle_max: float = 0.0
    coa_cycle_min: float = 0.0
    coa_cycle_bin_se: float = 0.0
    # the lag's SE with the speed fit's residual taken as first-order autoregressive instead of white (its lag-1
    # correlation read from the window: a smoothed speed signal's residual is correlated, and the white SE then
    # understates the scatter of the lag several times); single-tone windows only (180 with extra tones)
    phase_lag_se_corrected_deg: float = NO_SE_DEG
    # the rotation lock-in's reading of the speed's ripple at the wheelset's rotation frequency (a target wheel's
    # runout, cof_gym.physics.encoder): the first harmonic's amplitude (rad/s) and its phase's standard error (deg;
    # a clear ripple reads a small one); 0 and 180 where it is not fitted (the plain lock-in, or a harmonic the
    # window cannot tell from a tone, left out)
    rotation_ripple_rad_s: float = 0.0
    rotation_ripple_phase_se_deg: float = NO_SE_DEG


# the measured CoA's synchronous-average fields of WindowMeasurement, in CycleExtremes' order
COA_CYCLE_FIELDS = ("coa_cycle_max", "coa_cycle_min", "coa_cycle_bin_se")
TONE_FIELDS = ("phase_lag_deg", "phase_lag_se_deg", "amplitude_ratio", "torque_amplitude_nm", "omega_amplitude_rad_s")


def tone_field(k: int, name: str) -> str:
    """The :class:`WindowMeasurement` field of tone ``k`` (1-based): ``tone_field(2, "phase_lag_deg")``."""
    return f"tone{k}_{name}"


def _fit(ud: np.ndarray, btb: str, bty: str, yty: str, n: float):
    b0, y0 = I[f"{btb}_0"], I[f"{bty}_0"]
    return fit_from_sums(ud[b0:b0 + 10], ud[y0:y0 + 4], ud[I[yty]], n)


def _tone_fits(ud: np.ndarray, n: float, size: int,
               columns: list[int] | None = None) -> tuple[tuple[SineFit, ...], ...]:
    """The joint fits (torque, omega, creepage, measured creepage) over the window's ``size`` columns, or over the
    ``columns`` of them kept (pairs, then the offset and drift: :func:`_rotation_columns`), one SineFit per pair
    each."""
    packed = size * (size + 1) // 2
    out = []
    for btb, bty, yty in (("MT_BTB_TORQUE", "MT_BTY_TORQUE", "YTY_TORQUE"), ("MT_BTB_STATE", "MT_BTY_OMEGA", "YTY_OMEGA"),
                          ("MT_BTB_STATE", "MT_BTY_CREEP", "YTY_CREEP"),
                          ("MT_BTB_STATE", "MT_BTY_CREEP_MEASURED", "YTY_CREEP_MEASURED")):
        b0, y0 = I[f"{btb}_0"], I[f"{bty}_0"]
        sums, products = _kept(ud[b0:b0 + packed], ud[y0:y0 + size], size, columns)
        out.append(fit_tones_from_sums(sums, products, ud[I[yty]], n, len(products) // 2 - 1))
    return tuple(out)


def _kept(sums: np.ndarray, products: np.ndarray, size: int,
          columns: list[int] | None) -> tuple[np.ndarray, np.ndarray]:
    """A fit's packed B'B and its B'y over ``size`` columns, reduced to the ``columns`` kept (None: all, as given)."""
    if columns is None:
        return sums, products
    kept = unpack_symmetric(sums, size)[np.ix_(columns, columns)]
    return kept[np.triu_indices(len(columns))], products[columns]


# a rotation harmonic whose pair would raise a tone's coefficient variance more than this many times (it shares more
# than half of the tone's information over the window: its frequency within about 0.44 / span of the tone's) is left
# out of the rotation lock-in's fit, which cannot tell the two apart there; its ripple then leaks into the tone as it
# does into the plain lock-in's
MAX_ROTATION_INFLATION = 2.0


def _rotation_columns(ud: np.ndarray, ntones: int, size: int) -> list[int]:
    """The rotation lock-in's columns kept of its ``size``: every tone's pair, each rotation harmonic's pair that
    raises no tone's coefficient variance more than :data:`MAX_ROTATION_INFLATION` times (from the speed basis's
    sums), the offset and the drift."""
    a = unpack_symmetric(ud[I["MT_BTB_STATE_0"]: I["MT_BTB_STATE_0"] + size * (size + 1) // 2], size)
    tones, tail = list(range(2 * ntones)), [size - 2, size - 1]

    def tone_variances(cols: list[int]) -> np.ndarray:
        return np.diag(coefficient_covariance(a[np.ix_(cols, cols)]))[:2 * ntones]

    base = tone_variances(tones + tail)
    kept = [[2 * ntones + 2 * h, 2 * ntones + 2 * h + 1] for h in range(layout.ROTATION_BASIS // 2)]
    kept = [pair for pair in kept if np.all(tone_variances(tones + pair + tail) <= MAX_ROTATION_INFLATION * base)]
    return tones + [c for pair in kept for c in pair] + tail


def _lag(torque: SineFit, omega: SineFit, commanded: bool) -> tuple[float, float, float]:
    """(lag of omega behind torque deg, its SE deg (<= 180), amplitude ratio) of one tone."""
    if not (commanded and torque.amplitude > 1e-9):
        return 0.0, NO_SE_DEG, 0.0
    lag = wrap_deg(math.degrees(torque.phase_rad - omega.phase_rad))
    lag_se = min(math.degrees(math.hypot(torque.phase_se_rad, omega.phase_se_rad)), NO_SE_DEG)
    return lag, lag_se, omega.amplitude / torque.amplitude


def _coa_cycle(ud: np.ndarray) -> dict[str, float]:
    """The measured CoA's synchronous-average fields of :class:`WindowMeasurement`."""
    bins = [ud[I[f"{name}_0"]: I[f"{name}_0"] + layout.PHASE_BINS] for name in ("COA_BIN_N", "COA_BIN_SUM", "COA_BIN_SUM2")]
    extremes = cycle_extremes(*bins)
    return dict(zip(COA_CYCLE_FIELDS, (extremes.maximum, extremes.minimum, extremes.bin_se)))


def _joint_tones(ud: np.ndarray, n: float, ntones: int, size: int,
                 columns: list[int] | None) -> tuple[dict[str, float], tuple]:
    """A joint fit's per-tone readings (phase lag, its SE, amplitude ratio, torque and speed amplitudes, keyed by
    :func:`tone_field`) from the joint fit of every tone over ``size`` columns or the ``columns`` kept of them (with
    the rotation lock-in, its harmonics' pairs after the tones', read as further tones and left out, but for the
    first harmonic's ripple in the speed: :func:`_rotation_ripple`), and tone 1's fits of the torque, the speed,
    the creepage and the measured creepage."""
    if n <= size + 4:
        raise ValueError(f"window too short: {n:g} samples for {ntones} tones; lengthen the window")
    t_fits, o_fits, c_fits, cm_fits = _tone_fits(ud, n, size, columns)
    commanded = [ud[I["TORQUE_AMPLITUDE"]] > 0.0] + [ud[I[f"TONE{k}_AMPLITUDE"]] > 0.0 for k in range(2, ntones + 1)]
    tones: dict[str, float] = {}
    for k in range(1, ntones + 1):
        lag_k, se_k, ratio_k = _lag(t_fits[k - 1], o_fits[k - 1], commanded[k - 1])
        tones.update({tone_field(k, "phase_lag_deg"): lag_k, tone_field(k, "phase_lag_se_deg"): se_k,
                      tone_field(k, "amplitude_ratio"): ratio_k,
                      tone_field(k, "torque_amplitude_nm"): t_fits[k - 1].amplitude,
                      tone_field(k, "omega_amplitude_rad_s"): o_fits[k - 1].amplitude})
    if columns is not None:
        tones.update(_rotation_ripple(o_fits, ntones, columns))
    return tones, (t_fits[0], o_fits[0], c_fits[0], cm_fits[0])


def _rotation_ripple(o_fits: tuple[SineFit, ...], ntones: int, columns: list[int]) -> dict[str, float]:
    """The first rotation harmonic's ripple in the speed (:class:`WindowMeasurement`'s ``rotation_ripple_*``) from
    the rotation lock-in's joint speed fit, whose pairs are the tones' and then the harmonics' kept in ``columns``
    (the first harmonic's, if kept, first among them); none where it was left out."""
    if 2 * ntones not in columns:
        return {}
    ripple = o_fits[ntones]
    return {"rotation_ripple_rad_s": ripple.amplitude,
            "rotation_ripple_phase_se_deg": min(math.degrees(ripple.phase_se_rad), NO_SE_DEG)}


def _lag_se_corrected(ud: np.ndarray, n: float, torque: SineFit, omega: SineFit, joint_size: int = 0,
                      columns: list[int] | None = None) -> float:
    """Tone 1's lag SE (deg) with the speed fit's SE scaled by
    :func:`~cof_gym.measurement.sine_fit.colored_noise_factor` of its residual's lag-1 correlation: the single-tone
    fit's, or the rotation lock-in's joint fit's over ``joint_size`` columns (its ``columns`` kept)."""
    size, btb, bty, lag1 = (joint_size, "MT_BTB_STATE", "MT_BTY_OMEGA", "MT_LAG1") if joint_size else (
        4, "BTB_STATE", "BTY_OMEGA", "LAG1")
    b0, y0 = I[f"{btb}_0"], I[f"{bty}_0"]
    sums, products = _kept(ud[b0:b0 + size * (size + 1) // 2], ud[y0:y0 + size], size, columns)
    by, py = ud[I[f"{lag1}_BY_0"]: I[f"{lag1}_BY_0"] + size], ud[I[f"{lag1}_PY_0"]: I[f"{lag1}_PY_0"] + size]
    cross = ud[I[f"{lag1}_BB_0"]: I[f"{lag1}_BB_0"] + size * size]
    if columns is not None:
        by, py, cross = by[columns], py[columns], np.reshape(cross, (size, size))[np.ix_(columns, columns)].ravel()
    rho = lag1_correlation(sums, products, ud[I["YTY_OMEGA"]], n, ud[I["LAG1_YY"]], by, py, cross,
                           omega.coefficients)
    factor = colored_noise_factor(rho, ud[I["MOD_OMEGA"]] * ud[I["TIMESTEP_S"]])
    return _lag(torque, replace(omega, phase_se_rad=omega.phase_se_rad * factor), True)[1]


def read_window(ud: np.ndarray) -> WindowMeasurement:
    """The window's measurement from the accumulated sums (once per window, in Python)."""
    n = float(ud[I["N_SAMPLES"]])
    if n <= 8:
        raise ValueError(f"window too short: {n:g} samples accumulated (need > 8); lengthen the window")
    torque = _fit(ud, "BTB_TORQUE", "BTY_TORQUE", "YTY_TORQUE", n)
    omega = _fit(ud, "BTB_STATE", "BTY_OMEGA", "YTY_OMEGA", n)
    creep = _fit(ud, "BTB_STATE", "BTY_CREEP", "YTY_CREEP", n)
    creep_measured = _fit(ud, "BTB_STATE", "BTY_CREEP_MEASURED", "YTY_CREEP_MEASURED", n)
    ntones = min(max(int(ud[I["N_TONES"]]), 1), MAX_TONES)
    rotation = bool(ud[I["LOCK_IN_ROTATION"]] > 0.0)
    tones: dict[str, float] = {}
    if ntones > 1 or rotation:  # every tone from the joint fit, tone 1's replacing the single-tone fit (leaked into)
        size = 2 * ntones + (layout.ROTATION_BASIS if rotation else 0) + 2
        columns = _rotation_columns(ud, ntones, size) if rotation else None
        tones, (torque, omega, creep, creep_measured) = _joint_tones(ud, n, ntones, size, columns)
        lag, lag_se, ratio = (tones[tone_field(1, f)] for f in ("phase_lag_deg", "phase_lag_se_deg", "amplitude_ratio"))
        # the rotation lock-in keeps the lag-1 sums of its joint fit's residual; several tones keep none (their
        # agents were fitted on the SE of no information)
        lag_se_corrected = (_lag_se_corrected(ud, n, torque, omega, size, columns) if rotation and ntones == 1
                            else NO_SE_DEG)
    else:
        lag, lag_se, ratio = _lag(torque, omega, True)
        lag_se_corrected = _lag_se_corrected(ud, n, torque, omega)
    creep_lag, creep_lag_se, _ = _lag(torque, creep_measured, torque.amplitude > 1e-9)
    mean = lambda key: float(ud[I[key]] / n)  # noqa: E731
    dt_energy = lambda key: float(ud[I[key]])  # noqa: E731
    return WindowMeasurement(
        phase_lag_deg=lag,
        phase_lag_se_deg=lag_se,
        phase_lag_se_corrected_deg=lag_se_corrected,
        amplitude_ratio=ratio,
        torque_amplitude_nm=torque.amplitude,
        omega_amplitude_rad_s=omega.amplitude,
        creep_phase_lag_deg=wrap_deg(math.degrees(omega.phase_rad - creep.phase_rad)),
        creepage_amplitude=creep.amplitude,
        coa_measured=mean("SUM_COA_MEASURED"),
        coa_true=mean("SUM_COA_TRUE"),
        creepage_mean=mean("SUM_CREEPAGE"),
        creepage_measured=mean("SUM_CREEPAGE_MEASURED"),
        speed_measured_m_s=mean("SUM_SPEED_MEASURED"),
        normal_load_n=mean("SUM_NORMAL"),
        normal_load_measured_n=mean("SUM_NORMAL_MEASURED"),
        tangential_force_n=mean("SUM_TANGENTIAL"),
        tangential_force_measured_n=mean("SUM_TANGENTIAL_MEASURED"),
        torque_mean_nm=mean("SUM_TORQUE"),
        torque_peak_nm=float(ud[I["MAX_ABS_TORQUE"]]),
        wd_rms_m_s2=math.sqrt(ud[I["SUM_WD2"]] / max(ud[I["N_COMFORT_SAMPLES"]], 1.0)),
        jerk_rms_m_s3=math.sqrt(ud[I["SUM_JERK2"]] / max(ud[I["N_COMFORT_SAMPLES"]], 1.0)),
        wd_peak_m_s2=float(ud[I["MAX_ABS_WD"]]),
        friction_energy_j=dt_energy("FRICTION_ENERGY"),
        time_past_peak_s=dt_energy("TIME_PAST_PEAK"),
        energy_past_peak_j=dt_energy("ENERGY_PAST_PEAK"),
        max_abs_creepage=float(ud[I["MAX_ABS_CREEPAGE"]]),
        samples=int(n),
        creepage_modulation_amplitude=creep_measured.amplitude,
        creepage_modulation_lag_deg=creep_lag,
        creepage_modulation_lag_se_deg=creep_lag_se,
        **_coa_cycle(ud),
        n_tones=ntones,
        **(tones or {"tone1_phase_lag_deg": lag, "tone1_phase_lag_se_deg": lag_se,
                     "tone1_amplitude_ratio": ratio,
                     "tone1_torque_amplitude_nm": torque.amplitude, "tone1_omega_amplitude_rad_s": omega.amplitude}),
    )


def state_is_finite(qpos: np.ndarray, qvel: np.ndarray, ud: np.ndarray) -> bool:
    return bool(np.isfinite(qpos).all() and np.isfinite(qvel).all() and np.isfinite(ud).all())


class SimulationDiverged(RuntimeError):
    """The simulation blew up during a window (MuJoCo's bad position/velocity/acceleration warnings,
    after which MuJoCo resets the data)."""


_DIVERGENCE_WARNINGS = (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL,
                        mujoco.mjtWarning.mjWARN_BADQACC)


class Simulation:
    """One model and one ``MjData`` stepped window by window."""

    def __init__(self, built: BuiltModel) -> None:
        install_callback()
        self.built = built
        self.model = built.model
        self.data = mujoco.MjData(self.model)
        self.scenario: Scenario | None = None

    @property
    def timestep(self) -> float:
        return float(self.model.opt.timestep)

    def reset(self, scenario: Scenario) -> None:
        install_callback()  # idempotent: back in place if anything replaced the process-global callback since
        mujoco.mj_resetData(self.model, self.data)
        initial_state(self.built, scenario.op.speed_m_s, self.data.qpos, self.data.qvel)
        self.data.userdata[:] = initial_userdata(self.built, scenario)
        self.scenario = scenario
        mujoco.mj_forward(self.model, self.data)

    def run_window(self, drive: DriveCommand, duration_s: float, settle_s: float = 0.0,
                   ramp_s: float = 0.0) -> WindowMeasurement:
        """Command ``drive``, step ``duration_s`` in one native call, return the measurement of the
        part after ``settle_s``."""
        if self.scenario is None:
            raise RuntimeError("call reset() before run_window()")
        if not (0.0 <= settle_s < duration_s):
            raise ValueError(f"settle_s must be in [0, duration_s={duration_s}), got {settle_s!r}")
        install_callback()
        begin_window(self.data.userdata, self.data.time, drive, ramp_s, settle_s)
        nstep = int(round(duration_s / self.timestep))
        mujoco.mj_step(self.model, self.data, nstep)
        bad = [w.name for w in _DIVERGENCE_WARNINGS if self.data.warning[w].number > 0]
        if bad:
            raise SimulationDiverged(f"simulation diverged at t = {self.data.time:.3f} s (MuJoCo {', '.join(bad)})")
        return read_window(self.data.userdata)

    def is_finite(self) -> bool:
        return state_is_finite(self.data.qpos, self.data.qvel, self.data.userdata)
