"""Training the learned interrogator's filter (:mod:`cof_gym.agents.interrogator`).

**Data.** Climbs on the training env's own randomisation (every v2 draw: creep-law family and shape,
systematic sensor errors, CoF, speed, load, noise, motor lag), in every vehicle configuration listed,
with training seeds that no evaluation uses. Each climb starts at the shared safe first step and
visits utilisations ``u = DC / M_sat`` drawn sorted from U(first, u_max), ``u_max ~ U(0.8, 1.05)``,
with a modulation ratio log-uniform in 3-40 % and a frequency of 5 Hz or log-uniform in 3-10 Hz,
until the last target or a macro-slip. The climb is steered by the true saturation torque so that
the data cover the last 20 % before the peak densely; the labels (``ln(M_sat / DC)``,
``ln(CoF / CoA measured)``) are the episode's ground truth. The readings of every window are kept
(:class:`Dataset`); the features are rebuilt from them through the same
:class:`~cof_gym.agents.interrogator.EpisodeFeatures` the agent runs.

**Networks.** Each member is a tanh MLP fitted by the Gaussian negative log-likelihood of both
targets (mean and log variance per target), on a bootstrap resample of the training episodes
(bagging: members differ in data and initialisation). Torch is imported only here.
"""

from __future__ import annotations

import math
from concurrent.futures import ProcessPoolExecutor
from dataclasses import astuple, dataclass, fields
from typing import Any

import gymnasium as gym
import numpy as np

from cof_gym.agents.interrogator import (
    FEATURE_NAMES, TARGET_NAMES, ClimbParameters, EpisodeFeatures, FilterNetwork, Reading,
)
from cof_gym.agents.staircase import ElasticityClimb
from cof_gym.task.interface import encode_action

TRAINING_SEED = 1_000_000  # first training seed: far from every evaluation and validation seed


READING_FIELDS = tuple(f.name for f in fields(Reading))


@dataclass(frozen=True)
class Dataset:
    """Driven windows of training climbs: the raw readings (so that features can change without new
    simulations), the vehicle configuration, the targets and the episode of each window."""

    readings: np.ndarray  # (n, len(READING_FIELDS))
    counter_torque: np.ndarray  # (n,) bool
    targets: np.ndarray  # (n, 2): ln(M_sat / DC), ln(CoF / CoA)
    episode: np.ndarray  # (n,) episode index (windows of an episode are contiguous, in order)

    def __len__(self) -> int:
        return len(self.targets)

    def subset(self, rows: np.ndarray) -> "Dataset":
        return Dataset(self.readings[rows], self.counter_torque[rows], self.targets[rows], self.episode[rows])

    @property
    def features(self) -> np.ndarray:
        """Each window's feature vector, rebuilt from the readings of its episode up to it."""
        out = np.empty((len(self), len(FEATURE_NAMES)))
        features = None
        for i in range(len(self)):
            if i == 0 or self.episode[i] != self.episode[i - 1]:
                features = EpisodeFeatures(bool(self.counter_torque[i]))
            features.push(Reading(*(float(v) for v in self.readings[i])))
            out[i] = features.vector()
        return out

    def save(self, path) -> None:
        np.savez(path, readings=self.readings, counter_torque=self.counter_torque, targets=self.targets,
                 episode=self.episode, reading_fields=np.asarray(READING_FIELDS))

    @classmethod
    def load(cls, path) -> "Dataset":
        with np.load(path) as z:
            if tuple(str(f) for f in z["reading_fields"]) != READING_FIELDS:
                raise ValueError(f"{path}: recorded with other reading fields; collect again")
            return cls(z["readings"], z["counter_torque"], z["targets"], z["episode"])

    @classmethod
    def concatenate(cls, parts: list["Dataset"]) -> "Dataset":
        offset, episodes = 0, []
        for p in parts:
            episodes.append(p.episode + offset)
            offset += int(p.episode.max()) + 1 if len(p) else 0
        return cls(np.concatenate([p.readings for p in parts]), np.concatenate([p.counter_torque for p in parts]),
                   np.concatenate([p.targets for p in parts]), np.concatenate(episodes))


def _climb_episode(env, seed: int) -> tuple[list[Reading], list[tuple[float, float]]]:
    rng = np.random.default_rng([seed, 7])
    obs, info = env.reset(seed=seed)
    base = env.unwrapped
    limits = base.limits
    truth = info["ground_truth"]
    m_sat, cof = truth["saturation_torque_nm"], truth["cof"]
    first = ElasticityClimb().first_dc(limits)
    u_max = rng.uniform(0.8, 1.05)
    n = int(rng.integers(3, 16))
    targets = np.sort(rng.uniform(min(first / m_sat, u_max), u_max, n)) * m_sat
    dcs = [first] + [float(t) for t in targets if t > first]
    p = ClimbParameters(amplitude_ratio=float(math.exp(rng.uniform(math.log(0.03), math.log(0.4)))),
                        frequency_hz=5.0 if rng.random() < 0.5 else float(math.exp(rng.uniform(math.log(3), math.log(10)))))
    xs, ys = [], []
    for dc in dcs[: base.task.max_windows]:
        action = encode_action(dc, p.amplitude(dc, limits), p.frequency_hz, 0.1, False, limits)
        obs, _, terminated, truncated, info = env.step(action)
        reading = Reading.of(obs, limits)
        xs.append(reading)
        ys.append((math.log(m_sat / dc), math.log(cof / reading.coa)))
        if terminated or truncated:
            break
    return xs, ys


def collect(env_id: str, configs: list[dict[str, Any]], episodes: int, first_seed: int = TRAINING_SEED) -> Dataset:
    """``episodes`` training climbs (seeds ``first_seed...``), the configurations in turn."""
    envs = [gym.make(env_id, **c) for c in configs]
    xs, cts, ys, eps = [], [], [], []
    for i in range(episodes):
        k = i % len(configs)
        x, y = _climb_episode(envs[k], first_seed + i)
        xs += [astuple(r) for r in x]
        ys += y
        cts += [bool(envs[k].unwrapped.task.counter_torque)] * len(x)
        eps += [i] * len(x)
    for e in envs:
        e.close()
    return Dataset(np.asarray(xs, dtype=np.float64).reshape(-1, len(READING_FIELDS)), np.asarray(cts, dtype=bool),
                   np.asarray(ys, dtype=np.float64).reshape(-1, len(TARGET_NAMES)), np.asarray(eps, dtype=np.int64))


def collect_parallel(env_id: str, configs: list[dict[str, Any]], episodes: int, workers: int,
                     first_seed: int = TRAINING_SEED) -> Dataset:
    """:func:`collect` split over ``workers`` processes (the same episodes, in the same order)."""
    if workers <= 1:
        return collect(env_id, configs, episodes, first_seed)
    n_configs = len(configs)
    chunk = math.ceil(episodes / workers / n_configs) * n_configs  # keeps the configuration rotation aligned
    starts = list(range(0, episodes, chunk))
    with ProcessPoolExecutor(workers) as pool:
        parts = list(pool.map(collect, [env_id] * len(starts), [configs] * len(starts),
                              [min(chunk, episodes - s) for s in starts], [first_seed + s for s in starts]))
    return Dataset.concatenate(parts)


@dataclass(frozen=True)
class FitSettings:
    hidden: tuple[int, ...] = (64, 64)
    epochs: int = 150
    batch_size: int = 256
    learning_rate: float = 2e-3
    weight_decay: float = 1e-5


def fit_member(data: Dataset, seed: int, settings: FitSettings = FitSettings()) -> FilterNetwork:
    """One member: a bootstrap resample of ``data``'s episodes (``seed``), Gaussian NLL, Adam."""
    import torch

    rng = np.random.default_rng(seed)
    episodes = np.unique(data.episode)
    chosen = rng.choice(episodes, size=len(episodes), replace=True)
    rows_of = {e: np.flatnonzero(data.episode == e) for e in episodes}
    rows = np.concatenate([rows_of[e] for e in chosen])
    all_features = data.features
    x, y = all_features[rows], data.targets[rows]
    mean, std = x.mean(axis=0), x.std(axis=0)
    std = np.where(std > 1e-8, std, 1.0)
    torch.manual_seed(seed)
    n_out = len(TARGET_NAMES)
    layers: list[Any] = []
    width = x.shape[1]
    for h in settings.hidden:
        layers += [torch.nn.Linear(width, h), torch.nn.Tanh()]
        width = h
    layers.append(torch.nn.Linear(width, 2 * n_out))
    net = torch.nn.Sequential(*layers).double()
    opt = torch.optim.Adam(net.parameters(), lr=settings.learning_rate, weight_decay=settings.weight_decay)
    sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, settings.epochs)
    xt = torch.as_tensor((x - mean) / std)
    yt = torch.as_tensor(y)
    gen = torch.Generator().manual_seed(seed)
    for _ in range(settings.epochs):
        for idx in torch.randperm(len(xt), generator=gen).split(settings.batch_size):
            out = net(xt[idx])
            mu, log_var = out[:, :n_out], out[:, n_out:].clamp(-12.0, 4.0)
            loss = (0.5 * (log_var + (yt[idx] - mu) ** 2 * torch.exp(-log_var))).mean()
            opt.zero_grad()
            loss.backward()
            opt.step()
        sched.step()
    linear = [m for m in net if isinstance(m, torch.nn.Linear)]
    return FilterNetwork(mean, std, tuple(m.weight.detach().numpy().T.copy() for m in linear),
                         tuple(m.bias.detach().numpy().copy() for m in linear))


def nll(member_or_ensemble, data: Dataset) -> dict[str, float]:
    """Per-target RMSE and mean Gaussian NLL of a member's predictions on ``data``."""
    x = data.features
    if isinstance(member_or_ensemble, FilterNetwork):
        mu, log_var = member_or_ensemble(x)
        std = np.exp(0.5 * log_var)
    else:
        mu, std = member_or_ensemble.predict(x)
    out = {}
    for k, name in enumerate(TARGET_NAMES):
        err = data.targets[:, k] - mu[:, k]
        out[f"{name}_rmse"] = float(np.sqrt(np.mean(err**2)))
        out[f"{name}_nll"] = float(np.mean(np.log(std[:, k]) + 0.5 * (err / std[:, k]) ** 2))
    return out
