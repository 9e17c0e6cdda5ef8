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

void kd_can_encode_sync(int64_t bus_cycle, struct can_frame *f)
{
    memset(f, 0, sizeof *f);
    f->can_id = KD_CAN_SYNC_ID;
    f->len = 1;
    f->data[0] = (uint8_t)(bus_cycle % KD_CAN_SYNC_COUNTER_MAX + 1);
}

void kd_can_encode_rpdo(const kd_can_joint *j, double q, double qd, struct can_frame *f)
{
    memset(f, 0, sizeof *f);
    f->can_id = KD_CAN_RPDO_BASE + (canid_t)j->node;
    f->len = 8;
    put_i32(&f->data[0], kd_can_pos_counts(j, q));
    put_i32(&f->data[4], kd_can_vel_counts(j, qd));
}

void kd_can_encode_heartbeat(int node, uint8_t state, struct can_frame *f)
{
    memset(f, 0, sizeof *f);
    f->can_id = KD_CAN_HEARTBEAT_BASE + (canid_t)node;
    f->len = 1;
    f->data[0] = state;
}

int kd_can_decode_tpdo(const kd_can_joint *j, const struct can_frame *f, double *q, uint16_t *statusword)
{
    if (f->len < 6)
        return -1;
    *q = ((double)get_i32(&f->data[0]) - (double)j->offset_counts) / ((double)j->sign * j->counts_per_unit);
    *statusword = (uint16_t)(f->data[4] | f->data[5] << 8);
    return 0;
}
