/* SPDX-License-Identifier: BSD-3-Clause */
/* canopen_boot.h - bringing one CiA 402 drive from power-on to NMT
 * operational as its CANopen master: boot-up, identity checks, then the
 * configuration as a table of expedited SDO writes, each read back, then
 * NMT start. Caller-owned and pure, like canopen_sdo.h: frames in through
 * kd_boot_rx, out into the caller's buffer (at most KD_BOOT_OUT_MAX per
 * call), time passed in through kd_boot_process. One kd_boot per drive;
 * drives boot side by side.
 *
 * Sequence (CiA 301 and CiA 402, the order of lely-core's and python
 * canopen's masters):
 *   1. NMT reset communication (0x000: 82 node) and the boot-up (0x700 +
 *      node: 00); or, without the reset, the boot-up or any heartbeat (a
 *      drive already up: one in operational or stopped is sent NMT enter
 *      pre-operational, 80 node, first).
 *   2. 0x1000 device type under a mask (CiA 402: 0x0192 in the low 16
 *      bits), 0x1018:1..4 identity where configured.
 *   3. Each PDO the master uses (CiA 301 7.5.2.35/36: a PDO's mapping
 *      changes only while the PDO is invalid and sub 0 is 0):
 *      COB-ID with bit 31 set (invalid), transmission type, mapping sub 0
 *      = 0, the entries, sub 0 = n, COB-ID without bit 31 (valid).
 *      RPDO k (1..2) COB-ID 0x100 + 0x100 k + node, TPDO k 0x080 + 0x100 k
 *      + node (the CiA 301 predefined connection set).
 *      Then every other PDO of the predefined set (RPDO and TPDO 1..4) is
 *      made invalid, so that a drive's factory PDOs do not load the bus;
 *      these writes are optional: a drive that has no such PDO, or refuses,
 *      keeps it as it is.
 *   4. 0x6060 = 8 (cyclic synchronous position), 0x60C2 interpolation
 *      period (value:index, value * 10^index s); 0x1019 SYNC counter
 *      overflow where set, after 0x1006 = 0 (CiA 301: 0x1019 changes only
 *      while 0x1006 is 0; optional, for drives without 0x1006); 0x1006
 *      communication cycle period where set; 0x1017
 *      producer heartbeat, 0x1016:1 consumer heartbeat of the master
 *      (master id << 16 | ms), 0x6007 reaction to a lost master, then the
 *      configuration's own writes (0x6065, 0x607D, 0x605A, vendor objects).
 *   5. NMT start (0x000: 01 node).
 * Every write is read back by an upload and compared (COB-IDs on bits 31
 * and 0..10: drives may set bit 30, "no RTR"). A refusal stops the boot with
 * the drive's abort code, a wrong value with the value read. The SDO
 * client sends a request the drive does not answer again (canopen_sdo.h:
 * KD_SDO_SENDS in all) before the boot fails.
 */
#ifndef KINCTL_DAEMON_CANOPEN_BOOT_H
#define KINCTL_DAEMON_CANOPEN_BOOT_H

#include <stddef.h>
#include <stdint.h>

#include <linux/can.h>

#include "canopen_sdo.h"

#define KD_BOOT_PDOS 2        /* RPDOs and TPDOs per drive the master configures */
#define KD_BOOT_MAP_MAX 8     /* mapping entries per PDO (CiA 301) */
#define KD_BOOT_EXTRA_MAX 16  /* the configuration's own writes per drive */
#define KD_BOOT_STEPS_MAX 96  /* checks and writes of one boot */
#define KD_BOOT_OUT_MAX 2     /* frames out of one call: NMT and a request, or an abort and the request again */

#define KD_NMT_ID 0x000u
#define KD_NMT_START 0x01u
#define KD_NMT_STOP 0x02u
#define KD_NMT_ENTER_PRE_OPERATIONAL 0x80u
#define KD_NMT_RESET_COMMUNICATION 0x82u
#define KD_HEARTBEAT_BASE 0x700u

/* Results: 0 done (NMT start sent), positive under way, negative failed. */
#define KD_BOOT_DONE 0
#define KD_BOOT_WAITING 1
#define KD_BOOT_E_NO_BOOTUP (-1) /* no boot-up (or heartbeat) within bootup_timeout_us */
#define KD_BOOT_E_ABORTED (-2)   /* the drive aborted an SDO: sdo.abort_code */
#define KD_BOOT_E_SDO (-3)       /* no SDO answer, or one the client cannot take (aborted by us) */
#define KD_BOOT_E_MISMATCH (-4)  /* a check or read-back found another value: got */
#define KD_BOOT_E_ARG (-5)       /* a configuration that cannot be written (kd_boot_init) */

/* A write of size (1..4) bytes. */
typedef struct kd_boot_write {
    uint16_t index;
    uint8_t subindex;
    uint8_t size;
    uint32_t value;
} kd_boot_write;

typedef struct kd_boot_pdo {
    int n_map;                      /* 0 .. KD_BOOT_MAP_MAX */
    uint32_t map[KD_BOOT_MAP_MAX];  /* index << 16 | subindex << 8 | bits */
    int transmission_type;          /* 0 .. 240 synchronous (TPDO: every N-th SYNC), 254, 255 */
} kd_boot_pdo;

typedef struct kd_boot_cfg {
    int node;                    /* 1 .. 127 */
    int reset_communication;     /* 1: NMT reset communication first */
    int configure;               /* 1: steps 3 and 4; 0: the checks of step 2 only (a drive configured by other means) */
    uint32_t device_type;        /* 0x1000 expected under device_type_mask */
    uint32_t device_type_mask;
    uint32_t identity[4];        /* 0x1018:1..4 expected; 0: unchecked */
    int n_rpdo;                  /* RPDO1 .. RPDOn configured, 0 .. KD_BOOT_PDOS */
    kd_boot_pdo rpdo[KD_BOOT_PDOS];
    int n_tpdo;
    kd_boot_pdo tpdo[KD_BOOT_PDOS];
    uint32_t interpolation_us;   /* 0x60C2; 0: not written */
    uint32_t cycle_period_us;    /* 0x1006; 0: not written */
    int sync_overflow;           /* 0x1019 (0: empty SYNC, 2..240: counter); -1: not written */
    uint16_t heartbeat_ms;       /* 0x1017 */
    int master_id;               /* 1 .. 127 */
    uint16_t consumer_ms;        /* 0x1016:1; 0: not written */
    int lost_master_reaction;    /* 0x6007 (int16); -1: not written */
    int n_extra;
    kd_boot_write extra[KD_BOOT_EXTRA_MAX];
    uint32_t bootup_timeout_us;  /* > 0 */
    uint32_t sdo_timeout_us;     /* > 0 */
} kd_boot_cfg;

/* One check (upload and compare) or write (download, upload, compare). */
typedef struct kd_boot_step {
    int write;
    uint16_t index;
    uint8_t subindex;
    uint8_t size;
    uint32_t value;
    uint32_t mask;      /* compared bits */
    int optional;       /* a refusal or another value read back skips it */
    const char *what;   /* "RPDO1 COB-ID (invalid)", for the reason */
} kd_boot_step;

typedef struct kd_boot {
    kd_boot_cfg cfg;
    kd_boot_step step[KD_BOOT_STEPS_MAX];
    int n_steps;
    int at;             /* the step under way */
    int phase;          /* private: where the sequence is */
    uint32_t waited_us; /* for the boot-up */
    kd_sdo sdo;
    int result;         /* the last result returned */
    uint32_t got;       /* KD_BOOT_E_MISMATCH: the value read */
} kd_boot;

/* The defaults for node: reset communication, configure, device type 0x0192 under
 * 0x0000FFFF, no identity, RPDO1 = controlword + target position
 * (0x60400010, 0x607A0020, type 1), TPDO1 = statusword + position actual
 * (0x60410010, 0x60640020, type 1), 0x60C2 1 ms, heartbeat 100 ms, master
 * 127 watched for 500 ms, 0x6007 = 3 (quick stop), boot-up within 5 s,
 * SDO answers within 500 ms. */
kd_boot_cfg kd_boot_cfg_default(int node);

/* The interpolation period us as CiA 402's 0x60C2 value (uint8) and index
 * (int8, power of ten, -6 .. 0): the largest index up to -3 (milliseconds)
 * that holds it exactly, a larger one only where the value would exceed
 * 255 (1000 us: 1, -3; 250 us: 25, -5; 2500 us: 25, -4). Returns 0, or -1
 * when no value 0..255 holds it (e.g. 256 us). */
int kd_boot_interpolation(uint32_t us, uint8_t *value, int8_t *index);

/* Sets up b from cfg (copied): the step table. Returns 0 or KD_BOOT_E_ARG
 * (a node or master id, a PDO, an interpolation period or a size out of
 * range). */
int kd_boot_init(kd_boot *b, const kd_boot_cfg *cfg);

/* Starts: the NMT reset into out (*n_out 1) or nothing (waits for the
 * drive). Returns KD_BOOT_WAITING. */
int kd_boot_start(kd_boot *b, struct can_frame *out, int *n_out);

/* Takes a received frame (any id; others are ignored). Returns
 * KD_BOOT_WAITING, KD_BOOT_DONE (NMT start in out) or a KD_BOOT_E_*;
 * frames to send in out[0 .. *n_out). After the end it returns the
 * result again and sends nothing. */
int kd_boot_rx(kd_boot *b, const struct can_frame *f, struct can_frame *out, int *n_out);

/* Lets elapsed_us pass: boot-up and SDO timeouts. Same returns. */
int kd_boot_process(kd_boot *b, uint32_t elapsed_us, struct can_frame *out, int *n_out);

/* What went wrong, naming the node, object and code or value ("node 3:
 * SDO write 0x6060:00 (modes of operation) aborted by the drive with
 * 0x06090030: invalid value for parameter"; a timeout with the number of
 * sends); "" while under way or done. */
void kd_boot_why(const kd_boot *b, char *buf, size_t size);

#endif
