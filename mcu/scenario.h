/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * scenario.h - one goal of every kind for a PUMA 560 starting at rest at
 * scn_q0: the workload the bare-metal programs share (the determinism hash
 * in ctrl_hash.c, the instruction counts in bench.c), so the board and the
 * host run exactly the same goals.
 */
#ifndef KINCTL_MCU_SCENARIO_H
#define KINCTL_MCU_SCENARIO_H

#include "kinctl/kinctl.h"

/* Goal kinds in the order they are run: joint, line, arc, joint path,
 * Cartesian path, servo. */
#define SCN_KINDS 6
extern const kc_goal_kind scn_kinds[SCN_KINDS];
extern const char *const scn_kind_names[SCN_KINDS];

/* The start configuration (rad), inside the PUMA 560's limits. */
extern const kc_real scn_q0[6];

/* Ticks a servo goal is streamed before the stream goes quiet. */
#define SCN_SERVO_TICKS 300

/* Fills g with the goal of that kind, id id, relative to the tool pose
 * `here` where it starts; a servo goal's target at tick k of its stream
 * (0 <= k < SCN_SERVO_TICKS) moves along y at 0.1 m/s. */
void scn_goal(kc_goal *g, kc_goal_kind kind, int64_t id, const kc_pose *here, int k);

#endif /* KINCTL_MCU_SCENARIO_H */
