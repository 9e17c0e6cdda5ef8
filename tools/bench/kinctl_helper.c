/*
 * kinctl_helper.c - kinctl's FK and Jacobian in one precision, for fk_bench.
 *
 * Compiled twice (kinctl_bench_double, kinctl_bench_float): the two core
 * builds share their symbol names, so they cannot live in one executable.
 * The driver (fk_bench.cpp) runs it once to check results and then once per
 * timed block, interleaved with KDL's and Pinocchio's blocks. Output follows
 * the protocol in bench_common.h.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "kinctl/kinctl.h"

static const kc_model bench_to_kc[BENCH_N_MODELS] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};

/* Static: a configuration set and a block of timings are too big to want
 * on the stack. */
static double q_double[BENCH_CONFIGS][BENCH_MAX_JOINTS];
static kc_real q_set[BENCH_CONFIGS][BENCH_MAX_JOINTS];
static double timings_ns[BENCH_BATCHES];

/* Builds the model and its configuration set; the float build gets the
 * double set rounded once, here, outside any timed loop. */
static int setup(int model, kc_chain *chain)
{
    kc_status st = kc_chain_init_model(chain, bench_to_kc[model], NULL);
    if (st != KC_OK || chain->n_joints != bench_model_joints[model]) {
        printf("error %s: kc_chain_init_model: %s\n", bench_model_names[model], kc_status_str(st));
        return 1;
    }
    bench_make_configs(model, q_double);
    for (int k = 0; k < BENCH_CONFIGS; k++)
        for (int j = 0; j < BENCH_MAX_JOINTS; j++)
            q_set[k][j] = (kc_real)q_double[k][j];
    return 0;
}

static int check(int model)
{
    const char *name = bench_model_names[model];
    kc_chain chain;
    if (setup(model, &chain) != 0)
        return 1;
    for (int k = 0; k < BENCH_CHECKS; k++) {
        kc_pose pose, pose_j;
        kc_jacobian jac;
        if (kc_fk_eval(&chain, q_set[k], &pose) != KC_OK || kc_fk_jacobian(&chain, q_set[k], &jac, &pose_j) != KC_OK) {
            printf("error %s: FK failed on configuration %d\n", name, k);
            return 1;
        }
        printf("check %s %d pose", name, k);
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                printf(" %.17g", (double)pose.R.m[r][c]);
        for (int r = 0; r < 3; r++)
            printf(" %.17g", (double)pose.t.v[r]);
        printf("\ncheck %s %d jac", name, k);
        for (int r = 0; r < 6; r++)
            for (int c = 0; c < chain.n_joints; c++)
                printf(" %.17g", (double)jac.m[r][c]);
        printf("\n");
    }
    return 0;
}

static int time_block(int model, const char *op, int n_batches)
{
    kc_chain chain;
    if (setup(model, &chain) != 0)
        return 1;
    /* The checksum reads one output of every call, so no call can be
     * dropped as dead code; it costs one add per call, as in the driver. */
    double sum = 0.0;
    if (strcmp(op, "fk") == 0) {
        kc_pose pose;
        BENCH_TIME(timings_ns, n_batches, kc_fk_eval(&chain, q_set[k], &pose); sum += (double)pose.t.v[0]);
    } else if (strcmp(op, "jac") == 0) {
        kc_jacobian jac;
        int last = chain.n_joints - 1;
        BENCH_TIME(timings_ns, n_batches, kc_fk_jacobian(&chain, q_set[k], &jac, NULL); sum += (double)jac.m[0][last]);
    } else {
        printf("error: unknown op %s\n", op);
        return 1;
    }
    printf("ns");
    for (int b = 0; b < n_batches; b++)
        printf(" %.3f", timings_ns[b]);
    printf("\nchecksum %.17g\n", sum);
    return 0;
}

static int model_index(const char *name)
{
    for (int m = 0; m < BENCH_N_MODELS; m++)
        if (strcmp(name, bench_model_names[m]) == 0)
            return m;
    return -1;
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "check") == 0) {
        int bad = 0;
        for (int m = 0; m < BENCH_N_MODELS; m++)
            bad |= check(m);
        return bad;
    }
    if (argc == 5 && strcmp(argv[1], "time") == 0) {
        int model = model_index(argv[2]);
        int n_batches = atoi(argv[4]);
        if (model >= 0 && n_batches > 0 && n_batches <= BENCH_BATCHES)
            return time_block(model, argv[3], n_batches);
    }
    printf("usage: %s check | time <puma560|panda> <fk|jac> <batches 1..%d>\n", argv[0], BENCH_BATCHES);
    return 2;
}
