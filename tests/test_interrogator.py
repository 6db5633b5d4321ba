"""The learned interrogator (cof_gym/agents/interrogator/): what it reads, its files, its training."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, astuple
import subprocess
from dataclasses import replace
import sys

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.commands.suites import make_suite
from cof_gym.task.scenarios import COF_ENVELOPE, ScenarioRanges
from cof_gym.agents import registry
from cof_gym.agents.interrogator import (
    CREEPAGE_MODULATION_FEATURE_NAMES, CREST_RATIO_FLOOR, CYCLE_CREST_FEATURE_NAMES, CREEPAGE_RISE_FEATURE_NAMES, CREEPAGE_RISE_FLOORS, FEATURE_NAMES, blocks_of, feature_names, SHIPPED_INTERROGATOR, TARGET_NAMES, ClimbParameters, EpisodeFeatures, FilterEnsemble, FilterNetwork,
    PEAK_GAP_CLIP, SE_CLIP_DEG, LearnedInterrogator, Reading, floor_headroom, pooled_correction, interrogator_for, manifest_climb, peak_gap, slope_from_phase, slope_index,
)
from cof_gym.agents.interrogator.training import (
    GENTLE_FALL, PROCEDURAL_PEAK_CREEPAGE, STEEP_FALL, ClimbDraws, Dataset, FallingBranch, FitSettings, _climb_episode,
    READING_FIELDS, collect, fit_member, procedural_shape,
)
from cof_gym.physics.creep_laws import creep_law_from_spec
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.agents.base import agent_view
from cof_gym.agents.runaway import CrestCeiling, RunawayBracket
from cof_gym.task.interface import OBSERVATION_NAMES, decode_action
from exact_sensors import QUIET
from fixed_options import FixedOptions

SHIPPED = (SHIPPED_INTERROGATOR / "manifest.json").is_file()
CREEPAGE = OBSERVATION_NAMES.index("creepage_measured")


def random_network(seed: int = 0, width: int = 8) -> FilterNetwork:
    rng = np.random.default_rng(seed)
    n = len(FEATURE_NAMES)
    shapes = [(n, width), (width, 2 * len(TARGET_NAMES))]
    return FilterNetwork(np.zeros(n), np.ones(n), tuple(rng.normal(0, 0.3, s) for s in shapes),
                         tuple(rng.normal(0, 0.1, s[1]) for s in shapes))


def test_slope_index_is_ln_cot_and_falls_towards_the_peak():
    assert slope_index(45.0) == pytest.approx(0.0, abs=1e-12)
    assert slope_index(30.0) == pytest.approx(math.log(math.sqrt(3.0)), rel=1e-12)
    values = [slope_index(p) for p in (5, 20, 45, 70, 88, 89, 120)]
    assert all(a > b for a, b in zip(values, values[1:-1]))
    assert values[-1] == values[-2]  # clipped at 89 deg: finite


def test_network_round_trip_and_feature_check(tmp_path):
    net = random_network()
    net.save(tmp_path / "member_0.npz")
    loaded = FilterNetwork.load(tmp_path / "member_0.npz")
    x = np.random.default_rng(1).normal(size=(5, len(FEATURE_NAMES)))
    for a, b in zip(net(x), loaded(x)):
        np.testing.assert_array_equal(a, b)
    np.savez(tmp_path / "member_1.npz", feature_names=np.asarray(["other"]), feature_mean=np.zeros(1))
    with pytest.raises(ValueError, match="other features"):
        FilterNetwork.load(tmp_path / "member_1.npz")


def test_ensemble_std_combines_spread_and_predicted_variance():
    a, b = random_network(0), random_network(1)
    x = np.random.default_rng(2).normal(size=(4, len(FEATURE_NAMES)))
    mean, std = FilterEnsemble((a, b)).predict(x)
    (ma, la), (mb, lb) = a(x), b(x)
    np.testing.assert_allclose(mean, (ma + mb) / 2, rtol=1e-12)
    np.testing.assert_allclose(std**2, ((ma - mb) / 2) ** 2 + (np.exp(la) + np.exp(lb)) / 2, rtol=1e-12)
    same_mean, same_std, spread = FilterEnsemble((a, b)).predict_with_spread(x)
    np.testing.assert_array_equal(same_mean, mean)
    np.testing.assert_array_equal(same_std, std)
    np.testing.assert_allclose(spread, np.abs(ma - mb) / 2, rtol=1e-12)  # the members' disagreement alone
    assert not FilterEnsemble((a, a)).predict_with_spread(x)[2].any()  # identical members: no spread


def test_spread_caution_takes_the_members_disagreement_off_the_headroom_and_nothing_when_zero():
    shipped = ClimbParameters(caution=2.0)
    assert shipped.cautious_headroom(0.5, 0.1, spread=0.3) == 0.5 - 2.0 * 0.1  # 0: the climb is unchanged
    wary = replace(shipped, spread_caution=3.0, creep_log_step=0.03, creep_while_std=0.08, creep_until=0.12)
    assert wary.cautious_headroom(0.5, 0.1, spread=0.05) == pytest.approx(0.5 - 0.2 - 0.15, abs=1e-15)
    # the slow probe's end reads the mean headroom, which the spread caution does not move: 0.13 > 0.12
    assert wary.creeps(wary.cautious_headroom(0.13, 0.1, 0.05), 0.1, 0.05)
    assert not wary.creeps(wary.cautious_headroom(0.11, 0.1, 0.05), 0.1, 0.05)


def play(agent, seed: int, env_kwargs: dict | None = None, perturb_creepage: float = 0.0):
    env = gym.make(cof_gym.WAGON_ENV_ID, **(env_kwargs or {}))
    obs, info = env.reset(seed=seed)
    agent.reset(obs, {})
    actions = []
    while True:
        seen = obs.copy()
        seen[CREEPAGE] += perturb_creepage
        action = agent.act(seen, {})
        actions.append(action)
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            return np.asarray(actions), info


def test_blind_to_a_creepage_offset_and_to_ground_truth():
    """A constant creepage offset (a speed-sensor bias) changes nothing but float rounding; the agent
    is not an oracle and is given no info."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(3), random_network(4))))
    a, _ = play(agent, 5)
    b, _ = play(agent, 5, perturb_creepage=0.2)  # observation units: a creepage offset of 0.02
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-4)  # float32 observations: the difference of two offset values rounds
    assert agent.oracle is False


def test_features_are_finite_and_reject_undriven_windows():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    feats = EpisodeFeatures(counter_torque=False)
    obs, _ = env.reset(seed=0)
    with pytest.raises(ValueError, match="driven"):
        feats.push(Reading.of(obs, limits))  # the reset window has no DC torque
    bad = obs.copy()
    bad[OBSERVATION_NAMES.index("dc_torque")] = 0.01
    bad[OBSERVATION_NAMES.index("phase_lag")] = np.nan
    feats.push(Reading.of(bad, limits))
    v = feats.vector()
    assert v.shape == (len(FEATURE_NAMES),) and np.all(np.isfinite(v))


def test_training_data_and_fit_learn_the_headroom():
    """A few climbs, then a member fitted on them predicts the headroom ln(M_sat / DC) of those windows
    better than the best constant (their mean) does: the features carry information and the fit finds it."""
    data = collect(cof_gym.WAGON_ENV_ID, [{}, {"counter_torque": True}], 16, first_seed=2_000_000)
    assert data.features.shape[1] == len(FEATURE_NAMES) and len(data) >= 30
    assert np.all(np.isfinite(data.features)) and np.all(np.isfinite(data.targets))
    member = fit_member(data, seed=0, settings=FitSettings(hidden=(16,), epochs=100, batch_size=32))
    mean, _ = member(data.features)
    residual = np.mean((mean[:, 0] - data.targets[:, 0]) ** 2)
    assert residual < np.var(data.targets[:, 0])
    again = fit_member(data, seed=0, settings=FitSettings(hidden=(16,), epochs=100, batch_size=32))
    np.testing.assert_array_equal(again(data.features)[0], mean)  # seeded fits reproduce


def test_distribution_note_names_untrained_settings():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(),)),
                                trained_on=(cof_gym.WAGON_ENV_ID, ({}, {"counter_torque": True})))
    assert agent.distribution_note(cof_gym.WAGON_ENV_ID, {}) is None
    assert agent.distribution_note(cof_gym.WAGON_ENV_ID, {"counter_torque": True, "max_windows": 20}) is None
    # a longer horizon than its training climbs had: its slow probe climbs on past where any of them went
    assert "max_windows=60 (its training climbs had a horizon of 30)" in agent.distribution_note(
        cof_gym.WAGON_ENV_ID, {"max_windows": 60})
    # every way at once: the horizon and an episode no training draw gives
    both = agent.distribution_note(cof_gym.WAGON_ENV_ID, {"max_windows": 60}, [{"noise_level": 3.0}])
    assert "max_windows=60" in both and "1 of 1 episodes lie outside" in both and both.count("; ") >= 1
    assert "out of its training distribution" in agent.distribution_note(cof_gym.WAGON_V1_ENV_ID, {})
    assert "traction_balance" in agent.distribution_note(cof_gym.WAGON_ENV_ID, {"traction_balance": False})


def test_distribution_note_reads_constructor_defaults_and_scenario_fields_as_the_env_does():
    """An argument equal to the env's default is the env made without it (no note); scenario fields given
    as constructor arguments fix every episode's scenario, so they count as its options (an episode's own
    option over them, as in the env)."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(),)),
                                trained_on=(cof_gym.WAGON_ENV_ID, ({}, {"counter_torque": True})))
    for defaults in ({"counter_torque": False}, {"vehicle": "wagon", "window_s": 1.0, "traction_balance": None}):
        assert agent.distribution_note(cof_gym.WAGON_ENV_ID, defaults, [{}]) is None, defaults
    assert "counter_torque=0" in agent.distribution_note(cof_gym.WAGON_ENV_ID, {"counter_torque": 0})  # 0 is no False
    kwargs = {"noise_level": 3.0, "speed_sensor_error": 0.05, "motor_lag_s": 0.1}
    note = agent.distribution_note(cof_gym.WAGON_ENV_ID, kwargs, [{}, {"cof": 0.3}])
    assert note.startswith("interrogator: 2 of 2 episodes") and "noise_level in 2 (e.g. 3, drawn: 0-1)" in note
    assert "motor_lag_s in 2" in note and "speed_sensor_error in 2" in note
    inside = {"noise_level": 0.5, "speed_sensor_error": 0.0, "motor_lag_s": 0.01}
    assert agent.distribution_note(cof_gym.WAGON_ENV_ID, kwargs, [inside, {**inside, "noise_level": None}]) == (
        "interrogator: 1 of 2 episodes lie outside the scenario draws it was trained on, out of its training "
        "distribution: noise_level in 1 (e.g. 3, drawn: 0-1)")  # None: the constructor's value stays


def test_distribution_note_counts_episodes_beyond_the_training_draws(env):
    """The held-out grid (tables, larger sensor errors) lies wholly outside the v2 draws; the paper suite
    has one CoF below the dry draws; the default suite's seeded draws lie inside."""
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(),)),
                                trained_on=(cof_gym.WAGON_ENV_ID, ({}, {"counter_torque": True})))
    heldout = make_suite("experiments/suites/v2_heldout_grid.json", 60, 0)
    note = agent.distribution_note(heldout.env_id, heldout.env_kwargs, [o for _, o in heldout.episodes])
    assert note.startswith(f"interrogator: {len(heldout.episodes)} of {len(heldout.episodes)} episodes")
    assert "creep_law in 48 (e.g. 'table'" in note and "out of its training distribution" in note
    paper = make_suite("paper", 5, 0)
    note = agent.distribution_note(paper.env_id, paper.env_kwargs, [o for _, o in paper.episodes])
    assert "1 of 5 episodes" in note and "cof in 1 (e.g. 0.1, drawn: 0.15-0.6)" in note
    default = make_suite("default", 60, 0)
    assert agent.distribution_note(default.env_id, default.env_kwargs, [o for _, o in default.episodes]) is None
    ranges = ScenarioRanges(speed_m_s=(10.0, 20.0))
    assert "ranges" in agent.distribution_note(cof_gym.WAGON_ENV_ID, {"ranges": ranges})


def test_bad_directory_is_one_line_and_exit_2(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "cof_gym.cli", "evaluate", "--agents", f"interrogator:{tmp_path}",
                           "--episodes", "1", "--out", str(tmp_path / "out")], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and "member_" in proc.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_shipped_interrogator_is_a_default_agent_and_measures():
    assert "interrogator" in registry.default_agents()
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = registry.make_agent("interrogator", env)
    assert agent.distribution_note(cof_gym.WAGON_ENV_ID, {}) is None
    # the recipe's guards: the one that learns the shipped climb (session 30) and the probing guard (session 31)
    assert len(agent.guards) == 2 and all(len(g.members) == 5 for g in agent.guards)
    records = [run_episode(env, agent, seed, {}, i) for i, seed in enumerate((11, 12, 13))]
    assert not any(r.macro_slip for r in records)
    assert all(r.scored and r.relative_error < 0.5 for r in records)


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


def test_the_estimate_source_does_not_change_the_climb():
    """Both estimate sources see the same windows: the actions differ only in the estimate component."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    ensemble = FilterEnsemble((random_network(5), random_network(6)))
    a, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble, params=ClimbParameters(estimate_from="filter")), 8)
    b, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble, params=ClimbParameters(estimate_from="best_coa")), 8)
    estimate = 3  # ACTION_NAMES index of cof_estimate
    np.testing.assert_array_equal(np.delete(a, estimate, axis=1), np.delete(b, estimate, axis=1))


def test_peak_gap_is_exact_on_a_quadratic_peak():
    """On mu(s) = mu_p - a (s_p - s)^2 with the phase of Eq. 3 (cot(phase) proportional to the slope
    d mu / d s over the frequency), two windows extrapolate the peak exactly (up to rounding): the
    quadratic-peak law the feature is built on. Off the peak law, a falling CoA gives 0 and a slope that
    did not fall gives the clip."""
    mu_p, a, s_p, scale = 0.3, 400.0, 0.01, 0.5

    def reading(s: float, frequency: float) -> Reading:
        slope = 2.0 * a * (s_p - s)
        phase = math.degrees(math.atan2(frequency * scale, slope))  # cot(phase) = slope / (f scale)
        return Reading(phase, 0.1, 0.5, mu_p - a * (s_p - s) ** 2, s, 1000.0, 50.0, frequency, 20.0, 1.0)

    for s1, s2, f1, f2 in ((0.004, 0.006, 5.0, 5.0), (0.002, 0.008, 5.0, 7.0), (0.007, 0.0095, 3.0, 3.0)):
        windows = [reading(s1, f1), reading(s2, f2)]
        assert 1.0 < windows[1].phase_deg < 89.0
        expected = math.log(mu_p / windows[1].coa)
        assert peak_gap(windows, 1, 0, slope_from_phase) == pytest.approx(expected, rel=1e-9)
    past = [reading(0.006, 5.0), reading(0.006, 5.0)]
    assert peak_gap(past, 1, 0, slope_from_phase) == 0.0
    linear = [reading(0.004, 5.0), replace(reading(0.004, 5.0), coa=0.29)]
    assert peak_gap(linear, 1, 0, slope_from_phase) == PEAK_GAP_CLIP


class _ScrambledTruth(gym.Wrapper):
    """The same env, with its ground truth doubled in ``info`` and its actions recorded."""

    def __init__(self, env):
        super().__init__(env)
        self.actions: list[np.ndarray] = []

    def _scramble(self, info):
        info["ground_truth"] = {**info["ground_truth"], "cof": 2 * info["ground_truth"]["cof"],
                                "saturation_torque_nm": 2 * info["ground_truth"]["saturation_torque_nm"]}
        return info

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        return obs, self._scramble(info)

    def step(self, action):
        self.actions.append(np.asarray(action).copy())
        obs, reward, terminated, truncated, info = self.env.step(action)
        return obs, reward, terminated, truncated, self._scramble(info)


def test_training_climbs_are_steered_by_readings_not_by_the_truth():
    """A truth-steered schedule would leak the labels into the torque-step features: the training
    climb's actions are the same whatever the ground truth says (up to where it ends the climb)."""
    plain, scrambled = _ScrambledTruth(gym.make(cof_gym.WAGON_ENV_ID)), _ScrambledTruth(gym.make(cof_gym.WAGON_ENV_ID))
    plain._scramble = lambda info: info
    for seed in (2_000_100, 2_000_101):
        plain.actions.clear()
        scrambled.actions.clear()
        _climb_episode(plain, seed)
        labels = _climb_episode(scrambled, seed)[1]
        n = min(len(plain.actions), len(scrambled.actions))
        assert n >= 3
        np.testing.assert_array_equal(np.asarray(plain.actions[:n]), np.asarray(scrambled.actions[:n]))
        assert labels[0][0] > 0.0


def test_on_policy_climbs_are_the_deployed_interrogators_own_with_the_truths_labels():
    """``collect(..., policy=DIR)`` records the interrogator of DIR acting as it is deployed: the same
    readings window by window as the agent played by hand on the same episodes (it never sees the truth),
    each labelled ``ln(M_sat / DC)`` and ``ln(CoF / CoA)`` from the episode's truth."""
    seeds = (2_000_700, 2_000_701)
    data = collect(cof_gym.WAGON_ENV_ID, [{}], len(seeds), first_seed=seeds[0], policy=str(SHIPPED_INTERROGATOR))
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = interrogator_for(env, SHIPPED_INTERROGATOR)
    for k, seed in enumerate(seeds):
        obs, info = env.reset(seed=seed)
        truth = info["ground_truth"]
        agent.reset(obs, agent_view(info, oracle=False))
        readings, labels = [], []
        while True:
            action = agent.act(obs, agent_view(info, oracle=False))
            dc = agent.dc_nm
            obs, _, terminated, truncated, info = env.step(action)
            readings.append(astuple(Reading.of(obs, env.unwrapped.limits, info)))
            labels.append((math.log(truth["saturation_torque_nm"] / dc), math.log(truth["cof"] / readings[-1][READING_FIELDS.index("coa")])))
            if terminated or truncated:
                break
        rows = data.episode == k
        assert rows.sum() == len(readings) >= 3
        np.testing.assert_array_equal(data.readings[rows], np.asarray(readings))
        np.testing.assert_allclose(data.targets[rows], np.asarray(labels), rtol=1e-12)


def test_procedural_shapes_are_valid_creep_laws_with_their_peak_where_drawn():
    """Every procedural curve is a table the env accepts (rising strictly to exactly 1, then anything
    in [0, 1]), peaks at a creepage in PROCEDURAL_PEAK_CREEPAGE and reproduces from its seed."""
    for seed in range(200):
        spec = procedural_shape(np.random.default_rng([seed, 11]))
        shape = creep_law_from_spec(spec)
        creepage, ratio = np.asarray(shape.creepage), np.asarray(shape.adhesion_ratio)
        lo, hi = PROCEDURAL_PEAK_CREEPAGE
        assert lo <= creepage[shape.peak_index] <= hi
        assert np.all(ratio[shape.peak_index:] <= 1.0) and np.all(ratio >= 0.0)
        assert spec == procedural_shape(np.random.default_rng([seed, 11]))


def test_steep_procedural_shapes_fall_as_drawn_and_the_default_draws_are_unchanged():
    """STEEP_FALL curves are valid tables that lose 20-60 % of the peak adhesion, most of it within
    0.3 peak creepages of the peak (a decay length <= 0.3); GENTLE_FALL is the default draw."""
    for seed in range(100):
        spec = procedural_shape(np.random.default_rng([seed, 13]), STEEP_FALL)
        shape = creep_law_from_spec(spec)
        x = np.asarray(shape.creepage) / shape.creepage[shape.peak_index]
        ratio = np.asarray(shape.adhesion_ratio)
        assert 0.4 - 1e-3 <= ratio[-1] <= 0.8 + 1e-3  # x = 4: exp(-3 / 0.3) of the drop is left
        assert ratio[x >= 1.3][0] <= 1.0 - 0.2 * (1.0 - math.exp(-1.0))  # past one decay length
        assert procedural_shape(np.random.default_rng([seed, 11]), GENTLE_FALL) == procedural_shape(
            np.random.default_rng([seed, 11]))
    with pytest.raises(ValueError, match="FallingBranch.drops"):
        FallingBranch(drops=(0.5, 0.2))


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


def _window(phase_deg: float, se_deg: float) -> Reading:
    """A driven window with this lag and standard error (the rest does not enter the knee test)."""
    return Reading(phase_deg=phase_deg, se_deg=se_deg, compliance=1e-4, coa=0.05, creepage=0.0, dc_nm=4000.0,
                   amplitude_nm=1600.0, frequency_hz=5.0, speed_m_s=10.0, normal_load=1.0)


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
    assert params.knee_stops(_window(*reading), _window(*previous), driven, crept) is stops
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


def test_floor_jump_training_climbs_take_the_floor_step():
    """A collection with floor_margins takes the floor step when it is the larger (at a high CoF its
    second window lands within the largest margin of the floor); without it, the same first window."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    options = {"condition": "dry", "cof": 0.55, "load_case": "laden"}
    jumped, _ = _climb_episode(FixedOptions(env, options), 2_000_200, ClimbDraws(floor_margins=(0.1, 0.5)))
    plain, _ = _climb_episode(FixedOptions(env, options), 2_000_200)
    assert jumped[0] == plain[0]
    assert jumped[1].coa > plain[1].coa
    assert floor_headroom(jumped[1].coa) < 0.5 + 0.05  # landed within the largest margin of the floor
    with pytest.raises(ValueError, match="floor_margins"):
        ClimbDraws(floor_margins=(0.5, 0.1))


def test_crest_shrink_training_climbs_shrink_their_modulation_and_never_grow_it():
    """With crest_powers the modulation ratio (amplitude / DC) falls as the slope falls and never rises
    again, down to no less than CREST_RATIO_FLOOR; the first window is the plain climb's."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    options = {"condition": "wet", "cof": 0.12, "load_case": "empty"}  # the crest stays within the drive's range
    draws = ClimbDraws(amplitude_ratios=(0.4, 0.4), crest_powers=(2.0, 2.0))
    shrunk, _ = _climb_episode(FixedOptions(env, options), 2_000_300, draws)
    plain, _ = _climb_episode(FixedOptions(env, options), 2_000_300, ClimbDraws(amplitude_ratios=(0.4, 0.4)))
    assert shrunk[0] == plain[0]
    # the readings come from the float32 observation: a ratio carries a relative error of a few 1.2e-7
    ratios = np.array([r.amplitude_nm / r.dc_nm for r in shrunk])
    assert np.all(np.diff(ratios) <= 1e-5) and ratios[-1] < 0.2 and ratios.min() >= CREST_RATIO_FLOOR * (1 - 1e-5)
    assert [r.amplitude_nm / r.dc_nm for r in plain] == pytest.approx([0.4] * len(plain), rel=1e-5)
    with pytest.raises(ValueError, match="crest_powers"):
        ClimbDraws(crest_powers=(2.0, 0.5))


def test_noisy_training_climbs_draw_the_sensors_noise_and_the_drives_lag_in_their_ranges():
    """With noise_levels and motor_lags_s a training climb's episode plays a noise level and a motor lag drawn in
    those ranges (from a generator of the seed's own, the same for the same seed), set as reset options that
    the env plays (its ground truth says so); without them the reset leaves both to the env; ranges beyond
    what the env accepts are refused naming the field."""
    class Recorder(gym.Wrapper):
        def reset(self, **kwargs):
            self.options = kwargs.get("options")
            obs, info = self.env.reset(**kwargs)
            self.truth = info["ground_truth"]
            return obs, info

    draws = ClimbDraws(noise_levels=(2.0, 3.0), motor_lags_s=(0.05, 0.1))
    env = Recorder(gym.make(cof_gym.WAGON_ENV_ID))
    drawn = []
    for seed in (2_000_500, 2_000_501, 2_000_500):
        _climb_episode(env, seed, draws)
        assert 2.0 <= env.options["noise_level"] <= 3.0 and 0.05 <= env.options["motor_lag_s"] <= 0.1
        assert env.truth["noise_level"] == env.options["noise_level"]
        drawn.append(env.options)
    assert drawn[0] == drawn[2] != drawn[1]
    _climb_episode(env, 2_000_500)
    assert env.options is None and env.truth["noise_level"] <= 1.0
    for field, bad in (("noise_levels", (0.0, 4.0)), ("motor_lags_s", (0.0, 0.2))):
        with pytest.raises(ValueError, match=field):
            ClimbDraws(**{field: bad})


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


def _readings(creepages, coas):
    return [Reading(20.0 + 5 * k, 0.5, 0.5, coa, s, 1000.0 * (1 + k), 400.0 * (1 + k), 5.0, 20.0, 1.0)
            for k, (s, coa) in enumerate(zip(creepages, coas))]


def test_creepage_rise_block_is_offset_free_and_reads_the_rise():
    """The creepage_rise block: ln of the rise since the first window, of the rise per CoA rise and of
    the last step's rise; a constant creepage offset (a speed-sensor bias) changes none of them."""
    creepages, coas = [0.001, 0.003, 0.006], [0.1, 0.15, 0.2]
    feats = EpisodeFeatures(False, blocks=("creepage_rise",))
    shifted = EpisodeFeatures(False, blocks=("creepage_rise",))
    for a, b in zip(_readings(creepages, coas), _readings([s + 0.013 for s in creepages], coas)):
        feats.push(a)
        shifted.push(b)
    v, w = feats.vector(), shifted.vector()
    n = len(FEATURE_NAMES)
    assert v.shape == (len(feature_names(("creepage_rise",))),) == (n + len(CREEPAGE_RISE_FEATURE_NAMES),)
    np.testing.assert_allclose(v[n:], [math.log(0.005), math.log(0.005 / 0.1), math.log(0.003)], rtol=1e-9)
    np.testing.assert_allclose(v, w, rtol=0, atol=1e-12)  # differences of creepages: the offset cancels
    falling = EpisodeFeatures(False, blocks=("creepage_rise",))
    for r in _readings([0.004, 0.003], [0.1, 0.09]):
        falling.push(r)
    np.testing.assert_allclose(falling.vector()[n:], np.log(CREEPAGE_RISE_FLOORS))  # no rise: the floors


def test_creepage_modulation_block_reads_the_tangent_flexibility_and_its_noise():
    """The creepage_modulation block: the lag and SE of the measured creepage's modulation, ln of its
    swing per relative torque modulation, ln of its swing per torque against the first and the previous
    windows (a scale error of the creepage cancels in both ratios), the previous window's lag."""
    def reading(k: int, swing: float, scale: float = 1.0) -> Reading:
        return replace(_readings([0.001], [0.1])[0], dc_nm=1000.0 * (1 + k), amplitude_nm=400.0 * (1 + k),
                       creepage_modulation=scale * swing, creepage_modulation_lag_deg=10.0 * (k + 1),
                       creepage_modulation_se_deg=12.0)
    swings = [1e-4, 3e-4, 1.2e-3]  # per 400, 800, 1200 N m of modulation
    feats = EpisodeFeatures(False, blocks=("creepage_modulation",))
    scaled = EpisodeFeatures(False, blocks=("creepage_modulation",))
    for k, swing in enumerate(swings):
        feats.push(reading(k, swing))
        scaled.push(reading(k, swing, scale=1.02))
    v, w = feats.vector(), scaled.vector()
    n = len(FEATURE_NAMES)
    assert v.shape == (n + len(CREEPAGE_MODULATION_FEATURE_NAMES),)
    np.testing.assert_allclose(v[n:], [30.0 / 90.0, 12.0 / 30.0, math.log(1.2e-3 / 0.4),
                                       math.log((1.2e-3 / 1200.0) / (1e-4 / 400.0)),
                                       math.log((1.2e-3 / 1200.0) / (3e-4 / 800.0)), 20.0 / 90.0], rtol=1e-12)
    np.testing.assert_allclose(w[n + 3:n + 5], v[n + 3:n + 5], rtol=0, atol=1e-12)  # the scale error cancels


def test_cycle_crest_block_reads_the_crests_lift_its_clipping_and_the_climbs_best_bound():
    """The cycle_crest block: ln of the crest over the mean CoA and of the mean over the trough, their ratio
    (0 for a symmetric cycle, below 0 for a clipped crest), the crest's lift per lift of the torque's crest,
    ln of the best crest bound so far over the CoA, a bin's SE over the CoA and the crest's step; ratios of
    force readings, so a force gain cancels. A reading without the crest is refused, naming it."""
    def reading(k: int, coa: float, crest: float, trough: float, gain: float = 1.0) -> Reading:
        return replace(_readings([0.001], [0.1])[0], dc_nm=1000.0 * (1 + k), amplitude_nm=400.0 * (1 + k),
                       coa=gain * coa, coa_cycle_max=gain * crest, coa_cycle_min=gain * trough,
                       coa_cycle_bin_se=gain * 0.001)
    windows = [(0.10, 0.13, 0.07), (0.20, 0.26, 0.14), (0.25, 0.28, 0.19)]  # the last one's crest clipped
    feats, scaled = (EpisodeFeatures(False, blocks=("cycle_crest",)) for _ in range(2))
    for k, (coa, crest, trough) in enumerate(windows):
        feats.push(reading(k, coa, crest, trough))
        scaled.push(reading(k, coa, crest, trough, gain=1.03))
    v, w = feats.vector(), scaled.vector()
    n = len(FEATURE_NAMES)
    assert v.shape == (n + len(CYCLE_CREST_FEATURE_NAMES),)
    lift, drop = math.log(0.28 / 0.25), math.log(0.25 / 0.19)
    np.testing.assert_allclose(v[n:], [lift, drop, math.log(lift / drop), lift / math.log1p(0.4),
                                       math.log((0.28 - 0.001) / 0.25), 0.001 / 0.25, math.log(0.28 / 0.26)],
                               rtol=1e-12)
    assert v[n + 2] < 0.0  # the clipped crest lifts less than the trough drops
    np.testing.assert_allclose(w[n:], v[n:], rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="coa_cycle_max"):
        EpisodeFeatures(False, blocks=("cycle_crest",)).push(reading(0, 0.1, 0.0, 0.0))


def test_feature_blocks_name_themselves_in_the_networks_file(tmp_path):
    for blocks in ((), ("tone2",), ("creepage_rise",), ("tone2", "creepage_rise"), ("creepage_modulation",),
                   ("tone2", "creepage_rise", "creepage_modulation"), ("cycle_crest",),
                   ("creepage_modulation", "cycle_crest")):
        assert blocks_of(feature_names(blocks)) == blocks
    assert feature_names(("creepage_rise", "tone2")) == feature_names(("tone2", "creepage_rise"))  # one order
    with pytest.raises(ValueError, match="feature blocks must be among"):
        feature_names(("harmonics",))
    with pytest.raises(ValueError, match="tone2 follows the data"):
        FitSettings(features=("tone2",)).blocks(None)
    data = collect(cof_gym.WAGON_ENV_ID, [{}], 4, first_seed=2_000_500)
    member = fit_member(data, seed=0, settings=FitSettings(hidden=(8,), epochs=3, features=("creepage_rise",)))
    member.save(tmp_path / "member_0.npz")
    loaded = FilterNetwork.load(tmp_path / "member_0.npz")
    assert loaded.blocks == ("creepage_rise",) and loaded.tones == 1
    agent = LearnedInterrogator(gym.make(cof_gym.WAGON_ENV_ID).unwrapped.limits, FilterEnsemble((loaded,)))
    actions, info = play(agent, 7)
    assert agent.features.blocks == ("creepage_rise",) and np.all(np.isfinite(actions))


def constant_network(headroom: float, correction: float, log_variance: float = -6.0) -> FilterNetwork:
    """A member whose prediction is the same whatever it reads (its last layer is a bias alone)."""
    n, width = len(FEATURE_NAMES), 4
    weights = (np.zeros((n, width)), np.zeros((width, 2 * len(TARGET_NAMES))))
    return FilterNetwork(np.zeros(n), np.ones(n), weights,
                         (np.zeros(width), np.array([headroom, correction, log_variance, log_variance])))


def test_a_guard_like_the_filter_or_bolder_leaves_the_climb_unchanged():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    ensemble = FilterEnsemble((random_network(5), random_network(6)))
    alone, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble), 8)
    twin, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble, guards=(ensemble,)), 8)
    bold, _ = play(LearnedInterrogator(env.unwrapped.limits, ensemble, guards=(FilterEnsemble((constant_network(5.0, 0.0),)),)), 8)
    np.testing.assert_array_equal(twin, alone)
    np.testing.assert_array_equal(bold, alone)


def test_a_cautious_guard_stops_the_climb_and_the_estimate_stays_the_filters():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    primary = FilterEnsemble((constant_network(1.0, 0.2),))  # far from the peak: it would step on
    guard = FilterEnsemble((constant_network(-0.5, -0.4),))  # past the target: no step
    free = LearnedInterrogator(limits, primary)
    actions, _ = play(free, 8)
    assert len(actions) > 3 and free.stop_reason != "headroom"
    guarded = LearnedInterrogator(limits, primary, guards=(guard,))
    actions, info = play(guarded, 8)
    assert len(actions) == 2 and guarded.stop_reason == "headroom"  # the first window, then the stop
    coa = guarded.features.readings[-1].coa
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(0.2), rel=1e-6)  # the filter's correction


def test_guard_cautions_give_each_guard_its_own_caution_and_the_climbs_caution_changes_nothing():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    ensemble = FilterEnsemble((random_network(5), random_network(6)))
    params = ClimbParameters(caution=2.0, guard_cautions=[1.0, 3.0])
    assert params.guard_cautions == (1.0, 3.0) and params.guard_caution(1) == 3.0
    assert ClimbParameters(**json.loads(json.dumps(asdict(params)))) == params  # a manifest's list reads back
    assert ClimbParameters(caution=2.0).guard_caution(1) == 2.0
    agent = LearnedInterrogator(limits, ensemble, params=params, guards=(ensemble, ensemble))
    column = lambda v: np.array([[v, 0.0]])  # noqa: E731 (headroom, correction) outputs
    guard = (column(0.9), column(0.1), column(0.0))
    # the filter: 1.0 - 2 x 0.1 = 0.8; guard 0: 0.9 - 1 x 0.1 = 0.8, not lower; guard 1: 0.9 - 3 x 0.1 = 0.6
    steering = agent._steering_headroom(params, column(1.0), column(0.1), column(0.0), [guard, guard])
    assert steering == pytest.approx((0.6, 0.1, 0.0, 3.0), abs=1e-15)
    assert params.mean_headroom(steering[0], 0.1, 0.0, steering[3]) == pytest.approx(0.9, abs=1e-15)  # the guard's mean
    with pytest.raises(ValueError, match="guard_cautions names 2 caution.*1 guard"):
        LearnedInterrogator(limits, ensemble, params=params, guards=(ensemble,))
    primary = FilterEnsemble((constant_network(1.0, 0.2),))  # far from the peak and sure of it: steps on
    unsure = (FilterEnsemble((constant_network(0.5, 0.2, log_variance=-2.0),)),)  # std e^-1: 0.5 - 2 x 0.37 < 0
    climbs = {cautions: play(LearnedInterrogator(limits, primary, params=replace(params, guard_cautions=cautions),
                                                 guards=unsure), 8)[0] for cautions in (None, (2.0,), (0.0,))}
    np.testing.assert_array_equal(climbs[(2.0,)], climbs[None])  # the climb's own caution: nothing changes
    assert len(climbs[None]) == 2 and len(climbs[(0.0,)]) > 3  # the unsure guard stops it, or not at caution 0


def test_the_lockin_noise_reading_follows_the_sensors_noise(env):
    """Reading.lockin_noise_nms (the phase SE times the response amplitude) of one episode's first window,
    driven alike at every noise level, is the fit's residual: in proportion to the sensors' noise level (the
    same noise samples, scaled), and without noise only what a sine does not fit (under 2 % of level 1's)."""
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(5),)))
    noise = {}
    for level in (0.0, 1.0, 2.0):
        run_episode(env, agent, 8, {"noise_level": level}, 0)
        noise[level] = agent.features.readings[0].lockin_noise_nms
    assert noise[1.0] > 0.0 and noise[0.0] < 0.02 * noise[1.0]
    assert noise[2.0] / noise[1.0] == pytest.approx(2.0, rel=0.03)  # the level-0 residual adds in quadrature


def test_the_noise_ratio_is_the_median_of_the_first_windows_over_the_reference():
    def noisy(se_deg: float) -> Reading:
        return replace(_window(10.0, se_deg), compliance=0.2)  # noise: rad(se) x 0.2 x 1600 N m / (2 pi 5 Hz)

    readings = [noisy(se) for se in (2.0, 8.0, 4.0, 30.0)]  # the fourth window is past NOISE_WINDOWS
    noise = [r.lockin_noise_nms for r in readings]
    assert noise[0] == pytest.approx(math.radians(2.0) * 0.2 * 1600.0 / (2.0 * math.pi * 5.0), rel=1e-12)
    params = ClimbParameters(noise_reference_nms=noise[0])
    assert params.noise_ratio(readings) == pytest.approx(2.0, rel=1e-12)  # the median 4 deg over 2 deg
    assert params.noise_ratio(readings[:2]) == pytest.approx(2.5, rel=1e-12)  # the mean of two
    assert ClimbParameters(noise_reference_nms=noise[3]).noise_ratio(readings) == 1.0  # never below 1
    assert ClimbParameters().noise_ratio(readings) == 1.0 and params.noise_ratio([]) == 1.0


def test_the_reported_standard_error_reads_noise_the_clip_hides():
    window = replace(_window(10.0, SE_CLIP_DEG), compliance=0.2)  # the filter's clip: 30 deg
    scale = 0.2 * 1600.0 / (2.0 * math.pi * 5.0)  # the response amplitude, N m s per rad
    readings = [replace(window, se_reported_deg=se) for se in (60.0, 90.0, 20.0)]
    assert [r.lockin_noise_nms for r in readings] == pytest.approx([math.radians(30.0) * scale] * 3, rel=1e-12)
    assert [r.lockin_noise_reported_nms for r in readings] == pytest.approx(
        [math.radians(se) * scale for se in (60.0, 90.0, 20.0)], rel=1e-12)
    assert window.lockin_noise_reported_nms == window.lockin_noise_nms  # not read (0): the clipped one
    reference = math.radians(30.0) * scale
    assert ClimbParameters(noise_reference_nms=reference).noise_ratio(readings) == 1.0  # clipped: 30 / 30
    reported = ClimbParameters(noise_reference_nms=reference, noise_se_reported=True)
    assert reported.noise_ratio(readings) == pytest.approx(2.0, rel=1e-12)  # the median 60 deg over 30 deg
    with pytest.raises(ValueError, match="noise_se_reported"):
        ClimbParameters(noise_se_reported=1)


def test_a_window_observation_keeps_the_lock_ins_standard_error_up_to_its_no_information_value():
    limits = gym.make(cof_gym.WAGON_ENV_ID).unwrapped.limits
    observation = np.zeros(len(OBSERVATION_NAMES))
    observation[[OBSERVATION_NAMES.index("amplitude"), OBSERVATION_NAMES.index("frequency")]] = 0.1, 0.25
    for se_deg, clipped, reported in ((10.0, 10.0, 10.0), (45.0, SE_CLIP_DEG, 45.0), (400.0, SE_CLIP_DEG, 180.0)):
        observation[OBSERVATION_NAMES.index("phase_lag_se")] = se_deg / 90.0
        reading = Reading.of(observation, limits)
        assert (reading.se_deg, reading.se_reported_deg) == pytest.approx((clipped, reported), rel=1e-12)


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


def test_pooled_correction_is_the_inverse_variance_mean():
    assert pooled_correction([(0.2, 0.1), (0.5, 0.2)]) == pytest.approx((0.2 / 0.01 + 0.5 / 0.04) / 125.0, rel=1e-12)
    assert pooled_correction([(0.3, 0.05)]) == 0.3
    with pytest.raises(ValueError, match="no predictions"):
        pooled_correction([])


@pytest.mark.parametrize("source", ["guard", "pooled", "pooled_at_headroom"])
def test_the_guarded_estimates_read_the_guards_correction_and_leave_the_climb_alone(source):
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    primary = FilterEnsemble((constant_network(1.0, 0.2, log_variance=-6.0),))
    guard = FilterEnsemble((constant_network(5.0, -0.1, log_variance=-4.0),))  # bolder: it never steers
    shipped_like = LearnedInterrogator(limits, primary, guards=(guard,))
    reference, _ = play(shipped_like, 8)
    agent = LearnedInterrogator(limits, primary, params=ClimbParameters(estimate_from=source), guards=(guard,))
    actions, info = play(agent, 8)
    estimate = 3  # ACTION_NAMES index of cof_estimate
    np.testing.assert_array_equal(np.delete(actions, estimate, axis=1), np.delete(reference, estimate, axis=1))
    coa = agent.features.readings[-1].coa
    # each member's std is exp(log_variance / 2): e^-3 for the filter, e^-2 for the guard
    pooled = pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0))])
    correction = {"guard": -0.1, "pooled": pooled, "pooled_at_headroom": 0.2}[source]  # not a headroom stop here
    assert agent.stop_reason != "headroom"
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(correction), rel=1e-6)
    assert agent.candidate_estimates(1.0)["filter"] == pytest.approx(coa * math.exp(0.2), rel=1e-12)


def test_the_pooled_estimate_at_a_headroom_stop_and_the_filters_before_it():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    primary = FilterEnsemble((constant_network(1.0, 0.2, log_variance=-6.0),))
    guard = FilterEnsemble((constant_network(-0.5, -0.1, log_variance=-4.0),))  # past the target: it stops the climb
    agent = LearnedInterrogator(env.unwrapped.limits, primary, params=ClimbParameters(estimate_from="pooled_at_headroom"),
                                guards=(guard,))
    actions, info = play(agent, 8)
    assert len(actions) == 2 and agent.stop_reason == "headroom"
    coa = agent.features.readings[-1].coa
    pooled = pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0))])
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(pooled), rel=1e-6)


def test_a_guarded_estimate_without_guards_names_the_field():
    env = gym.make(cof_gym.WAGON_ENV_ID)
    with pytest.raises(ValueError, match="estimate_from"):
        LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(5),)),
                            params=ClimbParameters(estimate_from="pooled"))


@pytest.mark.parametrize("source", ["estimator", "estimator_pooled"])
def test_the_estimators_corrections_change_the_estimate_and_never_the_climb(source):
    """An estimator never steers: every action component but the estimate is byte-identical with and without
    it, even where its predicted headroom would stop the climb at once; the estimate reads its correction
    alone, or pooled with the filter's and the guards' (inverse-variance)."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    limits = env.unwrapped.limits
    primary = FilterEnsemble((constant_network(1.0, 0.2, log_variance=-6.0),))
    guard = FilterEnsemble((constant_network(5.0, -0.1, log_variance=-4.0),))
    estimator = FilterEnsemble((constant_network(-0.5, 0.05, log_variance=-5.0),))  # it would stop: it must not
    reference, _ = play(LearnedInterrogator(limits, primary, guards=(guard,)), 8)
    agent = LearnedInterrogator(limits, primary, params=ClimbParameters(estimate_from=source), guards=(guard,),
                                estimators=(estimator,))
    actions, info = play(agent, 8)
    estimate = 3  # ACTION_NAMES index of cof_estimate
    np.testing.assert_array_equal(np.delete(actions, estimate, axis=1), np.delete(reference, estimate, axis=1))
    coa = agent.features.readings[-1].coa
    pooled = pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0)), (0.05, math.exp(-2.5))])
    correction = {"estimator": 0.05, "estimator_pooled": pooled}[source]
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(correction), rel=1e-6)
    assert agent.candidate_estimates(1.0)["pooled"] == pytest.approx(
        coa * math.exp(pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0))])), rel=1e-12)


@pytest.mark.parametrize("source", ["estimator_pooled_at_headroom", "estimator_at_headroom"])
def test_the_estimators_read_at_a_headroom_stop_and_the_filters_before_it(source):
    """At a headroom stop the estimators' corrections, pooled with the filter's and the guard's or alone
    (inverse-variance); at any other stop the filter's."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    primary = FilterEnsemble((constant_network(1.0, 0.2, log_variance=-6.0),))
    guard = FilterEnsemble((constant_network(-0.5, -0.1, log_variance=-4.0),))  # past the target: it stops the climb
    estimators = tuple(FilterEnsemble((constant_network(5.0, c, log_variance=-5.0),)) for c in (0.3, 0.4))
    agent = LearnedInterrogator(env.unwrapped.limits, primary, guards=(guard,), estimators=estimators,
                                params=ClimbParameters(estimate_from=source))
    actions, info = play(agent, 8)
    assert len(actions) == 2 and agent.stop_reason == "headroom"
    coa = agent.features.readings[-1].coa
    theirs = [(0.3, math.exp(-2.5)), (0.4, math.exp(-2.5))]
    pooled = pooled_correction([(0.2, math.exp(-3.0)), (-0.1, math.exp(-2.0)), *theirs])
    correction = pooled if source == "estimator_pooled_at_headroom" else pooled_correction(theirs)
    assert info["cof_estimate"] == pytest.approx(coa * math.exp(correction), rel=1e-6)
    free = LearnedInterrogator(env.unwrapped.limits, primary, estimators=estimators,  # no guard: no headroom stop
                               params=ClimbParameters(estimate_from=source))
    _, info = play(free, 8)
    assert free.stop_reason != "headroom"
    assert info["cof_estimate"] == pytest.approx(free.features.readings[-1].coa * math.exp(0.2), rel=1e-6)


def test_an_estimators_estimate_without_estimators_names_the_field(tmp_path):
    env = gym.make(cof_gym.WAGON_ENV_ID)
    with pytest.raises(ValueError, match="estimate_from='estimator'.*no estimators"):
        LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(5),)),
                            params=ClimbParameters(estimate_from="estimator"))
    run = tmp_path / "run"
    (run / "est").mkdir(parents=True)
    random_network(1).save(run / "member_0.npz")
    constant_network(0.0, 0.1).save(run / "est" / "member_0.npz")
    (run / "manifest.json").write_text('{"estimators": ["est"], "climb": {"estimate_from": "estimator"}}')
    agent = interrogator_for(env, run)
    assert len(agent.estimators) == 1 and not agent.guards and agent.params.estimate_from == "estimator"
    assert not interrogator_for(env, run, params=ClimbParameters(), estimators=[]).estimators


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


def test_guards_come_from_the_manifest_and_must_drive_the_climbs_tones(tmp_path):
    env = gym.make(cof_gym.WAGON_ENV_ID)
    run, guard_dir = tmp_path / "run", tmp_path / "run" / "guard"
    guard_dir.mkdir(parents=True)
    random_network(1).save(run / "member_0.npz")
    constant_network(-0.5, 0.0).save(guard_dir / "member_0.npz")
    assert not interrogator_for(env, run).guards
    (run / "manifest.json").write_text('{"guards": ["guard"]}')
    agent = interrogator_for(env, run)
    assert len(agent.guards) == 1 and agent.guards[0].members[0].biases[-1][0] == -0.5
    assert not interrogator_for(env, run, guards=[]).guards
    names = feature_names(("tone2",))
    two_tone = FilterNetwork(np.zeros(len(names)), np.ones(len(names)), (np.zeros((len(names), 2 * len(TARGET_NAMES))),),
                             (np.zeros(2 * len(TARGET_NAMES)),), names)
    with pytest.raises(ValueError, match="guard reads another excitation"):
        LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(1),)),
                            guards=(FilterEnsemble((two_tone,)),))


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


def test_training_climbs_record_the_cycle_crest_and_a_cycle_crest_filter_fits_on_them(tmp_path):
    """Climbs collected now carry the CoA's cycle crest, trough and bin SE (read from info["measurement"]),
    so a filter reading the cycle_crest block fits on them and plays."""
    data = collect(cof_gym.WAGON_ENV_ID, [{}], 3, first_seed=2_000_700)
    crest, trough, coa = (data.readings[:, READING_FIELDS.index(f)] for f in ("coa_cycle_max", "coa_cycle_min", "coa"))
    assert (crest > coa).all() and (trough < coa).all() and (data.readings[:, READING_FIELDS.index("coa_cycle_bin_se")] > 0).all()
    member = fit_member(data, seed=0, settings=FitSettings(hidden=(8,), epochs=2, features=("cycle_crest",)))
    member.save(tmp_path / "member_0.npz")
    loaded = FilterNetwork.load(tmp_path / "member_0.npz")
    assert loaded.blocks == ("cycle_crest",)
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((loaded,)))
    obs, info = env.reset(seed=3)
    agent.reset(obs, info)
    for _ in range(3):
        obs, _, terminated, truncated, info = env.step(agent.act(obs, info))
        if terminated or truncated:
            break


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
    (free, _, _), (held, crept, crest) = windows[False], windows[True]
    start = next(k for k, (dc, c) in enumerate(held) if c == pytest.approx(crest, rel=1e-6))  # the probe's first
    assert crest is not None and held[:start + 1] == free[:start + 1]
    later = held[start + 1:]
    assert later and all(c <= crest * (1 + 1e-6) for _, c in later)  # float32 actions: a few epsilons
    assert all(b[0] > a[0] for a, b in zip(held[start:], later[:-1]))  # the DC rises under it (the last: the stop's)

