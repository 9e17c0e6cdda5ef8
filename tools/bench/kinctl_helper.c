/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl_helper.c - kinctl's FK, Jacobian and IK in one precision, for
 * fk_bench and ik_bench.
 *
 * Compiled twice (kinctl_bench_double, kinctl_bench_float): the two core
 * builds share their symbol names, so they cannot live in one executable.
 * The drivers run it once to check results and then once per timed block,
 * interleaved with the other libraries' blocks. Output follows the protocol
 * in bench_common.h. ik_bench also uses the double build's `fk` to judge
 * every library's IK solutions with kinctl's own FK and limit check.
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
    bench_print_block(timings_ns, n_batches, sum);
    return 0;
}

/* ---- inverse kinematics ---- */

/* The IK set as read from the driver's file; targets rounded to kc_real
 * once, here (the float build then solves the double targets' rounding). */
static struct {
    int n;
    double fixed[BENCH_MAX_JOINTS];
    double q_start[BENCH_IK_TARGETS][BENCH_MAX_JOINTS];
    kc_pose target[BENCH_IK_TARGETS];
} ik_set;
static double step_ns[BENCH_STEP_RUNS * BENCH_STEP_CYCLES];

static int read_numbers(FILE *f, double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (fscanf(f, "%lf", &x[i]) != 1)
            return 1;
    return 0;
}

static int read_ik_set(int model, const char *path)
{
    FILE *f = fopen(path, "r");
    char name[32];
    int n = 0, count = 0, bad = f == NULL;
    if (!bad)
        bad = fscanf(f, BENCH_IK_SET_MAGIC " %31s %d %d fixed", name, &n, &count) != 3 ||
              strcmp(name, bench_model_names[model]) != 0 || n != bench_model_joints[model] ||
              count != BENCH_IK_TARGETS || read_numbers(f, ik_set.fixed, n) != 0;
    for (int k = 0; !bad && k < BENCH_IK_TARGETS; k++) {
        double x[12 + 2 * BENCH_MAX_JOINTS];
        bad = read_numbers(f, x, 12 + 2 * n);
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                ik_set.target[k].R.m[r][c] = (kc_real)x[3 * r + c];
            ik_set.target[k].t.v[r] = (kc_real)x[9 + r];
        }
        for (int j = 0; j < n; j++)
            ik_set.q_start[k][j] = x[12 + n + j];
    }
    if (f != NULL)
        fclose(f);
    if (bad) {
        printf("error: %s is not a %s IK set of %d targets\n", path, bench_model_names[model], BENCH_IK_TARGETS);
        return 1;
    }
    ik_set.n = n;
    return 0;
}

static void to_real(const double *x, int n, kc_real *dest)
{
    for (int j = 0; j < n; j++)
        dest[j] = (kc_real)x[j];
}

/* Pose and limit check of every q in the file: the judge of all libraries. */
static int fk_file(int model, const char *path)
{
    kc_chain chain;
    FILE *f = fopen(path, "r");
    if (f == NULL || setup(model, &chain) != 0) {
        printf("error: cannot read %s\n", path);
        if (f != NULL)
            fclose(f);
        return 1;
    }
    int n = chain.n_joints;
    double x[BENCH_MAX_JOINTS];
    while (read_numbers(f, x, n) == 0) {
        kc_real q[BENCH_MAX_JOINTS];
        kc_pose pose;
        to_real(x, n, q);
        if (kc_fk_eval(&chain, q, &pose) != KC_OK) {
            /* A non-finite q: no pose, which the driver counts as a miss. */
            printf("pose nan\n");
            continue;
        }
        printf("pose");
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                printf(" %.17g", (double)pose.R.m[r][c]);
        for (int r = 0; r < 3; r++)
            printf(" %.17g", (double)pose.t.v[r]);
        printf(" %d\n", kc_chain_check_q(&chain, q, NULL) == KC_OK);
    }
    fclose(f);
    return 0;
}

static int ik_block(int model, const char *path, int fixed, int first, int count)
{
    kc_chain chain;
    if (setup(model, &chain) != 0 || read_ik_set(model, path) != 0)
        return 1;
    const kc_ik_cfg cfg = kc_ik_cfg_default();
    int n = ik_set.n;
    kc_real fixed_q[BENCH_MAX_JOINTS];
    to_real(ik_set.fixed, n, fixed_q);
    kc_real q[BENCH_MAX_JOINTS];
    kc_ik_result res;
    /* Warm-up: the block's first targets, untimed, so the first timed solve
     * does not pay for page faults and cold caches. */
    for (int k = first; k < first + BENCH_IK_WARMUP && k < first + count; k++) {
        kc_real q0[BENCH_MAX_JOINTS];
        to_real(ik_set.q_start[k], n, q0);
        kc_ik_solve(&chain, &cfg, &ik_set.target[k], fixed ? fixed_q : q0, q, &res);
    }
    for (int k = first; k < first + count; k++) {
        kc_real q0[BENCH_MAX_JOINTS];
        to_real(ik_set.q_start[k], n, q0);
        const kc_real *start = fixed ? fixed_q : q0;
        double t0 = bench_now_ns();
        kc_status st = kc_ik_solve(&chain, &cfg, &ik_set.target[k], start, q, &res);
        double t1 = bench_now_ns();
        if (st == KC_E_ARG) {
            printf("error %s target %d: kc_ik_solve: %s\n", bench_model_names[model], k, kc_status_str(st));
            return 1;
        }
        /* Not converged: the status says where it stopped (ik.h); the
         * driver counts them. */
        if (st != KC_OK)
            printf("status %d %s\n", k, kc_status_str(st));
        printf("ik %d %.1f %d %d %d", k, t1 - t0, st == KC_OK, res.steps, res.restarts);
        for (int j = 0; j < n; j++)
            printf(" %.17g", (double)q[j]);
        printf("\n");
    }
    return 0;
}

/* kc_ik_step as the daemon calls it: every cycle from the state the last
 * one left, so after the first cycle the arm is moving. */
static int step_block(int model, const char *path, int first, int runs)
{
    kc_chain chain;
    if (setup(model, &chain) != 0 || read_ik_set(model, path) != 0)
        return 1;
    const kc_ik_cfg cfg = kc_ik_cfg_default();
    const kc_real dt = (kc_real)BENCH_STEP_DT;
    int n = ik_set.n, n_ns = 0, done = 0;
    for (int r = first; r < first + runs; r++) {
        kc_real q[BENCH_MAX_JOINTS], qd[BENCH_MAX_JOINTS] = {0};
        kc_ik_result res;
        to_real(ik_set.q_start[r], n, q);
        for (int c = 0; c < BENCH_STEP_CYCLES; c++) {
            double t0 = bench_now_ns();
            kc_status st = kc_ik_step(&chain, &cfg, &ik_set.target[r], NULL, dt, q, qd, q, qd, &res);
            double t1 = bench_now_ns();
            step_ns[n_ns++] = t1 - t0;
            if (st == KC_DONE) {
                done++;
                break;
            }
            if (st != KC_OK && st != KC_E_LIMIT && st != KC_E_SINGULAR) {
                printf("error %s run %d: kc_ik_step: %s\n", bench_model_names[model], r, kc_status_str(st));
                return 1;
            }
        }
    }
    printf("ns");
    for (int i = 0; i < n_ns; i++)
        printf(" %.1f", step_ns[i]);
    printf("\ndone %d\n", done);
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
    int model = argc >= 4 ? model_index(argv[2]) : -1;
    if (argc == 4 && model >= 0 && strcmp(argv[1], "fk") == 0)
        return fk_file(model, argv[3]);
    if (argc == 7 && model >= 0 && strcmp(argv[1], "ik") == 0) {
        int first = atoi(argv[5]), count = atoi(argv[6]);
        int fixed = strcmp(argv[4], "fixed") == 0;
        if ((fixed || strcmp(argv[4], "random") == 0) && first >= 0 && count > 0 && first + count <= BENCH_IK_TARGETS)
            return ik_block(model, argv[3], fixed, first, count);
    }
    if (argc == 6 && model >= 0 && strcmp(argv[1], "step") == 0) {
        int first = atoi(argv[4]), runs = atoi(argv[5]);
        if (first >= 0 && runs > 0 && first + runs <= BENCH_STEP_RUNS)
            return step_block(model, argv[3], first, runs);
    }
    printf("usage: %s check | time <puma560|panda> <fk|jac> <batches 1..%d>\n"
           "  | fk <model> <q file> | ik <model> <set file> <fixed|random> <first> <count>\n"
           "  | step <model> <set file> <first run> <runs>\n",
           argv[0], BENCH_BATCHES);
    return 2;
}
