"""How far the learned interrogator's estimate can be trusted: an interval calibrated on the validation grids,
its coverage measured on every reported suite. (Run from the repository root; 2 cores, about 6 min.)

    python experiments/estimate_interval.py [--policy DIR] [--coverage 0.9] [--lower-coverage 0.95] [--write]
                                            [--workers 2] [--out out/estimate_interval.md]

1. **Calibration.** Plays the interrogator of ``--policy`` (default: the shipped one) on the three validation
   grids (family, procedural and steep creep curves: model-selection data, never reported; both vehicle
   configurations, 360 climbs). From the scored episodes it computes the split conformal scales
   (:class:`cof_gym.agents.interrogator.IntervalScales`): the two-sided interval at ``--coverage`` and the lower
   bound at ``--lower-coverage``, in stds of the estimate's log, per way the estimate was committed (the climb's
   stop, the horizon, no stop: ``LearnedInterrogator.commitment``) or pooled, whichever a leave-one-grid-out
   comparison on the validation grids alone chooses (each calibrated on two grids, measured on the third: the
   smaller worst shortfall below a target wins, the pooled scales on a tie). With ``--write`` it saves them as the policy
   directory's ``interval.json``, which the agent then loads (``LearnedInterrogator.cof_interval`` and
   ``cof_lower_bound``).
2. **Report** (nothing is chosen here). Plays the default suite (60 seeded v2 draws, as ``cof-gym evaluate``)
   and every v2 held-out grid with the scales of step 1, and tabulates per suite how often the CoF lies in
   the interval and above the lower bound, and the interval's median width (high over low), in all and by how
   the episode ended (the agent's stop, the horizon, a macro-slip). The validation grids' own row is the
   calibration itself: its coverage is at least the target by construction. The held-out grids' creep curves
   and sensor errors are unlike the calibration climbs', so their rows measure what the guarantee does not
   cover.
"""

from __future__ import annotations

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from make_grids import v2_heldout_grids  # noqa: E402
from script_checks import check_out_file, write_report  # noqa: E402
from train_interrogator import CONFIGS, PROCEDURAL_VALIDATION, STEEP_VALIDATION, VALIDATION, episodes  # noqa: E402

from cof_gym.agents.interrogator import POOLED, SHIPPED_INTERROGATOR, IntervalScales, check_coverage  # noqa: E402
from cof_gym.commands.args import Parser, positive_int  # noqa: E402
from cof_gym.commands.evaluate_episodes import ENDINGS as EVALUATE_ENDINGS  # noqa: E402

CALIBRATION = {"family": VALIDATION, "procedural": PROCEDURAL_VALIDATION, "steep": STEEP_VALIDATION}
ENDINGS = tuple(e for e in EVALUATE_ENDINGS if e != "diverged")  # how a scored episode ends: the breakdown's columns


@dataclass(frozen=True)
class Committed:
    """One scored episode: the estimate the env scored, the CoF, the std of the estimate's log, how it ended."""

    estimate: float
    cof: float
    log_std: float
    commitment: str  # how the agent committed it (LearnedInterrogator.commitment): the scale it reads
    ended: str

    @property
    def calibration(self) -> tuple[float, float, float, str]:
        return self.estimate, self.cof, self.log_std, self.commitment


def play(policy: str, suite: str, config: dict) -> list[Committed]:
    """The scored episodes of ``suite`` (a suite file or ``"default"``) played by the interrogator of ``policy``
    in the vehicle configuration ``config``."""
    return [Committed(r.estimate, r.cof, agent.estimate_log_std, agent.commitment, r.ended)
            for r, agent in episodes(policy, suite, config) if r.scored]


def coverage_cells(episodes: list[Committed], scales: IntervalScales) -> tuple[str, str, str]:
    """(two-sided coverage, lower-bound coverage, median width high / low) of ``episodes`` ("-" for none)."""
    if not episodes:
        return "-", "-", "-"
    inside, above, width = covered(episodes, scales)
    return f"{inside:.1%}", f"{above:.1%}", f"{width:.2f}"


def row(label: str, episodes: list[Committed], scales: IntervalScales) -> str:
    cells = [label, str(len(episodes)), *coverage_cells(episodes, scales)]
    for ending in ENDINGS:
        part = [e for e in episodes if e.ended == ending]
        two_sided, lower, width = coverage_cells(part, scales)
        cells.append(f"{len(part)}: {two_sided} / {lower} / {width}" if part else "-")
    return "| " + " | ".join(cells) + " |"


METHODS = {"pooled": False, "per commitment": True}  # the calibrations compared: IntervalScales.calibrate's flag


def covered(episodes: list[Committed], scales: IntervalScales) -> tuple[float, float, float]:
    """(the fraction of ``episodes`` whose CoF lies in the interval, the fraction at least the lower bound, the
    interval's median width high / low)."""
    intervals = [scales.interval(e.estimate, e.log_std, e.commitment) for e in episodes]
    inside = [low <= e.cof <= high for e, (low, high) in zip(episodes, intervals)]
    above = [scales.lower_bound(e.estimate, e.log_std, e.commitment) <= e.cof for e in episodes]
    return float(np.mean(inside)), float(np.mean(above)), float(np.median([high / low for low, high in intervals]))


def select_method(by_grid: dict[str, list[Committed]], coverage: float, lower_coverage: float
                  ) -> tuple[list[str], bool]:
    """Leave one validation grid out: each method of :data:`METHODS` calibrated on the other two grids and measured
    on it. The method whose worst shortfall below a target (over the left-out grids, the interval's and the lower
    bound's) is the smallest is chosen, the pooled one on a tie. (The table's lines, per_commitment.)"""
    lines = [f"Leave one validation grid out (calibrated on the other two; targets {coverage:.0%} in the interval, "
             f"{lower_coverage:.0%} above the lower bound):", "",
             "| method | " + " | ".join(f"left out: {grid}" for grid in by_grid) + " | worst shortfall |",
             "|---" * (len(by_grid) + 2) + "|"]
    shortfalls = {}
    for method, flag in METHODS.items():
        cells, worst = [], 0.0
        for left_out in by_grid:
            rest = [e.calibration for grid, part in by_grid.items() if grid != left_out for e in part]
            inside, above, _ = covered(by_grid[left_out], IntervalScales.calibrate(rest, coverage, lower_coverage,
                                                                                   per_commitment=flag))
            worst = max(worst, coverage - inside, lower_coverage - above)
            cells.append(f"{inside:.1%} / {above:.1%}")
        shortfalls[method] = worst
        lines.append(f"| {method} | " + " | ".join(cells) + f" | {100 * worst:.1f} points |")
    chosen = min(METHODS, key=lambda m: (shortfalls[m], m != "pooled"))
    lines += ["", f"Chosen: {chosen} (the smaller worst shortfall; the pooled one on a tie)."]
    return lines, METHODS[chosen]


def coverage(option: str):
    """An argparse type for a coverage in (0, 1)."""
    def parse(text: str) -> float:
        try:
            return check_coverage(option, float(text))
        except ValueError as error:
            raise argparse.ArgumentTypeError(str(error)) from None
    return parse


def main() -> None:
    parser = Parser(description=__doc__.split("\n")[0])
    parser.add_argument("--policy", type=Path, default=SHIPPED_INTERROGATOR, help="the interrogator's directory")
    parser.add_argument("--coverage", type=coverage("--coverage"), default=0.9, help="of the two-sided interval")
    parser.add_argument("--lower-coverage", type=coverage("--lower-coverage"), default=0.95,
                        help="of the lower bound")
    parser.add_argument("--write", action="store_true", help="save the scales as the policy's interval.json")
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--out", type=Path, default=Path("out/estimate_interval.md"))
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    if not (args.policy / "manifest.json").is_file():
        parser.error(f"--policy: {args.policy} holds no manifest.json (an interrogator's directory)")
    reported = {"default suite": "default",
                **{label: str(HERE / "suites" / f"{name}.json") for name, label in v2_heldout_grids().items()}}
    jobs = [(str(args.policy), str(path), config) for path in CALIBRATION.values() for config in CONFIGS]
    jobs += [(str(args.policy), suite, {}) for suite in reported.values()]
    with ProcessPoolExecutor(args.workers) as pool:
        played = list(pool.map(play, *zip(*jobs)))
    calibration_parts = played[:len(CALIBRATION) * len(CONFIGS)]
    calibration = [e for part in calibration_parts for e in part]
    by_grid = {grid: [e for part in calibration_parts[k * len(CONFIGS):(k + 1) * len(CONFIGS)] for e in part]
               for k, grid in enumerate(CALIBRATION)}
    selection, per_commitment = select_method(by_grid, args.coverage, args.lower_coverage)
    scales = IntervalScales.calibrate([e.calibration for e in calibration], args.coverage, args.lower_coverage,
                                      "the validation grids (family, procedural, steep; both vehicle configurations)",
                                      per_commitment)
    if args.write:
        print(f"wrote {scales.save(args.policy)}")
    header = (f"Scales (`python experiments/estimate_interval.py`, split conformal per commitment on "
              f"{scales.climbs[POOLED]} scored validation climbs), in stds of the estimate's log "
              f"(`LearnedInterrogator.estimate_log_std`): the {scales.coverage:.0%} interval is the estimate times "
              f"exp(+-scale x std), the {scales.lower_coverage:.0%} lower bound the estimate times exp(-lower scale x "
              "std); " + "; ".join(f"{group} ({scales.climbs[group]} climbs): {pair[0]:.3f} / {pair[1]:.3f}"
                                   for group, pair in scales.scales.items()) + ".")
    lines = [*selection, "", header, "",
             f"| suite | scored episodes | CoF in the {scales.coverage:.0%} interval | CoF above the "
             f"{scales.lower_coverage:.0%} lower bound | median width (high / low) | "
             + " | ".join(f"{ending}: episodes: in / above / width" for ending in ENDINGS) + " |",
             "|---" * (5 + len(ENDINGS)) + "|",
             row("validation grids (the calibration)", calibration, scales)]
    lines += [row(label, part, scales) for label, part in zip(reported, played[len(calibration_parts):])]
    write_report(args.out, lines)


if __name__ == "__main__":
    main()
