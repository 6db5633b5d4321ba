"""Choose how far the phase rule or the learned interrogator modulates from the wheelset's rotation frequency
(``phase-rule-rotation``, ``interrogator-rotation``: :func:`cof_gym.agents.phase_rule.rotation_clear_frequency`) on
validation seeds only.

A speed probe whose target wheel runs out reads the wheelset's speed with a ripple at the rotation frequency
``v / (2 pi r)`` (and, through the period method, a little at twice it). The rotation lock-in (env argument
``lock_in="rotation"``) fits both harmonics beside the tone, but a harmonic within about ``1 / T`` of the tone (T the
window, 0.6 s) it cannot tell from the tone and leaves out, so the ripple leaks into the lag; near 5 Hz that is 12-17
m/s (the rotation) and 6-8 m/s (twice it, where the ripple is of the runout's second order and negligible). A train
knows its speed and its nominal wheel radius, so an agent can choose its modulation frequency away from the rotation
frequency (:data:`cof_gym.agents.phase_rule.ROTATION_HARMONICS`): the margin, in Hz, and the side it moves to are
chosen here (the interrogator's side since session 85; session 84 played its nearest side only).

Validation set (the seeds of ``select_phase_rule.py``: never the default evaluate suite, seeds 0-59, nor a held-out
grid): the v2 wagon's seeds 100000-100119 as drawn, with and without the paper's counter torque, each played with the
encoder read from 100 pulses per revolution and a runout of 0.05 % (reset options; the draws give neither) through the
rotation lock-in (the setting the margin is for, ranked: fewest macro-slips, then the median, then the P90), through
the plain lock-in, and with the drawn (continuous) encoder, where any margin only moves the frequency and must not
cost (information). Every other parameter is the validation-chosen agent's.

``--gate`` chooses instead, at the margin and side chosen above (the registered agents'), how clearly the reset
window must read a ripple for the frequency to move (``rotation_ripple_max_se_deg``: the rotation lock-in's phase SE
of the first harmonic at most this; a harmonic it cannot read, at the tone's frequency, still moves it:
:func:`cof_gym.agents.phase_rule.ripple_possible`), on the same seeds with the runout and with the drawn encoder,
both through the rotation lock-in, ranked by the macro-slips of both, then the sum of their P90s, then of their
medians (the plain lock-in reads no ripple, so there every gate moves as the ungated agent does).

    python experiments/select_rotation_margin.py [--agent phase-rule|interrogator] [--gate] [--workers 2] [--quick]
                                                 [--out PATH.json]

Runs on 2 cores in about 9 min for the phase rule (13 candidates; 558 s in session 84) and 16 min for the interrogator
(the same 13; 984 s in session 85, which added its sides); with ``--gate`` (6 candidates, 2 encoders) in about 3 and 5
min (198 s and 338 s in session 85); ``--quick``: a fifth of the seeds, for a smoke test.
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
# the (margin, side) candidates of rotation_clear_frequency, for either agent; (0, "nearest"): the agent as chosen
# (5 Hz); the interrogator's sides since session 85 (session 84 played its nearest side only)
CANDIDATES: tuple[tuple[float, str], ...] = ((0.0, "nearest"),) + tuple(
    (margin, side) for side in ("nearest", "below", "above") for margin in (0.75, 1.0, 1.25, 1.5))
AGENTS = ("phase-rule", "interrogator")
RUNOUT = {"encoder_pulses_per_rev": 100, "encoder_runout": 0.0005}
ROTATION = {"lock_in": "rotation"}
# (label, reset options, env arguments); the first is ranked
ENCODERS: tuple[tuple[str, dict[str, Any], dict[str, Any]], ...] = (
    ("runout, rotation lock-in", RUNOUT, ROTATION),
    ("runout, plain lock-in", RUNOUT, {}),
    ("as drawn", {}, {}),
)
# --gate: the candidates of rotation_ripple_max_se_deg (deg; 180: no gate) and the encoders they play (all ranked)
GATE_MAX_SE_DEG = (180.0, 30.0, 20.0, 15.0, 10.0, 5.0)
GATE_ENCODERS: tuple[tuple[str, dict[str, Any], dict[str, Any]], ...] = (
    ("runout, rotation lock-in", RUNOUT, ROTATION),
    ("as drawn, rotation lock-in", {}, ROTATION),
)


def chosen_margin(agent: str) -> tuple[float, str]:
    """The registered rotation agent's margin (Hz) and side."""
    from cof_gym.agents.interrogator.agent import INTERROGATOR_ROTATION_MARGIN_HZ, INTERROGATOR_ROTATION_SIDE
    from cof_gym.agents.phase_rule import ROTATION_MARGIN_HZ, ROTATION_SIDE

    if agent == "phase-rule":
        return ROTATION_MARGIN_HZ, ROTATION_SIDE
    return INTERROGATOR_ROTATION_MARGIN_HZ, INTERROGATOR_ROTATION_SIDE


def candidates_of(agent: str, gate: bool) -> tuple[tuple[float, str, float], ...]:
    """(margin Hz, side, ripple gate deg) of every candidate: CANDIDATES ungated, or with ``gate`` GATE_MAX_SE_DEG at
    the chosen margin and side."""
    if gate:
        return tuple((*chosen_margin(agent), max_se) for max_se in GATE_MAX_SE_DEG)
    return tuple((margin, side, GATE_MAX_SE_DEG[0]) for margin, side in CANDIDATES)


def make_agent(agent: str, env, margin_hz: float, side: str, max_se_deg: float):
    """``agent`` (of AGENTS) as chosen, modulating ``margin_hz`` clear of the rotation frequency where the
    reset window reads its ripple's phase to within ``max_se_deg`` (or not at all)."""
    from dataclasses import replace

    from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR, interrogator_for, manifest_climb
    from cof_gym.agents.phase_rule import PhaseRule

    if agent == "phase-rule":
        return PhaseRule(env.unwrapped.limits, rotation_margin_hz=margin_hz, rotation_side=side,
                         rotation_ripple_max_se_deg=max_se_deg)
    params = replace(manifest_climb(SHIPPED_INTERROGATOR), rotation_margin_hz=margin_hz or None, rotation_side=side,
                     rotation_ripple_max_se_deg=max_se_deg)
    return interrogator_for(env, SHIPPED_INTERROGATOR, params=params)


def play(agent: str, candidate: tuple[float, str, float], encoder: tuple[str, dict, dict], config: int,
         seeds: int) -> list[tuple[float, bool]]:
    """(relative error, macro-slip) of every scored episode ``agent`` with ``candidate`` (candidates_of) plays on the
    validation seeds with ``encoder`` (label, reset options, env arguments) in the ``config``-th of CONFIGS."""
    import gymnasium as gym

    import cof_gym  # noqa: F401  (registers the envs)
    from cof_gym.commands.evaluate_episodes import run_episode

    _, options, env_kwargs = encoder
    env = gym.make(ENV_ID, **CONFIGS[config], **env_kwargs)
    player = make_agent(agent, env, *candidate)
    records = [run_episode(env, player, seed, dict(options), i)
               for i, seed in enumerate(range(FIRST_SEED, FIRST_SEED + seeds))]
    env.close()
    return [(r.relative_error, r.macro_slip) for r in records if r.scored]


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("--agent", choices=AGENTS, default="phase-rule")
    parser.add_argument("--gate", action="store_true", help="choose the ripple gate at the chosen margin instead")
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--quick", action="store_true", help="a fifth of the seeds (smoke test)")
    parser.add_argument("--out", type=Path,
                        help="default: experiments/results/select_rotation_margin_AGENT[_gate].json")
    args = parser.parse_args()
    out = args.out or Path(f"experiments/results/select_rotation_margin_{args.agent}{'_gate' * args.gate}.json")
    check_out_file(parser, "--out", out)
    candidates, encoders = candidates_of(args.agent, args.gate), GATE_ENCODERS if args.gate else ENCODERS
    t0 = time.time()
    seeds = SEEDS // 5 if args.quick else SEEDS
    jobs = [(m, e, c) for m in range(len(candidates)) for e in range(len(encoders)) for c in range(len(CONFIGS))]
    with ProcessPoolExecutor(args.workers) as pool:
        played = list(pool.map(play, *zip(*[(args.agent, candidates[m], encoders[e], c, seeds) for m, e, c in jobs])))
    rows = []
    for m, (margin_hz, side, max_se_deg) in enumerate(candidates):
        row: dict[str, Any] = {"rotation_margin_hz": margin_hz, "rotation_side": side,
                               "rotation_ripple_max_se_deg": max_se_deg}
        for e, (label, _, _) in enumerate(encoders):
            results = [p for (jm, je, _), part in zip(jobs, played) if jm == m and je == e for p in part]
            row[label] = error_summary([x[0] for x in results], [x[1] for x in results])
        rows.append(row)
    ranked = [label for label, _, _ in encoders] if args.gate else [encoders[0][0]]
    order = ("macro_slips", "p90", "median") if args.gate else ("macro_slips", "median", "p90")
    best = min(rows, key=lambda r: tuple(sum(r[label][key] for label in ranked) for key in order))
    print(f"{args.agent}: {len(candidates)} candidates x {len(encoders)} encoders on {2 * seeds} validation episodes "
          f"in {time.time() - t0:.0f} s; ranked on {ranked}: best margin {best['rotation_margin_hz']:g} Hz, "
          f"{best['rotation_side']}, ripple gate {best['rotation_ripple_max_se_deg']:g} deg")
    print("| margin, Hz | side | ripple gate, deg | " + " | ".join(label for label, _, _ in encoders) + " |\n"
          + "|---" * (len(encoders) + 3) + "|")
    for r in rows:
        cells = [f"{r[label]['median']:.1%} / {r[label]['p90']:.1%} / {r[label]['macro_slips']}"
                 for label, _, _ in encoders]
        print(f"| {r['rotation_margin_hz']:g} | {r['rotation_side']} | {r['rotation_ripple_max_se_deg']:g} | "
              + " | ".join(cells) + " |")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"best": best, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
