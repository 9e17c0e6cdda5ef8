/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * systick.h - instruction counts on QEMU's MPS2 boards. Under -icount
 * shift=0 QEMU advances its virtual clock one nanosecond per instruction;
 * SysTick on the 25 MHz CPU clock then counts once per 40 instructions, so
 * one call is known to +-40 instructions and a mean over n calls to 40 / n.
 * (QEMU models no cycle counter: these are instructions, not cycles.)
 */
#ifndef KINCTL_MCU_SYSTICK_H
#define KINCTL_MCU_SYSTICK_H

#include <stdint.h>

#define KC_SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define KC_SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define KC_SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define KC_SYST_TICK_INSNS 40u /* 1 GHz of instructions / 25 MHz */

static inline void kc_systick_start(void)
{
    KC_SYST_RVR = 0x00FFFFFFu;
    KC_SYST_CVR = 0u;
    KC_SYST_CSR = 5u; /* enabled, CPU clock, no interrupt */
}

/* SysTick counts down, 24 bits; a call must be shorter than a wrap
 * (2^24 40 = 671 million instructions). */
static inline uint32_t kc_systick_now(void) { return KC_SYST_CVR; }

static inline uint32_t kc_systick_insns(uint32_t from, uint32_t to)
{
    return ((from - to) & 0x00FFFFFFu) * KC_SYST_TICK_INSNS;
}

#endif /* KINCTL_MCU_SYSTICK_H */
