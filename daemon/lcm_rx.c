/* SPDX-License-Identifier: BSD-3-Clause */
/* lcm_rx.c - client messages off LCM's multicast group (lcm_rx.h). */
#define _GNU_SOURCE /* SO_RCVBUFFORCE */
#include "lcm_rx.h"

#include <arpa/inet.h>
#include <errno.h>
#include <linux/filter.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#define KD_RX_DEFAULT_GROUP "239.255.76.67"
#define KD_RX_DEFAULT_PORT 7667
#define KD_UDP_HEADER 8

/* The group, port and receive buffer of an LCM UDP multicast URL. */
typedef struct rx_url {
    struct in_addr group;
    uint16_t port;
    int recv_buf;
} rx_url;

static int fail(char *why, size_t size, const char *fmt, const char *arg)
{
    snprintf(why, size, fmt, arg);
    return -1;
}

static int parse_url(const char *url, rx_url *u, char *why, size_t why_size)
{
    static const char scheme[] = "udpm://";
    char net[128], host[128];
    const char *opts, *colon;
    size_t n;
    if (strncmp(url, scheme, sizeof scheme - 1) != 0)
        return fail(why, why_size, "%s", "is not LCM's UDP multicast (udpm://GROUP:PORT), the one kinctld listens on");
    url += sizeof scheme - 1;
    opts = strchr(url, '?');
    n = opts != NULL ? (size_t)(opts - url) : strlen(url);
    if (n >= sizeof net)
        return fail(why, why_size, "%s", "has an address that is too long");
    memcpy(net, url, n);
    net[n] = '\0';
    u->port = KD_RX_DEFAULT_PORT;
    u->recv_buf = KD_RX_RECV_BUF;
    snprintf(host, sizeof host, "%s", net[0] != '\0' ? net : KD_RX_DEFAULT_GROUP);
    colon = strchr(net, ':');
    if (colon != NULL) {
        char *end;
        long port = strtol(colon + 1, &end, 10);
        if (*end != '\0' || end == colon + 1 || port < 1 || port > 65535)
            return fail(why, why_size, "has a port \"%s\" that is not 1..65535", colon + 1);
        u->port = (uint16_t)port;
        host[colon - net] = '\0';
    }
    if (inet_pton(AF_INET, host, &u->group) != 1 || !IN_MULTICAST(ntohl(u->group.s_addr)))
        return fail(why, why_size, "has a group \"%s\" that is not an IPv4 multicast address (224.0.0.0/4)", host);
    while (opts != NULL) {
        static const char key[] = "recv_buf_size=";
        opts++;
        if (strncmp(opts, key, sizeof key - 1) == 0) {
            char *end;
            long v = strtol(opts + sizeof key - 1, &end, 10);
            if ((*end != '\0' && *end != '&') || v <= 0 || v > (1L << 30))
                return fail(why, why_size, "%s", "has a recv_buf_size that is not a size in bytes (1 to 2^30)");
            if (v > u->recv_buf)
                u->recv_buf = (int)v;
        }
        opts = strchr(opts, '&');
    }
    return 0;
}

/* The kernel filter (lcm_rx.h): on a UDP socket the program sees the UDP
 * header (8 bytes) then the payload; it keeps a datagram whole when it is no
 * longer than max_len (header included) and its payload starts with LCM's
 * short-message magic, and drops it otherwise (a datagram too short to hold
 * the magic fails the load and is dropped too). */
static int attach_filter(int fd, uint32_t max_len)
{
    struct sock_filter code[] = {
        BPF_STMT(BPF_LD | BPF_W | BPF_LEN, 0),
        BPF_JUMP(BPF_JMP | BPF_JGT | BPF_K, max_len, 2, 0),
        BPF_STMT(BPF_LD | BPF_W | BPF_ABS, KD_UDP_HEADER),
        BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, KD_RX_MAGIC_SHORT, 1, 0),
        BPF_STMT(BPF_RET | BPF_K, 0),
        BPF_STMT(BPF_RET | BPF_K, 0xFFFFFFFFu),
    };
    struct sock_fprog prog = {(unsigned short)(sizeof code / sizeof code[0]), code};
    return setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &prog, sizeof prog);
}

int kd_rx_open(kd_rx *rx, const char *url, size_t payload_max, char *why, size_t why_size)
{
    rx_url u;
    struct sockaddr_in addr;
    struct ip_mreq mreq;
    socklen_t len = sizeof rx->recv_buf;
    int one = 1;
    memset(rx, 0, sizeof *rx);
    rx->fd = -1;
    if (payload_max < 1 || payload_max > KD_RX_PAYLOAD_MAX)
        return fail(why, why_size, "%s", "payload limit out of range");
    if (parse_url(url, &u, why, why_size) != 0)
        return -1;
    rx->datagram_max = (uint32_t)(KD_RX_HEADER + KD_RX_CHANNEL_MAX + 1 + payload_max);
    rx->fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (rx->fd < 0)
        return fail(why, why_size, "cannot open the receive socket: %s", strerror(errno));
    /* The filter goes on before the socket is bound: nothing it would drop
     * ever reaches the queue. */
    if (attach_filter(rx->fd, KD_UDP_HEADER + rx->datagram_max) != 0) {
        fail(why, why_size, "cannot attach the receive socket's filter: %s", strerror(errno));
        goto fail;
    }
    if (setsockopt(rx->fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0) {
        fail(why, why_size, "SO_REUSEADDR on the receive socket: %s", strerror(errno));
        goto fail;
    }
    /* Beyond net.core.rmem_max where allowed (CAP_NET_ADMIN), else up to it. */
    if (setsockopt(rx->fd, SOL_SOCKET, SO_RCVBUFFORCE, &u.recv_buf, sizeof u.recv_buf) != 0)
        (void)setsockopt(rx->fd, SOL_SOCKET, SO_RCVBUF, &u.recv_buf, sizeof u.recv_buf);
    if (getsockopt(rx->fd, SOL_SOCKET, SO_RCVBUF, &rx->recv_buf, &len) != 0)
        rx->recv_buf = 0;
    memset(&addr, 0, sizeof addr);
    addr.sin_family = AF_INET;
    addr.sin_addr = u.group; /* the group only, as LCM binds on Linux */
    addr.sin_port = htons(u.port);
    if (bind(rx->fd, (const struct sockaddr *)&addr, sizeof addr) != 0) {
        fail(why, why_size, "cannot bind the receive socket to the LCM group's port: %s", strerror(errno));
        goto fail;
    }
    mreq.imr_multiaddr = u.group;
    mreq.imr_interface.s_addr = htonl(INADDR_ANY);
    if (setsockopt(rx->fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mreq, sizeof mreq) != 0) {
        fail(why, why_size, "cannot join the LCM multicast group (is there a multicast route?): %s",
             strerror(errno));
        goto fail;
    }
    return 0;
fail:
    close(rx->fd);
    rx->fd = -1;
    return -1;
}

int kd_rx_url_check(const char *url, char *why, size_t why_size)
{
    rx_url u;
    return parse_url(url, &u, why, why_size);
}

int kd_rx_read(kd_rx *rx, const char **channel, const void **payload, size_t *len)
{
    ssize_t n = recv(rx->fd, rx->buf, sizeof rx->buf, MSG_DONTWAIT | MSG_TRUNC);
    uint32_t magic;
    size_t c;
    if (n < 0)
        return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? 0 : -1;
    rx->datagrams++;
    /* MSG_TRUNC: n is the datagram's whole length, even past the buffer. */
    if ((size_t)n > rx->datagram_max || (size_t)n < KD_RX_HEADER + 2) {
        rx->refused++;
        return 0;
    }
    magic = ((uint32_t)rx->buf[0] << 24) | ((uint32_t)rx->buf[1] << 16) | ((uint32_t)rx->buf[2] << 8) | rx->buf[3];
    if (magic != KD_RX_MAGIC_SHORT) {
        rx->refused++;
        return 0;
    }
    for (c = KD_RX_HEADER; c < (size_t)n && c <= KD_RX_HEADER + KD_RX_CHANNEL_MAX; c++)
        if (rx->buf[c] == '\0')
            break;
    if (c >= (size_t)n || c > KD_RX_HEADER + KD_RX_CHANNEL_MAX || c == KD_RX_HEADER) {
        rx->refused++;
        return 0;
    }
    *channel = (const char *)rx->buf + KD_RX_HEADER;
    *payload = rx->buf + c + 1;
    *len = (size_t)n - (c + 1);
    return 1;
}

int kd_rx_fd(const kd_rx *rx)
{
    return rx->fd;
}

void kd_rx_close(kd_rx *rx)
{
    if (rx->fd >= 0)
        close(rx->fd);
    rx->fd = -1;
}
