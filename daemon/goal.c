/* goal.c - goal messages into kc_goal, and rejection reasons (goal.h). */
#include "goal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "kinctl/se3.h"

#define KD_QUAT_NORM_TOL 1e-3

const char *kd_reason_token(kc_ctrl_reason reason)
{
    switch ((int)reason) {
    case KC_REASON_NONE: return "none";
    case KC_REASON_BAD_GOAL: return "bad_goal";
    case KC_REASON_JOINT_COUNT: return "joint_count";
    case KC_REASON_JOINT_LIMIT: return "joint_limit";
    case KC_REASON_QUEUE_FULL: return "queue_full";
    case KC_REASON_STATE: return "state";
    case KC_REASON_PLAN: return "plan";
    case KC_REASON_UNREACHABLE: return "unreachable";
    case KC_REASON_TRACKING: return "tracking";
    case KC_REASON_LIMIT_GUARD: return "limit_guard";
    case KC_REASON_SERVO_TIMEOUT: return "servo_timeout";
    case KC_REASON_DUPLICATE_ID: return "duplicate_id";
    case KC_REASON_ZONE: return "zone";
    case (int)KD_REASON_OVERRUN: return "overrun";
    case (int)KD_REASON_SHUTDOWN: return "shutdown";
    case KC_REASON_EXTERNAL: return "external";
    case (int)KD_REASON_DRIVE: return "drive";
    case (int)KD_REASON_CAN: return "can";
    default: return "unknown";
    }
}

kc_status kd_reason_code(kc_ctrl_reason reason)
{
    switch ((int)reason) {
    case KC_REASON_NONE: return KC_OK;
    case KC_REASON_BAD_GOAL:
    case KC_REASON_JOINT_COUNT:
    case KC_REASON_PLAN: return KC_E_ARG;
    case KC_REASON_JOINT_LIMIT:
    case KC_REASON_ZONE:
    case KC_REASON_LIMIT_GUARD: return KC_E_LIMIT;
    case KC_REASON_QUEUE_FULL: return KC_E_CAPACITY;
    case KC_REASON_UNREACHABLE:
    case KC_REASON_TRACKING: return KC_E_UNREACHABLE;
    case KC_REASON_STATE:
    case KC_REASON_SERVO_TIMEOUT:
    case (int)KD_REASON_OVERRUN:
    case (int)KD_REASON_SHUTDOWN:
    case KC_REASON_EXTERNAL:
    case (int)KD_REASON_DRIVE:
    case (int)KD_REASON_CAN: return KC_E_STATE;
    default: return KC_E_ARG;
    }
}

void kd_reject_set(kd_reject *rej, kc_ctrl_reason reason, const char *fmt, ...)
{
    va_list ap;
    int n;
    rej->reason = reason;
    rej->code = kd_reason_code(reason);
    n = snprintf(rej->text, sizeof rej->text, "%s: ", kd_reason_token(reason));
    if (n < 0 || (size_t)n >= sizeof rej->text)
        return;
    va_start(ap, fmt);
    (void)vsnprintf(rej->text + n, sizeof rej->text - (size_t)n, fmt, ap);
    va_end(ap);
}

int64_t kd_goal_id_peek(kd_msg_type type, const void *buf, size_t len)
{
    const unsigned char *p = buf;
    uint64_t v = 0;
    int i;
    if (type > KD_MSG_GOAL_SERVO || buf == NULL || len < 24)
        return 0;
    for (i = 16; i < 24; i++)
        v = (v << 8) | p[i];
    return (int64_t)v;
}

static kc_real scale_of(double s)
{
    return (kc_real)(s > 0.0 ? s : 1.0);
}

/* A unit quaternion (w x y z) into R, or a rejection. */
static int rotation_of(const double *q4, const char *what, kc_mat3 *R, kd_reject *rej)
{
    kc_quat q, u;
    double norm = sqrt(q4[0] * q4[0] + q4[1] * q4[1] + q4[2] * q4[2] + q4[3] * q4[3]);
    if (!(fabs(norm - 1.0) <= KD_QUAT_NORM_TOL)) {
        kd_reject_set(rej, KC_REASON_BAD_GOAL, "%s is not a unit quaternion (norm %.9g)", what, norm);
        return -1;
    }
    q.w = (kc_real)q4[0];
    q.x = (kc_real)q4[1];
    q.y = (kc_real)q4[2];
    q.z = (kc_real)q4[3];
    if (kc_quat_normalize(&q, &u) != KC_OK) {
        kd_reject_set(rej, KC_REASON_BAD_GOAL, "%s is not a unit quaternion", what);
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

static int joint_goal(const kinctl_goal_joint_t *m, const kc_chain *chain, kc_goal *g, kd_reject *rej)
{
    int j, bad = -1;
    if (m->n != chain->n_joints) {
        kd_reject_set(rej, KC_REASON_JOINT_COUNT, "goal_joint_t.n = %d, the arm has %d joints", (int)m->n,
                      chain->n_joints);
        return -1;
    }
    g->kind = KC_GOAL_JOINT;
    for (j = 0; j < chain->n_joints; j++)
        g->q[j] = (kc_real)m->q[j];
    if (kc_chain_check_q(chain, g->q, &bad) != KC_OK && bad >= 0 && bad < chain->n_joints) {
        const kc_joint_limits *l = &chain->joints[bad].limits;
        kd_reject_set(rej, KC_REASON_JOINT_LIMIT, "goal_joint_t.q[%d] = %.9g is outside joint %d's limits [%.9g, %.9g]",
                      bad, m->q[bad], bad + 1, (double)l->q_min, (double)l->q_max);
        return -1;
    }
    g->vel_scale = scale_of(m->vel_scale);
    g->acc_scale = scale_of(m->acc_scale);
    return 0;
}

static int line_goal(const kinctl_goal_line_t *m, kc_goal *g, kd_reject *rej)
{
    g->kind = KC_GOAL_LINE;
    vec3_of(m->position, &g->pose.t);
    if (rotation_of(m->orientation, "goal_line_t.orientation", &g->pose.R, rej) != 0)
        return -1;
    g->speed = (kc_real)m->speed;
    g->accel = (kc_real)m->accel;
    g->omega = (kc_real)m->angular_speed;
    g->alpha = (kc_real)m->angular_accel;
    g->orient = m->orientation_method == KINCTL_GOAL_LINE_T_SLERP ? KC_INTERP_SLERP : KC_INTERP_TWO_ROTATIONS;
    g->vel_scale = scale_of(m->vel_scale);
    g->acc_scale = scale_of(m->acc_scale);
    return 0;
}

static int arc_goal(const kinctl_goal_arc_t *m, kc_goal *g, kd_reject *rej)
{
    g->kind = KC_GOAL_ARC;
    vec3_of(m->position, &g->pose.t);
    vec3_of(m->via, &g->via);
    if (rotation_of(m->orientation, "goal_arc_t.orientation", &g->pose.R, rej) != 0)
        return -1;
    g->speed = (kc_real)m->speed;
    g->accel = (kc_real)m->accel;
    g->omega = (kc_real)m->angular_speed;
    g->alpha = (kc_real)m->angular_accel;
    g->vel_scale = scale_of(m->vel_scale);
    g->acc_scale = scale_of(m->acc_scale);
    return 0;
}

static int path_goal(const kinctl_goal_path_t *m, const kc_chain *chain, kc_goal *g, kd_reject *rej)
{
    int i, j, dim;
    if (m->space == KINCTL_GOAL_PATH_T_JOINT) {
        g->kind = KC_GOAL_PATH;
        dim = chain->n_joints;
        if (m->dim != dim) {
            kd_reject_set(rej, KC_REASON_JOINT_COUNT, "goal_path_t.dim = %d, the arm has %d joints", (int)m->dim, dim);
            return -1;
        }
    } else {
        g->kind = KC_GOAL_PATH_CART;
        dim = KINCTL_GOAL_PATH_T_CARTESIAN_DIM;
        if (m->dim != dim) {
            kd_reject_set(rej, KC_REASON_BAD_GOAL, "goal_path_t.dim = %d, a Cartesian knot has %d numbers", (int)m->dim,
                          dim);
            return -1;
        }
    }
    /* The controller holds the current state plus KC_PATH_MAX_KNOTS - 1 knots. */
    if (m->n_points < 1 || m->n_points > KC_PATH_MAX_KNOTS - 1) {
        kd_reject_set(rej, KC_REASON_BAD_GOAL, "goal_path_t.n_points = %d, expected 1 .. %d", (int)m->n_points,
                      KC_PATH_MAX_KNOTS - 1);
        return -1;
    }
    switch (m->method) {
    case KINCTL_GOAL_PATH_T_BLEND: g->method = KC_PATH_BLEND; break;
    case KINCTL_GOAL_PATH_T_SPLINE: g->method = KC_PATH_SPLINE; break;
    case KINCTL_GOAL_PATH_T_QUINTIC: g->method = KC_PATH_QUINTIC; break;
    default: g->method = KC_PATH_LAGRANGE; break;
    }
    g->blend = m->blend_shape == KINCTL_GOAL_PATH_T_BLEND_PARABOLIC ? KC_PATH_BLEND_PARABOLIC : KC_PATH_BLEND_QUARTIC;
    g->spline_end = m->spline_ends == KINCTL_GOAL_PATH_T_SPLINE_NATURAL ? KC_PATH_SPLINE_NATURAL : KC_PATH_SPLINE_CLAMPED;
    g->n_points = m->n_points;
    for (i = 0; i < m->n_points; i++)
        for (j = 0; j < dim; j++)
            g->points[i][j] = (kc_real)m->points[i][j];
    if (g->kind == KC_GOAL_PATH) {
        for (i = 0; i < m->n_points; i++) {
            int bad = -1;
            if (kc_chain_check_q(chain, g->points[i], &bad) != KC_OK && bad >= 0 && bad < dim) {
                const kc_joint_limits *l = &chain->joints[bad].limits;
                kd_reject_set(rej, KC_REASON_JOINT_LIMIT,
                              "goal_path_t.points[%d][%d] = %.9g is outside joint %d's limits [%.9g, %.9g]", i, bad,
                              m->points[i][bad], bad + 1, (double)l->q_min, (double)l->q_max);
                return -1;
            }
        }
    }
    g->has_times = m->has_times != 0;
    if (g->has_times)
        for (i = 0; i < m->n_points; i++)
            g->times[i] = (kc_real)m->times[i];
    g->blend_time = (kc_real)m->blend_time;
    g->speed = (kc_real)m->speed;
    g->accel = (kc_real)m->accel;
    g->vel_scale = scale_of(m->vel_scale);
    g->acc_scale = scale_of(m->acc_scale);
    return 0;
}

static int servo_goal(const kinctl_goal_servo_t *m, double timeout_max_s, kc_goal *g, int64_t *timeout_ns,
                      kd_reject *rej)
{
    int i;
    double t = (double)m->timeout_us * 1e3, t_max = timeout_max_s * 1e9;
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
        if (rotation_of(m->orientation, "goal_servo_t.orientation", &g->pose.R, rej) != 0)
            return -1;
    }
    *timeout_ns = (int64_t)(t < t_max ? t : t_max);
    return 0;
}

int kd_goal_from_msg(kd_msg_type type, const kd_msg_any *msg, const kc_chain *chain, double servo_timeout_max_s,
                     kc_goal *goal, int64_t *servo_timeout_ns, kd_reject *rej)
{
    int mode;
    memset(goal, 0, sizeof *goal);
    *servo_timeout_ns = 0;
    switch (type) {
    case KD_MSG_GOAL_JOINT:
        goal->id = msg->goal_joint.goal_id;
        mode = (int)msg->goal_joint.mode;
        if (joint_goal(&msg->goal_joint, chain, goal, rej) != 0)
            return -1;
        break;
    case KD_MSG_GOAL_LINE:
        goal->id = msg->goal_line.goal_id;
        mode = (int)msg->goal_line.mode;
        if (line_goal(&msg->goal_line, goal, rej) != 0)
            return -1;
        break;
    case KD_MSG_GOAL_ARC:
        goal->id = msg->goal_arc.goal_id;
        mode = (int)msg->goal_arc.mode;
        if (arc_goal(&msg->goal_arc, goal, rej) != 0)
            return -1;
        break;
    case KD_MSG_GOAL_PATH:
        goal->id = msg->goal_path.goal_id;
        mode = (int)msg->goal_path.mode;
        if (path_goal(&msg->goal_path, chain, goal, rej) != 0)
            return -1;
        break;
    case KD_MSG_GOAL_SERVO:
        goal->id = msg->goal_servo.goal_id;
        mode = (int)msg->goal_servo.mode;
        if (servo_goal(&msg->goal_servo, servo_timeout_max_s, goal, servo_timeout_ns, rej) != 0)
            return -1;
        break;
    default:
        kd_reject_set(rej, KC_REASON_BAD_GOAL, "not a goal type");
        return -1;
    }
    goal->replace = mode == KINCTL_GOAL_JOINT_T_REPLACE;
    return 0;
}
