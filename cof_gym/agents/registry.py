"""The agents ``cof-gym evaluate`` knows: name -> factory, with an ``oracle`` flag.

Adding an agent is one :func:`register` line. ``factory`` is ``"module:attribute"`` (imported only
when the agent is built, so listing agents imports neither torch nor SB3) and is called as
``factory(limits)`` with the env's :class:`~cof_gym.task.interface.MotorLimits` (the staircases'
convention), or as ``factory(env, argument)`` when registered with ``takes_env=True``. An agent
registered with ``argument="PATH"`` is named ``name:PATH`` on the command line.

Only agents registered with ``oracle=True`` receive ``info["ground_truth"]`` from the evaluator.

``NAME+runaway`` is the single-tone agent ``NAME`` reporting between its stops what a runaway in the
coming window would measure (:class:`~cof_gym.agents.runaway.RunawayEstimate`); an agent registered with
``runaway=True`` reports it under its own name (rule 24 in docs/interrogator.md chose which, on validation),
and ``NAME+plain`` is the agent without it. ``NAME+ceiling`` is the agent as registered with the crest
ceiling too (every estimate at most the crest once it has fallen under a rising torque crest:
:class:`~cof_gym.agents.runaway.CrestCeiling`); an agent registered with ``ceiling=True`` has it under its
own name.
"""

from __future__ import annotations

import importlib
import importlib.util
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from cof_gym import WAGON_IN_SERVICE_ENV_ID
from cof_gym.agents.policy_files import (
    MANIFEST_FILE, MODEL_NAMES, SHIPPED_INTERROGATOR, SHIPPED_INTERROGATOR_IN_SERVICE, SHIPPED_PPO,
)


class AgentSpecError(ValueError):
    """An agent name the registry does not know, or an argument it does not accept."""


@dataclass(frozen=True)
class AgentEntry:
    name: str
    factory: str  # "module:attribute"
    oracle: bool
    help: str = ""
    takes_env: bool = False  # factory(env, argument) instead of factory(limits)
    argument: str | None = None  # metavar of an optional ":ARG" (e.g. "PATH"), None: no argument
    default: bool = True  # part of the default --agents list when available
    shipped: Path | None = None  # a file the agent needs when named without ":ARG" (a shipped policy)
    runaway: bool = False  # reports the runaway estimate between its stops, under its own name
    ceiling: bool = False  # caps every estimate at the crest ceiling, under its own name
    check: str | None = None  # "module:function" checking an ":ARG" before any simulation (ValueError, one line)
    default_on: tuple[str, ...] = ()  # env ids whose suites also play it by default (an agent fitted for that task)

    @property
    def needs_argument(self) -> bool:
        """Named only with its ``:ARG`` (it takes one and ships nothing to play without it)."""
        return self.argument is not None and self.shipped is None

    @property
    def spellings(self) -> tuple[str, ...]:
        """How it is named on the command line: ``NAME`` (unless it needs its argument), ``NAME:ARG``."""
        return (() if self.needs_argument else (self.name,)) + ((f"{self.name}:{self.argument}",) if self.argument
                                                                 else ())

    def shipped_available(self) -> bool:
        return self.shipped is None or self.shipped.is_file()

    def available(self) -> bool:
        module = self.factory.partition(":")[0]
        try:
            return importlib.util.find_spec(module) is not None
        except ModuleNotFoundError:
            return False

    def load(self):
        module, _, attr = self.factory.partition(":")
        return getattr(importlib.import_module(module), attr)


AGENTS: dict[str, AgentEntry] = {}


def register(name: str, factory: str, *, oracle: bool, help: str = "", takes_env: bool = False,
             argument: str | None = None, default: bool = True, shipped: Path | None = None,
             runaway: bool = False, ceiling: bool = False, check: str | None = None,
             default_on: tuple[str, ...] = ()) -> None:
    """Register an agent under ``name`` (later registrations of the same name replace earlier ones)."""
    if not name or any(c in name for c in ":,+"):
        raise ValueError(f"agent names must be non-empty without ':', ',' or '+', got {name!r}")
    AGENTS[name] = AgentEntry(name, factory, oracle, help, takes_env, argument, default, shipped, runaway, ceiling,
                              check, tuple(default_on))


def _sb3(env, argument: str | None, prefix: str | None = None):
    """``sb3:PATH``: the Stable-Baselines3 or sb3-contrib model at PATH (a zip, a ``cof-gym train`` output or an RL
    Zoo run directory), named ``PREFIX:`` (default: its algorithm, e.g. ``sac:``) and the file's or directory's name;
    without a PATH the shipped PPO."""
    from cof_gym.agents.sb3_policy import SB3Agent

    path = Path(argument) if argument else SHIPPED_PPO
    agent = SB3Agent.load(path)
    if argument:
        agent.name = f"{prefix or agent.name}:{path.stem if path.suffix else path.name}"
    return agent


def _ppo(env, argument: str | None):
    """The shipped policy, or ``ppo:PATH`` (a model zip or a ``cof-gym train`` output directory)."""
    return _sb3(env, argument, prefix="ppo")


def shipped_ppo_available() -> bool:
    return AGENTS["ppo"].shipped_available()


register("oracle", "cof_gym.agents.oracle:SaturationOracle", oracle=True,
         help="holds 98.5 % of the true saturation torque, its 1 % crest below it, and reports the CoA there (the physics' floor)")
register("staircase-paper", "cof_gym.agents.staircase:PaperStaircase", oracle=True,
         help="the paper's rule on the true saturation torque (oracle)")
# runaway=True: rule 24 (session 23) on the validation grids; the phase rule's procedural median rose with it;
# ceiling=True: rule 29 (session 25) on the validation grids, no median or P90 higher for any of the four
register("staircase", "cof_gym.agents.staircase:PracticalStaircase", oracle=False, runaway=True, ceiling=True,
         help="a staircase that knows no ground truth")
register("phase-rule", "cof_gym.agents.phase_rule:PhaseRule", oracle=False, ceiling=True,
         help="the paper's phase rule without ground truth or creepage: the modulation probes ahead of the DC level, stop on a phase jump (validation-chosen)")
register("model-based", "cof_gym.agents.model_based:ModelBasedAgent", oracle=False, runaway=True, ceiling=True,
         help="creep-curve fit from windows below the peak")
# the two that read the creepage, reading it zeroed at the reset window, where no torque acts (session 73)
register("staircase-zeroed", "cof_gym.agents.zeroed:staircase_zeroed", oracle=False, runaway=True, ceiling=True,
         help="the staircase reading the creepage zeroed at the reset window (no torque: no creep)")
register("model-based-zeroed", "cof_gym.agents.zeroed:model_based_zeroed", oracle=False, runaway=True, ceiling=True,
         help="the model-based agent reading the creepage zeroed at the reset window (no torque: no creep), its fit "
         "reading both analytic families (Polach, Shen-Hedrick-Elkins)")
# the same, also stopping on the phase rule's jump test: a stop that does not trust the creepage alone (session 74,
# experiments/select_model_based.py on validation)
register("model-based-zeroed-knee", "cof_gym.agents.zeroed:model_based_zeroed_knee", oracle=False, runaway=True,
         ceiling=True, help="model-based-zeroed also stopping where the lag jumps (the phase rule's test; validation-chosen)")
register("robust-model", "cof_gym.agents.robust_model:RobustModel", oracle=False, runaway=True, ceiling=True,
         help="the phase rule's probing climb, the knee bracketed by bisecting the probe's crest at a held DC, no creepage read (validation-chosen)")
# the same reading the lag's SE for an autocorrelated speed residual (session 75; not in the default list, as the two
# below): under a smoothed encoder the knee agent's jump test fires on noise (README, sensor_sensitivity_zeroed)
register("model-based-zeroed-knee-ar1", "cof_gym.agents.zeroed:model_based_zeroed_knee_ar1", oracle=False,
         runaway=True, ceiling=True, default=False,
         help="model-based-zeroed-knee reading the lag's SE for an autocorrelated speed residual (a smoothed encoder)")
# the same two with the lag's SE for an autocorrelated speed residual (session 59; not in the default list): an
# encoder whose speed signal is smoothed (encoder_lag_s) makes the white-noise SE understate the lag's scatter
register("phase-rule-ar1", "cof_gym.agents.phase_rule:phase_rule_ar1", oracle=False, ceiling=True, default=False,
         help="the phase rule reading the lag's SE for an autocorrelated speed residual (a smoothed encoder signal)")
register("robust-model-ar1", "cof_gym.agents.robust_model:robust_model_ar1", oracle=False, runaway=True,
         ceiling=True, default=False,
         help="the robust model reading the lag's SE for an autocorrelated speed residual (a smoothed encoder signal)")
# the same two reading that SE only where the reset window's speed residual reads smoothed (session 65: its noise
# colour, cof_gym.measurement.sine_fit.noise_colour), the white one otherwise
register("phase-rule-gated", "cof_gym.agents.phase_rule:phase_rule_gated", oracle=False, ceiling=True, default=False,
         help="the phase rule reading that SE only where its reset window reads a smoothed speed signal")
register("robust-model-gated", "cof_gym.agents.robust_model:robust_model_gated", oracle=False, runaway=True,
         ceiling=True, default=False,
         help="the robust model reading that SE only where its reset window reads a smoothed speed signal")
# the phase rule modulating clear of the wheelset's rotation frequency (session 84; not in the default list): a speed
# probe's target wheel that runs out read by the rotation lock-in (experiments/select_rotation_margin.py on validation)
register("phase-rule-rotation", "cof_gym.agents.phase_rule:phase_rule_rotation", oracle=False, ceiling=True,
         default=False, help="the phase rule modulating at least ROTATION_MARGIN_HZ from the wheelset's rotation "
         "frequency at its measured speed (a speed probe's runout read by the rotation lock-in)")
# the phase rule chosen for task v3 (session 86; not in the default list: the default suite is v2's; in it on a suite of
# the v3 id, since session 88), on the v3 id's validation seeds by experiments/select_phase_rule.py --in-service
register("phase-rule-in-service", "cof_gym.agents.phase_rule:phase_rule_in_service", oracle=False, ceiling=True,
         default=False, default_on=(WAGON_IN_SERVICE_ENV_ID,), help="the phase rule chosen on task v3's validation seeds "
         "(CofGym/TorqueInterrogationInService-v3: a speed probe, an irregular track): a smaller probe at 8 Hz")
register("interrogator", "cof_gym.agents.interrogator:load_interrogator", oracle=False, takes_env=True,
         argument="DIR", shipped=SHIPPED_INTERROGATOR / MANIFEST_FILE,
         help="the learned interrogator (v2): a torque climb steered by a learned filter of phase, "
         "compliance and CoA; interrogator:DIR for other networks (a two-tone climb plays in an env of "
         "its own with the suite's scenarios)")
# the same modulating clear of the wheelset's rotation frequency (session 84; not in the default list)
register("interrogator-rotation", "cof_gym.agents.interrogator.agent:load_interrogator_rotation", oracle=False,
         takes_env=True, argument="DIR", shipped=SHIPPED_INTERROGATOR / MANIFEST_FILE, default=False,
         help="the learned interrogator modulating at least INTERROGATOR_ROTATION_MARGIN_HZ from the wheelset's "
         "rotation frequency at its measured speed (a speed probe's runout read by the rotation lock-in)")
# the same recipe fitted on task v3's wagon (rule 144, session 88; not in the default list: the default suite is v2's,
# out of its training distribution; in it on a suite of the v3 id)
register("interrogator-in-service", "cof_gym.agents.interrogator.agent:load_interrogator_in_service", oracle=False,
         takes_env=True, shipped=SHIPPED_INTERROGATOR_IN_SERVICE / MANIFEST_FILE, default=False,
         default_on=(WAGON_IN_SERVICE_ENV_ID,),
         help="the learned interrogator fitted on task v3 (CofGym/TorqueInterrogationInService-v3: a speed probe, an "
         "irregular track): the same recipe, its climbs collected there")
register("ppo", "cof_gym.agents.registry:_ppo", oracle=False, takes_env=True, argument="PATH",
         shipped=SHIPPED_PPO / MODEL_NAMES[0], check="cof_gym.agents.sb3_policy:check_model_argument",
         help="the shipped PPO policy, or ppo:PATH for any saved model")
register("sb3", "cof_gym.agents.registry:_sb3", oracle=False, takes_env=True, argument="PATH", default=False,
         check="cof_gym.agents.sb3_policy:check_model_argument",
         help="sb3:PATH: a policy saved by Stable-Baselines3 or sb3-contrib (PPO, A2C, TRPO, SAC, TD3, DDPG, TQC, "
         "CrossQ, ARS, RecurrentPPO; the algorithm read from its policy class), a cof-gym train output or an RL Zoo "
         "run directory")

# an agent of your own, from a Python file, without registering it (cof_gym/agents/plugin.py)
register("py", "cof_gym.agents.plugin:python_agent", oracle=False, takes_env=True, argument="FILE.py:NAME",
         default=False, check="cof_gym.agents.plugin:check_python_agent",
         help="py:FILE.py:NAME: an agent of your own, NAME(limits) of that file (reset and act; never an oracle)")


def check_argument(entry: AgentEntry, argument: str | None) -> None:
    """``entry``'s check of its ``:ARG`` (none without one), before anything is simulated; ``ValueError``."""
    if argument is not None and entry.check is not None:
        module, _, function = entry.check.partition(":")
        getattr(importlib.import_module(module), function)(argument)


def names(available_only: bool = True) -> list[str]:
    return [n for n, e in AGENTS.items() if not available_only or e.available()]


def describe() -> str:
    """``a, b, c or ppo:PATH`` for messages."""
    from cof_gym.agents.runaway import CEILING_MODIFIER, MODIFIER

    spellings = [s for n in names() for s in AGENTS[n].spellings]  # the bare names first, then NAME:ARG
    parts = ([s for s in spellings if ":" not in s] + [s for s in spellings if ":" in s]
             + [f"any of them +{MODIFIER}, +{CEILING_MODIFIER} or +{PLAIN}"])
    return ", ".join(parts[:-1]) + f" or {parts[-1]}" if len(parts) > 1 else "".join(parts)


def default_agents(env_id: str | None = None) -> list[str]:
    """The agents ``cof-gym evaluate`` plays without ``--agents``, in registration order: those registered with
    ``default``, and on a suite of ``env_id`` also those whose ``default_on`` names it; each only where it can be
    built here (its module and shipped files present)."""
    out = []
    for name, entry in AGENTS.items():
        if not (entry.default or env_id in entry.default_on) or not entry.available():
            continue
        if not entry.shipped_available():
            continue
        out.append(name)
    return out


def default_on_text() -> str:
    """``; on a suite of ID also A, B`` for every id some agent's ``default_on`` names (help texts); empty if none."""
    ids = dict.fromkeys(i for e in AGENTS.values() for i in e.default_on)
    base = set(default_agents())
    return "".join(f"; on a suite of {i} also {','.join(n for n in default_agents(i) if n not in base)}" for i in ids)


PLAIN = "plain"  # the agent-name suffix of an agent without the runaway estimate or the crest ceiling


def split_modifier(spec: str) -> tuple[str, str | None]:
    """``NAME[:ARG]+runaway``, ``+ceiling`` or ``+plain`` -> (``NAME[:ARG]``, the modifier); any other spec ->
    (spec, None)."""
    from cof_gym.agents.runaway import CEILING_MODIFIER, MODIFIER

    spec = spec.strip()
    for modifier in (MODIFIER, CEILING_MODIFIER, PLAIN):
        if spec.endswith(f"+{modifier}"):
            return spec[: -len(modifier) - 1], modifier
    return spec, None


def parse(spec: str) -> tuple[AgentEntry, str | None]:
    """``name`` or ``name:ARG`` (either with ``+runaway``, ``+ceiling`` or ``+plain``) -> (entry, ARG or None);
    :class:`AgentSpecError` for anything else."""
    if not isinstance(spec, str):
        raise AgentSpecError(f"an agent is named by a string (e.g. 'phase-rule' or 'interrogator:DIR'), got {spec!r}")
    name, sep, argument = split_modifier(spec)[0].partition(":")
    entry = AGENTS.get(name)
    if entry is None or not entry.available():
        raise AgentSpecError(f"unknown agent {spec.strip()!r}; allowed: {describe()}")
    if sep and entry.argument is None:
        raise AgentSpecError(f"agent {name!r} takes no ':' argument, got {spec.strip()!r}")
    if (sep and not argument) or (not sep and entry.needs_argument):
        raise AgentSpecError(f"agent {name}:{entry.argument} needs a value after ':', got {spec.strip()!r}")
    if not sep and not entry.shipped_available():
        raise AgentSpecError(f"no shipped {name} policy in this installation ({entry.shipped} is missing); use "
                             f"{name}:{entry.argument} with a trained one")
    return entry, (argument if sep else None)


def make_agent(spec: str, env: Any):
    """Build the agent named by ``spec`` for ``env``, wrapped in
    :class:`~cof_gym.agents.runaway.RunawayEstimate` where it reports the runaway bracket or the crest
    ceiling: with ``+runaway`` the bracket alone; with ``+ceiling`` the ceiling and, registered with
    ``runaway``, the bracket; without a modifier what it is registered with; with ``+plain`` as its factory
    builds it (named so)."""
    entry, argument = parse(spec)
    if not hasattr(getattr(env, "unwrapped", None), "limits"):
        raise ValueError(f"make_agent({spec!r}, env): env must be a cof_gym env (gym.make of one of its ids), "
                         f"got {env!r}")
    factory = entry.load()
    agent = factory(env, argument) if entry.takes_env else factory(env.unwrapped.limits)
    return as_registered(entry, agent, env.unwrapped.limits, split_modifier(spec)[1])


def _wrapping(entry: AgentEntry, modifier: str | None) -> tuple[bool, bool]:
    """Whether ``entry``'s agent with ``modifier`` reports the runaway bracket and whether it caps its estimates at
    the crest ceiling (see :func:`make_agent`)."""
    from cof_gym.agents.runaway import CEILING_MODIFIER, MODIFIER

    if modifier == PLAIN:
        return False, False
    return (modifier == MODIFIER or entry.runaway,
            modifier == CEILING_MODIFIER or (modifier is None and entry.ceiling))


def plays_as(spec: str) -> tuple[str, str | None, bool, bool]:
    """What the agent ``spec`` names plays as: (registered name, its ':' argument, bracket, ceiling). Two specs with
    the same play the same agent, e.g. ``staircase`` and ``staircase+ceiling`` (registered with the ceiling)."""
    entry, argument = parse(spec)
    return (entry.name, argument, *_wrapping(entry, split_modifier(spec)[1]))


def check_distinct(specs: list[str]) -> None:
    """:class:`AgentSpecError` naming the first two of ``specs`` that play the same agent (:func:`plays_as`): one
    name given twice, or e.g. ``staircase`` and ``staircase+ceiling``."""
    seen: dict[tuple, str] = {}
    for spec in (s.strip() for s in specs):
        play = plays_as(spec)
        if play not in seen:
            seen[play] = spec
        elif seen[play] == spec:
            raise AgentSpecError(f"agent {spec!r} is given twice")
        else:
            raise AgentSpecError(f"agents {seen[play]!r} and {spec!r} are the same agent (its registration already has "
                                 "what the name adds): give one")


def as_registered(entry: AgentEntry, agent: Any, limits: Any, modifier: str | None = None):
    """``agent`` (built by ``entry``'s factory, or as that factory would with other parameters) wrapped as
    :func:`make_agent` wraps it for ``entry`` with ``modifier`` (None, ``runaway``, ``ceiling`` or ``plain``) for
    the drive ``limits``."""
    from cof_gym.agents.runaway import RunawayEstimate

    if modifier == PLAIN:
        agent.name = f"{agent.name}+{PLAIN}"
        return agent
    bracket, ceiling = _wrapping(entry, modifier)
    if not (bracket or ceiling):
        return agent
    return RunawayEstimate(agent, limits, name=f"{agent.name}+{modifier}" if modifier else agent.name,
                           bracket=bracket, ceiling=ceiling)

