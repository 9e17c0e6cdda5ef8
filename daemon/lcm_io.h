/* SPDX-License-Identifier: BSD-3-Clause */
/* lcm_io.h - kinctld's I/O thread: everything LCM, on one thread.
 *
 * In: the client channels
 *   <prefix>GOAL_JOINT  GOAL_LINE  GOAL_ARC  GOAL_PATH  GOAL_SERVO  COMMAND
 * (prefix "KINCTL_" by default), read off LCM's multicast group by kd_rx
 * (lcm_rx.h: kinctld's own socket behind a kernel filter, never LCM's
 * receive path, whose fragment buffers take any size a datagram claims).
 * Every datagram goes through kd_msg_decode (daemon/msg.h); one that fails
 * is counted by its reason and ignored, and answered with a status REJECTED
 * when it names a goal_id. Commands go straight into the cycle's command
 * ring. A valid goal is turned into a kc_goal (goal.h); a servo message
 * gets the cheap checks only (kc_ctrl_goal_check: it streams) and goes
 * straight into the cycle's goal ring, its staleness judged on
 * CLOCK_MONOTONIC at receipt. Every other goal goes to the checker thread
 * (checker.h), whose dry run judges it from where it will start; no dry
 * run, however long, stands between a datagram and the cycle. Its verdict
 * comes back in arrival order: a goal refused is answered with the text of
 * its verdict (reject.h), one taken goes to the cycle through the goal
 * ring (so each of the cycle's rings keeps one producer, this thread), and
 * a goal refused here before any dry run is answered in its turn.
 *
 * Out, each encoded into a preallocated buffer with kd_msg_encode:
 *   <prefix>SETPOINT  setpoint_t for every tick the cycle produced
 *   <prefix>STATUS    status_t on every controller event (ACCEPTED,
 *                     REJECTED, COMPLETED, PREEMPTED, ABORTED, FAULT; a
 *                     goal's start as event NONE), on every rejection here,
 *                     at status_hz (event NONE), and once at shutdown
 *                     (event NONE, reason "shutdown: ...")
 *   <prefix>STATS     stats_t at stats_hz
 *
 * CAN (optional): the cycle writes the bus cycle (can_bus.h); here the
 * link is drained on every pass of the loop (can_io.h) and the drives'
 * master (can_master.h) boots and enables them, seating the controller at
 * their positions through the command ring, and steers their controlwords
 * (ESTOP: quick stop; RESET: boot and enable again; shutdown: disable,
 * then NMT). Goals are refused until every drive is enabled. A drive or
 * bus condition is raised as the controller's external fault (cycle.h
 * ext_fault), again after a RESET while it lasts, and its text becomes the
 * FAULT's reason ("drive: ...", "can: "). status_t says the drives' state
 * (drives) and, with feedback on, their measured joints.
 *
 * The loop: drain the tick ring and publish (copying each tick to the
 * checker), answer the goals whose verdicts are back, then wait on the
 * receive socket and the checker's eventfd for at most one period and
 * handle what the socket holds, a burst at a time. At the end the checker
 * is stopped and every goal still waiting is answered (shutdown).
 */
#ifndef KINCTL_DAEMON_LCM_IO_H
#define KINCTL_DAEMON_LCM_IO_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>

#include <lcm/lcm.h>

#include "can_bus.h"
#include "can_io.h"
#include "can_master.h"
#include "checker.h"
#include "config.h"
#include "cycle.h"
#include "goal.h"
#include "lcm_rx.h"
#include "kinctl/check.h"
#include "msg.h"
#include "reject.h"

#define KD_CHANNEL_MAX (KD_PREFIX_MAX + 24)
#define KD_INVALID_KINDS 16 /* indexed by -kd_msg_status */

typedef struct kd_io kd_io;

struct kd_io {
    const kd_config *cfg;
    kd_cycle *cycle;
    kc_check *check; /* the goals' dry run, caller-owned (large): the checker thread's */
    kd_checker checker;
    lcm_t *lcm;  /* publishing only */
    kd_rx rx;    /* receiving */
    int64_t rx_errors;
    char channel[KD_MSG_TYPE_COUNT][KD_CHANNEL_MAX];
    int64_t realtime_offset_ns; /* CLOCK_REALTIME - CLOCK_MONOTONIC, for utime */

    /* Receive side. */
    kd_msg_any msg;
    kc_goal goal;
    int64_t goals_pushed, cmds_pushed;
    int64_t servo_id; /* the servo goal last handed to the cycle (0: none): its messages pass straight */
    kc_ctrl_cfg check_cfg; /* the controller's configuration at the dry run's coarser period */

    /* The latest tick seen. */
    kd_tick last;
    int have_last;

    /* Counters, the I/O thread's own (stats_t). */
    int64_t msgs_in, msgs_invalid, msgs_out, msgs_dropped, rejections;
    int64_t invalid_by[KD_INVALID_KINDS];
    int64_t publish_errors, step_errors_seen;

    /* Encoding: the messages and one buffer. */
    kinctl_setpoint_t sp;
    kinctl_status_t st;
    kinctl_stats_t stats;
    char reason[KD_MSG_STATUS_REASON_MAX + 1];
    unsigned char buf[KD_MSG_MAX_SIZE];

    /* CAN: the bus cycle (the cycle writes it), the link, the drives'
     * master, a seat on its way to the cycle, and the external fault
     * raised from a condition. */
    kd_bus bus;
    kd_can can;
    kd_master master;
    int seat_pending;
    int64_t seat_seq;
    int ext_raised;
    int64_t ext_raised_cycle;
    kc_ctrl_reason ext_reason;
    char ext_text[KD_CAN_TEXT];

    /* Why the controller was last told to stop: what a goal's ABORTED
     * says when the core gives no reason of its own (a STOP or ESTOP
     * command, the overrun policy's, kinctld's own at exit). */
    kc_ctrl_reason stop_reason;
    char stop_text[KD_REASON_TEXT];

    int64_t next_status_ns, next_stats_ns, status_period_ns, stats_period_ns;
    int stats_due;

    /* Lifecycle: main asks, the I/O thread answers. */
    atomic_int run;
    atomic_int stop_request; /* 1: send STOP and report when at rest */
    atomic_int stop_done;    /* 1: STOP taken and the arm at rest */
    int stop_sent;
    int64_t stop_seq;
    pthread_t thread;
    int thread_live;
};

/* Starts the goals' dry run in check (caller-owned storage) and sets the
 * checker up over it (budget controller.check_budget_ms), opens the
 * receive socket (kd_rx) and the LCM instance that publishes, both on
 * cfg->lcm_url. Returns 0, or -1 with a message on stderr (a configuration
 * the dry run refuses, a URL that is not UDP multicast or is malformed, no
 * network or multicast route). Main thread, before the threads start. */
int kd_io_init(kd_io *io, const kd_config *cfg, kd_cycle *cycle, kc_check *check);

/* Starts the checker thread, then the I/O thread, each off the cycle's
 * CPU. Returns 0 or -1. */
int kd_io_start(kd_io *io);

/* Stops the thread: it drains the tick ring, stops the checker thread and
 * answers every goal still waiting (REJECTED, shutdown), publishes the
 * final status and stats, and exits; then joins it. After kd_cycle_stop. */
void kd_io_stop(kd_io *io);

/* Frees LCM. After kd_io_stop. */
void kd_io_destroy(kd_io *io);

/* A one-line summary of the counters (invalid messages by reason...). */
void kd_io_summary(const kd_io *io, char *buf, int size);

#endif
