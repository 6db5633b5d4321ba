"""Batched vector environment: N torque-interrogation envs stepped by one ``mujoco.batch.Batch``.

``gym.make_vec("CofGym/TorqueInterrogation-v1", num_envs=N, vectorization_mode="vector_entry_point")``
returns a :class:`TorqueInterrogationVectorEnv`. It composes the same task as the single env
(:class:`~cof_gym.task.InterrogationTask`: scenario draws, ground truth, reward, observation, info,
one :class:`~cof_gym.task.Episode` per sub-env) with batched physics: each window, the N simulations
are rows of one batch, stepped by a single ``Batch.step(nstep=...)`` on ``num_threads`` threads. The
native passive callback is C, so the batch runs without the GIL.

Results are bit-identical to ``gym.make_vec(..., vectorization_mode="sync")`` (N single envs made with
``gym.make``, sub-env i seeded ``seed + i``, next-step autoreset, infos merged by
:meth:`gymnasium.vector.VectorEnv._add_info`), at any thread count.

Each simulation runs on the model of its episode's load case (``Batch.set_models``); the empty and
laden wagons are compiled from one structure, so they share the batch's state layout.
"""

from __future__ import annotations

import os
import time
from dataclasses import fields
from typing import Any, Mapping, Sequence

import gymnasium as gym
import mujoco
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space
from mujoco.batch import Batch, SimulationError

from cof_gym.envs.torque_interrogation import make_task, window_diverged
from cof_gym.task import Episode
from cof_gym.task.interface import DecodedAction
from cof_gym.physics.native import layout
from cof_gym.physics.native.build import install_callback
from cof_gym.physics.simulation import (SimulationDiverged, begin_window, initial_state, initial_userdata, read_window,
                                        state_is_finite)
from cof_gym.validation import check_int, is_int

_BADQACC = int(mujoco.mjtWarning.mjWARN_BADQACC)
_MAGIC = layout.OFFSETS["MAGIC"]

# one sub-env's result: obs, reward, terminated, truncated, info
StepResult = tuple[np.ndarray, float, bool, bool, dict]
AUTORESET_MODES = (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP, AutoresetMode.DISABLED)
MAX_NUM_ENVS = 4096  # simulations in one batch
MAX_NUM_THREADS = 256  # threads of the batch
MAX_EPISODE_STEPS_LIMIT = 2**31 - 1  # the largest max_episode_steps (a TimeLimit; the task's horizon is shorter)
NO_TIME_LIMIT = -1  # max_episode_steps that applies no TimeLimit (gymnasium's make and make_vec read it so)


def _autoreset_mode(value: AutoresetMode | str) -> AutoresetMode:
    """One of :data:`AUTORESET_MODES` (the enum or its value); ``ValueError`` in one line otherwise."""
    try:
        mode = AutoresetMode(value)
    except ValueError:
        mode = None
    if mode not in AUTORESET_MODES:
        raise ValueError(f"autoreset_mode must be one of {[m.value for m in AUTORESET_MODES]} "
                         f"(gymnasium.vector.AutoresetMode), got {value!r}")
    return mode


def _is_seed(value: Any) -> bool:
    """An int >= 0 (a numpy integer too), not a bool: what ``gymnasium.utils.seeding.np_random`` takes."""
    return is_int(value) and value >= 0


class TorqueInterrogationVectorEnv(gym.vector.VectorEnv):
    """``num_envs`` torque-interrogation environments on one ``mujoco.batch.Batch``.

    Args:
        num_envs: number of sub-environments (simulations), an int in [1, 4096] (:data:`MAX_NUM_ENVS`).
        num_threads: threads of the batch, an int in [1, 256] (:data:`MAX_NUM_THREADS`); default
            ``min(num_envs, os.cpu_count(), 256)``.
        max_episode_steps: a ``TimeLimit`` (``gym.make_vec`` passes the spec's), an int in [1, 2**31 - 1],
            applied per sub-env exactly as ``gymnasium.wrappers.TimeLimit`` does; None or -1 (as
            ``gym.make(..., max_episode_steps=-1)``): the task's horizon ``max_windows`` ends episodes. One below
            ``max_windows`` truncates episodes unscored (a warning says so).
        **kwargs: the arguments of :class:`TorqueInterrogationEnv` (vehicle, window_s, scenario fields...).

    ``autoreset_mode`` (:data:`AUTORESET_MODES`, declared in ``metadata["autoreset_mode"]``), as
    gymnasium's vector envs: ``NEXT_STEP`` (default) resets a sub-env at the step after it terminated
    or truncated (its action is ignored, reward 0, the info is the reset's); ``SAME_STEP`` resets it
    within the step that ended it (the observation and info are the reset's; the last ones are in
    ``info["final_obs"]`` / ``info["final_info"]``, masked by ``info["_final_obs"]``); ``DISABLED``
    never resets by itself (``reset(options={"reset_mask": ...})``).
    ``reset(options={"reset_mask": mask, ...})`` resets only the masked sub-envs; other options are
    passed to every reset sub-env (scenario fields, as for the single env). ``options`` is a mapping or
    None; ``seed`` None, an int >= 0 (sub-env i seeded ``seed + i``) or a sequence of ``num_envs`` ints
    >= 0 or None (a bool is no seed).
    Integer arguments are ints (a numpy integer too), never bools; anything else raises ``ValueError``
    naming the argument and its range.

    torchrl's ``GymWrapper`` takes this env (or the sync one) with ``autoreset_mode=SAME_STEP`` and
    ``info_layout="flat"`` (its reader stacks each info key into a tensor: nested dicts and strings
    fail there), or with ``autoreset_mode=DISABLED`` in either layout (torchrl then reads no info).

    Divergence is detected per simulation as in the single env (bad-acceleration warning, non-finite
    state or measurement: ``info["diverged"]``, the episode terminates). A simulation in which MuJoCo
    raises an error, or whose state MuJoCo auto-reset (cof_gym's userdata marker lost), is treated as
    diverged too instead of stopping the whole batch.
    """

    metadata: dict[str, Any] = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(self, num_envs: int = 1, num_threads: int | None = None, max_episode_steps: int | None = None,
                 render_mode: str | None = None, autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
                 **kwargs: Any) -> None:
        self.autoreset_mode = _autoreset_mode(autoreset_mode)
        num_envs = check_int("num_envs", num_envs, 1, MAX_NUM_ENVS)
        if num_threads is None:
            num_threads = min(num_envs, os.cpu_count() or 1, MAX_NUM_THREADS)
        num_threads = check_int("num_threads", num_threads, 1, MAX_NUM_THREADS)
        if is_int(max_episode_steps) and max_episode_steps == NO_TIME_LIMIT:
            max_episode_steps = None  # as gym.make(..., max_episode_steps=-1): the task's horizon alone
        elif max_episode_steps is not None:
            max_episode_steps = check_int("max_episode_steps", max_episode_steps, 1, MAX_EPISODE_STEPS_LIMIT)
        if render_mode is not None:
            raise ValueError("the batched vector env does not render; use gym.make_vec(..., "
                             "vectorization_mode='sync', render_mode=...) to render sub-environments")
        self.num_envs = num_envs
        self.num_threads = num_threads
        self.max_episode_steps = max_episode_steps
        self.render_mode = None
        self.task = make_task(**kwargs)
        if max_episode_steps is not None and max_episode_steps < self.task.max_windows:
            gym.logger.warn(f"max_episode_steps={max_episode_steps} (gym.make_vec passes the spec's unless given) "
                            f"ends every episode before the task's horizon max_windows={self.task.max_windows} "
                            f"scores its estimate: pass max_episode_steps={self.task.max_windows} (or -1)")
        self.metadata = {**type(self).metadata, "render_fps": max(1, int(round(1.0 / self.task.window_s))),
                         "autoreset_mode": self.autoreset_mode}
        self.single_action_space = self.task.action_space
        self.single_observation_space = self.task.observation_space
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.episodes: list[Episode | None] = [None] * num_envs
        self._np_randoms: list[np.random.Generator | None] = [None] * num_envs

        base = self.task.model(self.task.ranges.load_cases[-1])
        install_callback()  # before the batch exists; process-global and idempotent
        self._batch = Batch(base.model, num_envs, nthread=self.num_threads)
        self._models: list[mujoco.MjModel] = [base.model] * num_envs
        self._batch.set_models(self._models)
        self._qpos = self._batch.bind("qpos")
        self._qvel = self._batch.bind("qvel")
        self._ud = self._batch.bind("userdata")
        self._time = self._batch.bind("time")
        self._nstep = int(round(self.task.window_s / float(base.model.opt.timestep)))

        self._observations = np.zeros(self.observation_space.shape, dtype=self.single_observation_space.dtype)
        self._rewards = np.zeros(num_envs, dtype=np.float64)
        self._terminations = np.zeros(num_envs, dtype=np.bool_)
        self._truncations = np.zeros(num_envs, dtype=np.bool_)
        self._autoreset_envs = np.zeros(num_envs, dtype=np.bool_)
        self._elapsed_steps = np.zeros(num_envs, dtype=np.int64)
        self._started = np.zeros(num_envs, dtype=np.bool_)
        self.step_seconds = 0.0  # wall time inside Batch.step (for benchmarks)

    # ------------------------------------------------------------------ core
    def _advance(self, resets: dict[int, tuple[int | None, dict | None]],
                 actions: dict[int, Any]) -> dict[int, StepResult]:
        """Reset the sub-envs in ``resets`` (index -> (seed, options)) and step those in ``actions``
        (index -> action), all in one batch call. Returns each one's (obs, reward, terminated,
        truncated, info); a reset's reward is 0 and its flags False, as in next-step autoreset."""
        checked = self._checked_actions(resets, actions)  # raises before any state changes
        resets = {int(i): r for i, r in resets.items()}
        reset_ids = sorted(resets)
        self._reset_rows(resets)
        decoded: dict[int, DecodedAction] = {i: self.task.decode(self.episodes[i], checked[i]) for i in checked}
        stopping = sorted(i for i in checked if decoded[i].stop)  # a stop runs no window
        active = sorted(reset_ids + [i for i in checked if not decoded[i].stop])
        failed = self._run_windows(active)
        results: dict[int, StepResult] = {}
        for i in stopping:
            results[i] = self._limit(i, self.task.after_stop(self.episodes[i]))
        for i in active:
            results[i] = self._after_reset(i, failed) if i in resets else self._after_step(i, decoded[i], failed)
        return results

    def _checked_actions(self, resets: dict[int, Any], actions: dict[int, Any]) -> dict[int, np.ndarray]:
        """Each stepped sub-env's action as the task checks it; a sub-env reset and stepped at once, or stepped
        before its first reset, raises."""
        overlap = set(resets) & set(actions)
        if overlap:
            raise ValueError(f"sub-env(s) {sorted(overlap)} cannot be reset and stepped at once")
        for i in actions:
            if not self._started[i]:
                raise RuntimeError(f"sub-env {i}: call reset() before step()")
        return {int(i): self.task.check_action(a) for i, a in actions.items()}

    def _reset_rows(self, resets: dict[int, tuple[int | None, dict | None]]) -> None:
        """The task draws each reset sub-env's scenario (from its own generator, seeded as gymnasium.Env.reset
        seeds np_random); its simulation row is reset to that episode's model and initial state."""
        reset_ids = sorted(resets)
        self._started[reset_ids] = False  # until its row is reset (a draw may raise on bad options)
        for i in reset_ids:
            seed, options = resets[i]
            if seed is not None or self._np_randoms[i] is None:
                self._np_randoms[i], _ = seeding.np_random(seed)
            self.episodes[i] = None
            self.episodes[i] = self.task.new_episode(self._np_randoms[i], options)
        changed = False
        for i in reset_ids:
            model = self.episodes[i].built.model
            if self._models[i] is not model:
                self._models[i] = model
                changed = True
        if changed:
            self._batch.set_models(self._models)
        if not reset_ids:
            return
        ids = np.asarray(reset_ids, dtype=np.int32)
        self._batch.reset(ids, stage=mujoco.mjtStage.mjSTAGE_NONE)  # defaults, time 0, warnings cleared
        for i in reset_ids:
            episode = self.episodes[i]
            initial_state(episode.built, episode.physics.op.speed_m_s, self._qpos[i], self._qvel[i])
            self._ud[i] = initial_userdata(episode.built, episode.physics)
        self._batch.forward(ids)  # as Simulation.reset's mj_forward (the callback starts there)
        self._started[ids] = True
        self._elapsed_steps[ids] = 0

    def _run_windows(self, active: list[int]) -> set[int]:
        """One window of the sub-envs ``active`` in one batch call (a reset's baseline window, a step's driven
        one); returns those in which MuJoCo raised."""
        task = self.task
        for i in active:
            begin_window(self._ud[i], float(self._time[i]), self.episodes[i].drive, task.ramp_s, task.settle_s)
        if not active:
            return set()
        ids = None if len(active) == self.num_envs else np.asarray(active, dtype=np.int32)
        install_callback()  # idempotent: back in place if anything replaced the process-global callback since
        t0 = time.perf_counter()
        failed: set[int] = set()
        try:
            self._batch.step(ids, nstep=self._nstep)
        except SimulationError as err:
            failed = {int(i) for i in err.ids}
        self.step_seconds += time.perf_counter() - t0
        return failed

    def _after_reset(self, i: int, failed: set[int]) -> StepResult:
        """Sub-env ``i``'s first observation from its baseline window (a MuJoCo error there raises)."""
        if i in failed:
            raise RuntimeError(f"sub-env {i}: MuJoCo raised in the baseline window: {self._batch.error(i)}")
        if self._ud[i][_MAGIC] != layout.MAGIC:  # MuJoCo's auto-reset wiped the userdata: it diverged
            raise SimulationDiverged(f"sub-env {i}: the simulation diverged in the baseline window (MuJoCo reset it)")
        obs, info = self.task.after_reset(self.episodes[i], read_window(self._ud[i]))
        return obs, 0.0, False, False, info

    def _after_step(self, i: int, decoded: DecodedAction, failed: set[int]) -> StepResult:
        """Sub-env ``i``'s step result from its driven window; a window MuJoCo raised in, or whose userdata its
        auto-reset wiped, or that diverged, ends the episode as diverged."""
        episode, ud = self.episodes[i], self._ud[i]
        if i in failed or ud[_MAGIC] != layout.MAGIC:  # MuJoCo error, or its auto-reset wiped userdata
            m, diverged = episode.last, True
        else:
            m = read_window(ud)
            bad_qacc = self._batch.warning[i, _BADQACC, 1] > 0  # mjWarningStat: (lastinfo, number)
            diverged = window_diverged(m, bool(bad_qacc), state_is_finite(self._qpos[i], self._qvel[i], ud))
        return self._limit(i, self.task.after_step(episode, m, decoded, diverged))

    def _limit(self, i: int, result: StepResult) -> StepResult:
        """Count sub-env i's step and apply ``max_episode_steps`` as gymnasium's TimeLimit does."""
        obs, reward, terminated, truncated, info = result
        self._elapsed_steps[i] += 1
        if self.max_episode_steps is not None and self._elapsed_steps[i] >= self.max_episode_steps:
            truncated = True
        return obs, reward, terminated, truncated, info

    @staticmethod
    def _seeds(seed: int | Sequence[int | None] | None, n: int) -> list[int | None]:
        """Each sub-env's seed: None, ``seed + i``, or the sequence's i-th (``ValueError`` for anything else)."""
        if seed is None:
            return [None] * n
        if _is_seed(seed):
            return [int(seed) + i for i in range(n)]
        if isinstance(seed, (str, bytes)) or not isinstance(seed, (Sequence, np.ndarray)):
            raise ValueError(f"seed must be None, an int >= 0 or a sequence of num_envs={n} ints >= 0 (or None), "
                             f"got {seed!r} ({type(seed).__name__})")
        seeds = list(seed)
        if len(seeds) != n:
            raise ValueError(f"If seeds are passed as a list the length must match num_envs={n} "
                             f"but got length={len(seeds)}.")
        for i, s in enumerate(seeds):
            if s is not None and not _is_seed(s):
                raise ValueError(f"seed[{i}] must be an int >= 0 or None, got {s!r} ({type(s).__name__})")
        return [None if s is None else int(s) for s in seeds]

    # ------------------------------------------------------------------ gymnasium API
    def _check_open(self) -> None:
        if self.closed:
            raise gym.error.ClosedEnvironmentError("the vector env is closed: make a new one to reset or step")

    def reset(self, *, seed: int | Sequence[int | None] | None = None, options: dict[str, Any] | None = None):
        """Reset all sub-envs (or ``options["reset_mask"]``'s); sub-env i is seeded ``seed + i``."""
        self._check_open()
        seeds = self._seeds(seed, self.num_envs)
        if options is not None and not isinstance(options, Mapping):
            raise ValueError(f"options must be a dict (a mapping of scenario fields, and 'reset_mask') or None, "
                             f"got {options!r} ({type(options).__name__})")
        options = dict(options) if options is not None else None
        mask = np.ones(self.num_envs, dtype=np.bool_)
        if options is not None and "reset_mask" in options:
            mask = options.pop("reset_mask")
            if not isinstance(mask, np.ndarray):
                raise TypeError(f"`options['reset_mask']` must be a numpy array, got {type(mask)}")
            if mask.shape != (self.num_envs,):
                raise ValueError(f"`options['reset_mask']` must have shape `({self.num_envs},)`, got {mask.shape}")
            if mask.dtype != np.bool_:
                raise TypeError(f"`options['reset_mask']` must have `dtype=np.bool_`, got {mask.dtype}")
            if not mask.any():
                raise ValueError(f"`options['reset_mask']` must contain at least one True value, got reset_mask={mask}")
        self._terminations[mask] = False
        self._truncations[mask] = False
        self._autoreset_envs[mask] = False
        self._rewards[mask] = 0.0
        results = self._advance({i: (seeds[i], options) for i in np.flatnonzero(mask)}, {})
        infos: dict[str, Any] = {}
        for i, (obs, _, _, _, info) in sorted(results.items()):
            self._observations[i] = obs
            infos = self._add_info(infos, info, i)
        return self._observations.copy(), infos

    def step(self, actions):
        """Step every sub-env; ended ones are reset as ``autoreset_mode`` says (next step: those that
        ended at the previous step are reset instead; same step: those that end now are reset too)."""
        self._check_open()
        actions = np.asarray(actions)
        if actions.shape != self.action_space.shape:
            raise ValueError(f"actions must have shape {self.action_space.shape}, got {actions.shape}")
        resetting = self._autoreset_envs if self.autoreset_mode == AutoresetMode.NEXT_STEP else \
            np.zeros(self.num_envs, dtype=np.bool_)
        results = self._advance({i: (None, None) for i in np.flatnonzero(resetting)},
                                {i: actions[i] for i in np.flatnonzero(~resetting)})
        ended = [i for i, r in results.items() if r[2] or r[3]]
        restarted = self._advance({i: (None, None) for i in ended}, {}) \
            if self.autoreset_mode == AutoresetMode.SAME_STEP and ended else {}
        infos: dict[str, Any] = {}
        for i in range(self.num_envs):
            obs, self._rewards[i], self._terminations[i], self._truncations[i], info = results[i]
            if i in restarted:
                infos = self._add_info(infos, {"final_obs": obs, "final_info": info}, i)
                obs, _, _, _, info = restarted[i]
            self._observations[i] = obs
            infos = self._add_info(infos, info, i)
        self._autoreset_envs = np.logical_or(self._terminations, self._truncations)
        return (self._observations.copy(), self._rewards.copy(), self._terminations.copy(),
                self._truncations.copy(), infos)

    def get_attr(self, name: str) -> tuple[Any, ...]:
        """An attribute of every sub-env's episode (e.g. ``scenario``, ``truth``; None before its first reset):
        the batch has no sub-env objects, so a name :class:`~cof_gym.task.Episode` does not have is an
        ``AttributeError`` naming those it has."""
        episode_fields = [f.name for f in fields(Episode)]
        if name not in episode_fields:
            raise AttributeError(f"get_attr reads each sub-env's episode (the batch has no sub-env objects); "
                                 f"{name!r} is none of its fields {episode_fields}")
        return tuple(None if episode is None else getattr(episode, name) for episode in self.episodes)

    def close_extras(self, **kwargs: Any) -> None:
        # the bound arrays are views of the batch's state rows: drop them with it
        self._qpos = self._qvel = self._ud = self._time = None  # type: ignore[assignment]
        self._batch = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        env_id = self.spec.id if self.spec is not None else "TorqueInterrogation"
        return f"TorqueInterrogationVectorEnv({env_id}, num_envs={self.num_envs}, num_threads={self.num_threads})"
