"""One agent's episode as ``cof-gym evaluate`` plays and records it: :func:`run_episode` and its
:class:`EpisodeRecord` (the scenario, what the agent did and scored, how the episode ended)."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

from cof_gym.agents.base import agent_view
from cof_gym.task.reward import REWARD_TERMS

# how an episode ended, in the breakdown's order: the agent's stop action before its last step, the horizon (the
# episode ran to the task's last step, max_windows: the agent used every window it had, whether it asked to stop at
# that step or the task ended the episode there), a macro-slip (scored, penalised), a diverging simulation (unscored)
ENDINGS = ("stop", "horizon", "macro-slip", "diverged")
# a trace's window, in order: the env's elapsed time [s], the measured DC torque [N m], the speed sensor's reading and
# the wheel's speed [m/s], the measured CoA, the phase lag [deg], the agent's estimate and the true CoF
TRACE_FIELDS = ("t", "dc_torque_nm", "speed_m_s", "wheel_speed_m_s", "coa", "phase_deg", "estimate", "cof")
# a step as windows.csv holds it (evaluate --windows): its trace, whether it drove a window (a stop and a diverged
# step did not: their readings repeat the last window's, WindowTotals), the measured modulation amplitude [N m], the
# lag's standard error [deg] and the measured creepage, the step's reward and its terms, from the ground truth the
# true CoA and the true torque over the saturation torque, and the lower bound on the CoF the agent held in flight when
# it chose the step's action (its in_flight_lower_bound(), the learned interrogator's; None: none)
STEP_FIELDS = (*TRACE_FIELDS, "drove_window", "torque_amplitude_nm", "phase_se_deg", "creepage", "reward",
               *REWARD_TERMS, "coa_true", "torque_fraction", "lower_bound_in_flight")


@dataclass
class ScenarioColumns:
    """An episode's scenario as a record holds it: the entries of ``info["ground_truth"]`` of these names."""

    cof: float
    condition: str
    speed_m_s: float
    load_case: str
    noise_level: float
    motor_lag_s: float
    creep_family: str
    creepage_offset: float  # the sensors' systematic creepage error (1 + e_R)/(1 + e_v) - 1
    peak_creepage: float  # the creepage of the true creep curve's peak at the episode's speed and load

    @classmethod
    def read(cls, ground_truth: dict[str, Any]) -> dict[str, Any]:
        """These columns' values in an episode's ground truth."""
        return {f.name: ground_truth[f.name] for f in fields(cls)}


@dataclass
class EpisodeRecord(ScenarioColumns):
    """One agent's episode: its scenario (:class:`ScenarioColumns`), then what the agent did and scored."""

    agent: str
    oracle: bool
    episode: int
    seed: int
    estimate: float
    relative_error: float  # |estimate / CoF - 1|; 1.0 when the episode ended unscored (divergence)
    scored: bool
    macro_slip: bool
    # the windows the agent drove, each counted once (:class:`WindowTotals`): a stop runs none
    slip_energy_j: float  # energy dissipated past the creep-curve peak [J]
    friction_energy_j: float  # [J]
    wd_rms_m_s2: float  # over the driven windows (0 where none was driven) [m/s^2]
    measurement_time_s: float
    peak_torque_fraction: float  # max |torque| over the real saturation torque
    episode_return: float
    steps: int
    ended: str  # how the episode ended: one of ENDINGS
    note: str = ""  # the suite's label of the episode (e.g. a held-out grid's creep-curve shape)
    # the interval and the lower bound the agent reported around its estimate (CoF), for an agent that reports
    # them (cof_interval(), cof_lower_bound(): the learned interrogator's calibrated ones); None (an empty
    # cell) otherwise
    interval_low: float | None = None
    interval_high: float | None = None
    lower_bound: float | None = None
    # what the agent's own readings said lay outside the sensors it was fitted on ("; "-joined labels of its
    # sensor_notes(), e.g. the learned interrogator's "smoothed encoder"; "" for none, or an agent without them)
    sensor_notes: str = ""

    @property
    def in_interval(self) -> bool | None:
        """Whether the CoF lies in the reported interval (None without one or unscored)."""
        if self.interval_low is None or self.interval_high is None or not self.scored:
            return None
        return self.interval_low <= self.cof <= self.interval_high

    @property
    def above_lower_bound(self) -> bool | None:
        """Whether the CoF is at least the reported lower bound (None without one or unscored)."""
        return None if self.lower_bound is None or not self.scored else self.lower_bound <= self.cof

    @property
    def error_slip_failed(self) -> float:
        """The relative error with a macro-slip counted as a failed measurement (1.0, as an unscored episode):
        a measurement that spun the wheel past its peak is one a train would not make, however accurate the
        estimate the runaway gave."""
        return 1.0 if self.macro_slip or not self.scored else self.relative_error


def _field(info: dict, key: str, default: float = 0.0) -> float:
    """A window quantity wherever the env files it (ground truth first, then the sensor readings)."""
    for group in ("ground_truth", "measurement"):
        value = info.get(group, {}).get(key)
        if value is not None:
            return value
    return default


class AgentError(RuntimeError):
    """An agent failed in an episode: its ``reset`` or ``act`` raised, or it returned an action the env refuses. The
    message is one line naming the agent, the episode and its seed (the cause chained for a caller's traceback)."""


def _failed(agent: Any, what: str, episode: int, seed: int, error: Exception) -> AgentError:
    return AgentError(f"agent {agent.name} {what} in episode {episode} (seed {seed}): {type(error).__name__}: "
                      f"{' '.join(str(error).split())}")


@dataclass
class WindowTotals:
    """The energy and comfort of the windows an episode drove, each window counted once. A step adds its window
    only where one ran and was measured: the env's elapsed time grew and it did not diverge. A stop runs no
    window, and a diverged window has no measurement: the env's ``info`` repeats the last window's readings for
    both, which are not counted again (nor is the reset's baseline window, which the agent did not drive)."""

    slip_energy_j: float = 0.0
    friction_energy_j: float = 0.0
    wd_squared_sum: float = 0.0  # sum of the windows' Wd RMS squared [m^2/s^4] (windows of equal length)
    windows: int = 0
    elapsed_s: float = 0.0  # the env's elapsed time at the last window counted (or at the reset)

    def add(self, info: dict) -> bool:
        """The step's window, if it ran one (see the class); whether it did."""
        if info["elapsed_s"] <= self.elapsed_s or info.get("diverged", False):
            return False
        self.elapsed_s = info["elapsed_s"]
        self.windows += 1
        self.slip_energy_j += _field(info, "energy_past_peak_j")
        self.friction_energy_j += _field(info, "friction_energy_j")
        self.wd_squared_sum += info["measurement"]["wd_rms_m_s2"] ** 2
        return True

    @property
    def wd_rms_m_s2(self) -> float:
        """The Wd-weighted RMS acceleration over the windows counted [m/s^2]; 0 for none."""
        return math.sqrt(self.wd_squared_sum / self.windows) if self.windows else 0.0


def run_episode(env, agent, seed: int, options: dict, episode: int, trace: list | None = None,
                oracle: bool | None = None, note: str = "", steps_out: list | None = None) -> EpisodeRecord:
    """One episode of ``agent``. ``oracle`` (default: the agent's own flag) decides whether the agent
    sees ``info["ground_truth"]``; the evaluator always reads it for scoring. :class:`AgentError` where the agent
    raises or returns an action the env refuses. Each step is appended to ``trace`` (:data:`TRACE_FIELDS`) and to
    ``steps_out`` (:data:`STEP_FIELDS`) where they are given."""
    oracle = bool(getattr(agent, "oracle", False)) if oracle is None else bool(oracle)
    obs, info = env.reset(seed=seed, options=options)
    try:
        agent.reset(obs, agent_view(info, oracle))
    except Exception as e:  # noqa: BLE001 - whatever an agent (one of your own too) raises
        raise _failed(agent, "raised in reset", episode, seed, e) from e
    total, steps = 0.0, 0
    windows = WindowTotals(elapsed_s=info["elapsed_s"])
    peak = 0.0
    while True:
        try:
            action = agent.act(obs, agent_view(info, oracle))
        except Exception as e:  # noqa: BLE001
            raise _failed(agent, f"raised in act at step {steps}", episode, seed, e) from e
        bound = _in_flight_bound(agent, episode, seed, steps) if steps_out is not None else None
        try:
            obs, reward, terminated, truncated, info = env.step(action)
        except ValueError as e:  # the env's checks of the action (shape, type, finite values)
            raise _failed(agent, f"returned an action the env refuses at step {steps}", episode, seed, e) from e
        total += reward
        steps += 1
        m = info["measurement"]
        drove = windows.add(info)
        peak = max(peak, _field(info, "peak_torque_fraction"))  # the true torque, not the biased reading
        if trace is not None or steps_out is not None:
            window = dict(zip(TRACE_FIELDS, (
                info["elapsed_s"], m["torque_mean_nm"], m["speed_measured_m_s"],
                m["speed_measured_m_s"] * (1.0 + _field(info, "creepage_mean")), m["coa_measured"], m["phase_lag_deg"],
                info["cof_estimate"], info["ground_truth"]["cof"]), strict=True))
            if trace is not None:
                trace.append(window)
            if steps_out is not None:
                steps_out.append(_step_row(window, drove, info, reward, bound))
        if terminated or truncated:
            break
    gt = info["ground_truth"]
    macro_slip = bool(info.get("macro_slip", False))
    ended = ("diverged" if info.get("diverged", False) else "macro-slip" if macro_slip else
             "horizon" if truncated or steps >= env.unwrapped.task.max_windows else "stop")
    err = info.get("relative_error")
    scored = err is not None and bool(info.get("scored", True)) and not info.get("diverged", False)
    try:
        interval, notes = _reported_interval(agent), _sensor_notes(agent)
    except Exception as e:  # noqa: BLE001 - what an agent's own interval or notes method raises, or a bad report
        raise _failed(agent, "reported after its episode", episode, seed, e) from e
    return EpisodeRecord(
        **ScenarioColumns.read(gt), agent=agent.name, oracle=oracle, episode=episode, seed=seed,
        estimate=info["cof_estimate"],
        relative_error=float(err) if err is not None else 1.0, scored=scored,
        macro_slip=macro_slip, slip_energy_j=windows.slip_energy_j, friction_energy_j=windows.friction_energy_j,
        wd_rms_m_s2=windows.wd_rms_m_s2, measurement_time_s=info["elapsed_s"], peak_torque_fraction=peak,
        episode_return=total, steps=steps, note=note, ended=ended,
        interval_low=interval[0], interval_high=interval[1], lower_bound=interval[2],
        sensor_notes="; ".join(notes),
    )


def _step_row(window: dict[str, float], drove: bool, info: dict, reward: float,
              bound: float | None) -> dict[str, Any]:
    """A step's :data:`STEP_FIELDS`: its trace ``window``, whether it drove one, what ``info`` and ``reward`` add and
    the agent's in-flight lower ``bound``."""
    m, truth = info["measurement"], info["ground_truth"]
    return {**window, **dict(zip(STEP_FIELDS[len(TRACE_FIELDS):], (
        drove, m["torque_amplitude_nm"], m["phase_lag_se_deg"], m["creepage_measured"], reward,
        *(info[term] for term in REWARD_TERMS), truth["coa_true"], truth["torque_fraction"], bound), strict=True))}


def _in_flight_bound(agent, episode: int, seed: int, step: int) -> float | None:
    """The lower bound on the CoF ``agent`` holds in flight after its action (``in_flight_lower_bound()``; None for
    none, or an agent without it); :class:`AgentError` where it raises or reports no positive finite CoF."""
    try:
        bound = getattr(agent, "in_flight_lower_bound", lambda: None)()
        if bound is None:
            return None
        bound = float(bound)
        if not (math.isfinite(bound) and bound > 0.0):
            raise ValueError(f"reported the in-flight lower bound {bound!r}: it must be a positive finite CoF")
    except Exception as e:  # noqa: BLE001 - what an agent's own method raises, or a bad report
        raise _failed(agent, f"reported in flight at step {step}", episode, seed, e) from e
    return bound


def _sensor_notes(agent) -> tuple[str, ...]:
    """The labels of the agent's ``sensor_notes()`` after its episode (none for an agent without them); ValueError
    naming the agent unless each is a non-empty string without ';'."""
    notes = tuple(getattr(agent, "sensor_notes", tuple)())
    if not all(isinstance(n, str) and n and ";" not in n for n in notes):
        raise ValueError(f"{agent.name} reported the sensor notes {notes!r}: each must be a non-empty string "
                         "without ';'")
    return notes


def _reported_interval(agent) -> tuple[float | None, float | None, float | None]:
    """(low, high, lower bound) of the interval and the lower bound the agent reports around its estimate
    (``cof_interval()``, ``cof_lower_bound()``; None where it reports none). ValueError naming the agent
    unless each is a positive finite CoF and low <= high."""
    interval = getattr(agent, "cof_interval", lambda: None)()
    lower = getattr(agent, "cof_lower_bound", lambda: None)()
    low, high = (None, None) if interval is None else (float(interval[0]), float(interval[1]))
    lower = None if lower is None else float(lower)
    values = [v for v in (low, high, lower) if v is not None]
    if not all(math.isfinite(v) and v > 0.0 for v in values) or (low is not None and low > high):
        raise ValueError(f"{agent.name} reported the interval {interval!r} and the lower bound {lower!r}: each must "
                         "be a positive finite CoF, the interval's low end at most its high end")
    return low, high, lower
