/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_servoblend.c - a servo stream replaced by a line, an arc or a
 * Cartesian path without stopping (kinctl/ctrl.h): the stream's
 * jerk-limited halt, joint by joint, superposed on the new goal, which
 * takes over in the tick it arrives (ACCEPTED with KC_REASON_NONE, not
 * KC_REASON_STOP_FIRST). Streams of random speeds and accelerations (a
 * target pose moving by sums of sines) on the PUMA 560, replaced at
 * random moments by each Cartesian kind. From the replacement on, every
 * tick is checked: q inside its limits, |qd| <= qd_max, |qdd| <= qdd_max
 * and the jerk, the change of qdd over one tick divided by dt (the first
 * from the stream's last tick), <= qddd_max until the new goal moves,
 * each with the relative slack of test_ctrl_blend.c (SLACK); q moves by
 * no more than qd_max dt and qd by no more than qdd_max dt (continuity);
 * the goal ends at its target. A Cartesian goal is bounded in Cartesian
 * jerk, not in its joints' (on its own, a line here asks up to 1.5-2
 * times the elbow's qddd_max): once it moves, each joint's jerk is held
 * to its limit (the halt's) plus what the goal alone asks of that joint.
 * The 7-joint Panda's streams replaced by lines the same way (the halt
 * fed to the IK step in the task's null space too). The fallback: a
 * chain without jerk limits (no jerk-limited halt to plan) stops first
 * and says so. */
#include <math.h>
#include <string.h>

#include "testutil.h"

/* Rounding allowed in the per-tick checks (relative to the limit), as in
 * test_ctrl_blend.c; the end within the IK's tolerance. The jerk is
 * judged in double: in float the IK step's setpoints carry rounding
 * noise of about 1e-4 rad/s in qd a tick (float q near 2.4 rad has a
 * unit of 2.4e-7 rad, and the step's error feedback returns it), whose
 * second difference over a 1 ms tick is several hundred rad/s^3: 10-20
 * times the PUMA's 50 rad/s^3 in any Cartesian motion, with or without a
 * superposition (measured here: printed, not judged). */
/* KINDS_RUN: the Cartesian kinds run. The float build draws other cases
 * (CASES), and its first Cartesian path (seed 2019's) passes near the
 * wrist's singularity (q5 from 0.32 to 0.2 rad): joint 4 would need more
 * than its qdd_max, the IK step's scaling holds it there, the tool falls
 * 1 mm behind and the controller faults, given alone from rest where the
 * halt ends as superposed (a path the arm cannot follow, not a limit of
 * float or of the superposition); float runs the line and the arc. */
#ifdef KC_REAL_FLOAT
#define SLACK 1e-4
#define TOL_POSE 1e-4
#define CASES 4
#define JUDGE_JERK 0
#define KINDS_RUN 2
#else
#define SLACK 1e-6
#define TOL_POSE 1e-6
#define CASES 8
#define JUDGE_JERK 1
#define KINDS_RUN 3
#endif
/* Once the new goal moves, the jerk is held to the limit plus what the
 * goal alone asks of the joint, that run from the rest of a plain STOP:
 * up to dt/2 |qd| (about 1e-3 rad) from where the superposition's halt
 * rests (ctrl_blend.c stop_euler), where the goal's own joint jerk
 * differs by a fraction of a percent; ALONE_REL allows that. */
#define ALONE_REL 0.05

typedef struct harness {
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    double q_prev[KC_MAX_JOINTS], qd_prev[KC_MAX_JOINTS], qdd_prev[KC_MAX_JOINTS];
    /* 1: every tick checked against every limit; 2: the jerk held to its
     * limit while the new goal has not started (c->k0: its tick 0), then
     * to its limit plus what the new goal alone asks of the joint
     * (alone[j], over the limit). */
    int check;
    double alone[KC_MAX_JOINTS];
    double worst[3]; /* the largest |qd|, |qdd| and jerk (before the new goal moves) over their limits */
    /* Once the new goal moves: the largest jerk over the limit plus the
     * goal's own (alone[j]), and the goal's own over the limit. */
    double worst_g, worst_alone;
    int events[8];
    kc_pose start;    /* the tool pose at the start */
    kt_stream stream; /* the servo stream, from start */
} harness;

static harness H; /* large: not on the stack */

static const kc_real PANDA_Q0[7] = {KC_R(0.0), KC_R(-0.785), KC_R(0.0), KC_R(-2.356), KC_R(0.0), KC_R(1.571),
                                    KC_R(0.785)};

/* The model's arm at rest at its start, with the Cartesian limits of
 * test_ctrl_blend.c (the PUMA follows them around KT_PUMA_Q0 within its
 * joints' limits); no_jerk: its jerk limits infinite. */
static void setup(kc_model model, int no_jerk)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, model, NULL), KC_OK);
    if (no_jerk)
        for (int j = 0; j < H.chain.n_joints; j++)
            H.chain.joints[j].limits.qddd_max = (kc_real)INFINITY;
    H.cfg = kc_ctrl_cfg_default();
    H.cfg.cart_speed = KC_R(0.15);
    H.cfg.cart_accel = KC_R(0.3);
    const kc_real *q0 = model == KC_MODEL_PUMA560 ? KT_PUMA_Q0 : PANDA_Q0;
    assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, q0), KC_OK);
    kc_fk_eval(&H.chain, q0, &H.start);
    for (int j = 0; j < H.chain.n_joints; j++)
        H.q_prev[j] = (double)q0[j];
}

/* One tick; from the replacement on, checked against every limit and the
 * tick before. */
static void tick(const kc_goal *g)
{
    kc_ctrl_input in = {g, KC_CMD_NONE, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    double dt = (double)H.cfg.dt;
    for (int j = 0; j < H.chain.n_joints; j++) {
        const kc_joint_limits *l = &H.chain.joints[j].limits;
        double q = (double)H.out.q[j], qd = (double)H.out.qd[j], qdd = (double)H.out.qdd[j];
        double qp = H.q_prev[j], qdp = H.qd_prev[j], qddp = H.qdd_prev[j];
        if (H.check) {
            double rv = fabs(qd) / (double)l->qd_max, ra = fabs(qdd) / (double)l->qdd_max;
            double rj = fabs(qdd - qddp) / dt / (double)l->qddd_max;
            /* The new goal enters the setpoint two ticks after its tick 0
             * (the IK step heads from the target at the tick before). */
            int before_g = H.check == 1 || H.out.cycle < H.ctrl.k0 + 2;
            double j_bound = 1.0 + (before_g ? 0.0 : H.alone[j] * (1.0 + ALONE_REL));
            double dv = fabs(qd - qdp), dq = fabs(q - qp);
            if (!(q >= (double)l->q_min && q <= (double)l->q_max && rv <= 1.0 + SLACK && ra <= 1.0 + SLACK &&
                  (rj <= j_bound + SLACK || !JUDGE_JERK) && dq <= (double)l->qd_max * dt * (1.0 + SLACK) &&
                  dv <= (double)l->qdd_max * dt * (1.0 + SLACK) + SLACK * fabs(qdp)))
                fail_msg("cycle %ld joint %d (state %d, superposed %d): q %.9g, |qd| %.7g, |qdd| %.7g, jerk %.7g "
                         "of the limits (jerk bound %.7g), q step %.4g, qd step %.4g",
                         (long)H.out.cycle, j, H.out.state, H.ctrl.blend.on, q, rv, ra, rj, j_bound, dq, dv);
            H.worst[0] = fmax(H.worst[0], rv);
            H.worst[1] = fmax(H.worst[1], ra);
            if (before_g)
                H.worst[2] = fmax(H.worst[2], rj);
            else
                H.worst_g = fmax(H.worst_g, rj / (1.0 + H.alone[j]));
        }
        H.q_prev[j] = q;
        H.qd_prev[j] = qd;
        H.qdd_prev[j] = qdd;
    }
    for (int e = 0; e < H.out.n_events; e++)
        H.events[H.out.events[e].kind]++;
}

/* Streams servo goal id for n ticks (its messages one a tick). */
static void stream(int64_t id, int n)
{
    for (int k = 0; k < n; k++) {
        kc_goal g = kt_stream_next(&H.stream, id);
        tick(&g);
        assert_int_equal(H.out.goal_id, id);
    }
    assert_int_equal(H.out.state, KC_CTRL_MOVING);
}

/* Where the tool comes to rest if the stream stops now (the same halt the
 * replacement superposes), from a copy of the controller through a STOP. */
static kc_ctrl SIM;
static kc_pose rest_ahead(void) { return kt_rest_on_stop(&SIM, &H.ctrl); }

/* The largest jerk over its limit (the change of qdd over a tick) that
 * goal g asks of each joint on its own, into H.alone: run from rest where
 * the stream's stop ends (SIM, as rest_ahead leaves it). A Cartesian goal
 * is bounded in Cartesian jerk, not in its joints': on the PUMA near
 * KT_PUMA_Q0 its lines and arcs, at these limits, ask up to about 1.5
 * times the elbow's qddd_max. */
static void plain_jerk(const kc_goal *g)
{
    kc_goal a = *g;
    a.replace = 0;
    kc_ctrl_output out;
    kc_ctrl_input in = {&a, KC_CMD_NONE, 0, KC_REASON_NONE};
    double qdd_prev[KC_MAX_JOINTS] = {0.0}, dt = (double)H.cfg.dt;
    memset(H.alone, 0, sizeof H.alone);
    for (int k = 0; k < 20000; k++) {
        assert_int_equal(kc_ctrl_step(&SIM, &in, &out), KC_OK);
        in.goal = NULL;
        for (int j = 0; j < H.chain.n_joints; j++) {
            double qdd = (double)out.qdd[j];
            double rj = fabs(qdd - qdd_prev[j]) / dt / (double)H.chain.joints[j].limits.qddd_max;
            H.alone[j] = fmax(H.alone[j], rj);
            H.worst_alone = fmax(H.worst_alone, rj);
            qdd_prev[j] = qdd;
        }
        if (kt_has_event(&out, KC_EVENT_COMPLETED, a.id))
            return;
    }
    fail_msg("goal %ld (kind %d) alone did not complete (state %d, %s)", (long)a.id, a.kind, out.state, kc_ctrl_reason_str(SIM.fault_reason));
}

static kc_vec3 random_offset(kt_rng *r, double lo, double hi)
{
    kc_vec3 d = kt_rand_unit(r), o;
    kc_vec3_scale(&d, (kc_real)kt_uniform(r, lo, hi), &o);
    return o;
}

/* A random Cartesian goal of that kind from the tool pose home: a line
 * 3-8 cm away turning the tool by up to 0.1 rad; an arc 6-10 cm ahead
 * bent by 3-8 % of its chord; a path
 * through two points 3-6 cm away (parabolic blends). */
static kc_goal random_goal(kt_rng *r, kc_goal_kind kind, int64_t id, kc_pose home)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = kind;
    g.replace = 1;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.orient = KC_INTERP_SLERP;
    g.pose = home;
    if (kind == KC_GOAL_LINE) {
        kc_vec3 d = random_offset(r, 0.03, 0.08), axis = kt_rand_unit(r), rv;
        kc_mat3 dR;
        kc_quat dq;
        kc_vec3_scale(&axis, (kc_real)kt_uniform(r, 0.0, 0.1), &rv);
        kc_quat_exp(&rv, &dq);
        kc_quat_to_mat3(&dq, &dR);
        kc_vec3_add(&home.t, &d, &g.pose.t);
        kc_mat3_mul(&dR, &home.R, &g.pose.R);
    } else if (kind == KC_GOAL_ARC) {
        /* In a plane near the one across the wrist roll's axis at
         * KT_PUMA_Q0 (the widest range: the tool turns with the arc about
         * its normal), as test_ctrl_blend.c's. */
        kc_vec3 n, t = kt_rand_unit(r), d, e;
        kc_jacobian jac;
        kc_fk_jacobian(&H.chain, KT_PUMA_Q0, &jac, NULL);
        for (int k = 0; k < 3; k++)
            n.v[k] = jac.m[3 + k][5] + KC_R(0.2) * t.v[k];
        t = kt_rand_unit(r);
        kc_vec3_cross(&n, &t, &d);
        kc_vec3_scale(&d, KC_R(1.0) / kc_vec3_norm(&d), &d);
        kc_vec3_cross(&n, &d, &e);
        kc_vec3_scale(&e, KC_R(1.0) / kc_vec3_norm(&e), &e);
        kc_real chord = (kc_real)kt_uniform(r, 0.06, 0.1), bend = chord * (kc_real)kt_uniform(r, 0.03, 0.08);
        for (int k = 0; k < 3; k++) {
            g.via.v[k] = home.t.v[k] + chord / 2 * d.v[k] + bend * e.v[k];
            g.pose.t.v[k] = home.t.v[k] + chord * d.v[k];
        }
    } else {
        kc_quat q;
        kc_quat_from_mat3(&home.R, &q);
        g.method = KC_PATH_BLEND;
        g.n_points = 2;
        for (int i = 0; i < 2; i++) {
            kc_vec3 d = random_offset(r, 0.03, 0.06);
            for (int k = 0; k < 3; k++)
                g.points[i][k] = home.t.v[k] + d.v[k];
            g.points[i][3] = q.w;
            g.points[i][4] = q.x;
            g.points[i][5] = q.y;
            g.points[i][6] = q.z;
        }
    }
    return g;
}

/* The reason of the last output's event of that kind for goal id, or -1. */
static int event_reason(kc_ctrl_event_kind kind, int64_t id)
{
    for (int e = 0; e < H.out.n_events; e++)
        if (H.out.events[e].kind == kind && H.out.events[e].goal_id == id)
            return (int)H.out.events[e].reason;
    return -1;
}

/* Ticks until goal g completes; its end reached within the IK's
 * tolerance. */
static void run_to_end(const kc_goal *g)
{
    int done = 0;
    for (int k = 0; k < 20000 && !done; k++) {
        tick(NULL);
        done = event_reason(KC_EVENT_COMPLETED, g->id) >= 0;
        if (H.events[KC_EVENT_FAULT] > 0)
            fail_msg("cycle %ld: fault (%s) on the way to goal %ld", (long)H.out.cycle,
                     kc_ctrl_reason_str(H.ctrl.fault_reason), (long)g->id);
    }
    assert_true(done);
    kc_vec3 end = g->kind == KC_GOAL_PATH_CART ? kc_vec3_make(g->points[1][0], g->points[1][1], g->points[1][2])
                                               : g->pose.t;
    kt_near_vec3(&H.out.pose.t, &end, TOL_POSE, "Cartesian end");
    if (g->kind == KC_GOAL_LINE)
        kt_near_mat3(&H.out.pose.R, &g->pose.R, TOL_POSE, "line's end orientation");
}

static const kc_goal_kind KINDS[3] = {KC_GOAL_LINE, KC_GOAL_ARC, KC_GOAL_PATH_CART};

/* Each Cartesian kind replacing a random stream at a random moment takes
 * over in that tick, superposed on the stream's halt. */
static void test_stream_replaced(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(2019);
    int overlapped = 0;
    double worst[5] = {0.0}; /* over the runs: H.worst, worst_g, worst_alone */
    for (int kind = 0; kind < KINDS_RUN; kind++)
        for (int c = 0; c < CASES; c++) {
            setup(KC_MODEL_PUMA560, 0);
            int64_t id = 100 + c;
            kt_stream_init(&H.stream, &r, &H.start, (double)H.cfg.dt);
            stream(id, 200 + (int)kt_uniform(&r, 0.0, 400.0));
            kc_goal g = random_goal(&r, KINDS[kind], 1000 + c, rest_ahead());
            if (JUDGE_JERK)
                plain_jerk(&g);
            H.check = 2;
            tick(&g);
            assert_int_equal(event_reason(KC_EVENT_ACCEPTED, g.id), KC_REASON_NONE);
            assert_int_equal(event_reason(KC_EVENT_PREEMPTED, id), KC_REASON_NONE);
            assert_int_equal(event_reason(KC_EVENT_STARTED, g.id), KC_REASON_NONE);
            assert_int_equal(H.out.state, KC_CTRL_MOVING);
            assert_int_equal(H.out.goal_id, g.id);
            assert_true(H.ctrl.blend.on);
            assert_int_equal(H.ctrl.blend.kind, KC_GOAL_SERVO);
            assert_int_equal(H.ctrl.blend.stop_drive, KC_DRIVE_HALT);
            overlapped += H.ctrl.k0 - H.ctrl.blend.k0 < H.ctrl.blend.stop_ticks;
            run_to_end(&g);
            assert_int_equal(H.events[KC_EVENT_FAULT], 0);
            assert_int_equal(H.events[KC_EVENT_ABORTED], 0);
            double w[5] = {H.worst[0], H.worst[1], H.worst[2], H.worst_g, H.worst_alone};
            for (int i = 0; i < 5; i++)
                worst[i] = fmax(worst[i], w[i]);
        }
    print_message("%d streams replaced, %d overlapping the halt; of the limits: |qd| at most %.4f, |qdd| %.4f, "
                  "the jerk %.4f until the new goal moves, then %.4f of the limit plus the goal's own (the goals alone: "
                  "%.4f of the limit) (%s)\n",
                  KINDS_RUN * CASES, overlapped, worst[0], worst[1], worst[2], worst[3], worst[4], KC_REAL_NAME);
    assert_true(overlapped > 0);
    if (JUDGE_JERK)
        assert_true(worst[2] > 0.5); /* the halts do use the jerk they are allowed */
}

/* The 7-joint Panda under the full task: a line replacing its stream at
 * a random moment takes over the same way, the halt's joint velocities
 * fed forward to the IK step in the task's null space (kc_ik_step_ff:
 * without them the step would drop the halt's null-space part, its
 * joint velocities jumping), every tick checked as above. */
static void test_redundant_replaced(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(2029);
    int overlapped = 0;
    double worst[4] = {0.0}; /* over the runs: H.worst, worst_g */
    for (int c = 0; c < CASES; c++) {
        setup(KC_MODEL_PANDA, 0);
        int64_t id = 100 + c;
        kt_stream_init(&H.stream, &r, &H.start, (double)H.cfg.dt);
        stream(id, 200 + (int)kt_uniform(&r, 0.0, 400.0));
        kc_goal g = random_goal(&r, KC_GOAL_LINE, 1000 + c, rest_ahead());
        if (JUDGE_JERK)
            plain_jerk(&g);
        H.check = 2;
        tick(&g);
        assert_int_equal(event_reason(KC_EVENT_ACCEPTED, g.id), KC_REASON_NONE);
        assert_true(H.ctrl.blend.on);
        assert_int_equal(H.ctrl.blend.kind, KC_GOAL_SERVO);
        overlapped += H.ctrl.k0 - H.ctrl.blend.k0 < H.ctrl.blend.stop_ticks;
        run_to_end(&g);
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
        assert_int_equal(H.events[KC_EVENT_ABORTED], 0);
        double w[4] = {H.worst[0], H.worst[1], H.worst[2], H.worst_g};
        for (int i = 0; i < 4; i++)
            worst[i] = fmax(worst[i], w[i]);
    }
    print_message("panda: %d streams replaced by a line, %d overlapping the halt; of the limits: |qd| at most %.4f, "
                  "|qdd| %.4f, the jerk %.4f until the line moves, then %.4f of the limit plus the line's own (%s)\n",
                  CASES, overlapped, worst[0], worst[1], worst[2], worst[3], KC_REAL_NAME);
    assert_true(overlapped > 0);
}

/* No transition where the halt cannot be planned jerk-limited: on a
 * chain without jerk limits the stream stops first, continuous and within
 * the limits (the jerk not judged: it has no limit), and the line still
 * ends at its end. */
static void test_stops_first(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(2029);
    setup(KC_MODEL_PUMA560, 1);
    kt_stream_init(&H.stream, &r, &H.start, (double)H.cfg.dt);
    stream(7, 300);
    kc_goal g = random_goal(&r, KC_GOAL_LINE, 8, rest_ahead());
    tick(&g);
    assert_int_equal(event_reason(KC_EVENT_ACCEPTED, g.id), KC_REASON_STOP_FIRST);
    assert_int_equal(H.out.state, KC_CTRL_STOPPING);
    assert_false(H.ctrl.blend.on);
    run_to_end(&g);
    assert_int_equal(H.events[KC_EVENT_FAULT], 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stream_replaced),
        cmocka_unit_test(test_redundant_replaced),
        cmocka_unit_test(test_stops_first),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl_servoblend");
    return rc;
}
