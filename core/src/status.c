/* SPDX-License-Identifier: BSD-3-Clause */
/* status.c - readable texts for kc_status. */
#include "kinctl/status.h"

const char *kc_status_str(kc_status status)
{
    switch (status) {
    case KC_OK: return "ok";
    case KC_DONE: return "done";
    case KC_MORE: return "unfinished";
    case KC_E_ARG: return "invalid argument (NULL, NaN, infinite or out of domain)";
    case KC_E_LIMIT: return "a joint or Cartesian limit would be violated";
    case KC_E_SINGULAR: return "singular configuration or degenerate geometry";
    case KC_E_NOCONVERGE: return "did not converge within the iteration bound";
    case KC_E_CAPACITY: return "a compile-time capacity is exceeded";
    case KC_E_STATE: return "not allowed in the current state";
    case KC_E_UNREACHABLE: return "target outside the reachable workspace";
    }
    return "unknown status";
}
