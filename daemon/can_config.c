/* SPDX-License-Identifier: BSD-3-Clause */
/* can_config.c - controller.can: read, then checked against the arm
 * (can_config.h). */
#include "can_config.h"

#include <libconfig.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "kinctl/cfgread.h"

kd_can_cfg kd_can_cfg_default(void)
{
    kd_can_cfg can;
    memset(&can, 0, sizeof can);
    can.sync_every = 1;
    can.master_id = 127;
    can.heartbeat_ms = 100.0;
    can.on_error_stop = 1;
    can.feedback = 0;
    return can;
}

/* controller.can (can_config.h). The joints' count and ranges are checked
 * against the arm in kd_can_cfg_check, once the arm is known. */
int kd_can_cfg_read(kc_cfg *r, const config_setting_t *g, kd_can_cfg *can)
{
    static const char *const keys[] = {"interface", "sync_every", "master_id", "heartbeat_ms", "on_error",
                                       "joints", "feedback", NULL};
    static const char *const joint_keys[] = {"node", "counts_per_unit", "sign", "offset_counts", NULL};
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
    if (kc_cfg_lookup_int(r, g, "sync_every", "controller.can", 1, 1000, &can->sync_every) != 0 ||
        kc_cfg_lookup_int(r, g, "master_id", "controller.can", 1, 127, &can->master_id) != 0 ||
        kc_cfg_lookup_number(r, g, "heartbeat_ms", "controller.can", 0.0, 60000.0, &can->heartbeat_ms) != 0 ||
        kc_cfg_lookup_string(r, g, "on_error", "controller.can", &str, &s) != 0)
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

int kd_can_cfg_check(const kd_can_cfg *can, const kc_chain *chain, const char *robot_name, const char *path)
{
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
    return 0;
}
