"""The runaway estimate: its bracket's arithmetic, and any agent reporting it between its stops."""

import math

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents import registry
from cof_gym.agents.base import agent_view
from cof_gym.agents.runaway import CrestCeiling, RunawayBracket, RunawayEstimate, crest_bound
from cof_gym.agents.staircase import PracticalStaircase
from cof_gym.task.interface import decode_action
from exact_sensors import QUIET


def test_the_bracket_is_the_geometric_middle_of_what_was_survived_and_what_is_demanded():
    bracket = RunawayBracket()
    assert bracket.estimate(1000.0) is None  # no crest read yet
    bracket.observe(0.19, 1400.0)
    bracket.observe(0.14, 1540.0)  # a lower crest later: the best one stays
    assert (bracket.crest_bound, bracket.crest_torque_nm) == (0.19, 1400.0)
    rho = 1.1
    middle = bracket.estimate(1400.0 * rho)
    assert middle == pytest.approx(0.19 * math.sqrt(rho), rel=1e-15)
    assert bracket.estimate(1200.0) == 0.19  # a lower crest than survived: the bound itself
    # the middle's log error is at most half the bracket's width for a CoF anywhere in it, and that at its ends
    for cof in np.linspace(0.19, 0.19 * rho, 11):
        assert abs(math.log(middle / cof)) <= 0.5 * math.log(rho) + 1e-15
    assert abs(math.log(middle / 0.19)) == pytest.approx(0.5 * math.log(rho), rel=1e-12)


def test_the_ceiling_holds_once_the_crest_falls_under_a_rising_torque_crest():
    """No bound while the crest rises with the torque crest, nor when it falls with it, nor from an unread
    window (crest 0); once it falls under a rising torque crest, the best crest plus its bin's error."""
    ceiling = CrestCeiling()
    for crest, se, torque in [(0.10, 0.002, 1000.0), (0.12, 0.002, 1100.0), (0.0, 0.0, 1150.0),
                              (0.115, 0.003, 1050.0)]:  # rising, rising, unread, falling with the torque
        ceiling.observe(crest, se, torque)
        assert ceiling.bound is None
    ceiling.observe(0.118, 0.004, 1200.0)  # rises again under a rising torque crest
    assert ceiling.bound is None
    ceiling.observe(0.117, 0.004, 1250.0)  # falls under a rising torque crest: the peak is reached
    assert ceiling.bound == pytest.approx(0.12 + 0.002, rel=1e-15)
    ceiling.observe(0.125, 0.001, 1300.0)  # a higher crest later raises the bound, which stays
    assert ceiling.bound == pytest.approx(0.126, rel=1e-15)



def test_with_fall_z_only_a_fall_beyond_the_crests_noise_reaches_the_ceiling():
    """With ``fall_z`` a crest below the last one counts only where the fall exceeds ``fall_z`` standard
    errors of the two crests' difference, ``hypot(se_1, se_2)``; any fall with 0; the field is checked."""
    for fall_z, small_fall_counts in ((0.0, True), (1.0, False)):
        ceiling = CrestCeiling(fall_z=fall_z)
        ceiling.observe(0.120, 0.003, 1000.0)
        ceiling.observe(0.117, 0.004, 1100.0)  # 0.003 below: 0.6 of hypot(0.003, 0.004) = 0.005
        assert ceiling.reached is small_fall_counts
    ceiling = CrestCeiling(fall_z=1.0)
    ceiling.observe(0.120, 0.003, 1000.0)
    ceiling.observe(0.114, 0.004, 1100.0)  # 0.006 below: 1.2 of the difference's standard error
    assert ceiling.reached and ceiling.bound == pytest.approx(0.123, rel=1e-15)
    with pytest.raises(ValueError, match="fall_z"):
        CrestCeiling(fall_z=-0.5)

def test_the_crest_bound_is_the_cycle_crest_less_a_bins_error_and_zero_unread():
    assert crest_bound({"coa_cycle_max": 0.2, "coa_cycle_bin_se": 0.01}) == pytest.approx(0.19, rel=1e-15)
    assert crest_bound({"coa_cycle_max": 0.005, "coa_cycle_bin_se": 0.01}) == 0.0
    assert crest_bound({}) == 0.0


def _twin_envs(agents, seed: int, options: dict, **sensors):
    """One quiet wagon env per agent (``sensors`` overriding QUIET), reset alike, each agent reset on its
    own: (envs, [(observation, info), ...])."""
    envs = [gym.make(cof_gym.WAGON_ENV_ID, **{**QUIET, **sensors}) for _ in agents]
    observed = [env.reset(seed=seed, options=options) for env in envs]
    for agent, (obs, info) in zip(agents, observed):
        agent.reset(obs, agent_view(info, False))
    return envs, observed


def test_a_wrapped_agent_keeps_its_torques_and_stops_and_reports_the_bracket_between_them():
    """The staircase and the same staircase +runaway in twin envs: every action the same but the estimate
    of an action that is not a stop, which is the bracket's middle for that action's commanded crest; with
    its speed reference 1 % off the staircase misreads the creepage and runs away on a dry rail, and the
    runaway is scored on that estimate."""
    limits = gym.make(cof_gym.WAGON_ENV_ID).unwrapped.limits
    plain, wrapped = PracticalStaircase(limits), RunawayEstimate(PracticalStaircase(limits), limits)
    assert wrapped.name == "staircase+runaway" and wrapped.oracle is False
    envs, observed = _twin_envs((plain, wrapped), 2, {"creep_law": "dry"}, speed_sensor_error=0.01)
    bracket, reported, done = RunawayBracket(), 0, False
    while not done:
        actions = [agent.act(obs, agent_view(info, False)) for agent, (obs, info) in zip((plain, wrapped), observed)]
        np.testing.assert_array_equal(np.delete(actions[0], 3), np.delete(actions[1], 3))
        command = decode_action(actions[1], limits)
        crest = command.drive.dc_torque_nm + command.drive.amplitude_nm
        expected = None if command.stop else bracket.estimate(crest)
        if expected is None:
            assert actions[1][3] == actions[0][3]
        else:
            assert command.cof_estimate == pytest.approx(expected, rel=1e-5)
            reported += 1
        steps = [env.step(action) for env, action in zip(envs, actions)]
        observed = [(obs, info) for obs, _, _, _, info in steps]
        bracket.observe(crest_bound(observed[1][1]["measurement"]), crest)
        done = steps[1][2] or steps[1][3]
    info = observed[1][1]
    assert reported > 0 and info["macro_slip"] and info["cof_estimate"] == pytest.approx(expected, rel=1e-5)
    assert bracket.crest_bound <= info["ground_truth"]["cof"] * 1.003  # the survived crest: below the peak


def test_the_registry_builds_name_plus_runaway_and_refuses_other_suffixes():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = registry.make_agent("phase-rule+runaway", env)
    assert isinstance(agent, RunawayEstimate) and agent.name == "phase-rule+runaway"
    assert registry.parse("phase-rule+runaway") == registry.parse("phase-rule")
    assert not isinstance(registry.make_agent("phase-rule+plain", env), RunawayEstimate)
    with pytest.raises(registry.AgentSpecError, match="phase-rule\\+slip"):
        registry.parse("phase-rule+slip")


@pytest.mark.parametrize("name", ["staircase", "model-based", "robust-model"])
def test_the_agents_rule_24_chose_report_it_under_their_own_names(name):
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = registry.make_agent(name, env)
    assert isinstance(agent, RunawayEstimate) and agent.name == name
    plain = registry.make_agent(f"{name}+plain", env)
    assert not isinstance(plain, RunawayEstimate) and plain.name == f"{name}+plain"
    with pytest.raises(ValueError, match="'\\+'"):
        registry.register(f"{name}+x", "cof_gym.agents.staircase:PracticalStaircase", oracle=False)


@pytest.mark.parametrize("spec, bracket, ceiling, name", [
    ("staircase+ceiling", True, True, "staircase+ceiling"),  # registered with the bracket: both
    ("phase-rule+ceiling", False, True, "phase-rule+ceiling"),  # registered without: the ceiling alone
    ("staircase+runaway", True, False, "staircase+runaway"),
    ("staircase", True, True, "staircase"),  # rules 24 and 29: both under its own name
    ("phase-rule", False, True, "phase-rule"),  # rule 29 only
])
def test_the_registry_builds_name_plus_ceiling_on_what_the_agent_is_registered_with(spec, bracket, ceiling, name):
    agent = registry.make_agent(spec, gym.make(cof_gym.WAGON_ENV_ID))
    assert isinstance(agent, RunawayEstimate) and (agent.bracket, agent.ceiling, agent.name) == (bracket, ceiling, name)
    # what evaluate compares to find one agent given twice
    assert registry.plays_as(spec) == (registry.split_modifier(spec)[0], None, bracket, ceiling)
    with pytest.raises(ValueError, match="neither"):
        RunawayEstimate(agent.agent, agent.limits, bracket=False, ceiling=False)


def test_a_ceiling_caps_a_wrapped_agents_estimates_once_the_crest_falls_and_keeps_its_torques():
    """The phase rule and the same rule +ceiling in twin envs, its probe pushed far past its stop test
    (a jump of 90 deg) so that its crest reaches the peak of a Shen-Hedrick-Elkins curve at a low CoF
    (noise off): every action the same but the estimate, which is the rule's own until the crest falls under
    a rising torque crest (CrestCeiling fed the same windows) and at most the best crest plus its bin's
    error from then on, the cap binding at least once (the test can fail)."""
    from cof_gym.agents.phase_rule import PhaseRule
    limits = gym.make(cof_gym.WAGON_ENV_ID).unwrapped.limits
    bold = dict(jump_deg=90.0, correction=1.3)  # no knee stop; an estimate well above the crest
    plain = PhaseRule(limits, **bold)
    wrapped = RunawayEstimate(PhaseRule(limits, **bold), limits, bracket=False, ceiling=True)
    assert wrapped.name == "phase-rule+ceiling"
    she = {"shen_hedrick_elkins": {"k_stiffness": 1.0, "friction_ratio": 0.4, "friction_decay_s_per_m": 0.6}}
    envs, observed = _twin_envs((plain, wrapped), 4, {"creep_law": she, "cof": 0.03})
    ceiling, capped, done = CrestCeiling(), 0, False
    while not done:
        actions = [agent.act(obs, agent_view(info, False)) for agent, (obs, info) in zip((plain, wrapped), observed)]
        np.testing.assert_array_equal(np.delete(actions[0], 3), np.delete(actions[1], 3))
        own, reported = (decode_action(a, limits).cof_estimate for a in actions)
        if ceiling.bound is None or own <= ceiling.bound:
            assert actions[1][3] == actions[0][3]
        else:
            assert reported == pytest.approx(ceiling.bound, rel=1e-5)
            capped += 1
        command = decode_action(actions[1], limits)
        crest = command.drive.dc_torque_nm + command.drive.amplitude_nm
        steps = [env.step(action) for env, action in zip(envs, actions)]
        observed = [(obs, info) for obs, _, _, _, info in steps]
        m = observed[1][1]["measurement"]
        ceiling.observe(m["coa_cycle_max"], m["coa_cycle_bin_se"], crest)
        done = steps[1][2] or steps[1][3]
    assert capped > 0


def test_a_multitone_action_is_refused_naming_the_agent():
    class ThreeTones:
        name, oracle = "three", False

        def reset(self, observation, info):
            pass

        def act(self, observation, info):
            return np.zeros(9, dtype=np.float32)

    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = RunawayEstimate(ThreeTones(), env.unwrapped.limits)
    agent.reset(None, {})
    with pytest.raises(ValueError, match="three\\+runaway.*single-tone"):
        agent.act(None, {})
