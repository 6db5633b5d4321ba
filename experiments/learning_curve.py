"""Is the learned interrogator's filter data-limited? Its held-out likelihood against the number of
training climbs. (run from the repository root; 2 cores, ~4 min on cached climbs)

    python experiments/learning_curve.py --run runs/interrogator_more --climbs env=8000 env_more=8000 \\
        --sizes 2000 4000 8000 16000 --ensembles cof_gym/agents/policies/interrogator \\
        runs/interrogator_more/ensemble runs/interrogator_32k/ensemble --out out/learning_curve.md

The training climbs of ``--climbs`` (train_interrogator.py's collections, in that order; read from RUN's
cache, collected there when missing) are split as the recipe splits them: every 10th climb apart.
For each size N one member (``--seed``, the recipe's fit settings) is fitted on the first N climbs less
those held apart, exactly the recipe's member for ``--climbs env=N``; it and every ``--ensembles``
directory are scored on the same held-apart windows of all the climbs (a network whose recipe used the
same split never trained on them). Per row: headroom and correction RMSE (log units) and mean Gaussian
NLL (lower is better).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from script_checks import check_out_dir, check_out_file  # noqa: E402
from train_interrogator import collect, parse_climbs, require_networks, split  # noqa: E402

from cof_gym.agents.interrogator import FilterEnsemble, read_manifest  # noqa: E402
from cof_gym.agents.interrogator.training import Dataset, FitSettings, fit_member, nll  # noqa: E402
from cof_gym.commands.args import Parser, positive_int, seed_int  # noqa: E402

COLUMNS = ("headroom_rmse", "headroom_nll", "correction_rmse", "correction_nll")


def row(label: str, climbs: str, scores: dict[str, float], seconds: float | None = None) -> str:
    """One markdown row: the networks, their training climbs, the four scores and the fit's time."""
    cells = " | ".join(f"{scores[c]:.3f}" for c in COLUMNS)
    return f"| {label} | {climbs} | {cells} | {'-' if seconds is None else f'{seconds:.0f} s'} |"


def trained_climbs(directory: Path) -> str:
    """The training climbs a run directory's manifest names (``env=8000 ...``), or "-"."""
    climbs = read_manifest(directory).get("training", {}).get("climbs", {})
    return " ".join(f"{k}={v}" for k, v in climbs.items()) or "-"


def table(data: Dataset, sizes: list[int], seed: int, ensembles: list[Path], epochs: int) -> str:
    """The learning curve (markdown): one member per size, then the ensembles, on the held-apart windows."""
    train, held = split(data)
    lines = [f"Held-apart windows: {len(held)} of {len(data)} (every 10th of {int(data.episode.max()) + 1} climbs).", "",
             "| networks | training climbs | headroom RMSE | headroom NLL | correction RMSE | correction NLL | fit |",
             "|---|---|---|---|---|---|---|"]
    settings = FitSettings(epochs=epochs)
    for n in sizes:
        t0 = time.time()
        member = fit_member(train.subset(train.episode < n), seed, settings)
        lines.append(row(f"member, seed {seed}", f"first {n}", nll(member, held), time.time() - t0))
        print(lines[-1], flush=True)
    for directory in ensembles:
        lines.append(row(str(directory), trained_climbs(directory), nll(FilterEnsemble.load(directory), held)))
        print(lines[-1], flush=True)
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = Parser(description=__doc__.split("\n")[0])
    parser.add_argument("--run", type=Path, default=Path("runs/interrogator"),
                        help="the directory whose climb caches (climbs*.npz) are read, or written when missing")
    parser.add_argument("--climbs", nargs="+", default=["env=8000"], metavar="NAME=N",
                        help="the training climbs, as train_interrogator.py's --climbs (in order)")
    parser.add_argument("--sizes", type=int, nargs="+", default=[2000, 4000, 8000],
                        help="numbers of climbs (the first N of --climbs) a member is fitted on")
    parser.add_argument("--seed", type=seed_int, default=0)
    parser.add_argument("--epochs", type=int, default=FitSettings.epochs)
    parser.add_argument("--ensembles", type=Path, nargs="*", default=[],
                        help="directories of networks (member_*.npz) scored on the same windows")
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--out", type=Path, default=Path("out/learning_curve.md"))
    args = parser.parse_args()
    check_out_dir(parser, "--run", args.run)
    check_out_file(parser, "--out", args.out)
    climbs = parse_climbs(parser, args.climbs)
    total = sum(climbs.values())
    if any(not 10 <= n <= total for n in args.sizes):
        parser.error(f"--sizes must lie in [10, {total}] (the climbs of --climbs)")
    if args.epochs < 1:
        parser.error(f"--epochs must be at least 1, got {args.epochs}")
    require_networks(parser, "--ensembles", args.ensembles)
    args.run.mkdir(parents=True, exist_ok=True)
    data = collect(args.run, climbs, args.workers)
    text = table(data, args.sizes, args.seed, args.ensembles, args.epochs)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
