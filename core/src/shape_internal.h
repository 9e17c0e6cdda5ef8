/* SPDX-License-Identifier: BSD-3-Clause */
/* shape_internal.h - the parts of a shape distance (shape.c) that the zone
 * check (zone.c) runs itself, to stop early on pairs farther than the
 * closest so far. Private to the core. */
#ifndef KINCTL_SHAPE_INTERNAL_H
#define KINCTL_SHAPE_INTERNAL_H

#include "kinctl/shape.h"

/* The radius a shape's core is grown by (spheres and capsules; 0 else). */
kc_real kc_shape_core_radius(const kc_shape *s);

/* Lower bound (within KC_ZONE_TOL once converged) of the distance between
 * the cores of a and b. Stops early, with a lower bound above it, once the
 * distance is known to exceed stop (INFINITY: run to convergence). */
kc_real kc_shape_gjk(const kc_shape *a, const kc_shape *b, kc_real stop);

/* Distance of shape s from the half-space zone h. */
kc_real kc_shape_halfspace_distance(const kc_shape *h, const kc_shape *s);

#endif /* KINCTL_SHAPE_INTERNAL_H */
