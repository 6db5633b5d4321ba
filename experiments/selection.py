"""What the validation-only selections (select_phase_rule.py, select_robust_model.py,
train_interrogator.py) share: one summary of an agent's relative CoF errors and macro-slips, and the
best-ranked row of every group of a parameter grid."""

from __future__ import annotations

import json
from typing import Any, Iterable, Mapping, Sequence

import numpy as np


# issue 16's absolute targets for the learned agent, one place for every script that reads them (readme_results.py's
# targets table, frontier.py's target rows): the median and the P90 relative CoF error (%) at most these, and at most
# this many macro-slips per 100 episodes
TARGET_MEDIAN_PCT, TARGET_P90_PCT, TARGET_SLIPS_PER_100 = 3.0, 8.0, 1.0


def target_rows(median_pct: float, p90_pct: float, slips: int, episodes: int,
                others: Sequence[tuple[float, float, int]] = ()) -> list[bool]:
    """Issue 16's target rows for one suite (or grid) that a learned agent's median and P90 error (%), macro-slips
    and episodes meet: the three absolute targets and, with ``others`` (each other agent's median %, P90 % and
    macro-slips on the same episodes), a median and a P90 below every one of theirs and no more macro-slips than the
    fewest of theirs."""
    rows = [median_pct <= TARGET_MEDIAN_PCT, p90_pct <= TARGET_P90_PCT, slips <= episodes * TARGET_SLIPS_PER_100 / 100.0]
    if others:
        rows += [all(median_pct < o[0] for o in others), all(p90_pct < o[1] for o in others),
                 slips <= min(o[2] for o in others)]
    return rows


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
