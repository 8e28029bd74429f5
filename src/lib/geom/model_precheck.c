// Checks a model file's header before assimp reads it, for the formats whose
// readers size their arrays from counts in the header (PLY, OFF): a count
// the file cannot possibly hold is refused here, so a 200-byte file claiming
// four billion vertices costs nothing instead of a 48 GB allocation. A .glb
// must have a consistent binary glTF header for the same reason. Beyond the
// header, bk_import_precheck_content walks a 3DS file's chunk tree (below)
// and checks a glTF document's JSON (model_precheck_gltf.c).
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
    } else {
      // Free text without "comment" (old Blender exports wrote a line of
      // it): our reader takes it as a comment, with a note. assimp 5.2's
      // header parser corrupts its heap or jumps through a null pointer on
      // lines it does not know in damaged files (found by fuzz_import), so
      // bk_import_ply never hands it a header with such a line.
      ok = true;
    }
    // Header lines are plain ASCII text: anything else is a damaged file.
    for (const char* c = line; c < eol && ok; ++c)
      ok = ((unsigned char)*c >= 0x20 && (unsigned char)*c < 0x7f) || *c == '\t' || *c == '\r';
    if (!ok) return bk_error_set(err, "%s: malformed PLY header at line %u", name, number);
    line = eol + 1;
  }
  return bk_error_set(err, "%s: malformed PLY header: no end_header in the first %zu bytes", name, size);
}

// The leading digits of a word, as assimp's strtoul10 reads a count (it
// stops at the first other character; 0 when there is none).
static uint64_t leading_count(const char* word, size_t length) {
  uint64_t value = 0;
  for (size_t i = 0; i < length && word[i] >= '0' && word[i] <= '9'; ++i)
    if (value < (1ull << 50)) value = value * 10 + (uint64_t)(word[i] - '0');
  return value;
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
        // assimp 5.2 skips a line that starts with 'O' whole and reads the
        // counts from the next line's leading digits, whatever the line
        // holds (found by fuzz_import: "OFF 8" over "0500050000" made it
        // allocate 11 GB): those must fit the file too.
        if (eol < end) {
          const char* next_eol = memchr(eol + 1, '\n', (size_t)(end - eol - 1));
          const char* next_cursor = eol + 1;
          uint64_t counts[2] = {0, 0};
          for (int k = 0; k < 2 && next_word(&next_cursor, next_eol ? next_eol : end, &word, &length); ++k)
            counts[k] = leading_count(word, length);
          if (!check_element(name, "vertex", 6, counts[0], 6, file_size, err) ||
              !check_element(name, "face", 4, counts[1], 8, file_size, err))
            return false;
        }
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

// ---------------------------------------------------------------- 3DS
// assimp's 3DS reader (5.2) follows the chunk tree MAIN (0x4D4D) > EDITOR
// (0x3D3D objects, 0xB000 keyframer) > ... and sizes its arrays from counts it
// reads inside chunks: in a keyframer track (position, rotation, roll keys)
// a 32-bit key count is reserved before a single key is read, so 40 bytes can
// ask for 40 GB. The walk below follows the same contexts and requires every
// chunk to nest inside its parent (assimp only logs a chunk that does not,
// and reads on) and every count to fit the bytes left in its chunk.

typedef struct tds_walk {
  const char* name;
  const unsigned char* data;
  bk_error* err;
} tds_walk;

enum { TDS_MAIN, TDS_EDITOR, TDS_OBJECTS, TDS_OBJECT, TDS_MESH, TDS_KEYFRAMER, TDS_TRACK };

static uint16_t read_u16le(const unsigned char* p) { return (uint16_t)(p[0] | p[1] << 8); }

// `count` items of at least `item` bytes each must fit in [at, end) of the
// chunk starting at `chunk`.
static bool tds_count(const tds_walk* w, uint16_t id, size_t chunk, size_t at, size_t end, uint64_t count,
                      uint64_t item, const char* what) {
  if (at > end || count > (end - at) / item)
    return bk_error_set(w->err,
                        "%s: 3DS chunk 0x%04X at byte %zu declares %llu %s, more than its %zu bytes can hold",
                        w->name, id, chunk, (unsigned long long)count, what, end - chunk);
  return true;
}

static bool tds_chunks(const tds_walk* w, size_t begin, size_t end, int context, uint16_t parent) {
  const unsigned char* d = w->data;
  for (size_t at = begin; end - at >= 6;) {
    uint16_t id = read_u16le(d + at);
    uint32_t length = read_u32le(d + at + 2);
    if (length < 6 || length > end - at)
      return bk_error_set(w->err,
                          "%s: 3DS chunk 0x%04X at byte %zu has length %u, which does not fit in its parent "
                          "(%zu bytes left)",
                          w->name, id, at, length, end - at);
    size_t body = at + 6, stop = at + length;
    bool ok = true;
    switch (context) {
    case TDS_MAIN:
      if (id == 0x4D4D) ok = tds_chunks(w, body, stop, TDS_EDITOR, id);
      break;
    case TDS_EDITOR:
      if (id == 0x3D3D) ok = tds_chunks(w, body, stop, TDS_OBJECTS, id);
      if (id == 0xB000) ok = tds_chunks(w, body, stop, TDS_KEYFRAMER, id);
      break;
    case TDS_OBJECTS:
      if (id == 0x4000) { // a NUL-terminated name, then the object's chunks
        const unsigned char* nul = memchr(d + body, 0, stop - body);
        if (!nul)
          return bk_error_set(w->err, "%s: 3DS object chunk at byte %zu has an unterminated name", w->name,
                              at);
        ok = tds_chunks(w, (size_t)(nul - d) + 1, stop, TDS_OBJECT, id);
      }
      break;
    case TDS_OBJECT:
      if (id == 0x4100) ok = tds_chunks(w, body, stop, TDS_MESH, id);
      break;
    case TDS_MESH: // vertices (3 floats), UVs (2 floats), faces (4 shorts): 16-bit counts
      if (id == 0x4110 || id == 0x4140 || id == 0x4120) {
        if (stop - body < 2)
          return bk_error_set(w->err, "%s: 3DS chunk 0x%04X at byte %zu has no count", w->name, id, at);
        uint64_t item = id == 0x4110 ? 12 : 8;
        const char* what = id == 0x4110 ? "vertices" : id == 0x4140 ? "texture coordinates" : "faces";
        ok = tds_count(w, id, at, body + 2, stop, read_u16le(d + body), item, what);
      }
      break;
    case TDS_KEYFRAMER:
      if (id >= 0xB002 && id <= 0xB007) ok = tds_chunks(w, body, stop, TDS_TRACK, id);
      break;
    case TDS_TRACK: // 10 bytes of flags, the key count, then keys of a time, TCB flags and values
      if (id == 0xB020 || id == 0xB021 || (id == 0xB024 && parent == 0xB003)) {
        uint64_t values = id == 0xB020 ? 12 : id == 0xB021 ? 16 : 4;
        if (stop - body < 14)
          return bk_error_set(w->err, "%s: 3DS track chunk 0x%04X at byte %zu has no key count", w->name, id,
                              at);
        ok = tds_count(w, id, at, body + 14, stop, read_u32le(d + body + 10), 6 + values, "keys");
      } else if (id == 0xB022) {
        if (stop - body < 14)
          return bk_error_set(w->err, "%s: 3DS track chunk 0x%04X at byte %zu has no key count", w->name, id,
                              at);
        ok = tds_count(w, id, at, body + 14, stop, read_u16le(d + body + 10), 18, "keys");
      }
      break;
    }
    if (!ok) return false;
    at = stop;
  }
  return true;
}

static bool precheck_3ds(const char* name, const unsigned char* data, size_t size, uint64_t file_size,
                         bk_error* err) {
  if (size < file_size)
    return bk_error_set(err, "%s: 3DS file larger than the %zu bytes checked", name,
                        size); // the callers read it all
  tds_walk w = {.name = name, .data = data, .err = err};
  return tds_chunks(&w, 0, size, TDS_MAIN, 0);
}

// Collada: assimp 5.2 reads the index lists of <p>, <vcount> and <v> with a
// parser that, on a character that is neither a digit nor a space (a "*" or
// a "[" in a damaged file), keeps allocating until it asks for gigabytes.
// Those lists may hold only unsigned integers and whitespace.
//
// It also dereferences a null pointer on an array element (<float_array>,
// <int_array>, ...) without a count attribute: every one must have it.
static bool dae_arrays_counted(const char* name, const char* text, const char* end, bk_error* err) {
  static const char* const arrays[] = {"<float_array", "<int_array", "<bool_array", "<Name_array",
                                       "<IDREF_array"};
  for (const char* at = text; at < end; ++at) {
    if (*at != '<') continue;
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; ++a) {
      size_t length = strlen(arrays[a]);
      if ((size_t)(end - at) < length || memcmp(at, arrays[a], length) != 0) continue;
      const char* open_end = memchr(at, '>', (size_t)(end - at));
      if (!open_end)
        return bk_error_set(err, "%s: Collada element at byte %zu is not closed", name, (size_t)(at - text));
      bool counted = false;
      for (const char* c = at + length; c + 7 <= open_end && !counted; ++c)
        counted = (c[0] == ' ' || c[0] == '\t' || c[0] == '\n' || c[0] == '\r') &&
                  memcmp(c + 1, "count", 5) == 0 && (c[6] == '=' || c[6] == ' ');
      if (!counted)
        return bk_error_set(err, "%s: Collada %s> at byte %zu has no count attribute", name, arrays[a],
                            (size_t)(at - text));
    }
  }
  return true;
}

// A primitive list (<triangles>, <polylist>, <polygons>, <trifans>,
// <tristrips>) that claims primitives (count > 0) but holds no index list
// <p>: assimp's build asserts that it read as many as the count, and aborts.
static bool dae_primitives_listed(const char* name, const char* text, const char* end, bk_error* err) {
  static const char* const lists[] = {"<triangles", "<polylist", "<polygons", "<trifans", "<tristrips"};
  for (const char* at = text; at < end; ++at) {
    if (*at != '<') continue;
    for (size_t l = 0; l < sizeof lists / sizeof *lists; ++l) {
      size_t length = strlen(lists[l]);
      if ((size_t)(end - at) <= length || memcmp(at, lists[l], length) != 0) continue;
      if (at[length] != ' ' && at[length] != '\t' && at[length] != '\n' && at[length] != '\r' &&
          at[length] != '>')
        continue;
      const char* open_end = memchr(at, '>', (size_t)(end - at));
      if (!open_end)
        return bk_error_set(err, "%s: Collada element at byte %zu is not closed", name, (size_t)(at - text));
      // Its count attribute, if any, and whether a <p> follows before it closes.
      unsigned long long count = 0;
      for (const char* c = at + length; c + 7 <= open_end; ++c)
        if ((c[0] == ' ' || c[0] == '\t' || c[0] == '\n' || c[0] == '\r') && memcmp(c + 1, "count", 5) == 0) {
          const char* v = c + 6;
          while (v < open_end && (*v == ' ' || *v == '=' || *v == '"' || *v == '\''))
            ++v;
          while (v < open_end && *v >= '0' && *v <= '9' && count < 1000000000ULL)
            count = count * 10 + (unsigned long long)(*v++ - '0');
          break;
        }
      if (count == 0 || open_end[-1] == '/') {
        if (count > 0)
          return bk_error_set(err, "%s: Collada %s> at byte %zu claims %llu primitives and lists none", name,
                              lists[l], (size_t)(at - text), count);
        continue;
      }
      bool listed = false;
      for (const char* c = open_end + 1; c + 2 < end && !listed; ++c) {
        if (*c != '<') continue;
        if (c[1] == '/' && (size_t)(end - c) > length && memcmp(c + 2, lists[l] + 1, length - 1) == 0) break;
        listed = c[1] == 'p' && (c[2] == '>' || c[2] == ' ' || c[2] == '/');
      }
      if (!listed)
        return bk_error_set(err, "%s: Collada %s> at byte %zu claims %llu primitives and lists none", name,
                            lists[l], (size_t)(at - text), count);
    }
  }
  return true;
}

static bool precheck_dae(const char* name, const void* data, size_t size, bk_error* err) {
  const char* text = data;
  const char* end = text + size;
  if (!dae_arrays_counted(name, text, end, err) || !dae_primitives_listed(name, text, end, err)) return false;
  static const char* const tags[] = {"<p>", "<p ", "<vcount>", "<vcount ", "<v>", "<v "};
  for (const char* at = text; at < end; ++at) {
    if (*at != '<') continue;
    size_t tag = 0, count = sizeof tags / sizeof *tags;
    while (tag < count &&
           ((size_t)(end - at) < strlen(tags[tag]) || memcmp(at, tags[tag], strlen(tags[tag])) != 0))
      ++tag;
    if (tag == count) continue;
    const char* open_end = memchr(at, '>', (size_t)(end - at));
    if (!open_end)
      return bk_error_set(err, "%s: Collada element at byte %zu is not closed", name, (size_t)(at - text));
    if (open_end[-1] == '/') continue; // an empty element
    for (const char* c = open_end + 1;; ++c) {
      if (c == end)
        return bk_error_set(err, "%s: Collada index list at byte %zu has no end", name, (size_t)(at - text));
      if (*c == '<') break;
      if (!(*c >= '0' && *c <= '9') && *c != ' ' && *c != '\t' && *c != '\r' && *c != '\n')
        return bk_error_set(err, "%s: Collada index list at byte %zu holds '%c', not a whole number", name,
                            (size_t)(c - text), *c >= 32 && *c < 127 ? *c : '?');
    }
  }
  return true;
}

uint64_t bk_import_precheck_content_bytes(const char* ext, const void* head, size_t size,
                                          uint64_t file_size) {
  if (strcmp(ext, "gltf") == 0 || strcmp(ext, "3ds") == 0 || strcmp(ext, "dae") == 0 ||
      strcmp(ext, "ply") == 0)
    return file_size;
  if (strcmp(ext, "glb") == 0) { // up to the BIN chunk's header (bk_import_precheck checked the header)
    if (size < 20) return size;
    uint64_t want = 20ull + read_u32le((const unsigned char*)head + 12) + 8;
    return want < file_size ? want : file_size;
  }
  return 0;
}

bool bk_import_precheck_content(const char* name, const char* ext, const void* data, size_t size,
                                uint64_t file_size, bk_error* err) {
  if (file_size == 0) return true;
  if (strcmp(ext, "gltf") == 0 || strcmp(ext, "glb") == 0)
    return bk_import_precheck_gltf(name, ext, data, size, file_size, err);
  if (strcmp(ext, "3ds") == 0) return precheck_3ds(name, data, size, file_size, err);
  if (strcmp(ext, "dae") == 0) return precheck_dae(name, data, size, err);
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
