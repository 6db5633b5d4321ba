"""The agents' published numbers never change: every default agent on four episodes of the default v2 suite
plays the episodes ``tests/golden/agents_v2.json`` holds (``tests/golden/make_agents_golden.py``: the rows of
``cof-gym evaluate``'s ``episodes.csv``, each equal to the published row of its agent and seed when written).

What an agent did is compared exactly (its stop, the windows, a macro-slip, how the episode ended, the scenario's
labels); its numbers within 1e-6 relative, with an absolute floor of 1e-9 of the column's largest magnitude. The
tolerance is the observations' (``tests/test_v2_golden.py``): the lock-in's solve and the interrogator's matrix
products (float64) may round differently on another CPU's BLAS kernels, by a few float64 ulps that every agent
reads through the float32 observation. The PPO policy is a float32 network (hidden layers of 128, three
products): a kernel's summation order moves each product by up to 128 float32 ulps (128 x 1.2e-7), about 4.6e-5
over three, and its actions steer the episode: its rows are held to 1e-4. A decision at a threshold would flip only with a reading
within that rounding of it.

Two columns carry the estimate through a difference, where a relative tolerance of the column itself would be below
its arithmetic: a relative change ``r`` of the estimate moves ``relative_error = |estimate / CoF - 1|`` by up to
``r (1 + relative_error)`` (a 0.4 % error by 250 times its own ``r``), and the return's error term
``w_error |ln(estimate / CoF)|`` by ``w_error r``. Their tolerance is ``rtol (|value| + 1)`` and
``rtol (|value| + w_error)``."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from cof_gym.task.reward import Reward

GOLDEN = Path(__file__).parent / "golden"
sys.path.insert(0, str(GOLDEN))
from make_agents_golden import rows  # noqa: E402

EXPECTED = json.loads((GOLDEN / "agents_v2.json").read_text())


def _number(text: str) -> float | None:
    """The CSV cell as a float, None for a label or a flag (compared exactly)."""
    if text in ("True", "False"):
        return None
    try:
        return float(text)
    except ValueError:
        return None


@pytest.fixture(scope="module")
def played() -> list[dict[str, str]]:
    return rows()


# the columns that hold a number in any row (an agent without an interval leaves interval_low empty: compared as
# a number where the published row has one, and empty where it is empty), less the counts compared exactly
NUMBER_COLUMNS = sorted({k for r in EXPECTED for k, v in r.items() if _number(v) is not None}
                        - {"steps", "episode", "seed"})


def test_the_same_agents_play_the_same_episodes_alike(played) -> None:
    assert [(r["agent"], r["seed"]) for r in played] == [(r["agent"], r["seed"]) for r in EXPECTED]
    for got, want in zip(played, EXPECTED):
        labels = {k: v for k, v in want.items() if k not in NUMBER_COLUMNS}
        assert {k: got[k] for k in labels} == labels, (want["agent"], want["seed"])


FLOAT32_POLICIES = {"ppo": 1e-4}  # agent -> relative tolerance of its rows (the module docstring); others 1e-6
ESTIMATE_FLOORS = {"relative_error": 1.0, "episode_return": Reward().w_error}  # column -> rtol's floor (docstring)


def test_the_interval_columns_are_among_the_numbers_compared() -> None:
    # the oracle's row (the first) leaves them empty: the columns come from every row
    assert {"interval_low", "interval_high", "lower_bound", "estimate"} <= set(NUMBER_COLUMNS)


@pytest.mark.parametrize("column", NUMBER_COLUMNS)
def test_every_agents_numbers_are_the_published_ones(played, column) -> None:
    given = [r[column] != "" for r in EXPECTED]
    assert [r[column] != "" for r in played] == given, column  # a number exactly where the published row has one
    expected, got_rows = [r for r, g in zip(EXPECTED, given) if g], [r for r, g in zip(played, given) if g]
    want = np.array([float(r[column]) for r in expected])
    got = np.array([float(r[column]) for r in got_rows])
    rtol = np.array([FLOAT32_POLICIES.get(r["agent"], 1e-6) for r in expected])
    scale = float(np.max(np.abs(want)))
    far = np.abs(got - want) > rtol * (np.abs(want) + ESTIMATE_FLOORS.get(column, 0.0)) + 1e-9 * scale
    assert not far.any(), (column, [(r["agent"], r["seed"], g, w) for r, g, w, f in zip(expected, got, want, far) if f])
