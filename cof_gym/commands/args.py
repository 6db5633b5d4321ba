"""Command-line building blocks shared by every cof-gym command: one-line usage errors (exit status
2), argparse with defaults in --help, argument types with their allowed ranges, output-directory
checks. Imports nothing of cof_gym, so every command (and the CLI above them) may import it."""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

PROG = "cof-gym"


class UsageError(Exception):
    """A bad command line: reported as one line ``cof-gym CMD: error: FLAG: message``, exit status 2."""

    def __init__(self, flag: str | None, message: str) -> None:
        super().__init__(f"{flag}: {message}" if flag else message)
        self.flag = flag


class HelpFormatter(argparse.RawDescriptionHelpFormatter, argparse.ArgumentDefaultsHelpFormatter):
    """Descriptions as written, and every option's default (unless it has none worth showing)."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if "%(default)" in text or action.default in (None, False, argparse.SUPPRESS) or not action.option_strings:
            return text
        return text + " (default: %(default)s)"


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``cof-gym evaluate: error: argument --episodes: ...`` (no usage
    block), exit status 2."""

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str):  # noqa: D102 - argparse API
        message = " ".join(message.split())
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


# ---------------------------------------------------------------------------- argument types
def _int_at_least(text: str, low: int) -> int:
    try:
        value = int(text)
    except ValueError:
        value = low - 1
    if value < low:
        raise argparse.ArgumentTypeError(f"must be an integer >= {low}, got {text!r}")
    return value


def positive_int(text: str) -> int:
    return _int_at_least(text, 1)


def non_negative_int(text: str) -> int:
    return _int_at_least(text, 0)


def _float_above(text: str, low: float, inclusive: bool) -> float:
    bound = f">= {low:g}" if inclusive else f"> {low:g}"
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number {bound}, got {text!r}") from None
    if not math.isfinite(value) or value < low or (value == low and not inclusive):
        raise argparse.ArgumentTypeError(f"must be a finite number {bound}, got {text!r}")
    return value


def positive_float(text: str) -> float:
    return _float_above(text, 0.0, inclusive=False)


def non_negative_float(text: str) -> float:
    return _float_above(text, 0.0, inclusive=True)


def check_output_dir(path: Path, flag: str = "--out") -> Path:
    """An output directory that can be created or replaced: not an existing file, below no file, in a
    writable place, not the current directory or one of its parents. Creates nothing."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise UsageError(flag, f"{path} exists and is not a directory; give a directory")
    resolved = path.resolve()
    cwd = Path.cwd().resolve()
    if resolved == cwd or resolved in cwd.parents:
        raise UsageError(flag, f"{path} is the current directory or one of its parents; give a subdirectory")
    ancestor = resolved
    while not ancestor.exists():
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise UsageError(flag, f"{path}: {ancestor} is a file, not a directory")
    if not os.access(ancestor, os.W_OK | os.X_OK):
        raise UsageError(flag, f"{path}: {ancestor} is not writable")
    return path
