/* SPDX-License-Identifier: BSD-3-Clause */
/* zones.c - kinctl-calc zones: the distance of every link volume of an arm
 * to every forbidden zone at one configuration (kinctl/zone.h), and
 * optionally the world geometry of both as JSON for plotting. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "calc.h"
#include "kinctl/desc.h"

const calc_opt zones_opts[] = {
    CALC_MODEL_OPTS,
    {"--zone", "zone", CALC_APPEND, calc_conv_string, "KIND:NUMBERS",
     "a forbidden zone (repeatable), world frame, m: box:cx,cy,cz,hx,hy,hz | sphere:cx,cy,cz,r | "
     "cylinder:x0,y0,z0,x1,y1,z1,r | capsule:x0,y0,z0,x1,y1,z1,r | frustum:cx,cy,cz,bx,by,tx,ty,h | "
     "halfspace:px,py,pz,nx,ny,nz (normal out of the zone)"},
    {"--zones-file", "zones_file", CALC_VALUE, calc_conv_string, "PATH",
     "read the zones (and margin) of a kinctld configuration's controller.zones; --zone adds to them"},
    {"--margin", "margin", CALC_VALUE, calc_conv_real, "M", "the margin judged against (m, default 0.02)"},
    {"--geometry", "geometry", CALC_FLAG, NULL, NULL,
     "also print the world-frame shapes of the volumes and zones (\"geometry\")"},
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

static const char *const kind_names[] = {"", "sphere", "capsule", "cylinder", "box", "frustum", "halfspace"};
#define ZONE_KINDS "box, sphere, cylinder, capsule, frustum or halfspace"

/* Parses "kind:n1,n2,..." into a zone. */
static int parse_zone(calc_ctx *ctx, const char *spec, kc_shape *z)
{
    static const struct {
        const char *name;
        int count;
    } forms[] = {{"box", 6}, {"sphere", 4}, {"cylinder", 7}, {"capsule", 7}, {"frustum", 8}, {"halfspace", 6}};
    enum { N_FORMS = sizeof forms / sizeof forms[0] };
    const char *colon = strchr(spec, ':');
    if (colon == NULL)
        return calc_fail(ctx, "zone \"%s\": expected KIND:NUMBERS (%s)", spec, ZONE_KINDS);
    size_t klen = (size_t)(colon - spec);
    int form = -1;
    for (int f = 0; f < N_FORMS; f++)
        if (strlen(forms[f].name) == klen && strncmp(spec, forms[f].name, klen) == 0)
            form = f;
    if (form < 0)
        return calc_fail(ctx, "zone \"%s\": unknown kind (expected %s)", spec, ZONE_KINDS);
    char err[256];
    json_t *arr = calc_conv_reals(colon + 1, err, sizeof err);
    if (arr == NULL)
        return calc_fail(ctx, "zone \"%s\": %s", spec, err);
    kc_real v[8];
    int n = 0;
    int rc = req_reals(ctx, arr, "zone", v, 8, &n);
    json_decref(arr);
    if (rc != 0)
        return -1;
    if (n != forms[form].count)
        return calc_fail(ctx, "zone \"%s\": %s takes %d numbers, got %d", spec, forms[form].name, forms[form].count, n);
    memset(z, 0, sizeof *z);
    kc_pose_identity(&z->pose);
    kc_status st = KC_OK;
    switch (form) {
    case 0:
        z->kind = KC_SHAPE_BOX;
        z->pose.t = kc_vec3_make(v[0], v[1], v[2]);
        z->dim[0] = v[3];
        z->dim[1] = v[4];
        z->dim[2] = v[5];
        break;
    case 1:
        z->kind = KC_SHAPE_SPHERE;
        z->pose.t = kc_vec3_make(v[0], v[1], v[2]);
        z->dim[0] = v[3];
        break;
    case 2:
    case 3: {
        kc_vec3 p0 = kc_vec3_make(v[0], v[1], v[2]), p1 = kc_vec3_make(v[3], v[4], v[5]);
        st = kc_shape_segment(form == 2 ? KC_SHAPE_CYLINDER : KC_SHAPE_CAPSULE, &p0, &p1, v[6], z);
        break;
    }
    case 4:
        /* upright: the bottom rectangle at cz - h, the top one at cz + h */
        z->kind = KC_SHAPE_FRUSTUM;
        z->pose.t = kc_vec3_make(v[0], v[1], v[2]);
        for (int i = 0; i < 5; i++)
            z->dim[i] = v[3 + i];
        break;
    default: {
        /* a frame whose z axis is the normal: the one a segment along it has */
        kc_vec3 p0 = kc_vec3_make(v[0], v[1], v[2]), p1 = kc_vec3_make(v[0] + v[3], v[1] + v[4], v[2] + v[5]);
        st = kc_shape_segment(KC_SHAPE_CYLINDER, &p0, &p1, KC_R(1.0), z);
        z->kind = KC_SHAPE_HALFSPACE;
        z->pose.t = p0;
        for (int i = 0; i < KC_SHAPE_DIMS; i++)
            z->dim[i] = KC_R(0.0);
        break;
    }
    }
    if (st != KC_OK || kc_shape_check(z, 1) != KC_OK)
        return calc_fail(ctx, "zone \"%s\": sizes must be positive and finite, a cylinder's or capsule's ends and a "
                         "normal nonzero", spec);
    return 0;
}

static void put_shape(jw *w, const kc_shape *s, int frame)
{
    jw_obj_begin(w);
    jw_key(w, "kind");
    jw_str(w, kind_names[s->kind]);
    if (frame >= 0) {
        jw_key(w, "frame");
        jw_real(w, (kc_real)(frame + 1));
    }
    jw_key(w, "pose");
    jw_pose(w, &s->pose);
    jw_key(w, "dim");
    jw_reals(w, s->dim, KC_SHAPE_DIMS);
    jw_obj_end(w);
}

int run_zones(const json_t *req, calc_ctx *ctx)
{
    kc_chain chain;
    kc_real q[KC_MAX_JOINTS];
    int deg = 0, geometry = 0;
    kc_zone_set set;
    const char *zones_file = NULL;
    kc_zone_set_init(&set);
    if (req_string(ctx, req, "zones_file", 0, &zones_file) != 0)
        return -1;
    if (zones_file != NULL) {
        kc_desc_error err;
        if (kc_desc_load_zones(zones_file, &set, NULL, &err) != KC_OK)
            return calc_fail(ctx, "%s", err.text);
    }
    if (req_bool(ctx, req, "deg", &deg) != 0 || req_bool(ctx, req, "geometry", &geometry) != 0 ||
        (json_object_get(req, "margin") != NULL && req_real(ctx, req, "margin", &set.margin) != 0) || req_model(ctx, req, &chain) != 0 ||
        req_q(ctx, req, &chain, deg, q) != 0)
        return -1;
    if (!(set.margin >= KC_R(0.0)))
        return calc_fail(ctx, "margin must be >= 0 m");
    const json_t *zs = json_object_get(req, "zone");
    if (zs != NULL && !json_is_array(zs))
        return calc_fail(ctx, "zone must be an array of \"KIND:NUMBERS\" strings");
    for (size_t i = 0; zs != NULL && i < json_array_size(zs); i++) {
        const json_t *s = json_array_get(zs, i);
        kc_shape z;
        if (!json_is_string(s))
            return calc_fail(ctx, "zone %zu is not a \"KIND:NUMBERS\" string", i + 1);
        if (parse_zone(ctx, json_string_value(s), &z) != 0)
            return -1;
        if (kc_zone_set_add(&set, &z) != KC_OK)
            return calc_fail(ctx, "more than %d zones", KC_ZONE_MAX);
    }
    if (chain.n_volumes == 0)
        calc_warn(ctx, "the model has no link volumes");
    static kc_real dist[KC_MAX_VOLUMES * KC_ZONE_MAX];
    kc_zone_hit hit;
    if (kc_zone_distances(&chain, &set, q, dist) != KC_OK)
        return calc_fail(ctx, "q is not finite");
    kc_status st = kc_zone_check(&chain, &set, q, NULL, &hit);
    jw *w = ctx->out;
    jw_key(w, "volumes");
    jw_arr_begin(w);
    for (int i = 0; i < chain.n_volumes; i++) {
        jw_obj_begin(w);
        jw_key(w, "kind");
        jw_str(w, kind_names[chain.volumes[i].shape.kind]);
        jw_key(w, "frame");
        jw_real(w, (kc_real)(chain.volumes[i].frame + 1));
        jw_obj_end(w);
    }
    jw_arr_end(w);
    jw_key(w, "distances");
    jw_arr_begin(w);
    for (int i = 0; i < chain.n_volumes; i++)
        jw_reals(w, &dist[(size_t)i * (size_t)set.n_zones], set.n_zones);
    jw_arr_end(w);
    jw_key(w, "margin");
    jw_real(w, set.margin);
    jw_key(w, "closest");
    if (hit.volume < 0) {
        jw_null(w);
    } else {
        jw_obj_begin(w);
        jw_key(w, "volume");
        jw_real(w, (kc_real)hit.volume);
        jw_key(w, "zone");
        jw_real(w, (kc_real)hit.zone);
        jw_key(w, "distance");
        jw_real(w, dist[hit.volume * set.n_zones + hit.zone]);
        jw_obj_end(w);
    }
    jw_key(w, "clear");
    jw_bool(w, st == KC_OK);
    if (geometry) {
        kc_pose frames[KC_MAX_FRAMES];
        kc_shape world[KC_MAX_VOLUMES];
        kc_fk_frames(&chain, q, frames, NULL);
        kc_zone_volumes_world(&chain, frames, world);
        jw_key(w, "geometry");
        jw_obj_begin(w);
        jw_key(w, "volumes");
        jw_arr_begin(w);
        for (int i = 0; i < chain.n_volumes; i++)
            put_shape(w, &world[i], chain.volumes[i].frame);
        jw_arr_end(w);
        jw_key(w, "zones");
        jw_arr_begin(w);
        for (int z = 0; z < set.n_zones; z++)
            put_shape(w, &set.zones[z], -1);
        jw_arr_end(w);
        jw_obj_end(w);
    }
    return 0;
}
