"""The learned interrogator's climb (cof_gym/agents/interrogator/climb.py, as the agent steps it): steps, the slow
probe, the floor jump, knee and crest stops, the crest's floor and ceiling, the runaway estimate, the probe past
the headroom stop."""

from __future__ import annotations

import math
from dataclasses import replace

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.commands.suites import make_suite
from cof_gym.task.scenarios import COF_ENVELOPE
from cof_gym.agents.interrogator import (
    CREST_RATIO_FLOOR, SHIPPED_INTERROGATOR, ClimbParameters, FilterEnsemble, LearnedInterrogator, Reading,
    floor_headroom, interrogator_for, manifest_climb,
)
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.agents.base import agent_view
from cof_gym.agents.interrogator.readings import creep_elasticity
from cof_gym.agents.runaway import CrestCeiling, RunawayBracket
from cof_gym.task.interface import MotorLimits, decode_action
from exact_sensors import QUIET
from interrogator_helpers import SHIPPED, window_reading, constant_network, play, random_network

def test_spread_caution_takes_the_members_disagreement_off_the_headroom_and_nothing_when_zero():
    shipped = ClimbParameters(caution=2.0)
    assert shipped.cautious_headroom(0.5, 0.1, spread=0.3) == 0.5 - 2.0 * 0.1  # 0: the climb is unchanged
    wary = replace(shipped, spread_caution=3.0, creep_log_step=0.03, creep_while_std=0.08, creep_until=0.12)
    assert wary.cautious_headroom(0.5, 0.1, spread=0.05) == pytest.approx(0.5 - 0.2 - 0.15, abs=1e-15)
    # the slow probe's end reads the mean headroom, which the spread caution does not move: 0.13 > 0.12
    assert wary.creeps(wary.cautious_headroom(0.13, 0.1, 0.05), 0.1, 0.05)
    assert not wary.creeps(wary.cautious_headroom(0.11, 0.1, 0.05), 0.1, 0.05)


@pytest.mark.parametrize("kwargs, field", [({"estimate_from": "median"}, "estimate_from"),
                                            ({"amplitude_ratio": float("nan")}, "amplitude_ratio"),
                                            ({"best_coa_factor": -1.0}, "best_coa_factor"),
                                            ({"spread_caution": -0.5}, "spread_caution"),
                                            ({"caution": -1.0}, "caution"),
                                            ({"target_headroom": float("inf")}, "target_headroom"),
                                            ({"crest_floor": "yes"}, "crest_floor"),
                                            ({"runaway_estimate": 1}, "runaway_estimate"),
                                            ({"creep_sticky": 1}, "creep_sticky"),
                                            ({"guard_cautions": [2.0, -1.0]}, r"guard_cautions\[1\]"),
                                            ({"guard_cautions": []}, "guard_cautions"),
                                            ({"guard_cautions": 2.0}, "guard_cautions"),
                                            ({"guard_cautions": ["2"]}, r"guard_cautions\[0\]"),
                                            ({"noise_reference_nms": 0.0}, "noise_reference_nms"),
                                            ({"noise_caution_exponent": 3.0}, "noise_caution_exponent"),
                                            ({"noise_creep_exponent": -1.0}, "noise_creep_exponent")])
def test_bad_climb_parameters_name_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        ClimbParameters(**kwargs)


def test_climb_step_is_the_cautious_gap_capped_near_and_far_from_the_peak():
    near = ClimbParameters(target_headroom=0.05, max_log_step=0.15)
    assert near.log_step(0.12) == pytest.approx(0.07, rel=1e-12)  # the gap itself, below the cap
    assert near.log_step(3.0) == 0.15  # capped
    assert near.log_step(0.01) < 0.0  # past the target: the climb stops (smaller than min_log_step)
    far = ClimbParameters(target_headroom=0.05, max_log_step=0.15, approach_fraction=0.5)
    assert far.log_step(3.05) == pytest.approx(1.5, rel=1e-12)  # half the gap far from the peak
    assert far.log_step(0.3) == 0.15 and far.log_step(0.12) == pytest.approx(0.07, rel=1e-12)
    with pytest.raises(ValueError, match="approach_fraction"):
        ClimbParameters(approach_fraction=1.0)


def test_an_uncertain_headroom_creeps_instead_of_stopping():
    """Where the cautious gap is closed, the climb stops only once the predicted headroom is certain
    (std at most creep_while_std); before that it creeps by creep_log_step. Off by default."""
    creeping = ClimbParameters(target_headroom=0.05, max_log_step=0.15, creep_log_step=0.03, creep_while_std=0.08)
    assert creeping.log_step(0.06, headroom_std=0.2) == 0.03  # gap 0.01 < min_log_step, uncertain: creep
    assert creeping.log_step(0.06, headroom_std=0.05) == pytest.approx(0.01, rel=1e-12)  # certain: stop
    assert creeping.log_step(0.12, headroom_std=0.2) == pytest.approx(0.07, rel=1e-12)  # open gap: unchanged
    assert ClimbParameters(target_headroom=0.05).log_step(0.06, headroom_std=0.2) == pytest.approx(0.01, rel=1e-12)
    with pytest.raises(ValueError, match="creep_log_step"):
        ClimbParameters(max_log_step=0.15, creep_log_step=0.2)
    with pytest.raises(ValueError, match="creep_while_std"):
        ClimbParameters(creep_while_std=0.0)


class _ScriptedFilter:
    """A stand-in ensemble whose predicted (headroom, correction) means and stds follow a script."""

    tones, blocks = 1, ()

    def __init__(self, script: list[tuple[float, float]]):
        self.script = iter(script)

    def predict(self, x):
        mean, std = next(self.script)
        return np.array([[mean, 0.0]]), np.array([[std, 0.01]])

    def predict_with_spread(self, x):
        return *self.predict(x), np.zeros((1, 2))


def _creep_then_open_gap_steps(env, second_std: float = 0.01, **climb) -> tuple[float, float]:
    """The log steps of the DC torque after window 1 (mean headroom 0.26, std 0.2: a cautious gap of 0.01,
    closed and uncertain: a creep) and window 2 (mean 1, std ``second_std``: an open gap), with max_log_step
    0.15, creep_log_step 0.03 and ``climb``."""
    params = ClimbParameters(target_headroom=0.05, max_log_step=0.15, creep_log_step=0.03, creep_while_std=0.08,
                             caution=1.0, **climb)
    agent = LearnedInterrogator(env.unwrapped.limits, _ScriptedFilter([(0.26, 0.2), (1.0, second_std)]), params=params)
    obs, info = env.reset(seed=5)
    agent.reset(obs, info)
    dcs = []
    for _ in range(3):
        obs, _, _, _, info = env.step(agent.act(obs, info))
        dcs.append(agent.dc_nm)
    return math.log(dcs[1] / dcs[0]), math.log(dcs[2] / dcs[1])


@pytest.mark.parametrize("sticky", [False, True])
def test_a_sticky_creep_takes_no_big_step_after_it_crept(env, sticky):
    """After an uncertain, closed gap (a creep), a confident, open gap allows max_log_step again, unless
    creep_sticky holds the climb to creep_log_step from then on."""
    creep, after = _creep_then_open_gap_steps(env, creep_sticky=sticky)
    assert creep == pytest.approx(0.03, rel=1e-9)
    assert after == pytest.approx(0.03 if sticky else 0.15, rel=1e-9)
    with pytest.raises(ValueError, match="creep_sticky"):
        ClimbParameters(creep_sticky=1)


@pytest.mark.parametrize("release, big_step", [(None, False), (0.9, True), (0.995, False)])
def test_a_sticky_creep_lets_go_once_the_cautious_headroom_is_above_its_release(env, release, big_step):
    """creep_release: a sticky climb takes max_log_step again only where the cautious headroom (here
    1 - 0.01 = 0.99 after the creep) is above the release; below it, or unset, it stays slow."""
    creep, after = _creep_then_open_gap_steps(env, creep_sticky=True, creep_release=release)
    assert creep == pytest.approx(0.03, rel=1e-9)
    assert after == pytest.approx(0.15 if big_step else 0.03, rel=1e-9)
    params = ClimbParameters(creep_log_step=0.03, creep_sticky=True, creep_release=release)
    assert params.sticks(True, 0.5) and not params.sticks(False, 0.5)
    with pytest.raises(ValueError, match="creep_release"):
        ClimbParameters(creep_release=-0.1)


@pytest.mark.parametrize("pace, after", [(None, 0.03), (0.0, 0.95 / 27), (1.0, 0.03)])
def test_a_paced_slow_probe_spreads_the_predicted_headroom_over_the_windows_left(env, pace, after):
    """pace_caution: after its creep, a sticky climb's step is at least (mean - pace_caution x std - target)
    over the windows left before the horizon (here (1 - 0.05) / 27 = 0.035 with pace_caution 0; with 1,
    (1 - 0.2 - 0.05) / 27 = 0.028 is below the creep step, which stands)."""
    creep, step = _creep_then_open_gap_steps(env, second_std=0.2, creep_sticky=True, pace_caution=pace)
    assert creep == pytest.approx(0.03, rel=1e-9)
    assert step == pytest.approx(after, rel=1e-9)
    assert ClimbParameters(pace_caution=0.0, max_log_step=0.15).pace_step(3.0, 0.0, 0.0, 2) == 0.15  # capped
    with pytest.raises(ValueError, match="pace_caution"):
        ClimbParameters(pace_caution=-0.5)


def test_pacing_never_turns_a_stop_into_a_step(env):
    """With one window left before the horizon, a certain headroom (std 0.05 < creep_while_std) whose cautious
    gap is closed stops the paced climb on its headroom, although the pace (0.06) exceeds min_log_step."""
    params = ClimbParameters(target_headroom=0.05, max_log_step=0.15, creep_log_step=0.03, creep_while_std=0.08,
                             caution=1.0, creep_sticky=True, pace_caution=0.0)
    agent = LearnedInterrogator(env.unwrapped.limits, _ScriptedFilter([(0.26, 0.2), (0.11, 0.05)]), params=params,
                                max_windows=4)
    obs, info = env.reset(seed=5)
    agent.reset(obs, info)
    for _ in range(3):
        action = agent.act(obs, info)
        if decode_action(action, agent.limits).stop:
            break
        obs, _, _, _, info = env.step(action)
    assert agent.stop_reason == "headroom" and agent.crept
    assert params.pace_step(0.06, 0.05, 0.0, 1) == pytest.approx(0.06, rel=1e-12)


@pytest.mark.parametrize("knee_stop, driven, crept, previous, reading, stops", [
    (None, 5, True, (20.0, 1.0), (40.0, 1.0), False),  # unused
    ("any", 5, False, (20.0, 1.0), (40.0, 1.0), True),  # a 20 deg jump, 2 x hypot(1, 1) = 2.8 deg of noise
    ("any", 2, False, (20.0, 1.0), (40.0, 1.0), False),  # within the phase rule's baseline windows
    ("any", 5, False, (20.0, 1.0), (26.0, 1.0), False),  # 6 - 2.83 = 3.2 deg: below the 4 deg jump
    ("any", 5, False, (20.0, 1.0), (27.0, 1.0), True),  # 7 - 2.83 = 4.2 deg
    ("any", 5, False, (20.0, 1.0), (60.0, 6.0), False),  # SE above 5 deg: uninformative
    ("any", 5, False, (40.0, 1.0), (20.0, 1.0), False),  # a fall is no knee
    ("slow_probe", 5, False, (20.0, 1.0), (40.0, 1.0), False),  # not crept yet
    ("slow_probe", 5, True, (20.0, 1.0), (40.0, 1.0), True),
])
def test_the_knee_stop_is_the_phase_rules_jump_test(knee_stop, driven, crept, previous, reading, stops):
    """knee_stop ends the climb where the phase rule would see its knee: the lag over the previous window's
    by more than 4 deg beyond 2 SEs of both (SE at most 5 deg), after its 2 baseline windows; "slow_probe"
    only once the climb has crept."""
    params = ClimbParameters(knee_stop=knee_stop)
    assert params.knee_stops(window_reading(*reading), window_reading(*previous), driven, crept) is stops
    with pytest.raises(ValueError, match="knee_stop"):
        ClimbParameters(knee_stop="always")


def test_a_knee_stop_reports_the_headroom_stops_estimate(env):
    """A climb ended by the knee test reports what a headroom stop reports ("pooled_at_headroom": the pooled
    estimate), the same as its "pooled" source; before a stop it reports the filter's."""
    agent = LearnedInterrogator(env.unwrapped.limits, _ScriptedFilter([]), params=ClimbParameters(knee_stop="any"))
    obs, info = env.reset(seed=5)
    agent.reset(obs, info)
    agent._source_estimates = {"filter": 0.1, "pooled": 0.12}
    assert agent.candidate_estimates(1.0)["pooled_at_headroom"] == 0.1
    agent.stop_reason = "knee"
    assert agent.candidate_estimates(1.0)["pooled_at_headroom"] == 0.12


@pytest.mark.parametrize("cof, condition, load_case", [(0.02, "low_adhesion", "empty"), (0.02, "low_adhesion", "laden"),
                                                       (0.6, "dry", "laden")])
def test_the_floor_step_jumps_to_the_lowest_cof_and_never_past_its_peak(env, cof, condition, load_case):
    """With floor_margin, the step out of a window is ln(CoF_min / CoA) - target - margin whatever the
    filter predicts: from the first DC it lands below the saturation torque of the lowest CoF the task
    admits (here that CoF itself, exact sensors), and at a high CoF several times above the first DC."""
    params = ClimbParameters(floor_margin=0.2, target_headroom=0.1)
    no_headroom = [(0.0, 1.0)]  # the filter's (mean, std): without the floor the climb stops at once
    agent = LearnedInterrogator(env.unwrapped.limits, _ScriptedFilter(no_headroom), params=params)
    options = {"condition": condition, "cof": cof, "load_case": load_case, "speed_m_s": 20.0, "speed_sensor_error": 0.0,
               "wheel_radius_error": 0.0, "force_gain_error": 0.0, "torque_gain_error": 0.0}
    obs, info = env.reset(seed=3, options=options)
    m_sat = info["ground_truth"]["saturation_torque_nm"]
    agent.reset(obs, {})
    obs, _, _, _, info = env.step(agent.act(obs, {}))
    first = agent._dc
    agent.act(obs, {})
    coa = agent.features.readings[0].coa
    assert math.log(agent._dc / first) == pytest.approx(floor_headroom(coa) - 0.3, rel=1e-12, abs=1e-12)
    assert agent._dc < m_sat * COF_ENVELOPE[0] / cof
    if cof > 0.1:
        assert agent._dc > 3.0 * first
    plain = LearnedInterrogator(env.unwrapped.limits, _ScriptedFilter(no_headroom),
                                params=ClimbParameters(target_headroom=0.1))
    obs, info = env.reset(seed=3, options=options)
    plain.reset(obs, {})
    obs, _, _, _, info = env.step(plain.act(obs, {}))
    plain.act(obs, {})
    assert plain._dc == first and plain.stop_reason == "headroom"
    with pytest.raises(ValueError, match="floor_margin"):
        ClimbParameters(floor_margin=-0.1)


def test_the_slow_probe_ends_where_the_predicted_headroom_reaches_creep_until():
    """creep_until stops the creep once the mean headroom (cautious + caution x std) is that low."""
    params = ClimbParameters(target_headroom=0.1, caution=2.0, creep_log_step=0.03, creep_while_std=0.08,
                             creep_until=0.12)
    assert params.log_step(0.1 - 0.4 + 0.13, headroom_std=0.2) == 0.03  # mean 0.53: creeps
    assert params.creeps(0.13 - 2.0 * 0.2, 0.2)  # mean 0.13 > 0.12: creeps
    assert not params.creeps(0.11 - 2.0 * 0.2, 0.2)  # mean 0.11: stops (the gap is closed)
    assert params.log_step(0.11 - 2.0 * 0.2, headroom_std=0.2) < params.min_log_step
    assert replace(params, creep_until=None).creeps(0.11 - 2.0 * 0.2, 0.2)
    with pytest.raises(ValueError, match="creep_until"):
        ClimbParameters(creep_until=float("inf"))


def test_the_slow_probe_ends_where_the_cautious_headroom_falls_below_creep_cautious_floor():
    """creep_cautious_floor stops the creep once the cautious (steering) headroom itself is below it, whatever the
    mean headroom still says; the step there is a headroom stop (below min_log_step)."""
    params = ClimbParameters(target_headroom=0.1, caution=2.0, creep_log_step=0.03, creep_while_std=0.08,
                             creep_until=0.12, creep_cautious_floor=0.0)
    assert params.creeps(0.0, 0.25)  # at the floor (mean 0.5): creeps
    assert params.log_step(0.0, headroom_std=0.25) == 0.03
    assert not params.creeps(-0.01, 0.25)  # below it, the mean (0.49) far above creep_until: stops
    assert params.log_step(-0.01, headroom_std=0.25) < params.min_log_step
    assert replace(params, creep_cautious_floor=None).creeps(-0.01, 0.25)
    assert replace(params, creep_cautious_floor=-0.05).creeps(-0.01, 0.25)
    for bad in (float("nan"), 5.5, "0"):
        with pytest.raises(ValueError, match="creep_cautious_floor"):
            ClimbParameters(creep_cautious_floor=bad)


def test_a_noisier_reading_lowers_the_cautions_and_raises_the_slow_probes_threshold():
    params = ClimbParameters(caution=2.0, guard_cautions=[1.0, 3.0], creep_while_std=0.1, noise_reference_nms=0.4,
                             noise_caution_exponent=0.5, noise_creep_exponent=1.0)
    assert params.at_noise(1.0) is params
    noisy = params.at_noise(4.0)
    assert (noisy.caution, *noisy.guard_cautions) == pytest.approx((1.0, 0.5, 1.5), rel=1e-12)
    assert noisy.creep_while_std == pytest.approx(0.4, rel=1e-12)
    assert replace(noisy, caution=2.0, guard_cautions=(1.0, 3.0), creep_while_std=0.1) == params  # nothing else
    limits = gym.make(cof_gym.WAGON_ENV_ID).unwrapped.limits
    unsure = FilterEnsemble((constant_network(0.5, 0.2, log_variance=-2.0),))  # std e^-1: 0.5 - 2 x 0.37 < 0
    climbs = {reference: play(LearnedInterrogator(limits, unsure, params=ClimbParameters(
        caution=2.0, noise_reference_nms=reference, noise_caution_exponent=1.0)), 8)[0] for reference in (None, 1e6, 1e-6)}
    np.testing.assert_array_equal(climbs[1e6], climbs[None])  # never above the reference: nothing changes
    assert len(climbs[None]) == 2 and len(climbs[1e-6]) > 3  # far above it the caution vanishes and it climbs


def test_the_crest_ratio_keeps_the_crest_below_the_cautious_saturation_torque():
    """With crest_fraction f the modulation ratio is at most exp(f h) - 1 for the cautious headroom h
    after the step, at least CREST_RATIO_FLOOR, at most amplitude_ratio; unset, always amplitude_ratio."""
    capped = ClimbParameters(amplitude_ratio=0.4, crest_fraction=1.0)
    assert capped.crest_ratio(0.1) == pytest.approx(math.expm1(0.1), rel=1e-12)  # crest at the cautious M_sat
    assert ClimbParameters(amplitude_ratio=0.4, crest_fraction=0.5).crest_ratio(0.1) == pytest.approx(math.expm1(0.05))
    assert capped.crest_ratio(2.0) == 0.4 and capped.crest_ratio(-0.3) == CREST_RATIO_FLOOR
    assert ClimbParameters(amplitude_ratio=0.4).crest_ratio(0.1) == 0.4
    with pytest.raises(ValueError, match="crest_fraction"):
        ClimbParameters(crest_fraction=-0.1)
    slow_only = ClimbParameters(amplitude_ratio=0.4, crest_fraction=1.0, crest_below_m_s=12.0)
    assert slow_only.crest_ratio(0.1, speed_m_s=8.0) == capped.crest_ratio(0.1)  # below: capped
    assert slow_only.crest_ratio(0.1, speed_m_s=12.0) == 0.4  # at or above: the full modulation
    with pytest.raises(ValueError, match="crest_below_m_s"):
        ClimbParameters(crest_below_m_s=0.0)


def test_a_crest_cap_below_a_speed_leaves_every_faster_climb_as_it_was():
    """crest_below_m_s: a climb whose starting speed is at or above it is the uncapped climb, action for action."""
    from dataclasses import replace

    from cof_gym.agents.interrogator.agent import SHIPPED_INTERROGATOR, interrogator_for, manifest_climb

    env = gym.make(cof_gym.WAGON_ENV_ID)
    shipped = manifest_climb(SHIPPED_INTERROGATOR)
    actions = {}
    for name, params in (("plain", shipped), ("slow_only", replace(shipped, crest_fraction=1.0, crest_below_m_s=5.0))):
        agent = interrogator_for(env, SHIPPED_INTERROGATOR, params)
        obs, info = env.reset(seed=3)  # the default draws: every speed at least 5 m/s
        agent.reset(obs, info)
        taken = []
        for _ in range(30):
            action = agent.act(obs, info)
            taken.append(action.copy())
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break
        actions[name] = np.array(taken)
    env.close()
    np.testing.assert_array_equal(actions["plain"], actions["slow_only"])


def test_a_crest_capped_climb_shrinks_its_modulation_as_the_headroom_closes():
    """The same climb (same DC torques) with crest_fraction: each window's amplitude is the ratio its
    cautious headroom after the step allows, times its DC; the first window's is amplitude_ratio's."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    ensemble = FilterEnsemble((constant_network(0.3, 0.0, log_variance=math.log(0.05**2)),))
    plain = ClimbParameters(amplitude_ratio=0.4, target_headroom=0.05, max_log_step=0.1, caution=1.0)
    free, _ = play(LearnedInterrogator(limits, ensemble, params=plain), 8)
    capped, _ = play(LearnedInterrogator(limits, ensemble, params=replace(plain, crest_fraction=1.0)), 8)
    np.testing.assert_array_equal(capped[:, 0], free[:, 0])  # the DC torques
    amplitudes = [decode_action(a, limits).drive.amplitude_nm for a in capped]
    dcs = [decode_action(a, limits).drive.dc_torque_nm for a in capped]
    assert amplitudes[0] == pytest.approx(0.4 * dcs[0], rel=1e-4)
    assert amplitudes[1] == pytest.approx(math.expm1(0.25 - math.log(dcs[1] / dcs[0])) * dcs[1], rel=1e-4)
    assert amplitudes[1] < 0.4 * dcs[1]


def test_a_crest_cap_once_crept_leaves_the_approach_alone(env):
    """With crest_once_crept the cap bites only from the first slow probe on: a big step far from the
    peak keeps amplitude_ratio even where the cap would shrink it; the creep's window is capped."""
    params = ClimbParameters(amplitude_ratio=0.4, target_headroom=0.05, max_log_step=0.15, creep_log_step=0.03,
                             creep_while_std=0.08, caution=1.0, crest_fraction=1.0, crest_once_crept=True)
    # window 1: cautious headroom 0.39, step 0.15 (the cap would allow expm1(0.24) = 0.27 < 0.4);
    # window 2: cautious headroom 0.06, uncertain: a creep of 0.03, capped at expm1(0.03) -> the 3 % floor
    agent = LearnedInterrogator(env.unwrapped.limits, _ScriptedFilter([(0.40, 0.01), (0.26, 0.2)]), params=params)
    obs, info = env.reset(seed=5)
    agent.reset(obs, info)
    drives = []
    for _ in range(3):
        action = agent.act(obs, info)
        drives.append(decode_action(action, agent.limits).drive)
        obs, _, _, _, info = env.step(action)
    limits = agent.limits
    assert drives[1].amplitude_nm == pytest.approx(params.amplitude(drives[1].dc_torque_nm, limits, 0.4), rel=1e-4)
    assert drives[2].amplitude_nm == pytest.approx(
        params.amplitude(drives[2].dc_torque_nm, limits, CREST_RATIO_FLOOR), rel=1e-4)
    always = replace(params, crest_once_crept=False)
    assert always.crest_ratio(0.24, crept=False) == pytest.approx(math.expm1(0.24))
    assert params.crest_ratio(0.24, crept=False) == 0.4
    with pytest.raises(ValueError, match="crest_once_crept"):
        ClimbParameters(crest_once_crept=1)


def test_the_crest_floor_raises_the_estimate_to_the_best_crest_bound_and_leaves_the_climb_alone():
    """With ``crest_floor`` every source's estimate is at least the largest crest bound of the windows so
    far (the cycle crest of the measured CoA less a bin's standard error, read from info["measurement"]);
    the actions differ in the estimate component only."""
    ensemble = FilterEnsemble((random_network(5), random_network(6)))
    envs = [gym.make(cof_gym.WAGON_ENV_ID) for _ in range(2)]
    agents = [LearnedInterrogator(envs[0].unwrapped.limits, ensemble, params=ClimbParameters(crest_floor=floor))
              for floor in (False, True)]
    observed = [env.reset(seed=8) for env in envs]
    for agent, (obs, info) in zip(agents, observed):
        agent.reset(obs, info)
    best_bound, raised, done = 0.0, 0, False
    while not done:
        actions = [agent.act(obs, info) for agent, (obs, info) in zip(agents, observed)]
        np.testing.assert_array_equal(np.delete(actions[0], 3), np.delete(actions[1], 3))
        plain, floored = (agent.candidate_estimates(1.0) for agent in agents)
        assert floored == {source: max(value, best_bound) for source, value in plain.items()}
        raised += floored["filter"] > plain["filter"]
        steps = [env.step(action) for env, action in zip(envs, actions)]
        observed = [(obs, info) for obs, _, _, _, info in steps]
        m = observed[0][1]["measurement"]
        assert Reading.of(observed[0][0], agents[0].limits, observed[0][1]).crest_bound == \
            max(m["coa_cycle_max"] - m["coa_cycle_bin_se"], 0.0) > 0.0
        best_bound = max(best_bound, m["coa_cycle_max"] - m["coa_cycle_bin_se"])
        done = steps[0][2] or steps[0][3]
    assert raised > 0  # random networks' corrections: the floor binds somewhere, so the test can fail


# a Shen-Hedrick-Elkins curve at a low CoF: a bold climb's crest holds at its peak for windows before the runaway
SHARP_LOW_COF = {"creep_law": {"shen_hedrick_elkins": {"k_stiffness": 1.0, "friction_ratio": 0.4,
                                                       "friction_decay_s_per_m": 0.6}}, "cof": 0.03}


def test_the_crest_ceiling_caps_every_estimate_once_the_crest_falls_and_leaves_the_climb_alone():
    """With ``crest_ceiling`` the actions differ from the plain climb's in the estimate component only; every
    source reads the plain estimate until the crest falls under a rising torque crest (CrestCeiling fed the
    same windows), at most the best crest plus its bin's error from then on. A bold climb on a Shen-Hedrick-
    Elkins curve at a low CoF (noise off) holds its crest at the peak for windows before the wheel runs away:
    the ceiling is reached and binds (the test can fail), and the runaway is scored on the capped estimate,
    within 1 % of the CoF (at the peak the force is stationary in creepage, so the crest's phase bin
    averages it to second order)."""
    bold = FilterEnsemble((constant_network(3.0, 0.3),))
    envs = [gym.make(cof_gym.WAGON_ENV_ID, **QUIET) for _ in range(2)]
    limits = envs[0].unwrapped.limits
    agents = [LearnedInterrogator(limits, bold, params=ClimbParameters(amplitude_ratio=0.4, max_log_step=0.07,
                                                                       runaway_estimate=True, crest_ceiling=cap))
              for cap in (False, True)]
    observed = [env.reset(seed=4, options=SHARP_LOW_COF) for env in envs]
    for agent, (obs, info) in zip(agents, observed):
        agent.reset(obs, agent_view(info, False))
    ceiling, capped, done = CrestCeiling(), 0, False
    while not done:
        actions = [agent.act(obs, agent_view(info, False)) for agent, (obs, info) in zip(agents, observed)]
        np.testing.assert_array_equal(np.delete(actions[0], 3), np.delete(actions[1], 3))
        plain, ceiled = (agent.candidate_estimates(1.0) for agent in agents)
        bound = ceiling.bound
        assert ceiled == (plain if bound is None else {s: min(v, bound) for s, v in plain.items()})
        capped += bound is not None and ceiled["filter"] < plain["filter"]
        steps = [env.step(action) for env, action in zip(envs, actions)]
        observed = [(obs, info) for obs, _, _, _, info in steps]
        reading = Reading.of(observed[0][0], limits, observed[0][1])
        ceiling.observe(reading.coa_cycle_max, reading.coa_cycle_bin_se, reading.dc_nm + reading.amplitude_nm)
        done = steps[0][2] or steps[0][3]
    assert capped > 0
    info = observed[1][1]
    assert info["macro_slip"] and info["cof_estimate"] == pytest.approx(0.03, rel=0.01)


def test_a_ceiling_stop_ends_the_climb_where_the_crest_falls_and_reports_the_crest():
    """With ``ceiling_stop`` the bold climb of the crest-ceiling test stops at the window where its crest
    falls under a rising torque crest, instead of running away, and reports within 1 % of the CoF (the
    crest held at the peak; noise off)."""
    env = gym.make(cof_gym.WAGON_ENV_ID, **QUIET)
    params = ClimbParameters(amplitude_ratio=0.4, max_log_step=0.07, runaway_estimate=True, crest_ceiling=True,
                             ceiling_stop=True)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((constant_network(3.0, 0.3),)), params=params)
    record = run_episode(env, agent, 4, SHARP_LOW_COF, 0)
    assert agent.stop_reason == "ceiling" and not record.macro_slip
    assert record.estimate == pytest.approx(0.03, rel=0.01)
    with pytest.raises(ValueError, match="ceiling_stop"):
        ClimbParameters(ceiling_stop="yes")


def test_ceiling_fall_z_holds_the_crest_stop_to_a_fall_beyond_the_crests_noise():
    """``ceiling_fall_z`` is the agent's CrestCeiling.fall_z. On the sharp peak of the crest-stop test above
    the crest that reached the peak falls by less than half a standard error of two windows' crests (it
    stops rising there): with any fall counted the climb stops on it, with ``ceiling_fall_z`` 0.5 it climbs
    on and the wheel runs away: the trade rule 48 measures. The field is checked."""
    env = gym.make(cof_gym.WAGON_ENV_ID, **QUIET)
    base = dict(amplitude_ratio=0.4, max_log_step=0.07, runaway_estimate=True, crest_ceiling=True, ceiling_stop=True)
    ended = {}
    for fall_z in (0.0, 0.5):
        agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((constant_network(3.0, 0.3),)),
                                    params=ClimbParameters(**base, ceiling_fall_z=fall_z))
        record = run_episode(env, agent, 4, SHARP_LOW_COF, 0)
        assert agent._ceiling.fall_z == fall_z
        ended[fall_z] = ("macro-slip" if record.macro_slip else agent.stop_reason,
                         len(agent.decisions))
    assert ended[0.0][0] == "ceiling" and ended[0.5][0] == "macro-slip" and ended[0.5][1] > ended[0.0][1]
    with pytest.raises(ValueError, match="ceiling_fall_z"):
        ClimbParameters(ceiling_fall_z=-1)


def test_ceiling_near_headroom_counts_any_fall_where_the_climb_expects_the_peak():
    """With ``ceiling_near_headroom`` the margin is 0 at a window whose predicted (mean) headroom is at most it and
    ``ceiling_fall_z`` beyond it (fall_margin); on the sharp peak of the crest-stop test, where the constant
    filter predicts a headroom of 3, a gate above 3 restores the stop that ``ceiling_fall_z`` 0.5 alone misses
    (the same windows as with any fall counted), and a gate below it does not. The field is checked."""
    gated = ClimbParameters(ceiling_fall_z=2.0, ceiling_near_headroom=0.3)
    assert (gated.fall_margin(0.3), gated.fall_margin(0.31), ClimbParameters(ceiling_fall_z=2.0).fall_margin(0.1),
            ClimbParameters().fall_margin(5.0)) == (0.0, 2.0, 2.0, 0.0)
    env = gym.make(cof_gym.WAGON_ENV_ID, **QUIET)
    base = dict(amplitude_ratio=0.4, max_log_step=0.07, runaway_estimate=True, crest_ceiling=True, ceiling_stop=True)
    ended = {}
    for setting in ({}, {"ceiling_fall_z": 0.5, "ceiling_near_headroom": 3.5},
                    {"ceiling_fall_z": 0.5, "ceiling_near_headroom": 2.5}):
        agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((constant_network(3.0, 0.3),)),
                                    params=ClimbParameters(**base, **setting))
        record = run_episode(env, agent, 4, SHARP_LOW_COF, 0)
        ended[len(ended)] = ("macro-slip" if record.macro_slip else agent.stop_reason, len(agent.decisions))
    assert ended[0] == ended[1] and ended[0][0] == "ceiling" and ended[2][0] == "macro-slip"
    with pytest.raises(ValueError, match="ceiling_near_headroom"):
        ClimbParameters(ceiling_near_headroom=-0.1)


def test_ceiling_noise_z_widens_the_fall_margin_with_the_noise_the_climb_reads():
    """``ceiling_noise_z`` adds ``ceiling_noise_z x (r - 1)`` standard errors to the margin, near the expected peak
    as far from it, at a read noise ratio ``r`` above 1, and nothing at or below it (fall_margin). The agent passes
    its read ratio: on the sharp peak of the crest-stop test, where any fall near the expected peak ends the climb at
    the ceiling, a reference noise far below what the climb reads with a margin of 10 such errors per unit of ratio
    lets no fall count, and the climb runs away as with the gate below the peak. The field is checked."""
    noisy = ClimbParameters(ceiling_fall_z=2.0, ceiling_near_headroom=0.3, ceiling_noise_z=1.5)
    assert (noisy.fall_margin(0.3, 3.0), noisy.fall_margin(0.31, 3.0), noisy.fall_margin(0.3, 1.0),
            noisy.fall_margin(0.31, 0.5)) == (3.0, 5.0, 0.0, 2.0)
    env = gym.make(cof_gym.WAGON_ENV_ID, **QUIET)
    base = dict(amplitude_ratio=0.4, max_log_step=0.07, runaway_estimate=True, crest_ceiling=True, ceiling_stop=True,
                ceiling_near_headroom=3.5)
    ended = {}
    for setting in ({}, {"noise_reference_nms": 1e-9, "ceiling_noise_z": 10.0},
                    {"noise_reference_nms": 1e-9}):
        agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((constant_network(3.0, 0.3),)),
                                    params=ClimbParameters(**base, **setting))
        record = run_episode(env, agent, 4, SHARP_LOW_COF, 0)
        ended[len(ended)] = "macro-slip" if record.macro_slip else agent.stop_reason
    assert ended == {0: "ceiling", 1: "macro-slip", 2: "ceiling"}
    with pytest.raises(ValueError, match="ceiling_noise_z"):
        ClimbParameters(ceiling_noise_z=-0.5)

def test_the_runaway_estimate_is_reported_between_stops_and_scored_when_the_wheel_runs_away():
    """With ``runaway_estimate`` the actions differ from the plain climb's in the estimate component only;
    after an action that is not a stop every source reads the bracket's middle for that action's
    commanded crest; a bold climb that runs away is scored on it, and its lower end (the survived crest
    bound, noise off) is below the CoF within the ground truth's 0.3 %."""
    bold = FilterEnsemble((constant_network(3.0, 0.3),))  # far from the peak whatever it reads: big steps
    envs = [gym.make(cof_gym.WAGON_ENV_ID, **QUIET) for _ in range(2)]
    limits = envs[0].unwrapped.limits
    agents = [LearnedInterrogator(limits, bold, params=ClimbParameters(amplitude_ratio=0.4, max_log_step=0.2,
                                                                       runaway_estimate=runaway))
              for runaway in (False, True)]
    observed = [env.reset(seed=4, options={"creep_law": "dry"}) for env in envs]
    for agent, (obs, info) in zip(agents, observed):
        agent.reset(obs, agent_view(info, False))
    bracket, done, reported = RunawayBracket(), False, 0
    while not done:
        actions = [agent.act(obs, agent_view(info, False)) for agent, (obs, info) in zip(agents, observed)]
        np.testing.assert_array_equal(np.delete(actions[0], 3), np.delete(actions[1], 3))
        plain, runaway = (agent.candidate_estimates(1.0) for agent in agents)
        command = decode_action(actions[1], limits)
        expected = bracket.estimate(command.drive.dc_torque_nm + command.drive.total_amplitude_nm)
        if command.stop or expected is None:
            assert runaway == plain
        else:
            assert len(set(runaway.values())) == 1 and runaway["filter"] == pytest.approx(expected, rel=1e-5)
            reported += 1
        steps = [env.step(action) for env, action in zip(envs, actions)]
        observed = [(obs, info) for obs, _, _, _, info in steps]
        reading = Reading.of(observed[1][0], limits, observed[1][1])
        bracket.observe(reading.crest_bound, reading.dc_nm + reading.amplitude_nm)
        done = steps[1][2] or steps[1][3]
    info = observed[1][1]
    assert reported > 0 and info["macro_slip"] and info["scored"]
    assert info["cof_estimate"] == pytest.approx(expected, rel=1e-5)
    assert agents[1].candidate_estimates(1.0)["filter"] == pytest.approx(info["cof_estimate"], rel=1e-5)
    assert agents[1]._bracket.crest_bound <= info["ground_truth"]["cof"] * 1.003


def _probe_reading(phase_deg: float, crest: float) -> Reading:
    return Reading(phase_deg, 1.0, 0.5, 0.05, 0.01, 1000.0, 400.0, 5.0, 20.0, 1.0, coa_cycle_max=crest)


def test_probes_on_needs_the_lags_rise_since_the_first_window_and_a_rising_crest():
    probe = ClimbParameters(creep_log_step=0.03, crest_probe_lag_rise_deg=30.0)
    first = _probe_reading(40.0, 0.04)  # a drive lag of 40 deg: the first window's lag, which the rise cancels
    assert probe.probes_on([first, _probe_reading(69.0, 0.060), _probe_reading(70.0, 0.061)])
    assert not probe.probes_on([first, _probe_reading(69.0, 0.060), _probe_reading(69.9, 0.061)])  # risen < 30 deg
    assert not probe.probes_on([first, _probe_reading(69.0, 0.060), _probe_reading(75.0, 0.060)])  # crest not above
    assert not probe.probes_on([first, _probe_reading(75.0, 0.060), _probe_reading(80.0, 0.0)])  # no crest read
    assert not probe.probes_on([first]) and not ClimbParameters().probes_on([first, _probe_reading(90.0, 0.1)])
    capped = replace(probe, crest_probe_max_lag_deg=85.0, crest_probe_max_lag_step_deg=10.0)
    assert capped.probes_on([first, _probe_reading(75.0, 0.060), _probe_reading(85.0, 0.061)])
    assert not capped.probes_on([first, _probe_reading(76.0, 0.060), _probe_reading(85.5, 0.061)])  # above 85 deg
    assert not capped.probes_on([first, _probe_reading(70.0, 0.060), _probe_reading(80.5, 0.061)])  # a 10.5 deg jump
    for bad, match in (({"crest_probe_lag_rise_deg": -1.0}, "crest_probe_lag_rise_deg"),
                       ({"crest_probe_lag_rise_deg": 30.0, "creep_log_step": 0.01}, "min_log_step"),
                       ({"crest_probe_max_lag_deg": 181.0}, "crest_probe_max_lag_deg"),
                       ({"crest_probe_max_lag_step_deg": -1.0}, "crest_probe_max_lag_step_deg")):
        with pytest.raises(ValueError, match=match):
            ClimbParameters(**bad)


def test_the_probe_stays_off_where_the_first_windows_read_more_noise_than_the_ratio_allows():
    quiet = [_probe_reading(40.0, 0.04), _probe_reading(69.0, 0.060), _probe_reading(70.0, 0.061)]
    noisy = [replace(r, se_deg=2.0 * r.se_deg) for r in quiet]  # the lock-in reads twice the speed noise
    reference = quiet[0].lockin_noise_nms  # every quiet window reads it (the same se, compliance and amplitude)
    probe = ClimbParameters(creep_log_step=0.03, crest_probe_lag_rise_deg=30.0, noise_reference_nms=reference)
    gated = replace(probe, crest_probe_max_noise_ratio=1.5)
    assert gated.noise_ratio(quiet) == 1.0 and gated.noise_ratio(noisy) == pytest.approx(2.0, rel=1e-12)
    assert probe.probes_on(quiet) and probe.probes_on(noisy)  # ungated: the noise is not read
    assert gated.probes_on(quiet) and not gated.probes_on(noisy)
    assert replace(gated, crest_probe_max_noise_ratio=2.5).probes_on(noisy)
    for bad, match in (({"crest_probe_max_noise_ratio": 0.5, "noise_reference_nms": 0.4}, "crest_probe_max_noise_ratio"),
                       ({"crest_probe_max_noise_ratio": 1.5}, "needs noise_reference_nms")):
        with pytest.raises(ValueError, match=match):
            ClimbParameters(**bad)


@pytest.mark.skipif(not SHIPPED, reason="the shipped interrogator is not built")
def test_a_far_peak_climb_probes_on_past_its_headroom_stop_and_is_the_same_climb_before_it():
    """Default-suite episode 4 (Polach, low adhesion, 39 m/s, its peak at 5.1 % creepage): the shipped climb stops on
    its headroom with the crest still rising; with the probe it takes every earlier step alike and then climbs on."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    seed, options = make_suite("default", 60, 0).episodes[4]
    decisions = {}
    for threshold in (None, 30.0):
        params = replace(manifest_climb(SHIPPED_INTERROGATOR), crest_probe_lag_rise_deg=threshold)
        agent = interrogator_for(env, SHIPPED_INTERROGATOR, params)
        run_episode(env, agent, seed, options, 4)
        decisions[threshold] = (agent.stop_reason, [d.log_step for d in agent.decisions])
    (stop, steps), (_, probed) = decisions[None], decisions[30.0]
    assert stop == "headroom" and len(probed) > len(steps)
    assert probed[:len(steps) - 1] == steps[:-1] and steps[-1] == 0.0 and probed[len(steps) - 1] == 0.03
    env.close()


def test_held_crest_ratio_keeps_the_crest_at_most_the_held_one_down_to_the_floor():
    limits = gym.make(cof_gym.WAGON_ENV_ID).unwrapped.limits
    p = ClimbParameters(amplitude_ratio=0.4, min_amplitude_nm=50.0)
    assert p.held_crest_ratio(6_000.0, 4_000.0, limits) == 0.4  # the climb's own ratio fits under it
    ratio = p.held_crest_ratio(5_600.0, 4_800.0, limits)
    assert ratio == pytest.approx(5_600.0 / 4_800.0 - 1.0, rel=1e-12)
    assert 4_800.0 + p.amplitude(4_800.0, limits, ratio) <= 5_600.0 * (1 + 1e-12)
    assert p.held_crest_ratio(5_600.0, 5_600.0 / 1.029, limits) is None  # below CREST_RATIO_FLOOR (0.03)
    assert p.held_crest_ratio(1_000.0, 960.0, limits) is None  # the 50 N m least amplitude would pass it
    with pytest.raises(ValueError, match="crest_probe_hold_crest"):
        ClimbParameters(crest_probe_hold_crest=1)


@pytest.mark.skipif(not SHIPPED, reason="the shipped interrogator is not built")
def test_a_held_crest_probe_never_commands_a_crest_above_the_one_it_started_under():
    """Default-suite episode 4 (a far peak: the probe defers its headroom stop, above): with the crest held, every
    window after the probe began is commanded under that window's crest while the DC still rises, and every window
    before it is the unheld probe's."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    seed, options = make_suite("default", 60, 0).episodes[4]
    windows = {}
    for hold in (False, True):
        params = replace(manifest_climb(SHIPPED_INTERROGATOR), crest_probe_lag_rise_deg=30.0,
                         crest_probe_hold_crest=hold)
        agent = interrogator_for(env, SHIPPED_INTERROGATOR, params)
        obs, info = env.reset(seed=seed, options=options)
        agent.reset(obs, agent_view(info, oracle=False))
        commanded = []  # (DC, crest) of each window, as the action decodes
        while True:
            action = agent.act(obs, agent_view(info, oracle=False))
            decoded = decode_action(action, env.unwrapped.limits)
            drive = decoded.drive
            commanded.append((drive.dc_torque_nm, drive.dc_torque_nm + drive.amplitude_nm))
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break
        windows[hold] = (commanded, [d.crept for d in agent.decisions], agent._held_crest)
    env.close()
    (free, _, _), (held, _, crest) = windows[False], windows[True]
    start = next(k for k, (dc, c) in enumerate(held) if c == pytest.approx(crest, rel=1e-6))  # the probe's first
    assert crest is not None and held[:start + 1] == free[:start + 1]
    later = held[start + 1:]
    assert later and all(c <= crest * (1 + 1e-6) for _, c in later)  # float32 actions: a few epsilons
    assert all(b[0] > a[0] for a, b in zip(held[start:], later[:-1]))  # the DC rises under it (the last: the stop's)


def test_the_modulation_raise_makes_up_a_lag_below_the_floor():
    assert ClimbParameters().modulation_raise([0.3, 0.3]) == 1.0  # no floor: never raised
    lagging = ClimbParameters(lag_floor=0.6)
    assert lagging.modulation_raise([]) == 1.0  # nothing measured yet
    assert lagging.modulation_raise([0.29, 0.3, 0.5]) == pytest.approx(2.0, rel=1e-12)  # the median 0.3
    assert lagging.modulation_raise([0.7, 0.95]) == 1.0  # above the floor: as commanded
    limits = MotorLimits(max_dc_torque_nm=20_000.0)
    lagging = replace(lagging, amplitude_ratio=0.4)
    assert lagging.commanded_amplitude(2000.0, limits, raise_by=2.0) == pytest.approx(1600.0, rel=1e-12)
    assert lagging.commanded_amplitude(6000.0, limits, raise_by=2.0) == limits.max_amplitude_nm  # the drive's most
    for bad in (0.0, 1.5, True):
        with pytest.raises(ValueError, match="lag_floor"):
            ClimbParameters(lag_floor=bad)
    with pytest.raises(ValueError, match="two-tone climb has no lag_floor"):
        ClimbParameters(lag_floor=0.6, tone2_frequency_hz=7.0)


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator")
def test_a_raised_command_applies_the_floors_fraction_of_the_climbs_modulation():
    """With a 0.1 s drive lag the drive applies 0.30 of a 5 Hz modulation (first-order gain); with ``lag_floor``
    0.65 the climb raises every command after its first driven window (but the stop's, which is not read) by 0.65
    over the median applied fraction
    so far, so each window's measured over its planned modulation is 0.65 times that window's fraction over the
    median (the fractions of one climb agree to a few per cent: the lag's transient after each DC step), and
    the readings describe the planned modulation. At the draws' lags (at most 0.03 s: 0.73) nothing changes."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    floor = replace(manifest_climb(SHIPPED_INTERROGATOR), lag_floor=0.65)
    agent = interrogator_for(env, SHIPPED_INTERROGATOR, params=floor)
    obs, info = env.reset(seed=5, options={"motor_lag_s": 0.1})
    agent.reset(obs, info)
    limits = env.unwrapped.limits
    planned, commanded, measured = [], [], []
    while True:
        action = agent.act(obs, info)
        planned.append(floor.amplitude(agent.dc_nm, limits, agent._ratio))
        commanded.append(decode_action(action, limits).drive.amplitude_nm)
        obs, _, terminated, truncated, info = env.step(action)
        measured.append(info["measurement"]["torque_amplitude_nm"])
        if terminated or truncated:
            break
    applied = np.array(measured) / np.array(planned)
    assert applied[0] < 0.35  # the first window as commanded: the lag's 0.30 (and the torque gain error)
    capped = np.array(commanded) >= limits.max_amplitude_nm * (1.0 - 1e-6)  # the drive's most: raised less
    raised = ~capped[1:-1]  # the windows after the first, but the stop's (its command is not raised)
    assert np.all(np.abs(applied[1:-1][raised] / 0.65 - 1.0) < 0.1) and raised.sum() >= 3
    readings = agent.features.readings
    assert [r.amplitude_nm for r in readings] == pytest.approx(planned[:len(readings)], rel=1e-6)
    shipped = interrogator_for(env, SHIPPED_INTERROGATOR)
    assert np.array_equal(play(agent, 6)[0], play(shipped, 6)[0])  # the draws' lag: the same climb


def _creep_reading(coa: float, creepage: float) -> Reading:
    return Reading(0.0, 1.0, 0.5, coa, creepage, 1000.0, 400.0, 5.0, 20.0, 1.0)


def test_creep_elasticity_reads_the_power_of_the_creepages_rise_whatever_its_offset_and_scale():
    """``s = offset + k CoA^n`` reads ``n`` with any offset (the sensors' zero) and any ``k`` (their scale), over a
    baseline of at least 10 % in CoA, else nothing. The first window's CoA, 1e-12, moves the reading by about
    1e-12 / 0.055 / ln(0.066 / 0.055), 1e-10, below the tolerance."""
    coas = (1e-12, 0.05, 0.055, 0.06, 0.066)
    for n, offset, k in ((1.0, 0.017, 0.2), (3.0, -0.01, 40.0)):
        readings = [_creep_reading(c, offset + k * c ** n) for c in coas]
        assert creep_elasticity(readings) == pytest.approx(n, rel=1e-9)  # back to 0.055: ln(0.066 / 0.055) >= 0.1
    assert creep_elasticity([_creep_reading(c, 0.01 + c) for c in (1e-9, 0.062, 0.066)]) is None  # no window 10 % below
    flat = [_creep_reading(c, s) for c, s in ((1e-9, 0.0), (0.05, 0.002), (0.06, 0.002))]
    assert creep_elasticity(flat) is None  # the rise did not grow: the noise's


def test_an_elasticity_release_defers_a_headroom_stop_where_the_creepage_still_grows_as_on_a_rising_half():
    release = ClimbParameters(creep_log_step=0.03, elasticity_release=3.0)
    coas = (1e-9, 0.05, 0.06)
    assert release.probes_on([_creep_reading(c, 0.01 + 0.2 * c ** 2) for c in coas])  # elasticity 2
    assert not release.probes_on([_creep_reading(c, 0.01 + 0.2 * c ** 5) for c in coas])  # 5: near the peak
    assert not ClimbParameters(creep_log_step=0.03).probes_on([_creep_reading(c, 0.2 * c) for c in coas])
    with pytest.raises(ValueError, match="elasticity_release"):
        ClimbParameters(elasticity_release=0.5)
