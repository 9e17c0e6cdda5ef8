/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/path.h - multi-point paths through knots (seed 001 lab 7,
 * "Планирование сглаженных траекторий") in joint space, planned once and
 * evaluated at integer ticks. The methods here also drive the position of
 * Cartesian paths (kinctl/path_cart.h).
 *
 * A path goes through n knots q_0 .. q_{n-1} (2 <= n <= KC_PATH_MAX_KNOTS,
 * each of dimension 1 .. KC_MAX_JOINTS) at knot times t_0 < .. < t_{n-1}.
 * Every method turns them into a sequence of polynomial pieces in the local
 * time tau of each piece; planning is bounded (every loop runs over the
 * knots, the pieces or a fixed count of samples and bisection steps),
 * evaluation finds the piece by a bisection of at most 6 steps and runs
 * Horner's scheme: no state is kept between ticks.
 *
 * Methods (T_i = t_{i+1} - t_i, delta_i = (q_{i+1} - q_i) / T_i):
 *
 * KC_PATH_BLEND - straight lines through consecutive knots,
 *     q = q_i + delta_i (t - t_i) for t_i + t_acc <= t < t_{i+1} - t_acc,
 *   and around every knot j a blend on [t_j - t_acc, t_j + t_acc] with
 *     h = (t - t_j + t_acc) / (2 t_acc), B = q_j, C = q_{j+1} (C = B at the
 *     last knot), A = the incoming line at t_j - t_acc (A = q_0 at the first
 *     knot), dB = A - B, dC = C - B, K = dC t_acc / T_j + dB:
 *   quartic (KC_PATH_BLEND_QUARTIC, default; Paul 1981, the seed's printed
 *   formula restored, vectors/README.md typo #31):
 *     q   = [(K (2 - h) h^2 - 2 dB) h] + B + dB
 *     qd  = [K (1.5 - h) 2 h^2 - dB] / t_acc
 *     qdd = K (1 - h) 3 h / t_acc^2
 *   position, velocity and acceleration continuous (peak |qdd| = 0.75 |dv| /
 *   t_acc for a velocity change dv);
 *   parabolic (KC_PATH_BLEND_PARABOLIC, the usual constant-acceleration blend):
 *     q = (K h - 2 dB) h + B + dB,  qd = (K h - dB) / t_acc,  qdd = K / (2 t_acc^2)
 *   position and velocity continuous, acceleration jumps at the blend ends.
 *   The path does not pass through the knots (it cuts the corners); it
 *   starts at rest at q_0 at t_0 - t_acc and ends at rest at q_{n-1} at
 *   t_{n-1} + t_acc: tick 0 is t_0 - t_acc (see t_origin). Rule: 0 < t_acc
 *   <= min_i T_i / 2, so blends never overlap (a line of zero length between
 *   two blends is allowed).
 *
 * KC_PATH_LAGRANGE - the single polynomial of degree n - 1 through all knots
 *   (the seed's Lagrange formula, all n knots: typo #33). Caveat (the seed's
 *   own): it oscillates between the knots more as n grows (Runge's
 *   phenomenon) and nothing bounds its velocity; hence n <=
 *   KC_PATH_MAX_LAGRANGE_KNOTS. It does not start or end at rest. Stored as
 *   its Taylor expansion at every knot, which keeps the evaluation accurate.
 *
 * KC_PATH_SPLINE - cubic pieces (seed sec. 6.3, typo #34: correct, cubic
 *   Hermite), on [t_{i-1}, t_i] with tau = t - t_{i-1}, t_m = T:
 *     S = K3 tau^3 + K2 tau^2 + K1 tau + K0,  K0 = S_{i-1},  K1 = v_{i-1},
 *     K2 = (3 S_i - 3 S_{i-1} - 2 v_{i-1} t_m - v_i t_m) / t_m^2,
 *     K3 = (v_i t_m + v_{i-1} t_m - 2 S_i + 2 S_{i-1}) / t_m^3.
 *   With knot velocities given (cfg.qd) the acceleration jumps at the knots;
 *   without, the knot velocities solve the tridiagonal system of a C2 spline
 *     T_i v_{i-1} + 2 (T_{i-1} + T_i) v_i + T_{i-1} v_{i+1}
 *         = 3 (T_i delta_{i-1} + T_{i-1} delta_i)
 *   with clamped ends v_0 = v_{n-1} = 0 (KC_PATH_SPLINE_CLAMPED, default:
 *   starts and ends at rest) or natural ends q'' = 0 (KC_PATH_SPLINE_NATURAL:
 *   2 v_0 + v_1 = 3 delta_0, v_{n-2} + 2 v_{n-1} = 3 delta_{n-2}; does not
 *   start at rest). The system is strictly diagonally dominant: Thomas'
 *   algorithm without pivoting is stable.
 *
 * KC_PATH_QUINTIC - quintic Hermite pieces matching position, velocity and
 *   acceleration at both knots, so acceleration is continuous at the knots
 *   (seed sec. 4: six conditions, fifth degree). Knot velocities given
 *   (cfg.qd) or computed by the rule of Siciliano et al. (Robotics:
 *   Modelling, Planning and Control, sec. 4.2.1): v_0 = v_{n-1} = 0,
 *   v_i = 0 where delta_{i-1} and delta_i differ in sign (or one is zero),
 *   else (delta_{i-1} + delta_i) / 2;
 *   knot accelerations given (cfg.qdd) or computed as the mean of the two
 *   accelerations that cubic Hermite pieces with the same knot velocities
 *   would have at the knot (left (-6 dq + 2 v_{i-1} T + 4 v_i T) / T^2 and
 *   right (6 dq - 4 v_i T - 2 v_{i+1} T) / T^2), and 0 at both ends.
 *
 * Knot times: given (cfg.t, seconds, strictly increasing), or computed from
 * the limits when cfg.t is NULL: each segment lasts the time of a
 * rest-to-rest trapezoid over its largest distance,
 *     T_i = max_j t_trap(|q_{i+1,j} - q_{i,j}|, vmax_j, amax_j),
 *     t_trap(D, v, a) = D / v + v / a   if D >= v^2 / a,  2 sqrt(D / a) else,
 * with t_0 = 0. Blends: t_acc (if not given) = 1.5 max_j vmax_j / amax_j
 * (quartic; max_j vmax_j / amax_j parabolic), so that the largest possible
 * velocity change 2 vmax_j keeps |qdd| <= amax_j, and T_i >= 2 t_acc; a
 * given t_acc that would need more than amax_j in a blend is KC_E_LIMIT. Lagrange, and splines and quintics whose knot
 * derivatives are all computed: the whole timing is then stretched by the
 * factor lambda = max(1, Vb / vmax, sqrt(Ab / amax), cbrt(Jb / jmax)) (per
 * joint), where Vb, Ab and Jb bound |qd|, |qdd| and |qddd| rigorously
 * (Bernstein coefficients on eight sub-intervals of each piece): the
 * stretched path keeps the three limits within its pieces (a cubic
 * spline's acceleration still jumps at its ends unless they are natural:
 * there no stretch helps; the controller runs such a path on ramps of its
 * own, kinctl/ctrl.h). With
 * given knot velocities the times follow the rule alone and the limits are
 * not checked. A segment with no motion gets T_i = 0 and is KC_E_ARG (except
 * for blends, where T_i >= 2 t_acc).
 *
 * Time law. A plan is a function of its plan time: the knot times fix how
 * fast the path runs and so its velocity, acceleration and jerk; nothing
 * here changes them. A caller that runs a path on another time law (the
 * controller's ramps of a path that does not start at rest, its stops on
 * the path and resumes, jerk-limited by default: kinctl/ctrl.h) evaluates
 * it at its own tau and applies the chain rule.
 *
 * Ticks: a plan keeps its tick period dt; tick k is plan time t = k dt
 * (computed from k, never accumulated), i.e. knot time t_origin + k dt.
 * kc_path.ticks is the first k with k dt >= duration (up to rounding of a
 * few units in the last place of duration/dt); from that tick on the state
 * is the end state: q exactly q_{n-1}, qd and qdd the method's values at
 * the end (zero where it ends at rest; the left limit of qdd for the
 * parabolic blend and cubic splines, whose acceleration jumps there).
 * Pieces are half-open [start, end): at a knot the piece on the right is
 * evaluated. Durations are capped at KC_PATH_MAX_TICKS ticks.
 *
 * Units: the joint coordinates' own (rad or m; the vectors use the seed's
 * units), seconds. Planning and evaluation allocate nothing, use no global
 * state and are safe in the control cycle. Costs measured here (x86-64,
 * -O2, double): a tick 15-35 ns in joint space (6 joints), 105-130 ns in
 * Cartesian space; planning 1-4 us for 6 knots x 6 joints with given times,
 * up to ~150 us for 32 knots x 16 joints when the limits stretch the
 * timing, 20-160 us for a Cartesian path (its length table): plan a long
 * path off the cycle, or accept the goal a cycle later.
 */
#ifndef KINCTL_PATH_H
#define KINCTL_PATH_H

#include <stdint.h>

#include "kinctl/chain.h"
#include "kinctl/decls.h"
#include "kinctl/real.h"
#include "kinctl/status.h"

KC_BEGIN_DECLS

/* Most knots of a path. */
#ifndef KC_PATH_MAX_KNOTS
#define KC_PATH_MAX_KNOTS 32
#endif
/* Most knots of a Lagrange path (degree 7). */
#define KC_PATH_MAX_LAGRANGE_KNOTS 8
/* Pieces: a blend path has n blends and n - 1 lines. */
#define KC_PATH_MAX_PIECES (2 * KC_PATH_MAX_KNOTS - 1)
/* Coefficients of a piece: degree 7 (Lagrange through 8 knots). */
#define KC_PATH_MAX_COEFFS KC_PATH_MAX_LAGRANGE_KNOTS
/* Longest path in ticks: 2^24, below which every k dt is exact in float. */
#define KC_PATH_MAX_TICKS 16777216
/* Path-length table of a Cartesian piece: uniform sub-intervals, plus
 * splits at up to KC_PATH_ARC_MINIMA local minima of the speed. */
#define KC_PATH_ARC_SPLITS 32
#define KC_PATH_ARC_MINIMA 4
#define KC_PATH_ARC_POINTS (KC_PATH_ARC_SPLITS + KC_PATH_ARC_MINIMA + 1)
/* A knot quaternion must have |norm - 1| below this; it is then normalised. */
#define KC_PATH_TOL_QUAT_NORM KC_R(1e-3)

typedef enum kc_path_method {
    KC_PATH_BLEND = 0,    /* lines with blends of half-length t_acc */
    KC_PATH_LAGRANGE = 1, /* one polynomial through every knot */
    KC_PATH_SPLINE = 2,   /* cubic: given knot velocities, or C2 */
    KC_PATH_QUINTIC = 3   /* quintic: C2 at the knots */
} kc_path_method;

typedef enum kc_path_blend {
    KC_PATH_BLEND_QUARTIC = 0,  /* Paul's quartic: C2 */
    KC_PATH_BLEND_PARABOLIC = 1 /* constant acceleration: C1 */
} kc_path_blend;

typedef enum kc_path_spline_end {
    KC_PATH_SPLINE_CLAMPED = 0, /* v = 0 at both ends (at rest) */
    KC_PATH_SPLINE_NATURAL = 1  /* q'' = 0 at both ends */
} kc_path_spline_end;

/* What a joint-space path is made of. Start from kc_path_cfg_default(). The
 * arrays are read during kc_path_plan only. */
typedef struct kc_path_cfg {
    kc_path_method method;
    kc_path_blend blend;           /* KC_PATH_BLEND only */
    kc_path_spline_end spline_end; /* KC_PATH_SPLINE without cfg.qd only */
    int n_knots;                   /* 2 .. KC_PATH_MAX_KNOTS */
    int dim;                       /* 1 .. KC_MAX_JOINTS */
    /* Knot positions, knot after knot: q[i * dim + j]. */
    const kc_real *q;
    /* n_knots knot times (s), strictly increasing; NULL: from the limits. */
    const kc_real *t;
    /* Knot velocities like q (spline, quintic), or NULL: computed. */
    const kc_real *qd;
    /* Knot accelerations like q (quintic), or NULL: computed. */
    const kc_real *qdd;
    /* Blend half-length (s): required with given times; 0 with computed
     * times means the rule above (1.5 max_j vmax_j / amax_j for quartic). */
    kc_real t_acc;
    /* Limits per coordinate (> 0) for computed times; unused with times.
     * jmax may be +infinity (kc_path_cfg_default's): jerk unbounded. */
    kc_real vmax[KC_MAX_JOINTS];
    kc_real amax[KC_MAX_JOINTS];
    kc_real jmax[KC_MAX_JOINTS];
    /* Tick period (s), > 0. */
    kc_real dt;
} kc_path_cfg;

/* A planned path. Plain data: copy it freely; read the fields, set them only
 * through kc_path_plan. Piece p covers plan time [start[p], start[p] +
 * len[p]) and is q = sum_i c[p][i][j] tau^i, tau = t - start[p]. */
typedef struct kc_path {
    kc_path_method method;
    kc_path_blend blend;
    int dim, n_knots, n_pieces;
    int n_coeffs; /* coefficients used per piece (degree + 1) */
    kc_real dt;
    int64_t ticks;     /* first tick with k dt >= duration */
    kc_real duration;  /* s */
    kc_real t_origin;  /* knot time of tick 0: t_0 - t_acc (blend) or t_0 */
    kc_real t_acc;     /* blend half-length used (s), 0 for other methods */
    kc_real stretch;   /* lambda of the limit stretch (1 when none) */
    kc_real t_knot[KC_PATH_MAX_KNOTS]; /* knot times used (knot time axis) */
    kc_real start[KC_PATH_MAX_PIECES];
    kc_real len[KC_PATH_MAX_PIECES];
    kc_real c[KC_PATH_MAX_PIECES][KC_PATH_MAX_COEFFS][KC_MAX_JOINTS];
    kc_real q_end[KC_MAX_JOINTS], qd_end[KC_MAX_JOINTS], qdd_end[KC_MAX_JOINTS];
} kc_path;

/* Quartic blends, clamped splines, no knots, no times, t_acc 0, limits 1,
 * dt 0.001 s. */
kc_path_cfg kc_path_cfg_default(void);

/* Plans a joint-space path (see above). Returns KC_OK, or, with *path
 * untouched:
 *   KC_E_ARG       NULL path/cfg/q, unknown method, dim out of 1..KC_MAX_JOINTS,
 *                  n_knots < 2, a non-finite number, times not strictly
 *                  increasing, t_acc <= 0 with given times or > min T_i / 2,
 *                  a limit <= 0 or NaN (computed times), qd/qdd given to a
 *                  method that takes none, dt <= 0, a segment without motion
 *                  with computed times;
 *   KC_E_CAPACITY  n_knots > KC_PATH_MAX_KNOTS (KC_PATH_MAX_LAGRANGE_KNOTS
 *                  for Lagrange), or more than KC_PATH_MAX_TICKS ticks;
 *   KC_E_LIMIT     a given t_acc too short for amax with computed times. */
kc_status kc_path_plan(kc_path *path, const kc_path_cfg *cfg);

/* State at tick k >= 0 (plan time k dt): q, qd, qdd (dim values each; qd
 * and qdd may be NULL). KC_OK while moving (k < ticks), KC_DONE from tick
 * `ticks` on (the end state), KC_E_ARG for NULL path/q or k < 0 (outputs
 * untouched). */
kc_status kc_path_eval(const kc_path *path, int64_t k, kc_real *q, kc_real *qd, kc_real *qdd);

/* State at plan time t >= 0 (s), off the tick grid: KC_OK for t <
 * duration, KC_DONE for t >= duration (end state), KC_E_ARG for NULL, NaN or
 * t < 0. */
kc_status kc_path_eval_time(const kc_path *path, kc_real t, kc_real *q, kc_real *qd, kc_real *qdd);

/* Piece p (0 .. n_pieces - 1) at its local time tau (any finite tau, also
 * past its end: for checking continuity where two pieces meet). KC_E_ARG for
 * NULL, p out of range or tau not finite. */
kc_status kc_path_eval_piece(const kc_path *path, int p, kc_real tau, kc_real *q, kc_real *qd, kc_real *qdd);

KC_END_DECLS

#endif /* KINCTL_PATH_H */
