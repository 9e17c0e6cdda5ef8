/* SPDX-License-Identifier: BSD-3-Clause */
/* lcm_io.c - the I/O thread (lcm_io.h). */
#define _GNU_SOURCE /* ppoll */
#include "lcm_io.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <unistd.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/prctl.h>
#include <time.h>

#include "kinctl/se3.h"

#define KD_HANDLE_BURST 64 /* datagrams per wake-up before the tick ring is drained again */

/* ---- publishing -------------------------------------------------------- */

static void publish(kd_io *io, kd_msg_type type, const void *msg)
{
    size_t len = 0;
    if (kd_msg_encode(type, msg, io->buf, sizeof io->buf, &len) != KD_MSG_OK ||
        lcm_publish(io->lcm, io->channel[type], io->buf, (unsigned)len) != 0) {
        io->publish_errors++;
        io->msgs_dropped++;
        return;
    }
    io->msgs_out++;
}

static int64_t utime_of(const kd_io *io, int64_t mono_ns)
{
    return (mono_ns + io->realtime_offset_ns) / 1000;
}

static void publish_setpoint(kd_io *io, const kd_tick *t)
{
    kinctl_setpoint_t *sp = &io->sp;
    const kc_ctrl_output *o = &t->out;
    int j, n = io->cfg->chain.n_joints;
    kc_quat q;
    memset(sp, 0, sizeof *sp);
    sp->utime = utime_of(io, t->deadline_ns);
    sp->cycle = o->cycle;
    sp->goal_id = o->goal_id;
    sp->state = (int8_t)o->state;
    sp->n = n;
    for (j = 0; j < n; j++) {
        sp->q[j] = (double)o->q[j];
        sp->qd[j] = (double)o->qd[j];
        sp->qdd[j] = (double)o->qdd[j];
    }
    for (j = 0; j < 3; j++)
        sp->position[j] = (double)o->pose.t.v[j];
    kc_quat_from_mat3(&o->pose.R, &q);
    sp->orientation[0] = (double)q.w;
    sp->orientation[1] = (double)q.x;
    sp->orientation[2] = (double)q.y;
    sp->orientation[3] = (double)q.z;
    sp->input_goal_id = t->in_goal_id;
    sp->input_command = (int8_t)t->in_command;
    sp->input_servo_stale = (int8_t)(t->in_servo_stale != 0);
    sp->input_fault = (int8_t)(t->in_fault != 0);
    sp->input_seated = (int8_t)(t->in_seated != 0);
    sp->input_goal_share = t->in_goal_share;
    sp->input_goal_stop_first = (int8_t)(t->in_goal_stop_first != 0);
    sp->input_goal_qu = t->in_goal_qu;
    sp->input_goal_scheduled = (int8_t)(t->in_goal_scheduled != 0);
    sp->input_goal_take_ahead = t->in_goal_take_ahead;
    sp->input_goal_take_state = (int64_t)t->in_goal_take_state;
    publish(io, KD_MSG_SETPOINT, sp);
}

/* A status from the latest tick, with an event about goal_id. */
static kinctl_status_t *fill_status(kd_io *io, int8_t event, int64_t goal_id, kc_status code, const char *reason)
{
    kinctl_status_t *st = &io->st;
    int j, n = io->cfg->chain.n_joints;
    memset(st, 0, sizeof *st);
    st->utime = utime_of(io, kd_now_ns());
    st->n = n;
    for (j = 0; j < n; j++)
        st->prismatic[j] = (int8_t)(io->cfg->chain.joints[j].type == KC_JOINT_PRISMATIC);
    if (io->have_last) {
        const kc_ctrl_output *o = &io->last.out;
        st->cycle = o->cycle;
        st->state = (int8_t)o->state;
        st->active_goal_id = o->goal_id;
        st->progress = (double)o->progress;
        st->queue_length = o->queue_length;
        for (j = 0; j < n; j++) {
            st->q_measured[j] = (double)io->last.q_meas[j];
            st->qd_measured[j] = (double)io->last.qd_meas[j];
        }
        /* With drive feedback, the arm is measured by its drives. */
        for (j = 0; j < n && io->cfg->can.feedback; j++) {
            if (io->can.have_fb[j]) {
                st->q_measured[j] = io->can.q_fb[j];
                st->qd_measured[j] = io->can.qd_fb[j];
            }
        }
    } else {
        st->state = KINCTL_STATUS_T_IDLE;
        for (j = 0; j < n; j++)
            st->q_measured[j] = (double)io->cfg->home[j];
    }
    st->can_state = (int8_t)io->can.state;
    st->drives = (int8_t)io->master.drives;
    st->event = event;
    st->event_goal_id = goal_id;
    st->code = (int32_t)code;
    snprintf(io->reason, sizeof io->reason, "%s", reason != NULL ? reason : "");
    st->reason = io->reason;
    return st;
}

static void publish_status(kd_io *io, int8_t event, int64_t goal_id, kc_status code, const char *reason)
{
    publish(io, KD_MSG_STATUS, fill_status(io, event, goal_id, code, reason));
}

/* A REJECTED status with the verdict's text, and the joint a limit
 * rejection names (status_t.joint..: clients show it in their own units). */
static void reject(kd_io *io, int64_t goal_id, const kd_reject *rej)
{
    kinctl_status_t *st = fill_status(io, KINCTL_STATUS_T_REJECTED, goal_id, rej->code, rej->text);
    io->rejections++;
    st->joint = rej->joint;
    st->joint_prismatic = (int8_t)(rej->prismatic != 0);
    st->joint_value = rej->value;
    st->joint_lower = rej->lower;
    st->joint_upper = rej->upper;
    publish(io, KD_MSG_STATUS, st);
}

static void publish_stats(kd_io *io, const kd_cycle_stats *cs)
{
    kinctl_stats_t *s = &io->stats;
    memset(s, 0, sizeof *s);
    s->utime = utime_of(io, kd_now_ns());
    s->period_ns = io->cfg->period_ns;
    s->cycles = atomic_load(&io->cycle->cycles);
    s->latency_p50_ns = cs->lat_p50;
    s->latency_p99_ns = cs->lat_p99;
    s->latency_p999_ns = cs->lat_p999;
    s->latency_max_ns = cs->lat_max;
    s->compute_p50_ns = cs->comp_p50;
    s->compute_p99_ns = cs->comp_p99;
    s->compute_max_ns = cs->comp_max;
    s->overruns = atomic_load(&io->cycle->overruns);
    s->msgs_in = io->msgs_in;
    s->msgs_invalid = io->msgs_invalid;
    s->msgs_dropped = io->msgs_dropped + atomic_load(&io->cycle->ticks_dropped) +
                      atomic_load(&io->cycle->events_dropped);
    s->rejections = io->rejections;
    if (io->can.state != KD_CAN_OFF)
        kd_can_totals(&io->can, &s->can_frames, &s->can_tx_dropped, &s->can_errors);
    s->can_state = (int8_t)io->can.state;
    s->can_error_frames = io->can.error_frames;
    s->can_bus_off = io->can.bus_off;
    s->can_link_down = io->can.link_down;
    s->can_rx_frames = io->can.rx_frames;
    /* Counted before it goes out, so that it counts itself. */
    s->msgs_out = io->msgs_out + 1;
    publish(io, KD_MSG_STATS, s);
}

/* ---- ticks from the cycle ---------------------------------------------- */

static int8_t status_event_of(kc_ctrl_event_kind kind)
{
    switch (kind) {
    case KC_EVENT_ACCEPTED: return KINCTL_STATUS_T_ACCEPTED;
    case KC_EVENT_REJECTED: return KINCTL_STATUS_T_REJECTED;
    case KC_EVENT_COMPLETED: return KINCTL_STATUS_T_COMPLETED;
    case KC_EVENT_PREEMPTED: return KINCTL_STATUS_T_PREEMPTED;
    case KC_EVENT_ABORTED: return KINCTL_STATUS_T_ABORTED;
    case KC_EVENT_FAULT: return KINCTL_STATUS_T_EVENT_FAULT;
    case KC_EVENT_STARTED: return KINCTL_STATUS_T_STARTED;
    }
    return KINCTL_STATUS_T_NONE;
}

/* What a goal aborted from now on with no reason of the core's says. */
static void stop_cause(kd_io *io, kc_ctrl_reason reason, const char *text)
{
    io->stop_reason = reason;
    (void)snprintf(io->stop_text, sizeof io->stop_text, "%s", text);
}

static void publish_event(kd_io *io, const kc_ctrl_event *e)
{
    int8_t ev = status_event_of(e->kind);
    kd_reject rej;
    if (e->kind == KC_EVENT_REJECTED || e->kind == KC_EVENT_ABORTED || e->kind == KC_EVENT_FAULT ||
        e->reason != KC_REASON_NONE) {
        if (e->kind == KC_EVENT_REJECTED)
            io->rejections++;
        if (e->kind == KC_EVENT_ABORTED && e->reason == KC_REASON_NONE) {
            kd_reject_set(&rej, io->stop_reason, "%s", io->stop_text);
        } else if (e->reason == KC_REASON_EXTERNAL) {
            kd_reject_set(&rej, io->ext_reason, "%s", io->ext_text);
        } else if (e->reason == KC_REASON_ZONE) {
            char pair[256];
            kd_config_zone_pair(io->cfg, e->zone, e->volume, pair, sizeof pair);
            kd_reject_set(&rej, e->reason, "%s: %s (at %.6g)", kc_ctrl_reason_str(e->reason), pair, (double)e->where);
        } else if (e->kind == KC_EVENT_FAULT || e->reason == KC_REASON_TRACKING)
            kd_reject_set(&rej, e->reason, "%s (at %.6g)", kc_ctrl_reason_str(e->reason), (double)e->where);
        else
            kd_reject_set(&rej, e->reason, "%s", kc_ctrl_reason_str(e->reason));
        if (e->reason == KC_REASON_NONE && e->kind != KC_EVENT_ABORTED)
            rej.code = KC_OK;
        publish_status(io, ev, e->goal_id, rej.code, rej.text);
    } else {
        publish_status(io, ev, e->goal_id, KC_OK, "");
    }
}

static void drain_ticks(kd_io *io)
{
    const kd_tick *t;
    int64_t step_errors;
    while ((t = kd_spsc_slot_read(&io->cycle->ticks)) != NULL) {
        int i;
        memcpy(&io->last, t, sizeof *t);
        io->have_last = 1;
        kd_spsc_release(&io->cycle->ticks);
        t = &io->last;
        publish_setpoint(io, t);
        if (io->seat_pending && t->cmds_taken >= io->seat_seq) {
            io->seat_pending = 0;
            kd_master_seated(&io->master, t->seat_status, t->seat_joint, kd_now_ns());
        }
        if (t->policy_cmd != KC_CMD_NONE) {
            kd_reject rej;
            char what[96];
            (void)snprintf(what, sizeof what, "%lld consecutive missed cycles: %s sent", (long long)t->policy_missed,
                           t->policy_cmd == KC_CMD_ESTOP ? "ESTOP" : "STOP");
            kd_reject_set(&rej, KD_REASON_OVERRUN, "%s", what);
            fprintf(stderr, "kinctld: %s\n", rej.text);
            publish_status(io, KINCTL_STATUS_T_NONE, t->out.goal_id, rej.code, rej.text);
            stop_cause(io, KD_REASON_OVERRUN, what);
        }
        for (i = 0; i < t->out.n_events && i < KC_CTRL_EVENTS_MAX; i++)
            publish_event(io, &t->out.events[i]);
        /* The dry runs learn where the queue ends (from the goals they
         * judged: servo messages pass them by). */
        kd_checker_tick(&io->checker, &t->out, t->goals_taken - t->servo_taken);
    }
    step_errors = atomic_load_explicit(&io->cycle->step_errors, memory_order_relaxed);
    if (step_errors != io->step_errors_seen) {
        fprintf(stderr, "kinctld: error: kc_ctrl_step refused %lld tick(s); no setpoint for them\n",
                (long long)(step_errors - io->step_errors_seen));
        io->step_errors_seen = step_errors;
    }
}

/* ---- messages in ------------------------------------------------------- */

/* Goals handed to the cycle and not yet taken: the controller answers
 * them when it takes them, so nothing behind them is answered before. */
static int goals_in_flight(const kd_io *io)
{
    return io->goals_pushed > (io->have_last ? io->last.goals_taken : 0);
}

/* A goal refused here, answered in its turn: behind the goals still in
 * their dry runs or on their way to the controller (checker.h). */
static void refuse(kd_io *io, int64_t goal_id, const kd_reject *rej)
{
    if (kd_checker_refuse(&io->checker, goal_id, rej, goals_in_flight(io)) == 1)
        reject(io, goal_id, rej);
}

/* The answers that are ready, in arrival order: a goal the checker took
 * goes to the cycle (the controller answers ACCEPTED when it takes it), one
 * it refused, or stopped for its budget, is answered here. When the goal
 * ring is full the goal waits, and every one behind it, for the next pass:
 * the cycle takes one a tick; so does a refusal while goals before it are
 * still on their way to the controller. final: the cycle has stopped, and
 * nothing will take a goal again. */
static void answer_goals(kd_io *io, int final)
{
    kd_answer a;
    while (kd_checker_answer(&io->checker, &a)) {
        const kd_job *j = a.job;
        kd_reject rej;
        int taken = (a.servo != NULL || (j != NULL && j->end == KD_JOB_JUDGED && j->verdict.status == KC_OK)) && !final;
        if (!taken && !final && goals_in_flight(io))
            return; /* a refusal waits for the goals before it to be answered */
        if (a.servo != NULL && taken) {
            if (kd_spsc_push(&io->cycle->goals, a.servo) != 0)
                return;
            io->goals_pushed++;
            io->servo_id = a.servo->id;
        } else if (a.servo != NULL) {
            kd_reject_set(&rej, KD_REASON_SHUTDOWN, "kinctld exiting before the goal reached the controller");
            reject(io, a.goal_id, &rej);
        } else if (j == NULL) {
            reject(io, a.goal_id, &a.rej);
        } else if (taken) {
            if (kd_spsc_push(&io->cycle->goals, &j->goal) != 0)
                return;
            io->goals_pushed++;
        } else {
            if (j->end == KD_JOB_OVER_BUDGET)
                kd_reject_budget(&rej, io->cfg, j->elapsed_ns, j->ticks, j->progress);
            else if (j->end == KD_JOB_STOPPED || j->verdict.status == KC_OK)
                kd_reject_set(&rej, KD_REASON_SHUTDOWN, "kinctld exiting before the goal reached the controller");
            else if (j->verdict.reason == KD_REASON_JERK)
                kd_reject_jerk(&rej, io->cfg, (double)j->verdict.jerk, j->slowed, j->goal.stop_first, j->cut);
            else
                kd_reject_verdict(&rej, io->cfg, &j->goal, &j->verdict);
            reject(io, a.goal_id, &rej);
        }
        kd_checker_answered(&io->checker);
    }
}

/* A servo message streams past the dry runs: the cheap checks (the core's
 * kc_ctrl_goal_check) and on to the cycle, in its turn. A stream already
 * handed on goes straight (its messages update it: it must not go stale
 * behind a long dry run); a new one waits for the goals sent before it
 * that are in their dry runs (kd_checker_servo), or goes straight. */
static void handle_servo(kd_io *io, const kc_goal *g, int64_t received_ns, int64_t servo_timeout_ns)
{
    kc_verdict v;
    kd_reject rej;
    if (kc_ctrl_goal_check(&io->cfg->chain, g, &v) != KC_OK) {
        kd_reject_verdict(&rej, io->cfg, g, &v);
        reject(io, g->id, &rej);
        return;
    }
    /* The staleness clock starts at receipt, before the cycle sees it. */
    atomic_store_explicit(&io->cycle->servo_deadline_ns, received_ns + servo_timeout_ns, memory_order_release);
    int waits = g->id == io->servo_id ? 0 : kd_checker_servo(&io->checker, g);
    if (waits > 0)
        return;
    if (waits < 0 || kd_spsc_push(&io->cycle->goals, g) != 0) {
        io->msgs_dropped++;
        kd_reject_set(&rej, KC_REASON_QUEUE_FULL, "the daemon's goal queue (%d goals) is full", io->cfg->queue_size);
        reject(io, g->id, &rej);
        return;
    }
    io->goals_pushed++;
    io->servo_id = g->id;
}

/* With drives on CAN, goals wait for every drive to be enabled: 1 with
 * rej set when they are not. */
static int drives_refuse(const kd_io *io, kd_reject *rej)
{
    const kd_master *m = &io->master;
    if (m->drives == KD_DRIVES_NONE || m->drives == KD_DRIVES_ENABLED)
        return 0;
    kd_reject_set(rej, KD_REASON_DRIVE, "drives not enabled (%s: %s)", kd_master_drives_str(m->drives), m->text);
    return 1;
}

static void handle_goal(kd_io *io, kd_msg_type type, int64_t received_ns)
{
    kc_goal *g = &io->goal;
    kc_verdict v;
    kd_reject rej;
    int64_t servo_timeout_ns = 0;

    /* Converted here; judged once, by the core, on the checker thread: from
     * where the goal will start, with the queue's room, tick by tick of its
     * motion. */
    if (kd_goal_from_msg(type, &io->msg, io->cfg->servo_timeout_s, g, &servo_timeout_ns, &v) != 0) {
        kd_reject_verdict(&rej, io->cfg, g, &v);
        refuse(io, g->id, &rej);
        return;
    }
    if (drives_refuse(io, &rej)) {
        if (g->kind == KC_GOAL_SERVO)
            reject(io, g->id, &rej);
        else
            refuse(io, g->id, &rej);
        return;
    }
    if (g->kind == KC_GOAL_SERVO) {
        handle_servo(io, g, received_ns, servo_timeout_ns);
        return;
    }
    if (kd_checker_submit(&io->checker, g) != 0) {
        io->msgs_dropped++;
        if (kd_checker_refuse(&io->checker, g->id, NULL, goals_in_flight(io)) == 1) {
            kd_checker_busy(&rej);
            reject(io, g->id, &rej);
        }
    }
}

static void push_command(kd_io *io, kc_ctrl_command command)
{
    kd_cmd c;
    memset(&c, 0, sizeof c);
    c.command = command;
    if (kd_spsc_push(&io->cycle->cmds, &c) != 0) {
        io->msgs_dropped++;
        fprintf(stderr, "kinctld: warning: command ring full, command %d dropped\n", (int)command);
        return;
    }
    io->cmds_pushed++;
    /* What ended an aborted goal; the drives follow: quick stop on ESTOP,
     * enabled again on RESET. */
    if (command == KC_CMD_STOP) {
        stop_cause(io, KD_REASON_STOPPED, "a STOP command ended it");
    } else if (command == KC_CMD_ESTOP) {
        stop_cause(io, KD_REASON_STOPPED, "an ESTOP command ended it");
        kd_master_estop(&io->master, kd_now_ns());
    } else if (command == KC_CMD_RESET) {
        kd_master_reset(&io->master, kd_now_ns());
    }
}

/* The controller seated where the drives are, before the step of the
 * tick that takes it. */
static void push_seat(kd_io *io, const kc_real *q)
{
    kd_cmd c;
    memset(&c, 0, sizeof c);
    c.seat = 1;
    memcpy(c.q, q, sizeof(kc_real) * (size_t)io->cfg->chain.n_joints);
    if (kd_spsc_push(&io->cycle->cmds, &c) != 0) {
        kd_master_seated(&io->master, KC_E_STATE, -1, kd_now_ns()); /* asked again later */
        return;
    }
    io->cmds_pushed++;
    io->seat_pending = 1;
    io->seat_seq = io->cmds_pushed;
}

/* One client datagram's payload on the channel of type. */
static void on_message(kd_io *io, kd_msg_type type, const void *data, size_t len)
{
    int64_t received_ns = kd_now_ns();
    char why[KD_MSG_REASON_SIZE];
    kd_msg_status ms;

    io->msgs_in++;
    ms = kd_msg_decode(type, data, len, &io->msg, why, sizeof why);
    if (ms != KD_MSG_OK) {
        kd_msg_type named;
        int64_t id = 0;
        io->msgs_invalid++;
        if (-(int)ms >= 0 && -(int)ms < KD_INVALID_KINDS)
            io->invalid_by[-(int)ms]++;
        /* Answer only when the datagram is a kinctl goal (whatever is wrong
         * with it): a goal_id read from garbage would be noise. */
        if (kd_msg_identify(data, len, &named) == KD_MSG_OK && named <= KD_MSG_GOAL_SERVO)
            id = kd_msg_goal_id(named, data, len);
        if (id != 0) {
            kd_reject rej;
            kd_reject_set(&rej, KC_REASON_BAD_GOAL, "%s on %s: %s", kd_msg_status_str(ms), io->channel[type], why);
            refuse(io, id, &rej);
        }
        return;
    }
    if (type == KD_MSG_COMMAND)
        push_command(io, (kc_ctrl_command)io->msg.command.command);
    else
        handle_goal(io, type, received_ns);
}

/* ---- CAN --------------------------------------------------------------- */

#define KD_CAN_RX_BURST 1024 /* CAN frames read per pass */

static void raise_condition(kd_io *io);

/* Frames in (the link's feedback, the master's answers), timers, a lost
 * or recovered bus told in a status, a drive or bus condition raised as
 * the controller's external fault, the drives' master a step on, and what
 * it has to tell. */
static void can_step(kd_io *io)
{
    kd_can *c = &io->can;
    struct can_frame f;
    int64_t now;
    kd_reject rej;
    kc_real q_seat[KC_MAX_JOINTS];
    const char *news;
    int k;
    if (c->state == KD_CAN_OFF)
        return;
    now = kd_now_ns();
    for (k = 0; k < KD_CAN_RX_BURST && kd_can_read(c, &f, now); k++)
        kd_master_rx(&io->master, &f, now);
    kd_can_timers(c, now);
    if (kd_master_seat_wanted(&io->master, q_seat))
        push_seat(io, q_seat);
    if (c->state_changed) {
        c->state_changed = 0;
        if (c->state == KD_CAN_LOST)
            kd_reject_set(&rej, KD_REASON_CAN, "%s (%s)", c->lost_text,
                          io->cfg->can.on_error_stop ? "on_error = stop: the arm stops" : "on_error = lcm_only");
        else
            kd_reject_set(&rej, KD_REASON_CAN, "%s is back: CAN output resumed", io->cfg->can.interface);
        fprintf(stderr, "kinctld: %s\n", rej.text);
        publish_status(io, KINCTL_STATUS_T_NONE, 0, KC_OK, rej.text);
    }
    if (!io->have_last)
        return;
    /* A condition is raised before the master takes it as its own (the
     * arm stops on its path's joints, the drives hold or stop). */
    raise_condition(io);
    kd_master_step(&io->master, now);
    if (kd_master_take_news(&io->master, &news)) {
        kd_reject_set(&rej, KD_REASON_DRIVE, "%s", news);
        fprintf(stderr, "kinctld: %s\n", rej.text);
        publish_status(io, KINCTL_STATUS_T_NONE, 0, rej.code, rej.text);
    }
}

/* A drive or bus condition as the controller's external fault: raised
 * once; raised again when the controller has left FAULT (RESET) while the
 * condition lasts. */
static void raise_condition(kd_io *io)
{
    kd_can *c = &io->can;
    kc_ctrl_state s = io->last.out.state;
    if (io->ext_raised && io->last.out.cycle > io->ext_raised_cycle + 1 && s != KC_CTRL_FAULT &&
        s != KC_CTRL_ESTOP && s != KC_CTRL_STOPPING)
        io->ext_raised = 0;
    if (kd_can_condition(c) != KD_CAN_COND_NONE && !io->ext_raised && s != KC_CTRL_FAULT && s != KC_CTRL_ESTOP) {
        io->ext_reason = kd_can_condition(c) == KD_CAN_COND_BUS ? KD_REASON_CAN : KD_REASON_DRIVE;
        snprintf(io->ext_text, sizeof io->ext_text, "%s", c->condition_text);
        io->ext_raised = 1;
        io->ext_raised_cycle = io->last.out.cycle;
        atomic_store_explicit(&io->cycle->ext_fault, (int)KC_REASON_EXTERNAL, memory_order_release);
        fprintf(stderr, "kinctld: %s: %s: stopping the arm\n", kd_reason_token(io->ext_reason), io->ext_text);
    }
}

/* ---- the thread -------------------------------------------------------- */

static void shutdown_step(kd_io *io)
{
    if (!atomic_load(&io->stop_request))
        return;
    if (!io->stop_sent) {
        kd_cmd c;
        memset(&c, 0, sizeof c);
        c.command = KC_CMD_STOP;
        if (kd_spsc_push(&io->cycle->cmds, &c) == 0) {
            io->cmds_pushed++;
            stop_cause(io, KD_REASON_SHUTDOWN, "kinctld exiting: the arm stopped");
            io->stop_sent = 1;
            io->stop_seq = io->cmds_pushed;
        }
        return;
    }
    if (io->have_last && io->last.cmds_taken >= io->stop_seq) {
        kc_ctrl_state s = io->last.out.state;
        /* At rest: the drives are disabled, then NMT (can_master.h). */
        if (s == KC_CTRL_IDLE || s == KC_CTRL_FAULT || s == KC_CTRL_ESTOP) {
            kd_master_shutdown(&io->master, kd_now_ns());
            if (kd_master_shutdown_done(&io->master))
                atomic_store(&io->stop_done, 1);
        }
    }
}

static void timers(kd_io *io)
{
    int64_t now = kd_now_ns();
    kd_cycle_stats cs;
    if (now >= io->next_status_ns) {
        publish_status(io, KINCTL_STATUS_T_NONE, 0, KC_OK, "");
        io->next_status_ns += io->status_period_ns;
        if (io->next_status_ns <= now)
            io->next_status_ns = now + io->status_period_ns;
    }
    if (now >= io->next_stats_ns) {
        io->stats_due = 1;
        io->next_stats_ns += io->stats_period_ns;
        if (io->next_stats_ns <= now)
            io->next_stats_ns = now + io->stats_period_ns;
    }
    if (io->stats_due && kd_cycle_stats_take(io->cycle, &cs)) {
        io->stats_due = 0;
        publish_stats(io, &cs);
    }
}

/* Reads one datagram and handles it when it is on a client channel of
 * ours. Returns 0 when none was waiting (or the one read was refused: the
 * next poll finds the rest). Everything else on the group (our
 * own setpoints, status and stats looped back, other arms' channels) is
 * passed over uncounted. */
static int receive_one(kd_io *io)
{
    const char *channel;
    const void *payload;
    size_t len;
    int t, r = kd_rx_read(&io->rx, &channel, &payload, &len);
    if (r < 0) {
        io->rx_errors++;
        return 0;
    }
    if (r == 0)
        return 0;
    for (t = 0; t < KD_MSG_TYPE_COUNT; t++)
        if (kd_msg_type_info((kd_msg_type)t)->from_client && strcmp(channel, io->channel[t]) == 0) {
            on_message(io, (kd_msg_type)t, payload, len);
            break;
        }
    return 1;
}

static void *io_main(void *arg)
{
    kd_io *io = arg;
    struct pollfd pfd[2];
    struct timespec wait;
    int64_t now = kd_now_ns();
    kd_cycle_stats cs;

    prctl(PR_SET_NAME, "kinctld-io");
    pfd[0].fd = kd_rx_fd(&io->rx);
    pfd[0].events = POLLIN;
    pfd[1].fd = kd_checker_done_fd(&io->checker);
    pfd[1].events = POLLIN;
    wait.tv_sec = (time_t)(io->cfg->period_ns / KD_NS);
    wait.tv_nsec = (long)(io->cfg->period_ns % KD_NS);
    io->next_status_ns = now + io->status_period_ns;
    io->next_stats_ns = now + io->stats_period_ns;
    kd_master_start(&io->master, now);
    while (atomic_load(&io->run)) {
        int burst;
        drain_ticks(io);
        answer_goals(io, 0);
        can_step(io);
        shutdown_step(io);
        timers(io);
        pfd[0].revents = pfd[1].revents = 0;
        if (ppoll(pfd, 2, &wait, NULL) <= 0)
            continue;
        if (pfd[1].revents & POLLIN) {
            uint64_t n;
            ssize_t r = read(pfd[1].fd, &n, sizeof n);
            (void)r;
        }
        for (burst = 0; burst < KD_HANDLE_BURST && (pfd[0].revents & POLLIN); burst++) {
            if (!receive_one(io))
                break;
            drain_ticks(io);
        }
    }
    /* The cycle has stopped: publish what it left, answer every goal still
     * waiting (in order, as refused: nothing takes a goal now), then the
     * last word. */
    drain_ticks(io);
    kd_checker_stop(&io->checker);
    answer_goals(io, 1);
    {
        kd_reject rej;
        kd_reject_set(&rej, KD_REASON_SHUTDOWN, "kinctld exiting (%s)",
                      atomic_load(&io->stop_done) ? "arm at rest" : "stop timed out");
        publish_status(io, KINCTL_STATUS_T_NONE, 0, KC_OK, rej.text);
    }
    /* Final stats (the cycle is gone: the take swaps itself). Two calls,
     * each with effects: the second completes a take the first left pending. */
    if (kd_cycle_stats_take(io->cycle, &cs) || kd_cycle_stats_take(io->cycle, &cs)) /* NOLINT(misc-redundant-expression) */
        publish_stats(io, &cs);
    return NULL;
}


int kd_io_init(kd_io *io, const kd_config *cfg, kd_cycle *cycle, kc_check *check)
{
    struct timespec rt, mono;
    int t, n = cfg->chain.n_joints;
    memset(io, 0, sizeof *io);
    io->cfg = cfg;
    io->cycle = cycle;
    io->check = check;
    stop_cause(io, KD_REASON_STOPPED, "a STOP or ESTOP ended it");
    kd_msg_init();
    clock_gettime(CLOCK_REALTIME, &rt);
    clock_gettime(CLOCK_MONOTONIC, &mono);
    io->realtime_offset_ns = ((int64_t)rt.tv_sec - (int64_t)mono.tv_sec) * KD_NS + (rt.tv_nsec - mono.tv_nsec);
    /* The dry run steps the motion at the cycle's period: it is then the
     * controller's own run, tick for tick (a joint's jerk above all, which
     * the IK step's scaling makes of a Cartesian goal's law differently at
     * another period: at 4 ms, 11 of 788 random Panda lines and arcs taken
     * went over qddd_max at 1 ms). About 0.6 us a tick for a PUMA 560's
     * line, 0.8 for a Panda's (x86, -O2): a 120 s motion in about 100 ms of
     * the 500 ms budget. */
    io->check_cfg = cfg->ctrl;
    if (kc_check_init(check, &cfg->chain, &io->check_cfg, (int64_t)(cfg->check_max_s / (double)io->check_cfg.dt) + 1,
                      cfg->home) != KC_OK) {
        fprintf(stderr, "kinctld: the goals' dry run refuses the configuration (period %.6g s)\n",
                (double)io->check_cfg.dt);
        return -1;
    }
    if (kd_checker_init(&io->checker, check, (int64_t)(cfg->check_budget_s * 1e9), cycle) != 0)
        return -1;
    io->status_period_ns = (int64_t)(1e9 / cfg->status_hz);
    io->stats_period_ns = (int64_t)(1e9 / cfg->stats_hz);
    atomic_init(&io->run, 0);
    atomic_init(&io->stop_request, 0);
    atomic_init(&io->stop_done, 0);

    /* Clients' messages come in through kd_rx (lcm_rx.h: never LCM's
     * receive path, whose fragment buffers take any size a datagram
     * claims), no longer than the largest type a client sends. */
    size_t client_max = 0;
    char why[256];
    for (t = 0; t < KD_MSG_TYPE_COUNT; t++) {
        const kd_msg_info *info = kd_msg_type_info((kd_msg_type)t);
        snprintf(io->channel[t], sizeof io->channel[t], "%s%s", cfg->prefix, info->channel);
        if (info->from_client && info->size > client_max)
            client_max = info->size;
    }
    io->rx.fd = -1;
    io->bus.fd = -1;
    if (cfg->can.enable && kd_bus_init(&io->bus, &cfg->can, n) != 0)
        return -1;
    if (kd_can_open(&io->can, &cfg->can, &io->bus, n, cfg->period_ns, kd_now_ns()) != 0) {
        kd_bus_close(&io->bus);
        return -1;
    }
    kd_master_init(&io->master, &io->can, &io->bus, &cfg->chain, cfg->period_ns);
    if (cfg->can.enable)
        cycle->bus = &io->bus;
    if (kd_rx_open(&io->rx, cfg->lcm_url, client_max, why, sizeof why) != 0) {
        kd_can_close(&io->can);
        kd_bus_close(&io->bus);
        fprintf(stderr, "kinctld: LCM URL \"%s\" (%s): %s\n", cfg->lcm_url, cfg->lcm_url_source, why);
        return -1;
    }
    /* LCM publishes only: no subscription, so it never opens a receive
     * socket of its own. */
    io->lcm = lcm_create(cfg->lcm_url);
    if (io->lcm == NULL) {
        kd_rx_close(&io->rx);
        kd_can_close(&io->can);
        kd_bus_close(&io->bus);
        fprintf(stderr, "kinctld: cannot open LCM on \"%s\" (%s): check the URL and the network (multicast route)\n",
                cfg->lcm_url, cfg->lcm_url_source);
        return -1;
    }
    return 0;
}

int kd_io_start(kd_io *io)
{
    int rc;
    if (kd_checker_start(&io->checker, io->cfg) != 0)
        return -1;
    atomic_store(&io->run, 1);
    rc = pthread_create(&io->thread, NULL, io_main, io);
    if (rc != 0) {
        atomic_store(&io->run, 0);
        kd_checker_stop(&io->checker);
        fprintf(stderr, "kinctld: cannot start the I/O thread: %s\n", strerror(rc));
        return -1;
    }
    io->thread_live = 1;
    kd_cycle_keep_off(io->cfg, io->thread, "I/O");
    return 0;
}

void kd_io_stop(kd_io *io)
{
    atomic_store(&io->run, 0);
    if (io->thread_live) {
        pthread_join(io->thread, NULL);
        io->thread_live = 0;
    }
}

void kd_io_destroy(kd_io *io)
{
    kd_checker_destroy(&io->checker);
    kd_can_close(&io->can);
    kd_bus_close(&io->bus);
    kd_rx_close(&io->rx);
    if (io->lcm != NULL)
        lcm_destroy(io->lcm);
    io->lcm = NULL;
}

void kd_io_summary(const kd_io *io, char *buf, int size)
{
    int k, o;
    if (size <= 0)
        return;
    o = snprintf(buf, (size_t)size,
                 "messages in %lld, out %lld, dropped %lld (setpoints %lld, events %lld), rejections %lld, invalid %lld",
                 (long long)io->msgs_in, (long long)io->msgs_out,
                 (long long)(io->msgs_dropped + atomic_load(&io->cycle->ticks_dropped) +
                             atomic_load(&io->cycle->events_dropped)),
                 (long long)atomic_load(&io->cycle->ticks_dropped), (long long)atomic_load(&io->cycle->events_dropped),
                 (long long)io->rejections, (long long)io->msgs_invalid);
    if (o > 0 && o < size)
        o += snprintf(buf + o, (size_t)(size - o),
                      ", dry runs %lld (over budget %lld, replacing goals from the moving state %lld, goals slowed or "
                      "stopping first for their joints' jerk %lld)",
                      (long long)atomic_load(&io->checker.judged), (long long)atomic_load(&io->checker.over_budget),
                      (long long)atomic_load(&io->checker.moving), (long long)atomic_load(&io->checker.slowed));
    if (o > 0 && o < size && atomic_load(&io->checker.jerk_refused) > 0)
        o += snprintf(buf + o, (size_t)(size - o), ", goals refused for their joints' jerk %lld",
                      (long long)atomic_load(&io->checker.jerk_refused));
    if (o > 0 && o < size && atomic_load(&io->checker.late) > 0)
        o += snprintf(buf + o, (size_t)(size - o), ", replacing goals judged again for a later cycle %lld",
                      (long long)atomic_load(&io->checker.late));
    if (o > 0 && o < size && io->checker.answered_early > 0)
        o += snprintf(buf + o, (size_t)(size - o), ", refusals answered out of order %lld",
                      (long long)io->checker.answered_early);
    if (o > 0 && o < size && (io->rx.refused > 0 || io->rx_errors > 0))
        o += snprintf(buf + o, (size_t)(size - o), ", datagrams refused by the receiver %lld, receive errors %lld",
                      (long long)io->rx.refused, (long long)io->rx_errors);
    for (k = 0; k < KD_INVALID_KINDS && o > 0 && o < size; k++)
        if (io->invalid_by[k] > 0)
            o += snprintf(buf + o, (size_t)(size - o), ", %s %lld", kd_msg_status_str((kd_msg_status)(-k)),
                          (long long)io->invalid_by[k]);
    if (io->can.state != KD_CAN_OFF && o > 0 && o < size) {
        int64_t frames, dropped, errors;
        kd_can_totals(&io->can, &frames, &dropped, &errors);
        snprintf(buf + o, (size_t)(size - o),
                 "; CAN %s: frames %lld, dropped %lld, errors %lld, error frames %lld, bus-off %lld, link down %lld, "
                 "received %lld; drives %s; per bus cycle p50 %lld ns, p99 %lld ns, max %lld ns over %lld",
                 io->cfg->can.interface, (long long)frames, (long long)dropped, (long long)errors,
                 (long long)io->can.error_frames, (long long)io->can.bus_off, (long long)io->can.link_down,
                 (long long)io->can.rx_frames, kd_master_drives_str(io->master.drives),
                 (long long)kd_hist_percentile(&io->bus.send_ns, 0.50),
                 (long long)kd_hist_percentile(&io->bus.send_ns, 0.99), (long long)io->bus.send_ns.max,
                 (long long)io->bus.send_ns.count);
    }
}
