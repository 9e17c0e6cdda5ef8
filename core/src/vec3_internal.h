/* SPDX-License-Identifier: BSD-3-Clause */
/* vec3_internal.h - vectors by value, for formulas that read better as
 * expressions (the rotation knots of path_cart.c, GJK in shape.c), and the
 * one place of the component formulas: se3's pointer functions
 * (kinctl/se3.h) are these, so every result is the same to the bit either
 * way. Inline arithmetic rather than calls of se3: a call passes its
 * vectors through memory, which cost 1.3 KB over the core on a Cortex-M4F
 * at -Os. Private to the core. */
#ifndef KINCTL_VEC3_INTERNAL_H
#define KINCTL_VEC3_INTERNAL_H

#include "kinctl/se3.h"

static inline kc_vec3 kc_v3_add(kc_vec3 a, kc_vec3 b)
{
    return kc_vec3_make(a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2]);
}

static inline kc_vec3 kc_v3_sub(kc_vec3 a, kc_vec3 b)
{
    return kc_vec3_make(a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2]);
}

static inline kc_vec3 kc_v3_scale(kc_vec3 a, kc_real s) { return kc_vec3_make(a.v[0] * s, a.v[1] * s, a.v[2] * s); }

/* a + k b */
static inline kc_vec3 kc_v3_add_scaled(kc_vec3 a, kc_vec3 b, kc_real k) { return kc_v3_add(a, kc_v3_scale(b, k)); }

static inline kc_vec3 kc_v3_neg(kc_vec3 a) { return kc_v3_scale(a, KC_R(-1.0)); }

static inline kc_real kc_v3_dot(kc_vec3 a, kc_vec3 b) { return a.v[0] * b.v[0] + a.v[1] * b.v[1] + a.v[2] * b.v[2]; }

static inline kc_vec3 kc_v3_cross(kc_vec3 a, kc_vec3 b)
{
    return kc_vec3_make(a.v[1] * b.v[2] - a.v[2] * b.v[1], a.v[2] * b.v[0] - a.v[0] * b.v[2],
                        a.v[0] * b.v[1] - a.v[1] * b.v[0]);
}

#endif /* KINCTL_VEC3_INTERNAL_H */
