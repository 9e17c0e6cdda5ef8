/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * bench_common.h - what the kinctl helpers (C99, one per precision) and the
 * driver (C++, KDL and Pinocchio) must agree on, so that every library is
 * timed on the same configurations in the same way.
 *
 * - The configuration set: BENCH_CONFIGS joint vectors per model, uniform
 *   within the joint limits of tests/vectors/fk.json, drawn from splitmix64
 *   with a fixed seed. The generator is integer arithmetic plus one exact
 *   scaling, so C and C++ produce bit-identical sets without passing files.
 * - The timing loop (BENCH_TIME): batches of BENCH_BATCH calls timed with
 *   CLOCK_MONOTONIC; per-call time = batch time / batch size, after
 *   BENCH_WARMUP untimed batches.
 * - The schedule: the speed of a shared (virtual) machine drifts by tens of
 *   percent over seconds, so libraries timed one after the other would be
 *   compared under different conditions. Each series is timed in
 *   BENCH_ROUNDS blocks of BENCH_BATCHES_PER_ROUND batches, interleaved with
 *   the other libraries' blocks, and its statistics pool all its blocks.
 * - The statistics: median, p99 and max of the per-call times.
 * - The line protocol the helpers print and the driver parses.
 */
#ifndef KINCTL_BENCH_COMMON_H
#define KINCTL_BENCH_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define BENCH_CONFIGS 1024 /* a multiple of BENCH_BATCH */
#define BENCH_BATCH 64
#define BENCH_ROUNDS 10
#define BENCH_BATCHES_PER_ROUND 400
#define BENCH_BATCHES (BENCH_ROUNDS * BENCH_BATCHES_PER_ROUND)
#define BENCH_WARMUP 100 /* per block */
/* Configurations (the first of the set) compared across libraries. */
#define BENCH_CHECKS 16
#define BENCH_SEED 20240601u
#define BENCH_MAX_JOINTS 7

enum { BENCH_PUMA560 = 0, BENCH_PANDA = 1, BENCH_N_MODELS = 2 };

static const char *const bench_model_names[BENCH_N_MODELS] = {"puma560", "panda"};
static const int bench_model_joints[BENCH_N_MODELS] = {6, 7};

/* Joint limits (rad) from tests/vectors/fk.json, qlim_rad. */
static const double bench_qlim[BENCH_N_MODELS][BENCH_MAX_JOINTS][2] = {
    {{-2.792526803190927, 2.792526803190927},
     {-0.7853981633974483, 3.9269908169872414},
     {-3.9269908169872414, 0.7853981633974483},
     {-1.9198621771937625, 2.9670597283903604},
     {-1.7453292519943295, 1.7453292519943295},
     {-4.642575810304916, 4.642575810304916},
     {0.0, 0.0}},
    {{-2.8973, 2.8973},
     {-1.7628, 1.7628},
     {-2.8973, 2.8973},
     {-3.0718, -0.0698},
     {-2.8973, 2.8973},
     {-0.0175, 3.7525},
     {-2.8973, 2.8973}},
};

static inline uint64_t bench_splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* 53 random bits scaled to [0, 1): exact, so identical in C and C++. */
static inline double bench_uniform01(uint64_t *state)
{
    return (double)(bench_splitmix64(state) >> 11) * (1.0 / 9007199254740992.0);
}

/* One configuration uniform within the limits into q[BENCH_MAX_JOINTS];
 * unused joints 0. Draws BENCH_MAX_JOINTS numbers whatever the model. */
static inline void bench_uniform_q(int model, uint64_t *state, double *q)
{
    for (int j = 0; j < BENCH_MAX_JOINTS; j++) {
        double u = bench_uniform01(state);
        double lo = bench_qlim[model][j][0], hi = bench_qlim[model][j][1];
        q[j] = j < bench_model_joints[model] ? lo + (hi - lo) * u : 0.0;
    }
}

/* Fills q[BENCH_CONFIGS][BENCH_MAX_JOINTS] for one model. */
static inline void bench_make_configs(int model, double q[][BENCH_MAX_JOINTS])
{
    uint64_t state = BENCH_SEED + (uint64_t)model;
    for (int k = 0; k < BENCH_CONFIGS; k++)
        bench_uniform_q(model, &state, q[k]);
}

/* ---- inverse kinematics (ik_bench) ----
 *
 * The IK set of a model: BENCH_IK_TARGETS joint vectors q_true uniform
 * within the limits, each with a random start q_start drawn right after it
 * (uniform within the limits, from the same stream), and one fixed start.
 * The targets are kinctl's double FK of q_true; the driver writes targets
 * and starts to a file (format below) that the helpers and the Python
 * script read, so every library solves the very same numbers.
 *
 * Solve times are per solve (each solve is a different problem, 1 to 1000
 * us), one CLOCK_MONOTONIC read before and after; the drift of the machine
 * is spread over the libraries by solving the targets in BENCH_IK_ROUNDS
 * blocks, each library's block of a round right after the others'. Each
 * block starts with BENCH_IK_WARMUP untimed solves of its first targets.
 */
#define BENCH_IK_TARGETS 1000
#define BENCH_IK_ROUNDS 5 /* divides BENCH_IK_TARGETS */
#define BENCH_IK_WARMUP 10
#define BENCH_IK_SEED 20240603u
/* vectors/ik.json's acceptance: max |FK(q) - T| over the 12 entries of
 * [R | t] (m and direction cosines). */
#define BENCH_IK_TOL 1e-6

/* kc_ik_step: BENCH_STEP_RUNS runs (each from a random start towards a
 * target of the set, starting at rest) of at most BENCH_STEP_CYCLES cycles
 * at BENCH_STEP_DT, each call timed; a run ends early when the step says
 * KC_DONE. Blocks of BENCH_STEP_RUNS / BENCH_IK_ROUNDS runs. */
#define BENCH_STEP_RUNS 100
#define BENCH_STEP_CYCLES 1000
#define BENCH_STEP_DT 1e-3

/* The fixed start: rtb's Puma560.qn for puma560 (the start of vectors/
 * ik.json; the puma's mid-range has the elbow nearly straight, q3 = -pi/2),
 * the middle of every joint's range for panda. */
static inline void bench_ik_fixed_start(int model, double *q)
{
    static const double puma_qn[6] = {0.0, 0.7853981633974483, -3.141592653589793, 0.0, 0.7853981633974483, 0.0};
    for (int j = 0; j < BENCH_MAX_JOINTS; j++) {
        if (j >= bench_model_joints[model])
            q[j] = 0.0;
        else if (model == BENCH_PUMA560)
            q[j] = puma_qn[j];
        else
            q[j] = 0.5 * (bench_qlim[model][j][0] + bench_qlim[model][j][1]);
    }
}

static inline void bench_make_ik_set(int model, double q_true[][BENCH_MAX_JOINTS], double q_start[][BENCH_MAX_JOINTS])
{
    uint64_t state = BENCH_IK_SEED + (uint64_t)model;
    for (int k = 0; k < BENCH_IK_TARGETS; k++) {
        bench_uniform_q(model, &state, q_true[k]);
        bench_uniform_q(model, &state, q_start[k]);
    }
}

/* ---- motion profiles and interpolators (interp_bench) ----
 *
 * The joint-move set: BENCH_CONFIGS moves of the puma560 (6 joints, kinctl's
 * model limits), start q0 and goal q1 both uniform within the position
 * limits, and with each move a fraction f in [0, 1) that picks the tick
 * bench_interp_tick(f, ticks) in [0, ticks]: the tick series evaluate
 * random ticks over the whole motion, every phase and the end included.
 * Plan series call the planner on move k for call k (inputs change every
 * call). Tick series evaluate sample k on plan k / BENCH_INTERP_TICKS_PER_PLAN
 * of the first BENCH_INTERP_TICK_PLANS moves, so a batch of BENCH_BATCH
 * ticks stays on one plan, as a controller's cycle does.
 */
#define BENCH_INTERP_SEED 20240607u
#define BENCH_INTERP_DT 1e-3
#define BENCH_INTERP_TICK_PLANS 16
#define BENCH_INTERP_TICKS_PER_PLAN (BENCH_CONFIGS / BENCH_INTERP_TICK_PLANS)
/* Plans are slower than ticks: their series time fewer batches a round. */
#define BENCH_INTERP_PLAN_BATCHES 100
/* Fractions of the duration at which the cross-check compares positions. */
#define BENCH_INTERP_CHECK_POINTS 7
static const double bench_interp_check_at[BENCH_INTERP_CHECK_POINTS] = {0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0};

static inline void bench_make_moves(double q0[][BENCH_MAX_JOINTS], double q1[][BENCH_MAX_JOINTS], double *frac)
{
    uint64_t state = BENCH_INTERP_SEED;
    for (int k = 0; k < BENCH_CONFIGS; k++) {
        bench_uniform_q(BENCH_PUMA560, &state, q0[k]);
        bench_uniform_q(BENCH_PUMA560, &state, q1[k]);
        frac[k] = bench_uniform01(&state);
    }
}

static inline int64_t bench_interp_tick(double frac, int64_t ticks)
{
    return (int64_t)(frac * (double)(ticks + 1));
}

static inline double bench_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

/*
 * Runs BODY (which may use the config index k) over BENCH_WARMUP warm-up
 * batches and then n_batches timed ones, storing the per-call time of each
 * timed batch in ns_out[0..n_batches-1]. Batches walk through the
 * configuration set in order, so every library sees the same inputs. A
 * macro rather than a function taking a callback: an indirect call per
 * iteration would cost about as much as the cheapest operation we time.
 */
#define BENCH_TIME(ns_out, n_batches, ...)                                    \
    do {                                                                      \
        for (int b_ = -BENCH_WARMUP; b_ < (n_batches); b_++) {                \
            int first_ = ((b_ + BENCH_WARMUP) * BENCH_BATCH) % BENCH_CONFIGS; \
            double t0_ = bench_now_ns();                                      \
            for (int k = first_; k < first_ + BENCH_BATCH; k++) {             \
                __VA_ARGS__;                                                  \
            }                                                                 \
            double t1_ = bench_now_ns();                                      \
            if (b_ >= 0)                                                      \
                (ns_out)[b_] = (t1_ - t0_) / (double)BENCH_BATCH;             \
        }                                                                     \
    } while (0)

typedef struct bench_stats {
    double median_ns, p99_ns, max_ns;
} bench_stats;

static inline int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sorts ns[0..n-1] in place. p99 is the nearest-rank percentile. */
static inline bench_stats bench_summarize(double *ns, int n)
{
    bench_stats s;
    qsort(ns, (size_t)n, sizeof ns[0], bench_cmp_double);
    s.median_ns = ns[n / 2];
    s.p99_ns = ns[(99 * n + 99) / 100 - 1];
    s.max_ns = ns[n - 1];
    return s;
}

/* The `ns` and `checksum` lines of one timed block (protocol below). */
static inline void bench_print_block(const double *ns, int n, double checksum)
{
    printf("ns");
    for (int b = 0; b < n; b++)
        printf(" %.3f", ns[b]);
    printf("\nchecksum %.17g\n", checksum);
}

/*
 * IK set file (text, numbers in %.17g, one file per model):
 *   kinctl-ik-set <model> <joints n> <targets N>
 *   fixed <q n>
 *   N lines: <T: R row-major 9, t 3> <q_true n> <q_start n>
 */
#define BENCH_IK_SET_MAGIC "kinctl-ik-set"

/*
 * Helper protocol. `helper check` prints, numbers in %.17g:
 *   check <model> <config> pose <R row-major 9> <t 3>
 *   check <model> <config> jac <6 x n row-major, rows vx vy vz wx wy wz>
 * `helper time <model> <fk|jac> <batches>` prints one block:
 *   ns <per-call ns of each batch...>
 *   checksum <sum>
 * `helper fk <model> <file of q, n per line>` prints for each line
 *   pose <R row-major 9> <t 3> <1 if kc_chain_check_q accepts q, else 0>
 * `helper ik <model> <set file> <fixed|random> <first> <count>` solves
 * targets first..first+count-1 with kc_ik_solve (default cfg) and prints
 *   ik <k> <ns> <1 if KC_OK> <steps> <restarts> <q n>
 * preceded by `status <k> <kc_status_str>` when kc_ik_solve did not
 * return KC_OK.
 * (ik_bench_rtb.py prints the same lines for rtb's ik_LM).
 * `helper step <model> <set file> <first run> <runs>` prints one block:
 *   ns <per-call ns of every kc_ik_step call...>
 *   done <runs that reached KC_DONE>
 * interp_helper.c (kinctl_interp_<precision>):
 * `helper check` prints, numbers in %.17g,
 *   limits <qd_max 6> <qdd_max 6> <qddd_max 6>     (kinctl's puma560)
 *   motion <name> <plans that succeeded> <set size> <ticks min> <median> <max>
 *   joint <move> <duration s> <ticks> <lead joint>
 *   pos <move> <tick> <q 6>       (the ticks of bench_interp_check_at)
 * `helper time <motion> <plan|tick> <batches>` prints one block as `time`
 * above (ns, checksum).
 * Anything else (an error text) makes the driver stop.
 */

#endif /* KINCTL_BENCH_COMMON_H */
