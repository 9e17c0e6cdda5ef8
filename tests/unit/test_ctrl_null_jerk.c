/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_null_jerk.c - a redundant arm's null-space motion within its
 * joints' jerk limits (kinctl/ik.h, kinctl/ctrl.h). Random lines and arcs
 * of the Panda from KT_PANDA_Q0 (testutil.h, off its rest), at
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

static kc_chain CHAIN;
static kc_ctrl CTRL; /* large: not on the stack */
static kc_check CHECK;

/* g judged from rest at KT_PANDA_Q0 (kt_judge_fn). */
static kc_status judge_at_rest(const kc_goal *g, kc_verdict *v, void *ctx)
{
    (void)ctx;
    return kc_check_from(&CHECK, KT_PANDA_Q0, g, v);
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
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &check_cfg, 100000, KT_PANDA_Q0), KC_OK);
    kc_pose home;
    kc_fk_eval(&CHAIN, KT_PANDA_Q0, &home);
    kt_rng r = kt_rng_make(0x4E11);
    int taken = 0;
    double worst = 0.0;
    for (int c = 0; c < CASES; c++) {
        /* A line or an arc, at the default limits or (half of them) fast. */
        kc_goal g = kt_cart_goal(&r, 10 + c, &home, c % 2, c % 4 >= 2);
        kc_verdict v;
        if (kt_judge_slowed(judge_at_rest, NULL, &check_cfg, &g, &v) != KC_OK)
            continue; /* out of reach, or a degenerate arc */
        taken++;
        double jerk = kt_stepped_jerk(&CTRL, &CHAIN, KT_PANDA_Q0, &g, check_cfg.dt);
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
