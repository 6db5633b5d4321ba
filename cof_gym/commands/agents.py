"""``cof-gym agents``: every agent ``cof-gym evaluate`` and ``cof-gym watch`` know, from the one registry
(:mod:`cof_gym.agents.registry`): how to name it, whether it reads the ground truth, whether the default list plays
it, and what it does."""

from __future__ import annotations

import argparse
import shutil
import textwrap

from cof_gym.agents import registry

DESCRIPTION = ("Every agent cof-gym evaluate and cof-gym watch know (one registry, cof_gym/agents/registry.py): its "
               "name (NAME:ARG where it takes an argument), 'oracle' where it reads the ground truth, 'default' where "
               "cof-gym evaluate plays it without --agents ('default on ID' where it does on a suite played on that "
               "id), and what it does. Any of them takes +runaway, +ceiling or +plain (cof-gym evaluate --help).")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--names", action="store_true", help="only the names, one a line (for scripts)")


def listing(width: int) -> list[str]:
    """One block a registered agent that can be built here: its spellings and flags, then its description
    indented, wrapped to ``width`` columns."""
    defaults = set(registry.default_agents())
    lines = []
    for name in registry.names():
        entry = registry.AGENTS[name]
        flags = [flag for flag, on in (("oracle", entry.oracle), ("default", name in defaults)) if on]
        flags += [f"default on {env_id}" for env_id in entry.default_on]
        lines.append(", ".join(entry.spellings) + (f"  [{', '.join(flags)}]" if flags else ""))
        lines += textwrap.wrap(entry.help or "(no description)", width, initial_indent="    ",
                               subsequent_indent="    ", break_long_words=False, break_on_hyphens=False)
    return lines


def run(args: argparse.Namespace) -> int:
    if args.names:
        print("\n".join(s for name in registry.names() for s in registry.AGENTS[name].spellings))
    else:
        print("\n".join(listing(max(60, min(120, shutil.get_terminal_size().columns)))))
    return 0
