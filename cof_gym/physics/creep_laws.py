"""Creep-law families: the one table of every law the native callback can run, with each family's
parameters, their validation, their sources and the ranges episodes draw shapes from.

A family is one C function in ``native/cofgym_native.c`` (listed by name in its ``FAMILIES`` table)
and one frozen dataclass here, registered in :data:`FAMILIES`. The dataclass's fields are the
family's parameters, in the order the C function reads them (``LAW_CREEP_P0 + k``); a field listed
in ``TABLE`` is a tabulated curve instead (the native table arrays). The dataclass is the *shape*
of a creep curve; the friction level ``mu0`` is solved per episode so that the curve's maximum
(supremum) at the episode's speed and load is its CoF (:func:`cof_gym.physics.creep.mu0_for_cof`).
Adding a family: its C function and ``FAMILIES`` row, one dataclass here and its :data:`FAMILIES`
entry; the task, the environments and the agents take it through :func:`creep_law_from_spec` and
:func:`draw_shape`. With drawing ranges it can be drawn (``ScenarioRanges.creep_families``); the v2 ids' draws stay
the two families their numbers were published with (``cof_gym.task.scenarios.V2_CREEP_FAMILIES``).

**Families.**

``polach``
    Polach (2005, Wear 258:992-1000, "Creep forces in simulations of traction vehicles running on
    adhesion limit", presented at CM2003; the underlying fast method: Polach 1999, "A fast
    wheel-rail forces calculation computer code", Vehicle System Dynamics 33 Suppl.; its extension
    to large creep: Polach 2001, Vehicle System Dynamics 35 Suppl.): falling friction with slip
    velocity, so the curve has a peak and a falling branch.
``shen_hedrick_elkins``
    Shen, Hedrick and Elkins (1983, 8th IAVSD Symposium, Cambridge MA: "A comparison of alternative
    creep force models for rail vehicle dynamic analysis"): Kalker's linear creep force saturated
    by ``F/(mu N) = x - x^2/3 + x^3/27`` for ``x = k C_K |s| / mu < 3`` and ``1`` beyond, with
    ``C_K = G a b c11 / N`` Kalker's linear stiffness per unit load (Kalker 1990, the same contact
    patch constants Polach uses). With constant friction (``friction_ratio = 1`` or
    ``friction_decay_s_per_m = 0``, the original law) the curve rises monotonically to ``mu`` and
    stays there: no falling branch, which no Polach shape gives (Polach's curve only approaches
    ``mu`` asymptotically without falling friction, and falls with it). The CoF is then the
    supremum ``mu``, *reached* at the finite creepage ``3 mu / (k C_K)``: that is the peak
    creepage the macro-slip limit is relative to. Optional Polach falling friction adds a peak.
``table``
    A tabulated adhesion ratio, e.g. a curve measured on a twin disc or a roller rig: points
    ``(creepage, adhesion_ratio)``, ``CoA = cof x ratio(|s|)`` (odd in s), used as given at every
    speed and load, interpolated natively by monotone piecewise-cubic Hermite interpolation (PCHIP:
    Fritsch & Carlson 1980, SIAM J. Numer. Anal. 17:238-246; the knot slopes of
    :class:`scipy.interpolate.PchipInterpolator`, computed once here) and constant beyond the last
    point. PCHIP keeps every interval monotone, so the curve's maximum is exactly the first point of
    ratio 1.

The extended creep force model with a third-body layer (Meierhofer et al., Wear 314:148-154, 2014)
is not implemented: its equations were not available to source here.

**Ranges** for drawing shapes per episode (:data:`RANGES`, :func:`draw_shape`; each parameter
uniform in its range; Polach draws with kS > kA are redrawn, see :meth:`PolachShape.drawable`):

====================== ============= ============ ============ ============ ==============
family / condition      k_adhesion    k_slip       friction_    friction_    k_stiffness
                        (kA)          (kS)         ratio (A)    decay (B)
====================== ============= ============ ============ ============ ==============
polach dry              0.6-1.2       0.2-1.0      0.25-0.6     0.1-1.2 s/m
polach wet              0.15-0.6      0.05-0.3     0.25-0.6     0.1-0.6 s/m
polach low_adhesion     0.05-0.3      0.02-0.15    0.3-0.6      0.1-0.6 s/m
SHE dry                                            1            0            0.5-1.0
SHE wet                                            1            0            0.1-0.5
SHE low_adhesion                                   1            0            0.04-0.2
====================== ============= ============ ============ ============ ==============

Sources and choices: Polach's published sets (Polach 2005, Table "parameters for dry and wet
conditions", as widely cited, unverified against the original table) are dry kA 1.00, kS 0.40,
A 0.40, B 0.60 s/m and wet kA 0.30, kS 0.10, A 0.40, B 0.20 s/m. The ranges are cof_gym's choice
around them: each contains its preset of :data:`CONDITIONS` (``dry_kalker``, kS 1.0, is the dry
range's corner) and the dry range contains both off-preset shapes the v2 issue measured
((0.8, 0.3, 0.25, 1.2) and (1.2, 0.9, 0.6, 0.1)). The low-adhesion range is an extrapolation of
the wet one to the flatter slopes of leaf layers (unverified). For Shen-Hedrick-Elkins the friction
is constant (the original law: the family's point is a curve without a falling branch) and
``k_stiffness`` brackets the reduction of Kalker's initial slope that Polach's presets imply,
(kA + kS) / 2 = 0.7 dry, 0.2 wet, 0.075 low adhesion (Polach 2005, Sect. 2: measured initial
slopes are below Kalker's); 1 is Kalker's unreduced theory. The table family has no ranges: a
table is given, not drawn.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, fields
from functools import lru_cache
from types import MappingProxyType
from collections.abc import Set
from typing import Any, Callable, ClassVar, Mapping

import numpy as np

from cof_gym.physics.native import layout
from cof_gym.validation import brief, check_number, first_not_rising

MAX_CREEPAGE = 2.0  # the creep-curve maximum (the CoF) must lie below this creepage; a table stays within it


@dataclass(frozen=True)
class CreepPeak:
    """Where the steady creep curve first reaches its maximum: creepage (-) and CoA there (-)."""

    creepage: float
    coa: float


class CreepShape:
    """Base of every family's shape (a frozen dataclass whose fields are the family's parameters).

    Class attributes a family sets: ``family`` (its name, as in the native ``FAMILIES`` table),
    ``TABLE`` (names of fields that are the tabulated curve, empty for analytic families) and
    ``RANGES`` (per condition, per parameter: the (low, high) range :func:`draw_shape` draws from).
    """

    family: ClassVar[str]
    TABLE: ClassVar[tuple[str, ...]] = ()
    RANGES: ClassVar[Mapping[str, Mapping[str, tuple[float, float]]]] = MappingProxyType({})

    def law_params(self) -> tuple[float, ...]:
        """The analytic parameters in the order the C function reads them."""
        return tuple(float(getattr(self, f.name)) for f in fields(self) if f.name not in self.TABLE)

    def table(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """Tabulated curve (creepage, value, slope) for the native table arrays, or None."""
        return None

    @classmethod
    def example(cls) -> "CreepShape":
        """A representative shape of the family (``cof-gym bench`` times one per family)."""
        raise NotImplementedError

    def drawable(self) -> bool:
        """Whether :func:`draw_shape` keeps this draw (a family's structural constraint on its ranges)."""
        return True

    def max_is_mu0(self) -> bool:
        """True when the curve's maximum (supremum) is mu0 itself at every speed and load, so that
        the calibration is exact: mu0 = cof."""
        return False

    def mu0_upper(self, cof: float) -> float:
        """A first upper bracket for the mu0 whose curve peaks at ``cof`` (doubled until it is one)."""
        return 2.0 * cof

    def exact_peak(self, mu0: float) -> CreepPeak | None:
        """The peak when it is known in closed form (independent of speed and load), else None."""
        return None

MAX_REDUCTION_FACTOR = 100.0  # Polach's kA, kS accepted up to this (any published set is at most 1)
# Polach's A = mu_inf / mu0 at least this: at A = 0 the friction falls to exactly 0 once exp(-B |u|) underflows and the
# curve's eps = C s / mu divides by it (NaN forces); every drawn range and preset has A >= 0.25
MIN_FRICTION_RATIO = 0.01


@dataclass(frozen=True)
class PolachShape(CreepShape):
    """Polach's law (2005, Wear 258:992-1000): reduction factors kA (adhesion) and kS (slip) of the
    Kalker stiffness, and the falling friction mu = mu0 [(1 - A) exp(-B w) + A] with w the slip
    velocity (m/s). Ranges: module docstring."""

    k_adhesion: float
    k_slip: float
    friction_ratio: float  # A = mu_inf / mu0
    friction_decay_s_per_m: float  # B

    family: ClassVar[str] = "polach"
    RANGES: ClassVar[Mapping[str, Mapping[str, tuple[float, float]]]] = MappingProxyType({
        "dry": {"k_adhesion": (0.6, 1.2), "k_slip": (0.2, 1.0), "friction_ratio": (0.25, 0.6),
                "friction_decay_s_per_m": (0.1, 1.2)},
        "wet": {"k_adhesion": (0.15, 0.6), "k_slip": (0.05, 0.3), "friction_ratio": (0.25, 0.6),
                "friction_decay_s_per_m": (0.1, 0.6)},
        "low_adhesion": {"k_adhesion": (0.05, 0.3), "k_slip": (0.02, 0.15), "friction_ratio": (0.3, 0.6),
                         "friction_decay_s_per_m": (0.1, 0.6)},
    })

    def __post_init__(self) -> None:
        # reduction factors of Kalker's slope (Polach: at most 1; drawn up to 1.2): bounded far above any published
        # set, where the curve's terms (k eps)^2 would overflow into NaN slopes
        check_number("k_adhesion", self.k_adhesion, 0.0, MAX_REDUCTION_FACTOR, low_open=True)
        check_number("k_slip", self.k_slip, 0.0, MAX_REDUCTION_FACTOR, low_open=True)
        check_number("friction_ratio", self.friction_ratio, MIN_FRICTION_RATIO, 1.0, high_open=True,
                     unit=" (A; below 1 for a creep curve with a peak)")
        check_number("friction_decay_s_per_m", self.friction_decay_s_per_m, 0.0, math.inf, low_open=True,
                     unit=" s/m (B)")

    def mu0_upper(self, cof: float) -> float:
        return cof / max(self.friction_ratio, 0.05)

    @classmethod
    def example(cls) -> "PolachShape":
        return CONDITIONS["dry"]

    def drawable(self) -> bool:
        """kS <= kA, as in every preset and published set: with kS > kA the atan (slip) term outgrows
        the adhesion term and many such curves have no maximum at all."""
        return self.k_slip <= self.k_adhesion


@dataclass(frozen=True)
class ShenHedrickElkinsShape(CreepShape):
    """Shen-Hedrick-Elkins saturation (8th IAVSD, 1983) of Kalker's linear law, stiffness reduced by
    ``k_stiffness`` (1: Kalker's), with Polach's falling friction (A = 1 or B = 0: constant friction,
    the original law, no falling branch). Ranges: module docstring."""

    k_stiffness: float = 1.0
    friction_ratio: float = 1.0  # A = mu_inf / mu0
    friction_decay_s_per_m: float = 0.0  # B

    family: ClassVar[str] = "shen_hedrick_elkins"
    RANGES: ClassVar[Mapping[str, Mapping[str, tuple[float, float]]]] = MappingProxyType({
        "dry": {"k_stiffness": (0.5, 1.0), "friction_ratio": (1.0, 1.0), "friction_decay_s_per_m": (0.0, 0.0)},
        "wet": {"k_stiffness": (0.1, 0.5), "friction_ratio": (1.0, 1.0), "friction_decay_s_per_m": (0.0, 0.0)},
        "low_adhesion": {"k_stiffness": (0.04, 0.2), "friction_ratio": (1.0, 1.0),
                         "friction_decay_s_per_m": (0.0, 0.0)},
    })

    def __post_init__(self) -> None:
        check_number("k_stiffness", self.k_stiffness, 0.0, 2.0, low_open=True, unit=" (1: Kalker's linear stiffness)")
        check_number("friction_ratio", self.friction_ratio, 0.0, 1.0, low_open=True, unit=" (A; 1: constant friction)")
        check_number("friction_decay_s_per_m", self.friction_decay_s_per_m, 0.0, 100.0,
                     unit=" s/m (B; 0: constant friction)")

    def max_is_mu0(self) -> bool:
        return self.friction_ratio == 1.0 or self.friction_decay_s_per_m == 0.0

    @classmethod
    def example(cls) -> "ShenHedrickElkinsShape":
        return cls(k_stiffness=0.7)

    def mu0_upper(self, cof: float) -> float:
        return cof / max(self.friction_ratio, 0.05)


def pchip_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Knot slopes dy/dx of the monotone PCHIP interpolant (Fritsch & Carlson 1980), as scipy's."""
    from scipy.interpolate import PchipInterpolator

    with np.errstate(all="ignore"):  # points too close overflow: scipy refuses the non-finite slopes, silently
        return PchipInterpolator(x, y)(x, 1)


def below_peak(rise: np.ndarray, margin: float = 1e-6) -> np.ndarray:
    """A table's adhesion ratios before its peak (a strictly increasing array), capped so that
    :class:`TableShape` takes them: point ``k`` of ``n`` at most ``1 - margin x (n - k)``, strictly
    below the peak's 1 and, where several are capped, still strictly increasing (one common cap would
    make them equal)."""
    rise = np.asarray(rise, dtype=np.float64)
    return np.minimum(rise, 1.0 - margin * np.arange(len(rise), 0, -1))


@dataclass(frozen=True)
class TableShape(CreepShape):
    """A tabulated curve: ``adhesion_ratio`` (CoA / CoF) at ``creepage`` (tuples; lists are
    converted). Creepage strictly increasing from exactly 0 to at most :data:`MAX_CREEPAGE`, its
    points far enough apart that the slopes are finite; the ratio starts at 0, rises
    strictly to its maximum, exactly 1 (to 1e-9, stored as 1), and is anything in [0, 1] after it;
    3 to ``layout.MAX_TABLE_POINTS`` points."""

    creepage: tuple[float, ...]
    adhesion_ratio: tuple[float, ...]

    family: ClassVar[str] = "table"
    TABLE: ClassVar[tuple[str, ...]] = ("creepage", "adhesion_ratio")
    MAX_TOLERANCE: ClassVar[float] = 1e-9

    def __post_init__(self) -> None:
        s = _float_tuple("creepage", self.creepage)
        r = _float_tuple("adhesion_ratio", self.adhesion_ratio)
        n_max = layout.MAX_TABLE_POINTS
        if not (3 <= len(s) <= n_max):
            raise ValueError(f"creepage must have 3 to {n_max} points, got {len(s)}")
        if len(r) != len(s):
            raise ValueError(f"adhesion_ratio must have one value per creepage ({len(s)}), got {len(r)}")
        if s[0] != 0.0:
            raise ValueError(f"creepage must be strictly increasing from exactly 0 (finite values >= 0), got {s[0]!r} "
                             "at index 0")
        if (i := first_not_rising(s)) is not None:
            raise ValueError(f"creepage must be strictly increasing from exactly 0 (finite values >= 0), got {s[i]!r} "
                             f"then {s[i + 1]!r} at indices {i} and {i + 1}")
        if s[-1] > MAX_CREEPAGE:
            raise ValueError(f"creepage must be in [0, {MAX_CREEPAGE:g}] (where every creep law's maximum lies), "
                             f"got {s[-1]!r} at index {len(s) - 1}")
        if r[0] != 0.0 or min(r) < 0.0:
            i = 0 if r[0] != 0.0 else int(np.argmin(r))
            raise ValueError(f"adhesion_ratio must start at exactly 0 and stay >= 0, got {r[i]!r} at index {i}")
        peak = int(np.argmax(r))
        if abs(r[peak] - 1.0) > self.MAX_TOLERANCE or max(r) > 1.0 + self.MAX_TOLERANCE:
            raise ValueError(f"adhesion_ratio must reach its maximum exactly 1 (within {self.MAX_TOLERANCE:g}), "
                             f"the CoF, got maximum {max(r)!r}")
        if (i := first_not_rising(r[:peak + 1])) is not None:
            raise ValueError(f"adhesion_ratio must rise strictly from 0 to its maximum 1, got {r[i]!r} then "
                             f"{r[i + 1]!r} at indices {i} and {i + 1}, before the maximum at index {peak}")
        r = tuple(1.0 if abs(v - 1.0) <= self.MAX_TOLERANCE else v for v in r)
        if not _finite_slopes(np.array(s), np.array(r)):
            raise ValueError(f"creepage points must lie far enough apart that the slopes d(adhesion_ratio)/d(creepage) "
                             f"are finite (at most {np.finfo(float).max:.3g}), got {brief(list(s))}")
        object.__setattr__(self, "creepage", s)
        object.__setattr__(self, "adhesion_ratio", r)

    @property
    def peak_index(self) -> int:
        """Index of the first point of ratio 1 (the curve's maximum)."""
        return self.adhesion_ratio.index(1.0)

    def table(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Points and PCHIP knot slopes; the last slope is zero, so that the constant continuation
        beyond the last point is smooth (C1); a zero slope keeps the last interval monotone
        (Fritsch & Carlson 1980, Sect. 3)."""
        s, r = np.array(self.creepage), np.array(self.adhesion_ratio)
        slopes = pchip_slopes(s, r)
        slopes[-1] = 0.0
        return s, r, slopes

    def max_is_mu0(self) -> bool:
        return True

    @classmethod
    def example(cls) -> "TableShape":
        """48 points of a saturating curve (Shen-Hedrick-Elkins-like rise to 1 at creepage 0.01,
        geometric spacing) falling to 0.8 at 0.05: a full-size table for timing."""
        rise = np.geomspace(1e-5, 1e-2, 40)
        fall = np.geomspace(1.2e-2, 5e-2, 7)
        s = np.concatenate([[0.0], rise, fall])
        r = np.concatenate([[0.0], 1.0 - (1.0 - rise / 1e-2) ** 3, 1.0 - 0.2 * (fall - 1e-2) / 4e-2])
        return cls(tuple(s), tuple(r))

    def exact_peak(self, mu0: float) -> CreepPeak:
        return CreepPeak(self.creepage[self.peak_index], mu0)


def _finite_slopes(s: np.ndarray, r: np.ndarray) -> bool:
    """Whether a table's secant slopes and PCHIP knot slopes are all finite (points not too close)."""
    with np.errstate(all="ignore"):
        if not np.all(np.isfinite(np.diff(r) / np.diff(s))):
            return False
    try:
        return bool(np.all(np.isfinite(pchip_slopes(s, r))))
    except ValueError:  # scipy refuses non-finite knot slopes
        return False


def _float_tuple(name: str, values: Any) -> tuple[float, ...]:
    """A sequence of finite real numbers as a tuple of floats (ValueError naming ``name``); an unordered
    collection (a set: its order is arbitrary) is refused."""
    if (isinstance(values, (str, bytes, Mapping, Set)) or not hasattr(values, "__len__")
            or not hasattr(values, "__getitem__")):
        raise ValueError(f"{name} must be a list of finite numbers, got {values!r}")
    out = []
    for i, v in enumerate(values):
        try:
            out.append(check_number(name, v, -math.inf, math.inf))
        except ValueError:  # the list's own message: which entry, where
            raise ValueError(f"{name} must be a list of finite numbers, got {v!r} at index {i}") from None
    return tuple(out)


FAMILIES: Mapping[str, type[CreepShape]] = MappingProxyType({
    cls.family: cls for cls in (PolachShape, ShenHedrickElkinsShape, TableShape)
})
"""Every creep-law family by name: the one registry (native ``FAMILIES`` holds the C side)."""

CONDITIONS: Mapping[str, CreepShape] = MappingProxyType({
    "dry": PolachShape(1.00, 0.40, 0.40, 0.60),
    "wet": PolachShape(0.30, 0.10, 0.40, 0.20),
    "low_adhesion": PolachShape(0.10, 0.05, 0.45, 0.20),
    "dry_kalker": PolachShape(1.00, 1.00, 0.40, 0.60),
})
"""The named presets: points of the Polach family (see :mod:`cof_gym.physics.creep`)."""
PRESET_FAMILY = PolachShape.family  # the family every preset (CONDITIONS) is a point of

RANGES: Mapping[str, Mapping[str, Mapping[str, tuple[float, float]]]] = MappingProxyType(
    {name: cls.RANGES for name, cls in FAMILIES.items() if cls.RANGES})
"""Per family, per condition, per parameter: the (low, high) range :func:`draw_shape` draws from."""


@lru_cache(maxsize=None)
def family_id(family: str) -> int:
    """The native id of a registered family (its row in the C ``FAMILIES`` table)."""
    from cof_gym.physics.native.build import native

    i = int(native().cofgym_family_id(family.encode()))
    if i < 0:
        raise RuntimeError(f"creep-law family {family!r} has a Python description but no C function in the "
                           "native FAMILIES table (cof_gym/physics/native/cofgym_native.c)")
    return i


def law_vector(shape: CreepShape, mu0: float, shear_modulus_pa: float) -> np.ndarray:
    """The native law block (``layout.LAW_FIELDS``) of ``shape`` at friction level mu0 and shear
    modulus (Pa)."""
    v = np.zeros(len(layout.LAW_FIELDS))
    at = {f: i for i, f in enumerate(layout.LAW_FIELDS)}
    v[at["CREEP_FAMILY"]], v[at["MU0"]], v[at["SHEAR_MODULUS"]] = family_id(shape.family), mu0, shear_modulus_pa
    params = shape.law_params()
    if len(params) > layout.MAX_LAW_PARAMS:
        raise ValueError(f"family {shape.family} has {len(params)} parameters, the layout holds {layout.MAX_LAW_PARAMS}")
    v[at["CREEP_P0"]: at["CREEP_P0"] + len(params)] = params
    table = shape.table()
    if table is not None:
        n = table[0].size
        v[at["TABLE_N"]] = n
        for prefix, values in zip(("TABLE_S_0", "TABLE_R_0", "TABLE_D_0"), table):
            v[at[prefix]: at[prefix] + n] = values
    return v


# ---------------------------------------------------------------- specs and draws


def preset(name: Any) -> CreepShape:
    """A named preset of :data:`CONDITIONS`."""
    if not isinstance(name, str) or name not in CONDITIONS:
        raise ValueError(f"creep_law preset must be one of {sorted(CONDITIONS)}, got {name!r}")
    return CONDITIONS[name]


def _spec_value(path: str, value: Any, is_table: bool) -> Any:
    if is_table:
        return _float_tuple(path, value)
    return check_number(path, value, -math.inf, math.inf)


def creep_law_from_spec(spec: Any) -> CreepShape:
    """A creep-curve shape from a spec: a preset name (``"dry"``, ``"wet"``, ``"low_adhesion"``,
    ``"dry_kalker"``), ``{"<family>": {<parameter>: value, ...}}`` (e.g. ``{"polach": {"k_adhesion":
    .., "k_slip": .., "friction_ratio": .., "friction_decay_s_per_m": ..}}``, ``{"table":
    {"creepage": [...], "adhesion_ratio": [...]}}``), or a shape. Anything else: one ValueError
    naming the field (``creep_law.<family>.<parameter>``) and what it allows."""
    if isinstance(spec, CreepShape):
        return spec
    if isinstance(spec, str):
        return preset(spec)
    if not (isinstance(spec, Mapping) and len(spec) == 1):
        raise ValueError(f"creep_law must be a preset name {sorted(CONDITIONS)} or a one-key mapping "
                         f"{{family: {{parameters}}}} with family in {sorted(FAMILIES)}, got {spec!r}")
    ((family, params),) = spec.items()
    if family not in FAMILIES:
        raise ValueError(f"creep_law family must be one of {sorted(FAMILIES)}, got {family!r}")
    cls = FAMILIES[family]
    names = [f.name for f in fields(cls)]
    if not isinstance(params, Mapping):
        raise ValueError(f"creep_law.{family} must be a mapping of its parameters {names}, got {params!r}")
    for key in params:
        if key not in names:
            raise ValueError(f"creep_law.{family}.{key} is not a parameter of the {family} family; "
                             f"its parameters are {names}")
    required = [f.name for f in fields(cls) if f.default is MISSING and f.default_factory is MISSING]
    for key in required:
        if key not in params:
            raise ValueError(f"creep_law.{family}.{key} is missing (required parameters: {required})")
    values = {k: _spec_value(f"creep_law.{family}.{k}", v, k in cls.TABLE) for k, v in params.items()}
    try:
        return cls(**values)
    except ValueError as e:
        raise ValueError(f"creep_law.{family}.{e}") from None


MAX_DRAWS = 1000


def draw_shape(rng: np.random.Generator, family: str, condition: str,
               accept: Callable[[CreepShape], bool] | None = None) -> CreepShape:
    """A shape of ``family`` drawn for ``condition`` from :data:`RANGES`: each parameter uniform in its
    range, in field order, redrawn until the family's constraint (:meth:`CreepShape.drawable`) and
    ``accept`` (e.g. "the curve has a maximum at this episode's speed and load",
    :func:`cof_gym.physics.creep.has_maximum`) hold. Randomness only from ``rng``."""
    if not isinstance(rng, np.random.Generator):
        raise ValueError(f"rng must be a numpy Generator (np.random.default_rng(seed), an env's np_random), "
                         f"got {rng!r}")
    if not isinstance(family, str) or family not in RANGES:
        raise ValueError(f"family must be one of {sorted(RANGES)} (the families with parameter ranges), got {family!r}")
    ranges = RANGES[family]
    if condition not in ranges:
        raise ValueError(f"condition must be one of {sorted(ranges)} for the {family} family, got {condition!r}")
    cls = FAMILIES[family]
    for _ in range(MAX_DRAWS):
        shape = cls(**{f.name: float(rng.uniform(*ranges[condition][f.name])) for f in fields(cls)})
        if shape.drawable() and (accept is None or accept(shape)):
            return shape
    raise ValueError(f"no {family} shape for {condition} passed the acceptance test in {MAX_DRAWS} draws")
