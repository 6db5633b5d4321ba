"""An interval around the learned interrogator's CoF estimate, calibrated by split conformal prediction.

The interrogator reports ``estimate = CoA x exp(c)`` with ``c`` the correction ``ln(CoF / CoA)`` its networks
predict, each with a std ``s`` (log units: :attr:`~cof_gym.agents.interrogator.LearnedInterrogator.estimate_log_std`).
How far that std can be trusted is measured, not assumed: on calibration climbs (the validation grids, never a
reported suite) each scored episode gives a normalised score, and the interval's scale is a quantile of those
scores (split conformal prediction with normalised residuals: Vovk, Gammerman and Shafer, *Algorithmic Learning
in a Random World*, Springer 2005; Lei, G'Sell, Rinaldo, Tibshirani and Wasserman, "Distribution-free predictive
inference for regression", J. Amer. Statist. Assoc. 113 (2018), Sect. 5.2):

- two-sided: score ``|ln(CoF / estimate)| / s``; ``estimate x exp(+-q s)`` holds the CoF;
- lower bound (what a braking planner needs: an over-estimated CoF lengthens the real braking distance): score
  ``ln(estimate / CoF) / s``; ``estimate x exp(-q s)`` is at most the CoF.

With ``n`` calibration scores, ``q`` is the ``ceil((n + 1) x coverage)``-th smallest; a new episode drawn like
the calibration climbs is then covered with probability at least ``coverage`` (exchangeability, whatever the
networks' errors are). The scales are calibrated per way the estimate was committed (:data:`COMMITMENTS`: at
the climb's own stop, at the horizon, or with no stop, where the wheel ran away under the runaway estimate),
which the agent knows when it reports: Mondrian conformal prediction (Vovk et al., Sect. 4.5), whose guarantee
holds within each of them. A stop near the peak and an extrapolation from far below it are not one population:
pooled, the scale would be too wide for the first and too narrow for the second. A commitment with too few
calibration climbs for a coverage takes the pooled scale. Which of the two a policy ships (pooled alone, or per
commitment) is chosen on the validation grids alone: ``experiments/estimate_interval.py`` calibrates each on two
of the three grids and measures it on the third. Creep curves and sensors unlike the calibration climbs' carry no such guarantee: there the
coverage is measured (``experiments/estimate_interval.py`` reports it on every held-out grid).

**Past the draws' noise.** A climb whose first windows read more noise than the v2 draws give (the climb's noise
ratio, :meth:`~cof_gym.agents.interrogator.ClimbParameters.noise_ratio`, at least :data:`NOISY_RATIO`) extrapolates
further from noisier readings. Its estimate takes scales of its own (each group in its noise class,
:func:`noise_group`), calibrated on the validation grids played with the noise tripled and with a 0.1 s drive lag
(the climbs there that read noisy); the draws' groups stay calibrated on the draws alone. The noise class is a
reading of the agent's, so the Mondrian guarantee holds within it for climbs drawn like those calibration climbs.

**A smoothed encoder.** A climb whose first windows show a smoothed speed signal
(:func:`~cof_gym.agents.interrogator.readings.reads_smoothed_encoder`: the residual's noise colour) reads every phase
lag late by the smoothing's delay, which none of the networks met: its estimate extrapolates in another way than a
noisy climb's. It takes scales of its own (its class :data:`SMOOTHED`, which comes before the noise's where a climb
reads both), calibrated on the validation grids played with the encoder's speed signal lagged
(``experiments/estimate_interval.py``: the climbs there that read a smoothed encoder). The colour does not say how
large the lag is, and lags outside the calibration's bias the estimate otherwise (a 4-15 ms lag leaves it low, and
the calibrated lower scales narrow), so a smoothed group's scales are never narrower than its base group's
(:data:`FLOORED_CLASSES`): against the draws' scales the note only ever widens the interval and lowers the bound
(a climb that also reads noisy takes the smoothed class, floored at the draws' scales, not the noisy ones). A
calibration without such climbs has no smoothed scales; its smoothed climbs then read their base group's.

**In flight.** A climb that has not stopped has read windows too: the networks' estimate from them (without the
runaway's, :attr:`~cof_gym.agents.interrogator.LearnedInterrogator.in_flight_estimate`) takes scales of its own,
per place in the climb (:data:`IN_FLIGHT`: before the slow probe, in it), calibrated on one window per
calibration climb and place, drawn at random. A new climb's window drawn at random among those of a place is then
covered with the same guarantee; how early the bound is tight, by the utilisation its crest has reached, is
measured (``experiments/estimate_interval.py``).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Iterable

from cof_gym.agents.interrogator.readings import SMOOTHED_ENCODER
from cof_gym.validation import check_number

INTERVAL_FILE = "interval.json"  # beside a policy directory's manifest.json
# how the estimate was committed: the climb's own stop, the horizon, or no stop (the episode ended under the
# runaway estimate); the groups the scales are calibrated in
COMMITMENTS = ("stop", "horizon", "no stop")
# where a climb that has not stopped stands (LearnedInterrogator.in_flight): before its slow probe, or in it; the
# groups of the in-flight interval, which a climb reads at any window
IN_FLIGHT = ("climbing", "probing")
BASE_GROUPS = (*COMMITMENTS, *IN_FLIGHT)  # every group of a climb at the noise of the calibration's draws
NOISY = "noisy"  # the class of a climb whose first windows read more noise than the draws give (NOISY_RATIO)
SMOOTHED = SMOOTHED_ENCODER  # the class of a climb whose first windows show a smoothed speed signal
SENSOR_CLASSES = (NOISY, SMOOTHED)  # the classes past the draws' sensors, each calibrated apart (a group's suffix)
# the classes whose scales are never narrower than their base group's (IntervalScales.scale_of): a smoothed encoder's
# lag is not read (its colour saturates past a few ms), and lags outside the calibration's bias the estimate otherwise
FLOORED_CLASSES = (SMOOTHED,)
# a climb whose first windows read a noise ratio (ClimbParameters.noise_ratio) at least this is scored and scaled in
# the noisy groups: 1 at every noise and drive lag the v2 draws give, about 1.6 with the noise doubled, 2.2-2.5 with
# it tripled or a 0.1 s lag (the validation grids, session 51)
NOISY_RATIO = 1.25


def sensor_group(group: str, sensor_class: str = "") -> str:
    """``group`` (a commitment, an in-flight place or :data:`POOLED`) in a sensor class (:data:`SENSOR_CLASSES`;
    "" for the draws' sensors). ValueError for another class."""
    if sensor_class and sensor_class not in SENSOR_CLASSES:
        raise ValueError(f"sensor_class must be '' or one of {SENSOR_CLASSES}, got {sensor_class!r}")
    return f"{group}, {sensor_class}" if sensor_class else group


def noise_group(group: str, noisy: bool) -> str:
    """``group`` in the noise class of its climb (:data:`NOISY` where ``noisy``)."""
    return sensor_group(group, NOISY if noisy else "")


def sensor_class_of(group: str) -> str:
    """The sensor class of ``group`` (:data:`SENSOR_CLASSES`), "" for a group of the draws' sensors."""
    return next((c for c in SENSOR_CLASSES if group.endswith(f", {c}")), "")


def base_group(group: str) -> str:
    """``group`` without its sensor class."""
    sensor_class = sensor_class_of(group)
    return group.removesuffix(f", {sensor_class}") if sensor_class else group


def is_noisy(group: str) -> bool:
    """Whether ``group`` is one of the noisy groups (:func:`noise_group`)."""
    return sensor_class_of(group) == NOISY


POOLED = "pooled"  # the scales over every committed calibration climb: a group's where it had too few
CLASS_POOLS = {c: sensor_group(POOLED, c) for c in SENSOR_CLASSES}  # ... over every committed one of a sensor class
POOLED_NOISY = CLASS_POOLS[NOISY]
POOLED_SMOOTHED = CLASS_POOLS[SMOOTHED]
GROUPS = (*BASE_GROUPS, *(sensor_group(g, c) for c in SENSOR_CLASSES for g in BASE_GROUPS))  # every group scored
LOG_STD_FLOOR = 1e-6  # a std below this (log units) scores as this: a point estimate still has a finite score


def check_coverage(name: str, coverage: float) -> float:
    """A coverage: a number in (0, 1) (ValueError naming ``name`` otherwise)."""
    return check_number(name, coverage, 0.0, 1.0, low_open=True, high_open=True)  # 1: an unbounded interval


def conformal_quantile(scores: Iterable[float], coverage: float) -> float:
    """The ``ceil((n + 1) x coverage)``-th smallest of the ``n`` calibration ``scores``: the split conformal
    scale that covers a new exchangeable score with probability at least ``coverage`` (in (0, 1)). ValueError
    where ``n`` is too small for that coverage (``(n + 1) x coverage > n``) or a score is not a finite number."""
    check_coverage("coverage", coverage)
    values = sorted(float(s) for s in scores)
    if not all(math.isfinite(v) for v in values):
        raise ValueError("conformal_quantile: every score must be a finite number")
    rank = math.ceil((len(values) + 1) * coverage)
    if rank > len(values):
        raise ValueError(f"conformal_quantile: {len(values)} scores cannot calibrate a coverage of {coverage} "
                         f"(at least {math.ceil(coverage / (1.0 - coverage))} are needed)")
    return values[rank - 1]


def two_sided_score(estimate: float, cof: float, log_std: float) -> float:
    """``|ln(CoF / estimate)| / log_std`` (the std floored at :data:`LOG_STD_FLOOR`)."""
    return abs(math.log(cof / estimate)) / max(log_std, LOG_STD_FLOOR)


def lower_score(estimate: float, cof: float, log_std: float) -> float:
    """``ln(estimate / CoF) / log_std``: positive where the estimate is above the CoF."""
    return math.log(estimate / cof) / max(log_std, LOG_STD_FLOOR)


def enough_for(count: int, coverage: float) -> bool:
    """Whether ``count`` calibration scores can calibrate ``coverage`` (:func:`conformal_quantile`)."""
    return math.ceil((count + 1) * coverage) <= count


@dataclass(frozen=True)
class IntervalScales:
    """The calibrated scales (in stds of the estimate's log) of the two-sided interval at ``coverage`` and of
    the lower bound at ``lower_coverage``: per commitment (:data:`COMMITMENTS`) and :data:`POOLED`, each
    ``[scale, lower_scale]``; the calibration climbs per commitment (``climbs``) and what they were."""

    coverage: float
    lower_coverage: float
    scales: dict[str, list[float]]
    climbs: dict[str, int]
    calibrated_on: str = ""

    def __post_init__(self) -> None:
        for name in ("coverage", "lower_coverage"):
            check_coverage(name, getattr(self, name))
        if POOLED not in self.scales or set(self.scales) - {POOLED, *CLASS_POOLS.values(), *GROUPS}:
            raise ValueError(f"scales must name {POOLED!r} and at most {(*CLASS_POOLS.values(), *GROUPS)}, "
                             f"got {sorted(self.scales)}")
        for group, pair in self.scales.items():
            if not (isinstance(pair, (list, tuple)) and len(pair) == 2):
                raise ValueError(f"scales[{group!r}] must be [scale, lower_scale], got {pair!r}")
            check_number(f"scales[{group!r}] scale", pair[0], 0.0, math.inf)
            check_number(f"scales[{group!r}] lower_scale", pair[1], -math.inf, math.inf)

    @classmethod
    def calibrate(cls, episodes: Iterable[tuple[float, float, float, str]], coverage: float = 0.9,
                  lower_coverage: float = 0.95, calibrated_on: str = "", per_commitment: bool = True
                  ) -> "IntervalScales":
        """The scales from scored calibration ``episodes`` of ``(estimate, CoF, log_std, group)`` (a group of
        :data:`GROUPS`: a commitment, or an in-flight window's place in its climb, each in its sensor class): pooled
        over the commitments of each sensor class, and with ``per_commitment`` per group with enough of them for both
        coverages. Without episodes of a sensor class there are no scales of it (its climbs then read their base
        group's)."""
        episodes = list(episodes)
        groups = {POOLED: [e for e in episodes if e[3] in COMMITMENTS],
                  **{pool: [e for e in episodes if e[3] in {sensor_group(c, sensor_class) for c in COMMITMENTS}]
                     for sensor_class, pool in CLASS_POOLS.items()},
                  **{g: [e for e in episodes if e[3] == g] for g in GROUPS}}
        scales, climbs = {}, {}
        for group, members in groups.items():
            if sensor_class_of(group) and not members:
                continue  # no calibration climbs of the class: the file stays as a calibration without them writes it
            climbs[group] = len(members)
            enough = enough_for(len(members), coverage) and enough_for(len(members), lower_coverage)
            if group == POOLED or (group in CLASS_POOLS.values() and enough) or (per_commitment and enough):
                scales[group] = [conformal_quantile([two_sided_score(*e[:3]) for e in members], coverage),
                                 conformal_quantile([lower_score(*e[:3]) for e in members], lower_coverage)]
        return cls(coverage, lower_coverage, scales, climbs, calibrated_on)

    def scale_of(self, commitment: str) -> tuple[float, float]:
        """(two-sided scale, lower scale) of a group (:data:`GROUPS`): its own; else, for a group of a sensor class,
        that class's pooled ones, or where there are none its base group's; else the pooled ones. A group of a class
        of :data:`FLOORED_CLASSES` reads each of the two at least at its base group's."""
        scales = self._calibrated_scale_of(commitment)
        if sensor_class_of(commitment) in FLOORED_CLASSES:
            base = self.scale_of(base_group(commitment))
            return max(scales[0], base[0]), max(scales[1], base[1])
        return scales

    def _calibrated_scale_of(self, commitment: str) -> tuple[float, float]:
        if commitment in self.scales:
            return tuple(self.scales[commitment])
        sensor_class = sensor_class_of(commitment)
        if not sensor_class:
            return tuple(self.scales[POOLED])
        if CLASS_POOLS[sensor_class] in self.scales:
            return tuple(self.scales[CLASS_POOLS[sensor_class]])
        return self.scale_of(base_group(commitment))

    def interval(self, estimate: float, log_std: float, commitment: str = POOLED) -> tuple[float, float]:
        """``estimate x exp(-+scale x log_std)``: the two-sided interval (CoF) at the commitment's scale."""
        half = self.scale_of(commitment)[0] * max(log_std, LOG_STD_FLOOR)
        return estimate * math.exp(-half), estimate * math.exp(half)

    def lower_bound(self, estimate: float, log_std: float, commitment: str = POOLED) -> float:
        """``estimate x exp(-lower_scale x log_std)``: the lower bound (CoF) at the commitment's scale."""
        return estimate * math.exp(-self.scale_of(commitment)[1] * max(log_std, LOG_STD_FLOOR))

    def save(self, directory: Path) -> Path:
        path = Path(directory) / INTERVAL_FILE
        path.write_text(json.dumps(asdict(self), indent=2) + "\n")
        return path

    @classmethod
    def load(cls, directory: Path) -> "IntervalScales | None":
        """The scales of a policy directory's :data:`INTERVAL_FILE`, None where it has none."""
        path = Path(directory) / INTERVAL_FILE
        return cls(**json.loads(path.read_text())) if path.is_file() else None
