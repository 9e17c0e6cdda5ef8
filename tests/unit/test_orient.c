/* SPDX-License-Identifier: BSD-3-Clause */
/* test_orient.c - roll-pitch-yaw, Z-Y-Z Euler and axis-angle (seed 001 lab 2,
 * vectors/orientation.json). */
#include "testutil.h"

#include <stdio.h>
#include <string.h>

#define N_RANDOM 2000

typedef int (*extract_fn)(const kc_mat3 *, kc_euler *);
typedef void (*build_fn)(const kc_euler *, kc_mat3 *);

/* One Euler convention: how to build and extract, and the term whose
 * smallness makes phi and psi ill-conditioned (|cos theta| for RPY,
 * |sin theta| for Z-Y-Z). */
typedef struct convention {
    const char *name;
    build_fn build;
    extract_fn extract;
    double (*conditioning)(double theta);
} convention;

static double abs_cos(double theta) { return fabs(cos(theta)); }
static double abs_sin(double theta) { return fabs(sin(theta)); }

static const convention RPY = {"rpy", kc_orient_rpy_to_mat3, kc_orient_mat3_to_rpy, abs_cos};
static const convention ZYZ = {"zyz", kc_orient_zyz_to_mat3, kc_orient_mat3_to_zyz, abs_sin};

/* phi and psi come from atan2 of entries of size c (the conditioning term)
 * that carry KT_TOL_ENTRY of rounding: their error is up to KT_TOL_ENTRY / c
 * on top of the well-conditioned KT_TOL_ANGLE. theta is well conditioned. */
static double side_angle_tol(const convention *cv, double theta)
{
    double c = cv->conditioning(theta);
    return KT_TOL_ANGLE + (c > 0.0 ? KT_TOL_ENTRY / c : 0.0);
}

static kc_euler euler_of(const double a[3])
{
    kc_euler e = {(kc_real)a[0], (kc_real)a[1], (kc_real)a[2]};
    return e;
}

/* Extracts from R and checks: the angles against expected (mod 2 pi), the
 * singular flag against the file's, and that the angles rebuild R. */
static void check_extraction(const convention *cv, const kc_mat3 *R, const double expect[3], int expect_lock,
                             const char *label)
{
    kc_euler e;
    kc_mat3 back;
    char what[160];
    int lock = cv->extract(R, &e);
    if (lock != expect_lock) {
        print_error("%s %s: singular flag %d, reference %d\n", cv->name, label, lock, expect_lock);
        fail();
    }
    assert_true(kc_isfinite(e.phi) && kc_isfinite(e.theta) && kc_isfinite(e.psi));
    double side = side_angle_tol(cv, expect[1]);
    snprintf(what, sizeof what, "%s %s theta", cv->name, label);
    kt_near_angle((double)e.theta, expect[1], KT_TOL_ANGLE, what);
    snprintf(what, sizeof what, "%s %s phi", cv->name, label);
    kt_near_angle((double)e.phi, expect[0], side, what);
    snprintf(what, sizeof what, "%s %s psi", cv->name, label);
    kt_near_angle((double)e.psi, expect[2], side, what);
    /* In gimbal lock only a sum or difference is defined: the rebuilt matrix
     * is the real test (and also holds outside it). */
    cv->build(&e, &back);
    snprintf(what, sizeof what, "%s %s matrix from extracted angles", cv->name, label);
    kt_near_mat3(&back, R, KT_TOL_RT, what);
}

static void read_triple(const json_t *arr, double out[3], double scale)
{
    for (size_t i = 0; i < 3; i++)
        out[i] = kt_num(kt_at(arr, i)) * scale;
}

/* ---- table variants ---- */

static void check_table_variants(const convention *cv, const json_t *variants, const char *const keys[3])
{
    char what[96];
    assert_int_equal(json_array_size(variants), 6);
    for (size_t v = 0; v < json_array_size(variants); v++) {
        const json_t *row = kt_at(variants, v);
        const json_t *ex = kt_get(row, "extracted");
        double in[3], expect[3];
        kc_mat3 R, Rref;
        kc_quat q;
        for (int i = 0; i < 3; i++)
            in[i] = kt_num_of(row, keys[i]) * KT_PI / 180.0;
        kc_euler e = euler_of(in);
        cv->build(&e, &R);
        snprintf(what, sizeof what, "%s variant %zu R", cv->name, v + 1);
        kt_near_mat3_json(&R, kt_get(row, "R"), KT_TOL_T, what);
        expect[0] = kt_num_of(ex, "phi_rad");
        expect[1] = kt_num_of(ex, "theta_rad");
        expect[2] = kt_num_of(ex, "psi_rad");
        kt_read_mat3(kt_get(row, "R"), &Rref);
        snprintf(what, sizeof what, "variant %zu", v + 1);
        check_extraction(cv, &Rref, expect, json_is_true(kt_get(ex, "gimbal_lock")), what);
        kc_quat_from_mat3(&Rref, &q);
        snprintf(what, sizeof what, "%s variant %zu quaternion", cv->name, v + 1);
        kt_near_quat_json(&q, kt_get(row, "quaternion_wxyz"), KT_TOL_RT, what);
    }
}

static void test_rpy_variants(void **state)
{
    (void)state;
    static const char *const keys[3] = {"roll_phi_about_Z_deg", "pitch_theta_about_Y_deg", "yaw_psi_about_X_deg"};
    json_t *root = kt_load("orientation.json");
    check_table_variants(&RPY, kt_get(root, "rpy_variants"), keys);
    json_decref(root);
}

static void test_zyz_variants(void **state)
{
    (void)state;
    static const char *const keys[3] = {"phi_deg", "theta_deg", "psi_deg"};
    json_t *root = kt_load("orientation.json");
    check_table_variants(&ZYZ, kt_get(root, "zyz_variants"), keys);
    json_decref(root);
}

/* ---- round trips ---- */

static void check_round_trips(const convention *cv, const json_t *cases)
{
    char what[128];
    for (size_t c = 0; c < json_array_size(cases); c++) {
        const json_t *row = kt_at(cases, c);
        const char *name = json_string_value(kt_get(row, "case"));
        double in[3], expect[3];
        kc_mat3 R, Rref;
        read_triple(kt_get(row, "input_deg"), in, KT_PI / 180.0);
        read_triple(kt_get(row, "extracted_rad"), expect, 1.0);
        kc_euler e = euler_of(in);
        cv->build(&e, &R);
        snprintf(what, sizeof what, "%s '%s' R", cv->name, name);
        kt_near_mat3_json(&R, kt_get(row, "R"), KT_TOL_T, what);
        kt_read_mat3(kt_get(row, "R"), &Rref);
        check_extraction(cv, &Rref, expect, json_is_true(kt_get(row, "gimbal_lock")), name);
        /* And from the matrix the library built itself. */
        kc_euler e2;
        kc_mat3 back;
        cv->extract(&R, &e2);
        cv->build(&e2, &back);
        snprintf(what, sizeof what, "%s '%s' own matrix round trip", cv->name, name);
        kt_near_mat3(&back, &R, KT_TOL_RT, what);
    }
}

static void test_round_trip_rpy(void **state)
{
    (void)state;
    json_t *root = kt_load("orientation.json");
    check_round_trips(&RPY, kt_get(root, "round_trip_rpy"));
    json_decref(root);
}

static void test_round_trip_zyz(void **state)
{
    (void)state;
    json_t *root = kt_load("orientation.json");
    check_round_trips(&ZYZ, kt_get(root, "round_trip_zyz"));
    json_decref(root);
}

/* ---- axis-angle ---- */

/* Extraction from R against the reference axis and angle (axis NULL: the
 * identity, whose axis is (0, 0, 1) by the header's convention). */
static void check_axis_extraction(const kc_mat3 *R, const json_t *k_expect, double theta_expect, const char *label)
{
    kc_vec3 k;
    kc_real theta;
    kc_mat3 back;
    char what[128];
    int singular = kc_orient_mat3_to_axis_angle(R, &k, &theta);
    snprintf(what, sizeof what, "%s theta", label);
    kt_near((double)theta, theta_expect, KT_TOL_RT, what);
    snprintf(what, sizeof what, "%s axis", label);
    if (k_expect == NULL || json_is_null(k_expect)) {
        kc_vec3 z = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(1.0));
        kt_near_vec3(&k, &z, 0.0, what);
        assert_int_equal(singular, 1);
    } else {
        kt_near_reals_json(k.v, 3, k_expect, KT_TOL_RT, what);
    }
    if (theta_expect == 0.0 || theta_expect == KT_PI)
        assert_int_equal(singular, 1);
    else if (theta_expect > 1e-3 && theta_expect < KT_PI - 1e-3)
        assert_int_equal(singular, 0);
    kt_near((double)kc_vec3_norm(&k), 1.0, KT_TOL_RT, what);
    assert_int_equal(kc_orient_axis_angle_to_mat3(&k, theta, &back), KC_OK);
    snprintf(what, sizeof what, "%s matrix from extracted axis-angle", label);
    kt_near_mat3(&back, R, KT_TOL_RT, what);
}

static void test_axis_angle_variants(void **state)
{
    (void)state;
    json_t *root = kt_load("orientation.json");
    const json_t *variants = kt_get(root, "axis_angle_variants");
    char what[96];
    assert_int_equal(json_array_size(variants), 6);
    for (size_t v = 0; v < json_array_size(variants); v++) {
        const json_t *row = kt_at(variants, v);
        const json_t *ex = kt_get(row, "extracted_canonical");
        kc_vec3 K;
        kc_mat3 R, Rref;
        kc_quat q;
        kt_read_reals(kt_get(row, "K"), K.v, 3); /* unnormalised, as in the table */
        assert_int_equal(kc_orient_axis_angle_to_mat3(&K, (kc_real)(kt_num_of(row, "theta_deg") * KT_PI / 180.0), &R),
                         KC_OK);
        snprintf(what, sizeof what, "axis-angle variant %zu R", v + 1);
        kt_near_mat3_json(&R, kt_get(row, "R"), KT_TOL_T, what);
        kt_read_mat3(kt_get(row, "R"), &Rref);
        snprintf(what, sizeof what, "axis-angle variant %zu", v + 1);
        check_axis_extraction(&Rref, kt_get(ex, "k"), kt_num_of(ex, "theta_rad"), what);
        kc_quat_from_mat3(&Rref, &q);
        snprintf(what, sizeof what, "axis-angle variant %zu quaternion", v + 1);
        kt_near_quat_json(&q, kt_get(row, "quaternion_wxyz"), KT_TOL_RT, what);
    }
    json_decref(root);
}

static void test_round_trip_axis_angle(void **state)
{
    (void)state;
    json_t *root = kt_load("orientation.json");
    const json_t *cases = kt_get(root, "round_trip_axis_angle");
    char what[128];
    for (size_t c = 0; c < json_array_size(cases); c++) {
        const json_t *row = kt_at(cases, c);
        const char *name = json_string_value(kt_get(row, "case"));
        kc_vec3 k;
        kc_mat3 R, Rref;
        kc_quat q;
        kt_read_reals(kt_get(row, "k_in"), k.v, 3);
        assert_int_equal(kc_orient_axis_angle_to_mat3(&k, (kc_real)(kt_num_of(row, "theta_in_deg") * KT_PI / 180.0), &R),
                         KC_OK);
        snprintf(what, sizeof what, "axis-angle '%s' R", name);
        kt_near_mat3_json(&R, kt_get(row, "R"), KT_TOL_T, what);
        kt_read_mat3(kt_get(row, "R"), &Rref);
        snprintf(what, sizeof what, "axis-angle '%s'", name);
        check_axis_extraction(&Rref, kt_get(row, "extracted_k"), kt_num_of(row, "extracted_theta_rad"), what);
        kc_quat_from_mat3(&Rref, &q);
        snprintf(what, sizeof what, "axis-angle '%s' quaternion", name);
        kt_near_quat_json(&q, kt_get(row, "quaternion_wxyz"), KT_TOL_RT, what);
    }
    json_decref(root);
}

static void test_axis_angle_errors(void **state)
{
    (void)state;
    kc_mat3 R;
    kc_vec3 zero = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    kc_vec3 nan_axis = kc_vec3_make((kc_real)NAN, KC_R(0.0), KC_R(1.0));
    kc_vec3 z = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(1.0));
    memset(&R, KT_SENTINEL, sizeof R);
    assert_int_equal(kc_orient_axis_angle_to_mat3(&zero, KC_R(1.0), &R), KC_E_ARG);
    assert_int_equal(kc_orient_axis_angle_to_mat3(&nan_axis, KC_R(1.0), &R), KC_E_ARG);
    assert_int_equal(kc_orient_axis_angle_to_mat3(&z, (kc_real)INFINITY, &R), KC_E_ARG);
    assert_true(kt_is_sentinel(&R, sizeof R));
}

/* Just below pi the axis sign still matters: R(k, pi - d) and R(-k, pi - d)
 * differ by about 2 d, down to d at rounding level. */
static void test_axis_angle_near_pi(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x0121E48);
    static const double d[] = {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
    char what[64];
    for (size_t i = 0; i < sizeof d / sizeof d[0]; i++)
        for (int n = 0; n < 100; n++) {
            kc_vec3 k = kt_rand_unit(&rng), k2;
            kc_real th;
            kc_mat3 R, back;
            assert_int_equal(kc_orient_axis_angle_to_mat3(&k, (kc_real)(KT_PI - d[i]), &R), KC_OK);
            kc_orient_mat3_to_axis_angle(&R, &k2, &th);
            assert_int_equal(kc_orient_axis_angle_to_mat3(&k2, th, &back), KC_OK);
            snprintf(what, sizeof what, "axis-angle at pi - %g", d[i]);
            kt_near_mat3(&back, &R, KT_TOL_RT, what);
        }
}

/* ---- NaN-free extraction, random and exactly singular ---- */

static int finite_euler(const kc_euler *e)
{
    return kc_isfinite(e->phi) && kc_isfinite(e->theta) && kc_isfinite(e->psi);
}

static void extract_all_finite(const kc_mat3 *R, const char *label)
{
    kc_euler e;
    kc_vec3 k;
    kc_real th;
    kc_mat3 back;
    char what[96];
    kc_orient_mat3_to_rpy(R, &e);
    assert_true(finite_euler(&e));
    kc_orient_rpy_to_mat3(&e, &back);
    snprintf(what, sizeof what, "%s rpy round trip", label);
    kt_near_mat3(&back, R, KT_TOL_RT, what);
    kc_orient_mat3_to_zyz(R, &e);
    assert_true(finite_euler(&e));
    kc_orient_zyz_to_mat3(&e, &back);
    snprintf(what, sizeof what, "%s zyz round trip", label);
    kt_near_mat3(&back, R, KT_TOL_RT, what);
    kc_orient_mat3_to_axis_angle(R, &k, &th);
    assert_true(kc_vec3_isfinite(&k) && kc_isfinite(th));
    assert_int_equal(kc_orient_axis_angle_to_mat3(&k, th, &back), KC_OK);
    snprintf(what, sizeof what, "%s axis-angle round trip", label);
    kt_near_mat3(&back, R, KT_TOL_RT, what);
}

static void test_extraction_nan_free(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(0x0121E47);
    char what[64];
    for (int i = 0; i < N_RANDOM; i++) {
        kc_quat q = kt_rand_quat(&rng);
        kc_mat3 R;
        kc_quat_to_mat3(&q, &R);
        extract_all_finite(&R, "random");
    }
    /* Exactly singular matrices: every signed permutation with det +1 (the
     * 24 rotations of the cube: 0, 90, 180 degrees, RPY and Z-Y-Z locks). */
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    int n = 0;
    for (int p = 0; p < 6; p++)
        for (int s = 0; s < 8; s++) {
            kc_mat3 R;
            memset(&R, 0, sizeof R);
            for (int i = 0; i < 3; i++)
                R.m[i][perms[p][i]] = (s >> i) & 1 ? KC_R(-1.0) : KC_R(1.0);
            if (kc_mat3_rotation_error(&R) != KC_R(0.0))
                continue; /* a reflection */
            snprintf(what, sizeof what, "cube rotation %d", n);
            extract_all_finite(&R, what);
            n++;
        }
    assert_int_equal(n, 24);
    /* Gimbal lock built from angles, with the flag the header promises. */
    for (int i = 0; i < 200; i++) {
        kc_real a = (kc_real)kt_uniform(&rng, -KT_PI, KT_PI), b = (kc_real)kt_uniform(&rng, -KT_PI, KT_PI);
        kc_euler rpy = {a, i % 2 ? KC_PI_2 : -KC_PI_2, b}, zyz = {a, i % 2 ? KC_R(0.0) : KC_PI, b}, e;
        kc_mat3 R;
        kc_orient_rpy_to_mat3(&rpy, &R);
        assert_int_equal(kc_orient_mat3_to_rpy(&R, &e), 1);
        extract_all_finite(&R, "rpy lock");
        kc_orient_zyz_to_mat3(&zyz, &R);
        assert_int_equal(kc_orient_mat3_to_zyz(&R, &e), 1);
        extract_all_finite(&R, "zyz lock");
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rpy_variants),
        cmocka_unit_test(test_zyz_variants),
        cmocka_unit_test(test_axis_angle_variants),
        cmocka_unit_test(test_round_trip_rpy),
        cmocka_unit_test(test_round_trip_zyz),
        cmocka_unit_test(test_round_trip_axis_angle),
        cmocka_unit_test(test_axis_angle_errors),
        cmocka_unit_test(test_axis_angle_near_pi),
        cmocka_unit_test(test_extraction_nan_free),
    };
    int failed = cmocka_run_group_tests_name("orient (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("orient");
    return failed;
}
