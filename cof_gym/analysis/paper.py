"""``cof-gym reproduce-paper``: the paper's Figs. 5, 4/7 and 8 re-simulated, with every plotted number
written to ``results.json``."""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from cof_gym.analysis.theory import creep_slope_at_torque, paper_schedule, phase_eq3_deg, phase_eq4_deg
from cof_gym.physics.creep import OperatingConditions
from cof_gym.physics.models import BuiltModel, build_half_wheelset, build_wagon
from cof_gym.physics.simulation import DriveCommand, Scenario, Simulation, WindowMeasurement
from cof_gym.physics.vehicle import HalfWheelsetParameters, wagon_parameters

PAPER_AMPLITUDE_NM = 345.0
PAPER_FREQUENCY_HZ = 5.0
PAPER_SPEED_M_S = 10.0
PAPER_COFS = (0.1, 0.2, 0.3, 0.4, 0.5)


@dataclass(frozen=True)
class Timing:
    """Window timing of one staircase step, s."""

    ramp: float
    settle: float
    measure: float


FULL = Timing(ramp=0.5, settle=2.0, measure=2.0)
QUICK = Timing(ramp=0.3, settle=1.2, measure=1.0)


def _drive(fraction: float, m_sat: float) -> DriveCommand:
    return DriveCommand(fraction * m_sat, PAPER_AMPLITUDE_NM, PAPER_FREQUENCY_HZ)


def half_wheelset_sweep(timing: Timing) -> dict:
    """Fig. 5 analogue: simulated half-wheelset phase vs Eq. 3 over the schedule, CoF 0.1...0.5."""
    params = HalfWheelsetParameters()
    built = build_half_wheelset(params)
    sim = Simulation(built)
    r, n = params.wheel_radius_m, params.normal_load_n
    wm = 2 * math.pi * PAPER_FREQUENCY_HZ
    out: dict = {"parameters": {**asdict(params), "speed_m_s": PAPER_SPEED_M_S, "amplitude_nm": PAPER_AMPLITUDE_NM,
                                "frequency_hz": PAPER_FREQUENCY_HZ}, "cofs": {}}
    worst = 0.0
    for cof in PAPER_COFS:
        op = OperatingConditions(cof=cof, wheel_load_n=n, speed_m_s=PAPER_SPEED_M_S)
        m_sat = built.saturation_torque_per_cof * cof
        rows = []
        for frac in paper_schedule():
            sim.reset(Scenario(op))
            m = sim.run_window(_drive(frac, m_sat), timing.settle + timing.measure, timing.settle, timing.ramp)
            eq3 = phase_eq3_deg(params.spin_inertia_kg_m2, wm, PAPER_SPEED_M_S, n, r,
                                creep_slope_at_torque(frac * m_sat, r, n, op))
            small_signal = bool(PAPER_AMPLITUDE_NM <= 0.25 * (m_sat - frac * m_sat))
            error = abs(m.phase_lag_deg - eq3)
            ok = bool(error <= max(0.2, 0.05 * abs(eq3)))
            if small_signal:
                worst = max(worst, error / max(0.2, 0.05 * abs(eq3)))
            rows.append({"fraction": float(frac), "phase_sim_deg": m.phase_lag_deg, "phase_se_deg": m.phase_lag_se_deg,
                         "phase_eq3_deg": eq3, "small_signal": small_signal, "within_tolerance": ok})
        out["cofs"][str(cof)] = rows
    per_cof = {}
    for cof, rows in out["cofs"].items():
        fails = [r["fraction"] for r in rows if r["small_signal"] and not r["within_tolerance"]]
        per_cof[cof] = {"passed": not fails, "failing_fractions": fails}
    out["acceptance"] = {
        "rule": "|phi_sim - phi_Eq3| <= max(0.2 deg, 5 % of phi_Eq3) where M0 <= 0.25 (M_sat - M_c)",
        "worst_error_over_tolerance": worst,
        "passed": bool(worst <= 1.0),
        "per_cof": per_cof,
    }
    out["amplitude_check"] = amplitude_check(sim, built, timing)
    return out


def amplitude_check(sim: Simulation, built: BuiltModel, timing: Timing, cof: float = 0.1,
                    fractions: tuple[float, ...] = (0.56, 0.61, 0.66),
                    amplitudes: tuple[float, ...] = (345.0, 200.0, 100.0, 50.0, 20.0)) -> list[dict]:
    """Eq. 3 is small-signal: at CoF 0.1 the paper's 345 N m is 7.5 % of the saturation torque and the
    modulation sweeps a curved part of the creep curve. Shrinking M0 shows the simulation converging
    to Eq. 3 (the deviation is the physics of a large modulation, not a numerical error)."""
    op = OperatingConditions(cof=cof, wheel_load_n=built.nominal_wheel_load_n, speed_m_s=PAPER_SPEED_M_S)
    m_sat = built.saturation_torque_per_cof * cof
    r, n = built.wheel_radius_m, built.nominal_wheel_load_n
    rows = []
    for frac in fractions:
        eq3 = phase_eq3_deg(built.drive_spin_inertia_kg_m2, 2 * math.pi * PAPER_FREQUENCY_HZ, PAPER_SPEED_M_S, n, r,
                            creep_slope_at_torque(frac * m_sat, r, n, op))
        for amp in amplitudes:
            sim.reset(Scenario(op))
            m = sim.run_window(DriveCommand(frac * m_sat, amp, PAPER_FREQUENCY_HZ), timing.settle + timing.measure,
                               timing.settle, timing.ramp)
            rows.append({"cof": cof, "fraction": frac, "amplitude_nm": amp, "phase_sim_deg": m.phase_lag_deg,
                         "phase_eq3_deg": eq3, "relative_deviation": m.phase_lag_deg / eq3 - 1.0})
    return rows


def wagon_staircase(built: BuiltModel, cof: float, timing: Timing, fractions: np.ndarray) -> list[dict]:
    """The paper's procedure on the wagon: one continuous run, DC torque stepped up the schedule."""
    op = OperatingConditions(cof=cof, wheel_load_n=built.nominal_wheel_load_n, speed_m_s=PAPER_SPEED_M_S)
    sim = Simulation(built)
    sim.reset(Scenario(op))
    m_sat = built.saturation_torque_per_cof * cof
    sim.run_window(_drive(0.0, m_sat), timing.settle + timing.measure, timing.settle)  # settle the cruise control
    n_contact = built.nominal_wheel_load_n * built.wheels_per_contact
    wm = 2 * math.pi * PAPER_FREQUENCY_HZ
    rows = []
    for frac in fractions:
        m: WindowMeasurement = sim.run_window(_drive(frac, m_sat), timing.settle + timing.measure, timing.settle,
                                              timing.ramp)
        eq3 = phase_eq3_deg(built.drive_spin_inertia_kg_m2, wm, PAPER_SPEED_M_S, n_contact, built.wheel_radius_m,
                            creep_slope_at_torque(frac * m_sat, built.wheel_radius_m, n_contact, op))
        rows.append({
            "fraction": float(frac), "phase_sim_deg": m.phase_lag_deg, "phase_se_deg": m.phase_lag_se_deg,
            "phi_v_deg": m.creep_phase_lag_deg, "phase_eq3_deg": eq3, "phase_eq4_deg": phase_eq4_deg(eq3, m.creep_phase_lag_deg),
            "coa_measured": m.coa_measured, "normal_load_n": m.normal_load_n, "speed_m_s": m.speed_measured_m_s,
            "wd_rms_m_s2": m.wd_rms_m_s2, "max_abs_creepage": m.max_abs_creepage,
        })
    return rows


def zero_crossing(rows: list[dict], cof: float) -> dict:
    """The paper's rule: first step whose phase is positive; its measured CoA taken as the CoF."""
    for prev, row in zip([None] + rows[:-1], rows):
        if row["phase_sim_deg"] > 0.0:
            interp = row["fraction"]
            if prev is not None:
                p0, p1 = prev["phase_sim_deg"], row["phase_sim_deg"]
                interp = prev["fraction"] + (row["fraction"] - prev["fraction"]) * (-p0) / (p1 - p0)
            return {"fraction": row["fraction"], "fraction_interpolated": interp, "coa_measured": row["coa_measured"],
                    "cof_error_relative": (row["coa_measured"] - cof) / cof}
    return {"fraction": None, "fraction_interpolated": None, "coa_measured": None, "cof_error_relative": None}


def reproduce(out_dir: Path, quick: bool = False) -> dict:
    timing = QUICK if quick else FULL
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    results: dict = {"quick": quick, "timing_s": asdict(timing)}
    results["fig5_half_wheelset"] = half_wheelset_sweep(timing)
    built = build_wagon(wagon_parameters("laden"))
    fractions = paper_schedule()
    sweep = {}
    for cof in PAPER_COFS:
        rows = wagon_staircase(built, cof, timing, fractions)
        sweep[str(cof)] = {"steps": rows, "zero_crossing": zero_crossing(rows, cof)}
    results["fig7_wagon_cof_0.4"] = sweep["0.4"]["steps"]
    results["fig8_wagon_cof_sweep"] = sweep
    results["wall_time_s"] = time.perf_counter() - t0
    (out_dir / "results.json").write_text(json.dumps(results, indent=1))
    from cof_gym.analysis.paper_figures import plot_all

    results["figures"] = [str(p) for p in plot_all(results, out_dir)]
    (out_dir / "results.json").write_text(json.dumps(results, indent=1))
    return results


def summary_lines(results: dict) -> list[str]:
    acc = results["fig5_half_wheelset"]["acceptance"]
    lines = [f"half wheelset vs Eq. 3: worst error / tolerance = {acc['worst_error_over_tolerance']:.3f} "
             f"({'PASS' if acc['passed'] else 'FAIL'})"]
    for cof, entry in acc["per_cof"].items():
        status = "pass" if entry["passed"] else f"outside at {[round(100 * f) for f in entry['failing_fractions']]} % (large-signal)"
        lines.append(f"  CoF {cof}: {status}")
    lines += [
             "wagon, paper's rule (first positive phase):",
             "  CoF   crossing [% M_sat]  interpolated  CoA there  CoA-as-CoF error"]
    for cof, entry in results["fig8_wagon_cof_sweep"].items():
        z = entry["zero_crossing"]
        if z["fraction"] is None:
            lines.append(f"  {float(cof):.1f}   no positive phase up to 99 %")
        else:
            lines.append(f"  {float(cof):.1f}   {100 * z['fraction']:6.0f}             {100 * z['fraction_interpolated']:6.1f}"
                         f"       {z['coa_measured']:.4f}     {100 * z['cof_error_relative']:+6.1f} %")
    lines.append(f"wall time {results['wall_time_s']:.1f} s")
    return lines
