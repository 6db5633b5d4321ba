"""The learned interrogator's training climbs and fits (cof_gym/agents/interrogator/training.py): steered by their
readings, never by the truth; procedural shapes; noisy, floor-jump and crest-shrink draws."""

from __future__ import annotations

import math
from dataclasses import astuple

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator import (
    CREST_RATIO_FLOOR, FEATURE_NAMES, SHIPPED_INTERROGATOR, FilterEnsemble, FilterNetwork, LearnedInterrogator,
    Reading, floor_headroom, interrogator_for,
)
from cof_gym.agents.interrogator.training import (
    FAR_PEAK_CREEPAGE, GENTLE_FALL, PROCEDURAL_PEAK_CREEPAGE, READING_FIELDS, STEEP_FALL, ClimbDraws, Dataset,
    FallingBranch, FitSettings, _climb_episode, collect, fit_member, procedural_shape,
)
from cof_gym.physics.creep_laws import creep_law_from_spec
from cof_gym.agents.base import agent_view
from fixed_options import FixedOptions

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


def test_far_peaks_stretch_the_same_curve_up_to_the_envs_largest_drawn_peak():
    """With FAR_PEAK_CREEPAGE a seed's curve is the default draw's (the same adhesion ratios) with its creepages scaled
    to a peak within that range, up to the largest peak the env draws; a range past it is refused by name."""
    peaks = []
    for seed in range(200):
        near = creep_law_from_spec(procedural_shape(np.random.default_rng([seed, 11])))
        far = creep_law_from_spec(procedural_shape(np.random.default_rng([seed, 11]), peak_creepages=FAR_PEAK_CREEPAGE))
        assert np.array_equal(far.adhesion_ratio, near.adhesion_ratio) and far.peak_index == near.peak_index
        scale = np.asarray(far.creepage[1:]) / np.asarray(near.creepage[1:])
        np.testing.assert_allclose(scale, scale[0], rtol=1e-12)
        peaks.append(far.creepage[far.peak_index])
    assert FAR_PEAK_CREEPAGE[0] <= min(peaks) and max(peaks) <= FAR_PEAK_CREEPAGE[1] == 0.2
    # ln(0.2 / 0.04) / ln(0.2 / 0.003): 38 % of the draws lie past the default's 4 %
    assert sum(p > PROCEDURAL_PEAK_CREEPAGE[1] for p in peaks) > 50
    with pytest.raises(ValueError, match="ClimbDraws.peak_creepages"):
        ClimbDraws(shapes="procedural", peak_creepages=(0.01, 0.3))


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


class ResetRecorder(gym.Wrapper):
    """Keeps the options of the last reset and the ground truth it gave."""

    def reset(self, **kwargs):
        self.options = kwargs.get("options")
        obs, info = self.env.reset(**kwargs)
        self.truth = info["ground_truth"]
        return obs, info


def test_noisy_training_climbs_draw_the_sensors_noise_and_the_drives_lag_in_their_ranges():
    """With noise_levels and motor_lags_s a training climb's episode plays a noise level and a motor lag drawn in
    those ranges (from a generator of the seed's own, the same for the same seed), set as reset options that
    the env plays (its ground truth says so); without them the reset leaves both to the env; ranges beyond
    what the env accepts are refused naming the field."""
    draws = ClimbDraws(noise_levels=(2.0, 3.0), motor_lags_s=(0.05, 0.1))
    env = ResetRecorder(gym.make(cof_gym.WAGON_ENV_ID))
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


def test_training_climbs_draw_the_encoders_lag_in_its_range_where_asked():
    """With encoder_lags_s a training climb's episode plays an encoder lag drawn in that range (the same for the same
    seed, from a generator of its own: the other draws unchanged), which the env plays (its ground truth says so);
    a range past what the env accepts is refused naming the field."""
    env = ResetRecorder(gym.make(cof_gym.WAGON_ENV_ID))
    drawn = []
    for seed in (3_300_500, 3_300_501, 3_300_500):
        _climb_episode(env, seed, ClimbDraws(encoder_lags_s=(0.005, 0.02)))
        assert 0.005 <= env.options["encoder_lag_s"] <= 0.02 and set(env.options) == {"encoder_lag_s"}
        assert env.truth["encoder_lag_s"] == env.options["encoder_lag_s"]
        drawn.append(env.options["encoder_lag_s"])
    assert drawn[0] == drawn[2] != drawn[1]
    with pytest.raises(ValueError, match="encoder_lags_s"):
        ClimbDraws(encoder_lags_s=(0.0, 0.1))


def test_training_climbs_draw_systematic_sensor_errors_past_the_envs_draws_where_asked():
    """With sensor_errors a training climb's episode plays each named systematic error drawn uniform in its range
    (the same for the same seed), as a reset option the env plays; ranges past what the env accepts, unknown
    fields and malformed entries are refused naming the field."""
    draws = ClimbDraws(sensor_errors=(("torque_gain_error", -0.15, -0.1), ("speed_sensor_error", 0.03, 0.05)))
    env = ResetRecorder(gym.make(cof_gym.WAGON_ENV_ID))
    drawn = []
    for seed in (2_000_600, 2_000_601, 2_000_600):
        _climb_episode(env, seed, draws)
        assert -0.15 <= env.options["torque_gain_error"] <= -0.1 and 0.03 <= env.options["speed_sensor_error"] <= 0.05
        assert env.truth["torque_gain_error"] == env.options["torque_gain_error"]
        drawn.append(env.options)
    assert drawn[0] == drawn[2] != drawn[1] and set(drawn[0]) == {"torque_gain_error", "speed_sensor_error"}
    for bad, match in (((("torque_gain_error", -0.2, 0.0),), "torque_gain_error"), ((("tilt_error", 0.0, 0.1),), "tilt"),
                       ((("torque_gain_error", 0.1),), "field, low, high"),
                       ((("force_gain_error", 0.05, -0.05),), "min <= max")):
        with pytest.raises(ValueError, match=match):
            ClimbDraws(sensor_errors=bad)


def test_calibrated_climbs_read_the_torque_sensor_at_the_force_channels_accuracy():
    """Dataset.calibrated divides an episode's torque readings by the gain its first window's torque balance reads
    (the climb's own ClimbParameters.torque_gain): the same training climbs with the torque reading 12 % high and
    exact read compliances 12 % apart as recorded and within the balance's 1 % once calibrated, the phases
    untouched; a lag bound below the first window's lag leaves the readings as read, and climbs recorded before
    the balance was read are refused."""
    seeds = (2_000_900, 2_000_901)
    exact, high = (collect(cof_gym.WAGON_ENV_ID, [{}], len(seeds), first_seed=seeds[0],
                           draws=ClimbDraws(sensor_errors=(("torque_gain_error", e, e), ("force_gain_error", 0.0, 0.0))))
                   for e in (0.0, 0.12))
    compliance = READING_FIELDS.index("compliance")
    rows = min(len(exact), len(high))  # the climbs read the phase, which the gain does not touch
    float32 = 4 * float(np.finfo(np.float32).eps)  # the observation's float32 rounding of both compliances
    np.testing.assert_allclose(high.readings[:rows, compliance] * 1.12, exact.readings[:rows, compliance], rtol=float32)
    calibrated = high.calibrated(None)
    np.testing.assert_allclose(calibrated.readings[:rows, compliance], exact.readings[:rows, compliance], rtol=1e-2)
    phase = READING_FIELDS.index("phase_deg")
    np.testing.assert_array_equal(calibrated.readings[:, phase], high.readings[:, phase])
    first_lag = float(high.readings[0, phase])
    np.testing.assert_array_equal(high.calibrated(first_lag - 1.0).readings[high.episode == 0],
                                  high.readings[high.episode == 0])
    recorded_before = Dataset(high.readings.copy(), high.counter_torque, high.targets, high.episode)
    recorded_before.readings[:, READING_FIELDS.index("torque_balance")] = 0.0
    with pytest.raises(ValueError, match="torque balance"):
        recorded_before.calibrated(None)


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
