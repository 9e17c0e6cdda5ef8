/* SPDX-License-Identifier: BSD-3-Clause */
/* path_cart.c - Cartesian multi-point paths (seed 001 lab 7): the position
 * as a 3-D path of path.c's methods, the orientation through rotation knots
 * in the tangent spaces of the knot orientations, and the path-length
 * tables; the formulas are documented in kinctl/path_cart.h. */
#include "kinctl/path_cart.h"

#include <string.h>

#include "path_internal.h"
#include "vec3_internal.h"

/* Below this rotation angle (rad) the SO(3) Jacobian terms use their series
 * (truncation below 1e-16 in double at 0.1, below 1e-10 in float at 0.5,
 * where the closed forms lose no more than a few ulps to cancellation). */
#ifdef KC_REAL_FLOAT
#define PATH_SERIES_ANGLE KC_R(0.5)
#else
#define PATH_SERIES_ANGLE KC_R(0.1)
#endif

/* Rotations of the knots: sign-aligned unit quaternions, w_i = log(r_i^*
 * r_{i+1}) (angle <= pi), and the knot angular velocities (body frame). */
typedef struct rot_knots {
    kc_quat r[KC_PATH_MAX_KNOTS];
    kc_vec3 w[KC_PATH_MAX_KNOTS];
    kc_vec3 om[KC_PATH_MAX_KNOTS];
} rot_knots;

/* Coefficients of the right Jacobian of SO(3), J_r(v) = I - ca [v]x + cb
 * [v]x^2 with ca = (1 - cos th) / th^2, cb = (th - sin th) / th^3, and
 * their derivatives divided by th (for d/dt J_r). */
static void jr_coeffs(kc_real th, kc_real *ca, kc_real *cb, kc_real *dca, kc_real *dcb)
{
    kc_real t2 = th * th;
    if (th < PATH_SERIES_ANGLE) {
        *ca = KC_R(0.5) - t2 / KC_R(24.0) + t2 * t2 / KC_R(720.0) - t2 * t2 * t2 / KC_R(40320.0);
        *cb = KC_R(1.0) / KC_R(6.0) - t2 / KC_R(120.0) + t2 * t2 / KC_R(5040.0) - t2 * t2 * t2 / KC_R(362880.0);
        *dca = -KC_R(1.0) / KC_R(12.0) + t2 / KC_R(180.0) - t2 * t2 / KC_R(6720.0) + t2 * t2 * t2 / KC_R(453600.0);
        *dcb = -KC_R(1.0) / KC_R(60.0) + t2 / KC_R(1260.0) - t2 * t2 / KC_R(60480.0) + t2 * t2 * t2 / KC_R(4989600.0);
        return;
    }
    kc_real s, c;
    kc_sincos(th, &s, &c);
    *ca = (KC_R(1.0) - c) / t2;
    *cb = (th - s) / (t2 * th);
    *dca = s / (t2 * th) - KC_R(2.0) * (KC_R(1.0) - c) / (t2 * t2);
    *dcb = (KC_R(1.0) - c) / (t2 * t2) - KC_R(3.0) * (th - s) / (t2 * t2 * th);
}

/* J_r(v)^-1 x = x + 1/2 v x x + ce v x (v x x), ce = 1/th^2 - cot(th/2) /
 * (2 th): finite for th in [0, pi]. */
static kc_vec3 jr_inv_apply(kc_vec3 v, kc_vec3 x)
{
    kc_real th = kc_vec3_norm(&v), t2 = th * th, ce;
    if (th < PATH_SERIES_ANGLE) {
        ce = KC_R(1.0) / KC_R(12.0) + t2 / KC_R(720.0) + t2 * t2 / KC_R(30240.0) + t2 * t2 * t2 / KC_R(1209600.0);
    } else {
        kc_real s, c;
        kc_sincos(KC_R(0.5) * th, &s, &c);
        ce = KC_R(1.0) / t2 - c / (KC_R(2.0) * th * s);
    }
    kc_vec3 vx = kc_v3_cross(v, x);
    return kc_v3_add(x, kc_v3_add(kc_v3_scale(vx, KC_R(0.5)), kc_v3_scale(kc_v3_cross(v, vx), ce)));
}

/* (d/dt J_r(v)) vd for a motion with v' = vd:
 * -ca' (v.vd/th) v x vd + cb' (v.vd/th) v x (v x vd) + cb vd x (v x vd). */
static kc_vec3 jr_dot_apply(kc_vec3 v, kc_vec3 vd)
{
    kc_real ca, cb, dca, dcb;
    jr_coeffs(kc_vec3_norm(&v), &ca, &cb, &dca, &dcb);
    kc_real vv = kc_v3_dot(v, vd);
    kc_vec3 vx = kc_v3_cross(v, vd);
    kc_vec3 r = kc_v3_scale(vx, -dca * vv);
    r = kc_v3_add(r, kc_v3_scale(kc_v3_cross(v, vx), dcb * vv));
    return kc_v3_add(r, kc_v3_scale(kc_v3_cross(vd, vx), cb));
}

/* Orientation coefficients of piece p: base quaternion and the rotation
 * vector polynomial rc[i][axis]. */
static void build_rot_piece(const kc_path_knots *K, const rot_knots *R, int p, kc_quat *base, kc_real rc[6][3])
{
    for (int i = 0; i < 6; i++)
        rc[i][0] = rc[i][1] = rc[i][2] = KC_R(0.0);
    if (K->method == KC_PATH_BLEND) {
        int i = p / 2;
        *base = R->r[i];
        for (int x = 0; x < 3; x++) {
            if (p % 2 == 0) {
                /* The blend in the tangent space at r_i: B = 0, A on the
                 * incoming turn, C = w_i. */
                kc_real A = i == 0 ? KC_R(0.0) : -R->w[i - 1].v[x] * K->t_acc / kc_path_seg_time(K, i - 1);
                kc_real dC = i == K->n - 1 ? KC_R(0.0) : R->w[i].v[x];
                kc_real T1 = i == K->n - 1 ? KC_R(1.0) : kc_path_seg_time(K, i);
                kc_path_blend_coeffs(A, KC_R(0.0), dC, T1, K->t_acc, K->blend, &rc[0][x], 3);
            } else {
                kc_real rate = R->w[i].v[x] / kc_path_seg_time(K, i);
                rc[0][x] = rate * K->t_acc;
                rc[1][x] = rate;
            }
        }
        return;
    }
    /* Quintic in the tangent space at r_p: v(0) = 0, v'(0) = omega_p, v''(0)
     * = 0 (J_r(0) = I and its derivative vanishes on v' there), v(T) = w_p,
     * J_r(w_p) v'(T) = omega_{p+1}, d/dt (J_r v') = 0 at T. */
    kc_real T = kc_path_seg_time(K, p);
    kc_vec3 w = R->w[p];
    kc_vec3 v1 = jr_inv_apply(w, R->om[p + 1]);
    kc_vec3 a1 = kc_v3_scale(jr_inv_apply(w, jr_dot_apply(w, v1)), KC_R(-1.0));
    *base = R->r[p];
    for (int x = 0; x < 3; x++)
        kc_path_quintic_coeffs(KC_R(0.0), R->om[p].v[x], KC_R(0.0), w.v[x], v1.v[x], a1.v[x], T, &rc[0][x], 3);
}

/* Knot angular velocities (body frame): the slope of the parabola through
 * three knots, 0 at both ends. w_{i-1} is the same vector in the frames of
 * r_{i-1} and r_i (it is the axis of the turn between them). */
static void knot_rates(const kc_path_knots *K, rot_knots *R)
{
    R->om[0] = R->om[K->n - 1] = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    for (int i = 1; i + 1 < K->n; i++) {
        kc_real Tl = kc_path_seg_time(K, i - 1), Tr = kc_path_seg_time(K, i);
        kc_vec3 rl = kc_v3_scale(R->w[i - 1], KC_R(1.0) / Tl), rr = kc_v3_scale(R->w[i], KC_R(1.0) / Tr);
        R->om[i] = kc_v3_scale(kc_v3_add(kc_v3_scale(rl, Tr), kc_v3_scale(rr, Tl)), KC_R(1.0) / (Tl + Tr));
    }
}

/* 5-point Gauss-Legendre on [0, 1]: over a table sub-interval (at most
 * 1/32 of a piece, split at the speed's minima, so |p'| is smooth on it)
 * it integrates polynomials of degree 9 exactly, far inside the 1e-7 of the
 * length that s must keep (measured against Simpson in the path tests),
 * one speed evaluation a tick cheaper than 6 points. */
#define PATH_GL_POINTS 5
static const kc_real gl_x[PATH_GL_POINTS] = {
    KC_R(0.046910077030668004), KC_R(0.23076534494715845), KC_R(0.5), KC_R(0.76923465505284155),
    KC_R(0.953089922969332),
};
static const kc_real gl_w[PATH_GL_POINTS] = {
    KC_R(0.11846344252809454), KC_R(0.23931433524968323), KC_R(0.28444444444444444), KC_R(0.23931433524968323),
    KC_R(0.11846344252809454),
};

/* |p'| of piece p at tau from the velocity coefficients. */
static kc_real speed_at(const kc_path_cart *path, int p, kc_real tau)
{
    const kc_real(*vc)[3] = path->vc[p];
    kc_real x = KC_R(0.0), y = KC_R(0.0), z = KC_R(0.0);
    for (int i = path->pos.n_coeffs - 2; i >= 0; i--) {
        x = x * tau + vc[i][0];
        y = y * tau + vc[i][1];
        z = z * tau + vc[i][2];
    }
    return kc_sqrt(x * x + y * y + z * z);
}

static int piece_is_line(const kc_path *pos, int p)
{
    for (int i = 2; i < pos->n_coeffs; i++)
        for (int j = 0; j < 3; j++)
            if (pos->c[p][i][j] != KC_R(0.0))
                return 0;
    return 1;
}

/* Gauss-Legendre of |p'| over [a, b] of piece p. */
static kc_real arc_gl(const kc_path_cart *path, int p, kc_real a, kc_real b)
{
    kc_real s = KC_R(0.0), h = b - a;
    for (int i = 0; i < PATH_GL_POINTS; i++)
        s += gl_w[i] * speed_at(path, p, a + gl_x[i] * h);
    return s * h;
}

/* Path length at tau on piece p: the table's entry at or below tau plus
 * the quadrature from there (lines: speed times tau). */
static kc_real arc_length(const kc_path_cart *path, int p, kc_real tau)
{
    const kc_path *pos = &path->pos;
    if (piece_is_line(pos, p))
        return path->s_arc[p][0] + speed_at(path, p, KC_R(0.0)) * tau;
    int lo = 0, hi = path->n_arc[p] - 2;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (path->tau_arc[p][mid] <= tau)
            lo = mid;
        else
            hi = mid - 1;
    }
    return path->s_arc[p][lo] + arc_gl(path, p, path->tau_arc[p][lo], tau);
}

/* p'.p'' of piece p at tau: half the rate of the squared speed. */
static kc_real speed2_rate(const kc_path *pos, int p, kc_real tau)
{
    kc_real r = KC_R(0.0);
    for (int j = 0; j < 3; j++) {
        kc_real q, qd, qdd;
        kc_path_horner3(&pos->c[p][0][j], pos->n_coeffs, KC_MAX_JOINTS, tau, &q, &qd, &qdd);
        r += qd * qdd;
    }
    return r;
}

/* Compensated (Kahan) sum: *sum += x with the lost low part kept in *comp,
 * so the table's rounding does not grow with its length. */
static kc_real kahan_add(kc_real *sum, kc_real *comp, kc_real x)
{
    kc_real y = x - *comp;
    kc_real t = *sum + y;
    *comp = (t - *sum) - y;
    *sum = t;
    return t;
}

/* The length table of piece p (see kc_path_cart), continuing the running
 * compensated sum (*s, *comp). */
static void arc_table(kc_path_cart *path, int p, kc_real *s, kc_real *comp)
{
    const kc_path *pos = &path->pos;
    kc_real L = pos->len[p];
    kc_real minima[KC_PATH_ARC_MINIMA] = {KC_R(0.0)}; /* [0, nm) are found below */
    int nm = 0;
    if (!piece_is_line(pos, p) && L > KC_R(0.0)) {
        /* Local minima of the speed: p'.p'' changes from - to +. */
        const int samples = 64;
        kc_real prev = speed2_rate(pos, p, KC_R(0.0));
        for (int i = 1; i <= samples && nm < KC_PATH_ARC_MINIMA; i++) {
            kc_real b = L * (kc_real)i / (kc_real)samples;
            kc_real cur = speed2_rate(pos, p, b);
            if (prev < KC_R(0.0) && cur >= KC_R(0.0) && i < samples) {
                kc_real a = L * (kc_real)(i - 1) / (kc_real)samples, hb = b;
                for (int it = 0; it < 60; it++) {
                    kc_real m = KC_R(0.5) * (a + hb);
                    if (speed2_rate(pos, p, m) < KC_R(0.0))
                        a = m;
                    else
                        hb = m;
                }
                minima[nm++] = KC_R(0.5) * (a + hb);
            }
            prev = cur;
        }
    }
    /* Merge the uniform points with the minima. */
    kc_real h = L / (kc_real)KC_PATH_ARC_SPLITS;
    int n = 0, m = 0;
    int line = piece_is_line(pos, p);
    kc_real speed = speed_at(path, p, KC_R(0.0));
    path->tau_arc[p][n] = KC_R(0.0);
    path->s_arc[p][n++] = *s;
    for (int i = 1; i <= KC_PATH_ARC_SPLITS; i++) {
        kc_real u = i == KC_PATH_ARC_SPLITS ? L : (kc_real)i * h;
        while (m < nm && minima[m] < u) {
            if (minima[m] > path->tau_arc[p][n - 1]) {
                path->tau_arc[p][n] = minima[m];
                path->s_arc[p][n] = kahan_add(s, comp, arc_gl(path, p, path->tau_arc[p][n - 1], minima[m]));
                n++;
            }
            m++;
        }
        path->tau_arc[p][n] = u;
        path->s_arc[p][n] = kahan_add(s, comp, line ? speed * (u - path->tau_arc[p][n - 1])
                                                     : arc_gl(path, p, path->tau_arc[p][n - 1], u));
        n++;
    }
    path->n_arc[p] = n;
}

kc_path_cart_cfg kc_path_cart_cfg_default(void)
{
    kc_path_cart_cfg c;
    memset(&c, 0, sizeof c);
    KC_PATH_KNOT_DEFAULTS(c);
    c.p = NULL;
    c.r = NULL;
    c.v = NULL;
    c.a = NULL;
    c.v_max = c.a_max = KC_R(1.0);
    c.w_max = c.alpha_max = KC_R(0.0);
    return c;
}

kc_status kc_path_cart_plan(kc_path_cart *path, const kc_path_cart_cfg *cfg)
{
    kc_path_knots K;
    kc_path_limits L;
    rot_knots R;
    if (path == NULL || cfg == NULL || cfg->p == NULL || cfg->r == NULL)
        return KC_E_ARG;
    kc_status st = kc_path_check_common(cfg->method, cfg->blend, cfg->spline_end, cfg->n_knots, cfg->v != NULL,
                                cfg->a != NULL, cfg->t, cfg->t_acc, cfg->dt);
    if (st != KC_OK)
        return st;
    int n = cfg->n_knots;
    kc_path_knots_init(&K, cfg->method, cfg->blend, cfg->spline_end, n, 3, cfg->t_acc, cfg->dt);
    for (int i = 0; i < n; i++) {
        st = kc_path_load_knot(&K, i, cfg->p[i].v, cfg->v != NULL ? cfg->v[i].v : NULL,
                               cfg->a != NULL ? cfg->a[i].v : NULL);
        if (st != KC_OK)
            return st;
        const kc_quat *r = &cfg->r[i];
        if (!kc_isfinite(r->w) || !kc_isfinite(r->x) || !kc_isfinite(r->y) || !kc_isfinite(r->z))
            return KC_E_ARG;
        kc_real norm = kc_quat_norm(r);
        if (!(kc_fabs(norm - KC_R(1.0)) <= KC_PATH_TOL_QUAT_NORM))
            return KC_E_ARG;
        kc_quat u;
        kc_quat_normalize(r, &u);
        /* The double cover: turn the shorter way to the next knot. */
        if (i > 0 && R.r[i - 1].w * u.w + R.r[i - 1].x * u.x + R.r[i - 1].y * u.y + R.r[i - 1].z * u.z < KC_R(0.0)) {
            u.w = -u.w;
            u.x = -u.x;
            u.y = -u.y;
            u.z = -u.z;
        }
        R.r[i] = u;
    }
    K.have_v = cfg->v != NULL;
    K.have_a = cfg->a != NULL;
    kc_real angle[KC_PATH_MAX_KNOTS];
    for (int i = 0; i + 1 < n; i++) {
        kc_quat ci, rel;
        kc_quat_conj(&R.r[i], &ci);
        kc_quat_mul(&ci, &R.r[i + 1], &rel);
        kc_quat_log(&rel, &R.w[i]);
        angle[i] = kc_vec3_norm(&R.w[i]);
    }
    R.w[n - 1] = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    memset(&L, 0, sizeof L);
    L.computed = cfg->t == NULL;
    L.norm = 1;
    if (!kc_isfinite(cfg->w_max) || !kc_isfinite(cfg->alpha_max) || cfg->w_max < KC_R(0.0) ||
        cfg->alpha_max < KC_R(0.0) || ((cfg->w_max > KC_R(0.0)) != (cfg->alpha_max > KC_R(0.0))))
        return KC_E_ARG;
    kc_real seg[KC_PATH_MAX_KNOTS] = {KC_R(0.0)}; /* computed times: the loop below fills seg[0..n-1) */
    kc_real ratio = KC_R(0.0);
    if (cfg->t != NULL) {
        kc_path_given_times(&K, cfg->t);
    } else {
        if (!kc_path_finite_positive(cfg->v_max) || !kc_path_finite_positive(cfg->a_max))
            return KC_E_ARG;
        L.vmax[0] = cfg->v_max;
        L.amax[0] = cfg->a_max;
        int angular = cfg->w_max > KC_R(0.0);
        for (int i = 0; i + 1 < n; i++) {
            kc_vec3 dp = kc_vec3_make(K.q[i + 1][0] - K.q[i][0], K.q[i + 1][1] - K.q[i][1], K.q[i + 1][2] - K.q[i][2]);
            seg[i] = kc_path_t_trap(kc_vec3_norm(&dp), cfg->v_max, cfg->a_max);
            if (angular)
                seg[i] = kc_max(seg[i], kc_path_t_trap(angle[i], cfg->w_max, cfg->alpha_max));
        }
        ratio = cfg->v_max / cfg->a_max;
        if (angular)
            ratio = kc_max(ratio, cfg->w_max / cfg->alpha_max);
    }
    st = kc_path_prepare(&K, &L, cfg->t == NULL ? seg : NULL, ratio);
    if (st != KC_OK)
        return st;
    /* Orientation on the final times; dry run first. */
    knot_rates(&K, &R);
    int np = kc_path_n_pieces(&K);
    for (int p = 0; p < np; p++) {
        kc_quat b;
        kc_real rc[6][3];
        build_rot_piece(&K, &R, p, &b, rc);
        for (int i = 0; i < 6; i++)
            for (int x = 0; x < 3; x++)
                if (!kc_isfinite(rc[i][x]))
                    return KC_E_ARG;
    }
    kc_path_commit(&path->pos, &K);
    memset(path->rc, 0, sizeof path->rc);
    memset(path->vc, 0, sizeof path->vc);
    for (int p = 0; p < np; p++)
        for (int i = 1; i < path->pos.n_coeffs; i++)
            for (int x = 0; x < 3; x++)
                path->vc[p][i - 1][x] = (kc_real)i * path->pos.c[p][i][x];
    memset(path->pc, 0, sizeof path->pc);
    for (int p = 0; p < np; p++)
        for (int i = 0; i < path->pos.n_coeffs; i++)
            for (int x = 0; x < 3; x++)
                path->pc[p][i][x] = path->pos.c[p][i][x];
    memset(path->tau_arc, 0, sizeof path->tau_arc);
    memset(path->s_arc, 0, sizeof path->s_arc);
    for (int p = 0; p < KC_PATH_MAX_PIECES; p++) {
        kc_quat_identity(&path->base[p]);
        kc_mat3_identity(&path->base_R[p]);
        path->n_arc[p] = 0;
    }
    kc_real s = KC_R(0.0), comp = KC_R(0.0);
    for (int p = 0; p < np; p++) {
        build_rot_piece(&K, &R, p, &path->base[p], path->rc[p]);
        kc_quat_to_mat3(&path->base[p], &path->base_R[p]);
        arc_table(path, p, &s, &comp);
    }
    path->length = s;
    path->r_end = R.r[n - 1];
    return KC_OK;
}

/* Orientation and angular velocity of piece p at tau: r = base exp(v) and
 * w = R(r) J_r(v) v' = R(base) J_l(v) v' (R(exp v) J_r(v) = J_l(v) = I +
 * ca [v]x + cb [v]x^2), with exp and J_l from one sine and cosine of
 * |v|/2: exp(v) = (cos(th/2), sin(th/2) v/th), ca = (1 - cos th)/th^2 =
 * 2 (sin(th/2)/th)^2, cb = (th - sin th)/th^3, sin th = 2 sin(th/2)
 * cos(th/2). */
static void eval_rot(const kc_path_cart *path, int p, kc_real tau, kc_quat *r, kc_vec3 *w)
{
    int nr = path->pos.method == KC_PATH_BLEND ? 5 : 6;
    kc_vec3 v, vd;
    for (int x = 0; x < 3; x++) {
        kc_real a = KC_R(0.0), b = KC_R(0.0);
        for (int i = nr - 1; i >= 0; i--) {
            b = b * tau + a;
            a = a * tau + path->rc[p][i][x];
        }
        v.v[x] = a;
        vd.v[x] = b;
    }
    kc_real th = kc_vec3_norm(&v), sh, ch, k, cb;
    kc_sincos(KC_R(0.5) * th, &sh, &ch);
    kc_real t2 = th * th;
    /* sin(th/2)/th has no cancellation: only th ~ 0 needs its series. */
    k = th < KC_TOL_SMALL_ANGLE ? KC_R(0.5) - t2 / KC_R(48.0) : sh / th;
    if (th < PATH_SERIES_ANGLE)
        cb = KC_R(1.0) / KC_R(6.0) - t2 / KC_R(120.0) + t2 * t2 / KC_R(5040.0) - t2 * t2 * t2 / KC_R(362880.0);
    else
        cb = (th - KC_R(2.0) * sh * ch) / (t2 * th);
    /* r = base (ch, k v), the Hamilton product written out. */
    const kc_quat *b = &path->base[p];
    kc_real ex = k * v.v[0], ey = k * v.v[1], ez = k * v.v[2];
    r->w = b->w * ch - b->x * ex - b->y * ey - b->z * ez;
    r->x = b->w * ex + b->x * ch + b->y * ez - b->z * ey;
    r->y = b->w * ey - b->x * ez + b->y * ch + b->z * ex;
    r->z = b->w * ez + b->x * ey - b->y * ex + b->z * ch;
    kc_real ca = KC_R(2.0) * k * k;
    kc_vec3 vx = kc_v3_cross(v, vd), vvx = kc_v3_cross(v, vx);
    kc_vec3 wb = kc_vec3_make(vd.v[0] + ca * vx.v[0] + cb * vvx.v[0], vd.v[1] + ca * vx.v[1] + cb * vvx.v[1],
                              vd.v[2] + ca * vx.v[2] + cb * vvx.v[2]);
    const kc_mat3 *R = &path->base_R[p];
    for (int i = 0; i < 3; i++)
        w->v[i] = R->m[i][0] * wb.v[0] + R->m[i][1] * wb.v[1] + R->m[i][2] * wb.v[2];
}

/* sd and sdd from p' and p'' (path.h: the one-sided rate where |p'| = 0). */
static void speed_terms(const kc_vec3 *v, const kc_vec3 *a, int at_end, kc_real *sd, kc_real *sdd)
{
    kc_real sp = kc_vec3_norm(v);
    *sd = sp;
    if (sp > KC_R(0.0))
        *sdd = kc_vec3_dot(v, a) / sp;
    else
        *sdd = at_end ? -kc_vec3_norm(a) : kc_vec3_norm(a);
}

static void eval_cart_piece(const kc_path_cart *path, int p, kc_real tau, kc_path_pose *out)
{
    /* horner3 on the three coordinates at once, from the packed rows. */
    const kc_real(*c)[3] = path->pc[p];
    kc_real q[3] = {KC_R(0.0), KC_R(0.0), KC_R(0.0)}, d1[3] = {KC_R(0.0), KC_R(0.0), KC_R(0.0)},
            d2[3] = {KC_R(0.0), KC_R(0.0), KC_R(0.0)};
    for (int i = path->pos.n_coeffs - 1; i >= 0; i--) {
        for (int x = 0; x < 3; x++) {
            d2[x] = d2[x] * tau + d1[x];
            d1[x] = d1[x] * tau + q[x];
            q[x] = q[x] * tau + c[i][x];
        }
    }
    out->p = kc_vec3_make(q[0], q[1], q[2]);
    out->v = kc_vec3_make(d1[0], d1[1], d1[2]);
    out->a = kc_vec3_make(KC_R(2.0) * d2[0], KC_R(2.0) * d2[1], KC_R(2.0) * d2[2]);
    eval_rot(path, p, tau, &out->r, &out->w);
    out->s = arc_length(path, p, tau);
    speed_terms(&out->v, &out->a, 0, &out->sd, &out->sdd);
}

static void cart_end(const kc_path_cart *path, kc_path_pose *out)
{
    const kc_path *pos = &path->pos;
    out->p = kc_vec3_make(pos->q_end[0], pos->q_end[1], pos->q_end[2]);
    out->v = kc_vec3_make(pos->qd_end[0], pos->qd_end[1], pos->qd_end[2]);
    out->a = kc_vec3_make(pos->qdd_end[0], pos->qdd_end[1], pos->qdd_end[2]);
    out->r = path->r_end;
    /* Every method ends its turn at rest (knot rate 0, blend rate dC/T = 0). */
    out->w = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    out->s = path->length;
    speed_terms(&out->v, &out->a, 1, &out->sd, &out->sdd);
}

kc_status kc_path_cart_eval_time(const kc_path_cart *path, kc_real t, kc_path_pose *out)
{
    if (path == NULL || out == NULL || !(t >= KC_R(0.0)) || path->pos.n_pieces < 1)
        return KC_E_ARG;
    if (t >= path->pos.duration) {
        cart_end(path, out);
        return KC_DONE;
    }
    int p = kc_path_find_piece(&path->pos, t);
    eval_cart_piece(path, p, t - path->pos.start[p], out);
    return KC_OK;
}

kc_status kc_path_cart_eval(const kc_path_cart *path, int64_t k, kc_path_pose *out)
{
    if (path == NULL || out == NULL || k < 0 || path->pos.n_pieces < 1)
        return KC_E_ARG;
    if (k >= path->pos.ticks) {
        cart_end(path, out);
        return KC_DONE;
    }
    kc_real t = (kc_real)k * path->pos.dt;
    int p = kc_path_find_piece(&path->pos, t);
    eval_cart_piece(path, p, t - path->pos.start[p], out);
    return KC_OK;
}

kc_status kc_path_cart_eval_piece(const kc_path_cart *path, int p, kc_real tau, kc_path_pose *out)
{
    if (path == NULL || out == NULL || p < 0 || p >= path->pos.n_pieces || !kc_isfinite(tau))
        return KC_E_ARG;
    eval_cart_piece(path, p, tau, out);
    return KC_OK;
}
