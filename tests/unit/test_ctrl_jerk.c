/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_jerk.c - the controller's jerk-limited joint moves
 * (kinctl/ctrl.h): random moves from rest and random replacements of a
 * moving one by another joint goal, stop, pause and resume, on the PUMA
 * 560 and the Panda (their own velocity, acceleration and jerk limits per
 * joint). Every tick is checked against the limits: |qd| <= qd_max,
 * |qdd| <= qdd_max and the jerk, measured as the change of qdd over one
 * tick divided by dt, <= qddd_max, each with a relative slack of SLACK;
 * the goal ends exactly on its target, every moving joint starts on the
 * first tick and ends on the last, and the duration from rest is the
 * slowest joint's time-optimal one, computed here independently. The
 * trapezoid, asked for by the goal or by the configuration, is still
 * exactly kc_interp_joint_plan's, and ESTOP stays acceleration-limited. */
#include <math.h>
#include <string.h>

#include "testutil.h"

/* Rounding allowed in the per-tick limit checks (relative to the limit).
 * Velocity and acceleration: SLACK. The jerk compares two accelerations a
 * tick apart divided by dt, and the tick's time t = k dt (from the
 * segment's start) carries a relative rounding of eps, so a phase's
 * acceleration a + J tau is off by up to J t eps and the change over one
 * tick by 2 J t eps, i.e. 2 t eps / dt of the limit: in float, for
 * segments of up to 8 s at 1 kHz, 2 * 8 * 1.2e-7 / 1e-3 = 2e-3 (seen:
 * 1.7e-4); in double 4e-11, under SLACK. */
#ifdef KC_REAL_FLOAT
#define SLACK 1e-4
#define SLACK_JERK 2e-3
#define CASES 60
#else
#define SLACK 1e-6
#define SLACK_JERK 1e-6
#define CASES 150
#endif

typedef struct harness {
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    /* The previous tick's setpoint. */
    double qd_prev[KC_MAX_JOINTS], qdd_prev[KC_MAX_JOINTS];
    /* Worst ratios to the limits seen (1 = at the limit). */
    double worst_v, worst_a, worst_j;
    int check_jerk; /* 0 for the trapezoid, whose jerk is impulses */
    int events[8];
    int resumed_stopping; /* RESUMEs sent while a pause's stop ran */
} harness;

static harness H; /* large: not on the stack */

static void setup(kc_model model, kc_profile_kind profile)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, model, NULL), KC_OK);
    H.cfg = kc_ctrl_cfg_default();
    H.cfg.profile = profile;
    H.check_jerk = 1;
    kc_real q0[KC_MAX_JOINTS];
    for (int j = 0; j < H.chain.n_joints; j++) {
        const kc_joint_limits *l = &H.chain.joints[j].limits;
        q0[j] = (l->q_min + l->q_max) / KC_R(2.0);
    }
    assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, q0), KC_OK);
}

/* One tick, its setpoint checked against every limit and the last one. */
static void tick(const kc_goal *g, kc_ctrl_command cmd)
{
    kc_ctrl_input in = {g, cmd, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    double dt = (double)H.cfg.dt;
    for (int j = 0; j < H.chain.n_joints; j++) {
        const kc_joint_limits *l = &H.chain.joints[j].limits;
        double q = (double)H.out.q[j], qd = (double)H.out.qd[j], qdd = (double)H.out.qdd[j];
        if (!(q >= (double)l->q_min && q <= (double)l->q_max))
            fail_msg("cycle %ld: q[%d] = %.9g outside the limits", (long)H.out.cycle, j, q);
        double rv = fabs(qd) / (double)l->qd_max, ra = fabs(qdd) / (double)l->qdd_max;
        double rj = H.check_jerk ? fabs(qdd - H.qdd_prev[j]) / dt / (double)l->qddd_max : 0.0;
        /* Continuity: qd changes by the acceleration over the tick (with
         * the rounding of qd itself, as the controller's own check). */
        double dv = fabs(qd - H.qd_prev[j]);
        if (!(rv <= 1.0 + SLACK && ra <= 1.0 + SLACK && rj <= 1.0 + SLACK_JERK &&
              dv <= (double)l->qdd_max * dt * (1.0 + SLACK) + SLACK * fabs(H.qd_prev[j])))
            fail_msg("cycle %ld joint %d (state %d): |qd| %.7g, |qdd| %.7g, jerk %.7g of the limits, qd step %.4g",
                     (long)H.out.cycle, j, H.out.state, rv, ra, rj, dv);
        H.worst_v = fmax(H.worst_v, rv);
        H.worst_a = fmax(H.worst_a, ra);
        H.worst_j = fmax(H.worst_j, rj);
        H.qd_prev[j] = qd;
        H.qdd_prev[j] = qdd;
    }
    for (int e = 0; e < H.out.n_events; e++)
        H.events[H.out.events[e].kind]++;
}

/* Ticks until goal id completes (its tick counted), at most max. */
static int run_until_completed(int64_t id, int max)
{
    for (int k = 1; k <= max; k++) {
        tick(NULL, KC_CMD_NONE);
        if (kt_has_event(&H.out, KC_EVENT_COMPLETED, id))
            return k;
        if (H.out.state == KC_CTRL_FAULT)
            fail_msg("fault while moving to goal %ld", (long)id);
    }
    fail_msg("goal %ld not completed in %d ticks", (long)id, max);
    return -1;
}

/* A random target inside the limits, a random share of the range away. */
static void random_target(kt_rng *r, kc_real *q)
{
    kt_rand_q(r, &H.chain, q);
}

static kc_goal random_goal(kt_rng *r, int64_t id, int scaled)
{
    kc_real q[KC_MAX_JOINTS];
    random_target(r, q);
    kc_goal g = kt_joint_goal(id, q, H.chain.n_joints);
    if (scaled) {
        g.vel_scale = (kc_real)kt_uniform(r, 0.2, 1.0);
        g.acc_scale = (kc_real)kt_uniform(r, 0.2, 1.0);
    }
    return g;
}

/* A move from rest to goal g, started now: its ticks, limits, sync, end
 * and duration against the slowest joint's optimum. */
static void check_move_from_rest(const kc_goal *g)
{
    int n = H.chain.n_joints;
    double q0[KC_MAX_JOINTS], T = 0.0, dt = (double)H.cfg.dt;
    int moving[KC_MAX_JOINTS];
    for (int j = 0; j < n; j++) {
        const kc_joint_limits *l = &H.chain.joints[j].limits;
        q0[j] = (double)H.ctrl.q[j];
        double D = fabs((double)g->q[j] - q0[j]);
        moving[j] = D > 0.0;
        T = fmax(T, kt_scurve_optimum_time(D, (double)(l->qd_max * g->vel_scale),
                                           (double)(l->qdd_max * g->acc_scale), (double)l->qddd_max));
    }
    tick(g, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_STARTED, g->id));
    /* Every moving joint starts on the first tick. */
    for (int j = 0; j < n; j++)
        if (moving[j] && H.out.qdd[j] == KC_R(0.0))
            fail_msg("joint %d has not started on the first tick", j);
    kc_real before_qd[KC_MAX_JOINTS], before_qdd[KC_MAX_JOINTS];
    int ticks = 1;
    for (;;) {
        memcpy(before_qd, H.out.qd, sizeof before_qd);
        memcpy(before_qdd, H.out.qdd, sizeof before_qdd);
        tick(NULL, KC_CMD_NONE);
        ticks++;
        if (kt_has_event(&H.out, KC_EVENT_COMPLETED, g->id))
            break;
        if (ticks > 200000)
            fail_msg("goal %ld never completes", (long)g->id);
    }
    /* Every moving joint still moves on the last tick before the end. */
    for (int j = 0; j < n; j++) {
        if (moving[j] && before_qd[j] == KC_R(0.0) && before_qdd[j] == KC_R(0.0))
            fail_msg("joint %d came to rest before the others", j);
        if (H.out.q[j] != g->q[j] || H.out.qd[j] != KC_R(0.0) || H.out.qdd[j] != KC_R(0.0))
            fail_msg("joint %d not exactly at rest on its target: %.9g vs %.9g", j, (double)H.out.q[j],
                     (double)g->q[j]);
    }
    /* The duration: the first tick at or after the slowest optimum (one
     * tick either way where the optimum lands on a tick in rounding). */
    double expect = ceil(T / dt - 1e-9);
    if (fabs((double)ticks - expect) > 1.0)
        fail_msg("goal %ld took %d ticks, the slowest joint's optimum %.6f s is %.0f", (long)g->id, ticks, T, expect);
}

/* Random moves from rest on both arms, random scales: limits, sync, exact
 * ends, optimal durations. */
static void test_random_moves(void **state)
{
    (void)state;
    kc_model models[2] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};
    for (int m = 0; m < 2; m++) {
        setup(models[m], KC_PROFILE_JERK);
        kt_rng r = kt_rng_make(1900 + (uint64_t)m);
        for (int c = 0; c < CASES; c++) {
            kc_goal g = random_goal(&r, 1 + c, c % 2);
            check_move_from_rest(&g);
        }
        print_message("model %d: %d moves, worst |qd| %.6f, |qdd| %.6f, jerk %.6f of the limits\n", m, CASES,
                      H.worst_v, H.worst_a, H.worst_j);
        /* The moves reach the limits they are bounded by. */
        assert_true(H.worst_v > 0.99 && H.worst_a > 0.99 && H.worst_j > 0.99);
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
    }
}

/* Random replacements of a moving joint move by another joint goal at a
 * random tick: the new goal takes over in the tick it arrives (from the
 * full state: q, qd and qdd continuous, the jerk within its limit on the
 * tick of the takeover), or where that would leave the limits stops and
 * starts; it ends exactly on its target with every joint arriving on the
 * same tick. */
static void test_random_replacements(void **state)
{
    (void)state;
    kc_model models[2] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};
    int taken = 0, fallback = 0;
    for (int m = 0; m < 2; m++) {
        setup(models[m], KC_PROFILE_JERK);
        kt_rng r = kt_rng_make(1919 + (uint64_t)m);
        int n = H.chain.n_joints;
        for (int c = 0; c < CASES; c++) {
            kc_goal a = random_goal(&r, 2 * c + 1, c % 3 == 0);
            kc_goal b = random_goal(&r, 2 * c + 2, c % 3 == 1);
            b.replace = 1;
            tick(&a, KC_CMD_NONE);
            int64_t len = H.ctrl.plan.joint.ticks;
            int64_t at = 1 + (int64_t)kt_uniform(&r, 0.0, (double)(len > 2 ? len - 2 : 1));
            for (int64_t k = 1; k < at; k++)
                tick(NULL, KC_CMD_NONE);
            kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS];
            memcpy(q, H.out.q, sizeof q);
            memcpy(qd, H.out.qd, sizeof qd);
            tick(&b, KC_CMD_NONE); /* checked: limits and jerk across the takeover */
            if (kt_has_event(&H.out, KC_EVENT_STARTED, b.id)) {
                taken++;
                assert_true(kt_has_event(&H.out, KC_EVENT_PREEMPTED, a.id));
                /* Position continues by the velocity, velocity by the
                 * acceleration: a tick of the old state's own motion. */
                for (int j = 0; j < n; j++) {
                    const kc_joint_limits *l = &H.chain.joints[j].limits;
                    double dt = (double)H.cfg.dt;
                    double dq = (double)H.out.q[j] - (double)q[j] - (double)qd[j] * dt;
                    double lim = (double)l->qdd_max * dt * dt * (1.0 + SLACK) + 4.0 * (double)KC_REAL_EPS * fabs((double)q[j]);
                    if (!(fabs(dq) <= lim))
                        fail_msg("case %d joint %d: q jumps by %.3g beyond qd dt", c, j, dq);
                }
                /* Every joint arrives on the same tick. */
                int64_t want = H.ctrl.plan.joint.ticks;
                int k = run_until_completed(b.id, 200000);
                if ((int64_t)k + 1 != want)
                    fail_msg("case %d: completed after %d ticks of %ld planned", c, k + 1, (long)want);
            } else {
                fallback++;
                assert_int_equal(H.out.state, KC_CTRL_STOPPING);
                run_until_completed(b.id, 400000);
            }
            for (int j = 0; j < n; j++)
                if (H.out.q[j] != b.q[j] || H.out.qd[j] != KC_R(0.0) || H.out.qdd[j] != KC_R(0.0))
                    fail_msg("case %d: joint %d not exactly at rest on its target", c, j);
        }
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
        assert_int_equal(H.events[KC_EVENT_ABORTED], 0);
    }
    print_message("%d replacements taken over at once, %d stopped first; worst |qd| %.6f, |qdd| %.6f, jerk %.6f\n",
                  taken, fallback, H.worst_v, H.worst_a, H.worst_j);
    assert_true(taken > fallback);
}

/* A goal re-sent mid-motion (a replacing goal with the same target) takes
 * over at once and arrives when the first would have, to the tick: the
 * rest of the first move is the fastest way there. */
static void test_resend_same_target(void **state)
{
    (void)state;
    kc_model models[2] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};
    for (int m = 0; m < 2; m++) {
        setup(models[m], KC_PROFILE_JERK);
        kt_rng r = kt_rng_make(1960 + (uint64_t)m);
        for (int c = 0; c < CASES / 3; c++) {
            kc_goal a = random_goal(&r, 3000 + 2 * c, c % 2);
            kc_goal b = a;
            b.id = a.id + 1;
            b.replace = 1;
            tick(&a, KC_CMD_NONE);
            int64_t start = H.out.cycle, len = H.ctrl.plan.joint.ticks;
            int64_t at = 1 + (int64_t)kt_uniform(&r, 0.0, (double)(len > 2 ? len - 2 : 1));
            for (int64_t k = 1; k < at; k++)
                tick(NULL, KC_CMD_NONE);
            tick(&b, KC_CMD_NONE);
            assert_true(kt_has_event(&H.out, KC_EVENT_STARTED, b.id) && kt_has_event(&H.out, KC_EVENT_PREEMPTED, a.id));
            run_until_completed(b.id, 400000);
            /* The first move's last tick was start + len - 1. */
            int64_t end = H.out.cycle, want = start + len - 1;
            if (end < want - 1 || end > want + 1)
                fail_msg("case %d: the re-sent goal arrived on cycle %ld, the first would have on %ld", c, (long)end,
                         (long)want);
            for (int j = 0; j < H.chain.n_joints; j++)
                assert_true(H.out.q[j] == a.q[j]);
        }
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
    }
}

/* STOP, PAUSE and RESUME of a jerk-limited move: the jerk stays within
 * its limits throughout, the resumed move ends exactly on the target. */
static void test_stop_pause_resume(void **state)
{
    (void)state;
    kc_model models[2] = {KC_MODEL_PUMA560, KC_MODEL_PANDA};
    for (int m = 0; m < 2; m++) {
        setup(models[m], KC_PROFILE_JERK);
        kt_rng r = kt_rng_make(1937 + (uint64_t)m);
        for (int c = 0; c < CASES / 3; c++) {
            kc_goal a = random_goal(&r, 1000 + c, c % 2);
            tick(&a, KC_CMD_NONE);
            int64_t len = H.ctrl.plan.joint.ticks;
            int64_t at = 1 + (int64_t)kt_uniform(&r, 0.0, (double)(len > 2 ? len - 2 : 1));
            for (int64_t k = 1; k < at; k++)
                tick(NULL, KC_CMD_NONE);
            if (c % 4 >= 2) {
                /* The stop of a replacing goal taken over from the moving
                 * state (its joints stop one by one). */
                kc_goal b = random_goal(&r, 2000 + c, 0);
                b.replace = 1;
                tick(&b, KC_CMD_NONE);
                if (kt_has_event(&H.out, KC_EVENT_STARTED, b.id)) {
                    a = b;
                    for (int64_t k = 0; k < H.ctrl.plan.joint.ticks / 3; k++)
                        tick(NULL, KC_CMD_NONE);
                } else {
                    run_until_completed(b.id, 400000);
                    continue;
                }
            }
            if (c % 2 == 0) {
                tick(NULL, KC_CMD_STOP);
                for (int k = 0; k < 100000 && H.out.state != KC_CTRL_IDLE; k++)
                    tick(NULL, KC_CMD_NONE);
                assert_int_equal(H.out.state, KC_CTRL_IDLE);
                for (int j = 0; j < H.chain.n_joints; j++)
                    assert_true(H.out.qd[j] == KC_R(0.0) && H.out.qdd[j] == KC_R(0.0));
            } else {
                /* RESUME once paused, or (every other pause) while the
                 * pause's stop still runs: the move goes on as the stop
                 * comes to rest, from its tick 1 there (it once started
                 * at its tick 2: qdd stepped by 2 qddd_max dt). */
                int64_t early = (c / 4) % 2 ? (int64_t)kt_uniform(&r, 0.0, 40.0) : -1;
                tick(NULL, KC_CMD_PAUSE);
                for (int64_t k = 0; k < 100000 && H.out.state != KC_CTRL_PAUSED && k != early; k++)
                    tick(NULL, KC_CMD_NONE);
                assert_true(H.out.state == KC_CTRL_PAUSED || (early >= 0 && H.out.state == KC_CTRL_STOPPING));
                H.resumed_stopping += H.out.state == KC_CTRL_STOPPING;
                tick(NULL, KC_CMD_RESUME);
                /* (paused on the target: it completes in the resuming tick) */
                if (!kt_has_event(&H.out, KC_EVENT_COMPLETED, a.id))
                    run_until_completed(a.id, 200000);
                for (int j = 0; j < H.chain.n_joints; j++)
                    assert_true(H.out.q[j] == a.q[j] && H.out.qd[j] == KC_R(0.0));
            }
        }
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
        print_message("%s: %d moves stopped, paused or replaced, %d of them resumed while their pause's stop ran: "
                      "the joints' jerk at most %.7f of their limits (%s)\n",
                      kc_model_name(models[m]), CASES / 3, H.resumed_stopping, H.worst_j, KC_REAL_NAME);
        assert_true(H.resumed_stopping > 0);
    }
}

/* The trapezoid, from the configuration or the goal, is exactly
 * kc_interp_joint_plan's, tick by tick. */
static void test_trapezoid_exact(void **state)
{
    (void)state;
    for (int mode = 0; mode < 2; mode++) {
        setup(KC_MODEL_PUMA560, mode == 0 ? KC_PROFILE_TRAPEZOID : KC_PROFILE_JERK);
        kt_rng r = kt_rng_make(1940);
        kc_goal g = random_goal(&r, 5, 1);
        H.check_jerk = 0;
        if (mode == 1)
            g.profile = KC_GOAL_PROFILE_TRAPEZOID;
        int n = H.chain.n_joints;
        kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS], q0[KC_MAX_JOINTS];
        for (int j = 0; j < n; j++) {
            vmax[j] = H.chain.joints[j].limits.qd_max * g.vel_scale;
            amax[j] = H.chain.joints[j].limits.qdd_max * g.acc_scale;
            q0[j] = H.ctrl.q[j];
        }
        static kc_interp_joint plan;
        assert_int_equal(kc_interp_joint_plan(&plan, n, q0, g.q, vmax, amax, KC_R(0.0), H.cfg.dt), KC_OK);
        tick(&g, KC_CMD_NONE);
        for (int64_t k = 1; k <= plan.ticks; k++) {
            kc_interp_joint_state s;
            kc_interp_joint_eval(&plan, k, &s);
            for (int j = 0; j < n; j++)
                if (H.out.q[j] != s.q[j] || H.out.qd[j] != s.qd[j] || H.out.qdd[j] != s.qdd[j])
                    fail_msg("mode %d tick %ld joint %d differs from the trapezoid", mode, (long)k, j);
            if (k < plan.ticks)
                tick(NULL, KC_CMD_NONE);
        }
        assert_true(kt_has_event(&H.out, KC_EVENT_COMPLETED, 5));
    }
}

/* ESTOP from a jerk-limited move stays acceleration-limited: some joint's
 * acceleration reaches its limit on the first tick (as documented). */
static void test_estop_acceleration_limited(void **state)
{
    (void)state;
    setup(KC_MODEL_PUMA560, KC_PROFILE_JERK);
    kt_rng r = kt_rng_make(1950);
    kc_goal g = random_goal(&r, 7, 0);
    tick(&g, KC_CMD_NONE);
    for (int k = 0; k < (int)(H.ctrl.plan.joint.ticks / 2); k++)
        tick(NULL, KC_CMD_NONE);
    kc_ctrl_input in = {NULL, KC_CMD_ESTOP, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    int at_limit = 0;
    for (int j = 0; j < H.chain.n_joints; j++)
        if (H.out.qd[j] != KC_R(0.0) &&
            fabs((double)H.out.qdd[j]) >= (double)H.chain.joints[j].limits.qdd_max * (1.0 - SLACK))
            at_limit = 1;
    assert_true(at_limit);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_moves),      cmocka_unit_test(test_random_replacements),
        cmocka_unit_test(test_resend_same_target),
        cmocka_unit_test(test_stop_pause_resume), cmocka_unit_test(test_trapezoid_exact),
        cmocka_unit_test(test_estop_acceleration_limited),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl_jerk");
    return rc;
}
