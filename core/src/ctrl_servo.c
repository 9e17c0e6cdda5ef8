/* SPDX-License-Identifier: BSD-3-Clause */
/* ctrl_servo.c - a servo stream's shaped target (kinctl/ctrl.h): a twist
 * stream's twist moving towards the commanded twist, a pose stream's pose
 * towards the commanded pose, each within the goal's Cartesian bounds
 * axis by axis, and where the shaping starts again (the stream's start,
 * RESUME, a pose message, a zone restraining the arm, a stream taking
 * over a moving arm from the tool's own motion). */
#include "ctrl_internal.h"
#include "vec3_internal.h"

#include <string.h>

/* 1 / sqrt(3): each axis within its bound over sqrt(3) keeps the linear
 * and angular vectors' norms within the bounds. */
#define AXIS_SHARE KC_R(0.57735026918962576)

/* Below this |phi| the left Jacobian's coefficients are their series. */
#define PHI_SERIES KC_R(0.1)

int kc_ctrl_servo_shaped(const kc_ctrl *c)
{
    return c->goal.kind == KC_GOAL_SERVO && !c->goal.servo_twist &&
           kc_ctrl_goal_profile(c, &c->goal) == KC_PROFILE_JERK;
}

/* One tick of a shaped velocity v (its rate a) towards the commanded w
 * within |a| <= amax and |change of a| <= h = jmax dt a tick: the rate a'
 * for the coming tick (a rate beyond amax, where a stream took over a
 * faster law, comes down by h a tick until it is within). From a',
 * lowering the rate to 0 by h a tick adds
 *     S(a') = dt sgn(a') sum_{i=1..m} (|a'| - i h) = dt sgn(a') (m |a'| - h m (m + 1) / 2)
 * to v, m = floor(|a'| / h), so v + dt a' + S(a') is continuous, odd and
 * increasing in a' and linear between multiples of h. a' is its root,
 * reaching w with the rate at 0 (with e = w - v and x = |e| / dt):
 *     |a'| = (x + h m (m + 1) / 2) / (m + 1),  sgn(a') = sgn(e),
 * m the integer with h m (m + 1) / 2 <= x < h (m + 1) (m + 2) / 2, clamped
 * to [a - h, a + h] and [-amax, amax]. Deadbeat: on the next tick the
 * root is a' - h (S(a') = dt (a' - h) + S(a' - h)), within reach, until
 * v = w, a = 0 exactly as far as rounding goes; so too after a tick
 * clamped at amax (the root then lies at or above amax - h). A new w
 * whose root is out of reach is approached at the clamp, overshooting w
 * where the rate already points past it, and then reached the same way.
 * A trapezoid's (jmax infinite): h infinite, m = 0, a' = e / dt clamped
 * to amax. */
static kc_real shaped_rate(kc_real v, kc_real a, kc_real w, kc_real amax, kc_real jmax, kc_real dt)
{
    kc_real h = jmax * dt, e = w - v, x = kc_fabs(e) / dt;
    kc_real m = kc_floor(KC_R(0.5) * (kc_sqrt(KC_R(1.0) + KC_R(8.0) * x / h) - KC_R(1.0)));
    if (m > KC_R(0.0) && KC_R(0.5) * h * m * (m + KC_R(1.0)) > x)
        m -= KC_R(1.0);
    else if (KC_R(0.5) * h * (m + KC_R(1.0)) * (m + KC_R(2.0)) <= x)
        m += KC_R(1.0);
    kc_real r = (x + KC_R(0.5) * h * m * (m + KC_R(1.0))) / (m + KC_R(1.0));
    if (!kc_isfinite(r)) /* h infinite: no ramp */
        r = x;
    r = e < KC_R(0.0) ? -r : r;
    kc_real top = kc_fabs(a) - h > amax ? kc_fabs(a) - h : amax;
    return kc_clamp(kc_clamp(r, a - h, a + h), -top, top);
}

/* R turned by exp(phi) in the base frame: R = exp(phi) R. */
static void turn_by(kc_mat3 *R, kc_vec3 phi)
{
    kc_quat dr, r, r2;
    kc_quat_exp(&phi, &dr);
    kc_quat_from_mat3(R, &r);
    kc_quat_mul(&dr, &r, &r2);
    kc_quat_to_mat3(&r2, R);
}

/* A twist stream's tick: the shaped twist v moves towards the commanded
 * twist axis by axis, its rate a' for the tick (shaped_rate) within the
 * goal's Cartesian acceleration and jerk (l.a, l.j) over sqrt(3) on each
 * linear axis, l.dw and l.dj over sqrt(3) on each angular one, so that
 * the linear and angular acceleration and jerk vectors stay within the
 * bounds (kinctl/ctrl.h); the commanded linear and angular velocity
 * vectors are first scaled down to the goal's speed and omega (l.v, l.w)
 * where they exceed them, their directions kept. The rate is held over
 * the tick: the target moves by v dt + a' dt^2 / 2 (the rotation by (w +
 * dw' dt / 2) dt) and the twist becomes v + a' dt, the target's own
 * velocity at the tick, which the IK step feeds forward as it does a
 * line's. The target so moves by a piecewise constant acceleration,
 * whose third difference over a tick is the mean of two consecutive
 * steps of the rate: within the jerk bound. Moved by the rate before the
 * step, a reversal of the rate's ramp gave 2 times the bound, and 1.5 its
 * every start. */
static void servo_twist_tick(kc_ctrl *c)
{
    kc_real dt = c->cfg.dt, half = KC_R(0.5) * dt * dt;
    kc_interp_limits l = kc_ctrl_cart_limits(&c->cfg, &c->goal);
    kc_real cap[2], a[6];
    for (int h = 0; h < 6; h += 3) { /* the linear part, then the angular */
        const kc_real *t = &c->goal.twist[h];
        kc_real size = kc_sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]), top = h == 0 ? l.v : l.w;
        cap[h / 3] = size > top ? top / size : KC_R(1.0);
    }
    for (int i = 0; i < 6; i++)
        a[i] = shaped_rate(c->servo_v[i], c->servo_a[i], c->goal.twist[i] * cap[i / 3],
                           AXIS_SHARE * (i < 3 ? l.a : l.dw), AXIS_SHARE * (i < 3 ? l.j : l.dj), dt);
    const kc_real *v = c->servo_v;
    turn_by(&c->servo_target.R,
            kc_vec3_make(v[3] * dt + a[3] * half, v[4] * dt + a[4] * half, v[5] * dt + a[5] * half));
    for (int i = 0; i < 3; i++)
        c->servo_target.t.v[i] += v[i] * dt + a[i] * half;
    for (int i = 0; i < 6; i++) {
        c->servo_a[i] = a[i];
        c->servo_v[i] += a[i] * dt;
    }
}

void kc_ctrl_turn(const kc_mat3 *from, const kc_mat3 *to, kc_vec3 *w)
{
    kc_quat r0, r1, r0c, d;
    kc_quat_from_mat3(from, &r0);
    kc_quat_from_mat3(to, &r1);
    kc_quat_conj(&r0, &r0c);
    kc_quat_mul(&r1, &r0c, &d);
    if (d.w < KC_R(0.0)) { /* the short way round */
        d.w = -d.w;
        d.x = -d.x;
        d.y = -d.y;
        d.z = -d.z;
    }
    kc_quat_log(&d, w);
}

/* A pose stream's shaped pose at tick k: the three coordinates of its
 * position and the rotation vector phi of R = exp(phi) ref, each a
 * jerk-limited profile from tick k0 (kinctl/scurve.h), give the pose, the
 * twist and its rate. R's angular velocity and acceleration in the base
 * frame are
 *     w = J dphi,  dw = J ddphi + (dJ/dt) dphi,
 * J = I + b [phi]x + c [phi]x^2 the left Jacobian of SO(3) (R' R^T =
 * [J dphi]x), th = |phi|, b = (1 - cos th) / th^2, c = (th - sin th) /
 * th^3, and since [dphi]x dphi = 0 and [phi]x [dphi]x dphi = 0,
 *     (dJ/dt) dphi = B s (phi x dphi) + C s phi x (phi x dphi)
 *                    + c dphi x (phi x dphi),
 * s = phi . dphi, B = (db/dth) / th = (th sin th - 2 (1 - cos th)) / th^4,
 * C = (dc/dth) / th = (th (1 - cos th) - 3 (th - sin th)) / th^5. Below
 * th = PHI_SERIES, where these differences cancel, their series to th^4:
 *     b = 1/2 - th^2/24 + th^4/720,   c = 1/6 - th^2/120 + th^4/5040,
 *     B = -1/12 + th^2/180 - th^4/6720,  C = -1/60 + th^2/1260 - th^4/60480
 * (the next terms under 3e-11 of each there). At phi = 0, where every
 * plan starts, w = dphi and dw = ddphi: a new plan continues the pose,
 * the twist and its rate. */
static void pose_at(kc_ctrl *c, int64_t k)
{
    const struct kc_ctrl_servo_plan *s = &c->plan.servo;
    kc_scurve_state x[6];
    for (int i = 0; i < 6; i++)
        kc_scurve_eval(&s->axis[i], k > s->k0 ? k - s->k0 : 0, &x[i]);
    kc_vec3 phi = kc_vec3_make(x[3].p, x[4].p, x[5].p), dphi = kc_vec3_make(x[3].v, x[4].v, x[5].v);
    kc_vec3 ddphi = kc_vec3_make(x[3].a, x[4].a, x[5].a);
    kc_real t2 = kc_v3_dot(phi, phi), b, cc, B, C;
    if (t2 < PHI_SERIES * PHI_SERIES) {
        b = KC_R(0.5) - t2 * (KC_R(1.0) / KC_R(24.0) - t2 / KC_R(720.0));
        cc = KC_R(1.0) / KC_R(6.0) - t2 * (KC_R(1.0) / KC_R(120.0) - t2 / KC_R(5040.0));
        B = -KC_R(1.0) / KC_R(12.0) + t2 * (KC_R(1.0) / KC_R(180.0) - t2 / KC_R(6720.0));
        C = -KC_R(1.0) / KC_R(60.0) + t2 * (KC_R(1.0) / KC_R(1260.0) - t2 / KC_R(60480.0));
    } else {
        kc_real th = kc_sqrt(t2), sn, cs;
        kc_sincos(th, &sn, &cs);
        b = (KC_R(1.0) - cs) / t2;
        cc = (th - sn) / (t2 * th);
        B = (th * sn - KC_R(2.0) * (KC_R(1.0) - cs)) / (t2 * t2);
        C = (th * (KC_R(1.0) - cs) - KC_R(3.0) * (th - sn)) / (t2 * t2 * th);
    }
    kc_vec3 pd = kc_v3_cross(phi, dphi), ppd = kc_v3_cross(phi, pd), pdd = kc_v3_cross(phi, ddphi);
    kc_vec3 w = kc_v3_add(dphi, kc_v3_add(kc_v3_scale(pd, b), kc_v3_scale(ppd, cc)));
    kc_real sd = kc_v3_dot(phi, dphi);
    kc_vec3 dw = kc_v3_add(ddphi, kc_v3_add(kc_v3_scale(pdd, b), kc_v3_scale(kc_v3_cross(phi, pdd), cc)));
    dw = kc_v3_add(dw, kc_v3_add(kc_v3_scale(pd, B * sd), kc_v3_scale(ppd, C * sd)));
    dw = kc_v3_add_scaled(dw, kc_v3_cross(dphi, pd), cc);
    kc_quat e, r;
    kc_quat_exp(&phi, &e);
    kc_quat_mul(&e, &s->ref, &r);
    kc_quat_to_mat3(&r, &c->servo_target.R);
    for (int i = 0; i < 3; i++) {
        c->servo_target.t.v[i] = x[i].p;
        c->servo_v[i] = x[i].v;
        c->servo_a[i] = x[i].a;
        c->servo_v[3 + i] = w.v[i];
        c->servo_a[3 + i] = dw.v[i];
    }
}

void kc_ctrl_servo_aim(kc_ctrl *c, int64_t k0)
{
    struct kc_ctrl_servo_plan *s = &c->plan.servo;
    kc_vec3 phi1;
    kc_quat_from_mat3(&c->servo_target.R, &s->ref);
    kc_ctrl_turn(&c->servo_target.R, &c->goal.pose.R, &phi1);
    kc_interp_limits l = kc_ctrl_cart_limits(&c->cfg, &c->goal);
    for (int i = 0; i < 6; i++) {
        int lin = i < 3;
        kc_real p0 = lin ? c->servo_target.t.v[i] : KC_R(0.0), p1 = lin ? c->goal.pose.t.v[i] : phi1.v[i - 3];
        kc_real v = AXIS_SHARE * (lin ? l.v : l.w), a = AXIS_SHARE * (lin ? l.a : l.dw);
        kc_real jm = AXIS_SHARE * (lin ? l.j : l.dj);
        /* A target too far for a plan's ticks (KC_PROFILE_MAX_TICKS): the
         * axis stops where it is instead, until the next message. */
        if (kc_scurve_plan(&s->axis[i], p0, c->servo_v[i], c->servo_a[i], p1, v, a, jm, c->cfg.dt) != KC_OK)
            kc_scurve_plan(&s->axis[i], p0, c->servo_v[i], c->servo_a[i], p0, v, a, jm, c->cfg.dt);
    }
    s->k0 = k0;
}

void kc_ctrl_servo_rest(kc_ctrl *c, int64_t last)
{
    memset(c->servo_v, 0, sizeof c->servo_v);
    memset(c->servo_a, 0, sizeof c->servo_a);
    c->servo_target = c->goal.servo_twist || kc_ctrl_servo_shaped(c) ? c->pose : c->goal.pose;
    if (kc_ctrl_servo_shaped(c))
        kc_ctrl_servo_aim(c, last);
}

void kc_ctrl_servo_tick(kc_ctrl *c)
{
    if (c->goal.servo_twist)
        servo_twist_tick(c);
    else if (kc_ctrl_servo_shaped(c))
        pose_at(c, c->cycle);
}

/* The largest rate a joint may take over a tick, its speed room short of
 * qd_max, from which a stop at jerk J (the stream's end: kc_ctrl_halt_plan,
 * kc_scurve_plan_stop) stays within qd_max: the speed after the tick, a
 * dt more, and the a^2 / (2 J) the stop's ramp of the rate down to 0
 * adds, within room: a = J (sqrt(dt^2 + 2 room / J) - dt). Within the
 * deadbeat step onto qd_max (shaped_rate), which lowers the rate by J dt
 * a tick from the tick's start and so adds S(a) <= a^2 / (2 J) (by h dt
 * (f^2 + m) / 2, a = (m + f) h): a joint held to that step alone left
 * the stop no room, and a stream going quiet with a joint accelerating
 * near its speed limit stopped acceleration-limited, that joint's jerk
 * 128 times its limit (test_ctrl_servoshape.c). */
static kc_real stop_rate(kc_real room, kc_real J, kc_real dt)
{
    return J * (kc_sqrt(dt * dt + KC_R(2.0) * kc_max(room, KC_R(0.0)) / J) - dt);
}

/* The joints' jerk under a jerk-limited stream. The IK step's velocities
 * c_k, one a tick, are a trajectory whose rate r = (c_k - c_{k-1}) / dt
 * the joint takes over the tick, qd' = qd + r dt, as long as its qdd
 * changes by at most h = qddd_max dt (it then is c_k exactly: qd went
 * to c_{k-1} the tick before). Where it would change by more, the joint
 * follows the trajectory by shaped_rate's deadbeat step in coordinates
 * relative to it, taken as going on at the rate r: the velocity's
 * offset qd - c_{k-1} and the rate's a - r brought to 0 within h a
 * tick, without overshooting the offset's 0, and so the step comes
 * back onto c exactly once the trajectory's own jerk is within h again.
 * (Held to h a tick alone, without the deadbeat, the rate overshot on
 * every catch-up and the loop through the IK step's error wound up:
 * 4.7 mm from a pose stream's last pose, a joint at its speed limit.)
 * The step is kept where a stop from it stays within qd_max (stop_rate,
 * below the deadbeat step onto +-qd_max at rest), the rate within
 * qdd_max (or coming down by h), q within its limits. The
 * tick after a zone restrained the step (ctrl_zone.c, braking at the
 * acceleration limits), the IK step's velocities pass unchanged: the
 * stream's target has then been brought back to the arm. The tick after
 * that ramps from qdd 0, not from that jump of the velocities: ramped
 * down from it at h a tick, a joint ran on past the IK step's
 * velocities by qdd^2 / (2 qddd_max), and the IK step's correction of
 * the lag that left outran the ramp (in float, where a zone restrains a
 * reversed stream on rounding alone: the PUMA 560's elbow jumped by 1.3
 * rad/s^2, and the tool was 40 mm behind its target 0.6 s later). */
void kc_ctrl_servo_jerk(kc_ctrl *c, kc_real *q, kc_real *qd, kc_real *qdd)
{
    kc_real dt = c->cfg.dt;
    int valid = c->servo_cmd_cycle == c->cycle - 1, restrained = c->servo_zone_cycle == c->cycle - 1;
    int released = c->servo_zone_cycle == c->cycle - 2; /* the tick before passed unchanged */
    for (int j = 0; j < c->chain->n_joints; j++) {
        const kc_joint_limits *l = &c->chain->joints[j].limits;
        kc_real cmd = qd[j], v = c->qd[j], a0 = released ? KC_R(0.0) : c->qdd[j], h = l->qddd_max * dt;
        kc_real r = valid ? (cmd - c->servo_cmd[j]) / dt : a0, off = v - cmd + r * dt;
        c->servo_cmd[j] = cmd;
        /* The step as it is where the deadbeat step would be it: qdd
         * within h of a0, the offset within h dt (shaped_rate's m = 0),
         * and the step short of the speed limits' (S(a) <= dt a^2 / h). */
        kc_real reach = v + dt * qdd[j] * (KC_R(1.0) + kc_fabs(qdd[j]) / h);
        if (restrained ||
            (kc_fabs(qdd[j] - a0) <= h && kc_fabs(off) < h * dt && kc_fabs(reach) < l->qd_max))
            continue;
        kc_real a = r + shaped_rate(off, a0 - r, KC_R(0.0), KC_REAL_MAX, l->qddd_max, dt);
        a = kc_clamp(a, -stop_rate(l->qd_max + v, l->qddd_max, dt), stop_rate(l->qd_max - v, l->qddd_max, dt));
        kc_real top = kc_fabs(a0) - h > l->qdd_max ? kc_fabs(a0) - h : l->qdd_max;
        a = kc_clamp(kc_clamp(a, a0 - h, a0 + h), -top, top);
        qd[j] = kc_clamp(v + a * dt, -l->qd_max, l->qd_max);
        qdd[j] = (qd[j] - v) / dt;
        q[j] = kc_clamp(c->q[j] + qd[j] * dt, l->q_min, l->q_max);
    }
    c->servo_cmd_cycle = c->cycle;
}

/* Whether a stream can take over the motion in joint space under way
 * from a target of joint_target: under the full task, on six joints or
 * more. On six the IK step gives the joints' velocity back exactly (J
 * invertible). On a redundant arm it gives back the part the task sees,
 * J^+ J qd, and not the self-motion (I - J^+ J) qd: the jerk bound
 * (kc_ctrl_servo_jerk) brings the joints from their own velocities onto
 * the step's within their jerk limits, and the step corrects what that
 * moves the tool by (test_ctrl_servoshape.c: within 5.6e-6 m of the
 * stream's target on the Panda, 1.43e-5 m at five times its cases; 2.5e-6
 * m on the PUMA 560). */
static int joint_target_exists(const kc_ctrl *c)
{
    return c->cfg.ik.mask == KC_IK_MASK_FULL && c->chain->n_joints >= 6;
}

/* A target for the joints' motion at the last setpoint (q, qd, qdd),
 * whose law the IK step (kinctl/ik.h: qd' = J^-1 (v + k e), k the gain of
 * the row; J^+ and the self-motion apart on a redundant arm, above)
 * tracks with the joints going on at that acceleration: pose,
 * twist v and its rate a at that tick. The step's next velocity is to be
 * qd1 = qd + qdd dt, so v + k e = J qd1. A target moving by v dt + a
 * dt^2 / 2 over a tick, the tool by J qd1 dt + (dJ/dt) qd dt^2 / 2, keeps
 * the error e where
 *     k e = (a - (dJ/dt) qd) dt / 2 = J qdd dt / 2,
 * the law's own error at that acceleration (a line's, followed): e is
 * that, v = J qd1 - J qdd dt / 2 = J (qd + qdd dt / 2), and a the change
 * of J qd1 over the tick to J(q1) (qd1 + qdd dt), q1 = q + qd1 dt, over
 * dt. The pose is the tool's moved by e (the step's error of a rotation
 * exp(phi) is phi to third order in |phi|, here some 1e-5 rad). */
static void joint_target(const kc_ctrl *c, kc_pose *target, kc_real *v, kc_real *a)
{
    kc_real dt = c->cfg.dt, qd1[KC_MAX_JOINTS], q1[KC_MAX_JOINTS], e[6];
    int n = c->chain->n_joints;
    kc_jacobian jac;
    for (int j = 0; j < n; j++) {
        qd1[j] = c->qd[j] + c->qdd[j] * dt;
        q1[j] = c->q[j] + qd1[j] * dt;
    }
    kc_fk_jacobian(c->chain, c->q, &jac, target);
    for (int i = 0; i < 6; i++) {
        kc_real u = KC_R(0.0), jqdd = KC_R(0.0);
        for (int j = 0; j < n; j++) {
            u += jac.m[i][j] * qd1[j];
            jqdd += jac.m[i][j] * c->qdd[j];
        }
        v[i] = u - KC_R(0.5) * dt * jqdd;
        a[i] = u; /* J qd1, until J(q1) is known */
        e[i] = KC_R(0.5) * dt * jqdd / kc_ik_online_gain(i < 3 ? c->cfg.ik.gain_pos : c->cfg.ik.gain_rot, dt);
    }
    kc_fk_jacobian(c->chain, q1, &jac, NULL);
    for (int i = 0; i < 6; i++) {
        kc_real u1 = KC_R(0.0);
        for (int j = 0; j < n; j++)
            u1 += jac.m[i][j] * (qd1[j] + c->qdd[j] * dt);
        a[i] = (u1 - a[i]) / dt;
    }
    turn_by(&target->R, kc_vec3_make(e[3], e[4], e[5]));
    for (int i = 0; i < 3; i++)
        target->t.v[i] += e[i];
}

/* The segment's target at its tick j into o, while superposed the sum
 * (kc_ctrl_blend_point); 1 where that is on a stop in joint space. */
static int law_at(const kc_ctrl *c, int64_t j, kc_ctrl_seg_point *o)
{
    kc_real qd_m[KC_MAX_JOINTS];
    kc_ctrl_seg_eval(c, j, o);
    return c->blend.on && kc_ctrl_blend_point(c, c->k0 + j, o, qd_m);
}

int kc_ctrl_servo_take(kc_ctrl *c, const kc_goal *g, kc_ctrl_output *out)
{
    /* A motion that stops on its path (a STOP's, a PAUSE's, a stop for a
     * goal waiting on it) follows a law as the motion does; one stopping
     * joint by joint does in joint space; a fault's does not count. A
     * superposition: a line's, an arc's or a Cartesian path's on a stop on
     * its path, from the sum; any on a stop in joint space, from the
     * joints (below). */
    int stopping = c->state == KC_CTRL_STOPPING;
    int in_joints = c->goal.kind == KC_GOAL_JOINT || c->goal.kind == KC_GOAL_PATH;
    if (g->kind != KC_GOAL_SERVO || g->stop_first || !c->active || (c->state != KC_CTRL_MOVING && !stopping) ||
        (stopping && c->fault_reason != KC_REASON_NONE) || c->jstop || (c->drive == KC_DRIVE_HALT && !in_joints) ||
        c->drive == KC_DRIVE_STOPPING_WAIT || (c->blend.on && c->goal.kind == KC_GOAL_PATH && !joint_target_exists(c)))
        return 0;
    /* The stream's target goes on from the motion's own target as it is
     * sampled tick by tick, which the IK step tracks with an error of its
     * own that so goes on unchanged: a line's, an arc's, a Cartesian
     * path's, a shaped pose stream's or a twist stream's (kinctl/ctrl.h).
     * From a motion in joint space, a target placed where the IK step
     * would have tracked one (joint_target). */
    int twist_law = c->goal.kind == KC_GOAL_SERVO && c->goal.servo_twist;
    int law = c->goal.kind == KC_GOAL_LINE || c->goal.kind == KC_GOAL_ARC || c->goal.kind == KC_GOAL_PATH_CART ||
              kc_ctrl_servo_shaped(c) || twist_law;
    if ((!law && !(in_joints && joint_target_exists(c))) ||
        (!(g->servo_twist && twist_law) && kc_ctrl_goal_profile(c, g) != KC_PROFILE_JERK))
        return 0;
    /* A twist stream holds its rate over each tick (servo_twist_tick):
     * one taking over another law goes on from the rate of that law's
     * last tick, ab, its twist's backward difference (for a cubic law of
     * jerk J, a - J dt / 2), whose twist it so continues: the twist's
     * change over the next tick is the step of the rate from there. From
     * a, the rate at the tick, the target's jerk (third difference) at the
     * takeover reaches 4 / 3 of the two laws'. A pose stream's profiles
     * start from the rate at the tick. */
    int held = g->servo_twist && !twist_law;
    kc_real v[6], a[6], ab[6], dt = c->cfg.dt;
    kc_pose from = c->servo_target;
    int64_t j = c->cycle - 1 - c->k0;
    kc_ctrl_seg_point o;
    /* A segment's target at j (o, below); a superposition on a stop in
     * joint space (and one in its first tick, whose sum has no tick before
     * it for the rate) from the joints, as a motion in joint space: from
     * the sum, the joints' jerk reached their limits at the takeover, 0.46
     * of them around it. (A stream is never superposed on.) */
    if (law && c->goal.kind != KC_GOAL_SERVO &&
        ((c->blend.on && c->cycle - 2 < c->blend.k0) || law_at(c, j, &o))) {
        if (!joint_target_exists(c))
            return 0;
        law = 0;
    }
    if (!law) {
        joint_target(c, &from, v, a);
        memcpy(ab, a, sizeof ab);
    } else if (c->goal.kind == KC_GOAL_SERVO) {
        memcpy(v, c->servo_v, sizeof v);
        memcpy(a, c->servo_a, sizeof a);
        memcpy(ab, a, sizeof ab);
        /* A shaped pose stream's twist a tick before (its plan started
         * before it; else the rate at the tick). */
        if (held && c->plan.servo.k0 < c->cycle - 1) {
            pose_at(c, c->cycle - 2);
            for (int i = 0; i < 6; i++)
                ab[i] = (v[i] - c->servo_v[i]) / dt;
            pose_at(c, c->cycle - 1);
        }
    } else {
        /* The segment's target at j, the last setpoint's tick, its twist,
         * and the twist's rate by the central difference of its twists at
         * j + 1 and j - 1, and by the backward one of j and j - 1. While
         * superposed on a stop on its path, the sum's (o, above). */
        from = o.pose;
        memcpy(v, o.twist, sizeof v);
        law_at(c, j + 1, &o);
        memcpy(a, o.twist, sizeof a);
        law_at(c, j - 1, &o);
        memcpy(ab, o.twist, sizeof ab);
        for (int i = 0; i < 6; i++) {
            a[i] = (a[i] - ab[i]) / (KC_R(2.0) * dt);
            ab[i] = (v[i] - ab[i]) / dt;
        }
    }
    if (held)
        memcpy(a, ab, sizeof a);
    /* Within the goal's Cartesian bounds: the vectors (a pose stream's
     * profiles bring an axis beyond its own share back within it,
     * jerk-limited, and a twist stream's step brings its rate so), with
     * the rounding of the rate's differences (cfg.limit_slack: a line
     * stopping at the same acceleration limit was refused by 1e-16 of
     * it). */
    kc_interp_limits l = kc_ctrl_cart_limits(&c->cfg, g);
    for (int h = 0; h < 6; h += 3) { /* the linear part, then the angular */
        const kc_real *vh = &v[h], *ah = &a[h], e = KC_R(1.0) + c->cfg.limit_slack;
        kc_real vmax = (h == 0 ? l.v : l.w) * e, amax = (h == 0 ? l.a : l.dw) * e;
        if (vh[0] * vh[0] + vh[1] * vh[1] + vh[2] * vh[2] > vmax * vmax ||
            ah[0] * ah[0] + ah[1] * ah[1] + ah[2] * ah[2] > amax * amax)
            return 0;
    }
    kc_ctrl_emit_takeover(out, g->id, c->goal.id);
    kc_ctrl_goal_copy(&c->goal, g);
    c->k0 = c->cycle - 1; /* tick 0 is the last setpoint, as for every segment */
    c->drive = KC_DRIVE_NOMINAL;
    c->stop_intent = KC_CMD_NONE;
    c->settle = 0;
    c->path_length = KC_R(0.0);
    c->state = KC_CTRL_MOVING;
    /* A superposition's sum goes on in the stream's target: the tracking
     * bound stays the transition's until the tool has settled. */
    c->blend.lax = c->blend.on;
    c->blend.on = 0;
    c->servo_last = c->cycle;
    c->servo_target = from;
    memcpy(c->servo_v, v, sizeof c->servo_v);
    memcpy(c->servo_a, a, sizeof c->servo_a);
    if (kc_ctrl_servo_shaped(c))
        kc_ctrl_servo_aim(c, c->cycle - 1);
    return 1;
}
