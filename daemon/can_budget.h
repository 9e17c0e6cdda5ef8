/* SPDX-License-Identifier: BSD-3-Clause */
/* can_budget.h - the bus time of kinctld's bus cycle on classic CAN, worst
 * case, against a share of the bus cycle's period. Pure arithmetic, for the
 * start-up check; no frame, no clock.
 *
 * Frame (classic CAN, 11-bit id, n data bytes, Davis et al., "Controller
 * Area Network (CAN) schedulability analysis: refuted, revisited and
 * revised", Real-Time Systems 35, 2007, eq. 1):
 *     bits(n) = 47 + 8 n + floor((34 + 8 n - 1) / 4)
 * 47 bits of frame and interframe space, 8 n of data, and the worst case of
 * stuff bits over the 34 + 8 n bits from start of frame to the CRC: 55 bits
 * for an empty SYNC, 65 for a SYNC with its counter, 115 for 6 bytes, 135
 * for 8 (135 us at 1 Mbit/s).
 *
 * Bus cycle: one SYNC (0 or 1 byte), every drive's RPDOs, and its TPDOs,
 * a TPDO of transmission type N (1..240) once every N-th SYNC. The mean
 * counts each TPDO 1/N times, the peak counts every TPDO (drives count
 * their own SYNCs, so those of type N may all answer the same one). The
 * check refuses a mean above share (default 0.70) of the bus cycle's
 * period; a peak above the share is said but not refused (the bus takes
 * the burst in the next cycle's idle time).
 *
 * What fits under the default share (0.70) with an empty SYNC (55 bits),
 * per drive an RPDO of controlword + target (6 bytes, 115 bits) and a TPDO
 * of statusword + actual position (6 bytes, 115 bits), drives per bus:
 *                         TPDO every SYNC    TPDO every 2nd SYNC
 *     1 Mbit/s,   1 kHz          2                   3
 *     1 Mbit/s,   500 Hz         5                   7
 *     500 kbit/s, 1 kHz          1                   1
 *     500 kbit/s, 500 Hz         2                   3
 * e.g. 1 Mbit/s at 1 kHz: (700 - 55) / 230 = 2.8, (700 - 55) / (115 +
 * 115 / 2) = 3.7; unit.can_budget checks the table.
 */
#ifndef KINCTL_DAEMON_CAN_BUDGET_H
#define KINCTL_DAEMON_CAN_BUDGET_H

#include <stddef.h>
#include <stdint.h>

#include "kinctl/chain.h"

#define KD_CAN_BUDGET_PDOS 2 /* RPDOs and TPDOs per drive */
#define KD_CAN_BUDGET_SHARE_DEFAULT 0.70

typedef struct kd_can_budget_drive {
    int n_rpdo;                         /* 0 .. KD_CAN_BUDGET_PDOS */
    int rpdo_bytes[KD_CAN_BUDGET_PDOS]; /* 0 .. 8 each */
    int n_tpdo;
    int tpdo_bytes[KD_CAN_BUDGET_PDOS];
    int tpdo_every[KD_CAN_BUDGET_PDOS]; /* transmission type: every N-th SYNC, 1 .. 240 */
} kd_can_budget_drive;

typedef struct kd_can_budget {
    int64_t bitrate;    /* bit/s, > 0 */
    int64_t period_ns;  /* the controller's period, > 0 */
    int sync_every;     /* periods per bus cycle, >= 1 */
    int sync_bytes;     /* 0 (0x1019 = 0) or 1 (SYNC counter) */
    double share;       /* largest mean share of the bus cycle, (0, 1] */
    int n_drives;       /* 1 .. KC_MAX_JOINTS */
    kd_can_budget_drive drive[KC_MAX_JOINTS];
} kd_can_budget;

typedef struct kd_can_budget_use {
    int64_t peak_bits;     /* every frame of a bus cycle */
    double mean_bits;      /* TPDOs of type N counted 1/N */
    double peak_ns, mean_ns;
    double peak_share, mean_share; /* of the bus cycle's period */
    int64_t cycle_ns;      /* the bus cycle's period: period_ns * sync_every */
} kd_can_budget_use;

/* Worst-case bits of a classic 11-bit frame with n (0..8) data bytes, or
 * -1 for another n. */
int kd_can_frame_bits(int n);

/* Defaults: 1 Mbit/s, share 0.70, empty SYNC, sync_every 1; no drives,
 * no period (the caller fills those). */
kd_can_budget kd_can_budget_default(void);

/* Computes b's use into *use and judges it. Returns 0 when the mean fits
 * the share, 1 when it does not (why says the figures and what would fit:
 * fewer drives, a longer bus cycle as sync_every, TPDOs every N-th SYNC),
 * -1 for a bad b (why says which field; *use untouched). why (size
 * why_size, may be 0) is written for 1 and -1. */
int kd_can_budget_check(const kd_can_budget *b, kd_can_budget_use *use, char *why, size_t why_size);

#endif
