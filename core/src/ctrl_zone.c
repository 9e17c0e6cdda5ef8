/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl_zone.c - forbidden zones in the controller: the servo's braking
 * toward a zone and the final check of every setpoint (kinctl/ctrl.h,
 * kinctl/zone.h). */
#include "ctrl_internal.h"
#include "vec3_internal.h"

#include <string.h>

/* Units in the last place of a position of the arm's size within which a
 * change of a zone distance is rounding (kc_ctrl_zone_servo_limit). */
#define NOISE KC_R(2.0)

void kc_ctrl_zone_init(kc_ctrl *c)
{
    kc_zone_hit none = {-1, -1, INF};
    c->zone_now = none;
    c->zone_hit = none;
    kc_zone_levers(c->chain, c->zone_lever);
    /* The servo's braking law: a point's braking a makes joint j brake at
     * most a / lever_j, so a = min qdd_max_j lever_j keeps every joint
     * within its limit; half of it leaves room for the IK's own changes. */
    c->zone_brake = INF;
    for (int j = 0; j < c->chain->n_joints; j++)
        if (c->zone_lever[j] > KC_R(0.0))
            c->zone_brake = kc_min(c->zone_brake, KC_R(0.5) * c->chain->joints[j].limits.qdd_max * c->zone_lever[j]);
    if (kc_ctrl_zones_on(c))
        kc_zone_check(c->chain, c->cfg.zones, c->q, NULL, &c->zone_now);
}

void kc_ctrl_zone_servo_limit(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd)
{
    int n = c->chain->n_joints;
    kc_real travel = KC_R(0.0), dt = c->cfg.dt;
    for (int j = 0; j < n; j++)
        travel += kc_fabs(q[j] - c->q[j]) * c->zone_lever[j];
    if (!(travel > KC_R(0.0)))
        return;
    kc_zone_hit hit;
    kc_status st = kc_zone_check(c->chain, c->cfg.zones, q, NULL, &hit);
    if ((st != KC_OK && st != KC_E_LIMIT) || hit.distance >= c->zone_now.distance)
        return; /* not finite (the final check refuses it) or not approaching */
    /* The room left, short of the margin by the distances' rounding
     * (band): the arm at rest there, a step whose change of distance is
     * rounding alone stays out of the margin, which the final check keeps. */
    kc_real band = NOISE * KC_REAL_EPS * (KC_R(1.0) + kc_vec3_norm(&c->pose.t));
    kc_real e = kc_max(c->zone_now.distance - c->cfg.zones->margin - band, KC_R(0.0));
    /* The braking law on the measured approach; the bound on the travel
     * of any point keeps the step short of the margin whatever it is. */
    kc_real approach = c->zone_now.distance - hit.distance, s = KC_R(1.0), a = KC_R(1.0);
    kc_real brake = dt * kc_sqrt(KC_R(2.0) * c->zone_brake * e);
    if (approach > brake)
        s = brake / approach;
    if (travel * s > KC_R(0.5) * e)
        s = KC_R(0.5) * e / travel;
    if (s >= KC_R(1.0))
        return;
    for (int j = 0; j < n; j++) {
        kc_real dv = kc_fabs(s * qd[j] - c->qd[j]), lim = c->chain->joints[j].limits.qdd_max * dt;
        if (dv * a > lim)
            a = lim / dv;
    }
    for (int j = 0; j < n; j++) {
        qd[j] = c->qd[j] + a * (s * qd[j] - c->qd[j]);
        q[j] = c->q[j] + qd[j] * dt;
        qdd[j] = (qd[j] - c->qd[j]) / dt;
    }
    c->servo_zone_cycle = c->cycle; /* kc_ctrl_servo_jerk */
    /* The tool held back, the stream's lag bound is a stop's until it has
     * closed in on the target again (kc_ctrl_follow). */
    c->blend.lax = 1;
    /* A twist stream's or a shaped pose stream's target stays with the
     * restrained arm instead of running on into the zone, and its shaped
     * twist is the arm's over the tick (the rate zero), so a reversed twist
     * or a pose away from the zone moves it away at once. Not for an
     * approach within the band while the target is within ZONE_LEAD of the
     * arm: at rest against the margin, a reversed stream's first steps
     * measure that much (rounding alone), and taking the stream back to
     * rest on them would take it back on every tick, never away (so too
     * judged on the direction of the step's velocity: sliding along a
     * wall, a reversed stream's first steps may head in, its axes' rates
     * ramping alike before the commanded twist's direction shows). But a
     * stream pushing on, its step from rest within qdd_max dt, can measure
     * an approach of no more than the band for good (in float, the PUMA
     * 560 against a wall: 4 units in the last place on both), its target
     * then running on into the zone at the stream's twist while the arm
     * stays, and a reversed stream would first brake that twist. The step
     * itself is restrained all the same. */
    int shaped = kc_ctrl_servo_shaped(c);
    kc_vec3 lead = kc_v3_sub(c->servo_target.t, c->pose.t);
    if ((c->goal.servo_twist || shaped) && (approach > band || kc_v3_dot(lead, lead) > ZONE_LEAD * ZONE_LEAD)) {
        kc_fk_eval(c->chain, q, &c->servo_target);
        kc_vec3 w;
        kc_ctrl_turn(&c->pose.R, &c->servo_target.R, &w);
        for (int i = 0; i < 3; i++) {
            c->servo_v[i] = (c->servo_target.t.v[i] - c->pose.t.v[i]) / dt;
            c->servo_v[3 + i] = w.v[i] / dt;
        }
        memset(c->servo_a, 0, sizeof c->servo_a);
        if (shaped)
            kc_ctrl_servo_aim(c, c->cycle);
    }
}

static void emit_zone(kc_ctrl_output *out, kc_ctrl_event_kind kind, int64_t id, kc_real where, const kc_zone_hit *hit)
{
    int before = out->n_events;
    kc_ctrl_emit(out, kind, id, KC_REASON_ZONE, where);
    if (out->n_events > before) {
        out->events[before].zone = hit->zone;
        out->events[before].volume = hit->volume;
    }
}

void kc_ctrl_zone_guard(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd, kc_ctrl_output *out)
{
    kc_zone_hit hit;
    if (kc_zone_check(c->chain, c->cfg.zones, q, NULL, &hit) == KC_E_ARG)
        return; /* not finite: never the case after setpoint_ok */
    if (c->fault_reason == KC_REASON_ZONE || !(hit.distance < c->cfg.zones->margin) ||
        !(hit.distance < c->zone_now.distance)) {
        c->zone_now = hit;
        return;
    }
    kc_real where = c->active && c->path_length > KC_R(0.0) ? out->progress * c->path_length : out->progress;
    c->zone_hit = hit;
    c->fault_reason = KC_REASON_ZONE;
    emit_zone(out, KC_EVENT_FAULT, c->active ? c->goal.id : 0, where, &hit);
    if (c->active)
        emit_zone(out, KC_EVENT_ABORTED, c->goal.id, where, &hit);
    kc_ctrl_queue_clear(c, out);
    kc_ctrl_joint_stop(c, 0, KC_CTRL_FAULT);
    c->state = KC_CTRL_STOPPING;
    kc_ctrl_joint_stop_eval(c, q, qd, qdd);
    kc_zone_check(c->chain, c->cfg.zones, q, NULL, &c->zone_now);
}
