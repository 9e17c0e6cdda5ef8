/* SPDX-License-Identifier: BSD-3-Clause */
/* config_file.c - kinctld's configuration file (config.h), parsed once:
 * the top level, the controller section (its can group: can_config.c), and
 * through the description library (kinctl/desc_tree.h) controller.zones
 * and the robot section, every problem "<file>:<line>: <problem>". */
#include "config_internal.h"

#include <libconfig.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "kinctl/cfgread.h"
#include "kinctl/desc_tree.h"

/* The controller section (config.h) into cfg; what waits for the command
 * line or the robot (period, LCM URL, home) into fc. */
static int read_controller(kc_cfg *r, const config_setting_t *c, kd_config *cfg, kd_file *fc)
{
    static const char *const keys[] = {"period_us", "angles", "home", "vel_scale", "acc_scale", "prefix",
                                       "lcm_url", "queue_size", "servo_timeout_ms", "check_max_s", "check_budget_ms",
                                       "stop_timeout_s", "status_hz", "stats_hz", "overrun", "rt", "plant",
                                       "cartesian", "can", "zones", "profile", NULL};
    static const char *const overrun_keys[] = {"missed_cycles", "action", NULL};
    static const char *const rt_keys[] = {"enable", "priority", "cpu", "mlock", NULL};
    static const char *const plant_keys[] = {"lag_s", NULL};
    static const char *const cart_keys[] = {"speed",        "accel", "omega", "alpha", "jerk", "angular_jerk",
                                            "track_tol",    NULL};
    const config_setting_t *s, *g;
    const char *str = NULL;
    double v, ms;

    if (!config_setting_is_group(c))
        return kc_cfg_fail(r, c, "controller must be a group: controller = { period_us = 1000; ... };");
    if (kc_cfg_check_keys(r, c, "controller", keys) != 0)
        return -1;

    v = 0.0;
    if (kc_cfg_lookup_number(r, c, "period_us", "controller", KD_PERIOD_US_MIN, KD_PERIOD_US_MAX, &v) != 0)
        return -1;
    if (config_setting_get_member(c, "period_us") != NULL) {
        fc->has_period = 1;
        fc->period_us = v;
    }
    if (kc_cfg_lookup_string(r, c, "angles", "controller", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        if (strcmp(str, "rad") != 0 && strcmp(str, "deg") != 0)
            return kc_cfg_fail(r, s, "controller.angles must be \"rad\" or \"deg\", not \"%s\"", str);
        fc->home_deg_set = 1;
        fc->home_deg = strcmp(str, "deg") == 0;
    }
    s = config_setting_get_member(c, "home");
    if (s != NULL) {
        int i, n = config_setting_length(s);
        if (!config_setting_is_aggregate(s) || n < 1 || n > KC_MAX_JOINTS)
            return kc_cfg_fail(r, s, "controller.home must be a vector of 1 to %d numbers, one per joint",
                               KC_MAX_JOINTS);
        for (i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(s, (unsigned)i);
            double x;
            if (!kc_cfg_is_number(e))
                return kc_cfg_fail(r, s, "controller.home[%d] must be a number", i);
            x = kc_cfg_value(e);
            if (!isfinite(x))
                return kc_cfg_fail(r, s, "controller.home[%d] is not a finite number", i);
            fc->home[i] = x;
        }
        fc->has_home = 1;
        fc->home_n = n;
        fc->home_line = (int)config_setting_source_line(s);
    }
    if (kc_cfg_lookup_number(r, c, "vel_scale", "controller", 0.0, 1.0, &cfg->vel_scale) != 0 ||
        kc_cfg_lookup_number(r, c, "acc_scale", "controller", 0.0, 1.0, &cfg->acc_scale) != 0)
        return -1;
    if (!(cfg->vel_scale > 0.0))
        return kc_cfg_fail(r, config_setting_get_member(c, "vel_scale"), "controller.vel_scale must be > 0");
    if (!(cfg->acc_scale > 0.0))
        return kc_cfg_fail(r, config_setting_get_member(c, "acc_scale"), "controller.acc_scale must be > 0");
    if (kc_cfg_lookup_string(r, c, "profile", "controller", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        if (strcmp(str, "jerk") == 0)
            cfg->ctrl.profile = KC_PROFILE_JERK;
        else if (strcmp(str, "trapezoid") == 0)
            cfg->ctrl.profile = KC_PROFILE_TRAPEZOID;
        else
            return kc_cfg_fail(r, s, "controller.profile must be \"jerk\" or \"trapezoid\", not \"%s\"", str);
    }
    if (kc_cfg_lookup_string(r, c, "prefix", "controller", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        const char *why = kd_prefix_problem(str);
        if (why != NULL)
            return kc_cfg_fail(r, s, "controller.prefix \"%s\" %s", str, why);
        snprintf(cfg->prefix, sizeof cfg->prefix, "%s", str);
    }
    if (kc_cfg_lookup_string(r, c, "lcm_url", "controller", &str, &s) != 0)
        return -1;
    if (s != NULL && str[0] != '\0') {
        const char *why = kd_url_problem(str);
        if (why != NULL)
            return kc_cfg_fail(r, s, "controller.lcm_url \"%s\" %s", str, why);
        fc->has_url = 1;
        snprintf(fc->url, sizeof fc->url, "%s", str);
    }
    if (kc_cfg_lookup_int(r, c, "queue_size", "controller", KD_QUEUE_MIN, KD_QUEUE_MAX, &cfg->queue_size) != 0)
        return -1;
    ms = cfg->servo_timeout_s * 1e3;
    if (kc_cfg_lookup_number(r, c, "servo_timeout_ms", "controller", 1.0, 60000.0, &ms) != 0)
        return -1;
    cfg->servo_timeout_s = ms * 1e-3;
    ms = cfg->check_budget_s * 1e3;
    if (kc_cfg_lookup_number(r, c, "check_budget_ms", "controller", 1.0, 600000.0, &ms) != 0)
        return -1;
    cfg->check_budget_s = ms * 1e-3;
    if (kc_cfg_lookup_number(r, c, "check_max_s", "controller", 0.1, 3600.0, &cfg->check_max_s) != 0 ||
        kc_cfg_lookup_number(r, c, "stop_timeout_s", "controller", 0.0, 600.0, &cfg->stop_timeout_s) != 0 ||
        kc_cfg_lookup_number(r, c, "status_hz", "controller", 0.1, 1000.0, &cfg->status_hz) != 0 ||
        kc_cfg_lookup_number(r, c, "stats_hz", "controller", 0.01, 100.0, &cfg->stats_hz) != 0)
        return -1;

    if (kc_cfg_lookup_group(r, c, "overrun", "controller", &g) != KC_OK)
        return -1;
    if (g != NULL) {
        if (kc_cfg_check_keys(r, g, "controller.overrun", overrun_keys) != 0 ||
            kc_cfg_lookup_int(r, g, "missed_cycles", "controller.overrun", 0, 1000000, &cfg->overrun_missed) != 0 ||
            kc_cfg_lookup_string(r, g, "action", "controller.overrun", &str, &s) != 0)
            return -1;
        if (s != NULL) {
            if (strcmp(str, "stop") == 0)
                cfg->overrun_action = KC_CMD_STOP;
            else if (strcmp(str, "estop") == 0)
                cfg->overrun_action = KC_CMD_ESTOP;
            else
                return kc_cfg_fail(r, s, "controller.overrun.action must be \"stop\" or \"estop\", not \"%s\"", str);
        }
    }
    if (kc_cfg_lookup_group(r, c, "rt", "controller", &g) != KC_OK)
        return -1;
    if (g != NULL) {
        long ncpu = sysconf(_SC_NPROCESSORS_CONF);
        int cpu_max = ncpu > 0 && ncpu < 4096 ? (int)ncpu - 1 : 4095;
        if (kc_cfg_check_keys(r, g, "controller.rt", rt_keys) != 0 ||
            kc_cfg_lookup_bool(r, g, "enable", "controller.rt", &cfg->rt_enable) != 0 ||
            kc_cfg_lookup_int(r, g, "priority", "controller.rt", 1, 99, &cfg->rt_priority) != 0 ||
            kc_cfg_lookup_int(r, g, "cpu", "controller.rt", -1, cpu_max, &cfg->rt_cpu) != 0 ||
            kc_cfg_lookup_bool(r, g, "mlock", "controller.rt", &cfg->rt_mlock) != 0)
            return -1;
    }
    if (kc_cfg_lookup_group(r, c, "plant", "controller", &g) != KC_OK)
        return -1;
    if (g != NULL) {
        if (kc_cfg_check_keys(r, g, "controller.plant", plant_keys) != 0 ||
            kc_cfg_lookup_number(r, g, "lag_s", "controller.plant", 0.0, 10.0, &cfg->plant_lag_s) != 0)
            return -1;
    }
    if (kc_cfg_lookup_group(r, c, "can", "controller", &g) != KC_OK ||
        (g != NULL && kd_can_cfg_read(r, g, &cfg->can) != 0))
        return -1;
    if (kc_cfg_lookup_group(r, c, "cartesian", "controller", &g) != KC_OK)
        return -1;
    if (g != NULL) {
        double speed = (double)cfg->ctrl.cart_speed, accel = (double)cfg->ctrl.cart_accel;
        double omega = (double)cfg->ctrl.cart_omega, alpha = (double)cfg->ctrl.cart_alpha;
        double tol = (double)cfg->ctrl.track_tol, jerk = -1.0, angular_jerk = -1.0;
        if (kc_cfg_check_keys(r, g, "controller.cartesian", cart_keys) != 0 ||
            kc_cfg_lookup_number(r, g, "speed", "controller.cartesian", 1e-6, 100.0, &speed) != 0 ||
            kc_cfg_lookup_number(r, g, "accel", "controller.cartesian", 1e-6, 1000.0, &accel) != 0 ||
            kc_cfg_lookup_number(r, g, "omega", "controller.cartesian", 1e-6, 1000.0, &omega) != 0 ||
            kc_cfg_lookup_number(r, g, "alpha", "controller.cartesian", 1e-6, 10000.0, &alpha) != 0 ||
            kc_cfg_lookup_number(r, g, "jerk", "controller.cartesian", 1e-6, 1e6, &jerk) != 0 ||
            kc_cfg_lookup_number(r, g, "angular_jerk", "controller.cartesian", 1e-6, 1e7, &angular_jerk) != 0 ||
            kc_cfg_lookup_number(r, g, "track_tol", "controller.cartesian", 1e-9, 1.0, &tol) != 0)
            return -1;
        /* Jerk bounds not given follow the acceleration bounds, as the
         * core's defaults do (KC_INTERP_JERK_PER_ACCEL). */
        cfg->ctrl.cart_jerk = jerk > 0.0 ? (kc_real)jerk : KC_INTERP_JERK_PER_ACCEL * (kc_real)accel;
        cfg->ctrl.cart_angular_jerk =
            angular_jerk > 0.0 ? (kc_real)angular_jerk : KC_INTERP_JERK_PER_ACCEL * (kc_real)alpha;
        cfg->ctrl.cart_speed = (kc_real)speed;
        cfg->ctrl.cart_accel = (kc_real)accel;
        cfg->ctrl.cart_omega = (kc_real)omega;
        cfg->ctrl.cart_alpha = (kc_real)alpha;
        cfg->ctrl.track_tol = (kc_real)tol;
    }
    return 0;
}

int kd_config_read_file(const char *path, kd_config *cfg, kd_file *f)
{
    static const char *const sections[] = {"robot", "controller", NULL};
    kc_desc_error err;
    kc_cfg r = {path, ".", &err};
    config_t tree;
    const config_setting_t *root, *c, *robot;
    int rc = 0;

    memset(&err, 0, sizeof err);
    if (kc_cfg_parse_file(&r, path, &tree) != KC_OK) {
        fprintf(stderr, "%s\n", err.text);
        return -1;
    }
    root = config_root_setting(&tree);
    c = config_setting_get_member(root, "controller");
    robot = config_setting_get_member(root, "robot");
    f->has_robot = robot != NULL;
    if (kc_cfg_check_keys(&r, root, "the top level", sections) != KC_OK)
        rc = -1;
    if (rc == 0 && c != NULL && read_controller(&r, c, cfg, f) != 0)
        rc = -1;
    if (rc == 0 && c != NULL) {
        /* controller.zones, in the description library's format. */
        kc_desc_zone_info info;
        const config_setting_t *zs = config_setting_get_member(c, "zones");
        if (zs != NULL) {
            const config_setting_t *m = config_setting_is_group(zs) ? config_setting_get_member(zs, "margin") : NULL;
            f->zones_line = (int)config_setting_source_line(zs);
            f->margin_line = m != NULL ? (int)config_setting_source_line(m) : f->zones_line;
        }
        if (kc_desc_read_zones(zs, path, &cfg->zones, &info, &err) != KC_OK)
            rc = -1;
        else
            for (int z = 0; z < info.n_zones; z++)
                snprintf(cfg->zone_names[z], sizeof cfg->zone_names[z], "%s", info.names[z]);
    }
    if (rc == 0 && robot != NULL) {
        kc_desc_info info;
        if (kc_desc_read_robot(robot, path, &cfg->chain, &info, &err) != KC_OK) {
            rc = -1;
        } else {
            snprintf(cfg->robot_name, sizeof cfg->robot_name, "%s", info.name);
            f->robot_deg = info.angles_deg;
            for (int v = 0; v < info.n_volumes; v++)
                snprintf(cfg->volume_names[v], sizeof cfg->volume_names[v], "%s", info.volume_names[v]);
            memcpy(cfg->joint_lines, info.joint_lines, sizeof cfg->joint_lines);
            for (int j = 0; j < info.n_joints; j++)
                snprintf(cfg->joint_names[j], sizeof cfg->joint_names[j], "%s", info.joint_names[j]);
        }
    }
    if (rc != 0)
        fprintf(stderr, "%s\n", err.text);
    config_destroy(&tree);
    return rc;
}
