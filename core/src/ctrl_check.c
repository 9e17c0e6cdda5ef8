/* ctrl_check.c - the dry run of a goal (kinctl/ctrl.h). */
#include "ctrl_internal.h"

#include <string.h>

kc_status kc_ctrl_check(kc_ctrl *scratch, const kc_chain *chain, const kc_ctrl_cfg *cfg, const kc_goal *goal,
                        const kc_real *q_start, int64_t max_ticks, kc_real *q_end, kc_ctrl_reason *reason,
                        kc_real *where)
{
    kc_ctrl_reason why = KC_REASON_NONE;
    if (where != NULL)
        *where = KC_R(0.0);
    if (scratch == NULL || goal == NULL || q_end == NULL || max_ticks < 1 || chain == NULL || q_start == NULL ||
        chain->n_joints < 1 || chain->n_joints > KC_MAX_JOINTS)
        return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
    /* A start outside the position limits (an arm a stop carried past one)
     * is judged from where it is: the scratch controller starts inside and
     * is then put there. */
    kc_real inside[KC_MAX_JOINTS];
    for (int j = 0; j < chain->n_joints; j++) {
        if (!kc_isfinite(q_start[j]))
            return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
        inside[j] = kc_clamp(q_start[j], chain->joints[j].limits.q_min, chain->joints[j].limits.q_max);
    }
    if (kc_ctrl_init(scratch, chain, cfg, inside) != KC_OK)
        return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL);
    memcpy(scratch->q, q_start, sizeof(kc_real) * (size_t)chain->n_joints);
    if (kc_ctrl_goal_check(chain, goal, &why) != KC_OK)
        return kc_ctrl_refuse(reason, why);
    if (goal->kind == KC_GOAL_SERVO) {
        /* A servo target is judged tick by tick as it moves. */
        memcpy(q_end, q_start, sizeof(kc_real) * (size_t)chain->n_joints);
        if (reason != NULL)
            *reason = KC_REASON_NONE;
        return KC_OK;
    }
    if (goal->kind == KC_GOAL_JOINT && !kc_ctrl_zones_on(scratch)) {
        /* A joint move is exactly its plan: the plan is the whole check
         * (with zones, its ticks are stepped like any other goal's). */
        kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS];
        kc_ctrl_scaled_limits(scratch, goal, vmax, amax);
        if (kc_interp_joint_plan(&scratch->plan.joint, chain->n_joints, q_start, goal->q, vmax, amax, KC_R(0.0),
                                 cfg->dt) != KC_OK)
            return kc_ctrl_refuse(reason, KC_REASON_PLAN);
        memcpy(q_end, goal->q, sizeof(kc_real) * (size_t)chain->n_joints);
        if (reason != NULL)
            *reason = KC_REASON_NONE;
        return KC_OK;
    }
    kc_goal g = *goal;
    g.replace = 0;
    kc_ctrl_input in = {&g, KC_CMD_NONE, 0, KC_REASON_NONE};
    kc_ctrl_output out;
    for (int64_t k = 0; k < max_ticks; k++) {
        if (kc_ctrl_step(scratch, &in, &out) != KC_OK)
            return kc_ctrl_refuse(reason, KC_REASON_BAD_GOAL); /* not reached: scratch was initialised above */
        in.goal = NULL;
        for (int e = 0; e < out.n_events; e++) {
            const kc_ctrl_event *ev = &out.events[e];
            if (ev->kind == KC_EVENT_COMPLETED) {
                memcpy(q_end, scratch->q, sizeof(kc_real) * (size_t)chain->n_joints);
                if (reason != NULL)
                    *reason = KC_REASON_NONE;
                return KC_OK;
            }
            if (ev->kind == KC_EVENT_REJECTED || ev->kind == KC_EVENT_ABORTED || ev->kind == KC_EVENT_FAULT) {
                if (reason != NULL)
                    *reason = ev->reason == KC_REASON_TRACKING ? KC_REASON_UNREACHABLE : ev->reason;
                if (where != NULL)
                    *where = ev->where;
                return ev->reason == KC_REASON_PLAN || ev->kind == KC_EVENT_REJECTED ? KC_E_ARG : KC_E_UNREACHABLE;
            }
        }
    }
    if (reason != NULL)
        *reason = KC_REASON_PLAN;
    return KC_E_CAPACITY;
}
