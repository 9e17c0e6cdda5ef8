/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl_blend.c - a replacing Cartesian goal taken over from a moving
 * goal without stopping (kinctl/ctrl.h): the replaced segment M stops
 * (kc_ctrl_stop_on_path, from tick k: a line or an arc on its path, a
 * joint move or a servo stream in joint space; a path joint by joint,
 * halt_stop), coming to rest at pose P_s after T_s
 * ticks; the new segment G is planned from P_s at rest and starts t0 ticks
 * after k. The target while M's stop lasts is the superposition
 *     p = p_M + (p_G - p_s),   R = A R_M,  A = R_G R_s^T (left, base frame),
 *     v = v_M + v_G,           w = w_G + A w_M,
 * the derivative of R being (w_G^ A + A w_M^ A^T A) R_M = (w_G + A w_M)^ R.
 * A stop in joint space gives (p_M, R_M) = FK(q_M) and (v_M, w_M) =
 * J(q_M) qd_M, its geometric Jacobian's twist (exact, where a difference
 * of consecutive ticks would lag by half a tick). Before t0 G is at rest
 * at P_s (A = I): the sum is M's stop; once the stop has ended (M at P_s)
 * it is G. G starts at rest with no acceleration, so the sum continues M's
 * motion in position, velocity and acceleration. t0 is the earliest of a
 * bounded search in [0, T_s] whose sum keeps the Cartesian limits on every
 * tick of the overlap; T_s always does (no overlap). A joint path G
 * replacing any of them is superposed the same way in joint space, M's
 * stop (a line's or an arc's joint by joint, halt_stop) taken exactly: q = q_M + (q_G - q_s), t0 keeping
 * the joints' limits (admissible_joints). */
#include "ctrl_internal.h"
#include "size_internal.h"

#include <string.h>


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

/* One profile of a stop in joint space as the IK step integrates it:
 * the step moves q by dt times the twist fed forward, so a stop fed its
 * velocity at tick j + 1 from its position at tick j goes
 *     p_E(j) = p(0) + dt (v(1) + ... + v(j))
 *            = p(j) + dt/2 (v(j) - v(0)) + dt^2/12 (a(j) - a(0))
 *              + dt^3/6 sum_k dJ_k B3(x_k)
 * (Euler-Maclaurin, exact for v piecewise quadratic in t with v and a
 * continuous: each switch of the jerk by dJ_k at x_k dt, 0 < x_k < j,
 * adds its term, B3(x) = f (f - 1/2) (f - 1) of f = x - floor(x), the
 * periodic Bernoulli polynomial; the end T is a switch to jerk 0). The
 * setpoints then have the stop's own velocities, v(j + 1) at tick j + 1,
 * from the one that ended the replaced motion on (v(0)): fed its velocity
 * at tick j, the step would hold v(0) for the takeover's tick, its
 * acceleration dropping to zero and back. *v gets v(j + 1). */
static kc_real stop_euler(const kc_scurve *s, int64_t j, kc_real dt, kc_real *v)
{
    kc_scurve_state u0, u, u1;
    kc_real b3 = KC_R(0.0);
    kc_scurve_eval(s, 0, &u0);
    kc_scurve_eval(s, j, &u);
    kc_scurve_eval(s, j + 1, &u1);
    for (int i = 0; i < s->n; i++) {
        kc_real t = i + 1 < s->n ? s->t_end[i] : s->T, x = t / dt;
        if (!(x < (kc_real)j))
            break;
        kc_real f = x - (kc_real)(int32_t)x; /* x < j <= 2^24: truncation is floor */
        b3 += ((i + 1 < s->n ? s->j[i + 1] : KC_R(0.0)) - s->j[i]) * f * (f - KC_R(0.5)) * (f - KC_R(1.0));
    }
    *v = u1.v;
    return u.p + dt / KC_R(2.0) * (u.v - u0.v) + dt * dt / KC_R(12.0) * (u.a - u0.a) + dt * dt * dt / KC_R(6.0) * b3;
}

/* The replaced joint move's or servo stream's jerk-limited stop at its
 * tick j (>= 0), on its line or joint by joint: as the IK step follows it
 * (stop_euler) its joints into o->q and the velocities fed forward from
 * there into o->qd; exact (a joint path superposed in joint space) its
 * (q, qd, qdd) at tick j. */
static void stop_joints(const kc_ctrl *c, int64_t j, int exact, kc_ctrl_seg_point *o)
{
    const kc_ctrl_blend *b = &c->blend;
    kc_scurve_state u = {KC_R(0.0), KC_R(0.0), KC_R(0.0), KC_R(0.0), 0};
    kc_real dt = c->cfg.dt;
    if (b->stop_drive == KC_DRIVE_SCURVE && exact)
        kc_scurve_eval(&b->stop.scurve, j, &u);
    else if (b->stop_drive == KC_DRIVE_SCURVE)
        u.p = stop_euler(&b->stop.scurve, j, dt, &u.v);
    for (int i = 0; i < c->chain->n_joints; i++) {
        if (b->stop_drive == KC_DRIVE_HALT && exact) {
            kc_scurve_eval(&b->plan.halt[i], j, &u);
            o->q[i] = u.p, o->qd[i] = u.v, o->qdd[i] = u.a;
        } else if (b->stop_drive == KC_DRIVE_HALT) {
            o->q[i] = stop_euler(&b->plan.halt[i], j, dt, &o->qd[i]);
        } else {
            const kc_ctrl_blend_joint *bj = &b->plan.joint;
            o->q[i] = bj->q0[i] + bj->dq[i] * u.p, o->qd[i] = bj->dq[i] * u.v, o->qdd[i] = bj->dq[i] * u.a;
        }
    }
}

/* Whether the replaced segment stops on its path (a line's or an arc's
 * own stop), not in joint space. */
static int stop_on_path(const kc_ctrl_blend *b)
{
    return b->stop_drive != KC_DRIVE_HALT && (b->kind == KC_GOAL_LINE || b->kind == KC_GOAL_ARC);
}

/* The replaced segment's stop at its tick j: a line's or an arc's point,
 * or a joint move's or servo stream's tool pose and twist J(q) qd
 * (stop_joints' q and qd). */
static void stop_point(const kc_ctrl *c, int64_t j, kc_ctrl_seg_point *o)
{
    const kc_ctrl_blend *b = &c->blend;
    j = j < 0 ? 0 : j;
    if (stop_on_path(b)) {
        kc_ctrl_interp_point(b->kind, &b->plan.line, &b->plan.arc, b->stop_drive, &b->stop.prof, &b->stop.scurve, j,
                             o);
        return;
    }
    kc_jacobian jac;
    stop_joints(c, j, 0, o);
    kc_fk_jacobian(c->chain, o->q, &jac, &o->pose);
    for (int r = 0; r < 6; r++) {
        o->twist[r] = KC_R(0.0);
        for (int i = 0; i < c->chain->n_joints; i++)
            o->twist[r] += jac.m[r][i] * o->qd[i];
    }
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

/* M's stop, G and their sum at one tick (x[0], x[1], x[2]): each one's
 * twist (0..5) and tool point (6..8). */
typedef struct blend_twists {
    kc_real x[3][9];
} blend_twists;

/* A point's twist and tool point into x. */
static void put_twist(const kc_ctrl_seg_point *p, kc_real *x)
{
    for (int i = 0; i < 6; i++)
        x[i] = p->twist[i];
    for (int i = 0; i < 3; i++)
        x[6 + i] = p->pose.t.v[i];
}

/* The twists at M's tick j with G started at t0; m and g are scratch. */
static void twists_at(const kc_ctrl *c, int64_t t0, int64_t j, kc_ctrl_seg_point *m, kc_ctrl_seg_point *g,
                      blend_twists *out)
{
    stop_point(c, j, m);
    kc_ctrl_seg_eval(c, j - t0, g);
    put_twist(m, out->x[0]);
    put_twist(g, out->x[1]);
    compose(&c->blend, m, g);
    put_twist(g, out->x[2]);
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

/* Of x[s][k..k+2] at ticks j, j - 1, j - 2 (w[0], w[1], w[2]): the norm
 * at tick j (order 0), of its change over the tick (1), or of the change
 * of that change (2). */
static kc_real diff3(const blend_twists *const w[3], int s, int k, int order)
{
    return comb3(&w[0]->x[s][k], (kc_real)-order, &w[order > 0]->x[s][k], KC_R(1.0),
                 order == 2 ? &w[2]->x[s][k] : NULL);
}

/* Whether the sum's diff3 of this order at k is within *bound times
 * dt^order (and e, plus extra), *bound raised first to what M or G alone
 * does there when that is more. */
static int keeps(const blend_twists *const w[3], int k, int order, kc_real *bound, kc_real dt, kc_real e,
                 kc_real extra)
{
    kc_real scale = order == 2 ? dt * dt : order == 1 ? dt : KC_R(1.0);
    kc_real b = kc_max(*bound, kc_max(diff3(w, 0, k, order), diff3(w, 1, k, order)) / scale);
    *bound = b;
    for (int i = 0; i < order; i++)
        b *= dt;
    return diff3(w, 2, k, order) <= b * e + extra;
}

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
        const blend_twists *t[3] = {&w[j % 3], &w[(j - 1) % 3], j >= 2 ? &w[(j - 2) % 3] : NULL};
        for (int k = 0; k < 6; k += 3) {
            kc_real vmax = k == 0 ? lim->v : lim->w, amax = k == 0 ? lim->a : lim->dw;
            kc_real jmax = k == 0 ? lim->j : lim->dj;
            if (!keeps(t, k, 0, &vmax, dt, e, KC_R(0.0)) || !keeps(t, k, 1, &amax, dt, e, KC_R(0.0)))
                return 0;
            /* The step, with the rounding of the two positions it is the
             * difference of (a few units of KC_REAL_EPS |p|). */
            if (k == 0 && !keeps(t, 6, 1, &vmax, dt, e, KC_R(4.0) * KC_REAL_EPS * norm3(&t[0]->x[2][6])))
                return 0;
            if (t[2] != NULL && !keeps(t, k, 2, &jmax, dt, e, KC_R(0.0)))
                return 0;
        }
    }
    return 1;
}

/* G's point o at its tick jg as the sum takes it: at rest until it starts
 * (jg <= 0: its qd and qdd 0, where a path's qdd at its tick 0 may be
 * that of its first phase). */
static void path_at_rest(int64_t jg, int n, kc_ctrl_seg_point *o)
{
    for (int i = 0; i < n && jg <= 0; i++)
        o->qd[i] = o->qdd[i] = KC_R(0.0);
}

/* Whether a joint path G started at t0, superposed in joint space on M's
 * stop (q = q_M + q_G - q_s), keeps on every stride-th tick j of the
 * overlap (t0 <= j <= T_s, M's ticks) every joint inside its position
 * limits, the change of its qd over the tick within qdd_max dt (the final
 * check's: the tick's mean qdd, which a jerk of qddd_max dt > qdd_max
 * takes well away from its qdd at the tick), and its qd, its qdd and the
 * change of qdd over the tick (tick 0 is the last setpoint, M's) within
 * the joint's limits, or within what M or G alone does there when that is
 * more (a parabolic blend's jump of qdd). */
static int admissible_joints(const kc_ctrl *c, int64_t t0, int64_t stride)
{
    const kc_ctrl_blend *b = &c->blend;
    kc_real dt = c->cfg.dt, e = KC_R(1.0) + c->cfg.limit_slack;
    kc_ctrl_seg_point m[2], g[2]; /* [0]: tick j - 1, [1]: tick j */
    for (int64_t j = t0 > 0 ? t0 : 1; j <= b->stop_ticks; j += stride) {
        for (int k = 0; k < 2; k++) {
            stop_joints(c, j - 1 + k, 1, &m[k]);
            kc_ctrl_seg_eval(c, j - 1 + k - t0, &g[k]);
            path_at_rest(j - 1 + k - t0, c->chain->n_joints, &g[k]);
        }
        for (int i = 0; i < c->chain->n_joints; i++) {
            const kc_joint_limits *l = &c->chain->joints[i].limits;
            kc_real q = m[1].q[i] + g[1].q[i] - b->q_rest[i], qd = m[1].qd[i] + g[1].qd[i];
            kc_real qdd = m[1].qdd[i] + g[1].qdd[i], qdd0 = m[0].qdd[i] + g[0].qdd[i];
            kc_real dqd = qd - (m[0].qd[i] + g[0].qd[i]);
            kc_real vb = kc_max(l->qd_max, kc_max(kc_fabs(m[1].qd[i]), kc_fabs(g[1].qd[i])));
            kc_real ab = kc_max(l->qdd_max, kc_max(kc_fabs(m[1].qdd[i]), kc_fabs(g[1].qdd[i])));
            kc_real jb = kc_max(l->qddd_max * dt, kc_max(kc_fabs(m[1].qdd[i] - m[0].qdd[i]),
                                                         kc_fabs(g[1].qdd[i] - g[0].qdd[i])));
            if (!(q >= l->q_min && q <= l->q_max && kc_fabs(qd) <= vb * e && kc_fabs(qdd) <= ab * e &&
                  kc_fabs(dqd) <= l->qdd_max * dt * e && kc_ctrl_jerk_within(qdd0, qdd, jb)))
                return 0;
        }
    }
    return 1;
}

/* admissible_joints for a joint path, else admissible. */
static int admits(const kc_ctrl *c, const blend_bounds *lim, int64_t t0, int64_t stride)
{
    return c->goal.kind == KC_GOAL_PATH ? admissible_joints(c, t0, stride) : admissible(c, lim, t0, stride);
}

/* The first admitted t0 in (lo, hi] (hi admitted, lo refused or -1) that
 * at most 20 bisection steps find. */
static KC_SIZE_NOINLINE int64_t bisect(const kc_ctrl *c, const blend_bounds *lim, int64_t lo, int64_t hi, int64_t stride)
{
    for (int i = 0; i < 20 && hi - lo > 1; i++) {
        int64_t mid = lo + (hi - lo) / 2;
        if (admits(c, lim, mid, stride))
            hi = mid;
        else
            lo = mid;
    }
    return hi;
}

/* The earliest admissible t0 the search finds (T_s when none before). */
static int64_t start_offset(const kc_ctrl *c, const blend_bounds *lim)
{
    int64_t ts = c->blend.stop_ticks, step = (ts + BLEND_GRID - 1) / BLEND_GRID;
    int64_t lo = -1, hi = ts; /* lo refused (or none), hi admitted */
    if (step < 1)
        return ts;
    for (int64_t t = 0; t < ts; t += step) {
        if (admits(c, lim, t, BLEND_STRIDE)) {
            hi = t;
            break;
        }
        lo = t;
    }
    hi = bisect(c, lim, lo, hi, BLEND_STRIDE);
    /* A sparse check can miss the ticks that refuse, fewer than
     * BLEND_STRIDE where the overlap refuses at its edge: checked on every
     * tick, a refused t0 gives way to a bisection (on every tick) up to
     * BLEND_STRIDE ticks later, then up to the next point of the grid. */
    for (int tries = 0; hi < ts && !admits(c, lim, hi, 1); tries++) {
        int64_t next = tries == 0 ? hi + BLEND_STRIDE : (hi / step + 1) * step;
        lo = hi;
        hi = bisect(c, lim, lo, next < ts ? next : ts, 1);
    }
    return hi;
}

/* a and b exchanged, n each. */
static void swap_reals(kc_real *a, kc_real *b, int n)
{
    for (int i = 0; i < n; i++) {
        kc_real t = a[i];
        a[i] = b[i];
        b[i] = t;
    }
}

/* Exchanges what a jerk-limited joint move's stop reads of its plan (its
 * line) between c->plan.joint and the record: keep_stop moves it in,
 * give_back_stop back (what G's planning left in c->plan is not read
 * again). */
static void swap_joint_line(kc_ctrl *c)
{
    kc_interp_joint *pj = &c->plan.joint;
    kc_ctrl_blend_joint *bj = &c->blend.plan.joint;
    int n = pj->n;
    kc_profile_kind kind = pj->kind;
    kc_interp_sync sync = pj->sync;
    swap_reals(pj->q0, bj->q0, c->chain->n_joints);
    swap_reals(pj->q1, bj->q1, c->chain->n_joints);
    swap_reals(pj->dq, bj->dq, c->chain->n_joints);
    swap_reals(&pj->u_vmax, &bj->u_vmax, 1);
    swap_reals(&pj->u_amax, &bj->u_amax, 1);
    swap_reals(&pj->u_jmax, &bj->u_jmax, 1);
    pj->n = bj->n, pj->kind = bj->kind, pj->sync = bj->sync;
    bj->n = n, bj->kind = kind, bj->sync = sync;
}

/* M's stops joint by joint into the record, stop_ticks their last
 * joint's. */
static void keep_halts(kc_ctrl *c, const kc_scurve *halt)
{
    kc_ctrl_blend *b = &c->blend;
    b->stop_drive = KC_DRIVE_HALT;
    b->stop_ticks = 0;
    for (int i = 0; i < c->chain->n_joints; i++)
        b->stop_ticks = halt[i].ticks > b->stop_ticks ? halt[i].ticks : b->stop_ticks;
    memcpy(b->plan.halt, halt, sizeof(kc_scurve) * (size_t)c->chain->n_joints);
}

/* Moves what M's stop reads out of c->plan into the record (G is planned
 * there), with its start tick: a line or an arc (small), a jerk-limited
 * joint move's line, or a joint move's or servo stream's stops joint by
 * joint (stop_ticks: its last joint's; a servo's from jstop_k0). Returns 0
 * for a stop that is no such plan (the goal waits for it). */
static int keep_stop(kc_ctrl *c)
{
    kc_ctrl_blend *b = &c->blend;
    b->kind = c->goal.kind;
    b->stop_drive = c->drive;
    b->stop_ticks = 0;
    b->k0 = c->goal.kind == KC_GOAL_SERVO ? c->jstop_k0 : c->k0;
    if (c->drive == KC_DRIVE_HALT) {
        keep_halts(c, c->plan.halt);
        return 1;
    }
    if (c->drive == KC_DRIVE_SCURVE) {
        b->stop.scurve = c->drive_scurve;
        b->stop_ticks = c->drive_scurve.ticks;
    } else if (c->drive == KC_DRIVE_PROFILE && b->kind != KC_GOAL_JOINT) {
        b->stop.prof = c->drive_prof;
        b->stop_ticks = c->drive_prof.ticks;
    } else {
        return 0;
    }
    if (b->kind == KC_GOAL_LINE) {
        b->plan.line = c->plan.line;
    } else if (b->kind == KC_GOAL_ARC) {
        b->plan.arc = c->plan.arc;
    } else {
        swap_joint_line(c);
    }
    return 1;
}

/* Puts M's stop back into c->plan (G not taken): what keep_stop moved. */
static void give_back_stop(kc_ctrl *c)
{
    const kc_ctrl_blend *b = &c->blend;
    int n = c->chain->n_joints;
    if (b->kind == KC_GOAL_LINE) {
        c->plan.line = b->plan.line;
    } else if (b->kind == KC_GOAL_ARC) {
        c->plan.arc = b->plan.arc;
    } else if (b->stop_drive == KC_DRIVE_HALT) {
        memcpy(c->plan.halt, b->plan.halt, sizeof(kc_scurve) * (size_t)n);
    } else {
        swap_joint_line(c);
    }
}

/* M stops joint by joint, from the last setpoint, its plan giving way to
 * G's: the halts (kc_ctrl_halt_plan; a Cartesian M's within its
 * Cartesian bounds lm) planned in the storage of a joint goal's retarget,
 * unused here, and moved into the record only once every joint's is
 * (the record may hold a superposition under way). 0 where they cannot
 * be planned: nothing changed, M goes on and G waits for its own stop. */
static int halt_stop(kc_ctrl *c, const kc_interp_limits *lm)
{
    kc_ctrl_blend *b = &c->blend;
    kc_scurve *halt = c->retarget_plan.sj;
    if (!kc_ctrl_halt_plan(c, halt, c->goal.kind == KC_GOAL_PATH ? NULL : lm))
        return 0;
    keep_halts(c, halt);
    b->kind = c->goal.kind;
    b->k0 = c->cycle - 1;
    c->state = KC_CTRL_STOPPING;
    c->stop_intent = INTENT_PREEMPT;
    return 1;
}

int kc_ctrl_blend_take(kc_ctrl *c, const kc_goal *g, kc_ctrl_output *out)
{
    kc_ctrl_blend *b = &c->blend;
    int in_joints = c->goal.kind == KC_GOAL_JOINT || c->goal.kind == KC_GOAL_SERVO;
    int stopping = c->state == KC_CTRL_STOPPING;
    /* A joint or Cartesian path (its plan is as large as G's), a line or
     * an arc under a joint path (superposed in joint space, M's stop must
     * be known there), a superposition (the sum of two plans, neither of
     * which alone stops it) and a motion already stopping (for a STOP, a
     * PAUSE, a goal waiting for it, the servo timeout) stop joint by joint
     * from the last setpoint (halt_stop). Not a stop in joint space by
     * jstop_prof (an e-stop's, a fault's: no goal is taken then). */
    int halts = b->on || stopping || kc_ctrl_is_path(c->goal.kind) ||
                (g->kind == KC_GOAL_PATH && (c->goal.kind == KC_GOAL_LINE || c->goal.kind == KC_GOAL_ARC));
    if (!c->active || (c->state != KC_CTRL_MOVING && !stopping) || c->jstop ||
        (g->kind != KC_GOAL_LINE && g->kind != KC_GOAL_ARC && !kc_ctrl_is_path(g->kind)))
        return 0;
    /* A path that the controller ramps (kc_ctrl_path_ramped: one that
     * moves at its ends, or whose acceleration steps there) is superposed
     * on its jerk-limited ramps, its own timing (ramp_on: a stop while
     * superposed waits on it too, ctrl_stop.c); at a constant rate its
     * tau'' steps at rest: it waits for the stop. */
    if (kc_ctrl_is_path(g->kind) && kc_ctrl_path_ramped(c, g) && !kc_ctrl_path_jerk_law(c, g))
        return 0;
    /* A trapezoid joint move's stop brakes at a joint's acceleration limit
     * from its first tick to its last: the IK step, adding its correction
     * to that, cannot follow it within the limit, and the tool would lag
     * its target. It stops first, in joint space. */
    if (c->goal.kind == KC_GOAL_JOINT && (c->drive == KC_DRIVE_RETARGET ||
                                          (c->drive != KC_DRIVE_HALT && c->plan.joint.kind != KC_PROFILE_JERK)))
        return 0; /* (a joint move stopping joint by joint is a jerk-limited one: plan.halt holds its stops) */
    /* A joint move, a servo stream or a joint path has no Cartesian limits
     * of its own: G's bound the sum (or what M's stop alone does, where
     * that is more; a servo stream's stop that cannot be planned
     * jerk-limited is no KC_DRIVE_HALT: keep_stop refuses it, the goal
     * waits for it). */
    kc_interp_limits lg = kc_ctrl_cart_limits(&c->cfg, g);
    kc_interp_limits lm = in_joints || c->goal.kind == KC_GOAL_PATH ? lg : kc_ctrl_cart_limits(&c->cfg, &c->goal);
    blend_bounds lim = {kc_max(lm.v, lg.v), kc_max(lm.a, lg.a), kc_max(lm.j, lg.j),
                        kc_max(lm.w, lg.w), kc_max(lm.dw, lg.dw), kc_max(lm.dj, lg.dj)};
    kc_real old_length = c->path_length;
    if (halts) {
        if (!halt_stop(c, &lm))
            return 0; /* M goes on; the goal waits for its stop on its path */
    } else {
        kc_ctrl_stop_on_path(c, INTENT_PREEMPT);
        if (!keep_stop(c))
            return 0; /* a stop that is not a profile: it goes on, the goal waits for it */
    }
    kc_ctrl_seg_point rest;
    kc_status st;
    if (g->kind == KC_GOAL_PATH) {
        /* In joint space, from where M's stop rests (q_s), at rest there. */
        stop_joints(c, b->stop_ticks, 1, &rest);
        memcpy(b->q_rest, rest.q, sizeof(kc_real) * (size_t)c->chain->n_joints);
        st = kc_ctrl_plan_path_from(c, g, b->q_rest);
    } else {
        stop_point(c, b->stop_ticks, &rest);
        b->rest = rest.pose;
        st = kc_ctrl_plan_cart_from(c, g, &b->rest);
    }
    if (st != KC_OK) {
        /* M goes on stopping; G waits for it (and is planned again then).
         * A stop joint by joint runs from plan.halt (kc_ctrl_halting), M's
         * own plan being gone. */
        if (halts) {
            memcpy(c->plan.halt, b->plan.halt, sizeof(kc_scurve) * (size_t)c->chain->n_joints);
            c->drive = KC_DRIVE_HALT;
            c->jstop_k0 = c->k0 = b->k0; /* (a joint move's is its drive: kc_ctrl_seg_eval) */
            b->on = 0;
        } else {
            give_back_stop(c);
        }
        c->path_length = old_length;
        return 0;
    }
    int64_t old_id = c->goal.id;
    kc_ctrl_goal_copy(&c->goal, g);
    c->drive = KC_DRIVE_NOMINAL;
    c->ramp_on = 0;
    if (kc_ctrl_is_path(g->kind) && kc_ctrl_path_ramped(c, g))
        kc_ctrl_path_plan_ramp(c, 1); /* (the dry run judges its limits with the sum) */
    c->stop_intent = KC_CMD_NONE;
    c->settle = 0;
    c->state = KC_CTRL_MOVING;
    b->on = 1;
    b->lax = 1;
    b->err = INF;
    c->k0 = b->k0 + start_offset(c, &lim);
    kc_ctrl_emit_takeover(out, g->id, old_id);
    return 1;
}

void kc_ctrl_blend_joints(const kc_ctrl *c, int64_t k, kc_ctrl_seg_point *o)
{
    const kc_ctrl_blend *b = &c->blend;
    int64_t j = k - b->k0;
    path_at_rest(k - c->k0, c->chain->n_joints, o);
    if (!b->on || j >= b->stop_ticks)
        return;
    /* q = q_M + q_G - q_s, and so for qd, qdd. */
    kc_ctrl_seg_point m;
    stop_joints(c, j, 1, &m);
    for (int i = 0; i < c->chain->n_joints; i++) {
        o->q[i] += m.q[i] - b->q_rest[i];
        o->qd[i] += m.qd[i];
        o->qdd[i] += m.qdd[i];
    }
}

int kc_ctrl_blend_apply(kc_ctrl *c, int64_t k, kc_ctrl_seg_point *o, kc_real *qd_m)
{
    kc_ctrl_blend *b = &c->blend;
    int64_t j = k - b->k0;
    if (c->goal.kind == KC_GOAL_PATH) {
        kc_ctrl_blend_joints(c, k, o);
        b->on = j < b->stop_ticks; /* M rests at q_s: the sum is G alone from here */
        return 0;
    }
    b->on = j < b->stop_ticks; /* M rests at P_s: the sum is G alone from there */
    return kc_ctrl_blend_point(c, k, o, qd_m);
}

int kc_ctrl_blend_point(const kc_ctrl *c, int64_t k, kc_ctrl_seg_point *o, kc_real *qd_m)
{
    const kc_ctrl_blend *b = &c->blend;
    int64_t j = k - b->k0;
    if (j >= b->stop_ticks)
        return 0;
    kc_ctrl_seg_point m;
    stop_point(c, j, &m);
    compose(b, &m, o);
    if (qd_m == NULL || stop_on_path(b))
        return 0;
    memcpy(qd_m, m.qd, sizeof(kc_real) * (size_t)c->chain->n_joints);
    return 1;
}
