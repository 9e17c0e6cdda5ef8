/* SPDX-License-Identifier: BSD-3-Clause */
/* cia402.h - the CiA 402 power state machine as a master sees it: the
 * statusword (0x6041) decoded into a state with the standard's masks, and
 * the controlword (0x6040) of the next transition towards a wanted state.
 * Pure functions, no frame, no clock: safe to call in the cycle.
 *
 * Statusword masks (CiA 402-2, 0x6041 bits 0-3, 5, 6):
 *   mask 0x4F value 0x00  not ready to switch on
 *   mask 0x4F value 0x40  switch on disabled
 *   mask 0x6F value 0x21  ready to switch on
 *   mask 0x6F value 0x23  switched on
 *   mask 0x6F value 0x27  operation enabled
 *   mask 0x6F value 0x07  quick stop active
 *   mask 0x4F value 0x0F  fault reaction active
 *   mask 0x4F value 0x08  fault
 * Bit 12 in cyclic synchronous position: the drive follows the target;
 * bit 13: following error.
 *
 * Controlword commands (0x6040 bits 0-3, 7):
 *   shutdown 0x06 (transitions 2, 6, 8), switch on 0x07 (3), enable
 *   operation 0x0F (4, 16), disable voltage 0x00 (7, 9, 10, 12), quick
 *   stop 0x02 (bit 2 clear: 7, 10, 11), fault reset 0x80 (15, on the
 *   rising edge of bit 7: the master sends 0x00 first, then 0x80).
 */
#ifndef KINCTL_DAEMON_CIA402_H
#define KINCTL_DAEMON_CIA402_H

#include <stdint.h>

typedef enum kd_cia402_state {
    KD_CIA402_NOT_READY = 0,
    KD_CIA402_SWITCH_ON_DISABLED,
    KD_CIA402_READY_TO_SWITCH_ON,
    KD_CIA402_SWITCHED_ON,
    KD_CIA402_OPERATION_ENABLED,
    KD_CIA402_QUICK_STOP_ACTIVE,
    KD_CIA402_FAULT_REACTION_ACTIVE,
    KD_CIA402_FAULT,
    KD_CIA402_UNKNOWN /* a statusword matching no mask */
} kd_cia402_state;

/* What the master wants of a drive. */
typedef enum kd_cia402_goal {
    KD_CIA402_GOAL_ENABLED = 0, /* operation enabled (through fault reset if faulted) */
    KD_CIA402_GOAL_QUICK_STOP,  /* quick stop from operation enabled, else hold disabled */
    KD_CIA402_GOAL_DISABLED     /* switch on disabled (disable voltage) */
} kd_cia402_goal;

#define KD_CIA402_CW_SHUTDOWN 0x0006u
#define KD_CIA402_CW_SWITCH_ON 0x0007u
#define KD_CIA402_CW_ENABLE_OPERATION 0x000Fu
#define KD_CIA402_CW_DISABLE_VOLTAGE 0x0000u
#define KD_CIA402_CW_QUICK_STOP 0x0002u
#define KD_CIA402_CW_FAULT_RESET 0x0080u

#define KD_CIA402_SW_TARGET_FOLLOWED 0x1000u /* bit 12 in CSP */
#define KD_CIA402_SW_FOLLOWING_ERROR 0x2000u /* bit 13 in CSP */

/* The state a statusword says. */
kd_cia402_state kd_cia402_state_of(uint16_t statusword);

/* The state's name ("operation enabled"), for reasons and logs. */
const char *kd_cia402_state_str(kd_cia402_state s);

/* The controlword to send to a drive in state s that should reach goal,
 * given the controlword sent last (prev_controlword: a fault reset needs
 * bit 7's rising edge, so from fault it answers 0x00 when the previous
 * controlword had bit 7 set and 0x80 otherwise). In the goal state it
 * answers the controlword that holds it. In fault reaction active or an
 * unknown state: disable voltage (the drive moves on its own). */
uint16_t kd_cia402_controlword(kd_cia402_state s, kd_cia402_goal goal, uint16_t prev_controlword);

#endif
