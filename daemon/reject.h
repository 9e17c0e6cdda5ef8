/* SPDX-License-Identifier: BSD-3-Clause */
/* reject.h - the daemon's answers that refuse or report: a reason's token
 * and code, and the one place a goal's rejection text is formed, from the
 * core's verdict (kinctl/ctrl.h kc_verdict).
 *
 * A rejection travels back in status_t as event REJECTED with
 *   code    a kc_status (negative), kd_reason_code() of the reason;
 *   reason  "<token>: <readable detail>", the token one of
 *           bad_goal joint_count joint_limit queue_full state plan
 *           unreachable tracking limit_guard servo_timeout duplicate_id
 *           zone external overrun shutdown drive can check_budget
 *           (kd_reason_token), so that tools can match it and people read it:
 *           "joint_count: goal_joint_t.n = 5, the arm has 6 joints".
 * An ACCEPTED may carry a reason too, with code 0: stop_first (a replacing
 * goal waits while the motion it replaces stops on its path).
 * Not for the cycle (it formats text); for the I/O thread.
 */
#ifndef KINCTL_DAEMON_REJECT_H
#define KINCTL_DAEMON_REJECT_H

#include "config.h"
#include "kinctl/ctrl.h"

#define KD_REASON_TEXT 256

/* Daemon-side reasons beyond kc_ctrl_reason. */
#define KD_REASON_OVERRUN ((kc_ctrl_reason)(KC_REASON_COUNT + 1))
#define KD_REASON_SHUTDOWN ((kc_ctrl_reason)(KC_REASON_COUNT + 2))
#define KD_REASON_DRIVE ((kc_ctrl_reason)(KC_REASON_COUNT + 3))   /* a drive on CAN: fault, silent, lagging */
#define KD_REASON_CAN ((kc_ctrl_reason)(KC_REASON_COUNT + 4))     /* the CAN bus: bus-off, interface down */
#define KD_REASON_CHECK_BUDGET ((kc_ctrl_reason)(KC_REASON_COUNT + 5)) /* a dry run longer than its budget */
/* a jerk-limited Cartesian goal whose joints' jerk the dry run finds beyond
 * their limits at every share of its speed tried, stopping first too */
#define KD_REASON_JERK ((kc_ctrl_reason)(KC_REASON_COUNT + 6))
/* a STOP or ESTOP command ended the goal (its ABORTED, code 0) */
#define KD_REASON_STOPPED ((kc_ctrl_reason)(KC_REASON_COUNT + 7))

typedef struct kd_reject {
    kc_ctrl_reason reason;
    kc_status code;
    char text[KD_REASON_TEXT];
    /* A joint's limit at fault (status_t.joint..): the joint, 1-based (0:
     * none), prismatic or not, the value and the limits (rad or m). */
    int joint, prismatic;
    double value, lower, upper;
} kd_reject;

/* The stable token of a reason ("joint_limit"); "unknown" for others. */
const char *kd_reason_token(kc_ctrl_reason reason);

/* The kc_status sent as status_t.code for a reason. */
kc_status kd_reason_code(kc_ctrl_reason reason);

/* Fills rej: reason, its code, and "<token>: <detail>". */
void kd_reject_set(kd_reject *rej, kc_ctrl_reason reason, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* The rejection of goal g (converted by kd_goal_from_msg, judged by the
 * core) from its verdict v: the field, knot and joint at fault with the
 * wire's names ("goal_path_t.points[2][1] = 3.1 is outside joint 2's
 * limits [...]"), the zone pair by name, where along the motion the dry run
 * failed. cfg names the arm's joints, limits, zones and volumes. */
void kd_reject_verdict(kd_reject *rej, const kd_config *cfg, const kc_goal *g, const kc_verdict *v);

/* The rejection of a goal whose joints' jerk would reach `jerk` times
 * their limits (KD_REASON_JERK) as judged at its best: at `slowed` of its
 * speed (1: as asked), stopping the motion it replaces first or not;
 * `cut` when the budget (controller.check_budget_ms) ran out before a
 * slower one was judged. */
void kd_reject_jerk(kd_reject *rej, const kd_config *cfg, double jerk, double slowed, int stop_first, int cut);

/* The rejection of a goal whose dry run was stopped by its budget
 * (controller.check_budget_ms) after elapsed_ns, ticks dry-run ticks in,
 * the motion at progress (0..1). */
void kd_reject_budget(kd_reject *rej, const kd_config *cfg, int64_t elapsed_ns, int64_t ticks, kc_real progress);

#endif
