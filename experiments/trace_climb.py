"""The learned interrogator's climb, window by window: a diagnostic that reads the truth (never the agent).

    python experiments/trace_climb.py --suite default --episodes 37 12
    python experiments/trace_climb.py --suite experiments/suites/v2_validation_grid.json --episodes 3 \
        --agent runs/speed_scaled/ensemble --set frequency_reference_m_s=20

For each chosen episode of a suite (``--suite``: ``default``, ``paper`` or a suite file; ``--episodes``:
indices into it; ``--counter-torque``: in the paper's vehicle configuration, crest_tradeoff.py's second) the
interrogator of ``--agent`` (default: the shipped one, its manifest's climb with
``--set NAME=VALUE`` fields of :class:`~cof_gym.agents.interrogator.ClimbParameters` replaced, values as JSON or
plain text)
plays the episode as ``cof-gym evaluate`` would, and the table lists per driven window what the climb
decided (:class:`~cof_gym.agents.interrogator.WindowDecision`) beside the truth: the DC torque over the
true saturation torque and the true headroom ``ln(M_sat / DC)``, the measured lag, the crest asymmetry of the measured CoA's cycle
(:func:`crest_asymmetry`), the filter's predicted
headroom and std, the cautious headroom that steered and its std (the filter's or a guard's), the log step
and whether the climb has crept. A last line gives how the climb ended, the estimate, the CoF and the
error. It shows where a climb's windows went: how long the approach took, where the cautious gap closed,
how far below the peak the slow probe began (docs/interrogator.md, rule 34's traces).
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import replace
from pathlib import Path

import gymnasium as gym

sys.path.insert(0, str(Path(__file__).resolve().parent))
from crest_tradeoff import climb_setting  # noqa: E402

from cof_gym.agents.base import agent_view  # noqa: E402
from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR, Reading, interrogator_for, manifest_climb  # noqa: E402
from cof_gym.agents.interrogator.networks import member_files  # noqa: E402
from cof_gym.commands.args import Parser  # noqa: E402
from cof_gym.commands.suites import make_suite, scenario_option  # noqa: E402

HEADER = ("| window | DC / M_sat | true headroom | lag [deg] | crest asymmetry | filter headroom +- std "
          "| steering headroom +- std | log step | crept |")


def crest_asymmetry(reading: Reading) -> float:
    """How far the measured CoA's cycle rises above its window mean over how far it falls below it (1 for a wave
    the creep curve passes on unbent; below 1 where the crest flattens against the curve's top; NaN unread)."""
    below = reading.coa - reading.coa_cycle_min
    return (reading.coa_cycle_max - reading.coa) / below if reading.coa_cycle_max > 0.0 and below > 0.0 else math.nan


def trace(env, agent, seed: int, options: dict) -> tuple[str, list[str], str]:
    """One episode of ``agent`` in ``env``: the scenario's line, the table's rows and the closing line."""
    obs, info = env.reset(seed=seed, options=options)
    truth = info["ground_truth"]
    agent.reset(obs, agent_view(info, oracle=False))
    rows, fractions, lags, asymmetries = [], [], [], []
    while True:
        obs, _, terminated, truncated, info = env.step(agent.act(obs, agent_view(info, oracle=False)))
        fractions.append(info["ground_truth"]["torque_fraction"])
        reading = Reading.of(obs, env.unwrapped.limits, info)
        lags.append(reading.phase_deg)
        asymmetries.append(crest_asymmetry(reading))
        if terminated or truncated:
            break
    for k, d in enumerate(agent.decisions):  # decision k follows driven window k
        rows.append(f"| {k} | {fractions[k]:.3f} | {-math.log(fractions[k]):.3f} | {lags[k]:.1f} | {asymmetries[k]:.3f} | "
                    f"{d.filter_headroom:.3f} +- {d.filter_std:.3f} | {d.steering_headroom:.3f} +- {d.steering_std:.3f} | "
                    f"{d.log_step:.3f} | {'yes' if d.crept else ''} |")
    estimate, cof = info["cof_estimate"], truth["cof"]
    ended = "macro-slip" if info["macro_slip"] else agent.stop_reason or "truncated"
    title = (f"{truth['condition']}, {truth['creep_family']}, CoF {cof:.4f}, {truth['speed_m_s']:.1f} m/s, "
             f"{truth['load_case']}")
    last = (f"ended: {ended} after {len(fractions)} windows; estimate {estimate:.4f}, CoF {cof:.4f}, "
            f"error {100 * (estimate / cof - 1):+.1f} %")
    return title, rows, last


def main() -> None:
    ap = Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--suite", default="default", help="default, paper or a suite file (default: %(default)s)")
    ap.add_argument("--episodes", type=int, nargs="+", default=[0], help="indices into the suite")
    ap.add_argument("--agent", type=Path, default=SHIPPED_INTERROGATOR,
                    help="an interrogator's directory (member_*.npz; its manifest's climb and guards, where it has one)")
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE",
                    help="a ClimbParameters field (a JSON or plain-text value)")
    ap.add_argument("--counter-torque", action="store_true",
                    help="the paper's vehicle configuration (counter torque on the other wheelset), as crest_tradeoff.py's "
                         "second configuration plays every grid")
    ap.add_argument("--scenario", nargs="+", default=[], metavar="NAME=VALUE", type=scenario_option,
                    help="reset options over every episode's own, as crest_tradeoff.py's --scenario (e.g. noise_level=2)")
    args = ap.parse_args()
    if not member_files(args.agent):
        ap.error(f"--agent: {args.agent} holds no member_*.npz")
    params = manifest_climb(args.agent)
    try:  # crest_tradeoff.py's --set items, on the agent's own climb
        params = replace(params, **dict(map(climb_setting, args.set)))
    except (argparse.ArgumentTypeError, ValueError) as e:
        ap.error(f"--set: {e}")
    try:
        suite = make_suite(args.suite, 60, 0)
    except (OSError, ValueError) as e:
        ap.error(f"--suite: {e}")
    for k in args.episodes:
        if not 0 <= k < len(suite.episodes):
            ap.error(f"--episodes: {k} is not an index of the suite (0 to {len(suite.episodes) - 1})")
    configuration = {"counter_torque": True} if args.counter_torque else {}
    env = gym.make(suite.env_id, **{**suite.env_kwargs, **configuration, **params.env_options})
    try:
        agent = interrogator_for(env, args.agent, params)
    except ValueError as e:
        ap.error(f"--agent: {e}")
    for k in args.episodes:
        seed, options = suite.episodes[k]
        title, rows, last = trace(env, agent, seed, {**options, **dict(args.scenario)})
        over = "".join(f", {name} {value}" for name, value in args.scenario)
        print(f"\n### episode {k} (seed {seed}){', counter torque' if args.counter_torque else ''}{over}: {title}\n")
        print("\n".join([HEADER, "|---" * 9 + "|", *rows, "", last]))


if __name__ == "__main__":
    main()
