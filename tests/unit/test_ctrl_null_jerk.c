/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_null_jerk.c - a redundant arm's null-space motion within its
 * joints' jerk limits (kinctl/ik.h, kinctl/ctrl.h). Random lines and arcs
 * of the Panda from a pose away from mid-range (test_ctrl_settle's), at
 * the default Cartesian limits and at random fast ones, judged
 * as kinctld judges them (a dry run at the cycle's period, slowed along
 * kc_check_slow's search where the joints' jerk is over; kt_judge_slowed)
 * and stepped at 1 ms: on every tick every joint's qdd
 * changes by at most qddd_max dt. Two things decide it:
 * - The null-space motion's joint-limit barrier. With its gradient rising
 *   linearly inside the margin (100 / m^2 per rad), the null-space
 *   velocity jumped to its bound within a few mrad of a joint entering the
 *   margin, the IK step's one scale for every joint then stepped qdd where
 *   a joint met its acceleration limit, and slowing the tool did little
 *   against that: 6 of the 124 taken went over, up to 2.0 x qddd_max.
 * - The dry run's period. Where the IK step holds a joint at its
 *   acceleration limit, its scaling makes a different motion at 4 ms than
 *   at 1 ms: judged at 4 ms, 1 of the 123 taken (11 of 788 in 1000 cases)
 *   went over at 1 ms, 1.23 x qddd_max, while its verdict said 0.48.
 * In double only: in float the IK step's rounding alone makes
 * tick-to-tick jerk noise above qddd_max in any Cartesian motion. */
#include <math.h>
#include <string.h>

#include "kinctl/check.h"
#include "kinctl/fk.h"
#include "testutil.h"

#define CASES 150

static const kc_real Q0[7] = {KC_R(0.0), KC_R(-0.3), KC_R(0.0), KC_R(-2.0), KC_R(0.0), KC_R(1.8), KC_R(0.8)};

static kc_chain CHAIN;
static kc_ctrl CTRL; /* large: not on the stack */
static kc_check CHECK;

/* A line or (odd c) an arc of 5 to 30 cm from the pose of Q0: at the
 * default limits for c % 4 < 2, else at speed, accel and jerk drawn up to
 * fast ones. */
static kc_goal random_goal(kt_rng *r, int c, const kc_pose *home)
{
    kc_goal g = kt_line_goal(10 + c, home);
    kc_vec3 dir = kt_rand_unit(r);
    kc_real len = (kc_real)kt_uniform(r, 0.05, 0.3);
    for (int i = 0; i < 3; i++)
        g.pose.t.v[i] += len * dir.v[i];
    if (c % 2) {
        g.kind = KC_GOAL_ARC;
        for (int i = 0; i < 3; i++)
            g.via.v[i] = KC_R(0.5) * (home->t.v[i] + g.pose.t.v[i]) + (kc_real)kt_uniform(r, -0.05, 0.05);
    }
    if (c % 4 >= 2) {
        g.speed = (kc_real)kt_uniform(r, 0.05, 0.5);
        g.accel = g.speed * (kc_real)kt_uniform(r, 2.0, 8.0);
        g.jerk = g.accel * (kc_real)kt_uniform(r, 5.0, 20.0);
    }
    return g;
}

/* g judged from rest at Q0 (kt_judge_fn). */
static kc_status judge_at_rest(const kc_goal *g, kc_verdict *v, void *ctx)
{
    (void)ctx;
    return kc_check_from(&CHECK, Q0, g, v);
}

/* The largest change of a joint's qdd over a tick, in units of its
 * qddd_max dt, of g stepped from rest at Q0 at period dt to its end (which
 * must be COMPLETED). */
static double stepped_jerk(const kc_goal *g, kc_real dt)
{
    kc_ctrl_cfg cfg = kc_ctrl_cfg_default();
    cfg.dt = dt;
    assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &cfg, Q0), KC_OK);
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

static void test_null_space_motion_within_jerk(void **state)
{
    (void)state;
#ifdef KC_REAL_FLOAT
    skip(); /* the file's header: float's rounding noise */
#endif
    assert_int_equal(kc_chain_init_model(&CHAIN, KC_MODEL_PANDA, NULL), KC_OK);
    kc_ctrl_cfg check_cfg = kc_ctrl_cfg_default();
    check_cfg.dt = KC_R(0.001); /* kinctld's dry run, at its cycle's period */
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &check_cfg, 100000, Q0), KC_OK);
    kc_pose home;
    kc_fk_eval(&CHAIN, Q0, &home);
    kt_rng r = kt_rng_make(0x4E11);
    int taken = 0;
    double worst = 0.0;
    for (int c = 0; c < CASES; c++) {
        kc_goal g = random_goal(&r, c, &home);
        kc_verdict v;
        if (kt_judge_slowed(judge_at_rest, NULL, &check_cfg, &g, &v) != KC_OK)
            continue; /* out of reach, or a degenerate arc */
        taken++;
        double jerk = stepped_jerk(&g, check_cfg.dt);
        if (jerk > 1.0)
            print_message("goal %lld: its joints' jerk %.3f x qddd_max at 1 ms\n", (long long)g.id, jerk);
        worst = fmax(worst, jerk);
    }
    print_message("%d of %d taken, the largest change of qdd over a tick %.4f x qddd_max dt\n", taken, CASES, worst);
    assert_true(taken >= CASES * 2 / 3);
    assert_true(worst <= 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_null_space_motion_within_jerk),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl_null_jerk");
    return rc;
}
