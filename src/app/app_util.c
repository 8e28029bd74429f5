// Small helpers shared by the subcommands: number parsing, clocks, memory, assets.
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "app.h"

bool bk_parse_u64(const char* text, uint64_t min, uint64_t max, uint64_t* out) {
  if (!text || !*text || *text == '-' || *text == '+') return false;
  char* end = NULL;
  errno = 0;
  unsigned long long v = strtoull(text, &end, 10);
  if (errno || *end || v < min || v > max) return false;
  *out = v;
  return true;
}

bool bk_parse_double(const char* text, double min_exclusive, double max_inclusive, double* out) {
  if (!text || !*text) return false;
  char* end = NULL;
  errno = 0;
  double v = strtod(text, &end);
  if (errno || *end || !isfinite(v) || v <= min_exclusive || v > max_inclusive) return false;
  *out = v;
  return true;
}

double bk_now_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

double bk_peak_rss_mb(void) {
  struct rusage usage = {0};
  getrusage(RUSAGE_SELF, &usage);
  return (double)usage.ru_maxrss / 1024.0; // ru_maxrss is in KiB on Linux
}

const char* bk_app_asset_dir(void) {
  // Prefer assets installed beside the executable (../assets from build/),
  // then the source tree the binary was built from.
  static char dir[PATH_MAX];
  char exe[PATH_MAX] = {0};
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) {
    exe[n] = 0;
    char* slash = strrchr(exe, '/');
    if (slash) {
      *slash = 0;
      const char* candidates[] = {"/assets", "/../assets"};
      for (size_t i = 0; i < sizeof candidates / sizeof *candidates; ++i) {
        snprintf(dir, sizeof dir, "%s%s", exe, candidates[i]);
        char probe[PATH_MAX + 32];
        snprintf(probe, sizeof probe, "%s/meshes/bunny.obj", dir);
        if (access(probe, R_OK) == 0) return dir;
      }
    }
  }
  return BK_ASSET_DIR;
}

static int compare_double(const void* a, const void* b) {
  double x = *(const double*)a, y = *(const double*)b;
  return x < y ? -1 : x > y;
}

double bk_median(double* values, uint32_t count) {
  if (count == 0) return 0.0;
  qsort(values, count, sizeof(double), compare_double);
  return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}
