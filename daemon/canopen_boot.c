/* SPDX-License-Identifier: BSD-3-Clause */
/* canopen_boot.c - a drive's boot and configuration (canopen_boot.h). */
#include "canopen_boot.h"

#include <stdio.h>
#include <string.h>

enum { PH_IDLE, PH_WAIT_BOOT, PH_REQUEST, PH_READBACK, PH_END };

#define COB_VALID_MASK 0x800007FFu
#define COB_INVALID 0x80000000u

kd_boot_cfg kd_boot_cfg_default(int node)
{
    kd_boot_cfg c;
    memset(&c, 0, sizeof c);
    c.node = node;
    c.reset_communication = 1;
    c.configure = 1;
    c.device_type = 0x00000192u;
    c.device_type_mask = 0x0000FFFFu;
    c.n_rpdo = 1;
    c.rpdo[0].n_map = 2;
    c.rpdo[0].map[0] = 0x60400010u;
    c.rpdo[0].map[1] = 0x607A0020u;
    c.rpdo[0].transmission_type = 1;
    c.n_tpdo = 1;
    c.tpdo[0].n_map = 2;
    c.tpdo[0].map[0] = 0x60410010u;
    c.tpdo[0].map[1] = 0x60640020u;
    c.tpdo[0].transmission_type = 1;
    c.interpolation_us = 1000;
    c.sync_overflow = -1;
    c.heartbeat_ms = 100;
    c.master_id = 127;
    c.consumer_ms = 500;
    c.lost_master_reaction = 3;
    c.bootup_timeout_us = 5000000;
    c.sdo_timeout_us = 500000;
    return c;
}

int kd_boot_interpolation(uint32_t us, uint8_t *value, int8_t *index)
{
    /* value * 10^index s = us * 10^-6 s: divide by ten while exact, up
     * to milliseconds (index -3, what drives support most), further only
     * while the value exceeds a byte */
    int idx = -6;
    while (us % 10 == 0 && us != 0 && (idx < -3 || (us > 255 && idx < 0))) {
        us /= 10;
        idx++;
    }
    if (us > 255)
        return -1;
    *value = (uint8_t)us;
    *index = (int8_t)idx;
    return 0;
}

static uint32_t size_mask(int size)
{
    return size >= 4 ? 0xFFFFFFFFu : (1u << (8 * size)) - 1u;
}

typedef struct table {
    kd_boot_step *s;
    int n;
    int bad;
} table;

static kd_boot_step *add(table *t, int write, uint16_t index, uint8_t sub, int size, uint32_t value, uint32_t mask,
                         const char *what)
{
    static kd_boot_step spare;
    if (t->n >= KD_BOOT_STEPS_MAX) {
        t->bad = 1;
        return &spare;
    }
    kd_boot_step *s = &t->s[t->n++];
    s->optional = 0;
    s->write = write;
    s->index = index;
    s->subindex = sub;
    s->size = (uint8_t)size;
    s->value = value & size_mask(size);
    s->mask = mask;
    s->what = what;
    return s;
}

static void put(table *t, uint16_t index, uint8_t sub, int size, uint32_t value, const char *what)
{
    add(t, 1, index, sub, size, value, size_mask(size), what);
}

static int pdo_bad(const kd_boot_pdo *p)
{
    int bits = 0;
    if (p->n_map < 0 || p->n_map > KD_BOOT_MAP_MAX)
        return 1;
    for (int i = 0; i < p->n_map; i++)
        bits += (int)(p->map[i] & 0xFFu);
    if (bits > 64)
        return 1;
    return !(p->transmission_type >= 0 && p->transmission_type <= 240) && p->transmission_type != 254 &&
           p->transmission_type != 255;
}

/* Step 3 for one PDO: CiA 301's order. */
static void pdo_steps(table *t, uint16_t comm, uint16_t map, uint32_t cob, const kd_boot_pdo *p, const char *const *what)
{
    add(t, 1, comm, 1, 4, COB_INVALID | cob, COB_VALID_MASK, what[0]);
    put(t, comm, 2, 1, (uint32_t)p->transmission_type, what[1]);
    put(t, map, 0, 1, 0, what[2]);
    for (int i = 0; i < p->n_map; i++)
        put(t, map, (uint8_t)(i + 1), 4, p->map[i], what[3]);
    put(t, map, 0, 1, (uint32_t)p->n_map, what[4]);
    add(t, 1, comm, 1, 4, cob, COB_VALID_MASK, what[5]);
}

static const char *const rpdo_what[KD_BOOT_PDOS][6] = {
    {"RPDO1 COB-ID (invalid)", "RPDO1 transmission type", "RPDO1 mapping cleared", "RPDO1 mapping entry",
     "RPDO1 number of entries", "RPDO1 COB-ID (valid)"},
    {"RPDO2 COB-ID (invalid)", "RPDO2 transmission type", "RPDO2 mapping cleared", "RPDO2 mapping entry",
     "RPDO2 number of entries", "RPDO2 COB-ID (valid)"},
};
static const char *const tpdo_what[KD_BOOT_PDOS][6] = {
    {"TPDO1 COB-ID (invalid)", "TPDO1 transmission type", "TPDO1 mapping cleared", "TPDO1 mapping entry",
     "TPDO1 number of entries", "TPDO1 COB-ID (valid)"},
    {"TPDO2 COB-ID (invalid)", "TPDO2 transmission type", "TPDO2 mapping cleared", "TPDO2 mapping entry",
     "TPDO2 number of entries", "TPDO2 COB-ID (valid)"},
};

static int build(const kd_boot_cfg *c, kd_boot_step *steps)
{
    static const char *const identity_what[4] = {"vendor-ID", "product code", "revision number", "serial number"};
    table t = {steps, 0, 0};
    uint32_t node = (uint32_t)c->node;
    add(&t, 0, 0x1000, 0, 4, c->device_type, c->device_type_mask, "device type");
    for (int i = 0; i < 4; i++)
        if (c->identity[i])
            add(&t, 0, 0x1018, (uint8_t)(i + 1), 4, c->identity[i], 0xFFFFFFFFu, identity_what[i]);
    if (!c->configure)
        return t.bad ? -1 : t.n;
    for (int k = 0; k < c->n_rpdo; k++)
        pdo_steps(&t, (uint16_t)(0x1400 + k), (uint16_t)(0x1600 + k), 0x200u + 0x100u * (uint32_t)k + node, &c->rpdo[k],
                  rpdo_what[k]);
    for (int k = 0; k < c->n_tpdo; k++)
        pdo_steps(&t, (uint16_t)(0x1800 + k), (uint16_t)(0x1A00 + k), 0x180u + 0x100u * (uint32_t)k + node, &c->tpdo[k],
                  tpdo_what[k]);
    for (int k = c->n_rpdo; k < 4; k++)
        add(&t, 1, (uint16_t)(0x1400 + k), 1, 4, COB_INVALID | (0x200u + 0x100u * (uint32_t)k + node), COB_VALID_MASK,
            "unused RPDO COB-ID (invalid)")->optional = 1;
    for (int k = c->n_tpdo; k < 4; k++)
        add(&t, 1, (uint16_t)(0x1800 + k), 1, 4, COB_INVALID | (0x180u + 0x100u * (uint32_t)k + node), COB_VALID_MASK,
            "unused TPDO COB-ID (invalid)")->optional = 1;
    put(&t, 0x6060, 0, 1, 8, "modes of operation");
    if (c->interpolation_us) {
        uint8_t value;
        int8_t index;
        if (kd_boot_interpolation(c->interpolation_us, &value, &index))
            return -1;
        put(&t, 0x60C2, 1, 1, value, "interpolation time period value");
        put(&t, 0x60C2, 2, 1, (uint32_t)(int32_t)index, "interpolation time index");
    }
    if (c->sync_overflow >= 0) {
        add(&t, 1, 0x1006, 0, 4, 0, 0xFFFFFFFFu, "communication cycle period (0 while 0x1019 changes)")->optional = 1;
        put(&t, 0x1019, 0, 1, (uint32_t)c->sync_overflow, "synchronous counter overflow value");
    }
    if (c->cycle_period_us)
        put(&t, 0x1006, 0, 4, c->cycle_period_us, "communication cycle period");
    put(&t, 0x1017, 0, 2, c->heartbeat_ms, "producer heartbeat time");
    if (c->consumer_ms)
        put(&t, 0x1016, 1, 4, (uint32_t)c->master_id << 16 | c->consumer_ms, "consumer heartbeat time");
    if (c->lost_master_reaction >= 0)
        put(&t, 0x6007, 0, 2, (uint32_t)c->lost_master_reaction, "abort connection option code");
    for (int i = 0; i < c->n_extra; i++)
        put(&t, c->extra[i].index, c->extra[i].subindex, c->extra[i].size, c->extra[i].value, "configured write");
    return t.bad ? -1 : t.n;
}

int kd_boot_init(kd_boot *b, const kd_boot_cfg *cfg)
{
    const kd_boot_cfg *c = cfg;
    if (c->node < 1 || c->node > 127 || c->master_id < 1 || c->master_id > 127 || c->bootup_timeout_us == 0 ||
        c->sdo_timeout_us == 0)
        return KD_BOOT_E_ARG;
    if (c->n_rpdo < 0 || c->n_rpdo > KD_BOOT_PDOS || c->n_tpdo < 0 || c->n_tpdo > KD_BOOT_PDOS ||
        c->n_extra < 0 || c->n_extra > KD_BOOT_EXTRA_MAX)
        return KD_BOOT_E_ARG;
    for (int k = 0; k < c->n_rpdo; k++)
        if (pdo_bad(&c->rpdo[k]))
            return KD_BOOT_E_ARG;
    for (int k = 0; k < c->n_tpdo; k++)
        if (pdo_bad(&c->tpdo[k]))
            return KD_BOOT_E_ARG;
    for (int i = 0; i < c->n_extra; i++)
        if (c->extra[i].size < 1 || c->extra[i].size > 4)
            return KD_BOOT_E_ARG;
    if (c->sync_overflow > 240 || c->sync_overflow == 1 || c->lost_master_reaction > 32767)
        return KD_BOOT_E_ARG;
    kd_boot_step steps[KD_BOOT_STEPS_MAX];
    int n = build(c, steps);
    if (n < 0)
        return KD_BOOT_E_ARG;
    memset(b, 0, sizeof *b);
    b->cfg = *c;
    memcpy(b->step, steps, sizeof steps);
    b->n_steps = n;
    b->phase = PH_IDLE;
    b->result = KD_BOOT_WAITING;
    (void)kd_sdo_init(&b->sdo, c->node, c->sdo_timeout_us);
    return 0;
}

static void nmt(const kd_boot *b, uint8_t command, struct can_frame *out)
{
    memset(out, 0, sizeof *out);
    out->can_id = KD_NMT_ID;
    out->len = 2;
    out->data[0] = command;
    out->data[1] = (uint8_t)b->cfg.node;
}

static int end(kd_boot *b, int result)
{
    b->phase = PH_END;
    b->result = result;
    return result;
}

/* Sends the request of step b->at, or NMT start after the last. */
static int request(kd_boot *b, struct can_frame *out, int *n_out)
{
    if (b->at >= b->n_steps) {
        nmt(b, KD_NMT_START, &out[*n_out]);
        (*n_out)++;
        return end(b, KD_BOOT_DONE);
    }
    const kd_boot_step *s = &b->step[b->at];
    if (s->write)
        (void)kd_sdo_download(&b->sdo, s->index, s->subindex, s->value, s->size, &out[*n_out]);
    else
        (void)kd_sdo_upload(&b->sdo, s->index, s->subindex, &out[*n_out]);
    (*n_out)++;
    b->phase = s->write ? PH_REQUEST : PH_READBACK;
    return KD_BOOT_WAITING;
}

int kd_boot_start(kd_boot *b, struct can_frame *out, int *n_out)
{
    *n_out = 0;
    b->waited_us = 0;
    b->at = 0;
    b->phase = PH_WAIT_BOOT;
    b->result = KD_BOOT_WAITING;
    if (b->cfg.reset_communication) {
        nmt(b, KD_NMT_RESET_COMMUNICATION, &out[0]);
        *n_out = 1;
    }
    return KD_BOOT_WAITING;
}

static int sdo_failed(kd_boot *b, int r)
{
    return end(b, r == KD_SDO_E_ABORTED ? KD_BOOT_E_ABORTED : KD_BOOT_E_SDO);
}

int kd_boot_rx(kd_boot *b, const struct can_frame *f, struct can_frame *out, int *n_out)
{
    *n_out = 0;
    if (b->phase == PH_END || b->phase == PH_IDLE)
        return b->result;
    if (f->can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG))
        return KD_BOOT_WAITING;
    if (b->phase == PH_WAIT_BOOT) {
        if (f->can_id != KD_HEARTBEAT_BASE + (canid_t)b->cfg.node || f->len < 1)
            return KD_BOOT_WAITING;
        uint8_t state = f->data[0];
        if (state != 0x00u && b->cfg.reset_communication)
            return KD_BOOT_WAITING; /* a heartbeat from before the reset */
        if (state == 0x04u || state == 0x05u) {
            nmt(b, KD_NMT_ENTER_PRE_OPERATIONAL, &out[0]);
            *n_out = 1;
        }
        return request(b, out, n_out);
    }
    int n_sdo;
    int r = kd_sdo_rx(&b->sdo, f, &out[0], &n_sdo);
    *n_out = n_sdo;
    if (r == KD_SDO_IGNORED)
        return KD_BOOT_WAITING;
    const kd_boot_step *s = &b->step[b->at];
    if (r == KD_SDO_E_ABORTED && s->optional) {
        b->at++; /* the drive has no such object, or keeps it: left as it is */
        return request(b, out, n_out);
    }
    if (r != KD_SDO_DONE)
        return sdo_failed(b, r);
    if (b->phase == PH_REQUEST) {
        /* written: read it back */
        (void)kd_sdo_upload(&b->sdo, s->index, s->subindex, &out[0]);
        *n_out = 1;
        b->phase = PH_READBACK;
        return KD_BOOT_WAITING;
    }
    if ((b->sdo.value & s->mask) != (s->value & s->mask) && !s->optional) {
        b->got = b->sdo.value;
        return end(b, KD_BOOT_E_MISMATCH);
    }
    b->at++;
    return request(b, out, n_out);
}

int kd_boot_process(kd_boot *b, uint32_t elapsed_us, struct can_frame *out, int *n_out)
{
    *n_out = 0;
    if (b->phase == PH_END || b->phase == PH_IDLE)
        return b->result;
    if (b->phase == PH_WAIT_BOOT) {
        b->waited_us = elapsed_us >= b->cfg.bootup_timeout_us - b->waited_us ? b->cfg.bootup_timeout_us
                                                                               : b->waited_us + elapsed_us;
        return b->waited_us >= b->cfg.bootup_timeout_us ? end(b, KD_BOOT_E_NO_BOOTUP) : KD_BOOT_WAITING;
    }
    int r = kd_sdo_process(&b->sdo, elapsed_us, &out[0], n_out);
    return r == KD_SDO_WAITING ? KD_BOOT_WAITING : sdo_failed(b, r);
}

void kd_boot_why(const kd_boot *b, char *buf, size_t size)
{
    if (size == 0)
        return;
    buf[0] = '\0';
    if (b->phase != PH_END || b->result >= 0)
        return;
    int node = b->cfg.node;
    if (b->result == KD_BOOT_E_NO_BOOTUP) {
        snprintf(buf, size, "node %d: no %s within %u ms", node,
                 b->cfg.reset_communication ? "boot-up after NMT reset communication" : "boot-up or heartbeat",
                 b->cfg.bootup_timeout_us / 1000u);
        return;
    }
    const kd_boot_step *s = &b->step[b->at];
    if (b->result == KD_BOOT_E_MISMATCH) {
        if (s->write)
            snprintf(buf, size, "node %d: 0x%04X:%02X (%s) reads back 0x%08X after writing 0x%08X", node, s->index,
                     s->subindex, s->what, b->got, s->value);
        else
            snprintf(buf, size, "node %d: 0x%04X:%02X (%s) is 0x%08X, expected 0x%08X under mask 0x%08X", node,
                     s->index, s->subindex, s->what, b->got, s->value, s->mask);
        return;
    }
    const char *op = !s->write ? "SDO read" : b->sdo.upload ? "SDO read-back" : "SDO write";
    int n = snprintf(buf, size, "node %d: %s 0x%04X:%02X (%s) %s 0x%08X: %s", node, op, s->index, s->subindex,
                     s->what, b->result == KD_BOOT_E_ABORTED ? "aborted by the drive with" : "aborted by the master with",
                     b->sdo.abort_code, kd_sdo_abort_str(b->sdo.abort_code));
    if (b->sdo.abort_code == KD_SDO_ABORT_TIMEOUT && b->result == KD_BOOT_E_SDO && n > 0 && (size_t)n < size)
        snprintf(buf + n, size - (size_t)n, ", sent %d times", b->sdo.sends);
}
