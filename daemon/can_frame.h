/* SPDX-License-Identifier: BSD-3-Clause */
/* can_frame.h - the CAN frames of kinctld's CANopen master (can_io.h,
 * can_bus.h, can_master.h), encoded and decoded: pure functions of their
 * arguments, no socket, no clock, so that a test calls them alike.
 *
 * Frames (CiA 301's predefined connection set, all little-endian;
 * tools/kinctl/kinctl.dbc describes every one):
 *   0x000          NMT, 2 bytes: command, node (0: every node)
 *   0x080          SYNC: empty, or 1 byte counter 1..overflow when the
 *                  drives' 0x1019 is overflow (2..240), (bus cycle mod
 *                  overflow) + 1, so a gap in the bus cycles shows
 *   0x080 + node   EMCY from a drive, 8 bytes: error code (uint16), error
 *                  register (0x1001), 5 bytes of the vendor's
 *   0x200 + node   RPDO1 to each joint's drive, 6 bytes: controlword
 *                  (0x6040, uint16), target position (0x607A, int32
 *                  counts); after the SYNC of the same bus cycle (a
 *                  synchronous RPDO acts at the next SYNC)
 *   0x300 + node   RPDO2, 4 bytes: velocity offset (0x60B1, int32 counts/s),
 *                  where configured (velocity_offset)
 *   0x180 + node   TPDO1 from each drive, 6 bytes: statusword (0x6041,
 *                  uint16), position actual value (0x6064, int32 counts)
 *   0x700 + node   heartbeat, 1 byte: NMT state (0x00 boot-up, 0x05
 *                  operational, 0x7F pre-operational); the master's every
 *                  heartbeat_ms, each drive's read back
 *   0x580/0x600 + node   SDO (canopen_sdo.h)
 *
 * Scaling per joint: counts = round(sign * q * counts_per_unit) +
 * offset_counts, velocity counts/s = round(sign * qd * counts_per_unit),
 * saturated to int32 (the configuration is checked so that the joint's
 * limits never need saturating); NaN gives 0. Back: q = (counts -
 * offset_counts) / (sign * counts_per_unit).
 */
#ifndef KINCTL_DAEMON_CAN_FRAME_H
#define KINCTL_DAEMON_CAN_FRAME_H

#include <stdint.h>

#include <linux/can.h>

#include "can_config.h"

#define KD_CAN_NMT_ID 0x000u
#define KD_CAN_SYNC_ID 0x080u
#define KD_CAN_EMCY_BASE 0x080u
#define KD_CAN_RPDO_BASE 0x200u
#define KD_CAN_RPDO2_BASE 0x300u
#define KD_CAN_TPDO_BASE 0x180u
#define KD_CAN_HEARTBEAT_BASE 0x700u
#define KD_CAN_NMT_BOOTUP 0x00u
#define KD_CAN_NMT_STOPPED 0x04u
#define KD_CAN_NMT_OPERATIONAL 0x05u
#define KD_CAN_NMT_PRE_OPERATIONAL 0x7Fu
#define KD_CAN_SYNC_COUNTER_MAX 240
#define KD_CAN_RPDO_LEN 6
#define KD_CAN_TPDO_LEN 6

/* Counts of a position (rad or m) and a velocity (per s), saturated to
 * int32, and a position back from counts. */
int32_t kd_can_pos_counts(const kd_can_joint *j, double q);
int32_t kd_can_vel_counts(const kd_can_joint *j, double qd);
double kd_can_pos_of_counts(const kd_can_joint *j, int32_t counts);

/* The SYNC of bus cycle bus_cycle (>= 0) into f: empty for overflow 0,
 * else a counter (bus_cycle mod overflow) + 1. */
void kd_can_encode_sync(int64_t bus_cycle, int overflow, struct can_frame *f);

/* Joint j's RPDO1 (controlword, target position q) into f. */
void kd_can_encode_rpdo(const kd_can_joint *j, uint16_t controlword, double q, struct can_frame *f);

/* Joint j's RPDO2 (velocity offset qd) into f. */
void kd_can_encode_rpdo2(const kd_can_joint *j, double qd, struct can_frame *f);

/* A heartbeat of node (1..127) in NMT state into f. */
void kd_can_encode_heartbeat(int node, uint8_t state, struct can_frame *f);

/* An NMT command (KD_NMT_* of canopen_boot.h) to node (0: all) into f. */
void kd_can_encode_nmt(uint8_t command, int node, struct can_frame *f);

/* Joint j's TPDO1 payload f (data and len; the id is the caller's to
 * match): the position in joint units and the statusword. Returns 0, or
 * -1 for a frame shorter than 6 bytes (outputs untouched). */
int kd_can_decode_tpdo(const kd_can_joint *j, const struct can_frame *f, double *q, uint16_t *statusword);

/* An EMCY payload: error code and error register. Returns 0, or -1 for a
 * frame shorter than 3 bytes (outputs untouched). */
int kd_can_decode_emcy(const struct can_frame *f, uint16_t *code, uint8_t *error_register);

#endif
