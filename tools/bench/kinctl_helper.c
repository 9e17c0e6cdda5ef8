/*
 * kinctl_helper.c - times kinctl's FK and Jacobian in one precision.
 *
 * Compiled twice (kinctl_bench_double, kinctl_bench_float): the two core
 * builds share their symbol names, so they cannot live in one executable.
 * The driver (fk_bench.cpp) runs both and merges their output with KDL's and
 * Pinocchio's. Output follows the line protocol in bench_common.h.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>

#include "bench_common.h"
#include "kinctl/kinctl.h"

static const kc_model bench_to_kc[BENCH_N_MODELS] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};

/* Static: two sets of 1024 configurations and 4000 timings are too big to
 * want on the stack. */
static double q_double[BENCH_CONFIGS][BENCH_MAX_JOINTS];
static kc_real q_set[BENCH_CONFIGS][BENCH_MAX_JOINTS];
static double timings_ns[BENCH_BATCHES];

static void print_stats(const char *model, const char *op, double checksum)
{
    bench_stats s = bench_summarize(timings_ns, BENCH_BATCHES);
    printf("time %s %s %.3f %.3f %.3f %.17g\n", model, op, s.median_ns, s.p99_ns, s.max_ns, checksum);
}

static int run_model(int model)
{
    const char *name = bench_model_names[model];
    kc_chain chain;
    kc_status st = kc_chain_init_model(&chain, bench_to_kc[model], NULL);
    if (st != KC_OK || chain.n_joints != bench_model_joints[model]) {
        printf("error %s: kc_chain_init_model: %s, %d joints\n", name, kc_status_str(st), chain.n_joints);
        return 1;
    }
    int n = chain.n_joints;

    /* The float build gets the double set rounded once, here, outside the
     * timed loop. */
    bench_make_configs(model, q_double);
    for (int k = 0; k < BENCH_CONFIGS; k++)
        for (int j = 0; j < BENCH_MAX_JOINTS; j++)
            q_set[k][j] = (kc_real)q_double[k][j];

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
            for (int c = 0; c < n; c++)
                printf(" %.17g", (double)jac.m[r][c]);
        printf("\n");
    }

    /* The checksum reads one output of every call, so no call can be
     * dropped as dead code; it costs one add per call, as in the driver. */
    double sum = 0.0;
    kc_pose pose;
    BENCH_TIME(timings_ns, kc_fk_eval(&chain, q_set[k], &pose); sum += (double)pose.t.v[0]);
    print_stats(name, "fk", sum);

    sum = 0.0;
    kc_jacobian jac;
    BENCH_TIME(timings_ns, kc_fk_jacobian(&chain, q_set[k], &jac, NULL); sum += (double)jac.m[0][n - 1]);
    print_stats(name, "jac", sum);
    return 0;
}

int main(void)
{
    int bad = 0;
    for (int model = 0; model < BENCH_N_MODELS; model++)
        bad |= run_model(model);
    return bad;
}
