/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/se3.h - vectors, rotations, rigid poses, homogeneous transforms,
 * quaternions and dual quaternions.
 *
 * Seed 001 lab 1 (homogeneous transforms: translation, rotation about x, y
 * and z, global scale in element (4,4), perspective with focal length f) and
 * seed 002 (the pose as a unit dual quaternion, "biquaternion").
 *
 * Conventions: matrices are row-major, m[row][col]. Rotations are active:
 * kc_mat3_rot_x(a) turns a point about x by +a. A rigid pose maps a point p
 * of its own frame to R p + t in the parent frame. Quaternions are
 * (w, x, y, z) with the Hamilton product; from a matrix they come with w >= 0.
 * A pose's dual quaternion is r + eps d with d = 1/2 t r (t as a pure
 * quaternion).
 *
 * Naming follows kc_<type>_<op>(inputs..., dest): outputs come last. Unless
 * a function says otherwise, dest may alias an input. All functions are
 * pure, allocate nothing and are safe to call in the control cycle.
 */
#ifndef KINCTL_SE3_H
#define KINCTL_SE3_H

#include <stddef.h>

#include "kinctl/decls.h"
#include "kinctl/real.h"
#include "kinctl/status.h"

KC_BEGIN_DECLS

typedef struct kc_vec3 {
    kc_real v[3];
} kc_vec3;

/* Row-major 3x3 matrix; as a rotation its columns are the frame's axes. */
typedef struct kc_mat3 {
    kc_real m[3][3];
} kc_mat3;

/* Rigid transform: rotation R and translation t (metres). */
typedef struct kc_pose {
    kc_mat3 R;
    kc_vec3 t;
} kc_pose;

/* General 4x4 homogeneous transform: may scale and project (seed 001 lab 1). */
typedef struct kc_mat4 {
    kc_real m[4][4];
} kc_mat4;

typedef struct kc_quat {
    kc_real w, x, y, z;
} kc_quat;

/* Dual quaternion r + eps d. A unit one (|r| = 1, r.d = 0) is a rigid pose. */
typedef struct kc_dquat {
    kc_quat r, d;
} kc_dquat;

/* Axis codes for elementary transforms and perspective. */
typedef enum kc_axis { KC_AXIS_X = 0, KC_AXIS_Y = 1, KC_AXIS_Z = 2 } kc_axis;

/* ---- vec3 ---- */
/* Inline: as a call, each use cost more code than the three stores (426 B
 * over the core on a Cortex-M4F at -Os). */
static inline kc_vec3 kc_vec3_make(kc_real x, kc_real y, kc_real z)
{
    kc_vec3 v;
    v.v[0] = x;
    v.v[1] = y;
    v.v[2] = z;
    return v;
}

void kc_vec3_add(const kc_vec3 *a, const kc_vec3 *b, kc_vec3 *dest);
void kc_vec3_sub(const kc_vec3 *a, const kc_vec3 *b, kc_vec3 *dest);
void kc_vec3_scale(const kc_vec3 *a, kc_real s, kc_vec3 *dest);
kc_real kc_vec3_dot(const kc_vec3 *a, const kc_vec3 *b);
/* dest = a x b; dest may alias a or b. */
void kc_vec3_cross(const kc_vec3 *a, const kc_vec3 *b, kc_vec3 *dest);
kc_real kc_vec3_norm(const kc_vec3 *a);
/* Nonzero when every component is finite. */
int kc_vec3_isfinite(const kc_vec3 *a);

/* ---- mat3 ---- */
void kc_mat3_identity(kc_mat3 *dest);
/* Active rotation by angle (rad) about x, y or z. */
void kc_mat3_rot(kc_axis axis, kc_real angle, kc_mat3 *dest);
/* dest = a b; dest may alias a or b. */
void kc_mat3_mul(const kc_mat3 *a, const kc_mat3 *b, kc_mat3 *dest);
/* dest = a^T b; dest may alias a or b. */
void kc_mat3_tmul(const kc_mat3 *a, const kc_mat3 *b, kc_mat3 *dest);
void kc_mat3_transpose(const kc_mat3 *a, kc_mat3 *dest);
/* dest = a v; dest may alias v. */
void kc_mat3_mul_vec(const kc_mat3 *a, const kc_vec3 *v, kc_vec3 *dest);
/* dest = a^T v; dest may alias v. */
void kc_mat3_tmul_vec(const kc_mat3 *a, const kc_vec3 *v, kc_vec3 *dest);
/* Largest |(a^T a - I)_ij| and how far det(a) is from +1, the larger of the
 * two: zero for an exact rotation. NaN entries give a NaN result. */
kc_real kc_mat3_rotation_error(const kc_mat3 *a);
/* Nearest rotation to a (Gram-Schmidt on the columns x, then z = x cross y,
 * then y = z cross x), for re-orthonormalising accumulated rounding. */
kc_status kc_mat3_orthonormalize(const kc_mat3 *a, kc_mat3 *dest);

/* ---- pose ---- */
void kc_pose_identity(kc_pose *dest);
/* dest = a b (a then b in a's frame); dest may alias a or b. */
void kc_pose_mul(const kc_pose *a, const kc_pose *b, kc_pose *dest);
/* Rigid inverse [R^T, -R^T t]; dest may alias a. */
void kc_pose_inv(const kc_pose *a, kc_pose *dest);
/* dest = R p + t; dest may alias p. */
void kc_pose_apply(const kc_pose *a, const kc_vec3 *p, kc_vec3 *dest);
void kc_pose_to_mat4(const kc_pose *a, kc_mat4 *dest);
/* Accepts a 4x4 only if its last row is 0 0 0 1 and its 3x3 block is a
 * rotation within KC_TOL_ORTHONORMAL; otherwise KC_E_ARG, dest untouched. */
kc_status kc_pose_from_mat4(const kc_mat4 *a, kc_pose *dest);
int kc_pose_isfinite(const kc_pose *a);

/* ---- mat4: seed 001 lab 1 ---- */
void kc_mat4_identity(kc_mat4 *dest);
/* dest = a b; dest may alias a or b. */
void kc_mat4_mul(const kc_mat4 *a, const kc_mat4 *b, kc_mat4 *dest);
void kc_mat4_translation(kc_real dx, kc_real dy, kc_real dz, kc_mat4 *dest);
/* Active rotation about an axis through the origin, angle in rad. */
void kc_mat4_rotation(kc_axis axis, kc_real angle, kc_mat4 *dest);
/* Global scale: identity with s in element (4,4). A point comes out as
 * (x, y, z)/s, so s > 1 shrinks (seed 001 lab 1 sec. 1.5). s != 0. */
kc_status kc_mat4_scale(kc_real s, kc_mat4 *dest);
/* Perspective with focal length f (f != 0) along the optical axis: identity
 * with -1/f in row 4 at the axis' column, so w = 1 - c/f where c is the
 * coordinate along that axis (seed 001 lab 1 sec. 1.6). */
kc_status kc_mat4_perspective(kc_axis axis, kc_real f, kc_mat4 *dest);
/* Homogeneous image of a point: dest = a [p; 1] (4 values). */
void kc_mat4_apply_h(const kc_mat4 *a, const kc_vec3 *p, kc_real dest[4]);
/* Cartesian image (x, y, z)/w. KC_E_SINGULAR when w is zero (the point lies
 * in the perspective's vanishing plane); dest untouched then. */
kc_status kc_mat4_apply(const kc_mat4 *a, const kc_vec3 *p, kc_vec3 *dest);

/* ---- quaternion ---- */
void kc_quat_identity(kc_quat *dest);
/* Hamilton product dest = a b; dest may alias a or b. */
void kc_quat_mul(const kc_quat *a, const kc_quat *b, kc_quat *dest);
void kc_quat_conj(const kc_quat *a, kc_quat *dest);
kc_real kc_quat_norm(const kc_quat *a);
/* Unit quaternion along a; KC_E_ARG if a is zero or not finite. */
kc_status kc_quat_normalize(const kc_quat *a, kc_quat *dest);
/* From a rotation matrix (Shepperd's method, stable for every angle); the
 * result has w >= 0 and unit norm. */
void kc_quat_from_mat3(const kc_mat3 *R, kc_quat *dest);
/* Rotation matrix of a unit quaternion. */
void kc_quat_to_mat3(const kc_quat *q, kc_mat3 *dest);
/* dest = q v q*, for a unit q; dest may alias v. */
void kc_quat_rotate(const kc_quat *q, const kc_vec3 *v, kc_vec3 *dest);
/* Logarithm of a unit quaternion as the rotation vector theta k (rad) with
 * theta in [0, 2 pi): q = (cos(theta/2), sin(theta/2) k). Exact near zero. */
void kc_quat_log(const kc_quat *q, kc_vec3 *dest);
/* Unit quaternion of the rotation vector w (rad): exp of w/2. */
void kc_quat_exp(const kc_vec3 *w, kc_quat *dest);

/* ---- dual quaternion: seed 002 ---- */
void kc_dquat_identity(kc_dquat *dest);
/* Product dest = a b (pose a then b); dest may alias a or b. */
void kc_dquat_mul(const kc_dquat *a, const kc_dquat *b, kc_dquat *dest);
/* Quaternion conjugate of both parts, r* + eps d*: for a unit dual
 * quaternion this is the inverse pose. */
void kc_dquat_conj(const kc_dquat *a, kc_dquat *dest);
/* Unit dual quaternion of a pose: r from R (w >= 0), d = 1/2 t r. */
void kc_dquat_from_pose(const kc_pose *a, kc_dquat *dest);
/* Pose of a unit dual quaternion: t = 2 d r*. */
void kc_dquat_to_pose(const kc_dquat *a, kc_pose *dest);
/* Logarithm in the decoupled form used by DQ Robotics: the rotation vector
 * w = theta k (rad) of r and the translation v = t = 2 d r* (m), so that
 * log(a) = 1/2 (w + eps v). Defined for every unit dual quaternion, exact
 * near zero rotation. */
void kc_dquat_log(const kc_dquat *a, kc_vec3 *w, kc_vec3 *v);
/* Exponential: inverse of kc_dquat_log. */
void kc_dquat_exp(const kc_vec3 *w, const kc_vec3 *v, kc_dquat *dest);

KC_END_DECLS

#endif /* KINCTL_SE3_H */
