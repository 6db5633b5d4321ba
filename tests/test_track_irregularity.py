"""Vertical track irregularity (cof_gym.physics.track): the drawn profile holds the spectrum's variance, the native
callback lays it under every wheelset, a smooth track is the track every draw had before, and asking for a profile
moves no other draw."""

from __future__ import annotations

import math

import gymnasium as gym
import mujoco
import numpy as np
import pytest
from scipy.integrate import quad

import cof_gym
from cof_gym.physics.creep import OperatingConditions
from cof_gym.physics.models import build_wagon
from cof_gym.physics.simulation import Scenario, Simulation
from cof_gym.physics.track import (MAX_TRACK_WAVES, SMOOTH, TRACK_CLASSES, TRACK_SPECTRA, WAVELENGTH_RANGE_M,
                                   TrackProfile, draw_profile)
from cof_gym.physics.vehicle import WagonParameters
from cof_gym.task.scenarios import V2_RANGES, outside_draws
from test_vector_env import assert_batched_plays_as_sync, same  # tests/ is on sys.path (pytest rootdir)

BAND = tuple(2.0 * math.pi / wavelength for wavelength in WAVELENGTH_RANGE_M[::-1])


@pytest.mark.parametrize("name", sorted(TRACK_SPECTRA))
def test_a_drawn_profile_holds_the_spectrums_variance_over_its_band(name: str) -> None:
    """Each cosine's amplitude is the square root of twice the spectrum's integral over its interval, so the profile's
    variance is the integral over the band: the closed form against scipy's quadrature (to its error estimate), and
    the amplitudes' sum of squares against the closed form. The intervals' integrals telescope to the band's, each a
    difference of two antiderivative values about seven times the band's integral, so 32 of them rounded to 1e-16 of
    those values leave at most about 5e-14 of the band's integral: held to 1e-12."""
    spectrum = TRACK_SPECTRA[name]
    numeric, error = quad(spectrum.density, *BAND, limit=200, epsabs=0.0, epsrel=1e-12)
    assert spectrum.integral(*BAND) == pytest.approx(numeric, rel=1e-10, abs=10 * error)
    profile = draw_profile(name, np.random.default_rng(0))
    assert len(profile.amplitudes_m) == MAX_TRACK_WAVES
    assert profile.standard_deviation_m() ** 2 == pytest.approx(spectrum.integral(*BAND), rel=1e-12)
    assert BAND[0] < min(profile.wavenumbers_rad_m) and max(profile.wavenumbers_rad_m) < BAND[1]


def test_the_high_irregularity_track_is_the_rougher_and_a_smooth_one_draws_nothing() -> None:
    low, high = (draw_profile(name, np.random.default_rng(1)) for name in ("ore_low", "ore_high"))
    assert high.standard_deviation_m() / low.standard_deviation_m() == pytest.approx(math.sqrt(1.080e-6 / 4.032e-7))
    assert 1e-3 < low.standard_deviation_m() < high.standard_deviation_m() < 5e-3  # millimetres, as track is
    rng = np.random.default_rng(2)
    state = rng.bit_generator.state
    assert draw_profile(SMOOTH, rng) == TrackProfile() and rng.bit_generator.state == state


@pytest.mark.parametrize("bad, match", [
    ("bumpy", r"track_irregularity must be one of \['smooth', 'ore_low', 'ore_high'\], got 'bumpy'"),
    (None, "track_irregularity must be one of"),
])
def test_an_unknown_track_class_is_refused_by_name(bad, match) -> None:
    with pytest.raises(ValueError, match=match):
        draw_profile(bad, np.random.default_rng(0))


def test_a_profile_with_a_negative_amplitude_or_unequal_lengths_is_refused() -> None:
    with pytest.raises(ValueError, match="finite and >= 0"):
        TrackProfile((-1e-3,), (1.0,), (0.0,))
    with pytest.raises(ValueError, match="as many amplitudes, wavenumbers and phases"):
        TrackProfile((1e-3,), (1.0, 2.0), (0.0,))
    with pytest.raises(ValueError, match=f"at most {MAX_TRACK_WAVES}"):
        TrackProfile(*((1e-6,) * (MAX_TRACK_WAVES + 1),) * 3)


def test_the_wheelsets_ride_on_the_profile() -> None:
    """One long wave (1 mm, 20 m: 0.5 Hz at 10 m/s, far below the wheelset's bounce on the track spring) under the
    wagon: every wheelset's height follows the rail's height at its own position, less the track spring's static
    deflection. What is left is the spring's deflection under the suspension's changing force (a few micrometres:
    primary stiffness x 1 mm over the track's 400 MN/m), far below the wave's 0.7 mm standard deviation."""
    built = build_wagon(WagonParameters())
    sim = Simulation(built)
    wave = TrackProfile((1e-3,), (2.0 * math.pi / 20.0,), (0.3,))
    op = OperatingConditions(cof=0.3, condition="dry", wheel_load_n=built.nominal_wheel_load_n, speed_m_s=10.0)
    sim.reset(Scenario(op=op, track=wave))
    heights, followed = [], []
    for step in range(3000):  # 3 s; the first second lets the wagon settle
        mujoco.mj_step(sim.model, sim.data)
        if step >= 1000:
            for contact in built.contacts:
                rail = wave.height_m(sim.data.xpos[contact.wheel_body][0])
                heights.append(rail)
                followed.append(sim.data.qpos[contact.z_qpos] - contact.z_rest_m - rail)
    assert np.std(heights) > 0.6e-3  # the wheelsets crossed the wave
    assert np.std(followed) < 0.01 * np.std(heights)


def play(env, seed: int, options: dict, steps: int = 3) -> list:
    obs, info = env.reset(seed=seed, options=options)
    out = [obs, info["ground_truth"]]
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(np.array([-0.9, 0.0, 0.0, 0.0, -1.0], np.float32))
        out += [obs, reward, info["measurement"]]
        if terminated or truncated:
            break
    return out


def test_a_smooth_track_is_the_default_and_a_profile_moves_no_other_draw() -> None:
    """``track_irregularity="smooth"`` plays the episode the default plays, bit for bit; a profile changes the
    physics (the wheel loads, the readings) and no drawn field of the episode."""
    env = gym.make(cof_gym.WAGON_ENV_ID)
    default = play(env, 4, {})
    assert default[1]["track_irregularity"] == SMOOTH
    assert same(play(env, 4, {"track_irregularity": SMOOTH}), default)
    rough = play(env, 4, {"track_irregularity": "ore_high"})
    assert rough[1]["track_irregularity"] == "ore_high"
    drawn = ("cof", "condition", "speed_m_s", "load_case", "noise_level", "motor_lag_s", "creep_law", "encoder_lag_s",
             "speed_sensor_error", "wheel_radius_error", "force_gain_error", "torque_gain_error")
    assert same({k: rough[1][k] for k in drawn}, {k: default[1][k] for k in drawn})
    assert rough[4]["phase_lag_deg"] != default[4]["phase_lag_deg"]


def test_the_batched_env_lays_the_same_profile() -> None:
    """The vector env (mujoco.batch) plays a rough track bit for bit as gymnasium's SyncVectorEnv of single envs
    does: every observation, reward, flag and info (the wagon id the vector env's own tests pair, test_vector_env;
    the profile is laid by the same userdata rows for every task version)."""
    assert_batched_plays_as_sync({"track_irregularity": "ore_low"})


def test_a_profile_is_outside_the_v2_draws() -> None:
    assert outside_draws({"track_irregularity": "ore_low"}, V2_RANGES) == {
        "track_irregularity": "'ore_low', drawn: 'smooth'"}
    assert outside_draws({"track_irregularity": SMOOTH}, V2_RANGES) == {}
    assert set(TRACK_CLASSES) == {SMOOTH, *TRACK_SPECTRA}
