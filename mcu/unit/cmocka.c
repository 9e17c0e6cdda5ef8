/* SPDX-License-Identifier: BSD-3-Clause */
/* cmocka.c - the runner and assertions of the bare-metal cmocka subset
 * (cmocka.h), with cmocka's output format.
 *
 * KC_MCU_TEST_FILTER, when defined, is a comma-separated list of test
 * names in which * matches any run of characters (as in cmocka's test
 * filter): only
 * those run, the others are reported skipped. Emulated, the board runs the
 * suites' property tests (hundreds of random cases in double comparisons,
 * soft double on the M4F) about a hundred times slower than the host, so a
 * few suites are run on the board by their reference-vector tests. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include "cmocka.h"

#include <string.h>

static jmp_buf test_env;

#ifdef KC_MCU_TEST_FILTER
/* Whether the n characters of pattern p match all of name. */
static int glob(const char *p, size_t n, const char *name)
{
    if (n == 0)
        return *name == '\0';
    if (*p == '*')
        return glob(p + 1, n - 1, name) || (*name != '\0' && glob(p, n, name + 1));
    return *name == *p && glob(p + 1, n - 1, name + 1);
}
#endif

/* Whether name is selected by the filter (see the top of the file). */
static int selected(const char *name)
{
#ifdef KC_MCU_TEST_FILTER
    const char *f = KC_MCU_TEST_FILTER;
    while (*f != '\0') {
        size_t n = strcspn(f, ",");
        if (glob(f, n, name))
            return 1;
        f += n;
        if (*f == ',')
            f++;
    }
    return 0;
#else
    (void)name;
    return 1;
#endif
}

void _fail(const char *file, int line)
{
    printf("[   LINE   ] --- %s:%d: Failure!\n", file, line);
    longjmp(test_env, 1);
}

void _assert_true(intmax_t result, const char *expression, const char *file, int line)
{
    if (!result) {
        printf("%s\n", expression);
        _fail(file, line);
    }
}

void _assert_int_equal(intmax_t a, intmax_t b, const char *file, int line)
{
    if (a != b) {
        printf("%lld != %lld\n", (long long)a, (long long)b);
        _fail(file, line);
    }
}

void _assert_memory_equal(const void *a, const void *b, size_t size, const char *file, int line)
{
    if (memcmp(a, b, size) != 0) {
        printf("%lu bytes differ\n", (unsigned long)size);
        _fail(file, line);
    }
}

void _assert_string_equal(const char *a, const char *b, const char *file, int line)
{
    if (strcmp(a, b) != 0) {
        printf("\"%s\" != \"%s\"\n", a, b);
        _fail(file, line);
    }
}

int _cmocka_run_group_tests(const char *group_name, const struct CMUnitTest *tests, size_t n,
                            CMFixtureFunction group_setup, CMFixtureFunction group_teardown)
{
    void *group_state = NULL;
    volatile size_t failed = 0, skipped = 0;
    printf("[==========] %s: Running %lu test(s).\n", group_name, (unsigned long)n);
    if (group_setup != NULL && group_setup(&group_state) != 0) {
        printf("[  ERROR   ] %s: group setup failed\n", group_name);
        return (int)n;
    }
    for (size_t i = 0; i < n; i++) {
        /* volatile: read after a longjmp out of the test. */
        volatile int ok = 1;
        void *state = tests[i].initial_state;
        if (!selected(tests[i].name)) {
            printf("[  SKIPPED ] %s (not in KC_MCU_TEST_FILTER)\n", tests[i].name);
            skipped++;
            continue;
        }
        printf("[ RUN      ] %s\n", tests[i].name);
        if (setjmp(test_env) == 0) {
            if (tests[i].setup_func != NULL && tests[i].setup_func(&state) != 0)
                ok = 0;
            else
                tests[i].test_func(&state);
            if (ok && tests[i].teardown_func != NULL && tests[i].teardown_func(&state) != 0)
                ok = 0;
        } else {
            ok = 0;
        }
        printf(ok ? "[       OK ] %s\n" : "[  FAILED  ] %s\n", tests[i].name);
        failed += ok ? 0u : 1u;
    }
    if (group_teardown != NULL)
        group_teardown(&group_state);
    printf("[==========] %s: %lu test(s) run.\n", group_name, (unsigned long)(n - skipped));
    printf("[  PASSED  ] %lu test(s).\n", (unsigned long)(n - failed - skipped));
    if (skipped)
        printf("[  SKIPPED ] %lu test(s).\n", (unsigned long)skipped);
    if (failed)
        printf("[  FAILED  ] %lu test(s).\n", (unsigned long)failed);
    return (int)failed;
}
