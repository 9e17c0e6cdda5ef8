/* SPDX-License-Identifier: BSD-3-Clause */
/* vectors_env.c - tells the unit tests on the board where the reference
 * vectors are, as ctest's KINCTL_VECTORS does on the host: the board has no
 * environment of its own, so the directory (read through semihosting) is
 * compiled in and set before main. */
#define _POSIX_C_SOURCE 200112L /* setenv */
#include <stdlib.h>

#ifndef KC_MCU_VECTORS_DIR
#error "KC_MCU_VECTORS_DIR must name the reference vectors directory"
#endif

__attribute__((constructor)) static void set_vectors_dir(void)
{
    setenv("KINCTL_VECTORS", KC_MCU_VECTORS_DIR, 1);
}
