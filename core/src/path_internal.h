/* SPDX-License-Identifier: BSD-3-Clause */
/* path_internal.h - what joint paths (path.c) and Cartesian paths
 * (path_cart.c) share: the knot-level data every method is built from, the
 * one-dimensional building blocks, and the planning passes (times, the
 * limit stretch, the dry run over every piece, the commit). Private to the
 * core; the formulas are documented in kinctl/path.h. */
#ifndef KINCTL_PATH_INTERNAL_H
#define KINCTL_PATH_INTERNAL_H

#include <stddef.h>

#include "kinctl/path.h"

/* Everything a path is built from, whatever its space. */
typedef struct kc_path_knots {
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
} kc_path_knots;

/* How the limits enter when times are computed. */
typedef struct kc_path_limits {
    int computed;                /* times computed from the limits */
    int norm;                    /* Cartesian: limits on |p'|, |p''| */
    kc_real vmax[KC_MAX_JOINTS]; /* per coordinate, or [0] for the norm */
    kc_real amax[KC_MAX_JOINTS];
    kc_real jmax[KC_MAX_JOINTS]; /* per coordinate, > 0, +infinity: none (not with norm) */
} kc_path_limits;

static inline int kc_path_finite_positive(kc_real x) { return kc_isfinite(x) && x > KC_R(0.0); }

static inline kc_real kc_path_seg_time(const kc_path_knots *K, int i) { return K->d[i + 1] - K->d[i]; }

static inline int kc_path_n_pieces(const kc_path_knots *K)
{
    return K->method == KC_PATH_BLEND ? 2 * K->n - 1 : K->n - 1;
}

/* Horner: value and first two derivatives of sum_i c[i*stride] tau^i. */
static inline void kc_path_horner3(const kc_real *c, int n, ptrdiff_t stride, kc_real tau, kc_real *q, kc_real *qd,
                                   kc_real *qdd)
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

/* The last piece starting at or before t (t >= 0). */
static inline int kc_path_find_piece(const kc_path *path, kc_real t)
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

/* The knot settings kc_path_cfg_default and kc_path_cart_cfg_default both
 * start from (the same fields): quartic blends, clamped splines, no knots,
 * t_acc 0 (the rule), dt 0.001 s. */
#define KC_PATH_KNOT_DEFAULTS(c)                                                                                       \
    do {                                                                                                               \
        (c).method = KC_PATH_BLEND;                                                                                    \
        (c).blend = KC_PATH_BLEND_QUARTIC;                                                                             \
        (c).spline_end = KC_PATH_SPLINE_CLAMPED;                                                                       \
        (c).n_knots = 0;                                                                                               \
        (c).t = NULL;                                                                                                  \
        (c).t_acc = KC_R(0.0);                                                                                         \
        (c).dt = KC_R(0.001);                                                                                          \
    } while (0)

/* Blend around a knot: A at its start, B the knot, dC = C - B, T1 the next
 * segment's time; as polynomial coefficients in tau = 2 t_acc h, written
 * to c[0], c[stride], ... */
void kc_path_blend_coeffs(kc_real A, kc_real B, kc_real dC, kc_real T1, kc_real t_acc, kc_path_blend shape,
                          kc_real *c, ptrdiff_t stride);

/* Quintic Hermite: position, velocity and acceleration at both ends. */
void kc_path_quintic_coeffs(kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real v1, kc_real a1, kc_real T,
                            kc_real *c, ptrdiff_t stride);

/* Time of a rest-to-rest trapezoid over distance D >= 0 (seed 001 lab 4). */
kc_real kc_path_t_trap(kc_real D, kc_real v, kc_real a);

/* Common checks of both configurations: counts, method, dt, which knot
 * derivatives the method takes, given times and t_acc. */
kc_status kc_path_check_common(kc_path_method m, kc_path_blend b, kc_path_spline_end e, int n, int has_qd,
                               int has_qdd, const kc_real *t, kc_real t_acc, kc_real dt);

/* Empty knots of a method: n knots of dimension dim, every value 0. */
void kc_path_knots_init(kc_path_knots *K, kc_path_method m, kc_path_blend b, kc_path_spline_end e, int n, int dim,
                        kc_real t_acc, kc_real dt);

/* The caller's knot times t[0..n). */
void kc_path_given_times(kc_path_knots *K, const kc_real *t);

/* Knot i from the rows q, v and a of K->dim values each (v, a: NULL when
 * not given, leaving K's zeros); KC_E_ARG when a value is not finite. */
kc_status kc_path_load_knot(kc_path_knots *K, int i, const kc_real *q, const kc_real *v, const kc_real *a);

/* Times from the limits when seg is not NULL (seg[i] the trapezoid time of
 * segment i, ratio the largest v/a for the blend rule of kinctl/path.h),
 * else the given ones already in K; then validates times, t_acc and
 * derived data, stretches if the limits ask for it, and checks every
 * piece. */
kc_status kc_path_prepare(kc_path_knots *K, const kc_path_limits *L, const kc_real *seg, kc_real ratio);

/* Writes the checked plan. */
void kc_path_commit(kc_path *path, const kc_path_knots *K);

#endif /* KINCTL_PATH_INTERNAL_H */
