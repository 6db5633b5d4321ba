"""Does a feature block tell the filter more? Held-out likelihood of one member per block set, on the
training climbs only (run from the repository root; 2 cores, ~3 min per block set on 8000 climbs):

    python experiments/feature_block_nll.py --climbs runs/climb_fit/climbs.npz --blocks none climb_fit \
        --out out/feature_block_nll.md
    python experiments/feature_block_nll.py --climbs runs/interrogator_torque/climbs_torque_wide.npz \
        --blocks none torque_free --out out/feature_block_nll_torque_free.md

The climbs' episodes are split once (``--seed``): a member per block set (``none``: the base features;
``a+b``: blocks a and b of ``FEATURE_BLOCKS``) is fitted by the recipe's settings on ``1 - --holdout`` of
them and scored on the rest: the RMSE and the mean Gaussian NLL of each target (the headroom
``ln(M_sat / DC)`` and the correction ``ln(CoF / CoA)``), over every held-out window and by the speed
measured and the true headroom (near the peak: at most 0.3). Training data only: no validation or
evaluation scenario is played, so nothing here selects a shipped network; a block's worth on the task is
decided by a rule on the validation grids (docs/interrogator.md).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from cof_gym.agents.interrogator import TARGET_NAMES
from cof_gym.commands.args import Parser, seed_int
from cof_gym.agents.interrogator.training import (
    FITTABLE_BLOCKS, READING_FIELDS, Dataset, FitSettings, fit_member, negative_log_likelihood,
)

sys.path.insert(0, str(Path(__file__).resolve().parent))
from script_checks import check_out_file, load_climbs  # noqa: E402

NEAR_PEAK = 0.3  # true headroom ln(M_sat / DC) at most this: the windows where a climb decides to stop
SPEED_BANDS_M_S = ((0.0, 10.0), (10.0, 20.0), (20.0, float("inf")))


def block_set(text: str) -> tuple[str, ...]:
    """``none`` or block names joined by ``+`` (argparse type: a one-line error for an unknown block)."""
    if text == "none":
        return ()
    blocks = tuple(text.split("+"))
    unknown = [b for b in blocks if b not in FITTABLE_BLOCKS]
    if unknown:
        raise argparse.ArgumentTypeError(f"unknown feature block {unknown[0]!r}; blocks are "
                                         f"{list(FITTABLE_BLOCKS)} (joined by +) or none")
    return blocks


def fraction(text: str) -> float:
    value = float(text)
    if not 0.05 <= value <= 0.5:
        raise argparse.ArgumentTypeError(f"--holdout must be within 0.05-0.5, got {text}")
    return value


def split_episodes(data: Dataset, holdout: float, seed: int) -> np.ndarray:
    """A boolean per window: whether its episode is held out (a ``holdout`` share of the episodes)."""
    episodes = np.unique(data.episode)
    rng = np.random.default_rng(seed)
    held = rng.choice(episodes, size=max(1, round(holdout * len(episodes))), replace=False)
    return np.isin(data.episode, held)


def scores(mu: np.ndarray, log_var: np.ndarray, targets: np.ndarray) -> list[float]:
    """RMSE and mean Gaussian NLL (with its constant) of each target, in TARGET_NAMES order."""
    out = []
    for k in range(len(TARGET_NAMES)):
        err = targets[:, k] - mu[:, k]
        nll = negative_log_likelihood("gaussian", err, log_var[:, k]) + 0.5 * np.log(2 * np.pi)
        out += [float(np.sqrt(np.mean(err**2))), float(np.mean(nll))]
    return out


def bands(data: Dataset) -> dict[str, np.ndarray]:
    """Masks of the windows by speed measured and by true headroom."""
    speed = data.readings[:, READING_FIELDS.index("speed_m_s")]
    masks = {"all": np.ones(len(data), bool)}
    for lo, hi in SPEED_BANDS_M_S:
        masks[f"speed {lo:g}-{hi:g} m/s" if np.isfinite(hi) else f"speed >= {lo:g} m/s"] = (speed >= lo) & (speed < hi)
    masks[f"true headroom <= {NEAR_PEAK:g}"] = data.targets[:, 0] <= NEAR_PEAK
    return masks


def main() -> None:
    ap = Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--climbs", type=Path, required=True, help="a climbs file written by train_interrogator.py")
    ap.add_argument("--blocks", type=block_set, nargs="+", default=[(), ("climb_fit",)], metavar="SET")
    ap.add_argument("--holdout", type=fraction, default=0.2)
    ap.add_argument("--seed", type=seed_int, default=0)
    ap.add_argument("--epochs", type=int, default=FitSettings.epochs)
    ap.add_argument("--out", type=Path, default=Path("out/feature_block_nll.md"))
    args = ap.parse_args()
    check_out_file(ap, "--out", args.out)
    if not args.climbs.is_file():
        ap.error(f"--climbs: no file {args.climbs}")
    if args.epochs < 1:
        ap.error(f"--epochs must be at least 1, got {args.epochs}")
    data = load_climbs(ap, "--climbs", args.climbs)
    held = split_episodes(data, args.holdout, args.seed)
    train = data.subset(np.flatnonzero(~held))
    masks = {name: mask[held] for name, mask in bands(data).items()}
    head = ["blocks", "windows held out", *(f"{t} {m}" for t in TARGET_NAMES for m in ("RMSE", "NLL"))]
    lines = [f"Command: `python experiments/feature_block_nll.py {' '.join(sys.argv[1:])}`", "",
             f"{len(np.unique(data.episode[~held]))} climbs fitted, {len(np.unique(data.episode[held]))} held out "
             f"({held.sum()} windows); one member per block set (seed {args.seed}, {args.epochs} epochs).", "",
             "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for blocks in args.blocks:
        t0 = time.time()
        member = fit_member(train, seed=args.seed, settings=FitSettings(epochs=args.epochs, features=blocks))
        mu, log_var = member(data.features_for(blocks)[held])
        name = "+".join(blocks) or "none"
        for band, mask in masks.items():
            values = scores(mu[mask], log_var[mask], data.targets[held][mask])
            lines.append(f"| {name}, {band} | {mask.sum()} | " + " | ".join(f"{v:.3f}" for v in values) + " |")
        print(f"{name}: fitted and scored in {time.time() - t0:.0f} s", flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
