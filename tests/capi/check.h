/* Assertions of the C API tests: status AND message of every call. */
#ifndef FFRF_TEST_CHECK_H
#define FFRF_TEST_CHECK_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ffrf.h"

static int failures = 0;

/* The call returned `expected` and ffrf_last_error(c) contains `fragment` ("" for success:
 * the message must then be empty). */
#define EXPECT(c, call, expected, fragment) \
    expect_status((c), (call), (expected), (fragment), #call, __LINE__)

static void expect_status(const ffrf_case *c, int status, int expected, const char *fragment,
                          const char *text, int line)
{
    const char *message = ffrf_last_error(c);
    int ok = status == expected;
    if (fragment[0] == '\0')
        ok = ok && message[0] == '\0';
    else
        ok = ok && strstr(message, fragment) != NULL;
    if (!ok) {
        fprintf(stderr, "FAIL line %d: %s\n  status %d (expected %d), message \"%s\" "
                "(expected to contain \"%s\")\n", line, text, status, expected, message,
                fragment);
        failures++;
    }
}

/* A condition that must hold. */
#define CHECK(condition) \
    do { \
        if (!(condition)) { \
            fprintf(stderr, "FAIL line %d: %s\n", __LINE__, #condition); \
            failures++; \
        } \
    } while (0)

#endif
