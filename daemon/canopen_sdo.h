/* SPDX-License-Identifier: BSD-3-Clause */
/* canopen_sdo.h - an expedited SDO client (CiA 301 7.2.4): one transfer at
 * a time to one server (a drive's node id), up to 4 bytes, no segmented or
 * block transfer. Caller-owned, pure: frames come in through
 * kd_sdo_rx, go out into the caller's buffer, and time is passed in
 * (kd_sdo_process(elapsed_us)), as CANopenNode's CO_SDOclient does; no
 * socket, no clock, no allocation.
 *
 * Frames (8 bytes, index little-endian in bytes 1-2, subindex in byte 3):
 *   0x600 + node  request:  0x23/0x27/0x2B/0x2F download 4/3/2/1 bytes
 *                            (data in bytes 4-7), 0x40 upload,
 *                            0x80 abort (32-bit code in bytes 4-7)
 *   0x580 + node  response: 0x60 download done, 0x43/0x47/0x4B/0x4F
 *                            upload of 4/3/2/1 bytes, 0x42 upload without
 *                            size (4 bytes), 0x80 abort with its code
 * A request the server does not answer within timeout_us is aborted with
 * 0x05040000 (SDO protocol timed out) and sent again, KD_SDO_SENDS times
 * in all, as python canopen's client tries again: a frame lost on a busy
 * bus costs a timeout, not the transfer. Each request writes or reads one
 * whole value, so a second send changes nothing, and a late answer to the
 * first is the answer to the second. After the last send the client gives
 * up with 0x05040000. On an answer it cannot take (segmented upload, wrong
 * command) it aborts with 0x05040001 (command specifier not valid).
 *
 * A server that was only slow answers every send: the answers to a
 * transfer's earlier sends beyond the one that ended it (owed) may still
 * come while the next request is out. The server answers in order, so
 * until the next transfer's own answer, a frame that answers the last
 * transfer (its object, its kind, or an abort) is one of those and is
 * ignored; where both transfers are the same kind on the same object, that
 * may be the new transfer's own answer, which then costs a timeout and a
 * send again, never a stale value taken.
 */
#ifndef KINCTL_DAEMON_CANOPEN_SDO_H
#define KINCTL_DAEMON_CANOPEN_SDO_H

#include <stdint.h>

#include <linux/can.h>

#define KD_SDO_TX_BASE 0x600u /* client -> server */
#define KD_SDO_RX_BASE 0x580u /* server -> client */

#define KD_SDO_SENDS 3   /* sends of a request the server does not answer */
#define KD_SDO_OUT_MAX 2 /* frames out of one call: an abort and the request again */

#define KD_SDO_ABORT_TIMEOUT 0x05040000u
#define KD_SDO_ABORT_COMMAND 0x05040001u

/* Results: 0 done, positive not yet, negative failed. */
#define KD_SDO_DONE 0
#define KD_SDO_WAITING 1 /* a transfer is under way */
#define KD_SDO_IGNORED 2 /* kd_sdo_rx: not this client's frame (or none awaited) */
#define KD_SDO_E_ABORTED (-1) /* the server aborted: abort_code says why */
#define KD_SDO_E_TIMEOUT (-2) /* no answer within timeout_us: aborted by the client */
#define KD_SDO_E_PROTOCOL (-3) /* an answer the client cannot take: aborted by the client */
#define KD_SDO_E_BUSY (-4)     /* a transfer is already under way */
#define KD_SDO_E_ARG (-5)      /* bad argument (size, node id) */

typedef struct kd_sdo {
    int node;              /* server node id, 1 .. 127 */
    uint32_t timeout_us;   /* longest wait for an answer, > 0 */
    int busy;              /* a transfer is under way */
    int upload;            /* the transfer under way reads (1) or writes (0) */
    uint16_t index;        /* object of the transfer under way, or of the last one */
    uint8_t subindex;
    uint32_t elapsed_us;   /* since the request was last sent */
    int sends;             /* sends of the request under way, or of the last one */
    uint32_t value;        /* upload: the value read (zero-extended); download: the value written */
    int size;              /* bytes read or written, 1 .. 4 */
    uint32_t abort_code;   /* after KD_SDO_E_*: the abort code (the server's or ours) */
    int owed;              /* answers the last transfer's sends may still bring */
    int owed_upload;       /* ... and that transfer's kind and object */
    uint16_t owed_index;
    uint8_t owed_subindex;
} kd_sdo;

/* Sets up c for server node (1..127) with timeout_us (> 0). Returns 0 or
 * KD_SDO_E_ARG (c untouched). */
int kd_sdo_init(kd_sdo *c, int node, uint32_t timeout_us);

/* Starts writing size (1..4) bytes of value to index:subindex: the request
 * into out. Returns KD_SDO_WAITING, KD_SDO_E_BUSY or KD_SDO_E_ARG (out
 * untouched then). */
int kd_sdo_download(kd_sdo *c, uint16_t index, uint8_t subindex, uint32_t value, int size, struct can_frame *out);

/* Starts reading index:subindex: the request into out. Returns
 * KD_SDO_WAITING or KD_SDO_E_BUSY. */
int kd_sdo_upload(kd_sdo *c, uint16_t index, uint8_t subindex, struct can_frame *out);

/* Takes a received frame. Returns KD_SDO_IGNORED for a frame that is not
 * the answer awaited (another id, another object, an answer owed to the
 * last transfer: the transfer goes on),
 * KD_SDO_DONE (value and size set), KD_SDO_E_ABORTED (abort_code set), or
 * KD_SDO_E_PROTOCOL with the client's abort into out (*n_out = 1). *n_out
 * is the number of frames written to out (0 or 1). */
int kd_sdo_rx(kd_sdo *c, const struct can_frame *f, struct can_frame *out, int *n_out);

/* Lets elapsed_us pass. Returns KD_SDO_WAITING (after a timeout before
 * the last send: the client's abort and the request again into out,
 * *n_out = 2), KD_SDO_E_TIMEOUT with the client's abort into out (*n_out =
 * 1), or KD_SDO_DONE when idle. out holds KD_SDO_OUT_MAX frames. */
int kd_sdo_process(kd_sdo *c, uint32_t elapsed_us, struct can_frame *out, int *n_out);

/* The text of a CiA 301 abort code ("object does not exist in the object
 * dictionary"), or "unknown abort code". */
const char *kd_sdo_abort_str(uint32_t code);

#endif
