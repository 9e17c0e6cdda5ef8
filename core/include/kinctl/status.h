/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/status.h - the status every kinctl function returns.
 *
 * Zero is success, negative values are errors, positive values are outcomes
 * that are not errors (a motion that has finished, say). On an error the
 * function has left every output untouched.
 */
#ifndef KINCTL_STATUS_H
#define KINCTL_STATUS_H

#include "kinctl/decls.h"

KC_BEGIN_DECLS

typedef enum kc_status {
    KC_OK = 0,
    /* Non-error outcomes. */
    KC_DONE = 1,
    KC_MORE = 2, /* unfinished: call again to go on (a dry run in slices) */
    /* Errors. */
    KC_E_ARG = -1,        /* an argument is NULL, NaN, infinite or out of its domain */
    KC_E_LIMIT = -2,      /* a joint or Cartesian limit would be violated */
    KC_E_SINGULAR = -3,   /* a singular configuration or degenerate geometry */
    KC_E_NOCONVERGE = -4, /* an iterative solver ran out of iterations */
    KC_E_CAPACITY = -5,   /* a compile-time capacity (KC_MAX_...) is exceeded */
    KC_E_STATE = -6,      /* the object is not in a state that allows the call */
    KC_E_UNREACHABLE = -7 /* the target lies outside the reachable workspace */
} kc_status;

/* A short readable text for a status (never NULL): what the daemon sends back
 * as a rejection reason. Safe to call in the cycle. */
const char *kc_status_str(kc_status status);

KC_END_DECLS

#endif /* KINCTL_STATUS_H */
