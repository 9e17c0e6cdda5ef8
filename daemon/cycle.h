/* SPDX-License-Identifier: BSD-3-Clause */
/* cycle.h - kinctld's cycle thread: kc_ctrl_step once per period on
 * absolute deadlines.
 *
 * Deadlines are start + k period on CLOCK_MONOTONIC, slept to with
 * clock_nanosleep(TIMER_ABSTIME), so that no error accumulates. Each tick:
 * take at most one goal and one command from the I/O thread's rings, step
 * the controller, step the simulated plant, and write the tick (setpoint,
 * events, timing) into the ring to the I/O thread, or drop and count it when
 * that ring is full; with drives on CAN, write the bus cycle right after the
 * step (can_bus.h: one non-blocking sendmmsg). Nothing here allocates,
 * locks, logs, decodes or publishes, and the only system calls are reading
 * the clock, sleeping and that write.
 *
 * Stalls. When the thread wakes a whole period or more after its deadline
 * (the machine stalled it), the deadlines it slept through are missed: they
 * are counted (overruns) and skipped, so the thread neither bursts to catch
 * up nor jumps the trajectory: the controller counts its own ticks, and
 * trajectory time advances by cycles actually executed. The optional
 * overrun policy sends STOP or ESTOP after a number of consecutive missed
 * cycles.
 *
 * Snapshots. The checker (checker.h) judges a replacing goal from the
 * controller's moving state: it asks for a copy of the kc_ctrl (snap_dst,
 * the checker's copy; snap_state KD_SNAP_ASKED), and the next tick, after
 * its step, copies the controller there once (KD_SNAP_COPYING while it
 * does, then KD_SNAP_DONE with the goals it had taken). A memcpy of
 * sizeof(kc_ctrl) in that one tick, no lock: the checker may withdraw an
 * ask (ASKED -> IDLE by compare-and-swap) but never touches snap_dst while
 * a copy is under way.
 *
 * Scheduled goals. A goal the checker judged for a later tick
 * (kc_goal.take_cycle) waits at the head of the goal ring until the tick
 * with that output cycle, and every goal behind it with it; commands pass.
 * One scheduled further than KD_HOLD_MAX_CYCLES ahead (not made by
 * kinctld's checker) is given at once, and refused by the controller.
 *
 * Timing. Wake-up latency (wake-up minus deadline) and compute time (the
 * tick's work) go into a pair of histograms: the cycle writes one while the
 * I/O thread reads the other, swapped on request (kd_cycle_stats_take).
 *
 * Threads: kd_cycle_init and kd_cycle_start/stop from the main thread;
 * the rings' other ends and kd_cycle_stats_take from the I/O thread only.
 */
#ifndef KINCTL_DAEMON_CYCLE_H
#define KINCTL_DAEMON_CYCLE_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>

#include "can_bus.h"
#include "clock.h"
#include "config.h"
#include "hist.h"
#include "kinctl/ctrl.h"
#include "plant.h"
#include "spsc.h"

/* One tick as the I/O thread receives it. */
typedef struct kd_tick {
    kc_ctrl_output out;
    int64_t deadline_ns;  /* this tick's deadline, CLOCK_MONOTONIC */
    int64_t goals_taken;  /* goals taken from the goal ring so far */
    int64_t servo_taken;  /* ... of which servo messages (the others passed a dry run) */
    int64_t cmds_taken;   /* commands taken so far */
    int64_t missed_total; /* overruns so far */
    kc_ctrl_command policy_cmd; /* the overrun policy fired this tick (or NONE) */
    int64_t policy_missed;      /* ... after this many consecutive missed cycles */
    kc_real q_meas[KC_MAX_JOINTS], qd_meas[KC_MAX_JOINTS];
    /* The step's inputs, published with the setpoint so that a log replays:
     * the goal's id (0: none), the command, the servo staleness flag. */
    int64_t in_goal_id;
    kc_ctrl_command in_command;
    int in_servo_stale;
    int in_fault; /* the step was given an external fault */
    int in_seated; /* the controller was seated (kc_ctrl_seat) before the step */
    /* The goal as the dry run handed it on (setpoint_t.input_goal_share ..). */
    double in_goal_share;
    int in_goal_stop_first;
    double in_goal_qu;
    int in_goal_scheduled; /* (setpoint_t.input_goal_scheduled ..) */
    int64_t in_goal_take_ahead;
    uint32_t in_goal_take_state;
    /* The last seat (kd_cmd.seat) the cycle took: kc_ctrl_seat's answer. */
    int seat_status, seat_joint;
} kd_tick;

/* The snapshot hand-off's states (kd_cycle.snap_state). */
enum { KD_SNAP_IDLE = 0, KD_SNAP_ASKED = 1, KD_SNAP_COPYING = 2, KD_SNAP_DONE = 3 };

/* A command with what the I/O thread wants done about it: a controller
 * command, or (seat set) the controller seated at q before the step
 * (kc_ctrl_seat: the drives' positions, can_master.h). */
typedef struct kd_cmd {
    kc_ctrl_command command;
    int seat;
    kc_real q[KC_MAX_JOINTS];
} kd_cmd;

#define KD_TICK_RING 2048 /* ticks in flight to the I/O thread (2 s at 1 kHz) */
/* Slots of the tick ring only ticks with events (or an overrun note) may
 * take: when the I/O thread falls behind, plain setpoints are dropped first
 * and every goal is still answered. Events come from goals the I/O thread
 * queued before it fell behind and from motions ending: a few a goal. */
#define KD_TICK_RESERVE 512
#define KD_CMD_RING 64
#define KD_HOLD_MAX_CYCLES 100000 /* a scheduled goal held at most this many cycles */

typedef struct kd_cycle {
    /* Configuration and the controller (caller-owned, large). */
    const kd_config *cfg;
    kc_ctrl *ctrl;
    kd_plant plant;
    int64_t period_ns;

    /* The bus cycle to write after each step (can_bus.h), or NULL. */
    kd_bus *bus;
    int seat_status, seat_joint; /* the last seat's answer */

    /* Rings: goals and commands in (the I/O thread produces), ticks out. */
    kd_spsc goals, cmds, ticks;

    /* The servo stream's staleness deadline (CLOCK_MONOTONIC ns; 0: none),
     * written by the I/O thread at each servo message's receipt. */
    atomic_llong servo_deadline_ns;

    /* An external fault the I/O thread raises (a kc_ctrl_reason; 0: none),
     * taken by the next tick as kc_ctrl_input.fault. */
    atomic_int ext_fault;

    /* The snapshot for the checker (see above): the state, where to copy
     * (the checker's, set before ASKED), and the goals from the checker the
     * controller had taken (the cycle's, read after DONE). */
    atomic_int snap_state;
    kc_ctrl *snap_dst;
    int64_t snap_goals_taken;
    atomic_llong snapshots; /* copies made */

    /* Counters (written by the cycle, read anywhere). */
    atomic_llong cycles;        /* ticks executed */
    atomic_llong overruns;      /* deadlines missed */
    atomic_llong ticks_dropped; /* tick ring full (or only the reserve left): no setpoint */
    atomic_llong events_dropped; /* events of dropped ticks: the reserve ran out too */
    atomic_llong step_errors;   /* kc_ctrl_step refused a tick (a bug) */
    atomic_int state;           /* kc_ctrl_state of the last tick */
    int64_t goals_taken_total, servo_taken_total, cmds_taken_total; /* the cycle's own */
    kd_tick spare;              /* the cycle's output when the tick ring is full */

    /* Histograms: hist[active] is the cycle's. */
    kd_hist lat[2], comp[2];
    atomic_int hist_active;
    atomic_int swap_request; /* I/O sets 1; the cycle swaps and clears it */
    int stats_pending;       /* the I/O thread's: a swap was asked for */

    /* Lifecycle. */
    atomic_int run;
    atomic_int started; /* 1 once the first tick ran */
    int rt_applied;     /* what the thread got: bit 0 SCHED_FIFO, 1 affinity */
    pthread_t thread;
    atomic_int thread_live;
} kd_cycle;

/* Sets up the cycle over the caller's controller (kc_ctrl_init done) and
 * the ring storage (capacities as kd_spsc_init wants: goal_storage holds
 * goal_capacity kc_goal). Returns 0 or -1. */
int kd_cycle_init(kd_cycle *c, const kd_config *cfg, kc_ctrl *ctrl, kc_goal *goal_storage, size_t goal_capacity,
                  kd_cmd *cmd_storage, kd_tick *tick_storage);

/* Starts the thread: SCHED_FIFO at cfg->rt_priority and on cfg->rt_cpu when
 * cfg->rt_enable and permitted, otherwise a warning on stderr and a normal
 * thread. Returns 0 or -1 (no thread could be created). */
int kd_cycle_start(kd_cycle *c);

/* The CPU the cycle thread is pinned to (the configured one, else the last
 * one), or -1 when it is not pinned (RT off, or a single CPU). */
int kd_cycle_cpu(const kd_config *cfg);

/* Keeps thread (the I/O or the checker thread, named what for a warning)
 * off the cycle's CPU, so that it never sits between the cycle and its
 * wake-up. Main thread. */
void kd_cycle_keep_off(const kd_config *cfg, pthread_t thread, const char *what);

/* Checker thread: asks the next tick for a copy of the controller into
 * dst (the cycle keeps no lock for it) and waits at most wait_ns for it.
 * Returns 1 with the copy made (*goals_taken: goals the controller had
 * taken, servo messages not counted), 0 when none came in time (the ask
 * withdrawn: dst is the caller's again). Not for the cycle thread. */
int kd_cycle_snapshot(kd_cycle *c, kc_ctrl *dst, int64_t wait_ns, int64_t *goals_taken);

/* Stops the thread after its current tick and joins it. */
void kd_cycle_stop(kd_cycle *c);

/* Timing of the cycles since the previous take. */
typedef struct kd_cycle_stats {
    int64_t count;
    int64_t lat_p50, lat_p99, lat_p999, lat_max;
    int64_t comp_p50, comp_p99, comp_max;
} kd_cycle_stats;

/* I/O thread: asks the cycle to swap histograms (returns 0: asked, come
 * back later) and, once it has, reads and clears the retired pair (returns
 * 1 with *s filled). Never waits. */
int kd_cycle_stats_take(kd_cycle *c, kd_cycle_stats *s);

#endif
