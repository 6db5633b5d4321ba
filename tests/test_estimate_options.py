"""Options that change the learned interrogator's estimate and no step of its climb: the estimate behind a slow drive
read at the modulation the drive applied (``ClimbParameters.slow_drive_applied_estimate``, rule 134), and the estimate
shifted by its own variance (``ClimbParameters.relative_error_shift``, session 70's exploration)."""

from __future__ import annotations

import math
from dataclasses import replace

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents import registry
from cof_gym.agents.interrogator import FEATURE_NAMES, ClimbParameters, EpisodeFeatures
from cof_gym.commands.evaluate_episodes import run_episode
from interrogator_helpers import SHIPPED, window_reading

RATIO = FEATURE_NAMES.index("amplitude_ratio")


def test_the_applied_ratio_replaces_the_commanded_one_and_nothing_else():
    """With ``applied_ratio`` the ``amplitude_ratio`` entry reads the measured torque amplitude over the DC; every
    other entry is the commanded vector's; a window whose torque amplitude was not read keeps the command."""
    measured = replace(window_reading(20.0, 2.0), torque_amplitude_measured_nm=480.0)  # DC 4000 N m, command 1600
    features = EpisodeFeatures(counter_torque=False)
    features.push(measured)
    commanded, applied = features.vector(), features.vector(applied_ratio=True)
    assert commanded[RATIO] == pytest.approx(0.4) and applied[RATIO] == pytest.approx(0.12)
    assert np.array_equal(np.delete(commanded, RATIO), np.delete(applied, RATIO))
    unread = EpisodeFeatures(counter_torque=False)
    unread.push(window_reading(20.0, 2.0))
    assert np.array_equal(unread.vector(applied_ratio=True), unread.vector())


@pytest.mark.parametrize("value", ["yes", 1, None])
def test_the_option_is_a_flag(value):
    with pytest.raises(ValueError, match="slow_drive_applied_estimate"):
        ClimbParameters(slow_drive_applied_estimate=value)


def _played(motor_lag_s: float, applied: bool, shift: float = 0.0):
    """The shipped interrogator (the options as given) on episode 11 of the v2 draws with this drive lag: its record,
    the steps it took and the agent."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = registry.make_agent("interrogator", env)
    agent.params = replace(agent.params, slow_drive_applied_estimate=applied, relative_error_shift=shift)
    record = run_episode(env, agent, 11, {"motor_lag_s": motor_lag_s}, 0)
    env.close()
    return record, [(d.log_step, d.stop_reason) for d in agent.decisions], agent


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_only_the_estimate_behind_a_slow_drive_changes():
    """Behind the draws' slowest drive (30 ms) the option changes nothing; behind a 0.1 s drive (a slow drive read)
    every step and the stop are the same, the estimate is not."""
    for motor_lag_s, changes in ((0.03, False), (0.1, True)):
        (off, off_steps, off_agent), (on, on_steps, on_agent) = (_played(motor_lag_s, a) for a in (False, True))
        assert on_steps == off_steps and on.peak_torque_fraction == off.peak_torque_fraction
        assert (on_agent.estimate != off_agent.estimate) == changes


@pytest.mark.parametrize("value", [-0.1, 5.5, math.nan, "1"])
def test_the_shift_is_a_number_within_its_range(value):
    with pytest.raises(ValueError, match="relative_error_shift"):
        ClimbParameters(relative_error_shift=value)


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_the_shift_lowers_the_estimate_by_its_variance_and_changes_no_step():
    """With ``relative_error_shift`` s the estimate is the unshifted one times ``exp(-s x std^2)`` (std: the
    estimate's own, unchanged), or the climb's best crest bound where that floor holds it up; every step the same."""
    (off, off_steps, off_agent), (on, on_steps, on_agent) = (_played(0.02, False, s) for s in (0.0, 2.0))
    assert on_steps == off_steps and on.peak_torque_fraction == off.peak_torque_fraction
    std = on_agent.estimate_log_std
    assert std == off_agent.estimate_log_std > 0.0
    shifted = off_agent.estimate * math.exp(-2.0 * std**2)
    assert on_agent.estimate == pytest.approx(max(shifted, on_agent.demonstrated_adhesion), rel=1e-12)
