"""Episode scenarios: what is drawn per episode, from which ranges, and how to override it.

Every draw comes from the environment's ``np_random``; any field can be fixed by a constructor kwarg
of the same name or per episode by ``reset(options={...})``.

**CoF ranges per condition** (the draws; a fixed ``cof`` may pair with any condition inside the
envelope :data:`COF_ENVELOPE`):

============= =========== =====================================================================
condition      CoF drawn   source
============= =========== =====================================================================
dry            0.15-0.60   clean dry rail 0.20-0.40 in service (UK Adhesion Working Group,
                           *Managing low adhesion*, "What is low adhesion"), up to ~0.5-0.6 in
                           laboratory tests; the paper sweeps 0.1-0.5
wet            0.05-0.25   wet rail 0.10-0.20 (same source); 0.05-0.15 in traction tables
low_adhesion   0.02-0.10   leaf layers: below the 0.09 a full-service brake needs, reported down
                           to ~0.01 (same source)
dry_kalker     0.15-0.60   the dry range (not drawn by default; see :mod:`cof_gym.physics.creep`)
============= =========== =====================================================================

**Creep law.** v1 (``ScenarioRanges()``): the condition's Polach preset. v2
(:data:`V2_RANGES`): per episode a family from ``ranges.creep_families`` and a shape of it drawn from
that family's documented ranges for the condition (:func:`cof_gym.physics.creep_laws.draw_shape`).
``creep_law`` fixes it (a preset name, ``{"polach": {...}}``, ``{"table": {"creepage": [...],
"adhesion_ratio": [...]}}``, any family of :data:`cof_gym.physics.creep_laws.FAMILIES`) and replaces
the condition's shape; the condition still sets the CoF range of a draw.

**Systematic sensor errors** (:mod:`cof_gym.task.sensors`): drawn in +-``sensor_error_scale`` x each
error's documented range (0 in v1, 1 in v2 and v3); each fixable within its accepted range.

**The speed probe and the track** (v3, :data:`V3_RANGES`; v1 and v2 read a continuous, unlagged encoder on a
level track): per episode the encoder's pulses per wheelset revolution, its target wheel's runout, its speed
signal's lag and the track's irregularity class, each fixable as in v2:

====================== ============= ==================================================================
field                   drawn (v3)    source
====================== ============= ==================================================================
encoder_pulses_per_rev  60-300        "between 60 and 300 pulses per revolution" for the two-channel
                                      probes that read a traction drive's target wheel (Wikipedia,
                                      "Wheel speed sensor", "Rail vehicles", as read in 2026); read by
                                      the period method (:mod:`cof_gym.physics.encoder`)
encoder_runout          0-0.1 %       the target wheel's runout over its pitch radius, up to 0.1 mm on a
                                      100 mm radius: cof_gym's choice, a machined and mounted toothed
                                      wheel's order of magnitude (unverified)
encoder_lag_s           0-5 ms        a first-order lag of the speed signal (the drive's filtering):
                                      cof_gym's choice, a filter well above the 5 Hz modulation
                                      (unverified; :mod:`cof_gym.task.sensors`)
track_irregularity      ore_low,      every real track has a vertical profile: ORE B176's spectra for
                        ore_high      low and high irregularity (:mod:`cof_gym.physics.track`)
====================== ============= ==================================================================
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np

from cof_gym.physics.creep import CONDITIONS, OperatingConditions
from cof_gym.physics.creep_laws import (PRESET_FAMILY, RANGES as CREEP_RANGES, CreepShape, creep_law_from_spec,
                                        draw_shape)
from cof_gym.physics.encoder import (PULSES_PER_REV_RANGE, RUNOUT_MAX, PulseEncoder, check_pulses_per_rev,
                                    check_runout)
from cof_gym.physics.simulation import Scenario, SensorNoise
from cof_gym.physics.track import SMOOTH, TRACK_CLASSES, draw_profile
from cof_gym.physics.vehicle import LOAD_CASES
from cof_gym.task.sensors import SYSTEMATIC_ERRORS, SensorErrors
from cof_gym.validation import check_choice, check_number, check_range, is_int

# sensor noise at full scale (noise_level = 1): realistic on-board sensors (assumed values)
FULL_SCALE_NOISE = SensorNoise(omega_rad_s=0.02, force_relative=0.02, speed_m_s=0.05)

COF_BY_CONDITION: Mapping[str, tuple[float, float]] = MappingProxyType({
    "dry": (0.15, 0.60),
    "wet": (0.05, 0.25),
    "low_adhesion": (0.02, 0.10),
    "dry_kalker": (0.15, 0.60),
})
DEFAULT_CONDITIONS = ("dry", "wet", "low_adhesion")
COF_ENVELOPE = (0.02, 0.60)  # every CoF the task accepts; the drive reaches its peak at each
SPEED_ENVELOPE_M_S = (5.0, 40.0)
NOISE_LEVEL_MAX = 3.0  # multiples of FULL_SCALE_NOISE
MOTOR_LAG_MAX_S = 0.1
ENCODER_LAG_MAX_S = 0.05  # the encoder's speed-signal lag a scenario may have (v1 and v2 draw 0)
SENSOR_ERROR_SCALE_MAX = 3.0  # multiples of each systematic error's drawn range


@dataclass(frozen=True)
class ScenarioRanges:
    """Ranges of the per-episode draws (uniform). ``cof`` maps each condition to its CoF range."""

    cof: Mapping[str, tuple[float, float]] = field(default_factory=lambda: dict(COF_BY_CONDITION))
    conditions: tuple[str, ...] = DEFAULT_CONDITIONS
    speed_m_s: tuple[float, float] = SPEED_ENVELOPE_M_S
    load_cases: tuple[str, ...] = LOAD_CASES
    noise_level: tuple[float, float] = (0.0, 1.0)  # multiplies FULL_SCALE_NOISE
    motor_lag_s: tuple[float, float] = (0.0, 0.03)
    creep_families: tuple[str, ...] | None = None  # None: the condition's preset (v1); else drawn shapes
    sensor_error_scale: float = 0.0  # systematic errors drawn in +- this x their ranges (v1: none)
    # the speed probe and the track (v3); the defaults draw none: a continuous, unlagged encoder on a level track
    encoder_pulses_per_rev: tuple[int, int] = (0, 0)  # integers drawn uniformly in this range; (0, 0): continuous
    encoder_runout: tuple[float, float] = (0.0, 0.0)
    encoder_lag_s: tuple[float, float] = (0.0, 0.0)
    track_irregularities: tuple[str, ...] = (SMOOTH,)

    def __post_init__(self) -> None:
        if not isinstance(self.cof, Mapping):
            raise ValueError(f"ranges.cof must map condition -> (min, max), got {self.cof!r}")
        # the numbers are stored as checked: (min, max) tuples of Python floats, so a numpy scalar draws
        # exactly what the float it holds would (a pair of Python floats draws as before, bit for bit)
        set_ = object.__setattr__
        cof = {}
        for cond, rng in self.cof.items():
            check_choice("ranges.cof condition", cond, CONDITIONS)
            cof[cond] = check_range(f"ranges.cof[{cond!r}]", rng, *COF_ENVELOPE)
        set_(self, "cof", cof)
        _choices("ranges.conditions", self.conditions, tuple(self.cof))
        set_(self, "speed_m_s", check_range("ranges.speed_m_s", self.speed_m_s, *SPEED_ENVELOPE_M_S))
        set_(self, "noise_level", check_range("ranges.noise_level", self.noise_level, 0.0, NOISE_LEVEL_MAX))
        set_(self, "motor_lag_s", check_range("ranges.motor_lag_s", self.motor_lag_s, 0.0, MOTOR_LAG_MAX_S))
        _choices("ranges.load_cases", self.load_cases, LOAD_CASES)
        if self.creep_families is not None:
            _choices("ranges.creep_families", self.creep_families, tuple(CREEP_RANGES))
        set_(self, "sensor_error_scale", check_number("ranges.sensor_error_scale", self.sensor_error_scale, 0.0,
                                                      SENSOR_ERROR_SCALE_MAX))
        set_(self, "encoder_pulses_per_rev", _pulses_range(self.encoder_pulses_per_rev))
        set_(self, "encoder_runout", check_range("ranges.encoder_runout", self.encoder_runout, 0.0, RUNOUT_MAX))
        set_(self, "encoder_lag_s", check_range("ranges.encoder_lag_s", self.encoder_lag_s, 0.0, ENCODER_LAG_MAX_S))
        _choices("ranges.track_irregularities", self.track_irregularities, TRACK_CLASSES)
        set_(self, "track_irregularities", tuple(self.track_irregularities))

    @classmethod
    def from_mapping(cls, value: Mapping[str, Any]) -> "ScenarioRanges":
        """Ranges from a mapping of their fields, as a spec's JSON holds them (``EnvSpec.to_json``: lists where the
        fields are tuples); a field the ranges do not have is a ``ValueError`` naming those they have."""
        names = [f.name for f in fields(cls)]
        unknown = sorted(set(value) - set(names))
        if unknown:
            raise ValueError(f"ranges: unknown field(s) {unknown}; allowed: {names}")

        def tuples(v: Any) -> Any:
            return tuple(v) if isinstance(v, list) else v

        return cls(**{name: {c: tuples(r) for c, r in v.items()} if name == "cof" and isinstance(v, Mapping)
                      else tuples(v) for name, v in value.items()})

    @property
    def draws_v2(self) -> bool:
        """Whether the v2 fields (a creep-law shape, systematic errors) are drawn."""
        return self.creep_families is not None or self.sensor_error_scale > 0.0

    @property
    def draws_v3(self) -> bool:
        """Whether the v3 fields (the speed probe's pulses, runout and lag, the track's irregularity) are drawn."""
        return (self.encoder_pulses_per_rev != (0, 0) or self.encoder_runout != (0.0, 0.0)
                or self.encoder_lag_s != (0.0, 0.0) or self.track_irregularities != (SMOOTH,))


def _pulses_range(value: Any) -> tuple[int, int]:
    """``ranges.encoder_pulses_per_rev``: (0, 0) (the continuous reading) or a (min, max) pair of integers within
    :data:`cof_gym.physics.encoder.PULSES_PER_REV_RANGE`."""
    name = "ranges.encoder_pulses_per_rev"
    low, high = PULSES_PER_REV_RANGE
    if isinstance(value, (tuple, list)) and len(value) == 2 and all(is_int(v) for v in value):
        lo, hi = int(value[0]), int(value[1])
        if (lo, hi) == (0, 0) or low <= lo <= hi <= high:
            return lo, hi
    raise ValueError(f"{name} must be (0, 0) (a continuous reading) or a (min, max) pair of integers within "
                     f"[{low}, {high}] with min <= max, got {value!r}")


def _choices(name: str, value: Any, allowed: tuple[str, ...]) -> None:
    if not isinstance(value, (tuple, list)) or not value or any(v not in allowed for v in value):
        raise ValueError(f"{name} must be a non-empty subset of {list(allowed)}, got {value!r}")


@dataclass(frozen=True)
class EpisodeScenario:
    """One episode's draw (the ground truth the agent never observes)."""

    cof: float
    condition: str
    speed_m_s: float
    load_case: str
    noise_level: float
    motor_lag_s: float
    creep_law: CreepShape | None = None  # None: the condition's preset
    speed_sensor_error: float = 0.0
    wheel_radius_error: float = 0.0
    force_gain_error: float = 0.0
    torque_gain_error: float = 0.0
    encoder_lag_s: float = 0.0  # first-order lag of the encoder's speed signal, s (cof_gym.task.sensors)
    track_irregularity: str = SMOOTH  # the rail's vertical profile: its spectrum's class (cof_gym.physics.track)
    encoder_pulses_per_rev: int = 0  # the speed probe's pulses per wheelset revolution, 0: a continuous reading
    encoder_runout: float = 0.0  # its target wheel's runout over its pitch radius (cof_gym.physics.encoder)

    @property
    def shape(self) -> CreepShape | str:
        """The creep-curve shape the physics runs: ``creep_law``, else the condition's preset."""
        return self.condition if self.creep_law is None else self.creep_law

    @property
    def creep_family(self) -> str:
        return PRESET_FAMILY if self.creep_law is None else self.creep_law.family

    @property
    def sensor_errors(self) -> SensorErrors:
        return SensorErrors(**{name: getattr(self, name) for name in SYSTEMATIC_ERRORS})

    def to_dict(self) -> dict:
        """Every field, the creep law as its spec (``{family: {parameter: value}}``, JSON-ready)."""
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        out["creep_law"] = shape_spec(self.creep_law) if self.creep_law is not None else self.condition
        out["creep_family"] = self.creep_family
        out["creepage_offset"] = self.sensor_errors.creepage_offset
        return out

    def noise(self) -> SensorNoise:
        return SensorNoise(*(self.noise_level * getattr(FULL_SCALE_NOISE, f.name) for f in fields(SensorNoise)))


SCENARIO_KEYS = tuple(f.name for f in fields(EpisodeScenario))


def shape_spec(shape: CreepShape) -> dict[str, dict[str, Any]]:
    """The spec of a shape, ``{family: {parameter: value}}`` (lists for tables): what
    :func:`cof_gym.physics.creep_laws.creep_law_from_spec` reads back."""
    return {shape.family: {f.name: (list(v) if isinstance(v := getattr(shape, f.name), tuple) else v)
                           for f in fields(shape)}}


def check_fixed(fixed: Mapping[str, Any], load_cases: tuple[str, ...] = LOAD_CASES) -> dict[str, Any]:
    """Validate fixed scenario fields (None: drawn), each by type and range; returns them cleaned."""
    if not isinstance(fixed, Mapping):
        raise ValueError(f"scenario options must be a dict of {list(SCENARIO_KEYS)}, got {fixed!r}")
    unknown = set(fixed) - set(SCENARIO_KEYS)
    if unknown:
        raise ValueError(f"unknown scenario option(s) {sorted(unknown)}; allowed: {list(SCENARIO_KEYS)}")
    out: dict[str, Any] = {}
    for key, value in fixed.items():
        if value is None:
            continue
        if key == "cof":
            out[key] = check_number("cof", value, *COF_ENVELOPE)
        elif key == "condition":
            out[key] = check_choice("condition", value, tuple(COF_BY_CONDITION))
        elif key == "speed_m_s":
            out[key] = check_number("speed_m_s", value, *SPEED_ENVELOPE_M_S, unit=" m/s")
        elif key == "load_case":
            out[key] = check_choice("load_case", value, load_cases)
        elif key == "noise_level":
            out[key] = check_number("noise_level", value, 0.0, NOISE_LEVEL_MAX)
        elif key == "motor_lag_s":
            out[key] = check_number("motor_lag_s", value, 0.0, MOTOR_LAG_MAX_S, unit=" s")
        elif key == "encoder_lag_s":
            out[key] = check_number("encoder_lag_s", value, 0.0, ENCODER_LAG_MAX_S, unit=" s")
        elif key == "creep_law":
            out[key] = creep_law_from_spec(value)
        elif key == "track_irregularity":
            out[key] = check_choice("track_irregularity", value, TRACK_CLASSES)
        elif key == "encoder_pulses_per_rev":
            out[key] = check_pulses_per_rev(key, value)
        elif key == "encoder_runout":
            out[key] = check_runout(key, value)
        else:
            bound = SYSTEMATIC_ERRORS[key].accepted
            out[key] = check_number(key, value, -bound, bound)
    return out


def draw_scenario(rng: np.random.Generator, ranges: ScenarioRanges, fixed: Mapping[str, Any]) -> EpisodeScenario:
    """Draw every field not in ``fixed`` (always drawing all, in a fixed order, so fixing one leaves
    the others' streams unchanged). The CoF is drawn in the range of the episode's condition."""
    fixed = check_fixed(fixed, ranges.load_cases)
    condition = str(ranges.conditions[rng.integers(len(ranges.conditions))])
    condition = fixed.get("condition", condition)
    unit_cof = float(rng.uniform())
    lo, hi = ranges.cof.get(condition, COF_ENVELOPE)
    drawn = {
        "cof": lo + (hi - lo) * unit_cof,
        "condition": condition,
        "speed_m_s": float(rng.uniform(*ranges.speed_m_s)),
        "load_case": str(ranges.load_cases[rng.integers(len(ranges.load_cases))]),
        "noise_level": float(rng.uniform(*ranges.noise_level)),
        "motor_lag_s": float(rng.uniform(*ranges.motor_lag_s)),
    }
    if ranges.draws_v2:  # drawn after the v1 fields, so v1 streams (and numbers) stay as they were
        drawn.update(_draw_v2(rng, ranges, condition))
    if ranges.draws_v3:  # drawn after the v2 fields, so v2 streams (and numbers) stay as they were
        drawn.update(_draw_v3(rng, ranges))
    drawn.update(fixed)
    return EpisodeScenario(**drawn)


def _draw_v2(rng: np.random.Generator, ranges: ScenarioRanges, condition: str) -> dict[str, Any]:
    """A creep-law shape for ``condition`` (when families are drawn) and the systematic errors."""
    out: dict[str, Any] = {}
    families = ranges.creep_families or ()
    family = str(families[rng.integers(len(families))]) if families else None
    if family is not None and condition in CREEP_RANGES[family]:
        out["creep_law"] = draw_shape(rng, family, condition)
    for name, err in SYSTEMATIC_ERRORS.items():
        out[name] = float(rng.uniform(-1.0, 1.0)) * err.drawn * ranges.sensor_error_scale
    return out


def _draw_v3(rng: np.random.Generator, ranges: ScenarioRanges) -> dict[str, Any]:
    """The speed probe (pulses per revolution, its target wheel's runout, its signal's lag) and the track's class."""
    low, high = ranges.encoder_pulses_per_rev
    tracks = ranges.track_irregularities
    return {"encoder_pulses_per_rev": int(rng.integers(low, high + 1)),
            "encoder_runout": float(rng.uniform(*ranges.encoder_runout)),
            "encoder_lag_s": float(rng.uniform(*ranges.encoder_lag_s)),
            "track_irregularity": str(tracks[rng.integers(len(tracks))])}


def outside_draws(options: Mapping[str, Any], ranges: ScenarioRanges) -> dict[str, str]:
    """Where an episode's fixed ``options`` (validated as :func:`check_fixed` does) lie outside what
    ``ranges`` draws: field -> what it is and what is drawn (``{}``: a scenario the draws could have
    produced). A learned agent trained on ``ranges`` is out of its training distribution there."""
    fixed = check_fixed(options, ranges.load_cases)
    out: dict[str, str] = {}
    condition = fixed.get("condition")
    if condition is not None and condition not in ranges.conditions:
        out["condition"] = f"{condition!r}, drawn: {', '.join(ranges.conditions)}"
    conditions = (condition,) if condition in ranges.cof else ranges.conditions
    intervals = {"cof": (min(ranges.cof[c][0] for c in conditions), max(ranges.cof[c][1] for c in conditions)),
                 "speed_m_s": ranges.speed_m_s, "noise_level": ranges.noise_level, "motor_lag_s": ranges.motor_lag_s,
                 "encoder_lag_s": ranges.encoder_lag_s, "encoder_runout": ranges.encoder_runout,
                 "encoder_pulses_per_rev": ranges.encoder_pulses_per_rev}
    for name, (lo, hi) in intervals.items():
        if name in fixed and not lo <= fixed[name] <= hi:
            drawn = f"{lo:g}" if lo == hi else f"{lo:g}-{hi:g}"
            continuous = name == "encoder_pulses_per_rev" and hi == 0
            out[name] = f"{fixed[name]:g}, drawn: {drawn}" + (" (a continuous reading)" if continuous else "")
    for name, drawn_choices in (("load_case", ranges.load_cases), ("track_irregularity", ranges.track_irregularities)):
        if name in fixed and fixed[name] not in drawn_choices:
            shown = ", ".join(drawn_choices) if name == "load_case" else ", ".join(map(repr, drawn_choices))
            out[name] = f"{fixed[name]!r}, drawn: {shown}"
    if "creep_law" in fixed and (why := _creep_law_outside(fixed["creep_law"], ranges, conditions)):
        out["creep_law"] = why
    for name, err in SYSTEMATIC_ERRORS.items():
        bound = err.drawn * ranges.sensor_error_scale
        if abs(fixed.get(name, 0.0)) > bound * (1.0 + 1e-9):
            out[name] = f"{fixed[name]:+g}, drawn: within +-{bound:g}"
    return out


def _creep_law_outside(shape: CreepShape, ranges: ScenarioRanges, conditions: tuple[str, ...]) -> str | None:
    """Why a fixed creep-law shape is none the draws give (a family not drawn, or parameters outside
    its family's ranges for every condition the episode may have), None when the draws include it."""
    families = ranges.creep_families or ()
    if shape.family not in families:
        return f"{shape.family!r}, drawn: {', '.join(families) or 'the condition presets'}"
    family_ranges = CREEP_RANGES[shape.family]
    if any(all(lo <= getattr(shape, name) <= hi for name, (lo, hi) in family_ranges[c].items())
           for c in conditions if c in family_ranges):
        return None
    return f"{shape.family} parameters beyond the drawn ranges"


# the families v2 draws, in this order: frozen with v2's published numbers (a family added to the creep-law registry
# with ranges of its own joins a new task version's draws, never v2's; tested)
V2_CREEP_FAMILIES = ("polach", "shen_hedrick_elkins")
V2_RANGES = ScenarioRanges(creep_families=V2_CREEP_FAMILIES, sensor_error_scale=1.0)
"""The v2 task's draws: the two analytic families (:data:`V2_CREEP_FAMILIES`), systematic sensor errors."""
V3_RANGES = replace(V2_RANGES, encoder_pulses_per_rev=(60, 300), encoder_runout=(0.0, 0.001),
                    encoder_lag_s=(0.0, 0.005), track_irregularities=("ore_low", "ore_high"))
"""The v3 task's draws: v2's, and a train's speed probe (pulses, runout, lag) on a track of ORE B176 irregularity
(the module docstring's table; drawn after v2's fields)."""
TASK_VERSION_RANGES: Mapping[int, ScenarioRanges] = MappingProxyType({1: ScenarioRanges(), 2: V2_RANGES, 3: V3_RANGES})
"""Each task version's draws (the -v1, -v2 and -v3 ids): one table, which the env and the agents read."""


def drawn_kinds(ranges: ScenarioRanges) -> str:
    """What kinds of uncertainty ``ranges`` draw, in words (for an error naming a version's draws)."""
    laws = ("creep-law families and systematic sensor errors" if ranges.draws_v2
            else "no creep-law family and no systematic sensor error")
    probe = "a speed probe's pulses, runout and lag and a track's irregularity" if ranges.draws_v3 \
        else "a continuous encoder on a level track"
    return f"{laws}, {probe}"


def physics_scenario(sc: EpisodeScenario, wheel_load_n: float, seed: int, traction_balance: bool,
                     lock_in: str = "plain") -> Scenario:
    """The simulation's scenario: the creep law is calibrated at ``wheel_load_n`` (the driven wheel's
    load at saturation, see :mod:`cof_gym.task.ground_truth`); ``lock_in`` the speed's lock-in
    (:data:`cof_gym.physics.simulation.LOCK_INS`)."""
    op = OperatingConditions(cof=sc.cof, condition=sc.shape, wheel_load_n=wheel_load_n, speed_m_s=sc.speed_m_s)
    track = draw_profile(sc.track_irregularity, np.random.default_rng([TRACK_STREAM, seed]))
    return Scenario(op=op, noise=sc.noise(), motor_lag_s=sc.motor_lag_s, traction_balance=traction_balance, seed=seed,
                    encoder_lag_s=sc.encoder_lag_s, track=track,
                    encoder=PulseEncoder(sc.encoder_pulses_per_rev, sc.encoder_runout), lock_in=lock_in)


# the track profile's phases come from a stream of their own, keyed by the episode's physics seed (itself drawn from
# the env's np_random), so that asking for a profile moves no other draw of the episode
TRACK_STREAM = 20261203
