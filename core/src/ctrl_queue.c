/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl_queue.c - events, the goal queue, and a goal taken in a tick:
 * servo updates, refusals, queueing, preemption, the retarget of a joint
 * move and the takeover of a Cartesian one or of a joint path
 * (ctrl_blend.c) (kinctl/ctrl.h). */
#include "ctrl_internal.h"

#include <string.h>

void kc_ctrl_emit(kc_ctrl_output *out, kc_ctrl_event_kind kind, int64_t id, kc_ctrl_reason reason, kc_real where)
{
    if (out->n_events >= KC_CTRL_EVENTS_MAX)
        return; /* not reached: KC_CTRL_EVENTS_MAX bounds a tick's events (ctrl.h) */
    kc_ctrl_event *e = &out->events[out->n_events++];
    e->kind = kind;
    e->goal_id = id;
    e->reason = reason;
    e->where = where;
    e->zone = -1;
    e->volume = -1;
}

void kc_ctrl_emit_takeover(kc_ctrl_output *out, int64_t id, int64_t old_id)
{
    kc_ctrl_emit(out, KC_EVENT_ACCEPTED, id, KC_REASON_NONE, 0);
    kc_ctrl_emit(out, KC_EVENT_PREEMPTED, old_id, KC_REASON_NONE, 0);
    kc_ctrl_emit(out, KC_EVENT_STARTED, id, KC_REASON_NONE, 0);
}

void kc_ctrl_queue_clear(kc_ctrl *c, kc_ctrl_output *out)
{
    for (int i = 0; i < c->queue_len; i++)
        kc_ctrl_emit(out, KC_EVENT_PREEMPTED, c->queue[(c->queue_head + i) % KC_CTRL_QUEUE_MAX].id, KC_REASON_NONE, 0);
    c->queue_head = 0;
    c->queue_len = 0;
}

static void queue_push(kc_ctrl *c, const kc_goal *g)
{
    kc_ctrl_goal_copy(&c->queue[(c->queue_head + c->queue_len) % KC_CTRL_QUEUE_MAX], g);
    c->queue_len++;
}

/* Whether a goal of this id is active or queued. */
static int id_in_flight(const kc_ctrl *c, int64_t id)
{
    if (c->active && c->goal.id == id)
        return 1;
    for (int i = 0; i < c->queue_len; i++)
        if (c->queue[(c->queue_head + i) % KC_CTRL_QUEUE_MAX].id == id)
            return 1;
    return 0;
}

/* Plans joint move g from the current, possibly moving, state into
 * c->plan.retarget, one time-optimal profile a joint, when every profile
 * stays inside its joint's position limits: a joint moving away from its
 * target first brakes through zero at p0 + v0 |v0| / (2 |a1|) (the other
 * phases run monotonically between the current q and the target). Returns 1
 * when planned; on 0 the active segment is untouched and the preemption
 * falls back to the stop on the path. */
static int retarget(kc_ctrl *c, const kc_goal *g)
{
    kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS];
    kc_profile prof[KC_MAX_JOINTS];
    kc_ctrl_scaled_limits(c, g, vmax, amax);
    for (int j = 0; j < c->chain->n_joints; j++) {
        const kc_joint_limits *l = &c->chain->joints[j].limits;
        kc_profile *p = &prof[j];
        if (kc_profile_plan(p, c->q[j], c->qd[j], g->q[j], vmax[j], amax[j], c->cfg.dt) != KC_OK)
            return 0;
        if (p->v0 * p->vc < KC_R(0.0)) {
            kc_real turn = p->p0 + p->v0 * kc_fabs(p->v0) / (KC_R(2.0) * kc_fabs(p->a1));
            if (!(turn >= l->q_min && turn <= l->q_max))
                return 0;
        }
    }
    /* cppcheck-suppress uninitvar ; the loop above planned prof[0..n_joints) or returned */
    memcpy(c->plan.retarget, prof, sizeof(kc_profile) * (size_t)c->chain->n_joints);
    return 1;
}

/* Plans jerk-limited joint move g from the current state into
 * c->retarget_plan (kinctl/ctrl.h): every joint from its (q, qd, qdd) to
 * rest at its target, arriving together. Returns 1 when planned and every
 * joint's profile stays inside its position limits and within its
 * velocity and acceleration limits (kc_scurve_extent_of: the start may be
 * beyond the goal's scaled limits, and is brought back within them, but
 * nothing may go beyond the joint's own); on 0 the active segment is
 * untouched. */
static int retarget_jerk(kc_ctrl *c, const kc_goal *g)
{
    kc_interp_joint *p = &c->retarget_plan;
    kc_real slack = c->cfg.limit_slack;
    kc_scurve_extent e;
    if (kc_ctrl_plan_joint(c, g, c->q, c->qd, c->qdd, p) != KC_OK)
        return 0;
    if (p->sync == KC_INTERP_SYNC_PHASE)
        kc_scurve_extent_of(&p->su, &e); /* on the line: q = q0 + dq u */
    for (int j = 0; j < c->chain->n_joints; j++) {
        const kc_joint_limits *l = &c->chain->joints[j].limits;
        if (p->sync == KC_INTERP_SYNC_PHASE) {
            kc_real d = p->dq[j], a = p->q0[j] + d * e.p_min, b = p->q0[j] + d * e.p_max;
            if (!(kc_min(a, b) >= l->q_min && kc_max(a, b) <= l->q_max &&
                  kc_fabs(d) * e.v_max <= l->qd_max * (KC_R(1.0) + slack) &&
                  kc_fabs(d) * e.a_max <= l->qdd_max * (KC_R(1.0) + slack)))
                return 0;
            continue;
        }
        kc_scurve_extent_of(&p->sj[j], &e);
        if (!(e.p_min >= l->q_min && e.p_max <= l->q_max && e.v_max <= l->qd_max * (KC_R(1.0) + slack) &&
              e.a_max <= l->qdd_max * (KC_R(1.0) + slack)))
            return 0;
    }
    return 1;
}

/* Makes g, whose retarget is planned, the active segment from this tick. */
static void take_retarget(kc_ctrl *c, const kc_goal *g)
{
    kc_ctrl_goal_copy(&c->goal, g);
    if (kc_ctrl_goal_profile(c, g) == KC_PROFILE_JERK) {
        c->plan.joint = c->retarget_plan;
        c->drive = KC_DRIVE_NOMINAL;
    } else {
        c->drive = KC_DRIVE_RETARGET;
    }
    c->k0 = c->cycle - 1; /* tick 0 is the last setpoint, as for every segment */
    c->stop_intent = KC_CMD_NONE;
    c->settle = 0;
    c->path_length = KC_R(0.0);
    c->jstop = 0; /* a servo's stop in joint space gives way too */
    c->blend.on = 0; /* from the current state, whatever it was made of */
    c->blend.lax = 0;
    c->active = 1;
    c->state = KC_CTRL_MOVING;
}

/* FNV-1a, 32 bits, over n bytes, from h. */
static uint32_t fnv(uint32_t h, const void *bytes, size_t n)
{
    const unsigned char *b = bytes;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 16777619u;
    return h;
}

/* ... over the four bytes of x, least significant first. */
static uint32_t fnv_word(uint32_t h, uint32_t x)
{
    for (int i = 0; i < 4; i++, x >>= 8)
        h = (h ^ (x & 0xFFu)) * 16777619u;
    return h;
}

uint32_t kc_ctrl_stamp(const kc_ctrl *c)
{
    if (c == NULL || c->chain == NULL)
        return 0;
    size_t row = sizeof(kc_real) * (size_t)c->chain->n_joints;
    uint64_t active_id = c->active ? (uint64_t)c->goal.id : 0u;
    uint32_t h = fnv(2166136261u, c->q, row);
    h = fnv(h, c->qd, row);
    h = fnv(h, c->qdd, row);
    h = fnv_word(h, (uint32_t)c->state);
    h = fnv_word(h, (uint32_t)c->active);
    h = fnv_word(h, (uint32_t)c->queue_len);
    h = fnv_word(h, (uint32_t)active_id);
    return fnv_word(h, (uint32_t)(active_id >> 32));
}

/* A scheduled goal (kc_goal.take_cycle) in its tick and from the state it
 * was judged from. */
static int on_schedule(const kc_ctrl *c, const kc_goal *g)
{
    return g->take_cycle == 0 || (g->take_cycle == c->cycle && g->take_state == kc_ctrl_stamp(c));
}

/* The same pose, entry by entry (a servo message that repeats it). */
static int pose_same(const kc_pose *a, const kc_pose *b)
{
    for (int i = 0; i < 3; i++) {
        if (a->t.v[i] != b->t.v[i])
            return 0;
        for (int k = 0; k < 3; k++)
            if (a->R.m[i][k] != b->R.m[i][k])
                return 0;
    }
    return 1;
}

void kc_ctrl_take_goal(kc_ctrl *c, const kc_goal *g, kc_ctrl_output *out)
{
    kc_verdict v;
    kc_status st = kc_ctrl_goal_check(c->chain, g, &v);
    /* A servo update for the active servo goal moves its target; so does
     * one for a servo goal still waiting in the queue (a replacing servo
     * goal waits while the motion before it stops on its path): the
     * stream's messages are one goal, answered once. */
    if (g->kind == KC_GOAL_SERVO && st == KC_OK) {
        kc_goal *w = c->active && c->goal.kind == KC_GOAL_SERVO && g->id == c->goal.id ? &c->goal : NULL;
        for (int i = 0; i < c->queue_len && w == NULL; i++) {
            kc_goal *q = &c->queue[(c->queue_head + i) % KC_CTRL_QUEUE_MAX];
            w = q->kind == KC_GOAL_SERVO && q->id == g->id ? q : NULL;
        }
        if (w != NULL) {
            /* The active twist stream keeps its pose: the shaped target
             * a switch to poses goes on from. */
            int same = !w->servo_twist && pose_same(&w->pose, &g->pose);
            w->servo_twist = g->servo_twist;
            memcpy(w->twist, g->twist, sizeof g->twist);
            if (w != &c->goal || !g->servo_twist)
                w->pose = g->pose;
            if (w == &c->goal) {
                /* A shaped pose goes on from its state to a new pose
                 * (unless stopping or paused: it starts again from rest
                 * when it follows again); an unshaped one jumps to it. */
                if (kc_ctrl_servo_shaped(c)) {
                    int following = c->state == KC_CTRL_MOVING && !c->jstop && c->drive != KC_DRIVE_HALT;
                    if (following && !same)
                        kc_ctrl_servo_aim(c, c->cycle - 1);
                } else if (!g->servo_twist) {
                    kc_ctrl_servo_rest(c, c->cycle - 1);
                }
                c->servo_last = c->cycle;
            }
            return;
        }
    }
    if (c->state == KC_CTRL_FAULT || c->state == KC_CTRL_ESTOP || c->fault_reason != KC_REASON_NONE) {
        kc_ctrl_emit(out, KC_EVENT_REJECTED, g->id, KC_REASON_STATE, 0);
        return;
    }
    if (id_in_flight(c, g->id)) {
        /* Its answers could not be told from the other goal's. */
        kc_ctrl_emit(out, KC_EVENT_REJECTED, g->id, KC_REASON_DUPLICATE_ID, 0);
        return;
    }
    if (st != KC_OK) {
        kc_ctrl_emit(out, KC_EVENT_REJECTED, g->id, v.reason, 0);
        return;
    }
    if (!on_schedule(c, g)) {
        kc_ctrl_emit(out, KC_EVENT_REJECTED, g->id, KC_REASON_LATE, 0);
        return;
    }
    if (g->replace) {
        kc_ctrl_queue_clear(c, out);
        if (g->kind == KC_GOAL_JOINT && !g->stop_first && c->active &&
            (c->state == KC_CTRL_MOVING || c->state == KC_CTRL_STOPPING) &&
            (kc_ctrl_goal_profile(c, g) == KC_PROFILE_JERK ? retarget_jerk(c, g) : retarget(c, g))) {
            kc_ctrl_emit_takeover(out, g->id, c->goal.id);
            take_retarget(c, g);
            return;
        }
        if (!g->stop_first && (kc_ctrl_servo_take(c, g, out) || kc_ctrl_blend_take(c, g, out)))
            return;
        queue_push(c, g);
        /* Anything still moving stops first, and the answer says so. */
        kc_ctrl_emit(out, KC_EVENT_ACCEPTED, g->id,
                     c->active && (c->state == KC_CTRL_MOVING || c->state == KC_CTRL_STOPPING) ? KC_REASON_STOP_FIRST
                                                                                               : KC_REASON_NONE,
                     0);
        if (c->active && c->state == KC_CTRL_MOVING) {
            kc_ctrl_stop_on_path(c, INTENT_PREEMPT);
        } else if (c->active && c->state == KC_CTRL_STOPPING) {
            c->stop_intent = INTENT_PREEMPT;
        } else if (c->active && c->state == KC_CTRL_PAUSED) {
            /* Already at rest: the paused goal gives way at once. */
            kc_ctrl_emit(out, KC_EVENT_PREEMPTED, c->goal.id, KC_REASON_NONE, 0);
            c->active = 0;
            c->state = KC_CTRL_IDLE;
        }
        return;
    }
    if (c->queue_len >= KC_CTRL_QUEUE_MAX) {
        kc_ctrl_emit(out, KC_EVENT_REJECTED, g->id, KC_REASON_QUEUE_FULL, 0);
        return;
    }
    queue_push(c, g);
    kc_ctrl_emit(out, KC_EVENT_ACCEPTED, g->id, KC_REASON_NONE, 0);
}
