/* SPDX-License-Identifier: BSD-3-Clause */
/* can_io.h - kinctld's CAN link on the I/O thread: the socket the drives
 * answer on, the master's own frames (heartbeat, NMT, SDO), the drives'
 * feedback and the conditions that stop the arm. The bus cycle itself
 * (SYNC, RPDOs) is the cycle thread's (can_bus.h); the drives' lifecycle
 * (boot, enable, quick stop, reset, shutdown) is can_master.h's.
 *
 * Read (kernel filters pass nothing else): each drive's TPDO1, EMCY,
 * heartbeat (boot-up included) and SDO responses, and error frames
 * (CAN_ERR_FLAG) from the interface's controller. Written: the master's
 * heartbeat every heartbeat_ms, and what the master sends (NMT, SDO), one
 * non-blocking sendmmsg a call, counted when it does not go out (EAGAIN,
 * ENOBUFS: tx_dropped) and never retried.
 *
 * Losing the bus. ENETDOWN or ENXIO on a write (here or on the cycle's
 * socket), or a bus-off error frame, puts the link in LOST: the bus cycle
 * pauses, nothing is written (the frames count as dropped), and the
 * interface is probed every 100 ms (IFF_UP and IFF_RUNNING). Once it is
 * back, both sockets are opened anew and the bus cycle resumes: the daemon
 * has no queue of its own to replay, and the kernel drops what sat in the
 * interface's queue when the link went down. The policy (on_error) decides
 * what the arm does meanwhile: "stop" faults the controller (FAULT, stop
 * in joint space, RESET needed), "lcm_only" carries on with LCM alone.
 *
 * Feedback. Each TPDO updates the joint's measured position (and a
 * velocity from successive TPDOs over their interval) and statusword. Once
 * the master has enabled the drives (kd_can_watch), a condition that stops
 * the arm (feedback on):
 *   - an EMCY with a code other than 0 (error reset), or a boot-up (the
 *     drive rebooted): latched until kd_can_clear;
 *   - statusword bit 3 (fault), bit 13 (following error) set, or bit 12
 *     (drive follows the target) clear;
 *   - |actual - target| beyond following_error, against the target the
 *     TPDO answers: TPDOs are counted against the SYNCs since the bus
 *     cycle started (or the drive was started: kd_can_rebase), so the k-th
 *     answers the k-th SYNC, however late it is read, and shows the target
 *     sent after the SYNC before it; the nearest of the targets within 1 +
 *     tpdo_every bus cycles of that one counts (a lost frame, or a drive
 *     whose every-N-th SYNC is not ours, stays within it). The targets of
 *     the last KD_CAN_RING bus cycles are kept (can_bus.h); a drive more
 *     than half of them behind (lost TPDOs) is taken to answer the latest;
 *   - a drive heartbeat missing for drive_timeout_ms (counted from the
 *     watch's start for a drive not heard since), or one with a state other
 *     than operational.
 * Such a condition (or a lost bus under on_error = "stop") is reported by
 * kd_can_condition, with a readable text; the I/O thread raises it as the
 * controller's external fault.
 *
 * Not thread-safe: the I/O thread only.
 */
#ifndef KINCTL_DAEMON_CAN_IO_H
#define KINCTL_DAEMON_CAN_IO_H

#include <stdint.h>

#include "can_bus.h"
#include "can_frame.h"
#include "config.h"

/* The link's state: status_t's CAN_OFF, CAN_OK, CAN_LOST. */
enum { KD_CAN_OFF = 0, KD_CAN_OK = 1, KD_CAN_LOST = 2 };

#define KD_CAN_TEXT 200

typedef struct kd_can {
    const kd_can_cfg *cfg;
    kd_bus *bus;       /* the cycle's bus cycle */
    int n;             /* joints */
    int64_t period_ns; /* of the cycle */
    int fd;            /* -1 when closed */
    int state;         /* KD_CAN_OFF, KD_CAN_OK, KD_CAN_LOST */
    char lost_text[KD_CAN_TEXT];   /* why it is lost */
    int state_changed;             /* 1: the I/O thread should tell (status) */
    int64_t next_probe_ns, next_heartbeat_ns, heartbeat_period_ns;
    int8_t node_joint[128];        /* node id -> joint index, -1: none */

    /* Counters since start (the I/O thread's frames; kd_can_totals adds
     * the bus cycle's). */
    int64_t frames, tx_dropped, error_frames, bus_off, link_down, rx_frames, errors;
    int64_t recoveries; /* times the link came back */

    /* Feedback per joint. */
    int have_fb[KC_MAX_JOINTS];
    double q_fb[KC_MAX_JOINTS], qd_fb[KC_MAX_JOINTS];
    uint16_t statusword[KC_MAX_JOINTS];
    int64_t tpdos[KC_MAX_JOINTS];        /* TPDOs received */
    int64_t fb_ns[KC_MAX_JOINTS];        /* when the last one came */
    int64_t tpdo_sync[KC_MAX_JOINTS];    /* the SYNC the last one answered */
    double following[KC_MAX_JOINTS];
    int64_t heartbeat_ns[KC_MAX_JOINTS]; /* last heartbeat heard (0: never) */
    uint8_t nmt_state[KC_MAX_JOINTS];
    int64_t bootups[KC_MAX_JOINTS];      /* boot-ups heard */
    uint16_t emcy_code[KC_MAX_JOINTS];   /* the last one's */
    uint8_t emcy_register[KC_MAX_JOINTS];

    /* Watching the enabled drives: latches and the conditions. */
    int watch;
    int64_t watch_ns;
    int emcy_latched[KC_MAX_JOINTS], reboot_latched[KC_MAX_JOINTS];
    int condition;                 /* 0 none, else KD_CAN_COND_* */
    char condition_text[KD_CAN_TEXT];
} kd_can;

enum { KD_CAN_COND_NONE = 0, KD_CAN_COND_DRIVE = 1, KD_CAN_COND_BUS = 2 };

/* Opens the link on the interface named in cfg (cfg->enable set) for n
 * joints at the cycle's period, beside bus (kd_bus_init done); now is
 * CLOCK_MONOTONIC (ns). Returns 0, or -1 with a message on stderr (no such
 * interface, no AF_CAN in this kernel). With cfg->enable clear it only
 * sets the link OFF and returns 0. */
int kd_can_open(kd_can *c, const kd_can_cfg *cfg, kd_bus *bus, int n, int64_t period_ns, int64_t now);

void kd_can_close(kd_can *c);

/* Writes frames[0..count) without blocking. Returns how many went out. */
int kd_can_write(kd_can *c, const struct can_frame *frames, int count);

/* Reads one frame, if the socket holds one, into *f and takes what it says
 * (feedback, heartbeat, EMCY, error frames). Returns 1 with *f set, or 0. */
int kd_can_read(kd_can *c, struct can_frame *f, int64_t now);

/* Timers: the master heartbeat, a lost link (the bus cycle's errors,
 * probing the interface), then the conditions. */
void kd_can_timers(kd_can *c, int64_t now);

/* Starts (on 1) or stops (0) watching the drives: the conditions above
 * apply from now; a drive silent from now for drive_timeout_ms is lost. */
void kd_can_watch(kd_can *c, int on, int64_t now);

/* Joint j's next TPDO answers the next SYNC (j < 0: every joint's): when
 * the bus cycle starts, and when a drive has just been started (NMT). In
 * between, TPDOs are counted against SYNCs, so a backlog of them in the
 * socket is still compared with the targets they answer. */
void kd_can_rebase(kd_can *c, int j);

/* Clears the EMCY and reboot latches (a RESET). */
void kd_can_clear(kd_can *c);

/* The condition stopping the arm now (KD_CAN_COND_*), its text in c. */
int kd_can_condition(const kd_can *c);

/* Frames written, dropped and errors, the bus cycle's included. */
void kd_can_totals(const kd_can *c, int64_t *frames, int64_t *dropped, int64_t *errors);

#endif
