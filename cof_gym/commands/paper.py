"""``cof-gym reproduce-paper``: the paper's Figs. 5, 4/7 and 8 re-simulated for two creep-curve
shapes, the mechanism that sets the zero crossing, and a verdict per check; every plotted number is
written to ``results.json``.

Checks that *should hold* on this code (a failure exits non-zero):

* ``half_wheelset_small_signal``: the half wheelset follows Eq. 3 within max(0.2 deg, 5 %) at every
  schedule point for CoF 0.2-0.5 (M0 = 345 N m is at most 3.75 % of their saturation torque);
* ``half_wheelset_large_signal``: every point outside that tolerance (CoF 0.1, where 345 N m is 7.5 %
  of the saturation torque) is a large-signal effect: its deviation falls at least as M0^1.5 as the
  modulation shrinks and is within the tolerance at M0 / 4;
* ``wagon_dry_kalker_paper``: with Kalker's initial creep slope the wagon crosses zero at 92-96 % of
  the saturation torque and the CoA-as-CoF error is -8 ... -3 % for every CoF (paper: 94-95 %, ~5 %);
* ``mechanism_small_signal_model``: the small-signal compliant-wheelset model predicts the wagon's
  crossing within 1 point for both shapes and every CoF;
* ``eq4_compliant_form``: at low torque Eq. 4 with cos^2(phi_v) matches the simulated phase better
  than the paper's cos(phi_v), and the measured creepage amplitude agrees with the small-signal
  model's within 2 % (about 0.95 cos(phi_v): the wheelset's mass and primary damper shrink it a bit
  more than a bare spring would).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from cof_gym.commands.args import UsageError, check_command_output
from cof_gym.commands.paper_readme import check_readme, update_readme
from cof_gym.analysis.theory import (
    PAPER_AMPLITUDE_NM,
    PAPER_COFS,
    PAPER_FREQUENCY_HZ,
    PAPER_SPEED_M_S,
    CompliantWheelset,
    creep_slope_at_torque,
    crossing_fraction,
    paper_schedule,
    phase_eq3_deg,
    phase_eq4_compliant_deg,
    phase_eq4_deg,
)
from cof_gym.physics.creep import CONDITIONS, OperatingConditions, PolachShape, shape_of
from cof_gym.physics.models import build_half_wheelset, build_wagon
from cof_gym.physics.simulation import DriveCommand, Scenario, Simulation
from cof_gym.physics.vehicle import HalfWheelsetParameters, WagonParameters, wagon_parameters

RESULTS_FILE = "results.json"  # every plotted number; also what marks an earlier output directory
PAPER_OMEGA_RAD_S = 2 * math.pi * PAPER_FREQUENCY_HZ
PAPER_CROSSING_PERCENT = (94.0, 95.0)  # paper Sect. 4.2
PAPER_ERROR_PERCENT = -5.0  # paper Sect. 4.2: "an expected error of 5 %" (the CoA is below the CoF)
SHAPES = ("dry", "dry_kalker")
ACCEPT_CROSSING_PERCENT = (92.0, 96.0)  # issue 8 acceptance for dry_kalker
ACCEPT_ERROR_PERCENT = (-8.0, -3.0)
AMPLITUDE_LADDER = (1.0, 0.5, 0.25, 0.125)  # M0 multiples tried at points outside the Eq. 3 tolerance
MECHANISM_COF = 0.4
MECHANISM_KX_MN_M = (100.0, 31.39, 10.0, 4.0, 2.0, 1.5)  # primary kx per axlebox
MECHANISM_K_SLIP = (0.4, 0.55, 0.7, 0.85, 1.0)  # Polach kS with the dry kA, A, B: dry ... dry_kalker
LOW_TORQUE_FRACTION = 0.31  # Eq. 4 forms compared at and below this torque (linear part of the curve)


@dataclass(frozen=True)
class Timing:
    """Window timing of one staircase step, s."""

    ramp: float
    settle: float
    measure: float


FULL = Timing(ramp=0.5, settle=2.0, measure=2.0)
QUICK = Timing(ramp=0.3, settle=1.2, measure=1.0)


def tolerance_deg(phase_eq3: float) -> float:
    """Eq. 3 agreement tolerance: max(0.2 deg, 5 % of the Eq. 3 phase)."""
    return max(0.2, 0.05 * abs(phase_eq3))


def _drive(dc_nm: float, amplitude_nm: float = PAPER_AMPLITUDE_NM) -> DriveCommand:
    return DriveCommand(dc_nm, amplitude_nm, PAPER_FREQUENCY_HZ)


# ---------------------------------------------------------------- half wheelset (paper Sect. 2, Fig. 5)
def half_wheelset_sweep(timing: Timing) -> dict:
    """Every schedule point vs Eq. 3, CoF 0.1 ... 0.5; points outside the tolerance get an amplitude
    ladder (M0 x 1, 1/2, 1/4, 1/8) that shows whether they are large-signal effects."""
    params = HalfWheelsetParameters()
    sim = Simulation(build_half_wheelset(params))
    r, n, iw = params.wheel_radius_m, params.normal_load_n, params.spin_inertia_kg_m2
    out: dict = {"parameters": {**asdict(params), "speed_m_s": PAPER_SPEED_M_S, "amplitude_nm": PAPER_AMPLITUDE_NM,
                                "frequency_hz": PAPER_FREQUENCY_HZ},
                 "tolerance": "max(0.2 deg, 5 % of phi_Eq3)", "amplitude_ladder": list(AMPLITUDE_LADDER), "cofs": {}}
    for cof in PAPER_COFS:
        op = OperatingConditions(cof=cof, wheel_load_n=n, speed_m_s=PAPER_SPEED_M_S)
        m_sat = r * n * cof
        rows = []
        for frac in paper_schedule():
            eq3 = phase_eq3_deg(iw, PAPER_OMEGA_RAD_S, PAPER_SPEED_M_S, n, r, creep_slope_at_torque(frac * m_sat, r, n, op))
            tol = tolerance_deg(eq3)

            def phase(amplitude: float) -> tuple[float, float]:
                sim.reset(Scenario(op))
                m = sim.run_window(_drive(frac * m_sat, amplitude), timing.settle + timing.measure, timing.settle,
                                   timing.ramp)
                return m.phase_lag_deg, m.phase_lag_se_deg

            sim_deg, se = phase(PAPER_AMPLITUDE_NM)
            row = {"fraction": float(frac), "phase_sim_deg": sim_deg, "phase_se_deg": se, "phase_eq3_deg": eq3,
                   "tolerance_deg": tol, "amplitude_over_margin": PAPER_AMPLITUDE_NM / (m_sat - frac * m_sat),
                   "within_tolerance": bool(abs(sim_deg - eq3) <= tol), "ladder": None}
            if not row["within_tolerance"]:
                dev = [sim_deg - eq3] + [phase(PAPER_AMPLITUDE_NM * k)[0] - eq3 for k in AMPLITUDE_LADDER[1:]]
                slope = np.polyfit(np.log(AMPLITUDE_LADDER), np.log(np.abs(dev)), 1)[0]
                row["ladder"] = {"deviation_deg": dev, "exponent": float(slope),
                                 "within_at_quarter": bool(abs(dev[AMPLITUDE_LADDER.index(0.25)]) <= tol)}
            row["large_signal"] = bool(row["ladder"] is not None and row["ladder"]["exponent"] >= 1.5
                                       and row["ladder"]["within_at_quarter"])
            rows.append(row)
        out["cofs"][str(cof)] = rows
    return out


# ---------------------------------------------------------------- wagon (paper Sect. 3-4, Figs. 4, 7, 8)
def _op(cof: float, condition: str | PolachShape, wheel_load_n: float) -> OperatingConditions:
    return OperatingConditions(cof=cof, condition=condition, wheel_load_n=wheel_load_n, speed_m_s=PAPER_SPEED_M_S)


def wagon_staircase(params: WagonParameters, op: OperatingConditions, timing: Timing, fractions: np.ndarray,
                    stop_at_crossing: bool = False) -> list[dict]:
    """The paper's procedure on the wagon (counter torque, cruise control): one continuous run, DC
    torque stepped up ``fractions`` of the saturation torque; optionally stop at the first positive phase."""
    built = build_wagon(params)
    sim = Simulation(built)
    sim.reset(Scenario(op))
    m_sat = built.saturation_torque_per_cof * op.cof
    r, n_contact, iw = built.wheel_radius_m, built.nominal_wheel_load_n * built.wheels_per_contact, built.drive_spin_inertia_kg_m2
    sim.run_window(_drive(0.0), timing.settle + timing.measure, timing.settle)  # settle the cruise control
    model = CompliantWheelset.of_wagon(params, PAPER_SPEED_M_S)
    rows = []
    for frac in fractions:
        m = sim.run_window(_drive(frac * m_sat), timing.settle + timing.measure, timing.settle, timing.ramp)
        slope = creep_slope_at_torque(frac * m_sat, r, n_contact, op)
        eq3 = phase_eq3_deg(iw, PAPER_OMEGA_RAD_S, PAPER_SPEED_M_S, n_contact, r, slope)
        rho = m.creepage_amplitude * m.speed_measured_m_s / (r * m.omega_amplitude_rad_s)
        phi_v = m.creep_phase_lag_deg
        rows.append({
            "fraction": float(frac), "phase_sim_deg": m.phase_lag_deg, "phase_se_deg": m.phase_lag_se_deg,
            "phi_v_deg": phi_v, "creep_amplitude_ratio": rho, "cos_phi_v": math.cos(math.radians(phi_v)),
            "phase_model_deg": model.phase_lag_deg(slope, PAPER_OMEGA_RAD_S),
            "phi_v_model_deg": model.creep_lag_deg(slope, PAPER_OMEGA_RAD_S),
            "creep_amplitude_ratio_model": model.creep_amplitude_ratio(slope, PAPER_OMEGA_RAD_S),
            "phase_eq3_deg": eq3, "phase_eq4_paper_deg": phase_eq4_deg(eq3, phi_v),
            "phase_eq4_compliant_deg": phase_eq4_compliant_deg(eq3, phi_v),
            "phase_eq4_measured_rho_deg": phase_eq4_deg(eq3, phi_v, rho),
            "coa_measured": m.coa_measured, "normal_load_n": m.normal_load_n, "speed_m_s": m.speed_measured_m_s,
            "wd_rms_m_s2": m.wd_rms_m_s2, "max_abs_creepage": m.max_abs_creepage,
        })
        if stop_at_crossing and m.phase_lag_deg > 0.0:
            break
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


def _model_crossing(params: WagonParameters, op: OperatingConditions) -> float:
    return crossing_fraction(CompliantWheelset.of_wagon(params, PAPER_SPEED_M_S), op, PAPER_OMEGA_RAD_S)


def wagon_cof_sweep(timing: Timing) -> dict:
    """Fig. 8 for each creep shape: the full schedule, CoF 0.1 ... 0.5, with the small-signal model's
    crossing beside the simulated one."""
    params = wagon_parameters("laden")
    out = {}
    for shape in SHAPES:
        out[shape] = {"shape": asdict(shape_of(shape)), "cofs": {}}
        for cof in PAPER_COFS:
            op = _op(cof, shape, params.static_wheel_load_n)
            rows = wagon_staircase(params, op, timing, paper_schedule())
            out[shape]["cofs"][str(cof)] = {"steps": rows, "zero_crossing": zero_crossing(rows, cof),
                                            "model_crossing_fraction": _model_crossing(params, op)}
    return out


def mechanism(timing: Timing) -> dict:
    """What sets the crossing: k_cross of the compliant wheelset against the creep curve's slope,
    crossing vs primary stiffness (both shapes) and vs the creep shape, at CoF 0.4."""
    base = wagon_parameters("laden")
    model = CompliantWheelset.of_wagon(base, PAPER_SPEED_M_S)
    schedule = paper_schedule()
    load = base.static_wheel_load_n
    # creep slope along the torque axis, for the figure
    fracs = np.linspace(0.01, 0.99, 99)
    n_contact = model.contact_load_n
    slope_curves = {}
    for shape in SHAPES:
        op = _op(MECHANISM_COF, shape, load)
        m_sat = model.radius_m * n_contact * op.cof
        slope_curves[shape] = [creep_slope_at_torque(f * m_sat, model.radius_m, n_contact, op) for f in fracs]
    stiffness = []
    for shape in SHAPES:
        op = _op(MECHANISM_COF, shape, load)
        for kx in MECHANISM_KX_MN_M:
            params = dataclasses.replace(base, primary_kx_n_m=kx * 1e6)
            rows = wagon_staircase(params, op, timing, schedule, stop_at_crossing=True)
            stiffness.append({"shape": shape, "kx_per_axlebox_mn_m": kx,
                              "crossing_sim": zero_crossing(rows, op.cof)["fraction_interpolated"],
                              "crossing_model": _model_crossing(params, op),
                              "k_cross": CompliantWheelset.of_wagon(params, PAPER_SPEED_M_S).k_cross(PAPER_OMEGA_RAD_S)})
    kx_grid = np.geomspace(1.2, 150.0, 60)
    stiffness_model = {shape: [_model_crossing(dataclasses.replace(base, primary_kx_n_m=k * 1e6),
                                               _op(MECHANISM_COF, shape, load)) for k in kx_grid] for shape in SHAPES}
    dry = CONDITIONS["dry"]
    shapes = []
    for ks in MECHANISM_K_SLIP:
        op = _op(MECHANISM_COF, dataclasses.replace(dry, k_slip=ks), load)
        rows = wagon_staircase(base, op, timing, schedule, stop_at_crossing=True)
        shapes.append({"k_adhesion": dry.k_adhesion, "k_slip": ks,
                       "initial_slope_over_kalker": (dry.k_adhesion + ks) / 2,
                       "crossing_sim": zero_crossing(rows, op.cof)["fraction_interpolated"],
                       "crossing_model": _model_crossing(base, op)})
    ks_grid = np.linspace(0.3, 1.2, 37)
    return {
        "cof": MECHANISM_COF,
        "model": asdict(model),
        "k_cross_estimate": model.k_cross_estimate(),
        "k_cross": model.k_cross(PAPER_OMEGA_RAD_S),
        "slope_vs_fraction": {"fraction": fracs.tolist(), **slope_curves},
        "stiffness": stiffness,
        "stiffness_model": {"kx_per_axlebox_mn_m": kx_grid.tolist(), **stiffness_model},
        "shape": shapes,
        "shape_model": {"k_slip": ks_grid.tolist(), "initial_slope_over_kalker": ((dry.k_adhesion + ks_grid) / 2).tolist(),
                        "crossing": [_model_crossing(base, _op(MECHANISM_COF, dataclasses.replace(dry, k_slip=float(k)), load))
                                     for k in ks_grid]},
    }


# ---------------------------------------------------------------- verdicts
def _check(name: str, passed: bool, detail: str) -> dict:
    return {"name": name, "passed": bool(passed), "detail": detail}


def checks(results: dict) -> list[dict]:
    """Every check that should hold on this code (see the module docstring)."""
    hw = results["half_wheelset"]["cofs"]
    out = []
    small = {c: [r for r in rows if not r["within_tolerance"]] for c, rows in hw.items() if float(c) >= 0.2}
    out.append(_check("half_wheelset_small_signal", not any(small.values()),
                      "CoF 0.2-0.5, all {} points within max(0.2 deg, 5 %); worst |error|/tolerance {:.2f}".format(
                          sum(len(rows) for c, rows in hw.items() if float(c) >= 0.2),
                          max(abs(r["phase_sim_deg"] - r["phase_eq3_deg"]) / r["tolerance_deg"]
                              for c, rows in hw.items() if float(c) >= 0.2 for r in rows))))
    outside = [(c, r) for c, rows in hw.items() for r in rows if not r["within_tolerance"]]
    unexplained = [(c, r["fraction"]) for c, r in outside if not r["large_signal"]]
    exps = [r["ladder"]["exponent"] for _, r in outside]
    out.append(_check("half_wheelset_large_signal", not unexplained,
                      f"{len(outside)} points outside at 345 N m (CoF {', '.join(sorted({c for c, _ in outside}))}), all converge "
                      f"to Eq. 3 as M0 shrinks (deviation ~ M0^{min(exps, default=0):.1f}...{max(exps, default=0):.1f}, "
                      f"within tolerance at M0/4)" if not unexplained else f"not large-signal: {unexplained}"))
    kal = results["wagon"]["dry_kalker"]["cofs"]
    bad = []
    for c, e in kal.items():
        z = e["zero_crossing"]
        if z["fraction"] is None or not (
                ACCEPT_CROSSING_PERCENT[0] <= 100 * z["fraction_interpolated"] <= ACCEPT_CROSSING_PERCENT[1]
                and ACCEPT_ERROR_PERCENT[0] <= 100 * z["cof_error_relative"] <= ACCEPT_ERROR_PERCENT[1]):
            bad.append(c)
    out.append(_check("wagon_dry_kalker_paper", not bad,
                      f"crossing within {ACCEPT_CROSSING_PERCENT[0]:.0f}-{ACCEPT_CROSSING_PERCENT[1]:.0f} % and "
                      f"CoA-as-CoF error within {ACCEPT_ERROR_PERCENT[0]:.0f} ... {ACCEPT_ERROR_PERCENT[1]:.0f} % for "
                      + ("every CoF" if not bad else f"all but CoF {bad}")))
    diffs = [100 * abs(e["zero_crossing"]["fraction_interpolated"] - e["model_crossing_fraction"])
             for shape in results["wagon"].values() for e in shape["cofs"].values()
             if e["zero_crossing"]["fraction"] is not None]
    n_cases = sum(len(s["cofs"]) for s in results["wagon"].values())
    out.append(_check("mechanism_small_signal_model", len(diffs) == n_cases and max(diffs) <= 1.0,
                      f"model vs wagon crossing, both shapes, every CoF: worst {max(diffs, default=math.nan):.2f} points"))
    low = [r for shape in results["wagon"].values() for r in shape["cofs"]["0.4"]["steps"]
           if r["fraction"] <= LOW_TORQUE_FRACTION]
    e_cos2 = max(abs(r["phase_eq4_compliant_deg"] - r["phase_sim_deg"]) for r in low)
    e_cos = min(abs(r["phase_eq4_paper_deg"] - r["phase_sim_deg"]) for r in low)
    rho_cos = [r["creep_amplitude_ratio"] / r["cos_phi_v"] for r in low]
    rho_model = max(abs(r["creep_amplitude_ratio"] / r["creep_amplitude_ratio_model"] - 1) for r in low)
    out.append(_check("eq4_compliant_form", e_cos2 < e_cos and rho_model <= 0.02,
                      f"CoF 0.4, both shapes, DC <= {100 * LOW_TORQUE_FRACTION:.0f} %: |Eq. 4 - sim| <= {e_cos2:.2f} deg "
                      f"with cos^2(phi_v), >= {e_cos:.2f} deg with the paper's cos(phi_v); measured creepage amplitude "
                      f"/ (R Omega0 / v) = {min(rho_cos):.2f}...{max(rho_cos):.2f} x cos(phi_v) (wheelset mass and "
                      f"primary damper), the small-signal model's within {100 * rho_model:.1f} %"))
    return out


# ---------------------------------------------------------------- command
def reproduce(out_dir: Path, quick: bool = False) -> dict:
    """Run everything, write results.json and the figures into ``out_dir``; returns the results."""
    timing = QUICK if quick else FULL
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    results: dict = {"quick": quick, "timing_s": asdict(timing),
                     "paper": {"amplitude_nm": PAPER_AMPLITUDE_NM, "frequency_hz": PAPER_FREQUENCY_HZ,
                               "speed_m_s": PAPER_SPEED_M_S, "cofs": list(PAPER_COFS),
                               "crossing_percent": list(PAPER_CROSSING_PERCENT), "error_percent": PAPER_ERROR_PERCENT,
                               "schedule_percent": [round(100 * f) for f in paper_schedule()]}}
    results["half_wheelset"] = half_wheelset_sweep(timing)
    results["wagon"] = wagon_cof_sweep(timing)
    results["mechanism"] = mechanism(timing)
    results["checks"] = checks(results)
    results["wall_time_s"] = time.perf_counter() - t0
    from cof_gym.commands.paper_figures import plot_all

    results["figures"] = [p.name for p in plot_all(results, out_dir)]
    (out_dir / RESULTS_FILE).write_text(json.dumps(results, indent=1))
    return results


def summary_lines(results: dict) -> list[str]:
    """The console report: the wagon table per shape, then one verdict per check."""
    lines = ["wagon, paper's rule (first positive phase), counter torque, laden, 10 m/s, 5 Hz, 345 N m:"]
    for shape, entry in results["wagon"].items():
        lines.append(f"  {shape}:  CoF  first positive  crossing (interp.)  model  CoA there  CoA-as-CoF error")
        for cof, e in entry["cofs"].items():
            z = e["zero_crossing"]
            if z["fraction"] is None:
                lines.append(f"        {float(cof):.1f}  no positive phase up to 99 %")
                continue
            lines.append(f"        {float(cof):.1f}  {100 * z['fraction']:6.0f} %        {100 * z['fraction_interpolated']:6.1f} %"
                         f"          {100 * e['model_crossing_fraction']:5.1f} %  {z['coa_measured']:.4f}    "
                         f"{100 * z['cof_error_relative']:+6.1f} %")
    lines.append(f"  paper (VI-Rail ERRI wagon): crossing {PAPER_CROSSING_PERCENT[0]:.0f}-{PAPER_CROSSING_PERCENT[1]:.0f} %, "
                 f"error about {PAPER_ERROR_PERCENT:.0f} %")
    mech = results["mechanism"]
    lines.append(f"mechanism: the phase crosses zero where dCoA/ds falls to k_cross = {mech['k_cross']:.2f} "
                 f"(v sqrt(Iw kx)/(R N) = {mech['k_cross_estimate']:.2f})")
    lines.append("checks:")
    for c in results["checks"]:
        lines.append(f"  {'PASS' if c['passed'] else 'FAIL'}  {c['name']}: {c['detail']}")
    lines.append(f"wall time {results['wall_time_s']:.1f} s")
    return lines


def exit_status(results: dict) -> int:
    """0 when every check that should hold holds, else 1."""
    return 0 if all(c["passed"] for c in results["checks"]) else 1


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``reproduce-paper`` options."""
    parser.add_argument("--out", default="out/paper", help="output directory (figures, results.json)")
    parser.add_argument("--quick", action="store_true", help="shorter windows (the README's numbers)")
    parser.add_argument("--readme", metavar="PATH", default=None,
                        help="also rewrite the README section between the reproduce-paper markers from this run")


def run(args: argparse.Namespace) -> int:
    """``cof-gym reproduce-paper``: exit status 1 when a check that should hold fails; the README to
    rewrite is checked before anything is simulated (a usage error otherwise)."""
    readme = getattr(args, "readme", None)
    if readme == "":
        raise UsageError("--readme", "an empty path; give the README file to rewrite")
    if readme is not None:
        try:
            check_readme(Path(readme))
        except ValueError as e:
            raise UsageError("--readme", str(e)) from None
    out = check_command_output(Path(args.out), RESULTS_FILE, "cof-gym reproduce-paper")
    results = reproduce(out, quick=args.quick)
    print("\n".join(summary_lines(results)))
    print(f"figures and results.json in {args.out}")
    if readme is not None:
        update_readme(Path(readme), results, Path(args.out))
        print(f"README section rewritten in {readme}")
    return exit_status(results)
