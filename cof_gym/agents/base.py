"""The one small interface every agent implements: observation (and info) in, action out."""

from __future__ import annotations

from collections import Counter
from typing import Any, Iterable, Mapping, Protocol, Sequence, runtime_checkable

import numpy as np

from cof_gym.task.scenarios import SCENARIO_KEYS, ScenarioRanges, outside_draws


@runtime_checkable
class Agent(Protocol):
    """A measurement policy. ``info`` is the environment's info dict; only agents labelled as oracles
    may read ``info["ground_truth"]``. An agent may also report, after its episode, an interval around its
    estimate, ``cof_interval() -> (low, high)``, and a lower bound, ``cof_lower_bound() -> float`` (CoF; None:
    none), which ``cof-gym evaluate`` records and scores (the learned interrogator's calibrated ones), and, after
    each action, the lower bound it holds in flight, ``in_flight_lower_bound() -> float`` (None: none yet), which
    ``cof-gym watch`` draws."""

    name: str
    oracle: bool

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        """Start an episode from the reset observation."""

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        """The action (float32, shape (5,), in [-1, 1]) for the next window."""


class AgentWrapper:
    """Base of an agent that wraps another (``self.agent``): it is an oracle where the wrapped one is, and every
    attribute it does not set itself (its limits, its interval, its notes, ...) is the wrapped agent's. A subclass sets
    ``agent`` and ``name`` and calls :meth:`_wrap` after them."""

    agent: Any

    def _wrap(self) -> None:
        self.oracle = bool(getattr(self.agent, "oracle", False))

    def __getattr__(self, attribute: str) -> Any:
        if attribute.startswith("_") or attribute == "agent":
            raise AttributeError(attribute)
        return getattr(self.agent, attribute)


def agent_view(info: dict[str, Any], oracle: bool) -> dict[str, Any]:
    """The info dict an agent receives: without ``ground_truth`` unless the agent is an oracle."""
    if oracle:
        return info
    return {k: v for k, v in info.items() if k != "ground_truth"}


def own_env_options(agent: Any) -> dict[str, Any]:
    """The env options an agent acts in beyond a suite's (``agent.env_options``, e.g. the two-tone
    interrogator's excitation); {} for an agent that has none."""
    return dict(getattr(agent, "env_options", None) or {})


def registered_ranges(env_id: str, env_kwargs: Mapping[str, Any] | None = None) -> ScenarioRanges:
    """The scenario draws of a registered env id made with ``env_kwargs`` (its ``ranges`` kwarg, else
    the default draws of its task version)."""
    import gymnasium as gym

    from cof_gym.envs.torque_interrogation import default_ranges

    kwargs = {**gym.spec(env_id).kwargs, **(env_kwargs or {})}
    return kwargs["ranges"] if kwargs.get("ranges") is not None else default_ranges(kwargs.get("task_version", 2))


def check_parameters(agent: Any, positive: Iterable[str] = (), off_at_infinity: Iterable[str] = ()) -> None:
    """A hand-built agent's numeric parameters (its dataclass fields, the private ones aside) as its defaults are:
    a bool stays a bool, an int an int, a number a real number that is never NaN, >= 0 where its default is (> 0
    for the fields named in ``positive``: scales such as a frequency or an amplitude) and infinite only where its
    default is or for the fields named in ``off_at_infinity`` (a test's threshold whose +inf turns the test off).
    ``ValueError`` naming the agent's class and the field at construction, not a NaN action or a silently clipped one
    mid-episode."""
    import dataclasses
    import math
    import numbers

    cls = type(agent).__name__
    for f in dataclasses.fields(agent):
        default, value = f.default, getattr(agent, f.name)
        if f.name.startswith("_") or isinstance(default, str) or not isinstance(default, numbers.Real):
            continue  # a name, a flag of another kind, a structure, or None (an optional switch: its own check)
        where = f"{cls}.{f.name}"
        if isinstance(default, bool):
            if not isinstance(value, (bool, np.bool_)):
                raise ValueError(f"{where} must be a bool (True or False), got {value!r}")
            continue
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real) or math.isnan(value):
            raise ValueError(f"{where} must be a number, got {value!r} ({type(value).__name__})")
        if isinstance(default, numbers.Integral) and not isinstance(value, numbers.Integral):
            raise ValueError(f"{where} must be an integer, got {value!r}")
        if math.isinf(value) and not math.isinf(default) and not (value > 0 and f.name in off_at_infinity):
            raise ValueError(f"{where} must be finite, got {value!r}")
        strict = f.name in positive
        if (strict and not value > 0) or (default >= 0 and value < 0):
            raise ValueError(f"{where} must be {'> 0' if strict else '>= 0'}, got {value!r}")


def env_defaults(env_id: str) -> dict[str, Any]:
    """The constructor arguments a registered cof_gym env id is made with by default: its spec's kwargs
    over the constructor's defaults (the constructor's alone for an id that is not registered)."""
    import inspect

    import gymnasium as gym

    from cof_gym.envs.torque_interrogation import TorqueInterrogationEnv

    defaults = {name: p.default for name, p in inspect.signature(TorqueInterrogationEnv.__init__).parameters.items()
                if p.default is not inspect.Parameter.empty}
    try:
        defaults.update(gym.spec(env_id).kwargs)
    except gym.error.Error:
        pass
    return defaults


def without_defaults(env_id: str, kwargs: Mapping[str, Any]) -> dict[str, Any]:
    """``kwargs`` less the arguments equal to ``env_id``'s defaults (:func:`env_defaults`): the env made with
    ``counter_torque=False`` is the env made without it (a bool never equals a number here)."""
    defaults = env_defaults(env_id)

    def default(name: str, value: Any) -> bool:
        if name not in defaults or isinstance(value, bool) != isinstance(defaults[name], bool):
            return False
        try:
            return bool(value == defaults[name])
        except (TypeError, ValueError):  # e.g. an array's elementwise comparison
            return False

    return {k: v for k, v in kwargs.items() if not default(k, v)}


def episode_scenarios(env_kwargs: Mapping[str, Any], episodes: Iterable[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Each episode's fixed scenario fields as the env applies them: the scenario fields given as constructor
    arguments (``env_kwargs``, e.g. ``noise_level``), with an episode's reset options over them (an option
    None leaves the constructor's value, as the env does)."""
    fixed = {k: v for k, v in env_kwargs.items() if k in SCENARIO_KEYS and v is not None}
    return [{**fixed, **{k: v for k, v in options.items() if v is not None}} for options in episodes]


def configuration_note(name: str, env_id: str, world: Mapping[str, Any], trained_id: str,
                       trained_worlds: Sequence[Mapping[str, Any]]) -> str | None:
    """A line naming how an evaluation's env id and world-changing constructor arguments (``world``:
    what the agent's sensors see differently, e.g. ``counter_torque``) differ from those an agent was
    trained on (the nearest of ``trained_worlds``), None when they are one of them."""
    if env_id == trained_id and any(dict(world) == dict(w) for w in trained_worlds):
        return None

    def differing(w: Mapping[str, Any]) -> list[str]:
        return [k for k in sorted(set(world) | set(w)) if world.get(k) != w.get(k)]

    nearest = min(trained_worlds, key=lambda w: len(differing(w)), default={})
    differs = [f"{k}={world.get(k, 'default')!r} (trained: {nearest.get(k, 'default')!r})" for k in differing(nearest)]
    if env_id != trained_id:
        differs.insert(0, f"env {env_id} (trained: {trained_id})")
    return f"{name} is out of its training distribution here: " + ", ".join(differs)


def outside_training_note(name: str, ranges: ScenarioRanges, episodes: Iterable[Mapping[str, Any]]) -> str | None:
    """A line counting the episodes (their ``reset`` options) that lie outside the scenario draws
    ``ranges`` an agent was trained on, per field with an example; None when every episode lies inside."""
    episodes = list(episodes)
    counts: Counter[str] = Counter()
    example: dict[str, str] = {}
    outside = 0
    for options in episodes:
        why = outside_draws(options, ranges)
        outside += bool(why)
        counts.update(why.keys())
        for field_name, reason in why.items():
            example.setdefault(field_name, reason)
    if not outside:
        return None
    fields_text = "; ".join(f"{f} in {n} (e.g. {example[f]})" for f, n in counts.most_common())
    return (f"{name}: {outside} of {len(episodes)} episodes lie outside the scenario draws it was trained on, "
            f"out of its training distribution: {fields_text}")
