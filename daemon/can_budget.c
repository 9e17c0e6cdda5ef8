/* SPDX-License-Identifier: BSD-3-Clause */
/* can_budget.c - bus time of a bus cycle (can_budget.h). */
#include "can_budget.h"

#include <stdio.h>

int kd_can_frame_bits(int n)
{
    if (n < 0 || n > 8)
        return -1;
    /* Davis et al. 2007, eq. 1, with g = 34 for an 11-bit identifier. */
    return 47 + 8 * n + (34 + 8 * n - 1) / 4;
}

kd_can_budget kd_can_budget_default(void)
{
    kd_can_budget b = {0};
    b.bitrate = 1000000;
    b.sync_every = 1;
    b.sync_bytes = 0;
    b.share = KD_CAN_BUDGET_SHARE_DEFAULT;
    return b;
}

static int bad(char *why, size_t why_size, const char *what)
{
    if (why_size > 0)
        snprintf(why, why_size, "bus budget: %s", what);
    return -1;
}

static int drive_bad(const kd_can_budget_drive *d)
{
    if (d->n_rpdo < 0 || d->n_rpdo > KD_CAN_BUDGET_PDOS || d->n_tpdo < 0 || d->n_tpdo > KD_CAN_BUDGET_PDOS)
        return 1;
    for (int k = 0; k < d->n_rpdo; k++)
        if (kd_can_frame_bits(d->rpdo_bytes[k]) < 0)
            return 1;
    for (int k = 0; k < d->n_tpdo; k++)
        if (kd_can_frame_bits(d->tpdo_bytes[k]) < 0 || d->tpdo_every[k] < 1 || d->tpdo_every[k] > 240)
            return 1;
    return 0;
}

/* Bits of one drive's frames in a bus cycle: peak and mean. */
static void drive_bits(const kd_can_budget_drive *d, int64_t *peak, double *mean)
{
    *peak = 0;
    *mean = 0.0;
    for (int k = 0; k < d->n_rpdo; k++) {
        *peak += kd_can_frame_bits(d->rpdo_bytes[k]);
        *mean += kd_can_frame_bits(d->rpdo_bytes[k]);
    }
    for (int k = 0; k < d->n_tpdo; k++) {
        *peak += kd_can_frame_bits(d->tpdo_bytes[k]);
        *mean += (double)kd_can_frame_bits(d->tpdo_bytes[k]) / (double)d->tpdo_every[k];
    }
}

int kd_can_budget_check(const kd_can_budget *b, kd_can_budget_use *use, char *why, size_t why_size)
{
    if (b->bitrate <= 0)
        return bad(why, why_size, "bitrate must be > 0 bit/s");
    if (b->period_ns <= 0 || b->sync_every < 1)
        return bad(why, why_size, "the period must be > 0 and sync_every >= 1");
    if (b->sync_bytes != 0 && b->sync_bytes != 1)
        return bad(why, why_size, "a SYNC has 0 or 1 byte");
    if (!(b->share > 0.0 && b->share <= 1.0))
        return bad(why, why_size, "the share must be in (0, 1]");
    if (b->n_drives < 1 || b->n_drives > KC_MAX_JOINTS)
        return bad(why, why_size, "no drives, or more than KC_MAX_JOINTS");
    for (int i = 0; i < b->n_drives; i++)
        if (drive_bad(&b->drive[i]))
            return bad(why, why_size, "a PDO of 0..8 bytes, 0..2 PDOs per drive, TPDOs every 1..240 SYNCs");

    kd_can_budget_use u;
    double ns_per_bit = 1e9 / (double)b->bitrate;
    int64_t sync_bits = kd_can_frame_bits(b->sync_bytes);
    u.peak_bits = sync_bits;
    u.mean_bits = (double)sync_bits;
    double worst_drive = 0.0; /* the drive with the most mean bits */
    for (int i = 0; i < b->n_drives; i++) {
        int64_t peak;
        double mean;
        drive_bits(&b->drive[i], &peak, &mean);
        u.peak_bits += peak;
        u.mean_bits += mean;
        if (mean > worst_drive)
            worst_drive = mean;
    }
    u.cycle_ns = b->period_ns * b->sync_every;
    u.peak_ns = (double)u.peak_bits * ns_per_bit;
    u.mean_ns = u.mean_bits * ns_per_bit;
    u.peak_share = u.peak_ns / (double)u.cycle_ns;
    u.mean_share = u.mean_ns / (double)u.cycle_ns;
    *use = u;
    if (u.mean_share <= b->share)
        return 0;

    /* What would fit: drives like the busiest one in this bus cycle; the
     * smallest sync_every; every drive's TPDOs every N-th SYNC. */
    double budget_bits = b->share * (double)u.cycle_ns / ns_per_bit;
    int fit_drives = worst_drive > 0.0 ? (int)((budget_bits - (double)sync_bits) / worst_drive) : 0;
    if (fit_drives < 0)
        fit_drives = 0;
    double need_ns = u.mean_ns / b->share;
    int64_t every = (int64_t)(need_ns / (double)b->period_ns);
    while ((double)(every * b->period_ns) < need_ns)
        every++;
    double rpdo_bits = (double)sync_bits, tpdo_bits = 0.0;
    for (int i = 0; i < b->n_drives; i++) {
        const kd_can_budget_drive *d = &b->drive[i];
        for (int k = 0; k < d->n_rpdo; k++)
            rpdo_bits += kd_can_frame_bits(d->rpdo_bytes[k]);
        for (int k = 0; k < d->n_tpdo; k++)
            tpdo_bits += kd_can_frame_bits(d->tpdo_bytes[k]);
    }
    int tpdo_every = 0; /* 0: TPDOs alone cannot make it fit */
    for (int n = 1; n <= 240 && rpdo_bits < budget_bits; n++)
        if (rpdo_bits + tpdo_bits / n <= budget_bits) {
            tpdo_every = n;
            break;
        }
    if (why_size > 0) {
        int len = snprintf(why, why_size,
                           "bus budget: %d drives need %.0f us of a %.0f us bus cycle at %lld bit/s (%.1f %%, "
                           "peak %.1f %%), above %.0f %%; would fit: %d drives, or sync_every %lld (a %.0f us bus "
                           "cycle)",
                           b->n_drives, u.mean_ns / 1e3, (double)u.cycle_ns / 1e3, (long long)b->bitrate,
                           100.0 * u.mean_share, 100.0 * u.peak_share, 100.0 * b->share, fit_drives,
                           (long long)every, (double)(every * b->period_ns) / 1e3);
        if (len >= 0 && (size_t)len < why_size) {
            if (tpdo_every)
                snprintf(why + len, why_size - (size_t)len, ", or TPDOs every %d SYNCs (tpdo_every = %d)", tpdo_every,
                         tpdo_every);
            else
                snprintf(why + len, why_size - (size_t)len, ", and TPDOs less often cannot make it fit");
        }
    }
    return 1;
}
