"""The statistics of ``cof-gym evaluate``: each metric per agent with a bootstrap 95 % CI (:data:`METRICS`),
and the breakdown by condition, CoF band, family, peak creepage, creepage-error band, utilisation and ending."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from cof_gym.commands.evaluate_episodes import ENDINGS, EpisodeRecord

N_BOOTSTRAP = 2000
BOOTSTRAP_BLOCK_VALUES = 1 << 22  # resampled values held at once by a bootstrap (32 MiB of floats)
COF_BANDS = (0.0, 0.1, 0.2, 0.3, 0.4, math.inf)  # CoF band edges of the breakdown
# |systematic creepage error| band edges (the sensors' (1 + e_R)/(1 + e_v) - 1; 0 in v1)
CREEPAGE_ERROR_BANDS = (0.0, 1e-9, 0.002, 0.005, 0.01, math.inf)
# the creepage of the true creep curve's peak: the lag reaches 90 deg there, and a curve that still rises slowly past
# its knee (a peak at several % creepage) reads a large lag well below its peak's adhesion
PEAK_CREEPAGE_BANDS = (0.0, 0.01, 0.02, 0.04, math.inf)
# "how early can you know": peak torque at the committed estimate, as a fraction of the true M_sat; closed on the
# right as the bands read (<= 80, 80-90, 90-95, > 95 %): a commitment at exactly 80 % is "<= 80"
UTILISATION_BANDS = (0.0, 0.8, 0.9, 0.95, math.inf)


def bootstrap_ci(values: np.ndarray, stat, rng: np.random.Generator,
                 n: int = N_BOOTSTRAP) -> tuple[float, float] | None:
    """Percentile bootstrap 95 % confidence interval of ``stat`` (a NumPy reduction taking ``axis``: each
    resample's statistic is a row's, computed as for the resample alone, in blocks of rows to bound memory); None
    for fewer than two values, which have no interval (one value resampled is itself: ``[v, v]`` would claim a
    certainty one episode does not give). ``rng`` is drawn from only where there is an interval."""
    if len(values) < 2:
        return None
    idx = rng.integers(0, len(values), size=(n, len(values)))
    block = max(1, BOOTSTRAP_BLOCK_VALUES // len(values))
    stats = np.concatenate([stat(values[idx[i:i + block]], axis=1) for i in range(0, n, block)])
    return float(np.percentile(stats, 2.5)), float(np.percentile(stats, 97.5))


def paired_differences(base_error: np.ndarray, other_error: np.ndarray, base_return: np.ndarray,
                       other_return: np.ndarray, seed: int = 0, tail_percent: float = 2.5,
                       resamples: int = N_BOOTSTRAP) -> dict[str, tuple[float, float | None, float | None]]:
    """(value, CI low, CI high) of an agent against a baseline over the same episodes (index by index), each
    resampled in pairs (``resamples`` draws of the episodes, seeded; the CI leaves ``tail_percent`` % of the draws out
    on each side): ``median`` and ``P90``, the difference other - base of the relative error's median and 90th
    percentile (percentage points); ``return``, of the mean episode return; ``lower_error``, the share of episodes in
    which the other's error is the lower, ties counted half (%): the probability of improvement (Agarwal et al.,
    "Deep reinforcement learning at the edge of the statistical precipice", NeurIPS 2021), 50 where neither is better.
    One episode has no interval: its CI bounds are None.
    """
    n = len(base_error)
    if not n or any(len(a) != n for a in (other_error, base_return, other_return)):
        raise ValueError(f"paired episodes must be as many for both and at least one, got {len(base_error)} and "
                         f"{len(other_error)}")
    if not all(np.isfinite(a).all() for a in (base_error, other_error, base_return, other_return)):
        raise ValueError("paired episodes need finite errors and returns (a NaN would count as the baseline's win)")
    draws = np.random.default_rng(seed).integers(0, n, size=(resamples, n)) if n > 1 else None

    def ci(boot_of) -> tuple[float | None, float | None]:
        """The percentile interval of ``boot_of(draws)`` (a statistic per draw); (None, None) for one episode."""
        if draws is None:
            return None, None
        boot = boot_of(draws)
        return float(np.percentile(boot, tail_percent)), float(np.percentile(boot, 100.0 - tail_percent))

    result = {}
    for name, stat in (("median", lambda e: np.median(e, axis=-1)), ("P90", lambda e: np.percentile(e, 90, axis=-1))):
        point = 100.0 * float(stat(other_error) - stat(base_error))
        result[name] = (point, *ci(lambda d, stat=stat: 100.0 * (stat(other_error[d]) - stat(base_error[d]))))
    result["return"] = (float(other_return.mean() - base_return.mean()),
                        *ci(lambda d: other_return[d].mean(axis=1) - base_return[d].mean(axis=1)))
    better = 100.0 * ((other_error < base_error) + 0.5 * (other_error == base_error))
    result["lower_error"] = (float(better.mean()), *ci(lambda d: better[d].mean(axis=1)))
    return result


def _p90(v: np.ndarray, axis: int | None = None):
    """The 90th percentile (per row along ``axis``)."""
    return np.percentile(v, 90, axis=axis) if axis is not None else float(np.percentile(v, 90))


METRICS = (
    # (key, label with unit, column, statistic, format of the value)
    ("median_error", "median rel. CoF error [%]", "relative_error", np.median, "pct"),
    ("p90_error", "P90 rel. CoF error [%]", "relative_error", _p90, "pct"),
    ("macro_slip_events", "macro-slips [episodes]", "macro_slip", np.sum, "int"),
    ("slip_energy_j", "slip energy past peak [J]", "slip_energy_j", np.mean, "g3"),
    ("wd_rms_m_s2", "Wd comfort [m/s^2]", "wd_rms_m_s2", np.mean, "g3"),
    ("measurement_time_s", "measurement time [s]", "measurement_time_s", np.mean, "g3"),
    ("peak_torque_fraction", "peak torque [% of real M_sat]", "peak_torque_fraction", np.mean, "pct"),
    # last, so that adding them left every bootstrap CI above as it was (one generator per agent, drawn in this order)
    ("median_error_slip_failed", "median rel. CoF error, macro-slip = 100 % [%]", "error_slip_failed", np.median, "pct"),
    ("p90_error_slip_failed", "P90 rel. CoF error, macro-slip = 100 % [%]", "error_slip_failed", _p90, "pct"),
)


def _band(value: float, edges: tuple[float, ...], label, right_closed: bool = False) -> str:
    """The label of the band of ``edges`` that holds ``value``: [lo, hi) (``right_closed``: (lo, hi], the first band
    [edges[0], hi]); a NaN or a value below the first edge is a ``ValueError``, never the top band."""
    if math.isnan(value) or value < edges[0]:
        raise ValueError(f"{value!r} lies in no band of {edges}")
    for lo, hi in zip(edges[:-1], edges[1:]):
        if (lo < value <= hi or value == lo == edges[0]) if right_closed else (lo <= value < hi):
            return label(lo, hi)
    return label(edges[-2], edges[-1])


def cof_band(cof: float) -> str:
    return _band(cof, COF_BANDS, lambda lo, hi: f"CoF {lo:.2f}+" if math.isinf(hi) else f"CoF {lo:.2f}-{hi:.2f}")


def creepage_error_band(offset: float) -> str:
    """The band of |systematic creepage error| (0: none, as in v1)."""
    return _band(abs(offset), CREEPAGE_ERROR_BANDS,
                 lambda lo, hi: "creepage error 0" if hi <= 1e-9 else
                 f"|creepage error| {100 * lo:.1f}+ %" if math.isinf(hi) else
                 f"|creepage error| {100 * lo:.1f}-{100 * hi:.1f} %")


def peak_creepage_band(creepage: float) -> str:
    """The band of the true creep curve's peak creepage (where its adhesion is the CoF)."""
    return _band(creepage, PEAK_CREEPAGE_BANDS,
                 lambda lo, hi: f"peak creepage {100 * lo:.0f}+ %" if math.isinf(hi) else
                 f"peak creepage < {100 * hi:.0f} %" if lo == 0 else f"peak creepage {100 * lo:.0f}-{100 * hi:.0f} %")


def _utilisation_label(lo: float, hi: float) -> str:
    return (f"committed at > {100 * lo:.0f} % M_sat" if math.isinf(hi) else
            f"committed at <= {100 * hi:.0f} % M_sat" if lo == 0 else f"committed at {100 * lo:.0f}-{100 * hi:.0f} % M_sat")


def utilisation_band(fraction: float) -> str:
    """The band of the peak torque (fraction of the true saturation torque) at the committed estimate."""
    return _band(fraction, UTILISATION_BANDS, _utilisation_label, right_closed=True)


def ending_group(ended: str) -> str:
    """The breakdown's group of an episode that ended as ``ended`` (one of ``ENDINGS``)."""
    return f"ended: {ended}"


UTILISATION_GROUPS = tuple(_utilisation_label(lo, hi) for lo, hi in zip(UTILISATION_BANDS[:-1], UTILISATION_BANDS[1:]))
ENDING_GROUPS = tuple(ending_group(e) for e in ENDINGS)
# the groupings whose groups depend on what an agent did, each as its groups in order: two agents may share none
# of a grouping's groups, so the tables take their order from here, not from the agents' breakdowns
AGENT_GROUPINGS = (UTILISATION_GROUPS, ENDING_GROUPS)


# the breakdown's groupings, in table order: (name, group of a record, the record's order within it)
GROUPINGS = (
    ("condition", lambda r: r.condition, lambda r: r.condition),
    ("CoF band", lambda r: cof_band(r.cof), lambda r: r.cof),
    ("creep-law family", lambda r: f"law {r.creep_family}", lambda r: r.creep_family),
    ("peak-creepage band", lambda r: peak_creepage_band(r.peak_creepage), lambda r: r.peak_creepage),
    ("creepage-error band", lambda r: creepage_error_band(r.creepage_offset), lambda r: abs(r.creepage_offset)),
    ("utilisation at commitment", lambda r: utilisation_band(r.peak_torque_fraction),
     lambda r: r.peak_torque_fraction),
    ("how the episode ended", lambda r: ending_group(r.ended), lambda r: ENDINGS.index(r.ended)),
    ("the suite's episode note", lambda r: f"note {r.note}" if r.note else "no note", lambda r: r.note),
    # what the agent's own readings said lay outside its sensors (sensor_notes): shown where some agent noted any
    ("the agent's sensor notes", lambda r: f"sensor notes: {r.sensor_notes}" if r.sensor_notes else "no sensor note",
     lambda r: r.sensor_notes),
)


def _group_stats(rows: list[EpisodeRecord]) -> dict[str, Any]:
    err = np.array([r.relative_error for r in rows])
    return {"episodes": len(rows), "median_error": float(np.median(err)), "p90_error": _p90(err),
            "macro_slip_events": int(sum(r.macro_slip for r in rows)),
            "peak_torque_fraction": float(np.mean([r.peak_torque_fraction for r in rows]))}


def breakdown(records: list[EpisodeRecord]) -> dict[str, dict[str, dict[str, Any]]]:
    """Per agent: statistics by each of :data:`GROUPINGS` (groups ordered within a grouping; a grouping
    other than condition and CoF band with a single group, e.g. one creep-law family, is left out)."""
    out: dict[str, dict[str, dict[str, Any]]] = {}
    keys = []
    for k, (_, key, order) in enumerate(GROUPINGS):
        first = {}
        for r in sorted(records, key=order):
            first.setdefault(key(r), len(first))
        if len(first) > 1 or k < 2:  # condition and CoF band always; the rest where they vary
            keys.append((key, list(first)))
    for agent in dict.fromkeys(r.agent for r in records):
        rows = [r for r in records if r.agent == agent]
        groups: dict[str, dict[str, Any]] = {}
        for key, values in keys:
            for v in values:
                sel = [r for r in rows if key(r) == v]
                if sel:
                    groups[v] = _group_stats(sel)
        out[agent] = groups
    return out


def summarize(records: list[EpisodeRecord], seed: int) -> dict[str, dict[str, Any]]:
    out: dict[str, dict[str, Any]] = {}
    groups = breakdown(records)
    for agent in dict.fromkeys(r.agent for r in records):
        rows = [r for r in records if r.agent == agent]
        rng = np.random.default_rng(seed)
        entry: dict[str, Any] = {"episodes": len(rows), "oracle": rows[0].oracle}
        for key, _, column, stat, _ in METRICS:
            values = np.array([getattr(r, column) for r in rows], dtype=float)
            if not np.isfinite(values).all():  # a NaN would make every statistic of the column NaN, silently
                bad = int(np.flatnonzero(~np.isfinite(values))[0])
                raise ValueError(f"{agent}: episode {rows[bad].episode} has {column} {float(values[bad])}; every "
                                 "statistic needs a finite value")
            ci = bootstrap_ci(values, stat, rng)
            entry[key] = {"value": float(stat(values)), "ci95": None if ci is None else list(ci)}
        interval = interval_stats(rows, rng)  # after METRICS: their CIs are drawn first, as before
        if interval is not None:
            entry["interval"] = interval
        entry["breakdown"] = groups[agent]
        out[agent] = entry
    return out


PAIRED_STATISTICS = (  # paired_differences' keys: (key, label with unit), in the tables' order
    ("median", "median error, agent - baseline [points]"), ("P90", "P90 error, agent - baseline [points]"),
    ("return", "mean return, agent - baseline"), ("lower_error", "agent's error the lower [% of episodes, ties half]"))


def paired_summary(records: list[EpisodeRecord], baseline: str, seed: int) -> dict[str, Any]:
    """Every other agent against ``baseline`` over the same episodes (:func:`paired_differences`, seeded with
    ``seed``): per agent each statistic as ``[value, CI low, CI high]`` and both agents' macro-slips."""
    by_agent: dict[str, list[EpisodeRecord]] = {}
    for r in sorted(records, key=lambda r: r.episode):
        by_agent.setdefault(r.agent, []).append(r)
    if baseline not in by_agent:
        raise ValueError(f"no agent {baseline!r} played here; agents: {list(by_agent)}")
    column = lambda rows, name: np.array([getattr(r, name) for r in rows], dtype=float)  # noqa: E731
    base = by_agent[baseline]
    out: dict[str, Any] = {"baseline": baseline, "episodes": len(base), "resamples": N_BOOTSTRAP, "agents": {}}
    for agent, rows in by_agent.items():
        if agent == baseline:
            continue
        d = paired_differences(column(base, "relative_error"), column(rows, "relative_error"),
                               column(base, "episode_return"), column(rows, "episode_return"), seed=seed)
        out["agents"][agent] = {**{key: list(d[key]) for key, _ in PAIRED_STATISTICS},
                                "macro_slips": [int(sum(r.macro_slip for r in base)),
                                                int(sum(r.macro_slip for r in rows))]}
    return out


def interval_stats(rows: list[EpisodeRecord], rng: np.random.Generator) -> dict[str, Any] | None:
    """How often the CoF lay in the interval the agent reported and above its lower bound, with bootstrap 95 %
    CIs, over the scored episodes with an interval, and the interval's median width (high over low); None where
    the agent reported none. An agent that reports no lower bound has no ``lower_bound_coverage``."""
    rows = [r for r in rows if r.in_interval is not None]
    if not rows:
        return None
    out: dict[str, Any] = {"episodes": len(rows)}
    for key, values in (("coverage", [r.in_interval for r in rows]),
                        ("lower_bound_coverage", [r.above_lower_bound for r in rows])):
        if None in values:  # a coverage of some episodes only would be no coverage of the agent's
            continue
        values = np.array(values, dtype=float)
        ci = bootstrap_ci(values, np.mean, rng)
        out[key] = {"value": float(np.mean(values)), "ci95": None if ci is None else list(ci)}
    out["median_width"] = float(np.median([r.interval_high / r.interval_low for r in rows]))
    return out
