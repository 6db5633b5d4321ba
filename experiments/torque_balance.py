"""How well does the first window's torque balance read the torque sensor's gain against the force sensor's?
(run from the repository root; 2 cores, about 10 s per suite)

    python experiments/torque_balance.py [--suites FILE ...] [--threshold-deg 65] [--out out/torque_balance.md]

A diagnostic that reads the truth (each episode's drawn or fixed systematic errors), information only. For every
episode of each suite (a suite file or ``default``, played in its own configuration as ``cof-gym evaluate`` plays
it), the shipped interrogator drives its first window, and the table compares the balance read there
(:attr:`~cof_gym.agents.interrogator.Reading.torque_balance` through
:func:`~cof_gym.agents.interrogator.readings.gain_from_balance`: the mean torque reading over the measured creep
force times the wheel radius) with what it should read on a settled wheel, ``(1 + e_T) / (1 + e_F)``: the median
of the relative difference, the P90 and the largest of its size, the episodes where it is above 1 %, and how many of
those and of all have a first-window lag above ``--threshold-deg`` (the shipped climb's
``torque_balance_max_lag_deg``: there the climb keeps its torque readings as read). Default suites: the three
validation grids and the torque validation set (model-selection data).
"""

from __future__ import annotations

import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import gymnasium as gym
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from script_checks import check_out_file, write_report  # noqa: E402

from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR, Reading, interrogator_for, manifest_climb  # noqa: E402
from cof_gym.agents.interrogator.readings import gain_from_balance  # noqa: E402
from cof_gym.commands.args import Parser, float_in_range, positive_int  # noqa: E402
from cof_gym.commands.evaluate_episodes import agent_view  # noqa: E402
from cof_gym.commands.suites import Suite, SuiteError, make_suite  # noqa: E402

SUITES = Path(__file__).resolve().parent / "suites"
DEFAULT_SUITES = tuple(str(SUITES / f"v2_{name}_grid.json") for name in (
    "validation", "validation_procedural", "validation_steep",
    "validation_torque", "validation_torque_procedural", "validation_torque_steep"))
MISREAD = 0.01  # a balance this far (relative) from (1 + e_T) / (1 + e_F) counts as misread


def first_windows(suite: Suite) -> list[tuple[float, float]]:
    """(the balance's relative difference from (1 + e_T) / (1 + e_F), the first window's lag in deg) of every
    episode of the suite, its first window driven by the shipped interrogator."""
    env = gym.make(suite.env_id, **suite.env_kwargs)
    agent = interrogator_for(env, SHIPPED_INTERROGATOR)
    limits = env.unwrapped.limits
    out = []
    for seed, options in suite.episodes:
        observation, info = env.reset(seed=seed, options=options)
        agent.reset(observation, agent_view(info, False))
        observation, _, _, _, info = env.step(agent.act(observation, agent_view(info, False)))
        errors = env.unwrapped.episode.scenario
        settled = (1.0 + errors.torque_gain_error) / (1.0 + errors.force_gain_error)
        reading = Reading.of(observation, limits, info)  # the balance and the lag, as the climb reads them
        out.append((gain_from_balance(reading.torque_balance) / settled - 1.0, reading.phase_deg))
    env.close()
    return out


def row(suite: str, windows: list[tuple[float, float]], threshold_deg: float) -> str:
    """The table's row of one suite."""
    difference, lag = (np.array(v) for v in zip(*windows))
    size, misread, unsettled = np.abs(difference), np.abs(difference) > MISREAD, lag > threshold_deg
    return (f"| {Path(suite).stem} | {len(difference)} | "
            f"{100 * np.median(difference):+.2f} | {100 * np.percentile(size, 90):.2f} | {100 * size.max():.2f} | "
            f"{int(misread.sum())} | {int((misread & unsettled).sum())} | {int(unsettled.sum())} |")


def main() -> None:
    parser = Parser(description=__doc__.split("\n")[0])
    parser.add_argument("--suites", nargs="+", default=list(DEFAULT_SUITES),
                        help="suite files (or 'default' / 'paper'), each played in its own configuration")
    parser.add_argument("--threshold-deg", type=float_in_range(0.0, 90.0, low_inclusive=True),
                        default=manifest_climb(SHIPPED_INTERROGATOR).torque_balance_max_lag_deg or 90.0,
                        help="the first-window lag above which the climb reads no balance (default: the shipped one)")
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--out", type=Path, default=Path("out/torque_balance.md"))
    args = parser.parse_args()
    try:
        suites = [make_suite(name, 60, 0) for name in args.suites]
    except SuiteError as error:
        parser.error(f"--suites: {' '.join(str(error).split())}")
    check_out_file(parser, "--out", args.out)
    with ProcessPoolExecutor(args.workers) as pool:
        results = list(pool.map(first_windows, suites))
    lines = [f"The first window's torque balance against (1 + e_T) / (1 + e_F), per suite (`python "
             f"experiments/torque_balance.py`): the relative difference in per cent; misread: above "
             f"{100 * MISREAD:g} %; unsettled: a first-window lag above {args.threshold_deg:g} deg.", "",
             "| suite | episodes | median difference [%] | P90 of its size [%] | largest [%] | misread | misread and "
             "unsettled | unsettled |", "|---" * 8 + "|"]
    lines += [row(suite, windows, args.threshold_deg) for suite, windows in zip(args.suites, results)]
    write_report(args.out, lines)


if __name__ == "__main__":
    main()
