"""What noise does the shipped interrogator read from its first windows, at each sensor noise level?
(run from the repository root; 2 cores, ~4 min)

    python experiments/noise_reading.py [--levels 0 0.5 1 2 3] [--episodes 48] [--out out/noise_reading.md]

Plays the shipped interrogator (its own climb) on the first ``--episodes`` episodes of the family validation
grid (experiments/suites/v2_validation_grid.json, model-selection data) in both vehicle configurations, with
every episode's ``noise_level`` replaced by each of ``--levels`` in turn (1: the top of the v2 draws, which
draw it uniformly from 0 to 1; the env admits up to 3), and tabulates per level the noise the climb reads
(``ClimbParameters.noise_ratio``'s input: the median of :attr:`~cof_gym.agents.interrogator.Reading.lockin_noise_nms`
over the climb's first ``NOISE_WINDOWS`` driven windows, N m s) over the episodes: median, P10, P90 and
the largest; the same from the lock-in's reported standard errors (``Reading.lockin_noise_reported_nms``: not
clipped at the filter's 30 deg); and over every driven window of the climbs (the largest single window). A reading
that follows the speed sensor's noise and not the operating point grows in proportion to the level with a
narrow spread at each; ``ClimbParameters.noise_reference_nms`` is chosen from this table.
"""

from __future__ import annotations

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from script_checks import check_out_file, write_report  # noqa: E402
from train_interrogator import CONFIGS, VALIDATION, episodes  # noqa: E402

from cof_gym.agents.interrogator import NOISE_WINDOWS, SHIPPED_INTERROGATOR, first_windows_noise_nms  # noqa: E402
from cof_gym.commands.args import Parser, positive_int  # noqa: E402
from cof_gym.task.scenarios import NOISE_LEVEL_MAX  # noqa: E402
from cof_gym.validation import check_number  # noqa: E402


def read_noise(level: float, config: dict, count: int) -> tuple[list[float], list[float], list[float]]:
    """(per episode the median lock-in noise of its first windows, the same from the reported standard errors,
    every driven window's) of the first ``count`` family validation episodes at noise ``level`` in the vehicle
    configuration ``config``."""
    firsts, reported, windows = [], [], []
    played = episodes(str(SHIPPED_INTERROGATOR), str(VALIDATION), config, scenario={"noise_level": level})
    for _, (_, agent) in zip(range(count), played):
        readings = agent.features.readings
        firsts.append(first_windows_noise_nms(readings))
        reported.append(first_windows_noise_nms(readings, reported=True))
        windows += [r.lockin_noise_nms for r in readings]
    return firsts, reported, windows


def row(level: float, firsts: list[float], reported: list[float], windows: list[float]) -> str:
    cells = [f"{v:.4f}" for values in (firsts, reported) for v in (*np.percentile(values, [50, 10, 90]), max(values))]
    return f"| {level:g} | {len(firsts)} | {' | '.join(cells)} | {np.median(windows):.4f} | {max(windows):.4f} |"


def level(text: str) -> float:
    """A ``--levels`` entry: a noise level in [0, NOISE_LEVEL_MAX]."""
    try:
        return check_number("--levels", float(text), 0.0, NOISE_LEVEL_MAX)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def main() -> None:
    parser = Parser(description=__doc__.split("\n")[0])
    parser.add_argument("--levels", type=level, nargs="+", default=[0.0, 0.5, 1.0, 2.0, 3.0])
    parser.add_argument("--episodes", type=positive_int, default=48, help="family validation episodes per configuration")
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--out", type=Path, default=Path("out/noise_reading.md"))
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    jobs = [(lv, c) for lv in args.levels for c in CONFIGS]
    with ProcessPoolExecutor(args.workers) as pool:
        results = list(pool.map(read_noise, *zip(*jobs), [args.episodes] * len(jobs)))
    lines = [f"| noise level | episodes | first {NOISE_WINDOWS} windows: median (N m s) | P10 | P90 | largest | "
             "reported SE: median | P10 | P90 | largest | every window: median | largest |", "|---" * 12 + "|"]
    for i, lv in enumerate(args.levels):
        parts = results[i * len(CONFIGS):(i + 1) * len(CONFIGS)]
        lines.append(row(lv, *([x for part in parts for x in part[k]] for k in range(3))))
    write_report(args.out, lines)


if __name__ == "__main__":
    main()
