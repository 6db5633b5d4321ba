"""The four validation plays a rule's candidate is judged on (rule 90's conditions, docs/interrogator.md): one command.

    python experiments/validation_plays.py rule109L2 --caution-policy runs/caution_lagrangian_long/seed_2/model.zip
    python experiments/validation_plays.py rule95shipped53          # the shipped agent, the baseline of rules 104-109
    python experiments/validation_plays.py --hand-built             # phase-rule, robust-model, staircase, model-based
    python experiments/validation_plays.py rule109L2 --print        # the commands, nothing played
    python experiments/validation_plays.py shipped --confirmation confirmation36 torque_confirmation17 \
        extremes_confirmation8                                      # the five confirmation plays instead

The four plays: the validation grids at the v2 draws, the torque validation grids (the torque gain anywhere within
+-15 %), the validation grids with every episode's noise at three times the full scale, and with a 0.1 s drive lag;
each in both vehicle configurations. A learned candidate plays them with ``crest_tradeoff.py`` (the shipped guards,
the climb's target headroom 0.1, its stops and returns recorded; ``--caution-policy`` a caution policy of
``learned_caution.py``, models joined by ``+`` as one mean action) into ``out/records_NAME_PLAY.json`` and
``out/crest_tradeoff_NAME_PLAY.md``; the hand-built agents play them with ``scripted_plays.py`` into
``out/records_AGENT_PLAY.json``. Those files are what ``learned_caution.py --report``, ``frontier.py`` and
``rule_check.py`` read, with PLAY in validation, validation_torque, noise_level and motor_lag_s. With
``--confirmation SET TORQUE_SET EXTREMES_SET`` (sets of ``make_grids.py`` no agent has played) the five plays a
qualified candidate is confirmed on instead: SET at the draws, with the noise tripled and with the 0.1 s lag, the
torque set and the extremes set, PLAY the set's name (``SET``, ``SET_noise_level``, ``SET_motor_lag_s``,
``TORQUE_SET``, ``EXTREMES_SET``). Run from the repository root.
"""

from __future__ import annotations

import argparse
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from make_grids import CONFIRMATION_SETS, EXTREMES_CONFIRMATION_SETS, TORQUE_CONFIRMATION_SETS  # noqa: E402
from train_interrogator import require_networks  # noqa: E402

from cof_gym.commands.args import Parser  # noqa: E402
from cof_gym.task.scenarios import ENCODER_LAG_MAX_S  # noqa: E402

SHIPPED_GUARDS = ("cof_gym/agents/policies/interrogator/guard_0", "cof_gym/agents/policies/interrogator/guard_1")
HAND_BUILT = ("phase-rule", "robust-model", "staircase", "model-based")
SENSOR_STRESSES = {"noise_level": "noise_level=3", "motor_lag_s": "motor_lag_s=0.1"}  # play suffix -> --scenario
ENCODER_STRESS = {"encoder_lag_s": "encoder_lag_s=0.01"}  # --encoder-lag's play: the encoder's signal lagged 10 ms


def encoder_stresses(lags_s: list[float]) -> dict[str, str]:
    """``--more-encoder-lags``' plays: the encoder's signal lagged each of ``lags_s`` (s), play suffix
    ``encoder_lag_s`` + the lag as given (e.g. ``encoder_lag_s0.02``)."""
    return {f"encoder_lag_s{lag:g}": f"encoder_lag_s={lag:g}" for lag in lags_s}


def stressed(grid_set: str, prefix: str, stresses: dict[str, str] = SENSOR_STRESSES) -> dict[str, tuple[str, ...]]:
    """A grid set's plays with the noise tripled and with the 0.1 s lag (or ``stresses``), named ``prefix`` + the
    stress."""
    return {prefix + suffix: ("--grids", grid_set, "--scenario", scenario)
            for suffix, scenario in stresses.items()}


PLAYS = {  # the play's name in the records' file names -> its grids and scenario
    "validation": ("--grids", "validation"),
    "validation_torque": ("--grids", "validation_torque"),
    **stressed("validation", ""),
}
CONFIRMATION_KINDS = (("SET", CONFIRMATION_SETS), ("TORQUE_SET", TORQUE_CONFIRMATION_SETS),
                      ("EXTREMES_SET", EXTREMES_CONFIRMATION_SETS))  # --confirmation's three sets, in order


def confirmation_plays(grid_set: str, torque_set: str, extremes_set: str) -> dict[str, tuple[str, ...]]:
    """The five confirmation plays on three sets of make_grids.py, by the play's name in the records' file names."""
    return {grid_set: ("--grids", grid_set), **stressed(grid_set, f"{grid_set}_"),
            torque_set: ("--grids", torque_set), extremes_set: ("--grids", extremes_set)}


def script(name: str) -> str:
    """An experiment script's path as the commands name it: relative to the working directory (the repository root)."""
    return os.path.relpath(HERE / name)


NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")  # a name that stands in a file name as it is


def candidate_commands(name: str, caution_policy: str | None, plays: dict[str, tuple[str, ...]] = PLAYS,
                       estimators: list[str] | None = None, settings: list[str] | None = None,
                       run: str | None = None, guards: list[str] | None = None) -> list[list[str]]:
    """The learned agent's ``crest_tradeoff.py`` plays (the four validation plays), recorded under ``name``; with
    ``estimators`` (network directories whose correction the estimate may read), climb ``settings``
    (``NAME=VALUE``, e.g. ``estimate_from=estimator``), a filter ``run`` and ``guards`` in place of the shipped."""
    policy = ["--caution-policy", caution_policy] if caution_policy else []
    policy += ["--run", run] if run else []
    policy += ["--estimators", *estimators] if estimators else []
    policy += ["--set", *settings] if settings else []
    return [[sys.executable, script("crest_tradeoff.py"), "--guards", *(guards or SHIPPED_GUARDS), "--guards-only",
             "--targets", "0.1", "--stops", "--return-digits", "4", *grids, *policy,
             "--records", f"out/records_{name}_{play}.json", "--out", f"out/crest_tradeoff_{name}_{play}.md"]
            for play, grids in plays.items()]


def hand_built_commands(plays: dict[str, tuple[str, ...]] = PLAYS) -> list[list[str]]:
    """The hand-built agents' ``scripted_plays.py`` plays, one records file per agent and play."""
    return [[sys.executable, script("scripted_plays.py"), "--agents", *HAND_BUILT, *grids,
             "--records", f"out/records_{{agent}}_{play}.json"] for play, grids in plays.items()]


def build_parser() -> Parser:
    parser = Parser(description=__doc__.split("\n\n")[0])
    parser.add_argument("name", nargs="?", default=None,
                        help="the learned candidate's name in the records' file names (letters, digits, _ . -)")
    parser.add_argument("--caution-policy", default=None, metavar="MODEL[+MODEL...]",
                        help="a learned_caution.py model.zip (several joined by +: their mean action)")
    parser.add_argument("--hand-built", action="store_true",
                        help="the hand-built agents' plays instead of a candidate's")
    parser.add_argument("--confirmation", nargs=3, default=None, metavar=("SET", "TORQUE_SET", "EXTREMES_SET"),
                        help="the five confirmation plays on these make_grids.py sets instead of the validation plays "
                             "(e.g. confirmation36 torque_confirmation17 extremes_confirmation8)")
    parser.add_argument("--estimators", nargs="+", default=None, metavar="DIR",
                        help="network directories (member_*.npz) whose correction the candidate's estimate may read "
                             "(crest_tradeoff.py --estimators)")
    parser.add_argument("--run", default=None, metavar="DIR",
                        help="the candidate's filter networks (member_*.npz) in place of the shipped filter")
    parser.add_argument("--guards", nargs="+", default=None, metavar="DIR",
                        help="the candidate's guards (network directories) in place of the shipped two")
    parser.add_argument("--set", nargs="+", default=None, metavar="NAME=VALUE",
                        help="the candidate's climb parameters changed (crest_tradeoff.py --set, e.g. "
                             "estimate_from=estimator)")
    parser.add_argument("--encoder-lag", action="store_true",
                        help="also the play with every episode's encoder lagged 10 ms (rule 110; PLAY encoder_lag_s, "
                             "or SET_encoder_lag_s with --confirmation)")
    parser.add_argument("--encoder-lag-only", action="store_true",
                        help="only the play with the encoder lagged 10 ms (the other plays already recorded)")
    parser.add_argument("--more-encoder-lags", nargs="+", type=float, default=None, metavar="S",
                        help="also the plays with every episode's encoder lagged S seconds (0 < S <= "
                             f"{ENCODER_LAG_MAX_S:g}; PLAY encoder_lag_sS, or SET_encoder_lag_sS with --confirmation)")
    parser.add_argument("--only", nargs="+", default=None, metavar="PLAY",
                        help="only these of the plays the other options ask for (PLAY as in the records' names)")
    parser.add_argument("--print", action="store_true", help="print the commands, play nothing")
    return parser


def commands_of(parser: Parser, args: argparse.Namespace) -> list[list[str]]:
    """The commands the arguments ask for, every argument checked first (one line and exit code 2)."""
    plays, grid_set, prefix = PLAYS, "validation", ""
    if args.confirmation is not None:
        for (kind, known), name in zip(CONFIRMATION_KINDS, args.confirmation):
            if name not in known:
                first, last = next(iter(known)), list(known)[-1]
                parser.error(f"--confirmation: {kind} must be one of {first} ... {last}, got {name!r}")
        plays = confirmation_plays(*args.confirmation)
        grid_set, prefix = args.confirmation[0], f"{args.confirmation[0]}_"
    if args.encoder_lag or args.encoder_lag_only:
        lagged = stressed(grid_set, prefix, ENCODER_STRESS)
        plays = lagged if args.encoder_lag_only else {**plays, **lagged}
    if args.more_encoder_lags is not None:
        for lag in args.more_encoder_lags:
            if not 0.0 < lag <= ENCODER_LAG_MAX_S:  # also refuses NaN
                parser.error(f"--more-encoder-lags: each lag must be in (0, {ENCODER_LAG_MAX_S:g}] s, got {lag:g}")
        plays = {**plays, **stressed(grid_set, prefix, encoder_stresses(args.more_encoder_lags))}
    if args.only is not None:
        unknown = [play for play in args.only if play not in plays]
        if unknown:
            parser.error(f"--only: {unknown[0]!r} is none of the plays asked for ({', '.join(plays)})")
        plays = {play: grids for play, grids in plays.items() if play in args.only}
    if args.hand_built:
        if any(v is not None for v in (args.name, args.caution_policy, args.estimators, args.set, args.run,
                                       args.guards)):
            parser.error("--hand-built: takes no NAME, --caution-policy, --estimators, --set, --run or --guards "
                         "(the agents' names name the records)")
        return hand_built_commands(plays)
    if args.name is None:
        parser.error("NAME: required (the candidate's name in the records' file names), or --hand-built")
    if not NAME.fullmatch(args.name):
        parser.error(f"NAME: letters, digits, '_', '.' and '-', starting with a letter or digit; got {args.name!r}")
    if args.caution_policy is not None:
        from learned_caution import ensemble_members

        missing = [m for m in ensemble_members(args.caution_policy) if not m.is_file()]
        if missing:
            parser.error(f"--caution-policy: no file {missing[0]} (a learned_caution.py model.zip)")
    for flag, directories in (("--estimators", args.estimators), ("--run", [args.run] if args.run else None),
                              ("--guards", args.guards)):
        require_networks(parser, flag, [Path(d) for d in directories or []])
    from crest_tradeoff import climb_setting  # the value checked against the shipped climb, as crest_tradeoff.py does

    for item in args.set or []:
        try:
            climb_setting(item)
        except (argparse.ArgumentTypeError, ValueError) as error:
            parser.error(f"--set: {error}")
    return candidate_commands(args.name, args.caution_policy, plays, args.estimators, args.set, args.run,
                              args.guards)


def main() -> None:
    parser = build_parser()
    args = parser.parse_args()
    commands = commands_of(parser, args)
    for command in commands:
        print(shlex.join(["python", *command[1:]]), flush=True)
        if not args.print:
            returncode = subprocess.run(command).returncode
            if returncode:
                sys.exit(returncode)  # the play has said why; the plays after it are not run


if __name__ == "__main__":
    main()
