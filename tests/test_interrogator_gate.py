"""The smoothed-encoder gate (rule 127): networks of their own steer and estimate a climb whose first windows read a
smoothed encoder, from the decision where the sensor note is final; every other climb is the climb's own."""

from __future__ import annotations

import json
import math
import shutil
from dataclasses import replace

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.base import agent_view
from cof_gym.agents.interrogator import (
    NOISE_WINDOWS, SHIPPED_INTERROGATOR, SLOW_DRIVE, SMOOTHED_ENCODER, TARGET_NAMES, ClimbParameters, FilterEnsemble,
    FilterNetwork, NetworkSet, interrogator_for, manifest_smoothed_networks,
)
from cof_gym.agents.interrogator.readings import drive_lag_s, first_windows_drive_lag_s

from interrogator_helpers import SHIPPED

pytestmark = pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator")

SEED = 60_001
LAGGED = {"encoder_lag_s": 0.005}  # a 5 ms encoder lag: the sensor note's smoothed encoder on this seed


def constant_ensemble(like: FilterEnsemble, headroom: float) -> FilterEnsemble:
    """One member that reads ``like``'s features and predicts ``headroom`` (and no correction) whatever it reads."""
    names = like.members[0].feature_names
    n, width = len(names), 4
    weights = (np.zeros((n, width)), np.zeros((width, 2 * len(TARGET_NAMES))))
    biases = (np.zeros(width), np.array([headroom, 0.0, -6.0, -6.0]))
    return FilterEnsemble((FilterNetwork(np.zeros(n), np.ones(n), weights, biases, names),))


def played(agent, options: dict) -> np.ndarray:
    """The actions of the agent's episode at ``SEED`` with these reset options (the decisions stay on the agent)."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    obs, info = env.reset(seed=SEED, options=options)
    agent.reset(obs, agent_view(info, oracle=False))
    actions = []
    while True:
        actions.append(agent.act(obs, agent_view(info, oracle=False)))
        obs, _, terminated, truncated, info = env.step(actions[-1])
        if terminated or truncated:
            env.close()
            return np.asarray(actions)


@pytest.fixture(scope="module")
def shipped():
    return interrogator_for(gym.make(cof_gym.WAGON_ENV_ID), SHIPPED_INTERROGATOR)


def test_the_climbs_own_networks_as_the_gates_change_nothing_on_a_smoothed_encoder(shipped):
    """The gate's networks read every window from the first: given the climb's own networks, the gated climb is the
    ungated one, action for action."""
    gated = replace(shipped, smoothed_networks=NetworkSet(shipped.ensemble, shipped.guards))
    plain = played(shipped, LAGGED)
    assert shipped.sensor_notes() == (SMOOTHED_ENCODER,)
    np.testing.assert_array_equal(played(gated, LAGGED), plain)
    assert gated.gated


def test_the_gate_steers_a_smoothed_encoders_climb_from_its_third_window_and_no_sharp_one(shipped):
    """Other networks behind the gate: a climb with a sharp encoder plays as without them; one with a smoothed
    encoder plays its first decisions as without them and, from the decision after its third driven window, takes
    their prediction."""
    headroom = 0.5
    other = constant_ensemble(shipped.ensemble, headroom)
    gated = replace(shipped, smoothed_networks=NetworkSet(other, shipped.guards))
    np.testing.assert_array_equal(played(gated, {}), played(shipped, {}))
    assert not gated.gated and gated.sensor_notes() == ()
    plain = played(shipped, LAGGED)
    plain_decisions = list(shipped.decisions)
    actions = played(gated, LAGGED)
    first = NOISE_WINDOWS  # the first action sets the first DC; the decision after driven window k is action k
    np.testing.assert_array_equal(actions[:first], plain[:first])
    assert gated.decisions[:first - 1] == plain_decisions[:first - 1]
    assert [d.filter_headroom for d in gated.decisions[first - 1:]] == pytest.approx(
        [headroom] * (len(gated.decisions) - first + 1))
    assert plain_decisions[first - 1].filter_headroom != pytest.approx(headroom)
    assert gated.gated


def test_the_gates_networks_must_read_the_climbs_excitation_and_bring_its_guard_count(shipped):
    with pytest.raises(ValueError, match="smoothed_networks: 1 guard"):
        replace(shipped, smoothed_networks=NetworkSet(shipped.ensemble, shipped.guards[:1]))


def test_a_policy_directory_names_the_gates_networks_in_its_manifest(tmp_path, shipped):
    directory = tmp_path / "policy"
    shutil.copytree(SHIPPED_INTERROGATOR, directory)
    manifest = json.loads((directory / "manifest.json").read_text())
    assert manifest_smoothed_networks(directory) is None
    manifest["smoothed_encoder"] = {"filter": ".", "guards": manifest["guards"]}
    (directory / "manifest.json").write_text(json.dumps(manifest))
    agent = interrogator_for(gym.make(cof_gym.WAGON_ENV_ID), directory)
    assert len(agent.smoothed_networks.guards) == len(shipped.guards)
    np.testing.assert_array_equal(played(agent, LAGGED), played(shipped, LAGGED))
    manifest["smoothed_encoder"] = {"guards": manifest["guards"]}
    (directory / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(ValueError, match="smoothed_encoder must be"):
        manifest_smoothed_networks(directory)


def test_an_assembled_policy_carries_the_gates_networks_and_its_agent_reads_them(tmp_path, shipped, monkeypatch):
    """experiments/assemble_policy.py with --smoothed-filter: the networks copied into the directory, named by its
    manifest, loaded by the agent as given."""
    from pathlib import Path

    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[1] / "experiments"))
    from assemble_policy import assemble

    guards = [SHIPPED_INTERROGATOR / "guard_0", SHIPPED_INTERROGATOR / "guard_1"]
    manifest = assemble(SHIPPED_INTERROGATOR, guards, SHIPPED_INTERROGATOR, tmp_path / "policy", guards[1],
                        [guards[1], guards[0]], {"caution": 2.5})
    assert manifest["smoothed_encoder"] == {"filter": "smoothed_encoder/filter",
                                            "guards": ["smoothed_encoder/guard_0", "smoothed_encoder/guard_1"],
                                            "climb": {"caution": 2.5}}
    agent = interrogator_for(gym.make(cof_gym.WAGON_ENV_ID), tmp_path / "policy")
    loaded = agent.smoothed_networks
    assert loaded.climb == {"caution": 2.5}
    for network, source in zip(loaded.networks, (shipped.guards[1], shipped.guards[1], shipped.guards[0])):
        for a, b in zip(network.members, source.members):
            np.testing.assert_array_equal(a.weights[0], b.weights[0])


def test_networks_added_into_a_policy_directory_keep_its_own_and_drop_its_interval(tmp_path, shipped, monkeypatch):
    """assemble_policy.py --into: the gate's networks join a copy of the shipped directory, whose networks, guards,
    climb and training record stay as they were; its interval, in the stds of networks it no longer alone reads, is
    removed; a sharp climb plays as the shipped agent's."""
    from pathlib import Path

    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[1] / "experiments"))
    from assemble_policy import add_smoothed

    directory = tmp_path / "policy"
    shutil.copytree(SHIPPED_INTERROGATOR, directory)
    (directory / "interval.json").write_text("{}")
    before = json.loads((directory / "manifest.json").read_text())
    guards = [directory / "guard_1", directory / "guard_0"]
    manifest = add_smoothed(directory, directory / "guard_1", guards, {"caution": 2.5})
    assert {k: v for k, v in manifest.items() if k != "smoothed_encoder"} == {
        **before, "training": {**before["training"], "smoothed_encoder": {"assembled_from": {
            "filter": str(directory / "guard_1"), "guards": [str(g) for g in guards]}}}}
    assert not (directory / "interval.json").exists()
    agent = interrogator_for(gym.make(cof_gym.WAGON_ENV_ID), directory)
    assert agent.smoothed_networks.climb == {"caution": 2.5}
    np.testing.assert_array_equal(played(agent, {}), played(shipped, {}))
    assert add_smoothed(directory, directory / "guard_0", guards)["smoothed_encoder"] == {
        "filter": "smoothed_encoder/filter", "guards": ["smoothed_encoder/guard_0", "smoothed_encoder/guard_1"]}


def test_the_gates_climb_parameters_change_its_decisions_alone(shipped):
    """A caution of the gate's own: the sharp climb and a smoothed one's first decisions as without it, the gated
    decisions more cautious (steps no larger, somewhere smaller)."""
    cautious = replace(shipped, smoothed_networks=NetworkSet(shipped.ensemble, shipped.guards, {"caution": 4.0}))
    np.testing.assert_array_equal(played(cautious, {}), played(shipped, {}))
    plain = played(shipped, LAGGED)
    plain_steps = [d.log_step for d in shipped.decisions]
    actions = played(cautious, LAGGED)
    np.testing.assert_array_equal(actions[:NOISE_WINDOWS], plain[:NOISE_WINDOWS])
    gated_steps = [d.log_step for d in cautious.decisions]
    assert gated_steps[NOISE_WINDOWS - 1] < plain_steps[NOISE_WINDOWS - 1]
    with pytest.raises(ValueError, match="smoothed_networks: climb"):
        replace(shipped, smoothed_networks=NetworkSet(shipped.ensemble, shipped.guards, {"caution": -1.0}))
    with pytest.raises(ValueError, match="smoothed_networks: climb"):
        replace(shipped, smoothed_networks=NetworkSet(shipped.ensemble, shipped.guards, {"no_such_parameter": 1}))


@pytest.mark.parametrize("frequency_hz", [2.0, 5.0, 20.0])
@pytest.mark.parametrize("lag_s", [0.001, 0.03, 0.1])
def test_the_drive_lag_read_inverts_a_first_order_drives_gain(lag_s, frequency_hz):
    """A first-order drive passes 1 / sqrt(1 + (w tau)^2) of a modulation: that fraction reads tau back (to rounding);
    a fraction of 1 or more (a torque gain error) reads no lag."""
    fraction = 1.0 / math.sqrt(1.0 + (2.0 * math.pi * frequency_hz * lag_s) ** 2)
    assert drive_lag_s(fraction, frequency_hz) == pytest.approx(lag_s, rel=1e-9)
    assert drive_lag_s(1.0, frequency_hz) == 0.0 and drive_lag_s(1.07, frequency_hz) == 0.0


def test_the_drive_lag_is_read_from_the_first_windows_median_and_bad_input_is_refused():
    fast, slow = (1.0 / math.sqrt(1.0 + (2.0 * math.pi * 5.0 * lag) ** 2) for lag in (0.01, 0.06))
    assert first_windows_drive_lag_s([fast, slow, slow, fast, fast], 5.0) == pytest.approx(0.06)  # windows 1-3 alone
    assert first_windows_drive_lag_s([], 5.0) == 0.0
    for fraction, frequency, field in ((0.0, 5.0, "applied_fraction"), (math.nan, 5.0, "applied_fraction"),
                                       (0.5, 0.0, "frequency_hz")):
        with pytest.raises(ValueError, match=field):
            drive_lag_s(fraction, frequency)
    with pytest.raises(ValueError, match="gate_max_drive_lag_s"):
        ClimbParameters(gate_max_drive_lag_s=0.0)


def test_a_drive_bound_keeps_a_slow_drives_climb_from_the_gate_and_no_other():
    """With gate_max_drive_lag_s a smoothed encoder behind a drive slower than it plays as the ungated climb (its
    sensor note as before); behind a faster one the gate steers it as without the bound."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    shipped = interrogator_for(env, SHIPPED_INTERROGATOR)
    other = NetworkSet(constant_ensemble(shipped.ensemble, 0.5), shipped.guards)
    bounded = replace(shipped, params=replace(shipped.params, gate_max_drive_lag_s=0.04), smoothed_networks=other)
    unbounded = replace(bounded, params=shipped.params)
    assert not bounded.params.gates_drive([0.5] * NOISE_WINDOWS, 5.0) and shipped.params.gates_drive([0.5], 5.0)
    slow = {**LAGGED, "motor_lag_s": 0.06}
    np.testing.assert_array_equal(played(bounded, slow), played(shipped, slow))
    assert not bounded.gated and bounded.sensor_notes() == (SMOOTHED_ENCODER, SLOW_DRIVE)
    assert not np.array_equal(played(unbounded, slow), played(shipped, slow)) and unbounded.gated
    fast = {**LAGGED, "motor_lag_s": 0.02}
    np.testing.assert_array_equal(played(bounded, fast), played(unbounded, fast))
    assert bounded.gated
