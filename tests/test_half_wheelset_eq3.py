"""Acceptance: the simulated half wheelset reproduces the paper's Eq. 3 over its torque schedule.

tan(phi) = Iw wm v / (N R^2 dCoA/ds), with dCoA/ds the creep-curve slope where CoA = Mc / (R N).
Eq. 3 is small-signal: every schedule point of CoF 0.2-0.5 agrees at the paper's 345 N m; at CoF 0.1
(345 N m = 7.5 % of the saturation torque) the points above ~55 % deviate, and the deviation is pinned
and shown to vanish as M0 shrinks (and to be the right solution of the nonlinear spin equation).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from cof_gym.analysis.theory import paper_schedule
from cof_gym.measurement.sine_fit import fit_samples
from cof_gym.physics.creep import OperatingConditions, creep_curve, creepage_at_coa
from cof_gym.physics.models import build_half_wheelset
from cof_gym.physics.simulation import DriveCommand, Scenario, Simulation
from cof_gym.physics.vehicle import HalfWheelsetParameters

P = HalfWheelsetParameters()
IW, R, N = P.spin_inertia_kg_m2, P.wheel_radius_m, P.normal_load_n
SPEED = 10.0
FREQ = 5.0
WM = 2 * math.pi * FREQ
M0 = 345.0
COFS = (0.1, 0.2, 0.3, 0.4, 0.5)
DURATION, SETTLE, RAMP = 2.0, 1.0, 0.5


def test_schedule_helper() -> None:
    s = list(paper_schedule())
    assert s[0] == 0.01 and s[-1] == 0.99
    steps = np.round(np.diff(s) * 100).astype(int)
    assert set(steps) == {10, 5, 3, 1}
    assert all(np.diff(steps) <= 0)  # steps only get finer towards saturation


def eq3_phase_deg(dc_torque: float, op: OperatingConditions, m_iw: float = IW) -> float:
    s = creepage_at_coa(dc_torque / (R * N), op)
    slope = creep_curve(s, op)[1][0]
    return math.degrees(math.atan(m_iw * WM * op.speed_m_s / (N * R**2 * slope)))


def _op(cof: float) -> OperatingConditions:
    return OperatingConditions(cof=cof, condition="dry", wheel_load_n=N, speed_m_s=SPEED)


SMALL_SIGNAL_COFS = (0.2, 0.3, 0.4, 0.5)  # M0 = 345 N m is at most 3.75 % of their saturation torque
LARGE_SIGNAL_COF = 0.1  # M0 = 345 N m is 7.5 % of the saturation torque


def _tolerance(phi_eq3: float) -> float:
    return max(0.2, 0.05 * phi_eq3)


def test_schedule_reads_the_paper_literally() -> None:
    """Steps accumulate from 1 %: 89 % is below 90 %, so the next step is +3 to 92 %; 90 and 91 % are
    not steps (cof_gym.analysis.theory documents the reading)."""
    percents = [round(100 * f) for f in paper_schedule()]
    assert percents[:7] == [1, 11, 21, 31, 41, 51, 56]
    assert 89 in percents and 92 in percents and 90 not in percents and 91 not in percents
    assert percents[percents.index(92):] == list(range(92, 100))


@pytest.fixture(scope="module")
def sim() -> Simulation:
    return Simulation(build_half_wheelset(timestep=1e-3))


def _simulate(sim: Simulation, cof: float, frac: float, amplitude: float = M0):
    sim.reset(Scenario(_op(cof)))
    mc = frac * R * N * cof
    return sim.run_window(DriveCommand(mc, amplitude, FREQ), duration_s=DURATION, settle_s=SETTLE, ramp_s=RAMP)


SMALL = [pytest.param(c, f, id=f"cof{c}-{round(100 * f)}pct") for c in SMALL_SIGNAL_COFS for f in paper_schedule()]


@pytest.mark.parametrize(("cof", "frac"), SMALL)
def test_phase_matches_eq3_at_every_schedule_point(sim: Simulation, cof: float, frac: float) -> None:
    """CoF 0.2-0.5 at the paper's 345 N m: every schedule point up to 99 % within max(0.2 deg, 5 %)."""
    op = _op(cof)
    mc = frac * R * N * cof
    m = _simulate(sim, cof, frac)
    phi_eq3 = eq3_phase_deg(mc, op)
    tol = _tolerance(phi_eq3)
    assert abs(m.phase_lag_deg - phi_eq3) <= tol, (
        f"phi_sim={m.phase_lag_deg:.4f} deg, phi_Eq3={phi_eq3:.4f} deg, tol={tol:.3f}")
    # the measured mean adhesion is the DC balance Mc / (R N)
    assert m.coa_true == pytest.approx(mc / (R * N), rel=1e-3, abs=1e-6)


@pytest.fixture(scope="module")
def low_cof_deviation(sim: Simulation) -> dict[float, tuple[float, float, float]]:
    """CoF 0.1, every schedule point: (phi_sim - phi_Eq3 at 345 N m, the same at 345/4 N m, tolerance)."""
    out = {}
    for frac in paper_schedule():
        phi_eq3 = eq3_phase_deg(frac * R * N * LARGE_SIGNAL_COF, _op(LARGE_SIGNAL_COF))
        out[float(frac)] = (_simulate(sim, LARGE_SIGNAL_COF, frac).phase_lag_deg - phi_eq3,
                            _simulate(sim, LARGE_SIGNAL_COF, frac, M0 / 4).phase_lag_deg - phi_eq3,
                            _tolerance(phi_eq3))
    return out


def test_low_cof_converges_to_eq3_as_the_modulation_shrinks(low_cof_deviation: dict) -> None:
    """CoF 0.1: at M0 / 4 (86 N m, 1.9 % of the saturation torque, like CoF 0.4 at 345 N m) every
    schedule point is within the tolerance."""
    outside = {f: d for f, (_, d, tol) in low_cof_deviation.items() if abs(d) > tol}
    assert not outside


def test_low_cof_large_signal_deviations(low_cof_deviation: dict) -> None:
    """CoF 0.1 at 345 N m: the points above ~55 % lag Eq. 3 by up to ~3 tolerances (16 of 24 points
    outside). The excess is positive (the modulation sweeps the curved creep curve, whose mean slope
    over the swing is below the slope at the DC point) and the low-torque points are unaffected."""
    outside = sorted(f for f, (d, _, tol) in low_cof_deviation.items() if abs(d) > tol)
    assert 14 <= len(outside) <= 18
    assert min(outside) >= 0.5
    assert all(low_cof_deviation[f][0] > 0 for f in outside)
    worst = max(low_cof_deviation[f][0] / low_cof_deviation[f][2] for f in outside)
    assert 2.0 <= worst <= 3.5
    assert all(abs(d) <= tol for f, (d, _, tol) in low_cof_deviation.items() if f <= 0.51)


def _reference_phase_deg(cof: float, frac: float, amplitude: float) -> float:
    """Independent scalar model: Iw dOmega/dt = M(t) - R N CoA((R Omega - v)/v), solved with Radau
    (implicit, tight tolerances), fitted over the same window with the same sine fit."""
    op = _op(cof)
    mc = frac * R * N * cof

    def torque(t: float) -> float:
        return mc * min(t / RAMP, 1.0) + amplitude * math.sin(WM * t)

    def rhs(t, y):
        coa, _ = creep_curve((R * y[0] - SPEED) / SPEED, op)
        return [(torque(t) - R * N * coa[0]) / IW]

    def jac(t, y):
        _, slope = creep_curve((R * y[0] - SPEED) / SPEED, op)
        return [[-N * R * R * slope[0] / (SPEED * IW)]]

    t_eval = np.arange(int(round(DURATION * 1000)) + 1) * 1e-3
    sol = solve_ivp(rhs, (0.0, DURATION), [SPEED / R], method="Radau", jac=jac, t_eval=t_eval,
                    rtol=1e-10, atol=1e-12, max_step=1e-3)
    assert sol.success
    keep = t_eval >= SETTLE
    t = t_eval[keep]
    f_omega = fit_samples(WM * t, t - SETTLE, sol.y[0][keep])
    f_torque = fit_samples(WM * t, t - SETTLE, np.array([torque(x) for x in t]))
    return math.degrees(f_torque.phase_rad - f_omega.phase_rad)


@pytest.mark.parametrize(("cof", "frac"), [(0.1, 0.66), (0.4, 0.92)])
def test_phase_matches_independent_stiff_solution(sim: Simulation, cof: float, frac: float) -> None:
    """Where Eq. 3 and the simulation disagree (CoF 0.1, 66 %) the simulation is still the right
    solution of the nonlinear spin equation; (0.4, 92 %) checks the reference itself against Eq. 3's
    regime."""
    m = _simulate(sim, cof, frac)
    ref = _reference_phase_deg(cof, frac, M0)
    assert m.phase_lag_deg == pytest.approx(ref, abs=0.05)


@pytest.mark.parametrize("frac", [0.56, 0.66, 0.92, 0.98])
def test_large_signal_deviation_vanishes_with_amplitude(sim: Simulation, frac: float) -> None:
    """At CoF 0.1 the excess phase over Eq. 3 shrinks roughly with M0^2 and is within tolerance at
    M0 = 43 N m."""
    cof = 0.1
    phi_eq3 = eq3_phase_deg(frac * R * N * cof, _op(cof))
    errors = [_simulate(sim, cof, frac, amp).phase_lag_deg - phi_eq3 for amp in (345.0, 172.5, 43.125)]
    assert errors[0] > errors[1] > errors[2] > 0.0
    assert errors[1] / errors[0] == pytest.approx(0.25, abs=0.08)  # halving M0 quarters the error
    assert abs(errors[2]) <= max(0.2, 0.05 * phi_eq3) * 0.25
