/* SPDX-License-Identifier: BSD-3-Clause */
/* test_can_frame.c - kinctld's CAN frames (daemon/can_frame.h) byte by
 * byte as CiA 301 and 402 lay them out: SYNC (0x080, empty or a counter
 * 1..overflow), RPDO1 (0x200 + node: controlword 0x6040 uint16 LE, target
 * position 0x607A int32 LE), RPDO2 (0x300 + node: velocity offset 0x60B1
 * int32 LE), TPDO1 (0x180 + node: statusword 0x6041 uint16 LE, position
 * actual 0x6064 int32 LE), EMCY, NMT and heartbeats, with the counts
 * computed by hand: scaling, sign, offset, rounding and saturation. */
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
        int overflow;
        uint8_t counter;
    } cases[] = {{0, 240, 1},   {1, 240, 2},   {238, 240, 239}, {239, 240, 240},
                 {240, 240, 1}, {479, 240, 240}, {480, 240, 1}, {1000000, 240, 1000000 % 240 + 1},
                 {0, 2, 1},     {1, 2, 2},     {2, 2, 1},       {17, 10, 8}};
    static const uint8_t empty[8] = {0};
    struct can_frame f;
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        uint8_t want[8] = {cases[i].counter, 0, 0, 0, 0, 0, 0, 0};
        memset(&f, 0xA5, sizeof f);
        kd_can_encode_sync(cases[i].bus_cycle, cases[i].overflow, &f);
        assert_bytes(&f, 0x080, 1, want);
    }
    /* 0x1019 = 0: the SYNC is empty, whatever the bus cycle */
    memset(&f, 0xA5, sizeof f);
    kd_can_encode_sync(12345, 0, &f);
    assert_bytes(&f, 0x080, 0, empty);
}

static void test_rpdo_scaling(void **state)
{
    struct can_frame f;
    (void)state;
    /* node 5, 10000 counts/rad: controlword 0x000F (enable operation), q
     * 0.5 -> 5000 = 0x00001388; RPDO2: qd -0.25 -> -2500 = 0xFFFFF63C */
    kd_can_joint j = joint(5, 10000.0, 1, 0);
    static const uint8_t w1[8] = {0x0F, 0x00, 0x88, 0x13, 0x00, 0x00, 0, 0};
    static const uint8_t v1[8] = {0x3C, 0xF6, 0xFF, 0xFF, 0, 0, 0, 0};
    memset(&f, 0xA5, sizeof f);
    kd_can_encode_rpdo(&j, 0x000F, 0.5, &f);
    assert_bytes(&f, 0x205, 6, w1);
    memset(&f, 0xA5, sizeof f);
    kd_can_encode_rpdo2(&j, -0.25, &f);
    assert_bytes(&f, 0x305, 4, v1);

    /* sign -1, offset 1000: q -0.2 -> 2000 + 1000 = 3000 = 0x0BB8,
     * controlword 0x0080 (fault reset); qd 0.3 -> -3000 = 0xFFFFF448 (the
     * offset is a position's only) */
    j = joint(127, 10000.0, -1, 1000);
    static const uint8_t w2[8] = {0x80, 0x00, 0xB8, 0x0B, 0x00, 0x00, 0, 0};
    static const uint8_t v2[8] = {0x48, 0xF4, 0xFF, 0xFF, 0, 0, 0, 0};
    kd_can_encode_rpdo(&j, 0x0080, -0.2, &f);
    assert_bytes(&f, 0x27F, 6, w2);
    kd_can_encode_rpdo2(&j, 0.3, &f);
    assert_bytes(&f, 0x37F, 4, v2);

    /* 4096 counts per m, offset -70000: q 1.25 -> 5120 - 70000 = -64880 =
     * 0xFFFF0290, a controlword with its high byte set */
    j = joint(1, 4096.0, 1, -70000);
    static const uint8_t w3[8] = {0x06, 0x01, 0x90, 0x02, 0xFF, 0xFF, 0, 0};
    kd_can_encode_rpdo(&j, 0x0106, 1.25, &f);
    assert_bytes(&f, 0x201, 6, w3);
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
    static const uint8_t w[8] = {0x0F, 0x00, 0xFF, 0xFF, 0xFF, 0x7F, 0, 0};
    static const uint8_t v[8] = {0x00, 0x00, 0x00, 0x80, 0, 0, 0, 0};
    kd_can_encode_rpdo(&j, 0x000F, 1e6, &f);
    assert_bytes(&f, 0x203, 6, w);
    kd_can_encode_rpdo2(&j, -1e6, &f);
    assert_bytes(&f, 0x303, 4, v);
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

static void test_nmt(void **state)
{
    struct can_frame f;
    static const uint8_t start5[8] = {0x01, 0x05, 0, 0, 0, 0, 0, 0};
    static const uint8_t preop_all[8] = {0x80, 0x00, 0, 0, 0, 0, 0, 0};
    (void)state;
    memset(&f, 0xA5, sizeof f);
    kd_can_encode_nmt(0x01, 5, &f);
    assert_bytes(&f, 0x000, 2, start5);
    kd_can_encode_nmt(0x80, 0, &f);
    assert_bytes(&f, 0x000, 2, preop_all);
}

static void test_emcy_decode(void **state)
{
    struct can_frame f;
    uint16_t code = 0;
    uint8_t reg = 0;
    (void)state;
    memset(&f, 0, sizeof f);
    f.can_id = 0x083;
    f.len = 8;
    f.data[0] = 0x30; /* 0x5530 little-endian, register 0x01 */
    f.data[1] = 0x55;
    f.data[2] = 0x01;
    f.data[3] = 0xEE;
    assert_int_equal(kd_can_decode_emcy(&f, &code, &reg), 0);
    assert_int_equal(code, 0x5530);
    assert_int_equal(reg, 0x01);
    f.len = 2; /* too short: untouched */
    code = 7;
    reg = 9;
    assert_int_equal(kd_can_decode_emcy(&f, &code, &reg), -1);
    assert_int_equal(code, 7);
    assert_int_equal(reg, 9);
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
    /* statusword 0x1237 (operation enabled, target followed), 5000 counts */
    static const uint8_t d1[6] = {0x37, 0x12, 0x88, 0x13, 0x00, 0x00};
    kd_can_joint j = joint(5, 10000.0, 1, 0);
    struct can_frame f = tpdo(d1, 6);
    assert_int_equal(kd_can_decode_tpdo(&j, &f, &q, &sw), 0);
    assert_true(q == 0.5);
    assert_int_equal(sw, 0x1237);
    /* -1000 counts = 0xFFFFFC18 */
    static const uint8_t d2[6] = {0x08, 0x00, 0x18, 0xFC, 0xFF, 0xFF};
    f = tpdo(d2, 6);
    assert_int_equal(kd_can_decode_tpdo(&j, &f, &q, &sw), 0);
    assert_true(q == -0.1);
    assert_int_equal(sw, 0x0008);
    /* sign -1, offset 1000: 3000 counts -> (3000 - 1000) / -10000 */
    static const uint8_t d3[6] = {0x00, 0x80, 0xB8, 0x0B, 0x00, 0x00};
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
        kd_can_encode_rpdo(&j, 0x000F, q, &rpdo);
        assert_int_equal(rpdo.can_id, 0x200u + (canid_t)j.node);
        fb = tpdo(rpdo.data, 6); /* position actual sits where the target does, the statusword where the controlword */
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
        cmocka_unit_test(test_round_trip), cmocka_unit_test(test_nmt),          cmocka_unit_test(test_emcy_decode),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
