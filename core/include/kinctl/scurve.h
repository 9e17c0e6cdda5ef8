/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/scurve.h - jerk-limited one-dimensional motion ("double S"),
 * planned once and evaluated at integer ticks like kinctl/profile.h's
 * trapezoid.
 *
 * A profile takes a coordinate p from a start state (p0, v0, a0) to rest at
 * a target p1 with |v| <= vmax, |a| <= amax and |j| <= jmax, where j is the
 * jerk (the rate of the acceleration). It is a chain of at most seven
 * phases of constant jerk on half-open time intervals; over a phase of
 * jerk j starting at (p, v, a), after a time tau:
 *     a(tau) = a + j tau
 *     v(tau) = v + a tau + j tau^2 / 2
 *     p(tau) = p + v tau + a tau^2 / 2 + j tau^3 / 6
 * so acceleration is continuous and piecewise linear, velocity C1, position
 * C2. Sources: Biagiotti & Melchiorri, "Trajectory Planning for Automatic
 * Machines and Robots", Springer 2008, sec. 3.4 (double S, eqs. 3.30-3.33
 * for rest to rest); Haschke, Weitnauer & Ritter, "On-line planning of
 * time-optimal, jerk-limited trajectories", IROS 2008 (a moving start: the
 * velocity change to a peak, cruise, stop); Berscheid & Kroeger,
 * "Jerk-limited Real-time Trajectory Generation with Arbitrary Target
 * States", RSS 2021 (Ruckig; its profiles for a target at rest are the ones
 * below, and the benchmark compares with it).
 *
 * Velocity change. The fastest way from (v, a), |a| <= A, to a velocity w
 * with zero acceleration, J = jmax: let vn = v + a |a| / (2J), the velocity
 * reached by taking a to zero at once. If w > vn (w < vn: mirror every sign)
 * the acceleration rises to a peak ap, holds it for th and falls to zero:
 *     (ap^2 - a^2) / (2J) + ap th + ap^2 / (2J) = w - v
 * with ap = A and th = (w - v - (2 A^2 - a^2) / (2J)) / A >= 0 when that is
 * non-negative (three phases: +J, 0, -J), otherwise th = 0 and
 *     ap = sqrt(J (w - v) + a^2 / 2)          (two phases: +J, -J).
 * A start with a > A (outside the limit) first ramps down to A: phases
 * -J for (a - A)/J, 0 for th = (w - vn) / A, -J for A/J.
 *
 * Rest to rest (v0 = a0 = 0, Biagiotti & Melchiorri 3.4 with
 * v0 = v1 = 0), D = |p1 - p0|, V = vmax, A = amax, J = jmax: with Tj the
 * jerk phase, Ta the whole acceleration (= deceleration) time and Tv the
 * cruise:
 *     V J >= A^2:  Tj = A / J,  Ta = Tj + V / A      (A is reached)
 *     V J <  A^2:  Tj = sqrt(V / J),  Ta = 2 Tj        (A is not reached)
 *     Tv = D / V - Ta                                  (3.31 with symmetry)
 * If Tv > 0 that is the profile (seven phases: +J, 0, -J, 0, -J, 0, +J,
 * speed V). Otherwise there is no cruise (Tv = 0) and the peak speed is
 * below V:
 *     D >= 2 A^3 / J^2:  Tj = A / J,  Ta = Tj / 2 + sqrt(Tj^2 / 4 + D / A)
 *                        (from D = A (Ta - Tj) Ta: six phases)
 *     otherwise:         Tj = (D / (2J))^(1/3),  Ta = 2 Tj
 *                        (from D = 2 J Tj^3: four phases, A not reached)
 * The duration is T = 2 Ta + Tv and the peak speed vp = A (Ta - Tj) (or
 * J Tj^2 when A is not reached). This is time-optimal: it is bang-bang in
 * jerk with every limit that can bind binding.
 *
 * From a moving start (the general plan). Every motion to rest has a last
 * velocity extremum vp, where a = 0: the plan is the velocity change from
 * (v0, a0) to vp, a cruise at vp for Tc >= 0, and the velocity change from
 * vp to 0 (the stop). Its distance d(vp) + vp Tc must equal d = p1 - p0:
 *     d >= d(V):   vp = V,  Tc = (d - d(V)) / V
 *     d <= d(-V):  vp = -V, Tc = (d(-V) - d) / V
 *     otherwise:   Tc = 0 and vp in (-V, V) solves d(vp) = d.
 * With vn = v0 + a0 |a0| / (2J), the plain branches are vp <= min(vn, 0)
 * and vp >= max(vn, 0): there the change ends on the other side of zero
 * acceleration than the stop begins, so vp is a true extremum, and d
 * increases along each branch; each root is found in its bracket by
 * regula falsi (Illinois variant, falling back to halving; at most
 * KC_SCURVE_MAX_ITER steps, about ten in practice, stopping at the
 * rounding of the distances). Where the change holds amax and the stop
 * reaches it (|vp| >= A^2 / J), d(vp) is a quadratic with leading
 * coefficient s / A (s the branch's sign): its root there comes from two
 * points and is checked by one evaluation. A vp of the other sign than
 * d is a start that must overshoot and come back.
 * The gap family covers the distances between the branches' ends d(0)
 * and d(vn): a0 is ramped towards zero by a fraction s in [0, 1] at jerk
 * J, then the fastest change to rest follows (s = 0: stop at once; s = 1:
 * a0 ramped out, then the stop from vn), s found the same way. Of the
 * roots found the fastest is the plan.
 * A start with |v0| > V is slowed to |vp| <= V by the first change (the
 * speed exceeds V only there); a start with |a0| > A is first ramped back
 * to A at jerk J; a start accelerating beyond V overshoots V as little as
 * J allows (up to |vn|). Every phase is bang-bang in jerk or a cruise at
 * V, so the plan is time-optimal for a start at rest and within these two
 * families otherwise. The time-optimal profile can have a valley of
 * acceleration that neither family holds (jerk +, -, +, - without a
 * return to zero acceleration, Ruckig's UDUD). Measured against Ruckig's
 * one-dimensional optimum by tools/bench/run_interp_bench.sh (puma560 and
 * panda limits): starts within the limits (|v0| <= 0.8 vmax,
 * |a0| <= 0.8 amax), 130,000 joints, none longer by more than 1e-6;
 * starts up to 1.5 times outside them, 0.6 % (puma560) and 0.03 % (panda)
 * of the joints longer, by at most 14 % (and some shorter than Ruckig's,
 * which first brakes into the limits). tests/unit/test_scurve.c bounds the
 * shortfall by replanning from the middle of random plans.
 *
 * Stretched to a duration T >= T_opt (synchronisation; rest to rest):
 * amax and jmax are kept and the cruise speed lowered to v (the standard
 * approach, as kinctl/profile.h does for the trapezoid). With T = 2 Ta + Tv
 * and D = v (Ta + Tv):
 *     v >= A^2 / J (A reached, Ta = v / A + A / J):
 *         v^2 / A - (T - A / J) v + D = 0, the smaller root
 *         v = 2 D / (T' + sqrt(T'^2 - 4 D / A)),  T' = T - A / J
 *     v <  A^2 / J (Tj = x, v = J x^2, Ta = 2x, Tv = T - 4x):
 *         x^3 - (T / 2) x^2 + D / (2J) = 0,  the root in (0, T/4]:
 *         x = (T / 6) (1 - cos th + sqrt(3) sin th),
 *         th = acos(1 - 54 D / (J T^3)) / 3
 *         (the trigonometric solution of the cubic; T >= T_opt makes
 *         T^3 >= 32 D / J, so the argument is in [-11/16, 1]), followed by
 *         two Newton steps to polish.
 * The first form applies when its v is at least A^2 / J, the second
 * otherwise. T >= T_opt gives v <= the optimal peak <= vmax, so a
 * solution exists for every T >= T_opt.
 *
 * Ticks. As kinctl/profile.h: tick k is t = k dt computed from k; the
 * duration in ticks is the first k with k dt >= T, and from that tick on
 * the state is exactly (p1, 0, 0). The stop phases are evaluated backwards
 * from (p1, 0, 0) at T, so the end is exact whatever the rounding of the
 * earlier phases; the last tick before the end has |a| <= J dt and
 * |v| <= J dt^2 / 2, so acceleration changes by at most J dt per tick
 * across the end too. Sampling a piecewise-linear acceleration whose slope
 * is at most J never shows a change of more than J dt per tick.
 *
 * Planning is bounded (closed forms; for a moving start at most three
 * root searches of at most KC_SCURVE_MAX_ITER steps, and to stretch it
 * two more and at most KC_SCURVE_MAX_ITER halvings, or with a slowed stop
 * or a push at most 64 and 40 halvings and 48 regula falsi steps each,
 * every step a plan: measured on formerly blocked stretches of one joint,
 * median 8 us, 99th percentile 88 us, at most 122 us on the benchmark
 * machine) and
 * allocation-free;
 * evaluation is O(1) (a scan of at most seven phase ends and a cubic).
 * Every function is pure and safe to call in the control cycle.
 */
#ifndef KINCTL_SCURVE_H
#define KINCTL_SCURVE_H

#include <stdint.h>

#include "kinctl/decls.h"
#include "kinctl/real.h"
#include "kinctl/status.h"

KC_BEGIN_DECLS

/* Most phases: velocity change (3), cruise (1), stop (3). */
#define KC_SCURVE_MAX_PHASES 7

/* Most root-finding steps of one branch of a moving-start plan. */
#define KC_SCURVE_MAX_ITER 200

/* A planned profile. Plain data: copy it freely; set it only through the
 * kc_scurve_plan* functions. Phase i covers [t_end[i-1], t_end[i]) (from 0
 * for i = 0) with jerk j[i]; its state at time t is the cubic above around
 * the reference instant tr[i] (its start, or for the stop its end, so the
 * polynomial argument t - tr[i] may be negative) with reference state
 * (pr, vr, ar)[i]. kind[i] is 1 for the velocity change, 2 for the cruise,
 * 3 for the stop (and a rest at p1 after it that a stretch may add,
 * kc_scurve_plan_duration_from). */
typedef struct kc_scurve {
    kc_real p0, v0, a0;  /* start state */
    kc_real p1;          /* target: the position from T on */
    kc_real vp;          /* velocity at the last extremum (cruise velocity, signed); 0 for a gap plan */
    int gap;             /* 1 for a plan of the gap family (see above) */
    int n;               /* phases, 0..KC_SCURVE_MAX_PHASES */
    kc_real t_end[KC_SCURVE_MAX_PHASES];
    kc_real tr[KC_SCURVE_MAX_PHASES];
    kc_real pr[KC_SCURVE_MAX_PHASES], vr[KC_SCURVE_MAX_PHASES], ar[KC_SCURVE_MAX_PHASES];
    kc_real j[KC_SCURVE_MAX_PHASES];
    int kind[KC_SCURVE_MAX_PHASES];
    kc_real T;     /* duration (s) */
    kc_real dt;    /* tick period (s) */
    int64_t ticks; /* first tick with k dt >= T */
} kc_scurve;

/* The state at one instant; phase is 1 (velocity change), 2 (cruise) or 3
 * (stop) while moving and 4 once finished. j is the jerk of the phase. */
typedef struct kc_scurve_state {
    kc_real p, v, a, j;
    int phase;
} kc_scurve_state;

/* Time-optimal profile (see above for moving starts) from (p0, v0, a0) to
 * rest at p1 within vmax (> 0, +infinity allowed), amax and jmax (> 0,
 * finite). dt > 0: tick period (s). Returns KC_OK; KC_E_ARG for a NULL
 * prof, a non-finite state, target or dt, a bad limit, or p1 - p0
 * overflowing; KC_E_CAPACITY when the duration exceeds
 * KC_PROFILE_MAX_TICKS ticks (kinctl/profile.h) or a speed overflows.
 * prof is untouched on error. */
kc_status kc_scurve_plan(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vmax,
                         kc_real amax, kc_real jmax, kc_real dt);

/* Rest-to-rest profile from p0 to p1 lasting exactly `duration` (s), for
 * synchronising several axes: amax and jmax kept, cruise speed lowered
 * (formulas above). A duration equal to the time-optimal one, or shorter by
 * at most 8 units of roundoff (relative), gives the time-optimal profile; a
 * shorter one is KC_E_LIMIT. KC_E_ARG for a negative or non-finite
 * duration; other errors as kc_scurve_plan. prof is untouched on error. */
kc_status kc_scurve_plan_duration(kc_scurve *prof, kc_real p0, kc_real p1, kc_real vmax, kc_real amax,
                                  kc_real jmax, kc_real duration, kc_real dt);

/* Profile from the moving start (p0, v0, a0) to rest at p1 lasting exactly
 * `duration` (s), for synchronising moving axes: amax and jmax kept, the
 * cruise slowed. With e the distance from where stopping at once ends to
 * the target, the plan is the plain one (change to vp, cruise, stop) with
 * vp on the side of e, the cruise covering the rest, and |vp| between 0
 * and the fastest cruise that side allows (vmax, or where the cruise
 * vanishes): its duration
 *     T(vp) = t_change(vp) + t_stop(vp) + (d - d(vp)) / vp
 * grows without bound as vp -> 0, and T(vp) = duration is solved by the
 * same root search in x = 1 / vp, where the cruise's share of T is
 * linear, bracketed by the fastest cruise and a vp = e / duration (where
 * the cruise alone would fill the duration) halved until T(vp) >= duration;
 * about eight evaluations of T. Where the change holds amax (or starts
 * beyond it) and the stop reaches it all the way between those two, T is
 * linear and d(vp) quadratic in vp with leading coefficient (sg + s) / (2A)
 * (sg the side of the change, s of vp), so (T(vp) - duration) vp is a
 * quadratic fixed by the two ends alone, T at the slow end in closed form,
 * and the search is one root of it. e = 0 (within the rounding of the
 * distances, 8 eps (|p0| + |p1| + the stop's distance): a start on its
 * stop to p1) is the stop followed by a wait. A start at rest is
 * kc_scurve_plan_duration.
 * No slower cruise lasts the duration where it is longer than the
 * optimum but shorter than the fastest cruise on the side of e lasts
 * (the optimum on the other branch or in the gap family), or where it
 * needs a cruise below vn whose change and stop alone already pass the
 * target (d(vp) > d; both seen mostly with small jerk limits). There the
 * stop is slowed instead: the time-optimal plan (both families) with its
 * stop, the last velocity change to rest, held within As < amax while
 * the change keeps amax. Its duration grows as As falls, about as 1 / As
 * (the stop's |vp| / As): As is halved until the plan lasts at least the
 * duration, then found by regula falsi in 1 / As (each step a plan), and
 * the profile laid out to last the duration exactly (a plain plan's
 * cruise, if any, takes up the rounding). The shapes are Ruckig's with an
 * acceleration held below its limit (Berscheid & Kroeger 2021, the
 * step-2 profiles with a3 != 0). Where the slowed plan's duration jumps
 * past the duration as As falls (its family changes), the acceleration
 * is first pushed further from zero at jmax for t1 (up to amax, to a
 * state the speed limit holds) and the time-optimal plan follows from
 * there: Ruckig's valley of acceleration (jerk -, +, -, + without a
 * return to zero) and its overshoots; t1 from 0 (the optimum) by halving
 * towards where that plan lasts at least the duration, then regula
 * falsi (each step a plan). Where neither reaches it, the time-optimal
 * plan is followed by rest at p1 until the duration: a target at rest can
 * always be reached early and held, so every duration from the optimum
 * on is reached. Measured over random starts the limits hold
 * (|v0| <= vmax, |a0| <= amax, jmax 0.1-50): of 320,000 stretches to
 * 1-10 times the optimum, 1.6 % need more than a slower cruise, and
 * 0.03-0.05 % end with the rest at p1 (a joint arriving early).
 * Returns KC_E_LIMIT for a duration shorter than the optimum (beyond 8
 * units of roundoff), or needing the rest after an optimum of seven
 * phases (no phase left for the rest; not seen in those measurements);
 * other errors as kc_scurve_plan. prof is untouched on error. */
kc_status kc_scurve_plan_duration_from(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vmax,
                                       kc_real amax, kc_real jmax, kc_real duration, kc_real dt);

/* As kc_scurve_plan_duration_from, from the time-optimal plan `fast`
 * already made by kc_scurve_plan with the same limits (saves planning it
 * again when synchronising). prof may alias fast. */
kc_status kc_scurve_stretch(kc_scurve *prof, const kc_scurve *fast, kc_real vmax, kc_real amax, kc_real jmax,
                            kc_real duration);

/* The fastest stop from the moving state (p0, v0, a0) within amax and
 * jmax: the velocity change to zero (see "Velocity change" above, two or
 * three phases), ending at rest wherever it ends (p1, exact from its
 * tick on, as every profile). Without a cruise, vmax plays no part: a
 * start beyond a speed limit slows from there. It is also the stop of
 * least distance: each phase changes the velocity as fast as the limits
 * allow towards zero, so a stop on a planned path within the same limits
 * never passes that path's own end. Returns KC_OK; KC_E_ARG for a NULL
 * prof, a non-finite state or dt, or a bad limit; KC_E_CAPACITY as
 * kc_scurve_plan. prof is untouched on error. */
kc_status kc_scurve_plan_stop(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real amax, kc_real jmax,
                              kc_real dt);

/* The range a profile covers, over [0, T] and its end: the extreme
 * positions and the largest |v| and |a|. */
typedef struct kc_scurve_extent {
    kc_real p_min, p_max;
    kc_real v_max, a_max;
} kc_scurve_extent;

/* The extent of a planned profile, exactly from its phases' polynomials
 * (positions at the phase ends and at the roots of v, speeds at the roots
 * of a): at most seven phases of five candidates. KC_E_ARG for NULL
 * arguments. Cycle-safe. */
kc_status kc_scurve_extent_of(const kc_scurve *prof, kc_scurve_extent *out);

/* State at tick k >= 0 (t = k dt): KC_OK while moving (k < ticks), KC_DONE
 * from tick `ticks` on (exactly p1, 0, 0, jerk 0, phase 4), KC_E_ARG for
 * NULL arguments or k < 0 (out untouched). */
kc_status kc_scurve_eval(const kc_scurve *prof, int64_t k, kc_scurve_state *out);

/* State at time t >= 0 (s), off the tick grid: KC_OK for t < T, KC_DONE
 * for t >= T, KC_E_ARG for NULL arguments, t < 0 or NaN. */
kc_status kc_scurve_eval_time(const kc_scurve *prof, kc_real t, kc_scurve_state *out);

KC_END_DECLS

#endif /* KINCTL_SCURVE_H */
