"""Choose whether ``model-based-zeroed`` also stops on the phase rule's jump test, at what jump and with what
estimate, on validation only.

The issue's third example of a model-based agent built for uncertain sensors and laws: a stop rule that does not
trust the creepage alone. :class:`~cof_gym.agents.model_based.ModelBasedAgent`'s ``knee_jump_deg`` adds the phase
rule's jump test (the lag of a window over the previous one's by more than the jump beyond 2 standard errors) to its
stops, reporting there the fit's estimate or (``knee_low_factor``) the low end of the fit's interval times a factor;
no jump test is the agent of session 73. Played as `cof-gym evaluate` plays ``model-based-zeroed`` (the creepage zeroed
at the reset window, the runaway estimate and the crest ceiling as registered) on the validation episodes of
``select_robust_model.py`` (the 72 of experiments/suites/v2_validation_grid.json and seeds 100000-100119 of the
default v2 distribution: never the evaluate suite nor a held-out grid), ranked as there: fewest macro-slips, then
median + P90 of the relative error.

    python experiments/select_model_based.py [--workers 2] [--quick] [--out PATH.json]   # out/select_model_based.json

Runs on 2 cores in about 2.5 minutes (137 s in session 74); ``--quick``: a fifth of the episodes (a smoke test).
Writes ``--out`` (JSON) and its table beside it (``--out`` with ``.md``).
The chosen setting and its table are in :mod:`cof_gym.agents.zeroed` (``model-based-zeroed-knee``).
"""

from __future__ import annotations

import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

from script_checks import check_out_file
from select_robust_model import episodes
from selection import error_summary

from cof_gym.commands.args import Parser, positive_int

AGENT = "model-based-zeroed"
KNEE_JUMPS_DEG = (2.0, 4.0, 6.0, 8.0)
KNEE_LOW_FACTORS = (None, 1.0, 1.025, 1.05)  # None: the fit's estimate at a jump stop
# (knee_jump_deg, knee_low_factor) of every candidate; the first, no jump test, is the agent of session 73
SETTINGS: tuple[dict[str, float | None], ...] = ({"knee_jump_deg": None, "knee_low_factor": None},) + tuple(
    {"knee_jump_deg": j, "knee_low_factor": f} for j in KNEE_JUMPS_DEG for f in KNEE_LOW_FACTORS)


def play(job: tuple[dict[str, float | None], list[tuple[str, int, dict[str, Any]]]]) -> list[dict[str, Any]]:
    """``model-based-zeroed`` with one setting on every episode: per episode the setting, the relative
    error it scored and whether it macro-slipped."""
    import gymnasium as gym

    from cof_gym.agents.registry import AGENTS, as_registered
    from cof_gym.agents.zeroed import model_based_zeroed
    from cof_gym.commands.evaluate_episodes import run_episode

    setting, eps = job
    env = gym.make("CofGym/TorqueInterrogation-v2")
    limits = env.unwrapped.limits
    agent = as_registered(AGENTS[AGENT], model_based_zeroed(limits, **setting), limits)
    out = []
    for i, (label, seed, options) in enumerate(eps):
        r = run_episode(env, agent, seed, options, i)
        out.append({"setting": label, "error": r.relative_error, "slipped": r.macro_slip, "ended": r.ended})
    env.close()
    return out


def summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    return error_summary([r["error"] for r in rows], [r["slipped"] for r in rows])


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--quick", action="store_true", help="a fifth of the episodes (smoke test)")
    parser.add_argument("--out", type=Path, default=Path("out/select_model_based.json"))
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    t0 = time.time()
    eps = episodes(args.quick)
    with ProcessPoolExecutor(args.workers) as pool:
        played = list(pool.map(play, [(setting, eps) for setting in SETTINGS]))
    rows = []
    for setting, recs in zip(SETTINGS, played):
        per: dict[str, list] = {}
        for r in recs:
            per.setdefault(r["setting"], []).append(r)
        rows.append({"params": setting, **summary(recs), "settings": {k: summary(v) for k, v in per.items()}})
    ranked = sorted(rows, key=lambda r: (r["macro_slips"], r["median"] + r["p90"]))
    text = table(ranked, len(eps))
    print(f"{time.time() - t0:.0f} s\n{text}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"agent": AGENT, "ranked": ranked}, indent=1))
    args.out.with_suffix(".md").write_text(text + "\n")


def table(ranked: list[dict[str, Any]], episodes: int) -> str:
    """The ranked settings as markdown (best first), per setting of the episodes too, with a first line that says
    which was chosen."""
    settings = list(ranked[0]["settings"])
    lines = [f"{len(ranked)} settings of {AGENT} on {episodes} validation episodes; chosen:",
             f"knee_jump_deg {ranked[0]['params']['knee_jump_deg']}, knee_low_factor "
             f"{ranked[0]['params']['knee_low_factor']} (None: no jump test / the fit's estimate)", "",
             "| knee_jump_deg | knee_low_factor | episodes | median | P90 | macro-slips | "
             + " | ".join(f"{s}: median / P90 / macro-slips" for s in settings) + " |",
             "|---" * (6 + len(settings)) + "|"]
    for r in ranked:
        cells = " | ".join(f"{v['median']:.1%} / {v['p90']:.1%} / {v['macro_slips']}" for v in r["settings"].values())
        lines.append(f"| {r['params']['knee_jump_deg']} | {r['params']['knee_low_factor']} | {r['episodes']} | "
                     f"{r['median']:.1%} | {r['p90']:.1%} | {r['macro_slips']} | {cells} |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
