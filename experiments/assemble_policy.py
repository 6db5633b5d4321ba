"""Assemble a learned interrogator's policy directory from a filter's networks, guards and another policy's climb
(run from the repository root; seconds, no simulation):

    python experiments/assemble_policy.py --filter runs/interrogator_torque/ensemble \
        --guards runs/interrogator_torque/guard/ensemble --out runs/torque_C_policy
    python experiments/assemble_policy.py --filter cof_gym/agents/policies/interrogator \
        --guards cof_gym/agents/policies/interrogator/guard_0 cof_gym/agents/policies/interrogator/guard_1 \
        --smoothed-filter runs/interrogator_smoothed/ensemble \
        --smoothed-guards cof_gym/agents/policies/interrogator/guard_0 runs/interrogator_smoothed/guard/ensemble \
        --out runs/gate127 [--smoothed-set caution=2.5]
    python experiments/assemble_policy.py --into cof_gym/agents/policies/interrogator \
        --smoothed-filter runs/interrogator_smoothed/ensemble \
        --smoothed-guards cof_gym/agents/policies/interrogator/guard_0 runs/interrogator_smoothed/guard/ensemble \
        --smoothed-set caution=2.25

A policy directory is what ``cof-gym evaluate --agents interrogator:DIR``, ``train_estimator.py --policy`` and
``crest_tradeoff.py --own-climb --run`` read: the filter's networks (``member_K.npz``), each guard's (``guard_K/``,
in the order given: the climb steers by the lowest cautious headroom of them all and the shipped estimate reads the
guards') and a ``manifest.json`` whose climb and training distribution are ``--climb-from``'s (default: the shipped
interrogator's). Networks fitted by ``train_interrogator.py --fit-only`` thus collect their own on-policy climbs
(the recipe's second step) under a climb chosen before, without a selection of their own. The manifest's
``training`` names the directories the networks were copied from (each one's ``training.json`` says what they were
fitted on); no interval is copied (``estimate_interval.py --write`` calibrates one for these networks). With
``--smoothed-filter`` (and ``--smoothed-guards``, as many as ``--guards``) the directory also carries the networks
that steer and estimate a climb whose first windows read a smoothed encoder (rule 127's gate:
``smoothed_encoder/filter``, ``smoothed_encoder/guard_K``, named by the manifest's ``smoothed_encoder``;
``--smoothed-set NAME=VALUE ...``: climb parameters changed for the decisions those networks take, rule 128).
``--into DIR`` adds (or replaces) those networks in an existing policy directory instead, the shipped one for
instance, keeping its networks, guards, climb and training record; its interval is removed, since the smoothed
class's scales are in the stds of the networks that read it (``estimate_interval.py --policy DIR --write``
recalibrates).
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from script_checks import check_out_dir  # noqa: E402
from crest_tradeoff import checked_climb, climb_item  # noqa: E402
from train_interrogator import copy_networks, install_guards, require_networks  # noqa: E402

from cof_gym.agents.interrogator import INTERVAL_FILE, SHIPPED_INTERROGATOR  # noqa: E402
from cof_gym.agents.interrogator.agent import read_manifest, write_manifest  # noqa: E402
from cof_gym.agents.interrogator.networks import ensemble_files  # noqa: E402
from cof_gym.commands.args import DistinctNames, Parser  # noqa: E402


def shown(path: Path) -> str:
    """``path`` relative to the working directory where it lies below it (the manifest names no machine's paths)."""
    path = Path(path)
    return str(path.resolve().relative_to(Path.cwd())) if path.resolve().is_relative_to(Path.cwd()) else str(path)


SMOOTHED_DIR = "smoothed_encoder"  # where a policy directory keeps its smoothed-encoder networks


def install_smoothed(out: Path, filter_dir: Path, guards: list[Path], climb: dict | None = None) -> dict:
    """Copies the smoothed-encoder networks into ``out/smoothed_encoder`` and returns the manifest's entry for them
    (paths relative to ``out``; ``climb``: the climb parameters their decisions change, if any)."""
    copy_networks(filter_dir, out / SMOOTHED_DIR / "filter")
    names = [f"{SMOOTHED_DIR}/guard_{k}" for k in range(len(guards))]
    for name, guard in zip(names, guards):
        copy_networks(guard, out / name)
    return {"filter": f"{SMOOTHED_DIR}/filter", "guards": names, **({"climb": dict(climb)} if climb else {})}


def smoothed_sources(filter_dir: Path, guards: list[Path]) -> dict:
    """Where the smoothed-encoder networks were copied from, as a manifest's ``training`` records it."""
    return {"filter": shown(filter_dir), "guards": [shown(g) for g in guards]}


def assemble(filter_dir: Path, guards: list[Path], climb_from: Path, out: Path, smoothed_filter: Path | None = None,
             smoothed_guards: list[Path] = (), smoothed_climb: dict | None = None) -> dict:
    """Write the policy directory ``out`` (its networks and guards replaced, nothing else there kept) and return its
    manifest: ``climb_from``'s climb and training distribution, ``filter_dir``'s networks, ``guards`` in order (with
    ``smoothed_filter``, also the smoothed-encoder networks: that filter and ``smoothed_guards``, their decisions with
    the climb parameters ``smoothed_climb``)."""
    source = read_manifest(climb_from)
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    for member in ensemble_files(filter_dir):
        shutil.copy2(member, out / member.name)
    manifest = {"climb": source["climb"], "trained_on": source["trained_on"],
                "training": {"assembled_from": {"filter": shown(filter_dir), "guards": [shown(g) for g in guards],
                                                "climb": shown(climb_from)}}}
    names = install_guards(out, guards)
    if names:
        manifest["guards"] = names
    if smoothed_filter is not None:
        manifest["smoothed_encoder"] = install_smoothed(out, smoothed_filter, list(smoothed_guards), smoothed_climb)
        manifest["training"]["assembled_from"][SMOOTHED_DIR] = smoothed_sources(smoothed_filter, smoothed_guards)
    write_manifest(out, manifest)
    return manifest


def add_smoothed(into: Path, smoothed_filter: Path, smoothed_guards: list[Path],
                 smoothed_climb: dict | None = None) -> dict:
    """Add the smoothed-encoder networks to the policy directory ``into`` (any it had replaced; its own networks,
    guards, climb and training record kept; its interval removed) and return its manifest."""
    manifest = read_manifest(into)
    if (into / SMOOTHED_DIR).exists():
        shutil.rmtree(into / SMOOTHED_DIR)
    manifest["smoothed_encoder"] = install_smoothed(into, smoothed_filter, list(smoothed_guards), smoothed_climb)
    manifest.setdefault("training", {})[SMOOTHED_DIR] = {
        "assembled_from": smoothed_sources(smoothed_filter, smoothed_guards)}
    (into / INTERVAL_FILE).unlink(missing_ok=True)
    write_manifest(into, manifest)
    return manifest


def check_into(ap: Parser, args) -> None:
    """``--into``'s arguments: a policy directory with a climb, only the smoothed-encoder options beside it, and no
    network read from inside the ``smoothed_encoder/`` it replaces (one line and exit code 2)."""
    for flag, given in (("--filter", args.filter), ("--guards", args.guards), ("--climb-from", args.climb_from),
                        ("--out", args.out)):
        if given:
            ap.error(f"{flag}: not with --into (the directory keeps its own networks and guards)")
    if args.smoothed_filter is None:
        ap.error("--into: needs --smoothed-filter (the networks it adds)")
    if "climb" not in read_manifest(args.into):
        ap.error(f"--into: {args.into} has no manifest.json with a climb (a policy directory)")
    replaced = (args.into / SMOOTHED_DIR).resolve()
    for source in (args.smoothed_filter, *args.smoothed_guards):
        if source.resolve().is_relative_to(replaced):
            ap.error(f"--into: {source} lies in {args.into / SMOOTHED_DIR}, which --into replaces")


def main() -> None:
    ap = Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--filter", type=Path, default=None, metavar="DIR",
                    help="the filter's networks (DIR/member_*.npz); required unless --into")
    ap.add_argument("--guards", type=Path, nargs="*", default=[], metavar="DIR",
                    help="each guard's networks (DIR/member_*.npz), in the order the manifest names them")
    ap.add_argument("--climb-from", type=Path, default=None, metavar="DIR",
                    help="the policy directory whose manifest's climb and training distribution are kept "
                         "(default: the shipped interrogator)")
    ap.add_argument("--smoothed-filter", type=Path, default=None, metavar="DIR",
                    help="the filter that steers a climb whose first windows read a smoothed encoder (rule 127)")
    ap.add_argument("--smoothed-guards", type=Path, nargs="*", default=[], metavar="DIR",
                    help="with --smoothed-filter: its guards, as many as --guards")
    ap.add_argument("--smoothed-set", type=climb_item, nargs="+", default=[], metavar="NAME=VALUE",
                    action=DistinctNames,
                    help="with --smoothed-filter: climb parameters changed for the decisions its networks take")
    ap.add_argument("--out", type=Path, default=None, metavar="DIR",
                    help="the policy directory written (replaced where it exists); required unless --into")
    ap.add_argument("--into", type=Path, default=None, metavar="DIR",
                    help="add the smoothed-encoder networks to this policy directory instead (its interval removed)")
    args = ap.parse_args()
    if args.into is not None:
        check_into(ap, args)
        args.guards = [args.into / g for g in read_manifest(args.into).get("guards", [])]
        args.climb_from = args.into
    else:
        for flag, given in (("--filter", args.filter), ("--out", args.out)):
            if given is None:
                ap.error(f"{flag}: required (or --into DIR)")
        require_networks(ap, "--filter", [args.filter])
        args.climb_from = args.climb_from or SHIPPED_INTERROGATOR
    require_networks(ap, "--guards", args.guards)
    for flag, given in (("--smoothed-guards", args.smoothed_guards), ("--smoothed-set", args.smoothed_set)):
        if args.smoothed_filter is None and given:
            ap.error(f"{flag}: needs --smoothed-filter")
    smoothed_climb = dict(args.smoothed_set)
    try:
        checked_climb(read_manifest(args.climb_from).get("climb", {}), smoothed_climb, len(args.guards))
    except (TypeError, ValueError) as error:
        ap.error(f"--smoothed-set: {error}")
    if args.smoothed_filter is not None:
        require_networks(ap, "--smoothed-filter", [args.smoothed_filter])
        require_networks(ap, "--smoothed-guards", args.smoothed_guards)
        if len(args.smoothed_guards) != len(args.guards):
            ap.error(f"--smoothed-guards: {len(args.smoothed_guards)} given, as many as --guards needed "
                     f"({len(args.guards)}: the climb's guard cautions apply guard by guard)")
    if args.into is not None:
        manifest = add_smoothed(args.into, args.smoothed_filter, args.smoothed_guards, smoothed_climb)
        print(f"{args.into}: smoothed-encoder networks of {args.smoothed_filter} added (climb "
              f"{manifest['smoothed_encoder'].get('climb', {})}); its interval removed: "
              f"estimate_interval.py --policy {args.into} --write recalibrates it")
        return
    if not {"climb", "trained_on"} <= read_manifest(args.climb_from).keys():
        ap.error(f"--climb-from: {args.climb_from} has no manifest.json with a climb and a training distribution")
    check_out_dir(ap, "--out", args.out)
    read = (args.filter, *args.guards, args.climb_from, *filter(None, [args.smoothed_filter]), *args.smoothed_guards)
    if args.out.resolve() in {p.resolve() for p in read}:
        ap.error(f"--out: {args.out} is one of the directories read")
    manifest = assemble(args.filter, args.guards, args.climb_from, args.out, args.smoothed_filter,
                        args.smoothed_guards, smoothed_climb)
    smoothed = f", smoothed-encoder networks of {args.smoothed_filter}" if args.smoothed_filter else ""
    steering = ", ".join(f"{k} {v}" for k, v in manifest["climb"].items() if k in ("target_headroom", "caution"))
    print(f"{args.out}: the filter of {args.filter}, {len(args.guards)} guard(s){smoothed}, the climb of "
          f"{shown(args.climb_from)} ({steering})")


if __name__ == "__main__":
    main()
