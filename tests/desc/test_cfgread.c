/* SPDX-License-Identifier: BSD-3-Clause */
/* test_cfgread.c - the libconfig lookups shared by the description library
 * and kinctld (kinctl/cfgread.h): values, absent keys left alone, and each
 * problem's "<file>:<line>: <problem>" in both naming styles; and the
 * readers over a parsed file (kinctl/desc_tree.h) against the loaders. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "kinctl/cfgread.h"
#include "kinctl/desc_tree.h"
#include "testutil.h"

static const char *const TEXT = "controller = {\n"   /* 1 */
                                "  period_us = 50;\n" /* 2 */
                                "  scale = 0.5;\n"    /* 3 */
                                "  big = 5000000000L;\n" /* 4: an int64 */
                                "  name = \"arm\";\n" /* 5 */
                                "  on = true;\n"      /* 6 */
                                "  rt = 3;\n"         /* 7 */
                                "  v = [1.0, 2.0];\n" /* 8 */
                                "  inf = 1e999;\n"    /* 9 */
                                "};\n";

typedef struct fixture {
    config_t tree;
    kc_desc_error err;
    kc_cfg path;  /* kinctld's naming: controller.x */
    kc_cfg where; /* the description library's: controller: x */
    const config_setting_t *c;
} fixture;

static int setup(void **state)
{
    static fixture f;
    memset(&f, 0, sizeof f);
    f.path = (kc_cfg){"k.cfg", ".", &f.err};
    f.where = (kc_cfg){"k.cfg", ": ", &f.err};
    if (kc_cfg_parse_string(&f.path, TEXT, &f.tree) != KC_OK)
        return -1;
    f.c = config_setting_get_member(config_root_setting(&f.tree), "controller");
    *state = &f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    config_destroy(&f->tree);
    return 0;
}

static void test_values(void **state)
{
    fixture *f = *state;
    double d = -1.0;
    int i = -1, b = -1;
    const char *s = NULL;
    const config_setting_t *found = NULL, *g = NULL;
    kc_real v[2] = {KC_R(0.0), KC_R(0.0)};
    assert_int_equal(kc_cfg_lookup_number(&f->path, f->c, "scale", "controller", 0.0, 1.0, &d), KC_OK);
    assert_true(d == 0.5);
    assert_int_equal(kc_cfg_lookup_number(&f->path, f->c, "big", "controller", 0.0, 1e10, &d), KC_OK);
    assert_true(d == 5000000000.0);
    assert_int_equal(kc_cfg_lookup_int(&f->path, f->c, "rt", "controller", 1, 99, &i), KC_OK);
    assert_int_equal(i, 3);
    assert_int_equal(kc_cfg_lookup_bool(&f->path, f->c, "on", "controller", &b), KC_OK);
    assert_int_equal(b, 1);
    assert_int_equal(kc_cfg_lookup_string(&f->path, f->c, "name", "controller", &s, &found), KC_OK);
    assert_string_equal(s, "arm");
    assert_non_null(found);
    assert_int_equal(kc_cfg_vector_real(&f->where, config_setting_get_member(f->c, "v"), "v", 2, KC_R(2.0), v), KC_OK);
    assert_true(v[0] == KC_R(2.0) && v[1] == KC_R(4.0));
    /* absent: outputs untouched, found NULL */
    d = -1.0;
    i = b = -1;
    s = "kept";
    assert_int_equal(kc_cfg_lookup_number(&f->path, f->c, "nope", "controller", 0.0, 1.0, &d), KC_OK);
    assert_int_equal(kc_cfg_lookup_int(&f->path, f->c, "nope", "controller", 0, 1, &i), KC_OK);
    assert_int_equal(kc_cfg_lookup_bool(&f->path, f->c, "nope", "controller", &b), KC_OK);
    assert_int_equal(kc_cfg_lookup_string(&f->path, f->c, "nope", "controller", &s, &found), KC_OK);
    assert_int_equal(kc_cfg_lookup_group(&f->path, f->c, "nope", "controller", &g), KC_OK);
    assert_true(d == -1.0 && i == -1 && b == -1);
    assert_string_equal(s, "kept");
    assert_null(found);
    assert_null(g);
    assert_string_equal(f->err.text, "");
}

/* Each problem: the status, and the whole message. */
static void expect(fixture *f, kc_status st, const char *text)
{
    assert_int_equal(st, KC_E_ARG);
    assert_string_equal(f->err.text, text);
    memset(&f->err, 0, sizeof f->err);
}

static void test_problems(void **state)
{
    fixture *f = *state;
    static const char *const keys[] = {"period_us", "scale", NULL};
    double d;
    int i;
    const char *s;
    const config_setting_t *g;
    kc_real v[3], x;
    expect(f, kc_cfg_lookup_number(&f->path, f->c, "period_us", "controller", 100, 100000, &d),
           "k.cfg:2: controller.period_us = 50 is outside 100 .. 100000");
    expect(f, kc_cfg_lookup_number(&f->where, f->c, "name", "controller", 0, 1, &d),
           "k.cfg:5: controller: name must be a number");
    expect(f, kc_cfg_lookup_number(&f->path, f->c, "inf", "controller", 0, 1, &d),
           "k.cfg:9: controller.inf is not a finite number");
    expect(f, kc_cfg_lookup_int(&f->path, f->c, "scale", "controller", 0, 1, &i),
           "k.cfg:3: controller.scale must be an integer");
    expect(f, kc_cfg_lookup_int(&f->path, f->c, "rt", "controller", 4, 9, &i), "k.cfg:7: controller.rt = 3 is outside 4 .. 9");
    expect(f, kc_cfg_lookup_bool(&f->where, f->c, "rt", "controller", &i), "k.cfg:7: controller: rt must be true or false");
    expect(f, kc_cfg_lookup_string(&f->path, f->c, "on", "controller", &s, NULL),
           "k.cfg:6: controller.on must be a string in double quotes");
    expect(f, kc_cfg_lookup_group(&f->path, f->c, "v", "controller", &g), "k.cfg:8: controller.v must be a group { ... }");
    expect(f, kc_cfg_string(&f->where, f->c, "type", "dh row 1", &s), "k.cfg:1: dh row 1: missing key \"type\"");
    expect(f, kc_cfg_lookup_real(&f->where, f->c, "alpha", "dh row 1", 1, KC_R(1.0), &x, NULL),
           "k.cfg:1: dh row 1: missing key \"alpha\"");
    expect(f, kc_cfg_vector_real(&f->where, config_setting_get_member(f->c, "v"), "xyz", 3, KC_R(1.0), v),
           "k.cfg:8: xyz must hold 3 numbers, not 2");
    expect(f, kc_cfg_vector_real(&f->where, config_setting_get_member(f->c, "scale"), "xyz", 3, KC_R(1.0), v),
           "k.cfg:3: xyz must be a vector of 3 numbers, e.g. [0.0, 0.0, 0.0]");
    expect(f, kc_cfg_check_keys(&f->path, f->c, "controller", keys),
           "k.cfg:4: unknown key \"big\" in controller (expected one of: period_us, scale)");
    assert_int_equal(f->err.line, 0);
}

static void test_parse_errors(void **state)
{
    kc_desc_error err;
    kc_cfg r = {"bad.cfg", ".", &err};
    config_t tree;
    (void)state;
    memset(&err, 0, sizeof err);
    assert_int_equal(kc_cfg_parse_string(&r, "a = 1;\nb = [1, 1.5];\n", &tree), KC_E_ARG);
    assert_string_equal(err.text, "bad.cfg:2: mismatched element type in array (an array [..] may not mix 1 and 1.5: "
                                  "write 1.0)");
    assert_int_equal(err.line, 2);
    assert_int_equal(kc_cfg_parse_file(&r, "/nonexistent/k.cfg", &tree), KC_E_ARG);
    assert_string_equal(err.text, "bad.cfg: cannot open: No such file or directory");
}

/* The robot and zones of a parsed file, as the loaders read them. */
static void test_tree_readers(void **state)
{
    static const char *const text =
        "robot = { name = \"two\"; angles = \"deg\";\n"
        "  dh = ( { type = \"revolute\"; a = 1.0; alpha = 0.0; d = 0.0; theta = 0.0; },\n"
        "         { type = \"revolute\"; a = 0.5; alpha = 90.0; d = 0.1; theta = 0.0; } ); };\n"
        "controller = { zones = { margin = 0.05; list = ( { name = \"ball\"; shape = \"sphere\"; xyz = [1.0, 0.0, 0.0];"
        " radius = 0.2; } ); }; };\n";
    kc_desc_error err;
    kc_cfg r = {"t.cfg", ".", &err};
    config_t tree;
    kc_chain a, b;
    kc_desc_info ia, ib;
    kc_zone_set zs;
    kc_desc_zone_info zi;
    kc_pose pa, pb;
    const kc_real q[2] = {KC_R(0.3), KC_R(-0.7)};
    (void)state;
    assert_int_equal(kc_cfg_parse_string(&r, text, &tree), KC_OK);
    const config_setting_t *root = config_root_setting(&tree);
    assert_int_equal(kc_desc_read_robot(config_setting_get_member(root, "robot"), "t.cfg", &a, &ia, &err), KC_OK);
    assert_int_equal(kc_desc_load_string(text, "t.cfg", &b, &ib, &err), KC_OK);
    assert_string_equal(ia.name, "two");
    assert_int_equal(a.n_joints, b.n_joints);
    assert_int_equal(kc_fk_eval(&a, q, &pa), KC_OK);
    assert_int_equal(kc_fk_eval(&b, q, &pb), KC_OK);
    kt_near_pose(&pa, &pb, 0.0, "same file, same chain");
    const config_setting_t *zones = config_setting_get_member(config_setting_get_member(root, "controller"), "zones");
    assert_int_equal(kc_desc_read_zones(zones, "t.cfg", &zs, &zi, &err), KC_OK);
    assert_int_equal(zs.n_zones, 1);
    assert_string_equal(zi.names[0], "ball");
    assert_true(zs.margin == KC_R(0.05));
    /* no zones group: an empty set with kc_zone_set_init's margin */
    kc_zone_set def;
    kc_zone_set_init(&def);
    assert_int_equal(kc_desc_read_zones(NULL, "t.cfg", &zs, &zi, &err), KC_OK);
    assert_int_equal(zs.n_zones, 0);
    assert_true(zs.margin == def.margin);
    /* a bad robot: the message names the file given, outputs untouched */
    config_destroy(&tree);
    assert_int_equal(kc_cfg_parse_string(&r, "robot = { name = \"x\"; angles = \"grad\"; };\n", &tree), KC_OK);
    kc_chain keep = a;
    assert_int_equal(kc_desc_read_robot(config_setting_get_member(config_root_setting(&tree), "robot"), "t.cfg", &a,
                                        NULL, &err),
                     KC_E_ARG);
    assert_string_equal(err.text, "t.cfg:1: robot: unknown angle unit \"grad\" (expected \"rad\" or \"deg\")");
    assert_memory_equal(&a, &keep, sizeof a);
    config_destroy(&tree);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_values, setup, teardown),
        cmocka_unit_test_setup_teardown(test_problems, setup, teardown),
        cmocka_unit_test(test_parse_errors),
        cmocka_unit_test(test_tree_readers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
