/* SPDX-License-Identifier: BSD-3-Clause */
/* test_msg.c - the daemon's message layer (daemon/msg.h): every type round
 * trips through kd_msg_encode and kd_msg_decode (status_t through the
 * generated decoder, which the daemon never uses); every way a datagram can
 * be wrong is refused with the right status and a reason naming the field,
 * and the output is left untouched. Runs under ASan/UBSan in the sanitizer
 * build, where the garbage tests are the point. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "msg.h"
#include "msg_sample.h"

/* Types kd_msg_decode accepts: the client types, setpoint_t and stats_t. */
#define N_DECODABLE 8
static const kd_msg_type decodable[N_DECODABLE] = {
    KD_MSG_GOAL_JOINT, KD_MSG_GOAL_LINE, KD_MSG_GOAL_ARC, KD_MSG_GOAL_PATH,
    KD_MSG_GOAL_SERVO, KD_MSG_COMMAND,   KD_MSG_SETPOINT, KD_MSG_STATS,
};

static unsigned char buf[KD_MSG_MAX_SIZE + 64];

static size_t encode(kd_msg_type t, const void *m)
{
    size_t len = 0;
    assert_int_equal(kd_msg_encode(t, m, buf, sizeof buf, &len), KD_MSG_OK);
    assert_int_equal(len, kd_msg_type_info(t)->size);
    return len;
}

/* Decode buf[0..len) as t; expects `want`, a reason containing `needle` when
 * it fails, and on failure the output untouched. */
static void expect_decode(kd_msg_type t, size_t len, kd_msg_status want, const char *needle)
{
    kd_msg_any out, sentinel;
    char reason[KD_MSG_REASON_SIZE];
    kd_msg_status s;
    memset(&out, 0xa5, sizeof out);
    memcpy(&sentinel, &out, sizeof out);
    s = kd_msg_decode(t, buf, len, &out, reason, sizeof reason);
    if (s != want || (needle && !strstr(reason, needle)))
        print_error("%s, %lu bytes: got %d (%s) \"%s\", wanted %d, reason with \"%s\"\n",
                    kd_msg_type_info(t)->name, (unsigned long)len, (int)s, kd_msg_status_str(s),
                    reason, (int)want, needle ? needle : "");
    assert_int_equal(s, want);
    if (needle)
        assert_non_null(strstr(reason, needle));
    if (s != KD_MSG_OK) {
        assert_memory_equal(&out, &sentinel, sizeof out);
        assert_true(reason[0] != '\0');
    } else {
        assert_string_equal(reason, "");
    }
}

static void test_sizes(void **state)
{
    int t;
    (void)state;
    for (t = 0; t < KD_MSG_TYPE_COUNT; t++) {
        kd_msg_any m;
        char r[64];
        const kd_msg_info *ti = kd_msg_type_info((kd_msg_type)t);
        assert_non_null(ti);
        memset(&m, 0, sizeof m);
        if (t == KD_MSG_STATUS) {
            m.status.reason = (char *)"";
            assert_int_equal(ti->size, (size_t)kinctl_status_t_encoded_size(&m.status));
        } else {
            msg_sample((kd_msg_type)t, 1, &m, r);
            assert_true(ti->size <= KD_MSG_MAX_SIZE);
            assert_int_equal(encode((kd_msg_type)t, &m), ti->size);
        }
        assert_int_equal(ti->from_client, t < KD_MSG_SETPOINT);
        assert_true(kd_msg_fingerprint((kd_msg_type)t) != 0);
    }
    assert_null(kd_msg_type_info(KD_MSG_TYPE_COUNT));
    assert_null(kd_msg_type_info((kd_msg_type)-1));
    assert_string_equal(kd_msg_type_info(KD_MSG_GOAL_PATH)->channel, "GOAL_PATH");
    /* goal_path_t is the largest; KD_MSG_MAX_SIZE is not wildly too large. */
    assert_true(kd_msg_type_info(KD_MSG_GOAL_PATH)->size + 1024 > KD_MSG_MAX_SIZE);
}

static void test_round_trip(void **state)
{
    int i;
    uint32_t seed;
    (void)state;
    for (i = 0; i < N_DECODABLE; i++) {
        kd_msg_type t = decodable[i];
        for (seed = 1; seed <= 200; seed++) {
            kd_msg_any m, out;
            char r[64];
            size_t len;
            msg_sample(t, seed, &m, r);
            len = encode(t, &m);
            memset(&out, 0, sizeof out);
            expect_decode(t, len, KD_MSG_OK, NULL);
            assert_int_equal(kd_msg_decode(t, buf, len, &out, NULL, 0), KD_MSG_OK);
            /* Both were zeroed before being filled field by field, so their
             * padding agrees too. */
            assert_memory_equal(&m, &out, sizeof m);
        }
    }
}

static void test_round_trip_status(void **state)
{
    uint32_t seed;
    (void)state;
    for (seed = 1; seed <= 100; seed++) {
        kd_msg_any m;
        kinctl_status_t out;
        char r[64];
        size_t len = 0;
        msg_sample(KD_MSG_STATUS, seed, &m, r);
        assert_int_equal(kd_msg_encode(KD_MSG_STATUS, &m, buf, sizeof buf, &len), KD_MSG_OK);
        assert_int_equal(len, kd_msg_type_info(KD_MSG_STATUS)->size + strlen(r));
        assert_int_equal(kinctl_status_t_decode(buf, 0, (int)len, &out), (int)len);
        assert_int_equal(out.cycle, m.status.cycle);
        assert_int_equal(out.active_goal_id, m.status.active_goal_id);
        assert_int_equal(out.event, m.status.event);
        assert_int_equal(out.code, m.status.code);
        assert_string_equal(out.reason, r);
        assert_int_equal(out.n, m.status.n);
        assert_memory_equal(out.q_measured, m.status.q_measured, sizeof out.q_measured);
        assert_memory_equal(out.qd_measured, m.status.qd_measured, sizeof out.qd_measured);
        assert_true(out.progress == m.status.progress);
        kinctl_status_t_decode_cleanup(&out);
    }
}

/* The daemon never decodes status_t, even a valid one. */
static void test_status_refused(void **state)
{
    kd_msg_any m;
    char r[64];
    size_t len = 0;
    (void)state;
    msg_sample(KD_MSG_STATUS, 3, &m, r);
    assert_int_equal(kd_msg_encode(KD_MSG_STATUS, &m, buf, sizeof buf, &len), KD_MSG_OK);
    expect_decode(KD_MSG_STATUS, len, KD_MSG_E_TYPE, "status_t carries a string");
}

static void test_status_reason_bounds(void **state)
{
    kinctl_status_t st, out;
    char longreason[1000];
    size_t len = 0;
    (void)state;
    memset(&st, 0, sizeof st);
    st.reason = NULL;
    assert_int_equal(kd_msg_encode(KD_MSG_STATUS, &st, buf, sizeof buf, &len), KD_MSG_OK);
    assert_int_equal(len, kd_msg_type_info(KD_MSG_STATUS)->size);
    assert_int_equal(kinctl_status_t_decode(buf, 0, (int)len, &out), (int)len);
    assert_string_equal(out.reason, "");
    kinctl_status_t_decode_cleanup(&out);

    memset(longreason, 'x', sizeof longreason - 1);
    longreason[sizeof longreason - 1] = '\0';
    st.reason = longreason;
    assert_int_equal(kd_msg_encode(KD_MSG_STATUS, &st, buf, sizeof buf, &len), KD_MSG_OK);
    assert_int_equal(len, kd_msg_type_info(KD_MSG_STATUS)->size + KD_MSG_STATUS_REASON_MAX);
    assert_int_equal(kinctl_status_t_decode(buf, 0, (int)len, &out), (int)len);
    assert_int_equal(strlen(out.reason), KD_MSG_STATUS_REASON_MAX);
    kinctl_status_t_decode_cleanup(&out);
}

static void test_truncated(void **state)
{
    int i;
    (void)state;
    for (i = 0; i < N_DECODABLE; i++) {
        kd_msg_type t = decodable[i];
        kd_msg_any m;
        char r[64];
        size_t len, k;
        msg_sample(t, 7, &m, r);
        len = encode(t, &m);
        for (k = 0; k < 8; k++)
            expect_decode(t, k, KD_MSG_E_TRUNCATED, "no fingerprint");
        for (k = 8; k < len; k++)
            expect_decode(t, k, KD_MSG_E_TRUNCATED, "the type has");
    }
}

static void test_oversized(void **state)
{
    int i;
    (void)state;
    for (i = 0; i < N_DECODABLE; i++) {
        kd_msg_type t = decodable[i];
        kd_msg_any m;
        char r[64];
        size_t len;
        msg_sample(t, 8, &m, r);
        len = encode(t, &m);
        memset(buf + len, 0, 64);
        expect_decode(t, len + 1, KD_MSG_E_OVERSIZED, "the type has");
        expect_decode(t, len + 64, KD_MSG_E_OVERSIZED, "the type has");
        /* Two messages in one datagram are not one message. */
        if (2 * len <= sizeof buf) {
            memcpy(buf + len, buf, len);
            expect_decode(t, 2 * len, KD_MSG_E_OVERSIZED, NULL);
        }
    }
    /* A length beyond INT_MAX (the generated code's int) is only a number. */
    {
        kd_msg_any out;
        msg_sample(KD_MSG_COMMAND, 1, &out, NULL);
        encode(KD_MSG_COMMAND, &out);
        assert_int_equal(kd_msg_decode(KD_MSG_COMMAND, buf, (size_t)INT_MAX + 10u, &out, NULL, 0),
                         KD_MSG_E_OVERSIZED);
    }
}

static void test_wrong_fingerprint(void **state)
{
    int i, j;
    (void)state;
    /* Every type decoded as every other: refused, the other type named. */
    for (i = 0; i < N_DECODABLE; i++) {
        for (j = 0; j < N_DECODABLE; j++) {
            kd_msg_any m;
            char r[64], needle[64];
            size_t len;
            if (i == j)
                continue;
            msg_sample(decodable[i], 9, &m, r);
            len = encode(decodable[i], &m);
            (void)snprintf(needle, sizeof needle, "fingerprint is %s's",
                           kd_msg_type_info(decodable[i])->name);
            expect_decode(decodable[j], len, KD_MSG_E_FINGERPRINT, needle);
        }
    }
    /* One bit off in the fingerprint: no kinctl type. */
    for (i = 0; i < N_DECODABLE; i++) {
        kd_msg_any m;
        char r[64];
        size_t len;
        int bit;
        msg_sample(decodable[i], 10, &m, r);
        len = encode(decodable[i], &m);
        for (bit = 0; bit < 64; bit++) {
            buf[bit / 8] ^= (unsigned char)(1u << (bit % 8));
            expect_decode(decodable[i], len, KD_MSG_E_FINGERPRINT, "of no kinctl type");
            buf[bit / 8] ^= (unsigned char)(1u << (bit % 8));
        }
    }
}

static void test_identify(void **state)
{
    int t;
    kd_msg_type seen;
    (void)state;
    for (t = 0; t < KD_MSG_TYPE_COUNT; t++) {
        kd_msg_any m;
        char r[64];
        size_t len = 0;
        msg_sample((kd_msg_type)t, 11, &m, r);
        assert_int_equal(kd_msg_encode((kd_msg_type)t, &m, buf, sizeof buf, &len), KD_MSG_OK);
        assert_int_equal(kd_msg_identify(buf, len, &seen), KD_MSG_OK);
        assert_int_equal(seen, t);
        assert_int_equal(kd_msg_identify(buf, 8, &seen), KD_MSG_OK);
        assert_int_equal(kd_msg_identify(buf, 7, &seen), KD_MSG_E_TRUNCATED);
    }
    memset(buf, 0, 8);
    assert_int_equal(kd_msg_identify(buf, 8, &seen), KD_MSG_E_FINGERPRINT);
    assert_int_equal(kd_msg_identify(NULL, 8, &seen), KD_MSG_E_ARG);
}

/* Counts: n = -1, 127, 17, INT32_MAX, INT32_MIN refused; 0 and MAX accepted. */
static void test_hostile_counts(void **state)
{
    static const int32_t bad[] = {-1, 127, 17, INT32_MAX, INT32_MIN, 1 << 28};
    size_t i;
    kd_msg_any m;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        msg_sample(KD_MSG_GOAL_JOINT, 12, &m, NULL);
        m.goal_joint.n = bad[i];
        expect_decode(KD_MSG_GOAL_JOINT, encode(KD_MSG_GOAL_JOINT, &m), KD_MSG_E_COUNT,
                      "goal_joint_t.n = ");

        msg_sample(KD_MSG_SETPOINT, 12, &m, NULL);
        m.setpoint.n = bad[i];
        expect_decode(KD_MSG_SETPOINT, encode(KD_MSG_SETPOINT, &m), KD_MSG_E_COUNT,
                      "setpoint_t.n = ");

        msg_sample(KD_MSG_GOAL_PATH, 12, &m, NULL);
        m.goal_path.n_points = bad[i] == 17 ? 33 : bad[i];
        expect_decode(KD_MSG_GOAL_PATH, encode(KD_MSG_GOAL_PATH, &m), KD_MSG_E_COUNT,
                      "goal_path_t.n_points = ");

        msg_sample(KD_MSG_GOAL_PATH, 12, &m, NULL);
        m.goal_path.space = KINCTL_GOAL_PATH_T_JOINT;
        m.goal_path.dim = bad[i];
        expect_decode(KD_MSG_GOAL_PATH, encode(KD_MSG_GOAL_PATH, &m), KD_MSG_E_COUNT,
                      "goal_path_t.dim = ");
    }
    /* n = -1 written into the wire bytes directly (after the fingerprint,
     * utime, goal_id and mode: offset 25), as a hostile sender would. */
    msg_sample(KD_MSG_GOAL_JOINT, 13, &m, NULL);
    encode(KD_MSG_GOAL_JOINT, &m);
    memset(buf + 25, 0xff, 4);
    expect_decode(KD_MSG_GOAL_JOINT, kd_msg_type_info(KD_MSG_GOAL_JOINT)->size, KD_MSG_E_COUNT,
                  "n = -1 outside 0..16");
    buf[25] = 0x00;
    buf[26] = 0x00;
    buf[27] = 0x00;
    buf[28] = 0x7f;
    expect_decode(KD_MSG_GOAL_JOINT, kd_msg_type_info(KD_MSG_GOAL_JOINT)->size, KD_MSG_E_COUNT,
                  "n = 127 outside 0..16");

    /* The edges are fine. */
    msg_sample(KD_MSG_GOAL_JOINT, 14, &m, NULL);
    m.goal_joint.n = 0;
    expect_decode(KD_MSG_GOAL_JOINT, encode(KD_MSG_GOAL_JOINT, &m), KD_MSG_OK, NULL);
    m.goal_joint.n = KINCTL_GOAL_JOINT_T_MAX_JOINTS;
    expect_decode(KD_MSG_GOAL_JOINT, encode(KD_MSG_GOAL_JOINT, &m), KD_MSG_OK, NULL);
    msg_sample(KD_MSG_GOAL_PATH, 14, &m, NULL);
    m.goal_path.space = KINCTL_GOAL_PATH_T_JOINT;
    m.goal_path.n_points = KINCTL_GOAL_PATH_T_MAX_POINTS;
    m.goal_path.dim = KINCTL_GOAL_PATH_T_MAX_DIM;
    expect_decode(KD_MSG_GOAL_PATH, encode(KD_MSG_GOAL_PATH, &m), KD_MSG_OK, NULL);

    /* A Cartesian path has dim 7, nothing else. */
    m.goal_path.space = KINCTL_GOAL_PATH_T_CARTESIAN;
    m.goal_path.dim = 6;
    expect_decode(KD_MSG_GOAL_PATH, encode(KD_MSG_GOAL_PATH, &m), KD_MSG_E_COUNT,
                  "a Cartesian path needs 7");
    m.goal_path.dim = 7;
    expect_decode(KD_MSG_GOAL_PATH, encode(KD_MSG_GOAL_PATH, &m), KD_MSG_OK, NULL);
}

/* One double of a type set to NaN, +inf or -inf: refused naming it. */
typedef struct double_field {
    kd_msg_type type;
    size_t offset; /* of the double in the C struct */
    const char *name;
} double_field;

#define DF(T, ty, member, label) {T, offsetof(kinctl_##ty, member), label}

static const double_field double_fields[] = {
    DF(KD_MSG_GOAL_JOINT, goal_joint_t, q[0], "goal_joint_t.q[0]"),
    DF(KD_MSG_GOAL_JOINT, goal_joint_t, q[15], "goal_joint_t.q[15]"),
    DF(KD_MSG_GOAL_JOINT, goal_joint_t, vel_scale, "goal_joint_t.vel_scale is"),
    DF(KD_MSG_GOAL_JOINT, goal_joint_t, acc_scale, "goal_joint_t.acc_scale is"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, position[2], "goal_line_t.position[2]"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, orientation[0], "goal_line_t.orientation[0]"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, speed, "goal_line_t.speed is"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, accel, "goal_line_t.accel is"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, angular_speed, "goal_line_t.angular_speed is"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, angular_accel, "goal_line_t.angular_accel is"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, jerk, "goal_line_t.jerk is"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, angular_jerk, "goal_line_t.angular_jerk is"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, vel_scale, "goal_line_t.vel_scale is"),
    DF(KD_MSG_GOAL_LINE, goal_line_t, acc_scale, "goal_line_t.acc_scale is"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, via[1], "goal_arc_t.via[1]"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, position[0], "goal_arc_t.position[0]"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, orientation[3], "goal_arc_t.orientation[3]"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, speed, "goal_arc_t.speed is"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, accel, "goal_arc_t.accel is"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, angular_speed, "goal_arc_t.angular_speed is"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, angular_accel, "goal_arc_t.angular_accel is"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, jerk, "goal_arc_t.jerk is"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, angular_jerk, "goal_arc_t.angular_jerk is"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, vel_scale, "goal_arc_t.vel_scale is"),
    DF(KD_MSG_GOAL_ARC, goal_arc_t, acc_scale, "goal_arc_t.acc_scale is"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, points[0][0], "goal_path_t.points[0][0]"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, points[30][15], "goal_path_t.points[30][15]"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, points[5][9], "goal_path_t.points[5][9]"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, times[30], "goal_path_t.times[30]"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, blend_time, "goal_path_t.blend_time is"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, speed, "goal_path_t.speed is"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, accel, "goal_path_t.accel is"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, jerk, "goal_path_t.jerk is"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, angular_jerk, "goal_path_t.angular_jerk is"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, vel_scale, "goal_path_t.vel_scale is"),
    DF(KD_MSG_GOAL_PATH, goal_path_t, acc_scale, "goal_path_t.acc_scale is"),
    DF(KD_MSG_GOAL_SERVO, goal_servo_t, position[1], "goal_servo_t.position[1]"),
    DF(KD_MSG_GOAL_SERVO, goal_servo_t, orientation[2], "goal_servo_t.orientation[2]"),
    DF(KD_MSG_GOAL_SERVO, goal_servo_t, twist[5], "goal_servo_t.twist[5]"),
    DF(KD_MSG_SETPOINT, setpoint_t, q[3], "setpoint_t.q[3]"),
    DF(KD_MSG_SETPOINT, setpoint_t, qd[15], "setpoint_t.qd[15]"),
    DF(KD_MSG_SETPOINT, setpoint_t, qdd[0], "setpoint_t.qdd[0]"),
    DF(KD_MSG_SETPOINT, setpoint_t, position[2], "setpoint_t.position[2]"),
    DF(KD_MSG_SETPOINT, setpoint_t, orientation[1], "setpoint_t.orientation[1]"),
};

static void test_nonfinite(void **state)
{
    const double values[3] = {(double)NAN, (double)INFINITY, -(double)INFINITY};
    size_t i;
    int v;
    (void)state;
    for (i = 0; i < sizeof double_fields / sizeof double_fields[0]; i++) {
        const double_field *f = &double_fields[i];
        for (v = 0; v < 3; v++) {
            kd_msg_any m;
            msg_sample(f->type, 15, &m, NULL);
            /* Even a slot past the count (q[15] with n < 16) must be finite. */
            if (f->type == KD_MSG_GOAL_JOINT)
                m.goal_joint.n = 3;
            memcpy((unsigned char *)&m + f->offset, &values[v], sizeof(double));
            expect_decode(f->type, encode(f->type, &m), KD_MSG_E_NONFINITE, f->name);
        }
    }
    /* Every double of the largest type, each in turn. */
    {
        int k, j;
        for (k = 0; k < KINCTL_GOAL_PATH_T_MAX_POINTS; k++) {
            for (j = 0; j < KINCTL_GOAL_PATH_T_MAX_DIM; j++) {
                kd_msg_any m;
                char needle[48];
                msg_sample(KD_MSG_GOAL_PATH, 16, &m, NULL);
                m.goal_path.points[k][j] = (double)NAN;
                (void)snprintf(needle, sizeof needle, "points[%d][%d] is NaN", k, j);
                expect_decode(KD_MSG_GOAL_PATH, encode(KD_MSG_GOAL_PATH, &m), KD_MSG_E_NONFINITE,
                              needle);
            }
        }
    }
}

/* An int8 enum field set to a value outside its consts. */
typedef struct enum_field {
    kd_msg_type type;
    size_t offset;
    int8_t value;
    const char *needle;
} enum_field;

#define EF(T, ty, member, v, label) {T, offsetof(kinctl_##ty, member), v, label}

static const enum_field enum_fields[] = {
    EF(KD_MSG_GOAL_JOINT, goal_joint_t, mode, 2, "goal_joint_t.mode = 2"),
    EF(KD_MSG_GOAL_JOINT, goal_joint_t, mode, -1, "goal_joint_t.mode = -1"),
    EF(KD_MSG_GOAL_JOINT, goal_joint_t, profile, 3, "goal_joint_t.profile = 3"),
    EF(KD_MSG_GOAL_JOINT, goal_joint_t, profile, -1, "goal_joint_t.profile = -1"),
    EF(KD_MSG_GOAL_LINE, goal_line_t, mode, 127, "goal_line_t.mode = 127"),
    EF(KD_MSG_GOAL_LINE, goal_line_t, orientation_method, 2, "goal_line_t.orientation_method = 2"),
    EF(KD_MSG_GOAL_ARC, goal_arc_t, mode, -128, "goal_arc_t.mode = -128"),
    EF(KD_MSG_GOAL_PATH, goal_path_t, mode, 3, "goal_path_t.mode = 3"),
    EF(KD_MSG_GOAL_PATH, goal_path_t, space, 2, "goal_path_t.space = 2"),
    EF(KD_MSG_GOAL_PATH, goal_path_t, method, 4, "goal_path_t.method = 4"),
    EF(KD_MSG_GOAL_PATH, goal_path_t, method, -1, "goal_path_t.method = -1"),
    EF(KD_MSG_GOAL_PATH, goal_path_t, blend_shape, 2, "goal_path_t.blend_shape = 2"),
    EF(KD_MSG_GOAL_PATH, goal_path_t, spline_ends, 5, "goal_path_t.spline_ends = 5"),
    EF(KD_MSG_GOAL_PATH, goal_path_t, has_times, 2, "goal_path_t.has_times = 2"),
    EF(KD_MSG_GOAL_SERVO, goal_servo_t, mode, 9, "goal_servo_t.mode = 9"),
    EF(KD_MSG_GOAL_SERVO, goal_servo_t, kind, 2, "goal_servo_t.kind = 2"),
    EF(KD_MSG_COMMAND, command_t, command, 0, "command_t.command = 0"),
    EF(KD_MSG_COMMAND, command_t, command, 6, "command_t.command = 6"),
    EF(KD_MSG_COMMAND, command_t, command, -128, "command_t.command = -128"),
    EF(KD_MSG_SETPOINT, setpoint_t, state, 6, "setpoint_t.state = 6"),
    EF(KD_MSG_SETPOINT, setpoint_t, state, -1, "setpoint_t.state = -1"),
    EF(KD_MSG_SETPOINT, setpoint_t, input_seated, 2, "setpoint_t.input_seated = 2"),
    EF(KD_MSG_SETPOINT, setpoint_t, input_goal_stop_first, -1, "setpoint_t.input_goal_stop_first = -1"),
    EF(KD_MSG_SETPOINT, setpoint_t, input_goal_scheduled, 2, "setpoint_t.input_goal_scheduled = 2"),
};

static void test_unknown_enums(void **state)
{
    size_t i;
    int c;
    (void)state;
    for (i = 0; i < sizeof enum_fields / sizeof enum_fields[0]; i++) {
        const enum_field *f = &enum_fields[i];
        kd_msg_any m;
        msg_sample(f->type, 17, &m, NULL);
        memcpy((unsigned char *)&m + f->offset, &f->value, 1);
        expect_decode(f->type, encode(f->type, &m), KD_MSG_E_ENUM, f->needle);
    }
    /* Every command that exists is accepted. */
    for (c = KINCTL_COMMAND_T_STOP; c <= KINCTL_COMMAND_T_RESET; c++) {
        kd_msg_any m;
        msg_sample(KD_MSG_COMMAND, 18, &m, NULL);
        m.command.command = (int8_t)c;
        expect_decode(KD_MSG_COMMAND, encode(KD_MSG_COMMAND, &m), KD_MSG_OK, NULL);
    }
}

static void test_ranges(void **state)
{
    kd_msg_any m;
    (void)state;
    msg_sample(KD_MSG_GOAL_JOINT, 19, &m, NULL);
    m.goal_joint.vel_scale = 1.5;
    expect_decode(KD_MSG_GOAL_JOINT, encode(KD_MSG_GOAL_JOINT, &m), KD_MSG_E_RANGE,
                  "vel_scale = 1.5 outside [0, 1]");
    m.goal_joint.vel_scale = 0.0; /* 0 means 1 */
    m.goal_joint.acc_scale = 1.0;
    expect_decode(KD_MSG_GOAL_JOINT, encode(KD_MSG_GOAL_JOINT, &m), KD_MSG_OK, NULL);
    m.goal_joint.acc_scale = -0.25;
    expect_decode(KD_MSG_GOAL_JOINT, encode(KD_MSG_GOAL_JOINT, &m), KD_MSG_E_RANGE,
                  "acc_scale = -0.25");
    msg_sample(KD_MSG_GOAL_JOINT, 19, &m, NULL);
    m.goal_joint.goal_id = 0;
    expect_decode(KD_MSG_GOAL_JOINT, encode(KD_MSG_GOAL_JOINT, &m), KD_MSG_E_RANGE,
                  "goal_id = 0");

    msg_sample(KD_MSG_GOAL_LINE, 19, &m, NULL);
    m.goal_line.speed = -0.1;
    expect_decode(KD_MSG_GOAL_LINE, encode(KD_MSG_GOAL_LINE, &m), KD_MSG_E_RANGE,
                  "goal_line_t.speed = -0.1 is negative");
    msg_sample(KD_MSG_GOAL_ARC, 19, &m, NULL);
    m.goal_arc.accel = -2.0;
    expect_decode(KD_MSG_GOAL_ARC, encode(KD_MSG_GOAL_ARC, &m), KD_MSG_E_RANGE,
                  "goal_arc_t.accel = -2 is negative");
    msg_sample(KD_MSG_GOAL_PATH, 19, &m, NULL);
    m.goal_path.blend_time = -0.5;
    expect_decode(KD_MSG_GOAL_PATH, encode(KD_MSG_GOAL_PATH, &m), KD_MSG_E_RANGE,
                  "blend_time = -0.5");
    msg_sample(KD_MSG_GOAL_SERVO, 19, &m, NULL);
    m.goal_servo.timeout_us = 0;
    expect_decode(KD_MSG_GOAL_SERVO, encode(KD_MSG_GOAL_SERVO, &m), KD_MSG_E_RANGE,
                  "timeout_us = 0, must be > 0");
    m.goal_servo.timeout_us = INT64_MIN;
    expect_decode(KD_MSG_GOAL_SERVO, encode(KD_MSG_GOAL_SERVO, &m), KD_MSG_E_RANGE,
                  "timeout_us");

    msg_sample(KD_MSG_SETPOINT, 19, &m, NULL);
    m.setpoint.input_goal_share = 0.0;
    expect_decode(KD_MSG_SETPOINT, encode(KD_MSG_SETPOINT, &m), KD_MSG_E_RANGE,
                  "setpoint_t.input_goal_share = 0 outside (0, 1]");
    m.setpoint.input_goal_share = 1.0;
    m.setpoint.input_goal_scheduled = 1;
    m.setpoint.input_goal_take_ahead = -3; /* handed on late: allowed, the step refuses it */
    m.setpoint.input_goal_take_state = (int64_t)UINT32_MAX;
    expect_decode(KD_MSG_SETPOINT, encode(KD_MSG_SETPOINT, &m), KD_MSG_OK, NULL);
    m.setpoint.input_goal_take_state = (int64_t)UINT32_MAX + 1;
    expect_decode(KD_MSG_SETPOINT, encode(KD_MSG_SETPOINT, &m), KD_MSG_E_RANGE,
                  "setpoint_t.input_goal_take_state = 4294967296 outside 0 .. 2^32 - 1");
    m.setpoint.input_goal_take_state = -1;
    expect_decode(KD_MSG_SETPOINT, encode(KD_MSG_SETPOINT, &m), KD_MSG_E_RANGE,
                  "setpoint_t.input_goal_take_state = -1 outside");
    m.setpoint.input_goal_take_state = 0;
    m.setpoint.input_goal_scheduled = 0;
    expect_decode(KD_MSG_SETPOINT, encode(KD_MSG_SETPOINT, &m), KD_MSG_E_RANGE,
                  "setpoint_t.input_goal_take_ahead and input_goal_take_state not 0 for a goal not scheduled");
    m.setpoint.input_goal_take_ahead = 0;
    expect_decode(KD_MSG_SETPOINT, encode(KD_MSG_SETPOINT, &m), KD_MSG_OK, NULL);
}

/* Random bytes: never accepted, never a crash (the sanitizer build watches).
 * Then random payloads behind a right fingerprint at the right size: whatever
 * decodes must have passed the checks. */
static void test_garbage(void **state)
{
    uint32_t s = 12345u;
    int iter, i;
    (void)state;
    for (iter = 0; iter < 20000; iter++) {
        kd_msg_type t = decodable[iter % N_DECODABLE];
        size_t len, k;
        kd_msg_any out;
        char reason[KD_MSG_REASON_SIZE];
        kd_msg_status st;
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        len = s % (KD_MSG_MAX_SIZE + 1);
        for (k = 0; k < len; k++) {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            buf[k] = (unsigned char)(s >> 24);
        }
        st = kd_msg_decode(t, buf, len, &out, reason, sizeof reason);
        assert_true(st == KD_MSG_E_TRUNCATED || st == KD_MSG_E_FINGERPRINT);
        assert_true(strlen(reason) > 0 && strlen(reason) < sizeof reason);
    }
    for (i = 0; i < N_DECODABLE; i++) {
        kd_msg_type t = decodable[i];
        size_t len = kd_msg_type_info(t)->size;
        int ok = 0, bad = 0;
        for (iter = 0; iter < 3000; iter++) {
            kd_msg_any m, out;
            size_t k;
            kd_msg_status st;
            msg_sample(t, 20, &m, NULL);
            encode(t, &m);
            for (k = 8; k < len; k++) {
                s ^= s << 13;
                s ^= s >> 17;
                s ^= s << 5;
                /* Mostly small bytes so that some payloads pass. */
                if (s % 4 == 0)
                    buf[k] = (unsigned char)(s >> 24);
            }
            st = kd_msg_decode(t, buf, len, &out, NULL, 0);
            if (st == KD_MSG_OK) {
                size_t len2 = 0;
                unsigned char again[KD_MSG_MAX_SIZE];
                ok++;
                /* What was accepted re-encodes to the same bytes. */
                assert_int_equal(kd_msg_encode(t, &out, again, sizeof again, &len2), KD_MSG_OK);
                assert_int_equal(len2, len);
                assert_memory_equal(again, buf, len);
            } else {
                bad++;
                assert_true(st == KD_MSG_E_COUNT || st == KD_MSG_E_ENUM ||
                            st == KD_MSG_E_NONFINITE || st == KD_MSG_E_RANGE);
            }
        }
        assert_int_equal(ok + bad, 3000);
        assert_true(bad > 0 || t == KD_MSG_STATS);
    }
}

static void test_arguments(void **state)
{
    kd_msg_any m, out;
    char tiny[8];
    size_t len = 0, cut;
    (void)state;
    msg_sample(KD_MSG_GOAL_LINE, 21, &m, NULL);
    len = encode(KD_MSG_GOAL_LINE, &m);
    assert_int_equal(kd_msg_decode(KD_MSG_GOAL_LINE, NULL, len, &out, NULL, 0), KD_MSG_E_ARG);
    assert_int_equal(kd_msg_decode(KD_MSG_GOAL_LINE, buf, len, NULL, NULL, 0), KD_MSG_E_ARG);
    assert_int_equal(kd_msg_decode(KD_MSG_TYPE_COUNT, buf, len, &out, NULL, 0), KD_MSG_E_ARG);
    assert_int_equal(kd_msg_decode((kd_msg_type)-3, buf, len, &out, NULL, 0), KD_MSG_E_ARG);
    /* A small reason buffer is cut, NUL-terminated. */
    memset(tiny, 'z', sizeof tiny);
    assert_int_equal(kd_msg_decode(KD_MSG_GOAL_JOINT, buf, len, &out, tiny, sizeof tiny),
                     KD_MSG_E_FINGERPRINT);
    assert_int_equal(strlen(tiny), sizeof tiny - 1);

    /* Encoding into a buffer one byte short writes nothing past it. */
    for (cut = 0; cut < 2; cut++) {
        size_t need = kd_msg_type_info(KD_MSG_GOAL_PATH)->size, got = 7;
        msg_sample(KD_MSG_GOAL_PATH, 21, &m, NULL);
        memset(buf, 0x5a, sizeof buf);
        if (cut == 0) {
            assert_int_equal(kd_msg_encode(KD_MSG_GOAL_PATH, &m, buf, need - 1, &got),
                             KD_MSG_E_SPACE);
            assert_int_equal(got, 7);
            assert_int_equal(buf[0], 0x5a);
        } else {
            assert_int_equal(kd_msg_encode(KD_MSG_GOAL_PATH, &m, buf, need, &got), KD_MSG_OK);
            assert_int_equal(got, need);
            assert_int_equal(buf[need], 0x5a);
        }
    }
    assert_int_equal(kd_msg_encode(KD_MSG_GOAL_PATH, NULL, buf, sizeof buf, &len), KD_MSG_E_ARG);
    assert_int_equal(kd_msg_encode(KD_MSG_GOAL_PATH, &m, NULL, sizeof buf, &len), KD_MSG_E_ARG);
    assert_int_equal(kd_msg_encode(KD_MSG_GOAL_PATH, &m, buf, sizeof buf, NULL), KD_MSG_E_ARG);
    assert_int_equal(kd_msg_encode(KD_MSG_TYPE_COUNT, &m, buf, sizeof buf, &len), KD_MSG_E_ARG);
    assert_string_equal(kd_msg_status_str(KD_MSG_E_NONFINITE), "not finite");
    assert_string_equal(kd_msg_status_str((kd_msg_status)99), "unknown status");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sizes),
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_round_trip_status),
        cmocka_unit_test(test_status_refused),
        cmocka_unit_test(test_status_reason_bounds),
        cmocka_unit_test(test_truncated),
        cmocka_unit_test(test_oversized),
        cmocka_unit_test(test_wrong_fingerprint),
        cmocka_unit_test(test_identify),
        cmocka_unit_test(test_hostile_counts),
        cmocka_unit_test(test_nonfinite),
        cmocka_unit_test(test_unknown_enums),
        cmocka_unit_test(test_ranges),
        cmocka_unit_test(test_garbage),
        cmocka_unit_test(test_arguments),
    };
    kd_msg_init();
    return cmocka_run_group_tests_name("msg", tests, NULL, NULL);
}
