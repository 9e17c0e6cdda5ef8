/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl_goal.c - the cheap checks of a goal, as a verdict naming the field,
 * knot and joint at fault, the texts of the reasons, and a goal's law
 * slowed (kinctl/ctrl.h). */
#include "ctrl_internal.h"

#include <stddef.h>
#include <string.h>

const char *kc_ctrl_reason_str(kc_ctrl_reason reason)
{
    switch (reason) {
    case KC_REASON_NONE: return "none";
    case KC_REASON_BAD_GOAL: return "a goal field is not finite or out of its domain";
    case KC_REASON_JOINT_COUNT: return "the goal's joint count does not match the arm";
    case KC_REASON_JOINT_LIMIT: return "a target lies outside the joint position limits";
    case KC_REASON_QUEUE_FULL: return "the goal queue is full";
    case KC_REASON_STATE: return "the controller is in fault or e-stop: reset first";
    case KC_REASON_PLAN: return "the motion cannot be planned (degenerate geometry or too long)";
    case KC_REASON_UNREACHABLE: return "the arm cannot follow this Cartesian motion";
    case KC_REASON_TRACKING: return "the tool fell behind the Cartesian path or servo target";
    case KC_REASON_LIMIT_GUARD: return "a setpoint failed the final limit check";
    case KC_REASON_SERVO_TIMEOUT: return "the servo stream went quiet";
    case KC_REASON_DUPLICATE_ID: return "a goal with this id is already active or queued";
    case KC_REASON_EXTERNAL: return "an external device (a drive, the field bus) reported a fault";
    case KC_REASON_ZONE: return "a link volume would enter the margin of a forbidden zone";
    case KC_REASON_STOP_FIRST: return "no continuous transition from the motion it replaces: that motion stops first";
    case KC_REASON_LATE: return "not taken in the cycle or from the state its dry run judged it for: send it again";
    case KC_REASON_COUNT: break;
    }
    return "unknown reason";
}

void kc_ctrl_goal_copy(kc_goal *dst, const kc_goal *src)
{
    int rows = kc_ctrl_is_path(src->kind) ? src->n_points : 0;
    if (rows < 0 || rows > KC_PATH_MAX_KNOTS - 1)
        rows = 0; /* refused by kc_ctrl_goal_check: its knots are never read */
    memcpy(dst, src, offsetof(kc_goal, points));
    memcpy(dst->points, src->points, sizeof src->points[0] * (size_t)rows);
    memcpy(&dst->has_times, &src->has_times, offsetof(kc_goal, times) - offsetof(kc_goal, has_times));
    memcpy(dst->times, src->times, sizeof src->times[0] * (size_t)rows);
    memcpy(&dst->blend_time, &src->blend_time, sizeof(kc_goal) - offsetof(kc_goal, blend_time));
}

static int pose_ok(const kc_pose *p)
{
    return kc_pose_isfinite(p) && kc_mat3_rotation_error(&p->R) <= KC_TOL_ORTHONORMAL;
}

static int scale_ok(kc_real s) { return kc_isfinite(s) && s > KC_R(0.0) && s <= KC_R(1.0); }

/* A limit of a goal: finite, 0 for the configuration's. */
static int limit_ok(kc_real x) { return kc_isfinite(x) && x >= KC_R(0.0); }

void kc_ctrl_verdict_init(kc_verdict *v)
{
    memset(v, 0, sizeof *v);
    v->status = KC_OK;
    v->reason = KC_REASON_NONE;
    v->field = KC_FIELD_NONE;
    v->joint = v->point = -1;
    v->tick = -1;
    v->zone = v->volume = -1;
    v->distance = INF;
}

kc_status kc_ctrl_refuse(kc_verdict *v, kc_ctrl_reason why, kc_goal_field field, int point, int joint,
                         kc_real value)
{
    if (v != NULL) {
        v->status = KC_E_ARG;
        v->reason = why;
        v->field = field;
        v->point = point;
        v->joint = joint;
        v->value = value;
    }
    return KC_E_ARG;
}

kc_status kc_ctrl_bad_goal(kc_verdict *v)
{
    return kc_ctrl_refuse(v, KC_REASON_BAD_GOAL, KC_FIELD_NONE, -1, -1, KC_R(0.0));
}

/* Joint targets q of knot point (-1: a joint move's target): inside the
 * position limits, naming the first joint that is not. */
static kc_status targets_ok(const kc_chain *chain, const kc_real *q, int point, kc_verdict *v)
{
    int j = -1;
    kc_status st = kc_chain_check_q(chain, q, &j);
    if (st == KC_OK)
        return KC_OK;
    kc_real value = j >= 0 && j < chain->n_joints ? q[j] : KC_R(0.0);
    /* A knot that fails at all is out of its limits (its numbers were
     * checked finite before). */
    if (st == KC_E_LIMIT || point >= 0)
        return kc_ctrl_refuse(v, KC_REASON_JOINT_LIMIT, KC_FIELD_TARGET, point, j, value);
    return kc_ctrl_refuse(v, KC_REASON_BAD_GOAL, KC_FIELD_TARGET, point, j, value);
}

/* A path's knots: count, method, numbers, joint targets, then times. */
static kc_status path_ok(const kc_chain *chain, const kc_goal *g, kc_verdict *v)
{
    int n = chain->n_joints, dim = g->kind == KC_GOAL_PATH ? n : 7;
    if (g->dim != 0 && g->dim != dim)
        return kc_ctrl_refuse(v, g->kind == KC_GOAL_PATH ? KC_REASON_JOINT_COUNT : KC_REASON_BAD_GOAL, KC_FIELD_DIM,
                              -1, -1, (kc_real)g->dim);
    if (g->n_points < 1 || g->n_points > KC_PATH_MAX_KNOTS - 1)
        return kc_ctrl_refuse(v, KC_REASON_BAD_GOAL, KC_FIELD_N_POINTS, -1, -1, (kc_real)g->n_points);
    if ((unsigned)g->method > (unsigned)KC_PATH_QUINTIC || (unsigned)g->blend > (unsigned)KC_PATH_BLEND_PARABOLIC ||
        (unsigned)g->spline_end > (unsigned)KC_PATH_SPLINE_NATURAL || !kc_isfinite(g->blend_time) ||
        g->blend_time < KC_R(0.0))
        return kc_ctrl_bad_goal(v);
    for (int i = 0; i < g->n_points; i++) {
        for (int j = 0; j < dim; j++)
            if (!kc_isfinite(g->points[i][j]))
                return kc_ctrl_refuse(v, KC_REASON_BAD_GOAL, KC_FIELD_TARGET, i, j, KC_R(0.0));
        if (g->kind == KC_GOAL_PATH && targets_ok(chain, g->points[i], i, v) != KC_OK)
            return KC_E_ARG;
    }
    for (int i = 0; i < g->n_points && g->has_times; i++)
        if (!kc_isfinite(g->times[i]) || g->times[i] <= (i > 0 ? g->times[i - 1] : KC_R(0.0)))
            return kc_ctrl_refuse(v, KC_REASON_BAD_GOAL, KC_FIELD_TIMES, i, -1, KC_R(0.0));
    return KC_OK;
}

kc_status kc_ctrl_goal_check(const kc_chain *chain, const kc_goal *g, kc_verdict *v)
{
    if (v != NULL)
        kc_ctrl_verdict_init(v);
    if (chain == NULL || g == NULL)
        return kc_ctrl_bad_goal(v);
    if ((unsigned)g->kind > (unsigned)KC_GOAL_SERVO || !scale_ok(g->vel_scale) || !scale_ok(g->acc_scale) ||
        (unsigned)g->profile > (unsigned)KC_GOAL_PROFILE_JERK)
        return kc_ctrl_bad_goal(v);
    const kc_real limits[7] = {g->speed, g->accel, g->omega, g->alpha, g->jerk, g->angular_jerk, g->qu};
    for (int i = 0; i < 7; i++)
        if (!limit_ok(limits[i]))
            return kc_ctrl_bad_goal(v);
    switch (g->kind) {
    case KC_GOAL_JOINT:
        if (g->dim != 0 && g->dim != chain->n_joints)
            return kc_ctrl_refuse(v, KC_REASON_JOINT_COUNT, KC_FIELD_DIM, -1, -1, (kc_real)g->dim);
        if (targets_ok(chain, g->q, -1, v) != KC_OK)
            return KC_E_ARG;
        break;
    case KC_GOAL_LINE:
        if (!pose_ok(&g->pose))
            return kc_ctrl_refuse(v, KC_REASON_BAD_GOAL, KC_FIELD_ORIENTATION, -1, -1, (kc_real)NAN);
        if (g->orient != KC_INTERP_TWO_ROTATIONS && g->orient != KC_INTERP_SLERP)
            return kc_ctrl_bad_goal(v);
        break;
    case KC_GOAL_ARC:
        if (!kc_vec3_isfinite(&g->pose.t) || !kc_vec3_isfinite(&g->via))
            return kc_ctrl_bad_goal(v);
        break;
    case KC_GOAL_PATH:
    case KC_GOAL_PATH_CART:
        if (path_ok(chain, g, v) != KC_OK)
            return KC_E_ARG;
        break;
    case KC_GOAL_SERVO:
        if (g->servo_twist) {
            for (int i = 0; i < 6; i++)
                if (!kc_isfinite(g->twist[i]))
                    return kc_ctrl_bad_goal(v);
        } else if (!pose_ok(&g->pose)) {
            return kc_ctrl_refuse(v, KC_REASON_BAD_GOAL, KC_FIELD_ORIENTATION, -1, -1, (kc_real)NAN);
        }
        break;
    }
    return KC_OK;
}

kc_status kc_goal_slow(kc_goal *g, const kc_ctrl_cfg *cfg, kc_real s)
{
    if (g == NULL || cfg == NULL || !(s > KC_R(0.0) && s <= KC_R(1.0)) ||
        (g->kind != KC_GOAL_LINE && g->kind != KC_GOAL_ARC && g->kind != KC_GOAL_PATH_CART))
        return KC_E_ARG;
    kc_interp_limits l = kc_ctrl_cart_limits(cfg, g);
    if (!kc_isfinite(l.j)) /* the trapezoid */
        return KC_E_ARG;
    kc_real s2 = s * s, s3 = s2 * s;
    g->speed = s * l.v;
    g->accel = s2 * l.a;
    g->omega = s * l.w;
    g->alpha = s2 * l.dw;
    g->jerk = s3 * l.j;
    g->angular_jerk = s3 * l.dj;
    if (g->kind == KC_GOAL_PATH_CART) {
        for (int i = 0; g->has_times && i < g->n_points && i < KC_PATH_MAX_KNOTS - 1; i++)
            g->times[i] /= s;
        g->blend_time /= s;
    }
    g->slowed = kc_goal_share(g) * s;
    return KC_OK;
}

kc_real kc_goal_share(const kc_goal *g)
{
    return g != NULL && g->slowed > KC_R(0.0) ? g->slowed : KC_R(1.0);
}
