/* SPDX-License-Identifier: BSD-3-Clause */
/* can_bus.c - the bus cycle on the cycle thread (can_bus.h). */
#define _GNU_SOURCE /* sendmmsg */
#include "can_bus.h"

#include <errno.h>
#include <net/if.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <linux/can/error.h>
#include <linux/can/raw.h>

#include "can_frame.h"
#include "clock.h"

int kd_can_socket(const char *ifname, const struct can_filter *filters, int nf, can_err_mask_t err_mask, int rcvbuf,
                  const char **what)
{
    struct ifreq ifr;
    struct sockaddr_can addr;
    int fd, err;

    fd = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC | SOCK_NONBLOCK, CAN_RAW);
    if (fd < 0) {
        *what = "socket(PF_CAN)";
        return -errno;
    }
    memset(&ifr, 0, sizeof ifr);
    snprintf(ifr.ifr_name, sizeof ifr.ifr_name, "%s", ifname);
    if (ioctl(fd, SIOCGIFINDEX, &ifr) != 0) {
        err = errno;
        close(fd);
        *what = "no such interface";
        return -err;
    }
    if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, nf > 0 ? filters : NULL,
                   (socklen_t)(sizeof filters[0] * (size_t)nf)) != 0 ||
        setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) != 0) {
        err = errno;
        close(fd);
        *what = "setsockopt(CAN_RAW_FILTER)";
        return -err;
    }
    /* A large receive buffer (beyond rmem_max when permitted). */
    if (rcvbuf > 0 && setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf, sizeof rcvbuf) != 0)
        (void)setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = ifr.ifr_ifindex;
    if (bind(fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        err = errno;
        close(fd);
        *what = "bind";
        return -err;
    }
    return fd;
}

void kd_can_open_failed(const char *ifname, const char *what, int rc)
{
    fprintf(stderr, "kinctld: cannot open CAN interface \"%s\": %s: %s%s\n", ifname, what, strerror(-rc),
            rc == -EAFNOSUPPORT ? " (this kernel has no SocketCAN: load the can and can-raw modules)" : "");
}

int kd_can_send(int fd, const struct can_frame *frames, int count, int *err)
{
    struct mmsghdr msgs[KD_BUS_FRAMES_MAX];
    struct iovec iov[KD_BUS_FRAMES_MAX];
    int i, sent;
    if (count > KD_BUS_FRAMES_MAX)
        count = KD_BUS_FRAMES_MAX;
    memset(msgs, 0, sizeof msgs[0] * (size_t)count);
    for (i = 0; i < count; i++) {
        iov[i].iov_base = (void *)&frames[i];
        iov[i].iov_len = sizeof frames[i];
        msgs[i].msg_hdr.msg_iov = &iov[i];
        msgs[i].msg_hdr.msg_iovlen = 1;
    }
    /* sendmmsg stops at the first frame that fails and says why on the
     * next call: one more call for the rest learns it. */
    *err = 0;
    for (sent = 0; sent < count;) {
        int r = sendmmsg(fd, msgs + sent, (unsigned)(count - sent), MSG_DONTWAIT);
        if (r <= 0) {
            *err = r < 0 ? errno : EAGAIN;
            break;
        }
        sent += r;
    }
    return sent;
}

int kd_bus_init(kd_bus *b, const kd_can_cfg *cfg, int n)
{
    const char *what = "";
    int j, fd;
    b->cfg = cfg;
    b->n = n;
    b->fd = -1;
    atomic_init(&b->fd_next, -1);
    atomic_init(&b->fd_retired, -1);
    atomic_init(&b->active, 0);
    atomic_init(&b->paused, 0);
    for (j = 0; j < KC_MAX_JOINTS; j++)
        atomic_init(&b->controlword[j], 0u);
    atomic_init(&b->syncs, 0);
    atomic_init(&b->frames, 0);
    atomic_init(&b->dropped, 0);
    atomic_init(&b->errors, 0);
    atomic_init(&b->link_errno, 0);
    memset(b->target, 0, sizeof b->target);
    kd_hist_clear(&b->send_ns);
    fd = kd_can_socket(cfg->interface, NULL, 0, 0, 0, &what);
    if (fd < 0) {
        kd_can_open_failed(cfg->interface, what, fd);
        return -1;
    }
    b->fd = fd;
    return 0;
}

void kd_bus_close(kd_bus *b)
{
    int fd;
    if (b->fd >= 0)
        close(b->fd);
    b->fd = -1;
    fd = atomic_exchange(&b->fd_next, -1);
    if (fd >= 0)
        close(fd);
    fd = atomic_exchange(&b->fd_retired, -1);
    if (fd >= 0)
        close(fd);
}

void kd_bus_cycle(kd_bus *b, int64_t cycle, const kc_real *q, const kc_real *qd)
{
    struct can_frame frames[KD_BUS_FRAMES_MAX];
    const kd_can_cfg *cfg = b->cfg;
    int64_t t0, syncs;
    int j, count = 0, sent, err = 0;
    int next = atomic_load_explicit(&b->fd_next, memory_order_acquire);

    if (next >= 0) {
        /* A fresh socket from the I/O thread: the old one goes back to it. */
        atomic_store_explicit(&b->fd_next, -1, memory_order_relaxed);
        atomic_store_explicit(&b->fd_retired, b->fd, memory_order_release);
        b->fd = next;
    }
    if (!atomic_load_explicit(&b->active, memory_order_acquire) ||
        atomic_load_explicit(&b->paused, memory_order_relaxed) || b->fd < 0 || cycle % cfg->sync_every != 0)
        return;
    t0 = kd_now_ns();
    syncs = atomic_load_explicit(&b->syncs, memory_order_relaxed);
    kd_can_encode_sync(syncs, cfg->sync_counter, &frames[count++]);
    for (j = 0; j < b->n; j++) {
        uint16_t cw = (uint16_t)atomic_load_explicit(&b->controlword[j], memory_order_relaxed);
        kd_can_encode_rpdo(&cfg->joint[j], cw, (double)q[j], &frames[count++]);
        if (cfg->velocity_offset)
            kd_can_encode_rpdo2(&cfg->joint[j], (double)qd[j], &frames[count++]);
        b->target[syncs % KD_CAN_RING][j] = (double)q[j];
    }
    sent = kd_can_send(b->fd, frames, count, &err);
    atomic_fetch_add_explicit(&b->frames, sent, memory_order_relaxed);
    if (sent > 0) /* the SYNC went out: the drives answer it */
        atomic_store_explicit(&b->syncs, syncs + 1, memory_order_release);
    if (sent < count) {
        /* The rest of this bus cycle is dropped (never retried: it would
         * be stale). */
        atomic_fetch_add_explicit(&b->dropped, count - sent, memory_order_relaxed);
        atomic_fetch_add_explicit(&b->errors, 1, memory_order_relaxed);
        if (err == ENETDOWN || err == ENXIO || err == ENODEV)
            atomic_store_explicit(&b->link_errno, err, memory_order_release);
    }
    kd_hist_add(&b->send_ns, kd_now_ns() - t0);
}
