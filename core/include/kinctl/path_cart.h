/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/path_cart.h - Cartesian multi-point paths (seed 001 lab 7): a tool
 * pose through knot poses, planned once and evaluated at integer ticks.
 *
 * The position (m) follows any of the methods of kinctl/path.h in 3-D
 * (limits on |p'| and |p''|). The orientation goes
 * through the knot orientations r_i (unit quaternions; the sign of r_{i+1}
 * is flipped where needed so that r_i . r_{i+1} >= 0: each segment turns by
 * the shorter way, at most pi, through the double cover) on the same knot
 * times, as r(t) = r_i exp(v(t)) with v a rotation vector (rad) in the body
 * frame of r_i and w_i = log(r_i^* r_{i+1}):
 *   blend: v follows the same blend as the position, in the tangent space
 *     of the knot's orientation (A = -w_{j-1} t_acc / T_{j-1}, B = 0,
 *     C = w_j) and the lines turn at constant rate w_i / T_i about a fixed
 *     axis: the angular velocity is continuous (and the angular
 *     acceleration too for the quartic blend), and, like the position, the
 *     orientation passes near, not through, the knot orientations;
 *   lagrange, spline, quintic: on each segment v is the quintic with
 *     v(0) = 0, v(T) = w_i and the knot angular velocities (body frame)
 *     omega_i = (T_i w_{i-1}/T_{i-1} + T_{i-1} w_i/T_i) / (T_{i-1} + T_i)
 *     (the slope of the parabola through three knots; 0 at both ends) and
 *     knot angular accelerations 0, mapped through the right Jacobian of
 *     SO(3): the orientation passes exactly through every knot orientation
 *     at its time with continuous angular velocity and acceleration.
 *   Why not slerp per segment on the same timing: it is only C0 (the
 *   angular velocity jumps at every knot); squad is C1 only for uniform
 *   knot spacing. Knot angular velocities cannot be given; cfg.v/cfg.a give
 *   linear ones. s is the path length so far, the integral of |p'|: a table
 *   holds it at KC_PATH_ARC_SPLITS points of every piece and at the local
 *   minima of the speed (roots of p'.p'' found on 64 samples of the piece
 *   and bisected, up to KC_PATH_ARC_MINIMA), each step by 6-point
 *   Gauss-Legendre summed with compensation, and a tick adds the same
 *   quadrature from the table's last point to t: s is continuous, exact on
 *   lines, and a stop or sharp reversal inside a piece (|p'| V-shaped,
 *   where Gauss-Legendre loses its order) falls on a table point; tested
 *   within 1e-8 of the length in double (random paths, against Simpson's
 *   rule), within rounding in float; sd = |p'| and
 *   sdd = p'.p''/|p'| (d|p'|/dt; where |p'| = 0, |p''| - the path starts
 *   moving - and at the end tick -|p''|).
 *
 * Units: m, rad, seconds. Planning and evaluation allocate nothing, use no
 * global state and are safe in the control cycle; costs are quoted in
 * kinctl/path.h (a tick 105-130 ns, planning 20-160 us for the length
 * table).
 */
#ifndef KINCTL_PATH_CART_H
#define KINCTL_PATH_CART_H

#include <stdint.h>

#include "kinctl/decls.h"
#include "kinctl/path.h"
#include "kinctl/real.h"
#include "kinctl/se3.h"
#include "kinctl/status.h"

KC_BEGIN_DECLS

/* What a Cartesian path is made of. Start from kc_path_cart_cfg_default().
 * Arrays are read during planning only. */
typedef struct kc_path_cart_cfg {
    kc_path_method method;
    kc_path_blend blend;
    kc_path_spline_end spline_end;
    int n_knots;            /* 2 .. KC_PATH_MAX_KNOTS */
    const kc_vec3 *p;       /* knot positions (m) */
    const kc_quat *r;       /* knot orientations (w, x, y, z), unit within KC_PATH_TOL_QUAT_NORM */
    const kc_real *t;       /* knot times (s) or NULL: from the limits */
    const kc_vec3 *v;       /* knot linear velocities (m/s) or NULL (spline, quintic) */
    const kc_vec3 *a;       /* knot linear accelerations (m/s^2) or NULL (quintic) */
    kc_real t_acc;          /* as kc_path_cfg.t_acc */
    kc_real v_max, a_max;   /* |p'| and |p''| limits for computed times (> 0) */
    /* Angular limits (rad/s, rad/s^2) for computed times: segment i also
     * lasts at least t_trap(angle_i, w_max, alpha_max) and t_acc at least
     * 1.5 w_max / alpha_max. 0 (default): the orientation does not set the
     * times. */
    kc_real w_max, alpha_max;
    kc_real dt;             /* tick period (s) */
} kc_path_cart_cfg;

/* A planned Cartesian path: the position as a 3-D kc_path, the orientation
 * per piece as base[p] exp(v), v = sum_i rc[p][i] tau^i. */
typedef struct kc_path_cart {
    kc_path pos;
    kc_quat base[KC_PATH_MAX_PIECES];
    kc_mat3 base_R[KC_PATH_MAX_PIECES]; /* base[p] as a matrix */
    kc_real rc[KC_PATH_MAX_PIECES][6][3];
    /* Velocity coefficients of the position, i c[p][i][j] at [p][i-1][j]:
     * the quadrature of s evaluates them several times a tick. */
    kc_real vc[KC_PATH_MAX_PIECES][KC_PATH_MAX_COEFFS - 1][3];
    /* pos's coefficients packed three to a row, for the tick. */
    kc_real pc[KC_PATH_MAX_PIECES][KC_PATH_MAX_COEFFS][3];
    /* Path length (m) s_arc[p][i] at local time tau_arc[p][i] of piece p,
     * i < n_arc[p]: from 0 to len[p], increasing. */
    kc_real tau_arc[KC_PATH_MAX_PIECES][KC_PATH_ARC_POINTS];
    kc_real s_arc[KC_PATH_MAX_PIECES][KC_PATH_ARC_POINTS];
    int n_arc[KC_PATH_MAX_PIECES];
    kc_real length;                      /* total path length (m) */
    kc_quat r_end;                       /* final orientation (sign-continuous) */
} kc_path_cart;

/* The state of a Cartesian path at one instant. */
typedef struct kc_path_pose {
    kc_vec3 p;          /* position (m) */
    kc_quat r;          /* orientation, unit; its sign is continuous along the path */
    kc_vec3 v, a;       /* linear velocity (m/s) and acceleration (m/s^2) */
    kc_vec3 w;          /* angular velocity in the base frame (rad/s) */
    kc_real s, sd, sdd; /* path length so far (m), speed, its rate */
} kc_path_pose;

/* Quartic blends, clamped splines, no knots, no times, t_acc 0, v_max and
 * a_max 1, no angular limits, dt 0.001 s. */
kc_path_cart_cfg kc_path_cart_cfg_default(void);

/* Plans a Cartesian path. Return codes as kc_path_plan; also KC_E_ARG for a
 * NULL p or r, or a quaternion not finite or farther than
 * KC_PATH_TOL_QUAT_NORM from unit norm, or w_max/alpha_max negative, NaN
 * or only one of them positive. path untouched on error. */
kc_status kc_path_cart_plan(kc_path_cart *path, const kc_path_cart_cfg *cfg);

/* State at tick k >= 0. KC_OK while moving, KC_DONE from tick pos.ticks on
 * (the end pose exactly: last knot for interpolating methods), KC_E_ARG for
 * NULL or k < 0 (out untouched). */
kc_status kc_path_cart_eval(const kc_path_cart *path, int64_t k, kc_path_pose *out);

/* State at plan time t (s); as kc_path_eval_time. */
kc_status kc_path_cart_eval_time(const kc_path_cart *path, kc_real t, kc_path_pose *out);

/* Piece p at local time tau (continuity checks); as kc_path_eval_piece.
 * out->s is the length at the piece's start plus the quadrature to tau. */
kc_status kc_path_cart_eval_piece(const kc_path_cart *path, int p, kc_real tau, kc_path_pose *out);

KC_END_DECLS

#endif /* KINCTL_PATH_CART_H */
