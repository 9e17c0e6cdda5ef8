/* SPDX-License-Identifier: BSD-3-Clause */
/* config.c - kinctld's configuration (config.h): the defaults, then the
 * file (config_file.c), then the command line (args.c) over it, and the
 * checks that need them all (the robot, the home joints, CAN, zones, the
 * controller's own). */
#include "config_internal.h"
#include "can_budget.h"
#include "lcm_rx.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void kd_problem(const char *fmt, ...)
{
    va_list ap;
    fputs("kinctld: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

/* ---- checks shared by the file and the flags --------------------------- */

/* Channel prefixes become part of LCM's channel regular expressions: keep
 * them to characters that need no escaping but '.'. */
const char *kd_prefix_problem(const char *p)
{
    size_t i, n = strlen(p);
    if (n > KD_PREFIX_MAX)
        return "is longer than 64 characters";
    for (i = 0; i < n; i++) {
        char c = p[i];
        int ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
                 c == '.' || c == '/' || c == '-';
        if (!ok)
            return "may hold only letters, digits and _ . / -";
    }
    return NULL;
}

const char *kd_url_problem(const char *u)
{
    if (strlen(u) >= KD_URL_MAX)
        return "is longer than 255 characters";
    static char why[192];
    if (strstr(u, "://") == NULL)
        return "is not an LCM URL (provider://address?options, e.g. " KD_DEFAULT_URL ")";
    /* The receiver's grammar (lcm_rx.h) is the one judge of what kinctld
     * can listen on. */
    return kd_rx_url_check(u, why, sizeof why) == 0 ? NULL : why;
}

/* Says why the value of a flag (or of the environment's what) is
 * refused, when check gave a reason; 1 then. */
static int refused(const char *what, const char *value, const char *why)
{
    if (why == NULL)
        return 0;
    kd_problem("%s \"%s\" %s", what, value, why);
    return 1;
}

/* ---- defaults ---------------------------------------------------------- */

static int builtin_model(kd_config *cfg, const char *name)
{
    int m = kc_model_from_name(name);
    if (m < 0 || kc_chain_init_model(&cfg->chain, (kc_model)m, NULL) != KC_OK)
        return -1;
    snprintf(cfg->robot_name, sizeof cfg->robot_name, "%s", name);
    return 0;
}

static void defaults(kd_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->ctrl = kc_ctrl_cfg_default();
    cfg->period_ns = 1000000;
    cfg->vel_scale = 1.0;
    cfg->acc_scale = 1.0;
    snprintf(cfg->prefix, sizeof cfg->prefix, "%s", KD_DEFAULT_PREFIX);
    cfg->queue_size = 64;
    cfg->servo_timeout_s = 0.1;
    cfg->check_max_s = 120.0;
    cfg->check_budget_s = 0.5;
    cfg->stop_timeout_s = 5.0;
    cfg->status_hz = 10.0;
    cfg->stats_hz = 1.0;
    cfg->overrun_missed = 0;
    cfg->overrun_action = KC_CMD_STOP;
    cfg->rt_enable = 1;
    cfg->rt_priority = 80;
    cfg->rt_cpu = -1;
    cfg->rt_mlock = 1;
    cfg->plant_lag_s = 0.0;
    cfg->can = kd_can_cfg_default();
}

void kd_config_zone_pair(const kd_config *cfg, int zone, int volume, char *buf, int size)
{
    char zn[KD_NAME_MAX + 16], vn[KD_NAME_MAX + 16];
    if (size <= 0)
        return;
    if (zone >= 0 && zone < KC_ZONE_MAX && cfg->zone_names[zone][0] != '\0')
        snprintf(zn, sizeof zn, "\"%s\"", cfg->zone_names[zone]);
    else
        snprintf(zn, sizeof zn, "%d", zone + 1);
    if (volume >= 0 && volume < KC_MAX_VOLUMES && cfg->volume_names[volume][0] != '\0')
        snprintf(vn, sizeof vn, "\"%s\"", cfg->volume_names[volume]);
    else
        snprintf(vn, sizeof vn, "%d", volume + 1);
    snprintf(buf, (size_t)size, "zone %s and link volume %s (frame %d)", zn, vn,
             volume >= 0 && volume < cfg->chain.n_volumes ? cfg->chain.volumes[volume].frame + 1 : 0);
}

/* ---- everything together ----------------------------------------------- */

static void scale_limits(kc_chain *chain, double vel, double acc)
{
    int j;
    for (j = 0; j < chain->n_joints; j++) {
        kc_joint_limits *l = &chain->joints[j].limits;
        /* Infinite rates (no limit) stay infinite. */
        l->qd_max = (kc_real)((double)l->qd_max * vel);
        l->qdd_max = (kc_real)((double)l->qdd_max * acc);
        l->qddd_max = (kc_real)((double)l->qddd_max * acc);
    }
}

static void default_home(const kc_chain *chain, kc_real *home)
{
    int j;
    for (j = 0; j < chain->n_joints; j++) {
        const kc_joint_limits *l = &chain->joints[j].limits;
        if (l->q_min <= 0 && l->q_max >= 0)
            home[j] = 0;
        else if (isfinite((double)l->q_min) && isfinite((double)l->q_max))
            home[j] = (l->q_min + l->q_max) / 2;
        else
            home[j] = isfinite((double)l->q_min) ? l->q_min : l->q_max;
    }
}

/* The command line over the file (and the environment): prefix, LCM URL,
 * period, rt. */
static int apply_flags(kd_config *cfg, const kd_args *a, const kd_file *fc)
{
    const char *env;
    if (a->prefix != NULL) {
        if (refused("--prefix", a->prefix, kd_prefix_problem(a->prefix)))
            return -1;
        snprintf(cfg->prefix, sizeof cfg->prefix, "%s", a->prefix);
    }
    if (a->url != NULL) {
        if (refused("--lcm-url", a->url, kd_url_problem(a->url)))
            return -1;
        snprintf(cfg->lcm_url, sizeof cfg->lcm_url, "%s", a->url);
        cfg->lcm_url_source = "command line";
    } else if (fc->has_url) {
        snprintf(cfg->lcm_url, sizeof cfg->lcm_url, "%s", fc->url);
        cfg->lcm_url_source = "config";
    } else if ((env = getenv("LCM_DEFAULT_URL")) != NULL && env[0] != '\0') {
        if (refused("LCM_DEFAULT_URL", env, kd_url_problem(env)))
            return -1;
        snprintf(cfg->lcm_url, sizeof cfg->lcm_url, "%s", env);
        cfg->lcm_url_source = "LCM_DEFAULT_URL";
    } else {
        snprintf(cfg->lcm_url, sizeof cfg->lcm_url, "%s", KD_DEFAULT_URL);
        cfg->lcm_url_source = "default";
    }
    if (a->period_us > 0)
        cfg->period_ns = (int64_t)a->period_us * 1000;
    else if (fc->has_period)
        cfg->period_ns = (int64_t)llround(fc->period_us * 1000.0);
    if (a->rt >= 0)
        cfg->rt_enable = a->rt;
    return 0;
}

/* The start joints: controller.home (it needs the robot, known only now;
 * in the unit of controller.angles, else the robot section's), else
 * default_home. */
static int place_home(kd_config *cfg, const kd_file *fc, int robot_deg, const char *path)
{
    int n = fc->home_n, line = fc->home_line, j;
    int deg = fc->home_deg_set ? fc->home_deg : robot_deg;
    int bad_joint = -1;
    if (!fc->has_home) {
        default_home(&cfg->chain, cfg->home);
        return 0;
    }
    if (n != cfg->chain.n_joints) {
        fprintf(stderr, "%s:%d: controller.home has %d values, the arm \"%s\" has %d joints\n", path, line, n,
                cfg->robot_name, cfg->chain.n_joints);
        return -1;
    }
    for (j = 0; j < n; j++) {
        double x = fc->home[j];
        if (deg && cfg->chain.joints[j].type == KC_JOINT_REVOLUTE)
            x *= (double)KC_DEG;
        cfg->home[j] = (kc_real)x;
    }
    if (kc_chain_check_q(&cfg->chain, cfg->home, &bad_joint) != KC_OK) {
        fprintf(stderr, "%s:%d: controller.home[%d] is outside joint %d's limits [%.6g, %.6g]\n", path, line,
                bad_joint, bad_joint + 1, (double)cfg->chain.joints[bad_joint].limits.q_min,
                (double)cfg->chain.joints[bad_joint].limits.q_max);
        return -1;
    }
    return 0;
}

/* The zones against the arm: goals are checked tick by tick, so no volume
 * may travel the margin in one cycle (kinctl/zone.h). */
static int check_zones(kd_config *cfg, const char *path, const kd_file *fc)
{
    kc_real travel;
    if (cfg->zones.n_zones == 0)
        return 0;
    travel = kc_zone_tick_travel(&cfg->chain, cfg->ctrl.dt);
    cfg->ctrl.zones = &cfg->zones;
    if (cfg->chain.n_volumes == 0) {
        fprintf(stderr, "%s:%d: warning: controller.zones is set but robot \"%s\" has no link volumes\n", path,
                fc->zones_line, cfg->robot_name);
    } else if (!(cfg->zones.margin > travel)) {
        fprintf(stderr, "%s:%d: controller.zones.margin = %g m is not above %g m, the farthest a link volume moves "
                        "in one cycle at the joints' velocity limits (raise the margin, shorten period_us or lower "
                        "vel_scale)\n", path, fc->margin_line, (double)cfg->zones.margin, (double)travel);
        return -1;
    }
    return 0;
}

/* The controller's own check of the whole (kc_ctrl_cfg_check_field): what it
 * refuses, named by its key, or for a joint's limit by the joint and the line
 * of its row in the description. 0 when it takes the configuration. */
static int refuse_ctrl(const kd_config *cfg, const char *path)
{
    static const char *const keys[] = {
        [KC_CFG_FIELD_DT] = "period_us",
        [KC_CFG_FIELD_CART_SPEED] = "controller.cartesian.speed",
        [KC_CFG_FIELD_CART_ACCEL] = "controller.cartesian.accel",
        [KC_CFG_FIELD_CART_OMEGA] = "controller.cartesian.omega",
        [KC_CFG_FIELD_CART_ALPHA] = "controller.cartesian.alpha",
        [KC_CFG_FIELD_CART_JERK] = "controller.cartesian.jerk",
        [KC_CFG_FIELD_CART_ANGULAR_JERK] = "controller.cartesian.angular_jerk",
        [KC_CFG_FIELD_TRACK_TOL] = "controller.cartesian.track_tol",
        [KC_CFG_FIELD_LIMIT_SLACK] = "the limit slack",
        [KC_CFG_FIELD_SERVO_TIMEOUT] = "controller.servo_timeout_ms",
        [KC_CFG_FIELD_IK] = "the inverse kinematics settings",
        [KC_CFG_FIELD_PROFILE] = "controller.profile",
        [KC_CFG_FIELD_ZONES] = "controller.zones",
        [KC_CFG_FIELD_ZONES_MARGIN] = "controller.zones.margin",
    };
    kc_ctrl_cfg_field field;
    int j;
    const char *file = path != NULL ? path : "built-in model";
    if (kc_ctrl_cfg_check_field(&cfg->ctrl, &cfg->chain, &field, &j) == KC_OK)
        return 0;
    if (field == KC_CFG_FIELD_JOINT_QD_MAX || field == KC_CFG_FIELD_JOINT_QDD_MAX) {
        const char *what = field == KC_CFG_FIELD_JOINT_QD_MAX ? "velocity limit (limits.qd)"
                                                               : "acceleration limit (limits.qdd)";
        int line = cfg->joint_lines[j];
        if (line > 0)
            fprintf(stderr, "%s:%d: robot \"%s\" joint %d%s%s%s has no %s: the controller needs a finite one for "
                            "every joint\n",
                    file, line, cfg->robot_name, j + 1, cfg->joint_names[j][0] ? " (" : "", cfg->joint_names[j],
                    cfg->joint_names[j][0] ? ")" : "", what);
        else
            kd_problem("%s: robot \"%s\" joint %d has no %s: the controller needs a finite one for every joint", file,
                       cfg->robot_name, j + 1, what);
        return -1;
    }
    kd_problem("%s: the controller refuses %s with robot \"%s\"", file,
               field > KC_CFG_FIELD_ARG && (size_t)field < sizeof keys / sizeof keys[0] && keys[field] != NULL
                   ? keys[field]
                   : "this configuration",
               cfg->robot_name);
    return -1;
}

kd_config_result kd_config_load(kd_config *cfg, int argc, char **argv)
{
    kd_args a;
    kd_file fc;
    kd_config_result parsed;
    int robot_deg = 0;

    defaults(cfg);
    memset(&fc, 0, sizeof fc);
    parsed = kd_args_parse(&a, argc, argv);
    if (parsed != KD_CONFIG_RUN)
        return parsed;
    if (a.config_path != NULL) {
        snprintf(cfg->config_path, sizeof cfg->config_path, "%s", a.config_path);
        if (kd_config_read_file(a.config_path, cfg, &fc) != 0)
            return KD_CONFIG_ERROR;
        robot_deg = fc.robot_deg;
    }
    if (a.model != NULL || !fc.has_robot) {
        const char *model = a.model != NULL ? a.model : "puma560";
        memset(cfg->volume_names, 0, sizeof cfg->volume_names);
        memset(cfg->joint_lines, 0, sizeof cfg->joint_lines);
        memset(cfg->joint_names, 0, sizeof cfg->joint_names);
        if (builtin_model(cfg, model) != 0) {
            kd_problem("cannot build the built-in model \"%s\"", model);
            return KD_CONFIG_ERROR;
        }
        robot_deg = 0;
    }
    if (apply_flags(cfg, &a, &fc) != 0)
        return KD_CONFIG_ERROR;

    /* The robot: scaled limits and the start joints; its drives. */
    scale_limits(&cfg->chain, cfg->vel_scale, cfg->acc_scale);
    if (place_home(cfg, &fc, robot_deg, a.config_path) != 0 ||
        kd_can_cfg_check(&cfg->can, &cfg->chain, cfg->robot_name, a.config_path, cfg->period_ns) != 0)
        return KD_CONFIG_ERROR;

    /* The controller's configuration, checked by the core itself. */
    cfg->ctrl.dt = (kc_real)((double)cfg->period_ns * 1e-9);
    cfg->ctrl.servo_timeout_ticks = (int64_t)ceil(cfg->servo_timeout_s / ((double)cfg->period_ns * 1e-9));
    if (cfg->ctrl.servo_timeout_ticks < 1)
        cfg->ctrl.servo_timeout_ticks = 1;
    if (check_zones(cfg, a.config_path, &fc) != 0)
        return KD_CONFIG_ERROR;
    if (refuse_ctrl(cfg, a.config_path) != 0)
        return KD_CONFIG_ERROR;
    if (a.check) {
        char line[512];
        kd_config_describe(cfg, line, sizeof line);
        printf("%s\n", line);
        return KD_CONFIG_EXIT;
    }
    return KD_CONFIG_RUN;
}

void kd_config_describe(const kd_config *cfg, char *buf, int size)
{
    if (size <= 0)
        return;
    snprintf(buf, (size_t)size,
             "robot %s (%d joints%s), period %lld us, channels %s*, LCM %s (%s), queue %d, overrun policy %s, "
             "rt %s, plant lag %g s, CAN %s",
             cfg->robot_name, cfg->chain.n_joints, cfg->config_path[0] ? ", from the config file" : ", built-in",
             (long long)(cfg->period_ns / 1000), cfg->prefix, cfg->lcm_url, cfg->lcm_url_source, cfg->queue_size,
             cfg->overrun_missed > 0 ? (cfg->overrun_action == KC_CMD_ESTOP ? "estop" : "stop") : "off",
             cfg->rt_enable ? "on" : "off", cfg->plant_lag_s, cfg->can.enable ? cfg->can.interface : "off");
    size_t used = strlen(buf);
    if (cfg->can.enable && used < (size_t)size) {
        kd_can_budget b;
        kd_can_budget_use use;
        kd_can_budget_of(&cfg->can, cfg->period_ns, &b);
        if (kd_can_budget_check(&b, &use, NULL, 0) >= 0)
            snprintf(buf + used, (size_t)size - used, " (%d drives, %lld bit/s, bus %.0f %% of a %.0f us bus cycle)",
                     cfg->can.n_joints, (long long)cfg->can.bitrate, 100.0 * use.mean_share,
                     (double)use.cycle_ns / 1e3);
        used = strlen(buf);
    }
    if (used < (size_t)size)
        snprintf(buf + used, (size_t)size - used, ", ");
    used = strlen(buf);
    if (cfg->zones.n_zones == 0)
        snprintf(buf + used, (size_t)size - used, "zones off");
    else
        snprintf(buf + used, (size_t)size - used, "%d zones (margin %g m) against %d link volumes", cfg->zones.n_zones,
                 (double)cfg->zones.margin, cfg->chain.n_volumes);
}
