/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_pathjerk.c - the time law of multi-point paths where the
 * controller chooses it (kinctl/ctrl.h): the ramp of tau' from rest and
 * into the end of a Lagrange path, the stop on the path, and the resume
 * are jerk-limited (tau'' continuous) by default, on the PUMA 560. Every
 * tick the law driving tau (read from the drive the controller says it
 * uses, or its ramp where it runs a path on its own ramps, evaluated by
 * the public kc_scurve_eval / kc_profile_eval) is
 * checked: 0 <= tau' <= 1 (plus rounding), tau'' changing by at most
 * J dt per tick with J the largest jerk of the drive's phases (slack as
 * test_scurve.c's: 8 eps (A + J T)), and tau''' |q'| within every joint's
 * qddd_max at the tick (tau''' the jerk of the drive's phase, q' the
 * path's own velocity at tau): the jerk the ramp adds through tau'''
 * stays within the limits.
 * A Cartesian path's law is checked the same way against the Cartesian
 * jerk limits (tau''' times the tool's speed and angular speed). The
 * joints' setpoints pass the controller's own per-tick limit checks (no
 * fault), a paused path resumes and ends exactly on its last knot, and
 * the trapezoid (cfg.profile) keeps the constant-rate ramp. */
#include <math.h>
#include <string.h>

#include "testutil.h"

#define LIMIT_SLACK (16.0 * (double)KC_REAL_EPS)

/* The controller's per-tick limit check's slack (kinctl/ctrl.h). */
#ifdef KC_REAL_FLOAT
#define JERK_SLACK 1e-4
#else
#define JERK_SLACK 1e-6
#endif

typedef struct harness {
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    double tau, rate, rate_dot; /* the last tick's tau, tau', tau'' */
    int active;
    int scurve_ticks;           /* ticks driven by a jerk-limited law */
    int events[8];
} harness;

static harness H; /* large: not on the stack */

static void setup(kc_profile_kind profile)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, KC_MODEL_PUMA560, NULL), KC_OK);
    H.cfg = kc_ctrl_cfg_default();
    H.cfg.profile = profile;
    assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, KT_PUMA_Q0), KC_OK);
}

/* The largest |jerk| of a profile's phases. */
static double scurve_jmax(const kc_scurve *s)
{
    double J = 0.0;
    for (int i = 0; i < s->n; i++)
        J = fmax(J, fabs((double)s->j[i]));
    return J;
}

/* The jerk tau''' adds, against its limits: every joint's tau''' |q'| /
 * qddd_max, or for a Cartesian path tau''' |v| / jerk and tau''' |w| /
 * angular jerk (the configured defaults); at most 1. */
static double added_jerk_ratio(const kc_ctrl *c, double tau, double Jnow)
{
    double worst = 0.0;
    if (c->goal.kind == KC_GOAL_PATH) {
        kc_real q[KC_MAX_JOINTS], d1[KC_MAX_JOINTS], d2[KC_MAX_JOINTS];
        kc_path_eval_time(&c->plan.path, (kc_real)fmax(tau, 0.0), q, d1, d2);
        for (int i = 0; i < H.chain.n_joints; i++)
            worst = fmax(worst, Jnow * fabs((double)d1[i]) / (double)H.chain.joints[i].limits.qddd_max);
        return worst;
    }
    kc_path_pose s;
    kc_path_cart_eval_time(&c->plan.path_cart, (kc_real)fmax(tau, 0.0), &s);
    worst = Jnow * (double)kc_vec3_norm(&s.v) / (double)H.cfg.cart_jerk;
    return fmax(worst, Jnow * (double)kc_vec3_norm(&s.w) / (double)H.cfg.cart_angular_jerk);
}

/* One tick; while a path is active its time law is checked. */
static void tick(const kc_goal *g, kc_ctrl_command cmd)
{
    kc_ctrl_input in = {g, cmd, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    for (int e = 0; e < H.out.n_events; e++)
        H.events[H.out.events[e].kind]++;
    const kc_ctrl *c = &H.ctrl;
    int path = c->active && (c->goal.kind == KC_GOAL_PATH || c->goal.kind == KC_GOAL_PATH_CART);
    if (!path || kt_has_event(&H.out, KC_EVENT_STARTED, c->goal.id)) {
        H.active = 0;
        if (!path)
            return;
    }
    int64_t j = c->cycle - c->k0;
    double T = (double)(c->goal.kind == KC_GOAL_PATH ? c->plan.path.duration : c->plan.path_cart.pos.duration);
    double tau = (double)j * (double)H.cfg.dt, rate = 1.0, rate_dot = 0.0, J = 0.0, Jnow = 0.0, dt = (double)H.cfg.dt;
    double E = (double)KC_REAL_EPS;
    /* A stop's or a resume's law, or the path's own ramps (its timing, with
     * the nominal drive or a stop waiting on it). */
    const kc_scurve *law = c->drive == KC_DRIVE_SCURVE ? &c->drive_scurve
                           : c->ramp_on && (c->drive == KC_DRIVE_NOMINAL || c->drive == KC_DRIVE_STOPPING_WAIT)
                               ? &c->ramp
                               : NULL;
    if (law != NULL) {
        kc_scurve_state s;
        kc_scurve_eval(law, j, &s);
        tau = (double)s.p;
        rate = (double)s.v;
        rate_dot = (double)s.a;
        J = scurve_jmax(law);
        Jnow = fabs((double)s.j);
        H.scurve_ticks++;
    } else if (c->drive == KC_DRIVE_PROFILE) {
        kc_profile_state s;
        kc_profile_eval(&c->drive_prof, j, &s);
        tau = (double)s.p;
        rate = (double)s.v;
        rate_dot = (double)s.a;
        J = (double)INFINITY;
    }
    /* A law whose tick 0 is this tick's setpoint (a RESUME a pause's stop
     * waited for, taken as the stop came to rest there) did not make it:
     * the stop did (the joints' jerk judges that tick, tick_jerk). */
    assert_true(rate >= -LIMIT_SLACK && rate <= 1.0 + LIMIT_SLACK + 4.0 * E * T);
    if (H.active && isfinite(J) && j > 0) {
        double lim = J * dt * (1.0 + LIMIT_SLACK) + 8.0 * E * (fabs(rate_dot) + J * (T + 10.0));
        if (!(fabs(rate_dot - H.rate_dot) <= lim))
            fail_msg("cycle %ld (drive %d): tau'' %.9g -> %.9g, more than J dt = %g", (long)H.out.cycle, c->drive,
                     H.rate_dot, rate_dot, J * dt);
        /* The jerk the law adds through tau''' within the limits. */
        double r = added_jerk_ratio(c, tau, Jnow);
        if (!(r <= 1.0 + 1e-6))
            fail_msg("cycle %ld: the jerk tau''' adds is %g of its limit", (long)H.out.cycle, r);
    }
    H.tau = tau;
    H.rate = rate;
    H.rate_dot = rate_dot;
    H.active = 1;
}

static void run_until(kc_ctrl_state state, int max)
{
    for (int k = 0; k < max && H.out.state != state; k++) {
        tick(NULL, KC_CMD_NONE);
        assert_true(H.out.state != KC_CTRL_FAULT);
    }
    assert_int_equal(H.out.state, state);
}

/* A joint path of n knots: KT_PUMA_Q0 plus offsets[i] on every joint. */
static kc_goal path_goal(int64_t id, kc_path_method method, int n, const kc_real *offsets)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = KC_GOAL_PATH;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.method = method;
    g.n_points = n;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < 6; j++)
            g.points[i][j] = KT_PUMA_Q0[j] + offsets[i];
    return g;
}

/* Lagrange: the ramps from rest and into the end jerk-limited; paused at
 * random ticks and resumed; it ends exactly on the last knot. */
static void test_lagrange_ramps_pause_resume(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x1A6);
    for (int c = 0; c < 6; c++) {
        setup(KC_PROFILE_JERK);
        const kc_real off[3] = {KC_R(0.1), KC_R(0.25), KC_R(0.3)};
        kc_goal p = path_goal(10 + c, KC_PATH_LAGRANGE, 3, off);
        tick(&p, KC_CMD_NONE);
        assert_true(kt_has_event(&H.out, KC_EVENT_STARTED, p.id));
        assert_int_equal(H.ctrl.drive, KC_DRIVE_NOMINAL); /* on its own ramps */
        assert_true(H.ctrl.ramp_on);
        int64_t len = H.ctrl.ramp.ticks;
        if (c > 0) {
            int64_t at = 1 + (int64_t)kt_uniform(&r, 0.0, (double)len - 2.0);
            for (int64_t k = 1; k < at; k++)
                tick(NULL, KC_CMD_NONE);
            tick(NULL, KC_CMD_PAUSE);
            assert_int_equal(H.ctrl.drive, KC_DRIVE_SCURVE);
            run_until(KC_CTRL_PAUSED, 20000);
            assert_true(H.rate == 0.0 && H.rate_dot == 0.0);
            tick(NULL, KC_CMD_RESUME);
        }
        run_until(KC_CTRL_IDLE, 40000);
        assert_int_equal(H.events[KC_EVENT_COMPLETED], 1);
        for (int j = 0; j < 6; j++)
            kt_near((double)H.out.q[j], (double)p.points[2][j], 1e-9, "Lagrange path end");
        assert_true(H.scurve_ticks > 0);
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
    }
}

/* A blend path (its law fixed by the knot times) stopped and paused on
 * the path at random ticks: the stop and the resume are jerk-limited. */
static void test_blend_stop_pause(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0xB1E);
    for (int c = 0; c < 8; c++) {
        setup(KC_PROFILE_JERK);
        const kc_real off[3] = {KC_R(0.3), KC_R(-0.2), KC_R(0.1)};
        kc_goal p = path_goal(20 + c, KC_PATH_BLEND, 3, off);
        tick(&p, KC_CMD_NONE);
        assert_int_equal(H.ctrl.drive, KC_DRIVE_NOMINAL);
        int64_t at = 1 + (int64_t)kt_uniform(&r, 0.0, (double)H.ctrl.plan.path.ticks - 2.0);
        for (int64_t k = 1; k < at; k++)
            tick(NULL, KC_CMD_NONE);
        tick(NULL, c % 2 ? KC_CMD_PAUSE : KC_CMD_STOP);
        /* Jerk-limited; a stop that would pass the end lets the path's own
         * law end it, at rest. */
        assert_true(H.ctrl.drive == KC_DRIVE_SCURVE || H.ctrl.drive == KC_DRIVE_NOMINAL);
        run_until(c % 2 ? KC_CTRL_PAUSED : KC_CTRL_IDLE, 20000);
        if (c % 2) {
            tick(NULL, KC_CMD_RESUME);
            run_until(KC_CTRL_IDLE, 40000);
            for (int j = 0; j < 6; j++)
                kt_near((double)H.out.q[j], (double)p.points[2][j], 1e-9, "blend path end after resume");
        }
        for (int j = 0; j < 6; j++)
            kt_near((double)H.out.qd[j], 0.0, 0.0, "at rest");
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
    }
}

/* A Cartesian spline path paused and resumed, and stopped: the same law
 * with the Cartesian jerk limits. */
static void test_cartesian_path(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0xCA7);
    for (int c = 0; c < 6; c++) {
        setup(KC_PROFILE_JERK);
        kc_pose here;
        kc_fk_eval(&H.chain, KT_PUMA_Q0, &here);
        const kc_real off[2][3] = {{KC_R(0.0), KC_R(0.1), KC_R(0.0)}, {KC_R(0.05), KC_R(0.2), KC_R(0.0)}};
        kc_vec3 knots[2];
        for (int i = 0; i < 2; i++)
            for (int k = 0; k < 3; k++)
                knots[i].v[k] = here.t.v[k] + off[i][k];
        kc_goal p = kt_cart_path_goal(40 + c, KC_PATH_SPLINE, knots, 2, &here.R);
        tick(&p, KC_CMD_NONE);
        assert_true(kt_has_event(&H.out, KC_EVENT_STARTED, p.id));
        int64_t at = 1 + (int64_t)kt_uniform(&r, 0.0, (double)H.ctrl.plan.path_cart.pos.ticks - 2.0);
        for (int64_t k = 1; k < at; k++)
            tick(NULL, KC_CMD_NONE);
        tick(NULL, c % 2 ? KC_CMD_PAUSE : KC_CMD_STOP);
        assert_true(H.ctrl.drive == KC_DRIVE_SCURVE || H.ctrl.drive == KC_DRIVE_NOMINAL); /* (as above) */
        run_until(c % 2 ? KC_CTRL_PAUSED : KC_CTRL_IDLE, 20000);
        if (c % 2) {
            tick(NULL, KC_CMD_RESUME);
            run_until(KC_CTRL_IDLE, 40000);
            assert_int_equal(H.events[KC_EVENT_COMPLETED], 1);
        }
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
    }
}

/* The trapezoid (cfg.profile): the constant-rate ramp of before. */
static void test_trapezoid_ramp(void **state)
{
    (void)state;
    setup(KC_PROFILE_TRAPEZOID);
    const kc_real off[3] = {KC_R(0.1), KC_R(0.25), KC_R(0.3)};
    kc_goal p = path_goal(30, KC_PATH_LAGRANGE, 3, off);
    tick(&p, KC_CMD_NONE);
    assert_int_equal(H.ctrl.drive, KC_DRIVE_PROFILE);
    run_until(KC_CTRL_IDLE, 40000);
    assert_int_equal(H.events[KC_EVENT_COMPLETED], 1);
    assert_int_equal(H.scurve_ticks, 0);
}

/* The largest change of a joint's qdd over a tick, over dt, against its
 * qddd_max, from the setpoint before to this one, while a path runs. */
static double tick_jerk(const kc_real *qdd_before)
{
    double worst = 0.0;
    for (int j = 0; j < H.chain.n_joints; j++)
        worst = fmax(worst, fabs((double)H.out.qdd[j] - (double)qdd_before[j]) / (double)H.cfg.dt /
                                (double)H.chain.joints[j].limits.qddd_max);
    return worst;
}

/* A joint path of a method through 2 to 4 random knots about KT_PUMA_Q0
 * (its knot times computed from the limits, its knot derivatives from
 * the times), run to its end, PAUSEd at a random tick and RESUMEd once
 * paused (pause 1) or within 40 ticks, while its stop may still run
 * (pause 2), or STOPped there (stop != 0): the largest change
 * of a joint's qdd over a tick against qddd_max dt, and the ticks run,
 * added to *worst and *ticks. Ends on its last knot exactly unless
 * stopped. */
static void run_path(kt_rng *r, kc_path_method method, kc_path_spline_end end, int pause, int stop, double *worst,
                     long *ticks)
{
    int n = 2 + (int)kt_uniform(r, 0.0, 3.0);
    kc_goal p = path_goal(40, method, n, (const kc_real[4]){0, 0, 0, 0});
    p.spline_end = end;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < 6; j++)
            p.points[i][j] = KT_PUMA_Q0[j] + (kc_real)kt_uniform(r, -0.4, 0.4);
    int64_t at = 1 + (int64_t)kt_uniform(r, 0.0, 1500.0);
    int64_t early = pause == 2 ? at + 1 + (int64_t)kt_uniform(r, 0.0, 40.0) : -1;
    kc_real before[KC_MAX_JOINTS] = {0};
    tick(&p, KC_CMD_NONE);
    assert_true(kt_has_event(&H.out, KC_EVENT_STARTED, p.id));
    for (int64_t k = 1; k < 40000 && H.out.state != KC_CTRL_IDLE; k++) {
        *worst = fmax(*worst, tick_jerk(before));
        memcpy(before, H.out.qdd, sizeof before);
        kc_ctrl_command cmd = k == at && pause ? KC_CMD_PAUSE : k == at && stop ? KC_CMD_STOP : KC_CMD_NONE;
        if (pause && k > at && (H.out.state == KC_CTRL_PAUSED || (k == early && H.out.state == KC_CTRL_STOPPING)))
            cmd = KC_CMD_RESUME;
        tick(NULL, cmd);
        (*ticks)++;
        assert_true(H.out.state != KC_CTRL_FAULT);
    }
    *worst = fmax(*worst, tick_jerk(before)); /* into rest */
    assert_int_equal(H.out.state, KC_CTRL_IDLE);
    if (!stop || H.events[KC_EVENT_COMPLETED])
        for (int j = 0; j < 6; j++)
            kt_near((double)H.out.q[j], (double)p.points[n - 1][j], 1e-9, "path end");
}

/* Joint paths through random knots, jerk-limited by default: their
 * knot times stretched until their pieces keep every joint's jerk within
 * qddd_max (kinctl/path.h), and the controller's time law (the ramps of
 * a Lagrange path, of a natural spline and of a clamped spline, whose
 * acceleration steps at its ends; the stops, the resumes) adding to the
 * path's own jerk no more than the rest of the limit (kinctl/ctrl.h):
 * every tick of every method is within qddd_max, from rest to rest,
 * through a PAUSE and its RESUME and through a STOP (a parabolic blend's
 * acceleration steps at its blends: not here). Where the law's bounds
 * left out the jerk 3 q'' tau' tau'' adds, quartic blends stopped or
 * paused went to 1.29 times qddd_max, natural splines to 1.27 and
 * Lagrange paths to 1.19; unramped, a clamped spline's ends stepped qdd
 * by 99.7 times qddd_max dt. With the trapezoid profile the same
 * quintics go over. */
static void test_paths_keep_the_jerk(void **state)
{
    (void)state;
    static const struct {
        kc_path_method method;
        kc_path_spline_end end;
        const char *name;
    } M[5] = {{KC_PATH_BLEND, KC_PATH_SPLINE_CLAMPED, "quartic blends"},
              {KC_PATH_SPLINE, KC_PATH_SPLINE_CLAMPED, "clamped splines"},
              {KC_PATH_SPLINE, KC_PATH_SPLINE_NATURAL, "natural splines"},
              {KC_PATH_QUINTIC, KC_PATH_SPLINE_CLAMPED, "quintics"},
              {KC_PATH_LAGRANGE, KC_PATH_SPLINE_CLAMPED, "Lagrange paths"}};
    for (int m = 0; m < 5; m++) {
        kt_rng r = kt_rng_make(0x9517 + (uint64_t)m);
        double worst = 0.0;
        long ticks = 0;
        for (int c = 0; c < 24; c++) {
            setup(KC_PROFILE_JERK);
            run_path(&r, M[m].method, M[m].end, c % 3 == 1 ? 1 + c % 2 : 0, c % 3 == 2, &worst, &ticks);
        }
        print_message("24 %s (8 paused, half of them resumed within 40 ticks; 8 stopped): joints' jerk at most %.7f "
                      "of qddd_max in %ld ticks (%s)\n",
                      M[m].name, worst, ticks, KC_REAL_NAME);
        assert_true(worst <= 1.0 + JERK_SLACK);
    }
    kt_rng r = kt_rng_make(0x9517 + 3);
    double worst = 0.0;
    long ticks = 0;
    for (int c = 0; c < 24; c++) {
        setup(KC_PROFILE_TRAPEZOID);
        run_path(&r, KC_PATH_QUINTIC, KC_PATH_SPLINE_CLAMPED, 0, 0, &worst, &ticks);
    }
    print_message("24 quintics with the trapezoid: joints' jerk up to %.3f of qddd_max in %ld ticks (%s)\n", worst,
                  ticks, KC_REAL_NAME);
    assert_true(worst > 1.0); /* the stretch is what keeps it */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lagrange_ramps_pause_resume),
        cmocka_unit_test(test_blend_stop_pause),
        cmocka_unit_test(test_cartesian_path),
        cmocka_unit_test(test_trapezoid_ramp),
        cmocka_unit_test(test_paths_keep_the_jerk),
    };
    int failed = cmocka_run_group_tests_name("ctrl_pathjerk (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("ctrl_pathjerk");
    return failed;
}
