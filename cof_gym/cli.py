"""cof-gym: measure the wheel-rail coefficient of friction by torque modulation, in simulation.

Commands: evaluate (agents side by side on the same seeded scenarios), agents (the agents evaluate knows), train (a
PPO interrogation policy), bench (simulation speed), reproduce-paper (the paper's figures re-simulated), watch (a video
of an episode). Run "cof-gym COMMAND --help" for the options of each.

Exit status: 0 on success, 2 on a usage error (one line on stderr, nothing written), 130 when
interrupted.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import cof_gym
from cof_gym.commands.args import PROG, Parser, UsageError, check_output_dir, check_output_file, float_in_range

BENCH_MIN_SECONDS = 0.01  # bench --seconds: ten physics steps of the wagon (dt = 1 ms), the shortest timing
BENCH_MAX_SECONDS = 3600.0  # and the longest: an hour of simulated time per timing (about 20 s of wall time each)


# ---------------------------------------------------------------------------- commands
def _add_reproduce(sub) -> None:
    from cof_gym.commands import paper

    p = sub.add_parser("reproduce-paper", help="re-simulate the paper's Figs. 5, 4/7 and 8; exit 1 if a check fails",
                       description="Re-simulate the paper's Figs. 5, 4/7 and 8 (figures and results.json); exit "
                                   "status 1 if a check that should hold fails.")
    paper.add_arguments(p)
    p.set_defaults(func=_reproduce)


def _reproduce(args: argparse.Namespace) -> int:
    from cof_gym.commands import paper

    if getattr(args, "out", None) is not None:
        check_output_dir(Path(args.out))
    return int(paper.run(args) or 0)


def _bench(args: argparse.Namespace) -> int:
    from cof_gym.commands.bench import main as bench_main

    if args.markdown is not None:  # checked before the benchmark runs
        check_output_file(Path(args.markdown), "--markdown")  # missing folders are made by the bench
    bench_main(args.seconds, args.markdown)
    return 0


def _evaluate(args: argparse.Namespace) -> int:
    from cof_gym.commands.evaluate import run

    return run(args)


def _train(args: argparse.Namespace) -> int:
    from cof_gym.commands.train import run

    return run(args)


def _add_watch(sub) -> None:
    from cof_gym.commands.watch import DESCRIPTION, add_arguments, run

    p = sub.add_parser("watch", help="a video (MP4 or GIF) of one agent's episode", description=DESCRIPTION)
    add_arguments(p)
    p.set_defaults(func=run)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog=PROG, description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=Parser)
    from cof_gym.commands.evaluate import DESCRIPTION as EVALUATE_DESCRIPTION, add_arguments as evaluate_arguments

    p = sub.add_parser("evaluate", help="agents side by side on the same seeded scenarios",
                       description=EVALUATE_DESCRIPTION)
    evaluate_arguments(p)
    p.set_defaults(func=_evaluate)
    from cof_gym.commands.agents import DESCRIPTION as AGENTS_DESCRIPTION, add_arguments as agents_arguments, run

    p = sub.add_parser("agents", help="the agents evaluate and watch know, and what each does",
                       description=AGENTS_DESCRIPTION)
    agents_arguments(p)
    p.set_defaults(func=run)
    try:
        from cof_gym.commands.train import DESCRIPTION as TRAIN_DESCRIPTION, add_arguments as train_arguments
    except ImportError:  # training extras not installed
        train_arguments = None
    if train_arguments is not None:
        p = sub.add_parser("train", help="train a PPO interrogation policy", description=TRAIN_DESCRIPTION)
        train_arguments(p)
        p.set_defaults(func=_train)
    p = sub.add_parser("bench", help="simulation speed: native callback vs bare MuJoCo, 1 vs 2 threads",
                       description="Simulation speed of the wagon with and without the native callback, and "
                                   "agent steps per second of the single and the vector env.")
    p.add_argument("--seconds", type=float_in_range(BENCH_MIN_SECONDS, BENCH_MAX_SECONDS, low_inclusive=True),
                   default=5.0, help=f"simulated seconds per physics timing, {BENCH_MIN_SECONDS:g} to "
                   f"{BENCH_MAX_SECONDS:g} (also sets the env timings' length)")
    p.add_argument("--markdown", metavar="PATH", default=None,
                   help="also write the table there as Markdown (experiments/readme_results.py copies it into the README)")
    p.set_defaults(func=_bench)
    _add_reproduce(sub)
    _add_watch(sub)
    for command_parser in sub.choices.values():  # each command's errors are named by its own parser
        command_parser.set_defaults(command_parser=command_parser)
    return parser


def main(argv: list[str] | None = None) -> int:
    cof_gym.ignore_out_of_date_notice()
    parser = build_parser()
    args, extras = parser.parse_known_args(argv)
    if extras:  # named by the command's own parser ("cof-gym evaluate: error: ..."), as its other errors are
        args.command_parser.error(f"unrecognized arguments: {' '.join(extras)}")
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
