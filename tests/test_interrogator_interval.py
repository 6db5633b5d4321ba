"""The calibrated interval around the learned interrogator's estimate (cof_gym.agents.interrogator.interval):
the split conformal quantile, the scales it gives, their file, and the agent's interval and lower bound."""

from __future__ import annotations

import io
import math
from dataclasses import replace

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.base import agent_view
from cof_gym.agents.interrogator import (
    COMMITMENTS, IN_FLIGHT, INTERVAL_FILE, NOISY, POOLED_NOISY, POOLED_SMOOTHED, SENSOR_CLASSES, SHIPPED_INTERROGATOR,
    SMOOTHED, lower_score, two_sided_score, IntervalScales, base_group, conformal_quantile, enough_for,
    interrogator_for, manifest_climb, noise_group, pooled_std, sensor_class_of, sensor_group,
)
from interrogator_helpers import SHIPPED, play


def test_the_conformal_quantile_is_the_finite_sample_rank():
    scores = [float(k) for k in range(1, 20)]  # n = 19: ceil(20 x 0.9) = 18th smallest
    assert conformal_quantile(scores, 0.9) == 18.0
    assert conformal_quantile(reversed(scores), 0.5) == 10.0  # ceil(20 x 0.5) = 10th, whatever the order
    with pytest.raises(ValueError, match="at least 19 are needed"):
        conformal_quantile(scores[:18], 0.95)  # ceil(19 x 0.95) = 19 > 18
    with pytest.raises(ValueError, match="finite"):
        conformal_quantile([1.0, math.nan, 2.0], 0.5)
    for bad in (0.0, 1.0, 1.5, math.nan, True):  # one message for every bad coverage, naming the open interval
        with pytest.raises(ValueError, match=r"coverage must be a (finite )?number in \(0, 1\)"):
            conformal_quantile(scores, bad)


def test_calibrated_scales_cover_new_exchangeable_episodes_as_promised():
    """Lognormal errors whose std each episode knows only up to a factor the calibration must find, a factor
    that differs between two commitments (the scores are exchangeable within each): the interval and the lower
    bound calibrated on 2000 episodes of each cover their targets on 20 000 fresh ones of each. Given one
    calibration set the coverage is a Beta variable of mean at least the target and standard deviation
    sqrt(c (1 - c) / n) (n = 2000), and the fresh count adds sqrt(c (1 - c) / 20 000): the test allows three of
    their combined standard deviations (2.1 and 1.5 points). The pooled scale, between the two, covers the wide
    commitment far less."""
    rng = np.random.default_rng(7)
    understated = {"stop": 1.2, "horizon": 2.5}  # the true log error's std over the stated std

    def draw(n: int, commitment: str) -> list[tuple[float, float, float, str]]:
        cof = rng.uniform(0.05, 0.5, n)
        log_std = rng.uniform(0.02, 0.3, n)
        estimate = cof * np.exp(understated[commitment] * log_std * rng.standard_normal(n))
        return [(e, c, s, commitment) for e, c, s in zip(estimate, cof, log_std)]

    scales = IntervalScales.calibrate(draw(2000, "stop") + draw(2000, "horizon"), 0.9, 0.95)
    assert scales.climbs == {"pooled": 4000, "stop": 2000, "horizon": 2000, "no stop": 0, "climbing": 0, "probing": 0}
    assert set(scales.scales) == {"pooled", "stop", "horizon"}  # none without climbs: it reads the pooled one
    assert scales.scale_of("no stop") == scales.scale_of("pooled")

    def allowance(c: float) -> float:
        return 3.0 * math.sqrt(c * (1.0 - c) * (1.0 / 2000 + 1.0 / 20_000))

    def covered(episodes, commitment=None) -> tuple[float, float]:
        inside, above = [], []
        for e, c, s, g in episodes:
            low, high = scales.interval(e, s, commitment or g)
            inside.append(low <= c <= high)
            above.append(scales.lower_bound(e, s, commitment or g) <= c)
        return float(np.mean(inside)), float(np.mean(above))

    for commitment, factor in understated.items():
        assert scales.scale_of(commitment)[0] == pytest.approx(factor * 1.645, rel=0.1)
        inside, above = covered(draw(20_000, commitment))
        assert inside >= 0.9 - allowance(0.9) and above >= 0.95 - allowance(0.95)
        assert inside <= 0.9 + allowance(0.9) + 1.0 / 2001  # and no wider than it needs: at most one rank above
    assert covered(draw(20_000, "horizon"), "pooled")[0] < 0.85


def episode_drawer(seed: int):
    """``draw(n, group, factor)``: ``n`` scored calibration episodes ``(estimate, CoF, log_std, group)`` whose log
    errors are ``factor`` times their std times a standard normal draw (one generator seeded ``seed``)."""
    rng = np.random.default_rng(seed)

    def draw(n: int, group: str, factor: float) -> list[tuple[float, float, float, str]]:
        cof, log_std = rng.uniform(0.05, 0.5, n), rng.uniform(0.02, 0.3, n)
        return [(c * math.exp(factor * s * z), c, s, group)
                for c, s, z in zip(cof, log_std, rng.standard_normal(n))]

    return draw


def test_in_flight_windows_take_scales_of_their_own_and_leave_the_pooled_one_to_the_commitments():
    """The pooled scale is the committed estimates' whatever in-flight windows the calibration also holds; each
    place in the climb gets the conformal quantile of its own windows' scores."""
    draw = episode_drawer(3)

    committed = draw(300, "stop", 1.0) + draw(100, "horizon", 2.0)
    windows = {"climbing": draw(200, "climbing", 4.0), "probing": draw(150, "probing", 0.5)}
    scales = IntervalScales.calibrate(committed + windows["climbing"] + windows["probing"], 0.9, 0.95)
    alone = IntervalScales.calibrate(committed, 0.9, 0.95)
    assert scales.scales["pooled"] == alone.scales["pooled"] and scales.climbs["pooled"] == 400
    for place, own in windows.items():
        assert scales.climbs[place] == len(own)
        assert scales.scale_of(place) == (conformal_quantile([two_sided_score(*w[:3]) for w in own], 0.9),
                                          conformal_quantile([lower_score(*w[:3]) for w in own], 0.95))
    assert scales.scale_of("climbing")[0] > scales.scale_of("horizon")[0] > scales.scale_of("probing")[0]


def test_noisy_climbs_take_scales_of_their_own_and_leave_the_draws_scales_as_they_were():
    """Climbs that read more noise than the draws give are scored in groups of their own: the clean groups' scales
    are those of a calibration without them (an interval file written before them stays as it was), each noisy
    group with enough climbs gets its own quantile, one with too few the noisy pooled one, and where a calibration
    holds no noisy climb a noisy group reads its base group's scale."""
    draw = episode_drawer(5)

    clean = draw(300, "stop", 1.0) + draw(100, "horizon", 2.0)
    noisy = draw(200, noise_group("stop", True), 3.0) + draw(5, noise_group("horizon", True), 6.0)
    alone, both = IntervalScales.calibrate(clean, 0.9, 0.95), IntervalScales.calibrate(clean + noisy, 0.9, 0.95)
    assert {g: both.scales[g] for g in alone.scales} == alone.scales and POOLED_NOISY not in alone.scales
    assert both.climbs[POOLED_NOISY] == 205 and both.climbs[noise_group("stop", True)] == 200
    own = [e for e in noisy if e[3] == noise_group("stop", True)]
    assert both.scale_of(noise_group("stop", True)) == (conformal_quantile([two_sided_score(*e[:3]) for e in own], 0.9),
                                                        conformal_quantile([lower_score(*e[:3]) for e in own], 0.95))
    assert both.scale_of(noise_group("stop", True))[0] > both.scale_of("stop")[0]  # 3 stds against 1
    assert both.scale_of(noise_group("horizon", True)) == tuple(both.scales[POOLED_NOISY])  # 5 are too few
    assert alone.scale_of(noise_group("horizon", True)) == alone.scale_of("horizon")
    assert base_group(noise_group("probing", True)) == "probing" and noise_group("probing", False) == "probing"


def test_a_smoothed_encoders_climbs_take_scales_of_their_own_beside_the_noisy_ones():
    """The smoothed-encoder class is calibrated apart from the draws' and the noisy ones: adding its climbs leaves
    every scale of a calibration without them as it was, its groups with enough climbs get their own quantiles, one
    with too few the class's pooled one, and without such climbs a smoothed group reads its base group's; what a
    smoothed group reads is never narrower than its base group's (the noisy ones are not floored)."""
    draw = episode_drawer(6)
    clean = draw(300, "stop", 1.0) + draw(100, "horizon", 2.0)
    noisy = draw(200, noise_group("stop", True), 3.0)
    smoothed = draw(250, sensor_group("horizon", SMOOTHED), 5.0) + draw(4, sensor_group("stop", SMOOTHED), 8.0)
    before, after = IntervalScales.calibrate(clean + noisy, 0.9, 0.95), IntervalScales.calibrate(
        clean + noisy + smoothed, 0.9, 0.95)
    assert {g: after.scales[g] for g in before.scales} == before.scales and POOLED_SMOOTHED not in before.scales
    assert after.climbs[POOLED_SMOOTHED] == 254 and after.climbs[sensor_group("horizon", SMOOTHED)] == 250
    own = [e for e in smoothed if e[3] == sensor_group("horizon", SMOOTHED)]
    assert after.scale_of(sensor_group("horizon", SMOOTHED)) == (
        conformal_quantile([two_sided_score(*e[:3]) for e in own], 0.9),
        conformal_quantile([lower_score(*e[:3]) for e in own], 0.95))
    assert after.scale_of(sensor_group("stop", SMOOTHED)) == tuple(after.scales[POOLED_SMOOTHED])  # 4 are too few
    assert after.scale_of(sensor_group("horizon", SMOOTHED))[0] > after.scale_of(noise_group("stop", True))[0]
    # never narrower than the base group's: smoothed climbs whose errors are smaller than the draws' leave those
    narrow = IntervalScales.calibrate(clean + draw(300, sensor_group("stop", SMOOTHED), 0.2), 0.9, 0.95)
    assert narrow.scales[sensor_group("stop", SMOOTHED)][0] < narrow.scales["stop"][0]  # calibrated: narrower
    assert narrow.scale_of(sensor_group("stop", SMOOTHED)) == narrow.scale_of("stop")  # read: the base group's
    estimate, log_std = 0.3, 0.1
    assert narrow.lower_bound(estimate, log_std, sensor_group("stop", SMOOTHED)) == narrow.lower_bound(
        estimate, log_std, "stop")
    noisy_narrow = IntervalScales.calibrate(clean + draw(300, noise_group("stop", True), 0.2), 0.9, 0.95)
    assert noisy_narrow.scale_of(noise_group("stop", True))[0] < noisy_narrow.scale_of("stop")[0]  # not floored
    assert before.scale_of(sensor_group("probing", SMOOTHED)) == before.scale_of("probing")
    for group in ("stop", "climbing"):
        for sensor_class in ("", *SENSOR_CLASSES):
            assert sensor_class_of(sensor_group(group, sensor_class)) == sensor_class
            assert base_group(sensor_group(group, sensor_class)) == group
    with pytest.raises(ValueError, match="sensor_class must be"):
        sensor_group("stop", "dirty")
    with pytest.raises(ValueError, match="scales must name"):
        IntervalScales(0.9, 0.95, {POOLED_SMOOTHED: [1.0, 1.0], "pooled": [1.0, 1.0], "stop, dirty": [1.0, 1.0]}, {})


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator")
def test_a_climb_is_noisy_where_its_first_windows_read_the_noise_past_the_draws():
    """The interval's noise class follows the climb's own noise reading (``ClimbParameters.noise_ratio``): clean at
    the draws' noise, noisy with the noise tripled; the committed estimate's group says so."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = interrogator_for(env, SHIPPED_INTERROGATOR)
    groups = {}
    for name, options in {"drawn": {}, "noisy": {"noise_level": 3.0}, "lagged": {"encoder_lag_s": 0.005}}.items():
        obs, info = env.reset(seed=60_001, options=options)
        agent.reset(obs, agent_view(info, oracle=False))
        done = False
        while not done:
            obs, _, terminated, truncated, info = env.step(agent.act(obs, agent_view(info, oracle=False)))
            done = terminated or truncated
        groups[name] = (agent.noisy, agent.interval_group, agent.commitment, agent.sensor_class)
    assert groups["drawn"][0] is False and groups["drawn"][1] == groups["drawn"][2] and groups["drawn"][3] == ""
    assert groups["noisy"][0] is True and groups["noisy"][1] == noise_group(groups["noisy"][2], True)
    assert groups["noisy"][3] == NOISY
    # a 5 ms lag: the sensor note's smoothed encoder (tests/test_sensor_notes.py), whose scales the interval reads
    assert groups["lagged"][3] == SMOOTHED and groups["lagged"][1] == sensor_group(groups["lagged"][2], SMOOTHED)
    own, base = agent.interval.scales[groups["lagged"][1]], agent.interval.scale_of(groups["lagged"][2])
    assert agent.interval.scale_of(groups["lagged"][1]) == (max(own[0], base[0]), max(own[1], base[1]))


def test_the_in_flight_calibration_draws_one_window_per_climb_and_place_and_the_table_counts_every_window(
        monkeypatch, tmp_path):
    """``experiments/estimate_interval.py``: a climb gives each place at most one calibration window, the same one
    for the same seed; the report counts every window in the band its crests had reached."""
    from conftest import EXPERIMENTS

    monkeypatch.syspath_prepend(EXPERIMENTS)
    from estimate_interval import Committed, InFlight, in_flight_calibration, in_flight_rows, plot_in_flight

    def window(estimate: float, place: str, utilisation: float) -> InFlight:
        return InFlight(estimate, 0.1, place, 0.05, utilisation)

    climbs = [Committed(0.2, 0.2, 0.1, "stop", "stop", (window(0.3, "climbing", 0.5), window(0.25, "climbing", 0.7),
                                                       window(0.21, "probing", 0.92))),
              Committed(0.1, 0.1, 0.1, "horizon", "horizon", (window(0.095, "climbing", 0.85),))]
    drawn = in_flight_calibration(climbs)
    assert sorted(d[3] for d in drawn) == ["climbing", "climbing", "probing"] and drawn == in_flight_calibration(climbs)
    assert {d[:3] for d in drawn if d[1] == 0.2 and d[3] == "climbing"} <= {(0.3, 0.2, 0.1), (0.25, 0.2, 0.1)}
    scales = IntervalScales(0.9, 0.95, {"pooled": [1.0, 1.0]}, {"pooled": 2})
    rows = {r.split(" | ")[1]: r.split(" | ")[2:] for r in in_flight_rows("grid", climbs, scales)}
    assert list(rows) == ["reached <= 80 % M_sat", "reached 80-90 % M_sat", "reached 90-95 % M_sat"]
    # 0.3 and 0.25 with bounds 0.3 e^-0.1 = 0.271 and 0.226: the CoF 0.2 is above neither, in neither interval
    assert rows["reached <= 80 % M_sat"][:4] == ["2", "37.5%", "0.0%", "0.0%"]  # errors 50 % and 25 %
    assert rows["reached 80-90 % M_sat"][:4] == ["1", "5.0%", "100.0%", "100.0%"]  # 0.095 x e^+-0.1 holds 0.1
    assert rows["reached 90-95 % M_sat"][-2:] == ["100.0%", "0.25 |"]  # the demonstrated 0.05 of a CoF of 0.2
    monkeypatch.setattr("estimate_interval.FIGURE_MIN_WINDOWS", 1)
    assert plot_in_flight({"grid": climbs}, scales, tmp_path / "in_flight.png").stat().st_size > 1000


def test_scales_check_their_fields_and_round_trip_through_their_file(tmp_path):
    scales = IntervalScales(0.9, 0.95, {"pooled": [1.5, 1.0], "horizon": [2.0, 1.2]},
                            {"pooled": 360, "stop": 5, "horizon": 179, "no stop": 0}, "validation")
    assert scales.save(tmp_path).name == INTERVAL_FILE
    assert IntervalScales.load(tmp_path) == scales
    assert IntervalScales.load(tmp_path / "none") is None
    low, high = scales.interval(0.2, 0.1)
    assert (low, high) == pytest.approx((0.2 * math.exp(-0.15), 0.2 * math.exp(0.15)), rel=1e-12)
    assert scales.interval(0.2, 0.1, "stop") == (low, high)  # not calibrated: the pooled scale
    assert scales.interval(0.2, 0.1, "horizon")[1] == pytest.approx(0.2 * math.exp(0.2), rel=1e-12)
    assert scales.lower_bound(0.2, 0.1, "horizon") == pytest.approx(0.2 * math.exp(-0.12), rel=1e-12)
    assert not enough_for(18, 0.95) and enough_for(19, 0.95)
    for field, bad, match in (("coverage", 1.0, "coverage"), ("lower_coverage", 0.0, "lower_coverage"),
                              ("scales", {"horizon": [1.0, 1.0]}, "pooled"),
                              ("scales", {"pooled": [1.0, 1.0], "later": [1.0, 1.0]}, "at most"),
                              ("scales", {"pooled": [-1.0, 1.0]}, "scale"),
                              ("scales", {"pooled": [1.0]}, "lower_scale")):
        with pytest.raises(ValueError, match=match):
            IntervalScales(**{**scales.__dict__, field: bad})


def test_the_pooled_std_is_each_ones_where_they_agree_and_does_not_shrink_with_their_count():
    assert pooled_std([(0.1, 0.2), (0.3, 0.2), (-1.0, 0.2)]) == pytest.approx(0.2, rel=1e-12)
    assert pooled_std([(0.0, 0.1), (0.0, 0.3)]) == pytest.approx(math.sqrt(2 / (100 + 100 / 9)), rel=1e-12)
    with pytest.raises(ValueError, match="no predictions"):
        pooled_std([])


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator")
def test_the_shipped_interrogator_reports_a_calibrated_interval_around_its_estimate(tmp_path):
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = interrogator_for(env, SHIPPED_INTERROGATOR)
    assert agent.interval == IntervalScales.load(SHIPPED_INTERROGATOR) and agent.interval.climbs["pooled"] >= 300
    assert agent.cof_interval() is not None  # before an episode: a point (no std yet), the estimate's floor
    actions, _ = play(agent, 3)
    low, high = agent.cof_interval()
    scale, lower_scale = agent.interval.scale_of(agent.commitment)
    assert agent.commitment in COMMITMENTS and agent.estimate_log_std > 0.0 and low < agent.estimate < high
    assert math.log(high / low) == pytest.approx(2 * scale * agent.estimate_log_std, rel=1e-12)
    assert agent.cof_lower_bound() == pytest.approx(
        agent.estimate * math.exp(-lower_scale * agent.estimate_log_std), rel=1e-12)
    for name in ("member_0.npz", "manifest.json"):  # the same policy without the calibration file
        (tmp_path / name).write_bytes((SHIPPED_INTERROGATOR / name).read_bytes())
    bare = interrogator_for(env, tmp_path, replace(manifest_climb(SHIPPED_INTERROGATOR), estimate_from="filter"),
                            guards=[])
    assert bare.interval is None and bare.cof_interval() is None and bare.cof_lower_bound() is None


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator")
def test_the_shipped_interrogator_bounds_the_cof_in_flight_at_its_places_scale():
    """Before the first window and once stopped there is no in-flight estimate; in between, the in-flight
    estimate is the estimate source's without the runaway's, its interval and lower bound read the place's
    scales, and the demonstrated adhesion only grows."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = interrogator_for(env, SHIPPED_INTERROGATOR)
    assert set(IN_FLIGHT) <= set(agent.interval.scales)  # the shipped calibration has both places
    obs, info = env.reset(seed=5)
    agent.reset(obs, agent_view(info, False))  # as cof-gym evaluate plays it: the crest readings in the info
    assert agent.in_flight is None and agent.in_flight_interval() is None and agent.in_flight_lower_bound() is None
    places, demonstrated, runaway_differs = [], [0.0], []
    while True:
        action = agent.act(obs, agent_view(info, False))
        if agent.in_flight is not None:
            places.append(agent.in_flight)
            estimate, std = agent.in_flight_estimate, agent.estimate_log_std
            expected = agent.candidate_estimates(agent.params.best_coa_factor, runaway=False)[agent.params.estimate_from]
            assert estimate == min(max(expected, agent.limits.min_cof_estimate), agent.limits.max_cof_estimate)
            scale, lower_scale = agent.interval.scale_of(agent.in_flight)
            low, high = agent.in_flight_interval()
            assert math.log(high / low) == pytest.approx(2 * scale * std, rel=1e-12) and low < estimate < high
            assert agent.in_flight_lower_bound() == pytest.approx(estimate * math.exp(-lower_scale * std), rel=1e-12)
            demonstrated.append(agent.demonstrated_adhesion)
            runaway_differs.append(agent.estimate != estimate)  # what the env would score were the wheel to run away
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    assert places[0] == "climbing" and set(places) <= set(IN_FLIGHT) and demonstrated == sorted(demonstrated)
    assert any(runaway_differs) and "probing" in places
    assert agent.stop_reason and agent.in_flight is None and agent.in_flight_estimate is None
    assert agent.in_flight_lower_bound() is None and agent.cof_lower_bound() is not None


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator")
def test_evaluate_records_and_summarises_the_intervals_agents_report():
    from cof_gym.agents.registry import make_agent
    from cof_gym.commands.evaluate_episodes import AgentError, run_episode
    from cof_gym.commands.evaluate_stats import summarize
    from cof_gym.commands.evaluate_tables import markdown_intervals, print_table
    from rich.console import Console

    env = gym.make(cof_gym.WAGON_ENV_ID)
    learned, rule = make_agent("interrogator", env), make_agent("phase-rule", env)
    records = [run_episode(env, agent, seed, {}, seed) for agent in (learned, rule) for seed in (0, 1, 2)]
    for r in records[:3]:
        assert 0.0 < r.lower_bound < r.estimate * 1.0001 and r.interval_low < r.estimate < r.interval_high
        assert r.in_interval == (r.interval_low <= r.cof <= r.interval_high)
    assert all(r.interval_low is None and r.lower_bound is None and r.in_interval is None for r in records[3:])
    summary = summarize(records, seed=0)
    assert "interval" not in summary["phase-rule"]
    stats = summary["interrogator"]["interval"]
    assert stats["episodes"] == 3 and stats["coverage"]["value"] == np.mean([r.in_interval for r in records[:3]])
    table = markdown_intervals(summary)
    assert table.count("\n") == 2 and "| interrogator | 3 |" in table and "phase-rule" not in table
    assert markdown_intervals(summarize(records[3:], seed=0)) == ""
    printed = io.StringIO()
    print_table(summary, "intervals", Console(file=printed, width=200, highlight=False, markup=False,
                                              color_system=None))
    line = next(row for row in printed.getvalue().splitlines() if "CoF in its reported interval" in row)
    assert line.split("│")[2].strip() == f"{100 * stats['coverage']['value']:.1f}" and line.split("│")[3].strip() == "-"

    class Careless:  # an agent whose interval is no interval
        name, oracle = "careless", False

        def __init__(self):
            self.inner = make_agent("phase-rule", env)

        def reset(self, obs, info):
            self.inner.reset(obs, info)

        def act(self, obs, info):
            return self.inner.act(obs, info)

        def cof_interval(self):
            return 0.3, 0.2

    with pytest.raises(AgentError, match="agent careless reported after its episode .*careless reported the interval"):
        run_episode(env, Careless(), 0, {}, 0)

    class IntervalOnly(Careless):  # an interval and no lower bound: no lower-bound coverage, not a NaN one
        name = "interval-only"

        def cof_interval(self):
            return 0.01, 1.0

    only = summarize([run_episode(env, IntervalOnly(), seed, {}, seed) for seed in (0, 1)], seed=0)
    assert only["interval-only"]["interval"]["coverage"]["value"] == 1.0
    assert "lower_bound_coverage" not in only["interval-only"]["interval"]
    assert markdown_intervals(only).splitlines()[-1] == "| interval-only | 2 | 100.0 [100.0, 100.0] | - | 100.00 |"


def test_estimate_interval_calibrates_each_sensor_class_on_its_own_plays_and_reports_the_lagged_suites(
        monkeypatch, tmp_path):
    """``experiments/estimate_interval.py --write`` with every play replaced by synthetic climbs: the draws' groups
    come from the plain validation plays alone, the noisy ones from the noisy plays' noisy climbs, the smoothed ones
    from the lagged plays' smoothed climbs (a noisy or a draws' climb there is left out), and the report has a row
    for each lagged default suite and the lagged held-out grid."""
    import shutil
    import sys
    from concurrent.futures import ThreadPoolExecutor

    from conftest import EXPERIMENTS

    monkeypatch.syspath_prepend(EXPERIMENTS)
    import estimate_interval

    def climbs(n: int, group: str, factor: float, seed: int) -> list:
        return [estimate_interval.Committed(e, c, s, group, "stop") for e, c, s, _ in
                episode_drawer(seed)(n, group, factor)]

    def play(policy, suite, config, scenario=None):
        seed = len(str(suite)) + 7 * bool(config)
        if scenario in estimate_interval.SMOOTHED_SCENARIOS and suite != "default":
            return (climbs(60, sensor_group("stop", SMOOTHED), 4.0, seed)
                    + climbs(10, noise_group("stop", True), 40.0, seed + 1) + climbs(10, "stop", 40.0, seed + 2))
        if scenario in estimate_interval.NOISY_SCENARIOS:
            return climbs(60, noise_group("stop", True), 2.0, seed) + climbs(10, "stop", 40.0, seed + 1)
        return climbs(60, "stop", 1.0, seed)

    policy = tmp_path / "policy"
    shutil.copytree(SHIPPED_INTERROGATOR, policy)
    monkeypatch.setattr(estimate_interval, "play", play)
    monkeypatch.setattr(estimate_interval, "ProcessPoolExecutor", ThreadPoolExecutor)
    monkeypatch.setattr(estimate_interval, "plot_in_flight", lambda suites, scales, path: path)
    monkeypatch.setattr(estimate_interval, "v2_heldout_grids", lambda: {"v2_heldout_grid": "v2 held-out grid"})
    monkeypatch.setattr(sys, "argv", ["estimate_interval.py", "--policy", str(policy), "--write",
                                      "--out", str(tmp_path / "report.md")])
    estimate_interval.main()
    scales = IntervalScales.load(policy)
    runs = len(estimate_interval.CALIBRATION) * len(estimate_interval.CONFIGS)
    assert scales.climbs["stop"] == 60 * runs
    assert scales.climbs[noise_group("stop", True)] == 60 * runs * len(estimate_interval.NOISY_SCENARIOS)
    assert scales.climbs[sensor_group("stop", SMOOTHED)] == 60 * runs * len(estimate_interval.SMOOTHED_SCENARIOS)
    assert scales.scale_of("stop")[0] < scales.scale_of(noise_group("stop", True))[0] < scales.scale_of(
        sensor_group("stop", SMOOTHED))[0] < 10.0  # 1, 2 and 4 stds; none of the 40-std climbs calibrated them
    report = (tmp_path / "report.md").read_text()
    for lag in estimate_interval.REPORTED_ENCODER_LAGS_S:
        assert f"| default suite, encoder lagged {1000 * lag:g} ms | 60 |" in report
    assert f"| v2 held-out grid, encoder lagged {1000 * estimate_interval.HELDOUT_ENCODER_LAG_S:g} ms |" in report
