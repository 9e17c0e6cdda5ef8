/* test_path.c - multi-point paths of seed 001 lab 7 (kinctl/path.h):
 * every case of vectors/smoothing.json (tables 7.1 blends, quartic and
 * parabolic; 7.2 Lagrange; 7.3 cubic Hermite), properties of random joint
 * and Cartesian paths of every method, and bad inputs.
 *
 * Tolerances.
 *   double: the file's own, 1e-9 absolute (and 1e-10 relative for the large
 *   Lagrange values: max(1e-9, 1e-10 |x|)).
 *   float (u = 2^-24): the inputs (knot times, t_acc, dt) carry relative
 *   rounding u, so tick k is at time k dt (1 + 2u) and each piece's local
 *   time tau is off by at most ~4 u t_span; the coefficients take ~10
 *   roundings and Horner 2 per degree. A value x is thus off by about
 *   4 u t_span |x'| + 16 u |x|, doubled for cancellation and rounded up:
 *       tol_x = 64 u (max|x| + t_span max|x'|)
 *   with the maxima of the case itself (x' of qdd: the largest jerk between
 *   two samples of one piece). Lagrange amplifies data rounding by its
 *   basis: tol_x^(m) = 64 u max_t [sum_i |L_i^(m)(t)| (|y_i| + |p'(t_i)|
 *   |t_i|) + t_span |p^(m+1)(t)|], the first-order perturbation bound for
 *   rounded values and nodes.
 *   Properties compare quantities computed two ways inside one build:
 *   KT_PATH_REL = 1000 u relative to the quantity's scale (1.1e-13 double,
 *   6e-5 float): ~50 roundings in coefficients and Horner times up to 20
 *   for the spread of segment times (0.2 .. 1.5 s).
 */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define U ((double)KC_REAL_EPS / 2.0)
#define KT_PATH_REL (1000.0 * U)
#ifdef KC_REAL_FLOAT
#define IS_FLOAT 1
#else
#define IS_FLOAT 0
#endif

/* Plans are large (tens of kB): static, one at a time. */
static kc_path P;

static double dmax(double a, double b) { return a > b ? a : b; }

/* ---- smoothing.json ---- */

typedef struct series {
    size_t n;
    double t[2000], q[2000], qd[2000], qdd[2000];
    int ambiguous[2000];
} series;

static series S;

static void read_series(const json_t *obj, const json_t *times, const json_t *amb)
{
    S.n = json_array_size(times);
    assert_true(S.n > 1 && S.n <= 2000);
    for (size_t k = 0; k < S.n; k++) {
        S.t[k] = kt_num(kt_at(times, k));
        S.q[k] = kt_num(kt_at(kt_get(obj, "q"), k));
        S.qd[k] = kt_num(kt_at(kt_get(obj, "qdot"), k));
        S.qdd[k] = kt_num(kt_at(kt_get(obj, "qddot"), k));
        S.ambiguous[k] = 0;
    }
    for (size_t i = 0; amb != NULL && i < json_array_size(amb); i++) {
        double idx = kt_num(kt_at(amb, i));
        assert_true(idx >= 0 && (size_t)idx < S.n);
        S.ambiguous[(size_t)idx] = 1;
    }
}

/* max |x| and the largest |x'| seen between samples of one piece. */
static double max_abs(const double *x) { double m = 0; for (size_t k = 0; k < S.n; k++) m = dmax(m, fabs(x[k])); return m; }

static double max_rate(const double *x)
{
    double m = 0;
    for (size_t k = 0; k + 1 < S.n; k++)
        if (!S.ambiguous[k] && !S.ambiguous[k + 1])
            m = dmax(m, fabs(x[k + 1] - x[k]) / (S.t[k + 1] - S.t[k]));
    return m;
}

typedef struct tols {
    double q, qd, qdd;
} tols;

/* Float tolerances of a blend or spline case (header). */
static tols float_tols(void)
{
    double span = S.t[S.n - 1] - S.t[0];
    tols t;
    t.q = 64 * U * (max_abs(S.q) + span * max_abs(S.qd));
    t.qd = 64 * U * (max_abs(S.qd) + span * max_abs(S.qdd));
    t.qdd = 64 * U * (max_abs(S.qdd) + span * max_rate(S.qdd));
    return t;
}

/* Largest |error| / tolerance seen against the vectors (reported). */
static double worst_ratio;

static void near_track(double a, double e, double tol, const char *what)
{
    worst_ratio = dmax(worst_ratio, fabs(a - e) / tol);
    kt_near(a, e, tol, what);
}

/* Compares the plan's ticks with the series; dt = 0.01 s. */
static void check_series(const char *label, tols tol, int lagrange)
{
    char what[128];
    assert_int_equal((long)P.ticks, (long)(S.n - 1));
    kt_near(P.t_origin, S.t[0], IS_FLOAT ? 4 * U * 20 : 1e-15, "t_origin");
    for (size_t k = 0; k < S.n; k++) {
        kc_real q, qd, qdd;
        kc_status st = kc_path_eval(&P, (int64_t)k, &q, &qd, &qdd);
        assert_int_equal(st, k + 1 < S.n ? KC_OK : KC_DONE);
        double rq = lagrange && !IS_FLOAT ? 1e-10 : 0;
        snprintf(what, sizeof what, "%s q at t = %.2f", label, S.t[k]);
        near_track(q, S.q[k], dmax(tol.q, rq * fabs(S.q[k])), what);
        snprintf(what, sizeof what, "%s qdot at t = %.2f", label, S.t[k]);
        near_track(qd, S.qd[k], dmax(tol.qd, rq * fabs(S.qd[k])), what);
        if (S.ambiguous[k])
            continue;
        snprintf(what, sizeof what, "%s qddot at t = %.2f", label, S.t[k]);
        near_track(qdd, S.qdd[k], dmax(tol.qdd, rq * fabs(S.qdd[k])), what);
    }
}

static int n_blend_cases, n_lagrange_cases, n_spline_cases;

static void read_knots(const json_t *v, kc_real *t, kc_real *q)
{
    kt_read_reals(kt_get(v, "t_knots_s"), t, 5);
    kt_read_reals(kt_get(v, "q_knots"), q, 5);
}

static void test_blend_vectors(void **state)
{
    (void)state;
    json_t *root = kt_load("smoothing.json");
    const json_t *tables = kt_get(root, "blend_tables_7_1");
    assert_int_equal(json_array_size(tables), 6);
    for (size_t v = 0; v < json_array_size(tables); v++) {
        const json_t *var = kt_at(tables, v);
        kc_real t[5], q[5];
        read_knots(var, t, q);
        for (int shape = 0; shape < 2; shape++) {
            const char *name = shape == 0 ? "quartic" : "parabolic";
            char label[64];
            snprintf(label, sizeof label, "7.1 variant %zu %s", v + 1, name);
            kc_path_cfg cfg = kc_path_cfg_default();
            cfg.method = KC_PATH_BLEND;
            cfg.blend = shape == 0 ? KC_PATH_BLEND_QUARTIC : KC_PATH_BLEND_PARABOLIC;
            cfg.n_knots = 5;
            cfg.dim = 1;
            cfg.q = q;
            cfg.t = t;
            cfg.t_acc = (kc_real)kt_num_of(var, "t_acc_s");
            cfg.dt = KC_R(0.01);
            assert_int_equal(kc_path_plan(&P, &cfg), KC_OK);
            const json_t *obj = kt_get(var, name);
            read_series(obj, kt_get(var, "t_s"), kt_get(obj, "qddot_ambiguous_indices"));
            tols tol = {1e-9, 1e-9, 1e-9};
            if (IS_FLOAT)
                tol = float_tols();
            check_series(label, tol, 0);
            /* The blend table: position at every knot time. */
            const json_t *blends = kt_get(var, "blends");
            for (size_t j = 0; j < json_array_size(blends); j++) {
                const json_t *b = kt_at(blends, j);
                kc_real qk;
                char what[96];
                double tk = kt_num_of(b, "t_knot");
                kc_path_eval_time(&P, (kc_real)(tk - (double)P.t_origin), &qk, NULL, NULL);
                snprintf(what, sizeof what, "%s q at knot %zu", label, j);
                kt_near(qk, kt_num_of(b, shape == 0 ? "q_at_knot_time_quartic" : "q_at_knot_time_parabolic"),
                        tol.q, what);
            }
            n_blend_cases++;
        }
    }
    json_decref(root);
}

/* Lagrange basis of the 5 knots as ascending coefficients in t (double). */
static void lagrange_basis(const double *x, int n, double basis[8][8])
{
    for (int i = 0; i < n; i++) {
        double c[8] = {1};
        int deg = 0;
        double den = 1;
        for (int k = 0; k < n; k++) {
            if (k == i)
                continue;
            c[deg + 1] = c[deg];
            for (int m = deg; m > 0; m--)
                c[m] = c[m - 1] - x[k] * c[m];
            c[0] = -x[k] * c[0];
            deg++;
            den *= x[i] - x[k];
        }
        for (int m = 0; m < n; m++)
            basis[i][m] = c[m] / den;
    }
}

static double poly_deriv(const double *c, int n, int m, double t)
{
    double s = 0;
    for (int i = n - 1; i >= m; i--) {
        double f = 1;
        for (int r = 0; r < m; r++)
            f *= i - r;
        s = s * t + f * c[i];
    }
    return s;
}

static void test_lagrange_vectors(void **state)
{
    (void)state;
    json_t *root = kt_load("smoothing.json");
    const json_t *tables = kt_get(root, "lagrange_tables_7_2");
    assert_int_equal(json_array_size(tables), 6);
    for (size_t v = 0; v < json_array_size(tables); v++) {
        const json_t *var = kt_at(tables, v);
        kc_real t[5], q[5];
        char label[64];
        read_knots(var, t, q);
        snprintf(label, sizeof label, "7.2 variant %zu", v + 1);
        kc_path_cfg cfg = kc_path_cfg_default();
        cfg.method = KC_PATH_LAGRANGE;
        cfg.n_knots = 5;
        cfg.dim = 1;
        cfg.q = q;
        cfg.t = t;
        cfg.dt = KC_R(0.01);
        assert_int_equal(kc_path_plan(&P, &cfg), KC_OK);
        read_series(var, kt_get(var, "t_s"), NULL);
        tols tol = {1e-9, 1e-9, 1e-9};
        if (IS_FLOAT) {
            /* First-order perturbation bound (header). */
            double x[5], y[5], basis[8][8], coef[8];
            const json_t *cj = kt_get(var, "coefficients_ascending_powers_of_t");
            for (int i = 0; i < 5; i++) {
                x[i] = kt_num(kt_at(kt_get(var, "t_knots_s"), (size_t)i));
                y[i] = kt_num(kt_at(kt_get(var, "q_knots"), (size_t)i));
                coef[i] = kt_num(kt_at(cj, (size_t)i));
            }
            lagrange_basis(x, 5, basis);
            double span = x[4] - x[0], b[3] = {0, 0, 0};
            for (size_t k = 0; k < S.n; k++) {
                for (int m = 0; m < 3; m++) {
                    double s = span * fabs(poly_deriv(coef, 5, m + 1, S.t[k]));
                    for (int i = 0; i < 5; i++)
                        s += fabs(poly_deriv(basis[i], 5, m, S.t[k])) *
                             (fabs(y[i]) + fabs(poly_deriv(coef, 5, 1, x[i])) * fabs(x[i]));
                    b[m] = dmax(b[m], s);
                }
            }
            tol.q = 64 * U * b[0];
            tol.qd = 64 * U * b[1];
            tol.qdd = 64 * U * b[2];
        }
        check_series(label, tol, 1);
        if (!IS_FLOAT) {
            /* t_0 = 0: piece 0's Taylor coefficients are the polynomial's. */
            const json_t *cj = kt_get(var, "coefficients_ascending_powers_of_t");
            for (size_t i = 0; i < 5; i++) {
                double e = kt_num(kt_at(cj, i));
                char what[96];
                snprintf(what, sizeof what, "%s coefficient %zu", label, i);
                kt_near(P.c[0][i][0], e, dmax(1e-9, 1e-10 * fabs(e)), what);
            }
        }
        n_lagrange_cases++;
    }
    json_decref(root);
}

static void test_spline_vectors(void **state)
{
    (void)state;
    json_t *root = kt_load("smoothing.json");
    const json_t *tables = kt_get(root, "spline_tables_7_3");
    assert_int_equal(json_array_size(tables), 6);
    for (size_t v = 0; v < json_array_size(tables); v++) {
        const json_t *var = kt_at(tables, v);
        kc_real t[5], q[5], vel[5];
        char label[64], what[128];
        read_knots(var, t, q);
        kt_read_reals(kt_get(var, "v_knots"), vel, 5);
        snprintf(label, sizeof label, "7.3 variant %zu", v + 1);
        kc_path_cfg cfg = kc_path_cfg_default();
        cfg.method = KC_PATH_SPLINE;
        cfg.n_knots = 5;
        cfg.dim = 1;
        cfg.q = q;
        cfg.t = t;
        cfg.qd = vel;
        cfg.dt = KC_R(0.01);
        assert_int_equal(kc_path_plan(&P, &cfg), KC_OK);
        read_series(var, kt_get(var, "t_s"), kt_get(var, "qddot_ambiguous_indices"));
        tols tol = {1e-9, 1e-9, 1e-9};
        if (IS_FLOAT)
            tol = float_tols();
        check_series(label, tol, 0);
        /* Segment coefficients K0..K3 (float: 64 u times the sum of the
         * formula's terms, a running-error bound). */
        const json_t *segs = kt_get(var, "segments");
        assert_int_equal(P.n_pieces, 4);
        for (size_t s = 0; s < 4; s++) {
            const json_t *K = kt_get(kt_at(segs, s), "K0_K1_K2_K3");
            double T = (double)t[s + 1] - (double)t[s];
            double a0 = fabs((double)q[s]), a1 = fabs((double)q[s + 1]);
            double v0 = fabs((double)vel[s]), v1 = fabs((double)vel[s + 1]);
            double terms[4] = {a0, v0, (3 * a1 + 3 * a0 + 2 * v0 * T + v1 * T) / (T * T),
                               (v1 * T + v0 * T + 2 * a1 + 2 * a0) / (T * T * T)};
            for (size_t i = 0; i < 4; i++) {
                snprintf(what, sizeof what, "%s segment %zu K%zu", label, s, i);
                kt_near(P.c[s][i][0], kt_num(kt_at(K, i)), IS_FLOAT ? 64 * U * terms[i] : 1e-9, what);
            }
        }
        /* The acceleration jumps at the interior knots. */
        const json_t *jumps = kt_get(var, "qddot_at_interior_knots");
        for (size_t i = 0; i < json_array_size(jumps); i++) {
            const json_t *j = kt_at(jumps, i);
            int knot = (int)kt_num_of(j, "knot");
            kc_real ql, qdl, qddl, qr, qdr, qddr;
            assert_int_equal(kc_path_eval_piece(&P, knot - 1, P.len[knot - 1], &ql, &qdl, &qddl), KC_OK);
            assert_int_equal(kc_path_eval_piece(&P, knot, KC_R(0.0), &qr, &qdr, &qddr), KC_OK);
            snprintf(what, sizeof what, "%s qddot left of knot %d", label, knot);
            kt_near(qddl, kt_num_of(j, "qddot_left"), tol.qdd, what);
            snprintf(what, sizeof what, "%s qddot right of knot %d", label, knot);
            kt_near(qddr, kt_num_of(j, "qddot_right"), tol.qdd, what);
            snprintf(what, sizeof what, "%s q continuous at knot %d", label, knot);
            kt_near(ql, qr, tol.q, what);
            snprintf(what, sizeof what, "%s qdot continuous at knot %d", label, knot);
            kt_near(qdl, qdr, tol.qd, what);
        }
        n_spline_cases++;
    }
    json_decref(root);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blend_vectors),
        cmocka_unit_test(test_lagrange_vectors),
        cmocka_unit_test(test_spline_vectors),
    };
    int failed = cmocka_run_group_tests_name("path (" KC_REAL_NAME ")", tests, NULL, NULL);
    printf("smoothing.json: %d/12 blend (7.1 x quartic, parabolic), %d/6 Lagrange (7.2), %d/6 spline (7.3) cases;"
           " worst |error|/tolerance %.3g\n",
           n_blend_cases, n_lagrange_cases, n_spline_cases, worst_ratio);
    kt_report("path");
    return failed;
}
