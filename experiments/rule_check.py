"""Whether a candidate meets a rule's conditions against a baseline, from crest_tradeoff.py ``--records`` files.

    python experiments/rule_check.py BASE.json CANDIDATE.json [BASE2.json CANDIDATE2.json ...] \
        [--more-runaways N | --fewer-runaways] [--errors [--error-grid GRID]] [--returns] [--gain | --no-loss] \
        [--strict-grid family] [--same-climbs] [--discordant] [--family-wise] [--sign-test] [--out FILE]

The files come in pairs, the baseline's and the candidate's play of the same episodes (e.g. one pair at the
grids' draws, one with the noise tripled); each file holds one setting's episodes (one crest_tradeoff.py row).
The conditions a rule of docs/interrogator.md writes before its candidate is played, checked on the paired
differences of :mod:`paired_comparison` (the same 95 % CIs, the same resamples):

- always: at most ``--more-runaways`` more macro-slips (runaways) than the baseline over every pair's grids
  together (default 0), and none more on the ``--strict-grid`` of any pair (default ``family``, the grid of the
  Polach, SHE and table families; ``none``: no such grid);
- ``--fewer-runaways``: strictly fewer runaways than the baseline over every pair's grids together (in place of
  ``--more-runaways``);
- ``--errors``: no grid's median or P90 relative error higher with a CI wholly above zero (with ``--error-grid``
  only on the grid of that name in every pair that has one);
- ``--returns``: no grid's mean return lower with a CI wholly below zero;
- ``--gain``: a strictly higher mean return over every pair's episodes together;
- ``--no-loss``: a mean return not lower than the baseline's over every pair's episodes together (a candidate that
  should change nothing on these plays: rule 127's gate where the encoder is sharp);
- ``--same-climbs``: every episode's climb ended as the baseline's did (the same ``ended`` and ``macro_slip``) at
  the same peak torque (``peak_torque_fraction``, exactly): a candidate that changes only the estimate (rule 102).

``--family-wise`` reads ``--errors`` and ``--returns`` on simultaneous CIs instead: with ``m`` intervals examined (a
median and a P90 on each grid ``--errors`` reads, a return on each grid with ``--returns``, over every pair), each CI
leaves 2.5 / ``m`` % out on either side (Bonferroni: a candidate equal to the baseline fails one of the ``m`` with
probability at most 5 %, where on 95 % CIs each fails it with probability 5 % and one of ``m`` far more often), from
:data:`FAMILY_RESAMPLES` draws so that each tail holds enough of them; the grid lines still print the 95 % CIs.
``--sign-test`` adds a condition on the runaways: the one-sided exact sign test below (the candidate running away
more often) must not reject at 5 %.

``--discordant`` adds information, no condition: on each grid's line the climbs that ran away in the baseline's play
alone and in the candidate's alone (``ran away alone B / C``), and a line with both counts over every pair's episodes
together and the exact one-sided sign test (McNemar's exact test) of the candidate running away more often: the
binomial probability of at least that many of the discordant climbs being the candidate's if each were equally likely
to be either's. The concordant climbs carry no information on the difference; a total's difference of a few runaways
can be well within chance.

Where the candidate's records say which climbs its smoothed-encoder networks steered (``gated``, rule 127), a line
counts them and the climbs that ended otherwise than the baseline's (information, no condition).

It prints each grid's differences, every condition that fails, and a last line ``holds`` or ``fails``; the exit
status is 0 when the conditions hold and 1 when they fail (2: a usage error, before anything is read further).
Rule 78's conditions, for instance: at the draws ``--more-runaways 2 --errors --returns``, on the torque set
``--errors --returns``, with the noise tripled ``--errors --gain``, with the drive lag ``--more-runaways 2
--returns``.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import NamedTuple

from scipy.stats import binomtest

from cof_gym.commands.args import Parser, non_negative_int

sys.path.insert(0, str(Path(__file__).resolve().parent))
from paired_comparison import ci_text, differences, paired, print_table, read_record_files, runaways  # noqa: E402

FAMILY_RESAMPLES = 20000  # --family-wise's draws: 2.5 / m % of them in each tail, 24 at m = 21
SIGN_TEST_ALPHA = 0.05  # --sign-test: the one-sided level at which more runaways reject
from script_checks import check_out_file  # noqa: E402


class Conditions(NamedTuple):
    """What a candidate must meet against the baseline (the module docstring says each)."""

    more_runaways: int = 0
    strict_grid: str | None = "family"
    errors: bool = False
    returns: bool = False
    gain: bool = False
    fewer_runaways: bool = False
    error_grid: str | None = None  # None: --errors on every grid
    same_climbs: bool = False
    discordant: bool = False
    family_wise: bool = False  # --errors and --returns on simultaneous (Bonferroni) CIs
    sign_test: bool = False  # the runaways' one-sided exact sign test must not reject at SIGN_TEST_ALPHA
    no_loss: bool = False  # a mean return not lower than the baseline's over every pair together


CLIMB_FIELDS = ("ended", "macro_slip", "peak_torque_fraction")  # where and how a climb ended (--same-climbs)


Grids = dict[str, dict[tuple, dict]]  # a play's episodes per grid (paired_comparison.paired)


def climbs_differing(base: dict[tuple, dict], other: dict[tuple, dict]) -> int:
    """How many of the paired episodes' climbs ended otherwise (:data:`CLIMB_FIELDS`) in ``other`` than in ``base``."""
    return sum(any(base[k][f] != other[k][f] for f in CLIMB_FIELDS) for k in base if k in other)


def discordant_runaways(base: dict[tuple, dict], candidate: dict[tuple, dict]) -> tuple[int, int]:
    """(climbs that ran away in the baseline's play alone, in the candidate's alone) on one grid's paired episodes."""
    counts = [0, 0]
    for key, r in base.items():
        base_slip, candidate_slip = bool(r["macro_slip"]), bool(candidate[key]["macro_slip"])
        if base_slip != candidate_slip:
            counts[candidate_slip] += 1
    return counts[0], counts[1]


def sign_test_p(candidate_only: int, discordant: int) -> float:
    """P(at least ``candidate_only`` of ``discordant`` fair coin flips): the exact one-sided McNemar p (1 with no
    discordant climb)."""
    return float(binomtest(candidate_only, discordant, 0.5, alternative="greater").pvalue) if discordant else 1.0


def mean_return(plays: list[Grids]) -> float:
    """The mean episode return over every play's grids' episodes together."""
    returns = [r["episode_return"] for play in plays for episodes in play.values() for r in episodes.values()]
    return sum(returns) / len(returns)


def intervals_examined(bases: list[Grids], conditions: Conditions) -> int:
    """How many CIs ``--errors`` and ``--returns`` read over every pair's grids (``--family-wise``'s ``m``)."""
    return sum(2 * (conditions.errors and conditions.error_grid in (None, grid)) + conditions.returns
               for b in bases for grid in b)


def gated_lines(bases: list[Grids], candidates: list[Grids]) -> list[str]:
    """A line with the candidate's climbs that its smoothed-encoder networks steered (the records' ``gated``, rule
    127) and how many of all its climbs ended otherwise than the baseline's; none where its records carry no
    ``gated``."""
    climbs = [r for play in candidates for episodes in play.values() for r in episodes.values()]
    if not any("gated" in r for r in climbs):
        return []
    differing = sum(climbs_differing(b[grid], c[grid]) for b, c in zip(bases, candidates) for grid in b)
    return [f"- gated: {sum(bool(r.get('gated')) for r in climbs)} of {len(climbs)} climbs in the candidate's plays; "
            f"{differing} ended otherwise than the baseline's"]


def check(bases: list[Grids], candidates: list[Grids], conditions: Conditions) -> tuple[list[str], list[str]]:
    """(lines describing each grid and the totals, the conditions that fail) of the ``candidates``' plays against
    the ``bases``' (in pairs, the same episodes; with several, each line names its play's index)."""
    lines, failed, alone = [], [], [0, 0]
    m = intervals_examined(bases, conditions)
    if conditions.family_wise and m:
        lines.append(f"- family-wise: {m} intervals, each leaving {2.5 / m:.3g} % out on either side "
                     f"({FAMILY_RESAMPLES} resamples)")
    for k, (b, c) in enumerate(zip(bases, candidates, strict=True)):
        if sorted(b) != sorted(c):
            raise ValueError(f"the two files played other grids: {sorted(b)} and {sorted(c)}")
        for grid in sorted(b):
            name = grid if len(bases) == 1 else f"{k + 1}, {grid}"
            d = differences(b[grid], c[grid])
            if d["median"][1] is None:  # the conditions read CIs, which one episode does not have
                raise ValueError(f"grid {grid} has one episode: a rule's conditions need at least two")
            # the CIs the conditions read: the 95 % ones, or with --family-wise the simultaneous ones
            dc = differences(b[grid], c[grid], tail_percent=2.5 / m, resamples=FAMILY_RESAMPLES) \
                if conditions.family_wise and m else d
            which = "a family-wise CI" if dc is not d else "a CI"
            slips = runaways(b[grid]), runaways(c[grid])
            lines.append(f"- {name}: runaways {slips[0]} -> {slips[1]}; median {ci_text(d['median'])} points, "
                         f"P90 {ci_text(d['P90'])} points, return {ci_text(d['return'], 4)}")
            grid_alone = discordant_runaways(b[grid], c[grid])
            alone[0] += grid_alone[0]
            alone[1] += grid_alone[1]
            if conditions.discordant:
                lines[-1] += f"; ran away alone {grid_alone[0]} / {grid_alone[1]}"
            if grid == conditions.strict_grid and slips[1] > slips[0]:
                failed.append(f"{name}: {slips[1]} runaways against {slips[0]} (none more allowed)")
            if conditions.errors and conditions.error_grid in (None, grid):
                failed += [f"{name}: {stat} higher with {which} wholly above zero ({ci_text(dc[stat])})"
                           for stat in ("median", "P90") if dc[stat][1] > 0.0]
            if conditions.returns and dc["return"][2] < 0.0:
                failed.append(f"{name}: return lower with {which} wholly below zero ({ci_text(dc['return'], 4)})")
            if conditions.same_climbs and (n := climbs_differing(b[grid], c[grid])):
                failed.append(f"{name}: {n} climbs ended otherwise than the baseline's (the same climbs needed)")
    totals = tuple(sum(runaways(e) for play in plays for e in play.values()) for plays in (bases, candidates))
    returns = mean_return(bases), mean_return(candidates)
    lines.append(f"- all: runaways {totals[0]} -> {totals[1]}; mean return {returns[0]:.4f} -> {returns[1]:.4f}")
    lines += gated_lines(bases, candidates)
    p_more = sign_test_p(alone[1], sum(alone))
    if conditions.discordant or conditions.sign_test:
        lines.append(f"- discordant climbs: {alone[0]} ran away in the baseline's play alone, {alone[1]} in the "
                     f"candidate's alone (one-sided exact sign test p = {p_more:.3f})")
    if conditions.sign_test and p_more < SIGN_TEST_ALPHA:
        failed.append(f"all: the candidate runs away more often by the one-sided sign test (p = {p_more:.3f} < "
                      f"{SIGN_TEST_ALPHA:g})")
    if conditions.fewer_runaways and not totals[1] < totals[0]:
        failed.append(f"all: {totals[1]} runaways against {totals[0]} (strictly fewer needed)")
    elif totals[1] > totals[0] + conditions.more_runaways:
        failed.append(f"all: {totals[1]} runaways against {totals[0]} (at most {conditions.more_runaways} more)")
    if conditions.gain and not returns[1] > returns[0]:
        failed.append(f"all: mean return {returns[1]:.4f} not above {returns[0]:.4f}")
    if conditions.no_loss and returns[1] < returns[0]:
        failed.append(f"all: mean return {returns[1]:.4f} below {returns[0]:.4f}")
    return lines, failed


def one_setting(parser: Parser, path: Path, records: list[dict]) -> Grids:
    """The per-grid episodes of the one setting a records file holds; a usage error naming the file otherwise."""
    settings = list(dict.fromkeys(r["setting"] for r in records))
    if len(settings) != 1:
        parser.error(f"records: {path}: holds {len(settings)} settings, one is needed (one crest_tradeoff.py row)")
    return paired(records, settings[0])


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("records", type=Path, nargs="+", metavar="BASE CANDIDATE",
                        help="crest_tradeoff.py --records files in pairs: the baseline's, then the candidate's play "
                             "of the same episodes")
    runaway_limit = parser.add_mutually_exclusive_group()
    runaway_limit.add_argument("--more-runaways", type=non_negative_int, default=0, metavar="N",
                               help="runaways the candidate may have beyond the baseline's over every grid "
                                    "(default: 0)")
    runaway_limit.add_argument("--fewer-runaways", action="store_true",
                               help="strictly fewer runaways than the baseline's over every grid")
    parser.add_argument("--strict-grid", default="family",
                        help="the grid on which no more runaways are allowed ('none': no such grid; default: family)")
    parser.add_argument("--errors", action="store_true", help="no median or P90 higher with a CI wholly above zero")
    parser.add_argument("--error-grid", default=None, metavar="GRID",
                        help="with --errors: only on the grid of this name (default: every grid)")
    parser.add_argument("--returns", action="store_true", help="no mean return lower with a CI wholly below zero")
    return_limit = parser.add_mutually_exclusive_group()
    return_limit.add_argument("--gain", action="store_true", help="a strictly higher mean return over every grid")
    return_limit.add_argument("--no-loss", action="store_true",
                              help="a mean return not lower than the baseline's over every grid")
    parser.add_argument("--same-climbs", action="store_true",
                        help="every climb ended as the baseline's, at the same peak torque (an estimate-only "
                             "candidate)")
    parser.add_argument("--discordant", action="store_true",
                        help="also print the climbs that ran away in one play alone and the sign test (information)")
    parser.add_argument("--family-wise", action="store_true",
                        help="--errors and --returns on simultaneous (Bonferroni) CIs over every interval they read")
    parser.add_argument("--sign-test", action="store_true",
                        help=f"the runaways' one-sided exact sign test must not reject at {SIGN_TEST_ALPHA:g}")
    parser.add_argument("--out", type=Path, default=None, help="also write the verdict to this markdown file")
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    if args.family_wise and not (args.errors or args.returns):
        parser.error("--family-wise: needs --errors or --returns (the CIs it adjusts)")
    if len(args.records) % 2:
        parser.error(f"records: {len(args.records)} files; they come in pairs (the baseline's, the candidate's)")
    plays = [one_setting(parser, path, read_record_files(parser, [path])) for path in args.records]
    strict = None if args.strict_grid == "none" else args.strict_grid
    if strict is not None and strict not in plays[0]:
        parser.error(f"--strict-grid: the records have no grid {strict!r} (grids: {', '.join(sorted(plays[0]))}; "
                     "or none)")
    if args.error_grid is not None:
        if not args.errors:
            parser.error("--error-grid: needs --errors")
        if not any(args.error_grid in play for play in plays):
            parser.error(f"--error-grid: the records have no grid {args.error_grid!r} (grids: "
                         f"{', '.join(sorted(plays[0]))})")
    conditions = Conditions(args.more_runaways, strict, args.errors, args.returns, args.gain, args.fewer_runaways,
                            args.error_grid, args.same_climbs, args.discordant, args.family_wise, args.sign_test,
                            args.no_loss)
    files = ", ".join(map(str, args.records))
    try:
        lines, failed = check(plays[0::2], plays[1::2], conditions)
    except KeyError as e:
        parser.error(f"records: an episode of {files} has no {e}")
    except ValueError as e:
        parser.error(f"records: {files}: {e}")
    text = "\n".join([*lines, *(f"- fails: {f}" for f in failed), "", "fails" if failed else "holds"]) + "\n"
    print_table(text, args.out, f"Rule check of {files}")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
