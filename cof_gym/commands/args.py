"""Command-line building blocks shared by every cof-gym command: one-line usage errors (exit status
2), argparse with defaults in --help, argument types with their allowed ranges, output-directory
checks. Imports nothing of cof_gym, so every command (and the CLI above them) may import it."""

from __future__ import annotations

import argparse
import ast
import json
import math
import os
import re
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
        default = action.default
        # by identity: 0 == False, and a default of 0 (a seed, a count) was hidden as a switch's False
        hidden = any(default is v for v in (None, False, argparse.SUPPRESS))
        if ("%(default)" in text or hidden or not action.option_strings
                or (isinstance(default, (list, tuple, dict, set)) and not default)):
            return text
        return text + f" (default: {default_text(default)})".replace("%", "%%")


def default_text(value: object) -> str:
    """A default as a user types it: a path relative to the working directory where it lies below it,
    a list as its items separated by spaces."""
    if isinstance(value, (list, tuple)):
        return " ".join(default_text(v) for v in value)
    if isinstance(value, Path):
        try:
            return str(value.resolve().relative_to(Path.cwd().resolve()))
        except ValueError:
            return str(value)
    return str(value)


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``cof-gym evaluate: error: argument --episodes: ...`` (no usage
    block), exit status 2."""

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str):  # noqa: D102 - argparse API
        message = " ".join(message.split())
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


class StoreDict(argparse.Action):
    """``key:value`` pairs into a dict (RL Zoo's ``--env-kwargs`` / ``--hyperparams`` syntax); values are
    Python literals (``5``, ``0.1``, ``True``, ``'dry'``, ``[1, 2]``) or else plain strings."""

    def __call__(self, parser, namespace, values, option_string=None):
        out = dict(getattr(namespace, self.dest) or {})
        given_attr = f"_{self.dest}_given"  # the keys of every earlier occurrence of the flag (the default's are not)
        given: set[str] = set(getattr(namespace, given_attr, ()))
        for item in values:
            key, sep, value = item.partition(":")
            if not sep or not key:
                parser.error(f"{option_string} expects key:value pairs, got {item!r}")
            if key in given:
                parser.error(f"{option_string}: {key!r} given twice; give each key once")
            given.add(key)
            out[key] = _literal_or_text(value)
            if isinstance(out[key], str) and _JOINED_PAIR.search(value):
                parser.error(f"{option_string}: {item!r} joins several pairs with a comma; separate key:value "
                             "pairs with spaces (KEY:VALUE KEY:VALUE)")
        setattr(namespace, given_attr, given)
        setattr(namespace, self.dest, out)


class DistinctValues(argparse.Action):
    """A ``nargs`` list whose values must differ (``--seeds 0 0`` would run or fit the same seed twice)."""

    what = "value"  # what the error asks to give once

    @staticmethod
    def compared(value):
        """What must differ between two of the values: the value itself."""
        return value

    def __call__(self, parser, namespace, values, option_string=None):
        keys = [self.compared(v) for v in values]
        repeated = sorted({str(k) for k in keys if keys.count(k) > 1})
        if repeated:
            parser.error(f"{option_string}: {', '.join(repeated)} given more than once; give each {self.what} once")
        setattr(namespace, self.dest, list(values))


class DistinctNames(DistinctValues):
    """A ``nargs`` list of ``(name, value)`` pairs (:func:`name_path`) whose names must differ."""

    what = "name"

    @staticmethod
    def compared(value):
        return value[0]


# text that reads as a second pair joined to a plain-text value by a comma (``0.04,encoder_lag_s:0.02``); a value
# that is a literal (a dict, a list) is read as one
_JOINED_PAIR = re.compile(r",\s*[A-Za-z_]\w*:")


def _literal_or_text(text: str) -> object:
    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return text


# ---------------------------------------------------------------------------- argument types
def _int_at_least(text: str, low: int, high: int | None = None) -> int:
    try:
        value = int(text)
    except ValueError:
        value = low - 1
    if value < low or (high is not None and value > high):
        bound = f">= {low}" if high is None else f"in [{low}, {high}]"
        raise argparse.ArgumentTypeError(f"must be an integer {bound}, got {text!r}")
    return value


def int_in_range(low: int, high: int):
    """An argparse type: an integer in [low, high]."""

    def parse(text: str) -> int:
        return _int_at_least(text, low, high)

    parse.__name__ = f"integer in [{low}, {high}]"
    return parse


MAX_SEED = 2**63 - 1  # an episode seed: a signed 64-bit integer (episodes.csv's seed column, numpy's int64)
MAX_TRAIN_SEED = 2**32 - 1  # a training seed: SB3's set_random_seed seeds numpy's legacy generator (32 bits)


def seed_int(text: str) -> int:
    """An argparse type: an episode seed, an integer in [0, MAX_SEED]."""
    return _int_at_least(text, 0, MAX_SEED)


def train_seed_int(text: str) -> int:
    """An argparse type: a training seed, an integer in [0, MAX_TRAIN_SEED]."""
    return _int_at_least(text, 0, MAX_TRAIN_SEED)


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


def float_at_least(low: float):
    """An argparse type: a finite number >= low."""

    def parse(text: str) -> float:
        return _float_above(text, low, inclusive=True)

    parse.__name__ = f"number >= {low:g}"
    return parse


def float_in_range(low: float, high: float, low_inclusive: bool = False):
    """An argparse type: a finite number in (low, high] (``low_inclusive``: [low, high])."""
    bound = f"{'[' if low_inclusive else '('}{low:g}, {high:g}]"

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not (math.isfinite(value) and (low <= value if low_inclusive else low < value) and value <= high):
            raise argparse.ArgumentTypeError(f"must be a finite number in {bound}, got {text!r}")
        return value

    parse.__name__ = f"number in {bound}"
    return parse


def positive_float(text: str) -> float:
    return _float_above(text, 0.0, inclusive=False)


def _name_and_text(text: str, what: str) -> tuple[str, str]:
    """``NAME=...`` split at its first ``=``, both sides non-empty; ArgumentTypeError (``expected NAME=what``)."""
    name, sep, value = text.partition("=")
    if not sep or not name or not value:
        raise argparse.ArgumentTypeError(f"expected NAME={what}, got {text!r}")
    return name, value


def name_path(text: str) -> tuple[str, Path]:
    """An argparse type: ``NAME=DIR`` as (name, path); the caller checks the path."""
    name, path = _name_and_text(text, "DIR")
    return name, Path(path)


def name_value(text: str) -> tuple[str, object]:
    """An argparse type: ``NAME=VALUE`` as (name, value), VALUE read as JSON (a number, true/false, null, a list
    or an object) or, where it is no JSON, as the text itself (``condition=dry``); the caller checks both."""
    name, value = _name_and_text(text, "VALUE")
    try:
        parsed = json.loads(value)
    except ValueError:  # json.JSONDecodeError is a ValueError
        parsed = value
    return name, parsed


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
    _check_nearest_ancestor(path, resolved, flag, "directory")
    return path


def check_command_output(path: Path, marker: str, command: str, flag: str = "--out") -> Path:
    """``flag``: a creatable directory (:func:`check_output_dir`) that, where it exists, is empty or an earlier output
    of ``command`` (it holds ``marker``), so that a run never writes into a directory of other files."""
    out = check_output_dir(Path(path), flag)
    if out.is_dir() and any(out.iterdir()) and not (out / marker).is_file():
        raise UsageError(flag, f"{out} exists and is not a {command} output (no {marker}); give a new or empty "
                               "directory")
    return out


def check_output_file(path: Path, flag: str = "--out") -> Path:
    """An output file that can be written: not a directory, writable if it exists, below no file, its nearest
    existing ancestor (missing folders are created by the writer) writable unless the file is there already,
    not on a pseudo-filesystem. Creates nothing."""
    path = Path(path)
    if path.is_dir():
        raise UsageError(flag, f"{path} is a directory; give a file")
    if path.exists() and not os.access(path, os.W_OK):
        raise UsageError(flag, f"{path} is not writable")
    _check_nearest_ancestor(path, path.resolve().parent, flag, "file", writable=not path.exists())
    return path


def _check_nearest_ancestor(path: Path, start: Path, flag: str, kind: str, writable: bool = True) -> None:
    """The nearest existing folder at or above ``start`` (where ``path``, a ``kind`` of output, will be made) is a
    directory, writable (where ``writable``) and on disk; :class:`UsageError` naming ``flag`` otherwise."""
    ancestor = start
    while not ancestor.exists():
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise UsageError(flag, f"{path}: {ancestor} is a file, not a directory")
    if writable and (not os.access(ancestor, os.W_OK | os.X_OK) or os.statvfs(ancestor).f_flag & os.ST_RDONLY):
        raise UsageError(flag, f"{path}: {ancestor} is not writable")
    fs_type = filesystem_type(ancestor)
    if fs_type in PSEUDO_FILESYSTEMS:
        raise UsageError(flag, f"{path}: {ancestor} is on a {fs_type} pseudo-filesystem; give a {kind} on disk")


# kernel filesystems that hold no files (writes fail even as root, where os.access says yes)
PSEUDO_FILESYSTEMS = frozenset({"proc", "sysfs", "devpts", "cgroup", "cgroup2", "debugfs", "tracefs", "securityfs",
                                "pstore", "bpf", "configfs", "fusectl", "mqueue", "binfmt_misc", "autofs"})


def filesystem_type(path: Path) -> str | None:
    """The type of the filesystem mounted at or above ``path`` (Linux ``/proc/self/mountinfo``; None
    elsewhere or when unknown)."""
    try:
        lines = Path("/proc/self/mountinfo").read_text().splitlines()
    except OSError:
        return None
    best, fs_type = "", None
    target = str(Path(path).resolve())
    for line in lines:
        fields = line.split()
        if " - " not in line or len(fields) < 5:
            continue
        mount = fields[4].replace("\\040", " ")
        inside = target == mount or target.startswith(mount.rstrip("/") + "/")
        if inside and len(mount) >= len(best):
            best, fs_type = mount, line.split(" - ", 1)[1].split()[0]
    return fs_type
