"""The paper's closed-form phase predictions (Eq. 3 and Eq. 4) and its torque schedule."""

from __future__ import annotations

import math

import numpy as np

from cof_gym.physics.creep import OperatingConditions, creep_curve, creepage_at_coa


def paper_schedule(last_percent: int = 99) -> np.ndarray:
    """DC torque as fractions of the saturation torque: 1 %, then steps of 10 %, 5 % from 50 %,
    3 % from 70 % and 1 % from 90 % (paper Sect. 4.1), up to ``last_percent``."""
    percents, p = [], 1
    while p <= last_percent:
        percents.append(p)
        p += 10 if p < 50 else 5 if p < 70 else 3 if p < 90 else 1
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


def phase_eq4_deg(phase_eq3: float, phi_v_deg: float) -> float:
    """Paper Eq. 4: tan(phi) = tan(phi_Eq3) / cos(phi_v) - tan(phi_v), degrees."""
    pv = math.radians(phi_v_deg)
    return math.degrees(math.atan(math.tan(math.radians(phase_eq3)) / math.cos(pv) - math.tan(pv)))

