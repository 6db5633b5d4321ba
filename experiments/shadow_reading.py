"""The learned interrogator's networks reading another agent's climb (information: nothing is chosen or adopted).

An agent (``--agent``, default ``model-based-zeroed``; ``interrogator``: the learned climb itself, the reference)
plays episodes of the v2 default distribution in both vehicle configurations; a shadow copy of the shipped learned
interrogator reads every window it drives (its own actions are discarded: the host steers) and keeps its estimate
and its decisions. Per ending of the host's climb: the median / P90 relative CoF error of the host's estimate and of
the shadow's, the shadow's median predicted-headroom std over the windows (the filter's; the shipped agent's slow
probe starts at 0.08), and how many climbs the shadow would have stopped before the host did (its cautious headroom,
the filter's or a guard's after the caution, below its target of 0.1 at a window before the host's last), with the
median utilisation there (the window's largest true torque over the true saturation torque: the experiment reads it,
no agent does). Compare `experiments/own_window_fit.py`, the mirror: a family fit reading the learned climb's
windows.

    python experiments/shadow_reading.py --episodes 100 --out out/shadow_reading.md

Seeds 7,000,000 on (``--first-seed``), as own_window_fit.py: neither the validation seeds, nor the reporting ones, nor
a confirmation set. 100 episodes x 2 configurations take about 15 s on 2 cores.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from own_window_fit import ENDINGS, add_draw_options, cell, check_draw_options, play_draws, report  # noqa: E402

from cof_gym.commands.args import Parser  # noqa: E402

TARGET_HEADROOM = 0.1  # the shipped climb's target (its manifest's target_headroom)


def play(job: tuple[str, dict[str, Any], list[int]]) -> list[dict[str, Any]]:
    """The host agent on each seed in one configuration with the shadow reading its windows: how the host's climb
    ended, both signed relative errors (estimate / CoF - 1), the shadow's filter stds and whether its cautious headroom
    fell below the target before the host's last window, and the utilisation of the first window where it did."""
    import gymnasium as gym

    import cof_gym
    from cof_gym.agents.base import agent_view
    from cof_gym.agents.registry import make_agent

    host_name, config, seeds = job
    env = gym.make(cof_gym.WAGON_ENV_ID, **config)
    host, shadow = make_agent(host_name, env), make_agent("interrogator", env)
    out = []
    for seed in seeds:
        obs, info = env.reset(seed=seed)
        for agent in (host, shadow):
            agent.reset(obs, agent_view(info, False))
        utilisation = []  # each driven window's largest true torque over the saturation torque
        while True:
            action = host.act(obs, agent_view(info, False))
            shadow.act(obs, agent_view(info, False))  # reads the window just driven; its action is discarded
            elapsed = info["elapsed_s"]
            obs, _, terminated, truncated, info = env.step(action)
            if info["elapsed_s"] == elapsed:  # the host's stop: no window driven
                break
            utilisation.append(info["ground_truth"]["peak_torque_fraction"])
            if terminated or truncated:
                shadow.act(obs, agent_view(info, False))  # the last window, driven into the horizon or a runaway
                break
        cof = info["ground_truth"]["cof"]
        decisions = shadow.decisions[:-1]  # those after a window the host went on from (decision k: window k + 1)
        early = next((utilisation[k] for k, d in enumerate(decisions) if d.steering_headroom < TARGET_HEADROOM), None)
        out.append({"ended": "macro-slip" if info["macro_slip"] else "horizon" if truncated else "stop",
                    "host": info["cof_estimate"] / cof - 1.0, "shadow": shadow.estimate / cof - 1.0,
                    "stds": [d.filter_std for d in shadow.decisions],
                    "early": early})
    env.close()
    return out


def table(rows: list[dict[str, Any]], host: str) -> str:
    """Per ending of the host's climb (and all): the host's and the shadow's median / P90 error, the shadow's median
    filter std and the climbs it would have stopped earlier."""
    lines = [f"| {host}'s climbs ended by | episodes | {host}'s estimate | the shadow's estimate | the shadow's median "
             "headroom std | the shadow would have stopped earlier: climbs, median utilisation there |",
             "|---|---|---|---|---|---|"]
    for label, ending in (*((e, e) for e in (*ENDINGS, "macro-slip")), ("all", None)):
        sel = [r for r in rows if ending is None or r["ended"] == ending]
        if not sel:
            continue
        stds = [s for r in sel for s in r["stds"]]
        early = [r["early"] for r in sel if r["early"] is not None]
        there = f", {np.median(early):.0%}" if early else ""
        lines.append(f"| {label} | {len(sel)} | {cell([r['host'] for r in sel])} | "
                     f"{cell([r['shadow'] for r in sel])} | {np.median(stds):.2f} | {len(early)}{there} |")
    return "\n".join(lines)


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("--agent", default="model-based-zeroed",
                        help="the host: an agent of the registry that reads no ground truth (interrogator: the shadow "
                        "reads the learned climb's own windows, a reference)")
    add_draw_options(parser, episodes=100)
    args = parser.parse_args()
    check_draw_options(parser, args)
    from cof_gym.agents import registry

    entry = registry.AGENTS.get(args.agent)
    if entry is None or entry.oracle or entry.argument is not None and not entry.shipped_available():
        parser.error(f"--agent must be an agent of the registry that reads no ground truth, got {args.agent!r}")
    report(table(play_draws(play, args, args.agent), args.agent), args.out)

if __name__ == "__main__":
    main()
