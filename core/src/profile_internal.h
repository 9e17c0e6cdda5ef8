/* SPDX-License-Identifier: BSD-3-Clause */
/* profile_internal.h - what the motion laws of profile.c and scurve.c
 * share: the tick rule of kinctl/profile.h and the evaluation's rule of
 * ticks and times. */
#ifndef KINCTL_PROFILE_INTERNAL_H
#define KINCTL_PROFILE_INTERNAL_H

#include <stdint.h>

#include "kinctl/real.h"
#include "kinctl/status.h"

/* First tick k with k dt >= T (T >= 0, dt > 0), on the grid the
 * evaluation uses, or -1 when that exceeds KC_PROFILE_MAX_TICKS. */
int64_t kc_profile_ticks(kc_real T, kc_real dt);

/* Which state tick k of a law of ticks ticks of dt shows: KC_E_ARG for
 * k < 0, KC_DONE (the end) for k >= ticks, else KC_OK with *t = k dt. */
kc_status kc_profile_tick(int64_t k, int64_t ticks, kc_real dt, kc_real *t);

/* The same by time for a law of duration T: KC_E_ARG unless t >= 0 (NaN
 * included), KC_DONE for t >= T, else KC_OK. */
kc_status kc_profile_time(kc_real t, kc_real T);

#endif /* KINCTL_PROFILE_INTERNAL_H */
