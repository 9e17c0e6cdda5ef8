/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/check.h - the dry run: a goal judged before it is accepted, by
 * stepping it through the controller's own step code from where it will
 * start, every tick of its motion (kinctl/ctrl.h: zones, tracking, limits).
 *
 * A kc_check is an object of its own: its storage (a scratch controller,
 * never the cycle's), the configuration it runs at (the controller's, at
 * the dry run's tick period), and where the controller's queue ends. It is
 * fed, in arrival order, the goals to judge (kc_check_goal), the goals
 * handed on to the controller (kc_check_handed), and the controller's ticks
 * (kc_check_tick); so each queued goal is checked from where the one before
 * it ends, at rest.
 * It has no globals and takes no locks: one kc_check for one thread, which
 * may be a thread of its own; the controller's ticks reach it as copies.
 *
 * A goal that replaces the others is judged from the controller's moving
 * state when the check holds a snapshot of the controller
 * (kc_check_snapshot: a copy of the whole kc_ctrl after a tick, made by
 * whoever owns the controller, into the check's scratch controller: no
 * second one) that is fresh: no tick fed since is newer, and every goal
 * handed on had been taken by it, and no tick fed is as new as the tick
 * the goal is judged for. The copy is stepped check->lead ticks of the
 * motion it holds, given the goal as the cycle gives it in the tick after
 * those, and stepped until the goal ends, at the controller's own period:
 * the verdict covers the transition the controller makes (kinctl/ctrl.h: a joint goal's retarget from (q, qd,
 * qdd), a Cartesian goal or a joint path superposed on the old motion's
 * stop, or the stop
 * first and then the goal from rest where it ends); a fault on the way
 * (a zone, a joint the IK step cannot bring along: the old motion's stop
 * included) refuses the goal; and a goal taken with the motion stopped
 * first is taken with reason KC_REASON_STOP_FIRST. The verdict schedules
 * the goal (kc_verdict.take_cycle, take_state: the tick and the state it
 * was given in; the caller copies them into the goal it hands on), and
 * the controller takes a scheduled goal in that tick from that state or
 * not at all (KC_REASON_LATE, kinctl/ctrl.h): so the verdict's ticks are
 * the controller's, and q_end where it comes to rest, to the bit. A lead
 * covers the time the caller needs to judge the goal and hand it on
 * (kinctld measures it: checker.h); a goal that reaches the controller
 * after its tick is refused, never taken from a state it was not judged
 * from. run_moving says which start the goal last judged had. Without
 * a fresh snapshot a replacing goal is judged as before the snapshot
 * existed: at rest at the latest setpoint (kc_check_tick's q), at the
 * check's period. A snapshot serves one goal: any run uses the scratch.
 *
 * A verdict (kinctl/ctrl.h kc_verdict) says what was found: KC_OK with the
 * joints where the goal ends (reason KC_REASON_STOP_FIRST when judged from
 * a snapshot and the motion it replaces stops first, else
 * KC_REASON_NONE); or the status and reason with the joint, knot
 * or field concerned, the tick and path length where the motion fails, and
 * for a zone the pair and its distance.
 *   KC_E_ARG          the goal's fields (kc_ctrl_goal_check), a plan the
 *                     planner refuses (KC_REASON_PLAN), or one the
 *                     controller would refuse when it arrives (from a
 *                     snapshot: refuses, KC_REASON_STATE in FAULT or
 *                     ESTOP, KC_REASON_DUPLICATE_ID);
 *   KC_E_UNREACHABLE  the motion faults on the way: KC_REASON_UNREACHABLE
 *                     (the tool cannot follow), KC_REASON_ZONE, ...;
 *   KC_E_CAPACITY     KC_REASON_QUEUE_FULL: the controller's queue (goals
 *                     queued at the latest tick plus those handed on since)
 *                     is full; or KC_REASON_PLAN: the motion does not end
 *                     within max_ticks (from a snapshot, within as many
 *                     seconds, in ticks of the controller's period).
 * Servo goals stream: they get kc_ctrl_goal_check alone, and end where the
 * arm is.
 *
 * The joints' jerk. A verdict of a run that stepped the motion says how
 * near its joints came to their jerk limits: kc_verdict.jerk, the largest
 * change of a joint's qdd over a tick of the run in units of its qddd_max
 * times the run's period. A joint move or a joint path is planned within
 * them; a Cartesian goal's limits are the tool's, and its joints' jerk is
 * what the arm's Jacobian makes of the tool's motion (kinctl/ctrl.h), which
 * may exceed them (a fast line, a line near a singularity, where the IK
 * step's scaling holds a joint at its acceleration limit). Such a goal, if
 * jerk-limited, can be slowed by kc_goal_slow by the factor
 * kc_check_slowing gives and judged again: the same path, its law
 * stretched in time, the joints' jerk about s^3 times what it was
 * (kinctld searches for the fastest such s, kc_check_slow below, before
 * it hands a goal on). The
 * verdict's jerk covers every tick stepped: from a snapshot, the replaced
 * motion's stop too, which slowing the goal does not change; where the
 * transition stays beyond the limits, kinctld judges the goal again with
 * stop_first (kinctl/ctrl.h: the motion stops on its path first) and
 * takes it so if that does better. A goal that stops first (ACCEPTED
 * with KC_REASON_STOP_FIRST) a motion whose law is not jerk-limited
 * (kc_ctrl_jerk_limited: a joint path, a trapezoid, a servo pose stream)
 * is judged on its own ticks: its jerk is measured from the tick it
 * starts, at rest (its first step from rest included), that motion's stop
 * being its own law's whatever the goal (judged over it, a goal beyond
 * the limits would hide behind the stop's excess, which no slowing
 * lowers). The stop of a jerk-limited motion stays in the verdict: what
 * it does beyond the limits (a Cartesian path's joints stopping on its
 * path) the goal that stops it causes; so does a stop joint by joint
 * (jerk-limited halts from the last setpoint, kinctl/ctrl.h: a joint
 * path's under a goal superposed on it), whatever the law it stops.
 * kc_verdict.jerk_own says whether the jerk is the goal's own so: 0 only
 * where the goal takes over from a motion whose law is not jerk-limited
 * superposed on that law's own stop (a trapezoid line's on its path),
 * whose excess it may then be.
 *
 * Not for the cycle: a dry run costs one controller step per tick of motion
 * (from a snapshot, per tick of the controller's period: cfg.dt over the
 * controller's dt times as many as at the check's own period).
 * It may run in slices (kc_check_begin, then kc_check_run until it
 * returns anything but KC_MORE), so that a caller with a clock can stop
 * one that takes too long; the verdict is the same as in one call.
 */
#ifndef KINCTL_CHECK_H
#define KINCTL_CHECK_H

#include <stdint.h>

#include "kinctl/ctrl.h"
#include "kinctl/decls.h"

KC_BEGIN_DECLS

/* What kc_check_slowing aims the joints' jerk at, in units of their
 * limits: below 1 because the law is not all of it (the IK step's
 * correction is not slowed with it) and a dry run at a coarser period than
 * the controller's sees a joint's jerk averaged over its longer tick. */
#define KC_CHECK_JERK_MARGIN KC_R(0.9)

/* A verdict's jerk above 1 by no more is within: the rounding of a
 * joint's jerk measured as its change of qdd over a tick. (A Cartesian
 * goal superposed on a jerk-limited joint move's stop adds the IK step's
 * correction to the stop's leading joint, braking at its jerk limit:
 * that stop is planned within 1 - 1e-5 of the limit, kinctl/ctrl.h; in
 * test_ctrl_cartstop's streams 412 of 561 verdicts on such goals were
 * between 1 and 1 + 9.9e-7 while it was planned at the whole limit, none
 * above 0.9999987 since.) */
#define KC_CHECK_JERK_SLACK KC_R(1e-6)

/* The slowing search ends once the fastest share found within the limits
 * and the slowest found over them are this close (a ratio). */
#define KC_CHECK_SLOW_CLOSE KC_R(1.05)

/* The dry runs of a slowed goal a caller of the search should allow
 * (kinctld does): enough to bracket a share within 5 % after one far too
 * slow (a cube root of a hundredfold jerk). */
#define KC_CHECK_SLOW_PASSES 5

typedef struct kc_check {
    const kc_chain *chain;
    kc_ctrl_cfg cfg;   /* the controller's, at the dry run's period */
    int64_t max_ticks; /* longest motion judged (ticks of cfg.dt) */
    kc_ctrl scratch;   /* the dry run's own controller */
    /* Where the controller's queue ends. */
    kc_real q_now[KC_MAX_JOINTS];   /* the latest setpoint (start of a replacing goal without a snapshot) */
    kc_real q_end[KC_MAX_JOINTS];   /* where the next queued goal starts */
    kc_real q_from[KC_MAX_JOINTS];  /* where the goal last judged started */
    kc_real q_start[KC_MAX_JOINTS]; /* where the last goal handed on started */
    int64_t last_id;                /* its id while the controller may still refuse it, else 0 */
    int64_t handed, taken;          /* goals handed on, and taken by the controller */
    int queue_length;               /* the controller's queue at the latest tick */
    int have_tick;
    int64_t tick_cycle;             /* the latest tick's cycle */
    /* A snapshot of the controller (kc_check_snapshot), held in scratch
     * until a replacing goal is judged from it or the scratch is needed. */
    int have_snapshot;
    int64_t snap_cycle; /* its cycle (the tick it was copied after) */
    int64_t snap_taken; /* goals handed on it had taken */
    /* The dry run under way (kc_check_begin .. kc_check_run). */
    kc_goal run_goal;     /* the goal stepped (its copy, queued behind nothing) */
    kc_ctrl_input run_in;
    int64_t run_tick;     /* ticks stepped so far */
    int64_t run_max;      /* the longest motion judged, in ticks of the run's period */
    kc_real run_progress; /* of the goal's motion when last stepped, 0..1 */
    kc_real run_qdd[KC_MAX_JOINTS]; /* the joints' qdd at the last tick stepped */
    kc_real run_jerk;               /* the verdict's jerk so far */
    kc_real run_qu;                 /* the verdict's qu so far */
    int run_stop_free;              /* the motion replaced follows no jerk-limited law (above) */
    int run_own;                    /* the run's jerk is the goal's own (kc_verdict.jerk_own) */
    int running;
    /* The run under way (or the goal last judged) started from a snapshot:
     * the controller's moving state, at the controller's period; else at
     * rest, at cfg.dt. */
    int run_moving;
    int run_stop_first; /* ... and the controller stops the motion first */
    /* Set by the caller: the ticks of the controller's period between a
     * snapshot and the tick a replacing goal judged from it is scheduled
     * for, less one (0: the tick after the snapshot; see above). */
    int64_t lead;
} kc_check;

/* Starts a dry run for chain and cfg (the controller's configuration; its
 * dt the dry run's tick, at least the controller's) with the arm at rest at
 * q0, nothing queued, judging motions of at most max_ticks ticks. chain
 * must outlive check and stay unchanged. KC_E_ARG for NULL, max_ticks < 1,
 * or what kc_ctrl_init refuses. Validates everything once: later goals
 * reuse the storage without initialising it again. */
kc_status kc_check_init(kc_check *check, const kc_chain *chain, const kc_ctrl_cfg *cfg, int64_t max_ticks,
                        const kc_real *q0);

/* Judges goal from where it will start: the snapshot or the latest
 * setpoint for a goal that replaces, the end of the queue for one that
 * waits (see above).
 * Returns verdict->status (never KC_MORE). The queue's end moves only once
 * the goal is handed on (kc_check_handed). */
kc_status kc_check_goal(kc_check *check, const kc_goal *goal, kc_verdict *verdict);

/* Judges goal started at rest at joints q_start (which may lie outside the
 * position limits: an arm a stop carried past one is judged from there),
 * as the controller would run it alone. Returns verdict->status. */
kc_status kc_check_from(kc_check *check, const kc_real *q_start, const kc_goal *goal, kc_verdict *verdict);

/* kc_check_goal in slices: judges goal as kc_check_goal does as far as
 * stepping its motion. Returns the verdict's status as kc_check_goal would
 * when that is all, else KC_MORE: call kc_check_run with the same verdict
 * until it returns anything else. A dry run under way is abandoned. */
kc_status kc_check_begin(kc_check *check, const kc_goal *goal, kc_verdict *verdict);

/* Steps the dry run under way by at most max_ticks ticks (>= 1). Returns
 * KC_MORE while it goes on (check->run_tick ticks stepped, the motion at
 * check->run_progress), else the verdict's status, then exactly what
 * kc_check_goal would have returned. KC_E_ARG with no dry run under way
 * (verdict untouched) or max_ticks < 1. */
kc_status kc_check_run(kc_check *check, int64_t max_ticks, kc_verdict *verdict);

/* The share of a Cartesian goal's speed (kc_goal_slow's s) that brings
 * its joints' jerk, v->jerk when judged as it is, within
 * KC_CHECK_JERK_MARGIN of their limits: cbrt(KC_CHECK_JERK_MARGIN /
 * v->jerk) when v->jerk > 1, else 1 (and 1 for NULL or no number). */
kc_real kc_check_slowing(const kc_verdict *v);

/* The search for the fastest share of a goal's speed (kc_goal_slow's s,
 * applied to the goal as asked) whose joints stay within their jerk
 * limits. The joints' jerk goes about as s^3 while the IK step follows the
 * law; where it holds a joint at its acceleration limit, it steps qdd far
 * beyond that (a PUMA 560 line: 112 x qddd_max), and kc_check_slowing's
 * cube root then slows much more than needed (to 0.2 where 0.75 does). So
 * the search brackets the share: s_ok, the fastest judged within the
 * limits (0 until one is), and s_over, the slowest judged over them; the
 * next share is kc_check_slowing's from the last verdict while none is
 * within (its square root instead where the jerk came down about as s^2
 * from the share judged before, between s^1.5 and s^2.5: an acceleration
 * step, such as a cubic spline's at its start, goes as s^2), then the
 * estimate from s_ok's verdict, or the bracket's geometric middle where
 * that estimate is not inside it; done when the bracket, or the
 * estimate's gain over s_ok, is within KC_CHECK_SLOW_CLOSE, or when, none
 * being within, slowing left the jerk at the least judged (rounding
 * apart: what exceeds the limits is not the goal's law, the stop of a
 * replaced trapezoid, say). Where a share is judged over the least (an
 * acceleration step's jerk depends on where it falls on the ticks), the
 * next is that verdict's square root. */
typedef struct kc_check_slow {
    kc_real s;      /* the share to judge next (0: done) */
    kc_real s_ok;   /* fastest share judged within the limits, 0: none yet */
    kc_real jerk_ok;
    kc_real s_over; /* slowest share judged over them */
    kc_real jerk_best; /* lowest jerk judged while none is within */
    kc_real s_best;    /* its share */
} kc_check_slow;

/* 1 when verdict v's jerk is within the joints' limits (rounding apart). */
int kc_check_jerk_within(const kc_verdict *v);

/* Starts the search from verdict v of the goal as asked; 0 when it is
 * within the limits (nothing to search: ss->s = 0), else 1 with ss->s the
 * first share to judge. */
int kc_check_slow_start(kc_check_slow *ss, const kc_verdict *v);

/* Takes the verdict v of the goal slowed by ss->s (taken: status KC_OK).
 * Returns 1 when that is the best judged so far (the fastest within the
 * limits, or, while none is, the lowest jerk), else 0; sets ss->s to the
 * next share to judge, or 0 when the search is done. */
int kc_check_slow_next(kc_check_slow *ss, const kc_verdict *v);

/* The goal last judged by kc_check_goal (or begin and run), taken (verdict KC_OK), was handed
 * to the controller: the queue now ends where it ends. */
void kc_check_handed(kc_check *check, const kc_goal *goal, const kc_verdict *verdict);

/* The controller ctrl (the same chain, initialised; any period) as it
 * stands after its tick ctrl->cycle, having taken goals_taken of the goals
 * handed on (as kc_check_tick counts them): copied into the scratch
 * controller, for the next replacing goal (see above). ctrl may be the
 * slot (kc_check_snapshot_slot) the owner copied it into: then nothing is
 * copied again. A dry run under way is abandoned. KC_E_ARG for NULL or
 * another chain: no snapshot is held then. Not for the cycle: it copies
 * sizeof(kc_ctrl) bytes (the owner's own copy into the slot is the
 * cheaper way for it). */
kc_status kc_check_snapshot(kc_check *check, const kc_ctrl *ctrl, int64_t goals_taken);

/* Where the controller's owner may copy it (memcpy of the whole kc_ctrl,
 * from any thread while the check's own thread waits for it), before
 * kc_check_snapshot(check, slot, goals_taken): the scratch controller.
 * Drops the snapshot held and a dry run under way. NULL for NULL. */
kc_ctrl *kc_check_snapshot_slot(kc_check *check);

/* 1 when the snapshot held is fresh (see above): the next replacing goal
 * is judged from it; 0 when it would be judged from rest. */
int kc_check_snapshot_fresh(const kc_check *check);

/* A tick of the controller: its output, and goals_taken, how many goals
 * handed on the controller has been given so far. A goal it refused gives
 * the queue's end back; at rest with nothing queued or on its way, the
 * queue ends where the arm is. */
void kc_check_tick(kc_check *check, const kc_ctrl_output *out, int64_t goals_taken);

KC_END_DECLS

#endif /* KINCTL_CHECK_H */
