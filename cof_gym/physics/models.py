"""MuJoCo models built from parameters with MjSpec: the paper's half wheelset and the planar wagon.

Wheel-rail forces are not MuJoCo contacts: MuJoCo's collision is disabled and the native callback
(:mod:`cof_gym.physics.native`) applies the normal (wheel-track spring) and creep forces at each
wheel's contact point. Suspensions are MuJoCo spatial tendons with stiffness and damping, preloaded so
that the nominal geometry is the static equilibrium.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco

from cof_gym.physics.contact_geometry import ContactGeometry
from cof_gym.physics.creep import ContactPatch
from cof_gym.physics.native import layout
from cof_gym.physics.scenery import add_scenery
from cof_gym.physics.vehicle import GRAVITY, HalfWheelsetParameters, WagonParameters
from cof_gym.validation import check_number

DEFAULT_TIMESTEP_S = 1e-3
HALF_WHEELSET_ARMATURE_KG = 1e12  # reflected mass that holds the half wheelset's speed constant


@dataclass(frozen=True)
class ContactSpec:
    """One wheel-rail contact as the native callback sees it (see layout.CONTACT_FIELDS)."""

    wheel_body: int
    reaction_body: int
    z_qpos: int
    z_dof: int
    n_wheels: int
    radius_m: float
    k_track_n_m: float
    c_track_n_s_m: float
    z_rest_m: float
    nominal_load_n: float
    patch: ContactPatch
    torque_sign: int

    def values(self) -> dict[str, float]:
        return {
            "WHEEL_BODY": self.wheel_body, "REACTION_BODY": self.reaction_body,
            "Z_QPOS": self.z_qpos, "Z_DOF": self.z_dof, "N_WHEELS": self.n_wheels,
            "RADIUS": self.radius_m, "K_TRACK": self.k_track_n_m, "C_TRACK": self.c_track_n_s_m,
            "Z_REST": self.z_rest_m, "NOMINAL_LOAD": self.nominal_load_n,
            "AB_REF": self.patch.ab_ref_m2, "Q_REF": self.patch.q_ref_n, "C11": self.patch.c11,
            "TORQUE_SIGN": self.torque_sign,
        }


@dataclass(eq=False)
class BuiltModel:
    """A compiled model plus what the callback and the measurement need to know about it (hashed by
    identity: models are built once per process and shared)."""

    kind: str
    model: mujoco.MjModel
    contacts: list[ContactSpec]
    measured_contact: int
    carbody_x_dof: int
    wheel_radius_m: float
    drive_spin_inertia_kg_m2: float  # spin inertia of the measured (driven) wheel(set)
    nominal_wheel_load_n: float  # static load per wheel
    wheels_per_contact: int
    total_mass_kg: float
    x_dofs: list[int] = field(default_factory=list)  # slide-x dofs (initial speed v)
    spin_dofs: list[tuple[int, float]] = field(default_factory=list)  # (dof, radius) rolling at v/R

    def __post_init__(self) -> None:
        """Every index the native callback reads from the userdata lies in the model (ValueError naming it)."""
        m = self.model
        if not 1 <= len(self.contacts) <= layout.MAX_CONTACTS:
            raise ValueError(f"contacts: 1 to {layout.MAX_CONTACTS} contacts, got {len(self.contacts)}")
        _check_index("measured_contact", self.measured_contact, 0, len(self.contacts))
        _check_index("carbody_x_dof", self.carbody_x_dof, -1, m.nv)
        for k, c in enumerate(self.contacts):
            _check_index(f"contacts[{k}].wheel_body", c.wheel_body, 1, m.nbody)
            _check_index(f"contacts[{k}].reaction_body", c.reaction_body, -1, m.nbody)
            _check_index(f"contacts[{k}].z_qpos", c.z_qpos, -1, m.nq)
            _check_index(f"contacts[{k}].z_dof", c.z_dof, 0 if c.z_qpos >= 0 else -1, m.nv)

    @property
    def saturation_torque_per_cof(self) -> float:
        """Static saturation torque of the driven wheel(set) per unit CoF, N m: R N_contact."""
        return self.wheel_radius_m * self.nominal_wheel_load_n * self.wheels_per_contact


def _check_index(name: str, value: int, low: int, high: int) -> None:
    """``value`` an integer in [low, high) (an index into the model's arrays; -1: none, where ``low`` is -1)."""
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value < high:
        raise ValueError(f"{name} must be an integer in [{low}, {high - 1}], got {value!r}")


def _spec(timestep: float) -> mujoco.MjSpec:
    # below 5 ms: the comfort filters sample above twice ISO 2631's 100 Hz band edge (measurement.comfort)
    check_number("timestep", timestep, 1e-6, 5e-3, high_open=True, unit=" s")
    spec = mujoco.MjSpec()
    spec.option.timestep = timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_EULER
    spec.option.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT) | int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    spec.nuserdata = layout.SIZE
    return spec


def _joint(body, kind: str, name: str, armature: float = 0.0):
    axis = {"x": ([1, 0, 0], mujoco.mjtJoint.mjJNT_SLIDE), "z": ([0, 0, 1], mujoco.mjtJoint.mjJNT_SLIDE),
            "pitch": ([0, 1, 0], mujoco.mjtJoint.mjJNT_HINGE)}[kind]
    return body.add_joint(name=name, type=axis[1], axis=axis[0], armature=armature)


def _wheel(parent, name: str, mass: float, spin_inertia: float, roll_inertia: float, radius: float,
           width: float = 0.14):
    wheel = parent.add_body(name=name, ipos=[0, 0, 0], explicitinertial=True, mass=mass, inertia=[roll_inertia, spin_inertia, roll_inertia])
    _joint(wheel, "pitch", f"{name}_spin")
    wheel.add_geom(type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[radius, width / 2, 0], quat=[0.7071068, 0.7071068, 0, 0],
                   rgba=[0.3, 0.3, 0.35, 1], contype=0, conaffinity=0, mass=0)
    wheel.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[radius * 0.9, width / 2 + 0.01, 0.03],
                   rgba=[0.9, 0.7, 0.1, 1], contype=0, conaffinity=0, mass=0)  # shows the spin
    return wheel


def build_half_wheelset(params: HalfWheelsetParameters = HalfWheelsetParameters(),
                        timestep: float = DEFAULT_TIMESTEP_S,
                        geometry: ContactGeometry = ContactGeometry()) -> BuiltModel:
    """Paper Sect. 2 / Fig. 1: a half wheelset at constant speed (a reflected mass of 1e12 kg on its
    longitudinal slide stands for the suspension holding v) under a constant normal load N."""
    spec = _spec(timestep)
    r = params.wheel_radius_m
    box = spec.worldbody.add_body(name="axlebox", pos=[0, 0, r], ipos=[0, 0, 0], explicitinertial=True, mass=params.mass_kg, inertia=[1, 1, 1])
    _joint(box, "x", "axlebox_x", armature=HALF_WHEELSET_ARMATURE_KG)
    _wheel(box, "wheel", 1.0, params.spin_inertia_kg_m2, 0.6 * params.spin_inertia_kg_m2, r)
    spec.worldbody.add_camera(name="side", mode=mujoco.mjtCamLight.mjCAMLIGHT_TRACKCOM, pos=[0, -3, 0.8],
                              xyaxes=[1, 0, 0, 0, 0.15, 1])
    add_scenery(spec, r, rail_y_m=(0.0,))
    model = spec.compile()
    contact = ContactSpec(
        wheel_body=model.body("wheel").id, reaction_body=-1, z_qpos=-1, z_dof=-1, n_wheels=1, radius_m=r,
        k_track_n_m=0.0, c_track_n_s_m=0.0, z_rest_m=0.0, nominal_load_n=params.normal_load_n,
        patch=ContactPatch.at_load(params.normal_load_n, geometry), torque_sign=1,
    )
    return BuiltModel(
        kind="half_wheelset", model=model, contacts=[contact], measured_contact=0, carbody_x_dof=-1,
        wheel_radius_m=r, drive_spin_inertia_kg_m2=params.spin_inertia_kg_m2,
        nominal_wheel_load_n=params.normal_load_n, wheels_per_contact=1, total_mass_kg=params.mass_kg,
        x_dofs=[model.joint("axlebox_x").dofadr[0]], spin_dofs=[(model.joint("wheel_spin").dofadr[0], r)],
    )


def _spring(spec, name: str, terms: list[tuple[str, float]], stiffness: float, damping: float,
            rest_length: float = 0.0) -> None:
    """A linear spring-damper on the deflection sum(coef * q) (a MuJoCo fixed tendon): the
    small-angle kinematics of a suspension element, free of the geometric stiffness a preloaded
    spatial strut would add. ``rest_length`` > 0 preloads it in compression."""
    t = spec.add_tendon(name=name, stiffness=[stiffness, 0, 0], damping=[damping, 0, 0],
                        springlength=[rest_length, rest_length])
    for joint, coef in terms:
        t.wrap_joint(joint, coef)


def build_wagon(params: WagonParameters, timestep: float = DEFAULT_TIMESTEP_S,
                geometry: ContactGeometry = ContactGeometry(), counter_torque: bool = True) -> BuiltModel:
    """Paper Sect. 3: car body, two bogie frames, four wheelsets; primary and secondary suspensions
    (Manchester benchmark); traction torque on the rear wheelset of the rear bogie and an equal,
    opposite torque on that bogie's front wheelset (reactions on the bogie frame); PD cruise control
    on the car body (in the callback). Planar: x (longitudinal), z (vertical), pitch.

    ``counter_torque=False`` drops the opposite torque: the traction then acts on the whole train, the
    cruise control balances it, and the car body feels the modulation (passenger comfort)."""
    p = params
    spec = _spec(timestep)
    r = p.wheel_radius_m
    m_body = _add_carbody(spec, p)
    f_secondary = m_body * GRAVITY / 2  # per bogie (both sides)
    f_primary = (f_secondary + p.bogie_mass_kg * GRAVITY) / 2  # per wheelset
    wheelsets: list[tuple[str, float, int]] = []  # (name, x, torque sign)
    for b_name, xb in (("bogie_front", p.bogie_centre_spacing_m / 2), ("bogie_rear", -p.bogie_centre_spacing_m / 2)):
        _add_bogie(spec, p, b_name, xb, f_secondary)
        for w_name, dx in (("front", p.bogie_wheelbase_m / 2), ("rear", -p.bogie_wheelbase_m / 2)):
            name = f"{b_name}_{w_name}_wheelset"
            sign = 0 if b_name == "bogie_front" else (1 if w_name == "rear" else (-1 if counter_torque else 0))
            wheelsets.append((name, xb + dx, sign))
            _add_wheelset(spec, p, b_name, name, xb + dx, dx, f_primary)
    spec.worldbody.add_camera(name="side", mode=mujoco.mjtCamLight.mjCAMLIGHT_TRACKCOM, pos=[0, -28, 3],
                              xyaxes=[1, 0, 0, 0, 0.1, 1])
    add_scenery(spec, r, [n for n, _, _ in wheelsets], next(n for n, _, sign in wheelsets if sign == 1))
    model = spec.compile()
    contacts = _wagon_contacts(model, p, geometry, wheelsets, f_primary + p.wheelset_mass_kg * GRAVITY)
    measured = next(i for i, c in enumerate(contacts) if c.torque_sign == 1)
    x_joints = ["carbody_x", "bogie_front_x", "bogie_rear_x"] + [f"{n}_x" for n, _, _ in wheelsets]
    return BuiltModel(
        kind="wagon", model=model, contacts=contacts, measured_contact=measured,
        carbody_x_dof=int(model.joint("carbody_x").dofadr[0]), wheel_radius_m=r,
        drive_spin_inertia_kg_m2=p.motor_spin_inertia_kg_m2, nominal_wheel_load_n=p.static_wheel_load_n,
        wheels_per_contact=2, total_mass_kg=p.total_mass_kg,
        x_dofs=[int(model.joint(j).dofadr[0]) for j in x_joints],
        spin_dofs=[(int(model.joint(f"{n}_spin").dofadr[0]), r) for n, _, _ in wheelsets],
    )


def _add_carbody(spec: mujoco.MjSpec, p: WagonParameters) -> float:
    """The car body with its payload (x, z and pitch joints); returns its mass (kg)."""
    m_body = p.carbody_mass_kg + p.payload_kg
    load_length = p.bogie_centre_spacing_m + 1.0  # payload spread over the underframe (assumed)
    i_body = p.carbody_pitch_inertia_kg_m2 + p.payload_kg * load_length**2 / 12.0
    body = spec.worldbody.add_body(name="carbody", pos=[0, 0, p.carbody_cog_height_m], ipos=[0, 0, 0],
                                   explicitinertial=True, mass=m_body, inertia=[56_800.0, i_body, i_body])
    for kind in ("x", "z", "pitch"):
        _joint(body, kind, f"carbody_{kind}")
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[12.0, 1.4, 1.1], pos=[0, 0, 0.6],
                  rgba=[0.15, 0.35, 0.6, 1], contype=0, conaffinity=0, mass=0)
    return m_body


def _add_bogie(spec: mujoco.MjSpec, p: WagonParameters, b_name: str, xb: float, f_secondary: float) -> None:
    """Bogie frame ``b_name`` at ``xb`` (m) with its secondary suspension to the car body (vertical, preloaded
    by ``f_secondary`` N; longitudinal, and the traction rod where it has one)."""
    bogie = spec.worldbody.add_body(name=b_name, pos=[xb, 0, p.bogie_cog_height_m], ipos=[0, 0, 0],
                                    explicitinertial=True, mass=p.bogie_mass_kg,
                                    inertia=[1_722.0, p.bogie_pitch_inertia_kg_m2, 3_067.0])
    for kind in ("x", "z", "pitch"):
        _joint(bogie, kind, f"{b_name}_{kind}")
    bogie.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[p.bogie_wheelbase_m / 2 + 0.4, 1.0, 0.15],
                   rgba=[0.25, 0.25, 0.25, 1], contype=0, conaffinity=0, mass=0)
    zb = p.bogie_cog_height_m
    hb, hc = p.secondary_height_m - zb, p.secondary_height_m - p.carbody_cog_height_m  # in bogie / body frames
    # small-angle kinematics: a point (x, z) of a body moves dx = x_j + z theta, dz = z_j - x theta
    _spring(spec, f"{b_name}_secondary_z",
            [("carbody_z", 1.0), ("carbody_pitch", -xb), (f"{b_name}_z", -1.0)],
            2 * p.secondary_kz_n_m, 2 * p.secondary_cz_n_s_m, f_secondary / (2 * p.secondary_kz_n_m))
    secondary_x = [("carbody_x", 1.0), ("carbody_pitch", hc), (f"{b_name}_x", -1.0), (f"{b_name}_pitch", -hb)]
    _spring(spec, f"{b_name}_secondary_x", secondary_x, 2 * p.secondary_kx_n_m, 2 * p.secondary_cx_n_s_m)
    if p.traction_rod_kx_n_m > 0:
        _spring(spec, f"{b_name}_traction_rod", secondary_x, p.traction_rod_kx_n_m, p.traction_rod_cx_n_s_m)


def _add_wheelset(spec: mujoco.MjSpec, p: WagonParameters, b_name: str, name: str, xw: float, dx: float,
                  f_primary: float) -> None:
    """Wheelset ``name`` of bogie ``b_name`` at ``xw`` (m; ``dx`` from the bogie's centre): its axlebox (x and z
    joints), the wheel (a drive's spin inertia on the rear, motored bogie) and the primary suspension (vertical,
    preloaded by ``f_primary`` N; longitudinal)."""
    r, zb = p.wheel_radius_m, p.bogie_cog_height_m
    box = spec.worldbody.add_body(name=f"{name}_axlebox", pos=[xw, 0, r], ipos=[0, 0, 0],
                                  explicitinertial=True, mass=1.0, inertia=[0.1, 0.1, 0.1])
    _joint(box, "x", f"{name}_x")
    _joint(box, "z", f"{name}_z")
    motored = b_name == "bogie_rear"  # both wheelsets of the rear bogie carry a drive
    spin = p.motor_spin_inertia_kg_m2 if motored else p.trailer_spin_inertia_kg_m2
    _wheel(box, name, p.wheelset_mass_kg - 1.0, spin, p.wheelset_roll_inertia_kg_m2, r)
    _spring(spec, f"{name}_primary_z", [(f"{b_name}_z", 1.0), (f"{b_name}_pitch", -dx), (f"{name}_z", -1.0)],
            2 * p.primary_kz_n_m, 2 * p.primary_cz_n_s_m, f_primary / (2 * p.primary_kz_n_m))
    _spring(spec, f"{name}_primary_x", [(f"{b_name}_x", 1.0), (f"{b_name}_pitch", r - zb), (f"{name}_x", -1.0)],
            2 * p.primary_kx_n_m, 2 * p.primary_cx_n_s_m)


def _wagon_contacts(model: mujoco.MjModel, p: WagonParameters, geometry: ContactGeometry,
                    wheelsets: list[tuple[str, float, int]], n_wheelset: float) -> list[ContactSpec]:
    """Each wheelset's wheel-rail contact (both wheels; ``n_wheelset`` N its static load): the track's spring
    and damper under it, the contact patch at the static wheel load, and its torque sign (a driven wheelset's
    reaction on the rear bogie)."""
    k_track = 2 * p.track_stiffness_n_m
    patch = ContactPatch.at_load(p.static_wheel_load_n, geometry)
    contacts = []
    for name, _, sign in wheelsets:
        zj = model.joint(f"{name}_z")
        reaction = model.body("bogie_rear").id if sign != 0 else -1
        contacts.append(ContactSpec(
            wheel_body=model.body(name).id, reaction_body=reaction, z_qpos=int(zj.qposadr[0]),
            z_dof=int(zj.dofadr[0]), n_wheels=2, radius_m=p.wheel_radius_m, k_track_n_m=k_track,
            c_track_n_s_m=2 * p.track_damping_n_s_m, z_rest_m=n_wheelset / k_track, nominal_load_n=n_wheelset,
            patch=patch, torque_sign=sign,
        ))
    return contacts
