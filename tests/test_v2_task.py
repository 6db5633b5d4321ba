"""The v2 task as a user reaches it: creep laws given as a table, a Polach dict or a preset name (through
``reset(options=...)`` and through a suite file of ``cof-gym evaluate``), and systematic sensor errors
that change the readings, never the physics."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym import cli
from cof_gym.task.scenarios import SCENARIO_KEYS, V2_RANGES, ScenarioRanges, draw_scenario, outside_draws
from cof_gym.task.sensors import SYSTEMATIC_ERRORS

TABLE = {"creepage": [0.0, 0.002, 0.005, 0.01, 0.02], "adhesion_ratio": [0.0, 0.5, 0.85, 1.0, 0.9]}
POLACH = {"polach": {"k_adhesion": 0.8, "k_slip": 0.3, "friction_ratio": 0.25, "friction_decay_s_per_m": 1.2}}
SHORT = {"max_windows": 3, "window_s": 0.5}
QUIET = np.array([-1.0, -1.0, -0.6, -0.5, -1.0], dtype=np.float32)  # no DC torque, small modulation


@pytest.fixture(scope="module")
def env():
    e = gym.make(cof_gym.WAGON_ENV_ID, **SHORT)
    yield e
    e.close()


@pytest.mark.parametrize("creep_law,family", [({"table": TABLE}, "table"), (POLACH, "polach"), ("wet", "polach")])
def test_a_given_creep_law_replaces_the_drawn_shape(env, creep_law, family):
    _, info = env.reset(seed=4, options={"creep_law": creep_law, "cof": 0.2, "condition": "dry"})
    gt = info["ground_truth"]
    assert gt["creep_family"] == family and gt["cof"] == 0.2
    if family == "table":  # used as given: the peak is the table's first point of ratio 1
        assert gt["peak_creepage"] == pytest.approx(0.01, rel=1e-9)
        assert gt["creep_law"] == {"table": TABLE}
    env.step(QUIET)


@pytest.mark.parametrize("creep_law,field", [
    ({"table": {**TABLE, "adhesion_ratio": [0.0, 0.5, 0.85, 0.95, 0.9]}}, "creep_law.table"),
    ({"table": {**TABLE, "creepage": [0.0, 0.002, float("nan"), 0.01, 0.02]}}, "creep_law.table.creepage"),
    ({"polach": {"k_adhesion": 1.0}}, "creep_law.polach.k_slip"),
    ({"kalker": {}}, "creep_law family"),
    ("icy", "creep_law preset"),
])
def test_a_bad_creep_law_is_one_value_error_naming_the_field(env, creep_law, field):
    with pytest.raises(ValueError, match=field.replace(".", r"\.")):
        env.reset(seed=0, options={"creep_law": creep_law})
    env.reset(seed=0)  # and the env is usable afterwards
    env.step(QUIET)


@pytest.mark.parametrize("creep_law,field", [
    ({"polach": {"k_adhesion": 1.0, "k_slip": 0.4, "friction_ratio": 0.4, "friction_decay_s_per_m": 1e-9}},
     "creep_law.polach"),
    ({"shen_hedrick_elkins": {"k_stiffness": 1e-20}}, "creep_law.shen_hedrick_elkins"),  # CoA 0 at every creepage
])
def test_a_given_creep_law_without_a_cof_is_one_value_error_naming_the_field(env, creep_law, field):
    """A well-formed law whose curve has no maximum at the episode's speed and load: the reset refuses
    it naming the field (never a CoF the curve does not reach)."""
    with pytest.raises(ValueError, match=field.replace(".", r"\.") + ": the creep curve has no maximum"):
        env.reset(seed=1, options={"creep_law": creep_law, "cof": 0.3})
    env.reset(seed=0)  # and the env is usable afterwards
    env.step(QUIET)


@pytest.mark.parametrize("name", sorted(SYSTEMATIC_ERRORS))
def test_a_systematic_error_out_of_range_names_the_field(env, name):
    bound = SYSTEMATIC_ERRORS[name].accepted
    with pytest.raises(ValueError, match=name):
        env.reset(seed=0, options={name: 1.01 * bound})
    env.reset(seed=0, options={name: bound})  # the bound itself is accepted


def test_systematic_errors_change_readings_not_physics(env):
    """Same seed, errors zero vs fixed: identical truth, readings moved exactly as the sensors' maps say."""
    errors = {"speed_sensor_error": 0.012, "wheel_radius_error": -0.004, "force_gain_error": 0.008,
              "torque_gain_error": -0.03}
    zero = {name: 0.0 for name in errors}
    drive = np.array([-0.7, -0.6, -0.6, -0.5, -1.0], dtype=np.float32)
    infos = []
    for fixed in (zero, errors):
        env.reset(seed=11, options=fixed)
        infos.append(env.step(drive)[4])
    (a, b) = infos
    for key in ("cof", "saturation_torque_nm", "coa_true", "creepage_mean", "normal_load_n"):
        assert a["ground_truth"][key] == b["ground_truth"][key], key  # bit-identical physics
    ma, mb = a["measurement"], b["measurement"]
    gain = (1 + errors["wheel_radius_error"]) / (1 + errors["speed_sensor_error"])
    eps = 8 * np.finfo(float).eps  # a product and a difference of O(1) numbers
    assert mb["creepage_measured"] == pytest.approx((1 + ma["creepage_measured"]) * gain - 1, abs=eps)
    assert mb["speed_measured_m_s"] == pytest.approx(ma["speed_measured_m_s"] * 1.012, rel=eps)
    assert mb["coa_measured"] == pytest.approx(ma["coa_measured"] * 1.008, rel=eps)
    assert mb["torque_mean_nm"] == pytest.approx(ma["torque_mean_nm"] * 0.97, rel=eps)
    assert mb["phase_lag_deg"] == ma["phase_lag_deg"]  # no gain moves a phase
    assert b["ground_truth"]["creepage_offset"] == pytest.approx(gain - 1, rel=1e-12)
    assert not set(errors) & set(mb), "systematic errors are ground truth, never sensor readings"
    assert all(b["ground_truth"][k] == v for k, v in errors.items())


def test_v2_draws_families_and_errors_v1_draws_neither():
    v2 = gym.make(cof_gym.WAGON_ENV_ID, **SHORT)
    v1 = gym.make(cof_gym.WAGON_V1_ENV_ID, **SHORT)
    families, offsets = set(), []
    for seed in range(12):
        gt = v2.reset(seed=seed)[1]["ground_truth"]
        families.add(gt["creep_family"])
        offsets.append(gt["creepage_offset"])
        gt1 = v1.reset(seed=seed)[1]["ground_truth"]
        assert gt1["creep_family"] == "polach" and gt1["creepage_offset"] == 0.0
        assert all(gt1[name] == 0.0 for name in SYSTEMATIC_ERRORS)
    assert families == {"polach", "shen_hedrick_elkins"}
    assert max(map(abs, offsets)) > 0.005 and all(math.isfinite(o) for o in offsets)


@pytest.mark.parametrize("seed", range(12))
def test_every_v2_draw_lies_inside_the_v2_draws(seed):
    """outside_draws names nothing for a scenario the v2 draws produced (every field fixed to it)."""
    drawn = draw_scenario(np.random.default_rng(seed), V2_RANGES, {}).to_dict()
    assert outside_draws({k: drawn[k] for k in SCENARIO_KEYS}, V2_RANGES) == {}


@pytest.mark.parametrize("options, field", [
    ({"creep_law": {"table": {"creepage": [0.0, 0.01, 0.02], "adhesion_ratio": [0.0, 1.0, 0.8]}}}, "creep_law"),
    ({"force_gain_error": 0.03}, "force_gain_error"),
    ({"condition": "dry", "cof": 0.1}, "cof"),
    ({"condition": "dry_kalker"}, "condition"),
    ({"creep_law": {"polach": {"k_adhesion": 5.0, "k_slip": 0.5, "friction_ratio": 0.4,
                               "friction_decay_s_per_m": 0.5}}}, "creep_law"),
])
def test_options_beyond_the_draws_are_named_by_field(options, field):
    assert list(outside_draws(options, V2_RANGES)) == [field]
    assert field in outside_draws(options, ScenarioRanges())  # v1 draws no creep law, no sensor error


def test_the_three_forms_run_through_a_suite_file(tmp_path: Path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    suite = {"options": {"cof": 0.15, "condition": "wet", "speed_m_s": 12.0},
             "episodes": [{"seed": 1, "options": {"creep_law": {"table": TABLE}}},
                          {"seed": 2, "options": {"creep_law": POLACH}},
                          {"seed": 3, "options": {"creep_law": "low_adhesion", "speed_sensor_error": -0.02,
                                                       "wheel_radius_error": 0.0}}]}
    (tmp_path / "forms.json").write_text(json.dumps(suite))
    assert cli.main(["evaluate", "--agents", "oracle", "--suite", "forms.json", "--out", "ev", "--quiet"]) == 0
    with open(tmp_path / "ev" / "episodes.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["creep_family"] for r in rows] == ["table", "polach", "polach"]
    assert float(rows[2]["creepage_offset"]) == pytest.approx(1 / 0.98 - 1, rel=1e-12)
    assert all(r["macro_slip"] == "False" for r in rows)
