/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * testutil.h - shared helpers of the kinctl unit tests: reference-vector
 * loading (tests/vectors, found through $KINCTL_VECTORS), comparisons with an
 * absolute tolerance that report which element failed and by how much, a
 * deterministic PRNG for property tests, and the tolerances of both
 * precisions, defined once here.
 *
 * Every comparison is done in double: an expected value read from JSON is
 * never rounded to kc_real first, so a float build is judged against the
 * double reference, not against a rounded copy of it.
 */
#ifndef KINCTL_TESTUTIL_H
#define KINCTL_TESTUTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <jansson.h>

#include "kinctl/kinctl.h"

/*
 * Tolerances (absolute), per quantity and precision.
 *
 * double: the reference files' own tolerances (vectors/README.md):
 *   1e-12 for transforms, orientation matrices, FK and Jacobians, code
 *   chains; 1e-9 for round trips and extracted angles.
 *
 * float (unit roundoff u = KC_REAL_EPS / 2 = 6e-8, KC_REAL_EPS = 1.2e-7):
 *   - KT_TOL_T 1e-5: entries of transforms, positions and Jacobians. Every
 *     input (angle, length, q) is rounded to float (relative u), and a chain
 *     has at most ~30 elementary transforms, each adding about 2u relative
 *     to quantities of at most ~1.5 m (pyramid coordinates of at most ~7 units
 *     pass through one product): 30 * 2 * 6e-8 * 1.5 = 5.4e-6, so 1e-5 bounds
 *     it with less than a factor 2 of headroom.
 *   - KT_TOL_RT 1e-5: round trips through a few float conversions of unit
 *     quantities (quaternion <-> matrix, dual quaternion, Euler angles):
 *     tens of roundings of values <= 1, i.e. ~10-30 u = 0.6e-6..2e-6, with
 *     the angle-to-matrix conditioning <= ~2.
 *   - KT_TOL_ANGLE 1e-5: an angle extracted by atan2 from float matrix
 *     entries that are well conditioned (the denominator, e.g. cos(theta)
 *     for RPY, of order 1); the ill-conditioned near-gimbal case adds
 *     KT_TOL_ENTRY / denominator explicitly (see kt_euler_angle_tol users).
 *   - KT_TOL_ENTRY: the rounding carried by an entry of a rotation matrix
 *     built or read in this precision, 4 KC_REAL_EPS (both precisions).
 */
#ifdef KC_REAL_FLOAT
#define KT_TOL_T 1e-5
#define KT_TOL_RT 1e-5
#define KT_TOL_ANGLE 1e-5
#else
#define KT_TOL_T 1e-12
#define KT_TOL_RT 1e-9
#define KT_TOL_ANGLE 1e-9
#endif
#define KT_TOL_ENTRY (4.0 * (double)KC_REAL_EPS)

#define KT_PI 3.14159265358979323846

/* ---- reference vectors ---- */

/* Loads $KINCTL_VECTORS/<name>; fails the current test with a clear message
 * when the variable is unset or the file cannot be read or parsed. The
 * caller owns the result (json_decref). */
json_t *kt_load(const char *name);
/* Member of an object, failing the test when absent. */
json_t *kt_get(const json_t *obj, const char *key);
/* Element i of an array, failing the test when out of range. */
json_t *kt_at(const json_t *arr, size_t i);
/* A number (integer or real), failing the test otherwise. */
double kt_num(const json_t *v);
/* kt_num(kt_get(obj, key)). */
double kt_num_of(const json_t *obj, const char *key);
/* Reads an array of exactly n numbers. */
void kt_read_reals(const json_t *arr, kc_real *out, size_t n);
void kt_read_mat3(const json_t *m, kc_mat3 *out);
void kt_read_mat4(const json_t *m, kc_mat4 *out);
/* A 4x4 homogeneous transform as a pose (R and t copied, last row checked
 * to be 0 0 0 1); does not go through kc_pose_from_mat4. */
void kt_read_pose(const json_t *m, kc_pose *out);

/* ---- comparisons ---- */

/* Each compares element by element in double, counts every element
 * compared (kt_checks), and on the first failure prints the label, the
 * element index, actual, expected, |difference| and the tolerance, then
 * fails the test at the caller's file and line. */
#define kt_near(a, e, tol, what) kt_near_(__FILE__, __LINE__, (a), (e), (tol), (what))
#define kt_near_angle(a, e, tol, what) kt_near_angle_(__FILE__, __LINE__, (a), (e), (tol), (what))
#define kt_near_reals_json(a, n, arr, tol, what) kt_near_reals_json_(__FILE__, __LINE__, (a), (n), (arr), (tol), (what))
#define kt_near_mat3_json(a, m, tol, what) kt_near_mat3_json_(__FILE__, __LINE__, (a), (m), (tol), (what))
#define kt_near_mat4_json(a, m, tol, what) kt_near_mat4_json_(__FILE__, __LINE__, (a), (m), (tol), (what))
#define kt_near_pose_json(a, m, tol, what) kt_near_pose_json_(__FILE__, __LINE__, (a), (m), (tol), (what))
#define kt_near_mat3(a, b, tol, what) kt_near_mat3_(__FILE__, __LINE__, (a), (b), (tol), (what))
#define kt_near_pose(a, b, tol, what) kt_near_pose_(__FILE__, __LINE__, (a), (b), (tol), (what))
#define kt_near_vec3(a, b, tol, what) kt_near_vec3_(__FILE__, __LINE__, (a), (b), (tol), (what))
#define kt_near_quat_json(a, arr, tol, what) kt_near_quat_json_(__FILE__, __LINE__, (a), (arr), (tol), (what))
#define kt_near_quat(a, b, tol, what) kt_near_quat_(__FILE__, __LINE__, (a), (b), (tol), (what))
#define kt_near_jac_json(a, n, m, tol, what) kt_near_jac_json_(__FILE__, __LINE__, (a), (n), (m), (tol), (what))

void kt_near_(const char *file, int line, double a, double e, double tol, const char *what);
/* Angles compared modulo 2 pi. */
void kt_near_angle_(const char *file, int line, double a, double e, double tol, const char *what);
void kt_near_reals_json_(const char *file, int line, const kc_real *a, size_t n, const json_t *arr, double tol,
                         const char *what);
void kt_near_mat3_json_(const char *file, int line, const kc_mat3 *a, const json_t *m, double tol, const char *what);
void kt_near_mat4_json_(const char *file, int line, const kc_mat4 *a, const json_t *m, double tol, const char *what);
/* A pose against a 4x4 homogeneous matrix (rows 1-3; row 4 must be 0 0 0 1). */
void kt_near_pose_json_(const char *file, int line, const kc_pose *a, const json_t *m, double tol, const char *what);
void kt_near_mat3_(const char *file, int line, const kc_mat3 *a, const kc_mat3 *b, double tol, const char *what);
void kt_near_pose_(const char *file, int line, const kc_pose *a, const kc_pose *b, double tol, const char *what);
void kt_near_vec3_(const char *file, int line, const kc_vec3 *a, const kc_vec3 *b, double tol, const char *what);
/* Quaternions as rotations: q and -q are accepted only when the expected w
 * is zero within tol (w >= 0 then no longer fixes the sign). */
void kt_near_quat_json_(const char *file, int line, const kc_quat *a, const json_t *wxyz, double tol,
                        const char *what);
void kt_near_quat_(const char *file, int line, const kc_quat *a, const kc_quat *b, double tol, const char *what);
/* The first n columns of a Jacobian against a 6 x n nested list. */
void kt_near_jac_json_(const char *file, int line, const kc_jacobian *a, int n, const json_t *m, double tol,
                       const char *what);

/* Number of scalar comparisons made so far (reported by kt_report). */
extern unsigned long kt_checks;
/* Prints "<suite> (<precision>): N scalar comparisons" to stdout. */
/* A joint goal to q (n joints) at the full limits, queued. */
kc_goal kt_joint_goal(int64_t id, const kc_real *q, int n);
/* A line goal to the pose to at the full limits, slerp orientation, queued. */
kc_goal kt_line_goal(int64_t id, const kc_pose *to);
/* A Cartesian path goal by method through the n (<= KC_PATH_MAX_KNOTS - 1)
 * positions at (after the start), in orientation R, at the full limits,
 * computed times, queued. */
kc_goal kt_cart_path_goal(int64_t id, kc_path_method method, const kc_vec3 *at, int n, const kc_mat3 *R);
/* 1 when the controller's output out carries an event of kind for goal id. */
int kt_has_event(const kc_ctrl_output *out, kc_ctrl_event_kind kind, int64_t id);
/* The PUMA 560 pose the controller suites start from: clear of every joint
 * limit and singularity, the tool in front of the arm. */
extern const kc_real KT_PUMA_Q0[6];
/* A Panda pose off its rest (mid-range), so that the IK step's null-space
 * motion pulls the joints while the tool moves. */
extern const kc_real KT_PANDA_Q0[7];
/* Where the servo suites start an arm: KT_PUMA_Q0 for the PUMA 560, every
 * joint at the middle of its limits for another. */
void kt_start_q(const kc_chain *chain, kc_model model, kc_real *q);

/* Where the tool comes to rest if ctrl's motion stops on its path now: a
 * STOP stepped on *sim, a copy of ctrl, to IDLE (failing the test after
 * 20,000 ticks); *sim is left at that rest. */
kc_pose kt_rest_on_stop(kc_ctrl *sim, const kc_ctrl *ctrl);

void kt_report(const char *suite);

/* Fills a buffer with a recognisable byte, to prove an output untouched. */
#define KT_SENTINEL 0xA5
int kt_is_sentinel(const void *p, size_t n);

/* ---- trajectory reference data (joint_trapezoid, cartesian_line, circle) ---- */

/* The files' 1e-9 in double; in float 64 KC_REAL_EPS times the case's
 * largest value of the quantity (at least 1): the float build rounds every
 * input and t = k dt, and each value takes a few tens of roundings. */
double kt_traj_tol(double scale);
/* Largest |x| over a JSON array of numbers or of arrays of numbers. */
double kt_max_abs_json(const json_t *arr);
/* Whether the index i is listed in a JSON array of indices (the files'
 * *_ambiguous_indices). */
int kt_index_listed(const json_t *list, size_t i);

/* ---- deterministic PRNG (splitmix64) ---- */

/* How many of a test's n random cases to run: n, or the share of them
 * that the environment's KINCTL_TEST_SHARE asks for (0 < share <= 1; at
 * least one case). tests/analysis/memcheck.py sets it: valgrind checks
 * the code each case runs, and a share of the cases runs the same code in
 * a fraction of the time. The suites' own runs keep every case. A value
 * that is not such a share fails the test. */
int kt_cases(int n);

typedef struct kt_rng {
    uint64_t s;
} kt_rng;

kt_rng kt_rng_make(uint64_t seed);
uint64_t kt_rng_next(kt_rng *r);
/* Uniform in [lo, hi). */
double kt_uniform(kt_rng *r, double lo, double hi);
/* Uniformly distributed rotation (Shoemake's method) as a unit quaternion
 * with w >= 0. */
kc_quat kt_rand_quat(kt_rng *r);
/* Random rigid pose: uniform rotation, translation in [-2, 2]^3 m. */
kc_pose kt_rand_pose(kt_rng *r);
/* Random unit vector. */
kc_vec3 kt_rand_unit(kt_rng *r);
/* kt_cart_path_goal through two knots in from's orientation, each in a
 * random direction lo to hi m from the one before (the first from
 * from's position). */
kc_goal kt_cart_path_walk(kt_rng *r, int64_t id, kc_path_method method, const kc_pose *from, double lo, double hi);
/* Random joint vector inside the chain's position limits (an infinite
 * limit is replaced by -pi or pi). */
void kt_rand_q(kt_rng *r, const kc_chain *chain, kc_real *q);

/* A servo stream for the controller suites: the tool's position moves
 * from start by amp (sin(w t + phi) - sin(phi)) along each axis, amp up
 * to 3 cm and w 0.5-5 rad/s, drawn by kt_stream_init (tool speeds up to
 * about 0.25 m/s, accelerations up to about 1.3 m/s^2); its orientation
 * stays start's. */
typedef struct kt_stream {
    kc_pose start;
    double dt;
    double amp[3], w[3], phi[3];
    long t; /* ticks streamed */
} kt_stream;

void kt_stream_init(kt_stream *s, kt_rng *r, const kc_pose *start, double dt);
/* The stream's next message for servo goal id (at the full limits). */
kc_goal kt_stream_next(kt_stream *s, int64_t id);

/* Where a random line goal may go (kt_checked_line): a length in
 * [len_lo, len_hi) m along a random direction from home, the tool turned
 * about a random axis by up to turn rad (0: in home's orientation, no
 * axis drawn), and the goal's speed, accel and jerk (0: the defaults). */
typedef struct kt_line_draw {
    double len_lo, len_hi, turn;
    kc_real speed, accel, jerk;
} kt_line_draw;

/* Line goal id as d draws it from home that the dry run (kinctl/check.h)
 * takes from joints q, as the daemon would: lines the arm cannot follow
 * (near a singularity: a tracking fault) are drawn again, up to 100 times
 * (then the test fails). */
kc_goal kt_checked_line(kt_rng *r, kc_check *check, const kc_real *q, const kc_pose *home, int64_t id,
                        const kt_line_draw *d);

/* A line or (arc set) an arc, goal id, of 5 to 30 cm from home's position
 * in its orientation along a random direction, the arc through a point
 * within 5 cm of the chord's middle; at the default Cartesian limits, or
 * (fast set) at speed 0.05-0.5 m/s, accel 2-8 times it and jerk 5-20
 * times that. */
kc_goal kt_cart_goal(kt_rng *r, int64_t id, const kc_pose *home, int arc, int fast);

/* The largest change of a joint's qdd over a tick, in units of its
 * qddd_max dt, of goal g stepped on ctrl (initialised here at rest at q0,
 * the controller's default configuration at period dt) to its end, which
 * must be COMPLETED without a fault. */
double kt_stepped_jerk(kc_ctrl *ctrl, const kc_chain *chain, const kc_real *q0, const kc_goal *g, kc_real dt);

/* A dry run of goal g into verdict v, as a test sets it up (from rest,
 * from a snapshot): kc_check_goal's status. */
typedef kc_status (*kt_judge_fn)(const kc_goal *g, kc_verdict *v, void *ctx);

/* Goal g as kinctld hands it on (daemon/checker.c), before any stop
 * first: judged by judge, and where taken with its joints' jerk over
 * their limits, slowed by cfg's defaults (kc_goal_slow) along
 * kc_check_slow's search, up to KC_CHECK_SLOW_PASSES dry runs; *g and *v
 * become the best the search found. Returns the status of the goal as
 * asked. */
kc_status kt_judge_slowed(kt_judge_fn judge, void *ctx, const kc_ctrl_cfg *cfg, kc_goal *g, kc_verdict *v);

/* The dry runs of a slowed goal the last kt_judge_slowed made, and the
 * first of them within the limits (1 ..; 0: none was). */
extern int kt_slow_passes, kt_slow_first_within;

/* An independent rest-to-rest optimum of a jerk-limited move over distance
 * D >= 0 within V, A, J: not kinctl/scurve.h's closed form, but from the
 * physics of one symmetric half. Reaching a speed v from rest and stopping
 * again, each as fast as A and J allow, takes ta(v) = v / A + A / J when
 * v >= A^2 / J (the acceleration saturates) and 2 sqrt(v / J) otherwise,
 * over the distance v ta(v) (the mean speed of an acceleration symmetric
 * in time is v / 2, twice). The fastest move cruises at the largest v <= V
 * with v ta(v) <= D, found by bisection, for T = 2 ta(v) + (D - v ta(v)) / v. */
double kt_scurve_optimum_time(double D, double V, double A, double J);

#endif /* KINCTL_TESTUTIL_H */
