/* SPDX-License-Identifier: BSD-3-Clause */
/* test_profile.c - one-dimensional motion laws (seed 001 lab 4 eqs.
 * 4.6-4.12; kinctl/profile.h): the leading joint of every case of
 * vectors/joint_trapezoid.json, then properties on random profiles (rest to
 * rest, from any velocity, stretched, stopping) and bad inputs.
 *
 * Tolerances. double: the file's 1e-9 absolute. float: the reference is
 * double. The float build rounds each input (positions, v, A, dt: half an
 * ulp each), forms t = k dt (one more rounding, and t carries dt's rounding
 * times k), then evaluates a value in fewer than ten operations on
 * quantities no larger than the largest value of that quantity in the case
 * (its scale, at least 1). Errors add: tens of ulps of the scale, so
 * 64 KC_REAL_EPS * scale (7.6e-6 * scale) bounds them with room for a factor
 * of about three. Acceleration and phase jump at phase boundaries: the file
 * lists the samples that fall on one (1e-9); in float a sample within
 * 8 ulps of a boundary is as ambiguous and is skipped the same way.
 *
 * Property checks allow rounding only: relative 16 KC_REAL_EPS on limits.
 */
#include "testutil.h"

#include <stdio.h>
#include <string.h>

#ifdef KC_REAL_FLOAT
#define FLOAT_BUILD 1
#else
#define FLOAT_BUILD 0
#endif

#define N_RANDOM 2000
/* Relative slack on a limit: rounding of the limit and of the value. */
#define LIMIT_SLACK (16.0 * (double)KC_REAL_EPS)

/* In float, a time within 8 ulps of a phase boundary is on it. */
static int near_boundary(double t, const double *bounds, int n)
{
    if (!FLOAT_BUILD)
        return 0;
    for (int i = 0; i < n; i++)
        if (fabs(t - bounds[i]) <= 8.0 * (double)KC_REAL_EPS * (bounds[i] > 1.0 ? bounds[i] : 1.0))
            return 1;
    return 0;
}

/* ---- vectors: the leading joint's profile ---- */

static void test_joint_trapezoid_lead(void **state)
{
    (void)state;
    json_t *root = kt_load("joint_trapezoid.json");
    const json_t *cases = kt_get(root, "cases");
    double file_tol = kt_num_of(kt_get(root, "tolerance"), "abs");
    char what[160];
    assert_true(file_tol == 1e-9);
    assert_int_equal(json_array_size(cases), 10);
    for (size_t c = 0; c < json_array_size(cases); c++) {
        const json_t *cs = kt_at(cases, c);
        const json_t *smp = kt_get(cs, "samples");
        const char *name = json_string_value(kt_get(cs, "case"));
        /* No leading joint when nothing moves: joint 1 stands for it. */
        const json_t *lj = kt_get(cs, "leading_joint");
        int lead = json_is_null(lj) ? 0 : (int)kt_num(lj) - 1;
        double v = kt_num_of(cs, "v_deg_s"), A = kt_num_of(cs, "A_deg_s2");
        double p0 = kt_num(kt_at(kt_get(cs, "q_start_deg"), (size_t)lead));
        double p1 = kt_num(kt_at(kt_get(cs, "q_end_deg"), (size_t)lead));
        kc_profile prof;
        assert_int_equal(kc_profile_plan(&prof, (kc_real)p0, KC_R(0.0), (kc_real)p1, (kc_real)v, (kc_real)A, KC_R(0.01)),
                         KC_OK);
        /* Timing: t_p (4.6), t_pv (4.9), T. */
        double tp = kt_num_of(cs, "t_p_s"), tpv = kt_num_of(cs, "t_pv_s"), T = kt_num_of(cs, "T_total_s");
        snprintf(what, sizeof what, "%s: t_p", name);
        kt_near((double)prof.t1, tp, kt_traj_tol(T), what);
        snprintf(what, sizeof what, "%s: t_p + t_pv", name);
        kt_near((double)prof.t2, tp + tpv, kt_traj_tol(T), what);
        snprintf(what, sizeof what, "%s: T", name);
        kt_near((double)prof.T, T, kt_traj_tol(T), what);
        snprintf(what, sizeof what, "%s: peak speed", name);
        kt_near(fabs((double)prof.vc), kt_num_of(cs, "v_peak_lead_deg_s"), kt_traj_tol(v), what);
        const json_t *ts = kt_get(smp, "t_s"), *ph = kt_get(smp, "phase");
        const json_t *q = kt_at(kt_get(smp, "q_deg"), (size_t)lead);
        const json_t *qd = kt_at(kt_get(smp, "qdot_deg_s"), (size_t)lead);
        const json_t *qdd = kt_at(kt_get(smp, "qddot_deg_s2"), (size_t)lead);
        const json_t *amb = kt_get(smp, "qddot_ambiguous_indices");
        double sq = kt_max_abs_json(q), sv = kt_max_abs_json(qd), sa = kt_max_abs_json(qdd);
        double bounds[3] = {tp, tp + tpv, T};
        size_t n = json_array_size(ts);
        for (size_t i = 0; i < n; i++) {
            kc_profile_state st;
            double t = kt_num(json_array_get(ts, i));
            /* Samples on the 10 ms grid are ticks of dt = 0.01; the last one
             * is T itself, off the grid: tick `ticks` and time T agree. */
            if (i + 1 < n) {
                assert_true(fabs(t - 0.01 * (double)i) < 1e-12);
                kc_status s = kc_profile_eval(&prof, (int64_t)i, &st);
                assert_int_equal(s, (int64_t)i < prof.ticks ? KC_OK : KC_DONE);
            } else {
                /* The file rounds T to 13 digits: the end is tick `ticks`. */
                snprintf(what, sizeof what, "%s: last sample at T", name);
                kt_near(t, T, 1e-11, what);
                assert_int_equal(kc_profile_eval(&prof, prof.ticks, &st), KC_DONE);
                assert_true((double)st.p == p1); /* exactly the target */
            }
            snprintf(what, sizeof what, "%s: q at t = %g", name, t);
            kt_near((double)st.p, kt_num(json_array_get(q, i)), kt_traj_tol(sq), what);
            snprintf(what, sizeof what, "%s: qdot at t = %g", name, t);
            kt_near((double)st.v, kt_num(json_array_get(qd, i)), kt_traj_tol(sv), what);
            if (kt_index_listed(amb, i) || near_boundary(t, bounds, 3))
                continue;
            snprintf(what, sizeof what, "%s: qddot at t = %g", name, t);
            kt_near((double)st.a, kt_num(json_array_get(qdd, i)), kt_traj_tol(sa), what);
            snprintf(what, sizeof what, "%s: phase at t = %g", name, t);
            kt_near((double)st.phase, kt_num(json_array_get(ph, i)), 0.0, what);
        }
    }
    json_decref(root);
}

/* ---- properties ---- */

/* Walks every tick of a profile and checks what must hold whatever the
 * plan: exact ends, acceleration within amax, velocity change per tick
 * within amax dt, position change consistent with the velocities, the
 * speed within vlim once it has come down to vlim, and t = k dt agreeing
 * with eval_time. */
static void walk(const kc_profile *pr, double p0, double v0, double p1, double vlim, double amax, const char *what)
{
    kc_profile_state prev, st, sti;
    double dt = (double)pr->dt;
    double scale = fabs(p0) + fabs(p1) + fabs(v0) * (double)pr->T + 1e-30;
    double vscale = fabs(v0) > vlim ? fabs(v0) : vlim;
    int was_within = fabs(v0) <= vlim;
    assert_int_equal(kc_profile_eval(pr, 0, &st), pr->ticks > 0 ? KC_OK : KC_DONE);
    if (pr->ticks > 0) {
        kt_near((double)st.p, p0, 0.0, what); /* exact start */
        kt_near((double)st.v, v0, 0.0, what);
    }
    prev = st;
    for (int64_t k = 1; k <= pr->ticks + 1; k++) {
        kc_status s = kc_profile_eval(pr, k, &st);
        assert_int_equal(s, k < pr->ticks ? KC_OK : KC_DONE);
        assert_int_equal(kc_profile_eval_time(pr, (kc_real)k * pr->dt, &sti), s);
        assert_true(sti.p == st.p && sti.v == st.v && sti.a == st.a && sti.phase == st.phase);
        assert_true(fabs((double)st.a) <= amax * (1.0 + LIMIT_SLACK));
        /* Rounding: of v itself, and of t = k dt (relative eps), which
         * moves the difference by amax eps t. */
        kt_near((double)st.v, (double)prev.v,
                amax * dt * (1.0 + LIMIT_SLACK) + 4.0 * (double)KC_REAL_EPS * (vscale + amax * (double)k * dt), what);
        /* p(k) - p(k-1) is the mean velocity times dt, exactly so inside
         * a phase; a phase change in between costs at most amax dt^2 / 4. */
        kt_near((double)(st.p - prev.p), 0.5 * (double)(st.v + prev.v) * dt,
                0.25 * amax * dt * dt + 16.0 * (double)KC_REAL_EPS * scale, what);
        if (was_within && !(fabs((double)st.v) <= vlim * (1.0 + LIMIT_SLACK))) {
            print_error("%s: |v| = %.9g above %.9g at tick %lld of %lld (t1 %.9g t2 %.9g T %.9g vc %.9g)\n", what,
                        (double)st.v, vlim, (long long)k, (long long)pr->ticks, (double)pr->t1, (double)pr->t2,
                        (double)pr->T, (double)pr->vc);
            fail();
        }
        if (fabs((double)st.v) <= vlim)
            was_within = 1;
        prev = st;
    }
    /* Exactly at rest on the target from the last tick on. */
    assert_true((double)st.p == p1 && st.v == KC_R(0.0) && st.a == KC_R(0.0) && st.phase == 4);
    /* ticks is the first tick at or after T. */
    assert_true((kc_real)pr->ticks * pr->dt >= pr->T);
    if (pr->ticks > 0)
        assert_true((kc_real)(pr->ticks - 1) * pr->dt < pr->T);
}

static double rand_dt(kt_rng *r)
{
    static const double dts[] = {0.001, 0.002, 0.004, 0.01, 0.0005, 1.0 / 3000.0};
    return dts[kt_rng_next(r) % 6];
}

static void test_rest_to_rest(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x9F0F11E1);
    for (int n = 0; n < N_RANDOM; n++) {
        double p0 = kt_uniform(&r, -3.0, 3.0), p1 = kt_uniform(&r, -3.0, 3.0);
        double v = kt_uniform(&r, 0.05, 4.0), a = kt_uniform(&r, 0.2, 40.0), dt = rand_dt(&r);
        if (n % 7 == 0)
            p1 = p0 + (kt_uniform(&r, 0.0, 1.0) < 0.5 ? -1.0 : 1.0) * v * v / a; /* the boundary */
        if (n % 11 == 0)
            p1 = p0; /* no motion */
        kc_profile pr;
        assert_int_equal(kc_profile_plan(&pr, (kc_real)p0, KC_R(0.0), (kc_real)p1, (kc_real)v, (kc_real)a, (kc_real)dt),
                         KC_OK);
        walk(&pr, (double)(kc_real)p0, 0.0, (double)(kc_real)p1, v, a, "rest to rest");
        /* Time optimal: T as lab 4 gives it (4.6-4.9), or the triangle. */
        double D = fabs((double)((kc_real)p1 - (kc_real)p0));
        double T = D >= v * v / a ? D / v + v / a : 2.0 * sqrt(D / a);
        kt_near((double)pr.T, T, 1e-6 * (T + 1.0) + (FLOAT_BUILD ? 1e-5 * (T + 1.0) : 0.0), "rest to rest T");
        /* Symmetric: the speed peaks at the middle. */
        if (D > 0.0) {
            kc_profile_state mid;
            kc_profile_eval_time(&pr, KC_R(0.5) * pr.T, &mid);
            kt_near((double)mid.p, 0.5 * (p0 + p1), 1e-9 + 16.0 * (double)KC_REAL_EPS * (fabs(p0) + fabs(p1)), "middle");
        }
    }
}

static void test_from_any_velocity(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5EED0F1E);
    int away = 0, over = 0, fast = 0;
    for (int n = 0; n < N_RANDOM; n++) {
        double p0 = kt_uniform(&r, -2.0, 2.0), p1 = kt_uniform(&r, -2.0, 2.0);
        double v = kt_uniform(&r, 0.1, 3.0), a = kt_uniform(&r, 0.5, 30.0), dt = rand_dt(&r);
        /* Up to three times the limit, either way. */
        double v0 = kt_uniform(&r, -3.0 * v, 3.0 * v);
        if (n % 13 == 0)
            p1 = p0 + v0 * fabs(v0) / (2.0 * a); /* braking at once lands on it */
        away += v0 * (p1 - p0) < 0.0;
        over += v0 * (p1 - p0) > 0.0 && v0 * v0 / (2.0 * a) > fabs(p1 - p0);
        fast += fabs(v0) > v;
        kc_profile pr;
        assert_int_equal(kc_profile_plan(&pr, (kc_real)p0, (kc_real)v0, (kc_real)p1, (kc_real)v, (kc_real)a, (kc_real)dt),
                         KC_OK);
        walk(&pr, (double)(kc_real)p0, (double)(kc_real)v0, (double)(kc_real)p1, v, a, "from any velocity");
        /* Never slower than braking and no faster than physics allows: T at
         * least the time to cancel v0's component away from the target. */
        assert_true((double)pr.T >= 0.0);
        if (v0 * (p1 - p0) < 0.0)
            assert_true((double)pr.T >= fabs(v0) / a * (1.0 - LIMIT_SLACK));
    }
    /* The random cases did cover each kind of start. */
    assert_true(away > N_RANDOM / 5 && over > N_RANDOM / 20 && fast > N_RANDOM / 5);
}

/* A start at rest reproduces kc_profile_plan's rest-to-rest, and a start
 * moving towards the target at cruise speed skips the acceleration. */
static void test_from_velocity_cases(void **state)
{
    (void)state;
    kc_profile a, b;
    kc_profile_state st;
    /* Cruising at vmax = 1 towards 10 from 0 with A = 2: brake over 0.25. */
    assert_int_equal(kc_profile_plan(&a, KC_R(0.0), KC_R(1.0), KC_R(10.0), KC_R(1.0), KC_R(2.0), KC_R(0.001)), KC_OK);
    kt_near((double)a.t1, 0.0, 0.0, "cruising: no phase 1");
    kt_near((double)a.T, 9.75 + 0.5, 1e-12 + 1e-5 * FLOAT_BUILD, "cruising: T = 9.75/1 + 1/2");
    /* Moving away at 1 from a target 1 behind: brake 0.5 s (0.25 away),
     * then 1.25 back: triangle peak sqrt(2 * 1.25) = 1.58 > vmax 1.2:
     * trapezoid. */
    assert_int_equal(kc_profile_plan(&b, KC_R(0.0), KC_R(1.0), KC_R(-1.0), KC_R(1.2), KC_R(2.0), KC_R(0.001)), KC_OK);
    kt_near((double)b.vc, (double)KC_R(-1.2), 0.0, "away: cruise at -vmax");
    kt_near((double)b.a1, -2.0, 0.0, "away: one phase brakes through zero");
    kt_near((double)b.t1, (1.0 + 1.2) / 2.0, 1e-12 + 1e-6 * FLOAT_BUILD, "away: t1");
    /* Too fast: 3 towards a target 10 away, vmax 1: slow down first. */
    assert_int_equal(kc_profile_plan(&b, KC_R(0.0), KC_R(3.0), KC_R(10.0), KC_R(1.0), KC_R(2.0), KC_R(0.001)), KC_OK);
    kt_near((double)b.a1, -2.0, 0.0, "too fast: decelerate to vmax");
    kt_near((double)b.vc, 1.0, 0.0, "too fast: cruise at vmax");
    kt_near((double)b.t1, 1.0, 1e-12, "too fast: t1 = (3 - 1)/2");
    /* Overshoot: 2 towards a target 0.5 away, A = 2: stops 1 past the start
     * (0.5 beyond the target) and comes back. */
    assert_int_equal(kc_profile_plan(&b, KC_R(0.0), KC_R(2.0), KC_R(0.5), KC_R(5.0), KC_R(2.0), KC_R(0.001)), KC_OK);
    assert_true(b.vc < KC_R(0.0) && b.a1 < KC_R(0.0));
    kc_real pmax = KC_R(0.0);
    for (int64_t k = 0; k <= b.ticks; k++) {
        kc_profile_eval(&b, k, &st);
        pmax = kc_max(pmax, st.p);
    }
    kt_near((double)pmax, 1.0, 1e-5, "overshoot: turns at 1");
    /* Exactly at the braking distance: braking is the whole profile. */
    assert_int_equal(kc_profile_plan(&b, KC_R(1.0), KC_R(-2.0), KC_R(0.0), KC_R(5.0), KC_R(2.0), KC_R(0.01)), KC_OK);
    kt_near((double)b.T, 1.0, 0.0, "brake to target: T = |v0|/A");
    kt_near((double)b.t2, 0.0, 0.0, "brake to target: phases 1 and 2 empty");
    assert_int_equal(kc_profile_eval(&b, 0, &st), KC_OK);
    assert_int_equal(st.phase, 3);
    kt_near((double)st.v, -2.0, 1e-12, "brake to target: starts at v0");
}

static void test_stretched(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x57E7C4ED);
    for (int n = 0; n < N_RANDOM; n++) {
        double p0 = kt_uniform(&r, -2.0, 2.0), p1 = kt_uniform(&r, -2.0, 2.0);
        double v = kt_uniform(&r, 0.1, 3.0), a = kt_uniform(&r, 0.5, 30.0), dt = rand_dt(&r);
        kc_profile fast, pr, untouched;
        assert_int_equal(kc_profile_plan(&fast, (kc_real)p0, KC_R(0.0), (kc_real)p1, (kc_real)v, (kc_real)a, (kc_real)dt),
                         KC_OK);
        double T = (double)fast.T * kt_uniform(&r, 1.0, 4.0);
        int optimum = n % 5 == 0;
        if (optimum)
            T = (double)fast.T;
        assert_int_equal(
            kc_profile_plan_duration(&pr, (kc_real)p0, (kc_real)p1, (kc_real)v, (kc_real)a, (kc_real)T, (kc_real)dt), KC_OK);
        kt_near((double)pr.T, (double)(kc_real)T, 0.0, "stretched: T as asked");
        assert_true(fabs((double)pr.a1) == (double)(kc_real)a || pr.a1 == KC_R(0.0)); /* acceleration kept */
        /* v = 2D / (T + sqrt(T^2 - 4D/A)) */
        double D = fabs((double)((kc_real)p1 - (kc_real)p0));
        double vc = 2.0 * D / (T + sqrt(fmax(T * T - 4.0 * D / a, 0.0)));
        /* At exactly the optimum the plan is the time-optimal one (the
         * formula's square root of a difference near zero would only add
         * rounding of sqrt(eps) there). */
        if (optimum)
            assert_true(pr.vc == fast.vc && pr.t1 == fast.t1 && pr.t2 == fast.t2);
        else
            kt_near(fabs((double)pr.vc), vc, 1e-9 + 1e-4 * FLOAT_BUILD * (vc + 1e-3), "stretched: cruise speed");
        walk(&pr, (double)(kc_real)p0, 0.0, (double)(kc_real)p1, v, a, "stretched");
        /* Shorter than possible: KC_E_LIMIT, prof untouched. */
        if (fast.T > KC_R(0.0)) {
            memset(&untouched, KT_SENTINEL, sizeof untouched);
            assert_int_equal(kc_profile_plan_duration(&untouched, (kc_real)p0, (kc_real)p1, (kc_real)v, (kc_real)a,
                                                      fast.T * KC_R(0.99), (kc_real)dt),
                             KC_E_LIMIT);
            assert_true(kt_is_sentinel(&untouched, sizeof untouched));
        }
    }
}

static void test_stop(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x5709);
    for (int n = 0; n < N_RANDOM; n++) {
        double p0 = kt_uniform(&r, -2.0, 2.0), v0 = kt_uniform(&r, -5.0, 5.0), a = kt_uniform(&r, 0.5, 30.0);
        double dt = rand_dt(&r);
        if (n % 9 == 0)
            v0 = 0.0;
        kc_profile pr;
        assert_int_equal(kc_profile_plan_stop(&pr, (kc_real)p0, (kc_real)v0, (kc_real)a, (kc_real)dt), KC_OK);
        double p1 = (double)((kc_real)p0 + (kc_real)v0 * kc_fabs((kc_real)v0) / (KC_R(2.0) * (kc_real)a));
        kt_near((double)pr.p1, p1, 0.0, "stop: where");
        kt_near((double)pr.T, fabs(v0) / a, 1e-12 + 1e-6 * FLOAT_BUILD, "stop: T = |v0|/A");
        walk(&pr, (double)(kc_real)p0, (double)(kc_real)v0, p1, fabs(v0), a, "stop");
        /* Monotone: the speed only falls. */
        kc_profile_state st, prev;
        kc_profile_eval(&pr, 0, &prev);
        for (int64_t k = 1; k <= pr.ticks; k++) {
            kc_profile_eval(&pr, k, &st);
            assert_true(fabs((double)st.v) <= fabs((double)prev.v));
            prev = st;
        }
    }
}

/* Phases are half-open: at exactly t1 the cruise has begun. */
static void test_half_open_phases(void **state)
{
    (void)state;
    kc_profile pr;
    kc_profile_state st;
    /* D = 3, v = 1, A = 1: t1 = 1, t2 = 3, T = 4 (all exact). */
    assert_int_equal(kc_profile_plan(&pr, KC_R(0.0), KC_R(0.0), KC_R(3.0), KC_R(1.0), KC_R(1.0), KC_R(0.5)), KC_OK);
    assert_true(pr.t1 == KC_R(1.0) && pr.t2 == KC_R(3.0) && pr.T == KC_R(4.0) && pr.ticks == 8);
    static const int phases[9] = {1, 1, 2, 2, 2, 2, 3, 3, 4};
    static const double acc[9] = {1, 1, 0, 0, 0, 0, -1, -1, 0};
    for (int64_t k = 0; k <= 8; k++) {
        assert_int_equal(kc_profile_eval(&pr, k, &st), k < 8 ? KC_OK : KC_DONE);
        assert_int_equal(st.phase, phases[k]);
        kt_near((double)st.a, acc[k], 0.0, "acceleration on half-open phases");
    }
    /* Triangle: phase 2 is empty and never reported. */
    assert_int_equal(kc_profile_plan(&pr, KC_R(0.0), KC_R(0.0), KC_R(1.0), KC_R(5.0), KC_R(1.0), KC_R(0.5)), KC_OK);
    assert_true(pr.t1 == pr.t2 && pr.T == KC_R(2.0));
    for (int64_t k = 0; k <= pr.ticks; k++) {
        kc_profile_eval(&pr, k, &st);
        assert_true(st.phase != 2);
    }
    /* A duration that is no multiple of dt ends at the next tick. */
    assert_int_equal(kc_profile_plan(&pr, KC_R(0.0), KC_R(0.0), KC_R(1.0), KC_R(5.0), KC_R(1.0), KC_R(0.3)), KC_OK);
    assert_true(pr.ticks == 7); /* T = 2, 6 * 0.3 = 1.8 < 2 <= 2.1 */
    /* Zero motion: done at tick 0. */
    assert_int_equal(kc_profile_plan(&pr, KC_R(2.0), KC_R(0.0), KC_R(2.0), KC_R(5.0), KC_R(1.0), KC_R(0.3)), KC_OK);
    assert_true(pr.ticks == 0 && pr.T == KC_R(0.0));
    assert_int_equal(kc_profile_eval(&pr, 0, &st), KC_DONE);
    assert_true(st.p == KC_R(2.0) && st.phase == 4);
    /* No speed limit: always a triangle. */
    assert_int_equal(kc_profile_plan(&pr, KC_R(0.0), KC_R(0.0), KC_R(8.0), (kc_real)INFINITY, KC_R(2.0), KC_R(0.01)),
                     KC_OK);
    assert_true(pr.T == KC_R(4.0) && pr.vc == KC_R(4.0));
}

/* ---- bad inputs ---- */

static void expect_untouched(kc_status got, kc_status want, const kc_profile *pr, const char *what)
{
    if (got != want || !kt_is_sentinel(pr, sizeof *pr)) {
        print_error("%s: status %d (%s), want %d; untouched %d\n", what, (int)got, kc_status_str(got), (int)want,
                    kt_is_sentinel(pr, sizeof *pr));
        fail();
    }
}

static void test_bad_inputs(void **state)
{
    (void)state;
    const kc_real nan = (kc_real)NAN, inf = (kc_real)INFINITY;
    kc_profile pr;
    kc_profile_state st;
    const kc_real one = KC_R(1.0), dt = KC_R(0.001);
    struct {
        kc_real p0, v0, p1, v, a, dt;
        kc_status want;
        const char *what;
    } plan_cases[] = {
        {nan, 0, 1, 1, 1, dt, KC_E_ARG, "NaN p0"},
        {0, nan, 1, 1, 1, dt, KC_E_ARG, "NaN v0"},
        {0, 0, nan, 1, 1, dt, KC_E_ARG, "NaN p1"},
        {0, 0, inf, 1, 1, dt, KC_E_ARG, "infinite p1"},
        {0, inf, 1, 1, 1, dt, KC_E_ARG, "infinite v0"},
        {0, 0, 1, nan, 1, dt, KC_E_ARG, "NaN vmax"},
        {0, 0, 1, 0, 1, dt, KC_E_ARG, "zero vmax"},
        {0, 0, 1, -1, 1, dt, KC_E_ARG, "negative vmax"},
        {0, 0, 1, 1, 0, dt, KC_E_ARG, "zero amax"},
        {0, 0, 1, 1, -2, dt, KC_E_ARG, "negative amax"},
        {0, 0, 1, 1, inf, dt, KC_E_ARG, "infinite amax"},
        {0, 0, 1, 1, nan, dt, KC_E_ARG, "NaN amax"},
        {0, 0, 1, 1, 1, 0, KC_E_ARG, "zero dt"},
        {0, 0, 1, 1, 1, -dt, KC_E_ARG, "negative dt"},
        {0, 0, 1, 1, 1, nan, KC_E_ARG, "NaN dt"},
        {0, 0, 1, 1, 1, inf, KC_E_ARG, "infinite dt"},
        {-KC_REAL_MAX, 0, KC_REAL_MAX, 1, 1, dt, KC_E_ARG, "distance overflows"},
        {0, 0, KC_R(1e6), 1, 1, dt, KC_E_CAPACITY, "too many ticks (1e6 s at 1 kHz)"},
        {0, KC_R(1e30), 0, 1, KC_R(1e-30), dt, KC_E_CAPACITY, "braking distance overflows"},
    };
    for (size_t i = 0; i < sizeof plan_cases / sizeof plan_cases[0]; i++) {
        memset(&pr, KT_SENTINEL, sizeof pr);
        kc_status s = kc_profile_plan(&pr, plan_cases[i].p0, plan_cases[i].v0, plan_cases[i].p1, plan_cases[i].v,
                                      plan_cases[i].a, plan_cases[i].dt);
        expect_untouched(s, plan_cases[i].want, &pr, plan_cases[i].what);
    }
    assert_int_equal(kc_profile_plan(NULL, 0, 0, one, one, one, dt), KC_E_ARG);
    memset(&pr, KT_SENTINEL, sizeof pr);
    expect_untouched(kc_profile_plan_duration(&pr, 0, one, one, one, nan, dt), KC_E_ARG, &pr, "NaN duration");
    expect_untouched(kc_profile_plan_duration(&pr, 0, one, one, one, -one, dt), KC_E_ARG, &pr, "negative duration");
    expect_untouched(kc_profile_plan_duration(&pr, 0, one, one, one, inf, dt), KC_E_ARG, &pr, "infinite duration");
    expect_untouched(kc_profile_plan_duration(&pr, 0, one, one, one, KC_R(1.0), dt), KC_E_LIMIT, &pr,
                     "duration below the minimum 2 s");
    expect_untouched(kc_profile_plan_duration(&pr, 0, one, one, one, KC_R(1e6), dt), KC_E_CAPACITY, &pr,
                     "duration of 1e9 ticks");
    expect_untouched(kc_profile_plan_duration(&pr, 0, one, 0, one, KC_R(3.0), dt), KC_E_ARG, &pr, "zero vmax");
    expect_untouched(kc_profile_plan_stop(&pr, 0, one, 0, dt), KC_E_ARG, &pr, "stop: zero amax");
    expect_untouched(kc_profile_plan_stop(&pr, nan, one, one, dt), KC_E_ARG, &pr, "stop: NaN p0");
    expect_untouched(kc_profile_plan_stop(&pr, 0, nan, one, dt), KC_E_ARG, &pr, "stop: NaN v0");
    expect_untouched(kc_profile_plan_stop(&pr, 0, one, one, -dt), KC_E_ARG, &pr, "stop: negative dt");
    assert_int_equal(kc_profile_plan_stop(NULL, 0, one, one, dt), KC_E_ARG);
    /* Evaluation. */
    assert_int_equal(kc_profile_plan(&pr, 0, 0, one, one, one, dt), KC_OK);
    memset(&st, KT_SENTINEL, sizeof st);
    assert_int_equal(kc_profile_eval(&pr, -1, &st), KC_E_ARG);
    assert_int_equal(kc_profile_eval_time(&pr, -KC_R(0.001), &st), KC_E_ARG);
    assert_int_equal(kc_profile_eval_time(&pr, nan, &st), KC_E_ARG);
    assert_true(kt_is_sentinel(&st, sizeof st));
    assert_int_equal(kc_profile_eval(NULL, 0, &st), KC_E_ARG);
    assert_int_equal(kc_profile_eval(&pr, 0, NULL), KC_E_ARG);
    assert_int_equal(kc_profile_eval_time(NULL, 0, &st), KC_E_ARG);
    /* Far beyond the end is simply done. */
    assert_int_equal(kc_profile_eval(&pr, INT64_MAX, &st), KC_DONE);
    assert_true(st.p == one && st.v == KC_R(0.0));
    assert_int_equal(kc_profile_eval_time(&pr, inf, &st), KC_DONE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_joint_trapezoid_lead), cmocka_unit_test(test_rest_to_rest),
        cmocka_unit_test(test_from_any_velocity),    cmocka_unit_test(test_from_velocity_cases),
        cmocka_unit_test(test_stretched),            cmocka_unit_test(test_stop),
        cmocka_unit_test(test_half_open_phases),     cmocka_unit_test(test_bad_inputs),
    };
    int failed = cmocka_run_group_tests_name("profile (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("profile");
    return failed;
}
