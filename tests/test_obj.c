// OBJ reading and writing: topology after welding, exact volumes, attribute
// round trips, error messages with line numbers, and robustness against
// corrupted input.
#include <locale.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bk_geom.h"
#include "ensure.h"

// Unit cube [0,1]^3, faces counter-clockwise seen from outside.
static const double cube_positions[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                            {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
static const int cube_faces[6][4] = {{1, 4, 3, 2}, {5, 6, 7, 8}, {1, 2, 6, 5},
                                     {4, 8, 7, 3}, {1, 5, 8, 4}, {2, 3, 7, 6}};
static const int cube_normals[6][3] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}};

typedef struct text_buffer {
  char data[8192];
  size_t length;
} text_buffer;

__attribute__((format(printf, 2, 3))) static void append(text_buffer* b, const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  int n = vsnprintf(b->data + b->length, sizeof b->data - b->length, fmt, args);
  va_end(args);
  ENSURE(n >= 0 && (size_t)n < sizeof b->data - b->length);
  b->length += (size_t)n;
}

// The cube as OBJ text: shared `v` lines (or repeated per face), quads, per-face `vn`.
static void cube_text(text_buffer* b, bool duplicate_vertices, bool with_normals) {
  b->length = 0;
  append(b, "# unit cube\n");
  if (!duplicate_vertices)
    for (int i = 0; i < 8; ++i)
      append(b, "v %g %g %g\n", cube_positions[i][0], cube_positions[i][1], cube_positions[i][2]);
  for (int f = 0; f < 6; ++f) {
    if (with_normals) append(b, "vn %d %d %d\n", cube_normals[f][0], cube_normals[f][1], cube_normals[f][2]);
    if (duplicate_vertices)
      for (int k = 0; k < 4; ++k) {
        const double* p = cube_positions[cube_faces[f][k] - 1];
        append(b, "v %g %g %g\n", p[0], p[1], p[2]);
      }
  }
  for (int f = 0; f < 6; ++f) {
    append(b, "f");
    for (int k = 0; k < 4; ++k) {
      int v = duplicate_vertices ? 4 * f + k + 1 : cube_faces[f][k];
      if (with_normals)
        append(b, " %d//%d", v, f + 1);
      else
        append(b, " %d", v);
    }
    append(b, "\n");
  }
}

static bool mesh_is_zeroed(const bk_mesh* m) {
  return !m->positions && !m->corners && !m->indices && !m->materials && !m->tags && m->position_count == 0 &&
         m->corner_count == 0 && m->triangle_count == 0 && m->position_capacity == 0 &&
         m->corner_capacity == 0 && m->triangle_capacity == 0;
}

static void parse_ok(const char* text, bk_mesh* m) {
  bk_error err = {{0}};
  bool ok = bk_obj_parse(text, strlen(text), "t.obj", m, &err);
  ENSURE_MSG(ok, "%s", err.message);
  ENSURE_MSG(bk_mesh_validate(m, &err), "%s", err.message);
}

// Parsing must fail with a message containing `expected`, leaving the mesh zeroed.
static void parse_fails(const char* text, const char* expected) {
  bk_mesh m = {0};
  bk_error err = {{0}};
  ENSURE_MSG(!bk_obj_parse(text, strlen(text), "t.obj", &m, &err), "parsed: %s", text);
  ENSURE_MSG(strstr(err.message, expected), "message '%s' lacks '%s'", err.message, expected);
  ENSURE(strchr(err.message, '\n') == NULL);
  ENSURE(mesh_is_zeroed(&m));
}

static void ensure_unit_cube(const bk_mesh* m) {
  ENSURE(m->position_count == 8);
  ENSURE(m->triangle_count == 12);
  ENSURE(bk_mesh_is_closed(m));
  ENSURE_SMALL(bk_mesh_volume(m), 1.0, 1e-12);
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    ENSURE(m->materials[t] == BK_MATERIAL_OUTER);
    ENSURE(m->tags[t] == 0);
  }
}

// Tangents are unit length and orthogonal to the normal wherever the normal is unit.
static void ensure_tangent_frames(const bk_mesh* m) {
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    const bk_corner* c = &m->corners[i];
    bk_vec3 n = bk_v3(c->normal[0], c->normal[1], c->normal[2]);
    bk_vec3 t = bk_v3(c->tangent[0], c->tangent[1], c->tangent[2]);
    ENSURE_SMALL(bk_v3_length(n), 1.0, 1e-6);
    ENSURE_SMALL(bk_v3_length(t), 1.0, 1e-6);
    ENSURE_SMALL(bk_v3_dot(n, t), 0.0, 1e-6);
    ENSURE(c->tangent[3] == 1.0f || c->tangent[3] == -1.0f);
  }
}

static void test_cube_shared_vertices(void) {
  text_buffer b = {{0}, 0};
  cube_text(&b, false, true);
  bk_mesh m = {0};
  parse_ok(b.data, &m);
  ensure_unit_cube(&m);
  ENSURE(m.corner_count == 24); // one per distinct v//vn pair
  // Given normals are kept per face: each triangle's corners carry its face normal.
  for (uint32_t t = 0; t < m.triangle_count; ++t) {
    bk_vec3 a = m.positions[bk_mesh_tri_position(&m, t, 0)];
    bk_vec3 e1 = bk_v3_sub(m.positions[bk_mesh_tri_position(&m, t, 1)], a);
    bk_vec3 e2 = bk_v3_sub(m.positions[bk_mesh_tri_position(&m, t, 2)], a);
    bk_vec3 face = bk_v3_normalize(bk_v3_cross(e1, e2));
    for (int k = 0; k < 3; ++k) {
      const bk_corner* c = &m.corners[m.indices[3 * t + k]];
      ENSURE_SMALL(c->normal[0], face.x, 1e-12);
      ENSURE_SMALL(c->normal[1], face.y, 1e-12);
      ENSURE_SMALL(c->normal[2], face.z, 1e-12);
      // No vt in the file: box projection drops the axis of the normal.
      bk_vec3 p = m.positions[c->position];
      double u = fabs(face.x) > 0.5 ? p.y : p.x, v = fabs(face.z) > 0.5 ? p.y : p.z;
      ENSURE_SMALL(c->uv[0], u, 0.0);
      ENSURE_SMALL(c->uv[1], v, 0.0);
    }
  }
  ensure_tangent_frames(&m);
  bk_mesh_free(&m);
}

static void test_cube_duplicated_vertices(void) {
  text_buffer b = {{0}, 0};
  cube_text(&b, true, true);
  bk_mesh m = {0};
  parse_ok(b.data, &m);
  ensure_unit_cube(&m);
  ENSURE(m.corner_count == 24);
  bk_mesh_free(&m);

  // Without normals every face shares its corners after welding: 8 smooth corners.
  cube_text(&b, true, false);
  parse_ok(b.data, &m);
  ensure_unit_cube(&m);
  ENSURE(m.corner_count == 8);
  for (uint32_t i = 0; i < m.corner_count; ++i) {
    // Smooth normals at a cube corner point outward along all three axes (the
    // fan split weights the faces unevenly, so not exactly along the diagonal).
    bk_vec3 p = m.positions[m.corners[i].position];
    const float* n = m.corners[i].normal;
    ENSURE((n[0] > 0.1f) == (p.x > 0.5) && (n[1] > 0.1f) == (p.y > 0.5) && (n[2] > 0.1f) == (p.z > 0.5));
    ENSURE((n[0] < -0.1f) == (p.x < 0.5) && (n[1] < -0.1f) == (p.y < 0.5) && (n[2] < -0.1f) == (p.z < 0.5));
  }
  ensure_tangent_frames(&m);
  bk_mesh_free(&m);
}

static void test_negative_indices(void) {
  bk_mesh m = {0};
  parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"
           "v 5 0 0\nv 6 0 0\nv 5 1 0\nf -3 -2 -1\n",
           &m);
  ENSURE(m.triangle_count == 2);
  ENSURE(m.position_count == 6);
  // Relative indices count back from the latest `v`, so the second triangle uses the later vertices.
  ENSURE(m.positions[bk_mesh_tri_position(&m, 0, 0)].x == 0.0);
  ENSURE(m.positions[bk_mesh_tri_position(&m, 0, 1)].x == 1.0);
  ENSURE(m.positions[bk_mesh_tri_position(&m, 1, 0)].x == 5.0);
  ENSURE(m.positions[bk_mesh_tri_position(&m, 1, 1)].x == 6.0);
  ENSURE(m.positions[bk_mesh_tri_position(&m, 1, 2)].y == 1.0);
  ENSURE(!bk_mesh_is_closed(&m));
  ENSURE_SMALL(m.corners[0].normal[2], 1.0, 1e-12); // computed: counter-clockwise in xy faces +z
  bk_mesh_free(&m);
}

static void test_face_forms_and_ignored_statements(void) {
  // Every face vertex form, vendor statements, comments, CRLF, a continuation
  // line, a stray vertex, and degenerate faces that must be dropped.
  const char* text = "# header\r\n"
                     "mtllib cube.mtl\r\n"
                     "o cube\r\ng side\r\ns 1\r\nusemtl stone\r\n"
                     "xyz 1 2 3\r\n"
                     "vp 0.5\r\n"
                     "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0 1.0\r\n"
                     "v 0 0 1 0.2 0.3 0.4\r\nv 1 0 1\r\nv 1 1 \\\r\n1\r\nv 0 1 1 # trailing comment\r\n"
                     "v 9 9 9\r\n"
                     "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1 0\r\n"
                     "vn 0 0 -2\r\n"
                     "f 1/1 4/2 3/3 2/4\r\n"
                     "f 5/1/ 6/2 7/3 8/4\r\n"
                     "f 1//1 2//1 1//1\r\n"
                     "f 1 2 6 5\r\n"
                     "f 4/1/1 8/2/1 7/3/1 3/4/1\r\n"
                     "l 1 2\r\np 3\r\n"
                     "f -9 -5 -2 -6\r\n"
                     "f -8 -7 -3 -4\r\n"
                     "\r\n   \t\r\n";
  // "f 5/1/ ..." has an empty normal slot: malformed, checked separately below.
  parse_fails(text, "t.obj:25: malformed face vertex '5/1/'");

  const char* fixed = "# header\r\n"
                      "mtllib cube.mtl\r\n"
                      "o cube\r\ng side\r\ns 1\r\nusemtl stone\r\n"
                      "xyz 1 2 3\r\n"
                      "vp 0.5\r\n"
                      "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0 1.0\r\n"
                      "v 0 0 1 0.2 0.3 0.4\r\nv 1 0 1\r\nv 1 1 \\\r\n1\r\nv 0 1 1 # trailing comment\r\n"
                      "v 9 9 9\r\n"
                      "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1 0\r\n"
                      "vn 0 0 -2\r\n"
                      "f 1/1 4/2 3/3 2/4\r\n"
                      "f 5/1 6/2 7/3 8/4\r\n"
                      "f 1//1 2//1 1//1\r\n"
                      "f 1 2 6 5\r\n"
                      "f 4/1/1 8/2/1 7/3/1 3/4/1\r\n"
                      "l 1 2\r\np 3\r\n"
                      "f -9 -5 -2 -6\r\n"
                      "f -8 -7 -3 -4\r\n"
                      "\r\n   \t\r\n";
  bk_mesh m = {0};
  parse_ok(fixed, &m);
  ensure_unit_cube(&m); // the stray vertex is gone, the degenerate face dropped
  // The vn is normalised; the +y face (4/1/1 ...) keeps it even though it points the wrong way.
  bool found_given_normal = false;
  for (uint32_t i = 0; i < m.corner_count; ++i)
    if (m.corners[i].normal[2] == -1.0f && m.positions[m.corners[i].position].y == 1.0)
      found_given_normal = true;
  ENSURE(found_given_normal);
  // The first face's corners carry the file's uvs.
  const bk_corner* c0 = &m.corners[m.indices[0]];
  const bk_corner* c1 = &m.corners[m.indices[1]];
  ENSURE(c0->uv[0] == 0.0f && c0->uv[1] == 0.0f);
  ENSURE(c1->uv[0] == 1.0f && c1->uv[1] == 0.0f);
  bk_mesh_free(&m);

  // Lone CR line ends work too.
  parse_ok("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", &m);
  ENSURE(m.triangle_count == 1);
  bk_mesh_free(&m);
}

static char* read_text(const char* path) {
  FILE* f = fopen(path, "rb");
  ENSURE_MSG(f, "cannot open %s", path);
  char* data = NULL;
  size_t length = 0;
  char chunk[4096];
  size_t got = 0;
  while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
    data = bk_realloc(data, length + got + 1);
    memcpy(data + length, chunk, got);
    length += got;
  }
  fclose(f);
  if (!data) data = bk_calloc(1, 1);
  data[length] = '\0';
  return data;
}

static bool file_exists(const char* path) {
  FILE* f = fopen(path, "rb");
  if (f) fclose(f);
  return f != NULL;
}

static void test_round_trip(void) {
  text_buffer b = {{0}, 0};
  cube_text(&b, false, true);
  bk_mesh cube = {0};
  parse_ok(b.data, &cube);
  // Non-trivial uvs and coordinates that need all 17 digits.
  for (uint32_t i = 0; i < cube.corner_count; ++i) {
    cube.corners[i].uv[0] = 0.1f * (float)i + 1.0f / 3.0f;
    cube.corners[i].uv[1] = -0.7f * (float)i;
  }
  for (uint32_t i = 0; i < cube.position_count; ++i)
    cube.positions[i] = bk_v3_scale(cube.positions[i], 0.1);

  const char* path = BK_TEST_TMP "/cube.obj";
  bk_error err = {{0}};
  ENSURE_MSG(bk_obj_save(path, &cube, 1, &err), "%s", err.message);
  ENSURE(!file_exists(BK_TEST_TMP "/cube.obj.tmp"));
  bk_mesh back = {0};
  ENSURE_MSG(bk_obj_load(path, &back, &err), "%s", err.message);
  ENSURE(back.position_count == cube.position_count);
  ENSURE(back.triangle_count == cube.triangle_count);
  ENSURE(back.corner_count == cube.corner_count);
  ENSURE(bk_mesh_is_closed(&back));
  ENSURE_SMALL(bk_mesh_volume(&back), bk_mesh_volume(&cube), 1e-12);
  ENSURE_SMALL(bk_mesh_volume(&back), 0.001, 1e-12);
  for (uint32_t t = 0; t < cube.triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      const bk_corner* a = &cube.corners[cube.indices[3 * t + k]];
      const bk_corner* c = &back.corners[back.indices[3 * t + k]];
      bk_vec3 pa = cube.positions[a->position], pc = back.positions[c->position];
      ENSURE(pa.x == pc.x && pa.y == pc.y && pa.z == pc.z); // %.17g is exact
      for (int j = 0; j < 2; ++j)
        ENSURE_SMALL(a->uv[j], c->uv[j], 1e-6);
      for (int j = 0; j < 3; ++j)
        ENSURE_SMALL(a->normal[j], c->normal[j], 1e-6);
    }
  }
  bk_mesh_free(&back);

  // Two fragments: a second, displaced cube. Offsets must accumulate across objects.
  bk_mesh pair[2] = {{0}};
  bk_mesh_copy(&pair[0], &cube);
  bk_mesh_copy(&pair[1], &cube);
  for (uint32_t i = 0; i < pair[1].position_count; ++i)
    pair[1].positions[i] = bk_v3_add(pair[1].positions[i], bk_v3(3, 0, 0));
  const char* pair_path = BK_TEST_TMP "/pair.obj";
  ENSURE_MSG(bk_obj_save(pair_path, pair, 2, &err), "%s", err.message);
  char* text = read_text(pair_path);
  ENSURE(strstr(text, "\no fragment_0\n"));
  ENSURE(strstr(text, "\no fragment_1\n"));
  ENSURE(strstr(text, "o fragment_2") == NULL);
  ENSURE(text[0] == '#');
  free(text);
  ENSURE_MSG(bk_obj_load(pair_path, &back, &err), "%s", err.message);
  ENSURE(back.position_count == 2 * cube.position_count);
  ENSURE(back.corner_count == 2 * cube.corner_count);
  ENSURE(back.triangle_count == 2 * cube.triangle_count);
  ENSURE(bk_mesh_is_closed(&back));
  ENSURE_SMALL(bk_mesh_volume(&back), 0.002, 1e-12);
  bk_mesh_free(&back);

  // Saving over an existing file replaces it whole.
  ENSURE_MSG(bk_obj_save(pair_path, &cube, 1, &err), "%s", err.message);
  ENSURE_MSG(bk_obj_load(pair_path, &back, &err), "%s", err.message);
  ENSURE(back.triangle_count == cube.triangle_count);
  ENSURE(!file_exists(BK_TEST_TMP "/pair.obj.tmp"));
  bk_mesh_free(&back);

  // Unwritable destination: the message names the path, nothing is left behind.
  const char* bad = BK_TEST_TMP "/no/such/dir/x.obj";
  ENSURE(!bk_obj_save(bad, &cube, 1, &err));
  ENSURE_MSG(strstr(err.message, bad) && strstr(err.message, "cannot open"), "%s", err.message);

  // A corrupt mesh is refused instead of written unreadable.
  pair[0].corners[0].position = 1000;
  ENSURE(!bk_obj_save(pair_path, pair, 2, &err));
  ENSURE_MSG(strstr(err.message, "mesh 0"), "%s", err.message);
  ENSURE_MSG(bk_obj_load(pair_path, &back, &err), "%s", err.message); // previous file intact
  ENSURE(back.triangle_count == cube.triangle_count);
  bk_mesh_free(&back);

  bk_mesh_free(&pair[0]);
  bk_mesh_free(&pair[1]);
  bk_mesh_free(&cube);
}

static void test_errors(void) {
  const char* tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  char text[512];
  parse_fails("# comment\nv 0 0 0\nv 1 2\n", "t.obj:3: malformed vertex: expected 3 numbers");
  parse_fails("v 0 0 0\n\nv 1 nan 3\n", "t.obj:3: non-finite coordinate (nan)");
  parse_fails("v 1 inf 3\n", "t.obj:1: non-finite coordinate (inf)");
  parse_fails("v 1e999 0 0\n", "t.obj:1: non-finite coordinate (1e999)");
  parse_fails("v 1e31 0 0\n", "t.obj:1: coordinate out of range (1e31");
  parse_fails("v 1 2 3x\n", "t.obj:1: malformed vertex: '3x' is not a number");
  parse_fails("v 1 2 3 4 5 6 7 8\n", "t.obj:1: malformed vertex: too many numbers");
  parse_fails("vn 0 1\n", "t.obj:1: malformed normal: expected 3 numbers");
  snprintf(text, sizeof text, "%sf 1 2 99\n", tri);
  parse_fails(text, "t.obj:4: face index 99 out of range (1..3 vertices)");
  snprintf(text, sizeof text, "%sf 1 2 -4\n", tri);
  parse_fails(text, "t.obj:4: face index -4 out of range (1..3 vertices)");
  snprintf(text, sizeof text, "%sf 1 2\n", tri);
  parse_fails(text, "t.obj:4: face needs at least 3 vertices");
  snprintf(text, sizeof text, "%sf 0 1 2\n", tri);
  parse_fails(text, "t.obj:4: face index 0 is invalid");
  snprintf(text, sizeof text, "%sf 1/1 2/1 3/1\n", tri);
  parse_fails(text, "t.obj:4: texture index 1 out of range (no texture coordinates defined)");
  snprintf(text, sizeof text, "%svn 0 0 1\nf 1//1 2//1 3//2\n", tri);
  parse_fails(text, "t.obj:5: normal index 2 out of range (1..1 normals)");
  snprintf(text, sizeof text, "%sf 1 2 3/a\n", tri);
  parse_fails(text, "t.obj:4: malformed texture index 'a'");
  snprintf(text, sizeof text, "%sf 1 2 3/1/1/1\n", tri);
  parse_fails(text, "t.obj:4: malformed face vertex '3/1/1/1'");
  snprintf(text, sizeof text, "%sf 1 2 x\n", tri);
  parse_fails(text, "t.obj:4: malformed face index 'x'");
  snprintf(text, sizeof text, "%sf 1 2 99999999999999999999999999\n", tri);
  parse_fails(text, "t.obj:4: face index 99999999999999999999999999 out of range");
  parse_fails("v 0 0 0\nvt 0.5 garbage\n",
              "t.obj:2: malformed texture coordinate: 'garbage' is not a number");
  parse_fails("vt\n", "t.obj:1: malformed texture coordinate: expected 1 to 3 numbers (got 0)");
  parse_fails("v 0 0 0\n\\\nv 1 \\\n2 3\nv 1 2 3 \\\n 4 5 6 7 8\n",
              "t.obj:5: malformed vertex: too many numbers");
  parse_fails("", "t.obj: no triangles");
  parse_fails("# only a comment\nv 0 0 0\n", "t.obj: no triangles");
  snprintf(text, sizeof text, "%sf 1 1 2\nf 2 3 3\n", tri);
  parse_fails(text, "t.obj: no triangles (2 degenerate dropped)");
  parse_fails("v 0 0 0\nv 0 0 0\nv 1 0 0\nf 1 2 3\n", "t.obj: no triangles (1 degenerate dropped)");
  {
    const char binary[] = "v 0 0 0\nv 1\0 0 0\n";
    bk_mesh m = {0};
    bk_error err = {{0}};
    ENSURE(!bk_obj_parse(binary, sizeof binary - 1, "t.obj", &m, &err));
    ENSURE_MSG(strstr(err.message, "t.obj:2: NUL byte"), "%s", err.message);
    ENSURE(mesh_is_zeroed(&m));
  }

  bk_mesh m = {0};
  bk_error err = {{0}};
  const char* missing = BK_TEST_TMP "/does_not_exist.obj";
  ENSURE(!bk_obj_load(missing, &m, &err));
  ENSURE_MSG(strstr(err.message, missing) && strstr(err.message, ": cannot open: No such file"), "%s",
             err.message);
  ENSURE(mesh_is_zeroed(&m));
  ENSURE(!bk_obj_load(BK_TEST_TMP, &m, &err)); // a directory
  ENSURE(err.message[0] != '\0');
  ENSURE(mesh_is_zeroed(&m));
  // A NULL error sink is allowed.
  ENSURE(!bk_obj_parse("f 1 2 3\n", 8, "t.obj", &m, NULL));
}

// Deterministic 64-bit LCG (Knuth's MMIX constants); the high bits are the good ones.
static uint32_t lcg_next(uint64_t* state) {
  *state = *state * 6364136223846793005ull + 1442695040888963407ull;
  return (uint32_t)(*state >> 33);
}

static void test_mutations(void) {
  const char* base = "# fuzz base\nmtllib a.mtl\no thing\n"
                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                     "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                     "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n"
                     "s off\nusemtl m\n"
                     "f 1/1/1 4/2/1 3/3/1 2/4/1\n"
                     "f 5/1/2 6/2/2 7/3/2 8/4/2\r\n"
                     "f 1//3 2//3 6//3 5//3\n"
                     "f 4/1 8/2 \\\n7/3 3/4\n"
                     "f -8 -4 -1 -5\n"
                     "f -7 -6 -2 -3\n";
  // Bytes that steer mutations towards the parser's interesting paths.
  static const char alphabet[] = "0123456789-+./ \n\r\t\\#eEfvtnx";
  size_t base_length = strlen(base);
  uint64_t state = 12345;
  int successes = 0, failures = 0;
  for (int iteration = 0; iteration < 2000; ++iteration) {
    size_t capacity = base_length + 16;
    char* work = bk_alloc(capacity);
    memcpy(work, base, base_length);
    size_t length = base_length;
    int edits = 1 + (int)(lcg_next(&state) % 4);
    for (int e = 0; e < edits; ++e) {
      uint32_t op = lcg_next(&state) % 4;
      uint32_t r = lcg_next(&state);
      char byte = (r & 1) ? alphabet[(r >> 1) % (sizeof alphabet - 1)] : (char)(r >> 8);
      size_t at = length ? lcg_next(&state) % length : 0;
      if (op == 0 && length > 0) {
        work[at] = byte;
      } else if (op == 1 && length + 1 <= capacity) {
        memmove(work + at + 1, work + at, length - at);
        work[at] = byte;
        length++;
      } else if (op == 2 && length > 0) {
        memmove(work + at, work + at + 1, length - at - 1);
        length--;
      } else if (op == 3) {
        length = at;
      }
    }
    // An exactly sized copy, so reading past the end trips AddressSanitizer.
    char* exact = bk_alloc(length);
    if (length) memcpy(exact, work, length);
    free(work);
    bk_mesh m = {0};
    bk_error err = {{0}};
    if (bk_obj_parse(exact, length, "fuzz.obj", &m, &err)) {
      ENSURE_MSG(bk_mesh_validate(&m, &err), "iteration %d: %s", iteration, err.message);
      ENSURE(m.triangle_count > 0 && m.position_count >= 3);
      bk_closure closure = bk_mesh_check_closure(&m);
      ENSURE(closure.degenerate_edges == 0);
      // Every position is used by some triangle.
      bool* used = bk_calloc(m.position_count, sizeof(bool));
      for (uint32_t t = 0; t < m.triangle_count; ++t)
        for (int k = 0; k < 3; ++k)
          used[bk_mesh_tri_position(&m, t, k)] = true;
      for (uint32_t i = 0; i < m.position_count; ++i)
        ENSURE(used[i]);
      free(used);
      successes++;
    } else {
      ENSURE_MSG(err.message[0] != '\0', "iteration %d: empty message", iteration);
      ENSURE(strncmp(err.message, "fuzz.obj", 8) == 0);
      ENSURE(mesh_is_zeroed(&m));
      failures++;
    }
    bk_mesh_free(&m);
    free(exact);
  }
  fprintf(stderr, "    %d parsed, %d rejected\n", successes, failures);
  ENSURE(successes > 100 && failures > 100);
}

static void test_bunny(void) {
  const char* path = BK_ASSET_DIR "/meshes/bunny.obj";
  if (!file_exists(path)) {
    fprintf(stderr, "    note: %s not present, skipping\n", path);
    return;
  }
  bk_mesh m = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_obj_load(path, &m, &err), "%s", err.message);
  ENSURE_MSG(bk_mesh_validate(&m, &err), "%s", err.message);
  bk_closure c = bk_mesh_check_closure(&m);
  ENSURE_MSG(bk_mesh_is_closed(&m), "open %u overused %u degenerate %u", c.open_edges, c.overused_edges,
             c.degenerate_edges);
  ENSURE(bk_mesh_volume(&m) > 0.0);
  ensure_tangent_frames(&m);
  bk_mesh_free(&m);
}

// A host application in a locale with a decimal comma (a German Godot or
// Unity editor) must not change what the OBJ reader and writer see: the
// test compiles de_DE into a private directory (localedef, from the
// locales package) so it runs the same on every machine.
static void test_decimal_comma_locale(void) {
  const char* dir = BK_TEST_TMP "/locales";
  char command[512];
  snprintf(command, sizeof command,
           "mkdir -p '%s' && localedef -i de_DE -f UTF-8 '%s/de_DE.UTF-8' 2>/dev/null", dir, dir);
  ENSURE_MSG(system(command) == 0 || access(BK_TEST_TMP "/locales/de_DE.UTF-8", R_OK) == 0,
             "localedef could not make de_DE (is Debian's locales package installed?)");
  setenv("LOCPATH", dir, 1);
  ENSURE_MSG(setlocale(LC_ALL, "de_DE.UTF-8") != NULL, "de_DE.UTF-8 is not usable from %s", dir);
  char shown[16];
  snprintf(shown, sizeof shown, "%.1f", 0.5);
  ENSURE_MSG(strcmp(shown, "0,5") == 0, "the locale is not in effect (%s)", shown);

  bk_mesh cube = {0};
  parse_ok("v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv -0.5 0.5 -0.5\nv 0.5 0.5 -0.5\n"
           "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv -0.5 0.5 0.5\nv 0.5 0.5 0.5\n"
           "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n",
           &cube);
  ENSURE_SMALL(bk_mesh_volume(&cube), 1.0, 1e-12); // "0.5" read as 0.5, not 0
  const char* path = BK_TEST_TMP "/locale_cube.obj";
  bk_error err = {{0}};
  ENSURE_MSG(bk_obj_save(path, &cube, 1, &err), "%s", err.message);
  FILE* f = fopen(path, "r");
  ENSURE(f);
  char text[4096] = {0};
  size_t n = fread(text, 1, sizeof text - 1, f);
  fclose(f);
  ENSURE(n > 0 && strstr(text, "v -0.5 -0.5 -0.5") && !strstr(text, "0,5"));
  bk_mesh back = {0};
  ENSURE_MSG(bk_obj_load(path, &back, &err), "%s", err.message);
  ENSURE_SMALL(bk_mesh_volume(&back), 1.0, 1e-12);
  snprintf(shown, sizeof shown, "%.1f", 0.5);
  ENSURE_MSG(strcmp(shown, "0,5") == 0, "the host's locale was not restored (%s)", shown);
  setlocale(LC_ALL, "C");
  bk_mesh_free(&cube);
  bk_mesh_free(&back);
}

// usemtl names give the triangles' source materials in the order of first
// use; the mtllib file beside the OBJ gives their colours and textures
// (map_Kd's options skipped, the name resolved against the OBJ's directory).
static void test_materials(void) {
  const char* obj = "mtllib two.mtl\n"
                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                    "f 1 3 2\n"          // before any usemtl: material 0, unnamed
                    "usemtl red brick\n" // names may hold blanks
                    "f 1 2 4\nf 1 4 3\n"
                    "usemtl glass\n"
                    "f 2 3 4\n"
                    "usemtl red brick\n"; // used again: the same id
  const char* mtl = "# two materials\nnewmtl glass\nKd 0.5 0.25 1\nd 0.5\n"
                    "newmtl red brick\nKd 0.8 0.1 0.1\nmap_Kd -o 0.5 0.5 -bm 2 tex/red brick.png\n"
                    "newmtl unused\nKd nan 2 -1\nmap_Kd\n";
  FILE* f = fopen(BK_TEST_TMP "/two.obj", "wb");
  ENSURE(f && fputs(obj, f) >= 0 && fclose(f) == 0);
  f = fopen(BK_TEST_TMP "/two.mtl", "wb");
  ENSURE(f && fputs(mtl, f) >= 0 && fclose(f) == 0);
  bk_mesh m = {0};
  bk_import_info info = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_model_import(BK_TEST_TMP "/two.obj", NULL, &m, &info, &err), "%s", err.message);
  ENSURE_MSG(info.materials == 3, "%u materials", info.materials);
  ENSURE(info.material_list[0].name[0] == '\0' && info.material_list[0].triangles == 1);
  ENSURE(strcmp(info.material_list[1].name, "red brick") == 0 && info.material_list[1].triangles == 2);
  ENSURE(strcmp(info.material_list[2].name, "glass") == 0 && info.material_list[2].triangles == 1);
  ENSURE(info.dominant_material == 1);
  const uint32_t expected[4] = {0, 1, 1, 2};
  for (uint32_t t = 0; t < 4; ++t)
    ENSURE_MSG(m.materials[t] == bk_material_id(expected[t], false), "triangle %u: %u", t, m.materials[t]);
  const bk_import_material* red = &info.material_list[1];
  const bk_import_material* glass = &info.material_list[2];
  ENSURE(red->base_color[0] == 0.8f && red->base_color[1] == 0.1f && red->base_color[3] == 1.0f);
  ENSURE(glass->base_color[2] == 1.0f && glass->base_color[3] == 0.5f);
  ENSURE_MSG(strcmp(red->texture, BK_TEST_TMP "/tex/red brick.png") == 0, "texture '%s'", red->texture);
  ENSURE(glass->texture[0] == '\0' && info.material_list[0].base_color[0] == 1.0f);
  bk_mesh_free(&m);
  bk_import_info_free(&info);
  // Without the library beside it (or from memory), the names alone.
  ENSURE(remove(BK_TEST_TMP "/two.mtl") == 0);
  ENSURE_MSG(bk_model_import(BK_TEST_TMP "/two.obj", NULL, &m, &info, &err), "%s", err.message);
  ENSURE(info.materials == 3 && info.material_list[1].base_color[1] == 1.0f &&
         !info.material_list[1].texture[0]);
  bk_mesh_free(&m);
  bk_import_info_free(&info);
  ENSURE(bk_model_import_memory(obj, strlen(obj), "obj", "mem.obj", NULL, &m, &info, &err));
  ENSURE(info.materials == 3 && strcmp(info.material_list[2].name, "glass") == 0);
  bk_mesh_free(&m);
  bk_import_info_free(&info);
}

int main(void) {
  RUN(test_cube_shared_vertices);
  RUN(test_cube_duplicated_vertices);
  RUN(test_negative_indices);
  RUN(test_face_forms_and_ignored_statements);
  RUN(test_round_trip);
  RUN(test_decimal_comma_locale);
  RUN(test_errors);
  RUN(test_mutations);
  RUN(test_bunny);
  RUN(test_materials);
  return 0;
}
