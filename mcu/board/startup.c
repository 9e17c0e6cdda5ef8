/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * startup.c - reset for QEMU's MPS2 boards (mps2-an386 Cortex-M4F,
 * mps2-an385 Cortex-M3) under newlib's semihosting runtime.
 *
 * The Cortex-M core loads its stack pointer and reset address from the
 * first two words of the vector table, placed at 0x0 by mps2.ld. Reset
 * enables the FPU where there is one (an FPU instruction with CP10/CP11
 * disabled faults), then hands over to newlib's rdimon crt0 (_start), which
 * zeroes .bss, opens the semihosting console, runs main and leaves through
 * semihosting's exit with main's status. .data needs no copy: QEMU loads the
 * ELF's segments at their run addresses in RAM.
 *
 * Every other exception goes to one handler that leaves with status 3, so a
 * fault ends the emulation with a failure instead of hanging it.
 */
#include <stdint.h>
#include <stdlib.h>

extern void _start(void);
extern uint32_t __stack_top;

void kc_board_reset(void);
void kc_board_fault(void);

void kc_board_reset(void)
{
#if defined(__ARM_FP)
    /* CPACR (0xE000ED88): full access to CP10 and CP11, the FPU. */
    volatile uint32_t *cpacr = (volatile uint32_t *)0xE000ED88u;
    *cpacr |= 0xFu << 20;
    __asm volatile("dsb\n\tisb" ::: "memory");
#endif
    _start();
    for (;;) {
    }
}

void kc_board_fault(void)
{
    _Exit(3);
}

/* Initial stack pointer, reset, then NMI, HardFault, MemManage, BusFault,
 * UsageFault: the exceptions a bare test program can raise. */
__attribute__((section(".vectors"), used)) static void (*const vectors[8])(void) = {
    (void (*)(void))(uintptr_t)&__stack_top,
    kc_board_reset,
    kc_board_fault,
    kc_board_fault,
    kc_board_fault,
    kc_board_fault,
    kc_board_fault,
    0,
};
