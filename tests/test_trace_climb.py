"""The interrogator's per-window decisions (LearnedInterrogator.decisions) and experiments/trace_climb.py,
which prints them beside the truth; bad input exits 2 with one line."""

from __future__ import annotations

import math
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import gymnasium as gym
import pytest

import cof_gym
from cof_gym.agents.base import agent_view
from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR, Reading, load_interrogator

SHIPPED = (SHIPPED_INTERROGATOR / "manifest.json").is_file()
# the DC torque is read back from the float32 observation: a relative error of a few float32 epsilons (1.2e-7)
DC_RTOL = 1e-5


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_each_decision_is_the_step_the_next_window_takes_and_the_last_is_the_stop():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = load_interrogator(env)
    obs, info = env.reset(seed=12)
    agent.reset(obs, agent_view(info, oracle=False))
    dcs = []
    while True:
        obs, _, terminated, truncated, info = env.step(agent.act(obs, agent_view(info, oracle=False)))
        dcs.append(Reading.of(obs, env.unwrapped.limits, info).dc_nm)
        if terminated or truncated:
            break
    decisions = agent.decisions
    assert len(decisions) == len(dcs) - 1  # one per driven window read, the last window is the stop's
    assert decisions[-1].stop_reason == agent.stop_reason != "" and decisions[-1].log_step == 0.0
    assert all(d.stop_reason == "" for d in decisions[:-1])
    for k, d in enumerate(decisions[:-1]):
        capped = dcs[k + 1] >= env.unwrapped.limits.max_dc_torque_nm * (1 - DC_RTOL)
        assert capped or dcs[k + 1] / dcs[k] == pytest.approx(math.exp(d.log_step), rel=2 * DC_RTOL)
        assert d.steering_headroom <= d.filter_headroom  # a guard may only lower it, caution only lowers it
    crept = [d.crept for d in decisions]
    assert crept == sorted(crept)  # once crept, always crept


@pytest.mark.parametrize("args, option", [(["--episodes", "60"], "--episodes"), (["--set", "nothing=1"], "--set"),
                                          (["--set", "caution=-1"], "--set"), (["--agent", "/nonexistent"], "--agent")])
def test_bad_input_exits_2_naming_the_option(args, option, experiment_exit):
    code, last = experiment_exit("trace_climb", args)
    assert code == 2 and last.startswith(f"trace_climb.py: error: {option}")


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_the_command_prints_a_row_per_decision_and_how_the_climb_ended():
    script = Path(__file__).resolve().parents[1] / "experiments" / "trace_climb.py"
    done = subprocess.run([sys.executable, str(script), "--episodes", "2"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    rows = [line for line in lines if line.startswith("| ") and line[2].isdigit()]
    ended = [line for line in lines if line.startswith("ended: ")]
    assert len(ended) == 1 and f"after {len(rows) + 1} windows" in ended[0]


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_counter_torque_traces_the_episode_in_the_papers_configuration():
    """--counter-torque plays the episode with the counter torque on (crest_tradeoff.py's second configuration):
    its title says so, and the climb differs from the same episode's without it."""
    script = Path(__file__).resolve().parents[1] / "experiments" / "trace_climb.py"
    runs = [subprocess.run([sys.executable, str(script), "--episodes", "2", *flag], capture_output=True, text=True,
                           timeout=300) for flag in ([], ["--counter-torque"])]
    assert all(done.returncode == 0 for done in runs), [done.stderr for done in runs]
    titles = [[line for line in done.stdout.splitlines() if line.startswith("### episode")] for done in runs]
    assert titles[1][0].startswith("### episode 2 (seed 2), counter torque: ") and "counter torque" not in titles[0][0]
    rows = [[line for line in done.stdout.splitlines() if line.startswith("| ") and line[2].isdigit()] for done in runs]
    assert rows[0] != rows[1]


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_scenario_traces_the_episode_with_those_reset_options_over_its_own():
    """--scenario sets reset options over the episode's own (crest_tradeoff.py's --scenario): its title says so,
    and twice the noise changes the windows' lags."""
    script = Path(__file__).resolve().parents[1] / "experiments" / "trace_climb.py"
    runs = [subprocess.run([sys.executable, str(script), "--episodes", "2", *flag], capture_output=True, text=True,
                           timeout=300) for flag in ([], ["--scenario", "noise_level=2"])]
    assert all(done.returncode == 0 for done in runs), [done.stderr for done in runs]
    titles = [[line for line in done.stdout.splitlines() if line.startswith("### episode")] for done in runs]
    assert titles[1][0].startswith("### episode 2 (seed 2), noise_level 2: ") and "noise_level" not in titles[0][0]
    rows = [[line for line in done.stdout.splitlines() if line.startswith("| ") and line[2].isdigit()] for done in runs]
    assert rows[0] != rows[1]


def test_a_bad_scenario_exits_2_naming_the_option(experiment_exit):
    code, last = experiment_exit("trace_climb", ["--scenario", "noise_level=-1"])
    assert code == 2 and last.startswith("trace_climb.py: error: argument --scenario: 'noise_level=-1': noise_level")


def test_crest_asymmetry_is_the_cycles_rise_over_its_fall_and_nan_unread(monkeypatch):
    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[1] / "experiments"))
    from trace_climb import crest_asymmetry

    window = Reading(60.0, 1.0, 0.5, 0.1, 0.01, 1000.0, 400.0, 5.0, 20.0, 1.0)
    assert crest_asymmetry(replace(window, coa_cycle_max=0.12, coa_cycle_min=0.07)) == pytest.approx(2 / 3, rel=1e-12)
    assert math.isnan(crest_asymmetry(window))  # no cycle read
    assert math.isnan(crest_asymmetry(replace(window, coa_cycle_max=0.12, coa_cycle_min=0.1)))  # no fall below
