/* SPDX-License-Identifier: BSD-3-Clause */
/* goal.h - client goal messages (decoded and validated by daemon/msg) turned
 * into the controller's kc_goal.
 *
 * Conversion only: the wire's fields into kc_goal's, the counts the client
 * gave kept in kc_goal.dim and n_points, scales of 0 taken as 1, unit
 * quaternions (|norm - 1| <= 1e-3, then normalised) into rotation matrices,
 * a servo timeout capped. Everything that depends on the arm (joint count,
 * limits, knot counts, reachability, zones) is judged once, in the core
 * (kc_ctrl_goal_check and the dry run, kinctl/check.h); the rejection text
 * comes from that verdict (reject.h). Not for the cycle; for the I/O
 * thread.
 */
#ifndef KINCTL_DAEMON_GOAL_H
#define KINCTL_DAEMON_GOAL_H

#include <stddef.h>
#include <stdint.h>

#include "kinctl/ctrl.h"
#include "msg.h"

/* Converts a goal message of type (KD_MSG_GOAL_*) into *goal. For a servo
 * goal, *servo_timeout_ns receives its staleness timeout capped at
 * servo_timeout_max_s. Returns 0 with *verdict taking the goal so far, or
 * -1 with *verdict saying what could not be converted (KC_REASON_BAD_GOAL:
 * KC_FIELD_ORIENTATION with the quaternion's norm as value, or no goal
 * type); goal->id is set in either case, the rest of *goal unspecified on
 * -1. */
int kd_goal_from_msg(kd_msg_type type, const kd_msg_any *msg, double servo_timeout_max_s, kc_goal *goal,
                     int64_t *servo_timeout_ns, kc_verdict *verdict);

#endif
