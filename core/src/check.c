/* SPDX-License-Identifier: BSD-3-Clause */
/* check.c - the dry run of a goal and where the controller's queue ends
 * (kinctl/check.h). The goal runs through kc_ctrl_step on the check's own
 * controller: put back at rest at the start of a run (kc_ctrl_restart,
 * at the check's period), or, for a replacing goal, a copy of the real
 * controller (kc_check_snapshot, at its period) given the goal as the
 * cycle gives it: the same code as the cycle's. A run is set up
 * (begin_from, begin_moving) and then stepped (kc_check_run) at most so
 * many ticks a call, so the one loop serves the whole run and its
 * slices. */
#include "kinctl/check.h"

#include <string.h>

#include "ctrl_internal.h"

kc_status kc_check_init(kc_check *k, const kc_chain *chain, const kc_ctrl_cfg *cfg, int64_t max_ticks,
                        const kc_real *q0)
{
    if (k == NULL || chain == NULL || cfg == NULL || q0 == NULL || max_ticks < 1)
        return KC_E_ARG;
    if (kc_ctrl_init(&k->scratch, chain, cfg, q0) != KC_OK)
        return KC_E_ARG;
    k->chain = chain;
    k->cfg = *cfg;
    k->max_ticks = max_ticks;
    memset(k->q_now, 0, sizeof k->q_now);
    memcpy(k->q_now, q0, sizeof(kc_real) * (size_t)chain->n_joints);
    memcpy(k->q_end, k->q_now, sizeof k->q_end);
    memcpy(k->q_from, k->q_now, sizeof k->q_from);
    memcpy(k->q_start, k->q_now, sizeof k->q_start);
    k->last_id = 0;
    k->handed = 0;
    k->taken = 0;
    k->queue_length = 0;
    k->have_tick = 0;
    k->tick_cycle = 0;
    k->have_snapshot = 0;
    k->snap_cycle = 0;
    k->snap_taken = 0;
    k->run_tick = 0;
    k->run_max = max_ticks;
    k->run_progress = KC_R(0.0);
    k->running = 0;
    k->run_moving = 0;
    k->run_stop_first = 0;
    k->run_stop_free = 0;
    k->run_own = 0;
    k->lead = 0;
    return KC_OK;
}

/* Accepted, ending at q. */
static kc_status taken(kc_verdict *v, const kc_real *q, int n)
{
    memcpy(v->q_end, q, sizeof(kc_real) * (size_t)n);
    v->status = KC_OK;
    v->reason = KC_REASON_NONE;
    return KC_OK;
}

/* The first event of the run that ends it: its verdict, or 0 when the run
 * goes on. The events are the goal's, and a fault of any goal (from a
 * snapshot, the replaced motion's stop may fault before the goal starts);
 * the replaced goals' own ends are not the goal's. */
static int judged(kc_check *k, const kc_ctrl_event *ev, int64_t tick, kc_verdict *v)
{
    int n = k->chain->n_joints;
    if (ev->goal_id != k->run_goal.id && ev->kind != KC_EVENT_FAULT)
        return 0;
    if (ev->kind == KC_EVENT_COMPLETED) { /* run_stop_first: jerk_of, stepped first */
        taken(v, k->scratch.q, n);
        if (k->run_stop_first)
            v->reason = KC_REASON_STOP_FIRST;
        v->tick = tick;
        return 1;
    }
    if (ev->kind != KC_EVENT_REJECTED && ev->kind != KC_EVENT_ABORTED && ev->kind != KC_EVENT_FAULT)
        return 0;
    v->status = ev->reason == KC_REASON_PLAN || ev->kind == KC_EVENT_REJECTED ? KC_E_ARG : KC_E_UNREACHABLE;
    /* The tool falling behind, in a dry run, is a motion the arm cannot
     * follow; an end with no reason, one the planner gave up on. */
    v->reason = ev->reason == KC_REASON_TRACKING ? KC_REASON_UNREACHABLE : ev->reason;
    if (v->reason == KC_REASON_NONE)
        v->reason = KC_REASON_PLAN;
    v->tick = tick;
    v->where = ev->where;
    v->zone = ev->zone;
    v->volume = ev->volume;
    if (ev->reason == KC_REASON_ZONE)
        v->distance = k->scratch.zone_hit.distance;
    return 1;
}

/* The run of k->run_goal set up for kc_check_run, judging motions of at
 * most max_ticks ticks. */
static kc_status run_set(kc_check *k, int64_t max_ticks)
{
    k->run_in.goal = &k->run_goal;
    k->run_in.command = KC_CMD_NONE;
    k->run_in.servo_stale = 0;
    k->run_in.fault = KC_REASON_NONE;
    k->run_tick = 0;
    k->run_max = max_ticks;
    k->run_progress = KC_R(0.0);
    memcpy(k->run_qdd, k->scratch.qdd, sizeof k->run_qdd);
    k->run_jerk = KC_R(0.0);
    k->run_qu = KC_R(0.0);
    k->run_own = !k->run_moving || !k->run_stop_free;
    k->running = 1;
    return KC_MORE;
}

/* The dry run of goal from q_start as far as stepping its motion: the
 * verdict, or KC_MORE with the run set up (kc_check_run steps it). v is
 * initialised, k and goal are not NULL. */
static kc_status begin_from(kc_check *k, const kc_real *q_start, const kc_goal *goal, kc_verdict *v)
{
    if (q_start == NULL)
        return kc_ctrl_bad_goal(v);
    const kc_chain *chain = k->chain;
    int n = chain->n_joints;
    /* A start outside the position limits (an arm a stop carried past one)
     * is judged from where it is: the scratch controller is put at rest
     * inside, as far as its zone state goes, and then there. */
    kc_real inside[KC_MAX_JOINTS];
    for (int j = 0; j < n; j++) {
        if (!kc_isfinite(q_start[j]))
            return kc_ctrl_refuse(v, KC_REASON_BAD_GOAL, KC_FIELD_NONE, -1, j, KC_R(0.0));
        inside[j] = kc_clamp(q_start[j], chain->joints[j].limits.q_min, chain->joints[j].limits.q_max);
    }
    kc_ctrl *scratch = &k->scratch;
    /* The scratch may hold a snapshot: its configuration is the
     * controller's (the period above all); the check's is put back. */
    k->have_snapshot = 0;
    scratch->chain = chain;
    scratch->cfg = k->cfg;
    kc_ctrl_restart(scratch, inside, q_start);
    if (kc_ctrl_goal_check(chain, goal, v) != KC_OK)
        return KC_E_ARG;
    if (goal->kind == KC_GOAL_SERVO) /* a servo target is judged tick by tick as it moves */
        return taken(v, q_start, n);
    if (goal->kind == KC_GOAL_JOINT && !kc_ctrl_zones_on(scratch)) {
        /* A joint move is exactly its plan: the plan is the whole check
         * (with zones, its ticks are stepped like any other goal's). */
        if (kc_ctrl_plan_joint(scratch, goal, q_start, NULL, NULL, &scratch->plan.joint) != KC_OK)
            return kc_ctrl_refuse(v, KC_REASON_PLAN, KC_FIELD_NONE, -1, -1, KC_R(0.0));
        return taken(v, goal->q, n);
    }
    kc_ctrl_goal_copy(&k->run_goal, goal);
    k->run_goal.replace = 0;
    k->run_goal.take_cycle = 0;
    return run_set(k, k->max_ticks);
}

/* The lead, 0 where negative. */
static int64_t lead_of(const kc_check *k) { return k->lead > 0 ? k->lead : 0; }

/* The dry run of replacing goal g from the snapshot in the scratch: the
 * copy of the controller stepped k->lead ticks with no input, then given
 * the goal as the cycle gives it, scheduled for that tick and that state
 * (v->take_cycle, take_state), with nothing else, and stepped until the
 * goal ends. The longest motion judged is as long in seconds as at the
 * check's period. The goal is checked. */
static kc_status begin_moving(kc_check *k, const kc_goal *goal, kc_verdict *v)
{
    /* Ticks of the controller's period per tick of the check's, rounded
     * up, in integers (a float to int64 conversion needs double helpers
     * on a single-precision FPU). */
    kc_real per = -kc_floor(-k->cfg.dt / k->scratch.cfg.dt);
    int64_t ratio = per < KC_R(1.0) ? 1 : per > KC_R(1048576.0) ? 1048576 : (int64_t)(int32_t)per;
    k->have_snapshot = 0; /* stepped from now on: used up */
    k->run_moving = 1;
    k->run_stop_first = 0;
    k->run_goal.id = goal->id;
    k->run_in.goal = NULL;
    k->run_in.command = KC_CMD_NONE;
    k->run_in.servo_stale = 0;
    k->run_in.fault = KC_REASON_NONE;
    for (int64_t t = 0; t < lead_of(k); t++) {
        kc_ctrl_output out;
        if (kc_ctrl_step(&k->scratch, &k->run_in, &out) != KC_OK) /* not reached: the snapshot is initialised */
            return kc_ctrl_bad_goal(v);
        for (int e = 0; e < out.n_events; e++)
            if (judged(k, &out.events[e], 0, v)) /* the motion it replaces faulted before the goal's tick */
                return v->status;
    }
    memcpy(k->q_from, k->scratch.q, sizeof k->q_from);
    k->run_stop_free = k->scratch.active && !kc_ctrl_jerk_limited(&k->scratch, &k->scratch.goal);
    kc_ctrl_goal_copy(&k->run_goal, goal);
    k->run_goal.take_cycle = v->take_cycle = k->scratch.cycle + 1;
    k->run_goal.take_state = v->take_state = kc_ctrl_stamp(&k->scratch);
    return run_set(k, k->max_ticks > INT64_MAX / ratio ? INT64_MAX : k->max_ticks * ratio);
}

/* The joints' jerk at the tick just stepped, into the run's largest; a
 * goal that stops first a motion without a jerk-limited law is measured
 * from the tick it starts (kinctl/check.h). A goal superposed on the
 * replaced motion's stop joint by joint (jerk-limited halts from the last
 * setpoint, whatever that motion's law: kinctl/ctrl.h) owns the jerk from
 * its takeover on, as over a jerk-limited motion's stop. */
static void jerk_of(kc_check *k, const kc_ctrl_output *out)
{
    for (int e = 0; e < out->n_events; e++) {
        const kc_ctrl_event *ev = &out->events[e];
        if (ev->goal_id != k->run_goal.id)
            continue;
        if (ev->kind == KC_EVENT_ACCEPTED && ev->reason == KC_REASON_STOP_FIRST)
            k->run_stop_first = 1;
        if (ev->kind == KC_EVENT_ACCEPTED && ev->reason == KC_REASON_NONE && k->scratch.blend.on &&
            k->scratch.blend.stop_drive == KC_DRIVE_HALT)
            k->run_own = 1;
        if (ev->kind == KC_EVENT_STARTED && k->run_stop_first && k->run_stop_free) {
            k->run_jerk = KC_R(0.0);
            k->run_own = 1;
        }
    }
    const kc_chain *chain = k->chain;
    for (int j = 0; j < chain->n_joints; j++) {
        kc_real r = kc_fabs(out->qdd[j] - k->run_qdd[j]) / (chain->joints[j].limits.qddd_max * k->scratch.cfg.dt);
        if (r > k->run_jerk)
            k->run_jerk = r;
        k->run_qdd[j] = out->qdd[j];
    }
}

kc_status kc_check_run(kc_check *k, int64_t max_ticks, kc_verdict *v)
{
    if (k == NULL || v == NULL || !k->running || max_ticks < 1)
        return KC_E_ARG;
    kc_ctrl_output out;
    int64_t last = k->run_max - k->run_tick > max_ticks ? k->run_tick + max_ticks : k->run_max;
    while (k->run_tick < last) {
        int64_t tick = ++k->run_tick;
        if (kc_ctrl_step(&k->scratch, &k->run_in, &out) != KC_OK) { /* not reached: the scratch controller is initialised */
            k->running = 0;
            return kc_ctrl_bad_goal(v);
        }
        k->run_in.goal = NULL;
        k->run_progress = out.progress;
        jerk_of(k, &out);
        if (k->scratch.goal.id == k->run_goal.id)
            k->run_qu = kc_max(k->run_qu, kc_ctrl_rate_per_u(&k->scratch));
        for (int e = 0; e < out.n_events; e++)
            if (judged(k, &out.events[e], tick, v)) {
                k->running = 0;
                v->jerk = k->run_jerk;
                v->jerk_own = k->run_own;
                v->qu = k->run_qu;
                return v->status;
            }
    }
    if (k->run_tick < k->run_max)
        return KC_MORE;
    k->running = 0;
    v->jerk = k->run_jerk;
    v->jerk_own = k->run_own;
    v->qu = k->run_qu;
    v->status = KC_E_CAPACITY;
    v->reason = KC_REASON_PLAN;
    v->tick = k->run_max;
    return KC_E_CAPACITY;
}

kc_real kc_check_slowing(const kc_verdict *v)
{
    if (v == NULL || !(v->jerk > KC_R(1.0)) || !kc_isfinite(v->jerk))
        return KC_R(1.0);
    return kc_cbrt(KC_CHECK_JERK_MARGIN / v->jerk);
}

int kc_check_jerk_within(const kc_verdict *v)
{
    return v != NULL && v->jerk <= KC_R(1.0) + KC_CHECK_JERK_SLACK;
}

int kc_check_slow_start(kc_check_slow *ss, const kc_verdict *v)
{
    ss->s_ok = KC_R(0.0);
    ss->jerk_ok = KC_R(0.0);
    ss->s_over = KC_R(1.0);
    ss->jerk_best = v->jerk;
    ss->s_best = KC_R(1.0);
    ss->s = kc_check_jerk_within(v) ? KC_R(0.0) : kc_check_slowing(v);
    return ss->s > KC_R(0.0);
}

int kc_check_slow_next(kc_check_slow *ss, const kc_verdict *v)
{
    kc_real s = ss->s, s_before = ss->s_best, jerk_before = ss->jerk_best;
    int best;
    if (kc_check_jerk_within(v)) {
        best = s > ss->s_ok;
        if (best) {
            ss->s_ok = s;
            ss->jerk_ok = v->jerk;
        }
    } else {
        best = ss->s_ok == KC_R(0.0) && v->jerk < ss->jerk_best;
        if (best) {
            ss->jerk_best = v->jerk;
            ss->s_best = s;
        }
        ss->s_over = kc_min(ss->s_over, s);
    }
    if (ss->s_ok == KC_R(0.0)) {
        /* Slowed without lowering the jerk: where it is the same as the
         * least judged (rounding apart), what exceeds the limits is not
         * the law's (a replaced trapezoid's stop, a joint path's own law).
         * Where it is more, an acceleration step fell on the ticks less
         * kindly (its jerk goes as s^2 times a factor of where it falls):
         * slowed again from this verdict by the square root. */
        if (!best) {
            int law = v->jerk > jerk_before * (KC_R(1.0) + KC_CHECK_JERK_SLACK);
            ss->s = law ? s * kc_sqrt(KC_CHECK_JERK_MARGIN / v->jerk) : KC_R(0.0);
            return 0;
        }
        /* The jerk came down about as s^2 since the share before (between
         * s^1.5 and s^2.5: an acceleration step, a cubic spline's start):
         * the square root. */
        kc_real r = s_before / s, fell = jerk_before / v->jerk;
        int step = fell > r * kc_sqrt(r) && fell < r * r * kc_sqrt(r);
        ss->s = step ? s * kc_sqrt(KC_CHECK_JERK_MARGIN / v->jerk) : s * kc_check_slowing(v);
        return 1;
    }
    /* Where the verdict within says the law has room: its cube root, kept
     * inside the bracket. */
    kc_real est = ss->s_ok * kc_cbrt(KC_CHECK_JERK_MARGIN / kc_max(ss->jerk_ok, KC_REAL_EPS));
    if (ss->s_over <= ss->s_ok * KC_CHECK_SLOW_CLOSE || est <= ss->s_ok * KC_CHECK_SLOW_CLOSE)
        ss->s = KC_R(0.0);
    else
        ss->s = est < ss->s_over ? est : kc_sqrt(ss->s_ok * ss->s_over);
    return best;
}

/* A run begun, stepped to its end. */
static kc_status run_all(kc_check *k, kc_status st, kc_verdict *v)
{
    return st == KC_MORE ? kc_check_run(k, k->run_max, v) : st;
}

/* A judgement's opening: the verdict cleared, the arguments checked, no
 * run under way. KC_OK, or the status to return (the verdict refusing). */
static kc_status opening(kc_check *k, const kc_goal *goal, kc_verdict *v)
{
    if (v == NULL)
        return KC_E_ARG;
    kc_ctrl_verdict_init(v);
    if (k == NULL || k->chain == NULL || goal == NULL)
        return kc_ctrl_bad_goal(v);
    k->running = 0;
    k->run_moving = 0;
    k->run_stop_first = 0;
    k->run_stop_free = 0;
    k->run_own = 0;
    return KC_OK;
}

kc_status kc_check_from(kc_check *k, const kc_real *q_start, const kc_goal *goal, kc_verdict *v)
{
    kc_status st = opening(k, goal, v);
    return st != KC_OK ? st : run_all(k, begin_from(k, q_start, goal, v), v);
}

kc_status kc_check_goal(kc_check *k, const kc_goal *goal, kc_verdict *v)
{
    kc_status st = kc_check_begin(k, goal, v);
    return st == KC_MORE ? run_all(k, st, v) : st;
}

/* The snapshot held is the controller as the next goal finds it: the
 * controller can still take the goal in its tick (no tick fed since is as
 * new: the snapshot's cycle plus the lead), and every goal handed on had
 * reached it. */
int kc_check_snapshot_fresh(const kc_check *k)
{
    return k != NULL && k->have_snapshot && (!k->have_tick || k->tick_cycle <= k->snap_cycle + lead_of(k)) &&
           k->snap_taken == k->handed;
}

kc_status kc_check_begin(kc_check *k, const kc_goal *goal, kc_verdict *v)
{
    kc_status st = opening(k, goal, v);
    if (st != KC_OK)
        return st;
    int n = k->chain->n_joints;
    memcpy(k->q_from, goal->replace ? k->q_now : k->q_end, sizeof k->q_from);
    if (kc_ctrl_goal_check(k->chain, goal, v) != KC_OK)
        return KC_E_ARG;
    /* The controller's queue as the latest tick saw it, plus the goals on
     * their way to it: when that is full the goal is refused at once, with
     * no dry run, so a flood costs little a goal and every goal is still
     * answered. A servo message may update the active servo: no new goal. */
    if (!goal->replace && goal->kind != KC_GOAL_SERVO && k->have_tick &&
        (int64_t)k->queue_length + (k->handed - k->taken) >= KC_CTRL_QUEUE_MAX) {
        v->status = KC_E_CAPACITY;
        v->reason = KC_REASON_QUEUE_FULL;
        v->value = (kc_real)KC_CTRL_QUEUE_MAX;
        return KC_E_CAPACITY;
    }
    if (goal->kind == KC_GOAL_SERVO) /* it streams: the cheap checks only, and it ends where the arm is */
        return taken(v, k->q_now, n);
    if (goal->replace && kc_check_snapshot_fresh(k))
        return begin_moving(k, goal, v);
    return begin_from(k, k->q_from, goal, v);
}

kc_ctrl *kc_check_snapshot_slot(kc_check *k)
{
    if (k == NULL)
        return NULL;
    k->have_snapshot = 0; /* the caller writes into it */
    k->running = 0;
    return &k->scratch;
}

kc_status kc_check_snapshot(kc_check *k, const kc_ctrl *ctrl, int64_t goals_taken)
{
    if (k == NULL || k->chain == NULL)
        return KC_E_ARG;
    k->have_snapshot = 0;
    if (ctrl == NULL || ctrl->chain != k->chain || !(ctrl->cfg.dt > KC_R(0.0)))
        return KC_E_ARG;
    if (ctrl != &k->scratch)
        memcpy(&k->scratch, ctrl, sizeof k->scratch);
    k->running = 0;
    k->have_snapshot = 1;
    k->snap_cycle = k->scratch.cycle;
    k->snap_taken = goals_taken;
    return KC_OK;
}

void kc_check_handed(kc_check *k, const kc_goal *goal, const kc_verdict *v)
{
    if (k == NULL || goal == NULL || v == NULL)
        return;
    k->handed++;
    k->last_id = goal->id;
    memcpy(k->q_start, k->q_from, sizeof k->q_start);
    memcpy(k->q_end, v->q_end, sizeof k->q_end);
}

void kc_check_tick(kc_check *k, const kc_ctrl_output *out, int64_t goals_taken)
{
    if (k == NULL || out == NULL || k->chain == NULL)
        return;
    int n = k->chain->n_joints;
    /* The controller refused the goal last handed on: the next one starts
     * where that one would have. */
    for (int i = 0; i < out->n_events && i < KC_CTRL_EVENTS_MAX; i++) {
        if (out->events[i].kind == KC_EVENT_REJECTED && out->events[i].goal_id == k->last_id && k->last_id != 0) {
            memcpy(k->q_end, k->q_start, sizeof k->q_end);
            k->last_id = 0;
        }
    }
    k->have_tick = 1;
    k->tick_cycle = out->cycle;
    k->queue_length = out->queue_length;
    k->taken = goals_taken;
    memcpy(k->q_now, out->q, sizeof(kc_real) * (size_t)n);
    /* At rest with nothing queued or on its way: the next goal starts here. */
    if ((out->state == KC_CTRL_IDLE || out->state == KC_CTRL_FAULT || out->state == KC_CTRL_ESTOP) &&
        out->goal_id == 0 && out->queue_length == 0 && goals_taken == k->handed)
        memcpy(k->q_end, out->q, sizeof(kc_real) * (size_t)n);
}
