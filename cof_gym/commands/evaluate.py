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
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from cof_gym.agents import registry
from cof_gym.agents.base import agent_view, own_env_options
from cof_gym.commands.suites import MAX_EPISODES, Suite, SuiteError, make_suite, with_env_kwargs
from cof_gym.envs.torque_interrogation import make_kwargs

DESCRIPTION = """\
Play every agent on the same seeded scenarios (same CoF, condition, speed, load, noise streams) and
write OUT/episodes.csv, OUT/summary.md, OUT/summary.json (median and P90 relative CoF error,
macro-slips, slip energy, Wd comfort, measurement time and peak torque as a fraction of the real
saturation torque, and the median and P90 error with a macro-slip counted as a failed measurement (100 %),
each with a bootstrap 95 % CI, and a breakdown by condition, CoF band, creep-law
family, the creep curve's peak creepage, systematic creepage-error band, the utilisation at which
the estimate was committed and how the episode ended: the agent's stop, the horizon (the last of the
task's steps), a macro-slip) and figures. --env-kwargs plays the suite with other env arguments
(e.g. max_windows:60, a longer horizon). The outputs appear all at once when the run completes (an
interrupted run leaves the previous OUT as it was). Only agents marked as oracles see
info["ground_truth"]."""

N_BOOTSTRAP = 2000
BOOTSTRAP_BLOCK_VALUES = 1 << 22  # resampled values held at once by a bootstrap (32 MiB of floats)
DEFAULT_OUT = Path("out") / "evaluate"
COF_BANDS = (0.0, 0.1, 0.2, 0.3, 0.4, math.inf)  # CoF band edges of the breakdown
# |systematic creepage error| band edges (the sensors' (1 + e_R)/(1 + e_v) - 1; 0 in v1)
CREEPAGE_ERROR_BANDS = (0.0, 1e-9, 0.002, 0.005, 0.01, math.inf)
# the creepage of the true creep curve's peak: the lag reaches 90 deg there, and a curve that still rises slowly past
# its knee (a peak at several % creepage) reads a large lag well below its peak's adhesion
PEAK_CREEPAGE_BANDS = (0.0, 0.01, 0.02, 0.04, math.inf)
# "how early can you know": peak torque at the committed estimate, as a fraction of the true M_sat
UTILISATION_BANDS = (0.0, 0.8, 0.9, 0.95, math.inf)
# how an episode ended, in the breakdown's order: the agent's stop action before its last step, the horizon (the
# episode ran to the task's last step, max_windows: the agent used every window it had, whether it asked to stop at
# that step or the task ended the episode there), a macro-slip (scored, penalised), a diverging simulation (unscored)
ENDINGS = ("stop", "horizon", "macro-slip", "diverged")
OUTPUT_MARKER = "summary.json"  # what makes an existing --out directory a previous evaluate output
# a worker's start (imports, env, agents: a few seconds) costs about as much as this many episodes, so the default
# number of workers gives each at least this many
EPISODES_PER_WORKER = 40
MAX_WORKERS = 1024
QUEUED_PER_WORKER = 4  # episodes handed to the workers at a time, per worker (however long the suite)
WORKER_MEMORY_BYTES = 1 << 30  # memory a worker may take (measured: 0.41 GB resident with every default agent)


def default_out(suite: str, env_overrides: Mapping[str, Any] | None = None) -> Path:
    """``out/evaluate`` for the default suite, ``out/evaluate-<suite>`` for any other, each followed by
    ``-NAME=VALUE`` per env argument given over the suite's (so that runs on different suites or envs never
    overwrite each other)."""
    name = "evaluate" if suite == "default" else f"evaluate-{Path(suite).stem if suite.endswith('.json') else suite}"
    for key, value in (env_overrides or {}).items():
        name += "-" + re.sub(r"[^A-Za-z0-9_.=+-]", "_", f"{key}={json.dumps(value)}")
    return DEFAULT_OUT.with_name(name)


@dataclass
class ScenarioColumns:
    """An episode's scenario as a record holds it: the entries of ``info["ground_truth"]`` of these names."""

    cof: float
    condition: str
    speed_m_s: float
    load_case: str
    noise_level: float
    motor_lag_s: float
    creep_family: str
    creepage_offset: float  # the sensors' systematic creepage error (1 + e_R)/(1 + e_v) - 1
    peak_creepage: float  # the creepage of the true creep curve's peak at the episode's speed and load

    @classmethod
    def read(cls, ground_truth: dict[str, Any]) -> dict[str, Any]:
        """These columns' values in an episode's ground truth."""
        return {f.name: ground_truth[f.name] for f in fields(cls)}


@dataclass
class EpisodeRecord(ScenarioColumns):
    """One agent's episode: its scenario (:class:`ScenarioColumns`), then what the agent did and scored."""

    agent: str
    oracle: bool
    episode: int
    seed: int
    estimate: float
    relative_error: float  # |estimate / CoF - 1|; 1.0 when the episode ended unscored (divergence)
    scored: bool
    macro_slip: bool
    slip_energy_j: float  # energy dissipated past the creep-curve peak
    friction_energy_j: float
    wd_rms_m_s2: float  # time-weighted over the episode
    measurement_time_s: float
    peak_torque_fraction: float  # max |torque| over the real saturation torque
    episode_return: float
    steps: int
    ended: str  # how the episode ended: one of ENDINGS
    note: str = ""  # the suite's label of the episode (e.g. a held-out grid's creep-curve shape)

    @property
    def error_slip_failed(self) -> float:
        """The relative error with a macro-slip counted as a failed measurement (1.0, as an unscored episode):
        a measurement that spun the wheel past its peak is one a train would not make, however accurate the
        estimate the runaway gave."""
        return 1.0 if self.macro_slip or not self.scored else self.relative_error


def _field(info: dict, key: str, default: float = 0.0) -> float:
    """A window quantity wherever the env files it (ground truth first, then the sensor readings)."""
    for group in ("ground_truth", "measurement"):
        value = info.get(group, {}).get(key)
        if value is not None:
            return value
    return default


def run_episode(env, agent, seed: int, options: dict, episode: int, trace: list | None = None,
                oracle: bool | None = None, note: str = "") -> EpisodeRecord:
    """One episode of ``agent``. ``oracle`` (default: the agent's own flag) decides whether the agent
    sees ``info["ground_truth"]``; the evaluator always reads it for scoring."""
    oracle = bool(getattr(agent, "oracle", False)) if oracle is None else bool(oracle)
    obs, info = env.reset(seed=seed, options=options)
    agent.reset(obs, agent_view(info, oracle))
    total, steps = 0.0, 0
    slip_e = fric_e = wd2 = 0.0
    peak = 0.0
    while True:
        action = agent.act(obs, agent_view(info, oracle))
        obs, reward, terminated, truncated, info = env.step(action)
        total += reward
        steps += 1
        m = info["measurement"]
        slip_e += _field(info, "energy_past_peak_j")
        fric_e += _field(info, "friction_energy_j")
        wd2 += m["wd_rms_m_s2"] ** 2
        peak = max(peak, _field(info, "peak_torque_fraction"))  # the true torque, not the biased reading
        if trace is not None:
            trace.append({"t": info["elapsed_s"], "dc_torque_nm": m["torque_mean_nm"], "speed_m_s": m["speed_measured_m_s"],
                          "wheel_speed_m_s": m["speed_measured_m_s"] * (1.0 + _field(info, "creepage_mean")),
                          "coa": m["coa_measured"], "phase_deg": m["phase_lag_deg"],
                          "estimate": info["cof_estimate"], "cof": info["ground_truth"]["cof"]})
        if terminated or truncated:
            break
    gt = info["ground_truth"]
    macro_slip = bool(info.get("macro_slip", False))
    ended = ("diverged" if info.get("diverged", False) else "macro-slip" if macro_slip else
             "horizon" if truncated or steps >= env.unwrapped.task.max_windows else "stop")
    err = info.get("relative_error")
    scored = err is not None and bool(info.get("scored", True)) and not info.get("diverged", False)
    return EpisodeRecord(
        **ScenarioColumns.read(gt), agent=agent.name, oracle=oracle, episode=episode, seed=seed,
        estimate=info["cof_estimate"],
        relative_error=float(err) if err is not None else 1.0, scored=scored,
        macro_slip=macro_slip, slip_energy_j=slip_e, friction_energy_j=fric_e,
        wd_rms_m_s2=math.sqrt(wd2 / steps), measurement_time_s=info["elapsed_s"], peak_torque_fraction=peak,
        episode_return=total, steps=steps, note=note, ended=ended,
    )


def bootstrap_ci(values: np.ndarray, stat, rng: np.random.Generator, n: int = N_BOOTSTRAP) -> tuple[float, float]:
    """Percentile bootstrap 95 % confidence interval of ``stat`` (a NumPy reduction taking ``axis``: each
    resample's statistic is a row's, computed as for the resample alone, in blocks of rows to bound memory)."""
    if len(values) < 2:
        v = float(stat(values)) if len(values) else float("nan")
        return v, v
    idx = rng.integers(0, len(values), size=(n, len(values)))
    block = max(1, BOOTSTRAP_BLOCK_VALUES // len(values))
    stats = np.concatenate([stat(values[idx[i:i + block]], axis=1) for i in range(0, n, block)])
    return float(np.percentile(stats, 2.5)), float(np.percentile(stats, 97.5))


def _p90(v: np.ndarray, axis: int | None = None):
    """The 90th percentile (per row along ``axis``)."""
    return np.percentile(v, 90, axis=axis) if axis is not None else float(np.percentile(v, 90))


METRICS = (
    # (key, label with unit, column, statistic, format of the value)
    ("median_error", "median rel. CoF error [%]", "relative_error", np.median, "pct"),
    ("p90_error", "P90 rel. CoF error [%]", "relative_error", _p90, "pct"),
    ("macro_slip_events", "macro-slips [episodes]", "macro_slip", np.sum, "int"),
    ("slip_energy_j", "slip energy past peak [J]", "slip_energy_j", np.mean, "g3"),
    ("wd_rms_m_s2", "Wd comfort [m/s^2]", "wd_rms_m_s2", np.mean, "g3"),
    ("measurement_time_s", "measurement time [s]", "measurement_time_s", np.mean, "g3"),
    ("peak_torque_fraction", "peak torque [% of real M_sat]", "peak_torque_fraction", np.mean, "pct"),
    # last, so that adding them left every bootstrap CI above as it was (one generator per agent, drawn in this order)
    ("median_error_slip_failed", "median rel. CoF error, macro-slip = 100 % [%]", "error_slip_failed", np.median, "pct"),
    ("p90_error_slip_failed", "P90 rel. CoF error, macro-slip = 100 % [%]", "error_slip_failed", _p90, "pct"),
)


def _fmt(value: float, kind: str) -> str:
    if not np.isfinite(value):
        return "-"
    if kind == "pct":
        return f"{100 * value:.1f}"
    if kind == "int":
        return f"{value:.0f}"
    return f"{value:.3g}"


def _band(value: float, edges: tuple[float, ...], label) -> str:
    for lo, hi in zip(edges[:-1], edges[1:]):
        if lo <= value < hi:
            return label(lo, hi)
    return label(edges[-2], edges[-1])


def cof_band(cof: float) -> str:
    return _band(cof, COF_BANDS, lambda lo, hi: f"CoF {lo:.2f}+" if math.isinf(hi) else f"CoF {lo:.2f}-{hi:.2f}")


def creepage_error_band(offset: float) -> str:
    """The band of |systematic creepage error| (0: none, as in v1)."""
    return _band(abs(offset), CREEPAGE_ERROR_BANDS,
                 lambda lo, hi: "creepage error 0" if hi <= 1e-9 else
                 f"|creepage error| {100 * lo:.1f}+ %" if math.isinf(hi) else
                 f"|creepage error| {100 * lo:.1f}-{100 * hi:.1f} %")


def peak_creepage_band(creepage: float) -> str:
    """The band of the true creep curve's peak creepage (where its adhesion is the CoF)."""
    return _band(creepage, PEAK_CREEPAGE_BANDS,
                 lambda lo, hi: f"peak creepage {100 * lo:.0f}+ %" if math.isinf(hi) else
                 f"peak creepage < {100 * hi:.0f} %" if lo == 0 else f"peak creepage {100 * lo:.0f}-{100 * hi:.0f} %")


def utilisation_band(fraction: float) -> str:
    """The band of the peak torque (fraction of the true saturation torque) at the committed estimate."""
    return _band(fraction, UTILISATION_BANDS,
                 lambda lo, hi: f"committed at > {100 * lo:.0f} % M_sat" if math.isinf(hi) else
                 f"committed at <= {100 * hi:.0f} % M_sat" if lo == 0 else
                 f"committed at {100 * lo:.0f}-{100 * hi:.0f} % M_sat")


# the breakdown's groupings, in table order: (name, group of a record, the record's order within it)
GROUPINGS = (
    ("condition", lambda r: r.condition, lambda r: r.condition),
    ("CoF band", lambda r: cof_band(r.cof), lambda r: r.cof),
    ("creep-law family", lambda r: f"law {r.creep_family}", lambda r: r.creep_family),
    ("peak-creepage band", lambda r: peak_creepage_band(r.peak_creepage), lambda r: r.peak_creepage),
    ("creepage-error band", lambda r: creepage_error_band(r.creepage_offset), lambda r: abs(r.creepage_offset)),
    ("utilisation at commitment", lambda r: utilisation_band(r.peak_torque_fraction),
     lambda r: r.peak_torque_fraction),
    ("how the episode ended", lambda r: f"ended: {r.ended}", lambda r: ENDINGS.index(r.ended)),
    ("the suite's episode note", lambda r: f"note {r.note}" if r.note else "no note", lambda r: r.note),
)


def _group_stats(rows: list[EpisodeRecord]) -> dict[str, Any]:
    err = np.array([r.relative_error for r in rows])
    return {"episodes": len(rows), "median_error": float(np.median(err)), "p90_error": _p90(err),
            "macro_slip_events": int(sum(r.macro_slip for r in rows)),
            "peak_torque_fraction": float(np.mean([r.peak_torque_fraction for r in rows]))}


def breakdown(records: list[EpisodeRecord]) -> dict[str, dict[str, dict[str, Any]]]:
    """Per agent: statistics by each of :data:`GROUPINGS` (groups ordered within a grouping; a grouping
    other than condition and CoF band with a single group, e.g. one creep-law family, is left out)."""
    out: dict[str, dict[str, dict[str, Any]]] = {}
    keys = []
    for k, (_, key, order) in enumerate(GROUPINGS):
        first = {}
        for r in sorted(records, key=order):
            first.setdefault(key(r), len(first))
        if len(first) > 1 or k < 2:  # condition and CoF band always; the rest where they vary
            keys.append((key, list(first)))
    for agent in dict.fromkeys(r.agent for r in records):
        rows = [r for r in records if r.agent == agent]
        groups: dict[str, dict[str, Any]] = {}
        for key, values in keys:
            for v in values:
                sel = [r for r in rows if key(r) == v]
                if sel:
                    groups[v] = _group_stats(sel)
        out[agent] = groups
    return out


def summarize(records: list[EpisodeRecord], seed: int) -> dict[str, dict[str, Any]]:
    out: dict[str, dict[str, Any]] = {}
    groups = breakdown(records)
    for agent in dict.fromkeys(r.agent for r in records):
        rows = [r for r in records if r.agent == agent]
        rng = np.random.default_rng(seed)
        entry: dict[str, Any] = {"episodes": len(rows), "oracle": rows[0].oracle}
        for key, _, column, stat, _ in METRICS:
            values = np.array([getattr(r, column) for r in rows], dtype=float)
            lo, hi = bootstrap_ci(values, stat, rng)
            entry[key] = {"value": float(stat(values)), "ci95": [lo, hi]}
        entry["breakdown"] = groups[agent]
        out[agent] = entry
    return out


def _agent_label(summary: dict, a: str) -> str:
    return f"{a} (oracle)" if summary[a]["oracle"] else a


def markdown_table(summary: dict[str, dict[str, Any]]) -> str:
    agents = list(summary)
    lines = ["| metric [unit] (95 % CI) | " + " | ".join(_agent_label(summary, a) for a in agents) + " |",
             "|---" * (len(agents) + 1) + "|"]
    for key, label, _, _, kind in METRICS:
        cells = []
        for a in agents:
            v = summary[a][key]
            cells.append(f"{_fmt(v['value'], kind)} [{_fmt(v['ci95'][0], kind)}, {_fmt(v['ci95'][1], kind)}]")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines.append("| episodes [count] | " + " | ".join(str(summary[a]["episodes"]) for a in agents) + " |")
    return "\n".join(lines)


def _shared_count(summary: dict[str, dict[str, Any]], group: str) -> int | None:
    """The episodes of ``group``, where every agent has that many in it (a scenario group: every agent plays
    the same scenarios); None where the group depends on what the agent did (the utilisation at commitment, how
    the episode ended)."""
    counts = {summary[a]["breakdown"].get(group, {}).get("episodes", 0) for a in summary}
    return counts.pop() if len(counts) == 1 else None


def _group_order(summary: dict[str, dict[str, Any]]) -> list[str]:
    """Every agent's breakdown groups in one order that keeps each agent's (the breakdown's, e.g. the utilisation
    bands from the lowest up), where some groups belong to some agents only; ties in order of first appearance."""
    before: dict[str, set[str]] = {}
    for a in summary:
        seen: set[str] = set()
        for g in summary[a]["breakdown"]:
            before.setdefault(g, set()).update(seen)
            seen.add(g)
    order: list[str] = []
    while len(order) < len(before):
        placed = set(order)
        remaining = [g for g in before if g not in placed]
        order.append(next((g for g in remaining if before[g] <= placed), remaining[0]))
    return order


def _breakdown_rows(summary: dict[str, dict[str, Any]], cell) -> list[tuple[str, int | None, list[str]]]:
    """``(group, shared count or None, a cell per agent)``: ``cell(stats)`` for an agent with episodes in the
    group, followed by its own count where the count is not shared; "-" for an agent with none."""
    rows = []
    for g in _group_order(summary):
        n = _shared_count(summary, g)
        cells = []
        for a in summary:
            s = summary[a]["breakdown"].get(g)
            cells.append("-" if s is None else cell(s) + ("" if n is not None else f" (n={s['episodes']})"))
        rows.append((g, n, cells))
    return rows


def markdown_breakdown(summary: dict[str, dict[str, Any]]) -> str:
    """Median relative error [%] / P90 [%] / macro-slips / mean peak torque [% of M_sat], per group."""
    agents = list(summary)
    lines = ["| group (episodes) | " + " | ".join(_agent_label(summary, a) for a in agents) + " |",
             "|---" * (len(agents) + 1) + "|"]
    for g, n, cells in _breakdown_rows(summary, lambda s: f"{_fmt(s['median_error'], 'pct')} % / "
                                                        f"{_fmt(s['p90_error'], 'pct')} % / {s['macro_slip_events']}"
                                                        f" / {_fmt(s['peak_torque_fraction'], 'pct')} %"):
        lines.append(f"| {g}{'' if n is None else f' ({n})'} | " + " | ".join(cells) + " |")
    return ("Cells: median rel. CoF error / P90 rel. CoF error / macro-slips [episodes] / mean peak torque "
            "[% of real M_sat]; (n=...): the agent's own episodes in a group that depends on what the agent did "
            "(the utilisation at commitment, how the episode ended), where the agents' counts differ.\n\n"
            + "\n".join(lines))


def print_table(summary: dict[str, dict[str, Any]], title: str, out=None) -> None:
    """The summary (value, CI below it) and the breakdown (median error per group) on ``out`` (a rich
    console; default: stdout at the terminal's width, or COLUMNS, or 100), splitting no word
    (:func:`cof_gym.commands.terminal.print_table`)."""
    from cof_gym.commands import terminal

    out = out or terminal.console()
    rows = [[label, *[f"{_fmt(summary[a][key]['value'], kind)}\n[{_fmt(summary[a][key]['ci95'][0], kind)}, "
                      f"{_fmt(summary[a][key]['ci95'][1], kind)}]" for a in summary]]
            for key, label, _, _, kind in METRICS]
    rows.append(["episodes [count]", *[str(summary[a]["episodes"]) for a in summary]])
    labels = [_agent_label(summary, a).replace(" (oracle)", "\n(oracle)") for a in summary]
    terminal.print_table(title, ["metric [unit]\n(95 % CI)", *labels], rows, out)
    bd_rows = [[g if n is None else f"{g} [{n}]", *cells] for g, n, cells in
               _breakdown_rows(summary, lambda s: f"{_fmt(s['median_error'], 'pct')} [{s['macro_slip_events']}]")]
    terminal.print_table("median rel. CoF error [%] by group (macro-slips in brackets)",
                         ["group [episodes]", *summary], bd_rows, out)


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
    from cof_gym.commands.args import UsageError, check_output_dir

    out = check_output_dir(Path(out))
    if out.is_dir() and any(out.iterdir()) and not (out / OUTPUT_MARKER).is_file():
        raise UsageError("--out", f"{out} exists and is not a cof-gym evaluate output (no {OUTPUT_MARKER}); "
                         "give a new or empty directory")
    return out


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


def _read(path: str) -> str:
    try:
        return Path(path).read_text()
    except OSError:
        return ""


def usable_cores() -> int:
    """The CPU cores this process may run on: its affinity, and a container's CPU quota where one is set
    (cgroup v2 ``cpu.max``: a container sees every core of its host but may use only its quota)."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    quota, _, period = _read("/sys/fs/cgroup/cpu.max").partition(" ")
    if quota.strip().isdigit() and period.strip().isdigit() and int(period) > 0:
        cores = min(cores, max(1, math.ceil(int(quota) / int(period))))
    return cores


def available_memory_bytes() -> int | None:
    """Memory available to new processes (``MemAvailable`` of /proc/meminfo); None where it cannot be read."""
    for line in _read("/proc/meminfo").splitlines():
        name, _, value = line.partition(":")
        kib = value.split()[:1]
        if name == "MemAvailable" and kib and kib[0].isdigit():
            return int(kib[0]) * 1024
    return None


def fitting_workers(memory_per_worker: int) -> int:
    """Processes this machine holds: one a usable core, at most one per ``memory_per_worker`` bytes of the
    available memory (the cores alone where it cannot be read); at least 1."""
    cores, memory = usable_cores(), available_memory_bytes()
    return max(1, cores if memory is None else min(cores, memory // memory_per_worker))


def default_workers(n_episodes: int) -> int:
    """One worker a usable core, each with at least :data:`EPISODES_PER_WORKER` of the ``n_episodes``
    (every agent's together) to play and :data:`WORKER_MEMORY_BYTES` of the available memory; 1: the episodes
    are played in this process."""
    return max(1, min(fitting_workers(WORKER_MEMORY_BYTES), n_episodes // EPISODES_PER_WORKER))


def evaluate(agent_specs: list[str], suite: Suite, out: Path, seed: int, quiet: bool = False,
             check_suite: bool = False, workers: int | None = 1) -> dict[str, Any]:
    """Play ``agent_specs`` on ``suite``; write the outputs to ``out`` (atomically); return the results.

    Before the first episode every agent is built (:class:`~cof_gym.agents.registry.AgentSpecError`)
    and, with ``check_suite``, the env kwargs and every distinct reset option set of the suite are tried
    (:class:`~cof_gym.commands.suites.SuiteError`). ``workers``: processes that play the episodes (None:
    :func:`default_workers`); every episode is seeded on its own, so the outputs are the same for any number. The
    workers are spawned: a script that asks for more than one needs the usual ``if __name__ == "__main__":`` guard."""
    import gymnasium as gym

    t0 = time.perf_counter()
    try:
        env = gym.make(suite.env_id, **make_kwargs(suite.env_kwargs))
    except (ValueError, TypeError) as e:
        if not check_suite:
            raise
        raise SuiteError(f"{suite.name}: env_kwargs {suite.env_kwargs}: {e}") from None
    agents: list[tuple[Any, bool]] = []
    envs: dict[str, Any] = {}
    try:
        if check_suite:
            check_suite_runs(suite, env)
        agents = build_agents(agent_specs, env)
        envs = agent_envs(agents, suite, env)
        staging = _Staging(out)
        try:
            n_workers = default_workers(len(agents) * len(suite.episodes)) if workers is None else workers
            result = _play_and_write(envs, agents, agent_specs, suite, staging.path, seed, quiet, t0, n_workers)
            staging.commit()
        except BaseException:
            staging.abort()
            raise
    finally:
        env.close()
        for own in envs.values():
            if own is not env:
                own.close()
        for agent, _ in agents:
            close = getattr(agent, "close", None)
            if callable(close):
                close()
    if not quiet:
        print_table(result["summary"], f"cof-gym evaluate: suite {suite.name} ({len(suite.episodes)} episodes per "
                                       f"agent), seed {seed}, {suite.env_id}")
        for note in result["notes"]:
            print(f"note: {note}")
        print(f"episodes.csv, summary.md/json and figures in {out} ({result['wall_time_s']:.1f} s)")
    return result


def agent_envs(agents, suite: Suite, shared_env) -> dict[str, Any]:
    """The env each agent plays in, by name: ``shared_env`` (the suite's), or an env of its own for an agent whose
    excitation needs env options beyond the suite's (``agent.env_options``, e.g. the two-tone interrogator's
    ``excitation="multitone"``): the suite's env id and kwargs with those options; the same seeds draw the same
    scenarios and ground truth, and only the drive and the measurement of the windows change."""
    import gymnasium as gym

    envs = {}
    for agent, _ in agents:
        options = own_env_options(agent)
        envs[agent.name] = gym.make(suite.env_id, **{**make_kwargs(suite.env_kwargs), **options}) if options \
            else shared_env
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


def _play_episode(envs: dict[str, Any], agents, suite: Suite, k: int, i: int) -> tuple[EpisodeRecord, list | None]:
    """Agent ``k`` on the suite's episode ``i``; the trace of every agent's first episode (the figures')."""
    agent, oracle = agents[k]
    ep_seed, options = suite.episodes[i]
    trace = [] if i == 0 else None
    return run_episode(envs[agent.name], agent, ep_seed, options, i, trace, oracle=oracle, note=suite.note(i)), trace


_WORKER: dict[str, Any] = {}  # a worker process's envs, agents and suite (:func:`_start_worker`)


def _start_worker(agent_specs: list[str], suite: Suite, warning_filters: list) -> None:
    """A worker's own env and agents, built as the parent built them, with the parent's warning filters (one
    torch thread: the cores are the workers')."""
    import warnings

    import gymnasium as gym
    import torch

    warnings.filters[:] = warning_filters
    torch.set_num_threads(1)
    env = gym.make(suite.env_id, **make_kwargs(suite.env_kwargs))
    agents = build_agents(agent_specs, env)
    _WORKER.update(envs=agent_envs(agents, suite, env), agents=agents, suite=suite)


def _worker_episode(task: tuple[int, int]) -> tuple[int, int, EpisodeRecord, list | None]:
    k, i = task
    return (k, i, *_play_episode(_WORKER["envs"], _WORKER["agents"], _WORKER["suite"], k, i))


def _play(envs: dict[str, Any], agents, agent_specs, suite: Suite, workers: int, advance) -> list[tuple]:
    """``(k, i, record, trace)`` of every agent ``k`` and episode ``i``, in that order: played here in that
    order (``workers`` 1), or by ``workers`` spawned processes, an episode a task. ``advance(k)`` after each."""
    tasks = [(k, i) for k in range(len(agents)) for i in range(len(suite.episodes))]
    workers = min(workers, len(tasks))
    played = _play_in_workers(agent_specs, suite, tasks, workers, advance) if workers > 1 else None
    if played is not None:
        return played
    played = []
    for k, i in tasks:
        played.append((k, i, *_play_episode(envs, agents, suite, k, i)))
        advance(k)
    return played


def _play_in_workers(agent_specs, suite: Suite, tasks: list[tuple[int, int]], workers: int, advance) -> list | None:
    """:func:`_play`'s tasks in ``workers`` spawned processes, a few handed to each at a time; None where no
    worker process can start here (no process-shared semaphores, e.g. no /dev/shm: one note on stderr)."""
    import multiprocessing
    import warnings
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    portable = replace(suite, env_kwargs=dict(suite.env_kwargs), episodes=list(suite.episodes))  # what pickles
    try:
        pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"), initializer=_start_worker,
                                   initargs=(list(agent_specs), portable, list(warnings.filters)))
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
                    k, i, record, trace = future.result()
                    done[k, i] = (k, i, record, trace)
                    advance(k)
        except BaseException:
            for future in pending:
                future.cancel()
            raise
    return [done[task] for task in tasks]


def _play_and_write(envs: dict[str, Any], agents, agent_specs, suite: Suite, out: Path, seed: int, quiet: bool,
                    t0: float, workers: int = 1) -> dict[str, Any]:
    progress = _progress(quiet)
    if progress is not None:
        progress.start()
    try:
        bars = [progress.add_task(agent.name, total=len(suite.episodes)) for agent, _ in agents] \
            if progress is not None else []
        played = _play(envs, agents, agent_specs, suite, workers,
                       lambda k: progress.advance(bars[k]) if progress is not None else None)
    finally:
        if progress is not None:
            progress.stop()
    records = [record for _, _, record, _ in played]
    traces = {agents[k][0].name: trace for k, i, _, trace in played if i == 0}
    summary = summarize(records, seed)
    notes = distribution_notes(agents, suite)
    with open(out / "episodes.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(asdict(records[0])))
        writer.writeheader()
        writer.writerows(asdict(r) for r in records)
    (out / "summary.md").write_text(
        f"# cof-gym evaluate: suite {suite.name}, seed {seed}, {suite.env_id}\n\n"
        + "".join(f"Note: {n}.\n\n" for n in notes) + f"{markdown_table(summary)}\n\n"
        "## By condition, CoF band, creep-law family, peak creepage, creepage-error band, utilisation, ending and "
        f"note\n\n{markdown_breakdown(summary)}\n")
    from cof_gym.commands.evaluate_figures import plot_all

    figures = [Path(p).name for p in plot_all(records, summary, traces, out)]
    result = {"suite": suite.name, "env_id": suite.env_id, "env_kwargs": suite.env_kwargs, "seed": seed,
              "agents": list(agent_specs), "summary": summary, "traces": traces, "figures": figures, "notes": notes,
              "cof_bands": [b for b in COF_BANDS if math.isfinite(b)]}
    # written last: its presence marks a complete output directory
    (out / OUTPUT_MARKER).write_text(json.dumps(result, indent=1))
    result["wall_time_s"] = time.perf_counter() - t0
    return result


# ---------------------------------------------------------------------------- command line
def add_arguments(parser: argparse.ArgumentParser) -> None:
    from cof_gym.commands.args import MAX_SEED, StoreDict, int_in_range, seed_int

    parser.add_argument("--agents", default=None, metavar="A,B,...",
                        help=f"comma-separated agents: {registry.describe()} (default: "
                             f"{','.join(registry.default_agents())})")
    parser.add_argument("--episodes", type=int_in_range(1, MAX_EPISODES), default=60,
                        help=f"episodes per agent, at most {MAX_EPISODES} (a suite file with an episode list sets "
                             "its own)")
    parser.add_argument("--suite", default="default", metavar="SUITE",
                        help="scenarios: 'default' (the env's distribution), 'paper' (the paper's setting) or a "
                             "JSON suite file (see cof_gym/commands/suites.py)")
    parser.add_argument("--env-kwargs", nargs="+", action=StoreDict, default={}, metavar="KEY:VALUE",
                        help="env constructor arguments over the suite's (a Python literal or text, as cof-gym train "
                             "and RL Zoo take them), e.g. max_windows:60 (a longer horizon) or counter_torque:True; "
                             "not the agents' interface (action_type, excitation, info_layout)")
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
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress and no table on the terminal")


def prepare(args: argparse.Namespace) -> tuple[list[str], Suite, Path]:
    """Check the whole command line before anything runs or is written (UsageError naming the flag)."""
    from cof_gym.commands.args import MAX_SEED, UsageError

    specs = [s.strip() for s in args.agents.split(",")] if args.agents is not None else registry.default_agents()
    if not specs or any(not s for s in specs):
        raise UsageError("--agents", f"empty agent name in {args.agents!r}; allowed: {registry.describe()}")
    for spec in specs:
        try:
            _, argument = registry.parse(spec)
        except registry.AgentSpecError as e:
            raise UsageError("--agents", str(e)) from None
        if argument is not None and spec.startswith("ppo:"):
            from cof_gym.agents.ppo import check_model, resolve_model_path

            try:
                check_model(resolve_model_path(argument))
            except (FileNotFoundError, ValueError) as e:
                raise UsageError("--agents", f"{spec}: {e}") from None
    if len(set(specs)) != len(specs):
        raise UsageError("--agents", f"an agent is given twice in {args.agents!r}")
    try:
        suite = make_suite(args.suite, args.episodes, args.seed)
    except SuiteError as e:
        raise UsageError("--suite", str(e)) from None
    env_overrides = dict(args.env_kwargs)
    if env_overrides:
        suite = _with_env(suite, env_overrides)
    last_seed = max(seed for seed, _ in suite.episodes)
    if last_seed > MAX_SEED:  # seeded episodes: seed + i
        raise UsageError("--seed", f"the last episode's seed {last_seed} is beyond {MAX_SEED}; give at most "
                                   f"{MAX_SEED - len(suite.episodes) + 1} for {len(suite.episodes)} episodes")
    out = check_out(Path(args.out) if args.out is not None else default_out(args.suite, env_overrides))
    return specs, suite, out


def _with_env(suite: Suite, overrides: dict[str, Any]) -> Suite:
    """``--env-kwargs``: the suite with these env arguments, the env built once with them (UsageError naming the
    flag)."""
    import gymnasium as gym

    from cof_gym.agents.base import env_defaults
    from cof_gym.commands.args import UsageError
    from cof_gym.task.scenarios import SCENARIO_KEYS

    # the constructor's arguments (a scenario field fixes it in every episode that does not set it), not the id's own
    allowed = sorted({*env_defaults(suite.env_id), *SCENARIO_KEYS, "max_episode_steps"} - {"vehicle", "task_version"})
    unknown = sorted(set(overrides) - set(allowed))
    if unknown:
        raise UsageError("--env-kwargs", f"unknown env argument(s) {unknown}; allowed: {allowed}")
    try:
        suite = with_env_kwargs(suite, overrides)
        gym.make(suite.env_id, **make_kwargs(suite.env_kwargs)).close()
    except (SuiteError, ValueError, TypeError) as e:
        raise UsageError("--env-kwargs", str(e)) from None
    return suite


def check_suite_runs(suite: Suite, env) -> None:
    """Every distinct reset option set of the suite is accepted by the env (one reset each)."""
    seen = set()
    for i, (ep_seed, options) in enumerate(suite.episodes):
        key = json.dumps(options, sort_keys=True, default=repr)
        if key in seen:
            continue
        seen.add(key)
        try:
            env.reset(seed=ep_seed, options=options)
        except (ValueError, TypeError, KeyError) as e:
            raise SuiteError(f"{suite.name}: episode {i} (options {options}): {e}") from None


def run(args: argparse.Namespace) -> int:
    from cof_gym.commands.args import UsageError

    specs, suite, out = prepare(args)
    try:
        evaluate(specs, suite, out, args.seed, quiet=args.quiet, check_suite=True, workers=args.workers)
    except SuiteError as e:
        raise UsageError("--suite", str(e)) from None
    except registry.AgentSpecError as e:
        raise UsageError("--agents", str(e)) from None
    return 0
