/* SPDX-License-Identifier: BSD-3-Clause */
/* fx.c - fixed-point FK and Jacobian (kinctl/fx.h): integer arithmetic
 * only, the walk of fk.c over elementary transforms. No float type or
 * operation may appear here (mcu/check_integer_only.sh). */
#include "kinctl/fx.h"

/* x / 2^n rounded to nearest, ties up (arithmetic shift). */
static inline int32_t round_shift(int64_t x, int n)
{
    return (int32_t)((x + ((int64_t)1 << (n - 1))) >> n);
}

/* Q2.30 times Q2.30 or Q8.24: the second operand's format. */
static inline int32_t mul_rot(int32_t a, int32_t b) { return round_shift((int64_t)a * b, KC_FX_ROT_BITS); }

/*
 * Sine and cosine. The angle (Q3.28 rad) becomes a fraction of a turn in
 * unsigned Q0.32, which wraps by itself: turns = q 16 / (2 pi) (times 2^28
 * in fixed point). A quadrant and the angle x in [0, pi/4] from its nearer
 * end come out of the top bits; sin x and cos x are their Taylor series by
 * Horner through x^11 and x^12, whose truncation ((pi/4)^13 / 13! = 8e-12)
 * is far below the roundings (about 2^-30 per step).
 */
/* 2^28 16 / (2 pi) = 683565275.5764316: the integer part, and the
 * fraction in Q16 (the constant to 2e-14 relative, so |q| = 8 rad turns
 * with an error far below the Q0.32 turn's own 1.5e-9 rad). */
#define TURNS_PER_RAD_Q28 683565275LL
#define TURNS_PER_RAD_Q28_FRAC_Q16 37777LL
#define PI_2_Q32 6746518852LL       /* 2^32 pi / 2 */

/* angle in Q3.28 widened to 64 bits (|angle| < 2^33: a joint value plus
 * its offset), so that the product with TURNS_PER_RAD_Q28 fits. */
static void sincos_q28(int64_t angle, int32_t *s, int32_t *c)
{
    int64_t scaled = angle * TURNS_PER_RAD_Q28 + ((angle * TURNS_PER_RAD_Q28_FRAC_Q16 + (1 << 15)) >> 16);
    uint32_t u = (uint32_t)((scaled + ((int64_t)1 << 27)) >> 28);
    unsigned quadrant = u >> 30;
    uint32_t f = u & 0x3FFFFFFFu; /* [0, 1/4 turn) in 2^-32 turns */
    int swap = f > 0x20000000u;
    if (swap)
        f = 0x40000000u - f;
    /* x = f 2 pi / 2^32 rad in Q2.30: f pi / 2, with pi / 2 in Q32. */
    int32_t x = round_shift((int64_t)f * PI_2_Q32, 32);
    int32_t z = mul_rot(x, x);
    int32_t ps = KC_FX_ONE_ROT, pc = KC_FX_ONE_ROT;
    static const int32_t sin_div[5] = {110, 72, 42, 20, 6}, cos_div[6] = {132, 90, 56, 30, 12, 2};
    for (int i = 0; i < 5; i++)
        ps = KC_FX_ONE_ROT - mul_rot(z, ps) / sin_div[i];
    for (int i = 0; i < 6; i++)
        pc = KC_FX_ONE_ROT - mul_rot(z, pc) / cos_div[i];
    int32_t sx = mul_rot(x, ps), cx = pc;
    if (swap) {
        int32_t t = sx;
        sx = cx;
        cx = t;
    }
    switch (quadrant) {
    case 0: *s = sx; *c = cx; break;
    case 1: *s = cx; *c = -sx; break;
    case 2: *s = -sx; *c = -cx; break;
    default: *s = -cx; *c = sx; break;
    }
}

void kc_fx_sincos(int32_t angle, int32_t *s, int32_t *c) { sincos_q28(angle, s, c); }

/* Columns i and j of R turn by (c, s) (fk.c's turn). */
static void turn(int32_t m[3][3], int i, int j, int32_t c, int32_t s)
{
    for (int r = 0; r < 3; r++) {
        int64_t a = m[r][i], b = m[r][j];
        m[r][i] = round_shift(c * a + s * b, KC_FX_ROT_BITS);
        m[r][j] = round_shift(c * b - s * a, KC_FX_ROT_BITS);
    }
}

static void quarter_turn(int32_t m[3][3], int i, int j, int sign)
{
    for (int r = 0; r < 3; r++) {
        int32_t a = m[r][i], b = m[r][j];
        m[r][i] = sign > 0 ? b : -b;
        m[r][j] = sign > 0 ? -a : a;
    }
}

/* The origin moves by v (Q8.24) along column k. */
static void shift(int32_t m[3][3], int32_t t[3], int k, int32_t v)
{
    for (int r = 0; r < 3; r++)
        t[r] += mul_rot(m[r][k], v);
}

/* a b of two poses. */
static void pose_mul(const kc_fx_pose *a, const kc_fx_pose *b, kc_fx_pose *dest)
{
    kc_fx_pose p;
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++) {
            int64_t sum = 0;
            for (int i = 0; i < 3; i++)
                sum += (int64_t)a->R[r][i] * b->R[i][k];
            p.R[r][k] = round_shift(sum, KC_FX_ROT_BITS);
        }
        int64_t sum = 0;
        for (int i = 0; i < 3; i++)
            sum += (int64_t)a->R[r][i] * b->t[i];
        p.t[r] = a->t[r] + round_shift(sum, KC_FX_ROT_BITS);
    }
    *dest = p;
}

/* The walk of fk.c: each joint's world axis into rows 3-5 of its column
 * and its origin into origin[j] when jac != NULL. */
static void walk(const kc_fx_chain *fx, const int32_t *q, kc_fx_jacobian *jac, int32_t origin[][3],
                 kc_fx_pose *tool)
{
    kc_fx_pose cur = fx->base;
    int32_t(*m)[3] = cur.R;
    int32_t *t = cur.t;
    for (int e = 0; e < fx->n_elements; e++) {
        const kc_fx_element *el = &fx->elements[e];
        int32_t c = el->c, s = el->s, v = el->value;
        int code = el->code;
        if (code <= KC_CODE_TZ_JOINT) {
            int j = (int)el->joint;
            code += KC_CODE_RX - KC_CODE_RX_JOINT;
            if (code <= KC_CODE_RZ)
                sincos_q28((int64_t)q[j] + fx->offset[j], &s, &c);
            else
                v = q[j] + fx->offset[j];
            if (jac != NULL) {
                int k = code <= KC_CODE_RZ ? code - KC_CODE_RX : code - KC_CODE_TX;
                for (int r = 0; r < 3; r++) {
                    jac->m[3 + r][j] = m[r][k];
                    origin[j][r] = t[r];
                }
            }
        } else if (el->quarter != 0) {
            code += 16;
        }
        switch (code) {
        case KC_CODE_RX: turn(m, 1, 2, c, s); break;
        case KC_CODE_RY: turn(m, 2, 0, c, s); break;
        case KC_CODE_RZ: turn(m, 0, 1, c, s); break;
        case KC_CODE_RX + 16: quarter_turn(m, 1, 2, el->quarter); break;
        case KC_CODE_RY + 16: quarter_turn(m, 2, 0, el->quarter); break;
        case KC_CODE_RZ + 16: quarter_turn(m, 0, 1, el->quarter); break;
        case KC_CODE_TX: shift(m, t, 0, v); break;
        case KC_CODE_TY: shift(m, t, 1, v); break;
        default: shift(m, t, 2, v); break;
        }
    }
    if (fx->tool_identity)
        *tool = cur;
    else
        pose_mul(&cur, &fx->tool, tool);
}

kc_status kc_fx_fk_eval(const kc_fx_chain *fx, const int32_t *q_fx, kc_fx_pose *tool)
{
    if (fx == NULL || q_fx == NULL || tool == NULL)
        return KC_E_ARG;
    walk(fx, q_fx, NULL, NULL, tool);
    return KC_OK;
}

kc_status kc_fx_jacobian_eval(const kc_fx_chain *fx, const int32_t *q_fx, kc_fx_jacobian *jac, kc_fx_pose *tool)
{
    int32_t origin[KC_MAX_JOINTS][3] = {{0}}; /* walk fills the rows of the joints */
    kc_fx_pose end;
    if (fx == NULL || q_fx == NULL || jac == NULL)
        return KC_E_ARG;
    walk(fx, q_fx, jac, origin, &end);
    for (int j = 0; j < fx->n_joints; j++) {
        int32_t zx = jac->m[3][j], zy = jac->m[4][j], zz = jac->m[5][j];
        if (fx->revolute[j]) {
            /* v = z x (p_tool - p_j): Q2.30 by Q8.24, summed in int64. */
            int64_t rx = end.t[0] - origin[j][0], ry = end.t[1] - origin[j][1], rz = end.t[2] - origin[j][2];
            jac->m[0][j] = round_shift(zy * rz - zz * ry, KC_FX_ROT_BITS);
            jac->m[1][j] = round_shift(zz * rx - zx * rz, KC_FX_ROT_BITS);
            jac->m[2][j] = round_shift(zx * ry - zy * rx, KC_FX_ROT_BITS);
        } else {
            /* The axis as a unitless Q8.24 column; no rotation. */
            jac->m[0][j] = round_shift(zx, KC_FX_ROT_BITS - KC_FX_POS_BITS);
            jac->m[1][j] = round_shift(zy, KC_FX_ROT_BITS - KC_FX_POS_BITS);
            jac->m[2][j] = round_shift(zz, KC_FX_ROT_BITS - KC_FX_POS_BITS);
            jac->m[3][j] = jac->m[4][j] = jac->m[5][j] = 0;
        }
    }
    if (tool != NULL)
        *tool = end;
    return KC_OK;
}
