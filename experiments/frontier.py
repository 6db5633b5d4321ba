"""Runaways against accuracy and return, one point per played candidate: where the rules' candidates lie.

    python experiments/frontier.py out/records_shipped_validation_session48.json out/records_rule*_validation.json \
        --shipped out/records_shipped_validation_session48.json --out out/frontier_validation.md \
        --figure docs/interrogator_frontier_validation.png

Each file holds ``crest_tradeoff.py --records`` plays on the same grids (one per setting: e.g. every candidate a rule
of docs/interrogator.md played on the validation grids at the draws); each setting is a point, named by its file
(less ``records_``) and, where the file holds several, its place among them. Files joined by ``+`` are one point per
setting over all their episodes (``A_validation.json+A_noise_level.json``: a candidate at the draws and with the
noise tripled together; their ``--grid`` grids pooled). Per point: its runaways (macro-slips) over every
grid, the median and P90 relative error on the ``--grid`` (default ``family``: the Polach, SHE and table families,
the default suite's kind) and over every grid, and the mean episode return (the task's own weighing of error, slip,
comfort and time, a runaway costing 10). A candidate is on the frontier where no other point has as few runaways and
as low a ``--grid`` P90, one of them lower. The table lists the files by their runaways; the figure (``--figure``)
plots the ``--grid`` P90 and the mean return against the runaways, the frontier joined and ``--shipped``'s point
marked. With ``--references`` (plays of the hand-built agents, ``experiments/scripted_plays.py``) those are shown
beside them, each with the number of candidates that beat it on both axes, and each candidate's count of issue 16's
target rows met over every grid of every play (the absolute ones, and with ``--references`` a median and a P90 below
every reference's and no more runaways than the fewest of theirs: ``selection.target_rows``, as the README's targets
table reads them). With ``--rows`` (and ``--references`` and ``--shipped``) a second table lists every target row
of every grid and play that some candidate meets and the shipped agent does not, or the reverse, with each one's
value there. With ``--endings`` the table also counts each play's climbs that ended at the horizon and its runaways in
the slow probe (the records' ``ended``). Nothing is chosen here: the plays were judged by their rules; this shows where
they lie together.
"""

from __future__ import annotations

import itertools
import math
import os
import sys
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from cof_gym.commands.args import Parser

sys.path.insert(0, str(Path(__file__).resolve().parent))
from paired_comparison import print_table, read_records  # noqa: E402
from script_checks import check_out_file  # noqa: E402
from selection import TARGET_MEDIAN_PCT, TARGET_P90_PCT, TARGET_SLIPS_PER_100, error_summary, target_rows  # noqa: E402

Cell = tuple[float, float, int, int]  # one grid of one play: median and P90 error (%), runaways, episodes
# selection.target_rows' rows, in its order: the three absolute targets, then the three against the hand-built agents
TARGET_ROWS = (f"median <= {TARGET_MEDIAN_PCT:g} %", f"P90 <= {TARGET_P90_PCT:g} %",
               f"<= {TARGET_SLIPS_PER_100:g} runaway per 100", "median below every hand-built agent's",
               "P90 below every hand-built agent's", "no more runaways than the fewest hand-built agent's")


@dataclass(frozen=True)
class Point:
    """One play's totals (errors relative, as fractions; an unscored episode's error is 1)."""

    label: str
    setting: str
    episodes: int
    runaways: int
    grid_median: float
    grid_p90: float
    median: float
    p90: float
    mean_return: float
    cells: dict[tuple[int, str], Cell] = field(default_factory=dict, compare=False)  # by (play, grid)
    endings: Counter = field(default_factory=Counter, compare=False)  # how its episodes ended (records' "ended")


def label_of(path: Path) -> str:
    """A play's name from its file: the stem less ``records_``."""
    return path.stem.removeprefix("records_")


def cells_of(plays: list[list[dict]]) -> dict[tuple[int, str], Cell]:
    """Each grid's median and P90 error (%), runaways and episodes in each play (``plays``: one setting's records,
    one list per play)."""
    cells = {}
    for k, records in enumerate(plays):
        for grid in dict.fromkeys(r["grid"] for r in records):
            s = summary([r for r in records if r["grid"] == grid])
            cells[(k, grid)] = (100 * s["median"], 100 * s["p90"], s["macro_slips"], s["episodes"])
    return cells


def summary(records: list[dict]) -> dict:
    """``selection.error_summary`` of ``records`` (their median and P90 error, runaways and episodes)."""
    return error_summary([r["error"] for r in records], [r["macro_slip"] for r in records])


def targets_met(point: Point, references: list[Point]) -> tuple[int, int]:
    """(met, rows) of issue 16's target rows (``selection.target_rows``) over ``point``'s grids in each play, the
    relative ones against the ``references`` on the same grid of the same play."""
    rows = [ok for key, (median, p90, slips, episodes) in point.cells.items()
            for ok in target_rows(median, p90, slips, episodes, [r.cells[key][:3] for r in references if key in r.cells])]
    return sum(rows), len(rows)


def point(label: str, setting: str, records: list[dict], grid: str, plays: list[list[dict]] | None = None) -> Point:
    """The totals of one setting's ``records`` (ValueError where it has no episode on ``grid``); ``plays``: the same
    records one list per play, for the per-grid cells (default: one play)."""
    on_grid = [r for r in records if r["grid"] == grid]
    if not on_grid:
        raise ValueError(f"has no episode on the grid {grid!r} (grids: {', '.join(sorted({r['grid'] for r in records}))})")
    grid_all, every = summary(on_grid), summary(records)
    return Point(label, setting, every["episodes"], every["macro_slips"], grid_all["median"], grid_all["p90"],
                 every["median"], every["p90"], float(np.mean([r["episode_return"] for r in records])),
                 cells_of(plays or [records]), Counter(r.get("ended", "") for r in records))


def beaten_by(point: Point, candidates: list[Point]) -> int:
    """How many ``candidates`` have at most ``point``'s runaways and at most its ``--grid`` P90, one of the two
    strictly lower (0: ``point`` is on the candidates' frontier, or beyond it)."""
    return sum(q.runaways <= point.runaways and q.grid_p90 <= point.grid_p90
               and (q.runaways < point.runaways or q.grid_p90 < point.grid_p90) for q in candidates)


def on_frontier(points: list[Point]) -> list[bool]:
    """Whether each point is on the frontier: no other point has at most its runaways and at most its ``--grid``
    P90, one of the two strictly lower."""
    return [beaten_by(p, points) == 0 for p in points]


ENDING_COLUMNS = {"ended at the horizon": "horizon", "runaways in the slow probe": "macro-slip, slow probe"}


def table(points: list[Point], grid: str, shipped: str | None, references: list[Point] = (),
          endings: bool = False) -> str:
    """The markdown table, by runaways (then the ``grid`` P90): every candidate and every reference (a hand-built
    agent), each with the number of candidates that beat it on both axes (a candidate beaten by none is on the
    frontier); with ``endings`` also how many of its episodes ended at the horizon and ran away in the slow probe
    (the records' ``ended``: :data:`ENDING_COLUMNS`)."""
    extra = "".join(f" {name} |" for name in ENDING_COLUMNS) if endings else ""
    lines = [f"| play | runaways (climbs) | {grid}: median / P90 | all: median / P90 | mean return |{extra} beaten by "
             "(candidates) | issue 16's target rows met | setting |", "|---" * (8 + (2 if endings else 0)) + "|"]
    rows = [(p, False) for p in points] + [(p, True) for p in references]
    for p, reference in sorted(rows, key=lambda row: (row[0].runaways, row[0].grid_p90)):
        name = (f"**{p.label}** (shipped)" if p.label == shipped else f"{p.label} (hand-built)" if reference
                else p.label)
        beaten = beaten_by(p, points)
        met = "-" if reference else "{} of {}".format(*targets_met(p, list(references)))
        counts = "".join(f" {p.endings[ended]} |" for ended in ENDING_COLUMNS.values()) if endings else ""
        lines.append(f"| {name} | {p.runaways} ({p.episodes}) | {100 * p.grid_median:.1f} % / {100 * p.grid_p90:.1f} % | "
                     f"{100 * p.median:.1f} % / {100 * p.p90:.1f} % | {p.mean_return:.4f} |{counts} "
                     f"{beaten if beaten or reference else '0: on the frontier'} | {met} | {p.setting} |")
    return "\n".join(lines) + "\n"


def play_names(labels: list[str]) -> list[str]:
    """The plays' names: their files' labels less the part up to the last ``_`` all of them share (the agent's
    name: ``shipped_confirmation34``, ``shipped_torque_confirmation15`` -> ``confirmation34``,
    ``torque_confirmation15``); the labels themselves where that would leave one empty."""
    shared = os.path.commonprefix(labels)
    cut = shared.rfind("_") + 1 if len(labels) > 1 else 0
    return labels if any(len(label) <= cut for label in labels) else [label[cut:] for label in labels]


def _row_value(cell: Cell, row: int) -> str:
    """A cell's value that target row ``row`` reads: its median or P90 (%), or its runaways of its episodes."""
    median, p90, slips, episodes = cell
    return (f"{median:.1f} %", f"{p90:.1f} %", f"{slips} of {episodes}")[row % 3]


def _reference_value(cells: list[Cell], row: int) -> str:
    """What a target row compares with: the target itself, or the best hand-built agent's value on that grid."""
    if row < 3:
        return TARGET_ROWS[row].split(" ", 1)[1] if row < 2 else f"{TARGET_SLIPS_PER_100:g} per 100"
    best = min(c[row % 3] for c in cells)
    return f"{best:.1f} %" if row % 3 < 2 else f"{best}"


def differing_rows(points: list[Point], shipped: str, references: list[Point], plays: list[str]) -> str:
    """The markdown table of every target row (grid of a play, ``plays`` naming the plays) that some candidate of
    ``points`` meets and the ``shipped`` one does not, or the reverse: each one's value, "(met)" where it meets it."""
    ship = next(p for p in points if p.label == shipped)
    order = [ship, *(p for p in points if p.label != shipped)]
    lines = ["| play | grid | target row | against | " + " | ".join(p.label for p in order) + " |",
             "|---" * (4 + len(order)) + "|"]
    for key in ship.cells:
        cells = [r.cells[key] for r in references if key in r.cells]
        met = {p.label: target_rows(*p.cells[key], [c[:3] for c in cells]) for p in order}
        for row, name in enumerate(TARGET_ROWS[:len(met[shipped])]):  # absolute rows only where no reference played
            if len({met[p.label][row] for p in order}) > 1:
                values = [_row_value(p.cells[key], row) + (" (met)" if met[p.label][row] else "") for p in order]
                lines.append(f"| {plays[key[0]]} | {key[1]} | {name} | {_reference_value(cells, row)} | "
                             + " | ".join(values) + " |")
    if len(lines) == 2:
        lines.append("| - | - | no row parts them | - |" + " - |" * len(order))
    return "\n".join(lines) + "\n"


REFERENCE_MARKERS = "^vsDPXo<>ph"  # one marker per reference (cycling only past eleven)
LEGEND_COLUMNS = 5


def figure(points: list[Point], grid: str, shipped: str | None, path: Path,
           references: list[Point] = ()) -> list[str]:
    """The ``grid`` P90 and the mean return against the runaways (a log axis where references run away far more
    often), the frontier joined, ``shipped`` marked, each reference a green marker of its own (named by its setting
    in the legend, below both panels); returns the legend's labels."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    front = sorted((p for p, f in zip(points, on_frontier(points)) if f), key=lambda p: p.runaways)
    everything = [*points, *references]
    wide = max(p.runaways for p in everything) > 4 * max(max(p.runaways for p in points), 1)
    candidates = [p for p in points if p.label != shipped]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, value, name in ((axes[0], lambda p: 100 * p.grid_p90, f"{grid} P90 rel. CoF error [%]"),
                            (axes[1], lambda p: p.mean_return, "mean episode return")):
        if candidates:
            ax.scatter([p.runaways for p in candidates], [value(p) for p in candidates], s=18, color="tab:blue",
                       label="candidate")
        if len(front) > 1 and ax is axes[0]:
            ax.plot([p.runaways for p in front], [value(p) for p in front], color="tab:gray", lw=1, label="frontier")
        for p in points:
            if p.label == shipped:
                ax.scatter([p.runaways], [value(p)], s=120, marker="*", color="tab:red", label="shipped", zorder=3)
        for p, marker in zip(references, itertools.cycle(REFERENCE_MARKERS)):
            ax.scatter([p.runaways], [value(p)], s=40, marker=marker, color="tab:green", label=p.setting, zorder=3)
        if wide:
            ax.set_xscale("log")
        ax.set_xlabel(f"runaways (of {points[0].episodes} climbs{', log scale' if wide else ''})")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    rows = math.ceil(len(labels) / LEGEND_COLUMNS)  # the legend below both panels, clear of every point
    fig.legend(handles, labels, loc="lower center", ncol=LEGEND_COLUMNS, fontsize=8, frameon=False)
    fig.suptitle("Runaways against accuracy and against the task's return", fontsize=10)
    fig.tight_layout(rect=(0.0, 0.05 * rows + 0.02, 1.0, 1.0))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return labels


def read_group(group: str, grid: str) -> list[Point]:
    """The points of one positional argument: a records file, or several joined by ``+`` (plays of the same
    candidates on other grids, e.g. the noise tripled), whose k-th settings together make its k-th point; named by
    the first file (OSError, ValueError or KeyError for a file it cannot read)."""
    if not all(group.split("+")):
        raise ValueError("an empty file name (files are joined by a single +, none before the first or after the last)")
    paths = [Path(p) for p in group.split("+")]
    plays = []
    for path in paths:
        records = read_records(path, set())
        settings = list(dict.fromkeys(r["setting"] for r in records))
        plays.append([[r for r in records if r["setting"] == s] for s in settings])
    if len({len(play) for play in plays}) != 1:
        raise ValueError("its files hold different numbers of settings; the k-th of each make one point")
    label = label_of(paths[0])
    return [point(label if len(plays[0]) == 1 else f"{label} [{k + 1}]", plays[0][k][0]["setting"],
                  [r for play in plays for r in play[k]], grid, [play[k] for play in plays])
            for k in range(len(plays[0]))]


def read_groups(parser: Parser, option: str, groups: list[str], grid: str) -> list[Point]:
    """The points of every group of ``option`` (:func:`read_group`); a file it cannot read is a usage error."""
    points = []
    for group in groups:
        try:
            points += read_group(group, grid)
        except (OSError, ValueError, KeyError) as e:  # KeyError: an episode without a field a record has
            parser.error(f"{option}: {group}: {e}")
    return points


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("records", nargs="+", metavar="FILE[+FILE...]",
                        help="crest_tradeoff.py --records files, a point per setting; files joined by + count as one "
                             "play of their settings together")
    parser.add_argument("--grid", default="family", help="the grid whose median and P90 are read (default: family)")
    parser.add_argument("--references", nargs="+", default=[], metavar="FILE[+FILE...]",
                        help="plays of hand-built agents (experiments/scripted_plays.py), shown beside the candidates "
                             "and counted against them, never on the frontier themselves")
    parser.add_argument("--shipped", default=None, metavar="FILE[+FILE...]",
                        help="the shipped agent's play, as given among the records (marked)")
    parser.add_argument("--out", type=Path, default=None, help="also write the table to this markdown file")
    parser.add_argument("--figure", type=Path, default=None, help="write the figure to this PNG file")
    parser.add_argument("--endings", action="store_true",
                        help="also count each play's episodes that ended at the horizon and its runaways in the slow "
                             "probe (the records' ended)")
    parser.add_argument("--rows", action="store_true",
                        help="also list the target rows some candidate meets and the shipped agent does not, or the "
                             "reverse (needs --references and --shipped)")
    args = parser.parse_args()
    if args.rows and (not args.references or args.shipped is None):
        parser.error("--rows: needs --references and --shipped (the rows are read against both)")
    check_out_file(parser, "--out", args.out)
    check_out_file(parser, "--figure", args.figure)
    if args.figure is not None and args.figure.suffix.lower() != ".png":
        parser.error(f"--figure: {args.figure}: give a .png file")
    labels = [label_of(Path(group.split("+")[0])) for group in [*args.records, *args.references]]
    if len(set(labels)) != len(labels):
        parser.error("records: two plays have the same name (a play is named by its first file's name)")
    if args.shipped is not None and args.shipped not in args.records:
        parser.error(f"--shipped: {args.shipped} is not one of the records given")
    points, references = (read_groups(parser, option, groups, args.grid)
                          for option, groups in (("records", args.records), ("--references", args.references)))
    if len({p.episodes for p in [*points, *references]}) != 1:
        parser.error("records: the plays hold different numbers of episodes (" +
                     ", ".join(f"{p.label} {p.episodes}" for p in [*points, *references]) +
                     "); one set of grids is needed")
    shipped = None if args.shipped is None else label_of(Path(args.shipped.split("+")[0]))
    if shipped is not None and shipped not in {p.label for p in points}:
        parser.error(f"--shipped: {args.shipped} holds several settings; the shipped agent's play is one")
    text = table(points, args.grid, shipped, references, args.endings)
    if args.rows:
        plays = play_names([label_of(Path(f)) for f in args.shipped.split("+")])
        text += ("\n## The target rows that part the candidates from the shipped agent\n\n"
                 + differing_rows(points, shipped, references, plays))
    print_table(text, args.out, "Runaways against accuracy and return")
    if args.figure is not None:
        figure(points, args.grid, shipped, args.figure, references)


if __name__ == "__main__":
    main()
