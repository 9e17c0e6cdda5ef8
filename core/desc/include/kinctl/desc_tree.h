/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/desc_tree.h - the description readers over a file already parsed
 * (kinctl/cfgread.h), for a program whose file holds the robot beside
 * sections of its own: kinctld parses its configuration once and hands the
 * robot and controller.zones settings here.
 *
 * Formats, messages and outputs as kinctl/desc.h's loaders: on error the
 * outputs are untouched and err (may be NULL) holds "<file>:<line>:
 * <problem>", file naming the input where a setting has no file of its own.
 * Not installed (cmake/install.cmake): it exposes libconfig. Not for the
 * cycle.
 */
#ifndef KINCTL_DESC_TREE_H
#define KINCTL_DESC_TREE_H

#include <libconfig.h>

#include "kinctl/decls.h"
#include "kinctl/desc.h"

KC_BEGIN_DECLS

/* The robot group (robot = { ... }) into chain (built and checked) and info
 * (may be NULL). */
kc_status kc_desc_read_robot(const config_setting_t *robot, const char *file, kc_chain *chain, kc_desc_info *info,
                             kc_desc_error *err);

/* The zones group (controller.zones = { ... }; NULL: none) into set and
 * info (may be NULL), margin and near kc_zone_set_init's unless given. */
kc_status kc_desc_read_zones(const config_setting_t *zones, const char *file, kc_zone_set *set,
                             kc_desc_zone_info *info, kc_desc_error *err);

KC_END_DECLS

#endif /* KINCTL_DESC_TREE_H */
