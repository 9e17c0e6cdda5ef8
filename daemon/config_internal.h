/* SPDX-License-Identifier: BSD-3-Clause */
/* config_internal.h - what the rooms of kinctld's configuration share:
 * the command line (args.c), the file (config_file.c) and the whole that
 * config.c makes of them with the defaults. */
#ifndef KINCTL_DAEMON_CONFIG_INTERNAL_H
#define KINCTL_DAEMON_CONFIG_INTERNAL_H

#include "config.h"

#define KD_PERIOD_US_MIN 100
#define KD_PERIOD_US_MAX 100000
#define KD_QUEUE_MIN 2
#define KD_QUEUE_MAX 4096

/* What the command line says (NULL, -1: not given). */
typedef struct kd_args {
    const char *config_path, *model, *prefix, *url;
    long period_us; /* checked against KD_PERIOD_US_MIN .. MAX */
    int rt;         /* 1 --rt, 0 --no-rt */
    int check;      /* --check */
} kd_args;

/* Parses argv (getopt_long); the model's name is checked, prefix and URL
 * are checked where they are applied (config.c). KD_CONFIG_EXIT after
 * --help (printed to stdout), KD_CONFIG_ERROR with the problem on stderr. */
kd_config_result kd_args_parse(kd_args *a, int argc, char **argv);

/* What the file's controller section says that needs the command line or
 * the robot before it can be applied. */
typedef struct kd_file {
    int has_robot;            /* the file has a robot section (read into cfg) */
    int robot_deg;            /* its angles are in degrees */
    int has_period;
    double period_us;
    int has_home, home_deg_set, home_deg;
    int home_n, home_line;
    double home[KC_MAX_JOINTS];
    int has_url;
    char url[KD_URL_MAX];
    int zones_line, margin_line; /* controller.zones and its margin (0: absent) */
} kd_file;

/* Parses the file at path once and reads it: the controller section into
 * cfg and f, controller.zones, and the robot section (into cfg->chain,
 * robot_name and volume_names). Returns 0, or -1 with "<file>:<line>:
 * <problem>" on stderr. */
int kd_config_read_file(const char *path, kd_config *cfg, kd_file *f);

/* "kinctld: <problem>" on stderr (a flag's or the whole's). */
#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
void kd_problem(const char *fmt, ...);

/* Why a channel prefix or an LCM URL is refused (NULL: it is fine). */
const char *kd_prefix_problem(const char *p);
const char *kd_url_problem(const char *u);

#endif
