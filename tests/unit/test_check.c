/* SPDX-License-Identifier: BSD-3-Clause */
/* test_check.c - a goal judged once (kinctl/ctrl.h kc_verdict,
 * kinctl/check.h): every reason of the goal check names the field, knot
 * and joint at fault; the dry run names the tick, where along the motion,
 * and the zone pair; a kc_check judges each queued goal from where the one
 * before it ends, follows a real controller's ticks, and refuses a goal
 * for a full queue. */
#include <math.h>
#include <string.h>

#include "testutil.h"

static kc_chain CHAIN;
static kc_ctrl_cfg CFG;
static kc_zone_set ZONES;
static kc_check CHECK;
static kc_ctrl CTRL;

static void setup(void)
{
    assert_int_equal(kc_chain_init_model(&CHAIN, KC_MODEL_PUMA560, NULL), KC_OK);
    kc_zone_set_init(&ZONES);
    CFG = kc_ctrl_cfg_default();
    CFG.zones = NULL;
}

static kc_goal joint_goal(int64_t id, const kc_real *q)
{
    kc_goal g = kt_joint_goal(id, q, 6);
    g.dim = 6;
    return g;
}

/* A joint path through KT_PUMA_Q0 + (i + 1) 0.1 rad on every joint. */
static kc_goal joint_path(int64_t id, int n_points)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = KC_GOAL_PATH;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.method = KC_PATH_SPLINE;
    g.dim = 6;
    g.n_points = n_points;
    for (int i = 0; i < n_points && i < KC_PATH_MAX_KNOTS - 1; i++)
        for (int j = 0; j < 6; j++)
            g.points[i][j] = KT_PUMA_Q0[j] + KC_R(0.1) * (kc_real)(i + 1);
    return g;
}

static void assert_names(const kc_verdict *v, kc_ctrl_reason reason, kc_goal_field field, int point, int joint)
{
    assert_int_equal(v->status, KC_E_ARG);
    assert_int_equal(v->reason, reason);
    assert_int_equal(v->field, field);
    assert_int_equal(v->point, point);
    assert_int_equal(v->joint, joint);
    /* the goal check judges no motion */
    assert_int_equal(v->tick, -1);
    assert_int_equal(v->zone, -1);
    assert_int_equal(v->volume, -1);
}

/* Each reason of kc_ctrl_goal_check, with the field, knot and joint it
 * names and the number at fault. */
static void test_goal_check_verdicts(void **state)
{
    (void)state;
    setup();
    kc_verdict v;
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, KT_PUMA_Q0), KC_OK);

    /* joint move: the count the client gave, then the first joint out */
    kc_goal g = joint_goal(1, KT_PUMA_Q0);
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_OK);
    assert_int_equal(v.status, KC_OK);
    assert_int_equal(v.reason, KC_REASON_NONE);
    g.dim = 0; /* not given: the chain's */
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_OK);
    g.dim = 5;
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_JOINT_COUNT, KC_FIELD_DIM, -1, -1);
    assert_true(v.value == KC_R(5.0));
    g.dim = 6;
    g.q[2] = CHAIN.joints[2].limits.q_max + KC_R(0.25);
    g.q[4] = CHAIN.joints[4].limits.q_min - KC_R(0.25);
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_JOINT_LIMIT, KC_FIELD_TARGET, -1, 2);
    assert_true(v.value == g.q[2]);

    /* joint path: the knot and the joint, limits before times */
    g = joint_path(2, 4);
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_OK);
    g.points[2][4] = CHAIN.joints[4].limits.q_max + KC_R(0.5);
    g.has_times = 1;
    g.times[0] = KC_R(1.0);
    g.times[1] = KC_R(0.5); /* not after the one before */
    g.times[2] = KC_R(2.0);
    g.times[3] = KC_R(3.0);
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_JOINT_LIMIT, KC_FIELD_TARGET, 2, 4);
    assert_true(v.value == g.points[2][4]);
    g.points[2][4] = KT_PUMA_Q0[4];
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_BAD_GOAL, KC_FIELD_TIMES, 1, -1);
    g = joint_path(3, 4);
    g.dim = 7;
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_JOINT_COUNT, KC_FIELD_DIM, -1, -1);
    assert_true(v.value == KC_R(7.0));
    g = joint_path(4, 0);
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_BAD_GOAL, KC_FIELD_N_POINTS, -1, -1);
    assert_true(v.value == KC_R(0.0));
    g = joint_path(5, KC_PATH_MAX_KNOTS); /* one more than a goal holds */
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_BAD_GOAL, KC_FIELD_N_POINTS, -1, -1);
    assert_true(v.value == (kc_real)KC_PATH_MAX_KNOTS);
    /* Cartesian knots have 7 numbers: not a joint count */
    g = joint_path(6, 2);
    g.kind = KC_GOAL_PATH_CART;
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_BAD_GOAL, KC_FIELD_DIM, -1, -1);

    /* a line whose orientation is no rotation; a scale out of (0, 1] */
    kc_pose to;
    kc_fk_eval(&CHAIN, KT_PUMA_Q0, &to);
    g = kt_line_goal(7, &to);
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_OK);
    to.R.m[0][0] *= KC_R(1.1);
    g = kt_line_goal(7, &to);
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_BAD_GOAL, KC_FIELD_ORIENTATION, -1, -1);
    assert_true(isnan((double)v.value));
    g = joint_goal(8, KT_PUMA_Q0);
    g.vel_scale = KC_R(1.5);
    assert_int_equal(kc_ctrl_goal_check(&CHAIN, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_BAD_GOAL, KC_FIELD_NONE, -1, -1);

    /* the dry run starts with the same check: the same verdict */
    g = joint_goal(9, KT_PUMA_Q0);
    g.q[1] = CHAIN.joints[1].limits.q_max + KC_R(0.1);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_E_ARG);
    assert_names(&v, KC_REASON_JOINT_LIMIT, KC_FIELD_TARGET, -1, 1);
}

/* A check from KT_PUMA_Q0 on the PUMA 560, and a line from the tool's
 * pose there (*start) moved by dy and dz (*to). */
static kc_goal line_from_start(int64_t id, kc_real dy, kc_real dz, kc_pose *start, kc_pose *to)
{
    setup();
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, KT_PUMA_Q0), KC_OK);
    kc_fk_eval(&CHAIN, KT_PUMA_Q0, start);
    *to = *start;
    to->t.v[1] += dy;
    to->t.v[2] += dz;
    return kt_line_goal(id, to);
}

/* The dry run's own verdicts: where the motion fails, and when it ends. */
static void test_dry_run_verdicts(void **state)
{
    (void)state;
    kc_verdict v;
    kc_pose start, to;
    kc_goal g = line_from_start(1, KC_R(0.2), KC_R(0.0), &start, &to);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_OK);
    assert_int_equal(v.reason, KC_REASON_NONE);
    kc_pose end;
    kc_fk_eval(&CHAIN, v.q_end, &end);
    kt_near_vec3(&end.t, &to.t, 1e-4, "end of the line");
    /* 0.2 m at 0.25 m/s and 0.5 m/s^2 takes 0.8 + 0.5 s: its last tick */
    assert_true(v.tick >= 1300 && v.tick < 1300 + 1000);

    /* out of the workspace: unreachable, on the way */
    to.t.v[0] += KC_R(2.0);
    g = kt_line_goal(2, &to);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_E_UNREACHABLE);
    assert_int_equal(v.status, KC_E_UNREACHABLE);
    assert_int_equal(v.reason, KC_REASON_UNREACHABLE);
    assert_true(v.where > KC_R(0.0) && v.where < KC_R(2.0));
    assert_true(v.tick > 0 && v.tick < 100000);
    assert_int_equal(v.zone, -1);

    /* a motion longer than the check looks: too long, at its last tick */
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 5, KT_PUMA_Q0), KC_OK);
    to = start;
    to.t.v[1] += KC_R(0.2);
    g = kt_line_goal(3, &to);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_E_CAPACITY);
    assert_int_equal(v.reason, KC_REASON_PLAN);
    assert_int_equal(v.tick, 5);
}

/* The dry run's qu (kc_verdict.qu): the joints' largest rate per unit of a
 * line's parameter rate over their qddd_max, while it moves at a tenth of
 * its top speed or more. Measured here on a controller running the same
 * line, u' from the tool point's speed (the FK of consecutive setpoints)
 * over the line's length: the two agree within 2 % (the tool's speed is
 * its target's, but for the half tick a difference lags and the
 * tracking). */
static void test_dry_run_qu(void **state)
{
    (void)state;
    kc_verdict v;
    kc_pose start, to;
    kc_goal g = line_from_start(1, KC_R(0.2), KC_R(-0.1), &start, &to);
    double length = sqrt(0.2 * 0.2 + 0.1 * 0.1);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_OK);
    assert_true(v.qu > KC_R(0.0));
    static double speed[4000], rate[4000];
    int n = 0;
    double top = 0.0, dt = (double)CFG.dt;
    kc_ctrl_output out;
    memset(&out, 0, sizeof out);
    assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &CFG, KT_PUMA_Q0), KC_OK);
    kc_pose before = start;
    for (int k = 0; k < 4000 && !kt_has_event(&out, KC_EVENT_COMPLETED, 1); k++) {
        kc_ctrl_input in = {k == 0 ? &g : NULL, KC_CMD_NONE, 0, KC_REASON_NONE};
        assert_int_equal(kc_ctrl_step(&CTRL, &in, &out), KC_OK);
        double d = 0.0;
        for (int i = 0; i < 3; i++)
            d += pow((double)out.pose.t.v[i] - (double)before.t.v[i], 2.0);
        before = out.pose;
        speed[n] = sqrt(d) / dt;
        rate[n] = 0.0;
        for (int j = 0; j < 6; j++)
            rate[n] = fmax(rate[n], fabs((double)out.qd[j]) / (double)CHAIN.joints[j].limits.qddd_max);
        top = fmax(top, speed[n]);
        n++;
    }
    assert_true(kt_has_event(&out, KC_EVENT_COMPLETED, 1));
    double qu = 0.0;
    for (int k = 0; k < n; k++)
        if (speed[k] >= 0.1 * top)
            qu = fmax(qu, rate[k] / (speed[k] / length));
    print_message("qu: the dry run's %.6g, measured %.6g (%s)\n", (double)v.qu, qu, KC_REAL_NAME);
    kt_near(qu, (double)v.qu, 0.02 * qu, "the dry run's qu");
    /* A joint move has no path parameter: 0. */
    kc_real q1[6];
    for (int j = 0; j < 6; j++)
        q1[j] = KT_PUMA_Q0[j] + KC_R(0.2);
    kc_goal jm = joint_goal(2, q1);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &jm, &v), KC_OK);
    assert_true(v.qu == KC_R(0.0));
}

/* A waist sweep into a sphere where the wrist passes: the zone, the link
 * volume that enters it, and their distance. */
static void test_zone_verdict(void **state)
{
    (void)state;
    setup();
    CFG.zones = &ZONES;
    kc_real qa[6], qb[6], qm[6];
    memcpy(qa, KT_PUMA_Q0, sizeof qa);
    memcpy(qb, KT_PUMA_Q0, sizeof qb);
    memcpy(qm, KT_PUMA_Q0, sizeof qm);
    qa[0] = KC_R(-0.8);
    qb[0] = KC_R(0.8);
    qm[0] = KC_R(0.0);
    kc_pose mid;
    kc_fk_eval(&CHAIN, qm, &mid);
    kc_shape far, s;
    memset(&far, 0, sizeof far);
    far.kind = KC_SHAPE_SPHERE;
    kc_pose_identity(&far.pose);
    far.pose.t = kc_vec3_make(KC_R(3.0), KC_R(0.0), KC_R(0.0));
    far.dim[0] = KC_R(0.1);
    s = far;
    s.pose.t = mid.t;
    s.dim[0] = KC_R(0.05);
    assert_int_equal(kc_zone_set_add(&ZONES, &far), KC_OK); /* zone 0: out of reach */
    assert_int_equal(kc_zone_set_add(&ZONES, &s), KC_OK);   /* zone 1: in the way */
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, qa), KC_OK);
    kc_goal g = joint_goal(1, qb);
    kc_verdict v;
    assert_int_equal(kc_check_from(&CHECK, qa, &g, &v), KC_E_UNREACHABLE);
    assert_int_equal(v.reason, KC_REASON_ZONE);
    assert_int_equal(v.zone, 1);
    assert_true(v.volume >= 0 && v.volume < CHAIN.n_volumes);
    assert_true(v.distance < ZONES.margin);
    assert_true(v.where > KC_R(0.0) && v.where < KC_R(0.5)); /* on the way in, before the middle */
    assert_true(v.tick > 0);
    /* the volume named is the one in the zone at the middle of the sweep */
    kc_real d[KC_MAX_VOLUMES * KC_ZONE_MAX];
    assert_int_equal(kc_zone_distances(&CHAIN, &ZONES, qm, d), KC_OK);
    assert_true(d[v.volume * ZONES.n_zones + 1] < ZONES.margin);
}

/* One controller tick, its output fed to the check as the daemon does. */
static void tick(const kc_goal *g, int64_t *taken)
{
    kc_ctrl_input in = {g, KC_CMD_NONE, 0, KC_REASON_NONE};
    kc_ctrl_output out;
    assert_int_equal(kc_ctrl_step(&CTRL, &in, &out), KC_OK);
    if (g != NULL)
        (*taken)++;
    kc_check_tick(&CHECK, &out, *taken);
}

/* Goals judged in arrival order: each queued one from where the one before
 * it ends, a replacing one from the latest setpoint; a full queue refused
 * at once; a goal the controller refuses gives the queue's end back; at
 * rest the queue ends where the arm is. */
static void test_queue_end(void **state)
{
    (void)state;
    setup();
    assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &CFG, KT_PUMA_Q0), KC_OK);
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, KT_PUMA_Q0), KC_OK);
    int64_t taken = 0;
    tick(NULL, &taken);
    kc_goal sent[KC_CTRL_QUEUE_MAX];
    kc_verdict v;
    kc_real target[6];
    for (int i = 0; i < KC_CTRL_QUEUE_MAX; i++) {
        memcpy(target, KT_PUMA_Q0, sizeof target);
        target[0] = KT_PUMA_Q0[0] + KC_R(0.05) * (kc_real)(i + 1);
        target[5] = KT_PUMA_Q0[5] - KC_R(0.05) * (kc_real)(i + 1);
        sent[i] = joint_goal(10 + i, target);
        assert_int_equal(kc_check_goal(&CHECK, &sent[i], &v), KC_OK);
        /* judged from the end of the goal before it */
        const kc_real *from = i == 0 ? KT_PUMA_Q0 : sent[i - 1].q;
        for (int j = 0; j < 6; j++) {
            assert_true(CHECK.q_from[j] == from[j]);
            assert_true(v.q_end[j] == target[j]);
        }
        kc_check_handed(&CHECK, &sent[i], &v);
    }
    /* handed on, not yet taken: the queue is full */
    memcpy(target, KT_PUMA_Q0, sizeof target);
    kc_goal more = joint_goal(30, target);
    assert_int_equal(kc_check_goal(&CHECK, &more, &v), KC_E_CAPACITY);
    assert_int_equal(v.reason, KC_REASON_QUEUE_FULL);
    assert_true(v.value == (kc_real)KC_CTRL_QUEUE_MAX);
    /* one that replaces them all is judged, from the latest setpoint */
    more.replace = 1;
    assert_int_equal(kc_check_goal(&CHECK, &more, &v), KC_OK);
    for (int j = 0; j < 6; j++)
        assert_true(CHECK.q_from[j] == KT_PUMA_Q0[j]);
    more.replace = 0;

    /* The controller takes one goal a tick, as the cycle does; the queue
     * drains and the goals run to their ends. */
    for (int i = 0; i < KC_CTRL_QUEUE_MAX; i++)
        tick(&sent[i], &taken);
    assert_int_equal(kc_check_goal(&CHECK, &more, &v), KC_OK); /* room again: 1 active, 7 queued */
    /* A goal whose id is in flight: the check takes it, the controller
     * refuses it, and the queue ends where it ended before. */
    kc_goal dup = joint_goal(10 + KC_CTRL_QUEUE_MAX - 1, KT_PUMA_Q0);
    assert_int_equal(kc_check_goal(&CHECK, &dup, &v), KC_OK);
    kc_check_handed(&CHECK, &dup, &v);
    for (int j = 0; j < 6; j++)
        assert_true(CHECK.q_end[j] == KT_PUMA_Q0[j]);
    tick(&dup, &taken);
    for (int j = 0; j < 6; j++)
        assert_true(CHECK.q_end[j] == sent[KC_CTRL_QUEUE_MAX - 1].q[j]);
    /* every goal to its end, then at rest: the queue ends where the arm is */
    for (int k = 0; k < 200000 && !(CTRL.state == KC_CTRL_IDLE && CTRL.queue_len == 0 && !CTRL.active); k++)
        tick(NULL, &taken);
    tick(NULL, &taken);
    assert_int_equal(CTRL.state, KC_CTRL_IDLE);
    for (int j = 0; j < 6; j++) {
        assert_true(CHECK.q_end[j] == CTRL.q[j]);
        assert_true(CHECK.q_now[j] == CTRL.q[j]);
    }
    kt_near((double)CTRL.q[0], (double)sent[KC_CTRL_QUEUE_MAX - 1].q[0], 1e-9, "the last goal's end");
}

/* Two verdicts the same, field by field (the dry run is deterministic). */
static void assert_same_verdict(const kc_verdict *a, const kc_verdict *b)
{
    assert_int_equal(a->status, b->status);
    assert_int_equal(a->reason, b->reason);
    assert_int_equal(a->field, b->field);
    assert_int_equal(a->joint, b->joint);
    assert_int_equal(a->point, b->point);
    assert_true(a->value == b->value);
    assert_int_equal(a->tick, b->tick);
    assert_true(a->where == b->where);
    assert_int_equal(a->zone, b->zone);
    assert_int_equal(a->volume, b->volume);
    assert_true(a->distance == b->distance);
    for (int j = 0; j < 6; j++)
        assert_true(a->q_end[j] == b->q_end[j]);
}

/* g judged in slices of slice ticks from a check just set up at q0 (max_ticks
 * of motion): KC_MORE until the end, the ticks counted and the progress
 * never going back; returns the number of calls to kc_check_run. */
static int sliced(const kc_real *q0, int64_t max_ticks, const kc_goal *g, int64_t slice, kc_verdict *v)
{
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, max_ticks, q0), KC_OK);
    kc_status st = kc_check_begin(&CHECK, g, v);
    int calls = 0;
    kc_real progress = KC_R(0.0);
    while (st == KC_MORE) {
        int64_t before = CHECK.run_tick;
        st = kc_check_run(&CHECK, slice, v);
        calls++;
        if (st == KC_MORE) {
            assert_int_equal(CHECK.run_tick, before + slice);
            assert_true(CHECK.run_progress >= progress && CHECK.run_progress <= KC_R(1.0));
            progress = CHECK.run_progress;
        }
    }
    assert_int_equal(st, v->status);
    assert_int_equal(kc_check_run(&CHECK, slice, v), KC_E_ARG); /* nothing under way */
    return calls;
}

/* A dry run in slices of any size gives the verdict of one call: a line
 * taken, one leaving the workspace, one longer than the check looks, a
 * joint sweep into a zone, and a goal refused before any motion. */
static void test_sliced_same_verdict(void **state)
{
    (void)state;
    setup();
    kc_pose start, to, far;
    kc_fk_eval(&CHAIN, KT_PUMA_Q0, &start);
    to = start;
    to.t.v[1] += KC_R(0.2);
    far = to;
    far.t.v[0] += KC_R(2.0);
    kc_real bad[6];
    memcpy(bad, KT_PUMA_Q0, sizeof bad);
    bad[2] = KC_R(40.0);
    kc_goal goals[4] = {kt_line_goal(1, &to), kt_line_goal(2, &far), kt_line_goal(3, &to), joint_goal(4, bad)};
    int64_t max_ticks[4] = {100000, 100000, 50, 100000};
    static const int64_t slices[3] = {1, 13, 1 << 20};
    for (int i = 0; i < 4; i++) {
        kc_verdict one, part;
        assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, max_ticks[i], KT_PUMA_Q0), KC_OK);
        kc_status st = kc_check_goal(&CHECK, &goals[i], &one);
        assert_int_equal(st, one.status);
        for (int k = 0; k < 3; k++) {
            int calls = sliced(KT_PUMA_Q0, max_ticks[i], &goals[i], slices[k], &part);
            assert_same_verdict(&one, &part);
            if (i < 3 && slices[k] == 1)
                assert_int_equal(calls, one.tick); /* one tick a call, to the tick that ended it */
            if (i == 3)
                assert_int_equal(calls, 0); /* refused before any motion */
        }
    }
    assert_int_equal(goals[0].id, 1);
    kc_verdict v;
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, KT_PUMA_Q0), KC_OK);
    assert_int_equal(kc_check_goal(&CHECK, &goals[0], &v), KC_OK);
    assert_int_equal(kc_check_goal(&CHECK, &goals[1], &v), KC_E_UNREACHABLE);
    assert_int_equal(kc_check_goal(&CHECK, &goals[2], &v), KC_OK);

    /* with zones, the sweep of test_zone_verdict: zone 0 in the way */
    CFG.zones = &ZONES;
    kc_real qa[6], qb[6], qm[6];
    memcpy(qa, KT_PUMA_Q0, sizeof qa);
    memcpy(qb, KT_PUMA_Q0, sizeof qb);
    memcpy(qm, KT_PUMA_Q0, sizeof qm);
    qa[0] = KC_R(-0.8);
    qb[0] = KC_R(0.8);
    qm[0] = KC_R(0.0);
    kc_pose mid;
    kc_fk_eval(&CHAIN, qm, &mid);
    kc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = KC_SHAPE_SPHERE;
    kc_pose_identity(&s.pose);
    s.pose.t = mid.t;
    s.dim[0] = KC_R(0.05);
    assert_int_equal(kc_zone_set_add(&ZONES, &s), KC_OK);
    kc_goal sweep = joint_goal(5, qb);
    kc_verdict one, part;
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, qa), KC_OK);
    assert_int_equal(kc_check_goal(&CHECK, &sweep, &one), KC_E_UNREACHABLE);
    assert_int_equal(one.reason, KC_REASON_ZONE);
    for (int k = 0; k < 3; k++) {
        assert_true(sliced(qa, 100000, &sweep, slices[k], &part) >= 1);
        assert_same_verdict(&one, &part);
    }
    /* a begin abandons the run under way: the next verdict is its own */
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, qa), KC_OK);
    assert_int_equal(kc_check_begin(&CHECK, &sweep, &part), KC_MORE);
    assert_int_equal(kc_check_run(&CHECK, 3, &part), KC_MORE);
    assert_int_equal(kc_check_goal(&CHECK, &sweep, &part), KC_E_UNREACHABLE);
    assert_same_verdict(&one, &part);
    assert_int_equal(kc_check_run(&CHECK, 0, &part), KC_E_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_goal_check_verdicts),
        cmocka_unit_test(test_dry_run_verdicts),
        cmocka_unit_test(test_dry_run_qu),
        cmocka_unit_test(test_zone_verdict),
        cmocka_unit_test(test_queue_end),
        cmocka_unit_test(test_sliced_same_verdict),
    };
    int failed = cmocka_run_group_tests_name("check (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("check");
    return failed;
}
