// Relative paths between files, for URIs written into exported files.
#define _XOPEN_SOURCE 700 // realpath
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"

// Splits an absolute path in place into its components.
static uint32_t path_components(char* path, char** parts, uint32_t capacity) {
  uint32_t count = 0;
  char* save = NULL;
  for (char* part = strtok_r(path, "/", &save); part && count < capacity; part = strtok_r(NULL, "/", &save))
    parts[count++] = part;
  return count;
}

bool app_relative_path(const char* from_file, const char* target, char* out, size_t capacity) {
  // Both made absolute (the file itself need not exist yet, its directory
  // must), then: one "../" per directory of from_file's not shared with the
  // target, followed by the target's own remaining components.
  char target_abs[PATH_MAX], dir_abs[PATH_MAX], dir[PATH_MAX];
  if (!realpath(target, target_abs)) return false;
  snprintf(dir, sizeof dir, "%s", from_file);
  char* slash = strrchr(dir, '/');
  if (!slash)
    snprintf(dir, sizeof dir, ".");
  else if (slash == dir)
    dir[1] = 0;
  else
    *slash = 0;
  if (!realpath(dir, dir_abs)) return false;
  char* from_parts[512];
  char* to_parts[512];
  uint32_t from_count = path_components(dir_abs, from_parts, 512);
  uint32_t to_count = path_components(target_abs, to_parts, 512);
  uint32_t common = 0;
  while (common < from_count && common + 1 < to_count && strcmp(from_parts[common], to_parts[common]) == 0)
    common++;
  size_t used = 0;
  out[0] = 0;
  for (uint32_t i = common; i < from_count; ++i) {
    int n = snprintf(out + used, capacity - used, "../");
    if (n < 0 || (size_t)n >= capacity - used) return false;
    used += (size_t)n;
  }
  for (uint32_t i = common; i < to_count; ++i) {
    int n = snprintf(out + used, capacity - used, "%s%s", to_parts[i], i + 1 < to_count ? "/" : "");
    if (n < 0 || (size_t)n >= capacity - used) return false;
    used += (size_t)n;
  }
  return used > 0;
}
