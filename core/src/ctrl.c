/* ctrl.c - the controller step: goal queue, segments, stops on the path,
 * commands, the final limit check. Behaviour documented in kinctl/ctrl.h. */
#include "kinctl/ctrl.h"

#include <string.h>

#define INF ((kc_real)INFINITY)

/* Samples over a path stop when checking that a deceleration rate keeps
 * every joint within its acceleration limit. */
#define STOP_SAMPLES 16
/* Ticks a Cartesian segment may take after its geometry ends for the tool
 * to settle within the IK tolerances. */
#define SETTLE_TICKS 1000
/* A tracking error this many times cfg.track_tol during a stop on the path
 * abandons the path for a stop in joint space. */
#define TRACK_GIVE_UP 4

/* ---- configuration ---- */

kc_ctrl_cfg kc_ctrl_cfg_default(void)
{
    kc_ctrl_cfg c;
    c.dt = KC_R(0.001);
    c.cart_speed = KC_R(0.25);
    c.cart_accel = KC_R(0.5);
    c.cart_omega = KC_R(1.0);
    c.cart_alpha = KC_R(4.0);
    c.track_tol = KC_R(0.001);
#ifdef KC_REAL_FLOAT
    c.limit_slack = KC_R(1e-4);
#else
    c.limit_slack = KC_R(1e-6);
#endif
    c.servo_timeout_ticks = 100;
    c.zones = NULL;
    c.ik = kc_ik_cfg_default();
    /* Fed forward, the online law only has to remove what one tick leaves:
     * a gain of 100/s (k dt = 0.1) settles in tens of ms. */
    c.ik.gain_pos = KC_R(100.0);
    c.ik.gain_rot = KC_R(100.0);
#ifdef KC_REAL_FLOAT
    c.ik.tol_pos = KC_R(2e-5);
    c.ik.tol_rot = KC_R(2e-4);
#else
    c.ik.tol_pos = KC_R(1e-7);
    c.ik.tol_rot = KC_R(1e-7);
#endif
    return c;
}

static int positive(kc_real x) { return kc_isfinite(x) && x > KC_R(0.0); }

kc_status kc_ctrl_cfg_check(const kc_ctrl_cfg *cfg, const kc_chain *chain)
{
    if (cfg == NULL || chain == NULL)
        return KC_E_ARG;
    if (!positive(cfg->dt) || !positive(cfg->cart_speed) || !positive(cfg->cart_accel) ||
        !positive(cfg->cart_omega) || !positive(cfg->cart_alpha) || !positive(cfg->track_tol) ||
        !kc_isfinite(cfg->limit_slack) || cfg->limit_slack < KC_R(0.0) || cfg->servo_timeout_ticks < 1)
        return KC_E_ARG;
    if (kc_ik_cfg_check(&cfg->ik, chain) != KC_OK)
        return KC_E_ARG;
    /* The controller commands velocities within every joint's limits: they
     * must be finite. */
    for (int j = 0; j < chain->n_joints; j++)
        if (!kc_isfinite(chain->joints[j].limits.qd_max) || !kc_isfinite(chain->joints[j].limits.qdd_max))
            return KC_E_ARG;
    /* Zones: a goal is checked tick by tick, so no volume may travel as far
     * as the margin in one tick (see kinctl/zone.h). */
    if (cfg->zones != NULL &&
        (kc_zone_set_check(cfg->zones) != KC_OK ||
         (cfg->zones->n_zones > 0 && chain->n_volumes > 0 &&
          !(cfg->zones->margin > kc_zone_tick_travel(chain, cfg->dt)))))
        return KC_E_ARG;
    return KC_OK;
}

const char *kc_ctrl_reason_str(kc_ctrl_reason reason)
{
    switch (reason) {
    case KC_REASON_NONE: return "none";
    case KC_REASON_BAD_GOAL: return "a goal field is not finite or out of its domain";
    case KC_REASON_JOINT_COUNT: return "the goal's joint count does not match the arm";
    case KC_REASON_JOINT_LIMIT: return "a target lies outside the joint position limits";
    case KC_REASON_QUEUE_FULL: return "the goal queue is full";
    case KC_REASON_STATE: return "the controller is in fault or e-stop: reset first";
    case KC_REASON_PLAN: return "the motion cannot be planned (degenerate geometry or too long)";
    case KC_REASON_UNREACHABLE: return "the arm cannot follow this Cartesian motion";
    case KC_REASON_TRACKING: return "the tool fell behind the Cartesian path";
    case KC_REASON_LIMIT_GUARD: return "a setpoint failed the final limit check";
    case KC_REASON_SERVO_TIMEOUT: return "the servo stream went quiet";
    case KC_REASON_DUPLICATE_ID: return "a goal with this id is already active or queued";
    case KC_REASON_EXTERNAL: return "an external device (a drive, the field bus) reported a fault";
    case KC_REASON_ZONE: return "a link volume would enter the margin of a forbidden zone";
    case KC_REASON_COUNT: break;
    }
    return "unknown reason";
}

/* ---- goal checks ---- */

static int pose_ok(const kc_pose *p)
{
    return kc_pose_isfinite(p) && kc_mat3_rotation_error(&p->R) <= KC_TOL_ORTHONORMAL;
}

static int scale_ok(kc_real s) { return kc_isfinite(s) && s > KC_R(0.0) && s <= KC_R(1.0); }

static kc_status refuse(kc_ctrl_reason *reason, kc_ctrl_reason why)
{
    if (reason != NULL)
        *reason = why;
    return KC_E_ARG;
}

kc_status kc_ctrl_goal_check(const kc_chain *chain, const kc_goal *g, kc_ctrl_reason *reason)
{
    if (chain == NULL || g == NULL)
        return refuse(reason, KC_REASON_BAD_GOAL);
    int n = chain->n_joints;
    if ((unsigned)g->kind > (unsigned)KC_GOAL_SERVO || !scale_ok(g->vel_scale) || !scale_ok(g->acc_scale))
        return refuse(reason, KC_REASON_BAD_GOAL);
    if (!kc_isfinite(g->speed) || g->speed < KC_R(0.0) || !kc_isfinite(g->accel) || g->accel < KC_R(0.0) ||
        !kc_isfinite(g->omega) || g->omega < KC_R(0.0) || !kc_isfinite(g->alpha) || g->alpha < KC_R(0.0))
        return refuse(reason, KC_REASON_BAD_GOAL);
    switch (g->kind) {
    case KC_GOAL_JOINT: {
        int bad = 0;
        kc_status st = kc_chain_check_q(chain, g->q, &bad);
        if (st == KC_E_LIMIT)
            return refuse(reason, KC_REASON_JOINT_LIMIT);
        if (st != KC_OK)
            return refuse(reason, KC_REASON_BAD_GOAL);
        break;
    }
    case KC_GOAL_LINE:
        if (!pose_ok(&g->pose) || (g->orient != KC_INTERP_TWO_ROTATIONS && g->orient != KC_INTERP_SLERP))
            return refuse(reason, KC_REASON_BAD_GOAL);
        break;
    case KC_GOAL_ARC:
        if (!kc_vec3_isfinite(&g->pose.t) || !kc_vec3_isfinite(&g->via))
            return refuse(reason, KC_REASON_BAD_GOAL);
        break;
    case KC_GOAL_PATH:
    case KC_GOAL_PATH_CART: {
        int dim = g->kind == KC_GOAL_PATH ? n : 7;
        if (g->n_points < 1 || g->n_points > KC_PATH_MAX_KNOTS - 1 ||
            (unsigned)g->method > (unsigned)KC_PATH_QUINTIC || (unsigned)g->blend > (unsigned)KC_PATH_BLEND_PARABOLIC ||
            (unsigned)g->spline_end > (unsigned)KC_PATH_SPLINE_NATURAL || !kc_isfinite(g->blend_time) ||
            g->blend_time < KC_R(0.0))
            return refuse(reason, KC_REASON_BAD_GOAL);
        for (int i = 0; i < g->n_points; i++) {
            for (int j = 0; j < dim; j++)
                if (!kc_isfinite(g->points[i][j]))
                    return refuse(reason, KC_REASON_BAD_GOAL);
            if (g->kind == KC_GOAL_PATH) {
                int bad = 0;
                if (kc_chain_check_q(chain, g->points[i], &bad) != KC_OK)
                    return refuse(reason, KC_REASON_JOINT_LIMIT);
            }
            if (g->has_times && (!kc_isfinite(g->times[i]) || g->times[i] <= (i > 0 ? g->times[i - 1] : KC_R(0.0))))
                return refuse(reason, KC_REASON_BAD_GOAL);
        }
        break;
    }
    case KC_GOAL_SERVO:
        if (g->servo_twist) {
            for (int i = 0; i < 6; i++)
                if (!kc_isfinite(g->twist[i]))
                    return refuse(reason, KC_REASON_BAD_GOAL);
        } else if (!pose_ok(&g->pose)) {
            return refuse(reason, KC_REASON_BAD_GOAL);
        }
        break;
    }
    if (reason != NULL)
        *reason = KC_REASON_NONE;
    return KC_OK;
}

/* ---- forbidden zones (kinctl/zone.h) ---- */

static int zones_on(const kc_ctrl *c)
{
    return c->cfg.zones != NULL && c->cfg.zones->n_zones > 0 && c->chain->n_volumes > 0;
}

static void zone_init(kc_ctrl *c)
{
    kc_zone_hit none = {-1, -1, INF};
    c->zone_now = none;
    c->zone_hit = none;
    kc_zone_levers(c->chain, c->zone_lever);
    /* The servo's braking law: a point's braking a makes joint j brake at
     * most a / lever_j, so a = min qdd_max_j lever_j keeps every joint
     * within its limit; half of it leaves room for the IK's own changes. */
    c->zone_brake = INF;
    for (int j = 0; j < c->chain->n_joints; j++)
        if (c->zone_lever[j] > KC_R(0.0))
            c->zone_brake = kc_min(c->zone_brake, KC_R(0.5) * c->chain->joints[j].limits.qdd_max * c->zone_lever[j]);
    if (zones_on(c))
        kc_zone_check(c->chain, c->cfg.zones, c->q, NULL, &c->zone_now);
}

/* A servo step toward a zone approaches it by at most dt sqrt(2 a e) and
 * moves no volume point (by the lever bound) more than e / 2, e the
 * clearance beyond the margin at the last setpoint: the arm brakes into the
 * margin and never reaches it. The step is scaled as a whole (the tool
 * keeps its direction), its velocity change kept within the acceleration
 * limits. */
static void zone_servo_limit(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd)
{
    int n = c->chain->n_joints;
    kc_real travel = KC_R(0.0), dt = c->cfg.dt;
    for (int j = 0; j < n; j++)
        travel += kc_fabs(q[j] - c->q[j]) * c->zone_lever[j];
    if (!(travel > KC_R(0.0)))
        return;
    kc_zone_hit hit;
    kc_status st = kc_zone_check(c->chain, c->cfg.zones, q, NULL, &hit);
    if ((st != KC_OK && st != KC_E_LIMIT) || hit.distance >= c->zone_now.distance)
        return; /* not finite (the final check refuses it) or not approaching */
    kc_real e = kc_max(c->zone_now.distance - c->cfg.zones->margin, KC_R(0.0));
    /* The braking law on the measured approach; the bound on the travel
     * of any point keeps the step short of the margin whatever it is. */
    kc_real approach = c->zone_now.distance - hit.distance, s = KC_R(1.0), a = KC_R(1.0);
    kc_real brake = dt * kc_sqrt(KC_R(2.0) * c->zone_brake * e);
    if (approach > brake)
        s = brake / approach;
    if (travel * s > KC_R(0.5) * e)
        s = KC_R(0.5) * e / travel;
    if (s >= KC_R(1.0))
        return;
    for (int j = 0; j < n; j++) {
        kc_real dv = kc_fabs(s * qd[j] - c->qd[j]), lim = c->chain->joints[j].limits.qdd_max * dt;
        if (dv * a > lim)
            a = lim / dv;
    }
    for (int j = 0; j < n; j++) {
        qd[j] = c->qd[j] + a * (s * qd[j] - c->qd[j]);
        q[j] = c->q[j] + qd[j] * dt;
        qdd[j] = (qd[j] - c->qd[j]) / dt;
    }
    /* A twist stream's target stays with the restrained arm instead of
     * running on into the zone, so a reversed twist moves it away at once. */
    if (c->goal.servo_twist)
        kc_fk_eval(c->chain, q, &c->servo_target);
}

static void joint_stop(kc_ctrl *c, int sync, kc_ctrl_state then);
static void queue_clear(kc_ctrl *c, kc_ctrl_output *out);
static void emit(kc_ctrl_output *out, kc_ctrl_event_kind kind, int64_t id, kc_ctrl_reason reason, kc_real where);

static void emit_zone(kc_ctrl_output *out, kc_ctrl_event_kind kind, int64_t id, kc_real where, const kc_zone_hit *hit)
{
    int before = out->n_events;
    emit(out, kind, id, KC_REASON_ZONE, where);
    if (out->n_events > before) {
        out->events[before].zone = hit->zone;
        out->events[before].volume = hit->volume;
    }
}

/* The final check against the zones: a setpoint that comes closer than
 * the margin (and closer than the last one) is replaced by the first tick
 * of an e-stop-like stop from the last good setpoint, and the controller
 * faults naming the pair. */
static void zone_guard(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd, kc_ctrl_output *out)
{
    kc_zone_hit hit;
    if (kc_zone_check(c->chain, c->cfg.zones, q, NULL, &hit) == KC_E_ARG)
        return; /* not finite: never the case after setpoint_ok */
    if (c->fault_reason == KC_REASON_ZONE || !(hit.distance < c->cfg.zones->margin) ||
        !(hit.distance < c->zone_now.distance)) {
        c->zone_now = hit;
        return;
    }
    kc_real where = c->active && c->path_length > KC_R(0.0) ? out->progress * c->path_length : out->progress;
    c->zone_hit = hit;
    c->fault_reason = KC_REASON_ZONE;
    emit_zone(out, KC_EVENT_FAULT, c->active ? c->goal.id : 0, where, &hit);
    if (c->active)
        emit_zone(out, KC_EVENT_ABORTED, c->goal.id, where, &hit);
    queue_clear(c, out);
    joint_stop(c, 0, KC_CTRL_FAULT);
    c->state = KC_CTRL_STOPPING;
    for (int j = 0; j < c->chain->n_joints; j++) {
        kc_profile_state s;
        kc_profile_eval(&c->jstop_prof[j], c->cycle - c->jstop_k0, &s);
        q[j] = s.p;
        qd[j] = s.v;
        qdd[j] = s.a;
    }
    kc_zone_check(c->chain, c->cfg.zones, q, NULL, &c->zone_now);
}

/* ---- init ---- */

kc_status kc_ctrl_init(kc_ctrl *c, const kc_chain *chain, const kc_ctrl_cfg *cfg, const kc_real *q0)
{
    if (c == NULL || chain == NULL || cfg == NULL || q0 == NULL || kc_chain_check(chain) != KC_OK ||
        kc_ctrl_cfg_check(cfg, chain) != KC_OK || kc_chain_check_q(chain, q0, NULL) != KC_OK)
        return KC_E_ARG;
    memset(c, 0, sizeof *c);
    c->chain = chain;
    c->cfg = *cfg;
    c->state = KC_CTRL_IDLE;
    for (int j = 0; j < chain->n_joints; j++)
        c->q[j] = q0[j];
    zone_init(c);
    return KC_OK;
}

/* ---- events and the queue ---- */

static void emit(kc_ctrl_output *out, kc_ctrl_event_kind kind, int64_t id, kc_ctrl_reason reason, kc_real where)
{
    if (out->n_events >= KC_CTRL_EVENTS_MAX)
        return; /* not reached: KC_CTRL_EVENTS_MAX bounds a tick's events (ctrl.h) */
    kc_ctrl_event *e = &out->events[out->n_events++];
    e->kind = kind;
    e->goal_id = id;
    e->reason = reason;
    e->where = where;
    e->zone = -1;
    e->volume = -1;
}

static void queue_clear(kc_ctrl *c, kc_ctrl_output *out)
{
    for (int i = 0; i < c->queue_len; i++)
        emit(out, KC_EVENT_PREEMPTED, c->queue[(c->queue_head + i) % KC_CTRL_QUEUE_MAX].id, KC_REASON_NONE, 0);
    c->queue_head = 0;
    c->queue_len = 0;
}

static void queue_push(kc_ctrl *c, const kc_goal *g)
{
    c->queue[(c->queue_head + c->queue_len) % KC_CTRL_QUEUE_MAX] = *g;
    c->queue_len++;
}

/* ---- limits ---- */

static void scaled_limits(const kc_ctrl *c, const kc_goal *g, kc_real *vmax, kc_real *amax)
{
    for (int j = 0; j < c->chain->n_joints; j++) {
        vmax[j] = c->chain->joints[j].limits.qd_max * g->vel_scale;
        amax[j] = c->chain->joints[j].limits.qdd_max * g->acc_scale;
    }
}

static kc_interp_limits cart_limits(const kc_ctrl *c, const kc_goal *g)
{
    kc_interp_limits l = kc_interp_limits_default();
    l.v = g->speed > KC_R(0.0) ? g->speed : c->cfg.cart_speed;
    l.a = g->accel > KC_R(0.0) ? g->accel : c->cfg.cart_accel;
    l.w = g->omega > KC_R(0.0) ? g->omega : c->cfg.cart_omega;
    l.dw = g->alpha > KC_R(0.0) ? g->alpha : c->cfg.cart_alpha;
    return l;
}

static int is_path(kc_goal_kind k) { return k == KC_GOAL_PATH || k == KC_GOAL_PATH_CART; }

/* ---- starting a segment ---- */

static kc_status plan_path(kc_ctrl *c, const kc_goal *g)
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
            knots[j] = c->q[j];
        for (int i = 1; i < m; i++)
            for (int j = 0; j < n; j++)
                knots[i * n + j] = g->points[i - 1][j];
        cfg.method = g->method;
        cfg.blend = g->blend;
        cfg.spline_end = g->spline_end;
        cfg.n_knots = m;
        cfg.dim = n;
        cfg.q = knots;
        cfg.t = g->has_times ? times : NULL;
        cfg.t_acc = g->blend_time;
        scaled_limits(c, g, cfg.vmax, cfg.amax);
        cfg.dt = c->cfg.dt;
        return kc_path_plan(&c->plan.path, &cfg);
    }
    kc_vec3 p[KC_PATH_MAX_KNOTS];
    kc_quat r[KC_PATH_MAX_KNOTS];
    kc_pose start;
    kc_fk_eval(c->chain, c->q, &start);
    p[0] = start.t;
    kc_quat_from_mat3(&start.R, &r[0]);
    for (int i = 1; i < m; i++) {
        const kc_real *v = g->points[i - 1];
        p[i] = kc_vec3_make(v[0], v[1], v[2]);
        r[i].w = v[3];
        r[i].x = v[4];
        r[i].y = v[5];
        r[i].z = v[6];
    }
    kc_interp_limits lim = cart_limits(c, g);
    kc_path_cart_cfg cfg = kc_path_cart_cfg_default();
    cfg.method = g->method;
    cfg.blend = g->blend;
    cfg.spline_end = g->spline_end;
    cfg.n_knots = m;
    cfg.p = p;
    cfg.r = r;
    cfg.t = g->has_times ? times : NULL;
    cfg.t_acc = g->blend_time;
    cfg.v_max = lim.v;
    cfg.a_max = lim.a;
    cfg.w_max = lim.w;
    cfg.alpha_max = lim.dw;
    cfg.dt = c->cfg.dt;
    kc_status st = kc_path_cart_plan(&c->plan.path_cart, &cfg);
    if (st == KC_OK)
        c->path_length = c->plan.path_cart.length;
    return st;
}

/* Plans the goal in c->goal from the current (resting) state. */
static kc_status plan_goal(kc_ctrl *c)
{
    const kc_goal *g = &c->goal;
    kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS];
    kc_pose from;
    kc_interp_limits lim = cart_limits(c, g);
    kc_fk_eval(c->chain, c->q, &from);
    c->path_length = KC_R(0.0);
    switch (g->kind) {
    case KC_GOAL_JOINT:
        scaled_limits(c, g, vmax, amax);
        return kc_interp_joint_plan(&c->plan.joint, c->chain->n_joints, c->q, g->q, vmax, amax, KC_R(0.0), c->cfg.dt);
    case KC_GOAL_LINE: {
        kc_status st = kc_interp_line_plan(&c->plan.line, &from, &g->pose, &lim, g->orient, c->cfg.dt);
        c->path_length = c->plan.line.length;
        return st;
    }
    case KC_GOAL_ARC: {
        kc_status st = kc_interp_arc_plan(&c->plan.arc, &from, &g->via, &g->pose.t, &lim, c->cfg.dt);
        c->path_length = c->plan.arc.length;
        return st;
    }
    case KC_GOAL_PATH:
    case KC_GOAL_PATH_CART:
        return plan_path(c, g);
    case KC_GOAL_SERVO:
        c->servo_target = g->servo_twist ? from : g->pose;
        c->servo_last = c->cycle;
        return KC_OK;
    }
    return KC_E_ARG;
}

static kc_real path_ramp_rate(const kc_ctrl *c, kc_real tau0);
static int path_starts_at_rest(const kc_ctrl *c);

/* Starts the next queued goal, if any; returns 1 when a segment is active. */
static int start_next(kc_ctrl *c, kc_ctrl_output *out)
{
    while (c->queue_len > 0) {
        c->goal = c->queue[c->queue_head];
        c->queue_head = (c->queue_head + 1) % KC_CTRL_QUEUE_MAX;
        c->queue_len--;
        /* Tick 0 of the segment is the last setpoint: the first output is
         * its tick 1. */
        c->k0 = c->cycle - 1;
        c->drive = KC_DRIVE_NOMINAL;
        c->stop_intent = KC_CMD_NONE;
        c->settle = 0;
        if (plan_goal(c) != KC_OK) {
            emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_PLAN, 0);
            continue;
        }
        if (is_path(c->goal.kind) && !path_starts_at_rest(c)) {
            /* Lagrange's polynomial moves at its first and last knot: run
             * it on a tau' that ramps up from rest and down into the end. */
            kc_real T = c->goal.kind == KC_GOAL_PATH ? c->plan.path.duration : c->plan.path_cart.pos.duration;
            kc_real C = path_ramp_rate(c, KC_R(0.0));
            if (!(C > KC_R(0.0)) || kc_profile_plan(&c->drive_prof, KC_R(0.0), KC_R(0.0), T, KC_R(1.0), C, c->cfg.dt) != KC_OK) {
                emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_PLAN, 0);
                continue;
            }
            c->drive = KC_DRIVE_PROFILE;
        }
        c->active = 1;
        c->state = KC_CTRL_MOVING;
        emit(out, KC_EVENT_STARTED, c->goal.id, KC_REASON_NONE, 0);
        return 1;
    }
    c->active = 0;
    return 0;
}

/* ---- the desired motion of the active segment ---- */

/* What the segment asks for at one tick: joints, or a Cartesian pose with
 * its twist. */
typedef struct seg_point {
    int cart;
    kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS], qdd[KC_MAX_JOINTS];
    kc_pose pose;
    kc_real twist[6];
    kc_real progress; /* 0..1 */
    kc_real s;        /* path length so far (m), Cartesian segments */
    int done;         /* the segment's own timing has ended (at rest) */
} seg_point;

static void cart_point(seg_point *o, const kc_vec3 *p, const kc_quat *r, const kc_vec3 *v, const kc_vec3 *w,
                       kc_real rate)
{
    o->cart = 1;
    o->pose.t = *p;
    kc_quat_to_mat3(r, &o->pose.R);
    for (int i = 0; i < 3; i++) {
        o->twist[i] = v->v[i] * rate;
        o->twist[3 + i] = w->v[i] * rate;
    }
}

/* The u (or tau) state driving the segment at its tick j. */
static void drive_state(const kc_ctrl *c, int64_t j, kc_profile_state *u)
{
    if (c->drive == KC_DRIVE_PROFILE) {
        kc_profile_eval(&c->drive_prof, j, u);
        return;
    }
    if (is_path(c->goal.kind)) {
        u->p = (kc_real)j * c->cfg.dt;
        u->v = KC_R(1.0);
        u->a = KC_R(0.0);
        u->phase = 2;
        return;
    }
    const kc_profile *prof = c->goal.kind == KC_GOAL_JOINT ? &c->plan.joint.prof
                             : c->goal.kind == KC_GOAL_LINE ? &c->plan.line.prof
                                                            : &c->plan.arc.prof;
    kc_profile_eval(prof, j, u);
}

/* Joint path at plan time tau with rate tau' and tau'': chain rule. */
static int path_joint_at(const kc_path *path, kc_real tau, kc_real rate, kc_real rate_dot, int n, seg_point *o)
{
    kc_real d1[KC_MAX_JOINTS], d2[KC_MAX_JOINTS];
    kc_status st = kc_path_eval_time(path, kc_max(tau, KC_R(0.0)), o->q, d1, d2);
    for (int j = 0; j < n; j++) {
        o->qd[j] = d1[j] * rate;
        o->qdd[j] = d2[j] * rate * rate + d1[j] * rate_dot;
    }
    return st == KC_DONE;
}

/* A retarget (or its stop) at its tick j: every joint on its own profile;
 * done when the last one has ended. */
static void retarget_eval(const kc_ctrl *c, int64_t j, seg_point *o)
{
    int64_t ticks = 0;
    o->done = 1;
    for (int i = 0; i < c->chain->n_joints; i++) {
        kc_profile_state s;
        if (kc_profile_eval(&c->plan.retarget[i], j, &s) != KC_DONE)
            o->done = 0;
        o->q[i] = s.p;
        o->qd[i] = s.v;
        o->qdd[i] = s.a;
        if (c->plan.retarget[i].ticks > ticks)
            ticks = c->plan.retarget[i].ticks;
    }
    o->progress = ticks > 0 ? kc_min((kc_real)j / (kc_real)ticks, KC_R(1.0)) : KC_R(1.0);
}

/* The segment's point at its tick j (j >= 0). */
static void seg_eval(const kc_ctrl *c, int64_t j, seg_point *o)
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
        if (c->drive == KC_DRIVE_RETARGET) {
            retarget_eval(c, j, o);
            return;
        }
        kc_interp_joint_state s;
        kc_status st = c->drive == KC_DRIVE_PROFILE ? kc_interp_joint_eval_profile(&c->plan.joint, &c->drive_prof, j, &s)
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
        kc_interp_cart_state s;
        kc_status st;
        if (g->kind == KC_GOAL_LINE)
            st = c->drive == KC_DRIVE_PROFILE ? kc_interp_line_eval_profile(&c->plan.line, &c->drive_prof, j, &s)
                                              : kc_interp_line_eval(&c->plan.line, j, &s);
        else
            st = c->drive == KC_DRIVE_PROFILE ? kc_interp_arc_eval_profile(&c->plan.arc, &c->drive_prof, j, &s)
                                              : kc_interp_arc_eval(&c->plan.arc, j, &s);
        cart_point(o, &s.p, &s.q, &s.v, &s.w, KC_R(1.0));
        o->progress = s.u;
        o->s = s.s;
        o->done = st == KC_DONE;
        return;
    }
    case KC_GOAL_PATH:
    case KC_GOAL_PATH_CART: {
        kc_profile_state u;
        drive_state(c, j, &u);
        kc_real T = g->kind == KC_GOAL_PATH ? c->plan.path.duration : c->plan.path_cart.pos.duration;
        o->progress = T > KC_R(0.0) ? kc_min(u.p / T, KC_R(1.0)) : KC_R(1.0);
        if (g->kind == KC_GOAL_PATH) {
            int end = path_joint_at(&c->plan.path, u.p, u.v, u.a, n, o);
            o->done = c->drive == KC_DRIVE_PROFILE ? c->drive_prof.ticks <= j : end;
        } else {
            kc_path_pose s;
            kc_status st = kc_path_cart_eval_time(&c->plan.path_cart, kc_max(u.p, KC_R(0.0)), &s);
            cart_point(o, &s.p, &s.r, &s.v, &s.w, u.v);
            o->s = s.s;
            o->done = c->drive == KC_DRIVE_PROFILE ? c->drive_prof.ticks <= j : st == KC_DONE;
        }
        return;
    }
    case KC_GOAL_SERVO: {
        kc_vec3 zero = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
        kc_quat r;
        kc_quat_from_mat3(&c->servo_target.R, &r);
        cart_point(o, &c->servo_target.t, &r, &zero, &zero, KC_R(0.0));
        if (g->servo_twist)
            for (int i = 0; i < 6; i++)
                o->twist[i] = g->twist[i];
        o->progress = KC_R(0.0);
        return;
    }
    }
}

/* ---- stops ---- */

/* Largest |q'' tau'^2 + q' tau''| / qdd_max (Cartesian: the tool point's
 * acceleration over its limit) on sampled instants of a change of tau' at
 * the constant rate a for the time D, from plan time tau0 at rate r0: at
 * most 1 when it keeps every limit. A stop is (tau, rate, -C, rate / C), a
 * start from rest (tau, 0, C, 1 / C), the ramp into the end (T - 1/(2C),
 * 1, -C, 1 / C). */
static kc_real path_ramp_load(const kc_ctrl *c, kc_real tau0, kc_real r0, kc_real a, kc_real D)
{
    const kc_goal *g = &c->goal;
    int n = c->chain->n_joints;
    kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS], worst = KC_R(0.0);
    scaled_limits(c, g, vmax, amax);
    kc_real a_cart = cart_limits(c, g).a;
    for (int i = 0; i <= STOP_SAMPLES; i++) {
        kc_real t = D * (kc_real)i / (kc_real)STOP_SAMPLES;
        kc_real r = r0 + a * t, at = kc_max(tau0 + r0 * t + KC_R(0.5) * a * t * t, KC_R(0.0));
        if (g->kind == KC_GOAL_PATH) {
            kc_real q[KC_MAX_JOINTS], d1[KC_MAX_JOINTS], d2[KC_MAX_JOINTS];
            kc_path_eval_time(&c->plan.path, at, q, d1, d2);
            for (int j = 0; j < n; j++)
                worst = kc_max(worst, kc_fabs(d2[j] * r * r + d1[j] * a) / amax[j]);
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
    scaled_limits(c, g, vmax, amax);
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
            dec = cart_limits(c, g).a / speed;
    }
    if (!kc_isfinite(dec))
        dec = KC_R(1.0) / c->cfg.dt; /* standing still: stop within a tick */
    for (int tries = 0; tries < 6; tries++) {
        if (path_ramp_load(c, tau, rate, -dec, rate / dec) <= KC_R(1.0))
            return dec;
        dec *= KC_R(0.5);
    }
    return KC_R(0.0);
}

/* The rate C of a tau' ramp from rest at tau0 up to 1 that, with the same
 * ramp down into the path's end, keeps every limit (a path that does not
 * start or end at rest, Lagrange's, and every resume); 0 when none of the
 * rates tried does. */
static kc_real path_ramp_rate(const kc_ctrl *c, kc_real tau0)
{
    kc_real T = c->goal.kind == KC_GOAL_PATH ? c->plan.path.duration : c->plan.path_cart.pos.duration;
    kc_real C = KC_R(1.0) / (KC_R(10.0) * c->cfg.dt); /* a ramp of at least ten ticks */
    for (int tries = 0; tries < 16; tries++) {
        if (path_ramp_load(c, tau0, KC_R(0.0), C, KC_R(1.0) / C) <= KC_R(1.0) &&
            path_ramp_load(c, T - KC_R(0.5) / C, KC_R(1.0), -C, KC_R(1.0) / C) <= KC_R(1.0))
            return C;
        C *= KC_R(0.5);
    }
    return KC_R(0.0);
}

/* Whether the planned path starts at rest (every knot method but Lagrange). */
static int path_starts_at_rest(const kc_ctrl *c)
{
    if (c->goal.kind == KC_GOAL_PATH) {
        kc_real q[KC_MAX_JOINTS], d1[KC_MAX_JOINTS], d2[KC_MAX_JOINTS];
        kc_path_eval_time(&c->plan.path, KC_R(0.0), q, d1, d2);
        for (int j = 0; j < c->chain->n_joints; j++)
            if (d1[j] != KC_R(0.0))
                return 0;
        return 1;
    }
    kc_path_pose s;
    kc_path_cart_eval_time(&c->plan.path_cart, KC_R(0.0), &s);
    return kc_vec3_norm(&s.v) == KC_R(0.0) && kc_vec3_norm(&s.w) == KC_R(0.0);
}

/* A stop of every joint in joint space: each at its own acceleration limit
 * (hard, for e-stop) or all synchronised on the current direction of motion
 * (sync). Ends in state `then`. */
static void joint_stop(kc_ctrl *c, int sync, kc_ctrl_state then)
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

/* Starts (or, for a path braking hard, arms) the stop on the path of the
 * active segment, for the given intent. */
static void stop_on_path(kc_ctrl *c, int intent)
{
    c->stop_intent = intent;
    c->state = KC_CTRL_STOPPING;
    int64_t j = (c->cycle - 1) - c->k0; /* the last setpoint's tick */
    kc_profile_state u;
    if (c->goal.kind == KC_GOAL_SERVO) {
        joint_stop(c, 1, intent == KC_CMD_PAUSE ? KC_CTRL_PAUSED : KC_CTRL_IDLE);
        c->active = 1; /* the servo goal stays active through its stop */
        return;
    }
    if (c->drive == KC_DRIVE_RETARGET) {
        /* Each joint brakes at the goal's own acceleration limit: it comes
         * to rest no further than its profile would have turned, so inside
         * the position limits the retarget was checked against. */
        kc_real vmax[KC_MAX_JOINTS] = {KC_R(0.0)}, amax[KC_MAX_JOINTS] = {KC_R(0.0)};
        scaled_limits(c, &c->goal, vmax, amax);
        for (int i = 0; i < c->chain->n_joints; i++)
            kc_profile_plan_stop(&c->plan.retarget[i], c->q[i], c->qd[i], amax[i], c->cfg.dt);
        c->k0 = c->cycle - 1;
        return;
    }
    drive_state(c, j, &u);
    if (is_path(c->goal.kind)) {
        kc_real dec = path_stop_rate(c, u.p, u.v);
        if (!(dec > KC_R(0.0))) {
            c->drive = c->drive == KC_DRIVE_PROFILE ? KC_DRIVE_PROFILE : KC_DRIVE_STOPPING_WAIT;
            return;
        }
        kc_profile_plan_stop(&c->drive_prof, u.p, u.v, dec, c->cfg.dt);
    } else {
        kc_real amax = c->goal.kind == KC_GOAL_JOINT ? c->plan.joint.u_amax
                       : c->goal.kind == KC_GOAL_LINE ? c->plan.line.u_amax
                                                      : c->plan.arc.u_amax;
        if (!kc_isfinite(amax))
            amax = KC_R(1.0); /* a zero motion: nothing to stop */
        kc_profile_plan_stop(&c->drive_prof, u.p, u.v, amax, c->cfg.dt);
    }
    c->drive = KC_DRIVE_PROFILE;
    c->k0 = c->cycle - 1;
}

/* Resumes a paused segment from where it rests. */
static void resume(kc_ctrl *c, kc_ctrl_output *out)
{
    int64_t j = (c->cycle - 1) - c->k0;
    kc_profile_state u;
    c->state = KC_CTRL_MOVING;
    c->stop_intent = KC_CMD_NONE;
    if (c->goal.kind == KC_GOAL_SERVO) {
        c->servo_last = c->cycle;
        return;
    }
    if (c->drive == KC_DRIVE_RETARGET) {
        /* At rest a retarget is an ordinary joint move from here. */
        c->drive = KC_DRIVE_NOMINAL;
        c->k0 = c->cycle - 1;
        if (plan_goal(c) != KC_OK) {
            emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_PLAN, 0);
            c->active = 0;
            c->state = KC_CTRL_IDLE;
        }
        return;
    }
    drive_state(c, j, &u);
    if (is_path(c->goal.kind)) {
        kc_real T = c->goal.kind == KC_GOAL_PATH ? c->plan.path.duration : c->plan.path_cart.pos.duration;
        kc_real C = path_ramp_rate(c, u.p);
        if (!(C > KC_R(0.0)))
            C = KC_R(1.0); /* the rates tried all fail: the gentlest ramp there is */
        kc_profile_plan(&c->drive_prof, u.p, KC_R(0.0), T, KC_R(1.0), C, c->cfg.dt);
    } else {
        const kc_interp_joint *pj = &c->plan.joint;
        kc_real vmax = c->goal.kind == KC_GOAL_JOINT ? pj->u_vmax
                       : c->goal.kind == KC_GOAL_LINE ? c->plan.line.u_vmax
                                                      : c->plan.arc.u_vmax;
        kc_real amax = c->goal.kind == KC_GOAL_JOINT ? pj->u_amax
                       : c->goal.kind == KC_GOAL_LINE ? c->plan.line.u_amax
                                                      : c->plan.arc.u_amax;
        if (!kc_isfinite(amax))
            amax = KC_R(1.0);
        kc_profile_plan(&c->drive_prof, u.p, KC_R(0.0), KC_R(1.0), vmax, amax, c->cfg.dt);
    }
    c->drive = KC_DRIVE_PROFILE;
    c->k0 = c->cycle - 1;
}

/* ---- commands and goals ---- */

static int at_rest(const kc_ctrl *c)
{
    for (int j = 0; j < c->chain->n_joints; j++)
        if (c->qd[j] != KC_R(0.0))
            return 0;
    return 1;
}

static int joint_stopping(const kc_ctrl *c) { return c->jstop; }

static void command(kc_ctrl *c, kc_ctrl_command cmd, kc_ctrl_output *out)
{
    switch (cmd) {
    case KC_CMD_NONE: return;
    case KC_CMD_ESTOP:
        if (c->state == KC_CTRL_ESTOP)
            return;
        queue_clear(c, out);
        /* A goal still active after a fault is stopping on its path and
         * was aborted with the fault. */
        if (c->active && c->fault_reason == KC_REASON_NONE)
            emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_NONE, 0);
        joint_stop(c, 0, KC_CTRL_ESTOP);
        c->state = KC_CTRL_ESTOP;
        return;
    case KC_CMD_RESET:
        if ((c->state == KC_CTRL_FAULT || c->state == KC_CTRL_ESTOP) && at_rest(c) && !c->jstop) {
            c->state = KC_CTRL_IDLE;
            c->fault_reason = KC_REASON_NONE;
        }
        return;
    case KC_CMD_STOP:
        if (c->state == KC_CTRL_FAULT || c->state == KC_CTRL_ESTOP)
            return;
        queue_clear(c, out);
        if (c->state == KC_CTRL_PAUSED) {
            emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_NONE, 0);
            c->active = 0;
            c->state = KC_CTRL_IDLE;
        } else if (c->active && c->state == KC_CTRL_MOVING) {
            stop_on_path(c, KC_CMD_STOP);
        } else if (c->state == KC_CTRL_STOPPING) {
            c->stop_intent = KC_CMD_STOP; /* whatever the stop was for, it now ends the goal */
        }
        return;
    case KC_CMD_PAUSE:
        if (c->active && c->state == KC_CTRL_MOVING)
            stop_on_path(c, KC_CMD_PAUSE);
        return;
    case KC_CMD_RESUME:
        if (c->state == KC_CTRL_PAUSED && c->active)
            resume(c, out);
        else if (c->state == KC_CTRL_STOPPING && c->stop_intent == KC_CMD_PAUSE)
            c->stop_intent = KC_CMD_RESUME; /* resume as soon as the pause has stopped */
        return;
    }
}

/* Whether a goal of this id is active or queued. */
static int id_in_flight(const kc_ctrl *c, int64_t id)
{
    if (c->active && c->goal.id == id)
        return 1;
    for (int i = 0; i < c->queue_len; i++)
        if (c->queue[(c->queue_head + i) % KC_CTRL_QUEUE_MAX].id == id)
            return 1;
    return 0;
}

/* Preemption marker for stop_intent. */
#define INTENT_PREEMPT 100

/* Plans joint move g from the current, possibly moving, state into
 * c->plan.retarget, one time-optimal profile a joint, when every profile
 * stays inside its joint's position limits: a joint moving away from its
 * target first brakes through zero at p0 + v0 |v0| / (2 |a1|) (the other
 * phases run monotonically between the current q and the target). Returns 1
 * when planned; on 0 the active segment is untouched and the preemption
 * falls back to the stop on the path. */
static int retarget(kc_ctrl *c, const kc_goal *g)
{
    kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS];
    kc_profile prof[KC_MAX_JOINTS];
    scaled_limits(c, g, vmax, amax);
    for (int j = 0; j < c->chain->n_joints; j++) {
        const kc_joint_limits *l = &c->chain->joints[j].limits;
        kc_profile *p = &prof[j];
        if (kc_profile_plan(p, c->q[j], c->qd[j], g->q[j], vmax[j], amax[j], c->cfg.dt) != KC_OK)
            return 0;
        if (p->v0 * p->vc < KC_R(0.0)) {
            kc_real turn = p->p0 + p->v0 * kc_fabs(p->v0) / (KC_R(2.0) * kc_fabs(p->a1));
            if (!(turn >= l->q_min && turn <= l->q_max))
                return 0;
        }
    }
    /* cppcheck-suppress uninitvar ; the loop above planned prof[0..n_joints) or returned */
    memcpy(c->plan.retarget, prof, sizeof(kc_profile) * (size_t)c->chain->n_joints);
    return 1;
}

/* Makes g, whose retarget is planned, the active segment from this tick. */
static void take_retarget(kc_ctrl *c, const kc_goal *g)
{
    c->goal = *g;
    c->drive = KC_DRIVE_RETARGET;
    c->k0 = c->cycle - 1; /* tick 0 is the last setpoint, as for every segment */
    c->stop_intent = KC_CMD_NONE;
    c->settle = 0;
    c->path_length = KC_R(0.0);
    c->jstop = 0; /* a servo's stop in joint space gives way too */
    c->active = 1;
    c->state = KC_CTRL_MOVING;
}

static void take_goal(kc_ctrl *c, const kc_goal *g, kc_ctrl_output *out)
{
    kc_ctrl_reason why = KC_REASON_NONE;
    /* A servo update for the active servo goal moves its target. */
    if (g->kind == KC_GOAL_SERVO && c->active && c->goal.kind == KC_GOAL_SERVO && g->id == c->goal.id &&
        kc_ctrl_goal_check(c->chain, g, &why) == KC_OK) {
        c->goal.servo_twist = g->servo_twist;
        memcpy(c->goal.twist, g->twist, sizeof g->twist);
        if (!g->servo_twist)
            c->servo_target = g->pose;
        c->servo_last = c->cycle;
        return;
    }
    /* So does one for a servo goal still waiting in the queue (a replacing
     * servo goal waits while the motion before it stops on its path): the
     * stream's messages are one goal, answered once. */
    if (g->kind == KC_GOAL_SERVO && kc_ctrl_goal_check(c->chain, g, &why) == KC_OK) {
        for (int i = 0; i < c->queue_len; i++) {
            kc_goal *w = &c->queue[(c->queue_head + i) % KC_CTRL_QUEUE_MAX];
            if (w->kind == KC_GOAL_SERVO && w->id == g->id) {
                w->servo_twist = g->servo_twist;
                memcpy(w->twist, g->twist, sizeof g->twist);
                w->pose = g->pose;
                return;
            }
        }
    }
    if (c->state == KC_CTRL_FAULT || c->state == KC_CTRL_ESTOP || c->fault_reason != KC_REASON_NONE) {
        emit(out, KC_EVENT_REJECTED, g->id, KC_REASON_STATE, 0);
        return;
    }
    if (id_in_flight(c, g->id)) {
        /* Its answers could not be told from the other goal's. */
        emit(out, KC_EVENT_REJECTED, g->id, KC_REASON_DUPLICATE_ID, 0);
        return;
    }
    if (kc_ctrl_goal_check(c->chain, g, &why) != KC_OK) {
        emit(out, KC_EVENT_REJECTED, g->id, why, 0);
        return;
    }
    if (g->replace) {
        queue_clear(c, out);
        if (g->kind == KC_GOAL_JOINT && c->active &&
            (c->state == KC_CTRL_MOVING || c->state == KC_CTRL_STOPPING) && retarget(c, g)) {
            emit(out, KC_EVENT_ACCEPTED, g->id, KC_REASON_NONE, 0);
            emit(out, KC_EVENT_PREEMPTED, c->goal.id, KC_REASON_NONE, 0);
            take_retarget(c, g);
            emit(out, KC_EVENT_STARTED, g->id, KC_REASON_NONE, 0);
            return;
        }
        queue_push(c, g);
        emit(out, KC_EVENT_ACCEPTED, g->id, KC_REASON_NONE, 0);
        if (c->active && c->state == KC_CTRL_MOVING) {
            stop_on_path(c, INTENT_PREEMPT);
        } else if (c->active && c->state == KC_CTRL_STOPPING) {
            c->stop_intent = INTENT_PREEMPT;
        } else if (c->active && c->state == KC_CTRL_PAUSED) {
            /* Already at rest: the paused goal gives way at once. */
            emit(out, KC_EVENT_PREEMPTED, c->goal.id, KC_REASON_NONE, 0);
            c->active = 0;
            c->state = KC_CTRL_IDLE;
        }
        return;
    }
    if (c->queue_len >= KC_CTRL_QUEUE_MAX) {
        emit(out, KC_EVENT_REJECTED, g->id, KC_REASON_QUEUE_FULL, 0);
        return;
    }
    queue_push(c, g);
    emit(out, KC_EVENT_ACCEPTED, g->id, KC_REASON_NONE, 0);
}

/* ---- the step ---- */

/* Ends the active segment after its stop on the path came to rest. */
static void stop_finished(kc_ctrl *c, kc_ctrl_output *out)
{
    int intent = c->stop_intent;
    c->stop_intent = KC_CMD_NONE;
    if (intent == KC_CMD_PAUSE) {
        c->state = KC_CTRL_PAUSED;
        return;
    }
    if (intent == KC_CMD_RESUME) {
        resume(c, out);
        return;
    }
    c->active = 0;
    if (intent == INTENT_PREEMPT) {
        emit(out, KC_EVENT_PREEMPTED, c->goal.id, KC_REASON_NONE, 0);
        c->state = KC_CTRL_IDLE;
        return;
    }
    if (c->fault_reason != KC_REASON_NONE) {
        c->state = KC_CTRL_FAULT;
        return;
    }
    emit(out, KC_EVENT_ABORTED, c->goal.id, c->goal.kind == KC_GOAL_SERVO && intent == KC_CMD_NONE
                                                  ? KC_REASON_SERVO_TIMEOUT
                                                  : KC_REASON_NONE,
         0);
    c->state = KC_CTRL_IDLE;
}

/* Puts the controller into a fault: the event, then a stop (on the path
 * when the segment allows it, else in joint space). */
static void fault(kc_ctrl *c, kc_ctrl_reason why, kc_real where, int on_path, kc_ctrl_output *out)
{
    if (c->fault_reason != KC_REASON_NONE) {
        /* Already in a fault, whose events went out with it (the goal
         * aborted once): a stop on the path that fails too gives way to
         * one in joint space. */
        joint_stop(c, 1, KC_CTRL_FAULT);
        c->state = KC_CTRL_STOPPING;
        return;
    }
    c->fault_reason = why;
    emit(out, KC_EVENT_FAULT, c->active ? c->goal.id : 0, why, where);
    if (c->active)
        emit(out, KC_EVENT_ABORTED, c->goal.id, why, where);
    queue_clear(c, out);
    if (on_path && c->active && c->goal.kind != KC_GOAL_SERVO) {
        stop_on_path(c, KC_CMD_STOP);
        return;
    }
    joint_stop(c, 1, KC_CTRL_FAULT);
    c->state = KC_CTRL_STOPPING;
}

/* Checks a setpoint against the limits and the last one (see ctrl.h). */
static int setpoint_ok(const kc_ctrl *c, const kc_real *q, const kc_real *qd)
{
    kc_real slack = c->cfg.limit_slack;
    for (int j = 0; j < c->chain->n_joints; j++) {
        const kc_joint_limits *l = &c->chain->joints[j].limits;
        kc_real range_slack = slack * (kc_fabs(l->q_min) + kc_fabs(l->q_max) + KC_R(1.0));
        if (!kc_isfinite(q[j]) || !kc_isfinite(qd[j]))
            return 0;
        /* Outside, only no further out than the last setpoint: an arm a stop
         * carried past a limit may come to rest there and move back in. */
        if ((q[j] < l->q_min - range_slack && q[j] < c->q[j]) || (q[j] > l->q_max + range_slack && q[j] > c->q[j]))
            return 0;
        if (kc_fabs(qd[j]) > l->qd_max * (KC_R(1.0) + slack))
            return 0;
        if (kc_fabs(qd[j] - c->qd[j]) > l->qdd_max * c->cfg.dt * (KC_R(1.0) + slack) + slack * kc_fabs(c->qd[j]))
            return 0;
    }
    return 1;
}

/* Computes the next setpoint of the active segment into q, qd, qdd. Returns
 * 1 when the segment has finished (at rest, at its end). */
static int follow(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd, kc_ctrl_output *out)
{
    int n = c->chain->n_joints;
    int64_t j = c->cycle - c->k0;
    seg_point now;
    if (c->drive == KC_DRIVE_STOPPING_WAIT) {
        /* Try to start the pending path stop from the last setpoint. */
        int intent = c->stop_intent;
        c->drive = KC_DRIVE_NOMINAL;
        stop_on_path(c, intent);
        j = c->cycle - c->k0;
    }
    seg_eval(c, j, &now);
    out->progress = now.progress;
    if (!now.cart) {
        memcpy(q, now.q, sizeof(kc_real) * (size_t)n);
        memcpy(qd, now.qd, sizeof(kc_real) * (size_t)n);
        memcpy(qdd, now.qdd, sizeof(kc_real) * (size_t)n);
        return now.done;
    }
    /* Cartesian: the target where the segment is at the last setpoint's
     * instant, its twist fed forward; the step heads for tick j. */
    seg_point before;
    seg_eval(c, j - 1, &before);
    if (c->goal.kind == KC_GOAL_SERVO && c->goal.servo_twist) {
        /* Move the servo target by the twist over one tick. */
        kc_vec3 w = kc_vec3_make(c->goal.twist[3] * c->cfg.dt, c->goal.twist[4] * c->cfg.dt, c->goal.twist[5] * c->cfg.dt);
        kc_quat dr, r, r2;
        kc_quat_exp(&w, &dr);
        kc_quat_from_mat3(&c->servo_target.R, &r);
        kc_quat_mul(&dr, &r, &r2);
        kc_quat_to_mat3(&r2, &c->servo_target.R);
        for (int i = 0; i < 3; i++)
            c->servo_target.t.v[i] += c->goal.twist[i] * c->cfg.dt;
    }
    kc_ik_result res;
    kc_status st = kc_ik_step(c->chain, &c->cfg.ik, &before.pose, before.twist, c->cfg.dt, c->q, c->qd, q, qd, &res);
    for (int i = 0; i < n; i++)
        qdd[i] = (qd[i] - c->qd[i]) / c->cfg.dt;
    /* A servo target may jump: the arm goes there within its limits, and
     * only a joint limit in the way is a fault. */
    kc_real limit = c->goal.kind == KC_GOAL_SERVO    ? INF
                    : c->state == KC_CTRL_STOPPING ? TRACK_GIVE_UP * c->cfg.track_tol
                                                   : c->cfg.track_tol;
    if (st == KC_E_ARG || res.pos_err > limit || st == KC_E_LIMIT) {
        kc_real where = c->path_length > KC_R(0.0) ? before.s : before.progress;
        if (c->state == KC_CTRL_STOPPING || st == KC_E_LIMIT || st == KC_E_ARG) {
            /* Even the stop on the path cannot be followed: stop in joint
             * space from the last setpoint. */
            int was_fault = c->fault_reason != KC_REASON_NONE;
            if (!was_fault) {
                c->fault_reason = KC_REASON_TRACKING;
                emit(out, KC_EVENT_FAULT, c->goal.id, KC_REASON_TRACKING, where);
                emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_TRACKING, where);
                queue_clear(c, out);
            }
            joint_stop(c, 1, KC_CTRL_FAULT);
            c->state = KC_CTRL_STOPPING;
            return -1;
        }
        fault(c, KC_REASON_TRACKING, where, 1, out);
        return -1;
    }
    if (now.done && c->goal.kind != KC_GOAL_SERVO) {
        /* The geometry has ended: finished once the tool has settled. */
        if (st == KC_DONE)
            return 1;
        if (++c->settle > SETTLE_TICKS) {
            fault(c, KC_REASON_TRACKING, c->path_length, 0, out);
            return -1;
        }
    }
    return 0;
}

kc_status kc_ctrl_step(kc_ctrl *c, const kc_ctrl_input *in, kc_ctrl_output *out)
{
    if (c == NULL || in == NULL || out == NULL || c->chain == NULL)
        return KC_E_ARG;
    int n = c->chain->n_joints;
    kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS], qdd[KC_MAX_JOINTS];
    out->n_events = 0;
    c->cycle++;

    command(c, in->command, out);
    /* An external fault: the hardware may not follow a path stop, so stop
     * in joint space, as fast as the limits allow. */
    if (in->fault != KC_REASON_NONE && c->fault_reason == KC_REASON_NONE && c->state != KC_CTRL_FAULT &&
        c->state != KC_CTRL_ESTOP)
        fault(c, in->fault, KC_R(0.0), 0, out);
    if (in->goal != NULL)
        take_goal(c, in->goal, out);
    if (c->active && c->goal.kind == KC_GOAL_SERVO && c->state == KC_CTRL_MOVING &&
        (in->servo_stale || c->cycle - c->servo_last > c->cfg.servo_timeout_ticks))
        stop_on_path(c, KC_CMD_NONE);
    if (!c->active && !joint_stopping(c) && c->state != KC_CTRL_FAULT && c->state != KC_CTRL_ESTOP) {
        if (!start_next(c, out) && c->state != KC_CTRL_PAUSED)
            c->state = KC_CTRL_IDLE;
    }

    /* The setpoint. */
    int finished = 0;
    out->progress = KC_R(0.0);
    if (joint_stopping(c) || (c->active && c->goal.kind == KC_GOAL_SERVO && c->state == KC_CTRL_STOPPING)) {
        int done = 1;
        for (int j = 0; j < n; j++) {
            kc_profile_state s;
            if (kc_profile_eval(&c->jstop_prof[j], c->cycle - c->jstop_k0, &s) != KC_DONE)
                done = 0;
            q[j] = s.p;
            qd[j] = s.v;
            qdd[j] = s.a;
        }
        if (done) {
            c->jstop = 0;
            if (c->active && c->goal.kind == KC_GOAL_SERVO) {
                stop_finished(c, out);
            } else {
                c->state = c->after_stop;
            }
        }
    } else if (c->active && c->state != KC_CTRL_PAUSED) {
        finished = follow(c, q, qd, qdd, out);
        if (finished < 0) {
            /* a fault started a stop: its first tick */
            if (joint_stopping(c)) {
                for (int j = 0; j < n; j++) {
                    kc_profile_state s;
                    kc_profile_eval(&c->jstop_prof[j], c->cycle - c->jstop_k0, &s);
                    q[j] = s.p;
                    qd[j] = s.v;
                    qdd[j] = s.a;
                }
            } else {
                follow(c, q, qd, qdd, out);
            }
            finished = 0;
        }
    } else {
        /* Holding still (idle, paused, fault, e-stop at rest). */
        for (int j = 0; j < n; j++) {
            q[j] = c->q[j];
            qd[j] = KC_R(0.0);
            qdd[j] = KC_R(0.0);
        }
    }

    if (zones_on(c) && c->active && c->goal.kind == KC_GOAL_SERVO && c->state == KC_CTRL_MOVING && !joint_stopping(c))
        zone_servo_limit(c, q, qd, qdd);

    if (!setpoint_ok(c, q, qd)) {
        /* Never send it: hold the last good position, stop in joint space. */
        if (c->fault_reason == KC_REASON_NONE) {
            emit(out, KC_EVENT_FAULT, c->active ? c->goal.id : 0, KC_REASON_LIMIT_GUARD, 0);
            if (c->active)
                emit(out, KC_EVENT_ABORTED, c->goal.id, KC_REASON_LIMIT_GUARD, 0);
            c->fault_reason = KC_REASON_LIMIT_GUARD;
            queue_clear(c, out);
        }
        c->active = 0;
        finished = 0; /* a segment whose last setpoint is refused has not ended: it was aborted */
        for (int j = 0; j < n; j++) {
            q[j] = c->q[j];
            qd[j] = c->qd[j];
        }
        /* Continue at the last velocity for this tick is not allowed either:
         * a joint-space stop from the last good state, its first tick. */
        joint_stop(c, 1, KC_CTRL_FAULT);
        c->state = KC_CTRL_STOPPING;
        for (int j = 0; j < n; j++) {
            kc_profile_state s;
            kc_profile_eval(&c->jstop_prof[j], c->cycle - c->jstop_k0, &s);
            q[j] = s.p;
            qd[j] = s.v;
            qdd[j] = s.a;
        }
    }

    if (zones_on(c)) {
        zone_guard(c, q, qd, qdd, out);
        if (c->fault_reason == KC_REASON_ZONE)
            finished = 0;
    }

    memcpy(c->q, q, sizeof(kc_real) * (size_t)n);
    memcpy(c->qd, qd, sizeof(kc_real) * (size_t)n);
    memcpy(c->qdd, qdd, sizeof(kc_real) * (size_t)n);

    if (finished == 1) {
        if (c->state == KC_CTRL_STOPPING) {
            stop_finished(c, out); /* a stop on the path has come to rest */
        } else {
            emit(out, KC_EVENT_COMPLETED, c->goal.id, KC_REASON_NONE, 0);
            c->active = 0;
            c->state = c->queue_len > 0 ? KC_CTRL_MOVING : KC_CTRL_IDLE;
        }
    }

    out->cycle = c->cycle;
    out->goal_id = c->active ? c->goal.id : 0;
    out->state = c->state;
    memcpy(out->q, c->q, sizeof(kc_real) * (size_t)n);
    memcpy(out->qd, c->qd, sizeof(kc_real) * (size_t)n);
    memcpy(out->qdd, c->qdd, sizeof(kc_real) * (size_t)n);
    kc_fk_eval(c->chain, c->q, &out->pose);
    out->queue_length = c->queue_len;
    return KC_OK;
}

/* ---- dry run ---- */

kc_status kc_ctrl_check(kc_ctrl *scratch, const kc_chain *chain, const kc_ctrl_cfg *cfg, const kc_goal *goal,
                        const kc_real *q_start, int64_t max_ticks, kc_real *q_end, kc_ctrl_reason *reason,
                        kc_real *where)
{
    kc_ctrl_reason why = KC_REASON_NONE;
    if (where != NULL)
        *where = KC_R(0.0);
    if (scratch == NULL || goal == NULL || q_end == NULL || max_ticks < 1 || chain == NULL || q_start == NULL ||
        chain->n_joints < 1 || chain->n_joints > KC_MAX_JOINTS)
        return refuse(reason, KC_REASON_BAD_GOAL);
    /* A start outside the position limits (an arm a stop carried past one)
     * is judged from where it is: the scratch controller starts inside and
     * is then put there. */
    kc_real inside[KC_MAX_JOINTS];
    for (int j = 0; j < chain->n_joints; j++) {
        if (!kc_isfinite(q_start[j]))
            return refuse(reason, KC_REASON_BAD_GOAL);
        inside[j] = kc_clamp(q_start[j], chain->joints[j].limits.q_min, chain->joints[j].limits.q_max);
    }
    if (kc_ctrl_init(scratch, chain, cfg, inside) != KC_OK)
        return refuse(reason, KC_REASON_BAD_GOAL);
    memcpy(scratch->q, q_start, sizeof(kc_real) * (size_t)chain->n_joints);
    if (kc_ctrl_goal_check(chain, goal, &why) != KC_OK)
        return refuse(reason, why);
    if (goal->kind == KC_GOAL_SERVO) {
        /* A servo target is judged tick by tick as it moves. */
        memcpy(q_end, q_start, sizeof(kc_real) * (size_t)chain->n_joints);
        if (reason != NULL)
            *reason = KC_REASON_NONE;
        return KC_OK;
    }
    if (goal->kind == KC_GOAL_JOINT && !zones_on(scratch)) {
        /* A joint move is exactly its plan: the plan is the whole check
         * (with zones, its ticks are stepped like any other goal's). */
        kc_real vmax[KC_MAX_JOINTS], amax[KC_MAX_JOINTS];
        scaled_limits(scratch, goal, vmax, amax);
        if (kc_interp_joint_plan(&scratch->plan.joint, chain->n_joints, q_start, goal->q, vmax, amax, KC_R(0.0),
                                 cfg->dt) != KC_OK)
            return refuse(reason, KC_REASON_PLAN);
        memcpy(q_end, goal->q, sizeof(kc_real) * (size_t)chain->n_joints);
        if (reason != NULL)
            *reason = KC_REASON_NONE;
        return KC_OK;
    }
    kc_goal g = *goal;
    g.replace = 0;
    kc_ctrl_input in = {&g, KC_CMD_NONE, 0, KC_REASON_NONE};
    kc_ctrl_output out;
    for (int64_t k = 0; k < max_ticks; k++) {
        if (kc_ctrl_step(scratch, &in, &out) != KC_OK)
            return refuse(reason, KC_REASON_BAD_GOAL); /* not reached: scratch was initialised above */
        in.goal = NULL;
        for (int e = 0; e < out.n_events; e++) {
            const kc_ctrl_event *ev = &out.events[e];
            if (ev->kind == KC_EVENT_COMPLETED) {
                memcpy(q_end, scratch->q, sizeof(kc_real) * (size_t)chain->n_joints);
                if (reason != NULL)
                    *reason = KC_REASON_NONE;
                return KC_OK;
            }
            if (ev->kind == KC_EVENT_REJECTED || ev->kind == KC_EVENT_ABORTED || ev->kind == KC_EVENT_FAULT) {
                if (reason != NULL)
                    *reason = ev->reason == KC_REASON_TRACKING ? KC_REASON_UNREACHABLE : ev->reason;
                if (where != NULL)
                    *where = ev->where;
                return ev->reason == KC_REASON_PLAN || ev->kind == KC_EVENT_REJECTED ? KC_E_ARG : KC_E_UNREACHABLE;
            }
        }
    }
    if (reason != NULL)
        *reason = KC_REASON_PLAN;
    return KC_E_CAPACITY;
}
