/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ik_rolled.c - the damped least-squares kernel of the IK
 * (core/src/ik_internal.h) rolled against unrolled: kc_ik_dls_rolled, which
 * the IK built for size calls for the position and axis tasks, against the
 * kernel instantiated here with the task size a constant (its loops
 * unrolled, as ik.c's own instances), bit for bit on random problems of
 * every task size, with and without the null-space term, frozen joints,
 * error damping and singularity damping. */
#include <string.h>

#include "testutil.h"

#include "ik_internal.h"

/* A problem of task size r on the model's chain: the task Jacobian is the
 * chain's own at a random configuration (rows 3-5 mixed as the axis task's
 * are for r = 5), u, q and the frozen joints random. */
typedef struct dls_case {
    kc_ik_problem p;
    kc_ik_cfg cfg;
    kc_real jt[6][KC_MAX_JOINTS];
    kc_real u[6], q[KC_MAX_JOINTS];
    kc_real lambda2, null_scale, null_bound;
    uint8_t frozen[KC_MAX_JOINTS];
} dls_case;

static void make_case(kt_rng *r, const kc_chain *c, int rows, dls_case *k)
{
    memset(k, 0, sizeof *k);
    k->cfg = kc_ik_cfg_default();
    k->p.chain = c;
    k->p.cfg = &k->cfg;
    k->p.n = c->n_joints;
    k->p.r = rows;
    k->p.singular_damping = kt_uniform(r, 0.0, 1.0) < 0.5;
    for (int j = 0; j < c->n_joints; j++) {
        const kc_joint_limits *l = &c->joints[j].limits;
        k->p.lo[j] = l->q_min;
        k->p.hi[j] = l->q_max;
        k->p.range[j] = l->q_max - l->q_min;
        k->p.rest[j] = KC_R(0.5) * (l->q_min + l->q_max);
        k->q[j] = (kc_real)kt_uniform(r, (double)l->q_min, (double)l->q_max);
        k->frozen[j] = kt_uniform(r, 0.0, 1.0) < 0.15;
    }
    kc_jacobian jac;
    kc_pose tool;
    kc_fk_jacobian(c, k->q, &jac, &tool);
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < c->n_joints; j++)
            k->jt[i][j] = jac.m[i][j];
    if (rows == 5)
        for (int j = 0; j < c->n_joints; j++)
            k->jt[4][j] = jac.m[5][j] - KC_R(0.3) * jac.m[3][j];
    for (int i = 0; i < rows; i++)
        k->u[i] = (kc_real)kt_uniform(r, -0.5, 0.5);
    k->lambda2 = kt_uniform(r, 0.0, 1.0) < 0.5 ? KC_R(0.0) : (kc_real)kt_uniform(r, 0.0, 1e-2);
    k->null_scale = kt_uniform(r, 0.0, 1.0) < 0.3 ? KC_R(0.0) : KC_R(0.5);
    k->null_bound = (kc_real)kt_uniform(r, 0.01, 2.0);
}

static kc_real unrolled(dls_case *k, kc_real *dq)
{
    switch (k->p.r) {
    case 3: return kc_ik_dls_kernel(&k->p, k->jt, k->u, k->lambda2, k->null_scale, k->null_bound, k->q, k->frozen, dq, 3);
    case 5: return kc_ik_dls_kernel(&k->p, k->jt, k->u, k->lambda2, k->null_scale, k->null_bound, k->q, k->frozen, dq, 5);
    default: return kc_ik_dls_kernel(&k->p, k->jt, k->u, k->lambda2, k->null_scale, k->null_bound, k->q, k->frozen, dq, 6);
    }
}

static void test_rolled_is_unrolled(void **state)
{
    (void)state;
    static const kc_model models[3] = {KC_MODEL_PUMA560, KC_MODEL_PANDA, KC_MODEL_RRR3};
    static const int rows[3] = {3, 5, 6};
    kt_rng r = kt_rng_make(20);
    int singular = 0;
    for (int m = 0; m < 3; m++) {
        kc_chain c;
        assert_int_equal(kc_chain_init_model(&c, models[m], NULL), KC_OK);
        for (int t = 0; t < 3; t++) {
            for (int i = 0; i < 300; i++) {
                dls_case k;
                make_case(&r, &c, rows[t], &k);
                kc_real a[KC_MAX_JOINTS], b[KC_MAX_JOINTS];
                kc_real wa = unrolled(&k, a);
                kc_real wb = kc_ik_dls_rolled(&k.p, k.jt, k.u, k.lambda2, k.null_scale, k.null_bound, k.q, k.frozen, b);
                assert_memory_equal(a, b, sizeof(kc_real) * (size_t)c.n_joints);
                assert_memory_equal(&wa, &wb, sizeof wa);
                singular += k.p.singular_damping && wa < k.cfg.manip_threshold;
            }
        }
    }
    /* The RRR arm's 6-row task is rank-deficient: the singularity damping
     * was exercised. */
    assert_true(singular > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rolled_is_unrolled),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ik_rolled");
    return failed;
}
