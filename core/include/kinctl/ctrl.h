/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/ctrl.h - the controller step: goals in, one joint setpoint out per
 * tick. Pure and deterministic: no I/O, no clock, no allocation; the daemon
 * is thin I/O around kc_ctrl_step, and a unit test can run thousands of
 * cycles of it.
 *
 * Motion. A goal becomes a segment when it starts, planned from where the
 * arm is then (at rest: every segment ends at rest):
 *   joint move      kc_interp_joint: jerk-limited by default
 *                   (kc_interp_joint_plan_cfg, kinctl/scurve.h: every joint
 *                   within its qd_max, qdd_max and qddd_max, all joints
 *                   starting on the same tick and arriving on the same
 *                   tick, in the time of the slowest joint's own optimum),
 *                   or seed 001 lab 4's trapezoid, exactly as
 *                   kc_interp_joint_plan plans it, when cfg.profile or the
 *                   goal's profile says so; velocity and acceleration
 *                   limits times vel_scale and acc_scale (the jerk limit
 *                   is the joint's own);
 *   line, arc       kc_interp_line / kc_interp_arc (labs 5, 6) from the tool
 *                   pose of the current joints: jerk-limited by default
 *                   (the goal's jerk and angular_jerk, or cfg.cart_jerk and
 *                   cfg.cart_angular_jerk), or the seed's trapezoid (jerk
 *                   limits infinite) when cfg.profile or the goal's
 *                   profile says so;
 *   path            kc_path through the current joints and the goal's
 *                   points, or kc_path_cart through the current pose and the
 *                   goal's poses (lab 7);
 *   servo           a target pose (or a twist that moves it) followed by the
 *                   online IK law until the stream goes quiet. A twist
 *                   stream's twist is shaped: each of its six axes moves
 *                   towards the commanded twist within the goal's
 *                   Cartesian acceleration and jerk bounds over sqrt(3)
 *                   (the linear and angular vectors' norms within the
 *                   bounds: accel, alpha, jerk, angular_jerk or the cfg
 *                   defaults), by the deadbeat step of ctrl_servo.c (the
 *                   commanded twist reached exactly, its rate back at
 *                   0, in about the time-optimal ramp's ticks; a change
 *                   mid-ramp approached at the bounds), from rest where
 *                   the stream starts or RESUMEs, from the arm's own
 *                   twist where a zone restrains it. The commanded
 *                   linear and angular velocities are capped at the
 *                   goal's speed and omega (cfg defaults), their
 *                   directions kept. A pose stream's target is
 *                   shaped too: on each new pose, x, y, z and the
 *                   rotation vector phi of R = exp(phi) ref (ref the
 *                   shaped orientation then) are planned to rest at it,
 *                   one time-optimal kc_scurve each from the shaped
 *                   state, within the goal's speed, omega, accel, alpha,
 *                   jerk and angular_jerk over sqrt(3); the pose, twist
 *                   and the twist's rate go on continuously through
 *                   every message (w and dw through SO(3)'s left
 *                   Jacobian; dw and its rate exceed the angular bounds
 *                   by terms of second order in phi, measured at most
 *                   1.5 %). A pose repeated is no new plan. From rest
 *                   where the stream starts or RESUMEs, from the arm's
 *                   own motion where a zone restrains it. The arm so
 *                   lags a moving pose, and a pose stream that goes
 *                   quiet is stopped where its shaped pose is, short of
 *                   a pose not yet reached. The joints follow either
 *                   stream within their jerk limits too: the IK step's
 *                   joint velocities are taken as they are where qdd
 *                   changes by at most qddd_max dt, and followed by a
 *                   deadbeat jerk-limited step where they would change
 *                   it by more (kc_ctrl_servo_jerk, ctrl_servo.c; the
 *                   Jacobian alone took a PUMA 560 elbow to 1.0088 of
 *                   qddd_max, and in float the rounding of q moved qdd
 *                   by 16 times it; random streams of up to 0.1 m/s and
 *                   0.3 rad/s at the default bounds, test_ctrl_servoshape.c:
 *                   within the limits in double on every tick, at five
 *                   times its cases too, and in float within 1.0002 of
 *                   them). The tick after a zone restrained the step
 *                   (forbidden zones, below) is not limited; the next
 *                   ramps from qdd 0. A shaped stream the tool falls
 *                   behind by more than cfg.track_tol (a joint at its
 *                   speed or acceleration limit, a singularity) ends
 *                   there: stopped joint by joint, jerk-limited, as
 *                   when it goes quiet, and ABORTED with
 *                   KC_REASON_TRACKING (no fault). With
 *                   the trapezoid profile a pose stream is not shaped:
 *                   its target jumps to each pose, and the IK step
 *                   brings the joints there within qd_max and qdd_max
 *                   (their jerk not limited).
 * Cartesian segments give a pose and twist each tick; one IK step with
 * the twist fed forward (kc_ik_step_ff, with a superposed stop's joint
 * velocities in the null space, below) turns them into the joint
 * setpoint. The twist fed forward is the target's at the tick's start,
 * so each step leaves the tool about a dt^2 / 2 short of the target, a
 * being the tool's acceleration along its path: 0.5 um at 1 ms and 1
 * m/s^2, but at long periods more than track_tol, and the dry run then
 * refuses the goal (the periods where: daemon/README.md, period_us). If the tool
 * falls more than cfg.track_tol behind (a joint limit, a singularity) the
 * arm stops on the path and the controller faults, naming the segment and
 * the path length where it happened. Their limits are Cartesian: every
 * joint stays within qd_max and qdd_max (the IK step's scaling, the final
 * check), but its jerk is what the arm's Jacobian makes of the tool's
 * motion, not bounded by qddd_max (where the Jacobian amplifies, e.g. a
 * line near a singularity, it may exceed it; slower Cartesian limits
 * avoid that: the dry run measures it, and kc_goal_slow slows a goal by
 * the factor kc_check_slowing gives, kinctl/check.h). A redundant arm's
 * null-space motion (the IK step's null_gain) is set going smoothly, over
 * 0.25 s, when a Cartesian motion starts from rest or from a joint move,
 * and brought to rest so once the geometry has ended; the tool has 1 s in all
 * to settle before the segment faults (seconds, whatever the period). That
 * motion's jerk is not bounded by qddd_max by construction either: its
 * velocity, up to half the slowest joint's qd_max, follows the redundancy
 * objective (kinctl/ik.h; its joint-limit barrier is cubic, so that the
 * null-space velocity rises from rest at the margin) and is scaled with
 * the rest where a joint reaches its velocity or acceleration limit, and,
 * when the target stops, by the IK step's braking towards a still target.
 * The dry run measures it with the rest. The Panda's random lines and arcs
 * at the default limits, unslowed: 1 of 238 over qddd_max in a tick
 * (2.46 x; with the barrier's gradient linear in the depth, 13 of 243, up
 * to 4 x); judged at the controller's period and slowed as kinctld does,
 * none of 123 at default and fast limits (tests/unit/test_ctrl_null_jerk.c).
 *
 * Goal ids name one goal while it is in flight: a goal whose id is that of
 * the active goal or of a queued one is refused (KC_REASON_DUPLICATE_ID),
 * except a servo message for a servo goal of that id, which updates it.
 * An id may be used again once its goal has ended.
 *
 * Goals wait in a queue of KC_CTRL_QUEUE_MAX. A goal with replace set
 * preempts: the queue is dropped and the active goal ends (PREEMPTED).
 * A joint move takes over at once from the current state, so nothing waits
 * for the arm to come to rest. Jerk-limited (the default): every joint
 * follows a jerk-limited profile from its (q, qd, qdd) to rest at the
 * target (kc_interp_joint_plan_cfg from a moving start: each joint's
 * profile stretched to the slowest one's, so the joints arrive on the same
 * tick; a goal re-sent with the target of a move on its line stays on that
 * line and arrives when the move would have), and q, qd and qdd stay
 * continuous. A trapezoid goal: every joint
 * follows its own time-optimal trapezoid from (q, qd) (kc_profile_plan
 * from a moving start) and arrives when it ends; qdd jumps. Either is a
 * retarget, not a straight line in joint space. Where a joint's profile
 * would pass its position limit (or, jerk-limited, its velocity or
 * acceleration limit: a start beyond the goal's limits is brought back
 * within them, never beyond the joint's), the retarget is not taken and
 * the goal starts as any other replacing goal does. A joint goal replacing
 * a Cartesian motion retargets the same way, from the joints' (q, qd, qdd)
 * (qdd of a Cartesian motion: the change of qd over the last tick).
 *
 * A line, an arc or a Cartesian path replacing a moving line, arc,
 * Cartesian or joint path, jerk-limited joint move or servo stream takes
 * over in the tick it arrives by superposition (ctrl_blend.c). The old
 * segment M gets its stop (the law of STOP, below: a line or an arc on its
 * path, jerk-limited by default, a trapezoid's for a trapezoid line or
 * arc; a joint move in joint space, on its line or joint by joint; a
 * servo stream's jerk-limited halt joint by joint; a path's the same
 * halt, within a Cartesian path's Cartesian bounds as well, its plan
 * giving way to G's (a path's plan is as large as the controller's room
 * for one: it cannot be kept beside G's); a stop in joint space has tool pose
 * FK(q_M) and twist J(q_M) qd_M, the geometric Jacobian's, q_M the stop
 * as the IK step integrates it: its velocity at the next tick fed forward
 * from q_M, q_M(j) = q_M(0) + dt (qd_M(1) + ... + qd_M(j)) in closed
 * form, so that the setpoints carry on with the stop's own velocities and
 * accelerations from the takeover's tick, within its joints' jerk
 * limits, and M rests up to dt |qd| / 2 from where STOP would), which
 * would bring the tool to rest at pose P_s = (R_s, p_s) T_s ticks after
 * the takeover; the new goal G is planned from P_s as if at rest there,
 * and starts t0 ticks after the takeover. The Cartesian target is
 *     p = p_M + (p_G - p_s),   R = A R_M,   A = R_G R_s^T (base frame),
 *     v = v_M + v_G,           w = w_G + A w_M,
 * so it is M's motion until G starts (G at rest at P_s) and G's alone from
 * the tick M's stop ends (M at rest at P_s): continuous in pose and twist,
 * and in acceleration as far as M's stop and G's start are (G starts from
 * rest with no acceleration). t0 is the earliest of a bounded search over
 * [0, T_s] (an even grid of 8, then bisection, judged on every 8th tick of
 * the overlap; the t0 found is checked on every tick, and where that fails
 * a bisection on every tick runs up to 8 ticks later, then to the next
 * point of the grid: a takeover tick evaluates both segments a few T_s
 * times, about 0.35 ms for T_s = 500 ticks in double on a PC, at most
 * some ten T_s times) at which, on every tick of
 * the overlap, the sum's tool-point speed (and its step over the tick),
 * its change over the tick (acceleration) and the change of that change
 * (jerk), and the same three of its angular velocity, stay within the
 * larger of the two goals' Cartesian limits (a joint move has none: G's)
 * (or within what M or G alone does at that tick, where that is more: an
 * arc's centripetal part, a stop in joint space). t0 = T_s,
 * no overlap, always qualifies: the new motion starts the tick the old
 * one stops, without waiting for the tool to settle. While M's stop lasts,
 * and after it until the tool is back within cfg.track_tol and closing
 * in, the tracking bound is a stop's (TRACK_GIVE_UP times it); from the
 * takeover the setpoint is the IK step's, following the sum (a stop in
 * joint space included: its joint velocities qd_M are fed forward in the
 * task's null space too, kc_ik_step_ff, so that the step gives them back
 * whole, J^+ J qd_M + (I - J^+ J) qd_M = qd_M, on a redundant arm as on
 * any other; the IK's own null-space objective rests while they are fed,
 * M's stop carrying the joints' null-space motion, and comes back from 0
 * after it as at a Cartesian goal's start). Limits:
 * the joints are not judged over the overlap beforehand (M's stop stays
 * inside the position limits its motion was planned or checked within,
 * give or take dt |qd| / 2; their jerk is M's stop's until G moves, then
 * that and what G asks of them, G being bounded in Cartesian jerk only;
 * the final check of every setpoint still holds, a joint that cannot
 * follow faults as any Cartesian motion does; the dry run, given a
 * snapshot of the controller, steps this very takeover and refuses a G
 * whose overlap faults, kinctl/check.h). A replacement that arrives while
 * a superposition lasts, or while the motion stops (a STOP's, a PAUSE's,
 * one a goal waits for, the servo timeout's), takes over the same way
 * from the motion under way, which stops joint by joint from the last
 * setpoint (the halt below: a sum of two plans has no stop of its own).
 * A STOP or PAUSE during the overlap lets the new segment go on as
 * judged until the old one's stop has ended, and then stops it on its
 * path: the two stops never add (the old one may brake at a joint's
 * limits, as a joint move's does). One that has not started yet stays at
 * rest where it starts.
 *
 * A joint path replacing any moving goal but a trapezoid joint move
 * takes over in the tick it arrives the same way, in joint space: M's
 * stop joint by joint (a joint move's or servo stream's as above; a
 * line's, an arc's or a path's the halt joint by joint, a line's, an
 * arc's or a Cartesian path's within its Cartesian bounds as well;
 * exact, no IK step in between), G planned from the
 * joints q_s where it rests, at rest there (a path the controller ramps,
 * Lagrange's, a cubic spline, a parabolic blend, on its jerk-limited
 * ramps of tau' from rest, its own timing; under the trapezoid's law,
 * whose constant-rate ramps step tau'' at rest, it stops first),
 * q = q_M + q_G - q_s (and so qd, qdd; G adds nothing
 * before it starts), t0 the earliest of the same bounded search at which
 * every joint of the sum stays inside its position limits and within its
 * qd_max, qdd_max and qddd_max (the change of qdd over a tick), or within
 * what M or G alone does at that tick where that is more (a parabolic
 * blend's step of qdd), on every tick of the overlap.
 *
 * A replacing servo stream takes over in the tick it arrives where the
 * old target follows a law: a line, an arc, a Cartesian path, a shaped
 * pose stream (all sampled from their laws tick by tick) or a twist
 * stream (whose target moves over each tick by its twist and the rate of
 * that tick's step, held over the tick: v dt + a dt^2 / 2, with v + a dt
 * the twist fed forward at the tick's target, the target's own velocity
 * there, as a sampled law's is); and from a joint move or a joint path
 * on an arm of six joints or more under the full task, from a target
 * with the law the
 * step would have tracked with the joints' (q, qd, qdd) at the last
 * setpoint: the tool's pose moved by the step's error at that
 * acceleration, k e = J qdd dt / 2 (k the row's gain), twist J (qd + qdd
 * dt / 2), its rate the change of J qd over the next tick with qdd held,
 * so that the step's first velocity is qd + qdd dt (the joints' qdd goes
 * on: no step at the takeover) and from there the stream's own law moves
 * the target. On six joints the IK step gives the joints' velocities
 * back (J invertible). On a redundant arm it gives back the part the task
 * sees and not the self-motion: the jerk bound of the stream (above,
 * kc_ctrl_servo_jerk) brings the joints onto the step's velocities within
 * their jerk limits over the next ticks, the step correcting what that
 * moves the tool by (the Panda in test_ctrl_servoshape.c: the joints'
 * jerk at their limits through it, the tool within 5.6e-6 m of the
 * stream's target, 1.43e-5 m at five times the cases; 2.5e-6 m on the
 * PUMA 560). So also from a stop: a line's, an arc's or a Cartesian
 * path's on its path (a STOP's, a PAUSE's, one for a goal waiting on it;
 * its law is the stop's), a joint motion's on its line or joint by joint
 * (from the joints, as above); from a superposition of a line, an arc
 * or a Cartesian path on a stop on its path, from the sum (its target at
 * the ticks each side composed the same way); and from a superposition
 * on a stop in joint space (a line's, an arc's, a Cartesian or a joint
 * path's on a joint move's stop), from the joints as from a joint move
 * (from the sum the joints' jerk went to their limits at the takeover,
 * 0.46 of them around it). The stream goes on from the old target's
 * pose, twist and the twist's rate at the last setpoint: a shaped pose
 * stream's profiles from the rate at that tick (a segment's by the
 * central difference of its twists over the ticks each side), a twist
 * stream from the rate of the old law's last tick (the backward
 * difference, the rate its own law holds: from the rate at the tick, its
 * target's jerk at the takeover reached 4 / 3 of the two laws'). Its
 * profiles or its twist's step then take it on within its bounds, so the
 * IK step tracks it with the error it already had. The target's twist and
 * rate must be within the stream's speed, omega, accel and alpha (with
 * the rounding of cfg.limit_slack; a joint move at speed is beyond a
 * stream's default Cartesian speed and acceleration). An axis' rate
 * beyond its share, 1 / sqrt(3) of the bound (a line accelerating along
 * no axis of the base), is brought within it by a pose stream's profile
 * of that axis and by a twist stream's step, each at the axis' jerk
 * bound (a twist stream stopped such a motion first before: 6 of 19
 * PUMA 560 and 11 of 28 Panda motions in test_ctrl_servoshape.c's
 * takeovers, none now). Random takeovers
 * (test_ctrl_servoshape.c): the joints' jerk on a takeover's first three
 * ticks at most 1.09 times that of the eight ticks each side, where the
 * IK step's response to the change of the target's jerk overshoots the
 * new level for a tick as it does on a pose stream's own new poses (up to
 * 1.17 times there); from a joint move, no change of qdd on the
 * takeover's tick (81 of 249 PUMA 560 joint moves taken over, the others
 * beyond the stream's bounds). A twist stream's target moved by the rate before
 * the tick's step reached twice its jerk bound on every reversal of the
 * rate's ramp, and a twist stream after a line 1.25 times the joints'
 * jerk around it.
 *
 * Every other replacement stops first: the active segment stops on its
 * path, and the goal starts from where the arm comes to rest. Its ACCEPTED
 * event carries KC_REASON_STOP_FIRST. These are a joint move whose
 * retarget would pass a limit; a line, an arc or a Cartesian path
 * replacing a trapezoid joint move (its stop brakes at a joint's acceleration limit
 * from its first tick to its last, which the IK step cannot follow
 * through a Cartesian target with its correction added), a servo stream
 * whose stop is not jerk-limited (a chain without jerk limits: it brakes
 * at the acceleration limits); a path the controller ramps at a constant
 * rate (one that does not start at rest, Lagrange's, a natural spline,
 * under the trapezoid's law); a joint path replacing a trapezoid joint move; a stop
 * joint by joint that cannot be planned jerk-limited (a chain without
 * jerk limits, a joint accelerating near its qd_max: the goal waits for
 * the motion's own stop); a replacing servo stream but those above (a
 * stream's stop, a fault's, a stop in joint space of a Cartesian goal or
 * waiting on its path; on an arm of fewer than six joints or under a
 * partial task, a joint move, a joint path, their stops and what is
 * superposed on them); a goal that cannot be
 * planned from P_s; and a goal with stop_first set. Setpoints stay continuous in
 * position and velocity throughout, and in acceleration through
 * everything jerk-limited.
 *
 * Commands. STOP: stop on the path, drop the queue, back to idle. PAUSE:
 * stop on the path and hold; RESUME: continue the same segment from there.
 * ESTOP: every joint decelerates at its own acceleration limit (off the
 * path: as hard as the limits allow), then the controller latches in ESTOP.
 * ESTOP and the stops of a fault (an external one, a failed limit check, a
 * zone, a Cartesian motion that cannot be followed) are
 * acceleration-limited, not jerk-limited: the acceleration jumps to the
 * limit in one tick, because stopping soonest matters more there than
 * smoothness. STOP, PAUSE and RESUME of a jerk-limited
 * joint move, line or arc are jerk-limited (below), and so are STOP, PAUSE,
 * a stop-first replacement and the servo timeout of a servo stream (a
 * stream that goes quiet is its usual end): every joint from its
 * (q, qd, qdd) to rest by kc_scurve_plan_stop within its qdd_max and
 * qddd_max, synchronised by phase (each joint's acceleration and jerk
 * bounds scaled with its speed: from qdd = 0 the joints end on the same
 * tick on the straight line of qd, in the slowest joint's own stopping
 * time or somewhat more where one joint's acceleration limit and
 * another's jerk limit bind; a joint whose qdd is beyond its scaled
 * bound stops at its own limits);
 * a chain without jerk limits stops acceleration-limited, and so does a
 * servo stream's stop that would carry a joint past its qd_max (one
 * accelerating near its speed limit gains qdd^2 / (2 qddd_max) before
 * its acceleration is down: the final check would refuse that and
 * fault; every such quiet stream faulted, limit_guard, before). A
 * stream's own steps leave a joint that room (kc_ctrl_servo_jerk), so
 * only a stream that took over such a motion stops so. RESUME of a
 * servo stream hands the arm back to the stream's own law.
 * RESET: leaves FAULT or ESTOP (at rest) for IDLE.
 *
 * Stopping on the path. Interpolated segments are driven by a profile of
 * their path parameter u; a stop replaces it with kc_profile_plan_stop at
 * the plan's own bound on u'', resume with a profile from there to u = 1.
 * A jerk-limited line or arc stops by kc_scurve_plan_stop of u from
 * (u, u', u'') within the plan's bounds on u'' and u''' (never past
 * u = 1), and resumes by the rest-to-rest kc_scurve from there to 1
 * within its bounds on u', u'' and u'''; the stop of a fault on its path
 * is the acceleration-limited one (kc_profile_plan_stop from (u, u'):
 * u'' jumps to its bound).
 * A jerk-limited joint move on a straight line (synchronised by phase)
 * stops on it by kc_scurve_plan_stop of u from (u, u', u'') within the
 * plan's bounds on the second and third derivatives of u (the stop of
 * least distance: at those bounds it never passes u = 1); one whose joints are
 * synchronised by time, or a retarget, stops each joint by
 * kc_scurve_plan_stop from its (q, qd, qdd) within the goal's limits (no
 * further than its profile would have turned, so inside the position
 * limits it was planned or checked within). Either resumes as a
 * jerk-limited move from where it rests to the goal's target. For a
 * replacing goal (stopped first, or superposed on the stop) either stop
 * is planned within 1 - 1e-5 of the jerk bounds, room for the IK step's
 * correction of a Cartesian goal superposed on it (ctrl_stop.c): such a
 * stop of a move braking into its end at the bound passes the end by
 * at most about 1e-5 of the stopping distance (the arm rests there; where that
 * would cross a position limit, the stop is planned at the whole bound).
 * Paths are driven by their plan time tau; a stop makes tau' fall from 1 to
 * 0 at a rate c, chosen (and its start delayed while the path is itself
 * braking hard) so that every joint's q'' tau'^2 + q' tau'' stays within
 * its limit on sampled instants of a stop at that constant rate. A joint
 * path's stop is then checked on every tick (|qdd| <= qdd_max, qd moving
 * by at most qdd_max dt): one that fails is planned again at half the
 * rate, up to PATH_STOP_TRIES (4) times, and where none fits the path
 * goes on under its own law and stops from a later tick, as it does while
 * no rate starts a stop (random PUMA 560 and Panda paths stopped at random
 * ticks, tests/unit/test_ctrl_pathstop.c: half of them waited, at most 98
 * ticks of 1 ms; the last of the four plans, kept unchecked before, faulted one
 * stop in 15,000 and took another's qdd to 1.0003 qdd_max). Where the
 * controller chooses the time law of a path - that stop, the resume, and
 * the ramps of tau' from rest and into the end of a path that does not
 * start at rest (Lagrange's, a natural spline's) or, jerk-limited, whose
 * acceleration steps at its ends (a clamped cubic spline's, a parabolic
 * blend's) - it is jerk-limited by default: tau follows
 * kc_scurve_plan_stop from (tau, tau', tau'') within c (the stop), or the
 * rest-to-rest kc_scurve to the path's end with tau' <= 1 and tau'' <= the
 * ramp's rate (the ramps, the resume), so tau'' is continuous (a path
 * whose ramps cannot be planned under its law is aborted as it would
 * start: KC_EVENT_ABORTED, KC_REASON_PLAN). A joint's jerk under that law
 * is
 *     q''' tau'^3 + 3 q'' tau' tau'' + q' tau''',
 * q' .. q''' the path's own derivatives in tau. Each joint's room is
 * qddd_max less the path's own |q'''| where the law runs (at least half
 * of qddd_max: where the path's own jerk comes near its limit, or beyond
 * it with given times); c and the ramps' rate keep 3 |q''| tau' |tau''|
 * within half the room (tau' the constant-rate law's there: a
 * jerk-limited ramp from rest, or into the end, has no more where it
 * reaches the same tau; a stop's at its start), and the bound on tau'''
 * is the room less 3 |q''| times the law's bound on |tau''| (at least
 * half the room) over |q'| (a Cartesian path: the goal's jerk and angular
 * jerk over the tool's speed and angular speed), on sampled instants of
 * the stretches the law runs over (the ramps: the plan time each covers),
 * each |q'| with half a sample spacing times its derivative. So the jerk
 * the law adds stays within what the path leaves of the limits. A stop
 * taken while a ramp's tau' still rises brings tau'' to 0 before tau'
 * reaches 1 (at the ramp's own jerk there at most). A stop that would
 * carry tau past the path's end leaves the law under way, which comes to
 * rest there sooner (every path's law in the controller ends at rest at
 * its end). Between those, tau' = 1: the path's own law, which its knot
 * times fix (blends, splines, quintics with given or computed times; the
 * path's own jerk there is the method's, kinctl/path.h). Knot times
 * computed from the limits of a jerk-limited joint path are stretched
 * so its pieces keep every joint's jerk within qddd_max too (kc_path_cfg
 * jmax). So a joint path of every method but the parabolic blend (whose
 * acceleration steps at its blends, whatever the times) keeps every
 * joint's jerk within qddd_max from rest to rest, through its stops,
 * pauses and resumes (24 random PUMA 560 paths of each method, a third
 * paused and a third stopped at random ticks: at most 0.9963 of qddd_max,
 * test_ctrl_pathjerk.c; the trapezoid's quintics reach 2.19). The ramps
 * cost time: 20 random clamped splines took 29 % longer than on their
 * own law, 20 Lagrange paths 1.4 % longer than with ramps that left out
 * the jerk 3 q'' tau' tau'' adds. A path that the controller ramps is
 * superposed on the stop of the motion it replaces on its jerk-limited
 * ramps, as its own timing (a STOP or PAUSE there waits on them as on a
 * path's own law while that stop lasts); at a constant rate it is not:
 * that motion stops first. A joint path's stop while superposed is
 * planned only where the sum with the stop under it keeps the joints'
 * acceleration and jerk limits on every tick (the path otherwise goes on
 * as judged and stops from a later tick, once that stop has ended at the
 * latest): of 3,721 random superposed paths stopped
 * (test_ctrl_pathstop.c) the joints' jerk at most 1 + 1e-9 of their
 * limits, 1.70 before the sum's jerk was judged.
 * A Cartesian goal's jerk-limited stop (a line, an arc, a Cartesian path;
 * for STOP, PAUSE and a replacement alike) has those bounds on u'' and
 * u''' (tau'', tau'''), which are the tool's, scaled down for its joints:
 * by the largest share, in halvings, that keeps each joint's acceleration
 * and jerk within a share of its limits, as estimated from the last
 * setpoint, or where none does the share whose estimate is least
 * (ctrl_stop.c, joint_bounded_stop, gives the estimate and the shares).
 * Its resume ramps at that share or less, and at a jerk whose share of
 * the joints' qddd_max the largest rates of the joints per unit of the
 * path's parameter hold, as the stop saw them and as the goal's dry run
 * did over the whole path (kc_goal.qu, which kinctld sets). It is an estimate at the
 * stop's start: where the joints' rates change fast along the path (near
 * a singularity) the joints may not follow the stop within their limits
 * (a PUMA 560 arc's STOP went 98 times beyond their jerk limits). In
 * double, the stop then leaves the path at the first tick whose IK step
 * would change a joint's qdd beyond qddd_max dt, and goes on joint by
 * joint, jerk-limited, from the last setpoint, as a servo stream's stop
 * (ctrl_internal.h, kc_ctrl_stop_leave_path); a PAUSE so stopped ends as
 * a STOP, the goal aborted at rest. Of 200 random streams of 100 STOPs
 * and 100 of each replacement (test_ctrl_cartstop.c), 20 of 40,000 stops
 * left their paths and none went beyond the limits; the tool came to
 * rest up to 3.1 cm and 0.42 rad from where the path's stop rests. Not
 * in float, where the IK step's rounding alone is above that bound: the
 * stop keeps its path. Of 200 random streams of 100 PAUSEs and RESUMEs
 * each, judged and handed on as kinctld does, none went beyond the
 * joints' limits (with the stop's rates alone, 4 did in their resumes, by
 * 1.03 to 1.28: a slow ramp's last jerk phase came where the joints'
 * rates are larger than anywhere the stop came; the resumes so held took
 * 1.5 % longer in all). A line's or an
 * arc's scaled stop that would pass u = 1 gives way to the gentlest
 * between it and the plan's own bounds that does not (the plan's own never
 * does); a path's leaves the law under way, as above. The trapezoid
 * (cfg.profile, the goal's profile, or a chain without jerk limits) keeps
 * constant-rate ramps and stops, and a fault's stop on the path is the
 * constant-rate one.
 *
 * Every setpoint is checked before it leaves: finite, inside the position
 * limits, |qd| within the velocity limits, and the change of qd within
 * qdd_max dt (both with a relative slack of cfg.limit_slack for rounding).
 * A violation is a bug or a bad model, never a normal outcome: the
 * controller then holds the last good setpoint's position and faults.
 *
 * Forbidden zones (cfg.zones, kinctl/zone.h; NULL: none). Every setpoint is
 * also checked against the zones: one that brings a link volume closer than
 * the set's margin to a zone, and closer than the last setpoint was, is
 * never sent; the arm stops as for e-stop (every joint at its own
 * acceleration limit, from the last good setpoint) and faults with
 * KC_REASON_ZONE, the event naming the zone and the volume. (A setpoint
 * inside the margin that does not come closer passes: an arm already there
 * may leave.) Goals are checked before they are accepted: the dry run
 * (kinctl/check.h) steps every tick of every goal, joint moves included, through the same
 * check (a replacing goal, from a snapshot of the controller: its
 * retarget's overshoot, its superposition or its stop first included), and kc_ctrl_cfg_check refuses a zone set whose margin is not above
 * kc_zone_tick_travel (the farthest any point of a volume moves in one tick
 * at the velocity limits), so a goal whose every tick keeps the margin
 * cannot cross a zone between two ticks. A servo goal is slowed instead:
 * while it approaches a zone, a step may come closer by at most
 * dt sqrt(2 a e) and move no point of a volume (by the lever bound of
 * kinctl/zone.h) more than e / 2, e the clearance beyond the margin and a
 * half the smallest qdd_max_j lever_j, so it brakes and comes to rest at
 * the margin rather than entering it. The cycle's check is a last line of
 * defence: an e-stop from speed travels its stopping distance, possibly
 * into the zone; keeping goals out is the dry run's job.
 *
 * Threads. kc_ctrl_step is for one thread (the cycle); the dry run
 * (kinctl/check.h) may run on another with its own kc_check (about
 * sizeof(kc_ctrl) of storage; it runs the goal through the same step code:
 * one IK step per tick of a Cartesian motion).
 */
#ifndef KINCTL_CTRL_H
#define KINCTL_CTRL_H

#include <stdint.h>

#include "kinctl/decls.h"
#include "kinctl/ik.h"
#include "kinctl/interp.h"
#include "kinctl/path_cart.h"
#include "kinctl/profile.h"
#include "kinctl/zone.h"

KC_BEGIN_DECLS

#ifndef KC_CTRL_QUEUE_MAX
#define KC_CTRL_QUEUE_MAX 8
#endif
/* Events one tick can produce. Every event names a goal: each of the at
 * most KC_CTRL_QUEUE_MAX + 1 goals queued or taken in the tick ends in one
 * event, except the one goal a tick can start (ACCEPTED, STARTED, FAULT,
 * ABORTED or COMPLETED: three more), and the goal active when the tick
 * began has at most FAULT and one end: 2 (a full queue replaced by a joint
 * goal is 8 PREEMPTED, ACCEPTED, PREEMPTED, STARTED). */
#define KC_CTRL_EVENTS_MAX (KC_CTRL_QUEUE_MAX + 8)

typedef enum kc_ctrl_state {
    KC_CTRL_IDLE = 0,
    KC_CTRL_MOVING = 1,
    KC_CTRL_PAUSED = 2,
    KC_CTRL_STOPPING = 3,
    KC_CTRL_FAULT = 4,
    KC_CTRL_ESTOP = 5
} kc_ctrl_state;

typedef enum kc_goal_kind {
    KC_GOAL_JOINT = 0,
    KC_GOAL_LINE = 1,
    KC_GOAL_ARC = 2,
    KC_GOAL_PATH = 3,      /* joint space */
    KC_GOAL_PATH_CART = 4, /* Cartesian */
    KC_GOAL_SERVO = 5
} kc_goal_kind;

typedef enum kc_ctrl_command {
    KC_CMD_NONE = 0,
    KC_CMD_STOP = 1,
    KC_CMD_ESTOP = 2,
    KC_CMD_PAUSE = 3,
    KC_CMD_RESUME = 4,
    KC_CMD_RESET = 5
} kc_ctrl_command;

/* A goal as a client describes it. Fields a kind does not use are ignored. */
/* The motion law a joint move asks for. */
typedef enum kc_goal_profile {
    KC_GOAL_PROFILE_CFG = 0,       /* the controller's (kc_ctrl_cfg.profile) */
    KC_GOAL_PROFILE_TRAPEZOID = 1, /* seed 001 lab 4's trapezoid */
    KC_GOAL_PROFILE_JERK = 2       /* jerk-limited */
} kc_goal_profile;

typedef struct kc_goal {
    int64_t id;        /* chosen by the client, echoed in events and setpoints */
    kc_goal_kind kind;
    int replace;       /* 0: queue behind the others; 1: preempt */
    /* With replace: 1 has the motion it replaces stop on its path first,
     * as where no continuous transition exists (no retarget, no
     * superposition; ACCEPTED with KC_REASON_STOP_FIRST). kinctld sets it
     * where the dry run finds the transition beyond a joint's jerk limit
     * and the stop first within it (kinctl/check.h). */
    int stop_first;
    /* A replacing goal judged from the controller's moving state
     * (kinctl/check.h) is taken only as judged: in the tick whose output
     * cycle is take_cycle, from the state whose kc_ctrl_stamp is
     * take_state; in any other tick, or from any other state (a command,
     * a servo message or a stalled cycle between), it is refused
     * (KC_REASON_LATE), the motion it would replace going on. 0: taken
     * whenever it arrives. kinctld holds such a goal until its cycle. */
    int64_t take_cycle;
    uint32_t take_state;
    /* Line, arc, Cartesian path: the largest of its joints' rates per unit
     * of the rate of its path parameter u (|qd_i| / u', over qddd_max_i)
     * that its dry run saw while u' was at least a tenth of its top
     * (kc_verdict.qu; kinctld sets it). A resume after a pause ramps u''
     * at a jerk whose share of the joints' qddd_max this holds for the
     * path still ahead, as the stop's own measure (kc_ctrl.stop_qu) holds
     * it for the way the stop came. 0: the stop's alone. */
    kc_real qu;
    /* The share of its speed kc_goal_slow has slowed it to (the product
     * of the shares, each call's s), 0 or 1: as asked (kc_goal_share).
     * The controller does not read it: a record of the goal as it runs
     * (kinctld publishes it with the setpoint, which kinctl-replay
     * reads). */
    kc_real slowed;
    kc_goal_profile profile; /* joint move, line, arc, path: its motion law */
    /* Fractions of the joints' velocity and acceleration limits, (0, 1]. */
    kc_real vel_scale, acc_scale;
    /* Cartesian speed and acceleration of the tool point (m/s, m/s^2) and
     * the tool's angular speed and acceleration bounds (rad/s, rad/s^2); 0
     * takes the configured defaults. */
    kc_real speed, accel;
    kc_real omega, alpha;
    /* Line, arc, Cartesian path: the jerk bounds of the tool point along
     * its path (m/s^3) and of the tool's rotation (rad/s^3); 0 takes
     * cfg.cart_jerk and cfg.cart_angular_jerk. The trapezoid (profile, or
     * cfg.profile) ignores them. */
    kc_real jerk, angular_jerk;
    kc_interp_orient orient;             /* line */
    /* Numbers per target or knot as the client gave them (joint move and
     * joint path: its joint count; Cartesian path: 7); 0 takes what the
     * kind and the chain need. A count that differs is refused. */
    int dim;
    kc_real q[KC_MAX_JOINTS];            /* joint move: the target */
    kc_pose pose;                        /* line, arc: end pose; servo: target */
    kc_vec3 via;                         /* arc */
    /* Paths: n_points knots after the current state, joint values or
     * x y z qw qx qy qz each; times (s, from the start, increasing) if
     * has_times, else from the limits; blend_time for blends (0: the rule
     * of kinctl/path.h). */
    kc_path_method method;
    kc_path_blend blend;           /* blends: quartic (C2) or parabolic (C1) */
    kc_path_spline_end spline_end; /* C2 splines: clamped or natural ends */
    int n_points;
    kc_real points[KC_PATH_MAX_KNOTS - 1][KC_MAX_JOINTS];
    int has_times;
    kc_real times[KC_PATH_MAX_KNOTS - 1];
    kc_real blend_time;
    /* Servo: follow pose, or with servo_twist move the target by twist
     * (vx vy vz wx wy wz, base frame, m/s and rad/s). A servo goal with the
     * id of the active servo updates it. */
    int servo_twist;
    kc_real twist[6];
} kc_goal;

/* Why a goal was refused or a motion ended abnormally. */
typedef enum kc_ctrl_reason {
    KC_REASON_NONE = 0,
    KC_REASON_BAD_GOAL,      /* non-finite or out-of-domain field */
    KC_REASON_JOINT_COUNT,   /* wrong number of joints in the goal */
    KC_REASON_JOINT_LIMIT,   /* a target outside the position limits */
    KC_REASON_QUEUE_FULL,    /* KC_CTRL_QUEUE_MAX goals waiting */
    KC_REASON_STATE,         /* not accepted in FAULT or ESTOP: reset first */
    KC_REASON_PLAN,          /* the planner refused it (degenerate arc, too long...) */
    KC_REASON_UNREACHABLE,   /* Cartesian: the arm cannot follow (checked by dry run) */
    KC_REASON_TRACKING,      /* the tool fell behind: a Cartesian path (fault) or a servo stream (stopped) */
    KC_REASON_LIMIT_GUARD,   /* fault: a setpoint failed the final check */
    KC_REASON_SERVO_TIMEOUT, /* the servo stream went quiet: stopped */
    KC_REASON_DUPLICATE_ID,  /* a goal with this id is active or queued */
    KC_REASON_EXTERNAL,      /* fault: the caller reported one (a drive, the field bus) */
    KC_REASON_ZONE,          /* a link volume would enter a forbidden zone's margin */
    /* Accepted, replacing a motion with no continuous transition into it:
     * the motion stops on its path first (the ACCEPTED event's reason). */
    KC_REASON_STOP_FIRST,
    /* Refused: a scheduled goal (kc_goal.take_cycle) given in another
     * tick, or with the controller in another state than judged from. */
    KC_REASON_LATE,
    KC_REASON_COUNT
} kc_ctrl_reason;

/* A readable text for a reason (never NULL). */
const char *kc_ctrl_reason_str(kc_ctrl_reason reason);


/* The part of a goal a verdict names. */
typedef enum kc_goal_field {
    KC_FIELD_NONE = 0,
    KC_FIELD_DIM,         /* dim: value is the count given */
    KC_FIELD_N_POINTS,    /* n_points: value is the count given */
    KC_FIELD_TARGET,      /* q (joint move) or points[point] (joint path); value is the number at joint */
    KC_FIELD_ORIENTATION, /* an orientation that is no rotation; value: its quaternion's norm, NaN if none */
    KC_FIELD_TIMES        /* times[point] not after the one before */
} kc_goal_field;

/* A goal judged: whether it is taken, and if not, why and where. Filled by
 * kc_ctrl_goal_check (the goal alone) and by the dry run (kinctl/check.h:
 * the motion, tick by tick). Indices are 0-based; -1 where they do not
 * apply. */
typedef struct kc_verdict {
    kc_status status;       /* KC_OK: taken; else KC_E_ARG, KC_E_UNREACHABLE, KC_E_CAPACITY */
    /* KC_REASON_NONE when taken; KC_REASON_STOP_FIRST when taken and the
     * dry run, from a snapshot, saw the replaced motion stop first */
    kc_ctrl_reason reason;
    kc_goal_field field;    /* the field at fault, KC_FIELD_NONE when none is */
    int joint;              /* the joint concerned */
    int point;              /* the knot concerned (index into kc_goal.points) */
    kc_real value;          /* the number at fault (see kc_goal_field), 0 when none */
    /* Where along the motion it failed (dry run): tick of the run (its
     * period: the check's, or from a snapshot the controller's; from 1)
     * and path length (m) or fraction, as kc_ctrl_event.where. */
    int64_t tick;
    kc_real where;
    /* KC_REASON_ZONE: the zone (index into cfg.zones), the link volume
     * (index into chain->volumes) and their distance (m). */
    int zone, volume;
    kc_real distance;
    /* Taken: the joints where the goal ends (its start for a servo goal). */
    kc_real q_end[KC_MAX_JOINTS];
    /* A dry run that stepped the motion: the largest change of a joint's
     * qdd over one tick of the run, in units of that joint's qddd_max
     * times the run's period (1: at the jerk limit), over every tick
     * stepped; 0 when nothing was (kinctl/check.h). */
    kc_real jerk;
    /* 1 when that jerk is the goal's own doing: judged from rest, or from
     * a snapshot whose motion the goal's takeover or stop-first stop
     * leaves to a jerk-limited law, or measured from the goal's start
     * (it stops first a motion whose law is not jerk-limited); 0 when it
     * includes the goal taking over from such a law (kinctl/check.h). */
    int jerk_own;
    /* Judged from a snapshot (kinctl/check.h): the cycle and the state
     * the controller takes the goal in (kc_goal.take_cycle, take_state);
     * 0 when judged from rest, for whenever it arrives. */
    int64_t take_cycle;
    uint32_t take_state;
    /* A dry run that stepped a line, an arc or a Cartesian path: the
     * largest |qd_i| / u' / qddd_max_i while it ran on its own law at a
     * tenth of u's top rate or more (kc_goal.qu); else 0. */
    kc_real qu;
} kc_verdict;

typedef enum kc_ctrl_event_kind {
    KC_EVENT_ACCEPTED = 1,
    KC_EVENT_REJECTED = 2,
    KC_EVENT_STARTED = 3,
    KC_EVENT_COMPLETED = 4,
    KC_EVENT_PREEMPTED = 5, /* replaced by a newer goal, or dropped from the queue */
    KC_EVENT_ABORTED = 6,   /* stopped by a command or a fault */
    KC_EVENT_FAULT = 7
} kc_ctrl_event_kind;

typedef struct kc_ctrl_event {
    kc_ctrl_event_kind kind;
    int64_t goal_id;
    kc_ctrl_reason reason;
    kc_real where; /* path length (m) or fraction where a fault happened */
    /* KC_REASON_ZONE: the zone (index into cfg.zones) and the link volume
     * (index into chain->volumes); -1 otherwise. */
    int zone, volume;
} kc_ctrl_event;

typedef struct kc_ctrl_cfg {
    kc_real dt;                    /* tick period (s) */
    kc_real cart_speed, cart_accel; /* defaults for Cartesian goals (m/s, m/s^2) */
    kc_real cart_omega, cart_alpha; /* tool angular speed and acceleration bound (rad/s, rad/s^2) */
    /* Jerk bounds for jerk-limited Cartesian goals: of the tool point along
     * its path (m/s^3) and of the tool's rotation (rad/s^3). */
    kc_real cart_jerk, cart_angular_jerk;
    kc_real track_tol;             /* largest tool position error while following (m) */
    kc_real limit_slack;           /* relative slack of the final limit check */
    int64_t servo_timeout_ticks;   /* default servo staleness */
    /* The motion law unless a goal says otherwise: KC_PROFILE_JERK (the
     * default) or KC_PROFILE_TRAPEZOID. Joint moves: a chain with a joint
     * without a jerk limit (qddd_max infinite) moves by trapezoids
     * whatever is asked. Lines, arcs and paths: the trapezoid takes the
     * jerk limits as infinite. */
    kc_profile_kind profile;
    kc_ik_cfg ik;                  /* the online law for Cartesian motion */
    /* Forbidden zones, or NULL; must outlive the controller, unchanged. */
    const kc_zone_set *zones;
} kc_ctrl_cfg;

/* 1 kHz, 0.25 m/s and 0.5 m/s^2, 1 rad/s and 4 rad/s^2, jerk bounds
 * KC_INTERP_JERK_PER_ACCEL (10/s) times the acceleration ones (5 m/s^3,
 * 40 rad/s^3), tracking 1 mm,
 * slack 1e-6 (1e-4 in float), servo timeout 100 ticks, jerk-limited joint
 * moves, kc_ik_cfg_default, no zones. */
kc_ctrl_cfg kc_ctrl_cfg_default(void);

/* Inputs of one tick. */
typedef struct kc_ctrl_input {
    const kc_goal *goal;     /* a new goal, or NULL */
    kc_ctrl_command command; /* KC_CMD_NONE mostly */
    int servo_stale;         /* 1: the servo stream has gone quiet (the caller's clock) */
    /* An external fault (KC_REASON_EXTERNAL; KC_REASON_NONE mostly): the
     * caller's hardware cannot follow (a drive faulted or went silent, the
     * bus is lost). Unless already in FAULT or ESTOP, the controller emits
     * FAULT (and ABORTED for the active goal), drops the queue and stops in
     * joint space at the joints' limits, then holds in FAULT until RESET. */
    kc_ctrl_reason fault;
} kc_ctrl_input;

/* The setpoint of one tick and what happened. q, qd, qdd: a joint
 * motion's (a joint move, a joint path, a stop in joint space) are its
 * law's values at the tick; a Cartesian goal's and a servo stream's come
 * from the IK step, q moving by qd dt over the tick and qdd the change of
 * qd over it. Where such a goal takes over a joint motion, q's second
 * difference over that tick is qdd and about half the tick before's:
 * up to 1.5 qdd_max for one tick (1.495 in kinctld, a line taking over a
 * PUMA 560's joint move), qd and qdd within the limits. */
typedef struct kc_ctrl_output {
    int64_t cycle;
    int64_t goal_id; /* active goal, 0 when none */
    kc_ctrl_state state;
    kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS], qdd[KC_MAX_JOINTS];
    kc_pose pose; /* FK of q */
    kc_real progress; /* of the active segment, 0..1 */
    int queue_length;
    int n_events;
    kc_ctrl_event events[KC_CTRL_EVENTS_MAX];
} kc_ctrl_output;

/* The active segment's plan. */
typedef union kc_ctrl_plan {
    kc_interp_joint joint;
    kc_interp_line line;
    kc_interp_arc arc;
    kc_path path;
    kc_path_cart path_cart;
    kc_profile retarget[KC_MAX_JOINTS]; /* one profile a joint, from (q, qd) to the target */
    kc_scurve halt[KC_MAX_JOINTS];      /* one jerk-limited stop a joint */
    /* A pose stream's shaped pose (ctrl_servo.c): from tick k0, x, y, z
     * and the rotation vector phi of R = exp(phi) ref, one profile each. */
    struct kc_ctrl_servo_plan {
        kc_scurve axis[6];
        kc_quat ref;
        int64_t k0;
    } servo;
} kc_ctrl_plan;

/* How the active segment is driven. */
typedef enum kc_ctrl_drive {
    KC_DRIVE_NOMINAL = 0, /* its own timing (a path on its own ramp: tau from kc_ctrl.ramp) */
    KC_DRIVE_PROFILE = 1, /* interp: u from drive_prof; path: tau from drive_prof */
    KC_DRIVE_STOPPING_WAIT = 2, /* path: a stop is pending until it is feasible */
    KC_DRIVE_RETARGET = 3,      /* trapezoid joint move from a moving state: plan.retarget per joint */
    KC_DRIVE_SCURVE = 4,        /* jerk-limited joint move on its line, line, arc: u from drive_scurve */
    KC_DRIVE_HALT = 5           /* a jerk-limited stop joint by joint: plan.halt */
} kc_ctrl_drive;

/* What a jerk-limited joint move stopping on its straight line keeps of
 * its plan (kc_interp_joint): q = q0 + dq u, and what a stop or a fault
 * of it reads again. */
typedef struct kc_ctrl_blend_joint {
    int n;
    kc_real q0[KC_MAX_JOINTS], q1[KC_MAX_JOINTS], dq[KC_MAX_JOINTS];
    kc_real u_vmax, u_amax, u_jmax;
    kc_profile_kind kind;
    kc_interp_sync sync;
} kc_ctrl_blend_joint;

/* A replacing goal's transition (a line, an arc or a Cartesian path; a
 * joint path in joint space): the motion it replaced, stopping,
 * superposed on it (ctrl_blend.c). */
typedef struct kc_ctrl_blend {
    int on;
    kc_goal_kind kind; /* the replaced segment's */
    /* Its plan (a line's or an arc's stopping on its path), or what a
     * stop elsewhere needs: a jerk-limited joint move's line (stop_drive
     * KC_DRIVE_SCURVE) or one jerk-limited stop a joint (KC_DRIVE_HALT:
     * a joint move's, a servo stream's, a path's, a line's or an arc's
     * under a joint path). */
    union {
        kc_interp_line line;
        kc_interp_arc arc;
        kc_ctrl_blend_joint joint;
        kc_scurve halt[KC_MAX_JOINTS];
    } plan;
    /* Its u from the takeover to rest: a jerk-limited stop (stop_drive
     * KC_DRIVE_SCURVE, stop.scurve) or a trapezoid's (KC_DRIVE_PROFILE,
     * stop.prof, a line or an arc); a stop joint by joint has none
     * (plan.halt); stop_ticks ticks (its last joint's). */
    kc_ctrl_drive stop_drive;
    union {
        kc_profile prof;
        kc_scurve scurve;
    } stop;
    int64_t stop_ticks;
    int64_t k0;        /* tick of the stop's start (its tick 0: the last setpoint before the takeover) */
    kc_pose rest;      /* where the stop ends: P_s, where the new segment starts */
    kc_real q_rest[KC_MAX_JOINTS]; /* its joints there, q_s (a joint path superposed) */
    /* The tracking bound is a stop's (the replaced motion's stop is part of
     * the target; or a zone held a stream's tool back, ctrl_zone.c) until,
     * after it, the tool's error (err, m, the last tick's) is within
     * cfg.track_tol and falling. */
    int lax;
    kc_real err;
} kc_ctrl_blend;

/* The controller: caller-owned, large (the plan of a 32-knot Cartesian
 * path), never copied in the cycle. Read its fields, change them only
 * through the functions here. */
typedef struct kc_ctrl {
    const kc_chain *chain;
    kc_ctrl_cfg cfg;
    kc_ctrl_state state;
    int64_t cycle;
    /* The last setpoint (the state everything continues from). */
    kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS], qdd[KC_MAX_JOINTS];
    /* The tool pose of q (FK), kept with it: where a segment starts. */
    kc_pose pose;
    /* Queue (ring buffer). */
    kc_goal queue[KC_CTRL_QUEUE_MAX];
    int queue_head, queue_len;
    /* Active segment. */
    int active;
    kc_goal goal;
    kc_ctrl_plan plan;
    /* A jerk-limited retarget, planned here before it replaces the active
     * segment's plan (which a retarget not taken still needs); a stop
     * joint by joint under a replacing goal is planned in its sj first
     * (ctrl_blend.c). */
    kc_interp_joint retarget_plan;
    int64_t k0;                /* tick of the segment's start (or of its drive profile) */
    kc_ctrl_drive drive;
    kc_profile drive_prof;
    kc_scurve drive_scurve;
    /* A path the controller ramps (kc_ctrl_path_ramped) under a
     * jerk-limited law: its own timing is tau from ramp (ramp_on), planned
     * where it starts, the stops and resumes of drive_scurve aside. */
    int ramp_on;
    kc_scurve ramp;
    int stop_intent;           /* KC_CMD_STOP/PAUSE or 1 for a preemption: what the stop is for */
    /* A Cartesian goal's stop (ctrl_stop.c): the share of its plan's
     * bounds it took, the speed of its parameter it started from, and the
     * largest |qd_i / u'| / qddd_max_i seen while it ran: what its resume
     * is held to. */
    kc_real resume_share, stop_v0, stop_qu;
    kc_ctrl_reason fault_reason;
    kc_real path_length;       /* Cartesian segments: length (m) */
    /* Servo. */
    kc_pose servo_target;
    int64_t servo_last;        /* tick of the last servo update */
    /* A shaped stream's target (above), its twist (vx vy vz wx wy wz)
     * and the twist's rate of change, at the last setpoint's tick: a
     * twist stream's twist moving towards the commanded twist, a pose
     * stream's pose towards the commanded pose (ctrl_servo.c). */
    kc_real servo_v[6], servo_a[6];
    /* The IK step's joint velocities on a stream's last tick, before the
     * joints' jerk limits (kc_ctrl_servo_jerk, ctrl_servo.c), and that
     * tick; the last tick a zone restrained the stream's step. */
    kc_real servo_cmd[KC_MAX_JOINTS];
    int64_t servo_cmd_cycle, servo_zone_cycle;
    int settle;                /* ticks a Cartesian segment has waited for the tool to settle */
    kc_real null_x;            /* the null-space motion's ramp, 0..1 (ctrl_seg.c) */
    int64_t null_cycle;        /* tick of the last IK step */
    /* A stop in joint space (e-stop, the servo timeout, a fault off the
     * path): per-joint stop profiles from tick jstop_k0, ending in state
     * after_stop. A servo stream's jerk-limited stop (drive KC_DRIVE_HALT)
     * runs plan.halt from jstop_k0 instead. */
    int jstop;
    kc_profile jstop_prof[KC_MAX_JOINTS];
    int64_t jstop_k0;
    kc_ctrl_state after_stop;
    /* Zones: the closest pair at the last setpoint, and at the last
     * violation (what a KC_REASON_ZONE names). */
    kc_zone_hit zone_now, zone_hit;
    kc_real zone_lever[KC_MAX_JOINTS]; /* kc_zone_levers of the chain */
    kc_real zone_brake;                /* a of the servo's braking law (m/s^2) */
    /* A replacing goal taking over from a moving line, arc, joint move or
     * servo stream. */
    kc_ctrl_blend blend;
} kc_ctrl;

/* Starts at rest at q0 (inside the limits), idle. chain must outlive ctrl
 * and stay unchanged. KC_E_ARG for a bad cfg (see kc_ctrl_cfg_check), a
 * chain that fails kc_chain_check, or q0 not finite or outside the limits. */
kc_status kc_ctrl_init(kc_ctrl *ctrl, const kc_chain *chain, const kc_ctrl_cfg *cfg, const kc_real *q0);

/* The arm is where its drives say: puts an idle controller at rest at q
 * (a drive's measured position, before it is enabled), keeping its cycle
 * count. KC_E_STATE unless the controller is IDLE, at rest, with nothing
 * active or queued; KC_E_ARG for NULL or q not finite; KC_E_LIMIT for q
 * outside the joints' limits (*bad_joint, if not NULL, says which,
 * 0-based). The controller is unchanged on error. Cycle-safe. */
kc_status kc_ctrl_seat(kc_ctrl *ctrl, const kc_real *q, int *bad_joint);

/* KC_OK for a usable cfg: positive rates, a valid IK cfg, finite joint rate
 * limits, and zones NULL or valid with a margin above
 * kc_zone_tick_travel(chain, dt) (when both zones and volumes exist). */
kc_status kc_ctrl_cfg_check(const kc_ctrl_cfg *cfg, const kc_chain *chain);

/* The first thing kc_ctrl_cfg_check refuses, for a message that names it. */
typedef enum kc_ctrl_cfg_field {
    KC_CFG_FIELD_NONE = 0, /* nothing: the cfg is usable */
    KC_CFG_FIELD_ARG,      /* cfg or chain NULL */
    KC_CFG_FIELD_DT,
    KC_CFG_FIELD_CART_SPEED,
    KC_CFG_FIELD_CART_ACCEL,
    KC_CFG_FIELD_CART_OMEGA,
    KC_CFG_FIELD_CART_ALPHA,
    KC_CFG_FIELD_CART_JERK,
    KC_CFG_FIELD_CART_ANGULAR_JERK,
    KC_CFG_FIELD_TRACK_TOL,
    KC_CFG_FIELD_LIMIT_SLACK,
    KC_CFG_FIELD_SERVO_TIMEOUT,
    KC_CFG_FIELD_IK,
    KC_CFG_FIELD_JOINT_QD_MAX,  /* a joint's velocity limit is not finite */
    KC_CFG_FIELD_JOINT_QDD_MAX, /* a joint's acceleration limit is not finite */
    KC_CFG_FIELD_PROFILE,       /* profile is neither kind */
    KC_CFG_FIELD_ZONES,         /* the zone set fails kc_zone_set_check */
    KC_CFG_FIELD_ZONES_MARGIN   /* the margin is not above a tick's travel */
} kc_ctrl_cfg_field;

/* kc_ctrl_cfg_check, saying what it refuses: *field (KC_CFG_FIELD_NONE when
 * the cfg is usable) and, for a joint's limit, *joint (0-based; else -1).
 * field and joint may be NULL. */
kc_status kc_ctrl_cfg_check_field(const kc_ctrl_cfg *cfg, const kc_chain *chain, kc_ctrl_cfg_field *field,
                                  int *joint);

/* A verdict that takes the goal and names nothing: indices -1, no tick,
 * infinite distance. */
void kc_ctrl_verdict_init(kc_verdict *verdict);

/* The cheap checks of a goal: finite fields, scales in (0, 1], joint
 * counts, joint targets inside the limits (naming the joint and knot),
 * knot counts and times. KC_OK or KC_E_ARG; *verdict (if not NULL) says
 * which (no tick, zone or end joints: no motion is judged). Cycle-safe. */
kc_status kc_ctrl_goal_check(const kc_chain *chain, const kc_goal *goal, kc_verdict *verdict);

/* Slows goal g's motion law by s in (0, 1]: the tool's speed and angular
 * speed s times, its accelerations s^2 times and its jerks s^3 times (each
 * the goal's, or where 0 cfg's), a Cartesian path's knot times and blend
 * time 1/s times. The path stays the same, its law is the same law in
 * time stretched by 1/s, and so the k-th time derivative of every joint
 * along it is s^k times what it was (the IK step's correction aside).
 * For a jerk-limited line, arc or Cartesian path (kinctl/check.h: how
 * kinctld brings a goal whose joints' jerk the dry run finds beyond their
 * qddd_max within them). g->slowed records it (times kc_goal_share's
 * value before). KC_E_ARG for NULL, s outside (0, 1], or any other goal
 * (a joint move or joint path is planned within the joints' limits; a
 * trapezoid's jerk is unbounded by design); g is then unchanged.
 * Cycle-safe. */
kc_status kc_goal_slow(kc_goal *g, const kc_ctrl_cfg *cfg, kc_real s);

/* The share of its speed goal g runs at: g->slowed, 1 where that is 0 (a
 * goal never slowed) or g is NULL. Cycle-safe. */
kc_real kc_goal_share(const kc_goal *g);

/* 1 when goal g's motion, given to controller c, follows a jerk-limited
 * law (kinctl/scurve.h): a joint move, line, arc, Cartesian path or servo
 * twist stream whose profile (or cfg.profile) is KC_PROFILE_JERK, on a
 * chain with a jerk limit on every joint; 0 for a trapezoid, a joint path,
 * a servo pose stream, or NULL. Cycle-safe. */
int kc_ctrl_jerk_limited(const kc_ctrl *c, const kc_goal *g);

/* One tick. Cycle-safe: bounded work (planning a segment when one starts:
 * see kinctl/path.h for the cost of long paths), no allocation. */
kc_status kc_ctrl_step(kc_ctrl *ctrl, const kc_ctrl_input *in, kc_ctrl_output *out);

/* The controller's state as a scheduled goal finds it (kc_goal.take_state):
 * a 32-bit FNV-1a hash of the last setpoint's bytes (q, qd, qdd of every
 * joint), the state, and the active goal's id and the queue's length.
 * Stepping is deterministic, so a copy of the controller stepped with the
 * same inputs has the same stamp at the same cycle; any other input
 * between (a command, a goal, a servo message, a fault) changes it, but
 * for the rare hash collision (2^-32). 0 for NULL. */
uint32_t kc_ctrl_stamp(const kc_ctrl *c);

KC_END_DECLS

#endif /* KINCTL_CTRL_H */
