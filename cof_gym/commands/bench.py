"""``cof-gym bench``: simulation speed of the wagon with and without the native callback, measured in
the same run (ratios are what to compare across machines), and agent steps per second of the
environment: one env (``gym.make``) and the batched vector env (``gym.make_vec``, 8 simulations on 1
and 2 threads)."""

from __future__ import annotations

import math
import os
from pathlib import Path
import time
from dataclasses import dataclass

import mujoco
import numpy as np

import cof_gym

from cof_gym.analysis.theory import PAPER_AMPLITUDE_NM, PAPER_FREQUENCY_HZ, PAPER_SPEED_M_S
from cof_gym.physics.creep import FAMILIES, CreepShape, OperatingConditions
from cof_gym.physics.creep_laws import PRESET_FAMILY
from cof_gym.physics.encoder import PulseEncoder
from cof_gym.physics.models import build_wagon
from cof_gym.physics.native.build import install_callback, native
from cof_gym.physics.simulation import DriveCommand, Scenario, Simulation, begin_window
from cof_gym.physics.track import draw_profile
from cof_gym.physics.vehicle import wagon_parameters
from cof_gym.validation import check_number


@dataclass(frozen=True)
class PhysicsBench:
    steps: int
    timestep_s: float
    native_steps_per_s: float
    bare_steps_per_s: float

    @property
    def realtime_factor(self) -> float:
        """Simulated seconds per wall second with the native callback, one thread."""
        return self.native_steps_per_s * self.timestep_s

    @property
    def ratio(self) -> float:
        return self.native_steps_per_s / self.bare_steps_per_s


def _best_rate(run, steps: int, repeats: int) -> float:
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        run(steps)
        best = min(best, time.perf_counter() - t0)
    return steps / best


def bench_physics(seconds: float = 5.0, repeats: int = 5, condition: str | CreepShape = "dry") -> PhysicsBench:
    """Wagon (laden, CoF 0.4, 10 m/s, 90 % of saturation torque, 345 Nm at 5 Hz, creep law
    ``condition``) stepped with ``mj_step(nstep)``; then the same model and state stepped bare,
    without the callback. The two are interleaved ``repeats`` times and the best of each is kept."""
    return _bench_laws({"law": condition}, seconds, repeats)["law"]


def bench_families(seconds: float = 5.0, repeats: int = 5) -> dict[str, PhysicsBench]:
    """:func:`bench_physics` for each creep-law family's example shape (one row per family), all
    interleaved in each repeat so that a passing load hits every family alike."""
    return _bench_laws({name: cls.example() for name, cls in FAMILIES.items()}, seconds, repeats)


def bench_track(seconds: float = 5.0, repeats: int = 5) -> dict[str, PhysicsBench]:
    """:func:`bench_physics` with the preset law on a level track and on a track of high vertical irregularity
    (a profile of ``ore_high``, :mod:`cof_gym.physics.track`), interleaved in each repeat."""
    rough = draw_profile("ore_high", np.random.default_rng(0))
    return _bench_laws({"level": "dry", "rough": "dry"}, seconds, repeats, options={"rough": {"track": rough}})


def bench_encoder(seconds: float = 5.0, repeats: int = 5) -> dict[str, PhysicsBench]:
    """:func:`bench_physics` with the preset law read by the continuous encoder and by a pulse encoder (100 pulses,
    a runout of 0.05 %, :mod:`cof_gym.physics.encoder`) through the rotation lock-in, interleaved in each repeat."""
    pulses = {"encoder": PulseEncoder(pulses_per_rev=100, runout=0.0005), "lock_in": "rotation"}
    return _bench_laws({"continuous": "dry", "pulses": "dry"}, seconds, repeats, options={"pulses": pulses})


def _bench_laws(conditions: dict[str, str | CreepShape], seconds: float, repeats: int,
                options: dict[str, dict] | None = None) -> dict[str, PhysicsBench]:
    """The wagon of :func:`bench_physics` under each named creep law, its :class:`Scenario` given the keyword
    arguments ``options[name]`` too (a track, an encoder)."""
    built = build_wagon(wagon_parameters("laden"))
    sims, bares = {}, {}
    for name, condition in conditions.items():
        op = OperatingConditions(cof=0.4, condition=condition, wheel_load_n=built.nominal_wheel_load_n,
                                 speed_m_s=PAPER_SPEED_M_S)
        sim = sims[name] = Simulation(built)
        sim.reset(Scenario(op, **(options or {}).get(name, {})))
        drive = DriveCommand(0.9 * built.saturation_torque_per_cof * 0.4, PAPER_AMPLITUDE_NM, PAPER_FREQUENCY_HZ)
        begin_window(sim.data.userdata, 0.0, drive, 0.5, 0.0)
        bare = bares[name] = mujoco.MjData(built.model)
        bare.qpos[:], bare.qvel[:] = sim.data.qpos, sim.data.qvel
    timestep = built.model.opt.timestep
    steps = int(seconds / timestep)
    if steps < 1:
        raise ValueError(f"seconds must be at least one physics step ({timestep:g} s), got {seconds!r}")
    callback = native().cofgym_passive
    native_best, bare_best = dict.fromkeys(conditions, 0.0), dict.fromkeys(conditions, 0.0)
    for _ in range(repeats):
        for name in conditions:
            install_callback()
            data = sims[name].data
            native_best[name] = max(native_best[name], _best_rate(lambda n: mujoco.mj_step(built.model, data, n), steps, 1))
            mujoco.set_mjcb_passive(None)
            try:
                bare_best[name] = max(bare_best[name], _best_rate(lambda n: mujoco.mj_step(built.model, bares[name], n),
                                                                  steps, 1))
            finally:
                mujoco.set_mjcb_passive(callback)
    return {name: PhysicsBench(steps, timestep, native_best[name], bare_best[name]) for name in conditions}


ENV_ID = cof_gym.WAGON_ENV_ID
# a fixed scenario, a long horizon and a DC torque kept below saturation: no episode ends in the timing
BENCH_SCENARIO = dict(cof=0.4, condition="dry", speed_m_s=20.0, load_case="laden", noise_level=0.5,
                      motor_lag_s=0.01)
BENCH_HORIZON = 10_000
VECTOR_SIMS = 8


@dataclass(frozen=True)
class AgentBench:
    single_steps_per_s: float
    vector_steps_per_s: dict[int, float]  # threads -> agent steps/s (all sub-envs)
    num_envs: int
    load_average: float  # 1-min load average when the timing started (other processes share the cores)

    @property
    def thread_ratio(self) -> float:
        """2-thread / 1-thread agent steps per second of the vector env."""
        return self.vector_steps_per_s[2] / self.vector_steps_per_s[1]


def _bench_actions(space) -> np.ndarray:
    """Random actions, stop forced off and the DC torque held in its lowest quarter (no macro-slip)."""
    a = space.sample()
    a[..., 0] = -1.0 + 0.25 * (a[..., 0] + 1.0)
    a[..., 4] = -1.0
    return a


def _make_single():
    import gymnasium as gym

    import cof_gym  # noqa: F401  (registers the ids)

    env = gym.make(ENV_ID, max_windows=BENCH_HORIZON, max_episode_steps=BENCH_HORIZON, **BENCH_SCENARIO)
    env.reset(seed=0)
    env.action_space.seed(0)
    return env


def _make_vector(num_envs: int, num_threads: int):
    import gymnasium as gym

    import cof_gym  # noqa: F401

    env = gym.make_vec(ENV_ID, num_envs=num_envs, vectorization_mode="vector_entry_point", num_threads=num_threads,
                       max_windows=BENCH_HORIZON, max_episode_steps=BENCH_HORIZON, **BENCH_SCENARIO)
    env.reset(seed=0)
    env.action_space.seed(0)
    return env


def _rate(env, steps: int, per_step: int) -> float:
    """Agent steps per second over ``steps`` calls of ``env.step`` (``per_step`` agent steps each)."""
    actions = [_bench_actions(env.action_space) for _ in range(steps)]
    t0 = time.perf_counter()
    for a in actions:
        _, _, terminated, truncated, _ = env.step(a)
        if np.any(terminated) or np.any(truncated):
            raise RuntimeError("an episode ended during the agent-step timing; the bench scenario must not end")
    return steps * per_step / (time.perf_counter() - t0)


def bench_agent(seconds: float = 5.0, num_envs: int = VECTOR_SIMS, repeats: int = 3) -> AgentBench:
    """Agent steps (windows) per second: one env; the vector env with ``num_envs`` simulations on 1 and
    2 threads. Each is timed ``repeats`` times, interleaved (so that a passing load hits all alike),
    for about ``seconds`` / 2 wall seconds in total per configuration; the best is kept."""
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    single = _make_single()
    vectors = {n: _make_vector(num_envs, n) for n in (1, 2)}
    # warm-up, and a rough rate to size the timed runs
    rough_single = _rate(single, 3, 1)
    rough_vector = _rate(vectors[1], 2, num_envs)
    budget = max(seconds, 1.0) / 2.0 / repeats
    single_steps = max(5, int(budget * rough_single))
    vector_steps = max(3, int(budget * rough_vector / num_envs))
    best_single, best_vector = 0.0, {1: 0.0, 2: 0.0}
    for _ in range(repeats):
        best_single = max(best_single, _rate(single, single_steps, 1))
        for n, env in vectors.items():
            best_vector[n] = max(best_vector[n], _rate(env, vector_steps, num_envs))
    single.close()
    for env in vectors.values():
        env.close()
    return AgentBench(best_single, best_vector, num_envs, load)


def main(seconds: float = 5.0, markdown: str | None = None) -> None:
    """Print the speed table; with ``markdown``, also write it there as a Markdown table (the README's
    speed section is copied from that file by ``experiments/readme_results.py``)."""
    check_number("seconds", seconds, 0.0, math.inf, low_open=True, unit=" s")
    from rich.console import Console
    from rich.table import Table

    families = bench_families(seconds)
    pb = families[PRESET_FAMILY]  # the wagon as the presets drive it
    rows = [
        ("wagon physics steps/s, native callback", f"{pb.native_steps_per_s:,.0f}"),
        ("wagon physics steps/s, bare mj_step (no callback)", f"{pb.bare_steps_per_s:,.0f}"),
        ("simulated s per wall s (dt = %.4g s)" % pb.timestep_s, f"{pb.realtime_factor:,.0f}"),
        *((f"ratio native / bare, creep law {name} (target >= 0.8)", f"{fb.ratio:.3f}") for name, fb in families.items()),
    ]
    track = bench_track(seconds)
    rows.append(("ratio native on a track of high vertical irregularity / level track",
                 f"{track['rough'].native_steps_per_s / track['level'].native_steps_per_s:.3f}"))
    encoder = bench_encoder(seconds)
    rows.append(("ratio native with a pulse encoder read by the rotation lock-in / continuous encoder",
                 f"{encoder['pulses'].native_steps_per_s / encoder['continuous'].native_steps_per_s:.3f}"))
    ab = bench_agent(seconds)
    agent_rows = [
        ("agent steps/s, one env (gym.make, 1 s windows)", f"{ab.single_steps_per_s:,.1f}"),
        *((f"agent steps/s, vector env ({ab.num_envs} sims, {n} thread{'s' if n > 1 else ''})", f"{rate:,.1f}")
          for n, rate in ab.vector_steps_per_s.items()),
        ("ratio vector 2 threads / 1 thread (target >= 1.7)", f"{ab.thread_ratio:.2f}"),
        ("CPUs / 1-min load average at start", f"{os.cpu_count()} / {ab.load_average:.2f}"),
    ]
    title = f"cof-gym bench (mujoco {mujoco.__version__}, one thread, --seconds {seconds:g})"
    table = Table(title=title)
    table.add_column("measure")
    table.add_column("value", justify="right")
    for row in rows:
        table.add_row(*row)
    table.add_section()
    for row in agent_rows:
        table.add_row(*row)
    Console().print(table)
    if markdown:
        lines = [f"# {title}", "", "| measure | value |", "|---|---|", *(f"| {a} | {b} |" for a, b in rows + agent_rows)]
        Path(markdown).parent.mkdir(parents=True, exist_ok=True)
        Path(markdown).write_text("\n".join(lines) + "\n")
