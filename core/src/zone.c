/* SPDX-License-Identifier: BSD-3-Clause */
/* zone.c - link volumes against forbidden zones (seed 003, module 6): zone
 * sets, the check of a chain's volumes at q, and the bound on the travel of
 * a volume between two samples. Behaviour documented in kinctl/zone.h;
 * shapes and their distances are shape.c's. */
#include "kinctl/zone.h"

#include <string.h>

#include "kinctl/chain.h"
#include "kinctl/fk.h"

#include "shape_internal.h"
#include "vec3_internal.h"

#define INF ((kc_real)INFINITY)

/* ---- zone sets ---- */

kc_status kc_zone_set_init(kc_zone_set *set)
{
    if (set == NULL)
        return KC_E_ARG;
    memset(set, 0, sizeof *set); /* unused entries too: a set compares and copies as plain bytes */
    set->margin = KC_R(0.02);
    set->near = KC_R(0.25);
    return KC_OK;
}

kc_status kc_zone_set_add(kc_zone_set *set, const kc_shape *zone)
{
    if (set == NULL || kc_shape_check(zone, 1) != KC_OK || set->n_zones < 0)
        return KC_E_ARG;
    if (set->n_zones >= KC_ZONE_MAX)
        return KC_E_CAPACITY;
    set->zones[set->n_zones++] = *zone;
    return KC_OK;
}

kc_status kc_zone_set_check(const kc_zone_set *set)
{
    if (set == NULL || set->n_zones < 0 || set->n_zones > KC_ZONE_MAX || !kc_isfinite(set->margin) ||
        set->margin < KC_R(0.0) || !kc_isfinite(set->near) || set->near < KC_R(0.0))
        return KC_E_ARG;
    for (int z = 0; z < set->n_zones; z++)
        if (kc_shape_check(&set->zones[z], 1) != KC_OK)
            return KC_E_ARG;
    return KC_OK;
}

kc_status kc_zone_volumes_world(const kc_chain *chain, const kc_pose *frames, kc_shape *volumes)
{
    if (chain == NULL || frames == NULL || volumes == NULL)
        return KC_E_ARG;
    for (int i = 0; i < chain->n_volumes; i++)
        kc_shape_place(&chain->volumes[i].shape, &frames[chain->volumes[i].frame], &volumes[i]);
    return KC_OK;
}

static int q_ok(const kc_chain *chain, const kc_real *q)
{
    for (int j = 0; j < chain->n_joints; j++)
        if (!kc_isfinite(q[j]))
            return 0;
    return 1;
}

kc_status kc_zone_distances(const kc_chain *chain, const kc_zone_set *set, const kc_real *q, kc_real *dist)
{
    kc_pose frames[KC_MAX_FRAMES];
    if (chain == NULL || set == NULL || q == NULL || dist == NULL || !q_ok(chain, q))
        return KC_E_ARG;
    kc_fk_frames(chain, q, frames, NULL);
    for (int i = 0; i < chain->n_volumes; i++) {
        kc_shape w;
        kc_shape_place(&chain->volumes[i].shape, &frames[chain->volumes[i].frame], &w);
        for (int z = 0; z < set->n_zones; z++)
            kc_shape_distance(&w, &set->zones[z], &dist[i * set->n_zones + z]);
    }
    return KC_OK;
}

kc_status kc_zone_check(const kc_chain *chain, const kc_zone_set *set, const kc_real *q, const kc_pose *frames,
                        kc_zone_hit *hit)
{
    kc_pose own[KC_MAX_FRAMES];
    if (chain == NULL || set == NULL || q == NULL || !q_ok(chain, q))
        return KC_E_ARG;
    kc_zone_hit best = {-1, -1, INF};
    if (chain->n_volumes > 0 && set->n_zones > 0) {
        if (frames == NULL) {
            kc_fk_frames(chain, q, own, NULL);
            frames = own;
        }
        kc_real far = set->margin + set->near;
        for (int i = 0; i < chain->n_volumes; i++) {
            kc_shape w;
            kc_shape_place(&chain->volumes[i].shape, &frames[chain->volumes[i].frame], &w);
            kc_real rw = kc_shape_bound_radius(&w);
            for (int z = 0; z < set->n_zones; z++) {
                const kc_shape *zn = &set->zones[z];
                kc_real d;
                if (zn->kind == KC_SHAPE_HALFSPACE) {
                    d = kc_shape_halfspace_distance(zn, &w);
                } else {
                    /* The bounding spheres' gap bounds the distance below. */
                    kc_vec3 dc = kc_v3_sub(w.pose.t, zn->pose.t);
                    kc_real gap = kc_vec3_norm(&dc) - rw - kc_shape_bound_radius(zn);
                    /* Only the closest pair needs its exact distance: GJK
                     * stops once a pair is known to be farther than the
                     * closest so far. */
                    kc_real cw = kc_shape_core_radius(&w), cz = kc_shape_core_radius(zn);
                    if (gap > far)
                        d = gap;
                    else
                        d = kc_max(kc_shape_gjk(&w, zn, best.distance + (cw + cz)) - cw - cz, KC_R(0.0));
                }
                if (d < best.distance) {
                    best.distance = d;
                    best.volume = i;
                    best.zone = z;
                }
            }
        }
    }
    if (hit != NULL)
        *hit = best;
    return best.distance < set->margin ? KC_E_LIMIT : KC_OK;
}

/* ---- travel between samples ---- */

/* Largest |value| an element can take: constants their own, prismatic
 * joints their travel (infinite when unbounded), rotations 0. */
static kc_real element_reach(const kc_chain *chain, const kc_element *el)
{
    if (el->code >= KC_CODE_TX)
        return kc_fabs(el->value);
    if (el->code >= KC_CODE_TX_JOINT && el->code <= KC_CODE_TZ_JOINT) {
        const kc_joint *j = &chain->joints[el->joint];
        return kc_max(kc_fabs(j->limits.q_min + j->offset), kc_fabs(j->limits.q_max + j->offset));
    }
    return KC_R(0.0);
}

void kc_zone_levers(const kc_chain *chain, kc_real *lever)
{
    if (chain == NULL || lever == NULL)
        return;
    for (int j = 0; j < chain->n_joints; j++)
        lever[j] = KC_R(0.0);
    for (int e = 0; e < chain->n_elements; e++) {
        const kc_element *el = &chain->elements[e];
        if (el->code > KC_CODE_TZ_JOINT)
            continue;
        int prismatic = el->code >= KC_CODE_TX_JOINT;
        for (int v = 0; v < chain->n_volumes; v++) {
            const kc_link_volume *vol = &chain->volumes[v];
            int end = chain->frame_end[vol->frame];
            if (end <= e)
                continue; /* this volume's frame comes before the joint */
            if (prismatic) {
                lever[el->joint] = KC_R(1.0);
                continue;
            }
            /* From the joint's origin (on its axis) to the volume's frame,
             * then to the farthest point of the volume. */
            kc_real r = kc_vec3_norm(&vol->shape.pose.t) + kc_shape_bound_radius(&vol->shape);
            for (int k = e + 1; k < end; k++)
                r += element_reach(chain, &chain->elements[k]);
            lever[el->joint] = kc_max(lever[el->joint], r);
        }
    }
}

kc_real kc_zone_tick_travel(const kc_chain *chain, kc_real dt)
{
    kc_real lever[KC_MAX_JOINTS], sum = KC_R(0.0);
    if (chain == NULL)
        return INF;
    kc_zone_levers(chain, lever);
    for (int j = 0; j < chain->n_joints; j++)
        if (lever[j] > KC_R(0.0))
            sum += chain->joints[j].limits.qd_max * dt * lever[j];
    return sum;
}
