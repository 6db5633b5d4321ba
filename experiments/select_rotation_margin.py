"""Choose how far the phase rule or the learned interrogator modulates from the wheelset's rotation harmonics
(``phase-rule-rotation``, ``interrogator-rotation``: :func:`cof_gym.agents.phase_rule.rotation_clear_frequency`) on
validation seeds only.

A speed probe whose target wheel runs out reads the wheelset's speed with a ripple at the rotation frequency
``v / (2 pi r)`` (and, through the period method, a little at twice it). The rotation lock-in (env argument
``lock_in="rotation"``) fits both harmonics beside the tone, but a harmonic within about ``1 / T`` of the tone (T the
window, 0.6 s) it cannot tell from the tone and leaves out, so the ripple leaks into the lag; near 5 Hz that is 12-17
m/s (the rotation) and 6-8 m/s (twice it, where the ripple is of the runout's second order and negligible). A train
knows its speed and its nominal wheel radius, so an agent can choose its modulation frequency away from the rotation
frequency (:data:`cof_gym.agents.phase_rule.ROTATION_HARMONICS`): the margin, in Hz (and for the phase rule the side it
moves to), is chosen here.

Validation set (the seeds of ``select_phase_rule.py``: never the default evaluate suite, seeds 0-59, nor a held-out
grid): the v2 wagon's seeds 100000-100119 as drawn, with and without the paper's counter torque, each played with the
encoder read from 100 pulses per revolution and a runout of 0.05 % (reset options; the draws give neither) through the
rotation lock-in (the setting the margin is for, ranked: fewest macro-slips, then the median, then the P90), through
the plain lock-in, and with the drawn (continuous) encoder, where any margin only moves the frequency and must not
cost (information). Every other parameter is the validation-chosen agent's.

    python experiments/select_rotation_margin.py [--agent phase-rule|interrogator] [--workers 2] [--quick]
                                                 [--out PATH.json]

Runs on 2 cores in about 9 min for the phase rule (13 candidates; 558 s in session 84) and 8 min for the
interrogator (5 candidates; 454 s); ``--quick``: a fifth of the seeds, for a smoke test.
"""

from __future__ import annotations

import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

from selection import error_summary
from script_checks import check_out_file

from cof_gym.commands.args import Parser, positive_int

ENV_ID = "CofGym/TorqueInterrogation-v2"
CONFIGS = ({}, {"counter_torque": True})  # the v2 wagon, then with the paper's counter torque
FIRST_SEED, SEEDS = 100000, 120
# per agent, the (margin, side) candidates of rotation_clear_frequency; (0, "nearest"): the agent as chosen (5 Hz);
# the interrogator's climb moves to the nearest side only (ClimbParameters.rotation_margin_hz)
CANDIDATES: dict[str, tuple[tuple[float, str], ...]] = {
    "phase-rule": ((0.0, "nearest"),) + tuple((margin, side) for side in ("nearest", "below", "above")
                                              for margin in (0.75, 1.0, 1.25, 1.5)),
    "interrogator": tuple((margin, "nearest") for margin in (0.0, 0.75, 1.0, 1.25, 1.5)),
}
RUNOUT = {"encoder_pulses_per_rev": 100, "encoder_runout": 0.0005}
# (label, reset options, env arguments); the first is ranked
ENCODERS: tuple[tuple[str, dict[str, Any], dict[str, Any]], ...] = (
    ("runout, rotation lock-in", RUNOUT, {"lock_in": "rotation"}),
    ("runout, plain lock-in", RUNOUT, {}),
    ("as drawn", {}, {}),
)


def make_agent(agent: str, env, margin_hz: float, side: str):
    """``agent`` (a key of CANDIDATES) as chosen, modulating ``margin_hz`` clear of the rotation's harmonics."""
    from dataclasses import replace

    from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR, interrogator_for, manifest_climb
    from cof_gym.agents.phase_rule import PhaseRule

    if agent == "phase-rule":
        return PhaseRule(env.unwrapped.limits, rotation_margin_hz=margin_hz, rotation_side=side)
    params = replace(manifest_climb(SHIPPED_INTERROGATOR), rotation_margin_hz=margin_hz or None)
    return interrogator_for(env, SHIPPED_INTERROGATOR, params=params)


def play(agent: str, candidate: int, encoder: int, config: int, seeds: int) -> list[tuple[float, bool]]:
    """(relative error, macro-slip) of every scored episode ``agent`` with its ``candidate``-th of CANDIDATES plays on
    the validation seeds with the ``encoder``-th of ENCODERS in the ``config``-th of CONFIGS."""
    import gymnasium as gym

    import cof_gym  # noqa: F401  (registers the envs)
    from cof_gym.commands.evaluate_episodes import run_episode

    _, options, env_kwargs = ENCODERS[encoder]
    env = gym.make(ENV_ID, **CONFIGS[config], **env_kwargs)
    player = make_agent(agent, env, *CANDIDATES[agent][candidate])
    records = [run_episode(env, player, seed, dict(options), i)
               for i, seed in enumerate(range(FIRST_SEED, FIRST_SEED + seeds))]
    env.close()
    return [(r.relative_error, r.macro_slip) for r in records if r.scored]


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("--agent", choices=tuple(CANDIDATES), default="phase-rule")
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--quick", action="store_true", help="a fifth of the seeds (smoke test)")
    parser.add_argument("--out", type=Path, help="default: experiments/results/select_rotation_margin_AGENT.json")
    args = parser.parse_args()
    out = args.out or Path(f"experiments/results/select_rotation_margin_{args.agent}.json")
    check_out_file(parser, "--out", out)
    candidates = CANDIDATES[args.agent]
    t0 = time.time()
    seeds = SEEDS // 5 if args.quick else SEEDS
    jobs = [(args.agent, m, e, c, seeds) for m in range(len(candidates)) for e in range(len(ENCODERS))
            for c in range(len(CONFIGS))]
    with ProcessPoolExecutor(args.workers) as pool:
        played = list(pool.map(play, *zip(*jobs)))
    rows = []
    for m, (margin_hz, side) in enumerate(candidates):
        row: dict[str, Any] = {"rotation_margin_hz": margin_hz, "rotation_side": side}
        for e, (label, _, _) in enumerate(ENCODERS):
            results = [p for (_, jm, je, _, _), part in zip(jobs, played) if jm == m and je == e for p in part]
            row[label] = error_summary([x[0] for x in results], [x[1] for x in results])
        rows.append(row)
    ranked = ENCODERS[0][0]
    best = min(rows, key=lambda r: (r[ranked]["macro_slips"], r[ranked]["median"], r[ranked]["p90"]))
    print(f"{args.agent}: {len(candidates)} candidates x {len(ENCODERS)} encoders on {2 * seeds} validation episodes "
          f"in {time.time() - t0:.0f} s; ranked on '{ranked}': best margin {best['rotation_margin_hz']:g} Hz, "
          f"{best['rotation_side']}")
    print("| margin, Hz | side | " + " | ".join(label for label, _, _ in ENCODERS) + " |\n"
          + "|---" * (len(ENCODERS) + 2) + "|")
    for r in rows:
        cells = [f"{r[label]['median']:.1%} / {r[label]['p90']:.1%} / {r[label]['macro_slips']}"
                 for label, _, _ in ENCODERS]
        print(f"| {r['rotation_margin_hz']:g} | {r['rotation_side']} | " + " | ".join(cells) + " |")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"best": best, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
