/* SPDX-License-Identifier: BSD-3-Clause */
/* interp.c - joint move (seed 001 lab 4), straight line with the
 * two-rotations method or slerp (lab 5) and arc through three points
 * (lab 6). The formulas and the seed's typos are in kinctl/interp.h. */
#include "kinctl/interp.h"

#include "interp_internal.h"
#include "scurve_internal.h"
#include "size_internal.h"

#include <stddef.h>
#include <string.h>

#define INF ((kc_real)INFINITY)

/* Limits of u for a quantity moving by D with limits (vmax, amax): the
 * running minimum of vmax / D and amax / D. D = 0 imposes nothing; the
 * quotients may overflow to infinity for a tiny D, which is right. */
static void bound_u(kc_real D, kc_real vmax, kc_real amax, kc_real *V, kc_real *A)
{
    if (D > KC_R(0.0)) {
        *V = kc_min(*V, vmax / D);
        *A = kc_min(*A, amax / D);
    }
}

/* The profile of u from 0 to 1 with limits V and A; a zero motion (nothing
 * bounds A, i.e. nothing moves by a representable amount) takes 0 ticks. */
static KC_SIZE_NOINLINE kc_status plan_u(kc_profile *prof, kc_real V, kc_real A, kc_real duration, kc_real dt)
{
    kc_real u0 = KC_R(0.0);
    if (!kc_isfinite(A)) { /* already there: u = 1 throughout */
        u0 = KC_R(1.0);
        V = INF;
        A = KC_R(1.0);
    }
    return duration > KC_R(0.0) ? kc_profile_plan_duration(prof, u0, KC_R(1.0), V, A, duration, dt)
                                : kc_profile_plan(prof, u0, KC_R(0.0), KC_R(1.0), V, A, dt);
}

/* ---- joint move ---- */

/* Time-optimal rest-to-rest time over D with (v, a). */
static kc_real move_time(kc_real D, kc_real v, kc_real a)
{
    if (D * a >= v * v) /* trapezoid (4.6-4.9): T = D / v + v / a */
        return D / v + v / a;
    return KC_R(2.0) * kc_sqrt(D / a); /* triangle */
}

/* The bytes of a plan of n joints: all but the profiles sj[n..], which
 * nothing reads (a plan is 7.5 KB for the 16 joints it has room for, and
 * clearing and copying it all would cost a planning as much as stretching
 * two joints). */
static size_t plan_size(int n) { return offsetof(kc_interp_joint, sj) + (size_t)n * sizeof(kc_scurve); }

/* What every joint move starts from, into *out (scratch on error): the
 * arguments checked, *out cleared (but for its profiles sj[n..], and all
 * of sj unless clear_sj: a planner that writes every sj[i] itself), q0, q1,
 * dq, the joints that set V and A (lead_vel, lead_acc) and the bounds of u
 * (u_vmax, u_amax); no leading joint yet (lead = -1). The planners below
 * fill their own plan with it instead of copying one more (a plan holds a
 * jerk-limited profile a joint: its copies are the planning's stack). */
static kc_status plan_common(kc_interp_joint *out, int n, const kc_real *q0, const kc_real *q1, const kc_real *qd_max,
                             const kc_real *qdd_max, kc_real duration, kc_real dt, int clear_sj)
{
    kc_real V = INF, A = INF, best_v = KC_R(0.0), best_a = KC_R(0.0);
    if (q0 == NULL || q1 == NULL || qd_max == NULL || qdd_max == NULL || n < 1)
        return KC_E_ARG;
    if (n > KC_MAX_JOINTS)
        return KC_E_CAPACITY;
    if (!kc_isfinite(duration) || duration < KC_R(0.0) || !(dt > KC_R(0.0)) || !kc_isfinite(dt))
        return KC_E_ARG;
    memset(out, 0, clear_sj ? plan_size(n) : offsetof(kc_interp_joint, sj));
    out->n = n;
    out->lead = out->lead_vel = out->lead_acc = -1;
    for (int i = 0; i < n; i++) {
        if (!kc_isfinite(q0[i]) || !kc_isfinite(q1[i]) || !(qd_max[i] > KC_R(0.0)) || !(qdd_max[i] > KC_R(0.0)) ||
            !kc_isfinite(qdd_max[i]))
            return KC_E_ARG;
        out->q0[i] = q0[i];
        out->q1[i] = q1[i];
        out->dq[i] = q1[i] - q0[i];
        kc_real D = kc_fabs(out->dq[i]);
        if (!kc_isfinite(D))
            return KC_E_ARG;
        if (D == KC_R(0.0))
            continue;
        /* Strict comparisons: ties go to the lowest index, as in (4.2). */
        if (D / qd_max[i] > best_v) {
            best_v = D / qd_max[i];
            out->lead_vel = i;
        }
        if (D / qdd_max[i] > best_a) {
            best_a = D / qdd_max[i];
            out->lead_acc = i;
        }
        bound_u(D, qd_max[i], qdd_max[i], &V, &A);
    }
    out->u_vmax = V;
    out->u_amax = A;
    return KC_OK;
}

/* kc_interp_joint_plan into *out, which is scratch on error: plan_common,
 * the leading joint (4.2) and the trapezoid of u. */
static kc_status plan_trap(kc_interp_joint *out, int n, const kc_real *q0, const kc_real *q1, const kc_real *qd_max,
                           const kc_real *qdd_max, kc_real duration, kc_real dt)
{
    kc_real T_lead = KC_R(-1.0);
    kc_status st = plan_common(out, n, q0, q1, qd_max, qdd_max, duration, dt, 1);
    if (st != KC_OK)
        return st;
    for (int i = 0; i < n; i++) {
        kc_real D = kc_fabs(out->dq[i]);
        if (D == KC_R(0.0))
            continue;
        /* Strict comparison: ties go to the lowest index, as in (4.2). */
        kc_real Ti = move_time(D, qd_max[i], qdd_max[i]);
        if (Ti > T_lead) {
            T_lead = Ti;
            out->lead = i;
        }
    }
    st = plan_u(&out->prof, out->u_vmax, out->u_amax, duration, dt);
    if (st != KC_OK)
        return st;
    out->kind = KC_PROFILE_TRAPEZOID;
    out->T = out->prof.T;
    out->ticks = out->prof.ticks;
    return KC_OK;
}

kc_status kc_interp_joint_plan(kc_interp_joint *plan, int n, const kc_real *q0, const kc_real *q1,
                               const kc_real *qd_max, const kc_real *qdd_max, kc_real duration, kc_real dt)
{
    kc_interp_joint r;
    if (plan == NULL)
        return KC_E_ARG;
    kc_status st = plan_trap(&r, n, q0, q1, qd_max, qdd_max, duration, dt);
    if (st == KC_OK)
        memcpy(plan, &r, plan_size(r.n));
    return st;
}

kc_interp_joint_cfg kc_interp_joint_cfg_default(void)
{
    kc_interp_joint_cfg c;
    memset(&c, 0, sizeof c);
    for (int i = 0; i < KC_MAX_JOINTS; i++)
        c.qd_max[i] = INF;
    c.profile = KC_PROFILE_TRAPEZOID;
    return c;
}

/* The jerk-limited move (kinctl/interp.h, kc_interp_joint_plan_cfg). */
static kc_status plan_jerk(kc_interp_joint *out, const kc_interp_joint_cfg *c)
{
    kc_real J = INF, T = KC_R(0.0);
    kc_status st;
    /* The limits, the start and the leading joints as the trapezoid has
     * them (u_vmax, u_amax, lead_vel, lead_acc): u's bounds V and A; the
     * rest of the plan cleared (prof stays so), no leading joint yet. */
    st = plan_common(out, c->n, c->q0, c->q1, c->qd_max, c->qdd_max, KC_R(0.0), c->dt, 1);
    if (st != KC_OK)
        return st;
    out->kind = KC_PROFILE_JERK;
    for (int i = 0; i < c->n; i++) {
        kc_real D = kc_fabs(out->dq[i]);
        if (D == KC_R(0.0))
            continue;
        if (!(c->qddd_max[i] > KC_R(0.0)) || !kc_isfinite(c->qddd_max[i]))
            return KC_E_ARG;
        st = kc_scurve_plan(&out->sj[i], out->q0[i], KC_R(0.0), KC_R(0.0), out->q1[i], c->qd_max[i], c->qdd_max[i],
                            c->qddd_max[i], c->dt);
        if (st != KC_OK)
            return st;
        /* Strict comparison: ties go to the lowest index, as in (4.2). */
        if (out->sj[i].T > T) {
            T = out->sj[i].T;
            out->lead = i;
        }
        J = kc_min(J, c->qddd_max[i] / D);
    }
    if (c->duration > KC_R(0.0)) {
        if (c->duration < T * (KC_R(1.0) - KC_R(8.0) * KC_REAL_EPS))
            return KC_E_LIMIT;
        T = kc_max(T, c->duration);
    }
    kc_real V = out->u_vmax, A = out->u_amax;
    out->u_jmax = J;
    out->T = T;
    out->sync = KC_INTERP_SYNC_PHASE;
    /* Phase: the straight line, if it is as fast, stretched to T in place;
     * when nothing moves (by a representable amount), u stays at 1 for T. */
    kc_real u0 = KC_R(0.0);
    if (out->lead < 0 || !kc_isfinite(J)) {
        u0 = KC_R(1.0);
        V = INF;
        A = J = KC_R(1.0);
    }
    st = kc_scurve_plan(&out->su, u0, KC_R(0.0), KC_R(0.0), KC_R(1.0), V, A, J, c->dt);
    if (st != KC_OK)
        return st;
    if (out->su.T <= T * (KC_R(1.0) + KC_R(8.0) * KC_REAL_EPS)) {
        if (T > out->su.T) {
            st = kc_scurve_stretch(&out->su, &out->su, V, A, J, T);
            if (st != KC_OK)
                return st;
        }
        out->T = out->su.T;
        out->ticks = out->su.ticks;
        return KC_OK;
    }
    /* Time: every moving joint stretched to T. */
    out->sync = KC_INTERP_SYNC_TIME;
    memset(&out->su, 0, sizeof out->su);
    for (int i = 0; i < c->n; i++) {
        /* A joint that does not move waits at q0 (its jerk limit unused). */
        kc_real jl = out->dq[i] == KC_R(0.0) ? KC_R(1.0) : c->qddd_max[i];
        st = kc_scurve_plan_duration(&out->sj[i], out->q0[i], out->q1[i], c->qd_max[i], c->qdd_max[i], jl, T, c->dt);
        if (st != KC_OK)
            return st;
    }
    out->ticks = out->sj[out->lead].ticks;
    return KC_OK;
}

/* Joint i's time-optimal plan from its moving start, its duration alone
 * (kc_scurve_plan_time), into out->sj[i]; jl[i] its jerk limit. */
static KC_SIZE_NOINLINE kc_status joint_optimum(kc_interp_joint *out, const kc_interp_joint_cfg *c, const kc_real *jl,
                                                int i)
{
    return kc_scurve_plan_time(&out->sj[i], out->q0[i], c->qd0[i], c->qdd0[i], out->q1[i], c->qd_max[i], c->qdd_max[i],
                               jl[i], c->dt);
}

/* Joint i's optimum out->sj[i] stretched to T, into *dst (which may be
 * out->sj[i]). */
static KC_SIZE_NOINLINE kc_status joint_stretch(kc_scurve *dst, const kc_interp_joint *out,
                                                const kc_interp_joint_cfg *c, const kc_real *jl, int i, kc_real T)
{
    return kc_scurve_stretch(dst, &out->sj[i], c->qd_max[i], c->qdd_max[i], jl[i], T);
}

/* Whether every joint's optimum in out->sj stretches to T: KC_OK,
 * KC_E_LIMIT when one refuses (kinctl/scurve.h: only a rest after an
 * optimum of seven phases), or another error. */
static kc_status stretches_all(const kc_interp_joint *out, const kc_interp_joint_cfg *c, const kc_real *jl, kc_real T,
                               kc_scurve *tmp)
{
    for (int i = 0; i < c->n; i++) {
        kc_status st = joint_stretch(tmp, out, c, jl, i, T);
        if (st != KC_OK)
            return st;
    }
    return KC_OK;
}

/* Every joint's optimum in out->sj replaced by its stretch to T, in
 * place: the plan needs each stretch once. When one refuses
 * (KC_E_LIMIT), the optima of the joints already stretched are
 * planned again, so that out->sj holds every optimum as before. */
static kc_status stretch_in_place(kc_interp_joint *out, const kc_interp_joint_cfg *c, const kc_real *jl, kc_real T)
{
    for (int i = 0; i < c->n; i++) {
        kc_status st = joint_stretch(&out->sj[i], out, c, jl, i, T);
        if (st == KC_OK)
            continue;
        for (int k = 0; k < i && st == KC_E_LIMIT; k++) {
            kc_status sk = joint_optimum(out, c, jl, k);
            if (sk != KC_OK)
                return sk;
        }
        return st;
    }
    return KC_OK;
}

/* Some joint's stretch to T is refused (kinctl/scurve.h: a rest needed
 * after an optimum of seven phases; not seen in random tests): the
 * shortest duration past it, found by growing T by 2^m / 1024 of itself
 * until every joint stretches, then halving the step between the last
 * refused and the first planned duration ten times. The optima stay in out->sj while searching
 * (one profile of scratch); then each is replaced by its stretch. */
static KC_SIZE_NOINLINE kc_status stretch_past_blocked(kc_interp_joint *out, const kc_interp_joint_cfg *c,
                                                      const kc_real *jl, kc_real T)
{
    kc_scurve tmp;
    kc_real lo = T, hi = T + T * (KC_R(1.0) / KC_R(1024.0)), grow = KC_R(2.0) / KC_R(1024.0);
    kc_status st;
    for (int m = 1;; m++) {
        st = stretches_all(out, c, jl, hi, &tmp);
        if (st == KC_OK)
            break;
        if (st != KC_E_LIMIT || m == 15)
            return st;
        lo = hi;
        hi += hi * grow;
        grow *= KC_R(2.0);
    }
    for (int i = 0; i < 10; i++) {
        kc_real mid = lo + KC_R(0.5) * (hi - lo);
        st = stretches_all(out, c, jl, mid, &tmp);
        if (st == KC_OK)
            hi = mid;
        else if (st == KC_E_LIMIT)
            lo = mid;
        else
            return st;
    }
    return stretch_in_place(out, c, jl, hi);
}

/* A start moving along the line to the target: qd0 = lv dq and
 * qdd0 = la dq for every joint, within the rounding of dq = q1 - q0 (a
 * replacing goal with the target of a move synchronised by phase). Sets
 * *lv, *la from the joint that moves farthest. */
static int start_on_line(const kc_interp_joint *r, const kc_interp_joint_cfg *c, kc_real *lv, kc_real *la)
{
    int m = -1;
    for (int i = 0; i < c->n; i++)
        if (r->dq[i] != KC_R(0.0) && (m < 0 || kc_fabs(r->dq[i]) > kc_fabs(r->dq[m])))
            m = i;
    if (m < 0)
        return 0;
    *lv = c->qd0[m] / r->dq[m];
    *la = c->qdd0[m] / r->dq[m];
    for (int i = 0; i < c->n; i++) {
        kc_real round = KC_R(64.0) * KC_REAL_EPS * (kc_fabs(r->dq[i]) + kc_fabs(r->q0[i]) + kc_fabs(r->q1[i]));
        if (kc_fabs(c->qd0[i] - *lv * r->dq[i]) > KC_R(64.0) * KC_REAL_EPS * kc_fabs(c->qd0[i]) + kc_fabs(*lv) * round ||
            kc_fabs(c->qdd0[i] - *la * r->dq[i]) > KC_R(64.0) * KC_REAL_EPS * kc_fabs(c->qdd0[i]) + kc_fabs(*la) * round)
            return 0;
    }
    return 1;
}

/* A moving start on the line to the target (start_on_line) may stay on
 * it: one profile of u from (0, lv, la) to rest at 1 within the move's
 * bounds on the first three derivatives of u (synchronisation by phase
 * from a moving start). Taken instead of the time-synchronised plan in
 * *out when it is faster: when a replacing goal keeps the target of a
 * move that was on its line, the rest of that move is such a profile,
 * while a joint's stretch may be refused (kinctl/scurve.h) and wait
 * longer. Without a requested duration only. */
static void line_from_moving(kc_interp_joint *out, const kc_interp_joint_cfg *c)
{
    kc_real lv, la;
    kc_scurve su;
    if (c->duration > KC_R(0.0) || !kc_isfinite(out->u_jmax) || !start_on_line(out, c, &lv, &la))
        return;
    if (kc_scurve_plan(&su, KC_R(0.0), lv, la, KC_R(1.0), out->u_vmax, out->u_amax, out->u_jmax, c->dt) != KC_OK ||
        !(su.T < out->T * (KC_R(1.0) - KC_R(64.0) * KC_REAL_EPS)))
        return;
    out->sync = KC_INTERP_SYNC_PHASE;
    out->su = su;
    out->T = su.T;
    out->ticks = su.ticks;
}

/* The jerk-limited move from a moving start: time synchronisation
 * (kinctl/interp.h). */
static kc_status plan_jerk_moving(kc_interp_joint *out, const kc_interp_joint_cfg *c)
{
    kc_real T = KC_R(0.0);
    /* Every sj[i] is planned below; prof and su stay cleared, no leading
     * joint yet. */
    kc_status st = plan_common(out, c->n, c->q0, c->q1, c->qd_max, c->qdd_max, KC_R(0.0), c->dt, 0);
    if (st != KC_OK)
        return st;
    out->kind = KC_PROFILE_JERK;
    out->sync = KC_INTERP_SYNC_TIME;
    out->u_jmax = INF;
    /* Each joint's optimum into out->sj[i], its duration without its
     * phases (kc_scurve_plan_time: the slowest joint's are laid out when
     * it is stretched to its own duration, the others' never are); a joint
     * at rest on its target: a zero-length plan, stretched into a wait. */
    kc_real jl[KC_MAX_JOINTS];
    for (int i = 0; i < c->n; i++) {
        int still = out->dq[i] == KC_R(0.0) && c->qd0[i] == KC_R(0.0) && c->qdd0[i] == KC_R(0.0);
        if (!still && (!(c->qddd_max[i] > KC_R(0.0)) || !kc_isfinite(c->qddd_max[i])))
            return KC_E_ARG;
        jl[i] = still ? KC_R(1.0) : c->qddd_max[i];
        st = joint_optimum(out, c, jl, i);
        if (st != KC_OK)
            return st;
        if (out->sj[i].T > T) {
            T = out->sj[i].T;
            out->lead = i;
        }
        if (out->dq[i] != KC_R(0.0))
            out->u_jmax = kc_min(out->u_jmax, c->qddd_max[i] / kc_fabs(out->dq[i]));
    }
    if (c->duration > KC_R(0.0)) {
        if (c->duration < T * (KC_R(1.0) - KC_R(8.0) * KC_REAL_EPS))
            return KC_E_LIMIT;
        T = kc_max(T, c->duration);
    }
    /* The shortest T every joint can be stretched to: T itself (each
     * joint stretched once, in place), or past a refused stretch. */
    st = stretch_in_place(out, c, jl, T);
    if (st == KC_E_LIMIT)
        st = stretch_past_blocked(out, c, jl, T);
    if (st != KC_OK)
        return st;
    out->T = out->sj[out->lead].T;
    out->ticks = out->sj[out->lead].ticks;
    line_from_moving(out, c);
    return KC_OK;
}

kc_status kc_interp_joint_plan_cfg_into(kc_interp_joint *out, const kc_interp_joint_cfg *cfg)
{
    if (out == NULL || cfg == NULL)
        return KC_E_ARG;
    if (cfg->n > KC_MAX_JOINTS)
        return KC_E_CAPACITY;
    int moving = 0;
    for (int i = 0; i < cfg->n; i++) {
        if (!kc_isfinite(cfg->qd0[i]) || !kc_isfinite(cfg->qdd0[i]))
            return KC_E_ARG;
        moving |= cfg->qd0[i] != KC_R(0.0) || cfg->qdd0[i] != KC_R(0.0);
    }
    if (cfg->profile == KC_PROFILE_TRAPEZOID)
        return moving ? KC_E_ARG
                      : plan_trap(out, cfg->n, cfg->q0, cfg->q1, cfg->qd_max, cfg->qdd_max, cfg->duration,
                                             cfg->dt);
    if (cfg->profile != KC_PROFILE_JERK)
        return KC_E_ARG;
    if (!kc_isfinite(cfg->duration) || cfg->duration < KC_R(0.0))
        return KC_E_ARG;
    return moving ? plan_jerk_moving(out, cfg) : plan_jerk(out, cfg);
}

kc_status kc_interp_joint_plan_cfg(kc_interp_joint *plan, const kc_interp_joint_cfg *cfg)
{
    kc_interp_joint r;
    if (plan == NULL)
        return KC_E_ARG;
    kc_status st = kc_interp_joint_plan_cfg_into(&r, cfg);
    if (st == KC_OK)
        memcpy(plan, &r, plan_size(r.n));
    return st;
}

/* The joint move's state for one state of its u profile (st: KC_OK or
 * KC_DONE from the profile). */
static kc_status joint_at(const kc_interp_joint *plan, kc_status st, const kc_profile_state *u,
                          kc_interp_joint_state *out)
{
    int n = plan->n;
    if (st == KC_DONE) {
        for (int i = 0; i < n; i++) {
            out->q[i] = plan->q1[i];
            out->qd[i] = KC_R(0.0);
            out->qdd[i] = KC_R(0.0);
            out->qddd[i] = KC_R(0.0);
        }
    } else {
        for (int i = 0; i < n; i++) {
            kc_real d = plan->dq[i];
            out->q[i] = plan->q0[i] + d * u->p;
            out->qd[i] = d * u->v;
            out->qdd[i] = d * u->a;
            out->qddd[i] = KC_R(0.0);
        }
    }
    out->u = u->p;
    out->ud = u->v;
    out->udd = u->a;
    out->phase = u->phase;
    return st;
}

/* The state of a profile of u at tick k, and whether the geometry is at its
 * exact end: the profile has finished at u = 1 (a segment's own profile
 * always does; a stop profile ends where it ends). */
static kc_status u_state(const kc_profile *prof, int64_t k, kc_profile_state *u, kc_status *end)
{
    kc_status st = kc_profile_eval(prof, k, u);
    *end = st == KC_DONE && u->p >= KC_R(1.0) ? KC_DONE : KC_OK;
    return st;
}

/* The joints at u (a profile of the path parameter along q0 -> q1), or
 * exactly at q1 at the end. */
static void along_line(const kc_interp_joint *plan, const kc_scurve_state *u, int end, kc_interp_joint_state *out)
{
    for (int i = 0; i < plan->n; i++) {
        kc_real d = plan->dq[i];
        out->q[i] = end ? plan->q1[i] : plan->q0[i] + d * u->p;
        out->qd[i] = d * u->v;
        out->qdd[i] = d * u->a;
        out->qddd[i] = d * u->j;
    }
    out->u = u->p;
    out->ud = u->v;
    out->udd = u->a;
    out->phase = u->phase;
}

/* A jerk-limited move at tick k >= 0. */
static kc_status joint_jerk_at(const kc_interp_joint *plan, int64_t k, kc_interp_joint_state *out)
{
    int n = plan->n;
    kc_scurve_state u;
    if (k >= plan->ticks) {
        for (int i = 0; i < n; i++) {
            out->q[i] = plan->q1[i];
            out->qd[i] = out->qdd[i] = out->qddd[i] = KC_R(0.0);
        }
        out->u = KC_R(1.0);
        out->ud = out->udd = KC_R(0.0);
        out->phase = 4;
        return KC_DONE;
    }
    if (plan->sync == KC_INTERP_SYNC_PHASE) {
        kc_scurve_eval(&plan->su, k, &u);
        along_line(plan, &u, 0, out);
        return KC_OK;
    }
    for (int i = 0; i < n; i++) {
        kc_scurve_eval(&plan->sj[i], k, &u);
        out->q[i] = u.p;
        out->qd[i] = u.v;
        out->qdd[i] = u.a;
        out->qddd[i] = u.j;
        if (i == plan->lead) {
            /* The leading joint's fraction; time itself when it returns
             * to where it started. */
            kc_real d = plan->dq[i];
            int back = d == KC_R(0.0);
            out->u = back ? (kc_real)k * plan->sj[i].dt / plan->T : (u.p - plan->q0[i]) / d;
            out->ud = back ? KC_R(0.0) : u.v / d;
            out->udd = back ? KC_R(0.0) : u.a / d;
            out->phase = u.phase;
        }
    }
    return KC_OK;
}

kc_status kc_interp_joint_eval(const kc_interp_joint *plan, int64_t k, kc_interp_joint_state *out)
{
    if (plan == NULL || out == NULL || k < 0)
        return KC_E_ARG;
    if (plan->kind == KC_PROFILE_JERK)
        return joint_jerk_at(plan, k, out);
    return kc_interp_joint_eval_profile(plan, &plan->prof, k, out);
}

kc_status kc_interp_joint_eval_profile(const kc_interp_joint *plan, const kc_profile *prof, int64_t k,
                                       kc_interp_joint_state *out)
{
    kc_profile_state u;
    kc_status end;
    if (plan == NULL || prof == NULL || out == NULL)
        return KC_E_ARG;
    kc_status st = u_state(prof, k, &u, &end);
    if (st >= 0)
        joint_at(plan, end, &u, out);
    return st;
}

kc_status kc_interp_joint_eval_scurve(const kc_interp_joint *plan, const kc_scurve *prof, int64_t k,
                                      kc_interp_joint_state *out)
{
    kc_scurve_state u;
    if (plan == NULL || prof == NULL || out == NULL)
        return KC_E_ARG;
    kc_status st = kc_scurve_eval(prof, k, &u);
    if (st < 0)
        return st;
    /* Ended at u = 1, or past it by the rounding of the profile's end:
     * exactly q1. (A stop may end further past it, kinctl/ctrl.h: it
     * rests there.) */
    along_line(plan, &u, st == KC_DONE && u.p >= KC_R(1.0) && u.p <= KC_R(1.0) + KC_R(4.0) * KC_REAL_EPS, out);
    return st;
}

/* ---- Cartesian helpers ---- */

kc_interp_limits kc_interp_limits_default(void)
{
    kc_interp_limits l = {KC_R(0.0), KC_R(0.0), INF, INF, INF, INF};
    return l;
}

static int limits_ok(const kc_interp_limits *l)
{
    return l->v > KC_R(0.0) && l->a > KC_R(0.0) && kc_isfinite(l->a) && l->w > KC_R(0.0) && l->dw > KC_R(0.0) &&
           l->j > KC_R(0.0) && l->dj > KC_R(0.0);
}

/* The speed law of a Cartesian segment whose tool point moves by S and
 * turns by Theta (kinctl/interp.h, the line's "Speed law"): u's bounds
 * *u_vmax, *u_amax, *u_jmax on its first three derivatives, then the
 * trapezoid into *prof or, with a finite bound on u''', the jerk-limited
 * profile into *su; *kind, *T and *ticks say which and how long. */
static kc_status plan_cart_u(kc_real S, kc_real Theta, const kc_interp_limits *lim, kc_real dt, kc_real *u_vmax,
                             kc_real *u_amax, kc_real *u_jmax, kc_profile_kind *kind, kc_profile *prof, kc_scurve *su,
                             kc_real *T, int64_t *ticks)
{
    kc_real V = INF, A = INF, J = INF, unused = INF;
    bound_u(S, lim->v, lim->a, &V, &A);
    bound_u(Theta, lim->w, lim->dw, &V, &A);
    bound_u(S, lim->j, INF, &J, &unused);
    bound_u(Theta, lim->dj, INF, &J, &unused);
    *u_vmax = V;
    *u_amax = A;
    *u_jmax = J;
    kc_status st;
    if (kc_isfinite(J) && kc_isfinite(A)) {
        *kind = KC_PROFILE_JERK;
        st = kc_scurve_plan(su, KC_R(0.0), KC_R(0.0), KC_R(0.0), KC_R(1.0), V, A, J, dt);
        *T = su->T;
        *ticks = su->ticks;
    } else {
        *kind = KC_PROFILE_TRAPEZOID;
        st = plan_u(prof, V, A, KC_R(0.0), dt);
        *T = prof->T;
        *ticks = prof->ticks;
    }
    return st;
}

static int pose_ok(const kc_pose *p)
{
    return kc_pose_isfinite(p) && kc_mat3_rotation_error(&p->R) <= KC_TOL_ORTHONORMAL;
}

static int dt_ok(kc_real dt) { return dt > KC_R(0.0) && kc_isfinite(dt); }

static kc_quat quat_neg(const kc_quat *q)
{
    kc_quat r = {-q->w, -q->x, -q->y, -q->z};
    return r;
}

static kc_real quat_dot(const kc_quat *a, const kc_quat *b)
{
    return a->w * b->w + a->x * b->x + a->y * b->y + a->z * b->z;
}

/* The end orientation q_end with the sign of the path's own end q_path, so
 * that the last tick continues the sequence instead of flipping it. */
static kc_quat match_sign(const kc_quat *q_end, const kc_quat *q_path)
{
    return quat_dot(q_end, q_path) < KC_R(0.0) ? quat_neg(q_end) : *q_end;
}

static KC_SIZE_NOINLINE void state_done(kc_interp_cart_state *out, const kc_vec3 *p, const kc_quat *q, kc_real s)
{
    out->p = *p;
    out->q = *q;
    out->v = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    out->w = out->v;
    out->s = s;
    out->sd = KC_R(0.0);
    out->sdd = KC_R(0.0);
    out->u = KC_R(1.0);
    out->phase = 4;
}

/* The speed law's part of a Cartesian state: u's state scaled by the law's
 * own length D (path length, or the angle when there is no path). */
static void state_law(kc_interp_cart_state *out, kc_real D, const kc_profile_state *u)
{
    out->s = D * u->p;
    out->sd = D * u->v;
    out->sdd = D * u->a;
    out->u = u->p;
    out->phase = u->phase;
}

/* A Cartesian plan's state for one state of a u profile (line_at, arc_at). */
typedef kc_status (*cart_at_fn)(const void *plan, kc_status st, const kc_profile_state *u,
                                kc_interp_cart_state *out);

/* A Cartesian plan at tick k of the jerk-limited u profile prof, drawn by
 * at (which takes u, u' and u'': the geometry needs no more). */
static kc_status cart_eval_scurve(const void *plan, const kc_scurve *prof, int64_t k, cart_at_fn at,
                                  kc_interp_cart_state *out)
{
    kc_scurve_state s;
    if (plan == NULL || prof == NULL || out == NULL)
        return KC_E_ARG;
    kc_status st = kc_scurve_eval(prof, k, &s);
    if (st >= 0) {
        kc_profile_state u = {s.p, s.v, s.a, s.phase};
        at(plan, st == KC_DONE && s.p >= KC_R(1.0) ? KC_DONE : KC_OK, &u, out);
    }
    return st;
}

/* A Cartesian plan at tick k of the u profile prof, drawn by at. */
static kc_status cart_eval(const void *plan, const kc_profile *prof, int64_t k, cart_at_fn at,
                           kc_interp_cart_state *out)
{
    kc_profile_state u;
    kc_status end;
    if (plan == NULL || prof == NULL || out == NULL)
        return KC_E_ARG;
    kc_status st = u_state(prof, k, &u, &end);
    if (st >= 0)
        at(plan, end, &u, out);
    return st;
}

/* ---- straight line ---- */

/* Orientation of the line at fraction u, and the angular velocity per unit
 * u' in the start frame. */
static void line_rotation(const kc_interp_line *l, kc_real u, kc_quat *q, kc_vec3 *w_local)
{
    kc_quat rel;
    if (l->orient == KC_INTERP_SLERP) {
        kc_real s, c;
        kc_sincos(KC_R(0.5) * l->angle * u, &s, &c);
        rel.w = c;
        rel.x = s * l->axis.v[0];
        rel.y = s * l->axis.v[1];
        rel.z = s * l->axis.v[2];
        kc_vec3_scale(&l->axis, l->angle, w_local);
    } else {
        /* R(u) = Ra(psi, theta u) Rz(phi u) (5.16): the quaternion of the
         * first turn about k1 = (-s_psi, c_psi, 0) times the second about z. */
        kc_real s1, c1, s2, c2, sa, ca;
        kc_sincos(KC_R(0.5) * l->theta * u, &s1, &c1);
        kc_sincos(KC_R(0.5) * l->phi * u, &s2, &c2);
        kc_real kx = l->k1.v[0], ky = l->k1.v[1];
        rel.w = c1 * c2;
        rel.x = s1 * (kx * c2 + ky * s2);
        rel.y = s1 * (ky * c2 - kx * s2);
        rel.z = c1 * s2;
        /* w = theta k1 + phi a(u), a(u) = Ra(psi, theta u) z = (c_psi sin, s_psi sin, cos)
         * of theta u; sin and cos from the half angle. */
        sa = KC_R(2.0) * s1 * c1;
        ca = KC_R(1.0) - KC_R(2.0) * s1 * s1;
        /* k1 = (-s_psi, c_psi, 0): c_psi = ky, s_psi = -kx. */
        w_local->v[0] = l->theta * kx + l->phi * ky * sa;
        w_local->v[1] = l->theta * ky - l->phi * kx * sa;
        w_local->v[2] = l->phi * ca;
    }
    kc_quat_mul(&l->q1, &rel, q);
}

kc_status kc_interp_line_plan(kc_interp_line *plan, const kc_pose *from, const kc_pose *to,
                              const kc_interp_limits *lim, kc_interp_orient orient, kc_real dt)
{
    kc_interp_line r;
    kc_mat3 R3;
    if (plan == NULL || from == NULL || to == NULL || lim == NULL || !pose_ok(from) || !pose_ok(to) ||
        !limits_ok(lim) || !dt_ok(dt) || (orient != KC_INTERP_TWO_ROTATIONS && orient != KC_INTERP_SLERP))
        return KC_E_ARG;
    memset(&r, 0, sizeof r);
    r.orient = orient;
    r.p1 = from->t;
    r.p2 = to->t;
    r.R1 = from->R;
    kc_vec3_sub(&r.p2, &r.p1, &r.dp);
    /* S = |p3| (5.7): |R1^T (p2 - p1)| = |p2 - p1|. hypot avoids overflow of
     * the squares. */
    r.length = kc_hypot(kc_hypot(r.dp.v[0], r.dp.v[1]), r.dp.v[2]);
    if (!kc_vec3_isfinite(&r.dp) || !kc_isfinite(r.length))
        return KC_E_CAPACITY;
    kc_quat q2;
    kc_quat_from_mat3(&from->R, &r.q1);
    kc_quat_from_mat3(&to->R, &q2);
    if (orient == KC_INTERP_SLERP) {
        kc_quat rel, c1;
        kc_quat_conj(&r.q1, &c1);
        kc_quat_mul(&c1, &q2, &rel);
        if (rel.w < KC_R(0.0))
            rel = quat_neg(&rel); /* the short way */
        kc_real sv = kc_sqrt(rel.x * rel.x + rel.y * rel.y + rel.z * rel.z);
        r.angle = KC_R(2.0) * kc_atan2(sv, rel.w);
        if (sv > KC_R(0.0))
            r.axis = kc_vec3_make(rel.x / sv, rel.y / sv, rel.z / sv);
        else
            r.axis = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(1.0));
    } else {
        kc_mat3_tmul(&from->R, &to->R, &R3); /* rotation of P3 = P1^-1 P2 (5.1) */
        kc_real(*m)[3] = R3.m;
        kc_real ax = m[0][2], ay = m[1][2], az = m[2][2];
        /* (5.18): psi undefined when a_x = a_y = 0; the seed sets it to 0
         * (atan2(0, -0) would give pi). */
        r.psi = ax == KC_R(0.0) && ay == KC_R(0.0) ? KC_R(0.0) : kc_atan2(ay, ax);
        if (r.psi >= KC_PI)
            r.psi -= KC_R(2.0) * KC_PI;
        r.theta = kc_atan2(kc_hypot(ax, ay), az); /* (5.19), [0, pi] */
        kc_real sp, cp, st, ct, sh, ch;
        kc_sincos(r.psi, &sp, &cp);
        kc_sincos(r.theta, &st, &ct);
        kc_sincos(KC_R(0.5) * r.theta, &sh, &ch);
        kc_real V = KC_R(2.0) * sh * sh; /* 1 - cos(theta) without cancellation */
        /* (5.21) with the corrected signs: column 2 of Ra(psi, theta) dotted
         * with n (S_phi) and o (C_phi). */
        kc_real y0 = -sp * cp * V, y1 = cp * cp * V + ct, y2 = -sp * st;
        kc_real Sphi = y0 * m[0][0] + y1 * m[1][0] + y2 * m[2][0];
        kc_real Cphi = y0 * m[0][1] + y1 * m[1][1] + y2 * m[2][1];
        r.phi = kc_atan2(Sphi, Cphi); /* (5.20) */
        if (r.phi >= KC_PI)
            r.phi -= KC_R(2.0) * KC_PI;
        r.k1 = kc_vec3_make(-sp, cp, KC_R(0.0));
        r.angle = kc_sqrt(r.theta * r.theta + r.phi * r.phi);
    }
    /* A rotation below the rounding of R1^T R2 is none. */
    kc_real Theta = r.angle > KC_R(16.0) * KC_REAL_EPS ? r.angle : KC_R(0.0);
    if (r.length == KC_R(0.0) && Theta > KC_R(0.0) && !kc_isfinite(lim->dw))
        return KC_E_ARG; /* a pure rotation needs an angular acceleration limit */
    kc_status st = plan_cart_u(r.length, Theta, lim, dt, &r.u_vmax, &r.u_amax, &r.u_jmax, &r.kind, &r.prof, &r.su,
                               &r.T, &r.ticks);
    if (st != KC_OK)
        return st;
    /* The end orientation, signed as the path arrives there. */
    kc_quat q_path;
    kc_vec3 w;
    line_rotation(&r, KC_R(1.0), &q_path, &w);
    r.q2 = match_sign(&q2, &q_path);
    *plan = r;
    return KC_OK;
}

/* The line's state for one state of a u profile; end: the exact end. */
static kc_status line_at(const void *line, kc_status st, const kc_profile_state *u_state,
                         kc_interp_cart_state *out)
{
    const kc_interp_line *plan = line;
    const kc_profile_state u = *u_state;
    /* The speed law's own variable: path length, or the angle when there
     * is no path. */
    kc_real D = plan->length > KC_R(0.0) ? plan->length : plan->angle;
    if (st == KC_DONE) {
        state_done(out, &plan->p2, &plan->q2, D);
        return KC_DONE;
    }
    kc_vec3 wl;
    for (int i = 0; i < 3; i++) {
        out->p.v[i] = plan->p1.v[i] + plan->dp.v[i] * u.p;
        out->v.v[i] = plan->dp.v[i] * u.v;
    }
    line_rotation(plan, u.p, &out->q, &wl);
    kc_vec3_scale(&wl, u.v, &wl);
    kc_mat3_mul_vec(&plan->R1, &wl, &out->w);
    state_law(out, D, &u);
    return KC_OK;
}

kc_status kc_interp_line_eval(const kc_interp_line *plan, int64_t k, kc_interp_cart_state *out)
{
    if (plan == NULL)
        return KC_E_ARG;
    return plan->kind == KC_PROFILE_JERK ? kc_interp_line_eval_scurve(plan, &plan->su, k, out)
                                         : kc_interp_line_eval_profile(plan, &plan->prof, k, out);
}

kc_status kc_interp_line_eval_scurve(const kc_interp_line *plan, const kc_scurve *prof, int64_t k,
                                     kc_interp_cart_state *out)
{
    return cart_eval_scurve(plan, prof, k, line_at, out);
}

kc_status kc_interp_line_eval_profile(const kc_interp_line *plan, const kc_profile *prof, int64_t k,
                                      kc_interp_cart_state *out)
{
    return cart_eval(plan, prof, k, line_at, out);
}

/* ---- arc ---- */

/* The counter-clockwise angle about the arc's normal from T1 to the point
 * p, in (0, 2 pi]. */
static kc_real arc_angle(const kc_interp_arc *arc, const kc_vec3 *p)
{
    kc_vec3 rp, x;
    kc_vec3_sub(p, &arc->centre, &rp);
    kc_vec3_cross(&arc->r, &rp, &x);
    kc_real angle = kc_atan2(kc_vec3_dot(&arc->normal, &x), kc_vec3_dot(&arc->r, &rp));
    return angle <= KC_R(0.0) ? angle + KC_R(2.0) * KC_PI : angle;
}

kc_status kc_interp_arc_plan(kc_interp_arc *plan, const kc_pose *from, const kc_vec3 *via, const kc_vec3 *to,
                             const kc_interp_limits *lim, kc_real dt)
{
    kc_interp_arc r;
    kc_vec3 a, b, m, t1, t2;
    if (plan == NULL || from == NULL || via == NULL || to == NULL || lim == NULL || !pose_ok(from) ||
        !kc_vec3_isfinite(via) || !kc_vec3_isfinite(to) || !limits_ok(lim) || !dt_ok(dt))
        return KC_E_ARG;
    memset(&r, 0, sizeof r);
    r.p1 = from->t;
    r.p3 = *to;
    kc_vec3_sub(via, &r.p1, &a);
    kc_vec3_sub(to, &r.p1, &b);
    kc_vec3_cross(&a, &b, &m);
    kc_real na = kc_vec3_norm(&a), nb = kc_vec3_norm(&b), nm = kc_vec3_norm(&m);
    if (!kc_isfinite(na) || !kc_isfinite(nb) || !kc_isfinite(nm))
        return KC_E_CAPACITY;
    /* Coincident points make a or b (or a x b) zero: all collinear. */
    if (!(nm > KC_INTERP_TOL_COLLINEAR * na * nb))
        return KC_E_SINGULAR;
    /* Circumcentre c = T1 + (|a|^2 b x m + |b|^2 m x a) / (2 |m|^2). */
    kc_vec3_cross(&b, &m, &t1);
    kc_vec3_cross(&m, &a, &t2);
    kc_real k = KC_R(0.5) / (nm * nm);
    for (int i = 0; i < 3; i++)
        r.centre.v[i] = r.p1.v[i] + k * (na * na * t1.v[i] + nb * nb * t2.v[i]);
    kc_vec3_scale(&m, KC_R(1.0) / nm, &r.normal);
    kc_vec3_sub(&r.p1, &r.centre, &r.r);
    kc_vec3_cross(&r.normal, &r.r, &r.nr);
    r.radius = kc_vec3_norm(&r.r);
    if (!kc_vec3_isfinite(&r.centre) || !(r.radius > KC_R(0.0)) || !kc_isfinite(r.radius))
        return KC_E_SINGULAR;
    r.angle = arc_angle(&r, to);
    r.angle_via = arc_angle(&r, via);
    /* T1 -> T2 -> T3 is counter-clockwise about N by construction; only
     * points at the collinearity threshold could round out of order. */
    if (!(r.angle_via < r.angle))
        return KC_E_SINGULAR;
    r.length = r.radius * r.angle;
    kc_quat_from_mat3(&from->R, &r.q1);
    /* End orientation by (6.1): the start one turned by alpha about N. */
    kc_real s, c;
    kc_sincos(KC_R(0.5) * r.angle, &s, &c);
    kc_quat turn = {c, s * r.normal.v[0], s * r.normal.v[1], s * r.normal.v[2]};
    kc_quat_mul(&turn, &r.q1, &r.q3);
    /* Speed law on the angle: alpha' <= min(v / R, w), alpha'' <= min(a / R, dw),
     * alpha''' <= min(j / R, dj). */
    kc_status st = plan_cart_u(r.length, r.angle, lim, dt, &r.u_vmax, &r.u_amax, &r.u_jmax, &r.kind, &r.prof, &r.su,
                               &r.T, &r.ticks);
    if (st != KC_OK)
        return st;
    *plan = r;
    return KC_OK;
}

/* The arc's state for one state of a u profile. */
static kc_status arc_at(const void *arc, kc_status st, const kc_profile_state *u_state,
                        kc_interp_cart_state *out)
{
    const kc_interp_arc *plan = arc;
    const kc_profile_state u = *u_state;
    if (st == KC_DONE) {
        state_done(out, &plan->p3, &plan->q3, plan->length);
        return KC_DONE;
    }
    /* One sincos of the half angle gives the quaternion and, by the double
     * angle formulas, the position (6.1, 6.19). */
    kc_real sh, ch;
    kc_sincos(KC_R(0.5) * plan->angle * u.p, &sh, &ch);
    kc_real sa = KC_R(2.0) * sh * ch, ca = KC_R(1.0) - KC_R(2.0) * sh * sh;
    kc_real ad = plan->angle * u.v; /* alpha' */
    const kc_real *n = plan->normal.v;
    for (int i = 0; i < 3; i++) {
        out->p.v[i] = plan->centre.v[i] + ca * plan->r.v[i] + sa * plan->nr.v[i];
        /* d/dt of the above: alpha' (cos N x r - sin r). */
        out->v.v[i] = ad * (ca * plan->nr.v[i] - sa * plan->r.v[i]);
        out->w.v[i] = ad * n[i];
    }
    kc_quat turn = {ch, sh * n[0], sh * n[1], sh * n[2]};
    kc_quat_mul(&turn, &plan->q1, &out->q);
    state_law(out, plan->length, &u);
    return KC_OK;
}

kc_status kc_interp_arc_eval(const kc_interp_arc *plan, int64_t k, kc_interp_cart_state *out)
{
    if (plan == NULL)
        return KC_E_ARG;
    return plan->kind == KC_PROFILE_JERK ? kc_interp_arc_eval_scurve(plan, &plan->su, k, out)
                                         : kc_interp_arc_eval_profile(plan, &plan->prof, k, out);
}

kc_status kc_interp_arc_eval_scurve(const kc_interp_arc *plan, const kc_scurve *prof, int64_t k,
                                    kc_interp_cart_state *out)
{
    return cart_eval_scurve(plan, prof, k, arc_at, out);
}

kc_status kc_interp_arc_eval_profile(const kc_interp_arc *plan, const kc_profile *prof, int64_t k,
                                     kc_interp_cart_state *out)
{
    return cart_eval(plan, prof, k, arc_at, out);
}
