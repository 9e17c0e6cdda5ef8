/* config.c - kinctld's configuration (config.h): defaults, the description
 * file's robot section through libkinctl_desc, the controller section read
 * here with libconfig in the same error style, then the command line. */
#include "config.h"

#include <errno.h>
#include <getopt.h>
#include <libconfig.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "kinctl/desc.h"

#if defined(__GNUC__)
#define KD_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define KD_PRINTF(f, a)
#endif

#define KD_PERIOD_US_MIN 100
#define KD_PERIOD_US_MAX 100000
#define KD_QUEUE_MIN 2
#define KD_QUEUE_MAX 4096

/* ---- messages ---------------------------------------------------------- */

static void problem(const char *fmt, ...) KD_PRINTF(1, 2);
static void problem(const char *fmt, ...)
{
    va_list ap;
    fputs("kinctld: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

/* "<file>:<line>: <problem>" at setting s (the file of an @include'd
 * setting is its own). Returns -1 for `return bad(...)`. */
static int bad(const char *file, const config_setting_t *s, const char *fmt, ...) KD_PRINTF(3, 4);
static int bad(const char *file, const config_setting_t *s, const char *fmt, ...)
{
    va_list ap;
    const char *f = file;
    int line = 0;
    if (s != NULL) {
        if (config_setting_source_file(s) != NULL)
            f = config_setting_source_file(s);
        line = (int)config_setting_source_line(s);
    }
    if (line > 0)
        fprintf(stderr, "%s:%d: ", f, line);
    else
        fprintf(stderr, "%s: ", f);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    return -1;
}

/* ---- libconfig helpers ------------------------------------------------- */

static int check_keys(const char *file, const config_setting_t *group, const char *where,
                      const char *const *allowed)
{
    int i, n = config_setting_length(group);
    for (i = 0; i < n; i++) {
        const config_setting_t *s = config_setting_get_elem(group, (unsigned)i);
        const char *name = config_setting_name(s);
        const char *const *a;
        int known = 0;
        for (a = allowed; *a != NULL; a++)
            if (name != NULL && strcmp(name, *a) == 0)
                known = 1;
        if (!known) {
            char list[512] = "";
            for (a = allowed; *a != NULL; a++) {
                if (a != allowed)
                    strncat(list, ", ", sizeof list - strlen(list) - 1);
                strncat(list, *a, sizeof list - strlen(list) - 1);
            }
            return bad(file, s, "unknown key \"%s\" in %s (expected one of: %s)", name != NULL ? name : "?", where,
                       list);
        }
    }
    return 0;
}

static int is_number(const config_setting_t *s)
{
    int t = config_setting_type(s);
    return t == CONFIG_TYPE_INT || t == CONFIG_TYPE_INT64 || t == CONFIG_TYPE_FLOAT;
}

/* An optional number: *out unchanged when absent. Range [lo, hi] inclusive. */
static int get_number(const char *file, const config_setting_t *group, const char *key, const char *where,
                      double lo, double hi, double *out)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    double v;
    if (s == NULL)
        return 0;
    if (!is_number(s))
        return bad(file, s, "%s.%s must be a number", where, key);
    v = config_setting_get_float(s);
    if (config_setting_type(s) == CONFIG_TYPE_INT64)
        v = (double)config_setting_get_int64(s);
    else if (config_setting_type(s) == CONFIG_TYPE_INT)
        v = (double)config_setting_get_int(s);
    if (!isfinite(v))
        return bad(file, s, "%s.%s is not a finite number", where, key);
    if (v < lo || v > hi)
        return bad(file, s, "%s.%s = %.17g is outside %g .. %g", where, key, v, lo, hi);
    *out = v;
    return 0;
}

static int get_int(const char *file, const config_setting_t *group, const char *key, const char *where, int lo,
                   int hi, int *out)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    long long v;
    if (s == NULL)
        return 0;
    if (config_setting_type(s) == CONFIG_TYPE_INT)
        v = config_setting_get_int(s);
    else if (config_setting_type(s) == CONFIG_TYPE_INT64)
        v = config_setting_get_int64(s);
    else
        return bad(file, s, "%s.%s must be an integer", where, key);
    if (v < lo || v > hi)
        return bad(file, s, "%s.%s = %lld is outside %d .. %d", where, key, v, lo, hi);
    *out = (int)v;
    return 0;
}

static int get_bool(const char *file, const config_setting_t *group, const char *key, const char *where, int *out)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    if (s == NULL)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_BOOL)
        return bad(file, s, "%s.%s must be true or false", where, key);
    *out = config_setting_get_bool(s);
    return 0;
}

/* An optional string; *found set to the setting when present (and *out
 * set with it). */
static int get_string(const char *file, const config_setting_t *group, const char *key, const char *where,
                      const char **out, const config_setting_t **found)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    *found = NULL;
    if (s == NULL)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_STRING)
        return bad(file, s, "%s.%s must be a string in double quotes", where, key);
    *out = config_setting_get_string(s);
    *found = s;
    return 0;
}

static const config_setting_t *get_group(const char *file, const config_setting_t *group, const char *key,
                                         const char *where, int *err)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    if (s != NULL && !config_setting_is_group(s)) {
        bad(file, s, "%s.%s must be a group { ... }", where, key);
        *err = 1;
        return NULL;
    }
    return s;
}

/* ---- checks shared by the file and the flags --------------------------- */

/* Channel prefixes become part of LCM's channel regular expressions: keep
 * them to characters that need no escaping but '.'. */
static const char *prefix_problem(const char *p)
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

static const char *url_problem(const char *u)
{
    if (strlen(u) >= KD_URL_MAX)
        return "is longer than 255 characters";
    if (strstr(u, "://") == NULL)
        return "is not an LCM URL (provider://address?options, e.g. " KD_DEFAULT_URL ")";
    return NULL;
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
    cfg->can.sync_every = 1;
    cfg->can.master_id = 127;
    cfg->can.heartbeat_ms = 100.0;
    cfg->can.on_error_stop = 1;
    cfg->can.feedback = 0;
}

/* ---- the controller section -------------------------------------------- */

/* What the file says, before the command line and the robot are combined. */
typedef struct file_ctrl {
    int has_period;
    double period_us;
    int has_home, home_deg_set, home_deg;
    int home_n, home_line;
    double home[KC_MAX_JOINTS];
    int has_url;
    char url[KD_URL_MAX];
} file_ctrl;

static int read_can(const char *file, const config_setting_t *g, kd_can_cfg *can);

static int read_controller(const char *file, const config_setting_t *c, kd_config *cfg, file_ctrl *fc)
{
    static const char *const keys[] = {"period_us", "angles", "home", "vel_scale", "acc_scale", "prefix",
                                       "lcm_url", "queue_size", "servo_timeout_ms", "check_max_s",
                                       "stop_timeout_s", "status_hz", "stats_hz", "overrun", "rt", "plant",
                                       "cartesian", "can", "zones", NULL};
    static const char *const overrun_keys[] = {"missed_cycles", "action", NULL};
    static const char *const rt_keys[] = {"enable", "priority", "cpu", "mlock", NULL};
    static const char *const plant_keys[] = {"lag_s", NULL};
    static const char *const cart_keys[] = {"speed", "accel", "omega", "alpha", "track_tol", NULL};
    const config_setting_t *s, *g;
    const char *str = NULL;
    double v, ms;
    int err = 0;

    if (!config_setting_is_group(c))
        return bad(file, c, "controller must be a group: controller = { period_us = 1000; ... };");
    if (check_keys(file, c, "controller", keys) != 0)
        return -1;

    v = 0.0;
    if (get_number(file, c, "period_us", "controller", KD_PERIOD_US_MIN, KD_PERIOD_US_MAX, &v) != 0)
        return -1;
    if (config_setting_get_member(c, "period_us") != NULL) {
        fc->has_period = 1;
        fc->period_us = v;
    }
    if (get_string(file, c, "angles", "controller", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        if (strcmp(str, "rad") != 0 && strcmp(str, "deg") != 0)
            return bad(file, s, "controller.angles must be \"rad\" or \"deg\", not \"%s\"", str);
        fc->home_deg_set = 1;
        fc->home_deg = strcmp(str, "deg") == 0;
    }
    s = config_setting_get_member(c, "home");
    if (s != NULL) {
        int i, n = config_setting_length(s);
        if (!config_setting_is_aggregate(s) || n < 1 || n > KC_MAX_JOINTS)
            return bad(file, s, "controller.home must be a vector of 1 to %d numbers, one per joint", KC_MAX_JOINTS);
        for (i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(s, (unsigned)i);
            double x;
            if (!is_number(e))
                return bad(file, s, "controller.home[%d] must be a number", i);
            x = config_setting_type(e) == CONFIG_TYPE_FLOAT ? config_setting_get_float(e)
                                                            : (double)config_setting_get_int64(e);
            if (config_setting_type(e) == CONFIG_TYPE_INT)
                x = (double)config_setting_get_int(e);
            if (!isfinite(x))
                return bad(file, s, "controller.home[%d] is not a finite number", i);
            fc->home[i] = x;
        }
        fc->has_home = 1;
        fc->home_n = n;
        fc->home_line = (int)config_setting_source_line(s);
    }
    if (get_number(file, c, "vel_scale", "controller", 0.0, 1.0, &cfg->vel_scale) != 0 ||
        get_number(file, c, "acc_scale", "controller", 0.0, 1.0, &cfg->acc_scale) != 0)
        return -1;
    if (!(cfg->vel_scale > 0.0))
        return bad(file, config_setting_get_member(c, "vel_scale"), "controller.vel_scale must be > 0");
    if (!(cfg->acc_scale > 0.0))
        return bad(file, config_setting_get_member(c, "acc_scale"), "controller.acc_scale must be > 0");
    if (get_string(file, c, "prefix", "controller", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        const char *why = prefix_problem(str);
        if (why != NULL)
            return bad(file, s, "controller.prefix \"%s\" %s", str, why);
        snprintf(cfg->prefix, sizeof cfg->prefix, "%s", str);
    }
    if (get_string(file, c, "lcm_url", "controller", &str, &s) != 0)
        return -1;
    if (s != NULL && str[0] != '\0') {
        const char *why = url_problem(str);
        if (why != NULL)
            return bad(file, s, "controller.lcm_url \"%s\" %s", str, why);
        fc->has_url = 1;
        snprintf(fc->url, sizeof fc->url, "%s", str);
    }
    if (get_int(file, c, "queue_size", "controller", KD_QUEUE_MIN, KD_QUEUE_MAX, &cfg->queue_size) != 0)
        return -1;
    ms = cfg->servo_timeout_s * 1e3;
    if (get_number(file, c, "servo_timeout_ms", "controller", 1.0, 60000.0, &ms) != 0)
        return -1;
    cfg->servo_timeout_s = ms * 1e-3;
    if (get_number(file, c, "check_max_s", "controller", 0.1, 3600.0, &cfg->check_max_s) != 0 ||
        get_number(file, c, "stop_timeout_s", "controller", 0.0, 600.0, &cfg->stop_timeout_s) != 0 ||
        get_number(file, c, "status_hz", "controller", 0.1, 1000.0, &cfg->status_hz) != 0 ||
        get_number(file, c, "stats_hz", "controller", 0.01, 100.0, &cfg->stats_hz) != 0)
        return -1;

    g = get_group(file, c, "overrun", "controller", &err);
    if (err)
        return -1;
    if (g != NULL) {
        if (check_keys(file, g, "controller.overrun", overrun_keys) != 0 ||
            get_int(file, g, "missed_cycles", "controller.overrun", 0, 1000000, &cfg->overrun_missed) != 0 ||
            get_string(file, g, "action", "controller.overrun", &str, &s) != 0)
            return -1;
        if (s != NULL) {
            if (strcmp(str, "stop") == 0)
                cfg->overrun_action = KC_CMD_STOP;
            else if (strcmp(str, "estop") == 0)
                cfg->overrun_action = KC_CMD_ESTOP;
            else
                return bad(file, s, "controller.overrun.action must be \"stop\" or \"estop\", not \"%s\"", str);
        }
    }
    g = get_group(file, c, "rt", "controller", &err);
    if (err)
        return -1;
    if (g != NULL) {
        long ncpu = sysconf(_SC_NPROCESSORS_CONF);
        int cpu_max = ncpu > 0 && ncpu < 4096 ? (int)ncpu - 1 : 4095;
        if (check_keys(file, g, "controller.rt", rt_keys) != 0 ||
            get_bool(file, g, "enable", "controller.rt", &cfg->rt_enable) != 0 ||
            get_int(file, g, "priority", "controller.rt", 1, 99, &cfg->rt_priority) != 0 ||
            get_int(file, g, "cpu", "controller.rt", -1, cpu_max, &cfg->rt_cpu) != 0 ||
            get_bool(file, g, "mlock", "controller.rt", &cfg->rt_mlock) != 0)
            return -1;
    }
    g = get_group(file, c, "plant", "controller", &err);
    if (err)
        return -1;
    if (g != NULL) {
        if (check_keys(file, g, "controller.plant", plant_keys) != 0 ||
            get_number(file, g, "lag_s", "controller.plant", 0.0, 10.0, &cfg->plant_lag_s) != 0)
            return -1;
    }
    g = get_group(file, c, "can", "controller", &err);
    if (err || (g != NULL && read_can(file, g, &cfg->can) != 0))
        return -1;
    g = get_group(file, c, "cartesian", "controller", &err);
    if (err)
        return -1;
    if (g != NULL) {
        double speed = (double)cfg->ctrl.cart_speed, accel = (double)cfg->ctrl.cart_accel;
        double omega = (double)cfg->ctrl.cart_omega, alpha = (double)cfg->ctrl.cart_alpha;
        double tol = (double)cfg->ctrl.track_tol;
        if (check_keys(file, g, "controller.cartesian", cart_keys) != 0 ||
            get_number(file, g, "speed", "controller.cartesian", 1e-6, 100.0, &speed) != 0 ||
            get_number(file, g, "accel", "controller.cartesian", 1e-6, 1000.0, &accel) != 0 ||
            get_number(file, g, "omega", "controller.cartesian", 1e-6, 1000.0, &omega) != 0 ||
            get_number(file, g, "alpha", "controller.cartesian", 1e-6, 10000.0, &alpha) != 0 ||
            get_number(file, g, "track_tol", "controller.cartesian", 1e-9, 1.0, &tol) != 0)
            return -1;
        cfg->ctrl.cart_speed = (kc_real)speed;
        cfg->ctrl.cart_accel = (kc_real)accel;
        cfg->ctrl.cart_omega = (kc_real)omega;
        cfg->ctrl.cart_alpha = (kc_real)alpha;
        cfg->ctrl.track_tol = (kc_real)tol;
    }
    return 0;
}

/* controller.can (config.h). The joints' count and ranges are checked
 * against the arm in can_check, once the arm is known. */
static int read_can(const char *file, const config_setting_t *g, kd_can_cfg *can)
{
    static const char *const keys[] = {"interface", "sync_every", "master_id", "heartbeat_ms", "on_error",
                                       "joints", "feedback", NULL};
    static const char *const joint_keys[] = {"node", "counts_per_unit", "sign", "offset_counts", NULL};
    static const char *const fb_keys[] = {"enable", "following_error", "drive_timeout_ms", NULL};
    const config_setting_t *s, *fb;
    const char *str = "";
    int err = 0, i, k, n;
    if (check_keys(file, g, "controller.can", keys) != 0 ||
        get_string(file, g, "interface", "controller.can", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        if (strlen(str) >= KD_CAN_IFNAME_MAX)
            return bad(file, s, "controller.can.interface \"%s\" is longer than %d characters", str,
                       KD_CAN_IFNAME_MAX - 1);
        snprintf(can->interface, sizeof can->interface, "%s", str);
        can->enable = str[0] != '\0';
    }
    if (get_int(file, g, "sync_every", "controller.can", 1, 1000, &can->sync_every) != 0 ||
        get_int(file, g, "master_id", "controller.can", 1, 127, &can->master_id) != 0 ||
        get_number(file, g, "heartbeat_ms", "controller.can", 0.0, 60000.0, &can->heartbeat_ms) != 0 ||
        get_string(file, g, "on_error", "controller.can", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        if (strcmp(str, "stop") == 0)
            can->on_error_stop = 1;
        else if (strcmp(str, "lcm_only") == 0)
            can->on_error_stop = 0;
        else
            return bad(file, s, "controller.can.on_error must be \"stop\" or \"lcm_only\", not \"%s\"", str);
    }
    s = config_setting_get_member(g, "joints");
    if (s != NULL) {
        n = config_setting_length(s);
        if (!config_setting_is_aggregate(s) || n < 1 || n > KC_MAX_JOINTS)
            return bad(file, s, "controller.can.joints must be a list of 1 .. %d groups", KC_MAX_JOINTS);
        for (i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(s, (unsigned)i);
            kd_can_joint *jc = &can->joint[i];
            char where[64];
            double off = 0.0;
            snprintf(where, sizeof where, "controller.can.joints[%d]", i);
            if (!config_setting_is_group(e))
                return bad(file, e, "%s must be a group { node = ...; counts_per_unit = ...; }", where);
            if (config_setting_get_member(e, "node") == NULL || config_setting_get_member(e, "counts_per_unit") == NULL)
                return bad(file, e, "%s needs node and counts_per_unit", where);
            jc->sign = 1;
            if (check_keys(file, e, where, joint_keys) != 0 || get_int(file, e, "node", where, 1, 127, &jc->node) != 0 ||
                get_number(file, e, "counts_per_unit", where, 1e-9, 1e12, &jc->counts_per_unit) != 0 ||
                get_int(file, e, "sign", where, -1, 1, &jc->sign) != 0 ||
                get_number(file, e, "offset_counts", where, -2147483647.0, 2147483647.0, &off) != 0)
                return -1;
            if (jc->sign == 0)
                return bad(file, config_setting_get_member(e, "sign"), "%s.sign must be 1 or -1", where);
            jc->offset_counts = (int64_t)llround(off);
            for (k = 0; k < i; k++)
                if (can->joint[k].node == jc->node)
                    return bad(file, e, "%s.node = %d is also joint %d's", where, jc->node, k + 1);
        }
        can->n_joints = n;
    }
    fb = get_group(file, g, "feedback", "controller.can", &err);
    if (err)
        return -1;
    if (fb != NULL) {
        if (check_keys(file, fb, "controller.can.feedback", fb_keys) != 0 ||
            get_bool(file, fb, "enable", "controller.can.feedback", &can->feedback) != 0 ||
            get_number(file, fb, "following_error", "controller.can.feedback", 0.0, 1e6, &can->following_error) != 0 ||
            get_number(file, fb, "drive_timeout_ms", "controller.can.feedback", 0.0, 60000.0,
                       &can->drive_timeout_ms) != 0)
            return -1;
    }
    return 0;
}

/* The CAN section against the arm: one drive per joint, node ids apart
 * from the master's, and every position and velocity inside int32 counts. */
static int can_check(const char *path, kd_config *cfg)
{
    const kd_can_cfg *can = &cfg->can;
    const char *f = path != NULL ? path : "kinctld";
    int j;
    if (!can->enable)
        return 0;
    if (can->n_joints != cfg->chain.n_joints) {
        fprintf(stderr, "%s: controller.can.joints has %d drives, the arm \"%s\" has %d joints\n", f, can->n_joints,
                cfg->robot_name, cfg->chain.n_joints);
        return -1;
    }
    for (j = 0; j < can->n_joints; j++) {
        const kd_can_joint *jc = &can->joint[j];
        const kc_joint_limits *l = &cfg->chain.joints[j].limits;
        double reach = fmax(fabs((double)l->q_min), fabs((double)l->q_max)) * jc->counts_per_unit +
                       fabs((double)jc->offset_counts);
        double vel = (double)l->qd_max * jc->counts_per_unit;
        if (jc->node == can->master_id) {
            fprintf(stderr, "%s: controller.can.joints[%d].node = %d is the master's id (master_id)\n", f, j,
                    jc->node);
            return -1;
        }
        if (!(reach < 2147483647.0) || !(vel < 2147483647.0)) {
            fprintf(stderr,
                    "%s: controller.can.joints[%d]: joint %d's range [%.6g, %.6g] or speed %.6g at %.6g counts per "
                    "unit does not fit int32 counts\n",
                    f, j, j + 1, (double)l->q_min, (double)l->q_max, (double)l->qd_max, jc->counts_per_unit);
            return -1;
        }
    }
    return 0;
}

/* controller.zones, read by the description library (its format). */
static int read_zones(const char *path, kd_config *cfg)
{
    kc_desc_zone_info info;
    kc_desc_error err;
    if (kc_desc_load_zones(path, &cfg->zones, &info, &err) != KC_OK) {
        fprintf(stderr, "%s\n", err.text);
        return -1;
    }
    for (int z = 0; z < info.n_zones; z++)
        snprintf(cfg->zone_names[z], sizeof cfg->zone_names[z], "%s", info.names[z]);
    return 0;
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

/* Parses the file; fills the robot (unless a built-in model is forced) and
 * the controller section. *has_robot tells whether the file had a robot. */
static int read_file(const char *path, kd_config *cfg, file_ctrl *fc, int *robot_deg, int *has_robot)
{
    static const char *const sections[] = {"robot", "controller", NULL};
    config_t lc;
    const config_setting_t *root, *c;
    FILE *f;
    int rc = 0;

    f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "%s: cannot open: %s\n", path, strerror(errno));
        return -1;
    }
    fclose(f);
    config_init(&lc);
    config_set_options(&lc, CONFIG_OPTION_AUTOCONVERT);
    {
        /* @include "x.cfg" beside the including file, as the desc reader does. */
        char dir[KD_PATH_MAX];
        const char *slash = strrchr(path, '/');
        if (slash != NULL && (size_t)(slash - path) + 2 < sizeof dir) {
            size_t len = (size_t)(slash - path);
            memcpy(dir, path, len + (len == 0));
            dir[len + (len == 0)] = '\0';
            config_set_include_dir(&lc, dir);
        }
    }
    if (!config_read_file(&lc, path)) {
        const char *ef = config_error_file(&lc);
        fprintf(stderr, "%s:%d: %s\n", ef != NULL ? ef : path, config_error_line(&lc),
                config_error_text(&lc) != NULL ? config_error_text(&lc) : "syntax error");
        config_destroy(&lc);
        return -1;
    }
    root = config_root_setting(&lc);
    if (check_keys(path, root, "the top level", sections) != 0) {
        config_destroy(&lc);
        return -1;
    }
    *has_robot = config_setting_get_member(root, "robot") != NULL;
    c = config_setting_get_member(root, "controller");
    if (c != NULL)
        rc = read_controller(path, c, cfg, fc);
    if (rc == 0 && c != NULL && read_zones(path, cfg) != 0)
        rc = -1;
    if (rc == 0 && *has_robot) {
        kc_desc_info info;
        kc_desc_error err;
        if (kc_desc_load_file(path, &cfg->chain, &info, &err) != KC_OK) {
            fprintf(stderr, "%s\n", err.text);
            rc = -1;
        } else {
            snprintf(cfg->robot_name, sizeof cfg->robot_name, "%s", info.name);
            *robot_deg = info.angles_deg;
            for (int v = 0; v < info.n_volumes; v++)
                snprintf(cfg->volume_names[v], sizeof cfg->volume_names[v], "%s", info.volume_names[v]);
        }
    }
    config_destroy(&lc);
    return rc;
}

/* ---- the command line -------------------------------------------------- */

static void usage(FILE *out)
{
    fprintf(out,
            "Usage: kinctld [options]\n"
            "\n"
            "kinctl's motion controller daemon: takes goals over LCM, publishes a\n"
            "joint setpoint every cycle (simulated arm). With no options: the\n"
            "built-in puma560 at 1 kHz on $LCM_DEFAULT_URL or " KD_DEFAULT_URL ".\n"
            "\n"
            "Options (they override the configuration file):\n"
            "  -c, --config FILE     robot description and/or controller section\n"
            "                        (libconfig; see daemon/README.md)\n"
            "  -m, --model NAME      built-in arm: rrr3 planar2 puma560 panda rb211 rm01\n"
            "  -p, --period-us N     cycle period in us (%d .. %d; default 1000)\n"
            "  -P, --prefix TEXT     channel prefix (default \"" KD_DEFAULT_PREFIX "\")\n"
            "  -u, --lcm-url URL     LCM URL (default $LCM_DEFAULT_URL, else " KD_DEFAULT_URL ")\n"
            "      --rt              SCHED_FIFO, mlockall and CPU affinity (default)\n"
            "      --no-rt           none of them (tests, sanitizers, laptops)\n"
            "      --check           read and check the configuration, print it, exit\n"
            "  -h, --help            this text\n"
            "\n"
            "Channels: <prefix>GOAL_JOINT GOAL_LINE GOAL_ARC GOAL_PATH GOAL_SERVO COMMAND\n"
            "(in), <prefix>SETPOINT STATUS STATS (out). Setpoints to drives over SocketCAN\n"
            "(CiA 402 cyclic synchronous position): the controller.can section.\n"
            "\n"
            "Example:\n"
            "  kinctld --model panda --period-us 500 --lcm-url 'udpm://239.255.76.67:7667?ttl=0' --no-rt\n"
            "  kinctld --config /etc/kinctl/puma560.cfg\n"
            "\n"
            "Exit status: 0 after SIGINT/SIGTERM (arm stopped), 1 on a run-time\n"
            "failure, 2 on a bad configuration or command line.\n",
            KD_PERIOD_US_MIN, KD_PERIOD_US_MAX);
}

/* Parses a whole decimal integer. */
static int parse_long(const char *s, long *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (errno != 0 || end == s || *end != '\0')
        return -1;
    *out = v;
    return 0;
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

kd_config_result kd_config_load(kd_config *cfg, int argc, char **argv)
{
    enum { OPT_RT = 256, OPT_NO_RT, OPT_CHECK };
    static const struct option opts[] = {
        {"config", required_argument, NULL, 'c'},  {"model", required_argument, NULL, 'm'},
        {"period-us", required_argument, NULL, 'p'}, {"prefix", required_argument, NULL, 'P'},
        {"lcm-url", required_argument, NULL, 'u'}, {"rt", no_argument, NULL, OPT_RT},
        {"no-rt", no_argument, NULL, OPT_NO_RT},   {"check", no_argument, NULL, OPT_CHECK},
        {"help", no_argument, NULL, 'h'},          {NULL, 0, NULL, 0}};
    const char *config_path = NULL, *model = NULL, *prefix = NULL, *url = NULL;
    long period_us = -1;
    int rt = -1, check = 0, opt;
    file_ctrl fc;
    int robot_deg = 0, has_robot = 0, j;
    const char *env;

    defaults(cfg);
    memset(&fc, 0, sizeof fc);
    opterr = 0;
    optind = 1;
    while ((opt = getopt_long(argc, argv, ":c:m:p:P:u:h", opts, NULL)) != -1) {
        switch (opt) {
        case 'c': config_path = optarg; break;
        case 'm': model = optarg; break;
        case 'p':
            if (parse_long(optarg, &period_us) != 0 || period_us < KD_PERIOD_US_MIN || period_us > KD_PERIOD_US_MAX) {
                problem("--period-us \"%s\": expected a whole number of us in %d .. %d", optarg, KD_PERIOD_US_MIN,
                        KD_PERIOD_US_MAX);
                return KD_CONFIG_ERROR;
            }
            break;
        case 'P': prefix = optarg; break;
        case 'u': url = optarg; break;
        case OPT_RT: rt = 1; break;
        case OPT_NO_RT: rt = 0; break;
        case OPT_CHECK: check = 1; break;
        case 'h': usage(stdout); return KD_CONFIG_EXIT;
        case ':':
            problem("%s needs a value (see --help)", argv[optind - 1]);
            return KD_CONFIG_ERROR;
        default:
            problem("unknown option \"%s\" (see --help)", argv[optind - 1]);
            return KD_CONFIG_ERROR;
        }
    }
    if (optind < argc) {
        problem("unexpected argument \"%s\" (see --help)", argv[optind]);
        return KD_CONFIG_ERROR;
    }

    if (model != NULL && kc_model_from_name(model) < 0) {
        problem("--model \"%s\": no such built-in model (rrr3, planar2, puma560, panda, rb211, rm01)", model);
        return KD_CONFIG_ERROR;
    }
    if (config_path != NULL) {
        snprintf(cfg->config_path, sizeof cfg->config_path, "%s", config_path);
        if (read_file(config_path, cfg, &fc, &robot_deg, &has_robot) != 0)
            return KD_CONFIG_ERROR;
    }
    if (model != NULL || !has_robot) {
        memset(cfg->volume_names, 0, sizeof cfg->volume_names);
        if (builtin_model(cfg, model != NULL ? model : "puma560") != 0) {
            problem("cannot build the built-in model \"%s\"", model != NULL ? model : "puma560");
            return KD_CONFIG_ERROR;
        }
        robot_deg = 0;
    }

    /* Flags over the file. */
    if (prefix != NULL) {
        const char *why = prefix_problem(prefix);
        if (why != NULL) {
            problem("--prefix \"%s\" %s", prefix, why);
            return KD_CONFIG_ERROR;
        }
        snprintf(cfg->prefix, sizeof cfg->prefix, "%s", prefix);
    }
    if (url != NULL) {
        const char *why = url_problem(url);
        if (why != NULL) {
            problem("--lcm-url \"%s\" %s", url, why);
            return KD_CONFIG_ERROR;
        }
        snprintf(cfg->lcm_url, sizeof cfg->lcm_url, "%s", url);
        cfg->lcm_url_source = "command line";
    } else if (fc.has_url) {
        snprintf(cfg->lcm_url, sizeof cfg->lcm_url, "%s", fc.url);
        cfg->lcm_url_source = "config";
    } else if ((env = getenv("LCM_DEFAULT_URL")) != NULL && env[0] != '\0') {
        const char *why = url_problem(env);
        if (why != NULL) {
            problem("LCM_DEFAULT_URL \"%s\" %s", env, why);
            return KD_CONFIG_ERROR;
        }
        snprintf(cfg->lcm_url, sizeof cfg->lcm_url, "%s", env);
        cfg->lcm_url_source = "LCM_DEFAULT_URL";
    } else {
        snprintf(cfg->lcm_url, sizeof cfg->lcm_url, "%s", KD_DEFAULT_URL);
        cfg->lcm_url_source = "default";
    }
    if (period_us > 0)
        cfg->period_ns = (int64_t)period_us * 1000;
    else if (fc.has_period)
        cfg->period_ns = (int64_t)llround(fc.period_us * 1000.0);
    if (rt >= 0)
        cfg->rt_enable = rt;

    /* The robot: scaled limits and the start joints. */
    scale_limits(&cfg->chain, cfg->vel_scale, cfg->acc_scale);
    if (fc.has_home) {
        /* home needs the robot, known only now. */
        int n = fc.home_n, line = fc.home_line;
        int deg = fc.home_deg_set ? fc.home_deg : robot_deg;
        int bad_joint = -1;
        kc_status st;
        if (n != cfg->chain.n_joints) {
            fprintf(stderr, "%s:%d: controller.home has %d values, the arm \"%s\" has %d joints\n", config_path, line,
                    n, cfg->robot_name, cfg->chain.n_joints);
            return KD_CONFIG_ERROR;
        }
        for (j = 0; j < n; j++) {
            double x = fc.home[j];
            if (deg && cfg->chain.joints[j].type == KC_JOINT_REVOLUTE)
                x *= (double)KC_DEG;
            cfg->home[j] = (kc_real)x;
        }
        st = kc_chain_check_q(&cfg->chain, cfg->home, &bad_joint);
        if (st != KC_OK) {
            fprintf(stderr, "%s:%d: controller.home[%d] is outside joint %d's limits [%.6g, %.6g]\n", config_path,
                    line, bad_joint, bad_joint + 1, (double)cfg->chain.joints[bad_joint].limits.q_min,
                    (double)cfg->chain.joints[bad_joint].limits.q_max);
            return KD_CONFIG_ERROR;
        }
    } else {
        default_home(&cfg->chain, cfg->home);
    }

    if (can_check(config_path, cfg) != 0)
        return KD_CONFIG_ERROR;

    /* The controller's configuration, checked by the core itself. */
    cfg->ctrl.dt = (kc_real)((double)cfg->period_ns * 1e-9);
    cfg->ctrl.servo_timeout_ticks = (int64_t)ceil(cfg->servo_timeout_s / ((double)cfg->period_ns * 1e-9));
    if (cfg->ctrl.servo_timeout_ticks < 1)
        cfg->ctrl.servo_timeout_ticks = 1;
    if (cfg->zones.n_zones > 0) {
        /* Goals are checked tick by tick: no volume may travel the margin
         * in one cycle (kinctl/zone.h). */
        kc_real travel = kc_zone_tick_travel(&cfg->chain, cfg->ctrl.dt);
        cfg->ctrl.zones = &cfg->zones;
        if (cfg->chain.n_volumes == 0)
            fprintf(stderr, "%s: warning: controller.zones is set but robot \"%s\" has no link volumes\n",
                    config_path, cfg->robot_name);
        else if (!(cfg->zones.margin > travel)) {
            fprintf(stderr, "%s: controller.zones.margin = %g m is not above %g m, the farthest a link volume moves in "
                            "one cycle at the joints' velocity limits (raise the margin, shorten period_us or lower "
                            "vel_scale)\n", config_path, (double)cfg->zones.margin, (double)travel);
            return KD_CONFIG_ERROR;
        }
    }
    if (kc_ctrl_cfg_check(&cfg->ctrl, &cfg->chain) != KC_OK) {
        problem("%s: the controller refuses this configuration with robot \"%s\" (%s; check the limits, period and "
                "cartesian settings)",
                config_path != NULL ? config_path : "built-in", cfg->robot_name, kc_status_str(KC_E_ARG));
        return KD_CONFIG_ERROR;
    }
    if (check) {
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
             "rt %s, plant lag %g s, CAN %s, ",
             cfg->robot_name, cfg->chain.n_joints, cfg->config_path[0] ? ", from the config file" : ", built-in",
             (long long)(cfg->period_ns / 1000), cfg->prefix, cfg->lcm_url, cfg->lcm_url_source, cfg->queue_size,
             cfg->overrun_missed > 0 ? (cfg->overrun_action == KC_CMD_ESTOP ? "estop" : "stop") : "off",
             cfg->rt_enable ? "on" : "off", cfg->plant_lag_s, cfg->can.enable ? cfg->can.interface : "off");
    size_t used = strlen(buf);
    if (cfg->zones.n_zones == 0)
        snprintf(buf + used, (size_t)size - used, "zones off");
    else
        snprintf(buf + used, (size_t)size - used, "%d zones (margin %g m) against %d link volumes", cfg->zones.n_zones,
                 (double)cfg->zones.margin, cfg->chain.n_volumes);
}
