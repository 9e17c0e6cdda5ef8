/* desc.c - reads robot description files with libconfig and builds chains
 * with the core's builders (format: kinctl/desc.h, examples: models/). */
#include "kinctl/desc.h"
#include "kinctl/orient.h"

#include <errno.h>
#include <libconfig.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* State of one load: where messages point and the file's angle unit. */
typedef struct reader {
    const char *file;
    kc_desc_error *err;
    int deg;
} reader;

static void write_error(kc_desc_error *e, const char *file, int line, const char *problem)
{
    snprintf(e->file, sizeof e->file, "%s", file);
    e->line = line;
    snprintf(e->problem, sizeof e->problem, "%s", problem);
    if (line > 0)
        snprintf(e->text, sizeof e->text, "%s:%d: %s", e->file, line, e->problem);
    else
        snprintf(e->text, sizeof e->text, "%s: %s", e->file, e->problem);
}

#if defined(__GNUC__)
#define KC_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define KC_PRINTF(f, a)
#endif

/* Records an error at setting s (its line and, for @include'd text, its
 * file). */
static void report(reader *r, const config_setting_t *s, const char *fmt, ...) KC_PRINTF(3, 4);
static void report(reader *r, const config_setting_t *s, const char *fmt, ...)
{
    char problem[KC_DESC_TEXT_LEN];
    const char *file = s != NULL ? config_setting_source_file(s) : NULL;
    va_list ap;
    if (r->err == NULL)
        return;
    va_start(ap, fmt);
    vsnprintf(problem, sizeof problem, fmt, ap);
    va_end(ap);
    write_error(r->err, file != NULL ? file : r->file, s != NULL ? (int)config_setting_source_line(s) : 0, problem);
}

/* Reports and evaluates to st, so that callers write `return fail(...)`; a
 * macro so that the status returned is plain where it is returned (static
 * analyzers do not follow calls into variadic functions). */
#define fail_at(r, s, st, ...) (report((r), (s), __VA_ARGS__), (st))
#define fail(r, s, ...) fail_at((r), (s), KC_E_ARG, __VA_ARGS__)

/* Every key of group must be in allowed (NULL-terminated). */
static kc_status check_keys(reader *r, const config_setting_t *group, const char *where, const char *const *allowed)
{
    int n = config_setting_length(group);
    for (int i = 0; i < n; i++) {
        const config_setting_t *s = config_setting_get_elem(group, (unsigned)i);
        const char *name = config_setting_name(s);
        int known = 0;
        for (const char *const *a = allowed; *a != NULL && !known; a++)
            known = strcmp(name, *a) == 0;
        if (!known) {
            char list[256] = "";
            size_t len = 0;
            for (const char *const *a = allowed; *a != NULL; a++) {
                int w = snprintf(list + len, sizeof list - len, "%s%s", a == allowed ? "" : ", ", *a);
                if (w < 0 || (size_t)w >= sizeof list - len)
                    break;
                len += (size_t)w;
            }
            return fail(r, s, "unknown key \"%s\" in %s (expected one of: %s)", name, where, list);
        }
    }
    return KC_OK;
}

static int is_number(const config_setting_t *s)
{
    int t = config_setting_type(s);
    return t == CONFIG_TYPE_INT || t == CONFIG_TYPE_INT64 || t == CONFIG_TYPE_FLOAT;
}

/* A number from s, times scale, finite in kc_real. */
static kc_status number_of(reader *r, const config_setting_t *s, const char *what, kc_real scale, kc_real *out)
{
    if (!is_number(s))
        return fail(r, s, "%s must be a number", what);
    kc_real v = (kc_real)config_setting_get_float(s) * scale;
    if (!kc_isfinite(v))
        return fail(r, s, "%s is not a finite number", what);
    *out = v;
    return KC_OK;
}

/* An optional (required = 0) or required number key; *present says which. */
static kc_status lookup_number(reader *r, const config_setting_t *group, const char *key, const char *where,
                               int required, kc_real scale, kc_real *out, int *present)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    char what[128];
    if (present != NULL)
        *present = s != NULL;
    if (s == NULL)
        return required ? fail(r, group, "%s: missing key \"%s\"", where, key) : KC_OK;
    snprintf(what, sizeof what, "%s: %s", where, key);
    return number_of(r, s, what, scale, out);
}

/* A vector of n numbers: an array [..] or a list (..). */
static kc_status vector_of(reader *r, const config_setting_t *s, const char *what, int n, kc_real scale, kc_real *out)
{
    if (!config_setting_is_array(s) && !config_setting_is_list(s))
        return fail(r, s, "%s must be a vector of %d numbers, e.g. [0.0, 0.0, 0.0]", what, n);
    if (config_setting_length(s) != n)
        return fail(r, s, "%s must hold %d numbers, not %d", what, n, config_setting_length(s));
    for (int i = 0; i < n; i++) {
        char item[112];
        snprintf(item, sizeof item, "%s[%d]", what, i);
        kc_status st = number_of(r, config_setting_get_elem(s, (unsigned)i), item, scale, &out[i]);
        if (st != KC_OK)
            return st;
    }
    return KC_OK;
}

static kc_status lookup_string(reader *r, const config_setting_t *group, const char *key, const char *where,
                               int required, const char **out)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    if (s == NULL)
        return required ? fail(r, group, "%s: missing key \"%s\"", where, key) : KC_OK;
    const char *v = config_setting_type(s) == CONFIG_TYPE_STRING ? config_setting_get_string(s) : NULL;
    if (v == NULL)
        return fail(r, s, "%s: %s must be a string in double quotes", where, key);
    *out = v;
    return KC_OK;
}

static kc_status lookup_bool(reader *r, const config_setting_t *group, const char *key, const char *where, int *out)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    if (s == NULL)
        return KC_OK;
    if (config_setting_type(s) != CONFIG_TYPE_BOOL)
        return fail(r, s, "%s: %s must be true or false", where, key);
    *out = config_setting_get_bool(s);
    return KC_OK;
}

/* Optional limits group; angular (revolute) limits and rates are in the
 * file's angle unit. */
static kc_status read_limits(reader *r, const config_setting_t *owner, const char *where, int angular,
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
    if ((st = check_keys(r, g, what, keys)) != KC_OK)
        return st;
    const config_setting_t *q = config_setting_get_member(g, "q");
    if (q != NULL) {
        kc_real mm[2] = {KC_R(0.0), KC_R(0.0)};
        char qwhat[112];
        snprintf(qwhat, sizeof qwhat, "%s: q", what);
        if ((st = vector_of(r, q, qwhat, 2, scale, mm)) != KC_OK)
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
        if ((st = lookup_number(r, g, rates[i], what, 0, scale, &v, &present)) != KC_OK)
            return st;
        if (!present)
            continue;
        if (!(v > KC_R(0.0)))
            return fail(r, config_setting_get_member(g, rates[i]), "%s: %s must be > 0 (omit it for no limit)", what,
                        rates[i]);
        *dest[i] = v;
    }
    *out = l;
    return KC_OK;
}

static kc_status read_pose(reader *r, const config_setting_t *robot, const char *key, kc_pose *out, int *present)
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
    if ((st = check_keys(r, g, key, keys)) != KC_OK)
        return st;
    const config_setting_t *s = config_setting_get_member(g, "xyz");
    snprintf(what, sizeof what, "%s xyz", key);
    if (s != NULL && (st = vector_of(r, s, what, 3, KC_R(1.0), xyz)) != KC_OK)
        return st;
    s = config_setting_get_member(g, "rpy");
    snprintf(what, sizeof what, "%s rpy", key);
    if (s != NULL && (st = vector_of(r, s, what, 3, r->deg ? KC_DEG : KC_R(1.0), rpy)) != KC_OK)
        return st;
    /* URDF's rpy [about x, about y, about z] is R = Rz Ry Rx: seed 001's
     * roll-pitch-yaw with phi about z, theta about y, psi about x. */
    kc_euler e = {rpy[2], rpy[1], rpy[0]};
    kc_orient_rpy_to_mat3(&e, &out->R);
    out->t = kc_vec3_make(xyz[0], xyz[1], xyz[2]);
    return KC_OK;
}

/* Copies an optional joint name into info's table. */
static kc_status read_joint_name(reader *r, const config_setting_t *g, const char *where, char *dest)
{
    const char *name = NULL;
    kc_status st = lookup_string(r, g, "name", where, 0, &name);
    if (st != KC_OK || name == NULL)
        return st;
    if (strlen(name) >= KC_DESC_NAME_LEN)
        return fail(r, config_setting_get_member(g, "name"), "%s: name is longer than %d characters", where,
                    KC_DESC_NAME_LEN - 1);
    snprintf(dest, KC_DESC_NAME_LEN, "%s", name);
    return KC_OK;
}

static kc_status too_many_joints(reader *r, const config_setting_t *s)
{
    return fail_at(r, s, KC_E_CAPACITY, "too many joints: kinctl supports at most %d", KC_MAX_JOINTS);
}

/* One standard or modified DH row. */
static kc_status read_dh_row(reader *r, const config_setting_t *g, const char *where, int modified, kc_chain *chain,
                             kc_desc_info *info)
{
    static const char *const keys[] = {"name", "type", "a", "alpha", "d", "theta", "limits", NULL};
    kc_real ang = r->deg ? KC_DEG : KC_R(1.0);
    kc_dh_row row;
    const char *type = NULL;
    kc_status st;
    if (!config_setting_is_group(g))
        return fail(r, g, "%s must be a group { type = ...; a = ...; alpha = ...; d = ...; theta = ...; }", where);
    if ((st = check_keys(r, g, where, keys)) != KC_OK)
        return st;
    if (chain->n_joints >= KC_MAX_JOINTS)
        return too_many_joints(r, g);
    if ((st = lookup_string(r, g, "type", where, 1, &type)) != KC_OK)
        return st;
    if (strcmp(type, "revolute") == 0)
        row.type = KC_JOINT_REVOLUTE;
    else if (strcmp(type, "prismatic") == 0)
        row.type = KC_JOINT_PRISMATIC;
    else
        return fail(r, config_setting_get_member(g, "type"),
                    "%s: unknown joint type \"%s\" (expected \"revolute\" or \"prismatic\")", where, type);
    if ((st = lookup_number(r, g, "a", where, 1, KC_R(1.0), &row.a, NULL)) != KC_OK ||
        (st = lookup_number(r, g, "alpha", where, 1, ang, &row.alpha, NULL)) != KC_OK ||
        (st = lookup_number(r, g, "d", where, 1, KC_R(1.0), &row.d, NULL)) != KC_OK ||
        (st = lookup_number(r, g, "theta", where, 1, ang, &row.theta, NULL)) != KC_OK ||
        (st = read_limits(r, g, where, row.type == KC_JOINT_REVOLUTE, &row.limits)) != KC_OK ||
        (st = read_joint_name(r, g, where, info->joint_names[chain->n_joints])) != KC_OK)
        return st;
    st = modified ? kc_chain_add_mdh(chain, &row) : kc_chain_add_dh(chain, &row);
    if (st == KC_E_CAPACITY)
        return fail_at(r, g, st, "%s: the chain exceeds kinctl's capacity (%d elements, %d frames)", where,
                       KC_MAX_ELEMENTS, KC_MAX_FRAMES);
    if (st != KC_OK)
        return fail_at(r, g, st, "%s: rejected by the chain builder: %s", where, kc_status_str(st));
    return KC_OK;
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
static kc_status read_element(reader *r, const config_setting_t *g, const char *where, kc_chain *chain,
                              kc_desc_info *info)
{
    static const char *const keys[] = {"op", "joint", "value", "offset", "frame", "limits", "name", NULL};
    const char *op = NULL;
    int joint = 0, frame = 0;
    kc_status st;
    if (!config_setting_is_group(g))
        return fail(r, g, "%s must be a group { op = \"rz\"; joint = true; } or { op = \"tz\"; value = 0.1; }", where);
    if ((st = check_keys(r, g, where, keys)) != KC_OK || (st = lookup_string(r, g, "op", where, 1, &op)) != KC_OK ||
        (st = lookup_bool(r, g, "joint", where, &joint)) != KC_OK ||
        (st = lookup_bool(r, g, "frame", where, &frame)) != KC_OK)
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
        if ((st = lookup_number(r, g, "offset", where, 0, scale, &offset, NULL)) != KC_OK ||
            (st = read_limits(r, g, where, rotation, &lim)) != KC_OK ||
            (st = read_joint_name(r, g, where, info->joint_names[chain->n_joints])) != KC_OK)
            return st;
        st = kc_chain_add_joint(chain, (kc_code)(KC_CODE_RX_JOINT + k), offset, &lim);
    } else {
        static const char *const joint_only[] = {"offset", "limits", "name", NULL};
        for (const char *const *key = joint_only; *key != NULL; key++)
            if (config_setting_get_member(g, *key) != NULL)
                return fail(r, config_setting_get_member(g, *key),
                            "%s: %s belongs to a joint (joint = true); a constant takes value", where, *key);
        kc_real value = KC_R(0.0);
        if ((st = lookup_number(r, g, "value", where, 1, scale, &value, NULL)) != KC_OK)
            return st;
        st = kc_chain_add_const(chain, (kc_code)(KC_CODE_RX + k), value);
        if (st == KC_OK && frame)
            st = kc_chain_add_frame(chain);
    }
    if (st == KC_E_CAPACITY)
        return fail_at(r, g, st, "%s: the chain exceeds kinctl's capacity (%d elements, %d frames)", where,
                       KC_MAX_ELEMENTS, KC_MAX_FRAMES);
    if (st != KC_OK)
        return fail_at(r, g, st, "%s: rejected by the chain builder: %s", where, kc_status_str(st));
    return KC_OK;
}

/* ---- shapes: link volumes and forbidden zones (kinctl/zone.h) ---- */

/* A rotation from rpy (the file's angle unit), as for base and tool. */
static void rpy_to_mat3(const kc_real *rpy, kc_mat3 *R)
{
    kc_euler e = {rpy[2], rpy[1], rpy[0]};
    kc_orient_rpy_to_mat3(&e, R);
}

/* One shape group: shape = "sphere" | "capsule" | "cylinder" | "box" |
 * "frustum" | "halfspace" (zones only) with its keys (see kinctl/desc.h).
 * extra lists the keys the caller reads itself (name, frame). */
static kc_status read_shape(reader *r, const config_setting_t *g, const char *where, int zone, kc_shape *out)
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
    if ((st = check_keys(r, g, where, keys)) != KC_OK || (st = lookup_string(r, g, "shape", where, 1, &shape)) != KC_OK)
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
        if ((st = vector_of(r, m_, what, n, scale, dst)) != KC_OK)                                   \
            return st;                                                                               \
    } while (0)
    switch (sh.kind) {
    case KC_SHAPE_SPHERE:
        VEC("xyz", 3, KC_R(1.0), v3);
        sh.pose.t = kc_vec3_make(v3[0], v3[1], v3[2]);
        if ((st = lookup_number(r, g, "radius", where, 1, KC_R(1.0), &sh.dim[0], NULL)) != KC_OK)
            return st;
        break;
    case KC_SHAPE_CAPSULE:
    case KC_SHAPE_CYLINDER: {
        VEC("from", 3, KC_R(1.0), v3);
        VEC("to", 3, KC_R(1.0), w3);
        if ((st = lookup_number(r, g, "radius", where, 1, KC_R(1.0), &r0, NULL)) != KC_OK)
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
        rpy_to_mat3(rpy, &sh.pose.R);
        if (sh.kind == KC_SHAPE_BOX) {
            VEC("half", 3, KC_R(1.0), sh.dim);
        } else {
            VEC("bottom", 2, KC_R(1.0), two);
            sh.dim[0] = two[0];
            sh.dim[1] = two[1];
            VEC("top", 2, KC_R(1.0), two);
            sh.dim[2] = two[0];
            sh.dim[3] = two[1];
            if ((st = lookup_number(r, g, "half_height", where, 1, KC_R(1.0), &sh.dim[4], NULL)) != KC_OK)
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

static kc_status read_shape_name(reader *r, const config_setting_t *g, const char *where, char *dest)
{
    return read_joint_name(r, g, where, dest);
}

/* robot.volumes: link volumes on frames 1..n_frames. */
static kc_status read_volumes(reader *r, const config_setting_t *list, kc_chain *chain, kc_desc_info *info)
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
        if ((st = read_shape(r, g, where, 0, &sh)) != KC_OK ||
            (st = lookup_number(r, g, "frame", where, 1, KC_R(1.0), &frame, NULL)) != KC_OK ||
            (st = read_shape_name(r, g, where, info->volume_names[chain->n_volumes])) != KC_OK)
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

static kc_status read_robot(reader *r, const config_setting_t *robot, kc_chain *chain, kc_desc_info *info)
{
    static const char *const keys[] = {"name", "angles", "base", "tool", "dh", "mdh", "elements", "volumes", NULL};
    static const char *const chains[3] = {"dh", "mdh", "elements"};
    const char *name = NULL, *angles = NULL;
    kc_status st;
    if (!config_setting_is_group(robot))
        return fail(r, robot, "robot must be a group: robot = { name = ...; angles = ...; dh = (...); };");
    if ((st = check_keys(r, robot, "robot", keys)) != KC_OK ||
        (st = lookup_string(r, robot, "name", "robot", 1, &name)) != KC_OK ||
        (st = lookup_string(r, robot, "angles", "robot", 1, &angles)) != KC_OK)
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
static kc_status read_root(reader *r, const config_t *cfg, kc_chain *chain, kc_desc_info *info)
{
    static const char *const sections[] = {"robot", "controller", NULL};
    const config_setting_t *root = config_root_setting(cfg);
    kc_status st = check_keys(r, root, "the top level", sections);
    if (st != KC_OK)
        return st;
    const config_setting_t *robot = config_setting_get_member(root, "robot");
    if (robot == NULL)
        return fail(r, NULL, "no robot section: expected robot = { name = ...; angles = ...; dh = (...); };");
    return read_robot(r, robot, chain, info);
}

/* Parses (text != NULL) or reads path into cfg; on error cfg is destroyed. */
static kc_status parse(reader *rd, const char *path, const char *text, const char *name, config_t *cfg)
{
    reader *r = rd;
    kc_desc_error *err = rd->err;
    kc_status st = KC_OK;
    if (path != NULL) {
        FILE *f = fopen(path, "r");
        if (f == NULL)
            return fail(r, NULL, "cannot open: %s", strerror(errno));
        fclose(f);
    }
    config_init(cfg);
    config_set_options(cfg, CONFIG_OPTION_AUTOCONVERT);
    int ok;
    if (path != NULL) {
        /* @include "x.cfg" is resolved beside the including file. */
        const char *slash = strrchr(path, '/');
        if (slash != NULL) {
            size_t len = (size_t)(slash - path);
            char *dir = malloc(len + 2);
            if (dir != NULL) {
                memcpy(dir, path, len + (len == 0));
                dir[len + (len == 0)] = '\0';
                config_set_include_dir(cfg, dir);
                free(dir); /* libconfig keeps its own copy */
            }
        }
        ok = config_read_file(cfg, path);
    } else {
        ok = config_read_string(cfg, text);
    }
    if (!ok) {
        const char *hint = "";
        if (config_error_text(cfg) != NULL && strstr(config_error_text(cfg), "mismatched element type") != NULL)
            hint = " (an array [..] may not mix 1 and 1.5: write 1.0)";
        const char *file = config_error_file(cfg);
        if (err != NULL) {
            char msg[KC_DESC_TEXT_LEN];
            snprintf(msg, sizeof msg, "%s%s", config_error_text(cfg) != NULL ? config_error_text(cfg) : "parse error",
                     hint);
            write_error(err, file != NULL ? file : name, config_error_line(cfg), msg);
        }
        st = KC_E_ARG;
        config_destroy(cfg);
    }
    return st;
}

/* Parses, then builds into temporaries so that the outputs stay untouched
 * on error. */
static kc_status load(const char *path, const char *text, const char *name, kc_chain *chain, kc_desc_info *info,
                      kc_desc_error *err)
{
    /* cppcheck-suppress ctuuninitvar ; err is an output: stored here, written before any read */
    reader r = {name, err, 0};
    config_t cfg;
    kc_chain tmp;
    kc_desc_info tmp_info;
    if (err != NULL)
        memset(err, 0, sizeof *err);
    if (chain == NULL || (path == NULL && text == NULL))
        return fail(&r, NULL, "no chain to fill or no input given");
    memset(&tmp_info, 0, sizeof tmp_info);
    kc_chain_init(&tmp);
    kc_status st = parse(&r, path, text, name, &cfg);
    if (st != KC_OK)
        return st;
    st = read_root(&r, &cfg, &tmp, &tmp_info);
    config_destroy(&cfg);
    if (st != KC_OK)
        return st;
    *chain = tmp;
    if (info != NULL)
        *info = tmp_info;
    return KC_OK;
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

/* ---- zones ---- */

static kc_status read_zones(reader *r, const config_setting_t *g, kc_zone_set *set, kc_desc_zone_info *info)
{
    static const char *const keys[] = {"margin", "near", "angles", "list", NULL};
    const char *angles = NULL;
    kc_status st;
    if (!config_setting_is_group(g))
        return fail(r, g, "controller.zones must be a group { margin = 0.02; list = ( ... ); }");
    if ((st = check_keys(r, g, "controller.zones", keys)) != KC_OK ||
        (st = lookup_number(r, g, "margin", "controller.zones", 0, KC_R(1.0), &set->margin, NULL)) != KC_OK ||
        (st = lookup_number(r, g, "near", "controller.zones", 0, KC_R(1.0), &set->near, NULL)) != KC_OK ||
        (st = lookup_string(r, g, "angles", "controller.zones", 0, &angles)) != KC_OK)
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
        if ((st = read_shape(r, z, where, 1, &sh)) != KC_OK ||
            (st = read_shape_name(r, z, where, info->names[set->n_zones])) != KC_OK)
            return st;
        set->zones[set->n_zones++] = sh;
    }
    info->n_zones = set->n_zones;
    return KC_OK;
}

kc_status kc_desc_load_zones(const char *path, kc_zone_set *set, kc_desc_zone_info *info, kc_desc_error *err)
{
    const char *name = path != NULL ? path : "<null>";
    /* cppcheck-suppress ctuuninitvar ; err is an output: stored here, written before any read */
    reader r = {name, err, 0};
    config_t cfg;
    kc_zone_set tmp;
    kc_desc_zone_info tmp_info;
    if (err != NULL)
        memset(err, 0, sizeof *err);
    if (path == NULL || set == NULL)
        return fail(&r, NULL, "no zone set to fill or no file given");
    kc_zone_set_init(&tmp);
    memset(&tmp_info, 0, sizeof tmp_info);
    kc_status st = parse(&r, path, NULL, name, &cfg);
    if (st != KC_OK)
        return st;
    const config_setting_t *ctl = config_setting_get_member(config_root_setting(&cfg), "controller");
    const config_setting_t *zones = ctl != NULL && config_setting_is_group(ctl) ? config_setting_get_member(ctl, "zones")
                                                                                 : NULL;
    if (zones != NULL)
        st = read_zones(&r, zones, &tmp, &tmp_info);
    config_destroy(&cfg);
    if (st != KC_OK)
        return st;
    *set = tmp;
    if (info != NULL)
        *info = tmp_info;
    return KC_OK;
}
