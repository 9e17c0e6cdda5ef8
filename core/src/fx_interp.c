/* SPDX-License-Identifier: BSD-3-Clause */
/* fx_interp.c - joint moves and lines evaluated at integer ticks in fixed
 * point (kinctl/fx.h): integer arithmetic only, like fx.c. */
#include "kinctl/fx.h"

/* x |c| in Q23.40, rounded: x < 2^48 an integer, |c| = m 2^-shift with
 * m < 2^32; x m (below 2^80) in 96 bits as hi 2^32 + lo. The result fits
 * 63 bits (a term of u is a few at most: kinctl/fx.h). */
static int64_t term(uint64_t x, kc_fx_scaled c)
{
    int sh = c.shift - KC_FX_RAMP_BITS;
    uint64_t lo = (x & 0xFFFFFFFFu) * c.m;
    uint64_t hi = (x >> 32) * c.m + (lo >> 32); /* < 2^49 */
    lo &= 0xFFFFFFFFu;
    if (sh >= 96)
        return 0; /* below 2^-16 of the last bit */
    if (sh > 32)
        return (int64_t)((hi + ((uint64_t)1 << (sh - 33))) >> (sh - 32)); /* rounding at bit sh - 1 of the whole */
    if (sh == 32)
        return (int64_t)(hi + (lo >> 31));
    if (sh <= 0)
        return (int64_t)((hi << 32 | lo) << -sh);
    /* Below 32 the high word moves up by 32 - sh (the result fits). */
    return (int64_t)((hi << (32 - sh)) + ((lo + ((uint64_t)1 << (sh - 1))) >> sh));
}

/* c m (m < 2^24) as a factor of at most 32 bits: the product (below 2^55)
 * rounded to its 31 leading bits. */
static kc_fx_scaled times(kc_fx_scaled c, uint32_t m)
{
    uint64_t w = (uint64_t)c.m * m;
    int e = 0;
    for (int b = 16; b > 0; b >>= 1) /* the largest e with w >> e >= 2^31, if any */
        if ((w >> (e + b)) >= ((uint64_t)1 << 31))
            e += b;
    if ((w >> e) >= ((uint64_t)1 << 31))
        e++;
    kc_fx_scaled r = {(uint32_t)((w + (e > 0 ? (uint64_t)1 << (e - 1) : 0u)) >> e), c.shift - e};
    return r;
}

/* u at tick k < ticks, Q2.30 (kinctl/fx.h's kc_fx_ramp). */
static int64_t ramp_eval(const kc_fx_ramp *r, int64_t k)
{
    int i = 0;
    while (i < r->n - 1 && k >= r->k0[i + 1])
        i++;
    uint32_t m = (uint32_t)(k - r->k0[i]);
    uint64_t m2 = (uint64_t)m * m;
    const kc_fx_scaled *c = r->c[i];
    int64_t t[3] = {term(m, c[0]), term(m2, c[1]), c[2].m ? term(m2, times(c[2], m)) : 0};
    int64_t u = r->u0[i];
    for (int d = 0; d < 3; d++)
        u += (r->neg[i] >> d & 1u) ? -t[d] : t[d];
    const int drop = KC_FX_RAMP_BITS - KC_FX_ROT_BITS;
    return (u + ((int64_t)1 << (drop - 1))) >> drop;
}

/* a + d u, rounded: d in a's format (64 bits), u in Q2.30. d u alone may
 * exceed the format (a move across more than half its range): the sum is
 * formed in 64 bits, and it lies between the segment's ends. */
static int32_t along(int32_t a, int64_t d, int64_t u)
{
    return (int32_t)(a + ((d * u + ((int64_t)1 << 29)) >> KC_FX_ROT_BITS));
}

kc_status kc_fx_joint_eval(const kc_fx_joint_move *move, int64_t k, int32_t *q_fx)
{
    if (move == NULL || q_fx == NULL || k < 0)
        return KC_E_ARG;
    if (k >= move->ramp[0].ticks) {
        for (int i = 0; i < move->n; i++)
            q_fx[i] = move->q1[i];
        return KC_DONE;
    }
    int64_t u = 0;
    for (int i = 0; i < move->n; i++) {
        if (i == 0 || move->per_joint)
            u = ramp_eval(&move->ramp[i], k);
        q_fx[i] = along(move->q0[i], move->dq[i], u);
    }
    return KC_OK;
}

/* x y of Q2.30 values, rounded (x, y: at most 2 in magnitude). */
static int32_t mul30(int64_t x, int64_t y) { return (int32_t)((x * y + ((int64_t)1 << 29)) >> KC_FX_ROT_BITS); }

/* Hamilton product a b of Q2.30 quaternions (w x y z), one rounding each. */
static void quat_mul(const int32_t a[4], const int32_t b[4], int32_t out[4])
{
    int64_t w = (int64_t)a[0] * b[0] - (int64_t)a[1] * b[1] - (int64_t)a[2] * b[2] - (int64_t)a[3] * b[3];
    int64_t x = (int64_t)a[0] * b[1] + (int64_t)a[1] * b[0] + (int64_t)a[2] * b[3] - (int64_t)a[3] * b[2];
    int64_t y = (int64_t)a[0] * b[2] - (int64_t)a[1] * b[3] + (int64_t)a[2] * b[0] + (int64_t)a[3] * b[1];
    int64_t z = (int64_t)a[0] * b[3] + (int64_t)a[1] * b[2] - (int64_t)a[2] * b[1] + (int64_t)a[3] * b[0];
    const int64_t half = (int64_t)1 << 29;
    out[0] = (int32_t)((w + half) >> KC_FX_ROT_BITS);
    out[1] = (int32_t)((x + half) >> KC_FX_ROT_BITS);
    out[2] = (int32_t)((y + half) >> KC_FX_ROT_BITS);
    out[3] = (int32_t)((z + half) >> KC_FX_ROT_BITS);
}

kc_status kc_fx_line_eval(const kc_fx_line *line, int64_t k, int32_t p[3], int32_t q[4])
{
    if (line == NULL || p == NULL || q == NULL || k < 0)
        return KC_E_ARG;
    if (k >= line->ramp.ticks) {
        for (int i = 0; i < 3; i++)
            p[i] = line->p2[i];
        for (int i = 0; i < 4; i++)
            q[i] = line->q2[i];
        return KC_DONE;
    }
    int64_t u = ramp_eval(&line->ramp, k);
    for (int i = 0; i < 3; i++)
        p[i] = along(line->p1[i], line->dp[i], u);
    int32_t rel[4];
    if (line->slerp) {
        int32_t s, c;
        kc_fx_sincos(along(0, line->half_angle, u), &s, &c);
        rel[0] = c;
        for (int i = 0; i < 3; i++)
            rel[i + 1] = mul30(s, line->axis[i]);
    } else {
        /* kinctl/interp.h's line_rotation: the turn about (kx, ky, 0) by
         * theta u, then about z by phi u. */
        int32_t s1, c1, s2, c2;
        kc_fx_sincos(along(0, line->half_theta, u), &s1, &c1);
        kc_fx_sincos(along(0, line->half_phi, u), &s2, &c2);
        int64_t kx = line->kx, ky = line->ky;
        rel[0] = mul30(c1, c2);
        rel[1] = mul30(s1, (kx * c2 + ky * s2 + ((int64_t)1 << 29)) >> KC_FX_ROT_BITS);
        rel[2] = mul30(s1, (ky * c2 - kx * s2 + ((int64_t)1 << 29)) >> KC_FX_ROT_BITS);
        rel[3] = mul30(c1, s2);
    }
    quat_mul(line->q1, rel, q);
    return KC_OK;
}
