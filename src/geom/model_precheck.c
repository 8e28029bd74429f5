// Checks a model file's header before assimp reads it, for the formats whose
// readers size their arrays from counts in the header (PLY, OFF): a count
// the file cannot possibly hold is refused here, so a 200-byte file claiming
// four billion vertices costs nothing instead of a 48 GB allocation. A .glb
// must have a consistent binary glTF header for the same reason.
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"
#include "model_import.h"

// Next whitespace-separated word of a line; false at the line's end.
static bool next_word(const char** cursor, const char* end, const char** word, size_t* length) {
  const char* s = *cursor;
  while (s < end && (*s == ' ' || *s == '\t' || *s == '\r'))
    ++s;
  const char* e = s;
  while (e < end && *e != ' ' && *e != '\t' && *e != '\r' && *e != '\n')
    ++e;
  *cursor = e;
  *word = s;
  *length = (size_t)(e - s);
  return e > s;
}

static bool word_is(const char* word, size_t length, const char* text) {
  return length == strlen(text) && memcmp(word, text, length) == 0;
}

static uint64_t parse_count(const char* word, size_t length) {
  uint64_t value = 0;
  for (size_t i = 0; i < length; ++i) {
    if (word[i] < '0' || word[i] > '9') return UINT64_MAX;
    if (value < (1ull << 50)) value = value * 10 + (uint64_t)(word[i] - '0');
  }
  return length ? value : UINT64_MAX;
}

// Size of a PLY scalar type; 0 if `word` is none.
static uint32_t ply_type_size(const char* word, size_t length) {
  static const char* const names[] = {"char",  "uchar",   "int8",   "uint8",  "short", "ushort",
                                      "int16", "uint16",  "int",    "uint",   "int32", "uint32",
                                      "float", "float32", "double", "float64"};
  static const uint32_t sizes[] = {1, 1, 1, 1, 2, 2, 2, 2, 4, 4, 4, 4, 4, 4, 8, 8};
  for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; ++i)
    if (word_is(word, length, names[i])) return sizes[i];
  return 0;
}

// Refuses an element whose declared count needs more bytes than the file
// has: at least `min_bytes` each (binary: its fixed-size properties and list
// counts; ascii: one digit and a separator per property).
static bool check_element(const char* name, const char* element, size_t element_length, uint64_t count,
                          uint64_t min_bytes, uint64_t file_size, bk_error* err) {
  if (count == UINT64_MAX || (min_bytes > 0 && count > file_size / min_bytes))
    return bk_error_set(err,
                        "%s: header declares %llu %.*s elements, more than the file's %llu bytes can hold",
                        name, (unsigned long long)count, (int)(element_length < 32 ? element_length : 32),
                        element, (unsigned long long)file_size);
  return true;
}

// assimp's PLY reader trusts the header (a header cut short in a property
// line crashes it), so the header must be well formed: "ply", then format,
// element NAME COUNT and property [list TYPE] TYPE NAME lines (any other line
// is a comment), then end_header, all within the part read.
static bool precheck_ply(const char* name, const char* head, size_t size, uint64_t file_size, bk_error* err) {
  const char* end = head + size;
  const char* line = head;
  bool binary = false, have_format = false;
  const char* element = NULL;
  size_t element_length = 0;
  uint64_t count = 0, min_bytes = 0;
  for (uint32_t number = 1; line < end; ++number) {
    const char* eol = memchr(line, '\n', (size_t)(end - line));
    if (!eol) eol = end;
    const char* cursor = line;
    const char* word = NULL;
    size_t length = 0;
    bool ok = next_word(&cursor, eol, &word, &length);
    if (number == 1) {
      ok = ok && word_is(word, length, "ply") && !next_word(&cursor, eol, &word, &length);
    } else if (!ok || word_is(word, length, "comment") || word_is(word, length, "obj_info")) {
      ok = true;
    } else if (word_is(word, length, "format")) {
      ok = next_word(&cursor, eol, &word, &length) && !have_format;
      binary = ok && !word_is(word, length, "ascii");
      ok = ok && (!binary || word_is(word, length, "binary_little_endian") ||
                  word_is(word, length, "binary_big_endian"));
      have_format = true;
    } else if (word_is(word, length, "element") || word_is(word, length, "end_header")) {
      if (element && !check_element(name, element, element_length, count, min_bytes, file_size, err))
        return false;
      element = NULL;
      if (word_is(word, length, "end_header")) {
        if (!have_format) return bk_error_set(err, "%s: malformed PLY header: no format line", name);
        return true;
      }
      const char* count_word = NULL;
      size_t count_length = 0;
      ok = next_word(&cursor, eol, &word, &length) && next_word(&cursor, eol, &count_word, &count_length);
      if (ok) {
        element = word, element_length = length;
        count = parse_count(count_word, count_length);
        min_bytes = 0;
      }
    } else if (word_is(word, length, "property")) {
      ok = element != NULL && next_word(&cursor, eol, &word, &length);
      if (ok && word_is(word, length, "list")) {
        ok = next_word(&cursor, eol, &word, &length) && ply_type_size(word, length);
        uint32_t count_size = ok ? ply_type_size(word, length) : 0;
        ok = ok && next_word(&cursor, eol, &word, &length) && ply_type_size(word, length);
        min_bytes += binary ? count_size : 2;
      } else if (ok) {
        ok = ply_type_size(word, length) != 0;
        min_bytes += binary ? ply_type_size(word, length) : 2;
      }
      ok = ok && next_word(&cursor, eol, &word, &length); // the property's name
    } // other lines are comments to assimp (exporters write free text)
    if (!ok) return bk_error_set(err, "%s: malformed PLY header at line %u", name, number);
    line = eol + 1;
  }
  return bk_error_set(err, "%s: malformed PLY header: no end_header in the first %zu bytes", name, size);
}

static bool precheck_off(const char* name, const char* head, size_t size, uint64_t file_size, bk_error* err) {
  // "[ST][C][N][4]OFF", comments, then "vertices faces edges".
  const char* end = head + size;
  const char* line = head;
  bool magic = false;
  while (line < end) {
    const char* eol = memchr(line, '\n', (size_t)(end - line));
    if (!eol) eol = end;
    const char* cursor = line;
    const char* word = NULL;
    size_t length = 0;
    if (next_word(&cursor, eol, &word, &length) && word[0] != '#') {
      if (!magic && length >= 3 && memcmp(word + length - 3, "OFF", 3) == 0) {
        magic = true;
        if (!next_word(&cursor, eol, &word, &length)) {
          line = eol + 1;
          continue;
        }
      }
      uint64_t vertices = parse_count(word, length), faces = 0;
      if (next_word(&cursor, eol, &word, &length)) faces = parse_count(word, length);
      // Each vertex takes at least "0 0 0\n", each face "3 0 0 0\n" (ascii) or more (binary).
      return check_element(name, "vertex", 6, vertices, 6, file_size, err) &&
             check_element(name, "face", 4, faces, 8, file_size, err);
    }
    line = eol + 1;
  }
  return true;
}

static uint32_t read_u32le(const unsigned char* p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

// Binary glTF: assimp allocates the JSON chunk by its declared length, and
// with any other bytes tries other readers; so the header must be a glTF 2
// header whose lengths fit the file.
static bool precheck_glb(const char* name, const unsigned char* head, size_t size, uint64_t file_size,
                         bk_error* err) {
  if (size < 20 || memcmp(head, "glTF", 4) != 0)
    return bk_error_set(err, "%s: not a binary glTF file (no 'glTF' header)", name);
  uint32_t version = read_u32le(head + 4), length = read_u32le(head + 8), json = read_u32le(head + 12);
  if (version != 2)
    return bk_error_set(err, "%s: binary glTF version %u is not supported (expected 2)", name, version);
  if (length > file_size)
    return bk_error_set(err, "%s: truncated binary glTF (header says %u bytes, the file has %llu)", name,
                        length, (unsigned long long)file_size);
  if (length < 20 || json > length - 20 || memcmp(head + 16, "JSON", 4) != 0)
    return bk_error_set(err, "%s: corrupt binary glTF (JSON chunk of %u bytes in a file of %u)", name, json,
                        length);
  uint64_t next = 20ull + json;
  if (next + 8 <= length && next + 8 <= size) {
    uint32_t bin = read_u32le(head + next);
    if (bin > length - next - 8)
      return bk_error_set(err, "%s: corrupt binary glTF (chunk of %u bytes past the file's end)", name, bin);
  }
  return true;
}

bool bk_import_precheck(const char* name, const char* ext, const void* head, size_t size, uint64_t file_size,
                        bk_error* err) {
  if (file_size == 0) return true; // the caller refuses empty files in its own words
  if (strcmp(ext, "ply") == 0) return precheck_ply(name, head, size, file_size, err);
  if (strcmp(ext, "off") == 0) return precheck_off(name, head, size, file_size, err);
  if (strcmp(ext, "glb") == 0) return precheck_glb(name, head, size, file_size, err);
  return true;
}
