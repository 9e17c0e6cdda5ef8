/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_pathstop.c - a joint path stopped on its path keeps the
 * final check (kinctl/ctrl.h): random joint paths through two knots near
 * a pose of the PUMA 560 and of the Panda (blends, cubic splines and
 * quintics, timed from the joints' limits), each stopped by STOP at a
 * random tick, in its first twenty ticks or anywhere. Every tick from the
 * STOP to rest: no FAULT (a stop that steps qd by more than qdd_max dt
 * fails the final check: limit_guard), |qdd| <= qdd_max, qd changing by
 * at most qdd_max dt, qd within qd_max, each with the relative slack of
 * the controller's final check (cfg.limit_slack); qdd changing by at
 * most qddd_max dt (JERK_SLACK, below); the stop ends at rest,
 * idle. Its rate keeps the limits on sampled instants of the constant-rate
 * stop; a jerk-limited stop lingers near the speed it starts from, and a
 * stop of a few ticks is far from its continuous law: before the stop was
 * checked on every tick, Panda quintics stopped in their first ticks
 * stepped qd by up to 1.0047 qdd_max dt (2 of 3,000 cases stopped
 * anywhere). The same for a joint path superposed on the stop of the
 * joint move it replaced (superposed_stops). Printed: how many stops
 * waited for one that fits (the path going on meanwhile) and the longest
 * wait; at five times the cases, the last of the four plans kept
 * unchecked faulted one PUMA 560 stop and took a Panda's qdd to 1.0003
 * qdd_max, before a stop that still fails waited too. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "testutil.h"

/* The joints' jerk on every tick of a stop, the change of qdd over it,
 * within qddd_max dt and JERK_SLACK of it: in double the rounding of qdd,
 * in float its rounding from q's (measured up to 1.00016). */
#ifdef KC_REAL_FLOAT
#define CASES kt_cases(1000)
#define JERK_SLACK 5e-4
#else
#define CASES kt_cases(3000)
#define JERK_SLACK 1e-9
#endif

static kc_chain CHAIN;
static kc_ctrl CTRL;
static kc_ctrl_output OUT;

static const kc_real PUMA_HOME[6] = {KC_R(0.0), KC_R(0.7854), KC_R(-3.1416), KC_R(0.0), KC_R(0.7854), KC_R(0.0)};
static const kc_real PANDA_HOME[7] = {KC_R(0.0), KC_R(-0.3), KC_R(0.0), KC_R(-2.0),
                                      KC_R(0.0), KC_R(1.8),  KC_R(0.8)};

/* One tick; returns whether it raised a FAULT. */
static int tick(const kc_goal *g, kc_ctrl_command cmd)
{
    kc_ctrl_input in = {g, cmd, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&CTRL, &in, &OUT), KC_OK);
    for (int e = 0; e < OUT.n_events; e++)
        if (OUT.events[e].kind == KC_EVENT_FAULT)
            return 1;
    return 0;
}

/* Joints home plus -0.5 to 0.5 rad each, drawn in turn. */
static void near(kt_rng *r, const kc_real *home, int n, kc_real *q)
{
    for (int j = 0; j < n; j++)
        q[j] = home[j] + (kc_real)kt_uniform(r, -0.5, 0.5);
}

/* A joint path (method: 0 blend, 1 spline, 2 quintic) through two knots
 * near home, timed from the joints' limits. */
static kc_goal path_goal(kt_rng *r, int64_t id, const kc_real *home, int method, int replace)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = KC_GOAL_PATH;
    g.replace = replace;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    const kc_path_method methods[3] = {KC_PATH_BLEND, KC_PATH_SPLINE, KC_PATH_QUINTIC};
    g.method = methods[method];
    g.n_points = 2;
    g.dim = CHAIN.n_joints;
    for (int k = 0; k < 2; k++)
        near(r, home, CHAIN.n_joints, g.points[k]);
    return g;
}

/* The most ticks a path went on after its STOP, waiting for a stop that
 * keeps the limits (KC_DRIVE_STOPPING_WAIT: none fits from where it is,
 * kinctl/ctrl.h), and the stops that waited, in the suite so far. */
static int LONGEST_WAIT, WAITED;
/* The largest jerk of a stop (of qddd_max) in the suite so far. */
static double WORST_JERK;

/* STOP, then every tick to rest checked (above); name names the case in
 * a failure. Returns the largest |qdd| or step of qd over its limit, or
 * worst if larger. */
static double stop_to_rest(const char *name, double worst)
{
    int waiting = 0;
    kc_ctrl_cfg cfg = CTRL.cfg;
    int n = CHAIN.n_joints;
    /* The final check's slack as the controller applies it, in its own
     * precision: fl(limit * fl(1 + limit_slack)), within 2 units of
     * KC_REAL_EPS of (1 + limit_slack) exactly (float: a superposed sum
     * admitted at qdd 5.0005002 of 5, 1.00010004 of it, above 1 + the
     * float 1e-4 as a double, 1.0000999999747). */
    double slack = (double)cfg.limit_slack + 2.0 * (double)KC_REAL_EPS, dt = (double)cfg.dt, qd[KC_MAX_JOINTS];
    double qdd[KC_MAX_JOINTS];
    for (int j = 0; j < n; j++) {
        qd[j] = (double)OUT.qd[j];
        qdd[j] = (double)OUT.qdd[j];
    }
    kc_ctrl_command cmd = KC_CMD_STOP;
    for (int k = 0; k < 20000 && (k == 0 || OUT.state != KC_CTRL_IDLE); k++, cmd = KC_CMD_NONE) {
        if (tick(NULL, cmd))
            fail_msg("%s: FAULT %d on the stop's tick %d", name, (int)OUT.events[0].reason, k);
        if (CTRL.drive == KC_DRIVE_STOPPING_WAIT) {
            WAITED += waiting == 0;
            LONGEST_WAIT = waiting + 1 > LONGEST_WAIT ? waiting + 1 : LONGEST_WAIT;
            waiting++;
        }
        for (int j = 0; j < n; j++) {
            const kc_joint_limits *l = &CHAIN.joints[j].limits;
            double A = (double)l->qdd_max, v = (double)OUT.qd[j];
            double ra = fmax(fabs((double)OUT.qdd[j]) / A, fabs(v - qd[j]) / (A * dt));
            worst = fmax(worst, ra);
            if (!(ra <= 1.0 + slack) || !(fabs(v) <= (double)l->qd_max * (1.0 + slack)))
                fail_msg("%s, the stop's tick %d, joint %d: qdd %.9g, qd %.9g -> %.9g (qdd_max %g)", name, k, j,
                         (double)OUT.qdd[j], qd[j], v, A);
            qd[j] = v;
            double rj = fabs((double)OUT.qdd[j] - qdd[j]) / ((double)l->qddd_max * dt);
            if (!(rj <= 1.0 + JERK_SLACK))
                fail_msg("%s, the stop's tick %d, joint %d: qdd %.9g -> %.9g, jerk %.9f of qddd_max %g", name, k, j,
                         qdd[j], (double)OUT.qdd[j], rj, (double)l->qddd_max);
            WORST_JERK = fmax(WORST_JERK, rj);
            qdd[j] = (double)OUT.qdd[j];
        }
    }
    assert_int_equal(OUT.state, KC_CTRL_IDLE);
    for (int j = 0; j < n; j++)
        assert_true(OUT.qd[j] == KC_R(0.0));
    return worst;
}

static void random_stops(kc_model model, const kc_real *home, uint64_t seed)
{
    kt_rng r = kt_rng_make(seed);
    assert_int_equal(kc_chain_init_model(&CHAIN, model, NULL), KC_OK);
    kc_ctrl_cfg cfg = kc_ctrl_cfg_default();
    int n = CHAIN.n_joints;
    int early = 0, stopped = 0;
    double worst = 0.0;
    char name[96];
    for (int c = 0; c < CASES; c++) {
        kc_real q0[KC_MAX_JOINTS];
        near(&r, home, n, q0);
        assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &cfg, q0), KC_OK);
        kc_goal g = path_goal(&r, 1, home, c % 3, 0);
        assert_int_equal(tick(&g, KC_CMD_NONE), 0);
        assert_int_equal(OUT.state, KC_CTRL_MOVING);
        int64_t ticks = CTRL.plan.path.ticks;
        int64_t at = c % 2 ? 1 + (int64_t)kt_uniform(&r, 0.0, 20.0) : 1 + (int64_t)kt_uniform(&r, 0.0, (double)ticks);
        for (int64_t k = 1; k < at && OUT.state == KC_CTRL_MOVING; k++)
            assert_int_equal(tick(NULL, KC_CMD_NONE), 0);
        if (OUT.state != KC_CTRL_MOVING)
            continue; /* a path shorter than the tick drawn */
        stopped++;
        early += at <= 20;
        snprintf(name, sizeof name, "case %d (method %d), stopped at tick %ld of %ld", c, c % 3, (long)at,
                 (long)ticks);
        worst = stop_to_rest(name, worst);
    }
    print_message("%d-joint arm: %d paths stopped (%d in their first 20 ticks), worst |qdd| or qd step %.9f of "
                  "qdd_max; so far %d stops waited for one that fits, at most %d ticks; the joints' jerk at most %.9f "
                  "of qddd_max\n",
                  n, stopped, early, worst, WAITED, LONGEST_WAIT, WORST_JERK);
    assert_true(stopped > CASES / 2 && early > CASES / 4);
}

/* A jerk-limited joint move replaced at a random tick by a joint path
 * superposed on its stop (ctrl_blend.c), then STOP 0 to 30 ticks later
 * or (half the cases) in the path's first 20 ticks, while the
 * superposition lasts: the path not yet started or moving.
 * Every tick from the STOP to rest as above. Before the path's stop
 * looked at the stop under it, 30 % (PUMA 560) and 42 % (Panda) of such
 * STOPs faulted limit_guard; before it looked at the joints' jerk there,
 * the sum took a joint to 1.70 times its jerk limit. */
static void superposed_stops(kc_model model, const kc_real *home, uint64_t seed)
{
    kt_rng r = kt_rng_make(seed);
    assert_int_equal(kc_chain_init_model(&CHAIN, model, NULL), KC_OK);
    kc_ctrl_cfg cfg = kc_ctrl_cfg_default();
    int n = CHAIN.n_joints;
    int superposed = 0, started = 0;
    double worst = 0.0;
    char name[96];
    for (int c = 0; c < CASES; c++) {
        kc_real q0[KC_MAX_JOINTS], to[KC_MAX_JOINTS];
        for (int j = 0; j < n; j++) {
            q0[j] = home[j] + (kc_real)kt_uniform(&r, -0.5, 0.5);
            to[j] = home[j] + (kc_real)kt_uniform(&r, -0.5, 0.5);
        }
        assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &cfg, q0), KC_OK);
        kc_goal m = kt_joint_goal(1, to, n);
        assert_int_equal(tick(&m, KC_CMD_NONE), 0);
        int64_t at = 2 + (int64_t)kt_uniform(&r, 0.0, 400.0);
        for (int64_t k = 1; k < at && OUT.state == KC_CTRL_MOVING; k++)
            assert_int_equal(tick(NULL, KC_CMD_NONE), 0);
        if (OUT.state != KC_CTRL_MOVING)
            continue;
        kc_goal g = path_goal(&r, 2, home, c % 3, 1);
        assert_int_equal(tick(&g, KC_CMD_NONE), 0);
        if (!CTRL.blend.on)
            continue; /* taken otherwise: not this test's */
        /* Half the STOPs in the path's first 20 ticks, where it has any. */
        int64_t start_in = CTRL.k0 - (CTRL.cycle - 1);
        int wait = c % 2 ? (int)(start_in > 0 ? start_in : 0) + (int)kt_uniform(&r, 1.0, 20.0)
                         : (int)kt_uniform(&r, 0.0, 30.0);
        for (int k = 0; k < wait; k++)
            assert_int_equal(tick(NULL, KC_CMD_NONE), 0);
        if (!CTRL.blend.on)
            continue;
        superposed++;
        started += CTRL.cycle - 1 >= CTRL.k0;
        snprintf(name, sizeof name, "case %d (method %d), replaced at tick %ld, STOP %d ticks later", c, c % 3,
                 (long)at, wait);
        worst = stop_to_rest(name, worst);
    }
    print_message("%d-joint arm: %d superposed paths stopped (%d of them started), worst |qdd| or qd step %.9f "
                  "of qdd_max; so far %d stops waited for one that fits, at most %d ticks; the joints' jerk at most "
                  "%.9f of qddd_max\n",
                  n, superposed, started, worst, WAITED, LONGEST_WAIT, WORST_JERK);
    assert_true(superposed > CASES / 4 && started > CASES / 50);
}

static void test_superposed_path_stops(void **state)
{
    (void)state;
    superposed_stops(KC_MODEL_PUMA560, PUMA_HOME, 4023);
    superposed_stops(KC_MODEL_PANDA, PANDA_HOME, 4024);
}

static void test_puma_path_stops(void **state)
{
    (void)state;
    random_stops(KC_MODEL_PUMA560, PUMA_HOME, 4021);
}

static void test_panda_path_stops(void **state)
{
    (void)state;
    random_stops(KC_MODEL_PANDA, PANDA_HOME, 4022);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_puma_path_stops),
        cmocka_unit_test(test_panda_path_stops),
        cmocka_unit_test(test_superposed_path_stops),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl_pathstop");
    return rc;
}
