"""The tables of ``cof-gym evaluate``: the summary and its breakdown as Markdown, and the terminal's table."""

from __future__ import annotations

from typing import Any

import numpy as np

from cof_gym.commands.evaluate_stats import AGENT_GROUPINGS, METRICS, PAIRED_STATISTICS

# the statistics of the intervals the agents reported (evaluate_stats.interval_stats' keys) and their labels
INTERVAL_ROWS = (("coverage", "CoF in its reported interval [%]"),
                 ("lower_bound_coverage", "CoF above its reported lower bound [%]"))


def _fmt(value: float, kind: str) -> str:
    if not np.isfinite(value):
        return "-"
    if kind == "pct":
        return f"{100 * value:.1f}"
    if kind == "int":
        return f"{value:.0f}"
    return f"{value:.3g}"


def _ci_cell(stat: dict[str, Any], kind: str, between: str = " ") -> str:
    """A statistic ``{"value", "ci95"}`` as ``value [low, high]`` (``between``: what separates the two); ``value [-]``
    where it has no interval (``ci95`` None: one episode)."""
    if stat["ci95"] is None:
        return f"{_fmt(stat['value'], kind)}{between}[-]"
    return f"{_fmt(stat['value'], kind)}{between}[{_fmt(stat['ci95'][0], kind)}, {_fmt(stat['ci95'][1], kind)}]"


def _agent_label(summary: dict, a: str) -> str:
    return f"{a} (oracle)" if summary[a]["oracle"] else a


def markdown_table(summary: dict[str, dict[str, Any]]) -> str:
    agents = list(summary)
    lines = ["| metric [unit] (95 % CI) | " + " | ".join(_agent_label(summary, a) for a in agents) + " |",
             "|---" * (len(agents) + 1) + "|"]
    for key, label, _, _, kind in METRICS:
        lines.append(f"| {label} | " + " | ".join(_ci_cell(summary[a][key], kind) for a in agents) + " |")
    lines.append("| episodes [count] | " + " | ".join(str(summary[a]["episodes"]) for a in agents) + " |")
    return "\n".join(lines)


def ci_text(value: tuple[float, float | None, float | None] | list, digits: int = 1, signed: bool = True,
            between: str = " ") -> str:
    """A statistic and its CI, ``(value, low, high)``, as ``+v [+lo, +hi]`` (``signed``: with their signs, as a
    difference reads) with ``digits`` decimals, ``between`` the value and the bracket; ``+v [-]`` without a CI (None
    bounds: one episode)."""
    sign = "+" if signed else ""
    value, low, high = value
    if low is None or high is None:
        return f"{value:{sign}.{digits}f}{between}[-]"
    return f"{value:{sign}.{digits}f}{between}[{low:{sign}.{digits}f}, {high:{sign}.{digits}f}]"


def _paired_cells(entry: dict[str, Any], between: str = " ") -> list[str]:
    """An agent's paired statistics (``paired_summary``'s entry) as ``value [low, high]`` cells, then its macro-slips
    against the baseline's."""
    digits = {"return": 4, "lower_error": 0}
    cells = [ci_text(entry[key], digits.get(key, 1), key != "lower_error", between) for key, _ in PAIRED_STATISTICS]
    return cells + [f"{entry['macro_slips'][0]} -> {entry['macro_slips'][1]}"]


def paired_title(paired: dict[str, Any]) -> str:
    return (f"against {paired['baseline']}, paired over the same {paired['episodes']} episodes (95 % CIs from "
            f"{paired['resamples']} paired resamples)")


PAIRED_HEADERS = ("agent", *(label for _, label in PAIRED_STATISTICS), "macro-slips (baseline -> agent)")


def markdown_paired(paired: dict[str, Any]) -> str:
    """Every agent against the baseline (``paired_summary``), as a Markdown table under a line saying so."""
    lines = [f"Every agent {paired_title(paired)}:", "", "| " + " | ".join(PAIRED_HEADERS) + " |",
             "|---" * len(PAIRED_HEADERS) + "|"]
    lines += [f"| {agent} | " + " | ".join(_paired_cells(entry)) + " |" for agent, entry in paired["agents"].items()]
    return "\n".join(lines)


def markdown_intervals(summary: dict[str, dict[str, Any]]) -> str:
    """The intervals the agents reported around their estimates (``summary[agent]["interval"]``), "" where
    none did."""
    agents = [a for a in summary if "interval" in summary[a]]
    if not agents:
        return ""
    lines = ["| agent | scored episodes | CoF in its interval [%] (95 % CI) | CoF above its lower bound [%] (95 % CI) "
             "| median interval width (high / low) |", "|---|---|---|---|---|"]
    for a in agents:
        i = summary[a]["interval"]
        cells = [_ci_cell(i[k], "pct") if k in i else "-" for k, _ in INTERVAL_ROWS]
        lines.append(f"| {_agent_label(summary, a)} | {i['episodes']} | {' | '.join(cells)} | {i['median_width']:.2f} |")
    return "\n".join(lines)


def _shared_count(summary: dict[str, dict[str, Any]], group: str) -> int | None:
    """The episodes of ``group``, where every agent has that many in it (a scenario group: every agent plays
    the same scenarios); None where the group depends on what the agent did (the utilisation at commitment, how
    the episode ended)."""
    counts = {summary[a]["breakdown"].get(group, {}).get("episodes", 0) for a in summary}
    return counts.pop() if len(counts) == 1 else None


def _group_order(summary: dict[str, dict[str, Any]]) -> list[str]:
    """Every agent's breakdown groups in one order that keeps each agent's (the breakdown's) and each of
    :data:`AGENT_GROUPINGS`' (e.g. the utilisation bands from the lowest up), where some groups belong to some
    agents only; ties in order of first appearance."""
    before: dict[str, set[str]] = {}
    for a in summary:
        seen: set[str] = set()
        for g in summary[a]["breakdown"]:
            before.setdefault(g, set()).update(seen)
            seen.add(g)
    for grouping in AGENT_GROUPINGS:
        present = [g for g in grouping if g in before]
        for k, g in enumerate(present):
            before[g].update(present[:k])
    order: list[str] = []
    while len(order) < len(before):
        placed = set(order)
        remaining = [g for g in before if g not in placed]
        order.append(next((g for g in remaining if before[g] <= placed), remaining[0]))
    return order


def _breakdown_rows(summary: dict[str, dict[str, Any]], cell) -> list[tuple[str, int | None, list[str]]]:
    """``(group, shared count or None, a cell per agent)``: ``cell(stats)`` for an agent with episodes in the
    group, followed by its own count where the count is not shared; "-" for an agent with none."""
    rows = []
    for g in _group_order(summary):
        n = _shared_count(summary, g)
        cells = []
        for a in summary:
            s = summary[a]["breakdown"].get(g)
            cells.append("-" if s is None else cell(s) + ("" if n is not None else f" (n={s['episodes']})"))
        rows.append((g, n, cells))
    return rows


def markdown_breakdown(summary: dict[str, dict[str, Any]]) -> str:
    """Median relative error [%] / P90 [%] / macro-slips / mean peak torque [% of M_sat], per group."""
    agents = list(summary)
    lines = ["| group (episodes) | " + " | ".join(_agent_label(summary, a) for a in agents) + " |",
             "|---" * (len(agents) + 1) + "|"]
    for g, n, cells in _breakdown_rows(summary, lambda s: f"{_fmt(s['median_error'], 'pct')} % / "
                                                        f"{_fmt(s['p90_error'], 'pct')} % / {s['macro_slip_events']}"
                                                        f" / {_fmt(s['peak_torque_fraction'], 'pct')} %"):
        lines.append(f"| {g}{'' if n is None else f' ({n})'} | " + " | ".join(cells) + " |")
    return ("Cells: median rel. CoF error / P90 rel. CoF error / macro-slips [episodes] / mean peak torque "
            "[% of real M_sat]; (n=...): the agent's own episodes in a group that depends on what the agent did "
            "(the utilisation at commitment, how the episode ended), where the agents' counts differ.\n\n"
            + "\n".join(lines))


def _interval_rows(summary: dict[str, dict[str, Any]]) -> list[list[str]]:
    """The terminal rows of the intervals the agents reported (:data:`INTERVAL_ROWS`; "-" for an agent that
    reported none), none where no agent did."""
    if not any("interval" in summary[a] for a in summary):
        return []
    return [[label, *[_ci_cell(summary[a]["interval"][key], "pct", "\n") if key in summary[a].get("interval", {})
                      else "-" for a in summary]] for key, label in INTERVAL_ROWS]


def print_paired(paired: dict[str, Any], out=None) -> None:
    """The paired comparison (``paired_summary``) on ``out`` (a rich console; default: stdout)."""
    from cof_gym.commands import terminal

    rows = [[agent, *_paired_cells(entry, "\n")] for agent, entry in paired["agents"].items()]
    terminal.print_table(paired_title(paired), list(PAIRED_HEADERS), rows, out or terminal.console())


def print_table(summary: dict[str, dict[str, Any]], title: str, out=None) -> None:
    """The summary (value, CI below it) and the breakdown (median error per group) on ``out`` (a rich
    console; default: stdout at the terminal's width, or COLUMNS, or 100), splitting no word
    (:func:`cof_gym.commands.terminal.print_table`)."""
    from cof_gym.commands import terminal

    out = out or terminal.console()
    rows = [[label, *[_ci_cell(summary[a][key], kind, "\n") for a in summary]] for key, label, _, _, kind in METRICS]
    rows += _interval_rows(summary)
    rows.append(["episodes [count]", *[str(summary[a]["episodes"]) for a in summary]])
    labels = [_agent_label(summary, a).replace(" (oracle)", "\n(oracle)") for a in summary]
    terminal.print_table(title, ["metric [unit]\n(95 % CI)", *labels], rows, out)
    bd_rows = [[g if n is None else f"{g} [{n}]", *cells] for g, n, cells in
               _breakdown_rows(summary, lambda s: f"{_fmt(s['median_error'], 'pct')} [{s['macro_slip_events']}]")]
    terminal.print_table("median rel. CoF error [%] by group (macro-slips in brackets)",
                         ["group [episodes]", *summary], bd_rows, out)
