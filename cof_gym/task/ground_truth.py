"""The ground truth the task scores against, defined by what the simulated vehicle can reach.

**Definition.** The scored CoF is the largest adhesion (CoA = tangential / normal force) that the
driven wheelset reaches in this simulation under steady traction, at its actual normal load under that
traction and at the cruise-controlled speed. ``saturation_torque_nm`` is the DC torque at which it
gets there.

Under a steady traction force F at the driven wheelset's rails, the vehicle's statics move load onto
(or off) that wheelset: N = N0 + alpha F, with N0 its static load and alpha the *load-transfer
coefficient* of the built vehicle (secondary and traction-rod heights over the bogie wheelbase and
bogie spacing, which side the reactions act on: about 0.375 for the wagon without the counter torque,
0 with it, 0 for the half wheelset). alpha is measured once per built vehicle by simulating a steady
torque (:func:`load_transfer_coefficient`), not typed in, so it follows the model.

At saturation F = cof N, so N_sat = N0 / (1 - alpha cof) and M_sat = R cof N_sat. The creep law's mu0
is solved so that the steady creep curve *at the wheel load N_sat / wheels and the set speed* peaks
exactly at ``cof`` (:func:`cof_gym.physics.creep.mu0_for_cof`); the PI cruise control holds the set
speed under steady traction. So the largest CoA the simulation can produce equals the scored CoF, and
it is produced at ``saturation_torque_nm`` (tests/test_ground_truth.py ramps the torque and checks it).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from cof_gym.physics.creep import CreepShape, OperatingConditions, creep_peak
from cof_gym.physics.models import BuiltModel
from cof_gym.physics.simulation import DriveCommand, Scenario, Simulation

CALIBRATION_COF = 0.6  # a friction level the calibration torque stays well below
CALIBRATION_TORQUE_FRACTION = 0.3  # of the static saturation torque at CALIBRATION_COF
CALIBRATION_SPEED_M_S = 20.0
CALIBRATION_SETTLE_S = 6.0  # the suspension and the PI cruise control settle
CALIBRATION_MEASURE_S = 2.0


@dataclass(frozen=True)
class GroundTruth:
    """What the episode is scored against (never observed by a non-oracle agent)."""

    cof: float  # the largest steady CoA of the driven wheelset
    saturation_torque_nm: float  # the DC torque at which it is reached
    saturation_load_n: float  # the driven contact's normal load there (whole contact), N
    peak_creepage: float  # the creepage of that peak

    def to_dict(self) -> dict[str, float]:
        return {"cof": self.cof, "saturation_torque_nm": self.saturation_torque_nm,
                "saturation_load_n": self.saturation_load_n, "peak_creepage": self.peak_creepage}


def static_contact_load_n(built: BuiltModel) -> float:
    """The driven contact's static normal load (all its wheels), N."""
    return built.nominal_wheel_load_n * built.wheels_per_contact


@lru_cache(maxsize=64)
def load_transfer_coefficient(built: BuiltModel, traction_balance: bool) -> float:
    """alpha = dN/dF of the driven contact under steady traction, measured on ``built`` (cached):
    one window without torque, one with a steady DC torque, both after the vehicle settled."""
    n0 = static_contact_load_n(built)
    op = OperatingConditions(cof=CALIBRATION_COF, condition="dry", wheel_load_n=built.nominal_wheel_load_n,
                             speed_m_s=CALIBRATION_SPEED_M_S)
    torque = CALIBRATION_TORQUE_FRACTION * CALIBRATION_COF * built.wheel_radius_m * n0
    sim = Simulation(built)
    loads = []
    for dc in (0.0, torque):
        sim.reset(Scenario(op, traction_balance=traction_balance))
        m = sim.run_window(DriveCommand(dc, 0.0, 5.0), CALIBRATION_SETTLE_S + CALIBRATION_MEASURE_S,
                           CALIBRATION_SETTLE_S, ramp_s=1.0)
        loads.append((m.normal_load_n, m.tangential_force_n))
    (n_free, _), (n_loaded, f_loaded) = loads
    return (n_loaded - n_free) / f_loaded


def saturation_load_n(built: BuiltModel, traction_balance: bool, cof: float) -> float:
    """The driven contact's normal load at saturation, N_sat = N0 / (1 - alpha cof), N."""
    alpha = load_transfer_coefficient(built, traction_balance)
    if alpha * cof >= 0.5:
        raise ValueError(f"cof={cof} with load transfer {alpha:.3f} would more than double the wheel load")
    return static_contact_load_n(built) / (1.0 - alpha * cof)


def ground_truth(built: BuiltModel, traction_balance: bool, cof: float, condition: str | CreepShape,
                 speed_m_s: float) -> tuple[GroundTruth, float]:
    """The episode's ground truth and the wheel load (N, per wheel) at which the creep law is
    calibrated so that its peak equals ``cof`` there. ``condition``: a preset name or a creep-curve
    shape of any family (:mod:`cof_gym.physics.creep_laws`); for a curve without a falling branch
    the peak is where its supremum is first reached."""
    n_sat = saturation_load_n(built, traction_balance, cof)
    wheel_load = n_sat / built.wheels_per_contact
    peak = creep_peak(OperatingConditions(cof=cof, condition=condition, wheel_load_n=wheel_load, speed_m_s=speed_m_s))
    truth = GroundTruth(cof=cof, saturation_torque_nm=built.wheel_radius_m * cof * n_sat, saturation_load_n=n_sat,
                        peak_creepage=peak.creepage)
    return truth, wheel_load


def max_saturation_torque_nm(built: BuiltModel, traction_balance: bool, max_cof: float) -> float:
    """The largest saturation torque of ``built`` over CoF up to ``max_cof`` (load transfer included)."""
    return built.wheel_radius_m * max_cof * saturation_load_n(built, traction_balance, max_cof)
