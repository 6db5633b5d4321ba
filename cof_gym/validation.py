"""Strict argument checks shared by every layer (the lowest: it imports nothing of cof_gym), from the physics'
creep laws to the agents' parameters: a wrong type or range raises a
``ValueError`` naming the field, the type or range allowed and the value given. Booleans are never
numbers here, strings are never booleans, and nothing non-finite passes."""

from __future__ import annotations

import math
import numbers
from typing import Any, Iterable

import numpy as np

# characters a label must not hold that becomes a cell of a markdown table (an agent's name, a suite's episode note)
TABLE_CELL_FORBIDDEN = ("|", "\n", "\r")


def check_bool(name: str, value: Any) -> bool:
    """A real boolean (``True``/``False`` or a numpy bool), nothing else; returned as a Python ``bool``."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise ValueError(f"{name} must be a bool (True or False), got {value!r} ({type(value).__name__})")


def check_number(name: str, value: Any, low: float, high: float, *, low_open: bool = False,
                 unit: str = "", high_open: bool = False) -> float:
    """A finite real number (not a bool, not a string) in [low, high] (``low_open`` / ``high_open``: without that
    end; an infinite end: no bound there), returned as a Python ``float`` (``float(value)``: a Python float is
    returned unchanged, a numpy scalar as the float it holds)."""
    allowed = _interval(low, high, low_open, high_open)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a number{allowed}{unit}, "
                         f"got {value!r} ({type(value).__name__})")
    try:
        v = float(value)
    except OverflowError:  # an int too large for a float: out of range, on its side
        v = math.inf if value > 0 else -math.inf
    if not math.isfinite(v) or v < low or v > high or (low_open and v == low) or (high_open and v == high):
        raise ValueError(f"{name} must be a finite number{allowed}{unit}, got {value!r}")
    return v


def check_range(name: str, value: Any, low: float, high: float) -> tuple[float, float]:
    """A (min, max) pair of numbers within [low, high] with min <= max."""
    if not (isinstance(value, (tuple, list)) and len(value) == 2):
        raise ValueError(f"{name} must be a (min, max) pair within [{low:g}, {high:g}], got {value!r}")
    lo = check_number(f"{name}[0]", value[0], low, high)
    hi = check_number(f"{name}[1]", value[1], low, high)
    if lo > hi:
        raise ValueError(f"{name} must satisfy min <= max, got {value!r}")
    return lo, hi


def is_number(value: Any) -> bool:
    """A finite real number (a numpy one too), never a bool."""
    return (isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
            and math.isfinite(float(value)))


def is_int(value: Any) -> bool:
    """An integer (a numpy integer too), never a bool (Python's or numpy's) nor a float."""
    return isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))


def check_int(name: str, value: Any, low: int, high: int | None = None) -> int:
    """An integer (:func:`is_int`) in [low, high] (``high`` None: no upper bound), returned as a Python ``int``;
    ``ValueError`` naming ``name`` and the range otherwise."""
    if not is_int(value) or int(value) < low or (high is not None and int(value) > high):
        bound = f">= {low}" if high is None else f"in [{low}, {high}]"
        raise ValueError(f"{name} must be an integer {bound}, got {value!r} ({type(value).__name__})")
    return int(value)


def check_choice(name: str, value: Any, allowed: Iterable[str]) -> str:
    allowed = tuple(allowed)
    if not isinstance(value, str) or value not in allowed:
        raise ValueError(f"{name} must be one of {list(allowed)}, got {value!r}")
    return value


def brief(value: Any, limit: int = 160) -> str:
    """``repr(value)`` cut to ``limit`` characters (with "..." and the full length where cut): a bad input named in an
    error message without a table of hundreds of points in it."""
    text = repr(value)
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


def first_not_rising(values: Any) -> int | None:
    """The first index ``i`` with ``values[i + 1] <= values[i]`` (None where every value rises strictly)."""
    return next((i for i, (a, b) in enumerate(zip(values, values[1:])) if b <= a), None)


def _interval(low: float, high: float, low_open: bool, high_open: bool = False) -> str:
    """The allowed range as the messages write it, with its leading space: `` in [low, high]`` (a bracket per
    end), `` > low`` / `` >= low`` where ``high`` is infinite, `` < high`` / `` <= high`` where ``low`` is, and
    nothing where both are (any finite number)."""
    if math.isinf(low) and math.isinf(high):
        return ""
    if math.isinf(high):
        return f" {'>' if low_open else '>='} {low:g}"
    if math.isinf(low):
        return f" {'<' if high_open else '<='} {high:g}"
    return f" in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
