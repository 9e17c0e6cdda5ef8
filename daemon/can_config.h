/* SPDX-License-Identifier: BSD-3-Clause */
/* can_config.h - the configuration of kinctld's CANopen master (can_io.h,
 * can_master.h): what controller.can says, read and checked here, beside
 * the CAN code. daemon/README.md says every key with its default.
 *
 *   can = {                   # CiA 402 drives in CSP; absent: off
 *     interface = "can0";     # SocketCAN interface; "": off
 *     bitrate = 1000000;      # bit/s, for the bus budget
 *     bus_share = 0.7;        # largest mean share of a bus cycle's period
 *     sync_every = 1;         # cycles per bus cycle (SYNC + RPDOs), 1 .. 1000
 *     sync_counter = 0;       # 0x1019: 0 empty SYNC, 2 .. 240 a counter
 *     tpdo_every = 1;         # TPDO1 every N-th SYNC (transmission type)
 *     velocity_offset = false;  # RPDO2: 0x60B1
 *     master_id = 127;        # master heartbeat 0x700 + id, 1 .. 127
 *     heartbeat_ms = 100.0;   # master heartbeat period; 0: none
 *     on_error = "stop";      # bus-off, interface down: "stop" (fault
 *                             # and stop) or "lcm_only" (carry on)
 *     boot = true;            # NMT reset and SDO configuration; false: the
 *                             # drives are configured by other means
 *     device_type = 0x0192; device_type_mask = 0xFFFF;  # 0x1000 check
 *     drive_heartbeat_ms = 100;   # 0x1017
 *     master_timeout_ms = 500;    # 0x1016:1; 0: not written
 *     lost_master_reaction = 3;   # 0x6007; -1: not written
 *     cycle_period = false;       # write 0x1006
 *     boot_timeout_ms = 5000.0; sdo_timeout_ms = 500.0;
 *     enable_timeout_ms = 2000.0;
 *     shutdown_nmt = "pre_operational";   # or "stop", after disabling
 *     joints = ( { node = 1; counts_per_unit = 10000.0; sign = 1;
 *                  offset_counts = 0; identity = [0, 0, 0, 0];
 *                  writes = ( { index = 0x6065; subindex = 0; size = 4;
 *                               value = 5000; } ); }, ... );
 *     feedback = { enable = true; following_error = 0.05;
 *                  drive_timeout_ms = 500.0; };
 *   };
 *
 * Read from the file first (kd_can_cfg_read), checked against the arm once
 * the arm is known (kd_can_cfg_check, which also checks the bus budget,
 * can_budget.h). At start-up only.
 */
#ifndef KINCTL_DAEMON_CAN_CONFIG_H
#define KINCTL_DAEMON_CAN_CONFIG_H

#include <stdint.h>

#include "can_budget.h"
#include "canopen_boot.h"
#include "kinctl/chain.h"

struct config_setting_t;
struct kc_cfg;

#define KD_CAN_IFNAME_MAX 16 /* IFNAMSIZ */

typedef struct kd_can_joint {
    int node;               /* CANopen node id of the joint's drive, 1 .. 127 */
    double counts_per_unit; /* drive counts per rad (revolute) or per m (prismatic), > 0 */
    int sign;               /* +1 or -1: the drive's direction against the joint's */
    int64_t offset_counts;  /* counts at joint position 0 */
    uint32_t identity[4];   /* 0x1018:1..4 expected; 0: unchecked */
    int n_writes;           /* the drive's own SDO writes at boot */
    kd_boot_write writes[KD_BOOT_EXTRA_MAX];
    int line;               /* its group's line in the file (0: none) */
} kd_can_joint;

typedef struct kd_can_cfg {
    int enable;                          /* 1 when an interface is named */
    char interface[KD_CAN_IFNAME_MAX];   /* "vcan0", "can0" */
    int64_t bitrate;                     /* bit/s */
    double bus_share;                    /* largest mean share of the bus cycle's period */
    int sync_every;                      /* cycles per bus cycle (SYNC and RPDOs), >= 1 */
    int sync_counter;                    /* 0x1019: 0 empty SYNC, 2 .. 240 */
    int tpdo_every;                      /* TPDO1 transmission type, 1 .. 240 */
    int velocity_offset;                 /* RPDO2 with 0x60B1 */
    int boot;                            /* NMT reset and SDO configuration */
    uint32_t device_type, device_type_mask;
    int drive_heartbeat_ms;              /* 0x1017 */
    int master_timeout_ms;               /* 0x1016:1; 0: not written */
    int lost_master_reaction;            /* 0x6007; -1: not written */
    int cycle_period;                    /* write 0x1006 */
    double boot_timeout_ms, sdo_timeout_ms, enable_timeout_ms;
    int shutdown_nmt;                    /* KD_NMT_ENTER_PRE_OPERATIONAL or KD_NMT_STOP */
    int master_id;                       /* master heartbeat 0x700 + master_id */
    double heartbeat_ms;                 /* master heartbeat period; 0: none */
    int on_error_stop;                   /* bus lost: 1 fault and stop, 0 carry on with LCM only */
    kd_can_joint joint[KC_MAX_JOINTS];
    int n_joints;                        /* as configured (checked against the arm) */
    int joints_line;                     /* the joints list's line in the file (0: none) */
    int feedback;                        /* watch the drives (statusword, following error, heartbeats) */
    double following_error;              /* largest |actual - target| (rad or m); 0: unchecked */
    double drive_timeout_ms;             /* longest silence of a drive's heartbeat; 0: unchecked */
} kd_can_cfg;

/* Off, with the defaults above for when an interface is named. */
kd_can_cfg kd_can_cfg_default(void);

/* Reads the group controller.can through r (kinctl/cfgread.h) into can.
 * Returns 0, or nonzero with the problem recorded in r. */
int kd_can_cfg_read(struct kc_cfg *r, const struct config_setting_t *g, kd_can_cfg *can);

/* The enabled output against the arm chain (called robot_name) at the
 * cycle's period: one drive per joint, node ids apart from the master's,
 * every position and velocity inside int32 counts, the interpolation
 * period a 0x60C2 can say, and the bus budget (can_budget.h). Returns 0,
 * or -1 with "<path>: <problem>" on stderr (path NULL: "kinctld"). */
int kd_can_cfg_check(const kd_can_cfg *can, const kc_chain *chain, const char *robot_name, const char *path,
                     int64_t period_ns);

/* The boot of joint j's drive (canopen_boot.h) as can says, at the cycle's
 * period. */
kd_boot_cfg kd_can_boot_cfg(const kd_can_cfg *can, int j, int64_t period_ns);

/* The bus budget of can (can_budget.h) at the cycle's period. */
void kd_can_budget_of(const kd_can_cfg *can, int64_t period_ns, kd_can_budget *b);

#endif
