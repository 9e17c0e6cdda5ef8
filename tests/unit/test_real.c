/* SPDX-License-Identifier: BSD-3-Clause */
/* test_real.c - the scalar layer: kc_sincos against libm and its two
 * forms against each other, angle wrapping. */
#include "testutil.h"

/* kc_sincos is a polynomial of its own (real.h): within 2 ulps of the
 * correctly rounded value at the precision's unit roundoff, i.e. 2 * eps
 * absolute for values of magnitude <= 1. The reference is libm's double
 * sin/cos of the same (rounded) argument. */
#define TOL_SINCOS (2.0 * (double)KC_REAL_EPS)

static void check_sincos(kc_real x)
{
    kc_real s, c;
    kc_sincos(x, &s, &c);
    kt_near((double)s, sin((double)x), TOL_SINCOS, "kc_sincos sine");
    kt_near((double)c, cos((double)x), TOL_SINCOS, "kc_sincos cosine");
}

static void test_sincos_random(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(5);
#ifdef KC_REAL_FLOAT
    const double wide = 64.0;
#else
    const double wide = 1e5;
#endif
    for (int i = 0; i < 200000; i++) {
        check_sincos((kc_real)kt_uniform(&r, -7.0, 7.0));
        check_sincos((kc_real)kt_uniform(&r, -wide, wide));
        check_sincos((kc_real)kt_uniform(&r, -1e-3, 1e-3));
    }
    /* Beyond the polynomial's range libm takes over. */
    for (int i = 0; i < 1000; i++)
        check_sincos((kc_real)kt_uniform(&r, -1e7, 1e7));
}

static void test_sincos_special(void **state)
{
    (void)state;
    const double xs[] = {0.0, -0.0, KT_PI / 4, -KT_PI / 4, KT_PI / 2, KT_PI, 1.5 * KT_PI, 2 * KT_PI, 100.0, -1e-300};
    for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++)
        check_sincos((kc_real)xs[i]);
    kc_real s, c;
    kc_sincos((kc_real)NAN, &s, &c);
    assert_true(s != s && c != c);
    kc_sincos((kc_real)INFINITY, &s, &c);
    assert_true(s != s && c != c);
}

/* The called copy (built for size) and the inlined one are the same
 * operations: the same bits for every argument, also beyond the polynomial's
 * range and for NaN. */
static void same_forms(kc_real x)
{
    kc_real s1, c1, s2, c2;
    kc_sincos_inline(x, &s1, &c1);
    kc_sincos_outline(x, &s2, &c2);
    assert_memory_equal(&s1, &s2, sizeof s1);
    assert_memory_equal(&c1, &c2, sizeof c1);
}

static void test_sincos_forms(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(7);
    for (int i = 0; i < 20000; i++) {
        same_forms((kc_real)kt_uniform(&r, -7.0, 7.0));
        same_forms((kc_real)kt_uniform(&r, -1e7, 1e7));
    }
    same_forms((kc_real)NAN);
    same_forms((kc_real)-0.0);
}

static void test_wrap_angle(void **state)
{
    (void)state;
    kt_rng r = kt_rng_make(6);
    for (int i = 0; i < 10000; i++) {
        double a = kt_uniform(&r, -50.0, 50.0);
        double w = (double)kc_wrap_angle((kc_real)a);
        assert_true(w > -KT_PI - 1e-6 && w <= KT_PI + 1e-6);
        kt_near_angle(w, a, 64.0 * (double)KC_REAL_EPS, "wrapped angle equals the input modulo 2 pi");
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sincos_random),
        cmocka_unit_test(test_sincos_special),
        cmocka_unit_test(test_sincos_forms),
        cmocka_unit_test(test_wrap_angle),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    kt_report("real");
    return failed;
}
