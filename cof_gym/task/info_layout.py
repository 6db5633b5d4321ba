"""The layouts of ``info`` (the task's ``info_layout`` argument).

``"nested"`` (default): the info as documented in the env's docstring: ``info["cost"]``,
``info["measurement"]`` and ``info["ground_truth"]`` are dicts, the condition, load case and creep
family are strings, ``info["ground_truth"]["creep_law"]`` is the creep law's spec (``{family:
{parameter: value}}``, or in v1 the condition's preset name).

``"flat"``: one level of keys, every value a number (``bool``, ``int`` or ``float``), for clients
that turn each info key into an array or tensor (torchrl's ``GymWrapper`` over a Gymnasium vector env,
tianshou's buffers):

- a nested key becomes its path joined by :data:`FLAT_SEPARATOR`: ``info["measurement"]["phase_lag_deg"]``
  is ``info["measurement/phase_lag_deg"]``, ``info["cost"]["slip"]`` is ``info["cost/slip"]``;
- a string becomes its index in :data:`FLAT_CODES` (``info["ground_truth/condition"] == 2`` is
  ``"low_adhesion"``; :func:`decode_flat` gives the name back);
- ``ground_truth/creep_law`` is left out: its family is ``ground_truth/creep_family``, and its parameters'
  names and number depend on the family (a table shape has lists), so no fixed set of keys holds them;
- the key set is the same in every episode; keys that do not exist yet stay absent as in the nested
  layout (``log_error`` and ``relative_error`` until the estimate is scored, the reward terms in a
  reset's info).

The flat info is computed from the nested one (:func:`flatten_info`), so both carry the same numbers.
"""

from __future__ import annotations

import numbers
from types import MappingProxyType
from typing import Any, Mapping

from cof_gym.physics.creep_laws import FAMILIES
from cof_gym.physics.track import TRACK_CLASSES
from cof_gym.physics.vehicle import LOAD_CASES
from cof_gym.task.scenarios import COF_BY_CONDITION

INFO_LAYOUTS = ("nested", "flat")
FLAT_SEPARATOR = "/"
FLAT_CODES: Mapping[str, tuple[str, ...]] = MappingProxyType({
    "ground_truth/condition": tuple(COF_BY_CONDITION),
    "ground_truth/load_case": tuple(LOAD_CASES),
    "ground_truth/creep_family": tuple(FAMILIES),
    "ground_truth/track_irregularity": TRACK_CLASSES,
})
"""The flat layout's code of each string field: its value is the name's index in the tuple."""
FLAT_DROPPED = ("ground_truth/creep_law",)
"""Nested keys the flat layout leaves out (see the module docstring)."""


def flatten_info(info: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """The flat layout of a nested ``info`` (see the module docstring)."""
    out: dict[str, Any] = {}
    for key, value in info.items():
        path = f"{prefix}{key}"
        if path in FLAT_DROPPED:
            continue
        if isinstance(value, Mapping):
            out.update(flatten_info(value, path + FLAT_SEPARATOR))
        elif isinstance(value, str):
            if path not in FLAT_CODES:
                raise TypeError(f"info[{path!r}] is a string with no code in FLAT_CODES: {value!r}")
            out[path] = FLAT_CODES[path].index(value)
        elif isinstance(value, numbers.Number):
            out[path] = value
        else:
            raise TypeError(f"info[{path!r}] is not a number: {value!r}")
    return out


def decode_flat(key: str, value: int) -> str:
    """The name a flat-layout code stands for (``decode_flat("ground_truth/condition", 2)``)."""
    return FLAT_CODES[key][int(value)]
