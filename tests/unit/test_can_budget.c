/* SPDX-License-Identifier: BSD-3-Clause */
/* test_can_budget.c - the worst-case bus time of a bus cycle
 * (daemon/can_budget.h) with figures computed by hand from Davis et al.
 * 2007 eq. 1, bits(n) = 47 + 8 n + floor((33 + 8 n) / 4):
 *   n = 0: 47 + 0 + 8 = 55       n = 1: 47 + 8 + 10 = 65
 *   n = 2: 47 + 16 + 12 = 75     n = 6: 47 + 48 + 20 = 115
 *   n = 8: 47 + 64 + 24 = 135
 * and the issue's case: SYNC (1 byte) + per joint an 8-byte RPDO and a
 * 6-byte TPDO, 6 joints at 1 kHz on 1 Mbit/s: 65 + 6 (135 + 115) = 1565
 * bits = 1565 us of 1000: 156.5 %. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "can_budget.h"

/* |a - b| <= tol, with both values in the message. */
#define assert_near(a, b, tol) near_((a), (b), (tol), #a, __LINE__)

static void near_(double a, double b, double tol, const char *what, int line)
{
    if (!(a - b <= tol && b - a <= tol))
        fail_msg("line %d: %s = %.12g, want %.12g", line, what, a, b);
}

static void test_frame_bits(void **state)
{
    (void)state;
    assert_int_equal(kd_can_frame_bits(0), 55);
    assert_int_equal(kd_can_frame_bits(1), 65);
    assert_int_equal(kd_can_frame_bits(2), 75);
    assert_int_equal(kd_can_frame_bits(6), 115);
    assert_int_equal(kd_can_frame_bits(8), 135);
    assert_int_equal(kd_can_frame_bits(-1), -1);
    assert_int_equal(kd_can_frame_bits(9), -1);
}

static kd_can_budget bus(int n, int rpdo_bytes, int tpdo_bytes, int tpdo_every, int64_t period_ns, int64_t bitrate)
{
    kd_can_budget b = kd_can_budget_default();
    b.period_ns = period_ns;
    b.bitrate = bitrate;
    b.n_drives = n;
    for (int i = 0; i < n; i++) {
        b.drive[i].n_rpdo = 1;
        b.drive[i].rpdo_bytes[0] = rpdo_bytes;
        b.drive[i].n_tpdo = 1;
        b.drive[i].tpdo_bytes[0] = tpdo_bytes;
        b.drive[i].tpdo_every[0] = tpdo_every;
    }
    return b;
}

static void test_issue_case(void **state)
{
    (void)state;
    char why[512];
    kd_can_budget_use u;
    kd_can_budget b = bus(6, 8, 6, 1, 1000000, 1000000);
    b.sync_bytes = 1;
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), 1);
    assert_int_equal(u.peak_bits, 1565);
    assert_near(u.mean_bits, 1565.0, 1e-9);
    assert_near(u.mean_ns, 1565000.0, 1e-6);
    assert_near(u.mean_share, 1.565, 1e-12);
    assert_int_equal(u.cycle_ns, 1000000);
    /* 700 bits fit: (700 - 65) / 250 = 2.54 -> 2 drives; 1565 / 0.7 = 2236
     * us -> sync_every 3; the SYNC and RPDOs alone, 65 + 810 = 875 bits,
     * are over 700 already */
    assert_non_null(strstr(why, "6 drives need 1565 us of a 1000 us bus cycle at 1000000 bit/s (156.5 %"));
    assert_non_null(strstr(why, "would fit: 2 drives, or sync_every 3 (a 3000 us bus cycle)"));
    assert_non_null(strstr(why, "TPDOs less often cannot make it fit"));
    /* 7 joints: 65 + 1750 = 1815: 181.5 % */
    b = bus(7, 8, 6, 1, 1000000, 1000000);
    b.sync_bytes = 1;
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), 1);
    assert_near(u.mean_share, 1.815, 1e-12);
}

static void test_fits(void **state)
{
    (void)state;
    char why[512] = "";
    kd_can_budget_use u;
    /* 2 drives, empty SYNC: 55 + 500 = 555 us of 1000 */
    kd_can_budget b = bus(2, 8, 6, 1, 1000000, 1000000);
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), 0);
    assert_near(u.mean_share, 0.555, 1e-12);
    assert_string_equal(why, "");
    /* 3 drives, TPDOs every 4th SYNC: mean 55 + 405 + 345 / 4 = 546.25,
     * peak 805 bits */
    b = bus(3, 8, 6, 4, 1000000, 1000000);
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), 0);
    assert_near(u.mean_bits, 546.25, 1e-9);
    assert_int_equal(u.peak_bits, 805);
    assert_near(u.peak_share, 0.805, 1e-12);
    /* 500 kbit/s, 2 ms (500 Hz as sync_every 2 of 1 kHz): 2 us a bit,
     * 3 drives 805 bits = 1610 us of 2000: 80.5 % */
    b = bus(3, 8, 6, 1, 1000000, 500000);
    b.sync_every = 2;
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), 1);
    assert_near(u.mean_ns, 1610000.0, 1e-6);
    assert_int_equal(u.cycle_ns, 2000000);
    b.share = 0.85;
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), 0);
}

static void test_options(void **state)
{
    (void)state;
    char why[512];
    kd_can_budget_use u;
    /* 4 drives, 6-byte RPDO (controlword + target), 6-byte TPDO: 55 + 4
     * (115 + 115) = 975 bits; 700 allow (700 - 55) / 230 = 2.8 -> 2
     * drives; 975 / 0.7 = 1392.9 us -> sync_every 2; TPDOs every n: 515 +
     * 460 / n <= 700 from n = 3 (n = 2: 745) */
    kd_can_budget b = bus(4, 6, 6, 1, 1000000, 1000000);
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), 1);
    assert_int_equal(u.peak_bits, 975);
    assert_non_null(strstr(why, "(97.5 %, peak 97.5 %), above 70 %"));
    assert_non_null(strstr(why, "would fit: 2 drives, or sync_every 2 (a 2000 us bus cycle), or TPDOs every 3 SYNCs"));
    for (int i = 0; i < 4; i++)
        b.drive[i].tpdo_every[0] = 3;
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), 0);
    assert_near(u.mean_bits, 55.0 + 460.0 + 460.0 / 3.0, 1e-9);
}

/* can_budget.h's table of what fits, by hand: (share * cycle bits - 55) /
 * bits per drive, 230 with the TPDO every SYNC, 172.5 every 2nd. */
static void test_what_fits(void **state)
{
    (void)state;
    static const struct {
        int64_t bitrate, period_ns;
        int every_sync, every_2nd;
    } table[] = {{1000000, 1000000, 2, 3}, {1000000, 2000000, 5, 7}, {500000, 1000000, 1, 1}, {500000, 2000000, 2, 3}};
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
        for (int every = 1; every <= 2; every++) {
            int fit = 0;
            for (int n = 1; n <= KC_MAX_JOINTS; n++) {
                kd_can_budget_use u;
                kd_can_budget b = bus(n, 6, 6, every, table[i].period_ns, table[i].bitrate);
                if (kd_can_budget_check(&b, &u, NULL, 0) == 0)
                    fit = n;
            }
            int want = every == 1 ? table[i].every_sync : table[i].every_2nd;
            if (fit != want)
                fail_msg("%lld bit/s, %lld ns, TPDO every %d: %d drives fit, the table says %d",
                         (long long)table[i].bitrate, (long long)table[i].period_ns, every, fit, want);
        }
    }
}

static void test_bad(void **state)
{
    (void)state;
    char why[128];
    kd_can_budget_use u;
    memset(&u, 0x5A, sizeof u);
    kd_can_budget_use before = u;
    kd_can_budget b = bus(2, 8, 6, 1, 1000000, 0);
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), -1);
    assert_non_null(strstr(why, "bitrate"));
    b = bus(2, 9, 6, 1, 1000000, 1000000);
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), -1);
    b = bus(2, 8, 6, 241, 1000000, 1000000);
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), -1);
    b = bus(0, 8, 6, 1, 1000000, 1000000);
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), -1);
    b = bus(2, 8, 6, 1, 1000000, 1000000);
    b.sync_bytes = 2;
    assert_int_equal(kd_can_budget_check(&b, &u, why, sizeof why), -1);
    b.sync_bytes = 0;
    b.share = 1.5;
    assert_int_equal(kd_can_budget_check(&b, &u, NULL, 0), -1);
    assert_memory_equal(&u, &before, sizeof u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frame_bits),
        cmocka_unit_test(test_issue_case),
        cmocka_unit_test(test_fits),
        cmocka_unit_test(test_options),
        cmocka_unit_test(test_what_fits),
        cmocka_unit_test(test_bad),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
