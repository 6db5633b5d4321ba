"""Terminal output of the commands: tables that never split a word, and progress that shows when the
output is not a terminal.

A table keeps every column at least as wide as its longest word; when the console cannot hold that,
the rows are printed as one block per value column (a vertical layout), and when even a block does
not fit, as plain ``label: value`` lines. Progress is a rich bar on a terminal and, elsewhere (a pipe,
a log file), one plain line every :data:`PROGRESS_EVERY_S` seconds."""

from __future__ import annotations

import shutil
import sys
import time
from typing import IO, Sequence

from rich.console import Console
from rich.measure import Measurement
from rich.table import Table

DEFAULT_WIDTH = 100  # columns when the width is unknown (not a terminal, no COLUMNS)
PROGRESS_EVERY_S = 5.0


def console(stream: IO[str] | None = None, width: int | None = None) -> Console:
    """A plain (no markup, no highlighting) console on ``stream`` (stdout), as wide as ``width``, else
    ``COLUMNS``, else the terminal, else :data:`DEFAULT_WIDTH`."""
    width = width or shutil.get_terminal_size((DEFAULT_WIDTH, 24)).columns
    return Console(file=stream or sys.stdout, width=width, highlight=False, markup=False)


def _longest(text: str, split: str | None) -> int:
    parts = text.split() if split is None else text.splitlines()
    return max((len(p) for p in parts), default=0)


def _table(title: str, headers: Sequence[str], rows: Sequence[Sequence[str]]) -> Table:
    table = Table(title=title, title_justify="left", pad_edge=False)
    for i, header in enumerate(headers):
        table.add_column(header, justify="left" if i == 0 else "right", overflow="fold")
    for row in rows:
        table.add_row(*row)
    return table


def fitted_table(title: str, headers: Sequence[str], rows: Sequence[Sequence[str]], width: int,
                 probe: Console) -> Table | None:
    """The table with column widths that split no word within ``width`` columns, or None when its
    longest words alone need more."""
    table = _table(title, headers, rows)
    columns = [[headers[j], *(row[j] for row in rows)] for j in range(len(headers))]
    words = [max(_longest(c, None) for c in col) for col in columns]
    lines = [max(_longest(c, "lines") for c in col) for col in columns]
    for column in table.columns:
        column.width = 1
    overhead = Measurement.get(probe, probe.options.update_width(10_000), table).maximum - len(headers)
    room = width - overhead
    if sum(lines) <= room:
        widths = lines
    elif sum(words) <= room:  # the columns that need the least widening get their whole lines first
        widths, spare = list(words), room - sum(words)
        for j in sorted(range(len(words)), key=lambda j: lines[j] - words[j]):
            extra = min(lines[j] - words[j], spare)
            widths[j] += extra
            spare -= extra
    else:
        return None
    for column, w in zip(table.columns, widths):
        column.width = w
    return table


def print_table(title: str, headers: Sequence[str], rows: Sequence[Sequence[str]], out: Console) -> None:
    """``rows`` under ``headers`` (the first column labels the rows), splitting no word at the
    console's width: as a table, else one block per value column, else ``label: value`` lines."""
    table = fitted_table(title, headers, rows, out.width, out)
    if table is not None:
        out.print(table)
        return
    blocks = [fitted_table(f"{title}: {headers[j]}", [headers[0], "value"], [[r[0], r[j]] for r in rows],
                           out.width, out) for j in range(1, len(headers))]
    if all(b is not None for b in blocks):
        for block in blocks:
            out.print(block)
        return
    out.print(title, soft_wrap=True)
    for j in range(1, len(headers)):
        out.print(headers[j].replace("\n", " ") + ":", soft_wrap=True)
        for row in rows:
            out.print(f"  {' '.join(row[0].split())}: {' '.join(row[j].split())}", soft_wrap=True)


class PlainProgress:
    """The subset of ``rich.progress.Progress`` the commands use, as one line on ``stream`` at most
    every ``every_s`` seconds (and at each task's end): for output that is not a terminal."""

    def __init__(self, stream: IO[str] | None = None, every_s: float = PROGRESS_EVERY_S, unit: str = "episodes",
                 clock=time.monotonic) -> None:
        self.stream, self.every_s, self.unit, self.clock = stream or sys.stderr, every_s, unit, clock
        self.tasks: list[dict] = []
        self._start = self._last = clock()

    def start(self) -> None:
        self._start = self._last = self.clock()

    def stop(self) -> None:
        pass

    def add_task(self, description: str, total: int) -> int:
        self.tasks.append({"description": description, "total": total, "completed": 0})
        return len(self.tasks) - 1

    def advance(self, task_id: int, advance: int = 1) -> None:
        task = self.tasks[task_id]
        now = self.clock()
        task["completed"] += advance
        if task["completed"] >= task["total"] or now - self._last >= self.every_s:
            self._last = now
            print(f"{task['description']}: {task['completed']}/{task['total']} {self.unit}, "
                  f"{now - self._start:.0f} s elapsed", file=self.stream, flush=True)
