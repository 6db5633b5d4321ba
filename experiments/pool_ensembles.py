"""Pool network ensembles into one (run from the repository root; seconds, no simulation):

    python experiments/pool_ensembles.py --out runs/union120/filter \
        cof_gym/agents/policies/interrogator runs/interrogator_three/ensemble

Every ``member_*.npz`` of each directory, in the order given (each directory's members in their own order), is copied
to ``--out`` as ``member_0.npz``, ``member_1.npz``, ...: one ensemble whose prediction is the mean of all members' and
whose spread their disagreement (:class:`~cof_gym.agents.interrogator.networks.FilterEnsemble`), as rules 115 and 120
of docs/interrogator.md pooled two generations of networks. The members must read the same features (tones and
feature blocks): the pool is loaded as one ensemble before anything is written. ``--out`` must hold no networks yet.
A filter's pool is played with ``crest_tradeoff.py --run OUT`` or ``validation_plays.py NAME --run OUT``, a guard's
with ``--guards ... OUT``; ``assemble_policy.py --filter OUT`` makes it a policy directory.

With ``--within-generations`` the pool also records each directory's member count (a directory that is itself such a
pool, its own counts) in ``OUT/generations.json``, and is read generation by generation
(``FilterEnsemble.generations``): the mean of the generations' means, the mean of their variances, their disagreement
with one another left out of the std (rule 126 of docs/interrogator.md).
"""

from __future__ import annotations

import json
import shutil
import sys
import zipfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from script_checks import check_out_dir  # noqa: E402

from cof_gym.agents.interrogator.networks import GENERATIONS_FILE, FilterEnsemble, member_files  # noqa: E402
from cof_gym.commands.args import Parser  # noqa: E402


def pool(directories: list[Path], out: Path) -> list[Path]:
    """Copy every member of ``directories`` to ``out`` renumbered from 0 (``out`` created); the written files."""
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for source in (f for d in directories for f in member_files(d)):
        target = out / f"member_{len(written)}.npz"
        shutil.copyfile(source, target)
        written.append(target)
    return written


def main() -> None:
    parser = Parser(description=__doc__.splitlines()[0])
    parser.add_argument("directories", type=Path, nargs="+", metavar="DIR",
                        help="ensembles to pool (directories of member_*.npz), at least two")
    parser.add_argument("--out", type=Path, required=True, help="the pooled ensemble's directory (no networks yet)")
    parser.add_argument("--within-generations", action="store_true",
                        help="read the pool generation by generation (OUT/generations.json: each DIR's member count)")
    args = parser.parse_args()
    if len(args.directories) < 2:
        parser.error(f"DIR: {len(args.directories)} directory given; pooling needs at least two")
    check_out_dir(parser, "--out", args.out)
    if member_files(args.out):
        parser.error(f"--out: {args.out} already holds networks (member_*.npz); give an empty or new directory")
    resolved = [d.resolve() for d in args.directories]
    if twice := sorted({str(d) for d, r in zip(args.directories, resolved) if resolved.count(r) > 1}):
        parser.error(f"DIR: {', '.join(twice)} given more than once; its networks would count twice in the pool")
    members = []
    for directory in args.directories:
        try:
            members.append(FilterEnsemble.load(directory))
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as e:
            parser.error(f"DIR: {directory}: {' '.join(str(e).split())[:160]}")
    generations = tuple(n for e in members for n in (e.generations or (len(e.members),))) \
        if args.within_generations else None
    try:
        FilterEnsemble(tuple(m for ensemble in members for m in ensemble.members), generations)
    except ValueError as e:
        parser.error(f"DIR: {', '.join(map(str, args.directories))}: {e}")
    written = pool(args.directories, args.out)
    if generations:
        (args.out / GENERATIONS_FILE).write_text(json.dumps({"members": list(generations)}) + "\n")
    sizes = " + ".join(str(len(e.members)) for e in members)
    print(f"{args.out}: {len(written)} members ({sizes}) from {', '.join(map(str, args.directories))}")


if __name__ == "__main__":
    main()
