/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/ik.h - inverse kinematics by integrating the kinematic equations
 * (seed 002), with damping, joint limits and redundancy (seed 003).
 *
 * The method. Let L(q) be the unit dual quaternion of the tool pose and L*
 * the target's. The error M = conj(L) o L* (seed 002 eq. 6, with the
 * conjugate the OCR lost) is the target seen from the tool. Its real part
 * M_r = (cos(a/2), sin(a/2) n) gives the commanded angular velocity
 *     w = 2 k sgn(w(M_r)) vec(M_r)          (the sign picks the short way:
 *                                             q and -q are the same pose)
 * and its dual part the translation error, so the commanded tool twist is
 *     U = [v; w],  v = k (t* - t)   (both mapped to the base frame by R(q)),
 * and the joints follow qdot = J^+(q) U (seed 002 eq. 4). For the continuous
 * system the position error obeys e' = -k e and the rotation angle
 * a' = -2k sin(a/2), decreasing monotonically: the target is asymptotically
 * stable from every start where J stays full rank (the seed's claim; with a
 * pseudo-inverse it holds in the task space, not for the joint path).
 *
 * The discrete version. kc_ik_solve integrates with explicit Euler, step h
 * and gain k: the task error then evolves as e+ = (1 - k h) e + O(|dq|^2),
 * which contracts for 0 < k h < 2 and is fastest at k h = 1 (then one step
 * is a damped Gauss-Newton step). The product k h must lie in (0, 1]
 * (cfg.gain_step); larger values overshoot on the neglected curvature.
 * Euler with k h = 1 is Gauss-Newton, quadratic near the target. RK4 was
 * measured against it: on the linearised error RK4 contracts by
 * 1 - kh + (kh)^2/2 - (kh)^3/6 + (kh)^4/24 = 0.375 per step at k h = 1, for
 * four Jacobians (0.78 per Jacobian), and the RK4 reference run of
 * vectors/ik.json (k = 1/s, h = 0.05 s) takes a median of 570 steps (2282
 * Jacobians) on the 50 targets where this solver takes a median of 10 (max
 * 145, restarts included).
 *
 * Damped least squares. qdot = J^T (J J^T + lambda^2 I)^-1 U with
 *     lambda^2 = c |e|^2 + lambda_s^2 (Sugihara's error-damped
 *     Levenberg-Marquardt, c = 0.05: damped far from the target, exact near
 *     it; kc_ik_solve only),
 *     lambda_s^2 = damping_max^2 (1 - w / w0)^2 when the manipulability
 *     w = sqrt(det(J J^T)) is below w0, else 0 (Nakamura-Hanafusa; the
 *     online step only: solve relies on its step bound instead),
 * and every joint step bounded by cfg.max_step (the whole step is scaled
 * down, keeping its direction).
 *
 * Tasks. KC_IK_MASK_FULL uses all six rows; KC_IK_MASK_POSITION the three
 * linear rows; KC_IK_MASK_AXIS the position and the direction of the tool's
 * z axis (5 rows: the rotation about the tool axis is free). When the chain
 * has more joints than the task rows, the spare motion descends the
 * objective H(q) = sum ((q_i - rest_i)/range_i)^2 + a barrier that grows
 * inside cfg.limit_margin of each position limit, projected into the null
 * space of J (seed 003's removal of redundancy):
 *     qdot = J^+ U + (I - J^+ J) (-null_gain grad H).
 * The barrier is cubic in the depth d into the margin m (m = limit_margin
 * x range), its gradient d^2 / (2 m^3): zero with zero slope where a joint
 * enters the margin, so the null-space velocity's rate, the gradient's
 * slope times qd, rises from 0 there. (A gradient linear in d, 100 d / m^2,
 * took the null-space velocity to its bound within a few mrad of the
 * margin; the Panda's lines and arcs then stepped qdd by up to
 * 4 x qddd_max.)
 *
 * Joint limits. Every step is clamped into the position limits; a joint that
 * sits at a limit and would be pushed beyond it is frozen for that step (its
 * column removed) and the step solved again, so the others make up for it.
 *
 * Both entry points are cycle-safe: no allocation, bounded work
 * (cfg.max_steps x (cfg.max_restarts + 1) Jacobians at most), deterministic
 * (restarts draw from a generator seeded by cfg.seed, so repeated runs are
 * bit-identical).
 */
#ifndef KINCTL_IK_H
#define KINCTL_IK_H

#include <stdint.h>

#include "kinctl/decls.h"
#include "kinctl/fk.h"

KC_BEGIN_DECLS

typedef enum kc_ik_mask {
    KC_IK_MASK_FULL = 0,     /* position and orientation: 6 rows */
    KC_IK_MASK_POSITION = 1, /* position only: 3 rows */
    KC_IK_MASK_AXIS = 2      /* position and tool z direction: 5 rows */
} kc_ik_mask;

typedef struct kc_ik_cfg {
    kc_ik_mask mask;
    /* Feedback gain k (1/s) of the online step, for rotation and position. */
    kc_real gain_rot, gain_pos;
    /* k h of kc_ik_solve, in (0, 1]: 1 is the fastest stable choice. */
    kc_real gain_step;
    /* Convergence: position error (m) and rotation error (rad). */
    kc_real tol_pos, tol_rot;
    /* Steps per attempt, and restarts from other starts when one stalls. */
    int max_steps;
    int max_restarts;
    /* Largest change of any joint in one step of kc_ik_solve (rad or m). */
    kc_real max_step;
    /* Singularity damping: lambda_s reaches damping_max as the
     * manipulability falls from manip_threshold to zero. */
    kc_real damping_max;
    kc_real manip_threshold;
    /* Null-space objective (redundant tasks only): gain (1/s for the online
     * step, per step for solve), the margin kept from each position limit as
     * a fraction of its range, and the rest posture. */
    kc_real null_gain;
    kc_real limit_margin;
    kc_real q_rest[KC_MAX_JOINTS];
    int use_rest; /* 0: rest = middle of each joint's range */
    /* Seed of the restart generator. */
    uint64_t seed;
} kc_ik_cfg;

/* Defaults: full task, k = 20 1/s online, k h = 1, tolerances 1e-10 m and
 * 1e-10 rad (double; 1e-5 m and 1e-4 rad in float), 100 steps, 100 restarts,
 * max step 1 rad, damping_max 0.05, manipulability threshold 1e-3,
 * null-space gain 0.5, margin 5 %, rest = mid-range. */
kc_ik_cfg kc_ik_cfg_default(void);

/* KC_OK when every field is usable (positive gains and tolerances, k h in
 * (0, 1], finite rest posture...), else KC_E_ARG. */
kc_status kc_ik_cfg_check(const kc_ik_cfg *cfg, const kc_chain *chain);

typedef struct kc_ik_result {
    kc_status status;
    int steps;       /* Jacobian evaluations, over all attempts */
    int restarts;    /* attempts after the first */
    kc_real pos_err; /* m, at the returned q */
    kc_real rot_err; /* rad (the axis angle for KC_IK_MASK_AXIS; 0 for position) */
} kc_ik_result;

/*
 * Integrates from q0 until the tool reaches target within the tolerances.
 *   KC_OK            converged; q holds the solution, inside the limits.
 *   Not within max_steps x (max_restarts + 1): q holds the best configuration
 *   found and res its residuals, and the status says where it stopped:
 *     KC_E_LIMIT       a joint of the best configuration sits at a limit;
 *     KC_E_SINGULAR    else its task Jacobian is singular (manipulability
 *                      below cfg.manip_threshold: e.g. a target beyond a
 *                      stretched elbow but inside the reach bound);
 *     KC_E_NOCONVERGE  else.
 *   KC_E_UNREACHABLE target farther from the base than the chain can reach
 *                    (q untouched).
 *   KC_E_ARG         NULL, non-finite target or q0, q0 count mismatch, bad
 *                    cfg (q and res untouched).
 * q0 outside the limits is clamped into them first. q may alias q0.
 */
kc_status kc_ik_solve(const kc_chain *chain, const kc_ik_cfg *cfg, const kc_pose *target, const kc_real *q0,
                      kc_real *q, kc_ik_result *res);

/*
 * One step of the online law for the control cycle: from joint state (q, qd)
 * towards target, over the period dt (s). target and twist_ff describe the
 * target at the instant of (q, qd); the step heads for where it will be
 * after dt. Commands
 *     qd_next = J^+ (twist_ff + k e) + null-space term,
 * k being kc_ik_online_gain of cfg's gain_pos or gain_rot and dt,
 * twist_ff being the target's own velocity [v; w] (base frame, m/s and
 * rad/s; NULL for a fixed target): with it a moving target is tracked with
 * an error of the order of its acceleration times dt^2, not v/k. The command
 * is scaled down as a whole to respect every joint's velocity limit and its
 * acceleration limit relative to qd, then q_next = q + qd_next dt is
 * clamped into the position limits.
 *   KC_OK            stepped; res holds the error before the step.
 *   KC_DONE          within the tolerances, twist_ff zero or NULL, and
 *                    every |qd| <= min(qdd_max dt, max(qddd_max dt^2 / 2,
 *                    4 KC_REAL_EPS max(|q|, 1) / dt)): q_next = q,
 *                    qd_next = 0 (a stop within the limits: qdd goes to
 *                    -qd/dt and back to 0, and from a qdd that is
 *                    decaying, as the law's own near rest, no change of
 *                    qdd over a tick exceeds qddd_max dt, nor when a
 *                    motion started from here gets that velocity back in
 *                    its first tick; in float the
 *                    law's rounding keeps qd at up to a few units of q's
 *                    last place per tick, which that allows).
 *   KC_E_LIMIT       stepped, but a joint was stopped at a position limit.
 *   KC_E_SINGULAR    stepped, but the singularity damping is active (the
 *                    tool will not follow the commanded twist exactly).
 *   KC_E_ARG         bad input; outputs untouched.
 * q_next and qd_next may alias q and qd.
 */
kc_status kc_ik_step(const kc_chain *chain, const kc_ik_cfg *cfg, const kc_pose *target, const kc_real *twist_ff,
                     kc_real dt, const kc_real *q, const kc_real *qd, kc_real *q_next, kc_real *qd_next,
                     kc_ik_result *res);

/* The gain k the online step applies for a configured gain at period dt:
 * the least of the two and 1/dt. Over a step the error evolves as
 * e+ = (1 - k dt) e (the discrete version, above): removed in one step at
 * k dt = 1, overshot beyond, growing from k dt = 2 on (the controller's
 * 100/s at a period of 20 ms or more: a 10 cm line on the PUMA 560 fell
 * more than cfg.track_tol behind its path within 100 ticks at 20 ms, 4
 * at 50 ms). */
kc_real kc_ik_online_gain(kc_real gain, kc_real dt);

/*
 * kc_ik_step with joint velocities qd_ff fed forward in the task's null
 * space: on a redundant task (more joints than the task's rows) the
 * command becomes
 *     qd_next = J^+ (twist_ff + k e) + (I - J^+ J) qd_ff + null-space term,
 * so that a joint-space motion whose tool twist J qd_ff is twist_ff is
 * given back whole (J^+ J qd_ff + (I - J^+ J) qd_ff = qd_ff), its part
 * that does not move the tool included (the controller's superposition
 * of a Cartesian goal on a stop in joint space, kinctl/ctrl.h). The
 * scaling to the velocity and acceleration limits applies to the whole
 * command. qd_ff NULL, or a task without a null space: kc_ik_step.
 * KC_E_ARG also for a non-finite qd_ff.
 */
kc_status kc_ik_step_ff(const kc_chain *chain, const kc_ik_cfg *cfg, const kc_pose *target, const kc_real *twist_ff,
                        const kc_real *qd_ff, kc_real dt, const kc_real *q, const kc_real *qd, kc_real *q_next,
                        kc_real *qd_next, kc_ik_result *res);

/* Distance from the base origin beyond which no configuration reaches: the
 * sum of every constant translation, the largest prismatic travels and the
 * tool offset. A cheap, conservative workspace bound (infinite when a
 * prismatic joint is unbounded). */
kc_real kc_ik_reach(const kc_chain *chain);

KC_END_DECLS

#endif /* KINCTL_IK_H */
