"""``cof-gym watch``: a video of one agent's episode.

The episode is played exactly as ``cof-gym evaluate`` plays it (:func:`~cof_gym.commands.evaluate_episodes.run_episode`
on ``gym.make(ENV)`` with that seed); a wrapper records each window's drive and the physics state after it.
The video then replays the same windows on a second simulation of the same model, stepping each window in
short chunks to render ``fps`` frames per video second (the env itself steps a window in one call), and
checks that every replayed window ends in the recorded state, bit for bit.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np

import cof_gym
from cof_gym.agents import registry
from cof_gym.agents.base import own_env_options
from cof_gym.commands.args import MAX_SEED, UsageError, check_output_file, float_in_range, int_in_range, seed_int
from cof_gym.commands.evaluate import suite_env
from cof_gym.commands.suites import MAX_EPISODES, Suite, SuiteError, make_suite, read_measured_curve
from cof_gym.envs.torque_interrogation import make_kwargs
from cof_gym.physics.creep import creep_curve
from cof_gym.physics.native import layout
from cof_gym.physics.simulation import DriveCommand, Simulation, begin_window, dc_torque_at

DESCRIPTION = """\
Play one episode of an agent (the episode cof-gym evaluate plays for that seed) and write a video of it:
the wagon on the track, the camera following the driven wheelset, beside the creep curve with the
operating point moving along it, the torque and wheelset-speed traces, the phase lag of each window and
the estimate against the true CoF (and the in-flight lower bound of an agent that reports one, the
learned interrogator). MP4 needs imageio-ffmpeg, GIF pillow. Rendered offscreen (EGL, or
MUJOCO_GL=osmesa)."""

EXTENSIONS = (".mp4", ".gif")
DEFAULT_WIDTH = {".mp4": 1280, ".gif": 960}  # frame width, pixels (height 9/16 of it)
DEFAULT_FPS = {".mp4": 25, ".gif": 12}
MIN_SPEED, MAX_SPEED = 0.05, 10.0  # --speed: simulated seconds per video second
SAMPLE_STEPS_S = 0.002  # the traces are sampled every 2 ms of simulated time (25 samples per 20 Hz period)
HOLD_S = 2.5  # the last frame is held this long (video seconds)
STATE_SPEC = mujoco.mjtState.mjSTATE_INTEGRATION  # time, qpos, qvel, act, userdata, ...
_U = layout.OFFSETS
DRIVEN = "orange spokes: the driven wheelset"


# ---------------------------------------------------------------------------- checks
def check_video_path(path: Path, flag: str = "--out") -> Path:
    """A video file that can be written: a known extension, not a directory, in a writable folder on disk
    (created when missing, so its nearest existing ancestor must be writable: :func:`check_output_file`).
    Creates nothing."""
    path = Path(path)
    if path.is_dir():
        raise UsageError(flag, f"{path} is a directory; give a file name ending in {' or '.join(EXTENSIONS)}")
    if path.suffix.lower() not in EXTENSIONS:
        raise UsageError(flag, f"{path}: the extension must be one of {', '.join(EXTENSIONS)}")
    check_output_file(path, flag)  # writable, below no file, on disk
    return path


def check_writer(suffix: str) -> None:
    """The library that writes ``suffix`` is installed (UsageError naming what to install)."""
    try:
        import imageio  # noqa: F401
    except ImportError:
        raise UsageError("--out", "writing a video needs imageio: pip install imageio imageio-ffmpeg") from None
    if suffix == ".mp4":
        try:
            import imageio_ffmpeg

            imageio_ffmpeg.get_ffmpeg_exe()
        except (ImportError, RuntimeError):
            raise UsageError("--out", "MP4 needs imageio-ffmpeg (pip install imageio-ffmpeg); or write a .gif") from None
    else:
        try:
            import PIL  # noqa: F401
        except ImportError:
            raise UsageError("--out", "GIF needs pillow (pip install pillow); or write an .mp4") from None


@dataclass(frozen=True)
class WatchRequest:
    """A checked command line."""

    agent: str
    oracle: bool
    env_id: str
    seed: int
    out: Path
    fps: int
    width: int
    speed: float  # simulated seconds per video second
    options: dict = field(default_factory=dict)  # reset options over the seed's draws (a suite's, --creep-table's)
    env_kwargs: dict = field(default_factory=dict)  # the env's arguments (a suite's)


def prepare(args: argparse.Namespace) -> WatchRequest:
    """Check the whole command line before anything is simulated or written (UsageError naming the flag)."""
    spec = args.agent.strip()
    try:
        entry, argument = registry.parse(spec)
    except registry.AgentSpecError as e:
        raise UsageError("--agent", str(e)) from None
    try:  # the checks evaluate makes (a model's zip, its statistics and its training record)
        registry.check_argument(entry, argument)
    except ValueError as e:
        raise UsageError("--agent", f"{spec}: {e}") from None
    if args.env is not None and args.env not in cof_gym.ENV_IDS:
        raise UsageError("--env", f"unknown env {args.env!r}; allowed: {', '.join(cof_gym.ENV_IDS)}")
    out = check_video_path(Path(args.out))
    suffix = out.suffix.lower()
    check_writer(suffix)
    env_id, env_kwargs, seed, options = _suite_episode(args)
    if args.creep_table is not None:
        try:
            curve = read_measured_curve(Path(args.creep_table))
        except ValueError as e:
            raise UsageError("--creep-table", str(e)) from None
        if clash := sorted(set(curve) & (set(options) | set(env_kwargs))):
            raise UsageError("--creep-table", f"it fixes {clash}, which episode {args.episode or 0} of suite "
                                              f"{args.suite} fixes too; play it on a suite that leaves them to the draws")
        options = {**options, **curve}
    if args.suite is not None:  # the env arguments and the episode's options, as evaluate checks a suite's
        try:
            suite_env(Suite(str(args.suite), env_id, env_kwargs, [(seed, options)]), first_episode=args.episode or 0
                      ).close()
        except SuiteError as e:
            raise UsageError("--suite", str(e)) from None
    return WatchRequest(spec, entry.oracle, env_id, seed, out,
                        args.fps if args.fps is not None else DEFAULT_FPS[suffix],
                        args.width if args.width is not None else DEFAULT_WIDTH[suffix], args.speed, options,
                        env_kwargs)


def _suite_episode(args: argparse.Namespace) -> tuple[str, dict, int, dict]:
    """The env id, env arguments, seed and reset options of the episode to play: ``--suite``'s episode ``--episode``
    as ``cof-gym evaluate --suite`` plays it (``--seed`` the default and paper suites' first), or ``--env`` with
    ``--seed`` (UsageError naming the flag)."""
    if args.suite is None:
        if args.episode is not None:
            raise UsageError("--episode", "picks an episode of --suite; give --suite too (or --seed alone)")
        return args.env or cof_gym.WAGON_ENV_ID, {}, args.seed, {}
    if args.env is not None:
        raise UsageError("--env", f"suite {args.suite} names its env id; give --suite or --env, not both")
    episode = args.episode or 0
    try:
        suite = make_suite(args.suite, episode + 1, args.seed)
    except SuiteError as e:
        raise UsageError("--suite", str(e)) from None
    if episode >= len(suite.episodes):
        raise UsageError("--episode", f"suite {args.suite} has {len(suite.episodes)} episodes (0 to "
                                      f"{len(suite.episodes) - 1}), got {episode}")
    seed, options = suite.episodes[episode]
    if seed > MAX_SEED:
        raise UsageError("--seed", f"episode {episode}'s seed {seed} is beyond {MAX_SEED}")
    return suite.env_id, dict(suite.env_kwargs), seed, dict(options)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--agent", default="model-based", metavar="AGENT",
                        help=f"the agent: {registry.describe()}")
    parser.add_argument("--seed", type=seed_int, default=0,
                        help="episode seed (the scenario cof-gym evaluate plays as its episode with this seed); with "
                             "--suite default or paper, the suite's first seed, as evaluate --seed")
    parser.add_argument("--env", default=None, metavar="ENV_ID",
                        help=f"environment id: {', '.join(cof_gym.ENV_IDS)} (default: {cof_gym.WAGON_ENV_ID})")
    parser.add_argument("--suite", default=None, metavar="SUITE",
                        help="play an episode of a suite as cof-gym evaluate --suite plays it (its env id, env "
                             "arguments, seed and scenario): 'default', 'paper', 'in-service' or a JSON suite file")
    parser.add_argument("--episode", type=int_in_range(0, MAX_EPISODES - 1), default=None, metavar="K",
                        help="with --suite: the episode's index in the suite, as in evaluate's episodes.csv "
                             "(default: 0)")
    parser.add_argument("--out", default="episode.mp4", metavar="FILE", help="the video, .mp4 or .gif")
    parser.add_argument("--creep-table", default=None, metavar="CSV",
                        help="a measured creep curve (rows of creepage and CoA), played at its own CoF, as cof-gym "
                             "evaluate --creep-table plays it")
    parser.add_argument("--fps", type=int_in_range(1, 60), default=None,
                        help="frames per video second (default: 25 for MP4, 12 for GIF)")
    parser.add_argument("--width", type=int_in_range(320, 3840), default=None,
                        help="frame width in pixels, height 9/16 of it (default: 1280 for MP4, 960 for GIF)")
    parser.add_argument("--speed", type=float_in_range(MIN_SPEED, MAX_SPEED, low_inclusive=True), default=1.0,
                        help=f"simulated seconds per video second, in [{MIN_SPEED:g}, {MAX_SPEED:g}] "
                             "(0.5: slow motion)")


# ---------------------------------------------------------------------------- the scored episode
@dataclass(frozen=True)
class WindowRecord:
    """One window of the scored episode: the drive the env ran and what it returned."""

    drive: DriveCommand
    ran: bool  # False for a stop (no window is run)
    state: np.ndarray  # the physics state after the window (STATE_SPEC)
    estimate: float  # the estimate reported with this window's drive (nan: the reset window)
    measurement: dict[str, float]
    lower_bound: float = math.nan  # the agent's in-flight lower bound when it chose this drive (nan: none)


class Recorder(gym.Wrapper):
    """Records each window of the wrapped env: what it drove and the state it ended in, and the lower bound the
    agent held when it chose the drive (:class:`BoundReader` sets it). Changes nothing."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        self.windows: list[WindowRecord] = []
        self.final_info: dict[str, Any] = {}
        self.next_lower_bound = math.nan

    def _record(self, ran: bool, estimate: float, info: dict) -> None:
        core = self.env.unwrapped
        sim = core._sim  # the simulation that ran the window (read only)
        state = np.empty(mujoco.mj_stateSize(sim.model, STATE_SPEC))
        mujoco.mj_getState(sim.model, sim.data, state, STATE_SPEC)
        self.windows.append(WindowRecord(core.episode.drive, ran, state, estimate, dict(info["measurement"]),
                                         self.next_lower_bound))
        self.final_info = info

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        self.windows, self.next_lower_bound = [], math.nan
        self._record(True, math.nan, info)
        return obs, info

    def step(self, action):
        t0 = self.env.unwrapped._sim.data.time
        out = self.env.step(action)
        info = out[-1]
        self._record(self.env.unwrapped._sim.data.time != t0, float(info["cof_estimate"]), info)
        return out


class BoundReader:
    """Plays ``agent`` as it is and, after each action, hands the recorder the in-flight lower bound the agent
    reports (``in_flight_lower_bound()``, the learned interrogator's; nan for an agent without one)."""

    def __init__(self, agent, recorder: Recorder) -> None:
        self.agent, self.recorder = agent, recorder
        self.name, self.oracle = agent.name, getattr(agent, "oracle", False)

    def reset(self, observation, info) -> None:
        self.agent.reset(observation, info)

    def act(self, observation, info):
        action = self.agent.act(observation, info)
        bound = getattr(self.agent, "in_flight_lower_bound", lambda: None)()
        self.recorder.next_lower_bound = math.nan if bound is None else float(bound)
        return action

    def __getattr__(self, name: str):  # the rest is the agent's (its interval, its close)
        return getattr(self.agent, name)


def play(request: WatchRequest):
    """Play the scored episode: (record, recorder, env). The caller closes the env."""
    from cof_gym.commands.evaluate_episodes import AgentError, run_episode

    env_kwargs = make_kwargs(request.env_kwargs)
    env = Recorder(gym.make(request.env_id, **env_kwargs))
    try:
        agent = registry.make_agent(request.agent, env)
    except (FileNotFoundError, ValueError, OSError) as e:
        env.close()
        raise UsageError("--agent", f"{request.agent}: {e}") from None
    options = own_env_options(agent)  # an excitation of its own (two tones)
    if options:
        env.close()
        env = Recorder(gym.make(request.env_id, **{**env_kwargs, **options}))
    try:
        record = run_episode(env, BoundReader(agent, env), request.seed, request.options, 0, oracle=request.oracle)
    except AgentError as e:
        env.close()
        raise UsageError("--agent", str(e)) from None
    finally:
        close = getattr(agent, "close", None)
        if callable(close):
            close()
    return record, env


# ---------------------------------------------------------------------------- the replay
def _result_line(record, sep: str = ", ") -> str:
    """The episode's score in words (``sep`` between the estimate and the error)."""
    signed = record.estimate / record.cof - 1.0
    line = f"estimate {record.estimate:.4f} vs true CoF {record.cof:.4f}{sep}error {100 * signed:+.1f} %"
    if record.macro_slip:
        line += ", macro-slip"
    elif not record.scored:
        line += ", not scored"
    return line


@dataclass
class Replay:
    """The recorded windows replayed in chunks: high-rate samples and one configuration per frame."""

    samples: dict[str, np.ndarray]  # t, torque_nm, dc_nm, omega, creepage, coa, window (index)
    frame_t: np.ndarray  # simulated time of each frame
    frame_qpos: np.ndarray  # (frames, nq)
    frame_sample: np.ndarray  # samples up to (excluding) this index belong to the frame
    frame_window: np.ndarray  # the window each frame is in
    window_end_s: np.ndarray


def replay(env, windows: list[WindowRecord], frame_dt_s: float) -> Replay:
    """Step the scored episode's windows again on a fresh simulation of the same model and scenario,
    in chunks of ``SAMPLE_STEPS_S``, and check every window ends in the recorded state, bit for bit."""
    core = env.unwrapped
    episode, task = core.episode, core.task
    sim = Simulation(episode.built)
    sim.reset(episode.physics)
    model, data, ud = sim.model, sim.data, sim.data.userdata
    dt = sim.timestep
    chunk = max(1, round(SAMPLE_STEPS_S / dt))
    nstep = int(round(task.window_s / dt))
    keys = ("t", "torque_nm", "dc_nm", "omega", "creepage", "coa", "window")
    n_samples = len(windows) * -(-nstep // chunk)
    samples = {k: np.empty(n_samples) for k in keys}
    frame_t, frame_qpos, frame_sample, frame_window, window_end = [], [], [], [], []
    state = np.empty(mujoco.mj_stateSize(model, STATE_SPEC))
    i, next_frame = 0, 0.0
    for k, w in enumerate(windows):
        begin_window(ud, data.time, w.drive, task.ramp_s, task.settle_s)
        done = 0
        while done < nstep:
            n = min(chunk, nstep - done)
            mujoco.mj_step(model, data, n)
            done += n
            for key, value in zip(keys, (data.time, ud[_U["LAST_TORQUE"]], dc_torque_at(ud, data.time),
                                         ud[_U["LAST_OMEGA"]], ud[_U["LAST_CREEPAGE"]], ud[_U["LAST_COA"]], k)):
                samples[key][i] = value
            i += 1
            if data.time + 1e-9 >= next_frame:
                frame_t.append(data.time)
                frame_qpos.append(data.qpos.copy())
                frame_sample.append(i)
                frame_window.append(k)
                next_frame += frame_dt_s
        mujoco.mj_getState(model, data, state, STATE_SPEC)
        if not np.array_equal(state, w.state):
            raise RuntimeError(f"the replay left the scored episode in window {k} (t = {data.time:.3f} s)")
        window_end.append(data.time)
    return Replay({k: v[:i] for k, v in samples.items()}, np.array(frame_t), np.array(frame_qpos),
                  np.array(frame_sample), np.array(frame_window), np.array(window_end))


# ---------------------------------------------------------------------------- the video
def _episode_view(env, windows: list[WindowRecord], rep: Replay):
    from cof_gym.commands.watch_frames import EpisodeView

    core = env.unwrapped
    truth, task = core.episode.truth, core.task
    limit = task.macro_slip.limit(truth.peak_creepage)
    s = np.linspace(0.0, 1.25 * limit, 400)
    coa, _ = creep_curve(s, core.episode.physics.op)
    lags = [w.measurement["phase_lag_deg"] for w in windows]
    torque = np.concatenate([rep.samples["torque_nm"], rep.samples["dc_nm"]]) / 1e3
    return EpisodeView(
        cof=truth.cof, peak_creepage=truth.peak_creepage, macro_slip_creepage=limit, curve_creepage=s,
        curve_coa=np.asarray(coa), duration_s=float(rep.window_end_s[-1]), window_s=task.window_s,
        torque_range_knm=(float(min(torque.min(), 0.0)), float(torque.max())),
        max_estimate=max((w.estimate for w in windows if math.isfinite(w.estimate)), default=truth.cof),
        phase_range_deg=(min(lags), max(lags)),
        shows_lower_bound=any(math.isfinite(w.lower_bound) for w in windows),
    )


def _traces(rep: Replay, windows: list[WindowRecord], dt_sample: float):
    """The samples as the panels draw them, oscillations normalised per window (one modulation period)."""
    from cof_gym.commands.watch_frames import Traces, oscillation

    s = rep.samples
    torque_osc, speed_osc = np.zeros_like(s["t"]), np.zeros_like(s["t"])
    for k, w in enumerate(windows):
        sel = s["window"] == k
        period = round(1.0 / (w.drive.frequency_hz * dt_sample))
        torque_osc[sel] = oscillation(s["torque_nm"][sel], period)
        speed_osc[sel] = oscillation(s["omega"][sel], period)
    return Traces(s["t"], s["torque_nm"] / 1e3, s["dc_nm"] / 1e3, s["creepage"], s["coa"], torque_osc, speed_osc)


def frame_s(path: Path, fps: int) -> float:
    """How long a frame shows (s): 1 / fps, in a GIF rounded to the format's hundredths of a second (at 12 fps a GIF
    frame shows 0.08 s, not 0.0833: the video then runs 4 % faster than 12 fps would)."""
    return 1.0 / fps if path.suffix.lower() == ".mp4" else max(round(100.0 / fps), 1) / 100.0


def _open_writer(path: Path, fps: int):
    import imageio.v2 as imageio

    if path.suffix.lower() == ".mp4":
        return imageio.get_writer(path, format="FFMPEG", mode="I", fps=fps, codec="libx264", quality=7,
                                  pixelformat="yuv420p", macro_block_size=16)
    return imageio.get_writer(path, format="GIF", mode="I", duration=1000.0 * frame_s(path, fps), loop=0)


def _window_point(w: WindowRecord, t_end_s: float):
    """A completed window as the panels plot it."""
    from cof_gym.commands.watch_frames import WindowPoint

    return WindowPoint(t_end_s, *(w.measurement[m] for m in ("phase_lag_deg", "phase_lag_se_deg", "coa_measured",
                                                             "creepage_measured")), w.estimate, w.lower_bound)


def _caption(request: WatchRequest, k: int, n: int, w: WindowRecord, t: float, wagon: bool) -> str:
    """The scene's caption: agent, time, window and its drive."""
    d = w.drive
    head = f"{request.agent}  seed {request.seed}  t = {t:5.2f} s"
    if k == 0:
        return (f"{head}\nbaseline window: no DC torque\nM0 {d.amplitude_nm / 1e3:.2f} kN m at {d.frequency_hz:.1f} Hz"
                + (f"\n{DRIVEN}" if wagon else ""))
    return (f"{head}\nwindow {k}/{n}  estimate {w.estimate:.4f}\n"
            f"Mc {d.dc_torque_nm / 1e3:.2f} kN m  M0 {d.amplitude_nm / 1e3:.2f} kN m at {d.frequency_hz:.1f} Hz"
            + (f"\n{DRIVEN}" if wagon else ""))


def render_video(request: WatchRequest, env, record, path: Path, max_frames: int | None = None) -> dict[str, Any]:
    """Replay the recorded windows and write the video to ``path``; returns facts about it (frames, size,
    render time, the last frame). ``max_frames`` stops early (tests)."""
    from cof_gym.commands.watch_frames import Caption, Panels, SceneCamera, Traces

    windows = [w for w in env.windows if w.ran]
    rep = replay(env, windows, request.speed / request.fps)
    built = env.unwrapped.episode.built
    model = built.model
    width, height = 16 * round(request.width / 16), 16 * round(request.width * 9 / 16 / 16)
    scene_w = 16 * round(width / 2 / 16)
    translucent = tuple(i for i in range(model.nbody) if model.body(i).name.startswith("bogie_")
                        and not model.body(i).name.endswith(("wheelset", "axlebox")))
    camera = SceneCamera(model, scene_w, height, built.contacts[built.measured_contact].wheel_body, translucent)
    panels = Panels(_episode_view(env, windows, rep), width - scene_w, height)
    caption = Caption(height)
    traces = _traces(rep, windows, SAMPLE_STEPS_S)
    n_frames = len(rep.frame_t) if max_frames is None else min(max_frames, len(rep.frame_t))
    hold = max(1, round(HOLD_S * request.fps)) if max_frames is None else 0
    writer = _open_writer(path, request.fps)
    t_render, frame = 0.0, None
    try:
        for f in range(n_frames):
            t0 = time.perf_counter()
            k, t, upto = rep.frame_window[f], rep.frame_t[f], rep.frame_sample[f]
            last = f == len(rep.frame_t) - 1
            done = [_window_point(windows[j], float(rep.window_end_s[j])) for j in range(k + 1 if last else k)]
            sofar = Traces(*(getattr(traces, name)[:upto] for name in Traces.__dataclass_fields__))
            scene = caption.draw(camera.render(rep.frame_qpos[f]), _caption(request, k, len(windows) - 1, windows[k], t, built.kind == "wagon"),
                                 _result_line(record, "\n") if last else "")
            frame = np.concatenate([scene, panels.draw(t, sofar, done, windows[k].estimate, windows[k].lower_bound)], axis=1)
            writer.append_data(frame)
            t_render += time.perf_counter() - t0
        for _ in range(hold if frame is not None else 0):
            writer.append_data(frame)
    finally:
        writer.close()
        camera.close()
        panels.close()
    frames = n_frames + (hold if frame is not None else 0)
    return {"frames": frames, "width": width, "height": height, "video_s": frames * frame_s(path, request.fps),
            "simulated_s": float(rep.window_end_s[-1]), "render_s_per_frame": t_render / max(n_frames, 1),
            "last_frame": frame}


def watch(request: WatchRequest, max_frames: int | None = None) -> dict[str, Any]:
    """Play the episode and write the video (through a temporary file renamed onto ``out``)."""
    record, env = play(request)
    out = request.out
    created = [d for d in reversed(out.resolve().parents) if not d.exists()]
    for d in created:
        d.mkdir()
    tmp = out.with_name(f".{out.stem}.partial-{os.getpid()}{out.suffix}")
    try:
        facts = render_video(request, env, record, tmp, max_frames)
        os.replace(tmp, out)
    except BaseException:
        tmp.unlink(missing_ok=True)
        for d in reversed(created):
            d.rmdir()
        raise
    finally:
        env.close()
    facts["record"] = record
    facts["bytes"] = out.stat().st_size
    return facts


def gl_error() -> str | None:
    """Why no offscreen OpenGL context can start (None: one can), with MUJOCO_GL as set."""
    try:
        ctx = mujoco.GLContext(16, 16)
        ctx.make_current()
        ctx.free()
    except Exception as e:  # noqa: BLE001 - any backend failure means the same to the user
        backend = os.environ.get("MUJOCO_GL", "glfw")
        return (f"no OpenGL context (MUJOCO_GL={backend}): {' '.join(str(e).split())}; install libegl1 libegl-mesa0 "
                "libgl1-mesa-dri (EGL) or libosmesa6 and set MUJOCO_GL=osmesa")
    return None


def run(args: argparse.Namespace) -> int:
    request = prepare(args)
    error = gl_error()
    if error is not None:
        print(f"cof-gym watch: error: {error}", file=sys.stderr)
        return 1
    t0 = time.perf_counter()
    facts = watch(request)
    print(f"{request.out}: {facts['frames']} frames of {facts['width']}x{facts['height']} at {request.fps} fps "
          f"({facts['video_s']:.1f} s of video, {facts['simulated_s']:.1f} s simulated), "
          f"{facts['bytes'] / 1e6:.1f} MB in {time.perf_counter() - t0:.1f} s; {_result_line(facts['record'])}")
    return 0
