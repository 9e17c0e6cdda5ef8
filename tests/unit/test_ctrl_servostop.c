/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_servostop.c - how a servo stream stops (kinctl/ctrl.h): STOP,
 * PAUSE (and RESUME) and a replacement that stops first (a Lagrange
 * joint path) bring every joint to rest jerk-limited from its (q, qd, qdd),
 * as does the servo timeout (test_ctrl_servoshape.c), while ESTOP still
 * brakes at the acceleration limits from its first tick, as STOP does on a
 * chain without jerk limits. Streams of random speeds and
 * accelerations (a target pose moving by sums of sines) on the PUMA 560
 * and the Panda, their own limits per joint. Every tick of a stop is
 * checked: |qd| <= qd_max, |qdd| <= qdd_max and the jerk, the change of
 * qdd over one tick divided by dt (the first from the stream's last
 * tick), <= qddd_max, each with a relative slack of SLACK (SLACK_JERK for
 * the jerk); q moves by no more than the tick's qd, qdd and jerk allow
 * and qd by no more than qdd_max dt (continuity); the stop ends at rest
 * exactly. */
#include <math.h>
#include <string.h>

#include "testutil.h"

/* Rounding allowed in the per-tick checks (relative to the limit). A stop
 * lasts well under a second, so the jerk's rounding (2 t eps / dt of the
 * limit, test_ctrl_jerk.c) stays under 2.4e-4 in float; in double under
 * SLACK. */
#ifdef KC_REAL_FLOAT
#define SLACK 1e-4
#define SLACK_JERK 5e-4
#define CASES 20
#else
#define SLACK 1e-6
#define SLACK_JERK 1e-6
#define CASES 40
#endif

typedef struct harness {
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    kc_real q_prev[KC_MAX_JOINTS], qd_prev[KC_MAX_JOINTS], qdd_prev[KC_MAX_JOINTS];
    int check; /* 1: the ticks of a stop, checked against every limit */
    double worst_j;
    int events[8];
    kc_pose start;    /* the tool pose at the start */
    kt_stream stream; /* the servo stream, from start */
} harness;

static harness H; /* large: not on the stack */

/* The model's arm at rest at its start; no_jerk: its jerk limits infinite
 * (a chain without them). */
static void setup(kc_model model, int no_jerk)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, model, NULL), KC_OK);
    if (no_jerk)
        for (int j = 0; j < H.chain.n_joints; j++)
            H.chain.joints[j].limits.qddd_max = (kc_real)INFINITY;
    H.cfg = kc_ctrl_cfg_default();
    kc_real q0[KC_MAX_JOINTS];
    kt_start_q(&H.chain, model, q0);
    assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, q0), KC_OK);
    kc_fk_eval(&H.chain, q0, &H.start);
}

/* One tick; a stop's ticks checked against every limit and the last one. */
static void tick(const kc_goal *g, kc_ctrl_command cmd)
{
    kc_ctrl_input in = {g, cmd, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    double dt = (double)H.cfg.dt, eps = (double)KC_REAL_EPS;
    for (int j = 0; j < H.chain.n_joints; j++) {
        const kc_joint_limits *l = &H.chain.joints[j].limits;
        double q = (double)H.out.q[j], qd = (double)H.out.qd[j], qdd = (double)H.out.qdd[j];
        double qp = (double)H.q_prev[j], qdp = (double)H.qd_prev[j], qddp = (double)H.qdd_prev[j];
        if (H.check) {
            double rv = fabs(qd) / (double)l->qd_max, ra = fabs(qdd) / (double)l->qdd_max;
            double rj = fabs(qdd - qddp) / dt / (double)l->qddd_max;
            double dv = fabs(qd - qdp);
            /* Over a tick of jerk at most J from (qd, qdd): the exact
             * cubic's step, with the rounding of q. */
            double dq = fabs(q - qp), dq_max = fabs(qdp) * dt + fabs(qddp) * dt * dt / 2.0 +
                                                 (double)l->qddd_max * dt * dt * dt / 6.0;
            if (!(rv <= 1.0 + SLACK && ra <= 1.0 + SLACK && rj <= 1.0 + SLACK_JERK &&
                  dv <= (double)l->qdd_max * dt * (1.0 + SLACK) + SLACK * fabs(qdp) &&
                  dq <= dq_max * (1.0 + SLACK) + 4.0 * eps * (fabs(q) + 1.0)))
                fail_msg("cycle %ld joint %d (state %d): |qd| %.7g, |qdd| %.7g, jerk %.7g of the limits, "
                         "qd step %.4g, q step %.4g of %.4g",
                         (long)H.out.cycle, j, H.out.state, rv, ra, rj, dv, dq, dq_max);
            H.worst_j = fmax(H.worst_j, rj);
        }
        H.q_prev[j] = H.out.q[j];
        H.qd_prev[j] = H.out.qd[j];
        H.qdd_prev[j] = H.out.qdd[j];
    }
    for (int e = 0; e < H.out.n_events; e++)
        H.events[H.out.events[e].kind]++;
}

/* Streams goal id for n ticks. */
static void stream(int64_t id, int n)
{
    for (int k = 0; k < n; k++) {
        kc_goal g = kt_stream_next(&H.stream, id);
        tick(&g, KC_CMD_NONE);
        assert_int_equal(H.out.goal_id, id);
    }
    assert_int_equal(H.out.state, KC_CTRL_MOVING);
}

static int moving(void)
{
    for (int j = 0; j < H.chain.n_joints; j++)
        if (H.out.qd[j] != KC_R(0.0))
            return 1;
    return 0;
}

static void assert_at_rest(void)
{
    for (int j = 0; j < H.chain.n_joints; j++)
        assert_true(H.out.qd[j] == KC_R(0.0) && H.out.qdd[j] == KC_R(0.0));
}

/* The stop's first tick: the jerk-limited stop joint by joint is under
 * way (not the acceleration-limited one it falls back to); *spread gets
 * the largest difference of the joints' stop durations over the longest
 * (0: all end on the same tick). */
static void first_stop_tick(double *spread)
{
    assert_int_equal(H.out.state, KC_CTRL_STOPPING);
    assert_int_equal(H.ctrl.drive, KC_DRIVE_HALT);
    assert_int_equal(H.ctrl.jstop, 0);
    int64_t lo = INT64_MAX, hi = 0;
    for (int j = 0; j < H.chain.n_joints; j++) {
        int64_t t = H.ctrl.plan.halt[j].ticks;
        if (t > 0) {
            lo = t < lo ? t : lo;
            hi = t > hi ? t : hi;
        }
    }
    *spread = hi > 0 ? (double)(hi - lo) / (double)hi : 0.0;
}

/* STOP, PAUSE + RESUME, and replacement by a joint path that stops
 * first, each from a random moment of a random stream. */
static void test_stops_jerk_limited(void **state)
{
    (void)state;
    kc_model models[2] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};
    for (int m = 0; m < 2; m++) {
        setup(models[m], 0);
        kt_rng r = kt_rng_make(1901 + (uint64_t)m);
        int n = H.chain.n_joints, stops = 0, longest = 0, together = 0;
        double spread = 0.0, worst_spread = 0.0;
        for (int c = 0; c < CASES; c++) {
            int64_t id = 100 + c;
            kt_stream_init(&H.stream, &r, &H.start, (double)H.cfg.dt);
            stream(id, 200 + (int)kt_uniform(&r, 0.0, 400.0));
            int k = 0, mode = c % 4;
            H.check = 1;
            if (mode == 0) {
                kc_goal g = kt_stream_next(&H.stream, id);
                tick(&g, KC_CMD_STOP);
                first_stop_tick(&spread);
                for (; k < 10000 && H.out.state != KC_CTRL_IDLE; k++)
                    tick(NULL, KC_CMD_NONE);
                assert_int_equal(H.out.state, KC_CTRL_IDLE);
                assert_true(kt_has_event(&H.out, KC_EVENT_ABORTED, id));
                assert_at_rest();
            } else if (mode == 1) {
                tick(NULL, KC_CMD_PAUSE);
                first_stop_tick(&spread);
                for (; k < 10000 && H.out.state != KC_CTRL_PAUSED; k++)
                    tick(NULL, KC_CMD_NONE);
                assert_int_equal(H.out.state, KC_CTRL_PAUSED);
                assert_at_rest();
                /* Held, then resumed: the stream takes over again (its own
                 * law, not a stop: the jerk is not judged), and stops. */
                H.check = 0;
                for (int i = 0; i < 20; i++)
                    tick(NULL, KC_CMD_NONE);
                assert_int_equal(H.out.state, KC_CTRL_PAUSED);
                tick(NULL, KC_CMD_RESUME);
                stream(id, 100);
                assert_true(moving());
                H.check = 1;
                kc_goal g = kt_stream_next(&H.stream, id);
                tick(&g, KC_CMD_STOP);
                first_stop_tick(&spread);
                for (; k < 10000 && H.out.state != KC_CTRL_IDLE; k++)
                    tick(NULL, KC_CMD_NONE);
                assert_int_equal(H.out.state, KC_CTRL_IDLE);
                assert_at_rest();
            } else {
                /* A replacement that stops first: a joint path through
                 * two knots near the joints now by Lagrange's polynomial
                 * under the trapezoid's law (it does not start at rest,
                 * and its ramps step tau'': not superposed; a line takes
                 * over without stopping, test_ctrl_servoblend.c). */
                kc_goal g;
                memset(&g, 0, sizeof g);
                g.id = 1000 + c;
                g.kind = KC_GOAL_PATH;
                g.vel_scale = g.acc_scale = KC_R(1.0);
                g.method = KC_PATH_LAGRANGE;
                g.profile = KC_GOAL_PROFILE_TRAPEZOID;
                g.n_points = 2;
                for (int j = 0; j < n; j++) {
                    const kc_joint_limits *l = &H.chain.joints[j].limits;
                    kc_real mid = (l->q_min + l->q_max) / KC_R(2.0);
                    kc_real to = H.out.q[j] + (mid > H.out.q[j] ? KC_R(0.1) : KC_R(-0.1));
                    g.points[0][j] = to;
                    g.points[1][j] = H.out.q[j];
                }
                g.replace = 1;
                tick(&g, KC_CMD_NONE);
                int stop_first = 0;
                for (int e = 0; e < H.out.n_events; e++)
                    if (H.out.events[e].kind == KC_EVENT_ACCEPTED && H.out.events[e].goal_id == g.id)
                        stop_first = H.out.events[e].reason == KC_REASON_STOP_FIRST;
                assert_true(stop_first);
                first_stop_tick(&spread);
                for (; k < 10000 && !kt_has_event(&H.out, KC_EVENT_PREEMPTED, id); k++)
                    tick(NULL, KC_CMD_NONE);
                assert_true(kt_has_event(&H.out, KC_EVENT_PREEMPTED, id));
                assert_at_rest();
                H.check = 0; /* from here on the new goal's own law */
                tick(NULL, KC_CMD_NONE);
                assert_int_equal(H.out.goal_id, g.id);
                assert_int_equal(H.events[KC_EVENT_PREEMPTED], c / 4 * 2 + mode - 1); /* the servo goal's */
                int done = 0;
                for (int i = 0; i < 20000 && !done; i++) {
                    tick(NULL, KC_CMD_NONE);
                    done = kt_has_event(&H.out, KC_EVENT_COMPLETED, g.id);
                }
                assert_true(done);
            }
            H.check = 0;
            assert_int_equal(H.events[KC_EVENT_FAULT], 0);
            stops++;
            together += spread == 0.0;
            worst_spread = fmax(worst_spread, spread);
            longest = k > longest ? k : longest;
            /* Back to the start for the next stream. */
            kc_real q0[KC_MAX_JOINTS];
            kt_start_q(&H.chain, models[m], q0);
            kc_goal home = kt_joint_goal(5000 + c, q0, n);
            tick(&home, KC_CMD_NONE);
            for (int i = 0; i < 20000 && !kt_has_event(&H.out, KC_EVENT_COMPLETED, home.id); i++)
                tick(NULL, KC_CMD_NONE);
            assert_int_equal(H.out.state, KC_CTRL_IDLE);
        }
        print_message("%s: %d servo stops, the longest %d ticks, jerk at most %.6f of the limit; joints ending "
                      "together in %d, the widest spread of their stop durations %.3f of the longest (%s)\n",
                      kc_model_name(models[m]), stops, longest, H.worst_j, together, worst_spread, KC_REAL_NAME);
        assert_true(H.worst_j > 0.5); /* the stops do use the jerk they are allowed */
    }
}

/* ESTOP brakes at the acceleration limits, and so does STOP on a chain
 * without jerk limits (no jerk-limited stop to plan):
 * on their first tick some moving joint's qdd is at its limit, reached by
 * a jump beyond the model's jerk limit (more than 1.5 qddd_max dt: the Panda's qdd_max
 * is 2 qddd_max dt at 1 kHz, the PUMA's 100). */
static void test_estop_acceleration_limited(void **state)
{
    (void)state;
    kc_model models[2] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};
    static kc_chain ref;
    for (int m = 0; m < 2; m++) {
        assert_int_equal(kc_chain_init_model(&ref, models[m], NULL), KC_OK);
        for (int which = 0; which < 3; which += 2) { /* 1 was the servo timeout's, now jerk-limited */
            /* 2: STOP where the chain has no jerk limits (no jerk-limited
             * stop to plan: today's stop) */
            setup(models[m], which == 2);
            kt_rng r = kt_rng_make(1911 + (uint64_t)(2 * m + which));
            kt_stream_init(&H.stream, &r, &H.start, (double)H.cfg.dt);
            /* A twist of random direction moving the target on at
             * 0.05 m/s: the arm moving steadily when it stops. */
            kc_goal g = kt_stream_next(&H.stream, 7);
            kc_vec3 u = kt_rand_unit(&r);
            g.servo_twist = 1;
            for (int k = 0; k < 3; k++)
                g.twist[k] = KC_R(0.05) * u.v[k];
            for (int k = 0; k < 1000; k++)
                tick(&g, KC_CMD_NONE);
            kc_real before[KC_MAX_JOINTS]; /* qdd of the tick before the stop's first */
            memcpy(before, H.out.qdd, sizeof before);
            if (which == 0) {
                tick(NULL, KC_CMD_ESTOP);
                assert_int_equal(H.out.state, KC_CTRL_ESTOP);
            } else if (which == 2) {
                tick(NULL, KC_CMD_STOP);
                assert_int_equal(H.out.state, KC_CTRL_STOPPING);
                assert_int_equal(H.ctrl.jstop, 1);
            }
            int at_limit = 0;
            for (int j = 0; j < H.chain.n_joints; j++) {
                double a = (double)H.chain.joints[j].limits.qdd_max;
                double jm = (double)ref.joints[j].limits.qddd_max; /* the model's, also where H's is infinite */
                double qdd = (double)H.out.qdd[j];
                if (H.out.qd[j] != KC_R(0.0) && fabs(qdd) >= a * (1.0 - SLACK) &&
                    fabs(qdd - (double)before[j]) / (double)H.cfg.dt > 1.5 * jm)
                    at_limit = 1;
            }
            assert_true(at_limit);
            for (int k = 0; k < 10000 && moving(); k++)
                tick(NULL, KC_CMD_NONE);
            assert_at_rest();
            if (which == 2) {
                assert_int_equal(H.out.state, KC_CTRL_IDLE);
                assert_int_equal(H.events[KC_EVENT_ABORTED], 1);
                assert_int_equal(H.out.events[0].reason, KC_REASON_NONE);
            }
        }
    }
}

/* A steady stream (a constant twist, the joints' accelerations small)
 * stops synchronised by phase: the moving joints' stops end on ticks at
 * most a quarter as far apart as each joint's own fastest stop
 * (kc_scurve_plan_stop at its own limits, computed here) would (seen: on
 * the PUMA at most 2 ticks apart in stops of 70-134 ticks in double, 7 in
 * float, whose stream's qdd is noisier, where the own stops spread over
 * 37-79 ticks; on the Panda the same tick, own stops 3-14 apart). */
static void test_steady_stream_stops_together(void **state)
{
    (void)state;
    kc_model models[2] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};
    for (int m = 0; m < 2; m++) {
        setup(models[m], 0);
        kt_rng r = kt_rng_make(1921 + (uint64_t)m);
        for (int c = 0; c < 4; c++) {
            kt_stream_init(&H.stream, &r, &H.start, (double)H.cfg.dt);
            kc_goal g = kt_stream_next(&H.stream, 300 + c);
            kc_vec3 u = kt_rand_unit(&r);
            g.servo_twist = 1;
            for (int k = 0; k < 3; k++)
                g.twist[k] = KC_R(0.05) * u.v[k];
            for (int k = 0; k < 1000; k++)
                tick(&g, KC_CMD_NONE);
            /* Each joint's own fastest stop from the stream's last state. */
            int64_t own_lo = INT64_MAX, own_hi = 0;
            for (int j = 0; j < H.chain.n_joints; j++) {
                const kc_joint_limits *l = &H.chain.joints[j].limits;
                kc_scurve own;
                assert_int_equal(kc_scurve_plan_stop(&own, H.out.q[j], H.out.qd[j], H.out.qdd[j], l->qdd_max,
                                                     l->qddd_max, H.cfg.dt),
                                 KC_OK);
                if (own.ticks > 0) {
                    own_lo = own.ticks < own_lo ? own.ticks : own_lo;
                    own_hi = own.ticks > own_hi ? own.ticks : own_hi;
                }
            }
            H.check = 1;
            tick(NULL, KC_CMD_STOP);
            double spread;
            first_stop_tick(&spread);
            int64_t lo = INT64_MAX, hi = 0;
            for (int j = 0; j < H.chain.n_joints; j++) {
                int64_t t = H.ctrl.plan.halt[j].ticks;
                if (t > 0) {
                    lo = t < lo ? t : lo;
                    hi = t > hi ? t : hi;
                }
            }
            print_message("%s: a steady stream's stop: the joints end after %ld..%ld ticks (each at its own "
                          "limits: %ld..%ld)\n",
                          kc_model_name(models[m]), (long)lo, (long)hi, (long)own_lo, (long)own_hi);
            assert_true(4 * (hi - lo) <= own_hi - own_lo);
            for (int k = 0; k < 10000 && H.out.state != KC_CTRL_IDLE; k++)
                tick(NULL, KC_CMD_NONE);
            assert_int_equal(H.out.state, KC_CTRL_IDLE);
            assert_at_rest();
            H.check = 0;
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stops_jerk_limited),
        cmocka_unit_test(test_estop_acceleration_limited),
        cmocka_unit_test(test_steady_stream_stops_together),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl_servostop");
    return rc;
}
