"""Why the tail lies on creep curves that peak far out: such a curve and one that peaks at its knee read alike.

    python experiments/knee_twins.py --counter-torque --out out/knee_twins.md

For each episode of a suite (default: the v2 default suite, 60 episodes) whose true creep curve peaks at
``--min-peak-creepage`` or more (4 %: the last peak-creepage band of ``cof-gym evaluate``'s breakdown), it
tabulates that curve: the steady curve the episode's ground truth is computed on (at its speed and at the wheel
load at saturation), through :data:`POINTS_TO_PEAK` points up to its peak and :data:`POINTS_PAST_PEAK` past it
(:func:`tabulated_curve`). This *far* curve is paired with a *near* twin (:func:`near_twin`): the same force up to
the point where the far curve reaches ``1 / --ratio`` of its CoF, then a rounded top at exactly that adhesion (a
quadratic rise whose slope falls to zero) and flat past it. The twin peaks ``--ratio`` times lower, where a
curve that rises slowly past its knee still has far to go. Both are played with the episode's seed and its
drawn speed, load, condition, sensor noise and drive lag, so the sensors' draws are the same in both.

Below the last shared point the wheel meets the same creep force on both, so an agent that reads only the
sensors drives both alike until its torque passes it. The table shows per agent:
- how many pairs it played and in how many it drove both alike (to 1e-6 in every action component) for the
  whole of the shorter episode;
- its macro-slips on each curve;
- its median error and median signed error (estimate over CoF, less 1) on each;
- in how many pairs it measured both within ``--tolerance`` without a macro-slip on either. A pair acted alike
  gives one estimate for CoFs ``R`` apart, which is within ``t`` of both only if ``R <= (1 + t) / (1 - t)``.

This reads the truth only to build the curves and to score, like every evaluation; no agent sees it.
"""

from __future__ import annotations

import sys
from pathlib import Path

import gymnasium as gym
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from indistinguishable_peaks import (  # noqa: E402
    ActionLog, acted_alike, add_pair_arguments, checked_pair_arguments, rounded_top)

import cof_gym  # noqa: E402,F401  (registers the envs)
from cof_gym.agents import registry  # noqa: E402
from cof_gym.commands.args import Parser  # noqa: E402
from cof_gym.commands.evaluate_episodes import run_episode  # noqa: E402
from cof_gym.commands.suites import SuiteError, make_suite  # noqa: E402
from cof_gym.physics.creep import OperatingConditions, creep_curve  # noqa: E402
from cof_gym.physics.creep_laws import creep_law_from_spec  # noqa: E402
from cof_gym.task.ground_truth import ground_truth  # noqa: E402
from cof_gym.task.scenarios import COF_ENVELOPE  # noqa: E402

POINTS_TO_PEAK = 44  # geometric in creepage from PEAK_SPAN_START x the peak creepage up to it (and 0 first)
POINTS_PAST_PEAK = 8  # geometric from 1.1 to PAST_PEAK_SPAN x the peak creepage
PEAK_SPAN_START = 1e-3
PAST_PEAK_SPAN = 3.0
TOP_POINTS = 8  # points of the near twin's rounded top
SCENARIO_FIELDS = ("condition", "speed_m_s", "load_case", "noise_level", "motor_lag_s")  # fixed alike in a pair
RISING_MARGIN = 1e-9  # TableShape's tolerance: a point this close to 1 before the peak is dropped


def tabulated_curve(env, truth: dict) -> dict | None:
    """The episode's steady creep curve (``truth``: its ``info["ground_truth"]``) as a table of adhesion over
    CoF: 0 at creepage 0, rising strictly to exactly 1 at the peak creepage, then the curve past it; None where
    the curve dips on its way to the peak (a local maximum at its knee), which a table cannot hold."""
    task = env.unwrapped.task
    shape = creep_law_from_spec(truth["creep_law"])
    built = task.model(truth["load_case"])
    _, wheel_load = ground_truth(built, task.balanced, truth["cof"], shape, truth["speed_m_s"])
    op = OperatingConditions(cof=truth["cof"], condition=shape, wheel_load_n=wheel_load, speed_m_s=truth["speed_m_s"])
    peak = truth["peak_creepage"]
    rising = peak * np.geomspace(PEAK_SPAN_START, 1.0, POINTS_TO_PEAK)[:-1]
    past = peak * np.geomspace(1.1, PAST_PEAK_SPAN, POINTS_PAST_PEAK)
    (ratio_rising, ratio_past) = (creep_curve(s, op)[0] / truth["cof"] for s in (rising, past))
    if np.any(np.diff(ratio_rising) <= 0.0):
        return None
    keep = ratio_rising < 1.0 - RISING_MARGIN
    creepage = np.concatenate([[0.0], rising[keep], [peak], past])
    ratio = np.concatenate([[0.0], ratio_rising[keep], [1.0], np.clip(ratio_past, 0.0, 1.0)])
    return {"creepage": creepage.tolist(), "adhesion_ratio": ratio.tolist()}


def near_twin(table: dict, ratio: float) -> dict:
    """The near twin of a tabulated curve (:func:`tabulated_curve`) for a CoF ``ratio`` times lower: its points
    below ``1 / ratio`` (in the twin's units, times ``ratio``), then a quadratic from the last of them with the slope
    of the last interval, rising to 1 (the twin's CoF) with zero slope, and flat past it. Monotone
    interpolation (PCHIP) sets each knot's slope from its neighbours, so the two coincide up to the point before
    the last shared one (:func:`~indistinguishable_peaks.rounded_top`)."""
    if not ratio > 1.0:
        raise ValueError(f"ratio must be > 1, got {ratio!r}")
    s, r = np.asarray(table["creepage"], dtype=float), np.asarray(table["adhesion_ratio"], dtype=float)
    top = 1.0 / ratio
    below = int(np.argmax(r >= top))  # the first point at or above the twin's top
    if below < 2:
        raise ValueError("the curve has fewer than two points below the twin's top")
    last = below - 1
    slope = (r[last] - r[last - 1]) / (s[last] - s[last - 1]) * ratio  # in the twin's ratio units
    top_creepage, top_adhesion = rounded_top(s[last], r[last] * ratio, slope, TOP_POINTS)
    creepage = np.concatenate([s[:last + 1], top_creepage])
    adhesion = np.concatenate([r[:last + 1] * ratio, top_adhesion])
    return {"creepage": creepage.tolist(), "adhesion_ratio": adhesion.tolist()}


# why a far curve has no pair
DIPS, LOW_TWIN = "the curve dips before its peak", "the twin's CoF would lie below the task's lowest"


def pair_options(env, seed: int, options: dict, ratio: float, min_peak: float) -> tuple[dict, dict] | str | None:
    """The reset options of an episode's far curve and of its near twin; None where its curve peaks below
    ``min_peak`` creepage; :data:`DIPS` or :data:`LOW_TWIN` where it has no pair (:func:`tabulated_curve`
    cannot hold it, or the twin's CoF would fall below the task's lowest)."""
    _, info = env.reset(seed=seed, options=options)
    truth = info["ground_truth"]
    if truth["peak_creepage"] < min_peak:
        return None
    if truth["cof"] / ratio < COF_ENVELOPE[0]:
        return LOW_TWIN
    far = tabulated_curve(env, truth)
    if far is None:
        return DIPS
    fixed = {k: truth[k] for k in SCENARIO_FIELDS}
    return ({**fixed, "cof": truth["cof"], "creep_law": {"table": far}},
            {**fixed, "cof": truth["cof"] / ratio, "creep_law": {"table": near_twin(far, ratio)}})


def play_pair(env, agent: ActionLog, seed: int, options: tuple[dict, dict], episode: int) -> dict:
    """The agent on the far curve and on its near twin: its records and whether it acted alike throughout."""
    far = run_episode(env, agent, seed, options[0], episode)
    first = agent.actions
    near = run_episode(env, agent, seed, options[1], episode)
    return {"far": far, "near": near, "alike": acted_alike(first, agent.actions)}


def _signed(record) -> float:
    return record.estimate / record.cof - 1.0


def table(agents: list[str], suite_name: str, episodes: int, min_peak: float, ratio: float, tolerance: float,
          counter_torque: bool) -> str:
    """The markdown table over the suite's far-peak episodes (see the module docstring)."""
    suite = make_suite(suite_name, episodes, 0)
    configs = [{}, {"counter_torque": True}] if counter_torque else [{}]
    played = {spec: [] for spec in agents}
    skipped: dict[str, int] = {}
    for config in configs:
        env = gym.make(suite.env_id, **{**suite.env_kwargs, **config})
        built = [(i, seed, pair_options(env, seed, options, ratio, min_peak))
                 for i, (seed, options) in enumerate(suite.episodes)]
        for _, _, b in built:
            if isinstance(b, str):
                skipped[b] = skipped.get(b, 0) + 1
        for spec in agents:
            agent = ActionLog(registry.make_agent(spec, env))
            played[spec] += [play_pair(env, agent, seed, b, i) for i, seed, b in built if isinstance(b, tuple)]
        env.close()
    if not played[agents[0]]:
        raise SuiteError(f"{suite_name}: no episode whose curve peaks at {100 * min_peak:g} % creepage or more "
                         f"has a pair ({', '.join(f'{n} {why}' for why, n in skipped.items()) or 'none that far'})")
    rows = []
    for spec, pairs in played.items():
        both = sum(not (p["far"].macro_slip or p["near"].macro_slip) and p["far"].relative_error <= tolerance
                   and p["near"].relative_error <= tolerance for p in pairs)
        med = {k: 100 * np.median([p[k].relative_error for p in pairs]) for k in ("far", "near")}
        signed = {k: 100 * np.median([_signed(p[k]) for p in pairs]) for k in ("far", "near")}
        rows.append(f"| {spec} | {len(pairs)} | {sum(p['alike'] for p in pairs)} | "
                    f"{sum(p['far'].macro_slip for p in pairs)} / {sum(p['near'].macro_slip for p in pairs)} | "
                    f"{med['far']:.1f} % / {med['near']:.1f} % | {signed['far']:+.1f} % / {signed['near']:+.1f} % | "
                    f"{both} |")
    head = (f"| agent | pairs | acted alike on both | macro-slips: far / near | median error: far / near | "
            f"median signed error: far / near | both within {100 * tolerance:g} %, no macro-slip |")
    without = "; without a pair: " + ", ".join(f"{n} ({why})" for why, n in skipped.items()) if skipped else ""
    note = (f"Pairs: the episodes of {suite_name} whose curve peaks at {100 * min_peak:g} % creepage or more"
            f"{', in both vehicle configurations' if counter_torque else ''}{without}. The near twin peaks at "
            f"1/{ratio:g} of the far curve's CoF; one estimate is within {100 * tolerance:g} % of both CoFs only if "
            f"{ratio:g} <= {(1 + tolerance) / (1 - tolerance):.3f}.")
    return "\n".join([head, "|---" * 7 + "|", *rows, "", note])


def main() -> int:
    ap = Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--suite", default="default", help="default or a suite file (default: %(default)s)")
    ap.add_argument("--episodes", type=int, default=60, help="episodes of a suite without a list (default: %(default)s)")
    ap.add_argument("--min-peak-creepage", type=float, default=0.04, help="the far curves' least peak creepage (0-1)")
    add_pair_arguments(ap, 1.5, "the far curve's CoF over its near twin's (> 1)")
    args = ap.parse_args()
    if not 0.0 < args.min_peak_creepage < 1.0:
        ap.error(f"--min-peak-creepage must be in (0, 1), got {args.min_peak_creepage:g}")
    if not 1 <= args.episodes <= 10_000:
        ap.error(f"--episodes must be in [1, 10000], got {args.episodes}")
    agents = checked_pair_arguments(ap, args)
    try:
        text = table(agents, args.suite, args.episodes, args.min_peak_creepage, args.ratio, args.tolerance,
                     args.counter_torque)
    except (SuiteError, OSError) as error:
        ap.error(f"--suite: {error}")
    print(text)
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(f"# Knee twins: {args.suite}\n\n{text}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
