/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/zone.h - forbidden zones: a chain's link volumes checked against
 * a set of zones at joints q.
 *
 * Seed 003, module 6 ("the intersection of the manipulator's links with
 * forbidden zones"): every frame O_k may carry a volume primitive (the seed's
 * prism, truncated pyramid, cylinder of revolution), placed in O_k by a code
 * that says which of O_k's axes is the primitive's axis (n_o = 1, 2, 3 for
 * x, y, z); the workspace carries forbidden zones. Here a primitive is a
 * kc_shape (kinctl/shape.h: the kinds, their sizes and the distance
 * between two shapes). The chain carries its volumes (kc_chain.volumes,
 * added with kc_chain_add_volume); a kc_zone_set carries the zones, in the
 * world (base) frame.
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

#include "kinctl/chain.h"
#include "kinctl/decls.h"
#include "kinctl/se3.h"
#include "kinctl/shape.h"

KC_BEGIN_DECLS

/* Most zones of a set. */
#define KC_ZONE_MAX 16

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

KC_END_DECLS

#endif /* KINCTL_ZONE_H */
