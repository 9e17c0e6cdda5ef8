/* SPDX-License-Identifier: BSD-3-Clause */
/* interp.c - `kinctl-calc interp KIND`: sampled motions of kinctl/interp.h
 * (joint move, straight line, arc), one row per tick, as CSV on the command
 * line or JSON rows in batch. How KIND dispatches, and how the path kind of
 * interp_path.c plugs in, is described in calc.h. */
#include <stdio.h>
#include <string.h>

#include "calc.h"
#include "kinctl/desc.h"

#define RATE_TEXT(x) #x
#define RATE_STR(x) RATE_TEXT(x)
/* The limits' range as the help says it. */
#define RATE_RANGE RATE_STR(KC_DESC_RATE_MIN) " .. " RATE_STR(KC_DESC_RATE_MAX)

#define EXIT_BAD_INPUT 2
#define EXIT_FAILURE_IO 1

/* More rows than this is a mistake (a tiny dt), not a request. */
#define MAX_ROWS 1000000

#ifdef KC_REAL_FLOAT
#define REAL_FMT "%.9g"
#else
#define REAL_FMT "%.17g"
#endif

#define INF ((kc_real)INFINITY)

/* ---- rows ---- */

void calc_rows_begin(calc_ctx *ctx, int ncol, const char *const *names)
{
    if (ctx->csv) {
        for (int i = 0; i < ncol; i++)
            printf("%s%s", i > 0 ? "," : "", names[i]);
        printf("\n");
        return;
    }
    jw_key(ctx->out, "columns");
    jw_arr_begin(ctx->out);
    for (int i = 0; i < ncol; i++)
        jw_str(ctx->out, names[i]);
    jw_arr_end(ctx->out);
    jw_key(ctx->out, "rows");
    jw_arr_begin(ctx->out);
}

void calc_rows_add(calc_ctx *ctx, int ncol, const kc_real *row)
{
    if (ctx->csv) {
        for (int i = 0; i < ncol; i++) {
            if (i > 0)
                putchar(',');
            printf(REAL_FMT, (double)row[i]);
        }
        putchar('\n');
        return;
    }
    jw_reals(ctx->out, row, ncol);
}

void calc_rows_end(calc_ctx *ctx)
{
    if (!ctx->csv)
        jw_arr_end(ctx->out);
}

/* ---- options ---- */

/* "1,2,3;4,5,6" to [[1,2,3],[4,5,6]]. */
static json_t *conv_points(const char *arg, char *err, size_t errlen)
{
    json_t *list = json_array();
    const char *p = arg;
    for (;;) {
        const char *semi = strchr(p, ';');
        size_t n = semi != NULL ? (size_t)(semi - p) : strlen(p);
        char buf[1024];
        if (n == 0 || n >= sizeof buf) {
            snprintf(err, errlen, n == 0 ? "empty point in \"%s\"" : "point too long in \"%.40s...\"", arg);
            json_decref(list);
            return NULL;
        }
        memcpy(buf, p, n);
        buf[n] = '\0';
        json_t *point = calc_conv_reals(buf, err, errlen);
        if (point == NULL) {
            json_decref(list);
            return NULL;
        }
        json_array_append_new(list, point);
        if (semi == NULL)
            break;
        p = semi + 1;
    }
    return list;
}

#define DT_OPT {"--dt", "dt", CALC_VALUE, calc_conv_real, "DT", "tick period (s), > 0; rows at t = k DT"}
#define CART_LIMIT_OPTS                                                                                          \
    {"--v", "v", CALC_VALUE, calc_conv_real, "V", "speed limit of the tool point along the path (m/s)"},        \
    {"--a", "a", CALC_VALUE, calc_conv_real, "A", "acceleration limit along the path (m/s^2)"},                 \
    {"--omega", "omega", CALC_VALUE, calc_conv_real, "W",                                                        \
     "angular speed limit of the tool (rad/s); default: none (the two-rotations method's own timing)"},          \
    {"--epsilon", "epsilon", CALC_VALUE, calc_conv_real, "E",                                                    \
     "angular acceleration limit of the tool (rad/s^2); default: none; needed by a pure rotation"},              \
    {"--jmax", "jmax", CALC_VALUE, calc_conv_real, "J",                                                          \
     "jerk limit along the path (m/s^3; jerk profile only); default: 10/s times --a"},                          \
    {"--angular-jmax", "angular_jmax", CALC_VALUE, calc_conv_real, "J",                                          \
     "angular jerk limit of the tool (rad/s^3; jerk profile only); default: 10/s times --epsilon, if given"},   \
    {"--profile", "profile", CALC_VALUE, calc_conv_string, "jerk|trapezoid",                                     \
     "speed law: jerk-limited (default, as the controller's) or the seed's trapezoid"}

static const calc_opt joint_opts[] = {
    CALC_CHAIN_OPTS,
    {"--q0", "q0", CALC_VALUE, calc_conv_reals, "Q1,Q2,...", "start, rad or m (deg with --deg)"},
    {"--q1", "q1", CALC_VALUE, calc_conv_reals, "Q1,Q2,...", "end, rad or m (deg with --deg)"},
    {"--qd0", "qd0", CALC_VALUE, calc_conv_reals, "V1,V2,...",
     "start velocity (jerk-limited only; rad/s or m/s, deg/s with --deg); default: at rest"},
    {"--qdd0", "qdd0", CALC_VALUE, calc_conv_reals, "A1,A2,...",
     "start acceleration (jerk-limited only; rad/s^2 or m/s^2, deg/s^2 with --deg); default: 0"},
    {"--vmax", "vmax", CALC_VALUE, calc_conv_reals, "V|V1,V2,..",
     "speed limit, one for every joint or one per joint (rad/s or m/s; deg/s with --deg); default: the model's"},
    {"--amax", "amax", CALC_VALUE, calc_conv_reals, "A|A1,A2,..",
     "acceleration limit, one or one per joint (rad/s^2 or m/s^2; deg/s^2 with --deg); default: the model's"},
    {"--jmax", "jmax", CALC_VALUE, calc_conv_reals, "J|J1,J2,..",
     "jerk limit, one or one per joint (rad/s^3 or m/s^3; deg/s^3 with --deg); default: the model's"},
    {"--profile", "profile", CALC_VALUE, calc_conv_string, "jerk|trapezoid",
     "motion law: jerk-limited (default, as the controller's) or seed 001 lab 4's trapezoid with a leading joint"},
    {"--duration", "duration", CALC_VALUE, calc_conv_real, "T",
     "stretch the move to last T s (synchronisation); default: as fast as the limits allow"},
    DT_OPT,
    {"--deg", "deg", CALC_FLAG, NULL, NULL, "revolute values (q0, q1, limits and the rows) in degrees"},
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

static const calc_opt line_opts[] = {
    {"--from", "from", CALC_VALUE, calc_conv_reals, "X,Y,Z,QW,QX,QY,QZ", "start pose (m; or 16 numbers, a 4x4)"},
    {"--to", "to", CALC_VALUE, calc_conv_reals, "X,Y,Z,QW,QX,QY,QZ", "end pose (m; or 16 numbers, a 4x4)"},
    CART_LIMIT_OPTS,
    {"--orientation", "orientation", CALC_VALUE, calc_conv_string, "METHOD",
     "two-rotations (default) or slerp"},
    DT_OPT,
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

static const calc_opt arc_opts[] = {
    {"--from", "from", CALC_VALUE, calc_conv_reals, "X,Y,Z,QW,QX,QY,QZ", "start pose (m; or 16 numbers, a 4x4)"},
    {"--via", "via", CALC_VALUE, calc_conv_reals, "X,Y,Z", "a point the arc passes through (m)"},
    {"--to", "to", CALC_VALUE, calc_conv_reals, "X,Y,Z", "end point (m); the orientation follows the arc"},
    CART_LIMIT_OPTS,
    DT_OPT,
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

const calc_opt interp_path_opts[] = {
    {"--space", "space", CALC_VALUE, calc_conv_string, "joint|cartesian", "space of the knots"},
    {"--method", "method", CALC_VALUE, calc_conv_string, "METHOD", "blend, lagrange, spline or quintic"},
    {"--points", "points", CALC_VALUE, conv_points, "P;P;...", "knots; a point is comma-separated numbers"},
    {"--times", "times", CALC_VALUE, calc_conv_reals, "T0,T1,...", "knot times (s); default: from the limits"},
    {"--velocities", "velocities", CALC_VALUE, conv_points, "V;V;...", "knot velocities; default: computed"},
    {"--tacc", "tacc", CALC_VALUE, calc_conv_real, "T", "blend time (s)"},
    {"--v", "v", CALC_VALUE, calc_conv_reals, "V", "speed limit(s)"},
    {"--a", "a", CALC_VALUE, calc_conv_reals, "A", "acceleration limit(s)"},
    {"--blend", "blend", CALC_VALUE, calc_conv_string, "quartic|parabolic", "blend shape (default quartic, C2)"},
    {"--ends", "ends", CALC_VALUE, calc_conv_string, "clamped|natural", "ends of a computed spline (default clamped)"},
    {"--accelerations", "accelerations", CALC_VALUE, conv_points, "A;A;...", "quintic knot accelerations"},
    {"--omega", "omega", CALC_VALUE, calc_conv_real, "W", "cartesian: angular speed limit (rad/s)"},
    {"--epsilon", "epsilon", CALC_VALUE, calc_conv_real, "E", "cartesian: angular acceleration limit (rad/s^2)"},
    DT_OPT,
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

/* Every key of every kind, for batch's key check and help. */
const calc_opt interp_opts[] = {
    {"--kind", "kind", CALC_VALUE, calc_conv_string, "KIND", "joint, line, arc or path"},
    CALC_CHAIN_OPTS,
    {"--q0", "q0", CALC_VALUE, NULL, NULL, NULL},
    {"--q1", "q1", CALC_VALUE, NULL, NULL, NULL},
    {"--qd0", "qd0", CALC_VALUE, NULL, NULL, NULL},
    {"--qdd0", "qdd0", CALC_VALUE, NULL, NULL, NULL},
    {"--vmax", "vmax", CALC_VALUE, NULL, NULL, NULL},
    {"--amax", "amax", CALC_VALUE, NULL, NULL, NULL},
    {"--jmax", "jmax", CALC_VALUE, NULL, NULL, NULL},
    {"--profile", "profile", CALC_VALUE, NULL, NULL, NULL},
    {"--duration", "duration", CALC_VALUE, NULL, NULL, NULL},
    {"--deg", "deg", CALC_FLAG, NULL, NULL, NULL},
    {"--from", "from", CALC_VALUE, NULL, NULL, NULL},
    {"--via", "via", CALC_VALUE, NULL, NULL, NULL},
    {"--to", "to", CALC_VALUE, NULL, NULL, NULL},
    {"--v", "v", CALC_VALUE, NULL, NULL, NULL},
    {"--a", "a", CALC_VALUE, NULL, NULL, NULL},
    {"--omega", "omega", CALC_VALUE, NULL, NULL, NULL},
    {"--epsilon", "epsilon", CALC_VALUE, NULL, NULL, NULL},
    {"--angular-jmax", "angular_jmax", CALC_VALUE, NULL, NULL, NULL},
    {"--orientation", "orientation", CALC_VALUE, NULL, NULL, NULL},
    {"--space", "space", CALC_VALUE, NULL, NULL, NULL},
    {"--method", "method", CALC_VALUE, NULL, NULL, NULL},
    {"--points", "points", CALC_VALUE, NULL, NULL, NULL},
    {"--times", "times", CALC_VALUE, NULL, NULL, NULL},
    {"--velocities", "velocities", CALC_VALUE, NULL, NULL, NULL},
    {"--tacc", "tacc", CALC_VALUE, NULL, NULL, NULL},
    {"--blend", "blend", CALC_VALUE, NULL, NULL, NULL},
    {"--ends", "ends", CALC_VALUE, NULL, NULL, NULL},
    {"--accelerations", "accelerations", CALC_VALUE, NULL, NULL, NULL},
    DT_OPT,
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

/* ---- request getters ---- */

static int dt_of(calc_ctx *ctx, const json_t *req, kc_real *dt) { return req_positive(ctx, req, "dt", 1, "s", dt); }

/* A pose from 7 numbers x,y,z,qw,qx,qy,qz (the quaternion normalised) or 16
 * (row-major 4x4); *q gets the quaternion as given (normalised), so that
 * the rows can keep its sign. */
static int pose_of(calc_ctx *ctx, const json_t *req, const char *key, kc_pose *pose, kc_quat *q)
{
    kc_real v[16];
    int n = 0;
    if (req_reals(ctx, json_object_get(req, key), key, v, 16, &n) != 0)
        return -1;
    if (n == 7) {
        kc_quat raw = {v[3], v[4], v[5], v[6]};
        kc_real norm = kc_quat_norm(&raw);
        if (kc_quat_normalize(&raw, q) != KC_OK)
            return calc_fail(ctx, "%s: the quaternion qw,qx,qy,qz is zero", key);
        if (kc_fabs(norm - KC_R(1.0)) > KC_R(1e-3))
            calc_warn(ctx, "%s: quaternion of norm %g normalised", key, (double)norm);
        kc_quat_to_mat3(q, &pose->R);
        pose->t = kc_vec3_make(v[0], v[1], v[2]);
        return 0;
    }
    if (n == 16) {
        kc_mat4 m;
        for (int i = 0; i < 16; i++)
            m.m[i / 4][i % 4] = v[i];
        if (kc_pose_from_mat4(&m, pose) != KC_OK)
            return calc_fail(ctx, "%s is not a rigid transform: its 3x3 block must be a rotation (orthonormal, "
                                  "det +1) and its last row 0 0 0 1", key);
        kc_quat_from_mat3(&pose->R, q);
        return 0;
    }
    return calc_fail(ctx, "%s has %d numbers: give x,y,z,qw,qx,qy,qz (7) or a row-major 4x4 (16)", key, n);
}

static int point_of(calc_ctx *ctx, const json_t *req, const char *key, kc_vec3 *p)
{
    int n = 0;
    if (req_reals(ctx, json_object_get(req, key), key, p->v, 3, &n) != 0)
        return -1;
    if (n != 3)
        return calc_fail(ctx, "%s has %d numbers: give x,y,z", key, n);
    return 0;
}

/* --profile: jerk (default, as the controller's) or trapezoid. */
static int profile_of(calc_ctx *ctx, const json_t *req, kc_profile_kind *kind)
{
    const json_t *v = json_object_get(req, "profile");
    *kind = KC_PROFILE_JERK;
    if (v == NULL)
        return 0;
    const char *s = json_string_value(v);
    if (s != NULL && strcmp(s, "trapezoid") == 0) {
        *kind = KC_PROFILE_TRAPEZOID;
        return 0;
    }
    if (s != NULL && strcmp(s, "jerk") == 0)
        return 0;
    return calc_fail(ctx, "profile must be trapezoid or jerk, not %s", s != NULL ? s : "a non-string");
}

/* The Cartesian limits; with the jerk-limited profile (the default) the
 * jerk limits too: given, or KC_INTERP_JERK_PER_ACCEL times the
 * acceleration limits (the angular one only when --epsilon is given). */
static int cart_limits_of(calc_ctx *ctx, const json_t *req, kc_interp_limits *lim)
{
    kc_profile_kind kind;
    *lim = kc_interp_limits_default();
    if (req_rate(ctx, req, "v", 1, "m/s", &lim->v) != 0 || req_rate(ctx, req, "a", 1, "m/s^2", &lim->a) != 0 ||
        req_rate(ctx, req, "omega", 0, "rad/s", &lim->w) != 0 ||
        req_rate(ctx, req, "epsilon", 0, "rad/s^2", &lim->dw) != 0 || profile_of(ctx, req, &kind) != 0)
        return -1;
    if (kind == KC_PROFILE_TRAPEZOID) {
        if (json_object_get(req, "jmax") != NULL || json_object_get(req, "angular_jmax") != NULL)
            return calc_fail(ctx, "jmax and angular_jmax do not apply to --profile trapezoid (its jerk is not limited)");
        return 0;
    }
    lim->j = KC_INTERP_JERK_PER_ACCEL * lim->a;
    lim->dj = KC_INTERP_JERK_PER_ACCEL * lim->dw;
    if (req_rate(ctx, req, "jmax", 0, "m/s^3", &lim->j) != 0 ||
        req_rate(ctx, req, "angular_jmax", 0, "rad/s^3", &lim->dj) != 0)
        return -1;
    return 0;
}

/* Joint limits under key: absent = the model's; one value = every joint;
 * or one per joint. Revolute ones in deg/s (deg/s^2, deg/s^3) with deg.
 * order: 0 speed, 1 acceleration, 2 jerk; the last two must be finite. */
static int joint_limits_of(calc_ctx *ctx, const json_t *req, const char *key, const kc_chain *chain, int deg,
                           int order, kc_real *out)
{
    int n = chain->n_joints, count = 0;
    kc_real v[KC_MAX_JOINTS];
    const json_t *val = json_object_get(req, key);
    for (int j = 0; j < n; j++) {
        const kc_joint_limits *l = &chain->joints[j].limits;
        out[j] = order == 2 ? l->qddd_max : order == 1 ? l->qdd_max : l->qd_max;
    }
    if (val == NULL) {
        for (int j = 0; j < n; j++)
            if (order > 0 && !(kc_isfinite(out[j]) && out[j] > KC_R(0.0)))
                return calc_fail(ctx, "the model gives joint %d no %s limit: give --%s", j + 1,
                                 order == 2 ? "jerk" : "acceleration", key);
        return 0;
    }
    if (req_reals(ctx, val, key, v, KC_MAX_JOINTS, &count) != 0)
        return -1;
    if (count != 1 && count != n)
        return calc_fail(ctx, "%s has %d values: give one for every joint or one per joint (%d)", key, count, n);
    for (int j = 0; j < n; j++) {
        kc_real x = v[count == 1 ? 0 : j];
        int angular = chain->joints[j].type == KC_JOINT_REVOLUTE;
        if (!(x > KC_R(0.0)))
            return calc_fail(ctx, "%s must be > 0 for every joint, not %g (joint %d)", key, (double)x, j + 1);
        if (deg && angular)
            x *= KC_DEG;
        if (rate_in_range(ctx, key, x) != 0)
            return -1;
        if (x > out[j] * (KC_R(1.0) + KC_R(1e-6))) {
            kc_real s = joint_shown(chain, j, deg);
            calc_warn(ctx, "%s for joint %d (%g) exceeds the model's limit %g", key, j + 1, (double)(x * s),
                      (double)(out[j] * s));
        }
        out[j] = x;
    }
    return 0;
}

static int too_many_rows(calc_ctx *ctx, kc_real T, int64_t ticks)
{
    if (ticks + 1 > MAX_ROWS)
        return calc_fail(ctx, "the motion lasts %.6g s = %lld ticks: more than %d rows; use a larger --dt",
                         (double)T, (long long)ticks, MAX_ROWS);
    return 0;
}

static int plan_failed(calc_ctx *ctx, const char *what, kc_status st)
{
    if (st == KC_E_CAPACITY)
        return calc_fail(ctx, "%s: the motion would last more than %d ticks (or its size overflows): use a larger --dt "
                              "or shorter moves", what, KC_PROFILE_MAX_TICKS);
    return calc_fail(ctx, "%s: %s", what, kc_status_str(st));
}

/* ---- joint ---- */

/* --qd0, --qdd0: the start's velocity or acceleration, one per joint
 * (deg/s, deg/s^2 with --deg for revolute joints), zero when absent. */
static int start_rates_of(calc_ctx *ctx, const json_t *req, const char *key, const kc_chain *chain, int deg,
                          kc_real *out)
{
    int n = 0;
    const json_t *val = json_object_get(req, key);
    if (val == NULL)
        return 0;
    if (req_reals(ctx, val, key, out, KC_MAX_JOINTS, &n) != 0)
        return -1;
    if (n != chain->n_joints)
        return calc_fail(ctx, "%s has %d values but the model has %d joints", key, n, chain->n_joints);
    for (int j = 0; j < n; j++)
        if (deg && chain->joints[j].type == KC_JOINT_REVOLUTE)
            out[j] *= KC_DEG;
    return 0;
}

/* A joint's range over the rows: its position's lowest and highest,
 * its largest speed and acceleration. */
typedef struct {
    kc_real lo, hi, v, a;
} joint_range;

/* Warnings for what a moving start carries beyond the limits before the
 * profile turns it (rest to rest stays within them): a joint past its
 * position limits further than q0 and q1 are (those are warned about as
 * given), which the controller takes by stopping first (ctrl_queue.c,
 * retarget_jerk); a speed or an acceleration past the move's limits (a
 * start beyond them, or one whose acceleration cannot come down to 0
 * before its speed passes vmax: brought back within, as kinctld does). */
static void range_warnings(calc_ctx *ctx, const kc_chain *chain, int deg, const kc_interp_joint_cfg *cfg,
                           const joint_range *r)
{
    for (int j = 0; j < chain->n_joints; j++) {
        const kc_joint *jt = &chain->joints[j];
        kc_real s = joint_shown(chain, j, deg);
        kc_real slack = KC_R(1e-9) * (kc_fabs(jt->limits.q_min) + kc_fabs(jt->limits.q_max) + KC_R(1.0));
        kc_real top = kc_max(jt->limits.q_max, kc_max(cfg->q0[j], cfg->q1[j])) + slack;
        kc_real bottom = kc_min(jt->limits.q_min, kc_min(cfg->q0[j], cfg->q1[j])) - slack;
        const char *unit = joint_unit(chain, j, deg);
        if (r[j].hi > top || r[j].lo < bottom)
            calc_warn(ctx,
                      "joint %d reaches %.9g %s on the way from this start, beyond its limits [%g, %g] (kinctld, "
                      "given this goal in this state, stops the motion first)",
                      j + 1, (double)((r[j].hi > top ? r[j].hi : r[j].lo) * s), unit, (double)(jt->limits.q_min * s),
                      (double)(jt->limits.q_max * s));
        if (r[j].v > cfg->qd_max[j] * (KC_R(1.0) + KC_R(1e-9)))
            calc_warn(ctx, "joint %d's speed reaches %.9g %s/s from this start, beyond vmax %g: brought back within",
                      j + 1, (double)(r[j].v * s), unit, (double)(cfg->qd_max[j] * s));
        if (r[j].a > cfg->qdd_max[j] * (KC_R(1.0) + KC_R(1e-9)))
            calc_warn(ctx,
                      "joint %d's acceleration reaches %.9g %s/s^2 from this start, beyond amax %g: brought back within",
                      j + 1, (double)(r[j].a * s), unit, (double)(cfg->qdd_max[j] * s));
    }
}

static int run_interp_joint(const json_t *req, calc_ctx *ctx)
{
    kc_chain chain;
    kc_interp_joint_cfg cfg = kc_interp_joint_cfg_default();
    kc_real *q0 = cfg.q0, *q1 = cfg.q1, dt, duration = KC_R(0.0);
    int deg = 0;
    if (req_bool(ctx, req, "deg", &deg) != 0 || req_model(ctx, req, &chain) != 0 ||
        req_joints(ctx, req, "q0", &chain, deg, q0) != 0 || req_joints(ctx, req, "q1", &chain, deg, q1) != 0 ||
        joint_limits_of(ctx, req, "vmax", &chain, deg, 0, cfg.qd_max) != 0 ||
        joint_limits_of(ctx, req, "amax", &chain, deg, 1, cfg.qdd_max) != 0 || profile_of(ctx, req, &cfg.profile) != 0 ||
        dt_of(ctx, req, &dt) != 0)
        return -1;
    int jerk = cfg.profile == KC_PROFILE_JERK;
    if (jerk && joint_limits_of(ctx, req, "jmax", &chain, deg, 2, cfg.qddd_max) != 0)
        return -1;
    if (!jerk && json_object_get(req, "jmax") != NULL)
        return calc_fail(ctx, "jmax does not apply to --profile trapezoid (the trapezoid's jerk is not limited)");
    if (start_rates_of(ctx, req, "qd0", &chain, deg, cfg.qd0) != 0 ||
        start_rates_of(ctx, req, "qdd0", &chain, deg, cfg.qdd0) != 0)
        return -1;
    if (!jerk && (json_object_get(req, "qd0") != NULL || json_object_get(req, "qdd0") != NULL))
        return calc_fail(ctx, "qd0 and qdd0 need the jerk-limited profile (the trapezoid starts at rest)");
    if (json_object_get(req, "duration") != NULL) {
        if (req_real(ctx, req, "duration", &duration) != 0)
            return -1;
        if (duration < KC_R(0.0))
            return calc_fail(ctx, "duration must be >= 0 s, not %g", (double)duration);
    }
    int n = chain.n_joints, n_raw = 0;
    /* q0 and q1 as given, for exact first and last rows (with --deg, q0
     * and q1 are in rad now). */
    kc_real q0_given[KC_MAX_JOINTS], q1_given[KC_MAX_JOINTS];
    req_reals(ctx, json_object_get(req, "q0"), "q0", q0_given, KC_MAX_JOINTS, &n_raw);
    req_reals(ctx, json_object_get(req, "q1"), "q1", q1_given, KC_MAX_JOINTS, &n_raw);
    kc_interp_joint plan;
    cfg.n = n;
    cfg.dt = dt;
    cfg.duration = duration;
    kc_status st = kc_interp_joint_plan_cfg(&plan, &cfg);
    if (st == KC_E_LIMIT) {
        cfg.duration = KC_R(0.0);
        kc_interp_joint_plan_cfg(&plan, &cfg);
        return calc_fail(ctx, "duration %g s is shorter than the limits allow (%.9g s)", (double)duration,
                         (double)plan.T);
    }
    if (st != KC_OK)
        return plan_failed(ctx, "joint move", st);
    if (too_many_rows(ctx, plan.T, plan.ticks) != 0)
        return -1;
    if (!ctx->csv) {
        /* Batch only: the leading joint (1-based, 0 when nothing moves) and the move's duration (s). */
        char lead[16];
        snprintf(lead, sizeof lead, "%d", plan.lead + 1);
        jw_key(ctx->out, "lead");
        jw_raw(ctx->out, lead);
        jw_key(ctx->out, "duration");
        jw_real(ctx->out, plan.T);
    }
    /* Columns t, q1..qn, qd1..qdn, qdd1..qddn, and with the jerk-limited
     * profile qddd1..qdddn. */
    static const char *const stems[4] = {"q", "qd", "qdd", "qddd"};
    char name_buf[1 + 4 * KC_MAX_JOINTS][8];
    const char *names[1 + 4 * KC_MAX_JOINTS];
    kc_real scale[KC_MAX_JOINTS], row[1 + 4 * KC_MAX_JOINTS];
    int nd = jerk ? 4 : 3;
    names[0] = "t";
    for (int d = 0; d < nd; d++)
        for (int j = 0; j < n; j++) {
            snprintf(name_buf[1 + d * n + j], sizeof name_buf[0], "%s%d", stems[d], j + 1);
            names[1 + d * n + j] = name_buf[1 + d * n + j];
        }
    for (int j = 0; j < n; j++)
        scale[j] = joint_shown(&chain, j, deg);
    int ncol = 1 + nd * n;
    /* Each joint's range over the rows: a moving start may carry it
     * beyond the limits before it turns. */
    joint_range range[KC_MAX_JOINTS];
    for (int j = 0; j < n; j++)
        range[j] = (joint_range){q0[j], q0[j], KC_R(0.0), KC_R(0.0)};
    calc_rows_begin(ctx, ncol, names);
    for (int64_t k = 0; k <= plan.ticks; k++) {
        kc_interp_joint_state s;
        kc_interp_joint_eval(&plan, k, &s);
        row[0] = (kc_real)k * dt;
        for (int j = 0; j < n; j++) {
            joint_range *r = &range[j];
            r->lo = kc_min(r->lo, s.q[j]);
            r->hi = kc_max(r->hi, s.q[j]);
            r->v = kc_max(r->v, kc_fabs(s.qd[j]));
            r->a = kc_max(r->a, kc_fabs(s.qdd[j]));
            /* The last row is q1 as given, not converted there and back. */
            row[1 + j] = k == plan.ticks ? q1_given[j] : k == 0 ? q0_given[j] : s.q[j] * scale[j];
            row[1 + n + j] = s.qd[j] * scale[j];
            row[1 + 2 * n + j] = s.qdd[j] * scale[j];
            if (jerk)
                row[1 + 3 * n + j] = s.qddd[j] * scale[j];
        }
        calc_rows_add(ctx, ncol, row);
    }
    calc_rows_end(ctx);
    range_warnings(ctx, &chain, deg, &cfg, range);
    return 0;
}

/* ---- line and arc ---- */

static const char *const cart_names[11] = {"t", "x", "y", "z", "qw", "qx", "qy", "qz", "s", "sd", "sdd"};

/* Rows of a planned Cartesian segment of `ticks` ticks lasting T; quaternions signed like the start the user gave (user_q), the sign
 * kinctl keeps continuous along the segment. */
static int cart_rows(calc_ctx *ctx, const void *plan, kc_status (*eval)(const void *, int64_t, kc_interp_cart_state *),
                     kc_real T, int64_t ticks, kc_real dt, const kc_quat *plan_q1, const kc_quat *user_q)
{
    if (too_many_rows(ctx, T, ticks) != 0)
        return -1;
    kc_real sign = plan_q1->w * user_q->w + plan_q1->x * user_q->x + plan_q1->y * user_q->y + plan_q1->z * user_q->z <
                           KC_R(0.0)
                       ? KC_R(-1.0)
                       : KC_R(1.0);
    calc_rows_begin(ctx, 11, cart_names);
    for (int64_t k = 0; k <= ticks; k++) {
        kc_interp_cart_state s;
        eval(plan, k, &s);
        kc_real row[11] = {(kc_real)k * dt,
                           s.p.v[0],
                           s.p.v[1],
                           s.p.v[2],
                           sign * s.q.w,
                           sign * s.q.x,
                           sign * s.q.y,
                           sign * s.q.z,
                           s.s,
                           s.sd,
                           s.sdd};
        calc_rows_add(ctx, 11, row);
    }
    calc_rows_end(ctx);
    return 0;
}

static kc_status line_eval(const void *p, int64_t k, kc_interp_cart_state *out)
{
    return kc_interp_line_eval(p, k, out);
}

static kc_status arc_eval(const void *p, int64_t k, kc_interp_cart_state *out)
{
    return kc_interp_arc_eval(p, k, out);
}

static int run_interp_line(const json_t *req, calc_ctx *ctx)
{
    kc_pose from, to;
    kc_quat qf, qt;
    kc_interp_limits lim;
    kc_real dt;
    const char *method = "two-rotations";
    kc_interp_orient orient;
    if (pose_of(ctx, req, "from", &from, &qf) != 0 || pose_of(ctx, req, "to", &to, &qt) != 0 ||
        cart_limits_of(ctx, req, &lim) != 0 || req_string(ctx, req, "orientation", 0, &method) != 0 ||
        dt_of(ctx, req, &dt) != 0)
        return -1;
    if (strcmp(method, "two-rotations") == 0)
        orient = KC_INTERP_TWO_ROTATIONS;
    else if (strcmp(method, "slerp") == 0)
        orient = KC_INTERP_SLERP;
    else
        return calc_fail(ctx, "unknown orientation method \"%s\": two-rotations or slerp", method);
    kc_interp_line plan;
    kc_status st = kc_interp_line_plan(&plan, &from, &to, &lim, orient, dt);
    if (st == KC_E_ARG && from.t.v[0] == to.t.v[0] && from.t.v[1] == to.t.v[1] && from.t.v[2] == to.t.v[2] &&
        !kc_isfinite(lim.dw))
        return calc_fail(ctx, "a pure rotation (from and to at the same position) runs its speed law on the angle: "
                              "give --omega and --epsilon");
    if (st != KC_OK)
        return plan_failed(ctx, "line", st);
    return cart_rows(ctx, &plan, line_eval, plan.T, plan.ticks, dt, &plan.q1, &qf);
}

static int run_interp_arc(const json_t *req, calc_ctx *ctx)
{
    kc_pose from;
    kc_quat qf;
    kc_vec3 via, to;
    kc_interp_limits lim;
    kc_real dt;
    if (pose_of(ctx, req, "from", &from, &qf) != 0 || point_of(ctx, req, "via", &via) != 0 ||
        point_of(ctx, req, "to", &to) != 0 || cart_limits_of(ctx, req, &lim) != 0 || dt_of(ctx, req, &dt) != 0)
        return -1;
    kc_interp_arc plan;
    kc_status st = kc_interp_arc_plan(&plan, &from, &via, &to, &lim, dt);
    if (st == KC_E_SINGULAR)
        return calc_fail(ctx, "the start, via and end points are collinear or two of them coincide: no unique "
                              "circle passes through them");
    if (st != KC_OK)
        return plan_failed(ctx, "arc", st);
    return cart_rows(ctx, &plan, arc_eval, plan.T, plan.ticks, dt, &plan.q1, &qf);
}

/* ---- path (interp_path.c) ---- */

#ifdef KINCTL_CALC_HAVE_INTERP_PATH
#define PATH_RUN run_interp_path
#else
static int path_unavailable(const json_t *req, calc_ctx *ctx)
{
    (void)req;
    return calc_fail(ctx, "interp path is not yet available in this build (multi-point paths come with "
                          "tools/calc/interp_path.c)");
}
#define PATH_RUN path_unavailable
#endif

/* ---- the kinds ---- */

static const calc_cmd kinds[] = {
    {"joint", "joint move: all joints start and end together",
     "kinctl-calc interp joint (--model NAME | --model-file PATH) --q0 Q1,Q2,... --q1 Q1,Q2,...\n"
     "       [--qd0 V1,..] [--qdd0 A1,..] [--vmax V] [--amax A] [--jmax J] [--profile jerk|trapezoid]\n"
     "       [--duration T] [--deg] --dt DT\n"
     "Jerk (default, as kinctld's): each joint's jerk-limited move within its speed, acceleration and\n"
     "jerk limits, all starting and ending on the same tick, in the slowest joint's optimal time (a\n"
     "straight line when that is as fast, else each joint stretched). From a moving start (--qd0,\n"
     "--qdd0: as kinctld takes over a moving arm for a replacing joint goal) each joint's profile\n"
     "from its state, stretched to the slowest one's; a joint it carries beyond its position limits\n"
     "before turning (kinctld would stop such a motion first), or past vmax or amax, is warned about.\n"
     "Trapezoid (seed 001 lab 4): every joint covers the same fraction of its move at every tick; the\n"
     "common trapezoid (triangle when short) keeps each joint within its own speed and acceleration limits.\n"
     "Limits given, and a model file's, lie within " RATE_RANGE " (rad or m per s, s^2, s^3).\n"
     "Prints CSV: t,q1..qn,qd1..qdn,qdd1..qddn (jerk: also qddd1..qdddn), one row per tick from t = 0\n"
     "to the end inclusive.\n"
     "Example: kinctl-calc interp joint --model planar2 --deg --q0 10,20 --q1 30,50 --jmax 3000 --dt 0.01\n"
     "Example: kinctl-calc interp joint --model planar2 --deg --q0 10,20 --q1 30,50 --profile trapezoid --vmax 50 "
     "--amax 600 --dt 0.01",
     joint_opts, run_interp_joint},
    {"line", "Cartesian straight line",
     "kinctl-calc interp line --from X,Y,Z,QW,QX,QY,QZ --to X,Y,Z,QW,QX,QY,QZ --v V --a A\n"
     "       [--omega W --epsilon E] [--jmax J] [--angular-jmax J] [--profile jerk|trapezoid]\n"
     "       [--orientation two-rotations|slerp] --dt DT\n"
     "The tool point moves on the straight line with a jerk-limited speed law (v, a, jmax; default, as\n"
     "kinctld's; jmax defaults to 10/s times a) or the seed's trapezoid (v, a) along the path;\n"
     "the orientation turns by the two-rotations method (about a fixed axis, then about the tool's z)\n"
     "or by slerp, within --omega and --epsilon if given. A pure rotation needs them: its speed law\n"
     "runs on the angle, and s is then the angle turned (rad).\n"
     "Prints CSV: t,x,y,z,qw,qx,qy,qz,s,sd,sdd (s: path length so far), one row per tick.\n"
     "Example: kinctl-calc interp line --from 0.4,0,0.5,1,0,0,0 --to 0.4,0.3,0.4,0.7071068,0,0,0.7071068 "
     "--v 0.5 --a 2 --dt 0.001",
     line_opts, run_interp_line},
    {"arc", "circular arc through three points",
     "kinctl-calc interp arc --from X,Y,Z,QW,QX,QY,QZ --via X,Y,Z --to X,Y,Z --v V --a A\n"
     "       [--omega W --epsilon E] [--jmax J] [--angular-jmax J] [--profile jerk|trapezoid] --dt DT\n"
     "The arc of the circle through the three points that passes through --via (more than half a\n"
     "circle if need be); the tool's orientation turns with the arc (6.1); speed law on the angle\n"
     "with omega = v/R, epsilon = a/R (jerk-limited by default with jmax/R, as for a line).\n"
     "Prints CSV: t,x,y,z,qw,qx,qy,qz,s,sd,sdd (s: arc length so far), one row per tick.\n"
     "Example: kinctl-calc interp arc --from 0.5,0,0.3,1,0,0,0 --via 0.4,0.1,0.3 --to 0.3,0,0.3 "
     "--v 0.2 --a 1 --dt 0.001",
     arc_opts, run_interp_arc},
    {"path", "multi-point path: blends, splines, quintics or Lagrange",
     "kinctl-calc interp path --space joint|cartesian --method blend|lagrange|spline|quintic\n"
     "       --points \"P;P;...\" [--times T0,T1,...] [--velocities \"V;V;...\"] [--tacc T]\n"
     "       [--v V --a A] [--omega W --epsilon E] [--blend quartic|parabolic] [--ends clamped|natural]\n"
     "       [--accelerations \"A;A;...\"] --dt DT\n"
     "A point is comma-separated numbers: joint values (rad or m), or x,y,z,qw,qx,qy,qz in cartesian\n"
     "space (quaternions normalised; velocities and accelerations then x,y,z). Methods (kinctl/path.h):\n"
     "  blend     lines with blends of half-length --tacc around each knot: quartic (Paul, C2) or\n"
     "            parabolic (C1); cuts the corners, starts at rest at t0 - tacc, ends at tn + tacc\n"
     "  lagrange  one polynomial through all knots (at most 8: it oscillates)\n"
     "  spline    cubic: Hermite with --velocities, else C2 with clamped (at rest) or natural ends\n"
     "  quintic   C2 at the knots: --velocities and --accelerations, or computed\n"
     "Times: --times (blend: also --tacc), or from --v and --a (one value, or one per joint; cartesian:\n"
     "along the path, plus --omega/--epsilon for the turns): each segment takes the trapezoid time of\n"
     "its largest move. Cartesian orientation goes through the knot orientations on the same times.\n"
     "Prints CSV: t,q1..qn,qd1..qdn,qdd1..qddn (joint) or t,x,y,z,qw,qx,qy,qz,s,sd,sdd (cartesian, s:\n"
     "path length so far), one row per tick from t = 0 (the motion's start) to the end inclusive.\n"
     "Example: kinctl-calc interp path --space joint --method blend --points \"0,0;1,0.5;2,0\" "
     "--times 0,1,2 --tacc 0.2 --dt 0.01",
     interp_path_opts, PATH_RUN},
};

#define N_KINDS (sizeof kinds / sizeof kinds[0])

static const calc_cmd *find_kind(const char *name)
{
    for (size_t i = 0; i < N_KINDS; i++)
        if (strcmp(kinds[i].name, name) == 0)
            return &kinds[i];
    return NULL;
}

/* Batch: op "interp", "kind": KIND and the kind's keys. */
int run_interp(const json_t *req, calc_ctx *ctx)
{
    const char *name = NULL, *key;
    json_t *value;
    if (req_string(ctx, req, "kind", 1, &name) != 0)
        return -1;
    const calc_cmd *kind = find_kind(name);
    if (kind == NULL)
        return calc_fail(ctx, "unknown interp kind \"%s\" (joint, line, arc, path)", name);
    json_object_foreach((json_t *)req, key, value)
    {
        int known = strcmp(key, "op") == 0 || strcmp(key, "id") == 0 || strcmp(key, "kind") == 0;
        for (const calc_opt *o = kind->opts; o->key != NULL && !known; o++)
            known = strcmp(o->key, key) == 0;
        if (!known)
            return calc_fail(ctx, "unknown key \"%s\" for interp %s", key, name);
    }
    return kind->run(req, ctx);
}

static void print_kinds(FILE *f)
{
    fprintf(f, "usage: kinctl-calc interp KIND [OPTIONS]   (kinctl-calc interp KIND --help for details)\n\n"
               "Sampled motions, one CSV row per tick.\n\nkinds:\n");
    for (size_t i = 0; i < N_KINDS; i++)
        fprintf(f, "  %-6s %s\n", kinds[i].name, kinds[i].summary);
    fprintf(f, "\nIn batch: {\"op\": \"interp\", \"kind\": KIND, ...} answers {\"columns\": [...], \"rows\": [[...], ...]}\n"
               "(joint also \"lead\": the leading joint, 1-based, 0 when nothing moves, and \"duration\" in s).\n");
}

static void print_kind_help(const calc_cmd *kind)
{
    printf("usage: %s\n\noptions:\n", kind->usage);
    for (const calc_opt *o = kind->opts; o->key != NULL; o++) {
        char left[64];
        snprintf(left, sizeof left, "%s %s", o->flag, o->metavar != NULL ? o->metavar : "");
        printf("  %-30s %s\n", left, o->help);
    }
    printf("  %-30s %s\n", "--help", "this text");
    printf("\nBatch: {\"op\": \"interp\", \"kind\": \"%s\", ...} with the option names as keys.\n"
           "Bad input: a message on stderr, exit status 2.\n",
           kind->name);
}

int calc_interp_main(int argc, char **argv)
{
    if (argc < 1 || strcmp(argv[0], "--help") == 0 || strcmp(argv[0], "-h") == 0) {
        print_kinds(argc < 1 ? stderr : stdout);
        return argc < 1 ? EXIT_BAD_INPUT : 0;
    }
    const calc_cmd *kind = find_kind(argv[0]);
    if (kind == NULL) {
        fprintf(stderr, "kinctl-calc interp: unknown kind \"%s\" (joint, line, arc, path)\n", argv[0]);
        return EXIT_BAD_INPUT;
    }
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            print_kind_help(kind);
            return 0;
        }
    }
    char err[1024];
    json_t *req = calc_parse_args(kind, argc - 1, argv + 1, err, sizeof err);
    if (req == NULL) {
        fprintf(stderr, "kinctl-calc interp %s: %s (kinctl-calc interp %s --help)\n", kind->name, err, kind->name);
        return EXIT_BAD_INPUT;
    }
    calc_ctx ctx;
    jw unused;
    memset(&ctx, 0, sizeof ctx);
    jw_init(&unused);
    ctx.out = &unused;
    ctx.csv = 1;
    ctx.warnings = json_array();
    int rc = kind->run(req, &ctx);
    for (size_t i = 0; i < json_array_size(ctx.warnings); i++)
        fprintf(stderr, "kinctl-calc: warning: %s\n", json_string_value(json_array_get(ctx.warnings, i)));
    json_decref(ctx.warnings);
    json_decref(req);
    jw_free(&unused);
    if (rc != 0) {
        fprintf(stderr, "kinctl-calc interp %s: %s\n", kind->name, ctx.err);
        return EXIT_BAD_INPUT;
    }
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "kinctl-calc interp %s: writing stdout failed\n", kind->name);
        return EXIT_FAILURE_IO;
    }
    return 0;
}
