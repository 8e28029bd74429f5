// The library's own math (det_math.c) and sort (sort.c), which make a tree
// the same bytes on every machine and in the WebAssembly build: each
// function within a few ulp of the C library's over many arguments, exact
// where the answer is exact, special values as the C library gives them,
// and a digest of fixed arguments' bits that every build (GCC, clang,
// sanitizers, emscripten's web/tests/module_check.mjs through the trees)
// must reproduce; the sort stable and a real sort.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bk_base.h"
#include "ensure.h"

// What test_digest must give (printed by the test when it differs).
#define DET_MATH_DIGEST 0xf5b9bd0bd8b9a3c9ull

static double ulps(double got, double want) {
  if (got == want) return 0.0;
  double unit = nextafter(fabs(want), INFINITY) - fabs(want);
  return fabs(got - want) / unit;
}

static uint64_t bits_of(double x) {
  uint64_t u = 0;
  memcpy(&u, &x, sizeof u);
  return u;
}

static uint64_t next_random(uint64_t* s) {
  *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
  return *s;
}

static void test_accuracy(void) {
  double worst[8] = {0};
  uint64_t s = 88172645463325252ull;
  for (int i = 0; i < 200000; ++i) {
    double u = (double)(next_random(&s) >> 11) * (1.0 / 9007199254740992.0);
    double x = (u - 0.5) * 40.0;
    if (fabs(sin(x)) > 1e-3) worst[0] = fmax(worst[0], ulps(bk_sin(x), sin(x)));
    if (fabs(cos(x)) > 1e-3) worst[1] = fmax(worst[1], ulps(bk_cos(x), cos(x)));
    worst[2] = fmax(worst[2], ulps(bk_atan2(x, u - 0.3), atan2(x, u - 0.3)));
    worst[3] = fmax(worst[3], ulps(bk_cbrt(x * 1e5), cbrt(x * 1e5)));
    double l = u * 1e3 + 1e-9;
    if (fabs(log2(l)) > 1e-3) worst[4] = fmax(worst[4], ulps(bk_log2(l), log2(l)));
    worst[5] = fmax(worst[5], ulps(bk_exp2(x), exp2(x)));
    worst[6] = fmax(worst[6], ulps(bk_pow(u, 0.3), pow(u, 0.3)));
    worst[7] = fmax(worst[7], ulps(bk_hypot(x, u), hypot(x, u)));
  }
  const char* names[8] = {"sin", "cos", "atan2", "cbrt", "log2", "exp2", "pow", "hypot"};
  const double allowed[8] = {2, 2, 4, 3, 2, 1, 8, 2};
  for (int k = 0; k < 8; ++k) {
    printf("%-5s within %.0f ulp of the C library's\n", names[k], worst[k]);
    ENSURE_MSG(worst[k] <= allowed[k], "%s: %.1f ulp from the C library's", names[k], worst[k]);
  }
}

static void test_exact_and_special(void) {
  ENSURE(bk_sin(0.0) == 0.0 && bk_cos(0.0) == 1.0);
  ENSURE(bk_cbrt(27.0) == 3.0 && bk_cbrt(-8.0) == -2.0 && bk_cbrt(0.0) == 0.0);
  ENSURE(bk_log2(8.0) == 3.0 && bk_log2(1.0) == 0.0 && bk_log2(0.0) == -INFINITY && isnan(bk_log2(-1.0)));
  ENSURE(bk_exp2(10.0) == 1024.0 && bk_exp2(-1.0) == 0.5 && bk_exp2(2000.0) == INFINITY);
  ENSURE(bk_pow(2.0, 10.0) == 1024.0 && bk_pow(0.0, 2.0) == 0.0 && bk_pow(5.0, 0.0) == 1.0);
  ENSURE(isnan(bk_pow(-1.0, 0.5)) && isnan(bk_pow(NAN, 1.0)));
  ENSURE(bk_hypot(3.0, 4.0) == 5.0 && bk_hypot(-3.0, 0.0) == 3.0 && bk_hypot(INFINITY, NAN) == INFINITY);
  ENSURE(isnan(bk_sin(INFINITY)) && isnan(bk_cos(NAN)));
  // atan2's quadrants and signed zeros, as the C library has them.
  const double ys[] = {1, 1, -1, -1, 0.0, -0.0, 0.0, -0.0, 1, -1};
  const double xs[] = {1, -1, 1, -1, 1, 1, -1, -1, 0, 0};
  for (size_t i = 0; i < sizeof ys / sizeof ys[0]; ++i) {
    double got = bk_atan2(ys[i], xs[i]), want = atan2(ys[i], xs[i]);
    ENSURE_MSG(ulps(got, want) <= 1 && signbit(got) == signbit(want),
               "atan2(%g, %g) = %.17g, C library %.17g", ys[i], xs[i], got, want);
  }
}

// The bits of fixed arguments' results: the same in every build. A change
// of the functions changes this digest, and every tree with it (raise
// BK_FRACTURE_GENERATION and update tests/tree_hashes.txt).
static void test_digest(void) {
  uint64_t digest = 0xcbf29ce484222325ull;
  for (int i = -500; i <= 500; ++i) {
    double x = i * 0.0731;
    const double r[8] = {bk_sin(x),        bk_cos(x),         bk_atan2(x, 0.77),      bk_cbrt(x * 13.0),
                         bk_log2(i + 501), bk_exp2(x * 0.25), bk_pow(i + 501.0, 0.3), bk_hypot(x, 1.5)};
    for (int k = 0; k < 8; ++k)
      digest = (digest ^ bits_of(r[k])) * 0x100000001b3ull;
  }
  printf("digest of 8008 results: %016llx\n", (unsigned long long)digest);
  ENSURE_MSG(digest == DET_MATH_DIGEST, "digest %016llx, expected %016llx", (unsigned long long)digest,
             (unsigned long long)DET_MATH_DIGEST);
}

typedef struct keyed {
  int key;
  int order;
} keyed;

static int compare_keyed(const void* a, const void* b) {
  int x = ((const keyed*)a)->key, y = ((const keyed*)b)->key;
  return (x > y) - (x < y);
}

static void test_sort(void) {
  uint64_t s = 12345;
  const size_t sizes[] = {0, 1, 2, 15, 16, 17, 31, 32, 33, 100, 1000, 4097};
  for (size_t n = 0; n < sizeof sizes / sizeof sizes[0]; ++n) {
    size_t count = sizes[n];
    keyed* a = malloc((count + 1) * sizeof *a);
    for (size_t i = 0; i < count; ++i)
      a[i] = (keyed){(int)(next_random(&s) % 7), (int)i}; // many ties
    bk_sort(a, count, sizeof *a, compare_keyed);
    for (size_t i = 1; i < count; ++i) {
      ENSURE_MSG(a[i - 1].key <= a[i].key, "%zu elements: not sorted at %zu", count, i);
      if (a[i - 1].key == a[i].key)
        ENSURE_MSG(a[i - 1].order < a[i].order, "%zu elements: equal keys out of their order at %zu", count,
                   i);
    }
    free(a);
  }
}

int main(void) {
  RUN(test_accuracy);
  RUN(test_exact_and_special);
  RUN(test_digest);
  RUN(test_sort);
  return 0;
}
