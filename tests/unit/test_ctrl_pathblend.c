/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_pathblend.c - a joint path replacing any moving goal without
 * stopping (kinctl/ctrl.h): the old motion's jerk-limited stop M, known
 * joint by joint (a joint move's on its line or joint by joint, every
 * other kind's joint by joint), superposed in joint space on the path G
 * planned from where M rests (q_s): q = q_M(t) + q_G(t - t0) - q_s.
 * Random joint moves, servo streams, lines, arcs, Cartesian paths and
 * joint paths on the PUMA 560, replaced at random moments by a joint path
 * through two knots near the joints (a quartic blend and a quintic, which
 * run on their own law; Lagrange's polynomial, which does not start at
 * rest, and a cubic spline, whose acceleration steps at its ends, which
 * run on the controller's jerk-limited ramps of tau', kc_ctrl_path_ramped),
 * and joint moves, servo streams, lines and joint paths on the 7-joint
 * Panda (no IK step in between: redundancy is no matter). The path takes
 * over in the tick it arrives (ACCEPTED with KC_REASON_NONE). Every tick
 * from the replacement on: the setpoint is that sum, computed here from
 * the plans the controller holds through the public evaluators (M's stops
 * in ctrl.blend, G in ctrl.plan.path on tau = t - t0 or on its ramp
 * ctrl.ramp, t0 from ctrl.k0); q inside its
 * limits, |qd| <= qd_max, |qdd| <= qdd_max, qd changing by at most
 * qdd_max dt (the final check's), and the jerk, the change of
 * qdd over one tick divided by dt, within qddd_max or what M or G alone
 * changes over that tick, where that is more (a parabolic blend's qdd
 * jumps), each with a relative slack of SLACK; the path ends on its last
 * knot exactly. A STOP while superposed stops the arm within its limits.
 * Under the trapezoid's law (the ramps at a constant rate: tau'' steps) a
 * Lagrange path and a natural spline stop first. */
#include <math.h>
#include <string.h>

#include "testutil.h"

/* The jerk's slack: the controller holds the sum to the joints' jerk
 * limits themselves (ctrl_internal.h, kc_ctrl_jerk_within), so in double to the
 * rounding of qdd; in float qdd's own rounding (a difference of qd over
 * a tick) is SLACK's size. */
#ifdef KC_REAL_FLOAT
#define SLACK 1e-4
#define JERK_SLACK SLACK
#define TOL_SUM 1e-5 /* rad: float rounding of the sum of three positions near 3 rad */
#define CASES 4
#else
#define SLACK 1e-6
#define JERK_SLACK 1e-9
#define TOL_SUM 1e-12
#define CASES 10
#endif

typedef struct harness {
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    double qdd_prev[KC_MAX_JOINTS], qd_prev[KC_MAX_JOINTS];
    double m_qdd_prev[KC_MAX_JOINTS], g_qdd_prev[KC_MAX_JOINTS];
    double worst_j; /* the largest jerk over its bound while superposed */
} harness;

static harness H; /* large: not on the stack */

static const kc_real PANDA_Q0[7] = {KC_R(0.0), KC_R(-0.785), KC_R(0.0), KC_R(-2.356), KC_R(0.0), KC_R(1.571),
                                    KC_R(0.785)};

/* The model's arm at rest at its start (the PUMA's KT_PUMA_Q0, the
 * Panda's PANDA_Q0) into H, *q0 set to it. */
static void setup_model(kc_model model, const kc_real **q0)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, model, NULL), KC_OK);
    H.cfg = kc_ctrl_cfg_default();
    *q0 = model == KC_MODEL_PUMA560 ? KT_PUMA_Q0 : PANDA_Q0;
    assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, *q0), KC_OK);
}

static void setup(void)
{
    const kc_real *q0;
    setup_model(KC_MODEL_PUMA560, &q0);
}

/* M's stop at its tick jm (>= 0), exactly: joint by joint, or on its line
 * q = q0 + dq u. */
static void stop_state(int64_t jm, kc_real *q, kc_real *qd, kc_real *qdd)
{
    const kc_ctrl_blend *b = &H.ctrl.blend;
    kc_scurve_state s;
    if (b->stop_drive == KC_DRIVE_SCURVE)
        kc_scurve_eval(&b->stop.scurve, jm, &s);
    for (int i = 0; i < H.chain.n_joints; i++) {
        if (b->stop_drive == KC_DRIVE_HALT) {
            kc_scurve_eval(&b->plan.halt[i], jm, &s);
            q[i] = s.p, qd[i] = s.v, qdd[i] = s.a;
        } else {
            q[i] = b->plan.joint.q0[i] + b->plan.joint.dq[i] * s.p;
            qd[i] = b->plan.joint.dq[i] * s.v;
            qdd[i] = b->plan.joint.dq[i] * s.a;
        }
    }
}

/* One tick; while superposed, the setpoint checked against the sum and
 * every limit. */
static void tick(const kc_goal *g)
{
    kc_ctrl_input in = {g, KC_CMD_NONE, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    const kc_ctrl *c = &H.ctrl;
    double dt = (double)H.cfg.dt;
    int64_t jm = H.out.cycle - c->blend.k0, jg = H.out.cycle - c->k0;
    int sum = c->goal.kind == KC_GOAL_PATH && c->blend.stop_drive != KC_DRIVE_NOMINAL && jm >= 1 &&
              jm <= c->blend.stop_ticks && c->state == KC_CTRL_MOVING;
    int n = H.chain.n_joints;
    kc_real qm[KC_MAX_JOINTS], qdm[KC_MAX_JOINTS], qddm[KC_MAX_JOINTS], qs[KC_MAX_JOINTS], qds[KC_MAX_JOINTS];
    kc_real qdds[KC_MAX_JOINTS], qg[KC_MAX_JOINTS], d1[KC_MAX_JOINTS], d2[KC_MAX_JOINTS];
    if (sum) {
        stop_state(jm, qm, qdm, qddm);
        stop_state(c->blend.stop_ticks, qs, qds, qdds);
        /* tau = t - t0, or on the path's ramp: q_G(tau), tau' q_G',
         * tau'^2 q_G'' + tau'' q_G' */
        kc_scurve_state u = {(kc_real)(jg < 0 ? 0 : jg) * H.cfg.dt, KC_R(1.0), KC_R(0.0), KC_R(0.0), 2};
        if (c->ramp_on)
            kc_scurve_eval(&c->ramp, jg < 0 ? 0 : jg, &u);
        kc_path_eval_time(&c->plan.path, u.p, qg, d1, d2);
        for (int j = 0; j < n; j++) {
            d2[j] = d2[j] * u.v * u.v + d1[j] * u.a;
            d1[j] *= u.v;
        }
        for (int j = 0; j < n && jg <= 0; j++)
            d1[j] = d2[j] = KC_R(0.0); /* at rest at its start until it starts */
    }
    for (int j = 0; j < n; j++) {
        const kc_joint_limits *l = &H.chain.joints[j].limits;
        double q = (double)H.out.q[j], qd = (double)H.out.qd[j], qdd = (double)H.out.qdd[j];
        if (sum) {
            /* The path's own law from rest (drive NOMINAL). */
            kt_near(q, (double)qm[j] + (double)qg[j] - (double)qs[j], TOL_SUM, "q = q_M + q_G - q_s");
            kt_near(qd, (double)qdm[j] + (double)d1[j], TOL_SUM / dt, "qd = qd_M + qd_G");
            double jerk = fabs(qdd - H.qdd_prev[j]) / dt;
            double own = fmax(fabs((double)qddm[j] - H.m_qdd_prev[j]), fabs((double)d2[j] - H.g_qdd_prev[j])) / dt;
            /* M's and G's qdd are evaluated here otherwise than in the
             * controller, which judged the sum against what either alone
             * does (G's ramp at its own jerk bound): 8 units of KC_REAL_EPS
             * of each, over dt, cover the difference (float: up to 0.005
             * rad/s^3 of the Panda's 6250 seen). */
            double jround = 8.0 * (double)KC_REAL_EPS * (fabs((double)qddm[j]) + fabs((double)d2[j])) / dt;
            double jb = fmax((double)l->qddd_max, own);
            double dv = fabs(qd - H.qd_prev[j]);
            if (!(q >= (double)l->q_min && q <= (double)l->q_max && fabs(qd) <= (double)l->qd_max * (1.0 + SLACK) &&
                  fabs(qdd) <= (double)l->qdd_max * (1.0 + SLACK) && jerk <= jb * (1.0 + JERK_SLACK) + jround &&
                  dv <= (double)l->qdd_max * dt * (1.0 + SLACK) + SLACK * fabs(H.qd_prev[j])))
                fail_msg("cycle %ld joint %d (M's tick %ld of %ld, G's %ld): q %.9g, |qd| %.6g, qdd %.6g (M %.6g, G "
                         "%.6g), jerk %.6g of %.6g",
                         (long)H.out.cycle, j, (long)jm, (long)c->blend.stop_ticks, (long)jg, q, fabs(qd), qdd,
                         (double)qddm[j], (double)d2[j], jerk, jb);
            H.worst_j = fmax(H.worst_j, jerk / jb);
        }
        H.m_qdd_prev[j] = sum ? (double)qddm[j] : 0.0;
        H.g_qdd_prev[j] = sum ? (double)d2[j] : 0.0;
        H.qdd_prev[j] = qdd;
        H.qd_prev[j] = qd;
    }
}

/* The reason of the output's event of that kind for goal id, or -1. */
static int event_reason(kc_ctrl_event_kind kind, int64_t id)
{
    for (int e = 0; e < H.out.n_events; e++)
        if (H.out.events[e].kind == kind && H.out.events[e].goal_id == id)
            return (int)H.out.events[e].reason;
    return -1;
}

/* A joint path from the joints now through two knots, each joint moving
 * on one way by 0.05-0.15 rad to the first and as much again to the
 * second, away from a position limit it would reach (a path timed from
 * the joints' limits: it starts at about their acceleration limits). */
static kc_goal path_goal(kt_rng *r, int64_t id, kc_path_method method)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = KC_GOAL_PATH;
    g.replace = 1;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.method = method;
    g.n_points = 2;
    for (int j = 0; j < H.chain.n_joints; j++) {
        kc_real d = (kc_real)(kt_uniform(r, 0.05, 0.15) * (kt_uniform(r, 0.0, 1.0) < 0.5 ? -1 : 1));
        /* away from a position limit the arm is near (the Panda's elbow,
         * q_max -0.07 rad): 0.1 rad to spare for the replaced motion's stop */
        const kc_joint_limits *l = &H.chain.joints[j].limits;
        if (H.out.q[j] + 2 * d > l->q_max - KC_R(0.1) || H.out.q[j] + 2 * d < l->q_min + KC_R(0.1))
            d = -d;
        g.points[0][j] = H.out.q[j] + d;
        g.points[1][j] = H.out.q[j] + 2 * d;
    }
    return g;
}

/* The motions replaced: on each arm (the Panda's qddd_max of twice
 * qdd_max per tick: the change of qd over a tick, the tick's mean qdd, is
 * far from the qdd at its end), the kind of goal. */
static const struct {
    kc_model model;
    kc_goal_kind kind;
} REPLACED[] = {
    {KC_MODEL_PUMA560, KC_GOAL_JOINT}, {KC_MODEL_PUMA560, KC_GOAL_SERVO}, {KC_MODEL_PANDA, KC_GOAL_JOINT},
    {KC_MODEL_PANDA, KC_GOAL_SERVO},   {KC_MODEL_PUMA560, KC_GOAL_LINE},  {KC_MODEL_PUMA560, KC_GOAL_ARC},
    {KC_MODEL_PUMA560, KC_GOAL_PATH_CART}, {KC_MODEL_PUMA560, KC_GOAL_PATH}, {KC_MODEL_PANDA, KC_GOAL_LINE},
    {KC_MODEL_PANDA, KC_GOAL_PATH},
};

/* The active segment's planned ticks (a Cartesian or joint path's
 * duration). */
static int64_t planned_ticks(void)
{
    const kc_ctrl *c = &H.ctrl;
    switch (c->goal.kind) {
    case KC_GOAL_LINE: return c->plan.line.ticks;
    case KC_GOAL_ARC: return c->plan.arc.ticks;
    case KC_GOAL_PATH_CART: return (int64_t)(c->plan.path_cart.pos.duration / c->cfg.dt);
    case KC_GOAL_PATH: return (int64_t)(c->plan.path.duration / c->cfg.dt);
    default: return c->plan.joint.ticks;
    }
}

/* Motion REPLACED[which] started from the arm's start and stepped to a
 * random tick; 1 when it is moving there (a joint path with a knot
 * beyond a limit is refused, a line the arm cannot follow faults: the
 * caller draws again). */
static int start_replaced(kt_rng *r, size_t which, kc_path_method method)
{
    const kc_real *q0;
    kc_goal_kind kind = REPLACED[which].kind;
    setup_model(REPLACED[which].model, &q0);
    int n = H.chain.n_joints;
    int64_t id = 1;
    if (kind != KC_GOAL_JOINT && kind != KC_GOAL_SERVO) {
        /* a line or an arc of 5 to 30 cm, a Cartesian path through
         * two points 3 to 8 cm apart, a joint path near the
         * joints, replaced at a random tick of its first 80 % */
        kc_goal a = kind == KC_GOAL_PATH_CART ? kt_cart_path_walk(r, id, KC_PATH_BLEND, &H.ctrl.pose, 0.03, 0.08)
                    : kind == KC_GOAL_PATH    ? path_goal(r, id, method)
                                              : kt_cart_goal(r, id, &H.ctrl.pose, kind == KC_GOAL_ARC, 0);
        a.replace = 0;
        tick(&a);
        int64_t at = 2 + (int64_t)kt_uniform(r, 0.0, 0.8 * (double)planned_ticks());
        for (int64_t k = 1; k < at; k++)
            tick(NULL);
    } else if (kind == KC_GOAL_JOINT) {
        /* a jerk-limited joint move, replaced at a random tick */
        kc_real to[KC_MAX_JOINTS];
        for (int j = 0; j < n; j++)
            to[j] = q0[j] + (kc_real)kt_uniform(r, -0.4, 0.4);
        kc_goal a = kt_joint_goal(id, to, n);
        tick(&a);
        int64_t at = 2 + (int64_t)kt_uniform(r, 0.0, (double)(H.ctrl.plan.joint.ticks - 4));
        for (int64_t k = 1; k < at; k++)
            tick(NULL);
    } else {
        /* a servo stream, its target moving at up to 0.1 m/s */
        kc_goal s;
        memset(&s, 0, sizeof s);
        s.id = id;
        s.kind = KC_GOAL_SERVO;
        s.vel_scale = s.acc_scale = KC_R(1.0);
        s.servo_twist = 1;
        kc_vec3 u = kt_rand_unit(r);
        for (int k = 0; k < 3; k++)
            s.twist[k] = (kc_real)kt_uniform(r, 0.02, 0.1) * u.v[k];
        int ticks = 100 + (int)kt_uniform(r, 0.0, 400.0);
        for (int k = 0; k < ticks; k++)
            tick(&s);
    }
    return H.out.state == KC_CTRL_MOVING;
}

static void test_replaced_by_a_path(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(3019);
    const kc_path_method methods[4] = {KC_PATH_BLEND, KC_PATH_QUINTIC, KC_PATH_LAGRANGE, KC_PATH_SPLINE};
    int ramped = 0;
    int overlapped = 0, cases = 0;
    double worst = 0.0;
    for (size_t which = 0; which < sizeof REPLACED / sizeof REPLACED[0]; which++)
        for (int c = 0; c < CASES; c++) {
            int tries = 0;
            while (!start_replaced(&r, which, methods[c % 4]))
                assert_true(++tries < 20);
            kc_goal g = path_goal(&r, 2, methods[c % 4]);
            tick(&g);
            assert_int_equal(event_reason(KC_EVENT_ACCEPTED, g.id), KC_REASON_NONE);
            assert_int_equal(event_reason(KC_EVENT_PREEMPTED, 1), KC_REASON_NONE);
            assert_int_equal(event_reason(KC_EVENT_STARTED, g.id), KC_REASON_NONE);
            assert_true(H.ctrl.blend.on);
            assert_int_equal(H.ctrl.ramp_on, c % 4 >= 2);
            ramped += H.ctrl.ramp_on;
            overlapped += H.ctrl.k0 - H.ctrl.blend.k0 < H.ctrl.blend.stop_ticks;
            int done = 0;
            for (int k = 0; k < 20000 && !done; k++) {
                tick(NULL);
                done = event_reason(KC_EVENT_COMPLETED, g.id) >= 0;
                assert_int_equal(H.out.state == KC_CTRL_FAULT, 0);
            }
            assert_true(done);
            for (int j = 0; j < H.chain.n_joints; j++)
                assert_true(H.out.q[j] == g.points[1][j]);
            worst = fmax(worst, H.worst_j);
            cases++;
        }
    print_message("%d joint moves, servo streams, lines, arcs, Cartesian and joint paths (PUMA 560, Panda) replaced "
                  "by a joint path (%d on its ramps), %d overlapping the stop; the jerk while superposed at most %.9f "
                  "of its bound (%s)\n",
                  cases, ramped, overlapped, worst, KC_REAL_NAME);
    assert_true(overlapped > 0);
    assert_true(ramped > 0);
}

/* A STOP while a path is superposed on a joint move's stop: the path
 * stops on its own law while the move's stop goes on; the arm comes to
 * rest, idle, every tick within the joints' velocity limits and each
 * joint's qd changing by at most qdd_max dt (kinctl/ctrl.h: the two stops
 * add up while they overlap). */
static void test_stop_while_superposed(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(3039);
    int stopped = 0, ramped = 0;
    for (int c = 0; c < CASES; c++) {
        setup();
        kc_real to[6];
        for (int j = 0; j < 6; j++)
            to[j] = KT_PUMA_Q0[j] + (kc_real)kt_uniform(&r, -0.4, 0.4);
        kc_goal a = kt_joint_goal(1, to, 6);
        tick(&a);
        int64_t at = 2 + (int64_t)kt_uniform(&r, 0.0, (double)(H.ctrl.plan.joint.ticks - 4));
        for (int64_t k = 1; k < at; k++)
            tick(NULL);
        const kc_path_method methods[3] = {KC_PATH_QUINTIC, KC_PATH_LAGRANGE, KC_PATH_SPLINE};
        kc_goal g = path_goal(&r, 2, methods[c % 3]);
        tick(&g);
        assert_true(H.ctrl.blend.on);
        assert_int_equal(H.ctrl.ramp_on, c % 3 > 0);
        int64_t overlap_end = H.ctrl.blend.k0 + H.ctrl.blend.stop_ticks;
        if (H.ctrl.k0 + 2 >= overlap_end)
            continue; /* no overlap to stop in */
        while (H.out.cycle < H.ctrl.k0 + 2)
            tick(NULL);
        kc_ctrl_input in = {NULL, KC_CMD_STOP, 0, KC_REASON_NONE};
        for (int k = 0; k < 20000 && (k == 0 || H.out.state != KC_CTRL_IDLE); k++) {
            assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
            in.command = KC_CMD_NONE;
            for (int j = 0; j < 6; j++) {
                const kc_joint_limits *l = &H.chain.joints[j].limits;
                double qd = (double)H.out.qd[j];
                if (!(fabs(qd) <= (double)l->qd_max * (1.0 + SLACK) &&
                      fabs(qd - H.qd_prev[j]) <= (double)l->qdd_max * (double)H.cfg.dt * (1.0 + SLACK)))
                    fail_msg("cycle %ld joint %d: qd %.6g after %.6g", (long)H.out.cycle, j, qd, H.qd_prev[j]);
                H.qd_prev[j] = qd;
            }
            assert_true(H.out.state != KC_CTRL_FAULT);
        }
        assert_int_equal(H.out.state, KC_CTRL_IDLE);
        for (int j = 0; j < 6; j++)
            assert_true(H.out.qd[j] == KC_R(0.0));
        stopped++;
        ramped += c % 3 > 0;
    }
    print_message("%d paths stopped while superposed, %d of them on their ramps (%s)\n", stopped, ramped,
                  KC_REAL_NAME);
    assert_true(stopped > 0 && ramped > 0);
}

/* Under the trapezoid's law a path the controller ramps (Lagrange's
 * polynomial, which does not start at rest; a natural spline) ramps tau'
 * at a constant rate, its tau'' stepping at rest: not superposed, the move
 * stops first, and the path still ends on its last knot exactly. */
static void test_constant_rate_ramps_stop_first(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(3029);
    const kc_path_method methods[2] = {KC_PATH_LAGRANGE, KC_PATH_SPLINE};
    for (int m = 0; m < 2; m++) {
        setup();
        kc_real to[6];
        for (int j = 0; j < 6; j++)
            to[j] = KT_PUMA_Q0[j] + KC_R(0.3);
        kc_goal a = kt_joint_goal(1, to, 6);
        tick(&a);
        for (int k = 0; k < 200; k++)
            tick(NULL);
        kc_goal g = path_goal(&r, 2, methods[m]);
        g.profile = KC_GOAL_PROFILE_TRAPEZOID;
        g.spline_end = KC_PATH_SPLINE_NATURAL;
        tick(&g);
        assert_int_equal(event_reason(KC_EVENT_ACCEPTED, g.id), KC_REASON_STOP_FIRST);
        assert_false(H.ctrl.blend.on);
        int done = 0;
        for (int k = 0; k < 20000 && !done; k++) {
            tick(NULL);
            done = event_reason(KC_EVENT_COMPLETED, g.id) >= 0;
        }
        assert_true(done);
        for (int j = 0; j < 6; j++)
            assert_true(H.out.q[j] == g.points[1][j]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_replaced_by_a_path),
        cmocka_unit_test(test_stop_while_superposed),
        cmocka_unit_test(test_constant_rate_ramps_stop_first),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl_pathblend");
    return rc;
}
