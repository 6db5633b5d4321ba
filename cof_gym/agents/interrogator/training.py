"""Training the learned interrogator's filter (:mod:`cof_gym.agents.interrogator`).

**Data.** Climbs on the training env's own randomisation (every v2 draw: creep-law family and shape,
systematic sensor errors, CoF, speed, load, noise, motor lag), in every vehicle configuration listed,
with training seeds that no evaluation uses. Each climb starts at the shared safe first step and
probes upwards with a modulation ratio log-uniform in 3-40 % and a frequency of 5 Hz or log-uniform
in 3-10 Hz (or in given ranges: :class:`ClimbDraws`; with ``crest_powers`` the ratio shrinks as the
slope falls); each log step is the climb's largest step
(log-uniform 0.15-0.6) times the local slope relative to the first window's (from the phase) to a
drawn power (1-3), floored at a drawn 2-15 % of the largest step, times a random factor: the climb
slows as the creep curve flattens, the way a cautious probe does, until a macro-slip, the horizon or
1.08 x ``M_sat``. The
creep curves are the env's own draws or procedural tables beyond every family
(:func:`procedural_shape`). **The DC torques depend on the readings and the climb's
own random draws only, never on the truth**: a schedule steered by the saturation torque would leak
it into the torque-step features (a network then learns the schedule, not the creep curve). The
labels (``ln(M_sat / DC)``, ``ln(CoF / CoA measured)``) are the episode's ground truth. **On policy**
(``collect(..., policy=DIR)``): the same episodes climbed by a deployed interrogator instead, its
torques chosen by its own networks from the readings, for an estimator that learns the correction
where that climb actually stops (:class:`~cof_gym.agents.interrogator.LearnedInterrogator`'s
``estimators``). The readings
of every window are kept (:class:`Dataset`); the features are rebuilt from them through the same
:class:`~cof_gym.agents.interrogator.EpisodeFeatures` the agent runs.

**Networks.** Each member is a tanh MLP fitted by the Gaussian negative log-likelihood of both
targets (mean and log variance per target), on a bootstrap resample of the training episodes
(bagging: members differ in data and initialisation). Torch is imported only here.
"""

from __future__ import annotations

import math
from concurrent.futures import ProcessPoolExecutor
from dataclasses import astuple, dataclass, fields
from functools import cached_property
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from cof_gym.agents.base import agent_view
from cof_gym.agents.interrogator import (
    CREST_RATIO_FLOOR, FEATURE_BLOCKS, NOISE_WINDOWS, TARGET_NAMES, TWO_TONE_ENV_OPTIONS, ClimbParameters,
    EpisodeFeatures, FilterNetwork, Reading, feature_names, floor_headroom, interrogator_for, manifest_climb,
    slope_from_phase, speed_scaled_frequency,
)
from cof_gym.agents.staircase import ElasticityClimb
from cof_gym.physics.creep_laws import below_peak
from cof_gym.task.interface import MotorLimits
from cof_gym.task.scenarios import ENCODER_LAG_MAX_S, MOTOR_LAG_MAX_S, NOISE_LEVEL_MAX
from cof_gym.task.sensors import SYSTEMATIC_ERRORS
from cof_gym.task.task import MAX_DRAWN_PEAK_CREEPAGE
from cof_gym.validation import check_number, check_range

TRAINING_SEED = 1_000_000  # first training seed: far from every evaluation and validation seed


READING_FIELDS = tuple(f.name for f in fields(Reading))


@dataclass(frozen=True)
class Dataset:
    """Driven windows of training climbs: the raw readings (so that features can change without new
    simulations), the vehicle configuration, the targets and the episode of each window."""

    readings: np.ndarray  # (n, len(READING_FIELDS))
    counter_torque: np.ndarray  # (n,) bool
    targets: np.ndarray  # (n, 2): ln(M_sat / DC), ln(CoF / CoA)
    episode: np.ndarray  # (n,) episode index (windows of an episode are contiguous, in order)

    def __len__(self) -> int:
        return len(self.targets)

    def subset(self, rows: np.ndarray) -> "Dataset":
        return Dataset(self.readings[rows], self.counter_torque[rows], self.targets[rows], self.episode[rows])

    @cached_property
    def tones(self) -> int:
        """2 where every window has a second tone, 1 where none has; a mix is refused."""
        two = self.readings[:, READING_FIELDS.index("tone2_frequency_hz")] > 0.0
        if two.any() and not two.all():
            raise ValueError("the dataset mixes one- and two-tone climbs; fit a filter on one excitation")
        return 2 if len(self) and two.all() else 1

    @cached_property
    def _features(self) -> dict[tuple[str, ...], np.ndarray]:
        return {}

    @property
    def features(self) -> np.ndarray:
        """Each window's feature vector with the blocks its data has (tone 2's for two-tone climbs)."""
        return self.features_for(("tone2",) if self.tones == 2 else ())

    def features_for(self, blocks: tuple[str, ...]) -> np.ndarray:
        """Each window's feature vector with the optional ``blocks``, rebuilt from the readings of its
        episode up to it (once per set of blocks)."""
        blocks = tuple(b for b in FEATURE_BLOCKS if b in blocks)
        if blocks not in self._features:
            out = np.empty((len(self), len(feature_names(blocks))))
            features = None
            for i in range(len(self)):
                if i == 0 or self.episode[i] != self.episode[i - 1]:
                    features = EpisodeFeatures(bool(self.counter_torque[i]), blocks=blocks)
                features.push(Reading(*(float(v) for v in self.readings[i])))
                out[i] = features.vector()
            self._features[blocks] = out
        return self._features[blocks]

    def save(self, path) -> None:
        np.savez(path, readings=self.readings, counter_torque=self.counter_torque, targets=self.targets,
                 episode=self.episode, reading_fields=np.asarray(READING_FIELDS))

    @classmethod
    def load(cls, path) -> "Dataset":
        with np.load(path) as z:
            recorded = tuple(str(f) for f in z["reading_fields"])
            if recorded != READING_FIELDS[:len(recorded)]:
                raise ValueError(f"{path}: recorded with other reading fields; collect again")
            readings = z["readings"]
            if len(recorded) < len(READING_FIELDS):  # recorded before the later fields: their defaults
                defaults = [f.default for f in fields(Reading)[len(recorded):]]
                readings = np.hstack([readings, np.tile(np.asarray(defaults, dtype=np.float64), (len(readings), 1))])
            return cls(readings, z["counter_torque"], z["targets"], z["episode"])

    @property
    def reads_torque_balance(self) -> bool:
        """Whether the climbs were recorded with each window's torque balance (:attr:`Reading.torque_balance`;
        climbs recorded before it was read hold none)."""
        return bool((self.readings[:, READING_FIELDS.index("torque_balance")] > 0.0).any())

    def climbs(self) -> list[slice]:
        """Each climb's windows (an episode's contiguous rows), in order."""
        starts = np.flatnonzero(np.r_[True, self.episode[1:] != self.episode[:-1]]) if len(self) else []
        return [slice(start, end) for start, end in zip(starts, [*starts[1:], len(self)])]

    def noise_ratios(self, climb: ClimbParameters) -> np.ndarray:
        """Each window's noise ratio as ``climb`` reads it from its episode's first driven windows
        (:meth:`ClimbParameters.noise_ratio`: fixed once those windows are driven; 1 without a noise reference)."""
        out = np.ones(len(self))
        for rows in self.climbs():
            first = self.readings[rows][:NOISE_WINDOWS]
            out[rows] = climb.noise_ratio([Reading(*(float(v) for v in row)) for row in first])
        return out

    def calibrated(self, max_lag_deg: float | None) -> "Dataset":
        """These climbs as a climb with ``ClimbParameters.torque_balance`` (and ``torque_balance_max_lag_deg`` =
        ``max_lag_deg``) reads them: every window's torque readings divided by the gain its episode's first window's
        torque balance reads (:meth:`ClimbParameters.torque_gain`, :meth:`Reading.calibrated`); climbs recorded
        without the balance are refused (ValueError)."""
        if len(self) and not self.reads_torque_balance:
            raise ValueError("the climbs were recorded without the torque balance (Reading.torque_balance): collect "
                             "them again to calibrate them")
        climb = ClimbParameters(torque_balance=True, torque_balance_max_lag_deg=max_lag_deg)
        readings, gain = self.readings.copy(), 1.0
        for i in range(len(self)):
            reading = Reading(*(float(v) for v in self.readings[i]))
            if i == 0 or self.episode[i] != self.episode[i - 1]:
                gain = climb.torque_gain(reading)
            if gain != 1.0:
                readings[i] = astuple(reading.calibrated(gain))
        return Dataset(readings, self.counter_torque, self.targets, self.episode)

    @classmethod
    def concatenate(cls, parts: list["Dataset"]) -> "Dataset":
        offset, episodes = 0, []
        for p in parts:
            episodes.append(p.episode + offset)
            offset += int(p.episode.max()) + 1 if len(p) else 0
        return cls(np.concatenate([p.readings for p in parts]), np.concatenate([p.counter_torque for p in parts]),
                   np.concatenate([p.targets for p in parts]), np.concatenate(episodes))


PROBING_SIGMA = (0.15, 0.6)  # log-uniform: a climb's largest log step
PROBING_POWER = (1.0, 3.0)  # uniform: how sharply it slows as the slope falls
PROBING_FLOOR = (0.02, 0.15)  # uniform: its smallest step, as a fraction of the largest
STOP_UTILISATION = 1.08  # a training climb ends once its DC torque passes 1.08 x M_sat


def _probing_step(rng: np.random.Generator, readings: list[Reading], sigma: float, power: float,
                  floor: float) -> float:
    """The next log step of a training climb: ``sigma`` times the local slope relative to the first
    window's (from the phase, :func:`~cof_gym.agents.interrogator.slope_from_phase`) to the ``power``,
    floored, times a random factor in ``exp(+-0.5)``. A function of the readings and ``rng`` only,
    never of the truth."""
    return sigma * min(max(_slope_ratio(readings)**power, floor), 1.0) * math.exp(rng.uniform(-0.5, 0.5))


def _slope_ratio(readings: list[Reading]) -> float:
    """The local slope of the creep curve relative to the first window's, from the phase (falls from
    about 1 towards 0 as the climb nears the peak)."""
    return slope_from_phase(readings[-1]) / slope_from_phase(readings[0])


def _shrunk_ratio(readings: list[Reading], amplitude_ratio: float, power: float) -> float:
    """A crest-shrinking training climb's next modulation ratio: ``amplitude_ratio`` times the slope ratio
    (:func:`_slope_ratio`) to the ``power``, between :data:`~cof_gym.agents.interrogator.CREST_RATIO_FLOOR`
    and ``amplitude_ratio``: the modulation shrinks as the slope falls, as a crest-capped climb's does
    (``ClimbParameters.crest_fraction``), from the readings only."""
    return min(amplitude_ratio, max(CREST_RATIO_FLOOR, amplitude_ratio * _slope_ratio(readings)**power))


SHAPE_SOURCES = ("env", "procedural")  # the env's own creep-law draw, or :func:`procedural_shape`
PROCEDURAL_PEAK_CREEPAGE = (0.003, 0.04)  # log-uniform
# the same, up to the largest peak creepage the env draws (MAX_DRAWN_PEAK_CREEPAGE): curves that still rise far past
# their knee, as Polach's law does at high slip velocity and a wet or contaminated rail may (ClimbDraws.peak_creepages)
FAR_PEAK_CREEPAGE = (PROCEDURAL_PEAK_CREEPAGE[0], MAX_DRAWN_PEAK_CREEPAGE)
PROCEDURAL_KNOTS = (0.0, 0.05, 0.15, 0.3, 0.5, 0.7, 0.85, 1.0)  # x = creepage / peak creepage


@dataclass(frozen=True)
class FallingBranch:
    """How a procedural creep curve falls past its peak: by a fraction drawn uniform in ``drops`` of the
    peak adhesion, over a decay length drawn log-uniform in ``decays`` (peak creepages), held flat with
    probability ``plateau``."""

    drops: tuple[float, float] = (0.0, 0.4)
    decays: tuple[float, float] = (0.2, 4.0)
    plateau: float = 0.2

    def __post_init__(self) -> None:
        check_range("FallingBranch.drops", self.drops, 0.0, 1.0)
        check_range("FallingBranch.decays", self.decays, 1e-3, 100.0)
        check_number("FallingBranch.plateau", self.plateau, 0.0, 1.0)


GENTLE_FALL = FallingBranch()  # the training climbs' and the procedural validation grid's
STEEP_FALL = FallingBranch(drops=(0.2, 0.6), decays=(0.03, 0.3), plateau=0.0)  # a steep validation grid's


def procedural_shape(rng: np.random.Generator, fall: FallingBranch = GENTLE_FALL,
                     peak_creepages: tuple[float, float] = PROCEDURAL_PEAK_CREEPAGE) -> dict[str, Any]:
    """A random creep curve as a ``creep_law`` table spec (domain randomisation beyond the families):
    the rise is a monotone cubic through knots at :data:`PROCEDURAL_KNOTS` whose increments are drawn
    from a Dirichlet distribution (shrinking: a concave rise; with probability 0.4 growing over the
    first 2-4 knots first: a low initial slope and one inflection, as a third-body layer gives), with a
    zero slope at the peak half of the time (a smooth maximum) and the interpolant's slope otherwise
    (a kink); after the peak it falls as ``fall`` draws (by default by 0-40 % over 0.2-4 peak
    creepages, a plateau one time in five); its peak creepage is drawn last, log-uniform in ``peak_creepages``."""
    from scipy.interpolate import CubicHermiteSpline, PchipInterpolator

    n = len(PROCEDURAL_KNOTS) - 1
    increments = 0.02 + (1.0 - 0.02 * n) * rng.dirichlet(np.full(n, rng.uniform(0.5, 3.0)))
    increments = np.sort(increments)[::-1]
    if rng.random() < 0.4:  # a low initial slope: the increments grow to their largest, then shrink
        m = int(rng.integers(2, 5))
        increments[:m] = increments[:m][::-1]
    knots = np.asarray(PROCEDURAL_KNOTS)
    values = np.concatenate([[0.0], np.cumsum(increments)])
    values[-1] = 1.0
    slopes = PchipInterpolator(knots, values).derivative()(knots)
    if rng.random() < 0.5:
        slopes[-1] = 0.0
    rise = CubicHermiteSpline(knots, values, slopes)
    drop = 0.0 if rng.random() < fall.plateau else rng.uniform(*fall.drops)
    decay = math.exp(rng.uniform(*np.log(fall.decays)))
    x_rise = np.concatenate([[0.0], np.geomspace(2e-3, 0.97, 30), [0.985, 1.0]])
    x_fall = 1.0 + np.geomspace(0.02, 3.0, 10)
    ratio = np.concatenate([np.clip(rise(x_rise), 0.0, 1.0), 1.0 - drop * (1.0 - np.exp(-(x_fall - 1.0) / decay))])
    ratio[0], ratio[len(x_rise) - 1] = 0.0, 1.0
    rising = ratio[: len(x_rise) - 1]
    rising[1:] = np.maximum.accumulate(np.maximum(rising[1:], 1e-9))  # strictly rising, below the maximum
    rising[1:] += np.arange(1, len(rising)) * 1e-9
    ratio[: len(x_rise) - 1] = below_peak(rising)
    peak = math.exp(rng.uniform(*np.log(peak_creepages)))
    return {"table": {"creepage": [float(v) for v in np.concatenate([x_rise, x_fall]) * peak],
                      "adhesion_ratio": [float(v) for v in ratio]}}


@dataclass(frozen=True)
class ClimbDraws:
    """What a collection's training climbs draw beyond the env's own randomisation: the creep curves
    (:data:`SHAPE_SOURCES`), the modulation frequency (log-uniform in ``frequencies_hz``; None: 5 Hz or
    log-uniform in 3-10 Hz, half and half), the modulation ratio (log-uniform in ``amplitude_ratios``)
    and, with ``floor_margins``, the deployed climb's jumps to the lowest CoF the task admits: a step is at
    least :func:`~cof_gym.agents.interrogator.floor_headroom` less a margin drawn uniform in that range;
    ``fall``: how procedural curves fall past their peak; ``tone2_hz``: a two-tone excitation (the env's
    ``excitation="multitone"``), tone 2 log-uniform in that range with a weight (its share against tone 1's
    1) uniform in ``tone2_weights``, drawn from their own generator (the other draws unchanged);
    ``frequency_references_m_s``: the drawn frequency raised below a reference speed log-uniform in that
    range as a speed-scheduled climb raises it (:func:`~cof_gym.agents.interrogator.speed_scaled_frequency`,
    from the first observation's measured speed; the reference from its own generator); ``noise_levels`` and
    ``motor_lags_s``: the sensors' noise (multiples of the full-scale noise) and the drive's lag (s) uniform in
    these ranges, set as the episode's reset options from their own generator in place of the env's draws
    (0-1 and 0-0.03 s), up to what the env accepts: noisier sensors and a slower drive than the v2 draws;
    ``sensor_errors``: ``(field, low, high)`` of systematic errors (:data:`~cof_gym.task.sensors.SYSTEMATIC_ERRORS`)
    drawn uniform in that range, each from a generator of its own, in place of the env's draw, up to what the
    env accepts (e.g. a torque gain error of +-15 % where the v2 draws reach +-5 %); ``encoder_lags_s``: the
    encoder's speed-signal lag (s, the env's ``encoder_lag_s``, which v2 never draws) uniform in this range, from a
    generator of its own; ``peak_creepages``: where a procedural curve peaks (:func:`procedural_shape`)."""

    shapes: str = "env"
    frequencies_hz: tuple[float, float] | None = None
    amplitude_ratios: tuple[float, float] = (CREST_RATIO_FLOOR, 0.4)
    floor_margins: tuple[float, float] | None = None  # a step may close the gap to the lowest CoF less this
    fall: FallingBranch = GENTLE_FALL
    tone2_hz: tuple[float, float] | None = None
    tone2_weights: tuple[float, float] = (0.5, 1.5)
    crest_powers: tuple[float, float] | None = None  # a shrinking modulation (:func:`_shrunk_ratio`)
    frequency_references_m_s: tuple[float, float] | None = None  # a speed-scheduled frequency (m/s)
    noise_levels: tuple[float, float] | None = None  # the sensors' noise drawn in this range (None: the env's draw)
    motor_lags_s: tuple[float, float] | None = None  # the drive's lag (s) drawn in this range (None: the env's draw)
    sensor_errors: tuple[tuple[str, float, float], ...] = ()  # (field, low, high) in place of the env's draw
    encoder_lags_s: tuple[float, float] | None = None  # the encoder's speed-signal lag (s) drawn in this range
    peak_creepages: tuple[float, float] = PROCEDURAL_PEAK_CREEPAGE  # a procedural curve's peak creepage (log-uniform)

    @property
    def env_options(self) -> dict[str, Any]:
        return dict(TWO_TONE_ENV_OPTIONS) if self.tone2_hz else {}

    def encoder_lag_s(self, seed: int) -> float:
        """Training episode ``seed``'s encoder lag (s): uniform in ``encoder_lags_s`` from a generator of its own,
        0 without that range."""
        return float(np.random.default_rng([seed, 31]).uniform(*self.encoder_lags_s)) if self.encoder_lags_s else 0.0

    def __post_init__(self) -> None:
        if self.tone2_hz is not None:
            check_range("ClimbDraws.tone2_hz", self.tone2_hz, MotorLimits.min_frequency_hz, MotorLimits.max_frequency_hz)
        check_range("ClimbDraws.tone2_weights", self.tone2_weights, 0.0, 2.0)
        if self.shapes not in SHAPE_SOURCES:
            raise ValueError(f"shapes must be one of {SHAPE_SOURCES}, got {self.shapes!r}")
        for name, high in (("noise_levels", NOISE_LEVEL_MAX), ("motor_lags_s", MOTOR_LAG_MAX_S),
                           ("encoder_lags_s", ENCODER_LAG_MAX_S)):
            if getattr(self, name) is not None:
                check_range(f"ClimbDraws.{name}", getattr(self, name), 0.0, high)
        for entry in self.sensor_errors:
            if not (isinstance(entry, (tuple, list)) and len(entry) == 3):
                raise ValueError(f"ClimbDraws.sensor_errors: each entry must be (field, low, high), got {entry!r}")
            name, low, high = entry
            if name not in SYSTEMATIC_ERRORS:
                raise ValueError(f"ClimbDraws.sensor_errors: unknown error {name!r}; allowed: {list(SYSTEMATIC_ERRORS)}")
            accepted = SYSTEMATIC_ERRORS[name].accepted
            check_range(f"ClimbDraws.sensor_errors {name}", (low, high), -accepted, accepted)
        check_range("ClimbDraws.peak_creepages", self.peak_creepages, 1e-4, MAX_DRAWN_PEAK_CREEPAGE)
        for name in ("frequencies_hz", "amplitude_ratios", "floor_margins", "crest_powers", "frequency_references_m_s"):
            value = getattr(self, name)
            if value is not None and not (len(value) == 2 and 0.0 < value[0] <= value[1]):
                raise ValueError(f"{name} must be a (low, high) pair with 0 < low <= high, got {value!r}")


def _reset(env, seed: int, draws: ClimbDraws) -> tuple[np.ndarray, dict[str, Any]]:
    """The env reset for training episode ``seed``: the env's own creep curve, or a procedural one; the env's
    sensor noise, drive lag and systematic errors, or ``draws``' (:func:`_sensor_options`)."""
    options = _sensor_options(seed, draws)
    if draws.shapes == "procedural":
        options["creep_law"] = procedural_shape(np.random.default_rng([seed, 11]), draws.fall, draws.peak_creepages)
    return env.reset(seed=seed, options=options or None)


def _sensor_options(seed: int, draws: ClimbDraws) -> dict[str, float]:
    """Training episode ``seed``'s noise level, motor lag and systematic errors where ``draws`` names their ranges
    (uniform, from generators of their own), as reset options; none where it leaves them to the env."""
    rng = np.random.default_rng([seed, 23])
    options = {name: float(rng.uniform(*span)) for name, span in (("noise_level", draws.noise_levels),
                                                                  ("motor_lag_s", draws.motor_lags_s)) if span}
    for k, (name, low, high) in enumerate(draws.sensor_errors):
        options[name] = float(np.random.default_rng([seed, 29, k]).uniform(low, high))
    if draws.encoder_lags_s:
        options["encoder_lag_s"] = draws.encoder_lag_s(seed)
    return options


def _labels(truth: dict[str, Any], dc_nm: float, reading: Reading) -> tuple[float, float]:
    """A window's targets: ``ln(M_sat / DC)`` and ``ln(CoF / CoA measured)``."""
    return math.log(truth["saturation_torque_nm"] / dc_nm), math.log(truth["cof"] / reading.coa)


def _policy_episode(env, agent, seed: int, draws: ClimbDraws) -> tuple[list[Reading], list[tuple[float, float]]]:
    """One episode of a deployed ``agent`` (the interrogator: it never reads the truth), on the training
    episode ``seed``: every driven window's reading and labels, as the agent's own climb chose its torques."""
    obs, info = _reset(env, seed, draws)
    truth = info["ground_truth"]
    agent.reset(obs, agent_view(info, oracle=False))
    xs, ys = [], []
    while True:
        action = agent.act(obs, agent_view(info, oracle=False))
        dc = agent.dc_nm
        obs, _, terminated, truncated, info = env.step(action)
        xs.append(Reading.of(obs, env.unwrapped.limits, info))
        ys.append(_labels(truth, dc, xs[-1]))
        if terminated or truncated:
            return xs, ys


def _climb_episode(env, seed: int, draws: ClimbDraws = ClimbDraws()) -> tuple[list[Reading], list[tuple[float, float]]]:
    """One training climb (module docstring): its readings and their labels."""
    rng = np.random.default_rng([seed, 7])
    obs, info = _reset(env, seed, draws)
    base = env.unwrapped
    limits = base.limits
    truth = info["ground_truth"]
    amplitude_ratio = float(math.exp(rng.uniform(*np.log(draws.amplitude_ratios))))
    if draws.frequencies_hz is None:
        frequency = 5.0 if rng.random() < 0.5 else float(math.exp(rng.uniform(math.log(3), math.log(10))))
    else:
        frequency = float(math.exp(rng.uniform(*np.log(draws.frequencies_hz))))
    if draws.frequency_references_m_s is not None:
        reference = float(math.exp(np.random.default_rng([seed, 19]).uniform(*np.log(draws.frequency_references_m_s))))
        frequency = speed_scaled_frequency(frequency, reference, Reading.of(obs, limits, info).speed_m_s, limits)
    tone2 = {}
    if draws.tone2_hz:
        tone_rng = np.random.default_rng([seed, 13])
        tone2 = {"tone2_frequency_hz": float(math.exp(tone_rng.uniform(*np.log(draws.tone2_hz)))),
                 "tone2_weight": float(tone_rng.uniform(*draws.tone2_weights))}
    p = ClimbParameters(amplitude_ratio=amplitude_ratio, frequency_hz=frequency, **tone2)
    sigma = float(math.exp(rng.uniform(*np.log(PROBING_SIGMA))))
    power, floor = float(rng.uniform(*PROBING_POWER)), float(rng.uniform(*PROBING_FLOOR))
    margin = float(rng.uniform(*draws.floor_margins)) if draws.floor_margins else None
    crest_power = float(np.random.default_rng([seed, 17]).uniform(*draws.crest_powers)) if draws.crest_powers else None
    dc = ElasticityClimb().first_dc(limits)
    xs, ys, ratio = [], [], None
    for _ in range(base.task.max_windows):
        obs, _, terminated, truncated, info = env.step(p.action(dc, 0.1, False, limits, ratio))
        reading = Reading.of(obs, limits, info)
        xs.append(reading)
        ys.append(_labels(truth, dc, reading))
        if terminated or truncated or dc > STOP_UTILISATION * truth["saturation_torque_nm"]:
            break
        step = _probing_step(rng, xs, sigma, power, floor)
        if margin is not None:
            step = max(step, floor_headroom(reading.coa) - margin)
        dc = min(dc * math.exp(step), limits.max_dc_torque_nm)
        if crest_power is not None:  # never grows again: a crest-capped climb's ratio falls as its headroom closes
            ratio = min(ratio or amplitude_ratio, _shrunk_ratio(xs, amplitude_ratio, crest_power))
    return xs, ys


def collect(env_id: str, configs: list[dict[str, Any]], episodes: int, first_seed: int = TRAINING_SEED,
            draws: ClimbDraws = ClimbDraws(), policy: str | None = None) -> Dataset:
    """``episodes`` training climbs (seeds ``first_seed...``), the configurations in turn; with ``policy`` (an
    interrogator's directory) that interrogator's own climbs on the same episodes (on policy: only
    ``draws.shapes`` and ``draws.fall`` are read, the climb is the policy's)."""
    if policy is None:
        envs = [gym.make(env_id, **c, **draws.env_options) for c in configs]
        play = lambda k, seed: _climb_episode(envs[k], seed, draws)  # noqa: E731
    else:
        options = manifest_climb(Path(policy)).env_options
        envs = [gym.make(env_id, **c, **options) for c in configs]
        agents = [interrogator_for(e, Path(policy)) for e in envs]
        play = lambda k, seed: _policy_episode(envs[k], agents[k], seed, draws)  # noqa: E731
    xs, cts, ys, eps = [], [], [], []
    for i in range(episodes):
        k = i % len(configs)
        x, y = play(k, first_seed + i)
        xs += [astuple(r) for r in x]
        ys += y
        cts += [bool(envs[k].unwrapped.task.counter_torque)] * len(x)
        eps += [i] * len(x)
    for e in envs:
        e.close()
    return Dataset(np.asarray(xs, dtype=np.float64).reshape(-1, len(READING_FIELDS)), np.asarray(cts, dtype=bool),
                   np.asarray(ys, dtype=np.float64).reshape(-1, len(TARGET_NAMES)), np.asarray(eps, dtype=np.int64))


def collect_parallel(env_id: str, configs: list[dict[str, Any]], episodes: int, workers: int,
                     first_seed: int = TRAINING_SEED, draws: ClimbDraws = ClimbDraws(),
                     policy: str | None = None) -> Dataset:
    """:func:`collect` split over ``workers`` processes (the same episodes, in the same order)."""
    if workers <= 1:
        return collect(env_id, configs, episodes, first_seed, draws, policy)
    n_configs = len(configs)
    chunk = math.ceil(episodes / workers / n_configs) * n_configs  # keeps the configuration rotation aligned
    starts = list(range(0, episodes, chunk))
    with ProcessPoolExecutor(workers) as pool:
        parts = list(pool.map(collect, [env_id] * len(starts), [configs] * len(starts),
                              [min(chunk, episodes - s) for s in starts], [first_seed + s for s in starts],
                              [draws] * len(starts), [policy] * len(starts)))
    return Dataset.concatenate(parts)


FIT_LOSSES = ("gaussian", "laplace")  # FitSettings.loss: the likelihood each member's outputs are fitted under
# the feature blocks a fit may be asked for (FitSettings.features): every optional block but tone 2's, which
# follows the data (two-tone climbs)
FITTABLE_BLOCKS = tuple(b for b in FEATURE_BLOCKS if b != "tone2")


def negative_log_likelihood(loss: str, residual, log_var, exp=np.exp):
    """The per-element NLL (up to a constant) of ``residual`` (target - location) under ``loss`` with
    variance ``exp(log_var)``: Gaussian, whose location is the conditional mean, or Laplace (scale
    ``b = sqrt(var / 2)``, NLL ``|r| / b + ln b``), whose location is the conditional median: the point
    that minimises the expected absolute error, the log-ratio's version of the relative CoF error the
    task scores (where the readings leave two creep curves possible, the mean falls between them, the
    median on the likelier). The network stores the variance either way, so its std means the same.
    ``exp``: ``np.exp`` for arrays, ``torch.exp`` for tensors."""
    if loss == "gaussian":
        return 0.5 * (log_var + residual**2 * exp(-log_var))
    return abs(residual) * math.sqrt(2.0) * exp(-0.5 * log_var) + 0.5 * log_var


@dataclass(frozen=True)
class FitSettings:
    hidden: tuple[int, ...] = (64, 64)
    epochs: int = 80
    batch_size: int = 512
    learning_rate: float = 2e-3
    weight_decay: float = 1e-5
    features: tuple[str, ...] = ()  # optional feature blocks besides tone 2's (which follows the data)
    loss: str = "gaussian"  # "gaussian": each output's mean (Gaussian NLL); "laplace": its median (Laplace NLL)

    def __post_init__(self) -> None:
        if self.loss not in FIT_LOSSES:
            raise ValueError(f"loss must be one of {FIT_LOSSES}, got {self.loss!r}")

    def blocks(self, data: "Dataset") -> tuple[str, ...]:
        """The feature blocks a member fitted on ``data`` reads, in :data:`FEATURE_BLOCKS` order."""
        if "tone2" in self.features:
            raise ValueError("features: tone2 follows the data (two-tone climbs), do not name it")
        wanted = set(self.features) | ({"tone2"} if data.tones == 2 else set())
        feature_names(wanted)  # an unknown block: ValueError naming the allowed ones
        return tuple(b for b in FEATURE_BLOCKS if b in wanted)


def fit_member(data: Dataset, seed: int, settings: FitSettings = FitSettings()) -> FilterNetwork:
    """One member: a bootstrap resample of ``data``'s episodes (``seed``), the NLL of ``settings.loss``, Adam."""
    import torch

    rng = np.random.default_rng(seed)
    episodes = np.unique(data.episode)
    chosen = rng.choice(episodes, size=len(episodes), replace=True)
    rows_of = {e: np.flatnonzero(data.episode == e) for e in episodes}
    rows = np.concatenate([rows_of[e] for e in chosen])
    blocks = settings.blocks(data)
    all_features = data.features_for(blocks)
    x, y = all_features[rows], data.targets[rows]
    mean, std = x.mean(axis=0), x.std(axis=0)
    std = np.where(std > 1e-8, std, 1.0)
    torch.manual_seed(seed)
    n_out = len(TARGET_NAMES)
    layers: list[Any] = []
    width = x.shape[1]
    for h in settings.hidden:
        layers += [torch.nn.Linear(width, h), torch.nn.Tanh()]
        width = h
    layers.append(torch.nn.Linear(width, 2 * n_out))
    net = torch.nn.Sequential(*layers).double()
    opt = torch.optim.Adam(net.parameters(), lr=settings.learning_rate, weight_decay=settings.weight_decay)
    sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, settings.epochs)
    xt = torch.as_tensor((x - mean) / std)
    yt = torch.as_tensor(y)
    gen = torch.Generator().manual_seed(seed)
    for _ in range(settings.epochs):
        for idx in torch.randperm(len(xt), generator=gen).split(settings.batch_size):
            out = net(xt[idx])
            mu, log_var = out[:, :n_out], out[:, n_out:].clamp(-12.0, 4.0)
            loss = negative_log_likelihood(settings.loss, yt[idx] - mu, log_var, torch.exp).mean()
            opt.zero_grad()
            loss.backward()
            opt.step()
        sched.step()
    linear = [m for m in net if isinstance(m, torch.nn.Linear)]
    return FilterNetwork(mean, std, tuple(m.weight.detach().numpy().T.copy() for m in linear),
                         tuple(m.bias.detach().numpy().copy() for m in linear), feature_names(blocks))


def nll(member_or_ensemble, data: Dataset) -> dict[str, float]:
    """Per-target RMSE and mean Gaussian NLL of a member's predictions on ``data`` (at least one window)."""
    if not len(data):
        raise ValueError("nll: data holds no window to score")
    x = data.features_for(member_or_ensemble.blocks)
    if isinstance(member_or_ensemble, FilterNetwork):
        mu, log_var = member_or_ensemble(x)
        std = np.exp(0.5 * log_var)
    else:
        mu, std = member_or_ensemble.predict(x)
    out = {}
    for k, name in enumerate(TARGET_NAMES):
        err = data.targets[:, k] - mu[:, k]
        out[f"{name}_rmse"] = float(np.sqrt(np.mean(err**2)))
        out[f"{name}_nll"] = float(np.mean(np.log(std[:, k]) + 0.5 * (err / std[:, k]) ** 2))
    return out
