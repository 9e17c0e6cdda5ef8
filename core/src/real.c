/* SPDX-License-Identifier: BSD-3-Clause */
/* real.c - the one called copy of kc_sincos (kinctl/real.h), for code built
 * for size; the rest of the scalar layer is inline in the header. */
#include "kinctl/real.h"

void kc_sincos_outline(kc_real x, kc_real *s, kc_real *c) { kc_sincos_inline(x, s, c); }
