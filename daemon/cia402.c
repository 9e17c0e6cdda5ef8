/* SPDX-License-Identifier: BSD-3-Clause */
/* cia402.c - the CiA 402 state machine seen from the master (cia402.h):
 * CiA 402-2 figure "state machine", table "statusword bits" and table
 * "device control commands". */
#include "cia402.h"

kd_cia402_state kd_cia402_state_of(uint16_t statusword)
{
    /* Checked in the standard's order: the 0x4F masks first (bit 5, quick
     * stop, is don't-care in those states), then the 0x6F ones. */
    unsigned sw = statusword;
    if ((sw & 0x4Fu) == 0x00u)
        return KD_CIA402_NOT_READY;
    if ((sw & 0x4Fu) == 0x40u)
        return KD_CIA402_SWITCH_ON_DISABLED;
    if ((sw & 0x4Fu) == 0x0Fu)
        return KD_CIA402_FAULT_REACTION_ACTIVE;
    if ((sw & 0x4Fu) == 0x08u)
        return KD_CIA402_FAULT;
    switch (sw & 0x6Fu) {
    case 0x21u:
        return KD_CIA402_READY_TO_SWITCH_ON;
    case 0x23u:
        return KD_CIA402_SWITCHED_ON;
    case 0x27u:
        return KD_CIA402_OPERATION_ENABLED;
    case 0x07u:
        return KD_CIA402_QUICK_STOP_ACTIVE;
    default:
        return KD_CIA402_UNKNOWN;
    }
}

const char *kd_cia402_state_str(kd_cia402_state s)
{
    switch (s) {
    case KD_CIA402_NOT_READY:
        return "not ready to switch on";
    case KD_CIA402_SWITCH_ON_DISABLED:
        return "switch on disabled";
    case KD_CIA402_READY_TO_SWITCH_ON:
        return "ready to switch on";
    case KD_CIA402_SWITCHED_ON:
        return "switched on";
    case KD_CIA402_OPERATION_ENABLED:
        return "operation enabled";
    case KD_CIA402_QUICK_STOP_ACTIVE:
        return "quick stop active";
    case KD_CIA402_FAULT_REACTION_ACTIVE:
        return "fault reaction active";
    case KD_CIA402_FAULT:
        return "fault";
    case KD_CIA402_UNKNOWN:
    default:
        return "unknown state";
    }
}

static uint16_t towards_enabled(kd_cia402_state s, uint16_t prev)
{
    switch (s) {
    case KD_CIA402_FAULT:
        /* Transition 15 on the rising edge of bit 7. */
        return (prev & KD_CIA402_CW_FAULT_RESET) ? KD_CIA402_CW_DISABLE_VOLTAGE : KD_CIA402_CW_FAULT_RESET;
    case KD_CIA402_SWITCH_ON_DISABLED:
        return KD_CIA402_CW_SHUTDOWN; /* 2 */
    case KD_CIA402_READY_TO_SWITCH_ON:
        return KD_CIA402_CW_SWITCH_ON; /* 3 */
    case KD_CIA402_SWITCHED_ON:
    case KD_CIA402_OPERATION_ENABLED:
        return KD_CIA402_CW_ENABLE_OPERATION; /* 4, then hold */
    case KD_CIA402_QUICK_STOP_ACTIVE:
        /* Quick stop is left through switch on disabled (12): transition
         * 16 is optional in CiA 402. */
    case KD_CIA402_NOT_READY:
    case KD_CIA402_FAULT_REACTION_ACTIVE:
    case KD_CIA402_UNKNOWN:
    default:
        return KD_CIA402_CW_DISABLE_VOLTAGE;
    }
}

uint16_t kd_cia402_controlword(kd_cia402_state s, kd_cia402_goal goal, uint16_t prev_controlword)
{
    switch (goal) {
    case KD_CIA402_GOAL_ENABLED:
        return towards_enabled(s, prev_controlword);
    case KD_CIA402_GOAL_QUICK_STOP:
        /* From operation enabled (11) and in quick stop active (hold), bit
         * 2 clear; elsewhere quick stop leads to switch on disabled (7, 10)
         * as well, and a fault stays a fault. */
        return KD_CIA402_CW_QUICK_STOP;
    case KD_CIA402_GOAL_DISABLED:
    default:
        return KD_CIA402_CW_DISABLE_VOLTAGE;
    }
}
