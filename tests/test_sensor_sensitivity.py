"""``experiments/sensor_sensitivity.py``: the rows it plays and how a row's error reaches every episode."""

from __future__ import annotations

import sys

from conftest import EXPERIMENTS

from cof_gym.task.scenarios import ENCODER_LAG_MAX_S
from cof_gym.task.sensors import SYSTEMATIC_ERRORS

sys.path.insert(0, EXPERIMENTS)
import sensor_sensitivity  # noqa: E402


def test_the_rows_are_the_draws_then_each_error_at_both_ends_of_what_the_env_accepts_then_the_encoders():
    rows = sensor_sensitivity.settings()
    lags, pulses = sensor_sensitivity.ENCODER_LAGS_S, sensor_sensitivity.PULSE_ENCODERS
    assert rows[0] == {} and len(rows) == 1 + 2 * len(SYSTEMATIC_ERRORS) + len(lags) + len(pulses)
    for name, span in SYSTEMATIC_ERRORS.items():
        assert {name: span.accepted} in rows and {name: -span.accepted} in rows
    encoders = rows[-len(lags) - len(pulses):]
    assert encoders[:len(lags)] == [{"encoder_lag_s": lag} for lag in lags] and max(lags) == ENCODER_LAG_MAX_S
    assert encoders[len(lags):] == list(pulses) and pulses[-1]["lock_in"] == "rotation"
    assert sensor_sensitivity.label(rows[0]) == "as drawn"
    assert sensor_sensitivity.label({"force_gain_error": -0.1}) == "force_gain_error -0.1"
    assert sensor_sensitivity.label({"encoder_lag_s": 0.01}) == "encoder_lag_s 0.01 s"
    assert sensor_sensitivity.label(pulses[-1]) == ("encoder_pulses_per_rev 100, encoder_runout 0.0005, "
                                                    "lock_in rotation")
    assert sensor_sensitivity.cell([(0.01, False), (0.03, True), (0.02, False)]) == "2.0 / 2.8 / 1"


def test_a_rows_error_replaces_each_episodes_own_and_leaves_its_other_options(monkeypatch):
    played = []

    def record(env, agent, seed, options, episode):
        played.append(options)
        return type("Record", (), {"scored": True, "relative_error": 0.0, "macro_slip": False})()

    monkeypatch.setattr(sensor_sensitivity, "run_episode", record)
    sensor_sensitivity.play("oracle", {"force_gain_error": 0.1}, {})
    suite = sensor_sensitivity.make_suite(str(sensor_sensitivity.VALIDATION), 60, 0)
    assert played == [{**own, "force_gain_error": 0.1} for _, own in suite.episodes]
    # a row's env argument (the lock-in) makes the env, never a reset option
    played.clear()
    made = []
    real_make = sensor_sensitivity.gym.make
    monkeypatch.setattr(sensor_sensitivity.gym, "make", lambda *a, **kw: made.append(kw) or real_make(*a, **kw))
    sensor_sensitivity.play("oracle", {"encoder_pulses_per_rev": 100, "lock_in": "rotation"}, {})
    assert made[0]["lock_in"] == "rotation"
    assert played == [{**own, "encoder_pulses_per_rev": 100} for _, own in suite.episodes]
