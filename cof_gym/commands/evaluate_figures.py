"""Figures of ``cof-gym evaluate``: error per CoF level, error vs discomfort, error vs peak torque
(accuracy against intrusiveness), one trace per agent."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cof_gym.analysis.plotting import finish, plt, save  # selects the Agg backend

ERROR_FLOOR_PCT = 0.01  # |relative error| below this is drawn at it on the log axes


def _error_axis(ax, label: str = "|relative CoF error| [%]") -> None:
    """A log axis of the non-negative relative error, from the floor up."""
    ax.set_yscale("log")
    ax.set_ylim(bottom=ERROR_FLOOR_PCT * 0.8)
    ax.set_ylabel(f"{label} (log; < {ERROR_FLOOR_PCT:g} % at {ERROR_FLOOR_PCT:g} %)")


def _error_pct(err) -> np.ndarray:
    """Relative errors in %, as magnitudes, floored for the log axes."""
    return np.maximum(100 * np.abs(np.asarray(err, dtype=float)), ERROR_FLOOR_PCT)


def plot_all(records, summary, traces, out: Path) -> list[Path]:
    agents = list(summary)
    paths = []
    # error per CoF level
    fig, ax = plt.subplots(figsize=(7, 4.5))
    edges = np.linspace(0.0, 0.6, 7)
    centres = 0.5 * (edges[1:] + edges[:-1])
    for k, a in enumerate(agents):
        rows = [r for r in records if r.agent == a]
        cof = np.array([r.cof for r in rows])
        err = np.array([r.relative_error for r in rows])
        ax.scatter(cof, _error_pct(err), s=10, alpha=0.35)
        ax.plot(centres, _error_pct(per_bin(cof, err, edges, np.median)), "o-", label=f"{a} (median per bin)")
    ax.set(xlabel="true CoF", title="Error per CoF level")
    _error_axis(ax)
    finish(ax)
    paths.append(save(fig, out / "error_per_cof.png", dpi=110))

    # error vs discomfort trade-off
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for a in agents:
        s = summary[a]
        x, y = s["wd_rms_m_s2"], s["median_error"]
        ax.errorbar(x["value"], 100 * y["value"], xerr=_error_bar(x), yerr=_error_bar(y, 100.0), fmt="o", capsize=3,
                    label=a)
    ax.set(xlabel="mean Wd-weighted RMS car-body acceleration [m/s^2]", ylabel="median relative CoF error [%]",
           title="Error vs discomfort (95 % CI)")
    finish(ax)
    paths.append(save(fig, out / "error_vs_discomfort.png", dpi=110))

    # accuracy against intrusiveness: error vs the peak torque as a fraction of the real saturation torque
    paths.append(plot_error_vs_peak_torque(records, agents, out))
    paths.append(plot_traces(traces, out))
    paths += plot_creepage_error(records, agents, out)
    return paths


def _error_bar(stat: dict, scale: float = 1.0) -> list[list[float]] | None:
    """A statistic's CI as matplotlib's error bar (below, above), times ``scale``; None where it has none."""
    if stat["ci95"] is None:
        return None
    return [[scale * (stat["value"] - stat["ci95"][0])], [scale * (stat["ci95"][1] - stat["value"])]]


def plot_error_vs_peak_torque(records, agents: list[str], out: Path) -> Path:
    """Each episode's error against its peak torque (% of the real saturation torque), one colour an agent: a dot
    where the agent stopped, a ring where the episode ran to the horizon, a cross at a macro-slip, a diamond at the
    agent's medians; the legend beside the axes (an entry per agent, one per marker)."""
    from matplotlib.lines import Line2D

    fig, ax = plt.subplots(figsize=(9, 4.5))
    handles = []
    for k, a in enumerate(agents):
        rows = [r for r in records if r.agent == a]
        frac = np.array([100 * r.peak_torque_fraction for r in rows])
        err = _error_pct([r.relative_error for r in rows])
        slip = np.array([r.macro_slip for r in rows], dtype=bool)
        horizon = np.array([r.ended == "horizon" for r in rows], dtype=bool)
        color, stopped = f"C{k % 10}", ~slip & ~horizon
        ax.scatter(frac[stopped], err[stopped], s=12, alpha=0.45, color=color)
        ax.scatter(frac[horizon], err[horizon], s=16, alpha=0.7, facecolors="none", edgecolors=color)
        ax.scatter(frac[slip], err[slip], s=30, marker="x", color=color)
        ax.plot([np.median(frac)], [np.median(err)], marker="D", ms=9, mec="k", color=color, ls="none")
        handles.append(Line2D([], [], marker="s", ms=7, ls="none", color=color, label=a))
    grey = "0.45"
    handles += [Line2D([], [], marker="o", ms=4, ls="none", color=grey, alpha=0.6, label="episode, agent's stop"),
                Line2D([], [], marker="o", ms=5, ls="none", mfc="none", mec=grey, label="episode, at the horizon"),
                Line2D([], [], marker="x", ms=6, ls="none", color=grey, label="episode, macro-slip"),
                Line2D([], [], marker="D", ms=8, ls="none", mec="k", color="0.8", label="median of an agent")]
    ax.axvline(100.0, color="k", lw=0.6)
    ax.set(xlabel="peak torque [% of the real saturation torque]", title="Accuracy against intrusiveness (per episode)")
    _error_axis(ax)
    finish(ax, handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return save(fig, out / "error_vs_peak_torque.png", dpi=110)


def _final_error(trace: list[dict]) -> float:
    """|estimate / CoF - 1| at the end of a trace."""
    return abs(trace[-1]["estimate"] / trace[-1]["cof"] - 1.0)


def plot_traces(traces: dict[str, list], out: Path) -> Path:
    """One episode trace per agent; the worst final estimate is drawn last, thick, and labelled."""
    from matplotlib.lines import Line2D

    fig, axes = plt.subplots(4, 1, figsize=(8, 8), sharex=True)
    colors = {a: f"C{k}" for k, a in enumerate(traces)}
    shown = {a: tr for a, tr in traces.items() if tr}
    worst = max(shown, key=lambda a: _final_error(shown[a]), default=None)
    for a in sorted(shown, key=lambda name: name == worst):  # the worst last: on top
        trace, color, top = shown[a], colors[a], a == worst
        t = [p["t"] for p in trace]
        axes[0].step(t, [p["dc_torque_nm"] / 1e3 for p in trace], where="post", color=color, label=a)
        axes[1].plot(t, [p["wheel_speed_m_s"] - p["speed_m_s"] for p in trace], "o-", ms=3, color=color)
        axes[2].plot(t, [p["phase_deg"] for p in trace], "o-", ms=3, color=color)
        axes[3].plot(t, [p["coa"] for p in trace], "o-", ms=3, lw=1.0, color=color)
        axes[3].plot(t, [p["estimate"] for p in trace], "--", color=color, lw=2.8 if top else 1.4,
                     zorder=10 if top else 3)
        if top:
            axes[3].annotate(f"worst estimate: {a} ({100 * _final_error(trace):.0f} % off)",
                             (t[-1], trace[-1]["estimate"]), xytext=(-6, 8), textcoords="offset points", ha="right",
                             fontsize=8, fontweight="bold", color=color, zorder=11,
                             bbox=dict(boxstyle="round", fc="white", alpha=0.8, lw=0))
    if shown:
        axes[3].axhline(next(iter(shown.values()))[0]["cof"], color="k", lw=1.0)
    axes[0].set_ylabel("mean torque [kN m]")
    axes[1].set_ylabel("wheelset R*Omega - v [m/s]")
    axes[2].set_ylabel("phase lag [deg]")
    axes[3].set_ylabel("CoF [-]")
    axes[3].set_xlabel("time [s]")
    axes[0].legend(fontsize=8, title="agent", title_fontsize=8)
    axes[3].legend(handles=[Line2D([], [], color="0.3", marker="o", ms=3, lw=1.0, label="measured CoA"),
                            Line2D([], [], color="0.3", ls="--", lw=1.4, label="estimate"),
                            Line2D([], [], color="k", lw=1.0, label="true CoF")], fontsize=8, loc="best")
    axes[0].set_title("First episode of the suite, per agent")
    for ax in axes:
        ax.grid(alpha=0.3)
    return save(fig, out / "episode_traces.png", dpi=110)


def per_bin(x: np.ndarray, y: np.ndarray, edges: np.ndarray, stat) -> np.ndarray:
    """``stat`` of the ``y`` whose ``x`` falls in each bin of ``edges`` (the end bins take what lies
    beyond them), NaN for an empty bin."""
    which = np.digitize(x, edges[1:-1])
    return np.array([stat(y[which == k]) if np.any(which == k) else np.nan for k in range(len(edges) - 1)])


CREEPAGE_ERROR_EDGES_PCT = np.array([-3.0, -1.0, -0.5, -0.2, 0.2, 0.5, 1.0, 3.0])


def plot_creepage_error(records, agents: list[str], out: Path) -> list[Path]:
    """Each agent's median relative CoF error and macro-slip rate per band of the sensors' systematic
    creepage error (v2; one band at 0 in v1: then no figure)."""
    offsets = np.array([100 * r.creepage_offset for r in records])
    if np.ptp(offsets) == 0.0:
        return []
    edges = CREEPAGE_ERROR_EDGES_PCT
    centres = 0.5 * (edges[1:] + edges[:-1])
    fig, (ax_err, ax_slip) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    for a in agents:
        rows = [r for r in records if r.agent == a]
        x = np.array([100 * r.creepage_offset for r in rows])
        err = np.array([100 * r.relative_error for r in rows])
        slip = np.array([r.macro_slip for r in rows], dtype=float)
        med = per_bin(x, err, edges, np.median)
        rate = 100 * per_bin(x, slip, edges, np.mean)
        line, = ax_err.plot(centres, med, "o-", label=a)
        ax_err.scatter(x, err, s=8, alpha=0.25, color=line.get_color())
        ax_slip.plot(centres, rate, "o-", color=line.get_color(), label=a)
    ax_err.set(ylabel="relative CoF error [%]", yscale="symlog", ylim=(0, None),
               title="Error and macro-slips against the systematic creepage error (median per band)")
    ax_slip.set(xlabel="systematic creepage error (1 + e_R)/(1 + e_v) - 1 [%]", ylabel="macro-slip rate [%]",
                ylim=(-2, 102))
    for ax in (ax_err, ax_slip):
        finish(ax)
    return [save(fig, out / "error_vs_creepage_error.png", dpi=110)]
