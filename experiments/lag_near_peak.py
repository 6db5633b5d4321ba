"""What the sensors show on the way to the peak: a diagnostic, not an agent (it reads the truth).

    python experiments/lag_near_peak.py --suite experiments/suites/v2_validation_grid.json --episodes 12 18 27

For each chosen episode of a suite file it steps the DC torque through fixed fractions of the episode's
true saturation torque (``--levels``) with a modulation of ``--amplitude-ratio`` x DC at
``--frequency`` Hz, and prints per window the measured phase lag (deg, with its standard error), the
compliance (speed/torque amplitude ratio x I w: 1 for a free wheel), the measured CoA over the CoF and
the true mean creepage over the peak creepage. It shows how late the lag rises on sharp-kneed curves,
the reason the learned interrogator and the phase rule commit below the peak. ``--env`` plays the same
episodes in another env (e.g. ``CofGym/HalfWheelset-v2``, the wheelset without the wagon) and ``--set
KEY=VALUE`` overrides a reset option of every chosen episode (numbers as JSON, e.g. ``motor_lag_s=0``):

    python experiments/lag_near_peak.py --episodes 6 --levels 0.3 0.6 0.8 0.85 0.88 --amplitude-ratio 0.4 \
        --set load_case=laden motor_lag_s=0 [--env CofGym/HalfWheelset-v2]
"""

from __future__ import annotations

import argparse
import json

import gymnasium as gym

from cof_gym.agents.interrogator import Reading
from cof_gym.commands.suites import make_suite
from cof_gym.task.interface import encode_action

LEVELS = (0.3, 0.5, 0.7, 0.8, 0.85, 0.9, 0.93, 0.95, 0.97, 0.98, 0.99)


def trace(env, seed: int, options: dict, levels, amplitude_ratio: float, frequency_hz: float) -> list[str]:
    """Markdown rows, one per window of the staircase."""
    limits = env.unwrapped.limits
    _, info = env.reset(seed=seed, options=options)
    truth = info["ground_truth"]
    rows = []
    for u in levels:
        dc = u * truth["saturation_torque_nm"]
        obs, _, terminated, truncated, info = env.step(
            encode_action(dc, amplitude_ratio * dc, frequency_hz, 0.1, False, limits))
        r = Reading.of(obs, limits)
        rows.append(f"| {u:.2f} | {r.phase_deg:.1f} +- {r.se_deg:.1f} | {r.compliance:.3f} | "
                    f"{r.coa / truth['cof']:.3f} | {info['ground_truth']['creepage_mean'] / truth['peak_creepage']:.2f} | "
                    f"{'yes' if info['macro_slip'] else ''} |")
        if terminated or truncated:
            break
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--suite", default="experiments/suites/v2_validation_grid.json")
    ap.add_argument("--episodes", type=int, nargs="+", default=[12, 18, 27], help="indices into the suite")
    ap.add_argument("--levels", type=float, nargs="+", default=list(LEVELS), help="DC / true M_sat per window")
    ap.add_argument("--amplitude-ratio", type=float, default=0.05)
    ap.add_argument("--frequency", type=float, default=5.0, help="Hz")
    ap.add_argument("--env", default=None, help="play the episodes in this env id instead of the suite's")
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE", help="override a reset option")
    args = ap.parse_args()
    overrides = {}
    for item in args.set:
        key, sep, value = item.partition("=")
        if not sep or not key:
            ap.error(f"--set: expected KEY=VALUE, got {item!r}")
        try:
            overrides[key] = json.loads(value)
        except json.JSONDecodeError:
            overrides[key] = value
    suite = make_suite(args.suite, 60, 0)
    for k in args.episodes:
        if not 0 <= k < len(suite.episodes):
            ap.error(f"--episodes: {k} is not an index of the suite (0 to {len(suite.episodes) - 1})")
    env = gym.make(args.env or suite.env_id, **suite.env_kwargs)
    for k in args.episodes:
        seed, options = suite.episodes[k]
        options = {**options, **overrides}
        print(f"\n### episode {k} (seed {seed}): {options.get('condition')}, CoF {options.get('cof')}\n")
        print("| DC / M_sat | lag [deg] | compliance | CoA / CoF | creepage / peak creepage | macro-slip |")
        print("|---|---|---|---|---|---|")
        print("\n".join(trace(env, seed, options, args.levels, args.amplitude_ratio, args.frequency)))


if __name__ == "__main__":
    main()
