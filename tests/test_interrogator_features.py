"""The learned interrogator's readings and features (cof_gym/agents/interrogator/readings.py, features.py): the slope
from Eq. 3, the feature blocks, the lock-in's noise as the climb reads it."""

from __future__ import annotations

import math
from dataclasses import replace

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator import (
    APPLIED_AMPLITUDE_FEATURE_NAMES, CREEPAGE_MODULATION_FEATURE_NAMES, CREEPAGE_RISE_FEATURE_NAMES,
    CREEPAGE_RISE_FLOORS, CYCLE_CREST_FEATURE_NAMES,
    FEATURE_NAMES, PEAK_GAP_CLIP, SE_CLIP_DEG, ClimbParameters, EpisodeFeatures, FilterEnsemble, FilterNetwork,
    LearnedInterrogator, Reading, TORQUE_READING_FEATURE_NAMES, blocks_of, feature_names, peak_gap, slope_from_phase,
    slope_index,
)
from cof_gym.agents.interrogator.agent import SHIPPED_INTERROGATOR, interrogator_for, manifest_climb
from cof_gym.agents.interrogator.readings import TORQUE_BALANCE_RANGE, torque_balance_gain, torque_balance_ratio
from cof_gym.agents.interrogator.training import FitSettings, collect, fit_member
from cof_gym.commands.evaluate_episodes import run_episode
from cof_gym.task.interface import OBSERVATION_NAMES, encode_action
from interrogator_helpers import window_reading, play, random_network

def test_slope_index_is_ln_cot_and_falls_towards_the_peak():
    assert slope_index(45.0) == pytest.approx(0.0, abs=1e-12)
    assert slope_index(30.0) == pytest.approx(math.log(math.sqrt(3.0)), rel=1e-12)
    values = [slope_index(p) for p in (5, 20, 45, 70, 88, 89, 120)]
    assert all(a > b for a, b in zip(values, values[1:-1]))
    assert values[-1] == values[-2]  # clipped at 89 deg: finite


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


def test_the_torque_free_block_leaves_out_every_reading_of_the_torque_sensor():
    """A torque reading 15 % low raises every compliance by 1 / 0.85 (tone 2's too). The base and climb_fit
    features move, the torque_free ones do not move at all; they are the others, in their order, and a
    network's file names the block."""
    low = lambda readings: [replace(r, compliance=r.compliance / 0.85, tone2_compliance=r.tone2_compliance / 0.85)  # noqa: E731
                            for r in readings]
    readings = _readings([1e-3 * (1 + k) ** 1.5 for k in range(6)], [0.05 * (1 + k) ** 0.5 for k in range(6)])
    readings = [replace(r, compliance=0.1 + 0.12 * k, coa_cycle_max=r.coa * 1.02) for k, r in enumerate(readings)]
    for blocks in ((), ("climb_fit",), ("cycle_crest", "climb_fit")):
        vectors = {}
        for free in (False, True):
            wanted = (*blocks, "torque_free") if free else blocks
            for name, rs in (("drawn", readings), ("low", low(readings))):
                features = EpisodeFeatures(False, blocks=wanted)
                for r in rs:
                    features.push(r)
                vectors[free, name] = features.vector()
        assert not np.array_equal(vectors[False, "drawn"], vectors[False, "low"])
        assert np.array_equal(vectors[True, "drawn"], vectors[True, "low"])
        kept = [k for k, n in enumerate(feature_names(blocks)) if n not in TORQUE_READING_FEATURE_NAMES]
        assert np.array_equal(vectors[True, "drawn"], vectors[False, "drawn"][kept])
        assert feature_names((*blocks, "torque_free")) == tuple(feature_names(blocks)[k] for k in kept)
        assert blocks_of(feature_names((*blocks, "torque_free"))) == tuple(
            b for b in ("cycle_crest", "climb_fit", "torque_free") if b in (*blocks, "torque_free"))
    assert set(TORQUE_READING_FEATURE_NAMES) <= set(feature_names(("tone2", "climb_fit")))  # every name is a feature


def test_the_applied_amplitude_block_reads_what_the_drive_applied_in_place_of_the_command():
    """A drive that applies 30 % of the commanded modulation (a 0.1 s lag at 5 Hz): the applied_amplitude block's
    feature is the measured amplitude over the DC, it takes the commanded ratio's place (every other feature as
    without the block, in order), a network's file names the block, and a reading without the measured amplitude is
    refused rather than read as zero."""
    readings = [replace(r, torque_amplitude_measured_nm=0.3 * r.amplitude_nm)
                for r in _readings([1e-3 * (1 + k) for k in range(4)], [0.05 * (1 + k) ** 0.5 for k in range(4)])]
    for blocks in ((), ("climb_fit",), ("climb_fit", "torque_free")):
        plain = EpisodeFeatures(False, blocks=blocks)
        applied = EpisodeFeatures(False, blocks=(*blocks, "applied_amplitude"))
        for r in readings:
            plain.push(r)
            applied.push(r)
        names, applied_names = feature_names(blocks), feature_names((*blocks, "applied_amplitude"))
        kept = [k for k, name in enumerate(names) if name != "amplitude_ratio"]
        assert applied_names == (*(names[k] for k in kept), *APPLIED_AMPLITUDE_FEATURE_NAMES)
        assert blocks_of(applied_names) == (*blocks, "applied_amplitude")
        v, w = plain.vector(), applied.vector()
        assert v[names.index("amplitude_ratio")] == pytest.approx(0.4)  # 400 N m on 1000 N m, commanded
        assert w[-1] == pytest.approx(0.12) and np.array_equal(w[:-1], v[kept])
    with pytest.raises(ValueError, match="applied torque amplitude"):
        EpisodeFeatures(False, blocks=("applied_amplitude",)).push(_readings([1e-3], [0.05])[0])


def test_an_agent_on_torque_free_networks_plays_the_same_climb_whatever_the_torque_gain(env):
    """Filter and guard reading the torque_free features: the same actions and estimate with the torque reading 15 %
    low, as drawn and 15 % high (the climb's noise reading, which reads the compliance, acts only above its
    reference, unset here); on networks that read the compliance, the climb moves."""
    free = feature_names(("torque_free",))

    def climb(names: tuple[str, ...], gain: float) -> np.ndarray:
        """The estimate, then the cautious headroom that steered each window."""
        agent = LearnedInterrogator(env.unwrapped.limits, FilterEnsemble((random_network(3, names=names),)),
                                    guards=(FilterEnsemble((random_network(4, names=names),)),))
        estimate = run_episode(env, agent, 5, {"torque_gain_error": gain}, 0).estimate
        return np.array([estimate, *(d.steering_headroom for d in agent.decisions)])

    played = {gain: climb(free, gain) for gain in (-0.15, 0.0, 0.15)}
    assert np.array_equal(played[-0.15], played[0.0]) and np.array_equal(played[0.15], played[0.0])
    assert not np.array_equal(climb(FEATURE_NAMES, -0.15), climb(FEATURE_NAMES, 0.0))


@pytest.mark.parametrize("counter_torque", [False, True])
def test_the_torque_balance_reads_the_torque_gain_against_the_force_gain(counter_torque):
    """A climb's first window, far below the peak: its mean torque reading over the measured creep force times the
    wheel radius is (1 + e_T) / (1 + e_F) to within the wheel's mean spin acceleration over the window (under
    0.2 % on 120 drawn episodes; asserted here to 1 %); a window with no force, or a ratio no accepted errors
    give, calibrates nothing."""
    env = gym.make(cof_gym.WAGON_ENV_ID, counter_torque=counter_torque)
    limits = env.unwrapped.limits
    first_dc = LearnedInterrogator(limits, FilterEnsemble((random_network(1),))).climb.first_dc(limits)
    for seed, torque_gain, force_gain in ((1, -0.15, 0.0), (2, 0.08, -0.06), (3, 0.15, 0.1)):
        env.reset(seed=seed, options={"torque_gain_error": torque_gain, "force_gain_error": force_gain})
        observation, _, _, _, info = env.step(encode_action(first_dc, 0.4 * first_dc, 5.0, 0.2, False, limits))
        gain = torque_balance_gain(info["measurement"], limits.wheel_radius_m)
        assert gain == pytest.approx((1.0 + torque_gain) / (1.0 + force_gain), rel=1e-2)
        assert Reading.of(observation, limits, info).torque_balance == gain  # what the window's reading records
    env.close()
    window = {"torque_mean_nm": 1000.0, "tangential_force_measured_n": 1000.0 / 0.46}
    assert torque_balance_gain(window, 0.46) == pytest.approx(1.0, rel=1e-12)
    assert torque_balance_gain({**window, "tangential_force_measured_n": 0.0}, 0.46) == 1.0
    assert torque_balance_gain({**window, "torque_mean_nm": 1000.0 * TORQUE_BALANCE_RANGE[1] * 1.01}, 0.46) == 1.0


def test_the_torque_balance_is_read_only_where_the_first_window_has_settled():
    """ClimbParameters.torque_gain: 1 without torque_balance; with it the balance's ratio, unless the first window's
    lag is above torque_balance_max_lag_deg (a wheel whose settling time, tan(lag) / (2 pi f), is no longer small
    against the window); and a compliance calibrated by a gain is multiplied by it, the measured torque divided."""
    window = {"torque_mean_nm": 1100.0, "tangential_force_measured_n": 1000.0 / 0.46}
    settled, unsettled = (replace(window_reading(lag, 2.0), torque_balance=torque_balance_ratio(window, 0.46))
                          for lag in (40.0, 75.0))
    assert ClimbParameters().torque_gain(settled) == 1.0
    balance = ClimbParameters(torque_balance=True)
    assert balance.torque_gain(unsettled) == pytest.approx(1.1, rel=1e-12)
    assert balance.torque_gain(replace(unsettled, torque_balance=0.0)) == 1.0  # no balance read
    checked = replace(balance, torque_balance_max_lag_deg=60.0)
    assert checked.torque_gain(settled) == pytest.approx(1.1, rel=1e-12)
    assert checked.torque_gain(unsettled) == 1.0
    calibrated = replace(settled, torque_amplitude_measured_nm=1650.0).calibrated(1.1)
    assert (calibrated.compliance, calibrated.torque_amplitude_measured_nm) == pytest.approx((1.1e-4, 1500.0), rel=1e-12)
    with pytest.raises(ValueError, match="torque_balance_max_lag_deg"):
        ClimbParameters(torque_balance=True, torque_balance_max_lag_deg=-1.0)


def test_an_agent_with_the_torque_balance_plays_the_same_climb_whatever_the_torque_gain(env):
    """The shipped networks, which read the compliance, calibrated by the torque balance
    (ClimbParameters.torque_balance): the same steering headroom at every window and the same estimate with the
    torque reading 15 % low, as drawn and 15 % high (the physics does not see the sensor's gain, so the calibrated
    compliance differs only by the observation's float32 rounding, 6e-8 relative); without it the climb moves."""
    def climb(torque_balance: bool, gain: float) -> np.ndarray:
        """The estimate, then the cautious headroom that steered each window."""
        params = replace(manifest_climb(SHIPPED_INTERROGATOR), torque_balance=torque_balance)
        agent = interrogator_for(env, SHIPPED_INTERROGATOR, params=params)
        estimate = run_episode(env, agent, 5, {"torque_gain_error": gain}, 0).estimate
        return np.array([estimate, *(d.steering_headroom for d in agent.decisions)])

    played = {gain: climb(True, gain) for gain in (-0.15, 0.0, 0.15)}
    assert len(played[-0.15]) == len(played[0.0]) == len(played[0.15]) > 3
    assert np.allclose(played[-0.15], played[0.0], rtol=1e-5, atol=1e-6)
    assert np.allclose(played[0.15], played[0.0], rtol=1e-5, atol=1e-6)
    uncalibrated = climb(False, -0.15), climb(False, 0.0)
    assert len(uncalibrated[0]) != len(uncalibrated[1]) or not np.allclose(*uncalibrated, rtol=1e-3)
    with pytest.raises(ValueError, match="torque_balance"):
        ClimbParameters(torque_balance=1)


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
        return replace(window_reading(10.0, se_deg), compliance=0.2)  # noise: rad(se) x 0.2 x 1600 N m / (2 pi 5 Hz)

    readings = [noisy(se) for se in (2.0, 8.0, 4.0, 30.0)]  # the fourth window is past NOISE_WINDOWS
    noise = [r.lockin_noise_nms for r in readings]
    assert noise[0] == pytest.approx(math.radians(2.0) * 0.2 * 1600.0 / (2.0 * math.pi * 5.0), rel=1e-12)
    params = ClimbParameters(noise_reference_nms=noise[0])
    assert params.noise_ratio(readings) == pytest.approx(2.0, rel=1e-12)  # the median 4 deg over 2 deg
    assert params.noise_ratio(readings[:2]) == pytest.approx(2.5, rel=1e-12)  # the mean of two
    assert ClimbParameters(noise_reference_nms=noise[3]).noise_ratio(readings) == 1.0  # never below 1
    assert ClimbParameters().noise_ratio(readings) == 1.0 and params.noise_ratio([]) == 1.0


def test_the_reported_standard_error_reads_noise_the_clip_hides():
    window = replace(window_reading(10.0, SE_CLIP_DEG), compliance=0.2)  # the filter's clip: 30 deg
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


@pytest.mark.parametrize("lag_s, torque_gain_error", [(0.0, 0.0), (0.1, 0.1), (0.05, -0.1)])
def test_the_noise_read_at_the_measured_torque_is_the_inertia_times_the_speed_amplitude(env, lag_s, torque_gain_error):
    """With ``measured_torque`` the noise reading's response amplitude is the compliance times the torque
    amplitude the drive measured: exactly the wheelset's inertia times the measured speed amplitude (the
    compliance is the speed amplitude over that measured torque, times ``I w``), whatever the drive's lag and
    the torque gain error; float32 observations round each factor to 6e-8. The commanded reading is larger by
    the commanded over the measured amplitude, which a 0.1 s lag makes about 1 / 0.30 at 5 Hz (first-order gain
    1 / sqrt(1 + (2 pi x 5 Hz x 0.1 s)^2); here asserted only below 1 / 0.5)."""
    obs, info = env.reset(seed=3, options={"motor_lag_s": lag_s, "torque_gain_error": torque_gain_error})
    limits = env.unwrapped.limits
    obs, _, _, _, info = env.step(encode_action(3000.0, 600.0, 5.0, 0.2, False, limits))
    reading = Reading.of(obs, limits, info)
    inertia = env.unwrapped.task.scales(env.unwrapped.episode.built).spin_inertia_kg_m2
    response = inertia * info["measurement"]["omega_amplitude_rad_s"]
    assert reading.lockin_noise(measured_torque=True) == pytest.approx(math.radians(reading.se_deg) * response,
                                                                       rel=1e-6)
    assert reading.lockin_noise() == pytest.approx(
        reading.lockin_noise(measured_torque=True) * reading.amplitude_nm / reading.torque_amplitude_measured_nm,
        rel=1e-6)
    if lag_s == 0.1:
        assert reading.torque_amplitude_measured_nm / (1.0 + torque_gain_error) < 0.5 * reading.amplitude_nm


def test_the_noise_ratio_can_read_the_torque_the_drive_measured():
    window = replace(window_reading(10.0, 8.0), compliance=0.2, se_reported_deg=16.0)
    halved = replace(window, torque_amplitude_measured_nm=window.amplitude_nm / 2.0)
    assert halved.lockin_noise(measured_torque=True) == pytest.approx(window.lockin_noise_nms / 2.0, rel=1e-12)
    assert halved.lockin_noise(True, True) == pytest.approx(window.lockin_noise_reported_nms / 2.0, rel=1e-12)
    assert window.lockin_noise(measured_torque=True) == window.lockin_noise_nms  # not read (0): the commanded one
    reference = halved.lockin_noise(measured_torque=True) / 2.0
    assert ClimbParameters(noise_reference_nms=reference).noise_ratio([halved]) == pytest.approx(4.0, rel=1e-12)
    measured = ClimbParameters(noise_reference_nms=reference, noise_torque_measured=True)
    assert measured.noise_ratio([halved]) == pytest.approx(2.0, rel=1e-12)
    with pytest.raises(ValueError, match="noise_torque_measured"):
        ClimbParameters(noise_torque_measured=1)
