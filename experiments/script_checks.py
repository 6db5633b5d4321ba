"""Checks shared by the experiment scripts: run right after ``parse_args``, before any simulation and
before anything is created, so a bad ``--out`` (or an unreadable input file) is one usage line (exit status 2)
naming the option, not a traceback at the end of a long run (the checks of :mod:`cof_gym.commands.args`,
reported through the script's parser); and the report's write once the run is done (:func:`write_report`)."""

from __future__ import annotations

import argparse
import zipfile
from pathlib import Path
from typing import Any

from cof_gym.commands.args import UsageError, check_output_dir, check_output_file


def check_out_file(parser: argparse.ArgumentParser, option: str, path: Path | None) -> None:
    """``path`` (None: not given) can be written as a file (:func:`cof_gym.commands.args.check_output_file`: not
    a directory, below no file, in a writable place; its missing parent directories are created by the script);
    otherwise ``parser.error`` naming ``option``."""
    if path is None:
        return
    try:
        check_output_file(Path(path), option)
    except UsageError as error:
        parser.error(str(error))


def check_out_dir(parser: argparse.ArgumentParser, option: str, path: Path) -> None:
    """``path`` can be created or reused as an output directory (:func:`cof_gym.commands.args.check_output_dir`:
    not an existing file, below no file, writable); otherwise ``parser.error`` naming ``option``."""
    try:
        check_output_dir(Path(path), option)
    except UsageError as error:
        parser.error(str(error))


def checked_agents(parser: argparse.ArgumentParser, option: str, specs: list[str], no_oracle: str | None = None
                   ) -> list[str]:
    """The agents ``specs`` of ``option`` (cof-gym evaluate's names), at least one, each once, each known to the
    registry with a usable ``:ARG`` (a model file that exists); with ``no_oracle`` (why), none that reads the truth.
    Otherwise ``parser.error`` naming ``option``, before any simulation."""
    from cof_gym.agents import registry

    specs = [spec.strip() for spec in specs if spec.strip()]
    if not specs:
        parser.error(f"{option}: give at least one agent")
    if repeated := sorted({spec for spec in specs if specs.count(spec) > 1}):
        parser.error(f"{option}: {', '.join(repeated)} given more than once; give each agent once")
    for spec in specs:
        try:
            entry, argument = registry.parse(spec)
            registry.check_argument(entry, argument)
        except (ValueError, OSError) as error:
            parser.error(f"{option}: {spec}: {error}")
        if no_oracle and entry.oracle:
            parser.error(f"{option}: {spec} reads the truth; {no_oracle}")
    return specs


def load_climbs(parser: argparse.ArgumentParser, option: str, path: Path) -> Any:
    """The climbs ``path`` holds (a file ``Dataset.save`` wrote: :class:`~cof_gym.agents.interrogator.training.Dataset`);
    a missing or unreadable file is ``parser.error`` naming ``option``."""
    from cof_gym.agents.interrogator.training import Dataset  # torch: only the scripts that read climbs

    try:
        return Dataset.load(path)
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as error:
        parser.error(f"{option}: {path} is not a climbs file ({error.__class__.__name__}: {error})")


def write_report(path: Path | None, lines: list[str]) -> None:
    """Print the report ``lines`` and write them to ``path`` where one is given (checked by :func:`check_out_file`
    before the run; its missing parent directories are created)."""
    text = "\n".join(lines) + "\n"
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    print(text, end="")
