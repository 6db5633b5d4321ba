"""How well a climb's first windows tell a lagged encoder from a sharp one (run from the repository root; training
data only, seconds):

    python experiments/encoder_lag_reading.py --sharp runs/interrogator_three/climbs_torque_wide.npz \
        runs/interrogator_three/climbs_procedural_torque_wide.npz \
        --lagged runs/interrogator_three/climbs_torque_wide_encoder.npz \
        runs/interrogator_three/climbs_procedural_torque_wide_encoder.npz --out out/encoder_lag_reading.md

A first-order lag of the speed signal (time constant ``tau``) delays the measured wheel speed by ``atan(w tau)`` at
the modulation's ``w``: about 17 deg at 5 Hz and 10 ms, on top of the wheel's own lag, which is small far below the
peak. A gate that routes a climb to networks fitted on lagged encoders would read it from the windows before the
climb nears the peak. For each number of first windows ``k`` (``--windows``), each climb's inverse-variance weighted
mean phase lag over its first ``k`` driven windows (weights ``1 / se^2``, the standard error floored at
:data:`SE_FLOOR_DEG`) is compared between the climbs collected with a sharp encoder (``--sharp``) and with a lagged
one (``--lagged``, e.g. the recipe's encoder lags drawn in 0-20 ms): their medians and the area under the ROC curve
of a threshold on it (the probability that a lagged climb reads more than a sharp one, ties counted half: the
Mann-Whitney statistic over the product of the counts; 0.5: no better than chance). Nothing is fitted or chosen here.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.stats import mannwhitneyu

from cof_gym.commands.args import Parser, positive_int

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from script_checks import check_out_file, load_climbs, write_report  # noqa: E402

SE_FLOOR_DEG = 0.5  # the weights' floor on a window's phase standard error (deg): no window weighs more than this


def first_windows_phase(data, windows: int) -> np.ndarray:
    """Each climb's inverse-variance weighted mean phase lag (deg) over its first ``windows`` driven windows, from a
    climbs file's :class:`~cof_gym.agents.interrogator.training.Dataset` ``data``."""
    from cof_gym.agents.interrogator.training import READING_FIELDS

    phase, se = (data.readings[:, READING_FIELDS.index(name)] for name in ("phase_deg", "se_deg"))
    out = []
    for rows in data.climbs():
        weights = 1.0 / np.maximum(se[rows][:windows], SE_FLOOR_DEG) ** 2
        out.append(float(np.sum(weights * phase[rows][:windows]) / np.sum(weights)))
    return np.array(out)


def auc(lagged: np.ndarray, sharp: np.ndarray) -> float:
    """P(a lagged climb's value > a sharp climb's), ties counted half (Mann-Whitney U over the pairs)."""
    return float(mannwhitneyu(lagged, sharp).statistic) / (len(lagged) * len(sharp))


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("--sharp", nargs="+", required=True, type=Path, metavar="FILE",
                        help="climbs files collected with a sharp encoder (train_interrogator.py's climbs_*.npz)")
    parser.add_argument("--lagged", nargs="+", required=True, type=Path, metavar="FILE",
                        help="climbs files collected with a lagged encoder")
    parser.add_argument("--windows", nargs="+", type=positive_int, default=[1, 3, 5, 8], metavar="K",
                        help="numbers of first windows read (positive integers; default 1 3 5 8)")
    parser.add_argument("--out", type=Path, default=None, help="also write the table there as Markdown")
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    files = {option: [load_climbs(parser, option, path) for path in getattr(args, option[2:])]
             for option in ("--sharp", "--lagged")}
    lines = ["# A lagged encoder read from a climb's first windows", "",
             f"Each climb's inverse-variance weighted mean phase lag over its first k driven windows (standard errors "
             f"floored at {SE_FLOOR_DEG:g} deg); AUC: the probability that a lagged climb reads more than a sharp one "
             f"(0.5: chance).", "",
             "| first windows | climbs: sharp / lagged | median phase: sharp / lagged (deg) | AUC |",
             "|---|---|---|---|"]
    for k in args.windows:
        sharp, lagged = (np.concatenate([first_windows_phase(data, k) for data in files[option]])
                         for option in ("--sharp", "--lagged"))
        lines.append(f"| {k} | {len(sharp)} / {len(lagged)} | {np.median(sharp):.1f} / {np.median(lagged):.1f} | "
                     f"{auc(lagged, sharp):.3f} |")
    write_report(args.out, lines)


if __name__ == "__main__":
    main()
