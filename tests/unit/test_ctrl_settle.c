/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_settle.c - a redundant arm's Cartesian segment settles at its
 * end (kinctl/ctrl.h): the Panda's null-space motion (the IK step's
 * null_gain pulling the joints towards mid-range) is brought to rest once
 * the geometry has ended, so the joints come within the IK step's rest
 * bound and the segment completes, at a 1 ms period as at the dry run's
 * 4 ms. Random lines and arcs from a pose away from mid-range, at random
 * Cartesian limits: every one the dry run at 4 ms takes completes at 1 ms
 * without a fault, every joint at rest. Before, the null-space
 * motion, decaying at 0.5/s, kept a joint above the rest bound (at 1 ms
 * min(qdd_max dt, qddd_max dt^2) = 3.75e-3 rad/s for the Panda's joint 2)
 * for longer than the 1000 ticks a segment had to settle: seven lines and
 * arcs in a hundred faulted on the tracking bound at their end. */
#include <string.h>

#include "kinctl/check.h"
#include "kinctl/fk.h"
#include "testutil.h"

#ifdef KC_REAL_FLOAT
#define CASES 20
#else
#define CASES 60
#endif

static kc_chain CHAIN;
static kc_ctrl CTRL; /* large: not on the stack */
static kc_check CHECK;

static void test_redundant_arm_settles(void **state)
{
    (void)state;
    assert_int_equal(kc_chain_init_model(&CHAIN, KC_MODEL_PANDA, NULL), KC_OK);
    kc_ctrl_cfg check_cfg = kc_ctrl_cfg_default(), cfg = kc_ctrl_cfg_default();
    check_cfg.dt = KC_R(0.004); /* kinctld's dry run */
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &check_cfg, 100000, KT_PANDA_Q0), KC_OK);
    kc_pose home;
    kc_fk_eval(&CHAIN, KT_PANDA_Q0, &home);
    kt_rng r = kt_rng_make(0x5E771E);
    int judged = 0, settled = 0;
    for (int c = 0; c < CASES; c++) {
        kc_goal g = kt_cart_goal(&r, 10 + c, &home, c % 2, 1); /* a line or an arc, fast */
        kc_verdict v;
        if (kc_check_from(&CHECK, KT_PANDA_Q0, &g, &v) != KC_OK)
            continue; /* out of reach, or a degenerate arc */
        judged++;
        assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &cfg, KT_PANDA_Q0), KC_OK);
        kc_ctrl_output out;
        int done = 0, after = 0;
        for (int t = 0; t < 100000 && !done; t++) {
            kc_ctrl_input in = {t == 0 ? &g : NULL, KC_CMD_NONE, 0, KC_REASON_NONE};
            assert_int_equal(kc_ctrl_step(&CTRL, &in, &out), KC_OK);
            assert_false(kt_has_event(&out, KC_EVENT_FAULT, g.id));
            done = kt_has_event(&out, KC_EVENT_COMPLETED, g.id);
            after += out.progress >= KC_R(1.0); /* the geometry has ended: settling */
        }
        assert_true(done);
        for (int j = 0; j < CHAIN.n_joints; j++)
            assert_true(out.qd[j] == KC_R(0.0));
        settled += after > 1;
    }
    assert_true(judged >= CASES * 2 / 3);
    assert_true(settled >= judged / 2); /* most end with the tool still settling */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_redundant_arm_settles),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl_settle");
    return rc;
}
