/* SPDX-License-Identifier: BSD-3-Clause */
/* test_desc.c - the robot description reader (kinctl/desc.h): every example
 * file in models/ against its built-in model, and every kind of bad file
 * with the line and message it must report. */
#define _POSIX_C_SOURCE 200809L /* mkstemp, fdopen */

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "kinctl/desc.h"
#include "kinctl/fk.h"
#include "testutil.h"

#ifdef KC_REAL_FLOAT
#define TOL KC_R(2e-5)
#else
#define TOL KC_R(1e-12)
#endif

#define N_CONFIGS 500

static const char *models_dir(void)
{
    const char *d = getenv("KINCTL_MODELS");
    return d != NULL ? d : KINCTL_MODELS_DIR;
}

static void check_model_file(kc_model model)
{
    char path[1024];
    kc_chain file, ref;
    kc_desc_info info;
    kc_desc_error err;
    const char *name = kc_model_name(model);
    snprintf(path, sizeof path, "%s/%s.cfg", models_dir(), name);
    kc_status st = kc_desc_load_file(path, &file, &info, &err);
    if (st != KC_OK)
        fail_msg("%s", err.text);
    assert_int_equal(kc_chain_init_model(&ref, model, NULL), KC_OK);
    assert_string_equal(info.name, name);
    assert_int_equal(info.n_joints, ref.n_joints);
    assert_int_equal(file.n_joints, ref.n_joints);
    assert_int_equal(file.n_frames, ref.n_frames);
    /* Joint types, offsets and limits exactly as the built-in model. */
    for (int j = 0; j < ref.n_joints; j++) {
        const kc_joint *a = &file.joints[j], *b = &ref.joints[j];
        assert_int_equal(a->type, b->type);
        assert_true(a->offset == b->offset);
        assert_true(a->limits.q_min == b->limits.q_min);
        assert_true(a->limits.q_max == b->limits.q_max);
        assert_true(a->limits.qd_max == b->limits.qd_max);
        assert_true(a->limits.qdd_max == b->limits.qdd_max);
        assert_true(a->limits.qddd_max == b->limits.qddd_max);
        assert_true(info.joint_names[j][0] != '\0');
    }
    /* The same link volumes on the same frames, each named. */
    assert_int_equal(file.n_volumes, ref.n_volumes);
    assert_int_equal(info.n_volumes, ref.n_volumes);
    for (int v = 0; v < ref.n_volumes; v++) {
        const kc_link_volume *a = &file.volumes[v], *b = &ref.volumes[v];
        assert_int_equal(a->frame, b->frame);
        assert_int_equal(a->shape.kind, b->shape.kind);
        kt_near_pose(&a->shape.pose, &b->shape.pose, TOL, "volume pose");
        for (int i = 0; i < KC_SHAPE_DIMS; i++)
            assert_true(kc_fabs(a->shape.dim[i] - b->shape.dim[i]) <= TOL);
        assert_true(info.volume_names[v][0] != '\0');
    }
    kt_rng rng = kt_rng_make(20240601u + (uint64_t)model);
    for (int k = 0; k < N_CONFIGS; k++) {
        kc_real q[KC_MAX_JOINTS];
        kc_pose ta, tb, fa[KC_MAX_FRAMES], fb[KC_MAX_FRAMES];
        kc_jacobian ja, jb;
        kt_rand_q(&rng, &ref, q);
        assert_int_equal(kc_fk_frames(&file, q, fa, &ta), KC_OK);
        assert_int_equal(kc_fk_frames(&ref, q, fb, &tb), KC_OK);
        kt_near_pose(&ta, &tb, TOL, "tool pose");
        for (int f = 0; f < ref.n_frames; f++)
            kt_near_pose(&fa[f], &fb[f], TOL, "frame");
        assert_int_equal(kc_fk_jacobian(&file, q, &ja, NULL), KC_OK);
        assert_int_equal(kc_fk_jacobian(&ref, q, &jb, NULL), KC_OK);
        for (int i = 0; i < 6; i++)
            for (int j = 0; j < ref.n_joints; j++)
                assert_true(kc_fabs(ja.m[i][j] - jb.m[i][j]) <= TOL);
    }
}

static void test_puma560_file(void **state)
{
    (void)state;
    check_model_file(KC_MODEL_PUMA560);
}
static void test_panda_file(void **state)
{
    (void)state;
    check_model_file(KC_MODEL_PANDA);
}
static void test_rrr3_file(void **state)
{
    (void)state;
    check_model_file(KC_MODEL_RRR3);
}
static void test_planar2_file(void **state)
{
    (void)state;
    check_model_file(KC_MODEL_PLANAR2);
}
static void test_rb211_file(void **state)
{
    (void)state;
    check_model_file(KC_MODEL_RB211);
}
static void test_rm01_file(void **state)
{
    (void)state;
    check_model_file(KC_MODEL_RM01);
}

/* A good two-joint robot with the features the model files do not use:
 * integers as numbers, lists as vectors, a prismatic row, degrees in the
 * base rpy, a controller section the reader must leave alone. */
static void test_good_variants(void **state)
{
    (void)state;
    const char *text = "controller = { period_ns = 1000000; whatever = \"kinctld reads this\"; };\n"
                       "robot = {\n"
                       "  name = \"rp\"; angles = \"deg\";\n"
                       "  base = { xyz = (0, 0, 1); rpy = [0.0, 0.0, 90.0]; };\n"
                       "  dh = (\n"
                       "    { type = \"revolute\"; a = 1; alpha = 90; d = 0; theta = 90;\n"
                       "      limits = { q = [-90, 90]; qd = 180; }; },\n"
                       "    { type = \"prismatic\"; a = 0; alpha = 0; d = 0.5; theta = 0;\n"
                       "      limits = { q = (0, 0.3); qd = 0.2; }; }\n"
                       "  );\n"
                       "};\n";
    kc_chain c;
    kc_desc_info info;
    kc_desc_error err;
    kc_status st = kc_desc_load_string(text, "rp.cfg", &c, &info, &err);
    if (st != KC_OK)
        fail_msg("%s", err.text);
    assert_int_equal(c.n_joints, 2);
    assert_int_equal(info.angles_deg, 1);
    assert_int_equal(info.kind, KC_DESC_DH);
    assert_string_equal(info.joint_names[0], "");
    assert_true(c.joints[0].offset == KC_R(90.0) * KC_DEG);
    assert_true(c.joints[0].limits.q_min == KC_R(-90.0) * KC_DEG);
    assert_true(c.joints[0].limits.qd_max == KC_R(180.0) * KC_DEG);
    assert_true(kc_isfinite(c.joints[0].limits.qdd_max) == 0); /* omitted: no limit */
    assert_int_equal(c.joints[1].type, KC_JOINT_PRISMATIC);
    assert_true(c.joints[1].offset == KC_R(0.5));  /* d is the prismatic offset */
    assert_true(c.joints[1].limits.q_max == KC_R(0.3)); /* metres: no conversion */
    assert_true(c.joints[1].limits.qd_max == KC_R(0.2));
    /* q = 0: base Rz(90) at z = 1, Rz(90) Tx(1) Rx(90), then Tz(0.5). */
    kc_real q[2] = {KC_R(0.0), KC_R(0.0)};
    kc_pose t;
    assert_int_equal(kc_fk_eval(&c, q, &t), KC_OK);
    assert_true(kc_fabs(t.t.v[0] - KC_R(-1.0)) <= TOL);
    assert_true(kc_fabs(t.t.v[1] - KC_R(0.5)) <= TOL);
    assert_true(kc_fabs(t.t.v[2] - KC_R(1.0)) <= TOL);
}

static void test_elements_and_names(void **state)
{
    (void)state;
    const char *text = "robot = {\n"
                       "  name = \"cyl\"; angles = \"rad\";\n"
                       "  elements = (\n"
                       "    { op = \"rz\"; joint = true; name = \"turn\"; offset = 0.5; },\n"
                       "    { op = \"tz\"; joint = true; name = \"lift\"; limits = { q = [0.0, 1.0]; }; },\n"
                       "    { op = \"ry\"; value = 0.25; frame = true; },\n"
                       "    { op = \"tx\"; joint = true; }\n"
                       "  );\n"
                       "};\n";
    kc_chain c;
    kc_desc_info info;
    kc_desc_error err;
    kc_status st = kc_desc_load_string(text, NULL, &c, &info, &err);
    if (st != KC_OK)
        fail_msg("%s", err.text);
    assert_int_equal(info.kind, KC_DESC_ELEMENTS);
    assert_int_equal(c.n_joints, 3);
    assert_int_equal(c.n_frames, 4);
    assert_string_equal(info.joint_names[0], "turn");
    assert_string_equal(info.joint_names[1], "lift");
    assert_string_equal(info.joint_names[2], "");
    assert_int_equal(c.joints[1].type, KC_JOINT_PRISMATIC);
    assert_true(c.joints[0].offset == KC_R(0.5));
}

/* ---- bad files ---- */

typedef struct bad_case {
    const char *what;
    const char *text;
    int line;
    const char *message; /* a substring of the problem */
    kc_status status;
} bad_case;

#define HEAD "robot = {\n  name = \"x\"; angles = \"rad\";\n"
#define ROW "    { type = \"revolute\"; a = 0.1; alpha = 0.0; d = 0.0; theta = 0.0; },\n"
#define ROW_LAST "    { type = \"revolute\"; a = 0.1; alpha = 0.0; d = 0.0; theta = 0.0; }\n"
#define ROWS4 ROW ROW ROW ROW
#define ROWS16 ROWS4 ROWS4 ROWS4 ROWS4

static const bad_case bad_cases[] = {
    {"syntax error: no comma between rows", HEAD "  dh = (\n" ROW_LAST ROW_LAST "  );\n};\n", 5, "syntax error", KC_E_ARG},
    {"NaN cannot be written", HEAD "  dh = (\n    { type = \"revolute\"; a = nan; alpha = 0.0; d = 0.0; theta = 0.0; }\n  );\n};\n",
     4, "syntax error", KC_E_ARG},
    {"overflow to inf", HEAD "  dh = (\n    { type = \"revolute\"; a = 1e999; alpha = 0.0; d = 0.0; theta = 0.0; }\n  );\n};\n",
     4, "dh row 1: a is not a finite number", KC_E_ARG},
    {"-inf in a limit", HEAD "  dh = (\n    { type = \"revolute\"; a = 0.0; alpha = 0.0; d = 0.0; theta = 0.0;\n"
                             "      limits = { q = [-1e999, 1.0]; }; }\n  );\n};\n",
     5, "dh row 1 limits: q[0] is not a finite number", KC_E_ARG},
    {"min > max", HEAD "  dh = (\n" ROW "    { type = \"revolute\"; a = 0.0; alpha = 0.0; d = 0.0; theta = 0.0;\n"
                       "      limits = { q = [1.0, -1.0]; }; }\n  );\n};\n",
     6, "dh row 2 limits: q min 1 > max -1", KC_E_ARG},
    {"zero rate", HEAD "  dh = (\n    { type = \"revolute\"; a = 0.0; alpha = 0.0; d = 0.0; theta = 0.0;\n"
                       "      limits = {\n        qdd = 0.0; }; }\n  );\n};\n",
     6, "dh row 1 limits: qdd must be > 0", KC_E_ARG},
    {"rate beyond the planners' range", HEAD "  dh = (\n    { type = \"revolute\"; a = 0.0; alpha = 0.0; d = 0.0; theta = 0.0;\n"
                       "      limits = {\n        qddd = 1e-300; }; }\n  );\n};\n",
     6, "dh row 1 limits: qddd = 1e-300 is outside 1e-09 .. 1e+09 (in rad or m)", KC_E_ARG},
    {"unknown joint type", HEAD "  dh = (\n    { type = \"revolut\"; a = 0.0; alpha = 0.0; d = 0.0; theta = 0.0; }\n  );\n};\n",
     4, "dh row 1: unknown joint type \"revolut\" (expected \"revolute\" or \"prismatic\")", KC_E_ARG},
    {"unknown op", HEAD "  elements = (\n    { op = \"rz\"; joint = true; },\n    { op = \"rw\"; value = 1.0; }\n  );\n};\n",
     5, "elements element 2: unknown op \"rw\"", KC_E_ARG},
    {"too many joints", HEAD "  mdh = (\n" ROWS16 ROW_LAST "  );\n};\n", 20,
     "too many joints: kinctl supports at most 16", KC_E_CAPACITY},
    {"missing key", HEAD "  dh = (\n" ROW "    { type = \"revolute\"; a = 0.0; d = 0.0; theta = 0.0; }\n  );\n};\n", 5,
     "dh row 2: missing key \"alpha\"", KC_E_ARG},
    {"missing type", HEAD "  dh = (\n    { a = 0.0; alpha = 0.0; d = 0.0; theta = 0.0; }\n  );\n};\n", 4,
     "dh row 1: missing key \"type\"", KC_E_ARG},
    {"wrong type", HEAD "  dh = (\n    { type = \"revolute\"; a = \"0.1\"; alpha = 0.0; d = 0.0; theta = 0.0; }\n  );\n};\n",
     4, "dh row 1: a must be a number", KC_E_ARG},
    {"unknown key in robot", HEAD "  nmae = \"y\";\n  dh = ( " ROW_LAST " );\n};\n", 3,
     "unknown key \"nmae\" in robot (expected one of: name, angles, base, tool, dh, mdh, elements, volumes)", KC_E_ARG},
    {"unknown key in a row", HEAD "  dh = (\n    { type = \"revolute\"; a = 0.0; alhpa = 0.0; d = 0.0; theta = 0.0; }\n  );\n};\n",
     4, "unknown key \"alhpa\" in dh row 1", KC_E_ARG},
    {"unknown key in limits", HEAD "  dh = (\n    { type = \"revolute\"; a = 0.0; alpha = 0.0; d = 0.0; theta = 0.0;\n"
                                   "      limits = { q = [-1.0, 1.0];\n        qmax = 2.0; }; }\n  );\n};\n",
     6, "unknown key \"qmax\" in dh row 1 limits", KC_E_ARG},
    {"unknown top-level section", "robto = { name = \"x\"; };\n" HEAD "  dh = ( " ROW_LAST " );\n};\n", 1,
     "unknown key \"robto\" in the top level (expected one of: robot, controller)", KC_E_ARG},
    {"no robot", "controller = { period_ns = 1000000; };\n", 0, "no robot section", KC_E_ARG},
    {"robot not a group", "robot = 3;\n", 1, "robot must be a group", KC_E_ARG},
    {"missing name", "robot = {\n  angles = \"rad\";\n  dh = ( " ROW_LAST " );\n};\n", 1, "robot: missing key \"name\"",
     KC_E_ARG},
    {"empty name", "robot = {\n  name = \"\"; angles = \"rad\";\n  dh = ( " ROW_LAST " );\n};\n", 2,
     "robot: name must have 1 to 63 characters", KC_E_ARG},
    {"missing angles", "robot = {\n  name = \"x\";\n  dh = ( " ROW_LAST " );\n};\n", 1, "robot: missing key \"angles\"",
     KC_E_ARG},
    {"bad angle unit", "robot = {\n  name = \"x\";\n  angles = \"grad\";\n  dh = ( " ROW_LAST " );\n};\n", 3,
     "robot: unknown angle unit \"grad\"", KC_E_ARG},
    {"empty chain", HEAD "  dh = (\n  );\n};\n", 3, "dh is empty: a chain needs at least one joint", KC_E_ARG},
    {"no chain", HEAD "  base = { xyz = [0.0, 0.0, 0.0]; };\n};\n", 1, "robot has no chain", KC_E_ARG},
    {"two chains", HEAD "  dh = ( " ROW_LAST " );\n  mdh = ( " ROW_LAST " );\n};\n", 5, "robot has both dh and mdh",
     KC_E_ARG},
    {"dh as an array", HEAD "  dh = [1.0, 2.0];\n};\n", 3, "dh must be a list in parentheses", KC_E_ARG},
    {"row not a group", HEAD "  dh = ( " ROW "    3.0\n  );\n};\n", 4, "dh row 2 must be a group", KC_E_ARG},
    {"elements without a joint", HEAD "  elements = (\n    { op = \"tz\"; value = 1.0; }\n  );\n};\n", 3,
     "elements has no joint", KC_E_ARG},
    {"constant without value", HEAD "  elements = (\n    { op = \"rz\"; joint = true; },\n    { op = \"tz\"; }\n  );\n};\n", 5,
     "elements element 2: missing key \"value\"", KC_E_ARG},
    {"joint with value", HEAD "  elements = (\n    { op = \"rz\"; joint = true;\n      value = 1.0; }\n  );\n};\n", 5,
     "elements element 1: a joint takes offset, not value", KC_E_ARG},
    {"constant with limits", HEAD "  elements = (\n    { op = \"rz\"; joint = true; },\n"
                                  "    { op = \"tz\"; value = 1.0;\n      limits = { qd = 1.0; }; }\n  );\n};\n",
     6, "elements element 2: limits belongs to a joint", KC_E_ARG},
    {"joint flag not boolean", HEAD "  elements = (\n    { op = \"rz\"; joint = 1; }\n  );\n};\n", 4,
     "elements element 1: joint must be true or false", KC_E_ARG},
    {"vector too short", HEAD "  base = { xyz = [0.0, 0.0]; };\n  dh = ( " ROW_LAST " );\n};\n", 3,
     "base xyz must hold 3 numbers, not 2", KC_E_ARG},
    {"vector not a vector", HEAD "  tool = {\n    rpy = 0.5; };\n  dh = ( " ROW_LAST " );\n};\n", 4,
     "tool rpy must be a vector of 3 numbers", KC_E_ARG},
    {"mixed array", HEAD "  tool = { xyz = [0, 0, 0.1]; };\n  dh = ( " ROW_LAST " );\n};\n", 3,
     "mismatched element type in array (an array [..] may not mix 1 and 1.5: write 1.0)", KC_E_ARG},
    {"unknown volume shape", HEAD "  dh = ( " ROW_LAST " );\n  volumes = (\n    { frame = 1; shape = \"cone\"; }\n  );\n};\n", 6,
     "volume 1: unknown shape \"cone\" (expected sphere, capsule, cylinder, box, frustum)", KC_E_ARG},
    {"half-space volume", HEAD "  dh = ( " ROW_LAST " );\n  volumes = (\n    { frame = 1;\n shape = \"halfspace\"; }\n  );\n};\n", 7,
     "volume 1: unknown shape \"halfspace\"", KC_E_ARG},
    {"volume frame out of range", HEAD "  dh = ( " ROW_LAST " );\n  volumes = (\n    { shape = \"sphere\"; xyz = [0.0, 0.0, 0.0]; radius = 0.1;\n"
                                       "      frame = 2; }\n  );\n};\n", 7,
     "volume 1: frame must be a whole number 1 .. 1", KC_E_ARG},
    {"volume without frame", HEAD "  dh = ( " ROW_LAST " );\n  volumes = (\n    { shape = \"sphere\"; xyz = [0.0, 0.0, 0.0]; radius = 0.1; }\n  );\n};\n", 6,
     "volume 1: missing key \"frame\"", KC_E_ARG},
    {"capsule of zero length", HEAD "  dh = ( " ROW_LAST " );\n  volumes = (\n    { frame = 1; shape = \"capsule\"; from = [0.0, 0.0, 0.0];\n"
                                    "      to = [0.0, 0.0, 0.0]; radius = 0.1; }\n  );\n};\n", 6,
     "volume 1: a capsule needs from != to and radius > 0", KC_E_ARG},
    {"key of another shape", HEAD "  dh = ( " ROW_LAST " );\n  volumes = (\n    { frame = 1; shape = \"box\"; xyz = [0.0, 0.0, 0.0]; half = [0.1, 0.1, 0.1];\n"
                                  "      radius = 0.1; }\n  );\n};\n", 7,
     "volume 1: a box takes no radius", KC_E_ARG},
    {"negative box size", HEAD "  dh = ( " ROW_LAST " );\n  volumes = (\n    { frame = 1; shape = \"box\"; xyz = [0.0, 0.0, 0.0]; half = [0.1, -0.1, 0.1]; }\n  );\n};\n", 6,
     "volume 1: every size of a box must be > 0", KC_E_ARG},
    {"duplicate key", HEAD "  dh = ( " ROW_LAST " );\n  dh = ( " ROW_LAST " );\n};\n", 5, "duplicate setting name", KC_E_ARG},
};

static void test_bad_files(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) {
        const bad_case *b = &bad_cases[i];
        kc_chain c, before;
        kc_desc_info info;
        kc_desc_error err;
        char prefix[128];
        kc_chain_init(&c);
        c.n_joints = 99; /* a marker: the chain must stay untouched */
        before = c;
        kc_status st = kc_desc_load_string(b->text, "bad.cfg", &c, &info, &err);
        if (st != b->status || err.line != b->line || strstr(err.problem, b->message) == NULL)
            fail_msg("case \"%s\": status %d (want %d), message \"%s\" (want line %d: \"%s\")", b->what, (int)st,
                     (int)b->status, err.text, b->line, b->message);
        assert_memory_equal(&c, &before, sizeof c);
        assert_string_equal(err.file, "bad.cfg");
        if (b->line > 0)
            snprintf(prefix, sizeof prefix, "bad.cfg:%d: ", b->line);
        else
            snprintf(prefix, sizeof prefix, "bad.cfg: ");
        assert_int_equal(strncmp(err.text, prefix, strlen(prefix)), 0);
    }
}

/* The last valid joint count is accepted: 16 rows build. */
static void test_max_joints(void **state)
{
    (void)state;
    kc_chain c;
    kc_desc_error err;
    kc_status st = kc_desc_load_string(HEAD "  dh = (\n" ROWS4 ROWS4 ROWS4 ROW ROW ROW ROW_LAST "  );\n};\n", NULL, &c,
                                       NULL, &err);
    if (st != KC_OK)
        fail_msg("%s", err.text);
    assert_int_equal(c.n_joints, KC_MAX_JOINTS);
}

/* 1 joint frame + 64 constant frames: the 65th frame exceeds
 * KC_MAX_FRAMES on its own line. */
static void test_too_many_frames(void **state)
{
    (void)state;
    static char text[8192];
    size_t len = (size_t)snprintf(text, sizeof text, HEAD "  elements = (\n    { op = \"rz\"; joint = true; }");
    for (int i = 0; i < KC_MAX_FRAMES; i++)
        len += (size_t)snprintf(text + len, sizeof text - len, ",\n    { op = \"rz\"; value = 0.0; frame = true; }");
    snprintf(text + len, sizeof text - len, "\n  );\n};\n");
    kc_chain c;
    kc_desc_error err;
    assert_int_equal(kc_desc_load_string(text, "frames.cfg", &c, NULL, &err), KC_E_CAPACITY);
    assert_int_equal(err.line, 4 + KC_MAX_FRAMES);
    assert_non_null(strstr(err.problem, "elements element 65: the chain exceeds kinctl's capacity"));
}

static void test_file_errors(void **state)
{
    (void)state;
    kc_chain c;
    kc_desc_error err;
    assert_int_equal(kc_desc_load_file("/nonexistent/robot.cfg", &c, NULL, &err), KC_E_ARG);
    assert_int_equal(err.line, 0);
    assert_string_equal(err.file, "/nonexistent/robot.cfg");
    assert_non_null(strstr(err.text, "/nonexistent/robot.cfg: cannot open: No such file or directory"));

    /* A parse error in a real file names that file and line. */
    char path[] = "/tmp/kinctl_test_desc_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    fputs(HEAD "  dh = (\n    { type = \"revolute\"; a = 0.0; alpha = 0.0; d = 0.0; theta = 0.0; } }\n);\n};\n", f);
    fclose(f);
    assert_int_equal(kc_desc_load_file(path, &c, NULL, &err), KC_E_ARG);
    remove(path);
    assert_string_equal(err.file, path);
    assert_int_equal(err.line, 4);
    assert_non_null(strstr(err.text, ":4: syntax error"));
}

static void write_file(char *path, const char *text)
{
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* controller.zones: every kind, names, margin, angles; bad zones name the
 * line; a file without zones gives an empty set. */
static void test_zones(void **state)
{
    (void)state;
    char path[] = "/tmp/kinctl_test_zones_XXXXXX";
    write_file(path, "controller = {\n  period_us = 1000;\n  zones = {\n    margin = 0.03; angles = \"deg\";\n    list = (\n"
                     "      { name = \"table\"; shape = \"halfspace\"; point = [0.0, 0.0, 0.1]; normal = [0.0, 0.0, 2.0]; },\n"
                     "      { name = \"fence\"; shape = \"box\"; xyz = [0.8, 0.0, 0.5]; rpy = [0.0, 0.0, 90.0]; half = [0.02, 1.0, 0.5]; },\n"
                     "      { shape = \"sphere\"; xyz = [0.1, 0.2, 0.3]; radius = 0.1; },\n"
                     "      { name = \"pillar\"; shape = \"cylinder\"; from = [0.5, 0.5, 0.0]; to = [0.5, 0.5, 1.0]; radius = 0.05; }\n"
                     "    );\n  };\n};\n");
    kc_zone_set set;
    kc_desc_zone_info info;
    kc_desc_error err;
    kc_status st = kc_desc_load_zones(path, &set, &info, &err);
    remove(path);
    if (st != KC_OK)
        fail_msg("%s", err.text);
    assert_int_equal(set.n_zones, 4);
    assert_int_equal(info.n_zones, 4);
    assert_true(kc_fabs(set.margin - KC_R(0.03)) <= TOL);
    assert_string_equal(info.names[0], "table");
    assert_string_equal(info.names[2], "");
    assert_string_equal(info.names[3], "pillar");
    assert_int_equal(set.zones[0].kind, KC_SHAPE_HALFSPACE);
    assert_true(kc_fabs(set.zones[0].pose.R.m[2][2] - KC_R(1.0)) <= TOL); /* unit normal */
    assert_true(kc_fabs(set.zones[0].pose.t.v[2] - KC_R(0.1)) <= TOL);
    assert_int_equal(set.zones[1].kind, KC_SHAPE_BOX);
    assert_true(kc_fabs(set.zones[1].pose.R.m[1][0] - KC_R(1.0)) <= TOL); /* Rz(90 deg): x to y */
    assert_true(kc_fabs(set.zones[1].dim[1] - KC_R(1.0)) <= TOL);
    assert_int_equal(set.zones[3].kind, KC_SHAPE_CYLINDER);
    assert_true(kc_fabs(set.zones[3].dim[1] - KC_R(0.5)) <= TOL); /* half-length */
    assert_true(kc_fabs(set.zones[3].pose.t.v[2] - KC_R(0.5)) <= TOL);
    assert_int_equal(kc_zone_set_check(&set), KC_OK);

    char path2[] = "/tmp/kinctl_test_zones_XXXXXX";
    write_file(path2, "controller = {\n  zones = {\n    list = (\n      { shape = \"sphere\"; xyz = [0.0, 0.0, 0.0]; radius = 0.1;\n"
                      "        frame = 2; }\n    );\n  };\n};\n");
    kc_zone_set before = set;
    assert_int_equal(kc_desc_load_zones(path2, &set, NULL, &err), KC_E_ARG);
    remove(path2);
    assert_int_equal(err.line, 5);
    assert_non_null(strstr(err.problem, "zone 1: a zone is in the base frame: no frame key"));
    assert_memory_equal(&set, &before, sizeof set);

    char path3[] = "/tmp/kinctl_test_zones_XXXXXX";
    write_file(path3, "controller = {\n  zones = {\n    margn = 0.1;\n  };\n};\n");
    assert_int_equal(kc_desc_load_zones(path3, &set, NULL, &err), KC_E_ARG);
    remove(path3);
    assert_int_equal(err.line, 3);
    assert_non_null(strstr(err.problem, "unknown key \"margn\" in controller.zones"));

    char path4[] = "/tmp/kinctl_test_zones_XXXXXX";
    write_file(path4, "controller = { period_us = 1000; };\n");
    assert_int_equal(kc_desc_load_zones(path4, &set, &info, &err), KC_OK);
    remove(path4);
    assert_int_equal(set.n_zones, 0);
    assert_int_equal(info.n_zones, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_puma560_file), cmocka_unit_test(test_panda_file),
        cmocka_unit_test(test_rrr3_file),    cmocka_unit_test(test_planar2_file),
        cmocka_unit_test(test_rb211_file),   cmocka_unit_test(test_rm01_file),
        cmocka_unit_test(test_good_variants), cmocka_unit_test(test_elements_and_names),
        cmocka_unit_test(test_bad_files),    cmocka_unit_test(test_max_joints),
        cmocka_unit_test(test_too_many_frames), cmocka_unit_test(test_file_errors),
        cmocka_unit_test(test_zones),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
