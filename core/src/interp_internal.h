/* SPDX-License-Identifier: BSD-3-Clause */
/* interp_internal.h - the joint move's planning for callers that own
 * storage for a plan (the controller): kc_interp_joint_plan_cfg without its
 * local copy. A plan holds a jerk-limited profile a joint (2.4 KB in the
 * microcontroller's small configuration), and that copy would be the
 * deepest part of a controller tick's stack. Private to the core. */
#ifndef KINCTL_INTERP_INTERNAL_H
#define KINCTL_INTERP_INTERNAL_H

#include "kinctl/interp.h"

/* kc_interp_joint_plan_cfg into *out directly: the same plan on KC_OK;
 * on error *out is left partly written (scratch), never read. */
kc_status kc_interp_joint_plan_cfg_into(kc_interp_joint *out, const kc_interp_joint_cfg *cfg);

#endif /* KINCTL_INTERP_INTERNAL_H */
