"""What the validation-only selections (select_phase_rule.py, select_robust_model.py,
train_interrogator.py) share: one summary of an agent's relative CoF errors and macro-slips, and the
best-ranked row of every group of a parameter grid."""

from __future__ import annotations

import json
from typing import Any, Iterable, Mapping, Sequence

import numpy as np


def error_summary(errors: Iterable[float], macro_slips: Iterable[bool]) -> dict[str, Any]:
    """Median and 90th percentile of the relative errors (fractions), the number of macro-slips and of
    episodes."""
    e = np.asarray(list(errors), dtype=np.float64)
    if e.size == 0:
        raise ValueError("error_summary: no episodes")
    return {"median": float(np.median(e)), "p90": float(np.percentile(e, 90)),
            "macro_slips": int(sum(bool(s) for s in macro_slips)), "episodes": int(e.size)}


def best_per_group(ranked: Sequence[Mapping[str, Any]], groups: Iterable[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    """For every group (a partial parameter dict), the first row of ``ranked`` (best first) whose
    ``params`` contain it."""
    out = []
    for group in groups:
        match = next((r for r in ranked if all(r["params"].get(k) == v for k, v in group.items())), None)
        if match is None:
            raise ValueError(f"best_per_group: no row has the parameters {dict(group)}")
        out.append(match)
    return out


def group_line(group: Mapping[str, Any], row: Mapping[str, Any]) -> str:
    """``group: macro-slips / median / P90 with the rest of the row's parameters`` (one report line)."""
    rest = {k: v for k, v in row["params"].items() if k not in group}
    return (f"  {json.dumps(dict(group))}: {row['macro_slips']} / {row['median']:.1%} / {row['p90']:.1%} "
            f"with {json.dumps(rest)}")
