/* SPDX-License-Identifier: BSD-3-Clause */
/* can_master.h - the CiA 402 drives' lifecycle, as their CANopen master, on
 * the I/O thread: boot and configure, enable without a jump, watch, stop,
 * reset, shut down. Frames go out through the link (can_io.h); the
 * controlwords through the bus cycle (can_bus.h), which writes them with
 * each RPDO1.
 *
 *   booting    every drive booted side by side (canopen_boot.h: NMT reset
 *              communication, boot-up, 0x1000 and 0x1018 checks, PDO
 *              mapping, 0x6060 = 8, 0x60C2, 0x1006, 0x1019, 0x1017, 0x1016,
 *              0x6007, the joint's own writes, each read back, NMT start;
 *              with boot = false the checks and NMT start only)
 *   enabling   each drive's position actual (0x6064) read by SDO (asked
 *              up to KD_SDO_SENDS times when a drive does not answer
 *              within sdo_timeout_ms: a busy bus may lose a frame),
 *              converted with the joint's scale, sign and offset and
 *              checked against its limits; the controller is seated there
 *              (kc_ctrl_seat, through the I/O thread: kd_master_seat_wanted
 *              and kd_master_seated); then the bus cycle starts, its targets
 *              the controller's setpoint (where the drives are), and each
 *              drive's controlword walks the power state machine
 *              (cia402.h) one step per TPDO that answers it, to operation
 *              enabled, within enable_timeout_ms
 *   enabled    every drive in operation enabled: goals are taken, and the
 *              link watches the drives (can_io.h's conditions)
 *   disabled   a refused boot or enabling, a condition (EMCY, fault,
 *              reboot, silence, following error), or ESTOP; RESET boots the
 *              drives that need it (never booted, failed, rebooted, last
 *              heard not operational: it takes no PDO until started), then
 *              enables them all again from where they are
 * The drives' controlwords while disabled: after ESTOP, quick stop (0x02)
 * to every drive; after a condition, drives still in operation enabled
 * hold it (they follow the controller's own stop) and the others get
 * disable voltage (0x00: never a fault reset before RESET). A bus that
 * comes back after it was lost with drives enabled or being enabled: quick
 * stop to every drive, since the controller's setpoint has moved on
 * without them (a target they would jump to); RESET enables them again
 * where they are.
 *
 * Shutdown: every drive gets disable voltage until its statusword says
 * switch on disabled (or after enable_timeout_ms); then the bus cycle
 * stops, and two bus cycles later (the cycle thread's last write is
 * behind) NMT enter pre-operational or stop (shutdown_nmt), once per
 * drive.
 *
 * Every change of state is told once (kd_master_take_news) with its text:
 * "drives enabled (6 of 6) at q = [...]", "joint 3 (node 3): SDO write
 * 0x6060:00 = 0x00000008 (modes of operation) aborted 0x06090030: ...".
 *
 * Not thread-safe: the I/O thread only.
 */
#ifndef KINCTL_DAEMON_CAN_MASTER_H
#define KINCTL_DAEMON_CAN_MASTER_H

#include <stdint.h>

#include "can_io.h"
#include "canopen_boot.h"
#include "canopen_sdo.h"
#include "cia402.h"
#include "kinctl/chain.h"

/* status_t.drives */
enum { KD_DRIVES_NONE = 0, KD_DRIVES_BOOTING = 1, KD_DRIVES_ENABLING = 2, KD_DRIVES_ENABLED = 3, KD_DRIVES_DISABLED = 4 };

typedef struct kd_master {
    const kd_can_cfg *cfg;
    kd_can *can;
    kd_bus *bus;
    const kc_chain *chain;
    int n;
    int64_t period_ns;
    int drives;           /* KD_DRIVES_* */
    int phase;            /* private */
    int hold;             /* private: the controlwords while disabled */
    int64_t phase_ns, last_ns;
    kd_boot boot[KC_MAX_JOINTS];
    int booting[KC_MAX_JOINTS];      /* a boot under way */
    int booted[KC_MAX_JOINTS];       /* configured and started */
    int64_t bootups[KC_MAX_JOINTS];  /* the link's boot-ups when it was started */
    kd_sdo sdo[KC_MAX_JOINTS];
    int have_pos[KC_MAX_JOINTS];
    int32_t pos_counts[KC_MAX_JOINTS];
    kc_real q_seat[KC_MAX_JOINTS];
    int seat_wanted;
    int64_t seat_retry_ns;
    int64_t tpdos[KC_MAX_JOINTS];    /* the TPDO count the controlword last answered */
    int64_t tpdos_phase[KC_MAX_JOINTS]; /* ... at the phase's start */
    uint16_t controlword[KC_MAX_JOINTS];
    int disable_first[KC_MAX_JOINTS]; /* booted again while the bus cycle runs: shown disabled before enabled */
    int64_t recoveries;              /* the link's, as last seen */
    int disabled_in_time;            /* shutdown: every drive said switch on disabled */
    int news;                        /* a change to tell */
    char text[KD_CAN_TEXT];
} kd_master;

/* Sets m up over the open link c and the bus cycle b for the arm chain.
 * Does nothing with the CAN output off (drives KD_DRIVES_NONE). */
void kd_master_init(kd_master *m, kd_can *c, kd_bus *b, const kc_chain *chain, int64_t period_ns);

/* Starts booting the drives. */
void kd_master_start(kd_master *m, int64_t now);

/* A frame the link read (kd_can_read). */
void kd_master_rx(kd_master *m, const struct can_frame *f, int64_t now);

/* Timers and progress, every pass of the I/O thread. */
void kd_master_step(kd_master *m, int64_t now);

/* 1 with q (n joints) when the controller should be seated there now. */
int kd_master_seat_wanted(kd_master *m, kc_real *q);

/* The controller's answer to the seat: a kc_status (KC_E_LIMIT names
 * bad_joint; KC_E_STATE: it was not idle at rest, tried again). */
void kd_master_seated(kd_master *m, int status, int bad_joint, int64_t now);

/* ESTOP: quick stop to every drive. */
void kd_master_estop(kd_master *m, int64_t now);

/* RESET: boot and enable again where the drives are disabled. */
void kd_master_reset(kd_master *m, int64_t now);

/* Shutdown: disable every drive, then NMT. */
void kd_master_shutdown(kd_master *m, int64_t now);

/* 1 once the shutdown is done (or there is nothing to do). */
int kd_master_shutdown_done(const kd_master *m);

/* 1 with the text of a change not told yet (cleared by the call). */
int kd_master_take_news(kd_master *m, const char **text);

/* "booting", "enabling", "enabled", "disabled", "none". */
const char *kd_master_drives_str(int drives);

#endif
