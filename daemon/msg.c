/* SPDX-License-Identifier: BSD-3-Clause */
/* msg.c - decode-with-validation and encode for kinctl's LCM types (msg.h).
 *
 * Why a wrapper at all: the generated kinctl_*_decode() checks the
 * fingerprint and bounds its reads by maxlen, but it accepts a datagram with
 * trailing bytes, says only "-1" when anything is wrong, and knows nothing of
 * what the fields mean. Here each datagram must be exactly one message of the
 * expected type, and the reason for a refusal is spelled out, because the
 * daemon counts refusals and tools print them. */
#include "msg.h"

#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* ---- per-type glue around the generated functions ---------------------- */

/* One set of wrappers per type with the generated signatures made uniform;
 * calling through these (rather than casting function pointers) keeps the
 * calls well-defined C. */
#define KD_GLUE(T)                                                              \
    static int glue_decode_##T(const void *buf, int len, void *out)            \
    {                                                                           \
        return kinctl_##T##_decode(buf, 0, len, (kinctl_##T *)out);            \
    }                                                                           \
    static int glue_encode_##T(void *buf, int cap, const void *msg)            \
    {                                                                           \
        return kinctl_##T##_encode(buf, 0, cap, (const kinctl_##T *)msg);      \
    }                                                                           \
    static int glue_size_##T(const void *msg)                                   \
    {                                                                           \
        return kinctl_##T##_encoded_size((const kinctl_##T *)msg);             \
    }                                                                           \
    static int64_t glue_hash_##T(void)                                          \
    {                                                                           \
        return __kinctl_##T##_get_hash();                                       \
    }

KD_GLUE(goal_joint_t)
KD_GLUE(goal_line_t)
KD_GLUE(goal_arc_t)
KD_GLUE(goal_path_t)
KD_GLUE(goal_servo_t)
KD_GLUE(command_t)
KD_GLUE(setpoint_t)
KD_GLUE(status_t)
KD_GLUE(stats_t)

typedef struct kd_msg_glue {
    int (*decode)(const void *buf, int len, void *out);
    int (*encode)(void *buf, int cap, const void *msg);
    int (*size)(const void *msg);
    int64_t (*hash)(void);
    size_t struct_size;
} kd_msg_glue;

#define KD_GLUE_ROW(T) \
    { glue_decode_##T, glue_encode_##T, glue_size_##T, glue_hash_##T, sizeof(kinctl_##T) }

static const kd_msg_glue glue[KD_MSG_TYPE_COUNT] = {
    KD_GLUE_ROW(goal_joint_t), KD_GLUE_ROW(goal_line_t),  KD_GLUE_ROW(goal_arc_t),
    KD_GLUE_ROW(goal_path_t),  KD_GLUE_ROW(goal_servo_t), KD_GLUE_ROW(command_t),
    KD_GLUE_ROW(setpoint_t),   KD_GLUE_ROW(status_t),     KD_GLUE_ROW(stats_t),
};

/* Encoded sizes: the 8-byte fingerprint plus the fields (doubles and int64 8
 * bytes, int32 4, int8 1, string 4 + length + NUL). Written out so that a
 * change to an .lcm file that changes a size fails the tests loudly (they
 * compare each with the generated *_encoded_size()). status_t's is with an
 * empty reason. */
static const kd_msg_info info[KD_MSG_TYPE_COUNT] = {
    {"goal_joint_t", "GOAL_JOINT", 1, 8 + 8 + 8 + 1 + 4 + 16 * 8 + 8 + 8 + 1},
    {"goal_line_t", "GOAL_LINE", 1, 8 + 8 + 8 + 1 + 3 * 8 + 4 * 8 + 6 * 8 + 1 + 2 * 8},
    {"goal_arc_t", "GOAL_ARC", 1, 8 + 8 + 8 + 1 + 3 * 8 + 3 * 8 + 4 * 8 + 6 * 8 + 2 * 8},
    {"goal_path_t", "GOAL_PATH", 1,
     8 + 8 + 8 + 5 * 1 + 2 * 4 + 31 * 16 * 8 + 1 + 31 * 8 + 7 * 8},
    {"goal_servo_t", "GOAL_SERVO", 1, 8 + 8 + 8 + 2 * 1 + 3 * 8 + 4 * 8 + 6 * 8 + 8},
    {"command_t", "COMMAND", 1, 8 + 8 + 1},
    {"setpoint_t", "SETPOINT", 0,
     8 + 8 + 8 + 8 + 1 + 4 + 3 * 16 * 8 + 3 * 8 + 4 * 8 + 8 + 1 + 1 + 1 + 1 + 8 + 1 + 8 + 1 + 8 + 8},
    {"status_t", "STATUS", 0,
     8 + 8 + 8 + 1 + 8 + 8 + 4 + 1 + 8 + 4 + (4 + 1) + 4 + 2 * 16 * 8 + 1 + 4 + 1 + 3 * 8 + 1 + 16 * 1},
    {"stats_t", "STATS", 0, 8 + 18 * 8 + 1 + 5 * 8},
};

void kd_msg_init(void)
{
    int t;
    for (t = 0; t < KD_MSG_TYPE_COUNT; t++)
        (void)glue[t].hash();
}

const kd_msg_info *kd_msg_type_info(kd_msg_type type)
{
    if ((int)type < 0 || (int)type >= KD_MSG_TYPE_COUNT)
        return NULL;
    return &info[type];
}

const char *kd_msg_status_str(kd_msg_status status)
{
    switch (status) {
    case KD_MSG_OK: return "ok";
    case KD_MSG_E_ARG: return "bad argument";
    case KD_MSG_E_TYPE: return "type not decodable";
    case KD_MSG_E_TRUNCATED: return "truncated";
    case KD_MSG_E_OVERSIZED: return "oversized";
    case KD_MSG_E_FINGERPRINT: return "bad fingerprint";
    case KD_MSG_E_DECODE: return "decode failed";
    case KD_MSG_E_COUNT: return "bad count";
    case KD_MSG_E_ENUM: return "unknown enum value";
    case KD_MSG_E_NONFINITE: return "not finite";
    case KD_MSG_E_RANGE: return "out of range";
    case KD_MSG_E_SPACE: return "buffer too small";
    case KD_MSG_E_ENCODE: return "encode failed";
    }
    return "unknown status";
}

int64_t kd_msg_fingerprint(kd_msg_type type)
{
    if ((int)type < 0 || (int)type >= KD_MSG_TYPE_COUNT)
        return 0;
    return glue[type].hash();
}

/* ---- reasons ----------------------------------------------------------- */

/* The reason buffer of one decode: NULL when the caller wants none. */
typedef struct kd_reason {
    char *buf;
    size_t size;
} kd_reason;

#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 3, 4)))
#endif
static kd_msg_status fail(kd_reason *r, kd_msg_status status, const char *fmt, ...)
{
    if (r->buf) {
        va_list ap;
        va_start(ap, fmt);
        (void)vsnprintf(r->buf, r->size, fmt, ap);
        va_end(ap);
    }
    return status;
}

static int64_t read_be64(const unsigned char *p)
{
    uint64_t v = 0;
    int i;
    for (i = 0; i < 8; i++)
        v = (v << 8) | p[i];
    /* Two's complement reinterpretation, as the generated code does. */
    int64_t s;
    memcpy(&s, &v, sizeof s);
    return s;
}

int64_t kd_msg_goal_id(kd_msg_type type, const void *buf, size_t len)
{
    /* Every goal type starts fingerprint (8 bytes), utime (8), goal_id (8). */
    if (type > KD_MSG_GOAL_SERVO || buf == NULL || len < 24)
        return 0;
    return read_be64((const unsigned char *)buf + 16);
}

kd_msg_status kd_msg_identify(const void *buf, size_t len, kd_msg_type *type)
{
    int t;
    int64_t fp;
    if (!buf || !type)
        return KD_MSG_E_ARG;
    if (len < 8)
        return KD_MSG_E_TRUNCATED;
    fp = read_be64((const unsigned char *)buf);
    for (t = 0; t < KD_MSG_TYPE_COUNT; t++) {
        if (glue[t].hash() == fp) {
            *type = (kd_msg_type)t;
            return KD_MSG_OK;
        }
    }
    return KD_MSG_E_FINGERPRINT;
}

/* ---- content checks ---------------------------------------------------- */

/* Each returns KD_MSG_OK or a failure with its reason; `ty` is the type name
 * and `field` the field's name for the reason. */

static kd_msg_status check_enum(kd_reason *r, const char *ty, const char *field, int v, int lo,
                                int hi)
{
    if (v < lo || v > hi)
        return fail(r, KD_MSG_E_ENUM, "%s.%s = %d is not a known value (%d..%d)", ty, field, v,
                    lo, hi);
    return KD_MSG_OK;
}

static kd_msg_status check_count(kd_reason *r, const char *ty, const char *field, int32_t v,
                                 int32_t max)
{
    if (v < 0 || v > max)
        return fail(r, KD_MSG_E_COUNT, "%s.%s = %ld outside 0..%ld", ty, field, (long)v,
                    (long)max);
    return KD_MSG_OK;
}

static kd_msg_status check_finite(kd_reason *r, const char *ty, const char *field,
                                  const double *a, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        if (!isfinite(a[i])) {
            if (n == 1)
                return fail(r, KD_MSG_E_NONFINITE, "%s.%s is %s, not finite", ty, field,
                            isnan(a[i]) ? "NaN" : "infinite");
            return fail(r, KD_MSG_E_NONFINITE, "%s.%s[%d] is %s, not finite", ty, field, i,
                        isnan(a[i]) ? "NaN" : "infinite");
        }
    }
    return KD_MSG_OK;
}

/* A finite value >= 0. */
static kd_msg_status check_nonneg(kd_reason *r, const char *ty, const char *field, double v)
{
    kd_msg_status s = check_finite(r, ty, field, &v, 1);
    if (s != KD_MSG_OK)
        return s;
    if (v < 0.0)
        return fail(r, KD_MSG_E_RANGE, "%s.%s = %g is negative", ty, field, v);
    return KD_MSG_OK;
}

/* A fraction of the limits: finite, in [0, 1] (0 meaning 1). */
static kd_msg_status check_scale(kd_reason *r, const char *ty, const char *field, double v)
{
    kd_msg_status s = check_finite(r, ty, field, &v, 1);
    if (s != KD_MSG_OK)
        return s;
    if (v < 0.0 || v > 1.0)
        return fail(r, KD_MSG_E_RANGE, "%s.%s = %g outside [0, 1]", ty, field, v);
    return KD_MSG_OK;
}

static kd_msg_status check_goal_id(kd_reason *r, const char *ty, int64_t id)
{
    if (id == 0)
        return fail(r, KD_MSG_E_RANGE, "%s.goal_id = 0 (0 means no goal; choose another)", ty);
    return KD_MSG_OK;
}

/* Chains checks: stops at the first failure. */
#define CHECK(expr)                       \
    do {                                  \
        kd_msg_status s_ = (expr);        \
        if (s_ != KD_MSG_OK)              \
            return s_;                    \
    } while (0)

/* What every goal opens with: its id and whether it queues or replaces. */
static kd_msg_status check_goal_head(kd_reason *r, const char *ty, int64_t id, int mode, int queue,
                                     int replace)
{
    CHECK(check_goal_id(r, ty, id));
    return check_enum(r, ty, "mode", mode, queue, replace);
}

/* A Cartesian target: position (3) and orientation quaternion (4). */
static kd_msg_status check_pose(kd_reason *r, const char *ty, const double position[3],
                                const double orientation[4])
{
    CHECK(check_finite(r, ty, "position", position, 3));
    return check_finite(r, ty, "orientation", orientation, 4);
}

/* A Cartesian move's own limits, linear then angular (0 meaning the
 * configured ones). */
static kd_msg_status check_cart_limits(kd_reason *r, const char *ty, double speed, double accel,
                                       double angular_speed, double angular_accel)
{
    CHECK(check_nonneg(r, ty, "speed", speed));
    CHECK(check_nonneg(r, ty, "accel", accel));
    CHECK(check_nonneg(r, ty, "angular_speed", angular_speed));
    return check_nonneg(r, ty, "angular_accel", angular_accel);
}

/* A Cartesian move's own jerk limits (0 meaning the configured ones). */
static kd_msg_status check_cart_jerk(kd_reason *r, const char *ty, double jerk, double angular_jerk)
{
    CHECK(check_nonneg(r, ty, "jerk", jerk));
    return check_nonneg(r, ty, "angular_jerk", angular_jerk);
}

/* The fractions of the limits a goal moves at. */
static kd_msg_status check_scales(kd_reason *r, const char *ty, double vel_scale, double acc_scale)
{
    CHECK(check_scale(r, ty, "vel_scale", vel_scale));
    return check_scale(r, ty, "acc_scale", acc_scale);
}

static kd_msg_status validate_goal_joint(kd_reason *r, const kinctl_goal_joint_t *m)
{
    const char *ty = "goal_joint_t";
    CHECK(check_goal_head(r, ty, m->goal_id, m->mode, KINCTL_GOAL_JOINT_T_QUEUE,
                          KINCTL_GOAL_JOINT_T_REPLACE));
    CHECK(check_count(r, ty, "n", m->n, KINCTL_GOAL_JOINT_T_MAX_JOINTS));
    CHECK(check_finite(r, ty, "q", m->q, KINCTL_GOAL_JOINT_T_MAX_JOINTS));
    CHECK(check_enum(r, ty, "profile", m->profile, KINCTL_GOAL_JOINT_T_PROFILE_CONFIG,
                     KINCTL_GOAL_JOINT_T_PROFILE_JERK));
    return check_scales(r, ty, m->vel_scale, m->acc_scale);
}

static kd_msg_status validate_goal_line(kd_reason *r, const kinctl_goal_line_t *m)
{
    const char *ty = "goal_line_t";
    CHECK(check_goal_head(r, ty, m->goal_id, m->mode, KINCTL_GOAL_LINE_T_QUEUE,
                          KINCTL_GOAL_LINE_T_REPLACE));
    CHECK(check_enum(r, ty, "orientation_method", m->orientation_method,
                     KINCTL_GOAL_LINE_T_TWO_ROTATIONS, KINCTL_GOAL_LINE_T_SLERP));
    CHECK(check_pose(r, ty, m->position, m->orientation));
    CHECK(check_cart_limits(r, ty, m->speed, m->accel, m->angular_speed, m->angular_accel));
    CHECK(check_cart_jerk(r, ty, m->jerk, m->angular_jerk));
    return check_scales(r, ty, m->vel_scale, m->acc_scale);
}

static kd_msg_status validate_goal_arc(kd_reason *r, const kinctl_goal_arc_t *m)
{
    const char *ty = "goal_arc_t";
    CHECK(check_goal_head(r, ty, m->goal_id, m->mode, KINCTL_GOAL_ARC_T_QUEUE,
                          KINCTL_GOAL_ARC_T_REPLACE));
    CHECK(check_finite(r, ty, "via", m->via, 3));
    CHECK(check_pose(r, ty, m->position, m->orientation));
    CHECK(check_cart_limits(r, ty, m->speed, m->accel, m->angular_speed, m->angular_accel));
    CHECK(check_cart_jerk(r, ty, m->jerk, m->angular_jerk));
    return check_scales(r, ty, m->vel_scale, m->acc_scale);
}

static kd_msg_status validate_goal_path(kd_reason *r, const kinctl_goal_path_t *m)
{
    const char *ty = "goal_path_t";
    int i;
    CHECK(check_goal_head(r, ty, m->goal_id, m->mode, KINCTL_GOAL_PATH_T_QUEUE,
                          KINCTL_GOAL_PATH_T_REPLACE));
    CHECK(check_enum(r, ty, "space", m->space, KINCTL_GOAL_PATH_T_JOINT,
                     KINCTL_GOAL_PATH_T_CARTESIAN));
    CHECK(check_enum(r, ty, "method", m->method, KINCTL_GOAL_PATH_T_BLEND,
                     KINCTL_GOAL_PATH_T_LAGRANGE));
    CHECK(check_enum(r, ty, "blend_shape", m->blend_shape, KINCTL_GOAL_PATH_T_BLEND_QUARTIC,
                     KINCTL_GOAL_PATH_T_BLEND_PARABOLIC));
    CHECK(check_enum(r, ty, "spline_ends", m->spline_ends, KINCTL_GOAL_PATH_T_SPLINE_CLAMPED,
                     KINCTL_GOAL_PATH_T_SPLINE_NATURAL));
    CHECK(check_enum(r, ty, "has_times", m->has_times, 0, 1));
    CHECK(check_count(r, ty, "n_points", m->n_points, KINCTL_GOAL_PATH_T_MAX_POINTS));
    CHECK(check_count(r, ty, "dim", m->dim, KINCTL_GOAL_PATH_T_MAX_DIM));
    if (m->space == KINCTL_GOAL_PATH_T_CARTESIAN && m->dim != KINCTL_GOAL_PATH_T_CARTESIAN_DIM)
        return fail(r, KD_MSG_E_COUNT, "%s.dim = %ld, a Cartesian path needs %d (x y z qw qx qy qz)",
                    ty, (long)m->dim, KINCTL_GOAL_PATH_T_CARTESIAN_DIM);
    for (i = 0; i < KINCTL_GOAL_PATH_T_MAX_POINTS; i++) {
        int j;
        for (j = 0; j < KINCTL_GOAL_PATH_T_MAX_DIM; j++) {
            if (!isfinite(m->points[i][j]))
                return fail(r, KD_MSG_E_NONFINITE, "%s.points[%d][%d] is %s, not finite", ty, i,
                            j, isnan(m->points[i][j]) ? "NaN" : "infinite");
        }
    }
    CHECK(check_finite(r, ty, "times", m->times, KINCTL_GOAL_PATH_T_MAX_POINTS));
    CHECK(check_nonneg(r, ty, "blend_time", m->blend_time));
    CHECK(check_nonneg(r, ty, "speed", m->speed));
    CHECK(check_nonneg(r, ty, "accel", m->accel));
    CHECK(check_cart_jerk(r, ty, m->jerk, m->angular_jerk));
    return check_scales(r, ty, m->vel_scale, m->acc_scale);
}

static kd_msg_status validate_goal_servo(kd_reason *r, const kinctl_goal_servo_t *m)
{
    const char *ty = "goal_servo_t";
    CHECK(check_goal_head(r, ty, m->goal_id, m->mode, KINCTL_GOAL_SERVO_T_QUEUE,
                          KINCTL_GOAL_SERVO_T_REPLACE));
    CHECK(check_enum(r, ty, "kind", m->kind, KINCTL_GOAL_SERVO_T_POSE, KINCTL_GOAL_SERVO_T_TWIST));
    CHECK(check_pose(r, ty, m->position, m->orientation));
    CHECK(check_finite(r, ty, "twist", m->twist, 6));
    if (m->timeout_us <= 0)
        return fail(r, KD_MSG_E_RANGE, "%s.timeout_us = %lld, must be > 0", ty,
                    (long long)m->timeout_us);
    return KD_MSG_OK;
}

static kd_msg_status validate_command(kd_reason *r, const kinctl_command_t *m)
{
    return check_enum(r, "command_t", "command", m->command, KINCTL_COMMAND_T_STOP,
                      KINCTL_COMMAND_T_RESET);
}

static kd_msg_status validate_setpoint(kd_reason *r, const kinctl_setpoint_t *m)
{
    const char *ty = "setpoint_t";
    CHECK(check_enum(r, ty, "state", m->state, KINCTL_SETPOINT_T_IDLE, KINCTL_SETPOINT_T_ESTOP));
    CHECK(check_count(r, ty, "n", m->n, KINCTL_SETPOINT_T_MAX_JOINTS));
    CHECK(check_finite(r, ty, "q", m->q, KINCTL_SETPOINT_T_MAX_JOINTS));
    CHECK(check_finite(r, ty, "qd", m->qd, KINCTL_SETPOINT_T_MAX_JOINTS));
    CHECK(check_finite(r, ty, "qdd", m->qdd, KINCTL_SETPOINT_T_MAX_JOINTS));
    CHECK(check_pose(r, ty, m->position, m->orientation));
    CHECK(check_enum(r, ty, "input_command", m->input_command, 0, KINCTL_COMMAND_T_RESET));
    CHECK(check_enum(r, ty, "input_servo_stale", m->input_servo_stale, 0, 1));
    CHECK(check_enum(r, ty, "input_fault", m->input_fault, 0, 1));
    CHECK(check_enum(r, ty, "input_seated", m->input_seated, 0, 1));
    CHECK(check_finite(r, ty, "input_goal_share", &m->input_goal_share, 1));
    if (!(m->input_goal_share > 0.0 && m->input_goal_share <= 1.0))
        return fail(r, KD_MSG_E_RANGE, "%s.input_goal_share = %g outside (0, 1]", ty, m->input_goal_share);
    CHECK(check_enum(r, ty, "input_goal_stop_first", m->input_goal_stop_first, 0, 1));
    CHECK(check_nonneg(r, ty, "input_goal_qu", m->input_goal_qu));
    CHECK(check_enum(r, ty, "input_goal_scheduled", m->input_goal_scheduled, 0, 1));
    if (!(m->input_goal_take_state >= 0 && m->input_goal_take_state <= (int64_t)UINT32_MAX))
        return fail(r, KD_MSG_E_RANGE, "%s.input_goal_take_state = %" PRId64 " outside 0 .. 2^32 - 1", ty,
                    m->input_goal_take_state);
    if (!m->input_goal_scheduled && (m->input_goal_take_ahead != 0 || m->input_goal_take_state != 0))
        return fail(r, KD_MSG_E_RANGE, "%s.input_goal_take_ahead and input_goal_take_state not 0 for a goal not scheduled",
                    ty);
    return KD_MSG_OK;
}

static kd_msg_status validate(kd_reason *r, kd_msg_type type, const kd_msg_any *m)
{
    switch (type) {
    case KD_MSG_GOAL_JOINT: return validate_goal_joint(r, &m->goal_joint);
    case KD_MSG_GOAL_LINE: return validate_goal_line(r, &m->goal_line);
    case KD_MSG_GOAL_ARC: return validate_goal_arc(r, &m->goal_arc);
    case KD_MSG_GOAL_PATH: return validate_goal_path(r, &m->goal_path);
    case KD_MSG_GOAL_SERVO: return validate_goal_servo(r, &m->goal_servo);
    case KD_MSG_COMMAND: return validate_command(r, &m->command);
    case KD_MSG_SETPOINT: return validate_setpoint(r, &m->setpoint);
    case KD_MSG_STATS: return KD_MSG_OK; /* integers only: any value decodes */
    case KD_MSG_STATUS:
    case KD_MSG_TYPE_COUNT: break;
    }
    return fail(r, KD_MSG_E_TYPE, "no validation for this type");
}

/* ---- decode and encode ------------------------------------------------- */

kd_msg_status kd_msg_decode(kd_msg_type type, const void *buf, size_t len, void *out,
                            char *reason, size_t reason_size)
{
    kd_reason r;
    kd_msg_any tmp;
    kd_msg_type seen;
    const kd_msg_info *ti;
    int used;
    kd_msg_status s;

    r.buf = reason_size ? reason : NULL;
    r.size = reason_size;
    if (r.buf)
        r.buf[0] = '\0';
    if ((int)type < 0 || (int)type >= KD_MSG_TYPE_COUNT)
        return fail(&r, KD_MSG_E_ARG, "unknown message type %d", (int)type);
    if (!buf || !out)
        return fail(&r, KD_MSG_E_ARG, "NULL buffer or output");
    ti = &info[type];
    if (type == KD_MSG_STATUS)
        return fail(&r, KD_MSG_E_TYPE,
                    "status_t carries a string and is sent by the daemon only: never decoded here");

    if (len < 8)
        return fail(&r, KD_MSG_E_TRUNCATED, "%s: datagram of %lu bytes has no fingerprint",
                    ti->name, (unsigned long)len);
    if (read_be64((const unsigned char *)buf) != glue[type].hash()) {
        if (kd_msg_identify(buf, len, &seen) == KD_MSG_OK)
            return fail(&r, KD_MSG_E_FINGERPRINT, "%s expected, fingerprint is %s's", ti->name,
                        info[seen].name);
        return fail(&r, KD_MSG_E_FINGERPRINT, "%s expected, fingerprint is of no kinctl type",
                    ti->name);
    }
    if (len < ti->size)
        return fail(&r, KD_MSG_E_TRUNCATED, "%s: datagram of %lu bytes, the type has %lu",
                    ti->name, (unsigned long)len, (unsigned long)ti->size);
    if (len > ti->size)
        return fail(&r, KD_MSG_E_OVERSIZED, "%s: datagram of %lu bytes, the type has %lu",
                    ti->name, (unsigned long)len, (unsigned long)ti->size);

    /* Fixed-size types only reach here: the generated decoder writes in
     * place and allocates nothing. len == ti->size < INT_MAX. */
    memset(&tmp, 0, sizeof tmp);
    used = glue[type].decode(buf, (int)len, &tmp);
    if (used < 0)
        return fail(&r, KD_MSG_E_DECODE, "%s: the generated decoder refused the datagram",
                    ti->name);
    if ((size_t)used != len)
        return fail(&r, KD_MSG_E_DECODE, "%s: decoded %d bytes of a %lu-byte datagram", ti->name,
                    used, (unsigned long)len);

    s = validate(&r, type, &tmp);
    if (s != KD_MSG_OK)
        return s;
    memcpy(out, &tmp, glue[type].struct_size);
    return KD_MSG_OK;
}

kd_msg_status kd_msg_encode(kd_msg_type type, const void *msg, void *buf, size_t cap,
                            size_t *len)
{
    kinctl_status_t st;
    char reason[KD_MSG_STATUS_REASON_MAX + 1];
    int need, done, icap;

    if ((int)type < 0 || (int)type >= KD_MSG_TYPE_COUNT || !msg || !buf || !len)
        return KD_MSG_E_ARG;
    if (type == KD_MSG_STATUS) {
        /* Send a bounded copy of the reason: never strlen() past
         * KD_MSG_STATUS_REASON_MAX, never dereference NULL. */
        size_t n = 0;
        const char *src;
        memcpy(&st, msg, sizeof st);
        src = st.reason ? st.reason : "";
        while (n < KD_MSG_STATUS_REASON_MAX && src[n] != '\0')
            n++;
        memcpy(reason, src, n);
        reason[n] = '\0';
        st.reason = reason;
        msg = &st;
    }
    need = glue[type].size(msg);
    if (need < 0)
        return KD_MSG_E_ENCODE;
    if ((size_t)need > cap)
        return KD_MSG_E_SPACE;
    icap = cap > (size_t)INT_MAX ? INT_MAX : (int)cap;
    done = glue[type].encode(buf, icap, msg);
    if (done != need)
        return KD_MSG_E_ENCODE;
    *len = (size_t)done;
    return KD_MSG_OK;
}
