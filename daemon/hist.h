/* SPDX-License-Identifier: BSD-3-Clause */
/* hist.h - a fixed-size log-linear histogram of durations in ns, for the
 * cycle thread's wake-up latency and compute time.
 *
 * Values below 128 ns have a bin each; above, every power of two is split
 * into 64 bins, so a percentile read back is within 1/64 (1.6 %) of the
 * true value, up to 2^37 ns (137 s; larger values fall in the last bin; the
 * maximum is kept exactly). The storage is inside the struct: no
 * allocation. kd_hist_add is a few integer operations: safe for the cycle.
 *
 * Not thread-safe by itself: the cycle thread writes one histogram while
 * the I/O thread reads the other of a pair (see kd_cycle in cycle.h).
 */
#ifndef KINCTL_DAEMON_HIST_H
#define KINCTL_DAEMON_HIST_H

#include <stdint.h>

#define KD_HIST_LINEAR 128
#define KD_HIST_SUB 64
#define KD_HIST_OCTAVES 30 /* 2^7 .. 2^37 ns */
#define KD_HIST_BINS (KD_HIST_LINEAR + KD_HIST_OCTAVES * KD_HIST_SUB)

typedef struct kd_hist {
    uint32_t bins[KD_HIST_BINS];
    int64_t count;
    int64_t max;
} kd_hist;

void kd_hist_clear(kd_hist *h);

/* Adds one value (ns); negative values count as 0. */
void kd_hist_add(kd_hist *h, int64_t ns);

/* The value (ns) below which a fraction p (0..1) of the values lie: the
 * middle of the bin that holds it, never above the maximum. 0 when empty. */
int64_t kd_hist_percentile(const kd_hist *h, double p);

#endif
