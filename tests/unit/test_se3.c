/* SPDX-License-Identifier: BSD-3-Clause */
/* test_se3.c - homogeneous transforms (seed 001 lab 1, vectors/transforms.json),
 * rigid poses, quaternions and dual quaternions (seed 002). */
#include "testutil.h"

#include <stdio.h>
#include <string.h>

#define N_RANDOM 1000

/* Relative accuracy of the small-angle log/exp round trip: each of exp and
 * log rounds a handful of times (scale, sqrt, atan2, divide, scale), so
 * 16 roundings of the unit roundoff bound the relative error. */
#define KT_REL_SMALL (16.0 * (double)KC_REAL_EPS)

/* ---- transforms.json ---- */

/* The matrix a task/variant describes, built with the library. */
static void task_matrix(int task, const json_t *v, kc_mat4 *m)
{
    switch (task) {
    case 1: kc_mat4_translation((kc_real)kt_num_of(v, "dx"), KC_R(0.0), KC_R(0.0), m); break;
    case 2: kc_mat4_translation(KC_R(0.0), (kc_real)kt_num_of(v, "dy"), KC_R(0.0), m); break;
    case 3: kc_mat4_translation(KC_R(0.0), KC_R(0.0), (kc_real)kt_num_of(v, "dz"), m); break;
    case 4:
    case 5:
    case 6:
        kc_mat4_rotation((kc_axis)(task - 4), (kc_real)(kt_num_of(v, "beta_deg") * KT_PI / 180.0), m);
        break;
    case 7: assert_int_equal(kc_mat4_scale((kc_real)kt_num_of(v, "s"), m), KC_OK); break;
    case 8: {
        const char *ax = json_string_value(kt_get(v, "optical_axis"));
        assert_non_null(ax);
        kc_axis axis = strcmp(ax, "OX") == 0 ? KC_AXIS_X : strcmp(ax, "OY") == 0 ? KC_AXIS_Y : KC_AXIS_Z;
        assert_true(strcmp(ax, "OX") == 0 || strcmp(ax, "OY") == 0 || strcmp(ax, "OZ") == 0);
        assert_int_equal(kc_mat4_perspective(axis, (kc_real)kt_num_of(v, "f"), m), KC_OK);
        break;
    }
    default: fail();
    }
}

static void test_transforms_json(void **state)
{
    (void)state;
    json_t *root = kt_load("transforms.json");
    const json_t *A = kt_get(root, "pyramid_A_3x5");
    const json_t *tasks = kt_get(root, "tasks");
    char what[96];
    int n_variants = 0;
    assert_true(kt_num_of(kt_get(root, "tolerance"), "abs") == 1e-12);
    assert_int_equal(json_array_size(tasks), 8);
    for (size_t t = 0; t < json_array_size(tasks); t++) {
        const json_t *task = kt_at(tasks, t);
        int id = (int)kt_num_of(task, "task");
        const json_t *variants = kt_get(task, "variants");
        assert_int_equal(json_array_size(variants), 6);
        for (size_t k = 0; k < json_array_size(variants); k++) {
            const json_t *v = kt_at(variants, k);
            const json_t *hom = kt_get(v, "homogeneous_result_4x5");
            const json_t *cart = kt_get(v, "cartesian_result_3x5");
            kc_mat4 m;
            task_matrix(id, v, &m);
            snprintf(what, sizeof what, "task %d variant %zu M", id, k + 1);
            kt_near_mat4_json(&m, kt_get(v, "M"), KT_TOL_T, what);
            for (size_t j = 0; j < 5; j++) {
                kc_vec3 p, c;
                kc_real h[4];
                for (size_t i = 0; i < 3; i++)
                    p.v[i] = (kc_real)kt_num(kt_at(kt_at(A, i), j));
                kc_mat4_apply_h(&m, &p, h);
                for (size_t i = 0; i < 4; i++) {
                    snprintf(what, sizeof what, "task %d variant %zu vertex %zu homogeneous[%zu]", id, k + 1, j + 1, i);
                    kt_near((double)h[i], kt_num(kt_at(kt_at(hom, i), j)), KT_TOL_T, what);
                }
                assert_int_equal(kc_mat4_apply(&m, &p, &c), KC_OK);
                for (size_t i = 0; i < 3; i++) {
                    snprintf(what, sizeof what, "task %d variant %zu vertex %zu cartesian[%zu]", id, k + 1, j + 1, i);
                    kt_near((double)c.v[i], kt_num(kt_at(kt_at(cart, i), j)), KT_TOL_T, what);
                }
                if (id == 8) {
                    /* The image plane drops the optical-axis coordinate; w is row 4. */
                    const char *ax = json_string_value(kt_get(v, "optical_axis"));
                    int drop = ax[1] - 'X', r = 0;
                    snprintf(what, sizeof what, "task 8 variant %zu vertex %zu w", k + 1, j + 1);
                    kt_near((double)h[3], kt_num(kt_at(kt_get(v, "w_row"), j)), KT_TOL_T, what);
                    for (int i = 0; i < 3; i++) {
                        if (i == drop)
                            continue;
                        snprintf(what, sizeof what, "task 8 variant %zu vertex %zu image[%d]", k + 1, j + 1, r);
                        kt_near((double)c.v[i], kt_num(kt_at(kt_at(kt_get(v, "image_plane_coords_2x5"), (size_t)r), j)),
                                KT_TOL_T, what);
                        r++;
                    }
                }
            }
            n_variants++;
        }
    }
    assert_int_equal(n_variants, 48);
    json_decref(root);
}

static void test_mat4_errors(void **state)
{
    (void)state;
    kc_mat4 m;
    kc_vec3 p = kc_vec3_make(KC_R(10.0), KC_R(1.0), KC_R(2.0)), out;
    memset(&m, KT_SENTINEL, sizeof m);
    assert_int_equal(kc_mat4_scale(KC_R(0.0), &m), KC_E_ARG);
    assert_int_equal(kc_mat4_scale((kc_real)NAN, &m), KC_E_ARG);
    assert_int_equal(kc_mat4_perspective(KC_AXIS_X, KC_R(0.0), &m), KC_E_ARG);
    assert_int_equal(kc_mat4_perspective(KC_AXIS_X, (kc_real)INFINITY, &m), KC_E_ARG);
    assert_int_equal(kc_mat4_perspective((kc_axis)3, KC_R(1.0), &m), KC_E_ARG);
    assert_true(kt_is_sentinel(&m, sizeof m));
    /* A point in the vanishing plane (x = f) has no Cartesian image. */
    assert_int_equal(kc_mat4_perspective(KC_AXIS_X, KC_R(10.0), &m), KC_OK);
    memset(&out, KT_SENTINEL, sizeof out);
    assert_int_equal(kc_mat4_apply(&m, &p, &out), KC_E_SINGULAR);
    assert_true(kt_is_sentinel(&out, sizeof out));
}

/* ---- poses ---- */

static void identity_pose_check(const kc_pose *p, const char *what)
{
    kc_pose id;
    kc_pose_identity(&id);
    kt_near_pose(p, &id, KT_TOL_T * 10.0, what);
}

static void test_pose_inverse_random(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x5E3001);
    for (int i = 0; i < N_RANDOM; i++) {
        kc_pose a = kt_rand_pose(&rng), inv, prod, alias = a;
        kc_pose_inv(&a, &inv);
        kc_pose_mul(&a, &inv, &prod);
        identity_pose_check(&prod, "pose * inv");
        kc_pose_mul(&inv, &a, &prod);
        identity_pose_check(&prod, "inv * pose");
        kc_pose_inv(&alias, &alias); /* dest may alias a */
        kt_near_pose(&alias, &inv, 0.0, "aliased inverse");
        /* A point mapped there and back. */
        kc_vec3 p = kt_rand_unit(&rng), q, back;
        kc_pose_apply(&a, &p, &q);
        kc_pose_apply(&inv, &q, &back);
        kt_near_vec3(&back, &p, KT_TOL_T * 10.0, "inv(apply(p))");
    }
}

/*
 * The identity checks above use 10 KT_TOL_T: a pose product and inverse at
 * |t| <= 2*sqrt(3) m: R^T t has 3-term sums of magnitude ~3.5, then
 * R (R^T t) + t another 3-term sum; about 10 roundings of 3.5, i.e.
 * 35 u = 4e-15 (double) resp. 2e-6 (float), both below 10 KT_TOL_T
 * (1e-11 resp. 1e-4) and above KT_TOL_T only by that size factor.
 */

static void test_pose_mat4_and_rotation_error(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x5E3002);
    for (int i = 0; i < N_RANDOM; i++) {
        kc_pose a = kt_rand_pose(&rng), b;
        kc_mat4 h;
        kc_pose_to_mat4(&a, &h);
        assert_int_equal(kc_pose_from_mat4(&h, &b), KC_OK);
        kt_near_pose(&b, &a, 0.0, "from_mat4(to_mat4(pose))");
        kt_near((double)kc_mat3_rotation_error(&a.R), 0.0, KT_TOL_ENTRY * 4.0, "rotation error of a rotation");
    }
    kc_mat3 m;
    kc_mat3_identity(&m);
    kt_near((double)kc_mat3_rotation_error(&m), 0.0, 0.0, "rotation error of I");
    /* Scaling by 1 + e: (1+e)^2 - 1 on the diagonal, (1+e)^3 - 1 on det. */
    for (int i = 0; i < 3; i++)
        m.m[i][i] = KC_R(1.001);
    kt_near((double)kc_mat3_rotation_error(&m), 1.001 * 1.001 * 1.001 - 1.0, 1e-6, "rotation error of 1.001 I");
    /* A reflection is orthogonal but det = -1: the error is 2. */
    kc_mat3_identity(&m);
    m.m[2][2] = KC_R(-1.0);
    kt_near((double)kc_mat3_rotation_error(&m), 2.0, 0.0, "rotation error of a reflection");
    /* A NaN anywhere gives NaN, whichever entries it reaches. */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            kc_mat3 n = m;
            n.m[i][j] = (kc_real)NAN;
            if (!isnan((double)kc_mat3_rotation_error(&n))) {
                print_error("kc_mat3_rotation_error: NaN at [%d][%d] lost\n", i, j);
                fail();
            }
        }
}

static void test_pose_from_mat4_rejects(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x5E3003);
    kc_pose a = kt_rand_pose(&rng), out;
    kc_mat4 good, bad;
    kc_pose_to_mat4(&a, &good);
    struct {
        int i, j;
        kc_real v;
        const char *what;
    } cases[] = {
        {0, 0, KC_R(0.0), "non-rigid (column 1 changed)"},
        {1, 2, KC_R(1.0), "non-rigid (sheared)"},
        {2, 1, (kc_real)NAN, "NaN in R"},
        {0, 3, (kc_real)NAN, "NaN in t"},
        {1, 3, (kc_real)INFINITY, "inf in t"},
        {3, 0, KC_R(1e-3), "last row (4,1)"},
        {3, 2, KC_R(-1.0), "last row (4,3)"},
        {3, 3, KC_R(2.0), "last row (4,4) scale"},
        {3, 3, (kc_real)NAN, "last row NaN"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        bad = good;
        bad.m[cases[c].i][cases[c].j] = cases[c].v;
        if (cases[c].i < 3 && cases[c].j < 3 && cases[c].v == KC_R(0.0))
            bad.m[cases[c].i][cases[c].j] = good.m[cases[c].i][cases[c].j] + KC_R(0.5);
        memset(&out, KT_SENTINEL, sizeof out);
        if (kc_pose_from_mat4(&bad, &out) != KC_E_ARG || !kt_is_sentinel(&out, sizeof out)) {
            print_error("kc_pose_from_mat4 accepted or wrote on: %s\n", cases[c].what);
            fail();
        }
    }
    /* Scaled rotation just outside and just inside the documented tolerance. */
    bad = good;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            bad.m[i][j] = good.m[i][j] * (KC_R(1.0) + KC_R(2.0) * KC_TOL_ORTHONORMAL);
    assert_int_equal(kc_pose_from_mat4(&bad, &out), KC_E_ARG);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            bad.m[i][j] = good.m[i][j] * (KC_R(1.0) + KC_R(0.1) * KC_TOL_ORTHONORMAL);
    assert_int_equal(kc_pose_from_mat4(&bad, &out), KC_OK);
}

/* ---- quaternions ---- */

static void quat_matrix_round_trip(const kc_quat *q, const char *what)
{
    kc_mat3 R, R2;
    kc_quat back;
    kc_quat_to_mat3(q, &R);
    kc_quat_from_mat3(&R, &back);
    assert_true(back.w >= KC_R(0.0));
    kt_near((double)kc_quat_norm(&back), 1.0, KT_TOL_RT, what);
    kt_near_quat(&back, q, KT_TOL_RT, what);
    kc_quat_to_mat3(&back, &R2);
    kt_near_mat3(&R2, &R, KT_TOL_RT, what);
}

static void test_quat_mat3_round_trip(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x5E3004);
    char what[64];
    for (int i = 0; i < N_RANDOM; i++) {
        kc_quat q = kt_rand_quat(&rng);
        quat_matrix_round_trip(&q, "random quaternion -> R -> quaternion");
        /* kc_quat_rotate agrees with the matrix. */
        kc_vec3 v = kt_rand_unit(&rng), a, b;
        kc_mat3 R;
        kc_quat_to_mat3(&q, &R);
        kc_mat3_mul_vec(&R, &v, &a);
        kc_quat_rotate(&q, &v, &b);
        kt_near_vec3(&b, &a, KT_TOL_RT, "quat_rotate vs matrix");
    }
    /* 0 degrees, and 180 degrees about random and coordinate axes (w = 0:
     * every Shepperd branch but the trace one). */
    kc_quat id;
    kc_quat_identity(&id);
    quat_matrix_round_trip(&id, "identity");
    for (int i = 0; i < 100; i++) {
        kc_vec3 k = i < 3 ? kc_vec3_make((kc_real)(i == 0), (kc_real)(i == 1), (kc_real)(i == 2)) : kt_rand_unit(&rng);
        kc_quat q = {KC_R(0.0), k.v[0], k.v[1], k.v[2]};
        snprintf(what, sizeof what, "180 deg case %d", i);
        quat_matrix_round_trip(&q, what);
        /* Near 180: the trace branch is left for the diagonal ones. */
        kc_real h = KC_R(1e-4);
        kc_quat near_pi = {h, k.v[0], k.v[1], k.v[2]};
        assert_int_equal(kc_quat_normalize(&near_pi, &near_pi), KC_OK);
        snprintf(what, sizeof what, "180 deg - 2e-4 rad case %d", i);
        quat_matrix_round_trip(&near_pi, what);
    }
    /* Rotations about x, y, z by 0 and pi via kc_mat3_rot. */
    for (int ax = 0; ax < 3; ax++) {
        kc_mat3 R;
        kc_quat q;
        kc_mat3_rot((kc_axis)ax, KC_PI, &R);
        kc_quat_from_mat3(&R, &q);
        kc_quat e = {KC_R(0.0), (kc_real)(ax == 0), (kc_real)(ax == 1), (kc_real)(ax == 2)};
        kt_near_quat(&q, &e, KT_TOL_RT, "Rot(axis, pi) -> quaternion");
        kc_mat3_rot((kc_axis)ax, KC_R(0.0), &R);
        kc_quat_from_mat3(&R, &q);
        kt_near_quat(&q, &id, 0.0, "Rot(axis, 0) -> quaternion");
    }
}

static void test_quat_log_exp(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x5E3005);
    char what[80];
    /* Angles from zero to near pi, including the series range. */
    static const double angles[] = {0.0, 1e-12, 1e-9, 1e-7, 1e-5, 1e-3, 0.1, 1.0, 3.0, KT_PI - 1e-4, KT_PI - 1e-3};
    for (size_t a = 0; a < sizeof angles / sizeof angles[0]; a++) {
        for (int i = 0; i < 50; i++) {
            kc_vec3 k = kt_rand_unit(&rng), w, back;
            kc_quat q;
            kc_vec3_scale(&k, (kc_real)angles[a], &w);
            kc_quat_exp(&w, &q);
            kt_near((double)kc_quat_norm(&q), 1.0, KT_TOL_RT, "|exp(w)|");
            kc_quat_log(&q, &back);
            /* Absolute KT_TOL_RT and, for small angles, relative accuracy. */
            double tol = angles[a] < 1e-3 ? KT_REL_SMALL * angles[a] : KT_TOL_RT;
            snprintf(what, sizeof what, "log(exp(w)) |w| = %g", angles[a]);
            kt_near_vec3(&back, &w, tol, what);
        }
    }
}

/* ---- dual quaternions ---- */

static void test_dquat(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x5E3006);
    for (int i = 0; i < N_RANDOM; i++) {
        kc_pose a = kt_rand_pose(&rng), b = kt_rand_pose(&rng), p, ab;
        kc_dquat da, db, dab, dc, di;
        kc_dquat_from_pose(&a, &da);
        kc_dquat_from_pose(&b, &db);
        /* Unit: |r| = 1 and r.d = 0. */
        kt_near((double)kc_quat_norm(&da.r), 1.0, KT_TOL_RT, "|r|");
        kt_near((double)(da.r.w * da.d.w + da.r.x * da.d.x + da.r.y * da.d.y + da.r.z * da.d.z), 0.0, KT_TOL_RT,
                "r.d");
        kc_dquat_to_pose(&da, &p);
        kt_near_pose(&p, &a, KT_TOL_RT, "pose -> dq -> pose");
        /* Product = pose product. */
        kc_dquat_mul(&da, &db, &dab);
        kc_dquat_to_pose(&dab, &p);
        kc_pose_mul(&a, &b, &ab);
        kt_near_pose(&p, &ab, KT_TOL_RT, "dq(a) dq(b) = dq(a b)");
        /* Conjugate = inverse. */
        kc_pose inv;
        kc_dquat_conj(&da, &dc);
        kc_dquat_to_pose(&dc, &p);
        kc_pose_inv(&a, &inv);
        kt_near_pose(&p, &inv, KT_TOL_RT, "conj(dq) = dq(inv)");
        kc_dquat_mul(&da, &dc, &di);
        kc_dquat id;
        kc_dquat_identity(&id);
        kt_near_quat(&di.r, &id.r, KT_TOL_RT, "dq conj(dq) real part");
        kt_near_quat(&di.d, &id.d, KT_TOL_RT, "dq conj(dq) dual part");
        /* log / exp round trip. */
        kc_vec3 w, v;
        kc_dquat e;
        kc_dquat_log(&da, &w, &v);
        kt_near_vec3(&v, &a.t, KT_TOL_RT, "dq log translation");
        kc_dquat_exp(&w, &v, &e);
        kc_dquat_to_pose(&e, &p);
        kt_near_pose(&p, &a, KT_TOL_RT, "exp(log(dq))");
    }
}

static void test_dquat_log_exp_extremes(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x5E3007);
    char what[80];
    static const double angles[] = {0.0, 1e-10, 1e-7, 1e-4, KT_PI - 1e-3, KT_PI - 1e-5};
    for (size_t a = 0; a < sizeof angles / sizeof angles[0]; a++) {
        for (int i = 0; i < 50; i++) {
            kc_vec3 k = kt_rand_unit(&rng), w, v, w2, v2;
            kc_dquat dq;
            kc_pose p, expect;
            kc_vec3_scale(&k, (kc_real)angles[a], &w);
            v = kc_vec3_make((kc_real)kt_uniform(&rng, -1, 1), (kc_real)kt_uniform(&rng, -1, 1),
                             (kc_real)kt_uniform(&rng, -1, 1));
            kc_dquat_exp(&w, &v, &dq);
            kc_dquat_log(&dq, &w2, &v2);
            double tol = angles[a] < 1e-3 ? KT_REL_SMALL * angles[a] : KT_TOL_RT;
            snprintf(what, sizeof what, "dq log(exp) rotation |w| = %g", angles[a]);
            kt_near_vec3(&w2, &w, tol, what);
            snprintf(what, sizeof what, "dq log(exp) translation |w| = %g", angles[a]);
            kt_near_vec3(&v2, &v, KT_TOL_RT, what);
            /* The pose of exp(w, v) is Rot(k, |w|) with translation v. */
            kc_dquat_to_pose(&dq, &p);
            kc_quat q;
            kc_quat_exp(&w, &q);
            kc_quat_to_mat3(&q, &expect.R);
            expect.t = v;
            kt_near_pose(&p, &expect, KT_TOL_RT, "pose of dq exp");
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_transforms_json),
        cmocka_unit_test(test_mat4_errors),
        cmocka_unit_test(test_pose_inverse_random),
        cmocka_unit_test(test_pose_mat4_and_rotation_error),
        cmocka_unit_test(test_pose_from_mat4_rejects),
        cmocka_unit_test(test_quat_mat3_round_trip),
        cmocka_unit_test(test_quat_log_exp),
        cmocka_unit_test(test_dquat),
        cmocka_unit_test(test_dquat_log_exp_extremes),
    };
    int failed = cmocka_run_group_tests_name("se3 (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("se3");
    return failed;
}
