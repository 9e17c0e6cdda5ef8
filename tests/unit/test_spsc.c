/* SPDX-License-Identifier: BSD-3-Clause */
/* test_spsc.c - the daemon's single-producer single-consumer ring
 * (daemon/spsc.h): capacities, empty and full, order through many
 * wrap-arounds of the slots and of the head and tail counters themselves,
 * in-place slots, and one producer and one consumer on two threads. */
#include <pthread.h>
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "spsc.h"
#include "testutil.h"

static void test_round_capacity(void **state)
{
    (void)state;
    assert_int_equal(kd_spsc_round_capacity(0), 2);
    assert_int_equal(kd_spsc_round_capacity(1), 2);
    assert_int_equal(kd_spsc_round_capacity(2), 2);
    assert_int_equal(kd_spsc_round_capacity(3), 4);
    assert_int_equal(kd_spsc_round_capacity(64), 64);
    assert_int_equal(kd_spsc_round_capacity(65), 128);
    assert_int_equal(kd_spsc_round_capacity(4097), 8192);
    assert_true(kd_spsc_round_capacity(SIZE_MAX / 2 + 1) == SIZE_MAX / 2 + 1);
    assert_int_equal(kd_spsc_round_capacity(SIZE_MAX / 2 + 2), 0); /* no power of two that large */
}

static void test_init_rejects(void **state)
{
    kd_spsc q;
    int storage[8];
    (void)state;
    assert_int_equal(kd_spsc_init(NULL, storage, 8, sizeof storage[0]), -1);
    assert_int_equal(kd_spsc_init(&q, NULL, 8, sizeof storage[0]), -1);
    assert_int_equal(kd_spsc_init(&q, storage, 8, 0), -1);
    assert_int_equal(kd_spsc_init(&q, storage, 1, sizeof storage[0]), -1);
    assert_int_equal(kd_spsc_init(&q, storage, 6, sizeof storage[0]), -1);
    assert_int_equal(kd_spsc_init(&q, storage, 8, sizeof storage[0]), 0);
    assert_int_equal(kd_spsc_init(&q, storage, 2, sizeof storage[0]), 0);
}

static void test_empty_and_full(void **state)
{
    kd_spsc q;
    int storage[4], v = -1;
    (void)state;
    assert_int_equal(kd_spsc_init(&q, storage, 4, sizeof storage[0]), 0);
    assert_null(kd_spsc_slot_read(&q));
    assert_int_equal(kd_spsc_pop(&q, &v), -1);
    assert_int_equal(v, -1); /* untouched */
    assert_int_equal(kd_spsc_count(&q), 0);
    for (int i = 0; i < 4; i++) {
        assert_int_equal(kd_spsc_push(&q, &i), 0);
        assert_int_equal(kd_spsc_count(&q), (size_t)(i + 1));
    }
    int extra = 99;
    assert_null(kd_spsc_slot_write(&q));
    assert_int_equal(kd_spsc_push(&q, &extra), -1);
    assert_int_equal(kd_spsc_count(&q), 4);
    for (int i = 0; i < 4; i++) {
        assert_int_equal(kd_spsc_pop(&q, &v), 0);
        assert_int_equal(v, i); /* first in, first out; the refused 99 is nowhere */
    }
    assert_int_equal(kd_spsc_pop(&q, &v), -1);
    assert_int_equal(kd_spsc_count(&q), 0);
}

/* Pushes and pops in an irregular pattern against a plain array model of
 * the queue; starts (head, tail) at start, so the counters can be made to
 * wrap around SIZE_MAX. */
static void run_against_model(size_t start)
{
    enum { CAP = 8, STEPS = 5000 };
    kd_spsc q;
    uint32_t storage[CAP], model[STEPS];
    size_t model_head = 0, model_tail = 0;
    uint32_t next = 1;
    kt_rng rng = kt_rng_make(0x5b5cu + start);
    assert_int_equal(kd_spsc_init(&q, storage, CAP, sizeof storage[0]), 0);
    atomic_store(&q.head, start);
    atomic_store(&q.tail, start);
    for (int step = 0; step < STEPS; step++) {
        int pushes = (int)(kt_rng_next(&rng) % 6), pops = (int)(kt_rng_next(&rng) % 6);
        for (int k = 0; k < pushes; k++) {
            int rc = kd_spsc_push(&q, &next);
            if (model_head - model_tail < CAP) {
                assert_int_equal(rc, 0);
                model[model_head++ % STEPS] = next++;
            } else {
                assert_int_equal(rc, -1); /* full exactly when the model is */
            }
        }
        for (int k = 0; k < pops; k++) {
            uint32_t v = 0;
            int rc = kd_spsc_pop(&q, &v);
            if (model_head != model_tail) {
                assert_int_equal(rc, 0);
                assert_int_equal(v, model[model_tail++ % STEPS]);
            } else {
                assert_int_equal(rc, -1);
            }
        }
        assert_int_equal(kd_spsc_count(&q), model_head - model_tail);
    }
    assert_true(next > 4 * CAP); /* the slots wrapped many times */
}

static void test_wrap_around(void **state)
{
    (void)state;
    run_against_model(0);
}

static void test_counter_wrap(void **state)
{
    (void)state;
    /* head and tail pass SIZE_MAX -> 0 within the first steps */
    run_against_model(SIZE_MAX - 5);
}

static void test_slots_in_place(void **state)
{
    kd_spsc q;
    uint64_t storage[4];
    (void)state;
    assert_int_equal(kd_spsc_init(&q, storage, 4, sizeof storage[0]), 0);
    uint64_t *w = kd_spsc_slot_write(&q);
    assert_non_null(w);
    *w = 0x1122334455667788u;
    /* not the consumer's before the commit */
    assert_null(kd_spsc_slot_read(&q));
    assert_int_equal(kd_spsc_count(&q), 0);
    kd_spsc_commit(&q);
    const uint64_t *r = kd_spsc_slot_read(&q);
    assert_ptr_equal(r, w); /* the same storage, not a copy */
    assert_true(*r == 0x1122334455667788u);
    /* still the producer's until released: three more fit, not four */
    for (uint64_t i = 0; i < 3; i++)
        assert_int_equal(kd_spsc_push(&q, &i), 0);
    assert_null(kd_spsc_slot_write(&q));
    kd_spsc_release(&q);
    assert_non_null(kd_spsc_slot_write(&q));
    assert_int_equal(kd_spsc_count(&q), 3);
}

/* ---- two threads ---- */

enum { N_ITEMS = 300000, RING = 16 };

typedef struct item {
    uint64_t seq;
    uint64_t check; /* a function of seq: a torn element shows */
    unsigned char pad[48];
} item;

static uint64_t check_of(uint64_t seq) { return seq * 0x9e3779b97f4a7c15u ^ 0xdeadbeefu; }

static kd_spsc ring;
static item ring_storage[RING];

static void *producer(void *arg)
{
    (void)arg;
    for (uint64_t s = 1; s <= N_ITEMS; s++) {
        item *slot;
        while ((slot = kd_spsc_slot_write(&ring)) == NULL)
            sched_yield();
        slot->seq = s;
        memset(slot->pad, (int)(s & 0xffu), sizeof slot->pad);
        slot->check = check_of(s);
        kd_spsc_commit(&ring);
    }
    return NULL;
}

static void test_two_threads(void **state)
{
    pthread_t t;
    uint64_t expect = 1, bad = 0;
    (void)state;
    assert_int_equal(kd_spsc_init(&ring, ring_storage, RING, sizeof ring_storage[0]), 0);
    assert_int_equal(pthread_create(&t, NULL, producer, NULL), 0);
    while (expect <= N_ITEMS) {
        const item *it = kd_spsc_slot_read(&ring);
        if (it == NULL) {
            sched_yield();
            continue;
        }
        if (it->seq != expect || it->check != check_of(expect) || it->pad[0] != (unsigned char)(expect & 0xffu) ||
            it->pad[sizeof it->pad - 1] != (unsigned char)(expect & 0xffu))
            bad++;
        expect++;
        kd_spsc_release(&ring);
    }
    assert_int_equal(pthread_join(t, NULL), 0);
    assert_int_equal(bad, 0);
    assert_null(kd_spsc_slot_read(&ring)); /* nothing more than was sent */
    assert_int_equal(kd_spsc_count(&ring), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_capacity), cmocka_unit_test(test_init_rejects),
        cmocka_unit_test(test_empty_and_full),  cmocka_unit_test(test_wrap_around),
        cmocka_unit_test(test_counter_wrap),    cmocka_unit_test(test_slots_in_place),
        cmocka_unit_test(test_two_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
