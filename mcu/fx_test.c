/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * fx_test.c - the fixed-point kinematics (kinctl/fx.h) against the double
 * build: for every built-in arm, FK and the Jacobian at random
 * configurations inside the joint limits (infinite limits: +-pi), and
 * kc_fx_sincos over the whole Q3.28 range of a joint. Built against the
 * double core for the host and for the boards (soft double there: the
 * reference only), so the same program judges the M3, the M4F and x86.
 *
 * Tolerances (issue 20): tool position 1e-6 m, rotation entries 1e-6; the
 * Jacobian's linear rows 1e-6 m/rad, angular rows 1e-6; sine and cosine
 * 4e-9 (kinctl/fx.h's analysis). The joint values are rounded to fixed
 * point first and the double FK is evaluated at the rounded values, so the
 * errors are the fixed-point arithmetic's alone. Prints the largest errors
 * per arm; exit status 1 when one exceeds its tolerance.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "kinctl/kinctl.h"

#define N_CONFIGS 500
#define TOL_POS 1e-6
#define TOL_ROT 1e-6
#define TOL_JAC 1e-6
#define TOL_SINCOS 4e-9
#define TOL_JOINT_MOVE 2e-8 /* rad: kinctl/fx.h, |dq| 2e-9 + 3.8e-9 for moves up to 2 pi */
#define N_MOVES 20
#define N_LINES 10 /* of each orientation method */

static kc_chain chain;
static kc_fx_chain fx;

static uint64_t rng = 20240601u;

/* Uniform in [0, 1) (splitmix64). */
static double uniform(void)
{
    uint64_t z = (rng += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (double)(z >> 11) / 9007199254740992.0;
}

static double max_abs(double a, double b) { return fabs(a) > b ? fabs(a) : b; }

static int check(const char *what, double err, double tol)
{
    int ok = err <= tol;
    printf("  %-22s max error %.3e  (tolerance %.0e)%s\n", what, err, tol, ok ? "" : "  FAIL");
    return ok ? 0 : 1;
}

static int test_sincos(void)
{
    double err = 0.0;
    for (int i = 0; i < 20000; i++) {
        int32_t a = (int32_t)((uniform() * 2.0 - 1.0) * 2147483647.0), s, c;
        kc_fx_sincos(a, &s, &c);
        double x = (double)a / (double)(1 << KC_FX_ANGLE_BITS);
        err = max_abs((double)s / (double)KC_FX_ONE_ROT - sin(x), err);
        err = max_abs((double)c / (double)KC_FX_ONE_ROT - cos(x), err);
    }
    printf("sincos (Q3.28 -> Q2.30), 20000 angles in (-8, 8) rad\n");
    return check("sin, cos", err, TOL_SINCOS);
}

static int test_model(kc_model model)
{
    if (kc_chain_init_model(&chain, model, NULL) != KC_OK || kc_fx_chain_init(&fx, &chain) != KC_OK) {
        printf("FAIL: %s: cannot build the chain\n", kc_model_name(model));
        return 1;
    }
    double e_pos = 0.0, e_rot = 0.0, e_jv = 0.0, e_jw = 0.0;
    const double pos_unit = (double)(1 << KC_FX_POS_BITS), rot_unit = (double)KC_FX_ONE_ROT;
    for (int n = 0; n < N_CONFIGS; n++) {
        kc_real q[KC_MAX_JOINTS], qr[KC_MAX_JOINTS];
        int32_t qf[KC_MAX_JOINTS];
        for (int j = 0; j < chain.n_joints; j++) {
            double lo = (double)chain.joints[j].limits.q_min, hi = (double)chain.joints[j].limits.q_max;
            if (!isfinite(lo))
                lo = -(double)KC_PI;
            if (!isfinite(hi))
                hi = (double)KC_PI;
            q[j] = (kc_real)(lo + (hi - lo) * uniform());
        }
        if (kc_fx_q_from_real(&fx, q, qf) != KC_OK) {
            printf("FAIL: %s: q out of the fixed-point range\n", kc_model_name(model));
            return 1;
        }
        for (int j = 0; j < chain.n_joints; j++)
            qr[j] = (kc_real)qf[j] / (kc_real)(1 << (fx.revolute[j] ? KC_FX_ANGLE_BITS : KC_FX_POS_BITS));
        kc_pose T;
        kc_jacobian J;
        kc_fx_pose Tf, Tj;
        kc_fx_jacobian Jf;
        kc_fk_jacobian(&chain, qr, &J, &T);
        kc_fx_fk_eval(&fx, qf, &Tf);
        kc_fx_jacobian_eval(&fx, qf, &Jf, &Tj);
        for (int r = 0; r < 3; r++) {
            e_pos = max_abs((double)Tf.t[r] / pos_unit - (double)T.t.v[r], e_pos);
            for (int k = 0; k < 3; k++)
                e_rot = max_abs((double)Tf.R[r][k] / rot_unit - (double)T.R.m[r][k], e_rot);
            if (Tj.t[r] != Tf.t[r]) {
                printf("FAIL: %s: the Jacobian's tool pose differs from kc_fx_fk_eval's\n", kc_model_name(model));
                return 1;
            }
        }
        for (int j = 0; j < chain.n_joints; j++)
            for (int r = 0; r < 3; r++) {
                e_jv = max_abs((double)Jf.m[r][j] / pos_unit - (double)J.m[r][j], e_jv);
                e_jw = max_abs((double)Jf.m[r + 3][j] / rot_unit - (double)J.m[r + 3][j], e_jw);
            }
    }
    printf("%s: %d joints, %d elements, %d configurations\n", kc_model_name(model), chain.n_joints, chain.n_elements,
           N_CONFIGS);
    return check("tool position (m)", e_pos, TOL_POS) + check("rotation entries", e_rot, TOL_ROT) +
           check("Jacobian linear (m/rad)", e_jv, TOL_JAC) + check("Jacobian angular", e_jw, TOL_JAC);
}

/* A joint move of the PUMA 560 between random configurations inside its
 * limits, into plan: the trapezoid at its limits; jerk-limited at its
 * limits (their ratios the same on every joint: synchronised by phase, a
 * straight line) or, with `own`, at random limits of each joint's own
 * (mostly by time). */
static kc_status random_move(kc_interp_joint *plan, kc_profile_kind kind, int own)
{
    kc_interp_joint_cfg c = kc_interp_joint_cfg_default();
    c.n = 6;
    c.dt = KC_R(0.001);
    c.profile = kind;
    for (int j = 0; j < 6; j++) {
        const kc_joint_limits *l = &chain.joints[j].limits;
        c.q0[j] = l->q_min + (l->q_max - l->q_min) * (kc_real)uniform();
        c.q1[j] = l->q_min + (l->q_max - l->q_min) * (kc_real)uniform();
        c.qd_max[j] = own ? KC_R(0.5) + KC_R(2.5) * (kc_real)uniform() : l->qd_max;
        c.qdd_max[j] = own ? KC_R(2.0) + KC_R(18.0) * (kc_real)uniform() : l->qdd_max;
        c.qddd_max[j] = own ? KC_R(20.0) + KC_R(480.0) * (kc_real)uniform() : l->qddd_max;
    }
    return kc_interp_joint_plan_cfg(plan, &c);
}

/* Joint moves of the PUMA 560 (random_move: N_MOVES of each law, the
 * jerk-limited ones half at the arm's limits and half at random ones), every tick against
 * kc_interp_joint_eval of the double build (kinctl/fx.h: the plan is made
 * once in floating point). */
static int test_joint_moves(void)
{
    if (kc_chain_init_model(&chain, KC_MODEL_PUMA560, NULL) != KC_OK || kc_fx_chain_init(&fx, &chain) != KC_OK)
        return 1;
    double err[2] = {0.0, 0.0}; /* the trapezoid's, the jerk-limited moves' */
    long ticks = 0;
    int done_exact = 1, by_time = 0, by_phase = 0;
    for (int n = 0; n < 3 * N_MOVES; n++) {
        kc_profile_kind kind = n < N_MOVES ? KC_PROFILE_TRAPEZOID : KC_PROFILE_JERK;
        static kc_interp_joint plan;
        static kc_fx_joint_move move;
        if (random_move(&plan, kind, n >= 2 * N_MOVES) != KC_OK || kc_fx_joint_init(&move, &fx, &plan) != KC_OK) {
            printf("FAIL: joint move %d: cannot plan or convert it\n", n);
            return 1;
        }
        if (kind == KC_PROFILE_JERK) {
            by_time += plan.sync == KC_INTERP_SYNC_TIME;
            by_phase += plan.sync == KC_INTERP_SYNC_PHASE;
        }
        for (int64_t k = 0; k <= plan.ticks; k++) {
            kc_interp_joint_state ref;
            int32_t qf[6];
            kc_status st = kc_fx_joint_eval(&move, k, qf);
            kc_interp_joint_eval(&plan, k, &ref);
            for (int j = 0; j < 6; j++) {
                double q = (double)qf[j] / (double)(1 << KC_FX_ANGLE_BITS);
                err[kind == KC_PROFILE_JERK] = max_abs(q - (double)ref.q[j], err[kind == KC_PROFILE_JERK]);
                if (st == KC_DONE && qf[j] != move.q1[j])
                    done_exact = 0;
            }
            ticks++;
        }
    }
    printf("joint moves (puma560): %d trapezoids, %d jerk-limited by time and %d by phase, %ld ticks\n", N_MOVES,
           by_time, by_phase, ticks);
    if (by_time < N_MOVES / 2 || by_phase < N_MOVES / 2) {
        printf("FAIL: too few jerk-limited moves of a kind\n");
        return 1;
    }
    return check("q (rad), trapezoid", err[0], TOL_JOINT_MOVE) +
           check("q (rad), jerk-limited", err[1], TOL_JOINT_MOVE) + (done_exact ? 0 : 1);
}

/* What kc_fx_joint_init refuses (KC_E_ARG, the move cleared): a
 * jerk-limited move from a moving start (a replacement's: its fraction of
 * the travel overshoots), NULL. */
static int test_refusals(void)
{
    if (kc_chain_init_model(&chain, KC_MODEL_PUMA560, NULL) != KC_OK || kc_fx_chain_init(&fx, &chain) != KC_OK)
        return 1;
    static kc_interp_joint plan;
    static kc_fx_joint_move move;
    int failures = 0;
    for (int sync = 0; sync < 2; sync++) {
        kc_interp_joint_cfg c = kc_interp_joint_cfg_default();
        c.n = 6;
        c.dt = KC_R(0.001);
        c.profile = KC_PROFILE_JERK;
        for (int j = 0; j < 6; j++) {
            c.q0[j] = KC_R(0.1) * (kc_real)j;
            c.q1[j] = c.q0[j] + KC_R(0.5);
            c.qd_max[j] = chain.joints[j].limits.qd_max;
            c.qdd_max[j] = chain.joints[j].limits.qdd_max;
            c.qddd_max[j] = chain.joints[j].limits.qddd_max;
        }
        c.qd0[sync * 5] = KC_R(-1.0); /* moving away from its target */
        if (kc_interp_joint_plan_cfg(&plan, &c) != KC_OK) {
            printf("FAIL: a move from a moving start: cannot plan it\n");
            return 1;
        }
        memset(&move, 0x5a, sizeof move);
        if (kc_fx_joint_init(&move, &fx, &plan) != KC_E_ARG || move.n != 0 || move.ramp[0].ticks != 0) {
            printf("FAIL: a jerk-limited move from a moving start (joint %d) converted, or the move not cleared\n",
                   sync * 5 + 1);
            failures++;
        }
    }
    if (kc_fx_joint_init(NULL, &fx, &plan) != KC_E_ARG || kc_fx_joint_init(&move, NULL, &plan) != KC_E_ARG ||
        kc_fx_joint_init(&move, &fx, NULL) != KC_E_ARG) {
        printf("FAIL: a NULL argument accepted\n");
        failures++;
    }
    printf("refusals: %s\n", failures ? "FAIL" : "a moving start and NULL arguments refused");
    return failures;
}

/* Lines between the tool poses of random PUMA 560 configurations, both
 * orientation methods, by the trapezoid and jerk-limited, every tick
 * against kc_interp_line_eval of the double build: position 1e-6 m,
 * quaternion entries 1e-6 (as FK). */
static int test_lines(void)
{
    if (kc_chain_init_model(&chain, KC_MODEL_PUMA560, NULL) != KC_OK)
        return 1;
    double e_pos = 0.0, e_rot = 0.0;
    long ticks = 0;
    int done_exact = 1;
    for (int n = 0; n < 4 * N_LINES; n++) {
        kc_pose from, to;
        kc_real q[2][6];
        for (int c = 0; c < 2; c++)
            for (int j = 0; j < 6; j++) {
                const kc_joint_limits *l = &chain.joints[j].limits;
                q[c][j] = l->q_min + (l->q_max - l->q_min) * (kc_real)uniform();
            }
        kc_fk_eval(&chain, q[0], &from);
        kc_fk_eval(&chain, q[1], &to);
        kc_interp_line plan;
        kc_fx_line line;
        kc_interp_orient orient = n % 2 ? KC_INTERP_TWO_ROTATIONS : KC_INTERP_SLERP;
        kc_interp_limits lim = kc_interp_limits_default();
        lim.v = KC_R(0.5);
        lim.a = KC_R(2.0);
        if (n >= 2 * N_LINES) {
            lim.j = KC_R(20.0);
            lim.w = KC_R(2.0);
            lim.dw = KC_R(8.0);
            lim.dj = KC_R(80.0);
        }
        if (kc_interp_line_plan(&plan, &from, &to, &lim, orient, KC_R(0.001)) != KC_OK ||
            plan.kind != (n >= 2 * N_LINES ? KC_PROFILE_JERK : KC_PROFILE_TRAPEZOID) ||
            kc_fx_line_init(&line, &plan) != KC_OK) {
            printf("FAIL: line %d: cannot plan or convert it\n", n);
            return 1;
        }
        for (int64_t k = 0; k <= plan.ticks; k++) {
            kc_interp_cart_state ref;
            int32_t p[3], qf[4];
            kc_status st = kc_fx_line_eval(&line, k, p, qf);
            kc_interp_line_eval(&plan, k, &ref);
            const double qr[4] = {(double)ref.q.w, (double)ref.q.x, (double)ref.q.y, (double)ref.q.z};
            for (int i = 0; i < 3; i++)
                e_pos = max_abs((double)p[i] / (double)(1 << KC_FX_POS_BITS) - (double)ref.p.v[i], e_pos);
            for (int i = 0; i < 4; i++) {
                e_rot = max_abs((double)qf[i] / (double)KC_FX_ONE_ROT - qr[i], e_rot);
                if (st == KC_DONE && qf[i] != line.q2[i])
                    done_exact = 0;
            }
            ticks++;
        }
    }
    printf("lines (puma560 poses): %d of each orientation method, half by the trapezoid and half jerk-limited, %ld "
           "ticks\n",
           2 * N_LINES, ticks);
    return check("position (m)", e_pos, TOL_POS) + check("quaternion entries", e_rot, TOL_ROT) + (done_exact ? 0 : 1);
}

int main(void)
{
    int failures = test_sincos();
    failures += test_joint_moves();
    failures += test_refusals();
    failures += test_lines();
    for (int m = 0; m < KC_MODEL_COUNT; m++)
        failures += test_model((kc_model)m);
    printf(failures ? "FAIL: %d checks\n" : "ok: every check within its tolerance\n", failures);
    return failures ? 1 : 0;
}
