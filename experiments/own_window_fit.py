"""What a family fit reads from the learned agent's own climb (information: nothing is chosen or adopted).

The shipped interrogator plays episodes of the v2 default distribution in both vehicle configurations; after each
episode its driven windows, the creepage zeroed at the reset window (``cof_gym/agents/zeroed.py``: the offset read where
no torque acts) and the CoA's rising points kept as :class:`~cof_gym.task.creep_fit.ClimbRecord` keeps them, are
fitted by the zeroed model-based agent's fit (Polach's and Shen-Hedrick-Elkins' shapes,
:func:`~cof_gym.task.creep_fit.fit_peak`), once on each window's mean CoA and creepage and once reading each window's
CoA swing over its modulation cycle (``swing``: half the spread of the force sensors' 16 phase bins; the climb
modulates by 40 % of its DC torque, so a window's mean creepage is the cycle mean of the curve's, not its value at the
mean CoA). Per ending of the climb (its own stop, the horizon), the median / P90 relative CoF error of the learned
agent's estimate and of the two fits: does a classical reading of the same windows measure closer than the learned one?

    python experiments/own_window_fit.py --episodes 200 --out out/own_window_fit.md

Seeds 7,000,000 on (``--first-seed``): neither the validation seeds, nor the reporting ones, nor a confirmation set.
200 episodes x 2 configurations take about 45 s on 2 cores.
"""

from __future__ import annotations

import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any, Callable

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from script_checks import check_out_file  # noqa: E402
from train_interrogator import CONFIGS  # noqa: E402

from cof_gym.commands.args import MAX_SEED, Parser, positive_int, seed_int  # noqa: E402

ESTIMATES = {"learned": "the learned agent's estimate", "fit_mean": "fit of the windows' means",
             "fit_swing": "fit reading each window's CoA swing"}
ENDINGS = ("stop", "horizon")


Window = tuple[float, float, float, float, float]  # CoA, zeroed creepage, speed (m/s), CoA swing, DC torque (N m)


def rising_windows(windows: list[Window]) -> list[Window]:
    """The windows whose points a :class:`~cof_gym.task.creep_fit.ClimbRecord` keeps (a CoA that fell under a torque
    that did not is off the branch) and fits (positive CoA and creepage)."""
    from cof_gym.task.creep_fit import ClimbRecord

    record = ClimbRecord()
    kept = [w for w in windows if not record.add(w[0], w[1], w[2], w[4])]
    return [w for w in kept if w[0] > 0 and w[1] > 0]


def play(job: tuple[dict[str, Any], list[int]]) -> list[dict[str, Any]]:
    """The interrogator on each seed in one configuration: how the climb ended and the signed relative error
    (estimate / CoF - 1) of its estimate and of both fits of its windows."""
    import gymnasium as gym

    import cof_gym
    from cof_gym.agents.base import agent_view
    from cof_gym.agents.registry import make_agent
    from cof_gym.task.creep_fit import MIN_FIT_POINTS, SHAPE_FAMILIES, fit_peak
    from cof_gym.task.interface import window_reading

    config, seeds = job
    env = gym.make(cof_gym.WAGON_ENV_ID, **config)
    agent = make_agent("interrogator", env)
    out = []
    for seed in seeds:
        obs, info = env.reset(seed=seed)
        agent.reset(obs, agent_view(info, False))
        offset = window_reading(obs, "creepage_measured")  # the reset window: no torque, no creep
        windows = []
        while True:
            elapsed = info["elapsed_s"]
            obs, _, terminated, truncated, info = env.step(agent.act(obs, agent_view(info, False)))
            m = info["measurement"]
            if m["torque_mean_nm"] > 0.0 and info["elapsed_s"] > elapsed:  # a window was driven (a stop drives none)
                windows.append((m["coa_measured"], (m["creepage_measured"] - offset) / (1.0 + offset),
                                m["speed_measured_m_s"], 0.5 * (m["coa_cycle_max"] - m["coa_cycle_min"]),
                                m["torque_mean_nm"]))
            if terminated or truncated:
                break
        cof = info["ground_truth"]["cof"]
        ended = "macro-slip" if info["macro_slip"] else "horizon" if truncated else "stop"
        row = {"ended": ended, "learned": info["cof_estimate"] / cof - 1.0}
        points = rising_windows(windows)
        if len(points) >= MIN_FIT_POINTS:
            coa, creepage, speed, swing, _ = (np.array(x) for x in zip(*points))
            for name, cycle in (("fit_mean", None), ("fit_swing", swing)):
                fit = fit_peak(coa, creepage, float(np.median(speed)), families=SHAPE_FAMILIES, swing=cycle)
                row[name] = fit.estimate / cof - 1.0
        out.append(row)
    env.close()
    return out


def cell(errors: list[float]) -> str:
    e = np.abs(np.asarray(errors))
    return f"{np.median(e):.1%} / {np.percentile(e, 90):.1%}" if e.size else "-"


def table(rows: list[dict[str, Any]]) -> str:
    """Median / P90 relative error of each estimate per ending (the episodes with a fit: at least three points)."""
    lines = ["| climbs ended by | episodes | " + " | ".join(ESTIMATES.values()) + " |",
             "|---" * (2 + len(ESTIMATES)) + "|"]
    for label, ending in (*((e, e) for e in ENDINGS), ("all", None)):
        sel = [r for r in rows if (ending is None or r["ended"] == ending) and "fit_swing" in r]
        lines.append(f"| {label} | {len(sel)} | " + " | ".join(cell([r[k] for r in sel]) for k in ESTIMATES) + " |")
    unfit = sum("fit_swing" not in r for r in rows)
    slips = sum(r["ended"] == "macro-slip" for r in rows)
    lines += ["", f"{len(rows)} episodes, {slips} of them macro-slips; {unfit} with fewer than three rising windows "
              "have no fit and are left out"]
    return "\n".join(lines)


def add_draw_options(parser: Parser, episodes: int) -> None:
    """``--episodes``, ``--first-seed``, ``--workers`` and ``--out``: the draws both configurations play and where the
    table goes (this script's and ``shadow_reading.py``'s)."""
    parser.add_argument("--episodes", type=positive_int, default=episodes, help="seeds per vehicle configuration")
    parser.add_argument("--first-seed", type=seed_int, default=7_000_000)
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--out", type=Path, default=None, help="write the table (markdown) here too")


def check_draw_options(parser: Parser, args: Any) -> None:
    """The draws' last seed within what an episode seed may be (``parser.error`` naming ``--first-seed``), and
    ``--out`` writable, before anything is played."""
    last = args.first_seed + args.episodes - 1
    if last > MAX_SEED:
        parser.error(f"--first-seed: the last draw's seed {last} is beyond {MAX_SEED}")
    check_out_file(parser, "--out", args.out)


def play_draws(play: Callable[[tuple], list[dict[str, Any]]], args: Any, *lead: Any) -> list[dict[str, Any]]:
    """Every row of ``play((*lead, config, seeds))`` over both vehicle configurations, the seeds of ``args`` (its
    draw options) split among its workers."""
    seeds = list(range(args.first_seed, args.first_seed + args.episodes))
    jobs = [(*lead, config, seeds[i::args.workers]) for config in CONFIGS for i in range(args.workers)]
    with ProcessPoolExecutor(args.workers) as pool:
        return [r for part in pool.map(play, jobs) for r in part]


def report(text: str, out: Path | None) -> None:
    """Print the table, and write it to ``out`` too (where given)."""
    print(text)
    if out:
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(text + "\n")


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    add_draw_options(parser, episodes=200)
    args = parser.parse_args()
    check_draw_options(parser, args)
    report(table(play_draws(play, args)), args.out)


if __name__ == "__main__":
    main()
