"""How far below the peak must the shipped interrogator stop to survive steep falling branches?
(run from the repository root; 2 cores, ~4 min)

    python experiments/crest_tradeoff.py [--targets 0.1 0.15 0.2 0.3] [--out out/crest_tradeoff.md]
    python experiments/crest_tradeoff.py --run runs/interrogator_cm/ensemble --cautions 2 2.5 3 --targets 0.1 0.15
    python experiments/crest_tradeoff.py --spread-cautions 0 1 2 4 --targets 0.1 --out out/crest_tradeoff_spread.md
    python experiments/crest_tradeoff.py --guards runs/interrogator_cm/ensemble --cautions 1.5 2 --targets 0.07 0.1 0.15
    python experiments/crest_tradeoff.py --targets 0.1 --stops --out out/crest_tradeoff_stops.md
    python experiments/crest_tradeoff.py --guards cof_gym/agents/policies/interrogator/guard_0 \
        --crest-fractions none 0.5 1 2 --targets 0.1 --stops --out out/crest_tradeoff_crest.md
    python experiments/crest_tradeoff.py --run cof_gym/agents/policies/interrogator runs/interrogator_more/ensemble \
        runs/interrogator_32k/ensemble --targets 0.1 --stops --out out/crest_tradeoff_data.md
    python experiments/crest_tradeoff.py --own-climb --run cof_gym/agents/policies/interrogator \
        runs/interrogator_more/ensemble runs/interrogator_32k/ensemble --out out/crest_tradeoff_own.md

The shipped climb's modulation is 40 % of the DC torque, so its crest passes the saturation torque once
the DC is above ``1 / 1.4`` of it (a headroom below ``ln 1.4 = 0.34``); a creep curve that falls steeply
past its peak then lets the wheel run away. This plays the shipped filter with its climb and only the
target headroom (and the end of its slow probe) changed, and with ``--cautions`` each of these caution
factors in turn (the standard deviations taken off the predicted headroom), with ``--spread-cautions``
each of these further multiples of the members' spread alone (their disagreement), with ``--run`` other runs'
networks (directories of ``member_*.npz``; several: each in turn) under the shipped climb
(``--own-climb``: each with the climb its own manifest names, unchanged, and its manifest's guards unless
``--guards`` is given), with ``--guards`` every row also with
these networks as the climb's guards (it steers by the lowest cautious headroom of all; the estimate
reads the guards' as the shipped climb's does since session 20, or as ``--set estimate_from=...`` names
it; a row without guards reports the filter's unless ``--set`` names another; ``--estimators``: every row
with these estimator networks, whose correction ``--set estimate_from=estimator``, ``estimator_pooled`` or
``guard_estimator_pooled`` reads; ``--guards-only``: only
with them), with ``--stops`` also how the climbs ended (the stop reason or a macro-slip, before or after
the climb's first slow probe) and their errors (median, P90 and the median signed error), in both vehicle
configurations, on the three
validation grids (model selection data, never reported elsewhere as results): the family draws, the
procedural curves and the procedural curves with steep falling branches
(``experiments/suites/v2_validation_steep_grid.json``), or with ``--grids confirmation`` on the three
confirmation grids of the same kinds (``experiments/suites/v2_confirmation_*grid.json``; ``--grids
confirmationN``: the N-th such set, one for each of make_grids.CONFIRMATION_SETS, whose docstring says when
each was written and which rule it judged), or with ``--grids validation_torque`` on the three kinds with
each episode's torque gain error spread over what the env accepts
(``experiments/suites/v2_validation_torque*grid.json``, model selection too; ``--grids torque_confirmation``,
``torque_confirmationN``: the confirmation sets of that kind, one for each of make_grids.TORQUE_CONFIRMATION_SETS),
or with ``--grids validation_extremes`` / ``extremes_confirmation`` / ``extremes_confirmation2`` on one grid of random creep tables with every
scenario field anywhere within what the env accepts (model selection past every draw at once, and its confirmation
sets).
With ``--crest-fractions`` each row also with each of these crest caps (``ClimbParameters.crest_fraction``: the
modulation shrinks so that its crest stays within that fraction of the cautious headroom; ``none``: uncapped;
``--crest-once-crept``: each cap from the climb's first slow probe on). With ``--set NAME=VALUE ...`` the shipped
climb with those parameters (a name given several values: each in turn). Per grid: median / P90 relative CoF error,
macro-slips, and the mean episode return (the task's own trade of error against slip, comfort and time).
With ``--caution-policy MODEL ...`` every row with each of these PPO models setting the climb's caution at every
decision (experiments/learned_caution.py, rule 104; models joined by ``+``: the mean of their actions, rule 107).
With ``--records FILE`` every episode also goes to a JSON file,
with the error each estimate source the agent computes would have had (the climb does not depend on it), so that a
question about the estimate is answered from the played episodes by a named command rather than a throwaway script.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import sys
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict
from pathlib import Path
from typing import NamedTuple

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from train_interrogator import (  # noqa: E402
    CONFIGS, PROCEDURAL_VALIDATION, STEEP_VALIDATION, VALIDATION, episodes, require_networks, score,
    source_error,
)

from make_grids import CONFIRMATION_SETS, EXTREMES_CONFIRMATION_SETS, SUITES, TORQUE_CONFIRMATION_SETS  # noqa: E402
from script_checks import check_out_file  # noqa: E402

from cof_gym.agents.interrogator import (  # noqa: E402
    ESTIMATE_SOURCES, ESTIMATOR_ESTIMATES, GUARDED_ESTIMATES, SHIPPED_INTERROGATOR, ClimbParameters, manifest_networks,
    read_manifest,
)
from cof_gym.commands.args import Parser, name_value, positive_int  # noqa: E402
from cof_gym.agents.policy_files import MANIFEST_FILE  # noqa: E402
from cof_gym.commands.suites import scenario_option  # noqa: E402


def confirmation_set(name: str) -> dict[str, Path]:
    """The three grids of a set (a confirmation set, or the torque sets), by kind: ``v2_NAME_grid.json`` (family
    draws) and ``v2_NAME_procedural_grid.json`` / ``v2_NAME_steep_grid.json`` (experiments/make_grids.py writes
    them)."""
    return {kind: SUITES / f"v2_{name}{'' if kind == 'family' else '_' + kind}_grid.json"
            for kind in ("family", "procedural", "steep")}


# the grid sets a table plays: validation (model selection) and every confirmation set of make_grids.py (the
# same three kinds on other seeds, CoF values and speeds, to confirm a choice taken on the first by a rule
# written before; a new set for each candidate judged)
GRID_SETS = {
    "validation": {"family": VALIDATION, "procedural": PROCEDURAL_VALIDATION, "steep": STEEP_VALIDATION},
    # the three kinds with each episode's torque gain error spread over what the env accepts (session 45), and the
    # confirmation sets of that kind
    "validation_torque": confirmation_set("validation_torque"),
    **{name: confirmation_set(name) for name in TORQUE_CONFIRMATION_SETS},
    **{name: confirmation_set(name) for name in CONFIRMATION_SETS},
    # random creep tables with every scenario field anywhere within what the env accepts (session 51): one grid each
    "validation_extremes": {"extremes": SUITES / "v2_validation_extremes_grid.json"},
    **{name: {"extremes": SUITES / f"v2_{name}_grid.json"} for name in EXTREMES_CONFIRMATION_SETS},
}


def climb_at(climb: dict, target: float) -> dict:
    """The climb ``climb`` aiming at ``target``, its slow probe ending no lower than the target."""
    until = climb.get("creep_until")
    return {**climb, "target_headroom": target, "creep_until": None if until is None else max(until, target)}


class Played(NamedTuple):
    """One validation episode as the tables read it."""

    error: float  # relative CoF error (1.0 when unscored)
    macro_slip: bool
    episode_return: float
    ended: str  # why the climb ended: the agent's stop reason, or "macro-slip" (", slow probe": once crept)
    peak_torque_fraction: float  # the largest true torque over the saturation torque
    source_errors: dict[str, float] | None = None  # the error of each estimate source the agent could report
    signed_error: float | None = None  # estimate / CoF - 1 (None when unscored): below the CoF < 0
    gated: bool = False  # the smoothed-encoder networks steered the climb's end (LearnedInterrogator.gated; rule 127)

    @classmethod
    def of(cls, record, ended: str, source_errors: dict[str, float] | None = None, gated: bool = False) -> "Played":
        """An evaluated episode (``record``: :class:`~cof_gym.commands.evaluate_episodes.EpisodeRecord`) as the
        tables read it, ending as ``ended`` says (``gated``: by the smoothed-encoder networks)."""
        return cls(record.relative_error if record.scored else 1.0, record.macro_slip, record.episode_return, ended,
                   record.peak_torque_fraction, source_errors,
                   record.estimate / record.cof - 1.0 if record.scored else None, gated)

    def as_record(self, setting: str, grid: str, config: dict, episode: int) -> dict:
        """The episode as a ``--records`` entry (its setting, grid, vehicle configuration and index in the grid)."""
        return {"setting": setting, "grid": grid, "config": config, "episode": episode, **self._asdict()}


def available_sources(agent) -> tuple[str, ...]:
    """The estimate sources ``agent`` computes: the guarded ones with guards, the estimators' with estimators."""
    return tuple(s for s in ESTIMATE_SOURCES if (s not in GUARDED_ESTIMATES or agent.guards)
                 and (s not in ESTIMATOR_ESTIMATES or agent.estimators))


def _play(run: str, params: dict, grid: str, config: dict, guards: list[str] | None,
          estimators: list[str] | None = None, scenario: dict | None = None,
          caution_policy: str | None = None) -> list[Played]:
    """Every episode of ``grid`` in ``config``, the filter of ``run`` with the climb ``params``, the guard
    networks ``guards`` and the estimator networks ``estimators`` (None: those its manifest names), with the
    reset options ``scenario`` over every episode's own; ``caution_policy``: a PPO model that sets each decision's
    caution (experiments/learned_caution.py)."""
    wrap = None
    if caution_policy is not None:
        from learned_caution import ppo_policy, steered

        policy = ppo_policy(Path(caution_policy))
        wrap = lambda agent: steered(agent, policy)  # noqa: E731
    return [Played.of(r, ("macro-slip, slow probe" if agent.crept else "macro-slip") if r.macro_slip else agent.stop_reason,
                      {s: source_error(agent, r, s, params.get("best_coa_factor", 1.0)) for s in available_sources(agent)},
                      bool(getattr(agent, "gated", False)))
            for r, agent in episodes(run, grid, config, params, guards, estimators, scenario, wrap)]


def _ends(setting: str, grid: str, runs: list[Played]) -> list[str]:
    """Rows of the table of how the climbs ended: per reason, the episodes, median / P90 error, the median
    signed error (the estimate over the CoF less 1, scored episodes; "-" where none was scored) and the
    median peak torque."""
    rows = []
    for ended in sorted({r.ended for r in runs}):
        these = [r for r in runs if r.ended == ended]
        s = score([(r.error, r.macro_slip) for r in these])
        signed = [r.signed_error for r in these if r.signed_error is not None]
        signed_text = f"{100 * float(np.median(signed)):+.1f} %" if signed else "-"
        rows.append(f"| {setting}{grid} | {ended} | {len(these)} of {len(runs)} | {100 * s['median']:.1f} % | "
                    f"{100 * s['p90']:.1f} % | {signed_text} | "
                    f"{100 * float(np.median([r.peak_torque_fraction for r in these])):.0f} % |")
    return rows


def unguarded_estimate(climb: dict, guards: list[str] | None, settings: dict[str, list] | None) -> dict:
    """The climb a row plays: one played without guards (``guards == []``) reports the filter's estimate where
    the shipped climb's reads the guards' (as the recipe ships a climb without a guard), unless ``--set`` names
    the estimate."""
    if guards == [] and climb.get("estimate_from") in GUARDED_ESTIMATES and "estimate_from" not in (settings or {}):
        return {**climb, "estimate_from": "filter"}
    return climb


def row_variants(settings: dict[str, list] | None = None, crest_fractions: list[float | None] | None = None,
                 crest_once_crept: bool = False) -> list[dict]:
    """The climb parameters each row sets over the shipped climb: every combination of the values of
    ``settings`` ({name: values}) and of ``crest_fractions`` (each cap from the first slow probe on with
    ``crest_once_crept``); ``[{}]`` (the shipped climb) when neither is given."""
    axes = dict(settings or {})
    if crest_fractions:
        axes["crest_fraction"] = list(crest_fractions)
        if crest_once_crept:
            axes["crest_once_crept"] = [True]
    return [dict(zip(axes, values)) for values in itertools.product(*axes.values())]


def climb_settings(run: Path, shipped: dict, targets: list[float], cautions: list[float] | None,
                   spread_cautions: list[float] | None, own_climb: bool) -> list[tuple[str, dict]]:
    """(label, climb) of every setting a run is played with: the shipped climb x caution x spread caution x
    target, or (``own_climb``) the climb its manifest names, labelled by what differs from the shipped one."""
    if own_climb:
        manifest = read_manifest(run)
        climb = {**shipped, **manifest["climb"]}
        base = {**asdict(ClimbParameters()), **shipped}  # the shipped climb with every default it leaves out
        changed = ", ".join(f"{k} {v}" for k, v in climb.items() if base.get(k) != v) or "the shipped climb"
        guarded = f"; guards {', '.join(manifest['guards'])}" if manifest.get("guards") else ""
        return [(f"{run} ({changed}{guarded})", climb)]
    return [(str(run), {**climb_at(shipped, t), "caution": c, "spread_caution": k})
            for c in cautions or [shipped["caution"]] for k in spread_cautions or [shipped.get("spread_caution", 0.0)]
            for t in targets]


def table(targets: list[float], workers: int, networks: list[Path] = (SHIPPED_INTERROGATOR,),
          cautions: list[float] | None = None, spread_cautions: list[float] | None = None,
          guards: list[Path] | None = None, stops: bool = False, own_climb: bool = False,
          grids: dict[str, Path] = GRID_SETS["validation"], crest_fractions: list[float | None] | None = None,
          crest_once_crept: bool = False, settings: dict[str, list] | None = None, guards_only: bool = False,
          estimators: list[Path] | None = None, return_digits: int = 2, records: list | None = None,
          scenario: dict | None = None, caution_policies: list[Path] | None = None) -> str:
    """The table (markdown) of every run's networks x set climb parameters (``settings``: each value of each
    in turn) x caution x spread caution x crest fraction x target x guards (with and without; ``guards_only``:
    only with; ``estimators``: every row with these estimator networks; ``return_digits``: the decimals of
    the mean returns; ``records``: a list that receives every episode as a dict), each row on the three
    ``grids`` (the validation grids unless told; ``scenario``: reset options over every episode's own, said in
    a line above the table; ``caution_policies``: every row with each of these PPO models setting its caution, in turn);
    other networks than the shipped agent's, several runs or ``own_climb`` (each with its manifest's climb, unchanged):
    a first column names the networks."""
    manifest_climb = read_manifest(SHIPPED_INTERROGATOR)["climb"]
    # None: the guards the run's manifest names (with own_climb: the climb as shipped), [] none
    guard_sets = (([] if guards_only else [[]]) + [[str(g) for g in guards]]) if guards else [None if own_climb else []]
    # a first column (and the records' setting) names the networks unless they are the shipped agent's alone
    named = own_climb or [Path(n).resolve() for n in networks] != [SHIPPED_INTERROGATOR.resolve()]
    rows = [(n, label, climb, gs, ", ".join(f"{k} {v}" for k, v in variant.items() if k in (settings or {})), policy)
            for n in networks for variant in row_variants(settings, crest_fractions, crest_once_crept)
            for label, climb in climb_settings(n, {**manifest_climb, **variant}, targets, cautions, spread_cautions,
                                               own_climb)
            for gs in guard_sets for policy in (caution_policies or [None])]
    rows = [(n, label, unguarded_estimate(climb, gs, settings), gs, set_text, policy)
            for n, label, climb, gs, set_text, policy in rows]
    estimator_dirs = [str(e) for e in estimators] if estimators else None  # None: the manifest's
    jobs = [(str(n), climb, str(g), cfg, gs, estimator_dirs, scenario, None if policy is None else str(policy))
            for n, _, climb, gs, _, policy in rows for g in grids.values() for cfg in CONFIGS]
    with ProcessPoolExecutor(workers) as pool:
        results = iter(list(pool.map(_play, *zip(*jobs))))
    head = " | ".join(f"{name}: median / P90 / macro-slips / return" for name in grids)

    def columns(label: str, climb: dict, gs: list[str] | None, set_text: str,
                policy: Path | None) -> list[tuple[str, str, str]]:
        """(header, cell, prefix in the setting's label) of the columns that say what a row sets."""
        crest_text = "-" if climb.get("crest_fraction") is None else \
            f"{climb['crest_fraction']:g}{' once crept' if climb.get('crest_once_crept') else ''}"
        optional = [("networks", label, "", named), ("set", set_text, "", bool(settings)),
                    ("caution", f"{climb['caution']:g}", "caution ", True),
                    ("spread caution", f"{climb.get('spread_caution', 0.0):g}", "spread caution ", bool(spread_cautions)),
                    ("crest fraction", crest_text, "crest fraction ", bool(crest_fractions)),
                    ("target headroom", f"{climb['target_headroom']:g}", "target ", True),
                    ("guards", ", ".join(gs or []) or "-", "guards ", bool(guards)),
                    ("estimators", ", ".join(estimator_dirs or []), "estimators ", bool(estimators)),
                    ("caution policy", str(policy), "caution policy ", bool(caution_policies))]
        return [(header, cell, prefix) for header, cell, prefix, shown in optional if shown]

    first = columns(*rows[0][1:]) if rows else []
    lines = [f"Every episode with {scenario_text(scenario)} over its own options.", ""] if scenario else []
    lines += ["| " + " | ".join([h for h, _, _ in first] + [head, "all: macro-slips / return"]) + " |",
             "|---" * (len(first) + len(grids) + 1) + "|"]
    ends = ["", "Where the climbs ended (both configurations; median signed: the median of the estimate over the "
            "CoF less 1, below the CoF negative; peak torque: the median over the episodes of the largest true "
            "torque, crest included, over the saturation torque):", "",
            "| setting, grid | ended | episodes | median | P90 | median signed | peak torque |",
            "|---|---|---|---|---|---|---|"]
    for _, label, climb, gs, set_text, policy in rows:
        row_columns = columns(label, climb, gs, set_text, policy)
        setting = "".join(f"{prefix}{cell}, " for _, cell, prefix in row_columns)
        cells, pooled = [], []
        for grid in grids:
            per_config = [next(results) for _ in CONFIGS]
            runs = [r for part in per_config for r in part]
            if records is not None:
                records += [r.as_record(setting.rstrip(", "), grid, config, i)
                            for config, part in zip(CONFIGS, per_config) for i, r in enumerate(part)]
            pooled += runs
            ends += _ends(setting, grid, runs)
            s = score([(r.error, r.macro_slip) for r in runs])
            cells.append(f"{100 * s['median']:.1f} % / {100 * s['p90']:.1f} % / {s['macro_slips']} of {len(runs)} / "
                         f"{np.mean([r.episode_return for r in runs]):.{return_digits}f}")
        lines.append("| " + " | ".join([cell for _, cell, _ in row_columns] + cells) +
                     f" | {sum(r.macro_slip for r in pooled)} of {len(pooled)} / "
                     f"{np.mean([r.episode_return for r in pooled]):.{return_digits}f} |")
    if stops:
        lines += ends
    return "\n".join(lines) + "\n"


def scenario_text(scenario: dict) -> str:
    """``name value, ...`` of the reset options ``--scenario`` sets."""
    return ", ".join(f"{name} {value}" for name, value in scenario.items())


def crest_fraction(text: str) -> float | None:
    """A ``--crest-fractions`` value: a number in [0, 4] or ``none`` (uncapped)."""
    if text.lower() == "none":
        return None
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0.0 <= value <= 4.0:
        raise argparse.ArgumentTypeError(f"must be a number in [0, 4] or none, got {text!r}")
    return value


def climb_item(text: str) -> tuple[str, object]:
    """``NAME=VALUE`` (:func:`~cof_gym.commands.args.name_value`) with NAME a :class:`ClimbParameters` field, as
    (name, value); the value is checked against a climb by :func:`checked_climb`."""
    name, value = name_value(text)
    fields = asdict(ClimbParameters())
    if name not in fields:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE with NAME a climb parameter ({', '.join(fields)}), got {text!r}")
    return name, value


def checked_climb(climb: dict, changes: dict, guards: int | None = None, estimators: int | None = None) -> None:
    """Raises ValueError naming the parameter where ``climb`` with ``changes`` is no valid climb (with ``guards``:
    for an interrogator with that many guards; with ``estimators``: that many estimators, so that an estimate source
    that reads networks the agent lacks is refused here, not in a worker mid-play)."""
    params = ClimbParameters(**{**climb, **changes})
    if guards is not None:
        params.check_guard_count(guards)
    if estimators == 0 and params.estimate_from in ESTIMATOR_ESTIMATES:
        raise ValueError(f"estimate_from={params.estimate_from!r} reads the estimators' corrections, but the "
                         "interrogator has no estimators")


def climb_setting(text: str) -> tuple[str, object]:
    """A ``--set`` item (:func:`climb_item`) whose value the shipped climb accepts."""
    name, parsed = climb_item(text)
    try:
        checked_climb(read_manifest(SHIPPED_INTERROGATOR)["climb"], {name: parsed})
    except ValueError as error:
        raise argparse.ArgumentTypeError(f"{name}: {error}") from None
    return name, parsed


def build_parser() -> Parser:
    """The command line (every option, its default and its help)."""
    parser = Parser(description=__doc__.split("\n")[0])
    parser.add_argument("--targets", type=float, nargs="+", default=None,
                        help="target headrooms of the shipped climb to try (default: 0.1 0.15 0.2 0.3)")
    parser.add_argument("--cautions", type=float, nargs="+", default=None,
                        help="caution factors to try (default: the shipped climb's)")
    parser.add_argument("--spread-cautions", type=float, nargs="+", default=None,
                        help="multiples of the members' spread also taken off the headroom (default: the shipped climb's)")
    parser.add_argument("--crest-fractions", type=crest_fraction, nargs="+", default=None,
                        help="crest fractions to try (the modulation's crest stays within that fraction of the cautious "
                             "headroom; 'none': uncapped, the shipped climb's default)")
    parser.add_argument("--crest-once-crept", action="store_true",
                        help="the crest cap (--crest-fractions) only from the climb's first slow probe on")
    parser.add_argument("--set", nargs="+", default=[], metavar="NAME=VALUE", type=climb_setting,
                        help="climb parameters (ClimbParameters fields; values JSON or plain text) set in the rows; a "
                             "name given several values: each in turn, e.g. creep_log_step=0.02 creep_log_step=0.045")
    parser.add_argument("--run", type=Path, nargs="+", default=[SHIPPED_INTERROGATOR],
                        help="directories of networks (member_*.npz) played with the shipped climb, each in turn")
    parser.add_argument("--guards", type=Path, nargs="+", default=None,
                        help="directories of networks (member_*.npz) that also steer the climb, all of them together as guards of "
                             "one climb (each row with and without them)")
    parser.add_argument("--estimators", type=Path, nargs="+", default=None,
                        help="directories of networks (member_*.npz) whose correction the estimate may read "
                             "(estimate_from estimator, estimator_pooled or guard_estimator_pooled), in every row; "
                             "they never steer")
    parser.add_argument("--guards-only", action="store_true",
                        help="play every row with the --guards only, not also without them")
    parser.add_argument("--own-climb", action="store_true",
                        help="play each run with the climb its manifest.json names, unchanged (no --targets, --cautions, "
                             "--spread-cautions)")
    parser.add_argument("--stops", action="store_true",
                        help="also a table of how the climbs ended (the agent's stop reason or a macro-slip, before or after "
                             "its first slow probe), per grid")
    parser.add_argument("--grids", choices=sorted(GRID_SETS), default="validation",
                        help="the three grids played: validation (model selection), validation_torque (the same kinds "
                             "with each episode's torque gain error spread over +-15 %%; torque_confirmation, "
                             "torque_confirmationN: its confirmation sets) or a confirmation set (other episodes of "
                             "the same kinds, to confirm a choice taken on the first; confirmationN: the N-th set, "
                             "experiments/make_grids.py's docstring says when each was written); "
                             "validation_extremes, extremes_confirmation, extremes_confirmationN: one grid of random "
                             "tables with every scenario field anywhere within what the env accepts")
    parser.add_argument("--return-digits", type=int, default=2, choices=range(1, 7), metavar="{1..6}",
                        help="decimals of the mean returns (default: 2); more where two rows round alike")
    parser.add_argument("--records", type=Path, default=None, metavar="FILE",
                        help="also write every episode (its setting, grid, configuration, error, macro-slip, return, how "
                             "the climb ended, and the error of every estimate source the agent could have reported) "
                             "to this JSON file")
    parser.add_argument("--scenario", nargs="+", default=[], metavar="NAME=VALUE", type=scenario_option,
                        help="reset options over every episode's own (scenario fields; values JSON or plain text), e.g. "
                             "noise_level=3 motor_lag_s=0.1: the grids' episodes with a sensor or drive outside the "
                             "training draws")
    parser.add_argument("--caution-policy", type=Path, nargs="+", default=None, metavar="MODEL",
                        help="PPO models (experiments/learned_caution.py's model.zip) that set the climb's caution at "
                             "every decision, each in turn in every row; models joined by + act by their mean action")
    parser.add_argument("--workers", type=positive_int, default=2)
    parser.add_argument("--out", type=Path, default=Path("out/crest_tradeoff.md"))
    return parser


def check_arguments(parser: Parser, args: argparse.Namespace) -> None:
    """Every option checked before anything is played (a usage error names it; ``--targets`` gets its default)."""
    check_out_file(parser, "--out", args.out)
    check_out_file(parser, "--records", args.records)
    if args.own_climb:
        for option, value in (("--targets", args.targets), ("--cautions", args.cautions),
                              ("--spread-cautions", args.spread_cautions), ("--crest-fractions", args.crest_fractions),
                              ("--crest-once-crept", args.crest_once_crept or None), ("--set", args.set or None)):
            if value is not None:
                parser.error(f"{option}: not with --own-climb (each run plays its own manifest's climb)")
        for run in args.run:
            if not (run / MANIFEST_FILE).is_file():
                parser.error(f"--run: no manifest.json in {run} (--own-climb plays the climb it names)")
    args.targets = args.targets or [0.1, 0.15, 0.2, 0.3]
    if any(not 0.0 < t < 1.0 for t in args.targets):
        parser.error("--targets must lie in (0, 1) (a headroom ln(M_sat / DC))")
    if args.guards_only and not args.guards:
        parser.error("--guards-only: needs --guards (the guards every row is played with)")
    if args.crest_once_crept and not args.crest_fractions:
        parser.error("--crest-once-crept: needs --crest-fractions (the cap it delays)")
    if args.cautions is not None and any(not 0.0 <= c <= 10.0 for c in args.cautions):
        parser.error("--cautions must lie in [0, 10] (standard deviations)")
    if args.spread_cautions is not None and any(not 0.0 <= k <= 10.0 for k in args.spread_cautions):
        parser.error("--spread-cautions must lie in [0, 10] (member spreads)")
    for cautions in (v for n, v in args.set if n == "guard_cautions" and v is not None):  # the rows' guards: here
        if not args.guards_only:
            parser.error("--set: guard_cautions needs --guards-only (every row then plays the --guards)")
        try:
            checked_climb(read_manifest(SHIPPED_INTERROGATOR)["climb"], {"guard_cautions": cautions}, len(args.guards))
        except ValueError as error:
            parser.error(f"--set: {error}")
    estimators = len(args.estimators or manifest_networks(SHIPPED_INTERROGATOR, "estimators"))
    for source in (v for n, v in args.set if n == "estimate_from"):
        try:
            checked_climb(read_manifest(SHIPPED_INTERROGATOR)["climb"], {"estimate_from": source}, None, estimators)
        except ValueError as error:
            parser.error(f"--set: {error} (give --estimators)")
    require_networks(parser, "--run", args.run)
    require_networks(parser, "--guards", args.guards or [])
    require_networks(parser, "--estimators", args.estimators or [])
    from learned_caution import check_caution_model, ensemble_members

    for model in (member for models in args.caution_policy or [] for member in ensemble_members(models)):
        check_caution_model(parser, "--caution-policy", model)


def main() -> None:
    parser = build_parser()
    args = parser.parse_args()
    check_arguments(parser, args)
    records = [] if args.records else None
    text = table(args.targets, args.workers, args.run, args.cautions, args.spread_cautions, args.guards, args.stops,
                 args.own_climb, GRID_SETS[args.grids], args.crest_fractions, args.crest_once_crept,
                 {name: [v for n, v in args.set if n == name] for name, _ in args.set}, args.guards_only,
                 args.estimators, args.return_digits, records, dict(args.scenario), args.caution_policy)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    if args.records:
        args.records.parent.mkdir(parents=True, exist_ok=True)
        args.records.write_text(json.dumps(records, indent=1) + "\n")
    print(text, end="")


if __name__ == "__main__":
    main()
