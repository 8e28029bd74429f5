// A stable merge sort for every library's sorting, in place of the C
// library's qsort: qsort's order of equal elements is the C library's own
// (glibc merges, musl and emscripten's libc use smoothsort), and trees must be
// the same bytes on every machine and in the browser. glibc's qsort is a
// stable merge sort for arrays this size, so native results are unchanged.
#include <string.h>

#include "bk_base.h"

// Merges the sorted runs [lo, mid) and [mid, hi) of `from` into `to`.
static void merge(const char* from, char* to, size_t lo, size_t mid, size_t hi, size_t size,
                  int (*compare)(const void*, const void*)) {
  size_t i = lo, j = mid, k = lo;
  while (i < mid && j < hi) {
    // Ties take the left run first: that is what keeps the sort stable.
    if (compare(from + j * size, from + i * size) < 0)
      memcpy(to + k++ * size, from + j++ * size, size);
    else
      memcpy(to + k++ * size, from + i++ * size, size);
  }
  if (i < mid) memcpy(to + k * size, from + i * size, (mid - i) * size), k += mid - i;
  if (j < hi) memcpy(to + k * size, from + j * size, (hi - j) * size);
}

void bk_sort(void* base, size_t count, size_t size, int (*compare)(const void*, const void*)) {
  if (count < 2 || size == 0) return;
  char* a = base;
  // Short runs by insertion (stable: an element moves left only past greater ones).
  enum { RUN = 16 };
  char* hold = bk_alloc(size);
  for (size_t lo = 0; lo < count; lo += RUN) {
    size_t hi = lo + RUN < count ? lo + RUN : count;
    for (size_t i = lo + 1; i < hi; ++i) {
      size_t j = i;
      if (compare(a + (j - 1) * size, a + i * size) <= 0) continue;
      memcpy(hold, a + i * size, size);
      while (j > lo && compare(a + (j - 1) * size, hold) > 0) {
        memcpy(a + j * size, a + (j - 1) * size, size);
        --j;
      }
      memcpy(a + j * size, hold, size);
    }
  }
  bk_free(hold);
  if (count <= RUN) return;
  char* scratch = bk_alloc(count * size);
  char* from = a;
  char* to = scratch;
  for (size_t width = RUN; width < count; width *= 2) {
    for (size_t lo = 0; lo < count; lo += 2 * width) {
      size_t mid = lo + width < count ? lo + width : count;
      size_t hi = lo + 2 * width < count ? lo + 2 * width : count;
      merge(from, to, lo, mid, hi, size, compare);
    }
    char* t = from;
    from = to, to = t;
  }
  if (from != a) memcpy(a, from, count * size);
  bk_free(scratch);
}
