"""The caution policy: a small network learnt by reinforcement (PPO, ``experiments/learned_caution.py``, rule 104)
that sets the climb's caution at each decision from what the climb decided after its last window
(:meth:`~cof_gym.agents.interrogator.LearnedInterrogator.climb_state`). NumPy only: the policy directory holds its
weights (``caution_policy.npz``), exported from the stable-baselines3 model it was trained as."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from cof_gym.agents.interrogator.climb import ClimbParameters
from cof_gym.agents.interrogator.networks import open_npz

CAUTION_SPAN = math.log(2.0)  # an action of +-1: the climb's caution (filter and guards) times 2 or halved
CAUTION_POLICY_FILE = "caution_policy.npz"
# what a caution policy reads, in order (LearnedInterrogator.climb_state): the last decision's filter headroom and std,
# steering headroom and std, log step and whether the climb had crept; whether the probe is sticky; the windows left
# over the horizon; the log of the noise ratio read
CLIMB_STATE_FIELDS = ("filter_headroom", "filter_std", "steering_headroom", "steering_std", "log_step", "crept",
                      "stuck", "windows_left_fraction", "log_noise_ratio")


def cautioned(params: ClimbParameters, action: float) -> ClimbParameters:
    """The climb ``params`` with its caution times ``exp(CAUTION_SPAN a)``, ``a`` clipped to [-1, 1] (the guards
    follow it where their cautions are the climb's); ``params`` itself at ``a = 0``."""
    a = float(np.clip(action, -1.0, 1.0))
    return params if a == 0.0 else replace(params, caution=params.caution * math.exp(CAUTION_SPAN * a))


@dataclass(frozen=True)
class CautionPolicy:
    """A tanh multilayer perceptron's mean action (stable-baselines3's ``MlpPolicy``, deterministic), in float32:
    ``hidden`` (weight, bias) pairs, then the ``output`` pair; the action clipped to [-1, 1]."""

    hidden: tuple[tuple[np.ndarray, np.ndarray], ...]
    output: tuple[np.ndarray, np.ndarray]

    def __call__(self, state: np.ndarray) -> float:
        x = np.asarray(state, dtype=np.float32)
        for weight, bias in self.hidden:
            x = np.tanh(weight @ x + bias)
        return float(np.clip((self.output[0] @ x + self.output[1])[0], -1.0, 1.0))

    def save(self, path: Path) -> None:
        arrays = {f"hidden_{k}_{part}": a for k, pair in enumerate(self.hidden) for part, a in zip("wb", pair)}
        np.savez(path, **arrays, output_w=self.output[0], output_b=self.output[1])

    @classmethod
    def load(cls, path: Path) -> "CautionPolicy":
        with open_npz(path, "a caution policy") as data:
            depth = sum(1 for name in data.files if name.endswith("_w")) - 1
            hidden = tuple((data[f"hidden_{k}_w"].astype(np.float32), data[f"hidden_{k}_b"].astype(np.float32))
                           for k in range(depth))
            return cls(hidden, (data["output_w"].astype(np.float32), data["output_b"].astype(np.float32)))
