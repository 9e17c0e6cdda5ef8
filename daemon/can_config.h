/* SPDX-License-Identifier: BSD-3-Clause */
/* can_config.h - the configuration of kinctld's CAN output (can_io.h):
 * what controller.can says, read and checked here, beside the CAN code.
 *
 *   can = {                   # CAN output (CiA 402 CSP); absent: off
 *     interface = "can0";     # SocketCAN interface; "": off
 *     sync_every = 1;         # cycles per SYNC + RPDOs, 1 .. 1000
 *     master_id = 127;        # master heartbeat 0x700 + id, 1 .. 127
 *     heartbeat_ms = 100.0;   # master heartbeat period; 0: none
 *     on_error = "stop";      # bus-off, interface down: "stop" (fault
 *                             # and stop) or "lcm_only" (carry on)
 *     joints = ( { node = 1; counts_per_unit = 10000.0; sign = 1;
 *                  offset_counts = 0; }, ... );   # one per joint
 *     feedback = { enable = true; following_error = 0.05;
 *                  drive_timeout_ms = 500.0; };
 *   };
 *
 * Read from the file first (kd_can_cfg_read), checked against the arm once
 * the arm is known (kd_can_cfg_check). At start-up only.
 */
#ifndef KINCTL_DAEMON_CAN_CONFIG_H
#define KINCTL_DAEMON_CAN_CONFIG_H

#include <stdint.h>

#include "kinctl/chain.h"

struct config_setting_t;
struct kc_cfg;

#define KD_CAN_IFNAME_MAX 16 /* IFNAMSIZ */

typedef struct kd_can_joint {
    int node;               /* CANopen node id of the joint's drive, 1 .. 127 */
    double counts_per_unit; /* drive counts per rad (revolute) or per m (prismatic), > 0 */
    int sign;               /* +1 or -1: the drive's direction against the joint's */
    int64_t offset_counts;  /* counts at joint position 0 */
    int line;               /* its group's line in the file (0: none) */
} kd_can_joint;

typedef struct kd_can_cfg {
    int enable;                          /* 1 when an interface is named */
    char interface[KD_CAN_IFNAME_MAX];   /* "vcan0", "can0" */
    int sync_every;                      /* cycles per bus cycle (SYNC and RPDOs), >= 1 */
    int master_id;                       /* master heartbeat 0x700 + master_id */
    double heartbeat_ms;                 /* master heartbeat period; 0: none */
    int on_error_stop;                   /* bus lost: 1 fault and stop, 0 carry on with LCM only */
    kd_can_joint joint[KC_MAX_JOINTS];
    int n_joints;                        /* as configured (checked against the arm) */
    int joints_line;                     /* the joints list's line in the file (0: none) */
    int feedback;                        /* read TPDOs and drive heartbeats */
    double following_error;              /* largest |actual - target| (rad or m); 0: unchecked */
    double drive_timeout_ms;             /* longest silence of a drive's heartbeat; 0: unchecked */
} kd_can_cfg;

/* Off, with the defaults above for when an interface is named. */
kd_can_cfg kd_can_cfg_default(void);

/* Reads the group controller.can through r (kinctl/cfgread.h) into can.
 * Returns 0, or nonzero with the problem recorded in r. */
int kd_can_cfg_read(struct kc_cfg *r, const struct config_setting_t *g, kd_can_cfg *can);

/* The enabled output against the arm chain (called robot_name): one drive
 * per joint, node ids apart from the master's, every position and velocity
 * inside int32 counts. Returns 0, or -1 with "<path>: <problem>" on stderr
 * (path NULL: "kinctld"). */
int kd_can_cfg_check(const kd_can_cfg *can, const kc_chain *chain, const char *robot_name, const char *path);

#endif
