// The tree cache directory as the commands use it: a cache path too long to
// form (or to fit in a message) turns caching off with one whole warning
// line, and a long but possible one still caches.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "ensure.h"
#define RUN_STDERR_PATH BK_TEST_TMP "/cache_dir_stderr.txt"
#include "run_exe.h"

#define SIM_ARGS "sim --scene wall --pieces 8 --steps 1 --shots 0 --json"

// BK_TEST_TMP/cache_dir/ followed by directories of 100 'd's up to `length` bytes in all.
static void long_dir(char* out, size_t size, size_t length) {
  ENSURE(length < size);
  size_t at = (size_t)snprintf(out, size, "%s/cache_dir", BK_TEST_TMP);
  ENSURE(at < length);
  for (size_t component = 0; at < length; ++at, ++component)
    out[at] = component % 101 == 0 ? '/' : 'd';
  out[at] = 0;
  ENSURE(strlen(out) == length);
}

// The one warning: whole (it ends as the message ends), naming the variable, and nothing else.
static void expect_one_warning(const run_result* r, const char* variable) {
  ENSURE_MSG(r->status == 0, "exit %d: %s", r->status, r->err);
  ENSURE_MSG(count_lines(r->err) == 1, "expected one line, got: %s", r->err);
  ENSURE_MSG(
      strncmp(r->err, "breakables: warning: not caching mesh trees: the cache file's path from ", 72) == 0,
      "%s", r->err);
  ENSURE_MSG(strstr(r->err, variable) != NULL, "the warning does not name %s: %s", variable, r->err);
  const char* tail = "(set BREAKABLES_CACHE_DIR to a shorter directory)\n";
  ENSURE_MSG(strlen(r->err) > strlen(tail) && strcmp(r->err + strlen(r->err) - strlen(tail), tail) == 0,
             "the warning is cut: %s", r->err);
  ENSURE_MSG(strstr(r->out, "\"from_cache\": false") != NULL, "%s", r->out);
}

static void test_overlong_cache_dir(void) {
  static char dir[4200];
  long_dir(dir, sizeof dir, 4100); // longer than PATH_MAX: the path cannot even be formed
  setenv("BREAKABLES_CACHE_DIR", dir, 1);
  expect_one_warning(run(SIM_ARGS), "$BREAKABLES_CACHE_DIR");
  // The showcase fractures six objects: still one line.
  expect_one_warning(run("sim --scene showcase --pieces 8 --steps 1 --shots 0 --json"),
                     "$BREAKABLES_CACHE_DIR");

  // Too long for its messages to fit whole, though the file system would take it.
  long_dir(dir, sizeof dir, 400);
  setenv("BREAKABLES_CACHE_DIR", dir, 1);
  expect_one_warning(run(SIM_ARGS), "$BREAKABLES_CACHE_DIR");

  // The same from $XDG_CACHE_HOME.
  unsetenv("BREAKABLES_CACHE_DIR");
  long_dir(dir, sizeof dir, 4100);
  setenv("XDG_CACHE_HOME", dir, 1);
  expect_one_warning(run(SIM_ARGS), "$XDG_CACHE_HOME");
  unsetenv("XDG_CACHE_HOME");
}

static void test_long_cache_dir_still_caches(void) {
  static char dir[512];
  long_dir(dir, sizeof dir, 220);
  char command[1024] = {0};
  snprintf(command, sizeof command, "rm -rf '%s/cache_dir'", BK_TEST_TMP);
  ENSURE(system(command) == 0);
  setenv("BREAKABLES_CACHE_DIR", dir, 1);
  run_result* r = run(SIM_ARGS);
  ENSURE_MSG(r->status == 0 && r->err[0] == 0, "exit %d: %s", r->status, r->err);
  ENSURE_MSG(strstr(r->out, "\"from_cache\": false") != NULL, "%s", r->out);
  r = run(SIM_ARGS);
  ENSURE_MSG(r->status == 0 && r->err[0] == 0, "exit %d: %s", r->status, r->err);
  ENSURE_MSG(strstr(r->out, "\"from_cache\": true") != NULL, "the second run did not use the cache: %s",
             r->out);
}

int main(void) {
  RUN(test_overlong_cache_dir);
  RUN(test_long_cache_dir_still_caches);
  return 0;
}
