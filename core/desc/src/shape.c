/* SPDX-License-Identifier: BSD-3-Clause */
/* shape.c - the shapes of link volumes and forbidden zones in description
 * files (kinctl/desc.h, kinctl/zone.h), and the names they carry. */
#include "desc_internal.h"
#include "kinctl/orient.h"

#include <stdio.h>
#include <string.h>

kc_desc_reader kc_desc_reader_make(const char *file, kc_desc_error *err)
{
    kc_desc_reader r;
    memset(&r, 0, sizeof r);
    r.cfg.file = file;
    r.cfg.sep = ": ";
    r.cfg.err = err;
    if (err != NULL)
        memset(err, 0, sizeof *err);
    return r;
}

void kc_desc_rpy_to_mat3(const kc_real *rpy, kc_mat3 *R)
{
    /* URDF's rpy [about x, about y, about z] is R = Rz Ry Rx: seed 001's
     * roll-pitch-yaw with phi about z, theta about y, psi about x. */
    kc_euler e = {rpy[2], rpy[1], rpy[0]};
    kc_orient_rpy_to_mat3(&e, R);
}

kc_status kc_desc_read_name(kc_desc_reader *r, const config_setting_t *g, const char *where, char *dest)
{
    const char *name = NULL;
    kc_status st = kc_cfg_lookup_string(&r->cfg, g, "name", where, &name, NULL);
    if (st != KC_OK || name == NULL)
        return st;
    if (strlen(name) >= KC_DESC_NAME_LEN)
        return fail(r, config_setting_get_member(g, "name"), "%s: name is longer than %d characters", where,
                    KC_DESC_NAME_LEN - 1);
    snprintf(dest, KC_DESC_NAME_LEN, "%s", name);
    return KC_OK;
}

/* One shape group: shape = "sphere" | "capsule" | "cylinder" | "box" |
 * "frustum" | "halfspace" (zones only) with its keys (see kinctl/desc.h).
 * extra lists the keys the caller reads itself (name, frame). */
kc_status kc_desc_read_shape(kc_desc_reader *r, const config_setting_t *g, const char *where, int zone, kc_shape *out)
{
    static const char *const keys[] = {"name",  "frame",  "shape", "xyz",         "rpy",   "from",
                                       "to",    "radius", "half",  "half_height", "bottom", "top",
                                       "point", "normal", NULL};
    static const char *const kinds[] = {"sphere", "capsule", "cylinder", "box", "frustum", "halfspace"};
    /* the keys each kind takes, besides name and frame */
    static const char *const takes[6][5] = {{"xyz", "radius", NULL},
                                            {"from", "to", "radius", NULL},
                                            {"from", "to", "radius", NULL},
                                            {"xyz", "rpy", "half", NULL},
                                            {"xyz", "rpy", "bottom", "top", "half_height"},
                                            {"point", "normal", NULL}};
    const char *shape = NULL;
    kc_status st;
    if (!config_setting_is_group(g))
        return fail(r, g, "%s must be a group { shape = \"capsule\"; from = [..]; to = [..]; radius = ..; }", where);
    if ((st = kc_cfg_check_keys(&r->cfg, g, where, keys)) != KC_OK ||
        (st = kc_cfg_string(&r->cfg, g, "shape", where, &shape)) != KC_OK)
        return st;
    int k = -1;
    for (int i = 0; i < 6; i++)
        if (strcmp(shape, kinds[i]) == 0)
            k = i;
    if (k < 0 || (k == 5 && !zone))
        return fail(r, config_setting_get_member(g, "shape"), "%s: unknown shape \"%s\" (expected sphere, capsule, "
                    "cylinder, box, frustum%s)", where, shape, zone ? " or halfspace" : "");
    for (int i = 3; keys[i] != NULL; i++) {
        int ok = 0;
        for (int t = 0; t < 5 && takes[k][t] != NULL; t++)
            ok = ok || strcmp(keys[i], takes[k][t]) == 0;
        const config_setting_t *m = config_setting_get_member(g, keys[i]);
        if (m != NULL && !ok)
            return fail(r, m, "%s: a %s takes no %s", where, shape, keys[i]);
    }
    kc_shape sh;
    memset(&sh, 0, sizeof sh);
    kc_pose_identity(&sh.pose);
    sh.kind = k + 1; /* kc_shape_kind follows kinds[] */
    kc_real v3[3], w3[3], rpy[3] = {KC_R(0.0), KC_R(0.0), KC_R(0.0)}, two[2], r0 = KC_R(0.0);
    char what[96];
#define VEC(key, n, scale, dst)                                                                       \
    do {                                                                                             \
        const config_setting_t *m_ = config_setting_get_member(g, key);                               \
        snprintf(what, sizeof what, "%s: %s", where, key);                                           \
        if (m_ == NULL)                                                                              \
            return fail(r, g, "%s: a %s needs %s", where, shape, key);                                \
        if ((st = kc_cfg_vector_real(&r->cfg, m_, what, n, scale, dst)) != KC_OK)                                   \
            return st;                                                                               \
    } while (0)
    switch (sh.kind) {
    case KC_SHAPE_SPHERE:
        VEC("xyz", 3, KC_R(1.0), v3);
        sh.pose.t = kc_vec3_make(v3[0], v3[1], v3[2]);
        if ((st = kc_cfg_lookup_real(&r->cfg, g, "radius", where, 1, KC_R(1.0), &sh.dim[0], NULL)) != KC_OK)
            return st;
        break;
    case KC_SHAPE_CAPSULE:
    case KC_SHAPE_CYLINDER: {
        VEC("from", 3, KC_R(1.0), v3);
        VEC("to", 3, KC_R(1.0), w3);
        if ((st = kc_cfg_lookup_real(&r->cfg, g, "radius", where, 1, KC_R(1.0), &r0, NULL)) != KC_OK)
            return st;
        kc_vec3 p0 = kc_vec3_make(v3[0], v3[1], v3[2]), p1 = kc_vec3_make(w3[0], w3[1], w3[2]);
        if (kc_shape_segment(sh.kind, &p0, &p1, r0, &sh) != KC_OK)
            return fail(r, g, "%s: a %s needs from != to and radius > 0", where, shape);
        break;
    }
    case KC_SHAPE_BOX:
    case KC_SHAPE_FRUSTUM:
        VEC("xyz", 3, KC_R(1.0), v3);
        sh.pose.t = kc_vec3_make(v3[0], v3[1], v3[2]);
        if (config_setting_get_member(g, "rpy") != NULL)
            VEC("rpy", 3, r->deg ? KC_DEG : KC_R(1.0), rpy);
        kc_desc_rpy_to_mat3(rpy, &sh.pose.R);
        if (sh.kind == KC_SHAPE_BOX) {
            VEC("half", 3, KC_R(1.0), sh.dim);
        } else {
            VEC("bottom", 2, KC_R(1.0), two);
            sh.dim[0] = two[0];
            sh.dim[1] = two[1];
            VEC("top", 2, KC_R(1.0), two);
            sh.dim[2] = two[0];
            sh.dim[3] = two[1];
            if ((st = kc_cfg_lookup_real(&r->cfg, g, "half_height", where, 1, KC_R(1.0), &sh.dim[4], NULL)) != KC_OK)
                return st;
        }
        break;
    default: {
        VEC("point", 3, KC_R(1.0), v3);
        VEC("normal", 3, KC_R(1.0), w3);
        /* the frame whose z axis is the normal: that of a segment along it */
        kc_vec3 p0 = kc_vec3_make(v3[0], v3[1], v3[2]), p1 = kc_vec3_make(v3[0] + w3[0], v3[1] + w3[1], v3[2] + w3[2]);
        if (kc_shape_segment(KC_SHAPE_CYLINDER, &p0, &p1, KC_R(1.0), &sh) != KC_OK)
            return fail(r, g, "%s: normal must not be zero", where);
        sh.kind = KC_SHAPE_HALFSPACE;
        sh.pose.t = p0;
        for (int i = 0; i < KC_SHAPE_DIMS; i++)
            sh.dim[i] = KC_R(0.0);
        break;
    }
    }
#undef VEC
    if (kc_shape_check(&sh, zone) != KC_OK)
        return fail(r, g, "%s: every size of a %s must be > 0", where, shape);
    *out = sh;
    return KC_OK;
}
