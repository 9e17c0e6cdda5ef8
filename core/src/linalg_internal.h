/* SPDX-License-Identifier: BSD-3-Clause */
/* linalg_internal.h - the small dense linear algebra the solvers need: a
 * Cholesky factorisation of an r x r symmetric positive definite matrix
 * (r <= 6) and the solve with it. Private to the core. */
#ifndef KINCTL_LINALG_INTERNAL_H
#define KINCTL_LINALG_INTERNAL_H

#include "kinctl/real.h"

#define KC_LINALG_MAX 6

/* Inlining that the compiler must not decline: the solvers instantiate a
 * kernel once per task size so its loops have constant bounds. */
#if defined(__GNUC__) || defined(__clang__)
#define KC_ALWAYS_INLINE static inline __attribute__((always_inline))
#else
#define KC_ALWAYS_INLINE static inline
#endif

/* Complete unrolling of a loop with a small constant trip count, which -O2
 * does not do on its own for nested triangular loops. A file that defines
 * KC_LINALG_ROLLED before including this one gets plain loops (for a trip
 * count that is not a constant, where the pragma would only add copies). */
#if defined(KC_LINALG_ROLLED)
#define KC_UNROLL
#elif defined(__clang__)
#define KC_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define KC_UNROLL _Pragma("GCC unroll 8")
#else
#define KC_UNROLL
#endif

/* In place: the lower triangle of a becomes L with a = L L^T. Returns 0 when
 * a pivot is not positive (a is then not positive definite), else 1. *det
 * receives det(a) = prod(L_ii)^2 when det is not NULL. */
KC_ALWAYS_INLINE int kc_cholesky(kc_real a[KC_LINALG_MAX][KC_LINALG_MAX], int r, kc_real *det)
{
    kc_real d = KC_R(1.0);
    KC_UNROLL
    for (int j = 0; j < r; j++) {
        kc_real s = a[j][j];
        KC_UNROLL
        for (int k = 0; k < j; k++)
            s -= a[j][k] * a[j][k];
        if (!(s > KC_R(0.0))) {
            if (det != NULL)
                *det = KC_R(0.0);
            return 0;
        }
        d *= s;
        kc_real ljj = kc_sqrt(s);
        a[j][j] = ljj;
        kc_real inv = KC_R(1.0) / ljj;
        KC_UNROLL
        for (int i = j + 1; i < r; i++) {
            kc_real t = a[i][j];
            KC_UNROLL
            for (int k = 0; k < j; k++)
                t -= a[i][k] * a[j][k];
            a[i][j] = t * inv;
        }
    }
    if (det != NULL)
        *det = d;
    return 1;
}

/* Solves L L^T x = b in place in b, with L from kc_cholesky. */
KC_ALWAYS_INLINE void kc_cholesky_solve(kc_real l[KC_LINALG_MAX][KC_LINALG_MAX], int r, kc_real b[KC_LINALG_MAX])
{
    KC_UNROLL
    for (int i = 0; i < r; i++) {
        kc_real t = b[i];
        KC_UNROLL
        for (int k = 0; k < i; k++)
            t -= l[i][k] * b[k];
        b[i] = t / l[i][i];
    }
    /* Counted down from r - 1 with i >= 0 as the test: clang unrolls only
     * this form (i-- > 0 defeats the unroll pragma, an error with -Werror). */
    KC_UNROLL
    for (int i = r - 1; i >= 0; i--) {
        kc_real t = b[i];
        KC_UNROLL
        for (int k = i + 1; k < r; k++)
            t -= l[k][i] * b[k];
        /* The analyzer lets i wrap past INT_MIN; it runs r - 1 .. 0. */
        b[i] = t / l[i][i]; /* NOLINT(clang-analyzer-core.UndefinedBinaryOperatorResult) */
    }
}

#endif /* KINCTL_LINALG_INTERNAL_H */
