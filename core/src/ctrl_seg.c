/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl_seg.c - segments: a goal planned when it starts (joint move, line,
 * arc, path, servo), the motion it asks for at each tick, and the setpoint
 * that follows it (Cartesian: one IK step) (kinctl/ctrl.h). */
#include "ctrl_internal.h"
#include "interp_internal.h"

#include <string.h>

void kc_ctrl_scaled_limits(const kc_ctrl *c, const kc_goal *g, kc_real *vmax, kc_real *amax)
{
    for (int j = 0; j < c->chain->n_joints; j++) {
        vmax[j] = c->chain->joints[j].limits.qd_max * g->vel_scale;
        amax[j] = c->chain->joints[j].limits.qdd_max * g->acc_scale;
    }
}

kc_interp_limits kc_ctrl_cart_limits(const kc_ctrl_cfg *cfg, const kc_goal *g)
{
    kc_interp_limits l = kc_interp_limits_default();
    l.v = g->speed > KC_R(0.0) ? g->speed : cfg->cart_speed;
    l.a = g->accel > KC_R(0.0) ? g->accel : cfg->cart_accel;
    l.w = g->omega > KC_R(0.0) ? g->omega : cfg->cart_omega;
    l.dw = g->alpha > KC_R(0.0) ? g->alpha : cfg->cart_alpha;
    /* The trapezoid: jerk unbounded (kc_interp_limits_default's). */
    int trapezoid = g->profile == KC_GOAL_PROFILE_TRAPEZOID ||
                    (g->profile == KC_GOAL_PROFILE_CFG && cfg->profile == KC_PROFILE_TRAPEZOID);
    if (!trapezoid) {
        l.j = g->jerk > KC_R(0.0) ? g->jerk : cfg->cart_jerk;
        l.dj = g->angular_jerk > KC_R(0.0) ? g->angular_jerk : cfg->cart_angular_jerk;
    }
    return l;
}

/* The knot settings of path goal g, the same fields in kc_path_cfg and
 * kc_path_cart_cfg: m knots (the current state first) at times (t_0 = 0)
 * when the goal gives them, tick period dt. */
#define PATH_CFG_OF_GOAL(cfg, g, m, times, dt_)                                                                       \
    do {                                                                                                               \
        (cfg).method = (g)->method;                                                                                    \
        (cfg).blend = (g)->blend;                                                                                      \
        (cfg).spline_end = (g)->spline_end;                                                                            \
        (cfg).n_knots = (m);                                                                                           \
        (cfg).t = (g)->has_times ? (times) : NULL;                                                                     \
        (cfg).t_acc = (g)->blend_time;                                                                                 \
        (cfg).dt = (dt_);                                                                                              \
    } while (0)

/* Plans path goal g through the current state and its points (a
 * Cartesian one from the tool pose *from). */
static kc_status plan_path(kc_ctrl *c, const kc_goal *g, const kc_pose *from, const kc_real *q0)
{
    int n = c->chain->n_joints, m = g->n_points + 1;
    kc_real times[KC_PATH_MAX_KNOTS];
    times[0] = KC_R(0.0);
    for (int i = 1; i < m; i++)
        times[i] = g->times[i - 1];
    if (g->kind == KC_GOAL_PATH) {
        kc_real knots[KC_PATH_MAX_KNOTS * KC_MAX_JOINTS];
        kc_path_cfg cfg = kc_path_cfg_default();
        for (int j = 0; j < n; j++)
            knots[j] = q0[j];
        for (int i = 1; i < m; i++)
            for (int j = 0; j < n; j++)
                knots[i * n + j] = g->points[i - 1][j];
        PATH_CFG_OF_GOAL(cfg, g, m, times, c->cfg.dt);
        cfg.dim = n;
        cfg.q = knots;
        kc_ctrl_scaled_limits(c, g, cfg.vmax, cfg.amax);
        /* Computed times keep the joints' jerk within qddd_max too where
         * the motion is jerk-limited (kinctl/path.h: the stretch). */
        if (kc_ctrl_goal_profile(c, g) == KC_PROFILE_JERK)
            for (int j = 0; j < n; j++)
                cfg.jmax[j] = c->chain->joints[j].limits.qddd_max;
        return kc_path_plan(&c->plan.path, &cfg);
    }
    kc_vec3 p[KC_PATH_MAX_KNOTS];
    kc_quat r[KC_PATH_MAX_KNOTS];
    p[0] = from->t;
    kc_quat_from_mat3(&from->R, &r[0]);
    for (int i = 1; i < m; i++) {
        const kc_real *v = g->points[i - 1];
        p[i] = kc_vec3_make(v[0], v[1], v[2]);
        r[i].w = v[3];
        r[i].x = v[4];
        r[i].y = v[5];
        r[i].z = v[6];
    }
    kc_interp_limits lim = kc_ctrl_cart_limits(&c->cfg, g);
    kc_path_cart_cfg cfg = kc_path_cart_cfg_default();
    PATH_CFG_OF_GOAL(cfg, g, m, times, c->cfg.dt);
    cfg.p = p;
    cfg.r = r;
    cfg.v_max = lim.v;
    cfg.a_max = lim.a;
    cfg.w_max = lim.w;
    cfg.alpha_max = lim.dw;
    kc_status st = kc_path_cart_plan(&c->plan.path_cart, &cfg);
    if (st == KC_OK)
        c->path_length = c->plan.path_cart.length;
    return st;
}

kc_profile_kind kc_ctrl_goal_profile(const kc_ctrl *c, const kc_goal *g)
{
    kc_profile_kind k = g->profile == KC_GOAL_PROFILE_TRAPEZOID ? KC_PROFILE_TRAPEZOID
                        : g->profile == KC_GOAL_PROFILE_JERK    ? KC_PROFILE_JERK
                                                                : c->cfg.profile;
    /* Without a jerk limit on every joint there is no jerk-limited plan. */
    for (int j = 0; j < c->chain->n_joints && k == KC_PROFILE_JERK; j++)
        if (!kc_isfinite(c->chain->joints[j].limits.qddd_max))
            k = KC_PROFILE_TRAPEZOID;
    return k;
}

int kc_ctrl_jerk_limited(const kc_ctrl *c, const kc_goal *g)
{
    if (c == NULL || g == NULL || c->chain == NULL || g->kind == KC_GOAL_PATH)
        return 0;
    return kc_ctrl_goal_profile(c, g) == KC_PROFILE_JERK;
}

kc_status kc_ctrl_plan_joint(const kc_ctrl *c, const kc_goal *g, const kc_real *q0, const kc_real *qd0,
                             const kc_real *qdd0, kc_interp_joint *out)
{
    int n = c->chain->n_joints;
    kc_interp_joint_cfg cfg = kc_interp_joint_cfg_default();
    cfg.n = n;
    cfg.dt = c->cfg.dt;
    cfg.profile = kc_ctrl_goal_profile(c, g);
    kc_ctrl_scaled_limits(c, g, cfg.qd_max, cfg.qdd_max);
    for (int j = 0; j < n; j++) {
        cfg.q0[j] = q0[j];
        cfg.q1[j] = g->q[j];
        cfg.qddd_max[j] = c->chain->joints[j].limits.qddd_max;
        if (cfg.profile == KC_PROFILE_JERK && qd0 != NULL && qdd0 != NULL) {
            cfg.qd0[j] = qd0[j];
            cfg.qdd0[j] = qdd0[j];
        }
    }
    return kc_interp_joint_plan_cfg_into(out, &cfg);
}

kc_status kc_ctrl_plan_cart_from(kc_ctrl *c, const kc_goal *g, const kc_pose *from)
{
    kc_interp_limits lim = kc_ctrl_cart_limits(&c->cfg, g);
    kc_status st = KC_E_ARG;
    c->path_length = KC_R(0.0);
    if (g->kind == KC_GOAL_LINE) {
        st = kc_interp_line_plan(&c->plan.line, from, &g->pose, &lim, g->orient, c->cfg.dt);
        c->path_length = c->plan.line.length;
    } else if (g->kind == KC_GOAL_ARC) {
        st = kc_interp_arc_plan(&c->plan.arc, from, &g->via, &g->pose.t, &lim, c->cfg.dt);
        c->path_length = c->plan.arc.length;
    } else if (g->kind == KC_GOAL_PATH_CART) {
        st = plan_path(c, g, from, c->q);
    }
    return st;
}

kc_status kc_ctrl_plan_path_from(kc_ctrl *c, const kc_goal *g, const kc_real *q0)
{
    c->path_length = KC_R(0.0);
    return plan_path(c, g, &c->pose, q0);
}

kc_status kc_ctrl_plan_goal(kc_ctrl *c)
{
    const kc_goal *g = &c->goal;
    /* The tool pose where the segment starts (the Cartesian kinds start
     * from it): the last setpoint's, kept by kc_ctrl_step. */
    const kc_pose *from = &c->pose;
    c->path_length = KC_R(0.0);
    switch (g->kind) {
    case KC_GOAL_JOINT:
        return kc_ctrl_plan_joint(c, g, c->q, c->qd, c->qdd, &c->plan.joint);
    case KC_GOAL_LINE:
    case KC_GOAL_ARC:
    case KC_GOAL_PATH_CART:
        return kc_ctrl_plan_cart_from(c, g, from);
    case KC_GOAL_PATH:
        return plan_path(c, g, from, c->q);
    case KC_GOAL_SERVO:
        c->servo_last = c->cycle;
        kc_ctrl_servo_rest(c, c->cycle - 1);
        return KC_OK;
    }
    return KC_E_ARG;
}

int kc_ctrl_start_next(kc_ctrl *c, kc_ctrl_output *out)
{
    while (c->queue_len > 0) {
        kc_ctrl_goal_copy(&c->goal, &c->queue[c->queue_head]);
        c->queue_head = (c->queue_head + 1) % KC_CTRL_QUEUE_MAX;
        c->queue_len--;
        /* Tick 0 of the segment is the last setpoint: the first output is
         * its tick 1. */
        c->k0 = c->cycle - 1;
        c->drive = KC_DRIVE_NOMINAL;
        c->stop_intent = KC_CMD_NONE;
        c->settle = 0;
        c->blend.on = 0;
        c->blend.lax = 0;
        c->ramp_on = 0;
        kc_status st = kc_ctrl_plan_goal(c);
        /* A path moving at its first and last knot (Lagrange's), or whose
         * acceleration steps there under a jerk-limited law (a cubic
         * spline's): run on a tau' that ramps up from rest and down into
         * the end, at rate C, tau''' within Jt. */
        if (st == KC_OK && kc_ctrl_is_path(c->goal.kind) && kc_ctrl_path_ramped(c, &c->goal))
            st = kc_ctrl_path_plan_ramp(c, 0);
        if (st != KC_OK) {
            kc_ctrl_emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_PLAN, 0);
            continue;
        }
        c->active = 1;
        c->state = KC_CTRL_MOVING;
        kc_ctrl_emit(out, KC_EVENT_STARTED, c->goal.id, KC_REASON_NONE, 0);
        return 1;
    }
    c->active = 0;
    return 0;
}

static void cart_point(kc_ctrl_seg_point *o, const kc_vec3 *p, const kc_quat *r, const kc_vec3 *v,
                       const kc_vec3 *w, kc_real rate)
{
    o->cart = 1;
    o->pose.t = *p;
    kc_quat_to_mat3(r, &o->pose.R);
    for (int i = 0; i < 3; i++) {
        o->twist[i] = v->v[i] * rate;
        o->twist[3 + i] = w->v[i] * rate;
    }
}

/* A jerk-limited profile's state as kc_ctrl_drive_state gives it. */
static kc_status scurve_drive_state(const kc_scurve *prof, int64_t j, kc_profile_state *u)
{
    kc_scurve_state s;
    kc_status st = kc_scurve_eval(prof, j, &s);
    u->p = s.p;
    u->v = s.v;
    u->a = s.a;
    u->phase = s.phase;
    return st;
}

/* The jerk-limited u profile driving a line or an arc at its own timing,
 * or NULL for a trapezoid. */
static const kc_scurve *cart_own_scurve(const kc_ctrl *c)
{
    if (c->goal.kind == KC_GOAL_LINE && c->plan.line.kind == KC_PROFILE_JERK)
        return &c->plan.line.su;
    if (c->goal.kind == KC_GOAL_ARC && c->plan.arc.kind == KC_PROFILE_JERK)
        return &c->plan.arc.su;
    return NULL;
}

/* The u profile state of a line or an arc at its tick j, and whether it
 * has ended (KC_DONE), under any drive. */
static kc_status cart_u_state(const kc_ctrl *c, int64_t j, kc_profile_state *u)
{
    const kc_scurve *own = cart_own_scurve(c);
    if (c->drive == KC_DRIVE_PROFILE)
        return kc_profile_eval(&c->drive_prof, j, u);
    if (c->drive == KC_DRIVE_SCURVE)
        return scurve_drive_state(&c->drive_scurve, j, u);
    if (own != NULL)
        return scurve_drive_state(own, j, u);
    return kc_profile_eval(c->goal.kind == KC_GOAL_LINE ? &c->plan.line.prof : &c->plan.arc.prof, j, u);
}

void kc_ctrl_drive_state(const kc_ctrl *c, int64_t j, kc_profile_state *u)
{
    if (j < 0)
        j = 0; /* a segment that starts later (ctrl_blend.c) is at its start */
    if (c->drive == KC_DRIVE_PROFILE) {
        kc_profile_eval(&c->drive_prof, j, u);
        return;
    }
    if (c->goal.kind == KC_GOAL_LINE || c->goal.kind == KC_GOAL_ARC) {
        cart_u_state(c, j, u);
        return;
    }
    if (c->drive == KC_DRIVE_SCURVE) {
        scurve_drive_state(&c->drive_scurve, j, u);
        return;
    }
    if (kc_ctrl_is_path(c->goal.kind) && c->ramp_on) {
        scurve_drive_state(&c->ramp, j, u);
        return;
    }
    if (kc_ctrl_is_path(c->goal.kind)) {
        u->p = (kc_real)j * c->cfg.dt;
        u->v = KC_R(1.0);
        u->a = KC_R(0.0);
        u->phase = 2;
        return;
    }
    kc_profile_eval(&c->plan.joint.prof, j, u);
}

/* Whether a path has ended at its tick j: its drive profile has, or at its
 * own timing `end`. */
static int path_drive_done(const kc_ctrl *c, int64_t j, int end)
{
    if (c->drive == KC_DRIVE_PROFILE)
        return c->drive_prof.ticks <= j;
    if (c->drive == KC_DRIVE_SCURVE)
        return c->drive_scurve.ticks <= j;
    if (c->ramp_on)
        return c->ramp.ticks <= j;
    return end;
}

/* Joint path at plan time tau with rate tau' and tau'': chain rule. */
static int path_joint_at(const kc_path *path, kc_real tau, kc_real rate, kc_real rate_dot, int n,
                         kc_ctrl_seg_point *o)
{
    kc_real d1[KC_MAX_JOINTS], d2[KC_MAX_JOINTS];
    kc_status st = kc_path_eval_time(path, kc_max(tau, KC_R(0.0)), o->q, d1, d2);
    for (int j = 0; j < n; j++) {
        o->qd[j] = d1[j] * rate;
        o->qdd[j] = d2[j] * rate * rate + d1[j] * rate_dot;
    }
    return st == KC_DONE;
}

/* Joint by joint at tick j: a retarget, every joint on its own profile
 * (or its stop), or a jerk-limited halt (halt); done when the last joint
 * has ended. */
static void joints_eval(const kc_ctrl *c, int64_t j, int halt, kc_ctrl_seg_point *o)
{
    int64_t ticks = 0;
    o->done = 1;
    for (int i = 0; i < c->chain->n_joints; i++) {
        kc_profile_state s;
        kc_status st;
        int64_t n;
        if (halt) {
            n = c->plan.halt[i].ticks;
            st = scurve_drive_state(&c->plan.halt[i], j, &s);
        } else {
            n = c->plan.retarget[i].ticks;
            st = kc_profile_eval(&c->plan.retarget[i], j, &s);
        }
        if (st != KC_DONE)
            o->done = 0;
        o->q[i] = s.p;
        o->qd[i] = s.v;
        o->qdd[i] = s.a;
        if (n > ticks)
            ticks = n;
    }
    o->progress = ticks > 0 ? kc_min((kc_real)j / (kc_real)ticks, KC_R(1.0)) : KC_R(1.0);
}

void kc_ctrl_interp_point(kc_goal_kind kind, const kc_interp_line *line, const kc_interp_arc *arc,
                          kc_ctrl_drive drive, const kc_profile *prof, const kc_scurve *sc, int64_t j,
                          kc_ctrl_seg_point *o)
{
    kc_interp_cart_state s;
    kc_status st;
    if (kind == KC_GOAL_LINE)
        st = drive == KC_DRIVE_PROFILE  ? kc_interp_line_eval_profile(line, prof, j, &s)
             : drive == KC_DRIVE_SCURVE ? kc_interp_line_eval_scurve(line, sc, j, &s)
                                        : kc_interp_line_eval(line, j, &s);
    else
        st = drive == KC_DRIVE_PROFILE  ? kc_interp_arc_eval_profile(arc, prof, j, &s)
             : drive == KC_DRIVE_SCURVE ? kc_interp_arc_eval_scurve(arc, sc, j, &s)
                                        : kc_interp_arc_eval(arc, j, &s);
    cart_point(o, &s.p, &s.q, &s.v, &s.w, KC_R(1.0));
    o->progress = s.u;
    o->s = s.s;
    o->done = st == KC_DONE;
}

void kc_ctrl_seg_eval(const kc_ctrl *c, int64_t j, kc_ctrl_seg_point *o)
{
    const kc_goal *g = &c->goal;
    int n = c->chain->n_joints;
    o->cart = 0;
    o->s = KC_R(0.0);
    o->done = 0;
    if (j < 0)
        j = 0;
    switch (g->kind) {
    case KC_GOAL_JOINT: {
        if (c->drive == KC_DRIVE_RETARGET || c->drive == KC_DRIVE_HALT) {
            joints_eval(c, j, c->drive == KC_DRIVE_HALT, o);
            return;
        }
        kc_interp_joint_state s;
        kc_status st = c->drive == KC_DRIVE_PROFILE  ? kc_interp_joint_eval_profile(&c->plan.joint, &c->drive_prof, j, &s)
                       : c->drive == KC_DRIVE_SCURVE ? kc_interp_joint_eval_scurve(&c->plan.joint, &c->drive_scurve, j, &s)
                                                     : kc_interp_joint_eval(&c->plan.joint, j, &s);
        memcpy(o->q, s.q, sizeof(kc_real) * (size_t)n);
        memcpy(o->qd, s.qd, sizeof(kc_real) * (size_t)n);
        memcpy(o->qdd, s.qdd, sizeof(kc_real) * (size_t)n);
        o->progress = s.u;
        o->done = st == KC_DONE;
        return;
    }
    case KC_GOAL_LINE:
    case KC_GOAL_ARC: {
        kc_ctrl_interp_point(g->kind, &c->plan.line, &c->plan.arc, c->drive, &c->drive_prof, &c->drive_scurve, j, o);
        return;
    }
    case KC_GOAL_PATH:
    case KC_GOAL_PATH_CART: {
        kc_profile_state u;
        kc_ctrl_drive_state(c, j, &u);
        kc_real T = kc_ctrl_path_duration(c);
        o->progress = T > KC_R(0.0) ? kc_min(u.p / T, KC_R(1.0)) : KC_R(1.0);
        if (g->kind == KC_GOAL_PATH) {
            int end = path_joint_at(&c->plan.path, u.p, u.v, u.a, n, o);
            o->done = path_drive_done(c, j, end);
        } else {
            kc_path_pose s;
            kc_status st = kc_path_cart_eval_time(&c->plan.path_cart, kc_max(u.p, KC_R(0.0)), &s);
            cart_point(o, &s.p, &s.r, &s.v, &s.w, u.v);
            o->s = s.s;
            o->done = path_drive_done(c, j, st == KC_DONE);
        }
        return;
    }
    case KC_GOAL_SERVO: {
        kc_vec3 zero = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
        kc_quat r;
        kc_quat_from_mat3(&c->servo_target.R, &r);
        cart_point(o, &c->servo_target.t, &r, &zero, &zero, KC_R(0.0));
        if (g->servo_twist || kc_ctrl_servo_shaped(c))
            for (int i = 0; i < 6; i++)
                o->twist[i] = c->servo_v[i];
        o->progress = KC_R(0.0);
        return;
    }
    }
}

/* A Cartesian segment's progress and end at its tick j, as seg_eval gives
 * them, without its pose: the tick steers by the pose of tick j - 1. A line
 * or an arc is at u's profile state (u = 1 once it has ended at its end,
 * kc_interp_cart_state.u), a Cartesian path at its drive state, a servo
 * goal never ends on its own. */
static void cart_timing(const kc_ctrl *c, int64_t j, kc_ctrl_seg_point *o)
{
    const kc_goal *g = &c->goal;
    kc_profile_state u;
    o->progress = KC_R(0.0);
    o->done = 0;
    if (j < 0)
        j = 0;
    if (g->kind == KC_GOAL_LINE || g->kind == KC_GOAL_ARC) {
        kc_status st = cart_u_state(c, j, &u);
        o->progress = st == KC_DONE && u.p >= KC_R(1.0) ? KC_R(1.0) : u.p;
        o->done = st == KC_DONE;
    } else if (g->kind == KC_GOAL_PATH_CART) {
        kc_ctrl_drive_state(c, j, &u);
        kc_real T = c->plan.path_cart.pos.duration;
        o->progress = T > KC_R(0.0) ? kc_min(u.p / T, KC_R(1.0)) : KC_R(1.0);
        o->done = path_drive_done(c, j, kc_max(u.p, KC_R(0.0)) >= T);
    }
}

int kc_ctrl_follow(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd, kc_ctrl_output *out)
{
    int n = c->chain->n_joints;
    int64_t j = c->cycle - c->k0;
    kc_ctrl_seg_point now;
    if (c->drive == KC_DRIVE_STOPPING_WAIT) {
        /* Try to start the pending path stop from the last setpoint. */
        int intent = c->stop_intent;
        c->drive = KC_DRIVE_NOMINAL;
        kc_ctrl_stop_on_path(c, intent);
        j = c->cycle - c->k0;
    }
    int cart = kc_ctrl_is_cart(c->goal.kind);
    if (cart)
        cart_timing(c, j, &now);
    else
        kc_ctrl_seg_eval(c, j, &now);
    out->progress = now.progress;
    if (!cart) {
        if (c->blend.on) /* a joint path superposed on a stop in joint space */
            kc_ctrl_blend_apply(c, c->cycle, &now, NULL);
        memcpy(q, now.q, sizeof(kc_real) * (size_t)n);
        memcpy(qd, now.qd, sizeof(kc_real) * (size_t)n);
        memcpy(qdd, now.qdd, sizeof(kc_real) * (size_t)n);
        return now.done && !c->blend.on;
    }
    /* Cartesian: the target where the segment is at the last setpoint's
     * instant, its twist fed forward; the step heads for tick j. */
    kc_ctrl_seg_point before;
    kc_real qd_m[KC_MAX_JOINTS];
    const kc_real *null_ff = NULL;
    kc_ctrl_seg_eval(c, j - 1, &before);
    if (c->blend.on && kc_ctrl_blend_apply(c, c->cycle - 1, &before, qd_m))
        null_ff = qd_m; /* a stop in joint space: its null-space part too (kinctl/ctrl.h) */
    if (c->goal.kind == KC_GOAL_SERVO)
        kc_ctrl_servo_tick(c);
    kc_ik_result res;
    /* A redundant arm's null-space motion (a task without a null space has
     * none) set going and brought to rest smoothly (SETTLE_NULL_S): its
     * gain's share is 3x^2 - 2x^3 of null_x, which rises at dt /
     * SETTLE_NULL_S a tick from 0 at the first IK step after a tick
     * without one, and falls so while the tool settles. The gain is scaled
     * for this step only (no copy of the IK configuration on the stack). */
    kc_real null_gain = c->cfg.ik.null_gain, rate = c->cfg.dt / SETTLE_NULL_S, x = c->null_x;
    if (c->null_cycle != c->cycle - 1)
        x = KC_R(0.0);
    x = c->settle > 0 ? kc_max(x - rate, KC_R(0.0)) : kc_min(x + rate, KC_R(1.0));
    /* A stop in joint space fed forward carries the null-space motion
     * the joints had (the objective's included) while it lasts; the
     * objective comes back from 0 after it. */
    if (null_ff != NULL)
        x = KC_R(0.0);
    c->null_x = x;
    c->null_cycle = c->cycle;
    c->cfg.ik.null_gain = null_gain * x * x * (KC_R(3.0) - KC_R(2.0) * x);
    kc_status st =
        kc_ik_step_ff(c->chain, &c->cfg.ik, &before.pose, before.twist, null_ff, c->cfg.dt, c->q, c->qd, q, qd, &res);
    c->cfg.ik.null_gain = null_gain;
    for (int i = 0; i < n; i++)
        qdd[i] = (qd[i] - c->qd[i]) / c->cfg.dt;
    if (c->goal.kind == KC_GOAL_SERVO && kc_ctrl_goal_profile(c, &c->goal) == KC_PROFILE_JERK && st != KC_E_LIMIT &&
        st != KC_E_ARG)
        kc_ctrl_servo_jerk(c, q, qd, qdd);
    if (c->goal.kind != KC_GOAL_SERVO) {
        if (kc_ctrl_stop_leave_path(c, qdd)) {
            kc_ctrl_joint_stop_eval(c, q, qd, qdd);
            return 0;
        }
        kc_ctrl_stop_track(c, j - 1, qd);
    }
    /* The replaced motion's stop in a superposition is followed as a stop
     * is, until the tool is back within the tolerance after it, closing in. */
    if (c->blend.lax && !c->blend.on && res.pos_err <= c->cfg.track_tol && res.pos_err < c->blend.err)
        c->blend.lax = 0;
    c->blend.err = res.pos_err;
    kc_real limit = c->state == KC_CTRL_STOPPING || c->blend.lax ? TRACK_GIVE_UP * c->cfg.track_tol : c->cfg.track_tol;
    if (c->goal.kind == KC_GOAL_SERVO) {
        /* A shaped target (a twist stream's, a jerk-limited pose
         * stream's) moves within the Cartesian bounds: a tool falling
         * behind it by more than the tracking bound cannot follow the
         * stream (a joint at its speed or acceleration limit, a
         * singularity), which ends there, stopped joint by joint and
         * jerk-limited as when it goes quiet, not a fault. While lax (a
         * superposition's sum, or a zone held the tool back, the target
         * within ZONE_LEAD of it) the bound is a stop's, ZONE_LEAD's at
         * least. An unshaped pose may jump: the arm goes there within
         * its limits. Only a joint limit in the way is a fault. */
        int shaped = c->goal.servo_twist || kc_ctrl_servo_shaped(c);
        if (c->blend.lax)
            limit = TRACK_GIVE_UP * kc_max(c->cfg.track_tol, ZONE_LEAD);
        if (shaped && st != KC_E_ARG && st != KC_E_LIMIT && res.pos_err > limit) {
            kc_ctrl_stop_on_path(c, INTENT_LAG);
            kc_ctrl_joint_stop_eval(c, q, qd, qdd);
            return 0;
        }
        limit = INF;
    }
    if (st == KC_E_ARG || res.pos_err > limit || st == KC_E_LIMIT) {
        kc_real where = c->path_length > KC_R(0.0) ? before.s : before.progress;
        if (c->state == KC_CTRL_STOPPING || st == KC_E_LIMIT || st == KC_E_ARG) {
            /* Even the stop on the path cannot be followed: stop in joint
             * space from the last setpoint (the goal is active: its events
             * name it). */
            kc_ctrl_fault(c, KC_REASON_TRACKING, where, 0, out);
            return -1;
        }
        kc_ctrl_fault(c, KC_REASON_TRACKING, where, 1, out);
        return -1;
    }
    if (now.done && c->goal.kind != KC_GOAL_SERVO && !c->blend.on) {
        /* The geometry has ended: finished once the tool has settled. */
        if (st == KC_DONE)
            return 1;
        if ((kc_real)++c->settle * c->cfg.dt > SETTLE_S) {
            kc_ctrl_fault(c, KC_REASON_TRACKING, c->path_length, 0, out);
            return -1;
        }
    }
    return 0;
}
