"""Known-frequency sine fit (IEEE 1057 + drift) and the native lock-in that accumulates its sums."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from cof_gym.measurement.sine_fit import fit_from_sums, fit_samples, sums, wrap_deg
from cof_gym.physics.creep import OperatingConditions
from cof_gym.physics.models import build_half_wheelset
from cof_gym.physics.native import layout
from cof_gym.physics.simulation import DriveCommand, Scenario, Simulation, begin_window, read_window

FS = 1000.0
F_MOD = 5.0
N = 2000  # 10 periods at 1 kHz
AMP, PHASE, OFFSET, DRIFT = 1.3, 0.7, -0.4, 0.25


def _synthetic(rng: np.random.Generator, sigma: float, n: int = N, amp: float = AMP, phase: float = PHASE):
    t = np.arange(n) / FS
    theta = 2 * math.pi * F_MOD * t + 0.3  # arbitrary phase origin of the modulation
    y = amp * np.sin(theta + phase) + OFFSET + DRIFT * t + sigma * rng.standard_normal(n)
    return theta, t, y


def test_noise_free_fit_is_exact() -> None:
    theta, t, y = _synthetic(np.random.default_rng(0), 0.0)
    f = fit_samples(theta, t, y)
    assert f.amplitude == pytest.approx(AMP, rel=1e-10)
    assert f.phase_rad == pytest.approx(PHASE, abs=1e-10)
    assert f.offset == pytest.approx(OFFSET, rel=1e-9)
    assert f.drift_per_s == pytest.approx(DRIFT, rel=1e-9)
    # the residual comes from the normal-equation sums, rss = y'y - coef'B'y: a difference of two numbers
    # of size y'y, so its floor is a few ulps of y'y whatever the BLAS kernel rounds (0 on some CPUs,
    # 2.4e-8 rms on others); 16 ulps bound the rounding of the 4-term dot product and the subtraction
    _, _, yty, n = sums(theta, t, y)
    floor = math.sqrt(16 * np.finfo(float).eps * yty / n)
    assert f.residual_rms <= floor
    assert floor < 1e-6 * AMP  # and that floor is far below any signal the fit is used for


def test_non_integer_periods_with_drift() -> None:
    """The drift column keeps a ramp from leaking into the phase even over 7.3 periods."""
    theta, t, y = _synthetic(np.random.default_rng(0), 0.0, n=1460)
    f = fit_samples(theta, t, y)
    assert f.phase_rad == pytest.approx(PHASE, abs=1e-9)
    assert f.amplitude == pytest.approx(AMP, rel=1e-9)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_noisy_fit_recovers_parameters_within_standard_errors(seed: int) -> None:
    sigma = 0.5
    theta, t, y = _synthetic(np.random.default_rng(seed), sigma)
    f = fit_samples(theta, t, y)
    duration = N / FS
    se_amp = sigma * math.sqrt(2.0 / N)
    se_offset = sigma * 2.0 / math.sqrt(N)  # intercept of a regression over tau in [0, T]
    se_drift = sigma * math.sqrt(12.0 / N) / duration
    se_phase_theory = sigma / AMP * math.sqrt(2.0 / N)  # Cramer-Rao
    assert f.phase_se_rad == pytest.approx(se_phase_theory, rel=0.1)
    assert abs(f.amplitude - AMP) < 4 * se_amp
    assert abs(f.phase_rad - PHASE) < 4 * f.phase_se_rad
    assert abs(f.offset - OFFSET) < 4 * se_offset
    assert abs(f.drift_per_s - DRIFT) < 4 * se_drift
    assert f.residual_rms == pytest.approx(sigma, rel=0.1)


@pytest.mark.parametrize(("sigma", "amp"), [(0.5, 1.3), (2.0, 1.0)])
def test_reported_phase_se_matches_empirical_spread(sigma: float, amp: float) -> None:
    phases, ses = [], []
    for seed in range(200):
        theta, t, y = _synthetic(np.random.default_rng(1000 + seed), sigma, amp=amp)
        f = fit_samples(theta, t, y)
        phases.append(f.phase_rad)
        ses.append(f.phase_se_rad)
    empirical = float(np.std(phases, ddof=1))
    reported = float(np.mean(ses))
    assert reported == pytest.approx(empirical, rel=0.2)
    assert float(np.mean(phases)) == pytest.approx(PHASE, abs=4 * empirical / math.sqrt(200))


def test_fit_rejects_too_few_samples() -> None:
    theta, t, y = _synthetic(np.random.default_rng(0), 0.1, n=4)
    with pytest.raises(ValueError, match="samples"):
        fit_samples(theta, t, y)


@pytest.mark.parametrize(("angle", "wrapped"), [(0.0, 0.0), (190.0, -170.0), (-180.0, 180.0), (540.0, 180.0),
                                                (-190.0, 170.0), (359.5, -0.5)])
def test_wrap_deg(angle: float, wrapped: float) -> None:
    assert wrap_deg(angle) == pytest.approx(wrapped, abs=1e-12)


# ------------------------------------------------------------------ native lock-in vs sample arrays


def _sums_close(native: np.ndarray, reference: np.ndarray, rtol: float = 1e-9) -> None:
    native, reference = np.atleast_1d(native), np.atleast_1d(reference)
    scale = np.abs(reference).max()
    np.testing.assert_allclose(native, reference, rtol=rtol, atol=rtol * scale)


def test_native_lock_in_sums_equal_sample_fit() -> None:
    I = layout.OFFSETS
    built = build_half_wheelset(timestep=1e-3)
    op = OperatingConditions(cof=0.3, wheel_load_n=built.nominal_wheel_load_n, speed_m_s=10.0)
    drive = DriveCommand(0.85 * built.saturation_torque_per_cof * 0.3, 345.0, 5.0)
    duration, settle, ramp = 1.5, 0.5, 0.3

    sim = Simulation(built)
    sim.reset(Scenario(op))
    ud = sim.data.userdata
    begin_window(ud, sim.data.time, drive, ramp, settle)
    dt = sim.timestep
    t0 = ud[I["ACC_START_TIME"]]
    theta_at = lambda t: ud[I["THETA_BASE"]] + ud[I["MOD_OMEGA"]] * (t - ud[I["TIME_BASE"]])  # noqa: E731
    rec = {k: [] for k in ("t", "torque", "omega", "creep")}
    for _ in range(int(round(duration / dt))):
        t = sim.data.time
        mujoco.mj_step(sim.model, sim.data, 1)
        if t >= t0:  # the sample the native step accumulated at time t
            rec["t"].append(t)
            rec["torque"].append(ud[I["LAST_TORQUE"]])
            rec["omega"].append(ud[I["LAST_OMEGA"]])
            rec["creep"].append(ud[I["LAST_CREEPAGE"]])
    t = np.array(rec["t"])
    t_mid = t + 0.5 * dt
    n = t.size
    assert n == ud[I["N_SAMPLES"]] == int(round((duration - settle) / dt))

    checks = [
        ("TORQUE", "BTB_TORQUE", "BTY_TORQUE", "YTY_TORQUE", theta_at(t_mid), t_mid - t0, rec["torque"]),
        ("OMEGA", "BTB_STATE", "BTY_OMEGA", "YTY_OMEGA", theta_at(t), t - t0, rec["omega"]),
        ("CREEP", "BTB_STATE", "BTY_CREEP", "YTY_CREEP", theta_at(t), t - t0, rec["creep"]),
    ]
    fits = {}
    for name, btb_key, bty_key, yty_key, theta, tau, y in checks:
        btb, bty, yty, count = sums(theta, tau, np.array(y))
        native_btb = ud[I[f"{btb_key}_0"]: I[f"{btb_key}_0"] + 10]
        native_bty = ud[I[f"{bty_key}_0"]: I[f"{bty_key}_0"] + 4]
        _sums_close(native_btb, btb)
        _sums_close(native_bty, bty)
        _sums_close(ud[I[yty_key]], yty)
        native_fit = fit_from_sums(native_btb, native_bty, ud[I[yty_key]], ud[I["N_SAMPLES"]])
        sample_fit = fit_samples(theta, tau, np.array(y))
        assert native_fit.amplitude == pytest.approx(sample_fit.amplitude, rel=1e-9), name
        assert native_fit.phase_rad == pytest.approx(sample_fit.phase_rad, abs=1e-9), name
        assert native_fit.offset == pytest.approx(sample_fit.offset, rel=1e-9, abs=1e-12), name
        fits[name] = sample_fit

    m = read_window(ud)
    lag = wrap_deg(math.degrees(fits["TORQUE"].phase_rad - fits["OMEGA"].phase_rad))
    assert m.phase_lag_deg == pytest.approx(lag, abs=1e-7)
    assert m.torque_amplitude_nm == pytest.approx(345.0, rel=1e-3)
    assert 5.0 < m.phase_lag_deg < 60.0
    assert m.coa_true == pytest.approx(0.85 * 0.3, rel=1e-3)

    # stepping one step at a time is the same as one window call
    other = Simulation(built)
    other.reset(Scenario(op))
    assert other.run_window(drive, duration, settle, ramp) == m
