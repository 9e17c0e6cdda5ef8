/* SPDX-License-Identifier: BSD-3-Clause */
/* size_internal.h - KC_SIZE_NOINLINE: a static function that GCC, building
 * for size (-Os), would inline at each of its callers kept as one copy
 * instead (each use is measured: docs/microcontroller.md, "Budgets").
 * Built for speed, the compiler inlines as it sees fit. Private to the
 * core. */
#ifndef KINCTL_SIZE_INTERNAL_H
#define KINCTL_SIZE_INTERNAL_H

#if defined(__OPTIMIZE_SIZE__) && defined(__GNUC__)
#define KC_SIZE_NOINLINE __attribute__((noinline))
#else
#define KC_SIZE_NOINLINE
#endif

#endif /* KINCTL_SIZE_INTERNAL_H */
