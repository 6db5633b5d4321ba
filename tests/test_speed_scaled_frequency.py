"""A modulation frequency that rises as the speed falls (ClimbParameters.frequency_reference_m_s): its
arithmetic, the interrogator driving it, and the training climbs that draw it."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator import (
    FEATURE_NAMES, TARGET_NAMES, ClimbParameters, FilterEnsemble, FilterNetwork, LearnedInterrogator, Reading,
    speed_scaled_frequency,
)
from cof_gym.agents.interrogator.training import ClimbDraws, _climb_episode
from cof_gym.agents.phase_rule import rotation_clear_frequency
from cof_gym.task.interface import MotorLimits, decode_action
from fixed_options import FixedOptions
from test_rotation_clear_frequency import coincidence_speed

LIMITS = MotorLimits(max_dc_torque_nm=10_000.0)
# the action carries the frequency as a float32 on a log scale over the drive's 1-20 Hz (ln 20 = 3.0) and the
# observation reads it back as a float32: a few float32 epsilons (1.2e-7) times that scale
FREQUENCY_RTOL = 1e-5


@pytest.mark.parametrize("speed, expected", [(40.0, 5.0), (20.0, 5.0), (10.0, 10.0), (8.0, 12.5), (4.0, 20.0),
                                             (1.0, 20.0)])
def test_the_frequency_rises_as_one_over_the_speed_below_the_reference_within_the_drive(speed, expected):
    assert speed_scaled_frequency(5.0, 20.0, speed, LIMITS) == pytest.approx(expected, rel=1e-12)


def test_without_a_reference_the_climb_keeps_its_frequency():
    assert ClimbParameters(frequency_hz=7.0).frequency_at(3.0, LIMITS) == 7.0
    assert ClimbParameters(frequency_hz=7.0, frequency_reference_m_s=14.0).frequency_at(3.5, LIMITS) == 20.0


@pytest.mark.parametrize("value", [0.0, -5.0, float("nan"), float("inf"), True, "20"])
def test_a_bad_reference_speed_names_the_field(value):
    with pytest.raises(ValueError, match="frequency_reference_m_s"):
        ClimbParameters(frequency_reference_m_s=value)


@pytest.mark.parametrize("speed", [0.0, -1.0, float("nan")])
def test_a_speed_that_is_not_positive_names_it(speed):
    with pytest.raises(ValueError, match="speed_m_s"):
        speed_scaled_frequency(5.0, 20.0, speed, LIMITS)


def _zero_network() -> FilterNetwork:
    n, width = len(FEATURE_NAMES), 4
    shapes = [(n, width), (width, 2 * len(TARGET_NAMES))]
    return FilterNetwork(np.zeros(n), np.ones(n), tuple(np.zeros(s) for s in shapes), tuple(np.zeros(s[1]) for s in shapes))


ROTATING_AT_5_HZ = coincidence_speed(1)  # the speed (m/s) at which the wheelset turns at 5 Hz on the nominal wheel


@pytest.mark.parametrize("reference, margin, speed", [(None, None, 10.0), (5.0, None, 10.0), (40.0, None, 10.0),
                                                      (90.0, None, 10.0), (None, 1.0, ROTATING_AT_5_HZ),
                                                      (None, 1.0, 10.0), (24.0, 1.0, 18.0)])
def test_the_interrogator_drives_the_frequency_of_the_speed_it_measured_at_the_start(reference, margin, speed):
    """Every window of the climb is modulated at frequency_at(the reset observation's measured speed): the
    speed sensor's error included, never the true speed; scaled with the speed first, then moved clear of the
    rotation's harmonics (ClimbParameters.rotation_margin_hz)."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((_zero_network(),)),
                                params=ClimbParameters(frequency_reference_m_s=reference, rotation_margin_hz=margin,
                                                       floor_margin=0.2))
    obs, info = env.reset(seed=3, options={"speed_m_s": speed, "speed_sensor_error": 0.01})
    measured = Reading.of(obs, env.unwrapped.limits, info).speed_m_s
    assert measured == pytest.approx(speed * 1.01, rel=1e-3)  # the sensor's error, read by the agent
    expected = agent.params.frequency_at(measured, env.unwrapped.limits)
    agent.reset(obs, info)
    frequencies = []
    for _ in range(3):
        action = agent.act(obs, info)
        frequencies.append(decode_action(action, env.unwrapped.limits).drive.frequency_hz)
        obs, _, terminated, truncated, info = env.step(action)
        assert Reading.of(obs, env.unwrapped.limits, info).frequency_hz == pytest.approx(expected, rel=FREQUENCY_RTOL)
        if terminated or truncated:
            break
    assert frequencies == pytest.approx([expected] * len(frequencies), rel=FREQUENCY_RTOL)
    if margin is None:
        assert expected == {None: 5.0, 5.0: 5.0, 40.0: pytest.approx(5.0 * 40.0 / measured), 90.0: 20.0}[reference]
    else:  # scaled first, then moved off the rotation only where within the margin (5 Hz is 1.5 Hz from it at 10 m/s,
        # 1.3 Hz at 18 m/s, where 24 m/s scales it to 0.3 Hz from it)
        scaled = 5.0 if reference is None else speed_scaled_frequency(5.0, reference, measured, env.unwrapped.limits)
        assert expected == rotation_clear_frequency(scaled, measured, margin, env.unwrapped.limits)
        assert (expected != scaled) == (speed == ROTATING_AT_5_HZ or reference == 24.0)


def test_speed_scaled_training_climbs_raise_the_drawn_frequency_as_the_deployed_climb_would():
    """With frequency_references_m_s a training climb's frequency is its usual draw raised below a reference
    speed drawn in the range (at a slow speed, above the plain climb's); the other draws are unchanged."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    fixed = {"speed_m_s": 6.0, "condition": "wet", "load_case": "empty"}
    scaled, _ = _climb_episode(FixedOptions(env, fixed), 2_000_400, ClimbDraws(frequency_references_m_s=(12.0, 12.0)))
    plain, _ = _climb_episode(FixedOptions(env, fixed), 2_000_400)
    obs, info = FixedOptions(env, fixed).reset(seed=2_000_400)  # the climb's start: the speed it scales with
    speed = Reading.of(obs, env.unwrapped.limits, info).speed_m_s
    assert scaled[0].frequency_hz == pytest.approx(speed_scaled_frequency(plain[0].frequency_hz, 12.0, speed, LIMITS),
                                                   rel=FREQUENCY_RTOL)
    assert scaled[0].frequency_hz > plain[0].frequency_hz
    assert scaled[0].amplitude_nm / scaled[0].dc_nm == pytest.approx(plain[0].amplitude_nm / plain[0].dc_nm, rel=1e-5)
    with pytest.raises(ValueError, match="frequency_references_m_s"):
        ClimbDraws(frequency_references_m_s=(40.0, 10.0))
