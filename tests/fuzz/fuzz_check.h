/* SPDX-License-Identifier: BSD-3-Clause */
/* fuzz_check.h - invariant checks of the fuzz harnesses: active in every
 * build type (assert() is compiled out with NDEBUG), abort() so that
 * libFuzzer saves the input and the replay runner fails. */
#ifndef KINCTL_FUZZ_CHECK_H
#define KINCTL_FUZZ_CHECK_H

#include <stdio.h>
#include <stdlib.h>

#define FUZZ_CHECK(cond, ...)                                                                                          \
    do {                                                                                                               \
        if (!(cond)) {                                                                                                 \
            fprintf(stderr, "%s:%d: invariant failed: %s: ", __FILE__, __LINE__, #cond);                               \
            fprintf(stderr, __VA_ARGS__);                                                                              \
            fputc('\n', stderr);                                                                                       \
            abort();                                                                                                   \
        }                                                                                                              \
    } while (0)

#endif
