/* SPDX-License-Identifier: BSD-3-Clause */
/* test_interp.c - single-segment interpolators (seed 001 labs 4, 5, 6;
 * kinctl/interp.h): every case of vectors/joint_trapezoid.json,
 * cartesian_line.json and circle.json, then properties on random segments,
 * the degenerate cases and bad inputs.
 *
 * Tolerances against the files. double: their 1e-9 absolute. float: the
 * reference is double; the float build rounds every input (poses, limits,
 * dt: half an ulp), forms t = k dt, and computes each value in a few tens
 * of operations (a quaternion product, a conversion to a matrix, sums of
 * three terms) on quantities no larger than the largest value of that
 * quantity in the case (its scale, taken at least 1). The errors add up to
 * tens of ulps of the scale: 64 KC_REAL_EPS * scale (7.6e-6 * scale) bounds
 * them with a factor of about three to spare. The planes of lab 6 are
 * computed from cross products of chords: the circle's centre then carries
 * eps / sin(angle at T1) relative error; the files' circles have angles of
 * at least 2 degrees at T1 (sin > 0.03), so the same bound holds with the
 * scale of the positions. Acceleration and phase jump at phase boundaries:
 * the files list samples that fall on one (1e-9); in float a sample within 8
 * ulps of a boundary is as ambiguous and is skipped the same way.
 *
 * Properties allow rounding only: limits hold to 16 KC_REAL_EPS relative.
 */
#include "testutil.h"

#include <stdio.h>
#include <string.h>

#ifdef KC_REAL_FLOAT
#define FLOAT_BUILD 1
#else
#define FLOAT_BUILD 0
#endif

#define N_RANDOM 300
#define LIMIT_SLACK (16.0 * (double)KC_REAL_EPS)
#define INF ((kc_real)INFINITY)
#define DINF ((double)INFINITY)
#define DNAN ((double)NAN)

/* Phase boundaries of a profile, and whether (in float) t sits on one. */
static int near_boundary(double t, const kc_profile *p)
{
    double b[3] = {(double)p->t1, (double)p->t2, (double)p->T};
    if (!FLOAT_BUILD)
        return 0;
    for (int i = 0; i < 3; i++)
        if (fabs(t - b[i]) <= 8.0 * (double)KC_REAL_EPS * (b[i] > 1.0 ? b[i] : 1.0))
            return 1;
    return 0;
}

static void quat_to_rowmajor(const kc_quat *q, double out[9])
{
    kc_mat3 R;
    kc_quat_to_mat3(q, &R);
    for (int i = 0; i < 9; i++)
        out[i] = (double)R.m[i / 3][i % 3];
}

static kc_interp_limits limits(double v, double a, double w, double dw)
{
    kc_interp_limits l = kc_interp_limits_default();
    l.v = (kc_real)v;
    l.a = (kc_real)a;
    l.w = (kc_real)w;
    l.dw = (kc_real)dw;
    return l;
}

/* Samples on the 10 ms grid are ticks of dt = 0.01; the last one is the end
 * time T, off the grid, rounded to 13 digits in the file: tick `ticks`. */
static int64_t sample_tick(const json_t *ts, size_t i, const kc_profile *p, double T, const char *name)
{
    char what[160];
    double t = kt_num(json_array_get(ts, i));
    if (i + 1 < json_array_size(ts)) {
        snprintf(what, sizeof what, "%s: sample %zu on the grid", name, i);
        kt_near(t, 0.01 * (double)i, 1e-12, what);
        return (int64_t)i;
    }
    snprintf(what, sizeof what, "%s: last sample at T", name);
    kt_near(t, T, 1e-11, what);
    return p->ticks;
}

/* ---- vectors: joint_trapezoid.json ---- */

static void test_joint_vectors(void **state)
{
    (void)state;
    json_t *root = kt_load("joint_trapezoid.json");
    const json_t *cases = kt_get(root, "cases");
    char what[160];
    size_t passed = 0;
    assert_true(kt_num_of(kt_get(root, "tolerance"), "abs") == 1e-9);
    for (size_t c = 0; c < json_array_size(cases); c++) {
        const json_t *cs = kt_at(cases, c), *smp = kt_get(cs, "samples");
        const char *name = json_string_value(kt_get(cs, "case"));
        kc_real q0[2], q1[2], vm[2], am[2];
        kt_read_reals(kt_get(cs, "q_start_deg"), q0, 2);
        kt_read_reals(kt_get(cs, "q_end_deg"), q1, 2);
        vm[0] = vm[1] = (kc_real)kt_num_of(cs, "v_deg_s");
        am[0] = am[1] = (kc_real)kt_num_of(cs, "A_deg_s2");
        kc_interp_joint plan;
        assert_int_equal(kc_interp_joint_plan(&plan, 2, q0, q1, vm, am, KC_R(0.0), KC_R(0.01)), KC_OK);
        /* (4.1)-(4.5): dq, leading joint, K_i, joint speeds. */
        const json_t *lj = kt_get(cs, "leading_joint");
        int lead = json_is_null(lj) ? -1 : (int)kt_num(lj) - 1;
        snprintf(what, sizeof what, "%s: leading joint", name);
        kt_near(plan.lead, lead, 0.0, what);
        kt_near_reals_json(plan.dq, 2, kt_get(cs, "dq_deg"), kt_traj_tol(180.0), what);
        double T = kt_num_of(cs, "T_total_s"), tp = kt_num_of(cs, "t_p_s"), tpv = kt_num_of(cs, "t_pv_s");
        if (lead >= 0) {
            double ql = fabs((double)plan.dq[lead]);
            kc_real K[2] = {plan.dq[0] / (kc_real)ql, plan.dq[1] / (kc_real)ql}, vj[2] = {K[0] * vm[0], K[1] * vm[1]};
            snprintf(what, sizeof what, "%s: K", name);
            kt_near_reals_json(K, 2, kt_get(cs, "K"), kt_traj_tol(1.0), what);
            snprintf(what, sizeof what, "%s: joint speeds (4.5)", name);
            kt_near_reals_json(vj, 2, kt_get(cs, "v_joint_deg_s"), kt_traj_tol((double)vm[0]), what);
            /* (4.6)-(4.9) in the leading joint's units: q = q_lead u. */
            snprintf(what, sizeof what, "%s: q_p (4.7)", name);
            kt_near(ql * (double)plan.prof.pc, kt_num_of(cs, "q_p_deg"), kt_traj_tol(ql), what);
            snprintf(what, sizeof what, "%s: peak speed", name);
            kt_near(ql * (double)plan.prof.vc, kt_num_of(cs, "v_peak_lead_deg_s"), kt_traj_tol((double)vm[0]), what);
        }
        snprintf(what, sizeof what, "%s: t_p (4.6)", name);
        kt_near((double)plan.prof.t1, tp, kt_traj_tol(T), what);
        snprintf(what, sizeof what, "%s: t_pv (4.9)", name);
        kt_near((double)(plan.prof.t2 - plan.prof.t1), tpv, kt_traj_tol(T), what);
        snprintf(what, sizeof what, "%s: T", name);
        kt_near((double)plan.prof.T, T, kt_traj_tol(T), what);
        const json_t *ts = kt_get(smp, "t_s"), *ph = kt_get(smp, "phase"), *amb = kt_get(smp, "qddot_ambiguous_indices");
        const json_t *Q = kt_get(smp, "q_deg"), *QD = kt_get(smp, "qdot_deg_s"), *QDD = kt_get(smp, "qddot_deg_s2");
        double sq = kt_max_abs_json(Q), sv = kt_max_abs_json(QD), sa = kt_max_abs_json(QDD);
        for (size_t i = 0; i < json_array_size(ts); i++) {
            int64_t k = sample_tick(ts, i, &plan.prof, T, name);
            double t = kt_num(json_array_get(ts, i));
            kc_interp_joint_state st;
            assert_int_equal(kc_interp_joint_eval(&plan, k, &st), k < plan.prof.ticks ? KC_OK : KC_DONE);
            for (size_t j = 0; j < 2; j++) {
                snprintf(what, sizeof what, "%s: q%zu at t = %g", name, j + 1, t);
                kt_near((double)st.q[j], kt_num(kt_at(kt_at(Q, j), i)), kt_traj_tol(sq), what);
                snprintf(what, sizeof what, "%s: qdot%zu at t = %g", name, j + 1, t);
                kt_near((double)st.qd[j], kt_num(kt_at(kt_at(QD, j), i)), kt_traj_tol(sv), what);
                if (kt_index_listed(amb, i) || near_boundary(t, &plan.prof))
                    continue;
                snprintf(what, sizeof what, "%s: qddot%zu at t = %g", name, j + 1, t);
                kt_near((double)st.qdd[j], kt_num(kt_at(kt_at(QDD, j), i)), kt_traj_tol(sa), what);
            }
            if (!kt_index_listed(amb, i) && !near_boundary(t, &plan.prof)) {
                snprintf(what, sizeof what, "%s: phase at t = %g", name, t);
                kt_near(st.phase, kt_num(json_array_get(ph, i)), 0.0, what);
            }
            if (k == plan.prof.ticks) /* exactly the target */
                assert_true(st.q[0] == q1[0] && st.q[1] == q1[1] && st.qd[0] == KC_R(0.0) && st.qdd[1] == KC_R(0.0));
        }
        passed++;
    }
    printf("joint_trapezoid.json: %zu/%zu cases pass\n", passed, json_array_size(cases));
    json_decref(root);
}

/* ---- vectors: cartesian_line.json ---- */

static void test_line_vectors(void **state)
{
    (void)state;
    json_t *root = kt_load("cartesian_line.json");
    const json_t *cases = kt_get(root, "cases");
    char what[160];
    size_t passed = 0;
    assert_true(kt_num_of(kt_get(root, "tolerance"), "abs") == 1e-9);
    for (size_t c = 0; c < json_array_size(cases); c++) {
        const json_t *cs = kt_at(cases, c), *smp = kt_get(cs, "samples"), *tm = kt_get(cs, "timing");
        const char *name = json_string_value(kt_get(cs, "case"));
        kc_pose P1, P2, P3;
        kt_read_pose(kt_get(cs, "P1_corrected"), &P1);
        kt_read_pose(kt_get(cs, "P2_corrected"), &P2);
        double v = kt_num_of(cs, "v"), A = kt_num_of(cs, "A_used"), T = kt_num_of(tm, "T_total");
        kc_interp_limits lim = limits(v, A, DINF, DINF);
        kc_interp_line plan;
        assert_int_equal(kc_interp_line_plan(&plan, &P1, &P2, &lim, KC_INTERP_TWO_ROTATIONS, KC_R(0.01)), KC_OK);
        /* P3 (5.1), S (5.7), K (5.8-5.10). */
        double S = kt_num_of(cs, "S");
        double pscale = kt_max_abs_json(kt_get(cs, "P2_corrected")) + kt_max_abs_json(kt_get(cs, "P1_corrected"));
        kc_pose inv;
        kc_pose_inv(&P1, &inv);
        kc_pose_mul(&inv, &P2, &P3);
        snprintf(what, sizeof what, "%s: P3 (5.1)", name);
        kt_near_pose_json(&P3, kt_get(cs, "P3"), kt_traj_tol(pscale), what);
        snprintf(what, sizeof what, "%s: S (5.7)", name);
        kt_near((double)plan.length, S, kt_traj_tol(pscale), what);
        kc_vec3 K;
        kc_mat3_tmul_vec(&P1.R, &plan.dp, &K);
        kc_vec3_scale(&K, KC_R(1.0) / plan.length, &K);
        snprintf(what, sizeof what, "%s: K_xyz (5.8-5.10)", name);
        kt_near_reals_json(K.v, 3, kt_get(cs, "Kx_Ky_Kz"), kt_traj_tol(1.0) * (FLOAT_BUILD ? pscale / S : 1.0), what);
        /* (5.18-5.21) and (5.22-5.23). */
        snprintf(what, sizeof what, "%s: psi (5.18)", name);
        kt_near((double)plan.psi, kt_num_of(cs, "psi_rad"), kt_traj_tol(KT_PI), what);
        snprintf(what, sizeof what, "%s: theta (5.19)", name);
        kt_near((double)plan.theta, kt_num_of(cs, "theta_rad"), kt_traj_tol(KT_PI), what);
        snprintf(what, sizeof what, "%s: phi (5.20-5.21)", name);
        kt_near((double)plan.phi, kt_num_of(cs, "phi_rad"), kt_traj_tol(KT_PI), what);
        snprintf(what, sizeof what, "%s: K_theta (5.22)", name);
        kt_near((double)(plan.theta / plan.length), kt_num_of(cs, "K_theta"), kt_traj_tol(KT_PI / S), what);
        snprintf(what, sizeof what, "%s: K_phi (5.23)", name);
        kt_near((double)(plan.phi / plan.length), kt_num_of(cs, "K_phi"), kt_traj_tol(KT_PI / S), what);
        /* (5.3-5.6) */
        snprintf(what, sizeof what, "%s: t_p (5.3)", name);
        kt_near((double)plan.prof.t1, kt_num_of(tm, "t_p"), kt_traj_tol(T), what);
        snprintf(what, sizeof what, "%s: t_pv (5.6)", name);
        kt_near((double)(plan.prof.t2 - plan.prof.t1), kt_num_of(tm, "t_pv"), kt_traj_tol(T), what);
        snprintf(what, sizeof what, "%s: T", name);
        kt_near((double)plan.prof.T, T, kt_traj_tol(T), what);
        snprintf(what, sizeof what, "%s: peak speed", name);
        kt_near((double)(plan.prof.vc * plan.length), kt_num_of(tm, "v_peak"), kt_traj_tol(v), what);
        const json_t *ts = kt_get(smp, "t_s"), *ph = kt_get(smp, "phase"), *amb = kt_get(smp, "qddot_ambiguous_indices");
        const json_t *Ss = kt_get(smp, "S"), *Sd = kt_get(smp, "Sdot"), *Sdd = kt_get(smp, "Sddot");
        const json_t *ps = kt_get(smp, "p"), *Rs = kt_get(smp, "R_rowmajor");
        const json_t *th = kt_get(smp, "theta_j"), *phj = kt_get(smp, "phi_j");
        double sS = kt_max_abs_json(Ss), sSd = kt_max_abs_json(Sd), sSdd = kt_max_abs_json(Sdd), sp = kt_max_abs_json(ps);
        for (size_t i = 0; i < json_array_size(ts); i++) {
            int64_t k = sample_tick(ts, i, &plan.prof, T, name);
            double t = kt_num(json_array_get(ts, i)), R[9];
            kc_interp_cart_state st;
            assert_int_equal(kc_interp_line_eval(&plan, k, &st), k < plan.prof.ticks ? KC_OK : KC_DONE);
            snprintf(what, sizeof what, "%s: S at t = %g (5.7.1-5.7.3)", name, t);
            kt_near((double)st.s, kt_num(json_array_get(Ss, i)), kt_traj_tol(sS), what);
            snprintf(what, sizeof what, "%s: Sdot at t = %g", name, t);
            kt_near((double)st.sd, kt_num(json_array_get(Sd, i)), kt_traj_tol(sSd), what);
            snprintf(what, sizeof what, "%s: p at t = %g (5.11-5.13, 5.2)", name, t);
            kt_near_reals_json(st.p.v, 3, kt_at(ps, i), kt_traj_tol(sp), what);
            quat_to_rowmajor(&st.q, R);
            snprintf(what, sizeof what, "%s: R at t = %g (5.14-5.16, 5.24-5.25)", name, t);
            for (size_t e = 0; e < 9; e++)
                kt_near(R[e], kt_num(kt_at(kt_at(Rs, i), e)), kt_traj_tol(1.0), what);
            snprintf(what, sizeof what, "%s: theta_j at t = %g (5.24)", name, t);
            kt_near((double)(plan.theta * st.u), kt_num(json_array_get(th, i)), kt_traj_tol(KT_PI), what);
            snprintf(what, sizeof what, "%s: phi_j at t = %g (5.25)", name, t);
            kt_near((double)(plan.phi * st.u), kt_num(json_array_get(phj, i)), kt_traj_tol(KT_PI), what);
            if (kt_index_listed(amb, i) || near_boundary(t, &plan.prof))
                continue;
            snprintf(what, sizeof what, "%s: Sddot at t = %g", name, t);
            kt_near((double)st.sdd, kt_num(json_array_get(Sdd, i)), kt_traj_tol(sSdd), what);
            snprintf(what, sizeof what, "%s: phase at t = %g", name, t);
            kt_near(st.phase, kt_num(json_array_get(ph, i)), 0.0, what);
        }
        /* The end is P2 exactly (position bit for bit). */
        kc_interp_cart_state st;
        assert_int_equal(kc_interp_line_eval(&plan, plan.prof.ticks, &st), KC_DONE);
        assert_true(st.p.v[0] == P2.t.v[0] && st.p.v[1] == P2.t.v[1] && st.p.v[2] == P2.t.v[2]);
        kc_mat3 Re;
        kc_quat_to_mat3(&st.q, &Re);
        snprintf(what, sizeof what, "%s: end orientation R2", name);
        kt_near_mat3(&Re, &P2.R, kt_traj_tol(1.0), what);
        passed++;
    }
    printf("cartesian_line.json: %zu/%zu cases pass\n", passed, json_array_size(cases));
    json_decref(root);
}

/* ---- vectors: circle.json ---- */

static void test_circle_vectors(void **state)
{
    (void)state;
    json_t *root = kt_load("circle.json");
    const json_t *cases = kt_get(root, "cases");
    char what[160];
    size_t passed = 0;
    assert_true(kt_num_of(kt_get(root, "tolerance"), "abs") == 1e-9);
    for (size_t c = 0; c < json_array_size(cases); c++) {
        const json_t *cs = kt_at(cases, c), *smp = kt_get(cs, "samples"), *tm = kt_get(cs, "timing");
        const char *name = json_string_value(kt_get(cs, "case"));
        kc_pose T1;
        kc_vec3 T2, T3;
        kt_read_pose(kt_get(cs, "T1_corrected"), &T1);
        kt_read_reals(kt_get(cs, "T2_position"), T2.v, 3);
        kt_read_reals(kt_get(cs, "T3_position"), T3.v, 3);
        double v = kt_num_of(cs, "v"), A = kt_num_of(cs, "A_used"), T = kt_num_of(tm, "T_total");
        double pscale = kt_max_abs_json(kt_get(cs, "T1_corrected")) + kt_max_abs_json(kt_get(cs, "T3_position"));
        kc_interp_limits lim = limits(v, A, DINF, DINF);
        kc_interp_arc plan;
        assert_int_equal(kc_interp_arc_plan(&plan, &T1, &T2, &T3, &lim, KC_R(0.01)), KC_OK);
        snprintf(what, sizeof what, "%s: centre", name);
        kt_near_reals_json(plan.centre.v, 3, kt_get(cs, "centre"), kt_traj_tol(pscale), what);
        snprintf(what, sizeof what, "%s: radius", name);
        kt_near((double)plan.radius, kt_num_of(cs, "radius"), kt_traj_tol(pscale), what);
        snprintf(what, sizeof what, "%s: normal", name);
        kt_near_reals_json(plan.normal.v, 3, kt_get(cs, "normal_used"), kt_traj_tol(1.0), what);
        snprintf(what, sizeof what, "%s: swept angle alpha (6.21 corrected)", name);
        kt_near((double)plan.angle, kt_num_of(cs, "alpha_rad"), kt_traj_tol(2.0 * KT_PI), what);
        snprintf(what, sizeof what, "%s: angle of T2", name);
        kt_near((double)plan.angle_via, kt_num_of(cs, "alpha_to_T2_rad"), kt_traj_tol(2.0 * KT_PI), what);
        snprintf(what, sizeof what, "%s: arc length", name);
        kt_near((double)plan.length, kt_num_of(cs, "arc_length"), kt_traj_tol(pscale * 2.0 * KT_PI), what);
        double R = kt_num_of(cs, "radius"), omega = kt_num_of(cs, "omega");
        snprintf(what, sizeof what, "%s: t_p", name);
        kt_near((double)plan.prof.t1, kt_num_of(tm, "t_p"), kt_traj_tol(T), what);
        snprintf(what, sizeof what, "%s: T", name);
        kt_near((double)plan.prof.T, T, kt_traj_tol(T), what);
        /* The peak of alpha' is omega = v / R (trapezoid) or the triangle's. */
        snprintf(what, sizeof what, "%s: peak angular speed", name);
        kt_near((double)(plan.prof.vc * plan.angle), kt_num_of(tm, "v_peak"), kt_traj_tol(omega), what);
        /* The pose at the end by (6.1), with T3's position exactly. */
        kc_interp_cart_state st;
        kc_pose end;
        assert_int_equal(kc_interp_arc_eval(&plan, plan.prof.ticks, &st), KC_DONE);
        assert_true(st.p.v[0] == T3.v[0] && st.p.v[1] == T3.v[1] && st.p.v[2] == T3.v[2]);
        kc_quat_to_mat3(&st.q, &end.R);
        end.t = st.p;
        snprintf(what, sizeof what, "%s: T_end", name);
        kt_near_pose_json(&end, kt_get(cs, "T_end"), kt_traj_tol(pscale), what);
        const json_t *ts = kt_get(smp, "t_s"), *ph = kt_get(smp, "phase"), *amb = kt_get(smp, "qddot_ambiguous_indices");
        const json_t *al = kt_get(smp, "alpha"), *ald = kt_get(smp, "alphadot"), *aldd = kt_get(smp, "alphaddot");
        const json_t *ps = kt_get(smp, "p"), *Rs = kt_get(smp, "R_rowmajor");
        double sa = 2.0 * KT_PI, sad = kt_max_abs_json(ald), sadd = kt_max_abs_json(aldd), sp = kt_max_abs_json(ps);
        for (size_t i = 0; i < json_array_size(ts); i++) {
            int64_t k = sample_tick(ts, i, &plan.prof, T, name);
            double t = kt_num(json_array_get(ts, i)), Rm[9];
            assert_int_equal(kc_interp_arc_eval(&plan, k, &st), k < plan.prof.ticks ? KC_OK : KC_DONE);
            snprintf(what, sizeof what, "%s: alpha at t = %g (6.23-6.25)", name, t);
            kt_near((double)(plan.angle * st.u), kt_num(json_array_get(al, i)), kt_traj_tol(sa), what);
            kt_near((double)st.s / R, kt_num(json_array_get(al, i)), kt_traj_tol(sa), what);
            snprintf(what, sizeof what, "%s: alphadot at t = %g", name, t);
            kt_near((double)st.sd / R, kt_num(json_array_get(ald, i)), kt_traj_tol(sad), what);
            snprintf(what, sizeof what, "%s: p at t = %g (6.1)", name, t);
            kt_near_reals_json(st.p.v, 3, kt_at(ps, i), kt_traj_tol(sp), what);
            quat_to_rowmajor(&st.q, Rm);
            snprintf(what, sizeof what, "%s: R at t = %g (6.1)", name, t);
            for (size_t e = 0; e < 9; e++)
                kt_near(Rm[e], kt_num(kt_at(kt_at(Rs, i), e)), kt_traj_tol(1.0), what);
            if (kt_index_listed(amb, i) || near_boundary(t, &plan.prof))
                continue;
            snprintf(what, sizeof what, "%s: alphaddot at t = %g", name, t);
            kt_near((double)st.sdd / R, kt_num(json_array_get(aldd, i)), kt_traj_tol(sadd), what);
            snprintf(what, sizeof what, "%s: phase at t = %g", name, t);
            kt_near(st.phase, kt_num(json_array_get(ph, i)), 0.0, what);
        }
        passed++;
    }
    printf("circle.json: %zu/%zu cases pass\n", passed, json_array_size(cases));
    json_decref(root);
}

/* ---- properties: joint move ---- */

static double rand_dt(kt_rng *r)
{
    static const double dts[] = {0.001, 0.002, 0.004, 0.01, 0.0005, 1.0 / 3000.0};
    return dts[kt_rng_next(r) % 6];
}

/* Rest-to-rest time over D with (v, a), as the lab 4 formulas give it. */
static double move_time(double D, double v, double a)
{
    return D * a >= v * v ? D / v + v / a : 2.0 * sqrt(D / a);
}

static void check_joint_walk(const kc_interp_joint *p, const kc_real *qdmax, const kc_real *qddmax, const char *what)
{
    kc_interp_joint_state st, prev;
    int n = p->n;
    double dt = (double)p->prof.dt, peak_v = 0.0, peak_a = 0.0;
    assert_int_equal(kc_interp_joint_eval(p, 0, &prev), p->prof.ticks > 0 ? KC_OK : KC_DONE);
    for (int i = 0; i < n; i++)
        assert_true(p->prof.ticks == 0 ? prev.q[i] == p->q1[i] : prev.q[i] == p->q0[i]); /* exact start */
    for (int64_t k = 1; k <= p->prof.ticks; k++) {
        kc_status s = kc_interp_joint_eval(p, k, &st);
        assert_int_equal(s, k < p->prof.ticks ? KC_OK : KC_DONE);
        double ref = -1.0, ref_err = 0.0; /* fraction done, the same for every moving joint */
        for (int i = 0; i < n; i++) {
            double lim_v = (double)qdmax[i], lim_a = (double)qddmax[i], d = (double)p->dq[i];
            assert_true(fabs((double)st.qd[i]) <= lim_v * (1.0 + LIMIT_SLACK));
            assert_true(fabs((double)st.qdd[i]) <= lim_a * (1.0 + LIMIT_SLACK));
            /* Within qdd_max dt per tick, up to the rounding of qd (of the
             * speed limit's size) and of t = k dt (qdd_max eps t). */
            double lim_vi = isfinite(lim_v) ? lim_v : fabs((double)p->prof.vc * d);
            kt_near((double)st.qd[i], (double)prev.qd[i],
                    lim_a * dt * (1.0 + LIMIT_SLACK) + 4.0 * (double)KC_REAL_EPS * (lim_vi + lim_a * (double)k * dt),
                    what);
            kt_near((double)(st.q[i] - prev.q[i]), 0.5 * (double)(st.qd[i] + prev.qd[i]) * dt,
                    0.25 * lim_a * dt * dt + 16.0 * (double)KC_REAL_EPS * (fabs((double)p->q0[i]) + fabs(d)), what);
            if (d != 0.0 && fabs(d) > 1e-3) {
                /* Synchronised: the same fraction for every joint. q - q0
                 * carries the rounding of q (|q| <= 3): eps 3 / |d| in f. */
                double f = (double)(st.q[i] - p->q0[i]) / d, err = 4.0 * (double)KC_REAL_EPS * (1.0 + 3.0 / fabs(d));
                if (ref < 0.0) {
                    ref = f;
                    ref_err = err;
                }
                kt_near(f, ref, err + ref_err, what);
                peak_v = fmax(peak_v, fabs((double)st.qd[i]) / lim_v);
                peak_a = fmax(peak_a, fabs((double)st.qdd[i]) / lim_a);
            }
        }
        prev = st;
    }
    for (int i = 0; i < n; i++) /* exact end */
        assert_true(prev.q[i] == p->q1[i] && prev.qd[i] == KC_R(0.0) && prev.qdd[i] == KC_R(0.0));
    /* Time optimal (or stretched with the acceleration kept): some joint
     * reaches its acceleration limit, unless the move is shorter than a
     * tick or two and no tick falls inside phase 1. */
    if (p->prof.t1 > p->prof.dt && p->lead_acc >= 0 && fabs((double)p->dq[p->lead_acc]) > 1e-3)
        assert_true(peak_a >= 1.0 - LIMIT_SLACK);
    (void)peak_v;
}

static void test_joint_properties(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x10147);
    for (int t = 0; t < N_RANDOM; t++) {
        int n = 1 + (int)(kt_rng_next(&r) % KC_MAX_JOINTS);
        kc_real q0[KC_MAX_JOINTS], q1[KC_MAX_JOINTS], vm[KC_MAX_JOINTS], am[KC_MAX_JOINTS];
        double dt = rand_dt(&r);
        for (int i = 0; i < n; i++) {
            q0[i] = (kc_real)kt_uniform(&r, -3.0, 3.0);
            q1[i] = kt_uniform(&r, 0.0, 1.0) < 0.15 ? q0[i] : (kc_real)kt_uniform(&r, -3.0, 3.0);
            vm[i] = kt_uniform(&r, 0.0, 1.0) < 0.1 ? INF : (kc_real)kt_uniform(&r, 0.2, 3.0);
            am[i] = (kc_real)kt_uniform(&r, 1.0, 20.0);
        }
        if (t % 10 == 0) /* the seed's case: equal limits */
            for (int i = 0; i < n; i++) {
                vm[i] = vm[0] == INF ? KC_R(1.0) : vm[0];
                am[i] = am[0];
            }
        kc_interp_joint p;
        assert_int_equal(kc_interp_joint_plan(&p, n, q0, q1, vm, am, KC_R(0.0), (kc_real)dt), KC_OK);
        /* The leading joint needs the longest time of its own. */
        double Tlead = -1.0;
        int lead = -1;
        for (int i = 0; i < n; i++) {
            double D = fabs((double)(q1[i] - q0[i]));
            if (D == 0.0)
                continue;
            double Ti = move_time(D, (double)vm[i], (double)am[i]);
            if (Ti > Tlead * (1.0 + 1e-12)) {
                Tlead = Ti;
                lead = i;
            }
        }
        if (lead >= 0 && lead != p.lead) /* a near tie may go either way in rounding */
            kt_near(move_time(fabs((double)p.dq[p.lead]), (double)vm[p.lead], (double)am[p.lead]), Tlead,
                    1e-9 * Tlead + (FLOAT_BUILD ? 1e-5 * Tlead : 0.0), "leading joint");
        if (lead < 0)
            assert_int_equal(p.lead, -1);
        /* Never faster than the leading joint alone; equal when one joint
         * binds both limits. */
        if (lead >= 0) {
            assert_true((double)p.prof.T >= Tlead * (1.0 - 1e-9 - 1e-5 * FLOAT_BUILD));
            if (p.lead_vel == p.lead_acc)
                kt_near((double)p.prof.T, Tlead, Tlead * (1e-9 + 1e-5 * FLOAT_BUILD), "T = leading joint's time");
        }
        check_joint_walk(&p, vm, am, "joint move");
        /* Stretched for synchronisation: exactly the asked duration. */
        if (p.prof.T > KC_R(0.0)) {
            kc_interp_joint ps;
            kc_real Td = p.prof.T * (kc_real)kt_uniform(&r, 1.0, 2.5);
            assert_int_equal(kc_interp_joint_plan(&ps, n, q0, q1, vm, am, Td, (kc_real)dt), KC_OK);
            assert_true(ps.prof.T == Td);
            check_joint_walk(&ps, vm, am, "stretched joint move");
            assert_int_equal(kc_interp_joint_plan(&ps, n, q0, q1, vm, am, p.prof.T * KC_R(0.9), (kc_real)dt), KC_E_LIMIT);
        }
    }
}

/* ---- properties: Cartesian segments ---- */

/* Rotation vector of q (kc_quat_log) with q taken the short way. */
static kc_vec3 rotvec(kc_quat q)
{
    kc_vec3 w;
    if (q.w < KC_R(0.0)) {
        q.w = -q.w;
        q.x = -q.x;
        q.y = -q.y;
        q.z = -q.z;
    }
    kc_quat_log(&q, &w);
    return w;
}

/* What every Cartesian segment must do, tick by tick: unit, continuous
 * quaternions; the speed law within v and a (path length, or angle);
 * velocities consistent with the positions and orientations; the angular
 * speed within w; exact ends. acc_lin and acc_ang bound |dv/dt| and
 * |dw/dt| (the caller derives them from the plan): over one tick the step
 * then differs from the mean velocity times dt by at most acc dt^2 / 4 (a
 * velocity that turns round inside the tick, as at a triangle's peak), and
 * a rotation step from the mean angular velocity also by the commutator of
 * the turning axis, below |w|^2 dt^2. */
static void check_cart_walk(kc_status (*eval)(const void *, int64_t, kc_interp_cart_state *), const void *plan,
                            const kc_profile *prof, const kc_interp_limits *lim, double D_v, double D_a,
                            double acc_lin, double acc_ang, const kc_vec3 *p_start, const kc_vec3 *p_end,
                            const char *what)
{
    kc_interp_cart_state st, prev;
    double dt = (double)prof->dt;
    double pscale = (double)kc_vec3_norm(p_start) + (double)kc_vec3_norm(p_end) + 1.0;
    assert_int_equal(eval(plan, 0, &prev), prof->ticks > 0 ? KC_OK : KC_DONE);
    st = prev; /* the last tick's state, also for a plan of tick 0 only */
    if (prof->ticks > 0)
        assert_true(prev.p.v[0] == p_start->v[0] && prev.p.v[1] == p_start->v[1] && prev.p.v[2] == p_start->v[2]);
    for (int64_t k = 1; k <= prof->ticks; k++) {
        kc_status s = eval(plan, k, &st);
        assert_int_equal(s, k < prof->ticks ? KC_OK : KC_DONE);
        kt_near((double)kc_quat_norm(&st.q), 1.0, 8.0 * (double)KC_REAL_EPS, what);
        /* The speed law: sd within D_v, sdd within D_a (v and a, or w and
         * dw for a pure rotation). */
        assert_true(fabs((double)st.sd) <= D_v * (1.0 + LIMIT_SLACK));
        assert_true(fabs((double)st.sdd) <= D_a * (1.0 + LIMIT_SLACK));
        assert_true((double)kc_vec3_norm(&st.v) <= (double)lim->v * (1.0 + LIMIT_SLACK) + 1e-300);
        assert_true((double)kc_vec3_norm(&st.w) <= (double)lim->w * (1.0 + LIMIT_SLACK) + 1e-300);
        for (int i = 0; i < 3; i++)
            kt_near((double)(st.p.v[i] - prev.p.v[i]), 0.5 * (double)(st.v.v[i] + prev.v.v[i]) * dt,
                    0.25 * acc_lin * dt * dt * (1.0 + 1e-6) + 32.0 * (double)KC_REAL_EPS * pscale, what);
        kc_quat qc, dq;
        kc_quat_conj(&prev.q, &qc);
        kc_quat_mul(&st.q, &qc, &dq);
        /* No sign flip between ticks. */
        assert_true((double)(st.q.w * prev.q.w + st.q.x * prev.q.x + st.q.y * prev.q.y + st.q.z * prev.q.z) > 0.0);
        kc_vec3 rv = rotvec(dq);
        double wmax = fmax((double)kc_vec3_norm(&st.w), (double)kc_vec3_norm(&prev.w));
        for (int i = 0; i < 3; i++)
            kt_near((double)rv.v[i], 0.5 * (double)(st.w.v[i] + prev.w.v[i]) * dt,
                    0.25 * acc_ang * dt * dt * (1.0 + 1e-6) + wmax * wmax * dt * dt + 64.0 * (double)KC_REAL_EPS, what);
        prev = st;
    }
    assert_true(st.p.v[0] == p_end->v[0] && st.p.v[1] == p_end->v[1] && st.p.v[2] == p_end->v[2]);
    assert_true(st.phase == 4 && st.sd == KC_R(0.0) && kc_vec3_norm(&st.v) == KC_R(0.0));
}

/* Bounds of |dv/dt| and |dw/dt| on a line: u'' S, and u'' Theta plus, for
 * two rotations, the turning of the second axis u'^2 |theta phi|. */
static void line_acc(const kc_interp_line *p, double *lin, double *ang)
{
    double a = fabs((double)p->prof.a1) + fabs((double)p->prof.a3), v = fabs((double)p->prof.vc);
    *lin = a * (double)p->length;
    *ang = a * (double)p->angle + (p->orient == KC_INTERP_TWO_ROTATIONS ? v * v * fabs((double)(p->theta * p->phi)) : 0.0);
}

/* On an arc: tangential u'' L plus centripetal R alpha'^2; angular u'' alpha. */
static void arc_acc(const kc_interp_arc *p, double *lin, double *ang)
{
    double a = fabs((double)p->prof.a1) + fabs((double)p->prof.a3), v = fabs((double)p->prof.vc) * (double)p->angle;
    *lin = a * (double)p->length + v * v * (double)p->radius;
    *ang = a * (double)p->angle;
}

static kc_status line_eval(const void *p, int64_t k, kc_interp_cart_state *out)
{
    return kc_interp_line_eval(p, k, out);
}

static kc_status arc_eval(const void *p, int64_t k, kc_interp_cart_state *out)
{
    return kc_interp_arc_eval(p, k, out);
}

static void check_line_walk(const kc_interp_line *p, const kc_interp_limits *lim, double D_v, double D_a,
                            const kc_vec3 *p_start, const kc_vec3 *p_end, const char *what)
{
    double al, aa;
    line_acc(p, &al, &aa);
    check_cart_walk(line_eval, p, &p->prof, lim, D_v, D_a, al, aa, p_start, p_end, what);
}

/* The end orientation the path itself reaches (tick ticks - 1 plus at most
 * one tick of rotation) matches the target. */
static void check_line_end(const kc_interp_line *p, const kc_pose *to, const char *what)
{
    kc_interp_cart_state st;
    kc_mat3 R;
    kc_quat q;
    assert_int_equal(kc_interp_line_eval(p, p->prof.ticks, &st), KC_DONE);
    kc_quat_to_mat3(&st.q, &R);
    kt_near_mat3(&R, &to->R, 16.0 * (double)KC_REAL_EPS, what);
    if (p->prof.ticks > 0) {
        kc_interp_cart_state last;
        kc_interp_line_eval(p, p->prof.ticks - 1, &last);
        kc_quat c;
        kc_quat_conj(&last.q, &c);
        kc_quat_mul(&st.q, &c, &q);
        kc_vec3 rv = rotvec(q);
        /* At most the last tick's rotation: |w| <= u' Theta <= A_u dt Theta. */
        double lim = (double)p->angle * (double)p->prof.a1 * (double)p->prof.dt * (double)p->prof.dt +
                     (double)p->angle * 1e-6 + 1e-5 * FLOAT_BUILD + 1e-12;
        assert_true((double)kc_vec3_norm(&rv) <= lim);
    }
}

static kc_pose rand_pose_near(kt_rng *r, const kc_pose *base, double dist, double angle)
{
    kc_pose p = *base;
    kc_vec3 d = kt_rand_unit(r), ax = kt_rand_unit(r);
    kc_mat3 Rot;
    for (int i = 0; i < 3; i++)
        p.t.v[i] += (kc_real)dist * d.v[i];
    kc_orient_axis_angle_to_mat3(&ax, (kc_real)angle, &Rot);
    kc_mat3_mul(&base->R, &Rot, &p.R);
    return p;
}

static void test_line_properties(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0x11AE);
    for (int t = 0; t < N_RANDOM; t++) {
        kc_pose a = kt_rand_pose(&r);
        double dist = t % 9 == 0 ? 0.0 : kt_uniform(&r, 0.0, 1.5), ang = kt_uniform(&r, 0.0, 3.1);
        kc_pose b = rand_pose_near(&r, &a, dist, ang);
        kc_interp_orient m = t % 2 ? KC_INTERP_SLERP : KC_INTERP_TWO_ROTATIONS;
        double w = t % 3 == 0 ? (double)INFINITY : kt_uniform(&r, 0.3, 3.0), dw = t % 3 == 0 && dist > 0 ? (double)INFINITY : kt_uniform(&r, 1.0, 10.0);
        kc_interp_limits lim = limits(kt_uniform(&r, 0.05, 1.0), kt_uniform(&r, 0.2, 5.0), w, dw);
        kc_interp_line p;
        assert_int_equal(kc_interp_line_plan(&p, &a, &b, &lim, m, (kc_real)rand_dt(&r)), KC_OK);
        double D_v = p.length > KC_R(0.0) ? (double)lim.v : (double)lim.w;
        double D_a = p.length > KC_R(0.0) ? (double)lim.a : (double)lim.dw;
        check_line_walk(&p, &lim, D_v, D_a, &a.t, &b.t, "line");
        check_line_end(&p, &b, "line end orientation");
        /* On the segment: p = p1 + (s / S) (p2 - p1). */
        for (int64_t k = 0; k < p.prof.ticks; k += 1 + p.prof.ticks / 50) {
            kc_interp_cart_state st;
            kc_interp_line_eval(&p, k, &st);
            for (int i = 0; i < 3; i++)
                kt_near((double)st.p.v[i], (double)(a.t.v[i] + p.dp.v[i] * st.u), 8.0 * (double)KC_REAL_EPS * 4.0,
                        "line: on the segment");
            if (p.length > KC_R(0.0))
                kt_near((double)st.s, (double)(p.length * st.u), 8.0 * (double)KC_REAL_EPS * 4.0, "line: s = S u");
            if (m == KC_INTERP_SLERP && st.u > KC_R(0.0)) {
                /* One fixed axis: R1^T R(u) turns about `axis` by angle u. */
                kc_quat c, rel;
                kc_quat_conj(&p.q1, &c);
                kc_quat_mul(&c, &st.q, &rel);
                kc_vec3 rv = rotvec(rel), want;
                kc_vec3_scale(&p.axis, p.angle * st.u, &want);
                kt_near_vec3(&rv, &want, 1e-9 + 1e-5 * FLOAT_BUILD, "slerp: fixed axis");
            }
        }
    }
}

static void test_line_degenerate(void **state)
{
    (void)state;
    kc_interp_line p;
    kc_interp_cart_state st;
    kc_pose a, b;
    kc_interp_limits lim = limits(0.5, 2.0, 0.8, 3.0);
    kc_vec3 x = kc_vec3_make(1, 0, 0), z = kc_vec3_make(0, 0, 1), d = kc_vec3_make(1, 2, 2);
    kc_pose_identity(&a);
    a.t = kc_vec3_make(KC_R(0.3), KC_R(-0.2), KC_R(0.5));
    /* Pure rotation: the speed law runs on the angle with w and dw. */
    for (int m = 0; m < 2; m++) {
        b = a;
        kc_orient_axis_angle_to_mat3(&d, KC_R(1.2), &b.R);
        assert_int_equal(kc_interp_line_plan(&p, &a, &b, &lim, (kc_interp_orient)m, KC_R(0.001)), KC_OK);
        assert_true(p.length == KC_R(0.0));
        /* Slerp turns by 1.2 rad; two rotations by sqrt(theta^2 + phi^2). */
        if (m == KC_INTERP_SLERP)
            kt_near((double)p.angle, 1.2, 1e-12 + 1e-6 * FLOAT_BUILD, "pure rotation: angle");
        double Th = (double)p.angle, T = move_time(Th, 0.8, 3.0);
        kt_near((double)p.prof.T, T, 1e-9 + 1e-5 * FLOAT_BUILD, "pure rotation: T on the angle with w, dw");
        check_line_walk(&p, &lim, 0.8, 3.0, &a.t, &b.t, "pure rotation");
        check_line_end(&p, &b, "pure rotation end");
        for (int64_t k = 0; k <= p.prof.ticks; k++) {
            kc_interp_line_eval(&p, k, &st);
            assert_true(st.p.v[0] == a.t.v[0] && st.p.v[1] == a.t.v[1] && st.p.v[2] == a.t.v[2]);
        }
        /* cppcheck-suppress uninitvar ; the loop from k = 0 ran at least once */
        kt_near((double)st.s, Th, 0.0, "pure rotation: s is the angle");
    }
    /* ... and needs a finite dw. */
    kc_interp_limits nodw = limits(0.5, 2.0, 0.8, DINF);
    assert_int_equal(kc_interp_line_plan(&p, &a, &b, &nodw, KC_INTERP_SLERP, KC_R(0.001)), KC_E_ARG);
    /* Zero motion: 0 ticks, the target at once; angular limits may be off. */
    kc_interp_limits seed = limits(0.5, 2.0, DINF, DINF);
    for (int m = 0; m < 2; m++) {
        assert_int_equal(kc_interp_line_plan(&p, &a, &a, &seed, (kc_interp_orient)m, KC_R(0.001)), KC_OK);
        assert_true(p.prof.ticks == 0);
        assert_int_equal(kc_interp_line_eval(&p, 0, &st), KC_DONE);
        assert_true(st.p.v[0] == a.t.v[0] && st.u == KC_R(1.0));
    }
    /* a = (0, 0, -1) exactly (diag(1, -1, -1)): psi = 0 by the seed's rule
     * (5.18), theta = pi (#22), and phi = -pi: Ry(pi) Rz(-pi) = diag(1, -1, -1). */
    b = a;
    b.t.v[2] += KC_R(0.3);
    b.R.m[1][1] = b.R.m[2][2] = KC_R(-1.0);
    assert_int_equal(kc_interp_line_plan(&p, &a, &b, &seed, KC_INTERP_TWO_ROTATIONS, KC_R(0.002)), KC_OK);
    kt_near((double)p.psi, 0.0, 0.0, "a = (0,0,-1): psi");
    kt_near((double)p.theta, KT_PI, 4.0 * (double)KC_REAL_EPS, "a = (0,0,-1): theta");
    kt_near((double)p.phi, -KT_PI, 4.0 * (double)KC_REAL_EPS, "a = (0,0,-1): phi");
    check_line_walk(&p, &seed, 0.5, 2.0, &a.t, &b.t, "a = (0,0,-1)");
    check_line_end(&p, &b, "a = (0,0,-1)");
    /* Rotations of (nearly) 180 degrees, about x (a_z = -1: psi degenerate,
     * theta = pi), about z (theta = 0, phi = -pi), about a general axis;
     * and a pure z rotation (a_x = a_y = 0). */
    static const double angles[] = {KT_PI, KT_PI - 1e-7, KT_PI - 1e-3, 0.7};
    const kc_vec3 *axes[] = {&x, &z, &d};
    for (int m = 0; m < 2; m++)
        for (size_t i = 0; i < 4; i++)
            for (size_t j = 0; j < 3; j++) {
                char what[96];
                b = a;
                b.t.v[0] += KC_R(0.4);
                kc_orient_axis_angle_to_mat3(axes[j], (kc_real)angles[i], &b.R);
                assert_int_equal(kc_interp_line_plan(&p, &a, &b, &seed, (kc_interp_orient)m, KC_R(0.002)), KC_OK);
                snprintf(what, sizeof what, "method %d, angle %g about axis %zu", m, angles[i], j);
                check_line_walk(&p, &seed, 0.5, 2.0, &a.t, &b.t, what);
                check_line_end(&p, &b, what);
                if (m == KC_INTERP_TWO_ROTATIONS && j == 0 && i == 0) {
                    /* Rx(pi) as rounded: a = (0, -sin(pi), -1) with
                     * sin(pi) ~ 1e-16, so psi = -pi/2 and the first turn is
                     * about x itself, by theta = pi. */
                    kt_near((double)p.theta, KT_PI, 4.0 * (double)KC_REAL_EPS, what);
                    kt_near(fabs((double)p.k1.v[0]), 1.0, 4.0 * (double)KC_REAL_EPS, what);
                }
                if (m == KC_INTERP_TWO_ROTATIONS && j == 1) {
                    /* About z only: a_x = a_y = 0, psi = theta = 0, all in phi. */
                    kt_near((double)p.psi, 0.0, 0.0, what);
                    kt_near((double)p.theta, 0.0, 0.0, what);
                    kt_near(fabs((double)p.phi), angles[i], 8.0 * (double)KC_REAL_EPS, what);
                    if (i == 0) /* exactly pi: [-pi, pi) takes -pi */
                        assert_true(p.phi < KC_R(0.0));
                }
            }
}

/* A random circle: centre, radius, plane; start angle and the swept and via
 * angles (up to almost a full turn). */
static void rand_arc(kt_rng *r, kc_pose *from, kc_vec3 *via, kc_vec3 *to, kc_vec3 *c, double *R, kc_vec3 *n,
                     double *alpha, double *beta)
{
    kc_vec3 e1, e2;
    *c = kc_vec3_make((kc_real)kt_uniform(r, -1, 1), (kc_real)kt_uniform(r, -1, 1), (kc_real)kt_uniform(r, -1, 1));
    *n = kt_rand_unit(r);
    e1 = kt_rand_unit(r);
    kc_vec3 t;
    kc_vec3_scale(n, kc_vec3_dot(n, &e1), &t);
    kc_vec3_sub(&e1, &t, &e1);
    kc_vec3_scale(&e1, KC_R(1.0) / kc_vec3_norm(&e1), &e1);
    kc_vec3_cross(n, &e1, &e2);
    *R = kt_uniform(r, 0.05, 1.0);
    *alpha = kt_uniform(r, 0.2, 2.0 * KT_PI - 0.2);
    *beta = *alpha * kt_uniform(r, 0.1, 0.9);
    double a0 = kt_uniform(r, -KT_PI, KT_PI);
    double ang[3] = {a0, a0 + *beta, a0 + *alpha};
    /* cppcheck-suppress ctuuninitvar ; via and to are outputs: their addresses are taken, the loop writes them */
    kc_vec3 *pts[3] = {&from->t, via, to};
    *from = kt_rand_pose(r);
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 3; i++)
            pts[k]->v[i] = c->v[i] + (kc_real)(*R * (cos(ang[k]) * (double)e1.v[i] + sin(ang[k]) * (double)e2.v[i]));
}

static void test_arc_properties(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(0xA4C);
    int big = 0;
    for (int t = 0; t < N_RANDOM; t++) {
        kc_pose from;
        kc_vec3 via, to, c, n;
        double R, alpha, beta;
        rand_arc(&r, &from, &via, &to, &c, &R, &n, &alpha, &beta);
        big += alpha > KT_PI;
        double w = t % 2 ? (double)INFINITY : kt_uniform(&r, 0.5, 5.0), dw = t % 2 ? (double)INFINITY : kt_uniform(&r, 1.0, 20.0);
        kc_interp_limits lim = limits(kt_uniform(&r, 0.05, 1.0), kt_uniform(&r, 0.2, 5.0), w, dw);
        kc_interp_arc p;
        assert_int_equal(kc_interp_arc_plan(&p, &from, &via, &to, &lim, (kc_real)rand_dt(&r)), KC_OK);
        double tol = 1e-9 + 1e-4 * FLOAT_BUILD; /* eps / sin of the chords' angle, at least 0.05 rad */
        kt_near_vec3(&p.centre, &c, tol, "arc: centre");
        kt_near_vec3(&p.normal, &n, tol / R, "arc: normal (counter-clockwise)");
        kt_near((double)p.radius, R, tol, "arc: radius");
        kt_near((double)p.angle, alpha, tol / R, "arc: swept angle");
        kt_near((double)p.angle_via, beta, tol / R, "arc: angle of the via point");
        double al, aa;
        arc_acc(&p, &al, &aa);
        check_cart_walk(arc_eval, &p, &p.prof, &lim, (double)lim.v, (double)lim.a, al, aa, &from.t, &to, "arc");
        /* On the circle; passes the via point; the tool keeps its pose
         * relative to the centre (6.1): R(t)^T (p(t) - c) is constant. */
        kc_vec3 rel0, rel, d;
        kc_vec3_sub(&from.t, &p.centre, &d);
        kc_mat3_tmul_vec(&from.R, &d, &rel0);
        double closest = 1e9, step = (double)lim.v * (double)p.prof.dt;
        for (int64_t k = 0; k <= p.prof.ticks; k++) {
            kc_interp_cart_state st;
            kc_mat3 Rt;
            kc_interp_arc_eval(&p, k, &st);
            kc_vec3_sub(&st.p, &p.centre, &d);
            kt_near((double)kc_vec3_norm(&d), (double)p.radius, tol, "arc: on the circle");
            kt_near((double)kc_vec3_dot(&d, &p.normal), 0.0, tol, "arc: in the plane");
            kc_quat_to_mat3(&st.q, &Rt);
            kc_mat3_tmul_vec(&Rt, &d, &rel);
            kt_near_vec3(&rel, &rel0, tol, "arc: orientation carried with the arc (6.1)");
            kc_vec3_sub(&st.p, &via, &d);
            closest = fmin(closest, (double)kc_vec3_norm(&d));
        }
        assert_true(closest <= 0.5 * step * (1.0 + 1e-6) + tol);
    }
    assert_true(big > N_RANDOM / 4); /* arcs over 180 degrees were covered */
}

static void test_arc_degenerate(void **state)
{
    (void)state;
    kc_interp_arc p;
    kc_pose from;
    kc_interp_limits lim = limits(0.5, 2.0, DINF, DINF);
    kc_pose_identity(&from);
    kc_vec3 a = kc_vec3_make(1, 0, 0), b = kc_vec3_make(2, 0, 0), o = kc_vec3_make(0, 0, 0);
    memset(&p, KT_SENTINEL, sizeof p);
    /* Collinear, and every coincidence. */
    assert_int_equal(kc_interp_arc_plan(&p, &from, &a, &b, &lim, KC_R(0.001)), KC_E_SINGULAR);
    assert_int_equal(kc_interp_arc_plan(&p, &from, &b, &a, &lim, KC_R(0.001)), KC_E_SINGULAR); /* beyond the end */
    assert_int_equal(kc_interp_arc_plan(&p, &from, &o, &b, &lim, KC_R(0.001)), KC_E_SINGULAR); /* via = start */
    assert_int_equal(kc_interp_arc_plan(&p, &from, &a, &o, &lim, KC_R(0.001)), KC_E_SINGULAR); /* end = start */
    assert_int_equal(kc_interp_arc_plan(&p, &from, &a, &a, &lim, KC_R(0.001)), KC_E_SINGULAR); /* via = end */
    assert_int_equal(kc_interp_arc_plan(&p, &from, &o, &o, &lim, KC_R(0.001)), KC_E_SINGULAR);
    /* Just inside the collinearity threshold, and just outside it. */
    kc_vec3 near = kc_vec3_make(1, KC_INTERP_TOL_COLLINEAR * KC_R(0.5), 0);
    assert_int_equal(kc_interp_arc_plan(&p, &from, &near, &b, &lim, KC_R(0.001)), KC_E_SINGULAR);
    assert_true(kt_is_sentinel(&p, sizeof p));
    kc_vec3 off = kc_vec3_make(1, KC_R(0.01), 0);
    assert_int_equal(kc_interp_arc_plan(&p, &from, &off, &b, &lim, KC_R(0.001)), KC_OK);
    /* A half circle exactly, and the same points given the other way round
     * (the normal flips, the arc still passes the via point). */
    kc_vec3 top = kc_vec3_make(1, 1, 0), bottom = kc_vec3_make(1, -1, 0);
    assert_int_equal(kc_interp_arc_plan(&p, &from, &top, &b, &lim, KC_R(0.001)), KC_OK);
    kt_near((double)p.angle, KT_PI, 8.0 * (double)KC_REAL_EPS, "half circle");
    kt_near((double)p.normal.v[2], -1.0, 8.0 * (double)KC_REAL_EPS, "half circle: clockwise seen from +z");
    assert_int_equal(kc_interp_arc_plan(&p, &from, &bottom, &b, &lim, KC_R(0.001)), KC_OK);
    kt_near((double)p.normal.v[2], 1.0, 8.0 * (double)KC_REAL_EPS, "half circle: counter-clockwise");
    /* Three quarters: via at the top, end at the bottom. */
    kc_vec3 start_right = kc_vec3_make(2, 0, 0);
    from.t = start_right;
    assert_int_equal(kc_interp_arc_plan(&p, &from, &top, &bottom, &lim, KC_R(0.001)), KC_OK);
    kt_near((double)p.angle, 1.5 * KT_PI, 8.0 * (double)KC_REAL_EPS, "270 degrees");
    kt_near((double)p.angle_via, 0.5 * KT_PI, 8.0 * (double)KC_REAL_EPS, "270 degrees: via at 90");
}

/* ---- bad inputs ---- */

#define EXPECT(call, want, obj)                                                                                     \
    do {                                                                                                            \
        memset(&(obj), KT_SENTINEL, sizeof(obj));                                                                   \
        kc_status got_ = (call);                                                                                    \
        if (got_ != (want) || !kt_is_sentinel(&(obj), sizeof(obj))) {                                               \
            print_error("%s: status %d (%s), want %d; untouched %d\n", #call, (int)got_, kc_status_str(got_),         \
                        (int)(want), kt_is_sentinel(&(obj), sizeof(obj)));                                          \
            fail();                                                                                                 \
        }                                                                                                           \
    } while (0)

static void test_bad_inputs(void **state)
{
    (void)state;
    const kc_real nan = (kc_real)NAN, dt = KC_R(0.001);
    kc_real q0[KC_MAX_JOINTS + 1] = {0}, q1[KC_MAX_JOINTS + 1] = {1, 1}, vm[KC_MAX_JOINTS + 1], am[KC_MAX_JOINTS + 1];
    kc_interp_joint jp;
    kc_interp_joint_state js;
    for (int i = 0; i <= KC_MAX_JOINTS; i++)
        vm[i] = am[i] = KC_R(1.0);
    EXPECT(kc_interp_joint_plan(&jp, 0, q0, q1, vm, am, 0, dt), KC_E_ARG, jp);
    EXPECT(kc_interp_joint_plan(&jp, -1, q0, q1, vm, am, 0, dt), KC_E_ARG, jp);
    EXPECT(kc_interp_joint_plan(&jp, KC_MAX_JOINTS + 1, q0, q1, vm, am, 0, dt), KC_E_CAPACITY, jp);
    EXPECT(kc_interp_joint_plan(&jp, 2, NULL, q1, vm, am, 0, dt), KC_E_ARG, jp);
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, 0, 0), KC_E_ARG, jp);
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, 0, nan), KC_E_ARG, jp);
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, nan, dt), KC_E_ARG, jp);
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, -1, dt), KC_E_ARG, jp);
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, KC_R(0.5), dt), KC_E_LIMIT, jp); /* needs 2 s */
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, KC_R(1e5), dt), KC_E_CAPACITY, jp);
    q1[1] = KC_R(1e6); /* 1e6 s at 1 kHz */
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, 0, dt), KC_E_CAPACITY, jp);
    q1[1] = nan;
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, 0, dt), KC_E_ARG, jp);
    q1[1] = INF;
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, 0, dt), KC_E_ARG, jp);
    q1[1] = KC_REAL_MAX;
    q0[1] = -KC_REAL_MAX;
    EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, 0, dt), KC_E_ARG, jp); /* dq overflows */
    q1[1] = KC_R(1.0);
    q0[1] = KC_R(0.0);
    static const kc_real bad_limits[][2] = {{0, 1}, {-1, 1}, {(kc_real)NAN, 1}, {1, 0}, {1, -1}, {1, (kc_real)NAN},
                                            {1, (kc_real)INFINITY}};
    for (size_t i = 0; i < sizeof bad_limits / sizeof bad_limits[0]; i++) {
        vm[1] = bad_limits[i][0];
        am[1] = bad_limits[i][1];
        EXPECT(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, 0, dt), KC_E_ARG, jp);
    }
    vm[1] = am[1] = KC_R(1.0);
    assert_int_equal(kc_interp_joint_plan(&jp, 2, q0, q1, vm, am, 0, dt), KC_OK);
    EXPECT(kc_interp_joint_eval(&jp, -1, &js), KC_E_ARG, js);
    assert_int_equal(kc_interp_joint_eval(NULL, 0, &js), KC_E_ARG);
    assert_int_equal(kc_interp_joint_eval(&jp, 0, NULL), KC_E_ARG);

    /* Cartesian. */
    kc_pose a, b, bad;
    kc_vec3 via = kc_vec3_make(1, 1, 0), to = kc_vec3_make(2, 0, 0), nanv = kc_vec3_make(1, nan, 0);
    kc_interp_line lp;
    kc_interp_arc ap;
    kc_interp_cart_state cs;
    kc_interp_limits lim = limits(0.5, 2.0, DINF, DINF);
    kc_pose_identity(&a);
    b = a;
    b.t.v[0] = KC_R(1.0);
    bad = a;
    bad.t.v[1] = nan;
    EXPECT(kc_interp_line_plan(&lp, &bad, &b, &lim, KC_INTERP_SLERP, dt), KC_E_ARG, lp);
    EXPECT(kc_interp_line_plan(&lp, &a, &bad, &lim, KC_INTERP_SLERP, dt), KC_E_ARG, lp);
    EXPECT(kc_interp_arc_plan(&ap, &bad, &via, &to, &lim, dt), KC_E_ARG, ap);
    bad = a;
    bad.R.m[0][0] = KC_R(1.01); /* not a rotation */
    EXPECT(kc_interp_line_plan(&lp, &a, &bad, &lim, KC_INTERP_TWO_ROTATIONS, dt), KC_E_ARG, lp);
    EXPECT(kc_interp_arc_plan(&ap, &bad, &via, &to, &lim, dt), KC_E_ARG, ap);
    bad.R.m[0][0] = nan;
    EXPECT(kc_interp_line_plan(&lp, &a, &bad, &lim, KC_INTERP_TWO_ROTATIONS, dt), KC_E_ARG, lp);
    EXPECT(kc_interp_arc_plan(&ap, &a, &nanv, &to, &lim, dt), KC_E_ARG, ap);
    EXPECT(kc_interp_arc_plan(&ap, &a, &via, &nanv, &lim, dt), KC_E_ARG, ap);
    EXPECT(kc_interp_line_plan(&lp, &a, &b, &lim, (kc_interp_orient)7, dt), KC_E_ARG, lp);
    EXPECT(kc_interp_line_plan(&lp, NULL, &b, &lim, KC_INTERP_SLERP, dt), KC_E_ARG, lp);
    EXPECT(kc_interp_line_plan(&lp, &a, &b, NULL, KC_INTERP_SLERP, dt), KC_E_ARG, lp);
    EXPECT(kc_interp_arc_plan(&ap, &a, NULL, &to, &lim, dt), KC_E_ARG, ap);
    EXPECT(kc_interp_line_plan(&lp, &a, &b, &lim, KC_INTERP_SLERP, -dt), KC_E_ARG, lp);
    EXPECT(kc_interp_arc_plan(&ap, &a, &via, &to, &lim, 0), KC_E_ARG, ap);
    const double bl[][4] = {{0, 1, 1, 1},  {-1, 1, 1, 1}, {DNAN, 1, 1, 1}, {1, 0, 1, 1},   {1, DINF, 1, 1},
                            {1, DNAN, 1, 1}, {1, 1, 0, 1},  {1, 1, -1, 1},  {1, 1, DNAN, 1}, {1, 1, 1, 0},
                            {1, 1, 1, -2},  {1, 1, 1, DNAN}};
    for (size_t i = 0; i < sizeof bl / sizeof bl[0]; i++) {
        kc_interp_limits l = limits(bl[i][0], bl[i][1], bl[i][2], bl[i][3]);
        EXPECT(kc_interp_line_plan(&lp, &a, &b, &l, KC_INTERP_TWO_ROTATIONS, dt), KC_E_ARG, lp);
        EXPECT(kc_interp_arc_plan(&ap, &a, &via, &to, &l, dt), KC_E_ARG, ap);
    }
    kc_interp_limits def = kc_interp_limits_default(); /* v and a unset */
    EXPECT(kc_interp_line_plan(&lp, &a, &b, &def, KC_INTERP_TWO_ROTATIONS, dt), KC_E_ARG, lp);
    /* Too long, and too far to measure. */
    b.t.v[0] = KC_R(1e5);
    EXPECT(kc_interp_line_plan(&lp, &a, &b, &lim, KC_INTERP_SLERP, dt), KC_E_CAPACITY, lp);
    b.t.v[0] = KC_REAL_MAX;
    a.t.v[0] = -KC_REAL_MAX;
    EXPECT(kc_interp_line_plan(&lp, &a, &b, &lim, KC_INTERP_SLERP, dt), KC_E_CAPACITY, lp);
    a.t.v[0] = KC_R(0.0);
    b.t.v[0] = KC_R(1.0);
    assert_int_equal(kc_interp_line_plan(&lp, &a, &b, &lim, KC_INTERP_SLERP, dt), KC_OK);
    assert_int_equal(kc_interp_arc_plan(&ap, &a, &via, &to, &lim, dt), KC_OK);
    EXPECT(kc_interp_line_eval(&lp, -5, &cs), KC_E_ARG, cs);
    EXPECT(kc_interp_arc_eval(&ap, -1, &cs), KC_E_ARG, cs);
    assert_int_equal(kc_interp_line_eval(NULL, 0, &cs), KC_E_ARG);
    assert_int_equal(kc_interp_arc_eval(&ap, 0, NULL), KC_E_ARG);
}

/* Stopping on the path: at random ticks of random lines, arcs and joint
 * moves, a stop profile of u from the state there (kc_profile_plan_stop
 * with the plan's u_amax) drives the same geometry: it continues the
 * motion without a jump in position or velocity, decelerates within the
 * plan's acceleration bound, stays on the segment (the line's points are on
 * the line, the arc's at radius R) and ends at rest short of the end. */
static void test_stop_on_path(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(77);
    const kc_real dt = KC_R(0.001);
    for (int trial = 0; trial < 100; trial++) {
        kc_pose from = kt_rand_pose(&r), to = kt_rand_pose(&r);
        kc_vec3 via = kc_vec3_make(KC_R(0.5) * (from.t.v[0] + to.t.v[0]) + KC_R(0.3),
                                   KC_R(0.5) * (from.t.v[1] + to.t.v[1]) - KC_R(0.2),
                                   KC_R(0.5) * (from.t.v[2] + to.t.v[2]) + KC_R(0.1));
        kc_interp_limits lim = kc_interp_limits_default();
        lim.v = (kc_real)kt_uniform(&r, 0.1, 1.0);
        lim.a = (kc_real)kt_uniform(&r, 0.5, 5.0);
        kc_interp_line line;
        kc_interp_arc arc;
        assert_int_equal(kc_interp_line_plan(&line, &from, &to, &lim, KC_INTERP_SLERP, dt), KC_OK);
        assert_int_equal(kc_interp_arc_plan(&arc, &from, &via, &to.t, &lim, dt), KC_OK);
        for (int which = 0; which < 2; which++) {
            const kc_profile *prof = which == 0 ? &line.prof : &arc.prof;
            kc_real u_amax = which == 0 ? line.u_amax : arc.u_amax;
            int64_t k0 = (int64_t)kt_uniform(&r, 1.0, (double)prof->ticks - 1.0);
            kc_profile_state u0;
            kc_profile_eval(prof, k0, &u0);
            kc_profile stop;
            assert_int_equal(kc_profile_plan_stop(&stop, u0.p, u0.v, u_amax, dt), KC_OK);
            kc_interp_cart_state a, b, prev;
            if (which == 0) {
                kc_interp_line_eval(&line, k0, &a);
                kc_interp_line_eval_profile(&line, &stop, 0, &b);
            } else {
                kc_interp_arc_eval(&arc, k0, &a);
                kc_interp_arc_eval_profile(&arc, &stop, 0, &b);
            }
            kt_near_vec3(&b.p, &a.p, 1e-9 + 16.0 * (double)KC_REAL_EPS, "stop starts where the motion is");
            kt_near_vec3(&b.v, &a.v, 1e-9 + 16.0 * (double)KC_REAL_EPS, "stop starts at the motion's velocity");
            prev = b;
            kc_status st = KC_OK;
            for (int64_t k = 1; st == KC_OK; k++) {
                st = which == 0 ? kc_interp_line_eval_profile(&line, &stop, k, &b)
                                : kc_interp_arc_eval_profile(&arc, &stop, k, &b);
                assert_true(st == KC_OK || st == KC_DONE);
                /* deceleration along the path within the plan's bound */
                /* plus the rounding of the speeds, v0 - A k dt: of the order
                 * of eps times the speed the stop started from */
                double limit = (double)lim.a * (double)dt * (1.0 + LIMIT_SLACK) +
                               8.0 * (double)KC_REAL_EPS * fabs((double)a.sd);
                if (!(fabs((double)(b.sd - prev.sd)) <= limit))
                    fail_msg("trial %d %s k %ld: speed step %g > %g (sd %g -> %g)", trial, which ? "arc" : "line",
                             (long)k, fabs((double)(b.sd - prev.sd)), limit, (double)prev.sd, (double)b.sd);
                if (which == 1) {
                    kc_vec3 d;
                    kc_vec3_sub(&b.p, &arc.centre, &d);
                    kt_near((double)kc_vec3_norm(&d), (double)arc.radius, 1e-9 + 64.0 * (double)KC_REAL_EPS,
                            "stops on the circle");
                }
                prev = b;
            }
            kt_near((double)b.sd, 0.0, 0.0, "at rest");
            kt_near((double)b.u <= 1.0 + 4.0 * (double)KC_REAL_EPS, 1.0, 0.0, "not past the end");
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_joint_vectors),    cmocka_unit_test(test_line_vectors),
        cmocka_unit_test(test_circle_vectors),   cmocka_unit_test(test_joint_properties),
        cmocka_unit_test(test_line_properties),  cmocka_unit_test(test_line_degenerate),
        cmocka_unit_test(test_arc_properties),   cmocka_unit_test(test_arc_degenerate),
        cmocka_unit_test(test_bad_inputs),       cmocka_unit_test(test_stop_on_path),
    };
    int failed = cmocka_run_group_tests_name("interp (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("interp");
    return failed;
}
