/* SPDX-License-Identifier: BSD-3-Clause */
/* canopen_sdo.c - the expedited SDO client (canopen_sdo.h): CiA 301
 * 7.2.4.3.3 (initiate SDO download), 7.2.4.3.5 (initiate SDO upload),
 * 7.2.4.3.17 (abort SDO transfer) and table 22 (abort codes). */
#include "canopen_sdo.h"

#include <string.h>

static void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xffu);
    p[1] = (uint8_t)((v >> 8) & 0xffu);
    p[2] = (uint8_t)((v >> 16) & 0xffu);
    p[3] = (uint8_t)((v >> 24) & 0xffu);
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void request(const kd_sdo *c, uint8_t command, uint32_t data, struct can_frame *out)
{
    memset(out, 0, sizeof *out);
    out->can_id = KD_SDO_TX_BASE + (canid_t)c->node;
    out->len = 8;
    out->data[0] = command;
    out->data[1] = (uint8_t)(c->index & 0xffu);
    out->data[2] = (uint8_t)(c->index >> 8);
    out->data[3] = c->subindex;
    put_u32(&out->data[4], data);
}

int kd_sdo_init(kd_sdo *c, int node, uint32_t timeout_us)
{
    if (node < 1 || node > 127 || timeout_us == 0)
        return KD_SDO_E_ARG;
    memset(c, 0, sizeof *c);
    c->node = node;
    c->timeout_us = timeout_us;
    return 0;
}

static void start(kd_sdo *c, int upload, uint16_t index, uint8_t subindex)
{
    c->owed_upload = c->upload; /* owed was set as the last transfer ended */
    c->owed_index = c->index;
    c->owed_subindex = c->subindex;
    c->busy = 1;
    c->upload = upload;
    c->index = index;
    c->subindex = subindex;
    c->elapsed_us = 0;
    c->sends = 1;
    c->abort_code = 0;
}

/* The request of the transfer under way into out. */
static void send_request(const kd_sdo *c, struct can_frame *out)
{
    if (c->upload)
        request(c, 0x40u, 0, out);
    else /* ccs 1, n = 4 - size unused bytes, e = 1, s = 1 */
        request(c, (uint8_t)(0x23u | (unsigned)(4 - c->size) << 2), c->value, out);
}

int kd_sdo_download(kd_sdo *c, uint16_t index, uint8_t subindex, uint32_t value, int size, struct can_frame *out)
{
    if (c->busy)
        return KD_SDO_E_BUSY;
    if (size < 1 || size > 4)
        return KD_SDO_E_ARG;
    if (size < 4)
        value &= (1u << (8 * size)) - 1u;
    start(c, 0, index, subindex);
    c->value = value;
    c->size = size;
    send_request(c, out);
    return KD_SDO_WAITING;
}

int kd_sdo_upload(kd_sdo *c, uint16_t index, uint8_t subindex, struct can_frame *out)
{
    if (c->busy)
        return KD_SDO_E_BUSY;
    start(c, 1, index, subindex);
    c->value = 0;
    c->size = 0;
    send_request(c, out);
    return KD_SDO_WAITING;
}

/* The transfer under way ends; answered: on a frame of the server's. */
static void end(kd_sdo *c, int answered)
{
    c->busy = 0;
    c->owed = c->sends - answered;
}

static int client_abort(kd_sdo *c, uint32_t code, int answered, int result, struct can_frame *out, int *n_out)
{
    end(c, answered);
    c->abort_code = code;
    request(c, 0x80u, code, out);
    *n_out = 1;
    return result;
}

int kd_sdo_rx(kd_sdo *c, const struct can_frame *f, struct can_frame *out, int *n_out)
{
    *n_out = 0;
    if (!c->busy || (f->can_id & CAN_EFF_FLAG) || f->can_id != KD_SDO_RX_BASE + (canid_t)c->node)
        return KD_SDO_IGNORED;
    if (f->len < 4)
        return client_abort(c, KD_SDO_ABORT_COMMAND, 1, KD_SDO_E_PROTOCOL, out, n_out);
    uint16_t index = (uint16_t)(f->data[1] | f->data[2] << 8);
    uint8_t cmd = f->data[0];
    if (c->owed > 0 && index == c->owed_index && f->data[3] == c->owed_subindex &&
        (cmd == 0x80u || (c->owed_upload ? (cmd & 0xE0u) == 0x40u : cmd == 0x60u))) {
        c->owed--;
        return KD_SDO_IGNORED;
    }
    /* An answer about another object is a stale one (an earlier transfer
     * the client gave up on): not this transfer's. */
    if (index != c->index || f->data[3] != c->subindex)
        return KD_SDO_IGNORED;
    if (cmd == 0x80u) {
        end(c, 1);
        c->abort_code = f->len >= 8 ? get_u32(&f->data[4]) : 0;
        return KD_SDO_E_ABORTED;
    }
    if (!c->upload) {
        if (cmd != 0x60u)
            return client_abort(c, KD_SDO_ABORT_COMMAND, 1, KD_SDO_E_PROTOCOL, out, n_out);
        end(c, 1);
        return KD_SDO_DONE;
    }
    /* scs 2 with e = 1: expedited; s = 1: n says the unused bytes. */
    if ((cmd & 0xE0u) != 0x40u || !(cmd & 0x02u) || f->len < 8)
        return client_abort(c, KD_SDO_ABORT_COMMAND, 1, KD_SDO_E_PROTOCOL, out, n_out);
    int size = (cmd & 0x01u) ? 4 - (int)((cmd >> 2) & 0x03u) : 4;
    uint32_t value = get_u32(&f->data[4]);
    if (size < 4)
        value &= (1u << (8 * size)) - 1u;
    end(c, 1);
    c->value = value;
    c->size = size;
    return KD_SDO_DONE;
}

int kd_sdo_process(kd_sdo *c, uint32_t elapsed_us, struct can_frame *out, int *n_out)
{
    *n_out = 0;
    if (!c->busy)
        return KD_SDO_DONE;
    c->elapsed_us = elapsed_us >= c->timeout_us - c->elapsed_us ? c->timeout_us : c->elapsed_us + elapsed_us;
    if (c->elapsed_us < c->timeout_us)
        return KD_SDO_WAITING;
    if (c->sends >= KD_SDO_SENDS)
        return client_abort(c, KD_SDO_ABORT_TIMEOUT, 0, KD_SDO_E_TIMEOUT, out, n_out);
    request(c, 0x80u, KD_SDO_ABORT_TIMEOUT, &out[0]);
    send_request(c, &out[1]);
    c->sends++;
    c->elapsed_us = 0;
    *n_out = 2;
    return KD_SDO_WAITING;
}

const char *kd_sdo_abort_str(uint32_t code)
{
    static const struct {
        uint32_t code;
        const char *text;
    } codes[] = {
        {0x05030000u, "toggle bit not alternated"},
        {0x05040000u, "SDO protocol timed out"},
        {0x05040001u, "client/server command specifier not valid or unknown"},
        {0x05040005u, "out of memory"},
        {0x06010000u, "unsupported access to an object"},
        {0x06010001u, "attempt to read a write only object"},
        {0x06010002u, "attempt to write a read only object"},
        {0x06020000u, "object does not exist in the object dictionary"},
        {0x06040041u, "object cannot be mapped to the PDO"},
        {0x06040042u, "the number and length of the objects to be mapped would exceed PDO length"},
        {0x06040043u, "general parameter incompatibility reason"},
        {0x06040047u, "general internal incompatibility in the device"},
        {0x06060000u, "access failed due to a hardware error"},
        {0x06070010u, "data type does not match, length of service parameter does not match"},
        {0x06070012u, "data type does not match, length of service parameter too high"},
        {0x06070013u, "data type does not match, length of service parameter too low"},
        {0x06090011u, "sub-index does not exist"},
        {0x06090030u, "invalid value for parameter"},
        {0x06090031u, "value of parameter written too high"},
        {0x06090032u, "value of parameter written too low"},
        {0x06090036u, "maximum value is less than minimum value"},
        {0x060A0023u, "resource not available: SDO connection"},
        {0x08000000u, "general error"},
        {0x08000020u, "data cannot be transferred or stored to the application"},
        {0x08000021u, "data cannot be transferred or stored to the application because of local control"},
        {0x08000022u, "data cannot be transferred or stored to the application because of the present device state"},
        {0x08000023u, "object dictionary dynamic generation fails or no object dictionary is present"},
        {0x08000024u, "no data available"},
    };
    for (size_t i = 0; i < sizeof codes / sizeof codes[0]; i++)
        if (codes[i].code == code)
            return codes[i].text;
    return "unknown abort code";
}
