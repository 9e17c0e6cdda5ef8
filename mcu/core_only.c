/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * core_only.c - the image that holds the whole core and nothing else: the
 * vector table's two words point at a reset that only spins. Never run; it
 * exists so that check_image_symbols.sh sees exactly what the core's
 * objects pull from libm and libgcc once linked.
 */
#include <stdint.h>

void kc_core_only_reset(void);
extern uint32_t __stack_top;

void kc_core_only_reset(void)
{
    for (;;) {
    }
}

__attribute__((section(".vectors"), used)) static void (*const vectors[2])(void) = {
    (void (*)(void))(uintptr_t)&__stack_top,
    kc_core_only_reset,
};
