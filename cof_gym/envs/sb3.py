"""stable-baselines3 ``VecEnv``s of the torque-interrogation environments.

Two routes, same API (:func:`make_sb3_vec_env`):

- ``backend="batch"`` (default): :class:`BatchedSB3VecEnv`, an SB3 ``VecEnv`` over the batched
  :class:`~cof_gym.envs.vector.TorqueInterrogationVectorEnv` (one ``mujoco.batch.Batch``, the
  simulations stepped on ``num_threads`` threads without the GIL), in this process.
- ``backend="subproc"`` / ``"dummy"``: SB3's own ``SubprocVecEnv`` / ``DummyVecEnv`` of single envs
  through :func:`stable_baselines3.common.env_util.make_vec_env` (each wrapped in ``Monitor``).

SB3's conventions are kept: an episode that ends is reset in the same step; the returned observation
is the new episode's first, the last one is in ``info["terminal_observation"]``,
``info["TimeLimit.truncated"]`` flags truncation without termination, and ``info["episode"]`` holds
the episode's return, length and time as ``Monitor`` writes them (so SB3's ``ep_rew_mean`` logging
works). Seeds and options are those of ``VecEnv.seed`` / ``set_options``, used at the next
``reset()``: with the same seed both routes produce the same episodes (sub-env i is seeded
``seed + i`` in both).
"""

from __future__ import annotations

import time
from copy import deepcopy
from typing import Any, Sequence

import gymnasium as gym
import numpy as np
from stable_baselines3.common.monitor import Monitor
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecEnv
from stable_baselines3.common.vec_env.base_vec_env import VecEnvIndices, VecEnvObs, VecEnvStepReturn

from cof_gym.envs.vector import TorqueInterrogationVectorEnv

BACKENDS = ("batch", "subproc", "dummy")


class BatchedSB3VecEnv(VecEnv):
    """SB3 ``VecEnv`` adapter over a :class:`TorqueInterrogationVectorEnv`.

    A step runs every sub-env's window in one batch call; the sub-envs whose episode ended are then
    reset (their baseline window is a second batch call over those sub-envs only)."""

    def __init__(self, venv: TorqueInterrogationVectorEnv) -> None:
        if not isinstance(venv, TorqueInterrogationVectorEnv):
            raise TypeError(f"venv must be a TorqueInterrogationVectorEnv, got {type(venv).__name__}")
        self.venv = venv
        super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)
        n = venv.num_envs
        self._actions: np.ndarray | None = None
        self._obs = np.zeros((n, *self.observation_space.shape), dtype=self.observation_space.dtype)
        self._ep_rewards: list[list[float]] = [[] for _ in range(n)]
        self._t_start = time.time()
        self._needs_reset = True

    # ------------------------------------------------------------------ VecEnv API
    def reset(self) -> VecEnvObs:
        resets = {i: (self._seeds[i], self._options[i] if self._options[i] else None) for i in range(self.num_envs)}
        results = self.venv._advance(resets, {})
        for i, (obs, _, _, _, info) in results.items():
            self._obs[i] = obs
            self.reset_infos[i] = info
            self._ep_rewards[i] = []
        self._reset_seeds()
        self._reset_options()
        self._needs_reset = False
        return self._obs.copy()

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions)

    def step_wait(self) -> VecEnvStepReturn:
        if self._needs_reset:
            raise RuntimeError("call reset() before step()")
        if self._actions is None:
            raise RuntimeError("step_wait() without step_async()")
        actions, self._actions = self._actions, None
        shape = (self.num_envs, *self.action_space.shape)
        if actions.shape != shape:
            raise ValueError(f"actions must have shape {shape}, got {actions.shape}")
        n = self.num_envs
        results = self.venv._advance({}, {i: actions[i] for i in range(n)})
        rewards = np.zeros(n, dtype=np.float32)
        dones = np.zeros(n, dtype=bool)
        infos: list[dict[str, Any]] = []
        for i in range(n):
            obs, reward, terminated, truncated, info = results[i]
            rewards[i] = reward
            dones[i] = terminated or truncated
            info["TimeLimit.truncated"] = truncated and not terminated
            self._ep_rewards[i].append(float(reward))
            if dones[i]:
                info["terminal_observation"] = obs
                ep_rew = sum(self._ep_rewards[i])
                info["episode"] = {"r": round(ep_rew, 6), "l": len(self._ep_rewards[i]),
                                   "t": round(time.time() - self._t_start, 6)}
                self._ep_rewards[i] = []
            self._obs[i] = obs
            infos.append(info)
        done_ids = np.flatnonzero(dones)
        if done_ids.size:
            for i, (obs, _, _, _, info) in self.venv._advance({int(i): (None, None) for i in done_ids}, {}).items():
                self._obs[i] = obs
                self.reset_infos[i] = info
        return self._obs.copy(), rewards, dones, infos

    def close(self) -> None:
        self.venv.close()

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        if attr_name == "render_mode":
            return [None for _ in self._get_indices(indices)]
        return [getattr(self.venv.envs[i], attr_name) for i in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        for i in self._get_indices(indices):
            setattr(self.venv.envs[i], attr_name, value)

    def env_method(self, method_name: str, *method_args, indices: VecEnvIndices = None, **method_kwargs) -> list[Any]:
        return [getattr(self.venv.envs[i], method_name)(*method_args, **method_kwargs)
                for i in self._get_indices(indices)]

    def env_is_wrapped(self, wrapper_class: type[gym.Wrapper], indices: VecEnvIndices = None) -> list[bool]:
        """The wrappers this adapter emulates count: ``Monitor`` (its episode info) and ``TimeLimit``
        (when the vector env has ``max_episode_steps``)."""
        emulated = [Monitor] + ([gym.wrappers.TimeLimit] if self.venv.max_episode_steps is not None else [])
        wrapped = any(issubclass(w, wrapper_class) for w in emulated)
        return [wrapped for _ in self._get_indices(indices)]

    def get_images(self) -> Sequence[np.ndarray | None]:
        return [None for _ in range(self.num_envs)]

    def __repr__(self) -> str:
        return f"BatchedSB3VecEnv({self.venv!r})"


def _env_id_for_subprocess(env_id: str) -> str:
    """``module:Id`` form, which makes a spawned worker import cof_gym (which registers the ids)."""
    if ":" not in env_id and env_id.startswith("CofGym/"):
        return "cof_gym:" + env_id
    return env_id


def make_sb3_vec_env(env_id: str = "CofGym/TorqueInterrogation-v0", n_envs: int = 1, seed: int | None = None,
                     backend: str = "batch", num_threads: int | None = None, start_method: str | None = None,
                     **kwargs: Any) -> VecEnv:
    """An SB3 ``VecEnv`` of ``n_envs`` environments ``env_id`` (env kwargs in ``kwargs``).

    ``backend``: "batch" (the batched vector env, ``num_threads`` threads, default min(n_envs, CPUs)),
    "subproc" (SB3 ``SubprocVecEnv``, one process per env; ``start_method`` as SB3's) or "dummy"
    (SB3 ``DummyVecEnv``, sequential). ``seed``: sub-env i is seeded ``seed + i`` at the first reset."""
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {list(BACKENDS)}, got {backend!r}")
    if backend == "batch":
        import cof_gym  # noqa: F401  (registers the ids)

        venv = gym.make_vec(env_id.split(":", 1)[-1], num_envs=n_envs, vectorization_mode="vector_entry_point",
                            num_threads=num_threads, **kwargs)
        env = BatchedSB3VecEnv(venv)
        if seed is not None:
            env.action_space.seed(seed)
        env.seed(seed)  # as make_vec_env: None draws a random base seed
        return env
    if num_threads is not None:
        raise ValueError("num_threads applies to backend='batch' only")
    from stable_baselines3.common.env_util import make_vec_env

    vec_cls = SubprocVecEnv if backend == "subproc" else DummyVecEnv
    vec_kwargs = {"start_method": start_method} if backend == "subproc" and start_method else None
    return make_vec_env(_env_id_for_subprocess(env_id) if backend == "subproc" else env_id, n_envs=n_envs,
                        seed=seed, env_kwargs=deepcopy(kwargs), vec_env_cls=vec_cls, vec_env_kwargs=vec_kwargs)
