/*
 * cof_gym native core: creep-law families (Polach, Shen-Hedrick-Elkins, tabulated), wheel-rail
 * contact forces, modulated traction torque, cruise control and the in-step measurement chain
 * (lock-in sums, ISO 2631 Wd filter), run as a MuJoCo mjcb_passive callback. No Python runs per physics step.
 *
 * Everything a simulation needs is read from mjData.userdata (layout: cofgym_layout.h, generated
 * from layout.py), so one process-global callback serves any number of models and simulations,
 * and mujoco.batch (which copies userdata with the state) is bit-identical to single stepping.
 */
#include <math.h>
#include <string.h>
#include <stdint.h>
#include <mujoco/mujoco.h>
#include "cofgym_layout.h"

#define PI 3.14159265358979323846
#define TWO_OVER_PI 0.63661977236758134308

/* ---------------------------------------------------------------- creep-law families
 *
 * A family is one function: the longitudinal creep force per wheel (N, with the sign of u) and its
 * derivative with respect to the slip velocity u = R Omega - v (N s/m), at wheel load q > 0 (N) and
 * rolling speed v > 0 (m/s). Its parameters are law[LAW_CREEP_P0 + k] in the order of the family's
 * Python description (cof_gym/physics/creep_laws.py), which also gives their sources and ranges.
 * FAMILIES (below the functions) maps each family's name to its function; Python looks the id up
 * by name, so adding a family is one function here, one row in FAMILIES and one Python class.
 */
typedef double (*creep_family_fn)(const double* law, const double* claw, double q, double v, double u,
                                  double* dfdu);

/* Hertz product a*b (m^2) at wheel load q (N): it scales with q^(2/3) from its reference value (a/b
 * and so c11 stay constant). */
static double hertz_ab(const double* claw, double q) {
  double r = q / claw[CLAW_Q_REF];
  return claw[CLAW_AB_REF] * cbrt(r * r);
}

/* Polach's creep-stiffness constant C = G pi a b c11 / (4 Q) for wheel load q (N). */
static double creep_constant(const double* claw, double shear_modulus, double q) {
  double ab = hertz_ab(claw, q);
  return shear_modulus * PI * ab * claw[CLAW_C11] / (4.0 * q);
}

/* Falling friction mu = mu0 [(1 - A) exp(-B w) + A] at slip velocity w (m/s) and dmu/dw (Polach 2005). */
static double falling_friction(double mu0, double A, double B, double w, double* dmu_dw) {
  const double e = exp(-B * w);
  *dmu_dw = -mu0 * (1.0 - A) * B * e;
  return mu0 * ((1.0 - A) * e + A);
}

/* Polach (2005, Wear 258:992-1000); parameters kA, kS, A, B:
 *   F/(q mu) = (2/pi) [kA eps/(1 + (kA eps)^2) + atan(kS eps)],  eps = C |s| / mu,  s = u / v
 *   mu = mu0 [(1 - A) exp(-B |u|) + A]   (falling friction with slip velocity w = |s| v = |u|) */
static double polach_force(const double* law, const double* claw, double q, double v, double u, double* dfdu) {
  const double mu0 = law[LAW_MU0], kA = law[LAW_CREEP_P0], kS = law[LAW_CREEP_P0 + 1];
  const double A = law[LAW_CREEP_P0 + 2], B = law[LAW_CREEP_P0 + 3];
  const double c = creep_constant(claw, law[LAW_SHEAR_MODULUS], q);
  const double w = fabs(u);
  const double s = w / v;
  double dmu_dw;
  const double mu = falling_friction(mu0, A, B, w, &dmu_dw);
  const double eps = c * s / mu;
  const double ka_eps = kA * eps, ks_eps = kS * eps;
  const double g = TWO_OVER_PI * (ka_eps / (1.0 + ka_eps * ka_eps) + atan(ks_eps));
  const double dg_deps = TWO_OVER_PI * (kA * (1.0 - ka_eps * ka_eps) /
                                            ((1.0 + ka_eps * ka_eps) * (1.0 + ka_eps * ka_eps)) +
                                        kS / (1.0 + ks_eps * ks_eps));
  const double deps_dw = c / (v * mu) - c * s / (mu * mu) * dmu_dw;
  if (dfdu) *dfdu = q * (dmu_dw * g + mu * dg_deps * deps_dw);
  const double f = q * mu * g;
  return u >= 0.0 ? f : -f;
}

/* Shen, Hedrick, Elkins (8th IAVSD, 1983) saturation of Kalker's linear theory; parameters k, A, B:
 *   F/(q mu) = x - x^2/3 + x^3/27 = 1 - (1 - x/3)^3 for x < 3, else 1;   x = k C_K |s| / mu
 * with Kalker's linear stiffness per unit load C_K = G a b c11 / q (Kalker 1990), a reduction factor
 * k (1: Kalker's) and Polach's falling friction mu(w) (A = 1 or B = 0: constant friction, the
 * original law, which saturates at mu with no falling branch, reached at x = 3). */
static double she_force(const double* law, const double* claw, double q, double v, double u, double* dfdu) {
  const double mu0 = law[LAW_MU0], k = law[LAW_CREEP_P0];
  const double A = law[LAW_CREEP_P0 + 1], B = law[LAW_CREEP_P0 + 2];
  const double c = k * law[LAW_SHEAR_MODULUS] * hertz_ab(claw, q) * claw[CLAW_C11] / q;
  const double w = fabs(u);
  const double s = w / v;
  double dmu_dw;
  const double mu = falling_friction(mu0, A, B, w, &dmu_dw);
  const double x = c * s / mu;
  double g = 1.0, dg_dx = 0.0;
  if (x < 3.0) {
    const double y = 1.0 - x / 3.0;
    g = 1.0 - y * y * y;
    dg_dx = y * y;
  }
  const double dx_dw = c / (v * mu) - c * s / (mu * mu) * dmu_dw;
  if (dfdu) *dfdu = q * (dmu_dw * g + mu * dg_dx * dx_dw);
  const double f = q * mu * g;
  return u >= 0.0 ? f : -f;
}

/* Tabulated adhesion ratio: CoA = mu0 r(|s|), with r the monotone piecewise-cubic Hermite
 * interpolant (PCHIP, Fritsch & Carlson 1980; knot slopes computed once in Python) through the
 * points (TABLE_S, TABLE_R), constant beyond the last point; independent of speed and load. */
static double table_force(const double* law, const double* claw, double q, double v, double u, double* dfdu) {
  (void)claw;
  const int n = (int)law[LAW_TABLE_N];
  const double* xs = law + LAW_TABLE_S_0;
  const double* rs = law + LAW_TABLE_R_0;
  const double* ds = law + LAW_TABLE_D_0;
  if (n < 2 || n > LAW_MAX_TABLE_POINTS) {
    if (dfdu) *dfdu = 0.0;
    return 0.0;
  }
  const double s = fabs(u) / v;
  double r, dr = 0.0;
  if (s >= xs[n - 1]) {
    r = rs[n - 1];
  } else {
    int lo = 0, hi = n - 1; /* xs[lo] <= s < xs[hi] */
    while (hi - lo > 1) {
      int mid = (lo + hi) / 2;
      if (xs[mid] <= s) lo = mid; else hi = mid;
    }
    const double h = xs[hi] - xs[lo], t = (s - xs[lo]) / h, t1 = 1.0 - t;
    r = (1.0 + 2.0 * t) * t1 * t1 * rs[lo] + t * t1 * t1 * h * ds[lo] + t * t * (3.0 - 2.0 * t) * rs[hi] +
        t * t * (t - 1.0) * h * ds[hi];
    dr = 6.0 * t * (t - 1.0) * (rs[lo] - rs[hi]) / h + (3.0 * t * t - 4.0 * t + 1.0) * ds[lo] +
         (3.0 * t * t - 2.0 * t) * ds[hi];
  }
  const double mu0 = law[LAW_MU0];
  if (dfdu) *dfdu = q * mu0 * dr / v;
  const double f = q * mu0 * r;
  return u >= 0.0 ? f : -f;
}

typedef struct {
  const char* name;
  creep_family_fn force;
} creep_family;

static const creep_family FAMILIES[] = {
    {"polach", polach_force},
    {"shen_hedrick_elkins", she_force},
    {"table", table_force},
};
#define N_FAMILIES ((int)(sizeof FAMILIES / sizeof FAMILIES[0]))

/* The id (LAW_CREEP_FAMILY) of a family by name, -1 for an unknown name. */
int cofgym_family_id(const char* name) {
  for (int i = 0; i < N_FAMILIES; i++)
    if (strcmp(FAMILIES[i].name, name) == 0) return i;
  return -1;
}

/* Longitudinal creep force per wheel (N) and dF/du (N s/m) of the law block ``law`` (its family
 * chosen by LAW_CREEP_FAMILY); zero for no load, no speed or an unknown family. */
double cofgym_creep_force(const double* law, const double* claw, double q, double v, double u,
                          double* dfdu) {
  const int id = (int)law[LAW_CREEP_FAMILY];
  if (!(q > 0.0) || !(v > 0.0) || id < 0 || id >= N_FAMILIES) {
    if (dfdu) *dfdu = 0.0;
    return 0.0;
  }
  return FAMILIES[id].force(law, claw, q, v, u, dfdu);
}

/* Sample the steady creep curve: adhesion CoA(s) = F/q and its slope dCoA/ds for n creepages. */
void cofgym_creep_curve(const double* law, const double* claw, double q, double v,
                        const double* creepage, int n, double* coa, double* slope) {
  for (int i = 0; i < n; i++) {
    double dfdu = 0.0;
    double f = cofgym_creep_force(law, claw, q, v, creepage[i] * v, &dfdu);
    coa[i] = f / q;
    slope[i] = dfdu * v / q;
  }
}

/* ---------------------------------------------------------------- helpers */

static uint32_t rng_next(double* ud) {
  /* xorshift64 kept as two exact 32-bit integers in doubles (userdata is copied as numbers) */
  uint64_t x = ((uint64_t)ud[UD_RNG_STATE0] << 32) | (uint64_t)ud[UD_RNG_STATE1];
  if (x == 0) x = 0x9E3779B97F4A7C15ull;
  x ^= x << 13;
  x ^= x >> 7;
  x ^= x << 17;
  ud[UD_RNG_STATE0] = (double)(uint32_t)(x >> 32);
  ud[UD_RNG_STATE1] = (double)(uint32_t)(x & 0xffffffffu);
  return (uint32_t)(x >> 32);
}

/* The vertical track profile at x (m): its height (m) and slope dz/dx, the sum of the userdata's cosines
 * (layout.py, TRACK_*; cof_gym/physics/track.py draws them). */
static void track_profile(const double* ud, double x, double* height, double* slope) {
  int n = (int)ud[UD_TRACK_N_WAVES];
  if (n > UD_MAX_TRACK_WAVES) n = UD_MAX_TRACK_WAVES;
  double h = 0.0, s = 0.0;
  for (int i = 0; i < n; i++) {
    double k = ud[UD_TRACK_WAVENUMBER_0 + i], a = ud[UD_TRACK_AMP_0 + i];
    double arg = k * x + ud[UD_TRACK_PHASE_0 + i];
    h += a * cos(arg);
    s -= a * k * sin(arg);
  }
  *height = h;
  *slope = s;
}

/* the wheelset-speed encoder (cof_gym/physics/encoder.py): the wheel's angle th from the reset by the trapezoid rule,
 * read at the apparent angle th + e sin th (e the target wheel's relative runout). Without pulses the reading is that
 * angle's rate, spin (1 + e cos th). With them, pulses come where the apparent angle passes a multiple of the pitch,
 * each pulse's time interpolated linearly within the step; the reading is one pitch over the last complete interval
 * between pulses (the period method), held until the next pulse, and the spin rate at the reset before two pulses.
 * Forward rotation only: a wheel turning back gives no pulse and holds the reading. */
static double encoder_reading(double* ud, double spin, double t, double dt, int first_step) {
  const double e = ud[UD_ENCODER_RUNOUT];
  if (first_step) {
    ud[UD_ENCODER_ANGLE] = 0.0;
    ud[UD_ENCODER_SPIN] = spin;
    ud[UD_ENCODER_PULSES_SEEN] = 0.0;
    ud[UD_ENCODER_READING] = spin * (1.0 + e);
    ud[UD_ENCODER_COUNT_ANGLE] = 0.0;
    return ud[UD_ENCODER_READING];
  }
  const double th0 = ud[UD_ENCODER_ANGLE];
  const double th1 = th0 + 0.5 * (ud[UD_ENCODER_SPIN] + spin) * dt;
  ud[UD_ENCODER_ANGLE] = th1;
  ud[UD_ENCODER_SPIN] = spin;
  if (ud[UD_ENCODER_PULSES] <= 0.0) {
    ud[UD_ENCODER_READING] = spin * (1.0 + e * cos(th1));
    ud[UD_ENCODER_COUNT_ANGLE] = th1 + e * sin(th1); /* the reading's integral */
    return ud[UD_ENCODER_READING];
  }
  const double pitch = 2.0 * PI / ud[UD_ENCODER_PULSES];
  const double s0 = th0 + e * sin(th0), s1 = th1 + e * sin(th1);
  const double n0 = floor(s0 / pitch), n1 = floor(s1 / pitch);
  if (n1 > n0) {
    const double rate = (s1 - s0) / dt; /* the apparent angle's rate over the step, rad/s */
    const double t_last = t - dt + (n1 * pitch - s0) / rate;
    if (n1 - n0 >= 2.0) { /* two pulses in the step: their interval is the pitch over the rate */
      ud[UD_ENCODER_READING] = rate;
    } else if (ud[UD_ENCODER_PULSES_SEEN] >= 1.0) {
      ud[UD_ENCODER_READING] = pitch / (t_last - ud[UD_ENCODER_PULSE_TIME]);
    }
    ud[UD_ENCODER_PULSE_TIME] = t_last;
    ud[UD_ENCODER_PULSES_SEEN] = fmin(2.0, ud[UD_ENCODER_PULSES_SEEN] + (n1 - n0));
    ud[UD_ENCODER_COUNT_ANGLE] = n1 * pitch;
  }
  return ud[UD_ENCODER_READING];
}

static double rng_normal(double* ud) {
  /* Box-Muller; (k + 0.5) / 2^32 keeps u1 in (0, 1) */
  double u1 = ((double)rng_next(ud) + 0.5) / 4294967296.0;
  double u2 = ((double)rng_next(ud) + 0.5) / 4294967296.0;
  return sqrt(-2.0 * log(u1)) * cos(2.0 * PI * u2);
}

/* transposed direct form II cascade of second-order sections, states updated in place */
static double sos_filter(const double* sos, double* state, int nsect, double x) {
  for (int k = 0; k < nsect; k++) {
    const double* c = sos + 5 * k;
    double* z = state + 2 * k;
    double y = c[0] * x + z[0];
    z[0] = c[1] * x - c[3] * y + z[1];
    z[1] = c[2] * x - c[4] * y;
    x = y;
  }
  return x;
}

/* accumulate basis b = [cos th, sin th, 1, tau]: B'B (10 unique entries) */
static void acc_btb(double* btb, const double* b) {
  int k = 0;
  for (int i = 0; i < 4; i++)
    for (int j = i; j < 4; j++) btb[k++] += b[i] * b[j];
}

static void acc_bty(double* bty, double* yty, const double* b, double y) {
  for (int i = 0; i < 4; i++) bty[i] += b[i] * y;
  *yty += y * y;
}

/* multi-tone lock-in: packed upper triangle of B'B and B'y for a basis of np columns */
static void acc_btb_n(double* btb, const double* b, int np) {
  int k = 0;
  for (int i = 0; i < np; i++)
    for (int j = i; j < np; j++) btb[k++] += b[i] * b[j];
}

static void acc_bty_n(double* bty, const double* b, int np, double y) {
  for (int i = 0; i < np; i++) bty[i] += b[i] * y;
}

static double dc_torque(const double* ud, double t) {
  double dur = ud[UD_RAMP_DURATION];
  double start = ud[UD_TORQUE_DC_START], target = ud[UD_TORQUE_DC_TARGET];
  double frac = dur > 0.0 ? (t - ud[UD_RAMP_START_TIME]) / dur : 1.0;
  if (frac >= 1.0) return target;
  if (frac <= 0.0) return start;
  return start + (target - start) * frac;
}

static double modulation_phase(const double* ud, double t) {
  return ud[UD_THETA_BASE] + ud[UD_MOD_OMEGA] * (t - ud[UD_TIME_BASE]);
}

/* Jacobian rows of a world point on a body over its chain of dofs (as mj_jac, sparse, only the rows
 * needed): x and z of the point's velocity and the angular velocity about y. Returns the count. */
#define MAX_CHAIN 64
typedef struct {
  int n;
  int dof[MAX_CHAIN];
  double x[MAX_CHAIN], z[MAX_CHAIN], ry[MAX_CHAIN];
} chain_jac;

static void point_jacobian(const mjModel* m, const mjData* d, int body, const double* point, chain_jac* j) {
  j->n = 0;
  while (body > 0 && m->body_dofnum[body] == 0) body = m->body_parentid[body];
  if (body <= 0) return;
  const double* com = d->subtree_com + 3 * m->body_rootid[body];
  double off[3] = {point[0] - com[0], point[1] - com[1], point[2] - com[2]};
  int i = m->body_dofadr[body] + m->body_dofnum[body] - 1;
  while (i >= 0 && j->n < MAX_CHAIN) {
    const double* c = d->cdof + 6 * i; /* [angular, linear] about the root's subtree com */
    j->dof[j->n] = i;
    j->x[j->n] = c[3] + c[1] * off[2] - c[2] * off[1];
    j->z[j->n] = c[5] + c[0] * off[1] - c[1] * off[0];
    j->ry[j->n] = c[1];
    j->n++;
    i = m->dof_parentid[i];
  }
}

static double chain_dot(const chain_jac* j, const double* row, const double* v) {
  double s = 0.0;
  for (int k = 0; k < j->n; k++) s += row[k] * v[j->dof[k]];
  return s;
}

static void chain_add(const chain_jac* j, const double* row, double scale, double* out) {
  for (int k = 0; k < j->n; k++) out[j->dof[k]] += row[k] * scale;
}

/* ---------------------------------------------------------------- the callback */

typedef struct {
  double normal;    /* N, whole contact */
  double omega;     /* rad/s */
  double speed;     /* m/s, wheel centre */
  double slip;      /* u = R Omega - v, m/s */
  double force;     /* applied tangential force, N (whole contact, + forward) */
  double creepage;
} contact_state;

/* Every body, dof and qpos index the userdata gives lies in the model (Python's BuiltModel checks them when it
 * is built, models.py; this keeps a userdata written otherwise from reading or writing past MuJoCo's arrays). */
static int indices_valid(const mjModel* m, const double* ud, int ncon) {
  const int mc = (int)ud[UD_MEASURED_CONTACT], cx = (int)ud[UD_CARBODY_X_DOF];
  if (mc < 0 || mc >= ncon || cx < -1 || cx >= m->nv) return 0;
  for (int k = 0; k < ncon; k++) {
    const double* cfg = ud + UD_CONTACT0 + k * UD_CONTACT_STRIDE;
    const int body = (int)cfg[CF_WHEEL_BODY], rb = (int)cfg[CF_REACTION_BODY];
    const int zq = (int)cfg[CF_Z_QPOS], zd = (int)cfg[CF_Z_DOF];
    if (body < 1 || body >= m->nbody || rb < -1 || rb >= m->nbody || zq < -1 || zq >= m->nq) return 0;
    if (zq >= 0 && (zd < 0 || zd >= m->nv)) return 0;
  }
  return 1;
}

void cofgym_passive(const mjModel* m, mjData* d) {
  if (m->nuserdata < UD_SIZE) return;
  double* ud = d->userdata;
  if (ud[UD_MAGIC] != UD_MAGIC_VALUE) return;

  const int nv = m->nv;
  const double dt = m->opt.timestep;
  const double t = d->time;
  const int advance = t != ud[UD_LAST_TIME];
  const int ncon = (int)ud[UD_N_CONTACTS];
  if (ncon < 1 || ncon > UD_MAX_CONTACTS || !indices_valid(m, ud, ncon)) return;

  /* scratch on the C stack (variable-length arrays: nv is small for these vehicles) */
  double tau[nv];       /* generalised forces we add */
  double jx[nv * ncon];     /* contact-point Jacobians along x, per contact */
  double minv_j[nv * ncon];  /* M^-1 J' per contact */
  double total[nv];
  double unit_torque[nv];   /* generalised force of a unit motor torque */
  mju_zero(tau, nv);
  mju_zero(unit_torque, nv);
  int reaction_done[UD_MAX_CONTACTS];

  /* drive: DC ramp + sine (+ tones 2..N_TONES) at mid-step (the torque acts over [t, t+dt]), first-order lag */
  const double t_mid = t + 0.5 * dt;
  const double theta_mid = modulation_phase(ud, t_mid);
  const double amp = ud[UD_TORQUE_AMPLITUDE], wm = ud[UD_MOD_OMEGA];
  const double sin_mid = sin(theta_mid), cos_mid = cos(theta_mid);
  double torque_cmd = dc_torque(ud, t_mid) + amp * sin_mid;
  /* tones 2..N_TONES (N_TONES <= 1: the single tone above, nothing below runs); a tone with zero
   * amplitude adds nothing to the torque (it is still fitted by the joint lock-in) */
  int ntones = (int)ud[UD_N_TONES];
  if (ntones > UD_MAX_TONES) ntones = UD_MAX_TONES;
  double tone_sin_mid[UD_MAX_TONES], tone_cos_mid[UD_MAX_TONES], extra_rate = 0.0;
  if (ntones > 1) {
    double extra_cmd = 0.0;
    for (int k = 1; k < ntones; k++) {
      const double* tb = ud + UD_TONE0 + (k - 1) * UD_TONE_STRIDE;
      const double th = tb[TONE_THETA_BASE] + tb[TONE_OMEGA] * (t_mid - ud[UD_TIME_BASE]);
      tone_sin_mid[k] = sin(th);
      tone_cos_mid[k] = cos(th);
      if (tb[TONE_AMPLITUDE] != 0.0) {
        extra_cmd += tb[TONE_AMPLITUDE] * tone_sin_mid[k];
        extra_rate += tb[TONE_AMPLITUDE] * tb[TONE_OMEGA] * tone_cos_mid[k];
      }
    }
    torque_cmd += extra_cmd;
  }
  const double tau_m = ud[UD_MOTOR_TAU];
  if (advance) {
    double alpha = tau_m > 0.0 ? 1.0 - exp(-dt / tau_m) : 1.0;
    ud[UD_MOTOR_TORQUE] += alpha * (torque_cmd - ud[UD_MOTOR_TORQUE]);
  }
  const double torque = ud[UD_MOTOR_TORQUE];
  double torque_rate; /* dM/dt at mid-step, N m/s */
  if (tau_m > 0.0) {
    torque_rate = (torque_cmd - torque) / tau_m;
  } else {
    double dur = ud[UD_RAMP_DURATION], since = t_mid - ud[UD_RAMP_START_TIME];
    double ramp = (dur > 0.0 && since > 0.0 && since < dur)
                      ? (ud[UD_TORQUE_DC_TARGET] - ud[UD_TORQUE_DC_START]) / dur : 0.0;
    torque_rate = ramp + amp * wm * cos_mid;
    if (ntones > 1) torque_rate += extra_rate;
  }

  contact_state cs[UD_MAX_CONTACTS];
  double dfdu[UD_MAX_CONTACTS];
  const double* law = ud + UD_LAW0;
  const double vmin = ud[UD_MIN_SPEED];

  /* pass 1: kinematics, normal load, motor torque, explicit creep force, as Jacobian-transpose
   * products over each wheel's dof chain */
  chain_jac cj[UD_MAX_CONTACTS];
  for (int k = 0; k < ncon; k++) reaction_done[k] = 0;
  mju_zero(jx, nv * ncon);
  for (int k = 0; k < ncon; k++) {
    double* cfg = ud + UD_CONTACT0 + k * UD_CONTACT_STRIDE;
    int body = (int)cfg[CF_WHEEL_BODY];
    double radius = cfg[CF_RADIUS];
    double nwheels = cfg[CF_N_WHEELS];
    double point[3] = {d->xpos[3 * body], d->xpos[3 * body + 1], d->xpos[3 * body + 2] - radius};
    chain_jac* J = cj + k;
    point_jacobian(m, d, body, point, J);
    double* jp = jx + nv * k;
    for (int i = 0; i < J->n; i++) jp[J->dof[i]] = J->x[i];
    double cvel = chain_dot(J, J->x, d->qvel);         /* contact-point velocity along x */
    double omega = chain_dot(J, J->ry, d->qvel);       /* spin about y */
    double speed = cvel + radius * omega;              /* wheel-centre velocity */
    double slip = -cvel;

    double normal;
    int zq = (int)cfg[CF_Z_QPOS], zd = (int)cfg[CF_Z_DOF];
    if (zq >= 0) {
      double rest = cfg[CF_Z_REST], zvel = d->qvel[zd];
      if (ud[UD_TRACK_N_WAVES] > 0.0) { /* the rail's height under the wheelset, moving past at its speed */
        double height, slope;
        track_profile(ud, d->xpos[3 * body], &height, &slope);
        rest += height;
        zvel -= speed * slope;
      }
      normal = cfg[CF_K_TRACK] * (rest - d->qpos[zq]) - cfg[CF_C_TRACK] * zvel;
      if (normal < 0.0) normal = 0.0; /* unilateral: the wheel may lift */
      chain_add(J, J->z, normal, tau);
    } else {
      normal = cfg[CF_NOMINAL_LOAD];
    }

    double sign = cfg[CF_TORQUE_SIGN];
    if (sign != 0.0) {
      chain_add(J, J->ry, sign, unit_torque);
      int rb = (int)cfg[CF_REACTION_BODY];
      if (rb >= 0 && !reaction_done[k]) {
        /* reaction on the motor's mount; contacts sharing the mount are summed first */
        double net = 0.0;
        for (int j = k; j < ncon; j++) {
          double* cjf = ud + UD_CONTACT0 + j * UD_CONTACT_STRIDE;
          if ((int)cjf[CF_REACTION_BODY] == rb && cjf[CF_TORQUE_SIGN] != 0.0) {
            net += cjf[CF_TORQUE_SIGN];
            reaction_done[j] = 1;
          }
        }
        if (net != 0.0) {
          chain_jac R;
          point_jacobian(m, d, rb, d->xpos + 3 * rb, &R);
          chain_add(&R, R.ry, -net, unit_torque);
        }
      }
    }

    double vref = fabs(speed) > vmin ? fabs(speed) : vmin;
    double q = normal / nwheels;
    double dfw = 0.0;
    double fw = cofgym_creep_force(law, cfg + CF_AB_REF, q, vref, slip, &dfw);
    double f = nwheels * fw;
    dfdu[k] = nwheels * (dfw > 0.0 ? dfw : 0.0); /* past the peak the law stays explicit */
    chain_add(J, J->x, f, tau);

    cs[k].normal = normal;
    cs[k].omega = omega;
    cs[k].speed = speed;
    cs[k].slip = slip;
    cs[k].force = f;
    cs[k].creepage = slip / vref;
  }

  /* cruise control: PI on the car body's speed with acceleration feedback (acceleration from the
   * previous steps), and the traction balance: the rest of the train cancels the interrogation's DC
   * torque (same ramp), so a DC step does not change the train's speed; the modulation is not cancelled */
  int cx = (int)ud[UD_CARBODY_X_DOF];
  if (cx >= 0) {
    double vb = d->qvel[cx];
    double err = ud[UD_CRUISE_SPEED] - vb;
    if (advance) {
      ud[UD_CARBODY_ACC] = ud[UD_LAST_TIME] >= 0.0 ? (vb - ud[UD_CARBODY_PREV_VEL]) / dt : 0.0;
      ud[UD_CARBODY_PREV_VEL] = vb;
      ud[UD_CRUISE_INTEGRAL] += err * dt;
    }
    tau[cx] += ud[UD_CRUISE_KP] * err + ud[UD_CRUISE_KI] * ud[UD_CRUISE_INTEGRAL]
               - ud[UD_CRUISE_KD] * ud[UD_CARBODY_ACC] - ud[UD_BALANCE_PER_NM] * dc_torque(ud, t_mid);
  }

  for (int i = 0; i < nv; i++) tau[i] += torque * unit_torque[i];

  /* pass 2: exponential integration of each contact's slip velocity u over the step.
   * Linearised, du/dt = a + b (t - t_mid) - lambda (u - u_n) with a = -J M^-1 (total force at
   * mid-step), b its rate from the drive torque and lambda = A F', A = J M^-1 J'. Exactly:
   *   du = dt [(a - b dt/2) phi1(z) + b dt phi2(z)],  z = lambda dt,
   * which tends to the explicit midpoint step for a soft contact (z -> 0) and to the quasi-static
   * creep balance at the step's end for a stiff one (z >> 1): stable and phase-accurate at any
   * creep stiffness. The creep force applied is the one that makes MuJoCo's Euler step give du. */
  /* x_k = M^-1 J_k' (one solve for all contacts): A = J x, a_u = -x . total, b_u = -x . unit torque */
  mju_add(total, d->qfrc_passive, tau, nv);
  mj_solveM(m, d, minv_j, jx, ncon);
  for (int k = 0; k < ncon; k++) {
    double* xk = minv_j + nv * k;
    double a_inv = chain_dot(cj + k, cj[k].x, xk);
    double a_u = -mju_dot(xk, total, nv);
    double b_u = -mju_dot(xk, unit_torque, nv) * torque_rate;
    double z = dt * a_inv * dfdu[k];
    double phi1, phi2;
    if (z < 1e-3) {
      phi1 = 1.0 - z / 2.0 + z * z / 6.0;
      phi2 = 0.5 - z / 6.0 + z * z / 24.0;
    } else {
      double em1 = expm1(-z);
      phi1 = -em1 / z;
      phi2 = (z + em1) / (z * z);
    }
    double du = dt * ((a_u - 0.5 * b_u * dt) * phi1 + b_u * dt * phi2);
    double df = (dt * a_u - du) / (dt * a_inv);
    chain_add(cj + k, cj[k].x, df, tau);
    cs[k].force += df;
  }
  mju_addTo(d->qfrc_passive, tau, nv);

  /* measurement chain: only once per physics step */
  if (advance) {
    const int first_step = ud[UD_LAST_TIME] < 0.0; /* LAST_TIME starts at -1 */
    ud[UD_LAST_TIME] = t;
    int mc = (int)ud[UD_MEASURED_CONTACT];
    const contact_state* c = cs + mc;
    const int rotation = ud[UD_LOCK_IN_ROTATION] > 0.0;
    const double omega_read = ud[UD_ENCODER_PULSES] > 0.0 || ud[UD_ENCODER_RUNOUT] > 0.0 || rotation
                                  ? encoder_reading(ud, c->omega, t, dt, first_step) : c->omega;
    double omega_meas = omega_read + (ud[UD_NOISE_OMEGA] > 0.0 ? ud[UD_NOISE_OMEGA] * rng_normal(ud) : 0.0);
    const double tau_e = ud[UD_ENCODER_TAU];
    if (tau_e > 0.0) {
      /* the encoder's speed signal through a first-order lag of time constant tau_e, started at the first
       * reading: the step's input held at the mean of this reading and the last (so the lag's delay is tau_e,
       * not tau_e - dt/2), the exact response to a held input over the step; every use of the encoder below
       * reads the lagged signal */
      const double held = first_step ? omega_meas : 0.5 * (omega_meas + ud[UD_OMEGA_PREVIOUS]);
      const double a = first_step ? 1.0 : 1.0 - exp(-dt / tau_e);
      ud[UD_OMEGA_PREVIOUS] = omega_meas;
      ud[UD_OMEGA_FILTERED] += a * (held - ud[UD_OMEGA_FILTERED]);
      omega_meas = ud[UD_OMEGA_FILTERED];
    }
    double speed_meas = c->speed + (ud[UD_NOISE_SPEED] > 0.0 ? ud[UD_NOISE_SPEED] * rng_normal(ud) : 0.0);
    double coa_true = c->normal > 0.0 ? c->force / c->normal : 0.0;
    double ft = c->force, fn = c->normal;
    if (ud[UD_NOISE_FORCE] > 0.0) {
      ft *= 1.0 + ud[UD_NOISE_FORCE] * rng_normal(ud);
      fn *= 1.0 + ud[UD_NOISE_FORCE] * rng_normal(ud);
    }
    double coa_meas = fn > 0.0 ? ft / fn : 0.0;
    double radius = ud[UD_CONTACT0 + mc * UD_CONTACT_STRIDE + CF_RADIUS];
    double creep_meas = fabs(speed_meas) > vmin ? radius * omega_meas / speed_meas - 1.0 : 0.0;

    /* comfort: car-body acceleration through ISO 2631 Wd and the band limit (jerk) */
    double a_wd = 0.0, jerk = 0.0;
    if (cx >= 0) {
      double acc = ud[UD_CARBODY_ACC];
      double band = sos_filter(ud + UD_BAND_SOS_0, ud + UD_BAND_STATE_0, (int)ud[UD_BAND_NSECT], acc);
      a_wd = sos_filter(ud + UD_WD_SOS_0, ud + UD_WD_STATE_0, (int)ud[UD_WD_NSECT], acc);
      jerk = (band - ud[UD_BAND_PREV]) / dt;
      ud[UD_BAND_PREV] = band;
      ud[UD_LAST_CARBODY_ACC] = acc;
    }

    ud[UD_LAST_OMEGA] = c->omega;
    ud[UD_LAST_SPEED] = c->speed;
    ud[UD_LAST_CREEPAGE] = c->creepage;
    ud[UD_LAST_COA] = coa_true;
    ud[UD_LAST_NORMAL] = c->normal;
    ud[UD_LAST_TORQUE] = torque;

    /* comfort over the whole window: passengers feel the settling part too */
    ud[UD_N_COMFORT_SAMPLES] += 1.0;
    ud[UD_SUM_WD2] += a_wd * a_wd;
    ud[UD_SUM_JERK2] += jerk * jerk;
    if (fabs(a_wd) > ud[UD_MAX_ABS_WD]) ud[UD_MAX_ABS_WD] = fabs(a_wd);

    if (t >= ud[UD_ACC_START_TIME]) {
      double t0 = ud[UD_ACC_START_TIME];
      /* basis at t = rotation of the mid-step basis by -wm dt/2 (cos and sin cached per frequency) */
      if (ud[UD_ROT_OMEGA] != wm) {
        ud[UD_ROT_OMEGA] = wm;
        ud[UD_ROT_COS] = cos(0.5 * wm * dt);
        ud[UD_ROT_SIN] = sin(0.5 * wm * dt);
      }
      const double ch = ud[UD_ROT_COS], sh = ud[UD_ROT_SIN];
      double b_mid[4] = {cos_mid, sin_mid, 1.0, t_mid - t0};
      double b_now[4] = {cos_mid * ch + sin_mid * sh, sin_mid * ch - cos_mid * sh, 1.0, t - t0};
      ud[UD_N_SAMPLES] += 1.0;
      acc_btb(ud + UD_BTB_TORQUE_0, b_mid);
      acc_bty(ud + UD_BTY_TORQUE_0, ud + UD_YTY_TORQUE, b_mid, torque);
      acc_btb(ud + UD_BTB_STATE_0, b_now);
      acc_bty(ud + UD_BTY_OMEGA_0, ud + UD_YTY_OMEGA, b_now, omega_meas);
      const double y_prev = ud[UD_LAG1_PREV_Y]; /* the previous sample's speed reading (lag-1 sums) */
      if (ud[UD_N_SAMPLES] > 1.0) { /* a previous sample of this window: the lag-1 cross sums */
        const double* b_prev = ud + UD_LAG1_PREV_B_0;
        ud[UD_LAG1_YY] += omega_meas * y_prev;
        for (int i = 0; i < 4; i++) {
          ud[UD_LAG1_BY_0 + i] += b_now[i] * y_prev;
          ud[UD_LAG1_PY_0 + i] += b_prev[i] * omega_meas;
          for (int j = 0; j < 4; j++) ud[UD_LAG1_BB_0 + 4 * i + j] += b_now[i] * b_prev[j];
        }
      }
      ud[UD_LAG1_PREV_Y] = omega_meas;
      for (int i = 0; i < 4; i++) ud[UD_LAG1_PREV_B_0 + i] = b_now[i];
      acc_bty(ud + UD_BTY_CREEP_0, ud + UD_YTY_CREEP, b_now, c->creepage);
      acc_bty(ud + UD_BTY_CREEP_MEASURED_0, ud + UD_YTY_CREEP_MEASURED, b_now, creep_meas);
      if (ntones > 1 || rotation) {
        /* joint basis [cos th_1, sin th_1, ..., cos th_K, sin th_K, (cos phi, sin phi, cos 2 phi, sin 2 phi,) 1,
         * tau]; tone 1 as above, phi the encoder's counted angle where the rotation lock-in takes its ripple out */
        double mt_mid[UD_MT_MAX_BASIS], mt_now[UD_MT_MAX_BASIS];
        const int np = 2 * ntones + (rotation ? UD_ROTATION_BASIS : 0) + 2;
        mt_mid[0] = b_mid[0]; mt_mid[1] = b_mid[1];
        mt_now[0] = b_now[0]; mt_now[1] = b_now[1];
        for (int k = 1; k < ntones; k++) {
          const double* tb = ud + UD_TONE0 + (k - 1) * UD_TONE_STRIDE;
          const double th = tb[TONE_THETA_BASE] + tb[TONE_OMEGA] * (t - ud[UD_TIME_BASE]);
          mt_mid[2 * k] = tone_cos_mid[k];
          mt_mid[2 * k + 1] = tone_sin_mid[k];
          mt_now[2 * k] = cos(th);
          mt_now[2 * k + 1] = sin(th);
        }
        if (rotation) { /* the counted angle at the step's start, for the torque's basis too (it has no such ripple):
                         * its first and second harmonics (a runout's ripple, and the period method's e^2 term) */
          const double phi = ud[UD_ENCODER_COUNT_ANGLE];
          for (int h = 0; h < UD_ROTATION_BASIS / 2; h++) {
            mt_mid[2 * (ntones + h)] = mt_now[2 * (ntones + h)] = cos((h + 1) * phi);
            mt_mid[2 * (ntones + h) + 1] = mt_now[2 * (ntones + h) + 1] = sin((h + 1) * phi);
          }
        }
        mt_mid[np - 2] = 1.0; mt_mid[np - 1] = b_mid[3];
        mt_now[np - 2] = 1.0; mt_now[np - 1] = b_now[3];
        acc_btb_n(ud + UD_MT_BTB_TORQUE_0, mt_mid, np);
        acc_bty_n(ud + UD_MT_BTY_TORQUE_0, mt_mid, np, torque);
        acc_btb_n(ud + UD_MT_BTB_STATE_0, mt_now, np);
        acc_bty_n(ud + UD_MT_BTY_OMEGA_0, mt_now, np, omega_meas);
        acc_bty_n(ud + UD_MT_BTY_CREEP_0, mt_now, np, c->creepage);
        acc_bty_n(ud + UD_MT_BTY_CREEP_MEASURED_0, mt_now, np, creep_meas);
        if (rotation) { /* the joint basis's lag-1 cross sums (the single tone's above hold the plain fit's) */
          double* prev_b = ud + UD_MT_LAG1_PREV_B_0;
          if (ud[UD_N_SAMPLES] > 1.0) {
            for (int i = 0; i < np; i++) {
              ud[UD_MT_LAG1_BY_0 + i] += mt_now[i] * y_prev;
              ud[UD_MT_LAG1_PY_0 + i] += prev_b[i] * omega_meas;
              for (int j = 0; j < np; j++) ud[UD_MT_LAG1_BB_0 + np * i + j] += mt_now[i] * prev_b[j];
            }
          }
          for (int i = 0; i < np; i++) prev_b[i] = mt_now[i];
        }
      }
      {
        /* synchronous average of the measured CoA: its bin of tone 1's phase at the step's start */
        int bin = (int)floor((atan2(b_now[1], b_now[0]) + PI) * (UD_PHASE_BINS / (2.0 * PI)) + 0.5);
        if (bin >= UD_PHASE_BINS) bin -= UD_PHASE_BINS;  /* the bin centred on -pi wraps round */
        ud[UD_COA_BIN_N_0 + bin] += 1.0;
        ud[UD_COA_BIN_SUM_0 + bin] += coa_meas;
        ud[UD_COA_BIN_SUM2_0 + bin] += coa_meas * coa_meas;
      }
      ud[UD_SUM_COA_MEASURED] += coa_meas;
      ud[UD_SUM_COA_TRUE] += coa_true;
      ud[UD_SUM_CREEPAGE] += c->creepage;
      ud[UD_SUM_CREEPAGE_MEASURED] += creep_meas;
      ud[UD_SUM_SPEED_MEASURED] += speed_meas;
      ud[UD_SUM_NORMAL] += c->normal;
      ud[UD_SUM_NORMAL_MEASURED] += fn;
      ud[UD_SUM_TANGENTIAL] += c->force;
      ud[UD_SUM_TANGENTIAL_MEASURED] += ft;
      ud[UD_SUM_TORQUE] += torque;
      if (fabs(torque) > ud[UD_MAX_ABS_TORQUE]) ud[UD_MAX_ABS_TORQUE] = fabs(torque);
      int past_peak = 0;
      for (int k = 0; k < ncon; k++) {
        double power = fabs(cs[k].force * cs[k].slip);
        ud[UD_FRICTION_ENERGY] += power * dt;
        double as = fabs(cs[k].creepage);
        if (as > ud[UD_MAX_ABS_CREEPAGE]) ud[UD_MAX_ABS_CREEPAGE] = as;
        if (as > ud[UD_S_PEAK]) {
          past_peak = 1;
          ud[UD_ENERGY_PAST_PEAK] += power * dt;
        }
      }
      if (past_peak) ud[UD_TIME_PAST_PEAK] += dt;
    }
  }
}
