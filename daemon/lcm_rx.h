/* SPDX-License-Identifier: BSD-3-Clause */
/* lcm_rx.h - kinctld's receiver: client messages off LCM's UDP multicast
 * group, read into one fixed buffer, never a size a datagram claims.
 *
 * Why kinctld does not receive through LCM: LCM 1.5's UDP multicast
 * provider (lcm_udpm.c) allocates, on the first fragment of a fragmented
 * message, a buffer of the size that fragment's header claims (up to
 * LCM_MAX_MESSAGE_SIZE, 256 MiB), and LCM offers no lower limit. Under
 * mlockall every such allocation is faulted in and locked page by page: a few
 * kilobytes of forged fragment headers cost gigabytes of memory and seconds
 * of a deaf I/O thread. Every message a client sends kinctld is small and of
 * bounded size (lcmtypes/README.md; at most KD_MSG_MAX_SIZE bytes), and LCM
 * on Linux sends any message of up to 65,499 bytes with its channel name as
 * one "short" datagram, so a client message never needs reassembly. So
 * kinctld:
 *
 *   - publishes through LCM (lcm_publish) but never subscribes through it:
 *     LCM then never opens its receive socket or starts its receive thread;
 *   - opens its own socket on the URL's group and port (SO_REUSEADDR, as LCM
 *     does, so lcm-spy, loggers and other daemons share the port), bound to
 *     the group, with a kernel socket filter (classic BPF, SO_ATTACH_FILTER)
 *     that keeps only LCM short datagrams ("LC02") no longer than the largest
 *     client message: fragments ("LC03") and anything longer are dropped by
 *     the kernel before they take a byte of the socket's receive buffer or a
 *     wake-up of the I/O thread;
 *   - reads each datagram into one buffer of fixed size and checks it again
 *     (length, magic, a channel name terminated within LCM's 63 characters),
 *     then hands the channel and payload to the caller, which decodes it
 *     through kd_msg_decode (msg.h).
 *
 * Wire format read here (LCM's UDP multicast protocol, short message, all
 * integers big-endian): uint32 magic 0x4c433032, uint32 sequence number,
 * the channel name and a NUL byte, then the payload (the message's encoding
 * with its 8-byte fingerprint first).
 *
 * Refused, by design: a client message sent fragmented. LCM fragments only
 * messages over 65,499 bytes on Linux, far above any kinctl type; LCM on
 * macOS fragments above 1,435 bytes, so a path goal of many knots from a
 * macOS client does not reach kinctld (daemon/README.md).
 *
 * URLs: LCM's UDP multicast ones, udpm://[GROUP[:PORT]][?OPTIONS] (default
 * group 239.255.76.67, port 7667); of the options only recv_buf_size acts on
 * receiving: the socket's receive buffer is the larger of it and
 * KD_RX_RECV_BUF (bytes). Any other provider is refused at start with a
 * reason.
 *
 * Threads: one reader (the I/O thread); open and close on the main thread.
 */
#ifndef KINCTL_DAEMON_LCM_RX_H
#define KINCTL_DAEMON_LCM_RX_H

#include <stddef.h>
#include <stdint.h>

/* LCM's short-message header: magic, sequence number. */
#define KD_RX_MAGIC_SHORT 0x4c433032u
#define KD_RX_MAGIC_FRAGMENT 0x4c433033u
#define KD_RX_HEADER 8
/* LCM_MAX_CHANNEL_NAME_LENGTH (lcm.h). */
#define KD_RX_CHANNEL_MAX 63
/* The largest payload kd_rx_open accepts as its limit. */
#define KD_RX_PAYLOAD_MAX 16384
/* The least socket receive buffer asked for (bytes): a burst of goals waits
 * in the socket while the I/O thread publishes, instead of being dropped by
 * the kernel. 10,000 goals sent at once (tests/daemon/test_flood.py) take
 * about 12 MiB of socket memory at ~1.2 KiB per small datagram; with 4 MiB
 * a slow (sanitizer) build lost some of them. */
#define KD_RX_RECV_BUF (16 << 20)

typedef struct kd_rx {
    int fd;
    uint32_t datagram_max; /* header + channel + NUL + largest payload */
    int recv_buf;          /* the kernel's receive buffer, as granted (bytes) */
    /* Datagrams read, and those that passed the kernel's filter but not the
     * check here (truncated, a channel name not terminated in time). */
    int64_t datagrams, refused;
    unsigned char buf[KD_RX_HEADER + KD_RX_CHANNEL_MAX + 1 + KD_RX_PAYLOAD_MAX + 1];
} kd_rx;

/* Opens the receive socket for the LCM URL, joined to its group, with the
 * kernel filter for datagrams of at most KD_RX_HEADER + KD_RX_CHANNEL_MAX +
 * 1 + payload_max bytes (payload_max 1..KD_RX_PAYLOAD_MAX): room for
 * payload_max after the longest channel name. kd_msg_decode then holds each
 * payload to its type's exact size. Returns 0, or -1 with a reason in why (a URL of
 * another provider or malformed, a socket error with its errno text). */
int kd_rx_open(kd_rx *rx, const char *url, size_t payload_max, char *why, size_t why_size);

/* 0 when url is one kd_rx_open takes (its grammar above), else -1 with the
 * reason in why. Opens nothing. */
int kd_rx_url_check(const char *url, char *why, size_t why_size);

/* Reads one datagram without waiting. Returns 1 with *channel (NUL-
 * terminated, in rx's buffer) and the payload (valid until the next call);
 * 0 when none is waiting or the one read was refused (counted); -1 on a
 * socket error (errno). */
int kd_rx_read(kd_rx *rx, const char **channel, const void **payload, size_t *len);

/* The descriptor to poll for POLLIN. */
int kd_rx_fd(const kd_rx *rx);

void kd_rx_close(kd_rx *rx);

#endif
