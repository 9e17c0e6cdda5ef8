/* SPDX-License-Identifier: BSD-3-Clause */
/* fx_chain.c - conversions between kinctl's floating-point types and the
 * fixed-point formats of kinctl/fx.h: done once when a chain is set up,
 * outside the cycle. */
#include "kinctl/fx.h"

#include <string.h>

/* x 2^bits rounded to nearest into *out; 0 when out of int32_t's range. */
static int to_fixed(kc_real x, int bits, int32_t *out)
{
    kc_real scaled = x * (kc_real)((int32_t)1 << bits);
    kc_real r = kc_floor(scaled + KC_R(0.5));
    /* 2^31 - 128 keeps the float build's rounding of the bound inside. */
    if (!(r > KC_R(-2147483520.0) && r < KC_R(2147483520.0)))
        return 0;
    *out = (int32_t)r;
    return 1;
}

static int pose_to_fixed(const kc_pose *p, kc_fx_pose *dest)
{
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++)
            if (!to_fixed(p->R.m[r][k], KC_FX_ROT_BITS, &dest->R[r][k]))
                return 0;
        if (!to_fixed(p->t.v[r], KC_FX_POS_BITS, &dest->t[r]))
            return 0;
    }
    return 1;
}

kc_status kc_fx_chain_init(kc_fx_chain *fx, const kc_chain *chain)
{
    if (fx == NULL || chain == NULL || kc_chain_check(chain) != KC_OK)
        return KC_E_ARG;
    kc_fx_chain out;
    memset(&out, 0, sizeof out);
    out.n_joints = chain->n_joints;
    out.n_elements = chain->n_elements;
    for (int j = 0; j < chain->n_joints; j++) {
        out.revolute[j] = chain->joints[j].type == KC_JOINT_REVOLUTE;
        int bits = out.revolute[j] ? KC_FX_ANGLE_BITS : KC_FX_POS_BITS;
        if (!to_fixed(chain->joints[j].offset, bits, &out.offset[j]))
            return KC_E_CAPACITY;
    }
    for (int e = 0; e < chain->n_elements; e++) {
        const kc_element *el = &chain->elements[e];
        kc_fx_element *fe = &out.elements[e];
        fe->code = el->code;
        fe->joint = el->joint;
        fe->quarter = el->quarter;
        if (el->code >= KC_CODE_TX && !to_fixed(el->value, KC_FX_POS_BITS, &fe->value))
            return KC_E_CAPACITY;
        if (el->code >= KC_CODE_RX && el->code <= KC_CODE_RZ &&
            (!to_fixed(el->c, KC_FX_ROT_BITS, &fe->c) || !to_fixed(el->s, KC_FX_ROT_BITS, &fe->s)))
            return KC_E_CAPACITY;
    }
    if (!pose_to_fixed(&chain->base, &out.base) || !pose_to_fixed(&chain->tool, &out.tool))
        return KC_E_CAPACITY;
    out.tool_identity = 1;
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++)
            if (out.tool.R[r][k] != (r == k ? KC_FX_ONE_ROT : 0))
                out.tool_identity = 0;
        if (out.tool.t[r] != 0)
            out.tool_identity = 0;
    }
    *fx = out;
    return KC_OK;
}

kc_status kc_fx_q_from_real(const kc_fx_chain *fx, const kc_real *q, int32_t *q_fx)
{
    int32_t out[KC_MAX_JOINTS];
    if (fx == NULL || q == NULL || q_fx == NULL)
        return KC_E_ARG;
    for (int j = 0; j < fx->n_joints; j++) {
        int bits = fx->revolute[j] ? KC_FX_ANGLE_BITS : KC_FX_POS_BITS;
        if (!kc_isfinite(q[j]) || !to_fixed(q[j], bits, &out[j]))
            return KC_E_ARG;
    }
    memcpy(q_fx, out, sizeof(int32_t) * (size_t)fx->n_joints);
    return KC_OK;
}

void kc_fx_pose_to_real(const kc_fx_pose *p, kc_pose *dest)
{
    const kc_real rot = KC_R(1.0) / (kc_real)KC_FX_ONE_ROT, pos = KC_R(1.0) / (kc_real)((int32_t)1 << KC_FX_POS_BITS);
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++)
            dest->R.m[r][k] = (kc_real)p->R[r][k] * rot;
        dest->t.v[r] = (kc_real)p->t[r] * pos;
    }
}

/* x > 0 as m 2^-shift with m in [2^30, 2^31) (kinctl/fx.h); 0 for x = 0. */
static int scaled_of(kc_real x, kc_fx_scaled *out)
{
    int shift = 0;
    if (!(x >= KC_R(0.0)) || !kc_isfinite(x))
        return 0;
    out->m = 0;
    out->shift = 0;
    if (x == KC_R(0.0))
        return 1;
    /* Bounded: a finite positive float or double is within 2^-1100..2^1024. */
    while (x < KC_R(1073741824.0) && shift < 1100) {
        x *= KC_R(2.0);
        shift++;
    }
    while (x >= KC_R(2147483648.0)) {
        x *= KC_R(0.5);
        shift--;
    }
    kc_real r = kc_floor(x + KC_R(0.5));
    if (r >= KC_R(2147483648.0)) { /* rounded up to 2^31 */
        r = KC_R(1073741824.0);
        shift--;
    }
    out->m = (uint32_t)(int32_t)r;
    out->shift = shift;
    return 1;
}

/* A time in ticks (0 <= x < 2^24) into Q32.32, through int32_t parts (a
 * float-to-int64 conversion would pull in soft double on an M4F). */
static int64_t ticks_q32(kc_real x)
{
    kc_real ip = kc_floor(x);
    kc_real frac = (x - ip) * KC_R(65536.0);
    kc_real f1 = kc_floor(frac);
    kc_real f2 = kc_floor((frac - f1) * KC_R(65536.0) + KC_R(0.5));
    return (int64_t)(int32_t)ip * ((int64_t)1 << 32) + (int64_t)(int32_t)f1 * 65536 + (int32_t)f2;
}

/* The u profile of a plan from rest to rest (kinctl/fx.h's kc_fx_ramp). */
static int ramp_init(kc_fx_ramp *ramp, const kc_profile *p)
{
    if (p->p0 != KC_R(0.0) || p->v0 != KC_R(0.0) || p->p1 != KC_R(1.0) || !(p->dt > KC_R(0.0)))
        return 0;
    memset(ramp, 0, sizeof *ramp);
    kc_real dt = p->dt;
    ramp->ticks = p->ticks;
    if (p->ticks == 0)
        return 1;
    ramp->k1 = ticks_q32(p->t1 / dt);
    ramp->k2 = ticks_q32(p->t2 / dt);
    ramp->kT = ticks_q32(p->T / dt);
    return to_fixed(p->pc, KC_FX_ROT_BITS, &ramp->uc) && scaled_of(KC_R(0.5) * p->a1 * dt * dt, &ramp->a) &&
           scaled_of(p->vc * dt, &ramp->v) && scaled_of(-KC_R(0.5) * p->a3 * dt * dt, &ramp->b);
}

kc_status kc_fx_joint_init(kc_fx_joint_move *move, const kc_fx_chain *fx, const kc_interp_joint *plan)
{
    if (move == NULL || fx == NULL || plan == NULL || plan->n != fx->n_joints)
        return KC_E_ARG;
    kc_fx_joint_move out;
    memset(&out, 0, sizeof out);
    out.n = plan->n;
    if (!ramp_init(&out.ramp, &plan->prof) || kc_fx_q_from_real(fx, plan->q0, out.q0) != KC_OK ||
        kc_fx_q_from_real(fx, plan->q1, out.q1) != KC_OK)
        return KC_E_ARG;
    for (int i = 0; i < out.n; i++)
        out.dq[i] = (int64_t)out.q1[i] - out.q0[i]; /* so that u = 1 lands on q1 */
    *move = out;
    return KC_OK;
}

static int quat_to_fixed(const kc_quat *q, int32_t out[4])
{
    return to_fixed(q->w, KC_FX_ROT_BITS, &out[0]) && to_fixed(q->x, KC_FX_ROT_BITS, &out[1]) &&
           to_fixed(q->y, KC_FX_ROT_BITS, &out[2]) && to_fixed(q->z, KC_FX_ROT_BITS, &out[3]);
}

kc_status kc_fx_line_init(kc_fx_line *line, const kc_interp_line *plan)
{
    if (line == NULL || plan == NULL)
        return KC_E_ARG;
    kc_fx_line out;
    memset(&out, 0, sizeof out);
    if (!ramp_init(&out.ramp, &plan->prof) || !quat_to_fixed(&plan->q1, out.q1) || !quat_to_fixed(&plan->q2, out.q2))
        return KC_E_ARG;
    for (int i = 0; i < 3; i++) {
        if (!to_fixed(plan->p1.v[i], KC_FX_POS_BITS, &out.p1[i]) ||
            !to_fixed(plan->p2.v[i], KC_FX_POS_BITS, &out.p2[i]))
            return KC_E_ARG;
        out.dp[i] = (int64_t)out.p2[i] - out.p1[i];
    }
    out.slerp = plan->orient == KC_INTERP_SLERP;
    int ok;
    if (out.slerp) {
        ok = to_fixed(KC_R(0.5) * plan->angle, KC_FX_ANGLE_BITS, &out.half_angle);
        for (int i = 0; i < 3; i++)
            ok = ok && to_fixed(plan->axis.v[i], KC_FX_ROT_BITS, &out.axis[i]);
    } else {
        ok = to_fixed(KC_R(0.5) * plan->theta, KC_FX_ANGLE_BITS, &out.half_theta) &&
             to_fixed(KC_R(0.5) * plan->phi, KC_FX_ANGLE_BITS, &out.half_phi) &&
             to_fixed(plan->k1.v[0], KC_FX_ROT_BITS, &out.kx) && to_fixed(plan->k1.v[1], KC_FX_ROT_BITS, &out.ky);
    }
    if (!ok)
        return KC_E_ARG;
    *line = out;
    return KC_OK;
}
