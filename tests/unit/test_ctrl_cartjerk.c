/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_cartjerk.c - the controller's jerk-limited lines and arcs
 * (kinctl/ctrl.h): a goal from rest, then PAUSE and RESUME or STOP at a
 * random tick, on the PUMA 560. Every tick the law driving the segment
 * (its path parameter u, u', u'', read from the drive the controller
 * says it uses, evaluated by the public kc_scurve_eval / kc_profile_eval)
 * is checked as the tool point's path s = S u: |s'| <= v, |s''| <= a,
 * the change of s'' over one tick <= j dt (kinctl/scurve.h, "Ticks"),
 * s' changing by at most a dt, and u, u' and u'' continuous where the
 * drive switches (the first tick of a stop or a resume continues the
 * tick before within those bounds). In double the controller's own
 * progress (u) is checked against the same law by finite differences:
 * s'' from second differences of S u, rounding S eps / dt^2 (1e-10 m/s^2
 * here); in float that rounding (1e-2 m/s^2 at 1 kHz) is as large as the
 * jerk per tick, so only the drive's values are checked there. The goal
 * ends exactly at its target, the duration from rest is the rest-to-rest
 * optimum of u (kt_scurve_optimum_time, independent of kinctl/scurve.h),
 * and cfg.profile = KC_PROFILE_TRAPEZOID (or the goal's profile) keeps the
 * trapezoid. Slack as test_scurve.c's (rounding of t = k dt over the
 * segment's T): jerk j dt + 8 eps (a + j T), acceleration 4 eps j T. */
#include <math.h>
#include <string.h>

#include "kinctl/check.h"
#include "testutil.h"

#ifdef KC_REAL_FLOAT
#define FLOAT_BUILD 1
#define CASES 20
#else
#define FLOAT_BUILD 0
#define CASES 40
#endif
#define LIMIT_SLACK (16.0 * (double)KC_REAL_EPS)

typedef struct harness {
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    /* The law of the segment under way: the tool point's limits, S, T. */
    double v, a, j, S, T;
    /* The last tick's u, u', u'' from the drive, and the progress of the
     * last two ticks (double: finite differences). */
    double u, ud, udd, prog[3];
    int n_prog;
    int active;
    int left; /* the active goal's stop left its path (drive HALT) */
    int events[8];
} harness;

static harness H; /* large: not on the stack */
static kc_check CHECK;

static void setup(kc_profile_kind profile)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, KC_MODEL_PUMA560, NULL), KC_OK);
    H.cfg = kc_ctrl_cfg_default();
    H.cfg.profile = profile;
    assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, KT_PUMA_Q0), KC_OK);
    assert_int_equal(kc_check_init(&CHECK, &H.chain, &H.cfg, 100000, KT_PUMA_Q0), KC_OK);
}

/* u, u', u'' of the active line or arc at this tick, from its drive. */
static void drive_u(double *u, double *ud, double *udd)
{
    const kc_ctrl *c = &H.ctrl;
    int64_t j = c->cycle - c->k0;
    const kc_scurve *own = c->goal.kind == KC_GOAL_LINE ? &c->plan.line.su : &c->plan.arc.su;
    kc_profile_kind kind = c->goal.kind == KC_GOAL_LINE ? c->plan.line.kind : c->plan.arc.kind;
    if (c->drive == KC_DRIVE_PROFILE || (c->drive == KC_DRIVE_NOMINAL && kind == KC_PROFILE_TRAPEZOID)) {
        kc_profile_state s;
        kc_profile_eval(c->drive == KC_DRIVE_PROFILE ? &c->drive_prof
                        : c->goal.kind == KC_GOAL_LINE ? &c->plan.line.prof
                                                       : &c->plan.arc.prof,
                        j, &s);
        *u = (double)s.p, *ud = (double)s.v, *udd = (double)s.a;
        return;
    }
    assert_true(c->drive == KC_DRIVE_SCURVE || c->drive == KC_DRIVE_NOMINAL);
    kc_scurve_state s;
    kc_scurve_eval(c->drive == KC_DRIVE_SCURVE ? &c->drive_scurve : own, j, &s);
    *u = (double)s.p, *ud = (double)s.v, *udd = (double)s.a;
}

/* One tick; while a line or arc is active its law is checked. */
static void tick(const kc_goal *g, kc_ctrl_command cmd)
{
    kc_ctrl_input in = {g, cmd, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    for (int e = 0; e < H.out.n_events; e++)
        H.events[H.out.events[e].kind]++;
    /* (a stop that left its path, joint by joint, has no law of u:
     * ctrl_internal.h, kc_ctrl_halting) */
    if (!H.ctrl.active || (H.ctrl.goal.kind != KC_GOAL_LINE && H.ctrl.goal.kind != KC_GOAL_ARC) ||
        kt_has_event(&H.out, KC_EVENT_STARTED, H.ctrl.goal.id) || H.ctrl.drive == KC_DRIVE_HALT) {
        H.left = H.left || (H.ctrl.active && H.ctrl.drive == KC_DRIVE_HALT);
        /* (a segment's first tick continues from rest: checked from the next) */
        H.active = 0;
        H.n_prog = 0;
        if (!H.ctrl.active || H.ctrl.drive == KC_DRIVE_HALT)
            return;
    }
    double u, ud, udd, dt = (double)H.cfg.dt, E = (double)KC_REAL_EPS;
    drive_u(&u, &ud, &udd);
    if (H.active) {
        double S = H.S, sd = S * ud, sdd = S * udd;
        double jl = H.j * dt * (1.0 + LIMIT_SLACK) + 8.0 * E * (H.a + H.j * H.T);
        if (!(fabs(sd) <= H.v * (1.0 + LIMIT_SLACK) + 4.0 * E * H.a * H.T &&
              fabs(sdd) <= H.a * (1.0 + LIMIT_SLACK) + 4.0 * E * H.j * H.T && fabs(sdd - S * H.udd) <= jl &&
              fabs(sd - S * H.ud) <= H.a * dt * (1.0 + LIMIT_SLACK) + 8.0 * E * (H.v + H.a * H.T) &&
              fabs(S * (u - H.u)) <= H.v * dt * (1.0 + LIMIT_SLACK) + 4.0 * E * S))
            fail_msg("cycle %ld (state %d, drive %d): s' %.9g (v %g), s'' %.9g (a %g), s'' step %.6g (j dt %g), "
                     "s' step %.6g",
                     (long)H.out.cycle, H.out.state, H.ctrl.drive, sd, H.v, sdd, H.a, fabs(sdd - S * H.udd), jl,
                     fabs(sd - S * H.ud));
        /* While it moves, the controller's progress is u (double: its
         * differences too). */
        int moving = H.out.state == KC_CTRL_MOVING || H.out.state == KC_CTRL_STOPPING;
        if (moving)
            kt_near((double)H.out.progress, u, 4.0 * E, "progress is u");
        if (!FLOAT_BUILD && moving && H.n_prog >= 2) {
            double d2 = S * (u - 2.0 * H.prog[1] + H.prog[0]) / (dt * dt);
            if (!(fabs(d2) <= H.a * (1.0 + 1e-6) + 1e-6))
                fail_msg("cycle %ld: second difference of s %g over a %g", (long)H.out.cycle, d2, H.a);
        }
    }
    H.prog[0] = H.prog[1];
    H.prog[1] = u;
    H.n_prog++;
    H.u = u, H.ud = ud, H.udd = udd;
    H.active = 1;
}

static int run_until(kc_ctrl_event_kind kind, int64_t id, int max)
{
    for (int k = 1; k <= max; k++) {
        tick(NULL, KC_CMD_NONE);
        if (kt_has_event(&H.out, kind, id))
            return k;
        assert_true(H.out.state != KC_CTRL_FAULT);
    }
    fail_msg("goal %ld: no event %d in %d ticks", (long)id, kind, max);
    return -1;
}

/* The law's limits for goal g (its own or the defaults) and the plan's S. */
static void take_law(const kc_goal *g)
{
    H.v = (double)(g->speed > KC_R(0.0) ? g->speed : H.cfg.cart_speed);
    H.a = (double)(g->accel > KC_R(0.0) ? g->accel : H.cfg.cart_accel);
    H.j = (double)(g->jerk > KC_R(0.0) ? g->jerk : H.cfg.cart_jerk);
    H.S = (double)(g->kind == KC_GOAL_LINE ? H.ctrl.plan.line.length : H.ctrl.plan.arc.length);
    H.T = (double)(g->kind == KC_GOAL_LINE ? H.ctrl.plan.line.T : H.ctrl.plan.arc.T) + 10.0;
}

/* Line goal id to a random target within 15 cm of the tool's pose at
 * KT_PUMA_Q0, in its orientation (the tool point's limits bind), that the dry
 * run (kinctl/check.h) takes from where the arm is: as the daemon does,
 * lines the arm cannot follow (near a singularity: a tracking fault,
 * trapezoid or not) are drawn again. speed, accel, jerk: 0 or the goal's. */
static kc_goal random_line(kt_rng *r, int64_t id, kc_real speed, kc_real accel, kc_real jerk)
{
    kc_pose home;
    kc_fk_eval(&H.chain, KT_PUMA_Q0, &home);
    kt_line_draw d = {0.0, 0.15, 0.0, speed, accel, jerk};
    return kt_checked_line(r, &CHECK, H.ctrl.q, &home, id, &d);
}

/* A line from rest: jerk-limited by default, in the optimum time of u. */
static void test_line_from_rest(void **state)
{
    (void)state;
    setup(KC_PROFILE_JERK);
    kt_rng r = kt_rng_make(0xC1);
    for (int c = 0; c < CASES; c++) {
        kc_goal g = c % 2 ? random_line(&r, 100 + c, (kc_real)kt_uniform(&r, 0.05, 0.3),
                                        (kc_real)kt_uniform(&r, 0.2, 1.0), (kc_real)kt_uniform(&r, 1.0, 20.0))
                          : random_line(&r, 100 + c, KC_R(0.0), KC_R(0.0), KC_R(0.0));
        tick(&g, KC_CMD_NONE);
        assert_true(kt_has_event(&H.out, KC_EVENT_STARTED, g.id));
        assert_int_equal(H.ctrl.plan.line.kind, KC_PROFILE_JERK);
        take_law(&g);
        double S = H.S, T = (double)H.ctrl.plan.line.T, dt = (double)H.cfg.dt;
        double want = kt_scurve_optimum_time(1.0, H.v / S, H.a / S, H.j / S);
        kt_near(T, want, (FLOAT_BUILD ? 2e-5 : 1e-9) * want, "line: the optimum of u");
        int k = run_until(KC_EVENT_COMPLETED, g.id, 100000);
        /* It ends on its last tick, plus the ticks the tool takes to settle. */
        assert_true((double)k >= T / dt * (1.0 - 1e-6));
        kt_near((double)H.out.pose.t.v[0], (double)g.pose.t.v[0], 1e-5 + 2e-4 * FLOAT_BUILD, "at the target");
    }
    assert_int_equal(H.events[KC_EVENT_FAULT], 0);
}

/* PAUSE then RESUME, or STOP, at a random tick of a jerk-limited line. */
static void test_line_pause_resume_stop(void **state)
{
    (void)state;
    setup(KC_PROFILE_JERK);
    kt_rng r = kt_rng_make(0xC2);
    int paused = 0, stopped = 0, left = 0;
    for (int c = 0; c < CASES; c++) {
        kc_goal g = random_line(&r, 200 + c, KC_R(0.0), KC_R(0.0), KC_R(0.0));
        H.left = 0;
        tick(&g, KC_CMD_NONE);
        assert_true(kt_has_event(&H.out, KC_EVENT_STARTED, g.id));
        take_law(&g);
        int64_t len = H.ctrl.plan.line.ticks;
        int64_t at = 1 + (int64_t)kt_uniform(&r, 0.0, (double)(len - 2));
        for (int64_t k = 1; k < at; k++)
            tick(NULL, KC_CMD_NONE);
        if (c % 3 == 2) {
            tick(NULL, KC_CMD_STOP);
            for (int k = 0; k < 100000 && H.out.state != KC_CTRL_IDLE; k++)
                tick(NULL, KC_CMD_NONE);
            assert_int_equal(H.out.state, KC_CTRL_IDLE);
            for (int j = 0; j < 6; j++)
                assert_true(H.out.qd[j] == KC_R(0.0));
            /* on the path u at rest, unless its stop left the path */
            assert_true(H.left || (H.ud == 0.0 && H.udd == 0.0 && H.u <= 1.0));
            left += H.left;
            stopped++;
            continue;
        }
        tick(NULL, KC_CMD_PAUSE);
        assert_int_equal(H.ctrl.drive, KC_DRIVE_SCURVE);
        for (int k = 0; k < 100000 && H.out.state != KC_CTRL_PAUSED && H.out.state != KC_CTRL_IDLE; k++)
            tick(NULL, KC_CMD_NONE);
        if (H.left) {
            /* Its stop left the path (ctrl_internal.h, kc_ctrl_halting):
             * aborted at rest, as a STOP. */
            assert_int_equal(H.out.state, KC_CTRL_IDLE);
            assert_true(kt_has_event(&H.out, KC_EVENT_ABORTED, g.id));
            left++;
            continue;
        }
        assert_int_equal(H.out.state, KC_CTRL_PAUSED);
        assert_true(H.ud == 0.0 && H.udd == 0.0);
        for (int k = 0; k < 20; k++)
            tick(NULL, KC_CMD_NONE);
        tick(NULL, KC_CMD_RESUME);
        if (!kt_has_event(&H.out, KC_EVENT_COMPLETED, g.id))
            run_until(KC_EVENT_COMPLETED, g.id, 100000);
        kc_pose end;
        kc_fk_eval(&H.chain, H.out.q, &end);
        kt_near_vec3(&end.t, &g.pose.t, 1e-5 + 2e-4 * FLOAT_BUILD, "resumed to the target");
        paused++;
    }
    print_message("%d paused, %d stopped, %d left their paths\n", paused, stopped, left);
    assert_true(paused > 0 && stopped > 0);
    assert_int_equal(H.events[KC_EVENT_FAULT], 0);
}

/* An arc paused and resumed: the same law on its length. */
static void test_arc_pause_resume(void **state)
{
    (void)state;
    setup(KC_PROFILE_JERK);
    kc_pose here;
    kc_fk_eval(&H.chain, KT_PUMA_Q0, &here);
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = 300;
    g.kind = KC_GOAL_ARC;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.via = here.t;
    g.via.v[1] += KC_R(0.1);
    g.via.v[0] += KC_R(0.05);
    kc_pose_identity(&g.pose);
    g.pose.t = here.t;
    g.pose.t.v[1] += KC_R(0.2);
    tick(&g, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_STARTED, g.id));
    assert_int_equal(H.ctrl.plan.arc.kind, KC_PROFILE_JERK);
    take_law(&g);
    for (int64_t k = 1; k < H.ctrl.plan.arc.ticks / 2; k++)
        tick(NULL, KC_CMD_NONE);
    tick(NULL, KC_CMD_PAUSE);
    for (int k = 0; k < 100000 && H.out.state != KC_CTRL_PAUSED; k++)
        tick(NULL, KC_CMD_NONE);
    assert_int_equal(H.out.state, KC_CTRL_PAUSED);
    tick(NULL, KC_CMD_RESUME);
    run_until(KC_EVENT_COMPLETED, g.id, 100000);
    assert_int_equal(H.events[KC_EVENT_FAULT], 0);
}

/* The trapezoid, from the configuration or the goal: the plan is
 * kc_interp_line_plan's with infinite jerk limits. */
static void test_trapezoid_kept(void **state)
{
    (void)state;
    for (int how = 0; how < 2; how++) {
        setup(how == 0 ? KC_PROFILE_TRAPEZOID : KC_PROFILE_JERK);
        kc_pose here, to;
        kc_fk_eval(&H.chain, KT_PUMA_Q0, &here);
        to = here;
        to.t.v[2] += KC_R(0.15);
        kc_goal g = kt_line_goal(400 + how, &to);
        if (how == 1)
            g.profile = KC_GOAL_PROFILE_TRAPEZOID;
        tick(&g, KC_CMD_NONE);
        kc_interp_limits lim = kc_interp_limits_default();
        lim.v = H.cfg.cart_speed;
        lim.a = H.cfg.cart_accel;
        lim.w = H.cfg.cart_omega;
        lim.dw = H.cfg.cart_alpha;
        kc_interp_line want;
        assert_int_equal(kc_interp_line_plan(&want, &here, &to, &lim, KC_INTERP_SLERP, H.cfg.dt), KC_OK);
        assert_int_equal(H.ctrl.plan.line.kind, KC_PROFILE_TRAPEZOID);
        assert_true(H.ctrl.plan.line.prof.T == want.prof.T && H.ctrl.plan.line.ticks == want.prof.ticks);
        take_law(&g);
        H.j = (double)INFINITY; /* the trapezoid's jerk is impulses */
        run_until(KC_EVENT_COMPLETED, g.id, 100000);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_line_from_rest),
        cmocka_unit_test(test_line_pause_resume_stop),
        cmocka_unit_test(test_arc_pause_resume),
        cmocka_unit_test(test_trapezoid_kept),
    };
    int failed = cmocka_run_group_tests_name("ctrl_cartjerk (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("ctrl_cartjerk");
    return failed;
}
