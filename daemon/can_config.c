/* SPDX-License-Identifier: BSD-3-Clause */
/* can_config.c - controller.can: read, then checked against the arm
 * (can_config.h). */
#include "can_config.h"

#include <libconfig.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "can_budget.h"
#include "can_frame.h"
#include "kinctl/cfgread.h"

kd_can_cfg kd_can_cfg_default(void)
{
    kd_can_cfg can;
    kd_boot_cfg boot = kd_boot_cfg_default(1); /* the drives' side: canopen_boot.h */
    memset(&can, 0, sizeof can);
    can.bitrate = 1000000;
    can.bus_share = KD_CAN_BUDGET_SHARE_DEFAULT;
    can.sync_every = 1;
    can.sync_counter = 0;
    can.tpdo_every = 1;
    can.master_id = boot.master_id;
    can.heartbeat_ms = 100.0;
    can.on_error_stop = 1;
    can.boot = boot.reset_communication && boot.configure;
    can.device_type = boot.device_type;
    can.device_type_mask = boot.device_type_mask;
    can.drive_heartbeat_ms = boot.heartbeat_ms;
    can.master_timeout_ms = boot.consumer_ms;
    can.lost_master_reaction = boot.lost_master_reaction;
    can.boot_timeout_ms = (double)boot.bootup_timeout_us / 1000.0;
    can.sdo_timeout_ms = (double)boot.sdo_timeout_us / 1000.0;
    can.enable_timeout_ms = 2000.0;
    can.shutdown_nmt = KD_NMT_ENTER_PRE_OPERATIONAL;
    can.feedback = 1;
    return can;
}

/* joints[i].identity: 0x1018:1..4 expected, 0 unchecked. */
static int read_identity(kc_cfg *r, const config_setting_t *e, const char *where, kd_can_joint *jc)
{
    const config_setting_t *s = config_setting_get_member(e, "identity");
    int i;
    if (s == NULL)
        return 0;
    if (!config_setting_is_array(s) || config_setting_length(s) != 4)
        return kc_cfg_fail(r, s, "%s.identity must be [vendor, product, revision, serial] (0: unchecked)", where);
    for (i = 0; i < 4; i++) {
        double v = 0.0;
        char what[96];
        snprintf(what, sizeof what, "%s.identity[%d]", where, i);
        if (kc_cfg_number(r, config_setting_get_elem(s, (unsigned)i), what, &v) != 0)
            return -1;
        if (!(v >= 0.0 && v <= 4294967295.0) || v != floor(v))
            return kc_cfg_fail(r, s, "%s = %.17g is not a 32-bit unsigned integer", what, v);
        jc->identity[i] = (uint32_t)v;
    }
    return 0;
}

/* joints[i].writes: the drive's own expedited SDO writes, in order. */
static int read_writes(kc_cfg *r, const config_setting_t *e, const char *where, kd_can_joint *jc)
{
    static const char *const write_keys[] = {"index", "subindex", "size", "value", NULL};
    const config_setting_t *s = config_setting_get_member(e, "writes");
    int i, n;
    if (s == NULL)
        return 0;
    n = config_setting_length(s);
    if (!config_setting_is_list(s) || n > KD_BOOT_EXTRA_MAX)
        return kc_cfg_fail(r, s, "%s.writes must be a list of at most %d groups { index; subindex; size; value; }",
                           where, KD_BOOT_EXTRA_MAX);
    for (i = 0; i < n; i++) {
        const config_setting_t *w = config_setting_get_elem(s, (unsigned)i);
        kd_boot_write *bw = &jc->writes[i];
        char wh[96];
        int index = 0, sub = 0, size = 0;
        double value = 0.0, lo, hi;
        snprintf(wh, sizeof wh, "%s.writes[%d]", where, i);
        if (!config_setting_is_group(w))
            return kc_cfg_fail(r, w, "%s must be a group { index; subindex; size; value; }", wh);
        if (kc_cfg_check_keys(r, w, wh, write_keys) != 0 || kc_cfg_require(r, w, "index", wh) != 0 ||
            kc_cfg_require(r, w, "size", wh) != 0 || kc_cfg_require(r, w, "value", wh) != 0 ||
            kc_cfg_lookup_int(r, w, "index", wh, 0x1000, 0xFFFF, &index) != 0 ||
            kc_cfg_lookup_int(r, w, "subindex", wh, 0, 255, &sub) != 0 ||
            kc_cfg_lookup_int(r, w, "size", wh, 1, 4, &size) != 0)
            return -1;
        /* signed or unsigned, as long as size bytes hold it */
        hi = size == 4 ? 4294967295.0 : (double)((1ull << (8 * size)) - 1u);
        lo = -(double)(1ull << (8 * size - 1));
        if (kc_cfg_lookup_number(r, w, "value", wh, lo, hi, &value) != 0)
            return -1;
        if (value != floor(value))
            return kc_cfg_fail(r, config_setting_get_member(w, "value"), "%s.value = %.17g is not an integer", wh,
                               value);
        bw->index = (uint16_t)index;
        bw->subindex = (uint8_t)sub;
        bw->size = (uint8_t)size;
        bw->value = value < 0.0 ? (uint32_t)(int32_t)value : (uint32_t)value;
    }
    jc->n_writes = n;
    return 0;
}

/* controller.can (can_config.h). The joints' count and ranges are checked
 * against the arm in kd_can_cfg_check, once the arm is known. */
int kd_can_cfg_read(kc_cfg *r, const config_setting_t *g, kd_can_cfg *can)
{
    static const char *const keys[] = {"interface",  "bitrate",          "bus_share",         "sync_every",
                                       "sync_counter", "tpdo_every",     "velocity_offset",   "master_id",
                                       "heartbeat_ms", "on_error",       "boot",              "device_type",
                                       "device_type_mask", "drive_heartbeat_ms", "master_timeout_ms",
                                       "lost_master_reaction", "cycle_period", "boot_timeout_ms", "sdo_timeout_ms",
                                       "enable_timeout_ms", "shutdown_nmt", "joints", "feedback", NULL};
    static const char *const joint_keys[] = {"node", "counts_per_unit", "sign", "offset_counts", "identity", "writes",
                                             NULL};
    static const char *const fb_keys[] = {"enable", "following_error", "drive_timeout_ms", NULL};
    const config_setting_t *s, *fb;
    const char *str = "";
    int i, k, n;
    if (kc_cfg_check_keys(r, g, "controller.can", keys) != 0 ||
        kc_cfg_lookup_string(r, g, "interface", "controller.can", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        if (strlen(str) >= KD_CAN_IFNAME_MAX)
            return kc_cfg_fail(r, s, "controller.can.interface \"%s\" is longer than %d characters", str,
                               KD_CAN_IFNAME_MAX - 1);
        snprintf(can->interface, sizeof can->interface, "%s", str);
        can->enable = str[0] != '\0';
    }
    double bitrate = (double)can->bitrate, dtype = can->device_type, dmask = can->device_type_mask;
    if (kc_cfg_lookup_number(r, g, "bitrate", "controller.can", 10000.0, 1000000.0, &bitrate) != 0 ||
        kc_cfg_lookup_number(r, g, "bus_share", "controller.can", 0.01, 1.0, &can->bus_share) != 0 ||
        kc_cfg_lookup_int(r, g, "sync_every", "controller.can", 1, 1000, &can->sync_every) != 0 ||
        kc_cfg_lookup_int(r, g, "sync_counter", "controller.can", 0, KD_CAN_SYNC_COUNTER_MAX, &can->sync_counter) != 0 ||
        kc_cfg_lookup_int(r, g, "tpdo_every", "controller.can", 1, 240, &can->tpdo_every) != 0 ||
        kc_cfg_lookup_bool(r, g, "velocity_offset", "controller.can", &can->velocity_offset) != 0 ||
        kc_cfg_lookup_int(r, g, "master_id", "controller.can", 1, 127, &can->master_id) != 0 ||
        kc_cfg_lookup_number(r, g, "heartbeat_ms", "controller.can", 0.0, 60000.0, &can->heartbeat_ms) != 0 ||
        kc_cfg_lookup_bool(r, g, "boot", "controller.can", &can->boot) != 0 ||
        kc_cfg_lookup_number(r, g, "device_type", "controller.can", 0.0, 4294967295.0, &dtype) != 0 ||
        kc_cfg_lookup_number(r, g, "device_type_mask", "controller.can", 0.0, 4294967295.0, &dmask) != 0 ||
        kc_cfg_lookup_int(r, g, "drive_heartbeat_ms", "controller.can", 0, 65535, &can->drive_heartbeat_ms) != 0 ||
        kc_cfg_lookup_int(r, g, "master_timeout_ms", "controller.can", 0, 65535, &can->master_timeout_ms) != 0 ||
        kc_cfg_lookup_int(r, g, "lost_master_reaction", "controller.can", -1, 32767, &can->lost_master_reaction) != 0 ||
        kc_cfg_lookup_bool(r, g, "cycle_period", "controller.can", &can->cycle_period) != 0 ||
        kc_cfg_lookup_number(r, g, "boot_timeout_ms", "controller.can", 1.0, 600000.0, &can->boot_timeout_ms) != 0 ||
        kc_cfg_lookup_number(r, g, "sdo_timeout_ms", "controller.can", 1.0, 60000.0, &can->sdo_timeout_ms) != 0 ||
        kc_cfg_lookup_number(r, g, "enable_timeout_ms", "controller.can", 1.0, 600000.0, &can->enable_timeout_ms) !=
            0)
        return -1;
    can->bitrate = (int64_t)llround(bitrate);
    can->device_type = (uint32_t)llround(dtype);
    can->device_type_mask = (uint32_t)llround(dmask);
    if (can->sync_counter == 1)
        return kc_cfg_fail(r, config_setting_get_member(g, "sync_counter"),
                           "controller.can.sync_counter = 1 is not a SYNC counter: 0 (empty SYNC) or 2 .. 240");
    if (kc_cfg_lookup_string(r, g, "shutdown_nmt", "controller.can", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        if (strcmp(str, "pre_operational") == 0)
            can->shutdown_nmt = KD_NMT_ENTER_PRE_OPERATIONAL;
        else if (strcmp(str, "stop") == 0)
            can->shutdown_nmt = KD_NMT_STOP;
        else
            return kc_cfg_fail(r, s, "controller.can.shutdown_nmt must be \"pre_operational\" or \"stop\", not \"%s\"",
                               str);
    }
    if (kc_cfg_lookup_string(r, g, "on_error", "controller.can", &str, &s) != 0)
        return -1;
    if (s != NULL) {
        if (strcmp(str, "stop") == 0)
            can->on_error_stop = 1;
        else if (strcmp(str, "lcm_only") == 0)
            can->on_error_stop = 0;
        else
            return kc_cfg_fail(r, s, "controller.can.on_error must be \"stop\" or \"lcm_only\", not \"%s\"", str);
    }
    s = config_setting_get_member(g, "joints");
    if (s != NULL) {
        n = config_setting_length(s);
        can->joints_line = (int)config_setting_source_line(s);
        if (!config_setting_is_aggregate(s) || n < 1 || n > KC_MAX_JOINTS)
            return kc_cfg_fail(r, s, "controller.can.joints must be a list of 1 .. %d groups", KC_MAX_JOINTS);
        for (i = 0; i < n; i++) {
            const config_setting_t *e = config_setting_get_elem(s, (unsigned)i);
            kd_can_joint *jc = &can->joint[i];
            char where[64];
            double off = 0.0;
            snprintf(where, sizeof where, "controller.can.joints[%d]", i);
            jc->line = (int)config_setting_source_line(e);
            if (!config_setting_is_group(e))
                return kc_cfg_fail(r, e, "%s must be a group { node = ...; counts_per_unit = ...; }", where);
            if (config_setting_get_member(e, "node") == NULL || config_setting_get_member(e, "counts_per_unit") == NULL)
                return kc_cfg_fail(r, e, "%s needs node and counts_per_unit", where);
            jc->sign = 1;
            if (kc_cfg_check_keys(r, e, where, joint_keys) != 0 ||
                kc_cfg_lookup_int(r, e, "node", where, 1, 127, &jc->node) != 0 ||
                kc_cfg_lookup_number(r, e, "counts_per_unit", where, 1e-9, 1e12, &jc->counts_per_unit) != 0 ||
                kc_cfg_lookup_int(r, e, "sign", where, -1, 1, &jc->sign) != 0 ||
                kc_cfg_lookup_number(r, e, "offset_counts", where, -2147483647.0, 2147483647.0, &off) != 0)
                return -1;
            if (jc->sign == 0)
                return kc_cfg_fail(r, config_setting_get_member(e, "sign"), "%s.sign must be 1 or -1", where);
            jc->offset_counts = (int64_t)llround(off);
            if (read_identity(r, e, where, jc) != 0 || read_writes(r, e, where, jc) != 0)
                return -1;
            for (k = 0; k < i; k++)
                if (can->joint[k].node == jc->node)
                    return kc_cfg_fail(r, e, "%s.node = %d is also joint %d's", where, jc->node, k + 1);
        }
        can->n_joints = n;
    }
    if (kc_cfg_lookup_group(r, g, "feedback", "controller.can", &fb) != KC_OK)
        return -1;
    if (fb != NULL) {
        if (kc_cfg_check_keys(r, fb, "controller.can.feedback", fb_keys) != 0 ||
            kc_cfg_lookup_bool(r, fb, "enable", "controller.can.feedback", &can->feedback) != 0 ||
            kc_cfg_lookup_number(r, fb, "following_error", "controller.can.feedback", 0.0, 1e6,
                                 &can->following_error) != 0 ||
            kc_cfg_lookup_number(r, fb, "drive_timeout_ms", "controller.can.feedback", 0.0, 60000.0,
                                 &can->drive_timeout_ms) != 0)
            return -1;
    }
    return 0;
}

/* The CAN section against the arm: one drive per joint, node ids apart
 * from the master's, and every position and velocity inside int32 counts. */
/* "<file>:<line>: " where the line is known, else "<file>: ". */
static void where_in(const char *path, int line)
{
    if (line > 0)
        fprintf(stderr, "%s:%d: ", path != NULL ? path : "kinctld", line);
    else
        fprintf(stderr, "%s: ", path != NULL ? path : "kinctld");
}

void kd_can_budget_of(const kd_can_cfg *can, int64_t period_ns, kd_can_budget *b)
{
    int j;
    *b = kd_can_budget_default();
    b->bitrate = can->bitrate;
    b->period_ns = period_ns;
    b->sync_every = can->sync_every;
    b->sync_bytes = can->sync_counter > 0 ? 1 : 0;
    b->share = can->bus_share;
    b->n_drives = can->n_joints;
    for (j = 0; j < can->n_joints; j++) {
        kd_can_budget_drive *d = &b->drive[j];
        d->n_rpdo = can->velocity_offset ? 2 : 1;
        d->rpdo_bytes[0] = KD_CAN_RPDO_LEN;
        d->rpdo_bytes[1] = 4;
        d->n_tpdo = 1;
        d->tpdo_bytes[0] = KD_CAN_TPDO_LEN;
        d->tpdo_every[0] = can->tpdo_every;
    }
}

kd_boot_cfg kd_can_boot_cfg(const kd_can_cfg *can, int j, int64_t period_ns)
{
    const kd_can_joint *jc = &can->joint[j];
    kd_boot_cfg b = kd_boot_cfg_default(jc->node);
    uint32_t bus_us = (uint32_t)(period_ns * can->sync_every / 1000);
    int i;
    b.reset_communication = can->boot;
    b.configure = can->boot;
    b.device_type = can->device_type;
    b.device_type_mask = can->device_type_mask;
    memcpy(b.identity, jc->identity, sizeof b.identity);
    b.n_rpdo = can->velocity_offset ? 2 : 1;
    b.rpdo[1].n_map = 1;
    b.rpdo[1].map[0] = 0x60B10020u;
    b.rpdo[1].transmission_type = 1;
    b.tpdo[0].transmission_type = can->tpdo_every;
    b.interpolation_us = bus_us;
    b.cycle_period_us = can->cycle_period ? bus_us : 0;
    b.sync_overflow = can->sync_counter > 0 ? can->sync_counter : -1;
    b.heartbeat_ms = (uint16_t)can->drive_heartbeat_ms;
    b.master_id = can->master_id;
    b.consumer_ms = (uint16_t)can->master_timeout_ms;
    b.lost_master_reaction = can->lost_master_reaction;
    b.n_extra = jc->n_writes;
    for (i = 0; i < jc->n_writes; i++)
        b.extra[i] = jc->writes[i];
    b.bootup_timeout_us = (uint32_t)(can->boot_timeout_ms * 1000.0);
    b.sdo_timeout_us = (uint32_t)(can->sdo_timeout_ms * 1000.0);
    return b;
}

int kd_can_cfg_check(const kd_can_cfg *can, const kc_chain *chain, const char *robot_name, const char *path,
                     int64_t period_ns)
{
    kd_can_budget budget;
    kd_can_budget_use use;
    char why[512];
    uint8_t ip_value;
    int8_t ip_index;
    int64_t bus_us = period_ns * can->sync_every / 1000;
    int j;
    if (!can->enable)
        return 0;
    if (can->n_joints != chain->n_joints) {
        where_in(path, can->joints_line);
        fprintf(stderr, "controller.can.joints has %d drives, the arm \"%s\" has %d joints\n", can->n_joints,
                robot_name, chain->n_joints);
        return -1;
    }
    for (j = 0; j < can->n_joints; j++) {
        const kd_can_joint *jc = &can->joint[j];
        const kc_joint_limits *l = &chain->joints[j].limits;
        double reach = fmax(fabs((double)l->q_min), fabs((double)l->q_max)) * jc->counts_per_unit +
                       fabs((double)jc->offset_counts);
        double vel = (double)l->qd_max * jc->counts_per_unit;
        if (jc->node == can->master_id) {
            where_in(path, jc->line);
            fprintf(stderr, "controller.can.joints[%d].node = %d (joint %d) is the master's id (master_id)\n", j,
                    jc->node, j + 1);
            return -1;
        }
        if (!(reach < 2147483647.0) || !(vel < 2147483647.0)) {
            where_in(path, jc->line);
            fprintf(stderr,
                    "controller.can.joints[%d]: joint %d's range [%.6g, %.6g] or speed %.6g at %.6g counts per "
                    "unit does not fit int32 counts\n",
                    j, j + 1, (double)l->q_min, (double)l->q_max, (double)l->qd_max, jc->counts_per_unit);
            return -1;
        }
    }
    if (can->boot && (bus_us * 1000 != period_ns * can->sync_every || bus_us > 0xFFFFFFFF ||
                      kd_boot_interpolation((uint32_t)bus_us, &ip_value, &ip_index) != 0)) {
        where_in(path, 0);
        fprintf(stderr,
                "controller.can: the bus cycle (%.9g us: period x sync_every %d) is not an interpolation period "
                "0x60C2 can say (a whole number of us, value 0 .. 255 times a power of ten)\n",
                (double)period_ns * can->sync_every / 1000.0, can->sync_every);
        return -1;
    }
    kd_can_budget_of(can, period_ns, &budget);
    if (kd_can_budget_check(&budget, &use, why, sizeof why) != 0) {
        where_in(path, 0);
        fprintf(stderr, "controller.can: %s\n", why);
        return -1;
    }
    return 0;
}
