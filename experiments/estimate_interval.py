"""How far the learned interrogator's estimate can be trusted: an interval calibrated on the validation grids,
its coverage measured on every reported suite. (Run from the repository root; 2 cores, about 6 min.)

    python experiments/estimate_interval.py [--policy DIR] [--coverage 0.9] [--lower-coverage 0.95] [--write]
                                            [--workers 2] [--out out/estimate_interval.md]

1. **Calibration.** Plays the interrogator of ``--policy`` (default: the shipped one) on the three validation
   grids (family, procedural and steep creep curves: model-selection data, never reported; both vehicle
   configurations, 360 climbs). From the scored episodes it computes the split conformal scales
   (:class:`cof_gym.agents.interrogator.IntervalScales`): the two-sided interval at ``--coverage`` and the lower
   bound at ``--lower-coverage``, in stds of the estimate's log. With ``--write`` it saves them as the policy
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
from script_checks import check_out_file  # noqa: E402
from train_interrogator import CONFIGS, PROCEDURAL_VALIDATION, STEEP_VALIDATION, VALIDATION, episodes  # noqa: E402

from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR, IntervalScales, check_coverage  # noqa: E402
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
    ended: str

    @property
    def triple(self) -> tuple[float, float, float]:
        return self.estimate, self.cof, self.log_std


def play(policy: str, suite: str, config: dict) -> list[Committed]:
    """The scored episodes of ``suite`` (a suite file or ``"default"``) played by the interrogator of ``policy``
    in the vehicle configuration ``config``."""
    return [Committed(r.estimate, r.cof, agent.estimate_log_std, r.ended)
            for r, agent in episodes(policy, suite, config) if r.scored]


def coverage_cells(episodes: list[Committed], scales: IntervalScales) -> tuple[str, str, str]:
    """(two-sided coverage, lower-bound coverage, median width high / low) of ``episodes`` ("-" for none)."""
    if not episodes:
        return "-", "-", "-"
    inside, above, widths = [], [], []
    for e in episodes:
        low, high = scales.interval(e.estimate, e.log_std)
        inside.append(low <= e.cof <= high)
        above.append(scales.lower_bound(e.estimate, e.log_std) <= e.cof)
        widths.append(high / low)
    return f"{np.mean(inside):.1%}", f"{np.mean(above):.1%}", f"{np.median(widths):.2f}"


def row(label: str, episodes: list[Committed], scales: IntervalScales) -> str:
    cells = [label, str(len(episodes)), *coverage_cells(episodes, scales)]
    for ending in ENDINGS:
        part = [e for e in episodes if e.ended == ending]
        two_sided, lower, width = coverage_cells(part, scales)
        cells.append(f"{len(part)}: {two_sided} / {lower} / {width}" if part else "-")
    return "| " + " | ".join(cells) + " |"


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
    scales = IntervalScales.calibrate([e.triple for e in calibration], args.coverage, args.lower_coverage,
                                      "the validation grids (family, procedural, steep; both vehicle configurations)")
    if args.write:
        print(f"wrote {scales.save(args.policy)}")
    header = (f"Scales (`python experiments/estimate_interval.py`, split conformal on {scales.climbs} scored "
              f"validation climbs): the {scales.coverage:.0%} interval is the estimate times exp(+-{scales.scale:.3f} "
              f"std), the {scales.lower_coverage:.0%} lower bound the estimate times exp(-{scales.lower_scale:.3f} std), "
              "std the estimate's log std (`LearnedInterrogator.estimate_log_std`).")
    lines = [header, "",
             f"| suite | scored episodes | CoF in the {scales.coverage:.0%} interval | CoF above the "
             f"{scales.lower_coverage:.0%} lower bound | median width (high / low) | "
             + " | ".join(f"{ending}: episodes: in / above / width" for ending in ENDINGS) + " |",
             "|---" * (5 + len(ENDINGS)) + "|",
             row("validation grids (the calibration)", calibration, scales)]
    lines += [row(label, part, scales) for label, part in zip(reported, played[len(calibration_parts):])]
    text = "\n".join(lines) + "\n"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(text, end="")


if __name__ == "__main__":
    main()
