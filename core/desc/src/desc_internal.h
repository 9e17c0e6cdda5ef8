/* SPDX-License-Identifier: BSD-3-Clause */
/* desc_internal.h - what the description library's readers share: the
 * state of one reading, and the shapes and names that link volumes
 * (desc.c) and forbidden zones (zones.c) are written with. */
#ifndef KINCTL_DESC_INTERNAL_H
#define KINCTL_DESC_INTERNAL_H

#include "kinctl/cfgread.h"
#include "kinctl/desc.h"

/* One reading: the lookups' reader (settings named "where: key") and the
 * angle unit of the section being read (1: deg). */
typedef struct kc_desc_reader {
    kc_cfg cfg;
    int deg;
} kc_desc_reader;

/* kc_cfg_fail and kc_cfg_fail_at on a kc_desc_reader. */
#define fail_at(r, s, st, ...) kc_cfg_fail_at(&(r)->cfg, (s), (st), __VA_ARGS__)
#define fail(r, s, ...) kc_cfg_fail(&(r)->cfg, (s), __VA_ARGS__)

/* A fresh reader of the input called file (messages), into err (may be
 * NULL; cleared). */
kc_desc_reader kc_desc_reader_make(const char *file, kc_desc_error *err);

/* One shape group (kinctl/desc.h's shapes; halfspace only for a zone);
 * rpy in the reader's angle unit. */
kc_status kc_desc_read_shape(kc_desc_reader *r, const config_setting_t *g, const char *where, int zone,
                             kc_shape *out);

/* An optional name key of group g (a joint, volume or zone) into dest
 * (KC_DESC_NAME_LEN bytes), left as it is when absent. */
kc_status kc_desc_read_name(kc_desc_reader *r, const config_setting_t *g, const char *where, char *dest);

/* R = Rz(rpy[2]) Ry(rpy[1]) Rx(rpy[0]) (URDF's rpy order), rpy in rad. */
void kc_desc_rpy_to_mat3(const kc_real *rpy, kc_mat3 *R);

#endif
