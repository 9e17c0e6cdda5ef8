/* SPDX-License-Identifier: BSD-3-Clause */
/* vec3_internal.h - vectors by value, for formulas that read better as
 * expressions (the rotation knots of path_cart.c, GJK in zone.c). Each one
 * is se3's own operation (kinctl/se3.h), so every result is the same to the
 * bit as a call of it. Private to the core. */
#ifndef KINCTL_VEC3_INTERNAL_H
#define KINCTL_VEC3_INTERNAL_H

#include "kinctl/se3.h"

static inline kc_vec3 kc_v3_add(kc_vec3 a, kc_vec3 b)
{
    kc_vec3 c;
    kc_vec3_add(&a, &b, &c);
    return c;
}

static inline kc_vec3 kc_v3_sub(kc_vec3 a, kc_vec3 b)
{
    kc_vec3 c;
    kc_vec3_sub(&a, &b, &c);
    return c;
}

static inline kc_vec3 kc_v3_scale(kc_vec3 a, kc_real s)
{
    kc_vec3 c;
    kc_vec3_scale(&a, s, &c);
    return c;
}

/* a + k b */
static inline kc_vec3 kc_v3_add_scaled(kc_vec3 a, kc_vec3 b, kc_real k) { return kc_v3_add(a, kc_v3_scale(b, k)); }

static inline kc_vec3 kc_v3_neg(kc_vec3 a) { return kc_v3_scale(a, KC_R(-1.0)); }

static inline kc_real kc_v3_dot(kc_vec3 a, kc_vec3 b) { return kc_vec3_dot(&a, &b); }

static inline kc_vec3 kc_v3_cross(kc_vec3 a, kc_vec3 b)
{
    kc_vec3 c;
    kc_vec3_cross(&a, &b, &c);
    return c;
}

#endif /* KINCTL_VEC3_INTERNAL_H */
