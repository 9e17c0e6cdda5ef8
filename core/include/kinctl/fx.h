/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/fx.h - forward kinematics, the geometric Jacobian, and joint moves
 * and lines evaluated at integer ticks, in fixed point: for cores without
 * an FPU (Cortex-M0/M3), where every float operation is a libgcc call.
 *
 * The same walk over the chain's elementary transforms as kinctl/fk.h
 * (seed 000, seed 003), and the interpolators of kinctl/interp.h (seed 001
 * labs 4, 5) by either speed law, the trapezoid or jerk-limited
 * (kinctl/scurve.h), in integer arithmetic only: the objects that evaluate (fx.c,
 * fx_interp.c) use no float type, operation or call (checked by
 * mcu/check_integer_only.sh). Chains and plans are converted once,
 * outside the cycle and in floating point (kc_fx_chain_init,
 * kc_fx_joint_init, kc_fx_line_init in fx_chain.c); joint values come in
 * fixed point (from encoder counts directly, or kc_fx_q_from_real).
 *
 * Formats (Qm.n: a signed 32-bit integer, value = integer / 2^n):
 *   KC_FX_ROT   Q2.30  rotation entries, sine and cosine, Jacobian rows 3-5:
 *                      |x| < 2, resolution 9.3e-10
 *   KC_FX_POS   Q8.24  positions and lengths (m), Jacobian rows 0-2 (m/rad,
 *                      or unitless for a prismatic joint): |x| < 128 m,
 *                      resolution 6.0e-8 m
 *   KC_FX_ANGLE Q3.28  revolute joint values and offsets (rad): |q| < 8,
 *                      resolution 3.7e-9 rad; prismatic ones are KC_FX_POS
 * Products are formed in int64_t and rounded to nearest (ties up): a Q2.30
 * by Q2.30 product is Q4.60 (|x| < 4: below 2^62), a Q2.30 by Q8.24
 * product Q10.54; a rotation's row times a column sums three in int64
 * before the one rounding. Right shifts of negative values are arithmetic
 * (GCC and Clang on every target; C99 leaves it to the implementation).
 *
 * Rounding, per elementary transform: a rotation about a frame axis rounds
 * six entries by at most 2^-31 each (4.7e-10); a translation moves the
 * origin by v times a column, rounded by 2^-25 m (3e-8 m) per coordinate.
 * Sine and cosine (kc_fx_sincos) are within 4e-9 of the true values: the
 * angle becomes a Q0.32 fraction of a turn (rounding 7.3e-10 rad), then a
 * Q2.30 angle in [0, pi/4] (4.7e-10), and the series take about ten
 * roundings of 4.7e-10 (measured in mcu/fx_test.c). For a chain of N
 * elements the tool position is off by at most about N (3e-8 m + |p| 1e-8) and each rotation
 * entry by about N 1e-9 plus the conversion of the chain's constants
 * (half a resolution each): a PUMA 560 (15 elements) stays below 1 um and
 * 1e-6, the errors measured against the double build on random
 * configurations of every built-in arm by mcu/fx_test.c on the host and on
 * QEMU's Cortex-M3 and Cortex-M4F boards.
 *
 * IK stays in floating point: its damped least-squares solve divides by
 * quantities that approach zero near singularities, and the dynamic range
 * of J J^T + lambda^2 I spans more than any one fixed format keeps with 1e-6
 * accuracy; on an FPU-less core it is the planner's job, off the cycle.
 *
 * All functions are pure, allocate nothing and are safe in the cycle.
 */
#ifndef KINCTL_FX_H
#define KINCTL_FX_H

#include <stdint.h>

#include "kinctl/chain.h"
#include "kinctl/decls.h"
#include "kinctl/interp.h"

KC_BEGIN_DECLS

#define KC_FX_ROT_BITS 30
#define KC_FX_POS_BITS 24
#define KC_FX_ANGLE_BITS 28
#define KC_FX_ONE_ROT ((int32_t)1 << KC_FX_ROT_BITS)

/* A rigid pose: R in Q2.30, t in Q8.24 (m). */
typedef struct kc_fx_pose {
    int32_t R[3][3];
    int32_t t[3];
} kc_fx_pose;

typedef struct kc_fx_element {
    uint8_t code;   /* kc_code */
    int8_t joint;   /* joint index for codes 1-6, -1 for constants */
    int8_t quarter; /* +-1: a constant quarter turn (a column swap) */
    int32_t value;  /* constant translation, Q8.24 (codes 10-12) */
    int32_t c, s;   /* cosine and sine of a constant rotation, Q2.30 */
} kc_fx_element;

/* A chain in fixed point, made by kc_fx_chain_init. */
typedef struct kc_fx_chain {
    int n_joints;
    int n_elements;
    uint8_t revolute[KC_MAX_JOINTS];
    int32_t offset[KC_MAX_JOINTS]; /* Q3.28 (revolute) or Q8.24 (prismatic) */
    kc_fx_element elements[KC_MAX_ELEMENTS];
    kc_fx_pose base, tool;
    int tool_identity;
} kc_fx_chain;

/* 6 x n Jacobian: rows 0-2 in Q8.24, rows 3-5 in Q2.30. */
typedef struct kc_fx_jacobian {
    int32_t m[6][KC_MAX_JOINTS];
} kc_fx_jacobian;

/* Converts a checked chain (kc_chain_check). KC_E_ARG for NULL or a chain
 * that fails its check, KC_E_CAPACITY for a length, offset or base/tool
 * translation outside Q8.24's or Q3.28's range. Floating point: not for the
 * cycle of an FPU-less core. */
kc_status kc_fx_chain_init(kc_fx_chain *fx, const kc_chain *chain);

/* Joint values (rad, m) to fixed point, rounded to nearest: KC_E_ARG for a
 * non-finite value or one outside the format (|q| >= 8 rad, 128 m). */
kc_status kc_fx_q_from_real(const kc_fx_chain *fx, const kc_real *q, int32_t *q_fx);

/* Converts back, exactly (for comparisons and logs). */
void kc_fx_pose_to_real(const kc_fx_pose *p, kc_pose *dest);

/* Sine and cosine of an angle in Q3.28 (any value), in Q2.30. */
void kc_fx_sincos(int32_t angle, int32_t *s, int32_t *c);

/* Tool pose of joint values q_fx (n_joints, formats above). KC_E_ARG for
 * NULL. */
kc_status kc_fx_fk_eval(const kc_fx_chain *fx, const int32_t *q_fx, kc_fx_pose *tool);

/* Geometric Jacobian in the base frame (kinctl/fk.h), and the tool pose if
 * tool != NULL. KC_E_ARG for NULL. */
kc_status kc_fx_jacobian_eval(const kc_fx_chain *fx, const int32_t *q_fx, kc_fx_jacobian *jac, kc_fx_pose *tool);

/* ---- interpolators (kinctl/interp.h) evaluated at integer ticks ---- */

/* A positive factor as m 2^-shift, m in [2^30, 2^31): 31 significant bits
 * whatever its size (a per-tick acceleration of 1e-7 keeps them all). */
typedef struct kc_fx_scaled {
    uint32_t m;
    int shift;
} kc_fx_scaled;

/* The phases of a jerk-limited profile (kinctl/scurve.h); a trapezoid has
 * three. */
#define KC_FX_MAX_PHASES 7
/* The fraction bits of a ramp's sums (Q23.40 in int64_t). */
#define KC_FX_RAMP_BITS 40

/*
 * The fraction u of a segment planned from rest to rest, from 0 to 1, in
 * tick units: the trapezoid of kinctl/profile.h or the jerk-limited
 * profile of kinctl/scurve.h. Either is a polynomial of degree at most 3
 * in time over each of its phases, so over the ticks of a phase
 *   u(k) = u0 + c1 m + c2 m^2 + c3 m^3,      m = k - k0, an integer,
 * k0 the phase's first tick and u0, c1 = u' dt, c2 = u'' dt^2 / 2 and
 * c3 = u''' dt^3 / 6 the profile's state at k0: the phase's polynomial
 * expanded about that tick, in floating point, when the plan is
 * converted. A tick lies in the phase the floating-point evaluation puts
 * it in (the same comparison of k dt with the phase's end). In the cycle:
 *   m < 2^24 and m^2 < 2^48 are exact;
 *   each |c| is a 31-bit factor (kc_fx_scaled) with its sign;
 *   c3 m^3 is formed as (c3 m) m^2, c3 m renormalised to 31 bits;
 *   the three products (up to 2^79, in 96 bits from two 64-bit ones) are
 *   rounded to Q23.40 and summed with u0 (Q23.40), then u is rounded once
 *   to Q2.30.
 * Error against the floating-point evaluation of the same plan: the
 * factors' roundings, 2^-31 of |c1 m| + |c2 m^2| + 2 |c3 m^3| (each term
 * at most about the phase's own change of u, so together a few 2^-31),
 * four roundings to Q23.40 (2^-41 each) and the last one, half of 2^-30:
 * u within 2e-9 (measured in mcu/fx_test.c over random PUMA 560 moves and
 * lines, trapezoid and jerk-limited).
 */
typedef struct kc_fx_ramp {
    int n;                               /* phases with ticks */
    int32_t k0[KC_FX_MAX_PHASES];        /* each phase's first tick (k0[0] = 0) */
    int64_t u0[KC_FX_MAX_PHASES];        /* u at k0, Q23.40 */
    kc_fx_scaled c[KC_FX_MAX_PHASES][3]; /* |c1|, |c2|, |c3| */
    uint8_t neg[KC_FX_MAX_PHASES];       /* bit i set: c(i + 1) < 0 */
    int64_t ticks;                       /* first tick at the end */
} kc_fx_ramp;

/* A joint move (kc_interp_joint_plan, or kc_interp_joint_plan_cfg from
 * rest): q(k) = q0 + dq u(k), with one u for every joint (the trapezoid,
 * or a jerk-limited move synchronised by phase) or one per joint (by
 * time: joint i's profile from q0 to q1 as the fraction (q - q0) / dq; a
 * joint that does not move has u = 0). q is within |dq| 2e-9 + 3.8e-9 rad
 * of the double build's: u's error, then q0's conversion and q's
 * rounding, half a resolution each (measured in mcu/fx_test.c). */
typedef struct kc_fx_joint_move {
    int n;
    int per_joint; /* 1: ramp[i] is joint i's; 0: ramp[0] is every joint's */
    int32_t q0[KC_MAX_JOINTS], q1[KC_MAX_JOINTS]; /* joint formats */
    int64_t dq[KC_MAX_JOINTS];                    /* q1 - q0: up to twice a format's range */
    kc_fx_ramp ramp[KC_MAX_JOINTS];
} kc_fx_joint_move;

/* Converts a plan, trapezoid or jerk-limited: KC_E_ARG for NULL, a plan
 * not from rest to rest (a jerk-limited one from a moving start), a
 * fraction outside -0.5 .. 1.5 at a phase's ends, or joint values outside
 * the formats (*move cleared then). Floating point: set up outside the
 * cycle. */
kc_status kc_fx_joint_init(kc_fx_joint_move *move, const kc_fx_chain *fx, const kc_interp_joint *plan);

/* q at tick k (>= 0) into q_fx (n values). KC_OK while moving, KC_DONE
 * from the last tick on (q = q1 exactly); KC_E_ARG for NULL or k < 0.
 * Integer only, cycle-safe. */
kc_status kc_fx_joint_eval(const kc_fx_joint_move *move, int64_t k, int32_t *q_fx);

/*
 * A Cartesian line (kc_interp_line_plan): p(k) = p1 + dp u(k) in Q8.24 and
 * the orientation q1 rel(u) as a quaternion (w x y z) in Q2.30, rel(u) by
 * either method of kinctl/interp.h: slerp (cos, sin times the axis, of half
 * the angle times u) or the two rotations (5.16: about k1 by theta u, then
 * about z by phi u). Half angles are Q3.28; sine and cosine kc_fx_sincos's.
 * The position is within |dp| 2e-9 + 6e-8 m, the quaternion within about
 * 1e-8 of the double build's (measured in mcu/fx_test.c).
 */
typedef struct kc_fx_line {
    int32_t p1[3], p2[3]; /* Q8.24 */
    int64_t dp[3];        /* p2 - p1 */
    int32_t q1[4], q2[4]; /* Q2.30, w x y z */
    int slerp;            /* 1: slerp; 0: two rotations */
    int32_t half_angle;   /* slerp: angle / 2, Q3.28 */
    int32_t axis[3];      /* slerp: unit axis in the start frame, Q2.30 */
    int32_t half_theta, half_phi; /* two rotations: theta / 2, phi / 2, Q3.28 */
    int32_t kx, ky;               /* two rotations: the first axis (kx, ky, 0), Q2.30 */
    kc_fx_ramp ramp;
} kc_fx_line;

/* Converts a plan, trapezoid or jerk-limited (its su); KC_E_ARG as
 * kc_fx_joint_init, or for a position outside Q8.24. Floating point,
 * outside the cycle. */
kc_status kc_fx_line_init(kc_fx_line *line, const kc_interp_line *plan);

/* Position (Q8.24) and orientation (Q2.30, w x y z) at tick k (>= 0):
 * KC_OK while moving, KC_DONE from the last tick on (the end pose
 * exactly); KC_E_ARG for NULL or k < 0. Integer only, cycle-safe. */
kc_status kc_fx_line_eval(const kc_fx_line *line, int64_t k, int32_t p[3], int32_t q[4]);

KC_END_DECLS

#endif /* KINCTL_FX_H */
