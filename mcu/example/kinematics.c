/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinematics.c - a program of the kind a firmware holds, built outside the
 * core's own tests through KINCTL_MCU_PROGRAMS (mcu/CMakeLists.txt): for
 * every built-in arm, forward kinematics and the Jacobian at configurations
 * inside the joint limits, an inverse kinematics solve back to one of them,
 * and a joint move and a straight line evaluated at a few ticks. It prints
 * every number it computes, one labelled line each, so the same source
 * built for the board (float core) and for this host (double core) can be
 * compared number by number (tests/mcu/compare_numbers.py). Exit status 1
 * when a call fails or the IK solve misses its tolerance.
 */
#include <stdint.h>
#include <stdio.h>

#include "kinctl/kinctl.h"

#define N_CONFIGS 8
#define N_TICKS 5

static uint32_t rng = 12345u;

/* Uniform in [0, 1) from a 32-bit LCG: the same values in both builds. */
static double uniform(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (double)(rng >> 8) / 16777216.0;
}

static void print_row(const char *label, int model, int i, const kc_real *v, int n)
{
    printf("%s %d %d", label, model, i);
    for (int k = 0; k < n; k++)
        printf(" %.9e", (double)v[k]);
    printf("\n");
}

static void print_pose(const char *label, int model, int i, const kc_pose *p)
{
    kc_real v[12];
    for (int r = 0; r < 3; r++) {
        v[r] = p->t.v[r];
        for (int c = 0; c < 3; c++)
            v[3 + 3 * r + c] = p->R.m[r][c];
    }
    print_row(label, model, i, v, 12);
}

/* A configuration inside the limits (+-pi where a limit is infinite),
 * kept a tenth of the range away from either end. */
static void random_q(const kc_chain *chain, kc_real *q)
{
    for (int j = 0; j < chain->n_joints; j++) {
        double lo = (double)chain->joints[j].limits.q_min, hi = (double)chain->joints[j].limits.q_max;
        if (lo < -3.14159)
            lo = -3.14159;
        if (hi > 3.14159)
            hi = 3.14159;
        double span = hi - lo;
        q[j] = (kc_real)(lo + span * (0.1 + 0.8 * uniform()));
    }
}

static int arm(int model)
{
    static kc_chain chain;
    static kc_jacobian jac;
    static kc_interp_joint move;
    if (kc_chain_init_model(&chain, (kc_model)model, NULL) != KC_OK)
        return 1;
    int n = chain.n_joints;
    kc_real q[KC_MAX_JOINTS], q1[KC_MAX_JOINTS], sol[KC_MAX_JOINTS], row[KC_MAX_JOINTS];
    kc_pose tool;
    for (int i = 0; i < N_CONFIGS; i++) {
        random_q(&chain, q);
        if (kc_fk_jacobian(&chain, q, &jac, &tool) != KC_OK)
            return 1;
        print_pose("fk", model, i, &tool);
        for (int r = 0; r < 6; r++) {
            for (int j = 0; j < n; j++)
                row[j] = jac.m[r][j];
            print_row(r < 3 ? "jacobian_linear" : "jacobian_angular", model, 6 * i + r, row, n);
        }
    }

    /* IK back to the last configuration from one nearby: judged by the
     * pose reached, since float and double may stop at different q. */
    for (int j = 0; j < n; j++)
        q1[j] = q[j] + (kc_real)(0.1 * (uniform() - 0.5));
    kc_ik_cfg cfg = kc_ik_cfg_default();
    kc_ik_result res;
    kc_status st = kc_ik_solve(&chain, &cfg, &tool, q1, sol, &res);
    kc_pose reached;
    if (st != KC_OK || kc_fk_eval(&chain, sol, &reached) != KC_OK) {
        printf("ik %d: status %d\n", model, (int)st);
        return 1;
    }
    print_pose("ik_pose", model, 0, &reached);

    /* A joint move from q1 to q at half the limits, evaluated at a few
     * ticks of a 1 ms cycle. */
    kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS];
    for (int j = 0; j < n; j++) {
        vmax[j] = chain.joints[j].limits.qd_max * KC_R(0.5);
        amax[j] = chain.joints[j].limits.qdd_max * KC_R(0.5);
    }
    if (kc_interp_joint_plan(&move, n, q1, q, vmax, amax, KC_R(0.0), KC_R(0.001)) != KC_OK)
        return 1;
    printf("joint_move_ticks %d 0 %ld\n", model, (long)move.ticks);
    for (int k = 0; k < N_TICKS; k++) {
        kc_interp_joint_state s;
        int64_t tick = move.ticks * k / (N_TICKS - 1);
        if (kc_interp_joint_eval(&move, tick, &s) < KC_OK)
            return 1;
        print_row("joint_move_q", model, k, s.q, n);
        print_row("joint_move_qd", model, k, s.qd, n);
    }

    /* A straight line from the tool pose at q1 to the one at q. */
    kc_pose from;
    kc_interp_line line;
    kc_interp_limits lim = kc_interp_limits_default();
    lim.v = KC_R(0.25);
    lim.a = KC_R(0.5);
    lim.w = KC_R(1.0);
    lim.dw = KC_R(2.0);
    if (kc_fk_eval(&chain, q1, &from) != KC_OK ||
        kc_interp_line_plan(&line, &from, &tool, &lim, KC_INTERP_SLERP, KC_R(0.001)) != KC_OK)
        return 1;
    printf("line_ticks %d 0 %ld\n", model, (long)line.prof.ticks);
    for (int k = 0; k < N_TICKS; k++) {
        kc_interp_cart_state s;
        int64_t tick = line.prof.ticks * k / (N_TICKS - 1);
        if (kc_interp_line_eval(&line, tick, &s) < KC_OK)
            return 1;
        kc_real v[10] = {s.p.v[0], s.p.v[1], s.p.v[2], s.q.w, s.q.x, s.q.y, s.q.z, s.v.v[0], s.v.v[1], s.v.v[2]};
        print_row("line", model, k, v, 10);
    }
    return 0;
}

int main(void)
{
    int failed = 0;
    for (int m = 0; m < (int)KC_MODEL_COUNT; m++) {
        if (arm(m) != 0) {
            printf("model %s: FAILED\n", kc_model_name((kc_model)m));
            failed = 1;
        }
    }
    printf("%s\n", failed ? "FAILED" : "done");
    return failed;
}
