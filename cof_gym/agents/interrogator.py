"""The learned interrogator: a torque climb steered by a learned filter of the sensor history.

**What it reads.** Only sensor observations: per window the phase lag of the wheelset speed behind
the modulated torque and its standard error, the compliance (speed/torque amplitude ratio), the
measured CoA, the applied DC torque, amplitude and frequency, the measured speed and normal load, and
the vehicle configuration it was built for (counter torque on or off, known on board), and the measured
creepage only through *differences between windows, in ratio*: a train's creepage carries a systematic
offset of the size of the peak creepage (reference speed and wheel radius errors) and a scale error of
a percent or two; the offset cancels in a difference, the scale in a ratio of two differences. It
never reads ``info["ground_truth"]``.

**The learned filter.** An ensemble of small heteroscedastic networks
(:class:`FilterEnsemble`, trained by :mod:`cof_gym.agents.interrogator_training` on the v2
randomisation: creep-law families and shapes, systematic sensor errors, speeds, loads, both vehicle
configurations) maps the episode's features (:class:`EpisodeFeatures`: the window's phase, compliance,
slope index ``ln cot(phase)`` and their change since the first driven window, the CoA and torque
growth, the secant flexibility of the creep curve ``d creepage / d CoA`` over the last step relative to
its chord from the first driven window, the quadratic-peak extrapolation of the CoA from the slopes of
the last windows (:func:`peak_gap`, from the phase and from the compliance), the two previous
windows) to two Gaussian predictions:

- the **headroom** ``ln(M_sat / DC)``: how far the DC torque is below the saturation torque;
- the **correction** ``ln(CoF / CoA)``: the factor from the measured CoA to the CoF.

The phase lag goes to 90 deg as the creep curve flattens (the paper's Eq. 3: the lag is
``atan(I w v / (k r^2))`` for the half wheelset, ``k`` the local slope), so the slope index falls as the
operating point nears the peak; the filter learns how far the peak still is from how the slope has
fallen, across the shapes it was trained on.

**The climb.** From the shared safe first step (below the lowest saturation torque in range), each
window moves the DC torque to ``DC x exp(min(h - target_headroom, max_log_step))`` (or, far from the
peak, up to ``approach_fraction`` of the gap ``h - target_headroom``) with the cautious
headroom ``h = mean - caution x std - spread_caution x spread`` (``std``: the ensemble's spread and each
member's predicted variance combined; ``spread``: the members' disagreement alone, which grows where
the readings are unlike the training climbs'; ``spread_caution`` 0 unless chosen), the modulation a fixed fraction of the DC. Where that gap is closed while the predicted
headroom is still uncertain (its std above ``creep_while_std``), it creeps by ``creep_log_step``: a
stop there would report a poorly known estimate, and a slow probe buys the readings that settle it;
with ``creep_sticky`` no later step is larger (the filter thought the peak might be near: a big step
after that passes the peak on a curve unlike its training curves), and with ``creep_release`` too
unless the cautious headroom has grown above it again (a false alarm: a climb held to the slow probe
from its second window on ends at the horizon far below the peak). With ``creep_until`` the probe ends
once the predicted (mean) headroom is that low: the filter expects the peak within it, and each further
window there risks the modulation's crest passing the peak for readings the estimate no longer needs.
With ``pace_caution`` set, a slow-probe step (never a stop) is at least the horizon pace
(:meth:`ClimbParameters.pace_step`): the predicted headroom less that many stds, spread over the windows
left before the horizon; a probe that starts far below the peak of a curve the filter reads poorly (low
speeds, where Eq. 3's lag is small) otherwise ends at the horizon a factor of two or more below it.
With ``frequency_reference_m_s`` set, the modulation runs at ``frequency_hz x max(1, reference / v)`` (within the
drive's range; ``v`` the speed measured at the episode's start): Eq. 3's lag scales with ``w v``, and at a low
speed it stays flat until the slope has nearly vanished (:func:`speed_scaled_frequency`).
With ``floor_margin`` set, a step is at least the one that the lowest CoF the task admits
guarantees safe (:func:`floor_headroom`: the CoA is the DC's fraction of the saturation torque times
the CoF, so ``ln(CoF_min / CoA)`` bounds the headroom from below whatever the creep curve): a climb that
starts far below a high CoF's peak crosses that range in one step instead of spending windows there.
It stops (and reports ``CoA x exp(correction)``) when the next step would be smaller than
``min_log_step``, when the CoA falls although the torque rose (past the peak), at the drive's limit,
or one window before the horizon; with ``knee_stop`` also at a window whose lag jumps over the previous
window's as the phase rule's test has it (:meth:`ClimbParameters.knee_stops`; ``"slow_probe"``: only once
the climb has crept), reporting there what it reports at a headroom stop; with ``ceiling_stop`` also at the
window where the crest falls under a rising torque crest (:class:`~cof_gym.agents.runaway.CrestCeiling`),
reporting the same (with ``ceiling_fall_z`` a crest fall counts for both only beyond that many standard errors of
the two crests' difference: :attr:`~cof_gym.agents.runaway.CrestCeiling.fall_z`; with ``ceiling_near_headroom``
too, any fall counts where the predicted headroom is at most that: :meth:`ClimbParameters.fall_margin`). The
climb probes on past a headroom stop with ``crest_probe_lag_rise_deg`` set, at ``creep_log_step``, while its lag has
risen that much since its first driven window and its crest still rises (:meth:`ClimbParameters.probes_on`; with
``crest_probe_max_lag_deg`` and ``crest_probe_max_lag_step_deg`` only below that lag and that lag's step; with
``crest_probe_max_noise_ratio`` only where its first windows read at most that ratio of the reference noise; with
``crest_probe_hold_crest`` under the torque crest of the window it started from, its modulation shrinking as the DC
rises: :meth:`ClimbParameters.held_crest_ratio`). The
climb follows the noise its sensors read with ``noise_reference_nms`` set: where the median of
:attr:`Reading.lockin_noise_nms` over its first :data:`NOISE_WINDOWS` driven windows (the wheel-speed noise the
lock-in fit reads, whatever the operating point) is ``r`` times that reference with ``r`` above 1, its cautions
are ``r ** -noise_caution_exponent`` and its slow probe's ``creep_while_std`` ``r ** noise_creep_exponent``
times the climb's (:meth:`ClimbParameters.at_noise`): networks fitted on sensors up to the reference's noise
predict a wider headroom spread from noisier readings, and a constant caution spends it in slowness. The
estimate is the filter's (the last rising window's CoA times its
predicted correction), or the best CoA of the climb times a factor, or the same CoA times the guards'
correction or the filter's and the guards' corrections pooled (inverse-variance weighted,
:func:`pooled_correction`), or the pooled one where the climb stops on its headroom and the filter's
otherwise, or an estimator's (below), whichever the validation chose. The parameters are chosen on validation scenarios only
(``experiments/train_interrogator.py``).

**Guards.** With ``guards`` (further ensembles that read their own feature blocks, e.g. networks fitted
on the measured creepage's modulation) the climb steers by the lowest cautious headroom of the filter
and its guards, each with its own std and spread (and, with ``guard_cautions``, its own caution in place of
``caution``): a guard can only slow the climb, and the estimate stays
the filter's unless ``estimate_from`` reads the guards' (:data:`GUARDED_ESTIMATES`). A directory's
``manifest.json`` names its guards (``"guards"``: directories of ``member_*.npz``, relative to it); the shipped
interrogator has two since session 31: ``guard_0``, the same networks fitted on the family climbs, on
procedural creep curves and on the climbs of the agent shipped before session 30, on the env's draws; and
``guard_1``, fitted on the first two alone (the probing guard, its only guard from session 16 to 30).
Since session 32 the shipped estimate pools both guards' corrections at every window, without the filter's
(session 31: the filter's and both guards').

**Estimators.** With ``estimators`` (further ensembles fitted on the deployed climb's own windows, on
policy: :func:`~cof_gym.agents.interrogator_training.collect` with a ``policy``) the estimate may read
their correction (``estimate_from="estimator"``), or theirs, the filter's and the guards' pooled
(``"estimator_pooled"``), or that pool where the climb stops on its headroom and the filter's otherwise
(``"estimator_pooled_at_headroom"``), or theirs alone there (``"estimator_at_headroom"``; :data:`ESTIMATOR_ESTIMATES`). They never steer: the climb, and every
macro-slip, is the same with or without them. The filter and the guards learn from random probing
climbs, so that no schedule leaks the truth into their features; an estimator learns the correction
where the deployed climb actually stops. A manifest names them under ``"estimators"``.

**A crest floor.** With ``crest_floor`` the reported estimate is at least the climb's best crest bound:
over its windows, the largest crest of the measured CoA's synchronous average over the modulation cycle
(``info["measurement"]["coa_cycle_max"]``) less one phase bin's standard error
(:attr:`Reading.crest_bound`). The crest is the adhesion at the torque's crest; it cannot exceed the
creep curve's peak, the CoF, and where the crest of a 40 % modulation has reached into the knee it is
much nearer the CoF than the window's mean CoA. It changes no step of the climb.
With ``crest_ceiling``, once a window's crest has fallen below the previous window's while its commanded
torque crest rose (:class:`~cof_gym.agents.runaway.CrestCeiling`: the crest has reached the peak), every
estimate is also at most the best crest plus one bin's standard error. It changes no step either.

**The estimate a runaway would report.** The env scores the estimate of a window that is not a stop
only if the wheel runs away in it (a macro-slip). With ``runaway_estimate`` that estimate is what such a
runaway measures (:class:`~cof_gym.agents.runaway.RunawayBracket`): the creep curve's peak lies above the
climb's best crest bound ``c`` (survived) and below what the coming window's torque crest demands, about
``c x rho`` for ``rho`` the ratio of that crest to the crest of the window that gave ``c`` (commanded
torques: the torque gain error cancels); the reported estimate is the bracket's geometric middle
``c sqrt(rho)``, whose largest log error over the bracket is the smallest. A stop reports the estimate of ``estimate_from`` as
before. It changes no step of the climb, and no estimate of an episode that does not run away.

**A crest cap.** With ``crest_fraction`` set, the modulation shrinks as the climb nears the peak: the
ratio of each window is at most ``exp(crest_fraction x h) - 1`` for the cautious headroom ``h`` left
after the step (:meth:`ClimbParameters.crest_ratio`, at least :data:`CREST_RATIO_FLOOR`), so that the
crest ``DC (1 + ratio)`` stays that fraction of the way to the cautiously predicted saturation torque: on
a creep curve that falls steeply past its peak, a 40 % crest passing the peak lets the wheel run away
before any reading shows the peak (the paper's outlook: interrogation at lower magnitudes of torque). Its
networks should be fitted on climbs whose modulation shrinks too (``ClimbDraws.crest_powers``).

**Two tones.** With ``tone2_frequency_hz`` set, the modulation is two sines (the env's
``excitation="multitone"``, ``tones=2``; :attr:`LearnedInterrogator.env_options`, which
``cof-gym evaluate`` applies to the agent's own env): tone 1 at ``frequency_hz`` and tone 2 with
``tone2_weight / (1 + tone2_weight)`` of the amplitude, each read by its own lock-in. The lag rises
with the frequency (Eq. 3: ``tan(lag) = I w v / (k r^2)`` grows with ``w``), so a second, higher tone reads
the slope's fall where one tone's lag is still small (low speeds, far from the peak), and the two lags'
ratio tells the wheel's first-order response from the drive's and suspension's; the filter then reads
:data:`TONE2_FEATURE_NAMES` as well and must be fitted on two-tone climbs.

**Feature blocks.** Beyond :data:`FEATURE_NAMES` a filter may read optional blocks
(:data:`FEATURE_BLOCKS`; its file names them, :func:`blocks_of`): ``tone2`` (above) and
``creepage_rise``, the measured creepage's rise since the first driven window itself, not only in
ratio (:data:`CREEPAGE_RISE_FEATURE_NAMES`): the offset cancels in the difference, and a scale error of a
percent or two moves its ``ln`` by 0.01-0.02, so the rise tells a long, flat knee (wet and
low-adhesion curves peak at large creepages) from a peak that is near. ``cycle_crest`` reads the measured
CoA's synchronous average over the cycle (:data:`CYCLE_CREST_FEATURE_NAMES`): how far its crest and
trough lie from the mean, their asymmetry (a crest that reaches the knee is clipped, the trough is not),
the crest's lift per lift of the torque's crest, the climb's best crest bound over the CoA (a lower bound
on the correction) and the crest's step since the previous window; a filter that reads it must be
fitted on climbs collected with that reading (session 22 on). ``climb_fit`` regresses over the climb's
newest windows (:data:`CLIMB_FIT_FEATURE_NAMES`): the slope's fall per log torque, the quadratic-peak
gap and the creep curve's flexibility fitted over up to :data:`CLIMB_FIT_WINDOWS` windows rather than
read from two, so that a slow probe's many readings of nearly one slope average out.
"""

from __future__ import annotations

import itertools
import json
import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np

from cof_gym.agents.base import (configuration_note, env_defaults, episode_scenarios, outside_training_note,
                                 registered_ranges, without_defaults)
from cof_gym.agents.phase_rule import PhaseRule, knee_seen, probe_amplitude
from cof_gym.agents.runaway import CrestCeiling, RunawayBracket, crest_lower_bound
from cof_gym.agents.staircase import ElasticityClimb
from cof_gym.physics.simulation import COA_CYCLE_FIELDS
from cof_gym.task.excitation import encode_extra_tones
from cof_gym.task.creep_fit import coa_fell
from cof_gym.task.scenarios import COF_ENVELOPE
from cof_gym.task.validation import check_number
from cof_gym.task.interface import CREEPAGE_SCALE, OBSERVATION_NAMES, SPEED_SCALE_M_S, MotorLimits, encode_action

SHIPPED_INTERROGATOR = Path(__file__).resolve().parent / "policies" / "interrogator"
_INDEX = {name: OBSERVATION_NAMES.index(name) for name in OBSERVATION_NAMES}
PHASE_CLIP_DEG = (1.0, 89.0)  # the slope index ln cot(phase) is finite within these
SE_CLIP_DEG = 30.0
SE_REPORTED_MAX_DEG = 180.0  # the lock-in's standard error of no information (pi: cof_gym.measurement.sine_fit)
HISTORY = 2  # previous windows in the features
WORLD_KWARGS = ("vehicle", "counter_torque", "traction_balance", "window_s", "settle_fraction", "ramp_fraction",
                "timestep")  # constructor arguments that change what the sensors see
ESTIMATE_SOURCES = ("filter", "best_coa", "guard", "pooled", "pooled_at_headroom", "estimator", "estimator_pooled",
                    "estimator_pooled_at_headroom", "estimator_at_headroom")
HEADROOM_STOPS = ("headroom", "knee", "ceiling")  # stops whose estimate is a short extrapolation ("..._at_headroom" sources)
# the "..._at_headroom" sources: the source each reads at a headroom stop (the filter's before and at every other stop)
AT_HEADROOM = {"pooled_at_headroom": "pooled", "estimator_pooled_at_headroom": "estimator_pooled",
               "estimator_at_headroom": "estimator"}
KNEE_STOPS = (None, "any", "slow_probe")  # ClimbParameters.knee_stop: off, at every window, in the slow probe only
GUARDED_ESTIMATES = ("guard", "pooled", "pooled_at_headroom")  # estimate sources that read the guards' corrections
# estimate sources that read the estimators' corrections
ESTIMATOR_ESTIMATES = ("estimator", "estimator_pooled", "estimator_pooled_at_headroom", "estimator_at_headroom")
TARGET_NAMES = ("headroom", "correction")  # ln(M_sat / DC), ln(CoF / CoA measured)
NOISE_WINDOWS = 3  # the climb's first driven windows whose lock-in noise (Reading.lockin_noise_nms) it follows

FEATURE_NAMES = (
    "phase", "phase_se", "compliance", "slope_index", "slope_drop", "phase_rise", "compliance_rise",
    "coa_growth", "dc_growth", "log_coa", "amplitude_ratio", "frequency", "speed", "normal_load",
    "counter_torque", "window_index", "secant_flexibility",
    *(f"{name}_{k}" for k in range(1, HISTORY + 1)
      for name in ("phase", "slope_index", "coa_step", "dc_step", "secant_flexibility")),
    "peak_gap_phase", "peak_gap_compliance", "peak_gap_phase_2", "slope_ratio_phase", "slope_ratio_compliance",
)
# with a second tone (``ClimbParameters.tone2_frequency_hz``): the same small-signal readings at a second
# frequency, appended (:func:`feature_names`)
TONE2_FEATURE_NAMES = (
    "tone2_phase", "tone2_phase_se", "tone2_compliance", "tone2_slope_index", "tone2_slope_drop",
    "tone2_slope_ratio", "tone2_peak_gap", "tone_dispersion", "tone2_frequency", "tone2_share", "tone2_phase_1",
)
# the measured creepage's rise since the first driven window (offset-free: :meth:`EpisodeFeatures._creepage_rise_values`)
CREEPAGE_RISE_FEATURE_NAMES = ("creepage_rise", "chord_flexibility", "step_creepage_rise")
CREEPAGE_RISE_FLOORS = (1e-5, 1e-4, 1e-6)  # below these (no rise), each of the three reads ln(floor)
# the measured creepage's own modulation (its lock-in: :meth:`EpisodeFeatures._creepage_modulation_values`)
CREEPAGE_MODULATION_FEATURE_NAMES = (
    "creepage_modulation_lag", "creepage_modulation_se", "creepage_modulation_swing", "tangent_flexibility_rise",
    "tangent_flexibility_step", "creepage_modulation_lag_1",
)
CREEPAGE_SWING_FLOOR = 1e-6  # the creepage swing per relative torque modulation reads at least ln(this)
# the measured CoA's synchronous average over the cycle (:meth:`EpisodeFeatures._cycle_crest_values`)
CYCLE_CREST_FEATURE_NAMES = ("crest_lift", "trough_drop", "crest_asymmetry", "crest_compression",
                             "crest_bound_lift", "crest_se", "crest_step")
CYCLE_LIFT_FLOOR = 1e-5  # a crest lift or trough drop (ln of a CoA ratio) reads at least this
# regressions over the climb's newest windows (:meth:`EpisodeFeatures._climb_fit_values`)
CLIMB_FIT_FEATURE_NAMES = ("fit_slope_fall_phase", "fit_slope_fall_compliance", "fit_peak_gap_phase",
                           "fit_peak_gap_compliance", "fit_flexibility", "fit_phase_residual", "fit_windows")
CLIMB_FIT_WINDOWS = 8  # the newest driven windows the climb_fit block regresses over
CLIMB_FIT_MIN_SPAN = 1e-3  # a regressor whose spread (std) is below this reads "no fit" (ln DC, CoA / CoA now)
SLOPE_FALL_CLIP = 20.0  # |d ln slope / d ln DC| beyond this reads this
# optional feature blocks appended to FEATURE_NAMES, in this order (a network's file names the ones it reads)
FEATURE_BLOCKS = {"tone2": TONE2_FEATURE_NAMES, "creepage_rise": CREEPAGE_RISE_FEATURE_NAMES,
                  "creepage_modulation": CREEPAGE_MODULATION_FEATURE_NAMES, "cycle_crest": CYCLE_CREST_FEATURE_NAMES,
                  "climb_fit": CLIMB_FIT_FEATURE_NAMES}
TWO_TONE_ENV_OPTIONS = {"excitation": "multitone", "tones": 2}  # the env options a two-tone climb needs


def feature_names(blocks: Iterable[str] = ()) -> tuple[str, ...]:
    """The filter's features with the optional ``blocks`` of :data:`FEATURE_BLOCKS`."""
    blocks = tuple(blocks)
    unknown = sorted(set(blocks) - set(FEATURE_BLOCKS))
    if unknown:
        raise ValueError(f"feature blocks must be among {tuple(FEATURE_BLOCKS)}, got {unknown}")
    return FEATURE_NAMES + tuple(n for b, names in FEATURE_BLOCKS.items() if b in blocks for n in names)


def blocks_of(names: Iterable[str]) -> tuple[str, ...]:
    """The optional blocks (in :data:`FEATURE_BLOCKS` order) whose features are ``names``; ValueError if none."""
    names = tuple(names)
    for k in range(len(FEATURE_BLOCKS) + 1):
        for blocks in itertools.combinations(FEATURE_BLOCKS, k):
            if feature_names(blocks) == names:
                return blocks
    raise ValueError(f"not a feature list of this version ({len(names)} names)")


FLEXIBILITY_CLIP = 5.0  # |ln| of the secant/chord flexibility ratio: beyond it, the step went past the peak
PEAK_GAP_CLIP = 0.5  # ln(peak CoA / CoA) of the quadratic-peak extrapolation: beyond it, "far from the peak"
COMPLIANCE_CLIP = (1e-3, 0.999)  # the slope from the compliance, sqrt(1 / C^2 - 1), is finite within these
CREST_RATIO_FLOOR = 0.03  # the lowest modulation ratio a crest-capped climb uses (and training climbs draw)


def flexibility_ratio(readings: list["Reading"], k: int) -> float:
    """``ln`` of the creep curve's flexibility ``d creepage / d CoA`` over the step into window ``k``
    relative to its chord from the first driven window to window ``k``: 0 on the linear part, rising
    as the curve flattens towards its peak; ``FLEXIBILITY_CLIP`` once the CoA stops rising (past the
    peak), 0 before two windows. Offset-free (differences) and scale-free (a ratio) in the creepage."""
    if k < 2:
        return 0.0
    now, prev, first = readings[k], readings[k - 1], readings[0]
    d_coa, chord_coa = now.coa - prev.coa, now.coa - first.coa
    d_s, chord_s = now.creepage - prev.creepage, now.creepage - first.creepage
    if d_coa <= 0.0 or chord_coa <= 0.0 or chord_s <= 0.0:
        return FLEXIBILITY_CLIP if d_coa <= 0.0 < chord_coa else 0.0
    if d_s <= 0.0:
        return -FLEXIBILITY_CLIP
    return float(np.clip(math.log((d_s / d_coa) / (chord_s / chord_coa)), -FLEXIBILITY_CLIP, FLEXIBILITY_CLIP))


def _se_clipped(se_deg: float) -> float:
    """A lag's standard error (deg) as the filter reads it: :data:`SE_CLIP_DEG` where it is not in (0, that)."""
    return se_deg if 0.0 < se_deg < SE_CLIP_DEG else SE_CLIP_DEG


def _tan_clipped(phase_deg: float) -> float:
    """``tan(phase)`` with the phase clipped to :data:`PHASE_CLIP_DEG` (finite and > 0)."""
    return math.tan(math.radians(min(max(phase_deg, PHASE_CLIP_DEG[0]), PHASE_CLIP_DEG[1])))


def pooled_correction(predictions: Iterable[tuple[float, float]]) -> float:
    """The inverse-variance weighted mean of Gaussian predictions ``(mean, std)`` of one quantity (stds
    floored at 1e-6)."""
    weights_means = [(1.0 / max(std, 1e-6) ** 2, mean) for mean, std in predictions]
    if not weights_means:
        raise ValueError("pooled_correction: no predictions to pool")
    return sum(w * m for w, m in weights_means) / sum(w for w, _ in weights_means)


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


def slope_index(phase_deg: float) -> float:
    """``ln cot(phase)``: the log of the creep curve's local slope in units of the wheel's inertial
    impedance (Eq. 3 of the paper for the half wheelset); falls towards -inf as the phase nears 90 deg."""
    return math.log(1.0 / _tan_clipped(phase_deg))


def slope_from_phase(r: "Reading") -> float:
    """The creep curve's local slope up to a constant of the episode, ``f cot(phase)`` (Hz): Eq. 3 gives
    ``cot(phase) = k r^2 / (I w v)`` for a wheel on a creep curve of slope ``k``."""
    return r.frequency_hz / _tan_clipped(r.phase_deg)


def slope_from_compliance(r: "Reading") -> float:
    """The same slope from the speed/torque amplitude ratio ``C = I w |speed / torque|``:
    ``f sqrt(1 / C^2 - 1)`` (the torque gain error scales it; the phase does not see that error)."""
    c = min(max(r.compliance, COMPLIANCE_CLIP[0]), COMPLIANCE_CLIP[1])
    return r.frequency_hz * math.sqrt(1.0 / c**2 - 1.0)


def _regression_slope(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float] | None:
    """Least-squares line ``y = a + b x``: ``(a, b, residual std)``, or None where ``x`` spreads less than
    :data:`CLIMB_FIT_MIN_SPAN` (no line is determined)."""
    dx = x - x.mean()
    if dx.std() < CLIMB_FIT_MIN_SPAN:
        return None
    b = float(dx @ (y - y.mean()) / (dx @ dx))
    a = float(y.mean() - b * x.mean())
    return a, b, float(np.std(y - a - b * x))


def slope_fall(readings: list["Reading"], slope) -> float:
    """``-d ln(slope) / d ln(DC)`` fitted over ``readings`` (least squares, within
    :data:`SLOPE_FALL_CLIP`): 0 on the creep curve's linear part, growing as the slope falls towards the
    peak; every window of the fit reads, so the lock-in's noise averages out where two windows'
    difference (:func:`peak_gap`) does not. 0 where the DC torques do not spread."""
    fit = _regression_slope(np.log([r.dc_nm for r in readings]), np.log([slope(r) for r in readings]))
    return 0.0 if fit is None else float(np.clip(-fit[1], -SLOPE_FALL_CLIP, SLOPE_FALL_CLIP))


def fitted_peak_gap(readings: list["Reading"], slope) -> float:
    """``ln(peak CoA / CoA)`` of the newest window by the quadratic-peak law fitted over ``readings``:
    near a smooth maximum ``mu = mu_peak - c k^2`` (``k`` the local slope), a line in ``k^2`` whose
    intercept is the peak CoA (slope ratios to the newest window's only: no inertia, radius, load or
    speed). :data:`PEAK_GAP_CLIP` where the slope did not fall as the CoA rose (``c <= 0``: the linear
    part) or beyond it, 0 where the intercept lies below the newest CoA."""
    now = readings[-1]
    k_now = slope(now)
    fit = _regression_slope(np.array([(slope(r) / k_now) ** 2 for r in readings]), np.array([r.coa / now.coa for r in readings]))
    if fit is None or fit[1] >= 0.0:
        return PEAK_GAP_CLIP
    return float(np.clip(math.log(max(fit[0], 1e-9)), 0.0, PEAK_GAP_CLIP))


def fitted_flexibility(readings: list["Reading"], first: "Reading") -> float:
    """``ln`` of the creep curve's flexibility ``d creepage / d CoA`` fitted over ``readings`` (least
    squares) relative to its chord from the first driven window ``first`` to the newest: 0 on the
    linear part, rising as the curve flattens. Offset-free (a slope) and scale-free (a ratio) in the
    creepage, as :func:`flexibility_ratio`; 0 where the CoAs do not spread or the chord is not positive,
    :data:`FLEXIBILITY_CLIP` where the fitted flexibility is not positive while the chord is."""
    now = readings[-1]
    chord_coa, chord_s = now.coa - first.coa, now.creepage - first.creepage
    fit = _regression_slope(np.array([r.coa / now.coa for r in readings]), np.array([r.creepage for r in readings]))
    if fit is None or chord_coa <= 0.0 or chord_s <= 0.0:
        return 0.0
    tangent = fit[1] / now.coa
    if tangent <= 0.0:
        return FLEXIBILITY_CLIP
    return float(np.clip(math.log(tangent / (chord_s / chord_coa)), -FLEXIBILITY_CLIP, FLEXIBILITY_CLIP))


def peak_gap(readings: list["Reading"], i: int, j: int, slope) -> float:
    """``ln(peak CoA / CoA_i)`` extrapolated from windows ``j < i`` by the quadratic-peak law: near a
    smooth maximum ``mu_peak - mu = k^2 / (2 |mu''|)`` with ``k`` the local slope, so two windows give
    ``mu_peak = mu_i + (mu_i - mu_j) k_i^2 / (k_j^2 - k_i^2)``; only slope *ratios* enter (no inertia,
    radius, load or speed). 0 when the CoA did not rise (at or past the peak), :data:`PEAK_GAP_CLIP`
    when the slope did not fall (the linear part: far from the peak) or beyond it."""
    if j < 0:
        return PEAK_GAP_CLIP
    now, before = readings[i], readings[j]
    if now.coa <= before.coa:
        return 0.0
    q_now, q_before = slope(now) ** 2, slope(before) ** 2
    if q_now >= q_before:
        return PEAK_GAP_CLIP
    gap = math.log1p((now.coa - before.coa) / now.coa * q_now / (q_before - q_now))
    return min(gap, PEAK_GAP_CLIP)


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
        has it. A clipped standard error reads low (:attr:`lockin_noise_reported_nms` does not clip it)."""
        return self._noise_at(self.se_deg)

    @property
    def lockin_noise_reported_nms(self) -> float:
        """:attr:`lockin_noise_nms` from the standard error the lock-in reports (:attr:`se_reported_deg`, up to
        180 deg) rather than the filter's clipped one: ``sigma_w sqrt(2 / samples)`` over the fitted amplitude
        times that amplitude, so a window whose fit is poor reads its noise as well as one whose fit is good
        (from the clipped one where it was not read)."""
        return self._noise_at(self.se_reported_deg if self.se_reported_deg > 0.0 else self.se_deg)

    def _noise_at(self, se_deg: float) -> float:
        """The lock-in noise (N m s) of this window's response amplitude at a phase standard error ``se_deg``."""
        return math.radians(se_deg) * self.compliance * self.amplitude_nm / (2.0 * math.pi * self.frequency_hz)

    @classmethod
    def of(cls, observation: np.ndarray, limits: MotorLimits, info: Mapping[str, Any] | None = None) -> "Reading":
        """The window observation's reading; with a two-tone excitation (the observation's per-tone block
        after the window observation) also tone 2's, its applied frequency and amplitude from
        ``info["measurement"]``, and from there the measured creepage's modulation (its lock-in) and the
        crest of the measured CoA's synchronous average."""
        full = np.nan_to_num(np.asarray(observation, dtype=np.float64), nan=0.0)
        o = full[: len(OBSERVATION_NAMES)]
        se_deg = o[_INDEX["phase_lag_se"]] * 90.0
        tone2 = {}
        measurement = (info or {}).get("measurement", {})
        if len(full) >= len(OBSERVATION_NAMES) + 6 and "tone2_frequency_hz" in measurement:
            phase2, se2, compliance2 = full[len(OBSERVATION_NAMES) + 3: len(OBSERVATION_NAMES) + 6]
            tone2 = {"tone2_phase_deg": float(phase2 * 90.0),
                     "tone2_se_deg": float(_se_clipped(se2 * 90.0)),
                     "tone2_compliance": float(compliance2),
                     "tone2_frequency_hz": float(measurement["tone2_frequency_hz"]),
                     "tone2_amplitude_nm": float(measurement["tone2_amplitude_nm"])}
        if "creepage_modulation_amplitude" in measurement:
            tone2.update(creepage_modulation=float(measurement["creepage_modulation_amplitude"]),
                         creepage_modulation_lag_deg=float(measurement["creepage_modulation_lag_deg"]),
                         creepage_modulation_se_deg=float(_se_clipped(measurement["creepage_modulation_lag_se_deg"])))
        if "coa_cycle_max" in measurement:  # the same names as the sensor fields
            tone2.update({name: float(measurement[name]) for name in COA_CYCLE_FIELDS})
        return cls(
            phase_deg=float(o[_INDEX["phase_lag"]] * 90.0),
            se_deg=float(_se_clipped(se_deg)),
            se_reported_deg=float(min(max(se_deg, 0.0), SE_REPORTED_MAX_DEG)),
            compliance=float(o[_INDEX["compliance"]]),
            coa=float(max(o[_INDEX["coa_measured"]], 1e-4)),
            creepage=float(o[_INDEX["creepage_measured"]] / CREEPAGE_SCALE),
            dc_nm=float(o[_INDEX["dc_torque"]] * limits.max_dc_torque_nm),
            amplitude_nm=float(o[_INDEX["amplitude"]] * limits.max_amplitude_nm),
            frequency_hz=float(o[_INDEX["frequency"]] * limits.max_frequency_hz),
            speed_m_s=float(o[_INDEX["speed"]] * SPEED_SCALE_M_S),
            normal_load=float(o[_INDEX["normal_load"]]),
            **tone2,
        )

    def tone2(self) -> "Reading":
        """This window as tone 2 alone sees it (its phase, SE, compliance and frequency in tone 1's place)."""
        return replace(self, phase_deg=self.tone2_phase_deg, se_deg=self.tone2_se_deg,
                       compliance=self.tone2_compliance, frequency_hz=self.tone2_frequency_hz)


@dataclass
class EpisodeFeatures:
    """The driven windows of an episode, and the filter's feature vector of the newest one
    (:data:`FEATURE_NAMES`). The same class builds the training data and runs on board."""

    counter_torque: bool
    readings: list[Reading] = field(default_factory=list)
    blocks: tuple[str, ...] = ()  # optional feature blocks appended (:data:`FEATURE_BLOCKS`)

    def __post_init__(self) -> None:
        feature_names(self.blocks)  # an unknown block: ValueError naming the allowed ones

    def push(self, reading: Reading) -> None:
        if reading.dc_nm <= 0.0:
            raise ValueError("EpisodeFeatures.push takes driven windows (DC torque > 0)")
        if "tone2" in self.blocks and reading.tone2_frequency_hz <= 0.0:
            raise ValueError("EpisodeFeatures with the tone2 block takes two-tone readings (tone2_frequency_hz > 0)")
        if "cycle_crest" in self.blocks and not reading.coa_cycle_max > 0.0:
            raise ValueError("EpisodeFeatures with the cycle_crest block takes readings of the CoA's cycle crest "
                             "(coa_cycle_max > 0): climbs recorded before that reading must be collected again")
        self.readings.append(reading)

    def _creepage_rise_values(self) -> list[float]:
        """:data:`CREEPAGE_RISE_FEATURE_NAMES`: ``ln`` of the measured creepage's rise since the first driven
        window, of that rise per CoA rise (the creep curve's chord flexibility) and of the last step's
        rise, each floored (:data:`CREEPAGE_RISE_FLOORS`). A difference of creepages: the sensors' offset
        (of the size of the peak creepage) cancels, their scale error of a percent or two scales it."""
        now, first, prev = self.readings[-1], self.readings[0], self.readings[max(len(self.readings) - 2, 0)]
        rise, coa_rise = now.creepage - first.creepage, now.coa - first.coa
        floor_rise, floor_chord, floor_step = CREEPAGE_RISE_FLOORS
        chord = max(rise / coa_rise, floor_chord) if coa_rise > 0.0 else floor_chord
        return [math.log(max(rise, floor_rise)), math.log(chord), math.log(max(now.creepage - prev.creepage, floor_step))]

    def _creepage_modulation_values(self) -> list[float]:
        """:data:`CREEPAGE_MODULATION_FEATURE_NAMES`: the measured creepage's modulation (a lock-in of
        ``R omega / v - 1`` at the torque's frequency): its lag behind the torque and that lag's SE (which
        tells a reading from the sensors' noise), ``ln`` of its swing per relative torque modulation
        (``ds / (dM / M)``: the creepage a relative torque step moves, the creep curve's local
        flexibility times the CoA), and ``ln`` of its swing per torque (the tangent flexibility
        ``ds / dM``) over the first driven window's and over the previous window's. The creepage's
        offset has gone with its DC level; its scale error moves these by a percent or two."""
        now, first, prev = self.readings[-1], self.readings[0], self.readings[max(len(self.readings) - 2, 0)]
        tangent = lambda r: max(r.creepage_modulation, CREEPAGE_SWING_FLOOR) / max(r.amplitude_nm, 1e-9)  # noqa: E731
        swing = max(now.creepage_modulation, CREEPAGE_SWING_FLOOR) * now.dc_nm / max(now.amplitude_nm, 1e-9)
        return [now.creepage_modulation_lag_deg / 90.0, now.creepage_modulation_se_deg / SE_CLIP_DEG,
                math.log(max(swing, CREEPAGE_SWING_FLOOR)), math.log(tangent(now) / tangent(first)),
                math.log(tangent(now) / tangent(prev)), prev.creepage_modulation_lag_deg / 90.0]

    def _cycle_crest_values(self) -> list[float]:
        """:data:`CYCLE_CREST_FEATURE_NAMES`: ``ln`` of the cycle crest over the window's mean CoA and of the
        mean over the trough (each at least :data:`CYCLE_LIFT_FLOOR`), ``ln`` of their ratio (0 for a
        response as linear as the torque's sine, below 0 once the crest is clipped at the peak), the crest's
        lift over the torque crest's ``ln(1 + amplitude / DC)``, ``ln`` of the climb's best crest bound over
        the CoA (:attr:`Reading.crest_bound`: the correction ``ln(CoF / CoA)`` is at least about this),
        a bin's standard error over the CoA, and ``ln`` of the crest over the previous window's. Every one
        is a ratio of force readings: the force gain's error cancels."""
        now, prev = self.readings[-1], self.readings[max(len(self.readings) - 2, 0)]
        crest, trough = max(now.coa_cycle_max, now.coa), min(now.coa_cycle_min, now.coa)
        lift = max(math.log(crest / now.coa), CYCLE_LIFT_FLOOR)
        drop = max(math.log(now.coa / trough), CYCLE_LIFT_FLOOR) if trough > 0.0 else 1.0
        best = max(max(r.crest_bound for r in self.readings), now.coa)
        return [lift, drop, math.log(lift / drop), lift / math.log1p(now.amplitude_nm / now.dc_nm),
                math.log(best / now.coa), now.coa_cycle_bin_se / now.coa,
                math.log(crest / max(prev.coa_cycle_max, prev.coa))]

    def _climb_fit_values(self) -> list[float]:
        """:data:`CLIMB_FIT_FEATURE_NAMES`: regressions over the newest :data:`CLIMB_FIT_WINDOWS` driven
        windows, where the base features read one, two or three windows: the slope's fall per log torque
        from the phase and from the compliance (:func:`slope_fall`), the quadratic-peak gap fitted over
        all of them (:func:`fitted_peak_gap`, both slopes), the creep curve's fitted flexibility over its
        chord (:func:`fitted_flexibility`), the slope index's residual about its line (the lock-in's
        scatter, in the units of ``ln cot(phase)``) and the share of the windows read. A slow probe's
        many windows at nearly one torque each add a reading of the same slope: the fit averages them."""
        newest = self.readings[-CLIMB_FIT_WINDOWS:]
        fit = _regression_slope(np.log([r.dc_nm for r in newest]), np.array([slope_index(r.phase_deg) for r in newest]))
        return [slope_fall(newest, slope_from_phase), slope_fall(newest, slope_from_compliance),
                fitted_peak_gap(newest, slope_from_phase), fitted_peak_gap(newest, slope_from_compliance),
                fitted_flexibility(newest, self.readings[0]), 0.0 if fit is None else fit[2],
                len(newest) / CLIMB_FIT_WINDOWS]

    def _tone2_values(self) -> list[float]:
        """Tone 2's features (:data:`TONE2_FEATURE_NAMES`): its lag, SE, compliance, slope index and
        their change, its quadratic-peak gap, the lag's dispersion ``ln(tan lag_2 / tan lag_1) /
        ln(f_2 / f_1)`` (1 for the half wheelset's first-order response of Eq. 3), its frequency and
        its share of the modulation."""
        views = [r.tone2() for r in self.readings]
        now, first, prev = views[-1], views[0], views[max(len(views) - 2, 0)]
        i = len(views) - 1
        tone1 = self.readings[-1]
        ratio = now.frequency_hz / tone1.frequency_hz
        dispersion = (math.log(_tan_clipped(now.phase_deg) / _tan_clipped(tone1.phase_deg)) / math.log(ratio)
                      if abs(math.log(ratio)) > 1e-3 else 0.0)
        return [now.phase_deg / 90.0, now.se_deg / SE_CLIP_DEG, now.compliance, slope_index(now.phase_deg),
                slope_index(first.phase_deg) - slope_index(now.phase_deg),
                math.log(slope_from_phase(now) / slope_from_phase(prev)),
                peak_gap(views, i, i - 1, slope_from_phase), dispersion, now.frequency_hz / 20.0,
                now.tone2_amplitude_nm / max(now.amplitude_nm, 1e-9), prev.phase_deg / 90.0]

    def vector(self) -> np.ndarray:
        if not self.readings:
            raise ValueError("no driven window yet")
        now, first = self.readings[-1], self.readings[0]
        slope = slope_index(now.phase_deg)
        values = [
            now.phase_deg / 90.0, now.se_deg / SE_CLIP_DEG, now.compliance, slope,
            slope_index(first.phase_deg) - slope, (now.phase_deg - first.phase_deg) / 90.0,
            now.compliance - first.compliance, math.log(now.coa / first.coa), math.log(now.dc_nm / first.dc_nm),
            math.log(now.coa), now.amplitude_nm / now.dc_nm, now.frequency_hz / 20.0, now.speed_m_s / 40.0,
            now.normal_load, float(self.counter_torque), len(self.readings) / 30.0,
            flexibility_ratio(self.readings, len(self.readings) - 1),
        ]
        for k in range(1, HISTORY + 1):
            j = max(len(self.readings) - 1 - k, 0)
            prev = self.readings[j]
            values += [prev.phase_deg / 90.0, slope_index(prev.phase_deg), math.log(prev.coa / now.coa),
                       math.log(prev.dc_nm / now.dc_nm), flexibility_ratio(self.readings, j)]
        i = len(self.readings) - 1
        prev = self.readings[max(i - 1, 0)]
        values += [peak_gap(self.readings, i, i - 1, slope_from_phase),
                   peak_gap(self.readings, i, i - 1, slope_from_compliance),
                   peak_gap(self.readings, i, i - 2, slope_from_phase),
                   math.log(slope_from_phase(now) / slope_from_phase(prev)),
                   math.log(slope_from_compliance(now) / slope_from_compliance(prev))]
        if "tone2" in self.blocks:
            values += self._tone2_values()
        if "creepage_rise" in self.blocks:
            values += self._creepage_rise_values()
        if "creepage_modulation" in self.blocks:
            values += self._creepage_modulation_values()
        if "cycle_crest" in self.blocks:
            values += self._cycle_crest_values()
        if "climb_fit" in self.blocks:
            values += self._climb_fit_values()
        return np.nan_to_num(np.asarray(values, dtype=np.float64), nan=0.0, posinf=0.0, neginf=0.0)


@dataclass(frozen=True)
class FilterNetwork:
    """One member: a tanh MLP on standardised features giving (mean, log variance) of each target."""

    feature_mean: np.ndarray
    feature_std: np.ndarray
    weights: tuple[np.ndarray, ...]
    biases: tuple[np.ndarray, ...]
    feature_names: tuple[str, ...] = FEATURE_NAMES  # :func:`feature_names` of the blocks it reads

    @property
    def blocks(self) -> tuple[str, ...]:
        return blocks_of(self.feature_names)

    @property
    def tones(self) -> int:
        return 2 if "tone2" in self.blocks else 1

    def __call__(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        h = (np.atleast_2d(x) - self.feature_mean) / self.feature_std
        for w, b in zip(self.weights[:-1], self.biases[:-1]):
            h = np.tanh(h @ w + b)
        out = h @ self.weights[-1] + self.biases[-1]
        n = len(TARGET_NAMES)
        return out[:, :n], np.clip(out[:, n:], -12.0, 4.0)

    def save(self, path: Path) -> None:
        arrays = {"feature_mean": self.feature_mean, "feature_std": self.feature_std}
        arrays |= {f"w{i}": w for i, w in enumerate(self.weights)} | {f"b{i}": b for i, b in enumerate(self.biases)}
        np.savez(path, feature_names=np.asarray(self.feature_names), **arrays)

    @classmethod
    def load(cls, path: Path) -> "FilterNetwork":
        with np.load(path) as z:
            names = tuple(str(n) for n in z["feature_names"])
            try:
                blocks_of(names)
            except ValueError:
                raise ValueError(f"{path}: the network was trained on other features ({len(names)} names); retrain it") from None
            layers = sum(1 for k in z.files if k.startswith("w"))
            return cls(z["feature_mean"], z["feature_std"], tuple(z[f"w{i}"] for i in range(layers)),
                       tuple(z[f"b{i}"] for i in range(layers)), names)


@dataclass(frozen=True)
class FilterEnsemble:
    """Members' Gaussian predictions combined: the mean of the means, the variance their spread plus
    the mean predicted variance."""

    members: tuple[FilterNetwork, ...]

    def __post_init__(self) -> None:
        if len({m.feature_names for m in self.members}) > 1:
            raise ValueError("the ensemble's members read different features (tones or blocks); fit them alike")

    @property
    def blocks(self) -> tuple[str, ...]:
        return self.members[0].blocks

    @property
    def tones(self) -> int:
        return self.members[0].tones

    def predict(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(mean, std) of every target, shape (n, 2) each."""
        mean, std, _ = self.predict_with_spread(x)
        return mean, std

    def predict_with_spread(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(mean, std, spread) of every target, shape (n, 2) each: the mixture's std (the members'
        spread and their mean predicted variance together; Lakshminarayanan et al. 2017) and the
        members' spread alone (their disagreement: large where the readings are unlike the training
        climbs')."""
        outs = [m(x) for m in self.members]
        means = np.stack([o[0] for o in outs])
        variances = np.stack([np.exp(o[1]) for o in outs])
        spread_var = means.var(axis=0)
        return means.mean(axis=0), np.sqrt(spread_var + variances.mean(axis=0)), np.sqrt(spread_var)

    @classmethod
    def load(cls, directory: Path, members: list[str] | None = None) -> "FilterEnsemble":
        directory = Path(directory)
        files = [directory / f"{m}.npz" for m in members] if members else sorted(directory.glob("member_*.npz"))
        if not files or not all(f.is_file() for f in files):
            raise FileNotFoundError(f"no interrogator networks in {directory} (expected member_*.npz)")
        return cls(tuple(FilterNetwork.load(f) for f in files))


def first_windows_noise_nms(readings: list[Reading], reported: bool = False) -> float:
    """The noise a climb reads from its first :data:`NOISE_WINDOWS` driven ``readings`` (N m s): the median of their
    :attr:`Reading.lockin_noise_nms`, or with ``reported`` of their :attr:`Reading.lockin_noise_reported_nms`."""
    return float(np.median([r.lockin_noise_reported_nms if reported else r.lockin_noise_nms
                            for r in readings[:NOISE_WINDOWS]]))


@dataclass(frozen=True)
class ClimbParameters:
    """The climb's settings (chosen on validation; see the module docstring)."""

    amplitude_ratio: float = 0.1  # modulation amplitude / DC torque
    min_amplitude_nm: float = 50.0
    frequency_hz: float = 5.0
    # not None: below this speed (m/s) the frequency rises as 1 / speed (frequency_at), up to the drive's
    frequency_reference_m_s: float | None = None
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
    creep_until: float | None = None  # not None: no creep once the predicted (mean) headroom is this low
    estimate_from: str = "filter"  # "filter": CoA x exp(predicted correction); "best_coa": best CoA x factor;
    # "guard": CoA x exp(the guards' correction); "pooled": CoA x exp(the filter's and the guards' together);
    # "pooled_at_headroom": "pooled" once the climb stops on its headroom, "filter" before and otherwise;
    # "estimator": CoA x exp(the estimators' correction); "estimator_pooled": the filter's, guards' and estimators'
    # pooled; "estimator_pooled_at_headroom": that pool at a headroom stop, "filter" before and otherwise;
    # "estimator_at_headroom": the estimators' correction alone at a headroom stop, "filter" before and otherwise
    best_coa_factor: float = 1.0
    floor_margin: float | None = None  # not None: a step may close the gap to the task's lowest CoF less this
    tone2_frequency_hz: float | None = None  # not None: a second tone at this frequency (a two-tone excitation)
    tone2_weight: float = 1.0  # its weight against tone 1's 1 (the env's share_2 + 1, in [0, 2])
    crest_fraction: float | None = None  # not None: the crest stays within this fraction of the cautious headroom
    crest_once_crept: bool = False  # the crest cap only from the climb's first slow probe on
    crest_floor: bool = False  # the estimate at least the climb's best crest bound (Reading.crest_bound)
    runaway_estimate: bool = False  # a window that is not a stop reports what a runaway in it would (RunawayBracket)
    pace_caution: float | None = None  # not None: a slow-probe step at least the horizon pace (pace_step)
    knee_stop: str | None = None  # "any" / "slow_probe": the phase rule's jump test ends the climb (knee_stops)
    crest_ceiling: bool = False  # once the crest fell under a rising torque crest, every estimate at most CrestCeiling's
    ceiling_stop: bool = False  # the climb ends at the window where the crest falls under a rising torque crest
    ceiling_fall_z: float = 0.0  # a crest fall counts (crest_ceiling, ceiling_stop) beyond this many SEs (CrestCeiling.fall_z)
    ceiling_near_headroom: float | None = None  # not None: ... only where the predicted headroom is above this
    # not None: where the climb's first windows read more noise than this (N m s, noise_ratio), it follows it (at_noise)
    noise_reference_nms: float | None = None
    noise_caution_exponent: float = 0.0  # ... its cautions scale as (noise ratio) ** -this
    noise_creep_exponent: float = 0.0  # ... and creep_while_std as (noise ratio) ** this
    noise_se_reported: bool = False  # the noise reading from the lock-in's reported SE (lockin_noise_reported_nms)
    # not None: a headroom stop is deferred by a slow-probe step while the lag has risen this much (deg) since the
    # first driven window and the crest still rises (probes_on)
    crest_probe_lag_rise_deg: float | None = None
    crest_probe_max_lag_deg: float | None = None  # not None: ... and the window's lag is at most this (deg)
    crest_probe_max_lag_step_deg: float | None = None  # not None: ... and its lag rose at most this over the last (deg)
    # not None: ... and only where the climb's first windows read at most this noise ratio (noise_ratio, >= 1)
    crest_probe_max_noise_ratio: float | None = None
    # true: from the window the probe starts at, no later window's torque crest above that window's (held_crest_ratio)
    crest_probe_hold_crest: bool = False

    def __post_init__(self) -> None:
        if self.estimate_from not in ESTIMATE_SOURCES:
            raise ValueError(f"estimate_from must be one of {ESTIMATE_SOURCES}, got {self.estimate_from!r}")
        for name in ("amplitude_ratio", "min_amplitude_nm", "frequency_hz", "max_log_step", "min_log_step",
                     "best_coa_factor", "creep_while_std"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
        if not (isinstance(self.approach_fraction, (int, float)) and 0.0 <= self.approach_fraction < 1.0):
            raise ValueError(f"approach_fraction must be in [0, 1), got {self.approach_fraction!r}")
        for name, low in (("floor_margin", 0.0), ("creep_until", -math.inf), ("crest_fraction", 0.0),
                          ("creep_release", 0.0), ("ceiling_near_headroom", 0.0)):  # None: unused
            if getattr(self, name) is not None:
                check_number(name, getattr(self, name), low, math.inf)
        for name in ("creep_sticky", "crest_once_crept", "crest_floor", "runaway_estimate", "crest_ceiling",
                     "ceiling_stop", "noise_se_reported", "crest_probe_hold_crest"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{name} must be true or false, got {getattr(self, name)!r}")
        if self.tone2_frequency_hz is not None:
            check_number("tone2_frequency_hz", self.tone2_frequency_hz, MotorLimits.min_frequency_hz,
                         MotorLimits.max_frequency_hz)
        check_number("tone2_weight", self.tone2_weight, 0.0, 2.0)
        check_number("spread_caution", self.spread_caution, 0.0, 10.0)
        check_number("ceiling_fall_z", self.ceiling_fall_z, 0.0, 10.0)
        if self.noise_reference_nms is not None:
            check_number("noise_reference_nms", self.noise_reference_nms, 0.0, math.inf, low_open=True, unit=" N m s")
        check_number("noise_caution_exponent", self.noise_caution_exponent, 0.0, 2.0)
        check_number("noise_creep_exponent", self.noise_creep_exponent, 0.0, 2.0)
        if self.guard_cautions is not None:
            if not isinstance(self.guard_cautions, (list, tuple)) or not self.guard_cautions:
                raise ValueError("guard_cautions must be null or a non-empty list of numbers in [0, 10] (one per "
                                 f"guard), got {self.guard_cautions!r}")
            object.__setattr__(self, "guard_cautions", tuple(
                check_number(f"guard_cautions[{i}]", c, 0.0, 10.0) for i, c in enumerate(self.guard_cautions)))
        check_number("caution", self.caution, 0.0, 10.0)
        check_number("target_headroom", self.target_headroom, 0.0, 5.0)
        if self.pace_caution is not None:
            check_number("pace_caution", self.pace_caution, 0.0, 10.0)
        if self.frequency_reference_m_s is not None:
            check_number("frequency_reference_m_s", self.frequency_reference_m_s, 0.0, 100.0, low_open=True, unit=" m/s")
        if self.knee_stop not in KNEE_STOPS:
            raise ValueError(f"knee_stop must be one of {KNEE_STOPS}, got {self.knee_stop!r}")
        if not (isinstance(self.creep_log_step, (int, float)) and 0.0 <= self.creep_log_step <= self.max_log_step):
            raise ValueError(f"creep_log_step must be in [0, max_log_step={self.max_log_step}], got {self.creep_log_step!r}")
        for name in ("crest_probe_max_lag_deg", "crest_probe_max_lag_step_deg"):
            if getattr(self, name) is not None:
                check_number(name, getattr(self, name), 0.0, 180.0, unit=" deg")
        if self.crest_probe_max_noise_ratio is not None:
            check_number("crest_probe_max_noise_ratio", self.crest_probe_max_noise_ratio, 1.0, math.inf)
            if self.noise_reference_nms is None:
                raise ValueError("crest_probe_max_noise_ratio reads the noise ratio, which needs noise_reference_nms")
        if self.crest_probe_lag_rise_deg is not None:
            check_number("crest_probe_lag_rise_deg", self.crest_probe_lag_rise_deg, 0.0, 180.0, unit=" deg")
            if self.creep_log_step < self.min_log_step:
                raise ValueError(f"crest_probe_lag_rise_deg probes at creep_log_step, which must then be at least "
                                 f"min_log_step={self.min_log_step}, got {self.creep_log_step!r}")

    def fall_margin(self, mean_headroom: float) -> float:
        """The standard errors a crest fall must exceed to count (:class:`~cof_gym.agents.runaway.CrestCeiling`)
        at a window whose predicted (mean) headroom is ``mean_headroom``: ``ceiling_fall_z``, or with
        ``ceiling_near_headroom`` 0 where that headroom is at most it (the climb expects the peak: a crest that
        stops rising there is the peak's) and ``ceiling_fall_z`` beyond it (far from the expected peak a small
        fall is more likely the sensors' noise)."""
        near = self.ceiling_near_headroom is not None and mean_headroom <= self.ceiling_near_headroom
        return 0.0 if near else self.ceiling_fall_z

    def noise_ratio(self, readings: list["Reading"]) -> float:
        """How far the noise read over the climb's first :data:`NOISE_WINDOWS` driven ``readings`` (the median
        of their :attr:`Reading.lockin_noise_nms`, or with ``noise_se_reported`` their
        :attr:`Reading.lockin_noise_reported_nms`) is above ``noise_reference_nms``: that ratio, at least 1;
        1 without a reference or a reading."""
        if self.noise_reference_nms is None or not readings:
            return 1.0
        return max(1.0, first_windows_noise_nms(readings, self.noise_se_reported) / self.noise_reference_nms)

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
        """Whether the next step is the slow probe: the cautious gap is closed, the headroom uncertain
        and, with ``creep_until``, the predicted (mean) headroom still above it."""
        return (self.creep_log_step > 0.0 and headroom_std > self.creep_while_std
                and self._gap_step(cautious_headroom) < self.min_log_step
                and (self.creep_until is None
                     or self.mean_headroom(cautious_headroom, headroom_std, spread, caution) > self.creep_until))

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
        windows ``readings`` takes one more slow-probe step instead: its lag has risen at least that much since
        the first of them (the slope has fallen: the knee is passed; the drive's own lag cancels in the rise) and
        the newest window's crest is above the one before (:attr:`Reading.coa_cycle_max`). A curve that rises
        slowly past its knee keeps a large lag under a crest that still rises, and its peak lies far above
        (experiments/knee_twins.py); at a rounded peak the crest falls under a rising torque crest and the
        ceiling stop ends the climb. With ``crest_probe_max_lag_deg`` the window's lag must also be at most that (near
        90 deg the slope has vanished and the crest's rise is the sensors' noise), and with
        ``crest_probe_max_lag_step_deg`` its rise over the previous window's at most that (a lag that jumps from
        window to window is a sharp knee's, not a slow rise's). With ``crest_probe_max_noise_ratio`` only where the
        climb's first windows read at most that ratio of ``noise_reference_nms`` (:meth:`noise_ratio`): the lag's
        and the crest's rises are read against the noise of the sensors the networks were fitted on."""
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

    def frequency_at(self, speed_m_s: float, limits: MotorLimits) -> float:
        """The modulation frequency (Hz) of a climb at the measured speed ``speed_m_s``: ``frequency_hz``, or
        with ``frequency_reference_m_s`` that times ``max(1, reference / speed)``, within the drive's range.
        Eq. 3's lag is ``atan(I w v / (k r^2))``: at a low speed it stays small and flat until the slope
        ``k`` has nearly vanished; a frequency rising as ``1 / v`` keeps ``w v`` (the lag's sensitivity to
        the slope) at least the reference speed's."""
        if self.frequency_reference_m_s is None:
            return self.frequency_hz
        return speed_scaled_frequency(self.frequency_hz, self.frequency_reference_m_s, speed_m_s, limits)

    def amplitude(self, dc_nm: float, limits: MotorLimits, ratio: float | None = None) -> float:
        """The modulation amplitude (N m) at DC torque ``dc_nm``: ``ratio`` (default ``amplitude_ratio``) of
        it, within the drive's range (with two tones the total: ``tone2_weight / (1 + tone2_weight)`` of it
        is tone 2's)."""
        return probe_amplitude(self.amplitude_ratio if ratio is None else ratio, dc_nm, self.min_amplitude_nm, limits)

    def crest_ratio(self, cautious_headroom_after: float, crept: bool = True) -> float:
        """The modulation ratio at a DC torque whose cautious headroom is ``cautious_headroom_after``:
        ``amplitude_ratio``, or with ``crest_fraction`` at most ``exp(crest_fraction x headroom) - 1``, so
        that the crest ``DC (1 + ratio)`` stays that fraction (in log units) of the way from the DC to the
        cautiously predicted saturation torque, and at least :data:`CREST_RATIO_FLOOR` (the lowest ratio
        of the training climbs: below it the lock-in reads noise); with ``crest_once_crept`` only once the
        climb has ``crept`` (its slow probe, where the filter thinks the peak may be near)."""
        if self.crest_fraction is None or (self.crest_once_crept and not crept):
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

    def action(self, dc_nm: float, estimate: float, stop: bool, limits: MotorLimits,
               ratio: float | None = None, frequency_hz: float | None = None) -> np.ndarray:
        """The env action (modulation ``ratio`` of the DC, default ``amplitude_ratio``, at ``frequency_hz``,
        default ``self.frequency_hz``): the window action, and tone 2's frequency and weight with two tones."""
        frequency = self.frequency_hz if frequency_hz is None else frequency_hz
        base = encode_action(dc_nm, self.amplitude(dc_nm, limits, ratio), frequency, estimate, stop, limits)
        if self.tones == 1:
            return base
        extra = encode_extra_tones([(self.tone2_frequency_hz, self.tone2_weight)], limits.min_frequency_hz,
                                   limits.max_frequency_hz)
        return np.concatenate([base, extra]).astype(np.float32)


@dataclass(frozen=True)
class WindowDecision:
    """What the climb decided after one driven window (log units; a diagnostic, :attr:`LearnedInterrogator.decisions`):
    the filter's predicted headroom ``ln(M_sat / DC)`` and its std, the cautious headroom that steered
    (the filter's or a guard's, whichever is lower) and its std, the log step taken (0 at the stop), whether
    the climb has crept, and the stop's reason ("" before it). The drive's limit may cap the step's torque."""

    filter_headroom: float
    filter_std: float
    steering_headroom: float
    steering_std: float
    log_step: float
    crept: bool
    stop_reason: str


@dataclass
class LearnedInterrogator:
    """The agent (see the module docstring)."""

    limits: MotorLimits
    ensemble: FilterEnsemble
    counter_torque: bool = False
    params: ClimbParameters = field(default_factory=ClimbParameters)
    max_windows: int = 30
    name: str = "interrogator"
    oracle: bool = False
    climb: ElasticityClimb = field(default_factory=ElasticityClimb, repr=False)
    features: EpisodeFeatures = field(init=False, repr=False)
    stop_reason: str = field(default="", repr=False)
    trained_on: tuple[str, tuple[dict[str, Any], ...]] | None = None  # (env id, vehicle configurations)
    guards: tuple[FilterEnsemble, ...] = ()  # further filters that may only slow the climb (module docstring)
    estimators: tuple[FilterEnsemble, ...] = ()  # further filters whose correction the estimate may read
    _guard_features: tuple[EpisodeFeatures, ...] = field(default=(), repr=False)
    _estimator_features: tuple[EpisodeFeatures, ...] = field(default=(), repr=False)
    _dc: float = 0.0
    _source_estimates: dict[str, float] = field(default_factory=dict, repr=False)  # per guarded/filter source
    _estimate: float = 0.0
    _best_coa: float = 0.0
    _driven: int = 0
    _crept: bool = False
    _ratio: float | None = None  # the modulation ratio of the next window (None: the climb's amplitude_ratio)
    _held_crest: float | None = None  # the torque crest the probe holds (N m; crest_probe_hold_crest)
    _frequency: float | None = None  # the episode's modulation frequency (Hz), from the first observation's speed
    _bracket: RunawayBracket = field(default_factory=RunawayBracket, repr=False)
    _ceiling: CrestCeiling = field(default_factory=CrestCeiling, repr=False)
    _runaway: float | None = None  # what a runaway in the coming window would report (None: a stop, or no crest yet)
    decisions: list[WindowDecision] = field(default_factory=list, repr=False)  # this episode's, one per driven window

    def __post_init__(self) -> None:
        if self.ensemble.tones != self.params.tones:
            raise ValueError(f"the climb drives {self.params.tones} tone(s) but the networks read "
                             f"{self.ensemble.tones}: use networks fitted on that excitation")
        for role, networks in (("guard", self.guards), ("estimator", self.estimators)):
            if any(g.tones != self.params.tones for g in networks):
                raise ValueError(f"a {role} reads another excitation than the climb's {self.params.tones} tone(s): "
                                 f"use {role} networks fitted on that excitation")
        self.params.check_guard_count(len(self.guards))
        for role, sources, networks in (("guards", GUARDED_ESTIMATES, self.guards),
                                        ("estimators", ESTIMATOR_ESTIMATES, self.estimators)):
            if self.params.estimate_from in sources and not networks:
                raise ValueError(f"estimate_from={self.params.estimate_from!r} reads the {role}' corrections, "
                                 f"but the interrogator has no {role}")

    @property
    def env_options(self) -> dict[str, Any]:
        """The env options the agent acts in (its excitation), beyond the suite's."""
        return self.params.env_options

    def distribution_note(self, env_id: str, env_kwargs: dict[str, Any],
                          episodes: Iterable[Mapping[str, Any]] = ()) -> str | None:
        """A line naming every way an evaluation lies outside the training distribution (another env id or a
        vehicle configuration it was not trained on, a longer horizon than its training climbs had, other
        scenario draws, or episodes whose fixed options none of its training draws give:
        :func:`~cof_gym.task.scenarios.outside_draws`), None when it does not."""
        if self.trained_on is None:
            return None
        notes = (self._configuration_note(env_id, env_kwargs), self._horizon_note(env_id, env_kwargs),
                 self._draws_note(env_id, env_kwargs, episodes))
        return "; ".join(n for n in notes if n) or None

    def _configuration_note(self, env_id: str, env_kwargs: dict[str, Any]) -> str | None:
        trained_id, configs = self.trained_on
        # an argument equal to the env's default is the env made without it
        world = lambda env, kw: without_defaults(env, {k: v for k, v in kw.items() if k in WORLD_KWARGS})  # noqa: E731
        return configuration_note(self.name, env_id, world(env_id, env_kwargs), trained_id,
                                  [world(trained_id, c) for c in configs])

    def _horizon_note(self, env_id: str, env_kwargs: dict[str, Any]) -> str | None:
        """A shorter horizon plays a prefix of the climbs it learned from; a longer one climbs past all of them."""
        trained_id, configs = self.trained_on
        horizon = {**env_defaults(env_id), **env_kwargs}.get("max_windows")
        trained_horizon = max({**env_defaults(trained_id), **c}.get("max_windows") for c in configs)
        if horizon <= trained_horizon:
            return None
        return (f"{self.name} is out of its training distribution here: max_windows={horizon} (its training "
                f"climbs had a horizon of {trained_horizon})")

    def _draws_note(self, env_id: str, env_kwargs: dict[str, Any], episodes: Iterable[Mapping[str, Any]]) -> str | None:
        trained = registered_ranges(self.trained_on[0])
        if registered_ranges(env_id, env_kwargs) != trained:
            return f"{self.name}: the suite's scenario draws (ranges) are not its training draws: out of its training distribution"
        # scenario fields fixed as constructor arguments count as every episode's options
        return outside_training_note(self.name, trained, episode_scenarios(env_kwargs, episodes))

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        if self.params.tones == 2 and "tone2_frequency_hz" not in info.get("measurement", {}):
            raise ValueError(f"{self.name} drives two tones: make its env with {self.env_options} "
                             "(cof-gym evaluate does that itself)")
        self.features = EpisodeFeatures(self.counter_torque, blocks=self.ensemble.blocks)
        self._guard_features = tuple(EpisodeFeatures(self.counter_torque, blocks=g.blocks) for g in self.guards)
        self._estimator_features = tuple(EpisodeFeatures(self.counter_torque, blocks=e.blocks) for e in self.estimators)
        self._dc = 0.0
        self._driven = 0
        self._crept = False
        self._ratio = None
        self._held_crest = None
        self._frequency = None
        self._best_coa = 0.0
        self._bracket = RunawayBracket()
        self._ceiling = CrestCeiling(fall_z=self.params.ceiling_fall_z)
        self._runaway = None
        self._source_estimates = {}
        self.decisions = []
        self._estimate = self.limits.min_cof_estimate
        self.stop_reason = ""

    @property
    def dc_nm(self) -> float:
        """The DC torque (N m) of the window the last action drives (0 before the first)."""
        return self._dc

    @property
    def crept(self) -> bool:
        """Whether the climb of this episode has taken its slow probe (it may since have stopped)."""
        return self._crept

    def candidate_estimates(self, best_coa_factor: float) -> dict[str, float]:
        """The estimate of each source of :data:`ESTIMATE_SOURCES` after the windows so far (the
        trajectory does not depend on which one is reported; the guarded sources are 0 without guards, the
        estimators' without estimators; with ``crest_floor`` each at least the climb's best crest bound;
        with ``runaway_estimate``, after an action that is not a stop, each the runaway's estimate; with
        ``crest_ceiling``, once the crest has fallen under a rising torque crest, each at most
        :class:`~cof_gym.agents.runaway.CrestCeiling`'s bound)."""
        estimates = {**dict.fromkeys(ESTIMATE_SOURCES, 0.0), **self._source_estimates,
                     "best_coa": self._best_coa * best_coa_factor}
        at_headroom = self.stop_reason in HEADROOM_STOPS
        for source, at_stop in AT_HEADROOM.items():
            estimates[source] = estimates[at_stop if at_headroom else "filter"]
        if self.params.crest_floor:
            estimates = {source: max(value, self._bracket.crest_bound) for source, value in estimates.items()}
        if self.params.runaway_estimate and self._runaway is not None:
            estimates = dict.fromkeys(estimates, self._runaway)
        ceiling = self._ceiling.bound if self.params.crest_ceiling else None
        if ceiling is not None:
            estimates = {source: min(value, ceiling) for source, value in estimates.items()}
        return estimates

    @staticmethod
    def _estimates_at(coa: float, filter_prediction: tuple[float, float],
                      guard_predictions: list[tuple[float, float]],
                      estimator_predictions: list[tuple[float, float]] = ()) -> dict[str, float]:
        """The CoA times ``exp`` of each source's correction ``ln(CoF / CoA)``, from the filter's, each
        guard's and each estimator's (mean, std) of it."""
        corrections = {"filter": filter_prediction[0]}
        if guard_predictions:
            corrections["guard"] = pooled_correction(guard_predictions)
            corrections["pooled"] = pooled_correction([filter_prediction, *guard_predictions])
        if estimator_predictions:
            corrections["estimator"] = pooled_correction(estimator_predictions)
            corrections["estimator_pooled"] = pooled_correction(
                [filter_prediction, *guard_predictions, *estimator_predictions])
        return {source: coa * math.exp(c) for source, c in corrections.items()}

    @staticmethod
    def _corrections(networks: tuple[FilterEnsemble, ...], features: tuple[EpisodeFeatures, ...]) -> list[tuple[float, float]]:
        """Each network's (mean, std) of the correction ``ln(CoF / CoA)`` at the newest window."""
        outputs = [n.predict(f.vector()) for n, f in zip(networks, features)]
        return [(float(mean[0, 1]), float(std[0, 1])) for mean, std in outputs]

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        p = self.params
        stop = False
        if self._dc > 0.0:
            self._driven += 1
            reading = Reading.of(observation, self.limits, info)
            previous = self.features.readings[-1] if self.features.readings else None
            falling = previous is not None and coa_fell(reading.coa, previous.coa)
            knee = previous is not None and p.knee_stops(reading, previous, self._driven, self._crept)
            self._bracket.observe(reading.crest_bound, reading.dc_nm + reading.amplitude_nm)  # the floor's bound too
            for features in (self.features, *self._guard_features, *self._estimator_features):
                features.push(reading)
            p = p.at_noise(p.noise_ratio(self.features.readings))  # the climb at the noise its first windows read
            mean, std, spread = self.ensemble.predict_with_spread(self.features.vector())
            guard_outputs = [g.predict_with_spread(f.vector()) for g, f in zip(self.guards, self._guard_features)]
            headroom, headroom_std, headroom_spread, caution = self._steering_headroom(p, mean, std, spread, guard_outputs)
            self._ceiling.observe(reading.coa_cycle_max, reading.coa_cycle_bin_se, reading.dc_nm + reading.amplitude_nm,
                                  p.fall_margin(p.mean_headroom(headroom, headroom_std, headroom_spread, caution)))
            if not falling:
                self._best_coa = max(self._best_coa, reading.coa)
                self._source_estimates = self._estimates_at(
                    reading.coa, (float(mean[0, 1]), float(std[0, 1])),
                    [(float(g_mean[0, 1]), float(g_std[0, 1])) for g_mean, g_std, _ in guard_outputs],
                    self._corrections(self.estimators, self._estimator_features))
            step = p.log_step(headroom, headroom_std, headroom_spread, caution)
            if p.sticks(self._crept, headroom):  # the peak may be near: no big step again
                step = min(step, p.creep_log_step)
            self._crept |= p.creeps(headroom, headroom_std, headroom_spread, caution)
            windows_left = self.max_windows - 1 - self._driven  # windows before the horizon's stop
            if self._crept and step >= p.min_log_step:  # pacing sizes a slow-probe step, never turns a stop into one
                step = max(step, p.pace_step(headroom, headroom_std, headroom_spread, windows_left, caution))
            step = max(step, p.floor_step(reading.coa))  # safe whatever the filter predicts
            if step < p.min_log_step and p.probes_on(self.features.readings):  # a headroom stop the crest defers
                step = p.creep_log_step
                self._crept = True
                if p.crest_probe_hold_crest and self._held_crest is None:  # the crest of the window just read
                    self._held_crest = self._dc + p.amplitude(self._dc, self.limits, self._ratio)
            at_limit = self._dc >= self.limits.max_dc_torque_nm
            last = windows_left <= 0
            crest_fell = p.ceiling_stop and self._ceiling.reached
            stop = falling or knee or crest_fell or at_limit or last or step < p.min_log_step
            held_ratio = None
            if not stop:
                new_dc = min(self._dc * math.exp(step), self.limits.max_dc_torque_nm)
                if self._held_crest is not None:  # no DC step the held crest cannot carry: a headroom stop
                    held_ratio = p.held_crest_ratio(self._held_crest, new_dc, self.limits)
                    stop = held_ratio is None
            if stop:
                self.stop_reason = ("falling" if falling else "knee" if knee else "ceiling" if crest_fell
                                    else "limit" if at_limit else "horizon" if last else "headroom")
            else:
                self._ratio = p.crest_ratio(headroom - math.log(new_dc / self._dc), self._crept)
                if held_ratio is not None:
                    self._ratio = min(self._ratio, held_ratio)
                self._dc = new_dc
            self.decisions.append(WindowDecision(float(mean[0, 0]), float(std[0, 0]), headroom, headroom_std,
                                                 0.0 if stop else step, self._crept, self.stop_reason))
            self._runaway = None if stop else self._bracket.estimate(
                self._dc + p.amplitude(self._dc, self.limits, self._ratio))
            self._estimate = self.candidate_estimates(p.best_coa_factor)[p.estimate_from]  # the stop's reason known
        else:
            self._dc = self.climb.first_dc(self.limits)
            self._frequency = p.frequency_at(Reading.of(observation, self.limits, info).speed_m_s, self.limits)
        estimate = min(max(self._estimate, self.limits.min_cof_estimate), self.limits.max_cof_estimate)
        return p.action(self._dc, estimate, stop, self.limits, self._ratio, self._frequency)


    @staticmethod
    def _steering_headroom(p: ClimbParameters, mean: np.ndarray, std: np.ndarray, spread: np.ndarray,
                           guard_outputs: list[tuple[np.ndarray, np.ndarray, np.ndarray]]
                           ) -> tuple[float, float, float, float]:
        """(cautious headroom, its std, its members' spread, the caution it was taken with) that steers the
        climb ``p``: the filter's (its prediction ``mean``, ``std``, ``spread``, the climb's ``caution``), or a
        guard's where that is lower (``guard_outputs``: each guard's prediction, read through its own
        features, with its :meth:`ClimbParameters.guard_caution`)."""
        best = (float(p.cautious_headroom(mean[0, 0], std[0, 0], spread[0, 0])), float(std[0, 0]), float(spread[0, 0]),
                p.caution)
        for i, (g_mean, g_std, g_spread) in enumerate(guard_outputs):
            caution = p.guard_caution(i)
            cautious = float(p.cautious_headroom(g_mean[0, 0], g_std[0, 0], g_spread[0, 0], caution))
            if cautious < best[0]:
                best = (cautious, float(g_std[0, 0]), float(g_spread[0, 0]), caution)
        return best


def read_manifest(directory: Path) -> dict[str, Any]:
    """``directory/manifest.json`` (the climb's parameters, the training distribution), {} if absent."""
    manifest_file = Path(directory) / "manifest.json"
    return json.loads(manifest_file.read_text()) if manifest_file.is_file() else {}


def manifest_climb(directory: Path) -> ClimbParameters:
    """The climb of ``directory``'s manifest (the defaults where it names none)."""
    return ClimbParameters(**read_manifest(directory).get("climb", {}))


def manifest_networks(directory: Path, role: str) -> tuple[Path, ...]:
    """The network directories ``directory``'s manifest names under ``role`` (``"guards"`` or
    ``"estimators"``; relative to it), none where it names none."""
    return tuple(Path(directory) / g for g in read_manifest(directory).get(role, []))


def manifest_guards(directory: Path) -> tuple[Path, ...]:
    """The guard directories ``directory``'s manifest names."""
    return manifest_networks(directory, "guards")


def interrogator_for(env, directory: Path, params: ClimbParameters | None = None,
                     guards: Iterable[Path] | None = None, estimators: Iterable[Path] | None = None) -> LearnedInterrogator:
    """The interrogator of ``directory`` (``member_*.npz`` and a ``manifest.json`` with the climb's
    parameters, the training distribution and any guards and estimators) for ``env``'s drive and vehicle
    configuration; ``params`` replaces the manifest's climb, ``guards`` and ``estimators`` (directories of
    ``member_*.npz``) its guards and estimators. A two-tone climb acts in the env made with its ``env_options``."""
    directory = Path(directory)
    ensemble = FilterEnsemble.load(directory)
    trained = read_manifest(directory).get("trained_on")
    guard_dirs = manifest_guards(directory) if guards is None else tuple(guards)
    estimator_dirs = manifest_networks(directory, "estimators") if estimators is None else tuple(estimators)
    base = env.unwrapped
    return LearnedInterrogator(base.limits, ensemble, counter_torque=bool(base.task.counter_torque),
                               params=params or manifest_climb(directory),
                               max_windows=int(base.task.max_windows),
                               trained_on=(trained["env_id"], tuple(trained["configs"])) if trained else None,
                               guards=tuple(FilterEnsemble.load(g) for g in guard_dirs),
                               estimators=tuple(FilterEnsemble.load(e) for e in estimator_dirs))


def load_interrogator(env, argument: str | None = None) -> LearnedInterrogator:
    """The shipped interrogator, or ``interrogator:DIR`` (see :func:`interrogator_for`)."""
    directory = Path(argument) if argument else SHIPPED_INTERROGATOR
    agent = interrogator_for(env, directory)
    if argument:
        agent.name = f"interrogator:{directory.name}"
    return agent
