"""What the sensors show on the way to the peak: a diagnostic, not an agent (it reads the truth).

    python experiments/lag_near_peak.py --suite experiments/suites/v2_validation_grid.json --episodes 12 18 27

For each chosen episode of a suite file it steps the DC torque through fixed fractions of the episode's
true saturation torque (``--levels``) with a modulation of ``--amplitude-ratio`` x DC at
``--frequency`` Hz, and prints per window the measured phase lag (deg, with its standard error), the
compliance (speed/torque amplitude ratio x I w: 1 for a free wheel), the measured CoA over the CoF and
the true mean creepage over the peak creepage, and the measured creepage's own modulation (a sensor
reading: its swing per torque over the first window's, and its lag behind the torque with its standard
error). It shows how late the lag rises on sharp-kneed curves,
the reason the learned interrogator and the phase rule commit below the peak. ``--env`` plays the same
episodes in another env (e.g. ``CofGym/HalfWheelset-v2``, the wheelset without the wagon) and ``--set
KEY=VALUE`` overrides a reset option of every chosen episode (numbers as JSON, e.g. ``motor_lag_s=0``):

    python experiments/lag_near_peak.py --episodes 6 --levels 0.3 0.6 0.8 0.85 0.88 --amplitude-ratio 0.4 \
        --set load_case=laden motor_lag_s=0 [--env CofGym/HalfWheelset-v2]

``--harmonics`` drives the env's three-tone excitation with tones 2 and 3 silent (weight 0) at twice and
three times the modulation frequency: the torque is the same sine, and their lock-ins read the wheelset
speed's second and third harmonics, printed relative to the fundamental (H2, H3): the distortion a
curved or kinked creep curve puts on the response.
"""

from __future__ import annotations

import argparse
import json

import gymnasium as gym

import numpy as np

from cof_gym.agents.interrogator import Reading
from cof_gym.commands.suites import make_suite
from cof_gym.task.excitation import encode_extra_tones
from cof_gym.task.interface import MotorLimits, encode_action

HARMONIC_OPTIONS = {"excitation": "multitone", "tones": 3}  # tones 2 and 3 silent at 2 f and 3 f

LEVELS = (0.3, 0.5, 0.7, 0.8, 0.85, 0.9, 0.93, 0.95, 0.97, 0.98, 0.99)


def _harmonics(measurement: dict) -> str:
    """The speed's second and third harmonics over its fundamental (silent tones 2 and 3)."""
    fundamental = max(measurement["tone1_omega_amplitude_rad_s"], 1e-12)
    return " | ".join(f"{measurement[f'tone{k}_omega_amplitude_rad_s'] / fundamental:.3f}" for k in (2, 3))


def trace(env, seed: int, options: dict, levels, amplitude_ratio: float, frequency_hz: float,
          harmonics: bool = False) -> list[str]:
    """Markdown rows, one per window of the staircase."""
    limits = env.unwrapped.limits
    _, info = env.reset(seed=seed, options=options)
    truth = info["ground_truth"]
    silent = encode_extra_tones([(2 * frequency_hz, 0.0), (3 * frequency_hz, 0.0)], limits.min_frequency_hz,
                                limits.max_frequency_hz) if harmonics else np.zeros(0, dtype=np.float32)
    rows, first_swing = [], None
    for u in levels:
        dc = u * truth["saturation_torque_nm"]
        action = np.concatenate([encode_action(dc, amplitude_ratio * dc, frequency_hz, 0.1, False, limits), silent])
        obs, _, terminated, truncated, info = env.step(action)
        r = Reading.of(obs, limits)
        m = info["measurement"]
        swing = m["creepage_modulation_amplitude"] / max(m["torque_amplitude_nm"], 1e-9)
        first_swing = first_swing or swing
        rows.append(f"| {u:.2f} | {r.phase_deg:.1f} +- {r.se_deg:.1f} | {r.compliance:.3f} | "
                    f"{r.coa / truth['cof']:.3f} | {info['ground_truth']['creepage_mean'] / truth['peak_creepage']:.2f} | "
                    + (f"{_harmonics(m)} | " if harmonics else "")
                    + f"{swing / first_swing:.2f} | {m['creepage_modulation_lag_deg']:.1f} +- "
                    f"{m['creepage_modulation_lag_se_deg']:.1f} | {'yes' if info['macro_slip'] else ''} |")
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
    ap.add_argument("--harmonics", action="store_true", help="also read the speed's 2nd and 3rd harmonics")
    args = ap.parse_args()
    if args.harmonics and not 3 * args.frequency <= MotorLimits.max_frequency_hz:
        ap.error(f"--harmonics reads 3 x --frequency, which must be <= {MotorLimits.max_frequency_hz:g} Hz "
                 f"(the drive's range), got {args.frequency:g} Hz")
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
    env = gym.make(args.env or suite.env_id, **suite.env_kwargs, **(HARMONIC_OPTIONS if args.harmonics else {}))
    for k in args.episodes:
        seed, options = suite.episodes[k]
        options = {**options, **overrides}
        print(f"\n### episode {k} (seed {seed}): {options.get('condition')}, CoF {options.get('cof')}\n")
        extra = " H2 | H3 |" if args.harmonics else ""
        print(f"| DC / M_sat | lag [deg] | compliance | CoA / CoF | creepage / peak creepage |{extra} "
              "creepage swing / first | creepage lag [deg] | macro-slip |")
        print("|---" * (8 + 2 * args.harmonics) + "|")
        print("\n".join(trace(env, seed, options, args.levels, args.amplitude_ratio, args.frequency, args.harmonics)))


if __name__ == "__main__":
    main()
