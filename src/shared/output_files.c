// The files a command was asked to write, checked before any work: each has
// a name the later writer accepts, a directory that exists, and a target that
// may be replaced (not read-only, not a directory); none is one of the files
// the command reads, and no two are the same file (else one would be lost).
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "app.h"

// Whether path ends in one of the space-separated extensions (".glb .gltf").
static bool has_extension(const char* path, const char* extensions, bool any_case) {
  size_t length = strlen(path);
  for (const char* e = extensions; *e;) {
    size_t n = strcspn(e, " ");
    if (length > n &&
        (any_case ? strncasecmp(path + length - n, e, n) : strncmp(path + length - n, e, n)) == 0)
      return true;
    e += n + (e[n] == ' ');
  }
  return false;
}

// "a, b or c" from "a b c".
static void list_extensions(const char* extensions, char* out, size_t size) {
  size_t used = 0, count = 0, total = 0;
  for (const char* e = extensions; *e; e += strcspn(e, " ") + (e[strcspn(e, " ")] == ' '))
    ++total;
  out[0] = 0;
  for (const char* e = extensions; *e && used < size; ++count) {
    size_t n = strcspn(e, " ");
    const char* separator = count == 0 ? "" : count + 1 == total ? " or " : ", ";
    int written = snprintf(out + used, size - used, "%s%.*s", separator, (int)n, e);
    used += written > 0 ? (size_t)written : 0;
    e += n + (e[n] == ' ');
  }
}

bool app_check_files(const app_file* inputs, uint32_t input_count, const app_file* outputs,
                     uint32_t output_count, bk_error* err) {
  bool ok = true;
  for (uint32_t i = 0; i < output_count && ok; ++i) {
    const app_file* out = &outputs[i];
    if (!out->path) continue;
    if (out->extensions && !has_extension(out->path, out->extensions, out->any_case)) {
      char list[96];
      list_extensions(out->extensions, list, sizeof list);
      ok = bk_error_set(err, "%s '%s': the file name must end in %s", out->option, out->path, list);
    } else if (!bk_file_check_write(out->path, err)) {
      ok = false;
    }
    for (uint32_t k = 0; k < input_count && ok; ++k)
      if (inputs[k].path && bk_file_same(out->path, inputs[k].path))
        ok = bk_error_set(err, "%s '%s' is the file %s reads; refusing to overwrite it", out->option,
                          out->path, inputs[k].option);
    for (uint32_t k = 0; k < i && ok; ++k)
      if (outputs[k].path && bk_file_same(out->path, outputs[k].path))
        ok = bk_error_set(err, "%s '%s' and %s '%s' are the same file; give each its own name",
                          outputs[k].option, outputs[k].path, out->option, out->path);
  }
  return ok;
}
