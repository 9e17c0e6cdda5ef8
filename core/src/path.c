/* path.c - multi-point paths of seed 001 lab 7 (blends, Lagrange, cubic and
 * quintic splines) in joint and Cartesian space; the formulas and rules are
 * documented in kinctl/path.h.
 *
 * Planning runs in two passes over the same knot-level data (times, knot
 * velocities and accelerations): a dry run builds every piece in a local
 * buffer, checks that its coefficients are finite and, where the limits ask
 * for it, bounds its velocity and acceleration; only once everything is known
 * to be valid are the pieces written to the caller's plan, which is thus
 * untouched on every error. */
#include "kinctl/path.h"

#include <stddef.h>
#include <string.h>

/* Relative slack for comparisons that rounding can tip (t_acc <= T/2, the
 * limits of a blend, the tick count). */
#define PATH_SLACK (KC_R(8.0) * KC_REAL_EPS)

/* Below this rotation angle (rad) the SO(3) Jacobian terms use their series
 * (truncation below 1e-16 in double at 0.1, below 1e-10 in float at 0.5,
 * where the closed forms lose no more than a few ulps to cancellation). */
#ifdef KC_REAL_FLOAT
#define PATH_SERIES_ANGLE KC_R(0.5)
#else
#define PATH_SERIES_ANGLE KC_R(0.1)
#endif

/* Sub-intervals per piece of the Bernstein bound of the limit stretch. */
#define PATH_BOUND_SPLITS 8

typedef kc_real piece_coeffs[KC_PATH_MAX_COEFFS][KC_MAX_JOINTS];

/* Everything a path is built from, whatever its space. */
typedef struct knots {
    kc_path_method method;
    kc_path_blend blend;
    kc_path_spline_end spline_end;
    int n, dim;
    kc_real q[KC_PATH_MAX_KNOTS][KC_MAX_JOINTS];
    kc_real t0;                   /* knot time of the first knot */
    kc_real d[KC_PATH_MAX_KNOTS]; /* t_i - t_0 */
    kc_real t_acc;
    int have_v, have_a; /* knot velocities / accelerations given */
    kc_real v[KC_PATH_MAX_KNOTS][KC_MAX_JOINTS];
    kc_real a[KC_PATH_MAX_KNOTS][KC_MAX_JOINTS];
    kc_real dt;
    kc_real stretch;
} knots;

static int finite_positive(kc_real x) { return kc_isfinite(x) && x > KC_R(0.0); }

static kc_real seg_time(const knots *K, int i) { return K->d[i + 1] - K->d[i]; }

static int n_pieces(const knots *K) { return K->method == KC_PATH_BLEND ? 2 * K->n - 1 : K->n - 1; }

static int n_coeffs(const knots *K)
{
    switch (K->method) {
    case KC_PATH_BLEND: return K->blend == KC_PATH_BLEND_PARABOLIC ? 3 : 5;
    case KC_PATH_LAGRANGE: return K->n;
    case KC_PATH_SPLINE: return 4;
    case KC_PATH_QUINTIC:
    default: return 6;
    }
}

static kc_real duration_of(const knots *K)
{
    return K->d[K->n - 1] + (K->method == KC_PATH_BLEND ? KC_R(2.0) * K->t_acc : KC_R(0.0));
}

/* Start of piece p in plan time. Blends: blend j starts at t_j - t_0 (knot
 * time t_j - t_acc), the line after it at t_j - t_0 + 2 t_acc, never after
 * the next blend (a zero-length line is then never selected: the search
 * takes the last piece starting at or before t). */
static kc_real piece_start(const knots *K, int p)
{
    if (K->method != KC_PATH_BLEND)
        return K->d[p];
    int j = p / 2;
    if (p % 2 == 0)
        return K->d[j];
    return kc_min(K->d[j] + KC_R(2.0) * K->t_acc, K->d[j + 1]);
}

static kc_real piece_len(const knots *K, int p)
{
    kc_real end = p + 1 < n_pieces(K) ? piece_start(K, p + 1) : duration_of(K);
    return end - piece_start(K, p);
}

/* ---- one-dimensional building blocks ---- */

/* Blend around a knot: A at its start, B the knot, dC = C - B, T1 the next
 * segment's time (seed 001 lab 7 sec. 6.1, restored per typo #31); as
 * polynomial coefficients in tau = 2 t_acc h. */
static void blend_coeffs(kc_real A, kc_real B, kc_real dC, kc_real T1, kc_real t_acc, kc_path_blend shape,
                         kc_real *c, ptrdiff_t stride)
{
    kc_real dB = A - B;
    kc_real K = dC * t_acc / T1 + dB;
    kc_real ta2 = t_acc * t_acc;
    c[0] = B + dB;
    c[stride] = -dB / t_acc;
    if (shape == KC_PATH_BLEND_PARABOLIC) {
        /* q = (K h - 2 dB) h + B + dB */
        c[2 * stride] = K / (KC_R(4.0) * ta2);
    } else {
        /* q = [(K (2 - h) h^2 - 2 dB) h] + B + dB = B + dB - 2 dB h + 2 K h^3 - K h^4 */
        c[2 * stride] = KC_R(0.0);
        c[3 * stride] = K / (KC_R(4.0) * ta2 * t_acc);
        c[4 * stride] = -K / (KC_R(16.0) * ta2 * ta2);
    }
}

/* Cubic Hermite, seed sec. 6.3: K0..K3. */
static void cubic_coeffs(kc_real p0, kc_real v0, kc_real p1, kc_real v1, kc_real T, kc_real *c, ptrdiff_t stride)
{
    c[0] = p0;
    c[stride] = v0;
    c[2 * stride] = (KC_R(3.0) * p1 - KC_R(3.0) * p0 - KC_R(2.0) * v0 * T - v1 * T) / (T * T);
    c[3 * stride] = (v1 * T + v0 * T - KC_R(2.0) * p1 + KC_R(2.0) * p0) / (T * T * T);
}

/* Quintic Hermite: position, velocity and acceleration at both ends. */
static void quintic_coeffs(kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real v1, kc_real a1, kc_real T,
                           kc_real *c, ptrdiff_t stride)
{
    kc_real dp = p1 - p0, T2 = T * T, T3 = T2 * T;
    c[0] = p0;
    c[stride] = v0;
    c[2 * stride] = KC_R(0.5) * a0;
    c[3 * stride] =
        (KC_R(20.0) * dp - (KC_R(8.0) * v1 + KC_R(12.0) * v0) * T - (KC_R(3.0) * a0 - a1) * T2) / (KC_R(2.0) * T3);
    c[4 * stride] = (-KC_R(30.0) * dp + (KC_R(14.0) * v1 + KC_R(16.0) * v0) * T + (KC_R(3.0) * a0 - KC_R(2.0) * a1) * T2) /
                    (KC_R(2.0) * T3 * T);
    c[5 * stride] =
        (KC_R(12.0) * dp - KC_R(6.0) * (v1 + v0) * T + (a1 - a0) * T2) / (KC_R(2.0) * T3 * T2);
}

/* Horner: value and first two derivatives of sum_i c[i*stride] tau^i. */
static void horner3(const kc_real *c, int n, ptrdiff_t stride, kc_real tau, kc_real *q, kc_real *qd, kc_real *qdd)
{
    kc_real p = KC_R(0.0), d1 = KC_R(0.0), d2 = KC_R(0.0);
    for (int i = n - 1; i >= 0; i--) {
        d2 = d2 * tau + d1;
        d1 = d1 * tau + p;
        p = p * tau + c[i * stride];
    }
    *q = p;
    *qd = d1;
    *qdd = KC_R(2.0) * d2;
}

/* ---- knot-level data ---- */

/* Time of a rest-to-rest trapezoid over distance D >= 0 (seed 001 lab 4:
 * triangular below v^2/a). */
static kc_real t_trap(kc_real D, kc_real v, kc_real a)
{
    if (D >= v * v / a)
        return D / v + v / a;
    return KC_R(2.0) * kc_sqrt(D / a);
}

static kc_real slope(const knots *K, int i, int j) { return (K->q[i + 1][j] - K->q[i][j]) / seg_time(K, i); }

/* C2 cubic spline: knot velocities from the tridiagonal system (path.h),
 * Thomas' algorithm; the matrix is shared by every coordinate. */
static void spline_velocities(knots *K)
{
    int n = K->n;
    kc_real diag[KC_PATH_MAX_KNOTS], upper[KC_PATH_MAX_KNOTS], lower[KC_PATH_MAX_KNOTS];
    kc_real rhs[KC_PATH_MAX_KNOTS];
    if (n < 2)
        return;
    for (int j = 0; j < K->dim; j++) {
        for (int i = 0; i < n; i++) {
            if (i == 0 || i == n - 1) {
                if (K->spline_end == KC_PATH_SPLINE_CLAMPED) {
                    diag[i] = KC_R(1.0);
                    lower[i] = upper[i] = rhs[i] = KC_R(0.0);
                } else if (i == 0) {
                    diag[i] = KC_R(2.0);
                    upper[i] = KC_R(1.0);
                    lower[i] = KC_R(0.0);
                    rhs[i] = KC_R(3.0) * slope(K, 0, j);
                } else {
                    diag[i] = KC_R(2.0);
                    lower[i] = KC_R(1.0);
                    upper[i] = KC_R(0.0);
                    rhs[i] = KC_R(3.0) * slope(K, n - 2, j);
                }
            } else {
                kc_real Tl = seg_time(K, i - 1), Tr = seg_time(K, i);
                lower[i] = Tr;
                diag[i] = KC_R(2.0) * (Tl + Tr);
                upper[i] = Tl;
                rhs[i] = KC_R(3.0) * (Tr * slope(K, i - 1, j) + Tl * slope(K, i, j));
            }
        }
        /* Forward sweep, then back substitution. */
        for (int i = 1; i < n; i++) {
            kc_real m = lower[i] / diag[i - 1];
            diag[i] -= m * upper[i - 1];
            rhs[i] -= m * rhs[i - 1];
        }
        K->v[n - 1][j] = rhs[n - 1] / diag[n - 1];
        for (int i = n - 2; i >= 0; i--)
            K->v[i][j] = (rhs[i] - upper[i] * K->v[i + 1][j]) / diag[i];
    }
}

/* Knot velocities of a quintic path without given ones (path.h). */
static void heuristic_velocities(knots *K)
{
    for (int j = 0; j < K->dim; j++) {
        K->v[0][j] = K->v[K->n - 1][j] = KC_R(0.0);
        for (int i = 1; i < K->n - 1; i++) {
            kc_real s0 = slope(K, i - 1, j), s1 = slope(K, i, j);
            K->v[i][j] = (s0 > KC_R(0.0) && s1 > KC_R(0.0)) || (s0 < KC_R(0.0) && s1 < KC_R(0.0))
                             ? KC_R(0.5) * (s0 + s1)
                             : KC_R(0.0);
        }
    }
}

/* Knot accelerations of a quintic path without given ones: the mean of the
 * cubic Hermite pieces' accelerations on either side, 0 at the ends. */
static void mean_accelerations(knots *K)
{
    for (int j = 0; j < K->dim; j++) {
        K->a[0][j] = K->a[K->n - 1][j] = KC_R(0.0);
        for (int i = 1; i < K->n - 1; i++) {
            kc_real Tl = seg_time(K, i - 1), Tr = seg_time(K, i);
            kc_real dl = K->q[i][j] - K->q[i - 1][j], dr = K->q[i + 1][j] - K->q[i][j];
            kc_real left = (-KC_R(6.0) * dl + KC_R(2.0) * K->v[i - 1][j] * Tl + KC_R(4.0) * K->v[i][j] * Tl) / (Tl * Tl);
            kc_real right = (KC_R(6.0) * dr - KC_R(4.0) * K->v[i][j] * Tr - KC_R(2.0) * K->v[i + 1][j] * Tr) / (Tr * Tr);
            K->a[i][j] = KC_R(0.5) * (left + right);
        }
    }
}

/* Knot velocities and accelerations from the current times. */
static void derive_knot_data(knots *K)
{
    if (K->method == KC_PATH_SPLINE && !K->have_v)
        spline_velocities(K);
    if (K->method == KC_PATH_QUINTIC) {
        if (!K->have_v)
            heuristic_velocities(K);
        if (!K->have_a)
            mean_accelerations(K);
    }
}

/* ---- pieces ---- */

/* Coefficients of the Lagrange polynomial through every knot, expanded in
 * tau = t - t_p: sum_i q_i prod_{k != i} (tau - s_k) / (s_i - s_k) with
 * s_k = t_k - t_p, so that the expansion stays well conditioned over the
 * piece. */
static void lagrange_piece(const knots *K, int p, piece_coeffs c)
{
    int n = K->n;
    for (int m = 0; m < n; m++)
        for (int j = 0; j < K->dim; j++)
            c[m][j] = KC_R(0.0);
    for (int i = 0; i < n; i++) {
        kc_real basis[KC_PATH_MAX_COEFFS];
        kc_real denom = KC_R(1.0);
        kc_real si = K->d[i] - K->d[p];
        int deg = 0;
        basis[0] = KC_R(1.0);
        for (int k = 0; k < n; k++) {
            if (k == i)
                continue;
            kc_real sk = K->d[k] - K->d[p];
            /* basis *= (tau - sk) */
            basis[deg + 1] = basis[deg];
            for (int m = deg; m > 0; m--)
                basis[m] = basis[m - 1] - sk * basis[m];
            basis[0] = -sk * basis[0];
            deg++;
            denom *= si - sk;
        }
        for (int m = 0; m < n; m++) {
            kc_real b = basis[m] / denom;
            for (int j = 0; j < K->dim; j++)
                c[m][j] += K->q[i][j] * b;
        }
    }
    /* At tau = 0 only the knot's own term is nonzero: take it exactly. */
    for (int j = 0; j < K->dim; j++)
        c[0][j] = K->q[p][j];
}

/* Piece p's coefficients for every coordinate. */
static void build_piece(const knots *K, int p, piece_coeffs c)
{
    for (int m = 0; m < KC_PATH_MAX_COEFFS; m++)
        for (int j = 0; j < KC_MAX_JOINTS; j++)
            c[m][j] = KC_R(0.0);
    if (K->method == KC_PATH_LAGRANGE) {
        lagrange_piece(K, p, c);
        return;
    }
    for (int j = 0; j < K->dim; j++) {
        kc_real *col = &c[0][j];
        if (K->method == KC_PATH_BLEND) {
            int i = p / 2;
            if (p % 2 == 0) {
                /* Blend at knot i: A on the incoming line (q_0 at the first
                 * knot), C the next knot (B itself at the last). */
                kc_real B = K->q[i][j];
                kc_real A = i == 0 ? B : B - slope(K, i - 1, j) * K->t_acc;
                kc_real dC = i == K->n - 1 ? KC_R(0.0) : K->q[i + 1][j] - B;
                kc_real T1 = i == K->n - 1 ? KC_R(1.0) : seg_time(K, i);
                blend_coeffs(A, B, dC, T1, K->t_acc, K->blend, col, KC_MAX_JOINTS);
            } else {
                /* Line i from t_i + t_acc: q = q_i + delta_i (t - t_i). */
                kc_real s = slope(K, i, j);
                col[0] = K->q[i][j] + s * K->t_acc;
                col[KC_MAX_JOINTS] = s;
            }
        } else if (K->method == KC_PATH_SPLINE) {
            cubic_coeffs(K->q[p][j], K->v[p][j], K->q[p + 1][j], K->v[p + 1][j], seg_time(K, p), col, KC_MAX_JOINTS);
        } else {
            quintic_coeffs(K->q[p][j], K->v[p][j], K->a[p][j], K->q[p + 1][j], K->v[p + 1][j], K->a[p + 1][j],
                           seg_time(K, p), col, KC_MAX_JOINTS);
        }
    }
}

static int coeffs_finite(const knots *K, piece_coeffs c)
{
    for (int m = 0; m < n_coeffs(K); m++)
        for (int j = 0; j < K->dim; j++)
            if (!kc_isfinite(c[m][j]))
                return 0;
    return 1;
}

/* ---- limit stretch: rigorous bounds of |P| on an interval ---- */

static const kc_real binom[8][8] = {
    {1, 0, 0, 0, 0, 0, 0, 0},     {1, 1, 0, 0, 0, 0, 0, 0},      {1, 2, 1, 0, 0, 0, 0, 0},
    {1, 3, 3, 1, 0, 0, 0, 0},     {1, 4, 6, 4, 1, 0, 0, 0},      {1, 5, 10, 10, 5, 1, 0, 0},
    {1, 6, 15, 20, 15, 6, 1, 0},  {1, 7, 21, 35, 35, 21, 7, 1},
};

/* Upper bound of |P(tau)| on [0, L], P = sum_{i<n} b[i] tau^i (n <= 8): on
 * each of PATH_BOUND_SPLITS sub-intervals the largest Bernstein coefficient
 * bounds |P| (convex hull property); the bound exceeds the maximum by
 * O((L / splits)^2). */
static kc_real poly_bound(const kc_real *b, int n, kc_real L)
{
    kc_real best = KC_R(0.0);
    kc_real h = L / (kc_real)PATH_BOUND_SPLITS;
    int deg = n - 1;
    if (n <= 0)
        return best;
    for (int s = 0; s < PATH_BOUND_SPLITS; s++) {
        kc_real e[8];
        kc_real a0 = (kc_real)s * h;
        for (int i = 0; i < n; i++)
            e[i] = b[i];
        /* Taylor shift to a0 (repeated synthetic division). */
        for (int k = 0; k < deg; k++)
            for (int i = deg - 1; i >= k; i--)
                e[i] += a0 * e[i + 1];
        /* Scale to u in [0, 1]. */
        kc_real hp = KC_R(1.0);
        for (int i = 0; i < n; i++) {
            e[i] *= hp;
            hp *= h;
        }
        for (int k = 0; k <= deg; k++) {
            kc_real beta = KC_R(0.0);
            for (int m = 0; m <= k; m++)
                beta += binom[k][m] / binom[deg][m] * e[m];
            best = kc_max(best, kc_fabs(beta));
        }
    }
    return best;
}

/* Bounds of |qd_j| and |qdd_j| over piece c of length L. */
static void piece_bounds(const knots *K, piece_coeffs c, kc_real L, kc_real *vb, kc_real *ab)
{
    int nc = n_coeffs(K);
    for (int j = 0; j < K->dim; j++) {
        kc_real d1[KC_PATH_MAX_COEFFS], d2[KC_PATH_MAX_COEFFS];
        for (int i = 0; i < nc - 1; i++)
            d1[i] = (kc_real)(i + 1) * c[i + 1][j];
        for (int i = 0; i < nc - 2; i++)
            d2[i] = (kc_real)((i + 1) * (i + 2)) * c[i + 2][j];
        vb[j] = poly_bound(d1, nc - 1, L);
        ab[j] = poly_bound(d2, nc - 2, L);
    }
}

/* ---- planning ---- */

/* How the limits enter when times are computed. */
typedef struct limits {
    int computed;                /* times computed from the limits */
    int norm;                    /* Cartesian: limits on |p'|, |p''| */
    kc_real vmax[KC_MAX_JOINTS]; /* per coordinate, or [0] for the norm */
    kc_real amax[KC_MAX_JOINTS];
} limits;

static int stretchable(const knots *K)
{
    switch (K->method) {
    case KC_PATH_LAGRANGE: return 1;
    case KC_PATH_SPLINE: return !K->have_v;
    case KC_PATH_QUINTIC: return !K->have_v && !K->have_a;
    case KC_PATH_BLEND:
    default: return 0;
    }
}

/* Largest velocity change of a blend over the limit, or 0. */
static kc_status check_blends(const knots *K, const limits *L)
{
    kc_real peak = K->blend == KC_PATH_BLEND_PARABOLIC ? KC_R(0.5) : KC_R(0.75);
    for (int i = 0; i < K->n; i++) {
        kc_real sum2 = KC_R(0.0);
        for (int j = 0; j < K->dim; j++) {
            kc_real in = i == 0 ? KC_R(0.0) : slope(K, i - 1, j);
            kc_real out = i == K->n - 1 ? KC_R(0.0) : slope(K, i, j);
            kc_real acc = peak * kc_fabs(out - in) / K->t_acc;
            if (L->norm)
                sum2 += acc * acc;
            else if (acc > L->amax[j] * (KC_R(1.0) + PATH_SLACK))
                return KC_E_LIMIT;
        }
        if (L->norm && kc_sqrt(sum2) > L->amax[0] * (KC_R(1.0) + PATH_SLACK))
            return KC_E_LIMIT;
    }
    return KC_OK;
}

/* Dry run over every piece: finite coefficients, and (bounds) the stretch
 * factor the limits ask for. */
static kc_status dry_run(const knots *K, const limits *L, int bounds, kc_real *lambda)
{
    piece_coeffs c;
    kc_real vb[KC_MAX_JOINTS], ab[KC_MAX_JOINTS];
    kc_real lam = KC_R(1.0);
    int want = bounds && L->computed && stretchable(K);
    for (int p = 0; p < n_pieces(K); p++) {
        build_piece(K, p, c);
        if (!coeffs_finite(K, c))
            return KC_E_ARG;
        if (!want)
            continue;
        piece_bounds(K, c, piece_len(K, p), vb, ab);
        if (L->norm) {
            kc_real v2 = KC_R(0.0), a2 = KC_R(0.0);
            for (int j = 0; j < K->dim; j++) {
                v2 += vb[j] * vb[j];
                a2 += ab[j] * ab[j];
            }
            lam = kc_max(lam, kc_sqrt(v2) / L->vmax[0]);
            lam = kc_max(lam, kc_sqrt(kc_sqrt(a2) / L->amax[0]));
        } else {
            for (int j = 0; j < K->dim; j++) {
                lam = kc_max(lam, vb[j] / L->vmax[j]);
                lam = kc_max(lam, kc_sqrt(ab[j] / L->amax[j]));
            }
        }
    }
    if (!kc_isfinite(lam))
        return KC_E_ARG;
    *lambda = lam;
    return KC_OK;
}

/* Validates times, t_acc and derived data, stretches if the limits ask for
 * it, and checks every piece. K holds knots, times (d), t_acc (0: from the
 * limits, computed times only) and the given velocities/accelerations. */
static kc_status prepare(knots *K, const limits *L)
{
    /* Times: strictly increasing after the shift to t_0. */
    for (int i = 0; i + 1 < K->n; i++)
        if (!(seg_time(K, i) > KC_R(0.0)) || !kc_isfinite(K->d[i + 1]))
            return KC_E_ARG;
    if (K->method == KC_PATH_BLEND) {
        if (!finite_positive(K->t_acc))
            return KC_E_ARG;
        for (int i = 0; i + 1 < K->n; i++)
            if (KC_R(2.0) * K->t_acc > seg_time(K, i) * (KC_R(1.0) + PATH_SLACK))
                return KC_E_ARG;
        if (L->computed) {
            kc_status st = check_blends(K, L);
            if (st != KC_OK)
                return st;
        }
    } else {
        K->t_acc = KC_R(0.0);
    }
    K->stretch = KC_R(1.0);
    derive_knot_data(K);
    kc_real lambda = KC_R(1.0);
    kc_status st = dry_run(K, L, 1, &lambda);
    if (st != KC_OK)
        return st;
    if (lambda > KC_R(1.0)) {
        /* Every knot derivative is computed from the times, so the path
         * becomes q(t / lambda): velocities scale by 1/lambda,
         * accelerations by 1/lambda^2, and the bounds with them. */
        for (int i = 0; i < K->n; i++)
            K->d[i] *= lambda;
        K->stretch = lambda;
        derive_knot_data(K);
        st = dry_run(K, L, 0, &lambda);
        if (st != KC_OK)
            return st;
    }
    kc_real dur = duration_of(K);
    if (!kc_isfinite(dur) || !(dur / K->dt <= (kc_real)KC_PATH_MAX_TICKS))
        return KC_E_CAPACITY;
    return KC_OK;
}

/* Segment times from the limits (path.h): seg[i] is the trapezoid time, the
 * caller's rule; here the blend floor and the zero-motion check. */
static kc_status computed_times(knots *K, const kc_real *seg, kc_real t_acc_rule)
{
    if (K->method == KC_PATH_BLEND && K->t_acc == KC_R(0.0))
        K->t_acc = t_acc_rule;
    K->t0 = KC_R(0.0);
    K->d[0] = KC_R(0.0);
    for (int i = 0; i + 1 < K->n; i++) {
        kc_real T = seg[i];
        if (K->method == KC_PATH_BLEND)
            T = kc_max(T, KC_R(2.0) * K->t_acc);
        if (!(T > KC_R(0.0)) || !kc_isfinite(T))
            return KC_E_ARG;
        K->d[i + 1] = K->d[i] + T;
    }
    return KC_OK;
}

static int64_t tick_count(kc_real duration, kc_real dt)
{
    kc_real r = duration / dt;
    /* First k with k dt >= duration, forgiving the rounding of r. */
    kc_real k = -kc_floor(-(r - PATH_SLACK * kc_max(KC_R(1.0), r)));
    if (k < KC_R(1.0))
        k = KC_R(1.0);
    /* k <= KC_PATH_MAX_TICKS + 1 (prepare): int32_t converts in one
     * instruction where float-to-int64 would need libgcc's soft double. */
    return (int32_t)k;
}

/* Writes the checked plan. */
static void commit(kc_path *path, const knots *K)
{
    piece_coeffs c;
    int np = n_pieces(K), nc = n_coeffs(K);
    path->method = K->method;
    path->blend = K->blend;
    path->dim = K->dim;
    path->n_knots = K->n;
    path->n_pieces = np;
    path->n_coeffs = nc;
    path->dt = K->dt;
    path->duration = duration_of(K);
    path->ticks = tick_count(path->duration, K->dt);
    path->t_acc = K->t_acc;
    path->t_origin = K->t0 - K->t_acc;
    path->stretch = K->stretch;
    for (int i = 0; i < KC_PATH_MAX_KNOTS; i++)
        path->t_knot[i] = i < K->n ? K->t0 + K->d[i] : KC_R(0.0);
    memset(path->c, 0, sizeof path->c);
    for (int p = 0; p < np; p++) {
        build_piece(K, p, c);
        path->start[p] = piece_start(K, p);
        path->len[p] = piece_len(K, p);
        for (int m = 0; m < nc; m++)
            for (int j = 0; j < KC_MAX_JOINTS; j++)
                path->c[p][m][j] = c[m][j];
    }
    for (int p = np; p < KC_PATH_MAX_PIECES; p++)
        path->start[p] = path->len[p] = KC_R(0.0);
    /* End state: the last piece at its end, with the exact values where the
     * method knows them. */
    for (int j = 0; j < KC_MAX_JOINTS; j++)
        path->q_end[j] = path->qd_end[j] = path->qdd_end[j] = KC_R(0.0);
    for (int j = 0; j < K->dim; j++) {
        kc_real q, qd, qdd;
        horner3(&path->c[np - 1][0][j], nc, KC_MAX_JOINTS, path->len[np - 1], &q, &qd, &qdd);
        path->q_end[j] = K->q[K->n - 1][j];
        path->qd_end[j] = qd;
        path->qdd_end[j] = qdd;
        if (K->method == KC_PATH_BLEND) {
            path->qd_end[j] = KC_R(0.0);
            if (K->blend == KC_PATH_BLEND_QUARTIC)
                path->qdd_end[j] = KC_R(0.0);
        } else if (K->method == KC_PATH_SPLINE || K->method == KC_PATH_QUINTIC) {
            path->qd_end[j] = K->v[K->n - 1][j];
            if (K->method == KC_PATH_QUINTIC)
                path->qdd_end[j] = K->a[K->n - 1][j];
        }
    }
}

static int method_ok(kc_path_method m, kc_path_blend b, kc_path_spline_end e)
{
    return (m == KC_PATH_BLEND || m == KC_PATH_LAGRANGE || m == KC_PATH_SPLINE || m == KC_PATH_QUINTIC) &&
           (b == KC_PATH_BLEND_QUARTIC || b == KC_PATH_BLEND_PARABOLIC) &&
           (e == KC_PATH_SPLINE_CLAMPED || e == KC_PATH_SPLINE_NATURAL);
}

/* Common checks of both configurations: counts, method, dt, which knot
 * derivatives the method takes, given times and t_acc. */
static kc_status check_common(kc_path_method m, kc_path_blend b, kc_path_spline_end e, int n, int has_qd,
                              int has_qdd, const kc_real *t, kc_real t_acc, kc_real dt)
{
    if (!method_ok(m, b, e))
        return KC_E_ARG;
    if (n < 2)
        return KC_E_ARG;
    if (n > KC_PATH_MAX_KNOTS || (m == KC_PATH_LAGRANGE && n > KC_PATH_MAX_LAGRANGE_KNOTS))
        return KC_E_CAPACITY;
    if (!finite_positive(dt))
        return KC_E_ARG;
    if ((has_qd && m != KC_PATH_SPLINE && m != KC_PATH_QUINTIC) || (has_qdd && m != KC_PATH_QUINTIC))
        return KC_E_ARG;
    if (!kc_isfinite(t_acc) || t_acc < KC_R(0.0))
        return KC_E_ARG;
    if (t != NULL) {
        for (int i = 0; i < n; i++)
            if (!kc_isfinite(t[i]) || (i > 0 && !(t[i] > t[i - 1])))
                return KC_E_ARG;
        if (m == KC_PATH_BLEND && !(t_acc > KC_R(0.0)))
            return KC_E_ARG;
    }
    return KC_OK;
}

static void knots_init(knots *K, kc_path_method m, kc_path_blend b, kc_path_spline_end e, int n, int dim,
                       kc_real t_acc, kc_real dt)
{
    K->method = m;
    K->blend = b;
    K->spline_end = e;
    K->n = n;
    K->dim = dim;
    K->t_acc = t_acc;
    K->dt = dt;
    K->have_v = K->have_a = 0;
    K->t0 = KC_R(0.0);
    K->stretch = KC_R(1.0);
    for (int i = 0; i < KC_PATH_MAX_KNOTS; i++) {
        K->d[i] = KC_R(0.0);
        for (int j = 0; j < KC_MAX_JOINTS; j++)
            K->q[i][j] = K->v[i][j] = K->a[i][j] = KC_R(0.0);
    }
}

static void given_times(knots *K, const kc_real *t)
{
    K->t0 = t[0];
    for (int i = 0; i < K->n; i++)
        K->d[i] = t[i] - t[0];
}

kc_path_cfg kc_path_cfg_default(void)
{
    kc_path_cfg c;
    memset(&c, 0, sizeof c);
    c.method = KC_PATH_BLEND;
    c.blend = KC_PATH_BLEND_QUARTIC;
    c.spline_end = KC_PATH_SPLINE_CLAMPED;
    c.n_knots = 0;
    c.dim = 0;
    c.q = c.t = c.qd = c.qdd = NULL;
    c.t_acc = KC_R(0.0);
    for (int j = 0; j < KC_MAX_JOINTS; j++)
        c.vmax[j] = c.amax[j] = KC_R(1.0);
    c.dt = KC_R(0.001);
    return c;
}

kc_status kc_path_plan(kc_path *path, const kc_path_cfg *cfg)
{
    knots K;
    limits L;
    if (path == NULL || cfg == NULL || cfg->q == NULL)
        return KC_E_ARG;
    kc_status st = check_common(cfg->method, cfg->blend, cfg->spline_end, cfg->n_knots, cfg->qd != NULL,
                                cfg->qdd != NULL, cfg->t, cfg->t_acc, cfg->dt);
    if (st != KC_OK)
        return st;
    if (cfg->dim < 1 || cfg->dim > KC_MAX_JOINTS)
        return KC_E_ARG;
    int n = cfg->n_knots, dim = cfg->dim;
    knots_init(&K, cfg->method, cfg->blend, cfg->spline_end, n, dim, cfg->t_acc, cfg->dt);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < dim; j++) {
            K.q[i][j] = cfg->q[i * dim + j];
            if (cfg->qd != NULL)
                K.v[i][j] = cfg->qd[i * dim + j];
            if (cfg->qdd != NULL)
                K.a[i][j] = cfg->qdd[i * dim + j];
            if (!kc_isfinite(K.q[i][j]) || !kc_isfinite(K.v[i][j]) || !kc_isfinite(K.a[i][j]))
                return KC_E_ARG;
        }
    }
    K.have_v = cfg->qd != NULL;
    K.have_a = cfg->qdd != NULL;
    memset(&L, 0, sizeof L);
    L.computed = cfg->t == NULL;
    if (cfg->t != NULL) {
        given_times(&K, cfg->t);
    } else {
        kc_real seg[KC_PATH_MAX_KNOTS] = {KC_R(0.0)}; /* the loop below fills seg[0..n-1) */
        kc_real ratio = KC_R(0.0);
        for (int j = 0; j < dim; j++) {
            if (!finite_positive(cfg->vmax[j]) || !finite_positive(cfg->amax[j]))
                return KC_E_ARG;
            L.vmax[j] = cfg->vmax[j];
            L.amax[j] = cfg->amax[j];
            ratio = kc_max(ratio, cfg->vmax[j] / cfg->amax[j]);
        }
        for (int i = 0; i + 1 < n; i++) {
            seg[i] = KC_R(0.0);
            for (int j = 0; j < dim; j++)
                seg[i] = kc_max(seg[i], t_trap(kc_fabs(K.q[i + 1][j] - K.q[i][j]), L.vmax[j], L.amax[j]));
        }
        kc_real rule = (cfg->blend == KC_PATH_BLEND_PARABOLIC ? KC_R(1.0) : KC_R(1.5)) * ratio;
        st = computed_times(&K, seg, rule);
        if (st != KC_OK)
            return st;
    }
    st = prepare(&K, &L);
    if (st != KC_OK)
        return st;
    commit(path, &K);
    return KC_OK;
}

/* ---- evaluation ---- */

/* The last piece starting at or before t (t >= 0). */
static int find_piece(const kc_path *path, kc_real t)
{
    int lo = 0, hi = path->n_pieces - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (path->start[mid] <= t)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

static void eval_piece(const kc_path *path, int p, kc_real tau, kc_real *q, kc_real *qd, kc_real *qdd)
{
    for (int j = 0; j < path->dim; j++) {
        kc_real a, b, c;
        horner3(&path->c[p][0][j], path->n_coeffs, KC_MAX_JOINTS, tau, &a, &b, &c);
        q[j] = a;
        if (qd != NULL)
            qd[j] = b;
        if (qdd != NULL)
            qdd[j] = c;
    }
}

static void end_state(const kc_path *path, kc_real *q, kc_real *qd, kc_real *qdd)
{
    for (int j = 0; j < path->dim; j++) {
        q[j] = path->q_end[j];
        if (qd != NULL)
            qd[j] = path->qd_end[j];
        if (qdd != NULL)
            qdd[j] = path->qdd_end[j];
    }
}

kc_status kc_path_eval_time(const kc_path *path, kc_real t, kc_real *q, kc_real *qd, kc_real *qdd)
{
    if (path == NULL || q == NULL || !(t >= KC_R(0.0)) || path->n_pieces < 1)
        return KC_E_ARG;
    if (t >= path->duration) {
        end_state(path, q, qd, qdd);
        return KC_DONE;
    }
    int p = find_piece(path, t);
    eval_piece(path, p, t - path->start[p], q, qd, qdd);
    return KC_OK;
}

kc_status kc_path_eval(const kc_path *path, int64_t k, kc_real *q, kc_real *qd, kc_real *qdd)
{
    if (path == NULL || q == NULL || k < 0 || path->n_pieces < 1)
        return KC_E_ARG;
    if (k >= path->ticks) {
        end_state(path, q, qd, qdd);
        return KC_DONE;
    }
    kc_real t = (kc_real)k * path->dt;
    int p = find_piece(path, t);
    eval_piece(path, p, t - path->start[p], q, qd, qdd);
    return KC_OK;
}

kc_status kc_path_eval_piece(const kc_path *path, int p, kc_real tau, kc_real *q, kc_real *qd, kc_real *qdd)
{
    if (path == NULL || q == NULL || p < 0 || p >= path->n_pieces || !kc_isfinite(tau))
        return KC_E_ARG;
    eval_piece(path, p, tau, q, qd, qdd);
    return KC_OK;
}

/* ---- Cartesian paths ---- */

/* Rotations of the knots: sign-aligned unit quaternions, w_i = log(r_i^*
 * r_{i+1}) (angle <= pi), and the knot angular velocities (body frame). */
typedef struct rot_knots {
    kc_quat r[KC_PATH_MAX_KNOTS];
    kc_vec3 w[KC_PATH_MAX_KNOTS];
    kc_vec3 om[KC_PATH_MAX_KNOTS];
} rot_knots;

static kc_vec3 v3_scale(kc_vec3 a, kc_real s) { return kc_vec3_make(a.v[0] * s, a.v[1] * s, a.v[2] * s); }
static kc_vec3 v3_add(kc_vec3 a, kc_vec3 b) { return kc_vec3_make(a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2]); }
static kc_vec3 v3_cross(kc_vec3 a, kc_vec3 b)
{
    kc_vec3 c;
    kc_vec3_cross(&a, &b, &c);
    return c;
}
static kc_real v3_dot(kc_vec3 a, kc_vec3 b) { return kc_vec3_dot(&a, &b); }

/* Coefficients of the right Jacobian of SO(3), J_r(v) = I - ca [v]x + cb
 * [v]x^2 with ca = (1 - cos th) / th^2, cb = (th - sin th) / th^3, and
 * their derivatives divided by th (for d/dt J_r). */
static void jr_coeffs(kc_real th, kc_real *ca, kc_real *cb, kc_real *dca, kc_real *dcb)
{
    kc_real t2 = th * th;
    if (th < PATH_SERIES_ANGLE) {
        *ca = KC_R(0.5) - t2 / KC_R(24.0) + t2 * t2 / KC_R(720.0) - t2 * t2 * t2 / KC_R(40320.0);
        *cb = KC_R(1.0) / KC_R(6.0) - t2 / KC_R(120.0) + t2 * t2 / KC_R(5040.0) - t2 * t2 * t2 / KC_R(362880.0);
        *dca = -KC_R(1.0) / KC_R(12.0) + t2 / KC_R(180.0) - t2 * t2 / KC_R(6720.0) + t2 * t2 * t2 / KC_R(453600.0);
        *dcb = -KC_R(1.0) / KC_R(60.0) + t2 / KC_R(1260.0) - t2 * t2 / KC_R(60480.0) + t2 * t2 * t2 / KC_R(4989600.0);
        return;
    }
    kc_real s, c;
    kc_sincos(th, &s, &c);
    *ca = (KC_R(1.0) - c) / t2;
    *cb = (th - s) / (t2 * th);
    *dca = s / (t2 * th) - KC_R(2.0) * (KC_R(1.0) - c) / (t2 * t2);
    *dcb = (KC_R(1.0) - c) / (t2 * t2) - KC_R(3.0) * (th - s) / (t2 * t2 * th);
}

/* J_r(v)^-1 x = x + 1/2 v x x + ce v x (v x x), ce = 1/th^2 - cot(th/2) /
 * (2 th): finite for th in [0, pi]. */
static kc_vec3 jr_inv_apply(kc_vec3 v, kc_vec3 x)
{
    kc_real th = kc_vec3_norm(&v), t2 = th * th, ce;
    if (th < PATH_SERIES_ANGLE) {
        ce = KC_R(1.0) / KC_R(12.0) + t2 / KC_R(720.0) + t2 * t2 / KC_R(30240.0) + t2 * t2 * t2 / KC_R(1209600.0);
    } else {
        kc_real s, c;
        kc_sincos(KC_R(0.5) * th, &s, &c);
        ce = KC_R(1.0) / t2 - c / (KC_R(2.0) * th * s);
    }
    kc_vec3 vx = v3_cross(v, x);
    return v3_add(x, v3_add(v3_scale(vx, KC_R(0.5)), v3_scale(v3_cross(v, vx), ce)));
}

/* (d/dt J_r(v)) vd for a motion with v' = vd:
 * -ca' (v.vd/th) v x vd + cb' (v.vd/th) v x (v x vd) + cb vd x (v x vd). */
static kc_vec3 jr_dot_apply(kc_vec3 v, kc_vec3 vd)
{
    kc_real ca, cb, dca, dcb;
    jr_coeffs(kc_vec3_norm(&v), &ca, &cb, &dca, &dcb);
    kc_real vv = v3_dot(v, vd);
    kc_vec3 vx = v3_cross(v, vd);
    kc_vec3 r = v3_scale(vx, -dca * vv);
    r = v3_add(r, v3_scale(v3_cross(v, vx), dcb * vv));
    return v3_add(r, v3_scale(v3_cross(vd, vx), cb));
}

/* Orientation coefficients of piece p: base quaternion and the rotation
 * vector polynomial rc[i][axis]. */
static void build_rot_piece(const knots *K, const rot_knots *R, int p, kc_quat *base, kc_real rc[6][3])
{
    for (int i = 0; i < 6; i++)
        rc[i][0] = rc[i][1] = rc[i][2] = KC_R(0.0);
    if (K->method == KC_PATH_BLEND) {
        int i = p / 2;
        *base = R->r[i];
        for (int x = 0; x < 3; x++) {
            if (p % 2 == 0) {
                /* The blend in the tangent space at r_i: B = 0, A on the
                 * incoming turn, C = w_i. */
                kc_real A = i == 0 ? KC_R(0.0) : -R->w[i - 1].v[x] * K->t_acc / seg_time(K, i - 1);
                kc_real dC = i == K->n - 1 ? KC_R(0.0) : R->w[i].v[x];
                kc_real T1 = i == K->n - 1 ? KC_R(1.0) : seg_time(K, i);
                blend_coeffs(A, KC_R(0.0), dC, T1, K->t_acc, K->blend, &rc[0][x], 3);
            } else {
                kc_real rate = R->w[i].v[x] / seg_time(K, i);
                rc[0][x] = rate * K->t_acc;
                rc[1][x] = rate;
            }
        }
        return;
    }
    /* Quintic in the tangent space at r_p: v(0) = 0, v'(0) = omega_p, v''(0)
     * = 0 (J_r(0) = I and its derivative vanishes on v' there), v(T) = w_p,
     * J_r(w_p) v'(T) = omega_{p+1}, d/dt (J_r v') = 0 at T. */
    kc_real T = seg_time(K, p);
    kc_vec3 w = R->w[p];
    kc_vec3 v1 = jr_inv_apply(w, R->om[p + 1]);
    kc_vec3 a1 = v3_scale(jr_inv_apply(w, jr_dot_apply(w, v1)), KC_R(-1.0));
    *base = R->r[p];
    for (int x = 0; x < 3; x++)
        quintic_coeffs(KC_R(0.0), R->om[p].v[x], KC_R(0.0), w.v[x], v1.v[x], a1.v[x], T, &rc[0][x], 3);
}

/* Knot angular velocities (body frame): the slope of the parabola through
 * three knots, 0 at both ends. w_{i-1} is the same vector in the frames of
 * r_{i-1} and r_i (it is the axis of the turn between them). */
static void knot_rates(const knots *K, rot_knots *R)
{
    R->om[0] = R->om[K->n - 1] = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    for (int i = 1; i + 1 < K->n; i++) {
        kc_real Tl = seg_time(K, i - 1), Tr = seg_time(K, i);
        kc_vec3 rl = v3_scale(R->w[i - 1], KC_R(1.0) / Tl), rr = v3_scale(R->w[i], KC_R(1.0) / Tr);
        R->om[i] = v3_scale(v3_add(v3_scale(rl, Tr), v3_scale(rr, Tl)), KC_R(1.0) / (Tl + Tr));
    }
}

/* 5-point Gauss-Legendre on [0, 1]: over a table sub-interval (at most
 * 1/32 of a piece, split at the speed's minima, so |p'| is smooth on it)
 * it integrates polynomials of degree 9 exactly, far inside the 1e-7 of the
 * length that s must keep (measured against Simpson in the path tests),
 * one speed evaluation a tick cheaper than 6 points. */
#define PATH_GL_POINTS 5
static const kc_real gl_x[PATH_GL_POINTS] = {
    KC_R(0.046910077030668004), KC_R(0.23076534494715845), KC_R(0.5), KC_R(0.76923465505284155),
    KC_R(0.953089922969332),
};
static const kc_real gl_w[PATH_GL_POINTS] = {
    KC_R(0.11846344252809454), KC_R(0.23931433524968323), KC_R(0.28444444444444444), KC_R(0.23931433524968323),
    KC_R(0.11846344252809454),
};

/* |p'| of piece p at tau from the velocity coefficients. */
static kc_real speed_at(const kc_path_cart *path, int p, kc_real tau)
{
    const kc_real(*vc)[3] = path->vc[p];
    kc_real x = KC_R(0.0), y = KC_R(0.0), z = KC_R(0.0);
    for (int i = path->pos.n_coeffs - 2; i >= 0; i--) {
        x = x * tau + vc[i][0];
        y = y * tau + vc[i][1];
        z = z * tau + vc[i][2];
    }
    return kc_sqrt(x * x + y * y + z * z);
}

static int piece_is_line(const kc_path *pos, int p)
{
    for (int i = 2; i < pos->n_coeffs; i++)
        for (int j = 0; j < 3; j++)
            if (pos->c[p][i][j] != KC_R(0.0))
                return 0;
    return 1;
}

/* Gauss-Legendre of |p'| over [a, b] of piece p. */
static kc_real arc_gl(const kc_path_cart *path, int p, kc_real a, kc_real b)
{
    kc_real s = KC_R(0.0), h = b - a;
    for (int i = 0; i < PATH_GL_POINTS; i++)
        s += gl_w[i] * speed_at(path, p, a + gl_x[i] * h);
    return s * h;
}

/* Path length at tau on piece p: the table's entry at or below tau plus
 * the quadrature from there (lines: speed times tau). */
static kc_real arc_length(const kc_path_cart *path, int p, kc_real tau)
{
    const kc_path *pos = &path->pos;
    if (piece_is_line(pos, p))
        return path->s_arc[p][0] + speed_at(path, p, KC_R(0.0)) * tau;
    int lo = 0, hi = path->n_arc[p] - 2;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (path->tau_arc[p][mid] <= tau)
            lo = mid;
        else
            hi = mid - 1;
    }
    return path->s_arc[p][lo] + arc_gl(path, p, path->tau_arc[p][lo], tau);
}

/* p'.p'' of piece p at tau: half the rate of the squared speed. */
static kc_real speed2_rate(const kc_path *pos, int p, kc_real tau)
{
    kc_real r = KC_R(0.0);
    for (int j = 0; j < 3; j++) {
        kc_real q, qd, qdd;
        horner3(&pos->c[p][0][j], pos->n_coeffs, KC_MAX_JOINTS, tau, &q, &qd, &qdd);
        r += qd * qdd;
    }
    return r;
}

/* Compensated (Kahan) sum: *sum += x with the lost low part kept in *comp,
 * so the table's rounding does not grow with its length. */
static kc_real kahan_add(kc_real *sum, kc_real *comp, kc_real x)
{
    kc_real y = x - *comp;
    kc_real t = *sum + y;
    *comp = (t - *sum) - y;
    *sum = t;
    return t;
}

/* The length table of piece p (see kc_path_cart), continuing the running
 * compensated sum (*s, *comp). */
static void arc_table(kc_path_cart *path, int p, kc_real *s, kc_real *comp)
{
    const kc_path *pos = &path->pos;
    kc_real L = pos->len[p];
    kc_real minima[KC_PATH_ARC_MINIMA] = {KC_R(0.0)}; /* [0, nm) are found below */
    int nm = 0;
    if (!piece_is_line(pos, p) && L > KC_R(0.0)) {
        /* Local minima of the speed: p'.p'' changes from - to +. */
        const int samples = 64;
        kc_real prev = speed2_rate(pos, p, KC_R(0.0));
        for (int i = 1; i <= samples && nm < KC_PATH_ARC_MINIMA; i++) {
            kc_real b = L * (kc_real)i / (kc_real)samples;
            kc_real cur = speed2_rate(pos, p, b);
            if (prev < KC_R(0.0) && cur >= KC_R(0.0) && i < samples) {
                kc_real a = L * (kc_real)(i - 1) / (kc_real)samples, hb = b;
                for (int it = 0; it < 60; it++) {
                    kc_real m = KC_R(0.5) * (a + hb);
                    if (speed2_rate(pos, p, m) < KC_R(0.0))
                        a = m;
                    else
                        hb = m;
                }
                minima[nm++] = KC_R(0.5) * (a + hb);
            }
            prev = cur;
        }
    }
    /* Merge the uniform points with the minima. */
    kc_real h = L / (kc_real)KC_PATH_ARC_SPLITS;
    int n = 0, m = 0;
    int line = piece_is_line(pos, p);
    kc_real speed = speed_at(path, p, KC_R(0.0));
    path->tau_arc[p][n] = KC_R(0.0);
    path->s_arc[p][n++] = *s;
    for (int i = 1; i <= KC_PATH_ARC_SPLITS; i++) {
        kc_real u = i == KC_PATH_ARC_SPLITS ? L : (kc_real)i * h;
        while (m < nm && minima[m] < u) {
            if (minima[m] > path->tau_arc[p][n - 1]) {
                path->tau_arc[p][n] = minima[m];
                path->s_arc[p][n] = kahan_add(s, comp, arc_gl(path, p, path->tau_arc[p][n - 1], minima[m]));
                n++;
            }
            m++;
        }
        path->tau_arc[p][n] = u;
        path->s_arc[p][n] = kahan_add(s, comp, line ? speed * (u - path->tau_arc[p][n - 1])
                                                     : arc_gl(path, p, path->tau_arc[p][n - 1], u));
        n++;
    }
    path->n_arc[p] = n;
}

kc_path_cart_cfg kc_path_cart_cfg_default(void)
{
    kc_path_cart_cfg c;
    memset(&c, 0, sizeof c);
    c.method = KC_PATH_BLEND;
    c.blend = KC_PATH_BLEND_QUARTIC;
    c.spline_end = KC_PATH_SPLINE_CLAMPED;
    c.n_knots = 0;
    c.p = NULL;
    c.r = NULL;
    c.t = NULL;
    c.v = NULL;
    c.a = NULL;
    c.t_acc = KC_R(0.0);
    c.v_max = c.a_max = KC_R(1.0);
    c.w_max = c.alpha_max = KC_R(0.0);
    c.dt = KC_R(0.001);
    return c;
}

kc_status kc_path_plan_cart(kc_path_cart *path, const kc_path_cart_cfg *cfg)
{
    knots K;
    limits L;
    rot_knots R;
    if (path == NULL || cfg == NULL || cfg->p == NULL || cfg->r == NULL)
        return KC_E_ARG;
    kc_status st = check_common(cfg->method, cfg->blend, cfg->spline_end, cfg->n_knots, cfg->v != NULL,
                                cfg->a != NULL, cfg->t, cfg->t_acc, cfg->dt);
    if (st != KC_OK)
        return st;
    int n = cfg->n_knots;
    knots_init(&K, cfg->method, cfg->blend, cfg->spline_end, n, 3, cfg->t_acc, cfg->dt);
    for (int i = 0; i < n; i++) {
        for (int x = 0; x < 3; x++) {
            K.q[i][x] = cfg->p[i].v[x];
            if (cfg->v != NULL)
                K.v[i][x] = cfg->v[i].v[x];
            if (cfg->a != NULL)
                K.a[i][x] = cfg->a[i].v[x];
            if (!kc_isfinite(K.q[i][x]) || !kc_isfinite(K.v[i][x]) || !kc_isfinite(K.a[i][x]))
                return KC_E_ARG;
        }
        const kc_quat *r = &cfg->r[i];
        if (!kc_isfinite(r->w) || !kc_isfinite(r->x) || !kc_isfinite(r->y) || !kc_isfinite(r->z))
            return KC_E_ARG;
        kc_real norm = kc_quat_norm(r);
        if (!(kc_fabs(norm - KC_R(1.0)) <= KC_PATH_TOL_QUAT_NORM))
            return KC_E_ARG;
        kc_quat u;
        kc_quat_normalize(r, &u);
        /* The double cover: turn the shorter way to the next knot. */
        if (i > 0 && R.r[i - 1].w * u.w + R.r[i - 1].x * u.x + R.r[i - 1].y * u.y + R.r[i - 1].z * u.z < KC_R(0.0)) {
            u.w = -u.w;
            u.x = -u.x;
            u.y = -u.y;
            u.z = -u.z;
        }
        R.r[i] = u;
    }
    K.have_v = cfg->v != NULL;
    K.have_a = cfg->a != NULL;
    kc_real angle[KC_PATH_MAX_KNOTS];
    for (int i = 0; i + 1 < n; i++) {
        kc_quat ci, rel;
        kc_quat_conj(&R.r[i], &ci);
        kc_quat_mul(&ci, &R.r[i + 1], &rel);
        kc_quat_log(&rel, &R.w[i]);
        angle[i] = kc_vec3_norm(&R.w[i]);
    }
    R.w[n - 1] = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    memset(&L, 0, sizeof L);
    L.computed = cfg->t == NULL;
    L.norm = 1;
    if (!kc_isfinite(cfg->w_max) || !kc_isfinite(cfg->alpha_max) || cfg->w_max < KC_R(0.0) ||
        cfg->alpha_max < KC_R(0.0) || ((cfg->w_max > KC_R(0.0)) != (cfg->alpha_max > KC_R(0.0))))
        return KC_E_ARG;
    if (cfg->t != NULL) {
        given_times(&K, cfg->t);
    } else {
        if (!finite_positive(cfg->v_max) || !finite_positive(cfg->a_max))
            return KC_E_ARG;
        L.vmax[0] = cfg->v_max;
        L.amax[0] = cfg->a_max;
        int angular = cfg->w_max > KC_R(0.0);
        kc_real seg[KC_PATH_MAX_KNOTS] = {KC_R(0.0)}; /* the loop below fills seg[0..n-1) */
        for (int i = 0; i + 1 < n; i++) {
            kc_vec3 dp = kc_vec3_make(K.q[i + 1][0] - K.q[i][0], K.q[i + 1][1] - K.q[i][1], K.q[i + 1][2] - K.q[i][2]);
            seg[i] = t_trap(kc_vec3_norm(&dp), cfg->v_max, cfg->a_max);
            if (angular)
                seg[i] = kc_max(seg[i], t_trap(angle[i], cfg->w_max, cfg->alpha_max));
        }
        kc_real ratio = cfg->v_max / cfg->a_max;
        if (angular)
            ratio = kc_max(ratio, cfg->w_max / cfg->alpha_max);
        kc_real rule = (cfg->blend == KC_PATH_BLEND_PARABOLIC ? KC_R(1.0) : KC_R(1.5)) * ratio;
        st = computed_times(&K, seg, rule);
        if (st != KC_OK)
            return st;
    }
    st = prepare(&K, &L);
    if (st != KC_OK)
        return st;
    /* Orientation on the final times; dry run first. */
    knot_rates(&K, &R);
    int np = n_pieces(&K);
    for (int p = 0; p < np; p++) {
        kc_quat b;
        kc_real rc[6][3];
        build_rot_piece(&K, &R, p, &b, rc);
        for (int i = 0; i < 6; i++)
            for (int x = 0; x < 3; x++)
                if (!kc_isfinite(rc[i][x]))
                    return KC_E_ARG;
    }
    commit(&path->pos, &K);
    memset(path->rc, 0, sizeof path->rc);
    memset(path->vc, 0, sizeof path->vc);
    for (int p = 0; p < np; p++)
        for (int i = 1; i < path->pos.n_coeffs; i++)
            for (int x = 0; x < 3; x++)
                path->vc[p][i - 1][x] = (kc_real)i * path->pos.c[p][i][x];
    memset(path->pc, 0, sizeof path->pc);
    for (int p = 0; p < np; p++)
        for (int i = 0; i < path->pos.n_coeffs; i++)
            for (int x = 0; x < 3; x++)
                path->pc[p][i][x] = path->pos.c[p][i][x];
    memset(path->tau_arc, 0, sizeof path->tau_arc);
    memset(path->s_arc, 0, sizeof path->s_arc);
    for (int p = 0; p < KC_PATH_MAX_PIECES; p++) {
        kc_quat_identity(&path->base[p]);
        kc_mat3_identity(&path->base_R[p]);
        path->n_arc[p] = 0;
    }
    kc_real s = KC_R(0.0), comp = KC_R(0.0);
    for (int p = 0; p < np; p++) {
        build_rot_piece(&K, &R, p, &path->base[p], path->rc[p]);
        kc_quat_to_mat3(&path->base[p], &path->base_R[p]);
        arc_table(path, p, &s, &comp);
    }
    path->length = s;
    path->r_end = R.r[n - 1];
    return KC_OK;
}

/* Orientation and angular velocity of piece p at tau: r = base exp(v) and
 * w = R(r) J_r(v) v' = R(base) J_l(v) v' (R(exp v) J_r(v) = J_l(v) = I +
 * ca [v]x + cb [v]x^2), with exp and J_l from one sine and cosine of
 * |v|/2: exp(v) = (cos(th/2), sin(th/2) v/th), ca = (1 - cos th)/th^2 =
 * 2 (sin(th/2)/th)^2, cb = (th - sin th)/th^3, sin th = 2 sin(th/2)
 * cos(th/2). */
static void eval_rot(const kc_path_cart *path, int p, kc_real tau, kc_quat *r, kc_vec3 *w)
{
    int nr = path->pos.method == KC_PATH_BLEND ? 5 : 6;
    kc_vec3 v, vd;
    for (int x = 0; x < 3; x++) {
        kc_real a = KC_R(0.0), b = KC_R(0.0);
        for (int i = nr - 1; i >= 0; i--) {
            b = b * tau + a;
            a = a * tau + path->rc[p][i][x];
        }
        v.v[x] = a;
        vd.v[x] = b;
    }
    kc_real th = kc_vec3_norm(&v), sh, ch, k, cb;
    kc_sincos(KC_R(0.5) * th, &sh, &ch);
    kc_real t2 = th * th;
    /* sin(th/2)/th has no cancellation: only th ~ 0 needs its series. */
    k = th < KC_TOL_SMALL_ANGLE ? KC_R(0.5) - t2 / KC_R(48.0) : sh / th;
    if (th < PATH_SERIES_ANGLE)
        cb = KC_R(1.0) / KC_R(6.0) - t2 / KC_R(120.0) + t2 * t2 / KC_R(5040.0) - t2 * t2 * t2 / KC_R(362880.0);
    else
        cb = (th - KC_R(2.0) * sh * ch) / (t2 * th);
    /* r = base (ch, k v), the Hamilton product written out. */
    const kc_quat *b = &path->base[p];
    kc_real ex = k * v.v[0], ey = k * v.v[1], ez = k * v.v[2];
    r->w = b->w * ch - b->x * ex - b->y * ey - b->z * ez;
    r->x = b->w * ex + b->x * ch + b->y * ez - b->z * ey;
    r->y = b->w * ey - b->x * ez + b->y * ch + b->z * ex;
    r->z = b->w * ez + b->x * ey - b->y * ex + b->z * ch;
    kc_real ca = KC_R(2.0) * k * k;
    kc_vec3 vx = v3_cross(v, vd), vvx = v3_cross(v, vx);
    kc_vec3 wb = kc_vec3_make(vd.v[0] + ca * vx.v[0] + cb * vvx.v[0], vd.v[1] + ca * vx.v[1] + cb * vvx.v[1],
                              vd.v[2] + ca * vx.v[2] + cb * vvx.v[2]);
    const kc_mat3 *R = &path->base_R[p];
    for (int i = 0; i < 3; i++)
        w->v[i] = R->m[i][0] * wb.v[0] + R->m[i][1] * wb.v[1] + R->m[i][2] * wb.v[2];
}

/* sd and sdd from p' and p'' (path.h: the one-sided rate where |p'| = 0). */
static void speed_terms(const kc_vec3 *v, const kc_vec3 *a, int at_end, kc_real *sd, kc_real *sdd)
{
    kc_real sp = kc_vec3_norm(v);
    *sd = sp;
    if (sp > KC_R(0.0))
        *sdd = kc_vec3_dot(v, a) / sp;
    else
        *sdd = at_end ? -kc_vec3_norm(a) : kc_vec3_norm(a);
}

static void eval_cart_piece(const kc_path_cart *path, int p, kc_real tau, kc_path_pose *out)
{
    /* horner3 on the three coordinates at once, from the packed rows. */
    const kc_real(*c)[3] = path->pc[p];
    kc_real q[3] = {KC_R(0.0), KC_R(0.0), KC_R(0.0)}, d1[3] = {KC_R(0.0), KC_R(0.0), KC_R(0.0)},
            d2[3] = {KC_R(0.0), KC_R(0.0), KC_R(0.0)};
    for (int i = path->pos.n_coeffs - 1; i >= 0; i--) {
        for (int x = 0; x < 3; x++) {
            d2[x] = d2[x] * tau + d1[x];
            d1[x] = d1[x] * tau + q[x];
            q[x] = q[x] * tau + c[i][x];
        }
    }
    out->p = kc_vec3_make(q[0], q[1], q[2]);
    out->v = kc_vec3_make(d1[0], d1[1], d1[2]);
    out->a = kc_vec3_make(KC_R(2.0) * d2[0], KC_R(2.0) * d2[1], KC_R(2.0) * d2[2]);
    eval_rot(path, p, tau, &out->r, &out->w);
    out->s = arc_length(path, p, tau);
    speed_terms(&out->v, &out->a, 0, &out->sd, &out->sdd);
}

static void cart_end(const kc_path_cart *path, kc_path_pose *out)
{
    const kc_path *pos = &path->pos;
    out->p = kc_vec3_make(pos->q_end[0], pos->q_end[1], pos->q_end[2]);
    out->v = kc_vec3_make(pos->qd_end[0], pos->qd_end[1], pos->qd_end[2]);
    out->a = kc_vec3_make(pos->qdd_end[0], pos->qdd_end[1], pos->qdd_end[2]);
    out->r = path->r_end;
    /* Every method ends its turn at rest (knot rate 0, blend rate dC/T = 0). */
    out->w = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    out->s = path->length;
    speed_terms(&out->v, &out->a, 1, &out->sd, &out->sdd);
}

kc_status kc_path_eval_cart_time(const kc_path_cart *path, kc_real t, kc_path_pose *out)
{
    if (path == NULL || out == NULL || !(t >= KC_R(0.0)) || path->pos.n_pieces < 1)
        return KC_E_ARG;
    if (t >= path->pos.duration) {
        cart_end(path, out);
        return KC_DONE;
    }
    int p = find_piece(&path->pos, t);
    eval_cart_piece(path, p, t - path->pos.start[p], out);
    return KC_OK;
}

kc_status kc_path_eval_cart(const kc_path_cart *path, int64_t k, kc_path_pose *out)
{
    if (path == NULL || out == NULL || k < 0 || path->pos.n_pieces < 1)
        return KC_E_ARG;
    if (k >= path->pos.ticks) {
        cart_end(path, out);
        return KC_DONE;
    }
    kc_real t = (kc_real)k * path->pos.dt;
    int p = find_piece(&path->pos, t);
    eval_cart_piece(path, p, t - path->pos.start[p], out);
    return KC_OK;
}

kc_status kc_path_eval_cart_piece(const kc_path_cart *path, int p, kc_real tau, kc_path_pose *out)
{
    if (path == NULL || out == NULL || p < 0 || p >= path->pos.n_pieces || !kc_isfinite(tau))
        return KC_E_ARG;
    eval_cart_piece(path, p, tau, out);
    return KC_OK;
}
