/* SPDX-License-Identifier: BSD-3-Clause */
/* checker.h - kinctld's checker thread: the goals' dry runs, apart from the
 * receive path, and the goals' answers in arrival order.
 *
 * A dry run (kinctl/check.h) costs one controller step per tick of motion:
 * up to a second for the longest goal check_max_s allows. Run on the I/O
 * thread it would hold back every datagram behind it, STOP and ESTOP
 * included. So the checker thread owns the kc_check; the I/O thread hands
 * it each goal, decoded and converted (kc_goal), through the job ring, and
 * takes the verdicts back through the verdict ring, in the same order:
 *
 *   I/O thread --jobs-->     checker thread   (kd_checker_submit)
 *   I/O thread --ticks-->    checker thread   (kd_checker_tick: copies of
 *                                              the controller's ticks)
 *   I/O thread <--verdicts-- checker thread   (kd_checker_answer)
 *
 * The checker judges each job from where the one before it ends: it feeds
 * the kc_check every tick the I/O thread copies to it (between goals and
 * between the slices of a dry run), so a goal that waits is judged from
 * the end of the queue, and hands the kc_check each goal it accepts
 * (kc_check_handed) before the next. A goal that replaces is judged from
 * the controller's moving state: the checker asks the cycle for a snapshot
 * (kd_cycle_snapshot: the cycle copies its kc_ctrl into the checker's
 * keep after its next step, cycle.h), asks again while the copy is not
 * fresh (a goal accepted before it still on its way to the controller),
 * and after KD_SNAP_WAIT_MS (past the cycle a goal handed on before is
 * scheduled for) without one judges the goal from rest at the
 * latest setpoint (kinctl/check.h); with the controller moving, it asks
 * for as long as the dry runs' budget, and then refuses the goal (late:
 * taken unjudged from the moving state otherwise). Scheduled takeover: the goal is
 * judged for a tick some way after the snapshot (the kc_check's lead:
 * KD_LEAD_MS, then twice what a judgement that ended too late took), and
 * handed on scheduled for that tick and state (kc_goal.take_cycle,
 * take_state); the cycle holds it until that tick (cycle.h), and the
 * controller takes it there, along the transition the dry run stepped to
 * the bit, or refuses it (KC_REASON_LATE) when it came too late or the
 * state changed (a command between). Every pass of the slowing search
 * starts from a copy of the one snapshot (kc_check_snapshot from keep).
 * A dry run goes in slices of KD_CHECK_SLICE ticks with CLOCK_MONOTONIC
 * read between them: one that takes longer than the budget
 * (controller.check_budget_ms) is stopped and its job marked over budget.
 *
 * Answers in order. Every goal is answered once, in arrival order: the
 * verdicts come back in the order of the jobs, and a goal the I/O thread
 * refuses itself (a datagram that fails to decode or convert, a full job
 * ring) while goals before it wait for their verdicts takes its place in
 * the order (kd_checker_refuse) and is answered in its turn, also behind
 * the goals handed to the controller and not yet taken (the controller
 * answers those, ACCEPTED or REJECTED, when it takes them). Only when
 * that order is itself full (KD_ORDER_MAX goals waiting) is a refusal
 * answered at once, out of order, and counted (answered_early). Servo
 * messages stream past the dry runs (the cheap checks only, on the I/O
 * thread), in their turn (kd_checker_servo): they are answered by the
 * controller when it takes them.
 *
 * Every ring is kd_spsc (spsc.h): one producer, one consumer, no locks.
 * The checker sleeps on an eventfd (wake_fd) when it has nothing to do,
 * waking at least every KD_CHECK_IDLE_MS to take the ticks; it writes
 * done_fd after each verdict, for the I/O thread's poll.
 *
 * Threads: kd_checker_init, _start from the main thread before the I/O
 * thread runs; kd_checker_stop, _submit, _refuse, _tick, _answer and
 * _answered from the I/O thread only. After kd_checker_stop every ring is
 * the I/O thread's, and kd_checker_answer hands the jobs never judged back
 * as stopped. Not for the cycle.
 */
#ifndef KINCTL_DAEMON_CHECKER_H
#define KINCTL_DAEMON_CHECKER_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>

#include "config.h"
#include "cycle.h"
#include "kinctl/check.h"
#include "reject.h"
#include "spsc.h"

#define KD_CHECK_RING 64        /* goals on their way to or back from the checker */
#define KD_CHECK_TICK_RING 256  /* ticks copied to the checker */
#define KD_CHECK_SLICE 256      /* dry-run ticks between two looks at the clock */
#define KD_CHECK_IDLE_MS 20     /* longest sleep of an idle checker */
#define KD_ORDER_MAX 16384      /* goals waiting for their answer, in order */
#define KD_ORDER_TEXTS 256      /* of which refused with a text of their own */
#define KD_ORDER_SERVOS 8       /* of which servo messages (each a stream's latest) */
#define KD_SNAP_WAIT_MS 20      /* longest wait for a fresh snapshot (after the cycle of a goal held) */
#define KD_LEAD_MS 10           /* a replacing goal's tick, first: this long after the snapshot */
#define KD_LEAD_MAX_MS 2000     /* ... and at most this long */
#define KD_LEAD_TRIES 4         /* judgements of a replacing goal that end too late to hand on */
#define KD_HAND_MARGIN_MS 5     /* time kept for the verdict's way to the cycle */

/* How a job's dry run ended. */
typedef enum kd_job_end {
    KD_JOB_JUDGED = 0,      /* verdict is the dry run's */
    KD_JOB_OVER_BUDGET = 1, /* stopped after budget_ns: ticks, progress say how far */
    KD_JOB_STOPPED = 2      /* never judged: kinctld is shutting down */
} kd_job_end;

/* A goal to judge, and (back from the checker) its verdict. */
typedef struct kd_job {
    kc_goal goal;
    kc_verdict verdict;
    kd_job_end end;
    int64_t elapsed_ns; /* the dry run's wall-clock time */
    int64_t ticks;      /* dry-run ticks stepped */
    kc_real progress;   /* of the motion where it stopped, 0..1 */
    double slowed;      /* the share of its speed handed on (1: as asked) */
    int cut;            /* the budget ran out before a slower one was judged */
} kd_job;

/* A copy of one tick for the checker (kc_check_tick's arguments). */
typedef struct kd_check_tick {
    kc_ctrl_output out;
    int64_t goals_taken; /* goals from the checker the controller has taken */
} kd_check_tick;

/* One goal waiting for its answer: the checker's verdict, or a refusal. */
typedef struct kd_order {
    int64_t goal_id;
    int kind;  /* KD_ORDER_* (checker.c) */
    int text;  /* KD_ORDER_REFUSED: index into texts; KD_ORDER_SERVO: into servos */
} kd_order;

/* The next answer in order (kd_checker_answer). */
typedef struct kd_answer {
    int64_t goal_id;
    const kd_job *job;    /* the checker's job (valid until kd_checker_answered), or NULL: */
    const kc_goal *servo; /* ... a servo message for the cycle (valid as long), or NULL: */
    kd_reject rej;        /* ... a refusal */
} kd_answer;

typedef struct kd_checker {
    kc_check *check;   /* the checker thread's (caller-owned) */
    kd_cycle *cycle;   /* asked for snapshots of the controller, or NULL: none */
    int64_t budget_ns; /* longest dry run */
    kd_spsc jobs, verdicts, ticks;
    kd_job job_storage[KD_CHECK_RING], verdict_storage[KD_CHECK_RING];
    kd_check_tick tick_storage[KD_CHECK_TICK_RING];
    kd_job trial; /* the checker thread's: a goal slowed (or stopping first) for its joints' jerk */
    /* The checker thread's: the snapshot a replacing goal's dry runs start
     * from (each a copy of it), the goals it had taken, and when it was
     * seen (CLOCK_MONOTONIC ns). */
    kc_ctrl keep;
    int64_t keep_taken, keep_ns;
    int64_t held_ns; /* about when the last goal handed on, scheduled, is taken */
    int ctrl_moving; /* the controller moved (or stopped) at the latest tick taken */
    int wake_fd, done_fd; /* eventfds: work for the checker; verdicts for the I/O thread */

    /* The I/O thread's: the answers' order, and the tick waiting for room. */
    kd_order order[KD_ORDER_MAX];
    int64_t order_head, order_tail;
    kd_reject texts[KD_ORDER_TEXTS];
    int64_t texts_head, texts_tail;
    kc_goal servos[KD_ORDER_SERVOS];
    int64_t servos_head, servos_tail;
    kd_check_tick pending;
    int have_pending;
    int stopped;     /* the thread has been joined */
    int answer_from; /* where the answer last given came from (checker.c) */

    /* Counters (the checker's, read anywhere). */
    atomic_llong judged, over_budget;
    atomic_llong moving; /* replacing goals judged from a snapshot (the others from rest) */
    atomic_llong slowed; /* goals slowed, or stopping first, for their joints' jerk (checker.c) */
    atomic_llong late;   /* replacing goals judged again: the judgement ended too late for its tick */
    atomic_llong jerk_refused; /* goals refused for their joints' jerk (checker.c jerk_refused) */
    int64_t answered_early; /* the I/O thread's: refusals answered out of order */

    atomic_int run;
    pthread_t thread;
    int thread_live;
} kd_checker;

/* Sets the checker up over check (kc_check_init done; then the checker
 * thread's alone), with the dry runs' budget in ns, asking cycle (or NULL)
 * for snapshots of the controller. Returns 0, or -1 with a message on
 * stderr (no eventfd). */
int kd_checker_init(kd_checker *k, kc_check *check, int64_t budget_ns, kd_cycle *cycle);

/* Starts the thread at normal priority, off the cycle's CPU (cfg). Returns
 * 0 or -1. */
int kd_checker_start(kd_checker *k, const kd_config *cfg);

/* Stops the thread (a dry run under way ends as KD_JOB_STOPPED) and joins
 * it; then closes nothing: kd_checker_destroy does. */
void kd_checker_stop(kd_checker *k);
void kd_checker_destroy(kd_checker *k);

/* I/O thread: hands goal over for its dry run. 0, or -1 when the job ring
 * or the order is full (refuse the goal with kd_checker_refuse, rej NULL). */
int kd_checker_submit(kd_checker *k, const kc_goal *goal);

/* I/O thread: goal goal_id refused before any dry run, with rej (NULL: the
 * job ring was full); behind: goals the caller handed on are still to be
 * answered by the controller. Returns 1 when the caller answers it now
 * (nothing waits before it, or the order is full: counted), 0 when it is
 * kept and comes back from kd_checker_answer in its turn. */
int kd_checker_refuse(kd_checker *k, int64_t goal_id, const kd_reject *rej, int behind);

/* I/O thread: a servo message (its cheap checks passed) in its turn.
 * Behind goals still waiting for their answers it waits in the order, a
 * message for the servo goal last there taking that one's place (the
 * stream's latest), and comes back from kd_checker_answer (servo set) for
 * the cycle: a stream sent after a goal does not overtake that goal's dry
 * run. Returns 0 when nothing waits before it (the caller hands it to
 * the cycle now), 1 when kept, -1 when the order has no room (the caller
 * refuses it). */
int kd_checker_servo(kd_checker *k, const kc_goal *goal);

/* The refusal of a goal for a full job ring ("queue_full: ..."). */
void kd_checker_busy(kd_reject *rej);

/* I/O thread: a tick of the controller for the checker (copied; when its
 * ring is full the latest is kept, with the rejections of those it
 * replaces, and handed over at the next call). */
void kd_checker_tick(kd_checker *k, const kc_ctrl_output *out, int64_t goals_taken);

/* I/O thread: the next answer in order, when it is ready: 1 with *a filled
 * (then kd_checker_answered once it is dealt with), else 0. */
int kd_checker_answer(kd_checker *k, kd_answer *a);
void kd_checker_answered(kd_checker *k);

/* The eventfd the I/O thread polls for verdicts (read it to clear). */
int kd_checker_done_fd(const kd_checker *k);

#endif
