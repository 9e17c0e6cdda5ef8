/* SPDX-License-Identifier: BSD-3-Clause */
/* zones.c - forbidden zones from a file's controller.zones section
 * (format: kinctl/desc.h; shapes: shape.c). kinctld reads them from its
 * configuration (kinctl/desc_tree.h), kinctl-calc from --zones-file. */
#include "desc_internal.h"
#include "kinctl/desc_tree.h"

#include <stdio.h>
#include <string.h>

static kc_status read_zones(kc_desc_reader *r, const config_setting_t *g, kc_zone_set *set,
                            kc_desc_zone_info *info)
{
    static const char *const keys[] = {"margin", "near", "angles", "list", NULL};
    const char *angles = NULL;
    kc_status st;
    if (!config_setting_is_group(g))
        return fail(r, g, "controller.zones must be a group { margin = 0.02; list = ( ... ); }");
    const char *section = "controller.zones";
    if ((st = kc_cfg_check_keys(&r->cfg, g, section, keys)) != KC_OK ||
        (st = kc_cfg_lookup_real(&r->cfg, g, "margin", section, 0, KC_R(1.0), &set->margin, NULL)) != KC_OK ||
        (st = kc_cfg_lookup_real(&r->cfg, g, "near", section, 0, KC_R(1.0), &set->near, NULL)) != KC_OK ||
        (st = kc_cfg_lookup_string(&r->cfg, g, "angles", section, &angles, NULL)) != KC_OK)
        return st;
    if (!(set->margin >= KC_R(0.0)) || !(set->near >= KC_R(0.0)))
        return fail(r, g, "controller.zones: margin and near must be >= 0 m");
    r->deg = 0;
    if (angles != NULL && strcmp(angles, "deg") == 0)
        r->deg = 1;
    else if (angles != NULL && strcmp(angles, "rad") != 0)
        return fail(r, config_setting_get_member(g, "angles"),
                    "controller.zones: unknown angle unit \"%s\" (expected \"rad\" or \"deg\")", angles);
    const config_setting_t *list = config_setting_get_member(g, "list");
    if (list == NULL)
        return KC_OK;
    if (!config_setting_is_list(list))
        return fail(r, list, "controller.zones.list must be a list in parentheses: list = ( { ... }, ... );");
    int n = config_setting_length(list);
    for (int i = 0; i < n; i++) {
        const config_setting_t *z = config_setting_get_elem(list, (unsigned)i);
        char where[48];
        kc_shape sh;
        snprintf(where, sizeof where, "zone %d", i + 1);
        if (set->n_zones >= KC_ZONE_MAX)
            return fail_at(r, z, KC_E_CAPACITY, "too many zones: kinctl supports at most %d", KC_ZONE_MAX);
        if (config_setting_is_group(z) && config_setting_get_member(z, "frame") != NULL)
            return fail(r, config_setting_get_member(z, "frame"), "%s: a zone is in the base frame: no frame key", where);
        if ((st = kc_desc_read_shape(r, z, where, 1, &sh)) != KC_OK ||
            (st = kc_desc_read_name(r, z, where, info->names[set->n_zones])) != KC_OK)
            return st;
        set->zones[set->n_zones++] = sh;
    }
    info->n_zones = set->n_zones;
    return KC_OK;
}

kc_status kc_desc_read_zones(const config_setting_t *zones, const char *file, kc_zone_set *set,
                             kc_desc_zone_info *info, kc_desc_error *err)
{
    /* cppcheck-suppress ctuuninitvar ; err is an output: stored here, written before any read */
    kc_desc_reader r = kc_desc_reader_make(file != NULL ? file : "<null>", err);
    kc_zone_set tmp;
    kc_desc_zone_info tmp_info;
    if (set == NULL)
        return fail(&r, NULL, "no zone set to fill");
    kc_zone_set_init(&tmp);
    memset(&tmp_info, 0, sizeof tmp_info);
    if (zones != NULL) {
        kc_status st = read_zones(&r, zones, &tmp, &tmp_info);
        if (st != KC_OK)
            return st;
    }
    *set = tmp;
    if (info != NULL)
        *info = tmp_info;
    return KC_OK;
}

kc_status kc_desc_load_zones(const char *path, kc_zone_set *set, kc_desc_zone_info *info, kc_desc_error *err)
{
    const char *name = path != NULL ? path : "<null>";
    /* cppcheck-suppress ctuuninitvar ; err is an output: stored here, written before any read */
    kc_desc_reader r = kc_desc_reader_make(name, err);
    config_t tree;
    if (path == NULL || set == NULL)
        return fail(&r, NULL, "no zone set to fill or no file given");
    kc_status st = kc_cfg_parse_file(&r.cfg, path, &tree);
    if (st != KC_OK)
        return st;
    const config_setting_t *ctl = config_setting_get_member(config_root_setting(&tree), "controller");
    const config_setting_t *zones = ctl != NULL && config_setting_is_group(ctl) ? config_setting_get_member(ctl, "zones")
                                                                                 : NULL;
    st = kc_desc_read_zones(zones, name, set, info, err);
    config_destroy(&tree);
    return st;
}
