/* SPDX-License-Identifier: BSD-3-Clause */
/* se3.c - vectors, rotations, poses, homogeneous transforms, (dual)
 * quaternions. See kinctl/se3.h for conventions. */
#include "kinctl/se3.h"

#include <string.h>

#include "vec3_internal.h"

/* ---- vec3 ---- */

void kc_vec3_add(const kc_vec3 *a, const kc_vec3 *b, kc_vec3 *dest) { *dest = kc_v3_add(*a, *b); }

void kc_vec3_sub(const kc_vec3 *a, const kc_vec3 *b, kc_vec3 *dest) { *dest = kc_v3_sub(*a, *b); }

void kc_vec3_scale(const kc_vec3 *a, kc_real s, kc_vec3 *dest) { *dest = kc_v3_scale(*a, s); }

kc_real kc_vec3_dot(const kc_vec3 *a, const kc_vec3 *b) { return kc_v3_dot(*a, *b); }

void kc_vec3_cross(const kc_vec3 *a, const kc_vec3 *b, kc_vec3 *dest) { *dest = kc_v3_cross(*a, *b); }

kc_real kc_vec3_norm(const kc_vec3 *a) { return kc_sqrt(kc_vec3_dot(a, a)); }

int kc_vec3_isfinite(const kc_vec3 *a)
{
    return kc_isfinite(a->v[0]) && kc_isfinite(a->v[1]) && kc_isfinite(a->v[2]);
}

/* ---- mat3 ---- */

void kc_mat3_identity(kc_mat3 *dest)
{
    memset(dest, 0, sizeof *dest);
    dest->m[0][0] = dest->m[1][1] = dest->m[2][2] = KC_R(1.0);
}

void kc_mat3_rot(kc_axis axis, kc_real angle, kc_mat3 *dest)
{
    kc_real s, c;
    kc_sincos(angle, &s, &c);
    /* The two axes that turn, in right-handed order: (i, j) with k = axis. */
    int i = ((int)axis + 1) % 3, j = ((int)axis + 2) % 3;
    kc_mat3_identity(dest);
    dest->m[i][i] = c;
    dest->m[i][j] = -s;
    dest->m[j][i] = s;
    dest->m[j][j] = c;
}

void kc_mat3_mul(const kc_mat3 *a, const kc_mat3 *b, kc_mat3 *dest)
{
    kc_mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] + a->m[i][2] * b->m[2][j];
    *dest = r;
}

void kc_mat3_tmul(const kc_mat3 *a, const kc_mat3 *b, kc_mat3 *dest)
{
    kc_mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a->m[0][i] * b->m[0][j] + a->m[1][i] * b->m[1][j] + a->m[2][i] * b->m[2][j];
    *dest = r;
}

void kc_mat3_transpose(const kc_mat3 *a, kc_mat3 *dest)
{
    kc_mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a->m[j][i];
    *dest = r;
}

void kc_mat3_mul_vec(const kc_mat3 *a, const kc_vec3 *v, kc_vec3 *dest)
{
    kc_vec3 r;
    for (int i = 0; i < 3; i++)
        r.v[i] = a->m[i][0] * v->v[0] + a->m[i][1] * v->v[1] + a->m[i][2] * v->v[2];
    *dest = r;
}

void kc_mat3_tmul_vec(const kc_mat3 *a, const kc_vec3 *v, kc_vec3 *dest)
{
    kc_vec3 r;
    for (int i = 0; i < 3; i++)
        r.v[i] = a->m[0][i] * v->v[0] + a->m[1][i] * v->v[1] + a->m[2][i] * v->v[2];
    *dest = r;
}

static kc_real mat3_det(const kc_mat3 *a)
{
    const kc_real(*m)[3] = a->m;
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* |(A^T A)_ij - I_ij|: column i dotted with column j. */
#define ATA_ERR(m, i, j) \
    kc_fabs((m)[0][i] * (m)[0][j] + (m)[1][i] * (m)[1][j] + (m)[2][i] * (m)[2][j] - ((i) == (j) ? KC_R(1.0) : KC_R(0.0)))

/* The larger of err and e, NaN once either is: a NaN e replaces err, and
 * once err is NaN (err != err) it stays, where "!(e <= err)" alone let the
 * next finite entry overwrite it (found by tests/unit/test_se3.c). */
static inline kc_real worse(kc_real err, kc_real e) { return err == err && !(e <= err) ? e : err; }

kc_real kc_mat3_rotation_error(const kc_mat3 *a)
{
    const kc_real(*m)[3] = a->m;
    kc_real err = kc_fabs(mat3_det(a) - KC_R(1.0));
    /* The entries of A^T A on and above the diagonal, written out (every
     * goal and plan checks a pose): each entry below it sums the same
     * products in the same order, so it is the same number. */
    err = worse(err, ATA_ERR(m, 0, 0));
    err = worse(err, ATA_ERR(m, 0, 1));
    err = worse(err, ATA_ERR(m, 0, 2));
    err = worse(err, ATA_ERR(m, 1, 1));
    err = worse(err, ATA_ERR(m, 1, 2));
    err = worse(err, ATA_ERR(m, 2, 2));
    return err;
}

kc_status kc_mat3_orthonormalize(const kc_mat3 *a, kc_mat3 *dest)
{
    kc_vec3 x = kc_vec3_make(a->m[0][0], a->m[1][0], a->m[2][0]);
    kc_vec3 y = kc_vec3_make(a->m[0][1], a->m[1][1], a->m[2][1]);
    kc_vec3 z;
    kc_real nx = kc_vec3_norm(&x);
    if (!(nx > KC_REAL_EPS) || !kc_isfinite(nx))
        return KC_E_ARG;
    kc_vec3_scale(&x, KC_R(1.0) / nx, &x);
    kc_vec3_cross(&x, &y, &z);
    kc_real nz = kc_vec3_norm(&z);
    if (!(nz > KC_REAL_EPS) || !kc_isfinite(nz))
        return KC_E_ARG;
    kc_vec3_scale(&z, KC_R(1.0) / nz, &z);
    kc_vec3_cross(&z, &x, &y);
    for (int i = 0; i < 3; i++) {
        dest->m[i][0] = x.v[i];
        dest->m[i][1] = y.v[i];
        dest->m[i][2] = z.v[i];
    }
    return KC_OK;
}

/* ---- pose ---- */

void kc_pose_identity(kc_pose *dest)
{
    kc_mat3_identity(&dest->R);
    dest->t = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
}

void kc_pose_mul(const kc_pose *a, const kc_pose *b, kc_pose *dest)
{
    kc_pose r;
    kc_mat3_mul(&a->R, &b->R, &r.R);
    kc_mat3_mul_vec(&a->R, &b->t, &r.t);
    kc_vec3_add(&r.t, &a->t, &r.t);
    *dest = r;
}

void kc_pose_inv(const kc_pose *a, kc_pose *dest)
{
    kc_pose r;
    kc_mat3_transpose(&a->R, &r.R);
    kc_mat3_mul_vec(&r.R, &a->t, &r.t);
    kc_vec3_scale(&r.t, KC_R(-1.0), &r.t);
    *dest = r;
}

void kc_pose_apply(const kc_pose *a, const kc_vec3 *p, kc_vec3 *dest)
{
    kc_vec3 r;
    kc_mat3_mul_vec(&a->R, p, &r);
    kc_vec3_add(&r, &a->t, dest);
}

void kc_pose_to_mat4(const kc_pose *a, kc_mat4 *dest)
{
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            dest->m[i][j] = a->R.m[i][j];
        dest->m[i][3] = a->t.v[i];
        dest->m[3][i] = KC_R(0.0);
    }
    dest->m[3][3] = KC_R(1.0);
}

kc_status kc_pose_from_mat4(const kc_mat4 *a, kc_pose *dest)
{
    kc_pose r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            if (!kc_isfinite(a->m[i][j]))
                return KC_E_ARG;
    if (a->m[3][0] != KC_R(0.0) || a->m[3][1] != KC_R(0.0) || a->m[3][2] != KC_R(0.0) ||
        a->m[3][3] != KC_R(1.0))
        return KC_E_ARG;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            r.R.m[i][j] = a->m[i][j];
        r.t.v[i] = a->m[i][3];
    }
    if (!(kc_mat3_rotation_error(&r.R) <= KC_TOL_ORTHONORMAL))
        return KC_E_ARG;
    *dest = r;
    return KC_OK;
}

int kc_pose_isfinite(const kc_pose *a)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (!kc_isfinite(a->R.m[i][j]))
                return 0;
    return kc_vec3_isfinite(&a->t);
}

/* ---- mat4 ---- */

void kc_mat4_identity(kc_mat4 *dest)
{
    memset(dest, 0, sizeof *dest);
    for (int i = 0; i < 4; i++)
        dest->m[i][i] = KC_R(1.0);
}

void kc_mat4_mul(const kc_mat4 *a, const kc_mat4 *b, kc_mat4 *dest)
{
    kc_mat4 r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] +
                        a->m[i][2] * b->m[2][j] + a->m[i][3] * b->m[3][j];
    *dest = r;
}

void kc_mat4_translation(kc_real dx, kc_real dy, kc_real dz, kc_mat4 *dest)
{
    kc_mat4_identity(dest);
    dest->m[0][3] = dx;
    dest->m[1][3] = dy;
    dest->m[2][3] = dz;
}

void kc_mat4_rotation(kc_axis axis, kc_real angle, kc_mat4 *dest)
{
    kc_pose p;
    kc_mat3_rot(axis, angle, &p.R);
    p.t = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    kc_pose_to_mat4(&p, dest);
}

kc_status kc_mat4_scale(kc_real s, kc_mat4 *dest)
{
    if (!kc_isfinite(s) || s == KC_R(0.0))
        return KC_E_ARG;
    kc_mat4_identity(dest);
    dest->m[3][3] = s;
    return KC_OK;
}

kc_status kc_mat4_perspective(kc_axis axis, kc_real f, kc_mat4 *dest)
{
    if (!kc_isfinite(f) || f == KC_R(0.0) || (unsigned)axis > 2u)
        return KC_E_ARG;
    kc_mat4_identity(dest);
    dest->m[3][axis] = KC_R(-1.0) / f;
    return KC_OK;
}

void kc_mat4_apply_h(const kc_mat4 *a, const kc_vec3 *p, kc_real dest[4])
{
    for (int i = 0; i < 4; i++)
        dest[i] = a->m[i][0] * p->v[0] + a->m[i][1] * p->v[1] + a->m[i][2] * p->v[2] + a->m[i][3];
}

kc_status kc_mat4_apply(const kc_mat4 *a, const kc_vec3 *p, kc_vec3 *dest)
{
    kc_real h[4];
    kc_mat4_apply_h(a, p, h);
    if (h[3] == KC_R(0.0) || !kc_isfinite(h[3]))
        return KC_E_SINGULAR;
    *dest = kc_vec3_make(h[0] / h[3], h[1] / h[3], h[2] / h[3]);
    return KC_OK;
}

/* ---- quaternion ---- */

void kc_quat_identity(kc_quat *dest)
{
    dest->w = KC_R(1.0);
    dest->x = dest->y = dest->z = KC_R(0.0);
}

void kc_quat_mul(const kc_quat *a, const kc_quat *b, kc_quat *dest)
{
    kc_quat r;
    r.w = a->w * b->w - a->x * b->x - a->y * b->y - a->z * b->z;
    r.x = a->w * b->x + a->x * b->w + a->y * b->z - a->z * b->y;
    r.y = a->w * b->y - a->x * b->z + a->y * b->w + a->z * b->x;
    r.z = a->w * b->z + a->x * b->y - a->y * b->x + a->z * b->w;
    *dest = r;
}

void kc_quat_conj(const kc_quat *a, kc_quat *dest)
{
    dest->w = a->w;
    dest->x = -a->x;
    dest->y = -a->y;
    dest->z = -a->z;
}

kc_real kc_quat_norm(const kc_quat *a)
{
    return kc_sqrt(a->w * a->w + a->x * a->x + a->y * a->y + a->z * a->z);
}

kc_status kc_quat_normalize(const kc_quat *a, kc_quat *dest)
{
    kc_real n = kc_quat_norm(a);
    if (!(n > KC_R(0.0)) || !kc_isfinite(n))
        return KC_E_ARG;
    kc_real s = KC_R(1.0) / n;
    dest->w = a->w * s;
    dest->x = a->x * s;
    dest->y = a->y * s;
    dest->z = a->z * s;
    return KC_OK;
}

void kc_quat_from_mat3(const kc_mat3 *R, kc_quat *dest)
{
    /* Shepperd: compute the largest of 4w^2, 4x^2, 4y^2, 4z^2 from the
     * diagonal and take the other components from off-diagonal sums, so the
     * division is always by a number of at least 1. */
    const kc_real(*m)[3] = R->m;
    kc_real tr = m[0][0] + m[1][1] + m[2][2];
    kc_quat q;
    if (tr >= m[0][0] && tr >= m[1][1] && tr >= m[2][2]) {
        kc_real s = kc_sqrt(KC_R(1.0) + tr) * KC_R(2.0); /* 4w */
        q.w = KC_R(0.25) * s;
        q.x = (m[2][1] - m[1][2]) / s;
        q.y = (m[0][2] - m[2][0]) / s;
        q.z = (m[1][0] - m[0][1]) / s;
    } else if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
        kc_real s = kc_sqrt(KC_R(1.0) + m[0][0] - m[1][1] - m[2][2]) * KC_R(2.0); /* 4x */
        q.w = (m[2][1] - m[1][2]) / s;
        q.x = KC_R(0.25) * s;
        q.y = (m[0][1] + m[1][0]) / s;
        q.z = (m[0][2] + m[2][0]) / s;
    } else if (m[1][1] >= m[2][2]) {
        kc_real s = kc_sqrt(KC_R(1.0) + m[1][1] - m[0][0] - m[2][2]) * KC_R(2.0); /* 4y */
        q.w = (m[0][2] - m[2][0]) / s;
        q.x = (m[0][1] + m[1][0]) / s;
        q.y = KC_R(0.25) * s;
        q.z = (m[1][2] + m[2][1]) / s;
    } else {
        kc_real s = kc_sqrt(KC_R(1.0) + m[2][2] - m[0][0] - m[1][1]) * KC_R(2.0); /* 4z */
        q.w = (m[1][0] - m[0][1]) / s;
        q.x = (m[0][2] + m[2][0]) / s;
        q.y = (m[1][2] + m[2][1]) / s;
        q.z = KC_R(0.25) * s;
    }
    if (q.w < KC_R(0.0)) {
        q.w = -q.w;
        q.x = -q.x;
        q.y = -q.y;
        q.z = -q.z;
    }
    if (kc_quat_normalize(&q, dest) != KC_OK)
        kc_quat_identity(dest); /* only for a non-finite R */
}

void kc_quat_to_mat3(const kc_quat *q, kc_mat3 *dest)
{
    kc_real w = q->w, x = q->x, y = q->y, z = q->z;
    dest->m[0][0] = KC_R(1.0) - KC_R(2.0) * (y * y + z * z);
    dest->m[0][1] = KC_R(2.0) * (x * y - w * z);
    dest->m[0][2] = KC_R(2.0) * (x * z + w * y);
    dest->m[1][0] = KC_R(2.0) * (x * y + w * z);
    dest->m[1][1] = KC_R(1.0) - KC_R(2.0) * (x * x + z * z);
    dest->m[1][2] = KC_R(2.0) * (y * z - w * x);
    dest->m[2][0] = KC_R(2.0) * (x * z - w * y);
    dest->m[2][1] = KC_R(2.0) * (y * z + w * x);
    dest->m[2][2] = KC_R(1.0) - KC_R(2.0) * (x * x + y * y);
}

void kc_quat_rotate(const kc_quat *q, const kc_vec3 *v, kc_vec3 *dest)
{
    /* v' = v + 2 u x (u x v + w v), u the vector part: 18 multiplications. */
    kc_vec3 u = kc_vec3_make(q->x, q->y, q->z), t, r;
    kc_vec3_cross(&u, v, &t);
    for (int i = 0; i < 3; i++)
        t.v[i] += q->w * v->v[i];
    kc_vec3_cross(&u, &t, &r);
    for (int i = 0; i < 3; i++)
        dest->v[i] = v->v[i] + KC_R(2.0) * r.v[i];
}

void kc_quat_log(const kc_quat *q, kc_vec3 *dest)
{
    kc_real s = kc_sqrt(q->x * q->x + q->y * q->y + q->z * q->z);
    /* theta = 2 atan2(|u|, w) is accurate at every angle, unlike acos(w). */
    kc_real theta = KC_R(2.0) * kc_atan2(s, q->w);
    /* atan2 keeps theta/s accurate down to the smallest s; at s = 0 the
     * vector part is zero and so is the result. */
    kc_real k = s > KC_R(0.0) ? theta / s : KC_R(0.0);
    *dest = kc_vec3_make(q->x * k, q->y * k, q->z * k);
}

void kc_quat_exp(const kc_vec3 *w, kc_quat *dest)
{
    kc_real theta = kc_vec3_norm(w);
    kc_real s, c;
    kc_sincos(KC_R(0.5) * theta, &s, &c);
    /* sin(theta/2)/theta -> 1/2 - theta^2/48 as theta -> 0. */
    kc_real k = theta < KC_TOL_SMALL_ANGLE ? KC_R(0.5) - theta * theta / KC_R(48.0) : s / theta;
    dest->w = c;
    dest->x = w->v[0] * k;
    dest->y = w->v[1] * k;
    dest->z = w->v[2] * k;
}

/* ---- dual quaternion ---- */

void kc_dquat_identity(kc_dquat *dest)
{
    kc_quat_identity(&dest->r);
    dest->d.w = dest->d.x = dest->d.y = dest->d.z = KC_R(0.0);
}

void kc_dquat_mul(const kc_dquat *a, const kc_dquat *b, kc_dquat *dest)
{
    /* (ar + eps ad)(br + eps bd) = ar br + eps (ar bd + ad br), eps^2 = 0. */
    kc_dquat r;
    kc_quat t1, t2;
    kc_quat_mul(&a->r, &b->r, &r.r);
    kc_quat_mul(&a->r, &b->d, &t1);
    kc_quat_mul(&a->d, &b->r, &t2);
    r.d.w = t1.w + t2.w;
    r.d.x = t1.x + t2.x;
    r.d.y = t1.y + t2.y;
    r.d.z = t1.z + t2.z;
    *dest = r;
}

void kc_dquat_conj(const kc_dquat *a, kc_dquat *dest)
{
    kc_quat_conj(&a->r, &dest->r);
    kc_quat_conj(&a->d, &dest->d);
}

void kc_dquat_from_pose(const kc_pose *a, kc_dquat *dest)
{
    kc_quat t = {KC_R(0.0), a->t.v[0], a->t.v[1], a->t.v[2]};
    kc_quat_from_mat3(&a->R, &dest->r);
    kc_quat_mul(&t, &dest->r, &dest->d);
    dest->d.w *= KC_R(0.5);
    dest->d.x *= KC_R(0.5);
    dest->d.y *= KC_R(0.5);
    dest->d.z *= KC_R(0.5);
}

/* Translation of a unit dual quaternion: vector part of 2 d r*. */
static void dquat_translation(const kc_dquat *a, kc_vec3 *t)
{
    kc_quat rc, tq;
    kc_quat_conj(&a->r, &rc);
    kc_quat_mul(&a->d, &rc, &tq);
    *t = kc_vec3_make(KC_R(2.0) * tq.x, KC_R(2.0) * tq.y, KC_R(2.0) * tq.z);
}

void kc_dquat_to_pose(const kc_dquat *a, kc_pose *dest)
{
    kc_quat_to_mat3(&a->r, &dest->R);
    dquat_translation(a, &dest->t);
}

void kc_dquat_log(const kc_dquat *a, kc_vec3 *w, kc_vec3 *v)
{
    kc_vec3 t;
    dquat_translation(a, &t);
    kc_quat_log(&a->r, w);
    *v = t;
}

void kc_dquat_exp(const kc_vec3 *w, const kc_vec3 *v, kc_dquat *dest)
{
    kc_quat_exp(w, &dest->r);
    kc_quat t = {KC_R(0.0), v->v[0], v->v[1], v->v[2]};
    kc_quat_mul(&t, &dest->r, &dest->d);
    dest->d.w *= KC_R(0.5);
    dest->d.x *= KC_R(0.5);
    dest->d.y *= KC_R(0.5);
    dest->d.z *= KC_R(0.5);
}
