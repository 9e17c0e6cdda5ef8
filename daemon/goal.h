/* goal.h - client goal messages (decoded and validated by daemon/msg) turned
 * into the controller's kc_goal, and the daemon's rejection reasons.
 *
 * A rejection travels back in status_t as event REJECTED with
 *   code    a kc_status (negative), kd_reason_code() of the reason;
 *   reason  "<token>: <readable detail>", the token one of
 *           bad_goal joint_count joint_limit queue_full state plan
 *           unreachable tracking limit_guard servo_timeout external overrun
 *           shutdown drive can
 *           (kd_reason_token), so that tools can match it and people read it:
 *           "joint_count: goal_joint_t.n = 5, the arm has 6 joints".
 *
 * What is judged here (the arm-dependent parts the message layer leaves):
 * joint count, joint targets inside the limits (with the joint named),
 * unit quaternions (|norm - 1| <= 1e-3, then normalised), knot counts the
 * controller can hold. Reachability and the rest is kc_ctrl_check's.
 * Not for the cycle (it formats text); for the I/O thread.
 */
#ifndef KINCTL_DAEMON_GOAL_H
#define KINCTL_DAEMON_GOAL_H

#include <stddef.h>
#include <stdint.h>

#include "kinctl/ctrl.h"
#include "msg.h"

#define KD_REASON_TEXT 256

/* Daemon-side reasons beyond kc_ctrl_reason. */
#define KD_REASON_OVERRUN ((kc_ctrl_reason)(KC_REASON_COUNT + 1))
#define KD_REASON_SHUTDOWN ((kc_ctrl_reason)(KC_REASON_COUNT + 2))
#define KD_REASON_DRIVE ((kc_ctrl_reason)(KC_REASON_COUNT + 3))   /* a drive on CAN: fault, silent, lagging */
#define KD_REASON_CAN ((kc_ctrl_reason)(KC_REASON_COUNT + 4))     /* the CAN bus: bus-off, interface down */

typedef struct kd_reject {
    kc_ctrl_reason reason;
    kc_status code;
    char text[KD_REASON_TEXT];
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

/* The goal_id of a raw datagram of a goal type (bytes 16..23: after the
 * fingerprint and utime), whatever else is wrong with it; 0 when the type
 * carries none or the datagram is too short. */
int64_t kd_goal_id_peek(kd_msg_type type, const void *buf, size_t len);

/* Converts a goal message of type (KD_MSG_GOAL_*) into *goal for chain.
 * For a servo goal, *servo_timeout_ns receives its staleness timeout capped
 * at servo_timeout_max_s. Returns 0, or -1 with *rej filled and *goal
 * unspecified. */
int kd_goal_from_msg(kd_msg_type type, const kd_msg_any *msg, const kc_chain *chain, double servo_timeout_max_s,
                     kc_goal *goal, int64_t *servo_timeout_ns, kd_reject *rej);

#endif
