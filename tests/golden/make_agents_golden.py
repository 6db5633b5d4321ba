"""Writes ``agents_v2.json``: every default agent's episodes (``cof-gym evaluate``'s ``episodes.csv`` rows) on a
few episodes of the default v2 suite, which ``tests/test_agents_golden.py`` compares every later version of the
code with: the agents' published numbers must never change unless a change means them to (then regenerate
it and say so). Run from the commit whose numbers are published::

    python tests/golden/make_agents_golden.py tests/golden/agents_v2.json

(written in session 42, at a commit whose ``cof-gym evaluate`` default suite is byte-identical to the published
one; each row below equals the published ``out/evaluate/episodes.csv`` row of the same agent and seed; rewritten in
session 53 when rule 94 changed the shipped interrogator's climb, its rows again equal to the published ones; in
session 73 the rows of the two agents that joined the default list, ``staircase-zeroed`` and ``model-based-zeroed``,
were added from this script's output in their places, every earlier row kept as written; in session 74 likewise
``model-based-zeroed-knee``'s; rewritten in session 80, when evaluate counted each window an agent drove once (a
stop's repeated readings had been counted again): only ``slip_energy_j``, ``friction_energy_j`` and ``wd_rms_m_s2``
changed, besides ppo's return in its tenth digit (a float32 policy) and the ``sensor_notes`` column joining; every
row again equal to the published one).
"""

from __future__ import annotations

import csv
import json
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

from cof_gym.agents.registry import default_agents
from cof_gym.commands.evaluate import evaluate
from cof_gym.commands.suites import make_suite

EPISODES = (0, 15, 30, 45)  # of the default suite (60 episodes, seed 0): each episode is seeded on its own


def rows() -> list[dict[str, str]]:
    """The ``episodes.csv`` rows of every default agent on :data:`EPISODES`, as the CSV writes them."""
    suite = make_suite("default", 60, 0)
    subset = replace(suite, episodes=[suite.episodes[i] for i in EPISODES])
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "evaluate"
        evaluate(default_agents(), subset, out, seed=0, quiet=True, workers=1)
        with open(out / "episodes.csv", newline="") as fh:
            return list(csv.DictReader(fh))


if __name__ == "__main__":
    with open(sys.argv[1], "w") as f:
        json.dump(rows(), f, indent=1)
