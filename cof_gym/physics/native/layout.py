"""Layout of ``mjData.userdata``: the one definition shared by Python and the native callback.

The MuJoCo callback is process-global, so everything a simulation needs (its model's wheel-rail
contacts, its creep law, drive, cruise control, noise, filter states and the window accumulators)
lives in that simulation's ``userdata``. ``mujoco.batch`` copies userdata with the rest of the
integration state, so batched and single stepping see the same numbers.

This module is the single source of truth: :func:`c_header` renders the same offsets as a C header
that the native code is compiled against.
"""

from __future__ import annotations

MAGIC = 7263.0417  # marks a cof_gym simulation; other models in the process are left untouched
MAX_CONTACTS = 4
MAX_WD_SECTIONS = 4  # second-order sections of the ISO 2631 Wd weighting
MAX_BAND_SECTIONS = 2  # band limiting (for jerk)
SOS_COEFFS = 5  # b0 b1 b2 a1 a2 (a0 == 1)
# Multi-tone drive: tone 1 is the single modulation above (TORQUE_AMPLITUDE, MOD_OMEGA, THETA_BASE); tones
# 2..MAX_TONES each have an amplitude, an angular frequency and a phase at TIME_BASE (TONE_FIELDS, one block
# per tone, TONE_STRIDE apart). N_TONES > 1 switches on their torque terms and the joint lock-in over
# [cos th_1, sin th_1, ..., cos th_K, sin th_K, 1, tau] (the MT_ accumulators); N_TONES <= 1 leaves the
# single-tone arithmetic exactly as it was.
MAX_TONES = 3
TONE_FIELDS: tuple[str, ...] = ("AMPLITUDE", "OMEGA", "THETA_BASE")
TONE_STRIDE = len(TONE_FIELDS)
# LOCK_IN_ROTATION > 0 adds the encoder's counted angle phi as further pairs [cos phi, sin phi, cos 2 phi, sin 2 phi]
# after the tones (a once-per-revolution ripple of the speed reading and its second harmonic taken out of every fit),
# also to a single tone's window, which then runs the joint lock-in with K = 1
ROTATION_BASIS = 4
MT_MAX_BASIS = 2 * MAX_TONES + ROTATION_BASIS + 2
MT_MAX_BTB = MT_MAX_BASIS * (MT_MAX_BASIS + 1) // 2
# Synchronous (phase-binned) average of the measured CoA over tone 1's modulation cycle: the window's
# samples of the force sensors' CoA are summed in PHASE_BINS equal bins of tone 1's phase (COA_BIN_*),
# which averages the sensor noise over the cycles of a window while keeping the cycle's shape (its crest).
PHASE_BINS = 16
# Vertical track irregularity (cof_gym/physics/track.py): the rail's height under a wheelset at x is
# sum_k TRACK_AMP_k cos(TRACK_WAVENUMBER_k x + TRACK_PHASE_k) over the first TRACK_N_WAVES cosines; 0 waves (the
# default): a smooth track, and the normal-load arithmetic exactly as without it.
MAX_TRACK_WAVES = 32

# Per-contact configuration block (model constants, copied into every simulation's userdata).
CONTACT_FIELDS: tuple[str, ...] = (
    "WHEEL_BODY",  # body id of the spinning wheel(set)
    "REACTION_BODY",  # body receiving the motor's reaction torque (-1: none)
    "Z_QPOS",  # qpos address of the wheelset's vertical slide (-1: load is NOMINAL_LOAD)
    "Z_DOF",  # dof address of the same joint
    "N_WHEELS",  # wheels represented by this contact (2 for a planar wheelset, 1 for a half)
    "RADIUS",  # rolling radius, m
    "K_TRACK",  # vertical wheel-track stiffness of the contact, N/m
    "C_TRACK",  # vertical wheel-track damping, N s/m
    "Z_REST",  # wheelset height at which the track spring is unloaded, m
    "NOMINAL_LOAD",  # normal load of the contact when it has no vertical joint, N
    "AB_REF",  # Hertz a*b per wheel at Q_REF, m^2
    "Q_REF",  # wheel load at which AB_REF holds, N
    "C11",  # Kalker's longitudinal creep coefficient
    "TORQUE_SIGN",  # +1 driven by the modulated torque, -1 equal and opposite, 0 unpowered
)

# Creep-law block, generic over the law families (cof_gym/physics/creep_laws.py): the family's id (its
# index in the native FAMILIES table, looked up by name), the friction level mu0, the shear modulus
# (Pa), up to MAX_LAW_PARAMS family parameters (in the order of the family's Python description) and
# a tabulated curve of up to MAX_TABLE_POINTS points (creepage, value, slope). The same ordering is
# used by the analysis entry points.
MAX_LAW_PARAMS = 8
MAX_TABLE_POINTS = 64
LAW_FIELDS: tuple[str, ...] = (
    "CREEP_FAMILY",
    "MU0",
    "SHEAR_MODULUS",
    *(f"CREEP_P{i}" for i in range(MAX_LAW_PARAMS)),
    "TABLE_N",  # number of table points used (0: no table)
    *(f"TABLE_S_{i}" for i in range(MAX_TABLE_POINTS)),  # creepage, strictly increasing from 0
    *(f"TABLE_R_{i}" for i in range(MAX_TABLE_POINTS)),  # tabulated value at the creepage
    *(f"TABLE_D_{i}" for i in range(MAX_TABLE_POINTS)),  # its slope d value / d creepage
)
CONTACT_LAW_FIELDS: tuple[str, ...] = ("AB_REF", "Q_REF", "C11")

_SCALARS: tuple[str, ...] = (
    "MAGIC",
    "N_CONTACTS",
    "MEASURED_CONTACT",  # the driven contact whose signals are measured
    "CARBODY_X_DOF",  # dof of the car body's longitudinal slide (-1: no car body)
    "MIN_SPEED",  # regularisation of the creepage denominator, m/s
    "TIMESTEP_S",  # the model's physics step (what the lag-1 sums' one step is), s
    *LAW_FIELDS,
    # drive
    "TORQUE_DC_START",
    "TORQUE_DC_TARGET",
    "RAMP_START_TIME",
    "RAMP_DURATION",
    "TORQUE_AMPLITUDE",
    "MOD_OMEGA",  # modulation angular frequency, rad/s
    "THETA_BASE",  # modulation phase at TIME_BASE, rad
    "TIME_BASE",
    "ROT_OMEGA",  # the MOD_OMEGA for which ROT_COS / ROT_SIN hold (a cache, recomputed on change)
    "ROT_COS",  # cos(MOD_OMEGA dt / 2): rotates the mid-step basis to the step's start
    "ROT_SIN",
    "MOTOR_TAU",  # first-order traction-motor torque lag, s (0: none)
    "MOTOR_TORQUE",  # applied motor torque (lag state), N m
    # cruise control on the car body (PI with acceleration feedback)
    "CRUISE_SPEED",
    "CRUISE_KP",  # N per m/s
    "CRUISE_KI",  # N per m (integral of the speed error)
    "CRUISE_KD",  # N per m/s^2
    "CRUISE_INTEGRAL",  # integral of the speed error, m
    # traction balance: the rest of the train's traction, lumped on the car body, cancels the DC part
    # of the interrogation torque: F = -BALANCE_PER_NM x DC torque (N per N m; 0: none)
    "BALANCE_PER_NM",
    "CARBODY_PREV_VEL",
    "CARBODY_ACC",
    # sensor noise (standard deviations) and the generator's state
    "NOISE_OMEGA",  # rad/s
    "NOISE_FORCE",  # relative
    "NOISE_SPEED",  # m/s
    "ENCODER_TAU",  # first-order lag of the encoder's wheelset-speed signal, s (0: none)
    "OMEGA_FILTERED",  # the encoder's lagged speed reading (its state), rad/s
    "OMEGA_PREVIOUS",  # the encoder's reading of the step before, rad/s (the lag's input is held as their mean)
    # the encoder as a pulse generator (cof_gym.physics.encoder; ENCODER_PULSES 0: a continuous reading)
    "ENCODER_PULSES",  # pulses per revolution of the wheelset
    "ENCODER_RUNOUT",  # the target wheel's runout over its pitch radius, relative
    "ENCODER_ANGLE",  # the measured wheelset's angle since the reset, rad (its state)
    "ENCODER_SPIN",  # its spin rate at the last step, rad/s (the angle's trapezoid rule)
    "ENCODER_PULSE_TIME",  # time of the last pulse, s
    "ENCODER_PULSES_SEEN",  # pulses since the reset, capped at 2 (a reading needs two)
    "ENCODER_READING",  # the held reading, rad/s
    "ENCODER_COUNT_ANGLE",  # the angle the encoder counts (its pulses x the pitch; without pulses, its reading's), rad
    "LOCK_IN_ROTATION",  # 1: every fit also takes out a ripple at ENCODER_COUNT_ANGLE (see ROTATION_BASIS)
    "RNG_STATE0",
    "RNG_STATE1",
    # bookkeeping
    "LAST_TIME",  # time of the last state update (guards repeated mj_forward calls)
    "ACC_START_TIME",  # window accumulation starts at this time
    "S_PEAK",  # creepage of the creep-curve peak (slip cost), -
    "BAND_PREV",  # previous band-limited car-body acceleration (jerk)
    # last step (diagnostics)
    "LAST_OMEGA",
    "LAST_SPEED",
    "LAST_CREEPAGE",
    "LAST_COA",
    "LAST_NORMAL",
    "LAST_TORQUE",
    "LAST_CARBODY_ACC",
    # multi-tone drive (see MAX_TONES)
    "N_TONES",
    *(f"TONE{k}_{f}" for k in range(2, MAX_TONES + 1) for f in TONE_FIELDS),
    # vertical track irregularity (see MAX_TRACK_WAVES): m, rad/m, rad
    "TRACK_N_WAVES",
    *(f"TRACK_AMP_{i}" for i in range(MAX_TRACK_WAVES)),
    *(f"TRACK_WAVENUMBER_{i}" for i in range(MAX_TRACK_WAVES)),
    *(f"TRACK_PHASE_{i}" for i in range(MAX_TRACK_WAVES)),
)

# Window accumulators: zeroed by Python at the start of a window.
ACCUMULATORS: tuple[str, ...] = (
    "N_SAMPLES",
    *(f"BTB_TORQUE_{i}" for i in range(10)),  # basis [cos, sin, 1, t] at mid-step
    *(f"BTY_TORQUE_{i}" for i in range(4)),
    "YTY_TORQUE",
    *(f"BTB_STATE_{i}" for i in range(10)),  # the same basis at the step's start
    *(f"BTY_OMEGA_{i}" for i in range(4)),
    "YTY_OMEGA",
    *(f"BTY_CREEP_{i}" for i in range(4)),
    "YTY_CREEP",
    *(f"BTY_CREEP_MEASURED_{i}" for i in range(4)),  # the measured creepage (noisy encoder and speed sensor)
    "YTY_CREEP_MEASURED",
    # lag-1 cross sums of the speed reading y and the state basis b over consecutive samples (the speed fit's
    # residual autocorrelation): sum y_n y_(n-1), sum b_n y_(n-1), sum b_(n-1) y_n, sum b_n b_(n-1)' (row-major),
    # and the previous sample
    "LAG1_YY",
    *(f"LAG1_BY_{i}" for i in range(4)),
    *(f"LAG1_PY_{i}" for i in range(4)),
    *(f"LAG1_BB_{i}" for i in range(16)),
    "LAG1_PREV_Y",
    *(f"LAG1_PREV_B_{i}" for i in range(4)),
    "SUM_COA_MEASURED",
    "SUM_COA_TRUE",
    "SUM_CREEPAGE",
    "SUM_CREEPAGE_MEASURED",  # R omega / v from the noisy encoder and speed sensor
    "SUM_SPEED_MEASURED",
    "SUM_NORMAL",
    "SUM_NORMAL_MEASURED",
    "SUM_TANGENTIAL",
    "SUM_TANGENTIAL_MEASURED",
    "SUM_TORQUE",
    "MAX_ABS_TORQUE",
    "N_COMFORT_SAMPLES",  # comfort sums cover the whole window (from its start, not its settling end)
    "SUM_WD2",
    "SUM_JERK2",
    "MAX_ABS_WD",
    "FRICTION_ENERGY",  # J, all contacts
    "TIME_PAST_PEAK",  # s, any contact beyond the creep-curve peak
    "ENERGY_PAST_PEAK",  # J
    "MAX_ABS_CREEPAGE",  # any contact
    # multi-tone joint lock-in (N_TONES > 1 only): B'B packed upper triangle for the basis of 2 K + 2
    # columns [cos th_1, sin th_1, ..., cos th_K, sin th_K, 1, tau] (K = N_TONES), at mid-step (torque) and
    # at the step's start (state), and B'y; y'y is the single-tone YTY_ of the same signal
    *(f"MT_BTB_TORQUE_{i}" for i in range(MT_MAX_BTB)),
    *(f"MT_BTY_TORQUE_{i}" for i in range(MT_MAX_BASIS)),
    *(f"MT_BTB_STATE_{i}" for i in range(MT_MAX_BTB)),
    *(f"MT_BTY_OMEGA_{i}" for i in range(MT_MAX_BASIS)),
    *(f"MT_BTY_CREEP_{i}" for i in range(MT_MAX_BASIS)),
    *(f"MT_BTY_CREEP_MEASURED_{i}" for i in range(MT_MAX_BASIS)),
    # the joint basis's lag-1 cross sums with the speed reading (LOCK_IN_ROTATION only; as LAG1_ for the single
    # tone, with LAG1_YY and LAG1_PREV_Y shared): sum b_n y_(n-1), sum b_(n-1) y_n, sum b_n b_(n-1)' (row-major, np x
    # np for the window's np columns), and the previous sample's basis
    *(f"MT_LAG1_BY_{i}" for i in range(MT_MAX_BASIS)),
    *(f"MT_LAG1_PY_{i}" for i in range(MT_MAX_BASIS)),
    *(f"MT_LAG1_BB_{i}" for i in range(MT_MAX_BASIS * MT_MAX_BASIS)),
    *(f"MT_LAG1_PREV_B_{i}" for i in range(MT_MAX_BASIS)),
    # synchronous average of the measured CoA (PHASE_BINS bins of tone 1's phase at the step's start, bin k
    # centred on -pi + 2 pi k / PHASE_BINS, so one bin is centred on the torque's crest): samples, sum, sum of squares
    *(f"COA_BIN_N_{k}" for k in range(PHASE_BINS)),
    *(f"COA_BIN_SUM_{k}" for k in range(PHASE_BINS)),
    *(f"COA_BIN_SUM2_{k}" for k in range(PHASE_BINS)),
)


def _build_offsets() -> tuple[dict[str, int], int]:
    names: list[str] = list(_SCALARS)
    for k in range(MAX_CONTACTS):
        names += [f"C{k}_{f}" for f in CONTACT_FIELDS]
    names += [f"WD_SOS_{i}" for i in range(MAX_WD_SECTIONS * SOS_COEFFS)]
    names += [f"WD_STATE_{i}" for i in range(MAX_WD_SECTIONS * 2)]
    names += ["WD_NSECT"]
    names += [f"BAND_SOS_{i}" for i in range(MAX_BAND_SECTIONS * SOS_COEFFS)]
    names += [f"BAND_STATE_{i}" for i in range(MAX_BAND_SECTIONS * 2)]
    names += ["BAND_NSECT"]
    names += list(ACCUMULATORS)
    return {n: i for i, n in enumerate(names)}, len(names)


OFFSETS, SIZE = _build_offsets()
TONE0 = OFFSETS[f"TONE2_{TONE_FIELDS[0]}"]
assert all(OFFSETS[f"TONE{k}_{f}"] == TONE0 + (k - 2) * TONE_STRIDE + i
           for k in range(2, MAX_TONES + 1) for i, f in enumerate(TONE_FIELDS)), "tone blocks must be contiguous"
CONTACT_STRIDE = len(CONTACT_FIELDS)
_LAW_AT = CONTACT_FIELDS.index(CONTACT_LAW_FIELDS[0])
assert CONTACT_FIELDS[_LAW_AT:_LAW_AT + len(CONTACT_LAW_FIELDS)] == CONTACT_LAW_FIELDS, \
    "the contact-law fields must be contiguous in CONTACT_FIELDS, in CONTACT_LAW_FIELDS' order (cfg + CF_AB_REF)"
ACC_FIRST = OFFSETS[ACCUMULATORS[0]]
ACC_COUNT = len(ACCUMULATORS)


def index(name: str) -> int:
    """Userdata index of a named field (raises KeyError with the name)."""
    return OFFSETS[name]


def c_header() -> str:
    """The layout as C preprocessor definitions (``UD_<NAME>``)."""
    lines = ["/* generated from cof_gym/physics/native/layout.py: do not edit */", "#pragma once"]
    lines.append(f"#define UD_SIZE {SIZE}")
    lines.append(f"#define UD_MAGIC_VALUE {MAGIC!r}")
    lines.append(f"#define UD_MAX_CONTACTS {MAX_CONTACTS}")
    lines.append(f"#define UD_CONTACT_STRIDE {CONTACT_STRIDE}")
    lines.append(f"#define UD_CONTACT0 {OFFSETS['C0_' + CONTACT_FIELDS[0]]}")
    for i, f in enumerate(CONTACT_FIELDS):
        lines.append(f"#define CF_{f} {i}")
    for i, f in enumerate(LAW_FIELDS):
        lines.append(f"#define LAW_{f} {i}")
    lines.append(f"#define LAW_SIZE {len(LAW_FIELDS)}")
    lines.append(f"#define LAW_MAX_PARAMS {MAX_LAW_PARAMS}")
    lines.append(f"#define LAW_MAX_TABLE_POINTS {MAX_TABLE_POINTS}")
    lines.append(f"#define UD_LAW0 {OFFSETS[LAW_FIELDS[0]]}")
    for i, f in enumerate(CONTACT_LAW_FIELDS):
        lines.append(f"#define CLAW_{f} {i}")
    lines.append(f"#define UD_ACC_FIRST {ACC_FIRST}")
    lines.append(f"#define UD_MAX_TONES {MAX_TONES}")
    lines.append(f"#define UD_TONE0 {TONE0}")
    lines.append(f"#define UD_TONE_STRIDE {TONE_STRIDE}")
    for i, f in enumerate(TONE_FIELDS):
        lines.append(f"#define TONE_{f} {i}")
    lines.append(f"#define UD_MT_MAX_BASIS {MT_MAX_BASIS}")
    lines.append(f"#define UD_ROTATION_BASIS {ROTATION_BASIS}")
    lines.append(f"#define UD_PHASE_BINS {PHASE_BINS}")
    lines.append(f"#define UD_MAX_TRACK_WAVES {MAX_TRACK_WAVES}")
    lines.append(f"#define UD_ACC_COUNT {ACC_COUNT}")
    for name in ("WD_SOS_0", "WD_STATE_0", "WD_NSECT", "BAND_SOS_0", "BAND_STATE_0", "BAND_NSECT"):
        lines.append(f"#define UD_{name} {OFFSETS[name]}")
    for name in (*_SCALARS, *ACCUMULATORS):
        lines.append(f"#define UD_{name} {OFFSETS[name]}")
    return "\n".join(lines) + "\n"
