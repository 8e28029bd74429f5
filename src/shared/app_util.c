// Small helpers shared by the subcommands: number parsing, clocks, memory, assets.
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "app.h"

// Option values are parsed strictly: strtoull and strtod skip leading blanks,
// take a sign (strtoull then negates: " -1" becomes 2^64 - 1), hex, "inf" and
// "nan", all of which a command line should refuse rather than reinterpret.

typedef enum number_status {
  NUMBER_OK,
  NUMBER_MALFORMED,    // not exactly a number of the option's kind
  NUMBER_OUT_OF_RANGE, // a number, but outside the range (or beyond a double)
} number_status;

static bool is_digit(char c) { return c >= '0' && c <= '9'; }

static number_status scan_u64(const char* text, uint64_t min, uint64_t max, uint64_t* out) {
  if (!text || !is_digit(*text)) return NUMBER_MALFORMED;
  uint64_t value = 0;
  bool overflow = false;
  const char* p = text;
  for (; is_digit(*p); ++p) {
    uint64_t digit = (uint64_t)(*p - '0');
    if (value > (UINT64_MAX - digit) / 10) overflow = true;
    value = overflow ? UINT64_MAX : value * 10 + digit;
  }
  if (*p) return NUMBER_MALFORMED;
  if (overflow || value < min || value > max) return NUMBER_OUT_OF_RANGE;
  *out = value;
  return NUMBER_OK;
}

// Skips [0-9]* and says whether a digit was seen.
static bool skip_digits(const char** p) {
  const char* start = *p;
  while (is_digit(**p))
    ++*p;
  return *p != start;
}

static number_status scan_double(const char* text, double min, double max, double* out) {
  // [+-]? (digits [. digits?] | . digits) ([eE] [+-]? digits)?, nothing else.
  if (!text) return NUMBER_MALFORMED;
  const char* p = text;
  if (*p == '+' || *p == '-') ++p;
  bool whole = skip_digits(&p), fraction = false;
  if (*p == '.') {
    ++p;
    fraction = skip_digits(&p);
  }
  if (!whole && !fraction) return NUMBER_MALFORMED;
  if (*p == 'e' || *p == 'E') {
    ++p;
    if (*p == '+' || *p == '-') ++p;
    if (!skip_digits(&p)) return NUMBER_MALFORMED;
  }
  if (*p) return NUMBER_MALFORMED;
  // The text is plain decimal, which strtod reads the same in every locale
  // that keeps '.' as the radix (the program never calls setlocale).
  char* end = NULL;
  double value = strtod(text, &end);
  if (end != p || !isfinite(value)) return NUMBER_OUT_OF_RANGE;
  // Underflow rounds to 0 or a denormal; the range check below refuses it
  // whenever 0 is not allowed (min > 0).
  if (value == 0.0) value = 0.0; // -0 reads as 0
  if (!(value >= min && value <= max)) return NUMBER_OUT_OF_RANGE;
  *out = value;
  return NUMBER_OK;
}

bool parse_u64(const char* text, uint64_t min, uint64_t max, uint64_t* out) {
  return scan_u64(text, min, max, out) == NUMBER_OK;
}

bool parse_double(const char* text, double min, double max, double* out) {
  return scan_double(text, min, max, out) == NUMBER_OK;
}

void format_number(double value, char* out, size_t size) {
  char text[64] = "";
  int digits = 1;
  for (; digits < 17; ++digits) {
    snprintf(text, sizeof text, "%.*e", digits - 1, value);
    if (strtod(text, NULL) == value) break;
  }
  snprintf(text, sizeof text, "%.*e", digits - 1, value);
  char* e = strchr(text, 'e');
  int exponent = e ? atoi(e + 1) : 0;
  if (value == 0.0 || (exponent >= -4 && exponent < 4)) {
    int decimals = digits - 1 - exponent;
    snprintf(out, size, "%.*f", decimals > 0 ? decimals : 0, value);
  } else {
    *e = 0;
    snprintf(out, size, "%se%d", text, exponent);
  }
}

void app_warning(const char* format, ...) {
  char text[1024], shown[4096];
  va_list args;
  va_start(args, format);
  vsnprintf(text, sizeof text, format, args);
  va_end(args);
  bk_escape_text(text, strlen(text), shown, sizeof shown);
  fprintf(stderr, "breakables: warning: %s\n", shown);
}

void quote_text(const char* text, char* out, size_t size) {
  if (size < 4) {
    if (size > 0) out[0] = 0;
    return;
  }
  // At most 60 bytes shown, escaped as every message is, with room for "...".
  size_t length = strlen(text), room = size - 3 < 61 ? size - 3 : 61;
  if (bk_escape_text(text, length, out, room) < length) strcat(out, "...");
}

bool option_u64(const char* command, const char* option, const char* text, uint64_t min, uint64_t max,
                uint64_t* out) {
  number_status status = scan_u64(text, min, max, out);
  if (status == NUMBER_OK) return true;
  char shown[96] = "";
  quote_text(text ? text : "", shown, sizeof shown);
  fprintf(stderr, "breakables %s: %s '%s' is %s (%llu..%llu)\n", command, option, shown,
          status == NUMBER_MALFORMED ? "not a whole number" : "out of range", (unsigned long long)min,
          (unsigned long long)max);
  return false;
}

// The arguments split_option_values made, kept for the program's life.
static char** split_arguments;

// "--name=value" with a name of lower-case letters, digits and dashes: an
// option and its value. Anything else (a value such as "a=b.obj", "--=x")
// is an argument as it stands.
static size_t option_name_length(const char* arg) {
  if (strncmp(arg, "--", 2) != 0) return 0;
  size_t n = 2;
  while ((arg[n] >= 'a' && arg[n] <= 'z') || is_digit(arg[n]) || arg[n] == '-')
    ++n;
  return n > 2 && arg[n] == '=' ? n : 0;
}

char** split_option_values(int* argc, char** argv) {
  int count = *argc, extra = 0;
  for (int i = 1; i < count; ++i)
    extra += option_name_length(argv[i]) > 0;
  if (extra == 0) return argv;
  char** out = bk_alloc(sizeof(char*) * ((size_t)count + (size_t)extra + 1));
  int n = 0;
  for (int i = 0; i < count; ++i) {
    size_t length = i > 0 ? option_name_length(argv[i]) : 0;
    if (length == 0) {
      out[n++] = argv[i];
      continue;
    }
    char* name = bk_alloc(length + 1);
    memcpy(name, argv[i], length);
    name[length] = 0;
    out[n++] = name;
    out[n++] = argv[i] + length + 1;
  }
  out[n] = NULL;
  split_arguments = out;
  *argc = n;
  return out;
}

int take_option(const char* command, int argc, char** argv, int* i, const char* const* names, int count,
                const char** value) {
  const char* arg = argv[*i];
  int which = -1;
  for (int k = 0; k < count; ++k)
    if (strcmp(arg, names[k]) == 0) which = k;
  if (which < 0) return -1;
  if (*i + 1 >= argc) {
    fprintf(stderr, "breakables %s: %s needs a value (see 'breakables %s --help')\n", command, arg, command);
    return -2;
  }
  *value = argv[++*i];
  return which;
}

bool option_double(const char* command, const char* option, const char* text, double min, double max,
                   double* out) {
  number_status status = scan_double(text, min, max, out);
  if (status == NUMBER_OK) return true;
  char shown[96] = "", low[32] = "", high[32] = "";
  quote_text(text ? text : "", shown, sizeof shown);
  format_number(min, low, sizeof low);
  format_number(max, high, sizeof high);
  fprintf(stderr, "breakables %s: %s '%s' is %s (%s..%s)\n", command, option, shown,
          status == NUMBER_MALFORMED ? "not a decimal number" : "out of range", low, high);
  return false;
}

double app_now_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

double app_peak_rss_mb(void) {
  struct rusage usage = {0};
  getrusage(RUSAGE_SELF, &usage);
  return (double)usage.ru_maxrss / 1024.0; // ru_maxrss is in KiB on Linux
}

const char* app_asset_dir(void) {
  // Prefer data beside the executable: an installed one has it in
  // <prefix>/share/breakables (from <prefix>/bin), a build tree one level up
  // (build/ in the source tree); last, the source tree the binary was built from.
  static char dir[PATH_MAX];
  char exe[PATH_MAX] = {0};
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) {
    exe[n] = 0;
    char* slash = strrchr(exe, '/');
    if (slash) {
      *slash = 0;
      const char* candidates[] = {"/../share/breakables/assets", "/assets", "/../assets"};
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

double app_median(double* values, uint32_t count) {
  if (count == 0) return 0.0;
  qsort(values, count, sizeof(double), compare_double);
  return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

double app_percentile(double* values, uint32_t count, double p) {
  if (count == 0) return 0.0;
  qsort(values, count, sizeof(double), compare_double);
  // Nearest rank: the smallest value with at least p% of them at or below it.
  double rank = ceil(p / 100.0 * count);
  uint32_t index = rank < 1.0 ? 0u : rank >= count ? count - 1 : (uint32_t)rank - 1;
  return values[index];
}

double app_maximum(const double* values, uint32_t count) {
  double m = 0.0;
  for (uint32_t i = 0; i < count; ++i)
    m = values[i] > m ? values[i] : m;
  return m;
}

size_t append_name(char* out, size_t size, size_t used, uint32_t index, uint32_t count, const char* name) {
  if (used >= size) return used;
  int n =
      snprintf(out + used, size - used, "%s%s", index == 0 ? "" : (index + 1 == count ? " or " : ", "), name);
  return n < 0 ? used : used + (size_t)n;
}
