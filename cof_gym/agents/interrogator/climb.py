"""The climb's settings (:class:`ClimbParameters`): how the DC torque and the modulation move after each
window, given the cautious headroom the networks predict, and which estimate is reported."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from cof_gym.agents.interrogator.readings import (Reading, creep_elasticity, first_windows_drive_lag_s,
                                                  first_windows_noise_nms, gain_from_balance)
from cof_gym.agents.phase_rule import ROTATION_SIDES, PhaseRule, knee_seen, probe_amplitude, rotation_clear_frequency
from cof_gym.measurement.sine_fit import NO_SE_DEG
from cof_gym.task.excitation import encode_extra_tones
from cof_gym.task.interface import MotorLimits, encode_action
from cof_gym.task.scenarios import COF_ENVELOPE
from cof_gym.validation import check_bool, check_choice, check_number

ESTIMATE_SOURCES = ("filter", "best_coa", "guard", "pooled", "pooled_at_headroom", "estimator", "estimator_pooled",
                    "estimator_pooled_at_headroom", "estimator_at_headroom", "guard_estimator_pooled")
HEADROOM_STOPS = ("headroom", "knee", "ceiling")  # stops whose estimate is a short extrapolation ("..._at_headroom" sources)
# the "..._at_headroom" sources: the source each reads at a headroom stop (the filter's before and at every other stop)
AT_HEADROOM = {"pooled_at_headroom": "pooled", "estimator_pooled_at_headroom": "estimator_pooled",
               "estimator_at_headroom": "estimator"}
KNEE_STOPS = (None, "any", "slow_probe")  # ClimbParameters.knee_stop: off, at every window, in the slow probe only
# estimate sources that read the guards' corrections
GUARDED_ESTIMATES = ("guard", "pooled", "pooled_at_headroom", "guard_estimator_pooled")
# estimate sources that read the estimators' corrections
ESTIMATOR_ESTIMATES = ("estimator", "estimator_pooled", "estimator_pooled_at_headroom", "estimator_at_headroom",
                       "guard_estimator_pooled")
TWO_TONE_ENV_OPTIONS = {"excitation": "multitone", "tones": 2}  # the env options a two-tone climb needs
CREST_RATIO_FLOOR = 0.03  # the lowest modulation ratio a crest-capped climb uses (and training climbs draw)


def speed_scaled_frequency(frequency_hz: float, reference_m_s: float, speed_m_s: float, limits: MotorLimits) -> float:
    """``frequency_hz x max(1, reference_m_s / speed_m_s)`` (Hz) within the drive's frequency range: the
    modulation frequency that keeps Eq. 3's ``w v`` at least the reference speed's (ValueError for a speed
    that is not a positive finite number)."""
    check_number("speed_m_s", speed_m_s, 0.0, math.inf, low_open=True, unit=" m/s")
    scaled = frequency_hz * max(1.0, reference_m_s / speed_m_s)
    return min(max(scaled, limits.min_frequency_hz), limits.max_frequency_hz)


def floor_headroom(coa: float) -> float:
    """``ln(CoF_min / CoA)``: a lower bound of the headroom ``ln(M_sat / DC)`` at the measured CoA
    ``coa``, from the lowest CoF the task admits (:data:`~cof_gym.task.scenarios.COF_ENVELOPE`): at
    a steady DC torque the CoA is its fraction of the saturation torque times the CoF."""
    return math.log(COF_ENVELOPE[0] / coa)


# ClimbParameters' checks, one entry per field: finite numbers > 0; true-or-false flags; numbers within
# (low, high, low_open, unit); the same for the optional ones, where None leaves the part of the climb unused
POSITIVE_FIELDS = ("amplitude_ratio", "min_amplitude_nm", "frequency_hz", "max_log_step", "min_log_step",
                   "best_coa_factor", "creep_while_std")
FLAG_FIELDS = ("creep_sticky", "crest_once_crept", "crest_floor", "runaway_estimate", "crest_ceiling", "ceiling_stop",
               "noise_se_reported", "noise_torque_measured", "crest_probe_hold_crest", "torque_balance",
               "slow_drive_applied_estimate")
BOUNDED_FIELDS: dict[str, tuple[float, float, bool, str]] = {
    "caution": (0.0, 10.0, False, ""),
    "target_headroom": (0.0, 5.0, False, ""),
    "spread_caution": (0.0, 10.0, False, ""),
    "tone2_weight": (0.0, 2.0, False, ""),
    "ceiling_fall_z": (0.0, 10.0, False, ""),
    "ceiling_noise_z": (0.0, 10.0, False, ""),
    "noise_caution_exponent": (0.0, 2.0, False, ""),
    "noise_creep_exponent": (0.0, 2.0, False, ""),
    "relative_error_shift": (0.0, 5.0, False, ""),
    "rotation_ripple_max_se_deg": (0.0, NO_SE_DEG, False, " deg"),
}
OPTIONAL_BOUNDED_FIELDS: dict[str, tuple[float, float, bool, str]] = {
    "floor_margin": (0.0, math.inf, False, ""),
    "creep_until": (-math.inf, math.inf, False, ""),
    "creep_cautious_floor": (-5.0, 5.0, False, ""),
    "crest_fraction": (0.0, math.inf, False, ""),
    "creep_release": (0.0, math.inf, False, ""),
    "creep_sticky_below": (0.0, math.inf, False, ""),
    "ceiling_near_headroom": (0.0, math.inf, False, ""),
    "torque_balance_max_lag_deg": (0.0, math.inf, False, ""),
    "tone2_frequency_hz": (MotorLimits.min_frequency_hz, MotorLimits.max_frequency_hz, False, ""),
    "noise_reference_nms": (0.0, math.inf, True, " N m s"),
    "pace_caution": (0.0, 10.0, False, ""),
    "frequency_reference_m_s": (0.0, 100.0, True, " m/s"),
    "rotation_margin_hz": (0.0, 10.0, True, " Hz"),
    "crest_below_m_s": (0.0, 100.0, True, " m/s"),
    "crest_probe_max_lag_deg": (0.0, 180.0, False, " deg"),
    "crest_probe_max_lag_step_deg": (0.0, 180.0, False, " deg"),
    "crest_probe_max_noise_ratio": (1.0, math.inf, False, ""),
    "lag_floor": (0.0, 1.0, True, ""),
    "crest_probe_lag_rise_deg": (0.0, 180.0, False, " deg"),
    "gate_max_drive_lag_s": (0.0, math.inf, True, " s"),
    "elasticity_release": (1.0, 100.0, False, ""),
}


@dataclass(frozen=True)
class ClimbParameters:
    """The climb's settings (chosen on validation; see the module docstring)."""

    amplitude_ratio: float = 0.1  # modulation amplitude / DC torque
    min_amplitude_nm: float = 50.0
    frequency_hz: float = 5.0
    # not None: below this speed (m/s) the frequency rises as 1 / speed (frequency_at), up to the drive's
    frequency_reference_m_s: float | None = None
    # not None: the frequency then moved at least this far (Hz) from the wheelset's rotation frequency at the measured
    # speed (phase_rule.rotation_clear_frequency): a speed probe's runout read by the rotation lock-in
    rotation_margin_hz: float | None = None
    rotation_side: str = "nearest"  # ... to the nearest clear frequency, or only below or above it (ROTATION_SIDES)
    # ... only where the reset window leaves a runout's ripple possible (phase_rule.ripple_possible: read with a phase
    # SE at most this, deg, or not read); NO_SE_DEG: wherever the margin moves it
    rotation_ripple_max_se_deg: float = NO_SE_DEG
    target_headroom: float = 0.05  # ln(M_sat / DC) the climb aims at (0.05: DC at 95 % of M_sat)
    caution: float = 1.0  # standard deviations taken off the predicted headroom
    spread_caution: float = 0.0  # and this many more of the members' spread alone (their disagreement)
    guard_cautions: tuple[float, ...] | None = None  # not None: each guard's caution, in the guards' order
    max_log_step: float = 0.4
    approach_fraction: float = 0.0  # far from the peak a step may close this fraction of the cautious gap
    min_log_step: float = 0.02
    creep_log_step: float = 0.0  # > 0: a step this small where the cautious gap is closed but the
    creep_while_std: float = 0.1  # ... predicted headroom's std still exceeds this (more readings, not a stop)
    creep_sticky: bool = False  # once it has crept, no later step exceeds creep_log_step
    creep_release: float | None = None  # not None: ... unless the cautious headroom is above this again
    # not None: ... sticky only from a slow-probe step the filter placed near the peak (its predicted mean headroom
    # below this): a guard's or a noisy window's dip far from the peak creeps once, then the climb goes on
    creep_sticky_below: float | None = None
    creep_until: float | None = None  # not None: no creep once the predicted (mean) headroom is this low
    # not None: no creep once the cautious (steering) headroom is below this: the steering source's caution already
    # places the peak that close (or past it), whatever its mean still says (a headroom stop instead)
    creep_cautious_floor: float | None = None
    estimate_from: str = "filter"  # "filter": CoA x exp(predicted correction); "best_coa": best CoA x factor;
    # "guard": CoA x exp(the guards' correction); "pooled": CoA x exp(the filter's and the guards' together);
    # "pooled_at_headroom": "pooled" once the climb stops on its headroom, "filter" before and otherwise;
    # "estimator": CoA x exp(the estimators' correction); "estimator_pooled": the filter's, guards' and estimators'
    # pooled; "estimator_pooled_at_headroom": that pool at a headroom stop, "filter" before and otherwise;
    # "estimator_at_headroom": the estimators' correction alone at a headroom stop, "filter" before and otherwise;
    # "guard_estimator_pooled": the guards' and the estimators' pooled, without the filter's
    best_coa_factor: float = 1.0
    floor_margin: float | None = None  # not None: a step may close the gap to the task's lowest CoF less this
    tone2_frequency_hz: float | None = None  # not None: a second tone at this frequency (a two-tone excitation)
    tone2_weight: float = 1.0  # its weight against tone 1's 1 (the env's share_2 + 1, in [0, 2])
    crest_fraction: float | None = None  # not None: the crest stays within this fraction of the cautious headroom
    crest_once_crept: bool = False  # the crest cap only from the climb's first slow probe on
    # not None: the crest cap only in a climb whose speed measured at its start is below this (m/s): a crest past the
    # peak spins the wheel further at a low speed, the creepage its excess torque drives in a half cycle growing as
    # 1 / speed
    crest_below_m_s: float | None = None
    crest_floor: bool = False  # the estimate at least the climb's best crest bound (Reading.crest_bound)
    runaway_estimate: bool = False  # a window that is not a stop reports what a runaway in it would (RunawayBracket)
    pace_caution: float | None = None  # not None: a slow-probe step at least the horizon pace (pace_step)
    knee_stop: str | None = None  # "any" / "slow_probe": the phase rule's jump test ends the climb (knee_stops)
    crest_ceiling: bool = False  # once the crest fell under a rising torque crest, every estimate at most CrestCeiling's
    ceiling_stop: bool = False  # the climb ends at the window where the crest falls under a rising torque crest
    ceiling_fall_z: float = 0.0  # a crest fall counts (crest_ceiling, ceiling_stop) beyond this many SEs (CrestCeiling.fall_z)
    ceiling_near_headroom: float | None = None  # not None: ... only where the predicted headroom is above this
    # at a read noise ratio r above 1 (noise_ratio), a crest fall counts only beyond this many times (r - 1) standard
    # errors more, near the expected peak as far from it (fall_margin)
    ceiling_noise_z: float = 0.0
    # not None: where the climb's first windows read more noise than this (N m s, noise_ratio), it follows it (at_noise)
    noise_reference_nms: float | None = None
    noise_caution_exponent: float = 0.0  # ... its cautions scale as (noise ratio) ** -this
    noise_creep_exponent: float = 0.0  # ... and creep_while_std as (noise ratio) ** this
    noise_se_reported: bool = False  # the noise reading from the lock-in's reported SE (lockin_noise_reported_nms)
    noise_torque_measured: bool = False  # ... at the torque amplitude the drive measured (Reading.lockin_noise)
    # not None: where the drive applies less than this fraction of the commanded modulation, the command is raised
    # to make up the difference (modulation_raise)
    lag_floor: float | None = None
    # not None: a headroom stop is deferred by a slow-probe step while the lag has risen this much (deg) since the
    # first driven window and the crest still rises (probes_on)
    crest_probe_lag_rise_deg: float | None = None
    crest_probe_max_lag_deg: float | None = None  # not None: ... and the window's lag is at most this (deg)
    crest_probe_max_lag_step_deg: float | None = None  # not None: ... and its lag rose at most this over the last (deg)
    # not None: ... and only where the climb's first windows read at most this noise ratio (noise_ratio, >= 1)
    crest_probe_max_noise_ratio: float | None = None
    # true: from the window the probe starts at, no later window's torque crest above that window's (held_crest_ratio)
    crest_probe_hold_crest: bool = False
    # not None: a headroom stop is deferred by a slow-probe step while the creep curve's offset-free elasticity
    # (readings.creep_elasticity) is at most this (probes_on; rule 142)
    elasticity_release: float | None = None
    # true: every torque reading divided by the gain the first driven window's torque balance reads against the
    # force channel (Reading.torque_balance, readings.gain_from_balance, Reading.calibrated)
    torque_balance: bool = False
    # not None: ... only where that window's lag is at most this (deg): a wheel that settles within the window
    # (its time constant is tan(lag) / (2 pi f), Eq. 3); above it the torque readings stay as read
    torque_balance_max_lag_deg: float | None = None
    # not None: smoothed-encoder networks take the climb only where its first windows read a drive no slower than
    # this (s; gates_drive): past the drives the networks were fitted on, a residual's colour is not the encoder's
    gate_max_drive_lag_s: float | None = None
    # true: where the climb's first windows read a drive slower than the v2 draws give (readings.reads_slow_drive),
    # the estimate's networks read the modulation the drive applied over the DC in place of the commanded ratio
    # (EpisodeFeatures.vector(applied_ratio=True)); the networks that steer read the command as before, so no step
    # of any climb changes, only the estimate reported behind such a drive
    slow_drive_applied_estimate: bool = False
    # each estimate is CoA x exp(correction - this x std^2), std its source's (log units): 0 reports the posterior's
    # median of ln CoF (what the reward's |ln(estimate / CoF)| asks for); 1 the value that minimises the expected
    # relative error |estimate / CoF - 1| under the networks' Gaussian posterior (a lognormal CoF tilted by 1 / CoF)
    relative_error_shift: float = 0.0

    def __post_init__(self) -> None:
        if self.estimate_from not in ESTIMATE_SOURCES:
            raise ValueError(f"estimate_from must be one of {ESTIMATE_SOURCES}, got {self.estimate_from!r}")
        for name in POSITIVE_FIELDS:
            check_number(name, getattr(self, name), 0.0, math.inf, low_open=True)
        check_number("approach_fraction", self.approach_fraction, 0.0, 1.0, high_open=True)
        for name in FLAG_FIELDS:
            check_bool(name, getattr(self, name))
        for name, (low, high, low_open, unit) in (*BOUNDED_FIELDS.items(), *OPTIONAL_BOUNDED_FIELDS.items()):
            if getattr(self, name) is not None or name in BOUNDED_FIELDS:
                check_number(name, getattr(self, name), low, high, low_open=low_open, unit=unit)
        if self.guard_cautions is not None:
            if not isinstance(self.guard_cautions, (list, tuple)) or not self.guard_cautions:
                raise ValueError("guard_cautions must be null or a non-empty list of numbers in [0, 10] (one per "
                                 f"guard), got {self.guard_cautions!r}")
            object.__setattr__(self, "guard_cautions", tuple(
                check_number(f"guard_cautions[{i}]", c, 0.0, 10.0) for i, c in enumerate(self.guard_cautions)))
        check_choice("rotation_side", self.rotation_side, ROTATION_SIDES)
        if self.knee_stop not in KNEE_STOPS:
            raise ValueError(f"knee_stop must be one of {KNEE_STOPS}, got {self.knee_stop!r}")
        if not (isinstance(self.creep_log_step, (int, float)) and 0.0 <= self.creep_log_step <= self.max_log_step):
            raise ValueError(f"creep_log_step must be in [0, max_log_step={self.max_log_step}], got {self.creep_log_step!r}")
        self._check_combinations()

    def _check_combinations(self) -> None:
        """The parameters that need another one set, or exclude it."""
        if self.crest_probe_max_noise_ratio is not None and self.noise_reference_nms is None:
            raise ValueError("crest_probe_max_noise_ratio reads the noise ratio, which needs noise_reference_nms")
        if self.lag_floor is not None and self.tone2_frequency_hz is not None:
            raise ValueError("lag_floor raises the sine's modulation; a two-tone climb has no lag_floor (null)")
        if self.crest_probe_lag_rise_deg is not None and self.creep_log_step < self.min_log_step:
            raise ValueError(f"crest_probe_lag_rise_deg probes at creep_log_step, which must then be at least "
                             f"min_log_step={self.min_log_step}, got {self.creep_log_step!r}")

    def fall_margin(self, mean_headroom: float, noise_ratio: float = 1.0) -> float:
        """The standard errors a crest fall must exceed to count (:class:`~cof_gym.agents.runaway.CrestCeiling`)
        at a window whose predicted (mean) headroom is ``mean_headroom``: ``ceiling_fall_z``, or with
        ``ceiling_near_headroom`` 0 where that headroom is at most it (the climb expects the peak: a crest that
        stops rising there is the peak's) and ``ceiling_fall_z`` beyond it (far from the expected peak a small
        fall is more likely the sensors' noise); with ``ceiling_noise_z``, ``ceiling_noise_z x (noise_ratio - 1)``
        more where the climb's first windows read more noise than the reference (:meth:`noise_ratio`): the bins'
        errors are estimated from the window's own cycles, and a noisier sensor than the networks met makes a
        chance fall near the expected peak, which ends the climb far below it, more frequent."""
        near = self.ceiling_near_headroom is not None and mean_headroom <= self.ceiling_near_headroom
        return (0.0 if near else self.ceiling_fall_z) + self.ceiling_noise_z * max(0.0, noise_ratio - 1.0)

    def torque_gain(self, reading: Reading) -> float:
        """The gain the climb divides its torque readings by, from its first driven window's ``reading``: the gain
        its torque balance reads (:attr:`Reading.torque_balance`, :func:`gain_from_balance`) with
        ``torque_balance``, 1 without it or where the window's lag is above ``torque_balance_max_lag_deg`` (a wheel
        not yet settled)."""
        if not self.torque_balance or (self.torque_balance_max_lag_deg is not None
                                       and reading.phase_deg > self.torque_balance_max_lag_deg):
            return 1.0
        return gain_from_balance(reading.torque_balance)

    def noise_ratio(self, readings: list["Reading"]) -> float:
        """How far the noise read over the climb's first :data:`NOISE_WINDOWS` driven ``readings`` (the median
        of their :attr:`Reading.lockin_noise_nms`, or with ``noise_se_reported`` their
        :attr:`Reading.lockin_noise_reported_nms`, with ``noise_torque_measured`` read at the torque amplitude the
        drive measured: :meth:`Reading.lockin_noise`) is above ``noise_reference_nms``: that ratio, at least 1;
        1 without a reference or a reading."""
        if self.noise_reference_nms is None or not readings:
            return 1.0
        noise = first_windows_noise_nms(readings, self.noise_se_reported, self.noise_torque_measured)
        return max(1.0, noise / self.noise_reference_nms)

    def gates_drive(self, applied_fractions: list[float], frequency_hz: float) -> bool:
        """Whether a climb whose first driven windows measured these ``applied_fractions`` of the commanded
        modulation at ``frequency_hz`` may be handed to smoothed-encoder networks: its drive's time constant as they
        read it (:func:`~cof_gym.agents.interrogator.readings.first_windows_drive_lag_s`) at most
        ``gate_max_drive_lag_s``; always without it."""
        return (self.gate_max_drive_lag_s is None
                or first_windows_drive_lag_s(applied_fractions, frequency_hz) <= self.gate_max_drive_lag_s)

    def at_noise(self, ratio: float) -> "ClimbParameters":
        """The climb at a read noise ``ratio`` times the reference (:meth:`noise_ratio`): ``caution`` and every
        ``guard_cautions`` entry times ``ratio ** -noise_caution_exponent``, ``creep_while_std`` times ``ratio **
        noise_creep_exponent``; itself at a ratio of 1. Networks fitted on sensors up to the reference's noise
        predict a wider headroom spread from noisier readings than they were fitted on; a constant caution
        turns that spread into a slower climb, which ends at the horizon far below the peak."""
        if ratio <= 1.0:
            return self
        lower = ratio ** -self.noise_caution_exponent
        return replace(self, caution=self.caution * lower,
                       guard_cautions=None if self.guard_cautions is None else tuple(c * lower for c in self.guard_cautions),
                       creep_while_std=self.creep_while_std * ratio ** self.noise_creep_exponent)

    def modulation_raise(self, applied_fractions: list[float]) -> float:
        """How much the next window's commanded modulation is raised over the climb's (at least 1): with
        ``lag_floor`` set and the climb's driven windows so far measured to apply a median fraction ``a`` of
        their commanded modulation (``applied_fractions``: each window's measured over its commanded torque
        amplitude, :attr:`Reading.torque_amplitude_measured_nm`), ``lag_floor / a`` where ``a`` is below the
        floor, so that the drive applies that floor's fraction of what the climb means; 1 otherwise. A
        first-order drive lag ``tau`` applies ``1 / sqrt(1 + (w tau)^2)`` of a modulation at ``w`` (0.30 at 5 Hz
        and 0.1 s), the torque gain error shifts the measured fraction by at most its own size, and a floor
        below the fractions of the lags the networks were fitted on leaves those climbs as they were."""
        if self.lag_floor is None or not applied_fractions:
            return 1.0
        return max(1.0, self.lag_floor / max(float(np.median(applied_fractions)), 1e-9))

    def check_guard_count(self, guards: int) -> None:
        """ValueError unless ``guard_cautions`` is unset or names one caution per guard (``guards`` of them)."""
        if self.guard_cautions is not None and len(self.guard_cautions) != guards:
            raise ValueError(f"guard_cautions names {len(self.guard_cautions)} caution(s) but the interrogator has "
                             f"{guards} guard(s): one per guard, in the guards' order")

    def guard_caution(self, index: int) -> float:
        """The caution of guard ``index`` (0-based, the guards' order): its ``guard_cautions`` entry, else
        ``caution``."""
        return self.caution if self.guard_cautions is None else self.guard_cautions[index]

    def cautious_headroom(self, mean: float, std: float, spread: float = 0.0, caution: float | None = None) -> float:
        """The predicted headroom less ``caution`` stds (the climb's unless given: a guard's,
        :meth:`guard_caution`) and ``spread_caution`` member spreads."""
        return mean - self._caution(caution) * std - self.spread_caution * spread

    def mean_headroom(self, cautious_headroom: float, std: float, spread: float = 0.0,
                      caution: float | None = None) -> float:
        """The predicted (mean) headroom back from its cautious value (:meth:`cautious_headroom` with the
        same ``caution``)."""
        return cautious_headroom + self._caution(caution) * std + self.spread_caution * spread

    def _caution(self, caution: float | None) -> float:
        return self.caution if caution is None else caution

    def log_step(self, cautious_headroom: float, headroom_std: float = 0.0, spread: float = 0.0,
                 caution: float | None = None) -> float:
        """The next DC step in log units: the cautious gap to the target, at most ``max_log_step`` or,
        when larger, ``approach_fraction`` of that gap (big steps far from the peak, small ones near it);
        where that gap is closed but the headroom is still uncertain (std above ``creep_while_std``),
        ``creep_log_step`` (0: none): a slow probe that gathers readings rather than a stop."""
        step = self._gap_step(cautious_headroom)
        return max(step, self.creep_log_step) if self.creeps(cautious_headroom, headroom_std, spread, caution) else step

    def _gap_step(self, cautious_headroom: float) -> float:
        gap = cautious_headroom - self.target_headroom
        return min(gap, max(self.max_log_step, self.approach_fraction * gap))

    def creeps(self, cautious_headroom: float, headroom_std: float, spread: float = 0.0,
               caution: float | None = None) -> bool:
        """Whether the next step is the slow probe: the cautious gap is closed, the headroom uncertain,
        with ``creep_until`` the predicted (mean) headroom still above it and with ``creep_cautious_floor`` the
        cautious headroom itself at least that floor."""
        return (self.creep_log_step > 0.0 and headroom_std > self.creep_while_std
                and self._gap_step(cautious_headroom) < self.min_log_step
                and (self.creep_until is None
                     or self.mean_headroom(cautious_headroom, headroom_std, spread, caution) > self.creep_until)
                and (self.creep_cautious_floor is None or cautious_headroom >= self.creep_cautious_floor))

    def sticks_from(self, filter_headroom: float) -> bool:
        """Whether a slow-probe step taken where the filter predicts a mean headroom ``filter_headroom`` (log units)
        makes the probe sticky: always, unless ``creep_sticky_below`` is set and the filter places the peak at least
        that far away."""
        return self.creep_sticky_below is None or filter_headroom < self.creep_sticky_below

    def sticks(self, crept: bool, cautious_headroom: float) -> bool:
        """Whether a climb that has ``crept`` is held to ``creep_log_step``: with ``creep_sticky``, unless
        ``creep_release`` is set and the cautious headroom is above it again (the slow probe's alarm was
        false: the filters now place the peak far above even after their caution)."""
        return (self.creep_sticky and crept
                and (self.creep_release is None or cautious_headroom <= self.creep_release))

    def pace_step(self, cautious_headroom: float, headroom_std: float, spread: float, windows_left: int,
                  caution: float | None = None) -> float:
        """With ``pace_caution`` set, the step that reaches the target headroom in the ``windows_left`` windows
        before the horizon if the headroom is the predicted mean less ``pace_caution`` stds:
        ``(mean - pace_caution x std - target_headroom) / windows_left``, at most ``max_log_step``; 0 when
        unused. A slow probe that starts far below the peak (the filter uncertain, its cautious gap closed)
        at 3 % a window spends the horizon there; paced, it spreads the predicted distance over the windows
        it has."""
        if self.pace_caution is None:
            return 0.0
        gap = (self.mean_headroom(cautious_headroom, headroom_std, spread, caution) - self.pace_caution * headroom_std
               - self.target_headroom)
        return min(gap / max(windows_left, 1), self.max_log_step)

    def knee_stops(self, reading: "Reading", previous: "Reading", driven: int, crept: bool) -> bool:
        """With ``knee_stop`` set, whether the ``driven``-th driven window (``reading``) ends the climb: the
        phase rule's jump test (:func:`~cof_gym.agents.phase_rule.knee_seen` with :class:`PhaseRule`'s
        validated jump, margin and SE limit; its lag over the ``previous`` window's by more than the jump
        beyond the standard errors) after the phase rule's baseline windows, and with ``"slow_probe"`` only
        in a climb that has ``crept`` before this window. A rounded knee raises the lag once and holds it;
        near a sharp peak it keeps jumping from window to window."""
        if self.knee_stop is None or driven <= PhaseRule.baseline_windows or (self.knee_stop == "slow_probe" and not crept):
            return False
        return bool(knee_seen(reading.phase_deg, reading.se_deg, previous.phase_deg, previous.se_deg, 0.0, 0.0,
                              PhaseRule.jump_deg, math.inf, PhaseRule.margin_se, PhaseRule.max_se_deg))

    def probes_on(self, readings: list["Reading"]) -> bool:
        """With ``crest_probe_lag_rise_deg`` set, whether a climb that would stop on its headroom after the driven
        windows ``readings`` takes one more slow-probe step instead: its lag has risen at least that much since the
        first of them (the slope has fallen: the knee is passed; the drive's own lag cancels in the rise) and the newest
        window's crest is above the one before (:attr:`Reading.coa_cycle_max`). A curve that rises slowly past its knee
        keeps a large lag under a crest that still rises, and its peak lies far above (experiments/knee_twins.py); at a
        rounded peak the crest falls under a rising torque crest and the ceiling stop ends the climb. With
        ``elasticity_release`` set, also (whatever the crest and the lag) where the creep curve's offset-free elasticity
        (:func:`~cof_gym.agents.interrogator.readings.creep_elasticity`) is at most that: the creepage still grows as on
        a curve's rising half (rule 142). With ``crest_probe_max_lag_deg`` the window's lag must also be at most that
        (near 90 deg the slope has vanished and the crest's rise is the sensors' noise), and with
        ``crest_probe_max_lag_step_deg`` its rise over the previous window's at most that (a lag that jumps from window
        to window is a sharp knee's, not a slow rise's). With ``crest_probe_max_noise_ratio`` only where the climb's
        first windows read at most that ratio of ``noise_reference_nms`` (:meth:`noise_ratio`): the lag's and the
        crest's rises are read against the noise of the sensors the networks were fitted on."""
        if self.elasticity_release is not None and len(readings) >= 3:
            elasticity = creep_elasticity(readings)
            if elasticity is not None and elasticity <= self.elasticity_release:
                return True
        if self.crest_probe_lag_rise_deg is None or len(readings) < 2:
            return False
        if self.crest_probe_max_noise_ratio is not None and self.noise_ratio(readings) > self.crest_probe_max_noise_ratio:
            return False
        first, previous, now = readings[0], readings[-2], readings[-1]
        return (now.phase_deg - first.phase_deg >= self.crest_probe_lag_rise_deg
                and now.coa_cycle_max > previous.coa_cycle_max > 0.0
                and (self.crest_probe_max_lag_deg is None or now.phase_deg <= self.crest_probe_max_lag_deg)
                and (self.crest_probe_max_lag_step_deg is None
                     or now.phase_deg - previous.phase_deg <= self.crest_probe_max_lag_step_deg))

    def held_crest_ratio(self, held_crest_nm: float, dc_nm: float, limits: MotorLimits) -> float | None:
        """The modulation ratio at DC torque ``dc_nm`` whose torque crest (DC plus :meth:`amplitude`) stays at most
        ``held_crest_nm``: the climb's ratio, or less, down to :data:`CREST_RATIO_FLOOR`; None where even that floor
        (or the drive's least amplitude) would put the crest above it (``crest_probe_hold_crest``: the probe raises
        the mean torque under the largest crest the wheel has carried, never that crest)."""
        ratio = min(self.amplitude_ratio, held_crest_nm / dc_nm - 1.0)
        if ratio < CREST_RATIO_FLOOR or dc_nm + self.amplitude(dc_nm, limits, ratio) > held_crest_nm * (1.0 + 1e-12):
            return None
        return ratio

    def floor_step(self, coa: float) -> float:
        """The step that the task's lowest CoF (:data:`~cof_gym.task.scenarios.COF_ENVELOPE`) guarantees
        safe at the measured CoA ``coa``: ``ln(CoF_min / CoA) - target_headroom - floor_margin`` (the CoA
        is the DC torque's fraction of the saturation torque times the CoF, up to the sensors' gain
        errors, which the margin covers); 0 when unused."""
        if self.floor_margin is None:
            return 0.0
        return floor_headroom(coa) - self.target_headroom - self.floor_margin

    def frequency_at(self, speed_m_s: float, limits: MotorLimits, ripple_possible: bool = True) -> float:
        """The modulation frequency (Hz) of a climb at the measured speed ``speed_m_s``: ``frequency_hz``, or
        with ``frequency_reference_m_s`` that times ``max(1, reference / speed)``, within the drive's range.
        Eq. 3's lag is ``atan(I w v / (k r^2))``: at a low speed it stays small and flat until the slope
        ``k`` has nearly vanished; a frequency rising as ``1 / v`` keeps ``w v`` (the lag's sensitivity to
        the slope) at least the reference speed's. With ``rotation_margin_hz`` the frequency then moves at least that
        far from the rotation's harmonics (:func:`~cof_gym.agents.phase_rule.rotation_clear_frequency`) where
        ``ripple_possible`` (the reset window's reading, :func:`~cof_gym.agents.phase_rule.ripple_possible`)."""
        frequency = (self.frequency_hz if self.frequency_reference_m_s is None else
                     speed_scaled_frequency(self.frequency_hz, self.frequency_reference_m_s, speed_m_s, limits))
        if self.rotation_margin_hz is None or not ripple_possible:
            return frequency
        return rotation_clear_frequency(frequency, speed_m_s, self.rotation_margin_hz, limits, self.rotation_side)

    def amplitude(self, dc_nm: float, limits: MotorLimits, ratio: float | None = None) -> float:
        """The modulation amplitude (N m) at DC torque ``dc_nm``: ``ratio`` (default ``amplitude_ratio``) of
        it, within the drive's range (with two tones the total: ``tone2_weight / (1 + tone2_weight)`` of it
        is tone 2's)."""
        return probe_amplitude(self.amplitude_ratio if ratio is None else ratio, dc_nm, self.min_amplitude_nm, limits)

    def crest_ratio(self, cautious_headroom_after: float, crept: bool = True, speed_m_s: float | None = None) -> float:
        """The modulation ratio at a DC torque whose cautious headroom is ``cautious_headroom_after``:
        ``amplitude_ratio``, or with ``crest_fraction`` at most ``exp(crest_fraction x headroom) - 1``, so
        that the crest ``DC (1 + ratio)`` stays that fraction (in log units) of the way from the DC to the
        cautiously predicted saturation torque, and at least :data:`CREST_RATIO_FLOOR` (the lowest ratio
        of the training climbs: below it the lock-in reads noise); with ``crest_once_crept`` only once the
        climb has ``crept`` (its slow probe, where the filter thinks the peak may be near); with ``crest_below_m_s``
        only where the climb's starting speed ``speed_m_s`` is below it."""
        fast = self.crest_below_m_s is not None and speed_m_s is not None and speed_m_s >= self.crest_below_m_s
        if self.crest_fraction is None or (self.crest_once_crept and not crept) or fast:
            return self.amplitude_ratio
        cap = math.expm1(self.crest_fraction * max(cautious_headroom_after, 0.0))
        return min(self.amplitude_ratio, max(cap, CREST_RATIO_FLOOR))

    @property
    def tones(self) -> int:
        return 1 if self.tone2_frequency_hz is None else 2

    @property
    def env_options(self) -> dict[str, Any]:
        """The env options the climb's excitation needs (none for the sine)."""
        return dict(TWO_TONE_ENV_OPTIONS) if self.tones == 2 else {}

    def commanded_amplitude(self, dc_nm: float, limits: MotorLimits, ratio: float | None = None,
                            raise_by: float = 1.0) -> float:
        """The modulation amplitude (N m) the drive is asked for: :meth:`amplitude` times ``raise_by``
        (:meth:`modulation_raise`), at most the drive's maximum (exactly :meth:`amplitude` at a raise of 1, which
        is within that maximum already)."""
        return min(self.amplitude(dc_nm, limits, ratio) * raise_by, limits.max_amplitude_nm)

    def action(self, dc_nm: float, estimate: float, stop: bool, limits: MotorLimits,
               ratio: float | None = None, frequency_hz: float | None = None, raise_by: float = 1.0) -> np.ndarray:
        """The env action (modulation ``ratio`` of the DC, default ``amplitude_ratio``, raised by ``raise_by``
        (:meth:`commanded_amplitude`), at ``frequency_hz``, default ``self.frequency_hz``): the window action,
        and tone 2's frequency and weight with two tones."""
        frequency = self.frequency_hz if frequency_hz is None else frequency_hz
        amplitude = self.commanded_amplitude(dc_nm, limits, ratio, raise_by)
        base = encode_action(dc_nm, amplitude, frequency, estimate, stop, limits)
        if self.tones == 1:
            return base
        extra = encode_extra_tones([(self.tone2_frequency_hz, self.tone2_weight)], limits.min_frequency_hz,
                                   limits.max_frequency_hz)
        return np.concatenate([base, extra]).astype(np.float32)
