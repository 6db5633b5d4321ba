"""The learned interrogator's features of a climb's windows (:class:`EpisodeFeatures`): the base set and the
optional blocks a network may read (:data:`FEATURE_BLOCKS`), with the regressions over the newest windows."""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass, field
from typing import Iterable

import numpy as np

from cof_gym.agents.interrogator.readings import (
    SE_CLIP_DEG, Reading, slope_from_compliance, slope_from_phase, slope_index, tan_clipped,
)

HISTORY = 2  # previous windows in the features

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
# the features that read the compliance, the speed amplitude over the *measured* torque amplitude, and so the torque
# sensor's gain: the ``torque_free`` block leaves them out (a network immune to the torque gain error by construction,
# as the creepage differences make it immune to the wheel radius error)
TORQUE_READING_FEATURE_NAMES = ("compliance", "compliance_rise", "peak_gap_compliance", "slope_ratio_compliance",
                                "tone2_compliance", "fit_slope_fall_compliance", "fit_peak_gap_compliance")
# the modulation the drive applied, over the DC (the measured torque amplitude, calibrated where the climb calibrates
# its torque readings): the ``applied_amplitude`` block reads it in place of the commanded ``amplitude_ratio``. A
# drive that lags by ``tau`` applies ``1 / sqrt(1 + (w tau)^2)`` of a commanded modulation at ``w`` (0.30 at 5 Hz and
# 0.1 s): the crest reaches that much less far into the creep curve than the command says
APPLIED_AMPLITUDE_FEATURE_NAMES = ("applied_amplitude_ratio",)
# optional feature blocks, in this order (a network's file names the ones it reads): each appends its names to
# FEATURE_NAMES and leaves out those of BLOCK_LEAVES_OUT (``torque_free`` appends none)
FEATURE_BLOCKS = {"tone2": TONE2_FEATURE_NAMES, "creepage_rise": CREEPAGE_RISE_FEATURE_NAMES,
                  "creepage_modulation": CREEPAGE_MODULATION_FEATURE_NAMES, "cycle_crest": CYCLE_CREST_FEATURE_NAMES,
                  "climb_fit": CLIMB_FIT_FEATURE_NAMES, "torque_free": (),
                  "applied_amplitude": APPLIED_AMPLITUDE_FEATURE_NAMES}
BLOCK_LEAVES_OUT = {"torque_free": TORQUE_READING_FEATURE_NAMES, "applied_amplitude": ("amplitude_ratio",)}


def _all_feature_names(blocks: tuple[str, ...]) -> tuple[str, ...]:
    """:data:`FEATURE_NAMES` and the names every block of ``blocks`` appends (none left out)."""
    return FEATURE_NAMES + tuple(n for b, names in FEATURE_BLOCKS.items() if b in blocks for n in names)


def _kept(blocks: Iterable[str]) -> tuple[int, ...] | None:
    """The positions among :func:`_all_feature_names` that ``blocks`` keeps: None (all of them) unless one of them
    leaves names out (:data:`BLOCK_LEAVES_OUT`). One place for the names and the values, computed once per set of
    blocks (:func:`EpisodeFeatures.vector` asks at every window)."""
    return _kept_in_order(tuple(b for b in FEATURE_BLOCKS if b in blocks))


@functools.lru_cache(maxsize=None)
def _kept_in_order(blocks: tuple[str, ...]) -> tuple[int, ...] | None:
    left_out = {name for b in blocks for name in BLOCK_LEAVES_OUT.get(b, ())}
    if not left_out:
        return None
    return tuple(k for k, name in enumerate(_all_feature_names(blocks)) if name not in left_out)


def feature_names(blocks: Iterable[str] = ()) -> tuple[str, ...]:
    """The filter's features with the optional ``blocks`` of :data:`FEATURE_BLOCKS`."""
    blocks = tuple(blocks)
    unknown = sorted(set(blocks) - set(FEATURE_BLOCKS))
    if unknown:
        raise ValueError(f"feature blocks must be among {tuple(FEATURE_BLOCKS)}, got {unknown}")
    names, kept = _all_feature_names(blocks), _kept(blocks)
    return names if kept is None else tuple(names[k] for k in kept)


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
        if "applied_amplitude" in self.blocks and not reading.torque_amplitude_measured_nm > 0.0:
            raise ValueError("EpisodeFeatures with the applied_amplitude block takes readings of the applied torque "
                             "amplitude (torque_amplitude_measured_nm > 0): climbs recorded before that reading must "
                             "be collected again")
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
        dispersion = (math.log(tan_clipped(now.phase_deg) / tan_clipped(tone1.phase_deg)) / math.log(ratio)
                      if abs(math.log(ratio)) > 1e-3 else 0.0)
        return [now.phase_deg / 90.0, now.se_deg / SE_CLIP_DEG, now.compliance, slope_index(now.phase_deg),
                slope_index(first.phase_deg) - slope_index(now.phase_deg),
                math.log(slope_from_phase(now) / slope_from_phase(prev)),
                peak_gap(views, i, i - 1, slope_from_phase), dispersion, now.frequency_hz / 20.0,
                now.tone2_amplitude_nm / max(now.amplitude_nm, 1e-9), prev.phase_deg / 90.0]

    def vector(self, applied_ratio: bool = False) -> np.ndarray:
        """The features after the newest window; with ``applied_ratio`` the ``amplitude_ratio`` entry reads the
        modulation the drive applied over the DC (:attr:`Reading.torque_amplitude_measured_nm`, where measured)
        instead of the commanded one: what a network fitted on the command reads behind a drive slower than any it
        met (``ClimbParameters.slow_drive_applied_estimate``)."""
        if not self.readings:
            raise ValueError("no driven window yet")
        now, first = self.readings[-1], self.readings[0]
        slope = slope_index(now.phase_deg)
        modulation_nm = now.torque_amplitude_measured_nm if applied_ratio and now.torque_amplitude_measured_nm > 0.0 \
            else now.amplitude_nm
        values = [
            now.phase_deg / 90.0, now.se_deg / SE_CLIP_DEG, now.compliance, slope,
            slope_index(first.phase_deg) - slope, (now.phase_deg - first.phase_deg) / 90.0,
            now.compliance - first.compliance, math.log(now.coa / first.coa), math.log(now.dc_nm / first.dc_nm),
            math.log(now.coa), modulation_nm / now.dc_nm, now.frequency_hz / 20.0, now.speed_m_s / 40.0,
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
        if "applied_amplitude" in self.blocks:
            values.append(now.torque_amplitude_measured_nm / now.dc_nm)
        kept = _kept(self.blocks)
        if kept is not None:
            values = [values[k] for k in kept]
        return np.nan_to_num(np.asarray(values, dtype=np.float64), nan=0.0, posinf=0.0, neginf=0.0)
