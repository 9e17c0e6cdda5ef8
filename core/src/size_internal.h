/* SPDX-License-Identifier: BSD-3-Clause */
/* size_internal.h - KC_SIZE_NOINLINE: a static function that GCC, building
 * for size (-Os), would inline at each of its callers kept as one copy
 * instead (each use is measured: docs/microcontroller.md, "Budgets").
 * Built for speed, the compiler inlines as it sees fit, but for
 * KC_SPEED_INLINE. Private to the core. */
#ifndef KINCTL_SIZE_INTERNAL_H
#define KINCTL_SIZE_INTERNAL_H

#if defined(__OPTIMIZE_SIZE__) && defined(__GNUC__)
#define KC_SIZE_NOINLINE __attribute__((noinline))
#else
#define KC_SIZE_NOINLINE
#endif

/* KC_SPEED_INLINE: a small static function on a hot path inlined at every
 * caller where code is built for speed (GCC at -O2 keeps it out of line
 * and its results in memory); built for size, one copy. */
#if !defined(__OPTIMIZE_SIZE__) && defined(__GNUC__)
#define KC_SPEED_INLINE inline __attribute__((always_inline))
#else
#define KC_SPEED_INLINE
#endif

#endif /* KINCTL_SIZE_INTERNAL_H */
