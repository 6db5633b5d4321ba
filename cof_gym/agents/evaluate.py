"""``cof-gym evaluate``: agents side by side on the same seeded scenarios, with tables and figures."""

from __future__ import annotations

import argparse
import csv
import json
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import cof_gym  # noqa: F401  (registers the environments)
from cof_gym.agents.base import Agent
from cof_gym.agents.staircase import PaperStaircase, PracticalStaircase, limits_of
from cof_gym.agents.suites import Suite, make_suite

PACKAGE_DIR = Path(__file__).resolve().parent
SHIPPED_PPO = PACKAGE_DIR / "policies" / "ppo_wagon"
DEFAULT_AGENTS = "staircase-paper,staircase,ppo"
N_BOOTSTRAP = 2000


def make_agent(spec: str, env: gym.Env) -> Agent:
    """``staircase-paper``, ``staircase``, ``ppo`` (the shipped policy) or ``ppo:PATH``."""
    limits = limits_of(env)
    if spec == "staircase-paper":
        return PaperStaircase(limits)
    if spec == "staircase":
        return PracticalStaircase(limits)
    if spec == "ppo" or spec.startswith("ppo:"):
        from cof_gym.agents.ppo import PPOAgent

        path = Path(spec[4:]) if spec.startswith("ppo:") else SHIPPED_PPO
        agent = PPOAgent.load(path)
        if spec.startswith("ppo:"):
            agent.name = f"ppo:{path.stem if path.suffix else path.name}"
        return agent
    raise ValueError(f"agent must be staircase-paper, staircase, ppo or ppo:PATH, got {spec!r}")


@dataclass
class EpisodeRecord:
    agent: str
    oracle: bool
    episode: int
    seed: int
    cof: float
    condition: str
    speed_m_s: float
    load_case: str
    noise_level: float
    motor_lag_s: float
    estimate: float
    relative_error: float  # error_cap (1.0) when the episode ended in macro-slip or divergence
    scored: bool
    macro_slip: bool
    slip_energy_j: float  # energy dissipated past the creep-curve peak
    friction_energy_j: float
    wd_rms_m_s2: float  # time-weighted over the episode
    measurement_time_s: float
    peak_torque_fraction: float  # max |torque| over the saturation torque
    episode_return: float
    steps: int


def run_episode(env: gym.Env, agent: Agent, seed: int, options: dict, episode: int,
                trace: list | None = None) -> EpisodeRecord:
    obs, info = env.reset(seed=seed, options=options)
    agent.reset(obs, info)
    total, steps = 0.0, 0
    slip_e = fric_e = wd2 = 0.0
    peak = 0.0
    sat = info["ground_truth"]["saturation_torque_nm"]
    while True:
        action = agent.act(obs, info)
        obs, reward, terminated, truncated, info = env.step(action)
        total += reward
        steps += 1
        m = info["measurement"]
        slip_e += m["energy_past_peak_j"]
        fric_e += m["friction_energy_j"]
        wd2 += m["wd_rms_m_s2"] ** 2
        peak = max(peak, m["torque_peak_nm"] / sat)
        if trace is not None:
            trace.append({"t": info["elapsed_s"], "dc_torque_nm": m["torque_mean_nm"], "speed_m_s": m["speed_measured_m_s"],
                          "wheel_speed_m_s": m["speed_measured_m_s"] * (1.0 + m["creepage_mean"]),
                          "coa": m["coa_measured"], "phase_deg": m["phase_lag_deg"],
                          "estimate": info["cof_estimate"], "cof": info["ground_truth"]["cof"]})
        if terminated or truncated:
            break
    gt = info["ground_truth"]
    macro_slip = bool(info.get("macro_slip", False))
    scored = not macro_slip and info.get("relative_error") is not None
    err = float(info["relative_error"]) if info.get("relative_error") is not None else 1.0
    return EpisodeRecord(
        agent=agent.name, oracle=agent.oracle, episode=episode, seed=seed, cof=gt["cof"], condition=gt["condition"],
        speed_m_s=gt["speed_m_s"], load_case=gt["load_case"], noise_level=gt["noise_level"],
        motor_lag_s=gt["motor_lag_s"], estimate=info["cof_estimate"], relative_error=err, scored=scored,
        macro_slip=macro_slip, slip_energy_j=slip_e, friction_energy_j=fric_e,
        wd_rms_m_s2=math.sqrt(wd2 / steps), measurement_time_s=info["elapsed_s"], peak_torque_fraction=peak,
        episode_return=total, steps=steps,
    )


def bootstrap_ci(values: np.ndarray, stat, rng: np.random.Generator, n: int = N_BOOTSTRAP) -> tuple[float, float]:
    """Percentile bootstrap 95 % confidence interval of ``stat``."""
    if len(values) < 2:
        v = float(stat(values)) if len(values) else float("nan")
        return v, v
    idx = rng.integers(0, len(values), size=(n, len(values)))
    stats = np.array([stat(values[i]) for i in idx])
    return float(np.percentile(stats, 2.5)), float(np.percentile(stats, 97.5))


METRICS = (
    # (key, label, column, statistic)
    ("median_error", "median rel. CoF error", "relative_error", np.median),
    ("p90_error", "P90 rel. CoF error", "relative_error", lambda v: np.percentile(v, 90)),
    ("macro_slip_events", "macro-slip events", "macro_slip", np.sum),
    ("slip_energy_j", "slip energy past peak [J]", "slip_energy_j", np.mean),
    ("wd_rms_m_s2", "Wd comfort [m/s^2]", "wd_rms_m_s2", np.mean),
    ("measurement_time_s", "measurement time [s]", "measurement_time_s", np.mean),
    ("peak_torque_fraction", "peak torque / M_sat", "peak_torque_fraction", np.mean),
)


def summarize(records: list[EpisodeRecord], seed: int) -> dict[str, dict[str, Any]]:
    out: dict[str, dict[str, Any]] = {}
    for agent in dict.fromkeys(r.agent for r in records):
        rows = [r for r in records if r.agent == agent]
        rng = np.random.default_rng(seed)
        entry: dict[str, Any] = {"episodes": len(rows), "oracle": rows[0].oracle}
        for key, _, column, stat in METRICS:
            values = np.array([getattr(r, column) for r in rows], dtype=float)
            lo, hi = bootstrap_ci(values, stat, rng)
            entry[key] = {"value": float(stat(values)), "ci95": [lo, hi]}
        out[agent] = entry
    return out


def markdown_table(summary: dict[str, dict[str, Any]]) -> str:
    agents = list(summary)
    head = "| metric | " + " | ".join(f"{a}{' (oracle)' if summary[a]['oracle'] else ''}" for a in agents) + " |"
    lines = [head, "|---" * (len(agents) + 1) + "|"]
    for key, label, _, _ in METRICS:
        cells = []
        for a in agents:
            v = summary[a][key]
            fmt = "{:.1%}" if "error" in key else "{:.3g}"
            cells.append(f"{fmt.format(v['value'])} [{fmt.format(v['ci95'][0])}, {fmt.format(v['ci95'][1])}]")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines.append("| episodes | " + " | ".join(str(summary[a]["episodes"]) for a in agents) + " |")
    return "\n".join(lines)


def print_table(summary: dict[str, dict[str, Any]], title: str) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title=title)
    table.add_column("metric (95 % CI)")
    for a in summary:
        table.add_column(a + (" (oracle)" if summary[a]["oracle"] else ""), justify="right")
    for key, label, _, _ in METRICS:
        fmt = "{:.1%}" if "error" in key else "{:.3g}"
        table.add_row(label, *[f"{fmt.format(summary[a][key]['value'])} [{fmt.format(summary[a][key]['ci95'][0])}, "
                               f"{fmt.format(summary[a][key]['ci95'][1])}]" for a in summary])
    Console(width=160).print(table)


def evaluate(agent_specs: list[str], suite: Suite, out: Path, seed: int, quiet: bool = False) -> dict[str, Any]:
    out.mkdir(parents=True, exist_ok=True)
    env = gym.make(suite.env_id, **suite.env_kwargs)
    records: list[EpisodeRecord] = []
    traces: dict[str, list] = {}
    t0 = time.perf_counter()
    for spec in agent_specs:
        agent = make_agent(spec, env)
        traces[agent.name] = []
        for i, (ep_seed, options) in enumerate(suite.episodes):
            records.append(run_episode(env, agent, ep_seed, options, i, traces[agent.name] if i == 0 else None))
    env.close()
    summary = summarize(records, seed)
    with open(out / "episodes.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(asdict(records[0])))
        writer.writeheader()
        writer.writerows(asdict(r) for r in records)
    table = markdown_table(summary)
    (out / "summary.md").write_text(f"# cof-gym evaluate: suite {suite.name}, seed {seed}\n\n{table}\n")
    result = {"suite": suite.name, "env_id": suite.env_id, "env_kwargs": suite.env_kwargs, "seed": seed,
              "agents": agent_specs, "summary": summary, "traces": traces,
              "wall_time_s": time.perf_counter() - t0}
    (out / "summary.json").write_text(json.dumps({k: v for k, v in result.items() if k != "wall_time_s"}, indent=1))
    from cof_gym.agents.evaluate_figures import plot_all

    result["figures"] = [str(p) for p in plot_all(records, summary, traces, out)]
    if not quiet:
        print_table(summary, f"cof-gym evaluate: suite {suite.name} ({len(suite.episodes)} episodes), seed {seed}")
        print(f"per-episode CSV, summary.md/json and figures in {out} ({result['wall_time_s']:.1f} s)")
    return result


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--agents", default=None,
                        help=f"comma-separated: staircase-paper, staircase, ppo, ppo:PATH (default {DEFAULT_AGENTS}, "
                             "ppo only if the shipped policy exists)")
    parser.add_argument("--episodes", type=int, default=60, help="episodes per agent")
    parser.add_argument("--suite", default="default", help="default | paper | FILE.json")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default="out/evaluate")


def run(args: argparse.Namespace) -> int:
    if args.episodes < 1:
        raise ValueError(f"--episodes must be >= 1, got {args.episodes}")
    specs = args.agents.split(",") if args.agents else [
        a for a in DEFAULT_AGENTS.split(",") if a != "ppo" or (SHIPPED_PPO / "model.zip").exists()]
    evaluate([s.strip() for s in specs if s.strip()], make_suite(args.suite, args.episodes, args.seed), Path(args.out),
             args.seed)
    return 0
