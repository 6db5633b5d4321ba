"""How well the colour of a climb's speed-residual noise tells a smoothed encoder from a sharp one, and where the
learned interrogator's threshold lies (run from the repository root; training climbs only, seconds):

    python experiments/train_estimator.py --out runs/colour --collect-only \
        --climbs env=600 env_encoder=600 procedural=600 procedural_encoder=600
    python experiments/noise_colour_reading.py runs/colour/onpolicy_*.npz --out out/noise_colour_reading.md

The lock-in reports the lag's standard error twice: for a white residual and for a first-order autoregressive one
(``phase_lag_se_corrected_deg``, its lag-1 correlation read in the window). Their ratio, the *noise colour*
(:attr:`~cof_gym.agents.interrogator.readings.Reading.noise_colour`), is about 1 for an encoder's white noise; a
smoothing of the speed signal correlates successive samples and raises it several times over. Each climb reads the
least colour of its first driven windows (:func:`~cof_gym.agents.interrogator.readings.first_windows_noise_colour`);
this table gives its spread per collection (on-policy climbs of ``train_estimator.py``: the ``*_encoder`` ones lag
the encoder 0-20 ms, drawn per climb), by the drawn lag where the collection draws one, and the share of climbs
above :data:`~cof_gym.measurement.sine_fit.SMOOTHED_NOISE_COLOUR` where their noise reaches
:data:`~cof_gym.agents.interrogator.readings.COLOUR_NOISE_FLOOR_NMS`
(:func:`~cof_gym.agents.interrogator.readings.reads_smoothed_encoder`), where
:meth:`~cof_gym.agents.interrogator.LearnedInterrogator.sensor_notes` names a smoothed encoder. Nothing is fitted
here; the threshold and the floor were read off the sharp and the lagged training climbs (docs/interrogator.md).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

from cof_gym.commands.args import Parser

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from script_checks import check_out_file, load_climbs, write_report  # noqa: E402

LAG_BANDS_S = ((0.0, 0.001), (0.001, 0.002), (0.002, 0.005), (0.005, 0.02))  # the drawn lags' bands (s)
QUANTILES = (0, 1, 50, 99, 100)  # the colour's percentiles in the table
COLLECTION = re.compile(r"onpolicy_(?P<name>[a-z_]+?)_[0-9a-f]+\.npz$")  # train_estimator.py's cache file names


def climb_colours(data) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each climb's noise colour (:func:`first_windows_noise_colour`), its noise (:func:`first_windows_noise_nms`
    from the reported SEs, N m s) and whether it is flagged (:func:`reads_smoothed_encoder`), in a climbs file's
    ``data``."""
    from cof_gym.agents.interrogator.readings import (
        Reading, first_windows_noise_colour, first_windows_noise_nms, reads_smoothed_encoder,
    )

    climbs = [[Reading(*map(float, row)) for row in data.readings[rows]] for rows in data.climbs()]
    return (np.array([first_windows_noise_colour(c) for c in climbs]),
            np.array([first_windows_noise_nms(c, reported=True) for c in climbs]),
            np.array([reads_smoothed_encoder(c) for c in climbs]))


def collection_name(path: Path) -> str | None:
    """The on-policy collection a climbs file holds (``train_estimator.py``'s ``onpolicy_NAME_DIGEST.npz``), None
    for a file of another name."""
    match = COLLECTION.search(path.name)
    return match["name"] if match else None


def climb_lags_s(name: str | None, climbs: int) -> np.ndarray | None:
    """The encoder lag (s) each of the first ``climbs`` climbs of the on-policy collection ``name`` drew
    (``train_estimator.ON_POLICY``), None for no collection or one that draws none."""
    from train_estimator import ON_POLICY

    if name not in ON_POLICY or not ON_POLICY[name][1].encoder_lags_s:
        return None
    first_seed, draws = ON_POLICY[name]
    return np.array([draws.encoder_lag_s(first_seed + i) for i in range(climbs)])


def row(label: str, colours: np.ndarray, noise: np.ndarray, flagged: np.ndarray, floor: float) -> str:
    """A table row: the climbs, the colour's percentiles, the least noise, the shares below the noise ``floor`` and
    flagged."""
    percentiles = " / ".join(f"{v:.2f}" for v in np.percentile(colours, QUANTILES))
    return (f"| {label} | {len(colours)} | {percentiles} | {noise.min():.4f} | {100.0 * np.mean(noise < floor):.1f} | "
            f"{100.0 * np.mean(flagged):.1f} |")


def main() -> None:
    from cof_gym.agents.interrogator.readings import COLOUR_NOISE_FLOOR_NMS
    from cof_gym.measurement.sine_fit import SMOOTHED_NOISE_COLOUR

    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("climbs", nargs="+", type=Path, metavar="FILE",
                        help="climbs files (train_estimator.py's onpolicy_NAME_DIGEST.npz, read by name for the lags)")
    parser.add_argument("--out", type=Path, default=None, help="also write the table there as Markdown")
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    files = [(path, load_climbs(parser, "climbs", path)) for path in args.climbs]
    lines = ["# A smoothed encoder read from the speed residual's colour", "",
             f"Each climb's noise colour: the least, over its first driven windows, of the lag's SE for a first-order "
             f"autoregressive residual over its white-noise SE (about 1 for white noise). Flagged: above "
             f"{SMOOTHED_NOISE_COLOUR:g} where the windows' noise is at least {COLOUR_NOISE_FLOOR_NMS:g} N m s.", "",
             f"| climbs | n | colour: {' / '.join(f'{q} %' for q in QUANTILES)} | least noise [N m s] | "
             "noise below the floor [%] | flagged [%] |", "|---|---|---|---|---|---|"]
    for path, data in files:
        colours, noise, flagged = climb_colours(data)
        if not len(colours):
            parser.error(f"climbs: {path} holds no climb")
        collection = collection_name(path)
        name = collection or path.name
        lines.append(row(name, colours, noise, flagged, COLOUR_NOISE_FLOOR_NMS))
        lags = climb_lags_s(collection, len(colours))
        for low, high in LAG_BANDS_S if lags is not None else ():
            band = (lags >= low) & (lags < high)
            if band.any():
                lines.append(row(f"{name}, lag {1e3 * low:g}-{1e3 * high:g} ms", colours[band], noise[band],
                                 flagged[band], COLOUR_NOISE_FLOOR_NMS))
    write_report(args.out, lines)


if __name__ == "__main__":
    main()
