/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * fx_bench.c - instructions per call of the fixed-point FK and Jacobian
 * (kinctl/fx.h) beside the floating-point ones of the same core, on a PUMA
 * 560 at 100 random configurations, and of the evaluation of a joint move
 * and of a line (slerp) at every tick, between the tool poses of the first
 * two configurations: on the
 * Cortex-M3 the float calls are
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
    kc_real vmax[6], amax[6];
    for (int j = 0; j < 6; j++) {
        vmax[j] = chain.joints[j].limits.qd_max;
        amax[j] = chain.joints[j].limits.qdd_max;
    }
    kc_interp_joint plan;
    kc_fx_joint_move move;
    if (kc_interp_joint_plan(&plan, 6, q[0], q[1], vmax, amax, KC_R(0.0), KC_R(0.001)) != KC_OK ||
        kc_fx_joint_init(&move, &fx, &plan) != KC_OK)
        return 1;
    tally jm = {0, 0, 0}, fx_jm = {0, 0, 0};
    for (int64_t k = 0; k < plan.prof.ticks; k++) {
        kc_interp_joint_state st;
        int32_t qk[6];
        uint32_t c0 = kc_systick_now();
        kc_interp_joint_eval(&plan, k, &st);
        uint32_t c1 = kc_systick_now();
        kc_fx_joint_eval(&move, k, qk);
        uint32_t c2 = kc_systick_now();
        add(&jm, kc_systick_insns(c0, c1));
        add(&fx_jm, kc_systick_insns(c1, c2));
    }
    kc_pose from, to;
    kc_fk_eval(&chain, q[0], &from);
    kc_fk_eval(&chain, q[1], &to);
    kc_interp_limits lim = kc_interp_limits_default();
    lim.v = KC_R(0.5);
    lim.a = KC_R(2.0);
    kc_interp_line lplan;
    kc_fx_line line;
    if (kc_interp_line_plan(&lplan, &from, &to, &lim, KC_INTERP_SLERP, KC_R(0.001)) != KC_OK ||
        kc_fx_line_init(&line, &lplan) != KC_OK)
        return 1;
    tally le = {0, 0, 0}, fx_le = {0, 0, 0};
    for (int64_t k = 0; k < lplan.prof.ticks; k++) {
        kc_interp_cart_state st;
        int32_t p[3], qk[4];
        uint32_t c0 = kc_systick_now();
        kc_interp_line_eval(&lplan, k, &st);
        uint32_t c1 = kc_systick_now();
        kc_fx_line_eval(&line, k, p, qk);
        uint32_t c2 = kc_systick_now();
        add(&le, kc_systick_insns(c0, c1));
        add(&fx_le, kc_systick_insns(c1, c2));
    }
    report("fk_" KC_REAL_NAME, &fk);
    report("jacobian_" KC_REAL_NAME, &jac);
    report("fx_fk", &fx_fk);
    report("fx_jacobian", &fx_jac);
    report("joint_eval_" KC_REAL_NAME, &jm);
    report("fx_joint_eval", &fx_jm);
    report("line_eval_" KC_REAL_NAME, &le);
    report("fx_line_eval", &fx_le);
    return 0;
}
