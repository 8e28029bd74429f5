// Runs the breakables executable as a user would: a shell argument string
// in, its stdout, stderr and exit status out. A test defines RUN_STDERR_PATH
// (a file of its own under BK_TEST_TMP, as ctest runs tests in parallel)
// before including this.
#pragma once

#include <stdio.h>
#include <sys/wait.h>

#include "ensure.h"

#ifndef RUN_STDERR_PATH
#error "define RUN_STDERR_PATH (a file of this test's own) before including run_exe.h"
#endif

typedef struct run_result {
  int status; ///< exit status, -1 when killed by a signal
  char out[1 << 16];
  char err[1 << 14];
} run_result;

static run_result run_result_storage;

// Reads what fits of a stream into a NUL-terminated buffer.
static void run_read_all(FILE* f, char* buffer, size_t size) {
  size_t n = fread(buffer, 1, size - 1, f);
  buffer[n] = 0;
}

// Runs a shell command whose stderr goes to RUN_STDERR_PATH; its output,
// stderr and exit status.
static run_result* run_command(const char* command) {
  FILE* pipe = popen(command, "r");
  ENSURE(pipe != NULL);
  run_read_all(pipe, run_result_storage.out, sizeof run_result_storage.out);
  int status = pclose(pipe);
  run_result_storage.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  FILE* err = fopen(RUN_STDERR_PATH, "rb");
  ENSURE(err != NULL);
  run_read_all(err, run_result_storage.err, sizeof run_result_storage.err);
  fclose(err);
  return &run_result_storage;
}

static run_result* run(const char* args) {
  char command[4096] = {0};
  snprintf(command, sizeof command, "'%s' %s 2>'%s'", BK_BREAKABLES_EXE, args, RUN_STDERR_PATH);
  return run_command(command);
}

static inline int count_lines(const char* text) {
  int lines = 0;
  for (const char* p = text; *p; ++p)
    lines += *p == '\n';
  return lines;
}
