/* SPDX-License-Identifier: BSD-3-Clause */
/* can_master.c - the drives' lifecycle (can_master.h). */
#include "can_master.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "can_frame.h"

enum { P_OFF, P_BOOT, P_READ, P_SEAT, P_ENABLE, P_RUN, P_STOPPED, P_SHUTDOWN, P_SHUTDOWN_NMT, P_DONE };
enum { HOLD_CONDITION, HOLD_QUICK_STOP, HOLD_DISABLE };

#define SEAT_RETRY_NS 20000000LL /* a controller not yet idle is asked again after 20 ms */
#define OUT_MAX 8

static void tell(kd_master *m, int drives, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(m->text, sizeof m->text, fmt, ap);
    va_end(ap);
    m->drives = drives;
    m->news = 1;
}

static void send(kd_master *m, const struct can_frame *out, int n)
{
    if (n > 0)
        kd_can_write(m->can, out, n);
}

static int node_of(const kd_master *m, int j) { return m->cfg->joint[j].node; }

static void set_controlword(kd_master *m, int j, uint16_t cw)
{
    m->controlword[j] = cw;
    atomic_store_explicit(&m->bus->controlword[j], (unsigned)cw, memory_order_relaxed);
}

void kd_master_init(kd_master *m, kd_can *c, kd_bus *b, const kc_chain *chain, int64_t period_ns)
{
    memset(m, 0, sizeof *m);
    m->cfg = c->cfg;
    m->can = c;
    m->bus = b;
    m->chain = chain;
    m->n = chain->n_joints;
    m->period_ns = period_ns;
    m->phase = P_OFF;
    m->drives = KD_DRIVES_NONE;
}

/* Disabled, for why: the controlwords as hold says from now on. */
static void stop_with(kd_master *m, int hold, int64_t now, const char *why)
{
    char text[KD_CAN_TEXT];
    int j;
    snprintf(text, sizeof text, "%s", why); /* why may be the link's condition text, which unwatching clears */
    m->phase = P_STOPPED;
    m->phase_ns = now;
    m->hold = hold;
    m->seat_wanted = 0;
    for (j = 0; j < m->n; j++)
        m->booting[j] = 0;
    kd_can_watch(m->can, 0, now);
    if (hold == HOLD_QUICK_STOP)
        for (j = 0; j < m->n; j++)
            set_controlword(m, j, KD_CIA402_CW_QUICK_STOP);
    tell(m, KD_DRIVES_DISABLED, "%s", text);
}

static void fail(kd_master *m, int64_t now, const char *fmt, ...)
{
    char why[KD_CAN_TEXT];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    stop_with(m, HOLD_CONDITION, now, why);
}

/* ---- enabling ------------------------------------------------------------ */

/* Asks drive j for its position actual value. */
static void read_position(kd_master *m, int j)
{
    struct can_frame out[1];
    if (kd_sdo_upload(&m->sdo[j], 0x6064, 0, &out[0]) == KD_SDO_WAITING)
        send(m, out, 1);
}

static void start_read(kd_master *m, int64_t now)
{
    int j;
    m->phase = P_READ;
    m->phase_ns = now;
    if (m->drives != KD_DRIVES_ENABLING)
        tell(m, KD_DRIVES_ENABLING, "enabling %d drives: reading their positions (0x6064)", m->n);
    for (j = 0; j < m->n; j++) {
        m->have_pos[j] = 0;
        (void)kd_sdo_init(&m->sdo[j], node_of(m, j), (uint32_t)(m->cfg->sdo_timeout_ms * 1000.0));
        read_position(m, j);
    }
}

/* Every position read: where the controller is seated, inside the limits. */
static void positions_read(kd_master *m, int64_t now)
{
    int j;
    for (j = 0; j < m->n; j++) {
        const kc_joint_limits *l = &m->chain->joints[j].limits;
        double q = kd_can_pos_of_counts(&m->cfg->joint[j], m->pos_counts[j]);
        if (!(q >= (double)l->q_min && q <= (double)l->q_max)) {
            fail(m, now, "joint %d (node %d) is at %.6g (%ld counts), outside its limits [%.6g, %.6g]: not enabled",
                 j + 1, node_of(m, j), q, (long)m->pos_counts[j], (double)l->q_min, (double)l->q_max);
            return;
        }
        m->q_seat[j] = (kc_real)q;
    }
    m->phase = P_SEAT;
    m->phase_ns = now;
    m->seat_wanted = 1;
}

static void start_enable(kd_master *m, int64_t now)
{
    int j;
    m->phase = P_ENABLE;
    m->phase_ns = now;
    for (j = 0; j < m->n; j++) {
        uint16_t cw = KD_CIA402_CW_SHUTDOWN; /* a drive not heard yet: nothing that enables */
        if (m->disable_first[j])
            cw = KD_CIA402_CW_DISABLE_VOLTAGE;
        else if (m->can->have_fb[j])
            cw = kd_cia402_controlword(kd_cia402_state_of(m->can->statusword[j]), KD_CIA402_GOAL_ENABLED,
                                       m->controlword[j]);
        set_controlword(m, j, cw);
        m->tpdos[j] = m->can->tpdos[j];
        m->tpdos_phase[j] = m->can->tpdos[j];
    }
    kd_can_watch(m->can, 0, now);
    if (!atomic_load(&m->bus->active)) {
        kd_can_rebase(m->can, -1); /* the first SYNC of the bus cycle is the one the first TPDOs answer */
        atomic_store_explicit(&m->bus->active, 1, memory_order_release);
    }
}

/* A state without the power stage on. */
static int powered_off(kd_cia402_state s)
{
    return s == KD_CIA402_SWITCH_ON_DISABLED || s == KD_CIA402_READY_TO_SWITCH_ON || s == KD_CIA402_NOT_READY ||
           s == KD_CIA402_FAULT;
}

/* Each drive's next controlword, once per TPDO that answers the last one. */
static void walk(kd_master *m, int mode_enable)
{
    int j;
    for (j = 0; j < m->n; j++) {
        kd_cia402_state s;
        uint16_t cw;
        if (m->can->tpdos[j] == m->tpdos[j] || !m->can->have_fb[j])
            continue;
        m->tpdos[j] = m->can->tpdos[j];
        s = kd_cia402_state_of(m->can->statusword[j]);
        if (mode_enable && m->disable_first[j])
            m->disable_first[j] = !powered_off(s);
        if (mode_enable && m->disable_first[j])
            cw = KD_CIA402_CW_DISABLE_VOLTAGE;
        else if (mode_enable)
            cw = kd_cia402_controlword(s, KD_CIA402_GOAL_ENABLED, m->controlword[j]);
        else if (m->hold == HOLD_QUICK_STOP)
            cw = kd_cia402_controlword(s, KD_CIA402_GOAL_QUICK_STOP, m->controlword[j]);
        else if (m->hold == HOLD_CONDITION && s == KD_CIA402_OPERATION_ENABLED)
            cw = KD_CIA402_CW_ENABLE_OPERATION; /* follows the controller's own stop */
        else
            cw = kd_cia402_controlword(s, KD_CIA402_GOAL_DISABLED, m->controlword[j]);
        set_controlword(m, j, cw);
    }
}

/* A drive whose boot-up the link heard since it was started. */
static int rebooted(const kd_master *m)
{
    int j;
    for (j = 0; j < m->n; j++)
        if (m->booted[j] && m->can->bootups[j] != m->bootups[j])
            return j;
    return -1;
}

/* Drive j was last heard (its heartbeat) not operational: it missed its
 * NMT start (a lost frame) or left on its own (CiA 301 0x1029: a
 * communication error takes a drive to pre-operational by default). It
 * sends no PDO and takes none: only a boot brings it back. */
static int not_operational(const kd_master *m, int j)
{
    return m->can->heartbeat_ns[j] != 0 && m->can->nmt_state[j] != KD_CAN_NMT_OPERATIONAL;
}

static void enable_step(kd_master *m, int64_t now)
{
    int j, all = 1, r = rebooted(m);
    if (r >= 0) {
        m->booted[r] = 0;
        fail(m, now, "joint %d (node %d) rebooted (boot-up seen) while enabling", r + 1, node_of(m, r));
        return;
    }
    walk(m, 1);
    for (j = 0; j < m->n && all; j++)
        all = m->can->tpdos[j] != m->tpdos_phase[j] && !m->disable_first[j] &&
              kd_cia402_state_of(m->can->statusword[j]) == KD_CIA402_OPERATION_ENABLED;
    if (all) {
        char q[KD_CAN_TEXT / 2];
        int len = 0;
        for (j = 0; j < m->n && len < (int)sizeof q - 16; j++)
            len += snprintf(q + len, sizeof q - (size_t)len, "%s%.6g", j ? ", " : "", (double)m->q_seat[j]);
        m->phase = P_RUN;
        m->phase_ns = now;
        m->hold = HOLD_CONDITION; /* while running, the enabled hold and nothing else */
        kd_can_watch(m->can, 1, now);
        tell(m, KD_DRIVES_ENABLED, "drives enabled (%d of %d) at q = [%s]", m->n, m->n, q);
        return;
    }
    if ((double)(now - m->phase_ns) * 1e-6 > m->cfg->enable_timeout_ms) {
        for (j = 0; j < m->n; j++) {
            uint16_t sw = m->can->statusword[j];
            if (m->can->tpdos[j] == m->tpdos_phase[j]) {
                fail(m, now, "joint %d (node %d) not enabled within %g ms: no TPDO1 (statusword) from it", j + 1,
                     node_of(m, j), m->cfg->enable_timeout_ms);
                return;
            }
            if (m->disable_first[j]) {
                fail(m, now, "joint %d (node %d) not disabled within %g ms after it was booted again: %s (statusword "
                             "0x%04x)", j + 1, node_of(m, j), m->cfg->enable_timeout_ms,
                     kd_cia402_state_str(kd_cia402_state_of(sw)), sw);
                return;
            }
            if (kd_cia402_state_of(sw) != KD_CIA402_OPERATION_ENABLED) {
                fail(m, now, "joint %d (node %d) not enabled within %g ms: %s (statusword 0x%04x)", j + 1,
                     node_of(m, j), m->cfg->enable_timeout_ms, kd_cia402_state_str(kd_cia402_state_of(sw)), sw);
                return;
            }
        }
    }
}

/* ---- booting ------------------------------------------------------------- */

static void start_boot(kd_master *m, int64_t now)
{
    struct can_frame out[KD_BOOT_OUT_MAX];
    int j, n_out, any = 0;
    m->phase = P_BOOT;
    m->phase_ns = now;
    m->last_ns = now;
    for (j = 0; j < m->n; j++) {
        kd_boot_cfg bc;
        if (m->booted[j])
            continue;
        bc = kd_can_boot_cfg(m->cfg, j, m->period_ns);
        if (kd_boot_init(&m->boot[j], &bc) != 0) {
            fail(m, now, "joint %d (node %d): its boot cannot be written (kd_boot_init)", j + 1, node_of(m, j));
            return;
        }
        /* A drive booted again while the bus cycle runs may still be in
         * operation enabled (one that left OPERATIONAL without a 0x6007
         * reaction): the first RPDO it takes after NMT start disables it,
         * rather than hand it the controller's target, which moved on
         * without it; and it is enabled only once a TPDO has shown it
         * disabled, not on one sent before it took that RPDO. */
        set_controlword(m, j, KD_CIA402_CW_DISABLE_VOLTAGE);
        m->disable_first[j] = atomic_load(&m->bus->active) != 0;
        n_out = 0;
        kd_boot_start(&m->boot[j], out, &n_out);
        send(m, out, n_out);
        m->booting[j] = 1;
        any++;
    }
    if (!any) {
        start_read(m, now);
        return;
    }
    tell(m, KD_DRIVES_BOOTING, "booting %d drive%s (%s)", any, any == 1 ? "" : "s",
         m->cfg->boot ? "NMT reset communication, SDO configuration, NMT start" : "checks and NMT start only");
}

static void boot_result(kd_master *m, int j, int r, int64_t now)
{
    int k;
    if (r == KD_BOOT_DONE) {
        m->booting[j] = 0;
        m->booted[j] = 1;
        m->bootups[j] = m->can->bootups[j];
        kd_can_rebase(m->can, j); /* started: it answers the next SYNC */
    } else if (r < 0) {
        char why[KD_CAN_TEXT];
        const char *rest;
        kd_boot_why(&m->boot[j], why, sizeof why);
        rest = strstr(why, ": ");
        fail(m, now, "joint %d (node %d): %s; the drives stay disabled (RESET boots them again)", j + 1,
             node_of(m, j), rest != NULL ? rest + 2 : why);
        return;
    }
    for (k = 0; k < m->n; k++)
        if (m->booting[k])
            return;
    start_read(m, now);
}

/* ---- the API --------------------------------------------------------------- */

void kd_master_start(kd_master *m, int64_t now)
{
    if (!m->cfg->enable)
        return;
    start_boot(m, now);
}

/* Each boot under way takes frame f, or (f NULL) elapsed_us of time. */
static void boot_each(kd_master *m, const struct can_frame *f, uint32_t elapsed_us, int64_t now)
{
    struct can_frame out[OUT_MAX];
    int j, n_out, r;
    for (j = 0; j < m->n && m->phase == P_BOOT; j++) {
        if (!m->booting[j])
            continue;
        n_out = 0;
        r = f != NULL ? kd_boot_rx(&m->boot[j], f, out, &n_out) : kd_boot_process(&m->boot[j], elapsed_us, out, &n_out);
        send(m, out, n_out);
        if (r != KD_BOOT_WAITING)
            boot_result(m, j, r, now);
    }
}

/* Each read of 0x6064 under way takes frame f, or (f NULL) elapsed_us of
 * time; once every position is in, the seat. */
static void read_each(kd_master *m, const struct can_frame *f, uint32_t elapsed_us, int64_t now)
{
    struct can_frame out[OUT_MAX];
    int j, n_out, r;
    for (j = 0; j < m->n && m->phase == P_READ; j++) {
        if (m->have_pos[j])
            continue;
        n_out = 0;
        r = f != NULL ? kd_sdo_rx(&m->sdo[j], f, out, &n_out) : kd_sdo_process(&m->sdo[j], elapsed_us, out, &n_out);
        send(m, out, n_out);
        if (r == KD_SDO_DONE && f != NULL) {
            m->have_pos[j] = 1;
            m->pos_counts[j] = (int32_t)m->sdo[j].value;
        } else if (r == KD_SDO_E_TIMEOUT) {
            fail(m, now, "joint %d (node %d): SDO read 0x6064:00 (position actual value): no answer within %g ms, %d "
                         "times", j + 1, node_of(m, j), m->cfg->sdo_timeout_ms, m->sdo[j].sends);
        } else if (r < 0 && r != KD_SDO_E_BUSY) {
            fail(m, now, "joint %d (node %d): SDO read 0x6064:00 (position actual value) aborted 0x%08X: %s", j + 1,
                 node_of(m, j), m->sdo[j].abort_code, kd_sdo_abort_str(m->sdo[j].abort_code));
        }
    }
    for (j = 0; j < m->n && m->phase == P_READ; j++)
        if (!m->have_pos[j])
            return;
    if (m->phase == P_READ)
        positions_read(m, now);
}

void kd_master_rx(kd_master *m, const struct can_frame *f, int64_t now)
{
    if (m->phase == P_BOOT)
        boot_each(m, f, 0, now);
    else if (m->phase == P_READ)
        read_each(m, f, 0, now);
}

/* shutdown_nmt to every drive. */
static void send_shutdown_nmt(kd_master *m)
{
    struct can_frame out[OUT_MAX];
    int j, n_out = 0;
    for (j = 0; j < m->n; j++) {
        kd_can_encode_nmt((uint8_t)m->cfg->shutdown_nmt, node_of(m, j), &out[n_out++]);
        if (n_out == OUT_MAX || j == m->n - 1) {
            send(m, out, n_out);
            n_out = 0;
        }
    }
}

static void shutdown_step(kd_master *m, int64_t now)
{
    int j, all = 1;
    if (m->phase == P_SHUTDOWN_NMT) {
        /* The bus cycle stopped two bus cycles ago: the cycle thread wrote
         * its last one before, so nothing follows the NMT command. */
        if (now - m->phase_ns < 2 * m->period_ns * m->cfg->sync_every)
            return;
        send_shutdown_nmt(m);
        m->phase = P_DONE;
        tell(m, KD_DRIVES_DISABLED, "drives %s, then NMT %s",
             m->disabled_in_time ? "disabled" : "not all disabled in time",
             m->cfg->shutdown_nmt == KD_NMT_STOP ? "stop" : "enter pre-operational");
        return;
    }
    walk(m, 0);
    for (j = 0; j < m->n && all; j++)
        all = m->can->tpdos[j] != m->tpdos_phase[j] && powered_off(kd_cia402_state_of(m->can->statusword[j]));
    if (!all && (double)(now - m->phase_ns) * 1e-6 <= m->cfg->enable_timeout_ms)
        return;
    atomic_store_explicit(&m->bus->active, 0, memory_order_release);
    m->phase = P_SHUTDOWN_NMT;
    m->phase_ns = now;
    m->disabled_in_time = all;
}

void kd_master_step(kd_master *m, int64_t now)
{
    uint32_t elapsed_us;
    int r;
    if (m->phase == P_OFF || m->phase == P_DONE)
        return;
    elapsed_us = now > m->last_ns ? (uint32_t)((now - m->last_ns) / 1000) : 0;
    if (elapsed_us == 0 && now > m->last_ns)
        return; /* less than a microsecond: the timers wait for more */
    m->last_ns = now;
    if (m->can->recoveries != m->recoveries) {
        m->recoveries = m->can->recoveries;
        if (m->phase == P_READ || m->phase == P_SEAT || m->phase == P_ENABLE || m->phase == P_RUN) {
            stop_with(m, HOLD_QUICK_STOP, now,
                      "the bus was lost with the drives enabled: quick stop to every drive (RESET enables them "
                      "again where they are)");
            return;
        }
    }
    switch (m->phase) {
    case P_BOOT:
        boot_each(m, NULL, elapsed_us, now);
        break;
    case P_READ:
        read_each(m, NULL, elapsed_us, now);
        break;
    case P_SEAT:
        if ((double)(now - m->phase_ns) * 1e-6 > m->cfg->enable_timeout_ms)
            fail(m, now, "the controller did not take the drives' positions within %g ms (it must be idle and at "
                         "rest: RESET once the arm has stopped)", m->cfg->enable_timeout_ms);
        else if (!m->seat_wanted && m->seat_retry_ns != 0 && now >= m->seat_retry_ns) {
            m->seat_retry_ns = 0;
            m->seat_wanted = 1;
        }
        break;
    case P_ENABLE:
        enable_step(m, now);
        break;
    case P_RUN:
        r = rebooted(m);
        if (r >= 0)
            m->booted[r] = 0;
        if (kd_can_condition(m->can) == KD_CAN_COND_DRIVE) {
            stop_with(m, HOLD_CONDITION, now, m->can->condition_text);
            break;
        }
        walk(m, 0); /* hold: a drive that left operation enabled is never walked back (no fault reset) */
        break;
    case P_STOPPED:
        walk(m, 0);
        r = rebooted(m);
        if (r >= 0)
            m->booted[r] = 0;
        break;
    case P_SHUTDOWN:
    case P_SHUTDOWN_NMT:
        shutdown_step(m, now);
        break;
    default:
        break;
    }
}

int kd_master_seat_wanted(kd_master *m, kc_real *q)
{
    if (!m->seat_wanted)
        return 0;
    m->seat_wanted = 0;
    memcpy(q, m->q_seat, sizeof(kc_real) * (size_t)m->n);
    return 1;
}

void kd_master_seated(kd_master *m, int status, int bad_joint, int64_t now)
{
    if (m->phase != P_SEAT)
        return;
    if (status == KC_OK)
        start_enable(m, now);
    else if (status == KC_E_STATE)
        m->seat_retry_ns = now + SEAT_RETRY_NS;
    else if (bad_joint >= 0 && bad_joint < m->n)
        fail(m, now, "joint %d (node %d) is at %.6g, which the controller refuses (%d)", bad_joint + 1,
             node_of(m, bad_joint), (double)m->q_seat[bad_joint], status);
    else
        fail(m, now, "the controller refuses the drives' positions (%d)", status);
}

void kd_master_estop(kd_master *m, int64_t now)
{
    if (m->phase == P_OFF || m->phase == P_SHUTDOWN || m->phase == P_SHUTDOWN_NMT || m->phase == P_DONE)
        return;
    if (m->phase == P_STOPPED && m->hold == HOLD_QUICK_STOP)
        return;
    stop_with(m, HOLD_QUICK_STOP, now, "ESTOP: quick stop sent to every drive");
}

void kd_master_reset(kd_master *m, int64_t now)
{
    int j;
    if (m->phase != P_STOPPED)
        return;
    for (j = 0; j < m->n; j++)
        if (m->booted[j] && (m->can->bootups[j] != m->bootups[j] || not_operational(m, j)))
            m->booted[j] = 0;
    kd_can_clear(m->can);
    start_boot(m, now);
}

void kd_master_shutdown(kd_master *m, int64_t now)
{
    int j;
    if (m->phase == P_OFF || m->phase == P_SHUTDOWN || m->phase == P_SHUTDOWN_NMT || m->phase == P_DONE)
        return;
    kd_can_watch(m->can, 0, now);
    m->seat_wanted = 0;
    if (atomic_load(&m->bus->active)) {
        m->phase = P_SHUTDOWN;
        m->phase_ns = now;
        m->hold = HOLD_DISABLE;
        for (j = 0; j < m->n; j++) {
            set_controlword(m, j, KD_CIA402_CW_DISABLE_VOLTAGE);
            m->tpdos[j] = m->can->tpdos[j];
            m->tpdos_phase[j] = m->can->tpdos[j];
        }
        tell(m, KD_DRIVES_DISABLED, "shutdown: disabling every drive (controlword 0x0000)");
        return;
    }
    /* Never enabled: straight to NMT. */
    send_shutdown_nmt(m);
    m->phase = P_DONE;
    tell(m, KD_DRIVES_DISABLED, "shutdown: drives never enabled; NMT %s sent",
         m->cfg->shutdown_nmt == KD_NMT_STOP ? "stop" : "enter pre-operational");
}

int kd_master_shutdown_done(const kd_master *m) { return m->phase == P_OFF || m->phase == P_DONE; }

int kd_master_take_news(kd_master *m, const char **text)
{
    if (!m->news)
        return 0;
    m->news = 0;
    *text = m->text;
    return 1;
}

const char *kd_master_drives_str(int drives)
{
    switch (drives) {
    case KD_DRIVES_BOOTING:
        return "booting";
    case KD_DRIVES_ENABLING:
        return "enabling";
    case KD_DRIVES_ENABLED:
        return "enabled";
    case KD_DRIVES_DISABLED:
        return "disabled";
    default:
        return "none";
    }
}
