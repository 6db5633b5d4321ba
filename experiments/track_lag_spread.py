"""How far a track moves the phase lag a window reads: a diagnostic, not an agent (it reads the truth to hold the DC).

    python experiments/track_lag_spread.py --out out/track_lag_spread.md

On task v3's wagon (``CofGym/TorqueInterrogationInService-v3``), each of the first ``--episodes`` seeds of the
in-service suite is played with its drawn creep curve, sensors and speed probe on each track class (``--tracks``:
level, ORE B176 low and high irregularity), its DC torque held at ``--level`` of the episode's true saturation torque
for ``--windows`` windows, modulated at each frequency (``--frequencies``) with each modulation ratio
(``--ratios``: the amplitude over the DC). A held operating point has one true lag, so the spread of the lags its
windows read (their standard deviation, the first window, which ramps, left out) is the reading's own error; the
lock-in's standard error says what it should be for white noise. Per setting, over the episodes: the median lag, the
median spread, the median reported SE and the median of each episode's spread over its median SE (1: the SE tells the
truth; several: windows swing by more than the jump tests and the networks reading it expect). Nothing is fitted or
chosen here.
"""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np

import cof_gym
from cof_gym.commands.args import Parser, float_in_range, positive_int
from cof_gym.commands.suites import make_suite
from cof_gym.physics.track import TRACK_SPECTRA
from cof_gym.task.interface import MotorLimits

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from lag_near_peak import windows  # noqa: E402
from script_checks import check_out_file, write_report  # noqa: E402

TRACKS = ("smooth", *TRACK_SPECTRA)  # the level track (no profile) and every class a scenario may name
MIN_WINDOWS = 3  # a spread needs two windows after the ramped first


def lag_spread(env, seed: int, options: dict, level: float, ratio: float, frequency_hz: float,
               n_windows: int) -> tuple[float, float, float]:
    """(median lag, spread of the lags, median reported SE), deg, of one episode's windows at a held DC, the first
    (ramped) window left out."""
    _, played = windows(env, seed, options, [level] * n_windows, ratio, frequency_hz)
    lags = np.array([w.reading.phase_deg for w in played[1:]])
    ses = np.array([w.reading.se_deg for w in played[1:]])
    return float(np.median(lags)), float(np.std(lags, ddof=1)), float(np.median(ses))


def table(env, episodes, tracks, frequencies, ratios, level: float, n_windows: int) -> list[str]:
    """Markdown rows, one per (track, frequency, ratio), medians over ``episodes`` ((seed, options) pairs)."""
    rows = ["| track | frequency [Hz] | modulation / DC | median lag [deg] | spread [deg] | reported SE [deg] | "
            "spread / SE |", "|---|---|---|---|---|---|---|"]
    for track, f, ratio in itertools.product(tracks, frequencies, ratios):
        per_episode = np.array([lag_spread(env, seed, {**options, "track_irregularity": track}, level, ratio, f,
                                           n_windows) for seed, options in episodes])
        lag, spread, se = np.median(per_episode, axis=0)
        ratio_se = np.median(per_episode[:, 1] / np.maximum(per_episode[:, 2], 1e-9))
        rows.append(f"| {track} | {f:g} | {ratio:g} | {lag:.1f} | {spread:.2f} | {se:.2f} | {ratio_se:.2f} |")
    return rows


def main() -> None:
    ap = Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--episodes", type=positive_int, default=6, help="the in-service suite's first N seeds")
    ap.add_argument("--level", type=float_in_range(0.0, 1.0), default=0.5,
                    help="the held DC over the true saturation torque, in (0, 1]")
    ap.add_argument("--windows", type=positive_int, default=7, help=f"windows per setting, at least {MIN_WINDOWS}")
    ap.add_argument("--frequencies", type=float_in_range(MotorLimits.min_frequency_hz, MotorLimits.max_frequency_hz,
                                                         True), nargs="+", default=[5.0, 8.0, 12.0, 20.0],
                    help=f"Hz, within the drive's [{MotorLimits.min_frequency_hz:g}, {MotorLimits.max_frequency_hz:g}]")
    ap.add_argument("--ratios", type=float_in_range(0.0, 1.0), nargs="+", default=[0.1, 0.4],
                    help="modulation amplitudes over the DC, each in (0, 1]")
    ap.add_argument("--tracks", nargs="+", choices=TRACKS, default=list(TRACKS))
    ap.add_argument("--out", type=Path, default=None, help="also write the table here (markdown)")
    args = ap.parse_args()
    check_out_file(ap, "--out", args.out)
    if args.windows < MIN_WINDOWS:
        ap.error(f"--windows must be at least {MIN_WINDOWS} (the first ramps; a spread needs two more), "
                 f"got {args.windows}")
    suite = make_suite("in-service", args.episodes, 0)
    env = gym.make(cof_gym.WAGON_IN_SERVICE_ENV_ID, **suite.env_kwargs)
    lines = [f"In-service seeds 0-{args.episodes - 1}, DC held at {args.level:g} of the true saturation torque, "
             f"{args.windows} windows per setting (the first left out); medians over the episodes.", "",
             *table(env, list(suite.episodes), args.tracks, args.frequencies, args.ratios, args.level, args.windows)]
    env.close()
    write_report(args.out, lines)


if __name__ == "__main__":
    main()
