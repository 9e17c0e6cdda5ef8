/* SPDX-License-Identifier: BSD-3-Clause */
/* test_check_slow.c - the joints' jerk of a Cartesian goal as the dry run
 * measures it (kc_verdict.jerk), and a goal slowed until its joints stay
 * within their qddd_max (kc_goal_slow by kc_check_slowing, kinctl/check.h).
 *
 * - The verdict's jerk equals the largest change of a joint's qdd over a
 *   tick, over qddd_max dt, measured here (in double) on a controller of
 *   our own that steps the same goal from the same rest at the check's
 *   period.
 * - kc_goal_slow scales the law's limits by s, s^2, s^3 (the goal's or the
 *   configured defaults), a Cartesian path's times by 1/s, and refuses the
 *   goals it does not apply to, leaving them unchanged.
 * - Random fast lines on the PUMA 560, judged as kinctld judges them (a
 *   dry run at 4 ms for a controller at 1 ms, slowed and judged again up to
 *   three times): most exceed qddd_max as asked (the Jacobian amplifies the
 *   tool's jerk), and slowed, every tick at 1 ms stays within it. Double
 *   only: in float the IK step's rounding alone makes tick-to-tick jerk
 *   noise above qddd_max in any Cartesian motion (kinctl/ctrl.h). */
#include <math.h>
#include <string.h>

#include "kinctl/check.h"
#include "kinctl/fk.h"
#include "testutil.h"

#define CASES 24

static kc_chain CHAIN;
static kc_ctrl CTRL; /* large: not on the stack */
static kc_check CHECK;

/* A dry run at period dt from the PUMA 560's start pose. */
static kc_ctrl_cfg setup(kc_real dt)
{
    assert_int_equal(kc_chain_init_model(&CHAIN, KC_MODEL_PUMA560, NULL), KC_OK);
    kc_ctrl_cfg cfg = kc_ctrl_cfg_default();
    cfg.dt = dt;
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &cfg, 100000, KT_PUMA_Q0), KC_OK);
    return cfg;
}

/* The largest change of a joint's qdd over a tick, in units of its
 * qddd_max dt, of goal g stepped from rest at KT_PUMA_Q0 at period dt to
 * its end (which must be COMPLETED). */
static double stepped_jerk(const kc_goal *g, kc_real dt)
{
    kc_ctrl_cfg cfg = kc_ctrl_cfg_default();
    cfg.dt = dt;
    assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &cfg, KT_PUMA_Q0), KC_OK);
    double qdd[KC_MAX_JOINTS] = {0.0}, worst = 0.0;
    kc_ctrl_output out;
    for (int t = 0; t < 200000; t++) {
        kc_ctrl_input in = {t == 0 ? g : NULL, KC_CMD_NONE, 0, KC_REASON_NONE};
        assert_int_equal(kc_ctrl_step(&CTRL, &in, &out), KC_OK);
        for (int j = 0; j < CHAIN.n_joints; j++) {
            double r = fabs((double)out.qdd[j] - qdd[j]) / ((double)CHAIN.joints[j].limits.qddd_max * (double)dt);
            worst = fmax(worst, r);
            qdd[j] = (double)out.qdd[j];
        }
        assert_false(kt_has_event(&out, KC_EVENT_FAULT, g->id));
        if (kt_has_event(&out, KC_EVENT_COMPLETED, g->id))
            return worst;
    }
    fail_msg("goal %lld did not end", (long long)g->id);
    return worst;
}

/* A line of 5 to 25 cm from the start pose, turning the tool by up to
 * 0.2 rad, at speed, accel and jerk drawn up to fast ones, that the dry run
 * takes. */
static kc_goal fast_line(kt_rng *r, int64_t id)
{
    kc_pose home;
    kc_fk_eval(&CHAIN, KT_PUMA_Q0, &home);
    kc_real v = (kc_real)kt_uniform(r, 0.1, 0.5);
    kc_real a = v * (kc_real)kt_uniform(r, 2.0, 8.0);
    kt_line_draw d = {0.05, 0.25, 0.2, v, a, a * (kc_real)kt_uniform(r, 5.0, 20.0)};
    return kt_checked_line(r, &CHECK, KT_PUMA_Q0, &home, id, &d);
}

static void test_verdict_jerk_is_the_runs(void **state)
{
    (void)state;
    kc_ctrl_cfg cfg = setup(KC_R(0.004));
    kt_rng r = kt_rng_make(0x7E4C);
    for (int c = 0; c < CASES / 2; c++) {
        kc_goal g = fast_line(&r, 10 + c);
        kc_verdict v;
        assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_OK);
        double want = stepped_jerk(&g, cfg.dt); /* in double: the core's is kc_real's rounding of it */
        kt_near((double)v.jerk, want, 4.0 * (double)KC_REAL_EPS * want, "the verdict's jerk, stepped here");
        assert_true(v.jerk > KC_R(0.0));
    }
    /* Not stepped: a joint move without zones is judged by its plan, a
     * servo goal by its fields. */
    kc_goal j = kt_joint_goal(50, KT_PUMA_Q0, 6);
    j.q[0] += KC_R(0.5);
    kc_verdict v;
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &j, &v), KC_OK);
    assert_true(v.jerk == KC_R(0.0));
    assert_true(kc_check_slowing(&v) == KC_R(1.0));
    assert_true(kc_check_slowing(NULL) == KC_R(1.0));
    v.jerk = KC_R(8.0);
    kt_near((double)kc_check_slowing(&v), cbrt((double)KC_CHECK_JERK_MARGIN / 8.0), 4.0 * (double)KC_REAL_EPS,
            "the slowing for a jerk 8 times the limits");
}

static void test_slow_scales_the_law(void **state)
{
    (void)state;
    kc_ctrl_cfg cfg = kc_ctrl_cfg_default();
    const kc_real s = KC_R(0.8);
    kc_pose to = {.R = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, .t = {{0.5, 0.0, 0.5}}};
    kc_goal g = kt_line_goal(1, &to);
    assert_int_equal(kc_goal_slow(&g, &cfg, s), KC_OK);
    /* The defaults, taken and scaled. */
    kt_near((double)g.speed, (double)(s * cfg.cart_speed), 0.0, "speed");
    kt_near((double)g.accel, (double)(s * s * cfg.cart_accel), 0.0, "accel");
    kt_near((double)g.omega, (double)(s * cfg.cart_omega), 0.0, "omega");
    kt_near((double)g.alpha, (double)(s * s * cfg.cart_alpha), 0.0, "alpha");
    kt_near((double)g.jerk, (double)(s * s * s * cfg.cart_jerk), 0.0, "jerk");
    kt_near((double)g.angular_jerk, (double)(s * s * s * cfg.cart_angular_jerk), 0.0, "angular jerk");
    /* The goal's own, scaled again. */
    kc_goal h = g;
    assert_int_equal(kc_goal_slow(&h, &cfg, s), KC_OK);
    kt_near((double)h.speed, (double)(s * g.speed), 0.0, "speed slowed twice");
    kt_near((double)h.jerk, (double)(s * s * s * g.jerk), 0.0, "jerk slowed twice");
    /* A Cartesian path's knot times and blend time stretch by 1/s. */
    kc_goal p;
    memset(&p, 0, sizeof p);
    p.kind = KC_GOAL_PATH_CART;
    p.vel_scale = p.acc_scale = KC_R(1.0);
    p.n_points = 3;
    p.has_times = 1;
    p.blend_time = KC_R(0.2);
    for (int i = 0; i < 3; i++)
        p.times[i] = KC_R(0.5) * (kc_real)(i + 1);
    assert_int_equal(kc_goal_slow(&p, &cfg, s), KC_OK);
    for (int i = 0; i < 3; i++)
        kt_near((double)p.times[i], (double)(KC_R(0.5) * (kc_real)(i + 1) / s), 0.0, "knot time");
    kt_near((double)p.blend_time, (double)(KC_R(0.2) / s), 0.0, "blend time");
    /* Refused, and left as they were: a trapezoid line (the goal's or the
     * configuration's), a joint move, a servo goal, s outside (0, 1]. */
    const kc_real bad_s[4] = {KC_R(0.0), KC_R(-0.5), KC_R(1.5), (kc_real)NAN};
    for (int i = 0; i < 4; i++) {
        kc_goal b = g;
        assert_int_equal(kc_goal_slow(&b, &cfg, bad_s[i]), KC_E_ARG);
        assert_memory_equal(&b, &g, sizeof b);
    }
    kc_goal t = g;
    t.profile = KC_GOAL_PROFILE_TRAPEZOID;
    kc_goal t0 = t;
    assert_int_equal(kc_goal_slow(&t, &cfg, s), KC_E_ARG);
    assert_memory_equal(&t, &t0, sizeof t);
    kc_ctrl_cfg trap = cfg;
    trap.profile = KC_PROFILE_TRAPEZOID;
    kc_goal u = kt_line_goal(2, &to), u0 = u;
    assert_int_equal(kc_goal_slow(&u, &trap, s), KC_E_ARG);
    assert_memory_equal(&u, &u0, sizeof u);
    kc_goal j = kt_joint_goal(3, KT_PUMA_Q0, 6), j0 = j;
    assert_int_equal(kc_goal_slow(&j, &cfg, s), KC_E_ARG);
    assert_memory_equal(&j, &j0, sizeof j);
    kc_goal sv = g;
    sv.kind = KC_GOAL_SERVO;
    kc_goal sv0 = sv;
    assert_int_equal(kc_goal_slow(&sv, &cfg, s), KC_E_ARG);
    assert_memory_equal(&sv, &sv0, sizeof sv);
    assert_int_equal(kc_goal_slow(NULL, &cfg, s), KC_E_ARG);
    assert_int_equal(kc_goal_slow(&g, NULL, s), KC_E_ARG);
}

static void test_slowed_lines_keep_joints_within_jerk(void **state)
{
    (void)state;
#ifdef KC_REAL_FLOAT
    skip(); /* the file's header: float's rounding noise */
#endif
    kc_ctrl_cfg cfg = setup(KC_R(0.004)); /* kinctld's dry run, for its 1 ms cycle */
    const kc_real dt = KC_R(0.001);
    kt_rng r = kt_rng_make(0x5103);
    int over = 0;
    for (int c = 0; c < CASES; c++) {
        kc_goal g = fast_line(&r, 100 + c);
        over += stepped_jerk(&g, dt) > 1.0;
        kc_verdict v;
        assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_OK);
        for (int pass = 0; pass < 3 && kc_check_slowing(&v) < KC_R(1.0); pass++) {
            assert_int_equal(kc_goal_slow(&g, &cfg, kc_check_slowing(&v)), KC_OK);
            assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_OK);
        }
        assert_true(v.jerk <= KC_R(1.0));
        kt_near(stepped_jerk(&g, dt) <= 1.0, 1.0, 0.0, "the slowed line's joints within qddd_max at 1 ms");
    }
    /* Most of these lines need it. */
    assert_true(over >= CASES / 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_verdict_jerk_is_the_runs),
        cmocka_unit_test(test_slow_scales_the_law),
        cmocka_unit_test(test_slowed_lines_keep_joints_within_jerk),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("check_slow");
    return rc;
}
