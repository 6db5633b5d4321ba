"""Where do networks overstate the headroom? Each filter or guard ensemble's signed headroom error on the
held-apart tenth of training climbs (the climbs train_interrogator.py's fit never saw), by the true headroom
near the peak (run from the repository root; 2 cores, 7 s for the four files and five networks below):

    python experiments/headroom_bias.py --networks shipped=cof_gym/agents/policies/interrogator \
        LF=runs/interrogator_encoder/ensemble guard_0=cof_gym/agents/policies/interrogator/guard_0 \
        guard_1=cof_gym/agents/policies/interrogator/guard_1 guard_LF=runs/interrogator_encoder/guard/ensemble \
        --climbs \
        runs/interrogator_encoder/climbs_torque_wide.npz runs/interrogator_encoder/climbs_torque_wide_encoder.npz \
        runs/interrogator_encoder/climbs_procedural_torque_wide.npz \
        runs/interrogator_encoder/climbs_procedural_torque_wide_encoder.npz --out out/headroom_bias_rule113.md

For every climbs file, network and band of the true headroom ``h = ln(M_sat / DC)``: the mean of the predicted
minus the true headroom (> 0: the network reads the wheel farther from the peak than it is) and the share of
windows whose cautious bound ``mean - caution x std`` (the climb's, ``--caution``) still lies above the truth,
where a climb that trusts the network alone would step on. The climbs are those the shipped climb drove (off
policy): a network's own climbs differ once it steers. Training data only: nothing here selects a network.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from cof_gym.agents.interrogator.climb import BOUNDED_FIELDS
from cof_gym.commands.args import DistinctNames, Parser, float_in_range, name_path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from script_checks import check_out_file, load_climbs, write_report  # noqa: E402
from train_interrogator import require_networks, split  # noqa: E402

BANDS = ((-np.inf, 0.05), (0.05, 0.15), (0.15, 0.4))  # true headroom ln(M_sat / DC): at, near and short of the peak
CAUTION_RANGE = BOUNDED_FIELDS["caution"][:2]  # the climb's own range for its caution


def band_errors(mean: np.ndarray, std: np.ndarray, truth: np.ndarray, caution: float) -> list[tuple[int, float, float]]:
    """Per band of :data:`BANDS` (lower bound inclusive): (windows, mean of ``mean - truth``, share of windows with
    ``mean - caution std > truth``); NaN for a band with no window."""
    out = []
    for low, high in BANDS:
        rows = (truth >= low) & (truth < high)
        n = int(rows.sum())
        if not n:
            out.append((0, float("nan"), float("nan")))
            continue
        bias = float(np.mean(mean[rows] - truth[rows]))
        over = float(np.mean(mean[rows] - caution * std[rows] > truth[rows]))
        out.append((n, bias, over))
    return out


def band_label(low: float, high: float) -> str:
    return f"h < {high:g}" if low == -np.inf else f"{low:g} <= h < {high:g}"


def build_parser() -> Parser:
    p = Parser(description="Signed headroom error of filter and guard ensembles on held-apart training climbs.")
    p.add_argument("--networks", nargs="+", required=True, type=name_path, action=DistinctNames, metavar="NAME=DIR",
                   help="network directories (member_*.npz), each under a name of its own")
    p.add_argument("--climbs", nargs="+", required=True, type=Path, metavar="FILE",
                   help="climbs files train_interrogator.py collected (its runs' climbs_*.npz)")
    p.add_argument("--caution", type=float_in_range(*CAUTION_RANGE, low_inclusive=True), default=2.0,
                   help=f"standard deviations taken off the prediction, as the climb's caution "
                        f"({CAUTION_RANGE[0]:g}-{CAUTION_RANGE[1]:g}; default 2, the shipped climb's)")
    p.add_argument("--out", type=Path, default=None, help="also write the table there as Markdown")
    return p


def main() -> None:
    parser = build_parser()
    args = parser.parse_args()
    require_networks(parser, "--networks", [directory for _, directory in args.networks])
    check_out_file(parser, "--out", args.out)
    held_apart = {path: split(load_climbs(parser, "--climbs", path))[1] for path in args.climbs}
    for path, held in held_apart.items():
        if not len(held):
            parser.error(f"--climbs: {path} holds fewer than ten climbs (nothing held apart)")
    from cof_gym.agents.interrogator.networks import FilterEnsemble

    networks = {name: FilterEnsemble.load(directory) for name, directory in args.networks}
    header = " | ".join(f"{band_label(*band)}: windows / bias / bound above" for band in BANDS)
    lines = ["# Headroom error on held-apart training climbs", "",
             f"Held apart: every tenth climb of each file. Bias: mean predicted minus true `ln(M_sat / DC)`; bound "
             f"above: the share of windows whose `mean - {args.caution:g} std` exceeds the truth.", "",
             f"| climbs | network | {header} |", "|---|---|" + "---|" * len(BANDS)]
    for path, held in held_apart.items():
        truth = held.targets[:, 0]
        for name, ensemble in networks.items():
            mean, std = ensemble.predict(held.features_for(ensemble.blocks))
            cells = [f"{n} / {bias:+.3f} / {over:.3f}" for n, bias, over in
                     band_errors(mean[:, 0], std[:, 0], truth, args.caution)]
            lines.append(f"| {path.stem.removeprefix('climbs_')} | {name} | {' | '.join(cells)} |")
    write_report(args.out, lines)


if __name__ == "__main__":
    main()
