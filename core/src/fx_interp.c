/* SPDX-License-Identifier: BSD-3-Clause */
/* fx_interp.c - joint moves and lines evaluated at integer ticks in fixed
 * point (kinctl/fx.h): integer arithmetic only, like fx.c. */
#include "kinctl/fx.h"

/* x s in Q2.30, x an unsigned value with xbits fraction bits: x m 2^-(shift
 * + xbits - 30), rounded, with x m (up to 2^95) kept in 96 bits as
 * hi 2^32 + lo. The result must fit 63 bits (u and its pieces are <= 2). */
static int64_t mul_scaled(uint64_t x, kc_fx_scaled s, int xbits)
{
    int sh = s.shift + xbits - KC_FX_ROT_BITS;
    uint64_t lo = (x & 0xFFFFFFFFu) * s.m;
    uint64_t hi = (x >> 32) * s.m + (lo >> 32); /* < 2^64: x < 2^63, m < 2^31 */
    lo &= 0xFFFFFFFFu;
    if (sh >= 64)
        return 0;
    if (sh > 32) {
        hi += (uint64_t)1 << (sh - 33); /* rounding at bit sh - 1 of the whole */
        return (int64_t)(hi >> (sh - 32));
    }
    if (sh == 32)
        return (int64_t)(hi + (lo >> 31));
    /* Below 32 the high word moves up by 32 - sh (the result fits). */
    if (sh <= 0)
        return (int64_t)((hi << 32 | lo) << -sh);
    return (int64_t)((hi << (32 - sh)) + ((lo + ((uint64_t)1 << (sh - 1))) >> sh));
}

/* u at tick k < ticks, Q2.30 (kinctl/fx.h's kc_fx_ramp). */
static int64_t ramp_eval(const kc_fx_ramp *ramp, int64_t k)
{
    int64_t kq = k * ((int64_t)1 << 32); /* k in Q32.32: k < 2^24 */
    if (kq < ramp->k1)
        return mul_scaled((uint64_t)(k * k), ramp->a, 0);
    if (kq < ramp->k2)
        return ramp->uc + mul_scaled((uint64_t)(kq - ramp->k1), ramp->v, 32);
    /* Backwards from the end, as profile.c: b (kT - k)^2 as (b r) r. b r
     * (r in Q32.32) comes out in Q62 and is renormalised into a 31-bit
     * factor for the second product. */
    uint64_t r = (uint64_t)(ramp->kT - kq);
    kc_fx_scaled b62 = {ramp->b.m, ramp->b.shift - 32};
    uint64_t w = (uint64_t)mul_scaled(r, b62, 32);
    kc_fx_scaled br = {(uint32_t)w, 62};
    int extra = 0;
    while ((w >> extra) >= ((uint64_t)1 << 31))
        extra++;
    if (extra > 0) {
        br.m = (uint32_t)((w + ((uint64_t)1 << (extra - 1))) >> extra);
        br.shift = 62 - extra;
    }
    return KC_FX_ONE_ROT - mul_scaled(r, br, 32);
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
    if (k >= move->ramp.ticks) {
        for (int i = 0; i < move->n; i++)
            q_fx[i] = move->q1[i];
        return KC_DONE;
    }
    int64_t u = ramp_eval(&move->ramp, k);
    for (int i = 0; i < move->n; i++)
        q_fx[i] = along(move->q0[i], move->dq[i], u);
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
