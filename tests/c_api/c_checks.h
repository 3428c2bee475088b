/* The checks of the C API's test programs: each failure is printed with its line and counted
 * in `failures`, which main returns as its exit status. */
#ifndef PAR2D_TESTS_C_CHECKS_H
#define PAR2D_TESTS_C_CHECKS_H

#include <stdio.h>
#include <string.h>

#include "par2d/par2d.h"

static int failures = 0;

#define CHECK(cond)                                                   \
  do {                                                                \
    if (!(cond)) {                                                    \
      fprintf(stderr, "%s:%d: CHECK(%s) failed\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                     \
    }                                                                 \
  } while (0)

/* A failing call: its status and its whole one-line message. */
#define CHECK_ERROR(call, status, message)                                                        \
  do {                                                                                            \
    const par2d_status got_ = (call);                                                             \
    if (got_ != (status) || strcmp(par2d_last_error(), (message)) != 0) {                         \
      fprintf(stderr, "%s:%d: %s gave status %d \"%s\", expected %d \"%s\"\n", __FILE__, __LINE__, \
              #call, (int)got_, par2d_last_error(), (int)(status), (message));                   \
      ++failures;                                                                                 \
    }                                                                                             \
  } while (0)

/* A failing call whose message starts with `prefix` (the rest is the library's). */
#define CHECK_ERROR_PREFIX(call, status, prefix)                                                  \
  do {                                                                                            \
    const par2d_status got_ = (call);                                                             \
    if (got_ != (status) || strncmp(par2d_last_error(), (prefix), strlen(prefix)) != 0 ||         \
        strchr(par2d_last_error(), '\n') != NULL) {                                               \
      fprintf(stderr, "%s:%d: %s gave status %d \"%s\", expected %d \"%s...\"\n", __FILE__,      \
              __LINE__, #call, (int)got_, par2d_last_error(), (int)(status), (prefix));         \
      ++failures;                                                                                 \
    }                                                                                             \
  } while (0)

#endif
