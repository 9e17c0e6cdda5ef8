/* SPDX-License-Identifier: BSD-3-Clause */
/* kinctl-calc - the command-line calculator: forward kinematics, Jacobians,
 * orientation conversions and lab 1 transforms for built-in arms or arms
 * described in a file, one answer as JSON, or many from JSON lines (batch).
 *
 * Adding a subcommand: write `static int run_x(const json_t *req, calc_ctx
 * *ctx)`, an option table, and one entry in `commands` below. Batch gets the
 * op for free (its keys are the option keys). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "calc.h"
#include "kinctl/version.h"

#define EXIT_BAD_INPUT 2
#define EXIT_FAILURE_IO 1

/* ---- fk ---- */

static const calc_opt fk_opts[] = {
    CALC_MODEL_OPTS,
    {"--frames", "frames", CALC_FLAG, NULL, NULL,
     "also print the base pose (\"base\") and every frame 0T_1 .. 0T_m (\"frames\")"},
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

static int run_fk(const json_t *req, calc_ctx *ctx)
{
    kc_chain chain;
    kc_real q[KC_MAX_JOINTS];
    kc_pose tool, frames[KC_MAX_FRAMES];
    int deg = 0, want_frames = 0;
    if (req_bool(ctx, req, "deg", &deg) != 0 || req_bool(ctx, req, "frames", &want_frames) != 0 ||
        req_model(ctx, req, &chain) != 0 || req_q(ctx, req, &chain, deg, q) != 0)
        return -1;
    kc_status st = kc_fk_frames(&chain, q, frames, &tool);
    if (st != KC_OK)
        return calc_fail(ctx, "fk failed: %s", kc_status_str(st));
    jw_key(ctx->out, "pose");
    jw_pose(ctx->out, &tool);
    if (want_frames) {
        jw_key(ctx->out, "base");
        jw_pose(ctx->out, &chain.base);
        jw_key(ctx->out, "frames");
        jw_arr_begin(ctx->out);
        for (int f = 0; f < chain.n_frames; f++)
            jw_pose(ctx->out, &frames[f]);
        jw_arr_end(ctx->out);
    }
    return 0;
}

/* ---- jacobian ---- */

static const calc_opt jacobian_opts[] = {
    CALC_MODEL_OPTS,
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

static int run_jacobian(const json_t *req, calc_ctx *ctx)
{
    kc_chain chain;
    kc_real q[KC_MAX_JOINTS];
    kc_jacobian jac;
    int deg = 0;
    if (req_bool(ctx, req, "deg", &deg) != 0 || req_model(ctx, req, &chain) != 0 ||
        req_q(ctx, req, &chain, deg, q) != 0)
        return -1;
    kc_status st = kc_fk_jacobian(&chain, q, &jac, NULL);
    if (st != KC_OK)
        return calc_fail(ctx, "jacobian failed: %s", kc_status_str(st));
    jw_key(ctx->out, "jacobian");
    jw_arr_begin(ctx->out);
    for (int i = 0; i < 6; i++)
        jw_reals(ctx->out, jac.m[i], chain.n_joints);
    jw_arr_end(ctx->out);
    return 0;
}

/* ---- orient ---- */

static const calc_opt orient_opts[] = {
    {"--from", "from", CALC_VALUE, calc_conv_string, "FORM", "rpy, zyz, axis-angle, quat or matrix"},
    {"--to", "to", CALC_VALUE, calc_conv_string, "FORM", "rpy, zyz, axis-angle, quat or matrix"},
    {"--deg", "deg", CALC_FLAG, NULL, NULL, "angles in and out in degrees"},
    {NULL, "values", CALC_EXTEND, calc_conv_reals, "VALUES", "the input numbers (spaces or commas between them)"},
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

typedef enum orient_form { FORM_RPY, FORM_ZYZ, FORM_AXIS_ANGLE, FORM_QUAT, FORM_MATRIX, FORM_COUNT } orient_form;
static const char *const form_names[FORM_COUNT] = {"rpy", "zyz", "axis-angle", "quat", "matrix"};
static const int form_counts[FORM_COUNT] = {3, 3, 4, 4, 9};

static int form_of(calc_ctx *ctx, const json_t *req, const char *key)
{
    const char *name = NULL;
    if (req_string(ctx, req, key, 1, &name) != 0)
        return -1;
    for (int f = 0; f < FORM_COUNT; f++)
        if (strcmp(name, form_names[f]) == 0)
            return f;
    return calc_fail(ctx, "unknown %s form \"%s\" (expected rpy, zyz, axis-angle, quat or matrix)", key, name);
}

static int run_orient(const json_t *req, calc_ctx *ctx)
{
    kc_real v[9];
    int n = 0, deg = 0;
    int from = form_of(ctx, req, "from");
    int to = from < 0 ? -1 : form_of(ctx, req, "to");
    if (to < 0 || req_bool(ctx, req, "deg", &deg) != 0 ||
        req_reals(ctx, json_object_get(req, "values"), "values", v, 9, &n) != 0)
        return -1;
    if (n != form_counts[from])
        return calc_fail(ctx, "%s takes %d values, got %d", form_names[from], form_counts[from], n);
    kc_real unit = deg ? KC_DEG : KC_R(1.0);
    kc_mat3 R;
    switch ((orient_form)from) {
    case FORM_RPY:
    case FORM_ZYZ: {
        kc_euler e = {v[0] * unit, v[1] * unit, v[2] * unit};
        if (from == FORM_RPY)
            kc_orient_rpy_to_mat3(&e, &R);
        else
            kc_orient_zyz_to_mat3(&e, &R);
        break;
    }
    case FORM_AXIS_ANGLE: {
        kc_vec3 k = kc_vec3_make(v[0], v[1], v[2]);
        if (kc_orient_axis_angle_to_mat3(&k, v[3] * unit, &R) != KC_OK)
            return calc_fail(ctx, "axis-angle: the axis must not be zero");
        break;
    }
    case FORM_QUAT: {
        kc_quat q = {v[0], v[1], v[2], v[3]}, u;
        if (kc_quat_normalize(&q, &u) != KC_OK)
            return calc_fail(ctx, "quat: the quaternion must not be zero");
        kc_quat_to_mat3(&u, &R);
        break;
    }
    case FORM_MATRIX:
    default:
        for (int i = 0; i < 9; i++)
            R.m[i / 3][i % 3] = v[i];
        if (!(kc_mat3_rotation_error(&R) <= KC_TOL_ORTHONORMAL))
            return calc_fail(ctx, "matrix: not a rotation (error %g > %g: rows must be orthonormal, det +1)",
                             (double)kc_mat3_rotation_error(&R), (double)KC_TOL_ORTHONORMAL);
        break;
    }
    int singular = 0;
    jw *out = ctx->out;
    switch ((orient_form)to) {
    case FORM_RPY:
    case FORM_ZYZ: {
        kc_euler e;
        singular = to == FORM_RPY ? kc_orient_mat3_to_rpy(&R, &e) : kc_orient_mat3_to_zyz(&R, &e);
        kc_real a[3] = {e.phi / unit, e.theta / unit, e.psi / unit};
        jw_key(out, form_names[to]);
        jw_reals(out, a, 3);
        break;
    }
    case FORM_AXIS_ANGLE: {
        kc_vec3 k;
        kc_real theta;
        singular = kc_orient_mat3_to_axis_angle(&R, &k, &theta);
        jw_key(out, "axis");
        jw_reals(out, k.v, 3);
        jw_key(out, "angle");
        jw_real(out, theta / unit);
        break;
    }
    case FORM_QUAT: {
        kc_quat q;
        kc_quat_from_mat3(&R, &q);
        kc_real a[4] = {q.w, q.x, q.y, q.z};
        jw_key(out, "quat");
        jw_reals(out, a, 4);
        break;
    }
    case FORM_MATRIX:
    default:
        jw_key(out, "matrix");
        jw_mat3(out, &R);
        break;
    }
    jw_key(out, "singular");
    jw_bool(out, singular);
    return 0;
}

/* ---- transform ---- */

/* "AXIS,NUMBER" to {"axis": AXIS, name: NUMBER}. */
static json_t *conv_axis_number(const char *arg, const char *name, char *err, size_t errlen)
{
    if ((arg[0] != 'x' && arg[0] != 'y' && arg[0] != 'z') || arg[1] != ',') {
        snprintf(err, errlen, "expected AXIS,%s with AXIS x, y or z, not \"%s\"", name, arg);
        return NULL;
    }
    json_t *num = calc_conv_real(arg + 2, err, errlen);
    if (num == NULL)
        return NULL;
    char axis[2] = {arg[0], '\0'};
    return json_pack("{s:s,s:o}", "axis", axis, name, num);
}

static json_t *wrap(const char *op, json_t *v) { return v != NULL ? json_pack("{s:o}", op, v) : NULL; }

/* Three numbers (form names them in the message: "X,Y,Z"). */
static json_t *conv_vec3(const char *arg, const char *form, char *err, size_t errlen)
{
    json_t *v = calc_conv_reals(arg, err, errlen);
    if (v != NULL && json_array_size(v) != 3) {
        snprintf(err, errlen, "expected %s, not \"%s\"", form, arg);
        json_decref(v);
        return NULL;
    }
    return v;
}
static json_t *conv_translate(const char *arg, char *err, size_t errlen)
{
    return wrap("translate", conv_vec3(arg, "DX,DY,DZ", err, errlen));
}
static json_t *conv_rotate(const char *arg, char *err, size_t errlen)
{
    return wrap("rotate", conv_axis_number(arg, "angle", err, errlen));
}
static json_t *conv_scale(const char *arg, char *err, size_t errlen)
{
    return wrap("scale", calc_conv_real(arg, err, errlen));
}
static json_t *conv_perspective(const char *arg, char *err, size_t errlen)
{
    return wrap("perspective", conv_axis_number(arg, "f", err, errlen));
}
static json_t *conv_point(const char *arg, char *err, size_t errlen)
{
    return conv_vec3(arg, "X,Y,Z", err, errlen);
}

static const calc_opt transform_opts[] = {
    {"--translate", "ops", CALC_APPEND, conv_translate, "DX,DY,DZ", "translation"},
    {"--rotate", "ops", CALC_APPEND, conv_rotate, "AXIS,ANGLE", "rotation about x, y or z (rad; deg with --deg)"},
    {"--scale", "ops", CALC_APPEND, conv_scale, "S", "global scale: s in element (4,4), points shrink by 1/s"},
    {"--perspective", "ops", CALC_APPEND, conv_perspective, "AXIS,F", "perspective along x, y or z, focal length F"},
    {"--point", "points", CALC_APPEND, conv_point, "X,Y,Z", "a point to transform (repeatable)"},
    {"--deg", "deg", CALC_FLAG, NULL, NULL, "rotation angles in degrees"},
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

static int axis_of(calc_ctx *ctx, const json_t *op, const char *what, kc_axis *axis)
{
    const char *a = NULL;
    if (req_string(ctx, op, "axis", 1, &a) != 0)
        return -1;
    if (strcmp(a, "x") != 0 && strcmp(a, "y") != 0 && strcmp(a, "z") != 0)
        return calc_fail(ctx, "%s: axis must be \"x\", \"y\" or \"z\", not \"%s\"", what, a);
    *axis = (kc_axis)(a[0] - 'x');
    return 0;
}

/* One operation {"translate": [dx, dy, dz]}, {"rotate": {"axis", "angle"}},
 * {"scale": s} or {"perspective": {"axis", "f"}} as a matrix. */
static int op_matrix(calc_ctx *ctx, const json_t *op, size_t index, int deg, kc_mat4 *M)
{
    char what[48];
    snprintf(what, sizeof what, "ops[%zu]", index);
    if (!json_is_object(op) || json_object_size(op) != 1)
        return calc_fail(ctx, "%s must be an object with one key: translate, rotate, scale or perspective", what);
    const char *name = json_object_iter_key(json_object_iter((json_t *)op));
    const json_t *arg = json_object_iter_value(json_object_iter((json_t *)op));
    kc_axis axis;
    kc_real x;
    if (strcmp(name, "translate") == 0) {
        kc_real d[3];
        int n = 0;
        if (req_reals(ctx, arg, "translate", d, 3, &n) != 0)
            return -1;
        if (n != 3)
            return calc_fail(ctx, "%s: translate takes [dx, dy, dz]", what);
        kc_mat4_translation(d[0], d[1], d[2], M);
    } else if (strcmp(name, "rotate") == 0) {
        if (!json_is_object(arg) || axis_of(ctx, arg, "rotate", &axis) != 0 || req_real(ctx, arg, "angle", &x) != 0)
            return ctx->err[0] != '\0' ? -1 : calc_fail(ctx, "%s: rotate takes {\"axis\": \"z\", \"angle\": A}", what);
        kc_mat4_rotation(axis, deg ? x * KC_DEG : x, M);
    } else if (strcmp(name, "scale") == 0) {
        if (!json_is_number(arg) || !kc_isfinite(x = (kc_real)json_number_value(arg)))
            return calc_fail(ctx, "%s: scale takes a finite number", what);
        if (kc_mat4_scale(x, M) != KC_OK)
            return calc_fail(ctx, "%s: scale must not be 0", what);
    } else if (strcmp(name, "perspective") == 0) {
        if (!json_is_object(arg) || axis_of(ctx, arg, "perspective", &axis) != 0 || req_real(ctx, arg, "f", &x) != 0)
            return ctx->err[0] != '\0' ? -1 : calc_fail(ctx, "%s: perspective takes {\"axis\": \"z\", \"f\": F}", what);
        if (kc_mat4_perspective(axis, x, M) != KC_OK)
            return calc_fail(ctx, "%s: the focal length must not be 0", what);
    } else {
        return calc_fail(ctx, "%s: unknown operation \"%s\" (translate, rotate, scale, perspective)", what, name);
    }
    return 0;
}

static int run_transform(const json_t *req, calc_ctx *ctx)
{
    const json_t *ops = json_object_get(req, "ops"), *points = json_object_get(req, "points");
    int deg = 0;
    kc_mat4 M;
    if (req_bool(ctx, req, "deg", &deg) != 0)
        return -1;
    if (!json_is_array(ops) || json_array_size(ops) == 0)
        return calc_fail(ctx, "give at least one operation: --translate, --rotate, --scale or --perspective");
    if (points != NULL && !json_is_array(points))
        return calc_fail(ctx, "points must be an array of [x, y, z]");
    /* Operations act on the points in the order given: M = M_k ... M_1. */
    kc_mat4_identity(&M);
    for (size_t i = 0; i < json_array_size(ops); i++) {
        kc_mat4 Mi;
        if (op_matrix(ctx, json_array_get(ops, i), i, deg, &Mi) != 0)
            return -1;
        kc_mat4_mul(&Mi, &M, &M);
    }
    size_t np = points != NULL ? json_array_size(points) : 0;
    kc_vec3 *p = malloc((np + 1) * sizeof *p);
    if (p == NULL)
        return calc_fail(ctx, "out of memory");
    for (size_t i = 0; i < np; i++) {
        char what[48];
        int n = 0;
        snprintf(what, sizeof what, "points[%zu]", i);
        if (req_reals(ctx, json_array_get(points, i), what, p[i].v, 3, &n) != 0 ||
            (n != 3 && calc_fail(ctx, "%s must be [x, y, z]", what) != 0)) {
            free(p);
            return -1;
        }
    }
    jw *out = ctx->out;
    jw_key(out, "matrix");
    jw_mat4(out, &M);
    jw_key(out, "homogeneous");
    jw_arr_begin(out);
    for (size_t i = 0; i < np; i++) {
        kc_real h[4];
        kc_mat4_apply_h(&M, &p[i], h);
        jw_reals(out, h, 4);
    }
    jw_arr_end(out);
    /* null where w = 0: the point lies in the perspective's vanishing plane. */
    jw_key(out, "cartesian");
    jw_arr_begin(out);
    for (size_t i = 0; i < np; i++) {
        kc_vec3 c;
        if (kc_mat4_apply(&M, &p[i], &c) == KC_OK)
            jw_reals(out, c.v, 3);
        else
            jw_null(out);
    }
    jw_arr_end(out);
    free(p);
    return 0;
}

/* ---- the table ---- */

static int run_batch(const json_t *req, calc_ctx *ctx);

static const calc_opt batch_opts[] = {
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

static const calc_cmd commands[] = {
    {"fk", "forward kinematics: the tool pose (and every frame)",
     "kinctl-calc fk (--model NAME | --model-file PATH) --q Q1,Q2,... [--deg] [--frames]\n"
     "Prints {\"pose\": [[r11,r12,r13,px],[r21,..],[r31,..],[0,0,0,1]]} in the base frame (m),\n"
     "and \"base\" and \"frames\": [0T_1, .., 0T_m] with --frames. q outside a joint's position limits is\n"
     "computed anyway, with a warning on stderr (in batch: \"warnings\": [...]).\n"
     "Example: kinctl-calc fk --model puma560 --q 0,0.5,-0.5,0,0.3,0",
     fk_opts, run_fk},
    {"jacobian", "geometric Jacobian 6 x n in the base frame",
     "kinctl-calc jacobian (--model NAME | --model-file PATH) --q Q1,Q2,... [--deg]\n"
     "Prints {\"jacobian\": [6 rows of n]}: rows vx vy vz wx wy wz (v at the tool point, m/s and\n"
     "rad/s per unit joint rate: rad/s or m/s, whatever --deg says about the input).\n"
     "Example: kinctl-calc jacobian --model panda --q 0,-0.3,0,-2,0,1.7,0.8",
     jacobian_opts, run_jacobian},
    {"orient", "convert an orientation between rpy, zyz, axis-angle, quat, matrix",
     "kinctl-calc orient --from FORM --to FORM [--deg] VALUES...\n"
     "Forms and their VALUES:\n"
     "  rpy         phi theta psi: R = Rz(phi) Ry(theta) Rx(psi) (roll-pitch-yaw)\n"
     "  zyz         phi theta psi: R = Rz(phi) Ry(theta) Rz(psi)\n"
     "  axis-angle  kx ky kz theta (the axis need not be unit)\n"
     "  quat        w x y z (normalised)\n"
     "  matrix      r11 r12 r13 r21 r22 r23 r31 r32 r33 (row-major, a rotation)\n"
     "Prints {\"rpy\"|\"zyz\": [phi,theta,psi]} or {\"axis\": [..], \"angle\": a} or {\"quat\": [w,x,y,z]}\n"
     "or {\"matrix\": [[..],[..],[..]]}, with \"singular\": true in gimbal lock (rpy, zyz) or at\n"
     "angle 0 or pi (axis-angle), where the conventions of kinctl/orient.h pick the answer.\n"
     "Example: kinctl-calc orient --from rpy --to quat --deg 30 45 60",
     orient_opts, run_orient},
    {"transform", "homogeneous transforms of points (rotation, translation, scale, perspective)",
     "kinctl-calc transform OPERATION... [--point X,Y,Z]... [--deg]\n"
     "Operations act on the points in the order given (M = M_k ... M_2 M_1).\n"
     "Prints {\"matrix\": 4x4, \"homogeneous\": [[x,y,z,w] per point], \"cartesian\": [[x/w,y/w,z/w]\n"
     "per point, null where w = 0]}.\n"
     "Example: kinctl-calc transform --rotate z,90 --translate 2,0,0 --deg --point 0,0,2 --point 2,0,0",
     transform_opts, run_transform},
    {"ik", "inverse kinematics: joint values that put the tool at a target pose",
     "kinctl-calc ik (--model NAME | --model-file PATH) --target T [--q0 Q1,Q2,...] [--mask TASK] [--deg]\n"
     "Integrates the dual-quaternion feedback law from q0 (with damping, joint limits and,\n"
     "for redundant tasks, a null-space pull to mid-range) until the tool is within 1e-10 m and\n"
     "1e-10 rad of T, restarting from other starts when a run stalls. Prints {\"q\": [...],\n"
     "\"status\": \"converged\" | \"unreachable\" (q: null) | or, with q the best found, where it\n"
     "stopped: \"joint_limit\" | \"singular\" | \"not_converged\",\n"
     "\"steps\": n, \"restarts\": n, \"position_error\": m, \"orientation_error\": rad}; exit status 0\n"
     "whatever the status (it is the answer), 2 for bad input.\n"
     "Example: kinctl-calc ik --model puma560 --target 0.5,-0.15,0.6,0,0.7071068,0,0.7071068",
     ik_opts, run_ik},
    {"interp", "sampled motions: joint move, line, arc, path (CSV; kinctl-calc interp --help)",
     "kinctl-calc interp KIND [OPTIONS]   (KIND: joint, line, arc, path; see interp.c)", interp_opts, run_interp},
    {"zones", "distance of every link volume to every forbidden zone",
     "kinctl-calc zones (--model NAME | --model-file PATH) --q Q1,Q2,... [--deg] [--zone KIND:NUMBERS]...\n"
     "    [--zones-file PATH] [--margin M] [--geometry]\n"
     "--zones-file reads controller.zones of a kinctld configuration (format: kinctl/desc.h).\n"
     "Zones are in the base (world) frame, lengths in m: box:cx,cy,cz,hx,hy,hz (centre, half\n"
     "extents), sphere:cx,cy,cz,r, cylinder:x0,y0,z0,x1,y1,z1,r (axis ends, radius), capsule (the\n"
     "same numbers), frustum:cx,cy,cz,bx,by,tx,ty,h (upright truncated pyramid: centre, bottom and\n"
     "top half extents at cz -/+ h), halfspace:px,py,pz,nx,ny,nz (a point of the plane, the normal\n"
     "pointing out of the zone). Rotated boxes and frustums: --zones-file.\n"
     "Prints {\"volumes\": [{\"kind\", \"frame\" (1..m, as description files and fk's 0T_k number them)}...],\n"
     "\"distances\": [[d per zone] per volume] (m, 0 when\n"
     "touching or overlapping; see kinctl/zone.h for the accuracy), \"margin\": m, \"closest\":\n"
     "{\"volume\", \"zone\", \"distance\"} or null, \"clear\": true when every distance >= margin}, and\n"
     "with --geometry \"geometry\": {\"volumes\": [...], \"zones\": [...]}, each {\"kind\", \"pose\" (4x4,\n"
     "world), \"dim\" (sizes as kinctl/zone.h lists them), \"frame\" for volumes} for plotting.\n"
     "Example: kinctl-calc zones --model puma560 --q 0,0.8,-2.4,0,0.6,0 --zone halfspace:0,0,0,0,0,1\n"
     "    --zone box:0.6,0,0.3,0.1,0.3,0.3",
     zones_opts, run_zones},
    {"batch", "many requests: JSON lines on stdin, one answer line each",
     "kinctl-calc batch < requests.jsonl\n"
     "Each line is one request object with \"op\" (fk, jacobian, ik, orient, transform, zones) and\n"
     "the options of that subcommand as keys: --model-file is \"model_file\", positional VALUES are\n"
     "\"values\", flags are true/false, lists are arrays; transform takes \"ops\": [{\"translate\":\n"
     "[dx,dy,dz]}, {\"rotate\": {\"axis\": \"z\", \"angle\": a}}, {\"scale\": s}, {\"perspective\":\n"
     "{\"axis\": \"z\", \"f\": f}}] and \"points\": [[x,y,z], ...]. An \"id\" is echoed back.\n"
     "Each answer is one line, in order; a bad request answers {\"error\": \"...\"} and the next\n"
     "line is read. Blank lines are skipped. Exit status 0 once stdin is read to its end.\n"
     "Example: echo '{\"op\":\"fk\",\"model\":\"puma560\",\"q\":[0,0,0,0,0,0]}' | kinctl-calc batch",
     batch_opts, run_batch},
};

#define N_COMMANDS (sizeof commands / sizeof commands[0])

static const calc_cmd *find_command(const char *name)
{
    for (size_t i = 0; i < N_COMMANDS; i++)
        if (strcmp(commands[i].name, name) == 0)
            return &commands[i];
    return NULL;
}

static void print_help(const calc_cmd *cmd)
{
    printf("usage: %s\n\noptions:\n", cmd->usage);
    for (const calc_opt *o = cmd->opts; o->key != NULL; o++) {
        char left[64];
        if (o->flag == NULL)
            snprintf(left, sizeof left, "%s", o->metavar);
        else if (o->metavar != NULL)
            snprintf(left, sizeof left, "%s %s", o->flag, o->metavar);
        else
            snprintf(left, sizeof left, "%s", o->flag);
        printf("  %-26s %s\n", left, o->help);
    }
    printf("  %-26s %s\n", "--help", "this text");
    if (cmd->run == run_batch) {
        printf("\nkeys of each op's request (from the options of its subcommand):\n");
        for (size_t i = 0; i < N_COMMANDS; i++) {
            if (commands[i].run == run_batch)
                continue;
            printf("  %-10s", commands[i].name);
            const char *last = "";
            for (const calc_opt *o = commands[i].opts; o->key != NULL; o++)
                if (strcmp(o->key, last) != 0)
                    printf(" %s", last = o->key);
            printf("\n");
        }
    }
    printf("\nRadians and metres unless --deg. Bad input: a message on stderr, exit status 2.\n");
}

static void print_main_help(FILE *f)
{
    fprintf(f, "usage: kinctl-calc SUBCOMMAND [OPTIONS]   (kinctl-calc SUBCOMMAND --help for details)\n\n"
           "Kinematics calculator of kinctl; answers are JSON on stdout.\n\nsubcommands:\n");
    for (size_t i = 0; i < N_COMMANDS; i++)
        fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n--version prints the version.\nExample: kinctl-calc fk --model puma560 --q 0,0,0,0,0,0\n");
}

/* Runs one request and writes its answer object (result, or error) to out.
 * Returns 0 on success. Warnings go into the answer in batch mode, to
 * stderr on the command line. */
static int answer(const calc_cmd *cmd, const json_t *req, jw *out, long batch_line, char *err, size_t errlen)
{
    calc_ctx ctx;
    jw result;
    jw_init(&result);
    memset(&ctx, 0, sizeof ctx);
    ctx.out = &result;
    ctx.warnings = json_array();
    jw_obj_begin(&result);
    int rc = calc_check_keys(&ctx, req, cmd);
    if (rc == 0)
        rc = cmd->run(req, &ctx);
    if (rc == 0 && result.failed)
        rc = calc_fail(&ctx, "out of memory");
    const json_t *id = json_object_get(req, "id");
    char *id_text = id != NULL ? json_dumps(id, JSON_ENCODE_ANY | JSON_COMPACT) : NULL;
    if (rc != 0) {
        jw_free(&result);
        jw_obj_begin(out);
        char msg[1200];
        if (batch_line > 0)
            snprintf(msg, sizeof msg, "line %ld: %s", batch_line, ctx.err);
        else
            snprintf(msg, sizeof msg, "%s", ctx.err);
        jw_key(out, "error");
        jw_str(out, msg);
        snprintf(err, errlen, "%s", ctx.err);
    } else {
        /* The run wrote "{" and its members: copy them, then close. */
        int members = result.count[1];
        jw_raw(out, result.buf);
        out->depth++;
        out->count[out->depth] = members;
        jw_free(&result);
    }
    if (id_text != NULL) {
        jw_key(out, "id");
        jw_raw(out, id_text);
        free(id_text);
    }
    size_t nw = json_array_size(ctx.warnings);
    if (rc == 0 && nw > 0) {
        if (batch_line > 0) {
            jw_key(out, "warnings");
            jw_arr_begin(out);
        }
        for (size_t i = 0; i < nw; i++) {
            const char *w = json_string_value(json_array_get(ctx.warnings, i));
            if (batch_line > 0)
                jw_str(out, w);
            else
                fprintf(stderr, "kinctl-calc: warning: %s\n", w);
        }
        if (batch_line > 0)
            jw_arr_end(out);
    }
    jw_obj_end(out);
    json_decref(ctx.warnings);
    return rc;
}

/* Reads one line of any length; NULL at end of input. The caller frees. */
static char *read_line(FILE *f, int *error)
{
    size_t len = 0, cap = 256;
    char *buf = malloc(cap);
    int c;
    *error = 0;
    if (buf == NULL) {
        *error = 1;
        return NULL;
    }
    while ((c = fgetc(f)) != EOF && c != '\n') {
        if (len + 2 > cap) {
            char *nb = realloc(buf, cap *= 2);
            if (nb == NULL) {
                free(buf);
                *error = 1;
                return NULL;
            }
            buf = nb;
        }
        buf[len++] = (char)c;
    }
    if (c == EOF && len == 0) {
        *error = ferror(f) != 0;
        free(buf);
        return NULL;
    }
    buf[len] = '\0';
    return buf;
}

/* An error answer for a line that names no runnable op (with its "id" if
 * the request has one). */
static void print_error_line(const char *msg, const json_t *req)
{
    jw out;
    const json_t *id = json_is_object(req) ? json_object_get(req, "id") : NULL;
    char *id_text = id != NULL ? json_dumps(id, JSON_ENCODE_ANY | JSON_COMPACT) : NULL;
    jw_init(&out);
    jw_obj_begin(&out);
    jw_key(&out, "error");
    jw_str(&out, msg);
    if (id_text != NULL) {
        jw_key(&out, "id");
        jw_raw(&out, id_text);
        free(id_text);
    }
    jw_obj_end(&out);
    printf("%s\n", out.failed ? "{\"error\":\"out of memory\"}" : out.buf);
    jw_free(&out);
}

static int run_batch(const json_t *req, calc_ctx *ctx)
{
    (void)req;
    long line_no = 0;
    int error = 0;
    char *line;
    while ((line = read_line(stdin, &error)) != NULL) {
        char msg[1200];
        json_error_t jerr;
        line_no++;
        if (strspn(line, " \t\r") == strlen(line)) {
            free(line);
            continue;
        }
        json_t *r = json_loads(line, JSON_REJECT_DUPLICATES, &jerr);
        free(line);
        if (r == NULL) {
            snprintf(msg, sizeof msg, "line %ld: invalid JSON at column %d: %s", line_no, jerr.column, jerr.text);
            print_error_line(msg, NULL);
        } else if (!json_is_object(r)) {
            snprintf(msg, sizeof msg, "line %ld: a request must be a JSON object", line_no);
            print_error_line(msg, NULL);
        } else {
            const json_t *op = json_object_get(r, "op");
            const calc_cmd *cmd = json_is_string(op) ? find_command(json_string_value(op)) : NULL;
            if (cmd == NULL || cmd->run == run_batch) {
                snprintf(msg, sizeof msg, "line %ld: %s", line_no,
                         op == NULL            ? "missing \"op\" (fk, jacobian, orient, transform)"
                         : !json_is_string(op) ? "\"op\" must be a string"
                                               : "unknown op (fk, jacobian, orient, transform)");
                print_error_line(msg, r);
            } else {
                jw out;
                char err[1024];
                jw_init(&out);
                answer(cmd, r, &out, line_no, err, sizeof err);
                if (out.failed)
                    print_error_line("out of memory", r);
                else
                    printf("%s\n", out.buf);
                jw_free(&out);
            }
        }
        json_decref(r);
        fflush(stdout);
    }
    if (error)
        return calc_fail(ctx, "reading stdin failed");
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
        print_main_help(argc < 2 ? stderr : stdout);
        return argc < 2 ? EXIT_BAD_INPUT : 0;
    }
    if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "-V") == 0) {
        printf("kinctl-calc %s (core %s)\n", KC_VERSION, KC_REAL_NAME);
        return 0;
    }
    if (strcmp(argv[1], "interp") == 0) /* dispatches on its second word: calc.h */
        return calc_interp_main(argc - 2, argv + 2);
    const calc_cmd *cmd = find_command(argv[1]);
    if (cmd == NULL) {
        fprintf(stderr, "kinctl-calc: unknown subcommand \"%s\" (kinctl-calc --help lists them)\n", argv[1]);
        return EXIT_BAD_INPUT;
    }
    for (int i = 2; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            print_help(cmd);
            return 0;
        }
    }
    char err[1024];
    json_t *req = calc_parse_args(cmd, argc - 2, argv + 2, err, sizeof err);
    if (req == NULL) {
        fprintf(stderr, "kinctl-calc %s: %s (kinctl-calc %s --help)\n", cmd->name, err, cmd->name);
        return EXIT_BAD_INPUT;
    }
    if (cmd->run == run_batch) {
        calc_ctx ctx;
        memset(&ctx, 0, sizeof ctx);
        int rc = run_batch(req, &ctx);
        json_decref(req);
        if (rc != 0)
            fprintf(stderr, "kinctl-calc batch: %s\n", ctx.err);
        return rc != 0 ? EXIT_FAILURE_IO : 0;
    }
    jw out;
    jw_init(&out);
    int rc = answer(cmd, req, &out, 0, err, sizeof err);
    json_decref(req);
    if (rc != 0)
        fprintf(stderr, "kinctl-calc %s: %s\n", cmd->name, err);
    else if (out.failed)
        fprintf(stderr, "kinctl-calc %s: out of memory\n", cmd->name);
    else
        printf("%s\n", out.buf);
    jw_free(&out);
    return rc != 0 ? EXIT_BAD_INPUT : out.failed ? EXIT_FAILURE_IO : 0;
}
