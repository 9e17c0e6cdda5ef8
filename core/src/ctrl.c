/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl.c - the controller: configuration, init, commands and the step
 * (the final limit check, the setpoint). Behaviour documented in
 * kinctl/ctrl.h; the rooms it calls are listed in ctrl_internal.h. */
#include "ctrl_internal.h"

#include <string.h>

kc_ctrl_cfg kc_ctrl_cfg_default(void)
{
    kc_ctrl_cfg c;
    c.dt = KC_R(0.001);
    c.cart_speed = KC_R(0.25);
    c.cart_accel = KC_R(0.5);
    c.cart_omega = KC_R(1.0);
    c.cart_alpha = KC_R(4.0);
    c.cart_jerk = KC_INTERP_JERK_PER_ACCEL * c.cart_accel;
    c.cart_angular_jerk = KC_INTERP_JERK_PER_ACCEL * c.cart_alpha;
    c.track_tol = KC_R(0.001);
#ifdef KC_REAL_FLOAT
    c.limit_slack = KC_R(1e-4);
#else
    c.limit_slack = KC_R(1e-6);
#endif
    c.servo_timeout_ticks = 100;
    c.profile = KC_PROFILE_JERK;
    c.zones = NULL;
    c.ik = kc_ik_cfg_default();
    /* Fed forward, the online law only has to remove what one tick leaves:
     * a gain of 100/s (k dt = 0.1) settles in tens of ms. */
    c.ik.gain_pos = KC_R(100.0);
    c.ik.gain_rot = KC_R(100.0);
#ifdef KC_REAL_FLOAT
    c.ik.tol_pos = KC_R(2e-5);
    c.ik.tol_rot = KC_R(2e-4);
#else
    c.ik.tol_pos = KC_R(1e-7);
    c.ik.tol_rot = KC_R(1e-7);
#endif
    return c;
}

static int positive(kc_real x) { return kc_isfinite(x) && x > KC_R(0.0); }

/* The first field cfg_check refuses, KC_CFG_FIELD_NONE when none; *joint
 * for a joint's limit. */
static kc_ctrl_cfg_field cfg_problem(const kc_ctrl_cfg *cfg, const kc_chain *chain, int *joint)
{
    *joint = -1;
    if (cfg == NULL || chain == NULL)
        return KC_CFG_FIELD_ARG;
    /* The positive numbers, in the order of their fields (KC_CFG_FIELD_DT
     * to KC_CFG_FIELD_TRACK_TOL). */
    const kc_real pos[8] = {cfg->dt,         cfg->cart_speed, cfg->cart_accel,        cfg->cart_omega,
                            cfg->cart_alpha, cfg->cart_jerk,  cfg->cart_angular_jerk, cfg->track_tol};
    for (int i = 0; i < 8; i++)
        if (!positive(pos[i]))
            return (kc_ctrl_cfg_field)(KC_CFG_FIELD_DT + i);
    if (!kc_isfinite(cfg->limit_slack) || cfg->limit_slack < KC_R(0.0))
        return KC_CFG_FIELD_LIMIT_SLACK;
    if (cfg->servo_timeout_ticks < 1)
        return KC_CFG_FIELD_SERVO_TIMEOUT;
    if (kc_ik_cfg_check(&cfg->ik, chain) != KC_OK)
        return KC_CFG_FIELD_IK;
    if (cfg->profile != KC_PROFILE_JERK && cfg->profile != KC_PROFILE_TRAPEZOID)
        return KC_CFG_FIELD_PROFILE;
    /* The controller commands velocities within every joint's limits: they
     * must be finite. */
    for (int j = 0; j < chain->n_joints; j++) {
        *joint = j;
        if (!kc_isfinite(chain->joints[j].limits.qd_max))
            return KC_CFG_FIELD_JOINT_QD_MAX;
        if (!kc_isfinite(chain->joints[j].limits.qdd_max))
            return KC_CFG_FIELD_JOINT_QDD_MAX;
    }
    *joint = -1;
    /* Zones: a goal is checked tick by tick, so no volume may travel as far
     * as the margin in one tick (see kinctl/zone.h). */
    if (cfg->zones != NULL && kc_zone_set_check(cfg->zones) != KC_OK)
        return KC_CFG_FIELD_ZONES;
    if (cfg->zones != NULL && cfg->zones->n_zones > 0 && chain->n_volumes > 0 &&
        !(cfg->zones->margin > kc_zone_tick_travel(chain, cfg->dt)))
        return KC_CFG_FIELD_ZONES_MARGIN;
    return KC_CFG_FIELD_NONE;
}

kc_status kc_ctrl_cfg_check_field(const kc_ctrl_cfg *cfg, const kc_chain *chain, kc_ctrl_cfg_field *field,
                                  int *joint)
{
    int j;
    kc_ctrl_cfg_field f = cfg_problem(cfg, chain, &j);
    if (field != NULL)
        *field = f;
    if (joint != NULL)
        *joint = j;
    return f == KC_CFG_FIELD_NONE ? KC_OK : KC_E_ARG;
}

kc_status kc_ctrl_cfg_check(const kc_ctrl_cfg *cfg, const kc_chain *chain)
{
    return kc_ctrl_cfg_check_field(cfg, chain, NULL, NULL);
}

kc_status kc_ctrl_init(kc_ctrl *c, const kc_chain *chain, const kc_ctrl_cfg *cfg, const kc_real *q0)
{
    if (c == NULL || chain == NULL || cfg == NULL || q0 == NULL || kc_chain_check(chain) != KC_OK ||
        kc_ctrl_cfg_check(cfg, chain) != KC_OK || kc_chain_check_q(chain, q0, NULL) != KC_OK)
        return KC_E_ARG;
    memset(c, 0, sizeof *c);
    c->chain = chain;
    c->cfg = *cfg;
    c->state = KC_CTRL_IDLE;
    for (int j = 0; j < chain->n_joints; j++)
        c->q[j] = q0[j];
    kc_fk_eval(chain, c->q, &c->pose);
    c->servo_cmd_cycle = c->servo_zone_cycle = INT64_MIN;
    kc_ctrl_zone_init(c);
    return KC_OK;
}

void kc_ctrl_restart(kc_ctrl *c, const kc_real *q_at, const kc_real *q)
{
    int n = c->chain->n_joints;
    c->state = KC_CTRL_IDLE;
    c->cycle = 0;
    memset(c->q, 0, sizeof c->q);
    memset(c->qd, 0, sizeof c->qd);
    memset(c->qdd, 0, sizeof c->qdd);
    memcpy(c->q, q_at, sizeof(kc_real) * (size_t)n);
    c->queue_head = 0;
    c->queue_len = 0;
    c->active = 0;
    memset(&c->goal, 0, sizeof c->goal);
    c->k0 = 0;
    c->drive = KC_DRIVE_NOMINAL;
    c->stop_intent = KC_CMD_NONE;
    c->resume_share = KC_R(1.0);
    c->stop_v0 = KC_R(0.0);
    c->stop_qu = KC_R(0.0);
    c->fault_reason = KC_REASON_NONE;
    c->path_length = KC_R(0.0);
    memset(&c->servo_target, 0, sizeof c->servo_target);
    c->servo_last = 0;
    memset(c->servo_v, 0, sizeof c->servo_v);
    memset(c->servo_a, 0, sizeof c->servo_a);
    c->servo_cmd_cycle = c->servo_zone_cycle = INT64_MIN;
    c->settle = 0;
    c->null_x = KC_R(0.0);
    c->null_cycle = -1;
    c->jstop = 0;
    c->jstop_k0 = 0;
    c->after_stop = KC_CTRL_IDLE;
    c->blend.on = 0;
    c->blend.lax = 0;
    kc_ctrl_zone_init(c);
    memcpy(c->q, q, sizeof(kc_real) * (size_t)n);
    kc_fk_eval(c->chain, c->q, &c->pose);
}

static int at_rest(const kc_ctrl *c)
{
    for (int j = 0; j < c->chain->n_joints; j++)
        if (c->qd[j] != KC_R(0.0))
            return 0;
    return 1;
}

kc_status kc_ctrl_seat(kc_ctrl *c, const kc_real *q, int *bad_joint)
{
    kc_status st;
    if (bad_joint != NULL)
        *bad_joint = -1;
    if (c == NULL || q == NULL)
        return KC_E_ARG;
    if (c->state != KC_CTRL_IDLE || !at_rest(c) || c->active || c->queue_len > 0 || c->jstop)
        return KC_E_STATE;
    st = kc_chain_check_q(c->chain, q, bad_joint);
    if (st != KC_OK)
        return st;
    for (int j = 0; j < c->chain->n_joints; j++) {
        c->q[j] = q[j];
        c->qd[j] = KC_R(0.0);
        c->qdd[j] = KC_R(0.0);
    }
    kc_fk_eval(c->chain, c->q, &c->pose);
    kc_ctrl_zone_init(c); /* the zones' distances from where the arm is */
    return KC_OK;
}

static void command(kc_ctrl *c, kc_ctrl_command cmd, kc_ctrl_output *out)
{
    switch (cmd) {
    case KC_CMD_NONE: return;
    case KC_CMD_ESTOP:
        if (c->state == KC_CTRL_ESTOP)
            return;
        kc_ctrl_queue_clear(c, out);
        /* A goal still active after a fault is stopping on its path and
         * was aborted with the fault. */
        if (c->active && c->fault_reason == KC_REASON_NONE)
            kc_ctrl_emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_NONE, 0);
        kc_ctrl_joint_stop(c, 0, KC_CTRL_ESTOP);
        c->state = KC_CTRL_ESTOP;
        return;
    case KC_CMD_RESET:
        if ((c->state == KC_CTRL_FAULT || c->state == KC_CTRL_ESTOP) && at_rest(c) && !c->jstop) {
            c->state = KC_CTRL_IDLE;
            c->fault_reason = KC_REASON_NONE;
        }
        return;
    case KC_CMD_STOP:
        if (c->state == KC_CTRL_FAULT || c->state == KC_CTRL_ESTOP)
            return;
        kc_ctrl_queue_clear(c, out);
        if (c->state == KC_CTRL_PAUSED) {
            kc_ctrl_emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_NONE, 0);
            c->active = 0;
            c->state = KC_CTRL_IDLE;
        } else if (c->active && c->state == KC_CTRL_MOVING) {
            kc_ctrl_stop_on_path(c, KC_CMD_STOP);
        } else if (c->state == KC_CTRL_STOPPING) {
            c->stop_intent = KC_CMD_STOP; /* whatever the stop was for, it now ends the goal */
        }
        return;
    case KC_CMD_PAUSE:
        if (c->active && c->state == KC_CTRL_MOVING)
            kc_ctrl_stop_on_path(c, KC_CMD_PAUSE);
        return;
    case KC_CMD_RESUME:
        if (c->state == KC_CTRL_PAUSED && c->active)
            kc_ctrl_resume(c, c->cycle - 1, out);
        else if (c->state == KC_CTRL_STOPPING && c->stop_intent == KC_CMD_PAUSE)
            c->stop_intent = KC_CMD_RESUME; /* resume as soon as the pause has stopped */
        return;
    }
}

/* Checks a setpoint against the limits and the last one (see ctrl.h). */
static int setpoint_ok(const kc_ctrl *c, const kc_real *q, const kc_real *qd)
{
    kc_real slack = c->cfg.limit_slack;
    for (int j = 0; j < c->chain->n_joints; j++) {
        const kc_joint_limits *l = &c->chain->joints[j].limits;
        kc_real range_slack = slack * (kc_fabs(l->q_min) + kc_fabs(l->q_max) + KC_R(1.0));
        if (!kc_isfinite(q[j]) || !kc_isfinite(qd[j]))
            return 0;
        /* Outside, only no further out than the last setpoint: an arm a stop
         * carried past a limit may come to rest there and move back in. */
        if ((q[j] < l->q_min - range_slack && q[j] < c->q[j]) || (q[j] > l->q_max + range_slack && q[j] > c->q[j]))
            return 0;
        if (kc_fabs(qd[j]) > l->qd_max * (KC_R(1.0) + slack))
            return 0;
        if (kc_fabs(qd[j] - c->qd[j]) > l->qdd_max * c->cfg.dt * (KC_R(1.0) + slack) + slack * kc_fabs(c->qd[j]))
            return 0;
    }
    return 1;
}

kc_status kc_ctrl_step(kc_ctrl *c, const kc_ctrl_input *in, kc_ctrl_output *out)
{
    if (c == NULL || in == NULL || out == NULL || c->chain == NULL)
        return KC_E_ARG;
    int n = c->chain->n_joints;
    kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS], qdd[KC_MAX_JOINTS];
    out->n_events = 0;
    c->cycle++;

    command(c, in->command, out);
    /* An external fault: the hardware may not follow a path stop, so stop
     * in joint space, as fast as the limits allow. */
    if (in->fault != KC_REASON_NONE && c->fault_reason == KC_REASON_NONE && c->state != KC_CTRL_FAULT &&
        c->state != KC_CTRL_ESTOP)
        kc_ctrl_fault(c, in->fault, KC_R(0.0), 0, out);
    if (in->goal != NULL)
        kc_ctrl_take_goal(c, in->goal, out);
    if (c->active && c->goal.kind == KC_GOAL_SERVO && c->state == KC_CTRL_MOVING &&
        (in->servo_stale || c->cycle - c->servo_last > c->cfg.servo_timeout_ticks))
        kc_ctrl_stop_on_path(c, KC_CMD_NONE);
    if (!c->active && !kc_ctrl_joint_stopping(c) && c->state != KC_CTRL_FAULT && c->state != KC_CTRL_ESTOP) {
        if (!kc_ctrl_start_next(c, out) && c->state != KC_CTRL_PAUSED)
            c->state = KC_CTRL_IDLE;
    }

    /* The setpoint. finished: the segment has ended (1) or its stop has
     * come to rest on this tick (2), handled once the setpoint is kept. */
    int finished = 0;
    out->progress = KC_R(0.0);
    if (kc_ctrl_joint_stopping(c) || (c->active && c->goal.kind == KC_GOAL_SERVO && c->state == KC_CTRL_STOPPING) ||
        kc_ctrl_halting(c)) {
        if (kc_ctrl_joint_stop_eval(c, q, qd, qdd)) {
            c->jstop = 0;
            if (c->active && c->goal.kind != KC_GOAL_JOINT)
                finished = 2;
            else
                c->state = c->after_stop;
        }
    } else if (c->active && c->state != KC_CTRL_PAUSED) {
        finished = kc_ctrl_follow(c, q, qd, qdd, out);
        if (finished < 0) {
            /* a fault started a stop: its first tick */
            if (kc_ctrl_joint_stopping(c)) {
                kc_ctrl_joint_stop_eval(c, q, qd, qdd);
            } else {
                kc_ctrl_follow(c, q, qd, qdd, out);
            }
            finished = 0;
        }
    } else {
        /* Holding still (idle, paused, fault, e-stop at rest). */
        for (int j = 0; j < n; j++) {
            q[j] = c->q[j];
            qd[j] = KC_R(0.0);
            qdd[j] = KC_R(0.0);
        }
    }

    if (kc_ctrl_zones_on(c) && c->active && c->goal.kind == KC_GOAL_SERVO && c->state == KC_CTRL_MOVING &&
        !kc_ctrl_joint_stopping(c))
        kc_ctrl_zone_servo_limit(c, q, qd, qdd);

    if (!setpoint_ok(c, q, qd)) {
        /* Never send it: hold the last good position, stop in joint space.
         * Continue at the last velocity for this tick is not allowed either:
         * a joint-space stop from the last good state (kc_ctrl_fault, its
         * events unless in a fault already), its first tick. */
        kc_ctrl_fault(c, KC_REASON_LIMIT_GUARD, KC_R(0.0), 0, out);
        finished = 0; /* a segment whose last setpoint is refused has not ended: it was aborted */
        for (int j = 0; j < n; j++) {
            q[j] = c->q[j];
            qd[j] = c->qd[j];
        }
        kc_ctrl_joint_stop_eval(c, q, qd, qdd);
    }

    if (kc_ctrl_zones_on(c)) {
        kc_ctrl_zone_guard(c, q, qd, qdd, out);
        if (c->fault_reason == KC_REASON_ZONE)
            finished = 0;
    }

    memcpy(c->q, q, sizeof(kc_real) * (size_t)n);
    memcpy(c->qd, qd, sizeof(kc_real) * (size_t)n);
    memcpy(c->qdd, qdd, sizeof(kc_real) * (size_t)n);
    kc_fk_eval(c->chain, c->q, &c->pose);

    /* After the setpoint is kept: a RESUME the stop has waited for goes
     * on from it, its tick 0. */
    if (finished == 2 || (finished == 1 && c->state == KC_CTRL_STOPPING)) {
        kc_ctrl_stop_finished(c, out); /* a stop has come to rest */
    } else if (finished == 1) {
        kc_ctrl_emit(out, KC_EVENT_COMPLETED, c->goal.id, KC_REASON_NONE, 0);
        c->active = 0;
        c->state = c->queue_len > 0 ? KC_CTRL_MOVING : KC_CTRL_IDLE;
    }

    out->cycle = c->cycle;
    out->goal_id = c->active ? c->goal.id : 0;
    out->state = c->state;
    memcpy(out->q, c->q, sizeof(kc_real) * (size_t)n);
    memcpy(out->qd, c->qd, sizeof(kc_real) * (size_t)n);
    memcpy(out->qdd, c->qdd, sizeof(kc_real) * (size_t)n);
    out->pose = c->pose;
    out->queue_length = c->queue_len;
    return KC_OK;
}
