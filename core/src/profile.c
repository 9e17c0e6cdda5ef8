/* SPDX-License-Identifier: BSD-3-Clause */
/* profile.c - trapezoidal motion laws evaluated at integer ticks (seed 001
 * lab 4, eqs. 4.6-4.12 with the corrections listed in kinctl/profile.h). */
#include "kinctl/profile.h"

#include <stddef.h>

#include "profile_internal.h"

static int limits_ok(kc_real vmax, kc_real amax, kc_real dt)
{
    /* Written with ! so that NaN fails every test into an error. */
    return vmax > KC_R(0.0) && amax > KC_R(0.0) && kc_isfinite(amax) && dt > KC_R(0.0) && kc_isfinite(dt);
}

/* profile_internal.h */
int64_t kc_profile_ticks(kc_real T, kc_real dt)
{
    kc_real x = T / dt;
    if (!(x <= (kc_real)KC_PROFILE_MAX_TICKS))
        return -1;
    /* x >= 0: truncation is floor. Through int32_t (x <= 2^24 here), one
     * VCVT on an FPU-only-single core instead of libgcc's soft-double
     * float-to-int64 conversion. */
    int64_t n = (int32_t)x;
    /* The division rounds: settle on the exact grid the evaluation uses. */
    if ((kc_real)n * dt < T)
        n++;
    if (n > 0 && (kc_real)(n - 1) * dt >= T)
        n--;
    return n > KC_PROFILE_MAX_TICKS ? -1 : n;
}

/* profile_internal.h */
kc_status kc_profile_tick(int64_t k, int64_t ticks, kc_real dt, kc_real *t)
{
    if (k < 0)
        return KC_E_ARG;
    if (k >= ticks)
        return KC_DONE;
    /* k < ticks <= 2^24: exact in both precisions, and k dt < T. */
    *t = (kc_real)k * dt;
    return KC_OK;
}

/* profile_internal.h */
kc_status kc_profile_time(kc_real t, kc_real T)
{
    if (!(t >= KC_R(0.0)))
        return KC_E_ARG;
    return t >= T ? KC_DONE : KC_OK;
}

/* Fills the phases from the approach side s (+-1), the start speed v' = s v0
 * along it, the approach speed vc' > 0, phase 1's acceleration a1' (+-amax
 * along s) and the cruise time. */
static void fill(kc_profile *r, kc_real p0, kc_real v0, kc_real p1, kc_real s, kc_real vs, kc_real vc, kc_real a1,
                 kc_real amax, kc_real cruise_time)
{
    kc_real t1 = kc_fabs(vc - vs) / amax;
    r->p0 = p0;
    r->v0 = v0;
    r->p1 = p1;
    r->a1 = s * a1;
    r->vc = s * vc;
    /* Distance of phase 1: mean velocity times time. */
    r->pc = p0 + s * KC_R(0.5) * (vs + vc) * t1;
    r->a3 = -s * amax;
    r->t1 = t1;
    r->t2 = t1 + cruise_time;
    r->T = r->t2 + vc / amax;
}

static void fill_rest(kc_profile *r, kc_real p)
{
    r->p0 = r->p1 = r->pc = p;
    r->v0 = r->a1 = r->vc = r->a3 = KC_R(0.0);
    r->t1 = r->t2 = r->T = KC_R(0.0);
}

static kc_status finish(kc_profile *prof, kc_profile *r, kc_real dt)
{
    r->dt = dt;
    if (!kc_isfinite(r->T) || !kc_isfinite(r->pc))
        return KC_E_CAPACITY;
    r->ticks = kc_profile_ticks(r->T, dt);
    if (r->ticks < 0)
        return KC_E_CAPACITY;
    *prof = *r;
    return KC_OK;
}

/* Braking at once from (p0, v0): phases 1 and 2 empty. */
static void fill_stop(kc_profile *r, kc_real p0, kc_real v0, kc_real p1, kc_real amax)
{
    kc_real s = v0 > KC_R(0.0) ? KC_R(1.0) : KC_R(-1.0);
    fill_rest(r, p0);
    r->v0 = r->vc = v0;
    r->p1 = p1;
    r->a3 = -s * amax;
    r->T = kc_fabs(v0) / amax;
}

kc_status kc_profile_plan(kc_profile *prof, kc_real p0, kc_real v0, kc_real p1, kc_real vmax, kc_real amax,
                          kc_real dt)
{
    kc_profile r;
    if (prof == NULL || !kc_isfinite(p0) || !kc_isfinite(v0) || !kc_isfinite(p1) || !limits_ok(vmax, amax, dt))
        return KC_E_ARG;
    kc_real d = p1 - p0;
    if (!kc_isfinite(d))
        return KC_E_ARG;
    kc_real d_stop = v0 * kc_fabs(v0) / (KC_R(2.0) * amax);
    if (!kc_isfinite(d_stop))
        return KC_E_CAPACITY; /* a speed no profile of this capacity brakes */
    kc_real e = d - d_stop;
    if (e == KC_R(0.0)) {
        /* Braking at once stops on the target (or nothing moves at all). */
        if (v0 == KC_R(0.0))
            fill_rest(&r, p1);
        else
            fill_stop(&r, p0, v0, p1, amax);
        return finish(prof, &r, dt);
    }
    kc_real s = e > KC_R(0.0) ? KC_R(1.0) : KC_R(-1.0);
    kc_real ds = s * d, vs = s * v0;
    kc_real vc, a1, cruise;
    if (vs > vmax) {
        /* Too fast: slow down to vmax, cruise, brake. The braking distance
         * from v' is d_stop' < d', so the cruise is d' - v'^2 / (2A) > 0. */
        vc = vmax;
        a1 = -amax;
        cruise = (s * e) / vmax;
    } else {
        kc_real full = (KC_R(2.0) * vmax * vmax - vs * vs) / (KC_R(2.0) * amax);
        a1 = amax;
        if (ds >= full) {
            vc = vmax;
            cruise = (ds - full) / vmax;
        } else {
            /* Triangle: (vc^2 - v'^2)/(2A) + vc^2/(2A) = d'. The radicand is
             * A (d' - d_stop') + v'^2 > 0 up to rounding. */
            kc_real r2 = amax * ds + KC_R(0.5) * vs * vs;
            vc = kc_sqrt(kc_max(r2, KC_R(0.0)));
            if (vc < vs)
                vc = vs; /* rounding at d' = d_stop' */
            cruise = KC_R(0.0);
        }
    }
    if (!(vc > KC_R(0.0))) {
        /* Only when rounding swallowed e entirely: braking at once ends on
         * the target within rounding. */
        if (v0 == KC_R(0.0))
            fill_rest(&r, p1);
        else
            fill_stop(&r, p0, v0, p1, amax);
        r.p0 = p0;
        return finish(prof, &r, dt);
    }
    fill(&r, p0, v0, p1, s, vs, vc, a1, amax, cruise);
    return finish(prof, &r, dt);
}

kc_status kc_profile_plan_duration(kc_profile *prof, kc_real p0, kc_real p1, kc_real vmax, kc_real amax,
                                   kc_real duration, kc_real dt)
{
    kc_profile fast, r;
    kc_status st;
    if (prof == NULL || !kc_isfinite(duration) || duration < KC_R(0.0))
        return KC_E_ARG;
    st = kc_profile_plan(&fast, p0, KC_R(0.0), p1, vmax, amax, dt);
    if (st != KC_OK)
        return st;
    if (duration <= fast.T) {
        if (duration < fast.T * (KC_R(1.0) - KC_R(8.0) * KC_REAL_EPS))
            return KC_E_LIMIT;
        *prof = fast;
        return KC_OK;
    }
    kc_real d = kc_fabs(p1 - p0);
    kc_real s = p1 >= p0 ? KC_R(1.0) : KC_R(-1.0);
    /* v = 2D / (T + sqrt(T^2 - 4D/A)): the smaller root of v^2 - A T v +
     * A D = 0 written without cancellation. T > fast.T >= 2 sqrt(D/A), so
     * the radicand is positive up to rounding. */
    kc_real rad = duration * duration - KC_R(4.0) * d / amax;
    kc_real vc = KC_R(2.0) * d / (duration + kc_sqrt(kc_max(rad, KC_R(0.0))));
    kc_real cruise = duration - KC_R(2.0) * vc / amax;
    fill(&r, p0, KC_R(0.0), p1, s, KC_R(0.0), vc, amax, amax, kc_max(cruise, KC_R(0.0)));
    /* The phases add up to the requested duration up to rounding: take it
     * exactly, so synchronised axes share one T. */
    r.T = duration;
    if (r.t2 > duration)
        r.t2 = duration;
    if (r.t1 > r.t2)
        r.t1 = r.t2;
    return finish(prof, &r, dt);
}

kc_status kc_profile_plan_stop(kc_profile *prof, kc_real p0, kc_real v0, kc_real amax, kc_real dt)
{
    kc_profile r;
    if (prof == NULL || !kc_isfinite(p0) || !kc_isfinite(v0) || !limits_ok(KC_R(1.0), amax, dt))
        return KC_E_ARG;
    kc_real p1 = p0 + v0 * kc_fabs(v0) / (KC_R(2.0) * amax);
    if (!kc_isfinite(p1))
        return KC_E_CAPACITY;
    if (v0 == KC_R(0.0))
        fill_rest(&r, p0);
    else
        fill_stop(&r, p0, v0, p1, amax);
    return finish(prof, &r, dt);
}

/* The state at t in [0, T). */
static void state_at(const kc_profile *prof, kc_real t, kc_profile_state *out)
{
    if (t == KC_R(0.0)) {
        /* Exactly the start state, whichever phase comes first (phase 3,
         * evaluated from its end, would round it). */
        out->p = prof->p0;
        out->v = prof->v0;
        out->a = prof->t1 > KC_R(0.0) ? prof->a1 : prof->t2 > KC_R(0.0) ? KC_R(0.0) : prof->a3;
        out->phase = prof->t1 > KC_R(0.0) ? 1 : prof->t2 > KC_R(0.0) ? 2 : 3;
        return;
    }
    if (t < prof->t1) {
        out->p = prof->p0 + (prof->v0 + KC_R(0.5) * prof->a1 * t) * t;
        out->v = prof->v0 + prof->a1 * t;
        out->a = prof->a1;
        out->phase = 1;
    } else if (t < prof->t2) {
        out->p = prof->pc + prof->vc * (t - prof->t1);
        out->v = prof->vc;
        out->a = KC_R(0.0);
        out->phase = 2;
    } else {
        /* Backwards from the end (corrected 4.12): exact at T. */
        kc_real r = prof->T - t;
        out->p = prof->p1 + KC_R(0.5) * prof->a3 * r * r;
        out->v = -prof->a3 * r;
        /* T - t carries the rounding of T, an ulp of the whole duration
         * (large in float for long moves): never let it lift the speed
         * above the cruise speed the phase brakes from. */
        if (kc_fabs(out->v) > kc_fabs(prof->vc))
            out->v = prof->vc;
        out->a = prof->a3;
        out->phase = 3;
    }
}

static void state_done(const kc_profile *prof, kc_profile_state *out)
{
    out->p = prof->p1;
    out->v = KC_R(0.0);
    out->a = KC_R(0.0);
    out->phase = 4;
}

/* The state the tick rule's verdict st names: the end, or the law at t. */
static kc_status state_for(const kc_profile *prof, kc_status st, kc_real t, kc_profile_state *out)
{
    if (st == KC_DONE)
        state_done(prof, out);
    else if (st == KC_OK)
        state_at(prof, t, out);
    return st;
}

kc_status kc_profile_eval(const kc_profile *prof, int64_t k, kc_profile_state *out)
{
    kc_real t = KC_R(0.0);
    if (prof == NULL || out == NULL)
        return KC_E_ARG;
    kc_status st = kc_profile_tick(k, prof->ticks, prof->dt, &t);
    return state_for(prof, st, t, out);
}

kc_status kc_profile_eval_time(const kc_profile *prof, kc_real t, kc_profile_state *out)
{
    if (prof == NULL || out == NULL)
        return KC_E_ARG;
    return state_for(prof, kc_profile_time(t, prof->T), t, out);
}
