// Trees for the page: fracture a built-in shape, an OBJ file or triangles
// handed over by JavaScript; load .mtree bytes; hand out the tree's bytes,
// its hash (the one `breakables fracture --json` reports), a .glb of it, and
// its node meshes as float and index arrays JavaScript views in place.
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "web_bridge.h"

static char last_error[512];

void web_set_error(const bk_error* err) { snprintf(last_error, sizeof last_error, "%s", err->message); }
void web_set_error_text(const char* text) { snprintf(last_error, sizeof last_error, "%s", text); }

EMSCRIPTEN_KEEPALIVE const char* web_last_error(void) { return last_error; }
EMSCRIPTEN_KEEPALIVE void* web_alloc(size_t size) { return bk_alloc(size ? size : 1); }
EMSCRIPTEN_KEEPALIVE void web_free(void* memory) { bk_free(memory); }

static double now_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

// Progress goes to the page's Module.onProgress (a worker posts it on).
EM_JS(void, web_report_progress, (double fraction), {
  if (Module["onProgress"]) Module["onProgress"](fraction);
});

static bool report_progress(void* user, uint32_t leaves, uint32_t target) {
  (void)user;
  web_report_progress(target ? (double)leaves / (double)target : 0.0);
  return true;
}

static bool make_views(web_tree* t) {
  const bk_mesh_tree* tree = &t->tree;
  uint64_t corners = 0, triangles = 0, points = 0;
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    corners += tree->nodes[i].mesh.corner_count;
    triangles += tree->nodes[i].mesh.triangle_count;
    points += tree->nodes[i].mesh.position_count;
  }
  if (corners > (1u << 28) || triangles > (1u << 28) || points > (1u << 28)) {
    web_set_error_text("tree: too large for the page's memory");
    return false;
  }
  t->positions = bk_alloc((size_t)corners * 3 * sizeof(float) + 4);
  t->normals = bk_alloc((size_t)corners * 3 * sizeof(float) + 4);
  t->indices = bk_alloc((size_t)triangles * 3 * sizeof(uint32_t) + 4);
  t->inside = bk_alloc((size_t)triangles + 4);
  t->ranges = bk_alloc((size_t)tree->node_count * 4 * sizeof(uint32_t) + 4);
  t->hull_points = bk_alloc((size_t)points * 3 * sizeof(float) + 4);
  t->hull_ranges = bk_alloc((size_t)tree->node_count * 2 * sizeof(uint32_t) + 4);
  uint32_t c0 = 0, i0 = 0, p0 = 0;
  for (uint32_t n = 0; n < tree->node_count; ++n) {
    const bk_mesh* m = &tree->nodes[n].mesh;
    for (uint32_t c = 0; c < m->corner_count; ++c) {
      bk_vec3 p = m->positions[m->corners[c].position];
      float* pos = &t->positions[3 * (c0 + c)];
      pos[0] = (float)p.x, pos[1] = (float)p.y, pos[2] = (float)p.z;
      memcpy(&t->normals[3 * (c0 + c)], m->corners[c].normal, 3 * sizeof(float));
    }
    for (uint32_t k = 0; k < m->triangle_count * 3; ++k)
      t->indices[i0 + k] = m->indices[k];
    for (uint32_t k = 0; k < m->triangle_count; ++k)
      t->inside[i0 / 3 + k] = m->materials && bk_material_is_interior(m->materials[k]) ? 1 : 0;
    for (uint32_t k = 0; k < m->position_count; ++k) {
      float* q = &t->hull_points[3 * (p0 + k)];
      q[0] = (float)m->positions[k].x, q[1] = (float)m->positions[k].y, q[2] = (float)m->positions[k].z;
    }
    uint32_t* r = &t->ranges[4 * n];
    r[0] = c0, r[1] = m->corner_count, r[2] = i0, r[3] = m->triangle_count * 3;
    t->hull_ranges[2 * n] = p0, t->hull_ranges[2 * n + 1] = m->position_count;
    c0 += m->corner_count, i0 += m->triangle_count * 3, p0 += m->position_count;
  }
  return true;
}

EMSCRIPTEN_KEEPALIVE void web_tree_free(web_tree* t) {
  if (!t) return;
  bk_mesh_tree_free(&t->tree);
  bk_free(t->positions), bk_free(t->normals), bk_free(t->indices), bk_free(t->inside);
  bk_free(t->ranges), bk_free(t->hull_points), bk_free(t->hull_ranges);
  bk_free(t);
}

static web_tree* finish(web_tree* t, bool ok, bk_error* err) {
  if (!ok) {
    web_set_error(err);
    web_tree_free(t);
    return NULL;
  }
  if (!make_views(t)) {
    web_tree_free(t);
    return NULL;
  }
  return t;
}

// The fracture def's fields the page sets, as 8 doubles (web/js/breakables.js
// fills them): pieces (0: the default), pattern (< 0: the default), seed,
// aspect_bias (NaN: the default), whether an impact point follows, its x y z.
enum { ARG_PIECES, ARG_PATTERN, ARG_SEED, ARG_ASPECT_BIAS, ARG_HAS_IMPACT, ARG_IMPACT };

// Builds the tree of `source` (taken: freed here) with the def of `args`.
static web_tree* build(bk_mesh* source, const double* args) {
  bk_error err = {0};
  bk_fracture_def def = bk_default_fracture_def();
  if (!(args[ARG_PIECES] >= 0 && args[ARG_PIECES] <= (double)(1u << 30)) ||
      !(args[ARG_PATTERN] >= -1 && args[ARG_PATTERN] <= BK_PATTERN_COUNT)) { // checked before the casts
    bk_mesh_free(source);
    web_set_error_text("fracture: pieces or pattern out of range");
    return NULL;
  }
  int pieces = (int)args[ARG_PIECES], pattern = (int)args[ARG_PATTERN];
  double seed = args[ARG_SEED];
  if (!isnan(args[ARG_ASPECT_BIAS])) def.aspect_bias = args[ARG_ASPECT_BIAS];
  if (args[ARG_HAS_IMPACT] != 0.0)
    def.impact = bk_v3(args[ARG_IMPACT], args[ARG_IMPACT + 1], args[ARG_IMPACT + 2]);
  if (pieces > 0) def.pieces = (uint32_t)pieces;
  if (pattern >= BK_PATTERN_COUNT) {
    bk_mesh_free(source);
    web_set_error_text("fracture: pattern out of range");
    return NULL;
  }
  if (pattern >= 0) def.pattern = (bk_fracture_pattern)pattern;
  if (!(seed >= 0 && seed <= 9007199254740991.0)) {
    bk_mesh_free(source);
    web_set_error_text("fracture: seed must be a whole number from 0 to 2^53 - 1");
    return NULL;
  }
  def.seed = (uint64_t)seed;
  // The module's memory stops at 2 GiB (web/CMakeLists.txt), and running
  // out ends it: a fracture that would need more is refused first, as the
  // command line refuses one beyond the machine's memory. The trees, the
  // views made of them and the page's own share leave it about 1.5 GiB.
  uint64_t need = bk_mesh_tree_estimate_bytes(source, &def);
  const uint64_t limit = (uint64_t)3 << 29;
  if (need > limit) {
    bk_mesh_free(source);
    bk_error_set(&err, "fracture: %u pieces would need about %llu MiB, more than the page's %llu MiB",
                 def.pieces, (unsigned long long)(need >> 20), (unsigned long long)(limit >> 20));
    web_set_error(&err);
    return NULL;
  }
  def.progress = report_progress;
  web_tree* t = bk_calloc(1, sizeof *t);
  double start = now_ms();
  bool ok = bk_mesh_tree_build(source, &def, &t->tree, &err);
  t->build_ms = now_ms() - start;
  bk_mesh_free(source);
  return finish(t, ok, &err);
}

static bool repair(bk_mesh* m, const char* name) {
  bk_repair_info info = {0};
  bk_error err = {0};
  if (bk_mesh_repair(m, &info, &err)) return true;
  bk_error named = {0};
  bk_error_set(&named, "%s: %s", name, err.message);
  web_set_error(&named);
  bk_mesh_free(m);
  return false;
}

EMSCRIPTEN_KEEPALIVE web_tree* web_fracture_shape(const char* name, const double* args) {
  bk_shape shape = BK_SHAPE_CUBE;
  if (!bk_shape_from_name(name, &shape)) {
    bk_error err = {0};
    bk_error_set(&err, "unknown shape '%s'", name);
    web_set_error(&err);
    return NULL;
  }
  bk_mesh source = {0};
  bk_shape_build(shape, &source);
  return build(&source, args);
}

/// A model file's bytes (.obj or .ply by `format`); unit_height scales it
/// as the command line scales its bundled bunny.
EMSCRIPTEN_KEEPALIVE web_tree* web_fracture_file(const uint8_t* data, size_t size, const char* format,
                                                 const char* name, int unit_height, const double* args) {
  bk_mesh source = {0};
  bk_error err = {0};
  bk_import_def def = bk_default_import_def();
  if (!bk_model_import_memory(data, size, format, name, &def, &source, NULL, &err)) {
    web_set_error(&err);
    return NULL;
  }
  if (unit_height) bk_mesh_fit_unit_height(&source);
  if (!repair(&source, name)) return NULL;
  return build(&source, args);
}

/// Triangles JavaScript read from a model (three.js's GLTFLoader): xyz per
/// position, three position indices per triangle.
EMSCRIPTEN_KEEPALIVE web_tree* web_fracture_triangles(const float* positions, uint32_t position_count,
                                                      const uint32_t* indices, uint32_t triangle_count,
                                                      const char* name, const double* args) {
  bk_error err = {0};
  if (position_count < 4 || triangle_count < 4 || position_count > (1u << 24) ||
      triangle_count > (1u << 24)) {
    bk_error_set(&err, "%s: %u positions and %u triangles cannot enclose a solid (or are too many)", name,
                 position_count, triangle_count);
    web_set_error(&err);
    return NULL;
  }
  bk_mesh m = {0};
  bk_mesh_reserve(&m, position_count, position_count, triangle_count);
  for (uint32_t i = 0; i < position_count; ++i) {
    const float* p = &positions[3 * i];
    if (!(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]) && fabsf(p[0]) < 1e30f && fabsf(p[1]) < 1e30f &&
          fabsf(p[2]) < 1e30f)) {
      bk_mesh_free(&m);
      bk_error_set(&err, "%s: position %u is not a finite number", name, i);
      web_set_error(&err);
      return NULL;
    }
    bk_mesh_add_position(&m, bk_v3(p[0], p[1], p[2]));
    bk_corner c = {.position = i};
    bk_mesh_add_corner(&m, &c);
  }
  for (uint32_t t = 0; t < triangle_count; ++t) {
    const uint32_t* v = &indices[3 * t];
    if (v[0] >= position_count || v[1] >= position_count || v[2] >= position_count) {
      bk_mesh_free(&m);
      bk_error_set(&err, "%s: triangle %u names position %u of %u", name, t,
                   v[0] >= position_count   ? v[0]
                   : v[1] >= position_count ? v[1]
                                            : v[2],
                   position_count);
      web_set_error(&err);
      return NULL;
    }
    bk_mesh_add_triangle(&m, v[0], v[1], v[2], bk_material_id(0, false), 0);
  }
  if (!repair(&m, name)) return NULL;
  return build(&m, args);
}

EMSCRIPTEN_KEEPALIVE web_tree* web_tree_load(const uint8_t* data, size_t size) {
  bk_error err = {0};
  web_tree* t = bk_calloc(1, sizeof *t);
  bool ok = bk_mesh_tree_load_memory(data, size, "tree", &t->tree, &err);
  return finish(t, ok, &err);
}

/// The tree a .glb of bk_mesh_tree_save_gltf carries (a fractured export,
/// read back bit-exactly); a glTF without one is refused in one line.
EMSCRIPTEN_KEEPALIVE web_tree* web_tree_load_glb(const uint8_t* data, size_t size) {
  bk_error err = {0};
  web_tree* t = bk_calloc(1, sizeof *t);
  bool ok = bk_mesh_tree_load_gltf_memory(data, size, "glb", &t->tree, &err);
  return finish(t, ok, &err);
}

// ---------------------------------------------------------------- reading a tree

EMSCRIPTEN_KEEPALIVE uint32_t web_tree_node_count(const web_tree* t) { return t->tree.node_count; }
EMSCRIPTEN_KEEPALIVE uint32_t web_tree_leaf_count(const web_tree* t) { return t->tree.leaf_count; }
EMSCRIPTEN_KEEPALIVE uint32_t web_tree_bond_count(const web_tree* t) { return t->tree.bond_count; }
EMSCRIPTEN_KEEPALIVE double web_tree_build_ms(const web_tree* t) { return t->build_ms; }
EMSCRIPTEN_KEEPALIVE const uint32_t* web_tree_leaf_nodes(const web_tree* t) { return t->tree.leaf_nodes; }
/// Per node: parent (UINT32_MAX for the root), first child, child count, depth.
EMSCRIPTEN_KEEPALIVE uint32_t* web_tree_links(const web_tree* t) {
  uint32_t* out = bk_alloc((size_t)t->tree.node_count * 4 * sizeof(uint32_t) + 4);
  for (uint32_t i = 0; i < t->tree.node_count; ++i) {
    const bk_mesh_tree_node* n = &t->tree.nodes[i];
    out[4 * i] = n->parent, out[4 * i + 1] = n->first_child, out[4 * i + 2] = n->child_count;
    out[4 * i + 3] = n->depth;
  }
  return out;
}
/// The root's bounds: min xyz, max xyz.
EMSCRIPTEN_KEEPALIVE void web_tree_bounds(const web_tree* t, double* out) {
  bk_aabb b = t->tree.nodes[0].bounds;
  out[0] = b.min.x, out[1] = b.min.y, out[2] = b.min.z, out[3] = b.max.x, out[4] = b.max.y, out[5] = b.max.z;
}
EMSCRIPTEN_KEEPALIVE const float* web_tree_positions(const web_tree* t) { return t->positions; }
EMSCRIPTEN_KEEPALIVE const float* web_tree_normals(const web_tree* t) { return t->normals; }
EMSCRIPTEN_KEEPALIVE const uint32_t* web_tree_indices(const web_tree* t) { return t->indices; }
EMSCRIPTEN_KEEPALIVE const uint8_t* web_tree_inside(const web_tree* t) { return t->inside; }
EMSCRIPTEN_KEEPALIVE const uint32_t* web_tree_ranges(const web_tree* t) { return t->ranges; }
EMSCRIPTEN_KEEPALIVE const float* web_tree_hull_points(const web_tree* t) { return t->hull_points; }
EMSCRIPTEN_KEEPALIVE const uint32_t* web_tree_hull_ranges(const web_tree* t) { return t->hull_ranges; }

/// The .mtree bytes (bk_free them: web_free); size into *size; NULL on failure.
EMSCRIPTEN_KEEPALIVE uint8_t* web_tree_bytes(const web_tree* t, uint32_t* size) {
  uint8_t* bytes = NULL;
  size_t n = 0;
  bk_error err = {0};
  if (!bk_mesh_tree_save_memory(&t->tree, "tree", &bytes, &n, &err)) {
    web_set_error(&err);
    return NULL;
  }
  *size = (uint32_t)n;
  return bytes;
}

/// XXH3-64 of the .mtree bytes, as 16 hex digits into out[17].
EMSCRIPTEN_KEEPALIVE bool web_tree_hash(const web_tree* t, char* out) {
  uint32_t size = 0;
  uint8_t* bytes = web_tree_bytes(t, &size);
  if (!bytes) return false;
  snprintf(out, 17, "%016llx", (unsigned long long)XXH3_64bits(bytes, size));
  bk_free(bytes);
  return true;
}

/// A .glb of the tree (what `fracture --export-gltf` writes), through the
/// module's in-memory file system; NULL on failure.
EMSCRIPTEN_KEEPALIVE uint8_t* web_tree_glb(const web_tree* t, uint32_t* size) {
  const char* path = "/tmp/breakables_export.glb";
  bk_error err = {0};
  bk_gltf_def def = bk_default_gltf_def();
  if (!bk_mesh_tree_save_gltf(&t->tree, path, &def, &err)) {
    web_set_error(&err);
    return NULL;
  }
  void* data = NULL;
  size_t n = 0;
  bool ok = bk_file_read(path, (uint64_t)1 << 31, "2 GiB", &data, &n, &err);
  remove(path);
  if (!ok) {
    web_set_error(&err);
    return NULL;
  }
  *size = (uint32_t)n;
  return data;
}
