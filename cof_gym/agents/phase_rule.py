"""The paper's phase rule as a train would run it: no ground truth, no creepage.

**What it reads.** Per window only the phase lag of the wheelset speed behind the modulated torque and
its standard error (the sine fit's), the measured CoA (force sensor) and the applied DC torque and
modulation amplitude. It never reads the measured creepage (a train's creepage carries systematic
errors, the reason the paper proposes the phase) and never ``info["ground_truth"]``.

**The modulation as a probe ahead of the DC level.** The modulation amplitude is ``amplitude_ratio``
(p) x DC (at least ``min_amplitude_nm``, at most the drive's maximum), so the torque's crest DC (1 + p)
reaches the creep curve's knee before the DC does: for part of each cycle the wheel's response turns
large-signal (the phase jumps) while the DC stays below saturation and the wheel does not run away (the
excess is a half-cycle impulse the creep force pulls back). The DC torque starts at the practical
staircase's first step (:meth:`~cof_gym.agents.staircase.ElasticityClimb.first_dc`: below the
saturation torque of the lowest CoF in range, so it never slips) and grows by
``min(max_step x DC, probe_step x amplitude)``: a step smaller than the probe, so the next DC stays
below the last crest that showed no knee. A train knows neither the saturation torque nor the CoF, so
the steps cannot be scheduled in percent of either (that is :class:`PaperStaircase`, an oracle).
Frequency ``frequency_hz`` (the paper's 5 Hz; 10 Hz was measured worse: the phase jump at the knee is
smaller).

**The baseline.** The inverse-variance mean of the phase of the reset window (no DC torque) and the
first ``baseline_windows`` driven windows (low torque): the vehicle's own phase.

**The stop.** At the first window after the baseline whose phase (deg) either jumps over the previous
window's by more than ``jump_deg`` beyond ``margin_se`` standard errors (both windows' SEs combined)
-- the knee of a sharp curve (the Shen-Hedrick-Elkins family holds the phase flat until the crest
touches ~90-97 % of the saturation torque, then it jumps) -- or rises above the baseline by more than
``threshold_rise_deg`` beyond ``margin_se`` standard errors (window and baseline); windows with an SE
above ``max_se_deg`` are ignored. Also when the CoA falls although the torque rose (past the peak)
and at the drive's limit. It reports the best crest CoA of the climb, the measured CoA x (1 +
amplitude / DC) (the crest's CoA is what touched the knee), times ``correction``.

**The lag's standard error.** The white-noise SE the lock-in reports (the shipped rule), or with ``corrected_se``
the SE for a first-order autoregressive speed residual (``phase-rule-ar1``: a smoothed encoder signal correlates the
residual, and the white SE then understates the lag's scatter several times over), or with ``se_gate`` the corrected
SE only in an episode whose reset window reads a smoothed speed signal (``phase-rule-gated``:
:func:`smoothed_speed_signal`, the window's noise colour), the white one otherwise: the shipped rule wherever the
encoder is sharp.

**Parameters** (chosen by ``experiments/select_phase_rule.py`` on validation seeds only; see the
table in :class:`PhaseRule`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cof_gym.agents.base import check_parameters
from cof_gym.agents.staircase import COA, ElasticityClimb
from cof_gym.measurement.sine_fit import NO_SE_DEG, SMOOTHED_NOISE_COLOUR, noise_colour
from cof_gym.task.creep_fit import coa_fell
from cof_gym.task.interface import MotorLimits, encode_action, window_reading
from cof_gym.validation import check_choice, check_number

UNKNOWN_SE_DEG = NO_SE_DEG  # the standard error of a window whose sine fit gave none
PAPER_CORRECTION = 1.0 / 0.95  # the paper: the CoA at the zero crossing is ~95 % of the CoF


# phase-rule-rotation's distance (Hz) of its modulation frequency from the rotation frequency and the side it moves to
# (rotation_clear_frequency; experiments/select_rotation_margin.py on validation seeds only: ranked by macro-slips, then
# median, then P90 with a runout read by the rotation lock-in: 11.3 / 29.5 / 0 against 15.1 / 86.3 / 0 at 5 Hz always)
ROTATION_MARGIN_HZ = 1.0
ROTATION_SIDE = "above"
CORRECTED_SE = "phase_lag_se_corrected_deg"  # the info["measurement"] reading of the lag's SE for a correlated residual


def phase_of(observation: np.ndarray, info: dict[str, Any] | None = None,
             corrected_se: bool = False) -> tuple[float, float]:
    """(phase lag, its standard error) of a window, deg; a missing or non-positive SE is unknown (180). With
    ``corrected_se`` the SE is ``info["measurement"]``'s :data:`CORRECTED_SE` (the speed fit's residual taken as
    autocorrelated, as a smoothed speed signal's is), not the observation's white-noise SE."""
    phase = window_reading(observation, "phase_lag")
    se = float(info["measurement"][CORRECTED_SE]) if corrected_se else window_reading(observation, "phase_lag_se")
    if not math.isfinite(phase):
        return 0.0, UNKNOWN_SE_DEG
    if not math.isfinite(se) or se <= 0.0:
        se = UNKNOWN_SE_DEG
    return phase, min(se, UNKNOWN_SE_DEG)


def smoothed_speed_signal(observation: np.ndarray, info: dict[str, Any] | None) -> bool:
    """Whether a window's speed residual reads as smoothed: its noise colour (``info["measurement"]``'s
    :data:`CORRECTED_SE` over the observation's white-noise SE, :func:`~cof_gym.measurement.sine_fit.noise_colour`)
    above :data:`~cof_gym.measurement.sine_fit.SMOOTHED_NOISE_COLOUR`. A sensor reading: a train can tell it. Read on
    the reset window (no DC torque, the smallest modulation), where the wheel's own response leaves the residual to
    the sensor noise; unlike the learned interrogator's note (over its first driven windows,
    :func:`~cof_gym.agents.interrogator.readings.reads_smoothed_encoder`) it sets no noise floor: with the paper
    setting's noiseless sensors the gated rule's 60 records were the original's (session 65)."""
    white = window_reading(observation, "phase_lag_se")
    corrected = float((info or {}).get("measurement", {}).get(CORRECTED_SE, 0.0))
    return noise_colour(white, corrected) > SMOOTHED_NOISE_COLOUR


def probe_amplitude(ratio: float, dc_nm: float, floor_nm: float, limits: MotorLimits) -> float:
    """A modulation amplitude (N m) of ``ratio`` x the DC torque, at least ``floor_nm`` and the drive's
    minimum, at most its maximum (the probe of the phase rule, the robust model and the interrogator)."""
    return min(max(ratio * dc_nm, floor_nm, limits.min_amplitude_nm), limits.max_amplitude_nm)


def probe_next_dc(dc_nm: float, amplitude_nm: float, max_step: float, probe_step: float, limits: MotorLimits) -> float:
    """The DC torque after a window at ``dc_nm`` whose probe of ``amplitude_nm`` showed no knee: a step
    of at most ``max_step`` x DC and ``probe_step`` x the amplitude (below the probed crest)."""
    return min(dc_nm + min(max_step * dc_nm, probe_step * amplitude_nm), limits.max_dc_torque_nm)


# the harmonics of the wheelset's rotation a modulation keeps clear of (cof_gym.physics.encoder): a runout e reads as
# a ripple of e times the spin rate at the rotation frequency; the period method's term at twice it is of order e^2
# (2.5e-7 of the spin rate at e = 0.05 %), far below any modulation's response, though the rotation lock-in fits it
# too (avoiding both read worse on validation for the learned interrogator, session 84)
ROTATION_HARMONICS = (1,)
ROTATION_SIDES = ("nearest", "below", "above")  # where rotation_clear_frequency may move a frequency
EDGE_RTOL = 1e-12  # a band's edge c +- margin counts as clear of c: |edge - c| is the margin to a few roundings


# info["measurement"]'s reading of the phase SE (deg) of the speed's ripple at the rotation frequency (the rotation
# lock-in's; NO_SE_DEG where it is not read)
RIPPLE_SE = "rotation_ripple_phase_se_deg"


def ripple_possible(info: dict[str, Any] | None, max_se_deg: float) -> bool:
    """Whether a window leaves a runout's ripple possible (a gate on :func:`rotation_clear_frequency`): the rotation
    lock-in read the ripple's phase to within ``max_se_deg`` (a ripple clear of the noise), or did not read it
    (:data:`RIPPLE_SE` of :data:`NO_SE_DEG`: the plain lock-in, or the harmonic left out where the window cannot tell
    it from the tone); False only where it fitted the harmonic and read no clear ripple. ``max_se_deg`` of
    :data:`NO_SE_DEG`: always True (no gate)."""
    se = float((info or {}).get("measurement", {}).get(RIPPLE_SE, NO_SE_DEG))
    return se <= max_se_deg or se >= NO_SE_DEG


def rotation_frequency_hz(speed_m_s: float, limits: MotorLimits) -> float:
    """The wheelset's rotation frequency ``v / (2 pi r)`` (Hz) at the measured speed ``speed_m_s`` (m/s) on the drive's
    nominal wheel radius ``limits.wheel_radius_m``: what a train knows of it (no ground truth)."""
    return speed_m_s / (2.0 * math.pi * limits.wheel_radius_m)


def rotation_clear_frequency(frequency_hz: float, speed_m_s: float, margin_hz: float, limits: MotorLimits,
                             side: str = "nearest") -> float:
    """The modulation frequency (Hz) nearest ``frequency_hz`` at least ``margin_hz`` from every harmonic of the
    wheelset's rotation (:data:`ROTATION_HARMONICS` of :func:`rotation_frequency_hz`) within the drive's frequency
    range: ``frequency_hz`` itself where it is clear or ``margin_hz`` is 0, else the nearest edge of a harmonic's
    excluded band that no other band covers (``side``, :data:`ROTATION_SIDES`: on either side, the higher one on a
    tie; only below ``frequency_hz``; only above it), else ``frequency_hz`` (no clear edge, or a speed that is not a
    positive finite number). Where a tone lies within about ``1 / T`` of a harmonic (T the lock-in's window) the
    rotation lock-in cannot tell the two apart and leaves the harmonic out of its fit, so a runout's ripple leaks into
    the tone's lag."""
    check_choice("side", side, ROTATION_SIDES)
    rotation = rotation_frequency_hz(speed_m_s, limits) if math.isfinite(speed_m_s) and speed_m_s > 0.0 else 0.0
    centres = [k * rotation for k in ROTATION_HARMONICS] if rotation > 0.0 else []

    def clear(f: float) -> bool:
        return (limits.min_frequency_hz <= f <= limits.max_frequency_hz
                and all(abs(f - c) >= margin_hz * (1.0 - EDGE_RTOL) for c in centres))

    if margin_hz <= 0.0 or clear(frequency_hz):
        return frequency_hz
    edges = [e for c in centres for e in (c - margin_hz, c + margin_hz) if clear(e)
             and (side == "nearest" or (e < frequency_hz) == (side == "below"))]
    return min(edges, key=lambda e: (abs(e - frequency_hz), -e)) if edges else frequency_hz


def phase_rise(phase_deg, se_deg, ref_deg, ref_se_deg, margin_se: float):
    """How far (deg) a window's phase lies above a reference window's beyond ``margin_se`` standard
    errors of their difference (scalars or numpy arrays): > 0 is a significant rise."""
    return phase_deg - ref_deg - margin_se * np.hypot(se_deg, ref_se_deg)


def knee_seen(phase_deg, se_deg, prev_deg, prev_se_deg, base_deg, base_se_deg, jump_deg: float,
              threshold_rise_deg: float, margin_se: float, max_se_deg: float):
    """The stop test (scalars or numpy arrays, deg): the window is informative (its SE at most
    ``max_se_deg``) and its phase either jumps over the previous window's by ``jump_deg`` beyond
    ``margin_se`` standard errors (both windows') or rises over the baseline by ``threshold_rise_deg``
    beyond ``margin_se`` standard errors (window and baseline)."""
    jump = phase_rise(phase_deg, se_deg, prev_deg, prev_se_deg, margin_se)
    rise = phase_rise(phase_deg, se_deg, base_deg, base_se_deg, margin_se)
    return (se_deg <= max_se_deg) & ((jump > jump_deg) | (rise > threshold_rise_deg))


@dataclass(frozen=True)
class Window:
    """What the rule saw in one driven window (deg; the previous window's phase; the best crest CoA of
    the climb so far)."""

    phase_deg: float
    se_deg: float
    prev_deg: float
    prev_se_deg: float
    base_deg: float
    base_se_deg: float
    best_crest_coa: float


# the probing climb's parameters that are scales (> 0), the phase rule's and the robust model's alike
PROBE_SCALES = ("amplitude_ratio", "max_step", "probe_step", "min_amplitude_nm", "frequency_hz", "max_se_deg",
                "correction")


@dataclass
class PhaseRule:
    """The paper's phase rule without ground truth or creepage, the modulation probing ahead of the DC
    level (see the module docstring).

    **Chosen on validation only** (``experiments/select_phase_rule.py``: 4 climbs x 64 stop rules x 4
    corrections on 320 episodes, seeds 100000+, never the evaluate suite; ranked by macro-slips, then
    median, then P90): probe amplitude 40 % of DC (100 N m floor, the drive's 3000 N m cap), DC step
    min(25 % of DC, 0.8 x amplitude), 5 Hz, jump 4 deg beyond 2 SE, no rise-over-baseline test (every
    finite threshold stopped earlier at no gain in safety), windows with SE > 5 deg ignored, correction
    1.05. Validation (median / P90 / macro-slips / mean Wd RMS of the driven windows):

    | setting | episodes | median | P90 | macro-slips | Wd, m/s^2 |
    |---|---|---|---|---|---|
    | v2 wagon | 120 | 11.1% | 29.9% | 0 | 0.0150 |
    | v2 wagon, counter torque | 120 | 10.5% | 32.7% | 0 | 0.0000 |
    | v1 wagon | 40 | 17.2% | 30.3% | 0 | 0.0134 |
    | v2 half wheelset | 40 | 8.6% | 22.7% | 0 | 0.0000 |
    | all, correction 1.05 | 320 | 11.1% | 31.3% | 0 | 0.0073 |
    | all, correction 1.1 | 320 | 11.9% | 30.5% | 0 | |
    | all, best without the jump test (rise 10 deg, probe 50 %) | 320 | 13.3% | 29.9% | 11 | |

    The previous climb (multiplicative steps ruled by the phase rise, 4 % modulation, stop 30 deg above
    the baseline) had 28 macro-slips on the same set (median 25.1 %). The errors left are mostly
    underestimates: rounded (Polach wet / low-adhesion) curves whose phase rises at 60-70 % of the
    saturation torque, and high-CoF laden cases where the 3000 N m amplitude cap shrinks the probe and
    the steps, so the 30-window horizon ends the climb at 50-60 % of it.
    """

    limits: MotorLimits
    amplitude_ratio: float = 0.4
    max_step: float = 0.25
    probe_step: float = 0.8
    min_amplitude_nm: float = 100.0
    frequency_hz: float = 5.0
    jump_deg: float = 4.0
    threshold_rise_deg: float = math.inf
    margin_se: float = 2.0
    max_se_deg: float = 5.0
    baseline_windows: int = 2
    correction: float = 1.05
    corrected_se: bool = False  # read the lag's SE for an autocorrelated speed residual (phase_of)
    # read it in an episode whose reset window reads a smoothed speed signal (smoothed_speed_signal), the white one
    # otherwise
    se_gate: bool = False
    # > 0: the modulation frequency of the episode moved at least this far (Hz) from the rotation's harmonics at the
    # reset's measured speed (rotation_clear_frequency); 0: frequency_hz always (the shipped rule)
    rotation_margin_hz: float = 0.0
    rotation_side: str = "nearest"  # ... to the nearest clear frequency, or only below or above frequency_hz
    # ... only where the reset window leaves a runout's ripple possible (ripple_possible: read with a phase SE at most
    # this, deg, or not read); NO_SE_DEG: wherever the margin moves it (phase-rule-rotation: no gate read better on
    # validation, session 85: the lock-in reads the ripple only more than about 0.7 Hz from the tone, the band's edge)
    rotation_ripple_max_se_deg: float = NO_SE_DEG
    name: str = "phase-rule"
    oracle: bool = False
    climb: ElasticityClimb = field(default_factory=ElasticityClimb, repr=False)  # the shared safe first step
    _dc: float = 0.0
    _amp: float = 0.0
    _best_crest: float = 0.0
    _last_coa: float = 0.0
    _prev: tuple[float, float] = (0.0, UNKNOWN_SE_DEG)
    _base_sum: float = 0.0  # sum of phase / se^2 of the baseline windows
    _base_weight: float = 0.0  # sum of 1 / se^2
    _driven: int = 0
    _corrected: bool = False  # this episode's SE: corrected_se, or the gate's reading of the reset window
    _frequency: float = 0.0  # this episode's modulation frequency, Hz
    stop_reason: str = field(default="", repr=False)
    windows: list[Window] = field(default_factory=list, repr=False)  # this episode's driven windows

    def __post_init__(self) -> None:
        # every numeric parameter as its default is (these > 0; the jump test off at +inf, as the selection's rules
        # without it): a clear error, not a NaN action
        check_parameters(self, positive=PROBE_SCALES, off_at_infinity=("jump_deg",))
        check_choice(f"{type(self).__name__}.rotation_side", self.rotation_side, ROTATION_SIDES)
        check_number(f"{type(self).__name__}.rotation_ripple_max_se_deg", self.rotation_ripple_max_se_deg, 0.0,
                     NO_SE_DEG, unit=" deg")

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        self._dc = self._amp = 0.0
        self._best_crest = 0.0
        self._last_coa = 0.0
        self._base_sum = self._base_weight = 0.0
        self._driven = 0
        self.stop_reason = ""
        self.windows = []
        self._corrected = self.corrected_se or (self.se_gate and smoothed_speed_signal(observation, info))
        self._prev = phase_of(observation, info, self._corrected)
        self._add_baseline(*self._prev)
        margin = self.rotation_margin_hz if ripple_possible(info, self.rotation_ripple_max_se_deg) else 0.0
        self._frequency = rotation_clear_frequency(self.frequency_hz, window_reading(observation, "speed"), margin,
                                                   self.limits, self.rotation_side)

    def _add_baseline(self, phase: float, se: float) -> None:
        self._base_sum += phase / se**2
        self._base_weight += 1.0 / se**2

    @property
    def baseline(self) -> tuple[float, float]:
        """The low-torque phase (deg) and its standard error (deg)."""
        return self._base_sum / self._base_weight, 1.0 / math.sqrt(self._base_weight)

    def amplitude(self, dc: float) -> float:
        """The modulation amplitude (N m) at DC torque ``dc``: the probe, within the drive's range."""
        return probe_amplitude(self.amplitude_ratio, dc, self.min_amplitude_nm, self.limits)

    def next_dc(self, dc: float, amplitude: float) -> float:
        """The DC torque after a window at ``dc`` with modulation ``amplitude`` showed no knee: a step
        of at most ``max_step`` x DC and ``probe_step`` x the amplitude (below the probed crest)."""
        return probe_next_dc(dc, amplitude, self.max_step, self.probe_step, self.limits)

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        coa = float(observation[COA])
        phase, se = phase_of(observation, info, self._corrected)
        stop = False
        if self._dc > 0.0:
            self._driven += 1
            falling = self._driven > 1 and coa_fell(coa, self._last_coa)
            self._last_coa = coa
            self._best_crest = max(self._best_crest, coa * (1.0 + self._amp / self._dc))
            if self._driven <= self.baseline_windows:
                self._add_baseline(phase, se)
            base, base_se = self.baseline
            prev, prev_se = self._prev
            self._prev = (phase, se)
            self.windows.append(Window(phase, se, prev, prev_se, base, base_se, self._best_crest))
            knee = self._driven > self.baseline_windows and bool(knee_seen(
                phase, se, prev, prev_se, base, base_se, self.jump_deg, self.threshold_rise_deg, self.margin_se,
                self.max_se_deg))
            at_limit = self._dc >= self.limits.max_dc_torque_nm
            stop = knee or falling or at_limit
            if stop:
                self.stop_reason = "phase" if knee else "falling" if falling else "limit"
            else:
                self._dc = self.next_dc(self._dc, self._amp)
        else:
            self._dc = self.climb.first_dc(self.limits)
        self._amp = self.amplitude(self._dc)
        estimate = self._best_crest * self.correction if self._best_crest > 0 else self.limits.min_cof_estimate
        estimate = self.limits.clip_estimate(estimate)
        return encode_action(self._dc, self._amp, self._frequency, estimate, stop, self.limits)


def phase_rule_ar1(limits: MotorLimits) -> PhaseRule:
    """The phase rule reading the lag's SE for an autocorrelated speed residual (``phase-rule-ar1``): every
    parameter the validation-chosen rule's."""
    return PhaseRule(limits, corrected_se=True, name="phase-rule-ar1")


def phase_rule_gated(limits: MotorLimits) -> PhaseRule:
    """The phase rule reading the lag's SE for an autocorrelated speed residual only in an episode whose reset
    window reads a smoothed speed signal (``phase-rule-gated``: :func:`smoothed_speed_signal`), the white one
    otherwise: every parameter the validation-chosen rule's."""
    return PhaseRule(limits, se_gate=True, name="phase-rule-gated")


# the rule chosen for task v3 (a train's speed probe on an irregular track) by experiments/select_phase_rule.py
# --in-service on that id's validation seeds (session 86): a smaller probe at 8 Hz, above most of the track's band,
# the smallest jump and the largest correction of the grid; still far from the CoF there (docs/results.md)
IN_SERVICE_PARAMETERS: dict[str, float] = {"amplitude_ratio": 0.3, "max_step": 0.2, "probe_step": 0.67,
                                           "frequency_hz": 8.0, "jump_deg": 2.0, "threshold_rise_deg": math.inf,
                                           "margin_se": 2.0, "max_se_deg": 5.0, "correction": 1.2}


def phase_rule_in_service(limits: MotorLimits) -> PhaseRule:
    """The phase rule chosen on task v3's validation seeds (``phase-rule-in-service``: :data:`IN_SERVICE_PARAMETERS`),
    every other parameter the v2 rule's."""
    return PhaseRule(limits, **IN_SERVICE_PARAMETERS, name="phase-rule-in-service")


def phase_rule_rotation(limits: MotorLimits) -> PhaseRule:
    """The phase rule modulating clear of the wheelset's rotation frequency (``phase-rule-rotation``:
    :func:`rotation_clear_frequency` with :data:`ROTATION_MARGIN_HZ` and :data:`ROTATION_SIDE`), for a speed probe whose
    target wheel runs out, read by the rotation lock-in: every other parameter the validation-chosen rule's."""
    return PhaseRule(limits, rotation_margin_hz=ROTATION_MARGIN_HZ, rotation_side=ROTATION_SIDE,
                     name="phase-rule-rotation")
