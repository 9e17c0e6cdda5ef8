/* SPDX-License-Identifier: BSD-3-Clause */
/* checker.c - the checker thread and the goals' answers in order
 * (checker.h). */
#define _GNU_SOURCE /* syscall(SYS_gettid) */
#include "checker.h"

#include <errno.h>
#include <inttypes.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/eventfd.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "clock.h"
#include "cycle.h"

enum { KD_ORDER_CHECKED = 0, KD_ORDER_REFUSED = 1, KD_ORDER_BUSY = 2, KD_ORDER_SERVO = 3 };
enum { KD_FROM_ORDER = 0, KD_FROM_VERDICTS = 1, KD_FROM_JOBS = 2 };

/* Nice value of the checker: still SCHED_OTHER, but a dry run that keeps
 * its CPU busy yields at once to the I/O thread when a datagram wakes it. */
#define KD_CHECK_NICE 10

int kd_checker_init(kd_checker *k, kc_check *check, int64_t budget_ns, kd_cycle *cycle)
{
    memset(k, 0, sizeof *k);
    k->check = check;
    k->cycle = cycle;
    k->budget_ns = budget_ns;
    k->wake_fd = k->done_fd = -1;
    if (kd_spsc_init(&k->jobs, k->job_storage, KD_CHECK_RING, sizeof(kd_job)) != 0 ||
        kd_spsc_init(&k->verdicts, k->verdict_storage, KD_CHECK_RING, sizeof(kd_job)) != 0 ||
        kd_spsc_init(&k->ticks, k->tick_storage, KD_CHECK_TICK_RING, sizeof(kd_check_tick)) != 0)
        return -1;
    atomic_init(&k->judged, 0);
    atomic_init(&k->over_budget, 0);
    atomic_init(&k->moving, 0);
    atomic_init(&k->slowed, 0);
    atomic_init(&k->late, 0);
    atomic_init(&k->jerk_refused, 0);
    atomic_init(&k->run, 0);
    k->wake_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    k->done_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (k->wake_fd < 0 || k->done_fd < 0) {
        fprintf(stderr, "kinctld: cannot make the checker's eventfds: %s\n", strerror(errno));
        kd_checker_destroy(k);
        return -1;
    }
    return 0;
}

static void signal_fd(int fd)
{
    uint64_t one = 1;
    ssize_t r = write(fd, &one, sizeof one); /* EAGAIN: already signalled */
    (void)r;
}

/* ---- the checker thread ------------------------------------------------ */

static void take_ticks(kd_checker *k)
{
    const kd_check_tick *t;
    while ((t = kd_spsc_slot_read(&k->ticks)) != NULL) {
        kc_check_tick(k->check, &t->out, t->goals_taken);
        k->ctrl_moving = t->out.state == KC_CTRL_MOVING || t->out.state == KC_CTRL_STOPPING;
        kd_spsc_release(&k->ticks);
    }
}

/* The controller as a replacing goal finds it (checker.h): a snapshot from
 * the cycle into k->keep, taken again while it is not fresh for a goal
 * k->check->lead ticks after it, for at most KD_SNAP_WAIT_MS, or while
 * the controller moves the dry runs' budget. 1 with the snapshot kept
 * (k->keep_taken, k->keep_ns), else 0. */
static int take_snapshot(kd_checker *k)
{
    /* A goal handed on before, scheduled, is taken in its cycle: no
     * snapshot is fresh before that. */
    int64_t now = kd_now_ns();
    int64_t from = k->held_ns > now ? k->held_ns : now, until;
    do {
        until = from + (k->ctrl_moving ? k->budget_ns : KD_SNAP_WAIT_MS * 1000000LL);
        if (!kd_cycle_snapshot(k->cycle, &k->keep, until - kd_now_ns(), &k->keep_taken))
            return 0;
        k->keep_ns = kd_now_ns();
        take_ticks(k);
        if (kc_check_snapshot(k->check, &k->keep, k->keep_taken) == KC_OK && kc_check_snapshot_fresh(k->check))
            return 1;
    } while (kd_now_ns() < until && atomic_load_explicit(&k->run, memory_order_acquire));
    return 0;
}

/* One dry run of out->goal, in slices, into out, within the budget from
 * start; from the snapshot kept when snap. */
static void judge_once(kd_checker *k, kd_job *out, int64_t start, int snap)
{
    kc_status st;
    out->end = KD_JOB_JUDGED;
    if (snap)
        kc_check_snapshot(k->check, &k->keep, k->keep_taken);
    st = kc_check_begin(k->check, &out->goal, &out->verdict);
    while (st == KC_MORE) {
        int64_t elapsed = kd_now_ns() - start;
        if (!atomic_load_explicit(&k->run, memory_order_acquire)) {
            out->end = KD_JOB_STOPPED;
            break;
        }
        if (elapsed >= k->budget_ns) {
            out->end = KD_JOB_OVER_BUDGET;
            break;
        }
        st = kc_check_run(k->check, KD_CHECK_SLICE, &out->verdict);
        /* Where the controller is, between slices: the ring never fills
         * behind a long dry run. */
        take_ticks(k);
    }
    out->elapsed_ns = kd_now_ns() - start;
    out->ticks = k->check->run_tick;
    out->progress = k->check->run_progress;
}

static int taken(const kd_job *j) { return j->end == KD_JOB_JUDGED && j->verdict.status == KC_OK; }

/* The joints' jerk of a verdict beyond their limits, rounding apart. */
static int over_jerk(const kd_job *j) { return taken(j) && !kc_check_jerk_within(&j->verdict); }

/* Judges k->trial; 1 when taken with less jerk than out, which it then
 * replaces. */
static int better(kd_checker *k, kd_job *out, int64_t start, int snap)
{
    judge_once(k, &k->trial, start, snap);
    if (!taken(&k->trial) || !(k->trial.verdict.jerk < out->verdict.jerk))
        return 0;
    memcpy(out, &k->trial, sizeof *out);
    return 1;
}

/* What a search did (judge). */
typedef struct search_note {
    double jerk;   /* the goal as asked: its joints' jerk */
    double slowed; /* the share of its speed taken, 1: as asked */
    int stop_first, moving;
    int cut; /* a slower one's dry run ran over the budget */
} search_note;

/* The dry runs of job into out (judge), from the snapshot kept when
 * snap. A replacing goal judged from the moving state that the arm cannot
 * follow there (KC_E_UNREACHABLE: the superposition's tracking, a zone)
 * is judged again with the motion it replaces stopped first
 * (kc_goal.stop_first: no admissible transition, so stop and start), and
 * taken so if it passes; the search below then slows that. A jerk-limited Cartesian goal taken with its joints' jerk beyond
 * their limits (kinctl/check.h) is slowed and judged again by
 * kc_check_slow's search, up to KC_CHECK_SLOW_PASSES times within the one
 * budget: the fastest share of its speed judged within the limits is
 * handed on, or, where none is, the one with the least jerk (the goal as
 * asked if none has less). Such a replacing goal judged from the moving
 * state whose transition is still beyond them (the replaced motion's stop
 * is part of it: a line superposed on a joint move's stop adds the line's
 * joint jerk to the stop's) is judged again with the motion it replaces
 * stopped first (kc_goal.stop_first), and so taken if that does better.
 * The goal handed on is the last one taken: a pass that is refused, runs
 * over the budget or does no better leaves the one before (judge then
 * refuses one still beyond the limits: jerk_refused). */
static void search(kd_checker *k, const kd_job *job, kd_job *out, int64_t start, int snap, search_note *note)
{
    memcpy(&out->goal, &job->goal, sizeof out->goal);
    judge_once(k, out, start, snap);
    int slowable = 0;
    note->moving = k->check->run_moving;
    note->jerk = (double)out->verdict.jerk;
    note->slowed = 1.0;
    note->stop_first = 0;
    note->cut = 0;
    /* No admissible transition from the moving state (the arm cannot
     * follow the superposition, or it runs into a zone or a limit): the
     * motion it replaces stops first, if the goal is taken so. */
    if (out->end == KD_JOB_JUDGED && out->verdict.status == KC_E_UNREACHABLE && note->moving &&
        out->goal.replace && !out->goal.stop_first) {
        memcpy(&k->trial.goal, &out->goal, sizeof k->trial.goal);
        k->trial.goal.stop_first = 1;
        judge_once(k, &k->trial, start, snap);
        if (taken(&k->trial)) {
            memcpy(out, &k->trial, sizeof *out);
            note->jerk = (double)out->verdict.jerk;
            note->stop_first = 1;
        }
    }
    kc_check_slow ss;
    memset(&ss, 0, sizeof ss);
    if (over_jerk(out))
        kc_check_slow_start(&ss, &out->verdict);
    for (int pass = 0; pass < KC_CHECK_SLOW_PASSES && ss.s > KC_R(0.0); pass++) {
        memcpy(&k->trial.goal, &job->goal, sizeof k->trial.goal);
        k->trial.goal.stop_first = out->goal.stop_first;
        if (kc_goal_slow(&k->trial.goal, &k->check->cfg, ss.s) != KC_OK)
            break; /* a joint move (within the limits from any start), joint path or trapezoid */
        slowable = 1;
        double s = (double)ss.s;
        judge_once(k, &k->trial, start, snap);
        note->cut = k->trial.end == KD_JOB_OVER_BUDGET;
        if (!taken(&k->trial))
            break;
        if (kc_check_slow_next(&ss, &k->trial.verdict)) {
            memcpy(out, &k->trial, sizeof *out);
            note->slowed = s;
        }
    }
    /* Only a goal kc_goal_slow takes stops first for its jerk: a joint
     * path's or a trapezoid's own law is not jerk-limited, which stopping
     * first does not change. */
    if (over_jerk(out) && slowable && note->moving && out->goal.replace && !out->goal.stop_first &&
        out->verdict.reason != KC_REASON_STOP_FIRST) {
        memcpy(&k->trial.goal, &out->goal, sizeof k->trial.goal);
        k->trial.goal.stop_first = 1;
        note->stop_first = better(k, out, start, snap);
    }
}

/* A goal judged from the snapshot kept, taken, can still reach the cycle
 * before its tick (kc_verdict.take_cycle), with KD_HAND_MARGIN_MS to
 * spare: that tick runs about (take_cycle - the snapshot's cycle) periods
 * after the snapshot was seen (no earlier: a stalled cycle runs later). */
static int on_time(const kd_checker *k, const kd_job *out)
{
    int64_t ahead = out->verdict.take_cycle - k->keep.cycle;
    return out->verdict.take_cycle != 0 && k->check->run_moving &&
           kd_now_ns() + KD_HAND_MARGIN_MS * 1000000LL < k->keep_ns + ahead * k->cycle->period_ns;
}

/* A goal taken over its joints' jerk limits after the search is refused
 * when its law is jerk-limited and the excess is its own
 * (kc_verdict.jerk_own: judged from rest, from a motion on a jerk-limited
 * law, or from its start after stopping first a motion on one that is
 * not): the excess is then no other law's (a trapezoid's, a joint
 * path's), and taking it would drive the joints beyond their limits. */
static int jerk_refused(const kd_checker *k, const kd_job *out)
{
    return kc_ctrl_jerk_limited(&k->check->scratch, &out->goal) && out->goal.kind != KC_GOAL_JOINT &&
           out->verdict.jerk_own;
}

/* The dry run of job into out (search). A replacing goal is judged from a
 * snapshot of the controller for a tick k->check->lead ticks after it
 * (kinctl/check.h), first KD_LEAD_MS ahead; a judgement that ends too late
 * to reach the cycle before that tick (on_time) is made again, from a new
 * snapshot, with the lead twice the time it took plus the margin, up to
 * KD_LEAD_TRIES times: the goal handed on is taken in the tick and from
 * the state it was judged for, or refused by the controller (KC_REASON_LATE).
 * The lead is at most KD_LEAD_MAX_MS. */
static void judge(kd_checker *k, const kd_job *job, kd_job *out)
{
    int64_t start = kd_now_ns(), lead_ns = KD_LEAD_MS * 1000000LL;
    int replacing = job->goal.replace && job->goal.kind != KC_GOAL_SERVO && k->cycle != NULL;
    search_note note;
    for (int attempt = 0;; attempt++) {
        int64_t began = kd_now_ns(), period = replacing ? k->cycle->period_ns : 1;
        if (lead_ns > KD_LEAD_MAX_MS * 1000000LL)
            lead_ns = KD_LEAD_MAX_MS * 1000000LL;
        k->check->lead = replacing ? (lead_ns + period - 1) / period - 1 : 0;
        int snap = replacing && take_snapshot(k);
        if (replacing && !snap && k->ctrl_moving) {
            /* Judged from rest, it would be taken unjudged from the moving
             * state: refused. */
            memcpy(&out->goal, &job->goal, sizeof out->goal);
            kc_ctrl_verdict_init(&out->verdict);
            out->verdict.status = KC_E_STATE;
            out->verdict.reason = KC_REASON_LATE;
            out->end = atomic_load_explicit(&k->run, memory_order_acquire) ? KD_JOB_JUDGED : KD_JOB_STOPPED;
            memset(&note, 0, sizeof note);
            note.slowed = 1.0;
            break;
        }
        search(k, job, out, start, snap, &note);
        if (!snap || !taken(out) || on_time(k, out) || attempt + 1 >= KD_LEAD_TRIES ||
            out->end != KD_JOB_JUDGED)
            break;
        atomic_fetch_add_explicit(&k->late, 1, memory_order_relaxed);
        lead_ns = 2 * (kd_now_ns() - began) + KD_HAND_MARGIN_MS * 1000000LL;
        fprintf(stderr, "kinctld: goal %" PRId64 " judged again for a later tick (its judgement took %.3g ms)\n",
                job->goal.id, (double)(kd_now_ns() - began) * 1e-6);
    }
    if (note.moving)
        atomic_fetch_add_explicit(&k->moving, 1, memory_order_relaxed);
    out->goal.take_cycle = out->verdict.take_cycle;
    out->goal.take_state = out->verdict.take_state;
    out->goal.qu = out->verdict.qu; /* what its resume after a pause is held to */
    out->elapsed_ns = kd_now_ns() - start;
    out->slowed = note.slowed;
    out->cut = note.cut;
    if (note.slowed < 1.0 || note.stop_first)
        atomic_fetch_add_explicit(&k->slowed, 1, memory_order_relaxed);
    if (note.slowed < 1.0)
        fprintf(stderr,
                "kinctld: goal %" PRId64 " slowed to %.3g of its speed (its joints' jerk %.3g times their limits, "
                "now %.3g)\n",
                out->goal.id, note.slowed, note.jerk, (double)out->verdict.jerk);
    if (note.stop_first)
        fprintf(stderr,
                "kinctld: goal %" PRId64 " stops the motion it replaces first (taking over, its joints' jerk %.3g "
                "times their limits; so, %.3g)\n",
                out->goal.id, note.jerk, (double)out->verdict.jerk);
    if (over_jerk(out) && jerk_refused(k, out)) {
        out->verdict.status = KC_E_LIMIT;
        out->verdict.reason = KD_REASON_JERK;
        atomic_fetch_add_explicit(&k->jerk_refused, 1, memory_order_relaxed);
    } else if (over_jerk(out)) {
        fprintf(stderr,
                "kinctld: goal %" PRId64 " taken with its joints' jerk %.3g times their limits (the law of it or of "
                "the motion it replaces is not jerk-limited)\n",
                out->goal.id, (double)out->verdict.jerk);
    }
    if (out->end == KD_JOB_OVER_BUDGET)
        atomic_fetch_add_explicit(&k->over_budget, 1, memory_order_relaxed);
    if (taken(out)) {
        kc_check_handed(k->check, &out->goal, &out->verdict);
        if (out->goal.take_cycle != 0)
            k->held_ns = k->keep_ns + (out->goal.take_cycle - k->keep.cycle) * k->cycle->period_ns;
    }
    atomic_fetch_add_explicit(&k->judged, 1, memory_order_relaxed);
}

static void wait_for_work(kd_checker *k)
{
    struct pollfd pfd;
    uint64_t n;
    pfd.fd = k->wake_fd;
    pfd.events = POLLIN;
    pfd.revents = 0;
    if (poll(&pfd, 1, KD_CHECK_IDLE_MS) > 0) {
        ssize_t r = read(k->wake_fd, &n, sizeof n);
        (void)r;
    }
}

static void *checker_main(void *arg)
{
    kd_checker *k = arg;
    prctl(PR_SET_NAME, "kinctld-check");
    if (setpriority(PRIO_PROCESS, (id_t)syscall(SYS_gettid), KD_CHECK_NICE) != 0)
        fprintf(stderr, "kinctld: warning: the checker keeps its nice value (%s)\n", strerror(errno));
    while (atomic_load_explicit(&k->run, memory_order_acquire)) {
        const kd_job *job;
        kd_job *out;
        take_ticks(k);
        job = kd_spsc_slot_read(&k->jobs);
        out = job != NULL ? kd_spsc_slot_write(&k->verdicts) : NULL;
        if (out == NULL) { /* nothing to judge, or the I/O thread has every verdict still to answer */
            wait_for_work(k);
            continue;
        }
        judge(k, job, out);
        kd_spsc_commit(&k->verdicts);
        kd_spsc_release(&k->jobs);
        signal_fd(k->done_fd);
    }
    return NULL;
}

int kd_checker_start(kd_checker *k, const kd_config *cfg)
{
    int rc;
    atomic_store(&k->run, 1);
    rc = pthread_create(&k->thread, NULL, checker_main, k);
    if (rc != 0) {
        atomic_store(&k->run, 0);
        fprintf(stderr, "kinctld: cannot start the checker thread: %s\n", strerror(rc));
        return -1;
    }
    k->thread_live = 1;
    kd_cycle_keep_off(cfg, k->thread, "checker");
    return 0;
}

void kd_checker_stop(kd_checker *k)
{
    atomic_store(&k->run, 0);
    if (k->thread_live) {
        signal_fd(k->wake_fd);
        pthread_join(k->thread, NULL);
        k->thread_live = 0;
    }
    k->stopped = 1;
}

void kd_checker_destroy(kd_checker *k)
{
    if (k->wake_fd >= 0)
        close(k->wake_fd);
    if (k->done_fd >= 0)
        close(k->done_fd);
    k->wake_fd = k->done_fd = -1;
}

int kd_checker_done_fd(const kd_checker *k)
{
    return k->done_fd;
}

/* ---- the I/O thread's side --------------------------------------------- */

static int order_full(const kd_checker *k)
{
    return k->order_tail - k->order_head >= KD_ORDER_MAX;
}

static void order_push(kd_checker *k, int64_t goal_id, int kind, int text)
{
    kd_order *o = &k->order[k->order_tail % KD_ORDER_MAX];
    o->goal_id = goal_id;
    o->kind = kind;
    o->text = text;
    k->order_tail++;
}

int kd_checker_submit(kd_checker *k, const kc_goal *goal)
{
    kd_job *job;
    if (k->stopped || order_full(k) || (job = kd_spsc_slot_write(&k->jobs)) == NULL)
        return -1;
    memcpy(&job->goal, goal, sizeof job->goal);
    job->end = KD_JOB_STOPPED; /* until the checker judges it */
    kd_spsc_commit(&k->jobs);
    order_push(k, goal->id, KD_ORDER_CHECKED, 0);
    signal_fd(k->wake_fd);
    return 0;
}

int kd_checker_refuse(kd_checker *k, int64_t goal_id, const kd_reject *rej, int behind)
{
    if (k->order_tail == k->order_head && !behind)
        return 1; /* nothing waits before it */
    if (order_full(k) || (rej != NULL && k->texts_tail - k->texts_head >= KD_ORDER_TEXTS)) {
        k->answered_early++;
        return 1;
    }
    if (rej == NULL) {
        order_push(k, goal_id, KD_ORDER_BUSY, 0);
        return 0;
    }
    k->texts[k->texts_tail % KD_ORDER_TEXTS] = *rej;
    order_push(k, goal_id, KD_ORDER_REFUSED, (int)(k->texts_tail % KD_ORDER_TEXTS));
    k->texts_tail++;
    return 0;
}

int kd_checker_servo(kd_checker *k, const kc_goal *goal)
{
    if (k->order_tail == k->order_head)
        return 0;
    const kd_order *last = &k->order[(k->order_tail - 1) % KD_ORDER_MAX];
    if (last->kind == KD_ORDER_SERVO && last->goal_id == goal->id) {
        k->servos[last->text] = *goal;
        return 1;
    }
    if (order_full(k) || k->servos_tail - k->servos_head >= KD_ORDER_SERVOS)
        return -1;
    k->servos[k->servos_tail % KD_ORDER_SERVOS] = *goal;
    order_push(k, goal->id, KD_ORDER_SERVO, (int)(k->servos_tail % KD_ORDER_SERVOS));
    k->servos_tail++;
    return 1;
}

void kd_checker_tick(kd_checker *k, const kc_ctrl_output *out, int64_t goals_taken)
{
    kd_check_tick *p = &k->pending;
    if (k->have_pending) {
        /* The tick kept is replaced by this one: its rejections stay (the
         * checker learns from them that a goal handed on was refused). */
        kc_ctrl_event keep[KC_CTRL_EVENTS_MAX];
        int n_keep = 0;
        for (int i = 0; i < p->out.n_events && i < KC_CTRL_EVENTS_MAX; i++)
            if (p->out.events[i].kind == KC_EVENT_REJECTED)
                keep[n_keep++] = p->out.events[i];
        p->out = *out;
        for (int i = 0; i < n_keep && p->out.n_events < KC_CTRL_EVENTS_MAX; i++)
            p->out.events[p->out.n_events++] = keep[i];
    } else {
        p->out = *out;
    }
    p->goals_taken = goals_taken;
    k->have_pending = kd_spsc_push(&k->ticks, p) != 0;
}

void kd_checker_busy(kd_reject *rej)
{
    kd_reject_set(rej, KC_REASON_QUEUE_FULL, "the dry runs' queue (%d goals) is full", KD_CHECK_RING);
}

int kd_checker_answer(kd_checker *k, kd_answer *a)
{
    const kd_order *o;
    if (k->order_head == k->order_tail)
        return 0;
    o = &k->order[k->order_head % KD_ORDER_MAX];
    a->goal_id = o->goal_id;
    a->job = NULL;
    a->servo = NULL;
    if (o->kind == KD_ORDER_SERVO) {
        a->servo = &k->servos[o->text];
        k->answer_from = KD_FROM_ORDER;
        return 1;
    }
    if (o->kind == KD_ORDER_REFUSED) {
        a->rej = k->texts[o->text];
        k->answer_from = KD_FROM_ORDER;
        return 1;
    }
    if (o->kind == KD_ORDER_BUSY) {
        kd_checker_busy(&a->rej);
        k->answer_from = KD_FROM_ORDER;
        return 1;
    }
    a->job = kd_spsc_slot_read(&k->verdicts);
    k->answer_from = KD_FROM_VERDICTS;
    if (a->job == NULL && k->stopped) {
        /* The checker is gone: the jobs it never judged, as they were
         * handed over (end KD_JOB_STOPPED). */
        a->job = kd_spsc_slot_read(&k->jobs);
        k->answer_from = KD_FROM_JOBS;
    }
    return a->job != NULL;
}

void kd_checker_answered(kd_checker *k)
{
    const kd_order *o;
    if (k->order_head == k->order_tail)
        return;
    o = &k->order[k->order_head % KD_ORDER_MAX];
    if (o->kind == KD_ORDER_REFUSED)
        k->texts_head++;
    if (o->kind == KD_ORDER_SERVO)
        k->servos_head++;
    if (k->answer_from == KD_FROM_VERDICTS && o->kind == KD_ORDER_CHECKED) {
        /* A checker waiting for room for its verdict goes on at once. */
        int was_full = kd_spsc_count(&k->verdicts) == KD_CHECK_RING;
        kd_spsc_release(&k->verdicts);
        if (was_full && !k->stopped)
            signal_fd(k->wake_fd);
    } else if (k->answer_from == KD_FROM_JOBS && o->kind == KD_ORDER_CHECKED)
        kd_spsc_release(&k->jobs);
    k->order_head++;
}
