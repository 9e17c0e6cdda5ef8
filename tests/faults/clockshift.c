/* SPDX-License-Identifier: BSD-3-Clause */
/* clockshift.c - an LD_PRELOAD library for the fault tests that moves the
 * wall clock of one process while it runs: CLOCK_REALTIME (clock_gettime,
 * gettimeofday, time) reads the real clock plus an offset in nanoseconds
 * that the test writes, as a native int64, into the file named by
 * $KINCTL_CLOCKSHIFT_FILE (mapped shared, so a new value applies at once).
 * Every other clock is left alone: the daemon's cycle and staleness must
 * depend on CLOCK_MONOTONIC only, and this is how the tests show it. */
#define _GNU_SOURCE /* RTLD_NEXT */
#include <dlfcn.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

typedef int (*clock_gettime_fn)(clockid_t, struct timespec *);

static volatile const int64_t *offset_ns;
static clock_gettime_fn real_clock_gettime;

static void setup(void)
{
    if (real_clock_gettime != NULL)
        return;
    real_clock_gettime = (clock_gettime_fn)dlsym(RTLD_NEXT, "clock_gettime");
    const char *path = getenv("KINCTL_CLOCKSHIFT_FILE");
    int fd = path != NULL ? open(path, O_RDONLY) : -1;
    if (fd >= 0) {
        void *p = mmap(NULL, sizeof(int64_t), PROT_READ, MAP_SHARED, fd, 0);
        if (p != MAP_FAILED)
            offset_ns = p;
        close(fd);
    }
}

int clock_gettime(clockid_t clk, struct timespec *ts)
{
    setup();
    int rc = real_clock_gettime(clk, ts);
    if (rc == 0 && clk == CLOCK_REALTIME && offset_ns != NULL) {
        int64_t ns = (int64_t)ts->tv_sec * 1000000000 + ts->tv_nsec + *offset_ns;
        ts->tv_sec = (time_t)(ns / 1000000000);
        ts->tv_nsec = (long)(ns % 1000000000);
        if (ts->tv_nsec < 0) {
            ts->tv_nsec += 1000000000;
            ts->tv_sec--;
        }
    }
    return rc;
}

int gettimeofday(struct timeval *restrict tv, void *restrict tz)
{
    struct timespec ts;
    (void)tz;
    if (clock_gettime(CLOCK_REALTIME, &ts) != 0)
        return -1;
    tv->tv_sec = ts.tv_sec;
    tv->tv_usec = ts.tv_nsec / 1000;
    return 0;
}

time_t time(time_t *t)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    if (t != NULL)
        *t = ts.tv_sec;
    return ts.tv_sec;
}
