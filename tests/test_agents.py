"""Agents and the evaluation CLI: the paper's rule, the adapters, determinism of the tables."""

from __future__ import annotations

import csv
import math
import re
import json
from dataclasses import replace
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import cof_gym  # noqa: F401
from cof_gym.agents.adapters import incremental_to_env
from cof_gym.agents import registry
from cof_gym.agents.base import Agent
from cof_gym.commands.evaluate import evaluate
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.commands.evaluate_stats import GROUPINGS, peak_creepage_band, utilisation_band
from cof_gym.agents.staircase import PaperStaircase, PracticalStaircase, limits_of
from cof_gym.commands.suites import SuiteError, make_suite, paper_suite
from cof_gym.task.interface import OBSERVATION_NAMES, decode_action

WAGON = "CofGym/TorqueInterrogation-v1"


def test_agents_implement_the_interface() -> None:
    env = gym.make(WAGON)
    for agent in (PaperStaircase(limits_of(env)), PracticalStaircase(limits_of(env))):
        assert isinstance(agent, Agent)
    assert PaperStaircase(limits_of(env)).oracle and not PracticalStaircase(limits_of(env)).oracle


def test_paper_staircase_stops_at_the_first_positive_phase_like_reproduce_paper() -> None:
    """On the paper's setting (laden, dry, 10 m/s, counter torque) the oracle climbs the paper's schedule
    and stops at the first positive phase: for CoF 0.4, the 80 % step of `reproduce-paper` (Fig. 8, dry)."""
    suite = paper_suite(5, seed=0)
    env = gym.make(suite.env_id, **suite.env_kwargs)
    agent = PaperStaircase(limits_of(env))
    seed, options = suite.episodes[3]
    assert options["cof"] == 0.4
    obs, info = env.reset(seed=seed, options=options)
    agent.reset(obs, info)
    phases, fractions = [], []
    while True:
        obs, _, terminated, truncated, info = env.step(agent.act(obs, info))
        phases.append(info["measurement"]["phase_lag_deg"])
        fractions.append(info["ground_truth"]["torque_fraction"])
        if terminated or truncated:
            break
    assert terminated and not info["macro_slip"]
    assert phases[0] < 0 and all(p <= 0 for p in phases[:-2]) and phases[-2] > 0  # stop requested after it
    assert fractions[-2] == pytest.approx(0.80, abs=0.005)
    assert info["cof_estimate"] == pytest.approx(info["measurement"]["coa_measured"], abs=0.01)
    assert info["relative_error"] == pytest.approx(0.20, abs=0.03)


def test_incremental_adapter_is_the_env_relative_interface_on_the_agent_side() -> None:
    """``incremental`` moves the DC torque by a log-step (x e^0.5 at most per window) and reports the
    estimate as a factor on the best measured CoA, as the env's ``relative`` action type."""
    env = gym.make(WAGON)
    limits = limits_of(env)
    obs = np.zeros(len(OBSERVATION_NAMES), dtype=np.float32)
    obs[OBSERVATION_NAMES.index("dc_torque")] = 0.5
    obs[OBSERVATION_NAMES.index("coa_measured")] = 0.2
    d = decode_action(incremental_to_env(np.array([1.0, 0.0, 0.0, 0.0, 0.0]), obs, limits), limits)
    assert d.drive.dc_torque_nm == pytest.approx(0.5 * math.exp(0.5) * limits.max_dc_torque_nm, rel=1e-5)
    assert d.cof_estimate == pytest.approx(0.2, rel=1e-5) and not d.stop
    d = decode_action(incremental_to_env(np.array([-1.0, 0.0, 0.0, 1.0, 0.9]), obs, limits), limits)
    assert d.drive.dc_torque_nm == pytest.approx(0.5 * math.exp(-0.5) * limits.max_dc_torque_nm, rel=1e-5)
    assert d.cof_estimate == pytest.approx(0.2 * math.exp(0.5), rel=1e-5) and d.stop


def test_same_agents_same_seed_give_identical_tables(tmp_path: Path) -> None:
    suite = make_suite("default", 3, seed=5)
    a = evaluate(["staircase", "staircase-paper"], suite, tmp_path / "a", seed=5, quiet=True)
    b = evaluate(["staircase", "staircase-paper"], suite, tmp_path / "b", seed=5, quiet=True)
    assert a["summary"] == b["summary"]
    assert (tmp_path / "a" / "summary.md").read_text() == (tmp_path / "b" / "summary.md").read_text()
    assert (tmp_path / "a" / "episodes.csv").read_text() == (tmp_path / "b" / "episodes.csv").read_text()
    rows = list(csv.DictReader(open(tmp_path / "a" / "episodes.csv")))
    assert len(rows) == 6
    # every agent met the same scenarios
    by_agent = {}
    for r in rows:
        by_agent.setdefault(r["agent"], []).append((r["seed"], r["cof"], r["condition"], r["speed_m_s"]))
    assert by_agent["staircase"] == by_agent["staircase-paper"]
    for name in ("error_per_cof.png", "error_vs_discomfort.png", "episode_traces.png", "summary.json"):
        assert (tmp_path / "a" / name).stat().st_size > 1000
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())["summary"]
    lo, hi = summary["staircase"]["median_error"]["ci95"]
    assert lo <= summary["staircase"]["median_error"]["value"] <= hi


def test_worker_processes_write_what_one_process_writes(tmp_path: Path, monkeypatch, capsys) -> None:
    """Episodes played by two spawned workers (each its own env and agents, the learned one included, handed an
    episode at a time) give the same files, byte for byte, as the episodes played in order in this process."""
    from cof_gym.commands import evaluate as ev

    monkeypatch.setattr(ev, "QUEUED_PER_WORKER", 1)
    suite = make_suite("default", 2, seed=7)
    agents = ["staircase", "interrogator"]
    one = evaluate(agents, suite, tmp_path / "one", seed=7, quiet=True, workers=1)
    two = evaluate(agents, suite, tmp_path / "two", seed=7, quiet=True, workers=2)
    assert "no worker processes here" not in capsys.readouterr().err  # two workers played (no fallback)
    assert one["summary"] == two["summary"] and one["traces"] == two["traces"]
    for name in ("episodes.csv", "summary.md", "summary.json"):
        assert (tmp_path / "one" / name).read_bytes() == (tmp_path / "two" / name).read_bytes(), name


def test_windows_csv_holds_every_episodes_steps_and_changes_nothing_else(tmp_path: Path) -> None:
    """--windows: windows.csv has a row per step of each episode, the last holding the estimate the episode scored,
    its rewards summing to the episode's return and its driven windows those the record counted (a stop drives none);
    the same bytes from two workers as from one; the other outputs are those of a run without it."""
    from cof_gym.commands.evaluate import WINDOW_COLUMNS

    suite = make_suite("default", 2, seed=3)
    agents = ["staircase", "phase-rule"]
    plain = evaluate(agents, suite, tmp_path / "plain", seed=3, quiet=True, workers=1)
    one = evaluate(agents, suite, tmp_path / "one", seed=3, quiet=True, workers=1, windows=True)
    two = evaluate(agents, suite, tmp_path / "two", seed=3, quiet=True, workers=2, windows=True)
    assert not (tmp_path / "plain" / "windows.csv").exists()
    assert (tmp_path / "one" / "windows.csv").read_bytes() == (tmp_path / "two" / "windows.csv").read_bytes()
    for name in ("episodes.csv", "summary.md", "summary.json"):
        assert (tmp_path / "plain" / name).read_bytes() == (tmp_path / "one" / name).read_bytes(), name
    assert plain["traces"] == one["traces"] == two["traces"]
    with open(tmp_path / "one" / "windows.csv", newline="") as f:
        reader = csv.DictReader(f)
        assert tuple(reader.fieldnames) == WINDOW_COLUMNS
        windows = list(reader)
    with open(tmp_path / "one" / "episodes.csv", newline="") as f:
        episodes = list(csv.DictReader(f))
    assert len(episodes) == 4 and len(windows) == sum(int(e["steps"]) for e in episodes)
    for e in episodes:
        mine = [w for w in windows if (w["agent"], w["episode"]) == (e["agent"], e["episode"])]
        assert [int(w["step"]) for w in mine] == list(range(1, int(e["steps"]) + 1))
        assert {w["seed"] for w in mine} == {e["seed"]} and float(mine[-1]["estimate"]) == float(e["estimate"])
        assert all(float(w["cof"]) == float(e["cof"]) for w in mine)
        assert sum(float(w["reward"]) for w in mine) == float(e["episode_return"])  # the same sum, in the same order
        drove = [w["drove_window"] == "True" for w in mine]
        # every step but the last drove a window; a stop drives none (a horizon's last step may be a stop too)
        assert all(drove[:-1]) and (e["ended"] != "stop" or not drove[-1])
        assert sum(float(w["t"]) - float(p["t"]) > 0 for p, w in zip(mine, mine[1:])) == sum(drove[1:])
    assert {e["ended"] for e in episodes} >= {"stop"}  # the stop's row is seen
    assert {w["lower_bound_in_flight"] for w in windows} == {""}  # neither agent holds a bound in flight


class _BoundAgent(PracticalStaircase):
    """The staircase reporting a given in-flight lower bound after every action."""

    bound: object = 0.1

    def in_flight_lower_bound(self):
        return self.bound


@pytest.mark.parametrize("bound", [0.1, math.nan, -0.1, "high"])
def test_a_step_records_the_in_flight_bound_the_agent_held_and_refuses_a_bad_one(bound) -> None:
    """windows.csv's lower_bound_in_flight is what the agent reported after choosing the step's action; a NaN, a
    non-positive or non-numeric report is the agent's error, one line naming it, the step and the episode."""
    from cof_gym.commands.evaluate_episodes import AgentError

    env = gym.make("CofGym/TorqueInterrogation-v2")
    agent = _BoundAgent(limits_of(env))
    agent.bound = bound
    steps: list = []
    if bound == 0.1:
        record = run_episode(env, agent, 4, {}, 0, steps_out=steps)
        assert len(steps) == record.steps and all(row["lower_bound_in_flight"] == 0.1 for row in steps)
    else:
        with pytest.raises(AgentError, match=r"reported in flight at step 0 in episode 0 \(seed 4\)"):
            run_episode(env, agent, 4, {}, 0, steps_out=steps)
    record = run_episode(env, agent, 4, {}, 0)  # without steps_out the bound is not asked for
    assert record.steps > 0
    env.close()


def test_the_learned_interrogator_holds_a_bound_in_flight_in_windows_csv() -> None:
    """The shipped interrogator reports a calibrated lower bound in flight once its climb has read windows: the
    step rows carry it, a positive CoF, beside the estimate the step acted on."""
    env = gym.make("CofGym/TorqueInterrogation-v2")
    agent = registry.make_agent("interrogator", env)
    steps: list = []
    run_episode(env, agent, 0, {}, 0, steps_out=steps)
    bounds = [row["lower_bound_in_flight"] for row in steps]
    assert bounds[0] is None  # the reset window alone: no estimate in flight yet
    assert any(b is not None for b in bounds) and all(b > 0.0 for b in bounds if b is not None)
    env.close()


def test_where_no_worker_process_can_start_the_episodes_are_played_here(tmp_path: Path, monkeypatch, capsys) -> None:
    import concurrent.futures

    def unavailable(*args, **kwargs):
        raise OSError(38, "Function not implemented")  # what a machine without /dev/shm answers

    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", unavailable)
    suite = make_suite("default", 2, seed=7)
    here = evaluate(["staircase"], suite, tmp_path / "here", seed=7, quiet=True, workers=2)
    assert "no worker processes here" in capsys.readouterr().err
    one = evaluate(["staircase"], suite, tmp_path / "one", seed=7, quiet=True, workers=1)
    assert here["summary"] == one["summary"]


def test_default_workers_give_each_enough_episodes_and_memory_and_never_exceed_the_cores(monkeypatch) -> None:
    from cof_gym.commands import evaluate_workers as ev

    monkeypatch.setattr(ev, "usable_cores", lambda: 8)
    monkeypatch.setattr(ev, "available_memory_bytes", lambda: 100 * ev.WORKER_MEMORY_BYTES)
    n = ev.EPISODES_PER_WORKER
    assert ev.default_workers(1) == 1 and ev.default_workers(2 * n - 1) == 1 and ev.default_workers(2 * n) == 2
    assert ev.default_workers(10**6) == 8
    monkeypatch.setattr(ev, "available_memory_bytes", lambda: 3 * ev.WORKER_MEMORY_BYTES + 1)
    assert ev.default_workers(10**6) == 3
    monkeypatch.setattr(ev, "available_memory_bytes", lambda: ev.WORKER_MEMORY_BYTES // 2)
    assert ev.default_workers(10**6) == 1
    monkeypatch.setattr(ev, "available_memory_bytes", lambda: None)  # unreadable: the cores decide
    assert ev.default_workers(10**6) == 8


def test_workers_beyond_the_usable_cores_are_noted_and_still_started(monkeypatch, tmp_path, capsys) -> None:
    """--workers N is honoured as asked, but N processes on fewer cores share them and each starts on its own: the
    CLI says so in one line on stderr; at most one worker an episode is started, so one that fits says nothing."""
    from cof_gym.cli import main
    from cof_gym.commands import evaluate_workers as ev

    monkeypatch.setattr(ev, "usable_cores", lambda: 2)
    assert ev.oversubscription_note(2, 100) is None and ev.oversubscription_note(8, 2) is None
    note = ev.oversubscription_note(8, 3)
    assert note.startswith("note: --workers 8 starts 3 processes on the 2 usable core(s)") and "\n" not in note
    monkeypatch.setattr(ev, "usable_cores", lambda: 1)
    assert main(["evaluate", "--agents", "oracle", "--episodes", "2", "--workers", "2", "-q",
                 "--out", str(tmp_path / "ev")]) == 0
    assert capsys.readouterr().err.startswith("note: --workers 2 starts 2 processes on the 1 usable core(s)")


def test_usable_cores_honour_a_containers_cpu_quota(monkeypatch) -> None:
    from cof_gym.commands import evaluate_workers as ev

    monkeypatch.setattr(ev.os, "sched_getaffinity", lambda pid: set(range(64)), raising=False)
    files = {"/sys/fs/cgroup/cpu.max": "250000 100000\n"}
    monkeypatch.setattr(ev, "_read", lambda path: files.get(path, ""))
    assert ev.usable_cores() == 3  # 2.5 cores of quota
    files["/sys/fs/cgroup/cpu.max"] = "max 100000\n"
    assert ev.usable_cores() == 64
    files["/proc/meminfo"] = "MemTotal:  8000 kB\nMemAvailable:    2048 kB\n"
    assert ev.available_memory_bytes() == 2048 * 1024


def test_evaluate_from_python_checks_its_arguments_before_playing_and_never_replaces_other_files(tmp_path) -> None:
    """The CLI checked these; a script calling evaluate() lost a directory of its own files to the output."""
    suite = make_suite("default", 1, 0)
    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("keep me\n")
    with pytest.raises(ValueError, match="mine exists and is not a cof-gym evaluate output"):
        evaluate(["staircase"], suite, foreign, 0, quiet=True)
    assert (foreign / "notes.txt").read_text() == "keep me\n"
    (tmp_path / "a_file").write_text("x")
    for agents, the_suite, out, seed, fragment in (
            (["staircase"], suite, tmp_path / "a_file", 0, "a_file"),
            ("staircase", suite, tmp_path / "o", 0, "agent_specs must be a list of agent names"),
            (["staircase"], replace(suite, episodes=[]), tmp_path / "o", 0, "has no episodes to play"),
            (["staircase"], suite, tmp_path / "o", -1, "seed must be an integer in"),
            (["staircase"], suite, tmp_path / "o", float("nan"), "seed must be an integer in")):
        with pytest.raises(ValueError, match=fragment):
            evaluate(agents, the_suite, out, seed, quiet=True)
    assert not (tmp_path / "o").exists() and (tmp_path / "a_file").read_text() == "x"
    for n_episodes, seed, fragment in ((-1, 0, "n_episodes"), (0, 0, "n_episodes"), (float("nan"), 0, "n_episodes"),
                                       (2, -1, "seed"), (True, 0, "n_episodes")):
        with pytest.raises(SuiteError, match=f"{fragment} must be an integer in"):
            make_suite("default", n_episodes, seed)


@pytest.mark.parametrize("spec", [None, 3, ["staircase"]])
def test_an_agent_named_by_anything_but_a_string_is_refused_in_words(spec) -> None:
    with pytest.raises(registry.AgentSpecError, match="an agent is named by a string"):
        registry.parse(spec)
    with pytest.raises(ValueError, match="env must be a cof_gym env"):
        registry.make_agent("staircase", None)


def test_bad_agent_and_suite_names_raise(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="agent"):
        evaluate(["oracle-of-delphi"], make_suite("default", 1, 0), tmp_path, 0, quiet=True)
    with pytest.raises(ValueError, match="suite"):
        make_suite("no-such-suite", 1, 0)


def test_a_one_rollout_training_run_loads_in_evaluate(tmp_path: Path) -> None:
    """One short rollout (64 steps) and its update with the shipped hyperparameters otherwise, saved and played."""
    from cof_gym.commands.train import build_parser, run

    out = tmp_path / "run"
    args = build_parser().parse_args(["--env", WAGON, "--timesteps", "64", "--n-envs", "1", "--seed", "1",
                                      "--hyperparams", "n_steps:64", "batch_size:32",
                                      "--action-adapter", "incremental", "--eval-freq", "0", "--save-freq", "0",
                                      "--no-progress", "--out", str(out)])
    assert run(args) == 0
    result = evaluate([f"ppo:{out}"], make_suite("default", 2, seed=0), tmp_path / "eval", seed=0, quiet=True)
    (name,) = result["summary"]
    assert name.startswith("ppo") and result["summary"][name]["episodes"] == 2


def test_every_agent_reports_a_finite_scored_estimate_at_the_corners_of_what_the_task_accepts(tmp_path: Path) -> None:
    """Scenarios at the ends of every accepted range (the CoF envelope, the speeds, noise 3 x full scale, a 0.1 s
    drive lag, each systematic error at its accepted limit) on tabulated curves none of the agents was built for
    (a peak at 0.05 % creepage falling to nothing, a peak at 150 % creepage): every default agent plays every
    episode to a finite estimate that the task scores."""
    from cof_gym.physics.creep_laws import MAX_CREEPAGE
    from cof_gym.task.scenarios import COF_ENVELOPE, MOTOR_LAG_MAX_S, NOISE_LEVEL_MAX, SPEED_ENVELOPE_M_S
    from cof_gym.task.sensors import SYSTEMATIC_ERRORS

    sharp = {"table": {"creepage": [0.0, 0.0002, 0.0005, 0.002, 0.02], "adhesion_ratio": [0.0, 0.9, 1.0, 0.3, 0.0]}}
    far = {"table": {"creepage": [0.0, 0.01, 0.75 * MAX_CREEPAGE], "adhesion_ratio": [0.0, 0.2, 1.0]}}
    corners = [
        dict(cof=COF_ENVELOPE[0], condition="low_adhesion", speed_m_s=SPEED_ENVELOPE_M_S[0], load_case="empty",
             noise_level=NOISE_LEVEL_MAX, motor_lag_s=MOTOR_LAG_MAX_S, creep_law=sharp,
             **{name: r.accepted for name, r in SYSTEMATIC_ERRORS.items()}),
        dict(cof=COF_ENVELOPE[1], condition="dry", speed_m_s=SPEED_ENVELOPE_M_S[1], load_case="laden",
             noise_level=0.0, motor_lag_s=0.0, creep_law=far,
             **{name: -r.accepted for name, r in SYSTEMATIC_ERRORS.items()}),
    ]
    suite_file = tmp_path / "corners.json"
    suite_file.write_text(json.dumps({"env_id": "CofGym/TorqueInterrogation-v2", "episodes": [
        {"seed": i, "options": options} for i, options in enumerate(corners)]}))
    agents = registry.default_agents()
    evaluate(agents, make_suite(str(suite_file), len(corners), seed=0), tmp_path / "out", seed=0, quiet=True)
    rows = list(csv.DictReader(open(tmp_path / "out" / "episodes.csv")))
    assert sorted({r["agent"] for r in rows}) == sorted(agents) and len(rows) == len(agents) * len(corners)
    for r in rows:
        assert r["scored"] == "True" and math.isfinite(float(r["estimate"])) and float(r["estimate"]) > 0, r


def test_run_episode_records_the_ground_truth_it_was_given() -> None:
    env = gym.make(WAGON)
    rec = run_episode(env, PracticalStaircase(limits_of(env)), 3, {"cof": 0.25, "condition": "wet"}, 0)
    assert rec.cof == 0.25 and rec.condition == "wet" and rec.steps >= 1
    assert 0.0 <= rec.relative_error <= 1.0 and np.isfinite(rec.episode_return)


class _StopsAt:
    """Holds one DC torque (the action's [-1, 1]) and asks to stop at its ``stop_step``-th step (None: never)."""

    oracle = False

    def __init__(self, dc: float, stop_step: int | None) -> None:
        self.name, self.dc, self.stop_step = "stops-at", dc, stop_step

    def reset(self, observation, info) -> None:
        self.step = 0

    def act(self, observation, info) -> np.ndarray:
        self.step += 1
        return np.array([self.dc, 0.0, 0.0, 0.0, 1.0 if self.step == self.stop_step else -1.0], dtype=np.float32)


@pytest.mark.parametrize("dc, stop_step, cof, ended, steps", [
    (-1.0, 1, 0.3, "stop", 1),  # asks at once
    (-1.0, 2, 0.3, "stop", 2),  # asks before its last step
    (-1.0, 3, 0.3, "horizon", 3),  # asks at its last step: it used every window it had
    (-1.0, None, 0.3, "horizon", 3),  # never asks: the task's max_windows end the episode
    (1.0, None, 0.02, "macro-slip", None),  # the drive's maximum at the lowest CoF
])
def test_a_record_says_how_its_episode_ended(dc: float, stop_step: int | None, cof: float, ended: str,
                                             steps: int | None) -> None:
    from cof_gym.commands.evaluate_episodes import ENDINGS

    env = gym.make("CofGym/TorqueInterrogation-v2", max_windows=3)
    rec = run_episode(env, _StopsAt(dc, stop_step), 0, {"cof": cof, "condition": "low_adhesion"}, 0)
    assert rec.ended == ended and rec.ended in ENDINGS and rec.macro_slip == (ended == "macro-slip")
    assert steps is None or rec.steps == steps


@pytest.mark.parametrize("stop_step", [1, 3, None])
def test_a_record_counts_each_driven_window_once(stop_step: int | None) -> None:
    """Energy and comfort come from the windows the agent drove: a stop runs none (the env's info repeats the last
    window's readings, which are not counted again), and an agent that stops at once drove none (zeros)."""
    env = gym.make("CofGym/TorqueInterrogation-v2", max_windows=4)
    options = {"cof": 0.3, "condition": "low_adhesion"}
    agent = _StopsAt(-0.7, stop_step)  # 43 % of the saturation torque: no macro-slip
    rec = run_episode(env, agent, 0, options, 0)
    obs, info = env.reset(seed=0, options=options)
    agent.reset(obs, info)
    driven = []
    while True:
        obs, _, terminated, truncated, info = env.step(agent.act(obs, info))
        if terminated or truncated:
            break
        driven.append(info)
    if stop_step is None:
        driven.append(info)  # the horizon's last step drove its window
    assert len(driven) == {1: 0, 3: 2, None: 4}[stop_step]
    gt = [d["ground_truth"] for d in driven]
    assert rec.friction_energy_j == sum(g["friction_energy_j"] for g in gt)
    assert rec.slip_energy_j == sum(g["energy_past_peak_j"] for g in gt)
    wd = [d["measurement"]["wd_rms_m_s2"] for d in driven]
    assert rec.wd_rms_m_s2 == (math.sqrt(sum(w ** 2 for w in wd) / len(wd)) if wd else 0.0)
    assert (rec.friction_energy_j > 0.0) == bool(driven) and (rec.wd_rms_m_s2 > 0.0) == bool(driven)


class _InfoSpy:
    """Records the info dicts it is handed; stops at once with no DC torque."""

    def __init__(self, oracle: bool) -> None:
        self.name, self.oracle, self.infos = f"spy-{oracle}", oracle, []

    def reset(self, observation, info) -> None:
        self.infos.append(info)

    def act(self, observation, info) -> np.ndarray:
        self.infos.append(info)
        return np.array([-1.0, 0.0, 0.0, 0.0, 1.0], dtype=np.float32)


def test_only_oracle_agents_receive_the_ground_truth() -> None:
    from cof_gym.commands.evaluate import build_agents

    env = gym.make(cof_gym.WAGON_V1_ENV_ID)
    for oracle in (False, True):
        spy = _InfoSpy(oracle)
        rec = run_episode(env, spy, 3, {"cof": 0.25}, 0)
        assert len(spy.infos) >= 2  # reset and at least one step
        assert all(("ground_truth" in info) == oracle for info in spy.infos)
        assert all("measurement" in info for info in spy.infos[1:])
        assert rec.cof == pytest.approx(0.25) and rec.oracle == oracle  # the evaluator still scores
    # the registry's flag decides: staircase-paper is the only oracle among the built-in agents
    flags = {agent.name: oracle for agent, oracle in build_agents(["staircase", "staircase-paper"], env)}
    assert flags == {"staircase": False, "staircase-paper": True}
    env.close()


def test_a_new_agent_is_one_registry_line() -> None:
    from cof_gym.agents import registry

    registry.register("test-staircase", "cof_gym.agents.staircase:PracticalStaircase", oracle=False, default=False)
    try:
        assert "test-staircase" in registry.names() and "test-staircase" not in registry.default_agents()
        env = gym.make(cof_gym.WAGON_V1_ENV_ID)
        assert isinstance(registry.make_agent("test-staircase", env), PracticalStaircase)
        env.close()
        with pytest.raises(registry.AgentSpecError, match="unknown agent"):
            registry.parse("no-such-agent")
    finally:
        del registry.AGENTS["test-staircase"]



def test_every_registered_agent_is_built_with_its_registry_name_and_oracle_flag() -> None:
    """The registry's name and oracle flag are what evaluate groups and shields the ground truth by; the agent's own
    name and flag (which run_episode reads when it is given none) must say the same, for every agent a name builds."""
    from cof_gym.agents import registry

    env = gym.make(cof_gym.WAGON_ENV_ID)
    built = {name: registry.make_agent(name, env) for name, entry in registry.AGENTS.items()
             if not entry.needs_argument and entry.available() and entry.shipped_available()}
    env.close()
    assert {"oracle", "staircase-paper", "phase-rule", "model-based-zeroed", "interrogator"} <= set(built)
    assert {name: (agent.name, bool(agent.oracle)) for name, agent in built.items()} == {
        name: (name, registry.AGENTS[name].oracle) for name in built}

def _records(path: Path) -> list:
    """episodes.csv rows with the fields the breakdown groups by, as numbers where they are numbers."""
    from dataclasses import fields
    from types import SimpleNamespace

    from cof_gym.commands.evaluate_episodes import EpisodeRecord

    numeric = {f.name for f in fields(EpisodeRecord) if f.type in ("float", float)}
    return [SimpleNamespace(**{k: float(v) if k in numeric else v for k, v in row.items()})
            for row in csv.DictReader(open(path))]


def test_summary_has_the_breakdown_and_the_intrusiveness_figure(tmp_path: Path) -> None:
    result = evaluate(["staircase"], make_suite("default", 4, seed=2), tmp_path / "ev", seed=2, quiet=True)
    groups = result["summary"]["staircase"]["breakdown"]
    conditions = {r["condition"] for r in csv.DictReader(open(tmp_path / "ev" / "episodes.csv"))}
    assert conditions <= set(groups) and any(g.startswith("CoF ") for g in groups)
    assert sum(groups[c]["episodes"] for c in conditions) == 4
    assert sum(v["episodes"] for g, v in groups.items() if g.startswith("CoF ")) == 4
    for name, key, _ in GROUPINGS:  # every grouping partitions the episodes
        labels = {key(r) for r in _records(tmp_path / "ev" / "episodes.csv")}
        if len(labels) > 1 or name in ("condition", "CoF band"):
            assert sum(groups[g]["episodes"] for g in labels) == 4, name
    assert any(g.startswith("committed at") for g in groups) or len(
        {utilisation_band(float(r["peak_torque_fraction"])) for r in csv.DictReader(open(tmp_path / "ev" / "episodes.csv"))}) == 1
    assert "By condition, CoF band, creep-law family" in (tmp_path / "ev" / "summary.md").read_text()
    assert 0.0 < result["summary"]["staircase"]["peak_torque_fraction"]["value"] < 5.0
    assert (tmp_path / "ev" / "error_vs_peak_torque.png").stat().st_size > 1000


def test_a_breakdown_row_counts_each_agents_episodes_where_they_differ() -> None:
    """A scenario group has the same episodes for every agent (one count beside the group); a utilisation group
    depends on what each agent did, so each cell carries its agent's own count and the group none."""
    from cof_gym.commands.evaluate_tables import markdown_breakdown

    def stats(n: int) -> dict:
        return {"episodes": n, "median_error": 0.01, "p90_error": 0.02, "macro_slip_events": 0,
                "peak_torque_fraction": 0.9}

    summary = {"b": {"oracle": False, "breakdown": {"dry": stats(3), "committed at > 95 % M_sat": stats(3)}},
               "a": {"oracle": False, "breakdown": {"dry": stats(3), "committed at <= 80 % M_sat": stats(2),
                                                    "committed at > 95 % M_sat": stats(1)}}}
    lines = [line for line in markdown_breakdown(summary).splitlines() if line.startswith("| ")]
    rows = {line.split(" | ")[0]: line for line in lines}
    assert rows["| dry (3)"].count("(n=") == 0
    assert rows["| committed at <= 80 % M_sat"].endswith("| - | 1.0 % / 2.0 % / 0 / 90.0 % (n=2) |")
    assert rows["| committed at > 95 % M_sat"].endswith("90.0 % (n=3) | 1.0 % / 2.0 % / 0 / 90.0 % (n=1) |")
    # the bands in their order, though the first agent has only the highest
    assert [line.split(" | ")[0] for line in lines[1:]] == ["| dry (3)", "| committed at <= 80 % M_sat",
                                                             "| committed at > 95 % M_sat"]


def test_the_breakdown_keeps_the_bands_order_where_no_agent_has_two_of_them() -> None:
    """Two agents that share no utilisation band and no ending: the rows still follow the bands' and the
    endings' order (not the order in which the agents first showed them)."""
    from cof_gym.commands.evaluate_tables import markdown_breakdown

    stats = {"episodes": 1, "median_error": 0.01, "p90_error": 0.02, "macro_slip_events": 0,
             "peak_torque_fraction": 0.9}
    summary = {"a": {"oracle": False, "breakdown": {"dry": stats, "committed at 90-95 % M_sat": stats,
                                                    "ended: macro-slip": stats}},
               "b": {"oracle": False, "breakdown": {"dry": stats, "committed at 80-90 % M_sat": stats,
                                                    "ended: stop": stats}}}
    groups = [line.split(" | ")[0] for line in markdown_breakdown(summary).splitlines()[4:]]
    assert groups == ["| dry (1)", "| committed at 80-90 % M_sat", "| committed at 90-95 % M_sat", "| ended: stop",
                      "| ended: macro-slip"]


@pytest.mark.parametrize("block_values", [1 << 22, 7])
def test_the_bootstrap_computes_each_resamples_statistic_as_for_that_resample_alone(block_values: int,
                                                                                  monkeypatch) -> None:
    """Rows of resamples reduced at once (in blocks of rows) give every resample's statistic as the resample alone
    gives it: order statistics exactly; a sum or a mean of these positive values within what two summation orders
    can differ by, 2 (n - 1) eps relative (each is within (n - 1) eps of the exact sum)."""
    from cof_gym.commands import evaluate_stats as ev

    monkeypatch.setattr(ev, "BOOTSTRAP_BLOCK_VALUES", block_values)
    values = np.random.default_rng(3).lognormal(-3.0, 1.0, 37)
    values[::5] = 1.0  # ties, as the macro-slip column's 100 % gives them
    for _, _, _, stat, _ in ev.METRICS:
        lo, hi = ev.bootstrap_ci(values, stat, np.random.default_rng(11), n=301)
        idx = np.random.default_rng(11).integers(0, len(values), size=(301, len(values)))
        alone = np.array([stat(values[i]) for i in idx])
        expected = np.percentile(alone, 2.5), np.percentile(alone, 97.5)
        if stat in (np.sum, np.mean):
            np.testing.assert_allclose((lo, hi), expected, rtol=2 * len(values) * np.finfo(float).eps)
        else:
            assert (lo, hi) == expected, stat


def test_peak_creepage_bands_cover_every_creepage_once() -> None:
    assert [peak_creepage_band(c) for c in (0.0, 0.0099, 0.01, 0.03, 0.04, 0.5)] == [
        "peak creepage < 1 %", "peak creepage < 1 %", "peak creepage 1-2 %", "peak creepage 2-4 %",
        "peak creepage 4+ %", "peak creepage 4+ %"]


def test_utilisation_bands_read_as_their_labels_and_no_band_takes_a_nan() -> None:
    """The issue's bands (<= 80, 80-90, 90-95, > 95 %): 80 % exactly is "<= 80" (it was "80-90"), 95 % is "90-95"."""
    assert [utilisation_band(f) for f in (0.0, 0.5, 0.8, 0.8000001, 0.9, 0.95, 0.9500001, 1.3)] == [
        "committed at <= 80 % M_sat", "committed at <= 80 % M_sat", "committed at <= 80 % M_sat",
        "committed at 80-90 % M_sat", "committed at 80-90 % M_sat", "committed at 90-95 % M_sat",
        "committed at > 95 % M_sat", "committed at > 95 % M_sat"]
    for band, value in ((utilisation_band, math.nan), (peak_creepage_band, math.nan), (peak_creepage_band, -0.01)):
        with pytest.raises(ValueError, match="lies in no band"):
            band(value)


def test_statistics_refuse_a_nan_rather_than_report_one() -> None:
    from cof_gym.commands.evaluate_stats import paired_differences

    base, other, returns = np.array([0.1, np.nan, 0.3, 0.4]), np.array([0.1, 0.1, 0.4, 0.3]), np.zeros(4)
    with pytest.raises(ValueError, match="finite errors and returns"):
        paired_differences(base, other, returns, returns)
    from cof_gym.commands.evaluate_stats import summarize

    env = gym.make(cof_gym.WAGON_ENV_ID, max_windows=3, max_episode_steps=3)
    record = run_episode(env, registry.make_agent("staircase", env), 5, {"cof": 0.1}, 0)
    assert summarize([record, replace(record, episode=1)], 0)["staircase"]["episodes"] == 2
    with pytest.raises(ValueError, match=r"staircase: episode 1 has relative_error nan"):
        summarize([record, replace(record, episode=1, relative_error=math.nan)], 0)


def test_a_record_carries_the_true_curves_peak_creepage() -> None:
    env = gym.make(cof_gym.WAGON_ENV_ID)
    _, info = env.reset(seed=5, options={"cof": 0.1})
    record = run_episode(env, registry.make_agent("staircase", env), 5, {"cof": 0.1}, 0)
    assert record.peak_creepage == info["ground_truth"]["peak_creepage"] > 0.0  # the same draw: seeded


def test_breakdown_groups_by_the_suite_files_episode_notes(tmp_path: Path) -> None:
    spec = {"episodes": [{"seed": 3, "options": {"cof": 0.2}, "note": "steep"},
                         {"seed": 4, "options": {"cof": 0.3}, "note": "steep"},
                         {"seed": 5, "options": {"cof": 0.25}, "note": "flat"}]}
    (tmp_path / "s.json").write_text(json.dumps(spec))
    suite = make_suite(str(tmp_path / "s.json"), 60, 0)
    assert [suite.note(i) for i in range(3)] == ["steep", "steep", "flat"]
    result = evaluate(["staircase"], suite, tmp_path / "ev", seed=0, quiet=True)
    groups = result["summary"]["staircase"]["breakdown"]
    assert groups["note steep"]["episodes"] == 2 and groups["note flat"]["episodes"] == 1
    assert [r["note"] for r in csv.DictReader(open(tmp_path / "ev" / "episodes.csv"))] == ["steep", "steep", "flat"]
    assert make_suite("default", 2, 0).note(1) == ""


def test_a_suite_note_that_is_not_a_string_is_named(tmp_path: Path) -> None:
    (tmp_path / "s.json").write_text(json.dumps({"episodes": [{"seed": 3, "note": 7}]}))
    with pytest.raises(SuiteError, match=r"episodes\[0\]\.note must be a string"):
        make_suite(str(tmp_path / "s.json"), 60, 0)


def test_a_suite_keeps_the_interface_the_agents_act_through(tmp_path: Path) -> None:
    """env_kwargs that would change the agents' actions or info, or end episodes before the task's horizon
    scores them, are refused when the file is read; the env's defaults, no TimeLimit (-1) and a TimeLimit at
    or beyond the horizon are not."""
    def suite(env_kwargs):
        (tmp_path / "s.json").write_text(json.dumps({"env_kwargs": env_kwargs}))
        return make_suite(str(tmp_path / "s.json"), 2, 0)

    for env_kwargs in ({"action_type": "absolute", "excitation": "sine", "info_layout": "nested"},
                       {"max_episode_steps": -1}, {"max_episode_steps": 30}, {"max_episode_steps": 50},
                       {"max_windows": 40}, {"max_windows": 10, "max_episode_steps": 10}):
        assert suite(env_kwargs).env_kwargs == env_kwargs
    for env_kwargs, message in (
            ({"action_type": "relative"}, "env_kwargs.action_type must be 'absolute' (.*), got 'relative'"),
            ({"excitation": "multitone"}, "env_kwargs.excitation must be 'sine' (.*), got 'multitone'"),
            ({"info_layout": "flat"}, "env_kwargs.info_layout must be 'nested' (.*), got 'flat'"),
            ({"max_episode_steps": 3}, "env_kwargs.max_episode_steps must be -1 .* max_windows=30 .*, got 3$"),
            ({"max_windows": 40, "max_episode_steps": None}, "max_windows=40 .*, got None$"),  # the spec's 30
            ({"max_episode_steps": True},
             r"env_kwargs.max_episode_steps must be an integer \(-1: no TimeLimit\), got True"),
            ({"max_episode_steps": 1.5}, r"must be an integer \(-1: no TimeLimit\), got 1.5"),
            ({"max_episode_steps": 0}, "must be -1 .*, got 0$"), ({"max_episode_steps": -5}, "must be -1 .*, got -5$"),
            ({"vehicle": "half_wheelset"}, "env_kwargs.vehicle is the env id's own"),
            ({"task_version": 1},
             r"env_kwargs.task_version is the env id's own \(CofGym/TorqueInterrogation-v2 is made with "
             r"task_version=2\)")):
        with pytest.raises(SuiteError, match=message):
            suite(env_kwargs)


def test_a_suite_file_that_names_a_key_twice_or_renders_is_refused(tmp_path: Path) -> None:
    """A repeated key would keep its last value silently; a render mode would open windows in every worker."""
    (tmp_path / "s.json").write_text('{"options": {"cof": 0.3, "cof": 0.2}}')
    with pytest.raises(SuiteError, match=r"s\.json: key 'cof' given twice in one object"):
        make_suite(str(tmp_path / "s.json"), 2, 0)
    (tmp_path / "s.json").write_text(json.dumps({"env_kwargs": {"render_mode": "human"}}))
    with pytest.raises(SuiteError, match=r"env_kwargs\.render_mode must be None \(evaluation renders nothing"):
        make_suite(str(tmp_path / "s.json"), 2, 0)
    # a note is a row label of summary.md's tables: a '|' or a line break split the row, a blank one made a group
    for note in ("a|b", "c\nd", "  "):
        (tmp_path / "s.json").write_text(json.dumps({"episodes": [{"seed": 1, "note": note}]}))
        with pytest.raises(SuiteError, match=r"episodes\[0\]\.note must be a string of one line without '\|'"):
            make_suite(str(tmp_path / "s.json"), 2, 0)
    # the same seed and options twice: one episode counted twice (zero-width intervals)
    (tmp_path / "s.json").write_text(json.dumps({"episodes": [{"seed": 7, "options": {"cof": 0.2}}, {"seed": 8},
                                                              {"seed": 7, "options": {"cof": 0.2}}]}))
    with pytest.raises(SuiteError, match=r"episodes\[2\] repeats episodes\[0\] \(the same seed and options\)"):
        make_suite(str(tmp_path / "s.json"), 2, 0)
    # an integer beyond Python's str -> int digit limit was a traceback
    (tmp_path / "s.json").write_text('{"options": {"cof": 1' + "0" * 5000 + "}}")
    with pytest.raises(SuiteError, match=r"s\.json: cannot be read as JSON \(Exceeds the limit"):
        make_suite(str(tmp_path / "s.json"), 2, 0)


def test_a_listed_episode_without_a_seed_past_the_largest_seed_names_the_run_seed(tmp_path: Path) -> None:
    from cof_gym.commands.args import MAX_SEED

    (tmp_path / "s.json").write_text(json.dumps({"episodes": [{"seed": 3}, {}]}))
    assert make_suite(str(tmp_path / "s.json"), 2, MAX_SEED - 1).episodes == [(3, {}), (MAX_SEED, {})]
    with pytest.raises(SuiteError, match=r"episodes\[1\] has no seed of its own.*give a smaller --seed"):
        make_suite(str(tmp_path / "s.json"), 2, MAX_SEED)


def test_a_suite_files_options_are_checked_before_any_env_is_built(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setattr(gym, "make", lambda *a, **k: pytest.fail("an env was built"))
    episodes = [{"seed": i, "options": {"cof": 0.3}} for i in range(60)] + [{"seed": 60, "options": {"cof": "0.2"}}]
    (tmp_path / "s.json").write_text(json.dumps({"episodes": episodes}))
    with pytest.raises(SuiteError, match=r"s\.json: episode 60 \(options \{'cof': '0\.2'\}\): cof must be a number"):
        make_suite(str(tmp_path / "s.json"), 2, 0)
    (tmp_path / "s.json").write_text(json.dumps({"options": {"noise_level": -1}}))
    with pytest.raises(SuiteError, match=r"options \{'noise_level': -1\}: noise_level must be a finite number"):
        make_suite(str(tmp_path / "s.json"), 2, 0)
    # an episode's long options (a table of 64 points) are cut in the message, the fault named in full
    ratio = [i / 63 for i in range(64)]
    ratio[40] = ratio[39]
    table = {"creepage": [i / 630 for i in range(64)], "adhesion_ratio": ratio}
    (tmp_path / "s.json").write_text(json.dumps({"episodes": [{"seed": 0, "options": {"creep_law": {"table": table}}}]}))
    with pytest.raises(SuiteError, match=r"episode 0 \(options \{'creep_law'.*\.\.\. \(\d+ characters\)\): "
                       r"creep_law\.table\.adhesion_ratio must rise strictly.*at indices 39 and 40") as raised:
        make_suite(str(tmp_path / "s.json"), 1, 0)
    assert len(str(raised.value)) < 500


def test_configuration_note_names_each_difference_from_the_nearest_trained_world() -> None:
    from cof_gym.agents.base import configuration_note

    assert configuration_note("a", "X", {"counter_torque": True}, "X", ({}, {"counter_torque": True})) is None
    assert configuration_note("a", "X", {}, "X", ({"counter_torque": True},)) == (
        "a is out of its training distribution here: counter_torque='default' (trained: True)")
    assert configuration_note("a", "Y", {"counter_torque": True, "vehicle": "v"}, "X", ({}, {"counter_torque": True})) == (
        "a is out of its training distribution here: env Y (trained: X), vehicle='v' (trained: 'default')")


def test_the_ppo_note_reads_an_argument_equal_to_the_default_as_the_default() -> None:
    """``counter_torque=False`` is the env made without it: no note for the shipped v1 policy; True is a world it
    was not trained in."""
    env = gym.make(cof_gym.WAGON_V1_ENV_ID)
    agent = registry.make_agent("ppo", env)
    assert agent.distribution_note(cof_gym.WAGON_V1_ENV_ID, {"counter_torque": False}, [{}]) is None
    assert "counter_torque=True" in agent.distribution_note(cof_gym.WAGON_V1_ENV_ID, {"counter_torque": True}, [{}])


def test_saturation_oracle_keeps_its_crest_below_the_peak_and_refuses_a_crest_past_it() -> None:
    """The oracle's hold plus its modulation stays below the true saturation torque, so it survives creep
    curves that fall steeply past their peak (there a crest past the peak runs the wheel away); levels
    that put the crest at or past the saturation torque are refused at construction."""
    from cof_gym.agents.oracle import SaturationOracle
    from cof_gym.commands.evaluate_episodes import run_episode
    from cof_gym.commands.suites import make_suite

    suite = make_suite(str(Path(__file__).resolve().parents[1] / "experiments" / "suites"
                           / "v2_validation_steep_grid.json"), 60, 0)
    env = gym.make(suite.env_id, **suite.env_kwargs)
    oracle = SaturationOracle(limits_of(env))
    assert max(oracle.levels) + oracle.amplitude_fraction < 1.0
    for i, (seed, options) in enumerate(suite.episodes[:54:9]):
        record = run_episode(env, oracle, seed, options, i)
        assert not record.macro_slip and record.peak_torque_fraction < 1.0
        assert record.relative_error < 0.05  # the CoA held at 98.5 % of the peak, with the sensors' errors
    with pytest.raises(ValueError, match="levels must lie in"):
        SaturationOracle(limits_of(env), levels=(0.5, 0.995))
    with pytest.raises(ValueError, match="amplitude_fraction"):
        SaturationOracle(limits_of(env), amplitude_fraction=0.0)


def _record(episode: int, error: float, macro_slip: bool = False, scored: bool = True):
    from cof_gym.commands.evaluate_episodes import EpisodeRecord

    return EpisodeRecord(cof=0.2, condition="dry", speed_m_s=10.0, load_case="laden", noise_level=1.0, motor_lag_s=0.0,
                         creep_family="polach", creepage_offset=0.0, peak_creepage=0.01, agent="a", oracle=False,
                         episode=episode, seed=episode, estimate=0.2 * (1 + error), relative_error=error, scored=scored,
                         macro_slip=macro_slip, slip_energy_j=0.0, friction_energy_j=0.0, wd_rms_m_s2=0.01,
                         measurement_time_s=10.0, peak_torque_fraction=0.9, episode_return=-1.0, steps=10,
                         ended="diverged" if not scored else "macro-slip" if macro_slip else "stop")


def test_a_macro_slip_counts_as_a_failed_measurement_in_its_own_metrics_only() -> None:
    from cof_gym.commands.evaluate_stats import METRICS, bootstrap_ci, summarize

    # a runaway's estimate can be accurate (0.5 %): as a measurement it failed
    records = [_record(0, 0.02), _record(1, 0.04), _record(2, 0.005, macro_slip=True), _record(3, 1.0, scored=False)]
    assert [r.error_slip_failed for r in records] == [0.02, 0.04, 1.0, 1.0]
    entry = summarize(records, seed=7)["a"]
    assert entry["median_error_slip_failed"]["value"] == np.median([0.02, 0.04, 1.0, 1.0])
    assert entry["p90_error_slip_failed"]["value"] == np.percentile([0.02, 0.04, 1.0, 1.0], 90)
    assert entry["median_error"]["value"] == np.median([0.02, 0.04, 0.005, 1.0])  # the issue's measure, as before
    # the new metrics come last: every earlier metric's CI is the one drawn without them, in the same order
    rng = np.random.default_rng(7)
    earlier = [m for m in METRICS if not m[0].endswith("_slip_failed")]
    assert [m[0] for m in METRICS[:len(earlier)]] == [m[0] for m in earlier]
    for key, _, column, stat, _ in earlier:
        values = np.array([getattr(r, column) for r in records], dtype=float)
        assert entry[key]["ci95"] == list(bootstrap_ci(values, stat, rng)), key


def test_one_episode_has_no_interval_and_says_so() -> None:
    """A CI of one episode would be [v, v], a certainty one episode does not give: the summary holds None, the tables
    and the paired statistics print ``[-]``, and two episodes have an interval again."""
    from cof_gym.commands.evaluate_stats import METRICS, paired_summary, summarize
    from cof_gym.commands.evaluate_tables import markdown_paired, markdown_table

    one = summarize([_record(0, 0.02)], seed=0)
    assert all(one["a"][key]["ci95"] is None for key, *_ in METRICS)
    assert "| median rel. CoF error [%] | 2.0 [-] |" in markdown_table(one)
    json.dumps(one, allow_nan=False)  # valid JSON: no NaN stands in for the missing bounds
    two = summarize([_record(0, 0.02), _record(1, 0.04)], seed=0)
    assert all(len(two["a"][key]["ci95"]) == 2 for key, *_ in METRICS)
    other = [replace(_record(0, 0.05), agent="b")]
    paired = paired_summary([_record(0, 0.02), *other], "a", seed=0)
    assert all(paired["agents"]["b"][key][1:] == [None, None] for key in ("median", "P90", "return", "lower_error"))
    assert "[-]" in markdown_paired(paired)


@pytest.mark.parametrize("module, name, parameters, fragment", [
    ("phase_rule", "PhaseRule", {"frequency_hz": math.nan}, "PhaseRule.frequency_hz must be a number"),
    ("phase_rule", "PhaseRule", {"frequency_hz": -5.0}, "PhaseRule.frequency_hz must be > 0"),
    ("phase_rule", "PhaseRule", {"baseline_windows": 1.5}, "PhaseRule.baseline_windows must be an integer"),
    ("phase_rule", "PhaseRule", {"corrected_se": 1}, "PhaseRule.corrected_se must be a bool"),
    ("phase_rule", "PhaseRule", {"jump_deg": -math.inf}, "PhaseRule.jump_deg must be finite"),
    ("robust_model", "RobustModel", {"amplitude_ratio": -1.0}, "RobustModel.amplitude_ratio must be > 0"),
    ("robust_model", "RobustModel", {"margin_se": math.inf}, "RobustModel.margin_se must be finite"),
    ("model_based", "ModelBasedAgent", {"ci_tolerance": math.nan}, "ci_tolerance must be a number"),
    ("model_based", "ModelBasedAgent", {"shape_families": ("nope",)}, "shape_families must be"),
    ("staircase", "PracticalStaircase", {"min_stop_creepage": -0.1}, "must be >= 0"),
])
def test_a_hand_built_agent_refuses_a_parameter_that_would_become_a_nan_or_a_clipped_action(module, name, parameters,
                                                                                           fragment) -> None:
    """Before, each was accepted and sent a NaN action mid-episode (or one silently clipped to the drive's range)."""
    limits = gym.make(cof_gym.WAGON_ENV_ID).unwrapped.limits
    with pytest.raises(ValueError, match=re.escape(fragment)):
        registry_free(module, name, limits, **parameters)


def test_a_hand_built_agent_keeps_the_values_its_parameters_may_take() -> None:
    from cof_gym.agents.robust_model import RobustModel
    from cof_gym.agents.staircase import ElasticityClimb

    limits = gym.make(cof_gym.WAGON_ENV_ID).unwrapped.limits
    assert RobustModel(limits, knee_weight=0.0, refine_windows=0).knee_weight == 0.0  # the bracket's lower end
    assert registry_free("phase_rule", "PhaseRule", limits, threshold_rise_deg=math.inf, margin_se=0.0).margin_se == 0
    # the jump test off (select_phase_rule.py records its climbs so, and its rules without a jump test read so)
    assert registry_free("phase_rule", "PhaseRule", limits, jump_deg=math.inf).jump_deg == math.inf
    with pytest.raises(ValueError, match=r"ElasticityClimb.first_fraction must be > 0"):
        ElasticityClimb(first_fraction=0.0)


def registry_free(module: str, name: str, limits, **parameters):
    """``cof_gym.agents.MODULE.NAME(limits, **parameters)``: a hand-built agent made as a user's script makes it."""
    import importlib

    return getattr(importlib.import_module(f"cof_gym.agents.{module}"), name)(limits, **parameters)
