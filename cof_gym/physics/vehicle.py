"""Vehicle parameters: the Manchester benchmark vehicle (Iwnicki 1998, VSD 30:295-313) in a planar
(longitudinal-vertical-pitch) form, and the paper's half wheelset (Sect. 2).

Planar lumping: the two sides of the vehicle act in phase on straight track, so each wheelset carries
both wheels (contact force = 2 x one wheel's, normal load per wheel = half the wheelset's) and the
per-side / per-axlebox springs are summed. Values marked *assumed* are cof_gym's choices where the
benchmark is silent (documented in the README).
"""

from __future__ import annotations

from dataclasses import dataclass

GRAVITY = 9.81  # m/s^2


@dataclass(frozen=True)
class HalfWheelsetParameters:
    """The paper's Sect. 2 model: one wheel at constant speed under a constant normal load."""

    spin_inertia_kg_m2: float = 116.0  # paper, half wheelset
    wheel_radius_m: float = 0.46  # paper
    normal_load_n: float = 100e3  # paper, N
    mass_kg: float = 906.5  # half of the benchmark wheelset (only visual here)


@dataclass(frozen=True)
class WagonParameters:
    # car body
    carbody_mass_kg: float = 32_000.0
    carbody_pitch_inertia_kg_m2: float = 1.97e6
    carbody_cog_height_m: float = 1.8
    # bogie frame
    bogie_mass_kg: float = 2_615.0
    bogie_pitch_inertia_kg_m2: float = 1_476.0
    bogie_cog_height_m: float = 0.6
    # wheelset
    wheelset_mass_kg: float = 1_813.0
    wheelset_roll_inertia_kg_m2: float = 1_120.0
    trailer_spin_inertia_kg_m2: float = 112.0  # benchmark, whole wheelset
    motor_spin_inertia_kg_m2: float = 2 * 116.0  # paper's 116 per half wheelset (drive included)
    wheel_radius_m: float = 0.46
    # primary suspension, per axlebox (2 per wheelset)
    primary_kx_n_m: float = 31.39e6
    primary_kz_n_m: float = 1.22e6
    primary_cz_n_s_m: float = 4.0e3
    primary_cx_n_s_m: float = 50e3  # assumed (rubber-bush damping; the benchmark gives none)
    # secondary suspension, per side (2 per bogie)
    secondary_kx_n_m: float = 160e3
    secondary_kz_n_m: float = 430e3
    secondary_cz_n_s_m: float = 20e3
    secondary_cx_n_s_m: float = 32e3  # assumed equal to the benchmark's lateral cy
    secondary_height_m: float = 0.9  # assumed height of the secondary (traction) connection
    # traction rod between bogie frame and car body, per bogie (assumed: the benchmark coach has no
    # drive; a powered bogie passes its traction through a rod or centre pivot with rubber bushes,
    # much stiffer than the air springs' shear stiffness), at the secondary height
    traction_rod_kx_n_m: float = 10e6
    traction_rod_cx_n_s_m: float = 150e3
    # geometry
    bogie_wheelbase_m: float = 2.56
    bogie_centre_spacing_m: float = 19.0
    # wheel-track vertical contact, per wheel (assumed: rail pad + Hertz contact in series)
    track_stiffness_n_m: float = 200e6
    track_damping_n_s_m: float = 170e3
    # payload in the car body (set by the load case)
    payload_kg: float = 0.0

    @property
    def total_mass_kg(self) -> float:
        return self.carbody_mass_kg + self.payload_kg + 2 * self.bogie_mass_kg + 4 * self.wheelset_mass_kg

    @property
    def static_wheel_load_n(self) -> float:
        """Static normal load per wheel (8 wheels), N."""
        return self.total_mass_kg * GRAVITY / 8.0


LOAD_CASES = ("empty", "laden")
LADEN_WHEEL_LOAD_N = 100e3  # the paper's N


def wagon_parameters(load_case: str = "laden") -> WagonParameters:
    """Benchmark wagon empty (~54.5 kN per wheel) or laden with the payload that gives the paper's
    100 kN per wheel (a 20 t-axle-load freight wagon)."""
    empty = WagonParameters()
    if load_case == "empty":
        return empty
    if load_case == "laden":
        payload = LADEN_WHEEL_LOAD_N * 8.0 / GRAVITY - empty.total_mass_kg
        return WagonParameters(payload_kg=payload)
    raise ValueError(f"load_case must be one of {list(LOAD_CASES)}, got {load_case!r}")
