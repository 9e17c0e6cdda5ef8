/* SPDX-License-Identifier: BSD-3-Clause */
/* test_scurve.c - jerk-limited motion laws (kinctl/scurve.h): the
 * textbook's worked examples and hand-derived cases, then properties on
 * thousands of seeded random profiles (rest to rest against an independent
 * optimum, stretched, from moving starts) and bad inputs.
 *
 * Slack. Limits are checked with a relative 16 KC_REAL_EPS (rounding of
 * the limit and of the value). The jerk is measured as the change of the
 * acceleration per tick: sampling an acceleration that is piecewise linear
 * with slopes of at most J never shows more than J dt per tick in exact
 * arithmetic. Each sample of a is a + j tau with tau = k dt - tr: k dt
 * and tau carry an error of about eps T, which moves a by J eps T, and the
 * sum rounds by eps |a|. Two samples, so the change per tick may exceed
 * J dt by 2 eps (A + J T); JERK_SLACK allows four times that.
 */
#include "testutil.h"

#include <stdio.h>
#include <string.h>

#include "kinctl/interp.h"
#include "kinctl/scurve.h"

#ifdef KC_REAL_FLOAT
#define FLOAT_BUILD 1
#else
#define FLOAT_BUILD 0
#endif

#define N_RANDOM kt_cases(4000)
#define EPS ((double)KC_REAL_EPS)
#define LIMIT_SLACK (16.0 * EPS)

/* Hand and textbook cases: 1e-4 for four printed digits. */
#define PRINTED_TOL 1e-4

static double rand_dt(kt_rng *r)
{
    static const double dts[] = {0.001, 0.002, 0.004, 0.01, 0.0005, 1.0 / 3000.0};
    return dts[kt_rng_next(r) % 6];
}

/* What a start allows: the speed may exceed V only where the start is
 * faster, or accelerates beyond V before the jerk can stop it; the
 * acceleration only where it starts beyond A. */
static double speed_bound(double v0, double a0, double V, double J)
{
    double vn = fabs(v0 + a0 * fabs(a0) / (2.0 * J));
    double b = V;
    if (fabs(v0) > b)
        b = fabs(v0);
    if (vn > V && vn > b)
        b = vn;
    return b;
}

/* Walks every tick of a profile: the exact start, every tick within the
 * bounds, jerk per tick within J, v and p consistent with a (trapezoidal
 * sums of a piecewise-linear a and piecewise-quadratic v), the exact end on
 * tick `ticks`, and eval_time agreeing with eval. */
static void walk(const kc_scurve *pr, double p0, double v0, double a0, double p1, double V, double A, double J,
                 const char *what)
{
    kc_scurve_state prev, st, sti;
    double dt = (double)pr->dt, T = (double)pr->T;
    double vb = speed_bound(v0, a0, V, J), ab = fabs(a0) > A ? fabs(a0) : A;
    double pscale = fabs(p0) + fabs(p1) + vb * T + 1e-30;
    double jerk_slack = 8.0 * EPS * (ab + J * T) + LIMIT_SLACK * J * dt;
    assert_int_equal(kc_scurve_eval(pr, 0, &st), pr->ticks > 0 ? KC_OK : KC_DONE);
    if (pr->ticks > 0) {
        assert_true((double)st.p == p0 && (double)st.v == v0 && (double)st.a == a0);
    }
    prev = st;
    for (int64_t k = 1; k <= pr->ticks + 1; k++) {
        kc_status s = kc_scurve_eval(pr, k, &st);
        assert_int_equal(s, k < pr->ticks ? KC_OK : KC_DONE);
        assert_int_equal(kc_scurve_eval_time(pr, (kc_real)k * pr->dt, &sti), s);
        assert_true(sti.p == st.p && sti.v == st.v && sti.a == st.a && sti.phase == st.phase);
        if (!(fabs((double)st.v) <= vb * (1.0 + LIMIT_SLACK) + 4.0 * EPS * A * T &&
              fabs((double)st.a) <= ab * (1.0 + LIMIT_SLACK) + 4.0 * EPS * J * T &&
              fabs((double)(st.a - prev.a)) <= J * dt + jerk_slack)) {
            print_error("%s: tick %lld of %lld: v %.9g (bound %.9g) a %.9g (bound %.9g) da/dt %.9g (J %.9g)\n",
                        what, (long long)k, (long long)pr->ticks, (double)st.v, vb, (double)st.a, ab,
                        (double)(st.a - prev.a) / dt, J);
            fail();
        }
        /* v(k) - v(k-1) is the mean acceleration times dt inside a phase;
         * a jerk switch in between costs at most J dt^2 / 4. */
        kt_near((double)(st.v - prev.v), 0.5 * (double)(st.a + prev.a) * dt,
                0.25 * J * dt * dt + 8.0 * EPS * (vb + ab * T + J * T * dt), what);
        /* p by the trapezoid rule of v: error dt^3 |j| / 12 inside a
         * phase, at most J dt^3 / 6 across a switch. */
        kt_near((double)(st.p - prev.p), 0.5 * (double)(st.v + prev.v) * dt,
                J * dt * dt * dt / 6.0 + 16.0 * EPS * (pscale + vb * dt), what);
        prev = st;
    }
    /* Exactly at rest on the target from tick `ticks` on. */
    assert_true((double)st.p == p1 && st.v == KC_R(0.0) && st.a == KC_R(0.0) && st.phase == 4);
    assert_true((kc_real)pr->ticks * pr->dt >= pr->T);
    if (pr->ticks > 0)
        assert_true((kc_real)(pr->ticks - 1) * pr->dt < pr->T);
}

/* A moving start planned into pr: 1; or 0 where its motion is longer
 * than KC_PROFILE_MAX_TICKS ticks of dt (KC_E_CAPACITY: an acceleration
 * far beyond A ramped out at a small J first runs away, e.g. 24 m/s^2 at
 * 3 m/s^3, and comes back at V), checked by the plan at a tick long
 * enough to hold it. */
static int plan_moving(kc_scurve *pr, double p0, double v0, double a0, double p1, double V, double A, double J,
                       double dt)
{
    kc_status st = kc_scurve_plan(pr, (kc_real)p0, (kc_real)v0, (kc_real)a0, (kc_real)p1, (kc_real)V, (kc_real)A,
                                  (kc_real)J, (kc_real)dt);
    if (st == KC_OK)
        return 1;
    assert_int_equal(st, KC_E_CAPACITY);
    kc_scurve coarse;
    assert_int_equal(kc_scurve_plan(&coarse, (kc_real)p0, (kc_real)v0, (kc_real)a0, (kc_real)p1, (kc_real)V,
                                    (kc_real)A, (kc_real)J, KC_R(1.0)),
                     KC_OK);
    assert_true((double)coarse.T / dt > (double)KC_PROFILE_MAX_TICKS);
    return 0;
}

/* ---- hand-checked cases ---- */

static void plan_ok(kc_scurve *pr, double p0, double v0, double a0, double p1, double V, double A, double J, double dt)
{
    assert_int_equal(kc_scurve_plan(pr, (kc_real)p0, (kc_real)v0, (kc_real)a0, (kc_real)p1, (kc_real)V, (kc_real)A,
                                    (kc_real)J, (kc_real)dt),
                     KC_OK);
}

/* Biagiotti & Melchiorri, examples 3.9 and 3.10 (q0 = 0, q1 = 10, v0 = 1,
 * v1 = 0, amax = 10, jmax = 30), and rest-to-rest cases derived by hand. */
static void test_textbook(void **state)
{
    (void)state;
    kc_scurve pr;
    kc_scurve_state st;
    /* Example 3.9, vmax = 5: the book prints Ta = 0.7333, Tv = 1.1433,
     * Td = 0.8333, T = 2.7100, Tj1 = Tj2 = 0.3333, vlim = 5. By hand: from
     * 1 to 5 with A = 10, J = 30: Tj = 1/3, hold (4 - 10/3) / 10 = 1/15,
     * Ta = 11/15 over (1 + 5)/2 * 11/15 = 2.2; the stop Td = 1/3 + 1/6 +
     * 1/3 = 5/6 over 25/12; cruise (10 - 2.2 - 25/12) / 5 = 1.14333. */
    plan_ok(&pr, 0, 1, 0, 10, 5, 10, 30, 0.001);
    kt_near((double)pr.T, 2.71, PRINTED_TOL, "3.9: T");
    kt_near((double)pr.vp, 5.0, 0.0, "3.9: vlim");
    assert_int_equal(pr.n, 7);
    kt_near((double)pr.t_end[2], 0.7333, PRINTED_TOL, "3.9: Ta");
    kt_near((double)(pr.t_end[3] - pr.t_end[2]), 1.1433, PRINTED_TOL, "3.9: Tv");
    kt_near((double)(pr.T - pr.t_end[3]), 0.8333, PRINTED_TOL, "3.9: Td");
    kt_near((double)pr.t_end[0], 0.3333, PRINTED_TOL, "3.9: Tj1");
    kt_near((double)(pr.T - pr.t_end[5]), 0.3333, PRINTED_TOL, "3.9: Tj2");
    kc_scurve_eval_time(&pr, KC_R(0.35), &st);
    kt_near((double)st.a, 10.0, 1e-4, "3.9: alim_a");
    kc_scurve_eval_time(&pr, KC_R(2.3), &st);
    kt_near((double)st.a, -10.0, 1e-4, "3.9: alim_d");
    walk(&pr, 0, 1, 0, 10, 5, 10, 30, "3.9");
    /* Example 3.10, vmax = 10: no cruise; the book prints Ta = 1.0747,
     * Td = 1.1747, T = 2.2494, vlim = 8.4136. By hand, with vlim = v:
     * Ta = (v - 1)/10 + 1/3, Td = v/10 + 1/3, and (1 + v)/2 Ta + v/2 Td
     * = 10 gives v = 8.4136. */
    plan_ok(&pr, 0, 1, 0, 10, 10, 10, 30, 0.001);
    kt_near((double)pr.T, 2.2494, PRINTED_TOL, "3.10: T");
    kt_near((double)pr.vp, 8.4136, PRINTED_TOL, "3.10: vlim");
    assert_int_equal(pr.n, 6);
    kt_near((double)pr.t_end[2], 1.0747, PRINTED_TOL, "3.10: Ta");
    kt_near((double)(pr.T - pr.t_end[2]), 1.1747, PRINTED_TOL, "3.10: Td");
    walk(&pr, 0, 1, 0, 10, 10, 10, 30, "3.10");
    /* Rest to rest, D = 10, V = 5, A = 10, J = 30: V J = 150 >= A^2, so
     * Tj = 1/3, Ta = 1/3 + 1/2 = 5/6, Tv = 10/5 - 5/6 = 7/6, T = 17/6. */
    plan_ok(&pr, 0, 0, 0, 10, 5, 10, 30, 0.001);
    kt_near((double)pr.T, 17.0 / 6.0, 1e-12 + 8.0 * EPS * 3.0, "rest: T, seven phases");
    assert_int_equal(pr.n, 7);
    /* D = 5, V = 10: no cruise, D >= 2 A^3 / J^2 = 20/9: Tj = 1/3,
     * Ta = 1/6 + sqrt(1/36 + 1/2), T = 2 Ta = 1.786299648. */
    plan_ok(&pr, 0, 0, 0, -5, 10, 10, 30, 0.001);
    kt_near((double)pr.T, 2.0 * (1.0 / 6.0 + sqrt(1.0 / 36.0 + 0.5)), 1e-12 + 8.0 * EPS * 2.0, "rest: T, six");
    assert_int_equal(pr.n, 6);
    kt_near((double)pr.vp, -10.0 * (1.0 / 6.0 + sqrt(1.0 / 36.0 + 0.5) - 1.0 / 3.0), 1e-12 + 8.0 * EPS * 10.0,
            "rest: vlim, six");
    /* D = 1: A is not reached either: Tj = (1/60)^(1/3), T = 4 Tj. */
    plan_ok(&pr, 2, 0, 0, 3, 10, 10, 30, 0.001);
    kt_near((double)pr.T, 4.0 * cbrt(1.0 / 60.0), 1e-12 + 8.0 * EPS, "rest: T, four");
    assert_int_equal(pr.n, 4);
    /* D = 0.3, V = 0.5, A = 10, J = 30: V J = 15 < A^2: Tj = sqrt(1/60),
     * Ta = 2 Tj, Tv = 0.6 - Ta > 0: T = 0.6 + 2 sqrt(1/60) (five phases
     * with the cruise: +J, -J, 0, -J, +J). */
    plan_ok(&pr, 0, 0, 0, 0.3, 0.5, 10, 30, 0.001);
    kt_near((double)pr.T, 0.6 + 2.0 * sqrt(1.0 / 60.0), 1e-12 + 8.0 * EPS, "rest: T, five");
    assert_int_equal(pr.n, 5);
}

/* ---- random properties ---- */

static void test_rest_to_rest(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0FE001);
    int kinds[8] = {0};
    for (int n = 0; n < N_RANDOM; n++) {
        double p0 = kt_uniform(&r, -3.0, 3.0), p1 = kt_uniform(&r, -3.0, 3.0);
        double V = kt_uniform(&r, 0.05, 4.0), A = kt_uniform(&r, 0.2, 40.0), J = kt_uniform(&r, 1.0, 800.0);
        double dt = rand_dt(&r);
        if (n % 11 == 0)
            p1 = p0;
        kc_scurve pr;
        plan_ok(&pr, p0, 0, 0, p1, V, A, J, dt);
        double p0r = (double)(kc_real)p0, p1r = (double)(kc_real)p1;
        walk(&pr, p0r, 0, 0, p1r, (double)(kc_real)V, (double)(kc_real)A, (double)(kc_real)J, "rest to rest");
        kinds[pr.n]++;
        double T = kt_scurve_optimum_time(fabs((double)((kc_real)p1 - (kc_real)p0)), (double)(kc_real)V,
                                          (double)(kc_real)A, (double)(kc_real)J);
        kt_near((double)pr.T, T, 1e-9 * (T + 1.0) + (FLOAT_BUILD ? 64.0 * EPS * (T + 1.0) : 0.0), "optimum T");
    }
    /* Every shape occurred: none, four, five, six and seven phases. */
    assert_true(kinds[0] > 0 && kinds[4] > 0 && kinds[5] > 0 && kinds[6] > 0 && kinds[7] > 0);
}

static void test_stretched(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0FE002);
    for (int n = 0; n < N_RANDOM; n++) {
        double p0 = kt_uniform(&r, -3.0, 3.0), p1 = kt_uniform(&r, -3.0, 3.0);
        double V = kt_uniform(&r, 0.05, 4.0), A = kt_uniform(&r, 0.2, 40.0), J = kt_uniform(&r, 1.0, 800.0);
        double dt = rand_dt(&r);
        kc_scurve fast, pr;
        plan_ok(&fast, p0, 0, 0, p1, V, A, J, dt);
        /* Up to four times longer; a fifth exactly the optimum. */
        double f = n % 5 == 0 ? 1.0 : kt_uniform(&r, 1.0, 4.0);
        kc_real T = (kc_real)((double)fast.T * f);
        assert_int_equal(kc_scurve_plan_duration(&pr, (kc_real)p0, (kc_real)p1, (kc_real)V, (kc_real)A, (kc_real)J,
                                                 T, (kc_real)dt),
                         KC_OK);
        assert_true(pr.T == (f == 1.0 ? fast.T : T));
        walk(&pr, (double)(kc_real)p0, 0, 0, (double)(kc_real)p1, (double)(kc_real)V, (double)(kc_real)A,
             (double)(kc_real)J, "stretched");
        /* Shorter than the optimum is refused. */
        if (fast.T > KC_R(0.0)) {
            kc_real Ts = fast.T * KC_R(0.999);
            assert_int_equal(kc_scurve_plan_duration(&pr, (kc_real)p0, (kc_real)p1, (kc_real)V, (kc_real)A,
                                                     (kc_real)J, Ts, (kc_real)dt),
                             KC_E_LIMIT);
        }
    }
}

static void test_moving_start(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0FE003);
    int over = 0, fast = 0, hard = 0, away = 0, gap = 0, slower = 0, too_long = 0;
    double worst = 0.0;
    for (int n = 0; n < N_RANDOM; n++) {
        double p0 = kt_uniform(&r, -2.0, 2.0), p1 = kt_uniform(&r, -2.0, 2.0);
        double V = kt_uniform(&r, 0.1, 3.0), A = kt_uniform(&r, 0.5, 30.0), J = kt_uniform(&r, 2.0, 600.0);
        double dt = rand_dt(&r);
        /* Up to twice the limits, either way; a third within them. */
        double lim = n % 3 == 0 ? 1.0 : 2.0;
        double v0 = kt_uniform(&r, -lim * V, lim * V), a0 = kt_uniform(&r, -lim * A, lim * A);
        if (n % 17 == 0)
            p1 = p0; /* already there, but moving */
        kc_scurve pr;
        if (!plan_moving(&pr, p0, v0, a0, p1, V, A, J, dt)) {
            too_long++;
            continue;
        }
        double v0r = (double)(kc_real)v0, a0r = (double)(kc_real)a0;
        walk(&pr, (double)(kc_real)p0, v0r, a0r, (double)(kc_real)p1, (double)(kc_real)V, (double)(kc_real)A,
             (double)(kc_real)J, "moving start");
        fast += fabs(v0) > V;
        hard += fabs(a0) > A;
        away += v0 * (p1 - p0) < 0.0;
        over += (double)pr.vp * (p1 - p0) < 0.0;
        /* Replanning from the state at a tick in the middle never ends
         * later: the rest of the plan is a member of the family the
         * planner searches from there. It ends earlier where the plan was
         * not time-optimal (a start outside both families' optimum,
         * kinctl/scurve.h): counted and bounded. */
        gap += pr.gap;
        if (pr.ticks > 2) {
            kc_scurve_state mid;
            int64_t m = pr.ticks / 2;
            kc_scurve_eval(&pr, m, &mid);
            kc_scurve re;
            assert_int_equal(kc_scurve_plan(&re, mid.p, mid.v, mid.a, (kc_real)p1, (kc_real)V, (kc_real)A, (kc_real)J,
                                            (kc_real)dt),
                             KC_OK);
            double left = (double)pr.T - (double)m * dt;
            double tol = 1e-7 * ((double)pr.T + 1.0) + (FLOAT_BUILD ? 2e-3 * ((double)pr.T + 1.0) : 0.0);
            if ((double)re.T > left + tol)
                print_message("case %d: p0 %.17g v0 %.17g a0 %.17g p1 %.17g V %.17g A %.17g J %.17g: vp %.9g, "
                              "replanned vp %.9g\n",
                              n, p0, v0, a0, p1, V, A, J, (double)pr.vp, (double)re.vp);
            assert_true((double)re.T <= left + tol);
            if ((double)re.T < left - tol) {
                double ex = (left - (double)re.T) / (double)pr.T;
                slower++;
                if (ex > worst)
                    worst = ex;
            }
        }
    }
    print_message("moving starts: %d of %d planned by the gap family; %d replanned faster from the middle, "
                  "by at most %.3g of the duration; %d longer than the ticks a plan holds\n",
                  gap, N_RANDOM, slower, worst, too_long);
    assert_true(too_long <= N_RANDOM / 1000);
    assert_true(fast > N_RANDOM / 5 && hard > N_RANDOM / 5 && away > N_RANDOM / 5 && over > N_RANDOM / 20);
    /* Both families occurred; the measured shortfall (8 of 4000 cases,
     * at most 11 % of the duration) stays where it was. */
    assert_true(gap > 0 && gap < N_RANDOM);
    assert_true(slower <= N_RANDOM / 200 && worst < 0.15);
}

/* Moving starts stretched to a longer duration: the plan lasts exactly
 * that long and walks clean (a target at rest is reached in any duration
 * from the optimum on: no blocked intervals), also from starts beyond
 * the limits. */
static void test_moving_stretched(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0FE007);
    int done = 0;
    for (int n = 0; n < N_RANDOM; n++) {
        double p0 = kt_uniform(&r, -2.0, 2.0), p1 = kt_uniform(&r, -2.0, 2.0);
        double V = kt_uniform(&r, 0.1, 3.0), A = kt_uniform(&r, 0.5, 30.0), J = kt_uniform(&r, 2.0, 600.0);
        double dt = rand_dt(&r), lim = n % 2 == 0 ? 0.8 : 1.5;
        double v0 = kt_uniform(&r, -lim * V, lim * V), a0 = kt_uniform(&r, -lim * A, lim * A);
        kc_scurve fast, pr;
        double f = n % 7 == 0 ? 1.0 : kt_uniform(&r, 1.0, 3.0);
        if (!plan_moving(&fast, p0, v0, a0, p1, V, A, J, dt))
            continue; /* beyond the ticks a plan holds (counted in test_moving_start's draw) */
        kc_real T = (kc_real)((double)fast.T * f);
        kc_status st = kc_scurve_plan_duration_from(&pr, (kc_real)p0, (kc_real)v0, (kc_real)a0, (kc_real)p1,
                                                    (kc_real)V, (kc_real)A, (kc_real)J, T, (kc_real)dt);
        assert_int_equal(st, KC_OK);
        done++;
        assert_true(pr.T == (f == 1.0 ? fast.T : T));
        walk(&pr, (double)(kc_real)p0, (double)(kc_real)v0, (double)(kc_real)a0, (double)(kc_real)p1,
             (double)(kc_real)V, (double)(kc_real)A, (double)(kc_real)J, "moving, stretched");
    }
    assert_true(done >= N_RANDOM - N_RANDOM / 1000);
    /* From rest it is kc_scurve_plan_duration. */
    kc_scurve a, b;
    assert_int_equal(kc_scurve_plan_duration_from(&a, 0, 0, 0, KC_R(1.0), KC_R(1.0), KC_R(2.0), KC_R(10.0), KC_R(4.0),
                                                  KC_R(0.001)),
                     KC_OK);
    assert_int_equal(kc_scurve_plan_duration(&b, 0, KC_R(1.0), KC_R(1.0), KC_R(2.0), KC_R(10.0), KC_R(4.0), KC_R(0.001)),
                     KC_OK);
    assert_true(a.T == b.T && a.ticks == b.ticks && a.n == b.n && a.vp == b.vp);
    for (int i = 0; i < a.n; i++)
        assert_true(a.t_end[i] == b.t_end[i] && a.pr[i] == b.pr[i] && a.vr[i] == b.vr[i] && a.ar[i] == b.ar[i] &&
                    a.j[i] == b.j[i]);
    assert_int_equal(kc_scurve_plan_duration_from(&a, 0, KC_R(0.5), 0, KC_R(1.0), KC_R(1.0), KC_R(2.0), KC_R(10.0),
                                                  KC_R(0.1), KC_R(0.001)),
                     KC_E_LIMIT);
}

/* Whether a stretched profile ends with a rest at p1 before its
 * duration (kc_scurve_plan_duration_from: the optimum, then rest). */
static int ends_at_rest(const kc_scurve *pr)
{
    int i = pr->n - 1;
    return i > 0 && pr->kind[i] == 3 && pr->j[i] == KC_R(0.0) && pr->vr[i] == KC_R(0.0) && pr->ar[i] == KC_R(0.0);
}

/* Moving starts the limits hold (|v0| <= V, |a0| <= A, the speed with a0
 * ramped out within V) with small jerk limits, stretched to durations
 * from the optimum to twice it, the steps near the optimum fine: a target
 * at rest is reached in every one of them (arriving early and resting at
 * p1 is one way), so every stretch plans, lasts exactly its duration and
 * walks clean. A slower cruise does not reach all of them (jmax of a few
 * rad/s^3 or less: docs/testing.md); a slower stop or a push first
 * reaches nearly all of the rest, and a rest at p1 after the optimum the
 * others, counted. */
static void test_moving_stretched_small_jerk(void **state)
{
    (void)state;
    static const double factors[] = {1.0 + 1e-9, 1.001, 1.01, 1.03, 1.06, 1.1, 1.15, 1.2, 1.35, 1.6, 2.0};
    const int nf = (int)(sizeof factors / sizeof factors[0]);
    kt_rng r = kt_rng_make(0x19A11E);
    int stretched = 0, rests = 0;
    for (int n = 0; n < N_RANDOM / 4; n++) {
        double V = kt_uniform(&r, 0.3, 3.0), A = kt_uniform(&r, 1.0, 30.0);
        double J = n % 4 == 0 ? kt_uniform(&r, 0.1, 1.0) : kt_uniform(&r, 1.0, 3.0);
        double v0, a0;
        do {
            v0 = kt_uniform(&r, -V, V);
            a0 = kt_uniform(&r, -A, A);
        } while (fabs(v0 + a0 * fabs(a0) / (2.0 * J)) > V);
        double p0 = kt_uniform(&r, -1.5, 1.5), p1 = kt_uniform(&r, -1.5, 1.5), dt = n % 2 ? 0.004 : 0.01;
        kc_scurve fast, pr;
        plan_ok(&fast, p0, v0, a0, p1, V, A, J, dt);
        for (int i = 0; i < nf; i++) {
            kc_real T = (kc_real)((double)fast.T * factors[i]);
            if (!(T > fast.T))
                continue;
            assert_int_equal(kc_scurve_plan_duration_from(&pr, (kc_real)p0, (kc_real)v0, (kc_real)a0, (kc_real)p1,
                                                          (kc_real)V, (kc_real)A, (kc_real)J, T, (kc_real)dt),
                             KC_OK);
            assert_true(pr.T == T);
            walk(&pr, (double)(kc_real)p0, (double)(kc_real)v0, (double)(kc_real)a0, (double)(kc_real)p1,
                 (double)(kc_real)V, (double)(kc_real)A, (double)(kc_real)J, "small jerk, stretched");
            stretched++;
            rests += ends_at_rest(&pr);
        }
    }
    print_message("small-jerk moving starts: %d stretched, %d of them by a rest at p1\n", stretched, rests);
    assert_true(rests < stretched / 500);
}

/* Three starts whose stretch no slower cruise reaches (all seen as
 * blocked intervals before, 1-20 % longer than the optimum): a cruise
 * below vn would pass the target, and a slower stop takes it; the
 * optimum is of the gap family with a0 beyond what a slower stop keeps,
 * and a push of the acceleration first takes it (Ruckig's valley, jerk
 * -, +, -, +); neither reaches the third, which rests on its target after
 * its optimum (in the double build; the float one rounds the start). */
static void test_moving_stretched_blocked_cases(void **state)
{
    (void)state;
    static const double cases[3][7] = {
        {-0.2177244670, 0.4823555760, 0.7569098471, 0.8832020769, 2.8256592952, 28.8494566580, 1.3512147572},
        {-0.4969997830, 2.2350681809, -4.8603075210, 0.1326762425, 2.8399832101, 12.3238779830, 17.8865519036},
        {0.8794258713516827, -1.6962400634702395, 1.3681461724549648, -0.4353161086300843, 1.7028332481321455,
         1.414325258231972, 2.258146308822382},
    };
    int rests = 0;
    for (int c = 0; c < 3; c++) {
        const double *k = cases[c];
        kc_scurve fast, pr;
        plan_ok(&fast, k[0], k[1], k[2], k[3], k[4], k[5], k[6], 0.001);
        for (int i = 1; i <= 20; i++) {
            kc_real T = fast.T * (KC_R(1.0) + KC_R(0.01) * (kc_real)i);
            assert_int_equal(kc_scurve_plan_duration_from(&pr, (kc_real)k[0], (kc_real)k[1], (kc_real)k[2],
                                                          (kc_real)k[3], (kc_real)k[4], (kc_real)k[5], (kc_real)k[6],
                                                          T, KC_R(0.001)),
                             KC_OK);
            assert_true(pr.T == T);
            walk(&pr, (double)(kc_real)k[0], (double)(kc_real)k[1], (double)(kc_real)k[2], (double)(kc_real)k[3],
                 k[4], k[5], k[6], "blocked case, stretched");
            if (c < 2)
                assert_false(ends_at_rest(&pr));
            else
                rests += ends_at_rest(&pr);
        }
    }
    assert_true(FLOAT_BUILD || rests > 0);
}

/* A start at rest through the moving-start search (a speck of velocity)
 * takes the rest-to-rest time: the two methods agree. */
static void test_moving_agrees_with_rest(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0FE004);
    for (int n = 0; n < N_RANDOM / 4; n++) {
        double p0 = kt_uniform(&r, -2.0, 2.0), p1 = kt_uniform(&r, -2.0, 2.0);
        double V = kt_uniform(&r, 0.1, 3.0), A = kt_uniform(&r, 0.5, 30.0), J = kt_uniform(&r, 2.0, 600.0);
        kc_scurve rest, moving;
        plan_ok(&rest, p0, 0, 0, p1, V, A, J, 0.001);
        plan_ok(&moving, p0, 1e-7 * V, 0, p1, V, A, J, 0.001);
        kt_near((double)moving.T, (double)rest.T, 1e-5 * ((double)rest.T + 1.0), "speck of velocity");
    }
}

/* Scales far apart: distances from 1e-9 to 1e3, limits over many decades
 * (log-uniform), starts within and outside the limits, and stretched
 * moves; every plan either succeeds and walks clean or, when it would
 * last more than KC_PROFILE_MAX_TICKS ticks, says KC_E_CAPACITY. */
static double log_uniform(kt_rng *r, double lo, double hi)
{
    return exp(kt_uniform(r, log(lo), log(hi)));
}

static void test_extreme_scales(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0FE006);
    int walked = 0;
    for (int n = 0; n < N_RANDOM / 2; n++) {
        double D = log_uniform(&r, 1e-9, 1e3) * (kt_uniform(&r, 0.0, 1.0) < 0.5 ? -1.0 : 1.0);
        double V = log_uniform(&r, 1e-3, 1e3), A = log_uniform(&r, 1e-2, 1e4), J = log_uniform(&r, 1e-1, 1e6);
        double dt = rand_dt(&r), p0 = kt_uniform(&r, -10.0, 10.0);
        double v0 = 0.0, a0 = 0.0;
        if (n % 2 == 1) {
            v0 = kt_uniform(&r, -1.5, 1.5) * V;
            a0 = kt_uniform(&r, -1.5, 1.5) * A;
        }
        kc_scurve pr;
        kc_status st = kc_scurve_plan(&pr, (kc_real)p0, (kc_real)v0, (kc_real)a0, (kc_real)(p0 + D), (kc_real)V,
                                      (kc_real)A, (kc_real)J, (kc_real)dt);
        if (st == KC_E_CAPACITY)
            continue;
        assert_int_equal(st, KC_OK);
        assert_true(kc_isfinite(pr.T) && pr.T >= KC_R(0.0));
        if (pr.ticks > 200000)
            continue;
        walked++;
        double p1r = (double)(kc_real)(p0 + D);
        walk(&pr, (double)(kc_real)p0, (double)(kc_real)v0, (double)(kc_real)a0, p1r, (double)(kc_real)V,
             (double)(kc_real)A, (double)(kc_real)J, "extreme scales");
        if (n % 2 == 0) {
            kc_scurve ps;
            kc_real T = pr.T * (kc_real)kt_uniform(&r, 1.0, 3.0);
            st = kc_scurve_plan_duration(&ps, (kc_real)p0, (kc_real)(p0 + D), (kc_real)V, (kc_real)A, (kc_real)J, T,
                                         (kc_real)dt);
            if (st == KC_E_CAPACITY || T / (kc_real)dt > KC_R(200000.0))
                continue;
            assert_int_equal(st, KC_OK);
            walk(&ps, (double)(kc_real)p0, 0, 0, p1r, (double)(kc_real)V, (double)(kc_real)A, (double)(kc_real)J,
                 "extreme scales, stretched");
        }
    }
    assert_true(walked > N_RANDOM / 4);
}

/* ---- the synchronised joint move (kinctl/interp.h) ---- */

/* Random joint moves of 1..7 joints, equal limits in a third of them:
 * every joint starts on tick 0 and is exactly on its target from the
 * move's last tick, each within its own limits (jerk per tick as in
 * walk), the duration the longest of the joints' independent optima, a
 * straight line whenever the phase synchronisation is taken (always with
 * equal limits). */
static void test_joint_move(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0FE005);
    int phase = 0, timed = 0;
    for (int c = 0; c < N_RANDOM / 4; c++) {
        kc_interp_joint_cfg cfg = kc_interp_joint_cfg_default();
        int equal = c % 3 == 0;
        cfg.n = 1 + (int)(kt_rng_next(&r) % 7);
        cfg.dt = (kc_real)rand_dt(&r);
        cfg.profile = KC_PROFILE_JERK;
        double T_opt = 0.0;
        for (int i = 0; i < cfg.n; i++) {
            cfg.q0[i] = (kc_real)kt_uniform(&r, -3.0, 3.0);
            cfg.q1[i] = i == 2 && c % 5 == 0 ? cfg.q0[i] : (kc_real)kt_uniform(&r, -3.0, 3.0);
            cfg.qd_max[i] = equal && i > 0 ? cfg.qd_max[0] : (kc_real)kt_uniform(&r, 0.3, 4.0);
            cfg.qdd_max[i] = equal && i > 0 ? cfg.qdd_max[0] : (kc_real)kt_uniform(&r, 1.0, 40.0);
            cfg.qddd_max[i] = equal && i > 0 ? cfg.qddd_max[0] : (kc_real)kt_uniform(&r, 5.0, 800.0);
            double Ti = kt_scurve_optimum_time(fabs((double)(cfg.q1[i] - cfg.q0[i])), (double)cfg.qd_max[i],
                                               (double)cfg.qdd_max[i], (double)cfg.qddd_max[i]);
            if (Ti > T_opt)
                T_opt = Ti;
        }
        if (c % 4 == 1)
            cfg.duration = (kc_real)(T_opt * kt_uniform(&r, 1.01, 2.0));
        kc_interp_joint plan;
        assert_int_equal(kc_interp_joint_plan_cfg(&plan, &cfg), KC_OK);
        double T = cfg.duration > KC_R(0.0) ? (double)cfg.duration : T_opt;
        kt_near((double)plan.T, T, 1e-9 * (T + 1.0) + (FLOAT_BUILD ? 64.0 * EPS * (T + 1.0) : 0.0), "joint move T");
        assert_true((kc_real)plan.ticks * cfg.dt >= plan.T);
        if (equal)
            assert_int_equal(plan.sync, KC_INTERP_SYNC_PHASE);
        phase += plan.sync == KC_INTERP_SYNC_PHASE;
        timed += plan.sync == KC_INTERP_SYNC_TIME;
        kc_interp_joint_state prev, st;
        assert_int_equal(kc_interp_joint_eval(&plan, 0, &prev), plan.ticks > 0 ? KC_OK : KC_DONE);
        for (int i = 0; i < cfg.n; i++)
            assert_true(prev.q[i] == cfg.q0[i] && prev.qd[i] == KC_R(0.0) && prev.qdd[i] == KC_R(0.0));
        double dt = (double)cfg.dt;
        st = prev;
        for (int64_t k = 1; k <= plan.ticks; k++) {
            kc_status s = kc_interp_joint_eval(&plan, k, &st);
            assert_int_equal(s, k < plan.ticks ? KC_OK : KC_DONE);
            for (int i = 0; i < cfg.n; i++) {
                double V = (double)cfg.qd_max[i], A = (double)cfg.qdd_max[i], J = (double)cfg.qddd_max[i];
                double jerk_slack = 8.0 * EPS * (A + J * T) + LIMIT_SLACK * J * dt;
                if (!(fabs((double)st.qd[i]) <= V * (1.0 + LIMIT_SLACK) + 4.0 * EPS * A * T &&
                      fabs((double)st.qdd[i]) <= A * (1.0 + LIMIT_SLACK) + 4.0 * EPS * J * T &&
                      fabs((double)(st.qdd[i] - prev.qdd[i])) <= J * dt + jerk_slack &&
                      fabs((double)st.qddd[i]) <= J * (1.0 + LIMIT_SLACK))) {
                    print_error("move %d joint %d tick %lld: qd %.9g (%.9g) qdd %.9g (%.9g) jerk %.9g (%.9g)\n", c,
                                i, (long long)k, (double)st.qd[i], V, (double)st.qdd[i], A,
                                (double)(st.qdd[i] - prev.qdd[i]) / dt, J);
                    fail();
                }
                /* A straight line: every joint at the same fraction. */
                if (plan.sync == KC_INTERP_SYNC_PHASE && cfg.q1[i] != cfg.q0[i])
                    kt_near((double)((st.q[i] - cfg.q0[i]) / (cfg.q1[i] - cfg.q0[i])), (double)st.u,
                            16.0 * EPS * (fabs((double)cfg.q0[i]) + fabs((double)cfg.q1[i]) + 1.0) /
                                fabs((double)(cfg.q1[i] - cfg.q0[i])),
                            "straight line");
            }
            prev = st;
        }
        /* Every joint on its target, at rest, on the same last tick. */
        for (int i = 0; i < cfg.n; i++)
            assert_true(st.q[i] == cfg.q1[i] && st.qd[i] == KC_R(0.0) && st.qdd[i] == KC_R(0.0));
        /* The trapezoid through the request is kc_interp_joint_plan (the
         * fastest: its straight line may be slower than the jerk-limited
         * move synchronised by time). */
        kc_interp_joint trap, trap_cfg;
        cfg.profile = KC_PROFILE_TRAPEZOID;
        cfg.duration = KC_R(0.0);
        assert_int_equal(kc_interp_joint_plan_cfg(&trap_cfg, &cfg), KC_OK);
        assert_int_equal(kc_interp_joint_plan(&trap, cfg.n, cfg.q0, cfg.q1, cfg.qd_max, cfg.qdd_max, cfg.duration,
                                              cfg.dt),
                         KC_OK);
        assert_true(trap.prof.T == trap_cfg.prof.T && trap.ticks == trap_cfg.ticks && trap.ticks == trap.prof.ticks);
    }
    assert_true(phase > N_RANDOM / 20 && timed > N_RANDOM / 20);
}

/* Joint moves from moving starts (time synchronisation): the start state
 * exact on tick 0, every joint within what its start allows, all exactly
 * on target on one tick, the duration the slowest joint's own optimum
 * (every joint's stretch reaches it, kinctl/scurve.h). */
static void test_joint_move_moving(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0FE008);
    int longer = 0;
    for (int c = 0; c < N_RANDOM / 8; c++) {
        kc_interp_joint_cfg cfg = kc_interp_joint_cfg_default();
        cfg.n = 1 + (int)(kt_rng_next(&r) % 7);
        cfg.dt = (kc_real)rand_dt(&r);
        cfg.profile = KC_PROFILE_JERK;
        double lim = c % 2 == 0 ? 0.8 : 1.5, T_opt = 0.0;
        for (int i = 0; i < cfg.n; i++) {
            cfg.q0[i] = (kc_real)kt_uniform(&r, -3.0, 3.0);
            cfg.q1[i] = i == 1 ? cfg.q0[i] : (kc_real)kt_uniform(&r, -3.0, 3.0);
            cfg.qd_max[i] = (kc_real)kt_uniform(&r, 0.3, 4.0);
            cfg.qdd_max[i] = (kc_real)kt_uniform(&r, 1.0, 40.0);
            cfg.qddd_max[i] = (kc_real)kt_uniform(&r, 5.0, 800.0);
            cfg.qd0[i] = (kc_real)(lim * kt_uniform(&r, -1.0, 1.0) * (double)cfg.qd_max[i]);
            cfg.qdd0[i] = (kc_real)(lim * kt_uniform(&r, -1.0, 1.0) * (double)cfg.qdd_max[i]);
            kc_scurve one;
            assert_int_equal(kc_scurve_plan(&one, cfg.q0[i], cfg.qd0[i], cfg.qdd0[i], cfg.q1[i], cfg.qd_max[i],
                                            cfg.qdd_max[i], cfg.qddd_max[i], cfg.dt),
                             KC_OK);
            if ((double)one.T > T_opt)
                T_opt = (double)one.T;
        }
        kc_interp_joint plan;
        assert_int_equal(kc_interp_joint_plan_cfg(&plan, &cfg), KC_OK);
        /* Time synchronisation, or a start on the line to the target
         * staying on it (no faster: the stretches reach the optimum). */
        assert_true(plan.sync == KC_INTERP_SYNC_TIME || plan.sync == KC_INTERP_SYNC_PHASE);
        assert_true((double)plan.T >= T_opt * (1.0 - 8.0 * EPS));
        longer += (double)plan.T > T_opt * (1.0 + 8.0 * EPS);
        kc_interp_joint_state prev, st;
        kc_interp_joint_eval(&plan, 0, &prev);
        /* The start: exact, or on the line dq times the rates of u (the
         * rounding of one product). */
        for (int i = 0; i < cfg.n; i++) {
            double tv = plan.sync == KC_INTERP_SYNC_TIME ? 0.0 : 64.0 * EPS * (fabs((double)cfg.qd0[i]) + 1e-300);
            double ta = plan.sync == KC_INTERP_SYNC_TIME ? 0.0 : 64.0 * EPS * (fabs((double)cfg.qdd0[i]) + 1e-300);
            assert_true(prev.q[i] == cfg.q0[i] && fabs((double)(prev.qd[i] - cfg.qd0[i])) <= tv &&
                        fabs((double)(prev.qdd[i] - cfg.qdd0[i])) <= ta);
        }
        double dt = (double)cfg.dt, T = (double)plan.T;
        st = prev;
        for (int64_t k = 1; k <= plan.ticks; k++) {
            assert_int_equal(kc_interp_joint_eval(&plan, k, &st), k < plan.ticks ? KC_OK : KC_DONE);
            for (int i = 0; i < cfg.n; i++) {
                double J = (double)cfg.qddd_max[i];
                double V = speed_bound((double)cfg.qd0[i], (double)cfg.qdd0[i], (double)cfg.qd_max[i], J);
                double A = fabs((double)cfg.qdd0[i]) > (double)cfg.qdd_max[i] ? fabs((double)cfg.qdd0[i])
                                                                                : (double)cfg.qdd_max[i];
                double jerk_slack = 8.0 * EPS * (A + J * T) + LIMIT_SLACK * J * dt;
                if (!(fabs((double)st.qd[i]) <= V * (1.0 + LIMIT_SLACK) + 4.0 * EPS * A * T &&
                      fabs((double)st.qdd[i]) <= A * (1.0 + LIMIT_SLACK) + 4.0 * EPS * J * T &&
                      fabs((double)(st.qdd[i] - prev.qdd[i])) <= J * dt + jerk_slack)) {
                    print_error("moving move %d joint %d tick %lld: qd %.9g (%.9g) qdd %.9g (%.9g) jerk %.9g (%.9g)\n",
                                c, i, (long long)k, (double)st.qd[i], V, (double)st.qdd[i], A,
                                (double)(st.qdd[i] - prev.qdd[i]) / dt, J);
                    fail();
                }
            }
            prev = st;
        }
        for (int i = 0; i < cfg.n; i++)
            assert_true(st.q[i] == cfg.q1[i] && st.qd[i] == KC_R(0.0) && st.qdd[i] == KC_R(0.0));
    }
    print_message("moving joint moves: %d of %d longer than the slowest joint's optimum\n", longer, N_RANDOM / 8);
    assert_int_equal(longer, 0);
}

static void test_joint_move_bad(void **state)
{
    (void)state;
    kc_interp_joint plan;
    kc_interp_joint_cfg cfg = kc_interp_joint_cfg_default();
    cfg.n = 2;
    cfg.q1[0] = KC_R(1.0);
    cfg.qdd_max[0] = cfg.qdd_max[1] = KC_R(1.0);
    cfg.qddd_max[0] = KC_R(1.0);
    cfg.dt = KC_R(0.001);
    cfg.profile = KC_PROFILE_JERK;
    memset(&plan, KT_SENTINEL, sizeof plan);
    /* Joint 2 does not move: its jerk limit 0 is not needed. */
    assert_int_equal(kc_interp_joint_plan_cfg(&plan, &cfg), KC_OK);
    cfg.q1[1] = KC_R(1.0);
    memset(&plan, KT_SENTINEL, sizeof plan);
    assert_int_equal(kc_interp_joint_plan_cfg(&plan, &cfg), KC_E_ARG);
    assert_true(kt_is_sentinel(&plan, sizeof plan));
    cfg.qddd_max[1] = KC_R(1.0);
    cfg.duration = KC_R(0.5);
    assert_int_equal(kc_interp_joint_plan_cfg(&plan, &cfg), KC_E_LIMIT);
    cfg.duration = KC_R(0.0);
    cfg.profile = (kc_profile_kind)7;
    assert_int_equal(kc_interp_joint_plan_cfg(&plan, &cfg), KC_E_ARG);
    /* A moving start is the jerk-limited kind's alone; finite. */
    cfg.profile = KC_PROFILE_TRAPEZOID;
    cfg.qd0[0] = KC_R(0.1);
    assert_int_equal(kc_interp_joint_plan_cfg(&plan, &cfg), KC_E_ARG);
    cfg.profile = KC_PROFILE_JERK;
    assert_int_equal(kc_interp_joint_plan_cfg(&plan, &cfg), KC_OK);
    cfg.qdd0[1] = (kc_real)NAN;
    assert_int_equal(kc_interp_joint_plan_cfg(&plan, &cfg), KC_E_ARG);
    assert_int_equal(kc_interp_joint_plan_cfg(NULL, &cfg), KC_E_ARG);
    assert_int_equal(kc_interp_joint_plan_cfg(&plan, NULL), KC_E_ARG);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    kc_scurve pr;
    kc_scurve_state st;
    const kc_real one = KC_R(1.0), dt = KC_R(0.001), inf = (kc_real)INFINITY, nan = (kc_real)NAN;
    memset(&pr, KT_SENTINEL, sizeof pr);
    assert_int_equal(kc_scurve_plan(&pr, nan, 0, 0, one, one, one, one, dt), KC_E_ARG);
    assert_int_equal(kc_scurve_plan(&pr, 0, inf, 0, one, one, one, one, dt), KC_E_ARG);
    assert_int_equal(kc_scurve_plan(&pr, 0, 0, nan, one, one, one, one, dt), KC_E_ARG);
    assert_int_equal(kc_scurve_plan(&pr, 0, 0, 0, one, 0, one, one, dt), KC_E_ARG);
    assert_int_equal(kc_scurve_plan(&pr, 0, 0, 0, one, one, inf, one, dt), KC_E_ARG);
    assert_int_equal(kc_scurve_plan(&pr, 0, 0, 0, one, one, one, inf, dt), KC_E_ARG);
    assert_int_equal(kc_scurve_plan(&pr, 0, 0, 0, one, one, one, -one, dt), KC_E_ARG);
    assert_int_equal(kc_scurve_plan(&pr, 0, 0, 0, one, one, one, one, 0), KC_E_ARG);
    assert_int_equal(kc_scurve_plan(&pr, -KC_REAL_MAX, 0, 0, KC_REAL_MAX, one, one, one, dt), KC_E_ARG);
    assert_int_equal(kc_scurve_plan_duration(&pr, 0, one, one, one, one, -one, dt), KC_E_ARG);
    assert_int_equal(kc_scurve_plan_duration(&pr, 0, one, one, one, one, nan, dt), KC_E_ARG);
    /* Too long for the tick capacity. */
    assert_int_equal(kc_scurve_plan(&pr, 0, 0, 0, KC_R(1e6), KC_R(1e-3), one, one, dt), KC_E_CAPACITY);
    assert_true(kt_is_sentinel(&pr, sizeof pr));
    assert_int_equal(kc_scurve_plan(NULL, 0, 0, 0, one, one, one, one, dt), KC_E_ARG);
    /* No speed limit: the peak is the distance's. */
    assert_int_equal(kc_scurve_plan(&pr, 0, 0, 0, one, inf, one, one, dt), KC_OK);
    kt_near((double)pr.T, kt_scurve_optimum_time(1.0, 1e6, 1.0, 1.0), 1e-6, "no speed limit");
    assert_int_equal(kc_scurve_plan(&pr, 0, one, 0, one, inf, one, one, dt), KC_OK);
    walk(&pr, 0, 1, 0, 1, 1e30, 1, 1, "no speed limit, moving");
    /* Evaluation. */
    assert_int_equal(kc_scurve_plan(&pr, 0, 0, 0, one, one, one, one, dt), KC_OK);
    memset(&st, KT_SENTINEL, sizeof st);
    assert_int_equal(kc_scurve_eval(&pr, -1, &st), KC_E_ARG);
    assert_int_equal(kc_scurve_eval_time(&pr, -KC_R(0.001), &st), KC_E_ARG);
    assert_int_equal(kc_scurve_eval_time(&pr, nan, &st), KC_E_ARG);
    assert_true(kt_is_sentinel(&st, sizeof st));
    assert_int_equal(kc_scurve_eval(NULL, 0, &st), KC_E_ARG);
    assert_int_equal(kc_scurve_eval(&pr, 0, NULL), KC_E_ARG);
    assert_int_equal(kc_scurve_eval(&pr, INT64_MAX, &st), KC_DONE);
    assert_true(st.p == one && st.v == KC_R(0.0) && st.a == KC_R(0.0));
    assert_int_equal(kc_scurve_eval_time(&pr, inf, &st), KC_DONE);
}

/* The fastest stop (kc_scurve_plan_stop) from random moving states: every
 * tick within the limits and its jerk, at rest on its end exactly, and as
 * fast as kc_scurve_plan's way to the same point of rest, which cannot be
 * faster (it too must bring v to zero) and, from a start within the
 * limits, finds it by its own search.
 * The extent (kc_scurve_extent_of) of random moving plans against 4,000
 * samples of each: nothing sampled outside it, and its extremes reached
 * to within what the sampling step allows. */
static void test_stop_and_extent(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5C0FE019);
    double worst_T = 0.0;
    for (int n = 0; n < N_RANDOM / 8; n++) {
        double p0 = kt_uniform(&r, -2.0, 2.0);
        double V = kt_uniform(&r, 0.1, 3.0), A = kt_uniform(&r, 0.5, 30.0), J = kt_uniform(&r, 2.0, 600.0);
        double dt = rand_dt(&r);
        double lim = n % 4 == 0 ? 1.5 : 1.0;
        double v0 = (double)(kc_real)kt_uniform(&r, -V, V), a0 = (double)(kc_real)kt_uniform(&r, -lim * A, lim * A);
        kc_scurve st;
        assert_int_equal(kc_scurve_plan_stop(&st, (kc_real)p0, (kc_real)v0, (kc_real)a0, (kc_real)A, (kc_real)J,
                                             (kc_real)dt),
                         KC_OK);
        walk(&st, (double)(kc_real)p0, v0, a0, (double)st.p1, fabs(v0), (double)(kc_real)A, (double)(kc_real)J,
             "stop");
        /* The comparison from p = 0, where float resolves the stop's
         * short distance (beside p0 it keeps about 1e-7 |p0| of it). */
        kc_scurve pl;
        assert_int_equal(kc_scurve_plan_stop(&st, 0, (kc_real)v0, (kc_real)a0, (kc_real)A, (kc_real)J, (kc_real)dt),
                         KC_OK);
        assert_int_equal(kc_scurve_plan(&pl, 0, (kc_real)v0, (kc_real)a0, st.p1, (kc_real)V, (kc_real)A, (kc_real)J,
                                        (kc_real)dt),
                         KC_OK);
        /* Starts beyond A: the planner's way is not always the fastest
         * (kinctl/scurve.h); it is never faster than the stop. */
        double tol_T = FLOAT_BUILD ? 1e-5 : 1e-12;
        double d = ((double)pl.T - (double)st.T) / fmax((double)st.T, 1e-9);
        if (fabs(a0) <= A)
            worst_T = fmax(worst_T, fabs(d));
        if (!(d >= -tol_T && (fabs(a0) > A || d <= tol_T)))
            fail_msg("case %d: stop %.9g s, plan to its end %.9g s (v0 %g a0 %g A %g J %g)", n, (double)st.T,
                     (double)pl.T, v0, a0, A, J);
        /* The extent of a moving plan to a random target. */
        double p1 = kt_uniform(&r, -2.0, 2.0);
        assert_int_equal(kc_scurve_plan(&pl, (kc_real)p0, (kc_real)v0, (kc_real)a0, (kc_real)p1, (kc_real)V,
                                        (kc_real)A, (kc_real)J, (kc_real)dt),
                         KC_OK);
        kc_scurve_extent e;
        assert_int_equal(kc_scurve_extent_of(&pl, &e), KC_OK);
        double lo = HUGE_VAL, hi = -HUGE_VAL, vm = 0.0, am = 0.0, T = (double)pl.T;
        double tol = 16.0 * EPS * (fabs(p0) + fabs(p1) + V * T + 1.0);
        for (int i = 0; i <= 4000; i++) {
            kc_scurve_state s;
            kc_scurve_eval_time(&pl, (kc_real)(T * i / 4000.0), &s);
            lo = fmin(lo, (double)s.p);
            hi = fmax(hi, (double)s.p);
            vm = fmax(vm, fabs((double)s.v));
            am = fmax(am, fabs((double)s.a));
        }
        double h = T / 4000.0, amax = fmax(A, fabs(a0)) * (1.0 + 1e-6);
        assert_true(lo >= (double)e.p_min - tol && hi <= (double)e.p_max + tol);
        assert_true(vm <= (double)e.v_max * (1.0 + 16.0 * EPS) + tol && am <= (double)e.a_max * (1.0 + 16.0 * EPS) + tol);
        /* Between samples an extreme of p is missed by at most a h^2 / 2
         * (v = 0 there), one of v by J h^2 / 2, one of a by J h. */
        assert_true(lo - (double)e.p_min <= 0.5 * amax * h * h + tol && (double)e.p_max - hi <= 0.5 * amax * h * h + tol);
        assert_true((double)e.v_max - vm <= 0.5 * J * h * h + tol && (double)e.a_max - am <= J * h + tol);
    }
    print_message("stop vs plan to its end: worst relative difference of duration %.3g\n", worst_T);
    kc_scurve sp;
    assert_int_equal(kc_scurve_plan_stop(&sp, 0, 1, 0, 0, 1, KC_R(0.001)), KC_E_ARG);
    assert_int_equal(kc_scurve_plan_stop(NULL, 0, 1, 0, 1, 1, KC_R(0.001)), KC_E_ARG);
    assert_int_equal(kc_scurve_extent_of(NULL, NULL), KC_E_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_textbook),     cmocka_unit_test(test_rest_to_rest),
        cmocka_unit_test(test_stretched),    cmocka_unit_test(test_moving_start),
        cmocka_unit_test(test_moving_stretched),    cmocka_unit_test(test_moving_stretched_small_jerk),
        cmocka_unit_test(test_moving_stretched_blocked_cases), cmocka_unit_test(test_moving_agrees_with_rest),
        cmocka_unit_test(test_extreme_scales),
        cmocka_unit_test(test_joint_move),          cmocka_unit_test(test_joint_move_moving),
        cmocka_unit_test(test_joint_move_bad), cmocka_unit_test(test_bad_inputs),
        cmocka_unit_test(test_stop_and_extent),
    };
    int failed = cmocka_run_group_tests_name("scurve (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("scurve");
    return failed;
}
