// Wavefront OBJ reader: v / vt / vn / f into a welded, indexed bk_mesh.
//
// Parsing only records raw (v, vt, vn) references per triangle. Corners are
// built afterwards, once positions are welded, so two faces that repeat a
// vertex's coordinates under different `v` lines still share one corner.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"

// Coordinates beyond this are rejected: they are never meaningful for a
// breakable object, and the limit keeps every derived quantity finite (cross
// products for normals, float uvs from box projection, cubic volume terms).
#define OBJ_MAX_COORD 1e30
// Upper bound on any parsed array, so counts and 3 * triangles fit uint32_t.
#define OBJ_MAX_ITEMS (1u << 30)
#define OBJ_NONE UINT32_MAX
// The loader refuses larger files rather than exhausting memory.
#define OBJ_MAX_FILE_BYTES ((size_t)1 << 30)
// How much of an offending token an error message quotes.
#define OBJ_QUOTE 40

typedef struct obj_ref {
  uint32_t v, vt, vn;
} obj_ref;

typedef struct obj_parser {
  const char* name;
  size_t line;
  bk_error* err;
  bk_mesh mesh; // receives the raw positions, then becomes the result
  float* uvs;   // 2 per texture coordinate
  uint32_t uv_count, uv_capacity;
  float* normals; // 3 per normal, normalised on read
  uint32_t normal_count, normal_capacity;
  obj_ref* refs; // 3 per triangle, resolved to 0-based indices
  uint32_t ref_count, ref_capacity;
  obj_ref* face; // the polygon being fanned
  uint32_t face_count, face_capacity;
  char* text; // the current logical line, NUL-terminated for strtod
  size_t text_length, text_capacity;
  // Materials: `usemtl` names in the order of first use give the source
  // material ids (bk_material_source) of the faces after them.
  bk_obj_materials* materials; // where the names go (the parser's own when the caller wants none)
  uint8_t current_source;
  uint8_t* triangle_source; // per triangle in refs
  uint32_t triangle_source_capacity;
} obj_parser;

static void parser_free(obj_parser* p) {
  bk_mesh_free(&p->mesh);
  bk_free(p->uvs);
  bk_free(p->normals);
  bk_free(p->refs);
  bk_free(p->face);
  bk_free(p->text);
  bk_free(p->triangle_source);
  memset(p, 0, sizeof *p);
}

static void* grow_array(void* data, uint32_t* capacity, uint32_t need, size_t element) {
  if (need <= *capacity) return data;
  *capacity = bk_grow_capacity(*capacity, need);
  return bk_realloc(data, element * *capacity);
}

static void line_append(obj_parser* p, const char* s, size_t n) {
  if (p->text_length + n + 1 > p->text_capacity) {
    size_t cap = p->text_capacity ? p->text_capacity : 256;
    while (cap < p->text_length + n + 1)
      cap *= 2;
    p->text = bk_realloc(p->text, cap);
    p->text_capacity = cap;
  }
  memcpy(p->text + p->text_length, s, n);
  p->text_length += n;
  p->text[p->text_length] = '\0';
}

static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Returns the next whitespace-separated token of the line (NULL at its end).
static const char* next_token(const char** cursor, size_t* length) {
  const char* s = *cursor;
  while (is_space(*s))
    ++s;
  if (*s == '\0') {
    *cursor = s;
    return NULL;
  }
  const char* e = s;
  while (*e != '\0' && !is_space(*e))
    ++e;
  *length = (size_t)(e - s);
  *cursor = e;
  return s;
}

// The rest of the line without blanks at either end (names may hold blanks).
static const char* rest_of_line(const char* cursor, size_t* length) {
  while (is_space(*cursor))
    ++cursor;
  size_t n = strlen(cursor);
  while (n > 0 && is_space(cursor[n - 1]))
    --n;
  *length = n;
  return cursor;
}

// `usemtl NAME`: the faces after it are of that material. Names past
// BK_MATERIAL_SOURCES_MAX share the first material (counted as merged).
static void use_material(obj_parser* p, const char* cursor) {
  size_t n = 0;
  const char* name = rest_of_line(cursor, &n);
  char key[BK_OBJ_MATERIAL_NAME];
  snprintf(key, sizeof key, "%.*s", (int)(n < sizeof key - 1 ? n : sizeof key - 1), name);
  for (char* c = key; *c; ++c)
    if ((unsigned char)*c < 0x20) *c = ' ';
  bk_obj_materials* m = p->materials;
  for (uint32_t i = 0; i < m->count; ++i)
    if (strcmp(m->names[i], key) == 0) {
      p->current_source = (uint8_t)i;
      return;
    }
  if (m->count == 0 && p->ref_count > 0) {
    // Faces before the first usemtl keep material 0, unnamed.
    m->names[0][0] = '\0';
    m->count = 1;
  }
  if (m->count < BK_MATERIAL_SOURCES_MAX) {
    memcpy(m->names[m->count], key, sizeof key);
    p->current_source = (uint8_t)m->count++;
  } else {
    p->current_source = 0;
    m->merged++;
  }
}

static int quote_length(size_t n) { return (int)(n < OBJ_QUOTE ? n : OBJ_QUOTE); }

// Reads every remaining number on the line into out (min..max of them).
// `what` names the statement and `expected` the accepted count, for messages.
static bool parse_numbers(obj_parser* p, const char** cursor, double* out, int min, int max, const char* what,
                          const char* expected, int* count) {
  *count = 0;
  size_t n = 0;
  const char* tok = NULL;
  while ((tok = next_token(cursor, &n)) != NULL) {
    if (*count == max)
      return bk_error_set(p->err, "%s:%zu: malformed %s: too many numbers (at most %d)", p->name, p->line,
                          what, max);
    char* end = NULL;
    double value = strtod(tok, &end);
    if (end != tok + n)
      return bk_error_set(p->err, "%s:%zu: malformed %s: '%.*s' is not a number", p->name, p->line, what,
                          quote_length(n), tok);
    if (!isfinite(value))
      return bk_error_set(p->err, "%s:%zu: non-finite coordinate (%.*s)", p->name, p->line, quote_length(n),
                          tok);
    if (fabs(value) > OBJ_MAX_COORD)
      return bk_error_set(p->err, "%s:%zu: coordinate out of range (%.*s; limit 1e30)", p->name, p->line,
                          quote_length(n), tok);
    out[(*count)++] = value;
  }
  if (*count < min)
    return bk_error_set(p->err, "%s:%zu: malformed %s: expected %s (got %d)", p->name, p->line, what,
                        expected, *count);
  return true;
}

static bool too_many(obj_parser* p, const char* what) {
  return bk_error_set(p->err, "%s:%zu: too many %s (limit %u)", p->name, p->line, what, OBJ_MAX_ITEMS);
}

static bool parse_vertex(obj_parser* p, const char* cursor) {
  // x y z, optionally w (ignored) and the common r g b colour extension (ignored).
  double v[7] = {0};
  int count = 0;
  if (!parse_numbers(p, &cursor, v, 3, 7, "vertex", "3 numbers", &count)) return false;
  if (p->mesh.position_count >= OBJ_MAX_ITEMS) return too_many(p, "vertices");
  bk_mesh_add_position(&p->mesh, bk_v3(v[0], v[1], v[2]));
  return true;
}

static bool parse_texcoord(obj_parser* p, const char* cursor) {
  // u [v [w]]: the OBJ specification makes v and w optional (default 0).
  double t[3] = {0};
  int count = 0;
  if (!parse_numbers(p, &cursor, t, 1, 3, "texture coordinate", "1 to 3 numbers", &count)) return false;
  if (p->uv_count >= OBJ_MAX_ITEMS) return too_many(p, "texture coordinates");
  p->uvs = grow_array(p->uvs, &p->uv_capacity, 2u * (p->uv_count + 1), sizeof(float));
  p->uvs[2 * p->uv_count + 0] = (float)t[0];
  p->uvs[2 * p->uv_count + 1] = (float)t[1];
  p->uv_count++;
  return true;
}

static bool parse_normal(obj_parser* p, const char* cursor) {
  double n[3] = {0};
  int count = 0;
  if (!parse_numbers(p, &cursor, n, 3, 3, "normal", "3 numbers", &count)) return false;
  if (p->normal_count >= OBJ_MAX_ITEMS) return too_many(p, "normals");
  // Exporters often write unnormalised normals; shading and tangents assume unit length.
  // Scaling by the largest component first keeps tiny vectors from underflowing.
  double scale = fmax(fabs(n[0]), fmax(fabs(n[1]), fabs(n[2])));
  bk_vec3 u = scale > 0.0 ? bk_v3_normalize(bk_v3(n[0] / scale, n[1] / scale, n[2] / scale)) : bk_v3(0, 0, 0);
  p->normals = grow_array(p->normals, &p->normal_capacity, 3u * (p->normal_count + 1), sizeof(float));
  p->normals[3 * p->normal_count + 0] = (float)u.x;
  p->normals[3 * p->normal_count + 1] = (float)u.y;
  p->normals[3 * p->normal_count + 2] = (float)u.z;
  p->normal_count++;
  return true;
}

// Parses a signed decimal integer occupying exactly s[0..n). Magnitudes are
// clamped (they are out of range anyway), so hostile digit strings cannot overflow.
static bool parse_integer(const char* s, size_t n, long long* out) {
  size_t i = 0;
  bool negative = false;
  if (i < n && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  if (i == n) return false;
  long long value = 0;
  for (; i < n; ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    if (value < 10000000000000LL) value = value * 10 + (s[i] - '0');
  }
  *out = negative ? -value : value;
  return true;
}

// Turns a 1-based or negative (relative) OBJ index into a 0-based one.
static bool resolve_index(obj_parser* p, const char* s, size_t n, uint32_t count, const char* what,
                          const char* unit, uint32_t* out) {
  long long value = 0;
  if (!parse_integer(s, n, &value))
    return bk_error_set(p->err, "%s:%zu: malformed %s index '%.*s'", p->name, p->line, what, quote_length(n),
                        s);
  if (value == 0)
    return bk_error_set(p->err, "%s:%zu: %s index 0 is invalid (OBJ indices start at 1)", p->name, p->line,
                        what);
  long long index = value > 0 ? value - 1 : (long long)count + value;
  if (index < 0 || index >= (long long)count) {
    if (count == 0)
      return bk_error_set(p->err, "%s:%zu: %s index %.*s out of range (no %s defined)", p->name, p->line,
                          what, quote_length(n), s, unit);
    return bk_error_set(p->err, "%s:%zu: %s index %.*s out of range (1..%u %s)", p->name, p->line, what,
                        quote_length(n), s, count, unit);
  }
  *out = (uint32_t)index;
  return true;
}

// One face vertex: v, v/vt, v//vn or v/vt/vn.
static bool parse_face_vertex(obj_parser* p, const char* tok, size_t n, obj_ref* ref) {
  const char* parts[3] = {tok, NULL, NULL};
  size_t lengths[3] = {n, 0, 0};
  int part_count = 1;
  for (size_t i = 0; i < n; ++i) {
    if (tok[i] != '/') continue;
    if (part_count == 3)
      return bk_error_set(p->err, "%s:%zu: malformed face vertex '%.*s'", p->name, p->line, quote_length(n),
                          tok);
    lengths[part_count - 1] = (size_t)(tok + i - parts[part_count - 1]);
    parts[part_count] = tok + i + 1;
    lengths[part_count] = n - i - 1;
    part_count++;
  }
  // Only the texture slot may be empty, and only in the v//vn form.
  bool bad = lengths[0] == 0 || (part_count == 2 && lengths[1] == 0) || (part_count == 3 && lengths[2] == 0);
  if (bad)
    return bk_error_set(p->err, "%s:%zu: malformed face vertex '%.*s'", p->name, p->line, quote_length(n),
                        tok);
  *ref = (obj_ref){OBJ_NONE, OBJ_NONE, OBJ_NONE};
  if (!resolve_index(p, parts[0], lengths[0], p->mesh.position_count, "face", "vertices", &ref->v))
    return false;
  if (part_count >= 2 && lengths[1] > 0 &&
      !resolve_index(p, parts[1], lengths[1], p->uv_count, "texture", "texture coordinates", &ref->vt))
    return false;
  if (part_count == 3 &&
      !resolve_index(p, parts[2], lengths[2], p->normal_count, "normal", "normals", &ref->vn))
    return false;
  return true;
}

static bool parse_face(obj_parser* p, const char* cursor) {
  p->face_count = 0;
  size_t n = 0;
  const char* tok = NULL;
  while ((tok = next_token(&cursor, &n)) != NULL) {
    if (p->face_count >= OBJ_MAX_ITEMS) return too_many(p, "face vertices");
    p->face = grow_array(p->face, &p->face_capacity, p->face_count + 1, sizeof(obj_ref));
    if (!parse_face_vertex(p, tok, n, &p->face[p->face_count])) return false;
    p->face_count++;
  }
  if (p->face_count < 3)
    return bk_error_set(p->err, "%s:%zu: face needs at least 3 vertices (got %u)", p->name, p->line,
                        p->face_count);
  uint32_t new_refs = 3u * (p->face_count - 2);
  if (new_refs > OBJ_MAX_ITEMS - p->ref_count) return too_many(p, "triangles");
  p->refs = grow_array(p->refs, &p->ref_capacity, p->ref_count + new_refs, sizeof(obj_ref));
  p->triangle_source =
      grow_array(p->triangle_source, &p->triangle_source_capacity, (p->ref_count + new_refs) / 3, 1);
  memset(p->triangle_source + p->ref_count / 3, p->current_source, new_refs / 3);
  // Fan around the first vertex: exact for the convex polygons exporters write.
  for (uint32_t i = 1; i + 1 < p->face_count; ++i) {
    p->refs[p->ref_count++] = p->face[0];
    p->refs[p->ref_count++] = p->face[i];
    p->refs[p->ref_count++] = p->face[i + 1];
  }
  return true;
}

static bool parse_line(obj_parser* p) {
  // Comments may also trail a statement.
  char* hash = strchr(p->text, '#');
  if (hash) *hash = '\0';
  const char* cursor = p->text;
  size_t n = 0;
  const char* keyword = next_token(&cursor, &n);
  if (!keyword) return true;
  if (n == 1 && keyword[0] == 'v') return parse_vertex(p, cursor);
  if (n == 2 && keyword[0] == 'v' && keyword[1] == 't') return parse_texcoord(p, cursor);
  if (n == 2 && keyword[0] == 'v' && keyword[1] == 'n') return parse_normal(p, cursor);
  if (n == 1 && keyword[0] == 'f') return parse_face(p, cursor);
  if (n == 6 && memcmp(keyword, "usemtl", 6) == 0) return use_material(p, cursor), true;
  if (n == 6 && memcmp(keyword, "mtllib", 6) == 0 && !p->materials->library[0]) {
    const char* rest = rest_of_line(cursor, &n);
    if (n < sizeof p->materials->library) memcpy(p->materials->library, rest, n); // longer: not looked for
    return true;
  }
  // o, g, s, l, p, vp and vendor extensions carry nothing we use.
  return true;
}

static bool parse_text(obj_parser* p, const char* text, size_t length) {
  size_t pos = 0, physical_line = 0;
  bool continued = false;
  while (pos < length) {
    size_t start = pos;
    while (pos < length && text[pos] != '\n' && text[pos] != '\r')
      ++pos;
    size_t end = pos;
    // Accept \n, \r\n and lone \r line ends.
    if (pos < length && text[pos] == '\r') ++pos;
    if (pos < length && text[pos] == '\n') ++pos;
    ++physical_line;
    if (!continued) {
      p->line = physical_line;
      p->text_length = 0;
      line_append(p, "", 0);
    }
    if (memchr(text + start, '\0', end - start))
      return bk_error_set(p->err, "%s:%zu: NUL byte in text (binary file?)", p->name, physical_line);
    continued = end > start && text[end - 1] == '\\';
    if (continued) {
      line_append(p, text + start, end - start - 1);
      line_append(p, " ", 1);
      continue;
    }
    line_append(p, text + start, end - start);
    if (!parse_line(p)) return false;
  }
  if (continued) return parse_line(p);
  return true;
}

// ---------------------------------------------------------------- mesh building

static uint64_t ref_key(obj_ref r) {
  uint64_t h = bk_hash_bytes(BK_FNV_OFFSET, &r, sizeof r);
  return h == UINT64_MAX ? 0 : h; // UINT64_MAX marks empty map slots
}

static bool build_mesh(obj_parser* p) {
  bk_mesh* m = &p->mesh;
  uint32_t raw_triangles = p->ref_count / 3;
  if (raw_triangles == 0) return bk_error_set(p->err, "%s: no triangles", p->name);

  // Weld through identity corners: afterwards corner i names the welded index of `v` line i.
  uint32_t raw_positions = m->position_count;
  bk_mesh_reserve(m, 0, raw_positions, raw_triangles);
  for (uint32_t i = 0; i < raw_positions; ++i)
    m->corners[i] = (bk_corner){.position = i};
  m->corner_count = raw_positions;
  bk_mesh_weld(m);
  uint32_t* welded = bk_alloc(sizeof(uint32_t) * raw_positions);
  for (uint32_t i = 0; i < raw_positions; ++i)
    welded[i] = m->corners[i].position;
  m->corner_count = 0;

  // Topologically degenerate triangles are dropped; positions only they (or no face) used go too.
  uint32_t* final_index = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  for (uint32_t i = 0; i < m->position_count; ++i)
    final_index[i] = OBJ_NONE;
  uint32_t degenerate = 0;
  for (uint32_t t = 0; t < raw_triangles; ++t) {
    uint32_t a = welded[p->refs[3 * t].v], b = welded[p->refs[3 * t + 1].v], c = welded[p->refs[3 * t + 2].v];
    if (a == b || b == c || c == a) {
      degenerate++;
      continue;
    }
    final_index[a] = final_index[b] = final_index[c] = 0;
  }
  uint32_t used = 0;
  for (uint32_t i = 0; i < m->position_count; ++i) {
    if (final_index[i] == OBJ_NONE) continue;
    m->positions[used] = m->positions[i];
    final_index[i] = used++;
  }
  m->position_count = used;

  // One corner per distinct (position, vt, vn); hash hits are verified, so the dedupe is exact.
  bk_index_map map = {0};
  bk_index_map_init(&map, 3u * (raw_triangles - degenerate));
  obj_ref* sources = bk_alloc(sizeof(obj_ref) * 3u * (raw_triangles - degenerate + 1u));
  bool missing_normals = false, missing_uvs = false;
  for (uint32_t t = 0; t < raw_triangles; ++t) {
    uint32_t corner[3] = {0, 0, 0};
    obj_ref key[3];
    for (int k = 0; k < 3; ++k) {
      key[k] = p->refs[3 * t + k];
      key[k].v = welded[key[k].v];
    }
    if (key[0].v == key[1].v || key[1].v == key[2].v || key[2].v == key[0].v) continue;
    for (int k = 0; k < 3; ++k) {
      key[k].v = final_index[key[k].v];
      uint64_t h = ref_key(key[k]);
      for (;;) {
        bool inserted = false;
        uint32_t* slot = bk_index_map_insert(&map, h, m->corner_count, &inserted);
        if (inserted) {
          bk_corner c = {.position = key[k].v};
          if (key[k].vn != OBJ_NONE) memcpy(c.normal, &p->normals[3 * key[k].vn], sizeof c.normal);
          if (key[k].vt != OBJ_NONE) memcpy(c.uv, &p->uvs[2 * key[k].vt], sizeof c.uv);
          missing_normals |= key[k].vn == OBJ_NONE;
          missing_uvs |= key[k].vt == OBJ_NONE;
          sources[m->corner_count] = key[k];
          corner[k] = bk_mesh_add_corner(m, &c);
          break;
        }
        obj_ref s = sources[*slot];
        if (s.v == key[k].v && s.vt == key[k].vt && s.vn == key[k].vn) {
          corner[k] = *slot;
          break;
        }
        h = h * 0x100000001b3ull + 1;
        if (h == UINT64_MAX) h = 0;
      }
    }
    bk_mesh_add_triangle(m, corner[0], corner[1], corner[2], bk_material_id(p->triangle_source[t], false), 0);
  }
  bk_index_map_free(&map);
  bk_free(welded);
  bk_free(final_index);

  if (m->triangle_count == 0) {
    bk_free(sources);
    return bk_error_set(p->err, "%s: no triangles (%u degenerate dropped)", p->name, degenerate);
  }

  if (missing_normals) {
    // Smooth normals everywhere, then restore the ones the file gave.
    bk_mesh_compute_normals(m);
    for (uint32_t i = 0; i < m->corner_count; ++i)
      if (sources[i].vn != OBJ_NONE)
        memcpy(m->corners[i].normal, &p->normals[3 * sources[i].vn], 3 * sizeof(float));
  }
  if (missing_uvs) {
    // Box projection: drop the coordinate along the normal's dominant axis.
    for (uint32_t i = 0; i < m->corner_count; ++i) {
      if (sources[i].vt != OBJ_NONE) continue;
      bk_corner* c = &m->corners[i];
      bk_vec3 q = m->positions[c->position];
      float ax = fabsf(c->normal[0]), ay = fabsf(c->normal[1]), az = fabsf(c->normal[2]);
      if (ax >= ay && ax >= az) {
        c->uv[0] = (float)q.y;
        c->uv[1] = (float)q.z;
      } else if (ay >= az) {
        c->uv[0] = (float)q.x;
        c->uv[1] = (float)q.z;
      } else {
        c->uv[0] = (float)q.x;
        c->uv[1] = (float)q.y;
      }
    }
  }
  bk_free(sources);
  bk_mesh_compute_tangents(m);
  return true;
}

bool bk_obj_parse(const char* text, size_t length, const char* name, bk_mesh* out, bk_error* err) {
  bk_obj_materials* scratch = bk_calloc(1, sizeof *scratch);
  bool ok = bk_obj_parse_materials(text, length, name, out, scratch, err);
  bk_free(scratch);
  return ok;
}

bool bk_obj_parse_materials(const char* text, size_t length, const char* name, bk_mesh* out,
                            bk_obj_materials* materials, bk_error* err) {
  memset(out, 0, sizeof *out);
  memset(materials, 0, sizeof *materials);
  obj_parser p = {.name = name ? name : "obj", .err = err, .materials = materials};
  if (!text && length > 0) return bk_error_set(err, "%s: no text", p.name);
  // Numbers are read in the C locale whatever the host application set
  // (a decimal comma would stop strtod at "0,5").
  bk_c_locale c_locale = bk_c_locale_begin();
  bool ok = parse_text(&p, text, length) && build_mesh(&p);
  bk_c_locale_end(&c_locale);
  if (ok) {
    *out = p.mesh;
    memset(&p.mesh, 0, sizeof p.mesh);
  }
  parser_free(&p);
  return ok;
}

bool bk_obj_load(const char* path, bk_mesh* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  void* data = NULL;
  size_t length = 0;
  if (!bk_file_read(path, OBJ_MAX_FILE_BYTES, "1 GiB", &data, &length, err)) return false;
  bool ok = bk_obj_parse(data, length, path, out, err);
  bk_free(data);
  return ok;
}
