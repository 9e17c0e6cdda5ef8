/* SPDX-License-Identifier: BSD-3-Clause */
/* fx_chain.c - conversions between kinctl's floating-point types and the
 * fixed-point formats of kinctl/fx.h: done once when a chain is set up,
 * outside the cycle. */
#include "kinctl/fx.h"

#include <string.h>

#include "profile_internal.h"

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

/* u (within -0.5 .. 1.5) in Q23.40, through int32_t parts (a
 * float-to-int64 conversion would pull in soft double on an M4F). */
static int u_q40(kc_real u, int64_t *out)
{
    if (!(u >= KC_R(-0.5) && u <= KC_R(1.5)))
        return 0;
    kc_real x = u * KC_R(1048576.0); /* 2^20 */
    kc_real hi = kc_floor(x);
    kc_real lo = kc_floor((x - hi) * KC_R(1048576.0) + KC_R(0.5));
    *out = (int64_t)(int32_t)hi * ((int64_t)1 << 20) + (int32_t)lo;
    return 1;
}

/* A profile's state at tick k (p, v, a and the jerk). */
typedef void (*state_fn)(const void *prof, int64_t k, kc_scurve_state *st);

static void profile_state(const void *prof, int64_t k, kc_scurve_state *st)
{
    kc_profile_state s;
    kc_profile_eval((const kc_profile *)prof, k, &s);
    st->p = s.p;
    st->v = s.v;
    st->a = s.a;
    st->j = KC_R(0.0);
}

static void scurve_state(const void *prof, int64_t k, kc_scurve_state *st)
{
    kc_scurve_eval((const kc_scurve *)prof, k, st);
}

/*
 * The ramp (kinctl/fx.h's kc_fx_ramp) of a profile of n phases, phase i
 * holding the ticks with t_end[i - 1] <= k dt < t_end[i] (the first from
 * 0, the last to `ticks`: the evaluators' rule), as the fraction
 * u = (p - p0) s. 0 where u leaves -0.5 .. 1.5 at a phase's first or
 * last tick, or a factor has no 31-bit form.
 */
static int ramp_build(kc_fx_ramp *r, const void *prof, state_fn state, const kc_real *t_end, int n, int64_t ticks,
                      kc_real dt, kc_real p0, kc_real s)
{
    memset(r, 0, sizeof *r);
    r->ticks = ticks;
    int64_t k0 = 0;
    for (int i = 0; i < n && k0 < ticks; i++) {
        int64_t k1 = i == n - 1 ? ticks : kc_profile_ticks(t_end[i], dt);
        if (k1 < 0 || k1 > ticks)
            k1 = ticks;
        if (k1 <= k0)
            continue;
        kc_scurve_state st, end;
        state(prof, k0, &st);
        state(prof, k1 - 1, &end);
        const kc_real c[3] = {st.v * s * dt, KC_R(0.5) * st.a * s * dt * dt, st.j * s * dt * dt * dt / KC_R(6.0)};
        int p = r->n++;
        r->k0[p] = (int32_t)k0;
        for (int d = 0; d < 3; d++) {
            if (c[d] < KC_R(0.0))
                r->neg[p] |= (uint8_t)(1u << d);
            if (!scaled_of(kc_fabs(c[d]), &r->c[p][d]))
                return 0;
        }
        int64_t last;
        if (!u_q40((st.p - p0) * s, &r->u0[p]) || !u_q40((end.p - p0) * s, &last))
            return 0;
        k0 = k1;
    }
    return 1;
}

/* The ramp of a trapezoid of u from rest to rest, 0 to 1. */
static int ramp_of_profile(kc_fx_ramp *r, const kc_profile *p)
{
    const kc_real t_end[2] = {p->t1, p->t2};
    return p->p0 == KC_R(0.0) && p->v0 == KC_R(0.0) && p->p1 == KC_R(1.0) && p->dt > KC_R(0.0) &&
           ramp_build(r, p, profile_state, t_end, 3, p->ticks, p->dt, KC_R(0.0), KC_R(1.0));
}

/* The ramp of a jerk-limited profile from rest at p0 to p1 (p0 = p1: a
 * wait, u = 0 throughout), as the fraction (p - p0) / (p1 - p0), over
 * `ticks` ticks (its own). */
static int ramp_of_scurve(kc_fx_ramp *r, const kc_scurve *p, int64_t ticks)
{
    if (p->v0 != KC_R(0.0) || p->a0 != KC_R(0.0) || !(p->dt > KC_R(0.0)) || p->ticks != ticks)
        return 0;
    kc_real d = p->p1 - p->p0;
    if (d == KC_R(0.0)) {
        memset(r, 0, sizeof *r);
        r->n = 1;
        r->ticks = ticks;
        return 1;
    }
    return ramp_build(r, p, scurve_state, p->t_end, p->n, ticks, p->dt, p->p0, KC_R(1.0) / d);
}

/* The ramp of a plan's speed law: its trapezoid prof, or its jerk-limited
 * su from 0 to 1 (from 1 to 1 for a plan that moves nothing: u = 0 here,
 * the same setpoints). */
static int ramp_of_law(kc_fx_ramp *r, kc_profile_kind kind, const kc_profile *prof, const kc_scurve *su)
{
    if (kind != KC_PROFILE_JERK)
        return ramp_of_profile(r, prof);
    return su->p1 == KC_R(1.0) && (su->p0 == KC_R(0.0) || su->p0 == KC_R(1.0)) && ramp_of_scurve(r, su, su->ticks);
}

kc_status kc_fx_joint_init(kc_fx_joint_move *move, const kc_fx_chain *fx, const kc_interp_joint *plan)
{
    if (move == NULL || fx == NULL || plan == NULL || plan->n != fx->n_joints)
        return KC_E_ARG;
    /* Built in place (a ramp per joint is kilobytes, too many for a copy
     * on a small stack); cleared on error. */
    memset(move, 0, sizeof *move);
    move->n = plan->n;
    move->per_joint = plan->kind == KC_PROFILE_JERK && plan->sync == KC_INTERP_SYNC_TIME;
    int ok = kc_fx_q_from_real(fx, plan->q0, move->q0) == KC_OK && kc_fx_q_from_real(fx, plan->q1, move->q1) == KC_OK;
    if (!move->per_joint)
        ok = ok && ramp_of_law(&move->ramp[0], plan->kind, &plan->prof, &plan->su);
    for (int i = 0; i < move->n && move->per_joint; i++)
        ok = ok && plan->sj[i].p0 == plan->q0[i] && plan->sj[i].p1 == plan->q1[i] &&
             ramp_of_scurve(&move->ramp[i], &plan->sj[i], plan->ticks);
    if (!ok) {
        memset(move, 0, sizeof *move);
        return KC_E_ARG;
    }
    for (int i = 0; i < move->n; i++)
        move->dq[i] = (int64_t)move->q1[i] - move->q0[i]; /* so that u = 1 lands on q1 */
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
    if (!ramp_of_law(&out.ramp, plan->kind, &plan->prof, &plan->su) || !quat_to_fixed(&plan->q1, out.q1) ||
        !quat_to_fixed(&plan->q2, out.q2))
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
