/* SPDX-License-Identifier: BSD-3-Clause */
/* test_canopen_boot.c - a drive's boot and configuration
 * (daemon/canopen_boot.h) played against a drive written here from CiA 301:
 * an object dictionary with an expedited SDO server that answers 0x600 +
 * node requests on 0x580 + node, refuses a mapping change while the PDO is
 * valid (abort 0x06010000) as CiA 301 7.5.2.36 says, and may refuse or
 * alter one object. The test checks the frames the master sends (NMT reset,
 * the SDO writes in CiA 301's order, NMT start), the drive's dictionary at
 * the end, and the reasons of every failure. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "canopen_boot.h"

#define OBJECTS 64

typedef struct drive {
    int node;
    struct {
        uint16_t index;
        uint8_t sub;
        uint32_t value;
    } od[OBJECTS];
    int n;
    uint16_t refuse_index;   /* abort writes to it with refuse_code */
    uint32_t refuse_code;
    uint16_t clamp_index;    /* store clamp_value whatever is written */
    uint32_t clamp_value;
    int silent_sdo;          /* never answers */
    int deaf;                /* the next deaf requests go unanswered (frames lost) */
    int lose_each;           /* every new request: its first lose_each sends go unanswered */
    uint8_t last[8];         /* the last request's bytes (a send again repeats them) */
    int served;              /* requests received */
    struct {
        uint16_t index;
        uint8_t sub;
        uint32_t value;
    } writes[128];
    int n_writes;
} drive;

static uint32_t *obj(drive *d, uint16_t index, uint8_t sub)
{
    for (int i = 0; i < d->n; i++)
        if (d->od[i].index == index && d->od[i].sub == sub)
            return &d->od[i].value;
    return NULL;
}

static void def(drive *d, uint16_t index, uint8_t sub, uint32_t value)
{
    d->od[d->n].index = index;
    d->od[d->n].sub = sub;
    d->od[d->n].value = value;
    d->n++;
}

static void drive_init(drive *d, int node)
{
    memset(d, 0, sizeof *d);
    d->node = node;
    def(d, 0x1000, 0, 0x00020192u);
    def(d, 0x1018, 1, 0x4B494E43u);
    def(d, 0x1018, 2, 0x402u);
    def(d, 0x1016, 1, 0);
    def(d, 0x1017, 0, 0);
    def(d, 0x1006, 0, 0);
    def(d, 0x1019, 0, 0);
    for (uint16_t k = 0; k < 2; k++) {
        def(d, (uint16_t)(0x1400 + k), 1, (k ? 0x80000300u : 0x200u) + (uint32_t)node);
        def(d, (uint16_t)(0x1400 + k), 2, 255);
        def(d, (uint16_t)(0x1800 + k), 1, (k ? 0x80000280u : 0x40000180u) + (uint32_t)node); /* bit 30: no RTR */
        def(d, (uint16_t)(0x1800 + k), 2, 255);
        for (uint8_t s = 0; s <= 3; s++) {
            def(d, (uint16_t)(0x1600 + k), s, s == 0 ? 1 : s == 1 ? 0x60400010u : 0);
            def(d, (uint16_t)(0x1A00 + k), s, s == 0 ? 1 : s == 1 ? 0x60410010u : 0);
        }
    }
    def(d, 0x6007, 0, 1);
    def(d, 0x6060, 0, 0);
    def(d, 0x60C2, 1, 1);
    def(d, 0x60C2, 2, 0xFD);
    def(d, 0x6065, 0, 0xFFFFFFFFu);
}

static struct can_frame answer(const drive *d, uint8_t cmd, uint16_t index, uint8_t sub, uint32_t data)
{
    struct can_frame f;
    memset(&f, 0, sizeof f);
    f.can_id = 0x580u + (canid_t)d->node;
    f.len = 8;
    f.data[0] = cmd;
    f.data[1] = (uint8_t)(index & 0xFF);
    f.data[2] = (uint8_t)(index >> 8);
    f.data[3] = sub;
    for (int i = 0; i < 4; i++)
        f.data[4 + i] = (uint8_t)(data >> (8 * i));
    return f;
}

/* The drive's answer to a request; 0 when it does not answer. */
static int drive_serve(drive *d, const struct can_frame *req, struct can_frame *ans)
{
    assert_int_equal(req->can_id, 0x600u + (canid_t)d->node);
    assert_int_equal(req->len, 8);
    d->served++;
    if (d->lose_each > 0 && memcmp(req->data, d->last, 8) != 0)
        d->deaf = d->lose_each;
    memcpy(d->last, req->data, 8);
    if (d->silent_sdo)
        return 0;
    if (d->deaf > 0) {
        d->deaf--;
        return 0;
    }
    uint8_t cmd = req->data[0];
    uint16_t index = (uint16_t)(req->data[1] | req->data[2] << 8);
    uint8_t sub = req->data[3];
    uint32_t value = (uint32_t)req->data[4] | (uint32_t)req->data[5] << 8 | (uint32_t)req->data[6] << 16 |
                     (uint32_t)req->data[7] << 24;
    uint32_t *o = obj(d, index, sub);
    if (!o) {
        *ans = answer(d, 0x80, index, sub, 0x06020000u);
        return 1;
    }
    if (cmd == 0x40) {
        *ans = answer(d, 0x43, index, sub, *o);
        return 1;
    }
    assert_true(cmd == 0x23 || cmd == 0x27 || cmd == 0x2B || cmd == 0x2F);
    int size = 4 - ((cmd >> 2) & 3);
    value &= size == 4 ? 0xFFFFFFFFu : (1u << (8 * size)) - 1u;
    if (index == d->refuse_index) {
        *ans = answer(d, 0x80, index, sub, d->refuse_code);
        return 1;
    }
    /* CiA 301: the mapping of a valid PDO, or its entries while sub 0 is
     * not 0, cannot change */
    if ((index & 0xFE00u) == 0x1600u || (index & 0xFE00u) == 0x1A00u) {
        uint32_t cob = *obj(d, (uint16_t)(index - 0x200), 1);
        if (!(cob & 0x80000000u) || (sub > 0 && *obj(d, index, 0) != 0)) {
            *ans = answer(d, 0x80, index, sub, 0x06010000u);
            return 1;
        }
    }
    d->writes[d->n_writes].index = index;
    d->writes[d->n_writes].sub = sub;
    d->writes[d->n_writes].value = value;
    d->n_writes++;
    *o = index == d->clamp_index ? d->clamp_value : value;
    *ans = answer(d, 0x60, index, sub, 0);
    return 1;
}

static struct can_frame heartbeat(int node, uint8_t state)
{
    struct can_frame f;
    memset(&f, 0, sizeof f);
    f.can_id = 0x700u + (canid_t)node;
    f.len = 1;
    f.data[0] = state;
    return f;
}

/* Runs the boot against the drive from the boot-up on; returns the result. */
static int run(kd_boot *b, drive *d, struct can_frame *last)
{
    struct can_frame out[KD_BOOT_OUT_MAX], ans;
    int n;
    struct can_frame up = heartbeat(d->node, 0);
    int r = kd_boot_rx(b, &up, out, &n);
    for (int guard = 0; guard < 1000 && r == KD_BOOT_WAITING; guard++) {
        /* one request, or after a timeout the abort and the request again */
        assert_int_equal(n, out[0].data[0] == 0x80 ? 2 : 1);
        if (n == 2)
            assert_memory_equal(out[1].data, last->data, 4);
        *last = out[n - 1];
        if (drive_serve(d, &out[n - 1], &ans))
            r = kd_boot_rx(b, &ans, out, &n);
        else
            r = kd_boot_process(b, b->cfg.sdo_timeout_us, out, &n);
    }
    if (n > 0)
        *last = out[n - 1];
    return r;
}

/* Runs the boot against a drive that answers every request only after the
 * client has sent it again, and answers both sends: the late answer to
 * the first ends the transfer, and the answer to the second comes after
 * the client's next request. Returns the result. */
static int run_late(kd_boot *b, drive *d)
{
    struct can_frame out[KD_BOOT_OUT_MAX], late, again, owed;
    int n, have_owed = 0;
    struct can_frame up = heartbeat(d->node, 0);
    int r = kd_boot_rx(b, &up, out, &n);
    for (int guard = 0; guard < 1000 && r == KD_BOOT_WAITING; guard++) {
        assert_int_equal(n, 1);
        struct can_frame req = out[0];
        if (have_owed) {
            assert_int_equal(kd_boot_rx(b, &owed, out, &n), KD_BOOT_WAITING);
            assert_int_equal(n, 0);
            have_owed = 0;
        }
        assert_int_equal(drive_serve(d, &req, &late), 1);
        r = kd_boot_process(b, b->cfg.sdo_timeout_us, out, &n);
        assert_int_equal(r, KD_BOOT_WAITING);
        assert_int_equal(n, 2);
        assert_int_equal(out[0].data[0], 0x80);
        assert_memory_equal(out[1].data, req.data, 8);
        assert_int_equal(drive_serve(d, &out[1], &again), 1);
        r = kd_boot_rx(b, &late, out, &n);
        owed = again;
        have_owed = 1;
    }
    return r;
}

static kd_boot_cfg config(int node)
{
    kd_boot_cfg c = kd_boot_cfg_default(node);
    c.tpdo[0].transmission_type = 2;
    c.interpolation_us = 4000;
    c.heartbeat_ms = 50;
    c.consumer_ms = 250;
    c.extra[0] = (kd_boot_write){0x6065, 0, 4, 20000};
    c.n_extra = 1;
    return c;
}

static void test_boot(void **state)
{
    (void)state;
    drive d;
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX], last;
    int n;
    char why[256];
    drive_init(&d, 3);
    kd_boot_cfg c = config(3);
    assert_int_equal(kd_boot_init(&b, &c), 0);
    assert_int_equal(kd_boot_start(&b, out, &n), KD_BOOT_WAITING);
    assert_int_equal(n, 1);
    assert_int_equal(out[0].can_id, 0x000);
    assert_int_equal(out[0].len, 2);
    assert_int_equal(out[0].data[0], 0x82);
    assert_int_equal(out[0].data[1], 3);
    /* a heartbeat from before the reset is not the boot-up */
    struct can_frame hb = heartbeat(3, 0x05);
    assert_int_equal(kd_boot_rx(&b, &hb, out, &n), KD_BOOT_WAITING);
    assert_int_equal(n, 0);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_DONE);
    /* NMT start */
    assert_int_equal(last.can_id, 0x000);
    assert_int_equal(last.data[0], 0x01);
    assert_int_equal(last.data[1], 3);
    kd_boot_why(&b, why, sizeof why);
    assert_string_equal(why, "");
    /* the writes in CiA 301's order, by hand */
    static const struct {
        uint16_t index;
        uint8_t sub;
        uint32_t value;
    } want[] = {
        {0x1400, 1, 0x80000203u}, {0x1400, 2, 1}, {0x1600, 0, 0}, {0x1600, 1, 0x60400010u},
        {0x1600, 2, 0x607A0020u}, {0x1600, 0, 2}, {0x1400, 1, 0x203u},
        {0x1800, 1, 0x80000183u}, {0x1800, 2, 2}, {0x1A00, 0, 0}, {0x1A00, 1, 0x60410010u},
        {0x1A00, 2, 0x60640020u}, {0x1A00, 0, 2}, {0x1800, 1, 0x183u},
        {0x1401, 1, 0x80000303u}, {0x1801, 1, 0x80000283u}, /* the unused PDOs this drive has: invalid */
        {0x6060, 0, 8}, {0x60C2, 1, 4}, {0x60C2, 2, 0xFD}, /* 4 * 10^-3 s */
        {0x1017, 0, 50}, {0x1016, 1, 0x007F00FAu},        /* master 127, 250 ms */
        {0x6007, 0, 3}, {0x6065, 0, 20000},
    };
    assert_int_equal(d.n_writes, (int)(sizeof want / sizeof want[0]));
    for (int i = 0; i < d.n_writes; i++) {
        if (d.writes[i].index != want[i].index || d.writes[i].sub != want[i].sub || d.writes[i].value != want[i].value)
            fail_msg("write %d: 0x%04X:%02X = 0x%08X, want 0x%04X:%02X = 0x%08X", i, d.writes[i].index,
                     d.writes[i].sub, d.writes[i].value, want[i].index, want[i].sub, want[i].value);
    }
    /* after the end: nothing more */
    assert_int_equal(kd_boot_rx(&b, &hb, out, &n), KD_BOOT_DONE);
    assert_int_equal(n, 0);
}

static void test_without_reset(void **state)
{
    (void)state;
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX];
    int n;
    kd_boot_cfg c = config(5);
    c.reset_communication = 0;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    assert_int_equal(kd_boot_start(&b, out, &n), KD_BOOT_WAITING);
    assert_int_equal(n, 0);
    /* a drive already operational: NMT enter pre-operational, then the
     * first SDO (read 0x1000) */
    struct can_frame hb = heartbeat(5, 0x05);
    assert_int_equal(kd_boot_rx(&b, &hb, out, &n), KD_BOOT_WAITING);
    assert_int_equal(n, 2);
    assert_int_equal(out[0].can_id, 0x000);
    assert_int_equal(out[0].data[0], 0x80);
    assert_int_equal(out[0].data[1], 5);
    assert_int_equal(out[1].can_id, 0x605);
    const uint8_t read_1000[8] = {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0};
    assert_memory_equal(out[1].data, read_1000, 8);
}

static void test_device_type_and_identity(void **state)
{
    (void)state;
    drive d;
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX], last;
    int n;
    char why[256];
    drive_init(&d, 2);
    *obj(&d, 0x1000, 0) = 0x00020191u; /* CiA 401, not 402 */
    kd_boot_cfg c = config(2);
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_E_MISMATCH);
    kd_boot_why(&b, why, sizeof why);
    assert_string_equal(why, "node 2: 0x1000:00 (device type) is 0x00020191, expected 0x00000192 under mask 0x0000FFFF");
    assert_int_equal(d.n_writes, 0); /* nothing written to a stranger */
    drive_init(&d, 2);
    c.identity[1] = 0x403u;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_E_MISMATCH);
    kd_boot_why(&b, why, sizeof why);
    assert_string_equal(why, "node 2: 0x1018:02 (product code) is 0x00000402, expected 0x00000403 under mask 0xFFFFFFFF");
}

static void test_abort_and_readback(void **state)
{
    (void)state;
    drive d;
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX], last;
    int n;
    char why[256];
    drive_init(&d, 4);
    d.refuse_index = 0x6060;
    d.refuse_code = 0x06090030u;
    kd_boot_cfg c = config(4);
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_E_ABORTED);
    assert_int_equal(b.sdo.abort_code, 0x06090030u);
    kd_boot_why(&b, why, sizeof why);
    assert_string_equal(why, "node 4: SDO write 0x6060:00 (modes of operation) aborted by the drive with 0x06090030: "
                             "invalid value for parameter");
    /* a drive that keeps 0x1017 at 100 whatever is written */
    drive_init(&d, 4);
    d.clamp_index = 0x1017;
    d.clamp_value = 100;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_E_MISMATCH);
    kd_boot_why(&b, why, sizeof why);
    assert_string_equal(why, "node 4: 0x1017:00 (producer heartbeat time) reads back 0x00000064 after writing 0x00000032");
    /* a drive whose PDO 1 cannot be made invalid: its mapping is refused */
    drive_init(&d, 4);
    d.clamp_index = 0x1400;
    d.clamp_value = 0x204;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_E_MISMATCH);
    kd_boot_why(&b, why, sizeof why);
    assert_string_equal(why, "node 4: 0x1400:01 (RPDO1 COB-ID (invalid)) reads back 0x00000204 after writing 0x80000204");
}

static void test_timeouts(void **state)
{
    (void)state;
    drive d;
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX], last;
    int n;
    char why[256];
    kd_boot_cfg c = config(6);
    c.bootup_timeout_us = 2000000;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(kd_boot_process(&b, 1999999, out, &n), KD_BOOT_WAITING);
    assert_int_equal(kd_boot_process(&b, 1, out, &n), KD_BOOT_E_NO_BOOTUP);
    kd_boot_why(&b, why, sizeof why);
    assert_string_equal(why, "node 6: no boot-up after NMT reset communication within 2000 ms");
    /* the drive boots but never answers an SDO: the master aborts 0x05040000 */
    drive_init(&d, 6);
    d.silent_sdo = 1;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_E_SDO);
    assert_int_equal(last.can_id, 0x606);
    const uint8_t abort[8] = {0x80, 0x00, 0x10, 0x00, 0x00, 0x00, 0x04, 0x05};
    assert_memory_equal(last.data, abort, 8);
    kd_boot_why(&b, why, sizeof why);
    assert_string_equal(why, "node 6: SDO read 0x1000:00 (device type) aborted by the master with 0x05040000: SDO "
                             "protocol timed out, sent 3 times");
    assert_int_equal(d.served, KD_SDO_SENDS);
}

/* The boot of c against a drive that loses nothing, from power-on: what
 * the boots against lossy or slow drives are compared with. */
static void boot_clean(drive *clean, const kd_boot_cfg *c)
{
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX], last;
    int n;
    drive_init(clean, c->node);
    assert_int_equal(kd_boot_init(&b, c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, clean, &last), KD_BOOT_DONE);
}

/* got's writes are clean's, each made times times in a row. */
static void assert_writes_repeated(const drive *got, const drive *clean, int times)
{
    assert_int_equal(got->n_writes, times * clean->n_writes);
    for (int i = 0; i < clean->n_writes; i++)
        for (int k = 0; k < times; k++) {
            assert_int_equal(got->writes[times * i + k].index, clean->writes[i].index);
            assert_int_equal(got->writes[times * i + k].sub, clean->writes[i].sub);
            assert_int_equal(got->writes[times * i + k].value, clean->writes[i].value);
        }
}

/* Answers lost on the bus: each unanswered request is aborted and sent
 * again, and the boot ends as the one that lost nothing, with the same
 * writes; one answer too many lost fails it. */
static void test_lost_answers(void **state)
{
    (void)state;
    drive clean, lossy;
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX], last;
    int n;
    char why[256];
    kd_boot_cfg c = config(5);
    boot_clean(&clean, &c);
    /* every request answered at its last send only */
    drive_init(&lossy, 5);
    lossy.lose_each = KD_SDO_SENDS - 1;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &lossy, &last), KD_BOOT_DONE);
    assert_int_equal(lossy.served, clean.served * KD_SDO_SENDS);
    assert_writes_repeated(&lossy, &clean, 1);
    /* one more lost: the first request fails after its third send */
    drive_init(&lossy, 5);
    lossy.deaf = KD_SDO_SENDS;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &lossy, &last), KD_BOOT_E_SDO);
    kd_boot_why(&b, why, sizeof why);
    assert_string_equal(why, "node 5: SDO read 0x1000:00 (device type) aborted by the master with 0x05040000: SDO "
                             "protocol timed out, sent 3 times");
}

/* A drive slower than the SDO timeout, answering every send: each request
 * ends on its late first answer, the answer to its second send is not
 * taken for the next one's, and the boot writes what a prompt drive's
 * does (each write twice). */
static void test_late_answers(void **state)
{
    (void)state;
    drive clean, slow;
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX];
    int n;
    kd_boot_cfg c = config(5);
    boot_clean(&clean, &c);
    drive_init(&slow, 5);
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run_late(&b, &slow), KD_BOOT_DONE);
    assert_int_equal(slow.served, 2 * clean.served);
    assert_writes_repeated(&slow, &clean, 2);
}

/* configure = 0 (drives configured by other means): the checks, then NMT
 * start, and not one write. */
static void test_checks_only(void **state)
{
    (void)state;
    drive d;
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX], last;
    int n;
    drive_init(&d, 4);
    kd_boot_cfg c = config(4);
    c.configure = 0;
    c.identity[0] = 0x4B494E43u;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    assert_int_equal(b.n_steps, 2); /* 0x1000 and 0x1018:1, both reads */
    for (int i = 0; i < b.n_steps; i++)
        assert_int_equal(b.step[i].write, 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_DONE);
    assert_int_equal(d.n_writes, 0);
    assert_int_equal(last.can_id, 0x000);
    assert_int_equal(last.data[0], 0x01);
    assert_int_equal(last.data[1], 4);
    assert_int_equal(*obj(&d, 0x6060, 0), 0); /* untouched */
}

/* A SYNC counter: 0x1006 = 0 first (CiA 301: 0x1019 changes only while
 * 0x1006 is 0), then 0x1019, then 0x1006 where configured; a drive without
 * 0x1006 is still booted when no cycle period is asked for. */
static void test_sync_counter_order(void **state)
{
    (void)state;
    drive d;
    kd_boot b;
    struct can_frame out[KD_BOOT_OUT_MAX], last;
    int n, k = 0;
    uint32_t seq[8][2]; /* the writes to 0x1006 and 0x1019, in order: index, value */
    drive_init(&d, 2);
    *obj(&d, 0x1006, 0) = 1000; /* a period left from before */
    kd_boot_cfg c = config(2);
    c.sync_overflow = 5;
    c.cycle_period_us = 4000;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_DONE);
    for (int i = 0; i < d.n_writes && k < 8; i++)
        if (d.writes[i].index == 0x1006 || d.writes[i].index == 0x1019) {
            seq[k][0] = d.writes[i].index;
            seq[k][1] = d.writes[i].value;
            k++;
        }
    assert_int_equal(k, 3);
    assert_int_equal(seq[0][0], 0x1006);
    assert_int_equal(seq[0][1], 0);
    assert_int_equal(seq[1][0], 0x1019);
    assert_int_equal(seq[1][1], 5);
    assert_int_equal(seq[2][0], 0x1006);
    assert_int_equal(seq[2][1], 4000);
    /* no 0x1006 in this drive, none asked for: 0x1019 still written */
    drive_init(&d, 2);
    d.refuse_index = 0x1006;
    d.refuse_code = 0x06020000u;
    c.cycle_period_us = 0;
    assert_int_equal(kd_boot_init(&b, &c), 0);
    kd_boot_start(&b, out, &n);
    assert_int_equal(run(&b, &d, &last), KD_BOOT_DONE);
    assert_int_equal(*obj(&d, 0x1019, 0), 5);
}

static void test_interpolation_and_args(void **state)
{
    (void)state;
    static const struct {
        uint32_t us;
        int ok;
        uint8_t value;
        int8_t index;
    } cases[] = {{1000, 0, 1, -3},        {250, 0, 25, -5},   {125, 0, 125, -6},  {10000, 0, 10, -3},
                 {2500, 0, 25, -4},       {4000, 0, 4, -3},   {255000, 0, 255, -3}, {256000, -1, 0, 0},
                 {1000000, 0, 100, -2},   {256, -1, 0, 0},    {1001, -1, 0, 0},     {300000001, -1, 0, 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        uint8_t v = 0;
        int8_t x = 0;
        assert_int_equal(kd_boot_interpolation(cases[i].us, &v, &x), cases[i].ok);
        if (cases[i].ok == 0) {
            assert_int_equal(v, cases[i].value);
            assert_int_equal(x, cases[i].index);
        }
    }
    kd_boot b;
    kd_boot_cfg c = config(1);
    c.interpolation_us = 256;
    assert_int_equal(kd_boot_init(&b, &c), KD_BOOT_E_ARG);
    c = config(0);
    assert_int_equal(kd_boot_init(&b, &c), KD_BOOT_E_ARG);
    c = config(1);
    c.tpdo[0].map[2] = 0x60B10020u; /* 16 + 32 + 32 bits */
    c.tpdo[0].n_map = 3;
    assert_int_equal(kd_boot_init(&b, &c), KD_BOOT_E_ARG);
    c = config(1);
    c.tpdo[0].transmission_type = 241;
    assert_int_equal(kd_boot_init(&b, &c), KD_BOOT_E_ARG);
    c = config(1);
    c.extra[0].size = 5;
    assert_int_equal(kd_boot_init(&b, &c), KD_BOOT_E_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_boot),
        cmocka_unit_test(test_without_reset),
        cmocka_unit_test(test_device_type_and_identity),
        cmocka_unit_test(test_abort_and_readback),
        cmocka_unit_test(test_timeouts),
        cmocka_unit_test(test_lost_answers),
        cmocka_unit_test(test_late_answers),
        cmocka_unit_test(test_checks_only),
        cmocka_unit_test(test_sync_counter_order),
        cmocka_unit_test(test_interpolation_and_args),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
