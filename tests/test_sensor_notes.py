"""What the learned interrogator's own readings say lies outside the sensors it was fitted on (its
``sensor_notes()``): a smoothed encoder, read from the colour of the speed residual's noise, and a slow drive, read
from the modulation it applied; and how ``cof-gym evaluate`` records and reports them."""

from __future__ import annotations

import math
from dataclasses import replace

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents import registry
from cof_gym.agents.interrogator.readings import (
    COLOUR_NOISE_FLOOR_NMS, NOISE_WINDOWS, NOISY_SENSORS, SE_REPORTED_MAX_DEG, SLOW_DRIVE, SLOW_DRIVE_LAG_S,
    SMOOTHED_ENCODER, first_windows_noise_colour, reads_slow_drive, reads_smoothed_encoder,
)
from cof_gym.task.scenarios import ScenarioRanges
from cof_gym.commands.suites import make_suite
from cof_gym.commands.evaluate import sensor_notes
from cof_gym.commands.evaluate_episodes import AgentError, run_episode
from cof_gym.measurement.sine_fit import SMOOTHED_NOISE_COLOUR, colored_noise_factor
from cof_gym.physics.models import DEFAULT_TIMESTEP_S

from interrogator_helpers import SHIPPED, window_reading


def coloured(se_reported_deg: float, se_corrected_deg: float):
    """A driven window whose lock-in reported these standard errors (deg)."""
    return replace(window_reading(10.0, 1.0), se_reported_deg=se_reported_deg, se_corrected_deg=se_corrected_deg)


def test_the_noise_colour_is_the_corrected_se_over_the_white_one_and_zero_where_either_is_unread():
    assert coloured(2.0, 5.0).noise_colour == pytest.approx(2.5)
    assert coloured(2.0, 0.0).noise_colour == 0.0  # not read (climbs recorded before it)
    assert coloured(0.0, 2.0).noise_colour == 0.0
    assert coloured(2.0, SE_REPORTED_MAX_DEG).noise_colour == 0.0  # a multi-tone window reports no correction


def test_a_climb_reads_the_least_colour_of_its_first_windows():
    """The wheel's own harmonics can colour a later window's residual; a smoothing colours every window's."""
    readings = [coloured(1.0, c) for c in (3.0, 1.1, 4.0, 0.5)]
    assert first_windows_noise_colour(readings) == pytest.approx(1.1)  # the fourth is beyond NOISE_WINDOWS
    assert NOISE_WINDOWS == 3
    assert first_windows_noise_colour([coloured(1.0, 0.0)]) == 0.0
    assert first_windows_noise_colour([]) == 0.0


def test_a_smoothed_encoder_is_read_only_where_the_windows_read_sensor_noise():
    """The same coloured windows with the noise the lock-in reads above and below the floor: the colour of a residual
    without sensor noise is the wheel's own and says nothing of the encoder."""
    def windows(noise_nms: float, colour: float) -> list:
        # lockin_noise = se (rad) x compliance x amplitude / (2 pi f): compliance 0.5, 1000 N m at 5 Hz
        se_deg = math.degrees(noise_nms * 2 * math.pi * 5.0 / (0.5 * 1000.0))
        return [replace(window_reading(10.0, 1.0), compliance=0.5, amplitude_nm=1000.0, se_reported_deg=se_deg,
                        se_corrected_deg=colour * se_deg) for _ in range(NOISE_WINDOWS)]

    assert reads_smoothed_encoder(windows(2 * COLOUR_NOISE_FLOOR_NMS, 4.0))
    assert not reads_smoothed_encoder(windows(COLOUR_NOISE_FLOOR_NMS / 2, 4.0))
    assert not reads_smoothed_encoder(windows(2 * COLOUR_NOISE_FLOOR_NMS, 1.2))
    assert not reads_smoothed_encoder([])


def test_the_threshold_lies_between_white_noise_and_the_least_smoothing_the_chain_can_apply():
    """The native chain smooths ``y += (1 - phi) ((x_n + x_(n-1)) / 2 - y)``, ``phi = exp(-dt / tau)``: white
    readings leave an ARMA(1, 1) whose lag-1 correlation is ``(1 + phi) / 2``, at least 1/2 for any lag. Its
    autoregressive factor at 5 Hz is then above the threshold from a lag of 2 ms on (2.99 there); white noise's is 1."""
    omega_step = 2 * math.pi * 5.0 * DEFAULT_TIMESTEP_S
    assert colored_noise_factor(0.0, omega_step) == 1.0 < SMOOTHED_NOISE_COLOUR
    for lag_s in (0.002, 0.01, 0.05):
        rho = (1.0 + math.exp(-DEFAULT_TIMESTEP_S / lag_s)) / 2.0
        assert colored_noise_factor(rho, omega_step) > SMOOTHED_NOISE_COLOUR


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
@pytest.mark.parametrize("encoder_lag_s, notes", [(0.0, ""), (0.005, SMOOTHED_ENCODER)])
def test_the_shipped_interrogator_notes_a_smoothed_encoder_and_evaluate_records_it(encoder_lag_s, notes):
    """Training climbs read a colour of 0.86-1.61 with a sharp encoder (2.58 at most on nearly noiseless sensors)
    and 2.8 or more in 99 % of those lagged by 5-20 ms (docs/interrogator.md): at 5 ms, the threshold has a margin
    on both sides."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = registry.make_agent("interrogator", env)
    record = run_episode(env, agent, 11, {"encoder_lag_s": encoder_lag_s}, 0)
    env.close()
    assert record.sensor_notes == notes
    assert sensor_notes([record]) == ([] if not notes else [
        f"interrogator read its sensors outside those it was fitted on ({SMOOTHED_ENCODER}) in 1 of 1 episodes: "
        "its estimate there is an extrapolation"])


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_networks_fitted_on_another_ids_climbs_name_no_sensor_note(tmp_path):
    """The notes' bounds describe the v2 wagon's training climbs: the shipped networks, their manifest saying they
    were fitted on task v3's climbs (whose probe and track colour the residual), read the episode whose 5 ms encoder
    lag the shipped agent notes (above) and name nothing."""
    import json
    import shutil

    from cof_gym.agents.policy_files import MANIFEST_FILE, SHIPPED_INTERROGATOR

    directory = tmp_path / "fitted_on_v3"
    shutil.copytree(SHIPPED_INTERROGATOR, directory)
    manifest = json.loads((directory / MANIFEST_FILE).read_text())
    manifest["trained_on"]["env_id"] = cof_gym.WAGON_IN_SERVICE_ENV_ID
    (directory / MANIFEST_FILE).write_text(json.dumps(manifest))
    env = gym.make(cof_gym.WAGON_ENV_ID)
    shipped, fitted_on_v3 = (registry.make_agent(spec, env) for spec in ("interrogator", f"interrogator:{directory}"))
    records = [run_episode(env, agent, 11, {"encoder_lag_s": 0.005}, 0) for agent in (shipped, fitted_on_v3)]
    env.close()
    assert [r.sensor_notes for r in records] == [SMOOTHED_ENCODER, ""]
    assert records[0].estimate == records[1].estimate  # the notes change no step of the climb


def test_a_slow_drive_is_one_slower_than_the_draws_by_more_than_the_readings_spread():
    """The draws' slowest drive passes about 73 % of a 5 Hz modulation: not slow; one passing half of it (52 ms) is."""
    def passed(lag_s: float) -> float:
        return 1.0 / math.sqrt(1.0 + (2.0 * math.pi * 5.0 * lag_s) ** 2)

    slowest = ScenarioRanges().motor_lag_s[1]
    assert SLOW_DRIVE_LAG_S > slowest
    assert not reads_slow_drive([passed(slowest)] * NOISE_WINDOWS, 5.0)
    assert reads_slow_drive([0.5] * NOISE_WINDOWS, 5.0)
    assert not reads_slow_drive([0.5, 1.0, 1.0], 5.0) and not reads_slow_drive([], 5.0)  # the median; none read


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
@pytest.mark.parametrize("options, notes", [
    ({"motor_lag_s": 0.03}, ""),
    ({"motor_lag_s": 0.06}, SLOW_DRIVE),
    ({"motor_lag_s": 0.06, "encoder_lag_s": 0.005}, f"{SMOOTHED_ENCODER}; {SLOW_DRIVE}"),
    ({"noise_level": 1.0}, ""),
    ({"noise_level": 3.0}, NOISY_SENSORS),
])
def test_the_shipped_interrogator_notes_a_slow_drive_and_noisy_sensors_past_the_draws(options, notes):
    """The drive's lag read from the modulation it applied: the draws' slowest drive (30 ms) is not noted, one of
    60 ms is, beside a smoothed encoder where the speed signal is lagged too; the noise the first windows read (the
    interval's noisy class): not at the draws' full scale, at three times it."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = registry.make_agent("interrogator", env)
    record = run_episode(env, agent, 11, options, 0)
    env.close()
    assert record.sensor_notes == notes


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
@pytest.mark.parametrize("torque_gain_error, force_gain_error", [(0.05, -0.01), (-0.05, 0.01), (0.05, 0.01)])
def test_the_draws_slowest_drive_is_not_noted_at_the_ends_of_the_draws_gain_errors(torque_gain_error, force_gain_error):
    """The drive's reading goes through the torque sensor, calibrated against the force channel: at the ends of the
    gain errors the v2 draws give, the draws' slowest drive at their full-scale noise reads neither note."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    agent = registry.make_agent("interrogator", env)
    options = {"motor_lag_s": ScenarioRanges().motor_lag_s[1], "noise_level": 1.0,
               "torque_gain_error": torque_gain_error, "force_gain_error": force_gain_error}
    record = run_episode(env, agent, 12, options, 0)
    env.close()
    assert record.sensor_notes == ""


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_no_smoothed_encoder_is_noted_with_the_paper_settings_noiseless_sensors():
    """The paper's setting reads no sensor noise: its first episode's residual (coloured by the wheel's own
    response; noted as smoothed before the noise floor, session 65) is not an encoder's."""
    suite = make_suite("paper", 1, 0)
    env = gym.make(suite.env_id, **suite.env_kwargs)
    agent = registry.make_agent("interrogator", env)
    seed, options = suite.episodes[0]
    record = run_episode(env, agent, seed, options, 0)
    env.close()
    assert first_windows_noise_colour(agent.features.readings) > SMOOTHED_NOISE_COLOUR  # coloured, ...
    assert record.sensor_notes == ""  # ... and no sensor noise to read it from


class _Noting:
    name, oracle = "noting", False

    def __init__(self, notes):
        self.notes = notes

    def reset(self, observation, info):
        pass

    def act(self, observation, info):
        return np.zeros(5, dtype=np.float32)

    def sensor_notes(self):
        return self.notes


@pytest.mark.parametrize("notes", [("a;b",), ("",), (3,)])
def test_a_bad_sensor_note_names_the_agent(notes):
    env = gym.make(cof_gym.WAGON_ENV_ID, max_windows=1)
    agent = _Noting(notes)
    with pytest.raises(AgentError, match="agent noting reported after its episode in episode 0 .*noting reported the "
                                         "sensor notes"):
        run_episode(env, agent, 0, {}, 0)
    env.close()


def test_evaluate_counts_each_agents_notes_over_its_episodes():
    class Row:
        def __init__(self, agent, notes):
            self.agent, self.sensor_notes = agent, notes

    rows = [Row("a", "smoothed encoder"), Row("a", ""), Row("b", ""), Row("a", "smoothed encoder; other")]
    assert sensor_notes(rows) == [
        "a read its sensors outside those it was fitted on (smoothed encoder) in 2 of 3 episodes: its estimate "
        "there is an extrapolation",
        "a read its sensors outside those it was fitted on (other) in 1 of 3 episodes: its estimate there is an "
        "extrapolation"]


@pytest.mark.skipif(not SHIPPED, reason="no shipped interrogator in this checkout")
def test_evaluate_breaks_the_episodes_down_by_the_agents_sensor_notes_where_any_agent_noted_one(tmp_path):
    """One episode with a lagged encoder beside a sharp one: the interrogator's noted episode and its other in groups
    of their own, the staircase's two in "no sensor note"; without any note the grouping is left out."""
    from cof_gym.commands.evaluate import evaluate
    from cof_gym.commands.suites import Suite

    lagged = Suite("notes", cof_gym.WAGON_ENV_ID, {}, [(11, {"encoder_lag_s": 0.005}), (11, {})])
    result = evaluate(["interrogator", "staircase"], lagged, tmp_path / "lagged", seed=0, quiet=True)
    groups = {agent: entry["breakdown"] for agent, entry in result["summary"].items()}
    assert groups["interrogator"][f"sensor notes: {SMOOTHED_ENCODER}"]["episodes"] == 1
    assert groups["interrogator"]["no sensor note"]["episodes"] == 1
    assert groups["staircase"]["no sensor note"]["episodes"] == 2
    assert f"sensor notes: {SMOOTHED_ENCODER}" not in groups["staircase"]
    assert f"| sensor notes: {SMOOTHED_ENCODER} |" in (tmp_path / "lagged" / "summary.md").read_text()
    sharp = Suite("sharp", cof_gym.WAGON_ENV_ID, {}, [(11, {})])
    result = evaluate(["interrogator"], sharp, tmp_path / "sharp", seed=0, quiet=True)
    assert "no sensor note" not in result["summary"]["interrogator"]["breakdown"]
