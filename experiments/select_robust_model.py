"""Choose the robust-model agent's parameters (cof_gym/agents/robust_model.py) on validation only.

Validation set (never the default evaluate suite, seeds 0-59, nor experiments/suites/v2_heldout_grid.json):
the 72 episodes of experiments/suites/v2_validation_grid.json and seeds 100000-100119 of the default v2
wagon distribution (CofGym/TorqueInterrogation-v2), 192 episodes.

The climb (probe amplitude and step, the knee's jump threshold) and the bracketing (how many windows,
its jump threshold) decide the windows; the knee's place in the final bracket (``knee_weight``) and the
``correction`` only decide the reported number. So every climb/bracketing combination is played once,
and every (knee_weight, correction) is computed from the agent's final state
(:meth:`~cof_gym.agents.robust_model.RobustModel.estimate_with`, exactly what the agent would have
reported). Ranking: fewest macro-slips, then median + P90 of the relative error (both count: the goal
is to beat the phase rule on both). The phase rule (its shipped defaults) is played on the same
episodes as the reference row.

    python experiments/select_robust_model.py [--workers 2] [--quick] [--corrected-se] [--out PATH.json]

Runs on 2 cores in about 4 minutes (232-241 s in session 59; ``--quick``: a fifth of the seeds, for a smoke
test). ``--corrected-se`` selects for the model that reads the lag's SE for an autocorrelated speed residual
(``phase_lag_se_corrected_deg``, ``RobustModel.corrected_se``: ``robust-model-ar1``) on the same episodes (the
reference row stays the shipped phase rule).
"""

from __future__ import annotations

import itertools
import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

from selection import best_per_group, error_summary, group_line
from script_checks import check_out_file

from cof_gym.commands.args import Parser, positive_int

VALIDATION_GRID = Path(__file__).resolve().parent / "suites" / "v2_validation_grid.json"  # wherever run from
DEFAULT_SEEDS = (100000, 120)  # first seed, count, of the default v2 distribution
# (probe amplitude / DC, largest step / DC, largest step / amplitude)
CLIMBS: tuple[dict[str, float], ...] = tuple(
    {"amplitude_ratio": p, "max_step": s, "probe_step": g} for p, s, g in ((0.4, 0.25, 0.8), (0.5, 0.3, 0.67))
)
KNEES: tuple[dict[str, float], ...] = tuple({"jump_deg": j} for j in (4.0, 6.0))
REFINES: tuple[dict[str, float], ...] = (
    {"refine_windows": 0, "refine_jump_deg": 4.0},
    {"refine_windows": 2, "refine_jump_deg": 4.0},
    {"refine_windows": 3, "refine_jump_deg": 2.0},
    {"refine_windows": 3, "refine_jump_deg": 4.0},
)
KNEE_WEIGHTS = (0.0, 0.25, 0.5, 0.75, 1.0)
CORRECTIONS = tuple(round(0.9 + 0.025 * i, 3) for i in range(11))  # 0.9 ... 1.15


def episodes(quick: bool) -> list[tuple[str, int, dict[str, Any]]]:
    """(label, seed, reset options) of every validation episode."""
    grid = json.loads(VALIDATION_GRID.read_text())["episodes"]
    first, n = DEFAULT_SEEDS
    out = [("v2 validation grid", e["seed"], e.get("options") or {}) for e in grid]
    out += [("v2 seeds 100000+", s, {}) for s in range(first, first + n)]
    return out[::5] if quick else out


def play(job: tuple[str, dict[str, Any], list[tuple[str, int, dict[str, Any]]], bool]) -> list[dict[str, Any]]:
    """One agent configuration on every episode: per episode the setting, CoF, macro-slip and the
    estimate for every (knee_weight, correction) (or the agent's own for the phase rule)."""
    import gymnasium as gym

    import cof_gym  # noqa: F401  (registers the envs)
    from cof_gym.agents.phase_rule import PhaseRule
    from cof_gym.agents.robust_model import RobustModel
    from cof_gym.task.interface import decode_action

    kind, params, eps, corrected_se = job
    env = gym.make("CofGym/TorqueInterrogation-v2")
    limits = env.unwrapped.limits
    out = []
    for label, seed, options in eps:
        obs, info = env.reset(seed=seed, options=options or None)
        agent = PhaseRule(limits) if kind == "phase-rule" else RobustModel(limits, **params, corrected_se=corrected_se)
        agent.reset(obs, {"measurement": info["measurement"]})
        slipped = False
        while True:
            action = agent.act(obs, {"measurement": info["measurement"]})
            if decode_action(action, limits).stop:
                break
            obs, _, terminated, truncated, info = env.step(action)
            slipped |= bool(info["macro_slip"])
            if terminated or truncated:
                break
        row = {"setting": label, "cof": float(info["ground_truth"]["cof"]), "slipped": slipped}
        if kind == "phase-rule":
            row["estimate"] = decode_action(action, limits).cof_estimate
        else:
            row["estimates"] = {(w, c): agent.estimate_with(w, c) for w in KNEE_WEIGHTS for c in CORRECTIONS}
        out.append(row)
    env.close()
    return out


def summary(rows: list[dict[str, Any]], key=None) -> dict[str, Any]:
    return error_summary([abs((r["estimate"] if key is None else r["estimates"][key]) / r["cof"] - 1.0) for r in rows],
                         [r["slipped"] for r in rows])


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--quick", action="store_true", help="a fifth of the episodes (smoke test)")
    parser.add_argument("--corrected-se", action="store_true",
                        help="select for the model reading the lag's SE for an autocorrelated residual "
                        "(robust-model-ar1)")
    parser.add_argument("--out", type=Path, default=Path("experiments/results/select_robust_model.json"))
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    t0 = time.time()
    eps = episodes(args.quick)
    configs = [{**c, **k, **r} for c, k, r in itertools.product(CLIMBS, KNEES, REFINES)]
    jobs = [("phase-rule", {}, eps, False)] + [("robust-model", c, eps, args.corrected_se) for c in configs]
    with ProcessPoolExecutor(args.workers) as pool:
        played = list(pool.map(play, jobs))
    reference = summary(played[0])
    rows = []
    for params, recs in zip(configs, played[1:]):
        for w, c in itertools.product(KNEE_WEIGHTS, CORRECTIONS):
            s = summary(recs, (w, c))
            per = {}
            for r in recs:
                per.setdefault(r["setting"], []).append(r)
            rows.append({"params": {**params, "knee_weight": w, "correction": c}, **s,
                         "settings": {k: summary(v, (w, c)) for k, v in per.items()}})
    rows.sort(key=lambda r: (r["macro_slips"], r["median"] + r["p90"]))
    best = rows[0]
    print(f"{len(rows)} settings on {len(eps)} validation episodes in {time.time() - t0:.0f} s")
    print("best:", json.dumps(best["params"]))
    print("| agent, setting | episodes | median | P90 | macro-slips |\n|---|---|---|---|---|")
    print(f"| phase-rule (shipped), all | {reference['episodes']} | {reference['median']:.1%} | "
          f"{reference['p90']:.1%} | {reference['macro_slips']} |")
    for s, v in best["settings"].items():
        print(f"| robust-model, {s} | {v['episodes']} | {v['median']:.1%} | {v['p90']:.1%} | {v['macro_slips']} |")
    print(f"| robust-model, all | {best['episodes']} | {best['median']:.1%} | {best['p90']:.1%} | "
          f"{best['macro_slips']} |")
    print("best (knee_weight, correction) per climb and bracketing (macro-slips / median / P90):")
    per_config = best_per_group(rows, configs)
    print("\n".join(group_line(params, r) for params, r in zip(configs, per_config)))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"phase_rule": reference, "best": rows[:20], "per_config": per_config}, indent=1))


if __name__ == "__main__":
    main()
