/* SPDX-License-Identifier: BSD-3-Clause */
/* test_can_frame.c - kinctld's CAN frames (daemon/can_frame.h) byte by
 * byte against tools/kinctl/kinctl.dbc: SYNC (0x080, counter 1..240),
 * RPDO1 (0x200 + node: TargetPosition_607A int32 LE at bit 0,
 * VelocityOffset_60B1 int32 LE at bit 32), TPDO1 (0x180 + node:
 * PositionActual_6064 int32 LE at bit 0, Statusword_6041 uint16 LE at bit
 * 32) and heartbeats (0x700 + node), with the counts computed by hand:
 * scaling, sign, offset, rounding and saturation. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "can_frame.h"
#include "testutil.h"

static kd_can_joint joint(int node, double counts_per_unit, int sign, int64_t offset)
{
    kd_can_joint j;
    memset(&j, 0, sizeof j);
    j.node = node;
    j.counts_per_unit = counts_per_unit;
    j.sign = sign;
    j.offset_counts = offset;
    return j;
}

static void assert_bytes(const struct can_frame *f, canid_t id, int len, const uint8_t *want)
{
    assert_int_equal(f->can_id, id);
    assert_int_equal(f->len, len);
    assert_memory_equal(f->data, want, 8); /* the bytes past len are zero */
}

static void test_sync(void **state)
{
    static const struct {
        int64_t bus_cycle;
        uint8_t counter;
    } cases[] = {{0, 1}, {1, 2}, {238, 239}, {239, 240}, {240, 1}, {479, 240}, {480, 1}, {1000000, 1000000 % 240 + 1}};
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        struct can_frame f;
        uint8_t want[8] = {cases[i].counter, 0, 0, 0, 0, 0, 0, 0};
        memset(&f, 0xA5, sizeof f);
        kd_can_encode_sync(cases[i].bus_cycle, &f);
        assert_bytes(&f, 0x080, 1, want);
    }
}

static void test_rpdo_scaling(void **state)
{
    struct can_frame f;
    (void)state;
    /* node 5, 10000 counts/rad: q 0.5 -> 5000 = 0x00001388, qd -0.25 ->
     * -2500 = 0xFFFFF63C */
    kd_can_joint j = joint(5, 10000.0, 1, 0);
    static const uint8_t w1[8] = {0x88, 0x13, 0x00, 0x00, 0x3C, 0xF6, 0xFF, 0xFF};
    memset(&f, 0xA5, sizeof f);
    kd_can_encode_rpdo(&j, 0.5, -0.25, &f);
    assert_bytes(&f, 0x205, 8, w1);

    /* sign -1, offset 1000: q -0.2 -> 2000 + 1000 = 3000 = 0x0BB8; qd 0.3
     * -> -3000 = 0xFFFFF448 (the offset is a position's only) */
    j = joint(127, 10000.0, -1, 1000);
    static const uint8_t w2[8] = {0xB8, 0x0B, 0x00, 0x00, 0x48, 0xF4, 0xFF, 0xFF};
    kd_can_encode_rpdo(&j, -0.2, 0.3, &f);
    assert_bytes(&f, 0x27F, 8, w2);

    /* 4096 counts per m, offset -70000: q 1.25 -> 5120 - 70000 = -64880 =
     * 0xFFFF0290; qd 0 -> 0 */
    j = joint(1, 4096.0, 1, -70000);
    static const uint8_t w3[8] = {0x90, 0x02, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x00};
    kd_can_encode_rpdo(&j, 1.25, 0.0, &f);
    assert_bytes(&f, 0x201, 8, w3);
}

static void test_counts_rounding(void **state)
{
    (void)state;
    kd_can_joint j = joint(1, 2.0, 1, 0);
    assert_int_equal(kd_can_pos_counts(&j, 1.25), 3);  /* 2.5 rounds away from zero */
    assert_int_equal(kd_can_pos_counts(&j, -1.25), -3);
    assert_int_equal(kd_can_pos_counts(&j, 1.2), 2);   /* 2.4 */
    assert_int_equal(kd_can_vel_counts(&j, -0.76), -2); /* -1.52 */
    j = joint(1, 2.0, -1, 10);
    assert_int_equal(kd_can_pos_counts(&j, 1.25), 8);  /* -2.5 + 10 = 7.5 -> 8 */
    assert_int_equal(kd_can_vel_counts(&j, 1.25), -3);
}

static void test_saturation(void **state)
{
    struct can_frame f;
    (void)state;
    kd_can_joint j = joint(3, 1e4, 1, 0);
    assert_int_equal(kd_can_pos_counts(&j, 1e6), INT32_MAX);
    assert_int_equal(kd_can_pos_counts(&j, -1e6), INT32_MIN);
    assert_int_equal(kd_can_vel_counts(&j, 1e300), INT32_MAX);
    assert_int_equal(kd_can_pos_counts(&j, (double)NAN), 0);
    assert_int_equal(kd_can_vel_counts(&j, (double)INFINITY), INT32_MAX);
    assert_int_equal(kd_can_vel_counts(&j, -(double)INFINITY), INT32_MIN);
    /* the offset can push a position over the edge */
    j = joint(3, 1.0, 1, 2147483000);
    assert_int_equal(kd_can_pos_counts(&j, 647.0), INT32_MAX);
    assert_int_equal(kd_can_pos_counts(&j, 646.0), 2147483646);
    j = joint(3, 1e4, 1, 0);
    static const uint8_t w[8] = {0xFF, 0xFF, 0xFF, 0x7F, 0x00, 0x00, 0x00, 0x80};
    kd_can_encode_rpdo(&j, 1e6, -1e6, &f);
    assert_bytes(&f, 0x203, 8, w);
}

static void test_heartbeat(void **state)
{
    struct can_frame f;
    static const uint8_t w[8] = {0x05, 0, 0, 0, 0, 0, 0, 0};
    (void)state;
    memset(&f, 0xA5, sizeof f);
    kd_can_encode_heartbeat(127, KD_CAN_NMT_OPERATIONAL, &f);
    assert_bytes(&f, 0x77F, 1, w);
}

static struct can_frame tpdo(const uint8_t *data, int len)
{
    struct can_frame f;
    memset(&f, 0, sizeof f);
    f.can_id = 0x185;
    f.len = (uint8_t)len;
    memcpy(f.data, data, (size_t)len);
    return f;
}

static void test_tpdo_decode(void **state)
{
    double q = -7.0;
    uint16_t sw = 0;
    (void)state;
    /* 5000 counts, statusword 0x1237 (operation enabled, target followed) */
    static const uint8_t d1[6] = {0x88, 0x13, 0x00, 0x00, 0x37, 0x12};
    kd_can_joint j = joint(5, 10000.0, 1, 0);
    struct can_frame f = tpdo(d1, 6);
    assert_int_equal(kd_can_decode_tpdo(&j, &f, &q, &sw), 0);
    assert_true(q == 0.5);
    assert_int_equal(sw, 0x1237);
    /* -1000 counts = 0xFFFFFC18 */
    static const uint8_t d2[6] = {0x18, 0xFC, 0xFF, 0xFF, 0x08, 0x00};
    f = tpdo(d2, 6);
    assert_int_equal(kd_can_decode_tpdo(&j, &f, &q, &sw), 0);
    assert_true(q == -0.1);
    assert_int_equal(sw, 0x0008);
    /* sign -1, offset 1000: 3000 counts -> (3000 - 1000) / -10000 */
    static const uint8_t d3[6] = {0xB8, 0x0B, 0x00, 0x00, 0x00, 0x80};
    j = joint(5, 10000.0, -1, 1000);
    f = tpdo(d3, 6);
    assert_int_equal(kd_can_decode_tpdo(&j, &f, &q, &sw), 0);
    assert_true(q == -0.2);
    assert_int_equal(sw, 0x8000);
    /* short: refused, outputs untouched */
    f = tpdo(d3, 5);
    q = 42.0;
    sw = 42;
    assert_int_equal(kd_can_decode_tpdo(&j, &f, &q, &sw), -1);
    assert_true(q == 42.0);
    assert_int_equal(sw, 42);
}

/* What the drive simulator does: a drive that reached its target reports
 * it back; decoding the encoded position gives it within half a count. */
static void test_round_trip(void **state)
{
    kt_rng rng = kt_rng_make(402);
    (void)state;
    for (int i = 0; i < 10000; i++) {
        int sign = (kt_rng_next(&rng) & 1u) ? 1 : -1;
        double cpu = kt_uniform(&rng, 100.0, 1e5);
        int64_t offset = (int64_t)kt_uniform(&rng, -1e6, 1e6);
        kd_can_joint j = joint(1 + (int)(kt_rng_next(&rng) % 127), cpu, sign, offset);
        double q = kt_uniform(&rng, -6.3, 6.3), back = 0.0;
        uint16_t sw = 0;
        struct can_frame rpdo, fb;
        kd_can_encode_rpdo(&j, q, 0.0, &rpdo);
        assert_int_equal(rpdo.can_id, 0x200u + (canid_t)j.node);
        fb = tpdo(rpdo.data, 6); /* PositionActual_6064 sits where TargetPosition_607A does */
        assert_int_equal(kd_can_decode_tpdo(&j, &fb, &back, &sw), 0);
        /* half a count, plus the rounding of counts near 1e6 (far below 1e-6) */
        assert_true(fabs(back - q) <= (0.5 + 1e-6) / cpu);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sync),       cmocka_unit_test(test_rpdo_scaling), cmocka_unit_test(test_counts_rounding),
        cmocka_unit_test(test_saturation), cmocka_unit_test(test_heartbeat),    cmocka_unit_test(test_tpdo_decode),
        cmocka_unit_test(test_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
