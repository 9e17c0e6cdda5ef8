/* SPDX-License-Identifier: BSD-3-Clause */
/* shape.c - the seed's volume primitives (seed 003, module 6) and the
 * distance between two of them. Behaviour documented in kinctl/shape.h.
 *
 * Every shape is a convex "core" (a point, a segment, a cylinder, a box, a
 * frustum) grown by a radius (spheres and capsules; 0 otherwise). The
 * distance of two shapes is the distance of their cores minus both radii;
 * the distance of two cores is the norm of the point of the Minkowski
 * difference A - B nearest the origin, found by GJK from the cores' support
 * functions s(d) = argmax_{x in core} d.x. */
#include "kinctl/shape.h"

#include "shape_internal.h"
#include "vec3_internal.h"

#define INF ((kc_real)INFINITY)

#define INF ((kc_real)INFINITY)

static int positive(kc_real x) { return kc_isfinite(x) && x > KC_R(0.0); }

static int dims_needed(int kind)
{
    switch (kind) {
    case KC_SHAPE_SPHERE: return 1;
    case KC_SHAPE_CAPSULE:
    case KC_SHAPE_CYLINDER: return 2;
    case KC_SHAPE_BOX: return 3;
    case KC_SHAPE_FRUSTUM: return 5;
    case KC_SHAPE_HALFSPACE: return 0;
    }
    return -1;
}

kc_status kc_shape_check(const kc_shape *s, int zone)
{
    if (s == NULL)
        return KC_E_ARG;
    int n = dims_needed(s->kind);
    if (n < 0 || (s->kind == KC_SHAPE_HALFSPACE && !zone))
        return KC_E_ARG;
    if (!kc_pose_isfinite(&s->pose) || kc_mat3_rotation_error(&s->pose.R) > KC_TOL_ORTHONORMAL)
        return KC_E_ARG;
    for (int i = 0; i < KC_SHAPE_DIMS; i++)
        if (!kc_isfinite(s->dim[i]) || (i < n && !positive(s->dim[i])))
            return KC_E_ARG;
    return KC_OK;
}

kc_status kc_shape_segment(int kind, const kc_vec3 *p0, const kc_vec3 *p1, kc_real r, kc_shape *shape)
{
    if (p0 == NULL || p1 == NULL || shape == NULL || (kind != KC_SHAPE_CAPSULE && kind != KC_SHAPE_CYLINDER) ||
        !positive(r) || !kc_vec3_isfinite(p0) || !kc_vec3_isfinite(p1))
        return KC_E_ARG;
    kc_vec3 d, z, x, y;
    kc_vec3_sub(p1, p0, &d);
    kc_real len = kc_vec3_norm(&d);
    if (!positive(len))
        return KC_E_ARG;
    kc_vec3_scale(&d, KC_R(1.0) / len, &z);
    /* Any x perpendicular to z: from the world axis least aligned with z. */
    kc_vec3 e = kc_fabs(z.v[0]) < KC_R(0.6) ? kc_vec3_make(KC_R(1.0), KC_R(0.0), KC_R(0.0))
                                            : kc_vec3_make(KC_R(0.0), KC_R(1.0), KC_R(0.0));
    kc_vec3_cross(&e, &z, &y);
    kc_vec3_scale(&y, KC_R(1.0) / kc_vec3_norm(&y), &y);
    kc_vec3_cross(&y, &z, &x);
    for (int i = 0; i < 3; i++) {
        shape->pose.R.m[i][0] = x.v[i];
        shape->pose.R.m[i][1] = y.v[i];
        shape->pose.R.m[i][2] = z.v[i];
        shape->pose.t.v[i] = KC_R(0.5) * (p0->v[i] + p1->v[i]);
        shape->dim[i] = KC_R(0.0);
    }
    shape->kind = kind;
    shape->dim[0] = r;
    shape->dim[1] = KC_R(0.5) * len;
    shape->dim[3] = shape->dim[4] = KC_R(0.0);
    return KC_OK;
}

kc_real kc_shape_bound_radius(const kc_shape *s)
{
    const kc_real *d = s->dim;
    switch (s->kind) {
    case KC_SHAPE_SPHERE: return d[0];
    case KC_SHAPE_CAPSULE: return d[0] + d[1];
    case KC_SHAPE_CYLINDER: return kc_hypot(d[0], d[1]);
    case KC_SHAPE_BOX: return kc_sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    case KC_SHAPE_FRUSTUM: return kc_hypot(kc_max(kc_hypot(d[0], d[1]), kc_hypot(d[2], d[3])), d[4]);
    }
    return INF;
}

void kc_shape_place(const kc_shape *shape, const kc_pose *at, kc_shape *dest)
{
    kc_pose p;
    kc_pose_mul(at, &shape->pose, &p);
    if (dest != shape)
        *dest = *shape;
    dest->pose = p;
}

/* The radius a shape's core is grown by. */
kc_real kc_shape_core_radius(const kc_shape *s)
{
    return s->kind == KC_SHAPE_SPHERE || s->kind == KC_SHAPE_CAPSULE ? s->dim[0] : KC_R(0.0);
}

static kc_real sign_of(kc_real x) { return x < KC_R(0.0) ? KC_R(-1.0) : KC_R(1.0); }

/* Support point of the shape's core in the world direction d. */
static kc_vec3 support(const kc_shape *s, const kc_vec3 *d)
{
    kc_vec3 l, p, w;
    const kc_real *dim = s->dim;
    kc_mat3_tmul_vec(&s->pose.R, d, &l);
    switch (s->kind) {
    case KC_SHAPE_CAPSULE: p = kc_vec3_make(KC_R(0.0), KC_R(0.0), sign_of(l.v[2]) * dim[1]); break;
    case KC_SHAPE_CYLINDER: {
        kc_real rxy = kc_hypot(l.v[0], l.v[1]);
        kc_real k = rxy > KC_R(0.0) ? dim[0] / rxy : KC_R(0.0);
        p = kc_vec3_make(l.v[0] * k, l.v[1] * k, sign_of(l.v[2]) * dim[1]);
        break;
    }
    case KC_SHAPE_BOX:
        p = kc_vec3_make(sign_of(l.v[0]) * dim[0], sign_of(l.v[1]) * dim[1], sign_of(l.v[2]) * dim[2]);
        break;
    case KC_SHAPE_FRUSTUM: {
        /* The best vertex of the bottom rectangle against that of the top. */
        kc_real sx = sign_of(l.v[0]), sy = sign_of(l.v[1]);
        kc_real bottom = dim[0] * kc_fabs(l.v[0]) + dim[1] * kc_fabs(l.v[1]) - dim[4] * l.v[2];
        kc_real top = dim[2] * kc_fabs(l.v[0]) + dim[3] * kc_fabs(l.v[1]) + dim[4] * l.v[2];
        p = top >= bottom ? kc_vec3_make(sx * dim[2], sy * dim[3], dim[4])
                          : kc_vec3_make(sx * dim[0], sy * dim[1], -dim[4]);
        break;
    }
    default: /* sphere: its centre */
        p = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
        break;
    }
    kc_pose_apply(&s->pose, &p, &w);
    return w;
}

/* ---- GJK ---- */

/* A simplex of 1 to 4 points of A - B. */
typedef struct simplex {
    int n;
    kc_vec3 p[4];
} simplex;

/* Closest point to the origin on segment ab; reduces s to the feature. */
static kc_vec3 closest_segment(simplex *s)
{
    kc_vec3 a = s->p[0], b = s->p[1], ab = kc_v3_sub(b, a);
    kc_real t = -kc_v3_dot(a, ab), len2 = kc_v3_dot(ab, ab);
    if (t <= KC_R(0.0) || !(len2 > KC_R(0.0))) {
        s->n = 1;
        return a;
    }
    if (t >= len2) {
        s->n = 1;
        s->p[0] = b;
        return b;
    }
    return kc_v3_add_scaled(a, ab, t / len2);
}

/* Closest point to the origin on triangle abc (Ericson, Real-Time Collision
 * Detection 5.1.5, with p = 0); reduces s to the feature it lies on. */
static kc_vec3 closest_triangle(simplex *s)
{
    kc_vec3 a = s->p[0], b = s->p[1], c = s->p[2];
    kc_vec3 ab = kc_v3_sub(b, a), ac = kc_v3_sub(c, a);
    kc_real d1 = -kc_v3_dot(ab, a), d2 = -kc_v3_dot(ac, a);
    if (d1 <= KC_R(0.0) && d2 <= KC_R(0.0)) {
        s->n = 1;
        return a;
    }
    kc_real d3 = -kc_v3_dot(ab, b), d4 = -kc_v3_dot(ac, b);
    if (d3 >= KC_R(0.0) && d4 <= d3) {
        s->n = 1;
        s->p[0] = b;
        return b;
    }
    kc_real vc = d1 * d4 - d3 * d2;
    if (vc <= KC_R(0.0) && d1 >= KC_R(0.0) && d3 <= KC_R(0.0)) {
        s->n = 2;
        return kc_v3_add_scaled(a, ab, d1 / (d1 - d3));
    }
    kc_real d5 = -kc_v3_dot(ab, c), d6 = -kc_v3_dot(ac, c);
    if (d6 >= KC_R(0.0) && d5 <= d6) {
        s->n = 1;
        s->p[0] = c;
        return c;
    }
    kc_real vb = d5 * d2 - d1 * d6;
    if (vb <= KC_R(0.0) && d2 >= KC_R(0.0) && d6 <= KC_R(0.0)) {
        s->n = 2;
        s->p[1] = c;
        return kc_v3_add_scaled(a, ac, d2 / (d2 - d6));
    }
    kc_real va = d3 * d6 - d5 * d4;
    if (va <= KC_R(0.0) && d4 - d3 >= KC_R(0.0) && d5 - d6 >= KC_R(0.0)) {
        s->n = 2;
        s->p[0] = b;
        s->p[1] = c;
        return kc_v3_add_scaled(b, kc_v3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    kc_real sum = va + vb + vc;
    if (!(sum > KC_R(0.0))) {
        /* Degenerate (collinear) triangle: its longest edge carries it. */
        s->n = 2;
        if (kc_v3_dot(ac, ac) > kc_v3_dot(ab, ab))
            s->p[1] = c;
        return closest_segment(s);
    }
    kc_real denom = KC_R(1.0) / sum;
    return kc_v3_add_scaled(kc_v3_add_scaled(a, ab, vb * denom), ac, vc * denom);
}

/* Closest point to the origin on tetrahedron abcd (Ericson 5.1.6): the
 * best of the faces the origin lies outside of; 0 (and n = 4) when the
 * origin is inside. */
static kc_vec3 closest_tetra(simplex *s)
{
    static const int face[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
    kc_vec3 best = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    kc_real best2 = INF;
    simplex keep = *s;
    int outside_any = 0;
    for (int f = 0; f < 4; f++) {
        kc_vec3 a = s->p[face[f][0]], b = s->p[face[f][1]], c = s->p[face[f][2]], d = s->p[face[f][3]];
        kc_vec3 nrm = kc_v3_cross(kc_v3_sub(b, a), kc_v3_sub(c, a));
        kc_real side_o = -kc_v3_dot(a, nrm), side_d = kc_v3_dot(kc_v3_sub(d, a), nrm);
        /* Outside this face (or a flat tetrahedron: try every face). */
        if (side_o * side_d < KC_R(0.0) || side_d == KC_R(0.0)) {
            simplex t;
            t.n = 3;
            t.p[0] = a;
            t.p[1] = b;
            t.p[2] = c;
            kc_vec3 q = closest_triangle(&t);
            kc_real q2 = kc_v3_dot(q, q);
            outside_any = 1;
            if (q2 < best2) {
                best2 = q2;
                best = q;
                keep = t;
            }
        }
    }
    if (!outside_any)
        return best; /* the origin is inside: the cores overlap */
    *s = keep;
    return best;
}

/* Lower bound (within KC_ZONE_TOL once converged) of the distance between
 * the cores of a and b. Stops early, with a lower bound above it, once the
 * distance is known to exceed stop (INF: run to convergence). */
kc_real kc_shape_gjk(const kc_shape *a, const kc_shape *b, kc_real stop)
{
    simplex s;
    kc_vec3 d = kc_v3_sub(a->pose.t, b->pose.t);
    if (!(kc_v3_dot(d, d) > KC_R(0.0)))
        d = kc_vec3_make(KC_R(1.0), KC_R(0.0), KC_R(0.0));
    kc_vec3 nd = kc_v3_neg(d);
    s.n = 1;
    s.p[0] = kc_v3_sub(support(a, &nd), support(b, &d));
    kc_vec3 v = s.p[0];
    kc_real lower = KC_R(0.0);
    /* Below this |v| the cores touch within the tolerance. */
    const kc_real tiny = KC_R(0.1) * KC_ZONE_TOL;
    for (int it = 0; it < KC_ZONE_GJK_ITERS; it++) {
        kc_real vv = kc_v3_dot(v, v);
        if (!(vv > tiny * tiny))
            return KC_R(0.0);
        kc_vec3 nv = kc_v3_neg(v);
        kc_vec3 w = kc_v3_sub(support(a, &nv), support(b, &v));
        kc_real norm = kc_sqrt(vv);
        lower = kc_max(lower, kc_v3_dot(v, w) / norm);
        if (norm - lower <= KC_ZONE_TOL || lower > stop)
            break;
        int dup = 0;
        for (int i = 0; i < s.n; i++)
            if (s.p[i].v[0] == w.v[0] && s.p[i].v[1] == w.v[1] && s.p[i].v[2] == w.v[2])
                dup = 1;
        if (dup)
            break; /* no progress possible: lower is what there is */
        s.p[s.n++] = w;
        switch (s.n) {
        case 2: v = closest_segment(&s); break;
        case 3: v = closest_triangle(&s); break;
        default: v = closest_tetra(&s); break;
        }
        if (s.n == 4)
            return KC_R(0.0); /* origin enclosed */
    }
    return kc_max(lower, KC_R(0.0));
}

/* Distance of a shape from a half-space zone: the plane's distance to the
 * core's deepest point along -n, minus the radius. */
kc_real kc_shape_halfspace_distance(const kc_shape *h, const kc_shape *s)
{
    kc_vec3 n = kc_vec3_make(h->pose.R.m[0][2], h->pose.R.m[1][2], h->pose.R.m[2][2]);
    kc_vec3 nn = kc_v3_neg(n);
    kc_vec3 p = support(s, &nn);
    return kc_max(kc_v3_dot(n, kc_v3_sub(p, h->pose.t)) - kc_shape_core_radius(s), KC_R(0.0));
}

kc_status kc_shape_distance(const kc_shape *a, const kc_shape *b, kc_real *dist)
{
    if (a == NULL || b == NULL || dist == NULL || dims_needed(a->kind) < 0 || dims_needed(b->kind) < 0 ||
        (a->kind == KC_SHAPE_HALFSPACE && b->kind == KC_SHAPE_HALFSPACE))
        return KC_E_ARG;
    if (a->kind == KC_SHAPE_HALFSPACE)
        *dist = kc_shape_halfspace_distance(a, b);
    else if (b->kind == KC_SHAPE_HALFSPACE)
        *dist = kc_shape_halfspace_distance(b, a);
    else
        *dist = kc_max(kc_shape_gjk(a, b, INF) - kc_shape_core_radius(a) - kc_shape_core_radius(b), KC_R(0.0));
    return KC_OK;
}
