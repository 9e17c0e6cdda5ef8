/* SPDX-License-Identifier: BSD-3-Clause */
/* test_chain.c - coded chains (seed 003, vectors/code_chain.json), the chain
 * builders' error handling, validation and the built-in models. */
#include "testutil.h"

#include <stdio.h>
#include <string.h>

/* Builds a chain from seed 003's [[code, arg], ...] list with
 * kc_chain_add_code; every coded transform ends a frame. */
static void chain_from_codes(const json_t *list, kc_chain *chain)
{
    assert_int_equal(kc_chain_init(chain), KC_OK);
    for (size_t i = 0; i < json_array_size(list); i++) {
        const json_t *el = kt_at(list, i);
        int code = (int)kt_num(kt_at(el, 0));
        assert_int_equal(kc_chain_add_code(chain, code, (kc_real)kt_num(kt_at(el, 1))), KC_OK);
    }
    assert_int_equal(chain->n_frames, (int)json_array_size(list));
}

static void test_elementary_codes(void **state)
{
    (void)state;
    json_t *root = kt_load("code_chain.json");
    const json_t *el = kt_get(root, "elementary");
    char what[64];
    assert_true(kt_num_of(kt_get(root, "tolerance"), "abs") == 1e-12);
    assert_int_equal(json_array_size(el), 12);
    for (size_t i = 0; i < json_array_size(el); i++) {
        const json_t *row = kt_at(el, i);
        int code = (int)kt_num_of(row, "code");
        kc_real value = (kc_real)kt_num_of(row, "value");
        kc_real q[1] = {value};
        kc_chain c;
        kc_pose frame, tool;
        assert_int_equal(code, (int)i + 1);
        kc_chain_init(&c);
        /* A joint code takes the joint index (0) and q = value; a constant
         * code takes the value itself. */
        assert_int_equal(kc_chain_add_code(&c, code, code <= 6 ? KC_R(0.0) : value), KC_OK);
        assert_int_equal(c.n_joints, code <= 6 ? 1 : 0);
        assert_int_equal(c.n_frames, 1);
        if (code <= 6)
            assert_int_equal(c.joints[0].type, code <= 3 ? KC_JOINT_REVOLUTE : KC_JOINT_PRISMATIC);
        assert_int_equal(kc_fk_frames(&c, q, &frame, &tool), KC_OK);
        snprintf(what, sizeof what, "code %d frame", code);
        kt_near_pose_json(&frame, kt_get(row, "M"), KT_TOL_T, what);
        snprintf(what, sizeof what, "code %d tool", code);
        kt_near_pose_json(&tool, kt_get(row, "M"), KT_TOL_T, what);
    }
    json_decref(root);
}

static void test_code_cases(void **state)
{
    (void)state;
    json_t *root = kt_load("code_chain.json");
    const json_t *cases = kt_get(root, "cases");
    char what[96];
    int n_cum = 0;
    assert_int_equal(json_array_size(cases), 9);
    for (size_t i = 0; i < json_array_size(cases); i++) {
        const json_t *row = kt_at(cases, i);
        const json_t *list = kt_get(row, "chain_code_arg");
        const json_t *cum = json_object_get(row, "M0k_cumulative");
        kc_chain c;
        kc_real q[KC_MAX_JOINTS];
        kc_pose frames[KC_MAX_FRAMES], tool;
        chain_from_codes(list, &c);
        assert_int_equal(kc_chain_check(&c), KC_OK);
        kt_read_reals(kt_get(row, "q"), q, (size_t)c.n_joints);
        assert_int_equal(kc_fk_eval(&c, q, &tool), KC_OK);
        snprintf(what, sizeof what, "case %zu (%s) T", i, json_string_value(kt_get(row, "robot")));
        kt_near_pose_json(&tool, kt_get(row, "T"), KT_TOL_T, what);
        if (cum != NULL) {
            /* Frame k is M_0k, the pose after the k-th coded transform. */
            assert_int_equal(json_array_size(cum), (size_t)c.n_frames);
            assert_int_equal(kc_fk_frames(&c, q, frames, NULL), KC_OK);
            for (int k = 0; k < c.n_frames; k++) {
                snprintf(what, sizeof what, "case %zu M0%d", i, k + 1);
                kt_near_pose_json(&frames[k], kt_at(cum, (size_t)k), KT_TOL_T, what);
            }
            n_cum++;
        }
    }
    assert_int_equal(n_cum, 3);
    json_decref(root);
}

/* ---- builder errors: each leaves the chain byte for byte unchanged ---- */

/* A small valid chain to append to. */
static void base_chain(kc_chain *c)
{
    kc_chain_init(c);
    assert_int_equal(kc_chain_add_code(c, KC_CODE_RZ_JOINT, KC_R(0.0)), KC_OK);
    assert_int_equal(kc_chain_add_code(c, KC_CODE_TZ, KC_R(0.3)), KC_OK);
}

#define EXPECT_UNCHANGED(call, status)                                                                     \
    do {                                                                                                   \
        kc_chain before_;                                                                                  \
        memcpy(&before_, &c, sizeof c);                                                                    \
        assert_int_equal((call), (status));                                                                \
        assert_memory_equal(&before_, &c, sizeof c);                                                       \
    } while (0)

static void test_builder_errors(void **state)
{
    (void)state;
    kc_chain c;
    kc_real nan = (kc_real)NAN, inf = (kc_real)INFINITY;
    kc_joint_limits lim = kc_joint_limits_default();
    base_chain(&c);
    /* Bad codes. */
    EXPECT_UNCHANGED(kc_chain_add_code(&c, 0, KC_R(1.0)), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_code(&c, 13, KC_R(1.0)), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_code(&c, -3, KC_R(1.0)), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_joint(&c, KC_CODE_RX, KC_R(0.0), NULL), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_joint(&c, (kc_code)13, KC_R(0.0), NULL), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_const(&c, KC_CODE_TX_JOINT, KC_R(1.0)), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_const(&c, (kc_code)0, KC_R(1.0)), KC_E_ARG);
    /* NaN and infinite values. */
    EXPECT_UNCHANGED(kc_chain_add_code(&c, KC_CODE_RX, nan), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_code(&c, KC_CODE_TY, inf), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_code(&c, KC_CODE_RX_JOINT, nan), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_const(&c, KC_CODE_TZ, -inf), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_joint(&c, KC_CODE_RY_JOINT, nan, NULL), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_joint(&c, KC_CODE_RY_JOINT, inf, NULL), KC_E_ARG);
    /* The joint index must be the next one (1 here). */
    EXPECT_UNCHANGED(kc_chain_add_code(&c, KC_CODE_RZ_JOINT, KC_R(0.0)), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_code(&c, KC_CODE_RZ_JOINT, KC_R(2.0)), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_code(&c, KC_CODE_RZ_JOINT, KC_R(1.5)), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_code(&c, KC_CODE_RZ_JOINT, KC_R(-1.0)), KC_E_ARG);
    /* Limits: q_min > q_max, NaN, non-positive rates, wrong-signed infinity. */
    kc_joint_limits bad[] = {
        {KC_R(1.0), KC_R(0.0), inf, inf, inf},  {nan, KC_R(1.0), inf, inf, inf},
        {KC_R(-1.0), nan, inf, inf, inf},       {KC_R(-1.0), KC_R(1.0), KC_R(0.0), inf, inf},
        {KC_R(-1.0), KC_R(1.0), inf, KC_R(-1.0), inf}, {KC_R(-1.0), KC_R(1.0), inf, inf, KC_R(0.0)},
        {KC_R(-1.0), KC_R(1.0), nan, inf, inf}, {KC_R(-1.0), KC_R(1.0), -inf, inf, inf},
        {inf, inf, inf, inf, inf},              {-inf, -inf, inf, inf, inf},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        kc_dh_row row = {KC_JOINT_REVOLUTE, KC_R(0.1), KC_R(0.0), KC_R(0.0), KC_R(0.0), bad[i]};
        assert_int_equal(kc_chain_check_limits(&bad[i]), KC_E_ARG);
        EXPECT_UNCHANGED(kc_chain_add_joint(&c, KC_CODE_RX_JOINT, KC_R(0.0), &bad[i]), KC_E_ARG);
        EXPECT_UNCHANGED(kc_chain_set_limits(&c, 0, &bad[i]), KC_E_ARG);
        EXPECT_UNCHANGED(kc_chain_add_dh(&c, &row), KC_E_ARG);
        EXPECT_UNCHANGED(kc_chain_add_mdh(&c, &row), KC_E_ARG);
    }
    /* Equal bounds (a locked joint) and an infinite range are valid. */
    kc_joint_limits locked = {KC_R(0.5), KC_R(0.5), KC_R(1.0), KC_R(1.0), KC_R(1.0)};
    assert_int_equal(kc_chain_check_limits(&locked), KC_OK);
    assert_int_equal(kc_chain_check_limits(&lim), KC_OK);
    /* DH rows with a NaN parameter or a bad type. */
    kc_dh_row row = {KC_JOINT_REVOLUTE, nan, KC_R(0.0), KC_R(0.0), KC_R(0.0), lim};
    EXPECT_UNCHANGED(kc_chain_add_dh(&c, &row), KC_E_ARG);
    row.a = KC_R(0.0);
    row.theta = inf;
    EXPECT_UNCHANGED(kc_chain_add_mdh(&c, &row), KC_E_ARG);
    row.theta = KC_R(0.0);
    row.type = (kc_joint_type)7;
    EXPECT_UNCHANGED(kc_chain_add_dh(&c, &row), KC_E_ARG);
    /* set_limits on a joint that does not exist. */
    EXPECT_UNCHANGED(kc_chain_set_limits(&c, 1, &lim), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_set_limits(&c, -1, &lim), KC_E_ARG);
    /* Base and tool must be rigid and finite. */
    kc_pose p;
    kc_pose_identity(&p);
    p.R.m[0][0] = KC_R(1.1);
    EXPECT_UNCHANGED(kc_chain_set_base(&c, &p), KC_E_ARG);
    kc_pose_identity(&p);
    p.t.v[2] = nan;
    EXPECT_UNCHANGED(kc_chain_set_tool(&c, &p), KC_E_ARG);
    /* NULL arguments. */
    assert_int_equal(kc_chain_init(NULL), KC_E_ARG);
    assert_int_equal(kc_chain_add_code(NULL, KC_CODE_TX, KC_R(1.0)), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_add_dh(&c, NULL), KC_E_ARG);
    EXPECT_UNCHANGED(kc_chain_set_base(&c, NULL), KC_E_ARG);
}

static void test_capacity(void **state)
{
    (void)state;
    kc_chain c;
    kc_joint_limits lim = kc_joint_limits_default();
    kc_dh_row row = {KC_JOINT_REVOLUTE, KC_R(0.1), KC_R(0.2), KC_R(0.3), KC_R(0.0), lim};
    /* KC_MAX_JOINTS joints fit; one more is a capacity error. */
    kc_chain_init(&c);
    for (int j = 0; j < KC_MAX_JOINTS; j++)
        assert_int_equal(kc_chain_add_code(&c, KC_CODE_RX_JOINT + j % 6, (kc_real)j), KC_OK);
    assert_int_equal(c.n_joints, KC_MAX_JOINTS);
    assert_int_equal(kc_chain_check(&c), KC_OK);
    EXPECT_UNCHANGED(kc_chain_add_code(&c, KC_CODE_RZ_JOINT, (kc_real)KC_MAX_JOINTS), KC_E_CAPACITY);
    EXPECT_UNCHANGED(kc_chain_add_joint(&c, KC_CODE_RZ_JOINT, KC_R(0.0), NULL), KC_E_CAPACITY);
    EXPECT_UNCHANGED(kc_chain_add_dh(&c, &row), KC_E_CAPACITY);
    EXPECT_UNCHANGED(kc_chain_add_mdh(&c, &row), KC_E_CAPACITY);
    /* Frames: KC_MAX_FRAMES coded constants, then no room for another. */
    kc_chain_init(&c);
    for (int f = 0; f < KC_MAX_FRAMES; f++)
        assert_int_equal(kc_chain_add_code(&c, KC_CODE_TX, KC_R(0.01)), KC_OK);
    assert_int_equal(c.n_frames, KC_MAX_FRAMES);
    EXPECT_UNCHANGED(kc_chain_add_code(&c, KC_CODE_TX, KC_R(0.01)), KC_E_CAPACITY);
    EXPECT_UNCHANGED(kc_chain_add_frame(&c), KC_E_CAPACITY);
    EXPECT_UNCHANGED(kc_chain_add_joint(&c, KC_CODE_RZ_JOINT, KC_R(0.0), NULL), KC_E_CAPACITY);
    /* Elements: KC_MAX_ELEMENTS constants (no frames), then no room. */
    kc_chain_init(&c);
    for (int e = 0; e < KC_MAX_ELEMENTS; e++)
        assert_int_equal(kc_chain_add_const(&c, KC_CODE_RY, KC_R(0.01)), KC_OK);
    assert_int_equal(c.n_elements, KC_MAX_ELEMENTS);
    EXPECT_UNCHANGED(kc_chain_add_const(&c, KC_CODE_RY, KC_R(0.01)), KC_E_CAPACITY);
    EXPECT_UNCHANGED(kc_chain_add_joint(&c, KC_CODE_RZ_JOINT, KC_R(0.0), NULL), KC_E_CAPACITY);
    EXPECT_UNCHANGED(kc_chain_add_dh(&c, &row), KC_E_CAPACITY);
}

static void test_chain_check(void **state)
{
    (void)state;
    kc_chain c, bad;
    base_chain(&c);
    assert_int_equal(kc_chain_check(&c), KC_OK);
    /* No joints. */
    kc_chain_init(&bad);
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    assert_int_equal(kc_chain_check(NULL), KC_E_ARG);
    /* Tampered structs, as a corrupted or hand-filled chain would be. */
    bad = c;
    bad.elements[1].value = (kc_real)NAN;
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    bad = c;
    bad.joints[0].offset = (kc_real)INFINITY;
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    bad = c;
    bad.joints[0].limits.q_min = KC_R(2.0);
    bad.joints[0].limits.q_max = KC_R(1.0);
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    bad = c;
    bad.elements[1].joint = 0;
    bad.elements[1].code = KC_CODE_TZ_JOINT; /* joint 0 drives two transforms */
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    bad = c;
    bad.elements[0].joint = 1; /* no such joint */
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    bad = c;
    bad.elements[1].code = 0;
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    bad = c;
    bad.frame_end[1] = 0; /* frames out of order */
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    bad = c;
    bad.frame_end[1] = (uint8_t)(c.n_elements + 1);
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    bad = c;
    bad.base.R.m[1][1] = KC_R(-1.0); /* a reflection */
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
    bad = c;
    bad.tool.t.v[0] = (kc_real)NAN;
    assert_int_equal(kc_chain_check(&bad), KC_E_ARG);
}

static void test_check_q(void **state)
{
    (void)state;
    kc_chain c;
    kc_real q[6] = {0};
    int bad = -7;
    assert_int_equal(kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL), KC_OK);
    assert_int_equal(kc_chain_check_q(&c, q, &bad), KC_OK);
    assert_int_equal(bad, -7); /* untouched on success */
    for (int j = 0; j < 6; j++) {
        kc_real lo = c.joints[j].limits.q_min, hi = c.joints[j].limits.q_max;
        /* The bounds themselves are inside. */
        q[j] = lo;
        assert_int_equal(kc_chain_check_q(&c, q, NULL), KC_OK);
        q[j] = hi;
        assert_int_equal(kc_chain_check_q(&c, q, NULL), KC_OK);
        q[j] = hi + KC_R(1e-3);
        bad = -7;
        assert_int_equal(kc_chain_check_q(&c, q, &bad), KC_E_LIMIT);
        assert_int_equal(bad, j);
        q[j] = lo - KC_R(1e-3);
        assert_int_equal(kc_chain_check_q(&c, q, &bad), KC_E_LIMIT);
        assert_int_equal(bad, j);
        q[j] = (kc_real)NAN;
        assert_int_equal(kc_chain_check_q(&c, q, &bad), KC_E_ARG);
        assert_int_equal(bad, j);
        q[j] = (kc_real)INFINITY;
        assert_int_equal(kc_chain_check_q(&c, q, &bad), KC_E_ARG);
        assert_int_equal(bad, j);
        q[j] = KC_R(0.0);
    }
    /* The first offending joint is named. */
    q[2] = KC_R(100.0);
    q[4] = (kc_real)NAN;
    assert_int_equal(kc_chain_check_q(&c, q, &bad), KC_E_LIMIT);
    assert_int_equal(bad, 2);
    assert_int_equal(kc_chain_check_q(&c, NULL, &bad), KC_E_ARG);
    assert_int_equal(kc_chain_check_q(NULL, q, &bad), KC_E_ARG);
}

/* ---- built-in models ---- */

static void test_model_names(void **state)
{
    (void)state;
    static const char *const names[KC_MODEL_COUNT] = {"rrr3", "planar2", "puma560", "panda", "rb211", "rm01"};
    for (int m = 0; m < KC_MODEL_COUNT; m++) {
        const char *name = kc_model_name((kc_model)m);
        assert_non_null(name);
        assert_string_equal(name, names[m]);
        assert_int_equal(kc_model_from_name(name), m);
    }
    assert_null(kc_model_name(KC_MODEL_COUNT));
    assert_null(kc_model_name((kc_model)-1));
    assert_int_equal(kc_model_from_name("puma"), KC_E_ARG);
    assert_int_equal(kc_model_from_name("puma5600"), KC_E_ARG);
    assert_int_equal(kc_model_from_name("PANDA"), KC_E_ARG);
    assert_int_equal(kc_model_from_name(""), KC_E_ARG);
    assert_int_equal(kc_model_from_name(NULL), KC_E_ARG);
}

static void test_models_build(void **state)
{
    (void)state;
    static const int joints[KC_MODEL_COUNT] = {3, 2, 6, 7, 6, 6};
    kc_real q[KC_MAX_JOINTS] = {0};
    for (int m = 0; m < KC_MODEL_COUNT; m++) {
        kc_chain c;
        kc_pose T;
        memset(&c, KT_SENTINEL, sizeof c);
        assert_int_equal(kc_chain_init_model(&c, (kc_model)m, NULL), KC_OK);
        assert_int_equal(kc_chain_check(&c), KC_OK);
        assert_int_equal(c.n_joints, joints[m]);
        assert_int_equal(kc_fk_eval(&c, q, &T), KC_OK);
        assert_true(kc_pose_isfinite(&T));
    }
    kc_chain c;
    memset(&c, KT_SENTINEL, sizeof c);
    assert_int_equal(kc_chain_init_model(&c, KC_MODEL_COUNT, NULL), KC_E_ARG);
    kc_model_params p = {{(kc_real)NAN, KC_R(0.0), KC_R(0.0), KC_R(0.0)}};
    assert_int_equal(kc_chain_init_model(&c, KC_MODEL_RRR3, &p), KC_E_ARG);
    assert_true(kt_is_sentinel(&c, sizeof c));
}

/* Position limits equal fk.json's qlim_rad: exactly in double; in float the
 * library's float literal and the rounded double may differ by the
 * rounding of one conversion, half an ulp of |q|. */
static double limit_tol(double x)
{
#ifdef KC_REAL_FLOAT
    return fabs(x) * 0.5 * (double)KC_REAL_EPS;
#else
    (void)x;
    return 0.0;
#endif
}

static void check_limits(kc_model model, const json_t *table)
{
    kc_chain c;
    char what[64];
    assert_int_equal(kc_chain_init_model(&c, model, NULL), KC_OK);
    assert_int_equal(json_array_size(table), (size_t)c.n_joints);
    for (int j = 0; j < c.n_joints; j++) {
        const json_t *lim = kt_get(kt_at(table, (size_t)j), "qlim_rad");
        double lo = kt_num(kt_at(lim, 0)), hi = kt_num(kt_at(lim, 1));
        snprintf(what, sizeof what, "%s joint %d q_min", kc_model_name(model), j + 1);
        kt_near((double)c.joints[j].limits.q_min, lo, limit_tol(lo), what);
        snprintf(what, sizeof what, "%s joint %d q_max", kc_model_name(model), j + 1);
        kt_near((double)c.joints[j].limits.q_max, hi, limit_tol(hi), what);
    }
}

static void test_model_limits(void **state)
{
    (void)state;
    json_t *root = kt_load("fk.json");
    check_limits(KC_MODEL_PUMA560, kt_get(kt_get(root, "puma560"), "dh_table"));
    check_limits(KC_MODEL_PANDA, kt_get(kt_get(root, "panda"), "dh_table_modified"));
    json_decref(root);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_elementary_codes),
        cmocka_unit_test(test_code_cases),
        cmocka_unit_test(test_builder_errors),
        cmocka_unit_test(test_capacity),
        cmocka_unit_test(test_chain_check),
        cmocka_unit_test(test_check_q),
        cmocka_unit_test(test_model_names),
        cmocka_unit_test(test_models_build),
        cmocka_unit_test(test_model_limits),
    };
    int failed = cmocka_run_group_tests_name("chain (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("chain");
    return failed;
}
