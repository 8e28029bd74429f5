// Number options: a whole number is exactly [0-9]+ and a real number exactly
// plain decimal; anything else (blanks, signs on whole numbers, hex, inf, nan,
// trailing text) is refused, as is a number outside the option's range, with
// one line that names the option, the text and the range.
#include <fcntl.h>
#include <float.h>
#include <unistd.h>

// The parsers belong to the executable, not to a library: compile them in.
#include "../src/shared/app_util.c"
#include "ensure.h"

static void test_whole_numbers(void) {
  uint64_t v = 0;
  ENSURE(parse_u64("0", 0, 10, &v) && v == 0);
  ENSURE(parse_u64("007", 0, 10, &v) && v == 7);
  ENSURE(parse_u64("1048576", 1, 1u << 20, &v) && v == 1048576);
  ENSURE(parse_u64("18446744073709551615", 0, UINT64_MAX, &v) && v == UINT64_MAX);
  const char* malformed[] = {"",    " 1", "1 ",    "\t1",  "1\n",      "-1",
                             " -1", "+1", "-0",    "0x10", "010x",     "1e3",
                             "1.0", "1.", "1,000", "one",  "\xd9\xa1", " -18446744073709551615"};
  for (size_t i = 0; i < sizeof malformed / sizeof *malformed; ++i) {
    v = 42;
    ENSURE_MSG(!parse_u64(malformed[i], 0, UINT64_MAX, &v) && v == 42, "'%s' accepted", malformed[i]);
  }
  const char* too_big[] = {"18446744073709551616", "99999999999999999999999999"};
  for (size_t i = 0; i < sizeof too_big / sizeof *too_big; ++i)
    ENSURE_MSG(!parse_u64(too_big[i], 0, UINT64_MAX, &v) && v == 42, "'%s' accepted", too_big[i]);
  ENSURE(!parse_u64("0", 1, 10, &v) && !parse_u64("11", 1, 10, &v) && v == 42);
  ENSURE(!parse_u64(NULL, 0, 10, &v));
}

static void test_real_numbers(void) {
  double v = 0.0;
  ENSURE(parse_double("0.1", 1e-6, 1e6, &v) && v == 0.1);
  ENSURE(parse_double(".5", 0, 3, &v) && v == 0.5);
  ENSURE(parse_double("5.", 0, 10, &v) && v == 5.0);
  ENSURE(parse_double("+2", 0, 3, &v) && v == 2.0);
  ENSURE(parse_double("-2.5e-1", -1, 1, &v) && v == -0.25);
  ENSURE(parse_double("1E6", 1e-6, 1e6, &v) && v == 1e6);
  ENSURE(parse_double("1e-6", 1e-6, 1e6, &v) && v == 1e-6); // the bounds belong to the range
  ENSURE(parse_double("1e+6", 1e-6, 1e6, &v) && v == 1e6);
  ENSURE(parse_double("-0", 0, 3, &v) && v == 0.0 && !signbit(v));
  // Rounding to 0 is fine where 0 is allowed...
  ENSURE(parse_double("1e-400", 0, 3, &v) && v == 0.0);
  const char* malformed[] = {"",         " 0.5", "0.5 ", "\t1",   "1\n", "0x1p-3", "0X10", "inf",     "-inf",
                             "infinity", "nan",  "NAN",  ".",     "-.",  "e5",     "1e",   "1e+",     "1.2.3",
                             "1,5",      "--1",  "+-1",  "1e5.0", "1f",  "0.5m",   "1e 5", "\xd9\xa1"};
  for (size_t i = 0; i < sizeof malformed / sizeof *malformed; ++i) {
    v = 42.0;
    ENSURE_MSG(!parse_double(malformed[i], -1e9, 1e9, &v) && v == 42.0, "'%s' accepted", malformed[i]);
  }
  // ...but not where it is not, nor a denormal; overflow is never a number.
  const char* out_of_range[] = {"1e-300", "4.9e-324", "1e-400", "0", "1e999", "-1e999", "1000000.1", "-1"};
  for (size_t i = 0; i < sizeof out_of_range / sizeof *out_of_range; ++i)
    ENSURE_MSG(!parse_double(out_of_range[i], 1e-6, 1e6, &v) && v == 42.0, "'%s' accepted", out_of_range[i]);
  ENSURE(!parse_double("1e-310", DBL_MIN, 1.0, &v) && v == 42.0);
  ENSURE(!parse_double(NULL, 0, 1, &v));
}

// Runs one option parse with stderr sent to a file; returns what it printed.
static char captured[512];
static bool capture(bool (*parse)(void), const char* path) {
  fflush(stderr);
  int saved = dup(STDERR_FILENO);
  int file = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ENSURE(saved >= 0 && file >= 0);
  dup2(file, STDERR_FILENO);
  close(file);
  bool ok = parse();
  fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
  FILE* f = fopen(path, "rb");
  ENSURE(f != NULL);
  size_t n = fread(captured, 1, sizeof captured - 1, f);
  captured[n] = 0;
  fclose(f);
  return ok;
}

static const char* option_text;
static bool parse_seed(void) {
  uint64_t v = 0;
  return option_u64("fracture", "--seed", option_text, 0, UINT64_MAX, &v);
}
static bool parse_texture_scale(void) {
  double v = 0.0;
  return option_double("fracture", "--texture-scale", option_text, 1e-6, 1e6, &v);
}
static bool parse_speed(void) {
  double v = 0.0;
  return option_double("sim", "--speed", option_text, 0.1, 2000.0, &v);
}

static void expect_message(bool (*parse)(void), const char* text, const char* message) {
  option_text = text;
  ENSURE_MSG(!capture(parse, BK_TEST_TMP "/options_stderr.txt"), "'%s' accepted", text);
  ENSURE_MSG(strcmp(captured, message) == 0, "got '%s', expected '%s'", captured, message);
}

static void test_messages(void) {
  expect_message(parse_seed, " -1",
                 "breakables fracture: --seed ' -1' is not a whole number (0..18446744073709551615)\n");
  expect_message(
      parse_seed, "18446744073709551616",
      "breakables fracture: --seed '18446744073709551616' is out of range (0..18446744073709551615)\n");
  // A newline or other control character in the text cannot break the line.
  expect_message(
      parse_seed, "1\n2\r",
      "breakables fracture: --seed '1\\x0a2\\x0d' is not a whole number (0..18446744073709551615)\n");
  expect_message(parse_texture_scale, "1e-300",
                 "breakables fracture: --texture-scale '1e-300' is out of range (1e-6..1e6)\n");
  expect_message(parse_texture_scale, "0x1p-3",
                 "breakables fracture: --texture-scale '0x1p-3' is not a decimal number (1e-6..1e6)\n");
  expect_message(parse_speed, "nan", "breakables sim: --speed 'nan' is not a decimal number (0.1..2000)\n");
  // Long text is cut short.
  char long_text[300];
  memset(long_text, '7', sizeof long_text - 1);
  long_text[sizeof long_text - 1] = 0;
  option_text = long_text;
  ENSURE(!capture(parse_seed, BK_TEST_TMP "/options_stderr.txt"));
  ENSURE_MSG(strlen(captured) < 160 && strstr(captured, "...' is out of range"), "%s", captured);
  option_text = "123";
  ENSURE(capture(parse_seed, BK_TEST_TMP "/options_stderr.txt") && captured[0] == 0);
}

int main(void) {
  RUN(test_whole_numbers);
  RUN(test_real_numbers);
  RUN(test_messages);
  return 0;
}
