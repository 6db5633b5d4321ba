"""Evaluation suites: which environment, and which seeded scenarios every agent meets.

A suite file is JSON::

    {
      "env_id": "CofGym/TorqueInterrogation-v1",        (optional; default: the wagon)
      "env_kwargs": {"counter_torque": true},            (optional; constructor arguments, not ones that
                          change the agents' interface (INTERFACE_KWARGS), a max_episode_steps below the horizon
                          or the id's own vehicle and task_version (ID_KWARGS): env_id names those)
      "options": {"condition": "wet"},                   (optional; reset options of every episode)
      "episodes": [{"seed": 1, "options": {"cof": 0.2}, "note": "..."}, ...],
                          (options: any scenario field, e.g. "creep_law": "wet",
                           {"polach": {...}} or {"table": {"creepage": [...],
                           "adhesion_ratio": [...]}}, "speed_sensor_error": 0.01; or
                           "creep_table": "curves/dry.csv", a measured curve's CSV beside
                           the suite file, read as cof-gym evaluate --creep-table reads it:
                           its table, at its own CoF unless the options give "cof")
      "description": "..."                               (optional; free text)
    }

Without ``"episodes"``, ``--episodes`` seeded draws (seeds ``seed``, ``seed + 1``, ...) are played;
with it, exactly those (an episode's ``"options"`` are merged over the top-level ones, its ``"seed"``
defaults to ``seed + index``, its optional ``"note"`` labels it: ``cof-gym evaluate`` breaks its
results down by note, e.g. a grid's creep-curve shapes). Anything else is refused with a
:class:`SuiteError` naming the file.
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable, Iterator

import cof_gym
from cof_gym.analysis.theory import PAPER_COFS, PAPER_SPEED_M_S
from cof_gym.commands.args import MAX_SEED, name_value
from cof_gym.task.scenarios import COF_ENVELOPE, check_fixed, shape_spec
from cof_gym.validation import TABLE_CELL_FORBIDDEN, brief, check_int, check_number, is_int
from cof_gym.task.sensors import SYSTEMATIC_ERRORS

FILE_KEYS = ("env_id", "env_kwargs", "options", "episodes", "description")
EPISODE_KEYS = ("seed", "options", "note")  # note: a free-text label (evaluate's breakdown groups by it)
# env_kwargs that change the interface the evaluated agents act through: what every agent needs (the env's
# default). An agent that acts in another excitation gets an env of its own (its ``env_options``,
# cof_gym.commands.evaluate.agent_envs); the PPO agent applies its action type agent-side.
INTERFACE_KWARGS = {
    "action_type": "absolute",  # the agents encode absolute actions (cof_gym.task.interface.encode_action)
    "excitation": "sine",  # the agents send the sine's 5-value action
    "info_layout": "nested",  # the evaluator and the oracles read info["measurement"] and info["ground_truth"]
}
# env_kwargs an evaluation cannot honour: what each must be, and why
UNRENDERED_KWARGS = {"render_mode": (None, "evaluation renders nothing; cof-gym watch renders an episode")}
# the env id's own arguments: a suite (and a training run) names the id (cof_gym.ENV_IDS) instead, so that what was
# played is what its outputs' env_id says
ID_KWARGS = ("vehicle", "task_version")
MAX_EPISODES = 100_000  # episodes per agent (--episodes and a file's episode list): hours of simulation


def scenario_option(text: str) -> tuple[str, object]:
    """An argparse type: ``NAME=VALUE`` (:func:`~cof_gym.commands.args.name_value`) with NAME a scenario field a
    suite may fix and VALUE one the env accepts for it (:func:`~cof_gym.task.scenarios.check_fixed`), as
    (name, value): a reset option for every episode, checked before any simulation."""
    name, value = name_value(text)
    if value is None:  # check_fixed reads None as "drawn"
        raise argparse.ArgumentTypeError(f"{text!r}: {name} needs a value, not null")
    try:
        check_fixed({name: value})
    except ValueError as error:
        raise argparse.ArgumentTypeError(f"{text!r}: {error}") from None
    return name, value


class SeededEpisodes(Sequence):
    """``count`` episodes with seeds ``seed``, ``seed + 1``, ... and the reset options ``options(i)``
    of episode i, made when read (a long suite is streamed, never built as a list)."""

    def __init__(self, seed: int, count: int, options: Callable[[int], dict[str, Any]] = lambda i: {}) -> None:
        self.seed, self.count, self.options = seed, count, options

    def __len__(self) -> int:
        return self.count

    def __getitem__(self, i):  # noqa: ANN001 - Sequence protocol (int or slice)
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(self.count))]
        if not -self.count <= i < self.count:
            raise IndexError(f"episode {i} of {self.count}")
        i %= self.count
        return self.seed + i, self.options(i)

    def __iter__(self) -> Iterator[tuple[int, dict[str, Any]]]:
        return (self[i] for i in range(self.count))


class SuiteError(ValueError):
    """A suite name that does not exist, or a suite file that cannot be read or does not fit the schema."""


@dataclass(frozen=True)
class Suite:
    """An env id with kwargs and a list of episodes: (reset seed, reset options). The same list is
    played by every agent, so every agent meets the same scenarios (CoF, condition, speed, load,
    noise, motor lag) and the same sensor-noise streams."""

    name: str
    env_id: str
    env_kwargs: dict[str, Any]
    episodes: Sequence[tuple[int, dict[str, Any]]] = field(default_factory=list)
    episode_notes: tuple[str, ...] = ()  # a label per episode (a suite file's "note"; "" where none), or none

    def note(self, i: int) -> str:
        """Episode ``i``'s label ("" where the suite gives none)."""
        return self.episode_notes[i] if self.episode_notes else ""


def default_suite(n_episodes: int, seed: int) -> Suite:
    """The wagon env's default scenario distribution (CoF in each condition's range, all conditions,
    5-40 m/s, empty and laden, noise and motor lag drawn), ``n_episodes`` seeded draws."""
    return Suite("default", cof_gym.WAGON_ENV_ID, {}, SeededEpisodes(seed, n_episodes))


def paper_suite(n_episodes: int, seed: int) -> Suite:
    """The paper's setting: laden wagon with the opposite torque on the bogie, dry, 10 m/s, no noise
    or lag, CoF 0.1...0.5 (cycled over ``n_episodes``)."""
    # the paper's simulation: Polach's dry curve, ideal sensors (no noise, no systematic error)
    fixed = {"condition": "dry", "speed_m_s": PAPER_SPEED_M_S, "load_case": "laden", "noise_level": 0.0, "motor_lag_s": 0.0,
             "creep_law": "dry", **{name: 0.0 for name in SYSTEMATIC_ERRORS}}
    episodes = SeededEpisodes(seed, n_episodes, lambda i: {**fixed, "cof": PAPER_COFS[i % len(PAPER_COFS)]})
    return Suite("paper", cof_gym.WAGON_ENV_ID, {"counter_torque": True}, episodes)


def in_service_suite(n_episodes: int, seed: int) -> Suite:
    """The default suite's seeds on task v3 (``CofGym/TorqueInterrogationInService-v3``): v2's draws, and a train's
    speed probe (pulses, runout, lag) on a track of drawn irregularity."""
    return Suite("in-service", cof_gym.WAGON_IN_SERVICE_ENV_ID, {}, SeededEpisodes(seed, n_episodes))


# the suites played by name (cof-gym evaluate --suite NAME): one table
NAMED_SUITES: dict[str, Callable[[int, int], Suite]] = {"default": default_suite, "paper": paper_suite,
                                                        "in-service": in_service_suite}
SUITE_NAMES = tuple(NAMED_SUITES)


def _check_dict(value: Any, where: str, path: Path) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise SuiteError(f"{path}: {where} must be a JSON object, got {type(value).__name__}")
    return dict(value)


def _check_seed(value: Any, where: str, path: Path) -> int:
    if not is_int(value) or not 0 <= value <= MAX_SEED:
        raise SuiteError(f"{path}: {where} must be an integer >= 0, got {value!r}")
    return int(value)


def with_env_kwargs(suite: Suite, overrides: dict[str, Any], shown: dict[str, Any] | None = None) -> Suite:
    """``suite`` with the env constructor arguments ``overrides`` over its own (``cof-gym evaluate --env-kwargs``), its
    name saying so (``shown``'s names and values where given: ``--creep-table``'s file for its table);
    :class:`SuiteError` where one would change the agents' interface or cut episodes short (as a suite file's
    ``env_kwargs``)."""
    env_kwargs = {**suite.env_kwargs, **overrides}
    _check_interface(suite.env_id, env_kwargs, "")
    shown = " ".join(f"{k}={json.dumps(v)}" for k, v in (overrides if shown is None else shown).items())
    return replace(suite, name=f"{suite.name} (env {shown})", env_kwargs=env_kwargs)


def with_env_id(suite: Suite, env_id: str) -> Suite:
    """``suite`` played on another registered id (``cof-gym evaluate --env``: e.g. a v2 grid on task v3), its env
    arguments and episodes kept, its name saying so; :class:`SuiteError` for an id cof_gym does not register or env
    arguments that id refuses by name (an argument it refuses by value is the env's error)."""
    if env_id not in cof_gym.ENV_IDS:
        raise SuiteError(f"{env_id!r} is no cof_gym env id; allowed: {', '.join(cof_gym.ENV_IDS)}")
    _check_interface(env_id, dict(suite.env_kwargs), "")
    return replace(suite, name=f"{suite.name} (on {env_id})", env_id=env_id)


def _check_interface(env_id: str, env_kwargs: dict[str, Any], where: Path | str) -> None:
    """env_kwargs that would change what the evaluated agents act through (:data:`INTERFACE_KWARGS`) or cut
    episodes short: the registered TimeLimit (``max_episode_steps``) must not end an episode before the task's
    horizon (``max_windows``) scores it; -1 (no TimeLimit) or a value at or beyond the horizon is harmless.
    ``where`` (a suite file's path) begins each message."""
    prefix = f"{where}: " if str(where) else ""
    for key, needed in INTERFACE_KWARGS.items():
        if key in env_kwargs and env_kwargs[key] != needed:
            raise SuiteError(f"{prefix}env_kwargs.{key} must be {needed!r} (the evaluated agents act through it), "
                             f"got {env_kwargs[key]!r}")
    for key, (needed, why) in UNRENDERED_KWARGS.items():
        if env_kwargs.get(key, needed) != needed:
            raise SuiteError(f"{prefix}env_kwargs.{key} must be {needed!r} ({why}), got {env_kwargs[key]!r}")
    check_env_kwargs(env_id, env_kwargs, prefix)


def allowed_env_kwargs(env_id: str) -> list[str]:
    """The env arguments a suite, ``--env-kwargs`` or training may set for ``env_id``: the constructor's (a scenario
    field fixes it in every episode that does not set it) and ``max_episode_steps``, not the id's own
    (:data:`ID_KWARGS`) nor ``ranges`` (a ScenarioRanges, which no file or command-line text writes)."""
    from cof_gym.agents.base import env_defaults
    from cof_gym.task.scenarios import SCENARIO_KEYS

    return sorted({*env_defaults(env_id), *SCENARIO_KEYS, "max_episode_steps"} - {*ID_KWARGS, "ranges"})


def check_env_kwargs(env_id: str, env_kwargs: dict[str, Any], prefix: str = "") -> None:
    """:class:`SuiteError` where ``env_kwargs`` set the id's own arguments (:data:`ID_KWARGS`), one the env does not
    take (:func:`allowed_env_kwargs`) or a TimeLimit that ends episodes unscored (:func:`check_time_limit`):
    evaluation and training alike."""
    import gymnasium as gym

    for key in ID_KWARGS:
        if key in env_kwargs:
            own = gym.spec(env_id).kwargs.get(key)
            raise SuiteError(f"{prefix}env_kwargs.{key} is the env id's own ({env_id} is made with {key}={own!r}): "
                             f"name the id instead, one of {list(cof_gym.ENV_IDS)}")
    allowed = allowed_env_kwargs(env_id)
    unknown = sorted(set(env_kwargs) - set(allowed))
    if unknown:
        raise SuiteError(f"{prefix}unknown env argument(s) {unknown}; allowed: {allowed}")
    check_time_limit(env_id, env_kwargs, prefix)


def check_time_limit(env_id: str, env_kwargs: dict[str, Any], prefix: str = "") -> None:
    """:class:`SuiteError` where ``env_kwargs`` would give ``env_id`` a TimeLimit (``max_episode_steps``) that is not
    -1 (none) or an integer at least the task's horizon (``max_windows``): a shorter one ends episodes before the task
    scores them (evaluation and training alike)."""
    import gymnasium as gym

    from cof_gym.envs.torque_interrogation import make_kwargs

    kwargs = make_kwargs(env_kwargs)
    spec = gym.spec(env_id)
    horizon = kwargs.get("max_windows", spec.kwargs.get("max_windows", cof_gym.MAX_EPISODE_STEPS))
    steps = kwargs.get("max_episode_steps", spec.max_episode_steps)
    if steps is None:  # gym.make applies the registered TimeLimit
        steps = spec.max_episode_steps
    if steps is None:  # an id without a TimeLimit
        return
    if not is_int(steps):
        raise SuiteError(f"{prefix}env_kwargs.max_episode_steps must be an integer (-1: no TimeLimit), got {steps!r}")
    if is_int(horizon) and steps != -1 and steps < horizon:
        raise SuiteError(f"{prefix}env_kwargs.max_episode_steps must be -1 (no TimeLimit) or at least the task's "
                         f"horizon max_windows={horizon} (a shorter TimeLimit ends every episode unscored), "
                         f"got {env_kwargs.get('max_episode_steps', steps)!r}")


def _check_options(options: dict[str, Any], where: str, path: Path) -> None:
    """Reset options checked by type and range (:func:`~cof_gym.task.scenarios.check_fixed`, the env's own check)
    before any env is built; what only an env can tell (e.g. a load case its vehicle lacks) is left to its reset
    (cof_gym.commands.evaluate.check_suite_runs)."""
    try:
        check_fixed(options)
    except (ValueError, TypeError, KeyError) as e:
        raise SuiteError(f"{path}: {where}: {e}") from None


MEASURED_CURVE_KEY = "creep_table"  # a suite file's option: a measured curve's CSV, relative to the file


def _measured_options(options: dict[str, Any], where: str, path: Path, read: dict[Path, dict]) -> dict[str, Any]:
    """``options`` with a ``creep_table`` (a CSV path relative to the suite file) made the table and CoF it measures
    (:func:`read_measured_curve`, each file read once through ``read``); a ``cof`` of the options' own scales the
    table instead. SuiteError where the options also give a ``creep_law`` or the file is not a measured curve."""
    if MEASURED_CURVE_KEY not in options:
        return options
    options = dict(options)
    name = options.pop(MEASURED_CURVE_KEY)
    if not isinstance(name, str) or not name:
        raise SuiteError(f"{path}: {where}: {MEASURED_CURVE_KEY} must be a CSV file's path, got {name!r:.60}")
    if "creep_law" in options:
        raise SuiteError(f"{path}: {where}: give {MEASURED_CURVE_KEY} or creep_law, not both: each is the creep curve")
    csv_path = path.parent / name
    if csv_path not in read:
        try:
            read[csv_path] = read_measured_curve(csv_path)
        except ValueError as e:
            raise SuiteError(f"{path}: {where}: {MEASURED_CURVE_KEY}: {e}") from None
    return {**read[csv_path], **options}


def file_suite(path: Path, n_episodes: int, seed: int) -> Suite:
    """A suite read from a JSON file (schema in the module docstring)."""
    path = Path(path)
    spec = _check_dict(_read_json(path), "the top level", path)
    unknown = sorted(set(spec) - set(FILE_KEYS))
    if unknown:
        raise SuiteError(f"{path}: unknown key(s) {unknown}; allowed: {list(FILE_KEYS)}")
    env_id = spec.get("env_id", cof_gym.WAGON_ENV_ID)
    if env_id not in cof_gym.ENV_IDS:
        raise SuiteError(f"{path}: env_id must be a cof_gym id, one of {list(cof_gym.ENV_IDS)}; got {env_id!r}")
    env_kwargs = _check_dict(spec.get("env_kwargs", {}), "env_kwargs", path)
    _check_interface(env_id, env_kwargs, path)
    options = _check_dict(spec.get("options", {}), "options", path)
    if "description" in spec and not isinstance(spec["description"], str):
        raise SuiteError(f"{path}: description must be a string")
    if "episodes" in spec:
        episodes, notes = _listed_episodes(spec["episodes"], options, seed, path)
        return Suite(str(path), env_id, env_kwargs, episodes, tuple(notes) if any(notes) else ())
    options = _measured_options(options, "options", path, {})
    _check_options(options, f"options {brief(options)}", path)
    return Suite(str(path), env_id, env_kwargs, SeededEpisodes(seed, n_episodes, lambda i: dict(options)))


class DuplicateKey(ValueError):
    """A JSON object that names a key twice (``json`` keeps the last silently)."""


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """``json``'s object hook: the object as a dict, :class:`DuplicateKey` where a key repeats."""
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise DuplicateKey(key)
        out[key] = value
    return out


def _read_json(path: Path) -> Any:
    """The suite file's JSON; :class:`SuiteError` (one line) where it cannot be read or parsed."""
    try:
        text = path.read_text(encoding="utf-8")
    except IsADirectoryError:
        raise SuiteError(f"{path} is a directory, not a suite file") from None
    except UnicodeDecodeError:
        raise SuiteError(f"{path}: not UTF-8 text") from None
    except OSError as e:
        raise SuiteError(f"{path}: cannot be read ({e.strerror})") from None
    try:
        return json.loads(text, object_pairs_hook=_unique_keys)
    except DuplicateKey as e:
        raise SuiteError(f"{path}: key {e.args[0]!r} given twice in one object; give each key once") from None
    except json.JSONDecodeError as e:
        raise SuiteError(f"{path}: invalid JSON at line {e.lineno} column {e.colno}: {e.msg}") from None
    except ValueError as e:  # e.g. an integer beyond Python's digit limit for str -> int
        raise SuiteError(f"{path}: cannot be read as JSON ({' '.join(str(e).split())})") from None
    except RecursionError:
        raise SuiteError(f"{path}: JSON nested too deeply") from None


def _listed_episodes(raw: Any, options: dict, seed: int, path: Path) -> tuple[list[tuple[int, dict]], list[str]]:
    """A file's ``episodes`` list: each episode's (seed, options over the file's ``options``) and its note, every
    distinct set of options checked once (:class:`SuiteError` naming the episode)."""
    if not isinstance(raw, list) or not raw or len(raw) > MAX_EPISODES:
        raise SuiteError(f"{path}: episodes must be a list of 1 to {MAX_EPISODES} objects like "
                         f'{{"seed": 1, "options": {{...}}}}, got {raw!r:.60}')
    episodes, notes, read = [], [], {}
    for i, e in enumerate(raw):
        e = _check_dict(e, f"episodes[{i}]", path)
        bad = sorted(set(e) - set(EPISODE_KEYS))
        if bad:
            raise SuiteError(f"{path}: episodes[{i}]: unknown key(s) {bad}; allowed: {list(EPISODE_KEYS)}")
        if "seed" not in e and seed + i > MAX_SEED:
            raise SuiteError(f"{path}: episodes[{i}] has no seed of its own, and the run's first seed {seed} + {i} "
                             f"is past the largest seed {MAX_SEED}; give a smaller --seed")
        ep_seed = _check_seed(e.get("seed", seed + i), f"episodes[{i}].seed", path)
        note = e.get("note", "")
        if not isinstance(note, str) or (note and not note.strip()) or any(c in note for c in TABLE_CELL_FORBIDDEN):
            raise SuiteError(f"{path}: episodes[{i}].note must be a string of one line without '|' (a row label "
                             f"of summary.md's tables), not blank, got {note!r:.60}")
        notes.append(note)
        merged = {**options, **_check_dict(e.get("options", {}), f"episodes[{i}].options", path)}
        episodes.append((ep_seed, _measured_options(merged, f"episodes[{i}]", path, read)))
    checked, played = set(), {}
    for i, (ep_seed, ep_options) in enumerate(episodes):
        key = json.dumps(ep_options, sort_keys=True, default=repr)
        if (ep_seed, key) in played:
            raise SuiteError(f"{path}: episodes[{i}] repeats episodes[{played[ep_seed, key]}] (the same seed and "
                             "options): the same episode would count twice")
        played[ep_seed, key] = i
        if key not in checked:
            checked.add(key)
            _check_options(ep_options, f"episode {i} (options {brief(ep_options)})", path)
    return episodes, notes


def read_measured_curve(path: Path) -> dict[str, Any]:
    """The reset options that play a measured creep curve: ``creep_law`` (its table) and ``cof`` (its peak), from a
    CSV file of (creepage, CoA) rows (:func:`cof_gym.physics.measured_curves.measured_table`: the points made into a
    table). The first two columns are read; a first row whose first two cells are neither a number is a header (one
    with a number in it is data, read as such or refused as a row), blank rows and rows
    starting with ``#`` are skipped. A header cell with ``%`` or ``percent`` in it says its column is in percent (a
    twin-disc report's "creepage [%]"); one with ``m/s`` in the creepage's is refused (a slip velocity needs the
    speed it was measured at: divide by it). The cells are separated as :func:`_delimiter` finds them: by commas, by
    semicolons or tabs (a spreadsheet's export where the comma is the decimal mark, ``0,002;0,15``: there a number may
    use either mark), or by spaces (decimal points). ValueError (one line, naming the file and the row) otherwise."""
    import csv

    from cof_gym.physics.measured_curves import measured_table

    try:
        raw = Path(path).read_bytes()
    except OSError as e:
        raise ValueError(f"{path} cannot be read as CSV ({' '.join(str(e).split())})") from None
    lines = _text_lines(raw)
    if lines is None:
        raise ValueError(f"{path} cannot be read as CSV (not a text file: NUL bytes, or UTF-16 that does not decode)")
    data = [(i + 1, line) for i, line in enumerate(lines) if line.strip() and not line.lstrip().startswith("#")]
    delimiter = _delimiter([line for _, line in data])
    try:
        cells = [line.split() if delimiter is None else next(csv.reader([line], delimiter=delimiter))
                 for _, line in data]
    except csv.Error as e:
        raise ValueError(f"{path} cannot be read as CSV ({' '.join(str(e).split())})") from None
    rows = [(line, row) for (line, _), row in zip(data, cells) if "".join(row).strip()]
    number = float if delimiter == "," else _decimal_comma_float
    points = []
    scales = (1.0, 1.0)
    for k, (line, row) in enumerate(rows):
        try:
            if len(row) < 2:
                raise ValueError
            points.append((number(row[0]) * scales[0], number(row[1]) * scales[1]))
        except ValueError:
            if k == 0 and not any(_is_number(cell, number) for cell in row[:2]):
                if delimiter is None and len(row) > 2 and any(unit in " ".join(row).lower() for unit in _UNITS):
                    raise ValueError(f"{path}: row {line}, a header of columns separated by spaces, names units "
                                     f"({brief(row)}) without saying of which column; separate the columns with "
                                     "commas, semicolons or tabs") from None
                scales = _header_scales(path, row)
                continue
            raise ValueError(f"{path}: row {line} is not a creepage and a CoA (two numbers), got {brief(row)}"
                             ) from None
    try:
        table, cof = measured_table([p[0] for p in points], [p[1] for p in points])
        check_number("the measured curve's CoF (its largest CoA after the fit)", cof, *COF_ENVELOPE)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    return {"creep_law": shape_spec(table), "cof": cof}


# what a header cell may say of its column (_header_scales): in percent; a slip velocity (refused)
PERCENT_MARKS, SLIP_VELOCITY_MARK = ("%", "percent"), "m/s"
_UNITS = (*PERCENT_MARKS, SLIP_VELOCITY_MARK)


def _text_lines(raw: bytes) -> list[str] | None:
    """A text file's lines: UTF-16 after its byte-order mark (a spreadsheet's "Unicode text"), UTF-8 (a byte-order
    mark dropped), else Latin-1 (a header's "µ" or "°" from an older export); None for bytes of no text (a NUL, or
    UTF-16 that does not decode)."""
    import codecs

    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return raw.decode("utf-16").splitlines()
        except UnicodeDecodeError:
            return None
    if b"\x00" in raw:
        return None
    try:
        return raw.decode("utf-8-sig").splitlines()
    except UnicodeDecodeError:
        return raw.decode("latin-1").splitlines()


def _delimiter(lines: list[str]) -> str | None:
    """What separates a measured curve's cells: of a semicolon, a tab and a comma, the one in the most ``lines``
    (a tie: the first of them, so ``0,002;0,15`` is split at its semicolons), or (None) runs of spaces where no line
    holds any of them."""
    counts = {d: sum(d in line for line in lines) for d in (";", "\t", ",")}
    delimiter = max(counts, key=counts.get)  # the first of the most frequent
    return delimiter if counts[delimiter] else None


def _decimal_comma_float(cell: str) -> float:
    """A number with a decimal point or a decimal comma (``0,002``); ValueError otherwise."""
    return float(cell.replace(",", ".", 1) if "." not in cell else cell)


def _is_number(cell: str, number=float) -> bool:
    try:
        number(cell)
    except ValueError:
        return False
    return True


def _header_scales(path: Path, header: list[str]) -> tuple[float, float]:
    """What the creepage and the CoA columns are multiplied by: 0.01 where the header says percent, else 1."""
    cells = [cell.lower() for cell in [*header, "", ""][:2]]
    if SLIP_VELOCITY_MARK in cells[0]:
        raise ValueError(f"{path}: the first column is a slip velocity ({header[0].strip()!r}); give the creepage, "
                         "the slip velocity over the speed it was measured at")
    return tuple(0.01 if any(mark in cell for mark in PERCENT_MARKS) else 1.0 for cell in cells)


def per_curve(suite: Suite, curves: Sequence[tuple[str, dict[str, Any]]]) -> Suite:
    """``suite`` played once per creep curve: every episode (its seed, so the other draws pair up across the curves)
    with each curve's reset options over its own (:func:`read_measured_curve`), labelled by the curve's name (and the
    episode's own note); :class:`SuiteError` where that makes more than :data:`MAX_EPISODES` episodes."""
    if len(curves) * len(suite.episodes) > MAX_EPISODES:
        raise SuiteError(f"{len(curves)} curves x {len(suite.episodes)} episodes is more than {MAX_EPISODES} episodes")
    episodes = [(seed, {**options, **curve}) for _, curve in curves for seed, options in suite.episodes]
    notes = [", ".join(filter(None, (name, suite.note(i)))) for name, _ in curves for i in range(len(suite.episodes))]
    return Suite(f"{suite.name} (creep curves {', '.join(name for name, _ in curves)})", suite.env_id,
                 dict(suite.env_kwargs), episodes, tuple(notes))


def make_suite(name: str, n_episodes: int, seed: int) -> Suite:
    """A name of :data:`NAMED_SUITES` or a JSON file path (:class:`SuiteError` otherwise); ``n_episodes`` seeded
    draws from ``seed`` on where the suite lists no episodes of its own (integers in [1, MAX_EPISODES] and [0,
    MAX_SEED])."""
    try:
        check_int("n_episodes", n_episodes, 1, MAX_EPISODES)
        check_int("seed", seed, 0, MAX_SEED)
    except ValueError as e:
        raise SuiteError(str(e)) from None
    if not isinstance(name, (str, Path)):
        raise SuiteError(f"suite must be one of {', '.join(SUITE_NAMES)} or a JSON file path, got {name!r}")
    name = str(name)
    if name in NAMED_SUITES:
        return NAMED_SUITES[name](n_episodes, seed)
    path = Path(name)
    if path.exists():
        return file_suite(path, n_episodes, seed)
    if path.suffix == ".json" or "/" in name or "\\" in name:
        raise SuiteError(f"no such suite file: {name}")
    raise SuiteError(f"unknown suite {name!r}; allowed: {', '.join(SUITE_NAMES)} or a JSON suite file")
