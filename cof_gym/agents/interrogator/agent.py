"""The learned interrogator agent (:class:`LearnedInterrogator`) and its loading from a policy directory
(``member_*.npz`` and a ``manifest.json``: :func:`interrogator_for`)."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np

from cof_gym import MAX_EPISODE_STEPS, WAGON_ENV_ID
from cof_gym.agents.base import (
    configuration_note, env_defaults, episode_scenarios, outside_training_note, registered_ranges, without_defaults,
)
from cof_gym.agents.interrogator.caution import CautionPolicy, cautioned
from cof_gym.agents.interrogator.climb import (
    AT_HEADROOM, ESTIMATE_SOURCES, ESTIMATOR_ESTIMATES, GUARDED_ESTIMATES, HEADROOM_STOPS, ClimbParameters,
)
from cof_gym.agents.interrogator.features import EpisodeFeatures
from cof_gym.agents.interrogator.interval import NOISY, NOISY_RATIO, SMOOTHED, IntervalScales, sensor_group
from cof_gym.agents.interrogator.networks import FilterEnsemble, pooled_correction, pooled_std
from cof_gym.agents.policy_files import (  # noqa: F401 - read from here too
    MANIFEST_FILE, SHIPPED_INTERROGATOR, SHIPPED_INTERROGATOR_IN_SERVICE,
)
from cof_gym.agents.interrogator.readings import (
    NOISE_WINDOWS, NOISY_SENSORS, SLOW_DRIVE, SMOOTHED_ENCODER, Reading, reads_slow_drive, reads_smoothed_encoder,
)
from cof_gym.agents.phase_rule import ripple_possible
from cof_gym.agents.runaway import CrestCeiling, RunawayBracket
from cof_gym.agents.staircase import ElasticityClimb
from cof_gym.task.creep_fit import coa_fell
from cof_gym.task.interface import MotorLimits

WORLD_KWARGS = ("vehicle", "counter_torque", "traction_balance", "window_s", "settle_fraction", "ramp_fraction",
                "timestep", "lock_in")  # constructor arguments that change what the sensors see


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


@dataclass(frozen=True)
class NetworkSet:
    """A filter and its guards that steer and estimate a climb together (:attr:`LearnedInterrogator.smoothed_networks`:
    those of a climb whose first windows read a smoothed encoder), with the climb parameters they change for the
    decisions they take (``climb``: :class:`ClimbParameters` fields, e.g. ``{"caution": 2.5}``; none by default)."""

    filter: FilterEnsemble
    guards: tuple[FilterEnsemble, ...] = ()
    climb: Mapping[str, Any] = field(default_factory=dict)

    @property
    def networks(self) -> tuple[FilterEnsemble, ...]:
        """The filter, then the guards."""
        return (self.filter, *self.guards)


@dataclass
class LearnedInterrogator:
    """The agent (see the module docstring)."""

    limits: MotorLimits
    ensemble: FilterEnsemble
    counter_torque: bool = False
    params: ClimbParameters = field(default_factory=ClimbParameters)
    max_windows: int = MAX_EPISODE_STEPS  # the ids' horizon; a loaded agent takes its env's (load_interrogator)
    name: str = "interrogator"
    oracle: bool = False
    climb: ElasticityClimb = field(default_factory=ElasticityClimb, repr=False)
    features: EpisodeFeatures = field(init=False, repr=False)
    stop_reason: str = field(default="", repr=False)
    trained_on: tuple[str, tuple[dict[str, Any], ...]] | None = None  # (env id, vehicle configurations)
    guards: tuple[FilterEnsemble, ...] = ()  # further filters that may only slow the climb (module docstring)
    estimators: tuple[FilterEnsemble, ...] = ()  # further filters whose correction the estimate may read
    interval: IntervalScales | None = None  # the calibrated interval around the estimate (cof_interval), if any
    caution_policy: CautionPolicy | None = None  # sets each decision's caution from climb_state() (rule 104), if any
    # the filter and guards that steer and estimate a climb whose first windows read a smoothed encoder (rule 127)
    smoothed_networks: NetworkSet | None = None
    _guard_features: tuple[EpisodeFeatures, ...] = field(default=(), repr=False)
    _estimator_features: tuple[EpisodeFeatures, ...] = field(default=(), repr=False)
    _smoothed_features: tuple[EpisodeFeatures, ...] = field(default=(), repr=False)  # smoothed_networks' own
    _dc: float = 0.0
    _source_estimates: dict[str, float] = field(default_factory=dict, repr=False)  # per guarded/filter source
    _source_stds: dict[str, float] = field(default_factory=dict, repr=False)  # their corrections' stds (log units)
    _estimate: float = 0.0
    _best_coa: float = 0.0
    _driven: int = 0
    _crept: bool = False
    _stuck: bool = False  # a slow-probe step has made the probe sticky (ClimbParameters.sticks_from)
    _noise_ratio: float = 1.0  # the noise the climb's first windows read over the reference (noise_ratio)
    _smoothed: bool = False  # whether the first windows read a smoothed encoder (reads_smoothed_encoder)
    _ratio: float | None = None  # the modulation ratio of the next window (None: the climb's amplitude_ratio)
    _held_crest: float | None = None  # the torque crest the probe holds (N m; crest_probe_hold_crest)
    _frequency: float | None = None  # the episode's modulation frequency (Hz), from the first observation's speed
    _applied_fractions: list[float] = field(default_factory=list, repr=False)  # measured / commanded modulation
    _raised_by: float = 1.0  # the commanded modulation of the window the last action drives over the climb's
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
        if self.smoothed_networks is not None:
            self._check_smoothed_networks(self.smoothed_networks)
        for role, sources, networks in (("guards", GUARDED_ESTIMATES, self.guards),
                                        ("estimators", ESTIMATOR_ESTIMATES, self.estimators)):
            if self.params.estimate_from in sources and not networks:
                raise ValueError(f"estimate_from={self.params.estimate_from!r} reads the {role}' corrections, "
                                 f"but the interrogator has no {role}")

    def _check_smoothed_networks(self, networks: NetworkSet) -> None:
        """Raises ValueError where the smoothed-encoder networks read another excitation than the climb's or bring
        another number of guards than the climb's guards (their cautions are the climb's, guard by guard)."""
        if any(n.tones != self.params.tones for n in networks.networks):
            raise ValueError(f"smoothed_networks: a network reads another excitation than the climb's "
                             f"{self.params.tones} tone(s): use networks fitted on that excitation")
        if len(networks.guards) != len(self.guards):
            raise ValueError(f"smoothed_networks: {len(networks.guards)} guard(s) where the climb has "
                             f"{len(self.guards)}: the climb's guard cautions apply guard by guard")
        if networks.climb:
            try:
                replace(self.params, **networks.climb).check_guard_count(len(self.guards))
            except (TypeError, ValueError) as error:
                raise ValueError(f"smoothed_networks: climb {dict(networks.climb)}: {error}") from None

    @property
    def gated(self) -> bool:
        """Whether :attr:`smoothed_networks` steer and estimate the climb from here on: it has them, its first
        :data:`~cof_gym.agents.interrogator.readings.NOISE_WINDOWS` driven windows are read (the sensor note is
        final) and they read a smoothed encoder (:meth:`sensor_notes`) behind a drive the climb may hand them
        (:meth:`ClimbParameters.gates_drive`)."""
        return (self.smoothed_networks is not None and self._driven >= NOISE_WINDOWS and self._smoothed
                and self.params.gates_drive(self._applied_fractions, self._frequency))

    def _steering_networks(self) -> tuple[NetworkSet, tuple[EpisodeFeatures, ...]]:
        """The filter and guards that read the window just driven, with their features: the smoothed-encoder
        networks where the climb is :attr:`gated`, else the climb's own."""
        if self.gated:
            return self.smoothed_networks, self._smoothed_features
        return NetworkSet(self.ensemble, self.guards), (self.features, *self._guard_features)

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
        self._smoothed_features = () if self.smoothed_networks is None else tuple(
            EpisodeFeatures(self.counter_torque, blocks=n.blocks) for n in self.smoothed_networks.networks)
        self._dc = 0.0
        self._driven = 0
        self._crept = False
        self._stuck = False
        self._noise_ratio = 1.0
        self._smoothed = False
        self._ratio = None
        self._held_crest = None
        self._frequency = None
        self._start_speed: float | None = None  # the speed measured before the first window (m/s)
        self._applied_fractions = []
        self._torque_gain = None
        self._raised_by = 1.0
        self._best_coa = 0.0
        self._bracket = RunawayBracket()
        self._ceiling = CrestCeiling(fall_z=self.params.ceiling_fall_z)
        self._runaway = None
        self._source_estimates = {}
        self._source_stds = {}
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

    def candidate_estimates(self, best_coa_factor: float, runaway: bool = True) -> dict[str, float]:
        """The estimate of each source of :data:`ESTIMATE_SOURCES` after the windows so far (the
        trajectory does not depend on which one is reported; the guarded sources are 0 without guards, the
        estimators' without estimators; with ``crest_floor`` each at least the climb's best crest bound;
        with ``runaway_estimate`` and ``runaway``, after an action that is not a stop, each the runaway's estimate; with
        ``crest_ceiling``, once the crest has fallen under a rising torque crest, each at most
        :class:`~cof_gym.agents.runaway.CrestCeiling`'s bound)."""
        estimates = {**dict.fromkeys(ESTIMATE_SOURCES, 0.0), **self._source_estimates,
                     "best_coa": self._best_coa * best_coa_factor}
        at_headroom = self.stop_reason in HEADROOM_STOPS
        for source, at_stop in AT_HEADROOM.items():
            estimates[source] = estimates[at_stop if at_headroom else "filter"]
        if self.params.crest_floor:
            estimates = {source: max(value, self._bracket.crest_bound) for source, value in estimates.items()}
        if runaway and self.params.runaway_estimate and self._runaway is not None:
            estimates = dict.fromkeys(estimates, self._runaway)
        ceiling = self._ceiling.bound if self.params.crest_ceiling else None
        if ceiling is not None:
            estimates = {source: min(value, ceiling) for source, value in estimates.items()}
        return estimates

    def _in_range(self, estimate: float) -> float:
        """``estimate`` clipped to the drive's estimate range."""
        return self.limits.clip_estimate(estimate)

    @property
    def estimate(self) -> float:
        """The CoF estimate of the last action (within the drive's estimate range)."""
        return self._in_range(self._estimate)

    @property
    def estimate_log_std(self) -> float:
        """The std (log units) of the correction behind the estimate's source (``estimate_from``; an
        ``..._at_headroom`` source's at a headroom stop, the filter's before and at every other stop): 0 before
        the first driven window and for ``best_coa``. The crest floor, the crest ceiling and the runaway's
        estimate move the estimate, not this std; the calibrated interval measures how far to trust it."""
        source = self.params.estimate_from
        if source in AT_HEADROOM:
            source = AT_HEADROOM[source] if self.stop_reason in HEADROOM_STOPS else "filter"
        return self._source_stds.get(source, 0.0)

    @property
    def commitment(self) -> str:
        """How the estimate was committed (:data:`~cof_gym.agents.interrogator.interval.COMMITMENTS`): at the
        climb's own stop, at the horizon, or with no stop yet (an episode that ends there ended under the
        runaway estimate)."""
        return "horizon" if self.stop_reason == "horizon" else "stop" if self.stop_reason else "no stop"

    @property
    def noisy(self) -> bool:
        """Whether the climb's first windows read more noise than the v2 draws give (a noise ratio of at least
        :data:`~cof_gym.agents.interrogator.interval.NOISY_RATIO`): its interval takes the noisy scales."""
        return self._noise_ratio >= NOISY_RATIO

    @property
    def slow_drive(self) -> bool:
        """Whether the climb's first windows read a drive slower than the v2 draws give
        (:func:`~cof_gym.agents.interrogator.readings.reads_slow_drive`, from the modulation the drive applied)."""
        return reads_slow_drive(self._applied_fractions, self._frequency)

    def sensor_notes(self) -> tuple[str, ...]:
        """What this episode's own readings say lies outside the sensors the networks were fitted on:
        :data:`~cof_gym.agents.interrogator.readings.SMOOTHED_ENCODER` where the climb's first windows show a
        smoothed speed signal (:func:`~cof_gym.agents.interrogator.readings.reads_smoothed_encoder`: the networks
        met white encoder noise only, and a smoothing adds its delay to every phase lag),
        :data:`~cof_gym.agents.interrogator.readings.NOISY_SENSORS` where they read more noise than the draws give
        (:attr:`noisy`), :data:`~cof_gym.agents.interrogator.readings.SLOW_DRIVE` where they show a drive slower than
        the draws' (:func:`~cof_gym.agents.interrogator.readings.reads_slow_drive`: from the modulation the drive
        applied); none where the readings are like the training climbs'. Sensor readings only: a train can tell this
        without knowing its scenario. None for networks fitted on another id's climbs than the v2 wagon's (task v3's
        speed probe and track, e.g.): the notes' bounds describe the v2 wagon's training climbs."""
        if self.trained_on is not None and self.trained_on[0] != WAGON_ENV_ID:
            return ()
        read = ((SMOOTHED_ENCODER, self._smoothed), (NOISY_SENSORS, self.noisy), (SLOW_DRIVE, self.slow_drive))
        return tuple(note for note, seen in read if seen)

    @property
    def sensor_class(self) -> str:
        """The sensor class of the climb's interval (:data:`~cof_gym.agents.interrogator.interval.SENSOR_CLASSES`),
        read from its first windows: a smoothed encoder where :meth:`sensor_notes` names one, else "noisy" where the
        climb is :attr:`noisy`, else "" (the draws' sensors)."""
        return SMOOTHED if self._smoothed else NOISY if self.noisy else ""

    @property
    def interval_group(self) -> str:
        """The calibration group of the committed estimate's interval: its :attr:`commitment` in its sensor
        class."""
        return sensor_group(self.commitment, self.sensor_class)

    def cof_interval(self) -> tuple[float, float] | None:
        """The calibrated two-sided interval around :attr:`estimate` (:class:`IntervalScales`, at the scale of
        its :attr:`interval_group`), None without a calibration."""
        if self.interval is None:
            return None
        return self.interval.interval(self.estimate, self.estimate_log_std, self.interval_group)

    def cof_lower_bound(self) -> float | None:
        """The calibrated lower bound on the CoF under :attr:`estimate`, None without a calibration."""
        if self.interval is None:
            return None
        return self.interval.lower_bound(self.estimate, self.estimate_log_std, self.interval_group)

    @property
    def in_flight(self) -> str | None:
        """Where a climb that has not stopped stands (:data:`~cof_gym.agents.interrogator.interval.IN_FLIGHT`):
        "climbing" before its slow probe, "probing" in it; None before its first estimate and once it has stopped
        (then :attr:`commitment` says how)."""
        if self.stop_reason or not self._source_estimates:
            return None
        return "probing" if self._crept else "climbing"

    @property
    def in_flight_estimate(self) -> float | None:
        """The CoF the windows read so far give, at any window of a climb that has not stopped: the estimate
        source's, with the crest floor and ceiling but not the runaway's estimate (what :attr:`estimate` reports
        until the stop: a runaway in the coming window would leave no other), within the estimate range; its std
        is :attr:`estimate_log_std`. None where :attr:`in_flight` is."""
        if self.in_flight is None:
            return None
        return self._in_range(self.candidate_estimates(self.params.best_coa_factor, runaway=False)[self.params.estimate_from])

    @property
    def in_flight_group(self) -> str | None:
        """The calibration group of the in-flight estimate's interval: :attr:`in_flight` in its sensor class (None
        where that is)."""
        return None if self.in_flight is None else sensor_group(self.in_flight, self.sensor_class)

    def in_flight_interval(self) -> tuple[float, float] | None:
        """The calibrated two-sided interval around :attr:`in_flight_estimate` (at the scale of
        :attr:`in_flight_group`), None without a calibration or an in-flight estimate."""
        if self.interval is None or self.in_flight is None:
            return None
        return self.interval.interval(self.in_flight_estimate, self.estimate_log_std, self.in_flight_group)

    def in_flight_lower_bound(self) -> float | None:
        """The calibrated lower bound on the CoF under :attr:`in_flight_estimate`: what a braking planner may use
        before the climb has stopped; None without a calibration or an in-flight estimate."""
        if self.interval is None or self.in_flight is None:
            return None
        return self.interval.lower_bound(self.in_flight_estimate, self.estimate_log_std, self.in_flight_group)

    @property
    def demonstrated_adhesion(self) -> float:
        """The best crest bound the climb has carried without a runaway (measured CoA, a bin's standard error
        below the crest; 0 before one): the adhesion the wheel has shown it has, with no model at all."""
        return self._bracket.crest_bound

    @staticmethod
    def _pooled_predictions(filter_prediction: tuple[float, float], guard_predictions: list[tuple[float, float]],
                            estimator_predictions: list[tuple[float, float]] = ()
                            ) -> dict[str, list[tuple[float, float]]]:
        """The (mean, std) predictions of the correction ``ln(CoF / CoA)`` each source pools: the filter's, the
        guards', the filter's with the guards', the estimators', all of them, the guards' with the estimators' (those
        whose networks exist)."""
        sources = {"filter": [filter_prediction]}
        if guard_predictions:
            sources["guard"] = list(guard_predictions)
            sources["pooled"] = [filter_prediction, *guard_predictions]
        if estimator_predictions:
            sources["estimator"] = list(estimator_predictions)
            sources["estimator_pooled"] = [filter_prediction, *guard_predictions, *estimator_predictions]
        if guard_predictions and estimator_predictions:
            sources["guard_estimator_pooled"] = [*guard_predictions, *estimator_predictions]
        return sources

    @classmethod
    def _estimates_at(cls, coa: float, filter_prediction: tuple[float, float],
                      guard_predictions: list[tuple[float, float]],
                      estimator_predictions: list[tuple[float, float]] = ()) -> dict[str, float]:
        """The CoA times ``exp`` of each source's correction ``ln(CoF / CoA)``, from the filter's, each
        guard's and each estimator's (mean, std) of it."""
        sources = cls._pooled_predictions(filter_prediction, guard_predictions, estimator_predictions)
        corrections = {source: filter_prediction[0] if source == "filter" else pooled_correction(p)
                       for source, p in sources.items()}
        return {source: coa * math.exp(c) for source, c in corrections.items()}

    @classmethod
    def _stds_at(cls, filter_prediction: tuple[float, float], guard_predictions: list[tuple[float, float]],
                 estimator_predictions: list[tuple[float, float]] = ()) -> dict[str, float]:
        """Each source's std of its correction (:func:`pooled_std`; the filter's its own)."""
        sources = cls._pooled_predictions(filter_prediction, guard_predictions, estimator_predictions)
        return {source: filter_prediction[1] if source == "filter" else pooled_std(p) for source, p in sources.items()}

    @staticmethod
    def _corrections(networks: tuple[FilterEnsemble, ...], features: tuple[EpisodeFeatures, ...]) -> list[tuple[float, float]]:
        """Each network's (mean, std) of the correction ``ln(CoF / CoA)`` at the newest window."""
        outputs = [n.predict(f.vector()) for n, f in zip(networks, features)]
        return [(float(mean[0, 1]), float(std[0, 1])) for mean, std in outputs]

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        if self._dc > 0.0:
            p, stop = self._after_window(observation, info)
        else:
            p, stop = self.params, False
            self._dc = self.climb.first_dc(self.limits)
            self._start_speed = Reading.of(observation, self.limits, info).speed_m_s
            self._frequency = p.frequency_at(self._start_speed, self.limits,
                                             ripple_possible(info, p.rotation_ripple_max_se_deg))
        return self._command(p, stop)

    def _command(self, p: ClimbParameters, stop: bool) -> np.ndarray:
        """The action that drives the next window at the DC chosen (the modulation raised where ``p`` raises it)
        with the current estimate, or the stop."""
        estimate = self.estimate
        raise_by = 1.0 if stop else p.modulation_raise(self._applied_fractions)
        self._raised_by = p.commanded_amplitude(self._dc, self.limits, self._ratio, raise_by) / p.amplitude(
            self._dc, self.limits, self._ratio)
        return p.action(self._dc, estimate, stop, self.limits, self._ratio, self._frequency, raise_by)

    def climb_state(self) -> np.ndarray:
        """What the climb decided after its last window, as the caution policy reads it (float32, the fields of
        :data:`~cof_gym.agents.interrogator.caution.CLIMB_STATE_FIELDS`; zeros for the decision before the first
        window's): the filter's predicted headroom and std, the steering (cautious) headroom and its std, the log step
        taken, whether it has crept and whether the probe is sticky, the windows left over the horizon and the log of
        the noise ratio read. Sensor readings only."""
        d = self.decisions[-1] if self.decisions else None
        decided = [d.filter_headroom, d.filter_std, d.steering_headroom, d.steering_std, d.log_step, float(d.crept)] \
            if d else [0.0] * 6
        return np.array([*decided, float(self._stuck), self._windows_left / self.max_windows,
                         math.log(self._noise_ratio)], dtype=np.float32)

    def _decision_params(self) -> ClimbParameters:
        """The climb of the coming decision: ``params``, its caution set by the caution policy where there is one."""
        if self.caution_policy is None:
            return self.params
        return cautioned(self.params, self.caution_policy(self.climb_state()))

    def _after_window(self, observation: np.ndarray, info: dict[str, Any]) -> tuple[ClimbParameters, bool]:
        """Read the window just driven, update the estimates, and choose the next DC or the stop; returns the climb
        (its caution the policy's, where there is one) at the noise the first windows read
        (:meth:`ClimbParameters.at_noise`) and whether it stops."""
        params = self._decision_params()  # from the climb as it stood before this window
        self._driven += 1
        reading = self._reading(observation, info)
        previous = self.features.readings[-1] if self.features.readings else None
        falling = previous is not None and coa_fell(reading.coa, previous.coa)
        knee = previous is not None and self.params.knee_stops(reading, previous, self._driven, self._crept)
        self._bracket.observe(reading.crest_bound, reading.dc_nm + reading.amplitude_nm)  # the floor's bound too
        for features in (self.features, *self._guard_features, *self._estimator_features, *self._smoothed_features):
            features.push(reading)
        self._noise_ratio = params.noise_ratio(self.features.readings)
        self._smoothed = reads_smoothed_encoder(self.features.readings)
        if self.gated and self.smoothed_networks.climb:
            params = replace(params, **self.smoothed_networks.climb)
        p = params.at_noise(self._noise_ratio)
        networks, (filter_features, *guard_features) = self._steering_networks()
        mean, std, spread = networks.filter.predict_with_spread(filter_features.vector())
        guard_outputs = [g.predict_with_spread(f.vector()) for g, f in zip(networks.guards, guard_features)]
        steering = self._steering_headroom(p, mean, std, spread, guard_outputs)
        headroom, headroom_std, headroom_spread, caution = steering
        self._ceiling.observe(reading.coa_cycle_max, reading.coa_cycle_bin_se, reading.dc_nm + reading.amplitude_nm,
                              p.fall_margin(p.mean_headroom(headroom, headroom_std, headroom_spread, caution),
                                            self._noise_ratio))
        if not falling:
            self._update_estimates(reading, *self._estimate_outputs(p, networks, filter_features, guard_features,
                                                                    (mean, std), guard_outputs),
                                   p.relative_error_shift)
        step = self._next_step(p, reading, float(mean[0, 0]), *steering)
        stop = self._stop_or_step(p, step, headroom, self._stop_reason(p, step, falling, knee))
        self.decisions.append(WindowDecision(float(mean[0, 0]), float(std[0, 0]), headroom, headroom_std,
                                             0.0 if stop else step, self._crept, self.stop_reason))
        self._runaway = None if stop else self._bracket.estimate(
            self._dc + p.amplitude(self._dc, self.limits, self._ratio))
        self._estimate = self.candidate_estimates(p.best_coa_factor)[p.estimate_from]  # the stop's reason known
        return p, stop

    def _estimate_outputs(self, p: ClimbParameters, networks: NetworkSet, filter_features: EpisodeFeatures,
                          guard_features: list[EpisodeFeatures], filter_output: tuple[np.ndarray, np.ndarray],
                          guard_outputs: list[tuple[np.ndarray, np.ndarray, np.ndarray]]
                          ) -> tuple[np.ndarray, np.ndarray, list[tuple[np.ndarray, np.ndarray, np.ndarray]]]:
        """The filter's (mean, std) and the guards' outputs the estimate reads: those that steer, or with
        ``slow_drive_applied_estimate`` behind a slow drive (:attr:`slow_drive`) the same networks' outputs for the
        modulation the drive applied (:meth:`EpisodeFeatures.vector` with ``applied_ratio``)."""
        if not (p.slow_drive_applied_estimate and self.slow_drive):
            return (*filter_output, guard_outputs)
        mean, std, _ = networks.filter.predict_with_spread(filter_features.vector(applied_ratio=True))
        return mean, std, [g.predict_with_spread(f.vector(applied_ratio=True))
                           for g, f in zip(networks.guards, guard_features)]

    def _update_estimates(self, reading: Reading, mean: np.ndarray, std: np.ndarray,
                          guard_outputs: list[tuple[np.ndarray, np.ndarray, np.ndarray]], shift: float = 0.0) -> None:
        """The best CoA and every source's estimate and std after a window whose CoA has not fallen; each estimate
        times ``exp(-shift x std^2)`` (``ClimbParameters.relative_error_shift``)."""
        self._best_coa = max(self._best_coa, reading.coa)
        predictions = ((float(mean[0, 1]), float(std[0, 1])),
                       [(float(g_mean[0, 1]), float(g_std[0, 1])) for g_mean, g_std, _ in guard_outputs],
                       self._corrections(self.estimators, self._estimator_features))
        self._source_stds = self._stds_at(*predictions)
        self._source_estimates = {source: estimate * math.exp(-shift * self._source_stds[source] ** 2)
                                  for source, estimate in self._estimates_at(reading.coa, *predictions).items()}

    @property
    def _windows_left(self) -> int:
        """The windows the climb may still drive before the horizon's stop."""
        return self.max_windows - 1 - self._driven

    def _next_step(self, p: ClimbParameters, reading: Reading, filter_headroom: float, headroom: float,
                   headroom_std: float, headroom_spread: float, caution: float) -> float:
        """The next DC step (log units; below ``min_log_step`` a headroom stop) from the steering headroom: the gap
        to the target or the slow probe (held to it once sticky, paced to the horizon where ``p`` paces it), at least
        the floor's step, a stop the crest defers turned into a probe step. Marks the slow probe, whether it has
        become sticky (where the filter's own predicted headroom ``filter_headroom`` places the peak near) and the
        held crest."""
        step = p.log_step(headroom, headroom_std, headroom_spread, caution)
        if p.sticks(self._stuck, headroom):  # the peak may be near: no big step again
            step = min(step, p.creep_log_step)
        if p.creeps(headroom, headroom_std, headroom_spread, caution):
            self._mark_slow_probe(p, filter_headroom)
        if self._crept and step >= p.min_log_step:  # pacing sizes a slow-probe step, never turns a stop into one
            step = max(step, p.pace_step(headroom, headroom_std, headroom_spread, self._windows_left, caution))
        step = max(step, p.floor_step(reading.coa))  # safe whatever the filter predicts
        if step < p.min_log_step and p.probes_on(self.features.readings):  # a headroom stop the crest defers
            step = p.creep_log_step
            self._mark_slow_probe(p, filter_headroom)
            if p.crest_probe_hold_crest and self._held_crest is None:  # the crest of the window just read
                self._held_crest = self._dc + p.amplitude(self._dc, self.limits, self._ratio)
        return step

    def _mark_slow_probe(self, p: ClimbParameters, filter_headroom: float) -> None:
        """The climb has taken a slow-probe step; sticky from here where the filter places the peak near
        (:meth:`ClimbParameters.sticks_from`)."""
        self._crept = True
        self._stuck |= p.sticks_from(filter_headroom)

    def _stop_reason(self, p: ClimbParameters, step: float, falling: bool, knee: bool) -> str:
        """Why the climb stops after the window just read, the first that holds of: the CoA fell, a knee, the crest
        fell (the ceiling), the drive's DC limit, the horizon, the headroom closed ("" where it goes on, as far as
        these tell: a held crest may still stop it)."""
        if falling:
            return "falling"
        if knee:
            return "knee"
        if p.ceiling_stop and self._ceiling.reached:
            return "ceiling"
        if self._dc >= self.limits.max_dc_torque_nm:
            return "limit"
        if self._windows_left <= 0:
            return "horizon"
        return "headroom" if step < p.min_log_step else ""

    def _stop_or_step(self, p: ClimbParameters, step: float, headroom: float, reason: str) -> bool:
        """The stop (its reason recorded), or the step taken: the new DC and the modulation ratio it is driven with
        (within what a held crest carries; a step it cannot carry is a headroom stop). Returns whether it stops."""
        held_ratio = None
        if not reason:
            new_dc = min(self._dc * math.exp(step), self.limits.max_dc_torque_nm)
            if self._held_crest is not None:  # no DC step the held crest cannot carry: a headroom stop
                held_ratio = p.held_crest_ratio(self._held_crest, new_dc, self.limits)
                reason = "" if held_ratio is not None else "headroom"
        if reason:
            self.stop_reason = reason
            return True
        self._ratio = p.crest_ratio(headroom - math.log(new_dc / self._dc), self._crept, self._start_speed)
        if held_ratio is not None:
            self._ratio = min(self._ratio, held_ratio)
        self._dc = new_dc
        return False

    def _reading(self, observation: np.ndarray, info: dict[str, Any]) -> Reading:
        """The driven window's reading (with ``torque_balance``, its torque readings calibrated by the gain the
        first driven window's torque balance read), its applied fraction of the commanded modulation kept (where
        the torque's amplitude was measured) and, where the command was raised (``lag_floor``), its modulation described as
        the climb's own (the command over the raise), as the networks read a window of the lags they were fitted on."""
        reading = Reading.of(observation, self.limits, info)
        if self._torque_gain is None:  # the first driven window's, far below the peak
            self._torque_gain = self.params.torque_gain(reading)
        if self._torque_gain != 1.0:
            reading = reading.calibrated(self._torque_gain)
        if reading.torque_amplitude_measured_nm > 0.0 and reading.amplitude_nm > 0.0:
            self._applied_fractions.append(reading.torque_amplitude_measured_nm / reading.amplitude_nm)
        if self._raised_by != 1.0:
            reading = replace(reading, amplitude_nm=reading.amplitude_nm / self._raised_by)
        return reading

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
    manifest_file = Path(directory) / MANIFEST_FILE
    if not manifest_file.is_file():
        return {}
    try:
        manifest = json.loads(manifest_file.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ValueError(f"{manifest_file} is not JSON ({e})") from None
    if not isinstance(manifest, dict):
        raise ValueError(f"{manifest_file} must hold a JSON object (climb, trained_on, ...), got a "
                         f"{type(manifest).__name__}")
    return manifest


def write_manifest(directory: Path, manifest: dict[str, Any]) -> None:
    """Write ``manifest`` as ``directory/manifest.json`` (indented, as read_manifest reads it)."""
    (Path(directory) / MANIFEST_FILE).write_text(json.dumps(manifest, indent=2) + "\n")


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


def manifest_smoothed_networks(directory: Path) -> NetworkSet | None:
    """The networks ``directory``'s manifest names under ``smoothed_encoder`` (``{"filter": DIR, "guards": [DIR,
    ...], "climb": {NAME: VALUE, ...}}``, directories relative to it, the climb parameters optional) for a climb whose
    first windows read a smoothed encoder, None where it names none."""
    named = read_manifest(directory).get("smoothed_encoder")
    if named is None:
        return None
    if not isinstance(named, dict) or not isinstance(named.get("filter"), str) or not isinstance(
            named.get("guards", []), list) or not isinstance(named.get("climb", {}), dict):
        raise ValueError(f"{Path(directory) / 'manifest.json'}: smoothed_encoder must be "
                         '{"filter": DIR, "guards": [DIR, ...], "climb": {NAME: VALUE, ...}}')
    return NetworkSet(FilterEnsemble.load(Path(directory) / named["filter"]),
                      tuple(FilterEnsemble.load(Path(directory) / g) for g in named.get("guards", [])),
                      dict(named.get("climb", {})))


def interrogator_for(env, directory: Path, params: ClimbParameters | None = None,
                     guards: Iterable[Path] | None = None, estimators: Iterable[Path] | None = None) -> LearnedInterrogator:
    """The interrogator of ``directory`` (``member_*.npz``, a ``manifest.json`` with the climb's parameters, the
    training distribution, any guards and estimators and any smoothed-encoder networks
    (:func:`manifest_smoothed_networks`), and an optional calibrated interval:
    :class:`IntervalScales`) for ``env``'s drive and vehicle
    configuration; ``params`` replaces the manifest's climb, ``guards`` and ``estimators`` (directories of
    ``member_*.npz``) its guards and estimators. A two-tone climb acts in the env made with its ``env_options``."""
    directory = Path(directory)
    ensemble = FilterEnsemble.load(directory)
    trained = read_manifest(directory).get("trained_on")
    guard_dirs = manifest_guards(directory) if guards is None else tuple(guards)
    estimator_dirs = manifest_networks(directory, "estimators") if estimators is None else tuple(estimators)
    base = env.unwrapped
    caution_file = read_manifest(directory).get("caution_policy")
    return LearnedInterrogator(base.limits, ensemble, counter_torque=bool(base.task.counter_torque),
                               params=params or manifest_climb(directory),
                               max_windows=int(base.task.max_windows),
                               trained_on=(trained["env_id"], tuple(trained["configs"])) if trained else None,
                               guards=tuple(FilterEnsemble.load(g) for g in guard_dirs),
                               estimators=tuple(FilterEnsemble.load(e) for e in estimator_dirs),
                               interval=IntervalScales.load(directory),
                               caution_policy=CautionPolicy.load(directory / caution_file) if caution_file else None,
                               smoothed_networks=manifest_smoothed_networks(directory))


def load_interrogator(env, argument: str | None = None) -> LearnedInterrogator:
    """The shipped interrogator, or ``interrogator:DIR`` (see :func:`interrogator_for`)."""
    directory = Path(argument) if argument else SHIPPED_INTERROGATOR
    agent = interrogator_for(env, directory)
    if argument:
        agent.name = f"interrogator:{directory.name}"
    return agent


def load_interrogator_in_service(env, argument: str | None = None) -> LearnedInterrogator:
    """The learned interrogator fitted on task v3's wagon (``CofGym/TorqueInterrogationInService-v3``: a speed probe
    and an irregular track drawn; the recipe of experiments/train_interrogator.py run with ``--env`` there, shipped by
    rule 144, session 88): its own networks, guards and climb (the package's manifest). ``argument``: unused (the
    registry's factory signature; ``interrogator:DIR`` plays any other directory)."""
    agent = interrogator_for(env, SHIPPED_INTERROGATOR_IN_SERVICE)
    agent.name = "interrogator-in-service"
    return agent


# interrogator-rotation's distance (Hz) of its modulation frequency from the wheelset's rotation frequency and the
# side it moves to (ClimbParameters.rotation_margin_hz, rotation_side; experiments/select_rotation_margin.py --agent
# interrogator on validation seeds only, ranked by macro-slips, then median, then P90 with a runout read by the
# rotation lock-in: 2.9 / 22.9 / 0 against 3.8 / 42.6 / 0 at 5 Hz always; session 84 chose 1 Hz of the nearest side,
# 3.2 / 23.1 / 0, before the sides were played)
INTERROGATOR_ROTATION_MARGIN_HZ = 1.0
INTERROGATOR_ROTATION_SIDE = "below"
# ... only where the reset window leaves a runout's ripple possible (ClimbParameters.rotation_ripple_max_se_deg, deg;
# select_rotation_margin.py --gate --agent interrogator: every gate of 5-30 deg ties no gate but for one as-drawn
# median 0.01 points lower, so the rule's order picks 30)
INTERROGATOR_ROTATION_RIPPLE_MAX_SE_DEG = 30.0


def load_interrogator_rotation(env, argument: str | None = None) -> LearnedInterrogator:
    """The shipped interrogator (or ``interrogator-rotation:DIR``'s) with its climb's modulation frequency moved
    :data:`INTERROGATOR_ROTATION_MARGIN_HZ` clear of the wheelset's rotation frequency at the measured speed, below
    it, where the reset window leaves a runout's ripple possible (for a speed probe whose target wheel runs out, read
    by the rotation lock-in); every other setting its manifest's."""
    directory = Path(argument) if argument else SHIPPED_INTERROGATOR
    params = replace(manifest_climb(directory), rotation_margin_hz=INTERROGATOR_ROTATION_MARGIN_HZ,
                     rotation_side=INTERROGATOR_ROTATION_SIDE,
                     rotation_ripple_max_se_deg=INTERROGATOR_ROTATION_RIPPLE_MAX_SE_DEG)
    agent = interrogator_for(env, directory, params=params)
    agent.name = f"interrogator-rotation:{directory.name}" if argument else "interrogator-rotation"
    return agent
