/* SPDX-License-Identifier: BSD-3-Clause */
/* can_io.c - the CAN output (can_io.h). */
#define _GNU_SOURCE /* sendmmsg */
#include "can_io.h"
#include "can_frame.h"
#include "clock.h"

#include <errno.h>
#include <math.h>
#include <net/if.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>

#define KD_CAN_PROBE_NS 100000000LL      /* a lost interface is probed every 100 ms */
#define KD_CAN_RCVBUF (8 << 20)          /* feedback must wait in the socket, not be dropped */
#define KD_CAN_RX_BURST 1024             /* frames read per call */
#define KD_CAN_FRAMES_MAX (1 + KC_MAX_JOINTS)

/* Opens, filters and binds the socket. Returns 0 or -errno with *what set. */
static int open_socket(kd_can *c, const char **what)
{
    const kd_can_cfg *cfg = c->cfg;
    struct ifreq ifr;
    struct sockaddr_can addr;
    struct can_filter filters[2 * KC_MAX_JOINTS];
    can_err_mask_t err_mask = CAN_ERR_MASK;
    int fd, j, nf = 0, rcvbuf = KD_CAN_RCVBUF, err;

    fd = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC | SOCK_NONBLOCK, CAN_RAW);
    if (fd < 0) {
        *what = "socket(PF_CAN)";
        return -errno;
    }
    memset(&ifr, 0, sizeof ifr);
    snprintf(ifr.ifr_name, sizeof ifr.ifr_name, "%s", cfg->interface);
    if (ioctl(fd, SIOCGIFINDEX, &ifr) != 0) {
        err = errno;
        close(fd);
        *what = "no such interface";
        return -err;
    }
    /* Only the drives' feedback reaches this socket: a flood of foreign
     * frames is dropped by the kernel's filter, not read here. */
    memset(filters, 0, sizeof filters);
    if (cfg->feedback) {
        for (j = 0; j < c->n; j++) {
            filters[nf].can_id = KD_CAN_TPDO_BASE + (canid_t)cfg->joint[j].node;
            filters[nf++].can_mask = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
            filters[nf].can_id = KD_CAN_HEARTBEAT_BASE + (canid_t)cfg->joint[j].node;
            filters[nf++].can_mask = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
        }
    }
    if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, nf > 0 ? filters : NULL, (socklen_t)(sizeof filters[0] * (size_t)nf)) != 0 ||
        setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) != 0) {
        err = errno;
        close(fd);
        *what = "setsockopt(CAN_RAW_FILTER)";
        return -err;
    }
    /* A large receive buffer (beyond rmem_max when permitted). */
    if (setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf, sizeof rcvbuf) != 0)
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
    c->fd = fd;
    return 0;
}

/* IFF_UP and IFF_RUNNING. */
static int link_ok(const kd_can *c)
{
    struct ifreq ifr;
    int fd = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW), ok = 0;
    if (fd < 0)
        return 0;
    memset(&ifr, 0, sizeof ifr);
    snprintf(ifr.ifr_name, sizeof ifr.ifr_name, "%s", c->cfg->interface);
    if (ioctl(fd, SIOCGIFFLAGS, &ifr) == 0)
        ok = (ifr.ifr_flags & IFF_UP) && (ifr.ifr_flags & IFF_RUNNING);
    close(fd);
    return ok;
}

static void lose(kd_can *c, int64_t now, const char *fmt, const char *detail)
{
    if (c->state != KD_CAN_OK)
        return;
    c->state = KD_CAN_LOST;
    c->state_changed = 1;
    snprintf(c->lost_text, sizeof c->lost_text, fmt, c->cfg->interface, detail);
    c->next_probe_ns = now + KD_CAN_PROBE_NS;
    if (c->fd >= 0) {
        close(c->fd);
        c->fd = -1;
    }
}

int kd_can_open(kd_can *c, const kd_can_cfg *cfg, int n, int64_t period_ns, int64_t now)
{
    const char *what = "";
    int j, rc;
    memset(c, 0, sizeof *c);
    c->cfg = cfg;
    c->n = n;
    c->period_ns = period_ns;
    c->fd = -1;
    c->state = KD_CAN_OFF;
    kd_hist_clear(&c->send_ns);
    if (!cfg->enable)
        return 0;
    memset(c->node_joint, -1, sizeof c->node_joint);
    for (j = 0; j < n; j++)
        c->node_joint[cfg->joint[j].node] = (int8_t)j;
    rc = open_socket(c, &what);
    if (rc != 0) {
        fprintf(stderr, "kinctld: cannot open CAN interface \"%s\": %s: %s%s\n", cfg->interface, what, strerror(-rc),
                rc == -EAFNOSUPPORT ? " (this kernel has no SocketCAN: load the can and can-raw modules)" : "");
        return -1;
    }
    c->state = KD_CAN_OK;
    c->started_ns = now;
    c->heartbeat_period_ns = (int64_t)(cfg->heartbeat_ms * 1e6);
    c->next_heartbeat_ns = now;
    return 0;
}

void kd_can_close(kd_can *c)
{
    if (c->fd >= 0)
        close(c->fd);
    c->fd = -1;
}

int kd_can_fd(const kd_can *c) { return c->fd; }

/* Writes frames[0..count) in one call without blocking; counts and reacts
 * to what did not go out. */
static int write_frames(kd_can *c, struct can_frame *frames, int count, int64_t now)
{
    struct mmsghdr msgs[KD_CAN_FRAMES_MAX];
    struct iovec iov[KD_CAN_FRAMES_MAX];
    int i, sent;
    if (c->state != KD_CAN_OK || c->fd < 0) {
        c->tx_dropped += count;
        return 0;
    }
    memset(msgs, 0, sizeof msgs[0] * (size_t)count);
    for (i = 0; i < count; i++) {
        iov[i].iov_base = &frames[i];
        iov[i].iov_len = sizeof frames[i];
        msgs[i].msg_hdr.msg_iov = &iov[i];
        msgs[i].msg_hdr.msg_iovlen = 1;
    }
    sent = sendmmsg(c->fd, msgs, (unsigned)count, MSG_DONTWAIT);
    if (sent < 0)
        sent = 0;
    c->frames += sent;
    if (sent == count)
        return sent;
    /* The first frame that failed says why; the rest of this bus cycle is
     * dropped with it (never retried: it would be stale). */
    c->last_errno = errno;
    c->tx_dropped += count - sent;
    c->errors++;
    if (errno == ENETDOWN || errno == ENXIO || errno == ENODEV) {
        c->link_down++;
        lose(c, now, "%s is down (%s): CAN output lost", strerror(errno));
    }
    return sent;
}

void kd_can_send(kd_can *c, int64_t cycle, const kc_real *q, const kc_real *qd)
{
    struct can_frame frames[KD_CAN_FRAMES_MAX];
    int64_t t0, bus_cycle;
    int j, n = c->n;
    if (c->state == KD_CAN_OFF || cycle % c->cfg->sync_every != 0)
        return;
    t0 = kd_now_ns();
    bus_cycle = cycle / c->cfg->sync_every;
    kd_can_encode_sync(bus_cycle, &frames[0]);
    for (j = 0; j < n; j++) {
        kd_can_encode_rpdo(&c->cfg->joint[j], (double)q[j], (double)qd[j], &frames[1 + j]);
        c->target[c->syncs_out % KD_CAN_RING][j] = (double)q[j];
    }
    if (write_frames(c, frames, n + 1, t0) > 0)
        c->syncs_out++; /* the SYNC went out: the drives answer it */
    kd_hist_add(&c->send_ns, kd_now_ns() - t0);
}

static void set_condition(kd_can *c, int kind, const char *text)
{
    if (c->condition != KD_CAN_COND_NONE)
        return; /* the first one stands while it lasts */
    c->condition = kind;
    snprintf(c->condition_text, sizeof c->condition_text, "%s", text);
}

/* Re-evaluates the drive conditions from what is known now. */
static void evaluate(kd_can *c, int64_t now)
{
    const kd_can_cfg *cfg = c->cfg;
    char text[KD_CAN_TEXT];
    int j;
    c->condition = KD_CAN_COND_NONE;
    c->condition_text[0] = '\0';
    if (c->state == KD_CAN_LOST && cfg->on_error_stop)
        set_condition(c, KD_CAN_COND_BUS, c->lost_text);
    if (!cfg->feedback || c->state == KD_CAN_OFF)
        return;
    for (j = 0; j < c->n && c->condition == KD_CAN_COND_NONE; j++) {
        int node = cfg->joint[j].node;
        uint16_t sw = c->statusword[j];
        if (cfg->drive_timeout_ms > 0.0) {
            int64_t since = c->heartbeat_ns[j] != 0 ? c->heartbeat_ns[j] : c->started_ns;
            double silent_ms = (double)(now - since) * 1e-6;
            if (silent_ms > cfg->drive_timeout_ms) {
                snprintf(text, sizeof text, "joint %d (node %d) is silent: no heartbeat for %.0f ms (drive_timeout_ms %g)",
                         j + 1, node, silent_ms, cfg->drive_timeout_ms);
                set_condition(c, KD_CAN_COND_DRIVE, text);
                break;
            }
            if (c->heartbeat_ns[j] != 0 && c->nmt_state[j] != KD_CAN_NMT_OPERATIONAL) {
                snprintf(text, sizeof text, "joint %d (node %d) left OPERATIONAL: heartbeat state 0x%02x", j + 1, node,
                         c->nmt_state[j]);
                set_condition(c, KD_CAN_COND_DRIVE, text);
                break;
            }
        }
        if (!c->have_fb[j])
            continue;
        if (sw & (1u << 3)) {
            snprintf(text, sizeof text, "joint %d (node %d) reports a fault (statusword 0x%04x, bit 3)", j + 1, node,
                     sw);
            set_condition(c, KD_CAN_COND_DRIVE, text);
        } else if (sw & (1u << 13)) {
            snprintf(text, sizeof text, "joint %d (node %d) reports a following error (statusword 0x%04x, bit 13)",
                     j + 1, node, sw);
            set_condition(c, KD_CAN_COND_DRIVE, text);
        } else if (!(sw & (1u << 12))) {
            snprintf(text, sizeof text, "joint %d (node %d) does not follow the target (statusword 0x%04x, bit 12 clear)",
                     j + 1, node, sw);
            set_condition(c, KD_CAN_COND_DRIVE, text);
        } else if (cfg->following_error > 0.0 && c->following[j] > cfg->following_error) {
            snprintf(text, sizeof text, "joint %d (node %d) following error %.6g beyond %g (actual %.6g)", j + 1, node,
                     c->following[j], cfg->following_error, c->q_fb[j]);
            set_condition(c, KD_CAN_COND_DRIVE, text);
        }
    }
}

/* The following error of joint j's TPDO at q: the nearest of the targets
 * within two bus cycles of the one it answers (can_io.h). */
static void following(kd_can *c, int j, double q)
{
    int64_t k = c->tpdos[j], i, lo, hi;
    double best = HUGE_VAL;
    if (c->syncs_out - k > KD_CAN_RING / 2 || k >= c->syncs_out)
        k = c->syncs_out - 1; /* behind (lost TPDOs) or ahead (a TPDO before any SYNC) */
    c->tpdos[j] = k + 1;
    lo = k - 2 > c->syncs_out - KD_CAN_RING ? k - 2 : c->syncs_out - KD_CAN_RING;
    hi = k + 2 < c->syncs_out - 1 ? k + 2 : c->syncs_out - 1;
    if (lo < 0)
        lo = 0;
    for (i = lo; i <= hi; i++)
        best = fmin(best, fabs(q - c->target[i % KD_CAN_RING][j]));
    c->following[j] = hi >= lo ? best : 0.0;
}

static void on_frame(kd_can *c, const struct can_frame *f, int64_t now)
{
    canid_t id;
    int node, j;
    double q = 0.0;
    uint16_t statusword = 0;
    if (f->can_id & CAN_ERR_FLAG) {
        c->error_frames++;
        c->errors++;
        if (f->can_id & CAN_ERR_BUSOFF) {
            c->bus_off++;
            lose(c, now, "%s is bus-off (%s): CAN output lost", "error frame");
        }
        return;
    }
    if (f->can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG))
        return;
    id = f->can_id & CAN_SFF_MASK;
    node = (int)(id & 0x7fu);
    j = (int)c->node_joint[node];
    if (j < 0)
        return;
    c->rx_frames++;
    if ((id & ~0x7fu) == KD_CAN_TPDO_BASE && kd_can_decode_tpdo(&c->cfg->joint[j], f, &q, &statusword) == 0) {
        if (c->have_fb[j])
            c->qd_fb[j] = (q - c->q_fb[j]) / ((double)c->period_ns * 1e-9 * (double)c->cfg->sync_every);
        c->q_fb[j] = q;
        following(c, j, q);
        c->statusword[j] = statusword;
        c->have_fb[j] = 1;
    } else if ((id & ~0x7fu) == KD_CAN_HEARTBEAT_BASE && f->len >= 1) {
        c->heartbeat_ns[j] = now;
        c->nmt_state[j] = f->data[0];
    }
}

void kd_can_receive(kd_can *c, int64_t now)
{
    struct can_frame f;
    int k;
    for (k = 0; k < KD_CAN_RX_BURST && c->fd >= 0; k++) {
        ssize_t r = recv(c->fd, &f, sizeof f, MSG_DONTWAIT);
        if (r < 0) {
            if (errno == ENETDOWN || errno == ENXIO || errno == ENODEV) {
                c->link_down++;
                c->errors++;
                lose(c, now, "%s is down (%s): CAN output lost", strerror(errno));
            }
            break;
        }
        if ((size_t)r < sizeof f)
            continue;
        on_frame(c, &f, now);
    }
    evaluate(c, now);
}

void kd_can_timers(kd_can *c, int64_t now)
{
    if (c->state == KD_CAN_OFF)
        return;
    if (c->state == KD_CAN_LOST && now >= c->next_probe_ns) {
        const char *what = "";
        c->next_probe_ns = now + KD_CAN_PROBE_NS;
        if (link_ok(c) && open_socket(c, &what) == 0) {
            int j;
            c->state = KD_CAN_OK;
            c->state_changed = 1;
            c->next_heartbeat_ns = now;
            /* A new socket: the next TPDO answers the next SYNC, and every
             * drive has drive_timeout_ms from now to be heard again. */
            c->started_ns = now;
            for (j = 0; j < c->n; j++) {
                c->tpdos[j] = c->syncs_out;
                c->heartbeat_ns[j] = 0;
            }
        }
    }
    if (c->state == KD_CAN_OK && c->heartbeat_period_ns > 0 && now >= c->next_heartbeat_ns) {
        struct can_frame hb;
        kd_can_encode_heartbeat(c->cfg->master_id, KD_CAN_NMT_OPERATIONAL, &hb);
        write_frames(c, &hb, 1, now);
        c->next_heartbeat_ns += c->heartbeat_period_ns;
        if (c->next_heartbeat_ns <= now)
            c->next_heartbeat_ns = now + c->heartbeat_period_ns;
    }
    evaluate(c, now);
}

int kd_can_condition(const kd_can *c) { return c->condition; }
