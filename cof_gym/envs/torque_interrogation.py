"""Torque interrogation of the wheel-rail friction as a Gymnasium environment.

The environment composes the physics (one :class:`~cof_gym.physics.simulation.Simulation` per load
case) with the task (:class:`~cof_gym.task.InterrogationTask`: scenarios, ground truth, interface,
reward, constraints, horizon).
"""

from __future__ import annotations

import importlib
import os
import sys
from dataclasses import fields
from typing import Any, Mapping

import gymnasium as gym
import mujoco
import numpy as np
from gymnasium.utils import EzPickle

from cof_gym.physics.models import DEFAULT_TIMESTEP_S
from cof_gym.physics.simulation import SimulationDiverged, Simulation, WindowMeasurement
from cof_gym.task import InterrogationTask, MacroSlipLimit, Reward, ScenarioRanges
from cof_gym.task.interface import DecodedAction
from cof_gym.task.scenarios import SCENARIO_KEYS, TASK_VERSION_RANGES, drawn_kinds
from cof_gym.task.task import DEFAULT_MAX_WINDOWS, Episode
from cof_gym.validation import check_choice, check_int, is_int


def display_available() -> bool:
    """Whether an on-screen viewer can open (always assumed off Linux)."""
    return not sys.platform.startswith("linux") or bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def window_diverged(m: WindowMeasurement, bad_qacc: bool, state_finite: bool) -> bool:
    """Whether a window diverged: a bad-acceleration warning, a non-finite state or measurement."""
    values = np.array([getattr(m, f.name) for f in fields(m)], dtype=np.float64)
    return bool(bad_qacc or not state_finite or not np.isfinite(values).all())


def default_ranges(task_version: int) -> ScenarioRanges:
    """The scenario draws of a task version (:data:`cof_gym.task.scenarios.TASK_VERSION_RANGES`): 1 the Polach
    presets without systematic sensor errors, 2 creep-law families with drawn shapes and systematic sensor errors
    (:data:`~cof_gym.task.scenarios.V2_RANGES`), 3 also a train's speed probe and track
    (:data:`~cof_gym.task.scenarios.V3_RANGES`)."""
    return TASK_VERSION_RANGES[check_int("task_version", task_version, min(TASK_VERSION_RANGES),
                                         max(TASK_VERSION_RANGES))]


# how a user narrows each version's draws (the names of cof_gym.task's ranges), for the error below
NARROWING = {1: "cof_gym.task.ScenarioRanges(...)", 2: "dataclasses.replace(cof_gym.task.V2_RANGES, ...)",
             3: "dataclasses.replace(cof_gym.task.V3_RANGES, ...)"}


def _kinds(ranges: ScenarioRanges) -> tuple[bool, bool]:
    return ranges.draws_v2, ranges.draws_v3


def _version_of(ranges: ScenarioRanges) -> int:
    """The task version whose kinds of draws ``ranges`` have (narrowed or widened), 0 where none has them."""
    return next((v for v, r in TASK_VERSION_RANGES.items() if _kinds(r) == _kinds(ranges)), 0)


def task_ranges(task_version: int, ranges: ScenarioRanges | Mapping[str, Any] | None) -> ScenarioRanges:
    """The draws of a task: ``ranges`` (a mapping of its fields, as a spec's JSON gives it back, too), or the
    version's own where ``None``. Ranges that draw other kinds of uncertainty than the version (v1 draws on a v2
    task, which would quietly drop its creep-law families and sensor errors, v2 draws on a v3 task, which would
    drop its speed probe and track, or the reverse) are a ``ValueError`` naming both arguments."""
    version_ranges = default_ranges(task_version)
    if isinstance(ranges, Mapping):
        ranges = ScenarioRanges.from_mapping(ranges)
    if ranges is None or not isinstance(ranges, ScenarioRanges) or _kinds(ranges) == _kinds(version_ranges):
        return version_ranges if ranges is None else ranges  # (a wrong type is the task's error, named there)
    narrow = NARROWING[task_version]
    other = _version_of(ranges)
    instead = f", or make the -v{other} id (task_version={other})" if other else ""
    raise ValueError(f"ranges: draws {drawn_kinds(ranges)}, but task_version is {task_version} (the -v{task_version} "
                     f"ids draw {drawn_kinds(version_ranges)}): narrow that version's draws with {narrow}{instead}")


def make_kwargs(kwargs: dict[str, Any]) -> dict[str, Any]:
    """``gym.make`` / ``gym.make_vec`` keyword arguments in which a ``max_windows`` also moves the
    registered ``TimeLimit`` (``max_episode_steps``) unless that is given too, so that the task's own
    horizon ends the episode and scores the last estimate."""
    kwargs = dict(kwargs)
    if "max_windows" in kwargs and "max_episode_steps" not in kwargs and is_int(kwargs["max_windows"]):
        kwargs["max_episode_steps"] = kwargs["max_windows"]  # any other value: the task's check names max_windows
    return kwargs


def make_task(vehicle: str = "wagon", window_s: float = 1.0, settle_fraction: float = 0.4, ramp_fraction: float = 0.3,
              max_windows: int = DEFAULT_MAX_WINDOWS, counter_torque: bool = False,
              traction_balance: bool | None = None, timestep: float = DEFAULT_TIMESTEP_S,
              ranges: ScenarioRanges | None = None, w_error: float = 10.0, w_slip: float = 1.0,
              w_comfort: float = 0.05, w_time: float = 0.02, macro_slip_penalty: float = 10.0,
              macro_slip_ratio: float = 2.0, macro_slip_floor: float = 0.02, shaping: bool = False,
              action_type: str = "absolute", observation_type: str = "window", task_version: int = 1,
              info_layout: str = "nested", excitation: str = "sine", tones: int = 2, lock_in: str = "plain",
              **fixed: Any) -> InterrogationTask:
    """The task from the environment's keyword arguments (the table in the env's docstring). An unknown
    argument name is a ``TypeError`` (as Python's for an unexpected keyword: RL libraries such as
    torchrl retry without an optional argument on it); a wrong value is a ``ValueError``."""
    unknown = set(fixed) - set(SCENARIO_KEYS)
    if unknown:
        names = ", ".join(repr(name) for name in sorted(unknown))  # worded as Python's, which clients match
        raise TypeError(f"TorqueInterrogationEnv() got an unexpected keyword argument {names}; scenario fields are "
                        f"{list(SCENARIO_KEYS)}")
    return InterrogationTask(
        vehicle=vehicle, window_s=window_s, settle_fraction=settle_fraction, ramp_fraction=ramp_fraction,
        max_windows=max_windows, counter_torque=counter_torque, traction_balance=traction_balance, timestep=timestep,
        ranges=task_ranges(task_version, ranges), fixed=fixed,
        reward=Reward(w_error, w_slip, w_comfort, w_time, macro_slip_penalty),
        macro_slip=MacroSlipLimit(macro_slip_ratio, macro_slip_floor), shaping=shaping,
        action_type=action_type, observation_type=observation_type, info_layout=info_layout,
        excitation=excitation, tones=tones, lock_in=lock_in,
    )


class TorqueInterrogationEnv(gym.Env, EzPickle):
    r"""Measure the wheel-rail coefficient of friction (CoF) by torque modulation.

    A MuJoCo wagon (or the paper's half wheelset) runs at a cruise-controlled speed; the agent sets the
    traction torque of the driven wheelset, ``M = Mc + M0 sin(2 pi f t)``, window by window, reads
    the phase lag of the wheelset speed, the measured adhesion (CoA) and comfort, and reports a CoF
    estimate. One step is one measurement window (``window_s`` of simulated time, one native
    ``mj_step`` call).

    ## Action Space
    ``Box(-1, 1, (5,), float32)`` for every ``action_type``, rescaled inside (out-of-range values are
    clipped; NaN/inf, other shapes and non-real dtypes raise ``ValueError``). ``action_type="absolute"``
    (default):

    | Num | Action        | Rescaled to                                            | Unit |
    |-----|---------------|--------------------------------------------------------|------|
    | 0   | dc_torque     | linear 0 ... ``limits.max_dc_torque_nm`` (wagon ~89 kN m) | N m  |
    | 1   | amplitude     | logarithmic 20 ... 3000                                 | N m  |
    | 2   | frequency     | logarithmic 1 ... 20                                    | Hz   |
    | 3   | cof_estimate  | logarithmic 0.01 ... 1                                  | -    |
    | 4   | stop          | > 0 ends the measurement now (no window is run)          | -    |

    ``action_type="relative"`` (:class:`cof_gym.task.actions.RelativeActions`: scale-free across CoF
    0.02-0.6):

    | Num | Action        | Rescaled to                                                                | Unit |
    |-----|---------------|----------------------------------------------------------------------------|------|
    | 0   | dc_torque     | ``max(dc, floor) x exp(0.5 a)``, ``dc`` the current level, ``floor`` 0.3 % of max (the first step from zero stays below the smallest saturation torque in range, ~1.1 % of max) | N m |
    | 1   | amplitude     | logarithmic 1 ... 30 % of the new DC level (``max(dc', floor)``), within 20 ... 3000 | N m |
    | 2   | frequency     | logarithmic 1 ... 20                                                        | Hz   |
    | 3   | cof_estimate  | ``max(best measured CoA so far, 0.01) x exp(0.5 a)``, within 0.01 ... 1     | -    |
    | 4   | stop          | > 0.5 requests the end of the measurement                                   | -    |

    ``action_type="identified"`` (:class:`cof_gym.task.actions.IdentifiedActions`): as "relative", but
    the estimate is ``fitted peak x exp(0.05 a3)`` (x0.95 ... x1.05), the fitted peak that of the
    creep-curve fit of the climb so far (:mod:`cof_gym.task.creep_fit`: Polach's family with free
    peak CoA and peak creepage, fitted to the measured CoA and creepage of the driven windows), the best
    measured CoA before the climb has 3 points: a residual on the model-based identification (the
    interface ``cof_gym/agents/hyperparams/ppo.yml`` trains, with ``observation_type="identification"``).

    The DC level is ramped over the first ``ramp_fraction`` of the window; the modulation phase is
    continuous across windows. The drive reaches 1.25 x the largest saturation torque in the CoF
    envelope (load transfer included). Scripted agents encode with
    ``env.unwrapped.task.actions.encode(context, dc, amplitude, frequency, estimate, stop, limits)``.

    ``excitation="multitone"`` (:mod:`cof_gym.task.excitation`) drives ``tones`` = K (2 or 3) sines,
    ``M = Mc + sum_k a_k sin(2 pi f_k t)``, each phase-continuous across windows and measured by its own
    lock-in (a joint least-squares fit of all tones). The action is ``Box(-1, 1, (5 + 2 (K - 1),))``: the 5
    above, decoded by the ``action_type`` as listed (the amplitude is the TOTAL ``A = sum_k a_k``, the
    frequency is tone 1's), then per extra tone k = 2...K, decoded the same way for every action type:

    | Num         | Action      | Rescaled to                                                        | Unit |
    |-------------|-------------|--------------------------------------------------------------------|------|
    | 5 + 2(k-2)  | frequency_k | logarithmic 1 ... 20 (as tone 1's)                                  | Hz   |
    | 6 + 2(k-2)  | share_k     | weight ``w_k = 1 + a`` in [0, 2] (tone 1's is 1); ``a_k = A w_k / (1 + sum_j w_j)``: 0 an equal split, -1 silences the tone, +1 twice tone 1's share | - |

    Every ``a_k >= 0`` and they sum to ``A``. Tones closer than ``2 / T`` (``T = window_s x (1 -
    settle_fraction)``, the measured span; the fit resolves ~1 / T) are moved apart: an extra tone goes to
    the nearest frequency in 1-20 Hz at least ``2 / T`` from tone 1 and the earlier tones (tone 1 is never
    moved; the applied frequencies are in ``info["measurement"]["tone<k>_frequency_hz"]``); a window too
    short for K tones to fit that way is refused (``ValueError`` naming ``tones``). Tones at second-order
    intermodulation frequencies of others (``f_i + f_j``, ``|f_i - f_j|``, ``2 f_i``) pick up a small
    distortion product from the creep curve's curvature. The reset window splits its 100 N m equally over
    tone 1 at 5 Hz and extra tones at 11 and 17 Hz.

    ## Observation Space
    ``Box(-1000, 1000, (14,), float32)``, from the last window's *sensor readings* only
    (:data:`cof_gym.task.SENSOR_FIELDS`; :func:`cof_gym.task.decode_observation` inverts it):

    | Num | Observation        | Meaning                                                       |
    |-----|--------------------|---------------------------------------------------------------|
    | 0   | phase_lag          | lag of wheelset speed behind torque / 90 deg (sine fit)       |
    | 1   | phase_lag_se       | its standard error / 90 deg                                   |
    | 2   | compliance         | (speed amplitude / torque amplitude) x Iw x 2 pi f             |
    | 3   | coa_measured       | mean measured tangential / normal force, driven wheelset      |
    | 4   | creepage_measured  | mean of R omega / v - 1 (encoder, speed sensor) x 10          |
    | 5   | dc_torque          | applied DC torque / max DC torque                             |
    | 6   | amplitude          | modulation amplitude / 3000 N m                               |
    | 7   | frequency          | modulation frequency / 20 Hz                                  |
    | 8   | speed              | measured train speed / 40 m/s                                 |
    | 9   | wd_rms             | ISO 2631-1 Wd RMS car-body acceleration / 0.01 m/s^2           |
    | 10  | jerk_rms           | RMS car-body jerk / 10 m/s^3                                  |
    | 11  | normal_load        | measured normal load / static load                            |
    | 12  | elapsed            | elapsed time / horizon                                        |
    | 13  | cof_estimate       | the agent's last reported estimate                            |

    ``observation_type="history"``: ``Box(-1000, 1000, (29,), float32)``, the 14 above followed by a
    fixed-size memory of the episode, from the same sensor-only values
    (:class:`cof_gym.task.interface.HistoryObservation`, :func:`cof_gym.task.interface.decode_history`):

    | Num   | Observation          | Meaning                                                              |
    |-------|----------------------|----------------------------------------------------------------------|
    | 14    | baseline_phase_lag   | phase_lag of the first window the agent drove (until then: the reset window's) |
    | 15    | baseline_compliance  | its compliance                                                       |
    | 16    | best_coa             | the largest measured CoA so far (reset window included)              |
    | 17-28 | coa_measured_k, creepage_measured_k, phase_lag_k, dc_torque_k | of the k-th previous window, k = 1...K, K = 3 (newest first; the oldest known window repeats until there are K) |

    ``observation_type="identification"``: ``Box(-1000, 1000, (38,), float32)``, the 29 of "history"
    followed by the creep-curve fit of the climb (the driven windows with a DC torque whose CoA did not
    fall; :func:`cof_gym.task.interface.identification_features`), all from the same sensor readings:

    | Num | Observation     | Meaning                                                                   |
    |-----|-----------------|---------------------------------------------------------------------------|
    | 29  | fit_available   | 1 once the climb has 3 points with positive CoA and creepage              |
    | 30  | fit_peak_ratio  | ln(fitted peak CoA / best measured CoA of the climb) (0 without a fit)    |
    | 31  | fit_low_ratio   | ln(low end of the fit's confidence interval / best CoA)                   |
    | 32  | fit_high_ratio  | ln(high end / best CoA) (open interval: up to ln 4)                       |
    | 33  | fit_half_width  | the interval's relative half-width, 0.5 ln(high / low)                    |
    | 34  | load_fraction   | the last window's CoA / fitted peak (/ best CoA before a fit)             |
    | 35  | log_elasticity  | ln(d ln creepage / d ln CoA) over >= 3 % of CoA (0 on the linear part)    |
    | 36  | climb_points    | points of the climb / 10                                                  |
    | 37  | falling         | 1 when the last window's CoA fell (past the peak)                         |

    ``excitation="multitone"`` appends ``3 K`` values after whatever the ``observation_type`` produces
    (shape 14 + 3K, 29 + 3K or 38 + 3K), for k = 1...K: ``[phase_lag_k / 90, phase_lag_se_k / 90,
    compliance_k]``, ``compliance_k = (speed / torque amplitude of tone k) x Iw x 2 pi f_k``. A silent tone
    (share 0) reads 0, 2 (SE 180 deg: no information) and 0; tones that cannot be separated read SE 180 deg
    too, never NaN. The first three observations (and ``amplitude`` the total) are then tone 1's from the
    joint fit. ``info["measurement"]`` adds, per tone, ``tone<k>_frequency_hz``, ``tone<k>_amplitude_nm``
    (commanded), ``tone<k>_phase_lag_deg``, ``tone<k>_phase_lag_se_deg``, ``tone<k>_amplitude_ratio``
    (rad/s per N m), ``tone<k>_torque_amplitude_nm`` and ``tone<k>_omega_amplitude_rad_s``.

    ## Rewards
    ``reward = reward_error + reward_slip + reward_comfort + reward_time`` (:mod:`cof_gym.task.reward`,
    where each weight's trade is documented): ``-w_error |ln(estimate / CoF)|`` when the estimate is
    scored (stop, macro-slip or the horizon), ``-w_slip`` x (time and energy past the creep-curve peak)
    ``- macro_slip_penalty`` on a macro-slip, ``-w_comfort`` x Wd RMS / 0.01 m/s^2,
    ``-w_time`` x window length. Every term is in ``info``; ``info["cost"]`` holds the unweighted
    constraint costs (slip, discomfort, macro_slip). ``info["measurement"]`` holds only sensor readings
    (among them the measured creepage's own modulation, ``creepage_modulation_amplitude``,
    ``creepage_modulation_lag_deg`` behind the torque and its SE: a lock-in of ``R omega / v - 1`` from the
    noisy encoder and speed sensor, the creepage's offset gone with its DC level; and the measured CoA's
    synchronous average over the modulation cycle, ``coa_cycle_max``, ``coa_cycle_min`` and
    ``coa_cycle_bin_se``: the window's samples of the force sensors' CoA averaged in 16 bins of the
    modulation's phase over its cycles, their largest and smallest bin means and one bin's standard
    error, :mod:`cof_gym.measurement.synchronous_average`; and ``phase_lag_se_corrected_deg``, the lag's SE
    with the speed fit's residual taken as first-order autoregressive, its lag-1 correlation read in the window,
    180 with extra tones: :func:`cof_gym.measurement.sine_fit.colored_noise_factor`; and with ``lock_in="rotation"``
    ``rotation_ripple_rad_s`` and ``rotation_ripple_phase_se_deg``, the speed's ripple at the wheelset's rotation
    frequency (a target wheel's runout) and its phase's SE, 0 and 180 where it is not read);
    every privileged quantity (the CoF, the saturation torque, true creepage and CoA, anything relative
    to the creep peak) is under ``info["ground_truth"]``, for evaluation only. With ``shaping=True`` a
    potential-based term ``reward_shaping = 0.95 Phi' - Phi``, ``Phi = w_error (ln 100 - |ln(estimate /
    CoF)|) >= 0`` (0 in terminal states), gives the estimate a dense signal for training (Ng et al. 1999).

    ## Ground truth
    The scored CoF is the largest CoA the driven wheelset reaches in this simulation under steady
    traction, at its actual normal load under that traction (load transfer) and the cruise-controlled
    speed; ``info["ground_truth"]["saturation_torque_nm"]`` is the DC torque at which it gets there
    (:mod:`cof_gym.task.ground_truth`).

    ## Starting State
    Condition, CoF (in the condition's range, :data:`cof_gym.task.COF_BY_CONDITION`), speed, load case,
    sensor-noise level and motor lag are drawn from ``np_random`` (:class:`cof_gym.task.ScenarioRanges`:
    dry / wet / low_adhesion, CoF 0.02-0.6 overall, 5-40 m/s, empty / laden, noise 0-1 x full scale,
    lag 0-30 ms); v2 (``task_version=2``) also draws a creep-law family and its shape
    (:mod:`cof_gym.physics.creep_laws`) and the systematic sensor errors (:mod:`cof_gym.task.sensors`),
    which change readings, never physics, and are reported only under ``info["ground_truth"]``; v3
    (``task_version=3``, ``CofGym/TorqueInterrogationInService-v3``) then also draws a train's speed probe
    (pulses, runout, lag) and the track's irregularity (:data:`cof_gym.task.V3_RANGES`); each
    can be fixed by a constructor kwarg or ``reset(options={...})``. The vehicle
    starts at the static equilibrium, rolling, and a baseline window (no DC torque, 100 N m at 5 Hz) is
    measured for the first observation.

    ## Episode End
    - terminated: the agent requests stop (its estimate is scored at once: that step runs no window,
      costs no time, slip or comfort, and returns the last window's observation; its info repeats the last window's
      readings and ``info["elapsed_s"]`` does not grow: a sum of window quantities over steps counts a step only where
      it grew, as ``cof-gym evaluate`` does); macro-slip (any wheel's creepage
      beyond ``max(macro_slip_ratio x peak creepage, peak + macro_slip_floor)``: penalised, the estimate
      scored); a diverging simulation (``info["diverged"] = True``, treated as a macro-slip).
    - truncated: after ``max_windows`` windows (the task's horizon, default 30; the last estimate is
      scored). The registered ids carry the same horizon as ``max_episode_steps`` (gym.make's
      ``TimeLimit`` ends the episode at the same step); a longer ``max_windows`` needs
      ``max_episode_steps`` too (:func:`make_kwargs` adds it).

    ## Arguments
    | Argument | Default | Description |
    |----------|---------|-------------|
    | vehicle | "wagon" | "wagon" or "half_wheelset" |
    | window_s | 1.0 | simulated time per step, s, in [0.2, 10] |
    | settle_fraction | 0.4 | part of the window not measured (transient after a change), in [0, 0.8] |
    | ramp_fraction | 0.3 | part of the window over which the DC torque is ramped, <= settle_fraction |
    | max_windows | 30 | horizon in steps, int in [1, 10000] |
    | counter_torque | False | the paper's equal-and-opposite torque on the bogie's other wheelset (the wagon only: refused on the half wheelset) |
    | traction_balance | None | the rest of the train cancels the DC torque (None: on for the wagon without counter torque) |
    | timestep | 0.001 | physics step, s, in [1e-4, 2e-3] |
    | ranges | None | per-episode draw ranges (:class:`cof_gym.task.ScenarioRanges`); None: the task version's (v2: ``cof_gym.task.V2_RANGES``, v3: ``cof_gym.task.V3_RANGES``), or a mapping of its fields (as a spec's JSON holds them); ranges that draw other kinds than the version's (v1 ranges on a v2 task, v2 ranges on a v3 task, ...) are refused |
    | w_error, w_slip, w_comfort, w_time, macro_slip_penalty | 10, 1, 0.05, 0.02, 10 | reward weights |
    | macro_slip_ratio, macro_slip_floor | 2, 0.02 | the macro-slip limit relative to the peak creepage |
    | cof, condition, speed_m_s, load_case, noise_level, motor_lag_s | None | fix a scenario field |
    | creep_law | None | fix the creep curve: a preset name, ``{"polach": {...}}``, ``{"shen_hedrick_elkins": {...}}`` or ``{"table": {"creepage": [...], "adhesion_ratio": [...]}}`` (:func:`cof_gym.physics.creep_laws.creep_law_from_spec`); played where it has a peak (a draw where it has none is drawn again) |
    | speed_sensor_error, wheel_radius_error, force_gain_error, torque_gain_error | None | fix a systematic sensor error (relative; ranges in :data:`cof_gym.task.sensors.SYSTEMATIC_ERRORS`) |
    | encoder_lag_s | None (0) | a first-order lag of the encoder's speed signal, s, in [0, 0.05]: adds ``atan(w tau)`` to every phase the lock-in reads (drawn by v3 only, 0-5 ms; :mod:`cof_gym.task.sensors`) |
    | encoder_pulses_per_rev, encoder_runout | None (0, 0) | the wheelset-speed encoder as a speed probe's pulses: pulses per revolution of the wheelset, 0 (a continuous reading) or 8-10000, read by the period method (adds about one pulse interval's delay to every lag), and its target wheel's runout, relative, in [0, 0.01] (a once-per-revolution ripple of the reading; drawn by v3 only, 60-300 pulses and 0-0.1 %; :mod:`cof_gym.physics.encoder`) |
    | track_irregularity | None ("smooth") | the rail's vertical profile: "smooth", or a profile drawn per episode from ORE B176's spectrum for "ore_low" or "ore_high" irregularity (wavelengths 1-80 m; drawn by v3 only, "ore_low" or "ore_high"; :mod:`cof_gym.physics.track`) |
    | task_version | 1 | 1: Polach presets, unbiased sensors; 2: creep-law families and systematic sensor errors drawn (the -v2 ids); 3: also a train's speed probe and track (``CofGym/TorqueInterrogationInService-v3``) |
    | shaping | False | add the potential-based shaping term (training) |
    | action_type | "absolute" | "absolute", "relative" or "identified" (see Action Space) |
    | observation_type | "window" | "window" (14), "history" (29) or "identification" (38; see Observation Space) |
    | excitation | "sine" | "sine" (one tone, as in the paper) or "multitone" (``tones`` sines, each with its own lock-in; see Action Space) |
    | tones | 2 | tones of the "multitone" excitation, 2 or 3 (ignored with "sine", still checked) |
    | lock_in | "plain" | the speed's lock-in: "plain" (each tone's ``[cos, sin]``, an offset and a drift) or "rotation" (also ``[cos, sin]`` of the angle the encoder counts and of twice it: a runout's once-per-revolution ripple taken out of every tone's reading, but for a harmonic the window cannot tell from a tone, left out; :data:`cof_gym.physics.simulation.LOCK_INS`) |
    | info_layout | "nested" | "nested" (the info above) or "flat": one level of keys joined by "/" (``info["measurement/phase_lag_deg"]``), every value a number, strings as indices (:data:`cof_gym.task.info_layout.FLAT_CODES`), the creep law's spec left out; for torchrl's ``GymWrapper`` over ``gym.make_vec`` (:mod:`cof_gym.task.info_layout`) |
    | render_mode | None | "rgb_array" or "human" |
    | width, height | 480, 240 | rgb_array frame size, pixels |

    Booleans must be ``bool`` (or numpy booleans), numbers finite real numbers (not bool or str): anything
    else raises a ``ValueError`` naming the argument, the type and the range; an unknown argument name
    raises ``TypeError``. A numpy scalar is stored as the Python number it holds (``np.float32(0.3)`` runs
    exactly as ``float(np.float32(0.3))``).

    ## Version History
    - v3 (``CofGym/TorqueInterrogationInService-v3``, the wagon; session 86): each seed's v2 scenario, every v2 field
      as the -v2 id draws it, then a train's speed probe (60-300 pulses per revolution read by the period method, a
      target-wheel runout of 0-0.1 %, a signal lag of 0-5 ms) and a track of ORE B176 low or high irregularity
      (:data:`cof_gym.task.V3_RANGES`). A name of its own, so that Gymnasium calls no -v2 id out of date.
    - v2: creep-law families (Polach with drawn shapes, Shen-Hedrick-Elkins saturation, tables) and
      systematic sensor errors (reference speed, wheel radius, force and torque gains) drawn per
      episode; no ``None`` in ``info``. v1 stays registered with its numbers. Both versions' ids carry the
      task's horizon (30 steps) on their spec as well (``max_episode_steps``, the task still truncating there).
      Later additions to ``info["measurement"]`` (v1 and v2 alike) add readings and change no number
      of the observation, reward or ground truth: the measured creepage's modulation (session 12), the
      measured CoA's synchronous average over the cycle (``coa_cycle_*``, session 22), the lag's SE for an
      autocorrelated residual (``phase_lag_se_corrected_deg``, session 59), the rotation lock-in's ripple
      (``rotation_ripple_rad_s``, ``rotation_ripple_phase_se_deg``, session 85; 0 and 180 with the plain lock-in).
      Later options that no draw gives leave every drawn episode as it was: ``encoder_lag_s`` (session 59; 0 unless
      fixed, and ``info["ground_truth"]`` carries it), ``track_irregularity`` (session 82; "smooth" unless fixed, its
      profile's phases drawn from a stream of their own, so that fixing it moves no other draw),
      ``encoder_pulses_per_rev`` and ``encoder_runout`` (session 83; 0 unless fixed: the continuous reading).
    - v1: ground truth from the simulated physics (load transfer, controlled speed); PI cruise control
      and traction balance; a traction rod; CoF ranges per condition; macro-slip relative to the peak;
      log-ratio error, no slip cost below the peak, comfort over the whole window; sensors apart from
      truth (14 observations, creepage measured); logarithmic estimate 0.01-1; the task truncates at its horizon.
    - v0: initial release (removed: its ground truth disagreed with its own simulation).
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 1}

    def __init__(self, vehicle: str = "wagon", window_s: float = 1.0, settle_fraction: float = 0.4,
                 ramp_fraction: float = 0.3, max_windows: int = DEFAULT_MAX_WINDOWS, counter_torque: bool = False,
                 traction_balance: bool | None = None, timestep: float = DEFAULT_TIMESTEP_S,
                 ranges: ScenarioRanges | None = None, w_error: float = 10.0, w_slip: float = 1.0,
                 w_comfort: float = 0.05, w_time: float = 0.02, macro_slip_penalty: float = 10.0,
                 macro_slip_ratio: float = 2.0, macro_slip_floor: float = 0.02, shaping: bool = False,
                 render_mode: str | None = None, width: int = 480, height: int = 240, action_type: str = "absolute",
                 observation_type: str = "window", task_version: int = 1, info_layout: str = "nested",
                 excitation: str = "sine", tones: int = 2, lock_in: str = "plain", **fixed: Any) -> None:
        EzPickle.__init__(self, vehicle, window_s, settle_fraction, ramp_fraction, max_windows, counter_torque,
                          traction_balance, timestep, ranges, w_error, w_slip, w_comfort, w_time, macro_slip_penalty,
                          macro_slip_ratio, macro_slip_floor, shaping, render_mode, width, height,
                          action_type=action_type, observation_type=observation_type, task_version=task_version,
                          info_layout=info_layout, excitation=excitation, tones=tones, lock_in=lock_in, **fixed)
        self.task = make_task(vehicle, window_s, settle_fraction, ramp_fraction, max_windows, counter_torque,
                              traction_balance, timestep, ranges, w_error, w_slip, w_comfort, w_time,
                              macro_slip_penalty, macro_slip_ratio, macro_slip_floor, shaping,
                              action_type=action_type, observation_type=observation_type,
                              task_version=task_version, info_layout=info_layout, excitation=excitation,
                              tones=tones, lock_in=lock_in, **fixed)
        self.width = check_int("width", width, 16, 4096)
        self.height = check_int("height", height, 16, 4096)
        if render_mode is not None:
            check_choice("render_mode", render_mode, self.metadata["render_modes"])
        self.render_mode = render_mode
        self.limits = self.task.limits
        self.action_space = self.task.action_space
        self.observation_space = self.task.observation_space
        self.metadata = {**self.metadata, "render_fps": max(1, int(round(1.0 / self.task.window_s)))}
        self._sims: dict[str, Simulation] = {}
        self._sim: Simulation | None = None
        self.episode: Episode | None = None
        self._renderers: dict[int, mujoco.Renderer] = {}  # rgb_array: id(model) -> its renderer, one a load case
        self._viewer = None
        self._viewer_sim: Simulation | None = None  # the simulation the human viewer shows
        self._warned_display = False
        self._warned_cut = False

    # ------------------------------------------------------------------ episode
    def _simulation(self, load_case: str) -> Simulation:
        if load_case not in self._sims:
            self._sims[load_case] = Simulation(self.task.model(load_case))
        return self._sims[load_case]

    def _note_cut_episode(self) -> None:
        """Warn (once an env) where the episode ending now was cut unscored at the id's registered TimeLimit
        (``max_episode_steps``) while the task's horizon ``max_windows`` lies beyond it: gym.make applies the
        registered limit unless given ``max_episode_steps``, and a truncation there scores no estimate."""
        episode, spec = self.episode, self.spec
        if self._warned_cut or episode is None or episode.done or spec is None or spec.id not in gym.registry:
            return
        limit = gym.spec(spec.id).max_episode_steps
        if limit is not None and episode.windows == limit < self.task.max_windows:
            gym.logger.warn(f"an episode ended unscored at step {limit}, the TimeLimit registered with {spec.id} "
                            f"(max_episode_steps={limit}), before the task's horizon max_windows="
                            f"{self.task.max_windows} scores its estimate: make it with gym.make({spec.id!r}, "
                            f"max_windows={self.task.max_windows}, max_episode_steps={self.task.max_windows})")
            self._warned_cut = True

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        self._note_cut_episode()
        self.episode = None  # a reset that raises leaves an env that refuses to step
        if seed is not None and not (is_int(seed) and seed >= 0):  # Gymnasium takes True as seed 1
            raise ValueError(f"seed must be None or an int >= 0, got {seed!r} ({type(seed).__name__})")
        super().reset(seed=None if seed is None else int(seed))  # a numpy integer as the int it holds
        episode = self.task.new_episode(self.np_random, options)
        sim = self._simulation(episode.scenario.load_case)
        self._sim = None
        sim.reset(episode.physics)
        m = sim.run_window(episode.drive, self.task.window_s, self.task.settle_s, self.task.ramp_s)
        obs, info = self.task.after_reset(episode, m)
        self._sim, self.episode = sim, episode
        if self.render_mode == "human":
            self.render()
        return obs, info

    def step(self, action):
        if self.episode is None or self._sim is None:
            raise RuntimeError("call reset() (successfully) before step()")
        decoded = self.task.decode(self.episode, action)
        if decoded.stop:  # the measurement ends now: no window is run
            out = self.task.after_stop(self.episode)
        else:
            out = self._run_step(decoded)
        if self.render_mode == "human":
            self.render()
        return out

    def _run_step(self, decoded: DecodedAction) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        """Run one window with the decoded drive and score it (a diverged window terminates)."""
        try:
            m = self._sim.run_window(self.episode.drive, self.task.window_s, self.task.settle_s, self.task.ramp_s)
            diverged = self._diverged(m)
        except SimulationDiverged:
            m, diverged = self.episode.last, True
        return self.task.after_step(self.episode, m, decoded, diverged)

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
            renderer = self._renderers.get(id(model))
            if renderer is None:  # built once per load case's model (about a second each)
                renderer = self._renderers[id(model)] = mujoco.Renderer(model, self.height, self.width)
            renderer.update_scene(data, camera="side")
            return renderer.render()
        if not display_available():
            if not self._warned_display:
                gym.logger.warn("render_mode='human' needs a display (DISPLAY/WAYLAND_DISPLAY); nothing is shown")
                self._warned_display = True
            return None
        if self._viewer is not None and self._viewer_sim is not self._sim:  # another load case: its own model
            self._close_viewer()
        if self._viewer is None:
            viewer = importlib.import_module("mujoco.viewer")
            self._viewer, self._viewer_sim = viewer.launch_passive(model, data), self._sim
        self._viewer.sync()
        return None

    def _close_viewer(self) -> None:
        if self._viewer is not None:
            self._viewer.close()
        self._viewer, self._viewer_sim = None, None

    def close(self) -> None:
        for renderer in self._renderers.values():
            renderer.close()
        self._renderers.clear()
        self._close_viewer()
