"""cof-gym: measure the wheel-rail coefficient of friction by torque modulation, in simulation.

Commands: evaluate (agents side by side on the same seeded scenarios), train (a PPO interrogation
policy), bench (simulation speed), reproduce-paper (the paper's figures re-simulated). Run
"cof-gym COMMAND --help" for the options of each.

Exit status: 0 on success, 2 on a usage error (one line on stderr, nothing written), 130 when
interrupted.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

PROG = "cof-gym"


class UsageError(Exception):
    """A bad command line: reported as one line ``cof-gym CMD: error: FLAG: message``, exit status 2."""

    def __init__(self, flag: str | None, message: str) -> None:
        super().__init__(f"{flag}: {message}" if flag else message)
        self.flag = flag


class HelpFormatter(argparse.RawDescriptionHelpFormatter, argparse.ArgumentDefaultsHelpFormatter):
    """Descriptions as written, and every option's default (unless it has none worth showing)."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if "%(default)" in text or action.default in (None, False, argparse.SUPPRESS) or not action.option_strings:
            return text
        return text + " (default: %(default)s)"


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``cof-gym evaluate: error: argument --episodes: ...`` (no usage
    block), exit status 2."""

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str):  # noqa: D102 - argparse API
        message = " ".join(message.split())
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


# ---------------------------------------------------------------------------- argument types
def _int_at_least(text: str, low: int) -> int:
    try:
        value = int(text)
    except ValueError:
        value = low - 1
    if value < low:
        raise argparse.ArgumentTypeError(f"must be an integer >= {low}, got {text!r}")
    return value


def positive_int(text: str) -> int:
    return _int_at_least(text, 1)


def non_negative_int(text: str) -> int:
    return _int_at_least(text, 0)


def _float_above(text: str, low: float, inclusive: bool) -> float:
    bound = f">= {low:g}" if inclusive else f"> {low:g}"
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number {bound}, got {text!r}") from None
    if not math.isfinite(value) or value < low or (value == low and not inclusive):
        raise argparse.ArgumentTypeError(f"must be a finite number {bound}, got {text!r}")
    return value


def positive_float(text: str) -> float:
    return _float_above(text, 0.0, inclusive=False)


def non_negative_float(text: str) -> float:
    return _float_above(text, 0.0, inclusive=True)


def check_output_dir(path: Path, flag: str = "--out") -> Path:
    """An output directory that can be created or replaced: not an existing file, below no file, in a
    writable place, not the current directory or one of its parents. Creates nothing."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise UsageError(flag, f"{path} exists and is not a directory; give a directory")
    resolved = path.resolve()
    cwd = Path.cwd().resolve()
    if resolved == cwd or resolved in cwd.parents:
        raise UsageError(flag, f"{path} is the current directory or one of its parents; give a subdirectory")
    ancestor = resolved
    while not ancestor.exists():
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise UsageError(flag, f"{path}: {ancestor} is a file, not a directory")
    if not os.access(ancestor, os.W_OK | os.X_OK):
        raise UsageError(flag, f"{path}: {ancestor} is not writable")
    return path


# ---------------------------------------------------------------------------- commands
def _add_reproduce(sub) -> None:
    try:
        from cof_gym.analysis import paper
    except ImportError:  # reported when the command runs
        paper = None
    p = sub.add_parser("reproduce-paper", help="re-simulate the paper's Figs. 5, 4/7 and 8; exit 1 if a check fails",
                       description="Re-simulate the paper's Figs. 5, 4/7 and 8 (figures and results.json); exit "
                                   "status 1 if a check that should hold fails.")
    if paper is not None and hasattr(paper, "add_arguments"):
        paper.add_arguments(p)
    else:
        p.add_argument("--out", default="out/paper", help="output directory (figures, results.json)")
        p.add_argument("--quick", action="store_true", help="shorter windows (under 2 minutes)")
    p.set_defaults(func=_reproduce)


def _reproduce(args: argparse.Namespace) -> int:
    from cof_gym.analysis import paper

    if getattr(args, "out", None) is not None:
        check_output_dir(Path(args.out))
    if hasattr(paper, "run"):
        return int(paper.run(args) or 0)
    results = paper.reproduce(Path(args.out), quick=args.quick)
    print("\n".join(paper.summary_lines(results)))
    print(f"figures and results.json in {args.out}")
    return 0


def _bench(args: argparse.Namespace) -> int:
    from cof_gym.bench import main as bench_main

    bench_main(args.seconds)
    return 0


def _evaluate(args: argparse.Namespace) -> int:
    from cof_gym.agents.evaluate import run

    return run(args)


def _train(args: argparse.Namespace) -> int:
    from cof_gym.agents.train import run

    return run(args)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog=PROG, description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=Parser)
    from cof_gym.agents.evaluate import DESCRIPTION as EVALUATE_DESCRIPTION, add_arguments as evaluate_arguments

    p = sub.add_parser("evaluate", help="agents side by side on the same seeded scenarios",
                       description=EVALUATE_DESCRIPTION)
    evaluate_arguments(p)
    p.set_defaults(func=_evaluate)
    try:
        from cof_gym.agents.train import DESCRIPTION as TRAIN_DESCRIPTION, add_arguments as train_arguments
    except ImportError:  # training extras not installed
        train_arguments = None
    if train_arguments is not None:
        p = sub.add_parser("train", help="train a PPO interrogation policy", description=TRAIN_DESCRIPTION)
        train_arguments(p)
        p.set_defaults(func=_train)
    p = sub.add_parser("bench", help="simulation speed: native callback vs bare MuJoCo, 1 vs 2 threads",
                       description="Simulation speed of the wagon with and without the native callback, and "
                                   "agent steps per second of the single and the vector env.")
    p.add_argument("--seconds", type=positive_float, default=5.0,
                   help="simulated seconds per physics timing (also sets the env timings' length)")
    p.set_defaults(func=_bench)
    _add_reproduce(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    command = f"{PROG} {args.command}"
    try:
        return int(args.func(args) or 0)
    except UsageError as e:
        print(f"{command}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"{command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # python -m cof_gym.cli: run the importable module (one UsageError class)
    from cof_gym.cli import main as _main

    sys.exit(_main())
