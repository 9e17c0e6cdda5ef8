/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl_stop.c - stopping: on the path (interpolated segments by their
 * path parameter, paths by their plan time), in joint space, resuming, and
 * faults (kinctl/ctrl.h). */
#include "ctrl_internal.h"
#include "path_internal.h"
#include "size_internal.h"

#include <string.h>

/* The active segment driven by drive from the last setpoint on (its tick
 * 0, as for every segment). */
static KC_SIZE_NOINLINE void drive_from_here(kc_ctrl *c, kc_ctrl_drive drive)
{
    c->drive = drive;
    c->k0 = c->cycle - 1;
}

/* A joint path's q' and q'' at plan time tau and, where room is not NULL,
 * each joint's room for the jerk its time law adds (kinctl/ctrl.h):
 * qddd_max less the path's own |q'''| there (which tau'^3 <= 1 scales),
 * but at least half of qddd_max (where the path's own jerk comes near its
 * limit or beyond, with times given). */
static void path_jerk_room(const kc_ctrl *c, kc_real tau, kc_real *d1, kc_real *d2, kc_real *room)
{
    const kc_path *p = &c->plan.path;
    kc_real q[KC_MAX_JOINTS];
    int end = !(tau < p->duration), k = kc_path_find_piece(p, tau);
    kc_real x = tau - p->start[k];
    if (end) /* the end state, where the path's jerk is 0 */
        kc_path_eval_time(p, tau, q, d1, d2);
    else
        kc_path_eval_piece(p, k, x, q, d1, d2);
    for (int j = 0; room != NULL && j < c->chain->n_joints; j++) {
        kc_real d3 = KC_R(0.0), m = c->chain->joints[j].limits.qddd_max;
        for (int i = p->n_coeffs - 1; i >= 3 && !end; i--)
            d3 = d3 * x + (kc_real)(i * (i - 1) * (i - 2)) * p->c[k][i][j];
        room[j] = kc_max(m - kc_fabs(d3), KC_R(0.5) * m);
    }
}

/* Largest |q'' tau'^2 + q' tau''| / qdd_max (Cartesian: the tool point's
 * acceleration over its limit) on sampled instants of a change of tau' at
 * the constant rate a for the time D, from plan time tau0 at rate r0: at
 * most 1 when it keeps every limit. A stop is (tau, rate, -C, rate / C), a
 * start from rest (tau, 0, C, 1 / C), the ramp into the end (T - 1/(2C),
 * 1, -C, 1 / C). Under a jerk-limited law a joint path's 3 |q''| tau' |a|
 * (the jerk 3 q'' tau' tau'' adds) counts too, against half its room
 * (path_jerk_room; kc_ctrl_path_tau_jerk leaves tau''' the other half),
 * tau' being the sample's rate for a ramp (the jerk-limited ramp, its
 * |tau''| within |a|, has no more where it reaches the same tau: it
 * starts or ends at rest there), and r0 for a stop (which brakes later
 * than at the constant rate). */
static kc_real path_ramp_load(const kc_ctrl *c, kc_real tau0, kc_real r0, kc_real a, kc_real D, int ramp)
{
    const kc_goal *g = &c->goal;
    int n = c->chain->n_joints, jerk = kc_ctrl_goal_profile(c, g) == KC_PROFILE_JERK;
    kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS], worst = KC_R(0.0);
    kc_ctrl_scaled_limits(c, g, vmax, amax);
    kc_real a_cart = kc_ctrl_cart_limits(&c->cfg, g).a;
    for (int i = 0; i <= STOP_SAMPLES; i++) {
        kc_real t = D * (kc_real)i / (kc_real)STOP_SAMPLES;
        kc_real r = r0 + a * t, at = kc_max(tau0 + r0 * t + KC_R(0.5) * a * t * t, KC_R(0.0));
        if (g->kind == KC_GOAL_PATH) {
            kc_real d1[KC_MAX_JOINTS], d2[KC_MAX_JOINTS], room[KC_MAX_JOINTS];
            path_jerk_room(c, at, d1, d2, jerk ? room : NULL);
            for (int j = 0; j < n; j++) {
                worst = kc_max(worst, kc_fabs(d2[j] * r * r + d1[j] * a) / amax[j]);
                if (jerk)
                    worst = kc_max(worst, KC_R(6.0) * kc_fabs(d2[j] * a) * (ramp ? r : r0) / room[j]);
            }
        } else {
            kc_path_pose s;
            kc_path_cart_eval_time(&c->plan.path_cart, at, &s);
            kc_vec3 acc;
            for (int k = 0; k < 3; k++)
                acc.v[k] = s.a.v[k] * r * r + s.v.v[k] * a;
            worst = kc_max(worst, kc_vec3_norm(&acc) / a_cart);
        }
    }
    return worst;
}

/* The deceleration of tau' a path stop may use from (tau, rate), or 0 when
 * no rate tried keeps the limits now (the path is braking hard itself: try
 * again next tick). */
static kc_real path_stop_rate(const kc_ctrl *c, kc_real tau, kc_real rate)
{
    const kc_goal *g = &c->goal;
    int n = c->chain->n_joints;
    kc_real q[KC_MAX_JOINTS], d1[KC_MAX_JOINTS], d2[KC_MAX_JOINTS];
    kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS];
    kc_ctrl_scaled_limits(c, g, vmax, amax);
    /* Start from what the speed alone allows, then halve. */
    kc_real dec = INF;
    if (g->kind == KC_GOAL_PATH) {
        kc_path_eval_time(&c->plan.path, tau, q, d1, d2);
        for (int j = 0; j < n; j++)
            if (kc_fabs(d1[j]) > KC_R(0.0))
                dec = kc_min(dec, amax[j] / kc_fabs(d1[j]));
    } else {
        kc_path_pose s;
        kc_path_cart_eval_time(&c->plan.path_cart, tau, &s);
        kc_real speed = kc_vec3_norm(&s.v);
        if (speed > KC_R(0.0))
            dec = kc_ctrl_cart_limits(&c->cfg, g).a / speed;
    }
    if (!kc_isfinite(dec))
        dec = KC_R(1.0) / c->cfg.dt; /* standing still: stop within a tick */
    for (int tries = 0; tries < 6; tries++) {
        if (path_ramp_load(c, tau, rate, -dec, rate / dec, 0) <= KC_R(1.0))
            return dec;
        dec *= KC_R(0.5);
    }
    return KC_R(0.0);
}

/* The number of bisection steps refining a ramp's rate between the first
 * of the halvings that keeps the limits and the one before it (within
 * 1/16 of the rate that just does, on the samples). */
#define RAMP_RATE_STEPS 4

static int ramp_fits(const kc_ctrl *c, kc_real tau0, kc_real T, kc_real C)
{
    return path_ramp_load(c, tau0, KC_R(0.0), C, KC_R(1.0) / C, 1) <= KC_R(1.0) &&
           path_ramp_load(c, T - KC_R(0.5) / C, KC_R(1.0), -C, KC_R(1.0) / C, 1) <= KC_R(1.0);
}

kc_real kc_ctrl_path_ramp_rate(const kc_ctrl *c, kc_real tau0)
{
    kc_real T = kc_ctrl_path_duration(c);
    kc_real C = KC_R(1.0) / (KC_R(10.0) * c->cfg.dt); /* a ramp of at least ten ticks */
    for (int tries = 0; tries < 16; tries++) {
        if (ramp_fits(c, tau0, T, C)) {
            kc_real hi = KC_R(2.0) * C;
            for (int i = 0; i < RAMP_RATE_STEPS && tries > 0; i++) {
                kc_real m = KC_R(0.5) * (C + hi);
                if (ramp_fits(c, tau0, T, m))
                    C = m;
                else
                    hi = m;
            }
            return C;
        }
        C *= KC_R(0.5);
    }
    return KC_R(0.0);
}

kc_real kc_ctrl_path_ramp_jerk(const kc_ctrl *c, kc_real tau0, kc_real C)
{
    kc_real T = kc_ctrl_path_duration(c);
    kc_real J = kc_ctrl_path_tau_jerk(c, tau0, T, C);
    /* A ramp from rest to tau' = 1 within C and J covers (1 / C + C / J)
     * / 2 of plan time, and so does the ramp into the end: a larger J
     * only shortens them. */
    kc_real d = KC_R(0.5) * (KC_R(1.0) / C + C / J);
    if (!kc_isfinite(J) || !(J > KC_R(0.0)) || KC_R(2.0) * d >= T - tau0)
        return J;
    return kc_min(kc_ctrl_path_tau_jerk(c, tau0, tau0 + d, C), kc_ctrl_path_tau_jerk(c, T - d, T, C));
}

kc_real kc_ctrl_path_tau_jerk(const kc_ctrl *c, kc_real tau0, kc_real tau1, kc_real A)
{
    const kc_goal *g = &c->goal;
    kc_real J = INF;
    kc_interp_limits lim = kc_ctrl_cart_limits(&c->cfg, g);
    if (!kc_ctrl_path_jerk_law(c, g))
        return INF;
    /* A rate between two samples h apart exceeds the nearer one by about
     * h / 2 times the derivative there: each sample counts with it (the
     * tool's angular speed, whose derivative a path pose does not carry,
     * as sampled). */
    kc_real h = (tau1 - tau0) / (kc_real)STOP_SAMPLES;
    for (int i = 0; i <= STOP_SAMPLES; i++) {
        kc_real tau = kc_max(tau0 + h * (kc_real)i, KC_R(0.0));
        if (g->kind == KC_GOAL_PATH) {
            kc_real d1[KC_MAX_JOINTS], d2[KC_MAX_JOINTS], room[KC_MAX_JOINTS];
            path_jerk_room(c, tau, d1, d2, room);
            for (int j = 0; j < c->chain->n_joints; j++) {
                kc_real v = kc_fabs(d1[j]) + KC_R(0.5) * h * kc_fabs(d2[j]);
                if (v > KC_R(0.0))
                    J = kc_min(J, kc_max(room[j] - KC_R(3.0) * A * kc_fabs(d2[j]), KC_R(0.5) * room[j]) / v);
            }
        } else {
            kc_path_pose s;
            kc_path_cart_eval_time(&c->plan.path_cart, tau, &s);
            kc_real v = kc_vec3_norm(&s.v) + KC_R(0.5) * h * kc_vec3_norm(&s.a);
            kc_real w = kc_vec3_norm(&s.w);
            if (v > KC_R(0.0))
                J = kc_min(J, lim.j / v);
            if (w > KC_R(0.0))
                J = kc_min(J, lim.dj / w);
        }
    }
    return J;
}

int kc_ctrl_path_ramped(const kc_ctrl *c, const kc_goal *g)
{
    if (g->method == KC_PATH_LAGRANGE || (g->method == KC_PATH_SPLINE && g->spline_end == KC_PATH_SPLINE_NATURAL))
        return 1; /* moving at its ends */
    /* At rest at its ends, where a cubic spline's acceleration, and a
     * parabolic blend's, steps. */
    return kc_ctrl_goal_profile(c, g) == KC_PROFILE_JERK &&
           (g->method == KC_PATH_SPLINE || (g->method == KC_PATH_BLEND && g->blend == KC_PATH_BLEND_PARABOLIC));
}

int kc_ctrl_path_jerk_law(const kc_ctrl *c, const kc_goal *g)
{
    return g->kind == KC_GOAL_PATH ? kc_ctrl_goal_profile(c, g) == KC_PROFILE_JERK
                                   : kc_isfinite(kc_ctrl_cart_limits(&c->cfg, g).j);
}

kc_status kc_ctrl_path_plan_ramp(kc_ctrl *c, int gentlest)
{
    kc_real z = KC_R(0.0), T = kc_ctrl_path_duration(c), C = kc_ctrl_path_ramp_rate(c, z);
    if (!(C > z) && !gentlest)
        return KC_E_LIMIT;
    if (!(C > z))
        C = KC_R(1.0);
    kc_real Jt = kc_ctrl_path_ramp_jerk(c, z, C);
    if (kc_isfinite(Jt)) {
        kc_status st = kc_scurve_plan(&c->ramp, z, z, z, T, KC_R(1.0), C, Jt, c->cfg.dt);
        c->ramp_on = st == KC_OK;
        return st;
    }
    c->drive = KC_DRIVE_PROFILE;
    return kc_profile_plan(&c->drive_prof, z, z, T, KC_R(1.0), C, c->cfg.dt);
}

kc_real kc_ctrl_path_duration(const kc_ctrl *c)
{
    return c->goal.kind == KC_GOAL_PATH ? c->plan.path.duration : c->plan.path_cart.pos.duration;
}

void kc_ctrl_joint_stop(kc_ctrl *c, int sync, kc_ctrl_state then)
{
    int n = c->chain->n_joints;
    kc_real T = KC_R(0.0);
    for (int j = 0; j < n; j++)
        T = kc_max(T, kc_fabs(c->qd[j]) / c->chain->joints[j].limits.qdd_max);
    for (int j = 0; j < n; j++) {
        kc_real a = c->chain->joints[j].limits.qdd_max;
        if (sync && T > KC_R(0.0) && c->qd[j] != KC_R(0.0))
            a = kc_fabs(c->qd[j]) / T;
        if (kc_profile_plan_stop(&c->jstop_prof[j], c->q[j], c->qd[j], a, c->cfg.dt) != KC_OK)
            kc_profile_plan_stop(&c->jstop_prof[j], c->q[j], KC_R(0.0), KC_R(1.0), c->cfg.dt);
    }
    c->jstop_k0 = c->cycle - 1;
    c->jstop = 1;
    c->after_stop = then;
    c->active = 0;
}

int kc_ctrl_joint_stop_eval(const kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd)
{
    int done = 1;
    int jerk = kc_ctrl_halting(c);
    for (int j = 0; j < c->chain->n_joints; j++) {
        if (jerk) {
            kc_scurve_state s;
            if (kc_scurve_eval(&c->plan.halt[j], c->cycle - c->jstop_k0, &s) != KC_DONE)
                done = 0;
            q[j] = s.p;
            qd[j] = s.v;
            qdd[j] = s.a;
            continue;
        }
        kc_profile_state s;
        if (kc_profile_eval(&c->jstop_prof[j], c->cycle - c->jstop_k0, &s) != KC_DONE)
            done = 0;
        q[j] = s.p;
        qd[j] = s.v;
        qdd[j] = s.a;
    }
    return done;
}

/* A servo stream's stop (kinctl/ctrl.h), a Cartesian stop that leaves
 * its path (kc_ctrl_stop_leave_path) and a path's stop under a replacing
 * goal (ctrl_blend.c): every joint from its (q, qd, qdd) to rest by
 * kc_scurve_plan_stop into halt (plan.halt: a servo goal has no plan of
 * its own there; a stopped Cartesian goal needs its own no more).
 * Synchronised by phase where it can be: each
 * joint's limits scaled with its speed, A_i = ca |qd_i| and
 * J_i = cj |qd_i|, ca and cj the largest that keep every joint within
 * its qdd_max and qddd_max. From qdd = 0 every joint's velocity is then
 * the same function of time times its start (the phase times A_i / J_i
 * and |qd_i| / A_i, and which phases there are, are the same for all):
 * the joints end on the same tick on the straight line of qd, as the
 * acceleration-limited stop's do: the fastest stop of that shape, as long
 * as the slowest joint's own where one joint binds both bounds, somewhat
 * longer where one joint's acceleration and another's jerk bind; with
 * qdd != 0 they end near the same tick. A joint whose |qdd|
 * is beyond its scaled A_i (it would first ramp down at a scaled jerk: a
 * longer stop, an overshoot) stops as fast as its own limits allow
 * instead. With Cartesian bounds cart (a stop of a Cartesian goal), ca
 * and cj also keep the tool's acceleration and jerk of that straight
 * stop, its twist times ca and cj, within them. 0 when a
 * stop cannot be planned (a chain without jerk limits:
 * kc_scurve_plan_stop takes no infinite jmax), or would carry a joint's
 * speed past its qd_max: one accelerating near its speed limit, whose
 * acceleration falls to 0 at jerk J only after its speed has grown by
 * qdd^2 / (2 J) (the final check would refuse that setpoint and fault). */
int kc_ctrl_halt_plan(const kc_ctrl *c, kc_scurve *halt, const kc_interp_limits *cart)
{
    int n = c->chain->n_joints;
    kc_real ca = INF, cj = INF;
    for (int i = 0; i < n; i++) {
        const kc_joint_limits *l = &c->chain->joints[i].limits;
        kc_real v = kc_fabs(c->qd[i]);
        if (v > KC_R(0.0)) {
            ca = kc_min(ca, l->qdd_max / v);
            cj = kc_min(cj, l->qddd_max / v);
        }
    }
    if (cart != NULL) {
        /* The tool's twist J qd scaled alike: its speed and angular speed
         * times ca and cj within the Cartesian bounds. */
        kc_jacobian jac;
        kc_real t[6];
        kc_fk_jacobian(c->chain, c->q, &jac, NULL);
        for (int r = 0; r < 6; r++) {
            t[r] = KC_R(0.0);
            for (int i = 0; i < n; i++)
                t[r] += jac.m[r][i] * c->qd[i];
        }
        kc_real v = kc_sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        kc_real w = kc_sqrt(t[3] * t[3] + t[4] * t[4] + t[5] * t[5]);
        if (v > KC_R(0.0))
            ca = kc_min(ca, cart->a / v), cj = kc_min(cj, cart->j / v);
        if (w > KC_R(0.0))
            ca = kc_min(ca, cart->dw / w), cj = kc_min(cj, cart->dj / w);
    }
    for (int i = 0; i < n; i++) {
        const kc_joint_limits *l = &c->chain->joints[i].limits;
        kc_real v = kc_fabs(c->qd[i]), a = l->qdd_max, jm = l->qddd_max;
        if (v > KC_R(0.0) && kc_fabs(c->qdd[i]) <= ca * v)
            a = ca * v, jm = cj * v;
        if (c->qd[i] * c->qdd[i] > KC_R(0.0) &&
            v + KC_R(0.5) * c->qdd[i] * c->qdd[i] / jm > l->qd_max * (KC_R(1.0) + c->cfg.limit_slack))
            return 0;
        if (kc_scurve_plan_stop(&halt[i], c->q[i], c->qd[i], c->qdd[i], a, jm, c->cfg.dt) != KC_OK)
            return 0;
    }
    return 1;
}

/* The share of the jerk limits a jerk-limited joint move's stop for a
 * replacing goal is planned with. A line, an arc or a Cartesian path
 * superposed on that stop (ctrl_blend.c) adds the IK step's correction to
 * it, while the stop's leading joint brakes at its jerk limit: with the
 * whole limit, the sum went past it by up to 9.9e-7 of it (in
 * test_ctrl_cartstop's streams, 412 of the 561 verdicts on such goals
 * between 1 and 1 + 1e-6; none with this share, the largest 0.9999987). */
#define PREEMPT_JERK_SHARE (KC_R(1.0) - KC_R(1e-5))

/* Whether q lies within joint i's position limits. */
static int within_range(const kc_ctrl *c, int i, kc_real q)
{
    const kc_joint_limits *l = &c->chain->joints[i].limits;
    return q >= l->q_min && q <= l->q_max;
}

/* The stop of a jerk-limited joint move (kinctl/ctrl.h): on its line by
 * u's fastest stop, or joint by joint; for a replacing goal within
 * PREEMPT_JERK_SHARE of the jerk limits. */
static void jerk_stop(kc_ctrl *c)
{
    const kc_interp_joint *pj = &c->plan.joint;
    kc_real share = c->stop_intent == INTENT_PREEMPT ? PREEMPT_JERK_SHARE : KC_R(1.0);
    int64_t j = (c->cycle - 1) - c->k0; /* the last setpoint's tick */
    if (kc_ctrl_joint_on_line(c) && (c->drive == KC_DRIVE_NOMINAL || c->drive == KC_DRIVE_SCURVE)) {
        kc_scurve_state u;
        kc_scurve_eval(c->drive == KC_DRIVE_SCURVE ? &c->drive_scurve : &pj->su, j < 0 ? 0 : j, &u);
        kc_real a = pj->u_amax, jm = pj->u_jmax;
        if (!kc_isfinite(a) || !kc_isfinite(jm))
            a = jm = KC_R(1.0); /* a zero motion: nothing to stop */
        /* Within the share; the whole limit where that stop would end
         * beyond a joint's position limits (a move braking into its end
         * at the limit stops a little past it with less). */
        int ok = kc_scurve_plan_stop(&c->drive_scurve, u.p, u.v, u.a, a, jm * share, c->cfg.dt) == KC_OK;
        for (int i = 0; ok && share < KC_R(1.0) && i < pj->n; i++)
            ok = within_range(c, i, pj->q0[i] + pj->dq[i] * c->drive_scurve.p1);
        if (!ok && share < KC_R(1.0))
            ok = kc_scurve_plan_stop(&c->drive_scurve, u.p, u.v, u.a, a, jm, c->cfg.dt) == KC_OK;
        if (ok) {
            drive_from_here(c, KC_DRIVE_SCURVE);
            return;
        }
    }
    /* Joint by joint, from the last setpoint, at the goal's limits. */
    kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS];
    kc_ctrl_scaled_limits(c, &c->goal, vmax, amax);
    for (int i = 0; i < c->chain->n_joints; i++) {
        kc_scurve *h = &c->plan.halt[i];
        kc_real jm = c->chain->joints[i].limits.qddd_max;
        if (share < KC_R(1.0) && kc_scurve_plan_stop(h, c->q[i], c->qd[i], c->qdd[i], amax[i], jm * share, c->cfg.dt) == KC_OK &&
            within_range(c, i, h->p1))
            continue; /* within the share, as on the line */
        if (kc_scurve_plan_stop(h, c->q[i], c->qd[i], c->qdd[i], amax[i], jm, c->cfg.dt) != KC_OK)
            kc_scurve_plan_stop(h, c->q[i], KC_R(0.0), KC_R(0.0), KC_R(1.0), KC_R(1.0), c->cfg.dt);
    }
    drive_from_here(c, KC_DRIVE_HALT);
}

/* The shares of qdd_max and qddd_max a Cartesian stop's joints are held
 * to, its least share of the tool's bounds, and the share of qddd_max
 * its resume's first jerk is held to (joint_bounded_stop). */
#define STOP_ACC_SHARE KC_R(0.8)
#define STOP_JERK_SHARE KC_R(0.6)
#define STOP_SHARE_MIN KC_R(0.0625)
#define STOP_RESUME_SHARE KC_R(0.25)
#define STOP_TRACK_LEAST KC_R(0.1)
#define STOP_HALVINGS 4 /* 1 / 2^4 = STOP_SHARE_MIN */

/* The joints' largest rate per unit of the path's parameter over their
 * jerk limits, max |qd_i / v| / qddd_max_i, for joint velocities qd at
 * u' = v. */
static kc_real rate_per_u(const kc_ctrl *c, const kc_real *qd, kc_real v)
{
    kc_real qu = KC_R(0.0);
    for (int i = 0; i < c->chain->n_joints; i++)
        qu = kc_max(qu, kc_fabs(qd[i] / v) / c->chain->joints[i].limits.qddd_max);
    return qu;
}

/* joint_bounded_stop's estimate at share k: the largest of every joint's
 * acceleration and jerk over its share of qdd_max and qddd_max (within
 * the shares: at most 1). */
static kc_real stop_load(const kc_ctrl *c, kc_real v, kc_real a, kc_real dec, kc_real jm, kc_real k)
{
    kc_real D = kc_max(k * dec, kc_fabs(a)), load = KC_R(0.0);
    kc_real r = a > KC_R(0.0) ? KC_R(1.0) + a * a / (KC_R(2.0) * k * jm * v) : KC_R(1.0);
    for (int i = 0; i < c->chain->n_joints; i++) {
        const kc_joint_limits *l = &c->chain->joints[i].limits;
        kc_real qu = kc_fabs(c->qd[i] / v), cc = kc_fabs(c->qdd[i] - c->qd[i] / v * a);
        load = kc_max(load, (qu * D + cc * r * r) / (STOP_ACC_SHARE * l->qdd_max));
        load = kc_max(load, (qu * k * jm + KC_R(3.0) * cc * r * D / v) / (STOP_JERK_SHARE * l->qddd_max));
    }
    return load;
}

/* A Cartesian stop's bounds on its parameter u (a line's or an arc's u, a
 * Cartesian path's tau), from u' = v > 0 and u'' = a at the last
 * setpoint: *dec and *jm scaled by the largest k of 1, 1/2, ...,
 * STOP_SHARE_MIN whose stop keeps every joint's estimated acceleration and
 * jerk within STOP_ACC_SHARE of qdd_max and STOP_JERK_SHARE of qddd_max
 * (else the k whose estimate is least: from a rising u'', a smaller k
 * lets u' rise further first, and the joints' estimate grows with it; an
 * arc stopped early while it sped up, at the least k, 1/16, went on
 * speeding up over most of its path, its PUMA 560 joints to their speed
 * limits and 128 times beyond their jerk limits), *dec not below -a (a
 * stop already braking harder goes on from there) and k not below
 * a^2 / (v jm) (a braking u'' comes back to zero within half of v: with
 * less jerk the stop would overshoot rest and turn back). The joints'
 * rate per unit of u is q_u = qd / v,
 * and c = qdd - q_u a is their acceleration from the path's curve,
 * q_uu v^2. While the stop lasts u' <= w = v + a^2 / (2 k jm) (v but for
 * a rising u'', which the stop first brings to zero) and
 * |u''| <= D = max(k dec, |a|), so with r = w / v
 *     |qdd|  <= |q_u| D + |c| r^2,
 *     |qddd| <= |q_u| k jm + 3 |q_uu| u' |u''| <= |q_u| k jm + 3 |c| r D / v,
 * the path's own third derivative q_uuu u'^3, and how q_u and q_uu change
 * over the stop, left to the shares. At the tool's limits alone, where the
 * Jacobian amplifies them, the PUMA 560's joints went up to 185 times
 * beyond their jerk limits in a stop (test_ctrl_cartstop.c).
 * A resume from where it comes to rest (kc_ctrl_resume) takes the same k
 * at most, and at most (not below STOP_SHARE_MIN) the k whose |q_u| k jm
 * is within STOP_RESUME_SHARE of qddd_max, q_u the largest seen while the
 * stop ran (kc_ctrl_stop_track; at the stop's start alone it was half of
 * that at rest on a PUMA 560 line) and by the goal's dry run over its
 * whole path (kc_goal.qu): from rest, the IK step's first tick corrects
 * what error the tool had left, and stepped the joints' jerk up to twice
 * |q_u| k jm; and a slow ramp ends its last jerk phase far ahead, where
 * |q_u| may be larger than anywhere the stop came (a PUMA 560 Cartesian
 * path resumed at 0.16 of its length: the ramp's last phase at 0.71, the
 * joints' jerk 1.28 times their limits for 25 ticks, with the stop's
 * q_u alone). */
static void joint_bounded_stop(kc_ctrl *c, kc_real v, kc_real a, kc_real *dec, kc_real *jm)
{
    if (!(v > KC_R(0.0)))
        return;
    kc_real k = KC_R(1.0), least = STOP_SHARE_MIN, best = KC_R(1.0), load = INF;
    if (a < KC_R(0.0))
        least = kc_min(kc_max(least, a * a / (v * *jm)), KC_R(1.0));
    for (int h = 0;; h++) {
        kc_real kk = kc_max(k, least), l = stop_load(c, v, a, *dec, *jm, kk);
        if (l < load)
            load = l, best = kk;
        if (l <= KC_R(1.0) || kk <= least || h >= STOP_HALVINGS)
            break;
        k *= KC_R(0.5);
    }
    k = best;
    c->resume_share = k;
    c->stop_v0 = v;
    c->stop_qu = kc_max(c->stop_qu, rate_per_u(c, c->qd, v));
    *jm *= k;
    *dec = kc_max(k * *dec, a < KC_R(0.0) ? -a : KC_R(0.0));
}

/* The bounds of u's first three derivatives of the active joint move,
 * line or arc, and its speed law; a zero motion (infinite bounds: nothing
 * to stop or resume) gets bounds of 1. */
static kc_profile_kind seg_u_bounds(const kc_ctrl *c, kc_real *v, kc_real *a, kc_real *jm)
{
    kc_profile_kind kind;
    if (c->goal.kind == KC_GOAL_JOINT) {
        *v = c->plan.joint.u_vmax, *a = c->plan.joint.u_amax, *jm = c->plan.joint.u_jmax;
        kind = c->plan.joint.kind;
    } else if (c->goal.kind == KC_GOAL_LINE) {
        *v = c->plan.line.u_vmax, *a = c->plan.line.u_amax, *jm = c->plan.line.u_jmax;
        kind = c->plan.line.kind;
    } else {
        *v = c->plan.arc.u_vmax, *a = c->plan.arc.u_amax, *jm = c->plan.arc.u_jmax;
        kind = c->plan.arc.kind;
    }
    if (!kc_isfinite(*a))
        *a = KC_R(1.0);
    if (!kc_isfinite(*jm))
        *jm = KC_R(1.0);
    return kind;
}

kc_real kc_ctrl_rate_per_u(const kc_ctrl *c)
{
    if (!c->active || c->state != KC_CTRL_MOVING || c->drive != KC_DRIVE_NOMINAL || c->blend.on ||
        !kc_ctrl_is_cart(c->goal.kind) || c->goal.kind == KC_GOAL_SERVO)
        return KC_R(0.0);
    kc_real top = KC_R(1.0), a, jm; /* u's top rate: a path's own, tau' = 1 */
    if (!kc_ctrl_is_path(c->goal.kind))
        seg_u_bounds(c, &top, &a, &jm);
    kc_profile_state u;
    kc_ctrl_drive_state(c, (c->cycle - 1) - c->k0, &u);
    return u.v >= STOP_TRACK_LEAST * top ? rate_per_u(c, c->qd, u.v) : KC_R(0.0);
}

/* A jerk-limited line's or arc's stop from u's state into drive_scurve,
 * within the plan's bounds dec on u'' and jm on u''' scaled for the joints
 * (joint_bounded_stop). Where that stop would pass u = 1, the gentlest
 * between it and the plan's own bounds that does not (a bisection of
 * SEG_STOP_STEPS steps), the plan's own at worst: that one is the stop of
 * least distance, which never passes the end but by rounding (1 + 2.2e-16
 * seen from a law braking at those bounds; then it ends there). 0 when no
 * stop can be planned. */
#define SEG_STOP_STEPS 8
static int seg_jerk_stop(kc_ctrl *c, const kc_profile_state *u, kc_real dec, kc_real jm)
{
    kc_scurve s, t;
    kc_real D = dec, J = jm, lo = KC_R(0.0), hi = KC_R(1.0);
    joint_bounded_stop(c, u->v, u->a, &D, &J);
    if (kc_scurve_plan_stop(&s, u->p, u->v, u->a, D, J, c->cfg.dt) != KC_OK)
        return 0;
    if (s.p1 > KC_R(1.0) && (D < dec || J < jm)) {
        if (kc_scurve_plan_stop(&s, u->p, u->v, u->a, dec, jm, c->cfg.dt) != KC_OK)
            return 0;
        for (int i = 0; i < SEG_STOP_STEPS; i++) {
            kc_real m = KC_R(0.5) * (lo + hi);
            if (kc_scurve_plan_stop(&t, u->p, u->v, u->a, D + m * (dec - D), J + m * (jm - J), c->cfg.dt) == KC_OK &&
                t.p1 <= KC_R(1.0)) {
                s = t, hi = m;
            } else {
                lo = m;
            }
        }
    }
    if (s.p1 > KC_R(1.0) && s.p1 <= KC_R(1.0) + KC_R(16.0) * KC_REAL_EPS)
        s.p1 = KC_R(1.0);
    c->drive_scurve = s;
    return 1;
}

/* A jerk-limited stop of a path's tau from the state u at deceleration
 * dec, its bound on tau''' from the path's rates where it goes
 * (kc_ctrl_path_tau_jerk): over twice the distance of the constant-rate
 * stop first, then again over the distance the stop took while that is
 * longer (a lower bound makes a longer stop; at most four plans). 1: in
 * drive_scurve; 0 for the trapezoid's law, or no plan; -1 when it would
 * pass the path's end T, where the drive under way comes to rest sooner
 * (every drive of a path ends at rest at T). */
static int path_scurve_stop(kc_ctrl *c, const kc_profile_state *u, kc_real dec, kc_real T)
{
    kc_scurve s;
    kc_real end = u->p + u->v * u->v / dec;
    for (int i = 0; i < 4; i++) {
        kc_real Jt = kc_ctrl_path_tau_jerk(c, u->p, kc_min(end, T), kc_max(dec, kc_fabs(u->a)));
        kc_real D = dec;
        if (c->goal.kind == KC_GOAL_PATH_CART && kc_isfinite(Jt))
            joint_bounded_stop(c, u->v, u->a, &D, &Jt);
        /* A stop from a ramp whose tau' still rises brings tau'' to 0
         * before tau' passes 1 (the path's own rate): at the jerk that
         * ramp itself has there at most (in its last phase, the one
         * that just does: tau''^2 / (2 (1 - tau'))). */
        if (u->a > KC_R(0.0) && u->v < KC_R(1.0))
            Jt = kc_max(Jt, u->a * u->a / (KC_R(2.0) * (KC_R(1.0) - u->v)));
        if (!kc_isfinite(Jt) || kc_scurve_plan_stop(&s, u->p, u->v, u->a, D, Jt, c->cfg.dt) != KC_OK)
            return 0;
        if (s.p1 <= end)
            break;
        end = s.p1;
    }
    if (s.p1 > T)
        return -1;
    c->drive_scurve = s;
    return 1;
}

/* Whether a joint path's stop, planned into the drive from the last
 * setpoint on, keeps qdd within qdd_max and passes the final check's
 * continuity on every tick (ctrl.c, setpoint_ok: qd changing by at most
 * qdd_max dt a tick, here without its slack), and while superposed the
 * joints' jerk limits (the path's stop alone keeps them; added to the
 * stop under it, which may brake at them, it took a joint to 1.70 times
 * its limit in test_ctrl_pathstop.c). Its rate keeps the limits on sampled instants of
 * the constant-rate stop (path_ramp_load); the jerk-limited stop lingers
 * longer near the speed it starts from and goes further, and a stop of a
 * few ticks is far from its continuous law: a Panda quintic stopped in
 * its first ticks stepped qd by up to 1.0047 qdd_max dt (a limit_guard
 * fault), its qdd as far over. A path superposed on the stop of the
 * motion it replaced (ctrl_blend.c) is checked with that stop added,
 * which its rate does not see: stopped there, a Panda path faulted. */
#define PATH_STOP_TRIES 4
static int path_stop_fits(const kc_ctrl *c)
{
    kc_ctrl_seg_point o;
    kc_real qd[KC_MAX_JOINTS], qdd[KC_MAX_JOINTS];
    int64_t ticks = c->drive == KC_DRIVE_SCURVE ? c->drive_scurve.ticks : c->drive_prof.ticks;
    if (c->blend.on && c->blend.k0 + c->blend.stop_ticks - c->k0 > ticks)
        ticks = c->blend.k0 + c->blend.stop_ticks - c->k0; /* to the end of the superposed stop */
    memcpy(qd, c->qd, sizeof(kc_real) * (size_t)c->chain->n_joints);
    memcpy(qdd, c->qdd, sizeof(kc_real) * (size_t)c->chain->n_joints);
    for (int64_t j = 1; j <= ticks; j++) {
        kc_ctrl_seg_eval(c, j, &o);
        kc_ctrl_blend_joints(c, c->k0 + j, &o);
        for (int i = 0; i < c->chain->n_joints; i++) {
            const kc_joint_limits *l = &c->chain->joints[i].limits;
            if (kc_fabs(o.qd[i] - qd[i]) > l->qdd_max * c->cfg.dt || kc_fabs(o.qdd[i]) > l->qdd_max ||
                (c->blend.on && !kc_ctrl_jerk_within(qdd[i], o.qdd[i], l->qddd_max * c->cfg.dt)))
                return 0;
            qd[i] = o.qd[i];
            qdd[i] = o.qdd[i];
        }
    }
    return 1;
}

void kc_ctrl_stop_on_path(kc_ctrl *c, int intent)
{
    c->stop_intent = intent;
    c->state = KC_CTRL_STOPPING;
    c->resume_share = KC_R(1.0);
    c->stop_v0 = INF;
    c->stop_qu = KC_R(0.0);
    int64_t j = (c->cycle - 1) - c->k0; /* the last setpoint's tick */
    kc_profile_state u;
    if (c->goal.kind == KC_GOAL_SERVO) {
        /* Jerk-limited for STOP, PAUSE, a replacement and the servo
         * timeout (a stream's usual end); a fault brakes at the
         * acceleration limits, as does a stop that cannot be planned
         * jerk-limited. */
        if (c->fault_reason == KC_REASON_NONE && kc_ctrl_halt_plan(c, c->plan.halt, NULL)) {
            c->drive = KC_DRIVE_HALT;
            c->jstop_k0 = c->cycle - 1;
            return;
        }
        kc_ctrl_joint_stop(c, 1, intent == KC_CMD_PAUSE ? KC_CTRL_PAUSED : KC_CTRL_IDLE);
        c->active = 1; /* the servo goal stays active through its stop */
        return;
    }
    if (c->drive == KC_DRIVE_HALT)
        return; /* already stopping joint by joint (plan.halt holds the stops, not the move) */
    if (c->goal.kind == KC_GOAL_JOINT && (c->drive == KC_DRIVE_NOMINAL || c->drive == KC_DRIVE_SCURVE) &&
        c->plan.joint.kind == KC_PROFILE_JERK) {
        jerk_stop(c);
        return;
    }
    if (c->drive == KC_DRIVE_RETARGET) {
        /* Each joint brakes at the goal's own acceleration limit: it comes
         * to rest no further than its profile would have turned, so inside
         * the position limits the retarget was checked against. */
        kc_real vmax[KC_MAX_JOINTS] = {KC_R(0.0)}, amax[KC_MAX_JOINTS] = {KC_R(0.0)};
        kc_ctrl_scaled_limits(c, &c->goal, vmax, amax);
        for (int i = 0; i < c->chain->n_joints; i++)
            kc_profile_plan_stop(&c->plan.retarget[i], c->q[i], c->qd[i], amax[i], c->cfg.dt);
        drive_from_here(c, c->drive);
        return;
    }
    if (c->blend.on && c->goal.kind != KC_GOAL_PATH && c->drive == KC_DRIVE_NOMINAL && j >= 0 &&
        c->fault_reason == KC_REASON_NONE) {
        /* A Cartesian goal superposed on the stop of the motion it
         * replaced (ctrl_blend.c), under way: its stop would add to that
         * one, which may brake at a joint's limits (a joint move's does;
         * a PUMA 560's joints went 46 times beyond their jerk limits). It
         * goes on as judged, and stops once that stop has ended. */
        c->drive = KC_DRIVE_STOPPING_WAIT;
        return;
    }
    kc_ctrl_drive_state(c, j, &u);
    kc_real dec, jmax;
    int jerk;
    if (kc_ctrl_is_path(c->goal.kind) && j < 0) {
        /* A path superposed on the stop of the motion it replaced that has
         * not started (ctrl_blend.c): it stays at rest where it starts,
         * that stop going on alone. (Its law would give tau' = 1 there: a
         * Cartesian path stopped so set off from rest and braked at once,
         * its PUMA 560 joints up to 46 times beyond their jerk limits.) */
        kc_profile_plan_stop(&c->drive_prof, KC_R(0.0), KC_R(0.0), KC_R(1.0), c->cfg.dt);
        drive_from_here(c, KC_DRIVE_PROFILE);
        return;
    }
    if (kc_ctrl_is_path(c->goal.kind)) {
        dec = path_stop_rate(c, u.p, u.v);
        if (!(dec > KC_R(0.0))) {
            c->drive = c->drive == KC_DRIVE_PROFILE || c->drive == KC_DRIVE_SCURVE ? c->drive : KC_DRIVE_STOPPING_WAIT;
            return;
        }
        /* Jerk-limited from (tau, tau', tau''), but for a fault. A joint
         * path's stop that fails the final check on some tick is planned
         * again at half the rate, up to PATH_STOP_TRIES times (then the
         * slowest is kept). A first stop that would pass the end leaves
         * the drive under way, which stops at the end first; a slower one
         * that would gives way to the one before it. */
        kc_real T = kc_ctrl_path_duration(c);
        kc_ctrl_drive drive = c->drive;
        int64_t k0 = c->k0;
        for (int tries = 0;; tries++) {
            jerk = c->fault_reason == KC_REASON_NONE ? path_scurve_stop(c, &u, dec, T) : 0;
            if (jerk < 0 && tries == 0)
                return;
            if (jerk < 0) {
                dec *= KC_R(2.0), tries = PATH_STOP_TRIES - 1;
                continue;
            }
            if (!jerk)
                kc_profile_plan_stop(&c->drive_prof, u.p, u.v, dec, c->cfg.dt);
            drive_from_here(c, jerk ? KC_DRIVE_SCURVE : KC_DRIVE_PROFILE);
            if (c->goal.kind != KC_GOAL_PATH || path_stop_fits(c))
                return;
            if (drive == KC_DRIVE_NOMINAL &&
                (c->blend.on || (tries == PATH_STOP_TRIES && c->fault_reason == KC_REASON_NONE))) {
                /* Superposed on a stop braking at a joint's limit, where
                 * any stop of the path adds to it, or on the path's own law
                 * where no stop fits (its acceleration at a joint's limit,
                 * which any braking along the path adds to; not for a
                 * fault, which keeps the slowest plan): the path goes on as
                 * judged, and stops from a later tick (at the latest once
                 * the stop under it has ended, or at its end). */
                c->drive = KC_DRIVE_STOPPING_WAIT, c->k0 = k0;
                return;
            }
            if (tries == PATH_STOP_TRIES)
                return;
            dec *= KC_R(0.5);
        }
    } else {
        kc_real vmax;
        kc_profile_kind kind = seg_u_bounds(c, &vmax, &dec, &jmax);
        /* A jerk-limited line or arc stops jerk-limited, from (u, u', u''),
         * within its joints' limits (joint_bounded_stop), but for a fault
         * (kinctl/ctrl.h: stopping soonest matters more). */
        jerk = kind == KC_PROFILE_JERK && c->fault_reason == KC_REASON_NONE && c->drive != KC_DRIVE_PROFILE &&
               seg_jerk_stop(c, &u, dec, jmax);
    }
    if (!jerk)
        kc_profile_plan_stop(&c->drive_prof, u.p, u.v, dec, c->cfg.dt);
    drive_from_here(c, jerk ? KC_DRIVE_SCURVE : KC_DRIVE_PROFILE);
}

#ifndef KC_REAL_FLOAT
int kc_ctrl_stop_leave_path(kc_ctrl *c, const kc_real *qdd)
{
    int over = 0;
    if (c->state != KC_CTRL_STOPPING || c->drive != KC_DRIVE_SCURVE || c->fault_reason != KC_REASON_NONE ||
        c->blend.on)
        return 0;
    for (int i = 0; i < c->chain->n_joints; i++)
        if (kc_fabs(qdd[i] - c->qdd[i]) >
            c->chain->joints[i].limits.qddd_max * c->cfg.dt * (KC_R(1.0) + c->cfg.limit_slack))
            over = 1;
    if (!over || !kc_ctrl_halt_plan(c, c->plan.halt, NULL))
        return 0;
    c->drive = KC_DRIVE_HALT;
    c->jstop_k0 = c->cycle - 1;
    if (c->stop_intent == KC_CMD_PAUSE || c->stop_intent == KC_CMD_RESUME)
        c->stop_intent = KC_CMD_STOP; /* off its path: no resume, it ends there */
    return 1;
}
#endif

void kc_ctrl_stop_track(kc_ctrl *c, int64_t j, const kc_real *qd)
{
    kc_profile_state u;
    if (c->state != KC_CTRL_STOPPING || c->drive != KC_DRIVE_SCURVE)
        return;
    kc_ctrl_drive_state(c, j, &u);
    if (!(u.v >= STOP_TRACK_LEAST * c->stop_v0))
        return;
    c->stop_qu = kc_max(c->stop_qu, rate_per_u(c, qd, u.v));
}

void kc_ctrl_resume(kc_ctrl *c, int64_t last, kc_ctrl_output *out)
{
    int64_t j = last - c->k0;
    kc_profile_state u;
    c->state = KC_CTRL_MOVING;
    c->stop_intent = KC_CMD_NONE;
    if (c->goal.kind == KC_GOAL_SERVO) {
        c->servo_last = c->cycle;
        kc_ctrl_servo_rest(c, last); /* a twist stream goes on from where the arm stopped */
        c->drive = KC_DRIVE_NOMINAL; /* plan.halt held its stop */
        return;
    }
    if (c->goal.kind == KC_GOAL_JOINT &&
        (c->drive == KC_DRIVE_RETARGET || c->drive == KC_DRIVE_SCURVE || c->drive == KC_DRIVE_HALT)) {
        /* At rest a retarget, or a jerk-limited move stopped, is an
         * ordinary joint move from here. */
        drive_from_here(c, KC_DRIVE_NOMINAL);
        c->k0 = last;
        if (kc_ctrl_plan_goal(c) != KC_OK) {
            kc_ctrl_emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_PLAN, 0);
            c->active = 0;
            c->state = KC_CTRL_IDLE;
        }
        return;
    }
    kc_ctrl_drive_state(c, j, &u);
    kc_real end = KC_R(1.0), vmax, amax, jmax;
    int jerk;
    if (kc_ctrl_is_path(c->goal.kind)) {
        kc_real T = kc_ctrl_path_duration(c);
        /* (a constant-rate stop may have come to rest past the end) */
        u.p = kc_min(u.p, T);
        kc_real C = kc_ctrl_path_ramp_rate(c, u.p);
        if (!(C > KC_R(0.0)))
            C = KC_R(1.0); /* the rates tried all fail: the gentlest ramp there is */
        end = T, vmax = KC_R(1.0), amax = C;
        jmax = kc_ctrl_path_ramp_jerk(c, u.p, C);
        jerk = kc_isfinite(jmax);
    } else {
        /* A jerk-limited line or arc resumes jerk-limited. */
        jerk = seg_u_bounds(c, &vmax, &amax, &jmax) == KC_PROFILE_JERK;
    }
    /* A Cartesian goal's ramp from where its stop came to rest, at the
     * share of the bounds its stop chose (joint_bounded_stop). */
    if (c->goal.kind != KC_GOAL_PATH) {
        kc_real k = c->resume_share, qu = kc_max(c->stop_qu, c->goal.qu);
        if (qu * k * jmax > STOP_RESUME_SHARE)
            k = kc_max(STOP_RESUME_SHARE / (qu * jmax), STOP_SHARE_MIN);
        amax *= k, jmax *= k;
    }
    jerk = jerk && kc_scurve_plan(&c->drive_scurve, u.p, KC_R(0.0), KC_R(0.0), end, vmax, amax, jmax, c->cfg.dt) ==
                       KC_OK;
    if (!jerk)
        kc_profile_plan(&c->drive_prof, u.p, KC_R(0.0), end, vmax, amax, c->cfg.dt);
    drive_from_here(c, jerk ? KC_DRIVE_SCURVE : KC_DRIVE_PROFILE);
    c->k0 = last;
}

void kc_ctrl_stop_finished(kc_ctrl *c, kc_ctrl_output *out)
{
    int intent = c->stop_intent;
    c->stop_intent = KC_CMD_NONE;
    if (intent == KC_CMD_PAUSE) {
        c->state = KC_CTRL_PAUSED;
        return;
    }
    if (intent == KC_CMD_RESUME) {
        kc_ctrl_resume(c, c->cycle, out); /* this tick's setpoint, at rest, is its tick 0 */
        return;
    }
    c->active = 0;
    if (intent == INTENT_PREEMPT) {
        kc_ctrl_emit(out, KC_EVENT_PREEMPTED, c->goal.id, KC_REASON_NONE, 0);
        c->state = KC_CTRL_IDLE;
        return;
    }
    if (c->fault_reason != KC_REASON_NONE) {
        c->state = KC_CTRL_FAULT;
        return;
    }
    kc_ctrl_reason why = intent == INTENT_LAG                                        ? KC_REASON_TRACKING
                         : c->goal.kind == KC_GOAL_SERVO && intent == KC_CMD_NONE ? KC_REASON_SERVO_TIMEOUT
                                                                                  : KC_REASON_NONE;
    kc_ctrl_emit(out, KC_EVENT_ABORTED, c->goal.id, why, 0);
    c->state = KC_CTRL_IDLE;
}

void kc_ctrl_fault(kc_ctrl *c, kc_ctrl_reason why, kc_real where, int on_path, kc_ctrl_output *out)
{
    if (c->fault_reason != KC_REASON_NONE) {
        /* Already in a fault, whose events went out with it (the goal
         * aborted once): a stop on the path that fails too gives way to
         * one in joint space. */
        kc_ctrl_joint_stop(c, 1, KC_CTRL_FAULT);
        c->state = KC_CTRL_STOPPING;
        return;
    }
    c->fault_reason = why;
    kc_ctrl_emit(out, KC_EVENT_FAULT, c->active ? c->goal.id : 0, why, where);
    if (c->active)
        kc_ctrl_emit(out, KC_EVENT_ABORTED, c->goal.id, why, where);
    kc_ctrl_queue_clear(c, out);
    if (on_path && c->active && c->goal.kind != KC_GOAL_SERVO) {
        kc_ctrl_stop_on_path(c, KC_CMD_STOP);
        return;
    }
    kc_ctrl_joint_stop(c, 1, KC_CTRL_FAULT);
    c->state = KC_CTRL_STOPPING;
}
