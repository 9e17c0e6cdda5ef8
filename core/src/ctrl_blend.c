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
    kc_real v, a, j; /* the tool point's speed, acceleration and jerk */
    kc_real w, dw, dj; /* its angular ones */
} blend_bounds;

/* The replaced segment's stop at its tick j. */
static void stop_point(const kc_ctrl_blend *b, int64_t j, kc_ctrl_seg_point *o)
{
    kc_ctrl_interp_point(b->kind, &b->plan.line, &b->plan.arc, b->stop_drive, &b->stop.prof, &b->stop.scurve,
                         j < 0 ? 0 : j, o);
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

/* The twists of M's stop, of G and of their sum at one tick, and their
 * tool points (p). */
typedef struct blend_twists {
    kc_real m[6], g[6], s[6];
    kc_real pm[3], pg[3], ps[3];
} blend_twists;

/* The twists at M's tick j with G started at t0; m and g are scratch. */
static void twists_at(const kc_ctrl *c, int64_t t0, int64_t j, kc_ctrl_seg_point *m, kc_ctrl_seg_point *g,
                      blend_twists *out)
{
    stop_point(&c->blend, j, m);
    kc_ctrl_seg_eval(c, j - t0, g);
    for (int i = 0; i < 6; i++) {
        out->m[i] = m->twist[i];
        out->g[i] = g->twist[i];
    }
    for (int i = 0; i < 3; i++) {
        out->pm[i] = m->pose.t.v[i];
        out->pg[i] = g->pose.t.v[i];
    }
    compose(&c->blend, m, g);
    for (int i = 0; i < 6; i++)
        out->s[i] = g->twist[i];
    for (int i = 0; i < 3; i++)
        out->ps[i] = g->pose.t.v[i];
}

/* |x0 + c1 x1 + c2 x2| of three components (x2 may be NULL). */
static kc_real comb3(const kc_real *x0, kc_real c1, const kc_real *x1, kc_real c2, const kc_real *x2)
{
    kc_vec3 v;
    for (int i = 0; i < 3; i++)
        v.v[i] = x0[i] + c1 * x1[i] + (x2 != NULL ? c2 * x2[i] : KC_R(0.0));
    return kc_vec3_norm(&v);
}

/* |x| of three components. */
static kc_real norm3(const kc_real *x) { return comb3(x, KC_R(0.0), x, KC_R(0.0), NULL); }

/* Whether the sum with G starting at t0 keeps, on every stride-th tick j
 * of the overlap (t0 <= j <= T_s, M's ticks), its speed (at the tick, and
 * the tool point's step over it), acceleration (the change of the twist
 * over the tick), jerk (the change of that change, from M's tick 2 on: the
 * ticks before the takeover are M's own) and their angular counterparts
 * within the bounds, or within what M or G alone does at that tick when
 * that is more (an arc's centripetal part). */
static int admissible(const kc_ctrl *c, const blend_bounds *lim, int64_t t0, int64_t stride)
{
    const kc_ctrl_blend *b = &c->blend;
    kc_real dt = c->cfg.dt, e = KC_R(1.0) + c->cfg.limit_slack;
    kc_ctrl_seg_point m, g;
    blend_twists w[3]; /* ticks j - 2, j - 1, j at w[(j - 2) % 3] ... */
    int64_t j = t0 > 0 ? t0 : 1, have = -1; /* have: the last tick w holds (and those before it) */
    for (; j <= b->stop_ticks; j += stride) {
        for (int64_t i = (have >= j - 2 ? have + 1 : j - 2); i <= j; i++)
            if (i >= 0)
                twists_at(c, t0, i, &m, &g, &w[i % 3]);
        have = j;
        const blend_twists *t1 = &w[j % 3], *t0w = &w[(j - 1) % 3], *tm = j >= 2 ? &w[(j - 2) % 3] : NULL;
        for (int k = 0; k < 6; k += 3) {
            kc_real vmax = k == 0 ? lim->v : lim->w, amax = k == 0 ? lim->a : lim->dw;
            kc_real jmax = k == 0 ? lim->j : lim->dj;
            vmax = kc_max(vmax, kc_max(norm3(&t1->m[k]), norm3(&t1->g[k])));
            amax = kc_max(amax, kc_max(comb3(&t1->m[k], -1, &t0w->m[k], 0, NULL),
                                       comb3(&t1->g[k], -1, &t0w->g[k], 0, NULL)) / dt);
            if (!(norm3(&t1->s[k]) <= vmax * e &&
                  comb3(&t1->s[k], -1, &t0w->s[k], 0, NULL) <= amax * dt * e))
                return 0;
            if (k == 0) {
                /* The step, with the rounding of the two positions it is
                 * the difference of (a few units of KC_REAL_EPS |p|). */
                kc_real step = kc_max(vmax, kc_max(comb3(t1->pm, -1, t0w->pm, 0, NULL),
                                                   comb3(t1->pg, -1, t0w->pg, 0, NULL)) / dt);
                kc_real round = KC_R(4.0) * KC_REAL_EPS * norm3(t1->ps);
                if (!(comb3(t1->ps, -1, t0w->ps, 0, NULL) <= step * dt * e + round))
                    return 0;
            }
            if (tm == NULL)
                continue;
            jmax = kc_max(jmax, kc_max(comb3(&t1->m[k], -2, &t0w->m[k], 1, &tm->m[k]),
                                       comb3(&t1->g[k], -2, &t0w->g[k], 1, &tm->g[k])) / (dt * dt));
            if (!(comb3(&t1->s[k], -2, &t0w->s[k], 1, &tm->s[k]) <= jmax * dt * dt * e))
                return 0;
        }
    }
    return 1;
}

/* The earliest admissible t0 the search finds (T_s when none before). */
static int64_t start_offset(const kc_ctrl *c, const blend_bounds *lim)
{
    int64_t ts = c->blend.stop_ticks, step = (ts + BLEND_GRID - 1) / BLEND_GRID;
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
    blend_bounds lim = {kc_max(lm.v, lg.v), kc_max(lm.a, lg.a), kc_max(lm.j, lg.j),
                        kc_max(lm.w, lg.w), kc_max(lm.dw, lg.dw), kc_max(lm.dj, lg.dj)};
    kc_real old_length = c->path_length;
    kc_ctrl_stop_on_path(c, INTENT_PREEMPT);
    if (c->drive != KC_DRIVE_PROFILE && c->drive != KC_DRIVE_SCURVE)
        return 0; /* a stop that is not a profile of u: it goes on, the goal waits for it */
    /* M moves out of c->plan (a line or an arc: small), G is planned there. */
    b->kind = c->goal.kind;
    if (b->kind == KC_GOAL_LINE)
        b->plan.line = c->plan.line;
    else
        b->plan.arc = c->plan.arc;
    b->stop_drive = c->drive;
    if (c->drive == KC_DRIVE_SCURVE) {
        b->stop.scurve = c->drive_scurve;
        b->stop_ticks = c->drive_scurve.ticks;
    } else {
        b->stop.prof = c->drive_prof;
        b->stop_ticks = c->drive_prof.ticks;
    }
    b->k0 = c->k0;
    kc_ctrl_seg_point rest;
    stop_point(b, b->stop_ticks, &rest);
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
    if (j >= b->stop_ticks) {
        b->on = 0; /* M rests at P_s: the sum is G alone from here */
        return;
    }
    kc_ctrl_seg_point m;
    stop_point(b, j, &m);
    compose(b, &m, o);
}
