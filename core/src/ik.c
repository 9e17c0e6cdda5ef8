/* SPDX-License-Identifier: BSD-3-Clause */
/* ik.c - inverse kinematics by integrating qdot = J^+ U with the dual
 * quaternion feedback law of seed 002; damping, limits and redundancy as
 * documented in kinctl/ik.h. */
#include "kinctl/ik.h"

#include "fk_internal.h"
#include "ik_internal.h"

kc_ik_cfg kc_ik_cfg_default(void)
{
    kc_ik_cfg c;
    c.mask = KC_IK_MASK_FULL;
    c.gain_rot = KC_R(20.0);
    c.gain_pos = KC_R(20.0);
    c.gain_step = KC_R(1.0);
#ifdef KC_REAL_FLOAT
    c.tol_pos = KC_R(1e-5);
    c.tol_rot = KC_R(1e-4);
#else
    c.tol_pos = KC_R(1e-10);
    c.tol_rot = KC_R(1e-10);
#endif
    c.max_steps = 100;
    c.max_restarts = 100;
    c.max_step = KC_R(1.0);
    c.damping_max = KC_R(0.05);
    c.manip_threshold = KC_R(1e-3);
    c.null_gain = KC_R(0.5);
    c.limit_margin = KC_R(0.05);
    for (int i = 0; i < KC_MAX_JOINTS; i++)
        c.q_rest[i] = KC_R(0.0);
    c.use_rest = 0;
    c.seed = 0x6b696e63746cULL; /* "kinctl" */
    return c;
}

/* Inlined: kc_ik_step checks the configuration every tick, and fourteen
 * calls cost more than the tests. */
KC_ALWAYS_INLINE int positive(kc_real x) { return kc_isfinite(x) && x > KC_R(0.0); }

kc_status kc_ik_cfg_check(const kc_ik_cfg *cfg, const kc_chain *chain)
{
    if (cfg == NULL || chain == NULL)
        return KC_E_ARG;
    if ((unsigned)cfg->mask > (unsigned)KC_IK_MASK_AXIS)
        return KC_E_ARG;
    if (!positive(cfg->gain_rot) || !positive(cfg->gain_pos) || !positive(cfg->gain_step) ||
        cfg->gain_step > KC_R(1.0))
        return KC_E_ARG;
    if (!positive(cfg->tol_pos) || !positive(cfg->tol_rot) || !positive(cfg->max_step))
        return KC_E_ARG;
    if (cfg->max_steps < 1 || cfg->max_restarts < 0)
        return KC_E_ARG;
    if (!positive(cfg->damping_max) || !positive(cfg->manip_threshold))
        return KC_E_ARG;
    if (!kc_isfinite(cfg->null_gain) || cfg->null_gain < KC_R(0.0))
        return KC_E_ARG;
    if (!kc_isfinite(cfg->limit_margin) || cfg->limit_margin < KC_R(0.0) || cfg->limit_margin >= KC_R(0.5))
        return KC_E_ARG;
    if (cfg->use_rest)
        for (int j = 0; j < chain->n_joints; j++)
            if (!kc_isfinite(cfg->q_rest[j]))
                return KC_E_ARG;
    return KC_OK;
}

/* ---- the task: error and Jacobian rows ---- */

/* The task error at pose cur, in the base frame: rows 0-2 the translation
 * error (m), then the rotation rows. pos_err and rot_err get the magnitudes.
 * Full task: seed 002's law on M = conj(L) o L*, returned unscaled (k = 1):
 * w = 2 sgn(M_r.w) R vec(M_r), v = R vec(2 M_d o conj(M_r)) = t* - t.
 * Axis task: the rotation that turns the tool z onto the target's z, as its
 * components along the tool's x and y (the z component is free). */
static void task_error(kc_ik_mask mask, const kc_pose *cur, const kc_dquat *target_dq, const kc_pose *target,
                       kc_real e[6], kc_real *pos_err, kc_real *rot_err)
{
    kc_dquat l, lc, m;
    kc_dquat_from_pose(cur, &l);
    kc_dquat_conj(&l, &lc);
    kc_dquat_mul(&lc, target_dq, &m);

    kc_quat mrc, vt;
    kc_quat_conj(&m.r, &mrc);
    kc_quat_mul(&m.d, &mrc, &vt); /* half the translation error, tool frame */
    kc_vec3 v = kc_vec3_make(KC_R(2.0) * vt.x, KC_R(2.0) * vt.y, KC_R(2.0) * vt.z);
    kc_mat3_mul_vec(&cur->R, &v, &v);
    e[0] = v.v[0];
    e[1] = v.v[1];
    e[2] = v.v[2];
    *pos_err = kc_vec3_norm(&v);

    if (mask == KC_IK_MASK_FULL) {
        kc_real sgn = m.r.w < KC_R(0.0) ? KC_R(-2.0) : KC_R(2.0);
        kc_vec3 w = kc_vec3_make(sgn * m.r.x, sgn * m.r.y, sgn * m.r.z);
        kc_real s = KC_R(0.5) * kc_vec3_norm(&w);
        *rot_err = KC_R(2.0) * kc_atan2(s, kc_fabs(m.r.w));
        kc_mat3_mul_vec(&cur->R, &w, &w);
        e[3] = w.v[0];
        e[4] = w.v[1];
        e[5] = w.v[2];
    } else if (mask == KC_IK_MASK_AXIS) {
        kc_vec3 z = kc_vec3_make(cur->R.m[0][2], cur->R.m[1][2], cur->R.m[2][2]);
        kc_vec3 zt = kc_vec3_make(target->R.m[0][2], target->R.m[1][2], target->R.m[2][2]);
        kc_vec3 c;
        kc_vec3_cross(&z, &zt, &c);
        kc_real sn = kc_vec3_norm(&c), cs = kc_vec3_dot(&z, &zt);
        kc_real angle = kc_atan2(sn, cs);
        kc_vec3 axis;
        if (sn > KC_REAL_EPS) {
            kc_vec3_scale(&c, angle / sn, &axis);
        } else if (cs < KC_R(0.0)) {
            /* Anti-parallel: any axis normal to z turns it over; take x. */
            axis = kc_vec3_make(cur->R.m[0][0] * angle, cur->R.m[1][0] * angle, cur->R.m[2][0] * angle);
        } else {
            axis = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
        }
        /* Components along the tool's x and y axes. */
        e[3] = cur->R.m[0][0] * axis.v[0] + cur->R.m[1][0] * axis.v[1] + cur->R.m[2][0] * axis.v[2];
        e[4] = cur->R.m[0][1] * axis.v[0] + cur->R.m[1][1] * axis.v[1] + cur->R.m[2][1] * axis.v[2];
        *rot_err = angle;
    } else {
        *rot_err = KC_R(0.0);
    }
}

/* The task's rows of the Jacobian, in place in jac (no copy for the full
 * and position tasks): for the axis task rows 3 and 4 become the angular
 * rows along the tool's x and y axes, matching task_error. */
static kc_real (*task_jacobian(kc_ik_mask mask, kc_jacobian *jac, const kc_pose *cur, int n))[KC_MAX_JOINTS]
{
    if (mask == KC_IK_MASK_AXIS) {
        for (int j = 0; j < n; j++) {
            kc_real wx = jac->m[3][j], wy = jac->m[4][j], wz = jac->m[5][j];
            jac->m[3][j] = cur->R.m[0][0] * wx + cur->R.m[1][0] * wy + cur->R.m[2][0] * wz;
            jac->m[4][j] = cur->R.m[0][1] * wx + cur->R.m[1][1] * wy + cur->R.m[2][1] * wz;
        }
    }
    return jac->m;
}

/* ---- one damped least-squares step ---- */

static void problem_init(kc_ik_problem *p, const kc_chain *chain, const kc_ik_cfg *cfg)
{
    p->chain = chain;
    p->cfg = cfg;
    p->n = chain->n_joints;
    p->r = kc_ik_task_rows(cfg->mask);
    p->singular_damping = 1;
    for (int j = 0; j < p->n; j++) {
        const kc_joint_limits *l = &chain->joints[j].limits;
        p->lo[j] = l->q_min;
        p->hi[j] = l->q_max;
        if (p->n <= p->r)
            continue;
        int bounded = kc_isfinite(l->q_min) && kc_isfinite(l->q_max);
        p->range[j] = bounded && l->q_max > l->q_min ? l->q_max - l->q_min : KC_R(2.0) * KC_PI;
        if (cfg->use_rest)
            p->rest[j] = cfg->q_rest[j];
        else
            p->rest[j] = bounded ? KC_R(0.5) * (l->q_min + l->q_max) : KC_R(0.0);
    }
}

/* The kernel with the task size as a constant, so that the compiler
 * unrolls the r x r products and the factorisation for each task. Built
 * for size, only the full task keeps its unrolled copy, which the IK
 * step's instruction budget on a Cortex-M4F needs (4,900 against 7,900
 * rolled); the position and axis tasks share the rolled kernel (1.4 KB
 * less). The unrolled copy is then a function of its own, so that the
 * rolled kernel's frame is never stacked on top of its frame. */
#ifdef __OPTIMIZE_SIZE__
static __attribute__((noinline)) kc_real dls_full(const kc_ik_problem *p, kc_real jt[6][KC_MAX_JOINTS],
                                                  const kc_real *u, kc_real lambda2, kc_real null_scale,
                                                  kc_real null_bound, const kc_real *q, const uint8_t *frozen,
                                                  kc_real *dq)
{
    return kc_ik_dls_kernel(p, jt, u, lambda2, null_scale, null_bound, q, frozen, dq, 6);
}

static kc_real dls_solve(const kc_ik_problem *p, kc_real jt[6][KC_MAX_JOINTS], const kc_real *u, kc_real lambda2,
                         kc_real null_scale, kc_real null_bound, const kc_real *q, const uint8_t *frozen, kc_real *dq)
{
    if (p->r != 6)
        return kc_ik_dls_rolled(p, jt, u, lambda2, null_scale, null_bound, q, frozen, dq);
    return dls_full(p, jt, u, lambda2, null_scale, null_bound, q, frozen, dq);
}
#else
static kc_real dls_solve(const kc_ik_problem *p, kc_real jt[6][KC_MAX_JOINTS], const kc_real *u, kc_real lambda2,
                         kc_real null_scale, kc_real null_bound, const kc_real *q, const uint8_t *frozen, kc_real *dq)
{
    switch (p->r) {
    case 3: return kc_ik_dls_kernel(p, jt, u, lambda2, null_scale, null_bound, q, frozen, dq, 3);
    case 5: return kc_ik_dls_kernel(p, jt, u, lambda2, null_scale, null_bound, q, frozen, dq, 5);
    default: return kc_ik_dls_kernel(p, jt, u, lambda2, null_scale, null_bound, q, frozen, dq, 6);
    }
}
#endif

/* Solves, then freezes every joint at a limit that the step would push
 * beyond and solves again (at most twice: freezing only grows). */
static kc_real limited_step(const kc_ik_problem *p, kc_real jt[6][KC_MAX_JOINTS], const kc_real *u, kc_real lambda2,
                            kc_real null_scale, kc_real null_bound, const kc_real *q, kc_real *dq, int *n_frozen)
{
    uint8_t frozen[KC_MAX_JOINTS] = {0};
    kc_real w = KC_R(0.0);
    int count = 0;
    for (int pass = 0; pass < 3; pass++) {
        int more = 0;
        w = dls_solve(p, jt, u, lambda2, null_scale, null_bound, q, frozen, dq);
        for (int j = 0; j < p->n; j++) {
            if (!frozen[j] && ((q[j] >= p->hi[j] && dq[j] > KC_R(0.0)) || (q[j] <= p->lo[j] && dq[j] < KC_R(0.0)))) {
                frozen[j] = 1;
                more = 1;
                count++;
            }
        }
        if (!more)
            break;
    }
    if (n_frozen != NULL)
        *n_frozen = count;
    return w;
}

static void clamp_q(const kc_ik_problem *p, kc_real *q)
{
    for (int j = 0; j < p->n; j++)
        q[j] = kc_clamp(q[j], p->lo[j], p->hi[j]);
}

/* ---- workspace bound ---- */

kc_real kc_ik_reach(const kc_chain *chain)
{
    kc_real reach = kc_vec3_norm(&chain->tool.t);
    for (int e = 0; e < chain->n_elements; e++) {
        const kc_element *el = &chain->elements[e];
        if (el->code >= KC_CODE_TX && el->code <= KC_CODE_TZ) {
            reach += kc_fabs(el->value);
        } else if (el->code >= KC_CODE_TX_JOINT && el->code <= KC_CODE_TZ_JOINT) {
            const kc_joint *j = &chain->joints[el->joint];
            reach += kc_max(kc_fabs(j->limits.q_min + j->offset), kc_fabs(j->limits.q_max + j->offset));
        }
    }
    return reach;
}

/* ---- solve to convergence ---- */

/* Errors below which kc_ik_solve drops the null-space term (m, rad). */
#define KC_IK_POLISH_POS KC_R(1e-3)
#define KC_IK_POLISH_ROT KC_R(1e-3)
/* Steps over which the cost must halve before an attempt counts as stalled.
 * Measured on 1000 random puma560 and panda targets from random starts: a
 * window of 4 (against 6, 8, 10) halves the median and the p99 solve time at
 * the same success rate. An attempt that fails is almost always one pinned
 * at a joint limit on the way to a branch it cannot reach, and a new start
 * is cheaper than waiting. */
#define KC_IK_STALL_WINDOW 4
/* Steps pinned at a joint limit after which an attempt restarts. Measured
 * on 5000 random targets from random starts against 1, 2, 5 and never:
 * puma560 p99 134 -> 109 Jacobians, panda 96 -> 83, success unchanged. */
#define KC_IK_PIN_GIVE_UP 3
/* lambda^2 = c |e|^2 in solve (Sugihara's error damping; c = 0.05 measured
 * best of 0.5, 0.05 and 0.005 on random puma560 and panda targets). */
#define KC_IK_ERROR_DAMPING KC_R(0.05)

/* splitmix64: a small, well-mixed generator for restart configurations. */
static uint64_t next_random(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static void random_q(const kc_ik_problem *p, uint64_t *state, kc_real *q)
{
    for (int j = 0; j < p->n; j++) {
        kc_real u = (kc_real)(next_random(state) >> 11) * (kc_real)(1.0 / 9007199254740992.0);
        kc_real lo = kc_isfinite(p->lo[j]) ? p->lo[j] : -KC_PI;
        kc_real hi = kc_isfinite(p->hi[j]) ? p->hi[j] : KC_PI;
        q[j] = lo + u * (hi - lo);
    }
}

KC_ALWAYS_INLINE int q_valid(const kc_chain *chain, const kc_real *q)
{
    for (int j = 0; j < chain->n_joints; j++)
        if (!kc_isfinite(q[j]))
            return 0;
    return 1;
}

/* Why the best configuration of a failed solve stops short: a joint at a
 * position limit that the next step would push beyond (KC_E_LIMIT), else a
 * singular task Jacobian (manipulability below the threshold: the arm
 * cannot move towards the target, e.g. beyond a stretched elbow), else
 * plain non-convergence. */
static kc_status classify_miss(const kc_ik_problem *p, const kc_dquat *target_dq, const kc_pose *target, const kc_real *q)
{
    kc_jacobian jac;
    kc_pose cur;
    kc_real e[6], pos_err, rot_err, dq[KC_MAX_JOINTS];
    uint8_t frozen[KC_MAX_JOINTS] = {0};
    kc_ik_problem probe = *p;
    probe.singular_damping = 1; /* to get the manipulability back */
    kc_fk_jacobian_checked(p->chain, q, &jac, &cur);
    task_error(p->cfg->mask, &cur, target_dq, target, e, &pos_err, &rot_err);
    kc_real(*jt)[KC_MAX_JOINTS] = task_jacobian(p->cfg->mask, &jac, &cur, p->n);
    kc_real w = dls_solve(&probe, jt, e, KC_R(0.0), KC_R(0.0), KC_R(0.0), q, frozen, dq);
    /* Pushes beyond a limit by more than rounding of the step itself. */
    for (int j = 0; j < p->n; j++)
        if ((q[j] >= p->hi[j] && dq[j] > KC_TOL_SMALL_ANGLE) || (q[j] <= p->lo[j] && dq[j] < -KC_TOL_SMALL_ANGLE))
            return KC_E_LIMIT;
    if (w < p->cfg->manip_threshold)
        return KC_E_SINGULAR;
    return KC_E_NOCONVERGE;
}

kc_status kc_ik_solve(const kc_chain *chain, const kc_ik_cfg *cfg, const kc_pose *target, const kc_real *q0,
                      kc_real *q_out, kc_ik_result *res)
{
    if (chain == NULL || cfg == NULL || target == NULL || q0 == NULL || q_out == NULL || res == NULL)
        return KC_E_ARG;
    if (kc_ik_cfg_check(cfg, chain) != KC_OK || !kc_pose_isfinite(target) || !q_valid(chain, q0) ||
        !(kc_mat3_rotation_error(&target->R) <= KC_TOL_ORTHONORMAL))
        return KC_E_ARG;

    kc_vec3 d;
    kc_vec3_sub(&target->t, &chain->base.t, &d);
    if (kc_vec3_norm(&d) > kc_ik_reach(chain)) {
        res->status = KC_E_UNREACHABLE;
        res->steps = res->restarts = 0;
        res->pos_err = res->rot_err = KC_R(0.0);
        return KC_E_UNREACHABLE;
    }

    kc_ik_problem p;
    problem_init(&p, chain, cfg);
    /* The error damping and the step bound keep solve's steps finite at a
     * singularity; extra damping there would only slow the last digits. */
    p.singular_damping = 0;
    kc_dquat target_dq;
    kc_dquat_from_pose(target, &target_dq);

    kc_real q[KC_MAX_JOINTS], best_q[KC_MAX_JOINTS], dq[KC_MAX_JOINTS];
    kc_real best_cost = KC_REAL_MAX, best_pos = KC_REAL_MAX, best_rot = KC_REAL_MAX;
    kc_jacobian jac;
    kc_pose cur;
    uint64_t rng = cfg->seed;
    int steps = 0, attempt;
    kc_status status = KC_E_NOCONVERGE;

    for (int j = 0; j < p.n; j++)
        q[j] = q0[j];
    clamp_q(&p, q);
    for (int j = 0; j < p.n; j++)
        best_q[j] = q[j];

    for (attempt = 0; attempt <= cfg->max_restarts && status != KC_OK; attempt++) {
        if (attempt > 0) {
            /* Every other restart, a joint the failed attempt left pinned
             * at a limit starts within the tenth of its range next to the
             * other limit: the branch it was heading for lies beyond the
             * limit, and a twin of it may lie near the other end (measured
             * on 5000 random targets: misses 9 -> 6 on puma560). */
            int8_t pinned[KC_MAX_JOINTS] = {0};
            for (int j = 0; j < p.n; j++)
                pinned[j] = (int8_t)(q[j] >= p.hi[j] ? 1 : (q[j] <= p.lo[j] ? -1 : 0));
            random_q(&p, &rng, q);
            for (int j = 0; j < p.n && attempt % 2 == 1; j++) {
                if (pinned[j] > 0 && kc_isfinite(p.lo[j]))
                    q[j] = p.lo[j] + KC_R(0.1) * (q[j] - p.lo[j]);
                else if (pinned[j] < 0 && kc_isfinite(p.hi[j]))
                    q[j] = p.hi[j] - KC_R(0.1) * (p.hi[j] - q[j]);
            }
        }
        int pinned_steps = 0;
        /* Cost history for stall detection. */
        kc_real history[KC_IK_STALL_WINDOW];
        for (int i = 0; i < KC_IK_STALL_WINDOW; i++)
            history[i] = KC_REAL_MAX;
        for (int s = 0; s < cfg->max_steps; s++) {
            kc_real e[6], pos_err, rot_err;
            kc_fk_jacobian_checked(chain, q, &jac, &cur);
            steps++;
            task_error(cfg->mask, &cur, &target_dq, target, e, &pos_err, &rot_err);
            kc_real cost = KC_R(0.0);
            for (int i = 0; i < p.r; i++)
                cost += e[i] * e[i];
            if (cost < best_cost) {
                best_cost = cost;
                best_pos = pos_err;
                best_rot = rot_err;
                for (int j = 0; j < p.n; j++)
                    best_q[j] = q[j];
            }
            if (pos_err <= cfg->tol_pos && rot_err <= cfg->tol_rot) {
                status = KC_OK;
                break;
            }
            /* Progress: the cost must halve over the window, else restart. */
            if (s >= KC_IK_STALL_WINDOW && cost > KC_R(0.5) * history[s % KC_IK_STALL_WINDOW])
                break;
            history[s % KC_IK_STALL_WINDOW] = cost;

            kc_real u[6];
            for (int i = 0; i < p.r; i++)
                u[i] = cfg->gain_step * e[i];
            kc_real(*jt)[KC_MAX_JOINTS] = task_jacobian(cfg->mask, &jac, &cur, p.n);
            /* Close to the target the null-space motion stops: its curvature
             * would keep feeding a small task error back every step, and
             * plain Gauss-Newton finishes quadratically. */
            kc_real null_gain = pos_err < KC_IK_POLISH_POS && rot_err < KC_IK_POLISH_ROT ? KC_R(0.0) : cfg->null_gain;
            /* The null step shrinks with the task error, so its curvature
             * cannot hold the task error up. */
            kc_real null_bound = kc_min(cfg->max_step, kc_sqrt(cost));
            int n_frozen = 0;
            limited_step(&p, jt, u, KC_IK_ERROR_DAMPING * cost, null_gain, null_bound, q, dq, &n_frozen);
            /* An attempt held at a joint limit for KC_IK_PIN_GIVE_UP steps
             * in a row, far from the target, is heading for a branch beyond
             * the limit: restart at once (in the first half of the
             * restarts; the second half runs every attempt out). */
            pinned_steps = n_frozen > 0 ? pinned_steps + 1 : 0;
            if (pinned_steps >= KC_IK_PIN_GIVE_UP && attempt < cfg->max_restarts / 2 && pos_err > KC_IK_POLISH_POS)
                break;

            kc_real biggest = KC_R(0.0);
            for (int j = 0; j < p.n; j++)
                biggest = kc_max(biggest, kc_fabs(dq[j]));
            kc_real scale = biggest > cfg->max_step ? cfg->max_step / biggest : KC_R(1.0);
            for (int j = 0; j < p.n; j++)
                q[j] += scale * dq[j];
            clamp_q(&p, q);
        }
    }

    if (status != KC_OK)
        status = classify_miss(&p, &target_dq, target, best_q);
    for (int j = 0; j < p.n; j++)
        q_out[j] = best_q[j];
    res->status = status;
    res->steps = steps;
    res->restarts = attempt - 1;
    res->pos_err = best_pos;
    res->rot_err = best_rot;
    return status;
}

/* ---- one online step ---- */

kc_real kc_ik_online_gain(kc_real k, kc_real dt) { return kc_min(k, KC_R(1.0) / dt); }

kc_status kc_ik_step(const kc_chain *chain, const kc_ik_cfg *cfg, const kc_pose *target, const kc_real *twist_ff,
                     kc_real dt, const kc_real *q, const kc_real *qd, kc_real *q_next, kc_real *qd_next,
                     kc_ik_result *res)
{
    return kc_ik_step_ff(chain, cfg, target, twist_ff, NULL, dt, q, qd, q_next, qd_next, res);
}

kc_status kc_ik_step_ff(const kc_chain *chain, const kc_ik_cfg *cfg, const kc_pose *target, const kc_real *twist_ff,
                        const kc_real *qd_ff, kc_real dt, const kc_real *q, const kc_real *qd, kc_real *q_next,
                        kc_real *qd_next, kc_ik_result *res)
{
    if (chain == NULL || cfg == NULL || target == NULL || q == NULL || qd == NULL || q_next == NULL ||
        qd_next == NULL || res == NULL)
        return KC_E_ARG;
    if (kc_ik_cfg_check(cfg, chain) != KC_OK || !positive(dt) || !kc_pose_isfinite(target) ||
        !q_valid(chain, q) || !q_valid(chain, qd) || (qd_ff != NULL && !q_valid(chain, qd_ff)))
        return KC_E_ARG;

    kc_ik_problem p;
    problem_init(&p, chain, cfg);
    kc_dquat target_dq;
    kc_dquat_from_pose(target, &target_dq);
    kc_jacobian jac;
    kc_pose cur;
    /* task_error fills the p.r rows of e that the mask uses. The small
     * arrays here are cleared by unrolled stores: a memset call costs more. */
    kc_real e[6], ff[6], pos_err, rot_err, qd_des[KC_MAX_JOINTS];
    int n = p.n;
    KC_UNROLL
    for (int i = 0; i < 6; i++)
        e[i] = ff[i] = KC_R(0.0);

    kc_fk_jacobian_checked(chain, q, &jac, &cur);
    task_error(cfg->mask, &cur, &target_dq, target, e, &pos_err, &rot_err);
    res->steps = 1;
    res->restarts = 0;
    res->pos_err = pos_err;
    res->rot_err = rot_err;

    /* The feed-forward twist in the task's rows (as task_jacobian). */
    int moving_target = 0;
    if (twist_ff != NULL) {
        for (int i = 0; i < 6; i++) {
            if (!kc_isfinite(twist_ff[i]))
                return KC_E_ARG;
            moving_target |= twist_ff[i] != KC_R(0.0);
        }
        for (int i = 0; i < 3; i++)
            ff[i] = twist_ff[i];
        if (cfg->mask == KC_IK_MASK_FULL) {
            for (int i = 3; i < 6; i++)
                ff[i] = twist_ff[i];
        } else if (cfg->mask == KC_IK_MASK_AXIS) {
            for (int a = 0; a < 2; a++)
                ff[3 + a] = cur.R.m[0][a] * twist_ff[3] + cur.R.m[1][a] * twist_ff[4] + cur.R.m[2][a] * twist_ff[5];
        }
    }

    /* Done when within tolerance, the target still, and slow enough to stop
     * in this tick without exceeding an acceleration limit, nor a jerk
     * limit: the stop takes qdd to -qd/dt and the next tick back to 0, so
     * |qd| <= qddd_max dt^2 / 2, half, leaves room for the qdd of the tick
     * before (the settling law's) and for a motion started from here,
     * whose first tick the law may give that velocity again (with the
     * whole qddd_max dt^2, Panda lines stopped and started again stepped
     * qdd by 1.002 x qddd_max dt). Unless qd moves q by less than a few
     * units of its last place over the tick (float: about 5e-4 rad/s at 1
     * ms, above qddd_max dt^2; the law's rounding keeps qd there). */
    int at_rest = !moving_target && pos_err <= cfg->tol_pos && rot_err <= cfg->tol_rot;
    for (int j = 0; j < n && at_rest; j++) {
        const kc_joint_limits *l = &chain->joints[j].limits;
        kc_real ulps = KC_R(4.0) * KC_REAL_EPS * kc_max(kc_fabs(q[j]), KC_R(1.0)) / dt;
        at_rest = kc_fabs(qd[j]) <= kc_min(l->qdd_max * dt, kc_max(KC_R(0.5) * l->qddd_max * dt * dt, ulps));
    }
    if (at_rest) {
        for (int j = 0; j < n; j++) {
            q_next[j] = q[j];
            qd_next[j] = KC_R(0.0);
        }
        res->status = KC_DONE;
        return KC_DONE;
    }

    /* Every row (e and ff are 0 past p.r, and so u: -O3 cannot tell that
     * those rows go unread). */
    kc_real u[6], k_pos = kc_ik_online_gain(cfg->gain_pos, dt), k_rot = kc_ik_online_gain(cfg->gain_rot, dt);
    KC_UNROLL
    for (int i = 0; i < 6; i++)
        u[i] = ff[i] + (i < 3 ? k_pos : k_rot) * e[i];
    kc_real(*jt)[KC_MAX_JOINTS] = task_jacobian(cfg->mask, &jac, &cur, n);
    /* qd_ff's null-space part, J^+ (u - J qd_ff) + qd_ff = J^+ u + (I -
     * J^+ J) qd_ff: its task part taken out of u, and all of it added. */
    int null_ff = qd_ff != NULL && n > p.r;
    for (int i = 0; i < p.r && null_ff; i++)
        for (int j = 0; j < n; j++)
            u[i] -= jt[i][j] * qd_ff[j];
    /* The null-space velocity stays below half the slowest joint's limit
     * (only a redundant task has one). */
    kc_real null_bound = KC_REAL_MAX;
    for (int j = 0; j < n && n > p.r; j++)
        null_bound = kc_min(null_bound, chain->joints[j].limits.qd_max);
    kc_real w = limited_step(&p, jt, u, KC_R(0.0), cfg->null_gain, null_bound, q, qd_des, NULL);
    for (int j = 0; j < n && null_ff; j++)
        qd_des[j] += qd_ff[j];

    /* One scale for the whole command keeps the tool on its direction:
     * first the velocity limits, then the acceleration limits from qd. */
    kc_real s = KC_R(1.0);
    for (int j = 0; j < n; j++) {
        kc_real lim = chain->joints[j].limits.qd_max;
        if (kc_fabs(qd_des[j]) * s > lim)
            s = lim / kc_fabs(qd_des[j]);
    }
    if (!moving_target) {
        /* Towards a still target no faster than each joint can brake in the
         * way left, |qd| <= sqrt(2 qdd_max |dq|) with dq ~ qd_des / gain: the
         * law alone asks gain |dq|, which the acceleration limit then carries
         * past the target (a 2 cm jump of a servo target was overshot by
         * 2 cm; with the bound by 0.06 mm in double, 0.8 mm in float, where
         * one scale for every joint's acceleration slows some braking). */
        kc_real gain = kc_max(k_pos, k_rot);
        for (int j = 0; j < n; j++) {
            kc_real v = kc_fabs(qd_des[j]);
            if (v > KC_R(0.0)) {
                kc_real brake = kc_sqrt(KC_R(2.0) * chain->joints[j].limits.qdd_max / (gain * v));
                if (brake < s)
                    s = brake;
            }
        }
    }
    /* Towards a position limit no faster than the joint can brake before
     * it in whole ticks: slowing by A dt a tick from v covers
     * dt v (v / (A dt) + 1) / 2, so v <= (sqrt(A^2 dt^2 + 8 A room) - A dt) / 2.
     * Stopped at the limit by a velocity step instead, the joint failed the
     * controller's final check, whose stop from full speed then carried it
     * past the limit. A is half the acceleration limit, since one scale for
     * every joint's acceleration may slow this joint's braking. */
    for (int j = 0; j < n; j++) {
        kc_real v = kc_fabs(qd_des[j]);
        kc_real room = qd_des[j] > KC_R(0.0) ? p.hi[j] - q[j] : q[j] - p.lo[j];
        if (v > KC_R(0.0) && kc_isfinite(room)) {
            kc_real A = KC_R(0.5) * chain->joints[j].limits.qdd_max, Adt = A * dt;
            kc_real vmax = KC_R(0.5) * (kc_sqrt(Adt * Adt + KC_R(8.0) * A * kc_max(room, KC_R(0.0))) - Adt);
            if (v * s > vmax)
                s = vmax / v;
        }
    }
    kc_real a = KC_R(1.0);
    for (int j = 0; j < n; j++) {
        kc_real dv = kc_fabs(s * qd_des[j] - qd[j]);
        kc_real lim = chain->joints[j].limits.qdd_max * dt;
        if (dv * a > lim)
            a = lim / dv;
    }
    kc_status status = w < cfg->manip_threshold ? KC_E_SINGULAR : KC_OK;
    for (int j = 0; j < n; j++) {
        kc_real v = qd[j] + a * (s * qd_des[j] - qd[j]);
        kc_real qn = q[j] + v * dt;
        if (qn > p.hi[j] || qn < p.lo[j]) {
            qn = kc_clamp(qn, p.lo[j], p.hi[j]);
            v = KC_R(0.0);
            status = KC_E_LIMIT;
        }
        q_next[j] = qn;
        qd_next[j] = v;
    }
    res->status = status;
    return status;
}
