/* SPDX-License-Identifier: BSD-3-Clause */
/* test_check_moving.c - a replacing goal judged from the controller's
 * moving state (kinctl/check.h kc_check_snapshot): a joint goal whose
 * retarget from a fast waist sweep overshoots into a zone is refused,
 * though the same goal from rest at the same joints passes by it; a
 * replacement that is fine is taken, and the verdict's ticks and end
 * joints are where the real controller, given the goal in the next tick,
 * comes to rest, to the bit: a jerk-limited retarget, a line superposed on
 * a joint move's stop or on a servo stream's halt, a joint path superposed
 * on a joint move's stop in joint space, a line replacing a
 * trapezoid joint move and a joint
 * goal whose retarget would carry the waist past its limit (both stop
 * first: the verdict says so, as the controller's ACCEPTED does). A
 * snapshot older than the latest tick, or one that has not seen every goal
 * handed on, is not used: the goal is judged from rest. */
#include <math.h>
#include <string.h>

#include "testutil.h"

static kc_chain CHAIN;
static kc_ctrl_cfg CFG;
static kc_zone_set ZONES;
static kc_check CHECK;
static kc_ctrl CTRL, PROBE;

/* Ticks of the waist sweep before the replacement: joint 0 then moves at
 * about its top speed, far from both ends of the sweep. */
#define SWEEP_TICKS 700

static void setup(void)
{
    assert_int_equal(kc_chain_init_model(&CHAIN, KC_MODEL_PUMA560, NULL), KC_OK);
    kc_zone_set_init(&ZONES);
    CFG = kc_ctrl_cfg_default();
    CFG.zones = NULL;
}

static kc_goal joint_goal(int64_t id, const kc_real *q)
{
    kc_goal g = kt_joint_goal(id, q, 6);
    g.dim = 6;
    return g;
}

/* The sweep the replacement interrupts: the waist from -0.8 to 0.8 rad,
 * both shifted by shift. */
static kc_goal sweep_goal(int64_t id, kc_real shift)
{
    kc_real qb[6];
    memcpy(qb, KT_PUMA_Q0, sizeof qb);
    qb[0] = KC_R(0.8) + shift;
    return joint_goal(id, qb);
}

static void sweep_start(kc_real *qa, kc_real shift)
{
    memcpy(qa, KT_PUMA_Q0, sizeof(kc_real) * 6);
    qa[0] = KC_R(-0.8) + shift;
}

/* One tick of c with goal g (or none), fed to the check as the daemon
 * does; goals counts the goals given. */
static void step(kc_ctrl *c, const kc_goal *g, int64_t *goals, kc_ctrl_output *out)
{
    kc_ctrl_input in = {g, KC_CMD_NONE, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(c, &in, out), KC_OK);
    if (g != NULL)
        (*goals)++;
}

/* The first end of goal id among out's events (COMPLETED, ABORTED,
 * REJECTED, FAULT), or 0. */
static kc_ctrl_event_kind end_of(const kc_ctrl_output *out, int64_t id, kc_ctrl_reason *reason)
{
    for (int e = 0; e < out->n_events; e++) {
        const kc_ctrl_event *ev = &out->events[e];
        if (ev->kind == KC_EVENT_FAULT || (ev->goal_id == id && (ev->kind == KC_EVENT_COMPLETED ||
                                                                 ev->kind == KC_EVENT_ABORTED ||
                                                                 ev->kind == KC_EVENT_REJECTED))) {
            *reason = ev->reason;
            return ev->kind;
        }
    }
    return (kc_ctrl_event_kind)0;
}

/* The real controller c given g in its next tick, stepped until g ends:
 * the end event, its reason, the tick of it (1: the tick g was given) and
 * the reason of g's ACCEPTED. */
typedef struct run_end {
    kc_ctrl_event_kind kind;
    kc_ctrl_reason reason, accepted;
    int64_t tick;
} run_end;

static run_end run_to_end(kc_ctrl *c, const kc_goal *g)
{
    run_end r = {(kc_ctrl_event_kind)0, KC_REASON_NONE, KC_REASON_COUNT, 0};
    kc_ctrl_output out;
    int64_t goals = 0;
    for (int64_t k = 1; k <= 100000 && r.kind == 0; k++) {
        step(c, k == 1 ? g : NULL, &goals, &out);
        for (int e = 0; e < out.n_events; e++)
            if (out.events[e].goal_id == g->id && out.events[e].kind == KC_EVENT_ACCEPTED)
                r.accepted = out.events[e].reason;
        r.kind = end_of(&out, g->id, &r.reason);
        r.tick = k;
    }
    return r;
}

/* CTRL and CHECK set up at the sweep's start with CFG, the sweep (shifted
 * by shift, with motion law profile) judged, handed on, given and stepped
 * SWEEP_TICKS ticks, each fed to the check; then the snapshot. */
static void sweep_profile_then_snapshot(kc_goal_profile profile, kc_real shift)
{
    kc_real qa[6];
    sweep_start(qa, shift);
    assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &CFG, qa), KC_OK);
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, qa), KC_OK);
    kc_goal sweep = sweep_goal(1, shift);
    sweep.profile = profile;
    kc_verdict v;
    assert_int_equal(kc_check_goal(&CHECK, &sweep, &v), KC_OK);
    kc_check_handed(&CHECK, &sweep, &v);
    int64_t goals = 0;
    kc_ctrl_output out;
    for (int k = 0; k < SWEEP_TICKS; k++) {
        step(&CTRL, k == 0 ? &sweep : NULL, &goals, &out);
        assert_int_equal(out.state, KC_CTRL_MOVING);
        kc_check_tick(&CHECK, &out, goals);
    }
    assert_int_equal(kc_check_snapshot(&CHECK, &CTRL, goals), KC_OK);
}

/* CTRL and CHECK set up at KT_PUMA_Q0 with CFG, a servo stream (its
 * target moving at 0.1 m/s along (1, 1, 1)/sqrt(3)) judged, handed on and
 * streamed for 400 ticks, each fed to the check; then the snapshot. */
static void servo_then_snapshot(void)
{
    assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &CFG, KT_PUMA_Q0), KC_OK);
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, KT_PUMA_Q0), KC_OK);
    kc_goal s;
    memset(&s, 0, sizeof s);
    s.id = 1;
    s.kind = KC_GOAL_SERVO;
    s.vel_scale = s.acc_scale = KC_R(1.0);
    s.servo_twist = 1;
    for (int i = 0; i < 3; i++)
        s.twist[i] = KC_R(0.1) / kc_sqrt(KC_R(3.0));
    kc_verdict v;
    assert_int_equal(kc_check_goal(&CHECK, &s, &v), KC_OK);
    kc_check_handed(&CHECK, &s, &v);
    int64_t goals = 0;
    kc_ctrl_output out;
    for (int k = 0; k < 400; k++) {
        /* the stream's messages after the first are one goal: not counted */
        kc_ctrl_input in = {&s, KC_CMD_NONE, 0, KC_REASON_NONE};
        assert_int_equal(kc_ctrl_step(&CTRL, &in, &out), KC_OK);
        goals = 1;
        assert_int_equal(out.state, KC_CTRL_MOVING);
        kc_check_tick(&CHECK, &out, goals);
    }
    assert_int_equal(kc_check_snapshot(&CHECK, &CTRL, goals), KC_OK);
}

static void sweep_then_snapshot(void)
{
    sweep_profile_then_snapshot(KC_GOAL_PROFILE_CFG, KC_R(0.0));
}

/* The replacement: the waist back to where it is at the snapshot, the
 * elbow opened by 0.9 rad. From rest the arm opens in place; from the
 * sweep the waist overshoots forward while the elbow opens. */
static kc_goal reach_goal(int64_t id, const kc_real *q_snap)
{
    kc_real q[6];
    memcpy(q, KT_PUMA_Q0, sizeof q);
    q[0] = q_snap[0];
    q[2] = KT_PUMA_Q0[2] + KC_R(0.9);
    return joint_goal(id, q);
}

/* The zone: a sphere of radius r at the tool point of the retarget
 * (found on a controller without zones) on the first tick the elbow has
 * opened 0.6 rad, while the waist is still well past where it is to
 * return: a place the sweep passes with the elbow closed, and the move
 * from rest never reaches. */
static kc_shape overshoot_zone(kc_real r)
{
    CFG.zones = NULL;
    sweep_then_snapshot();
    kc_real q_snap[6];
    memcpy(q_snap, CTRL.q, sizeof q_snap);
    assert_true(CTRL.qd[0] > KC_R(0.5)); /* moving fast */
    PROBE = CTRL;
    kc_goal g = reach_goal(2, q_snap);
    kc_ctrl_output out;
    int64_t goals = 0;
    kc_real at_q[6];
    memcpy(at_q, q_snap, sizeof at_q);
    for (int k = 0; k < 100000 && at_q[2] < q_snap[2] + KC_R(0.6); k++) {
        step(&PROBE, k == 0 ? &g : NULL, &goals, &out);
        memcpy(at_q, out.q, sizeof at_q);
    }
    /* a retarget, not a stop first: the waist goes on past q_snap */
    assert_true(at_q[0] > q_snap[0] + KC_R(0.2));
    kc_pose at;
    kc_fk_eval(&CHAIN, at_q, &at);
    kc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = KC_SHAPE_SPHERE;
    kc_pose_identity(&s.pose);
    s.pose.t = at.t;
    s.dim[0] = r;
    return s;
}

/* A replacement whose moving transition enters a zone is refused, though
 * from rest at the same joints it passes, and the sweep alone passes too;
 * the verdict names the tick where the real controller faults. */
static void test_overshoot_into_zone(void **state)
{
    (void)state;
    setup();
    kc_shape s = overshoot_zone(KC_R(0.03));
    assert_int_equal(kc_zone_set_add(&ZONES, &s), KC_OK);
    CFG.zones = &ZONES;
    kc_real qa[6];
    sweep_start(qa, KC_R(0.0));
    kc_verdict v;
    /* the sweep alone keeps out of the zone */
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, qa), KC_OK);
    kc_goal sweep = sweep_goal(1, KC_R(0.0));
    assert_int_equal(kc_check_from(&CHECK, qa, &sweep, &v), KC_OK);

    sweep_then_snapshot();
    kc_real q_snap[6];
    memcpy(q_snap, CTRL.q, sizeof q_snap);
    kc_goal g = reach_goal(2, q_snap);
    g.replace = 1;
    assert_int_equal(kc_check_goal(&CHECK, &g, &v), KC_E_UNREACHABLE);
    assert_int_equal(CHECK.run_moving, 1);
    assert_int_equal(v.reason, KC_REASON_ZONE);
    assert_int_equal(v.zone, 0);
    assert_true(v.distance < ZONES.margin);
    for (int j = 0; j < 6; j++)
        assert_true(CHECK.q_from[j] == q_snap[j]);

    /* the real controller, given it in the next tick, faults on that tick */
    PROBE = CTRL;
    run_end r = run_to_end(&PROBE, &g);
    assert_int_equal(r.kind, KC_EVENT_FAULT);
    assert_int_equal(r.reason, KC_REASON_ZONE);
    assert_int_equal(r.accepted, KC_REASON_NONE); /* taken over moving, not stopped first */
    assert_int_equal(r.tick, v.tick);

    /* the same goal from rest at q_snap: the arm opens in place, clear */
    kc_verdict rest;
    assert_int_equal(kc_check_from(&CHECK, q_snap, &g, &rest), KC_OK);
    assert_int_equal(CHECK.run_moving, 0);
    for (int j = 0; j < 6; j++)
        assert_true(rest.q_end[j] == g.q[j]);

    /* the snapshot is used up: the goal again is judged from rest at the
     * latest setpoint, as before snapshots */
    assert_int_equal(kc_check_goal(&CHECK, &g, &v), KC_OK);
    assert_int_equal(CHECK.run_moving, 0);
}

/* A replacement fine from the moving state is taken: its verdict's tick
 * and end joints are the real controller's, to the bit. Returns the
 * verdict's tick. */
static int64_t assert_as_controller(const kc_goal *g, kc_ctrl_reason accepted)
{
    kc_verdict v;
    assert_int_equal(kc_check_goal(&CHECK, g, &v), KC_OK);
    assert_int_equal(CHECK.run_moving, 1);
    assert_int_equal(v.reason, accepted);
    PROBE = CTRL;
    run_end r = run_to_end(&PROBE, g);
    assert_int_equal(r.kind, KC_EVENT_COMPLETED);
    assert_int_equal(r.accepted, accepted);
    assert_int_equal(r.tick, v.tick);
    for (int j = 0; j < 6; j++)
        assert_memory_equal(&v.q_end[j], &PROBE.q[j], sizeof(kc_real));
    return v.tick;
}

static void test_taken_as_controller(void **state)
{
    (void)state;
    setup();
    /* a jerk-limited retarget (no zone in the way) */
    sweep_then_snapshot();
    kc_real q_snap[6];
    memcpy(q_snap, CTRL.q, sizeof q_snap);
    kc_goal g = reach_goal(2, q_snap);
    g.replace = 1;
    int64_t ticks = assert_as_controller(&g, KC_REASON_NONE);
    /* not the rest judgement's motion: the retarget brakes the waist,
     * overshoots and comes back, longer than the move from rest */
    assert_int_equal(kc_ctrl_init(&PROBE, &CHAIN, &CFG, q_snap), KC_OK);
    run_end rest = run_to_end(&PROBE, &g);
    assert_int_equal(rest.kind, KC_EVENT_COMPLETED);
    assert_true(ticks > rest.tick + 100);

    /* a line superposed on the sweep's stop */
    sweep_then_snapshot();
    kc_pose to = CTRL.pose;
    to.t.v[2] += KC_R(0.1);
    g = kt_line_goal(3, &to);
    g.replace = 1;
    int64_t over = assert_as_controller(&g, KC_REASON_NONE);
    /* ... and the same line with stop_first: the sweep stops on its line
     * first, and the line starts from rest there, later */
    sweep_then_snapshot();
    g.stop_first = 1;
    assert_true(assert_as_controller(&g, KC_REASON_STOP_FIRST) > over);
    /* a joint goal with stop_first: no retarget, the sweep stops first */
    sweep_then_snapshot();
    g = reach_goal(8, CTRL.q);
    g.replace = 1;
    g.stop_first = 1;
    assert_as_controller(&g, KC_REASON_STOP_FIRST);

    /* a line superposed on a servo stream's halt (not stopped first) */
    servo_then_snapshot();
    kc_real speed = KC_R(0.0);
    for (int j = 0; j < 6; j++)
        speed += kc_fabs(CTRL.qd[j]);
    assert_true(CTRL.goal.kind == KC_GOAL_SERVO && speed > KC_R(0.05));
    to = CTRL.pose;
    to.t.v[2] += KC_R(0.05);
    g = kt_line_goal(6, &to);
    g.replace = 1;
    assert_as_controller(&g, KC_REASON_NONE);

    /* a joint path superposed on the sweep's stop, in joint space */
    sweep_then_snapshot();
    memset(&g, 0, sizeof g);
    g.id = 7;
    g.kind = KC_GOAL_PATH;
    g.replace = 1;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.method = KC_PATH_QUINTIC;
    g.n_points = 2;
    for (int j = 0; j < 6; j++) {
        g.points[0][j] = CTRL.q[j] + KC_R(0.1);
        g.points[1][j] = CTRL.q[j] + KC_R(0.2);
    }
    g.dim = 6;
    assert_as_controller(&g, KC_REASON_NONE);

    /* a line replacing a trapezoid joint move: the move stops first */
    sweep_profile_then_snapshot(KC_GOAL_PROFILE_TRAPEZOID, KC_R(0.0));
    to = CTRL.pose;
    to.t.v[2] += KC_R(0.1);
    g = kt_line_goal(4, &to);
    g.replace = 1;
    assert_as_controller(&g, KC_REASON_STOP_FIRST);

    /* a joint goal whose retarget would carry the waist past its limit:
     * the sweep ends at the limit, and the goal, back behind the waist at
     * 0.3 of its acceleration, would brake the waist at 1.5 rad/s^2 from
     * 2 rad/s (1.3 rad) where the sweep needs 0.5 rad: it stops first */
    sweep_profile_then_snapshot(KC_GOAL_PROFILE_CFG, KC_R(1.99));
    assert_true(CTRL.qd[0] > KC_R(1.9));
    assert_true(CTRL.q[0] + KC_R(1.3) > CHAIN.joints[0].limits.q_max);
    kc_real back[6];
    memcpy(back, CTRL.q, sizeof back);
    back[0] = CTRL.q[0] - KC_R(0.5);
    g = joint_goal(5, back);
    g.acc_scale = KC_R(0.3);
    g.replace = 1;
    assert_as_controller(&g, KC_REASON_STOP_FIRST);
    for (int j = 0; j < 6; j++)
        assert_true(PROBE.q[j] == back[j]);
}

/* The copy the controller's owner makes into the slot is the snapshot;
 * judged in slices, the verdict is the same. */
static void test_snapshot_slot(void **state)
{
    (void)state;
    setup();
    sweep_then_snapshot();
    kc_goal g = reach_goal(2, CTRL.q);
    g.replace = 1;
    kc_verdict a, b;
    assert_int_equal(kc_check_goal(&CHECK, &g, &a), KC_OK);
    kc_ctrl *slot = kc_check_snapshot_slot(&CHECK);
    assert_non_null(slot);
    memcpy(slot, &CTRL, sizeof CTRL);
    assert_int_equal(kc_check_snapshot(&CHECK, slot, 1), KC_OK);
    assert_int_equal(kc_check_goal(&CHECK, &g, &b), KC_OK);
    assert_int_equal(CHECK.run_moving, 1);
    assert_int_equal(a.tick, b.tick);
    assert_memory_equal(a.q_end, b.q_end, sizeof(kc_real) * 6);
    /* in slices, as kinctld runs it: the same verdict */
    assert_int_equal(kc_check_snapshot(&CHECK, &CTRL, 1), KC_OK);
    kc_status st = kc_check_begin(&CHECK, &g, &b);
    int calls = 0;
    while (st == KC_MORE) {
        st = kc_check_run(&CHECK, 13, &b);
        calls++;
    }
    assert_int_equal(st, KC_OK);
    assert_int_equal(CHECK.run_moving, 1);
    assert_int_equal(calls, (a.tick + 12) / 13);
    assert_int_equal(a.tick, b.tick);
    assert_memory_equal(a.q_end, b.q_end, sizeof(kc_real) * 6);
    /* another chain's controller is no snapshot */
    kc_chain other = CHAIN;
    PROBE = CTRL;
    PROBE.chain = &other;
    assert_int_equal(kc_check_snapshot(&CHECK, &PROBE, 1), KC_E_ARG);
    assert_int_equal(kc_check_goal(&CHECK, &g, &b), KC_OK);
    assert_int_equal(CHECK.run_moving, 0);
    assert_int_equal(kc_check_snapshot(NULL, &CTRL, 1), KC_E_ARG);
    assert_int_equal(kc_check_snapshot(&CHECK, NULL, 1), KC_E_ARG);
}

/* A snapshot older than the latest tick, or one taken before a goal handed
 * on reached the controller, is not the state the goal will find: the goal
 * is judged from rest at the latest setpoint. A queued goal never uses it. */
static void test_stale_snapshot(void **state)
{
    (void)state;
    setup();
    sweep_then_snapshot();
    kc_goal g = reach_goal(2, CTRL.q);
    g.replace = 1;
    kc_verdict v;
    int64_t goals = 1;
    kc_ctrl_output out;
    assert_int_equal(kc_check_snapshot_fresh(&CHECK), 1);
    step(&CTRL, NULL, &goals, &out);
    kc_check_tick(&CHECK, &out, goals);
    assert_int_equal(kc_check_snapshot_fresh(&CHECK), 0);
    assert_int_equal(kc_check_goal(&CHECK, &g, &v), KC_OK);
    assert_int_equal(CHECK.run_moving, 0);
    for (int j = 0; j < 6; j++)
        assert_true(CHECK.q_from[j] == out.q[j]);

    /* a goal handed on and not yet taken */
    assert_int_equal(kc_check_snapshot(&CHECK, &CTRL, goals), KC_OK);
    kc_goal more = joint_goal(5, KT_PUMA_Q0);
    assert_int_equal(kc_check_goal(&CHECK, &more, &v), KC_OK);
    assert_int_equal(CHECK.run_moving, 0); /* queued: from the queue's end */
    assert_int_equal(kc_check_snapshot(&CHECK, &CTRL, goals), KC_OK);
    kc_check_handed(&CHECK, &more, &v);
    assert_int_equal(kc_check_snapshot_fresh(&CHECK), 0);
    assert_int_equal(kc_check_goal(&CHECK, &g, &v), KC_OK);
    assert_int_equal(CHECK.run_moving, 0);
    /* once it is taken, a new snapshot is fresh */
    step(&CTRL, &more, &goals, &out);
    kc_check_tick(&CHECK, &out, goals);
    assert_int_equal(kc_check_snapshot(&CHECK, &CTRL, goals), KC_OK);
    assert_int_equal(kc_check_goal(&CHECK, &g, &v), KC_OK);
    assert_int_equal(CHECK.run_moving, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_overshoot_into_zone),
        cmocka_unit_test(test_taken_as_controller),
        cmocka_unit_test(test_snapshot_slot),
        cmocka_unit_test(test_stale_snapshot),
    };
    int failed = cmocka_run_group_tests_name("check_moving (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("check_moving");
    return failed;
}
