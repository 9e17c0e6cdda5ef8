/* SPDX-License-Identifier: BSD-3-Clause */
/* fuzz_calc.c - `kinctl-calc batch` on arbitrary request lines: the
 * calculator's own sources, built with main renamed (CMake), run with the
 * input as standard input and the answers written to a memory buffer.
 * Invariants: no crash, hang or sanitizer report; exactly one answer line
 * per request line that is not blank, each a JSON object. */
#define _GNU_SOURCE /* fmemopen, open_memstream */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_check.h"

int kinctl_calc_main(int argc, char **argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* Requests are JSON text: a NUL would end a line early for fgetc-based
     * readers and means nothing in JSON; long inputs add nothing but time. */
    if (size == 0 || size > 4096 || memchr(data, '\0', size) != NULL)
        return 0;
    /* fmemopen takes a void * but only reads it in mode "r". */
    FILE *in = fmemopen((void *)(uintptr_t)data, size, "r"); /* NOLINT(performance-no-int-to-ptr) */
    char *answers = NULL;
    size_t answers_len = 0;
    FILE *out = open_memstream(&answers, &answers_len);
    FUZZ_CHECK(in != NULL && out != NULL, "memory streams");
    FILE *saved_in = stdin, *saved_out = stdout;
    stdin = in;
    stdout = out;
    char *argv[] = {"kinctl-calc", "batch", NULL};
    int rc = kinctl_calc_main(2, argv);
    fflush(stdout);
    stdin = saved_in;
    stdout = saved_out;
    fclose(in);
    fclose(out);
    FUZZ_CHECK(rc == 0 || rc == 1 || rc == 2, "exit status %d", rc);

    /* Lines of nothing but blanks get no answer (kinctl-calc batch --help). */
    size_t requests = 0, lines = 0;
    int blank = 1;
    for (size_t i = 0; i < size; i++) {
        if (data[i] != '\n' && data[i] != ' ' && data[i] != '\t' && data[i] != '\r')
            blank = 0;
        if (data[i] == '\n' || i == size - 1) {
            requests += !blank;
            blank = 1;
        }
    }
    for (size_t i = 0; i < answers_len; i++) {
        if (answers[i] != '\n')
            continue;
        size_t start = i;
        while (start > 0 && answers[start - 1] != '\n')
            start--;
        FUZZ_CHECK(i > start && answers[start] == '{' && answers[i - 1] == '}', "answer line %zu is no object",
                   lines + 1);
        lines++;
    }
    FUZZ_CHECK(lines == requests, "%zu answers to %zu request lines", lines, requests);
    free(answers);
    return 0;
}
