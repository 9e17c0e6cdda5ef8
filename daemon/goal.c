/* SPDX-License-Identifier: BSD-3-Clause */
/* goal.c - goal messages into kc_goal (goal.h). */
#include "goal.h"

#include <math.h>
#include <string.h>

#include "kinctl/se3.h"

/* One limit of knots everywhere: what the wire carries is what a goal holds
 * after the start of its motion. */
_Static_assert(KINCTL_GOAL_PATH_T_MAX_POINTS == KC_PATH_MAX_KNOTS - 1,
               "goal_path_t.MAX_POINTS (lcmtypes) must be KC_PATH_MAX_KNOTS - 1 (kinctl/path.h)");

#define KD_QUAT_NORM_TOL 1e-3

static kc_real scale_of(double s)
{
    return (kc_real)(s > 0.0 ? s : 1.0);
}

/* A unit quaternion (w x y z) into R; or -1, the verdict naming the
 * orientation and its norm. */
static int rotation_of(const double *q4, kc_mat3 *R, kc_verdict *v)
{
    kc_quat q, u;
    double norm = sqrt(q4[0] * q4[0] + q4[1] * q4[1] + q4[2] * q4[2] + q4[3] * q4[3]);
    q.w = (kc_real)q4[0];
    q.x = (kc_real)q4[1];
    q.y = (kc_real)q4[2];
    q.z = (kc_real)q4[3];
    if (!(fabs(norm - 1.0) <= KD_QUAT_NORM_TOL) || kc_quat_normalize(&q, &u) != KC_OK) {
        v->status = KC_E_ARG;
        v->reason = KC_REASON_BAD_GOAL;
        v->field = KC_FIELD_ORIENTATION;
        v->value = (kc_real)norm;
        return -1;
    }
    kc_quat_to_mat3(&u, R);
    return 0;
}

static void vec3_of(const double *v, kc_vec3 *dest)
{
    dest->v[0] = (kc_real)v[0];
    dest->v[1] = (kc_real)v[1];
    dest->v[2] = (kc_real)v[2];
}

/* A Cartesian motion's speed, acceleration and jerk bounds (0: the
 * configured ones) and the fractions of the joints' limits. */
static void cart_rates(kc_goal *g, double speed, double accel, double omega, double alpha, double jerk,
                       double angular_jerk, double vel_scale, double acc_scale)
{
    g->speed = (kc_real)speed;
    g->accel = (kc_real)accel;
    g->omega = (kc_real)omega;
    g->alpha = (kc_real)alpha;
    g->jerk = (kc_real)jerk;
    g->angular_jerk = (kc_real)angular_jerk;
    g->vel_scale = scale_of(vel_scale);
    g->acc_scale = scale_of(acc_scale);
}

static void joint_goal(const kinctl_goal_joint_t *m, kc_goal *g)
{
    int j;
    g->id = m->goal_id;
    g->replace = m->mode == KINCTL_GOAL_JOINT_T_REPLACE;
    g->kind = KC_GOAL_JOINT;
    g->dim = (int)m->n;
    for (j = 0; j < m->n && j < KC_MAX_JOINTS; j++)
        g->q[j] = (kc_real)m->q[j];
    g->vel_scale = scale_of(m->vel_scale);
    g->acc_scale = scale_of(m->acc_scale);
    g->profile = m->profile == KINCTL_GOAL_JOINT_T_PROFILE_TRAPEZOID ? KC_GOAL_PROFILE_TRAPEZOID
                 : m->profile == KINCTL_GOAL_JOINT_T_PROFILE_JERK    ? KC_GOAL_PROFILE_JERK
                                                                     : KC_GOAL_PROFILE_CFG;
}

static int line_goal(const kinctl_goal_line_t *m, kc_goal *g, kc_verdict *v)
{
    g->id = m->goal_id;
    g->replace = m->mode == KINCTL_GOAL_LINE_T_REPLACE;
    g->kind = KC_GOAL_LINE;
    vec3_of(m->position, &g->pose.t);
    if (rotation_of(m->orientation, &g->pose.R, v) != 0)
        return -1;
    g->orient = m->orientation_method == KINCTL_GOAL_LINE_T_SLERP ? KC_INTERP_SLERP : KC_INTERP_TWO_ROTATIONS;
    cart_rates(g, m->speed, m->accel, m->angular_speed, m->angular_accel, m->jerk, m->angular_jerk, m->vel_scale,
               m->acc_scale);
    return 0;
}

static int arc_goal(const kinctl_goal_arc_t *m, kc_goal *g, kc_verdict *v)
{
    g->id = m->goal_id;
    g->replace = m->mode == KINCTL_GOAL_ARC_T_REPLACE;
    g->kind = KC_GOAL_ARC;
    vec3_of(m->position, &g->pose.t);
    vec3_of(m->via, &g->via);
    if (rotation_of(m->orientation, &g->pose.R, v) != 0)
        return -1;
    cart_rates(g, m->speed, m->accel, m->angular_speed, m->angular_accel, m->jerk, m->angular_jerk, m->vel_scale,
               m->acc_scale);
    return 0;
}

/* Knots beyond what kc_goal holds are not copied: the core refuses the
 * count (n_points, dim) before it reads a knot. */
static void path_goal(const kinctl_goal_path_t *m, kc_goal *g)
{
    int i, j;
    g->id = m->goal_id;
    g->replace = m->mode == KINCTL_GOAL_PATH_T_REPLACE;
    g->kind = m->space == KINCTL_GOAL_PATH_T_JOINT ? KC_GOAL_PATH : KC_GOAL_PATH_CART;
    g->dim = (int)m->dim;
    switch (m->method) {
    case KINCTL_GOAL_PATH_T_BLEND: g->method = KC_PATH_BLEND; break;
    case KINCTL_GOAL_PATH_T_SPLINE: g->method = KC_PATH_SPLINE; break;
    case KINCTL_GOAL_PATH_T_QUINTIC: g->method = KC_PATH_QUINTIC; break;
    default: g->method = KC_PATH_LAGRANGE; break;
    }
    g->blend = m->blend_shape == KINCTL_GOAL_PATH_T_BLEND_PARABOLIC ? KC_PATH_BLEND_PARABOLIC : KC_PATH_BLEND_QUARTIC;
    g->spline_end = m->spline_ends == KINCTL_GOAL_PATH_T_SPLINE_NATURAL ? KC_PATH_SPLINE_NATURAL : KC_PATH_SPLINE_CLAMPED;
    g->n_points = m->n_points;
    for (i = 0; i < m->n_points && i < KC_PATH_MAX_KNOTS - 1; i++)
        for (j = 0; j < m->dim && j < KC_MAX_JOINTS; j++)
            g->points[i][j] = (kc_real)m->points[i][j];
    g->has_times = m->has_times != 0;
    if (g->has_times)
        for (i = 0; i < m->n_points && i < KC_PATH_MAX_KNOTS - 1; i++)
            g->times[i] = (kc_real)m->times[i];
    g->blend_time = (kc_real)m->blend_time;
    cart_rates(g, m->speed, m->accel, 0.0, 0.0, m->jerk, m->angular_jerk, m->vel_scale, m->acc_scale);
}

static int servo_goal(const kinctl_goal_servo_t *m, double timeout_max_s, kc_goal *g, int64_t *timeout_ns,
                      kc_verdict *v)
{
    int i;
    double t = (double)m->timeout_us * 1e3, t_max = timeout_max_s * 1e9;
    g->id = m->goal_id;
    g->replace = m->mode == KINCTL_GOAL_SERVO_T_REPLACE;
    g->kind = KC_GOAL_SERVO;
    g->vel_scale = 1;
    g->acc_scale = 1;
    if (m->kind == KINCTL_GOAL_SERVO_T_TWIST) {
        g->servo_twist = 1;
        for (i = 0; i < 6; i++)
            g->twist[i] = (kc_real)m->twist[i];
    } else {
        g->servo_twist = 0;
        vec3_of(m->position, &g->pose.t);
        if (rotation_of(m->orientation, &g->pose.R, v) != 0)
            return -1;
    }
    *timeout_ns = (int64_t)(t < t_max ? t : t_max);
    return 0;
}

int kd_goal_from_msg(kd_msg_type type, const kd_msg_any *msg, double servo_timeout_max_s, kc_goal *goal,
                     int64_t *servo_timeout_ns, kc_verdict *verdict)
{
    int st = 0;
    memset(goal, 0, sizeof *goal);
    kc_ctrl_verdict_init(verdict);
    *servo_timeout_ns = 0;
    switch (type) {
    case KD_MSG_GOAL_JOINT:
        joint_goal(&msg->goal_joint, goal);
        break;
    case KD_MSG_GOAL_LINE:
        st = line_goal(&msg->goal_line, goal, verdict);
        break;
    case KD_MSG_GOAL_ARC:
        st = arc_goal(&msg->goal_arc, goal, verdict);
        break;
    case KD_MSG_GOAL_PATH:
        path_goal(&msg->goal_path, goal);
        break;
    case KD_MSG_GOAL_SERVO:
        st = servo_goal(&msg->goal_servo, servo_timeout_max_s, goal, servo_timeout_ns, verdict);
        break;
    default:
        verdict->status = KC_E_ARG;
        verdict->reason = KC_REASON_BAD_GOAL;
        return -1;
    }
    return st != 0 ? -1 : 0;
}
