/* SPDX-License-Identifier: BSD-3-Clause */
/* msg_sample.h - valid kinctl messages with pseudo-random contents, the same
 * for a given seed on every machine, for the message tests (test_msg.c and
 * the msgtool behind test_msg_python.py). */
#ifndef KINCTL_TESTS_MSG_SAMPLE_H
#define KINCTL_TESTS_MSG_SAMPLE_H

#include <stdint.h>

#include "msg.h"

/* Fills *m with a valid message of the type: every field set (array tails
 * too), counts and enums in range, doubles finite with fractional parts.
 * status_t's reason points at reason_buf (at least 64 bytes). */
void msg_sample(kd_msg_type type, uint32_t seed, kd_msg_any *m, char *reason_buf);

#endif
