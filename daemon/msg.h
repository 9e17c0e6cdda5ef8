/* SPDX-License-Identifier: BSD-3-Clause */
/* msg.h - kinctld's message layer: the only path by which the daemon turns an
 * LCM datagram into a message, and a message into a datagram.
 *
 * The types are lcmtypes/<name>.lcm (package kinctl), generated into C by
 * lcm-gen without the _publish/_subscribe stubs (kinctl_lcmtypes_c). LCM's
 * generated decoders allocate for strings and variable-length arrays and
 * trust the lengths on the wire, so a hostile datagram can crash or exhaust
 * them. Therefore:
 *
 *   - every type a client sends (goal_*_t, command_t) has only fixed-size
 *     fields: arrays sized by a const declared in the type, plus a count;
 *     its encoded size is a constant, and decoding writes in place;
 *   - kd_msg_decode() checks, in this order: the datagram is at least the
 *     8-byte fingerprint; the fingerprint is the expected type's; the size
 *     equals the type's encoded size exactly (shorter: truncated, longer:
 *     oversized); the generated *_decode() consumed exactly the datagram;
 *     then the contents: counts in range and dimensions consistent, enum
 *     values known, every double on the wire finite (also the unused tail of
 *     an array), and the few ranges the message definition itself fixes
 *     (scales in [0, 1], speeds and accelerations >= 0, timeout > 0,
 *     goal_id != 0). What depends on the arm (joint count, limits,
 *     reachability, knot times increasing, unit quaternions) is for the
 *     controller to judge;
 *   - status_t carries a string and is only ever sent by the daemon:
 *     kd_msg_decode() refuses it (clients decode it with their bindings).
 *
 * Encoding writes into a caller-provided buffer and never allocates; the
 * daemon does it on its I/O thread. Nothing here locks, logs or reads a
 * clock. Every function is reentrant once kd_msg_init() has run (the
 * generated code computes each fingerprint lazily into a static on first use;
 * kd_msg_init() does all of them up front, before threads start).
 */
#ifndef KINCTL_DAEMON_MSG_H
#define KINCTL_DAEMON_MSG_H

#include <stddef.h>
#include <stdint.h>

#include "kinctl_command_t.h"
#include "kinctl_goal_arc_t.h"
#include "kinctl_goal_joint_t.h"
#include "kinctl_goal_line_t.h"
#include "kinctl_goal_path_t.h"
#include "kinctl_goal_servo_t.h"
#include "kinctl_setpoint_t.h"
#include "kinctl_stats_t.h"
#include "kinctl_status_t.h"

/* The message types. Those before KD_MSG_SETPOINT are sent by clients. */
typedef enum kd_msg_type {
    KD_MSG_GOAL_JOINT = 0, /* kinctl_goal_joint_t */
    KD_MSG_GOAL_LINE,      /* kinctl_goal_line_t */
    KD_MSG_GOAL_ARC,       /* kinctl_goal_arc_t */
    KD_MSG_GOAL_PATH,      /* kinctl_goal_path_t */
    KD_MSG_GOAL_SERVO,     /* kinctl_goal_servo_t */
    KD_MSG_COMMAND,        /* kinctl_command_t */
    KD_MSG_SETPOINT,       /* kinctl_setpoint_t (daemon -> clients) */
    KD_MSG_STATUS,         /* kinctl_status_t (daemon -> clients; has a string) */
    KD_MSG_STATS,          /* kinctl_stats_t (daemon -> clients) */
    KD_MSG_TYPE_COUNT
} kd_msg_type;

/* Outcome of a decode or an encode: 0 ok, negative an error. */
typedef enum kd_msg_status {
    KD_MSG_OK = 0,
    KD_MSG_E_ARG = -1,         /* NULL pointer or unknown type */
    KD_MSG_E_TYPE = -2,        /* type never decoded here (status_t) */
    KD_MSG_E_TRUNCATED = -3,   /* datagram shorter than the type */
    KD_MSG_E_OVERSIZED = -4,   /* datagram longer than the type */
    KD_MSG_E_FINGERPRINT = -5, /* fingerprint of another type, or garbage */
    KD_MSG_E_DECODE = -6,      /* generated decoder failed or size mismatch */
    KD_MSG_E_COUNT = -7,       /* count out of range or dimension inconsistent */
    KD_MSG_E_ENUM = -8,        /* unknown enum value */
    KD_MSG_E_NONFINITE = -9,   /* a double is NaN or infinite */
    KD_MSG_E_RANGE = -10,      /* a value outside the range the type defines */
    KD_MSG_E_SPACE = -11,      /* encode: buffer too small */
    KD_MSG_E_ENCODE = -12      /* encode: the generated encoder failed */
} kd_msg_status;

/* Longest reason kd_msg_decode() writes, with its NUL. */
#define KD_MSG_REASON_SIZE 160
/* Longest status_t.reason kd_msg_encode() sends (longer ones are cut), without
 * its NUL. */
#define KD_MSG_STATUS_REASON_MAX 255
/* A buffer of this size holds any encoded kinctl message (checked by the
 * tests); the largest is goal_path_t. */
#define KD_MSG_MAX_SIZE 5120

/* Any message, for callers that decode into one storage whatever the type. */
typedef union kd_msg_any {
    kinctl_goal_joint_t goal_joint;
    kinctl_goal_line_t goal_line;
    kinctl_goal_arc_t goal_arc;
    kinctl_goal_path_t goal_path;
    kinctl_goal_servo_t goal_servo;
    kinctl_command_t command;
    kinctl_setpoint_t setpoint;
    kinctl_stats_t stats;
    kinctl_status_t status;
} kd_msg_any;

/* What the message layer knows of a type. */
typedef struct kd_msg_info {
    const char *name;    /* LCM type name without package, "goal_joint_t" */
    const char *channel; /* channel suffix, "GOAL_JOINT": the daemon prefixes it */
    int from_client;     /* 1: sent by clients, fixed size, decodable here */
    size_t size;         /* encoded size in bytes (status_t: with reason "") */
} kd_msg_info;

/* Compute every fingerprint once. Call before any thread uses this module;
 * calling it again is harmless. */
void kd_msg_init(void);

/* Facts about a type; NULL for a value outside kd_msg_type. */
const kd_msg_info *kd_msg_type_info(kd_msg_type type);

/* Short fixed text for a status ("truncated", "bad fingerprint"...). */
const char *kd_msg_status_str(kd_msg_status status);

/* The fingerprint (first 8 bytes, big-endian on the wire) of a type, 0 for
 * an unknown one. */
int64_t kd_msg_fingerprint(kd_msg_type type);

/* Which type a datagram's fingerprint names: KD_MSG_OK and *type set, or
 * KD_MSG_E_TRUNCATED (< 8 bytes) / KD_MSG_E_FINGERPRINT (no kinctl type).
 * Looks at the first 8 bytes only: decode with kd_msg_decode() after. */
kd_msg_status kd_msg_identify(const void *buf, size_t len, kd_msg_type *type);

/* The goal_id of a raw datagram of a goal type (KD_MSG_GOAL_*: bytes
 * 16..23, after the fingerprint and utime), whatever else is wrong with it;
 * 0 when the type carries none or the datagram is too short. */
int64_t kd_msg_goal_id(kd_msg_type type, const void *buf, size_t len);

/* Decode and validate one datagram of the given client-sent type (or
 * setpoint_t / stats_t, which are fixed size too; tools and tests use that).
 *   buf, len     the datagram as received (len in bytes)
 *   out          storage of the type's struct (or a kd_msg_any); written only
 *                on success
 *   reason       if not NULL, receives a NUL-terminated readable reason of at
 *                most reason_size bytes (KD_MSG_REASON_SIZE is enough), e.g.
 *                "goal_joint_t.n = 127 outside 0..16"; "" on success
 * Returns KD_MSG_OK or the first failed check (see the list above). Never
 * allocates; safe on any input bytes. Not for the cycle thread (it is the I/O
 * thread's work; bounded, about a microsecond). */
kd_msg_status kd_msg_decode(kd_msg_type type, const void *buf, size_t len, void *out,
                            char *reason, size_t reason_size);

/* Encode a message of any type into buf (capacity cap bytes); *len receives
 * the encoded size. status_t's reason may be NULL (sent as "") and is cut to
 * KD_MSG_STATUS_REASON_MAX bytes; nothing else is checked or changed. Returns
 * KD_MSG_OK, KD_MSG_E_ARG, KD_MSG_E_SPACE (buf too small; nothing written
 * past cap) or KD_MSG_E_ENCODE. Never allocates. */
kd_msg_status kd_msg_encode(kd_msg_type type, const void *msg, void *buf, size_t cap,
                            size_t *len);

#endif
