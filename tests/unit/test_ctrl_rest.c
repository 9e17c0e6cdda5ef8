/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_rest.c - how a Cartesian segment comes to rest (kinctl/ik.h,
 * kc_ik_step's KC_DONE): once the tool has settled on the segment's end,
 * the IK step stops every joint in one tick (qd to 0, qdd to -qd/dt) and
 * the tick after it is idle (qdd 0). Random lines from the PUMA 560's
 * start pose, at the default limits and at random slower ones, each run
 * to its end: both changes of qdd stay within qddd_max dt, as every other
 * stop does. In float the online law's rounding keeps qd at up to a few
 * units of q's last place per tick (ik.h), which that stop may remove:
 * 4 KC_REAL_EPS max(|q|, 1) / dt^2 of qdd change. */
#include <math.h>
#include <string.h>

#include "kinctl/check.h"
#include "testutil.h"

#ifdef KC_REAL_FLOAT
#define CASES 20
#else
#define CASES 60
#endif

typedef struct harness {
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    double qd_prev[KC_MAX_JOINTS], qdd_prev[KC_MAX_JOINTS];
    int on_line; /* a line is the goal under way */
    int stops;   /* lines whose rest took some qd != 0 to 0 in a tick */
} harness;

static harness H; /* large: not on the stack */
static kc_check CHECK;

static void setup(void)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, KC_MODEL_PUMA560, NULL), KC_OK);
    H.cfg = kc_ctrl_cfg_default();
    assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, KT_PUMA_Q0), KC_OK);
    assert_int_equal(kc_check_init(&CHECK, &H.chain, &H.cfg, 100000, KT_PUMA_Q0), KC_OK);
}

/* The largest change of joint j's qdd over one tick the stop at rest may
 * make (the file's header). */
static double jerk_bound(int j, double q)
{
    double dt = (double)H.cfg.dt;
    double ulps = 4.0 * (double)KC_REAL_EPS * fmax(fabs(q), 1.0) / dt / dt;
    return fmax((double)H.chain.joints[j].limits.qddd_max * dt, ulps) * (1.0 + 1e-9);
}

/* One tick; at the tick that brings the arm to rest, and the one after,
 * the change of every joint's qdd within jerk_bound. */
static void tick(const kc_goal *g)
{
    kc_ctrl_input in = {g, KC_CMD_NONE, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    int n = H.chain.n_joints, was_moving = 0, moving = 0;
    for (int j = 0; j < n; j++) {
        was_moving |= H.qd_prev[j] != 0.0;
        moving |= H.out.qd[j] != KC_R(0.0);
    }
    int stopping = was_moving && !moving, after = !was_moving && !moving;
    for (int j = 0; j < n; j++) {
        double qdd = (double)H.out.qdd[j];
        if (stopping || after)
            kt_near(fabs(qdd - H.qdd_prev[j]) <= jerk_bound(j, (double)H.out.q[j]), 1.0, 0.0,
                    stopping ? "jerk of the stop at rest" : "jerk of the tick after it");
        H.qd_prev[j] = (double)H.out.qd[j];
        H.qdd_prev[j] = qdd;
    }
    H.stops += stopping && H.on_line;
}

/* A line of up to 30 cm from the start pose, turning the tool by up to
 * 0.2 rad, that the dry run accepts; limits 0: the defaults. */
static kc_goal random_line(kt_rng *r, int64_t id, kc_real speed, kc_real accel, kc_real jerk)
{
    kc_pose home;
    kc_fk_eval(&H.chain, KT_PUMA_Q0, &home);
    kt_line_draw d = {0.02, 0.3, 0.2, speed, accel, jerk};
    return kt_checked_line(r, &CHECK, H.ctrl.q, &home, id, &d);
}

static void test_lines_come_to_rest_within_jerk(void **state)
{
    (void)state;
    setup();
    kt_rng r = kt_rng_make(0x5E77);
    for (int c = 0; c < CASES; c++) {
        kc_goal g = c % 2 ? random_line(&r, 100 + c, (kc_real)kt_uniform(&r, 0.05, 0.3),
                                        (kc_real)kt_uniform(&r, 0.2, 1.0), (kc_real)kt_uniform(&r, 1.0, 20.0))
                          : random_line(&r, 100 + c, KC_R(0.0), KC_R(0.0), KC_R(0.0));
        H.on_line = 1;
        tick(&g);
        int done = 0;
        for (int k = 0; k < 100000 && !done; k++) {
            tick(NULL);
            assert_false(kt_has_event(&H.out, KC_EVENT_FAULT, g.id));
            done = kt_has_event(&H.out, KC_EVENT_COMPLETED, g.id);
        }
        assert_true(done);
        tick(NULL); /* the tick after the stop */
        H.on_line = 0;
        /* And back to the start for the next line. */
        kc_goal back = kt_joint_goal(1000 + c, KT_PUMA_Q0, 6);
        tick(&back);
        for (int k = 0; k < 100000 && !kt_has_event(&H.out, KC_EVENT_COMPLETED, back.id); k++)
            tick(NULL);
        tick(NULL);
    }
    /* Most lines end with the tool still creeping onto its end: a stop that
     * the bound judged (the others rest exactly). */
    assert_true(H.stops >= CASES / 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lines_come_to_rest_within_jerk),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl_rest");
    return rc;
}
