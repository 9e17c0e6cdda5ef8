/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_zone.c - forbidden zones in the controller (kinctl/ctrl.h):
 * the planning-time dry run rejects goals that cross a zone and accepts
 * ones that pass near it; kc_ctrl_step stops the arm on a violation and
 * names the pair; a servo stream driven into a wall stops at the margin. */
#include <math.h>
#include <string.h>

#include "testutil.h"

#ifdef KC_REAL_FLOAT
#define SLACK 1e-4
#else
#define SLACK 1e-6
#endif

typedef struct harness {
    kc_chain chain;
    kc_zone_set zones;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    int count[8];
    kc_ctrl_event last[8];
    double min_clear; /* smallest clearance of any setpoint sent */
} harness;

static harness H;
static kc_check CHECK; /* the dry runs' */

static void setup(void)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, KC_MODEL_PUMA560, NULL), KC_OK);
    kc_zone_set_init(&H.zones);
    H.cfg = kc_ctrl_cfg_default();
    H.cfg.zones = &H.zones;
    H.min_clear = HUGE_VAL;
}

static void start(const kc_real *q0) { assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, q0), KC_OK); }

/* Smallest distance of any volume from any zone at q. */
static double clearance(const kc_real *q)
{
    kc_real d[KC_MAX_VOLUMES * KC_ZONE_MAX];
    assert_int_equal(kc_zone_distances(&H.chain, &H.zones, q, d), KC_OK);
    double best = HUGE_VAL;
    for (int i = 0; i < H.chain.n_volumes * H.zones.n_zones; i++)
        best = fmin(best, (double)d[i]);
    return best;
}

static void tick(const kc_goal *g, kc_ctrl_command cmd)
{
    kc_ctrl_input in = {g, cmd, 0, KC_REASON_NONE};
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    for (int e = 0; e < H.out.n_events; e++) {
        H.count[H.out.events[e].kind]++;
        H.last[H.out.events[e].kind] = H.out.events[e];
    }
    if (H.count[KC_EVENT_FAULT] == 0)
        H.min_clear = fmin(H.min_clear, clearance(H.out.q));
}


static void add_sphere(kc_vec3 c, kc_real r)
{
    kc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = KC_SHAPE_SPHERE;
    kc_pose_identity(&s.pose);
    s.pose.t = c;
    s.dim[0] = r;
    assert_int_equal(kc_zone_set_add(&H.zones, &s), KC_OK);
}

static kc_real margin(void) { return H.zones.margin; }

/* The margin must exceed the farthest a volume point moves in one tick. */
static void test_margin_vs_tick_travel(void **state)
{
    (void)state;
    setup();
    add_sphere(kc_vec3_make(KC_R(2.0), KC_R(0.0), KC_R(0.0)), KC_R(0.1));
    kc_real travel = kc_zone_tick_travel(&H.chain, H.cfg.dt);
    /* hand count for the PUMA: waist lever >= the reach 0.86 m at 2 rad/s */
    assert_true(travel > KC_R(0.002) && travel < H.zones.margin);
    assert_int_equal(kc_ctrl_cfg_check(&H.cfg, &H.chain), KC_OK);
    H.zones.margin = travel * KC_R(0.99);
    assert_int_equal(kc_ctrl_cfg_check(&H.cfg, &H.chain), KC_E_ARG);
    H.zones.margin = travel * KC_R(1.01);
    assert_int_equal(kc_ctrl_cfg_check(&H.cfg, &H.chain), KC_OK);
    /* at a slower cycle the same margin is too small */
    H.cfg.dt = KC_R(0.004);
    assert_int_equal(kc_ctrl_cfg_check(&H.cfg, &H.chain), KC_E_ARG);
}

/* A waist sweep from -0.8 to 0.8 rad; the zone sits where the wrist passes
 * at 0 rad, then is moved outward until the sweep clears it by a few mm. */
static void test_joint_goal_through_and_near(void **state)
{
    (void)state;
    setup();
    kc_real qa[6], qb[6], qm[6];
    memcpy(qa, KT_PUMA_Q0, sizeof qa);
    memcpy(qb, KT_PUMA_Q0, sizeof qb);
    memcpy(qm, KT_PUMA_Q0, sizeof qm);
    qa[0] = KC_R(-0.8);
    qb[0] = KC_R(0.8);
    qm[0] = KC_R(0.0);
    kc_pose mid;
    kc_fk_eval(&H.chain, qm, &mid);
    add_sphere(mid.t, KC_R(0.05));
    assert_true(clearance(qa) > (double)margin() && clearance(qb) > (double)margin());
    assert_true(clearance(qm) == 0.0);

    kc_goal g = kt_joint_goal(1, qb, 6);
    kc_verdict v;
    assert_int_equal(kc_check_init(&CHECK, &H.chain, &H.cfg, 100000, qa), KC_OK);
    kc_status st = kc_check_from(&CHECK, qa, &g, &v);
    assert_int_equal(st, KC_E_UNREACHABLE);
    assert_int_equal(v.reason, KC_REASON_ZONE);
    assert_int_equal(v.zone, 0);
    assert_true(v.volume >= 0 && v.volume < H.chain.n_volumes);
    assert_true(v.distance < margin());
    assert_true(v.where > KC_R(0.0) && v.where < KC_R(0.5)); /* on the way in, before the middle */

    /* Outward (away from the waist axis) until the sweep's sampled
     * clearance is margin + 3..6 mm. */
    kc_vec3 out = kc_vec3_make(mid.t.v[0], mid.t.v[1], KC_R(0.0));
    kc_vec3_scale(&out, KC_R(1.0) / kc_vec3_norm(&out), &out);
    double chosen = -1.0;
    for (int k = 0; k < 600 && chosen < 0; k++) {
        kc_real off = KC_R(0.001) * (kc_real)k;
        H.zones.zones[0].pose.t = kc_vec3_make(mid.t.v[0] + off * out.v[0], mid.t.v[1] + off * out.v[1], mid.t.v[2]);
        double lo = HUGE_VAL;
        for (int s = 0; s <= 400; s++) {
            kc_real q[6];
            memcpy(q, KT_PUMA_Q0, sizeof q);
            q[0] = KC_R(-0.8) + KC_R(1.6) * (kc_real)s / KC_R(400.0);
            lo = fmin(lo, clearance(q));
        }
        if (lo >= (double)margin() + 0.003)
            chosen = lo;
    }
    assert_true(chosen > 0 && chosen < (double)margin() + 0.006);
    st = kc_check_from(&CHECK, qa, &g, &v);
    assert_int_equal(st, KC_OK);
    assert_int_equal(v.reason, KC_REASON_NONE);
    assert_int_equal(v.zone, -1);
    for (int j = 0; j < 6; j++)
        assert_true(v.q_end[j] == qb[j]);

    /* Run it: completes, every setpoint keeps the margin, and between ticks
     * (joints interpolated linearly, 8 points a tick) nothing enters. */
    start(qa);
    kc_real prev[6];
    memcpy(prev, qa, sizeof prev);
    tick(&g, KC_CMD_NONE);
    double between = HUGE_VAL;
    for (int k = 0; k < 5000 && H.count[KC_EVENT_COMPLETED] == 0; k++) {
        for (int s = 1; s < 8; s++) {
            kc_real q[6];
            for (int j = 0; j < 6; j++)
                q[j] = prev[j] + (H.out.q[j] - prev[j]) * (kc_real)s / KC_R(8.0);
            between = fmin(between, clearance(q));
        }
        memcpy(prev, H.out.q, sizeof prev);
        tick(NULL, KC_CMD_NONE);
    }
    assert_int_equal(H.count[KC_EVENT_COMPLETED], 1);
    assert_int_equal(H.count[KC_EVENT_FAULT], 0);
    assert_true(H.min_clear >= (double)margin());
    assert_true(H.min_clear < (double)margin() + 0.006);
    assert_true(between > 0.0);
}

/* The cycle's own check: a goal given straight to kc_ctrl_step (no dry
 * run) that crosses a zone stops the arm like e-stop, faulting with the
 * zone and the volume named; after reset the arm may move away. */
static void test_step_stops_on_violation(void **state)
{
    (void)state;
    setup();
    kc_real qa[6], qb[6], qm[6];
    memcpy(qa, KT_PUMA_Q0, sizeof qa);
    memcpy(qb, KT_PUMA_Q0, sizeof qb);
    memcpy(qm, KT_PUMA_Q0, sizeof qm);
    qa[0] = KC_R(-0.8);
    qb[0] = KC_R(0.8);
    qm[0] = KC_R(0.0);
    kc_pose mid;
    kc_fk_eval(&H.chain, qm, &mid);
    add_sphere(kc_vec3_make(KC_R(3.0), KC_R(3.0), KC_R(3.0)), KC_R(0.1)); /* far away: zone 0 */
    add_sphere(mid.t, KC_R(0.05));                                      /* in the way: zone 1 */
    start(qa);
    kc_goal g = kt_joint_goal(7, qb, 6);
    tick(&g, KC_CMD_NONE);
    double last_clear = HUGE_VAL;
    int k;
    for (k = 0; k < 5000 && H.count[KC_EVENT_FAULT] == 0; k++) {
        last_clear = clearance(H.out.q);
        tick(NULL, KC_CMD_NONE);
    }
    assert_int_equal(H.count[KC_EVENT_FAULT], 1);
    const kc_ctrl_event *f = &H.last[KC_EVENT_FAULT];
    assert_int_equal(f->reason, KC_REASON_ZONE);
    assert_int_equal(f->goal_id, 7);
    assert_int_equal(f->zone, 1);
    assert_true(f->volume >= 0 && f->volume < H.chain.n_volumes);
    assert_int_equal(H.last[KC_EVENT_ABORTED].reason, KC_REASON_ZONE);
    assert_int_equal(H.last[KC_EVENT_ABORTED].zone, 1);
    assert_int_equal(H.ctrl.zone_hit.volume, f->volume);
    /* the last setpoint sent before the fault kept the margin */
    assert_true(last_clear >= (double)margin());
    /* the stop: every joint at its own acceleration limit, to rest, FAULT */
    for (k = 0; k < 5000 && H.out.state != KC_CTRL_FAULT; k++)
        tick(NULL, KC_CMD_NONE);
    assert_int_equal(H.out.state, KC_CTRL_FAULT);
    for (int j = 0; j < 6; j++)
        assert_true(H.out.qd[j] == KC_R(0.0));
    /* Stopping from 2 rad/s at 5 rad/s^2 takes 0.4 rad: this last line of
     * defence stops the arm, it cannot keep it out of the zone. That is the
     * dry run's job (above). Where the arm rests now: */
    double rest = clearance(H.out.q);
    /* goals are refused until reset; then a move that does not come closer
     * is allowed (on through the zone's far side, here) */
    kc_real back[6];
    memcpy(back, H.out.q, sizeof back);
    back[0] = H.out.q[0] > KC_R(0.0) ? KC_R(0.8) : KC_R(-0.8);
    assert_true(rest < 0.2);
    g = kt_joint_goal(8, back, 6);
    tick(&g, KC_CMD_NONE);
    assert_int_equal(H.last[KC_EVENT_REJECTED].reason, KC_REASON_STATE);
    tick(NULL, KC_CMD_RESET);
    assert_int_equal(H.out.state, KC_CTRL_IDLE);
    int faults = H.count[KC_EVENT_FAULT];
    tick(&g, KC_CMD_NONE);
    for (k = 0; k < 5000 && H.count[KC_EVENT_COMPLETED] == 0; k++)
        tick(NULL, KC_CMD_NONE);
    if (H.count[KC_EVENT_COMPLETED] != 1)
        fail_msg("state %d, faults %d, rejected %d reason %d, aborted reason %d", H.out.state, H.count[KC_EVENT_FAULT],
                 H.count[KC_EVENT_REJECTED], H.last[KC_EVENT_REJECTED].reason, H.last[KC_EVENT_ABORTED].reason);
    assert_int_equal(H.count[KC_EVENT_FAULT], faults);
}

/* A Cartesian line through a box zone is refused at planning time. */
static void test_line_through_box(void **state)
{
    (void)state;
    setup();
    kc_pose a, b;
    kc_fk_eval(&H.chain, KT_PUMA_Q0, &a);
    b = a;
    b.t.v[1] += KC_R(0.3);
    kc_shape box;
    memset(&box, 0, sizeof box);
    box.kind = KC_SHAPE_BOX;
    kc_pose_identity(&box.pose);
    box.pose.t = a.t;
    box.pose.t.v[1] += KC_R(0.15);
    box.dim[0] = box.dim[1] = box.dim[2] = KC_R(0.02);
    assert_int_equal(kc_zone_set_add(&H.zones, &box), KC_OK);
    assert_true(clearance(KT_PUMA_Q0) > (double)margin());
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = 3;
    g.kind = KC_GOAL_LINE;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.pose = b;
    g.orient = KC_INTERP_SLERP;
    kc_verdict v;
    assert_int_equal(kc_check_init(&CHECK, &H.chain, &H.cfg, 100000, KT_PUMA_Q0), KC_OK);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_E_UNREACHABLE);
    assert_int_equal(v.reason, KC_REASON_ZONE);
    assert_int_equal(v.zone, 0);
    /* path length where it would enter: before the box's near face */
    assert_true(v.where > KC_R(0.05) && v.where < KC_R(0.15));
    /* moved 10 cm off the line, the same goal passes */
    H.zones.zones[0].pose.t.v[0] += KC_R(0.25);
    assert_int_equal(kc_check_from(&CHECK, KT_PUMA_Q0, &g, &v), KC_OK);
}

/* A servo twist drives the arm into a wall (a half-space 6 cm ahead),
 * straight at it or sliding along it (side, m/s across): the arm slows
 * and comes to rest at the margin, no fault, no entry; the twist reversed
 * moves it away at once. */
static void servo_into_wall(double side)
{
    setup();
    kc_pose p0;
    kc_fk_eval(&H.chain, KT_PUMA_Q0, &p0);
    kc_shape wall;
    memset(&wall, 0, sizeof wall);
    wall.kind = KC_SHAPE_HALFSPACE;
    kc_mat3_rot(KC_AXIS_Y, -KC_PI_2, &wall.pose.R); /* normal -x: the zone is x > x_w */
    wall.pose.t = kc_vec3_make(p0.t.v[0] + KC_R(0.12), KC_R(0.0), KC_R(0.0));
    assert_int_equal(kc_zone_set_add(&H.zones, &wall), KC_OK);
    /* whichever volume is ahead, put the wall 6 cm beyond the margin */
    H.zones.zones[0].pose.t.v[0] += (kc_real)(0.06 + (double)margin() - clearance(KT_PUMA_Q0));
    double c0 = clearance(KT_PUMA_Q0);
    kt_near(c0, (double)margin() + 0.06, 1e-4, "wall placed");
    start(KT_PUMA_Q0);
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = 9;
    g.kind = KC_GOAL_SERVO;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.servo_twist = 1;
    g.twist[0] = KC_R(0.2); /* +x, 0.2 m/s */
    g.twist[1] = (kc_real)side;
    double x_prev = (double)p0.t.v[0], speed_max = 0.0;
    for (int k = 0; k < 2500; k++) {
        tick(&g, KC_CMD_NONE);
        speed_max = fmax(speed_max, ((double)H.out.pose.t.v[0] - x_prev) / (double)H.cfg.dt);
        x_prev = (double)H.out.pose.t.v[0];
    }
    assert_int_equal(H.count[KC_EVENT_FAULT], 0);
    assert_int_equal(H.out.state, KC_CTRL_MOVING);
    /* it did move toward the wall at speed, then came to rest at the margin */
    assert_true(speed_max > 0.1);
    assert_true(H.min_clear >= (double)margin());
    double c_end = clearance(H.out.q);
    assert_true(c_end < (double)margin() + 0.002);
    /* at rest toward the wall: the tool no longer advances (motion along
     * the wall that does not come closer is not restrained) */
    double x_end = (double)H.out.pose.t.v[0];
    for (int k = 0; k < 100; k++)
        tick(&g, KC_CMD_NONE);
    assert_true(fabs((double)H.out.pose.t.v[0] - x_end) < 1e-4);
    assert_true(H.min_clear >= (double)margin());
    /* the stream's target stays with the arm held at the margin (within
     * ctrl_zone.c's ZONE_LEAD of 1 mm and a tick of the twist), not running on
     * into the wall: in float it once ran 18 cm in, at 0.2 m/s */
    kc_vec3 lead;
    kc_vec3_sub(&H.ctrl.servo_target.t, &H.ctrl.pose.t, &lead);
    assert_true((double)kc_vec3_norm(&lead) <= 1e-3 + 0.2 * (double)H.cfg.dt);
    /* a twist away from the wall is followed at once, shaped from the
     * arm's twist at rest (kinctl/ctrl.h; at 0.5 / sqrt(3) m/s^2 and
     * 5 / sqrt(3) m/s^3 it is 4.4 cm away after 0.6 s; 1 mm if it started
     * from the 0.2 m/s the stream asked for towards the wall) */
    g.twist[0] = KC_R(-0.2);
    g.twist[1] = (kc_real)-side;
    double lag_max = 0.0;
    for (int k = 0; k < 600; k++) {
        tick(&g, KC_CMD_NONE);
        kc_vec3_sub(&H.ctrl.servo_target.t, &H.ctrl.pose.t, &lead);
        lag_max = fmax(lag_max, (double)kc_vec3_norm(&lead));
    }
    /* followed throughout: the stream not ended for falling behind, the
     * tool within 0.1 mm of its target (measured 2 um in double, 8 um in
     * float; in float it once fell 40 mm behind, a joint's jerk bound
     * ramping down a jump the zone's release had made) */
    assert_int_equal(H.out.state, KC_CTRL_MOVING);
    assert_int_equal(H.count[KC_EVENT_ABORTED], 0);
    assert_true(lag_max < 1e-4);
    assert_true(clearance(H.out.q) > c_end + 0.04);
    assert_int_equal(H.count[KC_EVENT_FAULT], 0);
}

static void test_servo_into_wall(void **state)
{
    (void)state;
    servo_into_wall(0.0);
    /* Sliding, the reversed stream once stayed at the margin for good, in
     * both precisions: every step measured an approach of rounding size,
     * on which the stream was taken back to rest, tick after tick. */
    servo_into_wall(0.1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_margin_vs_tick_travel),
        cmocka_unit_test(test_joint_goal_through_and_near),
        cmocka_unit_test(test_step_stops_on_violation),
        cmocka_unit_test(test_line_through_box),
        cmocka_unit_test(test_servo_into_wall),
    };
    int failed = cmocka_run_group_tests_name("ctrl_zone (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("ctrl_zone");
    return failed;
}
