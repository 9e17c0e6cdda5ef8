/* SPDX-License-Identifier: BSD-3-Clause */
/* testutil.c - see testutil.h. */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

unsigned long kt_checks = 0;

/* ---- reference vectors ---- */

json_t *kt_load(const char *name)
{
    const char *dir = getenv("KINCTL_VECTORS");
    char path[4096];
    json_error_t err;
    if (dir == NULL || dir[0] == '\0') {
        print_error("KINCTL_VECTORS is not set: it must name the reference vectors directory "
                    "(tests/vectors); ctest sets it, a manual run needs it exported\n");
        _fail(__FILE__, __LINE__);
    }
    if (snprintf(path, sizeof path, "%s/%s", dir, name) >= (int)sizeof path) {
        print_error("vectors path too long: %s/%s\n", dir, name);
        _fail(__FILE__, __LINE__);
    }
    json_t *root = json_load_file(path, 0, &err);
    if (root == NULL) {
        print_error("cannot load reference vectors %s: %s (line %d)\n", path, err.text, err.line);
        _fail(__FILE__, __LINE__);
    }
    return root;
}

json_t *kt_get(const json_t *obj, const char *key)
{
    json_t *v = json_is_object(obj) ? json_object_get(obj, key) : NULL;
    if (v == NULL) {
        print_error("reference vectors: missing key \"%s\"\n", key);
        _fail(__FILE__, __LINE__);
    }
    return v;
}

json_t *kt_at(const json_t *arr, size_t i)
{
    json_t *v = json_is_array(arr) ? json_array_get(arr, i) : NULL;
    if (v == NULL) {
        print_error("reference vectors: no array element %zu\n", i);
        _fail(__FILE__, __LINE__);
    }
    return v;
}

double kt_num(const json_t *v)
{
    if (!json_is_number(v)) {
        print_error("reference vectors: expected a number\n");
        _fail(__FILE__, __LINE__);
    }
    return json_number_value(v);
}

double kt_num_of(const json_t *obj, const char *key) { return kt_num(kt_get(obj, key)); }

static void check_size(const json_t *arr, size_t n)
{
    if (!json_is_array(arr) || json_array_size(arr) != n) {
        print_error("reference vectors: expected an array of %zu\n", n);
        _fail(__FILE__, __LINE__);
    }
}

void kt_read_reals(const json_t *arr, kc_real *out, size_t n)
{
    check_size(arr, n);
    for (size_t i = 0; i < n; i++)
        out[i] = (kc_real)kt_num(json_array_get(arr, i));
}

void kt_read_mat3(const json_t *m, kc_mat3 *out)
{
    check_size(m, 3);
    for (size_t i = 0; i < 3; i++)
        kt_read_reals(json_array_get(m, i), out->m[i], 3);
}

void kt_read_mat4(const json_t *m, kc_mat4 *out)
{
    check_size(m, 4);
    for (size_t i = 0; i < 4; i++)
        /* cppcheck-suppress uninitvar ; out->m[i] is written, not read */
        kt_read_reals(json_array_get(m, i), out->m[i], 4);
}

static void check_last_row(const char *file, int line, const json_t *m, const char *what)
{
    for (size_t j = 0; j < 4; j++) {
        double v = kt_num(kt_at(kt_at(m, 3), j));
        if (v != (j == 3 ? 1.0 : 0.0)) {
            print_error("%s: reference row 4 is not 0 0 0 1\n", what);
            _fail(file, line);
        }
    }
}

void kt_read_pose(const json_t *m, kc_pose *out)
{
    kc_mat4 a;
    kt_read_mat4(m, &a);
    check_last_row(__FILE__, __LINE__, m, "kt_read_pose");
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            out->R.m[i][j] = a.m[i][j];
        out->t.v[i] = a.m[i][3];
    }
}

/* ---- comparisons ---- */

static int near(double a, double e, double tol) { return a - e <= tol && e - a <= tol; }

static void report(const char *file, int line, const char *what, const char *index, double a, double e, double tol)
{
    print_error("%s%s: got %.17g, expected %.17g, |diff| %.3g > tol %.3g (%s)\n", what, index, a, e,
                a > e ? a - e : e - a, tol, KC_REAL_NAME);
    _fail(file, line);
}

void kt_near_(const char *file, int line, double a, double e, double tol, const char *what)
{
    kt_checks++;
    if (!near(a, e, tol))
        report(file, line, what, "", a, e, tol);
}

void kt_near_angle_(const char *file, int line, double a, double e, double tol, const char *what)
{
    double d = fmod(a - e, 2.0 * KT_PI);
    if (d > KT_PI)
        d -= 2.0 * KT_PI;
    else if (d < -KT_PI)
        d += 2.0 * KT_PI;
    kt_checks++;
    if (!near(d, 0.0, tol)) {
        print_error("%s: angle %.17g, expected %.17g (mod 2 pi), |diff| %.3g > tol %.3g (%s)\n", what, a, e,
                    d < 0.0 ? -d : d, tol, KC_REAL_NAME);
        _fail(file, line);
    }
}

void kt_near_reals_json_(const char *file, int line, const kc_real *a, size_t n, const json_t *arr, double tol,
                         const char *what)
{
    char idx[32];
    check_size(arr, n);
    for (size_t i = 0; i < n; i++) {
        double e = kt_num(json_array_get(arr, i));
        kt_checks++;
        if (!near((double)a[i], e, tol)) {
            snprintf(idx, sizeof idx, "[%zu]", i);
            report(file, line, what, idx, (double)a[i], e, tol);
        }
    }
}

/* a (rows x cols, leading dimension ld) against a nested list. */
static void near_rows_json(const char *file, int line, const kc_real *a, size_t rows, size_t cols, size_t ld,
                           const json_t *m, double tol, const char *what)
{
    char idx[48];
    /* At least rows rows: a pose is compared with the first 3 of 4. */
    if (!json_is_array(m) || json_array_size(m) < rows) {
        print_error("%s: reference matrix has fewer than %zu rows\n", what, rows);
        _fail(file, line);
    }
    for (size_t i = 0; i < rows; i++) {
        const json_t *row = json_array_get(m, i);
        check_size(row, cols);
        for (size_t j = 0; j < cols; j++) {
            double e = kt_num(json_array_get(row, j));
            double v = (double)a[i * ld + j];
            kt_checks++;
            if (!near(v, e, tol)) {
                snprintf(idx, sizeof idx, "[%zu][%zu]", i, j);
                report(file, line, what, idx, v, e, tol);
            }
        }
    }
}

void kt_near_mat3_json_(const char *file, int line, const kc_mat3 *a, const json_t *m, double tol, const char *what)
{
    check_size(m, 3);
    near_rows_json(file, line, &a->m[0][0], 3, 3, 3, m, tol, what);
}

void kt_near_mat4_json_(const char *file, int line, const kc_mat4 *a, const json_t *m, double tol, const char *what)
{
    check_size(m, 4);
    near_rows_json(file, line, &a->m[0][0], 4, 4, 4, m, tol, what);
}

void kt_near_pose_json_(const char *file, int line, const kc_pose *a, const json_t *m, double tol, const char *what)
{
    kc_mat4 h;
    check_size(m, 4);
    check_last_row(file, line, m, what);
    kc_pose_to_mat4(a, &h);
    near_rows_json(file, line, &h.m[0][0], 3, 4, 4, m, tol, what);
}

void kt_near_mat3_(const char *file, int line, const kc_mat3 *a, const kc_mat3 *b, double tol, const char *what)
{
    char idx[32];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            kt_checks++;
            if (!near((double)a->m[i][j], (double)b->m[i][j], tol)) {
                snprintf(idx, sizeof idx, ".R[%d][%d]", i, j);
                report(file, line, what, idx, (double)a->m[i][j], (double)b->m[i][j], tol);
            }
        }
}

void kt_near_vec3_(const char *file, int line, const kc_vec3 *a, const kc_vec3 *b, double tol, const char *what)
{
    char idx[32];
    for (int i = 0; i < 3; i++) {
        kt_checks++;
        if (!near((double)a->v[i], (double)b->v[i], tol)) {
            snprintf(idx, sizeof idx, "[%d]", i);
            report(file, line, what, idx, (double)a->v[i], (double)b->v[i], tol);
        }
    }
}

void kt_near_pose_(const char *file, int line, const kc_pose *a, const kc_pose *b, double tol, const char *what)
{
    char idx[32];
    kt_near_mat3_(file, line, &a->R, &b->R, tol, what);
    for (int i = 0; i < 3; i++) {
        kt_checks++;
        if (!near((double)a->t.v[i], (double)b->t.v[i], tol)) {
            snprintf(idx, sizeof idx, ".t[%d]", i);
            report(file, line, what, idx, (double)a->t.v[i], (double)b->t.v[i], tol);
        }
    }
}

static void near_quat(const char *file, int line, const kc_quat *a, const double e[4], double tol, const char *what)
{
    static const char *const names[4] = {".w", ".x", ".y", ".z"};
    double v[4] = {(double)a->w, (double)a->x, (double)a->y, (double)a->z};
    /* -q is the same rotation; w >= 0 picks one unless w is zero. */
    double sign = 1.0;
    if (near(e[0], 0.0, tol)) {
        double dot = v[0] * e[0] + v[1] * e[1] + v[2] * e[2] + v[3] * e[3];
        sign = dot < 0.0 ? -1.0 : 1.0;
    }
    for (int i = 0; i < 4; i++) {
        kt_checks++;
        if (!near(sign * v[i], e[i], tol))
            report(file, line, what, names[i], sign * v[i], e[i], tol);
    }
}

void kt_near_quat_json_(const char *file, int line, const kc_quat *a, const json_t *wxyz, double tol,
                        const char *what)
{
    double e[4];
    check_size(wxyz, 4);
    for (size_t i = 0; i < 4; i++)
        e[i] = kt_num(json_array_get(wxyz, i));
    near_quat(file, line, a, e, tol, what);
}

void kt_near_quat_(const char *file, int line, const kc_quat *a, const kc_quat *b, double tol, const char *what)
{
    double e[4] = {(double)b->w, (double)b->x, (double)b->y, (double)b->z};
    near_quat(file, line, a, e, tol, what);
}

void kt_near_jac_json_(const char *file, int line, const kc_jacobian *a, int n, const json_t *m, double tol,
                       const char *what)
{
    check_size(m, 6);
    near_rows_json(file, line, &a->m[0][0], 6, (size_t)n, KC_MAX_JOINTS, m, tol, what);
}

void kt_report(const char *suite)
{
    printf("%s (%s): %lu scalar comparisons\n", suite, KC_REAL_NAME, kt_checks);
}

int kt_is_sentinel(const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        if (b[i] != KT_SENTINEL)
            return 0;
    return 1;
}

/* ---- PRNG ---- */

int kt_cases(int n)
{
    const char *text = getenv("KINCTL_TEST_SHARE");
    char *end;
    double share;
    if (text == NULL || text[0] == '\0')
        return n;
    share = strtod(text, &end);
    if (*end != '\0' || !(share > 0.0 && share <= 1.0)) {
        print_error("KINCTL_TEST_SHARE=%s: not a share of the random cases (0 < share <= 1)\n", text);
        _fail(__FILE__, __LINE__);
    }
    int cases = (int)(share * n);
    return cases > 0 ? cases : 1;
}

kt_rng kt_rng_make(uint64_t seed)
{
    kt_rng r = {seed};
    return r;
}

uint64_t kt_rng_next(kt_rng *r)
{
    /* splitmix64 (Steele, Lea, Flood 2014). */
    uint64_t z = (r->s += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

double kt_uniform(kt_rng *r, double lo, double hi)
{
    double u = (double)(kt_rng_next(r) >> 11) * (1.0 / 9007199254740992.0); /* [0, 1) with 53 bits */
    return lo + (hi - lo) * u;
}

kc_quat kt_rand_quat(kt_rng *r)
{
    /* Shoemake, "Uniform random rotations", Graphics Gems III. */
    double u1 = kt_uniform(r, 0.0, 1.0), u2 = kt_uniform(r, 0.0, 2.0 * KT_PI), u3 = kt_uniform(r, 0.0, 2.0 * KT_PI);
    double a = sqrt(1.0 - u1), b = sqrt(u1);
    double q[4] = {a * sin(u2), a * cos(u2), b * sin(u3), b * cos(u3)};
    double s = q[0] < 0.0 ? -1.0 : 1.0;
    kc_quat out = {(kc_real)(s * q[0]), (kc_real)(s * q[1]), (kc_real)(s * q[2]), (kc_real)(s * q[3])};
    kc_quat unit;
    /* Renormalise in kc_real so that a float quaternion is unit to float precision. */
    if (kc_quat_normalize(&out, &unit) != KC_OK)
        kc_quat_identity(&unit);
    return unit;
}

kc_pose kt_rand_pose(kt_rng *r)
{
    kc_pose p;
    kc_quat q = kt_rand_quat(r);
    kc_quat_to_mat3(&q, &p.R);
    for (int i = 0; i < 3; i++)
        p.t.v[i] = (kc_real)kt_uniform(r, -2.0, 2.0);
    return p;
}

kc_vec3 kt_rand_unit(kt_rng *r)
{
    double z = kt_uniform(r, -1.0, 1.0), a = kt_uniform(r, 0.0, 2.0 * KT_PI), s = sqrt(1.0 - z * z);
    return kc_vec3_make((kc_real)(s * cos(a)), (kc_real)(s * sin(a)), (kc_real)z);
}

void kt_rand_q(kt_rng *r, const kc_chain *chain, kc_real *q)
{
    for (int j = 0; j < chain->n_joints; j++) {
        double lo = (double)chain->joints[j].limits.q_min, hi = (double)chain->joints[j].limits.q_max;
        if (!isfinite(lo))
            lo = -KT_PI;
        if (!isfinite(hi))
            hi = KT_PI;
        q[j] = (kc_real)kt_uniform(r, lo, hi);
        /* Rounding to float can step just outside a limit. */
        q[j] = kc_clamp(q[j], chain->joints[j].limits.q_min, chain->joints[j].limits.q_max);
    }
}

/* ---- trajectory reference data ---- */

double kt_traj_tol(double scale)
{
#ifdef KC_REAL_FLOAT
    return 64.0 * (double)KC_REAL_EPS * (scale > 1.0 ? scale : 1.0);
#else
    (void)scale;
    return 1e-9;
#endif
}

double kt_max_abs_json(const json_t *arr)
{
    double m = 0.0;
    for (size_t i = 0; i < json_array_size(arr); i++) {
        const json_t *e = json_array_get(arr, i);
        double v = json_is_array(e) ? kt_max_abs_json(e) : fabs(kt_num(e));
        if (v > m)
            m = v;
    }
    return m;
}

int kt_index_listed(const json_t *list, size_t i)
{
    for (size_t j = 0; j < json_array_size(list); j++)
        if ((size_t)kt_num(json_array_get(list, j)) == i)
            return 1;
    return 0;
}

kc_goal kt_joint_goal(int64_t id, const kc_real *q, int n)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = KC_GOAL_JOINT;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    memcpy(g.q, q, sizeof(kc_real) * (size_t)n);
    return g;
}

kc_goal kt_line_goal(int64_t id, const kc_pose *to)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = KC_GOAL_LINE;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.pose = *to;
    g.orient = KC_INTERP_SLERP;
    return g;
}

kc_goal kt_cart_path_goal(int64_t id, kc_path_method method, const kc_vec3 *at, int n, const kc_mat3 *R)
{
    kc_goal g;
    kc_quat o;
    kc_quat_from_mat3(R, &o);
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = KC_GOAL_PATH_CART;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.method = method;
    g.n_points = n;
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++)
            g.points[i][k] = at[i].v[k];
        g.points[i][3] = o.w;
        g.points[i][4] = o.x;
        g.points[i][5] = o.y;
        g.points[i][6] = o.z;
    }
    return g;
}

kc_goal kt_cart_path_walk(kt_rng *r, int64_t id, kc_path_method method, const kc_pose *from, double lo, double hi)
{
    kc_vec3 at[2], last = from->t;
    for (int i = 0; i < 2; i++) {
        kc_vec3 d = kt_rand_unit(r);
        kc_real len = (kc_real)kt_uniform(r, lo, hi);
        for (int k = 0; k < 3; k++)
            at[i].v[k] = last.v[k] + len * d.v[k];
        last = at[i];
    }
    return kt_cart_path_goal(id, method, at, 2, &from->R);
}

int kt_has_event(const kc_ctrl_output *out, kc_ctrl_event_kind kind, int64_t id)
{
    for (int e = 0; e < out->n_events; e++)
        if (out->events[e].kind == kind && out->events[e].goal_id == id)
            return 1;
    return 0;
}

const kc_real KT_PUMA_Q0[6] = {KC_R(0.1), KC_R(0.8), KC_R(-2.4), KC_R(0.1), KC_R(0.6), KC_R(0.2)};
const kc_real KT_PANDA_Q0[7] = {KC_R(0.0), KC_R(-0.3), KC_R(0.0), KC_R(-2.0), KC_R(0.0), KC_R(1.8), KC_R(0.8)};

void kt_start_q(const kc_chain *chain, kc_model model, kc_real *q)
{
    for (int j = 0; j < chain->n_joints; j++) {
        const kc_joint_limits *l = &chain->joints[j].limits;
        q[j] = model == KC_MODEL_PUMA560 ? KT_PUMA_Q0[j] : (l->q_min + l->q_max) / KC_R(2.0);
    }
}

kc_pose kt_rest_on_stop(kc_ctrl *sim, const kc_ctrl *ctrl)
{
    kc_ctrl_output out;
    kc_ctrl_input in = {NULL, KC_CMD_STOP, 0, KC_REASON_NONE};
    *sim = *ctrl;
    for (int k = 0; k < 20000; k++) {
        assert_int_equal(kc_ctrl_step(sim, &in, &out), KC_OK);
        in.command = KC_CMD_NONE;
        if (out.state == KC_CTRL_IDLE)
            return out.pose;
    }
    fail_msg("the stop did not end");
    return out.pose;
}

kc_goal kt_cart_goal(kt_rng *r, int64_t id, const kc_pose *home, int arc, int fast)
{
    kc_goal g = kt_line_goal(id, home);
    kc_vec3 dir = kt_rand_unit(r);
    kc_real len = (kc_real)kt_uniform(r, 0.05, 0.3);
    for (int i = 0; i < 3; i++)
        g.pose.t.v[i] += len * dir.v[i];
    if (arc) {
        g.kind = KC_GOAL_ARC;
        for (int i = 0; i < 3; i++)
            g.via.v[i] = KC_R(0.5) * (home->t.v[i] + g.pose.t.v[i]) + (kc_real)kt_uniform(r, -0.05, 0.05);
    }
    if (fast) {
        g.speed = (kc_real)kt_uniform(r, 0.05, 0.5);
        g.accel = g.speed * (kc_real)kt_uniform(r, 2.0, 8.0);
        g.jerk = g.accel * (kc_real)kt_uniform(r, 5.0, 20.0);
    }
    return g;
}

double kt_stepped_jerk(kc_ctrl *ctrl, const kc_chain *chain, const kc_real *q0, const kc_goal *g, kc_real dt)
{
    kc_ctrl_cfg cfg = kc_ctrl_cfg_default();
    cfg.dt = dt;
    assert_int_equal(kc_ctrl_init(ctrl, chain, &cfg, q0), KC_OK);
    double qdd[KC_MAX_JOINTS] = {0.0}, worst = 0.0;
    kc_ctrl_output out;
    for (int t = 0; t < 200000; t++) {
        kc_ctrl_input in = {t == 0 ? g : NULL, KC_CMD_NONE, 0, KC_REASON_NONE};
        assert_int_equal(kc_ctrl_step(ctrl, &in, &out), KC_OK);
        for (int j = 0; j < chain->n_joints; j++) {
            double r = fabs((double)out.qdd[j] - qdd[j]) / ((double)chain->joints[j].limits.qddd_max * (double)dt);
            worst = fmax(worst, r);
            qdd[j] = (double)out.qdd[j];
        }
        assert_false(kt_has_event(&out, KC_EVENT_FAULT, g->id));
        if (kt_has_event(&out, KC_EVENT_COMPLETED, g->id))
            return worst;
    }
    fail_msg("goal %lld did not end", (long long)g->id);
    return worst;
}

int kt_slow_passes, kt_slow_first_within;

kc_status kt_judge_slowed(kt_judge_fn judge, void *ctx, const kc_ctrl_cfg *cfg, kc_goal *g, kc_verdict *v)
{
    kc_status st = judge(g, v, ctx);
    kc_check_slow ss;
    kt_slow_passes = kt_slow_first_within = 0;
    if (st != KC_OK || !kc_check_slow_start(&ss, v))
        return st;
    kc_goal asked = *g;
    for (int pass = 0; pass < KC_CHECK_SLOW_PASSES && ss.s > KC_R(0.0); pass++) {
        kc_goal h = asked;
        kc_verdict w;
        if (kc_goal_slow(&h, cfg, ss.s) != KC_OK || judge(&h, &w, ctx) != KC_OK)
            break;
        kt_slow_passes = pass + 1;
        if (kt_slow_first_within == 0 && kc_check_jerk_within(&w))
            kt_slow_first_within = pass + 1;
        if (kc_check_slow_next(&ss, &w)) {
            *g = h;
            *v = w;
        }
    }
    return st;
}

static double half_time(double v, double A, double J)
{
    return v >= A * A / J ? v / A + A / J : 2.0 * sqrt(v / J);
}

double kt_scurve_optimum_time(double D, double V, double A, double J)
{
    if (D == 0.0)
        return 0.0;
    double v = V;
    if (v * half_time(v, A, J) > D) {
        double lo = 0.0, hi = V;
        for (int i = 0; i < 200; i++) {
            double mid = 0.5 * (lo + hi);
            if (mid * half_time(mid, A, J) > D)
                hi = mid;
            else
                lo = mid;
        }
        v = lo;
    }
    double ta = half_time(v, A, J);
    return 2.0 * ta + (D - v * ta) / v;
}

void kt_stream_init(kt_stream *s, kt_rng *r, const kc_pose *start, double dt)
{
    s->start = *start;
    s->dt = dt;
    for (int k = 0; k < 3; k++) {
        s->amp[k] = kt_uniform(r, 0.0, 0.03);
        s->w[k] = kt_uniform(r, 0.5, 5.0);
        s->phi[k] = kt_uniform(r, 0.0, 2.0 * KT_PI);
    }
    s->t = 0;
}

kc_goal kt_stream_next(kt_stream *s, int64_t id)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = KC_GOAL_SERVO;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.pose = s->start;
    double t = (double)s->t * s->dt;
    for (int k = 0; k < 3; k++)
        g.pose.t.v[k] += (kc_real)(s->amp[k] * (sin(s->w[k] * t + s->phi[k]) - sin(s->phi[k])));
    s->t++;
    return g;
}

kc_goal kt_checked_line(kt_rng *r, kc_check *check, const kc_real *q, const kc_pose *home, int64_t id,
                        const kt_line_draw *d)
{
    for (int tries = 0; tries < 100; tries++) {
        kc_goal g = kt_line_goal(id, home);
        kc_vec3 dir = kt_rand_unit(r);
        kc_real len = (kc_real)kt_uniform(r, d->len_lo, d->len_hi);
        for (int i = 0; i < 3; i++)
            g.pose.t.v[i] += len * dir.v[i];
        if (d->turn > 0.0) {
            kc_vec3 axis = kt_rand_unit(r), rv;
            kc_quat dq;
            kc_mat3 dR;
            kc_vec3_scale(&axis, (kc_real)kt_uniform(r, 0.0, d->turn), &rv);
            kc_quat_exp(&rv, &dq);
            kc_quat_to_mat3(&dq, &dR);
            kc_mat3_mul(&dR, &home->R, &g.pose.R);
        }
        g.speed = d->speed;
        g.accel = d->accel;
        g.jerk = d->jerk;
        kc_verdict v;
        if (kc_check_from(check, q, &g, &v) == KC_OK)
            return g;
    }
    fail_msg("no line the arm can follow in 100 tries");
    return kt_line_goal(id, home);
}
