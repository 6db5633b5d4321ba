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

With ``--candidate-threshold T`` it matches the noise exponent instead. A climb whose first windows read more noise
than the reference (its noise ratio ``r``, ``ClimbParameters.noise_ratio``; a slow drive reads as noise too) creeps
where the std exceeds ``creep_while_std x r ** noise_creep_exponent`` (``ClimbParameters.at_noise``). On the near-peak
held-apart windows of the climbs that read noisy (``r`` at least ``--min-ratio``, the interval's ``NOISY_RATIO`` by
default; the ratio each climb reads from its first windows, ``Dataset.noise_ratios``, as the reference's climb reads
it), this finds the share of windows whose reference std exceeds ``--threshold x r ** --exponent`` and the candidate's
largest exponent at which its std exceeds ``T x r ** exponent`` as often (bisection: the share falls as the
exponent grows):

    python experiments/match_creep_threshold.py --reference cof_gym/agents/policies/interrogator/guard_1 \
        --candidate runs/union120/guard_1 --candidate-threshold 0.089 \
        --climbs runs/interrogator_three/climbs_noisy_torque_wide.npz \
        runs/interrogator_three/climbs_procedural_noisy_torque_wide.npz
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


def matched_exponent(reference_std: np.ndarray, candidate_std: np.ndarray, ratio: np.ndarray, threshold: float,
                     exponent: float, candidate_threshold: float, high: float = 4.0) -> tuple[float, float, float]:
    """(share of ``reference_std`` above ``threshold x ratio ** exponent``, share of ``candidate_std`` above
    ``candidate_threshold x ratio ** exponent``, the largest exponent in [0, ``high``] at which the candidate's
    share is at least the reference's): bisection to 1e-6 on the candidate's share, which does not rise with the
    exponent (every ratio is at least 1); an end of the range where the share lies beyond it."""
    share = float(np.mean(reference_std > threshold * ratio ** exponent))
    candidate_share = lambda e: float(np.mean(candidate_std > candidate_threshold * ratio ** e))  # noqa: E731
    low = 0.0
    while high - low > 1e-6:
        middle = 0.5 * (low + high)
        low, high = (middle, high) if candidate_share(middle) >= share else (low, middle)
    return share, candidate_share(exponent), low


def predicted_stds(directory: Path, climbs: list) -> np.ndarray:
    """The headroom stds an ensemble predicts on every window of ``climbs``, every file's together."""
    from cof_gym.agents.interrogator.networks import FilterEnsemble

    ensemble = FilterEnsemble.load(directory)
    return np.concatenate([ensemble.predict(held.features_for(ensemble.blocks))[1][:, 0] for held in climbs])


def print_noise_exponent(args, reference: np.ndarray, candidate: np.ndarray, ratio: np.ndarray) -> None:
    """The noisy climbs' windows, both shares and the matched noise exponent (``--candidate-threshold``)."""
    share, at_reference, exponent = matched_exponent(reference, candidate, ratio, args.threshold, args.exponent,
                                                     args.candidate_threshold)
    t, e, c = args.threshold, args.exponent, args.candidate_threshold
    print(f"reference {args.reference}: std above {t:g} x r^{e:g} on {100 * share:.1f} % of them")
    print(f"candidate {args.candidate}: std above {c:g} x r^{e:g} on {100 * at_reference:.1f} %, above {c:g} x "
          f"r^{exponent:.3f} on as many as the reference (noise_creep_exponent {exponent:.2f})")


def main() -> None:
    from cof_gym.agents.interrogator import NOISY_RATIO, SHIPPED_INTERROGATOR, manifest_climb

    shipped = manifest_climb(SHIPPED_INTERROGATOR)
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("--reference", type=Path, required=True, help="the networks whose threshold is matched")
    parser.add_argument("--candidate", type=Path, required=True, help="the networks a threshold is found for")
    parser.add_argument("--climbs", nargs="+", required=True, type=Path, metavar="FILE",
                        help="climbs files train_interrogator.py collected (its runs' climbs_*.npz)")
    parser.add_argument("--threshold", type=positive_float, default=shipped.creep_while_std,
                        help="the reference's creep_while_std (log units, > 0; default: the shipped climb's)")
    parser.add_argument("--near", type=float_in_range(0.0, 5.0), default=0.15,
                        help="only windows whose true headroom is below this (log units, > 0; default 0.15)")
    parser.add_argument("--candidate-threshold", type=positive_float, default=None,
                        help="match the noise exponent at this candidate creep_while_std (log units, > 0) on the "
                             "climbs that read noisy, instead of the threshold")
    parser.add_argument("--exponent", type=float_in_range(0.0, 4.0), default=None,
                        help="with --candidate-threshold: the reference's noise_creep_exponent (0-4; default: the "
                             "shipped climb's)")
    parser.add_argument("--min-ratio", type=float_in_range(1.0, 100.0), default=None,
                        help=f"with --candidate-threshold: only climbs reading at least this noise ratio (1-100; "
                             f"default {NOISY_RATIO:g})")
    args = parser.parse_args()
    noisy = args.candidate_threshold is not None
    for option, value in (("--exponent", args.exponent), ("--min-ratio", args.min_ratio)):
        if value is not None and not noisy:
            parser.error(f"{option}: needs --candidate-threshold (the noise exponent's match)")
    args.exponent = shipped.noise_creep_exponent if args.exponent is None else args.exponent
    args.min_ratio = NOISY_RATIO if args.min_ratio is None else args.min_ratio
    require_networks(parser, "--reference", [args.reference])
    require_networks(parser, "--candidate", [args.candidate])
    climbs = [split(load_climbs(parser, "--climbs", path))[1] for path in args.climbs]
    chosen = np.concatenate([held.targets[:, 0] < args.near for held in climbs])
    if noisy:
        ratio = np.concatenate([held.noise_ratios(shipped) for held in climbs])
        chosen &= ratio >= args.min_ratio
    if not chosen.any():
        parser.error(f"--climbs: no held-apart window with a true headroom below {args.near:g} (--near)"
                     + (f" in a climb reading a noise ratio of at least {args.min_ratio:g}" if noisy else ""))
    reference = predicted_stds(args.reference, climbs)[chosen]
    candidate = predicted_stds(args.candidate, climbs)[chosen]
    print(f"held-apart windows with a true headroom below {args.near:g}"
          + (f" in climbs reading a noise ratio of at least {args.min_ratio:g} (median {np.median(ratio[chosen]):.2f})"
             if noisy else "") + f": {len(reference)}")
    if noisy:
        print_noise_exponent(args, reference, candidate, ratio[chosen])
        return
    share, threshold = matched_threshold(reference, candidate, args.threshold)
    print(f"reference {args.reference}: std above {args.threshold:g} on {100 * share:.1f} % of them")
    print(f"candidate {args.candidate}: std above {args.threshold:g} on {100 * np.mean(candidate > args.threshold):.1f} "
          f"%, above {threshold:.3f} on as many as the reference (creep_while_std {threshold:.3f})")


if __name__ == "__main__":
    main()
