/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/orient.h - descriptions of orientation and the conversions between
 * them (seed 001 lab 2; seed 000's "Euler angles of R").
 *
 * Roll-pitch-yaw (lab 2 sec. 1.1): R = Rz(phi) Ry(theta) Rx(psi), angles in
 * rad: psi about x (yaw in the seed's table), theta about y (pitch), phi about
 * z (roll). Stored as kc_euler {phi, theta, psi}.
 *   Extraction: theta = atan2(-r31, hypot(r11, r21)) in [-pi/2, pi/2],
 *   phi = atan2(r21, r11), psi = atan2(r32, r33), both in (-pi, pi].
 *   Singular when hypot(r11, r21) <= KC_TOL_GIMBAL (theta = +-pi/2): only
 *   psi - phi (theta = +pi/2) or psi + phi (theta = -pi/2) is defined, so
 *   phi := 0 and psi = atan2(r12, r22) resp. atan2(-r12, r22).
 *
 * Z-Y-Z Euler (lab 2 sec. 1.2): R = Rz(phi) Ry(theta) Rz(psi).
 *   Extraction on the sin(theta) >= 0 branch: theta = atan2(hypot(r31, r32),
 *   r33) in [0, pi], phi = atan2(r23, r13), psi = atan2(r32, -r31).
 *   Singular when hypot(r31, r32) <= KC_TOL_GIMBAL (theta = 0 or pi): phi := 0
 *   and psi = atan2(r21, r22), which then carries phi + psi (theta = 0) or
 *   psi - phi (theta = pi).
 *
 * Axis-angle (lab 2 sec. 1.3, Rodrigues; the seed's printed matrix has two
 * sign typos in r23 and r32, see vectors/README.md): R = I + sin(theta) [k]x +
 * (1 - cos(theta)) [k]x^2 with k normalised here. Extraction gives theta in
 * [0, pi]; at theta = 0 the axis is (0, 0, 1) by convention; at theta = pi the
 * axis is taken from (R + I)/2 = k k^T with its first nonzero component
 * positive.
 *
 * Every extraction is NaN-free for any finite rotation matrix and returns
 * nonzero when the configuration is singular. Quaternion conversions are in
 * se3.h. All functions are pure and safe to call in the control cycle.
 */
#ifndef KINCTL_ORIENT_H
#define KINCTL_ORIENT_H

#include "kinctl/decls.h"
#include "kinctl/se3.h"

KC_BEGIN_DECLS

typedef struct kc_euler {
    kc_real phi, theta, psi;
} kc_euler;

void kc_orient_rpy_to_mat3(const kc_euler *rpy, kc_mat3 *dest);
/* Returns 1 in gimbal lock (see above), else 0. */
int kc_orient_mat3_to_rpy(const kc_mat3 *R, kc_euler *dest);

void kc_orient_zyz_to_mat3(const kc_euler *zyz, kc_mat3 *dest);
/* Returns 1 in gimbal lock (see above), else 0. */
int kc_orient_mat3_to_zyz(const kc_mat3 *R, kc_euler *dest);

/* Rotation by theta (rad) about axis k; k need not be unit but must be
 * nonzero and finite, else KC_E_ARG with dest untouched. */
kc_status kc_orient_axis_angle_to_mat3(const kc_vec3 *k, kc_real theta, kc_mat3 *dest);
/* Unit axis and angle in [0, pi]. Returns 1 when theta is 0 or pi (the axis
 * is then a convention, see above), else 0. */
int kc_orient_mat3_to_axis_angle(const kc_mat3 *R, kc_vec3 *k, kc_real *theta);

KC_END_DECLS

#endif /* KINCTL_ORIENT_H */
