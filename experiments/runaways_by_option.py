"""Runaways per band of one reset option, per setting, from crest_tradeoff.py's ``--records``.

    python experiments/runaways_by_option.py out/records_a.json [more.json ...] --grids validation_torque \
        --option torque_gain_error --edges 0.05 0.1 --absolute [--out FILE]

Each episode's option is read from the grid files it was played on (``--grids``: the set crest_tradeoff.py played;
an episode without the option counts as 0, the env's value when it is not set). The bands are split at ``--edges``
(ascending; ``--absolute``: on the option's magnitude): a band holds the values from its lower edge up to, not
including, its upper one. Every setting of the records must have played the same episodes. Nothing is decided
here: it places where macro-slips moved, e.g. whether a candidate's added runaways follow a sensor error's size.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from cof_gym.commands.args import Parser, float_in_range

sys.path.insert(0, str(Path(__file__).resolve().parent))
from crest_tradeoff import GRID_SETS  # noqa: E402
from paired_comparison import paired, print_table, read_record_files  # noqa: E402
from script_checks import check_out_file  # noqa: E402

from cof_gym.validation import is_number  # noqa: E402

EDGE = float_in_range(-1e9, 1e9, low_inclusive=True)  # a finite band edge (an option's value, any sign)


def grid_episodes(grids: dict[str, Path]) -> dict[str, list[dict]]:
    """Each grid file's episodes (seed and reset options), in the suite's order."""
    return {kind: json.loads(path.read_text())["episodes"] for kind, path in grids.items()}


def option_values(episodes: dict[str, list[dict]], option: str) -> dict[str, list[float]]:
    """Each grid's episodes' value of ``option`` (0 where an episode leaves it unset), in the suite's order."""
    return {kind: [float(e.get("options", {}).get(option, 0.0)) for e in grid] for kind, grid in episodes.items()}


def band_labels(edges: list[float]) -> list[str]:
    bounds = [f"{e:g}" for e in edges]
    return [f"< {bounds[0]}"] + [f"{a}-{b}" for a, b in zip(bounds, bounds[1:])] + [f">= {bounds[-1]}"]


def band(value: float, edges: list[float]) -> int:
    return sum(value >= e for e in edges)


def table(records: list[dict], values: dict[str, list[float]], option: str, edges: list[float],
          absolute: bool) -> str:
    """Macro-slips of each setting per band (all grids together), with the episodes in each band."""
    settings = list(dict.fromkeys(r["setting"] for r in records))
    labels = band_labels(edges)
    name = f"abs({option})" if absolute else option  # no pipe: it would split the table's cell
    lines = [f"| setting | {' | '.join(f'{name} {label}' for label in labels)} | all |",
             "|---|" + "---|" * (len(labels) + 1)]
    for setting in settings:
        counts, sizes = [0] * len(labels), [0] * len(labels)
        for grid, episodes in paired(records, setting).items():
            if grid not in values:
                raise ValueError(f"grid {grid!r} is not one of --grids' ({', '.join(values)})")
            for (_, episode), record in episodes.items():
                value = values[grid][episode]
                k = band(abs(value) if absolute else value, edges)
                counts[k] += bool(record["macro_slip"])
                sizes[k] += 1
        cells = [f"{c} of {n}" for c, n in zip(counts, sizes)]
        lines.append(f"| {setting} | {' | '.join(cells)} | {sum(counts)} of {sum(sizes)} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("records", type=Path, nargs="+", help="crest_tradeoff.py --records files")
    parser.add_argument("--grids", choices=sorted(GRID_SETS), default="validation",
                        help="the grid set the records were played on (crest_tradeoff.py --grids)")
    parser.add_argument("--option", required=True,
                        help="a reset option of the grid files' episodes, e.g. torque_gain_error")
    parser.add_argument("--edges", type=EDGE, nargs="+", required=True, help="where the bands split (ascending)")
    parser.add_argument("--absolute", action="store_true", help="band the option's magnitude")
    parser.add_argument("--out", type=Path, default=None, help="also write the table to this markdown file")
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    if any(b <= a for a, b in zip(args.edges, args.edges[1:])):
        parser.error(f"--edges: must be strictly ascending, got {' '.join(f'{e:g}' for e in args.edges)}")
    episodes = grid_episodes(GRID_SETS[args.grids])
    if not any(args.option in e.get("options", {}) for grid in episodes.values() for e in grid):
        parser.error(f"--option: no episode of --grids {args.grids} sets {args.option!r}")
    if not all(is_number(e.get("options", {}).get(args.option, 0.0)) for grid in episodes.values() for e in grid):
        parser.error(f"--option: {args.option!r} is not a number in the grids' episodes (e.g. a condition or a creep "
                     "law); band a numeric option such as torque_gain_error or noise_level")
    records = read_record_files(parser, args.records)
    values = option_values(episodes, args.option)
    try:
        text = table(records, values, args.option, args.edges, args.absolute)
    except (KeyError, IndexError, ValueError) as e:
        parser.error(f"records: not played on --grids {args.grids}: {e}")
    print_table(text, args.out, f"Runaways by {args.option} ({args.grids})")


if __name__ == "__main__":
    main()
