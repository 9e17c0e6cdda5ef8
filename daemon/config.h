/* SPDX-License-Identifier: BSD-3-Clause */
/* config.h - kinctld's configuration: the robot, the controller section and
 * the command line (config.c puts them together: the file is read in
 * config_file.c, the command line in args.c, controller.can in
 * can_config.c).
 *
 * Sources, later ones winning: built-in defaults (the puma560 model at
 * 1 kHz), the file given with --config (a robot description of
 * core/desc/include/kinctl/desc.h, with or without its robot section, plus
 * an optional controller section), then the command-line flags. Everything
 * is read and checked at start-up, before any thread starts or anything
 * moves; a problem is one line "<file>:<line>: <problem>" (or "kinctld:
 * <problem>" for a flag) and exit code 2.
 *
 * The controller section (every key optional; unknown keys are errors):
 *
 *   controller = {
 *     period_us = 1000;         # cycle period (us), 100 .. 100000
 *     angles = "rad";           # unit of home: "rad" or "deg"; default: the
 *                               # robot section's angles (rad without one)
 *     home = [0.0, ...];        # start joints, one per joint; default: 0
 *                               # where inside the limits, else mid-range
 *     vel_scale = 1.0;          # (0, 1]: scales every joint's qd limit
 *     acc_scale = 1.0;          # (0, 1]: scales every qdd and qddd limit
 *     profile = "jerk";         # joint moves' motion law: "jerk" or
 *                               # "trapezoid"; a goal may ask for either
 *     prefix = "KINCTL_";       # channel prefix: [A-Za-z0-9_./-], <= 64
 *     lcm_url = "";             # "": $LCM_DEFAULT_URL, else
 *                               # udpm://239.255.76.67:7667?ttl=0
 *     queue_size = 64;          # goals in flight from the I/O thread to
 *                               # the cycle (rounded up to a power of 2),
 *                               # 2 .. 4096; the controller queues
 *                               # KC_CTRL_QUEUE_MAX more itself
 *     servo_timeout_ms = 100.0; # longest staleness a servo stream may
 *                               # ask for (its timeout_us is capped)
 *     check_max_s = 120.0;      # longest motion the dry run follows
 *     check_budget_ms = 500.0;  # longest a dry run may take (wall clock),
 *                               # 1 .. 600000; longer: rejected
 *     stop_timeout_s = 5.0;     # SIGINT/SIGTERM: longest wait for rest
 *     status_hz = 10.0;         # periodic status rate (events are extra)
 *     stats_hz = 1.0;           # stats rate
 *     overrun = {
 *       missed_cycles = 0;      # stop after this many consecutive missed
 *                               # cycles; 0: never (the default)
 *       action = "stop";        # "stop" (on the path) or "estop"
 *     };
 *     rt = {
 *       enable = true;          # SCHED_FIFO, mlockall, affinity (each
 *                               # only when permitted, else a warning)
 *       priority = 80;          # SCHED_FIFO priority of the cycle, 1 .. 99
 *       cpu = -1;               # CPU of the cycle; -1: the last online CPU
 *                               # when there are several, else none
 *       mlock = true;
 *     };
 *     plant = { lag_s = 0.0; }; # simulated arm: first-order lag (s)
 *     can = { ... };            # CAN output: daemon/can_config.h
 *     cartesian = {             # defaults for Cartesian goals
 *       speed = 0.25; accel = 1.0;     # m/s, m/s^2
 *       omega = 1.0; alpha = 4.0;      # rad/s, rad/s^2 of the tool
 *       track_tol = 0.001;             # m: tool behind the path -> fault
 *     };
 *     zones = {                 # forbidden zones (base frame), checked
 *       margin = 0.02;          # against the robot's link volumes; the
 *       list = ( ... );         # format: core/desc/include/kinctl/desc.h
 *     };                        # (margin must exceed one cycle's travel)
 *   };
 *
 * Not for the cycle: stdio, libconfig, malloc.
 */
#ifndef KINCTL_DAEMON_CONFIG_H
#define KINCTL_DAEMON_CONFIG_H

#include <stdint.h>

#include "can_config.h"
#include "kinctl/chain.h"
#include "kinctl/ctrl.h"

#define KD_PREFIX_MAX 64
#define KD_URL_MAX 256
#define KD_NAME_MAX 64
#define KD_PATH_MAX 1024
#define KD_DEFAULT_URL "udpm://239.255.76.67:7667?ttl=0"
#define KD_DEFAULT_PREFIX "KINCTL_"

typedef struct kd_config {
    /* The arm, with its limits already scaled by vel_scale and acc_scale. */
    kc_chain chain;
    char robot_name[KD_NAME_MAX];
    char config_path[KD_PATH_MAX]; /* "" when none */
    kc_real home[KC_MAX_JOINTS];
    double vel_scale, acc_scale;
    /* The controller's own configuration (dt = period_ns / 1e9). */
    kc_ctrl_cfg ctrl;
    int64_t period_ns;
    char prefix[KD_PREFIX_MAX + 1];
    char lcm_url[KD_URL_MAX]; /* resolved: never empty */
    const char *lcm_url_source; /* "config", "command line", "LCM_DEFAULT_URL", "default" */
    int queue_size;
    double servo_timeout_s;
    double check_max_s;
    double check_budget_s; /* longest dry run (wall clock) */
    double stop_timeout_s;
    double status_hz, stats_hz;
    int overrun_missed;       /* 0: policy off */
    kc_ctrl_command overrun_action; /* KC_CMD_STOP or KC_CMD_ESTOP */
    int rt_enable, rt_priority, rt_cpu, rt_mlock;
    double plant_lag_s;
    kd_can_cfg can;
    /* controller.zones (cfg->ctrl.zones points here when there are any) and
     * the names messages give zones and link volumes ("" where none). */
    kc_zone_set zones;
    char zone_names[KC_ZONE_MAX][KD_NAME_MAX];
    char volume_names[KC_MAX_VOLUMES][KD_NAME_MAX];
    /* The robot section's name ("" where none) and line (0: a built-in
     * model) of each joint. */
    char joint_names[KC_MAX_JOINTS][KD_NAME_MAX];
    int joint_lines[KC_MAX_JOINTS];
} kd_config;

/* Outcome of kd_config_load. */
typedef enum kd_config_result {
    KD_CONFIG_RUN = 0,   /* configured: run */
    KD_CONFIG_EXIT = 1,  /* --help or --check done: exit 0 */
    KD_CONFIG_ERROR = 2  /* a problem, already printed to stderr: exit 2 */
} kd_config_result;

/* Parses the command line (getopt_long) and the files it names into cfg.
 * Prints --help to stdout and problems to stderr. */
kd_config_result kd_config_load(kd_config *cfg, int argc, char **argv);

/* Names a zone and a link volume for a message: zone "table" and link
 * volume "forearm" (frame 4), or zone 2 / volume 3 where unnamed. */
void kd_config_zone_pair(const kd_config *cfg, int zone, int volume, char *buf, int size);

/* One line about cfg for the log (robot, joints, period, URL, prefix). */
void kd_config_describe(const kd_config *cfg, char *buf, int size);

#endif
