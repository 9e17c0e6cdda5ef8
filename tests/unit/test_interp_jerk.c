/* SPDX-License-Identifier: BSD-3-Clause */
/* test_interp_jerk.c - jerk-limited lines and arcs (kinctl/interp.h, the
 * line's "Speed law"): on random segments every tick keeps the speed,
 * acceleration and jerk limits of the tool point along its path and of
 * its rotation, the ends are exact, and the duration is the rest-to-rest
 * optimum of u (kt_scurve_optimum_time, independent of kinctl/scurve.h)
 * with the bounds of u derived here from the limits and the geometry; a
 * stop on the path (kc_scurve_plan_stop from (u, u', u'')) and a resume
 * from there keep s, s' and s'' continuous and within the limits. Infinite
 * jerk limits keep the trapezoid (test_interp.c checks it against the
 * vectors).
 *
 * Jerk is measured as the change of the path acceleration sdd over one
 * tick: a piecewise-linear acceleration of slope at most j changes by at
 * most j dt between samples (kinctl/scurve.h, "Ticks"). Slack as
 * test_scurve.c's, for the same reasons (the rounding of t = k dt and of
 * the phase ends, up to eps T, moves the acceleration by up to eps j T):
 * jerk per tick j dt + 8 eps (a + j T) + 16 eps j dt, acceleration
 * a (1 + 16 eps) + 4 eps j T, speed v (1 + 16 eps) + 4 eps a T, T the
 * motion's duration.
 */
#include "kinctl/fx.h"
#include "testutil.h"

#include <stdio.h>

#ifdef KC_REAL_FLOAT
#define FLOAT_BUILD 1
#else
#define FLOAT_BUILD 0
#endif

#define N_RANDOM 200
#define LIMIT_SLACK (16.0 * (double)KC_REAL_EPS)
#define DINF ((double)INFINITY)

/* Relative agreement of a duration with the independent optimum: the
 * bounds of u differ from the plan's by the rounding of a few quotients. */
#define T_TOL (FLOAT_BUILD ? 2e-5 : 1e-9)

typedef kc_status (*eval_fn)(const void *, int64_t, kc_interp_cart_state *);

static kc_status line_eval(const void *p, int64_t k, kc_interp_cart_state *out)
{
    return kc_interp_line_eval(p, k, out);
}

static kc_status arc_eval(const void *p, int64_t k, kc_interp_cart_state *out)
{
    return kc_interp_arc_eval(p, k, out);
}

/* Limits of the speed law's own measure (path length or angle): speed,
 * acceleration, jerk; and the rotation's per unit of that measure. */
typedef struct law {
    double T; /* duration of the motion checked (s), for the slack */
    double v, a, j;
    double rot; /* rotation angle per unit of s (0: none, or s is the angle) */
    double w, dw, dj;
} law;

static void check_jerk_rate(double sdd, double prev, double j, double a, double T, double dt, const char *what)
{
    double lim = j * dt * (1.0 + LIMIT_SLACK) + 8.0 * (double)KC_REAL_EPS * (a + j * T);
    if (!(fabs(sdd - prev) <= lim))
        fail_msg("%s: sdd changes by %g in a tick, more than %g", what, fabs(sdd - prev), lim);
}

/* One state against the law: s', s'' within v, a (and the rotation's
 * w, dw); the change of s'' from the tick before within j (and dj). */
static void check_state(const law *L, const kc_interp_cart_state *st, const kc_interp_cart_state *prev, double dt,
                        const char *what)
{
    double sd = fabs((double)st->sd), sdd = (double)st->sdd, psdd = (double)prev->sdd, E = (double)KC_REAL_EPS;
    if (!(sd <= L->v * (1.0 + LIMIT_SLACK) + 4.0 * E * L->a * L->T) ||
        !(fabs(sdd) <= L->a * (1.0 + LIMIT_SLACK) + 4.0 * E * L->j * L->T))
        fail_msg("%s: |sd| %g (limit %g), |sdd| %g (limit %g)", what, sd, L->v, fabs(sdd), L->a);
    check_jerk_rate(sdd, psdd, L->j, L->a, L->T, dt, what);
    if (L->rot > 0.0) {
        /* The rotation's own bounds; its slack from the rates that bind
         * (an infinite limit bounds nothing). */
        double ab = fmin(L->dw, L->a * L->rot), jb = fmin(L->dj, L->j * L->rot);
        if (isfinite(L->w) && !(sd * L->rot <= L->w * (1.0 + LIMIT_SLACK) + 4.0 * E * ab * L->T))
            fail_msg("%s: angular speed %.17g over %.17g", what, sd * L->rot, L->w);
        assert_true(!isfinite(L->dw) || fabs(sdd) * L->rot <= L->dw * (1.0 + LIMIT_SLACK) + 4.0 * E * jb * L->T);
        if (isfinite(L->dj))
            check_jerk_rate(sdd * L->rot, psdd * L->rot, L->dj, ab, L->T, dt, what);
    }
}

/* Every tick of a planned segment; the end exact. */
static void walk(eval_fn eval, const void *plan, int64_t ticks, double dt, const law *L, const kc_vec3 *p_end,
                 const char *what)
{
    kc_interp_cart_state st, prev;
    assert_int_equal(eval(plan, 0, &prev), ticks > 0 ? KC_OK : KC_DONE);
    assert_true(prev.sd == KC_R(0.0) && prev.sdd == KC_R(0.0));
    st = prev;
    for (int64_t k = 1; k <= ticks; k++) {
        assert_int_equal(eval(plan, k, &st), k < ticks ? KC_OK : KC_DONE);
        check_state(L, &st, &prev, dt, what);
        prev = st;
    }
    assert_true(st.p.v[0] == p_end->v[0] && st.p.v[1] == p_end->v[1] && st.p.v[2] == p_end->v[2]);
    assert_true(st.phase == 4 && st.sd == KC_R(0.0) && st.sdd == KC_R(0.0) && st.u == KC_R(1.0));
}

/* The duration: the optimum of u over 1 with the bounds D-scaled from
 * the limits (terms with infinite limits or no motion impose nothing). */
static void check_duration(double T, int64_t ticks, double dt, double S, double Theta, const kc_interp_limits *lim,
                           const char *what)
{
    double V = DINF, A = DINF, J = DINF;
    if (S > 0.0) {
        V = fmin(V, (double)lim->v / S);
        A = fmin(A, (double)lim->a / S);
        J = fmin(J, (double)lim->j / S);
    }
    if (Theta > 0.0) {
        V = fmin(V, (double)lim->w / Theta);
        A = fmin(A, (double)lim->dw / Theta);
        J = fmin(J, (double)lim->dj / Theta);
    }
    double want = kt_scurve_optimum_time(1.0, V, A, J);
    kt_near(T, want, T_TOL * want, what);
    assert_true((double)ticks * dt >= T * (1.0 - 4.0 * (double)KC_REAL_EPS));
    assert_true((double)(ticks - 1) * dt < T * (1.0 + 4.0 * (double)KC_REAL_EPS));
}

static kc_pose rand_pose_near(kt_rng *r, const kc_pose *base, double dist, double angle)
{
    kc_pose p = *base;
    kc_vec3 d = kt_rand_unit(r), ax = kt_rand_unit(r);
    kc_mat3 Rot;
    for (int i = 0; i < 3; i++)
        p.t.v[i] += (kc_real)dist * d.v[i];
    kc_orient_axis_angle_to_mat3(&ax, (kc_real)angle, &Rot);
    kc_mat3_mul(&base->R, &Rot, &p.R);
    return p;
}

static double rand_dt(kt_rng *r) { return kt_uniform(r, 0.0005, 0.004); }

/* Random limits: finite v, a, j; angular ones finite or not (a pure
 * rotation needs dw, and dj to be jerk-limited). */
static kc_interp_limits rand_limits(kt_rng *r, int t, int pure)
{
    kc_interp_limits l = kc_interp_limits_default();
    l.v = (kc_real)kt_uniform(r, 0.05, 1.0);
    l.a = (kc_real)kt_uniform(r, 0.2, 5.0);
    l.j = (kc_real)kt_uniform(r, 1.0, 100.0);
    if (t % 3 != 0 || pure) {
        l.w = (kc_real)kt_uniform(r, 0.3, 3.0);
        l.dw = (kc_real)kt_uniform(r, 1.0, 10.0);
        l.dj = t % 2 && !pure ? (kc_real)INFINITY : (kc_real)kt_uniform(r, 5.0, 200.0);
    }
    return l;
}

/* The law of a line: along the path (s = S u) with the rotation Theta / S
 * per metre, or on the angle for a pure rotation. */
static law line_law(const kc_interp_line *p, const kc_interp_limits *lim)
{
    law L = {(double)p->T, (double)lim->v, (double)lim->a, (double)lim->j, 0.0, (double)lim->w, (double)lim->dw,
             (double)lim->dj};
    double S = (double)p->length, Th = (double)p->angle > 16.0 * (double)KC_REAL_EPS ? (double)p->angle : 0.0;
    if (S == 0.0) {
        L.v = L.w;
        L.a = L.dw;
        L.j = L.dj;
    } else {
        L.rot = Th / S;
    }
    return L;
}

static void test_line_random(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0E);
    int pure = 0;
    for (int t = 0; t < N_RANDOM; t++) {
        kc_pose a = kt_rand_pose(&r);
        int is_pure = t % 11 == 0;
        kc_pose b = rand_pose_near(&r, &a, is_pure ? 0.0 : kt_uniform(&r, 0.01, 1.5), kt_uniform(&r, 0.05, 3.1));
        kc_interp_limits lim = rand_limits(&r, t, is_pure);
        kc_interp_orient m = t % 2 ? KC_INTERP_SLERP : KC_INTERP_TWO_ROTATIONS;
        double dt = rand_dt(&r);
        kc_interp_line p;
        assert_int_equal(kc_interp_line_plan(&p, &a, &b, &lim, m, (kc_real)dt), KC_OK);
        assert_int_equal(p.kind, KC_PROFILE_JERK);
        pure += p.length == KC_R(0.0);
        law L = line_law(&p, &lim);
        char what[64];
        snprintf(what, sizeof what, "line %d", t);
        walk(line_eval, &p, p.ticks, dt, &L, &b.t, what);
        double Th = (double)p.angle > 16.0 * (double)KC_REAL_EPS ? (double)p.angle : 0.0;
        check_duration((double)p.T, p.ticks, dt, (double)p.length, Th, &lim, what);
    }
    assert_true(pure >= N_RANDOM / 11);
}

static void test_arc_random(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0xA5C);
    for (int t = 0; t < N_RANDOM; t++) {
        /* Three points on a random circle. */
        kc_vec3 c = kt_rand_unit(&r), n = kt_rand_unit(&r), e1 = kt_rand_unit(&r), e2, tmp;
        kc_vec3_scale(&n, kc_vec3_dot(&n, &e1), &tmp);
        kc_vec3_sub(&e1, &tmp, &e1);
        kc_vec3_scale(&e1, KC_R(1.0) / kc_vec3_norm(&e1), &e1);
        kc_vec3_cross(&n, &e1, &e2);
        double R = kt_uniform(&r, 0.05, 1.0), alpha = kt_uniform(&r, 0.2, 2.0 * KT_PI - 0.2);
        double ang[3] = {0.0, alpha * kt_uniform(&r, 0.1, 0.9), alpha};
        kc_pose from = kt_rand_pose(&r);
        kc_vec3 via, to;
        kc_vec3 *pts[3] = {&from.t, &via, &to};
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++)
                pts[k]->v[i] = c.v[i] + (kc_real)(R * (cos(ang[k]) * (double)e1.v[i] + sin(ang[k]) * (double)e2.v[i]));
        kc_interp_limits lim = rand_limits(&r, t, 0);
        double dt = rand_dt(&r);
        kc_interp_arc p;
        assert_int_equal(kc_interp_arc_plan(&p, &from, &via, &to, &lim, (kc_real)dt), KC_OK);
        assert_int_equal(p.kind, KC_PROFILE_JERK);
        /* Tangential law along s = R alpha u; the tool turns by alpha. */
        law L = {(double)p.T, (double)lim.v, (double)lim.a, (double)lim.j, (double)p.angle / (double)p.length,
                 (double)lim.w, (double)lim.dw, (double)lim.dj};
        char what[64];
        snprintf(what, sizeof what, "arc %d", t);
        walk(arc_eval, &p, p.ticks, dt, &L, &to, what);
        check_duration((double)p.T, p.ticks, dt, (double)p.length, (double)p.angle, &lim, what);
    }
}

/* Infinite jerk limits: the trapezoid, its profile the plan's. */
static void test_trapezoid_kept(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x7A9);
    for (int t = 0; t < 50; t++) {
        kc_pose a = kt_rand_pose(&r), b = rand_pose_near(&r, &a, kt_uniform(&r, 0.01, 1.0), kt_uniform(&r, 0.0, 3.0));
        kc_interp_limits lim = kc_interp_limits_default();
        lim.v = (kc_real)kt_uniform(&r, 0.05, 1.0);
        lim.a = (kc_real)kt_uniform(&r, 0.2, 5.0);
        kc_interp_line p;
        kc_profile want;
        assert_int_equal(kc_interp_line_plan(&p, &a, &b, &lim, KC_INTERP_SLERP, KC_R(0.001)), KC_OK);
        assert_int_equal(p.kind, KC_PROFILE_TRAPEZOID);
        assert_true(!kc_isfinite(p.u_jmax));
        assert_int_equal(kc_profile_plan(&want, KC_R(0.0), KC_R(0.0), KC_R(1.0), lim.v / p.length, lim.a / p.length,
                                         KC_R(0.001)),
                         KC_OK);
        assert_true(p.prof.T == want.T && p.prof.ticks == want.ticks && p.ticks == want.ticks && p.T == want.T);
    }
}

/* Stop on the path at a random tick of a random jerk-limited line, then
 * resume from where it rests: s, s' and s'' continuous across both
 * switches, every tick within the limits, the stop short of the end and
 * the resumed motion ending exactly there. */
static void test_line_stop_resume(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x570B);
    for (int t = 0; t < 100; t++) {
        kc_pose a = kt_rand_pose(&r), b = rand_pose_near(&r, &a, kt_uniform(&r, 0.05, 1.5), kt_uniform(&r, 0.0, 3.0));
        kc_interp_limits lim = rand_limits(&r, t, 0);
        double dt = rand_dt(&r);
        kc_interp_line p;
        assert_int_equal(kc_interp_line_plan(&p, &a, &b, &lim, (kc_interp_orient)(t % 2), (kc_real)dt), KC_OK);
        if (p.ticks < 3)
            continue;
        law L = line_law(&p, &lim);
        int64_t k0 = 1 + (int64_t)kt_uniform(&r, 0.0, (double)p.ticks - 2.0);
        kc_interp_cart_state prev, st;
        kc_scurve_state u;
        kc_interp_line_eval(&p, k0, &prev);
        assert_int_equal(kc_scurve_eval(&p.su, k0, &u), KC_OK);
        kc_scurve stop, go;
        assert_int_equal(kc_scurve_plan_stop(&stop, u.p, u.v, u.a, p.u_amax, p.u_jmax, (kc_real)dt), KC_OK);
        /* Tick 0 of the stop is the state it starts from. */
        kc_interp_line_eval_scurve(&p, &stop, 0, &st);
        kt_near((double)st.s, (double)prev.s, 8.0 * (double)KC_REAL_EPS * (double)p.length, "stop: s continuous");
        kt_near((double)st.sd, (double)prev.sd, 8.0 * (double)KC_REAL_EPS * L.v, "stop: sd continuous");
        kt_near((double)st.sdd, (double)prev.sdd, 8.0 * (double)KC_REAL_EPS * L.a, "stop: sdd continuous");
        kc_status s = KC_OK;
        L.T = (double)(p.T + stop.T);
        for (int64_t k = 1; s == KC_OK; k++) {
            s = kc_interp_line_eval_scurve(&p, &stop, k, &st);
            assert_true(s == KC_OK || s == KC_DONE);
            check_state(&L, &st, &prev, dt, "stop");
            assert_true((double)st.sd >= -LIMIT_SLACK * L.v); /* no reversal */
            prev = st;
        }
        assert_true(st.sd == KC_R(0.0) && st.sdd == KC_R(0.0) && st.u <= KC_R(1.0));
        /* Resume from rest at u to rest at 1 within the plan's bounds. */
        assert_int_equal(
            kc_scurve_plan(&go, st.u, KC_R(0.0), KC_R(0.0), KC_R(1.0), p.u_vmax, p.u_amax, p.u_jmax, (kc_real)dt), KC_OK);
        kc_interp_line_eval_scurve(&p, &go, 0, &st);
        kt_near((double)st.s, (double)prev.s, 0.0, "resume: s continuous");
        s = KC_OK;
        L.T = (double)go.T;
        for (int64_t k = 1; s == KC_OK; k++) {
            s = kc_interp_line_eval_scurve(&p, &go, k, &st);
            check_state(&L, &st, &prev, dt, "resume");
            prev = st;
        }
        assert_true(st.p.v[0] == b.t.v[0] && st.p.v[1] == b.t.v[1] && st.p.v[2] == b.t.v[2]);
        assert_true(st.phase == 4 && st.u == KC_R(1.0));
    }
}

static void test_bad_jerk(void **state)
{
    (void)state;
    kc_pose a, b;
    kc_pose_identity(&a);
    b = a;
    b.t.v[0] = KC_R(0.5);
    kc_interp_line p;
    kc_interp_limits lim = kc_interp_limits_default();
    lim.v = KC_R(0.5);
    lim.a = KC_R(1.0);
    /* The fixed-point line converts either law (its accuracy:
     * mcu/fx_test.c), over the plan's ticks. */
    kc_fx_line fx;
    assert_int_equal(kc_interp_line_plan(&p, &a, &b, &lim, KC_INTERP_SLERP, KC_R(0.001)), KC_OK);
    assert_int_equal(kc_fx_line_init(&fx, &p), KC_OK);
    assert_true(fx.ramp.ticks == p.ticks && fx.ramp.n == 3);
    kc_interp_limits jl = lim;
    jl.j = KC_R(5.0);
    assert_int_equal(kc_interp_line_plan(&p, &a, &b, &jl, KC_INTERP_SLERP, KC_R(0.001)), KC_OK);
    assert_int_equal(kc_fx_line_init(&fx, &p), KC_OK);
    assert_true(fx.ramp.ticks == p.ticks && fx.ramp.n == 7);
    kc_real bad[3] = {KC_R(0.0), KC_R(-1.0), (kc_real)NAN};
    for (int i = 0; i < 3; i++) {
        kc_interp_limits l = lim;
        l.j = bad[i];
        assert_int_equal(kc_interp_line_plan(&p, &a, &b, &l, KC_INTERP_SLERP, KC_R(0.001)), KC_E_ARG);
        l = lim;
        l.dj = bad[i];
        assert_int_equal(kc_interp_line_plan(&p, &a, &b, &l, KC_INTERP_SLERP, KC_R(0.001)), KC_E_ARG);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_line_random),      cmocka_unit_test(test_arc_random),
        cmocka_unit_test(test_trapezoid_kept),   cmocka_unit_test(test_line_stop_resume),
        cmocka_unit_test(test_bad_jerk),
    };
    int failed = cmocka_run_group_tests_name("interp_jerk (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("interp_jerk");
    return failed;
}
