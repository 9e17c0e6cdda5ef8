/* profile_internal.h - what the motion laws of profile.c and scurve.c
 * share: the tick rule of kinctl/profile.h. */
#ifndef KINCTL_PROFILE_INTERNAL_H
#define KINCTL_PROFILE_INTERNAL_H

#include <stdint.h>

#include "kinctl/real.h"

/* First tick k with k dt >= T (T >= 0, dt > 0), on the grid the
 * evaluation uses, or -1 when that exceeds KC_PROFILE_MAX_TICKS. */
int64_t kc_profile_ticks(kc_real T, kc_real dt);

#endif /* KINCTL_PROFILE_INTERNAL_H */
