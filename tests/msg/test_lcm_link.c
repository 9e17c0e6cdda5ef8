/* SPDX-License-Identifier: BSD-3-Clause */
/* test_lcm_link.c - an executable linking the LCM wheel's shared liblcm runs
 * (the build tree's rpath finds it) and carries a kinctl datagram through
 * LCM's in-process memq:// provider into kd_msg_decode, the way kinctld
 * receives goals: a raw lcm_subscribe handler, never a generated stub. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <string.h>

#include <lcm/lcm.h>

#include "msg.h"
#include "msg_sample.h"

typedef struct received {
    int count;
    kd_msg_status status;
    kinctl_goal_joint_t goal;
} received;

static void on_goal(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    received *r = (received *)user;
    (void)channel;
    r->count++;
    r->status = kd_msg_decode(KD_MSG_GOAL_JOINT, rbuf->data, rbuf->data_size, &r->goal, NULL, 0);
}

static void test_memq(void **state)
{
    lcm_t *lcm = lcm_create("memq://");
    kd_msg_any m;
    unsigned char buf[KD_MSG_MAX_SIZE];
    size_t len = 0;
    received r;
    lcm_subscription_t *sub;
    (void)state;
    assert_non_null(lcm);
    memset(&r, 0, sizeof r);
    sub = lcm_subscribe(lcm, "KINCTL_GOAL_JOINT", on_goal, &r);
    assert_non_null(sub);

    msg_sample(KD_MSG_GOAL_JOINT, 5, &m, NULL);
    assert_int_equal(kd_msg_encode(KD_MSG_GOAL_JOINT, &m, buf, sizeof buf, &len), KD_MSG_OK);
    assert_int_equal(lcm_publish(lcm, "KINCTL_GOAL_JOINT", buf, (unsigned int)len), 0);
    assert_true(lcm_handle_timeout(lcm, 1000) > 0);
    assert_int_equal(r.count, 1);
    assert_int_equal(r.status, KD_MSG_OK);
    assert_memory_equal(&r.goal, &m.goal_joint, sizeof r.goal);

    /* A truncated copy arrives too, and is refused. */
    assert_int_equal(lcm_publish(lcm, "KINCTL_GOAL_JOINT", buf, (unsigned int)len - 1), 0);
    assert_true(lcm_handle_timeout(lcm, 1000) > 0);
    assert_int_equal(r.count, 2);
    assert_int_equal(r.status, KD_MSG_E_TRUNCATED);

    lcm_unsubscribe(lcm, sub);
    lcm_destroy(lcm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_memq)};
    kd_msg_init();
    return cmocka_run_group_tests_name("msg.lcm_link", tests, NULL, NULL);
}
