/* SPDX-License-Identifier: BSD-3-Clause */
/* test_check_schedule.c - the scheduled takeover (kinctl/check.h,
 * kc_check.lead; kinctl/ctrl.h kc_goal.take_cycle): a replacing goal
 * judged from a snapshot for a tick lead ticks after it is taken by the
 * real controller in exactly that tick, along the transition the dry run
 * stepped: the same ticks, end joints and joints' jerk, to the bit; given
 * a tick early or late, or after a command changed the state, it is
 * refused (KC_REASON_LATE) and the motion it would replace goes on. A
 * snapshot stays fresh until a tick as new as the goal's is fed. Random
 * PUMA 560 lines and arcs replacing moving joint moves at random leads:
 * every verdict is the controller's. */
#include <math.h>
#include <string.h>

#include "testutil.h"

static kc_chain CHAIN;
static kc_ctrl_cfg CFG;
static kc_check CHECK;
static kc_ctrl CTRL, PROBE;

/* Cases of the random test, and the fewest of them that must be taken. */
#define CASES 100
#define TAKEN_MIN 20

static void setup(void)
{
    assert_int_equal(kc_chain_init_model(&CHAIN, KC_MODEL_PUMA560, NULL), KC_OK);
    CFG = kc_ctrl_cfg_default();
    CFG.zones = NULL;
}

static void step(kc_ctrl *c, const kc_goal *g, kc_ctrl_command cmd, kc_ctrl_output *out)
{
    kc_ctrl_input in = {g, cmd, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(c, &in, out), KC_OK);
}

/* CTRL and CHECK at rest at q0, the joint move to q1 judged, handed on,
 * given and stepped ticks ticks, each fed to the check; then the
 * snapshot. 1 when the arm still moves then. */
static int move_then_snapshot(const kc_real *q0, const kc_real *q1, int ticks)
{
    assert_int_equal(kc_ctrl_init(&CTRL, &CHAIN, &CFG, q0), KC_OK);
    assert_int_equal(kc_check_init(&CHECK, &CHAIN, &CFG, 100000, q0), KC_OK);
    kc_goal move = kt_joint_goal(1, q1, 6);
    kc_verdict v;
    assert_int_equal(kc_check_goal(&CHECK, &move, &v), KC_OK);
    kc_check_handed(&CHECK, &move, &v);
    kc_ctrl_output out;
    for (int k = 0; k < ticks; k++) {
        step(&CTRL, k == 0 ? &move : NULL, KC_CMD_NONE, &out);
        kc_check_tick(&CHECK, &out, 1);
    }
    assert_int_equal(kc_check_snapshot(&CHECK, &CTRL, 1), KC_OK);
    return CTRL.state == KC_CTRL_MOVING;
}

/* The waist swept from -0.8 to 0.8 rad, 700 ticks in: at about its top
 * speed. */
static void sweep_then_snapshot(void)
{
    kc_real qa[6], qb[6];
    memcpy(qa, KT_PUMA_Q0, sizeof qa);
    memcpy(qb, KT_PUMA_Q0, sizeof qb);
    qa[0] = KC_R(-0.8);
    qb[0] = KC_R(0.8);
    assert_int_equal(move_then_snapshot(qa, qb, 700), 1);
}

/* The replacing line: 10 cm up from the tool at the snapshot. */
static kc_goal lift_goal(int64_t id)
{
    kc_pose to = CTRL.pose;
    to.t.v[2] += KC_R(0.1);
    kc_goal g = kt_line_goal(id, &to);
    g.replace = 1;
    return g;
}

/* Judged from rest (no fresh snapshot): not scheduled. */
static void assert_judged_from_rest(const kc_goal *g)
{
    kc_verdict v;
    assert_int_equal(kc_check_goal(&CHECK, g, &v), KC_OK);
    assert_int_equal(CHECK.run_moving, 0);
    assert_int_equal(v.take_cycle, 0);
}

/* The first event of kind for goal id in out, or NULL. */
static const kc_ctrl_event *event(const kc_ctrl_output *out, kc_ctrl_event_kind kind, int64_t id)
{
    for (int e = 0; e < out->n_events; e++)
        if (out->events[e].kind == kind && out->events[e].goal_id == id)
            return &out->events[e];
    return NULL;
}

/* PROBE, a copy of CTRL stepped lead ticks with no input, given g in the
 * next and stepped until g ends: asserts the verdict v is what it does
 * (ACCEPTED with v's reason, COMPLETED at v's tick, v's end joints and
 * joints' jerk, to the bit). */
static void assert_taken_as_judged(const kc_goal *g, const kc_verdict *v, int64_t lead)
{
    kc_ctrl_output out;
    PROBE = CTRL;
    for (int64_t t = 0; t < lead; t++)
        step(&PROBE, NULL, KC_CMD_NONE, &out);
    assert_int_equal(PROBE.cycle + 1, v->take_cycle);
    assert_int_equal(kc_ctrl_stamp(&PROBE), v->take_state);
    kc_real qdd[KC_MAX_JOINTS], jerk = KC_R(0.0);
    memcpy(qdd, PROBE.qdd, sizeof qdd);
    int64_t tick = 0;
    const kc_ctrl_event *end = NULL;
    while (end == NULL && tick < 200000) {
        step(&PROBE, tick == 0 ? g : NULL, KC_CMD_NONE, &out);
        tick++;
        if (tick == 1) {
            const kc_ctrl_event *acc = event(&out, KC_EVENT_ACCEPTED, g->id);
            assert_non_null(acc);
            assert_int_equal(acc->reason, v->reason);
        }
        for (int j = 0; j < 6; j++) {
            kc_real r = kc_fabs(out.qdd[j] - qdd[j]) / (CHAIN.joints[j].limits.qddd_max * PROBE.cfg.dt);
            if (r > jerk)
                jerk = r;
            qdd[j] = out.qdd[j];
        }
        assert_null(event(&out, KC_EVENT_FAULT, g->id));
        end = event(&out, KC_EVENT_COMPLETED, g->id);
    }
    assert_non_null(end);
    assert_int_equal(tick, v->tick);
    assert_memory_equal(&jerk, &v->jerk, sizeof jerk);
    for (int j = 0; j < 6; j++)
        assert_memory_equal(&PROBE.q[j], &v->q_end[j], sizeof(kc_real));
}

/* PROBE, a copy of CTRL stepped ticks ticks (with cmd in the first of
 * them), given g in the next: refused as late, the sweep going on. */
static void assert_refused_late(const kc_goal *g, int64_t ticks, kc_ctrl_command cmd)
{
    kc_ctrl_output out;
    PROBE = CTRL;
    for (int64_t t = 0; t < ticks; t++)
        step(&PROBE, NULL, t == 0 ? cmd : KC_CMD_NONE, &out);
    step(&PROBE, g, KC_CMD_NONE, &out);
    const kc_ctrl_event *rej = event(&out, KC_EVENT_REJECTED, g->id);
    assert_non_null(rej);
    assert_int_equal(rej->reason, KC_REASON_LATE);
    assert_null(event(&out, KC_EVENT_ACCEPTED, g->id));
    assert_int_equal(out.goal_id, 1);
    assert_int_equal(out.state, cmd == KC_CMD_NONE ? KC_CTRL_MOVING : KC_CTRL_STOPPING);
}

static void test_taken_in_its_tick(void **state)
{
    (void)state;
    setup();
    sweep_then_snapshot();
    CHECK.lead = 37;
    kc_goal g = lift_goal(2);
    kc_verdict v;
    assert_int_equal(kc_check_goal(&CHECK, &g, &v), KC_OK);
    assert_int_equal(CHECK.run_moving, 1);
    assert_int_equal(v.take_cycle, CTRL.cycle + 38);
    kc_goal unscheduled = g;
    g.take_cycle = v.take_cycle;
    g.take_state = v.take_state;
    assert_taken_as_judged(&g, &v, 37);

    /* a tick early, a tick late, or after a STOP: refused */
    assert_refused_late(&g, 36, KC_CMD_NONE);
    assert_refused_late(&g, 38, KC_CMD_NONE);
    assert_refused_late(&g, 37, KC_CMD_STOP);
    /* the wrong state in the right tick */
    kc_goal wrong = g;
    wrong.take_state ^= 1u;
    assert_refused_late(&wrong, 37, KC_CMD_NONE);
    /* unscheduled, it is taken whenever it comes (the transition of that
     * tick: not the one judged) */
    kc_ctrl_output out;
    PROBE = CTRL;
    step(&PROBE, &unscheduled, KC_CMD_NONE, &out);
    assert_non_null(event(&out, KC_EVENT_ACCEPTED, 2));

    /* lead 0: the tick after the snapshot, as before the lead */
    sweep_then_snapshot();
    assert_int_equal(kc_check_goal(&CHECK, &unscheduled, &v), KC_OK);
    assert_int_equal(v.take_cycle, CTRL.cycle + 1);
    g = unscheduled;
    g.take_cycle = v.take_cycle;
    g.take_state = v.take_state;
    assert_taken_as_judged(&g, &v, 0);

    /* the snapshot used up: judged from rest, not scheduled */
    assert_judged_from_rest(&unscheduled);
}

/* The snapshot serves a goal judged for lead ticks after it until a tick
 * as new as that goal's is fed. */
static void test_fresh_until_its_tick(void **state)
{
    (void)state;
    setup();
    sweep_then_snapshot();
    CHECK.lead = 20;
    kc_ctrl_output out;
    PROBE = CTRL;
    for (int t = 0; t < 20; t++) {
        step(&PROBE, NULL, KC_CMD_NONE, &out);
        kc_check_tick(&CHECK, &out, 1);
    }
    assert_int_equal(kc_check_snapshot_fresh(&CHECK), 1);
    step(&PROBE, NULL, KC_CMD_NONE, &out);
    kc_check_tick(&CHECK, &out, 1);
    assert_int_equal(kc_check_snapshot_fresh(&CHECK), 0);
    kc_goal g = lift_goal(2);
    assert_judged_from_rest(&g);
}

/* Random lines and arcs (kt_cart_goal, at the default and at fast
 * limits) replacing random joint moves of the PUMA 560 at random moments,
 * judged for random leads of 0 to 30 ticks: each one taken is the
 * controller's transition, to the bit. */
static void test_random_replacements(void **state)
{
    (void)state;
    setup();
    kt_rng rng = kt_rng_make(0x5C4ED);
    int taken = 0, moving = 0, within = 0;
    for (int c = 0; c < CASES; c++) {
        kc_real q1[6];
        kt_rand_q(&rng, &CHAIN, q1);
        for (int j = 0; j < 6; j++) /* within reach of the start: a joint move of up to 1 rad a joint */
            q1[j] = KT_PUMA_Q0[j] + KC_R(0.5) * (q1[j] - KT_PUMA_Q0[j]) /
                                        kc_max(KC_R(1.0), CHAIN.joints[j].limits.q_max - CHAIN.joints[j].limits.q_min);
        int ticks = (int)kt_uniform(&rng, 20.0, 600.0);
        int64_t lead = (int64_t)kt_uniform(&rng, 0.0, 31.0);
        if (!move_then_snapshot(KT_PUMA_Q0, q1, ticks))
            continue;
        moving++;
        CHECK.lead = lead;
        kc_goal g = kt_cart_goal(&rng, 100 + c, &CTRL.pose, c % 2, c % 4 >= 2);
        g.replace = 1;
        kc_verdict v;
        if (kc_check_goal(&CHECK, &g, &v) != KC_OK)
            continue; /* the arm cannot follow it from there: refused, as kinctld would */
        assert_int_equal(CHECK.run_moving, 1);
        assert_int_equal(v.take_cycle, CTRL.cycle + lead + 1);
        g.take_cycle = v.take_cycle;
        g.take_state = v.take_state;
        assert_taken_as_judged(&g, &v, lead);
        taken++;
        within += kc_check_jerk_within(&v);
    }
    print_message("%d of %d cases moving at the snapshot, %d taken as judged, %d of them within the jerk limits\n",
                  moving, CASES, taken, within);
    assert_true(taken >= TAKEN_MIN);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_taken_in_its_tick),
        cmocka_unit_test(test_fresh_until_its_tick),
        cmocka_unit_test(test_random_replacements),
    };
    int failed = cmocka_run_group_tests_name("check_schedule (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("check_schedule");
    return failed;
}
