/* fk.c - forward kinematics over elementary transforms, and the geometric
 * Jacobian (seed 000, seed 003). */
#include "kinctl/fk.h"

/* Right-multiplies the running rotation by a rotation about its own axis:
 * only the two other columns change (12 multiplications, not 27). i and j
 * are the turning columns in right-handed order, constants after inlining. */
static inline void turn(kc_real m[3][3], int i, int j, kc_real c, kc_real s)
{
    for (int r = 0; r < 3; r++) {
        kc_real a = m[r][i], b = m[r][j];
        m[r][i] = c * a + s * b;
        m[r][j] = c * b - s * a;
    }
}

/* Moves the running origin along the running frame's axis k. */
static inline void shift(kc_real m[3][3], kc_real t[3], int k, kc_real v)
{
    t[0] += v * m[0][k];
    t[1] += v * m[1][k];
    t[2] += v * m[2][k];
}

/* Where a joint's world axis and origin go, for the Jacobian. */
typedef struct joint_axes {
    kc_vec3 z[KC_MAX_JOINTS];
    kc_vec3 p[KC_MAX_JOINTS];
} joint_axes;

static int q_finite(const kc_chain *chain, const kc_real *q)
{
    for (int j = 0; j < chain->n_joints; j++)
        if (!kc_isfinite(q[j]))
            return 0;
    return 1;
}

/* Walks the chain from the base. Records each frame (if frames) and each
 * joint's axis and origin (if axes); returns the tool pose. */
static void walk(const kc_chain *chain, const kc_real *q, kc_pose *frames, joint_axes *axes, kc_pose *tool)
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
            int j = el->joint;
            v = q[j] + chain->joints[j].offset;
            if (code <= KC_CODE_RZ_JOINT)
                kc_sincos(v, &s, &c);
            if (axes != NULL) {
                int k = (code - KC_CODE_RX_JOINT) % 3;
                axes->z[j] = kc_vec3_make(m[0][k], m[1][k], m[2][k]);
                axes->p[j] = cur.t;
            }
            code += KC_CODE_RX - KC_CODE_RX_JOINT; /* now as its constant twin */
        }
        switch (code) {
        case KC_CODE_RX: turn(m, 1, 2, c, s); break;
        case KC_CODE_RY: turn(m, 2, 0, c, s); break;
        case KC_CODE_RZ: turn(m, 0, 1, c, s); break;
        case KC_CODE_TX: shift(m, t, 0, v); break;
        case KC_CODE_TY: shift(m, t, 1, v); break;
        default: shift(m, t, 2, v); break; /* KC_CODE_TZ */
        }
        while (frames != NULL && f < chain->n_frames && chain->frame_end[f] == e + 1)
            frames[f++] = cur;
    }
    kc_pose_mul(&cur, &chain->tool, tool);
}

kc_status kc_fk_eval(const kc_chain *chain, const kc_real *q, kc_pose *tool)
{
    if (chain == NULL || q == NULL || tool == NULL || !q_finite(chain, q))
        return KC_E_ARG;
    walk(chain, q, NULL, NULL, tool);
    return KC_OK;
}

kc_status kc_fk_frames(const kc_chain *chain, const kc_real *q, kc_pose *frames, kc_pose *tool)
{
    kc_pose end;
    if (chain == NULL || q == NULL || frames == NULL || !q_finite(chain, q))
        return KC_E_ARG;
    walk(chain, q, frames, NULL, &end);
    if (tool != NULL)
        *tool = end;
    return KC_OK;
}

kc_status kc_fk_jacobian(const kc_chain *chain, const kc_real *q, kc_jacobian *jac, kc_pose *tool)
{
    joint_axes axes;
    kc_pose end;
    if (chain == NULL || q == NULL || jac == NULL || !q_finite(chain, q))
        return KC_E_ARG;
    walk(chain, q, NULL, &axes, &end);
    for (int j = 0; j < chain->n_joints; j++) {
        const kc_vec3 *z = &axes.z[j];
        kc_vec3 v;
        if (chain->joints[j].type == KC_JOINT_REVOLUTE) {
            kc_vec3 r;
            kc_vec3_sub(&end.t, &axes.p[j], &r);
            kc_vec3_cross(z, &r, &v);
            for (int i = 0; i < 3; i++) {
                jac->m[i][j] = v.v[i];
                jac->m[i + 3][j] = z->v[i];
            }
        } else {
            for (int i = 0; i < 3; i++) {
                jac->m[i][j] = z->v[i];
                jac->m[i + 3][j] = KC_R(0.0);
            }
        }
    }
    if (tool != NULL)
        *tool = end;
    return KC_OK;
}
