/* SPDX-License-Identifier: BSD-3-Clause */
/* interp_path.c - `kinctl-calc interp path`: multi-point paths of
 * kinctl/path.h (seed 001 lab 7) in joint or Cartesian space, one row per
 * tick. The options are interp_path_opts (interp.c); how the kind plugs in
 * is described in calc.h. */
#include <stdio.h>
#include <string.h>

#include "calc.h"

/* More rows than this is a mistake (a tiny dt), not a request (as interp.c). */
#define PATH_MAX_ROWS 1000000

/* Plans are tens of kB: static (the calculator answers one request at a
 * time). */
static kc_path plan_joint;
static kc_path_cart plan_cart;

typedef struct path_req {
    int cartesian;
    kc_path_method method;
    kc_path_blend blend;
    kc_path_spline_end ends;
    int n, dim; /* knots; numbers per point */
    kc_real pts[KC_PATH_MAX_KNOTS][KC_MAX_JOINTS > 7 ? KC_MAX_JOINTS : 7];
    int have_t, have_v, have_a;
    kc_real t[KC_PATH_MAX_KNOTS];
    kc_real v[KC_PATH_MAX_KNOTS][KC_MAX_JOINTS];
    kc_real a[KC_PATH_MAX_KNOTS][KC_MAX_JOINTS];
    kc_real tacc;
    int n_vmax, n_amax;
    kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS];
    kc_real omega, epsilon;
    kc_real dt;
} path_req;

static path_req R;

/* A list of points ("P;P;..." on the command line, [[...], ...] in batch),
 * each of `width` numbers (0: the width of the first point, at most max). */
static int points_of(calc_ctx *ctx, const json_t *req, const char *key, int count, int *width, int max,
                     kc_real (*out)[KC_MAX_JOINTS > 7 ? KC_MAX_JOINTS : 7], int *n_out)
{
    const json_t *list = json_object_get(req, key);
    if (!json_is_array(list))
        return calc_fail(ctx, "%s must be a list of points", key);
    int n = (int)json_array_size(list);
    if (n > KC_PATH_MAX_KNOTS)
        return calc_fail(ctx, "%s: %d points, more than the %d a path takes", key, n, KC_PATH_MAX_KNOTS);
    if (count >= 0 && n != count)
        return calc_fail(ctx, "%s has %d points: give one per knot (%d)", key, n, count);
    for (int i = 0; i < n; i++) {
        char what[64];
        int m = 0;
        snprintf(what, sizeof what, "%s point %d", key, i + 1);
        if (req_reals(ctx, json_array_get(list, (size_t)i), what, out[i], max, &m) != 0)
            return -1;
        if (*width == 0)
            *width = m;
        if (m != *width)
            return calc_fail(ctx, "%s has %d numbers, point 1 has %d: every point needs the same count", what, m,
                             *width);
    }
    if (n_out != NULL)
        *n_out = n;
    return 0;
}

/* Knot derivatives under key: one row of vw numbers for each of the R.n
 * points, into d. */
static int derivs_of(calc_ctx *ctx, const json_t *req, const char *key, int vw,
                     kc_real d[KC_PATH_MAX_KNOTS][KC_MAX_JOINTS])
{
    static kc_real tmp[KC_PATH_MAX_KNOTS][KC_MAX_JOINTS > 7 ? KC_MAX_JOINTS : 7];
    int w = vw;
    if (points_of(ctx, req, key, R.n, &w, KC_MAX_JOINTS, tmp, NULL) != 0)
        return -1;
    for (int i = 0; i < R.n; i++)
        for (int j = 0; j < vw; j++)
            d[i][j] = tmp[i][j];
    return 0;
}

/* One limit for every coordinate, or one per coordinate (joint space). */
static int limits_of(calc_ctx *ctx, const json_t *req, const char *key, int per, kc_real *out, int *n)
{
    *n = 0;
    if (json_object_get(req, key) == NULL)
        return 0;
    if (req_reals(ctx, json_object_get(req, key), key, out, KC_MAX_JOINTS, n) != 0)
        return -1;
    if (*n != 1 && *n != per)
        return calc_fail(ctx, "%s has %d values: give one for every coordinate or one per coordinate (%d)", key, *n,
                         per);
    for (int j = 0; j < *n; j++) {
        if (!(out[j] > KC_R(0.0)))
            return calc_fail(ctx, "%s must be > 0, not %g", key, (double)out[j]);
        if (rate_in_range(ctx, key, out[j]) != 0)
            return -1;
    }
    for (int j = *n; j < per; j++)
        out[j] = out[0];
    return 0;
}

static int name_of(calc_ctx *ctx, const json_t *req, const char *key, int required, const char *const *names,
                   int count, const char *fallback, int *out)
{
    const char *s = fallback;
    if (req_string(ctx, req, key, required, &s) != 0)
        return -1;
    for (int i = 0; i < count; i++)
        if (strcmp(s, names[i]) == 0) {
            *out = i;
            return 0;
        }
    char list[128] = "";
    for (int i = 0; i < count; i++)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i > 0 ? ", " : "", names[i]);
    return calc_fail(ctx, "unknown %s \"%s\" (%s)", key, s, list);
}

static int read_request(calc_ctx *ctx, const json_t *req)
{
    static const char *const spaces[2] = {"joint", "cartesian"};
    static const char *const methods[4] = {"blend", "lagrange", "spline", "quintic"};
    static const char *const blends[2] = {"quartic", "parabolic"};
    static const char *const ends[2] = {"clamped", "natural"};
    int space = 0, method = 0, blend = 0, end = 0;
    memset(&R, 0, sizeof R);
    if (name_of(ctx, req, "space", 1, spaces, 2, NULL, &space) != 0 ||
        name_of(ctx, req, "method", 1, methods, 4, NULL, &method) != 0 ||
        name_of(ctx, req, "blend", 0, blends, 2, "quartic", &blend) != 0 ||
        name_of(ctx, req, "ends", 0, ends, 2, "clamped", &end) != 0)
        return -1;
    R.cartesian = space == 1;
    R.method = (kc_path_method)method;
    R.blend = (kc_path_blend)blend;
    R.ends = (kc_path_spline_end)end;
    if (json_object_get(req, "blend") != NULL && R.method != KC_PATH_BLEND)
        return calc_fail(ctx, "--blend chooses the blend of the blend method, not of %s", methods[method]);
    if (json_object_get(req, "ends") != NULL && (R.method != KC_PATH_SPLINE || json_object_get(req, "velocities")))
        return calc_fail(ctx, "--ends chooses the ends of a spline whose knot velocities are computed");
    /* Knots. */
    int width = 0;
    if (json_object_get(req, "points") == NULL)
        return calc_fail(ctx, "missing --points (\"points\")");
    if (points_of(ctx, req, "points", -1, &width, R.cartesian ? 7 : KC_MAX_JOINTS, R.pts, &R.n) != 0)
        return -1;
    if (R.n < 2)
        return calc_fail(ctx, "a path needs at least 2 points, got %d", R.n);
    if (R.method == KC_PATH_LAGRANGE && R.n > KC_PATH_MAX_LAGRANGE_KNOTS)
        return calc_fail(ctx, "lagrange takes at most %d points (degree %d; it oscillates more with every point), got %d",
                         KC_PATH_MAX_LAGRANGE_KNOTS, KC_PATH_MAX_LAGRANGE_KNOTS - 1, R.n);
    if (R.cartesian && width != 7)
        return calc_fail(ctx, "a cartesian point is x,y,z,qw,qx,qy,qz (7 numbers), not %d", width);
    R.dim = width;
    /* Times. */
    if (json_object_get(req, "times") != NULL) {
        int nt = 0;
        if (req_reals(ctx, json_object_get(req, "times"), "times", R.t, KC_PATH_MAX_KNOTS, &nt) != 0)
            return -1;
        if (nt != R.n)
            return calc_fail(ctx, "times has %d values: give one per point (%d)", nt, R.n);
        for (int i = 1; i < R.n; i++)
            if (!(R.t[i] > R.t[i - 1]))
                return calc_fail(ctx, "times must increase strictly: t%d = %g after t%d = %g", i, (double)R.t[i], i - 1,
                                 (double)R.t[i - 1]);
        R.have_t = 1;
    }
    /* Knot derivatives. */
    int vw = R.cartesian ? 3 : R.dim;
    if (json_object_get(req, "velocities") != NULL) {
        if (R.method != KC_PATH_SPLINE && R.method != KC_PATH_QUINTIC)
            return calc_fail(ctx, "--velocities is for spline and quintic (%s computes its own)", methods[method]);
        if (derivs_of(ctx, req, "velocities", vw, R.v) != 0)
            return -1;
        R.have_v = 1;
    }
    if (json_object_get(req, "accelerations") != NULL) {
        if (R.method != KC_PATH_QUINTIC)
            return calc_fail(ctx, "--accelerations is for quintic only");
        if (derivs_of(ctx, req, "accelerations", vw, R.a) != 0)
            return -1;
        R.have_a = 1;
    }
    /* Blend time and limits. */
    if (json_object_get(req, "tacc") != NULL) {
        if (R.method != KC_PATH_BLEND)
            return calc_fail(ctx, "--tacc is the blend time of the blend method");
        if (req_positive(ctx, req, "tacc", 0, "s", &R.tacc) != 0)
            return -1;
    }
    if (limits_of(ctx, req, "v", R.cartesian ? 1 : R.dim, R.vmax, &R.n_vmax) != 0 ||
        limits_of(ctx, req, "a", R.cartesian ? 1 : R.dim, R.amax, &R.n_amax) != 0)
        return -1;
    if (json_object_get(req, "omega") != NULL || json_object_get(req, "epsilon") != NULL) {
        if (!R.cartesian)
            return calc_fail(ctx, "--omega and --epsilon are angular limits of a cartesian path");
        if (req_rate(ctx, req, "omega", 0, "rad/s", &R.omega) != 0 ||
            req_rate(ctx, req, "epsilon", 0, "rad/s^2", &R.epsilon) != 0)
            return -1;
        if (!(R.omega > KC_R(0.0)) || !(R.epsilon > KC_R(0.0)))
            return calc_fail(ctx, "give both --omega and --epsilon (or neither)");
    }
    if (R.have_t) {
        if (R.method == KC_PATH_BLEND) {
            if (!(R.tacc > KC_R(0.0)))
                return calc_fail(ctx, "the blend method with --times needs --tacc (the blend half-length, s)");
            for (int i = 1; i < R.n; i++)
                if (KC_R(2.0) * R.tacc > (R.t[i] - R.t[i - 1]) * (KC_R(1.0) + KC_R(8.0) * KC_REAL_EPS))
                    return calc_fail(ctx, "tacc %g s is longer than half the segment t%d..t%d (%g s): blends would overlap",
                                     (double)R.tacc, i - 1, i, (double)(R.t[i] - R.t[i - 1]));
        }
    } else if (R.n_vmax == 0 || R.n_amax == 0) {
        return calc_fail(ctx, "give --times, or --v and --a for knot times from the limits");
    }
    if (req_real(ctx, req, "dt", &R.dt) != 0)
        return -1;
    if (!(R.dt > KC_R(0.0)))
        return calc_fail(ctx, "dt must be > 0 s, not %g", (double)R.dt);
    return 0;
}

static int plan_failed(calc_ctx *ctx, kc_status st)
{
    switch (st) {
    case KC_E_CAPACITY:
        return calc_fail(ctx, "the path would last more than %d ticks: use a larger --dt or fewer, closer knots",
                         KC_PATH_MAX_TICKS);
    case KC_E_LIMIT:
        return calc_fail(ctx, "tacc is too short for --a: a blend would need more acceleration (omit --tacc to get "
                              "1.5 v/a)");
    default:
        return calc_fail(ctx, "path: %s (a segment without motion needs --times; cartesian quaternions must have "
                              "norm 1 within 1e-3)", kc_status_str(st));
    }
}

static int too_many_rows(calc_ctx *ctx, int64_t ticks, kc_real duration)
{
    if (ticks + 1 > PATH_MAX_ROWS)
        return calc_fail(ctx, "the path lasts %.6g s = %lld ticks: more than %d rows; use a larger --dt",
                         (double)duration, (long long)ticks, PATH_MAX_ROWS);
    return 0;
}

static int joint_path(calc_ctx *ctx)
{
    static kc_real q[KC_PATH_MAX_KNOTS * KC_MAX_JOINTS], v[KC_PATH_MAX_KNOTS * KC_MAX_JOINTS],
        a[KC_PATH_MAX_KNOTS * KC_MAX_JOINTS];
    int n = R.n, dim = R.dim;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < dim; j++) {
            q[i * dim + j] = R.pts[i][j];
            v[i * dim + j] = R.v[i][j];
            a[i * dim + j] = R.a[i][j];
        }
    kc_path_cfg cfg = kc_path_cfg_default();
    cfg.method = R.method;
    cfg.blend = R.blend;
    cfg.spline_end = R.ends;
    cfg.n_knots = n;
    cfg.dim = dim;
    cfg.q = q;
    cfg.t = R.have_t ? R.t : NULL;
    cfg.qd = R.have_v ? v : NULL;
    cfg.qdd = R.have_a ? a : NULL;
    cfg.t_acc = R.tacc;
    for (int j = 0; j < dim; j++) {
        cfg.vmax[j] = R.n_vmax > 0 ? R.vmax[j] : KC_R(1.0);
        cfg.amax[j] = R.n_amax > 0 ? R.amax[j] : KC_R(1.0);
    }
    cfg.dt = R.dt;
    kc_status st = kc_path_plan(&plan_joint, &cfg);
    if (st != KC_OK)
        return plan_failed(ctx, st);
    if (too_many_rows(ctx, plan_joint.ticks, plan_joint.duration) != 0)
        return -1;
    static const char *const stems[3] = {"q", "qd", "qdd"};
    char name_buf[1 + 3 * KC_MAX_JOINTS][8];
    const char *names[1 + 3 * KC_MAX_JOINTS];
    kc_real row[1 + 3 * KC_MAX_JOINTS];
    names[0] = "t";
    for (int d = 0; d < 3; d++)
        for (int j = 0; j < dim; j++) {
            snprintf(name_buf[1 + d * dim + j], sizeof name_buf[0], "%s%d", stems[d], j + 1);
            names[1 + d * dim + j] = name_buf[1 + d * dim + j];
        }
    int ncol = 1 + 3 * dim;
    calc_rows_begin(ctx, ncol, names);
    for (int64_t k = 0; k <= plan_joint.ticks; k++) {
        row[0] = (kc_real)k * R.dt;
        kc_path_eval(&plan_joint, k, row + 1, row + 1 + dim, row + 1 + dim + dim);
        calc_rows_add(ctx, ncol, row);
    }
    calc_rows_end(ctx);
    return 0;
}

static int cartesian_path(calc_ctx *ctx)
{
    kc_vec3 p[KC_PATH_MAX_KNOTS], v[KC_PATH_MAX_KNOTS], a[KC_PATH_MAX_KNOTS];
    kc_quat r[KC_PATH_MAX_KNOTS];
    int n = R.n;
    for (int i = 0; i < n; i++) {
        p[i] = kc_vec3_make(R.pts[i][0], R.pts[i][1], R.pts[i][2]);
        v[i] = kc_vec3_make(R.v[i][0], R.v[i][1], R.v[i][2]);
        a[i] = kc_vec3_make(R.a[i][0], R.a[i][1], R.a[i][2]);
        kc_quat raw = {R.pts[i][3], R.pts[i][4], R.pts[i][5], R.pts[i][6]};
        kc_real norm = kc_quat_norm(&raw);
        if (kc_quat_normalize(&raw, &r[i]) != KC_OK)
            return calc_fail(ctx, "point %d: the quaternion qw,qx,qy,qz is zero", i + 1);
        if (kc_fabs(norm - KC_R(1.0)) > KC_PATH_TOL_QUAT_NORM)
            calc_warn(ctx, "point %d: quaternion of norm %g normalised", i + 1, (double)norm);
    }
    kc_path_cart_cfg cfg = kc_path_cart_cfg_default();
    cfg.method = R.method;
    cfg.blend = R.blend;
    cfg.spline_end = R.ends;
    cfg.n_knots = n;
    cfg.p = p;
    cfg.r = r;
    cfg.t = R.have_t ? R.t : NULL;
    cfg.v = R.have_v ? v : NULL;
    cfg.a = R.have_a ? a : NULL;
    cfg.t_acc = R.tacc;
    if (R.n_vmax > 0)
        cfg.v_max = R.vmax[0];
    if (R.n_amax > 0)
        cfg.a_max = R.amax[0];
    cfg.w_max = R.omega;
    cfg.alpha_max = R.epsilon;
    cfg.dt = R.dt;
    kc_status st = kc_path_cart_plan(&plan_cart, &cfg);
    if (st == KC_E_ARG && !R.have_t && !(R.omega > KC_R(0.0)))
        for (int i = 1; i < n; i++)
            if (p[i].v[0] == p[i - 1].v[0] && p[i].v[1] == p[i - 1].v[1] && p[i].v[2] == p[i - 1].v[2])
                return calc_fail(ctx, "points %d and %d are at the same position: with times from the limits a turn "
                                      "in place needs --omega and --epsilon (or give --times)",
                                 i, i + 1);
    if (st != KC_OK)
        return plan_failed(ctx, st);
    if (too_many_rows(ctx, plan_cart.pos.ticks, plan_cart.pos.duration) != 0)
        return -1;
    static const char *const names[11] = {"t", "x", "y", "z", "qw", "qx", "qy", "qz", "s", "sd", "sdd"};
    calc_rows_begin(ctx, 11, names);
    for (int64_t k = 0; k <= plan_cart.pos.ticks; k++) {
        kc_path_pose e;
        kc_path_cart_eval(&plan_cart, k, &e);
        kc_real row[11] = {(kc_real)k * R.dt, e.p.v[0], e.p.v[1], e.p.v[2], e.r.w, e.r.x, e.r.y, e.r.z,
                           e.s,               e.sd,     e.sdd};
        calc_rows_add(ctx, 11, row);
    }
    calc_rows_end(ctx);
    return 0;
}

int run_interp_path(const json_t *req, calc_ctx *ctx)
{
    if (read_request(ctx, req) != 0)
        return -1;
    return R.cartesian ? cartesian_path(ctx) : joint_path(ctx);
}
