// Tiny assertion macros for the test executables: a failed check prints the
// expression and location and exits non-zero, so ctest reports the failure.
#pragma once

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define ENSURE(cond)                                                                                         \
  do {                                                                                                       \
    if (!(cond)) {                                                                                           \
      fprintf(stderr, "%s:%d: ENSURE failed: %s\n", __FILE__, __LINE__, #cond);                              \
      exit(1);                                                                                               \
    }                                                                                                        \
  } while (0)

#define ENSURE_MSG(cond, ...)                                                                                \
  do {                                                                                                       \
    if (!(cond)) {                                                                                           \
      fprintf(stderr, "%s:%d: ENSURE failed: %s: ", __FILE__, __LINE__, #cond);                              \
      fprintf(stderr, __VA_ARGS__);                                                                          \
      fputc('\n', stderr);                                                                                   \
      exit(1);                                                                                               \
    }                                                                                                        \
  } while (0)

/// |a - b| <= tol, printing both values on failure.
#define ENSURE_SMALL(a, b, tol)                                                                              \
  do {                                                                                                       \
    double ensure_a_ = (double)(a), ensure_b_ = (double)(b);                                                 \
    if (!(fabs(ensure_a_ - ensure_b_) <= (tol))) {                                                           \
      fprintf(stderr, "%s:%d: ENSURE_SMALL failed: %s = %.17g, %s = %.17g, tol %g\n", __FILE__, __LINE__,    \
              #a, ensure_a_, #b, ensure_b_, (double)(tol));                                                  \
      exit(1);                                                                                               \
    }                                                                                                        \
  } while (0)

/// |a - b| <= rel * max(|a|, |b|).
#define ENSURE_REL(a, b, rel)                                                                                \
  do {                                                                                                       \
    double ensure_a_ = (double)(a), ensure_b_ = (double)(b);                                                 \
    double ensure_s_ = fmax(fabs(ensure_a_), fabs(ensure_b_));                                               \
    if (!(fabs(ensure_a_ - ensure_b_) <= (rel)*ensure_s_)) {                                                 \
      fprintf(stderr, "%s:%d: ENSURE_REL failed: %s = %.17g, %s = %.17g, rel %g\n", __FILE__, __LINE__, #a,  \
              ensure_a_, #b, ensure_b_, (double)(rel));                                                      \
      exit(1);                                                                                               \
    }                                                                                                        \
  } while (0)

#define RUN(test_fn)                                                                                         \
  do {                                                                                                       \
    fprintf(stderr, "  %s\n", #test_fn);                                                                     \
    test_fn();                                                                                               \
  } while (0)
