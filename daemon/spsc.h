/* SPDX-License-Identifier: BSD-3-Clause */
/* spsc.h - a lock-free single-producer single-consumer ring of fixed-size
 * elements, the only way data crosses between kinctld's threads.
 *
 * One thread pushes, one other thread pops; neither ever waits for the
 * other. Storage is the caller's (allocated before the threads start and
 * never again); the capacity is a power of two. The producer fills a slot in
 * place (kd_spsc_slot_write, then kd_spsc_commit) and the consumer reads one
 * in place (kd_spsc_slot_read, then kd_spsc_release), so large elements are
 * written once and never copied through the stack.
 *
 * Memory order: the producer's commit is a release store of head, the
 * consumer's read an acquire load of it, so an element's contents are
 * visible before its slot is; the same pair on tail hands a slot back. Head
 * and tail count up forever (size_t wraps after 2^64 pushes) and live on
 * their own cache lines.
 *
 * Every function is bounded, never blocks, allocates or calls the kernel:
 * safe for the cycle thread.
 */
#ifndef KINCTL_DAEMON_SPSC_H
#define KINCTL_DAEMON_SPSC_H

#include <stdatomic.h>
#include <stddef.h>

typedef struct kd_spsc {
    _Alignas(64) atomic_size_t head; /* next slot to write; written by the producer */
    _Alignas(64) atomic_size_t tail; /* next slot to read; written by the consumer */
    _Alignas(64) size_t mask;        /* capacity - 1 */
    size_t elem_size;
    unsigned char *storage;          /* capacity * elem_size bytes, the caller's */
} kd_spsc;

/* The smallest power of two >= n (n >= 1), or 0 if there is none. */
size_t kd_spsc_round_capacity(size_t n);

/* Sets q up over storage (capacity * elem_size bytes, capacity a power of
 * two >= 2). Returns 0, or -1 for a bad argument. Before the threads start. */
int kd_spsc_init(kd_spsc *q, void *storage, size_t capacity, size_t elem_size);

/* Producer: the slot to fill next, or NULL when the ring is full (the
 * element is then dropped: the caller counts it). The slot is the
 * consumer's only after kd_spsc_commit. */
void *kd_spsc_slot_write(kd_spsc *q);
void kd_spsc_commit(kd_spsc *q);

/* Producer: copies elem in; 0, or -1 when full. */
int kd_spsc_push(kd_spsc *q, const void *elem);

/* Consumer: the oldest element, or NULL when empty; valid until
 * kd_spsc_release. */
const void *kd_spsc_slot_read(kd_spsc *q);
void kd_spsc_release(kd_spsc *q);

/* Consumer: copies the oldest element out; 0, or -1 when empty. */
int kd_spsc_pop(kd_spsc *q, void *elem);

/* Either side: elements waiting (a snapshot). */
size_t kd_spsc_count(kd_spsc *q);

#endif
