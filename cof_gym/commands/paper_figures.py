"""Figures of ``reproduce-paper`` (matplotlib, Agg), drawn only from the numbers in results.json."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cof_gym.analysis.plotting import finish, plt, save  # selects the Agg backend

SHAPE_STYLE = {"dry": {"color": "tab:blue", "label": "dry (Polach kA 1, kS 0.4)"},
               "dry_kalker": {"color": "tab:green", "label": "dry_kalker (kA = kS = 1)"}}
PAPER_BAND = {"color": "tab:orange", "alpha": 0.25}


def _col(rows: list[dict], key: str) -> np.ndarray:
    return np.array([np.nan if r[key] is None else r[key] for r in rows], dtype=float)


def _pct(rows: list[dict]) -> np.ndarray:
    return 100 * _col(rows, "fraction")


def _paper_band(ax, results: dict, vertical: bool = False) -> None:
    lo, hi = results["paper"]["crossing_percent"]
    span = ax.axvspan if vertical else ax.axhspan
    span(lo, hi, **PAPER_BAND, label=f"paper: crossing {lo:.0f}-{hi:.0f} %")


def fig_half_wheelset(results: dict, out_dir: Path) -> Path:
    """Every schedule point vs Eq. 3 with its tolerance band; large-signal points and their amplitude ladder."""
    hw = results["half_wheelset"]
    fig, axes = plt.subplots(2, 3, figsize=(14, 8))
    for ax, (cof, rows) in zip(axes.flat, hw["cofs"].items()):
        x, eq3, tol = _pct(rows), _col(rows, "phase_eq3_deg"), _col(rows, "tolerance_deg")
        ax.fill_between(x, eq3 - tol, eq3 + tol, color="0.8", label="Eq. 3 +- max(0.2 deg, 5 %)")
        ax.plot(x, eq3, "k-", lw=1, label="Eq. 3")
        sim = _col(rows, "phase_sim_deg")
        within = np.array([r["within_tolerance"] for r in rows])
        large = np.array([r["large_signal"] for r in rows])
        ax.plot(x[within], sim[within], "o", ms=4, color="tab:blue", label="MuJoCo, within tolerance")
        if large.any():
            ax.plot(x[large], sim[large], "D", ms=5, mfc="none", color="tab:red",
                    label="outside: large-signal (converges as M0 shrinks)")
        other = ~within & ~large
        if other.any():
            ax.plot(x[other], sim[other], "x", ms=7, color="k", label="outside, unexplained")
        ax.set_yscale("log")
        m_sat = float(cof) * hw["parameters"]["wheel_radius_m"] * hw["parameters"]["normal_load_n"]
        ax.set(xlabel="DC torque [% of saturation torque]", ylabel="phase lag [deg]",
               title=f"CoF {cof}: M0 = {100 * hw['parameters']['amplitude_nm'] / m_sat:.2f} % of M_sat")
        finish(ax, 7)
    ax = axes.flat[5]
    ladder = np.array(hw["amplitude_ladder"]) * hw["parameters"]["amplitude_nm"]
    for cof, rows in hw["cofs"].items():
        for r in rows:
            if r["ladder"] is not None:
                ax.plot(ladder, np.abs(r["ladder"]["deviation_deg"]) / r["tolerance_deg"], "o-", ms=3, lw=0.8,
                        color="tab:red", alpha=0.5)
    ax.plot([], [], "o-", color="tab:red", alpha=0.5, label="each point outside at 345 N m")
    ax.plot(ladder, 2.5 * (ladder / ladder[0]) ** 2, "k--", lw=1, label="~ M0^2")
    ax.axhline(1.0, color="0.4", lw=1, label="tolerance")
    ax.set(xscale="log", yscale="log", xlabel="modulation amplitude M0 [N m]", ylabel="|phi_sim - phi_Eq3| / tolerance",
           title="Large-signal points: deviation vs M0")
    finish(ax, 7)
    fig.suptitle("Half wheelset (paper Sect. 2, Fig. 5): N 100 kN, v 10 m/s, 5 Hz, every schedule point")
    return save(fig, out_dir / "fig5_half_wheelset.png", dpi=100)


def fig_eq4(results: dict, out_dir: Path) -> Path:
    """Wagon, CoF 0.4: simulated phase vs Eq. 4 in the paper's and the compliant form, measured phi_v;
    the residuals of both forms; the measured creepage amplitude against cos(phi_v)."""
    fig, axes = plt.subplots(2, 2, figsize=(13, 9))
    for ax, shape in zip(axes[0], ("dry", "dry_kalker")):
        rows = results["wagon"][shape]["cofs"]["0.4"]["steps"]
        x = _pct(rows)
        ax.errorbar(x, _col(rows, "phase_sim_deg"), yerr=_col(rows, "phase_se_deg"), fmt="o", ms=4, color="k",
                    label="MuJoCo wagon")
        ax.plot(x, _col(rows, "phase_eq4_compliant_deg"), "-", color="tab:green",
                label="Eq. 4, cos^2(phi_v) (compliant wheelset)")
        ax.plot(x, _col(rows, "phase_eq4_paper_deg"), "--", color="tab:purple", label="Eq. 4, cos(phi_v) (paper)")
        ax.plot(x, _col(rows, "phase_eq3_deg"), ":", color="tab:gray", label="Eq. 3")
        ax.plot(x, -_col(rows, "phi_v_deg"), "^", ms=3, color="tab:orange", alpha=0.7, label="-phi_v (measured)")
        ax.axhline(0, color="k", lw=0.5)
        ax.set(xlabel="DC torque [% of saturation torque]", ylabel="phase [deg]",
               title=f"{SHAPE_STYLE[shape]['label']}, CoF 0.4 (paper Figs. 4, 7)")
        finish(ax, 7)
    ax = axes[1, 0]
    for shape in ("dry", "dry_kalker"):
        rows = results["wagon"][shape]["cofs"]["0.4"]["steps"]
        c, sim = SHAPE_STYLE[shape]["color"], _col(rows, "phase_sim_deg")
        ax.plot(_pct(rows), _col(rows, "phase_eq4_compliant_deg") - sim, "-o", ms=3, color=c, label=f"{shape}: cos^2 form")
        ax.plot(_pct(rows), _col(rows, "phase_eq4_paper_deg") - sim, "--s", ms=3, mfc="none", color=c,
                label=f"{shape}: paper's cos form")
    ax.axhline(0, color="k", lw=0.5)
    ax.set(xlabel="DC torque [% of saturation torque]", ylabel="Eq. 4 - simulation [deg]",
           title="Eq. 4 residuals with the measured phi_v (large-signal near 99 %)", ylim=(-1.0, 0.5))
    finish(ax, 7)
    ax = axes[1, 1]
    for shape in ("dry", "dry_kalker"):
        rows = results["wagon"][shape]["cofs"]["0.4"]["steps"]
        c = SHAPE_STYLE[shape]["color"]
        ax.plot(_pct(rows), _col(rows, "creep_amplitude_ratio"), "o", ms=4, color=c,
                label=f"{shape}: measured creepage amplitude / (R Omega0 / v)")
        ax.plot(_pct(rows), _col(rows, "creep_amplitude_ratio_model"), "--", color=c, lw=1,
                label=f"{shape}: small-signal model")
        ax.plot(_pct(rows), _col(rows, "cos_phi_v"), "-", color=c, lw=1, label=f"{shape}: cos(phi_v) (measured phi_v)")
    ax.set(xlabel="DC torque [% of saturation torque]", ylabel="ratio",
           title="The creepage amplitude shrinks with cos(phi_v): hence cos^2")
    finish(ax, 7)
    return save(fig, out_dir / "fig7_wagon_eq4.png", dpi=100)


def fig_cof_sweep(results: dict, out_dir: Path) -> Path:
    """Paper Fig. 8 for both shapes; crossing and CoA-as-CoF error per CoF on separate axes."""
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5))
    for ax, shape in zip(axes[0], ("dry", "dry_kalker")):
        for cof, e in results["wagon"][shape]["cofs"].items():
            ax.plot(_pct(e["steps"]), _col(e["steps"], "phase_sim_deg"), "o-", ms=3, lw=1, label=f"CoF {cof}")
        _paper_band(ax, results, vertical=True)
        ax.axhline(0, color="k", lw=0.5)
        ax.set(xlabel="DC torque [% of saturation torque]", ylabel="phase lag [deg]",
               title=f"Wagon, {SHAPE_STYLE[shape]['label']} (paper Fig. 8)")
        finish(ax, 7)
    ax_c, ax_e = axes[1]
    _paper_band(ax_c, results)
    lo, hi = results["paper"]["crossing_percent"]
    for shape, entry in results["wagon"].items():
        st = SHAPE_STYLE[shape]
        cofs = [float(c) for c in entry["cofs"]]
        z = [e["zero_crossing"] for e in entry["cofs"].values()]
        ax_c.plot(cofs, [100 * (q["fraction_interpolated"] or np.nan) for q in z], "o-", color=st["color"],
                  label=f"{shape}: MuJoCo wagon")
        ax_c.plot(cofs, [100 * e["model_crossing_fraction"] for e in entry["cofs"].values()], "s", mfc="none",
                  ms=8, color=st["color"], label=f"{shape}: small-signal model")
        ax_e.plot(cofs, [100 * (q["cof_error_relative"] if q["fraction"] is not None else np.nan) for q in z], "o-",
                  color=st["color"], label=f"{shape}: MuJoCo wagon")
    ax_c.set(xlabel="CoF", ylabel="zero crossing [% of saturation torque]", title="Where the phase turns positive",
             ylim=(60, 100))
    finish(ax_c, 7)
    ax_e.axhline(results["paper"]["error_percent"], color=PAPER_BAND["color"], ls="--",
                 label=f"paper: about {results['paper']['error_percent']:.0f} %")
    ax_e.axhline(0, color="k", lw=0.5)
    ax_e.set(xlabel="CoF", ylabel="CoA-as-CoF error [%]", title="CoA at the first positive step, taken as the CoF",
             ylim=(-35, 2))
    finish(ax_e, 7)
    fig.suptitle("Counter torque, laden (100 kN per wheel), 10 m/s, 5 Hz, 345 N m")
    return save(fig, out_dir / "fig8_wagon_cof_sweep.png", dpi=100)


def fig_mechanism(results: dict, out_dir: Path) -> Path:
    """k_cross against the creep slope; crossing vs primary stiffness and vs creep shape."""
    mech = results["mechanism"]
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    ax = axes[0]
    x = 100 * np.array(mech["slope_vs_fraction"]["fraction"])
    for shape, st in SHAPE_STYLE.items():
        ax.plot(x, mech["slope_vs_fraction"][shape], color=st["color"], label=f"{st['label']}: dCoA/ds")
        ax.axvline(100 * results["wagon"][shape]["cofs"][str(mech["cof"])]["model_crossing_fraction"],
                   color=st["color"], ls=":", lw=1)
    ax.axhline(mech["k_cross"], color="k", ls="--", lw=1, label=f"k_cross = {mech['k_cross']:.1f}")
    ax.set(yscale="log", xlabel="DC torque [% of saturation torque]", ylabel="creep slope dCoA/ds",
           title=f"The crossing is where the slope meets k_cross (CoF {mech['cof']})")
    finish(ax, 7)
    ax = axes[1]
    model = mech["stiffness_model"]
    for shape, st in SHAPE_STYLE.items():
        ax.plot(model["kx_per_axlebox_mn_m"], 100 * np.array(model[shape], dtype=float), "-", color=st["color"],
                lw=1, label=f"{shape}: small-signal model")
        pts = [p for p in mech["stiffness"] if p["shape"] == shape]
        ax.plot([p["kx_per_axlebox_mn_m"] for p in pts], [100 * (p["crossing_sim"] or np.nan) for p in pts], "o",
                color=st["color"], label=f"{shape}: MuJoCo wagon")
    ax.axvline(mech["model"]["kx_n_m"] / 2e6, color="0.5", lw=0.8, ls=":", label="benchmark kx")
    _paper_band(ax, results)
    ax.set(xscale="log", xlabel="primary kx per axlebox [MN/m]", ylabel="zero crossing [% of saturation torque]",
           title=f"Crossing vs primary longitudinal stiffness (CoF {mech['cof']})", ylim=(0, 100))
    finish(ax, 7)
    ax = axes[2]
    sm = mech["shape_model"]
    ax.plot(sm["initial_slope_over_kalker"], 100 * np.array(sm["crossing"], dtype=float), "-", color="k", lw=1,
            label="small-signal model")
    ax.plot([p["initial_slope_over_kalker"] for p in mech["shape"]], [100 * (p["crossing_sim"] or np.nan) for p in mech["shape"]],
            "o", color="tab:red", label="MuJoCo wagon (kA 1, kS 0.4 ... 1)")
    for shape, st in SHAPE_STYLE.items():
        s = results["wagon"][shape]["shape"]
        ax.axvline((s["k_adhesion"] + s["k_slip"]) / 2, color=st["color"], ls=":", label=shape)
    _paper_band(ax, results)
    ax.set(xlabel="initial creep slope / Kalker's, (kA + kS) / 2", ylabel="zero crossing [% of saturation torque]",
           title="Crossing vs creep-curve shape (A 0.4, B 0.6 s/m)")
    finish(ax, 7)
    return save(fig, out_dir / "fig_mechanism.png", dpi=100)


def plot_all(results: dict, out_dir: Path) -> list[Path]:
    """Every figure of reproduce-paper into ``out_dir``."""
    return [fig_half_wheelset(results, out_dir), fig_eq4(results, out_dir), fig_cof_sweep(results, out_dir),
            fig_mechanism(results, out_dir)]
