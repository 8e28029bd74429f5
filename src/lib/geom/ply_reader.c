// PLY files, read by this library rather than assimp: assimp 5.2's PLY
// reader trusts a file's header words, list counts and face indices, and a
// damaged file corrupted its heap or jumped through a null pointer under
// fuzz_import, again and again. Here the header is parsed strictly, the whole
// body is walked as the header declares it (every scalar present, every list
// count small, every face index naming a vertex, the file not ending early),
// and the mesh is handed to the OBJ reader's builder as OBJ text (positions,
// normals and UVs when the file has them, faces as polygons).
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"
#include "model_import.h"

enum { PLY_MAX_ELEMENTS = 16, PLY_MAX_PROPERTIES = 64, PLY_MAX_LIST = 1024 };

typedef struct ply_property {
  char name[24];
  uint32_t size;       // bytes of a scalar, or of each list item
  uint32_t count_size; // bytes of a list's count; 0 for a scalar
  bool is_float;
  bool is_index; // a face's vertex_indices / vertex_index list
} ply_property;

typedef struct ply_element {
  uint64_t count;
  bool is_vertex, is_face;
  ply_property properties[PLY_MAX_PROPERTIES];
  uint32_t property_count;
} ply_element;

typedef struct ply_header {
  ply_element elements[PLY_MAX_ELEMENTS];
  uint32_t element_count;
  bool binary, big_endian;
  size_t body; // offset of the first byte after end_header's line
} ply_header;

static bool same(const char* word, size_t length, const char* text) {
  return length == strlen(text) && memcmp(word, text, length) == 0;
}

static uint32_t type_size(const char* word, size_t length, bool* is_float) {
  static const char* const names[] = {"char",  "uchar",   "int8",   "uint8",  "short", "ushort",
                                      "int16", "uint16",  "int",    "uint",   "int32", "uint32",
                                      "float", "float32", "double", "float64"};
  static const uint32_t sizes[] = {1, 1, 1, 1, 2, 2, 2, 2, 4, 4, 4, 4, 4, 4, 8, 8};
  for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; ++i)
    if (same(word, length, names[i])) {
      *is_float = i >= 12;
      return sizes[i];
    }
  return 0;
}

// Splits the header (already checked line by line by bk_import_precheck)
// into elements and properties.
static bool ply_name_ok(const char* word, size_t length) {
  if (length == 0 || length > 30 ||
      !((word[0] >= 'a' && word[0] <= 'z') || (word[0] >= 'A' && word[0] <= 'Z')))
    return false;
  for (size_t i = 0; i < length; ++i) {
    char c = word[i];
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-'))
      return false;
  }
  return true;
}

// A count: 1 to 19 digits (what fits a uint64 whatever the digits).
static bool ply_count_ok(const char* word, size_t length) {
  if (length == 0 || length > 19) return false;
  for (size_t i = 0; i < length; ++i)
    if (word[i] < '0' || word[i] > '9') return false;
  return true;
}

static bool parse_header(const char* name, const char* text, size_t size, ply_header* h, bk_error* err) {
  memset(h, 0, sizeof *h);
  const char* end = text + size;
  for (const char* line = text; line < end;) {
    const char* eol = memchr(line, '\n', (size_t)(end - line));
    if (!eol) break;
    char words[4][32] = {{0}};
    size_t lengths[4] = {0, 0, 0, 0};
    int n = 0, more = 0; // more: words past the fourth
    for (const char* c = line; c < eol;) {
      while (c < eol && (*c == ' ' || *c == '\t' || *c == '\r'))
        ++c;
      const char* start = c;
      while (c < eol && *c != ' ' && *c != '\t' && *c != '\r')
        ++c;
      if (c > start && n == 4) more++;
      if (c > start && n < 4) {
        snprintf(words[n], sizeof words[n], "%.*s", (int)(c - start < 31 ? c - start : 31), start);
        lengths[n++] = (size_t)(c - start);
      }
    }
    if (n >= 2 && strcmp(words[0], "format") == 0) {
      h->binary = strcmp(words[1], "ascii") != 0;
      h->big_endian = strcmp(words[1], "binary_big_endian") == 0;
    } else if (n >= 3 && strcmp(words[0], "element") == 0) {
      // "element NAME COUNT", exactly: a name of letters, digits and '_'
      // that starts with a letter, and a count of digits. Anything else
      // is refused here, never handed on (assimp reads a name of digits
      // as a count of 2^32 - 1 items).
      if (n != 3 || more || !ply_name_ok(words[1], lengths[1]) || !ply_count_ok(words[2], lengths[2]))
        return bk_error_set(err, "%s: malformed PLY element line (want 'element NAME COUNT': %.31s %.31s)",
                            name, words[1], words[2]);
      if (h->element_count == PLY_MAX_ELEMENTS)
        return bk_error_set(err, "%s: PLY header declares more than %d elements", name, PLY_MAX_ELEMENTS);
      ply_element* e = &h->elements[h->element_count++];
      e->count = strtoull(words[2], NULL, 10);
      e->is_vertex = strcmp(words[1], "vertex") == 0;
      e->is_face = strcmp(words[1], "face") == 0;
    } else if (n >= 3 && strcmp(words[0], "property") == 0 && h->element_count) {
      ply_element* e = &h->elements[h->element_count - 1];
      if (e->property_count == PLY_MAX_PROPERTIES)
        return bk_error_set(err, "%s: a PLY element declares more than %d properties", name,
                            PLY_MAX_PROPERTIES);
      ply_property* p = &e->properties[e->property_count++];
      bool is_float = false;
      if (strcmp(words[1], "list") == 0 && n >= 4) {
        p->count_size = type_size(words[2], strlen(words[2]), &is_float);
        p->size = type_size(words[3], strlen(words[3]), &p->is_float);
        if (is_float) return bk_error_set(err, "%s: a PLY list count must be an integer type", name);
        // The property's name is the fifth word; read it from the line.
        const char* last = eol;
        while (last > line && (last[-1] == ' ' || last[-1] == '\t' || last[-1] == '\r'))
          --last;
        const char* first = last;
        while (first > line && first[-1] != ' ' && first[-1] != '\t')
          --first;
        p->is_index = e->is_face && (same(first, (size_t)(last - first), "vertex_indices") ||
                                     same(first, (size_t)(last - first), "vertex_index"));
        snprintf(p->name, sizeof p->name, "%.*s", (int)(last - first < 23 ? last - first : 23), first);
      } else {
        p->size = type_size(words[1], strlen(words[1]), &p->is_float);
        snprintf(p->name, sizeof p->name, "%.23s", words[2]);
      }
    } else if (n >= 1 && strcmp(words[0], "end_header") == 0) {
      h->body = (size_t)(eol + 1 - text);
      return true;
    }
    line = eol + 1;
  }
  return bk_error_set(err, "%s: malformed PLY header: no end_header", name);
}

static uint64_t read_unsigned(const unsigned char* p, uint32_t size, bool big_endian) {
  uint64_t v = 0;
  for (uint32_t i = 0; i < size; ++i)
    v |= (uint64_t)p[big_endian ? size - 1 - i : i] << (8 * i);
  return v;
}

static int64_t read_signed(const unsigned char* p, uint32_t size, bool big_endian) {
  uint64_t v = read_unsigned(p, size, big_endian);
  uint64_t sign = 1ull << (8 * size - 1);
  return size < 8 && (v & sign) ? (int64_t)(v | ~((sign << 1) - 1)) : (int64_t)v;
}

// One value of the body: binary bytes or an ASCII token. Integers only where
// asked (list counts and indices).
typedef struct body_cursor {
  const unsigned char* at;
  const unsigned char* end;
  bool binary, big_endian;
} body_cursor;

static double read_float(const unsigned char* p, uint32_t size, bool big_endian) {
  uint64_t bits = read_unsigned(p, size, big_endian);
  if (size == 4) {
    uint32_t b32 = (uint32_t)bits;
    float f = 0.0f;
    memcpy(&f, &b32, 4);
    return f;
  }
  double d = 0.0;
  memcpy(&d, &bits, 8);
  return d;
}

static bool next_value(body_cursor* c, uint32_t size, bool is_float, int64_t* integer, double* real) {
  if (c->binary) {
    if ((size_t)(c->end - c->at) < size) return false;
    int64_t i = is_float ? 0 : read_signed(c->at, size, c->big_endian);
    if (integer) *integer = i;
    if (real) *real = is_float ? read_float(c->at, size, c->big_endian) : (double)i;
    c->at += size;
    return true;
  }
  while (c->at < c->end && (*c->at == ' ' || *c->at == '\t' || *c->at == '\r' || *c->at == '\n'))
    ++c->at;
  const unsigned char* start = c->at;
  while (c->at < c->end && *c->at != ' ' && *c->at != '\t' && *c->at != '\r' && *c->at != '\n')
    ++c->at;
  size_t length = (size_t)(c->at - start);
  if (length == 0 || length > 63) return false;
  char token[64];
  memcpy(token, start, length);
  token[length] = 0;
  char* stop = NULL;
  if (integer && !is_float) {
    long long v = strtoll(token, &stop, 10);
    *integer = v;
    if (real) *real = (double)v;
  } else {
    double v = strtod(token, &stop);
    if (real) *real = v;
  }
  return stop && *stop == 0;
}

// Growing text for the OBJ the mesh is handed over as.
typedef struct text_buffer {
  char* data;
  size_t length, capacity;
} text_buffer;

static void append(text_buffer* t, const char* format, ...) __attribute__((format(printf, 2, 3)));
static void append(text_buffer* t, const char* format, ...) {
  for (;;) {
    va_list args;
    va_start(args, format);
    size_t room = t->capacity - t->length;
    int n = vsnprintf(t->data ? t->data + t->length : NULL, room, format, args);
    va_end(args);
    if (n < 0) return;
    if ((size_t)n < room) {
      t->length += (size_t)n;
      return;
    }
    t->capacity = (t->capacity + (size_t)n + 1) * 2;
    t->data = bk_realloc(t->data, t->capacity);
  }
}

static int find_property(const ply_element* e, const char* const* names, int count) {
  for (uint32_t k = 0; k < e->property_count; ++k)
    for (int n = 0; n < count; ++n)
      if (e->properties[k].count_size == 0 && strcmp(e->properties[k].name, names[n]) == 0) return (int)k;
  return -1;
}

bool bk_ply_parse(const void* data, size_t size, const char* name, bk_mesh* out, bool* unknown_header,
                  bk_error* err) {
  memset(out, 0, sizeof *out);
  ply_header h;
  // Every refusal before the body is read is of a layout this reader does
  // not know (the header's form was checked by bk_import_precheck).
  *unknown_header = true;
  if (!parse_header(name, data, size, &h, err)) return false;
  int vertex_element = -1, face_element = -1;
  for (uint32_t e = 0; e < h.element_count; ++e) {
    if (h.elements[e].is_vertex && vertex_element < 0) vertex_element = (int)e;
    if (h.elements[e].is_face && face_element < 0) face_element = (int)e;
  }
  if (vertex_element < 0 || face_element < 0)
    return bk_error_set(err, "%s: a PLY mesh needs a vertex and a face element", name);
  const ply_element* ve = &h.elements[vertex_element];
  static const char *const xs[] = {"x"}, *const ys[] = {"y"}, *const zs[] = {"z"};
  static const char *const nxs[] = {"nx"}, *const nys[] = {"ny"}, *const nzs[] = {"nz"};
  static const char* const us[] = {"u", "s", "texture_u", "texture_s"};
  static const char* const vs[] = {"v", "t", "texture_v", "texture_t"};
  int px = find_property(ve, xs, 1), py = find_property(ve, ys, 1), pz = find_property(ve, zs, 1);
  int pnx = find_property(ve, nxs, 1), pny = find_property(ve, nys, 1), pnz = find_property(ve, nzs, 1);
  int pu = find_property(ve, us, 4), pv = find_property(ve, vs, 4);
  if (px < 0 || py < 0 || pz < 0) return bk_error_set(err, "%s: PLY vertices need x, y and z", name);
  bool normals = pnx >= 0 && pny >= 0 && pnz >= 0, uvs = pu >= 0 && pv >= 0;
  int index_property = -1;
  for (uint32_t k = 0; k < h.elements[face_element].property_count; ++k)
    if (h.elements[face_element].properties[k].is_index) index_property = (int)k;
  if (index_property < 0) return bk_error_set(err, "%s: PLY faces need a vertex_indices list", name);
  uint64_t vertices = ve->count;
  *unknown_header = false;

  bk_c_locale locale = bk_c_locale_begin(); // numbers read and written with '.'
  body_cursor c = {(const unsigned char*)data + h.body, (const unsigned char*)data + size, h.binary,
                   h.big_endian};
  text_buffer obj = {0};
  bool ok = true;
  uint64_t faces = 0;
  for (uint32_t e = 0; e < h.element_count && ok; ++e) {
    const ply_element* el = &h.elements[e];
    for (uint64_t item = 0; item < el->count && ok; ++item) {
      double value[PLY_MAX_PROPERTIES] = {0};
      for (uint32_t k = 0; k < el->property_count && ok; ++k) {
        const ply_property* p = &el->properties[k];
        if (p->count_size == 0) {
          if (!next_value(&c, p->size, p->is_float, NULL, &value[k]) || !isfinite(value[k]))
            ok = bk_error_set(err, "%s: PLY element %u item %llu ends early or holds a non-number", name, e,
                              (unsigned long long)item);
          continue;
        }
        int64_t count = 0;
        if (!next_value(&c, p->count_size, false, &count, NULL) || count < 0 || count > PLY_MAX_LIST) {
          ok = bk_error_set(err, "%s: PLY element %u item %llu has a bad list count", name, e,
                            (unsigned long long)item);
          break;
        }
        bool face_list = (int)e == face_element && (int)k == index_property;
        if (face_list && count >= 3) append(&obj, "f");
        for (int64_t i = 0; i < count && ok; ++i) {
          int64_t index = 0;
          if (!next_value(&c, p->size, p->is_float, p->is_index ? &index : NULL, NULL)) {
            ok = bk_error_set(err, "%s: PLY element %u item %llu ends early or holds a non-number", name, e,
                              (unsigned long long)item);
          } else if (p->is_index && (index < 0 || (uint64_t)index >= vertices)) {
            ok = bk_error_set(err, "%s: PLY face %llu names vertex %lld of %llu", name,
                              (unsigned long long)item, (long long)index, (unsigned long long)vertices);
          } else if (face_list && count >= 3) {
            long long one = (long long)index + 1;
            if (uvs && normals)
              append(&obj, " %lld/%lld/%lld", one, one, one);
            else if (uvs)
              append(&obj, " %lld/%lld", one, one);
            else if (normals)
              append(&obj, " %lld//%lld", one, one);
            else
              append(&obj, " %lld", one);
          }
        }
        if (face_list && count >= 3) append(&obj, "\n"), faces++;
      }
      if (!ok || (int)e != vertex_element) continue;
      append(&obj, "v %.17g %.17g %.17g\n", value[px], value[py], value[pz]);
      if (normals) append(&obj, "vn %.9g %.9g %.9g\n", value[pnx], value[pny], value[pnz]);
      if (uvs) append(&obj, "vt %.9g %.9g\n", value[pu], value[pv]);
    }
  }
  bk_c_locale_end(&locale);
  if (ok && faces == 0)
    ok = bk_error_set(err, "%s: no triangles (the PLY file has no faces of 3 or more vertices)", name);
  if (ok) ok = bk_obj_parse(obj.data, obj.length, name, out, err);
  bk_free(obj.data);
  return ok;
}

bool bk_ply_free_text_note(const void* data, size_t size, char* note, size_t note_size) {
  static const char* const keywords[] = {"ply", "format", "comment", "obj_info", "element", "property"};
  const char* text = data;
  const char* end = text + size;
  uint32_t number = 1;
  for (const char* line = text; line < end; line++, number++) {
    const char* eol = memchr(line, '\n', (size_t)(end - line));
    if (!eol) return false;
    const char* word = line;
    while (word < eol && (*word == ' ' || *word == '\t'))
      word++;
    size_t length = 0;
    while (word + length < eol && word[length] != ' ' && word[length] != '\t' && word[length] != '\r')
      length++;
    if (same(word, length, "end_header")) return false;
    bool known = length == 0;
    for (size_t k = 0; k < sizeof keywords / sizeof *keywords && !known; ++k)
      known = same(word, length, keywords[k]);
    if (!known) {
      // The header's lines are printable (bk_import_precheck); cut to fit.
      size_t shown = (size_t)(eol - word);
      while (shown > 0 && (word[shown - 1] == '\r' || word[shown - 1] == ' '))
        shown--;
      snprintf(note, note_size, "PLY header line %u ('%.*s%s') is not a PLY keyword: read as a comment",
               number, (int)(shown < 40 ? shown : 40), word, shown > 40 ? "..." : "");
      return true;
    }
    line = eol;
  }
  return false;
}

bool bk_ply_check_body(const void* data, size_t size, const char* name, bk_error* err) {
  ply_header h;
  if (!parse_header(name, data, size, &h, err)) return false;
  uint64_t vertices = 0;
  bool have_vertices = false;
  for (uint32_t e = 0; e < h.element_count && !have_vertices; ++e)
    if (h.elements[e].is_vertex) vertices = h.elements[e].count, have_vertices = true;
  if (!have_vertices) return bk_error_set(err, "%s: a PLY mesh needs a vertex element", name);
  bk_c_locale locale = bk_c_locale_begin();
  body_cursor c = {(const unsigned char*)data + h.body, (const unsigned char*)data + size, h.binary,
                   h.big_endian};
  bool ok = true;
  for (uint32_t e = 0; e < h.element_count && ok; ++e) {
    const ply_element* el = &h.elements[e];
    for (uint64_t item = 0; item < el->count && ok; ++item)
      for (uint32_t k = 0; k < el->property_count && ok; ++k) {
        const ply_property* p = &el->properties[k];
        double value = 0.0;
        int64_t count = 0;
        if (p->count_size == 0) {
          if (!next_value(&c, p->size, p->is_float, NULL, &value) || !isfinite(value))
            ok = bk_error_set(err, "%s: PLY element %u item %llu ends early or holds a non-number", name, e,
                              (unsigned long long)item);
          continue;
        }
        if (!next_value(&c, p->count_size, false, &count, NULL) || count < 0 || count > PLY_MAX_LIST) {
          ok = bk_error_set(err, "%s: PLY element %u item %llu has a bad list count", name, e,
                            (unsigned long long)item);
          break;
        }
        // Lists of vertex indices (any element's: faces, strips) name vertices, or -1 (a strip's restart).
        bool indices = strstr(p->name, "index") || strstr(p->name, "indices");
        if (indices && p->is_float) {
          ok = bk_error_set(err, "%s: PLY element %u: list '%s' of vertex indices is not of an integer type",
                            name, e, p->name);
          break;
        }
        for (int64_t i = 0; i < count && ok; ++i) {
          int64_t index = 0;
          if (!next_value(&c, p->size, p->is_float, &index, &value) || !isfinite(value))
            ok = bk_error_set(err, "%s: PLY element %u item %llu ends early or holds a non-number", name, e,
                              (unsigned long long)item);
          else if (indices && (index < -1 || (index >= 0 && (uint64_t)index >= vertices)))
            ok = bk_error_set(err, "%s: PLY element %u item %llu names vertex %lld of %llu", name, e,
                              (unsigned long long)item, (long long)index, (unsigned long long)vertices);
        }
      }
  }
  bk_c_locale_end(&locale);
  return ok;
}
