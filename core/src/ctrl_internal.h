/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl_internal.h - what the rooms of the controller share (kinctl/ctrl.h
 * is the behaviour): ctrl.c (configuration, init, commands, the step),
 * ctrl_goal.c (goal checks and verdicts), ctrl_zone.c (forbidden zones), ctrl_queue.c
 * (events, the queue, goals taken), ctrl_seg.c (segments: planning and
 * evaluation), ctrl_stop.c (stops on the path, resume, faults),
 * ctrl_blend.c (a replacing Cartesian goal superposed on the replaced
 * motion's stop) and check.c (the dry run, kinctl/check.h). Private to the core. */
#ifndef KINCTL_CTRL_INTERNAL_H
#define KINCTL_CTRL_INTERNAL_H

#include "kinctl/ctrl.h"

#define INF ((kc_real)INFINITY)

/* Samples over a path stop when checking that a deceleration rate keeps
 * every joint within its acceleration limit. */
#define STOP_SAMPLES 16

/* Time (s) a Cartesian segment may take after its geometry ends for the
 * tool to settle within the IK tolerances and the joints to come to rest:
 * seconds, not ticks, so that a dry run at a coarser period judges the
 * same wait as the controller. */
#define SETTLE_S KC_R(1.0)

/* Time (s) over which a redundant arm's null-space motion (the IK step's
 * null_gain) is set going when a Cartesian motion starts from one without
 * it (rest, a joint move) and brought to rest once the geometry has
 * ended: the gain rises as 3x^2 - 2x^3 of the time x, and falls so, so the
 * joints' velocity in the null space changes smoothly (no step of qdd).
 * Started at once, it stepped a Panda's qdd by up to qdd_max in the first
 * tick of a line from rest (twice qddd_max dt). Without the fall, that
 * motion, decaying at null_gain (0.5/s), kept joints moving above the IK
 * step's rest bound, which at a 1 ms period is jerk-limited and tight, for
 * longer than SETTLE_S. */
#define SETTLE_NULL_S KC_R(0.25)

/* A tracking error this many times cfg.track_tol during a stop on the path
 * abandons the path for a stop in joint space. */
#define TRACK_GIVE_UP 4

/* How far (m) a stream's target may run ahead of an arm a zone holds back
 * on a step whose approach is within the distances' rounding
 * (ctrl_zone.c). */
#define ZONE_LEAD KC_R(1e-3)

/* Whether a joint's qdd going from qdd0 to qdd1 over a tick keeps within
 * jb (qddd_max dt, or more where one motion of a sum does more alone):
 * the joints' jerk limits themselves, up to the rounding of the
 * difference (a few units in the last place of the qdd it is taken
 * from), not within cfg.limit_slack of them (1e-6 in double: a joint
 * path's sum reached 1.0000005 of qddd_max through kinctld). */
static inline int kc_ctrl_jerk_within(kc_real qdd0, kc_real qdd1, kc_real jb)
{
    return kc_fabs(qdd1 - qdd0) <= jb + KC_R(8.0) * KC_REAL_EPS * (kc_fabs(qdd0) + kc_fabs(qdd1));
}

/* A jerk-limited joint move's plan was synchronised by phase: a straight
 * line in joint space driven by one profile of u. */
static inline int kc_ctrl_joint_on_line(const kc_ctrl *c)
{
    return c->plan.joint.kind == KC_PROFILE_JERK && c->plan.joint.sync == KC_INTERP_SYNC_PHASE;
}

/* Preemption marker for stop_intent. */
#define INTENT_PREEMPT 100
/* stop_intent of a servo stream ended because the tool fell behind its
 * shaped target (ABORTED with KC_REASON_TRACKING). */
#define INTENT_LAG 101

/* What the segment asks for at one tick: joints, or a Cartesian pose with
 * its twist. */
typedef struct kc_ctrl_seg_point {
    int cart;
    kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS], qdd[KC_MAX_JOINTS];
    kc_pose pose;
    kc_real twist[6];
    kc_real progress; /* 0..1 */
    kc_real s;        /* path length so far (m), Cartesian segments */
    int done;         /* the segment's own timing has ended (at rest) */
} kc_ctrl_seg_point;

static inline int kc_ctrl_zones_on(const kc_ctrl *c)
{
    return c->cfg.zones != NULL && c->cfg.zones->n_zones > 0 && c->chain->n_volumes > 0;
}

static inline int kc_ctrl_is_path(kc_goal_kind k) { return k == KC_GOAL_PATH || k == KC_GOAL_PATH_CART; }

/* The goal kinds the IK step follows (a line, an arc, a Cartesian path, a
 * servo stream): not the joint move's and joint path's. */
static inline int kc_ctrl_is_cart(kc_goal_kind k) { return k != KC_GOAL_JOINT && k != KC_GOAL_PATH; }

/* A stop in joint space is under way. */
static inline int kc_ctrl_joint_stopping(const kc_ctrl *c) { return c->jstop; }

/* The active servo goal, a Cartesian goal whose stop left its path
 * (kc_ctrl_stop_leave_path), or a goal whose replacement could not be
 * planned after its stop joint by joint had taken the place of its plan
 * (ctrl_blend.c) is stopping jerk-limited, joint by joint (plan.halt from
 * tick jstop_k0), not by jstop_prof; a joint move's stop joint by joint
 * is its own drive (kc_ctrl_seg_eval). */
static inline int kc_ctrl_halting(const kc_ctrl *c)
{
    return !c->jstop && c->active && c->state == KC_CTRL_STOPPING && c->goal.kind != KC_GOAL_JOINT &&
           c->drive == KC_DRIVE_HALT;
}

/* ---- ctrl.c ---- */

/* Puts an initialised controller back at rest at q_at, idle, nothing
 * queued or active, as kc_ctrl_init leaves it (the zone state judged at
 * q_at), then its joints at q: the plan buffers are not cleared (each is
 * written before it is read) and nothing is validated again. */
void kc_ctrl_restart(kc_ctrl *c, const kc_real *q_at, const kc_real *q);

/* ---- ctrl_goal.c: goal checks ---- */

/* *dst = *src for everything that is read: a path's first n_points knots
 * and times, no other kind's (the knot rows are most of a goal: 2 KB of
 * its 2.3 KB with the default capacities, copied twice on the way from the
 * caller to the active segment). */
void kc_ctrl_goal_copy(kc_goal *dst, const kc_goal *src);

/* Fills *v (if not NULL): refused (KC_E_ARG) for why, naming the field,
 * knot, joint and number at fault; returns KC_E_ARG. */
kc_status kc_ctrl_refuse(kc_verdict *v, kc_ctrl_reason why, kc_goal_field field, int point, int joint,
                         kc_real value);

/* kc_ctrl_refuse for a field that is not finite or out of its domain,
 * naming none (KC_REASON_BAD_GOAL). */
kc_status kc_ctrl_bad_goal(kc_verdict *v);

/* ---- ctrl_zone.c: forbidden zones ---- */

/* The zone state of a controller at rest at c->q: no hit yet, the levers,
 * the servo's braking law. */
void kc_ctrl_zone_init(kc_ctrl *c);

/* A servo step toward a zone approaches it by at most dt sqrt(2 a e) and
 * moves no volume point (by the lever bound) more than e / 2, e the
 * clearance beyond the margin at the last setpoint: the arm brakes into the
 * margin and never reaches it. The step is scaled as a whole (the tool
 * keeps its direction), its velocity change kept within the acceleration
 * limits. */
void kc_ctrl_zone_servo_limit(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd);

/* The final check against the zones: a setpoint that comes closer than
 * the margin (and closer than the last one) is replaced by the first tick
 * of an e-stop-like stop from the last good setpoint, and the controller
 * faults naming the pair. */
void kc_ctrl_zone_guard(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd, kc_ctrl_output *out);

/* ---- ctrl_queue.c: events, the queue, goals taken ---- */

/* Appends an event to the tick's output (zone and volume -1). */
void kc_ctrl_emit(kc_ctrl_output *out, kc_ctrl_event_kind kind, int64_t id, kc_ctrl_reason reason, kc_real where);

/* A replacing goal taken over at once (a retarget, a superposition): its
 * ACCEPTED, the replaced goal's PREEMPTED, its STARTED. */
void kc_ctrl_emit_takeover(kc_ctrl_output *out, int64_t id, int64_t old_id);

/* Drops every queued goal, each with PREEMPTED. */
void kc_ctrl_queue_clear(kc_ctrl *c, kc_ctrl_output *out);

/* A new goal or servo message of this tick: updates the active or queued
 * servo goal of its id, or is refused, queued or preempts (kinctl/ctrl.h). */
void kc_ctrl_take_goal(kc_ctrl *c, const kc_goal *g, kc_ctrl_output *out);

/* ---- ctrl_seg.c: segments: planning and evaluation ---- */

/* The joints' velocity and acceleration limits times the goal's scales. */
void kc_ctrl_scaled_limits(const kc_ctrl *c, const kc_goal *g, kc_real *vmax, kc_real *amax);

/* The Cartesian limits of a goal: its own, or cfg's defaults. */
kc_interp_limits kc_ctrl_cart_limits(const kc_ctrl_cfg *cfg, const kc_goal *g);

/* The motion law of joint move g: its own, or cfg.profile; the trapezoid
 * for a chain with a joint without a jerk limit. */
kc_profile_kind kc_ctrl_goal_profile(const kc_ctrl *c, const kc_goal *g);

/* Plans joint move g (its motion law, the joints' limits with its scales)
 * from q0 with velocity qd0 and acceleration qdd0 (NULL: at rest; a
 * trapezoid always starts at rest) into *out, which is scratch on error
 * (kc_interp_joint_plan_cfg_into: no plan on the stack). */
kc_status kc_ctrl_plan_joint(const kc_ctrl *c, const kc_goal *g, const kc_real *q0, const kc_real *qd0,
                             const kc_real *qdd0, kc_interp_joint *out);

/* Plans the goal in c->goal from the current state (at rest, but for a
 * jerk-limited joint move, which starts from the last setpoint's q, qd
 * and qdd). */
kc_status kc_ctrl_plan_goal(kc_ctrl *c);

/* Plans Cartesian goal g (line, arc, Cartesian path) into c->plan as if at
 * rest at the tool pose *from, setting c->path_length; c->goal is not
 * read. On error c->plan is scratch. */
kc_status kc_ctrl_plan_cart_from(kc_ctrl *c, const kc_goal *g, const kc_pose *from);

/* Plans joint path g into c->plan.path as if at rest at joints q0;
 * c->goal is not read. On error c->plan is scratch. */
kc_status kc_ctrl_plan_path_from(kc_ctrl *c, const kc_goal *g, const kc_real *q0);

/* A line or an arc (kind) at tick j of its drive: its own law
 * (KC_DRIVE_NOMINAL), the profile prof (KC_DRIVE_PROFILE) or the
 * jerk-limited profile sc (KC_DRIVE_SCURVE) of its u. */
void kc_ctrl_interp_point(kc_goal_kind kind, const kc_interp_line *line, const kc_interp_arc *arc,
                          kc_ctrl_drive drive, const kc_profile *prof, const kc_scurve *sc, int64_t j,
                          kc_ctrl_seg_point *o);

/* The active segment's point at its tick j (j < 0: its tick 0). */
void kc_ctrl_seg_eval(const kc_ctrl *c, int64_t j, kc_ctrl_seg_point *o);

/* Starts the next queued goal, if any; returns 1 when a segment is active. */
int kc_ctrl_start_next(kc_ctrl *c, kc_ctrl_output *out);

/* The u (or tau) state driving the segment at its tick j. */
void kc_ctrl_drive_state(const kc_ctrl *c, int64_t j, kc_profile_state *u);

/* Computes the next setpoint of the active segment into q, qd, qdd. Returns
 * 1 when the segment has finished (at rest, at its end). */
int kc_ctrl_follow(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd, kc_ctrl_output *out);

/* ---- ctrl_servo.c: a servo stream's shaped target ---- */

/* w: the rotation vector of to from^T (from's rotation onto to's, in the
 * base frame), the short way round. */
void kc_ctrl_turn(const kc_mat3 *from, const kc_mat3 *to, kc_vec3 *w);

/* The active goal is a pose stream whose pose is shaped (jerk-limited). */
int kc_ctrl_servo_shaped(const kc_ctrl *c);

/* A servo stream's target set at rest where it starts or RESUMEs: a twist
 * stream's and a shaped pose stream's where the arm is (the last
 * setpoint, of tick last), an unshaped pose stream's the commanded pose;
 * the shaped twist and its rate zero; a shaped pose planned from there. */
void kc_ctrl_servo_rest(kc_ctrl *c, int64_t last);

/* A shaped pose stream's plan from its target, twist and rate as they
 * are (servo_target, servo_v, servo_a: the state at tick k0) to rest at
 * the commanded pose (goal.pose). */
void kc_ctrl_servo_aim(kc_ctrl *c, int64_t k0);

/* A following servo stream's tick: the shaped target, twist and rate
 * moved on to this tick (a pose stream without shaping has none). */
void kc_ctrl_servo_tick(kc_ctrl *c);

/* A jerk-limited stream's joint setpoint (q, qd, qdd: the IK step's)
 * brought within the joints' jerk limits, following the IK step's
 * velocities from tick to tick (kinctl/ctrl.h; ctrl_servo.c says how). */
void kc_ctrl_servo_jerk(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd);

/* A replacing servo goal g taking over the moving arm in this tick
 * (kinctl/ctrl.h): its shaped target starts from the tool's pose, twist
 * and the twist's rate at the last setpoint. Returns 1 when taken (the
 * takeover's events emitted), 0 when it stops first. */
int kc_ctrl_servo_take(kc_ctrl *c, const kc_goal *g, kc_ctrl_output *out);

/* ---- ctrl_blend.c: a replacing Cartesian goal superposed on the stop of
 * the motion it replaces (kinctl/ctrl.h) ---- */

/* Replacing goal g (line, arc or Cartesian path; a joint path from a joint
 * move or servo stream) takes over from the active line, arc, joint move
 * or servo stream, moving: the old segment stops (on its path, or in
 * joint space) (kept in
 * c->blend), g is planned from where that stop ends and starts at the
 * earliest tick its sum with the stop keeps the Cartesian limits. Returns
 * 1 when taken (ACCEPTED, PREEMPTED, STARTED emitted); 0 with the active
 * segment unchanged when there is no such transition (the caller stops
 * first). */
int kc_ctrl_blend_take(kc_ctrl *c, const kc_goal *g, kc_ctrl_output *out);

/* The segment's point o at absolute tick k, composed with the replaced
 * segment's stop at k while that stop lasts; the transition ends with it.
 * Returns 1 when that stop is in joint space and qd_m (non-NULL, the
 * chain's joints) then holds its joint velocities fed forward with o's
 * twist (the IK step's null-space feed-forward, kc_ik_step_ff); else 0. */
int kc_ctrl_blend_apply(kc_ctrl *c, int64_t k, kc_ctrl_seg_point *o, kc_real *qd_m);

/* What kc_ctrl_blend_apply does for a Cartesian segment at tick k, c
 * unchanged (the superposition not ended where that stop has: o is the
 * segment's alone from there). */
int kc_ctrl_blend_point(const kc_ctrl *c, int64_t k, kc_ctrl_seg_point *o, kc_real *qd_m);

/* A joint path's point o at absolute tick k with the replaced motion's
 * stop in joint space added while the superposition lasts (what
 * kc_ctrl_blend_apply does for a joint path, c unchanged). */
void kc_ctrl_blend_joints(const kc_ctrl *c, int64_t k, kc_ctrl_seg_point *o);

/* ---- ctrl_stop.c: stops, resume, faults ---- */

/* The plan time the active path's plan lasts. */
kc_real kc_ctrl_path_duration(const kc_ctrl *c);

/* The rate C of a tau' ramp from rest at tau0 up to 1 that, with the same
 * ramp down into the path's end, keeps every limit (a path the controller
 * ramps, kc_ctrl_path_ramped, and every resume); 0 when none of the rates
 * tried does. */
kc_real kc_ctrl_path_ramp_rate(const kc_ctrl *c, kc_real tau0);

/* The bound on tau''' of a jerk-limited change of a path's rate over plan
 * times [tau0, tau1] with |tau''| <= A (kinctl/ctrl.h): a joint path's
 * every joint's room for the jerk the law adds (qddd_max less the path's
 * own |q'''|, at least half of qddd_max) less 3 |q''| A (the jerk of
 * 3 q'' tau' tau''), but at least half its room, over |q'| on sampled
 * instants; a Cartesian path's the goal's jerk over the tool point's
 * speed, its angular jerk over the tool's angular speed. So the jerk the
 * change adds stays within the limit. Infinite for the trapezoid
 * (cfg.profile or the goal's, or a chain without jerk limits) and for a
 * path that stands still there. */
kc_real kc_ctrl_path_tau_jerk(const kc_ctrl *c, kc_real tau0, kc_real tau1, kc_real A);

/* The bound on tau''' of the ramps from rest at tau0 to tau' = 1 and into
 * the path's end at rate C (kc_ctrl_path_ramp_rate): kc_ctrl_path_tau_jerk
 * over the stretches of plan time the ramps cover, or over all of it from
 * tau0 where they meet. */
kc_real kc_ctrl_path_ramp_jerk(const kc_ctrl *c, kc_real tau0, kc_real C);

/* Whether the controller runs the path goal g on its own ramps of tau'
 * from rest and into the end: one that moves at its ends (Lagrange's, a
 * natural spline), and under a jerk-limited law one whose acceleration
 * steps at its ends (a clamped cubic spline, a parabolic blend). */
int kc_ctrl_path_ramped(const kc_ctrl *c, const kc_goal *g);

/* Whether the path goal g runs under a jerk-limited law: a joint path's
 * profile is KC_PROFILE_JERK, a Cartesian path has a finite jerk limit
 * (kc_ctrl_path_tau_jerk bounds tau''' then). */
int kc_ctrl_path_jerk_law(const kc_ctrl *c, const kc_goal *g);

/* The ramps of the active path (kc_ctrl_path_ramped) from rest at its
 * start and into its end, planned from tau = 0 at the rate
 * kc_ctrl_path_ramp_rate gives: jerk-limited, its own timing (ramp,
 * ramp_on); else at that constant rate (drive KC_DRIVE_PROFILE). Where no
 * rate keeps the limits: KC_E_LIMIT, or with gentlest the gentlest ramp
 * there is (C = 1, as a resume takes). */
kc_status kc_ctrl_path_plan_ramp(kc_ctrl *c, int gentlest);

/* A stop of every joint in joint space: each at its own acceleration limit
 * (hard, for e-stop) or all synchronised on the current direction of motion
 * (sync). Ends in state `then`. */
void kc_ctrl_joint_stop(kc_ctrl *c, int sync, kc_ctrl_state then);

/* The joint-space stop at this tick (c->cycle) into q, qd, qdd; 1 when
 * every joint has come to rest. */
int kc_ctrl_joint_stop_eval(const kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd);

/* Every joint's jerk-limited stop from the last setpoint's (q, qd, qdd)
 * into halt[0..n_joints), synchronised by phase where it can be, within
 * the Cartesian bounds cart too where not NULL; 0 (halt partly written)
 * where a joint has no jerk limit or would pass its qd_max. */
int kc_ctrl_halt_plan(const kc_ctrl *c, kc_scurve *halt, const kc_interp_limits *cart);

/* Starts (or, for a path braking hard, arms) the stop on the path of the
 * active segment, for the given intent. */
void kc_ctrl_stop_on_path(kc_ctrl *c, int intent);

/* Resumes a paused segment from where it rests: the setpoint of tick
 * last (the last one kept, or this tick's as its stop comes to rest),
 * the resumed motion's tick 0. */
void kc_ctrl_resume(kc_ctrl *c, int64_t last, kc_ctrl_output *out);

/* While a Cartesian goal stops jerk-limited, the joints' rates per unit of
 * its parameter at its tick j (the last setpoint's instant; qd the new
 * setpoint's), taken into stop_qu while u' is at least STOP_TRACK_LEAST of
 * the speed the stop started from: its resume starts where it rests. */
void kc_ctrl_stop_track(kc_ctrl *c, int64_t j, const kc_real *qd);

/* A line's, arc's or Cartesian path's joints' largest rate per unit of
 * its parameter's rate, |qd_i / u'| / qddd_max_i at the last setpoint,
 * while it runs on its own law at a tenth of u's top rate or more; else
 * 0 (the dry run's kc_verdict.qu). */
kc_real kc_ctrl_rate_per_u(const kc_ctrl *c);

/* A Cartesian goal's jerk-limited stop on its path whose IK step asks
 * qdd, the tick's setpoint, to change beyond a joint's qddd_max dt (and
 * cfg.limit_slack): the joints cannot follow the path's stop within their
 * limits there (near a wrist singularity the stop's own braking, at
 * bounds estimated where it started, carried PUMA 560 joints to their
 * acceleration limit, the tool lagged, and catching up stepped their
 * jerk 98 times beyond the limit). The stop leaves the path: joint by
 * joint, jerk-limited, from the last setpoint (as a servo stream's stop),
 * that tick's setpoint from it. A PAUSE's stop then ends the goal as a
 * STOP does, aborted at rest (a resume would start off the path, and the
 * IK step's first tick would step qdd to close the gap). 1 when it left
 * (kc_ctrl_halting from then on). Not in float, whose IK rounding alone
 * steps the joints' jerk beyond the limits (kinctl/ctrl.h): the test
 * would leave every path. */
#ifdef KC_REAL_FLOAT
static inline int kc_ctrl_stop_leave_path(kc_ctrl *c, const kc_real *qdd)
{
    (void)c, (void)qdd;
    return 0;
}
#else
int kc_ctrl_stop_leave_path(kc_ctrl *c, const kc_real *qdd);
#endif

/* Ends the active segment after its stop came to rest, that tick's
 * setpoint kept (kc_ctrl_step): paused, resumed (from that setpoint),
 * preempted, aborted or faulted, as the stop was for. */
void kc_ctrl_stop_finished(kc_ctrl *c, kc_ctrl_output *out);

/* Puts the controller into a fault: the event, then a stop (on the path
 * when the segment allows it, else in joint space). */
void kc_ctrl_fault(kc_ctrl *c, kc_ctrl_reason why, kc_real where, int on_path, kc_ctrl_output *out);

#endif /* KINCTL_CTRL_INTERNAL_H */
