/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * fx_bench.c - instructions per call of the fixed-point FK and Jacobian
 * (kinctl/fx.h) beside the floating-point ones of the same core, on a PUMA
 * 560 at 100 random configurations, and of the evaluation of joint moves
 * (the trapezoid; jerk-limited, synchronised by phase and by time) and of
 * lines (slerp; the trapezoid, jerk-limited) at every tick, between the
 * first two configurations and their tool poses: on the Cortex-M3 the
 * float calls are
 * libgcc's soft float, on the Cortex-M4F the FPU's. Counted with SysTick
 * under -icount shift=0 (board/systick.h). Prints
 *   icount <what> calls <n> mean <instructions> max <instructions>
 */
#include <stdint.h>
#include <stdio.h>

#include "board/systick.h"
#include "kinctl/kinctl.h"

#define N_CONFIGS 100

static kc_chain chain;
static kc_fx_chain fx;
static kc_real q[N_CONFIGS][6];
static int32_t qf[N_CONFIGS][6];

typedef struct tally {
    uint32_t calls, max;
    uint64_t total;
} tally;

static void add(tally *t, uint32_t n)
{
    t->calls++;
    t->total += n;
    if (n > t->max)
        t->max = n;
}

static void report(const char *what, const tally *t)
{
    printf("icount %s calls %lu mean %lu max %lu\n", what, (unsigned long)t->calls,
           (unsigned long)((t->total + t->calls / 2u) / t->calls), (unsigned long)t->max);
}

int main(void)
{
    if (kc_chain_init_model(&chain, KC_MODEL_PUMA560, NULL) != KC_OK || kc_fx_chain_init(&fx, &chain) != KC_OK)
        return 1;
    uint32_t s = 12345u;
    for (int i = 0; i < N_CONFIGS; i++) {
        for (int j = 0; j < 6; j++) {
            s = s * 1664525u + 1013904223u; /* LCG: any spread of angles */
            kc_real u = (kc_real)(s >> 8) / KC_R(16777216.0);
            kc_real lo = chain.joints[j].limits.q_min, hi = chain.joints[j].limits.q_max;
            q[i][j] = lo + (hi - lo) * u;
        }
        if (kc_fx_q_from_real(&fx, q[i], qf[i]) != KC_OK)
            return 1;
    }
    kc_systick_start();
    tally fk = {0, 0, 0}, jac = {0, 0, 0}, fx_fk = {0, 0, 0}, fx_jac = {0, 0, 0};
    kc_pose T;
    kc_jacobian J;
    kc_fx_pose Tf;
    kc_fx_jacobian Jf;
    for (int i = 0; i < N_CONFIGS; i++) {
        uint32_t c0 = kc_systick_now();
        kc_fk_eval(&chain, q[i], &T);
        uint32_t c1 = kc_systick_now();
        kc_fk_jacobian(&chain, q[i], &J, &T);
        uint32_t c2 = kc_systick_now();
        kc_fx_fk_eval(&fx, qf[i], &Tf);
        uint32_t c3 = kc_systick_now();
        kc_fx_jacobian_eval(&fx, qf[i], &Jf, &Tf);
        uint32_t c4 = kc_systick_now();
        add(&fk, kc_systick_insns(c0, c1));
        add(&jac, kc_systick_insns(c1, c2));
        add(&fx_fk, kc_systick_insns(c2, c3));
        add(&fx_jac, kc_systick_insns(c3, c4));
    }
    /* The trapezoid and jerk-limited moves at the arm's limits (by phase),
     * and one with the jerk limits of the joints spread (by time: a
     * profile per joint). */
    static const char *const joint_names[3][2] = {{"joint_eval_" KC_REAL_NAME, "fx_joint_eval"},
                                                  {"joint_jerk_eval_" KC_REAL_NAME, "fx_joint_jerk_eval"},
                                                  {"joint_jerk_time_eval_" KC_REAL_NAME, "fx_joint_jerk_time_eval"}};
    tally jm[3][2];
    for (int m = 0; m < 3; m++) {
        kc_interp_joint_cfg c = kc_interp_joint_cfg_default();
        c.n = 6;
        c.dt = KC_R(0.001);
        c.profile = m == 0 ? KC_PROFILE_TRAPEZOID : KC_PROFILE_JERK;
        for (int j = 0; j < 6; j++) {
            c.q0[j] = q[0][j];
            c.q1[j] = q[1][j];
            c.qd_max[j] = chain.joints[j].limits.qd_max;
            c.qdd_max[j] = chain.joints[j].limits.qdd_max;
            c.qddd_max[j] = chain.joints[j].limits.qddd_max * (m == 2 ? KC_R(1.0) + KC_R(0.5) * (kc_real)j : KC_R(1.0));
        }
        static kc_interp_joint plan;
        static kc_fx_joint_move move;
        if (kc_interp_joint_plan_cfg(&plan, &c) != KC_OK || kc_fx_joint_init(&move, &fx, &plan) != KC_OK ||
            (m > 0 && plan.sync != (m == 1 ? KC_INTERP_SYNC_PHASE : KC_INTERP_SYNC_TIME)))
            return 1;
        tally t0 = {0, 0, 0}, t1 = {0, 0, 0};
        for (int64_t k = 0; k < plan.ticks; k++) {
            kc_interp_joint_state st;
            int32_t qk[6];
            uint32_t c0 = kc_systick_now();
            kc_interp_joint_eval(&plan, k, &st);
            uint32_t c1 = kc_systick_now();
            kc_fx_joint_eval(&move, k, qk);
            uint32_t c2 = kc_systick_now();
            add(&t0, kc_systick_insns(c0, c1));
            add(&t1, kc_systick_insns(c1, c2));
        }
        jm[m][0] = t0;
        jm[m][1] = t1;
    }
    kc_pose from, to;
    kc_fk_eval(&chain, q[0], &from);
    kc_fk_eval(&chain, q[1], &to);
    /* A line (slerp) by the trapezoid and jerk-limited. */
    static const char *const line_names[2][2] = {{"line_eval_" KC_REAL_NAME, "fx_line_eval"},
                                                 {"line_jerk_eval_" KC_REAL_NAME, "fx_line_jerk_eval"}};
    tally le[2][2];
    for (int m = 0; m < 2; m++) {
        kc_interp_limits lim = kc_interp_limits_default();
        lim.v = KC_R(0.5);
        lim.a = KC_R(2.0);
        if (m == 1)
            lim.j = KC_R(20.0);
        kc_interp_line lplan;
        kc_fx_line line;
        if (kc_interp_line_plan(&lplan, &from, &to, &lim, KC_INTERP_SLERP, KC_R(0.001)) != KC_OK ||
            kc_fx_line_init(&line, &lplan) != KC_OK)
            return 1;
        tally t0 = {0, 0, 0}, t1 = {0, 0, 0};
        for (int64_t k = 0; k < lplan.ticks; k++) {
            kc_interp_cart_state st;
            int32_t p[3], qk[4];
            uint32_t c0 = kc_systick_now();
            kc_interp_line_eval(&lplan, k, &st);
            uint32_t c1 = kc_systick_now();
            kc_fx_line_eval(&line, k, p, qk);
            uint32_t c2 = kc_systick_now();
            add(&t0, kc_systick_insns(c0, c1));
            add(&t1, kc_systick_insns(c1, c2));
        }
        le[m][0] = t0;
        le[m][1] = t1;
    }
    report("fk_" KC_REAL_NAME, &fk);
    report("jacobian_" KC_REAL_NAME, &jac);
    report("fx_fk", &fx_fk);
    report("fx_jacobian", &fx_jac);
    for (int m = 0; m < 3; m++)
        for (int i = 0; i < 2; i++)
            report(joint_names[m][i], &jm[m][i]);
    for (int m = 0; m < 2; m++)
        for (int i = 0; i < 2; i++)
            report(line_names[m][i], &le[m][i]);
    return 0;
}
