/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl.c - the controller step (kinctl/ctrl.h) over thousands of
 * cycles: every goal kind to its end, the queue, preemption, stop, pause,
 * resume, e-stop, reset, rejections, servo and its timeout, the dry run,
 * and determinism. Every tick of every test goes through the same checks:
 * finite, inside the position limits, within the velocity limits, and a
 * change of velocity within qdd_max dt. */
#include <string.h>

#include "testutil.h"

/* Rounding allowed in the per-tick limit checks (relative). */
#ifdef KC_REAL_FLOAT
#define SLACK 1e-4
#define TOL_POSE 1e-4
#define TOL_RATE 1e-6 /* a velocity (rad/s) computed two ways */
#else
#define SLACK 1e-6
#define TOL_POSE 1e-6
#define TOL_RATE 1e-9
#endif

typedef struct harness {
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    kc_real qd_prev[KC_MAX_JOINTS];
    int64_t last_cycle;
    /* events seen, by kind, and the last one of each */
    int count[8];
    kc_ctrl_event last[8];
} harness;

static harness H; /* large (kc_ctrl holds a path plan): not on the stack */
static kc_check CHECK; /* the dry runs' */

/* kc_ctrl keeps the tool pose of its last setpoint (where a Cartesian
 * segment starts): the FK of q, to the bit. */
static void assert_pose_kept(void)
{
    kc_pose p;
    assert_int_equal(kc_fk_eval(&H.chain, H.ctrl.q, &p), KC_OK);
    for (int i = 0; i < 3; i++) {
        assert_true(H.ctrl.pose.t.v[i] == p.t.v[i]);
        for (int k = 0; k < 3; k++)
            assert_true(H.ctrl.pose.R.m[i][k] == p.R.m[i][k]);
    }
}

/* The controller at q0 with the default configuration at period dt. */
static void setup_at(kc_model model, const kc_real *q0, kc_real dt)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, model, NULL), KC_OK);
    H.cfg = kc_ctrl_cfg_default();
    H.cfg.dt = dt;
    assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, q0), KC_OK);
    assert_pose_kept();
}

static void setup(kc_model model, const kc_real *q0) { setup_at(model, q0, kc_ctrl_cfg_default().dt); }

/* One tick with the invariants checked, with an external fault input. */
static void tick_fault(const kc_goal *g, kc_ctrl_command cmd, kc_ctrl_reason fault)
{
    kc_ctrl_input in = {g, cmd, 0, fault};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    assert_true(H.out.cycle == H.last_cycle + 1);
    H.last_cycle = H.out.cycle;
    for (int j = 0; j < H.chain.n_joints; j++) {
        const kc_joint_limits *l = &H.chain.joints[j].limits;
        double q = (double)H.out.q[j], qd = (double)H.out.qd[j];
        if (!(q >= (double)l->q_min - 1e-9 && q <= (double)l->q_max + 1e-9))
            fail_msg("cycle %ld: q[%d] = %g outside the limits", (long)H.out.cycle, j, q);
        if (!(fabs(qd) <= (double)l->qd_max * (1.0 + SLACK)))
            fail_msg("cycle %ld: qd[%d] = %g beyond %g", (long)H.out.cycle, j, qd, (double)l->qd_max);
        double dv = fabs(qd - (double)H.qd_prev[j]), lim = (double)l->qdd_max * (double)H.cfg.dt * (1.0 + SLACK) +
                                                           SLACK * fabs((double)H.qd_prev[j]);
        if (!(dv <= lim))
            fail_msg("cycle %ld: qd[%d] jumps by %g > %g (state %d)", (long)H.out.cycle, j, dv, lim, H.out.state);
        H.qd_prev[j] = H.out.qd[j];
    }
    for (int e = 0; e < H.out.n_events; e++) {
        const kc_ctrl_event *ev = &H.out.events[e];
        assert_true(ev->kind >= 1 && ev->kind <= 7);
        H.count[ev->kind]++;
        H.last[ev->kind] = *ev;
    }
    assert_pose_kept();
}

static void tick(const kc_goal *g, kc_ctrl_command cmd) { tick_fault(g, cmd, KC_REASON_NONE); }

/* Ticks without input until the controller is idle (or in state), at most
 * max ticks; returns the ticks taken. */
static int run_until_state(kc_ctrl_state state, int max)
{
    for (int k = 1; k <= max; k++) {
        tick(NULL, KC_CMD_NONE);
        if (H.out.state == state && H.out.n_events == 0)
            return k;
    }
    fail_msg("state %d not reached in %d ticks (state %d)", state, max, H.out.state);
    return -1;
}

/* A path goal of n points; joint points are KT_PUMA_Q0 + offsets[i] on every
 * joint, Cartesian ones the pose here moved by offsets (x, y, z) with the
 * orientation kept. */
static kc_goal path_goal(int64_t id, kc_goal_kind kind, kc_path_method method, int n, const kc_real (*offsets)[3],
                         const kc_pose *here)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = kind;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.method = method;
    g.n_points = n;
    kc_quat r = {KC_R(1.0), 0, 0, 0};
    if (here != NULL)
        kc_quat_from_mat3(&here->R, &r);
    for (int i = 0; i < n; i++) {
        if (kind == KC_GOAL_PATH) {
            for (int j = 0; j < 6; j++)
                g.points[i][j] = KT_PUMA_Q0[j] + offsets[i][0];
        } else {
            for (int k = 0; k < 3; k++)
                g.points[i][k] = here->t.v[k] + offsets[i][k];
            g.points[i][3] = r.w;
            g.points[i][4] = r.x;
            g.points[i][5] = r.y;
            g.points[i][6] = r.z;
        }
    }
    return g;
}

static kc_pose pose_of(const kc_real *q)
{
    kc_pose p;
    kc_fk_eval(&H.chain, q, &p);
    return p;
}

static void assert_pose_near(const kc_pose *a, const kc_pose *b, double tol)
{
    kt_near_vec3(&a->t, &b->t, tol, "position");
    kt_near_mat3(&a->R, &b->R, tol, "orientation");
}

/* From KT_PUMA_Q0, a joint move of every joint by 0.5 rad (goal id), followed
 * for the given ticks. */
static void start_joint_move(int64_t id, int ticks)
{
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    kc_real a[6];
    for (int j = 0; j < 6; j++)
        a[j] = KT_PUMA_Q0[j] + KC_R(0.5);
    kc_goal g = kt_joint_goal(id, a, 6);
    tick(&g, KC_CMD_NONE);
    for (int k = 0; k < ticks; k++)
        tick(NULL, KC_CMD_NONE);
}

static void test_joint_goal(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    const kc_real target[6] = {KC_R(-0.5), KC_R(0.3), KC_R(-1.5), KC_R(0.8), KC_R(-0.4), KC_R(1.0)};
    kc_goal g = kt_joint_goal(7, target, 6);
    tick(&g, KC_CMD_NONE);
    assert_int_equal(H.count[KC_EVENT_ACCEPTED], 1);
    assert_int_equal(H.count[KC_EVENT_STARTED], 1);
    assert_int_equal(H.out.goal_id, 7);
    assert_int_equal(H.out.state, KC_CTRL_MOVING);
    run_until_state(KC_CTRL_IDLE, 20000);
    assert_int_equal(H.count[KC_EVENT_COMPLETED], 1);
    assert_int_equal(H.last[KC_EVENT_COMPLETED].goal_id, 7);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)target[j], 0.0, "joint goal reached exactly");
}

/* A line of 19 cm with a turn of 0.3 rad on the PUMA 560 at period dt:
 * judged by the dry run, then followed within the tracking tolerance to
 * its end. */
static void line_at(kc_real dt)
{
    setup_at(KC_MODEL_PUMA560, KT_PUMA_Q0, dt);
    kc_pose start = pose_of(KT_PUMA_Q0), to = start;
    to.t.v[0] += KC_R(0.1);
    to.t.v[1] += KC_R(0.15);
    to.t.v[2] -= KC_R(0.05);
    kc_mat3 turn;
    kc_mat3_rot(KC_AXIS_Z, KC_R(0.3), &turn);
    kc_mat3_mul(&turn, &start.R, &to.R);
    kc_goal g = kt_line_goal(11, &to);
    kc_verdict v;
    assert_int_equal(kc_check_init(&CHECK, &H.chain, &H.cfg, 100000, KT_PUMA_Q0), KC_OK);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_OK);
    tick(&g, KC_CMD_NONE);
    kc_vec3 dir;
    kc_vec3_sub(&to.t, &start.t, &dir);
    kc_real len = kc_vec3_norm(&dir);
    kc_vec3_scale(&dir, KC_R(1.0) / len, &dir);
    double worst = 0.0;
    int k = 0;
    for (; k < 20000 && H.out.state != KC_CTRL_IDLE; k++) {
        tick(NULL, KC_CMD_NONE);
        /* On the line within the tracking tolerance the controller enforces
         * (the elbow's acceleration limit binds near the end here). */
        kc_vec3 d, c;
        kc_vec3_sub(&H.out.pose.t, &start.t, &d);
        kc_vec3_cross(&d, &dir, &c);
        double dist = (double)kc_vec3_norm(&c);
        worst = dist > worst ? dist : worst;
        kt_near(dist, 0.0, (double)H.cfg.track_tol, "distance from the line");
    }
    print_message("line at %g ms: %d ticks, worst distance from the line %.3g m\n", 1e3 * (double)dt, k, worst);
    assert_int_equal(H.count[KC_EVENT_FAULT], 0);
    assert_int_equal(H.count[KC_EVENT_COMPLETED], 1);
    assert_pose_near(&H.out.pose, &to, TOL_POSE);
}

static void test_line_goal(void **state)
{
    (void)state;
    line_at(kc_ctrl_cfg_default().dt);
}

/* The same line at periods of 20 and 40 ms, where the controller's IK
 * gain of 100/s would make k dt 2 and 4 (kc_ik_online_gain: at most 1/dt;
 * the dry run refused it as unreachable at both). At 50 ms it is refused
 * still: near its end the elbow, braking at its acceleration limit over
 * ticks that long, leaves the tool 1.1 mm behind, beyond track_tol. */
static void test_line_at_slow_periods(void **state)
{
    (void)state;
    line_at(KC_R(0.02));
    line_at(KC_R(0.04));
}

static void test_arc_and_paths(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    kc_pose start = pose_of(KT_PUMA_Q0);
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = 21;
    g.kind = KC_GOAL_ARC;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.via = start.t;
    g.via.v[1] += KC_R(0.1);
    g.via.v[0] += KC_R(0.05);
    g.pose = start;
    g.pose.t.v[1] += KC_R(0.2);
    tick(&g, KC_CMD_NONE);
    run_until_state(KC_CTRL_IDLE, 20000);
    assert_int_equal(H.count[KC_EVENT_COMPLETED], 1);
    kt_near_vec3(&H.out.pose.t, &g.pose.t, TOL_POSE, "arc end");

    /* A joint-space spline through two points, then a Cartesian blend path
     * back through two poses. */
    const kc_real spline_off[2][3] = {{KC_R(0.2), 0, 0}, {KC_R(-0.1), 0, 0}};
    kc_goal p = path_goal(22, KC_GOAL_PATH, KC_PATH_SPLINE, 2, spline_off, NULL);
    tick(&p, KC_CMD_NONE);
    run_until_state(KC_CTRL_IDLE, 20000);
    assert_int_equal(H.count[KC_EVENT_COMPLETED], 2);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)p.points[1][j], 1e-9, "joint path end");

    kc_pose here = H.out.pose;
    const kc_real off[2][3] = {{KC_R(0.05), KC_R(0.05), KC_R(0.0)}, {KC_R(0.1), KC_R(0.0), KC_R(-0.05)}};
    p = path_goal(23, KC_GOAL_PATH_CART, KC_PATH_BLEND, 2, off, &here);
    tick(&p, KC_CMD_NONE);
    run_until_state(KC_CTRL_IDLE, 20000);
    assert_int_equal(H.count[KC_EVENT_COMPLETED], 3);
    kc_vec3 end = kc_vec3_make(p.points[1][0], p.points[1][1], p.points[1][2]);
    kt_near_vec3(&H.out.pose.t, &end, TOL_POSE, "Cartesian path end");
}

/* Whether the last output carries an event of that kind for that goal. */
static void test_queue_and_preemption(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    kc_real a[6], b[6], c[6];
    for (int j = 0; j < 6; j++) {
        a[j] = KT_PUMA_Q0[j] + KC_R(0.3);
        b[j] = KT_PUMA_Q0[j] - KC_R(0.2);
        c[j] = KT_PUMA_Q0[j] + KC_R(0.1);
    }
    kc_goal ga = kt_joint_goal(1, a, 6), gb = kt_joint_goal(2, b, 6), gc = kt_joint_goal(3, c, 6);
    tick(&ga, KC_CMD_NONE);
    tick(&gb, KC_CMD_NONE);
    assert_int_equal(H.out.queue_length, 1);
    run_until_state(KC_CTRL_IDLE, 40000);
    assert_int_equal(H.count[KC_EVENT_COMPLETED], 2);
    assert_int_equal(H.last[KC_EVENT_COMPLETED].goal_id, 2);

    /* Preempt a moving goal: it stops on its path, the new one completes. */
    tick(&ga, KC_CMD_NONE);
    for (int k = 0; k < 200; k++)
        tick(NULL, KC_CMD_NONE);
    gc.replace = 1;
    tick(&gc, KC_CMD_NONE);
    run_until_state(KC_CTRL_IDLE, 40000);
    assert_int_equal(H.count[KC_EVENT_PREEMPTED], 1);
    assert_int_equal(H.last[KC_EVENT_PREEMPTED].goal_id, 1);
    assert_int_equal(H.last[KC_EVENT_COMPLETED].goal_id, 3);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)c[j], 0.0, "replacing goal reached");

    /* An id in flight names one goal: the same id again, active or queued,
     * is refused; once its goal has ended the id may be used again. */
    kc_goal dup = kt_joint_goal(1, a, 6);
    tick(&ga, KC_CMD_NONE);
    tick(&gb, KC_CMD_NONE);
    int rejected = H.count[KC_EVENT_REJECTED];
    tick(&dup, KC_CMD_NONE); /* goal 1 is active */
    dup.id = 2;
    dup.replace = 1;
    tick(&dup, KC_CMD_NONE); /* goal 2 is queued: refused even as a replacement */
    assert_int_equal(H.count[KC_EVENT_REJECTED], rejected + 2);
    assert_int_equal(H.last[KC_EVENT_REJECTED].reason, KC_REASON_DUPLICATE_ID);
    assert_int_equal(H.out.queue_length, 1);
    assert_int_equal(H.out.goal_id, 1);
    run_until_state(KC_CTRL_IDLE, 40000);
    dup.replace = 0;
    tick(&dup, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_ACCEPTED, 2));
    run_until_state(KC_CTRL_IDLE, 40000);

    /* A full queue refuses more. */
    rejected = H.count[KC_EVENT_REJECTED];
    for (int i = 0; i < KC_CTRL_QUEUE_MAX + 2; i++) {
        kc_goal g = kt_joint_goal(100 + i, (i % 2) ? a : b, 6);
        tick(&g, KC_CMD_NONE);
    }
    assert_int_equal(H.count[KC_EVENT_REJECTED], rejected + 1);
    assert_int_equal(H.last[KC_EVENT_REJECTED].reason, KC_REASON_QUEUE_FULL);
    assert_int_equal(H.out.queue_length, KC_CTRL_QUEUE_MAX);

    /* Replacing all of it answers every goal in one tick: each queued one
     * preempted, the new one accepted and started, the active one preempted. */
    kc_goal gr = kt_joint_goal(200, c, 6);
    gr.replace = 1;
    int preempted = H.count[KC_EVENT_PREEMPTED];
    tick(&gr, KC_CMD_NONE);
    assert_int_equal(H.out.n_events, KC_CTRL_QUEUE_MAX + 3);
    assert_int_equal(H.count[KC_EVENT_PREEMPTED], preempted + KC_CTRL_QUEUE_MAX + 1);
    assert_true(kt_has_event(&H.out, KC_EVENT_ACCEPTED, 200) && kt_has_event(&H.out, KC_EVENT_STARTED, 200));
}

/* Ticks without input until goal id completes (at most max); returns the
 * ticks taken, the completing one included. */
static int run_until_completed(int64_t id, int max)
{
    for (int k = 1; k <= max; k++) {
        tick(NULL, KC_CMD_NONE);
        if (kt_has_event(&H.out, KC_EVENT_COMPLETED, id))
            return k;
        if (H.out.state == KC_CTRL_FAULT)
            fail_msg("fault %d while waiting for goal %ld", H.last[KC_EVENT_FAULT].reason, (long)id);
    }
    fail_msg("goal %ld did not complete in %d ticks", (long)id, max);
    return -1;
}

/* Time-optimal duration of one axis from (p, v) to rest at p1 when it must
 * first turn round (v away from p1) and then reaches vmax: brake v / A,
 * then a rest-to-rest trapezoid over the rest of the way. */
static double turn_and_trapezoid(double p, double v, double p1, double vmax, double amax)
{
    double turn = p + v * fabs(v) / (2.0 * amax), d = fabs(p1 - turn);
    assert_true(d >= vmax * vmax / amax); /* the trapezoid reaches vmax */
    return fabs(v) / amax + d / vmax + vmax / amax;
}

/* A joint goal replacing a moving one takes over in the same tick from the
 * current position and velocity; when turning round would carry a joint
 * past its limit it waits for the stop on the path instead. */
static void test_retarget(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    const kc_joint_limits *l0 = &H.chain.joints[0].limits;
    kc_real ahead[6], back[6];
    memcpy(ahead, KT_PUMA_Q0, sizeof ahead);
    memcpy(back, KT_PUMA_Q0, sizeof back);
    ahead[0] = KC_R(2.7);
    ahead[1] += KC_R(0.3);
    back[0] = KC_R(-1.0);
    back[1] -= KC_R(0.2);
    kc_goal ga = kt_joint_goal(41, ahead, 6), gb = kt_joint_goal(42, back, 6);
    gb.replace = 1;
    /* The trapezoid's retarget (test_ctrl_jerk.c has the jerk-limited one). */
    ga.profile = gb.profile = KC_GOAL_PROFILE_TRAPEZOID;

    /* Cruising at joint 0's full speed, reversed. */
    tick(&ga, KC_CMD_NONE);
    for (int k = 0; k < 700; k++)
        tick(NULL, KC_CMD_NONE);
    double q_before = (double)H.out.q[0], v_before = (double)H.out.qd[0];
    kt_near(v_before, (double)l0->qd_max, TOL_RATE, "cruising at the velocity limit");
    tick(&gb, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_ACCEPTED, 42) && kt_has_event(&H.out, KC_EVENT_PREEMPTED, 41) &&
                kt_has_event(&H.out, KC_EVENT_STARTED, 42));
    assert_int_equal(H.out.goal_id, 42);
    assert_int_equal(H.out.state, KC_CTRL_MOVING);
    /* The first setpoint continues the motion: one tick of braking at A. */
    kt_near((double)H.out.qd[0], v_before - (double)l0->qdd_max * (double)H.cfg.dt, TOL_RATE, "qd after the takeover");
    int ticks = 1 + run_until_completed(42, 40000);
    double T = turn_and_trapezoid(q_before, v_before, (double)back[0], (double)l0->qd_max, (double)l0->qdd_max);
    assert_true(fabs((double)ticks - T / (double)H.cfg.dt) <= 1.0);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)back[j], 0.0, "retarget reached");
    assert_int_equal(H.count[KC_EVENT_PREEMPTED], 1);

    /* The same reversal at a tenth of the acceleration would brake to
     * 2.x + 4 / 1 rad, past joint 0's limit: stop on the path, then start. */
    kc_goal gc = kt_joint_goal(43, back, 6);
    gc.replace = 1;
    gc.profile = KC_GOAL_PROFILE_TRAPEZOID;
    gc.acc_scale = KC_R(0.1);
    tick(&ga, KC_CMD_NONE);
    for (int k = 0; k < 700; k++)
        tick(NULL, KC_CMD_NONE);
    tick(&gc, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_ACCEPTED, 43) && !kt_has_event(&H.out, KC_EVENT_PREEMPTED, 41));
    assert_int_equal(H.out.state, KC_CTRL_STOPPING);
    assert_int_equal(H.out.goal_id, 41);
    for (int k = 0; k < 2000 && !kt_has_event(&H.out, KC_EVENT_PREEMPTED, 41); k++)
        tick(NULL, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_PREEMPTED, 41));
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.qd[j], 0.0, 0.0, "at rest when preempted");
    assert_true((double)H.out.q[0] <= (double)l0->q_max);
    run_until_completed(43, 40000);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)back[j], 0.0, "fallback goal reached");

    /* A retarget paused and resumed; then one that replaces a line. */
    gb.id = 44;
    tick(&ga, KC_CMD_NONE);
    for (int k = 0; k < 500; k++)
        tick(NULL, KC_CMD_NONE);
    tick(&gb, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_STARTED, 44));
    for (int k = 0; k < 100; k++)
        tick(NULL, KC_CMD_NONE);
    tick(NULL, KC_CMD_PAUSE);
    run_until_state(KC_CTRL_PAUSED, 5000);
    tick(NULL, KC_CMD_RESUME);
    run_until_completed(44, 40000);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)back[j], 0.0, "resumed retarget reached");

    kc_pose to = pose_of(H.out.q);
    to.t.v[2] += KC_R(0.15);
    kc_goal gl = kt_line_goal(45, &to);
    kc_goal gd = kt_joint_goal(46, KT_PUMA_Q0, 6);
    gd.replace = 1;
    gd.profile = KC_GOAL_PROFILE_TRAPEZOID;
    tick(&gl, KC_CMD_NONE);
    for (int k = 0; k < 400; k++)
        tick(NULL, KC_CMD_NONE);
    assert_true(fabs((double)H.out.qd[1]) + fabs((double)H.out.qd[2]) > 0.05); /* moving */
    tick(&gd, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_PREEMPTED, 45) && kt_has_event(&H.out, KC_EVENT_STARTED, 46));
    run_until_completed(46, 40000);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)KT_PUMA_Q0[j], 0.0, "joint goal after a line");
    assert_int_equal(H.count[KC_EVENT_FAULT], 0);
    assert_int_equal(H.count[KC_EVENT_ABORTED], 0);
}

/* An arm past a position limit (where a stop from full speed may carry
 * it) rests there without a fault and moves back in on a joint goal, which
 * the dry run also accepts from there. */
static void test_outside_a_limit(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    const kc_joint_limits *l4 = &H.chain.joints[3].limits;
    H.ctrl.q[3] = l4->q_max + KC_R(0.0155); /* as the soak saw it */
    for (int k = 0; k < 50; k++) {
        kc_ctrl_input in = {NULL, KC_CMD_NONE, 0, KC_REASON_NONE};
        assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
        assert_int_equal(H.out.n_events, 0);
    }
    assert_int_equal(H.out.state, KC_CTRL_IDLE);
    H.last_cycle = H.out.cycle;
    kc_real back[6];
    memcpy(back, KT_PUMA_Q0, sizeof back);
    kc_verdict v;
    kc_goal g = kt_joint_goal(51, back, 6);
    assert_int_equal(kc_check_init(&CHECK, &H.chain, &H.cfg, 100000, KT_PUMA_Q0), KC_OK);
    assert_int_equal(kc_check_from(&CHECK, H.ctrl.q, &g, &v), KC_OK);
    /* tick() checks the limits: only once the joint is back inside. */
    kc_ctrl_input in = {&g, KC_CMD_NONE, 0, KC_REASON_NONE};
    int k = 0;
    for (; k < 5000 && !(H.out.q[3] <= l4->q_max); k++) {
        assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
        in.goal = NULL;
        assert_true(H.out.state == KC_CTRL_MOVING);
        H.qd_prev[3] = H.out.qd[3];
    }
    H.last_cycle = H.out.cycle;
    memcpy(H.qd_prev, H.out.qd, sizeof H.qd_prev);
    run_until_completed(51, 40000);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)back[j], 0.0, "back inside");
    assert_int_equal(H.count[KC_EVENT_FAULT], 0);
}

static void test_stop_pause_resume(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    kc_pose start = pose_of(KT_PUMA_Q0), to = start;
    to.t.v[1] += KC_R(0.25);
    kc_goal g = kt_line_goal(31, &to);
    tick(&g, KC_CMD_NONE);
    for (int k = 0; k < 300; k++)
        tick(NULL, KC_CMD_NONE);
    tick(NULL, KC_CMD_PAUSE);
    run_until_state(KC_CTRL_PAUSED, 5000);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.qd[j], 0.0, 0.0, "paused at rest");
    kt_near((double)H.out.pose.t.v[0], (double)start.t.v[0], 1e-5, "paused on the line (x)");
    for (int k = 0; k < 100; k++)
        tick(NULL, KC_CMD_NONE);
    tick(NULL, KC_CMD_RESUME);
    run_until_state(KC_CTRL_IDLE, 20000);
    assert_int_equal(H.count[KC_EVENT_COMPLETED], 1);
    assert_pose_near(&H.out.pose, &to, TOL_POSE);

    /* Stop: on the path, the goal aborted, the queue dropped. */
    kc_goal back = kt_line_goal(32, &start), again = kt_line_goal(33, &to);
    tick(&back, KC_CMD_NONE);
    tick(&again, KC_CMD_NONE);
    for (int k = 0; k < 300; k++)
        tick(NULL, KC_CMD_NONE);
    tick(NULL, KC_CMD_STOP);
    run_until_state(KC_CTRL_IDLE, 5000);
    assert_int_equal(H.last[KC_EVENT_ABORTED].goal_id, 32);
    assert_int_equal(H.last[KC_EVENT_PREEMPTED].goal_id, 33);
    assert_int_equal(H.out.queue_length, 0);
    kt_near((double)H.out.pose.t.v[0], (double)start.t.v[0], 1e-5, "stopped on the line (x)");
}

static void test_estop_and_reset(void **state)
{
    (void)state;
    start_joint_move(41, 400);
    tick(NULL, KC_CMD_ESTOP);
    assert_int_equal(H.out.state, KC_CTRL_ESTOP);
    assert_int_equal(H.last[KC_EVENT_ABORTED].goal_id, 41);
    for (int k = 0; k < 2000; k++)
        tick(NULL, KC_CMD_NONE);
    assert_int_equal(H.out.state, KC_CTRL_ESTOP); /* latched */
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.qd[j], 0.0, 0.0, "at rest after e-stop");
    kc_goal g2 = kt_joint_goal(42, KT_PUMA_Q0, 6);
    tick(&g2, KC_CMD_NONE);
    assert_int_equal(H.last[KC_EVENT_REJECTED].reason, KC_REASON_STATE);
    tick(NULL, KC_CMD_RESET);
    assert_int_equal(H.out.state, KC_CTRL_IDLE);
    tick(&g2, KC_CMD_NONE);
    run_until_state(KC_CTRL_IDLE, 20000);
    assert_int_equal(H.last[KC_EVENT_COMPLETED].goal_id, 42);
}

/* Seating at the drives' positions: only an idle controller at rest takes
 * it, inside the limits; the cycle count goes on, and the arm holds at the
 * seat and moves from there. */
static void test_seat(void **state)
{
    (void)state;
    const kc_real seat[6] = {KC_R(0.3), KC_R(0.5), KC_R(-2.0), KC_R(-0.2), KC_R(0.4), KC_R(-0.1)};
    kc_real outside[6];
    int bad = 99;
    start_joint_move(51, 100);
    assert_int_equal(kc_ctrl_seat(&H.ctrl, seat, &bad), KC_E_STATE); /* moving */
    assert_int_equal(bad, -1);
    run_until_state(KC_CTRL_IDLE, 20000);
    memcpy(outside, seat, sizeof outside);
    outside[2] = H.chain.joints[2].limits.q_min - KC_R(0.01);
    kc_real before = H.ctrl.q[0];
    assert_int_equal(kc_ctrl_seat(&H.ctrl, outside, &bad), KC_E_LIMIT);
    assert_int_equal(bad, 2);
    assert_true(H.ctrl.q[0] == before); /* unchanged on error */
    int64_t cycle = H.out.cycle;
    assert_int_equal(kc_ctrl_seat(&H.ctrl, seat, &bad), KC_OK);
    assert_pose_kept();
    tick(NULL, KC_CMD_NONE);
    assert_true(H.out.cycle == cycle + 1);
    assert_int_equal(H.out.state, KC_CTRL_IDLE);
    for (int j = 0; j < 6; j++) {
        kt_near((double)H.out.q[j], (double)seat[j], 0.0, "holds at the seat");
        kt_near((double)H.out.qd[j], 0.0, 0.0, "at rest at the seat");
    }
    /* A move from the seat starts there: the first setpoint is within one
     * tick's acceleration of it. */
    kc_goal g = kt_joint_goal(52, KT_PUMA_Q0, 6);
    tick(&g, KC_CMD_NONE);
    for (int j = 0; j < 6; j++) {
        double step = 0.5 * (double)H.chain.joints[j].limits.qdd_max * (double)H.cfg.dt * (double)H.cfg.dt;
        assert_true(fabs((double)H.out.q[j] - (double)seat[j]) <= step * (1.0 + 1e-6) + 1e-12);
    }
    run_until_state(KC_CTRL_IDLE, 20000);
    assert_int_equal(H.last[KC_EVENT_COMPLETED].goal_id, 52);
    /* ESTOP latches: no seat until RESET. */
    tick(NULL, KC_CMD_ESTOP);
    assert_int_equal(kc_ctrl_seat(&H.ctrl, seat, NULL), KC_E_STATE);
    tick(NULL, KC_CMD_RESET);
    assert_int_equal(kc_ctrl_seat(&H.ctrl, seat, NULL), KC_OK);
    assert_int_equal(kc_ctrl_seat(NULL, seat, NULL), KC_E_ARG);
}

/* An external fault (a drive) in the middle of a joint move: FAULT and
 * ABORTED at once, a joint-space stop no longer than the slowest joint's
 * own braking time qd / qdd_max, latched in FAULT until RESET, goals
 * refused meanwhile; a second report while faulted adds nothing. */
static void test_external_fault(void **state)
{
    (void)state;
    start_joint_move(61, 300);
    double t_brake = 0.0;
    for (int j = 0; j < 6; j++)
        t_brake = fmax(t_brake, fabs((double)H.out.qd[j]) / (double)H.chain.joints[j].limits.qdd_max);
    assert_true(t_brake > 0.01); /* moving */
    tick_fault(NULL, KC_CMD_NONE, KC_REASON_EXTERNAL);
    assert_int_equal(H.count[KC_EVENT_FAULT], 1);
    assert_int_equal(H.last[KC_EVENT_FAULT].reason, KC_REASON_EXTERNAL);
    assert_int_equal(H.last[KC_EVENT_FAULT].goal_id, 61);
    assert_int_equal(H.last[KC_EVENT_ABORTED].goal_id, 61);
    assert_int_equal(H.out.state, KC_CTRL_STOPPING);
    int ticks = 1;
    while (H.out.state != KC_CTRL_FAULT && ticks < 5000) {
        tick_fault(NULL, KC_CMD_NONE, ticks % 2 ? KC_REASON_EXTERNAL : KC_REASON_NONE);
        ticks++;
    }
    assert_int_equal(H.out.state, KC_CTRL_FAULT);
    assert_true(ticks <= (int)(t_brake / (double)H.cfg.dt) + 2);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.qd[j], 0.0, 0.0, "at rest after the external fault");
    tick_fault(NULL, KC_CMD_NONE, KC_REASON_EXTERNAL);
    assert_int_equal(H.count[KC_EVENT_FAULT], 1);
    kc_goal g2 = kt_joint_goal(62, KT_PUMA_Q0, 6);
    tick(&g2, KC_CMD_NONE);
    assert_int_equal(H.last[KC_EVENT_REJECTED].reason, KC_REASON_STATE);
    tick(NULL, KC_CMD_RESET);
    assert_int_equal(H.out.state, KC_CTRL_IDLE);
    tick(&g2, KC_CMD_NONE);
    run_until_state(KC_CTRL_IDLE, 20000);
    assert_int_equal(H.last[KC_EVENT_COMPLETED].goal_id, 62);
}

static void test_rejections(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    kc_real far[6];
    memcpy(far, KT_PUMA_Q0, sizeof far);
    far[4] = KC_R(2.5); /* beyond q5's limit */
    kc_goal g = kt_joint_goal(51, far, 6);
    tick(&g, KC_CMD_NONE);
    assert_int_equal(H.last[KC_EVENT_REJECTED].reason, KC_REASON_JOINT_LIMIT);
    g = kt_joint_goal(52, KT_PUMA_Q0, 6);
    g.q[2] = (kc_real)NAN;
    tick(&g, KC_CMD_NONE);
    assert_int_equal(H.last[KC_EVENT_REJECTED].reason, KC_REASON_BAD_GOAL);
    g = kt_joint_goal(53, KT_PUMA_Q0, 6);
    g.vel_scale = KC_R(1.5);
    tick(&g, KC_CMD_NONE);
    assert_int_equal(H.last[KC_EVENT_REJECTED].reason, KC_REASON_BAD_GOAL);
    kc_pose bad = pose_of(KT_PUMA_Q0);
    bad.R.m[0][0] = KC_R(3.0);
    g = kt_line_goal(54, &bad);
    tick(&g, KC_CMD_NONE);
    assert_int_equal(H.last[KC_EVENT_REJECTED].reason, KC_REASON_BAD_GOAL);
    assert_int_equal(H.count[KC_EVENT_REJECTED], 4);
    assert_int_equal(H.count[KC_EVENT_ACCEPTED], 0);
    assert_int_equal(H.out.state, KC_CTRL_IDLE);
}

static void test_servo(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    kc_pose start = pose_of(KT_PUMA_Q0);
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = 61;
    g.kind = KC_GOAL_SERVO;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.pose = start;
    /* A target moving 1 mm per tick update, streamed for 300 ticks. */
    for (int k = 0; k < 300; k++) {
        g.pose.t.v[1] = start.t.v[1] + KC_R(0.0001) * (kc_real)k;
        tick(&g, KC_CMD_NONE);
    }
    assert_int_equal(H.count[KC_EVENT_ACCEPTED], 1); /* updates are not new goals */
    /* Its shaped pose (0.1 m/s asked, 0.29 m/s^2 and 2.9 m/s^3 an axis
     * allowed) is 2 cm behind and at rest on the last target 0.7 s on. */
    for (int k = 0; k < 1000; k++)
        tick(&g, KC_CMD_NONE);
    kt_near((double)H.out.pose.t.v[1], (double)g.pose.t.v[1], TOL_POSE, "servo follows");
    /* The stream stops: after the timeout the arm stops and the goal ends. */
    run_until_state(KC_CTRL_IDLE, 2000);
    assert_int_equal(H.last[KC_EVENT_ABORTED].reason, KC_REASON_SERVO_TIMEOUT);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.qd[j], 0.0, 0.0, "at rest after the timeout");

    /* A servo stream replacing a line waits while the line stops on its
     * path; its messages in the meantime update the waiting goal, which is
     * answered once and then follows the latest target. */
    kc_pose here = H.out.pose, to = here;
    to.t.v[2] += KC_R(0.2);
    kc_goal l = kt_line_goal(62, &to);
    /* The trapezoid's stop, whose length makes the target move the 2 cm
     * below while the servo goal waits. */
    l.profile = KC_GOAL_PROFILE_TRAPEZOID;
    tick(&l, KC_CMD_NONE);
    for (int k = 0; k < 300; k++)
        tick(NULL, KC_CMD_NONE);
    int accepted = H.count[KC_EVENT_ACCEPTED], preempted = H.count[KC_EVENT_PREEMPTED];
    g.id = 63;
    g.replace = 1;
    g.pose = H.out.pose;
    /* The trapezoid's pose stream is not shaped: the IK step's braking
     * bound is what keeps a jump from overshooting. */
    g.profile = KC_GOAL_PROFILE_TRAPEZOID;
    int k = 0;
    for (; H.out.goal_id != 63 && k < 2000; k++) {
        g.pose.t.v[0] = here.t.v[0] + KC_R(0.00002) * (kc_real)k;
        tick(&g, KC_CMD_NONE);
    }
    assert_int_equal(H.out.goal_id, 63);
    assert_int_equal(H.count[KC_EVENT_ACCEPTED], accepted + 1);
    assert_int_equal(H.count[KC_EVENT_PREEMPTED], preempted + 1); /* the line only */
    assert_int_equal(H.last[KC_EVENT_PREEMPTED].goal_id, 62);
    /* ... closing in on it (a 2 cm jump) overshooting by less than the
     * tracking tolerance (without the online step's braking bound, by the
     * whole 2 cm; measured 0.06 mm in double, 0.8 mm in float). */
    double closest = 1e9, overshoot = 1.0 * (double)H.cfg.track_tol, worst_os = 0;
    for (int i = 0; i < 300; i++) {
        tick(&g, KC_CMD_NONE);
        kc_vec3 d;
        kc_vec3_sub(&H.out.pose.t, &g.pose.t, &d);
        double dist = (double)kc_vec3_norm(&d);
        if (dist > closest + overshoot)
            fail_msg("tick %d: %g m from the target after %g", i, dist, closest);
        closest = fmin(closest, dist);
        worst_os = fmax(worst_os, dist - closest);
    }
    print_message("servo target jump of 2 cm: overshoot %g m (%s)\n", worst_os, KC_REAL_NAME);
    kt_near((double)H.out.pose.t.v[0], (double)g.pose.t.v[0], TOL_POSE, "follows the latest target");
}

/* Paths stop on the path too: tau' falls to zero at a rate that keeps
 * every joint within its limits (the per-tick checks), then resumes. */
static void test_path_pause_stop(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    const kc_real blend_off[3][3] = {{KC_R(0.3), 0, 0}, {KC_R(-0.2), 0, 0}, {KC_R(0.1), 0, 0}};
    kc_goal p = path_goal(91, KC_GOAL_PATH, KC_PATH_BLEND, 3, blend_off, NULL);
    tick(&p, KC_CMD_NONE);
    for (int k = 0; k < 400; k++)
        tick(NULL, KC_CMD_NONE);
    tick(NULL, KC_CMD_PAUSE);
    run_until_state(KC_CTRL_PAUSED, 5000);
    for (int k = 0; k < 50; k++)
        tick(NULL, KC_CMD_NONE);
    tick(NULL, KC_CMD_RESUME);
    run_until_state(KC_CTRL_IDLE, 40000);
    assert_int_equal(H.last[KC_EVENT_COMPLETED].goal_id, 91);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)p.points[2][j], 1e-9, "path end after pause and resume");

    /* A Cartesian path stopped half way ends at rest, aborted. */
    kc_pose here = H.out.pose;
    const kc_real off[2][3] = {{KC_R(0.0), KC_R(0.1), KC_R(0.0)}, {KC_R(0.05), KC_R(0.2), KC_R(0.0)}};
    p = path_goal(92, KC_GOAL_PATH_CART, KC_PATH_SPLINE, 2, off, &here);
    tick(&p, KC_CMD_NONE);
    for (int k = 0; k < 300; k++)
        tick(NULL, KC_CMD_NONE);
    tick(NULL, KC_CMD_STOP);
    run_until_state(KC_CTRL_IDLE, 5000);
    assert_int_equal(H.last[KC_EVENT_ABORTED].goal_id, 92);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.qd[j], 0.0, 0.0, "stopped");
}

/* Lagrange's polynomial moves at its ends: the controller ramps tau' up
 * from rest and down into the end, within the limits every tick, and the
 * arm ends exactly on the last knot. */
static void test_lagrange_path(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    const kc_real lagrange_off[3][3] = {{KC_R(0.1), 0, 0}, {KC_R(0.25), 0, 0}, {KC_R(0.3), 0, 0}};
    kc_goal p = path_goal(95, KC_GOAL_PATH, KC_PATH_LAGRANGE, 3, lagrange_off, NULL);
    tick(&p, KC_CMD_NONE);
    run_until_state(KC_CTRL_IDLE, 40000);
    assert_int_equal(H.last[KC_EVENT_COMPLETED].goal_id, 95);
    assert_int_equal(H.count[KC_EVENT_ABORTED], 0);
    for (int j = 0; j < 6; j++)
        kt_near((double)H.out.q[j], (double)p.points[2][j], 1e-9, "Lagrange path end");
}

static void test_dry_run(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    kc_verdict v;
    kc_pose to = pose_of(KT_PUMA_Q0);
    to.t.v[1] += KC_R(0.2);
    kc_goal g = kt_line_goal(71, &to);
    assert_int_equal(kc_check_init(&CHECK, &H.chain, &H.cfg, 100000, KT_PUMA_Q0), KC_OK);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_OK);
    assert_int_equal(v.reason, KC_REASON_NONE);
    kc_pose end = pose_of(v.q_end);
    assert_pose_near(&end, &to, TOL_POSE);
    /* A line out of the workspace: the arm cannot follow it to its end. */
    to.t.v[0] += KC_R(2.0);
    g = kt_line_goal(72, &to);
    kc_status st = kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v);
    assert_int_equal(st, KC_E_UNREACHABLE);
    assert_int_equal(v.status, KC_E_UNREACHABLE);
    assert_int_equal(v.reason, KC_REASON_UNREACHABLE);
    assert_true((double)v.where > 0.0 && (double)v.where < 2.0);
    assert_true(v.tick > 0 && v.tick < 100000);
    /* A bad goal is refused without running. */
    g.pose.t.v[0] = (kc_real)NAN;
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_E_ARG);
    assert_int_equal(v.reason, KC_REASON_BAD_GOAL);
    assert_int_equal(v.tick, -1);
}

/* FNV-1a over the bytes of every output's setpoint. */
static uint64_t hash_run(void)
{
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    uint64_t h = 1469598103934665603ULL;
    kc_pose to = pose_of(KT_PUMA_Q0);
    to.t.v[1] += KC_R(0.2);
    kc_goal l = kt_line_goal(81, &to);
    kc_real a[6];
    for (int j = 0; j < 6; j++)
        a[j] = KT_PUMA_Q0[j] + KC_R(0.2);
    kc_goal jg = kt_joint_goal(82, a, 6);
    for (int k = 0; k < 6000; k++) {
        const kc_goal *g = k == 0 ? &l : (k == 1 ? &jg : NULL);
        kc_ctrl_command cmd = k == 500 ? KC_CMD_PAUSE : (k == 900 ? KC_CMD_RESUME : KC_CMD_NONE);
        tick(g, cmd);
        const unsigned char *b = (const unsigned char *)H.out.q;
        for (size_t i = 0; i < sizeof(kc_real) * 18; i++) /* q, qd, qdd */
            h = (h ^ b[i]) * 1099511628211ULL;
    }
    assert_int_equal(H.count[KC_EVENT_COMPLETED], 2);
    return h;
}

static void test_determinism(void **state)
{
    (void)state;
    uint64_t a = hash_run(), b = hash_run();
    print_message("determinism hash (%s): %016llx\n", KC_REAL_NAME, (unsigned long long)a);
    assert_true(a == b);
}

/* Steps without input until the controller is in FAULT (at most max ticks),
 * counting FAULT events (the last one's reason too) and the ends of goals
 * first_id .. first_id + n_ids - 1 into ends[]; returns the ticks taken. */
static int run_to_fault_counting(int64_t first_id, int n_ids, int max, int *faults, int *ends, kc_ctrl_reason *reason)
{
    kc_ctrl_input in = {NULL, KC_CMD_NONE, 0, KC_REASON_NONE};
    int k = 0;
    for (; k < max && H.out.state != KC_CTRL_FAULT; k++) {
        assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
        for (int e = 0; e < H.out.n_events; e++) {
            const kc_ctrl_event *ev = &H.out.events[e];
            if (ev->kind == KC_EVENT_FAULT) {
                (*faults)++;
                *reason = ev->reason;
            }
            if ((ev->kind == KC_EVENT_COMPLETED || ev->kind == KC_EVENT_PREEMPTED || ev->kind == KC_EVENT_ABORTED) &&
                ev->goal_id >= first_id && ev->goal_id < first_id + n_ids)
                ends[ev->goal_id - first_id]++;
        }
    }
    return k;
}

/* A joint move (81) that a replacing joint path (82) makes stop first
 * (kinctl/ctrl.h: Lagrange's polynomial does not start at rest, and under
 * the trapezoid's law its ramps step tau'': not superposed on the move's
 * stop), up to the replacement. */
static void joint_move_stopped_by_a_path(void)
{
    start_joint_move(81, 300);
    const kc_real off[2][3] = {{KC_R(0.05), 0, 0}, {KC_R(0.1), 0, 0}};
    kc_goal path = path_goal(82, KC_GOAL_PATH, KC_PATH_LAGRANGE, 2, off, NULL);
    path.profile = KC_GOAL_PROFILE_TRAPEZOID;
    path.replace = 1;
    tick(&path, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_ACCEPTED, 82));
    assert_int_equal(H.out.state, KC_CTRL_STOPPING);
}

/* A setpoint the final check refuses on the very tick a stop on the path
 * comes to rest: the goal is aborted by the fault and is not preempted as
 * well (the soak once saw a goal ended twice), the replacing goal waiting
 * behind it ends once, and the controller ends in FAULT. The refused
 * setpoint is made here by giving the controller a last velocity the stop
 * cannot follow within one tick's acceleration. */
static void test_final_check_on_the_last_tick_of_a_stop(void **state)
{
    (void)state;
    /* The ticks the stop takes to come to rest, */
    joint_move_stopped_by_a_path();
    int n = 1;
    for (tick(NULL, KC_CMD_NONE); !kt_has_event(&H.out, KC_EVENT_PREEMPTED, 81); tick(NULL, KC_CMD_NONE))
        assert_true(++n < 20000);
    /* then again, to the tick before. */
    joint_move_stopped_by_a_path();
    int ends[2] = {0, 0}, faults = 0;
    kc_ctrl_reason fault_reason = KC_REASON_NONE;
    for (int k = 1; k < n; k++)
        tick(NULL, KC_CMD_NONE);
    assert_int_equal(H.out.state, KC_CTRL_STOPPING);
    H.ctrl.qd[0] += KC_R(0.5) * H.chain.joints[0].limits.qd_max;
    run_to_fault_counting(81, 2, 20000, &faults, ends, &fault_reason);
    assert_int_equal(faults, 1);
    assert_int_equal(fault_reason, KC_REASON_LIMIT_GUARD);
    assert_int_equal(ends[0], 1);
    assert_int_equal(ends[1], 1);
    assert_int_equal(H.out.state, KC_CTRL_FAULT);
    assert_int_equal(H.out.goal_id, 0);
}

/* A tracking fault's stop on the path whose end never settles is given up
 * in joint space after the settling time, and the goal, aborted with the
 * fault, is not aborted again (the soak once saw it: a second FAULT and
 * ABORTED a second after the first). The tool is pushed off the line here
 * by about 2 mm (between the tracking tolerance and the stop's), and the
 * IK's tolerance made 1e-30 m so that it never reports the tool settled. */
static void test_fault_stop_that_cannot_settle(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KT_PUMA_Q0);
    kc_pose to = pose_of(KT_PUMA_Q0);
    to.t.v[1] += KC_R(0.15);
    kc_goal g = kt_line_goal(91, &to);
    tick(&g, KC_CMD_NONE);
    for (int k = 0; k < 300; k++)
        tick(NULL, KC_CMD_NONE);
    assert_int_equal(H.out.state, KC_CTRL_MOVING);
    H.ctrl.q[0] += KC_R(0.003);
    int faults = 0, ends = 0;
    kc_ctrl_reason reason = KC_REASON_NONE;
    run_to_fault_counting(91, 1, 1, &faults, &ends, &reason);
    H.ctrl.cfg.ik.tol_pos = KC_R(1e-30);
    assert_int_equal(faults, 1); /* the tracking fault, */
    assert_int_equal(reason, KC_REASON_TRACKING);
    assert_int_equal(H.out.state, KC_CTRL_STOPPING);
    assert_int_equal(H.out.goal_id, 91); /* its stop on the path, */
    int ticks = run_to_fault_counting(91, 1, 20000, &faults, &ends, &reason);
    assert_true(ticks > 1000); /* given up after the settling time, */
    assert_int_equal(faults, 1);
    assert_int_equal(ends, 1); /* the goal ended once */
    assert_int_equal(H.out.state, KC_CTRL_FAULT);
    assert_int_equal(H.out.goal_id, 0);
}

/* kc_ctrl_cfg_check_field names the first field it refuses, and for a
 * joint's rate limit the joint; kc_ctrl_cfg_check agrees with it. */
static void test_cfg_field(void **state)
{
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl_cfg_field field;
    int joint;
    (void)state;
    assert_int_equal(kc_chain_init_model(&chain, KC_MODEL_PUMA560, NULL), KC_OK);
    cfg = kc_ctrl_cfg_default();
    assert_int_equal(kc_ctrl_cfg_check_field(&cfg, &chain, &field, &joint), KC_OK);
    assert_int_equal(field, KC_CFG_FIELD_NONE);
    assert_int_equal(joint, -1);
    cfg.cart_alpha = KC_R(0.0);
    assert_int_equal(kc_ctrl_cfg_check_field(&cfg, &chain, &field, &joint), KC_E_ARG);
    assert_int_equal(field, KC_CFG_FIELD_CART_ALPHA);
    assert_int_equal(kc_ctrl_cfg_check(&cfg, &chain), KC_E_ARG);
    cfg = kc_ctrl_cfg_default();
    cfg.dt = KC_R(-0.001);
    assert_int_equal(kc_ctrl_cfg_check_field(&cfg, &chain, &field, NULL), KC_E_ARG);
    assert_int_equal(field, KC_CFG_FIELD_DT);
    cfg = kc_ctrl_cfg_default();
    chain.joints[4].limits.qdd_max = kc_joint_limits_default().qdd_max; /* infinite: no limit */
    assert_int_equal(kc_ctrl_cfg_check_field(&cfg, &chain, &field, &joint), KC_E_ARG);
    assert_int_equal(field, KC_CFG_FIELD_JOINT_QDD_MAX);
    assert_int_equal(joint, 4);
    chain.joints[2].limits.qd_max = kc_joint_limits_default().qd_max;
    assert_int_equal(kc_ctrl_cfg_check_field(&cfg, &chain, &field, &joint), KC_E_ARG);
    assert_int_equal(field, KC_CFG_FIELD_JOINT_QD_MAX);
    assert_int_equal(joint, 2);
    assert_int_equal(kc_ctrl_cfg_check_field(NULL, &chain, &field, &joint), KC_E_ARG);
    assert_int_equal(field, KC_CFG_FIELD_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cfg_field),
        cmocka_unit_test(test_joint_goal),        cmocka_unit_test(test_line_goal),
        cmocka_unit_test(test_line_at_slow_periods),
        cmocka_unit_test(test_arc_and_paths),     cmocka_unit_test(test_queue_and_preemption),
        cmocka_unit_test(test_stop_pause_resume), cmocka_unit_test(test_estop_and_reset),
        cmocka_unit_test(test_external_fault),    cmocka_unit_test(test_seat),
        cmocka_unit_test(test_rejections),        cmocka_unit_test(test_servo),
        cmocka_unit_test(test_dry_run),           cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_path_pause_stop),   cmocka_unit_test(test_lagrange_path),
        cmocka_unit_test(test_retarget), cmocka_unit_test(test_outside_a_limit),
        cmocka_unit_test(test_final_check_on_the_last_tick_of_a_stop),
        cmocka_unit_test(test_fault_stop_that_cannot_settle),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl");
    return failed;
}
