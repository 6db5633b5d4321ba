"""A modulation frequency clear of the wheelset's rotation harmonics (phase_rule.rotation_clear_frequency,
``phase-rule-rotation``, ``interrogator-rotation``): its arithmetic, its refusals, and the phase rule and the learned
interrogator driving it from the speed they measured."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from cof_gym.agents.interrogator import ClimbParameters
from cof_gym.agents.phase_rule import (
    RIPPLE_SE, ROTATION_HARMONICS, ROTATION_MARGIN_HZ, ROTATION_SIDE, ROTATION_SIDES, PhaseRule, ripple_possible,
    rotation_clear_frequency, rotation_frequency_hz,
)
from cof_gym.agents.registry import AGENTS, default_agents, make_agent
from cof_gym.agents.runaway import RunawayEstimate
from cof_gym.measurement.sine_fit import NO_SE_DEG
from cof_gym.task.interface import MotorLimits, decode_action, window_reading

LIMITS = MotorLimits(max_dc_torque_nm=10_000.0)
NOMINAL_HZ = 5.0
# the action carries the frequency as a float32 on a log scale over the drive's 1-20 Hz (ln 20 = 3.0): a few float32
# epsilons (1.2e-7) times that scale (as tests/test_speed_scaled_frequency.py)
FREQUENCY_RTOL = 1e-5
GRID = np.arange(LIMITS.min_frequency_hz, LIMITS.max_frequency_hz + 1e-9, 1e-3)  # a brute-force search's frequencies


def coincidence_speed(harmonic: int, frequency_hz: float = NOMINAL_HZ) -> float:
    """The speed (m/s) at which the ``harmonic``-th harmonic of the rotation is ``frequency_hz`` on LIMITS' wheel."""
    return frequency_hz * 2.0 * math.pi * LIMITS.wheel_radius_m / harmonic


def distance_to_harmonics(frequency_hz: float, speed_m_s: float) -> float:
    rotation = rotation_frequency_hz(speed_m_s, LIMITS)
    return min(abs(frequency_hz - k * rotation) for k in ROTATION_HARMONICS)


def test_the_rotation_frequency_is_the_speed_over_the_wheels_circumference():
    assert rotation_frequency_hz(14.0, LIMITS) == pytest.approx(14.0 / (2 * math.pi * 0.46), rel=1e-15)
    assert distance_to_harmonics(NOMINAL_HZ, coincidence_speed(1)) == pytest.approx(0.0, abs=1e-12)


def test_only_the_runouts_own_harmonic_is_kept_clear_of():
    """The period method's second harmonic is of order e^2: a tone at twice the rotation frequency stays."""
    assert ROTATION_HARMONICS == (1,)
    assert rotation_clear_frequency(NOMINAL_HZ, coincidence_speed(2), 1.0, LIMITS) == NOMINAL_HZ


@pytest.mark.parametrize("side", ROTATION_SIDES)
def test_a_clear_frequency_or_no_margin_stays(side):
    assert distance_to_harmonics(NOMINAL_HZ, 10.0) > 1.5  # 3.46 Hz and 6.92 Hz
    assert rotation_clear_frequency(NOMINAL_HZ, 10.0, 1.5, LIMITS, side) == NOMINAL_HZ
    assert rotation_clear_frequency(NOMINAL_HZ, coincidence_speed(1), 0.0, LIMITS, side) == NOMINAL_HZ


@pytest.mark.parametrize("side", ROTATION_SIDES)
@pytest.mark.parametrize("margin", [0.5, 1.0, 1.5])
@pytest.mark.parametrize("speed", [4.0, 6.5, coincidence_speed(2), 7.6, 12.0, coincidence_speed(1), 16.0, 40.0])
def test_the_frequency_is_the_nearest_clear_one_on_its_side(side, margin, speed):
    """A brute-force search over the drive's range at 1 mHz: no frequency on the allowed side that keeps the margin
    from every harmonic lies nearer the nominal one (to the grid's step), and the one chosen keeps it; where none
    does, the nominal one stays."""
    chosen = rotation_clear_frequency(NOMINAL_HZ, speed, margin, LIMITS, side)
    rotation = rotation_frequency_hz(speed, LIMITS)
    clear = np.min([np.abs(GRID - k * rotation) for k in ROTATION_HARMONICS], axis=0) >= margin
    if side == "below":
        clear &= GRID <= NOMINAL_HZ
    elif side == "above":
        clear &= GRID >= NOMINAL_HZ
    if not clear.any():
        assert chosen == NOMINAL_HZ
        return
    assert LIMITS.min_frequency_hz <= chosen <= LIMITS.max_frequency_hz
    assert distance_to_harmonics(chosen, speed) >= margin * (1 - 1e-12)
    if side != "nearest" and chosen != NOMINAL_HZ:
        assert (chosen < NOMINAL_HZ) == (side == "below")
    assert np.all(np.abs(GRID[clear] - NOMINAL_HZ) >= abs(chosen - NOMINAL_HZ) - 1e-3 - 1e-12)


def test_at_a_coincidence_the_nearest_side_moves_up_on_a_tie():
    speed = coincidence_speed(1)  # the rotation at 5 Hz, twice it at 10 Hz: 4 and 6 Hz both 1 Hz away
    assert rotation_clear_frequency(NOMINAL_HZ, speed, 1.0, LIMITS) == pytest.approx(6.0, rel=1e-12)
    assert rotation_clear_frequency(NOMINAL_HZ, speed, 1.0, LIMITS, "below") == pytest.approx(4.0, rel=1e-12)


@pytest.mark.parametrize("speed", [0.0, -3.0, math.nan, math.inf])
def test_a_speed_that_is_not_a_positive_finite_number_keeps_the_frequency(speed):
    assert rotation_clear_frequency(NOMINAL_HZ, speed, 1.0, LIMITS) == NOMINAL_HZ


def test_no_clear_edge_keeps_the_frequency():
    # a margin of 20 Hz covers the drive's whole 1-20 Hz range from the rotation at 5 Hz
    assert rotation_clear_frequency(NOMINAL_HZ, coincidence_speed(1), 20.0, LIMITS) == NOMINAL_HZ


def test_a_bad_side_names_the_field():
    with pytest.raises(ValueError, match="side"):
        rotation_clear_frequency(NOMINAL_HZ, 14.0, 1.0, LIMITS, "left")
    with pytest.raises(ValueError, match="PhaseRule.rotation_side"):
        PhaseRule(LIMITS, rotation_side="left")


@pytest.mark.parametrize("value", [-1.0, math.nan, math.inf, True, "1"])
def test_a_bad_margin_names_the_field(value):
    with pytest.raises(ValueError, match="PhaseRule.rotation_margin_hz"):
        PhaseRule(LIMITS, rotation_margin_hz=value)


def test_registered_as_an_option_not_a_default(env):
    agent = make_agent("phase-rule-rotation", env)
    assert isinstance(agent, RunawayEstimate) and isinstance(agent.agent, PhaseRule)
    assert agent.agent.rotation_margin_hz == ROTATION_MARGIN_HZ > 0.0 and not agent.oracle
    assert agent.agent.rotation_side == ROTATION_SIDE
    assert "phase-rule-rotation" in AGENTS and "phase-rule-rotation" not in default_agents()
    assert make_agent("phase-rule", env).agent.rotation_margin_hz == 0.0  # the shipped rule: 5 Hz always


@pytest.mark.parametrize("speed", [coincidence_speed(1), 10.0])
def test_every_window_is_modulated_clear_of_the_harmonics_of_the_speed_it_measured(env, speed):
    """Every action of an episode carries the frequency chosen from the reset observation's measured speed (the speed
    sensor's error included, never the true speed); the shipped rule's is 5 Hz at any speed."""
    limits = env.unwrapped.limits
    for margin, expected_moved in ((ROTATION_MARGIN_HZ, speed != 10.0), (0.0, False)):
        agent = PhaseRule(limits, rotation_margin_hz=margin)
        obs, info = env.reset(seed=5, options={"speed_m_s": speed, "speed_sensor_error": 0.01})
        measured = window_reading(obs, "speed")
        assert measured != pytest.approx(speed, rel=1e-3)  # the sensor's error is in the reading
        expected = rotation_clear_frequency(NOMINAL_HZ, measured, margin, limits)
        assert (expected != NOMINAL_HZ) == expected_moved
        agent.reset(obs, info)
        for _ in range(4):
            action = agent.act(obs, info)
            assert decode_action(action, limits).drive.frequency_hz == pytest.approx(expected, rel=FREQUENCY_RTOL)
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break


def test_the_interrogators_climb_moves_its_frequency_as_the_phase_rule_does():
    """ClimbParameters.rotation_margin_hz: the frequency at a measured speed is rotation_clear_frequency's on the
    nearest side; None (the shipped climb) keeps frequency_hz at any speed."""
    speed = coincidence_speed(1)
    assert ClimbParameters().frequency_at(speed, LIMITS) == NOMINAL_HZ
    moved = ClimbParameters(rotation_margin_hz=1.0).frequency_at(speed, LIMITS)
    assert moved == rotation_clear_frequency(NOMINAL_HZ, speed, 1.0, LIMITS) == pytest.approx(6.0, rel=1e-12)


@pytest.mark.parametrize("side", ROTATION_SIDES)
@pytest.mark.parametrize("speed", [coincidence_speed(1) - 1.0, coincidence_speed(1), coincidence_speed(1) + 1.0])
def test_the_climb_moves_to_its_side_as_the_phase_rule_does(side, speed):
    climb = ClimbParameters(rotation_margin_hz=1.0, rotation_side=side)
    assert climb.frequency_at(speed, LIMITS) == rotation_clear_frequency(NOMINAL_HZ, speed, 1.0, LIMITS, side)


@pytest.mark.parametrize("value", [0.0, -1.0, 10.5, math.nan, True])
def test_a_bad_climb_margin_names_the_field(value):
    with pytest.raises(ValueError, match="rotation_margin_hz"):
        ClimbParameters(rotation_margin_hz=value)
    with pytest.raises(ValueError, match="rotation_side"):
        ClimbParameters(rotation_side="left")


def test_the_interrogator_variant_is_the_shipped_one_with_the_margin(env):
    """``interrogator-rotation``: the shipped networks and climb, only its rotation margin set; not a default."""
    from cof_gym.agents.interrogator.agent import (
        INTERROGATOR_ROTATION_MARGIN_HZ, INTERROGATOR_ROTATION_RIPPLE_MAX_SE_DEG, INTERROGATOR_ROTATION_SIDE,
    )

    shipped, variant = make_agent("interrogator", env), make_agent("interrogator-rotation", env)
    assert variant.name == "interrogator-rotation" and "interrogator-rotation" not in default_agents()
    assert shipped.params.rotation_margin_hz is None
    assert variant.params == replace(shipped.params, rotation_margin_hz=INTERROGATOR_ROTATION_MARGIN_HZ,
                                     rotation_side=INTERROGATOR_ROTATION_SIDE,
                                     rotation_ripple_max_se_deg=INTERROGATOR_ROTATION_RIPPLE_MAX_SE_DEG)


@pytest.mark.parametrize("se_deg, max_se_deg, possible", [
    (1.0, 5.0, True), (5.0, 5.0, True), (20.0, 5.0, False), (179.9, 5.0, False),  # read: a clear ripple, or none
    (180.0, 5.0, True),  # not read (the plain lock-in, a harmonic left out at the tone): it may be there
    (20.0, 180.0, True), (0.0, 0.0, True),  # no gate; a ripple read exactly
])
def test_a_ripple_is_ruled_out_only_where_the_rotation_lock_in_read_none(se_deg, max_se_deg, possible):
    assert ripple_possible({"measurement": {RIPPLE_SE: se_deg}}, max_se_deg) is possible
    assert ripple_possible({}, max_se_deg) and ripple_possible(None, max_se_deg)  # no reading: not ruled out


GATE_ENV_SPEED_M_S = 17.05  # the rotation at 5.9 Hz: within a 1 Hz margin of 5 Hz, far enough for the lock-in to read


@pytest.fixture(scope="module")
def rotation_env():
    import gymnasium as gym

    import cof_gym

    env = gym.make(cof_gym.WAGON_ENV_ID, lock_in="rotation")
    yield env
    env.close()


@pytest.mark.parametrize("speed, runout, gated_moves", [
    (GATE_ENV_SPEED_M_S, 0.0005, True),  # the ripple read clearly (a phase SE of about 1 deg)
    (GATE_ENV_SPEED_M_S, 0.0, False),  # none read (its SE tens of degrees)
    (coincidence_speed(1), 0.0, True),  # the harmonic left out at the tone: not read, so not ruled out
])
def test_the_gated_agents_move_only_where_the_reset_window_leaves_a_ripple_possible(rotation_env, speed, runout,
                                                                                    gated_moves):
    """rotation_ripple_max_se_deg (5 deg here): the phase rule and the interrogator's climb move their frequency where
    the reset window's rotation lock-in reads the ripple's phase to within it, or cannot read it; the ungated ones
    wherever the margin asks."""
    limits = rotation_env.unwrapped.limits
    obs, info = rotation_env.reset(seed=5, options={"speed_m_s": speed, "encoder_runout": runout})
    measured = window_reading(obs, "speed")
    moved = rotation_clear_frequency(NOMINAL_HZ, measured, 1.0, limits)
    assert moved != NOMINAL_HZ
    for max_se, expected in ((NO_SE_DEG, moved), (5.0, moved if gated_moves else NOMINAL_HZ)):
        rule = PhaseRule(limits, rotation_margin_hz=1.0, rotation_ripple_max_se_deg=max_se)
        rule.reset(obs, info)
        assert decode_action(rule.act(obs, info), limits).drive.frequency_hz == pytest.approx(expected,
                                                                                             rel=FREQUENCY_RTOL)
        climb = ClimbParameters(rotation_margin_hz=1.0, rotation_ripple_max_se_deg=max_se)
        assert climb.frequency_at(measured, limits, ripple_possible(info, max_se)) == expected


@pytest.mark.parametrize("value", [-1.0, 180.5, math.nan, math.inf, True, None])
def test_a_bad_ripple_gate_names_the_field(value):
    with pytest.raises(ValueError, match="PhaseRule.rotation_ripple_max_se_deg"):
        PhaseRule(LIMITS, rotation_ripple_max_se_deg=value)
    with pytest.raises(ValueError, match="rotation_ripple_max_se_deg"):
        ClimbParameters(rotation_ripple_max_se_deg=value)
