/* SPDX-License-Identifier: BSD-3-Clause */
/* scurve.c - jerk-limited (double S) motion laws evaluated at integer
 * ticks. The phase equations and their sources are in kinctl/scurve.h. */
#include "kinctl/scurve.h"

#include <stddef.h>

#include "kinctl/profile.h"
#include "profile_internal.h"
#include "scurve_internal.h"
#include "size_internal.h"

/* One velocity change: three phases of constant jerk in fixed slots (a
 * ramp, a hold at j = 0, a ramp), phase i present where t[i] > 0: those
 * of zero length (or NaN) are left out wherever a change is used. Fixed
 * slots let a change that is planned and measured at once stay in
 * registers (change_stop_time, on every root search's path). */
#define VCHANGE_PHASES 3
typedef struct vchange {
    kc_real j[VCHANGE_PHASES], t[VCHANGE_PHASES];
} vchange;

static int vchange_has(const vchange *c, int i) { return c->t[i] > KC_R(0.0); }

/* The fastest change from (v, a) to velocity w with zero acceleration,
 * limits A and J (kinctl/scurve.h, "Velocity change"). */
static KC_SPEED_INLINE void vchange_plan(vchange *c, kc_real v, kc_real a, kc_real w, kc_real A, kc_real J)
{
    /* One division by J (this is on every planning's path). vn may differ
     * in its last bit from a caller's v + a |a| / (2J): a w that misses it
     * so takes the general branch below, whose phases are then the same
     * ramp of a to zero (a hold of zero, ap = |a|). */
    kc_real iJ = KC_R(1.0) / J;
    kc_real vn = v + a * kc_fabs(a) * (KC_R(0.5) * iJ);
    /* The phases: jerk j1 for t1, a hold for th, -sg J for t3 (those of
     * zero length left out). */
    kc_real sg = KC_R(1.0), j1, t1, th = KC_R(0.0), t3 = KC_R(0.0);
    if (w == vn) {
        /* The ramp of a to zero alone. */
        j1 = a > KC_R(0.0) ? -J : J;
        t1 = kc_fabs(a) * iJ;
    } else {
        /* Work along sg, the side the acceleration must go to. */
        sg = w > vn ? KC_R(1.0) : KC_R(-1.0);
        kc_real as = sg * a, dw = sg * (w - v), dn = sg * (w - vn);
        if (as > A) {
            /* Outside the limit: ramp down to A, hold, ramp to zero. */
            j1 = -sg * J;
            t1 = (as - A) * iJ;
            th = dn / A;
            t3 = A * iJ;
        } else {
            kc_real full = (KC_R(2.0) * A * A - as * as) * (KC_R(0.5) * iJ), ap = A;
            if (dw >= full) {
                th = (dw - full) / A;
            } else {
                ap = kc_sqrt(kc_max(J * dw + KC_R(0.5) * as * as, KC_R(0.0)));
                /* dn > 0 makes ap > max(as, 0) exactly; keep it so under rounding. */
                ap = kc_min(kc_max(ap, kc_max(as, KC_R(0.0))), A);
            }
            j1 = sg * J;
            t1 = (ap - as) * iJ;
            t3 = ap * iJ;
        }
    }
    c->j[0] = j1;
    c->t[0] = t1;
    c->j[1] = KC_R(0.0);
    c->t[1] = th;
    c->j[2] = -sg * J;
    c->t[2] = t3;
}

/* Advances (p, v, a) by a phase of jerk j over tau (which may be
 * negative: backwards). */
static void advance(kc_real *p, kc_real *v, kc_real *a, kc_real j, kc_real tau)
{
    *p += tau * (*v + tau * (KC_R(0.5) * *a + tau * j * (KC_R(1.0) / KC_R(6.0))));
    *v += tau * (*a + KC_R(0.5) * tau * j);
    *a += j * tau;
}

/* Distance and duration of a velocity change from (v, a). */
static KC_SPEED_INLINE kc_real vchange_dist(const vchange *c, kc_real v, kc_real a, kc_real *time)
{
    kc_real p = KC_R(0.0), t = KC_R(0.0);
    for (int i = 0; i < VCHANGE_PHASES; i++) {
        if (vchange_has(c, i)) {
            advance(&p, &v, &a, c->j[i], c->t[i]);
            t += c->t[i];
        }
    }
    if (time != NULL)
        *time = t;
    return p;
}

/* The stop from (vp, 0) to rest: symmetric in time, so its distance is
 * vp t / 2, with t = |vp| / A + A / J when A is reached (|vp| >= A^2 / J)
 * and 2 sqrt(|vp| / J) otherwise (kinctl/scurve.h, "Velocity change"). */
static kc_real stop_time(kc_real vp, kc_real A, kc_real J)
{
    kc_real w = kc_fabs(vp);
    return w * J >= A * A ? w / A + A / J : KC_R(2.0) * kc_sqrt(w / J);
}

/* Duration of the change from (v0, a0) to vp and the stop from vp, with
 * no cruise; their distance d(vp) into *dist when given. The change
 * within A, the stop within As <= A (A but for a stop slowed by
 * kc_scurve_stretch, see stretch_blocked()). */
static kc_real change_stop_time(kc_real vp, kc_real v0, kc_real a0, kc_real A, kc_real As, kc_real J,
                                kc_real *dist)
{
    vchange c;
    kc_real tc, ts = stop_time(vp, As, J);
    vchange_plan(&c, v0, a0, vp, A, J);
    kc_real p = vchange_dist(&c, v0, a0, &tc) + KC_R(0.5) * vp * ts;
    if (dist != NULL)
        *dist = p;
    return tc + ts;
}

/* What a root search solves: d(x) = d for the plain family (x = vp) or the
 * gap family (x = s, the fraction of a0 ramped away, kinctl/scurve.h), or
 * T(vp) = T for a stretched plan. */
typedef struct dfun {
    int gap; /* 0: plain d(vp); 1: gap d(s); 2: the duration with a cruise to d, of x = 1 / vp;
                3: the optimum's duration to d with the stop within As = 1 / x;
                4: the push's duration to d, of x = t1 (kinds 3 and 4: blocked_time(),
                   searched by reach(), never by root(): they plan, and a plan searches) */
    kc_real v0, a0, A, As, J;
    kc_real d; /* kinds 2 and 3: the distance to cover */
    kc_real V; /* kind 3: vmax */
    /* Kinds 0 and 2, when not NULL: the last x evaluated and, found with
     * it, the change's and the stop's duration (kind 0) or the cruise's
     * (kind 2), so that a root's caller need not evaluate it again. */
    kc_real *memo;
} dfun;

/* The duration of the change to vp and the stop (change_stop_time) from
 * f's start within its limits. */
static KC_SIZE_NOINLINE kc_real time_of(const dfun *f, kc_real vp)
{
    return change_stop_time(vp, f->v0, f->a0, f->A, f->As, f->J, NULL);
}

/* d(vp) (change_stop_time) from f's start within its limits. */
static KC_SIZE_NOINLINE kc_real dist_of(const dfun *f, kc_real vp)
{
    kc_real p;
    change_stop_time(vp, f->v0, f->a0, f->A, f->As, f->J, &p);
    return p;
}

/* The gap family: ramp f->a0 towards zero by the fraction s at jerk
 * f->J, then the fastest change to rest within f->As. Fills the phases
 * when c and st are given. */
static kc_real gap_dist(const dfun *f, kc_real s, vchange *c, vchange *st, kc_real *time)
{
    vchange r, sp;
    kc_real a0 = f->a0, As = f->As, J = f->J, p = KC_R(0.0), v = f->v0, a = a0, ts = KC_R(0.0);
    r.j[0] = a0 > KC_R(0.0) ? -J : J;
    r.t[0] = s * kc_fabs(a0) / J;
    r.j[1] = r.j[2] = r.t[1] = r.t[2] = KC_R(0.0);
    if (vchange_has(&r, 0))
        advance(&p, &v, &a, r.j[0], r.t[0]);
    if (s >= KC_R(1.0))
        a = KC_R(0.0);
    vchange_plan(&sp, v, a, KC_R(0.0), As, J);
    if (c != NULL) {
        *c = r;
        *st = sp;
    }
    p += vchange_dist(&sp, v, a, &ts);
    if (time != NULL)
        *time = ts + (vchange_has(&r, 0) ? r.t[0] : KC_R(0.0));
    return p;
}

/* The duration of the plain plan from (f->v0, f->a0) through vp with the
 * cruise that covers f->d, within f->A and f->J (kinctl/scurve.h, "from
 * a moving start"); the cruise's time into *tc when given. */
static kc_real cruise_time_of(const dfun *f, kc_real vp, kc_real *tc)
{
    kc_real dv, t = change_stop_time(vp, f->v0, f->a0, f->A, f->A, f->J, &dv);
    kc_real c = (f->d - dv) / vp;
    if (tc != NULL)
        *tc = c;
    return t + c;
}

static kc_real dfun_eval(const dfun *f, kc_real x)
{
    kc_real r, m = KC_R(0.0);
    if (f->gap == 1)
        return gap_dist(f, x, NULL, NULL, NULL);
    else if (f->gap == 2) /* x = 1 / vp: the cruise's 1 / vp made linear */
        r = cruise_time_of(f, KC_R(1.0) / x, &m);
    else
        m = change_stop_time(x, f->v0, f->a0, f->A, f->As, f->J, &r);
    if (f->memo != NULL) {
        f->memo[0] = x;
        f->memo[1] = m;
    }
    return r;
}

/* Regula falsi, Illinois variant, on a bracket [lo, hi] with f - d of
 * opposite signs at the ends: the secant through the ends, the weight of
 * an end that stays twice in a row halved (superlinear, about ten steps),
 * a halving whenever the secant falls outside the bracket. Driven by its
 * caller (bracket_next, then bracket_take with f - d at that point), so
 * that root() and reach() share it without calling each other. */
typedef struct bracket {
    kc_real lo, hi, flo, fhi; /* the ends and f - d there */
    kc_real wlo, whi;         /* the weighted end values */
    int side;
} bracket;

/* The next point inside the bracket into *x; 0 when the ends are
 * adjacent numbers and the bracket cannot shrink. */
static inline int bracket_next(const bracket *b, kc_real *x)
{
    kc_real lo = b->lo, hi = b->hi, xn = (lo * b->whi - hi * b->wlo) / (b->whi - b->wlo);
    if (!(xn > lo && xn < hi))
        xn = KC_R(0.5) * (lo + hi);
    *x = xn;
    return xn > lo && xn < hi;
}

/* The bracket narrowed by the point x with f - d = fx. */
static inline void bracket_take(bracket *b, kc_real x, kc_real fx)
{
    if ((fx < KC_R(0.0)) == (b->flo < KC_R(0.0))) {
        b->lo = x;
        b->flo = b->wlo = fx;
        if (b->side == -1)
            b->whi *= KC_R(0.5);
        b->side = -1;
    } else {
        b->hi = x;
        b->fhi = b->whi = fx;
        if (b->side == 1)
            b->wlo *= KC_R(0.5);
        b->side = 1;
    }
}

/* The end of the bracket nearest the root. */
static KC_SIZE_NOINLINE kc_real bracket_best(const bracket *b)
{
    return kc_fabs(b->flo) <= kc_fabs(b->fhi) ? b->lo : b->hi;
}

/* Root of f(x) = d on [lo, hi], with f - d of opposite signs (or zero) at
 * the ends (flo, fhi), by regula falsi (bracket above). At most
 * KC_SCURVE_MAX_ITER steps; stops when f - d is within 4 units of
 * roundoff of d or the bracket reaches adjacent numbers. Returns the
 * point nearest the root. */
static kc_real root(const dfun *f, kc_real lo, kc_real hi, kc_real flo, kc_real fhi, kc_real d)
{
    if (flo == KC_R(0.0))
        return lo;
    if (fhi == KC_R(0.0))
        return hi;
    kc_real tol = KC_R(4.0) * KC_REAL_EPS * kc_fabs(d), x;
    bracket b = {lo, hi, flo, fhi, flo, fhi, 0};
    for (int i = 0; i < KC_SCURVE_MAX_ITER && bracket_next(&b, &x); i++) {
        kc_real fx = dfun_eval(f, x) - d;
        if (kc_fabs(fx) <= tol)
            return x;
        bracket_take(&b, x, fx);
    }
    return bracket_best(&b);
}

/* root() on the bracket of x1 and x2 in either order (f1, f2: f - d
 * there). */
static kc_real root_of(const dfun *f, kc_real x1, kc_real x2, kc_real f1, kc_real f2, kc_real d)
{
    return x1 < x2 ? root(f, x1, x2, f1, f2, d) : root(f, x2, x1, f2, f1, d);
}

/* The root strictly between lo and hi of qa x^2 + qb x + qc (the two
 * roots without cancellation), or 0 when it has none there. */
static kc_real poly2_root(kc_real qa, kc_real qb, kc_real qc, kc_real lo, kc_real hi)
{
    kc_real r1, r2;
    if (qa == KC_R(0.0)) {
        r1 = r2 = -qc / qb;
    } else {
        kc_real disc = qb * qb - KC_R(4.0) * qa * qc;
        if (!(disc >= KC_R(0.0)))
            return KC_R(0.0);
        kc_real q = KC_R(-0.5) * (qb + (qb >= KC_R(0.0) ? kc_sqrt(disc) : -kc_sqrt(disc)));
        r1 = q / qa;
        r2 = q != KC_R(0.0) ? qc / q : r1;
    }
    if (r1 > lo && r1 < hi)
        return r1;
    if (r2 > lo && r2 < hi)
        return r2;
    return KC_R(0.0);
}

/* The root strictly between x1 and x2 of the quadratic with leading
 * coefficient c2 through (x1, y1 - y0) and (x2, y2 - y0) (poly2_root), or
 * 0 when it has none there. */
static kc_real poly2_through(kc_real c2, kc_real x1, kc_real y1, kc_real x2, kc_real y2, kc_real y0)
{
    kc_real c1 = (y2 - y1) / (x2 - x1) - c2 * (x2 + x1), c0 = y1 - y0 - x1 * (c2 * x1 + c1);
    return poly2_root(c2, c1, c0, kc_min(x1, x2), kc_max(x1, x2));
}

/* The root of d(vp) = d on a plain branch [lo, hi] ([max(vn, 0), V] or
 * [-V, min(vn, 0)]; dlo, dhi: d at its ends, bracketing d). Along the
 * branch the change ends beyond vn (sg = s, the branch's sign). Where it
 * holds amax (or starts beyond it) and the stop reaches its limit As, from
 * vb to the branch's far end +-V, d(vp) is a quadratic with the leading
 * coefficient s (1 / A + 1 / As) / 2: the change's and the stop's
 * distances grow as vp^2 / (2A) and vp^2 / (2As) (kinctl/scurve.h,
 * "Velocity change"; s / A when As = A). A root there comes
 * from d at two points of that stretch and is checked with one more
 * evaluation; elsewhere, or when the check fails, regula falsi (root()). */
static kc_real plain_root(const dfun *f, kc_real lo, kc_real hi, kc_real dlo, kc_real dhi, kc_real d)
{
    kc_real v0 = f->v0, a0 = f->a0, A = f->A, As = f->As, J = f->J;
    kc_real s = hi > KC_R(0.0) ? KC_R(1.0) : KC_R(-1.0);
    kc_real v_near = s > KC_R(0.0) ? lo : hi, d_near = s > KC_R(0.0) ? dlo : dhi;
    kc_real v_far = s > KC_R(0.0) ? hi : lo, d_far = s > KC_R(0.0) ? dhi : dlo;
    kc_real as = s * a0, vn = s * v0 + as * kc_fabs(as) / (KC_R(2.0) * J);
    kc_real vb = s * kc_max(As * As / J, as > A ? vn : s * v0 + (KC_R(2.0) * A * A - as * as) / (KC_R(2.0) * J));
    if (!(s * vb < s * v_far))
        return root(f, lo, hi, dlo - d, dhi - d, d);
    if (s * vb > s * v_near) {
        kc_real db = dfun_eval(f, vb);
        if (s * (d - db) < KC_R(0.0)) /* between the v_near end and vb */
            return root_of(f, v_near, vb, d_near - d, db - d, d);
        v_near = vb;
        d_near = db;
    }
    /* The quadratic through (v_near, d_near - d), (v_far, d_far - d), its
     * root between them. */
    kc_real x = poly2_through(s * (KC_R(0.5) / A + KC_R(0.5) / As), v_near, d_near, v_far, d_far, d);
    if (x != KC_R(0.0)) {
        kc_real fx = dfun_eval(f, x) - d;
        if (kc_fabs(fx) <= KC_R(4.0) * KC_REAL_EPS * kc_fabs(d))
            return x;
        /* Narrow the stretch's bracket with x for regula falsi. */
        if ((fx < KC_R(0.0)) == (d_near - d < KC_R(0.0))) {
            v_near = x;
            d_near = fx + d;
        } else {
            v_far = x;
            d_far = fx + d;
        }
    }
    return root_of(f, v_near, v_far, d_near - d, d_far - d, d);
}

static int limits_ok(kc_real vmax, kc_real amax, kc_real jmax, kc_real dt)
{
    /* Written with ! so that NaN fails every test into an error. */
    return vmax > KC_R(0.0) && amax > KC_R(0.0) && kc_isfinite(amax) && jmax > KC_R(0.0) && kc_isfinite(jmax) &&
           dt > KC_R(0.0) && kc_isfinite(dt);
}

/* Phase i: its kind, end time, and the state (p, v, a) at its reference
 * time tr, jerk j. One copy built for size (178 B less on the Cortex-M4F
 * than inlined at its four callers). */
static KC_SIZE_NOINLINE void set_phase(kc_scurve *r, int i, int kind, kc_real t_end, kc_real tr, kc_real p, kc_real v,
                                       kc_real a, kc_real j)
{
    r->kind[i] = kind;
    r->t_end[i] = t_end;
    r->tr[i] = tr;
    r->pr[i] = p;
    r->vr[i] = v;
    r->ar[i] = a;
    r->j[i] = j;
}

static void add_phase(kc_scurve *r, int kind, kc_real t_end, kc_real tr, kc_real p, kc_real v, kc_real a, kc_real j)
{
    set_phase(r, r->n++, kind, t_end, tr, p, v, a, j);
}

/* A plan's header alone (scurve_internal.h): the start, target, vp and
 * duration T, with n = -1 and ticks = -1 (not counted: the stretch counts
 * its own). */
static void set_header(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vp, kc_real T,
                       kc_real dt)
{
    prof->p0 = p0;
    prof->v0 = v0;
    prof->a0 = a0;
    prof->p1 = p1;
    prof->vp = vp;
    prof->gap = 0;
    prof->n = -1;
    prof->T = T;
    prof->dt = dt;
    prof->ticks = -1;
}

/* set_header where T is finite, else KC_E_CAPACITY (prof untouched). */
static kc_status header(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vp, kc_real T,
                        kc_real dt)
{
    if (!kc_isfinite(T))
        return KC_E_CAPACITY;
    set_header(prof, p0, v0, a0, p1, vp, T, dt);
    return KC_OK;
}

/* The profile: the phases c from the start, a cruise at vp for tc, and
 * the stop s (a velocity change to rest) laid backwards from (p1, 0, 0) at
 * T, where T is `duration` when positive, the sum of the phases otherwise;
 * or, unless lay, its header alone (a time-optimal plan's end,
 * kc_scurve_plan_time). */
static kc_status build(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, const vchange *cp, kc_real vp,
                       kc_real tc, const vchange *sp, kc_real duration, kc_real dt, int lay)
{
    kc_scurve r;
    const vchange *c = cp, *s = sp;
    kc_real p = p0, v = v0, a = a0, t = KC_R(0.0), t_change = KC_R(0.0), t_stop = KC_R(0.0), jm = KC_R(0.0);
    int ns = 0;
    for (int i = 0; i < VCHANGE_PHASES; i++) {
        if (vchange_has(c, i)) {
            t_change += c->t[i];
            jm = kc_max(jm, kc_fabs(c->j[i]));
        }
        if (vchange_has(s, i)) {
            t_stop += s->t[i];
            jm = kc_max(jm, kc_fabs(s->j[i]));
            ns++;
        }
    }
    kc_real T = duration > KC_R(0.0) ? duration : t_change + kc_max(tc, KC_R(0.0)) + t_stop;
    if (!lay || !kc_isfinite(T))
        return header(prof, p0, v0, a0, p1, vp, T, dt);
    int64_t ticks = kc_profile_ticks(T, dt);
    if (ticks < 0)
        return KC_E_CAPACITY;
    /* Where the positions are bounded well within the range (|a| grows at
     * most jm t along the change, so |p - p0| <= |v0| t + |a0| t^2 + jm t^3
     * there, and the stop from rest backwards likewise), the profile is
     * written in place, sparing a copy of it (a tenth of a moving start's
     * planning); otherwise into r, and prof is untouched on error. */
    kc_real bound = kc_fabs(p0) + kc_fabs(p1) + t_change * (kc_fabs(v0) + t_change * (kc_fabs(a0) + t_change * jm)) +
                    jm * t_stop * t_stop * t_stop;
    kc_scurve *o = bound <= KC_REAL_MAX / KC_R(16.0) ? prof : &r;
    set_header(o, p0, v0, a0, p1, vp, T, dt); /* T is finite */
    o->n = 0;
    for (int i = 0; i < VCHANGE_PHASES; i++) {
        if (!vchange_has(c, i))
            continue;
        kc_real t0 = t, p_ = p, v_ = v, a_ = a;
        advance(&p, &v, &a, c->j[i], c->t[i]);
        t += c->t[i];
        add_phase(o, 1, t, t0, p_, v_, a_, c->j[i]);
    }
    kc_real te = T - t_stop; /* start of the stop */
    if ((tc > KC_R(0.0) || duration > KC_R(0.0)) && te > t)
        add_phase(o, 2, te, t, p, vp, KC_R(0.0), KC_R(0.0));
    /* The stop, backwards from the end: fill it in reverse order after the
     * slot where it begins. */
    int k = o->n + ns;
    o->n = k;
    kc_real pb = p1, vb = KC_R(0.0), ab = KC_R(0.0), tb = T;
    for (int i = VCHANGE_PHASES - 1; i >= 0; i--) {
        if (!vchange_has(s, i))
            continue;
        set_phase(o, --k, 3, tb, tb, pb, vb, ab, s->j[i]);
        advance(&pb, &vb, &ab, s->j[i], -s->t[i]);
        tb -= s->t[i];
    }
    o->ticks = ticks;
    if (o == prof)
        return KC_OK;
    if (!kc_isfinite(p) || !kc_isfinite(pb))
        return KC_E_CAPACITY;
    *prof = r;
    return KC_OK;
}

/* The plain profile through the extremum vp: change (within A), cruise,
 * stop (within As); or its header alone (build()). */
static kc_status build_vp(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vp, kc_real tc,
                          kc_real A, kc_real As, kc_real J, kc_real duration, kc_real dt, int lay)
{
    vchange c, s;
    vchange_plan(&c, v0, a0, vp, A, J);
    vchange_plan(&s, vp, KC_R(0.0), KC_R(0.0), As, J);
    return build(prof, p0, v0, a0, p1, &c, vp, tc, &s, duration, dt, lay);
}

/* Rest to rest over D >= 0 (kinctl/scurve.h, Biagiotti & Melchiorri 3.4):
 * the peak speed and the cruise time. */
static void rest_to_rest(kc_real D, kc_real V, kc_real A, kc_real J, kc_real *vpeak, kc_real *tc)
{
    kc_real Tj, Ta;
    if (V * J >= A * A) {
        Tj = A / J;
        Ta = Tj + V / A;
    } else {
        Tj = kc_sqrt(V / J);
        Ta = KC_R(2.0) * Tj;
    }
    kc_real Tv = D / V - Ta;
    if (Tv > KC_R(0.0)) {
        *vpeak = V;
        *tc = Tv;
        return;
    }
    *tc = KC_R(0.0);
    if (D >= KC_R(2.0) * A * A * A / (J * J)) {
        Tj = A / J;
        Ta = KC_R(0.5) * Tj + kc_sqrt(KC_R(0.25) * Tj * Tj + D / A);
        *vpeak = A * (Ta - Tj);
    } else {
        Tj = kc_cbrt(D / (KC_R(2.0) * J));
        *vpeak = J * Tj * Tj;
    }
    /* Never above V: the two forms meet it only at the boundary. */
    *vpeak = kc_min(*vpeak, V);
}

/* kc_scurve_plan, laying out the phases (lay) or making the header alone
 * (kc_scurve_plan_time). */
static kc_status plan(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vmax, kc_real amax,
                      kc_real astop, kc_real jmax, kc_real dt, int lay)
{
    if (prof == NULL || !kc_isfinite(p0) || !kc_isfinite(v0) || !kc_isfinite(a0) || !kc_isfinite(p1) ||
        !limits_ok(vmax, amax, jmax, dt))
        return KC_E_ARG;
    kc_real d = p1 - p0;
    if (!kc_isfinite(d))
        return KC_E_ARG;
    kc_real A = amax, As = astop, J = jmax;
    if (v0 == KC_R(0.0) && a0 == KC_R(0.0)) {
        kc_real vpeak = KC_R(0.0), tc = KC_R(0.0);
        if (d != KC_R(0.0))
            rest_to_rest(kc_fabs(d), vmax, A, J, &vpeak, &tc);
        return build_vp(prof, p0, v0, a0, p1, d < KC_R(0.0) ? -vpeak : vpeak, tc, A, A, J, KC_R(0.0), dt, lay);
    }
    /* The velocity range to search: vmax, or without a speed limit a bound
     * that brackets d, found by doubling (at most 64 times). */
    kc_real V = vmax;
    if (!kc_isfinite(V)) {
        dfun f = {0, v0, a0, A, As, J, KC_R(0.0), KC_R(0.0), NULL};
        kc_real vn = v0 + a0 * kc_fabs(a0) / (KC_R(2.0) * J);
        V = kc_max(kc_max(kc_fabs(v0), kc_fabs(vn)), kc_max(kc_sqrt(A * kc_fabs(d)), A * A / J));
        int i = 0;
        while ((dist_of(&f, V) < d || dist_of(&f, -V) > d) && i < 64) {
            V *= KC_R(2.0);
            i++;
        }
        if (i == 64 || !kc_isfinite(V))
            return KC_E_CAPACITY;
    }
    /* A header's duration is the one its choice was made with: the
     * change and the stop (change_stop_time) and the cruise. */
    kc_real dh, dl = KC_R(0.0), t = change_stop_time(V, v0, a0, A, As, J, &dh), vc = V;
    if (!kc_isfinite(dh))
        return KC_E_CAPACITY;
    if (d < dh) {
        t = change_stop_time(-V, v0, a0, A, As, J, &dl);
        if (!kc_isfinite(dl))
            return KC_E_CAPACITY;
        vc = -V;
    }
    if (d >= dh || d <= dl) {
        /* A cruise at V (d >= dh) or -V (d <= dl) covers the rest. */
        kc_real tc = (d >= dh ? d - dh : dl - d) / V;
        return lay ? build_vp(prof, p0, v0, a0, p1, vc, tc, A, As, J, KC_R(0.0), dt, lay)
                   : header(prof, p0, v0, a0, p1, vc, t + tc, dt);
    }
    /* dl < d < dh, Tc = 0. The plain branches are vp <= min(vn, 0) and
     * vp >= max(vn, 0), where the change ends on the other side of zero
     * acceleration than the stop starts, so vp is a true extremum; d
     * increases along each of them. The gap family (a0 partly ramped away,
     * then the stop) joins d(0) and d(vn). Of the roots these hold, the
     * fastest is the plan; if none does (vmax cut vn short), the plain
     * change to a vp between the branches. */
    kc_real vn = kc_clamp(v0 + a0 * kc_fabs(a0) / (KC_R(2.0) * J), -V, V);
    kc_real m1 = kc_min(vn, KC_R(0.0)), m2 = kc_max(vn, KC_R(0.0));
    /* The root searches remember their last point's duration. */
    kc_real memo[2] = {KC_R(0.0) / KC_R(0.0), KC_R(0.0)};
    dfun f = {0, v0, a0, A, As, J, KC_R(0.0), KC_R(0.0), memo}, g = {1, v0, a0, A, As, J, KC_R(0.0), KC_R(0.0), NULL};
    kc_real d1 = dist_of(&f, m1), d2 = dist_of(&f, m2);
    kc_real vp = KC_R(0.0), best = KC_R(-1.0), s_gap = KC_R(-1.0);
    if (d <= d1) {
        vp = plain_root(&f, -V, m1, dl, d1, d);
        best = memo[0] == vp ? memo[1] : time_of(&f, vp);
    }
    if (d >= d2) {
        kc_real w = plain_root(&f, m2, V, d2, dh, d);
        kc_real tw = memo[0] == w ? memo[1] : time_of(&f, w);
        if (best < KC_R(0.0) || tw < best) {
            vp = w;
            best = tw;
        }
    }
    /* s = 0 is the stop at once, d(0): d1 or d2 (with a slowed stop, the
     * stop at once within As). */
    kc_real g0 = (As != A ? gap_dist(&g, KC_R(0.0), NULL, NULL, NULL) : m1 == KC_R(0.0) ? d1 : d2) - d;
    kc_real g1 = gap_dist(&g, KC_R(1.0), NULL, NULL, NULL) - d;
    /* Signs compared, not multiplied: a product of small distances may
     * underflow to zero in float. */
    if (a0 != KC_R(0.0) && ((g0 <= KC_R(0.0) && g1 >= KC_R(0.0)) || (g0 >= KC_R(0.0) && g1 <= KC_R(0.0)))) {
        kc_real s = root(&g, KC_R(0.0), KC_R(1.0), g0, g1, d), ts;
        gap_dist(&g, s, NULL, NULL, &ts);
        if (best < KC_R(0.0) || ts < best) {
            s_gap = s;
            best = ts;
        }
    }
    if (s_gap >= KC_R(0.0)) {
        vchange c, st;
        gap_dist(&g, s_gap, &c, &st, NULL);
        kc_status r = build(prof, p0, v0, a0, p1, &c, KC_R(0.0), KC_R(0.0), &st, KC_R(0.0), dt, lay);
        if (r == KC_OK)
            prof->gap = 1;
        return r;
    }
    if (best < KC_R(0.0)) {
        vp = root(&f, m1, m2, d1 - d, d2 - d, d);
        best = lay ? best : time_of(&f, vp);
    }
    return lay ? build_vp(prof, p0, v0, a0, p1, vp, KC_R(0.0), A, As, J, KC_R(0.0), dt, lay)
               : header(prof, p0, v0, a0, p1, vp, best, dt);
}

/* The duration of the time-optimal plan to f->d whose stop is held
 * within As (KC_REAL_MAX when there is none). */
static kc_real stop_slowed_time(const dfun *f, kc_real As)
{
    kc_scurve h;
    if (plan(&h, KC_R(0.0), f->v0, f->a0, f->d, f->V, f->A, As, f->J, KC_R(1.0), 0) != KC_OK)
        return KC_REAL_MAX;
    return h.T;
}

kc_status kc_scurve_plan(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vmax,
                         kc_real amax, kc_real jmax, kc_real dt)
{
    return plan(prof, p0, v0, a0, p1, vmax, amax, amax, jmax, dt, 1);
}

kc_status kc_scurve_plan_time(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vmax,
                              kc_real amax, kc_real jmax, kc_real dt)
{
    return plan(prof, p0, v0, a0, p1, vmax, amax, amax, jmax, dt, 0);
}

kc_status kc_scurve_plan_stop(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real amax, kc_real jmax,
                              kc_real dt)
{
    if (prof == NULL || !kc_isfinite(p0) || !kc_isfinite(v0) || !kc_isfinite(a0) ||
        !limits_ok(KC_R(1.0), amax, jmax, dt))
        return KC_E_ARG;
    /* The velocity change to zero is the stop (kinctl/scurve.h): laid
     * backwards from where it ends, so that end is exact. */
    vchange none = {{KC_R(0.0), KC_R(0.0), KC_R(0.0)}, {KC_R(0.0), KC_R(0.0), KC_R(0.0)}}, s;
    vchange_plan(&s, v0, a0, KC_R(0.0), amax, jmax);
    kc_real p1 = p0 + vchange_dist(&s, v0, a0, NULL);
    if (!kc_isfinite(p1))
        return KC_E_CAPACITY;
    return build(prof, p0, v0, a0, p1, &none, KC_R(0.0), KC_R(0.0), &s, KC_R(0.0), dt, 1);
}

/* Records p, v, a in the extent. */
static void extent_add(kc_scurve_extent *e, kc_real p, kc_real v, kc_real a)
{
    e->p_min = kc_min(e->p_min, p);
    e->p_max = kc_max(e->p_max, p);
    e->v_max = kc_max(e->v_max, kc_fabs(v));
    e->a_max = kc_max(e->a_max, kc_fabs(a));
}

kc_status kc_scurve_extent_of(const kc_scurve *prof, kc_scurve_extent *out)
{
    if (prof == NULL || out == NULL)
        return KC_E_ARG;
    kc_scurve_extent e = {prof->p0, prof->p0, KC_R(0.0), KC_R(0.0)};
    extent_add(&e, prof->p0, prof->v0, prof->a0);
    extent_add(&e, prof->p1, KC_R(0.0), KC_R(0.0));
    kc_real t0 = KC_R(0.0);
    for (int i = 0; i < prof->n; i++) {
        /* Phase i on tau in [lo, hi] around its reference: p at both ends,
         * at the roots of v (p's extrema) and at the root of a (v's). */
        kc_real lo = t0 - prof->tr[i], hi = prof->t_end[i] - prof->tr[i];
        kc_real pr = prof->pr[i], vr = prof->vr[i], ar = prof->ar[i], j = prof->j[i];
        kc_real cand[5];
        int m = 0;
        cand[m++] = lo;
        cand[m++] = hi;
        if (j != KC_R(0.0)) {
            cand[m++] = -ar / j;
            /* v = vr + ar tau + j tau^2 / 2 = 0 */
            kc_real disc = ar * ar - KC_R(2.0) * j * vr;
            if (disc >= KC_R(0.0)) {
                kc_real r = kc_sqrt(disc);
                cand[m++] = (-ar + r) / j;
                cand[m++] = (-ar - r) / j;
            }
        } else if (ar != KC_R(0.0)) {
            cand[m++] = -vr / ar;
        }
        for (int c = 0; c < m; c++) {
            kc_real tau = cand[c];
            if (!(tau >= lo && tau <= hi))
                continue;
            kc_real p = pr + tau * (vr + tau * (KC_R(0.5) * ar + tau * j / KC_R(6.0)));
            kc_real v = vr + tau * (ar + KC_R(0.5) * tau * j);
            extent_add(&e, p, v, ar + j * tau);
        }
        t0 = prof->t_end[i];
    }
    *out = e;
    return KC_OK;
}

/* The peak speed v that makes a rest-to-rest move over D > 0 last T
 * (kinctl/scurve.h, "Stretched"), T >= the time-optimal duration. */
static kc_real stretch_speed(kc_real D, kc_real A, kc_real J, kc_real T)
{
    kc_real Tp = T - A / J;
    kc_real rad = Tp * Tp - KC_R(4.0) * D / A;
    if (Tp > KC_R(0.0) && rad >= KC_R(0.0)) {
        kc_real v = KC_R(2.0) * D / (Tp + kc_sqrt(rad));
        if (v >= A * A / J)
            return v;
    }
    /* x^3 - (T/2) x^2 + D/(2J) = 0, the root in (0, T/4]. */
    kc_real e = KC_R(54.0) * D / (J * T * T * T); /* 1 - cos(3 th) */
    kc_real c = kc_clamp(KC_R(1.0) - e, KC_R(-1.0), KC_R(1.0));
    kc_real th = kc_atan2(kc_sqrt(kc_max(e * (KC_R(2.0) - e), KC_R(0.0))), c) / KC_R(3.0);
    kc_real sn, cs;
    kc_sincos(KC_R(0.5) * th, &sn, &cs);
    /* 1 - cos th = 2 sin^2(th/2), sin th = 2 sin(th/2) cos(th/2). */
    kc_real x = T / KC_R(6.0) * (KC_R(2.0) * sn * sn + KC_R(2.0) * KC_R(1.7320508075688772935) * sn * cs);
    for (int i = 0; i < 2; i++) {
        kc_real g = x * x * (x - KC_R(0.5) * T) + D / (KC_R(2.0) * J);
        kc_real dg = x * (KC_R(3.0) * x - T);
        if (dg < KC_R(0.0)) {
            kc_real xn = x - g / dg;
            if (xn > KC_R(0.0) && xn <= KC_R(0.25) * T)
                x = xn;
        }
    }
    return J * x * x;
}

/* The rest-to-rest optimum fast stretched to duration > fast->T: its
 * peak speed lowered to the one that lasts duration (stretch_speed), never
 * above the optimum's own; no move is a wait at p0 for the duration. */
static kc_status stretch_rest(kc_scurve *prof, const kc_scurve *fast, kc_real amax, kc_real jmax, kc_real duration)
{
    kc_real p0 = fast->p0, p1 = fast->p1, D = kc_fabs(p1 - p0), v = KC_R(0.0), tc = duration;
    if (D != KC_R(0.0)) {
        v = kc_min(stretch_speed(D, amax, jmax, duration), fast->vp < KC_R(0.0) ? -fast->vp : fast->vp);
        tc = KC_R(0.0);
    }
    return build_vp(prof, p0, KC_R(0.0), KC_R(0.0), p1, p1 < p0 ? -v : v, tc, amax, amax, jmax, duration, fast->dt, 1);
}

kc_status kc_scurve_plan_duration(kc_scurve *prof, kc_real p0, kc_real p1, kc_real vmax, kc_real amax,
                                  kc_real jmax, kc_real duration, kc_real dt)
{
    return kc_scurve_plan_duration_from(prof, p0, KC_R(0.0), KC_R(0.0), p1, vmax, amax, jmax, duration, dt);
}

/* The root between v1 and v3 of the quadratic through (v1, g1), (v2, g2),
 * (v3, g3) (Newton's divided differences), or 0 when it has none there. */
static kc_real quad_root(kc_real v1, kc_real g1, kc_real v2, kc_real g2, kc_real v3, kc_real g3)
{
    kc_real f12 = (g2 - g1) / (v2 - v1), f23 = (g3 - g2) / (v3 - v2);
    kc_real qa = (f23 - f12) / (v3 - v1);
    kc_real qb = f12 - qa * (v1 + v2), qc = g1 - v1 * (f12 - qa * v2);
    return poly2_root(qa, qb, qc, kc_min(v1, v3), kc_max(v1, v3));
}

/* Whether the plain plans through every vp from vl to vh (one sign, vl !=
 * vh) have a change that holds amax for a while, or starts beyond it, on
 * one side sg of vn (into *sg) and a stop that reaches amax
 * (kinctl/scurve.h, "Velocity change"): their durations are then linear
 * in vp and their distances quadratic. Each condition is monotonic in vp
 * on one side of vn, so the ends decide. */
static int exact_fit(kc_real v0, kc_real a0, kc_real vl, kc_real vh, kc_real A, kc_real J, kc_real *sg)
{
    kc_real vn = v0 + a0 * kc_fabs(a0) / (KC_R(2.0) * J);
    if (vl == vh || !(kc_fabs(vl) * J >= A * A && kc_fabs(vh) * J >= A * A) || vl == vn || vh == vn ||
        (vl > vn) != (vh > vn))
        return 0;
    *sg = vl > vn ? KC_R(1.0) : KC_R(-1.0);
    kc_real as = *sg * a0, full = (KC_R(2.0) * A * A - as * as) / (KC_R(2.0) * J);
    return as > A || (*sg * (vl - v0) >= full && *sg * (vh - v0) >= full);
}

/* cruise_time_of in closed form where exact_fit holds (sg its side):
 * in the frame of sg (u = sg v, as = sg a0), the change's first phase
 * takes the acceleration to amax in t1, reaching u1 over x1; the hold
 * takes u1 to u2 = sg vp - A^2 / (2J) in (u2 - u1) / A over
 * (u2^2 - u1^2) / (2A); the last phase adds A / J and u2 A / J +
 * A^3 / (3 J^2). The stop lasts |vp| / A + A / J over half of vp times
 * that, and the cruise covers the rest of d. */
static kc_real held_time(kc_real vp, kc_real sg, kc_real d, kc_real v0, kc_real a0, kc_real A, kc_real J)
{
    kc_real iJ = KC_R(1.0) / J, iA = KC_R(1.0) / A; /* three divisions in all */
    kc_real u0 = sg * v0, as = sg * a0, jt = as > A ? -J : J, tj = A * iJ;
    kc_real t1 = (as > A ? as - A : A - as) * iJ;
    kc_real u1 = u0 + (as > A ? as * as - A * A : A * A - as * as) * (KC_R(0.5) * iJ); /* u0 + as t1 + jt t1^2 / 2 */
    kc_real x1 = t1 * (u0 + t1 * (KC_R(0.5) * as + t1 * jt * (KC_R(1.0) / KC_R(6.0))));
    kc_real u2 = sg * vp - KC_R(0.5) * A * tj;
    kc_real t_change = t1 + (u2 - u1) * iA + tj;
    kc_real d_change =
        sg * (x1 + (u2 * u2 - u1 * u1) * (KC_R(0.5) * iA) + u2 * tj + A * tj * tj * (KC_R(1.0) / KC_R(3.0)));
    kc_real ts = kc_fabs(vp) * iA + tj;
    return t_change + ts + (d - d_change - KC_R(0.5) * vp * ts) / vp;
}

/* Keeps the bracket (vh: T - duration <= 0, vl: >= 0) tight with a new
 * point v of value f. */
static void narrow(kc_real v, kc_real f, kc_real *vh, kc_real *th, kc_real *vl, kc_real *tl)
{
    if (!kc_isfinite(f))
        return;
    if (f <= KC_R(0.0)) {
        if (kc_fabs(v) < kc_fabs(*vh) && kc_fabs(v) > kc_fabs(*vl)) {
            *vh = v;
            *th = f;
        }
    } else if (kc_fabs(v) > kc_fabs(*vl) && kc_fabs(v) < kc_fabs(*vh)) {
        *vl = v;
        *tl = f;
    }
}

/* A stretched profile without a cruise to take up the rounding of its
 * duration (a gap plan, the push, the rest after the optimum): its end
 * moved to duration, into prof. */
static kc_status moved(kc_scurve *prof, kc_scurve *r, kc_real duration, kc_real dt)
{
    r->T = duration;
    r->ticks = kc_profile_ticks(duration, dt);
    if (r->ticks < 0)
        return KC_E_CAPACITY;
    *prof = *r;
    return KC_OK;
}

/* The push (kinctl/scurve.h): from (f->v0, f->a0) the
 * acceleration pushed further from zero at jerk J for t1, then the
 * time-optimal plan to f->d from there: its duration (KC_REAL_MAX when
 * there is none). */
static kc_real push_time(const dfun *f, kc_real t1)
{
    kc_scurve h;
    kc_real p = KC_R(0.0), v = f->v0, a = f->a0;
    advance(&p, &v, &a, a > KC_R(0.0) ? f->J : -f->J, t1);
    /* Only to a state the speed limit holds: v moves with a, which keeps
     * its sign, and with a ramped out it must stay within vmax too. */
    if (!(kc_fabs(v + a * kc_fabs(a) / (KC_R(2.0) * f->J)) <= f->V) ||
        plan(&h, KC_R(0.0), v, a, f->d - p, f->V, f->A, f->A, f->J, KC_R(1.0), 0) != KC_OK)
        return KC_REAL_MAX;
    return t1 + h.T;
}

/* The push for t1 laid out before the time-optimal plan from where it
 * ends, into *r (the plan's phases shifted by t1). KC_E_LIMIT when that
 * plan leaves no phase for the push. */
static kc_status lay_push(kc_scurve *r, const kc_scurve *fast, kc_real vmax, kc_real A, kc_real J, kc_real t1,
                            kc_real dt)
{
    kc_real p = fast->p0, v = fast->v0, a = fast->a0, jp = a > KC_R(0.0) ? J : -J;
    advance(&p, &v, &a, jp, t1);
    kc_status st = plan(r, p, v, a, fast->p1, vmax, A, A, J, dt, 1);
    if (st != KC_OK)
        return st;
    if (r->n >= KC_SCURVE_MAX_PHASES)
        return KC_E_LIMIT;
    for (int i = r->n; i > 0; i--)
        set_phase(r, i, r->kind[i - 1], r->t_end[i - 1] + t1, r->tr[i - 1] + t1, r->pr[i - 1], r->vr[i - 1],
                  r->ar[i - 1], r->j[i - 1]);
    set_phase(r, 0, 1, t1, KC_R(0.0), fast->p0, fast->v0, fast->a0, jp);
    r->n++;
    r->p0 = fast->p0;
    r->v0 = fast->v0;
    r->a0 = fast->a0;
    r->gap = 1;
    return KC_OK;
}

/* dfun kinds 3 and 4: the duration of the slower stop (x = 1 / As) or of
 * the push (x = t1). */
static KC_SIZE_NOINLINE kc_real blocked_time(const dfun *f, kc_real x)
{
    return f->gap == 3 ? stop_slowed_time(f, KC_R(1.0) / x) : push_time(f, x);
}

/* The x in [xl, xh] where blocked_time reaches duration, from tl and th
 * (its durations at the ends less duration: tl < 0 <= th), by regula
 * falsi to 4 units of roundoff, or the nearest point after 48 steps: a
 * plan's duration carries the rounding of its own root searches, where
 * regula falsi stalls after about fifteen steps (measured on formerly
 * blocked stretches: as many of them reached in 48 steps as in 200, with
 * half the plans at the 99th percentile). 0 when the nearest point is off
 * by more than 64 units (a jump in the duration). */
static kc_real reach(const dfun *f, kc_real xl, kc_real tl, kc_real xh, kc_real th, kc_real duration)
{
    kc_real x, tol = KC_R(4.0) * KC_REAL_EPS * duration;
    bracket b = {xl, xh, tl, th, tl, th, 0};
    if (th == KC_R(0.0))
        return xh;
    for (int i = 0; i < 48 && bracket_next(&b, &x); i++) {
        kc_real t = blocked_time(f, x) - duration;
        if (kc_fabs(t) <= tol)
            return x;
        bracket_take(&b, x, t);
    }
    x = bracket_best(&b);
    return kc_fabs(x == b.lo ? b.flo : b.fhi) <= KC_R(16.0) * tol ? x : KC_R(0.0);
}

/* A moving start that no slower cruise stretches to duration
 * (kinctl/scurve.h, kc_scurve_plan_duration_from). First the time-optimal
 * plan with its stop (the last velocity change) held within As < A: its
 * duration grows as As falls, about as 1 / As, so As is halved from A
 * until the plan lasts at least duration (at most 64 times), then found
 * by regula falsi in 1 / As; the profile is laid out to last duration.
 * Else a push first: t1 from 0 (the optimum itself) towards where |a|
 * reaches A; halving between the last point that lasts less than duration
 * and the last beyond it (too long, or no plan) until one lasts at least
 * duration (at most 40 steps), then regula falsi between the two. Else
 * the optimum followed by rest at p1, when the plan leaves a phase for
 * the rest; KC_E_LIMIT otherwise. */
static kc_status stretch_blocked(kc_scurve *prof, const kc_scurve *fast, kc_real vmax, kc_real A, kc_real J,
                                 kc_real duration, kc_real dt)
{
    kc_real p0 = fast->p0, p1 = fast->p1, a0 = fast->a0, x = KC_R(0.0);
    dfun f = {3, fast->v0, a0, A, A, J, p1 - p0, vmax, NULL};
    kc_real xl = KC_R(1.0) / A, tl = fast->T - duration, xh = xl, th = tl, xu;
    for (int i = 0; i < 64 && th < KC_R(0.0); i++) {
        xl = xh;
        tl = th;
        xh *= KC_R(2.0);
        th = blocked_time(&f, xh) - duration;
    }
    if (th >= KC_R(0.0) && th < KC_REAL_MAX - duration)
        x = reach(&f, xl, tl, xh, th, duration);
    kc_real As = x > KC_R(0.0) ? KC_R(1.0) / x : A;
    kc_scurve r;
    kc_status st;
    f.gap = 4;
    xu = (A - kc_fabs(a0)) / J;
    if (As == A && a0 != KC_R(0.0) && xu > KC_R(0.0) && (tl = blocked_time(&f, xl = KC_R(0.0)) - duration) < KC_R(0.0)) {
        xh = xu;
        for (int i = 0; i < 40 && xl < xu; i++) {
            th = blocked_time(&f, xh) - duration;
            if (th >= KC_R(0.0) && th < KC_REAL_MAX - duration) {
                x = reach(&f, xl, tl, xh, th, duration);
                if (x == KC_R(0.0))
                    break;
                st = lay_push(&r, fast, vmax, A, J, x, dt);
                if (st == KC_OK)
                    return moved(prof, &r, duration, dt);
                if (st != KC_E_LIMIT)
                    return st;
                break;
            }
            if (th < KC_R(0.0)) {
                xl = xh;
                tl = th;
            } else {
                xu = xh;
            }
            xh = KC_R(0.5) * (xl + xu);
        }
    }
    st = plan(&r, p0, fast->v0, a0, p1, vmax, A, As, J, dt, 1);
    if (st != KC_OK)
        return st;
    if (As == A) {
        if (r.n >= KC_SCURVE_MAX_PHASES || !(r.T < duration))
            return KC_E_LIMIT;
        add_phase(&r, 3, duration, r.T, p1, KC_R(0.0), KC_R(0.0), KC_R(0.0));
    } else if (!r.gap) {
        return build_vp(prof, p0, fast->v0, a0, p1, r.vp, KC_R(0.0), A, As, J, duration, dt, 1);
    }
    return moved(prof, &r, duration, dt);
}

/* The slower cruise that stretches the moving start of fast to duration
 * (kinctl/scurve.h, kc_scurve_plan_duration_from), e the distance from
 * where stopping at once ends to the target (not within its rounding):
 * its velocity and duration into *vp_out and *tc_out. KC_E_LIMIT when no
 * slower cruise does (stretch_blocked()), KC_E_CAPACITY when the search
 * fails. */
static kc_status slower_cruise(const kc_scurve *fast, kc_real vmax, kc_real A, kc_real J, kc_real duration, kc_real e,
                               kc_real *vp_out, kc_real *tc_out)
{
    kc_real p0 = fast->p0, v0 = fast->v0, a0 = fast->a0, p1 = fast->p1, d = p1 - p0;
    kc_real s = e > KC_R(0.0) ? KC_R(1.0) : KC_R(-1.0);
    kc_real V = kc_isfinite(vmax) ? vmax : kc_max(kc_fabs(fast->vp), kc_fabs(v0)) + A * A / J;
    /* vh: the fastest cruise on that side: the optimum's own vp when it is
     * a plain plan on that side; else V, or where the cruise vanishes (the
     * root of d(vp) = d between 0 and s V). */
    kc_real vh = fast->vp;
    if (fast->gap || !(s * vh > KC_R(0.0))) {
        vh = s * V;
        dfun f = {0, v0, a0, A, A, J, KC_R(0.0), KC_R(0.0), NULL};
        kc_real dv = dist_of(&f, vh);
        if (s * (d - dv) < KC_R(0.0)) {
            kc_real f0 = -e;
            vh = root_of(&f, KC_R(0.0), vh, f0, dv - d, d);
            if (vh == KC_R(0.0))
                return KC_E_LIMIT;
        }
    }
    kc_real memo[2] = {KC_R(0.0) / KC_R(0.0), KC_R(0.0)};
    dfun t = {2, v0, a0, A, A, J, d, KC_R(0.0), memo};
    /* The optimum through vh is fast itself: its duration is T(vh). */
    kc_real th = (vh == fast->vp && !fast->gap ? fast->T : cruise_time_of(&t, vh, NULL)) - duration;
    if (!(th <= KC_R(0.0))) /* between the optimum and the slowest cruise this side allows */
        return KC_E_LIMIT;
    /* vl: where the cruise alone, e / vp, would fill the duration, then
     * halved until the plan lasts at least that long (the cruise grows as
     * 1 / vp: rarely more than a halving); its duration in closed form
     * where exact_fit holds. */
    kc_real vl = kc_min(kc_fabs(e) / duration, kc_fabs(vh)) * s, tl = KC_R(-1.0), tc = KC_R(-1.0), sg;
    int exact = 0;
    for (int i = 0; i < KC_SCURVE_MAX_ITER && tl < KC_R(0.0); i++) {
        if (i > 0)
            vl *= KC_R(0.5);
        exact = exact_fit(v0, a0, vl, vh, A, J, &sg);
        tl = (exact ? held_time(vl, sg, d, v0, a0, A, J) : cruise_time_of(&t, vl, NULL)) - duration;
    }
    if (!(tl >= KC_R(0.0)) || !kc_isfinite(tl))
        return KC_E_CAPACITY;
    /* Where the change and the stop both reach amax, d(vp) is quadratic
     * and the duration linear in vp, so (T(vp) - duration) vp is a
     * quadratic in vp: fitted through vh, vl and their harmonic mean, its
     * root is exact there and a close first guess elsewhere. When both
     * reach amax all the way from vl to vh (exact_fit), the quadratic's
     * leading coefficient is known, (sg + s) / (2A): the change's time
     * grows as sg vp / A and the stop's as s vp / A, and their distances
     * as vp^2 / (2A) of the same signs, which the cruise gives back. Then
     * vh and vl alone fix the quadratic, and its root needs no check. */
    kc_real vp = KC_R(0.0);
    if (exact) {
        vp = poly2_through((sg + s) / (KC_R(2.0) * A), vh, th * vh, vl, tl * vl, KC_R(0.0));
        tc = KC_R(0.0); /* within the bracket, which the cruise covers */
    }
    if (vp == KC_R(0.0)) {
        kc_real vm = KC_R(2.0) / (KC_R(1.0) / vh + KC_R(1.0) / vl);
        kc_real tm = cruise_time_of(&t, vm, NULL) - duration;
        vp = quad_root(vh, th * vh, vm, tm * vm, vl, tl * vl);
        if (vp != KC_R(0.0)) {
            kc_real tq = cruise_time_of(&t, vp, &tc) - duration;
            if (kc_fabs(tq) > KC_R(4.0) * KC_REAL_EPS * duration) {
                narrow(vp, tq, &vh, &th, &vl, &tl);
                vp = KC_R(0.0);
            }
        }
        narrow(vm, tm, &vh, &th, &vl, &tl);
    }
    if (vp == KC_R(0.0)) {
        /* In x = 1 / vp (1 / vh < 1 / vl for s > 0, the other way round
         * for s < 0: root_of orders them). */
        kc_real xh = KC_R(1.0) / vh, xl = KC_R(1.0) / vl;
        kc_real x = root_of(&t, xh, xl, th, tl, duration);
        vp = KC_R(1.0) / x;
        tc = memo[0] == x ? memo[1] : (d - dist_of(&t, vp)) / vp;
    }
    if (!(tc >= KC_R(0.0))) /* the change and the stop alone pass the target */
        return KC_E_LIMIT;
    *vp_out = vp;
    *tc_out = tc;
    return KC_OK;
}

/* The moving start (v0, a0) != 0 stretched to duration > fast->T, fast
 * its time-optimal plan (kinctl/scurve.h, kc_scurve_plan_duration_from). */
static kc_status stretch_from(kc_scurve *prof, const kc_scurve *fast, kc_real vmax, kc_real A, kc_real J,
                              kc_real duration, kc_real dt)
{
    kc_real p0 = fast->p0, v0 = fast->v0, a0 = fast->a0, p1 = fast->p1, d = p1 - p0, vp = KC_R(0.0), tc = KC_R(0.0);
    /* e: how far the target lies beyond where stopping at once ends; the
     * cruise runs towards it. */
    dfun f = {0, v0, a0, A, A, J, KC_R(0.0), KC_R(0.0), NULL};
    kc_real ds = dist_of(&f, KC_R(0.0)), e = d - ds;
    /* Else stop at once, then wait: also for an e within the rounding of
     * the distances (a start on its stop to p1, as the rest of a stretched
     * plan is: a tiny e of either sign would have it come back instead). */
    if (kc_fabs(e) > KC_R(8.0) * KC_REAL_EPS * (kc_fabs(p0) + kc_fabs(p1) + kc_fabs(ds))) {
        kc_status st = slower_cruise(fast, vmax, A, J, duration, e, &vp, &tc);
        if (st == KC_E_LIMIT)
            return stretch_blocked(prof, fast, vmax, A, J, duration, dt);
        if (st != KC_OK)
            return st;
    }
    return build_vp(prof, p0, v0, a0, p1, vp, tc, A, A, J, duration, dt, 1);
}

kc_status kc_scurve_plan_duration_from(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vmax,
                                       kc_real amax, kc_real jmax, kc_real duration, kc_real dt)
{
    kc_scurve fast;
    if (prof == NULL || !kc_isfinite(duration) || duration < KC_R(0.0))
        return KC_E_ARG;
    kc_status st = kc_scurve_plan(&fast, p0, v0, a0, p1, vmax, amax, jmax, dt);
    if (st != KC_OK)
        return st;
    return kc_scurve_stretch(prof, &fast, vmax, amax, jmax, duration);
}

kc_status kc_scurve_stretch(kc_scurve *prof, const kc_scurve *fast, kc_real vmax, kc_real amax, kc_real jmax,
                            kc_real duration)
{
    if (prof == NULL || fast == NULL || !kc_isfinite(duration) || duration < KC_R(0.0) ||
        !limits_ok(vmax, amax, jmax, fast->dt))
        return KC_E_ARG;
    if (duration <= fast->T) {
        if (duration < fast->T * (KC_R(1.0) - KC_R(8.0) * KC_REAL_EPS))
            return KC_E_LIMIT;
        /* Its header alone (kc_scurve_plan_time): a plain plan is laid out
         * from vp to last T, its cruise (if any) filling the time between
         * the change and the stop; a gap plan is planned again. */
        if (fast->n < 0 && !fast->gap)
            return build_vp(prof, fast->p0, fast->v0, fast->a0, fast->p1, fast->vp, KC_R(0.0), amax, amax, jmax, fast->T,
                            fast->dt, 1);
        if (fast->n < 0)
            return kc_scurve_plan(prof, fast->p0, fast->v0, fast->a0, fast->p1, vmax, amax, jmax, fast->dt);
        if (prof != fast)
            *prof = *fast;
        return KC_OK;
    }
    if (fast->v0 == KC_R(0.0) && fast->a0 == KC_R(0.0))
        return stretch_rest(prof, fast, amax, jmax, duration);
    return stretch_from(prof, fast, vmax, amax, jmax, duration, fast->dt);
}

/* The state at t in [0, T). */
static void state_at(const kc_scurve *prof, kc_real t, kc_scurve_state *out)
{
    int i = 0;
    while (i < prof->n - 1 && !(t < prof->t_end[i]))
        i++;
    if (t == KC_R(0.0)) {
        /* Exactly the start state (a stop evaluated from its end would
         * round it). */
        out->p = prof->p0;
        out->v = prof->v0;
        out->a = prof->a0;
        out->j = prof->j[0];
        out->phase = prof->kind[0];
        return;
    }
    kc_real tau = t - prof->tr[i], j = prof->j[i];
    out->p = prof->pr[i] + tau * (prof->vr[i] + tau * (KC_R(0.5) * prof->ar[i] + tau * j / KC_R(6.0)));
    out->v = prof->vr[i] + tau * (prof->ar[i] + KC_R(0.5) * tau * j);
    out->a = prof->ar[i] + j * tau;
    out->j = j;
    out->phase = prof->kind[i];
}

static void state_done(const kc_scurve *prof, kc_scurve_state *out)
{
    out->p = prof->p1;
    out->v = KC_R(0.0);
    out->a = KC_R(0.0);
    out->j = KC_R(0.0);
    out->phase = 4;
}

/* The state the tick rule's verdict st names: the end, or the law at t. */
static kc_status state_for(const kc_scurve *prof, kc_status st, kc_real t, kc_scurve_state *out)
{
    if (st == KC_DONE)
        state_done(prof, out);
    else if (st == KC_OK)
        state_at(prof, t, out);
    return st;
}

kc_status kc_scurve_eval(const kc_scurve *prof, int64_t k, kc_scurve_state *out)
{
    kc_real t = KC_R(0.0);
    if (prof == NULL || out == NULL)
        return KC_E_ARG;
    kc_status st = kc_profile_tick(k, prof->ticks, prof->dt, &t);
    return state_for(prof, st, t, out);
}

kc_status kc_scurve_eval_time(const kc_scurve *prof, kc_real t, kc_scurve_state *out)
{
    if (prof == NULL || out == NULL)
        return KC_E_ARG;
    return state_for(prof, kc_profile_time(t, prof->T), t, out);
}
