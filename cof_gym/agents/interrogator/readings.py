"""One window's sensor readings as the learned interrogator reads them (:class:`Reading`), and the creep
curve's local slope from Eq. 3's phase lag and from the compliance."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Mapping

import numpy as np

from cof_gym.agents.runaway import crest_lower_bound
from cof_gym.measurement.sine_fit import NO_SE_DEG, SMOOTHED_NOISE_COLOUR, noise_colour
from cof_gym.physics.simulation import COA_CYCLE_FIELDS
from cof_gym.task.interface import OBSERVATION_NAMES, PHASE_SCALE_DEG, MotorLimits, window_reading
from cof_gym.task.scenarios import ScenarioRanges
from cof_gym.task.sensors import SYSTEMATIC_ERRORS
from cof_gym.validation import check_number

_INDEX = {name: OBSERVATION_NAMES.index(name) for name in OBSERVATION_NAMES}
PHASE_CLIP_DEG = (1.0, 89.0)  # the slope index ln cot(phase) is finite within these
SE_CLIP_DEG = 30.0
SE_REPORTED_MAX_DEG = NO_SE_DEG  # the lock-in's standard error of no information (pi)
NOISE_WINDOWS = 3  # the climb's first driven windows whose lock-in noise (Reading.lockin_noise_nms) it follows
# the sensor note of a climb whose first windows read a noise colour above SMOOTHED_NOISE_COLOUR
# (LearnedInterrogator.sensor_notes, reads_smoothed_encoder)
SMOOTHED_ENCODER = "smoothed encoder"
# the lock-in noise (first_windows_noise_nms from the reported SEs, N m s) below which a climb's noise colour reads the
# wheel's own residual rather than the sensor's noise: the least 0.001 step under every sharp-encoder training
# climb's (at least 0.0015, experiments/noise_colour_reading.py), about six times the noiseless paper setting's
# (at most 1.7e-4 over its 60 episodes; session 65)
COLOUR_NOISE_FLOOR_NMS = 1e-3
# the sensor note of a climb whose first windows read more noise than the v2 draws give (LearnedInterrogator.noisy,
# the interval's noisy class)
NOISY_SENSORS = "noisy sensors"
# the sensor note of a climb whose first windows read a drive slower than any the networks were fitted on
# (LearnedInterrogator.sensor_notes, reads_slow_drive)
SLOW_DRIVE = "slow drive"
# the drive lag (s, first_windows_drive_lag_s) above which a climb reads a drive slower than the v2 draws' slowest
# (ScenarioRanges().motor_lag_s, 0.03 s): that lag with 10 ms for the reading's spread, which lay within -3.3 and
# +3.2 ms of the truth on 360 climbs with drives of 20 and 30 ms and the sensors as the draws give them (session 69,
# docs/interrogator.md, rule 133)
SLOW_DRIVE_LAG_S = ScenarioRanges().motor_lag_s[1] + 0.01
COMPLIANCE_CLIP = (1e-3, 0.999)  # the slope from the compliance, sqrt(1 / C^2 - 1), is finite within these


def _gain_range(torque: float, force: float) -> tuple[float, float]:
    """The torque-over-force gain ratios ``(1 + e_T) / (1 + e_F)`` that systematic errors within +-``torque`` and
    +-``force`` can give."""
    return (1.0 - torque) / (1.0 + force), (1.0 + torque) / (1.0 - force)


# the torque balance's ratios the env's systematic errors can give (what cof_gym.task.sensors accepts)
TORQUE_BALANCE_RANGE = _gain_range(SYSTEMATIC_ERRORS["torque_gain_error"].accepted,
                                   SYSTEMATIC_ERRORS["force_gain_error"].accepted)


def torque_balance_ratio(measurement: Mapping[str, Any], wheel_radius_m: float) -> float:
    """One window's torque balance: its mean torque reading over the measured tangential force times the wheel
    radius (0 where the window measured no force). On a wheelset at a steady creepage (no mean spin acceleration)
    the drive torque equals the creep force times the radius, so the ratio is ``(1 + e_T) / (1 + e_F)`` (torque and
    force gain errors)."""
    force_nm = float(measurement.get("tangential_force_measured_n", 0.0)) * wheel_radius_m
    if not force_nm > 0.0:
        return 0.0
    return float(measurement.get("torque_mean_nm", 0.0)) / force_nm


def gain_from_balance(ratio: float) -> float:
    """The torque channel's gain against the force channel that a window's torque balance ``ratio``
    (:func:`torque_balance_ratio`) reads: the ratio itself where the accepted errors allow it
    (:data:`TORQUE_BALANCE_RANGE`), else 1 (no calibration: no force, or a wheel still accelerating). Read in a
    climb's first window, far below the peak, it calibrates every later torque reading to the force channel's
    accuracy."""
    return ratio if TORQUE_BALANCE_RANGE[0] <= ratio <= TORQUE_BALANCE_RANGE[1] else 1.0


def torque_balance_gain(measurement: Mapping[str, Any], wheel_radius_m: float) -> float:
    """The gain one window's torque balance reads (:func:`gain_from_balance` of :func:`torque_balance_ratio`)."""
    return gain_from_balance(torque_balance_ratio(measurement, wheel_radius_m))


def _se_clipped(se_deg: float) -> float:
    """A lag's standard error (deg) as the filter reads it: :data:`SE_CLIP_DEG` where it is not in (0, that)."""
    return se_deg if 0.0 < se_deg < SE_CLIP_DEG else SE_CLIP_DEG


def _se_reported(se_deg: float) -> float:
    """A lag's standard error (deg) as the lock-in reported it, within [0, :data:`SE_REPORTED_MAX_DEG`]."""
    return min(max(se_deg, 0.0), SE_REPORTED_MAX_DEG)


def tan_clipped(phase_deg: float) -> float:
    """``tan(phase)`` with the phase clipped to :data:`PHASE_CLIP_DEG` (finite and > 0)."""
    return math.tan(math.radians(min(max(phase_deg, PHASE_CLIP_DEG[0]), PHASE_CLIP_DEG[1])))


def slope_index(phase_deg: float) -> float:
    """``ln cot(phase)``: the log of the creep curve's local slope in units of the wheel's inertial
    impedance (Eq. 3 of the paper for the half wheelset); falls towards -inf as the phase nears 90 deg."""
    return math.log(1.0 / tan_clipped(phase_deg))


def slope_from_phase(r: "Reading") -> float:
    """The creep curve's local slope up to a constant of the episode, ``f cot(phase)`` (Hz): Eq. 3 gives
    ``cot(phase) = k r^2 / (I w v)`` for a wheel on a creep curve of slope ``k``."""
    return r.frequency_hz / tan_clipped(r.phase_deg)


def slope_from_compliance(r: "Reading") -> float:
    """The same slope from the speed/torque amplitude ratio ``C = I w |speed / torque|``:
    ``f sqrt(1 / C^2 - 1)`` (the torque gain error scales it; the phase does not see that error)."""
    c = min(max(r.compliance, COMPLIANCE_CLIP[0]), COMPLIANCE_CLIP[1])
    return r.frequency_hz * math.sqrt(1.0 / c**2 - 1.0)


@dataclass(frozen=True)
class Reading:
    """One driven window as the filter sees it (deg, N m, Hz, m/s; CoA and load ratio dimensionless)."""

    phase_deg: float
    se_deg: float
    compliance: float
    coa: float
    creepage: float  # as measured (with the sensors' offset): used only in differences
    dc_nm: float
    amplitude_nm: float
    frequency_hz: float
    speed_m_s: float
    normal_load: float
    tone2_phase_deg: float = 0.0  # the second tone's lock-in (a two-tone excitation); 0 Hz: none
    tone2_se_deg: float = SE_CLIP_DEG
    tone2_compliance: float = 0.0
    tone2_frequency_hz: float = 0.0
    tone2_amplitude_nm: float = 0.0
    creepage_modulation: float = 0.0  # the measured creepage's amplitude at the modulation (0: not read)
    creepage_modulation_lag_deg: float = 0.0  # its lag behind the torque
    creepage_modulation_se_deg: float = SE_CLIP_DEG
    coa_cycle_max: float = 0.0  # the crest of the measured CoA's synchronous average over the cycle (0: not read)
    coa_cycle_bin_se: float = 0.0  # the standard error of one of its phase bins
    coa_cycle_min: float = 0.0  # the trough of that synchronous average
    # the lag's standard error as the lock-in reports it (deg, up to 180: not clipped at SE_CLIP_DEG; 0: not read)
    se_reported_deg: float = 0.0
    # the modulation's amplitude the drive's torque reading measured (N m, the torque gain error included; 0: not
    # read): what the drive applied, a lag's attenuation included, where ``amplitude_nm`` is what it was asked for
    torque_amplitude_measured_nm: float = 0.0
    # the window's torque balance (torque_balance_ratio: its mean torque reading over the measured force times the
    # wheel radius; 0: not read), which a climb with ClimbParameters.torque_balance calibrates its torque readings by
    torque_balance: float = 0.0
    # the lag's standard error for a first-order autoregressive residual (the lock-in's ``phase_lag_se_corrected_deg``,
    # deg; 0: not read, as in a multi-tone window): over se_reported_deg, how correlated the speed residual is
    se_corrected_deg: float = 0.0

    @property
    def noise_colour(self) -> float:
        """How many times the speed residual's correlation widens the lag's standard error
        (:attr:`se_corrected_deg` over :attr:`se_reported_deg`:
        :func:`~cof_gym.measurement.sine_fit.colored_noise_factor` of the residual's lag-1 correlation): about 1 for
        the white noise of a sharp encoder, several times that for a smoothed one (its lag correlates successive
        samples); 0 where either was not read."""
        return noise_colour(self.se_reported_deg, self.se_corrected_deg)

    @property
    def crest_bound(self) -> float:
        """A lower bound on the CoF from this window: its CoA's cycle crest less one bin's standard error
        (:func:`~cof_gym.agents.runaway.crest_lower_bound`; 0 when the crest was not read)."""
        return crest_lower_bound(self.coa_cycle_max, self.coa_cycle_bin_se)

    @property
    def lockin_noise_nms(self) -> float:
        """The wheel-speed noise this window's lock-in fit reads, as angular momentum (N m s): the phase's
        standard error (rad) times the response amplitude ``compliance x amplitude / (2 pi f)``, the
        wheelset's inertia times the speed amplitude (``compliance`` is that amplitude over the torque's,
        times ``I w``). A least-squares sine fit's phase error is the residual noise over the amplitude times
        ``sqrt(2 / samples)`` (IEEE Std 1057), so this is ``I x sigma_w x sqrt(2 / samples)``: it follows the
        speed sensor's noise ``sigma_w`` and not the operating point. ``amplitude`` is the commanded modulation:
        a drive that applies less of it (a lag) reads as that much more noise, as the fit's signal-to-noise ratio
        has it (:meth:`lockin_noise` can read it from the applied amplitude instead). A clipped standard error
        reads low (:attr:`lockin_noise_reported_nms` does not clip it)."""
        return self.lockin_noise()

    @property
    def lockin_noise_reported_nms(self) -> float:
        """:attr:`lockin_noise_nms` from the standard error the lock-in reports (:attr:`se_reported_deg`, up to
        180 deg) rather than the filter's clipped one: ``sigma_w sqrt(2 / samples)`` over the fitted amplitude
        times that amplitude, so a window whose fit is poor reads its noise as well as one whose fit is good
        (from the clipped one where it was not read)."""
        return self.lockin_noise(reported=True)

    def lockin_noise(self, reported: bool = False, measured_torque: bool = False) -> float:
        """The lock-in noise (N m s): :attr:`lockin_noise_nms`, or with ``reported``
        :attr:`lockin_noise_reported_nms`; with ``measured_torque`` the response amplitude from the torque the
        drive measured (:attr:`torque_amplitude_measured_nm`, where read) rather than the commanded one. The
        compliance is the speed amplitude over that same measured torque amplitude (times ``I w``), so the
        response is then the wheelset's inertia times its measured speed amplitude exactly: neither a drive lag
        nor the torque gain error changes the reading, only the speed sensor's noise does."""
        se_deg = self.se_reported_deg if reported and self.se_reported_deg > 0.0 else self.se_deg
        measured = measured_torque and self.torque_amplitude_measured_nm > 0.0
        amplitude_nm = self.torque_amplitude_measured_nm if measured else self.amplitude_nm
        return math.radians(se_deg) * self.compliance * amplitude_nm / (2.0 * math.pi * self.frequency_hz)

    @classmethod
    def of(cls, observation: np.ndarray, limits: MotorLimits, info: Mapping[str, Any] | None = None) -> "Reading":
        """The window observation's reading; with a two-tone excitation (the observation's per-tone block
        after the window observation) also tone 2's, its applied frequency and amplitude from
        ``info["measurement"]``, and from there the measured creepage's modulation (its lock-in) and the
        crest of the measured CoA's synchronous average."""
        full = np.nan_to_num(np.asarray(observation, dtype=np.float64), nan=0.0)
        o = full[: len(OBSERVATION_NAMES)]
        se_deg = window_reading(o, "phase_lag_se")
        tone2 = {}
        measurement = (info or {}).get("measurement", {})
        if len(full) >= len(OBSERVATION_NAMES) + 6 and "tone2_frequency_hz" in measurement:
            phase2, se2, compliance2 = full[len(OBSERVATION_NAMES) + 3: len(OBSERVATION_NAMES) + 6]
            tone2 = {"tone2_phase_deg": float(phase2 * PHASE_SCALE_DEG),
                     "tone2_se_deg": float(_se_clipped(se2 * PHASE_SCALE_DEG)),
                     "tone2_compliance": float(compliance2),
                     "tone2_frequency_hz": float(measurement["tone2_frequency_hz"]),
                     "tone2_amplitude_nm": float(measurement["tone2_amplitude_nm"])}
        if "creepage_modulation_amplitude" in measurement:
            tone2.update(creepage_modulation=float(measurement["creepage_modulation_amplitude"]),
                         creepage_modulation_lag_deg=float(measurement["creepage_modulation_lag_deg"]),
                         creepage_modulation_se_deg=float(_se_clipped(measurement["creepage_modulation_lag_se_deg"])))
        if "coa_cycle_max" in measurement:  # the same names as the sensor fields
            tone2.update({name: float(measurement[name]) for name in COA_CYCLE_FIELDS})
        if "torque_amplitude_nm" in measurement:
            tone2["torque_amplitude_measured_nm"] = float(measurement["torque_amplitude_nm"])
        if "torque_mean_nm" in measurement:
            tone2["torque_balance"] = torque_balance_ratio(measurement, limits.wheel_radius_m)
        if "phase_lag_se_corrected_deg" in measurement:
            tone2["se_corrected_deg"] = _se_reported(float(measurement["phase_lag_se_corrected_deg"]))
        return cls(
            phase_deg=window_reading(o, "phase_lag"),
            se_deg=float(_se_clipped(se_deg)),
            se_reported_deg=_se_reported(float(se_deg)),
            compliance=window_reading(o, "compliance"),
            coa=max(window_reading(o, "coa_measured"), 1e-4),
            creepage=window_reading(o, "creepage_measured"),
            dc_nm=window_reading(o, "dc_torque", limits),
            amplitude_nm=window_reading(o, "amplitude", limits),
            frequency_hz=window_reading(o, "frequency", limits),
            speed_m_s=window_reading(o, "speed"),
            normal_load=float(o[_INDEX["normal_load"]]),
            **tone2,
        )

    def calibrated(self, torque_gain: float) -> "Reading":
        """This window with its torque readings divided by ``torque_gain`` (:func:`gain_from_balance`): the
        compliances (speed over torque amplitude) times it, the measured torque amplitude and the torque balance
        over it."""
        return replace(self, compliance=self.compliance * torque_gain, tone2_compliance=self.tone2_compliance * torque_gain,
                       torque_amplitude_measured_nm=self.torque_amplitude_measured_nm / torque_gain,
                       torque_balance=self.torque_balance / torque_gain)

    def tone2(self) -> "Reading":
        """This window as tone 2 alone sees it (its phase, SE, compliance and frequency in tone 1's place)."""
        return replace(self, phase_deg=self.tone2_phase_deg, se_deg=self.tone2_se_deg,
                       compliance=self.tone2_compliance, frequency_hz=self.tone2_frequency_hz)


def first_windows_noise_nms(readings: list[Reading], reported: bool = False, measured_torque: bool = False) -> float:
    """The noise a climb reads from its first :data:`NOISE_WINDOWS` driven ``readings`` (N m s): the median of their
    :meth:`Reading.lockin_noise` (with ``reported`` from the lock-in's reported standard errors, with
    ``measured_torque`` at the torque amplitude the drive measured)."""
    return float(np.median([r.lockin_noise(reported, measured_torque) for r in readings[:NOISE_WINDOWS]]))


def first_windows_noise_colour(readings: list[Reading]) -> float:
    """The noise colour a climb reads from its first :data:`NOISE_WINDOWS` driven ``readings``: the least of
    their :attr:`Reading.noise_colour` where read (0 where none was: a multi-tone climb, or none driven yet). A
    smoothing colours every window's noise; the wheel's own departures from a sine (harmonics near the peak,
    transients) colour the residual only where the modulation's response stands far above the noise, which the
    climb's first window, at its smallest modulation, does not reach: the least is the smoothing's."""
    colours = [c for c in (r.noise_colour for r in readings[:NOISE_WINDOWS]) if c > 0.0]
    return float(np.min(colours)) if colours else 0.0


def drive_lag_s(applied_fraction: float, frequency_hz: float) -> float:
    """The time constant (s) of a first-order drive that applies ``applied_fraction`` of a modulation commanded at
    ``frequency_hz``: ``sqrt(1 / a^2 - 1) / (2 pi f)`` from its gain ``a = 1 / sqrt(1 + (2 pi f tau)^2)``; 0 where
    it applies all of it or more (a torque reading's gain error or noise), ValueError where the fraction is not a
    positive finite number or the frequency not positive."""
    check_number("applied_fraction", applied_fraction, 0.0, math.inf, low_open=True)
    check_number("frequency_hz", frequency_hz, 0.0, math.inf, low_open=True, unit=" Hz")
    return math.sqrt(max(applied_fraction ** -2 - 1.0, 0.0)) / (2.0 * math.pi * frequency_hz)


def first_windows_drive_lag_s(applied_fractions: list[float], frequency_hz: float) -> float:
    """The drive's time constant (s) a climb reads from its first :data:`NOISE_WINDOWS` driven windows: the
    :func:`drive_lag_s` of the median fraction of the commanded modulation their torque readings measured
    (``applied_fractions``, calibrated as the climb calibrates its torque readings); 0 where none was measured."""
    fractions = applied_fractions[:NOISE_WINDOWS]
    return drive_lag_s(float(np.median(fractions)), frequency_hz) if fractions else 0.0


def reads_slow_drive(applied_fractions: list[float], frequency_hz: float) -> bool:
    """Whether a climb's first driven windows, which measured these ``applied_fractions`` of the modulation commanded
    at ``frequency_hz``, read a drive slower than the v2 draws give (:func:`first_windows_drive_lag_s` above
    :data:`SLOW_DRIVE_LAG_S`): a slow drive applies less of the modulation, later, than any training climb's did."""
    return first_windows_drive_lag_s(applied_fractions, frequency_hz) > SLOW_DRIVE_LAG_S


def reads_smoothed_encoder(readings: list[Reading]) -> bool:
    """Whether a climb's first :data:`NOISE_WINDOWS` driven ``readings`` show a smoothed speed signal: their noise
    colour (:func:`first_windows_noise_colour`) above :data:`~cof_gym.measurement.sine_fit.SMOOTHED_NOISE_COLOUR`
    where their noise (:func:`first_windows_noise_nms` from the reported SEs) is at least
    :data:`COLOUR_NOISE_FLOOR_NMS`; without sensor noise the residual is the wheel's own, whose colour says nothing
    of the encoder."""
    if not readings or first_windows_noise_nms(readings, reported=True) < COLOUR_NOISE_FLOOR_NMS:
        return False
    return first_windows_noise_colour(readings) > SMOOTHED_NOISE_COLOUR


ELASTICITY_SPAN = 0.1  # creep_elasticity's baseline: back to the latest window at least this much lower in ln CoA


def creep_elasticity(readings: list[Reading], span: float = ELASTICITY_SPAN) -> float | None:
    """The creep curve's elasticity ``d ln(creepage rise) / d ln(CoA)`` from the newest driven window back to the latest
    earlier one at least ``span`` lower in ``ln CoA``, the creepage's rise counted from the first driven window (a
    difference: the sensors' offset cancels; a ratio of rises: their scale error cancels). 1 on a creep curve's linear
    part, growing without bound at its peak. None where no window lies that far below, or where either rise is not
    positive or the rise did not grow (the noise's, not the curve's)."""
    first, now = readings[0], readings[-1]
    rise_now = now.creepage - first.creepage
    for earlier in reversed(readings[1:-1]):
        if earlier.coa > 0.0 and now.coa > 0.0 and math.log(now.coa / earlier.coa) >= span:
            rise = earlier.creepage - first.creepage
            if rise <= 0.0 or rise_now <= rise:
                return None
            return math.log(rise_now / rise) / math.log(now.coa / earlier.coa)
    return None

