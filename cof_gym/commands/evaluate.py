"""``cof-gym evaluate``: agents side by side on the same seeded scenarios, with tables and figures."""

from __future__ import annotations

import argparse
import csv
import itertools
import json
import math
import os
import re
import shutil
import sys
import time
from collections import Counter
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any, Callable, Mapping


from cof_gym.agents import registry
from cof_gym.agents.base import own_env_options
from cof_gym.commands.evaluate_episodes import STEP_FIELDS, AgentError, EpisodeRecord, run_episode
from cof_gym.commands.evaluate_stats import COF_BANDS, paired_summary, summarize
from cof_gym.commands.evaluate_tables import (markdown_breakdown, markdown_intervals, markdown_paired, markdown_table,
                                              print_paired, print_table)
from cof_gym.commands.evaluate_workers import (EPISODES_PER_WORKER, MAX_WORKERS, WORKER_MEMORY_BYTES, default_workers,
                                               oversubscription_note)
from cof_gym.commands.suites import (MAX_EPISODES, Suite, SuiteError, make_suite, per_curve,
                                     read_measured_curve, with_env_id, with_env_kwargs)
from cof_gym.envs.torque_interrogation import make_kwargs
from cof_gym.validation import brief, check_int

DESCRIPTION = """\
Play every agent on the same seeded scenarios (same CoF, condition, speed, load, noise streams) and
write OUT/episodes.csv, OUT/summary.md, OUT/summary.json (median and P90 relative CoF error,
macro-slips, slip energy, Wd comfort, measurement time and peak torque as a fraction of the real
saturation torque, and the median and P90 error with a macro-slip counted as a failed measurement (100 %),
each with a bootstrap 95 % CI, and a breakdown by condition, CoF band, creep-law
family, the creep curve's peak creepage, systematic creepage-error band, the utilisation at which
the estimate was committed and how the episode ended: the agent's stop, the horizon (the last of the
task's steps), a macro-slip), the coverage of the interval an agent reports around its estimate (the learned
interrogator's), and figures; with --windows also OUT/windows.csv, every episode step by step. --env-kwargs
plays the suite with other env arguments (e.g. max_windows:60, a longer horizon). The outputs appear all at once
when the run completes (an interrupted run leaves the previous OUT as it was). Only agents marked as oracles see
info["ground_truth"]."""

DEFAULT_OUT = Path("out") / "evaluate"
OUTPUT_MARKER = "summary.json"  # what makes an existing --out directory a previous evaluate output
# windows.csv's columns (--windows): the episode's agent, index and seed, the step (1: the first action's), then what
# the step read and scored (evaluate_episodes.STEP_FIELDS)
WINDOW_COLUMNS = ("agent", "episode", "seed", "step", *STEP_FIELDS)
QUEUED_PER_WORKER = 4  # episodes handed to the workers at a time, per worker (however long the suite)


def default_out(suite: str, env_overrides: Mapping[str, Any] | None = None) -> Path:
    """``out/evaluate`` for the default suite, ``out/evaluate-<suite>`` for any other, each followed by
    ``-NAME=VALUE`` per env argument given over the suite's (so that runs on different suites or envs never
    overwrite each other)."""
    name = "evaluate" if suite == "default" else f"evaluate-{Path(suite).stem if suite.endswith('.json') else suite}"
    for key, value in (env_overrides or {}).items():
        name += "-" + re.sub(r"[^A-Za-z0-9_.=+-]", "_", f"{key}={json.dumps(value)}")
    return DEFAULT_OUT.with_name(name)


# ---------------------------------------------------------------------------- output directory
class _Staging:
    """Outputs are written into a hidden sibling directory and renamed onto ``out`` when complete; on
    failure or interruption the staging directory (and any parent this run created) is removed."""

    def __init__(self, out: Path) -> None:
        self.out = Path(out)
        self.created: list[Path] = []
        parent = self.out.resolve().parent
        missing = []
        while not parent.exists():
            missing.append(parent)
            parent = parent.parent
        for d in reversed(missing):
            d.mkdir()
            self.created.append(d)
        self.path = self.out.parent / f".{self.out.name}.partial-{os.getpid()}"
        if self.path.exists():
            shutil.rmtree(self.path)
        self.path.mkdir()

    def commit(self) -> None:
        old = None
        if self.out.exists():
            old = self.out.parent / f".{self.out.name}.old-{os.getpid()}"
            os.replace(self.out, old)
        os.replace(self.path, self.out)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
        self.created = []

    def abort(self) -> None:
        shutil.rmtree(self.path, ignore_errors=True)
        for d in reversed(self.created):
            try:
                d.rmdir()
            except OSError:
                pass


def check_out(out: Path) -> Path:
    """``--out``: creatable, and if it exists, empty or a previous ``cof-gym evaluate`` output."""
    from cof_gym.commands.args import check_command_output

    return check_command_output(Path(out), OUTPUT_MARKER, "cof-gym evaluate")


# ---------------------------------------------------------------------------- the run
def _progress(quiet: bool):
    """A rich progress bar on stderr when it is a terminal; a plain line every few seconds otherwise
    (:class:`cof_gym.commands.terminal.PlainProgress`); nothing if quiet."""
    from cof_gym.commands import terminal

    if quiet:
        return None
    if sys.stderr.isatty():
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

        return Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                        TextColumn("episodes"), TimeElapsedColumn(), console=terminal.console(sys.stderr),
                        transient=False)
    return terminal.PlainProgress(sys.stderr)


def build_agents(agent_specs: list[str], env) -> list[tuple[Any, bool]]:
    """Every agent, built before the first episode: ``(agent, oracle)`` pairs. Raises
    :class:`~cof_gym.agents.registry.AgentSpecError` for an unknown name or a model that cannot be used."""
    if not agent_specs:
        raise registry.AgentSpecError(f"no agent given; allowed: {registry.describe()}")
    registry.check_distinct(agent_specs)
    built, names = [], set()
    for spec in agent_specs:
        entry, _ = registry.parse(spec)
        try:
            agent = registry.make_agent(spec, env)
        except (FileNotFoundError, ValueError, OSError) as e:
            raise registry.AgentSpecError(f"{spec}: {e}") from e
        if agent.name in names:
            raise registry.AgentSpecError(f"agent {agent.name!r} given twice")
        names.add(agent.name)
        built.append((agent, entry.oracle))
    return built


def check_request(agent_specs: list[str], suite: Suite, out: Path, seed: int, paired: str | None) -> None:
    """:func:`evaluate`'s arguments, before anything is built or played (``ValueError`` naming the argument): a list
    of agent names, a suite with episodes, an ``out`` that is new, empty or an earlier evaluate output (nothing else
    is replaced), a seed for the bootstraps, ``paired`` one of the agents beside another."""
    from cof_gym.commands.args import MAX_SEED, UsageError, check_command_output

    if isinstance(agent_specs, str) or not all(isinstance(spec, str) for spec in agent_specs):
        raise ValueError(f"agent_specs must be a list of agent names (str), got {agent_specs!r}")
    if not suite.episodes:
        raise ValueError(f"suite {suite.name} has no episodes to play")
    check_int("seed", seed, 0, MAX_SEED)
    if paired is not None and (paired not in agent_specs or len(agent_specs) < 2):
        raise ValueError(f"paired: {paired!r} must be one of the agents {agent_specs}, beside at least one other")
    try:
        check_command_output(Path(out), OUTPUT_MARKER, "cof-gym evaluate", flag="out")
    except UsageError as e:
        raise ValueError(str(e)) from None


def evaluate(agent_specs: list[str], suite: Suite, out: Path, seed: int, quiet: bool = False,
             check_suite: bool = False, workers: int | None = 1, paired: str | None = None,
             windows: bool = False) -> dict[str, Any]:
    """Play ``agent_specs`` on ``suite``; write the outputs to ``out`` (atomically); return the results.

    Before the first episode every agent is built (:class:`~cof_gym.agents.registry.AgentSpecError`)
    and, with ``check_suite``, the env kwargs and every distinct reset option set of the suite are tried
    (:class:`~cof_gym.commands.suites.SuiteError`). ``workers``: processes that play the episodes (None:
    :func:`default_workers`); every episode is seeded on its own, so the outputs are the same for any number. The
    workers are spawned: a script that asks for more than one needs the usual ``if __name__ == "__main__":`` guard.
    ``paired``: one of ``agent_specs``, every other agent compared with it over the same episodes
    (:func:`~cof_gym.commands.evaluate_stats.paired_summary`: in summary.md, summary.json and on the terminal).
    ``windows``: also write ``windows.csv``, every episode's steps, a row each (:data:`WINDOW_COLUMNS`)."""
    check_request(agent_specs, suite, out, seed, paired)
    t0 = time.perf_counter()
    env = suite_env(suite, check_suite)
    agents: list[tuple[Any, bool]] = []
    envs: dict[str, Any] = {}
    try:
        agents = build_agents(agent_specs, env)
        envs = agent_envs(agents, suite, env)
        staging = _Staging(out)
        try:
            n_workers = default_workers(len(agents) * len(suite.episodes)) if workers is None else workers
            baseline = agents[agent_specs.index(paired)][0].name if paired is not None else None
            result = _play_and_write(envs, agents, agent_specs, suite, staging.path, seed, quiet, t0, n_workers,
                                     baseline, windows)
            staging.commit()
        except BaseException:
            staging.abort()
            raise
    finally:
        env.close()
        _close_own_envs(envs, env)
        close_error = _close_agents(agents)
    if close_error is not None:  # the outputs are written: the agent's error is still the user's to see
        raise close_error
    if not quiet:
        print_table(result["summary"], f"cof-gym evaluate: suite {suite.name} ({len(suite.episodes)} episodes per "
                                       f"agent), seed {seed}, {suite.env_id}")
        if "paired" in result:
            print_paired(result["paired"])
        for note in result["notes"]:
            print(f"note: {note}")
        written = "episodes.csv, windows.csv" if windows else "episodes.csv"
        print(f"{written}, summary.md/json and figures in {out} ({result['wall_time_s']:.1f} s)")
    return result


def _close_agents(agents) -> AgentError | None:
    """Close every agent that has ``close()``; the first one that raised, as an :class:`AgentError` (None if none)."""
    error = None
    for agent, _ in agents:
        close = getattr(agent, "close", None)
        try:
            if callable(close):
                close()
        except Exception as e:  # noqa: BLE001 - whatever an agent (one of your own too) raises
            error = error or AgentError(f"agent {agent.name} raised in close() after the run: {type(e).__name__}: "
                                        f"{' '.join(str(e).split())}")
    return error


def _close_own_envs(envs: dict[str, Any], shared_env) -> None:
    """Close the envs of :func:`agent_envs` that agents have of their own (not ``shared_env``, the suite's)."""
    for env in envs.values():
        if env is not shared_env:
            env.close()


def agent_envs(agents, suite: Suite, shared_env) -> dict[str, Any]:
    """The env each agent plays in, by name: ``shared_env`` (the suite's), or an env of its own for an agent whose
    excitation needs env options beyond the suite's (``agent.env_options``, e.g. the two-tone interrogator's
    ``excitation="multitone"``): the suite's env id and kwargs with those options; the same seeds draw the same
    scenarios and ground truth, and only the drive and the measurement of the windows change."""
    import gymnasium as gym

    envs = {}
    for agent, _ in agents:
        options = own_env_options(agent)
        try:
            envs[agent.name] = gym.make(suite.env_id, **{**make_kwargs(suite.env_kwargs), **options}) if options \
                else shared_env
        except (ValueError, TypeError) as e:
            _close_own_envs(envs, shared_env)
            raise registry.AgentSpecError(f"agent {agent.name}: its env_options {options!r} make no env of "
                                          f"{suite.env_id}: {' '.join(str(e).split())}") from None
    return envs


def distribution_notes(agents, suite: Suite) -> list[str]:
    """One line per agent that says the suite lies outside what it was trained on (learned agents)."""
    notes = []
    for agent, _ in agents:
        note = getattr(agent, "distribution_note", None)
        line = note(suite.env_id, dict(suite.env_kwargs), [o for _, o in suite.episodes]) if callable(note) else None
        if line:
            notes.append(line)
    return notes


def sensor_notes(records) -> list[str]:
    """One line per agent and label of its episodes' ``sensor_notes`` (what its own readings said lay outside the
    sensors it was fitted on), with the episodes that read it, in the agents' order."""
    counts: dict[str, Counter] = {}
    totals: Counter = Counter()
    for r in records:
        totals[r.agent] += 1
        counts.setdefault(r.agent, Counter()).update(n for n in r.sensor_notes.split("; ") if n)
    return [f"{agent} read its sensors outside those it was fitted on ({label}) in {n} of {totals[agent]} episodes: "
            "its estimate there is an extrapolation" for agent, labels in counts.items() for label, n in labels.items()]


def _play_episode(envs: dict[str, Any], agents, suite: Suite, k: int, i: int,
                  windows: bool = False) -> tuple[EpisodeRecord, list | None, list | None]:
    """Agent ``k`` on the suite's episode ``i``: its record, its trace if it is the agent's first (the figures'),
    its steps with ``windows`` (windows.csv's rows)."""
    agent, oracle = agents[k]
    ep_seed, options = suite.episodes[i]
    trace = [] if i == 0 else None
    steps = [] if windows else None
    record = run_episode(envs[agent.name], agent, ep_seed, options, i, trace, oracle=oracle, note=suite.note(i),
                         steps_out=steps)
    return record, trace, steps


_WORKER: dict[str, Any] = {}  # a worker process's envs, agents and suite (:func:`_start_worker`)


def _start_worker(agent_specs: list[str], suite: Suite, warning_filters: list, windows: bool = False) -> None:
    """A worker's own env and agents, built as the parent built them, with the parent's warning filters (one
    torch thread: the cores are the workers')."""
    import warnings

    import gymnasium as gym
    import torch

    warnings.filters[:] = warning_filters
    torch.set_num_threads(1)
    env = gym.make(suite.env_id, **make_kwargs(suite.env_kwargs))
    agents = build_agents(agent_specs, env)
    _WORKER.update(envs=agent_envs(agents, suite, env), agents=agents, suite=suite, windows=windows)


def _worker_episode(task: tuple[int, int]) -> tuple[int, int, EpisodeRecord, list | None, list | None]:
    k, i = task
    return (k, i, *_play_episode(_WORKER["envs"], _WORKER["agents"], _WORKER["suite"], k, i, _WORKER["windows"]))


def _play(envs: dict[str, Any], agents, agent_specs, suite: Suite, workers: int, advance,
          windows: bool = False) -> list[tuple]:
    """``(k, i, record, trace, steps)`` of every agent ``k`` and episode ``i`` (:func:`_play_episode`), in that
    order: played here in that order (``workers`` 1), or by ``workers`` spawned processes, an episode a task.
    ``advance(k)`` after each."""
    tasks = [(k, i) for k in range(len(agents)) for i in range(len(suite.episodes))]
    workers = min(workers, len(tasks))
    played = _play_in_workers(agent_specs, suite, tasks, workers, advance, windows) if workers > 1 else None
    if played is not None:
        return played
    played = []
    for k, i in tasks:
        played.append((k, i, *_play_episode(envs, agents, suite, k, i, windows)))
        advance(k)
    return played


def _play_in_workers(agent_specs, suite: Suite, tasks: list[tuple[int, int]], workers: int, advance,
                     windows: bool = False) -> list | None:
    """:func:`_play`'s tasks in ``workers`` spawned processes, a few handed to each at a time; None where no
    worker process can start here (no process-shared semaphores, e.g. no /dev/shm: one note on stderr)."""
    import multiprocessing
    import warnings
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    portable = replace(suite, env_kwargs=dict(suite.env_kwargs), episodes=list(suite.episodes))  # what pickles
    try:
        pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"), initializer=_start_worker,
                                   initargs=(list(agent_specs), portable, list(warnings.filters), windows))
    except (OSError, NotImplementedError, ImportError) as e:
        print(f"note: no worker processes here ({e}); the episodes are played in this process", file=sys.stderr)
        return None
    done, pending, queue = {}, set(), iter(tasks)
    with pool:
        try:
            while True:
                room = QUEUED_PER_WORKER * workers - len(pending)
                pending |= {pool.submit(_worker_episode, task) for task in itertools.islice(queue, room)}
                if not pending:
                    break
                finished, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in finished:
                    outcome = future.result()  # (k, i, record, trace, steps)
                    done[outcome[:2]] = outcome
                    advance(outcome[0])
        except BaseException:
            for future in pending:
                future.cancel()
            raise
    return [done[task] for task in tasks]


def _intervals_section(summary: dict[str, Any]) -> str:
    """summary.md's section on the intervals the agents reported around their estimates ("" where none did)."""
    table = markdown_intervals(summary)
    return f"## The intervals the agents reported around their estimates\n\n{table}\n\n" if table else ""


def _paired_section(paired: dict[str, Any] | None) -> str:
    """summary.md's section comparing every agent with the baseline ("" where none was asked for)."""
    return f"## Paired against {paired['baseline']}\n\n{markdown_paired(paired)}\n\n" if paired else ""


def _write_windows(played: list[tuple], path: Path) -> None:
    """``windows.csv``: every played episode's steps, a row each, in the episodes' order."""
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=WINDOW_COLUMNS)
        writer.writeheader()
        for _, _, record, _, steps in played:
            writer.writerows({"agent": record.agent, "episode": record.episode, "seed": record.seed, "step": step,
                              **row} for step, row in enumerate(steps, start=1))


def _play_and_write(envs: dict[str, Any], agents, agent_specs, suite: Suite, out: Path, seed: int, quiet: bool,
                    t0: float, workers: int = 1, baseline: str | None = None,
                    windows: bool = False) -> dict[str, Any]:
    progress = _progress(quiet)
    if progress is not None:
        progress.start()
    try:
        bars = [progress.add_task(agent.name, total=len(suite.episodes)) for agent, _ in agents] \
            if progress is not None else []
        played = _play(envs, agents, agent_specs, suite, workers,
                       lambda k: progress.advance(bars[k]) if progress is not None else None, windows)
    finally:
        if progress is not None:
            progress.stop()
    records = [record for _, _, record, _, _ in played]
    traces = {agents[k][0].name: trace for k, i, _, trace, _ in played if i == 0}
    summary = summarize(records, seed)
    paired = paired_summary(records, baseline, seed) if baseline is not None else None
    notes = distribution_notes(agents, suite) + sensor_notes(records)
    with open(out / "episodes.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(asdict(records[0])))
        writer.writeheader()
        writer.writerows(asdict(r) for r in records)
    if windows:
        _write_windows(played, out / "windows.csv")
    (out / "summary.md").write_text(
        f"# cof-gym evaluate: suite {suite.name}, seed {seed}, {suite.env_id}\n\n"
        + "".join(f"Note: {n}.\n\n" for n in notes) + f"{markdown_table(summary)}\n\n" + _paired_section(paired)
        + _intervals_section(summary)
        + "## By condition, CoF band, creep-law family, peak creepage, creepage-error band, utilisation, ending and "
        f"note\n\n{markdown_breakdown(summary)}\n")
    from cof_gym.commands.evaluate_figures import plot_all

    figures = [Path(p).name for p in plot_all(records, summary, traces, out)]
    result = {"suite": suite.name, "env_id": suite.env_id, "env_kwargs": suite.env_kwargs, "seed": seed,
              "agents": list(agent_specs), "summary": summary, "traces": traces, "figures": figures, "notes": notes,
              "cof_bands": [b for b in COF_BANDS if math.isfinite(b)], **({"paired": paired} if paired else {})}
    # written last: its presence marks a complete output directory
    (out / OUTPUT_MARKER).write_text(json.dumps(result, indent=1))
    result["wall_time_s"] = time.perf_counter() - t0
    return result


# ---------------------------------------------------------------------------- command line
def add_arguments(parser: argparse.ArgumentParser) -> None:
    from cof_gym.commands.args import MAX_SEED, StoreDict, int_in_range, seed_int

    parser.add_argument("--agents", nargs="+", default=None, metavar="A,B",
                        help=f"agents, comma- or space-separated: {registry.describe()} (default: "
                             f"{','.join(registry.default_agents())}{registry.default_on_text()})")
    parser.add_argument("--episodes", type=int_in_range(1, MAX_EPISODES), default=60,
                        help=f"episodes per agent, at most {MAX_EPISODES} (a suite file with an episode list sets "
                             "its own)")
    parser.add_argument("--suite", default="default", metavar="SUITE",
                        help="scenarios: 'default' (the env's distribution), 'paper' (the paper's setting), "
                             "'in-service' (the default seeds on task v3: a train's speed probe and track drawn too) "
                             "or a JSON suite file (see cof_gym/commands/suites.py)")
    parser.add_argument("--env", default=None, metavar="ENV_ID",
                        help="play the suite on this registered id instead of its own, its env arguments and "
                             "episodes kept (e.g. a v2 grid on task v3, CofGym/TorqueInterrogationInService-v3)")
    parser.add_argument("--env-kwargs", nargs="+", action=StoreDict, default={}, metavar="KEY:VALUE",
                        help="env constructor arguments over the suite's (a Python literal or text, as cof-gym train "
                             "and RL Zoo take them), e.g. max_windows:60 (a longer horizon) or counter_torque:True; "
                             "not the agents' interface (action_type, excitation, info_layout)")
    parser.add_argument("--creep-table", nargs="+", default=None, metavar="CSV",
                        help="a measured creep curve, rows of creepage and CoA (a twin disc, a test run; separated "
                             "by commas, semicolons, tabs or spaces, a decimal comma where semicolons or tabs "
                             "separate), played in "
                             "every episode at its own CoF (its points made into a table: "
                             "cof_gym/physics/measured_curves.py); the other scenario fields as the suite draws them. "
                             "Several files: the suite's episodes played once per curve with the same seeds, each "
                             "episode noted by its file's name (the breakdown's 'note' rows)")
    parser.add_argument("--paired", default=None, metavar="AGENT",
                        help="one of --agents: every other agent against it over the same episodes, the difference "
                             "of the median and P90 error and of the mean return and the share of episodes with the "
                             "lower error (the probability of improvement), each with a paired bootstrap 95 %% CI, "
                             "and both agents' macro-slips (summary.md, summary.json and the terminal)")
    parser.add_argument("--seed", type=seed_int, default=0,
                        help=f"seed of the first episode (episode i uses seed + i) and of the bootstrap CIs; the "
                             f"last episode's at most {MAX_SEED}")
    parser.add_argument("--out", default=None, metavar="DIR",
                        help="output directory, replaced when the run completes (default: out/evaluate, or "
                             "out/evaluate-SUITE for another suite)")
    parser.add_argument("--workers", type=int_in_range(1, MAX_WORKERS), default=None, metavar="N",
                        help=f"processes that play the episodes, at most {MAX_WORKERS} (default: one a usable core, "
                             f"each with at least {EPISODES_PER_WORKER} episodes and {WORKER_MEMORY_BYTES >> 30} GiB "
                             "of the available memory); the outputs are the same for any N")
    parser.add_argument("--windows", action="store_true",
                        help="also write OUT/windows.csv: every episode's steps, a row each (agent, episode, seed, "
                             "step; the env's elapsed time, the measured DC torque, speed and wheel speed, CoA and "
                             "phase lag, the agent's estimate and the true CoF; whether the step drove a window, the "
                             "measured modulation amplitude, the lag's SE and the creepage, the reward and its terms, "
                             "the true CoA and torque over the saturation torque, the agent's in-flight lower bound)")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress and no table on the terminal")


def prepare(args: argparse.Namespace) -> tuple[list[str], Suite, Path]:
    """Check the whole command line before anything runs or is written (UsageError naming the flag)."""
    from cof_gym.commands.args import MAX_SEED, UsageError

    given = None if args.agents is None else ",".join(args.agents)  # --agents a,b and --agents a b alike
    try:
        suite = make_suite(args.suite, args.episodes, args.seed)
    except SuiteError as e:
        raise UsageError("--suite", str(e)) from None
    if args.env is not None:
        suite = _on_env(suite, args.env)
    # without --agents: the default list of the id the suite is played on (cof_gym.agents.registry.default_agents)
    specs = [s.strip() for s in given.split(",")] if given is not None else registry.default_agents(suite.env_id)
    if not specs or any(not s for s in specs):
        raise UsageError("--agents", f"empty agent name in {given!r}; allowed: {registry.describe()}")
    for spec in specs:
        try:
            entry, argument = registry.parse(spec)
        except registry.AgentSpecError as e:
            raise UsageError("--agents", str(e)) from None
        try:
            registry.check_argument(entry, argument)
        except ValueError as e:
            raise UsageError("--agents", f"{spec}: {e}") from None
    try:
        registry.check_distinct(specs)  # one name twice, or two names of one agent
    except registry.AgentSpecError as e:
        raise UsageError("--agents", str(e)) from None
    if args.paired is not None and args.paired not in specs:
        raise UsageError("--paired", f"{args.paired!r} is none of the agents played: {', '.join(specs)}")
    if args.paired is not None and len(specs) < 2:
        raise UsageError("--paired", f"compares every other agent with {args.paired!r}, and --agents plays no other; "
                                     "name at least one more")
    env_overrides = dict(args.env_kwargs)
    named = dict(env_overrides)  # what names the suite and the default output directory
    curves = [(Path(p).stem, _measured_curve(Path(p), env_overrides, suite)) for p in args.creep_table or ()]
    if len(curves) == 1:  # one curve: env arguments, fixed in every episode
        env_overrides.update(curves[0][1])
        named.update(creep_table=curves[0][0], cof=round(curves[0][1]["cof"], 5))
    elif curves:
        suite = _per_curve(suite, curves, args.creep_table)
    if env_overrides:
        suite = _with_env(suite, env_overrides, named)
    if len(curves) > 1:  # the suite's name says them already; the default output directory too
        named.update(creep_tables="+".join(name for name, _ in curves))
    last_seed = max(seed for seed, _ in suite.episodes)
    if last_seed > MAX_SEED:  # seeded episodes: seed + i
        raise UsageError("--seed", f"the last episode's seed {last_seed} is beyond {MAX_SEED}; give at most "
                                   f"{MAX_SEED - len(suite.episodes) + 1} for {len(suite.episodes)} episodes")
    on_env = {} if args.env is None else {"env": args.env}
    out = check_out(Path(args.out) if args.out is not None else default_out(args.suite, {**on_env, **named}))
    return specs, suite, out


def _measured_curve(path: Path, env_overrides: Mapping[str, Any], suite: Suite) -> dict[str, Any]:
    """``--creep-table``'s reset options (:func:`~cof_gym.commands.suites.read_measured_curve`; UsageError naming the
    flag, also where ``--env-kwargs`` or an episode of the suite fixes the same fields, which would play another
    curve there)."""
    from cof_gym.commands.args import UsageError

    try:
        curve = read_measured_curve(path)
    except ValueError as e:
        raise UsageError("--creep-table", str(e)) from None
    clash = sorted(set(curve) & set(env_overrides))
    if clash:
        raise UsageError("--creep-table", f"it fixes {clash}, which --env-kwargs fixes too; give one of them")
    for i, (_, options) in enumerate(suite.episodes):
        if clash := sorted(set(curve) & set(options)):
            raise UsageError("--creep-table", f"it fixes {clash}, which episode {i} of suite {suite.name} fixes too; "
                                              "play it on a suite that leaves them to the draws")
    return curve


def _per_curve(suite: Suite, curves: list[tuple[str, dict[str, Any]]], files: list[str]) -> Suite:
    """Several ``--creep-table`` curves: the suite played once per curve (:func:`~cof_gym.commands.suites.per_curve`;
    UsageError naming the flag, also where two files have one name, by which the episodes are noted)."""
    from cof_gym.commands.args import UsageError

    if len({name for name, _ in curves}) != len(curves):
        raise UsageError("--creep-table", f"two files have one name in {files}: each curve is known by its file's "
                                          "name (stem); rename one")
    try:
        return per_curve(suite, curves)
    except SuiteError as e:
        raise UsageError("--creep-table", str(e)) from None


def _with_env(suite: Suite, overrides: dict[str, Any], shown: dict[str, Any] | None = None) -> Suite:
    """``--env-kwargs`` (and ``--creep-table``'s options): the suite with these env arguments, named by ``shown``, the
    env built once with them (UsageError naming the flag)."""
    return _env_built("--env-kwargs", lambda: with_env_kwargs(suite, overrides, shown))


def _on_env(suite: Suite, env_id: str) -> Suite:
    """``--env``: the suite on that id, its env built once with the suite's arguments (UsageError naming the flag)."""
    return _env_built("--env", lambda: with_env_id(suite, env_id))


def _env_built(flag: str, changed: Callable[[], Suite]) -> Suite:
    """The suite ``changed()`` returns, its env built once with its arguments; a :class:`SuiteError`, ``ValueError`` or
    ``TypeError`` of either is a UsageError naming ``flag``."""
    import gymnasium as gym

    from cof_gym.commands.args import UsageError

    try:
        suite = changed()
        gym.make(suite.env_id, **make_kwargs(suite.env_kwargs)).close()
    except (SuiteError, ValueError, TypeError) as e:
        raise UsageError(flag, str(e)) from None
    return suite


def suite_env(suite: Suite, check: bool = True, first_episode: int = 0):
    """The suite's env, made with its env arguments; with ``check``, a :class:`SuiteError` naming the suite where the
    env refuses them or any of the suite's reset option sets (:func:`check_suite_runs`; ``first_episode``: the index
    its messages give the suite's first episode), before any episode."""
    import gymnasium as gym

    try:
        env = gym.make(suite.env_id, **make_kwargs(suite.env_kwargs))
    except (ValueError, TypeError) as e:
        if not check:
            raise
        raise SuiteError(f"{suite.name}: env_kwargs {suite.env_kwargs}: {e}") from None
    if check:
        try:
            check_suite_runs(suite, env, first_episode)
        except SuiteError:
            env.close()
            raise
    return env


def check_suite_runs(suite: Suite, env, first_episode: int = 0) -> None:
    """Every distinct reset option set of the suite is accepted by the env (one reset each; the messages number the
    episodes from ``first_episode``)."""
    seen = set()
    for i, (ep_seed, options) in enumerate(suite.episodes, start=first_episode):
        key = json.dumps(options, sort_keys=True, default=repr)
        if key in seen:
            continue
        seen.add(key)
        try:
            env.reset(seed=ep_seed, options=options)
        except (ValueError, TypeError, KeyError) as e:
            raise SuiteError(f"{suite.name}: episode {i} (options {brief(options)}): {e}") from None


def run(args: argparse.Namespace) -> int:
    from cof_gym.commands.args import UsageError

    specs, suite, out = prepare(args)
    note = None if args.workers is None else oversubscription_note(args.workers, len(specs) * len(suite.episodes))
    if note:
        print(note, file=sys.stderr)
    try:
        evaluate(specs, suite, out, args.seed, quiet=args.quiet, check_suite=True, workers=args.workers,
                 paired=args.paired, windows=args.windows)
    except SuiteError as e:
        raise UsageError("--suite", str(e)) from None
    except (registry.AgentSpecError, AgentError) as e:
        raise UsageError("--agents", str(e)) from None
    return 0
