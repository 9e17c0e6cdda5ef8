/* SPDX-License-Identifier: BSD-3-Clause */
/* test_ctrl_blend.c - goals replaced mid-motion (kinctl/ctrl.h): every
 * ordered pair of a joint move, a line, an arc and a Cartesian path
 * replacing one another at random ticks on the PUMA 560. A replacing line,
 * arc or path takes over from any of them in the tick it arrives (the
 * replaced motion's stop superposed on it: a line's or an arc's on its
 * path, a joint move's and a Cartesian path's in joint space, as the FK of
 * its joints, its twist J qd checked against FK's difference); a joint
 * goal retargets from the current state; a joint move of the 7-joint
 * Panda replaced by a line stops first and is accepted with
 * KC_REASON_STOP_FIRST. Every tick: the
 * joints inside their limits, each joint's change of q within qd_max dt,
 * of qd within qdd_max dt (the continuity of the setpoint); the tool
 * point's and the tool's angular speed, measured from the FK of
 * consecutive setpoints, within the Cartesian limits during Cartesian
 * motions (over a joint move's stop, within what the target may do).
 * While a superposition lasts, its target, computed here from the two
 * plans the controller holds, is checked on every tick against the
 * Cartesian limits (speed and step, acceleration, jerk, angular speed and
 * acceleration), or what either motion alone does where that is more, and
 * the tool against it; over a line's or arc's stop the tool's measured
 * acceleration is no worse than in the plain Cartesian motions of the
 * same runs. The replacing goal ends at its target. A line
 * continued along its direction is taken over with no change of speed.
 * Cartesian paths by a quartic blend, the replacing ones by a quartic
 * blend and a cubic spline in turn (the spline on the controller's ramps
 * of tau').
 * Each replacing goal is first judged by the dry run from a snapshot of
 * the controller, as kinctld judges it (kinctl/check.h, daemon/checker.c):
 * one the arm cannot follow from the moving state stops the motion first,
 * one it cannot follow at all (a random path near the PUMA's elbow
 * singularity, where the elbow's acceleration limit holds it back) is
 * refused; the goal handed on is accepted with the verdict's reason and
 * ends where the verdict said, to the bit.
 * Replacements during a superposition or a stop, chains of them; and
 * the fallbacks: a path that does not start at rest (Lagrange's) under
 * the trapezoid's law, a replacement that cannot be planned, each with
 * its reason. */
#include <math.h>
#include <string.h>

#include "testutil.h"

/* Rounding allowed in the joints' per-tick checks (relative to the limit),
 * as the controller's own final check. */
#ifdef KC_REAL_FLOAT
#define SLACK 1e-4
#define TOL_POSE 1e-4
#define CASES 3
#else
#define SLACK 1e-6
#define TOL_POSE 1e-6
#define CASES 6
#endif
/* The tool's motion is measured on the FK of the joint setpoints, which
 * follow the Cartesian target through one IK step a tick: the online law
 * adds gain * error to the fed-forward twist (gain 100/s, errors of the
 * order of the IK tolerance), and float rounds FK positions to ~1e-7 m,
 * i.e. 1e-4 m/s over a 1 ms tick. Speeds: within 1 % of the limit plus
 * 2e-4 m/s (rad/s). Accelerations, a difference of two such speeds over a
 * tick, carry the law's correction gain * (change of the error): where a
 * trapezoid's acceleration jumps (a stop starting, a line starting) the
 * tool's measured acceleration overshoots the limit by tens of percent
 * for a few ticks, superposed or not. So the superpositions' worst is held
 * against the worst of the plain Cartesian motions of the same runs
 * (each alone, and the stops of those that stopped first), within
 * TOOL_REL_A of it. */
#define TOOL_REL 0.01
#define TOOL_ABS_V 2e-4
#define TOOL_REL_A 0.02
/* Both worsts carry the measurement's rounding: in float two speeds'
 * (TOOL_ABS_V / 2 each) over a 1 ms tick, 0.2 m/s^2 (rad/s^2), two thirds
 * of the test's 0.3 m/s^2 limit, so float compares noise as much as motion
 * and the worsts may differ by that much; in double it is below 1e-9. */
#ifdef KC_REAL_FLOAT
#define TOOL_NOISE_A 0.2
#else
#define TOOL_NOISE_A 0.0
#endif

typedef struct harness {
    kc_chain chain;
    kc_ctrl_cfg cfg;
    kc_ctrl ctrl;
    kc_ctrl_output out;
    double q_prev[KC_MAX_JOINTS], qd_prev[KC_MAX_JOINTS];
    kc_pose pose_prev;
    double v_prev[6]; /* the tool's speed vector (linear, angular) at the last tick */
    int have_prev;
    int events[8];
    /* The speed bounds of the last superposed target checked (m/s, rad/s). */
    double v_bound, w_bound;
} harness;

static harness H; /* large: not on the stack */

/* Worst ratios to the Cartesian limits measured during superpositions
 * and during plain Cartesian motions: speed, acceleration, angular speed,
 * angular acceleration. */
static struct {
    double blend[4], plain[4], target[4];
    double joint[4]; /* measured on the tool while a joint move's stop is superposed */
    double jerk; /* the superposed targets' jerk over the limit */
} WORST;

/* The controller at rest at q0 on model, with the Cartesian limits below. */
static void setup_model(kc_model model, const kc_real *q0)
{
    memset(&H, 0, sizeof H);
    assert_int_equal(kc_chain_init_model(&H.chain, model, NULL), KC_OK);
    H.cfg = kc_ctrl_cfg_default();
    /* Cartesian limits this arm follows around KT_PUMA_Q0 within its joints'
     * acceleration limits (at the defaults, 0.25 m/s and 0.5 m/s^2, the
     * elbow's qdd_max binds while a line here stops, and the tool lags by
     * more than the tracking tolerance: a motion the dry run refuses). */
    H.cfg.cart_speed = KC_R(0.15);
    H.cfg.cart_accel = KC_R(0.3);
    assert_int_equal(kc_ctrl_init(&H.ctrl, &H.chain, &H.cfg, q0), KC_OK);
    kc_fk_eval(&H.chain, q0, &H.pose_prev);
    H.out.pose = H.pose_prev;
    for (int j = 0; j < H.chain.n_joints; j++)
        H.q_prev[j] = (double)q0[j];
}

static void setup(void) { setup_model(KC_MODEL_PUMA560, KT_PUMA_Q0); }

/* The Cartesian target of a superposition at absolute tick k, computed
 * here from the two plans kc_ctrl holds (the replaced line or arc and its
 * stop in ctrl.blend, the new segment in ctrl.plan) through the public
 * evaluators, composed with quaternions (kinctl/ctrl.h's formula):
 * p = p_M + p_G - p_s, r = r_G r_s^* r_M, v = v_M + v_G,
 * w = w_G + rot(r_G r_s^*) w_M. */
typedef struct target {
    kc_vec3 p, v, w;
    kc_quat r;
    kc_vec3 vg, wg; /* G's own twist */
} target;

/* The replaced joint move's joints at tick jm (>= 0) of its jerk-limited
 * stop as the IK step integrates it, and the velocities fed forward from
 * there (ctrl_blend.c stop_euler), from the stops the controller planned,
 * through the public evaluators: each profile's p(0) + dt (v(1) + ... +
 * v(jm)), summed here tick by tick, and v(jm + 1); on its line
 * q = q0 + dq u, or joint by joint. */
static kc_real euler_sum(const kc_scurve *sc, int64_t jm, kc_real *v)
{
    kc_scurve_state s;
    kc_scurve_eval(sc, 0, &s);
    double p = (double)s.p;
    for (int64_t i = 1; i <= jm; i++) {
        kc_scurve_eval(sc, i, &s);
        p += (double)H.cfg.dt * (double)s.v;
    }
    kc_scurve_eval(sc, jm + 1, &s);
    *v = s.v;
    return (kc_real)p;
}

static void joint_stop_eval(int64_t jm, kc_real *q, kc_real *qd)
{
    const kc_ctrl_blend *b = &H.ctrl.blend;
    kc_real u = KC_R(0.0), ud = KC_R(0.0);
    assert_true(b->stop_drive == KC_DRIVE_SCURVE || b->stop_drive == KC_DRIVE_HALT);
    if (b->stop_drive == KC_DRIVE_SCURVE)
        u = euler_sum(&b->stop.scurve, jm, &ud);
    for (int i = 0; i < H.chain.n_joints; i++) {
        if (b->stop_drive == KC_DRIVE_HALT) {
            q[i] = euler_sum(&b->plan.halt[i], jm, &qd[i]);
        } else {
            q[i] = b->plan.joint.q0[i] + b->plan.joint.dq[i] * u;
            qd[i] = b->plan.joint.dq[i] * ud;
        }
    }
}

/* The replaced segment at tick jm (>= 0) of its stop, as the controller
 * planned it: a line or an arc (jerk-limited or a trapezoid's stop), or
 * a stop in joint space (a joint move's, a Cartesian path's) its tool: FK of its joints, and its twist J(q) qd, checked
 * against the central difference of FK along qd (step JOINT_H, within
 * JOINT_TWIST_TOL m/s or rad/s: FK's rounding over the step, and its
 * truncation). */
#ifdef KC_REAL_FLOAT
#define JOINT_H 1e-3
#define JOINT_TWIST_TOL 5e-4
#else
#define JOINT_H 1e-5
#define JOINT_TWIST_TOL 1e-8
#endif
static void stop_eval(int64_t jm, kc_interp_cart_state *m)
{
    const kc_ctrl_blend *b = &H.ctrl.blend;
    jm = jm < 0 ? 0 : jm;
    if (b->kind == KC_GOAL_JOINT || b->stop_drive == KC_DRIVE_HALT) {
        kc_real q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS], qa[KC_MAX_JOINTS], qb[KC_MAX_JOINTS];
        kc_pose pose, pa, pb;
        kc_jacobian jac;
        joint_stop_eval(jm, q, qd);
        kc_fk_jacobian(&H.chain, q, &jac, &pose);
        const kc_real h = (kc_real)JOINT_H;
        for (int i = 0; i < H.chain.n_joints; i++) {
            qa[i] = q[i] - h * qd[i];
            qb[i] = q[i] + h * qd[i];
        }
        kc_fk_eval(&H.chain, qa, &pa);
        kc_fk_eval(&H.chain, qb, &pb);
        /* The rotation from pa to pb over 2h, as a rotation vector. */
        kc_mat3 dR;
        kc_quat dq;
        kc_vec3 w;
        kc_mat3_transpose(&pa.R, &dR);
        kc_mat3_mul(&pb.R, &dR, &dR);
        kc_quat_from_mat3(&dR, &dq);
        kc_quat_log(&dq, &w);
        m->p = pose.t;
        kc_quat_from_mat3(&pose.R, &m->q);
        for (int r = 0; r < 6; r++) {
            double t = 0.0;
            for (int i = 0; i < H.chain.n_joints; i++)
                t += (double)jac.m[r][i] * (double)qd[i];
            double fd = r < 3 ? (double)(pb.t.v[r] - pa.t.v[r]) / (2 * JOINT_H) : (double)w.v[r - 3] / (2 * JOINT_H);
            kt_near(t, fd, JOINT_TWIST_TOL, "a joint stop's twist J qd against FK's difference");
            if (r < 3)
                m->v.v[r] = (kc_real)t;
            else
                m->w.v[r - 3] = (kc_real)t;
        }
        return;
    }
    if (b->stop_drive == KC_DRIVE_SCURVE) {
        if (b->kind == KC_GOAL_LINE)
            kc_interp_line_eval_scurve(&b->plan.line, &b->stop.scurve, jm, m);
        else
            kc_interp_arc_eval_scurve(&b->plan.arc, &b->stop.scurve, jm, m);
    } else if (b->kind == KC_GOAL_LINE) {
        kc_interp_line_eval_profile(&b->plan.line, &b->stop.prof, jm, m);
    } else {
        kc_interp_arc_eval_profile(&b->plan.arc, &b->stop.prof, jm, m);
    }
}

static target blend_target(int64_t k)
{
    const kc_ctrl *c = &H.ctrl;
    kc_interp_cart_state m, gs;
    int64_t jm = k - c->blend.k0, jg = k - c->k0;
    jm = jm < 0 ? 0 : jm;
    jg = jg < 0 ? 0 : jg;
    stop_eval(jm, &m);
    target g;
    if (c->goal.kind == KC_GOAL_PATH_CART) {
        /* tau = t - t0, or on the path's own ramp (a path the controller
         * ramps): its twist scaled by tau' */
        kc_scurve_state u = {(kc_real)jg * c->cfg.dt, KC_R(1.0), KC_R(0.0), KC_R(0.0), 2};
        if (c->ramp_on)
            kc_scurve_eval(&c->ramp, jg, &u);
        kc_path_pose pp;
        kc_path_cart_eval_time(&c->plan.path_cart, u.p, &pp);
        g.p = pp.p;
        g.r = pp.r;
        kc_vec3_scale(&pp.v, u.v, &g.v);
        kc_vec3_scale(&pp.w, u.v, &g.w);
    } else {
        if (c->goal.kind == KC_GOAL_LINE)
            kc_interp_line_eval(&c->plan.line, jg, &gs);
        else
            kc_interp_arc_eval(&c->plan.arc, jg, &gs);
        g.p = gs.p;
        g.r = gs.q;
        g.v = gs.v;
        g.w = gs.w;
    }
    kc_quat rs, rs_conj, a, r;
    kc_quat_from_mat3(&c->blend.rest.R, &rs);
    kc_quat_conj(&rs, &rs_conj);
    kc_quat_mul(&g.r, &rs_conj, &a);
    kc_quat_mul(&a, &m.q, &r);
    target t;
    kc_vec3 aw;
    kc_quat_rotate(&a, &m.w, &aw);
    for (int i = 0; i < 3; i++) {
        t.p.v[i] = m.p.v[i] + g.p.v[i] - c->blend.rest.t.v[i];
        t.v.v[i] = m.v.v[i] + g.v.v[i];
        t.w.v[i] = g.w.v[i] + aw.v[i];
    }
    t.r = r;
    t.vg = g.v;
    t.wg = g.w;
    return t;
}

/* The superposition's target from tick k - 1 to k (the setpoint of tick k
 * heads for it): its position continues by its speed, its speed and
 * angular speed within the larger of the two goals' limits, and their
 * changes over the tick within the acceleration limits or what M's stop or
 * G alone changes over it, where that is more (an arc's centripetal part);
 * and the tool within the tracking bound of a stop of it. Not once the new
 * segment is itself stopping (a STOP, or a replacement, during the
 * superposition: two stops add up, kinctl/ctrl.h): the tool's speed then
 * within M's stop's plus the Cartesian limits (G's stop's bound). */
static void check_target(int64_t k)
{
    const kc_ctrl *c = &H.ctrl;
    if (c->drive != KC_DRIVE_NOMINAL || c->state != KC_CTRL_MOVING) {
        kc_interp_cart_state m;
        stop_eval(k - c->blend.k0, &m);
        H.v_bound = (double)H.cfg.cart_speed + (double)kc_vec3_norm(&m.v);
        H.w_bound = (double)H.cfg.cart_omega + (double)kc_vec3_norm(&m.w);
        return;
    }
    double e = 1.0 + (double)H.cfg.limit_slack, dt = (double)H.cfg.dt;
    target t0 = blend_target(k - 1), t1 = blend_target(k);
    /* The components alone over the same tick. */
    kc_interp_cart_state m0, m1;
    int64_t jm = k - c->blend.k0;
    stop_eval(jm - 1, &m0);
    stop_eval(jm, &m1);
    kc_vec3 dv, dw, dvm, dwm, step;
    kc_vec3_sub(&t1.v, &t0.v, &dv);
    kc_vec3_sub(&t1.w, &t0.w, &dw);
    kc_vec3_sub(&m1.v, &m0.v, &dvm);
    kc_vec3_sub(&m1.w, &m0.w, &dwm);
    kc_vec3_sub(&t1.p, &t0.p, &step);
    double lv = (double)H.cfg.cart_speed, la = (double)H.cfg.cart_accel;
    double lw = (double)H.cfg.cart_omega, ldw = (double)H.cfg.cart_alpha;
    /* Speeds: the limits, or M's stop or G alone where that is more (a
     * joint move's stop is bounded in its joints only). */
    double v_bound = fmax(lv, fmax((double)kc_vec3_norm(&m1.v), (double)kc_vec3_norm(&t1.vg)));
    double w_bound = fmax(lw, fmax((double)kc_vec3_norm(&m1.w), (double)kc_vec3_norm(&t1.wg)));
    /* The limits, or what M's stop or G alone (v_G = v - v_M: an arc's
     * acceleration has a centripetal part its tangential limit does not
     * bound) changes over the tick, where that is more; angular: the limit
     * or M's stop. */
    kc_vec3 dvg;
    for (int i = 0; i < 3; i++)
        dvg.v[i] = (t1.v.v[i] - m1.v.v[i]) - (t0.v.v[i] - m0.v.v[i]);
    double a_bound = fmax(la, fmax((double)kc_vec3_norm(&dvm), (double)kc_vec3_norm(&dvg)) / dt);
    double dw_bound = fmax(ldw, (double)kc_vec3_norm(&dwm) / dt);
    double sv = (double)kc_vec3_norm(&t1.v), sw = (double)kc_vec3_norm(&t1.w);
    double sa = (double)kc_vec3_norm(&dv) / dt, sdw = (double)kc_vec3_norm(&dw) / dt;
    /* The step is a difference of two positions of the target, each the
     * sum of three rounded ones: 8 units of KC_REAL_EPS |p| cover it. */
    double sp = (double)kc_vec3_norm(&step) / dt;
    /* Its bound: the speed's, or M's or G's own step where that is more
     * (p_G's step is the sum's less M's). */
    kc_vec3 stepm, stepg;
    kc_vec3_sub(&m1.p, &m0.p, &stepm);
    kc_vec3_sub(&step, &stepm, &stepg);
    double p_bound = fmax(v_bound, fmax((double)kc_vec3_norm(&stepm), (double)kc_vec3_norm(&stepg)) / dt);
    double sp_round = 8.0 * (double)KC_REAL_EPS * (double)kc_vec3_norm(&t1.p) / dt;
    if (!(sv <= v_bound * e && sw <= w_bound * e && sa <= a_bound * e && sdw <= dw_bound * e &&
          sp <= p_bound * e + sp_round))
        fail_msg("cycle %ld (superposed target): speed %.6g of %.6g, angular %.6g of %.6g, acceleration %.6g of %.6g, "
                 "angular %.6g of %.6g, step %.6g m/s",
                 (long)k, sv, v_bound, sw, w_bound, sa, a_bound, sdw, dw_bound, sp);
    /* The tool point's jerk (the second difference of the target's
     * velocity over two ticks) within the goals' jerk limit, or what M's
     * stop or G alone (v_G = v - v_M) does where that is more; from M's
     * third tick, the ticks before being M's own. Rounding: 8 units of
     * KC_REAL_EPS |v| over dt^2. */
    if (jm >= 2) {
        target tm = blend_target(k - 2);
        kc_interp_cart_state mm;
        stop_eval(jm - 2, &mm);
        double jt = 0.0, jmm = 0.0, jg = 0.0, vmag = (double)kc_vec3_norm(&t1.v);
        for (int i = 0; i < 3; i++) {
            double d2t = (double)t1.v.v[i] - 2.0 * (double)t0.v.v[i] + (double)tm.v.v[i];
            double d2m = (double)m1.v.v[i] - 2.0 * (double)m0.v.v[i] + (double)mm.v.v[i];
            jt += d2t * d2t;
            jmm += d2m * d2m;
            jg += (d2t - d2m) * (d2t - d2m);
        }
        jt = sqrt(jt) / (dt * dt);
        double j_bound = fmax((double)H.cfg.cart_jerk, fmax(sqrt(jmm), sqrt(jg)) / (dt * dt));
        double j_round = 8.0 * (double)KC_REAL_EPS * vmag / (dt * dt);
        if (!(jt <= j_bound * e + j_round))
            fail_msg("cycle %ld (superposed target): jerk %.6g of %.6g m/s^3", (long)k, jt, j_bound);
        WORST.jerk = fmax(WORST.jerk, jt / (double)H.cfg.cart_jerk);
    }
    H.v_bound = p_bound; /* the tool is measured by its step */
    /* The tool's angular speed is measured by its rotation over the tick:
     * the speeds at its start count too. */
    H.w_bound = fmax(w_bound, fmax((double)kc_vec3_norm(&m0.w), (double)kc_vec3_norm(&t0.wg)));
    WORST.target[0] = fmax(WORST.target[0], sv / lv);
    WORST.target[1] = fmax(WORST.target[1], sa / la);
    WORST.target[2] = fmax(WORST.target[2], sw / lw);
    WORST.target[3] = fmax(WORST.target[3], sdw / ldw);
    /* The tool heads for it: within the tracking bound of a stop. */
    kc_vec3 err;
    kc_vec3_sub(&H.out.pose.t, &t1.p, &err);
    if (!(kc_vec3_norm(&err) <= 4 * H.cfg.track_tol))
        fail_msg("cycle %ld: the tool %.3g m from the superposed target", (long)k, (double)kc_vec3_norm(&err));
}

/* One tick, every check above on its setpoint. */
static void step(const kc_goal *g, kc_ctrl_command cmd)
{
    kc_ctrl_input in = {g, cmd, 0, KC_REASON_NONE};
    int blending = H.ctrl.blend.on;
    assert_int_equal(kc_ctrl_step(&H.ctrl, &in, &H.out), KC_OK);
    blending = blending || H.ctrl.blend.on;
    double dt = (double)H.cfg.dt;
    if (H.ctrl.blend.on)
        check_target(H.out.cycle);
    for (int j = 0; j < H.chain.n_joints; j++) {
        const kc_joint_limits *l = &H.chain.joints[j].limits;
        double q = (double)H.out.q[j], qd = (double)H.out.qd[j];
        double dq = fabs(q - H.q_prev[j]), dv = fabs(qd - H.qd_prev[j]);
        if (!(q >= (double)l->q_min && q <= (double)l->q_max && fabs(qd) <= (double)l->qd_max * (1.0 + SLACK) &&
              dq <= (double)l->qd_max * dt * (1.0 + SLACK) &&
              dv <= (double)l->qdd_max * dt * (1.0 + SLACK) + SLACK * fabs(H.qd_prev[j])))
            fail_msg("cycle %ld joint %d: q %.9g, |qd| %.6g, q step %.4g, qd step %.4g", (long)H.out.cycle, j, q,
                     fabs(qd), dq, dv);
        H.q_prev[j] = q;
        H.qd_prev[j] = qd;
    }
    /* The tool's twist from the FK of consecutive setpoints: the position
     * difference, and the rotation R_k R_{k-1}^T as a rotation vector. */
    kc_mat3 dR;
    kc_quat dq;
    kc_vec3 w;
    double v[6];
    kc_mat3_transpose(&H.pose_prev.R, &dR);
    kc_mat3_mul(&H.out.pose.R, &dR, &dR);
    kc_quat_from_mat3(&dR, &dq);
    kc_quat_log(&dq, &w);
    for (int i = 0; i < 3; i++) {
        v[i] = ((double)H.out.pose.t.v[i] - (double)H.pose_prev.t.v[i]) / dt;
        v[3 + i] = (double)w.v[i] / dt;
    }
    double sv = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), sw = sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
    double lv = (double)H.cfg.cart_speed, lw = (double)H.cfg.cart_omega;
    /* Joint moves (and their stops) are bounded in the joints only: so is
     * the tool while a stop in joint space is superposed on a Cartesian
     * goal (its target's speed is checked above, against the limits or what
     * either motion alone does): a joint move's, or the halt joint by joint
     * of a motion replaced while a superposition lasted, which starts from
     * that sum's twist (a joint move's stop in it beyond the limits). */
    int cart_motion = H.ctrl.active && H.ctrl.goal.kind != KC_GOAL_JOINT;
    double bv = lv, bw = lw;
    if (blending && (H.ctrl.blend.kind == KC_GOAL_JOINT || H.ctrl.blend.stop_drive == KC_DRIVE_HALT)) {
        bv = fmax(lv, H.v_bound);
        bw = fmax(lw, H.w_bound);
    }
    if (cart_motion && !(sv <= bv * (1.0 + TOOL_REL) + TOOL_ABS_V && sw <= bw * (1.0 + TOOL_REL) + TOOL_ABS_V))
        fail_msg("cycle %ld: tool speed %.6g m/s, %.6g rad/s (bounds %.6g, %.6g)", (long)H.out.cycle, sv, sw, bv, bw);
    if (cart_motion && H.have_prev) {
        double a[6];
        for (int i = 0; i < 6; i++)
            a[i] = (v[i] - H.v_prev[i]) / dt;
        double sa = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        double sdw = sqrt(a[3] * a[3] + a[4] * a[4] + a[5] * a[5]);
        double la = (double)H.cfg.cart_accel, ldw = (double)H.cfg.cart_alpha;
        double *w4 = !blending ? WORST.plain : H.ctrl.blend.kind == KC_GOAL_JOINT ? WORST.joint : WORST.blend;
        w4[0] = fmax(w4[0], sv / lv);
        w4[1] = fmax(w4[1], sa / la);
        w4[2] = fmax(w4[2], sw / lw);
        w4[3] = fmax(w4[3], sdw / ldw);
    }
    memcpy(H.v_prev, v, sizeof v);
    H.have_prev = 1;
    H.pose_prev = H.out.pose;
    for (int e = 0; e < H.out.n_events; e++)
        H.events[H.out.events[e].kind]++;
}

static void tick(const kc_goal *g) { step(g, KC_CMD_NONE); }

/* The reason of the last output's event of that kind for goal id, or -1. */
static int event_reason(kc_ctrl_event_kind kind, int64_t id)
{
    for (int e = 0; e < H.out.n_events; e++)
        if (H.out.events[e].kind == kind && H.out.events[e].goal_id == id)
            return (int)H.out.events[e].reason;
    return -1;
}

/* Ticks until goal id completes, at most max. */
static void run_until_completed(int64_t id, int max)
{
    for (int k = 1; k <= max; k++) {
        tick(NULL);
        if (event_reason(KC_EVENT_COMPLETED, id) >= 0)
            return;
        if (H.events[KC_EVENT_FAULT] > 0 || H.out.state == KC_CTRL_FAULT || H.out.state == KC_CTRL_ESTOP)
            fail_msg("cycle %ld: fault (%s) while moving to goal %ld", (long)H.out.cycle,
                     kc_ctrl_reason_str(H.ctrl.fault_reason), (long)id);
    }
    fail_msg("goal %ld not completed in %d ticks", (long)id, max);
}

static kc_vec3 random_offset(kt_rng *r, double lo, double hi)
{
    kc_vec3 d = kt_rand_unit(r), o;
    kc_vec3_scale(&d, (kc_real)kt_uniform(r, lo, hi), &o);
    return o;
}

static const kc_goal_kind KINDS[4] = {KC_GOAL_JOINT, KC_GOAL_LINE, KC_GOAL_ARC, KC_GOAL_PATH_CART};

/* Where the tool comes to rest if the motion stops on its path now: where
 * a replacing Cartesian goal starts, superposed or not (the same stop),
 * found by running a copy of the controller through a STOP. */
static kc_ctrl SIM;
static kc_pose rest_ahead(void) { return kt_rest_on_stop(&SIM, &H.ctrl); }

/* A random goal of that kind near the tool pose home (within reach of
 * KT_PUMA_Q0's: a joint move is near KT_PUMA_Q0). */
static kc_goal random_goal(kt_rng *r, kc_goal_kind kind, int64_t id, kc_pose home)
{
    kc_goal g;
    memset(&g, 0, sizeof g);
    g.id = id;
    g.kind = kind;
    g.replace = 0;
    g.vel_scale = g.acc_scale = KC_R(1.0);
    g.orient = KC_INTERP_SLERP;
    if (kind == KC_GOAL_JOINT) {
        for (int j = 0; j < 6; j++)
            g.q[j] = KT_PUMA_Q0[j] + (kc_real)kt_uniform(r, -0.08, 0.08);
    } else if (kind == KC_GOAL_LINE) {
        kc_vec3 d = random_offset(r, 0.03, 0.08), axis = kt_rand_unit(r), rv;
        kc_mat3 dR;
        kc_quat dq;
        kc_vec3_scale(&axis, (kc_real)kt_uniform(r, 0.0, 0.1), &rv);
        kc_quat_exp(&rv, &dq);
        kc_quat_to_mat3(&dq, &dR);
        g.pose = home;
        kc_vec3_add(&home.t, &d, &g.pose.t);
        kc_mat3_mul(&dR, &home.R, &g.pose.R);
    } else if (kind == KC_GOAL_ARC) {
        /* A gentle arc from home's tool point ahead 6-10 cm along a
         * random direction, bent by 3-8 % of its chord, in a plane near
         * the one across the last joint's axis (the PUMA's wrist roll,
         * whose range is the widest): the tool turns with the arc about
         * its normal. */
        kc_vec3 n, t = kt_rand_unit(r), d, e;
        kc_jacobian jac;
        kc_fk_jacobian(&H.chain, KT_PUMA_Q0, &jac, NULL);
        for (int k = 0; k < 3; k++)
            n.v[k] = jac.m[3 + k][5] + KC_R(0.2) * t.v[k];
        t = kt_rand_unit(r);
        kc_vec3_cross(&n, &t, &d);
        kc_vec3_scale(&d, KC_R(1.0) / kc_vec3_norm(&d), &d);
        kc_vec3_cross(&n, &d, &e);
        kc_vec3_scale(&e, KC_R(1.0) / kc_vec3_norm(&e), &e);
        kc_real chord = (kc_real)kt_uniform(r, 0.06, 0.1), bend = chord * (kc_real)kt_uniform(r, 0.03, 0.08);
        g.pose = home;
        for (int k = 0; k < 3; k++) {
            g.via.v[k] = home.t.v[k] + chord / 2 * d.v[k] + bend * e.v[k];
            g.pose.t.v[k] = home.t.v[k] + chord * d.v[k];
        }
    } else {
        /* A quartic blend (on its own law); a replacing one (id 2) in
         * turn a quartic blend and a clamped cubic spline (on the
         * controller's ramps). */
        static int paths;
        kc_quat q;
        kc_quat_from_mat3(&home.R, &q);
        g.method = id == 2 && paths++ % 2 ? KC_PATH_SPLINE : KC_PATH_BLEND;
        g.n_points = 2;
        for (int i = 0; i < 2; i++) {
            kc_vec3 d = random_offset(r, 0.03, 0.06);
            for (int k = 0; k < 3; k++)
                g.points[i][k] = home.t.v[k] + d.v[k];
            g.points[i][3] = q.w;
            g.points[i][4] = q.x;
            g.points[i][5] = q.y;
            g.points[i][6] = q.z;
        }
    }
    return g;
}

/* The active segment's length in ticks as planned (a Cartesian segment's
 * geometry; the tool settles after it). */
static int64_t planned_ticks(void)
{
    const kc_ctrl *c = &H.ctrl;
    switch (c->goal.kind) {
    case KC_GOAL_JOINT: return c->plan.joint.ticks;
    case KC_GOAL_LINE: return c->plan.line.ticks;
    case KC_GOAL_ARC: return c->plan.arc.ticks;
    default: return (int64_t)(c->plan.path_cart.pos.duration / c->cfg.dt);
    }
}

/* A replacing goal judged by the dry run from a snapshot of the
 * controller in the tick before it is given, as kinctld judges it
 * (daemon/checker.c): one the arm cannot follow from the moving state
 * (KC_E_UNREACHABLE: a joint held at its acceleration limit while the
 * tool falls behind the sum, on the way or after it) is judged again with
 * the motion it replaces stopped first, and handed on so (g->stop_first);
 * g scheduled for the tick and state the verdict says. A random goal near
 * the PUMA's elbow singularity may be beyond its joints from the moving
 * state, or from anywhere: the controller alone would fault there (the
 * dry run's is its own step, to the bit). Returns the verdict's status;
 * *v the verdict of the goal as handed on. */
static kc_check CHECK;
static kc_status judge(kc_goal *g, kc_verdict *v)
{
    assert_int_equal(kc_check_init(&CHECK, &H.chain, &H.cfg, 20000, H.ctrl.q), KC_OK);
    assert_int_equal(kc_check_snapshot(&CHECK, &H.ctrl, 0), KC_OK);
    kc_status st = kc_check_goal(&CHECK, g, v);
    if (st == KC_E_UNREACHABLE && CHECK.run_moving && !g->stop_first) {
        g->stop_first = 1;
        assert_int_equal(kc_check_snapshot(&CHECK, &H.ctrl, 0), KC_OK);
        st = kc_check_goal(&CHECK, g, v);
    }
    assert_int_equal(CHECK.run_moving, 1);
    g->take_cycle = v->take_cycle;
    g->take_state = v->take_state;
    return st;
}

/* The goal handed on by judge() has ended where its verdict said, to the
 * bit. */
static void check_verdict(const kc_verdict *v)
{
    assert_memory_equal(H.out.q, v->q_end, sizeof(kc_real) * (size_t)H.chain.n_joints);
}

/* Goal b's end reached: a joint move exactly, a Cartesian one within the
 * IK's tolerance. */
static void check_end(const kc_goal *b)
{
    if (b->kind == KC_GOAL_JOINT) {
        for (int j = 0; j < 6; j++)
            kt_near((double)H.out.q[j], (double)b->q[j], 0.0, "joint move's end");
        return;
    }
    kc_vec3 end = b->kind == KC_GOAL_PATH_CART ? kc_vec3_make(b->points[1][0], b->points[1][1], b->points[1][2])
                                               : b->pose.t;
    kt_near_vec3(&H.out.pose.t, &end, TOL_POSE, "Cartesian end");
    if (b->kind == KC_GOAL_LINE)
        kt_near_mat3(&H.out.pose.R, &b->pose.R, TOL_POSE, "line's end orientation");
}

static int cart(kc_goal_kind k) { return k != KC_GOAL_JOINT; }

static void test_every_pair(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(1919);
    int superposed = 0, overlapped = 0, overlapped_joint = 0, retargeted = 0, stopped_first = 0, ramped = 0;
    int refused = 0, dry_stop_first = 0, judged_out = 0; /* Cartesian ones refused or stopping first */
    for (int ia = 0; ia < 4; ia++)
        for (int ib = 0; ib < 4; ib++)
            for (int c = 0; c < CASES; c++) {
                setup();
                kc_goal a = random_goal(&r, KINDS[ia], 1, H.out.pose), b;
                tick(&a);
                int64_t len = planned_ticks();
                int64_t at = 1 + (int64_t)kt_uniform(&r, 0.0, (double)(len > 3 ? len - 3 : 1));
                for (int64_t k = 1; k < at; k++)
                    tick(NULL);
                b = random_goal(&r, KINDS[ib], 2, rest_ahead());
                b.replace = 1;
                kc_verdict v;
                if (judge(&b, &v) != KC_OK) {
                    print_message("goal %d -> %d, case %d: refused by the dry run: %s at its tick %ld\n", ia, ib, c,
                                  kc_ctrl_reason_str(v.reason), (long)v.tick);
                    refused++;
                    judged_out += cart(b.kind);
                    continue;
                }
                dry_stop_first += b.stop_first;
                judged_out += cart(b.kind) && b.stop_first;
                tick(&b);
                assert_int_equal(event_reason(KC_EVENT_ACCEPTED, b.id), v.reason);
                int blend = cart(b.kind);
                if (event_reason(KC_EVENT_STARTED, b.id) >= 0) {
                    assert_int_equal(event_reason(KC_EVENT_PREEMPTED, a.id), KC_REASON_NONE);
                    assert_int_equal(event_reason(KC_EVENT_ACCEPTED, b.id), KC_REASON_NONE);
                    if (blend) {
                        superposed++;
                        ramped += H.ctrl.ramp_on;
                        assert_true(H.ctrl.blend.on);
                        if (H.ctrl.k0 - H.ctrl.blend.k0 < H.ctrl.blend.stop_ticks) {
                            overlapped++;
                            overlapped_joint += a.kind == KC_GOAL_JOINT;
                        }
                    } else {
                        assert_int_equal(b.kind, KC_GOAL_JOINT);
                        retargeted++;
                    }
                } else {
                    /* Stops first: only where no transition is built (a
                     * joint retarget may find its position limit), or the
                     * dry run found the arm cannot follow it. */
                    assert_int_equal(event_reason(KC_EVENT_ACCEPTED, b.id), KC_REASON_STOP_FIRST);
                    assert_int_equal(H.out.state, KC_CTRL_STOPPING);
                    stopped_first++;
                }
                run_until_completed(b.id, 20000);
                check_end(&b);
                check_verdict(&v);
                assert_int_equal(H.events[KC_EVENT_FAULT], 0);
                assert_int_equal(H.events[KC_EVENT_ABORTED], 0);
            }
    print_message("dry run: %d replacing goals refused, %d stopping first for the arm's joints\n", refused,
                  dry_stop_first);
    print_message("%d superposed (%d overlapping the stop, %d of them a joint move's; %d paths on their ramps), %d "
                  "retargeted, %d stopped first; worst of the limits "
                  "(speed, acceleration, angular speed, angular acceleration): superposed targets %.4f %.4f %.4f "
                  "%.4f; measured on the tool superposed %.4f %.4f %.4f %.4f (on a joint move's stop %.4f %.4f "
                  "%.4f %.4f), in plain Cartesian motions %.4f %.4f %.4f %.4f; superposed targets' jerk %.4f of the "
                  "limit\n",
                  superposed, overlapped, overlapped_joint, ramped, retargeted, stopped_first, WORST.target[0], WORST.target[1],
                  WORST.target[2], WORST.target[3], WORST.blend[0], WORST.blend[1], WORST.blend[2], WORST.blend[3],
                  WORST.joint[0], WORST.joint[1], WORST.joint[2], WORST.joint[3], WORST.plain[0], WORST.plain[1],
                  WORST.plain[2], WORST.plain[3], WORST.jerk);
    for (int i = 1; i < 4; i += 2)
        if (!(WORST.blend[i] <=
              fmax(1.0, WORST.plain[i]) * (1.0 + TOOL_REL_A) +
                  TOOL_NOISE_A / (double)(i == 1 ? H.cfg.cart_accel : H.cfg.cart_alpha)))
            fail_msg("superposed: %.4f of an acceleration limit, plain motions %.4f", WORST.blend[i], WORST.plain[i]);
    assert_int_equal(superposed + judged_out, 4 * 3 * CASES);
    assert_true(overlapped > 0 && ramped > 0);
    assert_true(overlapped_joint > 0);
}

/* Each of a jerk-limited joint move's stops superposed on a replacing
 * line: on its line, and joint by joint after a retarget (KC_DRIVE_HALT);
 * every tick checked as above, the line ending at its end. A trapezoid
 * joint move, retargeted or not, stops first (kinctl/ctrl.h: its stop
 * brakes at a joint's acceleration limit, which the IK cannot follow
 * with its correction added). */
static void test_joint_stops(void **state)
{
    (void)state;
    const kc_ctrl_drive expect[2] = {KC_DRIVE_SCURVE, KC_DRIVE_HALT};
    kt_rng r = kt_rng_make(4242);
    for (int i = 0; i < 4; i++) {
        setup();
        int trapezoid = i >= 2, retargeted = i % 2 == 1;
        kc_goal a = random_goal(&r, KC_GOAL_JOINT, 1, H.out.pose), a2, b;
        a.profile = trapezoid ? KC_GOAL_PROFILE_TRAPEZOID : KC_GOAL_PROFILE_JERK;
        tick(&a);
        for (int k = 0; k < 150; k++)
            tick(NULL);
        if (retargeted) {
            a2 = random_goal(&r, KC_GOAL_JOINT, 3, H.out.pose);
            a2.profile = a.profile;
            a2.replace = 1;
            tick(&a2);
            assert_int_equal(event_reason(KC_EVENT_STARTED, a2.id), KC_REASON_NONE);
            for (int k = 0; k < 100; k++)
                tick(NULL);
        }
        assert_int_equal(H.out.state, KC_CTRL_MOVING);
        b = random_goal(&r, KC_GOAL_LINE, 2, rest_ahead());
        b.replace = 1;
        tick(&b);
        if (trapezoid) {
            assert_int_equal(event_reason(KC_EVENT_ACCEPTED, b.id), KC_REASON_STOP_FIRST);
            assert_int_equal(H.out.state, KC_CTRL_STOPPING);
        } else {
            assert_int_equal(event_reason(KC_EVENT_STARTED, b.id), KC_REASON_NONE);
            assert_true(H.ctrl.blend.on);
            assert_int_equal(H.ctrl.blend.kind, KC_GOAL_JOINT);
            assert_int_equal(H.ctrl.blend.stop_drive, expect[i]);
        }
        run_until_completed(b.id, 20000);
        check_end(&b);
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
        assert_int_equal(H.events[KC_EVENT_ABORTED], 0);
    }
}

/* A 7-joint arm (the Panda) under the full task: a line replacing its
 * joint move at random ticks takes over in the tick it arrives, the joint
 * move's stop superposed in joint space, its joint velocities fed
 * forward to the IK step in the task's null space (kc_ik_step_ff) so
 * that the step gives them back whole; every tick continuous and within
 * the limits, and every joint's jerk within qddd_max from the joint
 * move's start to the line's end (double: in float the IK step's rounding
 * alone makes jerk noise above the limits, kinctl/ik.h), ending at the
 * line's end. Without the feed-forward the step dropped the stop's
 * null-space part: qdd stepped at the takeover. */
static const kc_real PANDA_Q0[7] = {KC_R(0.0), KC_R(-0.785), KC_R(0.0), KC_R(-2.356), KC_R(0.0), KC_R(1.571),
                                    KC_R(0.785)};
#ifdef KC_REAL_FLOAT
#define JERK_JUDGED 0
#else
#define JERK_JUDGED 1
#endif

static void test_joint_move_redundant(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(77);
    int taken = 0;
    double worst = 0.0;
    for (int c = 0; c < 2 * CASES; c++) {
        setup_model(KC_MODEL_PANDA, PANDA_Q0);
        kc_goal a, b;
        memset(&a, 0, sizeof a);
        a.id = 1;
        a.kind = KC_GOAL_JOINT;
        a.vel_scale = a.acc_scale = KC_R(1.0);
        for (int j = 0; j < 7; j++)
            a.q[j] = PANDA_Q0[j] + (kc_real)kt_uniform(&r, -0.1, 0.1);
        double qdd[7] = {0.0};
        tick(&a);
        int64_t len = H.ctrl.plan.joint.ticks;
        int64_t at = 1 + (int64_t)kt_uniform(&r, 0.0, (double)(len > 3 ? len - 3 : 1));
        memset(&b, 0, sizeof b);
        int completed = 0;
        for (int64_t k = 1; k < 20000 && !completed; k++) {
            for (int j = 0; j < 7; j++) {
                double jerk = fabs((double)H.out.qdd[j] - qdd[j]) / (double)H.cfg.dt /
                              (double)H.chain.joints[j].limits.qddd_max;
                worst = fmax(worst, jerk);
                if (JERK_JUDGED && !(jerk <= 1.0 + SLACK))
                    fail_msg("case %d cycle %ld (takeover %ld) joint %d: jerk %.6g of qddd_max", c,
                             (long)H.out.cycle, (long)at, j, jerk);
                qdd[j] = (double)H.out.qdd[j];
            }
            if (k == at) {
                b = random_goal(&r, KC_GOAL_LINE, 2, rest_ahead());
                b.replace = 1;
                tick(&b);
                assert_int_equal(event_reason(KC_EVENT_ACCEPTED, b.id), KC_REASON_NONE);
                assert_true(H.ctrl.blend.on);
                assert_int_equal(H.ctrl.blend.kind, KC_GOAL_JOINT);
                taken++;
            } else {
                tick(NULL);
            }
            completed = k > at && event_reason(KC_EVENT_COMPLETED, b.id) >= 0;
        }
        assert_true(completed);
        check_end(&b);
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
        assert_int_equal(H.events[KC_EVENT_ABORTED], 0);
    }
    print_message("panda: %d joint moves taken over by a line, the joints' jerk at most %.6f of qddd_max (%s)\n",
                  taken, worst, KC_REAL_NAME);
    assert_int_equal(taken, 2 * CASES);
}

/* A line replaced mid-cruise by a line on along its direction: the new one
 * starts in the same tick (t0 = 0: the stop's deceleration and the start's
 * acceleration cancel), the tool keeps its speed through the takeover and
 * arrives sooner than after a stop. */
static void test_line_continued(void **state)
{
    (void)state;
    setup();
    kc_pose home;
    kc_fk_eval(&H.chain, KT_PUMA_Q0, &home);
    kc_goal a, b;
    memset(&a, 0, sizeof a);
    a.id = 1;
    a.kind = KC_GOAL_LINE;
    a.vel_scale = a.acc_scale = KC_R(1.0);
    a.orient = KC_INTERP_SLERP;
    a.pose = home;
    a.pose.t.v[1] += KC_R(0.2);
    b = a;
    b.id = 2;
    b.replace = 1;
    b.pose.t.v[1] += KC_R(0.08);
    tick(&a);
    /* Into the cruise (0.15 m/s after 0.56 s, jerk-limited at 0.3 m/s^2
     * and the default 5 m/s^3, 0.042 m along): at 0.7 s the line is 0.063
     * m along, its stop ends 0.042 m further, and the new line, 0.175 m
     * long from there, reaches the full speed as the stop ends, by the same
     * ramp mirrored. */
    for (int64_t k = 1; k < 700; k++)
        tick(NULL);
    double v0 = H.v_prev[1];
    tick(&b);
    assert_int_equal(event_reason(KC_EVENT_STARTED, b.id), KC_REASON_NONE);
    assert_true(H.ctrl.k0 == H.ctrl.blend.k0);
    int64_t ts = H.ctrl.blend.stop_ticks, tg = H.ctrl.plan.line.ticks;
    for (int64_t k = 1; k < ts; k++) {
        tick(NULL);
        kt_near(H.v_prev[1], v0, 1e-3 * v0 + TOOL_ABS_V, "speed through the takeover");
    }
    int64_t start = H.out.cycle;
    run_until_completed(b.id, 20000);
    check_end(&b);
    /* Sooner than a stop and then the new line: it ends with G's plan
     * (plus the tool's settling), T_s before the stop-then-start would. */
    assert_true(H.out.cycle - start + ts < ts + tg);
}

/* A replacement during a superposition, and during a STOP's or a PAUSE's
 * stop: the motion under way (the sum, or the stop) stops joint by joint
 * from the last setpoint (KC_DRIVE_HALT), superposed on the new goal, an
 * arc, which takes over in the tick (ACCEPTED with no reason) and ends at
 * its goal; every tick checked as above. */
static void test_replaced_again(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(7);
    for (int how = 0; how < 3; how++) {
        setup();
        kc_goal a = random_goal(&r, KC_GOAL_LINE, 1, H.out.pose), b, c;
        tick(&a);
        for (int k = 0; k < 300; k++)
            tick(NULL);
        if (how == 0) {
            b = random_goal(&r, KC_GOAL_LINE, 2, rest_ahead());
            b.replace = 1;
            tick(&b);
            assert_true(H.ctrl.blend.on);
            tick(NULL);
        } else {
            step(NULL, how == 1 ? KC_CMD_STOP : KC_CMD_PAUSE);
            for (int k = 0; k < 20; k++)
                tick(NULL);
            assert_int_equal(H.out.state, KC_CTRL_STOPPING);
        }
        c = random_goal(&r, KC_GOAL_ARC, 3, rest_ahead());
        c.replace = 1;
        tick(&c);
        assert_int_equal(event_reason(KC_EVENT_ACCEPTED, c.id), KC_REASON_NONE);
        assert_int_equal(event_reason(KC_EVENT_STARTED, c.id), KC_REASON_NONE);
        assert_true(H.ctrl.blend.on);
        assert_int_equal(H.ctrl.blend.stop_drive, KC_DRIVE_HALT);
        run_until_completed(c.id, 20000);
        check_end(&c);
        assert_int_equal(H.events[KC_EVENT_PREEMPTED], how == 0 ? 2 : 1);
        assert_int_equal(H.events[KC_EVENT_ABORTED], 0);
    }
}

/* A STOP and a PAUSE while a Cartesian path on the controller's ramps (a
 * clamped or a natural cubic spline) is superposed on the stop of the
 * joint move or the line it replaced, at a random tick of the overlap:
 * the path goes on as judged while that stop lasts, then stops on its
 * ramp's law (ctrl_stop.c); every tick checked as above and, in double,
 * from the end of the replaced motion's stop on, every joint's qdd
 * changing by at most qddd_max dt (with SLACK; while the two are
 * superposed the joints' jerk is what the arm's Jacobian makes of the
 * sum, as in any Cartesian motion: one natural spline in 120 cases went
 * to 1.07 times a wrist joint's limit there, STOP or not; in float the IK
 * step's rounding alone goes beyond, as test_ctrl_cartstop.c says); no
 * fault; the arm at rest, idle or paused, and a resumed path ends at its
 * goal. */
static void test_stop_while_ramped_superposed(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(29);
    int stopped = 0;
    for (int c = 0; c < 4 * CASES; c++) {
        setup();
        kc_goal a = random_goal(&r, c % 2 ? KC_GOAL_LINE : KC_GOAL_JOINT, 1, H.out.pose);
        tick(&a);
        int64_t at = 2 + (int64_t)kt_uniform(&r, 0.0, 0.6 * (double)planned_ticks());
        for (int64_t k = 1; k < at; k++)
            tick(NULL);
        kc_goal b = random_goal(&r, KC_GOAL_PATH_CART, 2, rest_ahead());
        b.method = KC_PATH_SPLINE;
        b.spline_end = c % 4 < 2 ? KC_PATH_SPLINE_CLAMPED : KC_PATH_SPLINE_NATURAL;
        b.replace = 1;
        tick(&b);
        assert_int_equal(event_reason(KC_EVENT_ACCEPTED, b.id), KC_REASON_NONE);
        assert_true(H.ctrl.blend.on && H.ctrl.ramp_on);
        int64_t end = H.ctrl.blend.k0 + H.ctrl.blend.stop_ticks;
        int64_t when = H.out.cycle + 1 + (int64_t)kt_uniform(&r, 0.0, (double)(end - H.out.cycle));
        while (H.out.cycle + 1 < when)
            tick(NULL);
        int pause = c % 3 == 0;
#ifdef KC_REAL_FLOAT
        const int check_jerk = 0;
#else
        const int check_jerk = 1;
#endif
        double qdd[KC_MAX_JOINTS];
        for (int j = 0; j < 6; j++)
            qdd[j] = (double)H.out.qdd[j];
        step(NULL, pause ? KC_CMD_PAUSE : KC_CMD_STOP);
        kc_ctrl_state rest = pause ? KC_CTRL_PAUSED : KC_CTRL_IDLE;
        for (int k = 0;; k++) {
            /* The path's own stop once M's has ended (the superposition's
             * sum: what the Jacobian makes of it, kinctl/ctrl.h). */
            for (int j = 0; j < 6 && check_jerk; j++) {
                double jerk = fabs((double)H.out.qdd[j] - qdd[j]) / (double)H.cfg.dt;
                if (!H.ctrl.blend.on && !(jerk <= (double)H.chain.joints[j].limits.qddd_max * (1.0 + SLACK)))
                    fail_msg("case %d cycle %ld joint %d: jerk %.6g of %.6g", c, (long)H.out.cycle, j, jerk,
                             (double)H.chain.joints[j].limits.qddd_max);
                qdd[j] = (double)H.out.qdd[j];
            }
            if (H.out.state == rest || k == 20000)
                break;
            tick(NULL);
            assert_int_equal(H.events[KC_EVENT_FAULT], 0);
        }
        assert_int_equal(H.out.state, rest);
        for (int j = 0; j < 6; j++)
            assert_true(H.out.qd[j] == KC_R(0.0));
        if (pause) {
            step(NULL, KC_CMD_RESUME);
            run_until_completed(b.id, 40000);
            check_end(&b);
        }
        stopped++;
    }
    print_message("%d Cartesian paths on their ramps stopped or paused while superposed (%s)\n", stopped,
                  KC_REAL_NAME);
}

/* Chains of five goals of random kinds, each replacing the one before
 * 1 to 400 ticks after it, mostly while that one is still superposed on
 * the stop of the one before it, or stopping: every Cartesian goal takes
 * over in its tick (ACCEPTED with no reason), a joint goal retargets (or,
 * where its retarget would pass a limit, stops first); every tick checked
 * as above, the last goal ending at its goal. */
static void test_chains(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(2027);
    int during = 0, cartesian = 0, refused = 0, dry_stop_first = 0;
    for (int c = 0; c < 4 * CASES; c++) {
        setup();
        /* g: the last goal handed on, v its verdict (a replacing one's) */
        kc_goal g = random_goal(&r, KINDS[(int)kt_uniform(&r, 0.0, 4.0)], 1, H.out.pose);
        kc_verdict v;
        memset(&v, 0, sizeof v);
        tick(&g);
        for (int64_t id = 2; id <= 5; id++) {
            int wait = 1 + (int)kt_uniform(&r, 0.0, 400.0);
            for (int k = 0; k < wait; k++)
                tick(NULL);
            int busy = H.ctrl.blend.on || H.out.state == KC_CTRL_STOPPING;
            kc_goal next = random_goal(&r, KINDS[(int)kt_uniform(&r, 0.0, 4.0)], id, rest_ahead());
            kc_verdict vn;
            next.replace = 1;
            if (judge(&next, &vn) != KC_OK) {
                /* kinctld refuses it: the one before goes on */
                print_message("case %d: goal %ld (kind %d, stop first %d) refused by the dry run: %s at its tick %ld\n",
                              c, (long)id, next.kind, next.stop_first, kc_ctrl_reason_str(vn.reason), (long)vn.tick);
                refused++;
                continue;
            }
            g = next;
            v = vn;
            dry_stop_first += g.stop_first;
            tick(&g);
            assert_int_equal(event_reason(KC_EVENT_ACCEPTED, id), v.reason);
            if (cart(g.kind) && !g.stop_first) {
                if (event_reason(KC_EVENT_STARTED, id) != KC_REASON_NONE)
                    fail_msg("case %d: goal %ld (kind %d) not taken over: accepted with reason %d", c, (long)id,
                             g.kind, event_reason(KC_EVENT_ACCEPTED, id));
                cartesian++;
                during += busy;
            }
        }
        run_until_completed(g.id, 20000);
        check_end(&g);
        if (g.id > 1)
            check_verdict(&v);
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
        assert_int_equal(H.events[KC_EVENT_ABORTED], 0);
    }
    print_message("%d chains: %d Cartesian goals taken over in their tick, %d of them during a superposition or a "
                  "stop; the dry run refused %d replacing goals, stopped the motion first for %d\n",
                  4 * CASES, cartesian, during, refused, dry_stop_first);
    assert_true(during > 0);
}

/* Where no transition is built the replacement stops first and says so:
 * a Cartesian path by Lagrange's polynomial (it does not start at rest)
 * under the trapezoid's law (its ramps step tau'') replacing a Cartesian
 * path, which stops on its own path; still continuous and ending at its
 * goal. */
static void test_fallbacks(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(7);
    kc_goal a, b;
    setup();
    a = random_goal(&r, KC_GOAL_PATH_CART, 1, H.out.pose);
    tick(&a);
    for (int k = 0; k < 200; k++)
        tick(NULL);
    b = random_goal(&r, KC_GOAL_PATH_CART, 2, rest_ahead());
    b.method = KC_PATH_LAGRANGE;
    b.profile = KC_GOAL_PROFILE_TRAPEZOID;
    b.replace = 1;
    tick(&b);
    assert_int_equal(event_reason(KC_EVENT_ACCEPTED, b.id), KC_REASON_STOP_FIRST);
    assert_false(H.ctrl.blend.on);
    assert_int_equal(H.ctrl.drive, KC_DRIVE_SCURVE); /* on its path, jerk-limited */
    assert_string_equal(kc_ctrl_reason_str(KC_REASON_STOP_FIRST),
                        "no continuous transition from the motion it replaces: that motion stops first");
    run_until_completed(b.id, 20000);
    check_end(&b);
}

/* A replacing goal that cannot be planned from where the replaced path's
 * stop joint by joint comes to rest (a line of 20 cm at 1e-5 m/s: more
 * ticks than a profile holds), after the path's own plan gave way to it:
 * the path goes on stopping joint by joint (kc_ctrl_halting), the goal
 * waits for it (KC_REASON_STOP_FIRST) and is then aborted, unplannable
 * (KC_REASON_PLAN). A Cartesian path and a joint path; every tick within
 * the joints' limits, their jerk too, and the arm at rest in the end. */
static void test_plan_fails(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(11);
    for (int i = 0; i < 2; i++) {
        setup();
        kc_goal a = random_goal(&r, KC_GOAL_PATH_CART, 1, H.out.pose), b;
        if (i == 1) {
            a.kind = KC_GOAL_PATH;
            for (int k = 0; k < 2; k++)
                for (int j = 0; j < 6; j++)
                    a.points[k][j] = KT_PUMA_Q0[j] + (kc_real)(0.1 * (k + 1));
        }
        tick(&a);
        for (int k = 0; k < 200; k++)
            tick(NULL);
        kc_pose to = rest_ahead();
        to.t.v[0] += KC_R(0.2);
        b = kt_line_goal(2, &to);
        b.speed = KC_R(1e-5);
        b.replace = 1;
        double qdd[KC_MAX_JOINTS];
        for (int j = 0; j < 6; j++)
            qdd[j] = (double)H.out.qdd[j];
        tick(&b);
        assert_int_equal(event_reason(KC_EVENT_ACCEPTED, b.id), KC_REASON_STOP_FIRST);
        assert_false(H.ctrl.blend.on);
        assert_int_equal(H.ctrl.drive, KC_DRIVE_HALT);
        int aborted = -1;
        for (int k = 0; k < 20000 && aborted < 0; k++) {
            for (int j = 0; j < 6; j++) {
                double jerk = fabs((double)H.out.qdd[j] - qdd[j]) / (double)H.cfg.dt;
                if (!(jerk <= (double)H.chain.joints[j].limits.qddd_max * (1.0 + SLACK)))
                    fail_msg("cycle %ld joint %d: jerk %.6g", (long)H.out.cycle, j, jerk);
                qdd[j] = (double)H.out.qdd[j];
            }
            tick(NULL);
            aborted = event_reason(KC_EVENT_ABORTED, b.id);
        }
        assert_int_equal(aborted, KC_REASON_PLAN);
        assert_int_equal(H.events[KC_EVENT_PREEMPTED], 1);
        assert_int_equal(H.events[KC_EVENT_FAULT], 0);
        assert_int_equal(H.out.state, KC_CTRL_IDLE);
        for (int j = 0; j < 6; j++)
            assert_true(H.out.qd[j] == KC_R(0.0));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_pair),
        cmocka_unit_test(test_joint_stops),
        cmocka_unit_test(test_joint_move_redundant),
        cmocka_unit_test(test_line_continued),
        cmocka_unit_test(test_replaced_again),
        cmocka_unit_test(test_stop_while_ramped_superposed),
        cmocka_unit_test(test_chains),
        cmocka_unit_test(test_fallbacks),
        cmocka_unit_test(test_plan_fails),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("ctrl_blend");
    return rc;
}
