"""Model selection and reporting for several PPO seeds (run from the repository root).

    python experiments/ppo_seeds.py --runs runs/ppo_lo_s0 runs/ppo_lo_s1 runs/ppo_lo_s2 --out out/ppo_seeds [--ship]

1. Candidates per seed: the cloned policy before RL (``warm_start/``, when the run was warm-started),
   its checkpoints (``checkpoints/ppo_<N>_steps.zip``), its ``best/best_model.zip`` (the training-time
   evaluation's best) and its final ``model.zip``. Each is played on
   ``suites/validation_grid.json`` (model selection only); the candidate with the highest mean episode
   return there is that seed's policy: the task's own reward (relative error, slip past the peak,
   macro-slips, comfort, time; evaluated without the training-time shaping), so no single metric is
   bought at the others' cost.
2. The seeds' policies are played on ``suites/heldout_grid.json`` and on 100 episodes of the v1 default
   suite (``suites/v1_default.json``; reporting only; nothing is selected there). Per seed: median / P90 relative error,
   macro-slips. Over seeds: the interquartile mean (IQM) and median of the relative error with
   stratified-bootstrap 95 % CIs (runs resampled within each scenario, as rliable's
   ``StratifiedBootstrap`` does; Agarwal et al. 2021), so the CI covers seed and scenario variation.
3. ``--ship`` copies the policy of the best seed *on the validation grid* (highest mean return; model zip, VecNormalize
   statistics, train_meta.json) into ``cof_gym/agents/policies/ppo_wagon``, the default ``ppo`` agent.

Every grid is a v1 grid, so every run must have trained on ``CofGym/TorqueInterrogation-v1`` (``cof-gym train --env
CofGym/TorqueInterrogation-v1``, as ``experiments/shipped_policy.sh`` does): a run of another env is refused.

Writes ``OUT/report.md`` and ``OUT/report.json``.
"""

from __future__ import annotations

import argparse
import csv
import json
import shutil
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from cof_gym.commands.args import Parser, positive_int
from cof_gym.commands.evaluate import evaluate
from cof_gym.agents.sb3_policy import check_model, find_train_meta, vecnormalize_path
from cof_gym.agents.policy_files import META_NAME, MODEL_NAMES, SHIPPED_PPO, VECNORMALIZE_NAME
from cof_gym.commands.suites import make_suite

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from script_checks import check_out_dir  # noqa: E402

VALIDATION = HERE / "suites" / "validation_grid.json"
HELDOUT = HERE / "suites" / "heldout_grid.json"
V1_DEFAULT = HERE / "suites" / "v1_default.json"
REPORTS = {"heldout_grid": HELDOUT, "default": V1_DEFAULT}  # report name -> suite (the v1 task's)
DEFAULT_EPISODES = 100
N_BOOTSTRAP = 2000


def iqm(x: np.ndarray) -> float:
    """Interquartile mean: the mean of the middle 50 % of the values (ValueError for a NaN, which a sort would
    place last, shifting the middle window)."""
    x = np.sort(np.ravel(x))
    if not x.size or np.isnan(x).any():
        raise ValueError(f"an interquartile mean needs values, none of them NaN; got {x.size} values")
    lo, hi = int(np.floor(0.25 * x.size)), int(np.ceil(0.75 * x.size))
    return float(x[lo:hi].mean())


def stratified_bootstrap_ci(scores: np.ndarray, stat, seed: int = 0) -> tuple[float, float]:
    """95 % CI of ``stat`` over a (runs x scenarios) matrix, resampling runs within every scenario."""
    rng = np.random.default_rng(seed)
    runs, tasks = scores.shape
    stats = [stat(scores[rng.integers(0, runs, size=(runs, tasks)), np.arange(tasks)]) for _ in range(N_BOOTSTRAP)]
    return float(np.percentile(stats, 2.5)), float(np.percentile(stats, 97.5))


def suite_env_id(path: Path) -> str:
    """The env id a suite file plays."""
    return make_suite(str(path), DEFAULT_EPISODES, 0).env_id


def play(spec: str, suite_name: str, out: Path, episodes: int = DEFAULT_EPISODES) -> tuple[dict, np.ndarray, int, float]:
    """Summary, per-episode relative errors (from OUT/episodes.csv), macro-slips and mean episode return
    of one agent."""
    suite = make_suite(suite_name, episodes, 0)
    summary = next(iter(evaluate([spec], suite, out, seed=0, quiet=True)["summary"].values()))
    with open(out / "episodes.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    errors = np.array([float(r["relative_error"]) for r in rows])
    mean_return = float(np.mean([float(r["episode_return"]) for r in rows]))
    return summary, errors, sum(r["macro_slip"] == "True" for r in rows), mean_return


def play_all(plays: list[tuple[str, str, Path]], jobs: int) -> list[tuple[dict, np.ndarray, int, float]]:
    """:func:`play` for each (agent spec, suite, output directory), ``jobs`` processes at a time."""
    if not plays:
        return []
    with ProcessPoolExecutor(max_workers=max(jobs, 1)) as pool:
        return list(pool.map(play, *zip(*plays)))


def candidates(run: Path) -> list[Path]:
    checkpoints = sorted(run.glob("checkpoints/ppo_*_steps.zip"), key=lambda p: int(p.stem.split("_")[1]))
    warm_start = sorted(run.glob("warm_start/*.zip"))  # the cloned policy before RL (--pretrain-episodes)
    return [p for p in (*warm_start, *checkpoints, run / "best" / MODEL_NAMES[1], run / MODEL_NAMES[0]) if p.is_file()]


def check_runs(parser: argparse.ArgumentParser, runs: list[Path], env_id: str) -> None:
    """Each of ``runs`` a directory holding at least one candidate (:func:`candidates`), every one a readable
    Stable-Baselines3 model with usable statistics and metadata (:func:`~cof_gym.agents.sb3_policy.check_model`, as
    ``cof-gym evaluate --agents ppo:PATH`` checks it) trained on ``env_id`` (its ``train_meta.json``); otherwise a
    one-line usage error naming --runs, before anything is played."""
    for run in runs:
        if not run.is_dir():
            parser.error(f"--runs: no directory {run}")
        found = candidates(run)
        if not found:
            parser.error(f"--runs: {run} holds no model (model.zip, best/best_model.zip, checkpoints/ppo_*_steps.zip "
                         "or warm_start/*.zip)")
        for model in found:
            try:
                check_model(model)
            except ValueError as error:
                parser.error(f"--runs: {' '.join(str(error).split())}")
            trained = (find_train_meta(model) or {}).get("env_id")
            if trained != env_id:
                parser.error(f"--runs: {model} was trained on {trained or 'an unknown env'}, and the grids this "
                             f"script selects and reports on are {env_id}'s (cof-gym train --env {env_id})")


def main() -> None:
    parser = Parser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", nargs="+", required=True, type=Path, help="cof-gym train output directories")
    parser.add_argument("--out", type=Path, default=Path("out/ppo_seeds"))
    parser.add_argument("--ship", action="store_true", help="copy the best-on-validation policy into the package")
    parser.add_argument("--jobs", type=positive_int, default=2, help="evaluations run in parallel (processes)")
    args = parser.parse_args()
    check_out_dir(parser, "--out", args.out)
    check_runs(parser, args.runs, suite_env_id(VALIDATION))
    args.out.mkdir(parents=True, exist_ok=True)
    jobs = [(run, k, model) for run in args.runs for k, model in enumerate(candidates(run))]
    results = play_all([(f"ppo:{m}", str(VALIDATION), args.out / f"val_{run.name}_{k}") for run, k, m in jobs],
                       args.jobs)
    scored: dict[str, list[dict]] = {run.name: [] for run in args.runs}
    for (run, _, model), (summary, _, slips, mean_return) in zip(jobs, results):
        entry = {"model": str(model), "validation_return": mean_return,
                 "validation_median": summary["median_error"]["value"], "validation_p90": summary["p90_error"]["value"],
                 "validation_macro_slips": slips}
        print(f"{run.name}: {model} validation return {mean_return:.3f} median {entry['validation_median']:.2%}"
              f" P90 {entry['validation_p90']:.2%} macro-slips {slips}")
        scored[run.name].append(entry)
    chosen = {name: {**max(entries, key=lambda c: c["validation_return"]), "candidates": entries}
              for name, entries in scored.items() if entries}
    report: dict = {"seeds": chosen, "suites": {}}
    reports = [(name, report_name) for report_name in REPORTS for name in chosen]
    played = dict(zip(reports, play_all([(f"ppo:{chosen[name]['model']}", str(REPORTS[report_name]),
                                          args.out / f"rep_{name}_{report_name}")
                                         for name, report_name in reports], args.jobs)))
    for report_name in REPORTS:
        matrix = []
        per_seed = {}
        for name in chosen:
            _, errors, slips, _ = played[(name, report_name)]
            matrix.append(errors)
            per_seed[name] = {"median": float(np.median(errors)), "p90": float(np.percentile(errors, 90)),
                              "macro_slips": slips, "episodes": int(errors.size)}
        scores = np.array(matrix)
        report["suites"][report_name] = {
            "per_seed": per_seed,
            "iqm": iqm(scores), "iqm_ci95": stratified_bootstrap_ci(scores, iqm),
            "median": float(np.median(scores)),
            "median_ci95": stratified_bootstrap_ci(scores, lambda s: float(np.median(s))),
        }
    shipped = max(chosen.items(), key=lambda kv: kv[1]["validation_return"])
    report["shipped"] = {"seed_run": shipped[0], **shipped[1]}
    (args.out / "report.json").write_text(json.dumps(report, indent=1))
    lines = ["| seed run | chosen model | validation: return / median / P90 / macro-slips | " + " | ".join(
        f"{s}: median / P90 / macro-slips" for s in report["suites"]) + " |", "|---" * (3 + len(report["suites"])) + "|"]
    for name, entry in chosen.items():
        cells = [f"{v['per_seed'][name]['median']:.1%} / {v['per_seed'][name]['p90']:.1%} / "
                 f"{v['per_seed'][name]['macro_slips']}" for v in report["suites"].values()]
        lines.append(f"| {name} | {Path(entry['model']).relative_to(Path(entry['model']).parents[1])} | "
                     f"{entry['validation_return']:.3f} / {entry['validation_median']:.1%} / "
                     f"{entry['validation_p90']:.1%} / {entry['validation_macro_slips']} | " + " | ".join(cells) + " |")
    for s, v in report["suites"].items():
        lines.append(f"\n{s}: IQM {v['iqm']:.1%} [{v['iqm_ci95'][0]:.1%}, {v['iqm_ci95'][1]:.1%}], median "
                     f"{v['median']:.1%} [{v['median_ci95'][0]:.1%}, {v['median_ci95'][1]:.1%}] "
                     "(relative error over seeds x scenarios, stratified bootstrap 95 % CI)")
    verdict = "shipped" if args.ship else "to ship with --ship"
    lines.append(f"\n{verdict} (best on the validation grid): {shipped[0]} ({shipped[1]['model']})")
    (args.out / "report.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    if args.ship:
        model = Path(shipped[1]["model"])
        SHIPPED_PPO.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(model, SHIPPED_PPO / MODEL_NAMES[0])
        shutil.copyfile(vecnormalize_path(model), SHIPPED_PPO / VECNORMALIZE_NAME)
        run = model.parent if (model.parent / META_NAME).is_file() else model.parent.parent
        shutil.copyfile(run / META_NAME, SHIPPED_PPO / META_NAME)
        (SHIPPED_PPO / "selection.json").write_text(json.dumps(report["shipped"], indent=1))
        print(f"shipped to {SHIPPED_PPO}")


if __name__ == "__main__":
    main()
