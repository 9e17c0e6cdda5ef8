/* ctrl_goal.c - the cheap checks of a goal and the texts of the reasons
 * (kinctl/ctrl.h). */
#include "ctrl_internal.h"

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
    case KC_REASON_TRACKING: return "the tool fell behind the Cartesian path";
    case KC_REASON_LIMIT_GUARD: return "a setpoint failed the final limit check";
    case KC_REASON_SERVO_TIMEOUT: return "the servo stream went quiet";
    case KC_REASON_DUPLICATE_ID: return "a goal with this id is already active or queued";
    case KC_REASON_EXTERNAL: return "an external device (a drive, the field bus) reported a fault";
    case KC_REASON_ZONE: return "a link volume would enter the margin of a forbidden zone";
    case KC_REASON_COUNT: break;
    }
    return "unknown reason";
}

static int pose_ok(const kc_pose *p)
{
    return kc_pose_isfinite(p) && kc_mat3_rotation_error(&p->R) <= KC_TOL_ORTHONORMAL;
}

static int scale_ok(kc_real s) { return kc_isfinite(s) && s > KC_R(0.0) && s <= KC_R(1.0); }

kc_status kc_ctrl_refuse(kc_ctrl_reason *reason, kc_ctrl_reason why)
{
    if (reason != NULL)
        *reason = why;
    return KC_E_ARG;
}

kc_status kc_ctrl_goal_check(const kc_chain *chain, const kc_goal *g, kc_ctrl_reason *reason)
{
    if (chain == NULL || g == NULL)
        return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
    int n = chain->n_joints;
    if ((unsigned)g->kind > (unsigned)KC_GOAL_SERVO || !scale_ok(g->vel_scale) || !scale_ok(g->acc_scale))
        return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
    if (!kc_isfinite(g->speed) || g->speed < KC_R(0.0) || !kc_isfinite(g->accel) || g->accel < KC_R(0.0) ||
        !kc_isfinite(g->omega) || g->omega < KC_R(0.0) || !kc_isfinite(g->alpha) || g->alpha < KC_R(0.0))
        return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
    switch (g->kind) {
    case KC_GOAL_JOINT: {
        int bad = 0;
        kc_status st = kc_chain_check_q(chain, g->q, &bad);
        if (st == KC_E_LIMIT)
            return kc_ctrl_refuse(reason, KC_REASON_JOINT_LIMIT);
        if (st != KC_OK)
            return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
        break;
    }
    case KC_GOAL_LINE:
        if (!pose_ok(&g->pose) || (g->orient != KC_INTERP_TWO_ROTATIONS && g->orient != KC_INTERP_SLERP))
            return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
        break;
    case KC_GOAL_ARC:
        if (!kc_vec3_isfinite(&g->pose.t) || !kc_vec3_isfinite(&g->via))
            return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
        break;
    case KC_GOAL_PATH:
    case KC_GOAL_PATH_CART: {
        int dim = g->kind == KC_GOAL_PATH ? n : 7;
        if (g->n_points < 1 || g->n_points > KC_PATH_MAX_KNOTS - 1 ||
            (unsigned)g->method > (unsigned)KC_PATH_QUINTIC || (unsigned)g->blend > (unsigned)KC_PATH_BLEND_PARABOLIC ||
            (unsigned)g->spline_end > (unsigned)KC_PATH_SPLINE_NATURAL || !kc_isfinite(g->blend_time) ||
            g->blend_time < KC_R(0.0))
            return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
        for (int i = 0; i < g->n_points; i++) {
            for (int j = 0; j < dim; j++)
                if (!kc_isfinite(g->points[i][j]))
                    return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
            if (g->kind == KC_GOAL_PATH) {
                int bad = 0;
                if (kc_chain_check_q(chain, g->points[i], &bad) != KC_OK)
                    return kc_ctrl_refuse(reason, KC_REASON_JOINT_LIMIT);
            }
            if (g->has_times && (!kc_isfinite(g->times[i]) || g->times[i] <= (i > 0 ? g->times[i - 1] : KC_R(0.0))))
                return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
        }
        break;
    }
    case KC_GOAL_SERVO:
        if (g->servo_twist) {
            for (int i = 0; i < 6; i++)
                if (!kc_isfinite(g->twist[i]))
                    return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
        } else if (!pose_ok(&g->pose)) {
            return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
        }
        break;
    }
    if (reason != NULL)
        *reason = KC_REASON_NONE;
    return KC_OK;
}
