/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * interp_helper.c - kinctl's motion planners and tick evaluation in one
 * precision, for interp_bench (issue 4).
 *
 * Compiled twice (kinctl_interp_double, kinctl_interp_float), like
 * kinctl_helper.c and for the same reason: the two core builds share their
 * symbol names. The driver runs `check` once per precision and `time` once
 * per timed block, interleaved with KDL's and Ruckig's blocks. Output
 * follows the protocol in bench_common.h.
 *
 * The motions and their input sets (all drawn with bench_common.h's
 * generator, fixed seeds, in double and rounded to kc_real once, outside any
 * timed loop):
 *   joint            kc_interp_joint: the puma560 move set of bench_common.h
 *                    with kinctl's puma560 rate limits;
 *   line-2rot/slerp  kc_interp_line between two random poses;
 *   arc              kc_interp_arc from a random pose through two random points;
 *   jpath-<method>   kc_path_plan, 6 joints, PATH_KNOTS knots uniform within
 *                    the puma560's limits, knot times from its rate limits;
 *   cpath-<method>   kc_path_cart_plan, PATH_KNOTS random poses, times from
 *                    CART_V/CART_A/CART_W/CART_DW;
 * with <method> blend-quartic, blend-parabolic, lagrange, spline-given
 * (random knot velocities, zero at the ends), spline-c2 (computed, clamped)
 * and quintic (computed knot velocities and accelerations). Random poses:
 * positions in a box in front of the arm, orientations the tool pointing
 * down turned by a random rotation vector of up to ORIENT_SPREAD rad per
 * component.
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "kinctl/kinctl.h"

#define N_JOINTS 6
#define PATH_KNOTS 8
#define CART_V 0.5  /* m/s */
#define CART_A 2.0  /* m/s^2 */
#define CART_W 1.5  /* rad/s */
#define CART_DW 6.0 /* rad/s^2 */
#define ORIENT_SPREAD 0.6
/* Given knot velocities: up to this fraction of the limit (joint) or this
 * many m/s per component (Cartesian). */
#define GIVEN_V_FRACTION 0.5
#define GIVEN_V_CART 0.1

static const double box_lo[3] = {0.3, -0.4, 0.1}, box_hi[3] = {0.7, 0.4, 0.7};

typedef enum { M_JOINT, M_LINE, M_ARC, M_JPATH, M_CPATH } motion_kind;

typedef struct motion {
    const char *name;
    motion_kind kind;
    kc_interp_orient orient; /* lines */
    kc_path_method method;   /* paths */
    kc_path_blend blend;
    int given; /* paths: knot velocities given */
} motion;

static const motion motions[] = {
    {"joint", M_JOINT, KC_INTERP_TWO_ROTATIONS, KC_PATH_BLEND, KC_PATH_BLEND_QUARTIC, 0},
    {"line-2rot", M_LINE, KC_INTERP_TWO_ROTATIONS, KC_PATH_BLEND, KC_PATH_BLEND_QUARTIC, 0},
    {"line-slerp", M_LINE, KC_INTERP_SLERP, KC_PATH_BLEND, KC_PATH_BLEND_QUARTIC, 0},
    {"arc", M_ARC, KC_INTERP_TWO_ROTATIONS, KC_PATH_BLEND, KC_PATH_BLEND_QUARTIC, 0},
    {"jpath-blend-quartic", M_JPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_BLEND, KC_PATH_BLEND_QUARTIC, 0},
    {"jpath-blend-parabolic", M_JPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_BLEND, KC_PATH_BLEND_PARABOLIC, 0},
    {"jpath-lagrange", M_JPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_LAGRANGE, KC_PATH_BLEND_QUARTIC, 0},
    {"jpath-spline-given", M_JPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_SPLINE, KC_PATH_BLEND_QUARTIC, 1},
    {"jpath-spline-c2", M_JPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_SPLINE, KC_PATH_BLEND_QUARTIC, 0},
    {"jpath-quintic", M_JPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_QUINTIC, KC_PATH_BLEND_QUARTIC, 0},
    {"cpath-blend-quartic", M_CPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_BLEND, KC_PATH_BLEND_QUARTIC, 0},
    {"cpath-blend-parabolic", M_CPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_BLEND, KC_PATH_BLEND_PARABOLIC, 0},
    {"cpath-lagrange", M_CPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_LAGRANGE, KC_PATH_BLEND_QUARTIC, 0},
    {"cpath-spline-given", M_CPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_SPLINE, KC_PATH_BLEND_QUARTIC, 1},
    {"cpath-spline-c2", M_CPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_SPLINE, KC_PATH_BLEND_QUARTIC, 0},
    {"cpath-quintic", M_CPATH, KC_INTERP_TWO_ROTATIONS, KC_PATH_QUINTIC, KC_PATH_BLEND_QUARTIC, 0},
};
#define N_MOTIONS ((int)(sizeof motions / sizeof motions[0]))

/* The input sets, in kc_real. Static: too big for the stack. */
static struct {
    kc_real qd_max[N_JOINTS], qdd_max[N_JOINTS], qddd_max[N_JOINTS];
    kc_real q0[BENCH_CONFIGS][BENCH_MAX_JOINTS], q1[BENCH_CONFIGS][BENCH_MAX_JOINTS];
    double frac[BENCH_CONFIGS];
    kc_pose from[BENCH_CONFIGS], to[BENCH_CONFIGS];
    kc_vec3 via[BENCH_CONFIGS];
    kc_real jq[BENCH_CONFIGS][PATH_KNOTS * N_JOINTS], jqd[BENCH_CONFIGS][PATH_KNOTS * N_JOINTS];
    kc_vec3 cp[BENCH_CONFIGS][PATH_KNOTS], cv[BENCH_CONFIGS][PATH_KNOTS];
    kc_quat cr[BENCH_CONFIGS][PATH_KNOTS];
    kc_interp_limits lim;
    kc_path_cfg jcfg;
    kc_path_cart_cfg ccfg;
} set;

/* Plans of the tick series, and the tick of each sample. */
static union {
    kc_interp_joint joint[BENCH_INTERP_TICK_PLANS];
    kc_interp_line line[BENCH_INTERP_TICK_PLANS];
    kc_interp_arc arc[BENCH_INTERP_TICK_PLANS];
    kc_path jpath[BENCH_INTERP_TICK_PLANS];
    kc_path_cart cpath[BENCH_INTERP_TICK_PLANS];
} plans;
static int64_t tick_of[BENCH_CONFIGS];
static double timings_ns[BENCH_BATCHES];

/* ---- random poses, in double ---- */

static double uniform(uint64_t *state, double lo, double hi)
{
    return lo + (hi - lo) * bench_uniform01(state);
}

static void random_point(uint64_t *state, double p[3])
{
    for (int i = 0; i < 3; i++)
        p[i] = uniform(state, box_lo[i], box_hi[i]);
}

/* The tool pointing down (Rx(pi): quaternion (0, 1, 0, 0)) times exp of a
 * random rotation vector r: (0, 1, 0, 0) (c, s r/|r|) with c = cos(|r|/2),
 * s = sin(|r|/2). */
static void random_orientation(uint64_t *state, double q[4])
{
    double r[3], n = 0.0;
    for (int i = 0; i < 3; i++) {
        r[i] = uniform(state, -ORIENT_SPREAD, ORIENT_SPREAD);
        n += r[i] * r[i];
    }
    n = sqrt(n);
    double c = cos(0.5 * n), s = n > 0.0 ? sin(0.5 * n) / n : 0.0;
    double e[4] = {c, s * r[0], s * r[1], s * r[2]};
    /* (0, 1, 0, 0) * (w, x, y, z) = (-x, w, -z, y) */
    q[0] = -e[1];
    q[1] = e[0];
    q[2] = -e[3];
    q[3] = e[2];
}

static kc_vec3 to_vec3(const double p[3])
{
    return kc_vec3_make((kc_real)p[0], (kc_real)p[1], (kc_real)p[2]);
}

static kc_quat to_quat(const double q[4])
{
    kc_quat r = {(kc_real)q[0], (kc_real)q[1], (kc_real)q[2], (kc_real)q[3]};
    return r;
}

/* Rotation matrix of a unit quaternion in double, rounded once. */
static kc_pose to_pose(const double p[3], const double q[4])
{
    double w = q[0], x = q[1], y = q[2], z = q[3];
    double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    kc_pose pose;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            pose.R.m[r][c] = (kc_real)R[r][c];
    pose.t = to_vec3(p);
    return pose;
}

static int setup(void)
{
    kc_chain chain;
    kc_status st = kc_chain_init_model(&chain, KC_MODEL_PUMA560, NULL);
    if (st != KC_OK || chain.n_joints != N_JOINTS) {
        printf("error: kc_chain_init_model(puma560): %s\n", kc_status_str(st));
        return 1;
    }
    for (int j = 0; j < N_JOINTS; j++) {
        set.qd_max[j] = chain.joints[j].limits.qd_max;
        set.qdd_max[j] = chain.joints[j].limits.qdd_max;
        set.qddd_max[j] = chain.joints[j].limits.qddd_max;
    }

    static double q0[BENCH_CONFIGS][BENCH_MAX_JOINTS], q1[BENCH_CONFIGS][BENCH_MAX_JOINTS];
    bench_make_moves(q0, q1, set.frac);
    for (int k = 0; k < BENCH_CONFIGS; k++)
        for (int j = 0; j < BENCH_MAX_JOINTS; j++) {
            set.q0[k][j] = (kc_real)q0[k][j];
            set.q1[k][j] = (kc_real)q1[k][j];
        }

    /* One stream per kind of input, so that one set does not move another. */
    uint64_t s_line = BENCH_INTERP_SEED + 1, s_jpath = BENCH_INTERP_SEED + 2, s_cpath = BENCH_INTERP_SEED + 3;
    for (int k = 0; k < BENCH_CONFIGS; k++) {
        double p[3], q[4], via[3];
        random_point(&s_line, p);
        random_orientation(&s_line, q);
        set.from[k] = to_pose(p, q);
        random_point(&s_line, p);
        random_orientation(&s_line, q);
        set.to[k] = to_pose(p, q);
        random_point(&s_line, via);
        set.via[k] = to_vec3(via);

        for (int i = 0; i < PATH_KNOTS; i++) {
            double qk[BENCH_MAX_JOINTS];
            bench_uniform_q(BENCH_PUMA560, &s_jpath, qk);
            for (int j = 0; j < N_JOINTS; j++) {
                double v = uniform(&s_jpath, -GIVEN_V_FRACTION, GIVEN_V_FRACTION) * (double)set.qd_max[j];
                set.jq[k][i * N_JOINTS + j] = (kc_real)qk[j];
                set.jqd[k][i * N_JOINTS + j] = (kc_real)(i == 0 || i == PATH_KNOTS - 1 ? 0.0 : v);
            }
            double v[3];
            random_point(&s_cpath, p);
            random_orientation(&s_cpath, q);
            for (int c = 0; c < 3; c++)
                v[c] = i == 0 || i == PATH_KNOTS - 1 ? 0.0 : uniform(&s_cpath, -GIVEN_V_CART, GIVEN_V_CART);
            set.cp[k][i] = to_vec3(p);
            set.cr[k][i] = to_quat(q);
            set.cv[k][i] = to_vec3(v);
        }
    }

    set.lim = kc_interp_limits_default();
    set.lim.v = (kc_real)CART_V;
    set.lim.a = (kc_real)CART_A;
    set.lim.w = (kc_real)CART_W;
    set.lim.dw = (kc_real)CART_DW;

    set.jcfg = kc_path_cfg_default();
    set.jcfg.n_knots = PATH_KNOTS;
    set.jcfg.dim = N_JOINTS;
    for (int j = 0; j < N_JOINTS; j++) {
        set.jcfg.vmax[j] = set.qd_max[j];
        set.jcfg.amax[j] = set.qdd_max[j];
    }
    set.jcfg.dt = (kc_real)BENCH_INTERP_DT;

    set.ccfg = kc_path_cart_cfg_default();
    set.ccfg.n_knots = PATH_KNOTS;
    set.ccfg.v_max = (kc_real)CART_V;
    set.ccfg.a_max = (kc_real)CART_A;
    set.ccfg.w_max = (kc_real)CART_W;
    set.ccfg.alpha_max = (kc_real)CART_DW;
    set.ccfg.dt = (kc_real)BENCH_INTERP_DT;
    return 0;
}

/* ---- planning: input k of the set into plan slot `slot` ---- */

/* The path configurations as a caller fills them: the method's fields
 * over the template, the knots of input k. */
static inline kc_status plan_jpath(const motion *m, int k, kc_path *dest)
{
    kc_path_cfg cfg = set.jcfg;
    cfg.method = m->method;
    cfg.blend = m->blend;
    cfg.q = set.jq[k];
    cfg.qd = m->given ? set.jqd[k] : NULL;
    return kc_path_plan(dest, &cfg);
}

static inline kc_status plan_cpath(const motion *m, int k, kc_path_cart *dest)
{
    kc_path_cart_cfg cfg = set.ccfg;
    cfg.method = m->method;
    cfg.blend = m->blend;
    cfg.p = set.cp[k];
    cfg.r = set.cr[k];
    cfg.v = m->given ? set.cv[k] : NULL;
    return kc_path_cart_plan(dest, &cfg);
}

static const kc_real dt = (kc_real)BENCH_INTERP_DT;

/* Plans input k into plans.<kind>[slot]; *ticks gets its duration in ticks. */
static kc_status plan_slot(const motion *m, int k, int slot, int64_t *ticks)
{
    kc_status st = KC_E_ARG;
    switch (m->kind) {
    case M_JOINT:
        st = kc_interp_joint_plan(&plans.joint[slot], N_JOINTS, set.q0[k], set.q1[k], set.qd_max, set.qdd_max,
                                  (kc_real)0.0, dt);
        *ticks = plans.joint[slot].prof.ticks;
        break;
    case M_LINE:
        st = kc_interp_line_plan(&plans.line[slot], &set.from[k], &set.to[k], &set.lim, m->orient, dt);
        *ticks = plans.line[slot].prof.ticks;
        break;
    case M_ARC:
        st = kc_interp_arc_plan(&plans.arc[slot], &set.from[k], &set.via[k], &set.to[k].t, &set.lim, dt);
        *ticks = plans.arc[slot].prof.ticks;
        break;
    case M_JPATH:
        st = plan_jpath(m, k, &plans.jpath[slot]);
        *ticks = plans.jpath[slot].ticks;
        break;
    case M_CPATH:
        st = plan_cpath(m, k, &plans.cpath[slot]);
        *ticks = plans.cpath[slot].pos.ticks;
        break;
    }
    return st;
}

/* The tick series' plans (the first BENCH_INTERP_TICK_PLANS inputs) and
 * the tick of every sample. */
static int prepare_ticks(const motion *m)
{
    for (int p = 0; p < BENCH_INTERP_TICK_PLANS; p++) {
        int64_t ticks = 0;
        kc_status st = plan_slot(m, p, p, &ticks);
        if (st != KC_OK) {
            printf("error %s: input %d: %s\n", m->name, p, kc_status_str(st));
            return 1;
        }
        for (int i = 0; i < BENCH_INTERP_TICKS_PER_PLAN; i++) {
            int k = p * BENCH_INTERP_TICKS_PER_PLAN + i;
            tick_of[k] = bench_interp_tick(set.frac[k], ticks);
        }
    }
    return 0;
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* Every motion planned over the whole set (counts and durations), then the
 * joint moves that the driver compares with KDL. */
static int check(void)
{
    printf("limits");
    for (int j = 0; j < N_JOINTS; j++)
        printf(" %.17g", (double)set.qd_max[j]);
    for (int j = 0; j < N_JOINTS; j++)
        printf(" %.17g", (double)set.qdd_max[j]);
    for (int j = 0; j < N_JOINTS; j++)
        printf(" %.17g", (double)set.qddd_max[j]);
    printf("\n");
    static int64_t ticks[BENCH_CONFIGS];
    for (int mi = 0; mi < N_MOTIONS; mi++) {
        int ok = 0;
        for (int k = 0; k < BENCH_CONFIGS; k++) {
            kc_status st = plan_slot(&motions[mi], k, 0, &ticks[ok]);
            if (st == KC_OK)
                ok++;
            else
                printf("status %s %d %s\n", motions[mi].name, k, kc_status_str(st));
        }
        qsort(ticks, (size_t)ok, sizeof ticks[0], cmp_i64);
        printf("motion %s %d %d %lld %lld %lld\n", motions[mi].name, ok, BENCH_CONFIGS,
               ok ? (long long)ticks[0] : -1LL, ok ? (long long)ticks[ok / 2] : -1LL,
               ok ? (long long)ticks[ok - 1] : -1LL);
    }
    for (int k = 0; k < BENCH_CHECKS; k++) {
        kc_interp_joint *plan = &plans.joint[0];
        kc_status st = kc_interp_joint_plan(plan, N_JOINTS, set.q0[k], set.q1[k], set.qd_max, set.qdd_max,
                                            (kc_real)0.0, dt);
        if (st != KC_OK) {
            printf("error joint %d: %s\n", k, kc_status_str(st));
            return 1;
        }
        printf("joint %d %.17g %lld %d\n", k, (double)plan->prof.T, (long long)plan->prof.ticks, plan->lead);
        for (int i = 0; i < BENCH_INTERP_CHECK_POINTS; i++) {
            int64_t tick = (int64_t)(bench_interp_check_at[i] * (double)plan->prof.ticks);
            kc_interp_joint_state s;
            kc_interp_joint_eval(plan, tick, &s);
            printf("pos %d %lld", k, (long long)tick);
            for (int j = 0; j < N_JOINTS; j++)
                printf(" %.17g", (double)s.q[j]);
            printf("\n");
        }
    }
    return 0;
}

/* ---- timing ---- */

/* Plan series: call k plans input k (into one output, as a controller
 * replans into its own plan). Tick series: sample k evaluates tick_of[k] of
 * plan k / BENCH_INTERP_TICKS_PER_PLAN. The checksum reads one output of
 * every call, so no call can be dropped as dead code. */
static int time_block(const motion *m, int tick, int n_batches)
{
    double sum = 0.0;
    if (!tick) {
        int64_t ticks = 0;
        BENCH_TIME(timings_ns, n_batches, plan_slot(m, k, 0, &ticks); sum += (double)ticks);
    } else {
        if (prepare_ticks(m) != 0)
            return 1;
        const int per = BENCH_INTERP_TICKS_PER_PLAN;
        switch (m->kind) {
        case M_JOINT: {
            kc_interp_joint_state s;
            BENCH_TIME(timings_ns, n_batches, kc_interp_joint_eval(&plans.joint[k / per], tick_of[k], &s);
                       sum += (double)s.q[0]);
            break;
        }
        case M_LINE: {
            kc_interp_cart_state s;
            BENCH_TIME(timings_ns, n_batches, kc_interp_line_eval(&plans.line[k / per], tick_of[k], &s);
                       sum += (double)s.p.v[0]);
            break;
        }
        case M_ARC: {
            kc_interp_cart_state s;
            BENCH_TIME(timings_ns, n_batches, kc_interp_arc_eval(&plans.arc[k / per], tick_of[k], &s);
                       sum += (double)s.p.v[0]);
            break;
        }
        case M_JPATH: {
            kc_real q[N_JOINTS], qd[N_JOINTS], qdd[N_JOINTS];
            BENCH_TIME(timings_ns, n_batches, kc_path_eval(&plans.jpath[k / per], tick_of[k], q, qd, qdd);
                       sum += (double)q[0]);
            break;
        }
        case M_CPATH: {
            kc_path_pose s;
            BENCH_TIME(timings_ns, n_batches, kc_path_cart_eval(&plans.cpath[k / per], tick_of[k], &s);
                       sum += (double)s.p.v[0]);
            break;
        }
        }
    }
    bench_print_block(timings_ns, n_batches, sum);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "check") == 0)
        return setup() != 0 || check() != 0;
    if (argc == 5 && strcmp(argv[1], "time") == 0) {
        int n_batches = atoi(argv[4]);
        int tick = strcmp(argv[3], "tick") == 0;
        for (int mi = 0; mi < N_MOTIONS; mi++)
            if (strcmp(argv[2], motions[mi].name) == 0 && (tick || strcmp(argv[3], "plan") == 0) &&
                n_batches > 0 && n_batches <= BENCH_BATCHES)
                return setup() != 0 || time_block(&motions[mi], tick, n_batches) != 0;
    }
    printf("usage: %s check | time <motion> <plan|tick> <batches 1..%d>\nmotions:", argv[0], BENCH_BATCHES);
    for (int mi = 0; mi < N_MOTIONS; mi++)
        printf(" %s", motions[mi].name);
    printf("\n");
    return 2;
}
