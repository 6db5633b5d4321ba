"""Figures of ``reproduce-paper`` (matplotlib, Agg), drawn from the numbers in results.json."""

from __future__ import annotations

from pathlib import Path

from cof_gym.analysis.plotting import finish, plt, save  # selects the Agg backend


def _col(rows: list[dict], key: str) -> list[float]:
    return [r[key] for r in rows]


def plot_all(results: dict, out_dir: Path) -> list[Path]:
    paths = []
    # Fig. 5: half wheelset, simulation vs Eq. 3
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for cof, rows in results["fig5_half_wheelset"]["cofs"].items():
        x = [100 * f for f in _col(rows, "fraction")]
        line, = ax.plot(x, _col(rows, "phase_eq3_deg"), "-", lw=1, label=f"Eq. 3, CoF {cof}")
        ax.plot(x, _col(rows, "phase_sim_deg"), "o", ms=3, color=line.get_color(), label=f"MuJoCo, CoF {cof}")
    ax.set(xlabel="DC torque [% of saturation torque]", ylabel="phase lag of wheelset speed [deg]",
           title="Half wheelset (paper Fig. 5): N 100 kN, v 10 m/s, 5 Hz, 345 Nm")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    paths.append(save(fig, out_dir / "fig5_half_wheelset.png", dpi=120))

    # Fig. 4/7: wagon CoF 0.4 with Eq. 4
    rows = results["fig7_wagon_cof_0.4"]
    x = [100 * f for f in _col(rows, "fraction")]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.errorbar(x, _col(rows, "phase_sim_deg"), yerr=_col(rows, "phase_se_deg"), fmt="o-", ms=3, label="MuJoCo wagon")
    ax.plot(x, _col(rows, "phase_eq4_deg"), "s--", ms=3, label="Eq. 4 with measured phi_v")
    ax.plot(x, _col(rows, "phase_eq3_deg"), ":", label="Eq. 3")
    ax.plot(x, _col(rows, "phi_v_deg"), "^", ms=3, alpha=0.6, label="phi_v (creepage behind speed)")
    ax.axhline(0, color="k", lw=0.5)
    ax.set(xlabel="DC torque [% of saturation torque]", ylabel="phase [deg]",
           title="Wagon with cruise control, CoF 0.4 (paper Figs. 4 and 7)")
    finish(ax)
    paths.append(save(fig, out_dir / "fig7_wagon_eq4.png", dpi=120))

    # Fig. 8: CoF sweep on the wagon + crossing / error
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    cofs, crossing, errors = [], [], []
    for cof, entry in results["fig8_wagon_cof_sweep"].items():
        steps = entry["steps"]
        ax.plot([100 * f for f in _col(steps, "fraction")], _col(steps, "phase_sim_deg"), "o-", ms=3, label=f"CoF {cof}")
        z = entry["zero_crossing"]
        if z["fraction"] is not None:
            cofs.append(float(cof))
            crossing.append(100 * z["fraction_interpolated"])
            errors.append(100 * z["cof_error_relative"])
    ax.axhline(0, color="k", lw=0.5)
    ax.set(xlabel="DC torque [% of saturation torque]", ylabel="phase lag [deg]", title="Wagon, CoF 0.1...0.5 (paper Fig. 8)")
    finish(ax)
    ax2.plot(cofs, crossing, "o-", label="zero crossing [% M_sat]")
    ax2.axhspan(94, 95, color="tab:orange", alpha=0.3, label="paper: 94-95 %")
    ax2b = ax2.twinx()
    ax2b.plot(cofs, errors, "s--", color="tab:red", label="CoA-as-CoF error [%]")
    ax2.set(xlabel="CoF", ylabel="zero-crossing torque [% M_sat]", title="Paper's rule on this wagon")
    ax2b.set_ylabel("CoA-as-CoF error [%]")
    ax2.legend(loc="upper left", fontsize=8)
    ax2b.legend(loc="lower right", fontsize=8)
    ax2.grid(alpha=0.3)
    paths.append(save(fig, out_dir / "fig8_wagon_cof_sweep.png", dpi=120))
    return paths
