/* SPDX-License-Identifier: BSD-3-Clause */
/* can_frame.c - encoding and decoding kinctld's CAN frames (can_frame.h). */
#include "can_frame.h"

#include <math.h>
#include <string.h>

static int32_t saturate(double x)
{
    if (!(x == x))
        return 0;
    if (x >= 2147483647.0)
        return INT32_MAX;
    if (x <= -2147483648.0)
        return INT32_MIN;
    return (int32_t)llround(x);
}

int32_t kd_can_pos_counts(const kd_can_joint *j, double q)
{
    return saturate((double)j->sign * q * j->counts_per_unit + (double)j->offset_counts);
}

int32_t kd_can_vel_counts(const kd_can_joint *j, double qd)
{
    return saturate((double)j->sign * qd * j->counts_per_unit);
}

static void put_i32(uint8_t *p, int32_t v)
{
    uint32_t u = (uint32_t)v;
    p[0] = (uint8_t)(u & 0xffu);
    p[1] = (uint8_t)((u >> 8) & 0xffu);
    p[2] = (uint8_t)((u >> 16) & 0xffu);
    p[3] = (uint8_t)((u >> 24) & 0xffu);
}

static int32_t get_i32(const uint8_t *p)
{
    uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    return (int32_t)u;
}

double kd_can_pos_of_counts(const kd_can_joint *j, int32_t counts)
{
    return ((double)counts - (double)j->offset_counts) / ((double)j->sign * j->counts_per_unit);
}

static void frame(struct can_frame *f, canid_t id, int len)
{
    memset(f, 0, sizeof *f);
    f->can_id = id;
    f->len = (uint8_t)len;
}

void kd_can_encode_sync(int64_t bus_cycle, int overflow, struct can_frame *f)
{
    frame(f, KD_CAN_SYNC_ID, overflow > 0 ? 1 : 0);
    if (overflow > 0)
        f->data[0] = (uint8_t)(bus_cycle % overflow + 1);
}

void kd_can_encode_rpdo(const kd_can_joint *j, uint16_t controlword, double q, struct can_frame *f)
{
    frame(f, KD_CAN_RPDO_BASE + (canid_t)j->node, KD_CAN_RPDO_LEN);
    f->data[0] = (uint8_t)(controlword & 0xffu);
    f->data[1] = (uint8_t)(controlword >> 8);
    put_i32(&f->data[2], kd_can_pos_counts(j, q));
}

void kd_can_encode_rpdo2(const kd_can_joint *j, double qd, struct can_frame *f)
{
    frame(f, KD_CAN_RPDO2_BASE + (canid_t)j->node, 4);
    put_i32(&f->data[0], kd_can_vel_counts(j, qd));
}

void kd_can_encode_heartbeat(int node, uint8_t state, struct can_frame *f)
{
    frame(f, KD_CAN_HEARTBEAT_BASE + (canid_t)node, 1);
    f->data[0] = state;
}

void kd_can_encode_nmt(uint8_t command, int node, struct can_frame *f)
{
    frame(f, KD_CAN_NMT_ID, 2);
    f->data[0] = command;
    f->data[1] = (uint8_t)node;
}

int kd_can_decode_tpdo(const kd_can_joint *j, const struct can_frame *f, double *q, uint16_t *statusword)
{
    if (f->len < KD_CAN_TPDO_LEN)
        return -1;
    *statusword = (uint16_t)(f->data[0] | f->data[1] << 8);
    *q = kd_can_pos_of_counts(j, get_i32(&f->data[2]));
    return 0;
}

int kd_can_decode_emcy(const struct can_frame *f, uint16_t *code, uint8_t *error_register)
{
    if (f->len < 3)
        return -1;
    *code = (uint16_t)(f->data[0] | f->data[1] << 8);
    *error_register = f->data[2];
    return 0;
}
