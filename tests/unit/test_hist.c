/* SPDX-License-Identifier: BSD-3-Clause */
/* test_hist.c - the daemon's log-linear histogram (daemon/hist.h):
 * percentiles against the same percentile computed on the sorted values,
 * within the documented resolution (exact below 128 ns, half a bin above:
 * at most 1/128 of the value), the overflow bin, and clearing. */
#include <setjmp.h>
#include <stdarg.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "hist.h"
#include "testutil.h"

/* The smallest value with at least ceil(p n) of the n values at or below
 * it (hist.h's definition), from the sorted values. */
static int64_t sorted_percentile(const int64_t *sorted, size_t n, double p)
{
    double want = p * (double)n;
    size_t rank = (size_t)want;
    if ((double)rank < want)
        rank++;
    if (rank < 1)
        rank = 1;
    return sorted[rank - 1];
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

static const double PS[] = {0.0, 0.001, 0.1, 0.5, 0.9, 0.99, 0.999, 1.0};

static void test_empty(void **state)
{
    static kd_hist h;
    (void)state;
    kd_hist_clear(&h);
    assert_int_equal(h.count, 0);
    assert_int_equal(kd_hist_percentile(&h, 0.5), 0);
    assert_int_equal(kd_hist_percentile(&h, 1.0), 0);
}

/* Below KD_HIST_LINEAR every value has a bin: percentiles are exact. */
static void test_linear_exact(void **state)
{
    static kd_hist h;
    int64_t v[500];
    kt_rng rng = kt_rng_make(11);
    (void)state;
    kd_hist_clear(&h);
    for (size_t i = 0; i < 500; i++) {
        v[i] = (int64_t)(kt_rng_next(&rng) % KD_HIST_LINEAR);
        kd_hist_add(&h, v[i]);
    }
    qsort(v, 500, sizeof v[0], cmp_i64);
    for (size_t k = 0; k < sizeof PS / sizeof PS[0]; k++)
        assert_int_equal(kd_hist_percentile(&h, PS[k]), sorted_percentile(v, 500, PS[k]));
    assert_int_equal(h.max, v[499]);
    assert_int_equal(h.count, 500);
}

/* Log-uniform values from 1 ns to 100 s: within half a bin. */
static void test_log_range(void **state)
{
    enum { N = 20000 };
    static kd_hist h;
    static int64_t v[N];
    kt_rng rng = kt_rng_make(12);
    (void)state;
    kd_hist_clear(&h);
    for (size_t i = 0; i < N; i++) {
        v[i] = (int64_t)exp(kt_uniform(&rng, 0.0, 25.3)); /* e^25.3 = 9.7e10 ns */
        kd_hist_add(&h, v[i]);
    }
    qsort(v, N, sizeof v[0], cmp_i64);
    for (size_t k = 0; k < sizeof PS / sizeof PS[0]; k++) {
        int64_t exact = sorted_percentile(v, N, PS[k]), got = kd_hist_percentile(&h, PS[k]);
        int64_t err = got > exact ? got - exact : exact - got;
        /* above the linear bins, exact lies in a bin of width w whose
         * lower edge is at least 64 w: the bin's middle is at most
         * w / 2 <= exact / 128 away */
        if (exact < KD_HIST_LINEAR)
            assert_int_equal(got, exact);
        else
            assert_true(err * 128 <= exact);
        assert_true(got <= h.max);
    }
    assert_int_equal(h.max, v[N - 1]);
}

/* Values from 2^37 ns on share the last bin; the maximum stays exact. */
static void test_overflow_bin(void **state)
{
    static kd_hist h;
    const int64_t big = 1000000000000LL; /* 1000 s */
    const int64_t edge = (int64_t)1 << 37;
    /* the last bin: octave 2^36, sub-bin 63, width 2^30 */
    const int64_t last_lo = (int64_t)(KD_HIST_SUB + 63) << 30, last_mid = last_lo + ((int64_t)1 << 29);
    (void)state;
    kd_hist_clear(&h);
    for (int i = 0; i < 90; i++)
        kd_hist_add(&h, 1000);
    kd_hist_add(&h, edge - 1); /* the last bin's own top value */
    kd_hist_add(&h, edge);
    for (int i = 0; i < 8; i++)
        kd_hist_add(&h, big);
    assert_int_equal(h.bins[KD_HIST_BINS - 1], 10);
    assert_int_equal(h.count, 100);
    assert_int_equal(h.max, big);
    assert_true(last_lo <= edge - 1 && edge - 1 < last_lo + ((int64_t)1 << 30));
    int64_t p50 = kd_hist_percentile(&h, 0.5);
    assert_true(p50 >= 1000 - 1000 / 128 && p50 <= 1000 + 1000 / 128);
    assert_int_equal(kd_hist_percentile(&h, 0.95), last_mid);
    assert_int_equal(kd_hist_percentile(&h, 1.0), last_mid); /* the bin's middle: below the exact maximum */
}

static void test_negative_and_clamps(void **state)
{
    static kd_hist h;
    (void)state;
    kd_hist_clear(&h);
    kd_hist_add(&h, -5); /* counts as 0 */
    kd_hist_add(&h, 7);
    kd_hist_add(&h, 9);
    assert_int_equal(h.bins[0], 1);
    assert_int_equal(kd_hist_percentile(&h, -1.0), 0); /* p below 0: the smallest */
    assert_int_equal(kd_hist_percentile(&h, 0.5), 7);
    assert_int_equal(kd_hist_percentile(&h, 2.0), 9); /* p above 1: the largest */
}

static void test_clear_resets(void **state)
{
    static kd_hist h;
    (void)state;
    kd_hist_clear(&h);
    for (int64_t x = 1; x <= 1000000; x *= 10)
        kd_hist_add(&h, x);
    kd_hist_clear(&h);
    assert_int_equal(h.count, 0);
    assert_int_equal(h.max, 0);
    for (int b = 0; b < KD_HIST_BINS; b++)
        assert_int_equal(h.bins[b], 0);
    assert_int_equal(kd_hist_percentile(&h, 0.99), 0);
    /* after a clear only the new values count */
    kd_hist_add(&h, 3);
    kd_hist_add(&h, 5);
    assert_int_equal(kd_hist_percentile(&h, 1.0), 5);
    assert_int_equal(h.max, 5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_empty),        cmocka_unit_test(test_linear_exact),
        cmocka_unit_test(test_log_range),    cmocka_unit_test(test_overflow_bin),
        cmocka_unit_test(test_negative_and_clamps), cmocka_unit_test(test_clear_resets),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
