/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/profile.h - one-dimensional motion laws, planned once and evaluated
 * at integer ticks (seed 001 lab 4, eqs. 4.6-4.12; labs 5 and 6 reuse them).
 *
 * A profile takes a coordinate p (rad, m, or the dimensionless fraction the
 * interpolators use) from a start state to rest at a target p1, with the
 * speed |v| <= vmax and the acceleration |a| <= amax. It is made of three
 * constant-acceleration phases on half-open time intervals, as
 * vectors/README.md numbers them:
 *     phase 1 [0, t1):   a = a1, from v0 to the cruise velocity vc
 *     phase 2 [t1, t2):  a = 0,  v = vc                (cruise)
 *     phase 3 [t2, T):   a = a3, from vc to 0           (braking)
 *     phase 4 [T, inf):  p = p1, v = a = 0              (finished)
 * Any phase may have zero length (phase 2 of a triangular profile, phases 1
 * and 2 of a stopping profile); a zero-length interval contains no instant.
 *
 * Lab 4 from rest (v0 = 0), distance D = |p1 - p0|, v = vmax, A = amax:
 *     t_p  = v / A                 (4.6)  accelerating time
 *     q_p  = v^2 / (2 A)           (4.7)  accelerating distance
 *     q_pv = D - 2 q_p             (4.8)  cruising distance
 *     t_pv = q_pv / v              (4.9)  cruising time, T = 2 t_p + t_pv
 *     p = p0 + s A t^2/2                          on [0, t_p)           (4.10)
 *     p = p0 + s (q_p + v (t - t_p))              on [t_p, t_p + t_pv)  (4.11)
 *     p = p1 - s A (T - t)^2/2                    on [t_p + t_pv, T)    (4.12)
 * with s = sign(p1 - p0). The seed's (4.11) uses the absolute t and (4.12)
 * lacks the square (vectors/README.md typos #10, #11); its Pascal example
 * tests strict inequalities, so the phase boundaries fall into the braking
 * branch (#13): the forms above are the corrected ones. When D < v^2/A the
 * cruise vanishes (triangular profile, not in the seed, #14):
 *     v_peak = sqrt(D A),  t_p = v_peak / A,  T = 2 t_p.
 * Phase 3 is evaluated backwards from T, so the profile ends exactly on p1
 * whatever the rounding of the earlier phases.
 *
 * From a moving start (v0 != 0; re-targeting a moving axis). Let
 * d = p1 - p0 and d_stop = v0 |v0| / (2A), where braking at once would stop.
 * The final approach comes from the side s = sign(d - d_stop) (if
 * d = d_stop exactly, braking at once is the whole profile). With d' = s d
 * and v' = s v0, the approach speed is
 *     v' > vmax:                        vc = vmax,  a1 = -A (slow down first)
 *     d' >= (2 vmax^2 - v'^2) / (2A):   vc = vmax,  a1 = +A (trapezoid)
 *     otherwise:  vc = sqrt(A d' + v'^2/2),         a1 = +A (triangle)
 * (times s), t1 = |vc - v'| / A, t3 = vc / A, cruise t2 - t1 = (d' - (vc^2 -
 * v'^2)/(2 a1) - vc^2/(2A)) / vc. A start moving away from the target, or
 * too fast to stop before it, is one phase-1 acceleration that brakes through
 * zero and speeds up towards the target. The acceleration never exceeds A;
 * the speed never exceeds max(vmax, |v0|) and falls to vmax as fast as A
 * allows when |v0| > vmax.
 *
 * Stretched to a duration T (synchronisation; rest to rest): the
 * acceleration limit is kept and the cruise speed lowered to the root of
 * D = v (T - v/A) that does not exceed A T / 2:
 *     v = 2 D / (T + sqrt(T^2 - 4 D / A)),  t_p = v / A,  t_pv = T - 2 v / A,
 * defined when T is at least the triangular minimum 2 sqrt(D / A); if T is
 * at least the time-optimal duration for (vmax, A) then v <= vmax.
 *
 * Ticks. A plan keeps its tick period dt; tick k is time t = k dt, computed
 * from k (never accumulated). The duration in ticks, kc_profile.ticks, is the
 * first k with k dt >= T: from that tick on the state is exactly (p1, 0, 0).
 * The last tick before it has |v| <= A dt, so the velocity changes by at
 * most A dt per tick across the end too. Durations are capped at
 * KC_PROFILE_MAX_TICKS ticks, so that k dt is exact in both precisions.
 *
 * Planning is O(1) and allocation-free; evaluation is O(1), branch-light
 * and pure. Every function is safe to call in the control cycle. The
 * jerk-limited profile, with the same tick rule, is kinctl/scurve.h.
 */
#ifndef KINCTL_PROFILE_H
#define KINCTL_PROFILE_H

#include <stdint.h>

#include "kinctl/decls.h"
#include "kinctl/real.h"
#include "kinctl/status.h"

KC_BEGIN_DECLS

/* Longest profile in ticks: 2^24, below which every k dt is exact in float
 * (4.6 hours at 1 kHz). */
#define KC_PROFILE_MAX_TICKS 16777216

/* A planned profile. Plain data: copy it freely; read the fields, but set
 * them only through the kc_profile_plan* functions. */
typedef struct kc_profile {
    kc_real p0, v0;    /* start position and velocity */
    kc_real p1;        /* target: the position from T on */
    kc_real a1;        /* acceleration of phase 1 */
    kc_real vc;        /* velocity of phase 2 (signed; 0 when stopping) */
    kc_real pc;        /* position at the start of phase 2 */
    kc_real a3;        /* acceleration of phase 3 */
    kc_real t1, t2, T; /* ends of phases 1, 2, 3 (s); T is the duration */
    kc_real dt;        /* tick period (s) */
    int64_t ticks;     /* first tick with k dt >= T */
} kc_profile;

/* The state at one instant. phase is 1, 2 or 3 while moving and 4 once
 * finished. */
typedef struct kc_profile_state {
    kc_real p, v, a;
    int phase;
} kc_profile_state;

/* Time-optimal profile from (p0, v0) to rest at p1 within vmax (> 0,
 * +infinity allowed: no speed limit) and amax (> 0, finite); see above for
 * a start with |v0| > vmax. dt > 0 is the tick period (s). Returns KC_OK;
 * KC_E_ARG for a NULL prof, a non-finite p0, v0, p1 or dt, a non-positive
 * or NaN limit, an infinite amax, or p1 - p0 overflowing; KC_E_CAPACITY when
 * the duration exceeds KC_PROFILE_MAX_TICKS ticks. prof is untouched on
 * error. */
kc_status kc_profile_plan(kc_profile *prof, kc_real p0, kc_real v0, kc_real p1, kc_real vmax, kc_real amax,
                          kc_real dt);

/* Rest-to-rest profile from p0 to p1 lasting exactly `duration` (s), for
 * synchronising several axes: amax kept, cruise speed lowered (formula
 * above). A duration equal to the time-optimal one, or shorter by at most 8
 * units of roundoff (relative), gives the time-optimal profile; a shorter
 * one is KC_E_LIMIT. KC_E_ARG for a negative or non-finite duration; other
 * errors as kc_profile_plan. prof is untouched on error. */
kc_status kc_profile_plan_duration(kc_profile *prof, kc_real p0, kc_real p1, kc_real vmax, kc_real amax,
                                   kc_real duration, kc_real dt);

/* Stopping profile: brake from (p0, v0) at amax to rest, at
 * p1 = p0 + v0 |v0| / (2 amax) after T = |v0| / amax. Errors as
 * kc_profile_plan. */
kc_status kc_profile_plan_stop(kc_profile *prof, kc_real p0, kc_real v0, kc_real amax, kc_real dt);

/* State at tick k >= 0 (t = k dt). Returns KC_OK while moving (k < ticks),
 * KC_DONE from tick `ticks` on (state exactly p1, 0, 0, phase 4), KC_E_ARG
 * for NULL arguments or k < 0 (out untouched). */
kc_status kc_profile_eval(const kc_profile *prof, int64_t k, kc_profile_state *out);

/* State at time t >= 0 (s), for callers off the tick grid (checks against
 * reference data, plots). Returns KC_OK for t < T, KC_DONE for t >= T,
 * KC_E_ARG for NULL arguments, t < 0 or NaN (out untouched). */
kc_status kc_profile_eval_time(const kc_profile *prof, kc_real t, kc_profile_state *out);

KC_END_DECLS

#endif /* KINCTL_PROFILE_H */
