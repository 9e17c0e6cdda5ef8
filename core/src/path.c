/* SPDX-License-Identifier: BSD-3-Clause */
/* path.c - multi-point paths of seed 001 lab 7 (blends, Lagrange, cubic and
 * quintic splines) in joint space, and the planning passes Cartesian paths
 * (path_cart.c) share through path_internal.h; the formulas and rules are
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

#include "path_internal.h"

/* Relative slack for comparisons that rounding can tip (t_acc <= T/2, the
 * limits of a blend, the tick count). */
#define PATH_SLACK (KC_R(8.0) * KC_REAL_EPS)

/* Sub-intervals per piece of the Bernstein bound of the limit stretch. */
#define PATH_BOUND_SPLITS 8

typedef kc_real piece_coeffs[KC_PATH_MAX_COEFFS][KC_MAX_JOINTS];

static int n_coeffs(const kc_path_knots *K)
{
    switch (K->method) {
    case KC_PATH_BLEND: return K->blend == KC_PATH_BLEND_PARABOLIC ? 3 : 5;
    case KC_PATH_LAGRANGE: return K->n;
    case KC_PATH_SPLINE: return 4;
    case KC_PATH_QUINTIC:
    default: return 6;
    }
}

static kc_real duration_of(const kc_path_knots *K)
{
    return K->d[K->n - 1] + (K->method == KC_PATH_BLEND ? KC_R(2.0) * K->t_acc : KC_R(0.0));
}

/* Start of piece p in plan time. Blends: blend j starts at t_j - t_0 (knot
 * time t_j - t_acc), the line after it at t_j - t_0 + 2 t_acc, never after
 * the next blend (a zero-length line is then never selected: the search
 * takes the last piece starting at or before t). */
static kc_real piece_start(const kc_path_knots *K, int p)
{
    if (K->method != KC_PATH_BLEND)
        return K->d[p];
    int j = p / 2;
    if (p % 2 == 0)
        return K->d[j];
    return kc_min(K->d[j] + KC_R(2.0) * K->t_acc, K->d[j + 1]);
}

static kc_real piece_len(const kc_path_knots *K, int p)
{
    kc_real end = p + 1 < kc_path_n_pieces(K) ? piece_start(K, p + 1) : duration_of(K);
    return end - piece_start(K, p);
}

/* ---- one-dimensional building blocks ---- */

/* Blend around a knot: A at its start, B the knot, dC = C - B, T1 the next
 * segment's time (seed 001 lab 7 sec. 6.1, restored per typo #31); as
 * polynomial coefficients in tau = 2 t_acc h. */
void kc_path_blend_coeffs(kc_real A, kc_real B, kc_real dC, kc_real T1, kc_real t_acc, kc_path_blend shape,
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
void kc_path_quintic_coeffs(kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real v1, kc_real a1, kc_real T,
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

/* ---- knot-level data ---- */

/* Time of a rest-to-rest trapezoid over distance D >= 0 (seed 001 lab 4:
 * triangular below v^2/a). */
kc_real kc_path_t_trap(kc_real D, kc_real v, kc_real a)
{
    if (D >= v * v / a)
        return D / v + v / a;
    return KC_R(2.0) * kc_sqrt(D / a);
}

static kc_real slope(const kc_path_knots *K, int i, int j)
{
    return (K->q[i + 1][j] - K->q[i][j]) / kc_path_seg_time(K, i);
}

/* C2 cubic spline: knot velocities from the tridiagonal system (path.h),
 * Thomas' algorithm; the matrix is shared by every coordinate. */
static void spline_velocities(kc_path_knots *K)
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
                kc_real Tl = kc_path_seg_time(K, i - 1), Tr = kc_path_seg_time(K, i);
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
static void heuristic_velocities(kc_path_knots *K)
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
static void mean_accelerations(kc_path_knots *K)
{
    for (int j = 0; j < K->dim; j++) {
        K->a[0][j] = K->a[K->n - 1][j] = KC_R(0.0);
        for (int i = 1; i < K->n - 1; i++) {
            kc_real Tl = kc_path_seg_time(K, i - 1), Tr = kc_path_seg_time(K, i);
            kc_real dl = K->q[i][j] - K->q[i - 1][j], dr = K->q[i + 1][j] - K->q[i][j];
            kc_real left = (-KC_R(6.0) * dl + KC_R(2.0) * K->v[i - 1][j] * Tl + KC_R(4.0) * K->v[i][j] * Tl) / (Tl * Tl);
            kc_real right = (KC_R(6.0) * dr - KC_R(4.0) * K->v[i][j] * Tr - KC_R(2.0) * K->v[i + 1][j] * Tr) / (Tr * Tr);
            K->a[i][j] = KC_R(0.5) * (left + right);
        }
    }
}

/* Knot velocities and accelerations from the current times. */
static void derive_knot_data(kc_path_knots *K)
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
static void lagrange_piece(const kc_path_knots *K, int p, piece_coeffs c)
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
static void build_piece(const kc_path_knots *K, int p, piece_coeffs c)
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
                kc_real T1 = i == K->n - 1 ? KC_R(1.0) : kc_path_seg_time(K, i);
                kc_path_blend_coeffs(A, B, dC, T1, K->t_acc, K->blend, col, KC_MAX_JOINTS);
            } else {
                /* Line i from t_i + t_acc: q = q_i + delta_i (t - t_i). */
                kc_real s = slope(K, i, j);
                col[0] = K->q[i][j] + s * K->t_acc;
                col[KC_MAX_JOINTS] = s;
            }
        } else if (K->method == KC_PATH_SPLINE) {
            cubic_coeffs(K->q[p][j], K->v[p][j], K->q[p + 1][j], K->v[p + 1][j], kc_path_seg_time(K, p), col,
                         KC_MAX_JOINTS);
        } else {
            kc_path_quintic_coeffs(K->q[p][j], K->v[p][j], K->a[p][j], K->q[p + 1][j], K->v[p + 1][j], K->a[p + 1][j],
                                   kc_path_seg_time(K, p), col, KC_MAX_JOINTS);
        }
    }
}

static int coeffs_finite(const kc_path_knots *K, piece_coeffs c)
{
    for (int m = 0; m < n_coeffs(K); m++)
        for (int j = 0; j < K->dim; j++)
            if (!kc_isfinite(c[m][j]))
                return 0;
    return 1;
}

/* ---- limit stretch: rigorous bounds of |P| on an interval ---- */

/* Row k of Pascal's triangle from row k - 1 in place: row[m] = C(k, m),
 * at most C(7, 3) = 35 (bytes: the bound's frame is on the deepest path of
 * the controller's stack, a Cartesian path replacing a joint move). */
static void pascal_next(unsigned char *row, int k)
{
    row[k] = 1;
    for (int m = k - 1; m > 0; m--)
        row[m] = (unsigned char)(row[m] + row[m - 1]);
}

/* Upper bound of |P(tau)| on [0, L], P = sum_{i<n} b[i] tau^i (n <= 8): on
 * each of PATH_BOUND_SPLITS sub-intervals the largest Bernstein coefficient
 * bounds |P| (convex hull property); the bound exceeds the maximum by
 * O((L / splits)^2). */
static kc_real poly_bound(const kc_real *b, int n, kc_real L)
{
    kc_real best = KC_R(0.0);
    kc_real h = L / (kc_real)PATH_BOUND_SPLITS;
    int deg = n - 1;
    unsigned char top[8]; /* C(deg, m) */
    if (n <= 0)
        return best;
    for (int k = 0; k <= deg; k++)
        pascal_next(top, k);
    for (int s = 0; s < PATH_BOUND_SPLITS; s++) {
        kc_real e[8];
        unsigned char row[8];
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
            pascal_next(row, k); /* C(k, m) */
            for (int m = 0; m <= k; m++)
                beta += (kc_real)row[m] / (kc_real)top[m] * e[m];
            best = kc_max(best, kc_fabs(beta));
        }
    }
    return best;
}

/* Bounds of |qd_j|, |qdd_j| and |qddd_j| over piece c of length L. */
static void piece_bounds(const kc_path_knots *K, piece_coeffs c, kc_real L, kc_real *vb, kc_real *ab, kc_real *jb)
{
    int nc = n_coeffs(K);
    for (int j = 0; j < K->dim; j++) {
        kc_real d1[KC_PATH_MAX_COEFFS], d2[KC_PATH_MAX_COEFFS], d3[KC_PATH_MAX_COEFFS];
        for (int i = 0; i < nc - 1; i++)
            d1[i] = (kc_real)(i + 1) * c[i + 1][j];
        for (int i = 0; i < nc - 2; i++)
            d2[i] = (kc_real)(i + 1) * d1[i + 1];
        for (int i = 0; i < nc - 3; i++)
            d3[i] = (kc_real)(i + 1) * d2[i + 1];
        vb[j] = poly_bound(d1, nc - 1, L);
        ab[j] = poly_bound(d2, nc - 2, L);
        jb[j] = poly_bound(d3, nc - 3, L);
    }
}

/* ---- planning ---- */

static int stretchable(const kc_path_knots *K)
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
static kc_status check_blends(const kc_path_knots *K, const kc_path_limits *L)
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
static kc_status dry_run(const kc_path_knots *K, const kc_path_limits *L, int bounds, kc_real *lambda)
{
    piece_coeffs c;
    kc_real vb[KC_MAX_JOINTS], ab[KC_MAX_JOINTS], jb[KC_MAX_JOINTS];
    kc_real lam = KC_R(1.0);
    int want = bounds && L->computed && stretchable(K);
    for (int p = 0; p < kc_path_n_pieces(K); p++) {
        build_piece(K, p, c);
        if (!coeffs_finite(K, c))
            return KC_E_ARG;
        if (!want)
            continue;
        piece_bounds(K, c, piece_len(K, p), vb, ab, jb);
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
                lam = kc_max(lam, kc_cbrt(jb[j] / L->jmax[j]));
            }
        }
    }
    if (!kc_isfinite(lam))
        return KC_E_ARG;
    *lambda = lam;
    return KC_OK;
}

/* Segment times from the limits (path.h): seg[i] is the trapezoid time, the
 * caller's rule; here the blend floor and the zero-motion check. */
static kc_status computed_times(kc_path_knots *K, const kc_real *seg, kc_real t_acc_rule)
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

/* Validates times, t_acc and derived data, stretches if the limits ask for
 * it, and checks every piece. K holds knots, times (d), t_acc (0: from the
 * limits, computed times only) and the given velocities/accelerations. */
kc_status kc_path_prepare(kc_path_knots *K, const kc_path_limits *L, const kc_real *seg, kc_real ratio)
{
    if (seg != NULL) {
        kc_status st = computed_times(K, seg, (K->blend == KC_PATH_BLEND_PARABOLIC ? KC_R(1.0) : KC_R(1.5)) * ratio);
        if (st != KC_OK)
            return st;
    }
    /* Times: strictly increasing after the shift to t_0. */
    for (int i = 0; i + 1 < K->n; i++)
        if (!(kc_path_seg_time(K, i) > KC_R(0.0)) || !kc_isfinite(K->d[i + 1]))
            return KC_E_ARG;
    if (K->method == KC_PATH_BLEND) {
        if (!kc_path_finite_positive(K->t_acc))
            return KC_E_ARG;
        for (int i = 0; i + 1 < K->n; i++)
            if (KC_R(2.0) * K->t_acc > kc_path_seg_time(K, i) * (KC_R(1.0) + PATH_SLACK))
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
void kc_path_commit(kc_path *path, const kc_path_knots *K)
{
    int np = kc_path_n_pieces(K), nc = n_coeffs(K);
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
        build_piece(K, p, path->c[p]); /* every row and column: those past nc and dim are 0 */
        path->start[p] = piece_start(K, p);
        path->len[p] = piece_len(K, p);
    }
    for (int p = np; p < KC_PATH_MAX_PIECES; p++)
        path->start[p] = path->len[p] = KC_R(0.0);
    /* End state: the last piece at its end, with the exact values where the
     * method knows them. */
    for (int j = 0; j < KC_MAX_JOINTS; j++)
        path->q_end[j] = path->qd_end[j] = path->qdd_end[j] = KC_R(0.0);
    for (int j = 0; j < K->dim; j++) {
        kc_real q, qd, qdd;
        kc_path_horner3(&path->c[np - 1][0][j], nc, KC_MAX_JOINTS, path->len[np - 1], &q, &qd, &qdd);
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
kc_status kc_path_check_common(kc_path_method m, kc_path_blend b, kc_path_spline_end e, int n, int has_qd,
                              int has_qdd, const kc_real *t, kc_real t_acc, kc_real dt)
{
    if (!method_ok(m, b, e))
        return KC_E_ARG;
    if (n < 2)
        return KC_E_ARG;
    if (n > KC_PATH_MAX_KNOTS || (m == KC_PATH_LAGRANGE && n > KC_PATH_MAX_LAGRANGE_KNOTS))
        return KC_E_CAPACITY;
    if (!kc_path_finite_positive(dt))
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

void kc_path_knots_init(kc_path_knots *K, kc_path_method m, kc_path_blend b, kc_path_spline_end e, int n, int dim,
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

void kc_path_given_times(kc_path_knots *K, const kc_real *t)
{
    K->t0 = t[0];
    for (int i = 0; i < K->n; i++)
        K->d[i] = t[i] - t[0];
}

kc_status kc_path_load_knot(kc_path_knots *K, int i, const kc_real *q, const kc_real *v, const kc_real *a)
{
    for (int j = 0; j < K->dim; j++) {
        K->q[i][j] = q[j];
        if (v != NULL)
            K->v[i][j] = v[j];
        if (a != NULL)
            K->a[i][j] = a[j];
        if (!kc_isfinite(K->q[i][j]) || !kc_isfinite(K->v[i][j]) || !kc_isfinite(K->a[i][j]))
            return KC_E_ARG;
    }
    return KC_OK;
}

kc_path_cfg kc_path_cfg_default(void)
{
    kc_path_cfg c;
    memset(&c, 0, sizeof c);
    KC_PATH_KNOT_DEFAULTS(c);
    c.dim = 0;
    c.q = c.qd = c.qdd = NULL;
    for (int j = 0; j < KC_MAX_JOINTS; j++) {
        c.vmax[j] = c.amax[j] = KC_R(1.0);
        c.jmax[j] = (kc_real)HUGE_VAL;
    }
    return c;
}

kc_status kc_path_plan(kc_path *path, const kc_path_cfg *cfg)
{
    kc_path_knots K;
    kc_path_limits L;
    if (path == NULL || cfg == NULL || cfg->q == NULL)
        return KC_E_ARG;
    kc_status st = kc_path_check_common(cfg->method, cfg->blend, cfg->spline_end, cfg->n_knots, cfg->qd != NULL,
                                cfg->qdd != NULL, cfg->t, cfg->t_acc, cfg->dt);
    if (st != KC_OK)
        return st;
    if (cfg->dim < 1 || cfg->dim > KC_MAX_JOINTS)
        return KC_E_ARG;
    int n = cfg->n_knots, dim = cfg->dim;
    kc_path_knots_init(&K, cfg->method, cfg->blend, cfg->spline_end, n, dim, cfg->t_acc, cfg->dt);
    for (int i = 0; i < n; i++) {
        ptrdiff_t row = (ptrdiff_t)i * dim;
        st = kc_path_load_knot(&K, i, cfg->q + row, cfg->qd != NULL ? cfg->qd + row : NULL,
                               cfg->qdd != NULL ? cfg->qdd + row : NULL);
        if (st != KC_OK)
            return st;
    }
    K.have_v = cfg->qd != NULL;
    K.have_a = cfg->qdd != NULL;
    memset(&L, 0, sizeof L);
    L.computed = cfg->t == NULL;
    kc_real seg[KC_PATH_MAX_KNOTS] = {KC_R(0.0)}; /* computed times: the loop below fills seg[0..n-1) */
    kc_real ratio = KC_R(0.0);
    if (cfg->t != NULL) {
        kc_path_given_times(&K, cfg->t);
    } else {
        for (int j = 0; j < dim; j++) {
            if (!kc_path_finite_positive(cfg->vmax[j]) || !kc_path_finite_positive(cfg->amax[j]) ||
                !(cfg->jmax[j] > KC_R(0.0)))
                return KC_E_ARG;
            L.vmax[j] = cfg->vmax[j];
            L.amax[j] = cfg->amax[j];
            L.jmax[j] = cfg->jmax[j];
            ratio = kc_max(ratio, cfg->vmax[j] / cfg->amax[j]);
        }
        for (int i = 0; i + 1 < n; i++) {
            seg[i] = KC_R(0.0);
            for (int j = 0; j < dim; j++)
                seg[i] = kc_max(seg[i], kc_path_t_trap(kc_fabs(K.q[i + 1][j] - K.q[i][j]), L.vmax[j], L.amax[j]));
        }
    }
    st = kc_path_prepare(&K, &L, cfg->t == NULL ? seg : NULL, ratio);
    if (st != KC_OK)
        return st;
    kc_path_commit(path, &K);
    return KC_OK;
}

/* ---- evaluation ---- */

static void eval_piece(const kc_path *path, int p, kc_real tau, kc_real *q, kc_real *qd, kc_real *qdd)
{
    for (int j = 0; j < path->dim; j++) {
        kc_real a, b, c;
        kc_path_horner3(&path->c[p][0][j], path->n_coeffs, KC_MAX_JOINTS, tau, &a, &b, &c);
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

/* The path at time t, or its end (end != 0): KC_DONE there, else KC_OK. */
static kc_status eval_at(const kc_path *path, kc_real t, int end, kc_real *q, kc_real *qd, kc_real *qdd)
{
    if (end) {
        end_state(path, q, qd, qdd);
        return KC_DONE;
    }
    int p = kc_path_find_piece(path, t);
    eval_piece(path, p, t - path->start[p], q, qd, qdd);
    return KC_OK;
}

kc_status kc_path_eval_time(const kc_path *path, kc_real t, kc_real *q, kc_real *qd, kc_real *qdd)
{
    if (path == NULL || q == NULL || !(t >= KC_R(0.0)) || path->n_pieces < 1)
        return KC_E_ARG;
    return eval_at(path, t, t >= path->duration, q, qd, qdd);
}

kc_status kc_path_eval(const kc_path *path, int64_t k, kc_real *q, kc_real *qd, kc_real *qdd)
{
    if (path == NULL || q == NULL || k < 0 || path->n_pieces < 1)
        return KC_E_ARG;
    return eval_at(path, (kc_real)k * path->dt, k >= path->ticks, q, qd, qdd);
}

kc_status kc_path_eval_piece(const kc_path *path, int p, kc_real tau, kc_real *q, kc_real *qd, kc_real *qdd)
{
    if (path == NULL || q == NULL || p < 0 || p >= path->n_pieces || !kc_isfinite(tau))
        return KC_E_ARG;
    eval_piece(path, p, tau, q, qd, qdd);
    return KC_OK;
}
