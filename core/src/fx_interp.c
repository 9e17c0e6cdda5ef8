/* fx_interp.c - a joint move evaluated at integer ticks in fixed point
 * (kinctl/fx.h): integer arithmetic only, like fx.c. */
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

kc_status kc_fx_joint_eval(const kc_fx_joint_move *move, int64_t k, int32_t *q_fx)
{
    if (move == NULL || q_fx == NULL || k < 0)
        return KC_E_ARG;
    if (k >= move->ticks) {
        for (int i = 0; i < move->n; i++)
            q_fx[i] = move->q1[i];
        return KC_DONE;
    }
    int64_t kq = k * ((int64_t)1 << 32); /* k in Q32.32: k < 2^24 */
    int64_t u;
    if (kq < move->k1) {
        u = mul_scaled((uint64_t)(k * k), move->a, 0);
    } else if (kq < move->k2) {
        u = move->uc + mul_scaled((uint64_t)(kq - move->k1), move->v, 32);
    } else {
        /* Backwards from the end, as profile.c: b (kT - k)^2 as (b r) r.
         * b r (r in Q32.32) comes out in Q62 and is renormalised into a
         * 31-bit factor for the second product. */
        uint64_t r = (uint64_t)(move->kT - kq);
        kc_fx_scaled b62 = {move->b.m, move->b.shift - 32};
        uint64_t w = (uint64_t)mul_scaled(r, b62, 32);
        kc_fx_scaled br = {(uint32_t)w, 62};
        int extra = 0;
        while ((w >> extra) >= ((uint64_t)1 << 31))
            extra++;
        if (extra > 0) {
            br.m = (uint32_t)((w + ((uint64_t)1 << (extra - 1))) >> extra);
            br.shift = 62 - extra;
        }
        u = KC_FX_ONE_ROT - mul_scaled(r, br, 32);
    }
    for (int i = 0; i < move->n; i++)
        q_fx[i] = move->q0[i] + (int32_t)((move->dq[i] * u + ((int64_t)1 << 29)) >> KC_FX_ROT_BITS);
    return KC_OK;
}
