/*
 * kinctl/zone.h - link volumes, forbidden zones and the distance between
 * them.
 *
 * Seed 003, module 6 ("the intersection of the manipulator's links with
 * forbidden zones"): every frame O_k may carry a volume primitive (the seed's
 * prism, truncated pyramid, cylinder of revolution), placed in O_k by a code
 * that says which of O_k's axes is the primitive's axis (n_o = 1, 2, 3 for
 * x, y, z); the workspace carries forbidden zones. Here a primitive is a
 * kc_shape: a kind, a rigid placement (pose) and its sizes; the placement
 * generalises the seed's axis code (its rotation takes the shape's z axis to
 * any axis of O_k). The chain carries its volumes (kc_chain.volumes, added
 * with kc_chain_add_volume); a kc_zone_set carries the zones, in the world
 * (base) frame.
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
 * Every kind may be a zone; every kind but the half-space a link volume.
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
 * The check. kc_zone_check judges the link volumes of a chain at joints q
 * against a zone set: every distance must be at least the set's margin. A
 * pair whose bounding spheres are farther apart than margin + near is not
 * computed exactly (the bounding-sphere gap is a lower bound of its
 * distance), nor is one once GJK shows it farther than the closest pair so
 * far; so the cost is at most n_volumes x n_zones GJK runs and usually
 * far less: with 10 zones, 3.4 us (median over configurations) and 8.7 us
 * (worst of 1024) for the PUMA 560's 5 volumes, 4.8 and 13 us for the
 * Panda's 8, FK's frames included (tools/bench/zone_bench.c, this machine).
 *
 * Between samples. A point of a volume on frame k moves, for a change dq of
 * the joints, at most sum_j |dq_j| lever_j, lever_j (kc_zone_levers) being
 * a configuration-independent bound on the distance from joint j's axis to
 * any point of a volume beyond it (1 for a prismatic joint). At most
 * qd_max_j dt per tick, a point so moves at most kc_zone_tick_travel per
 * tick: when that is below the margin, a motion whose every tick keeps the
 * margin cannot put a volume into a zone between two ticks. kc_ctrl checks
 * every tick of a goal before it is accepted and refuses a zone set whose
 * margin is not above this bound (see kinctl/ctrl.h).
 *
 * Everything here is pure, allocates nothing, runs in bounded time and is
 * safe to call in the cycle and from several threads.
 */
#ifndef KINCTL_ZONE_H
#define KINCTL_ZONE_H

#include "kinctl/se3.h"

/* Compile-time capacities. */
#define KC_ZONE_MAX 16
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

/* ---- zone sets ---- */

typedef struct kc_zone_set {
    int n_zones;
    kc_shape zones[KC_ZONE_MAX]; /* world frame */
    /* Smallest distance (m) any link volume must keep from any zone. */
    kc_real margin;
    /* Pairs whose bounding-sphere gap exceeds margin + near are not
     * computed exactly: kc_zone_check's distance is exact below margin +
     * near and a lower bound above it (m, >= 0). */
    kc_real near;
} kc_zone_set;

/* Empty set, margin 0.02 m, near 0.25 m. KC_E_ARG for NULL. */
kc_status kc_zone_set_init(kc_zone_set *set);

/* Appends a zone (checked with kc_shape_check(zone, 1)): KC_E_ARG for a bad
 * shape, KC_E_CAPACITY when full; the set is unchanged on error. */
kc_status kc_zone_set_add(kc_zone_set *set, const kc_shape *zone);

/* KC_OK for a set with 0..KC_ZONE_MAX valid zones, margin >= 0 and near >=
 * 0, all finite. */
kc_status kc_zone_set_check(const kc_zone_set *set);

/* The closest pair of a check. */
typedef struct kc_zone_hit {
    int volume;       /* index into chain->volumes, -1 when none */
    int zone;         /* index into set->zones, -1 when none */
    kc_real distance; /* smallest distance found (m); infinite when no pair */
} kc_zone_hit;

/* forward declaration: kinctl/chain.h includes this header */
struct kc_chain;

/* The world pose of every link volume at joints q: volumes[i] for
 * chain->volumes[i] (chain->n_volumes shapes). frames are the chain's frames
 * at q (kc_fk_frames). */
kc_status kc_zone_volumes_world(const struct kc_chain *chain, const kc_pose *frames, kc_shape *volumes);

/* Every distance at q: dist[i * set->n_zones + z] for volume i and zone z,
 * each exact (no bounding-sphere shortcut). Not needed in the cycle; bounded
 * all the same. */
kc_status kc_zone_distances(const struct kc_chain *chain, const kc_zone_set *set, const kc_real *q, kc_real *dist);

/* The check at q (frames at q, from kc_fk_frames, or NULL to compute them):
 * KC_OK when every volume keeps at least set->margin from every zone,
 * KC_E_LIMIT when some pair is closer; either way *hit (if not NULL) is the
 * closest pair (exact below margin + near, see kc_zone_set). KC_E_ARG for
 * NULL chain, set or q, or a non-finite q. Cycle-safe. */
kc_status kc_zone_check(const struct kc_chain *chain, const kc_zone_set *set, const kc_real *q,
                        const kc_pose *frames, kc_zone_hit *hit);

/* Lever of each joint (lever[j], j < chain->n_joints): for a revolute joint
 * a bound (m) on the distance of any point of a volume on a later frame
 * from the joint's axis, for every q (the sum of the constant translations
 * and prismatic travels after it, plus the volume's offset and bounding
 * radius); for a prismatic joint 1; 0 when no volume moves with the joint.
 * A volume point then moves at most sum_j |dq_j| lever_j. */
void kc_zone_levers(const struct kc_chain *chain, kc_real *lever);

/* sum_j qd_max_j dt lever_j: the farthest any point of any volume can move
 * in one tick of dt (s) at the joints' velocity limits (m). */
kc_real kc_zone_tick_travel(const struct kc_chain *chain, kc_real dt);

#endif /* KINCTL_ZONE_H */
