/* SPDX-License-Identifier: BSD-3-Clause */
/* scurve_internal.h - a time-optimal jerk-limited plan without its phases,
 * for the joint move from a moving start (interp.c), which needs every
 * joint's optimal duration but lays out only the slowest joint's optimum:
 * the others are stretched to its duration. Private to the core. */
#ifndef KINCTL_SCURVE_INTERNAL_H
#define KINCTL_SCURVE_INTERNAL_H

#include "kinctl/scurve.h"

/* As kc_scurve_plan, but *prof gets only what kc_scurve_stretch reads of
 * the plan it stretches: p0, v0, a0, p1, vp, gap, T and dt (the same
 * values as kc_scurve_plan's, T within its rounding: the duration the
 * choice between the plans was made with, which the profile laid out
 * from the header lasts exactly), with n = -1 for the phases not laid out and
 * ticks = -1 (not counted: a duration beyond KC_PROFILE_MAX_TICKS is
 * KC_E_CAPACITY when the stretch lays out its profile).
 * Such a plan is never evaluated: kc_scurve_stretch makes a profile of it,
 * laying out the optimum itself for a duration at most its T.
 * Errors as kc_scurve_plan's. */
kc_status kc_scurve_plan_time(kc_scurve *prof, kc_real p0, kc_real v0, kc_real a0, kc_real p1, kc_real vmax,
                              kc_real amax, kc_real jmax, kc_real dt);

#endif /* KINCTL_SCURVE_INTERNAL_H */
