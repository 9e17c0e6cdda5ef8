/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * bench.c - what the core costs per call on the board, and the same
 * workload on the host for callgrind (tools/bench/run_mcu_bench.sh).
 *
 * Measured: kc_fk_eval, kc_fk_jacobian and kc_ik_step on a PUMA 560 at 100
 * configurations, and every tick of kc_ctrl_step for each goal kind of
 * scenario.h (from rest until idle), plus one dry run of a line (kc_check_from).
 * Each measured call goes through a bench_<what> function of its own, so
 * callgrind's inclusive counts on the host and the stack analysis of
 * tools/bench/mcu_stack.py name the same thing.
 *
 * On the board instructions are counted with SysTick under -icount
 * (board/systick.h: a single call to +-40, a mean over n calls to 40/n).
 * The stack high-water of each bench_
 * function is measured by painting the free stack below the caller with a
 * pattern and finding the deepest word overwritten.
 *
 * Output lines, parsed by the script:
 *   icount <what> calls <n> mean <instructions> max <instructions>
 *   stack <bench function> <bytes>
 *   sizeof <type> <bytes>
 * On the host only the calls are made (and `calls <what> <n>` printed);
 * `bench ctrl K` runs only the ticks of goal kind K (scenario.h order), so
 * that callgrind's count of bench_ctrl_step is that kind's alone.
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "kinctl/kinctl.h"
#include "scenario.h"

#define N_CONFIGS 100
#define MAX_TICKS 20000

#if defined(__arm__)
#define ON_BOARD 1
#else
#define ON_BOARD 0
#endif

#define NOINLINE __attribute__((noinline))

static kc_chain chain;
static kc_ctrl ctrl;
static kc_check check; /* the dry run's own storage */
static kc_ctrl_cfg cfg;
static kc_ctrl_output out;
static kc_real qs[N_CONFIGS][6];
static kc_pose pose_sink;
static kc_jacobian jac_sink;

/* ---- counting and stack painting (board only) ---- */

#if ON_BOARD
#include "board/systick.h"
#define PAINT_BYTES 32768u
#define PAINT_WORD 0xC5C5C5C5u

static uint32_t *stack_pointer(void)
{
    uint32_t *sp;
    __asm volatile("mov %0, sp" : "=r"(sp));
    return sp;
}
#endif

typedef struct tally {
    const char *what;
    uint32_t calls;
    uint64_t total;
    uint32_t max;
    uint32_t stack;
} tally;

/* Calls fn(arg) once: counted (and on the first call of a tally, with its
 * stack measured). Returns fn's status. */
static int measure(tally *t, int (*fn)(int), int arg)
{
#if ON_BOARD
    int paint = t->calls == 0;
    uint32_t *sp = stack_pointer();
    /* The words below sp are free; leave 64 bytes for this frame's spills. */
    uint32_t *lo = sp - PAINT_BYTES / 4u, *hi = sp - 16;
    if (paint)
        for (volatile uint32_t *w = lo; w < hi; w++)
            *w = PAINT_WORD;
    uint32_t c0 = kc_systick_now();
    int st = fn(arg);
    uint32_t c1 = kc_systick_now();
    uint32_t n = kc_systick_insns(c0, c1);
    if (paint) {
        volatile uint32_t *w = lo;
        while (w < hi && *w == PAINT_WORD)
            w++;
        t->stack = (uint32_t)((uintptr_t)sp - (uintptr_t)w);
    }
    t->total += n;
    if (n > t->max)
        t->max = n;
#else
    int st = fn(arg);
#endif
    t->calls++;
    return st;
}

static void report(const tally *t, const char *stack_fn)
{
#if ON_BOARD
    printf("icount %s calls %lu mean %lu max %lu\n", t->what, (unsigned long)t->calls,
           (unsigned long)((t->total + t->calls / 2u) / (t->calls ? t->calls : 1u)), (unsigned long)t->max);
    printf("stack %s %lu\n", stack_fn, (unsigned long)t->stack);
#else
    (void)stack_fn;
    printf("calls %s %lu\n", t->what, (unsigned long)t->calls);
#endif
}

/* ---- the measured calls ---- */

NOINLINE int bench_fk(int i);
NOINLINE int bench_jacobian(int i);
NOINLINE int bench_ik_step(int i);
NOINLINE int bench_ctrl_step(int goal);
NOINLINE int bench_ctrl_check(int unused);

static kc_ik_cfg ik_cfg;
static kc_pose ik_target;
static kc_real ik_q[6], ik_qd[6];
static kc_ik_result ik_res;
static const kc_goal *tick_goal;
static kc_goal check_goal;

int bench_fk(int i) { return kc_fk_eval(&chain, qs[i], &pose_sink); }
int bench_jacobian(int i) { return kc_fk_jacobian(&chain, qs[i], &jac_sink, &pose_sink); }

int bench_ik_step(int i)
{
    return kc_ik_step(&chain, &ik_cfg, &ik_target, NULL, cfg.dt, qs[i], ik_qd, ik_q, ik_qd, &ik_res);
}

int bench_ctrl_step(int unused)
{
    (void)unused;
    kc_ctrl_input in;
    memset(&in, 0, sizeof in);
    in.goal = tick_goal;
    return kc_ctrl_step(&ctrl, &in, &out);
}

int bench_ctrl_check(int unused)
{
    (void)unused;
    kc_verdict verdict;
    return kc_check_from(&check, scn_q0, &check_goal, &verdict);
}

/* Random configurations inside the limits (splitmix64, fixed seed). */
static void make_configs(void)
{
    uint64_t s = 20240601u;
    for (int i = 0; i < N_CONFIGS; i++)
        for (int j = 0; j < 6; j++) {
            uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
            z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
            z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
            z ^= z >> 31;
            kc_real u = (kc_real)(z >> 40) / (kc_real)16777216.0f;
            kc_real lo = chain.joints[j].limits.q_min, hi = chain.joints[j].limits.q_max;
            qs[i][j] = lo + (hi - lo) * (KC_R(0.05) + KC_R(0.9) * u);
        }
}

int main(int argc, char **argv)
{
    int only = -1; /* a goal kind alone, or everything */
    if (argc == 3 && strcmp(argv[1], "ctrl") == 0)
        only = argv[2][0] - '0';
    if (kc_chain_init_model(&chain, KC_MODEL_PUMA560, NULL) != KC_OK) {
        printf("FAIL: puma560 model\n");
        return 1;
    }
    cfg = kc_ctrl_cfg_default();
    ik_cfg = cfg.ik;
    make_configs();
#if ON_BOARD
    kc_systick_start();
#endif
    int failures = 0;

    tally fk = {"fk", 0, 0, 0, 0}, jac = {"jacobian", 0, 0, 0, 0}, ik = {"ik_step", 0, 0, 0, 0};
    for (int i = 0; i < N_CONFIGS && only < 0; i++) {
        failures += measure(&fk, bench_fk, i) != KC_OK;
        failures += measure(&jac, bench_jacobian, i) != KC_OK;
    }
    /* An IK step from each configuration towards the pose of the next. */
    for (int i = 0; i < N_CONFIGS && only < 0; i++) {
        kc_fk_eval(&chain, qs[(i + 1) % N_CONFIGS], &ik_target);
        memset(ik_qd, 0, sizeof ik_qd);
        failures += measure(&ik, bench_ik_step, i) < 0 && ik_res.status != KC_E_LIMIT && ik_res.status != KC_E_SINGULAR;
    }
    if (only < 0) {
        report(&fk, "bench_fk");
        report(&jac, "bench_jacobian");
        report(&ik, "bench_ik_step");
    }

    for (int s = 0; s < SCN_KINDS; s++) {
        if (only >= 0 && s != only)
            continue;
        char what[32];
        snprintf(what, sizeof what, "ctrl_tick_%s", scn_kind_names[s]);
        tally t = {what, 0, 0, 0, 0};
        kc_ctrl_init(&ctrl, &chain, &cfg, scn_q0);
        kc_pose here;
        kc_fk_eval(&chain, scn_q0, &here);
        kc_goal g;
        int idle = 0;
        for (int k = 0; k < MAX_TICKS && !idle; k++) {
            tick_goal = NULL;
            if (k == 0 || (scn_kinds[s] == KC_GOAL_SERVO && k < SCN_SERVO_TICKS)) {
                scn_goal(&g, scn_kinds[s], 200 + s, &here, k);
                tick_goal = &g;
            }
            if (measure(&t, bench_ctrl_step, 0) < 0)
                failures++;
            idle = k > 0 && out.state == KC_CTRL_IDLE && out.n_events == 0;
        }
        report(&t, "bench_ctrl_step");
    }

    if (only >= 0)
        return failures ? 1 : 0;
    kc_pose here;
    kc_fk_eval(&chain, scn_q0, &here);
    scn_goal(&check_goal, KC_GOAL_LINE, 300, &here, 0);
    if (kc_check_init(&check, &chain, &cfg, MAX_TICKS, scn_q0) != KC_OK) {
        printf("FAIL: kc_check_init\n");
        return 1;
    }
    tally chk = {"ctrl_check_line", 0, 0, 0, 0};
    failures += measure(&chk, bench_ctrl_check, 0) != KC_OK;
    report(&chk, "bench_ctrl_check");

    printf("sizeof kc_ctrl %lu\n", (unsigned long)sizeof(kc_ctrl));
    printf("sizeof kc_ctrl_plan %lu\n", (unsigned long)sizeof(kc_ctrl_plan));
    printf("sizeof kc_goal %lu\n", (unsigned long)sizeof(kc_goal));
    printf("sizeof kc_chain %lu\n", (unsigned long)sizeof(kc_chain));
    printf("sizeof kc_ctrl_output %lu\n", (unsigned long)sizeof(kc_ctrl_output));
    if (failures)
        printf("FAIL: %d calls failed\n", failures);
    return failures ? 1 : 0;
}
