"""Paired bootstrap of each setting against a baseline, per grid, from crest_tradeoff.py's ``--records``.

    python experiments/crest_tradeoff.py ... --set A B --records out/records.json
    python experiments/paired_comparison.py out/records.json [more.json ...] [--baseline SETTING] [--settings S ...]
        [--out FILE]

The rows of a crest_tradeoff table differ by a tenth of a point where a handful of episodes move: a
median of 108-180 episodes and, more so, their 90th percentile, move by that much when a few episodes
change. Every setting plays the same episodes (grid, vehicle configuration, seed), so the comparison is
paired: for each setting after the baseline (the first setting of the file unless ``--baseline`` names
one) and each grid (several files: their episodes together, e.g. the shipped agent's from one command and
a candidate's, other networks, from another; a setting named in two files is refused), the difference setting - baseline of the median and P90 relative CoF error (points)
and of the mean episode return, each with a 95 % CI from resampling the episodes (the same resample for
both: :data:`N_BOOTSTRAP` draws, seeded), and both macro-slip counts. Nothing is decided here: a rule
written before its candidate is played says how these numbers are read.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

from cof_gym.commands.args import Parser
from cof_gym.commands.evaluate_stats import N_BOOTSTRAP, paired_differences
from cof_gym.commands.evaluate_tables import ci_text  # noqa: F401 - a difference and its CI; rule_check reads it here
from cof_gym.validation import check_bool, check_int, check_number

sys.path.insert(0, str(Path(__file__).resolve().parent))
from script_checks import check_out_file  # noqa: E402


def paired(records: list[dict], setting: str) -> dict[str, dict[tuple, dict]]:
    """``setting``'s episodes per grid, keyed by (vehicle configuration, episode)."""
    out: dict[str, dict[tuple, dict]] = {}
    for r in records:
        if r["setting"] == setting:
            out.setdefault(r["grid"], {})[(json.dumps(r["config"], sort_keys=True), r["episode"])] = r
    return out


def differences(base: dict[tuple, dict], other: dict[tuple, dict], seed: int = 0, tail_percent: float = 2.5,
                resamples: int = N_BOOTSTRAP) -> dict[str, tuple[float, float, float]]:
    """(difference, CI low, CI high) of ``other`` - ``base`` on their common episodes: the median and P90
    relative error (percentage points) and the mean return, resampled in pairs (``resamples`` draws); the CI leaves
    ``tail_percent`` % of the draws out on each side (2.5: the 95 % CI)
    (:func:`cof_gym.commands.evaluate_stats.paired_differences`)."""
    keys = sorted(set(base) & set(other))
    if len(keys) != len(base) or len(keys) != len(other):
        raise ValueError("the two settings did not play the same episodes")
    arrays = [np.array([s[k][field] for k in keys]) for field in ("error", "episode_return") for s in (base, other)]
    return paired_differences(*arrays, seed=seed, tail_percent=tail_percent, resamples=resamples)


def runaways(episodes: dict[tuple, dict]) -> int:
    """The macro-slips (runaways) among ``episodes`` (one grid's, :func:`paired`)."""
    return sum(bool(r["macro_slip"]) for r in episodes.values())


def table(records: list[dict], baseline: str | None = None, compared: list[str] | None = None) -> str:
    """The markdown table of every setting (or of ``compared`` alone) against ``baseline`` (default: the
    first setting), per grid."""
    settings = list(dict.fromkeys(r["setting"] for r in records))
    baseline = baseline or settings[0]
    if baseline not in settings:
        raise ValueError(f"--baseline: no setting {baseline!r} in the records (settings: {settings})")
    missing = [s for s in compared or [] if s not in settings]
    if missing:
        raise ValueError(f"--settings: no setting {missing[0]!r} in the records (settings: {settings})")
    settings = compared or settings
    base = paired(records, baseline)
    lines = [f"Against `{baseline}` (paired over the same episodes; 95 % CIs from {N_BOOTSTRAP} resamples):", "",
             "| setting | grid | episodes | median error: difference [95 % CI] (points) | P90 error: difference [95 % CI] "
             "(points) | mean return: difference [95 % CI] | macro-slips (baseline -> setting) |",
             "|---|---|---|---|---|---|---|"]
    for setting in settings:
        if setting == baseline:
            continue
        other = paired(records, setting)
        for grid, episodes in base.items():
            d = differences(episodes, other[grid])
            lines.append(f"| {setting} | {grid} | {len(episodes)} | {ci_text(d['median'])} | {ci_text(d['P90'])} | "
                         f"{ci_text(d['return'], 4)} | {runaways(episodes)} -> {runaways(other[grid])} |")
    return "\n".join(lines) + "\n"


def check_record(index: int, record: dict) -> None:
    """An episode's fields as the tables read them: ``grid`` a name, ``config`` the vehicle configuration (an
    object of env arguments), ``episode`` an index >= 0, ``error`` a finite relative error >= 0, ``macro_slip`` a
    bool, ``episode_return`` (where present) a finite number (the package's argument checks,
    :mod:`cof_gym.validation`); ValueError naming the episode and the field."""
    try:
        if not isinstance(record.get("grid"), str):
            raise ValueError(f"grid must be a grid's name (a string), got {record.get('grid')!r}")
        if not isinstance(record.get("config"), dict):
            raise ValueError(f"config must be an object of env arguments, got {record.get('config')!r}")
        check_int("episode", record.get("episode"), 0)
        check_number("error", record.get("error"), 0.0, math.inf)
        check_bool("macro_slip", record.get("macro_slip"))
        if "episode_return" in record:
            check_number("episode_return", record["episode_return"], -math.inf, math.inf)
    except ValueError as e:
        raise ValueError(f"episode {index}: {e}") from None


def read_records(path: Path, seen: set[str]) -> list[dict]:
    """The episodes of one ``--records`` file; ValueError if it is not one (:func:`check_record` for each episode's
    numbers) or names a setting in ``seen``."""
    records = json.loads(path.read_text())
    if not isinstance(records, list) or not records or not all(isinstance(r, dict) and "setting" in r for r in records):
        raise ValueError("not a crest_tradeoff.py --records file (a list of episodes with their setting)")
    for index, record in enumerate(records):
        check_record(index, record)
    twice = sorted({r["setting"] for r in records} & seen)
    if twice:
        raise ValueError(f"setting {twice[0]!r} is also in an earlier file")
    return records


def read_record_files(parser: Parser, paths: list[Path]) -> list[dict]:
    """The episodes of every ``--records`` file together; a file that is none, or names a setting an earlier file
    named, is a one-line usage error naming it."""
    records: list[dict] = []
    for path in paths:
        try:
            records += read_records(path, {r["setting"] for r in records})
        except (OSError, ValueError) as e:  # json.JSONDecodeError is a ValueError
            parser.error(f"records: {path}: {e}")
    return records


def print_table(text: str, out: Path | None, title: str) -> None:
    """Print a markdown table and, with ``out``, also write it there under a level-1 ``title``."""
    print(text, end="")
    if out is not None:
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(f"# {title}\n\n{text}")


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("records", type=Path, nargs="+", help="crest_tradeoff.py --records files (their episodes together)")
    parser.add_argument("--baseline", default=None, help="the setting compared against (default: the file's first)")
    parser.add_argument("--settings", nargs="+", default=None, metavar="SETTING",
                        help="compare these settings only (default: every setting of the records)")
    parser.add_argument("--out", type=Path, default=None, help="also write the table to this markdown file")
    args = parser.parse_args()
    check_out_file(parser, "--out", args.out)
    records, files = read_record_files(parser, args.records), ", ".join(map(str, args.records))
    try:
        text = table(records, args.baseline, args.settings)
    except KeyError as e:
        parser.error(f"records: an episode of {files} has no {e}")
    except ValueError as e:
        parser.error(str(e) if str(e).startswith("--") else f"records: {files}: {e}")
    print_table(text, args.out, f"Paired comparison of {files}")


if __name__ == "__main__":
    main()
