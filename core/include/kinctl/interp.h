/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/interp.h - single-segment interpolators, planned once and evaluated
 * at integer ticks: the joint move of seed 001 lab 4, the Cartesian straight
 * line of lab 5 and the circular arc of lab 6.
 *
 * Every segment works the same way. A caller-owned plan struct is filled by
 * kc_interp_<kind>_plan(...), which validates every input and returns a
 * kc_status, leaving the plan untouched on error. The plan holds one
 * kinctl/profile.h profile of the fraction u of the segment (0 at the start,
 * 1 at the end) and the geometry; kc_interp_<kind>_eval(plan, k, out) gives
 * the setpoint at tick k (t = k dt, dt fixed at planning) in O(1) time with
 * no allocation. The duration in ticks is plan->ticks: eval returns
 * KC_OK for k < ticks and KC_DONE from then on, with the state exactly at
 * the segment's end (target position, velocity and acceleration zero). eval
 * is pure and safe to call in the control cycle and from several threads on
 * one plan; planning is bounded (no loop runs longer than KC_MAX_JOINTS,
 * except a jerk-limited joint move's root searches, each bounded by
 * KC_SCURVE_MAX_ITER, kinctl/scurve.h) and allocation-free, so it is
 * cycle-safe too, though it costs more (trig functions and square roots).
 *
 * Speed laws. The fraction u follows a trapezoid (triangle when short) from
 * rest to rest, with the limits of u chosen so that every physical limit
 * holds: for a quantity that moves by D over the segment with limits
 * (vmax, amax), u' <= vmax / D and u'' <= amax / D, and u takes the
 * smallest of these bounds. Where one quantity binds, this is exactly the
 * seed's trapezoid on it (lab 4 eqs. 4.6-4.12, see kinctl/profile.h). The
 * joint move may instead be jerk-limited (kc_interp_joint_plan_cfg,
 * kinctl/scurve.h), and so may lines and arcs: given a finite jerk limit,
 * u follows a jerk-limited profile (kc_scurve) with u''' <= jmax / D too.
 *
 * Units: positions in m (joint moves: rad or m per joint), times in s,
 * angles in rad; everything in the base frame unless said otherwise.
 * Quaternions are (w, x, y, z), Hamilton product (kinctl/se3.h).
 */
#ifndef KINCTL_INTERP_H
#define KINCTL_INTERP_H

#include <stdint.h>

#include "kinctl/chain.h"
#include "kinctl/decls.h"
#include "kinctl/profile.h"
#include "kinctl/scurve.h"

KC_BEGIN_DECLS

/*
 * Three points are taken as collinear when the sine of the angle at the
 * start point between the chords to the via and end points is at most this:
 * the circumcentre then carries a relative error of about eps / sin, i.e.
 * 1e-8 in double (radius up to 1e8 chords) and 1e-3 in float.
 */
#ifdef KC_REAL_FLOAT
#define KC_INTERP_TOL_COLLINEAR KC_R(1e-4)
#else
#define KC_INTERP_TOL_COLLINEAR KC_R(1e-8)
#endif

/* ======================================================================
 * Joint move (seed 001 lab 4): every joint starts and ends together and at
 * every tick has covered the same fraction u of its own move:
 *     dq_i = q1_i - q0_i                      (4.1)
 *     q_i(t) = q0_i + dq_i u(t),  qd_i = dq_i u',  qdd_i = dq_i u''
 * which is the seed's q_i = q0_i + K_i s(t) (4.3, 4.10-4.12) with
 * K_i = dq_i / q_lead and s = q_lead u. The seed assumes equal limits for
 * all joints and takes the joint with the largest |dq_i| as the leading one
 * (4.2); here each joint keeps its own limits: the common profile of u uses
 *     u' <= V = min_i qd_max_i / |dq_i|,   u'' <= A = min_i qdd_max_i / |dq_i|
 * (joints that do not move impose nothing), so no joint exceeds either of
 * its limits and the move is the fastest one of this shape. The leading
 * joint is the one whose own time-optimal move is longest; when a single
 * joint sets both V and A (always so with equal limits) the common profile
 * is exactly its trapezoid, as in the seed, otherwise it is somewhat longer.
 * ====================================================================== */

/* The motion law of a joint move: seed 001 lab 4's trapezoid (the
 * default for now), or jerk-limited (kinctl/scurve.h). */
typedef enum kc_profile_kind { KC_PROFILE_TRAPEZOID = 0, KC_PROFILE_JERK = 1 } kc_profile_kind;

/* How the joints of a jerk-limited move are synchronised (see
 * kc_interp_joint_plan_cfg). */
typedef enum kc_interp_sync { KC_INTERP_SYNC_PHASE = 0, KC_INTERP_SYNC_TIME = 1 } kc_interp_sync;

typedef struct kc_interp_joint {
    int n;                                            /* joints */
    kc_real q0[KC_MAX_JOINTS], q1[KC_MAX_JOINTS];     /* start, end */
    kc_real dq[KC_MAX_JOINTS];                        /* q1 - q0 (4.1) */
    int lead;     /* leading joint (0-based; ties: lowest index), -1 if nothing moves */
    int lead_vel; /* joint whose velocity limit sets V, -1 if nothing moves */
    int lead_acc; /* joint whose acceleration limit sets A, -1 if nothing moves */
    kc_profile prof; /* u from 0 to 1 (the trapezoid; all zero for a jerk-limited move) */
    /* The bounds of u' and u'' the profile was planned with (1/s, 1/s^2;
     * infinite for a zero motion): a stop on the path uses u_amax. */
    kc_real u_vmax, u_amax;
    kc_profile_kind kind; /* the motion law */
    /* Both kinds: the duration (s) and in ticks (every joint starts on tick
     * 0 and is at rest on its target from tick `ticks` on). */
    kc_real T;
    int64_t ticks;
    /* Jerk-limited only: the synchronisation; with KC_INTERP_SYNC_PHASE the
     * profile su of u (a straight line, as the trapezoid), with
     * KC_INTERP_SYNC_TIME one profile of q per joint, sj[i]. */
    kc_interp_sync sync;
    kc_real u_jmax; /* the bound of the third derivative of u (1/s^3) */
    kc_scurve su;
    kc_scurve sj[KC_MAX_JOINTS];
} kc_interp_joint;

typedef struct kc_interp_joint_state {
    kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS], qdd[KC_MAX_JOINTS];
    /* Jerk (rad/s^3 or m/s^3) of a jerk-limited move; 0 for the trapezoid,
     * whose jerk is impulses at its phase changes. */
    kc_real qddd[KC_MAX_JOINTS];
    /* Fraction of the move and its rates (1/s, 1/s^2); with time
     * synchronisation, the leading joint's. */
    kc_real u, ud, udd;
    int phase; /* 1 accelerate, 2 cruise, 3 brake, 4 finished */
} kc_interp_joint_state;

/* A joint move's request for kc_interp_joint_plan_cfg. */
typedef struct kc_interp_joint_cfg {
    int n;                                        /* joints, 1..KC_MAX_JOINTS */
    kc_real q0[KC_MAX_JOINTS], q1[KC_MAX_JOINTS]; /* start, end (rad or m) */
    /* Limits per joint, > 0; qd_max may be +infinity; qddd_max is used by
     * the jerk-limited kind only (finite there). */
    kc_real qd_max[KC_MAX_JOINTS], qdd_max[KC_MAX_JOINTS], qddd_max[KC_MAX_JOINTS];
    /* Start velocity and acceleration (jerk-limited kind only; zero, the
     * default, for a start at rest). */
    kc_real qd0[KC_MAX_JOINTS], qdd0[KC_MAX_JOINTS];
    kc_real duration;        /* 0: as fast as the limits allow; or a longer time (s) */
    kc_real dt;              /* tick period (s), > 0 */
    kc_profile_kind profile; /* KC_PROFILE_TRAPEZOID by default */
} kc_interp_joint_cfg;

/* n = 0 and every q 0, qd_max +infinity, qdd_max and qddd_max 0 (set
 * them), duration 0, dt 0 (set it), the trapezoid. */
kc_interp_joint_cfg kc_interp_joint_cfg_default(void);

/* Plans a joint move of n joints (1..KC_MAX_JOINTS) from q0 to q1 (rad or
 * m) with per-joint limits qd_max (> 0, +infinity allowed) and qdd_max
 * (> 0, finite). duration (s): 0 for the fastest move, or a longer time to
 * stretch it to (kinctl/profile.h: acceleration kept, cruise lowered; for
 * synchronising with other axes). dt > 0: tick period (s).
 * Returns KC_OK; KC_E_ARG for NULL pointers, n < 1, a non-finite q, a bad
 * limit, a negative or non-finite duration or a bad dt; KC_E_CAPACITY for
 * n > KC_MAX_JOINTS or a move longer than KC_PROFILE_MAX_TICKS ticks;
 * KC_E_LIMIT when duration is shorter than the limits allow. Limits on q
 * itself are the caller's business (kc_chain_check_q): a straight line in
 * joint space stays inside a box of position limits when both ends do. */
kc_status kc_interp_joint_plan(kc_interp_joint *plan, int n, const kc_real *q0, const kc_real *q1,
                               const kc_real *qd_max, const kc_real *qdd_max, kc_real duration, kc_real dt);

/* Plans a joint move from a request: KC_PROFILE_TRAPEZOID is exactly
 * kc_interp_joint_plan. KC_PROFILE_JERK: every joint's time-optimal
 * jerk-limited move (kinctl/scurve.h, rest to rest) with its own qd_max,
 * qdd_max and qddd_max; the move lasts T, the longest of these (or the
 * requested duration, if longer), and every joint starts on tick 0 and
 * arrives on the same tick. Two ways to synchronise, tried in order (as
 * Ruckig's phase and time synchronisation, Berscheid & Kroeger 2021):
 *   phase: one jerk-limited profile of u from 0 to 1 with the bounds
 *     min_i qd_max_i / |dq_i|, min_i qdd_max_i / |dq_i| and
 *     min_i qddd_max_i / |dq_i| on its three derivatives: a straight line
 *     in joint space like the trapezoid's, taken when it lasts no longer
 *     than T (always so with equal limits: the leading joint sets all
 *     three bounds);
 *   time: each joint's own profile stretched to T (amax and jmax kept,
 *     cruise lowered): not a straight line, but each joint moves
 *     monotonically from q0_i to q1_i, so a box of position limits that
 *     holds both ends holds the move.
 * From a moving start (qd0, qdd0 not all zero): time synchronisation,
 * every joint's own profile from its start state (kinctl/scurve.h) to
 * rest at q1_i, stretched to T, the longest optimum, by
 * kc_scurve_plan_duration_from, which reaches every duration from a
 * joint's optimum on (a slower cruise, a slower stop, or the optimum and
 * a rest on the target). Only where a joint would need that rest after an
 * optimum of seven phases (KC_E_LIMIT: not seen in random tests) does T
 * grow past it, by 2^m / 1024 of itself, m = 0..15, until every joint
 * plans (KC_E_LIMIT if none does), the step then halved ten times between
 * the last refused and the first planned duration, so T exceeds the first
 * reachable one by at most 2^(m-10) / 1024 of itself. A start moving
 * along the line to the target (qd0 and qdd0
 * both multiples of q1 - q0, within the rounding of that difference: a
 * replacing goal with the target of a move on its line) may instead stay
 * on the line, by phase: one profile of u from (0, u', u'') to rest at 1
 * within the bounds on u's derivatives, taken when it is shorter (only
 * where a stretch is refused); its start is the given state within the
 * rounding of one product. Each joint stays within its
 * limits as far as its start allows (kinctl/scurve.h).
 * Returns as kc_interp_joint_plan; KC_E_ARG also for a NULL cfg, an
 * unknown kind, a non-finite start velocity or acceleration, a moving
 * start with the trapezoid, or (jerk) a qddd_max of a joint that moves and
 * is not > 0 and finite. plan is untouched on error. */
kc_status kc_interp_joint_plan_cfg(kc_interp_joint *plan, const kc_interp_joint_cfg *cfg);

/* Setpoint at tick k >= 0: KC_OK while moving, KC_DONE from plan->ticks
 * on (q = q1 exactly, qd = qdd = qddd = 0), KC_E_ARG for NULL arguments or
 * k < 0. Writes the first plan->n entries of each array. */
kc_status kc_interp_joint_eval(const kc_interp_joint *plan, int64_t k, kc_interp_joint_state *out);

/* The move's geometry driven by another profile of u (for instance one
 * that stops on the path, kc_profile_plan_stop, or resumes from there): the
 * state at that profile's tick k. The end state is exact when the profile
 * ends at u = 1. For a straight line: the trapezoid, or a jerk-limited
 * move synchronised by phase. Return codes as kc_profile_eval. */
kc_status kc_interp_joint_eval_profile(const kc_interp_joint *plan, const kc_profile *prof, int64_t k,
                                       kc_interp_joint_state *out);

/* As kc_interp_joint_eval_profile, driven by a jerk-limited profile of u
 * (for instance kc_scurve_plan_stop of a straight jerk-limited move): q,
 * qd, qdd and qddd are dq times u and its derivatives; the end is exact
 * when the profile ends at u = 1. Return codes as kc_scurve_eval. */
kc_status kc_interp_joint_eval_scurve(const kc_interp_joint *plan, const kc_scurve *prof, int64_t k,
                                      kc_interp_joint_state *out);

/* ======================================================================
 * Cartesian segments: limits and the setpoint.
 * ====================================================================== */

/* Limits of a Cartesian segment. v and a bound the speed and the
 * acceleration of the tool point along its path (m/s, m/s^2; a finite);
 * w and dw bound the tool's angular speed and angular acceleration (rad/s,
 * rad/s^2), +infinity meaning unlimited: the seed's methods, where the
 * orientation simply follows the path parameter. j and dj bound the jerk
 * of the tool point along its path (m/s^3) and the tool's angular jerk
 * (rad/s^3); both infinite (the default) give the seed's trapezoid, and a
 * finite one a jerk-limited speed law (see the line's "Speed law"). All
 * must be > 0. */
typedef struct kc_interp_limits {
    kc_real v, a;
    kc_real w, dw;
    kc_real j, dj;
} kc_interp_limits;

/* Angular limits and jerk limits off (infinite), v and a zero: set them
 * before planning. */
kc_interp_limits kc_interp_limits_default(void);

/* The default jerk limit of a Cartesian motion, where a caller needs one
 * and none is given: this many times its acceleration limit (1/s), i.e.
 * the acceleration builds up in a tenth of a second (the controller's
 * cart_jerk and cart_angular_jerk defaults, kinctl-calc interp line and
 * arc). */
#define KC_INTERP_JERK_PER_ACCEL KC_R(10.0)

/* Setpoint of a Cartesian segment. */
typedef struct kc_interp_cart_state {
    kc_vec3 p;          /* tool position (m) */
    kc_quat q;          /* tool orientation; sign continuous along the segment */
    kc_vec3 v;          /* linear velocity of the tool point (m/s) */
    kc_vec3 w;          /* angular velocity (rad/s) */
    kc_real s, sd, sdd; /* path length so far (m) and its first two time derivatives;
                           for a pure rotation (no path) the rotation angle (rad) */
    kc_real u;          /* fraction of the segment done, 0..1 */
    int phase;          /* 1 accelerate, 2 cruise, 3 brake, 4 finished */
} kc_interp_cart_state;

/* ======================================================================
 * Straight line (seed 001 lab 5) from pose P1 to pose P2.
 *
 * Position: P3 = P1^-1 P2 (5.1), S = |p3| (5.7); the tool point moves on the
 * segment p(u) = p1 + u (p2 - p1), which is P1 T_j with x_3j = K_x S_j
 * etc. (5.8-5.13), S_j = S u.
 *
 * Orientation, KC_INTERP_TWO_ROTATIONS (the seed's method, 5.14-5.25): with
 * n, o, a the columns of R3 = R1^T R2,
 *     psi   = atan2(a_y, a_x) in [-pi, pi), 0 when a_x = a_y = 0    (5.18)
 *     theta = atan2(sqrt(a_x^2 + a_y^2), a_z) in [0, pi]            (5.19)
 *     phi   = atan2(S_phi, C_phi) in [-pi, pi)                      (5.20)
 *     S_phi = -s_psi c_psi V n_x + (c_psi^2 V + c_theta) n_y - s_psi s_theta n_z
 *     C_phi = -s_psi c_psi V o_x + (c_psi^2 V + c_theta) o_y - s_psi s_theta o_z
 *             (5.21), V = 1 - cos(theta)
 *     R(u) = R1 Ra(psi, theta u) Rz(phi u)          (5.16, 5.24-5.25)
 * where Ra(psi, x) turns by x about (-sin psi, cos psi, 0) (5.14). Typos
 * fixed (vectors/README.md): (5.14) element (3,3) is cos(theta), not
 * cos(psi) (#15); (5.21) needs the minus signs on the s_psi c_psi V terms
 * (#16); (5.17) is n = o x a (#17); theta = pi is reachable, so the range is
 * [0, pi] (#22). theta u and phi u are the seed's K_theta S_j and K_phi S_j
 * (5.22-5.25). The tool turns about the first axis and about its own z at
 * once, at angular speed |w| = u' sqrt(theta^2 + phi^2) (the two axes are
 * perpendicular).
 *
 * Orientation, KC_INTERP_SLERP: R(u) = R1 Rot(k, alpha u), k and alpha in
 * [0, pi] from R1^T R2 (the short way; at exactly pi either way is short
 * and the axis is the one R1^T R2's quaternion gives). |w| = u' alpha.
 *
 * Speed law: trapezoid on u with u' <= min(v / S, w / Theta) and
 * u'' <= min(a / S, dw / Theta), Theta = sqrt(theta^2 + phi^2) or alpha;
 * with w = dw = infinity this is the seed's trapezoid on the path length S
 * (5.3-5.7.3). With a finite jerk bound
 *     u''' <= J = min(j / S, dj / Theta)
 * (terms with an infinite limit, or a zero S or Theta, impose nothing) u
 * instead follows the time-optimal jerk-limited profile from rest at 0 to
 * rest at 1 (kinctl/scurve.h, rest to rest, with vmax = V, amax = A,
 * jmax = J: seven phases, fewer when short): s = S u keeps
 * |s'| <= v, |s''| <= a and |s'''| <= j, the rotation angle Theta u keeps
 * w, dw and dj (the jerk changes s'' by at most j dt per tick,
 * kinctl/scurve.h); kind is KC_PROFILE_JERK and su holds the profile. J
 * infinite (j = dj = infinity, the default; or a pure rotation without
 * dj) is the trapezoid, exactly as the seed's (kind
 * KC_PROFILE_TRAPEZOID, prof). A stop on the path from a moving state
 * (kc_scurve_plan_stop of (u, u', u'') within u_amax and u_jmax) and a
 * resume (kc_scurve_plan from rest at u to 1) drive the same geometry
 * through kc_interp_line_eval_scurve. dw bounds the part of the angular
 * acceleration along the angular velocity; two rotations also turn the
 * velocity's direction, adding u'^2 |theta phi| that dw does not bound
 * (slerp has no such term); likewise dj bounds the angular jerk along it.
 *
 * Degenerate cases: a_x = a_y = 0 sets psi = 0 as the seed says (theta is
 * then 0 or pi). A pure rotation (S = 0, seed's K_theta = theta / S
 * undefined, #22) runs its speed law on the rotation measure Theta with
 * the limits w and dw, which must then be finite; s, sd and sdd report the
 * angle turned (rad). A rotation of at most 16 units of roundoff counts as
 * none: with S = 0 too the segment is a zero motion of 0 ticks.
 * ====================================================================== */

typedef enum kc_interp_orient {
    KC_INTERP_TWO_ROTATIONS = 0, /* seed 001 lab 5 */
    KC_INTERP_SLERP = 1          /* quaternion spherical interpolation */
} kc_interp_orient;

typedef struct kc_interp_line {
    kc_vec3 p1, p2;          /* start and end position (m) */
    kc_vec3 dp;              /* p2 - p1 */
    kc_real length;          /* S (m) */
    kc_quat q1, q2;          /* start and end orientation (q2's sign as the path ends) */
    kc_mat3 R1;              /* start rotation */
    kc_interp_orient orient; /* method */
    kc_real psi, theta, phi; /* two rotations (5.18-5.21), rad */
    kc_vec3 k1;              /* two rotations: first axis (-sin psi, cos psi, 0) in the start frame */
    kc_vec3 axis;            /* slerp: unit axis in the start frame */
    kc_real angle;           /* Theta: sqrt(theta^2 + phi^2), or slerp's angle (rad) */
    kc_profile prof;         /* u from 0 to 1 (the trapezoid; all zero when jerk-limited) */
    /* The bounds of u', u'' and u''' the profile was planned with (1/s,
     * 1/s^2, 1/s^3; infinite for a zero motion, u_jmax for the
     * trapezoid): a stop on the path uses u_amax (and u_jmax). */
    kc_real u_vmax, u_amax, u_jmax;
    kc_profile_kind kind; /* the speed law: trapezoid (prof) or jerk-limited (su) */
    kc_scurve su;         /* u from 0 to 1 when jerk-limited (all zero otherwise) */
    kc_real T;            /* duration (s), either kind */
    int64_t ticks;        /* duration in ticks: at the end from this tick on */
} kc_interp_line;

/* Plans a line from `from` to `to` (rotations orthonormal within
 * KC_TOL_ORTHONORMAL, positions finite), with limits lim and the orientation
 * method orient; dt > 0 the tick period (s). Returns KC_OK; KC_E_ARG for a
 * NULL pointer, a non-finite or non-rigid pose, an unknown method, a bad
 * limit or dt, or a pure rotation with an infinite dw; KC_E_CAPACITY when
 * the segment exceeds KC_PROFILE_MAX_TICKS ticks or S overflows. */
kc_status kc_interp_line_plan(kc_interp_line *plan, const kc_pose *from, const kc_pose *to,
                              const kc_interp_limits *lim, kc_interp_orient orient, kc_real dt);

/* Setpoint at tick k >= 0: KC_OK while moving, KC_DONE from
 * plan->ticks on (exactly the end pose: p2, q2; velocities zero),
 * KC_E_ARG for NULL arguments or k < 0 (out untouched). */
kc_status kc_interp_line_eval(const kc_interp_line *plan, int64_t k, kc_interp_cart_state *out);

/* As kc_interp_joint_eval_profile, for the line. */
kc_status kc_interp_line_eval_profile(const kc_interp_line *plan, const kc_profile *prof, int64_t k,
                                      kc_interp_cart_state *out);

/* As kc_interp_joint_eval_scurve, for the line: its geometry driven by a
 * jerk-limited profile of u (the stop on the path, kc_scurve_plan_stop
 * from (u, u', u''), or a resume from there to 1). Return codes as
 * kc_scurve_eval. */
kc_status kc_interp_line_eval_scurve(const kc_interp_line *plan, const kc_scurve *prof, int64_t k,
                                     kc_interp_cart_state *out);

/* ======================================================================
 * Arc (seed 001 lab 6) from pose T1 through the via point T2 to the end
 * point T3 (positions; the orientation follows the arc).
 *
 * The circle through the three points: with a = T2 - T1, b = T3 - T1 and
 * m = a x b, the centre is c = T1 + (|a|^2 b x m + |b|^2 m x a) / (2 |m|^2),
 * R = |T1 - c|, and the unit normal N = m / |m| makes T1 -> T2 -> T3
 * counter-clockwise (this replaces 6.3-6.17; the seed's centre formulas and
 * normal-sign rule are garbled or undefined, vectors/README.md #23-25). The
 * swept angle alpha is the counter-clockwise angle from T1 to T3 about N,
 * in (0, 2 pi): the arc that passes through T2, whose own angle lies in
 * (0, alpha). The seed's alpha = atan(Y_L / X_L) in (-pi, pi] (6.21) takes
 * the short arc whether or not it passes T2, wrong beyond 180 degrees (#26).
 *
 * Pose: T(alpha_i) = P Rz(alpha_i) I (6.1, 6.19) with P the circle's frame
 * (origin c, x towards T1, z = N) and I = P^-1 T1: the tool turns with the
 * arc, keeping its orientation relative to the tangent (the text says the
 * tool keeps its orientation, but 6.1 rotates it; 6.1 is followed, #30):
 *     p = c + cos(alpha_i) r + sin(alpha_i) N x r,   r = T1 - c,
 *     q = (cos(alpha_i / 2), sin(alpha_i / 2) N) q1.
 *
 * Speed law on the angle (6.23-6.25 corrected, #27): the lab 4 trapezoid on
 * alpha with omega = v / R and epsilon = a / R, further bounded by w and dw
 * (the tool turns at alpha'), run on u = alpha_i / alpha; with a finite
 * jerk limit the line's jerk-limited law on the same measures, u''' <=
 * min(j / (R alpha), dj / alpha). a bounds the
 * tangential acceleration only, as in the seed: the centripetal part
 * (R alpha'^2 = v^2 / R at speed v) is not limited; lower v to
 * sqrt(a_n R) to bound it by a_n. s = R alpha_i.
 *
 * Rejected: coincident or collinear points (sine of the angle at T1 at most
 * KC_INTERP_TOL_COLLINEAR): KC_E_SINGULAR, as no circle or more than one
 * passes through them. A full circle (T3 = T1) is two arcs.
 * ====================================================================== */

typedef struct kc_interp_arc {
    kc_vec3 centre;    /* c (m) */
    kc_vec3 normal;    /* N, unit: the motion is counter-clockwise about it */
    kc_vec3 r, nr;     /* T1 - c and N x (T1 - c) */
    kc_real radius;    /* R (m) */
    kc_real angle;     /* swept angle alpha in (0, 2 pi) */
    kc_real angle_via; /* where the via point is passed, in (0, angle) */
    kc_real length;    /* R alpha (m) */
    kc_vec3 p1, p3;    /* start and end position */
    kc_quat q1, q3;    /* start orientation, and the end orientation by (6.1) */
    kc_profile prof;   /* u = alpha_i / alpha from 0 to 1 (the trapezoid) */
    /* As the line's: the bounds of u's derivatives, the speed law, the
     * jerk-limited profile, the duration. */
    kc_real u_vmax, u_amax, u_jmax;
    kc_profile_kind kind;
    kc_scurve su;
    kc_real T;
    int64_t ticks;
} kc_interp_arc;

/* Plans an arc from `from` through `via` to `to` (positions in m) with
 * limits lim; dt > 0 the tick period (s). Returns KC_OK; KC_E_ARG for a NULL
 * pointer, a non-finite or non-rigid pose, a non-finite point, a bad limit
 * or dt; KC_E_SINGULAR for coincident or collinear points; KC_E_CAPACITY
 * when the segment exceeds KC_PROFILE_MAX_TICKS ticks. */
kc_status kc_interp_arc_plan(kc_interp_arc *plan, const kc_pose *from, const kc_vec3 *via, const kc_vec3 *to,
                             const kc_interp_limits *lim, kc_real dt);

/* Setpoint at tick k >= 0: KC_OK while moving, KC_DONE from
 * plan->ticks on (exactly p3 and q3, velocities zero), KC_E_ARG for
 * NULL arguments or k < 0 (out untouched). */
kc_status kc_interp_arc_eval(const kc_interp_arc *plan, int64_t k, kc_interp_cart_state *out);

/* As kc_interp_joint_eval_profile, for the arc. */
kc_status kc_interp_arc_eval_profile(const kc_interp_arc *plan, const kc_profile *prof, int64_t k,
                                     kc_interp_cart_state *out);

/* As kc_interp_line_eval_scurve, for the arc. */
kc_status kc_interp_arc_eval_scurve(const kc_interp_arc *plan, const kc_scurve *prof, int64_t k,
                                    kc_interp_cart_state *out);

KC_END_DECLS

#endif /* KINCTL_INTERP_H */
