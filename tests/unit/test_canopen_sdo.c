/* SPDX-License-Identifier: BSD-3-Clause */
/* test_canopen_sdo.c - the expedited SDO client (daemon/canopen_sdo.h)
 * frame by frame against CiA 301 7.2.4.3: requests written out by hand
 * (command byte, index little-endian, subindex, data), answers of a
 * server, aborts with their codes, stale and foreign frames, timeouts. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "canopen_sdo.h"

static struct can_frame frame(canid_t id, const uint8_t *data, int len)
{
    struct can_frame f;
    memset(&f, 0, sizeof f);
    f.can_id = id;
    f.len = (uint8_t)len;
    memcpy(f.data, data, (size_t)len);
    return f;
}

static void assert_frame(const struct can_frame *f, canid_t id, const uint8_t *want)
{
    assert_int_equal(f->can_id, id);
    assert_int_equal(f->len, 8);
    assert_memory_equal(f->data, want, 8);
}

static void test_download(void **state)
{
    (void)state;
    kd_sdo c;
    struct can_frame out, back;
    int n;
    assert_int_equal(kd_sdo_init(&c, 3, 100000), 0);
    /* 0x607A:00 = 0x12345678, 4 bytes: 0x23 */
    assert_int_equal(kd_sdo_download(&c, 0x607A, 0, 0x12345678u, 4, &out), KD_SDO_WAITING);
    assert_frame(&out, 0x603, (const uint8_t[]){0x23, 0x7A, 0x60, 0x00, 0x78, 0x56, 0x34, 0x12});
    /* a second transfer while one is under way */
    assert_int_equal(kd_sdo_upload(&c, 0x6041, 0, &out), KD_SDO_E_BUSY);
    back = frame(0x583, (const uint8_t[]){0x60, 0x7A, 0x60, 0x00, 0, 0, 0, 0}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_DONE);
    assert_int_equal(n, 0);
    /* 0x6040 = 0x0006, 2 bytes: 0x2B; high bytes of value dropped */
    assert_int_equal(kd_sdo_download(&c, 0x6040, 0, 0xFFFF0006u, 2, &out), KD_SDO_WAITING);
    assert_frame(&out, 0x603, (const uint8_t[]){0x2B, 0x40, 0x60, 0x00, 0x06, 0x00, 0x00, 0x00});
    assert_int_equal(c.value, 0x0006u);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_IGNORED); /* answer about 0x607A: stale */
    back = frame(0x583, (const uint8_t[]){0x60, 0x40, 0x60, 0x00, 0, 0, 0, 0}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_DONE);
    /* 0x60C2:02 = -3 (int8 0xFD), 1 byte: 0x2F; 3 bytes: 0x27 */
    assert_int_equal(kd_sdo_download(&c, 0x60C2, 2, (uint32_t)(int32_t)-3, 1, &out), KD_SDO_WAITING);
    assert_frame(&out, 0x603, (const uint8_t[]){0x2F, 0xC2, 0x60, 0x02, 0xFD, 0x00, 0x00, 0x00});
    back = frame(0x583, (const uint8_t[]){0x60, 0xC2, 0x60, 0x02, 0, 0, 0, 0}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_DONE);
    assert_int_equal(kd_sdo_download(&c, 0x2000, 1, 0xABCDEFu, 3, &out), KD_SDO_WAITING);
    assert_frame(&out, 0x603, (const uint8_t[]){0x27, 0x00, 0x20, 0x01, 0xEF, 0xCD, 0xAB, 0x00});
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_IGNORED);
    back = frame(0x583, (const uint8_t[]){0x60, 0x00, 0x20, 0x01, 0, 0, 0, 0}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_DONE);
    assert_int_equal(kd_sdo_download(&c, 0x2000, 1, 0, 5, &out), KD_SDO_E_ARG);
    assert_int_equal(kd_sdo_download(&c, 0x2000, 1, 0, 0, &out), KD_SDO_E_ARG);
}

static void test_upload(void **state)
{
    (void)state;
    kd_sdo c;
    struct can_frame out, back;
    int n;
    assert_int_equal(kd_sdo_init(&c, 127, 100000), 0);
    assert_int_equal(kd_sdo_upload(&c, 0x6064, 0, &out), KD_SDO_WAITING);
    assert_frame(&out, 0x67F, (const uint8_t[]){0x40, 0x64, 0x60, 0x00, 0, 0, 0, 0});
    /* 0x43: 4 bytes, 100000 = 0x000186A0 */
    back = frame(0x5FF, (const uint8_t[]){0x43, 0x64, 0x60, 0x00, 0xA0, 0x86, 0x01, 0x00}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_DONE);
    assert_int_equal(c.value, 100000u);
    assert_int_equal(c.size, 4);
    /* 0x4B: 2 bytes, the rest of the frame is not the value */
    assert_int_equal(kd_sdo_upload(&c, 0x6041, 0, &out), KD_SDO_WAITING);
    back = frame(0x5FF, (const uint8_t[]){0x4B, 0x41, 0x60, 0x00, 0x37, 0x12, 0xEE, 0xEE}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_DONE);
    assert_int_equal(c.value, 0x1237u);
    assert_int_equal(c.size, 2);
    /* 0x4F: 1 byte */
    assert_int_equal(kd_sdo_upload(&c, 0x6061, 0, &out), KD_SDO_WAITING);
    back = frame(0x5FF, (const uint8_t[]){0x4F, 0x61, 0x60, 0x00, 0x08, 0xEE, 0xEE, 0xEE}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_DONE);
    assert_int_equal(c.value, 8u);
    assert_int_equal(c.size, 1);
    /* 0x42: expedited, size not indicated: 4 bytes */
    assert_int_equal(kd_sdo_upload(&c, 0x1000, 0, &out), KD_SDO_WAITING);
    back = frame(0x5FF, (const uint8_t[]){0x42, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_DONE);
    assert_int_equal(c.value, 0x00020192u);
    /* 0x41: a segmented upload is not taken: the client aborts 0x05040001 */
    assert_int_equal(kd_sdo_upload(&c, 0x1008, 0, &out), KD_SDO_WAITING);
    back = frame(0x5FF, (const uint8_t[]){0x41, 0x08, 0x10, 0x00, 0x20, 0, 0, 0}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_E_PROTOCOL);
    assert_int_equal(n, 1);
    assert_frame(&out, 0x67F, (const uint8_t[]){0x80, 0x08, 0x10, 0x00, 0x01, 0x00, 0x04, 0x05});
    assert_int_equal(c.abort_code, 0x05040001u);
    /* idle again */
    assert_int_equal(kd_sdo_upload(&c, 0x1008, 0, &out), KD_SDO_WAITING);
}

static void test_abort_and_foreign(void **state)
{
    (void)state;
    kd_sdo c;
    struct can_frame out, back;
    int n;
    assert_int_equal(kd_sdo_init(&c, 5, 100000), 0);
    assert_int_equal(kd_sdo_download(&c, 0x6060, 0, 8, 1, &out), KD_SDO_WAITING);
    /* another node's answer, an extended frame with our id, a heartbeat */
    back = frame(0x584, (const uint8_t[]){0x60, 0x60, 0x60, 0x00, 0, 0, 0, 0}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_IGNORED);
    back.can_id = 0x585 | CAN_EFF_FLAG;
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_IGNORED);
    back = frame(0x705, (const uint8_t[]){0x7F}, 1);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_IGNORED);
    /* the server aborts with 0x06090030 (invalid value) */
    back = frame(0x585, (const uint8_t[]){0x80, 0x60, 0x60, 0x00, 0x30, 0x00, 0x09, 0x06}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_E_ABORTED);
    assert_int_equal(n, 0);
    assert_int_equal(c.abort_code, 0x06090030u);
    assert_string_equal(kd_sdo_abort_str(c.abort_code), "invalid value for parameter");
    assert_string_equal(kd_sdo_abort_str(0x06020000u), "object does not exist in the object dictionary");
    assert_string_equal(kd_sdo_abort_str(0x12345678u), "unknown abort code");
    /* nothing awaited: every frame ignored */
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_IGNORED);
    /* a download answered with an upload response: protocol error */
    assert_int_equal(kd_sdo_download(&c, 0x6060, 0, 8, 1, &out), KD_SDO_WAITING);
    back = frame(0x585, (const uint8_t[]){0x4F, 0x60, 0x60, 0x00, 8, 0, 0, 0}, 8);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_E_PROTOCOL);
    assert_frame(&out, 0x605, (const uint8_t[]){0x80, 0x60, 0x60, 0x00, 0x01, 0x00, 0x04, 0x05});
}

static void test_timeout(void **state)
{
    (void)state;
    kd_sdo c;
    struct can_frame out;
    int n;
    assert_int_equal(kd_sdo_init(&c, 0, 1000), KD_SDO_E_ARG);
    assert_int_equal(kd_sdo_init(&c, 128, 1000), KD_SDO_E_ARG);
    assert_int_equal(kd_sdo_init(&c, 1, 0), KD_SDO_E_ARG);
    assert_int_equal(kd_sdo_init(&c, 1, 1000), 0);
    assert_int_equal(kd_sdo_process(&c, 5000, &out, &n), KD_SDO_DONE); /* idle */
    assert_int_equal(n, 0);
    struct can_frame sent, two[KD_SDO_OUT_MAX];
    const uint8_t abort[8] = {0x80, 0x17, 0x10, 0x00, 0x00, 0x00, 0x04, 0x05};
    assert_int_equal(kd_sdo_upload(&c, 0x1017, 0, &sent), KD_SDO_WAITING);
    /* each unanswered send: the abort, then the same request, its time afresh */
    for (int k = 1; k < KD_SDO_SENDS; k++) {
        assert_int_equal(kd_sdo_process(&c, 400, two, &n), KD_SDO_WAITING);
        assert_int_equal(kd_sdo_process(&c, 599, two, &n), KD_SDO_WAITING);
        assert_int_equal(n, 0);
        assert_int_equal(kd_sdo_process(&c, 1, two, &n), KD_SDO_WAITING);
        assert_int_equal(n, 2);
        assert_frame(&two[0], 0x601, abort);
        assert_frame(&two[1], 0x601, sent.data);
        assert_int_equal(c.sends, k + 1);
    }
    assert_int_equal(kd_sdo_process(&c, 999, two, &n), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_process(&c, 1, two, &n), KD_SDO_E_TIMEOUT);
    assert_int_equal(n, 1);
    assert_frame(&two[0], 0x601, abort);
    assert_int_equal(c.abort_code, KD_SDO_ABORT_TIMEOUT);
    assert_int_equal(c.sends, KD_SDO_SENDS);
    /* an answer to a request sent again ends the transfer; a download is
     * sent again with its value */
    assert_int_equal(kd_sdo_download(&c, 0x6065, 0, 20000, 4, &sent), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_process(&c, 1000, two, &n), KD_SDO_WAITING);
    assert_frame(&two[1], 0x601, sent.data);
    struct can_frame done = sent;
    done.can_id = 0x581;
    memset(done.data, 0, 8);
    done.data[0] = 0x60;
    done.data[1] = 0x65;
    done.data[2] = 0x60;
    assert_int_equal(kd_sdo_rx(&c, &done, two, &n), KD_SDO_DONE);
    assert_int_equal(c.sends, 2);
    /* a huge step does not wrap the elapsed time */
    assert_int_equal(kd_sdo_upload(&c, 0x1017, 0, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_process(&c, 999, two, &n), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_process(&c, UINT32_MAX, two, &n), KD_SDO_WAITING);
    assert_int_equal(n, 2);
}

/* A slow server answers every send: the answer to a second send comes
 * while the next request is out, and is not taken for its answer. */
static void test_late_answers(void **state)
{
    (void)state;
    kd_sdo c;
    struct can_frame out, two[KD_SDO_OUT_MAX], back;
    int n;
    const struct can_frame written = frame(0x585, (const uint8_t[]){0x60, 0x00, 0x16, 0x00, 0, 0, 0, 0}, 8);
    const struct can_frame read = frame(0x585, (const uint8_t[]){0x4F, 0x00, 0x16, 0x00, 2, 0, 0, 0}, 8);
    assert_int_equal(kd_sdo_init(&c, 5, 1000), 0);
    /* a write of 0x1600:00, sent twice, ended by the answer to the first */
    assert_int_equal(kd_sdo_download(&c, 0x1600, 0, 2, 1, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_process(&c, 1000, two, &n), KD_SDO_WAITING);
    assert_int_equal(n, 2);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_DONE);
    /* its read-back: the answer to the write's second send is ignored */
    assert_int_equal(kd_sdo_upload(&c, 0x1600, 0, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_IGNORED);
    assert_int_equal(n, 0);
    assert_true(c.busy);
    assert_int_equal(kd_sdo_rx(&c, &read, &out, &n), KD_SDO_DONE);
    assert_int_equal(c.value, 2);
    /* answered at its first send, nothing is owed: a second write answer
     * during the next read is the protocol error it always was */
    assert_int_equal(kd_sdo_download(&c, 0x1600, 0, 2, 1, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_DONE);
    assert_int_equal(kd_sdo_upload(&c, 0x1600, 0, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_E_PROTOCOL);
    /* the owed answer never came (lost): the next transfer's own answer of
     * another kind ends it at once, and nothing is owed after it */
    assert_int_equal(kd_sdo_download(&c, 0x1600, 0, 2, 1, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_process(&c, 1000, two, &n), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_DONE);
    assert_int_equal(kd_sdo_upload(&c, 0x1600, 0, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &read, &out, &n), KD_SDO_DONE);
    assert_int_equal(c.owed, 0);
    /* the same write twice: the first write's owed answer is not the
     * second's; the second's own answer after it ends it */
    assert_int_equal(kd_sdo_download(&c, 0x1600, 0, 0, 1, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_process(&c, 1000, two, &n), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_DONE);
    assert_int_equal(kd_sdo_download(&c, 0x1600, 0, 2, 1, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_IGNORED);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_DONE);
    /* ... and where that owed answer was lost, the second's own answer is
     * the one ignored: a timeout and a send again, then its answer */
    assert_int_equal(kd_sdo_download(&c, 0x1600, 0, 0, 1, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_process(&c, 1000, two, &n), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_DONE);
    assert_int_equal(kd_sdo_download(&c, 0x1600, 0, 2, 1, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_IGNORED);
    assert_int_equal(kd_sdo_process(&c, 1000, two, &n), KD_SDO_WAITING);
    assert_int_equal(n, 2);
    assert_memory_equal(two[1].data, out.data, 8);
    assert_int_equal(kd_sdo_rx(&c, &written, &out, &n), KD_SDO_DONE);
    /* an abort answering an owed send is ignored too */
    back = frame(0x585, (const uint8_t[]){0x80, 0x00, 0x16, 0x00, 0x00, 0x00, 0x04, 0x05}, 8);
    assert_int_equal(kd_sdo_upload(&c, 0x1600, 0, &out), KD_SDO_WAITING);
    assert_int_equal(kd_sdo_rx(&c, &back, &out, &n), KD_SDO_IGNORED);
    assert_int_equal(kd_sdo_rx(&c, &read, &out, &n), KD_SDO_DONE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_download),
        cmocka_unit_test(test_upload),
        cmocka_unit_test(test_abort_and_foreign),
        cmocka_unit_test(test_timeout),
        cmocka_unit_test(test_late_answers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
