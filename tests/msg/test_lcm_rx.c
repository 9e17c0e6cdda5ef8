/* SPDX-License-Identifier: BSD-3-Clause */
/* test_lcm_rx.c - kinctld's LCM receiver (daemon/lcm_rx.h) on a real
 * multicast group: what real LCM publishes arrives whole; fragments, forged
 * fragment headers claiming 256 MiB and datagrams over the limit never reach
 * the receiver (the kernel's filter drops them), while an unfiltered socket on
 * the same group and port sees every one of them, so each was really sent.
 * Where multicast does not loop back, as root it routes 224.0.0.0/4 on lo
 * as the Python suites do (kinctl.local.ensure_multicast), else skips (77). */
#define _GNU_SOURCE /* ip_mreq, in a C99 build */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <lcm/lcm.h>

#include "lcm_rx.h"

#define GROUP "239.255.77.91"
#define LIMIT 512 /* payload bytes the receiver takes after the longest channel name */
/* The longest payload on KINCTL_COMMAND (14 characters) that fits: the
 * datagram limit is header + 63 + NUL + LIMIT whatever the channel. */
#define FITS (LIMIT + KD_RX_CHANNEL_MAX - 14)

static char url[96];
static int port;

/* A plain socket on the group and port, no filter: what was really sent. */
static int open_plain(void)
{
    int fd = socket(AF_INET, SOCK_DGRAM, 0), one = 1;
    struct sockaddr_in a;
    struct ip_mreq m;
    assert_true(fd >= 0);
    assert_int_equal(setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one), 0);
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons((uint16_t)port);
    inet_pton(AF_INET, GROUP, &a.sin_addr);
    assert_int_equal(bind(fd, (struct sockaddr *)&a, sizeof a), 0);
    m.imr_multiaddr = a.sin_addr;
    m.imr_interface.s_addr = htonl(INADDR_ANY);
    assert_int_equal(setsockopt(fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &m, sizeof m), 0);
    return fd;
}

/* Datagrams waiting on fd within timeout_ms of quiet, each one's length. */
static int drain_plain(int fd, int timeout_ms, size_t *lens, int max)
{
    static unsigned char big[1 << 17];
    struct pollfd p = {fd, POLLIN, 0};
    int n = 0;
    while (poll(&p, 1, timeout_ms) > 0) {
        ssize_t r = recv(fd, big, sizeof big, MSG_TRUNC);
        assert_true(r >= 0);
        if (n < max)
            lens[n] = (size_t)r;
        n++;
    }
    return n;
}

/* Every datagram the receiver passes within timeout_ms of quiet. */
static int drain_rx(kd_rx *rx, int timeout_ms, char chans[][64], size_t *lens, int max)
{
    struct pollfd p = {kd_rx_fd(rx), POLLIN, 0};
    int n = 0;
    while (poll(&p, 1, timeout_ms) > 0) {
        const char *ch;
        const void *pl;
        size_t len;
        int r;
        while ((r = kd_rx_read(rx, &ch, &pl, &len)) == 1) {
            if (n < max) {
                snprintf(chans[n], 64, "%s", ch);
                lens[n] = len;
            }
            n++;
        }
        assert_int_equal(r, 0);
    }
    return n;
}

static void send_raw(const void *data, size_t len)
{
    int fd = socket(AF_INET, SOCK_DGRAM, 0);
    unsigned char ttl = 0;
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons((uint16_t)port);
    inet_pton(AF_INET, GROUP, &a.sin_addr);
    setsockopt(fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
    assert_int_equal(sendto(fd, data, len, 0, (struct sockaddr *)&a, sizeof a), (ssize_t)len);
    close(fd);
}

static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

static void test_only_short_messages_within_the_limit_arrive(void **state)
{
    kd_rx rx;
    char why[256], chans[16][64];
    size_t lens[16], plain_lens[16];
    static unsigned char payload[70000];
    unsigned char forged[64];
    int plain = open_plain(), n, i;
    lcm_t *lcm = lcm_create(url);
    (void)state;
    assert_non_null(lcm);
    assert_int_equal(kd_rx_open(&rx, url, LIMIT, why, sizeof why), 0);
    for (i = 0; i < (int)sizeof payload; i++)
        payload[i] = (unsigned char)(i * 7);

    /* 1: LCM's fragments of a 70,000-byte message (over 65,499: two). */
    assert_int_equal(lcm_publish(lcm, "KINCTL_GOAL_PATH", payload, 70000), 0);
    /* 2: a forged first fragment claiming 256 MiB in 2 fragments. */
    memset(forged, 0, sizeof forged);
    put32(forged, KD_RX_MAGIC_FRAGMENT);
    put32(forged + 4, 99);
    put32(forged + 8, 1u << 28);
    forged[18] = 0; forged[19] = 2;
    memcpy(forged + 20, "KINCTL_COMMAND", 15);
    send_raw(forged, 20 + 15 + 8);
    /* 3: a short message one byte over the limit. */
    assert_int_equal(lcm_publish(lcm, "KINCTL_COMMAND", payload, FITS + 1), 0);
    /* 4: garbage shorter than the magic, and another magic. */
    send_raw("LC0", 3);
    send_raw("LC04xxxxKINCTL_COMMAND\0abc", 26);
    /* 5: the real thing, at the limit and small. */
    assert_int_equal(lcm_publish(lcm, "KINCTL_COMMAND", payload, FITS), 0);
    assert_int_equal(lcm_publish(lcm, "KINCTL_GOAL_JOINT", payload + 1, 17), 0);

    n = drain_rx(&rx, 300, chans, lens, 16);
    assert_int_equal(n, 2);
    assert_string_equal(chans[0], "KINCTL_COMMAND");
    assert_int_equal(lens[0], FITS);
    assert_string_equal(chans[1], "KINCTL_GOAL_JOINT");
    assert_int_equal(lens[1], 17);
    /* The kernel dropped the rest: the receiver never read them. */
    assert_int_equal(rx.datagrams, 2);
    assert_int_equal(rx.refused, 0);
    /* ...but each was on the wire: 2 fragments, forged, over, 2 garbage, 2 good. */
    n = drain_plain(plain, 300, plain_lens, 16);
    assert_int_equal(n, 8);
    assert_int_equal(plain_lens[2], 20 + 15 + 8);
    assert_int_equal(plain_lens[3], 8 + sizeof "KINCTL_COMMAND" + FITS + 1);
    kd_rx_close(&rx);
    lcm_destroy(lcm);
    close(plain);
}

static void test_a_channel_name_never_terminated_is_refused(void **state)
{
    kd_rx rx;
    char why[256], chans[4][64];
    size_t lens[4];
    unsigned char d[8 + 80];
    (void)state;
    assert_int_equal(kd_rx_open(&rx, url, LIMIT, why, sizeof why), 0);
    put32(d, KD_RX_MAGIC_SHORT);
    put32(d + 4, 1);
    memset(d + 8, 'A', 80); /* no NUL in 80 bytes: longer than LCM's 63 */
    send_raw(d, sizeof d);
    d[8 + 10] = '\0';
    send_raw(d, sizeof d); /* "AAAAAAAAAA" and 69 payload bytes */
    d[8] = '\0';
    send_raw(d, sizeof d); /* an empty channel name */
    assert_int_equal(drain_rx(&rx, 300, chans, lens, 4), 1);
    assert_string_equal(chans[0], "AAAAAAAAAA");
    assert_int_equal(lens[0], 80 - 11);
    assert_int_equal(rx.datagrams, 3);
    assert_int_equal(rx.refused, 2);
    kd_rx_close(&rx);
}

static void test_urls(void **state)
{
    static const char *const bad[] = {
        "tcpq://127.0.0.1:7700", "memq://", "udpm://127.0.0.1:7667", "udpm://239.1.1.1:0",
        "udpm://239.1.1.1:70000", "udpm://239.1.1.1:12x", "udpm://nohost:7667", "udpm://239.1.1.1:7667?recv_buf_size=abc",
        "udpm://239.1.1.1:7667?ttl=0&recv_buf_size=-5",
    };
    kd_rx rx;
    char why[256];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        why[0] = '\0';
        assert_int_equal(kd_rx_open(&rx, bad[i], LIMIT, why, sizeof why), -1);
        assert_true(strlen(why) > 10);
        assert_int_equal(rx.fd, -1);
    }
    assert_int_equal(kd_rx_open(&rx, url, 0, why, sizeof why), -1);
    assert_int_equal(kd_rx_open(&rx, url, KD_RX_PAYLOAD_MAX + 1, why, sizeof why), -1);
    /* LCM's default group and port, and a receive buffer asked for. */
    assert_int_equal(kd_rx_open(&rx, "udpm://", LIMIT, why, sizeof why), 0);
    kd_rx_close(&rx);
    snprintf(why, sizeof why, "%s&recv_buf_size=262144", url);
    assert_int_equal(kd_rx_open(&rx, why, LIMIT, why, sizeof why), 0);
    assert_true(rx.recv_buf >= 262144);
    kd_rx_close(&rx);
}

/* Multicast loops back here: a datagram sent to the group reaches a socket
 * joined to it. */
static int multicast_loops_back(void)
{
    int fd = open_plain();
    size_t len;
    int n;
    send_raw("probe", 5);
    n = drain_plain(fd, 300, &len, 1);
    close(fd);
    return n == 1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_only_short_messages_within_the_limit_arrive),
        cmocka_unit_test(test_a_channel_name_never_terminated_is_refused),
        cmocka_unit_test(test_urls),
    };
    port = 20000 + (int)(getpid() % 20000);
    snprintf(url, sizeof url, "udpm://" GROUP ":%d?ttl=0", port);
    if (!multicast_loops_back() &&
        (geteuid() != 0 ||
         /* A fixed command line, no input in it. */
         system("ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo") != 0 || /* NOLINT(cert-env33-c) */
         !multicast_loops_back())) {
        fprintf(stderr, "test_lcm_rx: SKIPPED: multicast does not loop back here (as root: ip route add "
                        "224.0.0.0/4 dev lo)\n");
        return 77;
    }
    return cmocka_run_group_tests(tests, NULL, NULL);
}
