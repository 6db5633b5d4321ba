"""Torque interrogation of the wheel-rail friction as a Gymnasium environment."""

from __future__ import annotations

import importlib
import os
import sys
from dataclasses import asdict, fields, replace
from functools import lru_cache
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np
from gymnasium.utils import EzPickle

from cof_gym.envs.reward import RewardWeights, discomfort, relative_error, reward_terms, slip_cost
from cof_gym.envs.scenarios import SCENARIO_KEYS, EpisodeScenario, ScenarioRanges, draw_scenario
from cof_gym.envs.spaces import (
    DecodedAction, MotorLimits, action_space, check_action, decode_action, encode_observation, observation_space,
)
from cof_gym.physics.creep import OperatingConditions, creep_peak
from cof_gym.physics.models import DEFAULT_TIMESTEP_S, BuiltModel, build_half_wheelset, build_wagon
from cof_gym.physics.simulation import DriveCommand, SimulationDiverged, Scenario, Simulation, WindowMeasurement
from cof_gym.physics.vehicle import HalfWheelsetParameters, wagon_parameters

VEHICLES = ("wagon", "half_wheelset")
DEFAULT_MAX_WINDOWS = 30
SHAPING_GAMMA = 0.95  # discount the shaping potential assumes (cof_gym/agents/hyperparams/ppo.yml's gamma)
MAX_DC_TORQUE_PER_LADEN_SATURATION = 0.7 / 0.6  # the drive reaches saturation up to CoF ~0.7


def display_available() -> bool:
    """Whether an on-screen viewer can open (always assumed off Linux)."""
    return not sys.platform.startswith("linux") or bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


@lru_cache(maxsize=16)
def built_model(vehicle: str, load_case: str, timestep: float, counter_torque: bool) -> BuiltModel:
    """Models are built once per process and shared (read-only) by every env."""
    if vehicle == "wagon":
        return build_wagon(wagon_parameters(load_case), timestep=timestep, counter_torque=counter_torque)
    return build_half_wheelset(HalfWheelsetParameters(), timestep=timestep)


def window_diverged(m: WindowMeasurement, bad_qacc: bool, state_finite: bool) -> bool:
    """Whether a window diverged: a bad-acceleration warning, a non-finite state or measurement."""
    values = np.array([getattr(m, f.name) for f in fields(m)], dtype=np.float64)
    return bool(bad_qacc or not state_finite or not np.isfinite(values).all())


class TorqueInterrogationEnv(gym.Env, EzPickle):
    r"""Measure the wheel-rail coefficient of friction (CoF) by torque modulation.

    A MuJoCo wagon (or the paper's half wheelset) runs at a cruise-controlled speed; the agent sets the
    traction torque of the driven wheelset, ``M = Mc + M0 sin(2 pi f t)``, window by window, reads
    the phase lag of the wheelset speed, the measured adhesion (CoA) and comfort, and reports a CoF
    estimate. One step is one measurement window (``window_s`` of simulated time, one native
    ``mj_step`` call).

    ## Action Space
    ``Box(-1, 1, (5,), float32)``, rescaled inside (out-of-range values are clipped; NaN/inf raise
    ``ValueError`` naming the component):

    | Num | Action        | Rescaled to                                          | Unit |
    |-----|---------------|------------------------------------------------------|------|
    | 0   | dc_torque     | linear 0 ... ``max_dc_torque_nm`` (wagon 64.4 kN m)  | N m  |
    | 1   | amplitude     | logarithmic 20 ... 3000                               | N m  |
    | 2   | frequency     | logarithmic 1 ... 20                                  | Hz   |
    | 3   | cof_estimate  | linear 0 ... 0.8                                      | -    |
    | 4   | stop          | > 0 requests the end of the measurement               | -    |

    The DC level is ramped over the first ``ramp_fraction`` of the window; the modulation phase is
    continuous across windows.

    ## Observation Space
    ``Box(-1000, 1000, (13,), float32)``, from the last window only, never the ground truth:

    | Num | Observation    | Meaning                                                         |
    |-----|----------------|-----------------------------------------------------------------|
    | 0   | phase_lag      | lag of wheelset speed behind torque / 90 deg (sine fit)         |
    | 1   | phase_lag_se   | its standard error / 90 deg                                     |
    | 2   | compliance     | (speed amplitude / torque amplitude) x Iw x 2 pi f               |
    | 3   | coa_measured   | mean tangential / normal force of the driven wheelset (sensors) |
    | 4   | dc_torque      | applied DC torque / max_dc_torque_nm                            |
    | 5   | amplitude      | modulation amplitude / 3000 N m                                 |
    | 6   | frequency      | modulation frequency / 20 Hz                                    |
    | 7   | speed          | measured train speed / 40 m/s                                   |
    | 8   | wd_rms         | ISO 2631-1 Wd-weighted RMS car-body acceleration, m/s^2         |
    | 9   | jerk_rms       | RMS car-body jerk / 10 m/s^3                                    |
    | 10  | normal_load    | measured normal load / nominal                                  |
    | 11  | elapsed        | elapsed time / horizon                                          |
    | 12  | cof_estimate   | the agent's last reported estimate / 0.8                        |

    ## Rewards
    ``reward = reward_error + reward_slip + reward_comfort + reward_time`` (see
    :mod:`cof_gym.envs.reward`): ``-w_error |estimate - CoF| / CoF`` when the estimate is scored (stop
    or time limit), ``-w_slip`` x (time and energy past the creep-curve peak + frictional energy),
    ``-w_comfort`` x (Wd RMS acceleration + 0.1 RMS jerk), ``-w_time`` x window length. Every term
    is in ``info``; ``info["cost"]`` holds the unweighted constraint costs (slip, discomfort) and
    ``info["ground_truth"]`` the true CoF, condition, creepage and saturation torque, for evaluation
    only. With ``shaping=True`` a potential-based term ``reward_shaping = 0.95 Phi' - Phi``,
    ``Phi = w_error x (1 - relative error of the current estimate)`` (0 in terminal states), gives
    the estimate a dense signal for training (Ng et al. 1999). A non-negative potential: with a
    negative one, ``(1 - gamma) |Phi|`` per step pays the agent for stalling with a bad estimate.

    ## Starting State
    CoF, condition, speed, load case, sensor-noise level and motor lag are drawn from ``np_random``
    (ranges: :class:`~cof_gym.envs.scenarios.ScenarioRanges`; default CoF 0.02-0.6, speed 5-40 m/s,
    dry / wet / low_adhesion, empty / laden, noise 0-1 x full scale, lag 0-30 ms); each can be fixed
    by a constructor kwarg or ``reset(options={...})``. The vehicle starts at the nominal (static
    equilibrium) geometry, rolling, and a baseline window (no DC torque, 100 N m at 5 Hz) is measured
    for the first observation.

    ## Episode End
    - terminated: the agent requests stop (its estimate is scored); macro-slip (max creepage beyond
      ``macro_slip_creepage``: penalised, estimate scored as ``error_cap``); a diverging simulation
      (``info["diverged"] = True``, penalised like macro-slip).
    - truncated: after ``max_windows`` windows (default 30; the last reported estimate is scored).
      The registered ids set ``max_episode_steps`` to 30: with ``max_windows`` above 30 also pass
      ``max_episode_steps`` to ``gym.make``, or the TimeLimit cuts the episode before the env scores it.

    ## Arguments
    | Argument | Default | Description |
    |----------|---------|-------------|
    | vehicle | "wagon" | "wagon" or "half_wheelset" |
    | window_s | 1.0 | simulated time per step, s |
    | settle_fraction | 0.4 | part of the window not measured (transient after a change) |
    | ramp_fraction | 0.3 | part of the window over which the DC torque is ramped |
    | max_windows | 30 | horizon in steps (None: 30) |
    | macro_slip_creepage | 0.15 | creepage that counts as macro-slip |
    | counter_torque | False | the paper's equal-and-opposite torque on the bogie's other wheelset |
    | timestep | 0.001 | physics step, s |
    | ranges | ScenarioRanges() | per-episode draw ranges |
    | w_error, w_slip, w_comfort, w_time, macro_slip_penalty | 10, 1, 1, 0.02, 5 | reward weights |
    | cof, condition, speed_m_s, load_case, noise_level, motor_lag_s | None | fix a scenario field |
    | shaping | False | add the potential-based shaping term (training) |
    | render_mode | None | "rgb_array" or "human" |
    | width, height | 480, 240 | rgb_array frame size, pixels |

    ## Version History
    - v0: initial release (MuJoCo 4.0.0).
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 1}

    def __init__(self, vehicle: str = "wagon", window_s: float = 1.0, settle_fraction: float = 0.4,
                 ramp_fraction: float = 0.3, max_windows: int | None = None, macro_slip_creepage: float = 0.15,
                 counter_torque: bool = False, timestep: float = DEFAULT_TIMESTEP_S,
                 ranges: ScenarioRanges | None = None, w_error: float = 10.0, w_slip: float = 1.0,
                 w_comfort: float = 1.0, w_time: float = 0.02, macro_slip_penalty: float = 5.0,
                 shaping: bool = False, render_mode: str | None = None, width: int = 480, height: int = 240,
                 **fixed: Any) -> None:
        EzPickle.__init__(self, vehicle, window_s, settle_fraction, ramp_fraction, max_windows, macro_slip_creepage,
                          counter_torque, timestep, ranges, w_error, w_slip, w_comfort, w_time, macro_slip_penalty,
                          shaping, render_mode, width, height, **fixed)
        if vehicle not in VEHICLES:
            raise ValueError(f"vehicle must be one of {list(VEHICLES)}, got {vehicle!r}")
        if not (isinstance(window_s, (int, float)) and 0.2 <= window_s <= 10.0):
            raise ValueError(f"window_s must be in [0.2, 10] s, got {window_s!r}")
        if not (0.0 <= settle_fraction < 0.9):
            raise ValueError(f"settle_fraction must be in [0, 0.9), got {settle_fraction!r}")
        if not (0.0 <= ramp_fraction <= settle_fraction or ramp_fraction == 0.0):
            raise ValueError(f"ramp_fraction must be in [0, settle_fraction={settle_fraction}], got {ramp_fraction!r}")
        if max_windows is not None and not (type(max_windows) is int and 1 <= max_windows <= 10_000):
            raise ValueError(f"max_windows must be None or an int in [1, 10000], got {max_windows!r}")
        for name, value in (("width", width), ("height", height)):
            if not (type(value) is int and 16 <= value <= 4096):
                raise ValueError(f"{name} must be an int in [16, 4096] pixels, got {value!r}")
        if not (0.0 < macro_slip_creepage <= 1.0):
            raise ValueError(f"macro_slip_creepage must be in (0, 1], got {macro_slip_creepage!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']} or None, got {render_mode!r}")
        unknown = set(fixed) - set(SCENARIO_KEYS)
        if unknown:
            raise ValueError(f"unknown argument(s) {sorted(unknown)}; scenario fields are {list(SCENARIO_KEYS)}")
        self.vehicle = vehicle
        self.window_s = float(window_s)
        self.settle_s = settle_fraction * self.window_s
        self.ramp_s = ramp_fraction * self.window_s
        self.max_windows = DEFAULT_MAX_WINDOWS if max_windows is None else max_windows
        self.shaping = bool(shaping)
        self.macro_slip_creepage = macro_slip_creepage
        self.counter_torque = bool(counter_torque)
        self.timestep = float(timestep)
        self.ranges = ranges if ranges is not None else ScenarioRanges()
        if self.vehicle == "half_wheelset":
            self.ranges = replace(self.ranges, load_cases=("laden",))
        self.weights = RewardWeights(w_error, w_slip, w_comfort, w_time, macro_slip_penalty)
        self.fixed = dict(fixed)
        draw_scenario(np.random.default_rng(0), self.ranges, self.fixed)  # validates fixed fields now
        self.render_mode = render_mode
        self.width, self.height = width, height
        laden = built_model(vehicle, "laden", self.timestep, self.counter_torque)
        self.limits = MotorLimits(max_dc_torque_nm=MAX_DC_TORQUE_PER_LADEN_SATURATION * 0.6
                                  * laden.saturation_torque_per_cof)
        self.action_space = action_space()
        self.observation_space = observation_space()
        self.metadata = {**self.metadata, "render_fps": max(1, int(round(1.0 / self.window_s)))}
        self._sims: dict[str, Simulation] = {}
        self._sim: Simulation | None = None
        self._built: BuiltModel | None = None
        self._renderer = None
        self._viewer = None
        self._warned_display = False

    # ------------------------------------------------------------------ episode
    def _simulation(self, load_case: str) -> Simulation:
        if load_case not in self._sims:
            self._sims[load_case] = Simulation(built_model(self.vehicle, load_case, self.timestep, self.counter_torque))
        return self._sims[load_case]

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        physics = self._begin_episode(seed, options)
        sim = self._simulation(self.scenario.load_case)
        sim.reset(physics)
        self._sim = sim
        m = sim.run_window(self._drive, self.window_s, self.settle_s, self.ramp_s)
        return self._finish_reset(m)

    # The episode bookkeeping is split around the physics so that the vector env
    # (cof_gym.envs.vector) runs the same code with batched simulations.
    def _begin_episode(self, seed: int | None, options: dict | None) -> Scenario:
        """Seed, draw the scenario and reset the bookkeeping; the physics scenario to simulate (on
        ``self._built``, with the baseline drive ``self._drive``)."""
        super().reset(seed=seed)
        fixed = {**self.fixed, **(options or {})}
        self.scenario: EpisodeScenario = draw_scenario(self.np_random, self.ranges, fixed)
        built = built_model(self.vehicle, self.scenario.load_case, self.timestep, self.counter_torque)
        physics = self.scenario.physics(built.nominal_wheel_load_n, seed=int(self.np_random.integers(2**31)))
        self._built = built
        self._contact_load = built.nominal_wheel_load_n * built.wheels_per_contact
        op: OperatingConditions = physics.op
        self._peak = creep_peak(op)
        self._saturation_torque = built.saturation_torque_per_cof * self.scenario.cof
        self._elapsed = 0.0
        self._windows = 0
        self._estimate = 0.0
        self._potential = self._shaping_potential()
        self._drive = DriveCommand(0.0, 100.0, 5.0)
        return physics

    def _finish_reset(self, m: WindowMeasurement) -> tuple[np.ndarray, dict]:
        """The first observation and info from the baseline window."""
        self._last = m
        obs = self._observe(m)
        return obs, self._info(m, {}, diverged=False)

    def _observe(self, m: WindowMeasurement) -> np.ndarray:
        return encode_observation(m, self._drive, self.limits, self._built.drive_spin_inertia_kg_m2,
                                  self._contact_load, self._elapsed, self.max_windows * self.window_s, self._estimate)

    def _shaping_potential(self) -> float:
        """Phi = w_error x (error_cap - relative error of the current estimate) >= 0."""
        err = relative_error(self._estimate, self.scenario.cof, self.weights.error_cap)
        return self.weights.w_error * (self.weights.error_cap - err)

    def _info(self, m: WindowMeasurement, terms: dict, diverged: bool) -> dict:
        info = dict(terms)
        info["diverged"] = diverged
        info["cof_estimate"] = self._estimate
        info["cost"] = {"slip": terms.get("slip_cost", 0.0), "discomfort": terms.get("discomfort", 0.0)}
        info["measurement"] = asdict(m)
        info["ground_truth"] = {
            **self.scenario.to_dict(), "creepage": m.creepage_mean, "coa": m.coa_true,
            "saturation_torque_nm": self._saturation_torque, "peak_creepage": self._peak.creepage,
            "torque_fraction": self._drive.dc_torque_nm / self._saturation_torque,
        }
        info["elapsed_s"] = self._elapsed
        return info

    def step(self, action):
        if self._sim is None:
            raise RuntimeError("call reset() before step()")
        decoded = self._command(action)
        try:
            m = self._sim.run_window(self._drive, self.window_s, self.settle_s, self.ramp_s)
            diverged = self._diverged(m)
        except SimulationDiverged:
            m, diverged = self._last, True
        out = self._finish_step(m, decoded, diverged)
        if self.render_mode == "human":
            self.render()
        return out

    def _command(self, action) -> DecodedAction:
        """Check and decode the action; sets the drive (``self._drive``) of the next window."""
        a = check_action(action)
        decoded = decode_action(a, self.limits)
        self._drive = decoded.drive
        self._estimate = decoded.cof_estimate
        return decoded

    def _finish_step(self, m: WindowMeasurement, decoded: DecodedAction, diverged: bool):
        """The step's (obs, reward, terminated, truncated, info) from the window's measurement."""
        self._windows += 1
        self._elapsed += self.window_s
        if diverged:
            m = self._last
        self._last = m
        macro_slip = diverged or m.max_abs_creepage > self.macro_slip_creepage
        truncated = self._windows >= self.max_windows and not (macro_slip or decoded.stop)
        terminated = bool(macro_slip or decoded.stop)
        scored = relative_error(self._estimate, self.scenario.cof, self.weights.error_cap) \
            if (decoded.stop or truncated) and not macro_slip else None
        terms = reward_terms(self.weights, m, self._contact_load, self.scenario.speed_m_s, self.window_s, scored, macro_slip)
        if self.shaping:
            # Phi = 0 in terminal states; a truncated state is not terminal (learners bootstrap there)
            potential = 0.0 if terminated else self._shaping_potential()
            terms["reward_shaping"] = SHAPING_GAMMA * potential - self._potential
            self._potential = potential
        reward = float(sum(terms.values()))
        info = self._info(m, {**terms, "slip_cost": slip_cost(m, self._contact_load, self.scenario.speed_m_s, self.window_s),
                              "discomfort": discomfort(m)}, diverged)
        info["macro_slip"] = bool(macro_slip)
        info["relative_error"] = self.weights.error_cap if macro_slip else scored
        obs = self._observe(m)
        return obs, reward, terminated, bool(truncated), info

    def _diverged(self, m: WindowMeasurement) -> bool:
        d = self._sim.data
        bad = d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0
        return window_diverged(m, bad, self._sim.is_finite())

    # ------------------------------------------------------------------ rendering
    def render(self):
        if self.render_mode is None or self._sim is None:
            return None
        model, data = self._sim.model, self._sim.data
        if self.render_mode == "rgb_array":
            if self._renderer is None or self._renderer.model is not model:
                self._renderer = mujoco.Renderer(model, self.height, self.width)
            self._renderer.update_scene(data, camera="side")
            return self._renderer.render()
        if not display_available():
            if not self._warned_display:
                gym.logger.warn("render_mode='human' needs a display (DISPLAY/WAYLAND_DISPLAY); nothing is shown")
                self._warned_display = True
            return None
        if self._viewer is None:
            viewer = importlib.import_module("mujoco.viewer")
            self._viewer = viewer.launch_passive(model, data)
        self._viewer.sync()
        return None

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        if self._viewer is not None:
            self._viewer.close()
            self._viewer = None
