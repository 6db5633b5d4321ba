"""Acceptance: the simulated half wheelset reproduces the paper's Eq. 3 over its torque schedule.

tan(phi) = Iw wm v / (N R^2 dCoA/ds), with dCoA/ds the creep-curve slope where CoA = Mc / (R N).
Checked where the modulation is small against the distance to saturation, M0 <= 0.25 (M_sat - Mc).
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


# Eq. 3 is a small-signal (linearised) result. At CoF 0.1, M0 = 345 N m is 7.5 % of M_sat, and on the
# strongly curved creep curve above ~55 % the phase exceeds Eq. 3 by more than the tolerance even though
# M0 <= 0.25 (M_sat - Mc). The simulation is right there (see the two tests at the end: an independent
# stiff ODE solution agrees, and the error vanishes ~M0^2 as M0 shrinks): the acceptance rule's
# small-signal condition is not strict enough for low CoF. Not a library bug.
SMALL_SIGNAL_LIMIT = pytest.mark.xfail(
    reason="Eq. 3 small-signal limit, not a library bug: CoF 0.1, M0=345 Nm; sim matches an independent "
    "Radau solution and converges to Eq. 3 as M0 -> 0",
    strict=True,
)
KNOWN_LARGE_SIGNAL = {(0.1, 0.56), (0.1, 0.61), (0.1, 0.66)}


def _cases():
    for cof in COFS:
        m_sat = R * N * cof
        for frac in paper_schedule():
            mc = frac * m_sat
            if M0 <= 0.25 * (m_sat - mc):
                marks = [SMALL_SIGNAL_LIMIT] if (cof, frac) in KNOWN_LARGE_SIGNAL else []
                yield pytest.param(cof, frac, marks=marks, id=f"cof{cof}-{round(frac * 100)}pct")


CASES = list(_cases())


def test_acceptance_grid_covers_the_schedule() -> None:
    fracs = {c.values[1] for c in CASES if c.values[0] == 0.5}
    assert 0.01 in fracs and 0.94 in fracs and 0.95 not in fracs
    assert len(CASES) > 60


@pytest.fixture(scope="module")
def sim() -> Simulation:
    return Simulation(build_half_wheelset(timestep=1e-3))


def _simulate(sim: Simulation, cof: float, frac: float, amplitude: float = M0):
    sim.reset(Scenario(_op(cof)))
    mc = frac * R * N * cof
    return sim.run_window(DriveCommand(mc, amplitude, FREQ), duration_s=DURATION, settle_s=SETTLE, ramp_s=RAMP)


@pytest.mark.parametrize(("cof", "frac"), CASES)
def test_phase_matches_eq3(sim: Simulation, cof: float, frac: float) -> None:
    op = _op(cof)
    mc = frac * R * N * cof
    m = _simulate(sim, cof, frac)
    phi_eq3 = eq3_phase_deg(mc, op)
    tol = max(0.2, 0.05 * phi_eq3)
    assert abs(m.phase_lag_deg - phi_eq3) <= tol, (
        f"phi_sim={m.phase_lag_deg:.4f} deg, phi_Eq3={phi_eq3:.4f} deg, tol={tol:.3f}")
    # the measured mean adhesion is the DC balance Mc / (R N)
    assert m.coa_true == pytest.approx(mc / (R * N), rel=1e-3, abs=1e-6)


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


@pytest.mark.parametrize("frac", [0.56, 0.61, 0.66])
def test_large_signal_deviation_vanishes_with_amplitude(sim: Simulation, frac: float) -> None:
    """At CoF 0.1 the excess phase over Eq. 3 shrinks roughly with M0^2 and is within tolerance at
    M0 = 43 N m."""
    cof = 0.1
    phi_eq3 = eq3_phase_deg(frac * R * N * cof, _op(cof))
    errors = [_simulate(sim, cof, frac, amp).phase_lag_deg - phi_eq3 for amp in (345.0, 172.5, 43.125)]
    assert errors[0] > errors[1] > errors[2] > 0.0
    assert errors[1] / errors[0] == pytest.approx(0.25, abs=0.08)  # halving M0 quarters the error
    assert abs(errors[2]) <= max(0.2, 0.05 * phi_eq3) * 0.25
