/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ik.c - inverse kinematics (seed 002's law, kinctl/ik.h) against
 * vectors/ik.json and on random reachable targets. */
#include <string.h>

#include "testutil.h"

/* Acceptance of vectors/ik.json: every entry of FK(q) within 1e-6 of the
 * target (any branch). In float the FK itself carries KT_TOL_T of rounding
 * and the solver stops at its float tolerances (1e-5 m, 1e-4 rad), so the
 * criterion there is 1e-4 on direction cosines and positions. */
#ifdef KC_REAL_FLOAT
#define TOL_IK_T 1e-4
#define FLOAT_TOL 1
#else
#define TOL_IK_T 1e-6
#define FLOAT_TOL 0
#endif

static double max_pose_diff(const kc_pose *a, const kc_pose *b)
{
    double d = 0.0;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            double e = fabs((double)a->R.m[i][j] - (double)b->R.m[i][j]);
            d = e > d ? e : d;
        }
        double e = fabs((double)a->t.v[i] - (double)b->t.v[i]);
        d = e > d ? e : d;
    }
    return d;
}

static void assert_within_limits(const kc_chain *c, const kc_real *q)
{
    int bad = -1;
    kc_status st = kc_chain_check_q(c, q, &bad);
    if (st != KC_OK)
        fail_msg("joint %d outside its limits (status %d)", bad, st);
}

static void random_q(kt_rng *r, const kc_chain *c, kc_real *q)
{
    for (int j = 0; j < c->n_joints; j++)
        q[j] = (kc_real)kt_uniform(r, (double)c->joints[j].limits.q_min, (double)c->joints[j].limits.q_max);
}

static void test_vectors_from_start(void **state)
{
    (void)state;
    json_t *root = kt_load("ik.json");
    kc_chain c;
    assert_int_equal(kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL), KC_OK);
    kc_real q0[6], q[6];
    kt_read_reals(kt_get(root, "q_start_rad"), q0, 6);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    json_t *targets = kt_get(root, "targets");
    size_t n = json_array_size(targets);
    assert_int_equal(n, 50);
    for (size_t i = 0; i < n; i++) {
        json_t *t = kt_at(targets, i);
        kc_pose target, got;
        kt_read_pose(kt_get(t, "T_target"), &target);
        kc_ik_result res;
        kc_status st = kc_ik_solve(&c, &cfg, &target, q0, q, &res);
        if (st != KC_OK)
            fail_msg("target %zu: status %s, pos %g rot %g after %d steps", i, kc_status_str(st),
                     (double)res.pos_err, (double)res.rot_err, res.steps);
        assert_int_equal(kc_fk_eval(&c, q, &got), KC_OK);
        kt_near(max_pose_diff(&got, &target), 0.0, TOL_IK_T, "max |FK(q_solved) - T_target|");
        assert_within_limits(&c, q);
    }
    json_decref(root);
}

/* Solves n random reachable targets (FK of q drawn within the limits) from
 * a fixed or random start. At least 99 % must converge inside the limits
 * (the benchmark measures the rate on 1000 targets; the target is
 * 99.9 %); a miss must say so (a status saying where it stopped) with q inside the limits and
 * residuals that are the true ones of the q returned. */
static void solve_random(kc_model model, kc_ik_mask mask, int random_start, int n, uint64_t seed)
{
    kc_chain c;
    assert_int_equal(kc_chain_init_model(&c, model, NULL), KC_OK);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    cfg.mask = mask;
    kt_rng r = kt_rng_make(seed);
    kc_real q0[KC_MAX_JOINTS], qg[KC_MAX_JOINTS], q[KC_MAX_JOINTS];
    int missed = 0;
    for (int j = 0; j < c.n_joints; j++)
        q0[j] = KC_R(0.5) * (c.joints[j].limits.q_min + c.joints[j].limits.q_max);
    for (int k = 0; k < n; k++) {
        kc_pose target, got;
        random_q(&r, &c, qg);
        kc_fk_eval(&c, qg, &target);
        if (random_start)
            random_q(&r, &c, q0);
        kc_ik_result res;
        kc_status st = kc_ik_solve(&c, &cfg, &target, q0, q, &res);
        assert_within_limits(&c, q);
        kc_fk_eval(&c, q, &got);
        kc_vec3 dp;
        kc_vec3_sub(&got.t, &target.t, &dp);
        kt_near((double)res.pos_err, (double)kc_vec3_norm(&dp), KT_TOL_T, "reported position residual");
        if (st != KC_OK) {
            assert_true(st == KC_E_NOCONVERGE || st == KC_E_LIMIT || st == KC_E_SINGULAR);
            print_message("%s mask %d target %d: %s, pos %g rot %g, %d steps %d restarts\n", kc_model_name(model),
                          mask, k, kc_status_str(st), (double)res.pos_err, (double)res.rot_err, res.steps,
                          res.restarts);
            missed++;
            continue;
        }
        kt_near_vec3(&got.t, &target.t, TOL_IK_T, "position reached");
        if (mask == KC_IK_MASK_FULL)
            kt_near_mat3(&got.R, &target.R, TOL_IK_T, "orientation reached");
        if (mask == KC_IK_MASK_AXIS)
            for (int i = 0; i < 3; i++)
                kt_near((double)got.R.m[i][2], (double)target.R.m[i][2], TOL_IK_T, "tool axis reached");
    }
    if (missed * 100 > n)
        fail_msg("%s mask %d: %d of %d targets missed (more than 1 %%)", kc_model_name(model), mask, missed, n);
}

static void test_random_puma(void **state)
{
    (void)state;
    solve_random(KC_MODEL_PUMA560, KC_IK_MASK_FULL, 0, 200, 11);
    solve_random(KC_MODEL_PUMA560, KC_IK_MASK_FULL, 1, 200, 12);
}

static void test_random_panda(void **state)
{
    (void)state;
    solve_random(KC_MODEL_PANDA, KC_IK_MASK_FULL, 0, 200, 21);
    solve_random(KC_MODEL_PANDA, KC_IK_MASK_FULL, 1, 200, 22);
}

static void test_random_rrr3_position(void **state)
{
    (void)state;
    solve_random(KC_MODEL_RRR3, KC_IK_MASK_POSITION, 0, 200, 31);
    solve_random(KC_MODEL_RRR3, KC_IK_MASK_POSITION, 1, 200, 32);
}

static void test_random_masks_redundant(void **state)
{
    (void)state;
    /* puma560 with a position-only task has three spare joints, and with
     * the axis task one; both go to the null-space objective. */
    solve_random(KC_MODEL_PUMA560, KC_IK_MASK_POSITION, 1, 200, 41);
    solve_random(KC_MODEL_PUMA560, KC_IK_MASK_AXIS, 1, 200, 42);
    solve_random(KC_MODEL_PANDA, KC_IK_MASK_AXIS, 1, 200, 43);
}

static void test_unreachable(void **state)
{
    (void)state;
    kc_chain c;
    kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    kc_pose target;
    kc_pose_identity(&target);
    target.t = kc_vec3_make(KC_R(3.0), KC_R(0.0), KC_R(0.5));
    kc_real q0[6] = {0}, q[6];
    memset(q, KT_SENTINEL, sizeof q);
    kc_ik_result res;
    assert_int_equal(kc_ik_solve(&c, &cfg, &target, q0, q, &res), KC_E_UNREACHABLE);
    assert_true(kt_is_sentinel(q, sizeof q));
    assert_true(kc_ik_reach(&c) < KC_R(3.0));
}

static void test_bad_input(void **state)
{
    (void)state;
    kc_chain c;
    kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    kc_pose target;
    kc_real q0[6] = {0}, q[6];
    kc_ik_result res;
    kc_fk_eval(&c, q0, &target);
    memset(q, KT_SENTINEL, sizeof q);

    kc_pose bad = target;
    bad.t.v[1] = (kc_real)NAN;
    assert_int_equal(kc_ik_solve(&c, &cfg, &bad, q0, q, &res), KC_E_ARG);
    bad = target;
    bad.R.m[0][0] = KC_R(2.0); /* not a rotation */
    assert_int_equal(kc_ik_solve(&c, &cfg, &bad, q0, q, &res), KC_E_ARG);
    kc_real qn[6] = {0, 0, (kc_real)INFINITY, 0, 0, 0};
    assert_int_equal(kc_ik_solve(&c, &cfg, &target, qn, q, &res), KC_E_ARG);
    kc_ik_cfg bc = cfg;
    bc.gain_step = KC_R(1.5);
    assert_int_equal(kc_ik_solve(&c, &bc, &target, q0, q, &res), KC_E_ARG);
    bc = cfg;
    bc.tol_pos = KC_R(0.0);
    assert_int_equal(kc_ik_solve(&c, &bc, &target, q0, q, &res), KC_E_ARG);
    bc = cfg;
    bc.mask = (kc_ik_mask)7;
    assert_int_equal(kc_ik_solve(&c, &bc, &target, q0, q, &res), KC_E_ARG);
    assert_int_equal(kc_ik_solve(&c, &cfg, NULL, q0, q, &res), KC_E_ARG);
    assert_true(kt_is_sentinel(q, sizeof q));
}

static void test_singular_targets(void **state)
{
    (void)state;
    /* puma560 at qz has a wrist singularity (q5 = 0) and at qr-like
     * stretched configurations an elbow one; targets there and 1e-3 rad away
     * are reached from a regular start. */
    kc_chain c;
    kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    const kc_real qs[4][6] = {{0, 0, 0, 0, 0, 0},
                              {0, KC_R(1.5707963267948966), KC_R(-1.5707963267948966), 0, 0, 0},
                              {KC_R(0.3), KC_R(0.4), KC_R(-0.5), KC_R(0.6), KC_R(1e-3), KC_R(0.2)},
                              {KC_R(-0.2), KC_R(1.0), KC_R(-1.2), KC_R(0.1), KC_R(-1e-3), KC_R(-0.4)}};
    const kc_real q0[6] = {0, KC_R(0.7853981633974483), KC_R(-3.141592653589793), 0, KC_R(0.7853981633974483), 0};
    for (int k = 0; k < 4; k++) {
        kc_pose target, got;
        kc_real q[6];
        kc_ik_result res;
        kc_fk_eval(&c, qs[k], &target);
        kc_status st = kc_ik_solve(&c, &cfg, &target, q0, q, &res);
        if (st != KC_OK)
            fail_msg("singular target %d: %s pos %g rot %g", k, kc_status_str(st), (double)res.pos_err,
                     (double)res.rot_err);
        kc_fk_eval(&c, q, &got);
        kt_near(max_pose_diff(&got, &target), 0.0, TOL_IK_T, "singular target reached");
        assert_within_limits(&c, q);
    }
}

static void test_deterministic(void **state)
{
    (void)state;
    kc_chain c;
    kc_chain_init_model(&c, KC_MODEL_PANDA, NULL);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    kt_rng r = kt_rng_make(99);
    for (int k = 0; k < 50; k++) {
        kc_real qg[7], q0[7], a[7], b[7];
        kc_pose target;
        kc_ik_result ra, rb;
        random_q(&r, &c, qg);
        random_q(&r, &c, q0);
        kc_fk_eval(&c, qg, &target);
        kc_status sa = kc_ik_solve(&c, &cfg, &target, q0, a, &ra);
        kc_status sb = kc_ik_solve(&c, &cfg, &target, q0, b, &rb);
        assert_int_equal(sa, sb);
        assert_memory_equal(a, b, sizeof a);
        assert_int_equal(ra.steps, rb.steps);
    }
}

/* The online law at 1 kHz: converges, never exceeds a velocity or an
 * acceleration limit, never leaves the position limits, and comes to
 * rest within the jerk limits. */
static void test_step_online(void **state)
{
    (void)state;
    kc_chain c;
    kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    kt_rng r = kt_rng_make(7);
    const kc_real dt = KC_R(0.001);
    for (int k = 0; k < 20; k++) {
        kc_real q[6] = {0, KC_R(0.7853981633974483), KC_R(-3.141592653589793), 0, KC_R(0.7853981633974483), 0};
        kc_real qd[6] = {0}, qg[6];
        /* A target a moderate move away, as the cycle would see. */
        for (int j = 0; j < 6; j++)
            qg[j] = q[j] + (kc_real)kt_uniform(&r, -0.3, 0.3);
        for (int j = 0; j < 6; j++)
            qg[j] = kc_clamp(qg[j], c.joints[j].limits.q_min, c.joints[j].limits.q_max);
        kc_pose target;
        kc_fk_eval(&c, qg, &target);
        kc_ik_result res;
        kc_status st = KC_OK;
        int ticks;
        double qdd_prev[6] = {0};
        for (ticks = 0; ticks < 20000 && st != KC_DONE; ticks++) {
            kc_real qn[6], qdn[6];
            st = kc_ik_step(&c, &cfg, &target, NULL, dt, q, qd, qn, qdn, &res);
            assert_true(st == KC_OK || st == KC_DONE || st == KC_E_SINGULAR);
            for (int j = 0; j < 6 && st == KC_DONE; j++) {
                /* The stop at the end: qdd from the law's to -qd/dt, then
                 * back to 0 on the next tick, each change within qddd_max
                 * dt (float: within what rounding leaves, a few units of
                 * q's last place a tick, ik.h). */
                double jd = (double)c.joints[j].limits.qddd_max * (double)dt;
                double ulps = 4.0 * (double)KC_REAL_EPS * fmax(fabs((double)q[j]), 1.0) / (double)dt / (double)dt;
                double stop = -(double)qd[j] / (double)dt, bound = fmax(jd, ulps) * (1.0 + 1e-9);
                kt_near(fabs(stop - qdd_prev[j]) <= bound, 1.0, 0.0, "jerk of the stop at the end");
                kt_near(fabs(stop) <= bound, 1.0, 0.0, "jerk of the tick after the stop");
            }
            for (int j = 0; j < 6; j++)
                qdd_prev[j] = ((double)qdn[j] - (double)qd[j]) / (double)dt;
            for (int j = 0; j < 6; j++) {
                const kc_joint_limits *l = &c.joints[j].limits;
                kt_near(fabs((double)qdn[j]) <= (double)l->qd_max * (1.0 + 1e-6), 1.0, 0.0, "velocity limit");
                /* Slack for the rounding of qd itself in this precision. */
                double slack = 4.0 * (double)KC_REAL_EPS * (fabs((double)qd[j]) + fabs((double)qdn[j]));
                kt_near(fabs((double)(qdn[j] - qd[j])) <= (double)(l->qdd_max * dt) + slack, 1.0, 0.0,
                        "acceleration limit");
            }
            assert_within_limits(&c, qn);
            memcpy(q, qn, sizeof q);
            memcpy(qd, qdn, sizeof qd);
        }
        if (st != KC_DONE)
            fail_msg("online target %d not reached in %d ticks: pos %g rot %g", k, ticks, (double)res.pos_err,
                     (double)res.rot_err);
    }
}

/* The online step's gain at a period dt: at most 1/dt (kinctl/ik.h). From
 * rest, towards a still target 3 um and 3 urad away (near enough for no
 * acceleration limit to bind), one step at the controller's gain of 100/s
 * leaves (1 - k dt) of the error, to the step's second-order terms: 0.9
 * at 1 ms, none at 10 ms and beyond (without the bound, -1 and -4 times it
 * at 20 and 50 ms). In double: in float the positions' rounding is 2 % of
 * such an error. */
#ifndef KC_REAL_FLOAT
static void test_step_online_gain(void **state)
{
    (void)state;
    kc_chain c;
    kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    cfg.gain_pos = cfg.gain_rot = KC_R(100.0);
    const double d = 3e-6;
    const kc_real dts[4] = {KC_R(0.001), KC_R(0.01), KC_R(0.02), KC_R(0.05)};
    for (int i = 0; i < 4; i++) {
        kc_real dt = dts[i], k = kc_ik_online_gain(cfg.gain_pos, dt);
        assert_true(k == kc_min(KC_R(100.0), KC_R(1.0) / dt));
        kc_real q[6], qd[6] = {0}, qn[6], qdn[6];
        memcpy(q, KT_PUMA_Q0, sizeof q);
        kc_pose at, target;
        kc_fk_eval(&c, q, &at);
        target = at;
        target.t.v[0] += (kc_real)d;
        target.t.v[2] -= (kc_real)d;
        kc_mat3 turn;
        kc_mat3_rot(KC_AXIS_Y, (kc_real)d, &turn);
        kc_mat3_mul(&turn, &at.R, &target.R);
        kc_ik_result res;
        assert_int_equal(kc_ik_step(&c, &cfg, &target, NULL, dt, q, qd, qn, qdn, &res), KC_OK);
        kc_pose after;
        kc_fk_eval(&c, qn, &after);
        double before = sqrt(2.0) * d, left = 0.0;
        for (int j = 0; j < 3; j++)
            left += ((double)after.t.v[j] - (double)target.t.v[j]) * ((double)after.t.v[j] - (double)target.t.v[j]);
        left = sqrt(left);
        double want = (1.0 - (double)k * (double)dt) * before;
        print_message("online step at %g ms, k = %g 1/s: position error %.3g m to %.3g m (1 - k dt: %.3g m)\n",
                      1e3 * (double)dt, (double)k, before, left, want);
        kt_near(left, want, 0.01 * before, "error left by one online step");
    }
}
#endif

/* A target beyond a joint's position limit: the online step brings the
 * joint to rest at the limit within its acceleration limit every tick (no
 * velocity step at the limit, which the controller's final check refuses). */
static void test_step_into_a_limit(void **state)
{
    (void)state;
    kc_chain c;
    kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    const kc_real dt = KC_R(0.001);
    const kc_joint_limits *l4 = &c.joints[3].limits;
    kc_real q[6] = {0, KC_R(0.7853981633974483), KC_R(-3.141592653589793), KC_R(2.5), KC_R(0.7853981633974483), 0};
    kc_real qd[6] = {0}, qg[6];
    memcpy(qg, q, sizeof qg);
    qg[3] = l4->q_max + KC_R(0.6); /* out of reach for joint 4 */
    kc_pose target;
    kc_fk_eval(&c, qg, &target);
    kc_ik_result res;
    double top = (double)q[3];
    for (int t = 0; t < 3000; t++) {
        kc_real qn[6], qdn[6];
        kc_status st = kc_ik_step(&c, &cfg, &target, NULL, dt, q, qd, qn, qdn, &res);
        assert_true(st != KC_E_ARG);
        for (int j = 0; j < 6; j++) {
            const kc_joint_limits *l = &c.joints[j].limits;
            double slack = 4.0 * (double)KC_REAL_EPS * (fabs((double)qd[j]) + fabs((double)qdn[j]));
            if (!(fabs((double)(qdn[j] - qd[j])) <= (double)(l->qdd_max * dt) + slack))
                fail_msg("tick %d: joint %d velocity steps from %g to %g", t, j + 1, (double)qd[j], (double)qdn[j]);
        }
        assert_within_limits(&c, qn);
        top = fmax(top, (double)qn[3]);
        memcpy(q, qn, sizeof q);
        memcpy(qd, qdn, sizeof qd);
    }
    /* It got to the limit (within a millimetre-sized angle) and rests there. */
    assert_true(top > (double)l4->q_max - 2e-3);
    kt_near((double)qd[3], 0.0, 1e-3, "at rest at the limit");
}

/* A target moving at 0.3 m/s: with its twist fed forward the tool follows
 * within a few micrometres; without it the lag is about v / k. */
static double track_line(const kc_real *twist)
{
    kc_chain c;
    kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    const kc_real dt = KC_R(0.001), v = KC_R(0.3);
    kc_real q[6] = {KC_R(0.1), KC_R(0.8), KC_R(-2.4), KC_R(0.1), KC_R(0.6), KC_R(0.2)}, qd[6] = {0};
    kc_pose start;
    kc_fk_eval(&c, q, &start);
    double worst = 0.0;
    for (int k = 1; k <= 1000; k++) {
        /* The target where it is now, at the instant of (q, qd); the step
         * goes where it will be after dt. */
        kc_pose target = start;
        target.t.v[1] += v * (kc_real)(k - 1) * dt;
        kc_ik_result res;
        kc_status st = kc_ik_step(&c, &cfg, &target, twist, dt, q, qd, q, qd, &res);
        if (st != KC_OK && st != KC_DONE) /* done: at the start, still on target */
            fail_msg("tick %d: %s", k, kc_status_str(st));
        kc_pose reached;
        kc_vec3 d;
        kc_fk_eval(&c, q, &reached);
        target.t.v[1] += v * dt;
        kc_vec3_sub(&reached.t, &target.t, &d);
        double err = (double)kc_vec3_norm(&d);
        /* After the start-up transient: the target starts at full speed,
         * the arm only as fast as its acceleration limits allow. */
        if (k > 500)
            worst = err > worst ? err : worst;
    }
    return worst;
}

static void test_step_feed_forward(void **state)
{
    (void)state;
    const kc_real twist[6] = {0, KC_R(0.3), 0, 0, 0, 0};
    double with = track_line(twist), without = track_line(NULL);
    print_message("tracking error at 0.3 m/s: %.3g m with feed-forward, %.3g m without\n", with, without);
    kt_near(without, 0.3 / 20.0, 0.002, "lag without feed-forward, v / k");
    kt_near(with, 0.0, 1e-5, "error with feed-forward (the tick's second-order term)");
}

/* A miss says where it stopped: a one-joint arm asked to turn past its
 * limit stops there (KC_E_LIMIT); rrr3 asked for a point beyond its
 * stretched elbow (inside the reach bound) ends singular. */
static void test_miss_reasons(void **state)
{
    (void)state;
    kc_chain c;
    kc_chain_init(&c);
    kc_joint_limits l = kc_joint_limits_default();
    l.q_min = KC_R(0.0);
    l.q_max = KC_R(1.0);
    assert_int_equal(kc_chain_add_joint(&c, KC_CODE_RZ_JOINT, KC_R(0.0), &l), KC_OK);
    assert_int_equal(kc_chain_add_const(&c, KC_CODE_TX, KC_R(0.5)), KC_OK);
    assert_int_equal(kc_chain_check(&c), KC_OK);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    cfg.mask = KC_IK_MASK_POSITION;
    cfg.max_restarts = 3;
    kc_pose target;
    kc_pose_identity(&target);
    target.t = kc_vec3_make(KC_R(0.5) * kc_cos(KC_R(2.0)), KC_R(0.5) * kc_sin(KC_R(2.0)), KC_R(0.0));
    kc_real q0[1] = {KC_R(0.5)}, q[1];
    kc_ik_result res;
    assert_int_equal(kc_ik_solve(&c, &cfg, &target, q0, q, &res), KC_E_LIMIT);
    kt_near((double)q[0], 1.0, 0.0, "stopped at the upper limit");
    assert_int_equal(res.status, KC_E_LIMIT);
    assert_int_equal(res.restarts, 3);

    kc_chain_init_model(&c, KC_MODEL_RRR3, NULL);
    target.t = kc_vec3_make(KC_R(0.6), KC_R(0.0), KC_R(0.4)); /* 0.6 m from the shoulder, arm 0.55 m */
    assert_true(kc_vec3_norm(&target.t) < kc_ik_reach(&c));
    kc_real q3[3] = {KC_R(0.1), KC_R(0.2), KC_R(0.3)}, qo[3];
    assert_int_equal(kc_ik_solve(&c, &cfg, &target, q3, qo, &res), KC_E_SINGULAR);
    /* No configuration comes closer than 0.05 m; the best found is near it
     * (progress near the singularity is slow, which is why it stalls). */
    assert_true((double)res.pos_err >= 0.05 - 1e-6);
    kt_near((double)res.pos_err, 0.05, 1e-3, "closest approach of the stretched arm");
}

/* kc_ik_step_ff on the Panda under the full task (one null-space
 * dimension): at the target (e = 0), fed forward the joint velocities qd
 * the arm already has and their twist J qd, the step gives qd back whole,
 * its part that does not move the tool included; kc_ik_step keeps only
 * J^+ J qd (the same twist, the null-space part lost). On the PUMA 560
 * (no null space) the feed-forward changes nothing. A non-finite qd_ff is
 * refused. Random velocities up to 0.3 rad/s, the null-space objective
 * off (its gradient would add its own motion). */
static void test_step_null_feed_forward(void **state)
{
    (void)state;
    const double tol = FLOAT_TOL ? 1e-4 : 1e-10;
    kt_rng r = kt_rng_make(4242);
    kc_ik_cfg cfg = kc_ik_cfg_default();
    cfg.null_gain = KC_R(0.0);
    for (int m = 0; m < 2; m++) {
        kc_chain chain;
        assert_int_equal(kc_chain_init_model(&chain, m == 0 ? KC_MODEL_PANDA : KC_MODEL_PUMA560, NULL), KC_OK);
        int n = chain.n_joints;
        const kc_real *q = m == 0 ? KT_PANDA_Q0 : KT_PUMA_Q0;
        double worst = 0.0, lost = 0.0;
        for (int c = 0; c < 50; c++) {
            kc_real qd[KC_MAX_JOINTS], twist[6], q1[KC_MAX_JOINTS], qd1[KC_MAX_JOINTS], q2[KC_MAX_JOINTS],
                qd2[KC_MAX_JOINTS];
            for (int j = 0; j < n; j++)
                qd[j] = (kc_real)kt_uniform(&r, -0.3, 0.3);
            kc_jacobian jac;
            kc_pose at;
            assert_int_equal(kc_fk_jacobian(&chain, q, &jac, &at), KC_OK);
            for (int i = 0; i < 6; i++) {
                twist[i] = KC_R(0.0);
                for (int j = 0; j < n; j++)
                    twist[i] += jac.m[i][j] * qd[j];
            }
            kc_ik_result res;
            assert_int_equal(kc_ik_step_ff(&chain, &cfg, &at, twist, qd, KC_R(0.001), q, qd, q1, qd1, &res), KC_OK);
            assert_int_equal(kc_ik_step(&chain, &cfg, &at, twist, KC_R(0.001), q, qd, q2, qd2, &res), KC_OK);
            double off = 0.0, change = 0.0;
            for (int j = 0; j < n; j++) {
                off = fmax(off, fabs((double)qd1[j] - (double)qd[j]));
                change = fmax(change, fabs((double)qd2[j] - (double)qd[j]));
                if (m == 1)
                    assert_true(qd1[j] == qd2[j] && q1[j] == q2[j]);
            }
            /* Both give the twist: J qd1 = J qd2 = J qd. */
            for (int i = 0; i < 6; i++) {
                double t1 = 0.0, t2 = 0.0;
                for (int j = 0; j < n; j++) {
                    t1 += (double)jac.m[i][j] * (double)qd1[j];
                    t2 += (double)jac.m[i][j] * (double)qd2[j];
                }
                kt_near(t1, (double)twist[i], tol, "the twist with the feed-forward");
                kt_near(t2, (double)twist[i], tol, "the twist without it");
            }
            worst = fmax(worst, off);
            lost = fmax(lost, change);
            if (m == 0)
                assert_true(change > 1e-3); /* the null-space part kc_ik_step drops */
        }
        print_message("%s: qd given back within %.3g rad/s with the null-space feed-forward, up to %.3g rad/s off "
                      "without it\n",
                      m == 0 ? "panda" : "puma560", worst, lost);
        assert_true(worst <= tol);
    }
    kc_chain chain;
    kc_chain_init_model(&chain, KC_MODEL_PANDA, NULL);
    kc_real bad[7] = {0}, still[7] = {0}, q1[7], qd1[7];
    bad[3] = (kc_real)NAN;
    kc_pose at;
    kc_fk_eval(&chain, KT_PANDA_Q0, &at);
    kc_ik_result res;
    assert_int_equal(kc_ik_step_ff(&chain, &cfg, &at, NULL, bad, KC_R(0.001), KT_PANDA_Q0, still, q1, qd1, &res),
                     KC_E_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vectors_from_start),  cmocka_unit_test(test_random_puma),
        cmocka_unit_test(test_random_panda),        cmocka_unit_test(test_random_rrr3_position),
        cmocka_unit_test(test_random_masks_redundant), cmocka_unit_test(test_unreachable),
        cmocka_unit_test(test_bad_input),           cmocka_unit_test(test_singular_targets),
        cmocka_unit_test(test_deterministic),       cmocka_unit_test(test_step_online),
#ifndef KC_REAL_FLOAT
        cmocka_unit_test(test_step_online_gain),
#endif
        cmocka_unit_test(test_step_into_a_limit),
        cmocka_unit_test(test_miss_reasons),        cmocka_unit_test(test_step_feed_forward),
        cmocka_unit_test(test_step_null_feed_forward),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ik");
    return failed;
}
