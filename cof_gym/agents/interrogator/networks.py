"""The learned filter: small heteroscedastic networks (:class:`FilterNetwork`) and their ensemble
(:class:`FilterEnsemble`), predicting the headroom and the correction (:data:`TARGET_NAMES`) with their std."""

from __future__ import annotations

import json
import zipfile
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Iterator

import numpy as np

from cof_gym.agents.interrogator.features import FEATURE_NAMES, blocks_of

TARGET_NAMES = ("headroom", "correction")  # ln(M_sat / DC), ln(CoF / CoA measured)


def pooled_correction(predictions: Iterable[tuple[float, float]]) -> float:
    """The inverse-variance weighted mean of Gaussian predictions ``(mean, std)`` of one quantity (stds
    floored at 1e-6)."""
    weights_means = [(1.0 / max(std, 1e-6) ** 2, mean) for mean, std in predictions]
    if not weights_means:
        raise ValueError("pooled_correction: no predictions to pool")
    return sum(w * m for w, m in weights_means) / sum(w for w, _ in weights_means)


def pooled_std(predictions: Iterable[tuple[float, float]]) -> float:
    """The std that goes with :func:`pooled_correction`'s mean of Gaussian predictions ``(mean, std)``: the root
    of their mean variance under the same inverse-variance weights, ``sqrt(n / sum(1 / std^2))`` (stds floored
    at 1e-6). It is each one's std where they agree; it does not shrink as ``1 / sqrt(n)``, because the pooled
    networks read the same windows and their errors are not independent."""
    precisions = [1.0 / max(std, 1e-6) ** 2 for _, std in predictions]
    if not precisions:
        raise ValueError("pooled_std: no predictions to pool")
    return (len(precisions) / sum(precisions)) ** 0.5


@dataclass(frozen=True)
class FilterNetwork:
    """One member: a tanh MLP on standardised features giving (mean, log variance) of each target."""

    feature_mean: np.ndarray
    feature_std: np.ndarray
    weights: tuple[np.ndarray, ...]
    biases: tuple[np.ndarray, ...]
    feature_names: tuple[str, ...] = FEATURE_NAMES  # :func:`feature_names` of the blocks it reads

    def __post_init__(self) -> None:
        """Arrays that chain: a mean and a positive std per feature name, each layer's weights (in, out) with its
        biases (out,), the last out two per target (mean, log variance), every number finite (ValueError)."""
        n = len(self.feature_names)
        width = n
        problems = []
        if np.shape(self.feature_mean) != (n,) or np.shape(self.feature_std) != (n,):
            problems.append(f"feature_mean and feature_std must have {n} entries (one per feature name)")
        elif not (np.all(np.isfinite(self.feature_std)) and np.all(np.asarray(self.feature_std) > 0.0)):
            problems.append("feature_std must be finite and > 0")
        if not self.weights or len(self.weights) != len(self.biases):
            problems.append("the network needs as many weight as bias arrays, at least one of each")
        for i, (w, b) in enumerate(zip(self.weights, self.biases)):
            if np.ndim(w) != 2 or np.shape(w)[0] != width or np.shape(b) != (np.shape(w)[1],):
                problems.append(f"w{i} must be ({width}, k) with b{i} (k,), got {np.shape(w)} and {np.shape(b)}")
                break
            width = np.shape(w)[1]
        else:
            if self.weights and width != 2 * len(TARGET_NAMES):
                problems.append(f"the last layer must give {2 * len(TARGET_NAMES)} outputs, gives {width}")
        arrays = (self.feature_mean, self.feature_std, *self.weights, *self.biases)
        if not problems and not all(np.all(np.isfinite(a)) for a in arrays):
            problems.append("every weight, bias, mean and std must be finite")
        if problems:
            raise ValueError(f"not an interrogator network: {problems[0]}")

    @property
    def blocks(self) -> tuple[str, ...]:
        return blocks_of(self.feature_names)

    @property
    def tones(self) -> int:
        return 2 if "tone2" in self.blocks else 1

    def __call__(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        h = (np.atleast_2d(x) - self.feature_mean) / self.feature_std
        for w, b in zip(self.weights[:-1], self.biases[:-1]):
            h = np.tanh(h @ w + b)
        out = h @ self.weights[-1] + self.biases[-1]
        n = len(TARGET_NAMES)
        return out[:, :n], np.clip(out[:, n:], -12.0, 4.0)

    def save(self, path: Path) -> None:
        arrays = {"feature_mean": self.feature_mean, "feature_std": self.feature_std}
        arrays |= {f"w{i}": w for i, w in enumerate(self.weights)} | {f"b{i}": b for i, b in enumerate(self.biases)}
        np.savez(path, feature_names=np.asarray(self.feature_names), **arrays)

    @classmethod
    def load(cls, path: Path) -> "FilterNetwork":
        with open_npz(path, "an interrogator network") as z:
            if "feature_names" not in z.files:
                raise ValueError(f"{path}: not an interrogator network (no feature_names)")
            names = tuple(str(n) for n in z["feature_names"])
            try:
                blocks_of(names)
            except ValueError:
                raise ValueError(f"{path}: the network was trained on other features ({len(names)} names); retrain it") from None
            missing = sorted({"feature_mean", "feature_std", "w0", "b0"} - set(z.files))
            if missing:
                raise ValueError(f"{path}: not an interrogator network (no {', '.join(missing)})")
            layers = sum(1 for k in z.files if k.startswith("w"))
            try:
                return cls(z["feature_mean"], z["feature_std"], tuple(z[f"w{i}"] for i in range(layers)),
                           tuple(z[f"b{i}"] if f"b{i}" in z.files else np.zeros(0) for i in range(layers)), names)
            except ValueError as e:
                raise ValueError(f"{path}: {e}") from None


@contextmanager
def open_npz(path: Path, what: str) -> Iterator[np.lib.npyio.NpzFile]:
    """``np.load(path)`` of a network's ``.npz``; a file that is no readable ``.npz`` (garbage, truncated, a pickle
    numpy would refuse with its own words) is a one-line ``ValueError`` saying it is not ``what``."""
    try:
        archive = np.load(path)
    except FileNotFoundError:
        raise
    except (OSError, ValueError, EOFError, zipfile.BadZipFile):  # (numpy's words for garbage speak of pickles)
        raise ValueError(f"{path}: not {what} (not a readable .npz archive)") from None
    if not isinstance(archive, np.lib.npyio.NpzFile):  # a bare .npy array
        raise ValueError(f"{path}: not {what} (a single array, not an .npz archive)")
    with archive as z:
        yield z


# a pooled ensemble read generation by generation (FilterEnsemble.generations): {"members": [count, count, ...]}
GENERATIONS_FILE = "generations.json"


def member_files(directory: Path) -> list[Path]:
    """An ensemble directory's network files (``member_*.npz``), in the order :meth:`FilterEnsemble.load` reads them
    (sorted by name); empty where it holds none."""
    return sorted(Path(directory).glob("member_*.npz"))


def ensemble_files(directory: Path) -> list[Path]:
    """Every file an ensemble directory's predictions read: its network files (:func:`member_files`) and, where it
    has one, its :data:`GENERATIONS_FILE`: what a copy of the ensemble carries and a digest of it covers."""
    generations = Path(directory) / GENERATIONS_FILE
    return [*member_files(directory), *([generations] if generations.is_file() else [])]


@dataclass(frozen=True)
class FilterEnsemble:
    """Members' Gaussian predictions combined: the mean of the means, the variance their spread plus
    the mean predicted variance. With ``generations`` (the member counts of ensembles pooled, in the members'
    order), each generation's members are combined so and the generations averaged: the mean of their means, the
    variance the mean of their variances, so that the generations' disagreement with one another adds nothing to the
    std (where they were fitted on other climbs, it measures that, not what either is unsure of)."""

    members: tuple[FilterNetwork, ...]
    generations: tuple[int, ...] | None = None

    def __post_init__(self) -> None:
        if len({m.feature_names for m in self.members}) > 1:
            raise ValueError("the ensemble's members read different features (tones or blocks); fit them alike")
        if self.generations is not None and (
                any(not isinstance(n, int) or isinstance(n, bool) or n < 1 for n in self.generations)
                or sum(self.generations) != len(self.members)):
            raise ValueError(f"generations: member counts of at least 1 that add up to the {len(self.members)} "
                             f"members, got {list(self.generations)}")

    @property
    def blocks(self) -> tuple[str, ...]:
        return self.members[0].blocks

    @property
    def tones(self) -> int:
        return self.members[0].tones

    def predict(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(mean, std) of every target, shape (n, 2) each."""
        mean, std, _ = self.predict_with_spread(x)
        return mean, std

    def predict_with_spread(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(mean, std, spread) of every target, shape (n, 2) each: the mixture's std (the members'
        spread and their mean predicted variance together; Lakshminarayanan et al. 2017) and the
        members' spread alone (their disagreement: large where the readings are unlike the training
        climbs')."""
        outs = [m(x) for m in self.members]
        means = np.stack([o[0] for o in outs])
        variances = np.stack([np.exp(o[1]) for o in outs])
        if self.generations is None:
            spread_var = means.var(axis=0)
            return means.mean(axis=0), np.sqrt(spread_var + variances.mean(axis=0)), np.sqrt(spread_var)
        groups = np.split(np.arange(len(self.members)), np.cumsum(self.generations)[:-1])
        spread_var = np.mean([means[g].var(axis=0) for g in groups], axis=0)
        variance = np.mean([variances[g].mean(axis=0) for g in groups], axis=0)
        return np.mean([means[g].mean(axis=0) for g in groups], axis=0), np.sqrt(spread_var + variance), \
            np.sqrt(spread_var)

    @classmethod
    def load(cls, directory: Path, members: list[str] | None = None) -> "FilterEnsemble":
        directory = Path(directory)
        files = [directory / f"{m}.npz" for m in members] if members else member_files(directory)
        if not files or not all(f.is_file() for f in files):
            raise FileNotFoundError(f"no interrogator networks in {directory} (expected member_*.npz)")
        return cls(tuple(FilterNetwork.load(f) for f in files), None if members else read_generations(directory))


def read_generations(directory: Path) -> tuple[int, ...] | None:
    """The member counts ``directory``'s :data:`GENERATIONS_FILE` names (None where it has none)."""
    path = Path(directory) / GENERATIONS_FILE
    if not path.is_file():
        return None
    counts = json.loads(path.read_text()).get("members")
    if not isinstance(counts, list):
        raise ValueError(f"{path}: expected {{\"members\": [count, ...]}}")
    return tuple(counts)
