"""A trained Stable-Baselines3 or sb3-contrib policy behind the :class:`cof_gym.agents.base.Agent` protocol.

``SB3Agent.load(path)`` takes what ``cof-gym train`` writes (``OUT/model.zip`` with
``OUT/vecnormalize.pkl`` beside it, the directory ``OUT``, ``OUT/best`` or a checkpoint
``OUT/checkpoints/ppo_<N>_steps.zip`` with its ``ppo_vecnormalize_<N>_steps.pkl``), what RL Zoo writes
(``<run>/<env>.zip`` with ``<run>/<env>/vecnormalize.pkl``, ``config.yml`` and ``args.yml``, or the run
directory itself), or any model an algorithm's ``save`` wrote. The algorithm that loads it is read from the
saved policy's class (:data:`ALGORITHMS`, one row per policy module: PPO, A2C and TRPO share one), so a
policy of any of them plays in ``cof-gym evaluate`` (``sb3:PATH``); a recurrent policy (RecurrentPPO) keeps
its LSTM state through an episode and starts it afresh at every reset. The observation statistics are
loaded frozen (``training=False``, ``norm_reward=False``), as SB3 and RL Zoo evaluate.
"""

from __future__ import annotations

import importlib
import json
import re
from pathlib import Path
from types import MappingProxyType
from typing import Any, Iterable, Mapping

import gymnasium as gym
import numpy as np

import cof_gym
from cof_gym.agents.base import configuration_note, outside_training_note, registered_ranges, without_defaults
from cof_gym.agents.policy_files import META_NAME, MODEL_NAMES, VECNORMALIZE_NAME  # noqa: F401 - read from here too

DEFAULT_ENV_ID = cof_gym.WAGON_V1_ENV_ID  # the shipped policy was trained on v1
ZOO_CONFIG_NAME, ZOO_ARGS_NAME = "config.yml", "args.yml"  # RL Zoo's hyperparameters and arguments of a run

# the saved policy's module -> the algorithm ("module:Class") that loads it; only the policy acts, so one
# algorithm serves every algorithm sharing a policy class (PPO's loads A2C's and TRPO's, TD3's DDPG's)
ALGORITHMS: Mapping[str, str] = MappingProxyType({
    "stable_baselines3.common.policies": "stable_baselines3:PPO",  # PPO, A2C, sb3-contrib's TRPO
    "stable_baselines3.sac.policies": "stable_baselines3:SAC",
    "stable_baselines3.td3.policies": "stable_baselines3:TD3",  # TD3, DDPG
    "sb3_contrib.common.recurrent.policies": "sb3_contrib:RecurrentPPO",
    "sb3_contrib.tqc.policies": "sb3_contrib:TQC",
    "sb3_contrib.crossq.policies": "sb3_contrib:CrossQ",
    "sb3_contrib.ars.policies": "sb3_contrib:ARS",
})


def resolve_model_path(path: str | Path) -> Path:
    """The model zip named by ``path``: a zip file, a path without the ``.zip`` suffix, or a directory
    holding ``model.zip`` (a training output), RL Zoo's ``<env>.zip`` (a run directory: the zip beside the
    directory of its statistics and arguments) or ``best_model.zip`` (``OUT/best``, RL Zoo's best model)."""
    p = Path(path)
    if p.is_dir():
        zoo = [z for z in sorted(p.glob("*.zip")) if (z.with_suffix("") / ZOO_ARGS_NAME).is_file()]
        candidates = [p / MODEL_NAMES[0], *zoo[:1], *(p / name for name in MODEL_NAMES[1:])]
        for candidate in candidates:
            if candidate.is_file():
                return candidate
        raise FileNotFoundError(f"no {' or '.join(MODEL_NAMES)} and no RL Zoo model in directory {p}")
    if p.is_file():
        return p
    if p.suffix != ".zip" and p.with_name(p.name + ".zip").is_file():
        return p.with_name(p.name + ".zip")
    raise FileNotFoundError(f"model not found: {p}")


def _saved_data(path: str | Path) -> dict[str, Any]:
    """The data a Stable-Baselines3 model zip saves (its spaces, its policy class...), read without building the
    policy. ``ValueError`` (one line) for a file that is not a zip or a zip that is not a model."""
    from stable_baselines3.common.save_util import load_from_zip_file

    try:
        data, _, _ = load_from_zip_file(path, device="cpu", load_data=True, print_system_info=False)
    except Exception as e:  # noqa: BLE001 - SB3 raises ValueError, zipfile, pickle and torch errors alike
        raise ValueError(f"{path} is not a readable Stable-Baselines3 model ({' '.join(str(e).split())})") from None
    if not data or "observation_space" not in data or "action_space" not in data:
        raise ValueError(f"{path} is a zip file but not a Stable-Baselines3 model (no saved spaces)")
    return data


def model_algorithm(path: str | Path, data: Mapping[str, Any] | None = None) -> str:
    """``"module:Class"`` of the algorithm that loads the model zip ``path`` (its saved ``data`` when already
    read), from its saved policy class (:data:`ALGORITHMS`); ``ValueError`` (one line) for a policy class no row
    names."""
    policy = (data if data is not None else _saved_data(path)).get("policy_class")
    module = getattr(policy, "__module__", None)
    if module not in ALGORITHMS:
        known = ", ".join(sorted({a.partition(":")[2] for a in ALGORITHMS.values()}))
        raise ValueError(f"{path}: its policy class {getattr(policy, '__qualname__', policy)!r} (module {module}) is "
                         f"none of the algorithms cof_gym plays: {known}")
    return ALGORITHMS[module]


def load_algorithm(spec: str) -> Any:
    """The algorithm class ``"module:Class"`` (:data:`ALGORITHMS`)."""
    module, _, name = spec.partition(":")
    return getattr(importlib.import_module(module), name)


def zoo_params_dir(model_path: str | Path) -> Path | None:
    """The directory where RL Zoo saved a run's statistics and arguments for the model ``model_path``:
    ``<run>/<env>/`` for ``<run>/<env>.zip``, or for another model of the run (``best_model.zip``) the one
    subdirectory of ``<run>`` holding ``args.yml``; None outside RL Zoo's layout."""
    model_path = Path(model_path)
    own = model_path.with_suffix("")
    if (own / ZOO_ARGS_NAME).is_file() or (own / VECNORMALIZE_NAME).is_file():
        return own
    runs = [d for d in model_path.parent.glob("*/") if (d / ZOO_ARGS_NAME).is_file()]
    return runs[0] if len(runs) == 1 else None


def vecnormalize_path(model_path: str | Path) -> Path:
    """The VecNormalize statistics saved with a model: ``vecnormalize.pkl`` beside it, or, for an SB3
    checkpoint ``<prefix>_<N>_steps.zip``, ``<prefix>_vecnormalize_<N>_steps.pkl``, or, for an RL Zoo
    model, in its run's statistics directory (:func:`zoo_params_dir`). The path beside the model is
    returned when none exists."""
    model_path = Path(model_path)
    m = re.fullmatch(r"(.*)_(\d+)_steps", model_path.stem)
    if m:
        checkpoint = model_path.with_name(f"{m[1]}_vecnormalize_{m[2]}_steps.pkl")
        if checkpoint.is_file():
            return checkpoint
    beside = model_path.with_name(VECNORMALIZE_NAME)
    zoo = zoo_params_dir(model_path)
    return zoo / VECNORMALIZE_NAME if not beside.is_file() and zoo and (zoo / VECNORMALIZE_NAME).is_file() else beside


def find_train_meta(model_path: str | Path, strict: bool = False) -> dict[str, Any] | None:
    """``train_meta.json`` of the run that produced ``model_path`` (beside it, or one directory up
    for ``OUT/best`` and ``OUT/checkpoints``), or None when there is none. A file that cannot be read or
    holds no JSON object: None, or with ``strict`` a ``ValueError`` (one line) naming the file."""
    model_path = Path(model_path)
    for d in (model_path.parent, model_path.parent.parent):
        f = d / META_NAME
        if f.is_file():
            try:
                meta = json.loads(f.read_text())
            except (OSError, ValueError) as e:  # json.JSONDecodeError and UnicodeDecodeError are ValueErrors
                if strict:
                    raise ValueError(f"{f} cannot be read as JSON ({' '.join(str(e).split())})") from None
                return None
            if not isinstance(meta, dict):
                if strict:
                    raise ValueError(f"{f} holds {type(meta).__name__}, not a JSON object")
                return None
            return meta
    return None


def _read_zoo_yaml(path: Path) -> dict[str, Any]:
    """An RL Zoo ``config.yml`` or ``args.yml`` (a dumped OrderedDict) as a dict, read without running any
    Python object the file names: its OrderedDict and tuples become plain dicts and lists, every other
    Python tag None. ``ValueError`` (one line, naming the file) for a file that is no such mapping."""
    import yaml

    class ZooLoader(yaml.SafeLoader):
        pass

    def python_object(loader: yaml.SafeLoader, suffix: str, node: yaml.Node) -> Any:
        if suffix == "object/apply:collections.OrderedDict" and isinstance(node, yaml.SequenceNode):
            pairs = loader.construct_sequence(node, deep=True)
            return dict(pairs[0]) if pairs else {}
        if suffix == "tuple" and isinstance(node, yaml.SequenceNode):
            return loader.construct_sequence(node, deep=True)
        return None

    ZooLoader.add_multi_constructor("tag:yaml.org,2002:python/", python_object)
    try:
        data = yaml.load(path.read_text(), Loader=ZooLoader)  # a SafeLoader: no object is built
    except (OSError, ValueError, yaml.YAMLError) as e:
        raise ValueError(f"{path} cannot be read as RL Zoo's YAML ({' '.join(str(e).split())})") from None
    if not isinstance(data, dict):
        raise ValueError(f"{path} holds {type(data).__name__}, not RL Zoo's mapping of settings")
    return data


def zoo_training(model_path: str | Path) -> dict[str, Any] | None:
    """What RL Zoo recorded of the run that trained ``model_path``, in ``train_meta.json``'s keys: ``env_id``
    (``args.yml``'s ``env``) and ``env_kwargs`` (``config.yml``'s, then ``args.yml``'s, which RL Zoo let
    override them); None outside RL Zoo's layout (:func:`zoo_params_dir`)."""
    params = zoo_params_dir(model_path)
    if params is None or not (params / ZOO_ARGS_NAME).is_file():
        return None
    args = _read_zoo_yaml(params / ZOO_ARGS_NAME)
    config = _read_zoo_yaml(params / ZOO_CONFIG_NAME) if (params / ZOO_CONFIG_NAME).is_file() else {}
    env_kwargs = {**(config.get("env_kwargs") or {}), **(args.get("env_kwargs") or {})}
    return {"env_id": args.get("env"), "env_kwargs": env_kwargs}


class SpacesOnly(gym.Env):
    """A stand-in env with given spaces, never reset or stepped: SB3 builds a model or loads statistics on it
    without simulating (the checks of ``cof-gym train``, :func:`check_model`)."""

    def __init__(self, observation_space: gym.Space, action_space: gym.Space) -> None:
        self.observation_space, self.action_space = observation_space, action_space


def load_vecnormalize(stats: str | Path, venv: Any) -> Any:
    """``VecNormalize.load(stats, venv)``, with the statistics checked against ``venv``'s observation
    space. ``ValueError`` (one line) naming ``stats`` for a file that is not readable VecNormalize
    statistics or that does not fit ``venv`` (SB3 raises EOFError, pickle errors, AssertionError...)."""
    from stable_baselines3.common.vec_env import VecNormalize

    try:
        vec_normalize = VecNormalize.load(str(stats), venv)
    except Exception as e:  # noqa: BLE001 - pickle, EOF, attribute and assertion errors alike
        raise ValueError(f"{stats} is not usable VecNormalize statistics for this model "
                         f"({type(e).__name__}: {' '.join(str(e).split())})") from None
    if not isinstance(vec_normalize, VecNormalize):
        raise ValueError(f"{stats} holds a {type(vec_normalize).__name__}, not VecNormalize statistics")
    obs_rms = getattr(vec_normalize, "obs_rms", None)
    shape = getattr(venv.observation_space, "shape", None)
    if vec_normalize.norm_obs and shape is not None and getattr(getattr(obs_rms, "mean", None), "shape", None) != shape:
        raise ValueError(f"{stats}: its observation statistics do not have the model's observation shape {shape}")
    return vec_normalize


def check_model(path: str | Path) -> tuple[Any, Any]:
    """Everything :meth:`SB3Agent.load` and ``cof-gym train --resume`` read from a model zip, checked without
    building an env: the zip (its spaces and an algorithm that loads its policy, :func:`model_algorithm`), its
    VecNormalize statistics (when present, loaded on a stand-in of the model's spaces) and its
    ``train_meta.json`` or RL Zoo's ``args.yml`` and ``config.yml`` (when present). Returns the model's
    (observation space, action space); ``ValueError`` (one line, naming the file) otherwise."""
    from stable_baselines3.common.vec_env import DummyVecEnv

    path = Path(path)
    data = _saved_data(path)
    model_algorithm(path, data)
    spaces = data["observation_space"], data["action_space"]
    stats = vecnormalize_path(path)
    if stats.is_file():
        venv = DummyVecEnv([lambda: SpacesOnly(*spaces)])
        load_vecnormalize(stats, venv).close()
    if find_train_meta(path, strict=True) is None:
        zoo_training(path)
    return spaces


def check_model_argument(argument: str) -> None:
    """The checks of ``sb3:PATH`` (and ``ppo:PATH``) before anything is simulated: the path names a model
    (:func:`resolve_model_path`) that :func:`check_model` passes; ``ValueError`` (one line) otherwise."""
    try:
        check_model(resolve_model_path(argument))
    except FileNotFoundError as e:
        raise ValueError(str(e)) from None


def _make_env(full_id: str, adapter: str, **kwargs: Any):
    import gymnasium as gym

    import cof_gym
    from cof_gym.agents.adapters import wrap

    cof_gym.ignore_out_of_date_notice()  # in a subprocess worker too (the CLI's filter is not inherited there)
    return wrap(gym.make(full_id, **kwargs), adapter)


def make_env_fn(env_id: str, env_kwargs: dict[str, Any] | None = None, adapter: str = "absolute"):
    """A picklable env factory for ``make_vec_env``. ``gym.make`` is given ``"cof_gym:<id>"`` so that the
    registration also happens in spawned / forkserver subprocesses (Gymnasium 1.x has no plugin entry points: the
    ``module:Id`` form imports the module, which registers its ids, before the id is looked up). A
    ``max_windows`` other than the registered horizon also moves the TimeLimit (``max_episode_steps``)
    unless that is given too, so that the last estimate is scored by the env itself. ``adapter``:
    :mod:`cof_gym.agents.adapters` (how the policy's output becomes the env's action)."""
    import functools

    from cof_gym.envs.torque_interrogation import make_kwargs

    kwargs = make_kwargs(env_kwargs or {})
    full_id = env_id if ":" in env_id else f"cof_gym:{env_id}"
    return functools.partial(_make_env, full_id, adapter, **kwargs)


class SB3Agent:
    """Deterministic action of a trained Stable-Baselines3 or sb3-contrib policy on the normalised observation
    (a recurrent policy's state carried through the episode)."""

    name = "ppo"  # the algorithm's name, lower case, once loaded
    oracle = False

    def __init__(self, model: Any, vec_normalize: Any | None, env_id: str = DEFAULT_ENV_ID,
                 model_path: Path | None = None, adapter: str = "absolute", limits: Any = None) -> None:
        self.name = type(model).__name__.lower()
        self.model = model
        self.vec_normalize = vec_normalize
        self.env_id = env_id
        self.model_path = model_path
        self.adapter = adapter
        self.limits = limits

    @classmethod
    def load(cls, path: str | Path, env_id: str | None = None, env_kwargs: dict[str, Any] | None = None,
             device: str = "cpu") -> "SB3Agent":
        """Load a model zip (or a training output or RL Zoo run directory, :func:`resolve_model_path`) with the
        algorithm its policy class names (:func:`model_algorithm`) and the VecNormalize statistics saved
        beside it. ``env_id`` and ``env_kwargs`` default to the ones recorded in ``train_meta.json`` or by RL
        Zoo (:func:`zoo_training`); the env is only built to check the spaces and to host the (frozen)
        statistics, it is never stepped."""
        from stable_baselines3.common.vec_env import DummyVecEnv

        model_path = resolve_model_path(path)
        meta = find_train_meta(model_path) or zoo_training(model_path) or {}
        env_id = env_id or meta.get("env_id") or DEFAULT_ENV_ID
        if env_kwargs is None:
            env_kwargs = meta.get("env_kwargs") or {}
        model = load_algorithm(model_algorithm(model_path)).load(model_path, device=device)
        adapter = meta.get("action_adapter", "absolute")
        action_type = env_kwargs.get("action_type", "relative" if adapter in ("incremental", "relative") else "absolute")
        observation_type = env_kwargs.get("observation_type", "window")
        venv = DummyVecEnv([make_env_fn(env_id, env_kwargs, adapter)])
        limits = venv.envs[0].unwrapped.limits
        if model.observation_space.shape != venv.observation_space.shape or \
                model.action_space.shape != venv.action_space.shape:
            venv.close()
            raise ValueError(f"{model_path} was trained on observation {model.observation_space.shape} / action "
                             f"{model.action_space.shape}; {env_id} has {venv.observation_space.shape} / "
                             f"{venv.action_space.shape}")
        stats = vecnormalize_path(model_path)
        vec_normalize = None
        if stats.is_file():
            try:
                vec_normalize = load_vecnormalize(stats, venv)
            except ValueError:
                venv.close()
                raise
            vec_normalize.training = False
            vec_normalize.norm_reward = False
        else:
            import warnings

            warnings.warn(f"no VecNormalize statistics beside {model_path} ({stats.name}): "
                          "the policy will see raw observations", stacklevel=2)
            venv.close()
        agent = cls(model, vec_normalize, env_id=env_id, model_path=model_path, adapter=adapter, limits=limits)
        agent.trained_on = (meta.get("env_id") or env_id, dict(meta.get("env_kwargs") or {}))
        if action_type != "absolute" or observation_type != "window":
            # trained on other action/observation types: applied on the agent's side of a default env
            from cof_gym.agents.adapters import AgentSideInterface

            agent.interface = AgentSideInterface(limits, action_type, observation_type)
        return agent

    def normalize(self, observation: np.ndarray) -> np.ndarray:
        """The observation as the policy saw it in training (frozen statistics)."""
        obs = np.asarray(observation, dtype=np.float32)
        if self.vec_normalize is None:
            return obs
        return np.asarray(self.vec_normalize.normalize_obs(obs), dtype=np.float32)

    interface: Any = None  # AgentSideInterface when the policy was trained on non-default env types
    trained_on: tuple[str, dict[str, Any]] | None = None  # (env id, env kwargs) of its training run
    INTERFACE_KWARGS = ("action_type", "observation_type", "shaping")  # applied agent-side, not the world

    def distribution_note(self, env_id: str, env_kwargs: dict[str, Any],
                          episodes: Iterable[Mapping[str, Any]] = ()) -> str | None:
        """A line saying where an evaluation lies outside the policy's training distribution (its
        training env id and world-changing kwargs, e.g. ``counter_torque``, or episodes whose fixed
        options its training draws never give), None when it does not."""
        if self.trained_on is None:
            return None
        trained_id, trained_kwargs = self.trained_on
        # an argument equal to the env's default is the env made without it (as the interrogator's note)
        world = lambda env, kw: without_defaults(env, {k: v for k, v in kw.items()  # noqa: E731
                                                       if k not in self.INTERFACE_KWARGS})
        note = configuration_note(self.name, env_id, world(env_id, env_kwargs), trained_id,
                                  (world(trained_id, trained_kwargs),))
        return note or outside_training_note(self.name, registered_ranges(trained_id, world(trained_id, trained_kwargs)),
                                             episodes)
    _pending: np.ndarray | None = None
    _state: Any = None  # a recurrent policy's hidden state (None: none yet, or a memoryless policy)
    _episode_start: bool = True

    def reset(self, observation: np.ndarray, info: dict[str, Any]) -> None:
        """Start the memories: the agent-side one (when the policy uses one) and a recurrent policy's state."""
        self._state, self._episode_start = None, True
        if self.interface is not None:
            self._pending = self.interface.reset(observation)

    def _predict(self, observation: np.ndarray) -> np.ndarray:
        """The policy's deterministic action on ``observation`` (as the env gives it to the policy), its
        recurrent state carried on (every SB3 policy takes and returns one; a memoryless policy's stays None)."""
        action, self._state = self.model.predict(self.normalize(observation), state=self._state,
                                                 episode_start=np.array([self._episode_start]), deterministic=True)
        self._episode_start = False
        return np.asarray(action, dtype=np.float32).reshape(-1)

    def act(self, observation: np.ndarray, info: dict[str, Any]) -> np.ndarray:
        if self.interface is not None:
            if self._pending is not None:  # the reset observation, already in the memory
                policy_obs, self._pending = self._pending, None
            else:
                policy_obs = self.interface.observe(observation)
            return np.asarray(self.interface.to_env(self._predict(policy_obs)), dtype=np.float32)
        action = np.clip(self._predict(observation), -1.0, 1.0)
        if action.shape != (5,):
            raise ValueError(f"policy returned an action of shape {action.shape}, expected (5,)")
        if self.adapter == "incremental":
            from cof_gym.agents.adapters import incremental_to_env

            return incremental_to_env(action, observation, self.limits)
        return action

    def close(self) -> None:
        if self.vec_normalize is not None:
            self.vec_normalize.close()
