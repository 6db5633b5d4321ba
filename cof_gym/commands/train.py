"""``cof-gym train``: PPO (Stable-Baselines3) on the cof_gym environments.

Defaults come from ``cof_gym/agents/hyperparams/ppo.yml`` (RL Zoo format, the file ``python -m rl_zoo3.train``
reads too); the command line overrides them. Writes, under ``--out DIR``:

- ``model.zip`` and ``vecnormalize.pkl`` beside it (observation statistics; load them with
  ``training=False, norm_reward=False``, as :class:`cof_gym.agents.sb3_policy.SB3Agent` does);
- ``tb/PPO_<k>/``: TensorBoard logs, with per-episode reward terms, relative CoF error and
  macro-slip rate under ``episode/``;
- ``checkpoints/ppo_<N>_steps.zip`` + ``ppo_vecnormalize_<N>_steps.pkl`` (``--save-freq``);
- ``best/best_model.zip`` + ``best/vecnormalize.pkl`` (``--eval-freq``, on a separate frozen-statistics
  env);
- ``monitor/<rank>.monitor.csv``: SB3 Monitor episode logs (``<rank>.resume<k>.monitor.csv`` for the
  k-th resumed run into the same directory);
- ``eval/evaluations.npz`` (``eval/resume<k>/`` likewise);
- ``train_meta.json``: command line, seed, hyperparameters, timesteps, wall time, versions, ``status``
  (``setting up``, ``running``, then ``finished``, ``interrupted`` or ``failed``), and ``history`` (the
  earlier runs into the same directory).

``--resume PATH`` continues a saved model (and its statistics) for ``--timesteps`` more steps
(``reset_num_timesteps=False``: the step counter and TensorBoard curves continue). Into the same
``--out``, nothing is destroyed: the continued model is kept as ``checkpoints/ppo_<N>_steps.zip``
(``resumed_from`` points at it), and ``best/`` is only replaced by a better evaluation.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shlex
import subprocess
import sys
import time
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import numpy as np

import cof_gym
from cof_gym.agents.policy_files import META_NAME, MODEL_NAMES, VECNORMALIZE_NAME
from cof_gym.commands.train_hyperparams import (
    DEFAULT_CONF, MAX_N_ENVS, check_normalize_env, check_ppo_kwargs, load_hyperparams, split_hyperparams,
)

ALGOS = ("ppo",)
PRETRAIN_SEED_OFFSET = 200_000  # demonstration episodes draw seeds from here (not the suites' seeds)
DEFAULT_ENV_ID = cof_gym.WAGON_ENV_ID
DESCRIPTION = """\
Train a PPO interrogation policy (Stable-Baselines3). Defaults come from the RL Zoo hyperparameter
file (--conf-file); the command line overrides them. Writes, under --out DIR: model.zip and
vecnormalize.pkl (observation statistics), tb/ (TensorBoard, with per-episode reward terms, CoF error
and macro-slip rate), checkpoints/, best/ (best model on a frozen-statistics evaluation env),
monitor/ (episode logs) and train_meta.json (command, seed, hyperparameters, versions, status).

--resume PATH continues a saved model for --timesteps more steps. Into the same --out it appends:
the resumed model is kept as a checkpoint, new monitor files and evaluations sit beside the old ones,
best/ is replaced only by a better model, and train_meta.json keeps the earlier runs under "history".
Everything on the command line is checked before anything is written (usage errors exit with 2)."""
# PPO arguments the command sets itself (-> the option that sets it, or None)
SET_BY_COMMAND: dict[str, str | None] = {"seed": "--seed", "device": "--device", "verbose": "--verbose",
                                         "tensorboard_log": None, "env": "--env", "_init_setup_model": None}


# ---------------------------------------------------------------------------- callbacks
def _callbacks():
    """Callback classes, defined lazily so that importing this module does not import SB3 (nor the physics)."""
    from stable_baselines3.common.callbacks import BaseCallback

    from cof_gym.task.reward import REWARD_TERMS as TASK_TERMS, SHAPING_TERM

    REWARD_TERMS = (*TASK_TERMS, SHAPING_TERM)  # logged per episode (the shaping term: 0 without shaping)

    class EpisodeTermsCallback(BaseCallback):
        """Logs, per finished training episode (mean over the episodes of each logging interval):
        ``episode/reward_*`` (each term summed over the episode), ``episode/relative_error`` (macro-slip
        episodes count as the error cap, 1.0), ``episode/macro_slip_rate``, ``episode/scored_rate``, ``episode/diverged_rate``."""

        def _init_callback(self) -> None:
            self._sums = np.zeros((self.training_env.num_envs, len(REWARD_TERMS)))

        def _on_step(self) -> bool:
            infos = self.locals["infos"]
            dones = self.locals["dones"]
            for i, (info, done) in enumerate(zip(infos, dones)):
                for k, term in enumerate(REWARD_TERMS):
                    self._sums[i, k] += float(info.get(term, 0.0))
                if not done:
                    continue
                for k, term in enumerate(REWARD_TERMS):
                    self.logger.record_mean(f"episode/{term}", float(self._sums[i, k]))
                rel = info.get("relative_error")
                if rel is not None:
                    self.logger.record_mean("episode/relative_error", float(rel))
                scored = rel is not None and not info.get("macro_slip", False)
                self.logger.record_mean("episode/scored_rate", float(scored))
                self.logger.record_mean("episode/macro_slip_rate", float(bool(info.get("macro_slip", False))))
                self.logger.record_mean("episode/diverged_rate", float(bool(info.get("diverged", False))))
                self._sums[i] = 0.0
            return True

    class SaveVecNormalizeCallback(BaseCallback):
        """Saves the training VecNormalize statistics (used as EvalCallback's callback_on_new_best)."""

        def __init__(self, path: Path) -> None:
            super().__init__()
            self.path = Path(path)

        def _on_step(self) -> bool:
            vec_normalize = self.model.get_vec_normalize_env()
            if vec_normalize is not None:
                self.path.parent.mkdir(parents=True, exist_ok=True)
                vec_normalize.save(str(self.path))
            return True

    return EpisodeTermsCallback, SaveVecNormalizeCallback


# ---------------------------------------------------------------------------- run
def _versions() -> dict[str, str]:
    from importlib import metadata

    out = {"python": platform.python_version(), "platform": platform.platform()}
    for dist in ("cof_gym", "stable_baselines3", "torch", "gymnasium", "mujoco", "numpy", "rl_zoo3"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            pass
    if "cof_gym" not in out:
        import cof_gym

        out["cof_gym"] = cof_gym.__version__
    try:
        root = Path(__file__).resolve().parent.parent
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True, timeout=5)
        if commit.returncode == 0:
            out["git_commit"] = commit.stdout.strip()
            dirty = subprocess.run(["git", "status", "--porcelain"], cwd=root, capture_output=True, text=True, timeout=5)
            out["git_dirty"] = str(bool(dirty.stdout.strip()))
    except (OSError, subprocess.SubprocessError):
        pass
    return out


def _jsonable(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    if isinstance(value, (np.integer, np.floating)):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    return repr(value)


def _write_meta(path: Path, meta: dict[str, Any]) -> None:
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(_jsonable(meta), indent=2) + "\n")
    os.replace(tmp, path)


class _MonitoredEnvFn:
    """A picklable env factory: the env, its action space seeded, under an SB3 Monitor writing
    ``monitor_dir/<rank><suffix>.monitor.csv`` (as ``make_vec_env`` does, plus a suffix so that a resumed
    run writes new files beside the old ones instead of over them)."""

    def __init__(self, env_fn, rank: int, seed: int, monitor_dir: Path | None, suffix: str) -> None:
        self.env_fn, self.rank, self.seed, self.monitor_dir, self.suffix = env_fn, rank, seed, monitor_dir, suffix

    def __call__(self):
        from stable_baselines3.common.monitor import Monitor

        env = self.env_fn()
        env.action_space.seed(self.seed + self.rank)
        filename = None
        if self.monitor_dir is not None:
            os.makedirs(self.monitor_dir, exist_ok=True)
            filename = os.path.join(self.monitor_dir, f"{self.rank}{self.suffix}")
        return Monitor(env, filename=filename, info_keywords=("relative_error", "macro_slip"))


def _make_venv(env_id: str, env_kwargs: dict[str, Any], n_envs: int, seed: int, vec: str,
               monitor_dir: Path | None, adapter: str = "absolute", monitor_suffix: str = ""):
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    from cof_gym.agents.sb3_policy import make_env_fn

    cls = SubprocVecEnv if vec == "subproc" else DummyVecEnv
    env_fn = make_env_fn(env_id, env_kwargs, adapter)
    venv = cls([_MonitoredEnvFn(env_fn, rank, seed, monitor_dir, monitor_suffix) for rank in range(n_envs)])
    venv.seed(seed)
    return venv


WARM_START_DIR = "warm_start"
MAX_TORCH_THREADS = 1024


def _log_std_list(text: str) -> list[float]:
    """``L0,...,L4``: one finite log std per action component, each in [-5, 1]."""
    from cof_gym.task.interface import ACTION_NAMES

    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != len(ACTION_NAMES) or not all(np.isfinite(v) and -5.0 <= v <= 1.0 for v in values):
        raise argparse.ArgumentTypeError(f"must be {len(ACTION_NAMES)} comma-separated numbers in [-5, 1] "
                                         f"({', '.join(ACTION_NAMES)}), got {text!r}")
    return values


def save_warm_start(model, train_env, out: Path, env_id: str) -> Path:
    """The cloned policy before RL, in RL Zoo's layout (``OUT/warm_start/<Env-Name>.zip`` with
    ``OUT/warm_start/<Env-Name>/vecnormalize.pkl``), so that ``python -m rl_zoo3.train ... -i`` can
    fine-tune it too. Returns the zip's path."""
    name = env_id.split(":")[-1].replace("/", "-")
    (out / WARM_START_DIR / name).mkdir(parents=True, exist_ok=True)
    zip_path = out / WARM_START_DIR / f"{name}.zip"
    model.save(zip_path)
    train_env.save(str(out / WARM_START_DIR / name / VECNORMALIZE_NAME))
    return zip_path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``cof-gym train``."""
    from cof_gym.agents.pretrain import EXPERTS
    from cof_gym.commands.args import (MAX_TRAIN_SEED, StoreDict, float_in_range, int_in_range, non_negative_int,
                                       positive_int, train_seed_int)

    parser.add_argument("--algo", choices=ALGOS, default="ppo", help="RL algorithm")
    parser.add_argument("--env", default=None, choices=cof_gym.ENV_IDS, metavar="ENV_ID",
                        help=f"environment id, one of {', '.join(cof_gym.ENV_IDS)} (default: {DEFAULT_ENV_ID}, "
                             "or the resumed run's)")
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="output directory (model.zip, vecnormalize.pkl, tb/, ...)")
    parser.add_argument("--timesteps", "-n", type=positive_int, default=None,
                        help="environment steps to train (default: n_timesteps of the YAML); with --resume, "
                             "steps added to the loaded model's")
    parser.add_argument("--n-envs", type=int_in_range(1, MAX_N_ENVS), default=None,
                        help="parallel environments (default: n_envs of the YAML)")
    parser.add_argument("--seed", type=train_seed_int, default=None,
                        help=f"random seed, at most {MAX_TRAIN_SEED} (default: 0; with --resume: the run's seed + "
                             f"its timesteps, modulo {MAX_TRAIN_SEED + 1})")
    parser.add_argument("--resume", default=None, metavar="PATH",
                        help="continue training a saved model zip (or output directory); the "
                             "vecnormalize.pkl beside it is loaded too")
    parser.add_argument("--vec", choices=("subproc", "dummy"), default=None,
                        help="vector env type (default: dummy for 1 env, subproc otherwise)")
    parser.add_argument("--conf-file", default=str(DEFAULT_CONF), metavar="YAML",
                        help="RL Zoo hyperparameter file")
    parser.add_argument("--hyperparams", "-params", nargs="+", action=StoreDict, default={}, metavar="KEY:VALUE",
                        help="override hyperparameters of the YAML, e.g. n_steps:256 learning_rate:1e-4")
    parser.add_argument("--env-kwargs", nargs="+", action=StoreDict, default={}, metavar="KEY:VALUE",
                        help="environment constructor arguments, e.g. max_windows:10 condition:'dry' "
                             "counter_torque:True")
    parser.add_argument("--eval-freq", type=int, default=10_000,
                        help="evaluate every N environment steps, best model to OUT/best (<= 0: off)")
    parser.add_argument("--eval-episodes", type=positive_int, default=10, help="episodes per evaluation")
    parser.add_argument("--save-freq", type=int, default=50_000,
                        help="checkpoint every N environment steps to OUT/checkpoints (<= 0: off)")
    parser.add_argument("--device", default="cpu",
                        help="torch device: cpu, cuda, cuda:N or auto (cuda when there is one; PPO with an MLP is "
                             "faster on the CPU)")
    parser.add_argument("--torch-threads", type=int_in_range(0, MAX_TORCH_THREADS), default=1,
                        help="torch CPU threads of the learner (the MLP is tiny and OpenMP threads competing with "
                             "the simulation for the cores slow it down many-fold; 0: torch's default)")
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction, default=True,
                        help="progress bar (tqdm + rich) on the terminal")
    parser.add_argument("--verbose", "-v", type=int, choices=(0, 1, 2), default=0,
                        help="SB3 verbosity (1: print log tables)")
    parser.add_argument("--action-adapter", choices=("absolute", "incremental"), default=None,
                        help="how the policy's output becomes the env action (cof_gym/agents/adapters.py; default: "
                             "absolute, or the resumed run's)")
    parser.add_argument("--pretrain-episodes", type=non_negative_int, default=0,
                        help="behaviour-clone a scripted expert (policy and value) over N episodes before PPO (0: off)")
    cloning = _pretrain_defaults()
    parser.add_argument("--pretrain-agent", choices=EXPERTS, default=cloning["pretrain_agent"],
                        help="the expert --pretrain-episodes clones (cof_gym/agents/pretrain.py)")
    parser.add_argument("--pretrain-log-std", type=_log_std_list, default=cloning["pretrain_log_std"],
                        metavar="L0,...,L4",
                        help="the clone's exploration noise, log std per action component (default: the yml's "
                             "log_std_init for all); write --pretrain-log-std=-3,-2,-2,-2,-2 (values start with '-')")
    parser.add_argument("--pretrain-noise", type=float_in_range(0.0, 2.0, low_inclusive=True),
                        default=cloning["pretrain_noise"], metavar="STD", help="std of the noise added to the expert's executed actions while cloning "
                                            "(DART; the actions span [-1, 1])")
    parser.add_argument("--overwrite", action="store_true",
                        help="allow a new run to replace an existing OUT/model.zip")


def build_parser() -> argparse.ArgumentParser:
    from cof_gym.commands.args import Parser

    p = Parser(prog="cof-gym train", description=DESCRIPTION)
    add_arguments(p)
    return p


def main(argv: list[str] | None = None) -> int:
    return run(build_parser().parse_args(argv))


def check_device(device: str) -> None:
    """``--device``: exactly ``auto``, ``cpu``, ``cuda`` or ``cuda:N`` (N an integer), CUDA only where there is
    such a device; :class:`UsageError` otherwise."""
    import re

    from cof_gym.commands.args import UsageError

    if device in ("auto", "cpu"):
        return
    m = re.fullmatch(r"cuda(?::(\d+))?", device)
    if m is None:
        raise UsageError("--device", f"must be auto, cpu, cuda or cuda:N (N an integer >= 0), got {device!r}")
    import torch

    if not torch.cuda.is_available():
        raise UsageError("--device", f"{device!r}: no CUDA device here; use cpu")
    count = torch.cuda.device_count()
    if m[1] is not None and int(m[1]) >= count:
        raise UsageError("--device", f"{device!r}: there are {count} CUDA device(s) here, cuda:0 to cuda:{count - 1}")


def _check_resume_spaces(path: Path, saved: tuple[Any, Any], env: tuple[Any, Any], env_id: str,
                         env_kwargs: dict[str, Any], from_flag: bool) -> None:
    """A resumed model must fit the env it continues on (observation and action shapes)."""
    from cof_gym.commands.args import UsageError

    if tuple(s.shape for s in saved) != tuple(s.shape for s in env):
        raise UsageError("--env-kwargs" if from_flag else "--resume",
                         f"{path} was trained on observation {saved[0].shape} / action {saved[1].shape}; {env_id} "
                         f"with env_kwargs {env_kwargs} has {env[0].shape} / {env[1].shape}")


def _previous_best(out: Path, prev_meta: dict[str, Any]) -> float | None:
    """The best mean evaluation reward of the earlier runs into ``out`` (their best/ model's)."""
    if prev_meta.get("best_mean_reward") is not None:
        return float(prev_meta["best_mean_reward"])
    means = []
    for f in (out / "eval").rglob("evaluations.npz"):
        try:
            with np.load(f) as data:
                means.extend(np.mean(data["results"], axis=1).tolist())
        except (OSError, KeyError, ValueError):
            continue
    return max(means) if means else None


@dataclass(frozen=True)
class TrainPlan:
    """What a ``cof-gym train`` run will do, every part checked by :func:`_check` before anything is written."""

    out: Path
    resume_path: Path | None  # the model zip continued (--resume), None for a new model
    prev_meta: dict[str, Any]  # the continued run's train_meta.json ({} for a new model)
    same_out: bool  # continuing OUT/model.zip into OUT itself
    env_id: str
    adapter: str  # the action adapter (cof_gym/agents/adapters.py)
    raw: dict[str, Any]  # the hyperparameters as read: the YAML's entry with --hyperparams over it
    settings: dict[str, Any]  # what cof-gym train reads of them (policy, normalize, n_envs, ...)
    ppo_kwargs: dict[str, Any]  # what PPO's constructor reads of them
    env_kwargs: dict[str, Any]
    n_envs: int
    timesteps: int
    history: list  # the earlier runs into OUT (their train_meta.json), oldest first

    @property
    def resuming(self) -> bool:
        return self.resume_path is not None

    @property
    def run_index(self) -> int:
        """0 for the first run into OUT, k for the k-th resumed run into the same OUT."""
        return len(self.history)


def _check(args: argparse.Namespace) -> TrainPlan:
    """Everything on the command line, before anything is written; :class:`UsageError` naming the flag."""
    out, resume_path, resume_spaces, prev_meta, same_out = _check_out_and_resume(args)
    env_id = _check_env_id(args, prev_meta, resume_path is not None)
    raw, settings, ppo_kwargs = _check_hyperparams(args, env_id, resume_path is not None)
    env_kwargs = {**settings["env_kwargs"], **(prev_meta.get("env_kwargs") or {}), **(args.env_kwargs or {})}
    adapter = args.action_adapter or prev_meta.get("action_adapter", "absolute")
    spaces = _env_spaces(env_id, env_kwargs, adapter)
    if resume_path is not None:
        _check_resume_spaces(resume_path, resume_spaces, spaces, env_id, env_kwargs, bool(args.env_kwargs))
    n_envs, timesteps = _check_counts(args, settings)
    _check_pretrain(args, resume_path is not None)
    _check_model_settings(settings, ppo_kwargs, spaces, n_envs)
    check_device(args.device)
    return TrainPlan(out=out, resume_path=resume_path, prev_meta=prev_meta, same_out=same_out, env_id=env_id,
                     adapter=adapter, raw=raw, settings=settings, ppo_kwargs=ppo_kwargs, env_kwargs=env_kwargs,
                     n_envs=n_envs, timesteps=timesteps, history=_history(out, same_out))


PRETRAIN_FLAGS = (("--pretrain-agent", "pretrain_agent"), ("--pretrain-log-std", "pretrain_log_std"),
                  ("--pretrain-noise", "pretrain_noise"))  # the flags that only shape --pretrain-episodes' cloning


def _pretrain_defaults() -> dict[str, Any]:
    """The cloning flags' defaults (by dest): the first expert, the yml's log std, a DART noise std of 0.15."""
    from cof_gym.agents.pretrain import EXPERTS

    return {"pretrain_agent": EXPERTS[0], "pretrain_log_std": None, "pretrain_noise": 0.15}


def _check_pretrain(args: argparse.Namespace, resuming: bool) -> None:
    """Behaviour cloning's flags where they act: a resumed model is not cloned again, and a cloning setting
    away from its default needs ``--pretrain-episodes`` (it would be ignored)."""
    from cof_gym.commands.args import UsageError

    if args.pretrain_episodes > 0 and resuming:
        raise UsageError("--pretrain-episodes", "a resumed model is not behaviour-cloned again; drop it or --resume")
    if args.pretrain_episodes == 0:
        defaults = _pretrain_defaults()
        for flag, dest in PRETRAIN_FLAGS:
            if getattr(args, dest) != defaults[dest]:
                raise UsageError(flag, "has no effect without --pretrain-episodes N (N >= 1)")


def _check_out_and_resume(args: argparse.Namespace) -> tuple[Path, Path | None, Any, dict[str, Any], bool]:
    """``--out`` and ``--resume``: the output directory, the continued model's zip, its (observation, action)
    spaces, its train_meta.json and whether it is ``--out``'s own model."""
    from cof_gym.agents.sb3_policy import check_model, find_train_meta, resolve_model_path
    from cof_gym.commands.args import UsageError, check_output_dir

    out = check_output_dir(Path(args.out))
    resume_path, resume_spaces, prev_meta = None, None, {}
    if args.resume is not None and not args.resume.strip():
        raise UsageError("--resume", "an empty path: give a model zip or a cof-gym train output directory")
    if args.resume:
        try:  # the zip, its VecNormalize statistics and its train_meta.json
            resume_path = resolve_model_path(args.resume)
            resume_spaces = check_model(resume_path)
            prev_meta = find_train_meta(resume_path, strict=True) or {}
        except (FileNotFoundError, ValueError) as e:
            raise UsageError("--resume", str(e)) from None
    model_zip = out / MODEL_NAMES[0]
    same_out = resume_path is not None and resume_path.resolve() == model_zip.resolve()
    if out.is_dir() and not same_out and not (out / META_NAME).is_file() and any(out.iterdir()):
        raise UsageError("--out", f"{out} exists and is not a cof-gym train output (no {META_NAME}); "
                         "give a new or empty directory")
    if model_zip.exists() and not args.overwrite and not same_out:
        raise UsageError("--out", f"{model_zip} exists; use --overwrite, another --out or "
                         f"--resume {out}")
    return out, resume_path, resume_spaces, prev_meta, same_out


def _check_env_id(args: argparse.Namespace, prev_meta: dict[str, Any], resuming: bool) -> str:
    """``--env``, else the resumed run's env id, else the default; it must be registered."""
    import gymnasium as gym

    from cof_gym.commands.args import UsageError

    env_id = args.env or prev_meta.get("env_id") or DEFAULT_ENV_ID
    if env_id not in gym.registry:
        raise UsageError("--resume" if resuming and not args.env else "--env",
                         f"environment {env_id!r} is not registered; allowed: {', '.join(cof_gym.ENV_IDS)}")
    return env_id


def _check_hyperparams(args: argparse.Namespace, env_id: str,
                       resuming: bool) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    """``--conf-file`` and ``--hyperparams``: the hyperparameters as read, the command's settings and PPO's
    arguments (:func:`~cof_gym.commands.train_hyperparams.split_hyperparams`), none of them one the command
    sets itself or PPO does not take."""
    from cof_gym.commands.args import UsageError

    raw = _read_conf_file(Path(args.conf_file), env_id)
    overrides = args.hyperparams or {}
    for key, flag in SET_BY_COMMAND.items():
        if key in overrides or key in raw:
            source = "--hyperparams" if key in overrides else "--conf-file"
            raise UsageError(source, f"{key!r} is set by cof-gym train itself"
                             + (f"; use {flag}" if flag else "") + " (not a hyperparameter)")
    if resuming and "policy" in overrides:
        raise UsageError("--hyperparams", "'policy' cannot change when resuming (the saved model keeps its policy)")
    raw.update(overrides)
    try:
        settings, ppo_kwargs = split_hyperparams(raw)
    except (ValueError, TypeError, SyntaxError, NameError) as e:
        raise UsageError("--hyperparams", str(e)) from None
    import inspect

    from stable_baselines3 import PPO

    allowed = set(inspect.signature(PPO.__init__).parameters) - {"self", "policy", "env"}
    unknown = sorted(set(ppo_kwargs) - allowed)
    if unknown:
        raise UsageError("--hyperparams", f"unknown PPO argument(s) {unknown}")
    return raw, settings, ppo_kwargs


def _read_conf_file(conf: Path, env_id: str) -> dict[str, Any]:
    """The hyperparameter file's entry for ``env_id``; :class:`UsageError` on ``--conf-file``."""
    from cof_gym.commands.args import UsageError

    if not conf.is_file():
        raise UsageError("--conf-file", f"no such file: {conf}")
    try:
        return load_hyperparams(env_id, conf)
    except KeyError as e:
        raise UsageError("--conf-file", str(e.args[0])) from None
    except Exception as e:  # yaml.YAMLError and friends
        raise UsageError("--conf-file", f"{conf}: {' '.join(str(e).split())}") from None


def _env_spaces(env_id: str, env_kwargs: dict[str, Any], adapter: str) -> tuple[Any, Any]:
    """The (observation, action) spaces of one env made as training will make them; a bad ``--env-kwargs``
    is a :class:`UsageError`."""
    from cof_gym.agents.sb3_policy import make_env_fn
    from cof_gym.commands.args import UsageError

    from cof_gym.commands.suites import check_env_kwargs  # its SuiteError is a ValueError

    try:
        check_env_kwargs(env_id, env_kwargs)  # the id's own arguments; a TimeLimit that ends episodes unscored
        probe = make_env_fn(env_id, env_kwargs, adapter)()
    except (ValueError, TypeError) as e:
        raise UsageError("--env-kwargs", f"{env_id}: {e}") from None
    spaces = probe.observation_space, probe.action_space
    probe.close()
    return spaces


def _check_counts(args: argparse.Namespace, settings: dict[str, Any]) -> tuple[int, int]:
    """The number of parallel envs and of timesteps: the command line's, else the YAML's, each >= 1."""
    from cof_gym.commands.args import UsageError

    n_envs = args.n_envs or settings["n_envs"]
    timesteps = args.timesteps if args.timesteps is not None else settings["n_timesteps"]
    if n_envs < 1 or timesteps < 1:
        raise UsageError("--n-envs" if n_envs < 1 else "--timesteps", "must be >= 1 (the YAML says otherwise)")
    return n_envs, timesteps


def _check_model_settings(settings: dict[str, Any], ppo_kwargs: dict[str, Any], spaces: tuple[Any, Any],
                          n_envs: int) -> None:
    """PPO's arguments and the normalisation against the env's spaces; :class:`UsageError` on ``--hyperparams``."""
    from cof_gym.commands.args import UsageError

    try:
        check_ppo_kwargs(settings["policy"], ppo_kwargs, *spaces, n_envs)
        check_normalize_env(settings["normalize"], *spaces)
    except ValueError as e:
        raise UsageError("--hyperparams", str(e)) from None


def _history(out: Path, same_out: bool) -> list:
    """The earlier runs into ``out`` when this one continues its model there (their train_meta.json, oldest
    first), else none."""
    if not (same_out and (out / META_NAME).is_file()):
        return []
    previous = json.loads((out / META_NAME).read_text())
    return [*previous.pop("history", []), previous]


def run(args: argparse.Namespace) -> int:
    """Train; 0 on success, 2 on a usage error (one line on stderr, nothing written), 130 when
    interrupted (the model is saved anyway)."""
    from cof_gym.commands.args import UsageError

    try:
        plan = _check(args)
    except UsageError as e:
        print(f"cof-gym train: error: {e}", file=sys.stderr)
        return 2
    return _train(args, plan)


def _train(args: argparse.Namespace, plan: TrainPlan) -> int:
    """Set up, learn and save as ``plan`` says; train_meta.json records every stage, and a failure or an
    interruption too."""
    from stable_baselines3.common.utils import set_random_seed

    _quiet_progress_bar(args.progress)
    if args.torch_threads and args.torch_threads > 0:
        import torch

        torch.set_num_threads(args.torch_threads)
    previous_steps = _saved_timesteps(plan.resume_path, args.device)
    seed = _run_seed(args, plan, previous_steps)
    set_random_seed(seed)
    plan.out.mkdir(parents=True, exist_ok=True)
    resumed_from = _keep_continued_model(plan, previous_steps) if plan.same_out else plan.resume_path
    vec = args.vec or ("dummy" if plan.n_envs == 1 else "subproc")
    meta = _initial_meta(args, plan, seed, vec, resumed_from, previous_steps)
    meta_path = plan.out / META_NAME
    _write_meta(meta_path, meta)
    suffix = f".resume{plan.run_index}" if plan.run_index else ""
    train_env = eval_env = None
    try:
        train_env = _make_venv(plan.env_id, plan.env_kwargs, plan.n_envs, seed, vec, plan.out / "monitor",
                               plan.adapter, suffix)
        model, train_env = _model(args, plan, train_env, seed, meta, meta_path)
        start_steps = int(model.num_timesteps)
        _note_whole_rollouts(plan.timesteps, int(model.n_steps), int(model.n_envs))
        if args.eval_freq and args.eval_freq > 0:
            eval_env = _eval_venv(plan, seed)
        callbacks, eval_callback = _training_callbacks(args, plan, eval_env)
        meta["status"] = "running"
        _write_meta(meta_path, meta)
        status, code, wall = _learn(model, args, plan, callbacks)
        _save_and_record(model, plan, meta, meta_path, status, int(model.num_timesteps) - start_steps, wall,
                         eval_callback)
        return code
    except BaseException as e:
        _record_failure(meta, meta_path, e)
        if isinstance(e, KeyboardInterrupt):
            print("cof-gym train: interrupted during set-up", file=sys.stderr)
            return 130
        raise
    finally:
        _close(train_env, eval_env)


def _note_whole_rollouts(timesteps: int, n_steps: int, n_envs: int) -> int:
    """The steps PPO will train for ``timesteps`` (whole rollouts of ``n_steps x n_envs``); a note on stderr where
    that is more than asked (SB3's progress bar then reads e.g. 1,024/64)."""
    rollout = n_steps * n_envs
    trains = -(-timesteps // rollout) * rollout
    if trains != timesteps:
        print(f"cof-gym train: note: PPO collects whole rollouts of n_steps x n_envs = {n_steps} x {n_envs} = "
              f"{rollout} steps, so --timesteps {timesteps} trains {trains}", file=sys.stderr)
    return trains


def _quiet_progress_bar(progress: bool) -> None:
    """SB3's bar is tqdm.rich, which warns that it is experimental on every run."""
    if not progress:
        return
    import warnings

    try:
        from tqdm import TqdmExperimentalWarning

        warnings.filterwarnings("ignore", category=TqdmExperimentalWarning)
    except ImportError:
        pass


def _saved_timesteps(resume_path: Path | None, device: str) -> int:
    """The timesteps the continued model has been trained for (0 for a new model)."""
    if resume_path is None:
        return 0
    from stable_baselines3 import PPO

    return int(PPO.load(resume_path, device=device).num_timesteps)


def _run_seed(args: argparse.Namespace, plan: TrainPlan, previous_steps: int) -> int:
    """``--seed``; else 0 for a new model, and for a continued one its run's seed plus its timesteps (modulo
    the largest seed + 1), so that a continued run never replays its predecessor's random numbers."""
    from cof_gym.commands.args import MAX_TRAIN_SEED

    if args.seed is not None:
        return args.seed
    if not plan.resuming:
        return 0
    return (int(plan.prev_meta.get("seed", 0)) + previous_steps) % (MAX_TRAIN_SEED + 1)


def _keep_continued_model(plan: TrainPlan, previous_steps: int) -> Path:
    """Continuing OUT/model.zip into OUT, which this run replaces when it ends: the model (and its statistics)
    kept as ``checkpoints/ppo_<N>_steps.zip`` first; returns the kept zip."""
    import shutil

    from cof_gym.agents.sb3_policy import vecnormalize_path

    ckpt_dir = plan.out / "checkpoints"
    ckpt_dir.mkdir(exist_ok=True)
    kept = ckpt_dir / f"ppo_{previous_steps}_steps.zip"
    if not kept.exists():
        shutil.copy2(plan.resume_path, kept)
    stats = vecnormalize_path(plan.resume_path)
    kept_stats = ckpt_dir / f"ppo_vecnormalize_{previous_steps}_steps.pkl"
    if stats.is_file() and not kept_stats.exists():
        shutil.copy2(stats, kept_stats)
    return kept


def _initial_meta(args: argparse.Namespace, plan: TrainPlan, seed: int, vec: str, resumed_from: Path | None,
                  previous_steps: int) -> dict[str, Any]:
    """train_meta.json before set-up: the command, the plan, the versions, status ``setting up``."""
    meta: dict[str, Any] = {
        "command": shlex.join(sys.argv), "argv": sys.argv,
        # the options only (not the parser's own entries: its command, StoreDict's private "_DEST_given" sets)
        "args": {k: v for k, v in vars(args).items() if k not in ("func", "command_parser") and not k.startswith("_")},
        "algo": args.algo, "env_id": plan.env_id, "env_kwargs": plan.env_kwargs, "action_adapter": plan.adapter,
        "seed": seed, "n_envs": plan.n_envs, "vec": vec,
        "timesteps_requested": plan.timesteps, "conf_file": str(args.conf_file),
        # a resumed model keeps its own hyperparameters; only --hyperparams overrides apply
        "hyperparams": (plan.raw if not plan.resuming
                        else {**(plan.prev_meta.get("hyperparams") or {}), **(args.hyperparams or {})}),
        "resumed_from": str(resumed_from) if resumed_from else None,
        "resumed_from_timesteps": previous_steps if plan.resuming else None,
        "status": "setting up",
        "started": datetime.now(timezone.utc).isoformat(timespec="seconds"), "versions": _versions(),
    }
    if plan.history:
        meta["history"] = plan.history
    return meta


def _model(args: argparse.Namespace, plan: TrainPlan, venv, seed: int, meta: dict[str, Any], meta_path: Path):
    """The PPO model on ``venv`` under VecNormalize: the continued model with its statistics, or a new one
    (behaviour-cloned first with ``--pretrain-episodes``). Returns the model and the normalised env."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecNormalize

    if not plan.resuming:
        train_env = VecNormalize(venv, **plan.settings["normalize"])
        model = PPO(plan.settings["policy"], train_env, seed=seed, tensorboard_log=str(plan.out / "tb"),
                    verbose=args.verbose, device=args.device, **plan.ppo_kwargs)
        if args.pretrain_episodes > 0:
            meta["pretrain"] = _pretrain(args, plan, model, train_env, seed)
            _write_meta(meta_path, meta)
        return model, train_env
    train_env = _continued_statistics(plan, venv)
    overrides = split_hyperparams({**(args.hyperparams or {})})[1]
    model = PPO.load(plan.resume_path, env=train_env, device=args.device, tensorboard_log=str(plan.out / "tb"),
                     verbose=args.verbose, **overrides)
    model.set_random_seed(seed)
    return model, train_env


def _continued_statistics(plan: TrainPlan, venv):
    """``venv`` under the continued model's VecNormalize statistics (fresh ones, with a warning, where its
    vecnormalize.pkl is missing)."""
    from stable_baselines3.common.vec_env import VecNormalize

    from cof_gym.agents.sb3_policy import vecnormalize_path

    stats = vecnormalize_path(plan.resume_path)
    if not stats.is_file():
        print(f"cof-gym train: warning: no {stats.name} beside {plan.resume_path}; fresh statistics", file=sys.stderr)
        return VecNormalize(venv, **plan.settings["normalize"])
    train_env = VecNormalize.load(str(stats), venv)
    train_env.training = True
    train_env.norm_reward = plan.settings["normalize"]["norm_reward"]
    return train_env


def _pretrain(args: argparse.Namespace, plan: TrainPlan, model, train_env, seed: int) -> dict[str, Any]:
    """Behaviour cloning of ``--pretrain-agent`` before PPO (cof_gym/agents/pretrain.py), the clone saved as
    a warm start; returns train_meta.json's ``pretrain`` record."""
    from cof_gym.agents.pretrain import behaviour_clone, collect_demonstrations

    t_bc = time.perf_counter()
    demo_obs, demo_act, demo_ret = collect_demonstrations(
        plan.env_id, plan.env_kwargs, args.pretrain_episodes, PRETRAIN_SEED_OFFSET + seed * args.pretrain_episodes,
        expert=args.pretrain_agent, gamma=float(plan.ppo_kwargs.get("gamma", 0.99)), noise_std=args.pretrain_noise)
    losses = behaviour_clone(model, demo_obs, demo_act, demo_ret, seed=seed, log_std=args.pretrain_log_std)
    warm = save_warm_start(model, train_env, plan.out, plan.env_id)
    print(f"behaviour cloning: {len(demo_obs)} {args.pretrain_agent} samples, final action MSE "
          f"{losses['action_mse']:.4f}, value MSE {losses['value_mse']:.3f}")
    return {"agent": args.pretrain_agent, "episodes": args.pretrain_episodes, "noise_std": args.pretrain_noise,
            "log_std": args.pretrain_log_std, "samples": int(len(demo_obs)), **losses, "warm_start": str(warm),
            "wall_time_s": round(time.perf_counter() - t_bc, 3)}


def _eval_venv(plan: TrainPlan, seed: int):
    """The evaluation env: one env, its own seeds, observation statistics frozen (set by the callback)."""
    from stable_baselines3.common.vec_env import VecNormalize

    return VecNormalize(_make_venv(plan.env_id, plan.env_kwargs, 1, seed + 10_000, "dummy", None, plan.adapter),
                        training=False, norm_obs=plan.settings["normalize"]["norm_obs"], norm_reward=False)


def _training_callbacks(args: argparse.Namespace, plan: TrainPlan, eval_env) -> tuple[list, Any]:
    """The episode-terms logger, checkpoints (``--save-freq``) and, with ``eval_env``, the evaluation that keeps
    best/ (replaced only by a better model than the earlier runs' into the same OUT); returns them and the
    evaluation callback (None without one)."""
    from stable_baselines3.common.callbacks import CheckpointCallback, EvalCallback

    EpisodeTermsCallback, SaveVecNormalizeCallback = _callbacks()
    out, n_envs = plan.out, plan.n_envs
    callbacks: list = [EpisodeTermsCallback()]
    if args.save_freq and args.save_freq > 0:
        callbacks.append(CheckpointCallback(save_freq=max(args.save_freq // n_envs, 1),
                                            save_path=str(out / "checkpoints"), name_prefix="ppo",
                                            save_vecnormalize=True))
    if eval_env is None:
        return callbacks, None
    eval_callback = EvalCallback(
        eval_env, n_eval_episodes=args.eval_episodes, eval_freq=max(args.eval_freq // n_envs, 1),
        best_model_save_path=str(out / "best"),
        log_path=str(out / "eval" / f"resume{plan.run_index}" if plan.run_index else out / "eval"), deterministic=True,
        callback_on_new_best=SaveVecNormalizeCallback(out / "best" / VECNORMALIZE_NAME), verbose=args.verbose)
    if plan.same_out and (out / "best" / MODEL_NAMES[1]).is_file():
        best = _previous_best(out, plan.prev_meta)
        if best is not None:  # best/ is replaced only by a better model
            eval_callback.best_mean_reward = best
    callbacks.append(eval_callback)
    return callbacks, eval_callback


def _learn(model, args: argparse.Namespace, plan: TrainPlan, callbacks: list) -> tuple[str, int, float]:
    """PPO's learning for ``plan.timesteps``; returns the status, the exit code (130 when interrupted: the
    model is saved anyway) and the wall time (s)."""
    status, code = "finished", 0
    t0 = time.perf_counter()
    try:
        model.learn(total_timesteps=plan.timesteps, callback=callbacks, tb_log_name="PPO",
                    reset_num_timesteps=not plan.resuming, progress_bar=args.progress)
    except KeyboardInterrupt:
        status, code = "interrupted", 130
        print("cof-gym train: interrupted, saving the model", file=sys.stderr)
    return status, code, time.perf_counter() - t0


def _save_and_record(model, plan: TrainPlan, meta: dict[str, Any], meta_path: Path, status: str, steps: int,
                     wall: float, eval_callback) -> None:
    """OUT/model.zip and vecnormalize.pkl, then train_meta.json's final record and one line on the terminal."""
    model.save(plan.out / MODEL_NAMES[0])
    model.get_vec_normalize_env().save(str(plan.out / VECNORMALIZE_NAME))
    meta.update({
        "status": status, "finished": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "wall_time_s": round(wall, 3), "timesteps_trained": steps, "num_timesteps": int(model.num_timesteps),
        "steps_per_s": round(steps / wall, 2) if wall > 0 else None,
        "tensorboard_dir": model.logger.get_dir() if model.logger is not None else None,
    })
    if eval_callback is not None and np.isfinite(eval_callback.best_mean_reward):
        meta["best_mean_reward"] = float(eval_callback.best_mean_reward)
    _write_meta(meta_path, meta)
    print(f"{status}: {steps} steps ({model.num_timesteps} total) in {wall:.1f} s ({meta['steps_per_s']} steps/s); "
          f"model {plan.out / 'model.zip'}, statistics {plan.out / 'vecnormalize.pkl'}")


def _record_failure(meta: dict[str, Any], meta_path: Path, error: BaseException) -> None:
    """A run that stops in set-up or learning is never left marked as running: ``interrupted`` or ``failed``."""
    if meta["status"] not in ("setting up", "running"):
        return
    meta.update({"status": "interrupted" if isinstance(error, KeyboardInterrupt) else "failed",
                 "error": f"{type(error).__name__}: {error}",
                 "finished": datetime.now(timezone.utc).isoformat(timespec="seconds")})
    _write_meta(meta_path, meta)


def _close(*venvs) -> None:
    """Close the vector envs that were made; subprocess workers may already be gone (e.g. after Ctrl-C)."""
    for venv in venvs:
        if venv is None:
            continue
        try:
            venv.close()
        except (EOFError, BrokenPipeError, ConnectionResetError, OSError):
            pass


if __name__ == "__main__":
    sys.exit(main())
