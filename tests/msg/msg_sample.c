/* SPDX-License-Identifier: BSD-3-Clause */
/* msg_sample.c - see msg_sample.h. */
#include "msg_sample.h"

#include <stdio.h>
#include <string.h>

/* xorshift32: small, deterministic, good enough to vary the fields. */
static uint32_t next(uint32_t *s)
{
    uint32_t x = *s;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *s = x;
    return x;
}

/* In [lo, hi), with a fractional part that survives only an exact round trip. */
static double uniform(uint32_t *s, double lo, double hi)
{
    return lo + (hi - lo) * ((double)next(s) / 4294967296.0);
}

static int pick(uint32_t *s, int lo, int hi)
{
    return lo + (int)(next(s) % (uint32_t)(hi - lo + 1));
}

static void fill(uint32_t *s, double *a, int n, double lo, double hi)
{
    int i;
    for (i = 0; i < n; i++)
        a[i] = uniform(s, lo, hi);
}

static int64_t big(uint32_t *s)
{
    uint64_t v = ((uint64_t)next(s) << 32) | next(s);
    int64_t r;
    v &= 0x7fffffffffffffffULL;
    memcpy(&r, &v, sizeof r);
    return r == 0 ? 1 : r;
}

void msg_sample(kd_msg_type type, uint32_t seed, kd_msg_any *m, char *reason_buf)
{
    uint32_t st = seed * 2654435761u + 0x9e3779b9u;
    uint32_t *s = &st;
    int i;
    if (st == 0)
        st = 1;
    memset(m, 0, sizeof *m);
    switch (type) {
    case KD_MSG_GOAL_JOINT: {
        kinctl_goal_joint_t *g = &m->goal_joint;
        g->utime = big(s);
        g->goal_id = big(s) - INT64_C(0x4000000000000000);
        if (g->goal_id == 0)
            g->goal_id = -1;
        g->mode = (int8_t)pick(s, 0, 1);
        g->n = pick(s, 0, KINCTL_GOAL_JOINT_T_MAX_JOINTS);
        fill(s, g->q, KINCTL_GOAL_JOINT_T_MAX_JOINTS, -6.5, 6.5);
        g->vel_scale = uniform(s, 0.0, 1.0);
        g->acc_scale = uniform(s, 0.0, 1.0);
        g->profile = (int8_t)pick(s, KINCTL_GOAL_JOINT_T_PROFILE_CONFIG, KINCTL_GOAL_JOINT_T_PROFILE_JERK);
        break;
    }
    case KD_MSG_GOAL_LINE: {
        kinctl_goal_line_t *g = &m->goal_line;
        g->utime = big(s);
        g->goal_id = big(s);
        g->mode = (int8_t)pick(s, 0, 1);
        fill(s, g->position, 3, -2.0, 2.0);
        fill(s, g->orientation, 4, -1.0, 1.0);
        g->speed = uniform(s, 0.0, 2.0);
        g->accel = uniform(s, 0.0, 10.0);
        g->angular_speed = uniform(s, 0.0, 3.0);
        g->angular_accel = uniform(s, 0.0, 30.0);
        g->jerk = uniform(s, 0.0, 100.0);
        g->angular_jerk = uniform(s, 0.0, 300.0);
        g->orientation_method = (int8_t)pick(s, 0, 1);
        g->vel_scale = uniform(s, 0.0, 1.0);
        g->acc_scale = uniform(s, 0.0, 1.0);
        break;
    }
    case KD_MSG_GOAL_ARC: {
        kinctl_goal_arc_t *g = &m->goal_arc;
        g->utime = big(s);
        g->goal_id = big(s);
        g->mode = (int8_t)pick(s, 0, 1);
        fill(s, g->via, 3, -2.0, 2.0);
        fill(s, g->position, 3, -2.0, 2.0);
        fill(s, g->orientation, 4, -1.0, 1.0);
        g->speed = uniform(s, 0.0, 2.0);
        g->accel = uniform(s, 0.0, 10.0);
        g->angular_speed = uniform(s, 0.0, 3.0);
        g->angular_accel = uniform(s, 0.0, 30.0);
        g->jerk = uniform(s, 0.0, 100.0);
        g->angular_jerk = uniform(s, 0.0, 300.0);
        g->vel_scale = uniform(s, 0.0, 1.0);
        g->acc_scale = uniform(s, 0.0, 1.0);
        break;
    }
    case KD_MSG_GOAL_PATH: {
        kinctl_goal_path_t *g = &m->goal_path;
        g->utime = big(s);
        g->goal_id = big(s);
        g->mode = (int8_t)pick(s, 0, 1);
        g->space = (int8_t)pick(s, 0, 1);
        g->method = (int8_t)pick(s, 0, 3);
        g->blend_shape = (int8_t)pick(s, 0, 1);
        g->spline_ends = (int8_t)pick(s, 0, 1);
        g->n_points = pick(s, 0, KINCTL_GOAL_PATH_T_MAX_POINTS);
        g->dim = g->space == KINCTL_GOAL_PATH_T_CARTESIAN ? KINCTL_GOAL_PATH_T_CARTESIAN_DIM
                                                          : pick(s, 0, KINCTL_GOAL_PATH_T_MAX_DIM);
        for (i = 0; i < KINCTL_GOAL_PATH_T_MAX_POINTS; i++)
            fill(s, g->points[i], KINCTL_GOAL_PATH_T_MAX_DIM, -3.0, 3.0);
        g->has_times = (int8_t)pick(s, 0, 1);
        for (i = 0; i < KINCTL_GOAL_PATH_T_MAX_POINTS; i++)
            g->times[i] = 0.25 * i + uniform(s, 0.0, 0.2);
        g->blend_time = uniform(s, 0.0, 0.5);
        g->speed = uniform(s, 0.0, 2.0);
        g->accel = uniform(s, 0.0, 10.0);
        g->jerk = uniform(s, 0.0, 100.0);
        g->angular_jerk = uniform(s, 0.0, 300.0);
        g->vel_scale = uniform(s, 0.0, 1.0);
        g->acc_scale = uniform(s, 0.0, 1.0);
        break;
    }
    case KD_MSG_GOAL_SERVO: {
        kinctl_goal_servo_t *g = &m->goal_servo;
        g->utime = big(s);
        g->goal_id = big(s);
        g->mode = (int8_t)pick(s, 0, 1);
        g->kind = (int8_t)pick(s, 0, 1);
        fill(s, g->position, 3, -2.0, 2.0);
        fill(s, g->orientation, 4, -1.0, 1.0);
        fill(s, g->twist, 6, -1.0, 1.0);
        g->timeout_us = 1 + pick(s, 0, 1000000);
        break;
    }
    case KD_MSG_COMMAND:
        m->command.utime = big(s);
        m->command.command = (int8_t)pick(s, KINCTL_COMMAND_T_STOP, KINCTL_COMMAND_T_RESET);
        break;
    case KD_MSG_SETPOINT: {
        kinctl_setpoint_t *p = &m->setpoint;
        p->utime = big(s);
        p->cycle = big(s);
        p->goal_id = big(s);
        p->state = (int8_t)pick(s, KINCTL_SETPOINT_T_IDLE, KINCTL_SETPOINT_T_ESTOP);
        p->n = pick(s, 0, KINCTL_SETPOINT_T_MAX_JOINTS);
        fill(s, p->q, KINCTL_SETPOINT_T_MAX_JOINTS, -6.5, 6.5);
        fill(s, p->qd, KINCTL_SETPOINT_T_MAX_JOINTS, -3.0, 3.0);
        fill(s, p->qdd, KINCTL_SETPOINT_T_MAX_JOINTS, -20.0, 20.0);
        fill(s, p->position, 3, -2.0, 2.0);
        fill(s, p->orientation, 4, -1.0, 1.0);
        p->input_goal_id = big(s);
        p->input_command = (int8_t)pick(s, 0, KINCTL_COMMAND_T_RESET);
        p->input_servo_stale = (int8_t)pick(s, 0, 1);
        p->input_fault = (int8_t)pick(s, 0, 1);
        p->input_seated = (int8_t)pick(s, 0, 1);
        p->input_goal_share = uniform(s, 0.001, 1.0);
        p->input_goal_stop_first = (int8_t)pick(s, 0, 1);
        p->input_goal_qu = uniform(s, 0.0, 50.0);
        p->input_goal_scheduled = (int8_t)pick(s, 0, 1);
        if (p->input_goal_scheduled) {
            p->input_goal_take_ahead = pick(s, -1000, 1000);
            p->input_goal_take_state = (int64_t)next(s);
        }
        break;
    }
    case KD_MSG_STATUS: {
        kinctl_status_t *p = &m->status;
        p->utime = big(s);
        p->cycle = big(s);
        p->state = (int8_t)pick(s, KINCTL_STATUS_T_IDLE, KINCTL_STATUS_T_ESTOP);
        p->active_goal_id = big(s);
        p->progress = uniform(s, 0.0, 1.0);
        p->queue_length = pick(s, 0, 1000);
        p->event = (int8_t)pick(s, KINCTL_STATUS_T_NONE, KINCTL_STATUS_T_EVENT_FAULT);
        p->event_goal_id = big(s);
        p->code = -pick(s, 0, 40);
        (void)snprintf(reason_buf, 64, "reason %u: joint %d beyond its limit", (unsigned)seed,
                       pick(s, 1, 6));
        p->reason = reason_buf;
        p->n = pick(s, 0, KINCTL_STATUS_T_MAX_JOINTS);
        fill(s, p->q_measured, KINCTL_STATUS_T_MAX_JOINTS, -6.5, 6.5);
        fill(s, p->qd_measured, KINCTL_STATUS_T_MAX_JOINTS, -3.0, 3.0);
        p->can_state = (int8_t)pick(s, KINCTL_STATUS_T_CAN_OFF, KINCTL_STATUS_T_CAN_LOST);
        p->joint = pick(s, 0, KINCTL_STATUS_T_MAX_JOINTS);
        p->joint_prismatic = (int8_t)pick(s, 0, 1);
        p->joint_value = uniform(s, -7.0, 7.0);
        p->joint_lower = uniform(s, -3.2, 0.0);
        p->joint_upper = uniform(s, 0.0, 3.2);
        p->drives = (int8_t)pick(s, KINCTL_STATUS_T_DRIVES_NONE, KINCTL_STATUS_T_DRIVES_DISABLED);
        for (int j = 0; j < KINCTL_STATUS_T_MAX_JOINTS; j++)
            p->prismatic[j] = (int8_t)pick(s, 0, 1);
        break;
    }
    case KD_MSG_STATS: {
        kinctl_stats_t *p = &m->stats;
        p->utime = big(s);
        p->period_ns = 1000000;
        p->cycles = big(s);
        p->latency_p50_ns = big(s);
        p->latency_p99_ns = big(s);
        p->latency_p999_ns = big(s);
        p->latency_max_ns = big(s);
        p->compute_p50_ns = big(s);
        p->compute_p99_ns = big(s);
        p->compute_max_ns = big(s);
        p->overruns = big(s);
        p->msgs_in = big(s);
        p->msgs_invalid = big(s);
        p->msgs_out = big(s);
        p->msgs_dropped = big(s);
        p->rejections = big(s);
        p->can_frames = big(s);
        p->can_errors = big(s);
        p->can_state = (int8_t)pick(s, KINCTL_STATUS_T_CAN_OFF, KINCTL_STATUS_T_CAN_LOST);
        p->can_tx_dropped = big(s);
        p->can_error_frames = big(s);
        p->can_bus_off = big(s);
        p->can_link_down = big(s);
        p->can_rx_frames = big(s);
        break;
    }
    case KD_MSG_TYPE_COUNT: break;
    }
}
