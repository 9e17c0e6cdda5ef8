/* SPDX-License-Identifier: BSD-3-Clause */
/* spsc.c - the single-producer single-consumer ring (spsc.h). */
#include "spsc.h"

#include <stdint.h>
#include <string.h>

size_t kd_spsc_round_capacity(size_t n)
{
    size_t c = 2;
    if (n <= 2)
        return 2;
    while (c < n) {
        if (c > SIZE_MAX / 2)
            return 0;
        c *= 2;
    }
    return c;
}

int kd_spsc_init(kd_spsc *q, void *storage, size_t capacity, size_t elem_size)
{
    if (q == NULL || storage == NULL || elem_size == 0 || capacity < 2 || (capacity & (capacity - 1)) != 0)
        return -1;
    atomic_init(&q->head, 0);
    atomic_init(&q->tail, 0);
    q->mask = capacity - 1;
    q->elem_size = elem_size;
    q->storage = storage;
    return 0;
}

void *kd_spsc_slot_write(kd_spsc *q)
{
    /* Only this thread writes head: a relaxed load of it is exact. */
    size_t head = atomic_load_explicit(&q->head, memory_order_relaxed);
    size_t tail = atomic_load_explicit(&q->tail, memory_order_acquire);
    if (head - tail > q->mask)
        return NULL;
    return q->storage + (head & q->mask) * q->elem_size;
}

void kd_spsc_commit(kd_spsc *q)
{
    size_t head = atomic_load_explicit(&q->head, memory_order_relaxed);
    atomic_store_explicit(&q->head, head + 1, memory_order_release);
}

int kd_spsc_push(kd_spsc *q, const void *elem)
{
    void *slot = kd_spsc_slot_write(q);
    if (slot == NULL)
        return -1;
    memcpy(slot, elem, q->elem_size);
    kd_spsc_commit(q);
    return 0;
}

const void *kd_spsc_slot_read(kd_spsc *q)
{
    size_t tail = atomic_load_explicit(&q->tail, memory_order_relaxed);
    size_t head = atomic_load_explicit(&q->head, memory_order_acquire);
    if (head == tail)
        return NULL;
    return q->storage + (tail & q->mask) * q->elem_size;
}

void kd_spsc_release(kd_spsc *q)
{
    size_t tail = atomic_load_explicit(&q->tail, memory_order_relaxed);
    atomic_store_explicit(&q->tail, tail + 1, memory_order_release);
}

int kd_spsc_pop(kd_spsc *q, void *elem)
{
    const void *slot = kd_spsc_slot_read(q);
    if (slot == NULL)
        return -1;
    memcpy(elem, slot, q->elem_size);
    kd_spsc_release(q);
    return 0;
}

size_t kd_spsc_count(kd_spsc *q)
{
    size_t tail = atomic_load_explicit(&q->tail, memory_order_acquire);
    size_t head = atomic_load_explicit(&q->head, memory_order_acquire);
    return head - tail;
}
