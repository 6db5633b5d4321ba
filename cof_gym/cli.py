"""The ``cof-gym`` command line."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def _reproduce(args: argparse.Namespace) -> int:
    from cof_gym.analysis.paper import reproduce, summary_lines

    results = reproduce(Path(args.out), quick=args.quick)
    print("\n".join(summary_lines(results)))
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
    parser = argparse.ArgumentParser(prog="cof-gym", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    from cof_gym.analysis.paper import add_arguments as reproduce_arguments, run as reproduce_run

    p = sub.add_parser("reproduce-paper", help="re-simulate the paper's Figs. 5, 4/7 and 8; exit 1 if a check fails")
    reproduce_arguments(p)
    p.set_defaults(func=reproduce_run)
    p = sub.add_parser("bench", help="simulation speed and native/bare ratio")
    p.add_argument("--seconds", type=float, default=5.0, help="simulated seconds per timing")
    p.set_defaults(func=_bench)
    from cof_gym.agents.evaluate import add_arguments as evaluate_arguments

    p = sub.add_parser("evaluate", help="agents side by side on the same seeded scenarios")
    evaluate_arguments(p)
    p.set_defaults(func=_evaluate)
    try:
        from cof_gym.agents.train import add_arguments as train_arguments
    except ImportError:  # training extras not installed
        train_arguments = None
    if train_arguments is not None:
        p = sub.add_parser("train", help="train a PPO interrogation policy")
        train_arguments(p)
        p.set_defaults(func=_train)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return int(args.func(args) or 0)


if __name__ == "__main__":
    sys.exit(main())
