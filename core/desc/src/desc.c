/* SPDX-License-Identifier: BSD-3-Clause */
/* desc.c - reads the robot section of description files and builds
 * chains with the core's builders (format: kinctl/desc.h, examples:
 * models/; shapes of link volumes: shape.c; zones: zones.c). */
#include "desc_internal.h"
#include "kinctl/desc_tree.h"

#include <stdio.h>
#include <string.h>

/* Optional limits group; angular (revolute) limits and rates are in the
 * file's angle unit. */
static kc_status read_limits(kc_desc_reader *r, const config_setting_t *owner, const char *where, int angular,
                             kc_joint_limits *out)
{
    static const char *const keys[] = {"q", "qd", "qdd", "qddd", NULL};
    const config_setting_t *g = config_setting_get_member(owner, "limits");
    kc_joint_limits l = kc_joint_limits_default();
    kc_real scale = angular && r->deg ? KC_DEG : KC_R(1.0);
    char what[96];
    kc_status st;
    *out = l;
    if (g == NULL)
        return KC_OK;
    snprintf(what, sizeof what, "%s limits", where);
    if (!config_setting_is_group(g))
        return fail(r, g, "%s must be a group { q = [min, max]; qd = ..; ... }", what);
    if ((st = kc_cfg_check_keys(&r->cfg, g, what, keys)) != KC_OK)
        return st;
    const config_setting_t *q = config_setting_get_member(g, "q");
    if (q != NULL) {
        kc_real mm[2] = {KC_R(0.0), KC_R(0.0)};
        char qwhat[112];
        snprintf(qwhat, sizeof qwhat, "%s: q", what);
        if ((st = kc_cfg_vector_real(&r->cfg, q, qwhat, 2, scale, mm)) != KC_OK)
            return st;
        if (!(mm[0] <= mm[1]))
            return fail(r, q, "%s: q min %.17g > max %.17g", what, (double)(mm[0] / scale),
                        (double)(mm[1] / scale)); /* in the file's unit */
        l.q_min = mm[0];
        l.q_max = mm[1];
    }
    static const char *const rates[3] = {"qd", "qdd", "qddd"};
    kc_real *dest[3] = {&l.qd_max, &l.qdd_max, &l.qddd_max};
    for (int i = 0; i < 3; i++) {
        int present = 0;
        kc_real v = KC_R(0.0);
        if ((st = kc_cfg_lookup_real(&r->cfg, g, rates[i], what, 0, scale, &v, &present)) != KC_OK)
            return st;
        if (!present)
            continue;
        if (!(v > KC_R(0.0)))
            return fail(r, config_setting_get_member(g, rates[i]), "%s: %s must be > 0 (omit it for no limit)", what,
                        rates[i]);
        if (!(v >= (kc_real)KC_DESC_RATE_MIN && v <= (kc_real)KC_DESC_RATE_MAX))
            return fail(r, config_setting_get_member(g, rates[i]), "%s: %s = %g is outside %g .. %g (in rad or m)",
                        what, rates[i], (double)v, KC_DESC_RATE_MIN, KC_DESC_RATE_MAX);
        *dest[i] = v;
    }
    *out = l;
    return KC_OK;
}

static kc_status read_pose(kc_desc_reader *r, const config_setting_t *robot, const char *key, kc_pose *out,
                           int *present)
{
    static const char *const keys[] = {"xyz", "rpy", NULL};
    const config_setting_t *g = config_setting_get_member(robot, key);
    kc_real xyz[3] = {KC_R(0.0), KC_R(0.0), KC_R(0.0)}, rpy[3] = {KC_R(0.0), KC_R(0.0), KC_R(0.0)};
    kc_status st;
    char what[32];
    *present = g != NULL;
    if (g == NULL)
        return KC_OK;
    if (!config_setting_is_group(g))
        return fail(r, g, "%s must be a group { xyz = [x, y, z]; rpy = [rx, ry, rz]; }", key);
    if ((st = kc_cfg_check_keys(&r->cfg, g, key, keys)) != KC_OK)
        return st;
    const config_setting_t *s = config_setting_get_member(g, "xyz");
    snprintf(what, sizeof what, "%s xyz", key);
    if (s != NULL && (st = kc_cfg_vector_real(&r->cfg, s, what, 3, KC_R(1.0), xyz)) != KC_OK)
        return st;
    s = config_setting_get_member(g, "rpy");
    snprintf(what, sizeof what, "%s rpy", key);
    if (s != NULL && (st = kc_cfg_vector_real(&r->cfg, s, what, 3, r->deg ? KC_DEG : KC_R(1.0), rpy)) != KC_OK)
        return st;
    kc_desc_rpy_to_mat3(rpy, &out->R);
    out->t = kc_vec3_make(xyz[0], xyz[1], xyz[2]);
    return KC_OK;
}

static kc_status too_many_joints(kc_desc_reader *r, const config_setting_t *s)
{
    return fail_at(r, s, KC_E_CAPACITY, "too many joints: kinctl supports at most %d", KC_MAX_JOINTS);
}

/* What the chain builder answered to row or element g. */
static kc_status built(kc_desc_reader *r, const config_setting_t *g, const char *where, kc_status st)
{
    if (st == KC_E_CAPACITY)
        return fail_at(r, g, st, "%s: the chain exceeds kinctl's capacity (%d elements, %d frames)", where,
                       KC_MAX_ELEMENTS, KC_MAX_FRAMES);
    if (st != KC_OK)
        return fail_at(r, g, st, "%s: rejected by the chain builder: %s", where, kc_status_str(st));
    return KC_OK;
}

/* One standard or modified DH row. */
static kc_status read_dh_row(kc_desc_reader *r, const config_setting_t *g, const char *where, int modified,
                             kc_chain *chain, kc_desc_info *info)
{
    static const char *const keys[] = {"name", "type", "a", "alpha", "d", "theta", "limits", NULL};
    kc_real ang = r->deg ? KC_DEG : KC_R(1.0);
    kc_dh_row row;
    const char *type = NULL;
    kc_status st;
    if (!config_setting_is_group(g))
        return fail(r, g, "%s must be a group { type = ...; a = ...; alpha = ...; d = ...; theta = ...; }", where);
    if ((st = kc_cfg_check_keys(&r->cfg, g, where, keys)) != KC_OK)
        return st;
    if (chain->n_joints >= KC_MAX_JOINTS)
        return too_many_joints(r, g);
    if ((st = kc_cfg_string(&r->cfg, g, "type", where, &type)) != KC_OK)
        return st;
    if (strcmp(type, "revolute") == 0)
        row.type = KC_JOINT_REVOLUTE;
    else if (strcmp(type, "prismatic") == 0)
        row.type = KC_JOINT_PRISMATIC;
    else
        return fail(r, config_setting_get_member(g, "type"),
                    "%s: unknown joint type \"%s\" (expected \"revolute\" or \"prismatic\")", where, type);
    if ((st = kc_cfg_lookup_real(&r->cfg, g, "a", where, 1, KC_R(1.0), &row.a, NULL)) != KC_OK ||
        (st = kc_cfg_lookup_real(&r->cfg, g, "alpha", where, 1, ang, &row.alpha, NULL)) != KC_OK ||
        (st = kc_cfg_lookup_real(&r->cfg, g, "d", where, 1, KC_R(1.0), &row.d, NULL)) != KC_OK ||
        (st = kc_cfg_lookup_real(&r->cfg, g, "theta", where, 1, ang, &row.theta, NULL)) != KC_OK ||
        (st = read_limits(r, g, where, row.type == KC_JOINT_REVOLUTE, &row.limits)) != KC_OK ||
        (st = kc_desc_read_name(r, g, where, info->joint_names[chain->n_joints])) != KC_OK)
        return st;
    info->joint_lines[chain->n_joints] = (int)config_setting_source_line(g);
    st = modified ? kc_chain_add_mdh(chain, &row) : kc_chain_add_dh(chain, &row);
    return built(r, g, where, st);
}

/* "rx".."tz" to 0..5 (rotations x, y, z then translations x, y, z). */
static int op_index(const char *op)
{
    static const char *const ops[6] = {"rx", "ry", "rz", "tx", "ty", "tz"};
    for (int i = 0; i < 6; i++)
        if (strcmp(op, ops[i]) == 0)
            return i;
    return -1;
}

/* One elementary transform: a joint (ends a frame) or a constant. */
static kc_status read_element(kc_desc_reader *r, const config_setting_t *g, const char *where, kc_chain *chain,
                              kc_desc_info *info)
{
    static const char *const keys[] = {"op", "joint", "value", "offset", "frame", "limits", "name", NULL};
    const char *op = NULL;
    int joint = 0, frame = 0;
    kc_status st;
    if (!config_setting_is_group(g))
        return fail(r, g, "%s must be a group { op = \"rz\"; joint = true; } or { op = \"tz\"; value = 0.1; }", where);
    if ((st = kc_cfg_check_keys(&r->cfg, g, where, keys)) != KC_OK ||
        (st = kc_cfg_string(&r->cfg, g, "op", where, &op)) != KC_OK ||
        (st = kc_cfg_lookup_bool(&r->cfg, g, "joint", where, &joint)) != KC_OK ||
        (st = kc_cfg_lookup_bool(&r->cfg, g, "frame", where, &frame)) != KC_OK)
        return st;
    int k = op_index(op);
    if (k < 0)
        return fail(r, config_setting_get_member(g, "op"),
                    "%s: unknown op \"%s\" (expected rx, ry, rz, tx, ty or tz)", where, op);
    int rotation = k < 3;
    kc_real scale = rotation && r->deg ? KC_DEG : KC_R(1.0);
    if (joint) {
        static const char *const not_for_joint[] = {"value", "frame", NULL};
        for (const char *const *key = not_for_joint; *key != NULL; key++)
            if (config_setting_get_member(g, *key) != NULL)
                return fail(r, config_setting_get_member(g, *key),
                            "%s: a joint takes offset, not %s (a joint always ends a frame)", where, *key);
        if (chain->n_joints >= KC_MAX_JOINTS)
            return too_many_joints(r, g);
        kc_real offset = KC_R(0.0);
        kc_joint_limits lim;
        if ((st = kc_cfg_lookup_real(&r->cfg, g, "offset", where, 0, scale, &offset, NULL)) != KC_OK ||
            (st = read_limits(r, g, where, rotation, &lim)) != KC_OK ||
            (st = kc_desc_read_name(r, g, where, info->joint_names[chain->n_joints])) != KC_OK)
            return st;
        info->joint_lines[chain->n_joints] = (int)config_setting_source_line(g);
        st = kc_chain_add_joint(chain, (kc_code)(KC_CODE_RX_JOINT + k), offset, &lim);
    } else {
        static const char *const joint_only[] = {"offset", "limits", "name", NULL};
        for (const char *const *key = joint_only; *key != NULL; key++)
            if (config_setting_get_member(g, *key) != NULL)
                return fail(r, config_setting_get_member(g, *key),
                            "%s: %s belongs to a joint (joint = true); a constant takes value", where, *key);
        kc_real value = KC_R(0.0);
        if ((st = kc_cfg_lookup_real(&r->cfg, g, "value", where, 1, scale, &value, NULL)) != KC_OK)
            return st;
        st = kc_chain_add_const(chain, (kc_code)(KC_CODE_RX + k), value);
        if (st == KC_OK && frame)
            st = kc_chain_add_frame(chain);
    }
    return built(r, g, where, st);
}

/* robot.volumes: link volumes on frames 1..n_frames. */
static kc_status read_volumes(kc_desc_reader *r, const config_setting_t *list, kc_chain *chain, kc_desc_info *info)
{
    if (!config_setting_is_list(list))
        return fail(r, list, "volumes must be a list in parentheses: volumes = ( { frame = 1; shape = ...; }, ... );");
    int n = config_setting_length(list);
    for (int i = 0; i < n; i++) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)i);
        char where[48];
        kc_shape sh;
        kc_status st;
        kc_real frame = KC_R(0.0);
        snprintf(where, sizeof where, "volume %d", i + 1);
        if (chain->n_volumes >= KC_MAX_VOLUMES)
            return fail_at(r, g, KC_E_CAPACITY, "too many volumes: kinctl supports at most %d", KC_MAX_VOLUMES);
        if ((st = kc_desc_read_shape(r, g, where, 0, &sh)) != KC_OK ||
            (st = kc_cfg_lookup_real(&r->cfg, g, "frame", where, 1, KC_R(1.0), &frame, NULL)) != KC_OK ||
            (st = kc_desc_read_name(r, g, where, info->volume_names[chain->n_volumes])) != KC_OK)
            return st;
        int f = (int)frame;
        if ((kc_real)f != frame || f < 1 || f > chain->n_frames)
            return fail(r, config_setting_get_member(g, "frame"), "%s: frame must be a whole number 1 .. %d (the chain's frames)",
                        where, chain->n_frames);
        if ((st = kc_chain_add_volume(chain, f - 1, &sh)) != KC_OK)
            return fail_at(r, g, st, "%s: rejected: %s", where, kc_status_str(st));
    }
    info->n_volumes = chain->n_volumes;
    return KC_OK;
}

static kc_status read_robot(kc_desc_reader *r, const config_setting_t *robot, kc_chain *chain, kc_desc_info *info)
{
    static const char *const keys[] = {"name", "angles", "base", "tool", "dh", "mdh", "elements", "volumes", NULL};
    static const char *const chains[3] = {"dh", "mdh", "elements"};
    const char *name = NULL, *angles = NULL;
    kc_status st;
    if (!config_setting_is_group(robot))
        return fail(r, robot, "robot must be a group: robot = { name = ...; angles = ...; dh = (...); };");
    if ((st = kc_cfg_check_keys(&r->cfg, robot, "robot", keys)) != KC_OK ||
        (st = kc_cfg_string(&r->cfg, robot, "name", "robot", &name)) != KC_OK ||
        (st = kc_cfg_string(&r->cfg, robot, "angles", "robot", &angles)) != KC_OK)
        return st;
    if (name[0] == '\0' || strlen(name) >= KC_DESC_NAME_LEN)
        return fail(r, config_setting_get_member(robot, "name"), "robot: name must have 1 to %d characters",
                    KC_DESC_NAME_LEN - 1);
    snprintf(info->name, sizeof info->name, "%s", name);
    if (strcmp(angles, "deg") == 0)
        r->deg = 1;
    else if (strcmp(angles, "rad") == 0)
        r->deg = 0;
    else
        return fail(r, config_setting_get_member(robot, "angles"),
                    "robot: unknown angle unit \"%s\" (expected \"rad\" or \"deg\")", angles);
    info->angles_deg = r->deg;

    const config_setting_t *list = NULL;
    for (int i = 0; i < 3; i++) {
        const config_setting_t *s = config_setting_get_member(robot, chains[i]);
        if (s == NULL)
            continue;
        if (list != NULL)
            return fail(r, s, "robot has both %s and %s: give exactly one chain", chains[info->kind], chains[i]);
        list = s;
        info->kind = (kc_desc_kind)i;
    }
    if (list == NULL)
        return fail(r, robot, "robot has no chain: give one of dh = (...), mdh = (...), elements = (...)");
    const char *kind = chains[info->kind];
    if (!config_setting_is_list(list))
        return fail(r, list, "%s must be a list in parentheses: %s = ( { ... }, { ... } );", kind, kind);
    int n = config_setting_length(list);
    if (n == 0)
        return fail(r, list, "%s is empty: a chain needs at least one joint", kind);
    for (int i = 0; i < n; i++) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)i);
        char where[48];
        snprintf(where, sizeof where, "%s %s %d", kind, info->kind == KC_DESC_ELEMENTS ? "element" : "row", i + 1);
        st = info->kind == KC_DESC_ELEMENTS ? read_element(r, g, where, chain, info)
                                            : read_dh_row(r, g, where, info->kind == KC_DESC_MDH, chain, info);
        if (st != KC_OK)
            return st;
    }
    if (chain->n_joints == 0)
        return fail(r, list, "%s has no joint: mark at least one element joint = true", kind);
    info->n_joints = chain->n_joints;

    static const char *const poses[2] = {"base", "tool"};
    for (int i = 0; i < 2; i++) {
        kc_pose p;
        int present = 0;
        if ((st = read_pose(r, robot, poses[i], &p, &present)) != KC_OK)
            return st;
        if (present) {
            st = i == 0 ? kc_chain_set_base(chain, &p) : kc_chain_set_tool(chain, &p);
            if (st != KC_OK)
                return fail_at(r, config_setting_get_member(robot, poses[i]), st, "%s: rejected: %s", poses[i],
                               kc_status_str(st));
        }
    }
    const config_setting_t *vols = config_setting_get_member(robot, "volumes");
    if (vols != NULL && (st = read_volumes(r, vols, chain, info)) != KC_OK)
        return st;
    st = kc_chain_check(chain);
    if (st != KC_OK)
        return fail_at(r, robot, st, "robot: the chain fails kc_chain_check: %s", kc_status_str(st));
    return KC_OK;
}

/* The top level: robot, and controller reserved for kinctld. */
static kc_status find_robot(kc_desc_reader *r, const config_t *tree, const config_setting_t **robot)
{
    static const char *const sections[] = {"robot", "controller", NULL};
    const config_setting_t *root = config_root_setting(tree);
    kc_status st = kc_cfg_check_keys(&r->cfg, root, "the top level", sections);
    if (st != KC_OK)
        return st;
    *robot = config_setting_get_member(root, "robot");
    if (*robot == NULL)
        return fail(r, NULL, "no robot section: expected robot = { name = ...; angles = ...; dh = (...); };");
    return KC_OK;
}

kc_status kc_desc_read_robot(const config_setting_t *robot, const char *file, kc_chain *chain, kc_desc_info *info,
                             kc_desc_error *err)
{
    /* cppcheck-suppress ctuuninitvar ; err is an output: stored here, written before any read */
    kc_desc_reader r = kc_desc_reader_make(file != NULL ? file : "<null>", err);
    kc_chain tmp;
    kc_desc_info tmp_info;
    if (robot == NULL || chain == NULL)
        return fail(&r, NULL, "no robot section or no chain to fill");
    /* Built into temporaries so that the outputs stay untouched on error. */
    memset(&tmp_info, 0, sizeof tmp_info);
    kc_chain_init(&tmp);
    kc_status st = read_robot(&r, robot, &tmp, &tmp_info);
    if (st != KC_OK)
        return st;
    *chain = tmp;
    if (info != NULL)
        *info = tmp_info;
    return KC_OK;
}

/* Parses path or text, then reads its robot. */
static kc_status load(const char *path, const char *text, const char *name, kc_chain *chain, kc_desc_info *info,
                      kc_desc_error *err)
{
    /* cppcheck-suppress ctuuninitvar ; err is an output: stored here, written before any read */
    kc_desc_reader r = kc_desc_reader_make(name, err);
    const config_setting_t *robot = NULL;
    config_t tree;
    if (chain == NULL || (path == NULL && text == NULL))
        return fail(&r, NULL, "no chain to fill or no input given");
    kc_status st = path != NULL ? kc_cfg_parse_file(&r.cfg, path, &tree) : kc_cfg_parse_string(&r.cfg, text, &tree);
    if (st != KC_OK)
        return st;
    st = find_robot(&r, &tree, &robot);
    if (st == KC_OK)
        st = kc_desc_read_robot(robot, name, chain, info, err);
    config_destroy(&tree);
    return st;
}

kc_status kc_desc_load_file(const char *path, kc_chain *chain, kc_desc_info *info, kc_desc_error *err)
{
    return load(path, NULL, path != NULL ? path : "<null>", chain, info, err);
}

kc_status kc_desc_load_string(const char *text, const char *name, kc_chain *chain, kc_desc_info *info,
                              kc_desc_error *err)
{
    return load(NULL, text, name != NULL ? name : "<string>", chain, info, err);
}
