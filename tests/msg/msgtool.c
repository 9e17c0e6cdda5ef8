/* SPDX-License-Identifier: BSD-3-Clause */
/* msgtool.c - the C side of test_msg_python.py: puts the daemon's message
 * layer (daemon/msg.h) behind stdin and stdout so that the Python bindings
 * can be checked against it.
 *   msgtool decode TYPE        datagram on stdin -> fields as JSON on stdout;
 *                              refused: "<status>: <reason>" on stderr, exit 2
 *   msgtool roundtrip TYPE     datagram on stdin -> decode -> encode -> stdout
 *   msgtool sample TYPE SEED   a valid message (msg_sample.h) -> stdout
 * TYPE is the LCM name, e.g. goal_joint_t. status_t, which the daemon never
 * decodes, goes through the generated decoder here. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "msg.h"
#include "msg_sample.h"

static unsigned char in[KD_MSG_MAX_SIZE + 4096];

static void pd(const char *name, const double *a, int n, int array)
{
    int i;
    printf("\"%s\": ", name);
    if (array)
        printf("[");
    for (i = 0; i < n; i++)
        printf("%s%.17g", i ? ", " : "", a[i]);
    printf("%s, ", array ? "]" : "");
}

static void pi(const char *name, long long v)
{
    printf("\"%s\": %lld, ", name, v);
}

static void print_json(kd_msg_type t, const kd_msg_any *m)
{
    int i;
    printf("{");
    switch (t) {
    case KD_MSG_GOAL_JOINT: {
        const kinctl_goal_joint_t *g = &m->goal_joint;
        pi("utime", g->utime); pi("goal_id", g->goal_id); pi("mode", g->mode); pi("n", g->n);
        pd("q", g->q, 16, 1); pd("vel_scale", &g->vel_scale, 1, 0);
        pd("acc_scale", &g->acc_scale, 1, 0); pi("profile", g->profile);
        break;
    }
    case KD_MSG_GOAL_LINE: {
        const kinctl_goal_line_t *g = &m->goal_line;
        pi("utime", g->utime); pi("goal_id", g->goal_id); pi("mode", g->mode);
        pd("position", g->position, 3, 1); pd("orientation", g->orientation, 4, 1);
        pd("speed", &g->speed, 1, 0); pd("accel", &g->accel, 1, 0);
        pd("angular_speed", &g->angular_speed, 1, 0); pd("angular_accel", &g->angular_accel, 1, 0);
        pd("jerk", &g->jerk, 1, 0); pd("angular_jerk", &g->angular_jerk, 1, 0);
        pi("orientation_method", g->orientation_method);
        pd("vel_scale", &g->vel_scale, 1, 0); pd("acc_scale", &g->acc_scale, 1, 0);
        break;
    }
    case KD_MSG_GOAL_ARC: {
        const kinctl_goal_arc_t *g = &m->goal_arc;
        pi("utime", g->utime); pi("goal_id", g->goal_id); pi("mode", g->mode);
        pd("via", g->via, 3, 1); pd("position", g->position, 3, 1);
        pd("orientation", g->orientation, 4, 1);
        pd("speed", &g->speed, 1, 0); pd("accel", &g->accel, 1, 0);
        pd("angular_speed", &g->angular_speed, 1, 0); pd("angular_accel", &g->angular_accel, 1, 0);
        pd("jerk", &g->jerk, 1, 0); pd("angular_jerk", &g->angular_jerk, 1, 0);
        pd("vel_scale", &g->vel_scale, 1, 0); pd("acc_scale", &g->acc_scale, 1, 0);
        break;
    }
    case KD_MSG_GOAL_PATH: {
        const kinctl_goal_path_t *g = &m->goal_path;
        pi("utime", g->utime); pi("goal_id", g->goal_id); pi("mode", g->mode);
        pi("space", g->space); pi("method", g->method); pi("blend_shape", g->blend_shape);
        pi("spline_ends", g->spline_ends); pi("n_points", g->n_points); pi("dim", g->dim);
        printf("\"points\": [");
        for (i = 0; i < KINCTL_GOAL_PATH_T_MAX_POINTS; i++) {
            int j;
            printf("%s[", i ? ", " : "");
            for (j = 0; j < 16; j++)
                printf("%s%.17g", j ? ", " : "", g->points[i][j]);
            printf("]");
        }
        printf("], ");
        pi("has_times", g->has_times); pd("times", g->times, KINCTL_GOAL_PATH_T_MAX_POINTS, 1);
        pd("blend_time", &g->blend_time, 1, 0); pd("speed", &g->speed, 1, 0);
        pd("accel", &g->accel, 1, 0); pd("jerk", &g->jerk, 1, 0);
        pd("angular_jerk", &g->angular_jerk, 1, 0); pd("vel_scale", &g->vel_scale, 1, 0);
        pd("acc_scale", &g->acc_scale, 1, 0);
        break;
    }
    case KD_MSG_GOAL_SERVO: {
        const kinctl_goal_servo_t *g = &m->goal_servo;
        pi("utime", g->utime); pi("goal_id", g->goal_id); pi("mode", g->mode); pi("kind", g->kind);
        pd("position", g->position, 3, 1); pd("orientation", g->orientation, 4, 1);
        pd("twist", g->twist, 6, 1); pi("timeout_us", g->timeout_us);
        break;
    }
    case KD_MSG_COMMAND:
        pi("utime", m->command.utime); pi("command", m->command.command);
        break;
    case KD_MSG_SETPOINT: {
        const kinctl_setpoint_t *p = &m->setpoint;
        pi("utime", p->utime); pi("cycle", p->cycle); pi("goal_id", p->goal_id);
        pi("state", p->state); pi("n", p->n);
        pd("q", p->q, 16, 1); pd("qd", p->qd, 16, 1); pd("qdd", p->qdd, 16, 1);
        pd("position", p->position, 3, 1); pd("orientation", p->orientation, 4, 1);
        pi("input_goal_id", p->input_goal_id); pi("input_command", p->input_command);
        pi("input_servo_stale", p->input_servo_stale);
        pi("input_fault", p->input_fault); pi("input_seated", p->input_seated);
        pd("input_goal_share", &p->input_goal_share, 1, 0); pi("input_goal_stop_first", p->input_goal_stop_first);
        pd("input_goal_qu", &p->input_goal_qu, 1, 0);
        pi("input_goal_scheduled", p->input_goal_scheduled); pi("input_goal_take_ahead", p->input_goal_take_ahead);
        pi("input_goal_take_state", p->input_goal_take_state);
        break;
    }
    case KD_MSG_STATUS: {
        const kinctl_status_t *p = &m->status;
        const char *c;
        pi("utime", p->utime); pi("cycle", p->cycle); pi("state", p->state);
        pi("active_goal_id", p->active_goal_id); pd("progress", &p->progress, 1, 0);
        pi("queue_length", p->queue_length); pi("event", p->event);
        pi("event_goal_id", p->event_goal_id); pi("code", p->code);
        printf("\"reason\": \"");
        for (c = p->reason; *c; c++) {
            if (*c == '"' || *c == '\\')
                printf("\\%c", *c);
            else if ((unsigned char)*c < 0x20)
                printf("\\u%04x", (unsigned)(unsigned char)*c);
            else
                putchar(*c);
        }
        printf("\", ");
        pi("n", p->n); pd("q_measured", p->q_measured, 16, 1);
        pd("qd_measured", p->qd_measured, 16, 1);
        pi("can_state", p->can_state); pi("drives", p->drives);
        pi("joint", p->joint); pi("joint_prismatic", p->joint_prismatic);
        pd("joint_value", &p->joint_value, 1, 0); pd("joint_lower", &p->joint_lower, 1, 0);
        pd("joint_upper", &p->joint_upper, 1, 0);
        printf("\"prismatic\": [");
        for (i = 0; i < KINCTL_STATUS_T_MAX_JOINTS; i++)
            printf("%s%d", i ? ", " : "", (int)p->prismatic[i]);
        printf("], ");
        break;
    }
    case KD_MSG_STATS: {
        const kinctl_stats_t *p = &m->stats;
        pi("utime", p->utime); pi("period_ns", p->period_ns); pi("cycles", p->cycles);
        pi("latency_p50_ns", p->latency_p50_ns); pi("latency_p99_ns", p->latency_p99_ns);
        pi("latency_p999_ns", p->latency_p999_ns); pi("latency_max_ns", p->latency_max_ns);
        pi("compute_p50_ns", p->compute_p50_ns); pi("compute_p99_ns", p->compute_p99_ns);
        pi("compute_max_ns", p->compute_max_ns); pi("overruns", p->overruns);
        pi("msgs_in", p->msgs_in); pi("msgs_invalid", p->msgs_invalid);
        pi("msgs_out", p->msgs_out); pi("msgs_dropped", p->msgs_dropped);
        pi("rejections", p->rejections); pi("can_frames", p->can_frames);
        pi("can_errors", p->can_errors); pi("can_state", p->can_state);
        pi("can_tx_dropped", p->can_tx_dropped); pi("can_error_frames", p->can_error_frames);
        pi("can_bus_off", p->can_bus_off); pi("can_link_down", p->can_link_down);
        pi("can_rx_frames", p->can_rx_frames);
        break;
    }
    case KD_MSG_TYPE_COUNT: break;
    }
    printf("\"type\": \"%s\"}\n", kd_msg_type_info(t)->name);
}

/* Decodes stdin into *m; status_t (which allocates its reason) through the
 * generated decoder. Exits 2 with the reason when refused. */
static void decode_stdin(kd_msg_type t, kd_msg_any *m)
{
    size_t len = fread(in, 1, sizeof in, stdin);
    char reason[KD_MSG_REASON_SIZE];
    kd_msg_status s;
    if (t == KD_MSG_STATUS) {
        if (kinctl_status_t_decode(in, 0, (int)len, &m->status) != (int)len) {
            fprintf(stderr, "decode failed: status_t\n");
            exit(2);
        }
        return;
    }
    s = kd_msg_decode(t, in, len, m, reason, sizeof reason);
    if (s != KD_MSG_OK) {
        fprintf(stderr, "%s: %s\n", kd_msg_status_str(s), reason);
        exit(2);
    }
}

int main(int argc, char **argv)
{
    static kd_msg_any m;
    static unsigned char out[KD_MSG_MAX_SIZE + 512];
    static char reason[64];
    kd_msg_type t = KD_MSG_TYPE_COUNT;
    size_t len = 0;
    int i;

    kd_msg_init();
    if (argc < 3) {
        fprintf(stderr, "usage: msgtool decode|roundtrip TYPE < datagram\n"
                        "       msgtool sample TYPE SEED > datagram\n");
        return 1;
    }
    for (i = 0; i < KD_MSG_TYPE_COUNT; i++)
        if (strcmp(argv[2], kd_msg_type_info((kd_msg_type)i)->name) == 0)
            t = (kd_msg_type)i;
    if (t == KD_MSG_TYPE_COUNT) {
        fprintf(stderr, "msgtool: unknown type %s\n", argv[2]);
        return 1;
    }
    if (strcmp(argv[1], "decode") == 0) {
        decode_stdin(t, &m);
        print_json(t, &m);
    } else if (strcmp(argv[1], "roundtrip") == 0) {
        decode_stdin(t, &m);
        if (kd_msg_encode(t, &m, out, sizeof out, &len) != KD_MSG_OK)
            return 3;
        fwrite(out, 1, len, stdout);
    } else if (strcmp(argv[1], "sample") == 0 && argc > 3) {
        msg_sample(t, (uint32_t)strtoul(argv[3], NULL, 10), &m, reason);
        if (kd_msg_encode(t, &m, out, sizeof out, &len) != KD_MSG_OK)
            return 3;
        fwrite(out, 1, len, stdout);
        return 0;
    } else {
        fprintf(stderr, "msgtool: unknown command %s\n", argv[1]);
        return 1;
    }
    if (t == KD_MSG_STATUS)
        kinctl_status_t_decode_cleanup(&m.status);
    return 0;
}
