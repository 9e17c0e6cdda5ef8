/* SPDX-License-Identifier: BSD-3-Clause */
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
 *   KT_PATH_REL = 1000 u (1.1e-13 double, 6e-5 float: ~50 roundings in
 *   coefficients and Horner, with a factor 20 for cancellation) relative to
 *   the scale of what the coefficients of derivative m are made from,
 *   R_m = B_m + B_{m-1} / T_min + B_{m-2} / T_min^2, B_m the rigorous bound
 *   sum_i |c_i| i!/(i-m)! len^(i-m) of derivative m over the pieces and
 *   T_min the shortest piece.
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
static kc_path_cart PC;

static double dmax(double a, double b) { return a > b ? a : b; }

/* kt_near in double, whatever the precision of its arguments. */
#define NEAR(a, e, tol, what) kt_near((double)(a), (double)(e), (tol), (what))

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
    NEAR(a, e, tol, what);
}

/* Compares the plan's ticks with the series; dt = 0.01 s. */
static void check_series(const char *label, tols tol, int lagrange)
{
    char what[128];
    assert_int_equal((long)P.ticks, (long)(S.n - 1));
    NEAR(P.t_origin, S.t[0], IS_FLOAT ? 4 * U * 20 : 1e-15, "t_origin");
    for (size_t k = 0; k < S.n; k++) {
        kc_real q, qd, qdd;
        kc_status st = kc_path_eval(&P, (int64_t)k, &q, &qd, &qdd);
        assert_int_equal(st, k + 1 < S.n ? KC_OK : KC_DONE);
        double rq = lagrange && !IS_FLOAT ? 1e-10 : 0;
        snprintf(what, sizeof what, "%s q at t = %.2f", label, S.t[k]);
        near_track((double)q, S.q[k], dmax(tol.q, rq * fabs(S.q[k])), what);
        snprintf(what, sizeof what, "%s qdot at t = %.2f", label, S.t[k]);
        near_track((double)qd, S.qd[k], dmax(tol.qd, rq * fabs(S.qd[k])), what);
        if (S.ambiguous[k])
            continue;
        snprintf(what, sizeof what, "%s qddot at t = %.2f", label, S.t[k]);
        near_track((double)qdd, S.qdd[k], dmax(tol.qdd, rq * fabs(S.qdd[k])), what);
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
                NEAR(qk, kt_num_of(b, shape == 0 ? "q_at_knot_time_quartic" : "q_at_knot_time_parabolic"),
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
                NEAR(P.c[0][i][0], e, dmax(1e-9, 1e-10 * fabs(e)), what);
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
                NEAR(P.c[s][i][0], kt_num(kt_at(K, i)), IS_FLOAT ? 64 * U * terms[i] : 1e-9, what);
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
            NEAR(qddl, kt_num_of(j, "qddot_left"), tol.qdd, what);
            snprintf(what, sizeof what, "%s qddot right of knot %d", label, knot);
            NEAR(qddr, kt_num_of(j, "qddot_right"), tol.qdd, what);
            snprintf(what, sizeof what, "%s q continuous at knot %d", label, knot);
            NEAR(ql, qr, tol.q, what);
            snprintf(what, sizeof what, "%s qdot continuous at knot %d", label, knot);
            NEAR(qdl, qdr, tol.qd, what);
        }
        n_spline_cases++;
    }
    json_decref(root);
}

/* ---- properties of random joint paths ---- */

/* Rigorous bound of |d^m/dtau^m| of coordinate j over piece p: sum |c_i|
 * i!/(i-m)! len^(i-m) (the size of Horner's terms, so also the scale of
 * its rounding). */
static double piece_bound(const kc_path *path, int p, int j, int m)
{
    double L = (double)path->len[p], s = 0;
    for (int i = m; i < path->n_coeffs; i++) {
        double f = 1;
        for (int r = 0; r < m; r++)
            f *= i - r;
        s += fabs((double)path->c[p][i][j]) * f * pow(L, i - m);
    }
    return s;
}

static double path_bound(const kc_path *path, int j, int m)
{
    double b = 0;
    for (int p = 0; p < path->n_pieces; p++)
        b = dmax(b, piece_bound(path, p, j, m));
    return b;
}

typedef struct jcase {
    kc_path_cfg cfg;
    kc_real q[KC_PATH_MAX_KNOTS * KC_MAX_JOINTS];
    kc_real t[KC_PATH_MAX_KNOTS];
    kc_real qd[KC_PATH_MAX_KNOTS * KC_MAX_JOINTS];
    kc_real qdd[KC_PATH_MAX_KNOTS * KC_MAX_JOINTS];
} jcase;

static jcase JC;

/* Variants of the methods exercised. */
enum { V_QUARTIC, V_PARABOLIC, V_LAGRANGE, V_HERMITE, V_CLAMPED, V_NATURAL, V_QUINTIC_GIVEN, V_QUINTIC, V_COUNT };
static const char *const variant_name[V_COUNT] = {"quartic blend", "parabolic blend", "lagrange", "hermite spline",
                                                  "clamped spline", "natural spline", "quintic (given)", "quintic"};

static int variant_c2(int v) { return v != V_PARABOLIC && v != V_HERMITE; }
static int variant_interpolates(int v) { return v != V_QUARTIC && v != V_PARABOLIC; }
static int variant_rest(int v) { return v != V_LAGRANGE && v != V_NATURAL; }

/* A random case of a variant; times given (and t_acc) or from limits. */
static void make_case(kt_rng *rng, int v, int given_t)
{
    kc_path_cfg *c = &JC.cfg;
    *c = kc_path_cfg_default();
    int maxn = v == V_LAGRANGE ? KC_PATH_MAX_LAGRANGE_KNOTS : 12;
    int n = 2 + (int)(kt_rng_next(rng) % (uint64_t)(maxn - 1));
    int dim = kt_rng_next(rng) % 4 == 0 ? KC_MAX_JOINTS : 1 + (int)(kt_rng_next(rng) % 6);
    c->n_knots = n;
    c->dim = dim;
    c->dt = kt_rng_next(rng) % 2 ? KC_R(0.001) : KC_R(0.004);
    c->method = v <= V_PARABOLIC ? KC_PATH_BLEND : v == V_LAGRANGE ? KC_PATH_LAGRANGE
                : v <= V_NATURAL ? KC_PATH_SPLINE : KC_PATH_QUINTIC;
    c->blend = v == V_PARABOLIC ? KC_PATH_BLEND_PARABOLIC : KC_PATH_BLEND_QUARTIC;
    c->spline_end = v == V_NATURAL ? KC_PATH_SPLINE_NATURAL : KC_PATH_SPLINE_CLAMPED;
    double tmin = 1e9;
    for (int i = 0; i < n; i++) {
        JC.t[i] = (kc_real)(i == 0 ? kt_uniform(rng, -1, 1) : (double)JC.t[i - 1] + kt_uniform(rng, 0.2, 1.5));
        if (i > 0)
            tmin = fmin(tmin, (double)JC.t[i] - (double)JC.t[i - 1]);
        for (int j = 0; j < dim; j++) {
            JC.q[i * dim + j] = (kc_real)kt_uniform(rng, -2, 2);
            JC.qd[i * dim + j] = (kc_real)(i == 0 || i == n - 1 ? 0.0 : kt_uniform(rng, -2, 2));
            JC.qdd[i * dim + j] = (kc_real)(i == 0 || i == n - 1 ? 0.0 : kt_uniform(rng, -5, 5));
        }
    }
    c->q = JC.q;
    c->qd = v == V_HERMITE || v == V_QUINTIC_GIVEN ? JC.qd : NULL;
    c->qdd = v == V_QUINTIC_GIVEN ? JC.qdd : NULL;
    if (given_t) {
        c->t = JC.t;
        /* Half of the longest allowed, or all of it now and then. */
        c->t_acc = (kc_real)(tmin / 2 * (kt_rng_next(rng) % 4 == 0 ? 1.0 : kt_uniform(rng, 0.05, 0.99)));
    } else {
        c->t = NULL;
        for (int j = 0; j < dim; j++) {
            c->vmax[j] = (kc_real)kt_uniform(rng, 0.5, 3);
            c->amax[j] = (kc_real)kt_uniform(rng, 1, 10);
        }
    }
}

static unsigned long n_joint_cases, n_joint_ticks, n_stretched;
static double tightest_stretch = 0; /* smallest max(|qd|/v, sqrt(|qdd|/a)) after a stretch */

static void check_joint_case(int v, int given_t, int index)
{
    const kc_path_cfg *c = &JC.cfg;
    char what[160];
    int n = c->n_knots, dim = c->dim;
    snprintf(what, sizeof what, "%s case %d (n %d, dim %d, %s)", variant_name[v], index, n, dim,
             given_t ? "times" : "limits");
    kc_status st = kc_path_plan(&P, c);
    if (st != KC_OK)
        fail_msg("%s: plan returned %s", what, kc_status_str(st));
    n_joint_cases++;
    double B[4][KC_MAX_JOINTS], R[3][KC_MAX_JOINTS];
    double tmin = 1e300;
    for (int p = 0; p < P.n_pieces; p++)
        if (P.len[p] > KC_R(0.0))
            tmin = fmin(tmin, (double)P.len[p]);
    for (int j = 0; j < dim; j++) {
        for (int m = 0; m < 4; m++)
            B[m][j] = path_bound(&P, j, m);
        /* Scale of the rounding of derivative m: the coefficients come from
         * positions and velocities divided by piece times. */
        R[0][j] = B[0][j];
        R[1][j] = B[1][j] + B[0][j] / tmin;
        R[2][j] = B[2][j] + B[1][j] / tmin + B[0][j] / (tmin * tmin);
    }
    kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS], qdd[KC_MAX_JOINTS];
    kc_real q1[KC_MAX_JOINTS], qd1[KC_MAX_JOINTS], qdd1[KC_MAX_JOINTS];

    /* Start exactly on the first knot, at rest where the method starts so. */
    assert_int_equal(kc_path_eval(&P, 0, q, qd, qdd), KC_OK);
    for (int j = 0; j < dim; j++) {
        if (q[j] != c->q[j])
            fail_msg("%s: q(0)[%d] = %.17g, knot %.17g", what, j, (double)q[j], (double)c->q[j]);
        if (variant_rest(v) && qd[j] != KC_R(0.0))
            fail_msg("%s: qd(0)[%d] = %g, not at rest", what, j, (double)qd[j]);
        kt_checks += 2;
    }
    /* End exactly on the last knot from tick `ticks` on. */
    assert_true(P.ticks >= 1);
    assert_true((double)(P.ticks - 1) * (double)P.dt < (double)P.duration);
    assert_true((double)P.ticks * (double)P.dt >= (double)P.duration * (1 - 1e-6));
    for (int64_t k = P.ticks; k <= P.ticks + 3; k++) {
        assert_int_equal(kc_path_eval(&P, k, q, qd, qdd), KC_DONE);
        for (int j = 0; j < dim; j++) {
            if (q[j] != c->q[(n - 1) * dim + j])
                fail_msg("%s: end q[%d] = %.17g, knot %.17g", what, j, (double)q[j], (double)c->q[(n - 1) * dim + j]);
            if (variant_rest(v) && qd[j] != KC_R(0.0))
                fail_msg("%s: end qd[%d] = %g, not at rest", what, j, (double)qd[j]);
            kt_checks += 2;
        }
    }
    /* Through every knot at its time (interpolating methods); given knot
     * velocities and accelerations are met there. */
    if (variant_interpolates(v)) {
        for (int i = 0; i + 1 < n; i++) {
            assert_int_equal(kc_path_eval_time(&P, P.start[i], q, qd, qdd), KC_OK);
            for (int j = 0; j < dim; j++) {
                if (q[j] != c->q[i * dim + j])
                    fail_msg("%s: knot %d q[%d] = %.17g, knot %.17g", what, i, j, (double)q[j], (double)c->q[i * dim + j]);
                if (c->qd != NULL && qd[j] != c->qd[i * dim + j])
                    fail_msg("%s: knot %d qd[%d] = %.17g, given %.17g", what, i, j, (double)qd[j], (double)c->qd[i * dim + j]);
                kt_checks += 2;
                if (c->qdd != NULL)
                    NEAR(qdd[j], c->qdd[i * dim + j], KT_PATH_REL * R[2][j], "given knot acceleration");
            }
            /* On the knot-time axis too. */
            if (c->t != NULL) {
                kc_path_eval_time(&P, (kc_real)((double)c->t[i] - (double)P.t_origin), q, NULL, NULL);
                for (int j = 0; j < dim; j++)
                    NEAR(q[j], c->q[i * dim + j], KT_PATH_REL * (B[0][j] + B[1][j] * (double)P.duration), what);
            }
        }
    }
    /* Continuity where pieces meet, analytically. */
    for (int p = 0; p + 1 < P.n_pieces; p++) {
        assert_int_equal(kc_path_eval_piece(&P, p, P.len[p], q, qd, qdd), KC_OK);
        assert_int_equal(kc_path_eval_piece(&P, p + 1, KC_R(0.0), q1, qd1, qdd1), KC_OK);
        for (int j = 0; j < dim; j++) {
            snprintf(what, sizeof what, "%s case %d: piece %d/%d joint %d", variant_name[v], index, p, p + 1, j);
            NEAR(q[j], q1[j], KT_PATH_REL * R[0][j], what);
            NEAR(qd[j], qd1[j], KT_PATH_REL * R[1][j], what);
            if (variant_c2(v))
                NEAR(qdd[j], qdd1[j], KT_PATH_REL * R[2][j], what);
        }
    }
    /* Tick to tick: every change within the bound of its derivative. */
    double vpeak = 0, apeak = 0;
    kc_path_eval(&P, 0, q, qd, qdd);
    for (int64_t k = 0; k < P.ticks; k++) {
        kc_path_eval(&P, k + 1, q1, qd1, qdd1);
        n_joint_ticks++;
        for (int j = 0; j < dim; j++) {
            double dt = (double)P.dt;
            if (fabs((double)(q1[j] - q[j])) > B[1][j] * dt * (1 + 1e-9) + KT_PATH_REL * R[0][j] ||
                fabs((double)(qd1[j] - qd[j])) > B[2][j] * dt * (1 + 1e-9) + KT_PATH_REL * R[1][j] ||
                (variant_c2(v) && fabs((double)(qdd1[j] - qdd[j])) > B[3][j] * dt * (1 + 1e-9) + KT_PATH_REL * R[2][j]))
                fail_msg("%s case %d: jump at tick %ld joint %d: q %g -> %g, qd %g -> %g, qdd %g -> %g", variant_name[v],
                         index, (long)k, j, (double)q[j], (double)q1[j], (double)qd[j], (double)qd1[j], (double)qdd[j],
                         (double)qdd1[j]);
            kt_checks += 3;
            if (!given_t) {
                /* Limits: blends by construction, the others by the stretch. */
                double rv = fabs((double)qd1[j]) / (double)c->vmax[j], ra = fabs((double)qdd1[j]) / (double)c->amax[j];
                if (v != V_HERMITE && v != V_QUINTIC_GIVEN && (rv > 1 + KT_PATH_REL || ra > 1 + KT_PATH_REL))
                    fail_msg("%s case %d: tick %ld joint %d: qd %g (limit %g), qdd %g (limit %g)", variant_name[v], index,
                             (long)k + 1, j, (double)qd1[j], (double)c->vmax[j], (double)qdd1[j], (double)c->amax[j]);
                vpeak = dmax(vpeak, rv);
                apeak = dmax(apeak, sqrt(ra));
                kt_checks += 2;
            }
        }
        memcpy(q, q1, sizeof q);
        memcpy(qd, qd1, sizeof qd);
        memcpy(qdd, qdd1, sizeof qdd);
    }
    if (P.stretch > KC_R(1.0)) {
        n_stretched++;
        double r = dmax(vpeak, apeak);
        if (tightest_stretch == 0 || r < tightest_stretch)
            tightest_stretch = r;
    }
}

static void test_joint_properties(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x70617468); /* "path" */
    for (int v = 0; v < V_COUNT; v++)
        for (int i = 0; i < 30; i++) {
            int given_t = i % 2 == 0 || v == V_HERMITE || v == V_QUINTIC_GIVEN ? (i % 3 != 1) : 0;
            make_case(&rng, v, given_t);
            check_joint_case(v, given_t, i);
        }
    printf("joint paths: %lu random cases, %lu ticks; %lu stretched to the limits, the tightest reaching %.3f of them\n",
           n_joint_cases, n_joint_ticks, n_stretched, tightest_stretch);
}

/* The largest |qddd| of path P's pieces, sampled (SAMPLES points a piece,
 * both ends included) from their coefficients: independent of the
 * Bernstein bound the planner stretches by. */
static double sampled_jerk(void)
{
    enum { SAMPLES = 200 };
    double worst = 0.0;
    for (int p = 0; p < P.n_pieces; p++)
        for (int s = 0; s <= SAMPLES; s++) {
            double tau = (double)P.len[p] * s / SAMPLES;
            for (int j = 0; j < P.dim; j++) {
                double jerk = 0.0, pw = 1.0;
                for (int i = 3; i < P.n_coeffs; i++) {
                    jerk += (double)(i * (i - 1) * (i - 2)) * (double)P.c[p][i][j] * pw;
                    pw *= tau;
                }
                worst = fmax(worst, fabs(jerk) / (double)JC.cfg.jmax[j]);
            }
        }
    return worst;
}

/* Computed times with a jerk limit (kinctl/path.h): Lagrange paths, cubic
 * splines and quintics whose derivatives are all computed are stretched
 * so that their pieces keep |qddd| <= jmax, the bound tight to within
 * the Bernstein bound's slack; without jmax (+infinity) nothing changes,
 * and with one the knot times are the plain plan's scaled by the ratio
 * of the stretches. */
static void test_jerk_stretch(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x6a65726b); /* "jerk" */
    const int variants[4] = {V_LAGRANGE, V_CLAMPED, V_NATURAL, V_QUINTIC};
    double tightest = 1e9;
    int bound = 0;
    for (int k = 0; k < 200; k++) {
        int v = variants[k % 4];
        make_case(&rng, v, 0);
        assert_int_equal(kc_path_plan(&P, &JC.cfg), KC_OK);
        double plain = (double)P.stretch, d_plain = (double)P.duration;
        for (int j = 0; j < JC.cfg.dim; j++)
            JC.cfg.jmax[j] = (kc_real)kt_uniform(&rng, 0.5, 20.0);
        double loose = sampled_jerk();
        assert_int_equal(kc_path_plan(&P, &JC.cfg), KC_OK);
        double worst = sampled_jerk();
        if (!(worst <= 1.0 + KT_PATH_REL)) /* the coefficients rounded after the stretch */
            fail_msg("%s case %d: jerk %.9g of the limit (stretch %g, %g without jmax)", variant_name[v], k, worst,
                     (double)P.stretch, plain);
        assert_true((double)P.stretch >= plain);
        kt_near((double)P.duration, d_plain * (double)P.stretch / plain, 16.0 * (double)KC_REAL_EPS * d_plain,
                "the plain plan's times, scaled");
        if ((double)P.stretch > plain * (1.0 + 1e-6)) {
            /* The jerk set the stretch: it was over the limit before. */
            assert_true(loose > 1.0);
            tightest = fmin(tightest, worst);
            bound++;
        }
    }
    printf("jerk-limited joint paths: 200 random cases, %d stretched for jerk, every piece within jmax, the "
           "loosest reaching %.3f of it\n",
           bound, tightest);
    assert_true(bound >= 20); /* the jerk does set the stretch, in a fair share */
    assert_true(tightest >= 0.5);
}

/* ---- properties of random Cartesian paths ---- */

typedef struct ccase {
    kc_path_cart_cfg cfg;
    kc_vec3 p[KC_PATH_MAX_KNOTS], v[KC_PATH_MAX_KNOTS], a[KC_PATH_MAX_KNOTS];
    kc_quat r[KC_PATH_MAX_KNOTS];
    kc_real t[KC_PATH_MAX_KNOTS];
} ccase;

static ccase CC;

static kc_quat quat_scale(kc_quat q, double s)
{
    kc_quat r = {(kc_real)((double)q.w * s), (kc_real)((double)q.x * s), (kc_real)((double)q.y * s),
                 (kc_real)((double)q.z * s)};
    return r;
}

static double quat_dot(const kc_quat *a, const kc_quat *b)
{
    return (double)a->w * (double)b->w + (double)a->x * (double)b->x + (double)a->y * (double)b->y +
           (double)a->z * (double)b->z;
}

/* A rotation by angle about a random axis, applied after q. */
static kc_quat turn(kt_rng *rng, kc_quat q, double angle)
{
    kc_vec3 k = kt_rand_unit(rng), w;
    kc_quat e, r;
    kc_vec3_scale(&k, (kc_real)angle, &w);
    kc_quat_exp(&w, &e);
    kc_quat_mul(&q, &e, &r);
    return r;
}

static void make_cart_case(kt_rng *rng, int v, int given_t)
{
    kc_path_cart_cfg *c = &CC.cfg;
    *c = kc_path_cart_cfg_default();
    int maxn = v == V_LAGRANGE ? KC_PATH_MAX_LAGRANGE_KNOTS : 10;
    int n = 2 + (int)(kt_rng_next(rng) % (uint64_t)(maxn - 1));
    c->n_knots = n;
    c->dt = KC_R(0.001);
    c->method = v <= V_PARABOLIC ? KC_PATH_BLEND : v == V_LAGRANGE ? KC_PATH_LAGRANGE
                : v <= V_NATURAL ? KC_PATH_SPLINE : KC_PATH_QUINTIC;
    c->blend = v == V_PARABOLIC ? KC_PATH_BLEND_PARABOLIC : KC_PATH_BLEND_QUARTIC;
    c->spline_end = v == V_NATURAL ? KC_PATH_SPLINE_NATURAL : KC_PATH_SPLINE_CLAMPED;
    double tmin = 1e9;
    kc_quat unit = {1, 0, 0, 0};
    for (int i = 0; i < n; i++) {
        CC.t[i] = (kc_real)(i == 0 ? kt_uniform(rng, 0, 2) : (double)CC.t[i - 1] + kt_uniform(rng, 0.2, 1.5));
        if (i > 0)
            tmin = fmin(tmin, (double)CC.t[i] - (double)CC.t[i - 1]);
        CC.p[i] = kc_vec3_make((kc_real)kt_uniform(rng, -1, 1), (kc_real)kt_uniform(rng, -1, 1),
                               (kc_real)kt_uniform(rng, -1, 1));
        int rest = i == 0 || i == n - 1;
        CC.v[i] = kc_vec3_make((kc_real)(rest ? 0 : kt_uniform(rng, -1, 1)), (kc_real)(rest ? 0 : kt_uniform(rng, -1, 1)),
                               (kc_real)(rest ? 0 : kt_uniform(rng, -1, 1)));
        CC.a[i] = kc_vec3_make((kc_real)(rest ? 0 : kt_uniform(rng, -3, 3)), (kc_real)(rest ? 0 : kt_uniform(rng, -3, 3)),
                               (kc_real)(rest ? 0 : kt_uniform(rng, -3, 3)));
        /* Orientations: random, or the previous one's other sign (no turn),
         * the same, a tiny turn (series), a turn just short of pi. */
        int kind = i == 0 ? 0 : (int)(kt_rng_next(rng) % 8);
        switch (kind) {
        case 1: unit = quat_scale(unit, -1); break;
        case 2: break;
        case 3: unit = turn(rng, unit, 1e-4); break;
        case 4: unit = turn(rng, unit, KT_PI - 1e-3); break;
        case 5: unit = turn(rng, unit, kt_uniform(rng, 0.05, 0.5)); break;
        default: unit = kt_rand_quat(rng); break;
        }
        /* Off unit norm by less than the accepted tolerance, now and then. */
        CC.r[i] = kt_rng_next(rng) % 5 == 0 ? quat_scale(unit, 1 + kt_uniform(rng, -5e-4, 5e-4)) : unit;
    }
    c->p = CC.p;
    c->r = CC.r;
    c->v = v == V_HERMITE || v == V_QUINTIC_GIVEN ? CC.v : NULL;
    c->a = v == V_QUINTIC_GIVEN ? CC.a : NULL;
    if (given_t) {
        c->t = CC.t;
        c->t_acc = (kc_real)(tmin / 2 * kt_uniform(rng, 0.05, 1.0));
    } else {
        c->t = NULL;
        c->v_max = (kc_real)kt_uniform(rng, 0.3, 2);
        c->a_max = (kc_real)kt_uniform(rng, 1, 5);
        if (kt_rng_next(rng) % 2) {
            c->w_max = (kc_real)kt_uniform(rng, 0.5, 3);
            c->alpha_max = (kc_real)kt_uniform(rng, 1, 10);
        }
    }
}

/* Angular velocity from orientations alone: central differences of the
 * world-frame rotation between t - h and t + h, Richardson-extrapolated
 * over h and h/2 (the error is even in h: O(h^4) remains). */
static kc_vec3 fd_omega(double t, double h)
{
    double w[2][3];
    for (int s = 0; s < 2; s++) {
        double hh = s == 0 ? h : h / 2;
        kc_path_pose a, b;
        kc_quat ca, rel;
        kc_vec3 d, dw;
        kc_path_cart_eval_time(&PC, (kc_real)(t - hh), &a);
        kc_path_cart_eval_time(&PC, (kc_real)(t + hh), &b);
        kc_quat_conj(&a.r, &ca);
        kc_quat_mul(&ca, &b.r, &rel);
        kc_quat_log(&rel, &d);
        kc_quat_rotate(&a.r, &d, &dw);
        for (int x = 0; x < 3; x++)
            w[s][x] = (double)dw.v[x] / (2 * hh);
    }
    return kc_vec3_make((kc_real)((4 * w[1][0] - w[0][0]) / 3), (kc_real)((4 * w[1][1] - w[0][1]) / 3),
                        (kc_real)((4 * w[1][2] - w[0][2]) / 3));
}

static double speed_at_time(double t)
{
    kc_path_pose e;
    kc_path_cart_eval_time(&PC, (kc_real)t, &e);
    return (double)e.sd;
}

/* Simpson's rule on the speed over [a, b], split where pieces meet (the
 * speed's slope may jump there). */
static double simpson_speed(double a, double b)
{
    double s = 0, x0 = a;
    for (int p = 1; p <= PC.pos.n_pieces; p++) {
        double x1 = p < PC.pos.n_pieces ? (double)PC.pos.start[p] : b;
        if (x1 <= x0)
            continue;
        x1 = fmin(x1, b);
        s += (x1 - x0) / 6 * (speed_at_time(x0) + 4 * speed_at_time((x0 + x1) / 2) + speed_at_time(x1));
        x0 = x1;
        if (x0 >= b)
            break;
    }
    return s;
}

static unsigned long n_cart_cases, n_cart_ticks;
static double worst_omega_fd, worst_alpha_jump, worst_length_rel;

static void check_cart_case(int v, int given_t, int index)
{
    const kc_path_cart_cfg *c = &CC.cfg;
    char what[160];
    int n = c->n_knots;
    snprintf(what, sizeof what, "cartesian %s case %d (n %d, %s)", variant_name[v], index, n, given_t ? "times" : "limits");
    kc_status st = kc_path_cart_plan(&PC, c);
    if (st != KC_OK)
        fail_msg("%s: plan returned %s", what, kc_status_str(st));
    n_cart_cases++;
    const kc_path *pos = &PC.pos;
    double B[4][3], R[3][3], tmin = 1e300;
    for (int p = 0; p < pos->n_pieces; p++)
        if (pos->len[p] > KC_R(0.0))
            tmin = fmin(tmin, (double)pos->len[p]);
    for (int j = 0; j < 3; j++) {
        for (int m = 0; m < 4; m++)
            B[m][j] = path_bound(pos, j, m);
        R[0][j] = B[0][j];
        R[1][j] = B[1][j] + B[0][j] / tmin;
        R[2][j] = B[2][j] + B[1][j] / tmin + B[0][j] / (tmin * tmin);
    }
    /* Scale of the angular velocity's rounding: the rotation vectors' rates
     * and angles (<= pi + the blend's reach) over the shortest piece. */
    double wscale = 0, jscale = 0;
    for (int p = 0; p < pos->n_pieces; p++)
        for (int x = 0; x < 3; x++) {
            double b0 = 0, b1 = 0, L = (double)pos->len[p];
            for (int i = 0; i < 6; i++) {
                b0 += fabs((double)PC.rc[p][i][x]) * pow(L, i);
                if (i > 0)
                    b1 += fabs((double)PC.rc[p][i][x]) * i * pow(L, i - 1);
            }
            wscale = dmax(wscale, (1 + b0) * (1 + b0) * (b1 + b0 / tmin));
            /* d^3 omega / dt^3 is made of v'''', v''' v', v''^2, v'' v'^2
             * and v'^4 through J_r and its derivatives (coefficients of
             * order 1; the multiplicities of Faa di Bruno's formula). */
            double b2 = 0, b3 = 0, b4 = 0;
            for (int i = 2; i < 6; i++)
                b2 += fabs((double)PC.rc[p][i][x]) * i * (i - 1) * pow(L, i - 2);
            for (int i = 3; i < 6; i++)
                b3 += fabs((double)PC.rc[p][i][x]) * i * (i - 1) * (i - 2) * pow(L, i - 3);
            for (int i = 4; i < 6; i++)
                b4 += fabs((double)PC.rc[p][i][x]) * i * (i - 1) * (i - 2) * (i - 3) * pow(L, i - 4);
            jscale = dmax(jscale, (1 + b0) * (1 + b0) *
                                      (b4 + 4 * b3 * b1 + 3 * b2 * b2 + 6 * b2 * b1 * b1 + b1 * b1 * b1 * b1));
        }
    kc_quat r0u, rnu;
    kc_quat_normalize(&c->r[0], &r0u);
    kc_quat_normalize(&c->r[n - 1], &rnu);
    kc_path_pose s0, s1;

    /* Start: first knot exactly, its orientation (sign as given), s = 0. */
    assert_int_equal(kc_path_cart_eval(&PC, 0, &s0), KC_OK);
    for (int x = 0; x < 3; x++)
        if (s0.p.v[x] != c->p[0].v[x])
            fail_msg("%s: p(0) differs from the first knot", what);
    kt_near_quat(&s0.r, &r0u, 4 * U, "start orientation");
    assert_true(s0.s == KC_R(0.0));
    if (variant_rest(v))
        NEAR(s0.sd, 0, 0, "start speed");
    /* End: last knot exactly, at rest in rotation, s = length. */
    for (int64_t k = pos->ticks; k <= pos->ticks + 2; k++) {
        assert_int_equal(kc_path_cart_eval(&PC, k, &s1), KC_DONE);
        for (int x = 0; x < 3; x++)
            if (s1.p.v[x] != c->p[n - 1].v[x])
                fail_msg("%s: end p differs from the last knot", what);
        NEAR(fabs(quat_dot(&s1.r, &rnu)), 1, 16 * U, "end orientation");
        NEAR(kc_vec3_norm(&s1.w), 0, 0, "end angular velocity");
        NEAR(s1.s, PC.length, 0, "end s");
    }
    /* Knots at their times (interpolating methods). */
    if (variant_interpolates(v))
        for (int i = 0; i + 1 < n; i++) {
            kc_quat ri;
            kc_path_cart_eval_time(&PC, pos->start[i], &s0);
            for (int x = 0; x < 3; x++)
                if (s0.p.v[x] != c->p[i].v[x])
                    fail_msg("%s: knot %d position missed", what, i);
            kc_quat_normalize(&c->r[i], &ri);
            NEAR(fabs(quat_dot(&s0.r, &ri)), 1, 64 * U, "knot orientation");
        }
    /* Analytic continuity where pieces meet. */
    for (int p = 0; p + 1 < pos->n_pieces; p++) {
        if (pos->len[p] <= KC_R(0.0))
            continue;
        kc_path_cart_eval_piece(&PC, p, pos->len[p], &s0);
        kc_path_cart_eval_piece(&PC, p + 1, KC_R(0.0), &s1);
        snprintf(what, sizeof what, "cartesian %s case %d: pieces %d/%d", variant_name[v], index, p, p + 1);
        for (int x = 0; x < 3; x++) {
            NEAR(s0.p.v[x], s1.p.v[x], KT_PATH_REL * R[0][x], what);
            NEAR(s0.v.v[x], s1.v.v[x], KT_PATH_REL * R[1][x], what);
            if (variant_c2(v))
                NEAR(s0.a.v[x], s1.a.v[x], KT_PATH_REL * R[2][x], what);
            NEAR(s0.w.v[x], s1.w.v[x], KT_PATH_REL * wscale, what);
        }
        kt_near_quat(&s0.r, &s1.r, KT_PATH_REL, what);
        /* Angular acceleration (double only: float rounding over h). */
        if (!IS_FLOAT && v != V_PARABOLIC) {
            const double h = 1e-4;
            kc_path_pose l1, l2, r1, r2;
            kc_path_cart_eval_piece(&PC, p, (kc_real)((double)pos->len[p] - h), &l1);
            kc_path_cart_eval_piece(&PC, p, (kc_real)((double)pos->len[p] - 2 * h), &l2);
            kc_path_cart_eval_piece(&PC, p + 1, (kc_real)h, &r1);
            kc_path_cart_eval_piece(&PC, p + 1, (kc_real)(2 * h), &r2);
            for (int x = 0; x < 3; x++) {
                double al = (3 * (double)s0.w.v[x] - 4 * (double)l1.w.v[x] + (double)l2.w.v[x]) / (2 * h);
                double ar = (-3 * (double)s1.w.v[x] + 4 * (double)r1.w.v[x] - (double)r2.w.v[x]) / (2 * h);
                /* Truncation of the one-sided differences h^2/3 |omega'''|
                 * on each side, rounding 8 u |omega| / h. */
                double tol = 2 * h * h / 3 * jscale + 8 * U * (1 + wscale) / h;
                worst_alpha_jump = dmax(worst_alpha_jump, fabs(al - ar) / tol);
                NEAR(al, ar, tol, "angular acceleration across a boundary");
            }
        }
    }
    /* Reference length: composite Simpson with 2000 intervals per piece. */
    double ref_len = 0, s_ref = 0;
    for (int p = 0; p < pos->n_pieces; p++) {
        const int m = 2000;
        double L = (double)pos->len[p], acc = 0;
        for (int i = 0; i <= m; i++) {
            kc_path_pose e;
            kc_path_cart_eval_piece(&PC, p, (kc_real)(L * i / m), &e);
            acc += (i == 0 || i == m ? 1 : i % 2 ? 4 : 2) * (double)e.sd;
        }
        ref_len += acc * L / (3 * m);
    }
    /* Every tick: unit quaternion, sign continuity, position steps within
     * their bound, s. */
    snprintf(what, sizeof what, "cartesian %s case %d", variant_name[v], index);
    kc_path_cart_eval(&PC, 0, &s0);
    for (int64_t k = 0; k < pos->ticks; k++) {
        kc_path_cart_eval(&PC, k + 1, &s1);
        n_cart_ticks++;
        double dt = (double)pos->dt;
        NEAR(kc_quat_norm(&s1.r), 1, 64 * U, "unit orientation");
        if (!(quat_dot(&s0.r, &s1.r) > 0))
            fail_msg("%s: orientation sign flips at tick %ld", what, (long)k);
        for (int x = 0; x < 3; x++)
            if (fabs((double)(s1.p.v[x] - s0.p.v[x])) > B[1][x] * dt * (1 + 1e-9) + KT_PATH_REL * R[0][x])
                fail_msg("%s: position jump at tick %ld", what, (long)k);
        /* s: non-decreasing, and against Simpson's rule on the speed
         * accumulated over the ticks: 1e-7 of the length, plus the
         * rounding of s itself (compensated table, 8-term quadrature: 16 u s). */
        s_ref += simpson_speed((double)k * dt, fmin((double)(k + 1) * dt, (double)pos->duration));
        if ((double)s1.s < (double)s0.s - 8 * U * (double)s1.s)
            fail_msg("%s: s decreases at tick %ld: %.17g -> %.17g", what, (long)k, (double)s0.s, (double)s1.s);
        double err = fabs((double)s1.s - s_ref);
        worst_length_rel = dmax(worst_length_rel, err / dmax(ref_len, 1e-12));
        if (err > 1e-7 * ref_len + 16 * U * s_ref + 1e-15)
            fail_msg("%s: s = %.12g at tick %ld, reference %.12g (length %.12g, Simpson %.12g, duration %g, pieces %d)", what, (double)s1.s, (long)k + 1, s_ref, (double)PC.length, ref_len, (double)pos->duration, pos->n_pieces);
        kt_checks += 6;
        s0 = s1;
    }
    /* Angular velocity against the orientations (double only). */
    if (!IS_FLOAT) {
        kt_rng rng = kt_rng_make((uint64_t)index * 7919u + (uint64_t)v);
        /* Inside one piece (omega is smooth there), h <= len/64: the
         * Richardson error ~ (h/len)^4 |omega| / 80 stays below 1e-6 (1 +
         * |omega|) for the pieces here, rounding 8 u / h far below. */
        for (int i = 0; i < 64; i++) {
            int p = (int)(kt_rng_next(&rng) % (uint64_t)pos->n_pieces);
            double L = (double)pos->len[p], h = fmin(1e-3, L / 64);
            if (!(L > 0))
                continue;
            double t = (double)pos->start[p] + kt_uniform(&rng, 2 * h, L - 2 * h);
            kc_path_pose e;
            kc_path_cart_eval_time(&PC, (kc_real)t, &e);
            kc_vec3 fd = fd_omega(t, h);
            double tol = 1e-6 * (1 + (double)kc_vec3_norm(&e.w));
            for (int x = 0; x < 3; x++) {
                worst_omega_fd = dmax(worst_omega_fd, fabs((double)fd.v[x] - (double)e.w.v[x]) / tol);
                NEAR(fd.v[x], e.w.v[x], tol, "angular velocity vs orientations");
            }
        }
    }
}

static void test_cartesian_properties(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x63617274); /* "cart" */
    for (int v = 0; v < V_COUNT; v++)
        for (int i = 0; i < 16; i++) {
            int given_t = v == V_HERMITE || v == V_QUINTIC_GIVEN ? 1 : i % 2 == 0;
            make_cart_case(&rng, v, given_t);
            check_cart_case(v, given_t, i);
        }
    printf("cartesian paths: %lu random cases, %lu ticks; |s - Simpson| / length at most %.2g\n", n_cart_cases,
           n_cart_ticks, worst_length_rel);
    if (!IS_FLOAT)
        printf("cartesian paths: |omega - FD of orientations| at most %.2g of its tolerance, angular acceleration"
               " jump (FD) at most %.2g of its allowance\n",
               worst_omega_fd, worst_alpha_jump);
}

/* ---- ticks, limits rule, special orientations ---- */

static kc_real q3[3] = {0, 1, 3}, t3[3] = {0, KC_R(1.0005), 2};

static void test_ticks(void **state)
{
    (void)state;
    kc_real q[1], qd[1], qdd[1];
    kc_path_cfg c = kc_path_cfg_default();
    c.method = KC_PATH_QUINTIC;
    c.n_knots = 2;
    c.dim = 1;
    c.q = q3;
    c.t = t3;
    c.dt = KC_R(0.001);
    /* 1.0005 s: the first tick at or after the end is 1001. */
    assert_int_equal(kc_path_plan(&P, &c), KC_OK);
    assert_int_equal((long)P.ticks, 1001);
    assert_int_equal(kc_path_eval(&P, 1000, q, qd, qdd), KC_OK);
    assert_true(q[0] <= KC_R(1.0)); /* 1 - 1.25e-9: rounds to 1 in float */
    assert_int_equal(kc_path_eval(&P, 1001, q, qd, qdd), KC_DONE);
    assert_true(q[0] == KC_R(1.0) && qd[0] == KC_R(0.0) && qdd[0] == KC_R(0.0));
    /* On the grid: 2 s at 0.1 s is 20 ticks, not 21 (2 / 0.1 rounds up). */
    kc_real t2[2] = {0, 2};
    c.t = t2;
    c.dt = KC_R(0.1);
    assert_int_equal(kc_path_plan(&P, &c), KC_OK);
    assert_int_equal((long)P.ticks, 20);
    /* Shorter than a tick: the end at tick 1. */
    kc_real t4[2] = {0, KC_R(0.0005)};
    c.t = t4;
    c.dt = KC_R(0.001);
    assert_int_equal(kc_path_plan(&P, &c), KC_OK);
    assert_int_equal((long)P.ticks, 1);
    assert_int_equal(kc_path_eval(&P, 1, q, qd, qdd), KC_DONE);
    assert_true(q[0] == KC_R(1.0));
    /* Blend: tick 0 is t_0 - t_acc; knot times kept. */
    c = kc_path_cfg_default();
    c.n_knots = 3;
    c.dim = 1;
    c.q = q3;
    c.t = t3;
    c.t_acc = KC_R(0.25);
    assert_int_equal(kc_path_plan(&P, &c), KC_OK);
    NEAR(P.t_origin, -0.25, 0, "t_origin");
    NEAR(P.duration, (double)t3[2] + 0.5, 4 * U * 3, "blend duration");
    assert_int_equal(P.n_pieces, 5);
    /* t_acc exactly half the shortest segment: the line between vanishes. */
    c.t_acc = KC_R(0.5);
    kc_real t5[3] = {0, 1, 2};
    c.t = t5;
    assert_int_equal(kc_path_plan(&P, &c), KC_OK);
    NEAR(P.len[1], 0, 0, "zero-length line");
    kc_path_eval(&P, 0, q, qd, qdd);
    for (int64_t k = 1; k <= P.ticks; k++) {
        kc_real qn[1], qdn[1], qddn[1];
        kc_path_eval(&P, k, qn, qdn, qddn);
        assert_true(fabs((double)(qdn[0] - qd[0])) <= 0.75 * 2 / 0.5 * 0.001 * 1.01 + 1e-5);
        q[0] = qn[0];
        qd[0] = qdn[0];
    }
}

static void test_computed_times(void **state)
{
    (void)state;
    /* Two joints: distances 1 and 0.2 with vmax 1, amax 2: trapezoid
     * 1/1 + 1/2 = 1.5 s for joint 1 (triangular 2 sqrt(0.1) for joint 2). */
    kc_real q[4] = {0, 0, 1, KC_R(0.2)}, v[4] = {0, 0, 0, 0};
    kc_path_cfg c = kc_path_cfg_default();
    c.method = KC_PATH_SPLINE;
    c.n_knots = 2;
    c.dim = 2;
    c.q = q;
    c.qd = v; /* given velocities: the rule alone, no stretch */
    c.vmax[0] = c.vmax[1] = 1;
    c.amax[0] = c.amax[1] = 2;
    assert_int_equal(kc_path_plan(&P, &c), KC_OK);
    NEAR(P.t_knot[1] - P.t_knot[0], 1.5, 4 * U, "trapezoid rule");
    NEAR(P.stretch, 1, 0, "no stretch with given velocities");
    /* Computed velocities: the cubic peaks at 1.5 D / T = 1 and 6 D / T^2
     * = 2.67 > 2: stretched by sqrt(2.67 / 2) (within the bound's slack). */
    c.qd = NULL;
    assert_int_equal(kc_path_plan(&P, &c), KC_OK);
    assert_true(P.stretch > KC_R(1.15) && P.stretch < KC_R(1.2));
    /* Blends: t_acc = 1.5 vmax / amax = 0.75, T = max(1.5, 2 t_acc). */
    c.method = KC_PATH_BLEND;
    c.qd = NULL;
    assert_int_equal(kc_path_plan(&P, &c), KC_OK);
    NEAR(P.t_acc, 0.75, 4 * U, "t_acc rule");
    NEAR(P.t_knot[1] - P.t_knot[0], 1.5, 4 * U, "blend segment");
    c.blend = KC_PATH_BLEND_PARABOLIC;
    assert_int_equal(kc_path_plan(&P, &c), KC_OK);
    NEAR(P.t_acc, 0.5, 4 * U, "parabolic t_acc rule");
}

static kc_quat qmake(double w, double x, double y, double z)
{
    kc_quat q = {(kc_real)w, (kc_real)x, (kc_real)y, (kc_real)z};
    return q;
}

static void test_special_orientations(void **state)
{
    (void)state;
    kc_vec3 p[3] = {{{0, 0, 0}}, {{1, 0, 0}}, {{1, 1, 0}}};
    kc_quat r[3];
    kc_real t[3] = {0, 1, 2};
    kc_path_pose e;
    kc_path_cart_cfg c = kc_path_cart_cfg_default();
    c.n_knots = 3;
    c.p = p;
    c.r = r;
    c.t = t;
    c.t_acc = KC_R(0.2);
    /* The same rotation with either sign: no turn at all. */
    r[0] = qmake(0.5, 0.5, 0.5, 0.5);
    r[1] = qmake(-0.5, -0.5, -0.5, -0.5);
    r[2] = r[0];
    for (int m = 0; m < 4; m++) {
        c.method = (kc_path_method)m;
        assert_int_equal(kc_path_cart_plan(&PC, &c), KC_OK);
        for (int64_t k = 0; k <= PC.pos.ticks; k += 7) {
            kc_path_cart_eval(&PC, k, &e);
            NEAR(fabs(quat_dot(&e.r, &r[0])), 1, 8 * U, "double cover: constant orientation");
            NEAR(kc_vec3_norm(&e.w), 0, 8 * U, "double cover: no angular velocity");
        }
    }
    /* Exactly half a turn: reached, finite throughout. */
    r[0] = qmake(1, 0, 0, 0);
    r[1] = qmake(0, 0, 0, 1);
    r[2] = qmake(0, 1, 0, 0);
    for (int m = 0; m < 4; m++) {
        c.method = (kc_path_method)m;
        assert_int_equal(kc_path_cart_plan(&PC, &c), KC_OK);
        for (int64_t k = 0; k <= PC.pos.ticks; k++) {
            kc_path_cart_eval(&PC, k, &e);
            assert_true(kc_quat_norm(&e.r) > KC_R(0.999) && kc_vec3_isfinite(&e.w));
        }
        NEAR(fabs(quat_dot(&e.r, &r[2])), 1, 8 * U, "half turn reached");
        if (m != KC_PATH_BLEND) {
            kc_path_cart_eval_time(&PC, PC.pos.start[1], &e);
            NEAR(fabs(quat_dot(&e.r, &r[1])), 1, 64 * U, "half turn through the knot");
        }
    }
    /* Pure rotation with times from the limits: the angular limits set
     * them; without them only blends (T >= 2 t_acc) can plan it. */
    kc_vec3 same[3] = {{{KC_R(0.3), KC_R(0.2), KC_R(0.1)}}, {{KC_R(0.3), KC_R(0.2), KC_R(0.1)}}, {{KC_R(0.3), KC_R(0.2), KC_R(0.1)}}};
    c.p = same;
    c.t = NULL;
    c.t_acc = 0;
    c.method = KC_PATH_QUINTIC;
    assert_int_equal(kc_path_cart_plan(&PC, &c), KC_E_ARG);
    c.w_max = 1;
    c.alpha_max = 2;
    assert_int_equal(kc_path_cart_plan(&PC, &c), KC_OK);
    /* Half a turn at 1 rad/s, 2 rad/s^2: pi / 1 + 1 / 2. */
    NEAR(PC.pos.t_knot[1], KT_PI + 0.5, 8 * U * 4, "angular trapezoid rule");
    kc_path_cart_eval(&PC, PC.pos.ticks / 3, &e);
    NEAR(e.s, 0, 0, "no path length when only turning");
    NEAR(e.sd, 0, 0, "no speed when only turning");
    c.method = KC_PATH_BLEND;
    c.w_max = c.alpha_max = 0;
    assert_int_equal(kc_path_cart_plan(&PC, &c), KC_OK);
}

/* ---- bad inputs ---- */

static kc_status plan_untouched(const kc_path_cfg *c)
{
    memset(&P, KT_SENTINEL, sizeof P);
    kc_status st = kc_path_plan(&P, c);
    if (st != KC_OK)
        assert_true(kt_is_sentinel(&P, sizeof P));
    return st;
}

static kc_status plan_cart_untouched(const kc_path_cart_cfg *c)
{
    memset(&PC, KT_SENTINEL, sizeof PC);
    kc_status st = kc_path_cart_plan(&PC, c);
    if (st != KC_OK)
        assert_true(kt_is_sentinel(&PC, sizeof PC));
    return st;
}

static int n_bad;
#define EXPECT(call, status)                                                                                          \
    do {                                                                                                              \
        kc_status st_ = (call);                                                                                       \
        if (st_ != (status))                                                                                          \
            fail_msg("%s: %s, expected %s", #call, kc_status_str(st_), kc_status_str(status));                       \
        n_bad++;                                                                                                      \
    } while (0)

static void test_bad_inputs(void **state)
{
    (void)state;
    kc_real q[KC_PATH_MAX_KNOTS + 1], t[KC_PATH_MAX_KNOTS + 1], v[KC_PATH_MAX_KNOTS + 1];
    for (int i = 0; i <= KC_PATH_MAX_KNOTS; i++) {
        q[i] = (kc_real)(i % 3);
        t[i] = (kc_real)i;
        v[i] = 0;
    }
    const kc_real nan = (kc_real)NAN, inf = (kc_real)INFINITY;
    kc_path_cfg good = kc_path_cfg_default(), c;
    good.n_knots = 4;
    good.dim = 1;
    good.q = q;
    good.t = t;
    good.t_acc = KC_R(0.3);
    good.dt = KC_R(0.01);
    EXPECT(plan_untouched(&good), KC_OK);

    EXPECT(kc_path_plan(NULL, &good), KC_E_ARG);
    EXPECT(plan_untouched(NULL), KC_E_ARG);
    c = good; c.q = NULL; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.dim = 0; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.dim = KC_MAX_JOINTS + 1; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.n_knots = 1; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.n_knots = -3; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.n_knots = KC_PATH_MAX_KNOTS + 1; EXPECT(plan_untouched(&c), KC_E_CAPACITY);
    c = good; c.n_knots = KC_PATH_MAX_KNOTS; EXPECT(plan_untouched(&c), KC_OK);
    c = good; c.method = KC_PATH_LAGRANGE; c.n_knots = KC_PATH_MAX_LAGRANGE_KNOTS + 1;
    EXPECT(plan_untouched(&c), KC_E_CAPACITY);
    c = good; c.method = (kc_path_method)7; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.blend = (kc_path_blend)5; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.spline_end = (kc_path_spline_end)-1; EXPECT(plan_untouched(&c), KC_E_ARG);
    /* Numbers. */
    kc_real qb[4] = {0, 1, nan, 2}, qi[4] = {0, inf, 1, 2};
    c = good; c.q = qb; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.q = qi; EXPECT(plan_untouched(&c), KC_E_ARG);
    kc_real tn[4] = {0, 1, nan, 3}, te[4] = {0, 1, 1, 3}, td[4] = {0, 2, 1, 3};
    c = good; c.t = tn; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.t = te; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.t = td; EXPECT(plan_untouched(&c), KC_E_ARG);
    /* t_acc with given times: positive, at most half the shortest segment. */
    c = good; c.t_acc = 0; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.t_acc = -KC_R(0.1); EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.t_acc = nan; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.t_acc = KC_R(0.51); EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.t_acc = KC_R(0.5); EXPECT(plan_untouched(&c), KC_OK);
    c = good; c.method = KC_PATH_SPLINE; c.t_acc = -1; EXPECT(plan_untouched(&c), KC_E_ARG);
    /* Derivatives only where the method takes them. */
    c = good; c.qd = v; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.method = KC_PATH_LAGRANGE; c.qd = v; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.method = KC_PATH_SPLINE; c.qdd = v; EXPECT(plan_untouched(&c), KC_E_ARG);
    kc_real vn[4] = {0, nan, 0, 0};
    c = good; c.method = KC_PATH_SPLINE; c.qd = vn; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.method = KC_PATH_QUINTIC; c.qdd = vn; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.method = KC_PATH_QUINTIC; c.qd = v; c.qdd = v; EXPECT(plan_untouched(&c), KC_OK);
    /* dt. */
    c = good; c.dt = 0; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.dt = -KC_R(0.001); EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.dt = nan; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.dt = inf; EXPECT(plan_untouched(&c), KC_E_ARG);
    /* Limits, with times computed. */
    kc_path_cfg lim = good;
    lim.t = NULL;
    lim.t_acc = 0;
    EXPECT(plan_untouched(&lim), KC_OK);
    c = lim; c.vmax[0] = 0; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = lim; c.vmax[0] = -1; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = lim; c.vmax[0] = nan; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = lim; c.vmax[0] = inf; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = lim; c.amax[0] = 0; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = lim; c.amax[0] = nan; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = lim; c.vmax[1] = -1; EXPECT(plan_untouched(&c), KC_OK); /* beyond dim: unused */
    /* A given t_acc too short for amax: q 0 -> 1 -> 2 -> 0 at vmax 1 needs
     * up to 0.75 * 2 / t_acc <= 1. */
    c = lim; c.t_acc = KC_R(0.1); EXPECT(plan_untouched(&c), KC_E_LIMIT);
    c = lim; c.t_acc = KC_R(1.5); EXPECT(plan_untouched(&c), KC_OK);
    /* A segment without motion: no time from the limits (blends excepted). */
    kc_real qs[4] = {0, 1, 1, 2};
    c = lim; c.q = qs; EXPECT(plan_untouched(&c), KC_OK);
    c = lim; c.q = qs; c.method = KC_PATH_SPLINE; EXPECT(plan_untouched(&c), KC_E_ARG);
    c = good; c.q = qs; c.method = KC_PATH_SPLINE; EXPECT(plan_untouched(&c), KC_OK); /* given times: fine */
    /* Too long for the tick counter; overflowing coefficients. */
    kc_real tl[4] = {0, 1, 2, KC_R(1e5)};
    c = good; c.t = tl; c.dt = KC_R(0.001); EXPECT(plan_untouched(&c), KC_E_CAPACITY);
#ifdef KC_REAL_FLOAT
    kc_real tt[2] = {0, KC_R(1e-20)}, qq[2] = {0, KC_R(1e30)}; /* T^3 underflows: c3 = inf */
#else
    kc_real tt[2] = {0, KC_R(1e-100)}, qq[2] = {0, KC_R(1e200)}; /* c5 = 1e700 */
#endif
    c = good; c.method = KC_PATH_QUINTIC; c.n_knots = 2; c.t = tt; c.q = qq; EXPECT(plan_untouched(&c), KC_E_ARG);

    /* Evaluation. */
    assert_int_equal(kc_path_plan(&P, &good), KC_OK);
    kc_real out[3] = {7, 7, 7};
    EXPECT(kc_path_eval(&P, -1, &out[0], &out[1], &out[2]), KC_E_ARG);
    assert_true(out[0] == 7 && out[1] == 7 && out[2] == 7);
    EXPECT(kc_path_eval(NULL, 0, &out[0], NULL, NULL), KC_E_ARG);
    EXPECT(kc_path_eval(&P, 0, NULL, NULL, NULL), KC_E_ARG);
    EXPECT(kc_path_eval(&P, 0, &out[0], NULL, NULL), KC_OK);
    EXPECT(kc_path_eval_time(&P, nan, &out[0], NULL, NULL), KC_E_ARG);
    EXPECT(kc_path_eval_time(&P, -KC_R(0.1), &out[0], NULL, NULL), KC_E_ARG);
    EXPECT(kc_path_eval_time(&P, KC_R(1e9), &out[0], NULL, NULL), KC_DONE);
    EXPECT(kc_path_eval_piece(&P, P.n_pieces, 0, &out[0], NULL, NULL), KC_E_ARG);
    EXPECT(kc_path_eval_piece(&P, -1, 0, &out[0], NULL, NULL), KC_E_ARG);
    EXPECT(kc_path_eval_piece(&P, 0, nan, &out[0], NULL, NULL), KC_E_ARG);

    /* Cartesian. */
    kc_vec3 p[3] = {{{0, 0, 0}}, {{1, 0, 0}}, {{1, 1, 0}}};
    kc_quat r[3] = {{1, 0, 0, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}};
    kc_vec3 pv[3] = {{{0, 0, 0}}, {{1, 0, 0}}, {{0, 0, 0}}};
    kc_path_cart_cfg cg = kc_path_cart_cfg_default(), cc;
    cg.n_knots = 3;
    cg.p = p;
    cg.r = r;
    EXPECT(plan_cart_untouched(&cg), KC_OK);
    EXPECT(kc_path_cart_plan(NULL, &cg), KC_E_ARG);
    EXPECT(plan_cart_untouched(NULL), KC_E_ARG);
    cc = cg; cc.p = NULL; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.r = NULL; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    kc_quat rz[3] = {{1, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}};
    kc_quat r2[3] = {{1, 0, 0, 0}, {KC_R(1.01), 0, 0, 0}, {1, 0, 0, 0}};
    kc_quat rn[3] = {{1, 0, 0, 0}, {nan, 0, 0, 0}, {1, 0, 0, 0}};
    kc_quat rok[3] = {{1, 0, 0, 0}, {KC_R(0.70710), KC_R(0.70710), 0, 0}, {1, 0, 0, 0}};
    cc = cg; cc.r = rz; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.r = r2; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.r = rn; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.r = rok; EXPECT(plan_cart_untouched(&cc), KC_OK); /* 4 digits: within 1e-3 */
    kc_vec3 pn[3] = {{{0, 0, 0}}, {{1, nan, 0}}, {{1, 1, 0}}};
    cc = cg; cc.p = pn; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.v_max = 0; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.a_max = -1; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.w_max = 1; EXPECT(plan_cart_untouched(&cc), KC_E_ARG); /* alpha_max missing */
    cc = cg; cc.w_max = -1; cc.alpha_max = -1; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.alpha_max = nan; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.v = pv; EXPECT(plan_cart_untouched(&cc), KC_E_ARG); /* blend takes no velocities */
    cc = cg; cc.v = pv; cc.method = KC_PATH_SPLINE; EXPECT(plan_cart_untouched(&cc), KC_OK);
    cc = cg; cc.a = pv; cc.method = KC_PATH_SPLINE; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.n_knots = KC_PATH_MAX_KNOTS + 1; EXPECT(plan_cart_untouched(&cc), KC_E_CAPACITY);
    cc = cg; cc.n_knots = 1; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.dt = 0; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.t = td; EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.t = t; cc.t_acc = KC_R(0.6); EXPECT(plan_cart_untouched(&cc), KC_E_ARG);
    cc = cg; cc.t_acc = KC_R(0.01); EXPECT(plan_cart_untouched(&cc), KC_E_LIMIT);
    assert_int_equal(kc_path_cart_plan(&PC, &cg), KC_OK);
    kc_path_pose e;
    memset(&e, KT_SENTINEL, sizeof e);
    EXPECT(kc_path_cart_eval(&PC, -1, &e), KC_E_ARG);
    assert_true(kt_is_sentinel(&e, sizeof e));
    EXPECT(kc_path_cart_eval(&PC, 0, NULL), KC_E_ARG);
    EXPECT(kc_path_cart_eval(NULL, 0, &e), KC_E_ARG);
    EXPECT(kc_path_cart_eval_time(&PC, nan, &e), KC_E_ARG);
    EXPECT(kc_path_cart_eval_piece(&PC, PC.pos.n_pieces, 0, &e), KC_E_ARG);
    printf("bad inputs: %d calls with the expected status\n", n_bad);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blend_vectors),
        cmocka_unit_test(test_lagrange_vectors),
        cmocka_unit_test(test_spline_vectors),
        cmocka_unit_test(test_joint_properties),
        cmocka_unit_test(test_jerk_stretch),
        cmocka_unit_test(test_cartesian_properties),
        cmocka_unit_test(test_ticks),
        cmocka_unit_test(test_computed_times),
        cmocka_unit_test(test_special_orientations),
        cmocka_unit_test(test_bad_inputs),
    };
    int failed = cmocka_run_group_tests_name("path (" KC_REAL_NAME ")", tests, NULL, NULL);
    printf("smoothing.json: %d/12 blend (7.1 x quartic, parabolic), %d/6 Lagrange (7.2), %d/6 spline (7.3) cases;"
           " worst |error|/tolerance %.3g\n",
           n_blend_cases, n_lagrange_cases, n_spline_cases, worst_ratio);
    kt_report("path");
    return failed;
}
