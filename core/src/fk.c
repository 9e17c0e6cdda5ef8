/* SPDX-License-Identifier: BSD-3-Clause */
/* fk.c - forward kinematics over elementary transforms, and the geometric
 * Jacobian (seed 000, seed 003).
 *
 * The running pose is right-multiplied by each elementary transform in
 * place: a rotation about the frame's own axis changes two columns of R, a
 * translation along it moves the origin along one column. A DH link so costs
 * about 30 multiplications instead of a 4x4 product's 64. */
#include "fk_internal.h"

/* The element helpers are inlined even at -Os: called, each costs more in
 * the call than in its six products (measured on a Cortex-M4F), and only
 * inlined are i, j and k constants. */
#if defined(__GNUC__) || defined(__clang__)
#define FK_INLINE static inline __attribute__((always_inline))
#else
#define FK_INLINE static inline
#endif

/* Rotation about the running frame's axis: columns i and j (right-handed
 * order) turn by (c, s). i and j are constants after inlining. */
FK_INLINE void turn(kc_real m[3][3], int i, int j, kc_real c, kc_real s)
{
    for (int r = 0; r < 3; r++) {
        kc_real a = m[r][i], b = m[r][j];
        m[r][i] = c * a + s * b;
        m[r][j] = c * b - s * a;
    }
}

/* A constant quarter turn (c = 0, s = sign): a column swap with one sign. */
FK_INLINE void quarter_turn(kc_real m[3][3], int i, int j, int sign)
{
    for (int r = 0; r < 3; r++) {
        kc_real a = m[r][i], b = m[r][j];
        m[r][i] = sign > 0 ? b : -b;
        m[r][j] = sign > 0 ? -a : a;
    }
}

/* Moves the running origin along the running frame's axis k. */
FK_INLINE void shift(kc_real m[3][3], kc_real t[3], int k, kc_real v)
{
    t[0] += v * m[0][k];
    t[1] += v * m[1][k];
    t[2] += v * m[2][k];
}

static int q_finite(const kc_chain *chain, const kc_real *q)
{
    for (int j = 0; j < chain->n_joints; j++)
        if (!kc_isfinite(q[j]))
            return 0;
    return 1;
}

static int is_identity(const kc_pose *p)
{
    const kc_real(*m)[3] = p->R.m;
    return m[0][0] == KC_R(1.0) && m[1][1] == KC_R(1.0) && m[2][2] == KC_R(1.0) && m[0][1] == KC_R(0.0) &&
           m[0][2] == KC_R(0.0) && m[1][0] == KC_R(0.0) && m[1][2] == KC_R(0.0) && m[2][0] == KC_R(0.0) &&
           m[2][1] == KC_R(0.0) && p->t.v[0] == KC_R(0.0) && p->t.v[1] == KC_R(0.0) && p->t.v[2] == KC_R(0.0);
}

/* Walks the chain from the base. Records each frame (if frames != NULL);
 * for the Jacobian (jac != NULL) writes each joint's world axis into rows
 * 3-5 of its column and its origin into origin[j]. Returns the tool pose. */
static void walk(const kc_chain *chain, const kc_real *q, kc_pose *frames, kc_jacobian *jac,
                 kc_real origin[][3], kc_pose *tool)
{
    kc_pose cur = chain->base;
    kc_real(*m)[3] = cur.R.m;
    kc_real *t = cur.t.v;
    int f = 0;
    while (frames != NULL && f < chain->n_frames && chain->frame_end[f] == 0)
        frames[f++] = cur;
    for (int e = 0; e < chain->n_elements; e++) {
        const kc_element *el = &chain->elements[e];
        kc_real c = el->c, s = el->s, v = el->value;
        int code = el->code;
        if (code <= KC_CODE_TZ_JOINT) {
            int j = (int)el->joint; /* >= 0 for the joint codes */
            v = q[j] + chain->joints[j].offset;
            code += KC_CODE_RX - KC_CODE_RX_JOINT; /* now as its constant twin */
            if (code <= KC_CODE_RZ)
                kc_sincos_inline(v, &s, &c);
            if (jac != NULL) {
                /* The axis is unchanged by the motion along it. */
                int k = code <= KC_CODE_RZ ? code - KC_CODE_RX : code - KC_CODE_TX;
                jac->m[3][j] = m[0][k];
                jac->m[4][j] = m[1][k];
                jac->m[5][j] = m[2][k];
                origin[j][0] = t[0];
                origin[j][1] = t[1];
                origin[j][2] = t[2];
            }
        } else if (el->quarter != 0) {
            code += 16; /* dispatched below as a quarter turn */
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
        default: shift(m, t, 2, v); break; /* KC_CODE_TZ */
        }
        while (frames != NULL && f < chain->n_frames && chain->frame_end[f] == e + 1)
            frames[f++] = cur;
    }
    if (is_identity(&chain->tool))
        *tool = cur;
    else
        kc_pose_mul(&cur, &chain->tool, tool);
}

kc_status kc_fk_eval(const kc_chain *chain, const kc_real *q, kc_pose *tool)
{
    if (chain == NULL || q == NULL || tool == NULL || !q_finite(chain, q))
        return KC_E_ARG;
    walk(chain, q, NULL, NULL, NULL, tool);
    return KC_OK;
}

kc_status kc_fk_frames(const kc_chain *chain, const kc_real *q, kc_pose *frames, kc_pose *tool)
{
    kc_pose end;
    if (chain == NULL || q == NULL || frames == NULL || !q_finite(chain, q))
        return KC_E_ARG;
    walk(chain, q, frames, NULL, NULL, &end);
    if (tool != NULL)
        *tool = end;
    return KC_OK;
}

/* The Jacobian and the tool pose into tool; the public entry and the
 * solvers' each inline it (one call less for either). */
FK_INLINE void jacobian(const kc_chain *chain, const kc_real *q, kc_jacobian *jac, kc_pose *tool)
{
    /* Not cleared: walk writes the row of every joint, as it writes the
     * joint's axis into jac (a checked chain drives each joint by exactly
     * one element), and clearing it cost as much as a joint's element. */
    kc_real origin[KC_MAX_JOINTS][3];
    walk(chain, q, NULL, jac, origin, tool);
    const kc_real *pe = tool->t.v;
    for (int j = 0; j < chain->n_joints; j++) {
        kc_real zx = jac->m[3][j], zy = jac->m[4][j], zz = jac->m[5][j];
        if (chain->joints[j].type == KC_JOINT_REVOLUTE) {
            /* v = z x (p_tool - p_j); origin[j] was written by walk (a
             * checked chain drives each joint by exactly one element),
             * which the analyser cannot see. */
            /* NOLINTNEXTLINE(clang-analyzer-core.UndefinedBinaryOperatorResult) */
            kc_real rx = pe[0] - origin[j][0], ry = pe[1] - origin[j][1], rz = pe[2] - origin[j][2];
            jac->m[0][j] = zy * rz - zz * ry;
            jac->m[1][j] = zz * rx - zx * rz;
            jac->m[2][j] = zx * ry - zy * rx;
        } else {
            jac->m[0][j] = zx;
            jac->m[1][j] = zy;
            jac->m[2][j] = zz;
            jac->m[3][j] = jac->m[4][j] = jac->m[5][j] = KC_R(0.0);
        }
    }
}

void kc_fk_jacobian_checked(const kc_chain *chain, const kc_real *q, kc_jacobian *jac, kc_pose *tool)
{
    jacobian(chain, q, jac, tool);
}

kc_status kc_fk_jacobian(const kc_chain *chain, const kc_real *q, kc_jacobian *jac, kc_pose *tool)
{
    kc_pose end;
    if (chain == NULL || q == NULL || jac == NULL || !q_finite(chain, q))
        return KC_E_ARG;
    jacobian(chain, q, jac, tool != NULL ? tool : &end); /* no copy when the caller wants the pose */
    return KC_OK;
}
