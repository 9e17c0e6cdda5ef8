/* SPDX-License-Identifier: BSD-3-Clause */
/* ik_rolled.c - the damped least-squares kernel (ik_internal.h) with the
 * task size a variable and plain loops: ik.c calls it for the position and
 * axis tasks when built for size. A file of its own because the unrolling
 * pragmas of the kernel's loops are fixed where the kernel is read; here
 * linalg_internal.h reads them as nothing. */
#define KC_LINALG_ROLLED
#include "ik_internal.h"

kc_real kc_ik_dls_rolled(const kc_ik_problem *p, kc_real jt[6][KC_MAX_JOINTS], const kc_real *u, kc_real lambda2,
                         kc_real null_scale, kc_real null_bound, const kc_real *q, const uint8_t *frozen, kc_real *dq)
{
    return kc_ik_dls_kernel(p, jt, u, lambda2, null_scale, null_bound, q, frozen, dq, p->r);
}
