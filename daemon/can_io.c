/* SPDX-License-Identifier: BSD-3-Clause */
/* can_io.c - the CAN link on the I/O thread (can_io.h). */
#define _GNU_SOURCE /* sendmmsg */
#include "can_io.h"

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

#include "canopen_sdo.h"
#include "cia402.h"
#include "clock.h"

#define KD_CAN_PROBE_NS 100000000LL      /* a lost interface is probed every 100 ms */
#define KD_CAN_RCVBUF (8 << 20)          /* feedback must wait in the socket, not be dropped */
#define KD_CAN_FILTERS_PER_DRIVE 4

/* Opens, filters and binds the link's socket. Returns 0 or -errno with
 * *what set. */
static int open_socket(kd_can *c, const char **what)
{
    struct can_filter filters[KD_CAN_FILTERS_PER_DRIVE * KC_MAX_JOINTS];
    static const canid_t bases[KD_CAN_FILTERS_PER_DRIVE] = {KD_CAN_TPDO_BASE, KD_CAN_HEARTBEAT_BASE,
                                                            KD_CAN_EMCY_BASE, KD_SDO_RX_BASE};
    int j, k, nf = 0, fd;
    /* Only the drives' frames reach this socket: a flood of foreign frames
     * is dropped by the kernel's filter, not read here. */
    memset(filters, 0, sizeof filters);
    for (j = 0; j < c->n; j++)
        for (k = 0; k < KD_CAN_FILTERS_PER_DRIVE; k++) {
            filters[nf].can_id = bases[k] + (canid_t)c->cfg->joint[j].node;
            filters[nf++].can_mask = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
        }
    fd = kd_can_socket(c->cfg->interface, filters, nf, CAN_ERR_MASK, KD_CAN_RCVBUF, what);
    if (fd < 0)
        return fd;
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

/* The link LOST, its first probe a whole KD_CAN_PROBE_NS after the loss
 * was seen: the clock read here, as the caller's pass may have begun before
 * the frame or the write that told it. */
static void lose(kd_can *c, const char *fmt, const char *detail)
{
    if (c->state != KD_CAN_OK)
        return;
    c->state = KD_CAN_LOST;
    c->state_changed = 1;
    atomic_store_explicit(&c->bus->paused, 1, memory_order_release);
    snprintf(c->lost_text, sizeof c->lost_text, fmt, c->cfg->interface, detail);
    c->next_probe_ns = kd_now_ns() + KD_CAN_PROBE_NS;
    if (c->fd >= 0) {
        close(c->fd);
        c->fd = -1;
    }
}

int kd_can_open(kd_can *c, const kd_can_cfg *cfg, kd_bus *bus, int n, int64_t period_ns, int64_t now)
{
    const char *what = "";
    int j, rc;
    memset(c, 0, sizeof *c);
    c->cfg = cfg;
    c->bus = bus;
    c->n = n;
    c->period_ns = period_ns;
    c->fd = -1;
    c->state = KD_CAN_OFF;
    if (!cfg->enable)
        return 0;
    memset(c->node_joint, -1, sizeof c->node_joint);
    for (j = 0; j < n; j++)
        c->node_joint[cfg->joint[j].node] = (int8_t)j;
    rc = open_socket(c, &what);
    if (rc != 0) {
        kd_can_open_failed(cfg->interface, what, rc);
        return -1;
    }
    c->state = KD_CAN_OK;
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

int kd_can_write(kd_can *c, const struct can_frame *frames, int count)
{
    int sent, err;
    if (c->state != KD_CAN_OK || c->fd < 0) {
        c->tx_dropped += count;
        return 0;
    }
    sent = kd_can_send(c->fd, frames, count, &err);
    c->frames += sent;
    if (sent == count)
        return sent;
    c->tx_dropped += count - sent;
    c->errors++;
    if (err == ENETDOWN || err == ENXIO || err == ENODEV) {
        c->link_down++;
        lose(c, "%s is down (%s): CAN output lost", strerror(err));
    }
    return sent;
}

static void set_condition(kd_can *c, int kind, const char *text)
{
    if (c->condition != KD_CAN_COND_NONE)
        return; /* the first one stands while it lasts */
    c->condition = kind;
    snprintf(c->condition_text, sizeof c->condition_text, "%s", text);
}

/* The first of joint j's conditions, into text; 0 when none. */
static int drive_condition(const kd_can *c, int j, int64_t now, char *text, size_t size)
{
    const kd_can_cfg *cfg = c->cfg;
    int node = cfg->joint[j].node;
    uint16_t sw = c->statusword[j];
    if (c->reboot_latched[j]) {
        snprintf(text, size, "joint %d (node %d) rebooted (boot-up seen)", j + 1, node);
        return 1;
    }
    if (c->emcy_latched[j]) {
        snprintf(text, size, "joint %d (node %d): EMCY 0x%04x (error register 0x%02x)", j + 1, node,
                 c->emcy_code[j], c->emcy_register[j]);
        return 1;
    }
    if (!cfg->feedback)
        return 0;
    if (cfg->drive_timeout_ms > 0.0) {
        int64_t since = c->heartbeat_ns[j] > c->watch_ns ? c->heartbeat_ns[j] : c->watch_ns;
        double silent_ms = (double)(now - since) * 1e-6;
        if (silent_ms > cfg->drive_timeout_ms) {
            snprintf(text, size, "joint %d (node %d) is silent: no heartbeat for %.0f ms (drive_timeout_ms %g)", j + 1,
                     node, silent_ms, cfg->drive_timeout_ms);
            return 1;
        }
        /* A heartbeat from before the watch (before NMT start, say) does not count. */
        if (c->heartbeat_ns[j] > c->watch_ns && c->nmt_state[j] != KD_CAN_NMT_OPERATIONAL) {
            snprintf(text, size, "joint %d (node %d) left OPERATIONAL: heartbeat state 0x%02x", j + 1, node,
                     c->nmt_state[j]);
            return 1;
        }
    }
    if (!c->have_fb[j])
        return 0;
    if (sw & (1u << 3))
        snprintf(text, size, "joint %d (node %d) reports a fault (statusword 0x%04x, bit 3)", j + 1, node, sw);
    else if (sw & KD_CIA402_SW_FOLLOWING_ERROR)
        snprintf(text, size, "joint %d (node %d) reports a following error (statusword 0x%04x, bit 13)", j + 1, node,
                 sw);
    else if (kd_cia402_state_of(sw) != KD_CIA402_OPERATION_ENABLED)
        snprintf(text, size, "joint %d (node %d) left operation enabled: %s (statusword 0x%04x)", j + 1, node,
                 kd_cia402_state_str(kd_cia402_state_of(sw)), sw);
    else if (!(sw & KD_CIA402_SW_TARGET_FOLLOWED))
        snprintf(text, size, "joint %d (node %d) does not follow the target (statusword 0x%04x, bit 12 clear)",
                 j + 1, node, sw);
    else if (cfg->following_error > 0.0 && c->following[j] > cfg->following_error)
        snprintf(text, size, "joint %d (node %d) following error %.6g beyond %g (actual %.6g)", j + 1, node,
                 c->following[j], cfg->following_error, c->q_fb[j]);
    else
        return 0;
    return 1;
}

/* Re-evaluates the conditions from what is known now. */
static void evaluate(kd_can *c, int64_t now)
{
    char text[KD_CAN_TEXT];
    int j;
    c->condition = KD_CAN_COND_NONE;
    c->condition_text[0] = '\0';
    if (c->state == KD_CAN_LOST && c->cfg->on_error_stop)
        set_condition(c, KD_CAN_COND_BUS, c->lost_text);
    if (!c->watch || c->state == KD_CAN_OFF)
        return;
    for (j = 0; j < c->n && c->condition == KD_CAN_COND_NONE; j++)
        if (drive_condition(c, j, now, text, sizeof text))
            set_condition(c, KD_CAN_COND_DRIVE, text);
}

/* The following error of joint j's TPDO at q: the nearest of the targets
 * within 1 + tpdo_every bus cycles of the one it answers (can_io.h). */
static void following(kd_can *c, int j, double q)
{
    int64_t syncs = atomic_load_explicit(&c->bus->syncs, memory_order_acquire);
    int64_t every = c->cfg->tpdo_every, k = c->tpdo_sync[j] + every, i, lo, hi;
    double best = HUGE_VAL;
    if (syncs - k > KD_CAN_RING / 2 || k >= syncs)
        k = syncs - 1; /* behind (lost TPDOs) or ahead (a TPDO before any SYNC) */
    c->tpdo_sync[j] = k;
    lo = k - 1 - every > syncs - KD_CAN_RING + 1 ? k - 1 - every : syncs - KD_CAN_RING + 1;
    hi = k + 1 + every < syncs - 1 ? k + 1 + every : syncs - 1;
    if (lo < 0)
        lo = 0;
    for (i = lo; i <= hi; i++)
        best = fmin(best, fabs(q - c->bus->target[i % KD_CAN_RING][j]));
    c->following[j] = hi >= lo ? best : 0.0;
}

static void on_frame(kd_can *c, const struct can_frame *f, int64_t now)
{
    canid_t id, base;
    int node, j;
    double q = 0.0;
    uint16_t statusword = 0;
    if (f->can_id & CAN_ERR_FLAG) {
        c->error_frames++;
        c->errors++;
        if (f->can_id & CAN_ERR_BUSOFF) {
            c->bus_off++;
            lose(c, "%s is bus-off (%s): CAN output lost", "error frame");
        }
        return;
    }
    if (f->can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG))
        return;
    id = f->can_id & CAN_SFF_MASK;
    node = (int)(id & 0x7fu);
    base = id & ~0x7fu;
    j = (int)c->node_joint[node];
    if (j < 0 || node == 0)
        return;
    c->rx_frames++;
    if (base == KD_CAN_TPDO_BASE && kd_can_decode_tpdo(&c->cfg->joint[j], f, &q, &statusword) == 0) {
        if (c->have_fb[j] && now > c->fb_ns[j])
            c->qd_fb[j] = (q - c->q_fb[j]) / ((double)c->period_ns * 1e-9 * (double)c->cfg->sync_every *
                                             (double)c->cfg->tpdo_every);
        c->q_fb[j] = q;
        following(c, j, q);
        c->statusword[j] = statusword;
        c->have_fb[j] = 1;
        c->fb_ns[j] = now;
        c->tpdos[j]++;
    } else if (base == KD_CAN_HEARTBEAT_BASE && f->len >= 1) {
        /* A boot-up is the entry into state 0: a node that keeps sending
         * heartbeats in state 0 (initialising) has booted once. */
        int entered = f->data[0] == KD_CAN_NMT_BOOTUP &&
                      (c->heartbeat_ns[j] == 0 || c->nmt_state[j] != KD_CAN_NMT_BOOTUP);
        c->heartbeat_ns[j] = now;
        c->nmt_state[j] = f->data[0];
        if (entered) {
            c->bootups[j]++;
            c->have_fb[j] = 0; /* a rebooted drive has not answered a SYNC yet */
            if (c->watch)
                c->reboot_latched[j] = 1;
        }
    } else if (base == KD_CAN_EMCY_BASE) {
        uint16_t code = 0;
        uint8_t reg = 0;
        if (kd_can_decode_emcy(f, &code, &reg) == 0) {
            c->emcy_code[j] = code;
            c->emcy_register[j] = reg;
            if (c->watch && code != 0)
                c->emcy_latched[j] = 1;
        }
    }
}

int kd_can_read(kd_can *c, struct can_frame *f, int64_t now)
{
    for (;;) {
        ssize_t r;
        if (c->fd < 0)
            return 0;
        r = recv(c->fd, f, sizeof *f, MSG_DONTWAIT);
        if (r < 0) {
            if (errno == ENETDOWN || errno == ENXIO || errno == ENODEV) {
                c->link_down++;
                c->errors++;
                lose(c, "%s is down (%s): CAN output lost", strerror(errno));
            }
            return 0;
        }
        if ((size_t)r == sizeof *f) {
            on_frame(c, f, now);
            return 1;
        }
        /* shorter than a classic frame (a CAN FD socket never binds here): the next one */
    }
}

/* A lost link that is back: both sockets anew. */
static void recover(kd_can *c, int64_t now)
{
    const char *what = "";
    int fd;
    c->next_probe_ns = now + KD_CAN_PROBE_NS;
    if (!link_ok(c) || open_socket(c, &what) != 0)
        return;
    fd = kd_can_socket(c->cfg->interface, NULL, 0, 0, 0, &what); /* the cycle's: sends only */
    if (fd < 0) {
        close(c->fd);
        c->fd = -1;
        return;
    }
    /* The cycle swaps it in at its next tick and hands the old one back. */
    fd = atomic_exchange_explicit(&c->bus->fd_next, fd, memory_order_acq_rel);
    if (fd >= 0)
        close(fd);
    c->state = KD_CAN_OK;
    c->state_changed = 1;
    c->recoveries++;
    c->next_heartbeat_ns = now;
    atomic_store_explicit(&c->bus->link_errno, 0, memory_order_relaxed);
    atomic_store_explicit(&c->bus->paused, 0, memory_order_release);
    /* The next TPDO answers the next SYNC, and every drive has
     * drive_timeout_ms from now to be heard again. */
    c->watch_ns = now;
    kd_can_rebase(c, -1);
}

void kd_can_timers(kd_can *c, int64_t now)
{
    int err, fd;
    if (c->state == KD_CAN_OFF)
        return;
    fd = atomic_exchange_explicit(&c->bus->fd_retired, -1, memory_order_acq_rel);
    if (fd >= 0)
        close(fd);
    err = atomic_exchange_explicit(&c->bus->link_errno, 0, memory_order_acq_rel);
    if (err != 0 && c->state == KD_CAN_OK) {
        c->link_down++;
        lose(c, "%s is down (%s): CAN output lost", strerror(err));
    }
    if (c->state == KD_CAN_LOST && now >= c->next_probe_ns)
        recover(c, now);
    if (c->state == KD_CAN_OK && c->heartbeat_period_ns > 0 && now >= c->next_heartbeat_ns) {
        struct can_frame hb;
        kd_can_encode_heartbeat(c->cfg->master_id, KD_CAN_NMT_OPERATIONAL, &hb);
        kd_can_write(c, &hb, 1);
        c->next_heartbeat_ns += c->heartbeat_period_ns;
        if (c->next_heartbeat_ns <= now)
            c->next_heartbeat_ns = now + c->heartbeat_period_ns;
    }
    evaluate(c, now);
}

void kd_can_watch(kd_can *c, int on, int64_t now)
{
    c->watch = on;
    c->watch_ns = now;
    evaluate(c, now);
}

void kd_can_rebase(kd_can *c, int j)
{
    int k;
    for (k = j < 0 ? 0 : j; k < (j < 0 ? c->n : j + 1); k++) {
        c->tpdo_sync[k] = atomic_load(&c->bus->syncs) - c->cfg->tpdo_every;
        c->following[k] = 0.0;
    }
}

void kd_can_clear(kd_can *c)
{
    memset(c->emcy_latched, 0, sizeof c->emcy_latched);
    memset(c->reboot_latched, 0, sizeof c->reboot_latched);
}

int kd_can_condition(const kd_can *c) { return c->condition; }

void kd_can_totals(const kd_can *c, int64_t *frames, int64_t *dropped, int64_t *errors)
{
    *frames = c->frames + atomic_load_explicit(&c->bus->frames, memory_order_relaxed);
    *dropped = c->tx_dropped + atomic_load_explicit(&c->bus->dropped, memory_order_relaxed);
    *errors = c->errors + atomic_load_explicit(&c->bus->errors, memory_order_relaxed);
}
