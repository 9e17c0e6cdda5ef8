/* SPDX-License-Identifier: BSD-3-Clause */
/* can_frame.h - the CAN frames of kinctld's output (can_io.h), encoded and
 * decoded: pure functions of their arguments, no socket, no clock, so
 * that a test or a future CANopen master calls them alike.
 *
 * Frames (all little-endian; tools/kinctl/kinctl.dbc describes every one):
 *   0x080          SYNC, 1 byte: counter 1..240 (CiA 301 SYNC counter),
 *                  ((cycle / sync_every) mod 240) + 1, so a gap in the bus
 *                  cycles shows as a gap in the counter
 *   0x200 + node   RPDO1 to each joint's drive, 8 bytes: target position
 *                  (object 0x607A, int32 counts) then velocity offset
 *                  (0x60B1, int32 counts/s), after the SYNC of the same
 *                  bus cycle (a synchronous RPDO acts at the next SYNC)
 *   0x700 + node   heartbeat, 1 byte: NMT state (0x05 operational); the
 *                  master's every heartbeat_ms, each drive's read back
 *   0x180 + node   TPDO1 from each drive, 6 bytes: position actual value
 *                  (0x6064, int32 counts), statusword (0x6041, uint16)
 *
 * Scaling per joint: counts = round(sign * q * counts_per_unit) +
 * offset_counts, velocity counts/s = round(sign * qd * counts_per_unit),
 * saturated to int32 (the configuration is checked so that the joint's
 * limits never need saturating); NaN gives 0.
 */
#ifndef KINCTL_DAEMON_CAN_FRAME_H
#define KINCTL_DAEMON_CAN_FRAME_H

#include <stdint.h>

#include <linux/can.h>

#include "can_config.h"

#define KD_CAN_SYNC_ID 0x080u
#define KD_CAN_RPDO_BASE 0x200u
#define KD_CAN_TPDO_BASE 0x180u
#define KD_CAN_HEARTBEAT_BASE 0x700u
#define KD_CAN_NMT_OPERATIONAL 0x05u
#define KD_CAN_SYNC_COUNTER_MAX 240

/* Counts of a position (rad or m) and a velocity (per s), saturated to
 * int32. */
int32_t kd_can_pos_counts(const kd_can_joint *j, double q);
int32_t kd_can_vel_counts(const kd_can_joint *j, double qd);

/* The SYNC of bus cycle bus_cycle (>= 0) into f. */
void kd_can_encode_sync(int64_t bus_cycle, struct can_frame *f);

/* Joint j's RPDO1 for position q and velocity qd into f. */
void kd_can_encode_rpdo(const kd_can_joint *j, double q, double qd, struct can_frame *f);

/* A heartbeat of node (1..127) in NMT state into f. */
void kd_can_encode_heartbeat(int node, uint8_t state, struct can_frame *f);

/* Joint j's TPDO1 payload f (data and len; the id is the caller's to
 * match): the position in joint units and the statusword. Returns 0, or
 * -1 for a frame shorter than 6 bytes (outputs untouched). */
int kd_can_decode_tpdo(const kd_can_joint *j, const struct can_frame *f, double *q, uint16_t *statusword);

#endif
