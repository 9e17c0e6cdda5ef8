/* SPDX-License-Identifier: BSD-3-Clause */
/* main.c - kinctld: configuration, the threads (cycle, I/O, checker), and a
 * controlled stop.
 *
 * Start-up: configuration (exit 2 on a problem, before anything runs), the
 * controller at rest at the home joints, LCM, then mlockall (when rt is on
 * and permitted) and the checker, I/O and cycle threads. The main thread
 * then only waits for SIGINT or SIGTERM (blocked in every thread, taken here with
 * sigtimedwait): it asks the I/O thread to send STOP, waits until the
 * controller has taken it and the arm is at rest (at most stop_timeout_s; a
 * second signal cuts the wait short), stops the cycle, lets the I/O thread
 * publish the final status and stats, and exits 0.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#include "config.h"
#include "cycle.h"
#include "lcm_io.h"

/* Large and long-lived: static, never on a stack. */
static kd_config cfg;
static kc_ctrl ctrl;
static kc_check check;
static kd_cycle cycle;
static kd_io io;
static kd_tick ticks[KD_TICK_RING];
static kd_cmd cmds[KD_CMD_RING];

static int wait_signal(const sigset_t *set, int64_t timeout_ns)
{
    struct timespec ts;
    int sig;
    ts.tv_sec = (time_t)(timeout_ns / 1000000000LL);
    ts.tv_nsec = (long)(timeout_ns % 1000000000LL);
    sig = sigtimedwait(set, NULL, &ts);
    return sig > 0 ? sig : 0;
}

int main(int argc, char **argv)
{
    sigset_t set;
    kc_goal *goals;
    size_t goal_capacity;
    kc_status st;
    char line[1024];
    int sig;
    int64_t deadline;

    switch (kd_config_load(&cfg, argc, argv)) {
    case KD_CONFIG_RUN: break;
    case KD_CONFIG_EXIT: return 0;
    default: return 2;
    }

    /* Signals are taken by the main thread only: block them before any
     * thread exists so that every thread inherits the mask. */
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set, NULL);
    signal(SIGPIPE, SIG_IGN);

    st = kc_ctrl_init(&ctrl, &cfg.chain, &cfg.ctrl, cfg.home);
    if (st != KC_OK) {
        fprintf(stderr, "kinctld: the controller refuses robot \"%s\" with this configuration: %s\n", cfg.robot_name,
                kc_status_str(st));
        return 2;
    }
    goal_capacity = kd_spsc_round_capacity((size_t)cfg.queue_size);
    goals = calloc(goal_capacity, sizeof *goals);
    if (goals == NULL || kd_cycle_init(&cycle, &cfg, &ctrl, goals, goal_capacity, cmds, ticks) != 0) {
        fprintf(stderr, "kinctld: cannot set up the cycle\n");
        free(goals);
        return 1;
    }
    if (kd_io_init(&io, &cfg, &cycle, &check) != 0) {
        free(goals);
        return 1;
    }
    if (cfg.rt_enable && cfg.rt_mlock && mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
        fprintf(stderr, "kinctld: warning: mlockall failed (%s); page faults may delay cycles (grant CAP_IPC_LOCK or "
                        "LimitMEMLOCK=infinity)\n",
                strerror(errno));

    kd_config_describe(&cfg, line, sizeof line);
    fprintf(stderr, "kinctld: %s\n", line);
    if (kd_io_start(&io) != 0) {
        kd_io_destroy(&io);
        free(goals);
        return 1;
    }
    if (kd_cycle_start(&cycle) != 0) {
        kd_io_stop(&io);
        kd_io_destroy(&io);
        free(goals);
        return 1;
    }
    fprintf(stderr, "kinctld: running (cycle %s%s)\n", (cycle.rt_applied & 1) ? "SCHED_FIFO" : "normal priority",
            (cycle.rt_applied & 2) ? ", pinned" : "");

    do
        sig = wait_signal(&set, 1000000000LL);
    while (sig == 0);
    fprintf(stderr, "kinctld: %s: stopping the arm\n", strsignal(sig));

    atomic_store(&io.stop_request, 1);
    deadline = kd_now_ns() + (int64_t)(cfg.stop_timeout_s * 1e9);
    while (!atomic_load(&io.stop_done) && kd_now_ns() < deadline) {
        if (wait_signal(&set, 5000000LL) != 0) {
            fprintf(stderr, "kinctld: second signal: not waiting for the arm to stop\n");
            break;
        }
    }
    if (!atomic_load(&io.stop_done))
        fprintf(stderr, "kinctld: warning: the arm was not at rest within %g s\n", cfg.stop_timeout_s);

    kd_cycle_stop(&cycle);
    kd_io_stop(&io);
    kd_io_summary(&io, line, sizeof line);
    fprintf(stderr, "kinctld: %lld cycles, %lld overruns; %s\n", (long long)atomic_load(&cycle.cycles),
            (long long)atomic_load(&cycle.overruns), line);
    kd_io_destroy(&io);
    free(goals);
    return 0;
}
