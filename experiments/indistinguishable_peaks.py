"""Why no agent that does not read the truth can be both safe and accurate on a peak that gives no warning.

    python experiments/indistinguishable_peaks.py --counter-torque --out out/indistinguishable_peaks.md

For each episode of a suite whose creep curve is a table (default: the steep validation grid, whose curves
fall steeply past a kinked peak) and whose twin's CoF stays in the task's range, it builds a twin: the same
episode (seed, speed, load, sensors) with a curve that is the same in force up to the table point before the
peak and then keeps rising, to a CoF ``--ratio`` times higher (:func:`twin_law`). Below that point the wheel
meets the same creep force on both, so an agent that reads only the sensors drives both alike until its
torque passes the original peak. Each agent plays every pair (with ``--counter-torque`` twice: in the
suite's vehicle configuration and with counter torque); the table shows, per agent, how many pairs it
played, in how many it drove both members alike (to 1e-6 in every action component) for the whole of the
shorter episode, its macro-slips on the original, its median error on the original and on the twin, and in
how many pairs it measured both within ``--tolerance`` without running away on the original (at most the
pairs where its actions differed: with a twin CoF ``R`` times the original's, one estimate is within ``t``
of both only if ``R <= (1 + t) / (1 - t)``).

This reads the truth only to build the twins and to score, like every evaluation; no agent sees it.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np

import cof_gym  # noqa: F401  (registers the envs)
from cof_gym.agents import registry
from cof_gym.commands.args import Parser
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.commands.suites import SuiteError, make_suite
from cof_gym.task.scenarios import COF_ENVELOPE

sys.path.insert(0, str(Path(__file__).resolve().parent))
from script_checks import check_out_file, checked_agents  # noqa: E402

DEFAULT_SUITE = Path(__file__).resolve().parent / "suites" / "v2_validation_steep_grid.json"
DEFAULT_AGENTS = ("interrogator", "phase-rule", "staircase", "model-based", "robust-model")
CONTINUATION_POINTS = 8  # points of the twin's rise above the original peak
# actions in [-1, 1] counted alike: the twin's force (ratio / R) x (R x CoF) rounds differently from the
# original's ratio x CoF in the last bit, and a float32 action may follow by one of its own ulps (6e-8)
ACTION_ATOL = 1e-6


def twin_law(table: dict, ratio: float) -> dict:
    """The twin of a tabulated creep law (``{"creepage": [...], "adhesion_ratio": [...]}``, ratio to the CoF)
    for a CoF ``ratio`` times the original's: the same force (ratio / ``ratio``) at every point up to the
    peak, then a quadratic rise from the peak with the slope of the last rising interval to 1 (the twin's
    CoF) with zero slope, then flat. Monotone interpolation (PCHIP) sets each knot's slope from its
    neighbours, so the two curves coincide exactly up to the point before the peak and differ on the last
    interval before it."""
    if not ratio > 1.0:
        raise ValueError(f"ratio must be > 1, got {ratio!r}")
    s, r = np.asarray(table["creepage"], dtype=float), np.asarray(table["adhesion_ratio"], dtype=float)
    peak = int(np.argmax(r))
    if peak < 1:
        raise ValueError("the table has no rising interval before its peak")
    slope = (r[peak] - r[peak - 1]) / (s[peak] - s[peak - 1]) / ratio  # in the twin's ratio units
    top_creepage, top_adhesion = rounded_top(s[peak], 1.0 / ratio, slope, CONTINUATION_POINTS)
    creepage = np.concatenate([s[:peak + 1], top_creepage])
    adhesion = np.concatenate([r[:peak + 1] / ratio, top_adhesion])
    return {"table": {"creepage": creepage.tolist(), "adhesion_ratio": adhesion.tolist()}}


def rounded_top(creepage: float, adhesion: float, slope: float, points: int) -> tuple[np.ndarray, np.ndarray]:
    """The points of a twin's curve past (``creepage``, ``adhesion`` < 1; adhesion over the twin's CoF) where it
    leaves the original with ``slope``: ``points`` points of the quadratic ``adhesion + slope x - slope^2 x^2 /
    (4 rise)`` (``rise = 1 - adhesion``), which reaches 1 with zero slope at ``x = 2 rise / slope`` (its last point
    exactly 1), then a flat point at twice that span; (creepages, adhesion ratios)."""
    rise = 1.0 - adhesion
    span = 2.0 * rise / slope
    x = span * np.arange(1, points + 1) / points
    above = adhesion + slope * x - slope**2 * x**2 / (4.0 * rise)
    above[-1] = 1.0
    return np.concatenate([creepage + x, [creepage + 2.0 * span]]), np.concatenate([above, [1.0]])


def acted_alike(first: list[np.ndarray], second: list[np.ndarray]) -> bool:
    """Whether two episodes' actions agree to :data:`ACTION_ATOL` in every component over the shorter one."""
    return all(np.allclose(a, b, rtol=0.0, atol=ACTION_ATOL) for a, b in zip(first, second))


def last_shared_fraction(table: dict) -> float:
    """The original curve's adhesion ratio at the point before its peak: up to that force the twins coincide."""
    r = np.asarray(table["adhesion_ratio"], dtype=float)
    return float(r[int(np.argmax(r)) - 1])


class ActionLog:
    """An agent wrapper that records its actions (the agent's own behaviour is unchanged)."""

    def __init__(self, agent):
        self.agent, self.actions = agent, []

    def __getattr__(self, name):  # oracle, name, ...: the agent's
        if name.startswith("_") or name == "agent":
            raise AttributeError(name)
        return getattr(self.agent, name)

    def reset(self, observation, info) -> None:
        self.actions = []
        self.agent.reset(observation, info)

    def act(self, observation, info):
        action = self.agent.act(observation, info)
        self.actions.append(np.array(action, copy=True))
        return action


def play_pair(env, agent: ActionLog, seed: int, options: dict, ratio: float, episode: int) -> dict:
    """The agent on an episode and on its twin: its records and whether it acted alike throughout."""
    original = run_episode(env, agent, seed, options, episode)
    first = agent.actions
    law = options["creep_law"]["table"]
    twin_options = {**options, "cof": options["cof"] * ratio, "creep_law": twin_law(law, ratio)}
    twin = run_episode(env, agent, seed, twin_options, episode)
    return {"original": original, "twin": twin, "alike": acted_alike(first, agent.actions),
            "shared": last_shared_fraction(law)}


def table(agents: list[str], suite_path: Path, ratio: float, tolerance: float, counter_torque: bool) -> str:
    """The markdown table over every tabulated episode of the suite (see the module docstring)."""
    suite = make_suite(str(suite_path), 60, 0)
    tabulated = [(i, seed, options) for i, (seed, options) in enumerate(suite.episodes)
                 if "table" in (options or {}).get("creep_law", {})]
    episodes = [e for e in tabulated if e[2]["cof"] * ratio <= COF_ENVELOPE[1]]  # the twin's CoF in the task's range
    if not episodes:
        raise SuiteError(f"{suite_path}: no episode with a tabulated creep law whose CoF x {ratio:g} is at most "
                         f"{COF_ENVELOPE[1]:g}")
    configs = [{}, {"counter_torque": True}] if counter_torque else [{}]
    shared = [last_shared_fraction(options["creep_law"]["table"]) for _, _, options in episodes]
    rows = []
    for spec in agents:
        pairs = []
        for config in configs:
            env = gym.make(suite.env_id, **{**suite.env_kwargs, **config})
            agent = ActionLog(registry.make_agent(spec, env))
            pairs += [play_pair(env, agent, seed, options, ratio, i) for i, seed, options in episodes]
            env.close()
        both = sum(not p["original"].macro_slip and p["original"].relative_error <= tolerance
                   and p["twin"].relative_error <= tolerance for p in pairs)
        rows.append(f"| {spec} | {len(pairs)} | {sum(p['alike'] for p in pairs)} | "
                    f"{sum(p['original'].macro_slip for p in pairs)} | "
                    f"{100 * np.median([p['original'].relative_error for p in pairs]):.1f} % | "
                    f"{100 * np.median([p['twin'].relative_error for p in pairs]):.1f} % | {both} |")
    head = (f"| agent | pairs | acted alike on both | macro-slips (original) | median error (original) | "
            f"median error (twin, CoF x {ratio:g}) | both within {100 * tolerance:g} %, no macro-slip |")
    note = (f"Episodes: {len(episodes)} of the {len(tabulated)} tabulated (the others' twins would lie above the "
            f"task's highest CoF, {COF_ENVELOPE[1]:g}). Twins coincide in force up to the original's point before its "
            f"peak: median {np.median(shared):.3f}, lowest {min(shared):.3f} of its CoF.")
    return "\n".join([head, "|---" * 7 + "|", *rows, "", note])


def add_pair_arguments(ap: argparse.ArgumentParser, ratio: float, ratio_help: str) -> None:
    """The options every twin experiment takes: ``--agents``, ``--ratio`` (default ``ratio``), ``--tolerance``,
    ``--counter-torque`` and ``--out``."""
    ap.add_argument("--agents", default=",".join(DEFAULT_AGENTS), help="comma-separated agents that read no truth")
    ap.add_argument("--ratio", type=float, default=ratio, help=ratio_help)
    ap.add_argument("--tolerance", type=float, default=0.08, help="the error counted as measured (0-1)")
    ap.add_argument("--counter-torque", action="store_true", help="also play every pair with counter torque")
    ap.add_argument("--out", type=Path, default=None, help="also write the table here")


def checked_pair_arguments(ap: argparse.ArgumentParser, args: argparse.Namespace) -> list[str]:
    """The agents of :func:`add_pair_arguments`'s options once ``--ratio`` and ``--tolerance`` are in range
    and ``--out`` can be written (``ap.error`` otherwise: one line, exit code 2)."""
    check_out_file(ap, "--out", args.out)
    if not 1.0 < args.ratio <= 4.0:
        ap.error(f"--ratio must be in (1, 4], got {args.ratio:g}")
    if not 0.0 < args.tolerance < 1.0:
        ap.error(f"--tolerance must be in (0, 1), got {args.tolerance:g}")
    return sensor_only_agents(ap, args.agents)


def sensor_only_agents(ap: argparse.ArgumentParser, text: str) -> list[str]:
    """The comma-separated agents of ``--agents`` (``text``), each registered and none an oracle: twins read alike
    only to agents that do not read the truth (``ap.error`` otherwise: one line, exit code 2)."""
    return checked_agents(ap, "--agents", text.split(","), "the twins read alike only to agents that do not")


def main() -> None:
    ap = Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--suite", type=Path, default=DEFAULT_SUITE, help="a suite file with tabulated creep curves")
    add_pair_arguments(ap, 1.25, "the twin's CoF over the original's (> 1)")
    args = ap.parse_args()
    agents = checked_pair_arguments(ap, args)
    try:
        text = table(agents, args.suite, args.ratio, args.tolerance, args.counter_torque)
    except (SuiteError, OSError, json.JSONDecodeError) as error:
        ap.error(f"--suite: {error}")
    print(text)
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(f"# Indistinguishable peaks: {args.suite.name}\n\n{text}\n")


if __name__ == "__main__":
    sys.exit(main())
