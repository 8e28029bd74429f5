// Helpers of the tests that run the breakables command line: files to feed
// it, numbers from its JSON, and its one-line errors. Include after
// run_exe.h (expect_error runs the command).
#pragma once

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ensure.h"

/// Writes text to BK_TEST_TMP/name.
static inline void write_file(const char* name, const char* text) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", BK_TEST_TMP, name);
  FILE* f = fopen(path, "wb");
  ENSURE(f != NULL);
  fputs(text, f);
  fclose(f);
}

/// The number after "key": in a JSON text; fails when it is missing or not a number.
static inline double json_number(const char* json, const char* key) {
  char pattern[64];
  snprintf(pattern, sizeof pattern, "\"%s\": ", key);
  const char* at = strstr(json, pattern);
  ENSURE_MSG(at != NULL, "key %s missing in %s", key, json);
  char* end = NULL;
  double value = strtod(at + strlen(pattern), &end);
  ENSURE_MSG(end != at + strlen(pattern), "key %s is not a number in %s", key, json);
  return value;
}

/// Runs `args` and checks its exit status and that stderr is one line
/// containing `message`.
static inline void expect_error(const char* args, int status, const char* message) {
  run_result* r = run(args);
  ENSURE_MSG(r->status == status, "'%s' exited %d, expected %d (%s)", args, r->status, status, r->err);
  ENSURE_MSG(strstr(r->err, message) != NULL, "'%s': expected '%s' in: %s", args, message, r->err);
  // One line, naming the problem.
  const char* newline = strchr(r->err, '\n');
  ENSURE_MSG(newline && newline[1] == 0, "'%s': error is not one line: %s", args, r->err);
}
