/* SPDX-License-Identifier: BSD-3-Clause */
/* test_cia402.c - the master's view of the CiA 402 state machine
 * (daemon/cia402.h): statuswords of every state, with the don't-care bits
 * set and clear, against the masks of CiA 402-2; and the controlwords the
 * master sends, played against a drive's transitions written here from the
 * standard's table of device control commands. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "cia402.h"

static void test_state_of(void **state)
{
    static const struct {
        uint16_t sw;
        kd_cia402_state s;
    } cases[] = {
        {0x0000, KD_CIA402_NOT_READY},
        {0x0020, KD_CIA402_NOT_READY}, /* bit 5 is don't-care */
        {0x0240, KD_CIA402_SWITCH_ON_DISABLED},
        {0x0260, KD_CIA402_SWITCH_ON_DISABLED},
        {0x0250, KD_CIA402_SWITCH_ON_DISABLED}, /* bit 4, voltage enabled */
        {0x0221, KD_CIA402_READY_TO_SWITCH_ON},
        {0x0231, KD_CIA402_READY_TO_SWITCH_ON},
        {0x0223, KD_CIA402_SWITCHED_ON},
        {0x0233, KD_CIA402_SWITCHED_ON},
        {0x0237, KD_CIA402_OPERATION_ENABLED},
        {0x1237, KD_CIA402_OPERATION_ENABLED}, /* bit 12: follows the target */
        {0x3637, KD_CIA402_OPERATION_ENABLED}, /* bits 13, 10, 9 */
        {0x0217, KD_CIA402_QUICK_STOP_ACTIVE},
        {0x0007, KD_CIA402_QUICK_STOP_ACTIVE},
        {0x021F, KD_CIA402_FAULT_REACTION_ACTIVE},
        {0x003F, KD_CIA402_FAULT_REACTION_ACTIVE},
        {0x0208, KD_CIA402_FAULT},
        {0x0238, KD_CIA402_FAULT},
        {0x0218, KD_CIA402_FAULT},
        {0x0001, KD_CIA402_UNKNOWN},
        {0x0061, KD_CIA402_UNKNOWN}, /* 0x41 under 0x4F, 0x61 under 0x6F: no state */
        {0x004F, KD_CIA402_UNKNOWN},
    };
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        kd_cia402_state got = kd_cia402_state_of(cases[i].sw);
        if (got != cases[i].s)
            fail_msg("statusword 0x%04x: %s, want %s", cases[i].sw, kd_cia402_state_str(got),
                     kd_cia402_state_str(cases[i].s));
    }
}

/* A drive's transitions (CiA 402-2, "device control commands": bits 7, 3,
 * 2, 1, 0 of the controlword), with a fault reset on bit 7's rising edge;
 * its statusword. */
typedef struct drive {
    kd_cia402_state s;
    uint16_t last_cw;
} drive;

static void drive_apply(drive *d, uint16_t cw)
{
    unsigned c = cw & 0x8Fu;
    int reset_edge = (cw & 0x80u) && !(d->last_cw & 0x80u);
    d->last_cw = cw;
    int disable_voltage = !(c & 0x02u);
    int quick_stop = (c & 0x06u) == 0x02u;
    int shutdown = (c & 0x87u) == 0x06u;
    int switch_on = (c & 0x8Fu) == 0x07u;
    int enable = (c & 0x8Fu) == 0x0Fu;
    switch (d->s) {
    case KD_CIA402_SWITCH_ON_DISABLED:
        if (shutdown)
            d->s = KD_CIA402_READY_TO_SWITCH_ON; /* 2 */
        break;
    case KD_CIA402_READY_TO_SWITCH_ON:
        if (switch_on)
            d->s = KD_CIA402_SWITCHED_ON; /* 3 */
        else if (disable_voltage || quick_stop)
            d->s = KD_CIA402_SWITCH_ON_DISABLED; /* 7 */
        break;
    case KD_CIA402_SWITCHED_ON:
        if (enable)
            d->s = KD_CIA402_OPERATION_ENABLED; /* 4 */
        else if (shutdown)
            d->s = KD_CIA402_READY_TO_SWITCH_ON; /* 6 */
        else if (disable_voltage || quick_stop)
            d->s = KD_CIA402_SWITCH_ON_DISABLED; /* 10 */
        break;
    case KD_CIA402_OPERATION_ENABLED:
        if (quick_stop)
            d->s = KD_CIA402_QUICK_STOP_ACTIVE; /* 11 */
        else if (disable_voltage)
            d->s = KD_CIA402_SWITCH_ON_DISABLED; /* 9 */
        else if (shutdown)
            d->s = KD_CIA402_READY_TO_SWITCH_ON; /* 8 */
        else if (switch_on)
            d->s = KD_CIA402_SWITCHED_ON; /* 5 */
        break;
    case KD_CIA402_QUICK_STOP_ACTIVE:
        if (disable_voltage)
            d->s = KD_CIA402_SWITCH_ON_DISABLED; /* 12 */
        break;
    case KD_CIA402_FAULT:
        if (reset_edge)
            d->s = KD_CIA402_SWITCH_ON_DISABLED; /* 15 */
        break;
    default:
        break;
    }
}

static uint16_t drive_statusword(const drive *d)
{
    switch (d->s) {
    case KD_CIA402_SWITCH_ON_DISABLED:
        return 0x0250;
    case KD_CIA402_READY_TO_SWITCH_ON:
        return 0x0231;
    case KD_CIA402_SWITCHED_ON:
        return 0x0233;
    case KD_CIA402_OPERATION_ENABLED:
        return 0x1237;
    case KD_CIA402_QUICK_STOP_ACTIVE:
        return 0x0217;
    case KD_CIA402_FAULT:
        return 0x0218;
    default:
        return 0x0000;
    }
}

/* Plays the master against the drive until the drive is in want (or 10
 * exchanges); returns the controlwords sent. */
static int walk(drive *d, kd_cia402_goal goal, kd_cia402_state want, uint16_t *sent)
{
    uint16_t prev = d->last_cw;
    for (int i = 0; i < 10; i++) {
        kd_cia402_state s = kd_cia402_state_of(drive_statusword(d));
        assert_int_equal(s, d->s);
        if (s == want)
            return i;
        uint16_t cw = kd_cia402_controlword(s, goal, prev);
        sent[i] = cw;
        drive_apply(d, cw);
        prev = cw;
    }
    fail_msg("the drive did not reach %s", kd_cia402_state_str(want));
    return -1;
}

static void test_enable(void **state)
{
    (void)state;
    uint16_t sent[10];
    drive d = {KD_CIA402_SWITCH_ON_DISABLED, 0};
    assert_int_equal(walk(&d, KD_CIA402_GOAL_ENABLED, KD_CIA402_OPERATION_ENABLED, sent), 3);
    assert_int_equal(sent[0], 0x06);
    assert_int_equal(sent[1], 0x07);
    assert_int_equal(sent[2], 0x0F);
    /* enabled: the controlword that holds it */
    assert_int_equal(kd_cia402_controlword(KD_CIA402_OPERATION_ENABLED, KD_CIA402_GOAL_ENABLED, 0x0F), 0x0F);
}

static void test_fault_reset_edge(void **state)
{
    (void)state;
    uint16_t sent[10];
    /* after enable operation (bit 7 clear): 0x80 at once, then the walk */
    drive d = {KD_CIA402_FAULT, 0x0F};
    assert_int_equal(walk(&d, KD_CIA402_GOAL_ENABLED, KD_CIA402_OPERATION_ENABLED, sent), 4);
    assert_int_equal(sent[0], 0x80);
    assert_int_equal(sent[1], 0x06);
    /* a fault again with bit 7 still set (the reset did not clear it): 0x00
     * first, then 0x80 for a new rising edge */
    drive e = {KD_CIA402_FAULT, 0x80};
    assert_int_equal(walk(&e, KD_CIA402_GOAL_ENABLED, KD_CIA402_OPERATION_ENABLED, sent), 5);
    assert_int_equal(sent[0], 0x00);
    assert_int_equal(sent[1], 0x80);
    assert_int_equal(sent[2], 0x06);
    assert_int_equal(sent[3], 0x07);
    assert_int_equal(sent[4], 0x0F);
}

static void test_quick_stop_and_disable(void **state)
{
    (void)state;
    uint16_t sent[10];
    drive d = {KD_CIA402_OPERATION_ENABLED, 0x0F};
    assert_int_equal(walk(&d, KD_CIA402_GOAL_QUICK_STOP, KD_CIA402_QUICK_STOP_ACTIVE, sent), 1);
    assert_int_equal(sent[0], 0x02);
    /* re-enable from quick stop: through switch on disabled */
    assert_int_equal(walk(&d, KD_CIA402_GOAL_ENABLED, KD_CIA402_OPERATION_ENABLED, sent), 4);
    assert_int_equal(sent[0], 0x00);
    assert_int_equal(sent[1], 0x06);
    assert_int_equal(walk(&d, KD_CIA402_GOAL_DISABLED, KD_CIA402_SWITCH_ON_DISABLED, sent), 1);
    assert_int_equal(sent[0], 0x00);
    /* a faulted drive is not reset by a quick stop or a disable */
    drive f = {KD_CIA402_FAULT, 0};
    drive_apply(&f, kd_cia402_controlword(KD_CIA402_FAULT, KD_CIA402_GOAL_QUICK_STOP, 0));
    drive_apply(&f, kd_cia402_controlword(KD_CIA402_FAULT, KD_CIA402_GOAL_DISABLED, 0));
    assert_int_equal(f.s, KD_CIA402_FAULT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_state_of),
        cmocka_unit_test(test_enable),
        cmocka_unit_test(test_fault_reset_edge),
        cmocka_unit_test(test_quick_stop_and_disable),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
