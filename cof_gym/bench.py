"""``cof-gym bench``: simulation speed of the wagon with and without the native callback, measured in
the same run (ratios are what to compare across machines)."""

from __future__ import annotations

import time
from dataclasses import dataclass

import mujoco

from cof_gym.physics.creep import OperatingConditions
from cof_gym.physics.models import build_wagon
from cof_gym.physics.native.build import install_callback, native
from cof_gym.physics.simulation import DriveCommand, Scenario, Simulation, begin_window
from cof_gym.physics.vehicle import wagon_parameters


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


def bench_physics(seconds: float = 5.0, repeats: int = 5) -> PhysicsBench:
    """Wagon (laden, CoF 0.4, 10 m/s, 90 % of saturation torque, 345 Nm at 5 Hz) stepped with
    ``mj_step(nstep)``; then the same model and state stepped bare, without the callback. The two are
    interleaved ``repeats`` times and the best of each is kept."""
    built = build_wagon(wagon_parameters("laden"))
    op = OperatingConditions(cof=0.4, wheel_load_n=built.nominal_wheel_load_n, speed_m_s=10.0)
    sim = Simulation(built)
    sim.reset(Scenario(op))
    begin_window(sim.data.userdata, 0.0, DriveCommand(0.9 * built.saturation_torque_per_cof * 0.4, 345.0, 5.0), 0.5, 0.0)
    steps = int(seconds / sim.timestep)
    bare = mujoco.MjData(built.model)
    bare.qpos[:], bare.qvel[:] = sim.data.qpos, sim.data.qvel
    callback = native().cofgym_passive
    native_best, bare_best = 0.0, 0.0
    for _ in range(repeats):
        install_callback()
        native_best = max(native_best, _best_rate(lambda n: mujoco.mj_step(built.model, sim.data, n), steps, 1))
        mujoco.set_mjcb_passive(None)
        try:
            bare_best = max(bare_best, _best_rate(lambda n: mujoco.mj_step(built.model, bare, n), steps, 1))
        finally:
            mujoco.set_mjcb_passive(callback)
    return PhysicsBench(steps, sim.timestep, native_best, bare_best)


def main(seconds: float = 5.0) -> None:
    from rich.console import Console
    from rich.table import Table

    pb = bench_physics(seconds)
    table = Table(title=f"cof-gym bench (mujoco {mujoco.__version__}, one thread)")
    table.add_column("measure")
    table.add_column("value", justify="right")
    table.add_row("wagon physics steps/s, native callback", f"{pb.native_steps_per_s:,.0f}")
    table.add_row("wagon physics steps/s, bare mj_step (no callback)", f"{pb.bare_steps_per_s:,.0f}")
    table.add_row("simulated s per wall s (dt = %.4g s)" % pb.timestep_s, f"{pb.realtime_factor:,.0f}")
    table.add_row("ratio native / bare (target >= 0.8)", f"{pb.ratio:.3f}")
    Console().print(table)
