"""Agents of your own in ``cof-gym evaluate`` and ``cof-gym watch`` without registering them: ``py:FILE.py:NAME``
(cof_gym/agents/plugin.py). The file is imported in every worker process, the agent never receives the ground truth,
and every problem found before the first episode is one line with exit status 2."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from cof_gym import cli

AGENT_SOURCE = '''
from cof_gym.task.interface import OBSERVATION_NAMES, encode_action

COA = OBSERVATION_NAMES.index("coa_measured")


class Climb:
    """DC steps of 2 % of the drive's maximum, a stop after four windows reporting the last CoA measured."""

    name = "my-climb"
    oracle = ORACLE

    def __init__(self, limits):
        self.limits = limits

    def reset(self, observation, info):
        self.windows = 0

    def act(self, observation, info):
        if "ground_truth" in info:
            raise RuntimeError("an agent of your own was handed the ground truth")
        self.windows += 1
        return encode_action(0.02 * self.windows * self.limits.max_dc_torque_nm, 200.0, 5.0,
                             max(float(observation[COA]), 0.02), self.windows >= 4, self.limits)
'''


def _write(directory: Path, oracle: bool = False) -> Path:
    path = directory / "my_agents.py"
    path.write_text(AGENT_SOURCE.replace("ORACLE", str(oracle)))
    return path


def test_evaluate_plays_an_agent_of_your_own_in_every_worker(tmp_path: Path, monkeypatch, capsys) -> None:
    _write(tmp_path)
    monkeypatch.chdir(tmp_path)  # a path relative to the working directory, as a user types it
    code = cli.main(["evaluate", "--agents", "staircase,py:my_agents.py:Climb", "--episodes", "4", "--workers", "2",
                     "--env-kwargs", "max_windows:6", "--out", "out", "--quiet"])
    assert code == 0 and "no worker processes here" not in capsys.readouterr().err  # the workers played it
    with open(tmp_path / "out" / "episodes.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["agent"] == "my-climb"]
    assert len(rows) == 4 and all(r["oracle"] == "False" and r["ended"] in ("stop", "macro-slip") for r in rows)


@pytest.mark.parametrize("spec,fragment", [
    ("py:missing.py:Climb", "no such file"),
    ("py:my_agents.py", "expected FILE.py:NAME"),
    ("py:my_agents.py:Nope", "no callable 'Nope'"),
    ("py:broken.py:Climb", "importing"),
    ("py:not_an_agent.py:Thing", "has no reset(observation, info) and act(observation, info)"),
    ("py:oracle_agents.py:Climb", "never reads the ground truth"),
])
def test_a_bad_agent_of_your_own_is_one_line_exit_2_before_any_episode(spec: str, fragment: str, tmp_path: Path,
                                                                      monkeypatch, capsys) -> None:
    _write(tmp_path)
    (tmp_path / "oracle_agents.py").write_text(AGENT_SOURCE.replace("ORACLE", "True"))
    (tmp_path / "broken.py").write_text("raise RuntimeError('boom')\n")
    (tmp_path / "not_an_agent.py").write_text("class Thing:\n    def __init__(self, limits):\n        pass\n")
    monkeypatch.chdir(tmp_path)
    assert cli.main(["evaluate", "--agents", spec, "--episodes", "2", "--out", "out", "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--agents" in err and fragment in err, err
    assert not (tmp_path / "out").exists()


def test_watch_renders_an_agent_of_your_own(tmp_path: Path) -> None:
    path = _write(tmp_path)
    out = tmp_path / "episode.gif"
    argv = ["watch", "--agent", f"py:{path}:Climb", "--seed", "1", "--out", str(out), "--fps", "4", "--width", "320"]
    assert cli.main(argv) == 0
    assert out.stat().st_size > 0


def test_the_example_in_agents_plays_as_its_docstring_says(tmp_path: Path) -> None:
    """agents/lag_rise_example.py, named as its docstring's command names it (from the repository root)."""
    root = Path(__file__).resolve().parents[1]
    example = root / "agents" / "lag_rise_example.py"
    assert "py:agents/lag_rise_example.py:LagRise" in example.read_text()
    code = cli.main(["evaluate", "--agents", f"py:{example}:LagRise", "--episodes", "3", "--out", str(tmp_path / "e"),
                     "--quiet"])
    assert code == 0
    with open(tmp_path / "e" / "episodes.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["agent"] for r in rows] == ["lag-rise"] * 3 and all(r["ended"] != "horizon" for r in rows)


FAILING_AGENTS = '''
import numpy as np


class Short:
    def __init__(self, limits):
        pass

    def reset(self, observation, info):
        pass

    def act(self, observation, info):
        return np.zeros(4, dtype=np.float32)


class Raises:
    def __init__(self, limits):
        pass

    def reset(self, observation, info):
        pass

    def act(self, observation, info):
        raise KeyError("no such reading")
'''


@pytest.mark.parametrize("name,fragment", [("Short", "returned an action the env refuses at step 0 in episode 0"),
                                           ("Raises", "raised in act at step 0 in episode 0 (seed 0): KeyError")])
@pytest.mark.parametrize("command", ["evaluate", "watch"])
def test_an_agent_that_fails_in_an_episode_is_one_line_exit_2_and_writes_nothing(name: str, fragment: str, command: str,
                                                                               tmp_path: Path, capsys) -> None:
    path = tmp_path / "failing.py"
    path.write_text(FAILING_AGENTS)
    out = tmp_path / ("out" if command == "evaluate" else "episode.gif")
    flag = "--agents" if command == "evaluate" else "--agent"
    argv = [command, flag, f"py:{path}:{name}", "--out", str(out)] + (["--episodes", "2", "--quiet"]
                                                                       if command == "evaluate" else [])
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and flag in err and f"agent {name} " in err and fragment in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["failing.py"]


REPORTING_AGENTS = '''
from cof_gym.task.interface import encode_action


class Stops:
    oracle = False

    def __init__(self, limits):
        self.limits = limits

    def reset(self, observation, info):
        pass

    def act(self, observation, info):
        return encode_action(0.0, self.limits.min_amplitude_nm, 5.0, 0.2, True, self.limits)


class NanInterval(Stops):
    def cof_interval(self):
        return (float("nan"), 0.25)


class IntervalRaises(Stops):
    def cof_interval(self):
        raise RuntimeError("no interval")


class BadNotes(Stops):
    def sensor_notes(self):
        return ("a;b",)


class BogusEnv(Stops):
    env_options = {"excitation": "bogus"}


class CloseRaises(Stops):
    def close(self):
        raise RuntimeError("close failed")


class PipeName(Stops):
    name = "bad|name"
'''


@pytest.mark.parametrize("name,fragment,writes", [
    ("NanInterval", "reported after its episode in episode 0 (seed 0): ValueError: NanInterval reported the interval "
                    "(nan, 0.25)", False),
    ("IntervalRaises", "reported after its episode in episode 0 (seed 0): RuntimeError: no interval", False),
    ("BadNotes", "reported after its episode in episode 0 (seed 0): ValueError: BadNotes reported the sensor notes",
     False),
    ("BogusEnv", "its env_options {'excitation': 'bogus'} make no env of CofGym/TorqueInterrogation-v2: excitation "
                 "must be one of", False),
    ("CloseRaises", "raised in close() after the run: RuntimeError: close failed", True),
    ("PipeName", "its name 'bad|name' must be one line without '|'", False),  # a column more in summary.md
])
def test_what_an_agent_reports_or_asks_for_beside_its_actions_fails_in_one_line(name: str, fragment: str, writes: bool,
                                                                               tmp_path: Path, capsys) -> None:
    """Its interval, lower bound and sensor notes after an episode, the env options it asks for and its close():
    each failed with a traceback (a close() after the outputs were written, the summary never printed)."""
    path = tmp_path / "reporting.py"
    path.write_text(REPORTING_AGENTS)
    argv = ["evaluate", "--agents", f"oracle,py:{path}:{name}", "--episodes", "2", "--workers", "1", "--quiet",
            "--out", str(tmp_path / "out")]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--agents" in err and name in err and fragment in err, err
    assert (tmp_path / "out").exists() == writes
