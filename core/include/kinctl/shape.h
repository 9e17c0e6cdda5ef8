/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/shape.h - convex volume primitives and the distance between two.
 *
 * Seed 003, module 6: a frame may carry a volume primitive (the seed's
 * prism, truncated pyramid, cylinder of revolution), placed by a code that
 * says which axis is the primitive's axis. Here a primitive is a kc_shape:
 * a kind, a rigid placement (pose) and its sizes; the placement generalises
 * the seed's axis code (its rotation takes the shape's z axis to any axis).
 * Link volumes (kinctl/chain.h) and forbidden zones (kinctl/zone.h) are
 * shapes.
 *
 * Shapes, in their own frame (lengths in m, every size > 0 and finite):
 *   KC_SHAPE_SPHERE     dim[0] = radius, centred on the origin;
 *   KC_SHAPE_CAPSULE    dim[0] = radius, dim[1] = half-length: every point
 *                       within radius of the segment z in [-h, h];
 *   KC_SHAPE_CYLINDER   dim[0] = radius, dim[1] = half-length: the solid
 *                       cylinder x^2 + y^2 <= r^2, |z| <= h;
 *   KC_SHAPE_BOX        dim[0..2] = half extents along x, y, z (the seed's
 *                       prism with a rectangular section);
 *   KC_SHAPE_FRUSTUM    the seed's truncated pyramid: the convex hull of the
 *                       rectangle |x| <= dim[0], |y| <= dim[1] at z = -dim[4]
 *                       and the rectangle |x| <= dim[2], |y| <= dim[3] at
 *                       z = +dim[4] (equal rectangles make a prism);
 *   KC_SHAPE_HALFSPACE  zones only: the side z < 0 of the plane through the
 *                       pose's origin with normal the pose's z axis (the
 *                       normal points out of the zone, into free space): a
 *                       table top is the half-space below z = 0 with normal
 *                       +z; a wall at x = 0.6 is the pose (0.6, 0, 0) with
 *                       its z axis along -x.
 * Every kind may be a zone; every kind but the half-space a link volume
 * (kinctl/zone.h).
 *
 * Distance. kc_shape_distance is the Euclidean distance between two shapes
 * (0 when they touch or overlap; the depth of an overlap is not measured).
 * Spheres and capsules are a point or a segment swept by a radius: the
 * distance of the cores minus the radii. A half-space is exact and closed
 * form: the plane's distance to the shape's deepest support point. Any
 * other pair is the GJK distance of two convex sets (Gilbert, Johnson and
 * Keerthi 1988) from their support functions, at most KC_ZONE_GJK_ITERS
 * iterations: what is returned is GJK's lower bound v.w/|v|, never more than
 * the true distance, and within KC_ZONE_TOL of it once converged. Between
 * polytopes, points and segments (boxes, frusta, spheres' and capsules'
 * cores) GJK ends on the exact answer in a few iterations; a cylinder's
 * curved side converges linearly (over the 6 million GJK runs of a
 * tools/bench/zone_bench.c run none needed more than 27 of the 32). So the
 * test is exact (to rounding) for every pair without a cylinder, and for
 * cylinders conservative by at most KC_ZONE_TOL: a distance is never
 * overstated, so a check may stop the arm KC_ZONE_TOL early, never late.
 *
 *
 * Everything here is pure, allocates nothing, runs in bounded time and is
 * safe to call in the cycle and from several threads.
 */
#ifndef KINCTL_SHAPE_H
#define KINCTL_SHAPE_H

#include "kinctl/decls.h"
#include "kinctl/real.h"
#include "kinctl/se3.h"
#include "kinctl/status.h"

KC_BEGIN_DECLS

/* Sizes of a shape. */
#define KC_SHAPE_DIMS 5
/* Bound on GJK's iterations per pair. */
#define KC_ZONE_GJK_ITERS 32

/* Absolute accuracy of a converged GJK distance (m). */
#ifdef KC_REAL_FLOAT
#define KC_ZONE_TOL KC_R(2e-5)
#else
#define KC_ZONE_TOL KC_R(1e-9)
#endif

typedef enum kc_shape_kind {
    KC_SHAPE_SPHERE = 1,
    KC_SHAPE_CAPSULE = 2,
    KC_SHAPE_CYLINDER = 3,
    KC_SHAPE_BOX = 4,
    KC_SHAPE_FRUSTUM = 5,
    KC_SHAPE_HALFSPACE = 6
} kc_shape_kind;

typedef struct kc_shape {
    int kind;                  /* kc_shape_kind */
    kc_pose pose;              /* placement in its frame (link volume) or the world (zone) */
    kc_real dim[KC_SHAPE_DIMS]; /* sizes (m), per kind as above; unused ones 0 */
} kc_shape;

/* KC_OK when the shape is usable: a known kind, a rigid finite pose, its
 * sizes finite and > 0 (a frustum: both rectangles and the height). A
 * half-space is allowed only when zone is nonzero. KC_E_ARG otherwise. */
kc_status kc_shape_check(const kc_shape *shape, int zone);

/* A capsule or cylinder (kind) of radius r whose axis runs from p0 to p1
 * (distinct points, in the frame the shape is placed in); KC_E_ARG for a
 * bad kind, radius or p0 = p1, with *shape untouched. */
kc_status kc_shape_segment(int kind, const kc_vec3 *p0, const kc_vec3 *p1, kc_real r, kc_shape *shape);

/* Radius of a sphere about the shape's origin that holds it (infinite for
 * a half-space). */
kc_real kc_shape_bound_radius(const kc_shape *shape);

/* The shape moved by a pose: *dest = *shape with pose = at * shape->pose.
 * dest may alias shape. */
void kc_shape_place(const kc_shape *shape, const kc_pose *at, kc_shape *dest);

/* Distance (m) between two shapes whose poses are in the same frame; 0 for
 * shapes that touch or overlap. Exact or conservative as said above. At
 * most one of them may be a half-space. KC_E_ARG (with *dist untouched)
 * for NULL, two half-spaces or an unknown kind; shapes are not otherwise
 * validated (kc_shape_check them once). */
kc_status kc_shape_distance(const kc_shape *a, const kc_shape *b, kc_real *dist);

KC_END_DECLS

#endif /* KINCTL_SHAPE_H */
