"""The frames of ``cof-gym watch``: the MuJoCo scene (left) beside matplotlib panels (right).

The scene is rendered offscreen (EGL or OSMesa) with a camera that follows the driven wheelset; the
panels (Agg) show the creep curve with the operating point moving along it, the torque over the
episode, the torque and wheelset-speed oscillations of the last second (their phase lag is the
measurement), the phase lag of each window and the estimate against the true CoF (with an agent's in-flight
lower bound where it reports one). Every axis range is
fixed from the whole episode, so the static parts are drawn once and each frame only redraws the moving
artists (blitting): a frame costs one scene render and a few line draws.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.font_manager import findfont

from cof_gym.analysis.plotting import plt  # selects the Agg backend
from cof_gym.physics.scenery import SCENERY_PREFIX, TRACK_PERIOD_M

OSCILLATION_SPAN_S = 1.0  # the oscillation panel shows the last second
TAIL_S = 0.4  # the operating point's trail on the creep curve
TORQUE_COLOR = "tab:blue"
SPEED_COLOR = "tab:orange"
CURVE_COLOR = "#2ca02c"  # the creep curve (tests look for it)
POINT_COLOR = "#d62728"
ESTIMATE_COLOR = "tab:purple"


@dataclass(frozen=True)
class EpisodeView:
    """What the panels know about the whole episode before its first frame (axis ranges, truth)."""

    cof: float  # the true CoF (the peak of the creep curve)
    peak_creepage: float
    macro_slip_creepage: float
    curve_creepage: np.ndarray  # the true steady creep curve at the episode's load and speed
    curve_coa: np.ndarray
    duration_s: float  # simulated time the video covers (baseline window included)
    window_s: float
    torque_range_knm: tuple[float, float]
    max_estimate: float
    phase_range_deg: tuple[float, float]
    shows_lower_bound: bool = False  # the agent reported an in-flight lower bound (the estimate panel draws it)


@dataclass(frozen=True)
class WindowPoint:
    """One completed window as the panels plot it."""

    t_end_s: float
    phase_lag_deg: float
    phase_lag_se_deg: float
    coa_measured: float
    creepage_measured: float
    estimate: float  # the estimate the agent reported with this window's drive (nan: none)
    lower_bound: float = float("nan")  # the in-flight lower bound the agent held when it chose that drive (nan: none)


@dataclass(frozen=True)
class Traces:
    """The replay's samples (every few ms of simulated time) up to the frame being drawn."""

    t: np.ndarray
    torque_knm: np.ndarray
    dc_knm: np.ndarray
    creepage: np.ndarray
    coa: np.ndarray
    torque_osc: np.ndarray  # torque oscillation / its amplitude (one modulation period around each sample)
    speed_osc: np.ndarray  # wheelset-speed oscillation / its amplitude


def oscillation(x: np.ndarray, period_samples: int) -> np.ndarray:
    """``x`` minus its moving mean over one period, divided by its moving amplitude (sqrt 2 x RMS)."""
    n = max(int(period_samples), 1)
    if x.size < 2 or n < 2:
        return np.zeros_like(x)
    kernel = np.ones(min(n, x.size)) / min(n, x.size)
    padded = np.pad(x, (kernel.size // 2, kernel.size - 1 - kernel.size // 2), mode="edge")
    dev = x - np.convolve(padded, kernel, mode="valid")
    padded = np.pad(dev**2, (kernel.size // 2, kernel.size - 1 - kernel.size // 2), mode="edge")
    amp = np.sqrt(2.0 * np.convolve(padded, kernel, mode="valid"))
    return dev / np.maximum(amp, 1e-12 + 1e-9 * np.abs(x).max())


class SceneCamera:
    """Offscreen renders of the model, the camera following the driven wheelset; the bogie frames are
    drawn translucent so the wheels show through them."""

    def __init__(self, model: mujoco.MjModel, width: int, height: int, driven_body: int,
                 translucent_bodies: tuple[int, ...]) -> None:
        self.model = model
        self.data = mujoco.MjData(model)  # a render copy: only its kinematics are computed
        self.renderer = mujoco.Renderer(model, height, width)
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        self.camera.distance = 12.0
        self.camera.azimuth = 122.0
        self.camera.elevation = -10.0
        self.driven_body = driven_body
        self.translucent = {int(g) for g in np.flatnonzero(np.isin(model.geom_bodyid, translucent_bodies))}
        self.scenery = {g for g in range(model.ngeom)
                        if model.geom_bodyid[g] == 0 and model.geom(g).name.startswith(SCENERY_PREFIX)}

    def render(self, qpos: np.ndarray) -> np.ndarray:
        """The scene at configuration ``qpos``, (height, width, 3) uint8."""
        d = self.data
        d.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, d)
        mujoco.mj_comPos(self.model, d)
        mujoco.mj_camlight(self.model, d)
        target = d.xpos[self.driven_body]
        self.camera.lookat[:] = [target[0] + 1.6, target[1], target[2] + 0.7]
        self.renderer.update_scene(d, self.camera)
        shift = TRACK_PERIOD_M * math.floor(target[0] / TRACK_PERIOD_M)  # the periodic track follows the wagon
        scene = self.renderer.scene
        for i in range(scene.ngeom):
            g = scene.geoms[i]
            if g.objtype != mujoco.mjtObj.mjOBJ_GEOM:
                continue
            if g.objid in self.translucent:
                g.rgba[3] = 0.3
            elif g.objid in self.scenery:
                g.pos[0] += shift
        return self.renderer.render()

    def close(self) -> None:
        self.renderer.close()


class Caption:
    """Text on the scene (PIL, DejaVu from matplotlib): the caption top left, a banner at the bottom."""

    def __init__(self, height: int) -> None:
        from PIL import ImageFont

        self.mono = ImageFont.truetype(findfont("DejaVu Sans Mono"), max(10, round(height / 42)))
        self.bold = ImageFont.truetype(findfont("DejaVu Sans:bold"), max(11, round(height / 34)))

    def draw(self, scene: np.ndarray, text: str, banner: str = "") -> np.ndarray:
        from PIL import Image, ImageDraw

        img = Image.fromarray(scene)
        draw = ImageDraw.Draw(img, "RGBA")
        pad = 8
        box = draw.multiline_textbbox((pad * 2, pad * 2), text, font=self.mono, spacing=4)
        draw.rounded_rectangle((box[0] - pad, box[1] - pad, box[2] + pad, box[3] + pad), 6, fill=(255, 255, 255, 205))
        draw.multiline_text((pad * 2, pad * 2), text, font=self.mono, fill=(20, 20, 20), spacing=4)
        if banner:
            w, h = img.size
            box = draw.multiline_textbbox((0, 0), banner, font=self.bold, spacing=4, align="center")
            x, y = (w - (box[2] - box[0])) / 2, h - (box[3] - box[1]) - 4 * pad
            draw.rounded_rectangle((x - pad, y - pad, x + box[2] - box[0] + pad, y + box[3] - box[1] + pad), 6,
                                   fill=(255, 255, 255, 225))
            draw.multiline_text((x, y - box[1]), banner, font=self.bold, fill=(160, 20, 20), spacing=4,
                                align="center")
        return np.asarray(img)


class Panels:
    """The right part of the frame: five panels, static parts drawn once, moving artists blitted."""

    def __init__(self, view: EpisodeView, width: int, height: int, dpi: int = 100) -> None:
        self.view = view
        self.width, self.height = width, height
        fs = max(6.0, 7.5 * height / 720)  # points; readable down to the GIF size
        with plt.rc_context({"font.size": fs}):
            self.fig = plt.figure(figsize=(width / dpi, height / dpi), dpi=dpi, facecolor="white")
            gs = self.fig.add_gridspec(4, 2, left=0.11, right=0.975, top=0.955, bottom=0.065, hspace=0.62,
                                       wspace=0.36, height_ratios=(1.5, 0.85, 0.85, 1.0))
            self._creep_panel(self.fig.add_subplot(gs[0, :]))
            self._torque_panel(self.fig.add_subplot(gs[1, :]))
            self._oscillation_panel(self.fig.add_subplot(gs[2, :]))
            self._phase_panel(self.fig.add_subplot(gs[3, 0]))
            self._estimate_panel(self.fig.add_subplot(gs[3, 1]))
        self.animated = [a for a in self.fig.findobj() if getattr(a, "_watch_animated", False)]
        for a in self.animated:
            a.set_animated(True)
        self.fig.canvas.draw()
        self.background = self.fig.canvas.copy_from_bbox(self.fig.bbox)

    @staticmethod
    def _moving(artist):
        artist._watch_animated = True
        return artist

    # ------------------------------------------------------------------ layout (static parts)
    def _creep_panel(self, ax) -> None:
        v = self.view
        self.x_max = float(v.curve_creepage[-1])
        ax.plot(v.curve_creepage, v.curve_coa, color=CURVE_COLOR, lw=2.4, label="creep curve (truth)")
        ax.plot([v.peak_creepage], [v.cof], "k*", ms=10, label=f"peak = true CoF {v.cof:.3f}")
        ax.axvline(v.macro_slip_creepage, color=POINT_COLOR, ls=":", lw=1.2, label="macro-slip limit")
        self.est_line = self._moving(ax.axhline(np.nan, color=ESTIMATE_COLOR, ls="--", lw=1.4, label="estimate"))
        self.window_dots, = ax.plot([], [], "o", color="0.35", ms=4.5, mfc="white", label="window means (measured)")
        self._moving(self.window_dots)
        self.tail, = ax.plot([], [], "-", color=POINT_COLOR, lw=1.2, alpha=0.6)
        self._moving(self.tail)
        self.point, = ax.plot([], [], "o", color=POINT_COLOR, ms=9, mec="k", label="operating point")
        self._moving(self.point)
        y_top = 1.75 * max(v.cof, min(v.max_estimate, 1.5 * v.cof))
        ax.set(xlim=(-0.04 * self.x_max, self.x_max), ylim=(0, y_top), xlabel="creepage (R Omega - v) / v [-]",
               ylabel="adhesion CoA [-]", title="Creep curve: where the driven wheelset operates")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize="small", ncol=3, framealpha=0.9)
        self.ax_creep = ax

    def _torque_panel(self, ax) -> None:
        v = self.view
        self.torque_line, = ax.plot([], [], color=TORQUE_COLOR, lw=0.7, label="torque M")
        self.dc_line, = ax.plot([], [], color="k", lw=1.0, ls="--", label="DC level Mc")
        self._moving(self.torque_line), self._moving(self.dc_line)
        lo, hi = v.torque_range_knm
        pad = 0.08 * (hi - lo) + 1e-3
        ax.set(xlim=(0, v.duration_s), ylim=(lo - pad, hi + 2.5 * pad), ylabel="torque [kN m]",
               title="Drive torque over the episode")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize="small", ncol=2, framealpha=0.9)
        for k in range(1, int(round(v.duration_s / v.window_s))):
            ax.axvline(k * v.window_s, color="0.6", lw=0.5)
        self.ax_torque = ax

    def _oscillation_panel(self, ax) -> None:
        self.torque_osc, = ax.plot([], [], color=TORQUE_COLOR, lw=1.3, label="torque")
        self.speed_osc, = ax.plot([], [], color=SPEED_COLOR, lw=1.3, label="wheelset speed Omega")
        self._moving(self.torque_osc), self._moving(self.speed_osc)
        ax.set(xlim=(-OSCILLATION_SPAN_S, 0), ylim=(-1.6, 2.4), xlabel="time before now [s]",
               ylabel="oscillation / amplitude", title="Modulation: the speed lags the torque (last second)")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize="small", ncol=2, framealpha=0.9)
        self.ax_osc = ax

    def _phase_panel(self, ax) -> None:
        v = self.view
        self.phase_dots, = ax.plot([], [], "o", color=TORQUE_COLOR, ms=4)
        self.phase_bars = LineCollection([], colors=TORQUE_COLOR, linewidths=0.9)
        ax.add_collection(self.phase_bars)
        self._moving(self.phase_dots), self._moving(self.phase_bars)
        lo, hi = v.phase_range_deg
        ax.set(xlim=(0, 1.03 * v.duration_s), ylim=(min(0.0, lo - 5), max(100.0, hi + 5)), xlabel="time [s]",
               ylabel="phase lag [deg]", title="Phase lag per window")
        ax.axhline(90.0, color="k", lw=0.6, ls=":")
        ax.grid(alpha=0.3)
        self.ax_phase = ax

    def _estimate_panel(self, ax) -> None:
        v = self.view
        ax.axhline(v.cof, color="k", lw=1.3, label="true CoF")
        self.est_steps, = ax.step([], [], where="post", color=ESTIMATE_COLOR, lw=1.8, label="estimate")
        self.coa_dots, = ax.plot([], [], "o", color="0.35", ms=3.5, mfc="white", label="measured CoA")
        self.bound_steps, = ax.step([], [], where="post", color=ESTIMATE_COLOR, lw=1.2, ls=":",
                                    label="lower bound in flight" if v.shows_lower_bound else None)
        self._moving(self.est_steps), self._moving(self.coa_dots), self._moving(self.bound_steps)
        ax.set(xlim=(0, 1.03 * v.duration_s), ylim=(0, 1.8 * max(v.cof, min(v.max_estimate, 2.0 * v.cof))),
               xlabel="time [s]", ylabel="CoF [-]", title="Estimate vs truth")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper center", fontsize="small", ncol=2 if v.shows_lower_bound else 3, framealpha=0.9,
                  handlelength=1.2, columnspacing=0.8)
        self.ax_est = ax

    # ------------------------------------------------------------------ one frame
    def draw(self, t: float, traces: Traces, windows: list[WindowPoint], estimate: float,
             lower_bound: float = math.nan) -> np.ndarray:
        """The panels at simulated time ``t`` (``traces`` up to ``t``, ``windows`` the completed ones; ``estimate``
        and ``lower_bound``: the current window's), (height, width, 3) uint8."""
        ts = traces.t
        if ts.size:
            s = traces.creepage
            self.point.set_data([min(s[-1], self.x_max)], [traces.coa[-1]])
            self.point.set_marker(">" if s[-1] > self.x_max else "o")
            tail = ts >= t - TAIL_S
            self.tail.set_data(np.minimum(s[tail], self.x_max), traces.coa[tail])
            self.torque_line.set_data(ts, traces.torque_knm)
            self.dc_line.set_data(ts, traces.dc_knm)
            recent = ts >= t - OSCILLATION_SPAN_S
            self.torque_osc.set_data(ts[recent] - t, traces.torque_osc[recent])
            self.speed_osc.set_data(ts[recent] - t, traces.speed_osc[recent])
        self.est_line.set_ydata([estimate, estimate] if math.isfinite(estimate) else [np.nan, np.nan])
        if windows:
            te = np.array([w.t_end_s for w in windows])
            lag = np.array([w.phase_lag_deg for w in windows])
            se = np.minimum([w.phase_lag_se_deg for w in windows], 45.0)
            self.window_dots.set_data(np.clip([w.creepage_measured for w in windows], -0.04 * self.x_max, self.x_max),
                                      [w.coa_measured for w in windows])
            self.phase_dots.set_data(te, lag)
            self.phase_bars.set_segments([[(x, y - e), (x, y + e)] for x, y, e in zip(te, lag, se)])
            self.coa_dots.set_data(te, [w.coa_measured for w in windows])
            for line, field, current in ((self.est_steps, "estimate", estimate),
                                         (self.bound_steps, "lower_bound", lower_bound)):
                steps = [(w.t_end_s - self.view.window_s, getattr(w, field)) for w in windows
                         if math.isfinite(getattr(w, field))]
                if steps and math.isfinite(current):  # each window's value from its start, the current one up to t
                    line.set_data([s[0] for s in steps] + [t], [s[1] for s in steps] + [current])
        canvas = self.fig.canvas
        canvas.restore_region(self.background)
        for a in self.animated:
            self.fig.draw_artist(a)
        return np.array(np.asarray(canvas.buffer_rgba())[: self.height, : self.width, :3])

    def close(self) -> None:
        plt.close(self.fig)
