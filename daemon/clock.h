/* SPDX-License-Identifier: BSD-3-Clause */
/* clock.h - kinctld's time base: CLOCK_MONOTONIC in integer ns, for
 * deadlines, staleness and durations alike (never the sender's clock).
 *
 * kd_now_ns reads the clock and nothing else: safe for the cycle.
 */
#ifndef KINCTL_DAEMON_CLOCK_H
#define KINCTL_DAEMON_CLOCK_H

#include <stdint.h>
#include <time.h>

/* ns per s. */
#define KD_NS 1000000000LL

/* CLOCK_MONOTONIC in ns. */
static inline int64_t kd_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * KD_NS + ts.tv_nsec;
}

#endif
