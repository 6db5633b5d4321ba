"""Output-path checks shared by the experiment scripts: run right after ``parse_args``, before any
simulation and before anything is created, so a bad ``--out`` is one usage line (exit status 2) naming
the option, not a traceback at the end of a long run."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from cof_gym.commands.args import PSEUDO_FILESYSTEMS, UsageError, check_output_dir, filesystem_type


def check_out_file(parser: argparse.ArgumentParser, option: str, path: Path | None) -> None:
    """``path`` (None: not given) can be written as a file: not a directory, below no file, in a
    writable place (its missing parent directories are created by the script); otherwise
    ``parser.error`` naming ``option``."""
    if path is None:
        return
    path = Path(path)
    if path.is_dir():
        parser.error(f"{option}: {path} is a directory; give a file")
    if path.exists() and not os.access(path, os.W_OK):
        parser.error(f"{option}: {path} is not writable")
    ancestor = path.resolve().parent
    while not ancestor.exists():
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        parser.error(f"{option}: {path}: {ancestor} is a file, not a directory")
    if not os.access(ancestor, os.W_OK | os.X_OK) or os.statvfs(ancestor).f_flag & os.ST_RDONLY:
        if not path.exists():
            parser.error(f"{option}: {path}: {ancestor} is not writable")
    fs_type = filesystem_type(ancestor)
    if fs_type in PSEUDO_FILESYSTEMS:
        parser.error(f"{option}: {path}: {ancestor} is on a {fs_type} pseudo-filesystem; give a file on disk")


def check_out_dir(parser: argparse.ArgumentParser, option: str, path: Path) -> None:
    """``path`` can be created or reused as an output directory (:func:`cof_gym.commands.args.check_output_dir`:
    not an existing file, below no file, writable); otherwise ``parser.error`` naming ``option``."""
    try:
        check_output_dir(Path(path), option)
    except UsageError as error:
        parser.error(str(error))
