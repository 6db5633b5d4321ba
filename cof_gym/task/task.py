"""The torque-interrogation task: scenario draw, ground truth, action and observation interface, reward,
constraints and horizon, in one object that the single and the vector environment both compose with
their physics (as dm_control composes a Task with a Physics).

An :class:`Episode` holds one episode's bookkeeping; the task's methods turn a window's measurement
into what the environment returns. The physics (one ``Simulation`` or rows of a ``mujoco.batch``)
is the environment's business.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Any, Mapping

import numpy as np
from gymnasium import spaces

from cof_gym import MAX_EPISODE_STEPS
from cof_gym.physics.models import DEFAULT_TIMESTEP_S, BuiltModel, build_half_wheelset, build_wagon
from cof_gym.physics.creep import NoPeakError
from cof_gym.physics.creep_laws import CreepShape, draw_shape
from cof_gym.physics.simulation import LOCK_INS, DriveCommand, Scenario, WindowMeasurement
from cof_gym.physics.vehicle import HalfWheelsetParameters, wagon_parameters
from cof_gym.task.ground_truth import GroundTruth, ground_truth, max_saturation_torque_nm, static_contact_load_n
from cof_gym.task.actions import ACTION_TYPES, ActionContext, get_action_type
from cof_gym.task.excitation import Excitation
from cof_gym.task.info_layout import INFO_LAYOUTS, flatten_info
from cof_gym.task.interface import (
    ACTION_NAMES, OBS_BOUND, OBSERVATION_TYPES, SENSOR_FIELDS, DecodedAction, Memory, MotorLimits, ObservationScales,
    check_action, encode_observation, get_observation_type,
)
from cof_gym.task.reward import (COST_TERMS, NO_COSTS, SHAPING_TERM, MacroSlipLimit, Reward, discomfort, log_error,
                                 relative_error, slip_cost)
from cof_gym.task.scenarios import COF_ENVELOPE, EpisodeScenario, ScenarioRanges, check_fixed, draw_scenario, physics_scenario
from cof_gym.validation import check_bool, check_choice, check_int, check_number

VEHICLES = ("wagon", "half_wheelset")
DEFAULT_MAX_WINDOWS = MAX_EPISODE_STEPS  # the horizon the ids register (one number, in cof_gym/__init__.py)
TIMESTEP_RANGE_S = (1e-4, 2e-3)  # stable for every vehicle and scenario (tests/test_envs.py)
DRIVE_MARGIN = 1.25  # the drive's DC torque reaches 1.25 x the largest saturation torque in range
SHAPING_GAMMA = 0.95  # the discount the shaping potential assumes (agents' hyperparams' gamma)
BASELINE_DRIVE = DriveCommand(0.0, 100.0, 5.0)  # the reset window: no DC torque, a small modulation
MAX_DRAWN_PEAK_CREEPAGE = 0.2  # a drawn creep curve peaks below 20 % creepage (else drawn again)
# a fixed creep law without a peak at a draw's speed, load and CoF: the draw is made again, at most this many times
MAX_FIXED_LAW_DRAWS = 100
# the drawn fields on which whether a fixed creep law has a peak depends (the condition sets the CoF's range)
PEAK_FIELDS = ("speed_m_s", "load_case", "cof", "condition")
WINDOW_TRUTH_FIELDS = (
    "coa_true", "creepage_mean", "creep_phase_lag_deg", "creepage_amplitude", "normal_load_n", "tangential_force_n",
    "friction_energy_j", "time_past_peak_s", "energy_past_peak_j", "max_abs_creepage",
)


@lru_cache(maxsize=16)
def built_model(vehicle: str, load_case: str, timestep: float, counter_torque: bool) -> BuiltModel:
    """Models are built once per process and shared (read-only) by every env."""
    if vehicle == "wagon":
        return build_wagon(wagon_parameters(load_case), timestep=timestep, counter_torque=counter_torque)
    return build_half_wheelset(HalfWheelsetParameters(), timestep=timestep)


@dataclass
class Episode:
    """One episode's state: its scenario, ground truth and bookkeeping."""

    scenario: EpisodeScenario
    truth: GroundTruth
    built: BuiltModel
    physics: Scenario
    drive: DriveCommand = BASELINE_DRIVE
    estimate: float = 0.0
    elapsed_s: float = 0.0
    windows: int = 0
    potential: float = 0.0
    last: WindowMeasurement | None = None
    done: bool = False
    memory: Memory = field(default_factory=Memory)  # of the sensor-only window observations (best CoA, history)
    observation: np.ndarray | None = None  # the last observation returned

    @property
    def action_context(self) -> ActionContext:
        """What the action type may read: the applied DC torque and the best measured CoA."""
        return ActionContext.of(self.drive.dc_torque_nm, self.memory)


@dataclass(frozen=True)
class InterrogationTask:
    """Everything the environment scores and shows, apart from the physics.

    Arguments are checked strictly (types and ranges); see the environment's docstring table."""

    vehicle: str = "wagon"
    window_s: float = 1.0
    settle_fraction: float = 0.4
    ramp_fraction: float = 0.3
    max_windows: int = DEFAULT_MAX_WINDOWS
    counter_torque: bool = False
    traction_balance: bool | None = None  # None: on for the wagon without counter torque
    timestep: float = DEFAULT_TIMESTEP_S
    ranges: ScenarioRanges = field(default_factory=ScenarioRanges)
    fixed: Mapping[str, Any] = field(default_factory=dict)
    reward: Reward = field(default_factory=Reward)
    macro_slip: MacroSlipLimit = field(default_factory=MacroSlipLimit)
    shaping: bool = False
    action_type: str = "absolute"  # cof_gym.task.actions.ACTION_TYPES
    observation_type: str = "window"  # cof_gym.task.interface.OBSERVATION_TYPES
    info_layout: str = "nested"  # cof_gym.task.info_layout.INFO_LAYOUTS
    excitation: str = "sine"  # cof_gym.task.excitation.EXCITATIONS
    tones: int = 2  # tones of the "multitone" excitation (2 or 3)
    lock_in: str = "plain"  # the speed's lock-in: cof_gym.physics.simulation.LOCK_INS

    def __post_init__(self) -> None:
        check_choice("action_type", self.action_type, tuple(ACTION_TYPES))
        check_choice("observation_type", self.observation_type, tuple(OBSERVATION_TYPES))
        check_choice("info_layout", self.info_layout, INFO_LAYOUTS)
        check_choice("vehicle", self.vehicle, VEHICLES)
        check_choice("lock_in", self.lock_in, LOCK_INS)
        # the checked values are stored (a numpy scalar as the Python number it holds, so that it computes
        # exactly as that number would; a Python float is stored unchanged)
        set_ = object.__setattr__
        set_(self, "window_s", check_number("window_s", self.window_s, 0.2, 10.0, unit=" s"))
        set_(self, "settle_fraction", check_number("settle_fraction", self.settle_fraction, 0.0, 0.8))
        set_(self, "ramp_fraction", check_number("ramp_fraction", self.ramp_fraction, 0.0, self.settle_fraction))
        set_(self, "max_windows", check_int("max_windows", self.max_windows, 1, 10_000))
        set_(self, "counter_torque", check_bool("counter_torque", self.counter_torque))
        set_(self, "shaping", check_bool("shaping", self.shaping))
        set_(self, "timestep", check_number("timestep", self.timestep, *TIMESTEP_RANGE_S, unit=" s"))
        if self.counter_torque and self.vehicle != "wagon":
            raise ValueError(f"counter_torque=True needs the wagon (vehicle='wagon'): the counter torque acts on the "
                             f"bogie's other wheelset, which vehicle={self.vehicle!r} does not have")
        if self.traction_balance is not None:
            set_(self, "traction_balance", check_bool("traction_balance", self.traction_balance))
            if self.traction_balance and (self.counter_torque or self.vehicle != "wagon"):
                raise ValueError("traction_balance=True needs the wagon without counter_torque (the counter torque "
                                 "already cancels the traction; the half wheelset has no train)")
        for name, kind in (("ranges", ScenarioRanges), ("reward", Reward), ("macro_slip", MacroSlipLimit)):
            if not isinstance(getattr(self, name), kind):
                raise ValueError(f"{name} must be a {kind.__name__}, got {getattr(self, name)!r}")
        if self.vehicle == "half_wheelset":
            object.__setattr__(self, "ranges", replace(self.ranges, load_cases=("laden",)))
        object.__setattr__(self, "fixed", check_fixed(self.fixed, self.ranges.load_cases))
        # the interrogation signal (checks excitation and tones against the measured span)
        object.__setattr__(self, "_signal", Excitation(self.excitation, self.tones, self.window_s - self.settle_s))
        set_(self, "tones", self._signal.tones)  # as checked there (a Python int)

    @property
    def signal(self) -> Excitation:
        """The interrogation signal (:mod:`cof_gym.task.excitation`)."""
        return self._signal

    # ------------------------------------------------------------------ derived constants
    @property
    def balanced(self) -> bool:
        """Whether the rest of the train cancels the DC part of the interrogation torque."""
        if self.traction_balance is not None:
            return self.traction_balance
        return self.vehicle == "wagon" and not self.counter_torque

    @property
    def settle_s(self) -> float:
        return self.settle_fraction * self.window_s

    @property
    def ramp_s(self) -> float:
        return self.ramp_fraction * self.window_s

    @property
    def horizon_s(self) -> float:
        return self.max_windows * self.window_s

    def model(self, load_case: str) -> BuiltModel:
        return built_model(self.vehicle, load_case, self.timestep, self.counter_torque)

    @property
    def limits(self) -> MotorLimits:
        return _limits(self.model(self.ranges.load_cases[-1]), self.balanced)

    def scales(self, built: BuiltModel) -> ObservationScales:
        return ObservationScales(self.limits, built.drive_spin_inertia_kg_m2, static_contact_load_n(built),
                                 self.horizon_s)

    @property
    def actions(self):
        """The action type (:mod:`cof_gym.task.actions`)."""
        return get_action_type(self.action_type)

    @property
    def observations(self):
        """The observation type (:data:`cof_gym.task.interface.OBSERVATION_TYPES`)."""
        return get_observation_type(self.observation_type)

    @property
    def action_names(self) -> tuple[str, ...]:
        """The action's components: the action type's 5, then the excitation's (none for "sine")."""
        return ACTION_NAMES + self.signal.action_names

    @property
    def action_space(self):
        if not self.signal.multitone:
            return self.actions.space()
        return spaces.Box(-1.0, 1.0, shape=(len(self.action_names),), dtype=np.float32)

    @property
    def observation_names(self) -> tuple[str, ...]:
        """The observation type's names, then the excitation's per-tone values (none for "sine")."""
        return tuple(self.observations.names) + self.signal.observation_names

    @property
    def observation_space(self):
        if not self.signal.multitone:
            return self.observations.space()
        return spaces.Box(-OBS_BOUND, OBS_BOUND, shape=(len(self.observation_names),), dtype=np.float32)

    def check_action(self, action: Any) -> np.ndarray:
        """A real, finite action of the task's shape (``ValueError`` otherwise), clipped to [-1, 1]."""
        return check_action(action, self.action_names)

    # ------------------------------------------------------------------ episode
    def new_episode(self, rng: np.random.Generator, options: Mapping[str, Any] | None) -> Episode:
        """Draw a scenario (``options`` fix fields for this episode) and its ground truth."""
        fixed = {**self.fixed, **check_fixed({} if options is None else options, self.ranges.load_cases)}
        built, truth, wheel_load, scenario = self._draw(rng, fixed)
        physics = physics_scenario(scenario, wheel_load, seed=int(rng.integers(2**31)), traction_balance=self.balanced,
                                   lock_in=self.lock_in)
        episode = Episode(scenario=scenario, truth=truth, built=built, physics=physics,
                          drive=self.signal.baseline(BASELINE_DRIVE))
        episode.potential = self._potential(episode)
        return episode

    def decode(self, episode: Episode, action: Any) -> DecodedAction:
        """Check and decode an action; it sets the drive of the episode's next window."""
        if episode.done:
            raise RuntimeError("the episode has ended: call reset() before step()")
        a = self.check_action(action)
        decoded = self.actions.decode(episode.action_context, a[:len(ACTION_NAMES)], self.limits)
        if self.signal.multitone:  # the action type's amplitude is the total; the extra components add tones
            decoded = replace(decoded, drive=self.signal.drive(decoded.drive, a[len(ACTION_NAMES):]))
        if not decoded.stop:  # a stop runs no window: the drive stays what the last window applied
            episode.drive = decoded.drive
        episode.estimate = decoded.cof_estimate
        return decoded

    def observe(self, episode: Episode, sensed: WindowMeasurement) -> np.ndarray:
        """The observation of a window from what the sensors read of it (called once per window): the
        window's sensor-only encoding is recorded in the episode's memory, and the observation type builds
        the observation from both."""
        window = encode_observation(sensed, episode.drive, self.scales(episode.built), episode.elapsed_s,
                                    episode.estimate)
        episode.memory.push(window, driven=episode.windows > 0)
        episode.observation = self.observations.encode(window, episode.memory)
        if self.signal.multitone:
            tones = self.signal.features(sensed, episode.drive, episode.built.drive_spin_inertia_kg_m2)
            tones = np.clip(tones, -OBS_BOUND, OBS_BOUND).astype(np.float32)
            episode.observation = np.concatenate([episode.observation, tones]).astype(np.float32)
        return episode.observation.copy()

    def after_reset(self, episode: Episode, m: WindowMeasurement) -> tuple[np.ndarray, dict]:
        """The first observation and info, from the baseline window."""
        episode.last = m
        sensed = episode.scenario.sensor_errors.read(m)  # systematic errors change readings, not physics
        return self.observe(episode, sensed), self._info(episode, m, sensed, {}, diverged=False, macro_slip=False,
                                                         scored=False)

    def after_step(self, episode: Episode, m: WindowMeasurement, decoded: DecodedAction,
                   diverged: bool) -> tuple[np.ndarray, float, bool, bool, dict]:
        """(obs, reward, terminated, truncated, info) from the window's measurement."""
        episode.windows += 1
        episode.elapsed_s += self.window_s
        if diverged:
            m = episode.last
        episode.last = m
        macro_slip = diverged or self.macro_slip.violated(m, episode.truth.peak_creepage)
        terminated = bool(macro_slip or decoded.stop)
        truncated = episode.windows >= self.max_windows and not terminated
        scored = terminated or truncated
        err = log_error(episode.estimate, episode.truth.cof) if scored else None
        sc = episode.scenario
        contact_load = static_contact_load_n(episode.built)
        terms = self.reward.terms(m, contact_load, sc.speed_m_s, self.window_s, err, macro_slip)
        if self.shaping:
            # Phi = 0 in terminal states; a truncated state is not terminal (learners bootstrap there)
            potential = 0.0 if terminated else self._potential(episode)
            terms[SHAPING_TERM] = SHAPING_GAMMA * potential - episode.potential
            episode.potential = potential
        reward = float(sum(terms.values()))
        costs = dict(zip(COST_TERMS, (slip_cost(m, contact_load, sc.speed_m_s, self.window_s), discomfort(m),
                                      float(macro_slip))))
        sensed = episode.scenario.sensor_errors.read(m)
        info = self._info(episode, m, sensed, {**terms, "cost": costs}, diverged, macro_slip, scored)
        episode.done = terminated or truncated
        return self.observe(episode, sensed), reward, terminated, truncated, info

    def after_stop(self, episode: Episode) -> tuple[np.ndarray, float, bool, bool, dict]:
        """The agent stopped: its estimate is scored at once, no window is run (no time, slip or comfort
        cost); the observation is the last window's."""
        err = log_error(episode.estimate, episode.truth.cof)
        terms = self.reward.terms_without_window(err)
        if self.shaping:
            terms[SHAPING_TERM] = -episode.potential  # Phi = 0 in the terminal state
            episode.potential = 0.0
        costs = dict(NO_COSTS)
        info = self._info(episode, episode.last, episode.scenario.sensor_errors.read(episode.last),
                          {**terms, "cost": costs}, False, False, True)
        episode.done = True
        return episode.observation.copy(), float(sum(terms.values())), True, False, info

    # ------------------------------------------------------------------ helpers
    def _draw(self, rng: np.random.Generator,
              fixed: Mapping[str, Any]) -> tuple[BuiltModel, GroundTruth, float, EpisodeScenario]:
        """A scenario and its ground truth. A fixed creep law that has no peak (no CoF) at the drawn speed, load
        and CoF is played where it has one: the scenario is drawn again (the fixed fields kept; at most
        :data:`MAX_FIXED_LAW_DRAWS` times, none where those fields are all fixed), as a drawn shape is; a first
        draw that has a peak is played as drawn."""
        drawn = [name for name in PEAK_FIELDS if name not in fixed]
        redraws = MAX_FIXED_LAW_DRAWS - 1 if "creep_law" in fixed and drawn else 0
        for attempt in range(redraws + 1):
            scenario = draw_scenario(rng, self.ranges, fixed)
            built = self.model(scenario.load_case)
            try:
                truth, wheel_load, scenario = self._truth(built, scenario, rng, shape_fixed="creep_law" in fixed)
            except NoPeakError as e:
                if attempt < redraws:
                    continue
                if redraws:
                    raise NoPeakError(f"{e} (and at each of {redraws + 1} draws of {', '.join(drawn)}: fix "
                                      f"speed_m_s, load_case and cof where the curve has a peak)") from None
                raise
            return built, truth, wheel_load, scenario
        raise AssertionError("unreachable")

    def _truth(self, built: BuiltModel, scenario: EpisodeScenario, rng: np.random.Generator,
               shape_fixed: bool) -> tuple[GroundTruth, float, EpisodeScenario]:
        """The ground truth; a *drawn* shape whose curve has no peak, or one beyond
        :data:`MAX_DRAWN_PEAK_CREEPAGE`, at the episode's speed and load is drawn again (the acceptance
        test of :func:`~cof_gym.physics.creep_laws.draw_shape`, randomness from ``rng``)."""
        redraw = not shape_fixed and scenario.creep_law is not None
        truths: dict[CreepShape | str, tuple[GroundTruth, float]] = {}

        def usable(shape: CreepShape | str) -> bool:
            try:
                truths[shape] = ground_truth(built, self.balanced, scenario.cof, shape, scenario.speed_m_s)
            except NoPeakError:
                if not redraw:
                    raise
                return False
            return not redraw or truths[shape][0].peak_creepage <= MAX_DRAWN_PEAK_CREEPAGE

        try:
            ok = usable(scenario.shape)
        except (ValueError, RuntimeError) as e:  # no peak, or mu0 not solvable: name the law the user fixed
            if not (shape_fixed and scenario.creep_law is not None):
                raise
            raise NoPeakError(f"creep_law.{scenario.creep_family}: {e}") from None
        if not ok:
            shape = draw_shape(rng, scenario.creep_family, scenario.condition, accept=usable)
            scenario = replace(scenario, creep_law=shape)
        truth, wheel_load = truths[scenario.shape]
        return truth, wheel_load, scenario

    def _potential(self, episode: Episode) -> float:
        """Phi = w_error (E_max - |ln(estimate / CoF)|) >= 0, E_max the largest error in range."""
        lim = self.limits
        e_max = math.log(lim.max_cof_estimate / lim.min_cof_estimate)
        est = lim.clip_estimate(episode.estimate)
        return self.reward.w_error * max(e_max - log_error(est, episode.truth.cof), 0.0)

    def _info(self, episode: Episode, m: WindowMeasurement, sensed: WindowMeasurement, extra: dict, diverged: bool,
              macro_slip: bool, scored: bool) -> dict:
        """The step's info: ``m`` the window (ground truth), ``sensed`` what the sensors read of it."""
        truth = episode.truth
        info: dict[str, Any] = {**extra}
        info.setdefault("cost", dict(NO_COSTS))
        info["diverged"] = bool(diverged)
        info["macro_slip"] = bool(macro_slip)
        info["scored"] = bool(scored)
        info["cof_estimate"] = episode.estimate
        if scored:  # the errors exist once the estimate is scored; info holds no None
            info["log_error"] = log_error(episode.estimate, truth.cof)
            info["relative_error"] = relative_error(episode.estimate, truth.cof)
        info["elapsed_s"] = episode.elapsed_s
        info["measurement"] = {k: getattr(sensed, k) for k in SENSOR_FIELDS}
        info["measurement"].update(self.signal.measurement_info(sensed, episode.drive))
        info["ground_truth"] = {
            **episode.scenario.to_dict(), **truth.to_dict(),
            "macro_slip_creepage": self.macro_slip.limit(truth.peak_creepage),
            **{k: getattr(m, k) for k in WINDOW_TRUTH_FIELDS},
            "torque_fraction": episode.drive.dc_torque_nm / truth.saturation_torque_nm,
            "peak_torque_fraction": m.torque_peak_nm / truth.saturation_torque_nm,
        }
        return flatten_info(info) if self.info_layout == "flat" else info


@lru_cache(maxsize=32)
def _limits(laden: BuiltModel, balanced: bool) -> MotorLimits:
    """The drive reaches DRIVE_MARGIN x the largest saturation torque of the envelope's top CoF."""
    return MotorLimits(max_dc_torque_nm=DRIVE_MARGIN * max_saturation_torque_nm(laden, balanced, COF_ENVELOPE[1]),
                       wheel_radius_m=laden.wheel_radius_m)
