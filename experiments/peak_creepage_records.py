"""The episodes of ``crest_tradeoff.py --records`` files binned by where each true creep curve peaks: per setting and
per band of the peak's creepage (the bands of ``cof-gym evaluate``'s breakdown,
:data:`cof_gym.commands.evaluate_stats.PEAK_CREEPAGE_BANDS`), the climbs, their median and P90 relative CoF error,
its median signed error (estimate / CoF - 1, of the scored climbs), macro-slips, mean peak torque (fraction of the
true saturation torque) and how the climbs ended.

    python experiments/peak_creepage_records.py --suite experiments/suites/v2_extremes_confirmation17_grid.json \
        --records out/records_rule135shipped_extremes_confirmation17.json \
        out/records_rule135F_extremes_confirmation17.json --out out/peak_creepage_rule135.md

Each record names its episode's index in the suite and its vehicle configuration; the peak's creepage is the env's
ground truth at that episode's reset (``info["ground_truth"]["peak_creepage"]``), read without playing it. Records
of one grid only: the suite must be the one they played (a record whose index the suite lacks is a usage error).
"""

from __future__ import annotations

import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np

from cof_gym.commands.args import Parser
from cof_gym.commands.evaluate_stats import peak_creepage_band
from cof_gym.commands.suites import Suite, SuiteError, make_suite
from cof_gym.validation import is_number

sys.path.insert(0, str(Path(__file__).resolve().parent))
from paired_comparison import print_table, read_record_files  # noqa: E402
from script_checks import check_out_file  # noqa: E402


def peak_creepages(suite: Suite, configs: list[str]) -> dict[tuple[str, int], float]:
    """The true peak's creepage of every episode of ``suite`` in each vehicle configuration (JSON text of its env
    kwargs), by (configuration, episode index)."""
    import gymnasium as gym

    out = {}
    for config in configs:
        env = gym.make(suite.env_id, **{**suite.env_kwargs, **json.loads(config)})
        for i, (seed, options) in enumerate(suite.episodes):
            _, info = env.reset(seed=seed, options=options or None)
            out[config, i] = float(info["ground_truth"]["peak_creepage"])
        env.close()
    return out


def table(records: list[dict], peaks: dict[tuple[str, int], float]) -> str:
    """One markdown row per setting and peak-creepage band (the bands in order, empty ones left out)."""
    rows = ["| setting | band | climbs | median | P90 | median signed | macro-slips | mean peak torque | ended |",
            "|---|---|---|---|---|---|---|---|---|"]
    for setting in dict.fromkeys(r["setting"] for r in records):
        banded: dict[str, list[dict]] = {}
        for r in (r for r in records if r["setting"] == setting):
            banded.setdefault(peak_creepage_band(peaks[_config(r), r["episode"]]), []).append(r)
        for band, part in sorted(banded.items(), key=lambda kv: min(peaks[_config(r), r["episode"]] for r in kv[1])):
            errors = 100 * np.array([r["error"] for r in part])
            ended = ", ".join(f"{k} {n}" for k, n in Counter(r["ended"] for r in part).most_common())
            signed = [100 * r["signed_error"] for r in part if r.get("signed_error") is not None]
            rows.append(f"| {setting} | {band} | {len(part)} | {np.median(errors):.1f} % | "
                        f"{np.percentile(errors, 90):.1f} % | {f'{np.median(signed):+.1f} %' if signed else '-'} | "
                        f"{sum(r['macro_slip'] for r in part)} | "
                        f"{100 * np.mean([r['peak_torque_fraction'] for r in part]):.1f} % | {ended} |")
    return "\n".join(rows) + "\n"


def _config(record: dict) -> str:
    """A record's vehicle configuration as a key (JSON text, keys sorted)."""
    return json.dumps(record.get("config") or {}, sort_keys=True)


def main(argv: list[str] | None = None) -> None:
    parser = Parser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--suite", type=Path, required=True, help="the suite file the records played")
    parser.add_argument("--records", type=Path, nargs="+", required=True, help="crest_tradeoff.py --records files")
    parser.add_argument("--out", type=Path, help="also write the table here (markdown)")
    args = parser.parse_args(argv)
    check_out_file(parser, "--out", args.out)
    try:
        suite = make_suite(str(args.suite), 60, 0)
    except SuiteError as error:
        parser.error(f"--suite: {error}")
    records = read_record_files(parser, args.records)
    for index, record in enumerate(records):  # how each climb ended: what this table reads beyond the errors
        if not isinstance(record.get("ended"), str) or not is_number(record.get("peak_torque_fraction")):
            parser.error(f"--records: episode {index} has no 'ended' (text) and 'peak_torque_fraction' (a number): "
                         "records of crest_tradeoff.py --records carry both")
    missing = sorted({r["episode"] for r in records if not 0 <= r["episode"] < len(suite.episodes)})
    if missing:
        parser.error(f"--records: episode {missing[0]} is not in --suite {args.suite} "
                     f"({len(suite.episodes)} episodes: 0 to {len(suite.episodes) - 1})")
    peaks = peak_creepages(suite, sorted({_config(r) for r in records}))
    print_table(table(records, peaks), args.out, f"Episodes by peak creepage ({args.suite})")


if __name__ == "__main__":
    main()
