/* SPDX-License-Identifier: BSD-3-Clause */
/* cycle.c - the cycle thread (cycle.h). */
#define _GNU_SOURCE /* pthread_setaffinity_np, CPU_SET */
#include "cycle.h"

#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#define KD_CYCLE_STACK (8u << 20)    /* kc_ctrl_step plans paths on its stack */
#define KD_PREFAULT_STACK (256u << 10) /* touched once so no tick page-faults */

int kd_cycle_init(kd_cycle *c, const kd_config *cfg, kc_ctrl *ctrl, kc_goal *goal_storage, size_t goal_capacity,
                  kd_cmd *cmd_storage, kd_tick *tick_storage)
{
    memset(c, 0, sizeof *c);
    c->cfg = cfg;
    c->ctrl = ctrl;
    c->period_ns = cfg->period_ns;
    if (kd_spsc_init(&c->goals, goal_storage, goal_capacity, sizeof(kc_goal)) != 0 ||
        kd_spsc_init(&c->cmds, cmd_storage, KD_CMD_RING, sizeof(kd_cmd)) != 0 ||
        kd_spsc_init(&c->ticks, tick_storage, KD_TICK_RING, sizeof(kd_tick)) != 0)
        return -1;
    if (kd_plant_init(&c->plant, cfg->chain.n_joints, cfg->home, (double)cfg->period_ns * 1e-9, cfg->plant_lag_s) != 0)
        return -1;
    atomic_init(&c->servo_deadline_ns, 0);
    atomic_init(&c->ext_fault, 0);
    atomic_init(&c->cycles, 0);
    atomic_init(&c->overruns, 0);
    atomic_init(&c->ticks_dropped, 0);
    atomic_init(&c->events_dropped, 0);
    atomic_init(&c->step_errors, 0);
    atomic_init(&c->snap_state, KD_SNAP_IDLE);
    atomic_init(&c->snapshots, 0);
    atomic_init(&c->thread_live, 0);
    atomic_init(&c->state, (int)ctrl->state);
    atomic_init(&c->hist_active, 0);
    atomic_init(&c->swap_request, 0);
    atomic_init(&c->run, 0);
    atomic_init(&c->started, 0);
    kd_hist_clear(&c->lat[0]);
    kd_hist_clear(&c->lat[1]);
    kd_hist_clear(&c->comp[0]);
    kd_hist_clear(&c->comp[1]);
    return 0;
}

/* Touches the stack the ticks will use, so that with mlockall its pages are
 * resident before the first deadline. */
static void prefault_stack(void)
{
    volatile unsigned char buf[KD_PREFAULT_STACK];
    size_t i;
    for (i = 0; i < sizeof buf; i += 4096)
        buf[i] = 0;
}

/* The copy of the controller the checker asked for, once, after the step
 * (cycle.h). */
static void snapshot(kd_cycle *c)
{
    int asked = KD_SNAP_ASKED;
    if (atomic_load_explicit(&c->snap_state, memory_order_relaxed) != KD_SNAP_ASKED ||
        !atomic_compare_exchange_strong_explicit(&c->snap_state, &asked, KD_SNAP_COPYING, memory_order_acq_rel,
                                                 memory_order_relaxed))
        return;
    memcpy(c->snap_dst, c->ctrl, sizeof *c->snap_dst);
    c->snap_goals_taken = c->goals_taken_total - c->servo_taken_total;
    atomic_fetch_add_explicit(&c->snapshots, 1, memory_order_relaxed);
    atomic_store_explicit(&c->snap_state, KD_SNAP_DONE, memory_order_release);
}

/* One tick: everything between two sleeps. */
static void tick(kd_cycle *c, int64_t deadline_ns, int64_t consecutive_missed, int *policy_latched)
{
    kd_tick *t = kd_spsc_slot_write(&c->ticks);
    int to_ring = t != NULL;
    const kc_goal *goal = kd_spsc_slot_read(&c->goals);
    /* A scheduled goal waits for its tick (cycle.h), every goal behind it
     * too; commands do not wait. */
    if (goal != NULL && goal->take_cycle > c->ctrl->cycle + 1 &&
        goal->take_cycle - c->ctrl->cycle <= KD_HOLD_MAX_CYCLES)
        goal = NULL;
    kc_ctrl_input in;
    kd_cmd cmd;
    int64_t servo_deadline;
    kc_status st;
    const kc_real *q_cmd;
    const kc_real *qd_cmd;
    int seated = 0;

    if (!to_ring)
        t = &c->spare; /* the tick is dropped, but the controller still steps */
    in.goal = goal;
    in.command = KC_CMD_NONE;
    t->policy_cmd = KC_CMD_NONE;
    t->policy_missed = 0;
    /* The overrun policy, once per run of missed cycles; the command ring
     * waits a tick then, so no command is lost. */
    if (c->cfg->overrun_missed > 0 && consecutive_missed >= c->cfg->overrun_missed && !*policy_latched) {
        *policy_latched = 1;
        in.command = c->cfg->overrun_action;
        t->policy_cmd = c->cfg->overrun_action;
        t->policy_missed = consecutive_missed;
    } else if (kd_spsc_pop(&c->cmds, &cmd) == 0) {
        c->cmds_taken_total++;
        if (cmd.seat) {
            c->seat_status = kc_ctrl_seat(c->ctrl, cmd.q, &c->seat_joint);
            seated = c->seat_status == KC_OK;
            if (seated)
                kd_plant_seat(&c->plant, cmd.q);
        } else {
            in.command = cmd.command;
        }
    }
    if (consecutive_missed == 0)
        *policy_latched = 0;
    servo_deadline = atomic_load_explicit(&c->servo_deadline_ns, memory_order_acquire);
    in.servo_stale = servo_deadline != 0 && deadline_ns > servo_deadline;
    in.fault = (kc_ctrl_reason)atomic_exchange_explicit(&c->ext_fault, 0, memory_order_acq_rel);

    /* Read before the slot goes back to the I/O thread. */
    t->in_goal_id = goal != NULL ? goal->id : 0;
    t->in_goal_share = (double)kc_goal_share(goal);
    t->in_goal_stop_first = goal != NULL && goal->stop_first;
    t->in_goal_qu = goal != NULL ? (double)goal->qu : 0.0;
    t->in_goal_scheduled = goal != NULL && goal->take_cycle != 0;
    /* The step's output cycle is the controller's next. */
    t->in_goal_take_ahead = t->in_goal_scheduled ? goal->take_cycle - (c->ctrl->cycle + 1) : 0;
    t->in_goal_take_state = t->in_goal_scheduled ? goal->take_state : 0u;
    t->in_command = in.command;
    t->in_servo_stale = in.servo_stale;
    t->in_fault = in.fault != KC_REASON_NONE;
    t->in_seated = seated;
    st = kc_ctrl_step(c->ctrl, &in, &t->out);
    if (goal != NULL) {
        if (goal->kind == KC_GOAL_SERVO)
            c->servo_taken_total++;
        kd_spsc_release(&c->goals);
        c->goals_taken_total++;
    }
    if (st < 0) {
        /* The controller refused the step (a bug: its inputs come validated);
         * its output is untouched, so there is no setpoint to send. */
        atomic_fetch_add_explicit(&c->step_errors, 1, memory_order_relaxed);
        return;
    }
    q_cmd = t->out.q;
    qd_cmd = t->out.qd;
    if (c->bus != NULL)
        kd_bus_cycle(c->bus, t->out.cycle, q_cmd, qd_cmd);
    t->seat_status = c->seat_status;
    t->seat_joint = c->seat_joint;
    kd_plant_step(&c->plant, q_cmd, qd_cmd, t->q_meas, t->qd_meas);
    snapshot(c);
    t->deadline_ns = deadline_ns;
    t->goals_taken = c->goals_taken_total;
    t->servo_taken = c->servo_taken_total;
    t->cmds_taken = c->cmds_taken_total;
    t->missed_total = atomic_load_explicit(&c->overruns, memory_order_relaxed);
    atomic_store_explicit(&c->state, (int)t->out.state, memory_order_relaxed);
    atomic_fetch_add_explicit(&c->cycles, 1, memory_order_relaxed);
    /* A plain setpoint may not take the reserve (this slot included). */
    if (to_ring && t->out.n_events == 0 && t->policy_cmd == KC_CMD_NONE &&
        kd_spsc_count(&c->ticks) + KD_TICK_RESERVE >= KD_TICK_RING)
        to_ring = 0;
    if (to_ring) {
        kd_spsc_commit(&c->ticks);
        return;
    }
    atomic_fetch_add_explicit(&c->ticks_dropped, 1, memory_order_relaxed);
    if (t->out.n_events > 0)
        atomic_fetch_add_explicit(&c->events_dropped, t->out.n_events, memory_order_relaxed);
}

static void *cycle_main(void *arg)
{
    kd_cycle *c = arg;
    const int64_t period = c->period_ns;
    int64_t next, consecutive = 0;
    int policy_latched = 0;

    prctl(PR_SET_NAME, "kinctld-cycle"); /* for top -H, ps -L and the fault-injection tests */
    prefault_stack();
    next = kd_now_ns() + period;
    while (atomic_load_explicit(&c->run, memory_order_acquire)) {
        struct timespec ts;
        int64_t wake, late, missed, done;
        int active;
        ts.tv_sec = (time_t)(next / KD_NS);
        ts.tv_nsec = (long)(next % KD_NS);
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
        }
        wake = kd_now_ns();
        late = wake - next;
        /* Deadlines slept through are skipped, never made up: the tick runs
         * once, for the latest deadline that has passed. */
        missed = late >= period ? late / period : 0;
        if (missed > 0) {
            next += missed * period;
            consecutive += missed;
            atomic_fetch_add_explicit(&c->overruns, missed, memory_order_relaxed);
        } else {
            consecutive = 0;
        }
        if (atomic_load_explicit(&c->swap_request, memory_order_acquire)) {
            atomic_store_explicit(&c->hist_active, atomic_load_explicit(&c->hist_active, memory_order_relaxed) ^ 1,
                                  memory_order_relaxed);
            atomic_store_explicit(&c->swap_request, 0, memory_order_release);
        }
        tick(c, next, consecutive, &policy_latched);
        done = kd_now_ns();
        active = atomic_load_explicit(&c->hist_active, memory_order_relaxed);
        kd_hist_add(&c->lat[active], late);
        kd_hist_add(&c->comp[active], done - wake);
        atomic_store_explicit(&c->started, 1, memory_order_release);
        next += period;
    }
    return NULL;
}

int kd_cycle_start(kd_cycle *c)
{
    pthread_attr_t attr;
    int rc;
    c->rt_applied = 0;
    atomic_store(&c->run, 1);
    /* Live before it exists: the I/O thread must never touch the cycle's
     * histograms from the moment it could run. */
    atomic_store(&c->thread_live, 1);
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, KD_CYCLE_STACK);
    if (c->cfg->rt_enable) {
        struct sched_param sp;
        memset(&sp, 0, sizeof sp);
        sp.sched_priority = c->cfg->rt_priority;
        pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
        pthread_attr_setschedpolicy(&attr, SCHED_FIFO);
        pthread_attr_setschedparam(&attr, &sp);
        rc = pthread_create(&c->thread, &attr, cycle_main, c);
        if (rc == 0) {
            c->rt_applied |= 1;
        } else {
            fprintf(stderr, "kinctld: warning: no SCHED_FIFO priority %d for the cycle (%s); running it as a normal "
                            "thread (grant CAP_SYS_NICE or LimitRTPRIO)\n",
                    c->cfg->rt_priority, strerror(rc));
            pthread_attr_setinheritsched(&attr, PTHREAD_INHERIT_SCHED);
            rc = pthread_create(&c->thread, &attr, cycle_main, c);
        }
    } else {
        rc = pthread_create(&c->thread, &attr, cycle_main, c);
    }
    pthread_attr_destroy(&attr);
    if (rc != 0) {
        atomic_store(&c->run, 0);
        atomic_store(&c->thread_live, 0);
        fprintf(stderr, "kinctld: cannot start the cycle thread: %s\n", strerror(rc));
        return -1;
    }
    if (c->cfg->rt_enable) {
        int cpu = kd_cycle_cpu(c->cfg);
        if (cpu >= 0) {
            cpu_set_t set;
            CPU_ZERO(&set);
            CPU_SET((size_t)cpu, &set);
            rc = pthread_setaffinity_np(c->thread, sizeof set, &set);
            if (rc == 0)
                c->rt_applied |= 2;
            else
                fprintf(stderr, "kinctld: warning: cannot pin the cycle to CPU %d (%s); it runs on any CPU\n", cpu,
                        strerror(rc));
        }
    }
    return 0;
}

int kd_cycle_cpu(const kd_config *cfg)
{
    long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
    int cpu = cfg->rt_cpu;
    if (!cfg->rt_enable)
        return -1;
    if (cpu < 0 && ncpu > 1)
        cpu = (int)ncpu - 1;
    return cpu >= 0 && cpu < CPU_SETSIZE ? cpu : -1;
}

void kd_cycle_keep_off(const kd_config *cfg, pthread_t thread, const char *what)
{
    int cycle_cpu = kd_cycle_cpu(cfg);
    long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
    if (cycle_cpu >= 0 && ncpu > 1) {
        cpu_set_t set;
        int rc;
        CPU_ZERO(&set);
        for (long c = 0; c < ncpu && c < CPU_SETSIZE; c++)
            if (c != cycle_cpu)
                CPU_SET((size_t)c, &set);
        rc = pthread_setaffinity_np(thread, sizeof set, &set);
        if (rc != 0)
            fprintf(stderr, "kinctld: warning: cannot keep the %s thread off CPU %d (%s)\n", what, cycle_cpu,
                    strerror(rc));
    }
}

int kd_cycle_snapshot(kd_cycle *c, kc_ctrl *dst, int64_t wait_ns, int64_t *goals_taken)
{
    /* A tenth of a period between looks: the copy comes within a tick. */
    struct timespec nap = {0, (long)(c->period_ns / 10 > 0 ? c->period_ns / 10 : 1)};
    int64_t until = kd_now_ns() + wait_ns;
    c->snap_dst = dst;
    atomic_store_explicit(&c->snap_state, KD_SNAP_ASKED, memory_order_release);
    for (;;) {
        int st = atomic_load_explicit(&c->snap_state, memory_order_acquire);
        if (st == KD_SNAP_DONE) {
            *goals_taken = c->snap_goals_taken;
            atomic_store_explicit(&c->snap_state, KD_SNAP_IDLE, memory_order_relaxed);
            return 1;
        }
        if (st == KD_SNAP_ASKED && kd_now_ns() >= until) {
            int asked = KD_SNAP_ASKED;
            if (atomic_compare_exchange_strong_explicit(&c->snap_state, &asked, KD_SNAP_IDLE, memory_order_acq_rel,
                                                        memory_order_acquire))
                return 0;
            continue; /* the copy has begun: it ends within the tick */
        }
        nanosleep(&nap, NULL);
    }
}

void kd_cycle_stop(kd_cycle *c)
{
    atomic_store(&c->run, 0);
    if (atomic_load(&c->thread_live)) {
        pthread_join(c->thread, NULL);
        atomic_store(&c->thread_live, 0);
    }
}

int kd_cycle_stats_take(kd_cycle *c, kd_cycle_stats *s)
{
    int retired;
    kd_hist *lat, *comp;
    if (!c->stats_pending) {
        if (atomic_load(&c->thread_live)) {
            atomic_store_explicit(&c->swap_request, 1, memory_order_release);
            c->stats_pending = 1;
            return 0;
        }
        /* No cycle running: nothing writes the histograms; swap here. */
        atomic_store(&c->hist_active, atomic_load(&c->hist_active) ^ 1);
    } else if (atomic_load_explicit(&c->swap_request, memory_order_acquire)) {
        if (atomic_load(&c->thread_live))
            return 0; /* not swapped yet */
        atomic_store(&c->hist_active, atomic_load(&c->hist_active) ^ 1);
        atomic_store(&c->swap_request, 0);
    }
    c->stats_pending = 0;
    retired = atomic_load_explicit(&c->hist_active, memory_order_acquire) ^ 1;
    lat = &c->lat[retired];
    comp = &c->comp[retired];
    s->count = lat->count;
    s->lat_p50 = kd_hist_percentile(lat, 0.50);
    s->lat_p99 = kd_hist_percentile(lat, 0.99);
    s->lat_p999 = kd_hist_percentile(lat, 0.999);
    s->lat_max = lat->max;
    s->comp_p50 = kd_hist_percentile(comp, 0.50);
    s->comp_p99 = kd_hist_percentile(comp, 0.99);
    s->comp_max = comp->max;
    kd_hist_clear(lat);
    kd_hist_clear(comp);
    return 1;
}
