"""Agents of your own, played beside cof_gym's without registering them: ``py:FILE.py:NAME``.

``NAME`` is read from the Python file ``FILE.py`` (a path, relative to the working directory; imported once per
process, under a module name of its own) and called with the env's :class:`~cof_gym.task.interface.MotorLimits`
(the scripted agents' convention, e.g. ``PracticalStaircase(limits)``); what it returns is the agent: an object with
``reset(observation, info)`` and ``act(observation, info) -> action`` (:class:`~cof_gym.agents.base.Agent`; its
``name``, when it has one, names it in the tables, ``NAME`` otherwise). Such an agent never reads the ground truth:
``info["ground_truth"]`` is taken out of what it receives, as for every agent that is not a registered oracle.
Every problem found before the first episode (no such file, an import that fails, no such name, an object that is not
an agent) is a ``ValueError`` naming the file, which ``cof-gym evaluate`` and ``cof-gym watch`` print as one line.
"""

from __future__ import annotations

import hashlib
import importlib.util
import sys
from pathlib import Path
from typing import Any, Callable

from cof_gym.validation import TABLE_CELL_FORBIDDEN

SUFFIX = ".py"


def split_argument(argument: str) -> tuple[Path, str]:
    """``FILE.py:NAME`` -> (the file's absolute path, NAME); ``ValueError`` for any other form."""
    file, sep, name = argument.rpartition(":")
    if not sep or not file.endswith(SUFFIX) or not name.isidentifier():
        raise ValueError(f"expected FILE{SUFFIX}:NAME (a Python file and a name in it), got {argument!r}")
    return Path(file).resolve(), name


def load_factory(argument: str) -> Callable[..., Any]:
    """The callable ``NAME`` of ``FILE.py`` (``ValueError`` naming the file where it cannot be had)."""
    path, name = split_argument(argument)
    if not path.is_file():
        raise ValueError(f"no such file: {path}")
    module_name = "cof_gym_user_agent_" + hashlib.sha1(str(path).encode()).hexdigest()[:12]
    module = sys.modules.get(module_name)
    if module is None:
        spec = importlib.util.spec_from_file_location(module_name, path)
        if spec is None or spec.loader is None:
            raise ValueError(f"{path} cannot be imported as a Python module")
        module = importlib.util.module_from_spec(spec)
        try:
            spec.loader.exec_module(module)
        except Exception as e:  # noqa: BLE001 - whatever the user's module raises on import
            raise ValueError(f"importing {path} raised {type(e).__name__}: {' '.join(str(e).split())}") from None
        sys.modules[module_name] = module
    factory = getattr(module, name, None)
    if not callable(factory):
        raise ValueError(f"{path} has no callable {name!r}")
    return factory


def check_python_agent(argument: str) -> None:
    """The check of ``py:FILE.py:NAME`` before anything is simulated: the file imports and holds the callable."""
    load_factory(argument)


def python_agent(env: Any, argument: str) -> Any:
    """``NAME(limits)`` of ``FILE.py`` for ``env``'s drive limits, checked to be an agent that reads no ground
    truth, named by its own ``name`` or ``NAME``."""
    path, name = split_argument(argument)
    factory = load_factory(argument)
    try:
        agent = factory(env.unwrapped.limits)
    except Exception as e:  # noqa: BLE001 - whatever the user's constructor raises
        raise ValueError(f"{name}(limits) of {path} raised {type(e).__name__}: {' '.join(str(e).split())}") from None
    if not (callable(getattr(agent, "reset", None)) and callable(getattr(agent, "act", None))):
        raise ValueError(f"{name}(limits) of {path} returned {type(agent).__name__!r}, which has no reset(observation, "
                         "info) and act(observation, info)")
    if getattr(agent, "oracle", False):
        raise ValueError(f"{name} of {path} says it is an oracle: an agent of your own never reads the ground truth")
    own_name = getattr(agent, "name", None)
    if isinstance(own_name, str) and any(c in own_name for c in TABLE_CELL_FORBIDDEN):
        raise ValueError(f"{name} of {path}: its name {own_name!r} must be one line without '|' (a column of "
                         "summary.md's tables)")
    try:
        agent.name = own_name if isinstance(own_name, str) and own_name.strip() else name
        agent.oracle = False
    except AttributeError:
        raise ValueError(f"{name} of {path}: its name and oracle attributes cannot be set") from None
    return agent
