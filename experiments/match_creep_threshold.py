"""The slow probe's threshold for other networks, matched to a reference's trigger rate on held-apart training climbs
(run from the repository root; training data only, seconds):

    python experiments/match_creep_threshold.py --reference cof_gym/agents/policies/interrogator \
        --candidate runs/union120/filter --climbs runs/interrogator_three/climbs_torque_wide.npz \
        runs/interrogator_three/climbs_procedural_torque_wide.npz

The climb creeps (its slow probe, ``ClimbParameters.creep_while_std``) where the cautious gap to the target is closed
and the predicted headroom's std still exceeds the threshold. Networks whose stds lie on another scale (an ensemble
pooled from two generations adds their disagreement to every std) creep on other windows at the same threshold. On
the held-apart tenth of the given climbs files (the windows no fit saw), restricted to the windows near the peak (true
headroom ``ln(M_sat / DC)`` below ``--near``, where the gap closes), this finds the share of windows whose reference
std exceeds ``--threshold`` and the candidate's threshold exceeded by the same share: the ``(1 - share)`` quantile of
the candidate's stds there. It prints both shares at ``--threshold`` and the matched threshold; nothing is played or
chosen here.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from cof_gym.commands.args import Parser, float_in_range, positive_float

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from script_checks import load_climbs  # noqa: E402
from train_interrogator import require_networks, split  # noqa: E402


def matched_threshold(reference_std: np.ndarray, candidate_std: np.ndarray, threshold: float) -> tuple[float, float]:
    """(share of ``reference_std`` above ``threshold``, the threshold ``candidate_std`` exceeds as often): the
    ``(1 - share)`` quantile of ``candidate_std`` (linear interpolation between order statistics)."""
    share = float(np.mean(reference_std > threshold))
    return share, float(np.quantile(candidate_std, 1.0 - share))


def near_peak_stds(directory: Path, climbs: list, near: float) -> np.ndarray:
    """The headroom stds an ensemble predicts on the held-apart windows of ``climbs`` whose true headroom is below
    ``near``, every file's together."""
    from cof_gym.agents.interrogator.networks import FilterEnsemble

    ensemble = FilterEnsemble.load(directory)
    out = []
    for held in climbs:
        _, std = ensemble.predict(held.features_for(ensemble.blocks))
        out.append(std[held.targets[:, 0] < near, 0])
    return np.concatenate(out)


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("--reference", type=Path, required=True, help="the networks whose threshold is matched")
    parser.add_argument("--candidate", type=Path, required=True, help="the networks a threshold is found for")
    parser.add_argument("--climbs", nargs="+", required=True, type=Path, metavar="FILE",
                        help="climbs files train_interrogator.py collected (its runs' climbs_*.npz)")
    parser.add_argument("--threshold", type=positive_float, default=0.08,
                        help="the reference's creep_while_std (log units, > 0; default 0.08, the shipped climb's)")
    parser.add_argument("--near", type=float_in_range(0.0, 5.0), default=0.15,
                        help="only windows whose true headroom is below this (log units, > 0; default 0.15)")
    args = parser.parse_args()
    require_networks(parser, "--reference", [args.reference])
    require_networks(parser, "--candidate", [args.candidate])
    climbs = [split(load_climbs(parser, "--climbs", path))[1] for path in args.climbs]
    reference = near_peak_stds(args.reference, climbs, args.near)
    if not len(reference):
        parser.error(f"--climbs: no held-apart window with a true headroom below {args.near:g} (--near)")
    candidate = near_peak_stds(args.candidate, climbs, args.near)
    share, threshold = matched_threshold(reference, candidate, args.threshold)
    print(f"held-apart windows with a true headroom below {args.near:g}: {len(reference)}")
    print(f"reference {args.reference}: std above {args.threshold:g} on {100 * share:.1f} % of them")
    print(f"candidate {args.candidate}: std above {args.threshold:g} on {100 * np.mean(candidate > args.threshold):.1f} "
          f"%, above {threshold:.3f} on as many as the reference (creep_while_std {threshold:.3f})")


if __name__ == "__main__":
    main()
