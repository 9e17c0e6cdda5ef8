/* SPDX-License-Identifier: BSD-3-Clause */
/* can_bus.h - the bus cycle, written by the cycle thread right after its
 * step: every sync_every-th tick, the SYNC, then each drive's RPDO1
 * (controlword, target position = the tick's setpoint) and RPDO2 (velocity
 * offset, where configured), in joint order, in one sendmmsg with
 * MSG_DONTWAIT on a socket of its own that nothing else writes to. So the
 * bus cycle's jitter is the cycle's wake-up jitter, and no work of the I/O
 * thread (publishing, dry runs, SDO) delays or bunches it.
 *
 * The I/O thread (can_io.h, can_master.h) steers it through atomics: active
 * (the master writes bus cycles only once the controller sits where the
 * drives are, can_master.h), and each drive's controlword. The cycle
 * publishes what went out: the SYNCs written and, for each, the targets
 * (a ring of KD_CAN_RING bus cycles, a row written before the count that
 * makes it visible), which the I/O thread compares with the drives'
 * actual positions (following error).
 *
 * A frame that does not go out is counted (EAGAIN, ENOBUFS: dropped) and
 * never retried. ENETDOWN, ENXIO or ENODEV is handed to the I/O thread
 * (link_errno), which takes the bus as lost (can_io.h), stops the bus
 * cycles and, once the interface is back, hands a fresh socket over
 * (fd_next; the cycle hands the old one back in fd_retired to be closed).
 */
#ifndef KINCTL_DAEMON_CAN_BUS_H
#define KINCTL_DAEMON_CAN_BUS_H

#include <stdatomic.h>
#include <stdint.h>

#include <linux/can.h>

#include "can_config.h"
#include "hist.h"

#define KD_CAN_RING 1024 /* bus cycles whose targets are kept */
#define KD_BUS_FRAMES_MAX (1 + 2 * KC_MAX_JOINTS)

typedef struct kd_bus {
    const kd_can_cfg *cfg;
    int n;                  /* drives */
    int fd;                 /* the cycle's socket, -1: none */
    atomic_int fd_next;     /* I/O -> cycle: a fresh socket (-1: none) */
    atomic_int fd_retired;  /* cycle -> I/O: the socket it replaced (-1: none) */
    atomic_int active;      /* 1: write bus cycles (the master's) */
    atomic_int paused;      /* 1: the bus is lost, write nothing (can_io's) */
    atomic_uint controlword[KC_MAX_JOINTS];
    atomic_llong syncs;     /* SYNCs written */
    double target[KD_CAN_RING][KC_MAX_JOINTS]; /* by SYNC number (joint units) */
    atomic_llong frames, dropped, errors;
    atomic_int link_errno;  /* the interface is gone (taken by the I/O thread) */
    kd_hist send_ns;        /* the cycle's; read once it has stopped */
} kd_bus;

/* A raw CAN socket on interface ifname, non-blocking, with the receive
 * filters given (nf 0: receives nothing) and the error classes err_mask,
 * its receive buffer at least rcvbuf bytes where permitted (0: as it is).
 * Returns the descriptor, or -errno with *what naming the step that
 * failed. */
int kd_can_socket(const char *ifname, const struct can_filter *filters, int nf, can_err_mask_t err_mask, int rcvbuf,
                  const char **what);

/* "kinctld: cannot open CAN interface ..." on stderr for kd_can_socket's
 * failure rc at step what. */
void kd_can_open_failed(const char *ifname, const char *what, int rc);

/* Writes frames[0..count) on fd without blocking, in as few calls as it
 * can. Returns how many went out; when not all, *err says why (EAGAIN,
 * ENOBUFS, ENETDOWN...). The rest is never retried. */
int kd_can_send(int fd, const struct can_frame *frames, int count, int *err);

/* Sets b up for cfg's n drives, inactive, with its socket open (sends
 * only: it receives nothing). Returns 0, or -1 with a message on stderr.
 * Main thread. */
int kd_bus_init(kd_bus *b, const kd_can_cfg *cfg, int n);

void kd_bus_close(kd_bus *b);

/* The cycle thread, after the step of cycle: a bus cycle when active and
 * cycle is a multiple of sync_every (q, qd: the setpoint). */
void kd_bus_cycle(kd_bus *b, int64_t cycle, const kc_real *q, const kc_real *qd);

#endif
