/* SPDX-License-Identifier: BSD-3-Clause */
/* zone_bench - cost of the per-cycle zone check (kc_zone_check with the
 * frames computed inside, as kc_ctrl_step calls it) for the PUMA 560 and the
 * Panda with 10 zones, against the 1 ms budget of a 1 kHz cycle.
 *
 * 1024 joint vectors uniform within the limits (fixed seed), cycled through;
 * every call timed on its own with CLOCK_MONOTONIC (the clock costs tens of
 * ns, the check microseconds) after 6400 warm-up calls, so the percentiles
 * are those of single cycles: a configuration with many near pairs costs
 * more than one in free space. Prints median, p99 and max over 256000 calls
 * (4000 x 64), for the check, for FK's frames alone (what the check
 * includes), and the p99's share of a 1 ms cycle. This machine is shared
 * and virtual, so single calls catch stalls of the host: the "best of 30"
 * line times each configuration 30 times and keeps its fastest, which is
 * the configuration's own cost, and gives median, p99 and max of those. The zones are placed around and into the workspace so
 * that some configurations are near (exact GJK runs) and some violate.
 *
 * Usage: zone_bench [batches]   (default 4000) */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "bench_common.h"
#include "kinctl/kinctl.h"

#define CONFIGS 1024
#define BATCH 64 /* calls = batches x BATCH */
#define WARMUP 100

static uint64_t rng_state = BENCH_SEED;
static double uniform(double lo, double hi) { return lo + (hi - lo) * bench_uniform01(&rng_state); }

static void add(kc_zone_set *set, int kind, double x, double y, double z, double d0, double d1, double d2)
{
    kc_shape s = {0};
    s.kind = kind;
    kc_pose_identity(&s.pose);
    s.pose.t = kc_vec3_make((kc_real)x, (kc_real)y, (kc_real)z);
    s.dim[0] = (kc_real)d0;
    s.dim[1] = (kc_real)d1;
    s.dim[2] = (kc_real)d2;
    if (kc_zone_set_add(set, &s) != KC_OK) {
        fprintf(stderr, "zone_bench: bad zone\n");
        exit(1);
    }
}

static void ten_zones(kc_zone_set *set)
{
    kc_zone_set_init(set);
    kc_shape floor = {0}, wall = {0};
    floor.kind = wall.kind = KC_SHAPE_HALFSPACE;
    kc_pose_identity(&floor.pose);
    kc_mat3_rot(KC_AXIS_Y, -KC_PI_2, &wall.pose.R); /* normal -x */
    wall.pose.t = kc_vec3_make(KC_R(0.9), KC_R(0.0), KC_R(0.0));
    kc_zone_set_add(set, &floor);
    kc_zone_set_add(set, &wall);
    add(set, KC_SHAPE_BOX, 0.5, 0.4, 0.2, 0.15, 0.1, 0.2);
    add(set, KC_SHAPE_BOX, -0.5, 0.3, 0.5, 0.1, 0.2, 0.1);
    add(set, KC_SHAPE_BOX, 0.0, -0.6, 0.8, 0.2, 0.05, 0.2);
    add(set, KC_SHAPE_SPHERE, 0.4, -0.3, 0.9, 0.1, 0, 0);
    add(set, KC_SHAPE_SPHERE, -0.3, -0.3, 0.3, 0.08, 0, 0);
    add(set, KC_SHAPE_SPHERE, 0.2, 0.6, 1.1, 0.12, 0, 0);
    add(set, KC_SHAPE_CYLINDER, -0.6, -0.2, 0.6, 0.05, 0.6, 0);
    add(set, KC_SHAPE_CYLINDER, 0.6, -0.5, 0.4, 0.04, 0.4, 0);
}

int main(int argc, char **argv)
{
    int batches = argc > 1 ? atoi(argv[1]) : 4000;
    if (batches < 10 || batches > 1000000) {
        fprintf(stderr, "usage: zone_bench [batches]   (10 .. 1000000, default 4000)\n"
                        "Example: zone_bench 4000\n");
        return 2;
    }
    static kc_real q[CONFIGS][KC_MAX_JOINTS];
    int calls = batches * BATCH;
    double *ns = malloc(sizeof(double) * (size_t)calls);
    if (ns == NULL)
        return 1;
    kc_zone_set set;
    ten_zones(&set);
    const kc_model models[2] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};
    double checksum = 0;
    printf("zone_bench (%s): kc_zone_check incl. FK frames, %d zones, margin %.3f m, near %.3f m; "
           "each of %d calls timed\n",
           KC_REAL_NAME, set.n_zones, (double)set.margin, (double)set.near, calls);
    printf("%-8s %-7s %-11s %10s %10s %10s %12s\n", "model", "volumes", "what", "median_ns", "p99_ns", "max_ns",
           "p99/1ms_cycle");
    for (int m = 0; m < 2; m++) {
        kc_chain chain;
        kc_chain_init_model(&chain, models[m], NULL);
        for (int k = 0; k < CONFIGS; k++)
            for (int j = 0; j < chain.n_joints; j++)
                q[k][j] = (kc_real)uniform((double)chain.joints[j].limits.q_min, (double)chain.joints[j].limits.q_max);
        int violating = 0;
        for (int k = 0; k < CONFIGS; k++)
            violating += kc_zone_check(&chain, &set, q[k], NULL, NULL) == KC_E_LIMIT;
        for (int what = 0; what < 2; what++) {
            double sink = 0;
            for (int c = -WARMUP * BATCH; c < calls; c++) {
                int k = (c + WARMUP * BATCH) % CONFIGS;
                double t0 = bench_now_ns();
                if (what == 0) {
                    kc_zone_hit hit;
                    kc_zone_check(&chain, &set, q[k], NULL, &hit);
                    sink += (double)hit.distance;
                } else {
                    kc_pose frames[KC_MAX_FRAMES];
                    kc_fk_frames(&chain, q[k], frames, NULL);
                    sink += (double)frames[0].t.v[0];
                }
                double t1 = bench_now_ns();
                if (c >= 0)
                    ns[c] = t1 - t0;
            }
            checksum += sink; /* keeps the calls from being optimised away */
            bench_stats s = bench_summarize(ns, calls);
            if (what == 0) {
                static double best[CONFIGS];
                for (int k = 0; k < CONFIGS; k++) {
                    best[k] = 1e30;
                    for (int r = 0; r < 30; r++) {
                        double t0 = bench_now_ns();
                        kc_zone_check(&chain, &set, q[k], NULL, NULL);
                        double t1 = bench_now_ns();
                        if (t1 - t0 < best[k])
                            best[k] = t1 - t0;
                    }
                }
                bench_stats b = bench_summarize(best, CONFIGS);
                printf("%-8s %-7d %-11s %10.0f %10.0f %10.0f %11.2f%%\n", kc_model_name(models[m]), chain.n_volumes,
                       "best_of_30", b.median_ns, b.p99_ns, b.max_ns, b.p99_ns / 1e6 * 100.0);
            }
            printf("%-8s %-7d %-11s %10.0f %10.0f %10.0f %11.2f%%\n", kc_model_name(models[m]), chain.n_volumes,
                   what == 0 ? "zone_check" : "fk_frames", s.median_ns, s.p99_ns, s.max_ns, s.p99_ns / 1e6 * 100.0);
        }
        printf("%-8s configurations violating the margin: %d of %d\n", kc_model_name(models[m]), violating, CONFIGS);
    }
    printf("checksum %.17g\n", checksum);
    free(ns);
    return 0;
}
