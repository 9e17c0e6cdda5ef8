/* SPDX-License-Identifier: BSD-3-Clause */
/* hist.c - log-linear histogram (hist.h). */
#include "hist.h"

#include <string.h>

void kd_hist_clear(kd_hist *h)
{
    memset(h, 0, sizeof *h);
}

static int top_bit(uint64_t v)
{
    int b = 0;
    while (v >>= 1)
        b++;
    return b;
}

static int bin_of(int64_t ns)
{
    uint64_t v;
    int e, sub, bin;
    if (ns < KD_HIST_LINEAR)
        return ns < 0 ? 0 : (int)ns;
    v = (uint64_t)ns;
    e = top_bit(v); /* >= 7 */
    sub = (int)((v >> (e - 6)) & (KD_HIST_SUB - 1));
    bin = KD_HIST_LINEAR + (e - 7) * KD_HIST_SUB + sub;
    return bin < KD_HIST_BINS ? bin : KD_HIST_BINS - 1;
}

/* Lower edge and width of a bin. */
static void bin_range(int bin, int64_t *lo, int64_t *width)
{
    int e, sub;
    if (bin < KD_HIST_LINEAR) {
        *lo = bin;
        *width = 1;
        return;
    }
    e = (bin - KD_HIST_LINEAR) / KD_HIST_SUB + 7;
    sub = (bin - KD_HIST_LINEAR) % KD_HIST_SUB;
    *lo = (int64_t)(KD_HIST_SUB + sub) << (e - 6);
    *width = (int64_t)1 << (e - 6);
}

void kd_hist_add(kd_hist *h, int64_t ns)
{
    if (ns < 0)
        ns = 0;
    h->bins[bin_of(ns)]++;
    h->count++;
    if (ns > h->max)
        h->max = ns;
}

int64_t kd_hist_percentile(const kd_hist *h, double p)
{
    int64_t rank, seen = 0, lo, width, v;
    int b;
    if (h->count <= 0)
        return 0;
    if (p < 0.0)
        p = 0.0;
    if (p > 1.0)
        p = 1.0;
    /* The smallest value with at least ceil(p * count) values at or below it. */
    rank = (int64_t)(p * (double)h->count);
    if ((double)rank < p * (double)h->count)
        rank++;
    if (rank < 1)
        rank = 1;
    for (b = 0; b < KD_HIST_BINS; b++) {
        seen += h->bins[b];
        if (seen >= rank)
            break;
    }
    if (b == KD_HIST_BINS)
        return h->max;
    bin_range(b, &lo, &width);
    v = lo + width / 2;
    return v < h->max ? v : h->max;
}
