"""The hyperparameters of ``cof-gym train``: the RL Zoo YAML entry of an env (``cof_gym/agents/hyperparams/ppo.yml``,
the file ``python -m rl_zoo3.train`` reads too) split into run settings and PPO's arguments, each checked against
its bounds (``ValueError`` naming the key)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym

from cof_gym.validation import check_bool, check_int, check_number, is_int

DEFAULT_CONF = Path(__file__).resolve().parents[1] / "agents" / "hyperparams" / "ppo.yml"
_SCHEDULED = ("learning_rate", "clip_range", "clip_range_vf")
# integer hyperparameters: name -> (low, high); high None: no upper bound (PPO normalises each minibatch's advantages,
# so SB3 asks for a batch_size above 1)
MAX_N_ENVS = 256  # parallel envs: each a process with its own files and MuJoCo model (100 000 exhausts open files)
INT_BOUNDS: dict[str, tuple[int, int | None]] = {"n_steps": (1, 10**7), "batch_size": (2, 10**7),
                                                 "n_epochs": (1, 10**6), "n_envs": (1, MAX_N_ENVS)}
# VecNormalize arguments (of ``normalize``) that must be booleans / numbers in (low, high]
_NORMALIZE_BOOLS = ("training", "norm_obs", "norm_reward")
_NORMALIZE_BOUNDS = {"clip_obs": (0.0, 1e12), "clip_reward": (0.0, 1e12), "gamma": (0.0, 1.0), "epsilon": (0.0, 1.0)}


def load_hyperparams(env_id: str, conf_file: str | Path = DEFAULT_CONF) -> dict[str, Any]:
    """The raw YAML entry of ``env_id`` (falling back to a ``default`` entry, as RL Zoo does)."""
    import yaml

    with open(conf_file) as f:
        table = yaml.safe_load(f) or {}
    if not isinstance(table, dict):
        raise ValueError("not an RL Zoo hyperparameter file (a mapping of env ids to their "
                         f"hyperparameters), it holds a {type(table).__name__}")
    if env_id in table:
        return dict(table[env_id])
    if "default" in table:
        return dict(table["default"])
    raise KeyError(f"no hyperparameters for {env_id!r} in {conf_file} (ids: {sorted(table)})")


def _eval_kwargs(key: str, text: str) -> dict[str, Any]:
    """``policy_kwargs`` / ``normalize`` strings, evaluated as RL Zoo does (``dict(...)``, ``nn.Tanh``); whatever
    the evaluation raises is a one-line ``ValueError`` naming ``key``."""
    import torch

    namespace = {"__builtins__": {}, "dict": dict, "list": list, "tuple": tuple, "True": True, "False": False,
                 "None": None, "nn": torch.nn, "th": torch, "torch": torch}
    try:
        value = eval(text, namespace)  # noqa: S307 - same contract as RL Zoo: the YAML is trusted code
    except Exception as e:  # noqa: BLE001 - any error of the user's expression (AttributeError, KeyError, ...)
        raise ValueError(f"{key}: {text!r} does not evaluate ({type(e).__name__}: {' '.join(str(e).split())}); "
                         f"write a dict such as dict(net_arch=[64, 64], activation_fn=nn.Tanh)") from None
    if not isinstance(value, dict):
        raise ValueError(f"{key}: expected a dict, got {value!r} from {text!r}")
    return value


def check_net_arch(net_arch: Any) -> None:
    """SB3's ``net_arch``: a list of layer widths (ints >= 1) or a dict of such lists for ``pi`` and ``vf``;
    ``ValueError`` naming it otherwise (a width 0 built a network that trains nothing, -1 was torch's own error)."""
    lists = net_arch.items() if isinstance(net_arch, dict) else [("", net_arch)]
    for name, widths in lists:
        if (name not in ("", "pi", "vf") or not isinstance(widths, (list, tuple))
                or not all(is_int(w) and w >= 1 for w in widths)):
            raise ValueError(f"policy_kwargs.net_arch must be a list of layer widths (integers >= 1) or "
                             f"dict(pi=[...], vf=[...]) of such lists, got {net_arch!r}")


def check_normalize(normalize: dict[str, Any]) -> None:
    """``normalize`` as a dict: VecNormalize's keyword arguments only (its signature), booleans as booleans,
    clip_obs / clip_reward / epsilon > 0, gamma in (0, 1]; ``ValueError`` naming the key otherwise."""
    import inspect

    from stable_baselines3.common.vec_env import VecNormalize

    allowed = set(inspect.signature(VecNormalize.__init__).parameters) - {"self", "venv"}
    unknown = sorted(str(k) for k in set(normalize) - allowed)
    if unknown:
        raise ValueError(f"normalize: unknown VecNormalize argument(s) {unknown}; allowed: {sorted(allowed)}")
    for key, value in normalize.items():
        if key in _NORMALIZE_BOOLS and not isinstance(value, bool):
            raise ValueError(f"normalize.{key} must be True or False, got {value!r} ({type(value).__name__})")
        if key in _NORMALIZE_BOUNDS:
            check_number(f"normalize.{key}", value, *_NORMALIZE_BOUNDS[key], low_open=True)
        if key == "norm_obs_keys" and value is not None:
            raise ValueError(f"normalize.norm_obs_keys must be None (the observation is not a dict), got {value!r}")


def _schedule(key: str, value: Any) -> Any:
    """RL Zoo's ``lin_<x>`` strings into linear schedules (``x`` at the start, 0 at the end); the start value
    is checked against the constant's bounds (:data:`PPO_BOUNDS`)."""
    if isinstance(value, str):
        kind, _, initial = value.partition("_")
        try:
            start = float(initial)
        except ValueError:
            start = None
        if kind != "lin" or start is None:
            raise ValueError(f"{key}: expected a number or 'lin_<number>', got {value!r}")
        if key in PPO_BOUNDS:
            low, high, low_open = PPO_BOUNDS[key]
            check_number(f"{key} (the start of {value!r})", start, low, high, low_open=low_open)
        from stable_baselines3.common.utils import LinearSchedule

        return LinearSchedule(start, 0.0, 1.0)
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else value


def split_hyperparams(raw: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """``(run settings, PPO kwargs)`` from a YAML entry. Run settings: n_envs, n_timesteps, policy,
    normalize (VecNormalize kwargs, always obs-only by default), env_kwargs."""
    raw = dict(raw)
    n_timesteps = raw.pop("n_timesteps", 100_000)
    if isinstance(n_timesteps, str):  # '1e5'
        try:
            n_timesteps = float(n_timesteps)
        except ValueError:
            pass
    if isinstance(n_timesteps, float) and n_timesteps.is_integer() and n_timesteps >= 1:  # the YAML's !!float 4e4
        n_timesteps = int(n_timesteps)
    settings: dict[str, Any] = {
        "n_envs": check_int("n_envs", raw.pop("n_envs", 1), *INT_BOUNDS["n_envs"]),
        "n_timesteps": check_int("n_timesteps", n_timesteps, 1),
        "policy": raw.pop("policy", "MlpPolicy"),
        "env_kwargs": dict(raw.pop("env_kwargs", None) or {}),
    }
    normalize = raw.pop("normalize", True)
    if isinstance(normalize, str):
        normalize = _eval_kwargs("normalize", normalize)
    if isinstance(normalize, dict):
        check_normalize(normalize)
        norm = {"norm_obs": True, "norm_reward": False, **normalize}
    elif isinstance(normalize, bool):  # observations only (the reward scale is meaningful)
        norm = {"norm_obs": normalize, "norm_reward": False}
    else:
        raise ValueError(f"normalize must be True, False or a dict of VecNormalize arguments, got {normalize!r} "
                         f"({type(normalize).__name__})")
    if "gamma" in raw:
        norm.setdefault("gamma", float(raw["gamma"]))
    settings["normalize"] = norm
    unsupported = {"frame_stack", "env_wrapper", "vec_env_wrapper", "callback", "monitor_kwargs"} & set(raw)
    if unsupported:
        raise ValueError(f"RL Zoo keys not supported by cof-gym train: {sorted(unsupported)}")
    ppo: dict[str, Any] = {}
    for key, value in raw.items():
        if key == "policy_kwargs":
            value = _eval_kwargs(key, value) if isinstance(value, str) else value
            if isinstance(value, dict) and "net_arch" in value:
                check_net_arch(value["net_arch"])
        elif key in _SCHEDULED:
            value = _schedule(key, value)
        ppo[key] = value
    return settings, ppo


# PPO hyperparameters that Stable-Baselines3 takes unchecked: name -> (low, high, low_open)
PPO_BOUNDS: dict[str, tuple[float, float, bool]] = {
    "learning_rate": (0.0, 1.0, True), "gamma": (0.0, 1.0, True), "gae_lambda": (0.0, 1.0, False),
    "ent_coef": (0.0, 1e6, False), "vf_coef": (0.0, 1e6, False), "max_grad_norm": (0.0, 1e12, True),
    "clip_range": (0.0, 1e6, True), "clip_range_vf": (0.0, 1e6, True), "target_kl": (0.0, 1e6, True),
}
PPO_BOOLS = ("use_sde", "normalize_advantage")  # PPO switches SB3 takes by truthiness (``use_sde:1`` is no switch)


def check_ppo_kwargs(policy: str, ppo_kwargs: dict[str, Any], observation_space: gym.Space, action_space: gym.Space,
                     n_envs: int) -> None:
    """PPO's hyperparameters, as SB3 checks them when it builds the model (on a stand-in env with the
    same spaces and ``n_envs``: nothing is simulated or written) and within :data:`PPO_BOUNDS`.
    ``ValueError`` in one line."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import DummyVecEnv

    from cof_gym.agents.sb3_policy import SpacesOnly

    for key in ("n_steps", "batch_size", "n_epochs"):
        if key in ppo_kwargs:
            check_int(key, ppo_kwargs[key], *INT_BOUNDS[key])
    for key in PPO_BOOLS:
        if key in ppo_kwargs:
            check_bool(key, ppo_kwargs[key])
    for key, (low, high, low_open) in PPO_BOUNDS.items():
        if ppo_kwargs.get(key) is not None and not callable(ppo_kwargs[key]):
            check_number(key, ppo_kwargs[key], low, high, low_open=low_open)
    venv = DummyVecEnv([lambda: SpacesOnly(observation_space, action_space)] * n_envs)
    try:
        PPO(policy, venv, device="cpu", **ppo_kwargs)
    except Exception as e:  # noqa: BLE001 - SB3 reports bad values as AssertionError, TypeError or ValueError
        raise ValueError(" ".join(str(e).split()) or type(e).__name__) from None


def check_normalize_env(normalize: dict[str, Any], observation_space: gym.Space, action_space: gym.Space) -> None:
    """VecNormalize built with ``normalize`` on a stand-in env with the training env's spaces (nothing is
    simulated); ``ValueError`` in one line."""
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    from cof_gym.agents.sb3_policy import SpacesOnly

    venv = DummyVecEnv([lambda: SpacesOnly(observation_space, action_space)])
    try:
        VecNormalize(venv, **normalize)
    except Exception as e:  # noqa: BLE001 - SB3 reports bad values as AssertionError, TypeError or ValueError
        raise ValueError(f"normalize {normalize}: " + (" ".join(str(e).split()) or type(e).__name__)) from None
