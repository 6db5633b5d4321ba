"""The paper's closed-form phase predictions (Eq. 3 and Eq. 4), its torque schedule, and the
small-signal model of a compliant driven wheelset that explains where the phase crosses zero.

**The DC schedule, checked against the paper's text** (Sect. 4.1: "from 1 % of the saturation torque
with a step of 10 % until friction saturation is reached ... reducing to 5 % after 50 % ..., to 3 %
after 70 % ..., and to 1 % after 90 %"). Read literally, the steps accumulate from 1 %: 1, 11, 21, 31,
41, 51 (the first level past 50 %), then +5: 56, 61, 66, 71 (past 70 %), then +3: 74, 77, 80, 83, 86,
89, and, 89 % not being past 90 %, +3 again to 92; from there +1 up to 99 %. So **90 and 91 % are not
steps**. The text does not say that the grid snaps to the thresholds (50, 70, 90 %); a snapped reading
would differ only below 92 %, and both put 1 % steps across the paper's 94-95 % crossing, so the
reading does not move the paper's result. Saturation itself (100 %) is not a step: at 100 % of the
static saturation torque plus a modulation the wheel slips.

**Eq. 4 for a compliant wheelset.** With the speed oscillation of the paper's cruise control, the
creepage is the wheelset speed shifted by phi_v at unchanged amplitude, which gives the paper's
tan(phi) = tan(phi_Eq3) / cos(phi_v) - tan(phi_v). When phi_v comes instead from the wheelset's own
longitudinal compliance (creep force -> primary spring -> wheelset motion), the creepage is
R Omega / v filtered by 1 / (1 + j wm D / kx) (D = N k / v, the creep damping), i.e. its amplitude
also shrinks by cos(phi_v): tan(phi) = tan(phi_Eq3) / cos^2(phi_v) - tan(phi_v). reproduce-paper
measures the creepage amplitude on the wagon to show which form holds.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, fields

import numpy as np
from scipy.optimize import brentq

from cof_gym.physics.creep import OperatingConditions, creep_curve, creepage_at_coa
from cof_gym.physics.vehicle import WagonParameters
from cof_gym.validation import check_number

SCHEDULE_STEPS_PERCENT = ((50, 10), (70, 5), (90, 3))  # (below this level, step); 1 % from there on
# the paper's simulated setting (Sect. 4): the modulation superimposed on the DC torque, the speed, the CoFs
PAPER_AMPLITUDE_NM = 345.0
PAPER_FREQUENCY_HZ = 5.0
PAPER_SPEED_M_S = 10.0
PAPER_COFS = (0.1, 0.2, 0.3, 0.4, 0.5)


def paper_schedule(last_percent: int = 99) -> np.ndarray:
    """DC torque as fractions of the saturation torque: 1 %, then steps of 10 %, 5 % past 50 %,
    3 % past 70 % and 1 % past 90 % (paper Sect. 4.1, literal reading, see the module docstring),
    up to ``last_percent``."""
    percents, p = [], 1
    while p <= last_percent:
        percents.append(p)
        p += next((step for limit, step in SCHEDULE_STEPS_PERCENT if p < limit), 1)
    return np.array(percents, dtype=float) / 100.0


def creep_slope_at_torque(dc_torque_nm: float, radius_m: float, contact_load_n: float,
                          op: OperatingConditions) -> float:
    """dCoA/ds of the steady creep curve where it balances the DC torque: CoA = Mc / (R N)."""
    s = creepage_at_coa(dc_torque_nm / (radius_m * contact_load_n), op)
    return float(creep_curve(s, op)[1][0])


def phase_eq3_deg(spin_inertia: float, omega_m: float, speed: float, contact_load_n: float,
                  radius_m: float, creep_slope: float) -> float:
    """Paper Eq. 3: tan(phi) = Iw wm v / (N R^2 dCoA/ds), degrees."""
    return math.degrees(math.atan2(spin_inertia * omega_m * speed, contact_load_n * radius_m**2 * creep_slope))


def phase_eq4_deg(phase_eq3: float, phi_v_deg: float, creep_amplitude_ratio: float = 1.0) -> float:
    """Eq. 4 with the creepage lagging the wheelset speed by phi_v and its amplitude rho = creepage
    amplitude / (R Omega0 / v): tan(phi) = tan(phi_Eq3) / (rho cos(phi_v)) - tan(phi_v), degrees.
    rho = 1 is the paper's Eq. 4 (exact for a linear wheelset, whatever moves the creepage)."""
    pv = math.radians(phi_v_deg)
    return math.degrees(math.atan(math.tan(math.radians(phase_eq3)) / (creep_amplitude_ratio * math.cos(pv))
                                  - math.tan(pv)))


def phase_eq4_compliant_deg(phase_eq3: float, phi_v_deg: float) -> float:
    """Eq. 4 when phi_v comes from the wheelset's own (massless, undamped) longitudinal compliance,
    which makes rho = cos(phi_v): tan(phi) = tan(phi_Eq3) / cos^2(phi_v) - tan(phi_v), degrees."""
    return phase_eq4_deg(phase_eq3, phi_v_deg, math.cos(math.radians(phi_v_deg)))


@dataclass(frozen=True)
class CompliantWheelset:
    """Small-signal model of a driven wheelset whose bogie is held still (the paper's counter torque):
    spin inertia Iw (kg m^2) driven by the torque, the creep force between wheel and rail, and the
    wheelset's longitudinal mass (kg) on the primary spring kx (N/m) and damper cx (N s/m), all
    axleboxes together. Contact load N in N (all wheels of the wheelset), radius in m, speed in m/s."""

    spin_inertia_kg_m2: float
    radius_m: float
    contact_load_n: float
    speed_m_s: float
    mass_kg: float
    kx_n_m: float
    cx_n_s_m: float

    def __post_init__(self) -> None:
        # every constant a finite number > 0 (the damper >= 0), stored as checked: a zero speed or load divided by
        # zero, a negative speed turned the lag around, a NaN mass gave NaN lags
        for f in fields(self):
            object.__setattr__(self, f.name, check_number(f"CompliantWheelset.{f.name}", getattr(self, f.name), 0.0,
                                                          math.inf, low_open=f.name != "cx_n_s_m", high_open=True))

    @classmethod
    def of_wagon(cls, p: WagonParameters, speed_m_s: float) -> "CompliantWheelset":
        """The wagon's driven wheelset: two axleboxes, two wheels at the static load."""
        return cls(p.motor_spin_inertia_kg_m2, p.wheel_radius_m, 2 * p.static_wheel_load_n, speed_m_s,
                   p.wheelset_mass_kg, 2 * p.primary_kx_n_m, 2 * p.primary_cx_n_s_m)

    def _impedance(self, creep_slope: float, omega_m: float) -> tuple[complex, complex]:
        """(M / Omega, creepage / (R Omega / v)) at angular frequency ``omega_m``."""
        s = 1j * omega_m
        damping = self.contact_load_n * creep_slope / self.speed_m_s  # D: creep force per slip velocity
        compliance = 1.0 / (self.mass_kg * s * s + self.cx_n_s_m * s + self.kx_n_m)
        creep_transfer = 1.0 / (1.0 + damping * s * compliance)
        return s * self.spin_inertia_kg_m2 + self.radius_m**2 * damping * creep_transfer, creep_transfer

    def phase_lag_deg(self, creep_slope: float, omega_m: float) -> float:
        """Lag of the wheelset speed behind the torque, degrees."""
        return math.degrees(cmath.phase(self._impedance(creep_slope, omega_m)[0]))

    def creep_lag_deg(self, creep_slope: float, omega_m: float) -> float:
        """phi_v: lag of the creepage behind the wheelset speed, degrees."""
        return -math.degrees(cmath.phase(self._impedance(creep_slope, omega_m)[1]))

    def creep_amplitude_ratio(self, creep_slope: float, omega_m: float) -> float:
        """Creepage amplitude over R Omega0 / v (cos(phi_v) for a massless, undamped spring)."""
        return abs(self._impedance(creep_slope, omega_m)[1])

    def k_cross_estimate(self) -> float:
        """Creep slope at which the phase crosses zero, leading order: k = v sqrt(Iw kx) / (R N)."""
        return self.speed_m_s * math.sqrt(self.spin_inertia_kg_m2 * self.kx_n_m) / (self.radius_m * self.contact_load_n)

    def k_cross(self, omega_m: float) -> float:
        """Creep slope at which this model's phase is zero (root between 1e-3 and 100x the estimate);
        NaN where the phase does not change sign there."""
        k0 = self.k_cross_estimate()
        f = lambda logk: self.phase_lag_deg(math.exp(logk), omega_m)  # noqa: E731
        lo, hi = math.log(1e-3 * k0), math.log(100 * k0)
        if f(lo) * f(hi) > 0:
            return math.nan
        return math.exp(brentq(f, lo, hi, xtol=1e-12))


def crossing_fraction(model: CompliantWheelset, op: OperatingConditions, omega_m: float) -> float:
    """Fraction of the saturation torque R N CoF at which ``model``'s phase crosses zero on the steady
    creep curve of ``op`` (slope falling with torque); NaN if it does not in (0.01, 0.999). ``omega_m`` (rad/s) > 0:
    at 0 every phase is 0, which would read as a crossing at 1 %."""
    check_number("omega_m", omega_m, 0.0, math.inf, low_open=True, high_open=True)
    m_sat = model.radius_m * model.contact_load_n * op.cof

    def phase(frac: float) -> float:
        return model.phase_lag_deg(creep_slope_at_torque(frac * m_sat, model.radius_m, model.contact_load_n, op),
                                   omega_m)

    lo, hi = 0.01, 0.999
    if phase(lo) * phase(hi) > 0:
        return math.nan
    return float(brentq(phase, lo, hi, xtol=1e-6))
