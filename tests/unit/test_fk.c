/* SPDX-License-Identifier: BSD-3-Clause */
/* test_fk.c - forward kinematics and the geometric Jacobian (seed 000,
 * seed 003; vectors/fk.json).
 *
 * Frame numbering, as verified below against fk.json's T0i_cumulative: a DH
 * builder ends one frame after each row, so for an n-row DH chain
 * kc_fk_frames returns n poses and frames[i] (0-based) is seed 000's 0T_{i+1},
 * the pose after row i+1, base included as the left factor. The base itself
 * is NOT a frame of a DH chain; it is one only if kc_chain_add_frame is
 * called before the first element (test_frame_numbering). The last frame of
 * the Panda is its flange; the tool pose comes after it.
 */
#include "testutil.h"

#include <stdio.h>
#include <string.h>

#define N_RANDOM 1000

/* A built-in model, where fk.json describes it, and how its DH table reads. */
typedef struct model_ref {
    kc_model model;
    const char *key;   /* fk.json object */
    const char *table; /* its DH table */
    int modified;      /* Craig's modified DH (a_prev, alpha_prev) */
} model_ref;

static const model_ref RRR = {KC_MODEL_RRR3, "rrr", "dh_table", 0};
static const model_ref PUMA = {KC_MODEL_PUMA560, "puma560", "dh_table", 0};
static const model_ref PANDA = {KC_MODEL_PANDA, "panda", "dh_table_modified", 1};

static void model(kc_model m, kc_chain *c)
{
    assert_int_equal(kc_chain_init_model(c, m, NULL), KC_OK);
}

/* ---- reference configurations ---- */

static void test_rrr_configs(void **state)
{
    (void)state;
    json_t *root = kt_load("fk.json");
    const json_t *configs = kt_get(kt_get(root, "rrr"), "configs");
    kc_chain c;
    char what[64];
    model(KC_MODEL_RRR3, &c);
    assert_int_equal(c.n_frames, 3);
    assert_int_equal(json_array_size(configs), 20);
    for (size_t i = 0; i < json_array_size(configs); i++) {
        const json_t *cf = kt_at(configs, i);
        const json_t *A = kt_get(cf, "A_i");
        kc_real q[3];
        kc_pose T, frames[3], prod, Ai, rel, inv;
        kc_jacobian J;
        kt_read_reals(kt_get(cf, "q_rad"), q, 3);
        assert_int_equal(kc_fk_eval(&c, q, &T), KC_OK);
        snprintf(what, sizeof what, "rrr config %zu T", i);
        kt_near_pose_json(&T, kt_get(cf, "T"), KT_TOL_T, what);
        assert_int_equal(kc_fk_frames(&c, q, frames, NULL), KC_OK);
        kc_pose_identity(&prod);
        for (int k = 0; k < 3; k++) {
            /* frames[k] = A_1 ... A_(k+1), and A_(k+1) = frames[k-1]^-1 frames[k]. */
            kt_read_pose(kt_at(A, (size_t)k), &Ai);
            kc_pose_mul(&prod, &Ai, &prod);
            snprintf(what, sizeof what, "rrr config %zu A_1..A_%d", i, k + 1);
            kt_near_pose(&frames[k], &prod, KT_TOL_T, what);
            if (k == 0) {
                rel = frames[0];
            } else {
                kc_pose_inv(&frames[k - 1], &inv);
                kc_pose_mul(&inv, &frames[k], &rel);
            }
            snprintf(what, sizeof what, "rrr config %zu A_%d", i, k + 1);
            kt_near_pose_json(&rel, kt_at(A, (size_t)k), KT_TOL_T, what);
        }
        assert_int_equal(kc_fk_jacobian(&c, q, &J, NULL), KC_OK);
        snprintf(what, sizeof what, "rrr config %zu J0", i);
        kt_near_jac_json(&J, 3, kt_get(cf, "J0_6x3"), KT_TOL_T, what);
    }
    json_decref(root);
}

static void test_puma_configs(void **state)
{
    (void)state;
    json_t *root = kt_load("fk.json");
    const json_t *puma = kt_get(root, "puma560");
    const json_t *configs = kt_get(puma, "configs");
    kc_chain c;
    kc_pose base, tool;
    char what[64];
    model(KC_MODEL_PUMA560, &c);
    /* The file's base and tool are the identity, as the model's. */
    kt_read_pose(kt_get(puma, "base"), &base);
    kt_read_pose(kt_get(puma, "tool"), &tool);
    kt_near_pose(&c.base, &base, 0.0, "puma base");
    kt_near_pose(&c.tool, &tool, 0.0, "puma tool");
    assert_int_equal(c.n_frames, 6);
    assert_int_equal(json_array_size(configs), 50);
    for (size_t i = 0; i < json_array_size(configs); i++) {
        const json_t *cf = kt_at(configs, i);
        const json_t *cum = kt_get(cf, "T0i_cumulative");
        kc_real q[6];
        kc_pose T, T2, frames[6];
        kc_jacobian J;
        kt_read_reals(kt_get(cf, "q_rad"), q, 6);
        assert_int_equal(kc_fk_eval(&c, q, &T), KC_OK);
        snprintf(what, sizeof what, "puma config %zu T", i);
        kt_near_pose_json(&T, kt_get(cf, "T"), KT_TOL_T, what);
        assert_int_equal(kc_fk_frames(&c, q, frames, &T2), KC_OK);
        kt_near_pose(&T2, &T, 0.0, "puma frames' tool = fk_eval");
        assert_int_equal(json_array_size(cum), 6);
        for (int k = 0; k < 6; k++) {
            snprintf(what, sizeof what, "puma config %zu 0T_%d", i, k + 1);
            kt_near_pose_json(&frames[k], kt_at(cum, (size_t)k), KT_TOL_T, what);
        }
        assert_int_equal(kc_fk_jacobian(&c, q, &J, &T2), KC_OK);
        kt_near_pose(&T2, &T, 0.0, "puma jacobian's tool = fk_eval");
        snprintf(what, sizeof what, "puma config %zu J0", i);
        kt_near_jac_json(&J, 6, kt_get(cf, "J0_6x6"), KT_TOL_T, what);
    }
    json_decref(root);
}

/* Tool pose and flange (the last frame) of a Panda chain against the file. */
static void check_panda_configs(const kc_chain *c, const json_t *configs, int check_jacobian, const char *label)
{
    char what[80];
    assert_int_equal(json_array_size(configs), 20);
    for (size_t i = 0; i < json_array_size(configs); i++) {
        const json_t *cf = kt_at(configs, i);
        kc_real q[7];
        kc_pose T, frames[KC_MAX_FRAMES];
        kc_jacobian J;
        kt_read_reals(kt_get(cf, "q_rad"), q, 7);
        assert_int_equal(kc_fk_frames(c, q, frames, &T), KC_OK);
        snprintf(what, sizeof what, "%s config %zu T_tool", label, i);
        kt_near_pose_json(&T, kt_get(cf, "T_tool"), KT_TOL_T, what);
        snprintf(what, sizeof what, "%s config %zu T_flange", label, i);
        kt_near_pose_json(&frames[c->n_frames - 1], kt_get(cf, "T_flange"), KT_TOL_T, what);
        if (check_jacobian) {
            assert_int_equal(kc_fk_jacobian(c, q, &J, NULL), KC_OK);
            snprintf(what, sizeof what, "%s config %zu J0", label, i);
            kt_near_jac_json(&J, 7, kt_get(cf, "J0_6x7_tool_point"), KT_TOL_T, what);
        }
    }
}

static void test_panda_configs(void **state)
{
    (void)state;
    json_t *root = kt_load("fk.json");
    const json_t *panda = kt_get(root, "panda");
    kc_chain c;
    kc_pose tool;
    model(KC_MODEL_PANDA, &c);
    assert_int_equal(c.n_frames, 7);
    kt_read_pose(kt_get(panda, "tool"), &tool);
    kt_near_pose(&c.tool, &tool, KT_TOL_T, "panda tool");
    check_panda_configs(&c, kt_get(panda, "configs"), 1, "panda");
    json_decref(root);
}

/* A DH row from fk.json; modified rows carry a_prev/alpha_prev. */
static kc_dh_row dh_row(const json_t *r, int modified)
{
    kc_dh_row row;
    const char *type = json_string_value(kt_get(r, "type"));
    assert_non_null(type);
    row.type = type[0] == 'P' ? KC_JOINT_PRISMATIC : KC_JOINT_REVOLUTE;
    row.a = (kc_real)kt_num_of(r, modified ? "a_prev_m" : "a_m");
    row.alpha = (kc_real)kt_num_of(r, modified ? "alpha_prev_rad" : "alpha_rad");
    row.d = (kc_real)kt_num_of(r, "d_m");
    row.theta = (kc_real)kt_num_of(r, "offset_rad");
    row.limits = kc_joint_limits_default();
    return row;
}

static void test_panda_standard_dh(void **state)
{
    (void)state;
    json_t *root = kt_load("fk.json");
    const json_t *panda = kt_get(root, "panda");
    const json_t *table = kt_get(panda, "equivalent_standard_dh_table");
    kc_chain std, mdh;
    kc_pose tool;
    kt_rng rng = kt_rng_make(0xF0001);
    kc_chain_init(&std);
    for (size_t i = 0; i < json_array_size(table); i++) {
        kc_dh_row row = dh_row(kt_at(table, i), 0);
        assert_int_equal(kc_chain_add_dh(&std, &row), KC_OK);
    }
    kt_read_pose(kt_get(panda, "tool"), &tool);
    assert_int_equal(kc_chain_set_tool(&std, &tool), KC_OK);
    assert_int_equal(kc_chain_check(&std), KC_OK);
    check_panda_configs(&std, kt_get(panda, "configs"), 1, "panda standard DH");
    /* And the model itself at random configurations. */
    model(KC_MODEL_PANDA, &mdh);
    for (int n = 0; n < N_RANDOM; n++) {
        kc_real q[7];
        kc_pose a, b;
        kc_jacobian ja, jb;
        kt_rand_q(&rng, &mdh, q);
        assert_int_equal(kc_fk_jacobian(&std, q, &ja, &a), KC_OK);
        assert_int_equal(kc_fk_jacobian(&mdh, q, &jb, &b), KC_OK);
        kt_near_pose(&a, &b, KT_TOL_T, "panda standard vs modified DH");
        for (int r = 0; r < 6; r++)
            for (int j = 0; j < 7; j++)
                kt_near((double)ja.m[r][j], (double)jb.m[r][j], KT_TOL_T, "panda standard vs modified DH J");
    }
    json_decref(root);
}

/* ---- frame numbering ---- */

static void test_frame_numbering(void **state)
{
    (void)state;
    kc_chain c;
    kc_pose base, frames[3], T;
    kc_real q[1] = {KC_R(0.3)};
    kt_rng rng = kt_rng_make(0xF0002);
    base = kt_rand_pose(&rng);
    kc_chain_init(&c);
    assert_int_equal(kc_chain_set_base(&c, &base), KC_OK);
    assert_int_equal(kc_chain_add_frame(&c), KC_OK); /* an explicit base frame */
    assert_int_equal(kc_chain_add_code(&c, KC_CODE_RZ_JOINT, KC_R(0.0)), KC_OK);
    assert_int_equal(kc_chain_add_code(&c, KC_CODE_TX, KC_R(0.5)), KC_OK);
    assert_int_equal(c.n_frames, 3);
    assert_int_equal(kc_fk_frames(&c, q, frames, &T), KC_OK);
    kt_near_pose(&frames[0], &base, 0.0, "explicit frame 0 = base");
    kc_pose rz;
    kc_mat3_rot(KC_AXIS_Z, q[0], &rz.R);
    rz.t = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.0));
    kc_pose expect;
    kc_pose_mul(&base, &rz, &expect);
    kt_near_pose(&frames[1], &expect, KT_TOL_T, "frame after Rz(q)");
    kt_near_pose(&frames[2], &T, 0.0, "last frame = tool with identity tool");
    /* A dropped zero constant keeps its frame. */
    kc_chain_init(&c);
    assert_int_equal(kc_chain_add_code(&c, KC_CODE_RZ_JOINT, KC_R(0.0)), KC_OK);
    assert_int_equal(kc_chain_add_code(&c, KC_CODE_TX, KC_R(0.0)), KC_OK);
    assert_int_equal(c.n_frames, 2);
    assert_int_equal(c.n_elements, 1);
    assert_int_equal(kc_fk_frames(&c, q, frames, NULL), KC_OK);
    kt_near_pose(&frames[1], &frames[0], 0.0, "frame of a dropped Tx(0)");
}

/* ---- property tests ---- */

/* Largest distance any point of the chain can have from a joint axis: the
 * sum of the constant translations, the tool offset and the prismatic
 * travel. Bounds |f'''| of a position in one revolute q, and the size of
 * the positions whose rounding the finite differences divide by h. */
static double chain_reach(const kc_chain *c)
{
    double r = (double)kc_vec3_norm(&c->tool.t) + (double)kc_vec3_norm(&c->base.t);
    for (int e = 0; e < c->n_elements; e++)
        if (c->elements[e].code >= KC_CODE_TX)
            r += fabs((double)c->elements[e].value);
    for (int j = 0; j < c->n_joints; j++)
        if (c->joints[j].type == KC_JOINT_PRISMATIC)
            r += fmax(fabs((double)c->joints[j].limits.q_min), fabs((double)c->joints[j].limits.q_max));
    return r;
}

/*
 * Jacobian against central finite differences of FK.
 * FK rounds each of its n elementary steps (plus base and tool) at about one
 * unit of KC_REAL_EPS of the reach R, so a position carries at most
 * e = (n + 2) eps R. The central difference of a revolute joint has
 * truncation h^2/6 |f'''| <= h^2 R / 6 and rounding 2e / 2h = e / h; the
 * step h = cbrt(3 e / R) minimises the sum. The angular part is exact up to
 * rounding: turning joint j by 2h turns the tool by Rot(z_j, 2h), whose
 * rotation vector (quaternion log of R+ R-^T) is 2h z_j; its entries carry
 * (n + 2) eps each, so the error is (n + 2) eps / h. The step actually taken
 * is the rounded (q + h) - (q - h).
 */
static void check_jacobian_fd(const kc_chain *c, const kc_real *q, const char *label)
{
    double R = chain_reach(c), eps = (double)KC_REAL_EPS, n = (double)(c->n_elements + 2);
    double e = n * eps * fmax(R, 1.0);
    double h = cbrt(3.0 * e / fmax(R, 1.0));
    double tol_lin = h * h * R / 6.0 + e / h;
    double tol_ang = n * eps / h;
    kc_jacobian J;
    char what[96];
    assert_int_equal(kc_fk_jacobian(c, q, &J, NULL), KC_OK);
    for (int j = 0; j < c->n_joints; j++) {
        kc_real qp[KC_MAX_JOINTS], qm[KC_MAX_JOINTS];
        kc_pose Tp, Tm;
        memcpy(qp, q, sizeof qp[0] * (size_t)c->n_joints);
        memcpy(qm, q, sizeof qm[0] * (size_t)c->n_joints);
        qp[j] = q[j] + (kc_real)h;
        qm[j] = q[j] - (kc_real)h;
        double step = (double)(qp[j] - qm[j]);
        assert_int_equal(kc_fk_eval(c, qp, &Tp), KC_OK);
        assert_int_equal(kc_fk_eval(c, qm, &Tm), KC_OK);
        kc_mat3 dR;
        kc_quat dq;
        kc_vec3 w;
        kc_mat3_transpose(&Tm.R, &dR);
        kc_mat3_mul(&Tp.R, &dR, &dR);
        kc_quat_from_mat3(&dR, &dq);
        kc_quat_log(&dq, &w);
        for (int i = 0; i < 3; i++) {
            snprintf(what, sizeof what, "%s dJ/dq%d linear[%d] (h %.2g)", label, j + 1, i, h);
            kt_near((double)J.m[i][j], ((double)Tp.t.v[i] - (double)Tm.t.v[i]) / step, tol_lin, what);
            snprintf(what, sizeof what, "%s dJ/dq%d angular[%d] (h %.2g)", label, j + 1, i, h);
            kt_near((double)J.m[i + 3][j], (double)w.v[i] / step, tol_ang, what);
        }
    }
}

/* Orthonormality of the tool rotation: each of the n + 2 products rounds
 * the entries by about 2 eps, and R^T R - I doubles that. */
static void check_orthonormal(const kc_chain *c, const kc_pose *T, const char *label)
{
    double tol = 4.0 * (double)(c->n_elements + 2) * (double)KC_REAL_EPS;
    kt_near((double)kc_mat3_rotation_error(&T->R), 0.0, tol, label);
}

/* The DH table of fk.json as seed 003's elementary codes:
 * standard [3 q][12 d][10 a][7 alpha], modified [7 alpha][10 a][3 q][12 d]. */
static void code_chain_of_table(const json_t *root, const model_ref *m, kc_chain *c)
{
    const json_t *obj = kt_get(root, m->key);
    const json_t *table = kt_get(obj, m->table);
    kc_chain_init(c);
    for (size_t i = 0; i < json_array_size(table); i++) {
        kc_dh_row r = dh_row(kt_at(table, i), m->modified);
        assert_true(r.type == KC_JOINT_REVOLUTE && r.theta == KC_R(0.0)); /* codes carry no offset */
        if (m->modified) {
            assert_int_equal(kc_chain_add_code(c, KC_CODE_RX, r.alpha), KC_OK);
            assert_int_equal(kc_chain_add_code(c, KC_CODE_TX, r.a), KC_OK);
        }
        assert_int_equal(kc_chain_add_code(c, KC_CODE_RZ_JOINT, (kc_real)i), KC_OK);
        assert_int_equal(kc_chain_add_code(c, KC_CODE_TZ, r.d), KC_OK);
        if (!m->modified) {
            assert_int_equal(kc_chain_add_code(c, KC_CODE_TX, r.a), KC_OK);
            assert_int_equal(kc_chain_add_code(c, KC_CODE_RX, r.alpha), KC_OK);
        }
    }
    const json_t *tool = json_object_get(obj, "tool");
    if (tool != NULL) {
        kc_pose t;
        kt_read_pose(tool, &t);
        assert_int_equal(kc_chain_set_tool(c, &t), KC_OK);
    }
}

static void property_tests(const json_t *root, const model_ref *m, uint64_t seed)
{
    kc_chain c, codes;
    kt_rng rng = kt_rng_make(seed);
    char label[64];
    model(m->model, &c);
    code_chain_of_table(root, m, &codes);
    assert_int_equal(kc_chain_check(&codes), KC_OK);
    assert_int_equal(codes.n_joints, c.n_joints);
    for (int n = 0; n < N_RANDOM; n++) {
        kc_real q[KC_MAX_JOINTS];
        kc_pose T, Tc;
        kc_jacobian J, Jc;
        kt_rand_q(&rng, &c, q);
        assert_int_equal(kc_fk_jacobian(&c, q, &J, &T), KC_OK);
        snprintf(label, sizeof label, "%s random %d", m->key, n);
        check_orthonormal(&c, &T, label);
        check_jacobian_fd(&c, q, label);
        /* DH chain = its elementary-transform chain. */
        assert_int_equal(kc_fk_jacobian(&codes, q, &Jc, &Tc), KC_OK);
        kt_near_pose(&Tc, &T, KT_TOL_T, "DH chain vs elementary codes");
        for (int r = 0; r < 6; r++)
            for (int j = 0; j < c.n_joints; j++)
                kt_near((double)Jc.m[r][j], (double)J.m[r][j], KT_TOL_T, "DH chain vs elementary codes J");
    }
}

static void test_properties_rrr(void **state)
{
    (void)state;
    json_t *root = kt_load("fk.json");
    property_tests(root, &RRR, 0xF0010);
    json_decref(root);
}

static void test_properties_puma(void **state)
{
    (void)state;
    json_t *root = kt_load("fk.json");
    property_tests(root, &PUMA, 0xF0011);
    json_decref(root);
}

static void test_properties_panda(void **state)
{
    (void)state;
    json_t *root = kt_load("fk.json");
    property_tests(root, &PANDA, 0xF0012);
    json_decref(root);
}

/* Prismatic joints: column [z; 0] with z the joint's world axis, and the
 * finite differences, on a DH chain R-P-R and on seed 003's RPP demo. */
static void test_prismatic(void **state)
{
    (void)state;
    kc_chain c;
    kt_rng rng = kt_rng_make(0xF0013);
    kc_joint_limits lim = {KC_R(-0.5), KC_R(0.5), KC_R(1.0), KC_R(1.0), KC_R(1.0)};
    kc_dh_row rows[3] = {
        {KC_JOINT_REVOLUTE, KC_R(0.2), KC_R(0.7), KC_R(0.3), KC_R(0.1), lim},
        {KC_JOINT_PRISMATIC, KC_R(0.1), KC_R(-1.2), KC_R(0.25), KC_R(0.4), lim},
        {KC_JOINT_REVOLUTE, KC_R(0.15), KC_R(0.0), KC_R(0.05), KC_R(0.0), lim},
    };
    kc_chain_init(&c);
    for (int i = 0; i < 3; i++)
        assert_int_equal(kc_chain_add_dh(&c, &rows[i]), KC_OK);
    assert_int_equal(c.joints[1].type, KC_JOINT_PRISMATIC);
    for (int n = 0; n < N_RANDOM; n++) {
        kc_real q[3];
        kc_pose frames[3];
        kc_jacobian J;
        kt_rand_q(&rng, &c, q);
        assert_int_equal(kc_fk_frames(&c, q, frames, NULL), KC_OK);
        assert_int_equal(kc_fk_jacobian(&c, q, &J, NULL), KC_OK);
        /* Standard DH: joint 2 slides along z of frame 1. */
        for (int i = 0; i < 3; i++) {
            kt_near((double)J.m[i][1], (double)frames[0].R.m[i][2], KT_TOL_T, "prismatic column linear");
            kt_near((double)J.m[i + 3][1], 0.0, 0.0, "prismatic column angular");
        }
        check_jacobian_fd(&c, q, "R-P-R DH");
    }
    /* Seed 003's cylindrical RPP demo (codes 3, 12, 6, 4, 9). */
    kc_chain_init(&c);
    static const int codes[5] = {3, 12, 6, 4, 9};
    static const double args[5] = {0, 0.3, 1, 2, 1.5707963267948966};
    for (int i = 0; i < 5; i++)
        assert_int_equal(kc_chain_add_code(&c, codes[i], (kc_real)args[i]), KC_OK);
    for (int j = 1; j < 3; j++)
        assert_int_equal(kc_chain_set_limits(&c, j, &lim), KC_OK);
    for (int n = 0; n < N_RANDOM; n++) {
        kc_real q[3];
        kt_rand_q(&rng, &c, q);
        check_jacobian_fd(&c, q, "RPP codes");
    }
}

/* ---- errors ---- */

static void test_nan_q(void **state)
{
    (void)state;
    kc_chain c;
    kc_pose T, frames[KC_MAX_FRAMES];
    kc_jacobian J;
    model(KC_MODEL_PUMA560, &c);
    for (int j = 0; j < 6; j++) {
        kc_real q[6] = {0};
        q[j] = j % 2 ? (kc_real)NAN : (kc_real)INFINITY;
        memset(&T, KT_SENTINEL, sizeof T);
        memset(frames, KT_SENTINEL, sizeof frames);
        memset(&J, KT_SENTINEL, sizeof J);
        assert_int_equal(kc_fk_eval(&c, q, &T), KC_E_ARG);
        assert_int_equal(kc_fk_frames(&c, q, frames, &T), KC_E_ARG);
        assert_int_equal(kc_fk_jacobian(&c, q, &J, &T), KC_E_ARG);
        assert_true(kt_is_sentinel(&T, sizeof T));
        assert_true(kt_is_sentinel(frames, sizeof frames));
        assert_true(kt_is_sentinel(&J, sizeof J));
    }
    kc_real q[6] = {0};
    assert_int_equal(kc_fk_eval(NULL, q, &T), KC_E_ARG);
    assert_int_equal(kc_fk_eval(&c, NULL, &T), KC_E_ARG);
    assert_int_equal(kc_fk_eval(&c, q, NULL), KC_E_ARG);
    assert_int_equal(kc_fk_frames(&c, q, NULL, &T), KC_E_ARG);
    assert_int_equal(kc_fk_jacobian(&c, q, NULL, &T), KC_E_ARG);
    assert_true(kt_is_sentinel(&T, sizeof T));
}

/* ---- rrr3 with custom lengths: fk.json's rrr.closed_form ---- */

static void rrr_closed_form(const double l[3], const kc_real *q, kc_mat4 *T)
{
    double q1 = (double)q[0], q2 = (double)q[1], q3 = (double)q[2];
    double c1 = cos(q1), s1 = sin(q1), c2 = cos(q2), s2 = sin(q2), c23 = cos(q2 + q3), s23 = sin(q2 + q3);
    double r = l[1] * c2 + l[2] * c23;
    double m[4][4] = {{c1 * c23, -c1 * s23, s1, c1 * r},
                      {s1 * c23, -s1 * s23, -c1, s1 * r},
                      {s23, c23, 0.0, l[0] + l[1] * s2 + l[2] * s23},
                      {0.0, 0.0, 0.0, 1.0}};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            T->m[i][j] = (kc_real)m[i][j];
}

/* FK of an rrr3 chain against the closed form with lengths l. */
static void check_closed_form(const kc_chain *c, const double l[3], const kc_real *q, const char *label)
{
    kc_pose T;
    kc_mat4 H, E;
    assert_int_equal(kc_fk_eval(c, q, &T), KC_OK);
    rrr_closed_form(l, q, &E);
    kc_pose_to_mat4(&T, &H);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            kt_near((double)H.m[i][j], (double)E.m[i][j], KT_TOL_T, label);
}

static void test_rrr_custom_lengths(void **state)
{
    (void)state;
    json_t *root = kt_load("fk.json");
    const json_t *lengths = kt_get(kt_get(root, "rrr"), "lengths_m");
    kt_rng rng = kt_rng_make(0xF0014);
    static const double custom[3] = {0.55, 0.35, 0.2};
    const double defaults[3] = {kt_num_of(lengths, "l1"), kt_num_of(lengths, "l2"), kt_num_of(lengths, "l3")};
    /* Custom lengths; and a non-positive entry selects the default. */
    kc_model_params p = {{(kc_real)custom[0], (kc_real)custom[1], (kc_real)custom[2], KC_R(0.0)}};
    kc_model_params mixed = {{KC_R(0.0), (kc_real)custom[1], KC_R(-1.0), KC_R(0.0)}};
    const double mixed_l[3] = {defaults[0], custom[1], defaults[2]};
    kc_chain c, cm, cd;
    assert_int_equal(kc_chain_init_model(&c, KC_MODEL_RRR3, &p), KC_OK);
    assert_int_equal(kc_chain_init_model(&cm, KC_MODEL_RRR3, &mixed), KC_OK);
    model(KC_MODEL_RRR3, &cd);
    for (int n = 0; n < N_RANDOM; n++) {
        kc_real q[3];
        kt_rand_q(&rng, &c, q);
        check_closed_form(&c, custom, q, "rrr3 custom lengths vs closed form");
        check_closed_form(&cm, mixed_l, q, "rrr3 mixed lengths vs closed form");
        check_closed_form(&cd, defaults, q, "rrr3 default lengths vs closed form");
    }
    json_decref(root);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rrr_configs),
        cmocka_unit_test(test_puma_configs),
        cmocka_unit_test(test_panda_configs),
        cmocka_unit_test(test_panda_standard_dh),
        cmocka_unit_test(test_frame_numbering),
        cmocka_unit_test(test_properties_rrr),
        cmocka_unit_test(test_properties_puma),
        cmocka_unit_test(test_properties_panda),
        cmocka_unit_test(test_prismatic),
        cmocka_unit_test(test_nan_q),
        cmocka_unit_test(test_rrr_custom_lengths),
    };
    int failed = cmocka_run_group_tests_name("fk (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("fk");
    return failed;
}
