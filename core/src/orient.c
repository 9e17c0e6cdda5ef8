/* SPDX-License-Identifier: BSD-3-Clause */
/* orient.c - roll-pitch-yaw, Z-Y-Z Euler and axis-angle (seed 001 lab 2).
 * Conventions and singular branches are documented in kinctl/orient.h. */
#include "kinctl/orient.h"

/* R = Rot(a1, x1) Rot(a2, x2) Rot(a3, x3): both Euler forms are such a
 * product of three elementary rotations. */
static void rot3(kc_axis a1, kc_real x1, kc_axis a2, kc_real x2, kc_axis a3, kc_real x3, kc_mat3 *dest)
{
    kc_mat3 r1, r2, r3;
    kc_mat3_rot(a1, x1, &r1);
    kc_mat3_rot(a2, x2, &r2);
    kc_mat3_rot(a3, x3, &r3);
    kc_mat3_mul(&r1, &r2, dest);
    kc_mat3_mul(dest, &r3, dest);
}

void kc_orient_rpy_to_mat3(const kc_euler *rpy, kc_mat3 *dest)
{
    rot3(KC_AXIS_Z, rpy->phi, KC_AXIS_Y, rpy->theta, KC_AXIS_X, rpy->psi, dest);
}

int kc_orient_mat3_to_rpy(const kc_mat3 *R, kc_euler *dest)
{
    const kc_real(*m)[3] = R->m;
    kc_real c = kc_hypot(m[0][0], m[1][0]); /* |cos(theta)| */
    kc_euler e;
    e.theta = kc_atan2(-m[2][0], c);
    if (c <= KC_TOL_GIMBAL) {
        /* Rz(phi) Ry(+-pi/2) Rx(psi) depends on psi -+ phi only. */
        e.phi = KC_R(0.0);
        e.psi = m[2][0] < KC_R(0.0) ? kc_atan2(m[0][1], m[1][1]) : kc_atan2(-m[0][1], m[1][1]);
        *dest = e;
        return 1;
    }
    e.phi = kc_atan2(m[1][0], m[0][0]);
    e.psi = kc_atan2(m[2][1], m[2][2]);
    *dest = e;
    return 0;
}

void kc_orient_zyz_to_mat3(const kc_euler *zyz, kc_mat3 *dest)
{
    rot3(KC_AXIS_Z, zyz->phi, KC_AXIS_Y, zyz->theta, KC_AXIS_Z, zyz->psi, dest);
}

int kc_orient_mat3_to_zyz(const kc_mat3 *R, kc_euler *dest)
{
    const kc_real(*m)[3] = R->m;
    kc_real s = kc_hypot(m[2][0], m[2][1]); /* sin(theta) >= 0 */
    kc_euler e;
    e.theta = kc_atan2(s, m[2][2]);
    if (s <= KC_TOL_GIMBAL) {
        /* theta = 0 or pi: only phi + psi resp. psi - phi is defined. */
        e.phi = KC_R(0.0);
        e.psi = kc_atan2(m[1][0], m[1][1]);
        *dest = e;
        return 1;
    }
    e.phi = kc_atan2(m[1][2], m[0][2]);
    e.psi = kc_atan2(m[2][1], -m[2][0]);
    *dest = e;
    return 0;
}

kc_status kc_orient_axis_angle_to_mat3(const kc_vec3 *k, kc_real theta, kc_mat3 *dest)
{
    kc_real n = kc_vec3_norm(k);
    if (!kc_isfinite(n) || !(n > KC_R(0.0)) || !kc_isfinite(theta))
        return KC_E_ARG;
    kc_real x = k->v[0] / n, y = k->v[1] / n, z = k->v[2] / n;
    kc_real s, c;
    kc_sincos(theta, &s, &c);
    kc_real v = KC_R(1.0) - c; /* versine */
    dest->m[0][0] = x * x * v + c;
    dest->m[0][1] = x * y * v - z * s;
    dest->m[0][2] = x * z * v + y * s;
    dest->m[1][0] = x * y * v + z * s;
    dest->m[1][1] = y * y * v + c;
    dest->m[1][2] = y * z * v - x * s;
    dest->m[2][0] = x * z * v - y * s;
    dest->m[2][1] = y * z * v + x * s;
    dest->m[2][2] = z * z * v + c;
    return KC_OK;
}

/* Makes the first component that is not (nearly) zero positive. */
static void canonical_sign(kc_vec3 *k)
{
    for (int i = 0; i < 3; i++) {
        if (kc_fabs(k->v[i]) > KC_TOL_AXIS) {
            if (k->v[i] < KC_R(0.0))
                kc_vec3_scale(k, KC_R(-1.0), k);
            return;
        }
    }
}

int kc_orient_mat3_to_axis_angle(const kc_mat3 *R, kc_vec3 *k, kc_real *theta)
{
    const kc_real(*m)[3] = R->m;
    /* vee(R - R^T) = 2 sin(theta) k; trace(R) = 1 + 2 cos(theta). */
    kc_vec3 w = kc_vec3_make(m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1]);
    kc_real s2 = kc_vec3_norm(&w);
    kc_real c = KC_R(0.5) * (m[0][0] + m[1][1] + m[2][2] - KC_R(1.0));
    kc_real th = kc_atan2(KC_R(0.5) * s2, c);
    kc_vec3 axis;
    int singular = 0;

    if (c >= KC_R(0.0)) {
        /* Up to 90 degrees the antisymmetric part fixes the axis well. */
        if (s2 > KC_R(0.0)) {
            kc_vec3_scale(&w, KC_R(1.0) / s2, &axis);
        } else {
            axis = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(1.0));
        }
        singular = KC_R(0.5) * s2 < KC_TOL_AXIS * KC_TOL_AXIS;
    } else {
        /* Beyond 90 degrees sin(theta) loses accuracy: take k from the
         * symmetric part, k k^T = ((R + R^T)/2 - c I) / (1 - c), using the
         * largest diagonal term, and its sign from the antisymmetric part. */
        kc_real d = KC_R(1.0) / (KC_R(1.0) - c);
        int i = 0;
        kc_real b[3];
        for (int j = 0; j < 3; j++)
            b[j] = (m[j][j] - c) * d;
        if (b[1] > b[i])
            i = 1;
        if (b[2] > b[i])
            i = 2;
        kc_real ki = kc_sqrt(kc_max(b[i], KC_R(0.0)));
        for (int j = 0; j < 3; j++)
            axis.v[j] = j == i ? ki : KC_R(0.5) * (m[i][j] + m[j][i]) * d / ki;
        kc_real n = kc_vec3_norm(&axis);
        kc_vec3_scale(&axis, KC_R(1.0) / n, &axis);
        singular = KC_R(0.5) * s2 < KC_TOL_AXIS; /* theta is pi within the tolerance */
        /* The antisymmetric part fixes the sign as long as it stands above
         * the rounding of the entries (a few ulps): R(k, pi - d) and
         * R(-k, pi - d) differ by about 2 d, so taking the canonical sign
         * for every sin(theta) < KC_TOL_AXIS returned a rotation off by up
         * to 2e-3 in float (found by tests/unit/test_orient.c). Only at
         * rounding level are k and -k the same rotation, and the sign is
         * canonical. */
        if (KC_R(0.5) * s2 <= KC_R(8.0) * KC_REAL_EPS)
            canonical_sign(&axis); /* theta = pi: both signs are the same rotation */
        else if (kc_vec3_dot(&axis, &w) < KC_R(0.0))
            kc_vec3_scale(&axis, KC_R(-1.0), &axis);
    }
    *k = axis;
    *theta = th;
    return singular;
}
