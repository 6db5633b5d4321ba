"""experiments/indistinguishable_peaks.py: the twin of a tabulated creep curve and what an agent can tell apart."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"
sys.path.insert(0, str(EXPERIMENTS))
import indistinguishable_peaks as ip  # noqa: E402

from cof_gym.agents import registry  # noqa: E402
from cof_gym.physics.creep_laws import TableShape  # noqa: E402

STEEP = json.loads((EXPERIMENTS / "suites" / "v2_validation_steep_grid.json").read_text())


def _table(k: int = 0) -> tuple[dict, dict]:
    episode = STEEP["episodes"][k]
    return episode, episode["options"]["creep_law"]["table"]


@pytest.mark.parametrize("ratio", [1.1, 1.25, 2.0])
def test_the_twin_is_a_valid_table_with_the_same_force_up_to_the_peak_and_a_higher_cof(ratio):
    _, table = _table()
    twin = ip.twin_law(table, ratio)["table"]
    TableShape(tuple(twin["creepage"]), tuple(twin["adhesion_ratio"]))  # the env's own validation
    peak = int(np.argmax(table["adhesion_ratio"]))
    # force = CoF x ratio: the twin's (CoF R) x (ratio / R) equals the original's up to and at the peak point
    np.testing.assert_allclose(np.multiply(twin["adhesion_ratio"][:peak + 1], ratio),
                               table["adhesion_ratio"][:peak + 1], rtol=1e-12, atol=0)
    assert twin["creepage"][:peak + 1] == table["creepage"][:peak + 1]
    assert int(np.argmax(twin["adhesion_ratio"])) > peak and max(twin["adhesion_ratio"]) == 1.0
    with pytest.raises(ValueError, match="ratio"):
        ip.twin_law(table, 1.0)


def test_an_agent_that_acts_alike_on_both_reports_one_estimate_for_two_cofs():
    """The phase rule on the third steep episode (it stops below the peak there) and its twin (CoF x 1.25): it
    drives both alike, so its one estimate is more than 8 % off on at least one of them (1.25 > 1.08 / 0.92)."""
    episode, _ = _table(2)
    env = gym.make(STEEP["env_id"], **STEEP.get("env_kwargs", {}))
    agent = ip.ActionLog(registry.make_agent("phase-rule", env))
    pair = ip.play_pair(env, agent, episode["seed"], episode["options"], 1.25, 0)
    env.close()
    assert pair["alike"] and pair["shared"] > 0.9
    original, twin = pair["original"], pair["twin"]
    assert not original.macro_slip and not twin.macro_slip
    assert twin.estimate == pytest.approx(original.estimate, rel=1e-6)
    assert max(original.relative_error, twin.relative_error) > 0.08


@pytest.mark.parametrize("args, option", [(["--ratio", "1"], "--ratio"), (["--tolerance", "0"], "--tolerance"),
                                          (["--agents", "oracle"], "--agents"), (["--agents", "nobody"], "--agents"),
                                          (["--suite", "no/such.json"], "--suite")])
def test_bad_options_exit_2_naming_the_option(args, option, tmp_path, experiment_exit):
    code, last = experiment_exit("indistinguishable_peaks", [*args, "--out", str(tmp_path / "t.md")])
    assert code == 2 and option in last
    assert not (tmp_path / "t.md").exists()
