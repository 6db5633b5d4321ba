"""Episode scenarios: what is drawn per episode, from which ranges, and how to override it.

Every draw comes from the environment's ``np_random``; any field can be fixed by a constructor kwarg
of the same name or per episode by ``reset(options={...})``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from cof_gym.physics.creep import CONDITIONS, OperatingConditions
from cof_gym.physics.simulation import Scenario, SensorNoise
from cof_gym.physics.vehicle import LOAD_CASES

# sensor noise at full scale (noise_level = 1): realistic on-board sensors (assumed values)
FULL_SCALE_NOISE = SensorNoise(omega_rad_s=0.02, force_relative=0.02, speed_m_s=0.05)


@dataclass(frozen=True)
class ScenarioRanges:
    """Ranges of the per-episode draws (uniform unless stated)."""

    cof: tuple[float, float] = (0.02, 0.6)
    conditions: tuple[str, ...] = tuple(CONDITIONS)
    speed_m_s: tuple[float, float] = (5.0, 40.0)
    load_cases: tuple[str, ...] = LOAD_CASES
    noise_level: tuple[float, float] = (0.0, 1.0)  # multiplies FULL_SCALE_NOISE
    motor_lag_s: tuple[float, float] = (0.0, 0.03)

    def __post_init__(self) -> None:
        _range("cof", self.cof, 0.0, 1.5)
        _range("speed_m_s", self.speed_m_s, 0.0, 100.0)
        _range("noise_level", self.noise_level, -1e-12, 10.0)
        _range("motor_lag_s", self.motor_lag_s, -1e-12, 1.0)
        _choices("conditions", self.conditions, CONDITIONS)
        _choices("load_cases", self.load_cases, LOAD_CASES)


def _range(name: str, value: tuple[float, float], low: float, high: float) -> None:
    if len(value) != 2 or not all(math.isfinite(v) for v in value) or not (low < value[0] <= value[1] <= high):
        raise ValueError(f"{name} range must satisfy {low} < min <= max <= {high}, got {value!r}")


def _choices(name: str, value: tuple[str, ...], allowed) -> None:
    if not value or any(v not in allowed for v in value):
        raise ValueError(f"{name} must be a non-empty subset of {sorted(allowed)}, got {value!r}")


@dataclass(frozen=True)
class EpisodeScenario:
    """One episode's draw (the ground truth the agent never observes)."""

    cof: float
    condition: str
    speed_m_s: float
    load_case: str
    noise_level: float
    motor_lag_s: float

    def to_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def physics(self, wheel_load_n: float, seed: int) -> Scenario:
        op = OperatingConditions(cof=self.cof, condition=self.condition, wheel_load_n=wheel_load_n,
                                 speed_m_s=self.speed_m_s)
        noise = SensorNoise(*(self.noise_level * getattr(FULL_SCALE_NOISE, f.name) for f in fields(SensorNoise)))
        return Scenario(op=op, noise=noise, motor_lag_s=self.motor_lag_s, seed=seed)


SCENARIO_KEYS = tuple(f.name for f in fields(EpisodeScenario))


def draw_scenario(rng: np.random.Generator, ranges: ScenarioRanges, fixed: dict) -> EpisodeScenario:
    """Draw every field not in ``fixed`` (always drawing all, so fixing one leaves the others' stream
    unchanged), then validate the fixed ones through the physics layer."""
    unknown = set(fixed) - set(SCENARIO_KEYS)
    if unknown:
        raise ValueError(f"unknown scenario option(s) {sorted(unknown)}; allowed: {list(SCENARIO_KEYS)}")
    drawn = {
        "cof": float(rng.uniform(*ranges.cof)),
        "condition": str(ranges.conditions[rng.integers(len(ranges.conditions))]),
        "speed_m_s": float(rng.uniform(*ranges.speed_m_s)),
        "load_case": str(ranges.load_cases[rng.integers(len(ranges.load_cases))]),
        "noise_level": float(rng.uniform(*ranges.noise_level)),
        "motor_lag_s": float(rng.uniform(*ranges.motor_lag_s)),
    }
    drawn.update({k: v for k, v in fixed.items() if v is not None})
    sc = EpisodeScenario(**drawn)
    if sc.load_case not in LOAD_CASES:
        raise ValueError(f"load_case must be one of {list(LOAD_CASES)}, got {sc.load_case!r}")
    if not (math.isfinite(sc.noise_level) and sc.noise_level >= 0):
        raise ValueError(f"noise_level must be >= 0, got {sc.noise_level!r}")
    if not (math.isfinite(sc.motor_lag_s) and 0.0 <= sc.motor_lag_s <= 1.0):
        raise ValueError(f"motor_lag_s must be in [0, 1] s, got {sc.motor_lag_s!r}")
    if sc.load_case not in ranges.load_cases:
        raise ValueError(f"load_case must be one of {list(ranges.load_cases)} for this vehicle, got {sc.load_case!r}")
    OperatingConditions(cof=sc.cof, condition=sc.condition, speed_m_s=sc.speed_m_s)  # validates
    return sc
