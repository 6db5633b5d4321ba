"""Terminal output: evaluate's tables split no word at 80 or 100 columns (or at COLUMNS), and progress
shows as plain lines every few seconds when stderr is not a terminal."""

from __future__ import annotations

import io
import re
from dataclasses import fields

import numpy as np
import pytest
from rich.console import Console

from cof_gym.commands import terminal
from cof_gym.commands.evaluate_episodes import EpisodeRecord
from cof_gym.commands.evaluate_stats import summarize
from cof_gym.commands.evaluate_tables import print_table

AGENTS = ("staircase-paper", "staircase", "model-based", "phase-rule", "ppo")


def _record(**values) -> EpisodeRecord:
    """An episode record with ``values`` and a neutral value of its type for every other field."""
    neutral = {"str": "polach", "float": 0.0, "bool": False, "int": 0, "float | None": None}
    values.setdefault("ended", "macro-slip" if values.get("macro_slip") else "stop")
    return EpisodeRecord(**{f.name: values.get(f.name, neutral.get(str(f.type), 0.0)) for f in fields(EpisodeRecord)})


def _records() -> list[EpisodeRecord]:
    rng = np.random.default_rng(0)
    return [_record(agent=agent, oracle=agent == "staircase-paper", episode=i, seed=i, cof=float(rng.uniform(0.02, 0.6)),
                    condition=("dry", "wet", "low_adhesion")[i % 3], speed_m_s=20.0, load_case="laden",
                    relative_error=float(rng.uniform(0, 0.3)), scored=True, macro_slip=bool(i % 5 == 0),
                    slip_energy_j=123.4, wd_rms_m_s2=0.012, measurement_time_s=14.0, peak_torque_fraction=0.93,
                    steps=14)
            for agent in AGENTS for i in range(12)]


def _render(width: int, agents: int = len(AGENTS)) -> tuple[str, dict]:
    summary = summarize([r for r in _records() if r.agent in AGENTS[:agents]], seed=0)
    buf = io.StringIO()
    print_table(summary, "cof-gym evaluate: suite default (12 episodes per agent), seed 0", Console(
        file=buf, width=width, highlight=False, markup=False, color_system=None))
    return buf.getvalue(), summary


def _words(summary: dict) -> set[str]:
    """Every word the tables print: agent names, metric and group labels, values and CIs."""
    from cof_gym.commands.evaluate_stats import METRICS

    words = set()
    for agent, entry in summary.items():
        words.add(agent)
        words.update(entry["breakdown"])
    for _, label, *_ in METRICS:
        words.update(label.split())
    words.update({"[%]", "(oracle)"})
    return {w for text in words for w in text.split()}


@pytest.mark.parametrize("width", [60, 80, 100, 140])
@pytest.mark.parametrize("agents", [1, 3, len(AGENTS)])
def test_tables_split_no_word(width: int, agents: int) -> None:
    text, summary = _render(width, agents)
    lines = text.splitlines()
    assert all(len(line) <= width for line in lines), max(lines, key=len)
    tokens = set(re.split(r"[\s┃│┡━┩─┏┓┗┛╇┳┻╋|]+", text))
    for word in _words(summary):
        assert word in tokens or any(word in line for line in lines), f"{word!r} split at {width} columns:\n{text}"
    values = [f"{100 * summary[a]['median_error']['value']:.1f}" for a in summary]
    assert all(v in tokens for v in values)


def test_narrow_console_falls_back_to_blocks_or_lines() -> None:
    text, summary = _render(40)
    assert all(len(line) <= 40 for line in text.splitlines() if "┃" in line or "│" in line)
    assert "staircase-paper" in text and "median" in text


@pytest.mark.parametrize("columns", ["80", "100"])
def test_columns_sets_the_default_width(columns: str, monkeypatch) -> None:
    monkeypatch.setenv("COLUMNS", columns)
    assert terminal.console(io.StringIO()).width == int(columns)


def test_plain_progress_prints_every_few_seconds() -> None:
    now = [0.0]
    buf = io.StringIO()
    progress = terminal.PlainProgress(buf, every_s=5.0, clock=lambda: now[0])
    progress.start()
    task = progress.add_task("staircase", total=100)
    for _ in range(100):
        now[0] += 0.5  # an episode every half second: a line every 10 episodes, and at the end
        progress.advance(task)
    lines = buf.getvalue().splitlines()
    assert len(lines) == 10 and lines[0] == "staircase: 10/100 episodes, 5 s elapsed"
    assert lines[-1].startswith("staircase: 100/100 episodes")


def test_evaluate_progress_is_plain_lines_when_not_a_terminal(capsys) -> None:
    from cof_gym.commands.evaluate import _progress

    assert isinstance(_progress(quiet=False), terminal.PlainProgress)  # pytest's stderr is not a terminal
    assert _progress(quiet=True) is None
