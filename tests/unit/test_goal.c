/* SPDX-License-Identifier: BSD-3-Clause */
/* test_goal.c - the daemon's goal conversion (daemon/goal.h: a wire message
 * in, a kc_goal out, for each goal kind, and what it cannot convert), the
 * goal_id read from a raw datagram (daemon/msg.h kd_msg_goal_id), and the
 * rejection text formed from the core's verdict (daemon/reject.h), against
 * the texts clients see. Built in the daemon's precision. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "goal.h"
#include "msg.h"
#include "reject.h"

static kd_config CFG; /* the arm only: what a rejection names */
static kd_msg_any MSG;

static const double Q0[6] = {0.1, 0.8, -2.4, 0.1, 0.6, 0.2};

static void setup(void)
{
    memset(&CFG, 0, sizeof CFG);
    assert_int_equal(kc_chain_init_model(&CFG.chain, KC_MODEL_PUMA560, NULL), KC_OK);
    memset(&MSG, 0, sizeof MSG);
    kd_msg_init();
}

/* Converts MSG of type; returns what kd_goal_from_msg returns. */
static int convert(kd_msg_type type, kc_goal *g, int64_t *timeout_ns, kc_verdict *v)
{
    return kd_goal_from_msg(type, &MSG, 1.0, g, timeout_ns, v);
}

/* The text and code a refused goal is answered with. */
static void assert_rejection(const kc_goal *g, const kc_verdict *v, kc_status code, const char *text)
{
    kd_reject rej;
    kd_reject_verdict(&rej, &CFG, g, v);
    assert_int_equal(rej.code, code);
    assert_string_equal(rej.text, text);
}

static void test_joint(void **state)
{
    (void)state;
    setup();
    kinctl_goal_joint_t *m = &MSG.goal_joint;
    m->goal_id = 41;
    m->mode = KINCTL_GOAL_JOINT_T_REPLACE;
    m->n = 6;
    memcpy(m->q, Q0, sizeof Q0);
    m->vel_scale = 0.0; /* 0: the whole limit */
    m->acc_scale = 0.5;
    kc_goal g;
    kc_verdict v;
    int64_t timeout_ns = -1;
    assert_int_equal(convert(KD_MSG_GOAL_JOINT, &g, &timeout_ns, &v), 0);
    assert_int_equal(g.id, 41);
    assert_int_equal(g.kind, KC_GOAL_JOINT);
    assert_int_equal(g.replace, 1);
    assert_int_equal(g.dim, 6);
    for (int j = 0; j < 6; j++)
        assert_true(g.q[j] == (kc_real)Q0[j]);
    assert_true(g.vel_scale == KC_R(1.0) && g.acc_scale == KC_R(0.5));
    assert_int_equal(timeout_ns, 0);
    assert_int_equal(kc_ctrl_goal_check(&CFG.chain, &g, &v), KC_OK);

    /* the count the client gave reaches the core, which refuses it */
    m->n = 5;
    m->mode = KINCTL_GOAL_JOINT_T_QUEUE;
    assert_int_equal(convert(KD_MSG_GOAL_JOINT, &g, &timeout_ns, &v), 0);
    assert_int_equal(g.dim, 5);
    assert_int_equal(g.replace, 0);
    assert_int_equal(kc_ctrl_goal_check(&CFG.chain, &g, &v), KC_E_ARG);
    assert_rejection(&g, &v, KC_E_ARG, "joint_count: goal_joint_t.n = 5, the arm has 6 joints");

    /* a target outside its limits: the joint, its value and its limits */
    m->n = 6;
    m->q[3] = (double)CFG.chain.joints[3].limits.q_max + 0.125;
    assert_int_equal(convert(KD_MSG_GOAL_JOINT, &g, &timeout_ns, &v), 0);
    assert_int_equal(kc_ctrl_goal_check(&CFG.chain, &g, &v), KC_E_ARG);
    char want[KD_REASON_TEXT];
    snprintf(want, sizeof want, "joint_limit: goal_joint_t.q[3] = %.9g is outside joint 4's limits [%.9g, %.9g]",
             m->q[3], (double)CFG.chain.joints[3].limits.q_min, (double)CFG.chain.joints[3].limits.q_max);
    assert_rejection(&g, &v, KC_E_LIMIT, want);
}

/* Rz(a) as the quaternion (w x y z) and as the matrix it must become. */
static void rz(double a, double *q4, double R[3][3])
{
    q4[0] = cos(a / 2);
    q4[1] = 0;
    q4[2] = 0;
    q4[3] = sin(a / 2);
    double c = cos(a), s = sin(a);
    double M[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}};
    memcpy(R, M, sizeof M);
}

static void assert_rotation(const kc_mat3 *R, double M[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            assert_true(fabs((double)R->m[i][j] - M[i][j]) < 1e-6);
}

static void test_line_and_arc(void **state)
{
    (void)state;
    setup();
    double R[3][3];
    kinctl_goal_line_t *m = &MSG.goal_line;
    m->goal_id = 7;
    m->position[0] = 0.4;
    m->position[1] = -0.1;
    m->position[2] = 0.3;
    rz(0.3, m->orientation, R);
    m->speed = 0.2;
    m->accel = 0.6;
    m->angular_speed = 0.7;
    m->angular_accel = 2.0;
    m->jerk = 3.0;
    m->angular_jerk = 20.0;
    m->orientation_method = KINCTL_GOAL_LINE_T_SLERP;
    m->vel_scale = 0.25;
    m->acc_scale = 1.0;
    kc_goal g;
    kc_verdict v;
    int64_t timeout_ns;
    assert_int_equal(convert(KD_MSG_GOAL_LINE, &g, &timeout_ns, &v), 0);
    assert_int_equal(g.kind, KC_GOAL_LINE);
    assert_int_equal(g.id, 7);
    assert_true(g.pose.t.v[0] == (kc_real)0.4 && g.pose.t.v[1] == (kc_real)-0.1 && g.pose.t.v[2] == (kc_real)0.3);
    assert_rotation(&g.pose.R, R);
    assert_int_equal(g.orient, KC_INTERP_SLERP);
    assert_true(g.speed == (kc_real)0.2 && g.accel == (kc_real)0.6);
    assert_true(g.omega == (kc_real)0.7 && g.alpha == (kc_real)2.0);
    assert_true(g.jerk == (kc_real)3.0 && g.angular_jerk == (kc_real)20.0);
    assert_true(g.vel_scale == (kc_real)0.25 && g.acc_scale == KC_R(1.0));

    /* within 1e-3 of unit norm: normalised */
    for (int i = 0; i < 4; i++)
        m->orientation[i] *= 1.0005;
    assert_int_equal(convert(KD_MSG_GOAL_LINE, &g, &timeout_ns, &v), 0);
    assert_rotation(&g.pose.R, R);
    assert_true(kc_mat3_rotation_error(&g.pose.R) <= KC_TOL_ORTHONORMAL);
    /* farther: not converted, the norm named */
    for (int i = 0; i < 4; i++)
        m->orientation[i] *= 2.0 / 1.0005;
    assert_int_equal(convert(KD_MSG_GOAL_LINE, &g, &timeout_ns, &v), -1);
    assert_int_equal(g.id, 7);
    assert_int_equal(v.status, KC_E_ARG);
    assert_int_equal(v.reason, KC_REASON_BAD_GOAL);
    assert_int_equal(v.field, KC_FIELD_ORIENTATION);
    assert_true(fabs((double)v.value - 2.0) < 1e-12);
    assert_rejection(&g, &v, KC_E_ARG, "bad_goal: goal_line_t.orientation is not a unit quaternion (norm 2)");

    kinctl_goal_arc_t *a = &MSG.goal_arc;
    memset(a, 0, sizeof *a);
    a->goal_id = 8;
    a->mode = KINCTL_GOAL_ARC_T_REPLACE;
    a->via[0] = 0.5;
    a->via[1] = 0.1;
    a->via[2] = 0.2;
    a->position[0] = 0.4;
    a->position[1] = 0.2;
    a->position[2] = 0.2;
    rz(-0.5, a->orientation, R);
    a->speed = 0.1;
    assert_int_equal(convert(KD_MSG_GOAL_ARC, &g, &timeout_ns, &v), 0);
    assert_int_equal(g.kind, KC_GOAL_ARC);
    assert_int_equal(g.replace, 1);
    assert_true(g.via.v[0] == (kc_real)0.5 && g.via.v[1] == (kc_real)0.1 && g.via.v[2] == (kc_real)0.2);
    assert_true(g.pose.t.v[1] == (kc_real)0.2);
    assert_rotation(&g.pose.R, R);
    assert_true(g.vel_scale == KC_R(1.0) && g.acc_scale == KC_R(1.0)); /* 0: the whole limit */
    a->orientation[0] = 0.0; /* norm sin(0.25) */
    assert_int_equal(convert(KD_MSG_GOAL_ARC, &g, &timeout_ns, &v), -1);
    assert_int_equal(v.field, KC_FIELD_ORIENTATION);
    char want[KD_REASON_TEXT];
    snprintf(want, sizeof want, "bad_goal: goal_arc_t.orientation is not a unit quaternion (norm %.9g)",
             fabs(sin(-0.25)));
    assert_rejection(&g, &v, KC_E_ARG, want);
}

static void test_path(void **state)
{
    (void)state;
    setup();
    kinctl_goal_path_t *m = &MSG.goal_path;
    m->goal_id = 9;
    m->space = KINCTL_GOAL_PATH_T_JOINT;
    m->method = KINCTL_GOAL_PATH_T_QUINTIC;
    m->blend_shape = KINCTL_GOAL_PATH_T_BLEND_PARABOLIC;
    m->spline_ends = KINCTL_GOAL_PATH_T_SPLINE_NATURAL;
    m->n_points = 3;
    m->dim = 6;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 6; j++)
            m->points[i][j] = Q0[j] + 0.05 * (i + 1);
    m->has_times = 1;
    m->times[0] = 0.5;
    m->times[1] = 1.0;
    m->times[2] = 1.75;
    m->blend_time = 0.1;
    m->speed = 0.3;
    m->accel = 0.9;
    kc_goal g;
    kc_verdict v;
    int64_t timeout_ns;
    assert_int_equal(convert(KD_MSG_GOAL_PATH, &g, &timeout_ns, &v), 0);
    assert_int_equal(g.kind, KC_GOAL_PATH);
    assert_int_equal(g.method, KC_PATH_QUINTIC);
    assert_int_equal(g.blend, KC_PATH_BLEND_PARABOLIC);
    assert_int_equal(g.spline_end, KC_PATH_SPLINE_NATURAL);
    assert_int_equal(g.n_points, 3);
    assert_int_equal(g.dim, 6);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 6; j++)
            assert_true(g.points[i][j] == (kc_real)m->points[i][j]);
    assert_int_equal(g.has_times, 1);
    assert_true(g.times[2] == (kc_real)1.75 && g.blend_time == (kc_real)0.1);
    assert_true(g.speed == (kc_real)0.3 && g.accel == (kc_real)0.9);
    assert_int_equal(kc_ctrl_goal_check(&CFG.chain, &g, &v), KC_OK);
    /* the other methods' codes */
    const int8_t wire[4] = {KINCTL_GOAL_PATH_T_BLEND, KINCTL_GOAL_PATH_T_SPLINE, KINCTL_GOAL_PATH_T_QUINTIC,
                            KINCTL_GOAL_PATH_T_LAGRANGE};
    const kc_path_method core[4] = {KC_PATH_BLEND, KC_PATH_SPLINE, KC_PATH_QUINTIC, KC_PATH_LAGRANGE};
    for (int k = 0; k < 4; k++) {
        m->method = wire[k];
        assert_int_equal(convert(KD_MSG_GOAL_PATH, &g, &timeout_ns, &v), 0);
        assert_int_equal(g.method, core[k]);
    }

    /* a knot outside its joint's limits: the knot, the joint */
    m->points[1][4] = (double)CFG.chain.joints[4].limits.q_min - 0.5;
    assert_int_equal(convert(KD_MSG_GOAL_PATH, &g, &timeout_ns, &v), 0);
    assert_int_equal(kc_ctrl_goal_check(&CFG.chain, &g, &v), KC_E_ARG);
    char want[KD_REASON_TEXT];
    snprintf(want, sizeof want,
             "joint_limit: goal_path_t.points[1][4] = %.9g is outside joint 5's limits [%.9g, %.9g]", m->points[1][4],
             (double)CFG.chain.joints[4].limits.q_min, (double)CFG.chain.joints[4].limits.q_max);
    assert_rejection(&g, &v, KC_E_LIMIT, want);
    /* joint count */
    m->dim = 4;
    assert_int_equal(convert(KD_MSG_GOAL_PATH, &g, &timeout_ns, &v), 0);
    assert_int_equal(kc_ctrl_goal_check(&CFG.chain, &g, &v), KC_E_ARG);
    assert_rejection(&g, &v, KC_E_ARG, "joint_count: goal_path_t.dim = 4, the arm has 6 joints");
    /* as many knots as the wire holds, which is as many as a goal takes
     * (one number: goal.c checks it at compile time) */
    m->dim = 6;
    m->n_points = KINCTL_GOAL_PATH_T_MAX_POINTS;
    m->has_times = 0;
    for (int i = 0; i < KINCTL_GOAL_PATH_T_MAX_POINTS; i++)
        for (int j = 0; j < 6; j++)
            m->points[i][j] = 0.01 * (i + 1) * (j % 2 ? -1.0 : 1.0);
    assert_int_equal(convert(KD_MSG_GOAL_PATH, &g, &timeout_ns, &v), 0);
    assert_int_equal(g.n_points, KINCTL_GOAL_PATH_T_MAX_POINTS);
    assert_int_equal(kc_ctrl_goal_check(&CFG.chain, &g, &v), KC_OK);
    assert_int_equal(KINCTL_GOAL_PATH_T_MAX_POINTS, KC_PATH_MAX_KNOTS - 1);
    m->n_points = 0;
    assert_int_equal(convert(KD_MSG_GOAL_PATH, &g, &timeout_ns, &v), 0);
    assert_int_equal(kc_ctrl_goal_check(&CFG.chain, &g, &v), KC_E_ARG);
    snprintf(want, sizeof want, "bad_goal: goal_path_t.n_points = 0, expected 1 .. %d", KC_PATH_MAX_KNOTS - 1);
    assert_rejection(&g, &v, KC_E_ARG, want);

    /* Cartesian: x y z qw qx qy qz a knot */
    memset(m, 0, sizeof *m);
    m->goal_id = 10;
    m->space = KINCTL_GOAL_PATH_T_CARTESIAN;
    m->dim = KINCTL_GOAL_PATH_T_CARTESIAN_DIM;
    m->n_points = 2;
    for (int i = 0; i < 2; i++) {
        m->points[i][0] = 0.4 + 0.1 * i;
        m->points[i][3] = 1.0;
    }
    assert_int_equal(convert(KD_MSG_GOAL_PATH, &g, &timeout_ns, &v), 0);
    assert_int_equal(g.kind, KC_GOAL_PATH_CART);
    assert_int_equal(g.dim, 7);
    assert_int_equal(g.method, KC_PATH_BLEND);
    assert_int_equal(g.has_times, 0);
    assert_true(g.points[1][0] == (kc_real)0.5 && g.points[1][3] == KC_R(1.0));
    assert_int_equal(kc_ctrl_goal_check(&CFG.chain, &g, &v), KC_OK);
}

static void test_servo(void **state)
{
    (void)state;
    setup();
    double R[3][3];
    kinctl_goal_servo_t *m = &MSG.goal_servo;
    m->goal_id = 11;
    m->kind = KINCTL_GOAL_SERVO_T_POSE;
    m->position[2] = 0.5;
    rz(1.0, m->orientation, R);
    m->timeout_us = 50000;
    kc_goal g;
    kc_verdict v;
    int64_t timeout_ns;
    assert_int_equal(convert(KD_MSG_GOAL_SERVO, &g, &timeout_ns, &v), 0);
    assert_int_equal(g.kind, KC_GOAL_SERVO);
    assert_int_equal(g.servo_twist, 0);
    assert_true(g.pose.t.v[2] == (kc_real)0.5);
    assert_rotation(&g.pose.R, R);
    assert_int_equal(timeout_ns, 50000000);
    assert_true(g.vel_scale == KC_R(1.0) && g.acc_scale == KC_R(1.0));
    /* a twist stream; a timeout above the cap is capped (1 s here) */
    m->kind = KINCTL_GOAL_SERVO_T_TWIST;
    for (int i = 0; i < 6; i++)
        m->twist[i] = 0.01 * (i + 1);
    m->orientation[0] = 0.0; /* unused by a twist */
    m->timeout_us = 5000000;
    assert_int_equal(convert(KD_MSG_GOAL_SERVO, &g, &timeout_ns, &v), 0);
    assert_int_equal(g.servo_twist, 1);
    for (int i = 0; i < 6; i++)
        assert_true(g.twist[i] == (kc_real)(0.01 * (i + 1)));
    assert_int_equal(timeout_ns, 1000000000);
    /* a pose with a zero quaternion */
    m->kind = KINCTL_GOAL_SERVO_T_POSE;
    m->orientation[1] = m->orientation[2] = m->orientation[3] = 0.0;
    assert_int_equal(convert(KD_MSG_GOAL_SERVO, &g, &timeout_ns, &v), -1);
    assert_rejection(&g, &v, KC_E_ARG, "bad_goal: goal_servo_t.orientation is not a unit quaternion (norm 0)");
}

/* Not a goal type: nothing to convert. */
static void test_not_a_goal(void **state)
{
    (void)state;
    setup();
    kc_goal g;
    kc_verdict v;
    int64_t timeout_ns;
    assert_int_equal(convert(KD_MSG_COMMAND, &g, &timeout_ns, &v), -1);
    assert_int_equal(v.status, KC_E_ARG);
    assert_int_equal(v.reason, KC_REASON_BAD_GOAL);
}

/* The goal_id of a raw datagram, read where msg.c lays it out. */
static void test_goal_id_of_datagram(void **state)
{
    (void)state;
    setup();
    unsigned char buf[KD_MSG_MAX_SIZE];
    size_t len = 0;
    MSG.goal_joint.goal_id = -1234567890123LL;
    MSG.goal_joint.n = 6;
    assert_int_equal(kd_msg_encode(KD_MSG_GOAL_JOINT, &MSG.goal_joint, buf, sizeof buf, &len), KD_MSG_OK);
    assert_true(kd_msg_goal_id(KD_MSG_GOAL_JOINT, buf, len) == -1234567890123LL);
    /* whatever else is wrong with it: only 24 bytes needed */
    assert_true(kd_msg_goal_id(KD_MSG_GOAL_JOINT, buf, 24) == -1234567890123LL);
    assert_true(kd_msg_goal_id(KD_MSG_GOAL_JOINT, buf, 23) == 0);
    assert_true(kd_msg_goal_id(KD_MSG_COMMAND, buf, len) == 0);
    assert_true(kd_msg_goal_id(KD_MSG_GOAL_JOINT, NULL, len) == 0);
    memset(&MSG, 0, sizeof MSG);
    MSG.goal_path.goal_id = 77;
    MSG.goal_path.n_points = 1;
    MSG.goal_path.dim = 6;
    assert_int_equal(kd_msg_encode(KD_MSG_GOAL_PATH, &MSG.goal_path, buf, sizeof buf, &len), KD_MSG_OK);
    assert_true(kd_msg_goal_id(KD_MSG_GOAL_PATH, buf, len) == 77);
}

/* The dry run's verdicts as clients read them. */
static void test_dry_run_texts(void **state)
{
    (void)state;
    setup();
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.kind = KC_GOAL_LINE;
    kc_verdict v;
    memset(&v, 0, sizeof v);
    v.status = KC_E_UNREACHABLE;
    v.reason = KC_REASON_ZONE;
    v.zone = 0;
    v.volume = 1;
    v.distance = KC_R(0.0125);
    v.where = KC_R(0.25);
    snprintf(CFG.zone_names[0], sizeof CFG.zone_names[0], "table");
    char want[KD_REASON_TEXT];
    snprintf(want, sizeof want, "zone: %s: zone \"table\" and link volume 2 (frame %d) (0.0125 m, at 0.25)",
             kc_ctrl_reason_str(KC_REASON_ZONE), CFG.chain.n_volumes > 1 ? CFG.chain.volumes[1].frame + 1 : 0);
    assert_rejection(&g, &v, KC_E_LIMIT, want);
    v.reason = KC_REASON_UNREACHABLE;
    v.where = KC_R(0.5);
    snprintf(want, sizeof want, "unreachable: %s (%s at 0.5)", kc_ctrl_reason_str(KC_REASON_UNREACHABLE),
             kc_status_str(KC_E_UNREACHABLE));
    assert_rejection(&g, &v, KC_E_UNREACHABLE, want);
    v.status = KC_E_ARG;
    v.reason = KC_REASON_PLAN;
    snprintf(want, sizeof want, "plan: %s (%s)", kc_ctrl_reason_str(KC_REASON_PLAN), kc_status_str(KC_E_ARG));
    assert_rejection(&g, &v, KC_E_ARG, want);
    v.status = KC_E_CAPACITY;
    v.reason = KC_REASON_QUEUE_FULL;
    v.value = (kc_real)KC_CTRL_QUEUE_MAX;
    snprintf(want, sizeof want, "queue_full: the controller's goal queue (%d goals) is full", KC_CTRL_QUEUE_MAX);
    assert_rejection(&g, &v, KC_E_CAPACITY, want);
    /* The joints' jerk: what the search judged it at, and whether the
     * budget cut it short. */
    kd_reject rej;
    CFG.check_budget_s = 0.5;
    kd_reject_jerk(&rej, &CFG, 31.4, 1.0, 0, 1);
    assert_string_equal(rej.text, "jerk: its joints' jerk would reach 31.4 times their limits (qddd); "
                                  "controller.check_budget_ms = 500 ran out before a slower one was judged");
    kd_reject_jerk(&rej, &CFG, 1.3, 0.233, 1, 0);
    assert_string_equal(rej.text, "jerk: its joints' jerk would reach 1.3 times their limits (qddd) at 0.233 of its "
                                  "speed, stopping the motion it replaces first");
    v.status = KC_E_LIMIT;
    v.reason = KD_REASON_JERK;
    v.jerk = KC_R(2.5);
    assert_rejection(&g, &v, KC_E_LIMIT, "jerk: its joints' jerk would reach 2.5 times their limits (qddd)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_joint),         cmocka_unit_test(test_line_and_arc),
        cmocka_unit_test(test_path),          cmocka_unit_test(test_servo),
        cmocka_unit_test(test_not_a_goal),    cmocka_unit_test(test_goal_id_of_datagram),
        cmocka_unit_test(test_dry_run_texts),
    };
    return cmocka_run_group_tests_name("goal (daemon)", tests, NULL, NULL);
}
