/* SPDX-License-Identifier: BSD-3-Clause */
/* reject.c - reasons' tokens and codes, and a goal's rejection text from
 * the core's verdict (reject.h). */
#include "reject.h"

#include <stdarg.h>
#include <stdio.h>

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
    case KC_REASON_STOP_FIRST: return "stop_first";
    case KC_REASON_LATE: return "late";
    case (int)KD_REASON_OVERRUN: return "overrun";
    case (int)KD_REASON_SHUTDOWN: return "shutdown";
    case KC_REASON_EXTERNAL: return "external";
    case (int)KD_REASON_DRIVE: return "drive";
    case (int)KD_REASON_CAN: return "can";
    case (int)KD_REASON_CHECK_BUDGET: return "check_budget";
    case (int)KD_REASON_JERK: return "jerk";
    case (int)KD_REASON_STOPPED: return "stopped";
    default: return "unknown";
    }
}

kc_status kd_reason_code(kc_ctrl_reason reason)
{
    switch ((int)reason) {
    case KC_REASON_NONE:
    case KC_REASON_STOP_FIRST:                 /* an ACCEPTED's note, not a failure */
    case (int)KD_REASON_STOPPED: return KC_OK; /* ended as the caller asked */
    case KC_REASON_BAD_GOAL:
    case KC_REASON_JOINT_COUNT:
    case KC_REASON_PLAN: return KC_E_ARG;
    case KC_REASON_JOINT_LIMIT:
    case KC_REASON_ZONE:
    case KC_REASON_LIMIT_GUARD:
    case (int)KD_REASON_JERK: return KC_E_LIMIT;
    case KC_REASON_QUEUE_FULL:
    case (int)KD_REASON_CHECK_BUDGET: return KC_E_CAPACITY;
    case KC_REASON_UNREACHABLE:
    case KC_REASON_TRACKING: return KC_E_UNREACHABLE;
    case KC_REASON_STATE:
    case KC_REASON_LATE:
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
    rej->joint = rej->prismatic = 0;
    rej->value = rej->lower = rej->upper = 0.0;
    n = snprintf(rej->text, sizeof rej->text, "%s: ", kd_reason_token(reason));
    if (n < 0 || (size_t)n >= sizeof rej->text)
        return;
    va_start(ap, fmt);
    (void)vsnprintf(rej->text + n, sizeof rej->text - (size_t)n, fmt, ap);
    va_end(ap);
}

/* The wire type a goal kind came in. */
static const char *wire_name(kc_goal_kind kind)
{
    switch (kind) {
    case KC_GOAL_JOINT: return "goal_joint_t";
    case KC_GOAL_LINE: return "goal_line_t";
    case KC_GOAL_ARC: return "goal_arc_t";
    case KC_GOAL_PATH:
    case KC_GOAL_PATH_CART: return "goal_path_t";
    case KC_GOAL_SERVO: return "goal_servo_t";
    }
    return "goal";
}

/* A target outside its joint's limits: the joint move's q[j] or the path's
 * points[i][j]. */
static void limit_text(kd_reject *rej, const kd_config *cfg, const kc_goal *g, const kc_verdict *v)
{
    const kc_joint_limits *l = &cfg->chain.joints[v->joint].limits;
    if (v->point >= 0)
        kd_reject_set(rej, v->reason, "%s.points[%d][%d] = %.9g is outside joint %d's limits [%.9g, %.9g]",
                      wire_name(g->kind), v->point, v->joint, (double)v->value, v->joint + 1, (double)l->q_min,
                      (double)l->q_max);
    else
        kd_reject_set(rej, v->reason, "%s.q[%d] = %.9g is outside joint %d's limits [%.9g, %.9g]", wire_name(g->kind),
                      v->joint, (double)v->value, v->joint + 1, (double)l->q_min, (double)l->q_max);
    rej->joint = v->joint + 1;
    rej->prismatic = cfg->chain.joints[v->joint].type == KC_JOINT_PRISMATIC;
    rej->value = (double)v->value;
    rej->lower = (double)l->q_min;
    rej->upper = (double)l->q_max;
}

void kd_reject_verdict(kd_reject *rej, const kd_config *cfg, const kc_goal *g, const kc_verdict *v)
{
    kc_ctrl_reason reason = v->reason != KC_REASON_NONE ? v->reason : KC_REASON_BAD_GOAL;
    const char *why = kc_ctrl_reason_str(v->reason);
    if (reason == KC_REASON_JOINT_COUNT)
        kd_reject_set(rej, reason, "%s.%s = %d, the arm has %d joints", wire_name(g->kind),
                      g->kind == KC_GOAL_JOINT ? "n" : "dim", (int)v->value, cfg->chain.n_joints);
    else if (reason == KC_REASON_JOINT_LIMIT && v->joint >= 0 && v->joint < cfg->chain.n_joints)
        limit_text(rej, cfg, g, v);
    else if (reason == KC_REASON_BAD_GOAL && v->field == KC_FIELD_ORIENTATION && kc_isfinite(v->value))
        kd_reject_set(rej, reason, "%s.orientation is not a unit quaternion (norm %.9g)", wire_name(g->kind),
                      (double)v->value);
    else if (reason == KC_REASON_BAD_GOAL && v->field == KC_FIELD_N_POINTS)
        kd_reject_set(rej, reason, "%s.n_points = %d, expected 1 .. %d", wire_name(g->kind), (int)v->value,
                      KC_PATH_MAX_KNOTS - 1);
    else if (reason == KD_REASON_JERK)
        kd_reject_jerk(rej, cfg, (double)v->jerk, 1.0, g->stop_first, 0);
    else if (reason == KC_REASON_LATE)
        kd_reject_set(rej, reason, "no fresh snapshot of the moving controller came to judge it from: send it again");
    else if (reason == KC_REASON_QUEUE_FULL)
        kd_reject_set(rej, reason, "the controller's goal queue (%d goals) is full", (int)v->value);
    else if (reason == KC_REASON_ZONE) {
        char pair[256];
        kd_config_zone_pair(cfg, v->zone, v->volume, pair, sizeof pair);
        kd_reject_set(rej, reason, "%s: %s (%.4g m, at %.6g)", why, pair, (double)v->distance, (double)v->where);
    } else if (reason == KC_REASON_UNREACHABLE || reason == KC_REASON_TRACKING)
        kd_reject_set(rej, reason, "%s (%s at %.6g)", why, kc_status_str(v->status), (double)v->where);
    else
        kd_reject_set(rej, reason, "%s (%s)", why, kc_status_str(v->status));
}

void kd_reject_jerk(kd_reject *rej, const kd_config *cfg, double jerk, double slowed, int stop_first, int cut)
{
    char how[64] = "", budget[96] = "";
    if (slowed < 1.0)
        snprintf(how, sizeof how, " at %.3g of its speed", slowed);
    if (cut)
        snprintf(budget, sizeof budget, "; controller.check_budget_ms = %.6g ran out before a slower one was judged",
                 cfg->check_budget_s * 1e3);
    kd_reject_set(rej, KD_REASON_JERK, "its joints' jerk would reach %.3g times their limits (qddd)%s%s%s", jerk, how,
                  stop_first ? ", stopping the motion it replaces first" : "", budget);
}

void kd_reject_budget(kd_reject *rej, const kd_config *cfg, int64_t elapsed_ns, int64_t ticks, kc_real progress)
{
    kd_reject_set(rej, KD_REASON_CHECK_BUDGET,
                  "dry run stopped after %.0f ms at %.0f %% of the motion (%lld ticks; controller.check_budget_ms = %.6g)",
                  (double)elapsed_ns * 1e-6, 100.0 * (double)progress, (long long)ticks, cfg->check_budget_s * 1e3);
}
