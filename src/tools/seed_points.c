// Seed points for the Voronoi pattern: a text file of "x y z" lines. The
// numbers go through the command line's strict number reader, so a seed
// file accepts exactly the numbers an option would.
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "seed_points.h"

// Longer tokens are not numbers anyone writes; they are refused, not cut.
enum { TOKEN_MAX = 128 };

static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// A token as it can be shown in a one-line message: bytes outside printable
// ASCII as \xNN, long ones cut short.
static void quote_token(const char* token, size_t length, char* out, size_t size) {
  size_t used = 0;
  for (size_t i = 0; i < length && used + 8 < size; ++i) {
    unsigned char c = (unsigned char)token[i];
    if (i >= 40) {
      used += (size_t)snprintf(out + used, size - used, "...");
      break;
    }
    if (c < 0x20 || c >= 0x7f)
      used += (size_t)snprintf(out + used, size - used, "\\x%02x", c);
    else
      out[used++] = (char)c;
  }
  out[used] = 0;
}

// Reads the number of one token; false with err naming the line otherwise.
// Bad syntax, inf, nan and values beyond a double get the same words: the
// token is shown, which says which it is.
static bool read_number(const char* token, size_t length, const char* name, size_t line, double* out,
                        bk_error* err) {
  char text[TOKEN_MAX + 1] = "";
  // A NUL inside the token would end the copy early and let junk through.
  if (length <= TOKEN_MAX && !memchr(token, 0, length)) {
    memcpy(text, token, length);
    text[length] = 0;
    if (parse_double(text, -DBL_MAX, DBL_MAX, out)) return true;
  }
  char shown[96] = "";
  quote_token(token, length, shown, sizeof shown);
  return bk_error_set(err, "%s:%zu: '%s' is not a finite decimal number", name, line, shown);
}

bool seed_points_parse(const char* text, size_t length, const char* name, bk_vec3** points, uint32_t* count,
                       bk_error* err) {
  *points = NULL;
  *count = 0;
  bk_vec3* list = NULL;
  uint32_t used = 0, capacity = 0;
  size_t line = 0;
  for (size_t at = 0; at < length;) {
    ++line;
    const char* end_of_line = memchr(text + at, '\n', length - at);
    size_t stop = end_of_line ? (size_t)(end_of_line - text) : length;
    const char* comment = memchr(text + at, '#', stop - at);
    size_t content_end = comment ? (size_t)(comment - text) : stop;
    double xyz[3] = {0.0, 0.0, 0.0};
    int numbers = 0;
    for (size_t p = at; p < content_end;) {
      if (is_blank(text[p])) {
        ++p;
        continue;
      }
      size_t token_end = p;
      while (token_end < content_end && !is_blank(text[token_end]))
        ++token_end;
      if (numbers == 3) {
        char shown[96] = "";
        quote_token(text + p, token_end - p, shown, sizeof shown);
        free(list);
        return bk_error_set(err, "%s:%zu: expected 3 numbers x y z, found more ('%s')", name, line, shown);
      }
      if (!read_number(text + p, token_end - p, name, line, &xyz[numbers], err)) {
        free(list);
        return false;
      }
      ++numbers;
      p = token_end;
    }
    at = stop + 1;
    if (numbers == 0) continue; // a blank or comment line
    if (numbers != 3) {
      free(list);
      return bk_error_set(err, "%s:%zu: expected 3 numbers x y z, found %d", name, line, numbers);
    }
    if (used == BK_SEED_POINTS_MAX) {
      free(list);
      return bk_error_set(err, "%s:%zu: more than %u points", name, line, BK_SEED_POINTS_MAX);
    }
    if (used == capacity) {
      capacity = bk_grow_capacity(capacity, used + 1);
      list = bk_realloc(list, sizeof(bk_vec3) * capacity);
    }
    list[used++] = bk_v3(xyz[0], xyz[1], xyz[2]);
  }
  if (used == 0) {
    free(list);
    return bk_error_set(err, "%s: no points (%s)", name,
                        length ? "only blank lines and comments" : "the file is empty");
  }
  *points = list;
  *count = used;
  return true;
}

bool seed_points_load(const char* path, bk_vec3** points, uint32_t* count, bk_error* err) {
  *points = NULL;
  *count = 0;
  void* data = NULL;
  size_t size = 0;
  if (!bk_file_read(path, BK_SEED_FILE_MAX_BYTES, "256 MiB", &data, &size, err)) return false;
  bool ok = seed_points_parse(data, size, path, points, count, err);
  free(data);
  return ok;
}
