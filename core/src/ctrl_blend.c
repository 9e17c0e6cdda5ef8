/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl_blend.c - a replacing Cartesian goal taken over from a moving line
 * or arc without stopping (kinctl/ctrl.h): the replaced segment M stops on
 * its path (kc_ctrl_stop_on_path, from tick k), coming to rest at pose P_s
 * after T_s ticks; the new segment G is planned from P_s at rest and
 * starts t0 ticks after k. The target while M's stop lasts is the
 * superposition
 *     p = p_M + (p_G - p_s),   R = A R_M,  A = R_G R_s^T (left, base frame),
 *     v = v_M + v_G,           w = w_G + A w_M,
 * the derivative of R being (w_G^ A + A w_M^ A^T A) R_M = (w_G + A w_M)^ R.
 * Before t0 G is at rest at P_s (A = I): the sum is M's stop; once the
 * stop has ended (M at P_s) it is G. G starts at rest with no
 * acceleration, so the sum continues M's motion in position, velocity and
 * acceleration. t0 is the earliest of a bounded search in [0, T_s] whose
 * sum keeps the Cartesian limits on every tick of the overlap; T_s always
 * does (no overlap). */
#include "ctrl_internal.h"


/* Candidates of t0 spread evenly over [0, T_s], then bisection between the
 * last refused and the first admitted, judged on every BLEND_STRIDE-th
 * tick of the overlap (a tick and the one before it); the t0 found is then
 * checked on every tick, and where that fails a bisection on every tick
 * runs up to BLEND_STRIDE ticks later, then to the next point of the grid
 * (T_s at the latest). Each check
 * covers at most the T_s ticks of the overlap; mostly there is one full
 * check, at worst one bisection's worth. */
#define BLEND_GRID 8
#define BLEND_STRIDE 8

/* The bounds a tick of the sum is held to: the larger of the two goals'
 * Cartesian limits (a sum may do what either motion alone may). */
typedef struct blend_bounds {
    kc_real v, a, w, dw;
} blend_bounds;

/* The replaced segment's stop at its tick j. */
static void stop_point(const kc_ctrl_blend *b, int64_t j, kc_ctrl_seg_point *o)
{
    kc_ctrl_interp_point(b->kind, &b->plan.line, &b->plan.arc, &b->stop, j < 0 ? 0 : j, o);
}

/* o (G's point) composed with m (M's stop at the same instant), in place. */
static void compose(const kc_ctrl_blend *b, const kc_ctrl_seg_point *m, kc_ctrl_seg_point *o)
{
    kc_mat3 A, R, Rst;
    kc_vec3 wm, awm;
    kc_mat3_transpose(&b->rest.R, &Rst);
    kc_mat3_mul(&o->pose.R, &Rst, &A);
    kc_mat3_mul(&A, &m->pose.R, &R);
    o->pose.R = R;
    for (int i = 0; i < 3; i++) {
        o->pose.t.v[i] = m->pose.t.v[i] + (o->pose.t.v[i] - b->rest.t.v[i]);
        o->twist[i] += m->twist[i];
        wm.v[i] = m->twist[3 + i];
    }
    kc_mat3_mul_vec(&A, &wm, &awm);
    for (int i = 0; i < 3; i++)
        o->twist[3 + i] += awm.v[i];
}

/* |x| of the first or last three twist components. */
static kc_real norm3(const kc_real *x)
{
    kc_vec3 v = kc_vec3_make(x[0], x[1], x[2]);
    return kc_vec3_norm(&v);
}

/* |x - y| of three components. */
static kc_real dist3(const kc_real *x, const kc_real *y)
{
    kc_vec3 v = kc_vec3_make(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
    return kc_vec3_norm(&v);
}

/* Whether the sum with G starting at t0 keeps, on every stride-th tick j
 * of the overlap (t0 <= j <= T_s, M's ticks), its speed, acceleration (the
 * change of the twist over the tick), angular speed and angular
 * acceleration within the bounds, or within what M or G alone does at that
 * tick when that is more (an arc's centripetal part). */
static int admissible(const kc_ctrl *c, const blend_bounds *lim, int64_t t0, int64_t stride)
{
    const kc_ctrl_blend *b = &c->blend;
    kc_real dt = c->cfg.dt, e = KC_R(1.0) + c->cfg.limit_slack;
    kc_ctrl_seg_point m0, g0, s0, m1, g1, s1;
    int64_t j = t0 > 0 ? t0 : 1, last = -1; /* last: the tick m0, g0, s0 hold */
    for (; j <= b->stop.ticks; j += stride) {
        if (last != j - 1) {
            stop_point(b, j - 1, &m0);
            kc_ctrl_seg_eval(c, j - 1 - t0, &g0);
            s0 = g0;
            compose(b, &m0, &s0);
        }
        stop_point(b, j, &m1);
        kc_ctrl_seg_eval(c, j - t0, &g1);
        s1 = g1;
        compose(b, &m1, &s1);
        for (int k = 0; k < 6; k += 3) {
            kc_real vmax = k == 0 ? lim->v : lim->w, amax = k == 0 ? lim->a : lim->dw;
            vmax = kc_max(vmax, kc_max(norm3(&m1.twist[k]), norm3(&g1.twist[k])));
            amax = kc_max(amax, kc_max(dist3(&m1.twist[k], &m0.twist[k]), dist3(&g1.twist[k], &g0.twist[k])) / dt);
            if (!(norm3(&s1.twist[k]) <= vmax * e && dist3(&s1.twist[k], &s0.twist[k]) <= amax * dt * e))
                return 0;
        }
        m0 = m1;
        g0 = g1;
        s0 = s1;
        last = j;
    }
    return 1;
}

/* The earliest admissible t0 the search finds (T_s when none before). */
static int64_t start_offset(const kc_ctrl *c, const blend_bounds *lim)
{
    int64_t ts = c->blend.stop.ticks, step = (ts + BLEND_GRID - 1) / BLEND_GRID;
    int64_t lo = -1, hi = ts; /* lo refused (or none), hi admitted */
    if (step < 1)
        return ts;
    for (int64_t t = 0; t < ts; t += step) {
        if (admissible(c, lim, t, BLEND_STRIDE)) {
            hi = t;
            break;
        }
        lo = t;
    }
    for (int i = 0; i < 20 && hi - lo > 1; i++) {
        int64_t mid = lo + (hi - lo) / 2;
        if (admissible(c, lim, mid, BLEND_STRIDE))
            hi = mid;
        else
            lo = mid;
    }
    /* A sparse check can miss the ticks that refuse, fewer than
     * BLEND_STRIDE where the overlap refuses at its edge: checked on every
     * tick, a refused t0 gives way to a bisection (on every tick) up to
     * BLEND_STRIDE ticks later, then up to the next point of the grid. */
    for (int tries = 0; hi < ts && !admissible(c, lim, hi, 1); tries++) {
        int64_t next = tries == 0 ? hi + BLEND_STRIDE : (hi / step + 1) * step;
        lo = hi;
        hi = next < ts ? next : ts;
        for (int i = 0; i < 20 && hi - lo > 1; i++) {
            int64_t mid = lo + (hi - lo) / 2;
            if (admissible(c, lim, mid, 1))
                hi = mid;
            else
                lo = mid;
        }
    }
    return hi;
}

int kc_ctrl_blend_take(kc_ctrl *c, const kc_goal *g, kc_ctrl_output *out)
{
    kc_ctrl_blend *b = &c->blend;
    if (!c->active || c->state != KC_CTRL_MOVING || b->on ||
        (c->goal.kind != KC_GOAL_LINE && c->goal.kind != KC_GOAL_ARC) ||
        (g->kind != KC_GOAL_LINE && g->kind != KC_GOAL_ARC && g->kind != KC_GOAL_PATH_CART))
        return 0;
    kc_interp_limits lm = kc_ctrl_cart_limits(c, &c->goal), lg = kc_ctrl_cart_limits(c, g);
    blend_bounds lim = {kc_max(lm.v, lg.v), kc_max(lm.a, lg.a), kc_max(lm.w, lg.w), kc_max(lm.dw, lg.dw)};
    kc_real old_length = c->path_length;
    kc_ctrl_stop_on_path(c, INTENT_PREEMPT);
    if (c->drive != KC_DRIVE_PROFILE)
        return 0; /* a stop that is not a profile of u (none is today): it goes on, the goal waits for it */
    /* M moves out of c->plan (a line or an arc: small), G is planned there. */
    b->kind = c->goal.kind;
    if (b->kind == KC_GOAL_LINE)
        b->plan.line = c->plan.line;
    else
        b->plan.arc = c->plan.arc;
    b->stop = c->drive_prof;
    b->k0 = c->k0;
    kc_ctrl_seg_point rest;
    stop_point(b, b->stop.ticks, &rest);
    b->rest = rest.pose;
    kc_status st = kc_ctrl_plan_cart_from(c, g, &b->rest);
    if (st == KC_OK && g->kind == KC_GOAL_PATH_CART) {
        /* A path that does not start at rest (Lagrange's) needs a ramp of
         * its own: not superposed. */
        kc_path_pose s;
        kc_path_cart_eval_time(&c->plan.path_cart, KC_R(0.0), &s);
        if (kc_vec3_norm(&s.v) != KC_R(0.0) || kc_vec3_norm(&s.w) != KC_R(0.0))
            st = KC_E_ARG;
    }
    if (st != KC_OK) {
        /* M goes on stopping; G waits for it (and is planned again then). */
        if (b->kind == KC_GOAL_LINE)
            c->plan.line = b->plan.line;
        else
            c->plan.arc = b->plan.arc;
        c->path_length = old_length;
        return 0;
    }
    int64_t old_id = c->goal.id;
    kc_ctrl_goal_copy(&c->goal, g);
    c->drive = KC_DRIVE_NOMINAL;
    c->stop_intent = KC_CMD_NONE;
    c->settle = 0;
    c->state = KC_CTRL_MOVING;
    b->on = 1;
    b->lax = 1;
    b->err = INF;
    c->k0 = b->k0 + start_offset(c, &lim);
    kc_ctrl_emit(out, KC_EVENT_ACCEPTED, g->id, KC_REASON_NONE, 0);
    kc_ctrl_emit(out, KC_EVENT_PREEMPTED, old_id, KC_REASON_NONE, 0);
    kc_ctrl_emit(out, KC_EVENT_STARTED, g->id, KC_REASON_NONE, 0);
    return 1;
}

void kc_ctrl_blend_apply(kc_ctrl *c, int64_t k, kc_ctrl_seg_point *o)
{
    kc_ctrl_blend *b = &c->blend;
    int64_t j = k - b->k0;
    if (j >= b->stop.ticks) {
        b->on = 0; /* M rests at P_s: the sum is G alone from here */
        return;
    }
    kc_ctrl_seg_point m;
    stop_point(b, j, &m);
    compose(b, &m, o);
}
