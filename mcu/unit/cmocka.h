/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * cmocka.h - the part of cmocka's API that kinctl's unit tests use, for
 * bare metal, where cmocka itself (signals, its allocator wrappers) does
 * not build. The tests in tests/unit compile unchanged against it on the board:
 * an assertion that fails prints where and why and longjmps back to the
 * runner, which counts the test failed and goes on with the next one, as
 * cmocka does. No mocks, no expectations: the unit tests use none.
 *
 * Include after <setjmp.h>, <stdarg.h> and <stddef.h>, as cmocka requires.
 */
#ifndef KINCTL_MCU_CMOCKA_H
#define KINCTL_MCU_CMOCKA_H

#include <stdint.h>
#include <stdio.h>

typedef void (*CMUnitTestFunction)(void **state);
typedef int (*CMFixtureFunction)(void **state);

struct CMUnitTest {
    const char *name;
    CMUnitTestFunction test_func;
    CMFixtureFunction setup_func;
    CMFixtureFunction teardown_func;
    void *initial_state;
};

#define cmocka_unit_test(f) {#f, f, NULL, NULL, NULL}

/* Runs the tests, prints cmocka's summary lines, returns the failures. */
int _cmocka_run_group_tests(const char *group_name, const struct CMUnitTest *tests, size_t n,
                            CMFixtureFunction group_setup, CMFixtureFunction group_teardown);
#define cmocka_run_group_tests(group, setup, teardown) \
    _cmocka_run_group_tests(#group, group, sizeof(group) / sizeof((group)[0]), setup, teardown)
#define cmocka_run_group_tests_name(name, group, setup, teardown) \
    _cmocka_run_group_tests(name, group, sizeof(group) / sizeof((group)[0]), setup, teardown)

/* Fails the running test (does not return). */
void _fail(const char *file, int line) __attribute__((noreturn));
void _assert_true(intmax_t result, const char *expression, const char *file, int line);
void _assert_int_equal(intmax_t a, intmax_t b, const char *file, int line);
void _assert_memory_equal(const void *a, const void *b, size_t size, const char *file, int line);
void _assert_string_equal(const char *a, const char *b, const char *file, int line);

#define print_message(...) printf(__VA_ARGS__)
#define print_error(...) printf(__VA_ARGS__)
#define fail() _fail(__FILE__, __LINE__)
#define fail_msg(...) (print_error("ERROR: " __VA_ARGS__), print_error("\n"), _fail(__FILE__, __LINE__))
#define assert_true(c) _assert_true((intmax_t)((c) != 0), #c, __FILE__, __LINE__)
#define assert_false(c) _assert_true((intmax_t)((c) == 0), "!(" #c ")", __FILE__, __LINE__)
#define assert_non_null(p) _assert_true((intmax_t)((p) != NULL), #p, __FILE__, __LINE__)
#define assert_null(p) _assert_true((intmax_t)((p) == NULL), #p " == NULL", __FILE__, __LINE__)
#define assert_int_equal(a, b) _assert_int_equal((intmax_t)(a), (intmax_t)(b), __FILE__, __LINE__)
#define assert_memory_equal(a, b, size) _assert_memory_equal((a), (b), (size), __FILE__, __LINE__)
#define assert_string_equal(a, b) _assert_string_equal((a), (b), __FILE__, __LINE__)

#endif /* KINCTL_MCU_CMOCKA_H */
