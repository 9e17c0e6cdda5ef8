/* SPDX-License-Identifier: BSD-3-Clause */
/* can_io.h - kinctld's optional CAN output, shaped after CiA 402 cyclic
 * synchronous position (mode 8), on a SocketCAN interface.
 *
 * Frames and their scaling: can_frame.h. Each bus cycle is a SYNC and one
 * RPDO1 per joint; a master heartbeat goes out every heartbeat_ms. Read
 * back when feedback is on (kernel filters pass nothing else): each
 * drive's TPDO1 and heartbeat, and error frames (CAN_ERR_FLAG) from the
 * interface's controller.
 *
 * Everything here runs on the I/O thread, never the cycle: the cycle hands
 * its ticks over as always, and the I/O thread encodes and writes a bus
 * cycle when it publishes that tick's setpoint. Writes never block: one
 * sendmmsg per bus cycle with MSG_DONTWAIT. A frame that does not go out
 * is counted (EAGAIN, ENOBUFS: tx_dropped) and never retried, so nothing
 * old is queued in the daemon.
 *
 * Losing the bus. ENETDOWN or ENXIO on a write, or a bus-off error frame,
 * puts the output in LOST: nothing is written (the frames count as
 * dropped), and the interface is probed every 100 ms (IFF_UP and
 * IFF_RUNNING). Once it is back, the socket is opened anew and the output
 * resumes with the next tick: the daemon has no queue of its own to replay,
 * and the kernel drops what sat in the interface's queue when the link
 * went down (a bus-off takes the carrier off and resets the queue). The
 * policy (on_error) decides what the arm does meanwhile: "stop" faults the
 * controller (FAULT, stop in joint space, RESET needed), "lcm_only" carries
 * on with LCM alone.
 *
 * Drive feedback and watchdogs (feedback on). Each TPDO updates the joint's
 * measured position (and a velocity from successive TPDOs over the bus
 * cycle) that status_t reports. A condition that stops the arm:
 *   - statusword bit 3 (fault), bit 13 (following error) set, or bit 12
 *     (drive follows the target) clear;
 *   - |actual - target| beyond following_error, against the target the
 *     TPDO answers: the drive's k-th TPDO answers the k-th SYNC that went
 *     out and shows the target sent after the SYNC before it; the nearest of
 *     the targets within two bus cycles of that one counts (a drive that
 *     also answers the very first SYNC, or a lost frame, stays within
 *     it). The targets of the last KD_CAN_RING bus cycles are kept, so a
 *     late I/O thread that sends a burst of bus cycles does not look like
 *     a following error; a drive more than half of them behind (lost
 *     TPDOs) is taken to answer the latest, and after the socket is opened
 *     anew (a recovered bus) the next TPDO answers the next SYNC;
 *   - a drive heartbeat missing for drive_timeout_ms (counted from the
 *     output's start for a drive never heard), or one with a state other
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

#include "can_frame.h"
#include "config.h"
#include "hist.h"

/* The output's state: status_t's CAN_OFF, CAN_OK, CAN_LOST. */
enum { KD_CAN_OFF = 0, KD_CAN_OK = 1, KD_CAN_LOST = 2 };

#define KD_CAN_TEXT 200
#define KD_CAN_RING 1024 /* bus cycles whose targets are kept */

typedef struct kd_can {
    const kd_can_cfg *cfg;
    int n;             /* joints */
    int64_t period_ns; /* of the cycle */
    int fd;            /* -1 when closed */
    int state;         /* KD_CAN_OFF, KD_CAN_OK, KD_CAN_LOST */
    char lost_text[KD_CAN_TEXT];   /* why it is lost */
    int state_changed;             /* 1: the I/O thread should tell (status) */
    int64_t next_probe_ns, next_heartbeat_ns, heartbeat_period_ns, started_ns;
    int8_t node_joint[128];        /* node id -> joint index, -1: none */

    /* Counters since start. */
    int64_t frames, tx_dropped, error_frames, bus_off, link_down, rx_frames, errors;
    int last_errno;

    /* Targets of the last KD_CAN_RING bus cycles that went out (joint
     * units), by SYNC number; TPDOs seen per joint; following errors. */
    double target[KD_CAN_RING][KC_MAX_JOINTS];
    int64_t syncs_out;
    int64_t tpdos[KC_MAX_JOINTS];
    double following[KC_MAX_JOINTS];

    /* Feedback per joint. */
    int have_fb[KC_MAX_JOINTS];
    double q_fb[KC_MAX_JOINTS], qd_fb[KC_MAX_JOINTS];
    uint16_t statusword[KC_MAX_JOINTS];
    int64_t heartbeat_ns[KC_MAX_JOINTS]; /* last heartbeat heard (0: never) */
    uint8_t nmt_state[KC_MAX_JOINTS];

    /* The first condition that stops the arm, while it lasts. */
    int condition;                 /* 0 none, else KD_CAN_COND_* */
    char condition_text[KD_CAN_TEXT];

    /* Time spent encoding and writing a bus cycle (ns), since start. */
    kd_hist send_ns;
} kd_can;

enum { KD_CAN_COND_NONE = 0, KD_CAN_COND_DRIVE = 1, KD_CAN_COND_BUS = 2 };

/* Opens the interface named in cfg (cfg->enable set) for n joints at the
 * cycle's period; now is CLOCK_MONOTONIC (ns). Returns 0, or -1 with a
 * message on stderr (no such interface, no AF_CAN in this kernel). With
 * cfg->enable clear it only sets the output OFF and returns 0. */
int kd_can_open(kd_can *c, const kd_can_cfg *cfg, int n, int64_t period_ns, int64_t now);

void kd_can_close(kd_can *c);

/* The socket to poll for feedback and error frames (-1: none). */
int kd_can_fd(const kd_can *c);

/* One tick's setpoint (cycle number, q and qd of n joints): a bus cycle when
 * cycle is a multiple of sync_every. */
void kd_can_send(kd_can *c, int64_t cycle, const kc_real *q, const kc_real *qd);

/* Reads what the socket holds (at most a bounded burst). */
void kd_can_receive(kd_can *c, int64_t now);

/* Timers: master heartbeat, the drives' heartbeat watchdog, probing a lost
 * interface. */
void kd_can_timers(kd_can *c, int64_t now);

/* The condition stopping the arm now (KD_CAN_COND_*), its text in c. */
int kd_can_condition(const kd_can *c);

#endif
