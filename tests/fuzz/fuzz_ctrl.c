/* SPDX-License-Identifier: BSD-3-Clause */
/* fuzz_ctrl.c - the planner and controller step: random sequences of goals
 * (finite and not), commands and ticks through kc_ctrl_step on puma560.
 * External faults (a drive, the bus) come now and then too.
 * Invariants, every tick: the step succeeds; every setpoint is finite,
 * inside the position limits, within the velocity limits, and its velocity
 * changes by at most qdd_max dt (the slack of ctrl.h's final check). Every
 * goal given is answered in its tick, exactly once, ACCEPTED or REJECTED
 * (a servo update of the active servo excepted); every accepted goal ends
 * at most once (COMPLETED, PREEMPTED or ABORTED), and at the end of the
 * input the accepted goals not ended are exactly the queued and the active
 * one: no event is lost. */
#include <math.h>
#include <string.h>

#include "fuzz_check.h"
#include "kinctl/ctrl.h"
#include "kinctl/fk.h"

/* Ticks one input may run: enough for goals to start, stop, be preempted
 * and fault, few enough for thousands of inputs a second. */
#define MAX_TICKS 400
#define MAX_GOALS 64

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static kc_chain chain;
static int trace; /* KINCTL_FUZZ_TRACE=1: print every event (to study a finding) */
static kc_ctrl ctrl; /* large: not on the stack */
static const kc_real Q0[6] = {KC_R(0.1), KC_R(0.8), KC_R(-2.4), KC_R(0.1), KC_R(0.6), KC_R(0.2)};

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    FUZZ_CHECK(kc_chain_init_model(&chain, KC_MODEL_PUMA560, NULL) == KC_OK, "puma560");
    trace = getenv("KINCTL_FUZZ_TRACE") != NULL;
    return 0;
}

typedef struct input {
    const uint8_t *p;
    size_t n;
} input;

static unsigned byte(input *in)
{
    if (in->n == 0)
        return 0;
    in->n--;
    return *in->p++;
}

/* A number in [lo, hi] from two bytes, or (tag 255) any double at all. */
static kc_real number(input *in, double lo, double hi)
{
    unsigned tag = byte(in);
    if (tag == 255) {
        double raw = 0;
        uint8_t b[8] = {0};
        for (int i = 0; i < 8; i++)
            b[i] = (uint8_t)byte(in);
        memcpy(&raw, b, sizeof raw);
        return (kc_real)raw;
    }
    unsigned v = (tag << 8) | byte(in);
    return (kc_real)(lo + (hi - lo) * (double)v / 65279.0);
}

static void pose_near(input *in, const kc_pose *here, kc_pose *out)
{
    kc_quat r;
    out->t = kc_vec3_make(here->t.v[0] + number(in, -0.4, 0.4), here->t.v[1] + number(in, -0.4, 0.4),
                          here->t.v[2] + number(in, -0.4, 0.4));
    r.w = number(in, -1, 1);
    r.x = number(in, -1, 1);
    r.y = number(in, -1, 1);
    r.z = number(in, -1, 1);
    kc_real norm = kc_sqrt(r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
    if (byte(in) % 8 != 0 && norm > KC_R(1e-3)) { /* mostly unit quaternions */
        r.w /= norm;
        r.x /= norm;
        r.y /= norm;
        r.z /= norm;
    }
    kc_quat_to_mat3(&r, &out->R);
}

static void make_goal(input *in, int64_t id, kc_goal *g)
{
    int n = chain.n_joints;
    kc_pose here;
    kc_fk_eval(&chain, ctrl.q, &here);
    memset(g, 0, sizeof *g);
    g->id = id;
    g->kind = (kc_goal_kind)(byte(in) % 7); /* 6: an unknown kind */
    g->replace = (int)(byte(in) & 1);
    g->vel_scale = number(in, 0.0, 1.1);
    g->acc_scale = number(in, 0.0, 1.1);
    g->speed = number(in, -0.1, 2.0);
    g->accel = number(in, -0.1, 4.0);
    g->omega = number(in, -0.1, 4.0);
    g->alpha = number(in, -0.1, 10.0);
    g->orient = (kc_interp_orient)(byte(in) % 3);
    for (int j = 0; j < n; j++) {
        const kc_joint_limits *l = &chain.joints[j].limits;
        g->q[j] = number(in, (double)l->q_min - 0.2, (double)l->q_max + 0.2);
    }
    pose_near(in, &here, &g->pose);
    g->via = kc_vec3_make(here.t.v[0] + number(in, -0.4, 0.4), here.t.v[1] + number(in, -0.4, 0.4),
                          here.t.v[2] + number(in, -0.4, 0.4));
    g->method = (kc_path_method)(byte(in) % 7);
    g->blend = (kc_path_blend)(byte(in) % 3);
    g->spline_end = (kc_path_spline_end)(byte(in) % 3);
    g->n_points = (int)(byte(in) % (KC_PATH_MAX_KNOTS + 1));
    g->has_times = (int)(byte(in) & 1);
    g->blend_time = number(in, -0.05, 0.5);
    kc_real t = KC_R(0.0);
    /* Points: a few drawn, the rest repeat them shifted (cheap to encode). */
    for (int i = 0; i < g->n_points && i < KC_PATH_MAX_KNOTS - 1; i++) {
        if (i < 4 || in->n > 0) {
            if (g->kind == KC_GOAL_PATH_CART) {
                kc_pose p;
                kc_quat r;
                pose_near(in, &here, &p);
                kc_quat_from_mat3(&p.R, &r);
                kc_real v[7] = {p.t.v[0], p.t.v[1], p.t.v[2], r.w, r.x, r.y, r.z};
                memcpy(g->points[i], v, sizeof v);
            } else {
                for (int j = 0; j < n; j++) {
                    const kc_joint_limits *l = &chain.joints[j].limits;
                    g->points[i][j] = number(in, (double)l->q_min - 0.1, (double)l->q_max + 0.1);
                }
            }
        } else {
            memcpy(g->points[i], g->points[i % 4], sizeof g->points[i]);
        }
        t += number(in, -0.05, 1.0);
        g->times[i] = t;
    }
    g->servo_twist = (int)(byte(in) & 1);
    for (int i = 0; i < 6; i++)
        g->twist[i] = number(in, -0.3, 0.3);
    /* Last, so that the older fields take the same bytes: the controller's
     * motion law, the trapezoid, jerk-limited, or an unknown one. */
    g->profile = (kc_goal_profile)(byte(in) % 4);
}

typedef struct ledger {
    int64_t id;
    int answered, ended;
    int accepted;
} ledger;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    input in = {data, size};
    static ledger goals[MAX_GOALS];
    static kc_goal goal;
    int n_goals = 0, n = 0;
    kc_ctrl_cfg cfg = kc_ctrl_cfg_default();
    kc_ctrl_output out;
    kc_real qd_prev[KC_MAX_JOINTS] = {0};
    int64_t servo_id = 0, next_id = 1;
    FUZZ_CHECK(kc_ctrl_init(&ctrl, &chain, &cfg, Q0) == KC_OK, "init");
    n = chain.n_joints;

    for (int tick = 0; tick < MAX_TICKS && in.n > 0;) {
        unsigned op = byte(&in);
        int run = (int)(op & 0x3f) + 1; /* ticks until the next record */
        kc_ctrl_input step = {NULL, KC_CMD_NONE, (int)(op >> 6 == 2), KC_REASON_NONE};
        if ((op >> 6) == 3) {
            unsigned c = byte(&in);
            step.command = (kc_ctrl_command)(c % 7);
            if (c >= 0xf0) /* now and then a drive or the bus reports a fault */
                step.fault = KC_REASON_EXTERNAL;
        }
        int64_t given = 0, update_of = 0;
        if ((op >> 6) & 1 && n_goals < MAX_GOALS) {
            /* An update of the active servo (with no command in the same
             * tick, which could end the servo first and make the update a
             * new goal under an old id). */
            int update = servo_id != 0 && ctrl.active && ctrl.goal.kind == KC_GOAL_SERVO && ctrl.goal.id == servo_id &&
                         step.command == KC_CMD_NONE && (byte(&in) & 1);
            given = update ? servo_id : next_id++;
            make_goal(&in, given, &goal);
            if (update)
                goal.kind = KC_GOAL_SERVO;
            step.goal = &goal;
            if (!update) {
                goals[n_goals].id = given;
                goals[n_goals].answered = goals[n_goals].ended = goals[n_goals].accepted = 0;
                n_goals++;
            } else {
                update_of = servo_id;
            }
        }
        for (int k = 0; k < run && tick < MAX_TICKS; k++, tick++) {
            FUZZ_CHECK(kc_ctrl_step(&ctrl, &step, &out) == KC_OK, "step refused");
            for (int e = 0; e < out.n_events; e++) {
                const kc_ctrl_event *ev = &out.events[e];
                if (trace)
                    fprintf(stderr, "cycle %lld: event %d goal %lld reason %d (state %d, goal kind %d)\n",
                            (long long)out.cycle, (int)ev->kind, (long long)ev->goal_id, (int)ev->reason,
                            (int)out.state, (int)ctrl.goal.kind);
                ledger *l = NULL;
                for (int i = 0; i < n_goals; i++)
                    if (goals[i].id == ev->goal_id)
                        l = &goals[i];
                FUZZ_CHECK(l != NULL || ev->goal_id == 0, "event %d of unknown goal %lld", (int)ev->kind,
                           (long long)ev->goal_id);
                if (l == NULL || (ev->kind == KC_EVENT_REJECTED && ev->goal_id == update_of))
                    continue; /* a bad update is refused; the servo goes on */
                switch (ev->kind) {
                case KC_EVENT_ACCEPTED:
                case KC_EVENT_REJECTED:
                    FUZZ_CHECK(ev->goal_id == given && !l->answered, "goal %lld answered again or late",
                               (long long)ev->goal_id);
                    l->answered = 1;
                    l->accepted = ev->kind == KC_EVENT_ACCEPTED;
                    break;
                case KC_EVENT_COMPLETED:
                case KC_EVENT_PREEMPTED:
                case KC_EVENT_ABORTED:
                    FUZZ_CHECK(l->accepted && !l->ended, "goal %lld ended twice or unaccepted", (long long)l->id);
                    l->ended = 1;
                    break;
                default: break;
                }
            }
            if (given != 0) {
                FUZZ_CHECK(goals[n_goals - 1].answered, "goal %lld not answered in its tick", (long long)given);
                if (goal.kind == KC_GOAL_SERVO && goals[n_goals - 1].accepted)
                    servo_id = given;
            }
            for (int j = 0; j < n; j++) {
                const kc_joint_limits *lim = &chain.joints[j].limits;
                double q = (double)out.q[j], qd = (double)out.qd[j], s = (double)cfg.limit_slack;
                double range_slack = s * (fabs((double)lim->q_min) + fabs((double)lim->q_max) + 1.0);
                FUZZ_CHECK(isfinite(q) && isfinite(qd) && isfinite((double)out.qdd[j]), "joint %d not finite", j);
                FUZZ_CHECK(q >= (double)lim->q_min - range_slack && q <= (double)lim->q_max + range_slack,
                           "cycle %lld: q[%d] = %g outside the limits", (long long)out.cycle, j, q);
                FUZZ_CHECK(fabs(qd) <= (double)lim->qd_max * (1.0 + s), "cycle %lld: qd[%d] = %g", (long long)out.cycle,
                           j, qd);
                FUZZ_CHECK(fabs(qd - (double)qd_prev[j]) <=
                               (double)lim->qdd_max * (double)cfg.dt * (1.0 + s) + s * fabs((double)qd_prev[j]),
                           "cycle %lld: qd[%d] jumps from %g to %g", (long long)out.cycle, j, (double)qd_prev[j], qd);
                qd_prev[j] = out.qd[j];
            }
            FUZZ_CHECK(kc_pose_isfinite(&out.pose), "pose not finite");
            step.goal = NULL;
            step.command = KC_CMD_NONE;
            step.fault = KC_REASON_NONE;
            given = update_of = 0;
        }
    }
    /* Nothing lost: the accepted goals not ended are the queue and the
     * active one (an aborted goal stays active while it stops on its path:
     * it is no longer open). */
    int open = 0, active_open = 0;
    for (int i = 0; i < n_goals; i++) {
        open += goals[i].accepted && !goals[i].ended;
        if (ctrl.active && goals[i].id == ctrl.goal.id && !goals[i].ended)
            active_open = 1;
    }
    FUZZ_CHECK(open == ctrl.queue_len + active_open, "%d goals open, %d queued, active %d", open, ctrl.queue_len,
               active_open);
    return 0;
}
