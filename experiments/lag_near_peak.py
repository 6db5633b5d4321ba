"""What the sensors show on the way to the peak: a diagnostic, not an agent (it reads the truth).

    python experiments/lag_near_peak.py --suite experiments/suites/v2_validation_grid.json --episodes 12 18 27

For each chosen episode of a suite file it steps the DC torque through fixed fractions of the episode's
true saturation torque (``--levels``) with a modulation of ``--amplitude-ratio`` x DC at
``--frequency`` Hz, and prints per window the measured phase lag (deg, with its standard error), the
compliance (speed/torque amplitude ratio x I w: 1 for a free wheel), the measured CoA over the CoF and
the crest of the measured CoA's synchronous average over the cycle (``coa_cycle_max``, a sensor reading)
over the CoF with its bin's standard error, the true mean creepage over the peak creepage, and the
measured creepage's own modulation (a sensor reading: its swing per torque over the first window's, and
its lag behind the torque with its standard error). It shows how late the lag rises on sharp-kneed curves,
the reason the learned interrogator and the phase rule commit below the peak. ``--env`` plays the same
episodes in another env (e.g. ``CofGym/HalfWheelset-v2``, the wheelset without the wagon) and ``--set
NAME=VALUE`` overrides a reset option of every chosen episode (checked before any simulation, e.g. ``motor_lag_s=0``):

    python experiments/lag_near_peak.py --episodes 6 --levels 0.3 0.6 0.8 0.85 0.88 --amplitude-ratio 0.4 \
        --set load_case=laden motor_lag_s=0 [--env CofGym/HalfWheelset-v2]

``--harmonics`` drives the env's three-tone excitation with tones 2 and 3 silent (weight 0) at twice and
three times the modulation frequency: the torque is the same sine, and their lock-ins read the wheelset
speed's second and third harmonics, printed relative to the fundamental (H2, H3): the distortion a
curved or kinked creep curve puts on the response.

``--hold-dc F`` runs a held-DC amplitude probe instead of the staircase: the DC torque stays at ``F`` of
the saturation torque and ``--levels`` are the modulation's crest (DC + amplitude) over it, the amplitude
at most the drive's (:class:`~cof_gym.task.interface.MotorLimits`; a row marks where that limit cut it).
Below the peak the crest reaches into the knee while the trough pulls the wheel back; past it, the DC
is below the falling branch for longer than a DC climb's is. ``--summary`` prints one table over the
chosen episodes (``--all-episodes``: every episode of the suite; ``--counter-torque``: in the paper's
configuration) instead of one per episode: per level, the episodes that reached it, the macro-slips at
it, the windows whose amplitude the drive cut, and over the episodes the drive did not cut their number,
their macro-slips, the median lag, its median rise since the first level and the median of the measured
creepage's swing per torque over the first level's and, over those not running away at that level, the
median shift of the measured mean creepage since the first level in peak creepages (a held DC's mean
force is fixed, so a crest that clips at a rounded peak must raise the mean creepage) and the crest bound
(the measured CoA's cycle crest less a bin's standard error) over the CoF, its median and 10th percentile
(how near a crest past the knee reads the peak: session 24); then how many
episodes the drive never cut, how many of those ran away, and the mean creepage's shift in the window
before each runaway (``--out FILE``: also written there):

    python experiments/lag_near_peak.py --suite experiments/suites/v2_validation_steep_grid.json \
        --all-episodes --summary --levels 0.9 0.95 1 1.05 1.1 1.15 1.2 1.3 --hold-dc 0.7
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import NamedTuple

import gymnasium as gym

import numpy as np

from cof_gym import ENV_IDS
from cof_gym.agents.interrogator import Reading
from cof_gym.agents.runaway import crest_bound
from cof_gym.commands.args import Parser, float_in_range
from cof_gym.commands.suites import SuiteError, make_suite, scenario_option
from cof_gym.task.excitation import encode_extra_tones
from cof_gym.task.interface import MotorLimits, encode_action

HARMONIC_OPTIONS = {"excitation": "multitone", "tones": 3}  # tones 2 and 3 silent at 2 f and 3 f

LEVELS = (0.3, 0.5, 0.7, 0.8, 0.85, 0.9, 0.93, 0.95, 0.97, 0.98, 0.99)
MAX_LEVEL = 1.5  # a DC or crest at most this many saturation torques (--levels, --hold-dc)
DEFAULT_SUITE = Path(__file__).resolve().parent / "suites" / "v2_validation_grid.json"  # wherever run from

sys.path.insert(0, str(Path(__file__).resolve().parent))
from script_checks import check_out_file  # noqa: E402


def _harmonics(measurement: dict) -> str:
    """The speed's second and third harmonics over its fundamental (silent tones 2 and 3)."""
    fundamental = max(measurement["tone1_omega_amplitude_rad_s"], 1e-12)
    return " | ".join(f"{measurement[f'tone{k}_omega_amplitude_rad_s'] / fundamental:.3f}" for k in (2, 3))


class Window(NamedTuple):
    """One window of a staircase or an amplitude probe, as the tables print it."""

    level: float  # the DC (staircase) or the crest (held-DC probe) over the true saturation torque
    reading: Reading
    info: dict
    clipped: bool  # the drive's amplitude limit cut the modulation


def _swing(window: Window) -> float:
    """The measured creepage's modulation amplitude per N m of torque amplitude (a sensor reading)."""
    m = window.info["measurement"]
    return m["creepage_modulation_amplitude"] / max(m["torque_amplitude_nm"], 1e-9)


def _creepage_shift(episode: list[Window], k: int) -> float:
    """The measured mean creepage's change from the first window to window ``k``, in peak creepages (the
    sensors' offset cancels in the difference; the peak creepage is the truth's). At a held DC the mean
    force stays DC / R, so a force that clips at the peak must be made up below it: the mean creepage
    rises (Jensen's inequality) once the crest passes a rounded peak."""
    first, m = episode[0].info["measurement"], episode[k].info["measurement"]
    return (m["creepage_measured"] - first["creepage_measured"]) / episode[k].info["ground_truth"]["peak_creepage"]


def _crest_bound_over_cof(window: Window) -> float:
    """The window's crest bound (the measured CoA's cycle crest less a bin's standard error, a sensor reading:
    :func:`~cof_gym.agents.runaway.crest_bound`) over the true CoF: how near a crest that reaches into
    the knee reads the peak."""
    return crest_bound(window.info["measurement"]) / window.info["ground_truth"]["cof"]


def _uncut(episode: list[Window], upto: int | None = None) -> bool:
    """Whether the drive's amplitude limit cut none of the episode's windows (up to index ``upto``)."""
    return not any(w.clipped for w in episode[:None if upto is None else upto + 1])


def _slips(episodes: list[list[Window]], k: int) -> int:
    """How many of ``episodes`` ran away in their window ``k``."""
    return sum(bool(e[k].info["macro_slip"]) for e in episodes)


def _percentile(values: list[float], q: float, digits: int = 3) -> str:
    """The ``q`` th percentile of ``values`` to ``digits`` decimals, "-" for none."""
    return f"{np.percentile(values, q):.{digits}f}" if values else "-"


def _median(values: list[float], digits: int = 1) -> str:
    return f"{float(np.median(values)):.{digits}f}" if values else "-"


def drive(level: float, hold_dc: float | None, amplitude_ratio: float) -> tuple[float, float]:
    """(DC, amplitude) over the saturation torque at ``level``: the staircase's DC ``level`` and
    ``amplitude_ratio`` of it, or with ``hold_dc`` the held DC and the amplitude that puts the crest at
    ``level``."""
    if hold_dc is None:
        return level, amplitude_ratio * level
    return hold_dc, level - hold_dc


def windows(env, seed: int, options: dict, levels, amplitude_ratio: float, frequency_hz: float,
            harmonics: bool = False, hold_dc: float | None = None) -> tuple[dict, list[Window]]:
    """(the episode's ground truth, its windows): one window per level, until the episode ends."""
    limits = env.unwrapped.limits
    _, info = env.reset(seed=seed, options=options)
    truth = info["ground_truth"]
    m_sat = truth["saturation_torque_nm"]
    silent = encode_extra_tones([(2 * frequency_hz, 0.0), (3 * frequency_hz, 0.0)], limits.min_frequency_hz,
                                limits.max_frequency_hz) if harmonics else np.zeros(0, dtype=np.float32)
    out = []
    for u in levels:
        dc, amplitude = (m_sat * x for x in drive(u, hold_dc, amplitude_ratio))
        action = np.concatenate([encode_action(dc, amplitude, frequency_hz, 0.1, False, limits), silent])
        obs, _, terminated, truncated, info = env.step(action)
        out.append(Window(u, Reading.of(obs, limits), info, amplitude > limits.max_amplitude_nm))
        if terminated or truncated:
            break
    return truth, out


def trace(env, seed: int, options: dict, levels, amplitude_ratio: float, frequency_hz: float,
          harmonics: bool = False, hold_dc: float | None = None) -> list[str]:
    """Markdown rows, one per window of the staircase (or of the held-DC probe)."""
    truth, played = windows(env, seed, options, levels, amplitude_ratio, frequency_hz, harmonics, hold_dc)
    rows, first_swing = [], None
    for w in played:
        r, m = w.reading, w.info["measurement"]
        swing = _swing(w)
        first_swing = first_swing or swing
        rows.append(f"| {w.level:.2f}{' (cut)' if w.clipped else ''} | {r.phase_deg:.1f} +- {r.se_deg:.1f} | "
                    f"{r.compliance:.3f} | {r.coa / truth['cof']:.3f} | {m['coa_cycle_max'] / truth['cof']:.3f} +- "
                    f"{m['coa_cycle_bin_se'] / truth['cof']:.3f} | "
                    f"{w.info['ground_truth']['creepage_mean'] / truth['peak_creepage']:.2f} | "
                    + (f"{_harmonics(m)} | " if harmonics else "")
                    + f"{swing / first_swing:.2f} | {m['creepage_modulation_lag_deg']:.1f} +- "
                    f"{m['creepage_modulation_lag_se_deg']:.1f} | {'yes' if w.info['macro_slip'] else ''} |")
    return rows


def summary(episodes: list[list[Window]], levels) -> list[str]:
    """Markdown rows over many episodes, one per level: episodes that reached it, macro-slips at it,
    windows the drive's amplitude limit cut, and over the episodes it never cut up to that level their
    number, their macro-slips at it, the median lag, the median rise of the lag since the first level
    (deg), the median of the measured creepage's swing per torque over the first level's and, over those not
    running away at it, the median shift of the mean creepage and the crest bound over the CoF (its median
    and 10th percentile)."""
    rows = []
    for k, level in enumerate(levels):
        reached = [e for e in episodes if len(e) > k]
        uncut = [e for e in reached if _uncut(e, k)]
        lags = [e[k].reading.phase_deg for e in uncut]
        rises = [e[k].reading.phase_deg - e[0].reading.phase_deg for e in uncut]
        swings = [_swing(e[k]) / _swing(e[0]) for e in uncut]
        shifts = [_creepage_shift(e, k) for e in uncut if not e[k].info["macro_slip"]]
        bounds = [_crest_bound_over_cof(e[k]) for e in uncut if not e[k].info["macro_slip"]]
        rows.append(f"| {level:.2f} | {len(reached)} | {_slips(reached, k)} | {sum(e[k].clipped for e in reached)} | "
                    f"{len(uncut)} | {_slips(uncut, k)} | {_median(lags)} | {_median(rises)} | {_median(swings)} | "
                    f"{_median(shifts, 2)} | {_median(bounds, 3)} / {_percentile(bounds, 10)} |")
    return rows


def before_runaway(episodes: list[list[Window]]) -> str:
    """A line: the episodes that ran away after their first window, and the measured mean creepage's shift
    (:func:`_creepage_shift`) in the window before the runaway: the warning a held probe would have had."""
    shifts = [_creepage_shift(e, len(e) - 2) for e in episodes if len(e) > 1 and e[-1].info["macro_slip"]]
    if not shifts:
        return "No episode ran away after its first window."
    return (f"Episodes that ran away after their first window: {len(shifts)}; the measured mean creepage's shift "
            f"in the window before, in peak creepages: median {_median(shifts, 2)}, largest {max(shifts):.2f}.")


def never_cut(episodes: list[list[Window]]) -> str:
    """A line: the episodes whose amplitude the drive never cut, and how many of them ran away."""
    uncut = [e for e in episodes if _uncut(e)]
    return (f"Episodes whose amplitude the drive never cut: {len(uncut)} of {len(episodes)}; "
            f"macro-slips among them: {_slips(uncut, -1)}.")


def main() -> None:
    ap = Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--suite", default=str(DEFAULT_SUITE))
    ap.add_argument("--episodes", type=int, nargs="+", default=[12, 18, 27], help="indices into the suite")
    ap.add_argument("--levels", type=float_in_range(0.0, MAX_LEVEL), nargs="+", default=list(LEVELS),
                    help=f"DC / true M_sat per window, each in (0, {MAX_LEVEL:g}]")
    ap.add_argument("--amplitude-ratio", type=float_in_range(0.0, 1.0), default=0.05,
                    help="the modulation's amplitude over the DC, in (0, 1]")
    ap.add_argument("--frequency", type=float_in_range(MotorLimits.min_frequency_hz, MotorLimits.max_frequency_hz, True),
                    default=5.0, help=f"Hz, within the drive's range [{MotorLimits.min_frequency_hz:g}, "
                                      f"{MotorLimits.max_frequency_hz:g}]")
    ap.add_argument("--env", default=None, choices=ENV_IDS, help="play the episodes in this env id instead of the suite's")
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE", type=scenario_option,
                    help="a reset option over every episode's own (a scenario field and a value the env accepts)")
    ap.add_argument("--harmonics", action="store_true", help="also read the speed's 2nd and 3rd harmonics")
    ap.add_argument("--hold-dc", type=float, default=None, metavar="F",
                    help="a held-DC amplitude probe: DC at F x M_sat, --levels the crest / M_sat")
    ap.add_argument("--summary", action="store_true", help="one table over the chosen episodes")
    ap.add_argument("--all-episodes", action="store_true", help="every episode of the suite")
    ap.add_argument("--counter-torque", action="store_true", help="the paper's vehicle configuration")
    ap.add_argument("--out", type=Path, default=None, help="with --summary: also write the table here")
    args = ap.parse_args()
    check_out_file(ap, "--out", args.out)
    if args.hold_dc is not None:
        if not 0.0 < args.hold_dc <= MAX_LEVEL:
            ap.error(f"--hold-dc must be in (0, 1.5] (a fraction of the saturation torque), got {args.hold_dc:g}")
        if min(args.levels) <= args.hold_dc:
            ap.error(f"--levels are crests with --hold-dc: each must exceed the held DC {args.hold_dc:g}, "
                     f"got {min(args.levels):g}")
    if args.out is not None and not args.summary:
        ap.error("--out writes the --summary table: give --summary")
    if args.harmonics and not 3 * args.frequency <= MotorLimits.max_frequency_hz:
        ap.error(f"--harmonics reads 3 x --frequency, which must be <= {MotorLimits.max_frequency_hz:g} Hz "
                 f"(the drive's range), got {args.frequency:g} Hz")
    overrides = dict(args.set)
    try:
        suite = make_suite(args.suite, 60, 0)
    except SuiteError as error:
        ap.error(f"--suite: {' '.join(str(error).split())}")
    chosen = range(len(suite.episodes)) if args.all_episodes else args.episodes
    for k in chosen:
        if not 0 <= k < len(suite.episodes):
            ap.error(f"--episodes: {k} is not an index of the suite (0 to {len(suite.episodes) - 1})")
    env = gym.make(args.env or suite.env_id, **suite.env_kwargs, **(HARMONIC_OPTIONS if args.harmonics else {}),
                   **({"counter_torque": True} if args.counter_torque else {}))
    level_name = "DC / M_sat" if args.hold_dc is None else f"crest / M_sat (DC {args.hold_dc:g} M_sat)"
    played = []
    for k in chosen:
        seed, options = suite.episodes[k]
        options = {**options, **overrides}
        if args.summary:
            played.append(windows(env, seed, options, args.levels, args.amplitude_ratio, args.frequency,
                                  args.harmonics, args.hold_dc)[1])
            continue
        condition, cof = (options.get(name, "drawn") for name in ("condition", "cof"))
        print(f"\n### episode {k} (seed {seed}): {condition}, CoF {cof}\n")
        extra = " H2 | H3 |" if args.harmonics else ""
        print(f"| {level_name} | lag [deg] | compliance | CoA / CoF | cycle crest / CoF | creepage / peak creepage |"
              f"{extra} creepage swing / first | creepage lag [deg] | macro-slip |")
        print("|---" * (9 + 2 * args.harmonics) + "|")
        print("\n".join(trace(env, seed, options, args.levels, args.amplitude_ratio, args.frequency, args.harmonics,
                               args.hold_dc)))
    if args.summary:
        head = (f"| {level_name} | episodes | macro-slips | amplitude cut | not cut | macro-slips not cut | "
                "median lag [deg] | median lag rise [deg] | median creepage swing / first | "
                "median creepage shift [peak creepages] | crest bound / CoF: median / P10 |")
        table = "\n".join([head, "|---" * 11 + "|", *summary(played, args.levels), "", never_cut(played),
                           before_runaway(played)])
        print(table)
        if args.out is not None:
            args.out.parent.mkdir(parents=True, exist_ok=True)
            args.out.write_text(table + "\n")


if __name__ == "__main__":
    main()
