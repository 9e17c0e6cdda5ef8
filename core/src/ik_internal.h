/* SPDX-License-Identifier: BSD-3-Clause */
/* ik_internal.h - the damped least-squares step of kinctl/ik.h: the
 * problem it solves and its kernel, which ik.c instantiates per task size
 * with its loops unrolled and, in code built for size, ik_rolled.c once for
 * the 3- and 5-row tasks with its loops rolled. Private to the core. */
#ifndef KINCTL_IK_INTERNAL_H
#define KINCTL_IK_INTERNAL_H

#include "kinctl/ik.h"
#include "linalg_internal.h"

/* The rows of a task: 6 (full), 3 (position), 5 (axis). */
static inline int kc_ik_task_rows(kc_ik_mask mask)
{
    return mask == KC_IK_MASK_FULL ? 6 : (mask == KC_IK_MASK_POSITION ? 3 : 5);
}

typedef struct kc_ik_problem {
    const kc_chain *chain;
    const kc_ik_cfg *cfg;
    int n, r;
    int singular_damping; /* add the Nakamura-Hanafusa term (online step) */
    kc_real lo[KC_MAX_JOINTS], hi[KC_MAX_JOINTS];
    /* The redundancy objective's, set only when the task leaves a null
     * space (n > r): nothing else reads them. */
    kc_real rest[KC_MAX_JOINTS], range[KC_MAX_JOINTS];
} kc_ik_problem;

/* Gradient of the redundancy objective H (see ik.h). */
static inline void kc_ik_null_gradient(const kc_ik_problem *p, const kc_real *q, kc_real *g)
{
    for (int j = 0; j < p->n; j++) {
        kc_real range = p->range[j];
        kc_real gj = (q[j] - p->rest[j]) / (range * range);
        kc_real margin = p->cfg->limit_margin * range;
        if (margin > KC_R(0.0)) {
            /* Cubic barrier inside the margin m, d^3 / (6 m^3) at depth d:
             * its gradient d^2 / (2 m^3) starts from 0 with slope 0, so the
             * null-space velocity's rate (the gradient's slope times qd)
             * rises from 0 as a joint enters the margin instead of jumping
             * to its bound within a few mrad (see kinctl/ik.h). */
            kc_real over_hi = q[j] - (p->hi[j] - margin), over_lo = (p->lo[j] + margin) - q[j];
            kc_real k = KC_R(0.5) / (margin * margin * margin);
            if (over_hi > KC_R(0.0))
                gj += k * over_hi * over_hi;
            if (over_lo > KC_R(0.0))
                gj -= k * over_lo * over_lo;
        }
        g[j] = gj;
    }
}

/*
 * The damped least-squares step with the frozen joints' columns removed:
 *     dq = Jt^T A^-1 u + (z - Jt^T A^-1 Jt z),  A = Jt Jt^T + lambda^2 I,
 * task part first, then z = -grad H projected into the null space (on
 * redundant tasks). The null part is bounded by half of null_bound on its own
 * (it does not move the tool, so shrinking it never slows the task). lambda2
 * is the error damping; the singularity damping is added here. Returns the
 * manipulability of the unfrozen task Jacobian.
 */
KC_ALWAYS_INLINE kc_real kc_ik_dls_kernel(const kc_ik_problem *p, kc_real jt[6][KC_MAX_JOINTS], const kc_real *u,
                                        kc_real lambda2, kc_real null_scale, kc_real null_bound, const kc_real *q,
                                        const uint8_t *frozen, kc_real *dq, const int r)
{
    int n = p->n;
    kc_real a[KC_LINALG_MAX][KC_LINALG_MAX];
    kc_real z[KC_MAX_JOINTS];
    kc_real y[KC_LINALG_MAX], yz[KC_LINALG_MAX];
    kc_real jf[6][KC_MAX_JOINTS];
    int redundant = n > r && null_scale > KC_R(0.0);
    int any_frozen = 0;

    /* Frozen joints: work on a copy with their columns zeroed, so the loops
     * below stay branch-free. */
    for (int j = 0; j < n; j++)
        any_frozen |= frozen[j];
    if (any_frozen) {
        for (int i = 0; i < r; i++)
            for (int j = 0; j < n; j++)
                jf[i][j] = frozen[j] ? KC_R(0.0) : jt[i][j];
        jt = jf;
    }
    if (redundant) {
        kc_ik_null_gradient(p, q, z);
        for (int j = 0; j < n; j++)
            z[j] = frozen[j] ? KC_R(0.0) : -null_scale * z[j];
    }
    /* A = Jt Jt^T and Jt z, column by column: the r x r work inside is of
     * constant size and unrolls. */
    KC_UNROLL
    for (int i = 0; i < r; i++) {
        KC_UNROLL
        for (int k = 0; k <= i; k++)
            a[i][k] = KC_R(0.0);
        y[i] = u[i];
        yz[i] = KC_R(0.0);
    }
    for (int j = 0; j < n; j++) {
        kc_real c[6];
        KC_UNROLL
        for (int i = 0; i < r; i++)
            c[i] = jt[i][j];
        KC_UNROLL
        for (int i = 0; i < r; i++) {
            KC_UNROLL
            for (int k = 0; k <= i; k++)
                a[i][k] += c[i] * c[k];
        }
        if (redundant) {
            KC_UNROLL
            for (int i = 0; i < r; i++)
                yz[i] += c[i] * z[j];
        }
    }
    /* Only the lower triangle of A is filled: the factorisation and the
     * solves read no other. */

    kc_real damp = lambda2, w = KC_REAL_MAX;
    if (p->singular_damping) {
        /* Manipulability sqrt(det(J J^T)) from an undamped factorisation. */
        kc_real l[KC_LINALG_MAX][KC_LINALG_MAX], det = KC_R(0.0);
        KC_UNROLL
        for (int i = 0; i < r; i++) {
            KC_UNROLL
            for (int k = 0; k <= i; k++)
                l[i][k] = a[i][k];
        }
        kc_cholesky(l, r, &det);
        w = kc_sqrt(kc_max(det, KC_R(0.0)));
        if (w < p->cfg->manip_threshold) {
            kc_real f = KC_R(1.0) - w / p->cfg->manip_threshold;
            damp += p->cfg->damping_max * p->cfg->damping_max * f * f;
        }
    }
    /* A floor keeps the factorisation defined at an exact singularity. */
    damp = kc_max(damp, KC_REAL_EPS);
    for (int i = 0; i < r; i++)
        a[i][i] += damp;
    if (!kc_cholesky(a, r, NULL)) {
        for (int j = 0; j < n; j++)
            dq[j] = KC_R(0.0);
        return KC_R(0.0);
    }
    kc_cholesky_solve(a, r, y);
    for (int j = 0; j < n; j++) {
        kc_real t = KC_R(0.0);
        KC_UNROLL
        for (int i = 0; i < r; i++)
            t += jt[i][j] * y[i];
        dq[j] = t;
    }
    if (redundant) {
        kc_cholesky_solve(a, r, yz);
        kc_real null_max = KC_R(0.0);
        for (int j = 0; j < n; j++) {
            kc_real t = KC_R(0.0);
            for (int i = 0; i < r; i++)
                t += jt[i][j] * yz[i];
            z[j] -= t; /* zero for frozen joints: their column is zero */
            null_max = kc_max(null_max, kc_fabs(z[j]));
        }
        kc_real ns = null_max > KC_R(0.5) * null_bound ? KC_R(0.5) * null_bound / null_max : KC_R(1.0);
        for (int j = 0; j < n; j++)
            dq[j] += ns * z[j];
    }
    return w;
}

/* The kernel with the task size p->r a variable and its loops rolled
 * (ik_rolled.c): the same operations in the same order as an unrolled
 * instance, so the same bits. */
kc_real kc_ik_dls_rolled(const kc_ik_problem *p, kc_real jt[6][KC_MAX_JOINTS], const kc_real *u, kc_real lambda2,
                         kc_real null_scale, kc_real null_bound, const kc_real *q, const uint8_t *frozen, kc_real *dq);

#endif /* KINCTL_IK_INTERNAL_H */
