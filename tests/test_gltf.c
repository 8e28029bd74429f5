// glTF export (bk_mesh_tree_save_gltf) read back structurally by our own
// JSON reader, the round trip through bk_mesh_tree_load_gltf, and refusals of
// damaged and foreign files. With `--export DIR`, writes the exports the
// third-party checks read (tests/js/check_gltf.mjs, run by ctest's
// test_gltf_js) and prints one line of arguments for each.
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <meshoptimizer.h>

#include "bk_fracture.h"
#include "bk_geom.h"
#include "bk_json.h"
#include "ensure.h"
#include "gltf_internal.h"

// A cube of side 2 centred at (3, -2, 5): the tree's origin, the centroids and
// the node translations are all different from each other.
static void build_pattern_tree(uint32_t pieces, bk_fracture_pattern pattern, bk_mesh_tree* tree) {
  bk_mesh cube = {0};
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  for (uint32_t i = 0; i < cube.position_count; ++i)
    cube.positions[i] = bk_v3_add(bk_v3_scale(cube.positions[i], 2.0), bk_v3(3, -2, 5));
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.pattern = pattern;
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_build(&cube, &desc, tree, &err), "%s", err.message);
  bk_mesh_free(&cube);
  ENSURE(tree->leaf_count == pieces && tree->bond_count > 0);
}

static void build_tree(uint32_t pieces, bk_mesh_tree* tree) {
  build_pattern_tree(pieces, BK_PATTERN_PLANES, tree);
}

static void build_noisy_voronoi_tree(uint32_t pieces, bk_mesh_tree* tree) {
  bk_mesh torus = {0};
  bk_shape_build(BK_SHAPE_TORUS, &torus);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.pattern = BK_PATTERN_VORONOI;
  desc.noise_amplitude = 0.02;
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_build(&torus, &desc, tree, &err), "%s", err.message);
  bk_mesh_free(&torus);
  ENSURE(tree->leaf_count == pieces);
}

// A tree grown at run time (bk_mesh_tree_splice): the noisy Voronoi torus
// with two of its leaves fractured again, radially, where a hit would be.
static void build_refined_tree(bk_mesh_tree* tree) {
  build_noisy_voronoi_tree(16, tree);
  const uint32_t refined[2] = {9, 2}; // the later leaf first: the earlier keeps its number
  for (int i = 0; i < 2; ++i) {
    const bk_mesh_tree_node* leaf = bk_mesh_tree_leaf(tree, refined[i]);
    bk_fracture_def def = bk_default_fracture_def();
    def.pattern = BK_PATTERN_RADIAL;
    def.pieces = 12;
    def.impact = leaf->bounds.max;
    bk_mesh_tree pieces = {0};
    bk_error err = {{0}};
    ENSURE_MSG(bk_mesh_fracture_leaf(&leaf->mesh, tree->nodes[0].bounds, &def, &pieces, &err), "%s",
               err.message);
    ENSURE_MSG(bk_mesh_tree_splice(tree, refined[i], &pieces, NULL, &err), "%s", err.message);
  }
  ENSURE(tree->leaf_count > 30);
}

static uint8_t* read_all(const char* path, size_t* size) {
  void* data = NULL;
  bk_error err = {{0}};
  ENSURE_MSG(bk_file_read(path, (uint64_t)1 << 32, "4 GiB", &data, size, &err), "%s", err.message);
  return data;
}

static void write_all(const char* path, const void* data, size_t size) {
  FILE* f = fopen(path, "wb");
  ENSURE(f);
  ENSURE(fwrite(data, 1, size, f) == size);
  ENSURE(fclose(f) == 0);
}

static uint32_t u32le(const uint8_t* p) {
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

// ---------------------------------------------------------------- reading an export back

typedef struct parsed {
  uint8_t* file;
  size_t file_size;
  bk_json_doc doc;
  uint8_t* bin; // owned copy of the binary buffer
  size_t bin_size;
} parsed;

static uint32_t get(const parsed* p, uint32_t v, const char* key) {
  uint32_t r = bk_json_get(&p->doc, v, key);
  ENSURE_MSG(r != BK_JSON_NONE, "missing key %s", key);
  return r;
}

static uint64_t get_uint(const parsed* p, uint32_t v, const char* key) {
  uint64_t n = 0;
  ENSURE_MSG(bk_json_uint(&p->doc, get(p, v, key), UINT64_MAX, &n), "%s is not a whole number", key);
  return n;
}

static double number_at(const parsed* p, uint32_t array, uint32_t i) {
  double d = 0;
  ENSURE(bk_json_number(&p->doc, bk_json_at(&p->doc, array, i), &d));
  return d;
}

static int base64_digit(char c) {
  const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const char* at = strchr(alphabet, c);
  return c && at ? (int)(at - alphabet) : -1;
}

// Checks the container (GLB header, chunk lengths and alignment) or the data
// URI, and parses the JSON.
static void parse_export(const char* path, bool glb, parsed* p) {
  memset(p, 0, sizeof *p);
  p->file = read_all(path, &p->file_size);
  const char* json = (const char*)p->file;
  size_t json_size = p->file_size;
  if (glb) {
    const uint8_t* f = p->file;
    ENSURE(p->file_size >= 28 && p->file_size % 4 == 0);
    ENSURE(u32le(f) == BK_GLB_MAGIC && u32le(f + 4) == 2 && u32le(f + 8) == p->file_size);
    uint32_t json_chunk = u32le(f + 12);
    ENSURE(u32le(f + 16) == BK_GLB_CHUNK_JSON && json_chunk % 4 == 0 &&
           20 + (size_t)json_chunk + 8 <= p->file_size);
    uint32_t bin_chunk = u32le(f + 20 + json_chunk);
    ENSURE(u32le(f + 24 + json_chunk) == BK_GLB_CHUNK_BIN && bin_chunk % 4 == 0);
    ENSURE(28 + (size_t)json_chunk + bin_chunk == p->file_size);
    json = (const char*)f + 20;
    json_size = json_chunk;
    p->bin_size = bin_chunk;
    p->bin = bk_alloc(bin_chunk);
    memcpy(p->bin, f + 28 + json_chunk, bin_chunk);
  }
  char why[200];
  ENSURE_MSG(bk_json_parse(json, json_size, &p->doc, why, sizeof why), "%s: %s", path, why);
  uint32_t buffer = bk_json_at(&p->doc, get(p, 0, "buffers"), 0);
  uint64_t byte_length = get_uint(p, buffer, "byteLength");
  if (!glb) {
    const bk_json_value* uri = &p->doc.values[get(p, buffer, "uri")];
    size_t prefix = strlen(BK_GLTF_DATA_URI);
    ENSURE(uri->length > prefix && memcmp(json + uri->start, BK_GLTF_DATA_URI, prefix) == 0);
    const char* b64 = json + uri->start + prefix;
    size_t n = uri->length - prefix;
    ENSURE(n % 4 == 0);
    p->bin = bk_alloc(n / 4 * 3);
    for (size_t i = 0; i < n; i += 4) {
      uint32_t v = 0;
      for (int k = 0; k < 4; ++k)
        v = v << 6 | (uint32_t)(b64[i + k] == '=' ? 0 : base64_digit(b64[i + k]));
      p->bin[p->bin_size++] = (uint8_t)(v >> 16);
      p->bin[p->bin_size++] = (uint8_t)(v >> 8);
      p->bin[p->bin_size++] = (uint8_t)v;
    }
    p->bin_size -= (b64[n - 1] == '=') + (b64[n - 2] == '=');
  }
  ENSURE(byte_length == p->bin_size || (glb && byte_length <= p->bin_size && p->bin_size - byte_length < 4));
}

static void parsed_free(parsed* p) {
  bk_json_free(&p->doc);
  free(p->file);
  free(p->bin);
}

// The bytes an accessor covers; checks the view's and the accessor's bounds.
static const uint8_t* accessor_data(const parsed* p, uint32_t index, uint64_t* count, uint32_t* component,
                                    uint32_t element_bytes) {
  uint32_t accessor = bk_json_at(&p->doc, get(p, 0, "accessors"), index);
  ENSURE(accessor != BK_JSON_NONE);
  uint32_t view =
      bk_json_at(&p->doc, get(p, 0, "bufferViews"), (uint32_t)get_uint(p, accessor, "bufferView"));
  uint64_t view_offset = get_uint(p, view, "byteOffset"), view_length = get_uint(p, view, "byteLength");
  uint64_t offset = get_uint(p, accessor, "byteOffset");
  *count = get_uint(p, accessor, "count");
  *component = (uint32_t)get_uint(p, accessor, "componentType");
  if (*component == 5123) element_bytes = 2;
  if (*component == 5125) element_bytes = 4;
  ENSURE(view_offset + view_length <= p->bin_size);
  ENSURE(offset + *count * element_bytes <= view_length);
  ENSURE((view_offset + offset) % (element_bytes < 4 ? element_bytes : 4) == 0);
  return p->bin + view_offset + offset;
}

static float f32_at(const uint8_t* p) {
  float v = 0;
  memcpy(&v, p, sizeof v);
  return v;
}

// Everything about one export: the node list, the hierarchy and the
// translations, every mesh against the tree's, and the extras.
// The export material of a triangle: 2 per source material (surface, cut
// faces); sources past the export's `sources` use the first's.
static uint32_t export_material(uint8_t id, uint32_t sources) {
  uint32_t source = bk_material_source(id);
  return 2u * (source < sources ? source : 0u) + (bk_material_is_interior(id) ? 1u : 0u);
}

static double f64_at(const uint8_t* p) {
  double v = 0;
  memcpy(&v, p, sizeof v);
  return v;
}

// The bytes of one of our record views named in asset.extras.breakables
// (`key`: nodes or bonds): count records of `stride` bytes.
static const uint8_t* records(const parsed* p, uint32_t ours, const char* key, uint32_t count,
                              uint32_t stride) {
  uint32_t r = get(p, ours, key);
  ENSURE(get_uint(p, r, "count") == count && get_uint(p, r, "byteStride") == stride);
  if (count == 0) return NULL;
  uint32_t view = bk_json_at(&p->doc, get(p, 0, "bufferViews"), (uint32_t)get_uint(p, r, "bufferView"));
  uint64_t offset = get_uint(p, view, "byteOffset");
  ENSURE(get_uint(p, view, "byteLength") == (uint64_t)count * stride && offset % 8 == 0 &&
         offset + (uint64_t)count * stride <= p->bin_size);
  return p->bin + offset;
}

// The extras: the node records and bond records hold the tree's numbers exactly.
static void check_records(const parsed* p, const bk_mesh_tree* tree, uint32_t ours) {
  const uint8_t* nodes = records(p, ours, "nodes", tree->node_count, BK_GLTF_NODE_RECORD_BYTES);
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    const uint8_t* r = nodes + (size_t)i * BK_GLTF_NODE_RECORD_BYTES;
    const bk_mesh_tree_node* n = &tree->nodes[i];
    ENSURE(f64_at(r) == n->moments.v && f64_at(r + 8) == n->moments.x && f64_at(r + 72) == n->moments.zx);
    ENSURE(f64_at(r + 80) == n->bounds.min.x && f64_at(r + 120) == n->bounds.max.z);
    ENSURE(u32le(r + 128) == n->parent && u32le(r + 132) == n->leaf_begin && u32le(r + 136) == n->leaf_end &&
           u32le(r + 140) == n->depth);
  }
  const uint8_t* bonds = records(p, ours, "bonds", tree->bond_count, BK_GLTF_BOND_RECORD_BYTES);
  for (uint32_t i = 0; i < tree->bond_count; ++i) {
    const uint8_t* r = bonds + (size_t)i * BK_GLTF_BOND_RECORD_BYTES;
    const bk_bond* b = &tree->bonds[i];
    ENSURE(u32le(r) == b->leaf_a && u32le(r + 4) == b->leaf_b && f64_at(r + 8) == b->area);
    ENSURE(f64_at(r + 16) == b->centroid.x && f64_at(r + 40) == b->normal.x && f64_at(r + 56) == b->normal.z);
  }
}

// One node's mesh: one primitive per material present, sharing welded
// vertices (no two alike) that place every triangle corner where the tree
// has it. Returns the triangles drawn.
static uint64_t check_mesh(const parsed* p, const char* path, const bk_mesh_tree* tree, uint32_t tree_index,
                           uint32_t mesh, const double world[3], uint32_t sources) {
  const bk_json_doc* d = &p->doc;
  const bk_mesh_tree_node* tn = &tree->nodes[tree_index];
  const bk_mesh* m = &tn->mesh;
  uint32_t primitives = get(p, mesh, "primitives");
  uint32_t per_material[2 * BK_MATERIAL_SOURCES_MAX] = {0};
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    per_material[export_material(m->materials[t], sources)]++;
  uint32_t present = 0;
  for (uint32_t k = 0; k < 2u * sources; ++k)
    present += per_material[k] > 0;
  ENSURE(bk_json_count(d, primitives) == present);
  uint64_t triangles = 0;
  double size = bk_v3_length(bk_v3_sub(tn->bounds.max, tn->bounds.min));
  for (uint32_t prim = bk_json_first(d, primitives); prim != BK_JSON_NONE; prim = bk_json_next(d, prim)) {
    uint32_t attributes = get(p, prim, "attributes");
    uint64_t material = get_uint(p, prim, "material");
    ENSURE(material < 2u * sources);
    uint64_t count = 0, normals = 0, uvs = 0, tangents = 0, index_count = 0;
    uint32_t component = 0;
    uint32_t position_accessor = (uint32_t)get_uint(p, attributes, "POSITION");
    const uint8_t* pos = accessor_data(p, position_accessor, &count, &component, 12);
    const uint8_t* nrm =
        accessor_data(p, (uint32_t)get_uint(p, attributes, "NORMAL"), &normals, &component, 12);
    const uint8_t* uv =
        accessor_data(p, (uint32_t)get_uint(p, attributes, "TEXCOORD_0"), &uvs, &component, 8);
    const uint8_t* tan =
        accessor_data(p, (uint32_t)get_uint(p, attributes, "TANGENT"), &tangents, &component, 16);
    ENSURE(count >= 3 && count <= m->corner_count && normals == count && uvs == count && tangents == count);
    // Attribute views are consecutive per vertex kind: a vertex's 48 bytes, compared whole.
    for (uint64_t v = 0; v + 1 < count && count < 4096; ++v)
      for (uint64_t w = v + 1; w < count; ++w)
        ENSURE_MSG(memcmp(pos + 12 * v, pos + 12 * w, 12) || memcmp(nrm + 12 * v, nrm + 12 * w, 12) ||
                       memcmp(uv + 8 * v, uv + 8 * w, 8) || memcmp(tan + 16 * v, tan + 16 * w, 16),
                   "%s: node %u: vertices %llu and %llu are alike (not welded)", path, tree_index,
                   (unsigned long long)v, (unsigned long long)w);
    // min/max are the exact extremes of the positions.
    uint32_t accessor = bk_json_at(d, get(p, 0, "accessors"), position_accessor);
    for (int k = 0; k < 3; ++k) {
      float lo = INFINITY, hi = -INFINITY;
      for (uint64_t v = 0; v < count; ++v) {
        float x = f32_at(pos + 12 * v + 4 * k);
        lo = x < lo ? x : lo;
        hi = x > hi ? x : hi;
      }
      ENSURE_MSG(number_at(p, get(p, accessor, "min"), (uint32_t)k) == lo, "%s: node %u min[%d]", path,
                 tree_index, k);
      ENSURE_MSG(number_at(p, get(p, accessor, "max"), (uint32_t)k) == hi, "%s: node %u max[%d]", path,
                 tree_index, k);
    }
    for (uint64_t v = 0; v < count; ++v) {
      float nl = 0, tl = 0;
      for (int k = 0; k < 3; ++k) {
        nl += f32_at(nrm + 12 * v + 4 * k) * f32_at(nrm + 12 * v + 4 * k);
        tl += f32_at(tan + 16 * v + 4 * k) * f32_at(tan + 16 * v + 4 * k);
      }
      ENSURE(fabsf(nl - 1) < 1e-5f && fabsf(tl - 1) < 1e-5f &&
             fabsf(fabsf(f32_at(tan + 16 * v + 12)) - 1) == 0);
    }
    const uint8_t* idx =
        accessor_data(p, (uint32_t)get_uint(p, prim, "indices"), &index_count, &component, 4);
    ENSURE(index_count % 3 == 0 && index_count / 3 == per_material[material]);
    ENSURE(component == (count > 65535 ? 5125u : 5123u));
    // The primitive's triangles are the mesh's of its material, in order: each
    // corner's vertex, placed by the node's world translation, is the tree's position and UV.
    uint64_t k = 0;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      if (export_material(m->materials[t], sources) != material) continue;
      for (int c = 0; c < 3; ++c, ++k) {
        uint32_t v = component == 5123 ? (uint32_t)(idx[2 * k] | idx[2 * k + 1] << 8) : u32le(idx + 4 * k);
        ENSURE(v < count);
        const bk_corner* corner = &m->corners[m->indices[3 * t + c]];
        bk_vec3 expected = m->positions[corner->position];
        const double e[3] = {expected.x, expected.y, expected.z};
        for (int a = 0; a < 3; ++a)
          ENSURE_SMALL(world[a] + f32_at(pos + 12 * v + 4 * a), e[a], 1e-6 * size);
        ENSURE(f32_at(uv + 8 * v) == corner->uv[0] && f32_at(uv + 8 * v + 4) == corner->uv[1]);
      }
    }
    triangles += index_count / 3;
  }
  ENSURE(triangles == m->triangle_count);
  return triangles;
}

// `sources`: the source materials the export was given (1 for the default).
// Everything about one export: the node list, the hierarchy and the
// translations, which nodes have meshes (the object drawn once unless every
// level is asked for), every mesh against the tree's, and the extras.
static void check_export(const bk_mesh_tree* tree, const char* path, bool glb, bk_gltf_levels levels,
                         uint32_t sources) {
  parsed p;
  parse_export(path, glb, &p);
  const bk_json_doc* d = &p.doc;
  bool flat = levels == BK_GLTF_LEVELS_LEAVES, every_mesh = levels == BK_GLTF_LEVELS_ALL;
  uint32_t nodes = get(&p, 0, "nodes");
  uint32_t node_count = bk_json_count(d, nodes);
  ENSURE_MSG(node_count == (flat ? tree->leaf_count : tree->node_count), "%s: %u nodes", path, node_count);
  ENSURE(bk_json_count(d, get(&p, 0, "meshes")) == (every_mesh ? tree->node_count : tree->leaf_count));
  ENSURE(bk_json_count(d, get(&p, 0, "materials")) == 2u * sources);
  uint32_t roots = get(&p, bk_json_at(d, get(&p, 0, "scenes"), 0), "nodes");
  ENSURE(bk_json_count(d, roots) == (flat ? tree->leaf_count : 1u));

  // World translation of each glTF node: its own plus its parent's (parents come first).
  double* world = bk_calloc(3u * node_count, sizeof(double));
  uint32_t* parent = bk_alloc(sizeof(uint32_t) * node_count);
  for (uint32_t i = 0; i < node_count; ++i)
    parent[i] = BK_NULL_INDEX;
  for (uint32_t i = 0; i < node_count; ++i) {
    uint32_t n = bk_json_at(d, nodes, i);
    uint32_t children = bk_json_get(d, n, "children");
    for (uint32_t c = bk_json_first(d, children); c != BK_JSON_NONE; c = bk_json_next(d, c)) {
      uint64_t child = 0;
      ENSURE(bk_json_uint(d, c, node_count - 1, &child) && child > i && parent[child] == BK_NULL_INDEX);
      parent[child] = i;
    }
  }
  uint64_t drawn = 0, leaf_triangles = 0;
  bool* mesh_used = bk_calloc(node_count, sizeof(bool));
  for (uint32_t i = 0; i < node_count; ++i) {
    uint32_t n = bk_json_at(d, nodes, i);
    uint32_t tree_index = flat ? tree->leaf_nodes[i] : i;
    const bk_mesh_tree_node* tn = &tree->nodes[tree_index];
    if (!tn->child_count) leaf_triangles += tn->mesh.triangle_count;
    ENSURE(!flat || parent[i] == BK_NULL_INDEX);
    ENSURE(flat || (i == 0 ? parent[i] == BK_NULL_INDEX : parent[i] == tn->parent));
    char name[64];
    if (tn->child_count)
      snprintf(name, sizeof name, "node_%u", tree_index);
    else
      snprintf(name, sizeof name, "fragment_%u", tn->leaf_begin);
    ENSURE_MSG(bk_json_string_is(d, get(&p, n, "name"), name), "node %u is not named %s", i, name);
    uint32_t translation = get(&p, n, "translation");
    for (int k = 0; k < 3; ++k)
      world[3 * i + k] = number_at(&p, translation, (uint32_t)k) +
                         (parent[i] == BK_NULL_INDEX ? 0 : world[3 * parent[i] + k]);
    bk_vec3 centroid = bk_mesh_tree_mass(tree, tn->moments).centroid;
    ENSURE_SMALL(world[3 * i + 0], centroid.x, 1e-12);
    ENSURE_SMALL(world[3 * i + 1], centroid.y, 1e-12);
    ENSURE_SMALL(world[3 * i + 2], centroid.z, 1e-12);
    // Extras: node index, leaf range, volume.
    uint32_t extras = get(&p, get(&p, n, "extras"), "breakables");
    ENSURE(get_uint(&p, extras, "node") == tree_index);
    uint32_t leaves = get(&p, extras, "leaves");
    ENSURE(number_at(&p, leaves, 0) == tn->leaf_begin && number_at(&p, leaves, 1) == tn->leaf_end);
    double volume = 0;
    ENSURE(bk_json_number(d, get(&p, extras, "volume"), &volume) && volume == tn->moments.v);
    ENSURE(bk_json_get(d, extras, "moments") == BK_JSON_NONE); // in the node records

    // A mesh on the fragments only, unless every level is asked for.
    uint32_t mesh_value = bk_json_get(d, n, "mesh");
    ENSURE_MSG((mesh_value != BK_JSON_NONE) == (every_mesh || tn->child_count == 0), "%s: node %u's mesh",
               path, i);
    if (mesh_value == BK_JSON_NONE) continue;
    uint64_t mesh_index = 0;
    ENSURE(bk_json_uint(d, mesh_value, node_count - 1, &mesh_index) && !mesh_used[mesh_index]);
    mesh_used[mesh_index] = true;
    uint32_t mesh = bk_json_at(d, get(&p, 0, "meshes"), (uint32_t)mesh_index);
    ENSURE(bk_json_string_is(d, get(&p, mesh, "name"), name));
    drawn += check_mesh(&p, path, tree, tree_index, mesh, world + 3 * i, sources);
  }
  // What an importer draws: the object once (its fragments), or every level.
  uint64_t all_triangles = 0;
  for (uint32_t i = 0; i < tree->node_count; ++i)
    all_triangles += tree->nodes[i].mesh.triangle_count;
  ENSURE_MSG(drawn == (every_mesh ? all_triangles : leaf_triangles), "%s: %llu triangles drawn", path,
             (unsigned long long)drawn);
  uint32_t ours = get(&p, get(&p, get(&p, 0, "asset"), "extras"), "breakables");
  ENSURE(get_uint(&p, ours, "version") == BK_GLTF_EXTRAS_VERSION);
  ENSURE(bk_json_string_is(d, get(&p, ours, "levels"), bk_gltf_levels_name(levels)));
  check_records(&p, tree, ours);
  uint32_t fracture = get(&p, ours, "fracture");
  ENSURE(bk_json_string_is(d, get(&p, fracture, "pattern"), bk_fracture_pattern_name(tree->desc.pattern)));
  ENSURE(get_uint(&p, fracture, "pieces") == tree->desc.pieces &&
         get_uint(&p, fracture, "seed") == tree->desc.seed);
  ENSURE(get_uint(&p, ours, "node_count") == tree->node_count);
  free(mesh_used);
  free(world);
  free(parent);
  parsed_free(&p);
}

// ---------------------------------------------------------------- tests

static void round_trip(const bk_mesh_tree* tree, const char* path) {
  bk_mesh_tree back = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_load_gltf(path, &back, &err), "%s", err.message);
  uint8_t *a = NULL, *b = NULL;
  size_t a_size = 0, b_size = 0;
  ENSURE(bk_mesh_tree_save_memory(tree, "tree", &a, &a_size, &err));
  ENSURE(bk_mesh_tree_save_memory(&back, "back", &b, &b_size, &err));
  ENSURE_MSG(a_size == b_size && memcmp(a, b, a_size) == 0, "%s: the loaded tree is not byte-identical",
             path);
  ENSURE(back.leaf_count == tree->leaf_count && back.bond_count == tree->bond_count);
  for (uint32_t l = 0; l < tree->leaf_count; ++l)
    ENSURE(bk_mesh_tree_leaf(&back, l)->moments.v == bk_mesh_tree_leaf(tree, l)->moments.v);
  ENSURE(memcmp(back.bonds, tree->bonds, sizeof(bk_bond) * tree->bond_count) == 0);
  free(a);
  free(b);
  bk_mesh_tree_free(&back);
}

// The corners of a mesh's triangles as distinct exported vertices would be:
// how many vertices the export has without welding.
static void expect_refused(const void* data, size_t size, const char* name, const char* needle);

static uint32_t leaf_corners(const bk_mesh_tree* tree) {
  uint32_t corners = 0;
  for (uint32_t l = 0; l < tree->leaf_count; ++l)
    corners += bk_mesh_tree_leaf(tree, l)->mesh.corner_count;
  return corners;
}

// Vertices of the export (the POSITION view's length / 12).
static uint64_t exported_vertices(const char* path) {
  parsed p;
  parse_export(path, true, &p);
  uint64_t n = get_uint(&p, bk_json_at(&p.doc, get(&p, 0, "bufferViews"), 0), "byteLength") / 12;
  parsed_free(&p);
  return n;
}

static void test_exports(void) {
  bk_mesh_tree tree = {0};
  build_tree(16, &tree);
  static const char* const names[3] = {"hierarchy", "leaves", "all"};
  static const bk_gltf_levels levels[3] = {BK_GLTF_LEVELS_HIERARCHY, BK_GLTF_LEVELS_LEAVES,
                                           BK_GLTF_LEVELS_ALL};
  char paths[3][2][256];
  for (int l = 0; l < 3; ++l)
    for (int glb = 1; glb >= 0; --glb) {
      snprintf(paths[l][glb], sizeof paths[l][glb], BK_TEST_TMP "/cube16_%s.%s", names[l],
               glb ? "glb" : "gltf");
      bk_gltf_def def = bk_default_gltf_def();
      def.levels = levels[l];
      bk_error err = {{0}};
      ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, paths[l][glb], &def, &err), "%s", err.message);
      check_export(&tree, paths[l][glb], glb, def.levels, 1);
      round_trip(&tree, paths[l][glb]);
    }
  // Saving twice gives the same bytes; NULL def = the defaults (the hierarchy).
  size_t a_size = 0, b_size = 0;
  uint8_t* a = read_all(paths[0][1], &a_size);
  bk_error err = {{0}};
  ENSURE(bk_mesh_tree_save_gltf(&tree, paths[0][1], NULL, &err));
  uint8_t* b = read_all(paths[0][1], &b_size);
  ENSURE(a_size == b_size && memcmp(a, b, a_size) == 0);
  free(a);
  // Without the tree: the same meshes and records, smaller by the .mtree
  // bytes, and a one-line refusal to load back.
  uint8_t* mtree = NULL;
  size_t mtree_size = 0;
  ENSURE(bk_mesh_tree_save_memory(&tree, "tree", &mtree, &mtree_size, &err));
  free(mtree);
  bk_gltf_def def = bk_default_gltf_def();
  def.embed_tree = false;
  const char* shipped = BK_TEST_TMP "/cube16_shipped.glb";
  ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, shipped, &def, &err), "%s", err.message);
  check_export(&tree, shipped, true, def.levels, 1);
  a = read_all(shipped, &a_size);
  ENSURE_MSG(a_size < b_size && b_size - a_size >= mtree_size && b_size - a_size < mtree_size + 128,
             "%zu bytes with the tree, %zu without, the tree is %zu", b_size, a_size, mtree_size);
  ENSURE(!strstr((const char*)a, "\"mtree\""));
  expect_refused(a, a_size, "shipped.glb", "shipped.glb: exported without its mesh tree (--gltf-no-tree)");
  free(a);
  free(b);
  bk_mesh_tree_free(&tree);
  // A Voronoi tree (inner nodes are groups of cells; its pattern is
  // recorded): each cell triangle has its own corners, welded in the export.
  build_pattern_tree(16, BK_PATTERN_VORONOI, &tree);
  const char* voronoi = BK_TEST_TMP "/cube16_voronoi.glb";
  ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, voronoi, NULL, &err), "%s", err.message);
  check_export(&tree, voronoi, true, BK_GLTF_LEVELS_HIERARCHY, 1);
  round_trip(&tree, voronoi);
  uint64_t vertices = exported_vertices(voronoi);
  ENSURE_MSG(vertices * 3 < leaf_corners(&tree) * 2, "%llu vertices for %u corners: not welded",
             (unsigned long long)vertices, leaf_corners(&tree));
  bk_mesh_tree_free(&tree);
}

// The view's bytes as a reader gets them: a compressed view decoded with
// meshoptimizer's decoder (*owned then holds them).
static const uint8_t* view_bytes(const parsed* p, uint32_t view_index, uint64_t* length, uint8_t** owned) {
  uint32_t view = bk_json_at(&p->doc, get(p, 0, "bufferViews"), view_index);
  *length = get_uint(p, view, "byteLength");
  *owned = NULL;
  uint32_t ext = bk_json_get(&p->doc, bk_json_get(&p->doc, view, "extensions"), "EXT_meshopt_compression");
  if (ext == BK_JSON_NONE) return p->bin + get_uint(p, view, "byteOffset");
  ENSURE(get_uint(p, view, "buffer") == 1 && get_uint(p, ext, "buffer") == 0);
  ENSURE(bk_json_string_is(&p->doc, get(p, ext, "mode"), "ATTRIBUTES"));
  uint64_t count = get_uint(p, ext, "count"), stride = get_uint(p, ext, "byteStride");
  uint64_t offset = get_uint(p, ext, "byteOffset"), packed = get_uint(p, ext, "byteLength");
  ENSURE(count * stride == *length && offset + packed <= p->bin_size && packed < *length);
  *owned = bk_alloc(*length);
  ENSURE(meshopt_decodeVertexBuffer(*owned, count, stride, p->bin + offset, packed) == 0);
  return *owned;
}

// Compressed: the same vertices bit for bit (decoded), the file smaller, the
// extension required, and the tree loads back; off by default.
static void test_meshopt(void) {
  bk_mesh_tree tree = {0};
  build_noisy_voronoi_tree(24, &tree);
  bk_gltf_def def = bk_default_gltf_def();
  ENSURE(!def.meshopt_compression);
  bk_error err = {{0}};
  const char* plain_path = BK_TEST_TMP "/meshopt_plain.glb";
  const char* packed_path = BK_TEST_TMP "/meshopt.glb";
  ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, plain_path, &def, &err), "%s", err.message);
  def.meshopt_compression = true;
  for (int glb = 0; glb < 2; ++glb) {
    const char* path = glb ? packed_path : BK_TEST_TMP "/meshopt.gltf";
    ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, &def, &err), "%s", err.message);
    round_trip(&tree, path);
  }
  parsed plain, packed;
  parse_export(plain_path, true, &plain);
  parse_export(packed_path, true, &packed);
  ENSURE(bk_json_string_is(&packed.doc, bk_json_at(&packed.doc, get(&packed, 0, "extensionsRequired"), 0),
                           "EXT_meshopt_compression"));
  ENSURE(bk_json_get(&plain.doc, 0, "extensionsRequired") == BK_JSON_NONE);
  uint32_t fallback = bk_json_at(&packed.doc, get(&packed, 0, "buffers"), 1);
  ENSURE(bk_json_get(&packed.doc, fallback, "uri") == BK_JSON_NONE);
  uint32_t views = bk_json_count(&plain.doc, get(&plain, 0, "bufferViews"));
  ENSURE(views == bk_json_count(&packed.doc, get(&packed, 0, "bufferViews")));
  for (uint32_t v = 0; v < views; ++v) {
    uint64_t a_length = 0, b_length = 0;
    uint8_t *a_owned = NULL, *b_owned = NULL;
    const uint8_t* a = view_bytes(&plain, v, &a_length, &a_owned);
    const uint8_t* b = view_bytes(&packed, v, &b_length, &b_owned);
    ENSURE_MSG(v >= 4 || b_owned, "view %u is not compressed", v);
    ENSURE_MSG(a_length == b_length && memcmp(a, b, (size_t)a_length) == 0, "view %u differs once decoded",
               v);
    free(a_owned);
    free(b_owned);
  }
  printf("  %zu bytes compressed, %zu plain\n", packed.file_size, plain.file_size);
  ENSURE(packed.file_size < plain.file_size);
  parsed_free(&plain);
  parsed_free(&packed);
  bk_mesh_tree_free(&tree);
}

// Two boxes apart, of source materials 0 and 3 (x < 0 and x > 0): every cut
// face takes the material of the box it cuts, so each leaf is of one source
// material, its cut faces that material's interior.
static void build_two_material_tree(uint32_t pieces, bk_mesh_tree* tree) {
  bk_mesh a = {0}, b = {0}, both = {0};
  bk_shape_build(BK_SHAPE_CUBE, &a);
  bk_shape_build(BK_SHAPE_CUBE, &b);
  for (uint32_t i = 0; i < a.position_count; ++i) {
    a.positions[i] = bk_v3_add(a.positions[i], bk_v3(-1.0, 0, 0));
    b.positions[i] = bk_v3_add(bk_v3_scale(b.positions[i], 1.5), bk_v3(1.5, 0, 0));
  }
  for (uint32_t t = 0; t < b.triangle_count; ++t)
    b.materials[t] = bk_material_id(3, false);
  bk_mesh_append(&both, &a);
  bk_mesh_append(&both, &b);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_build(&both, &desc, tree, &err), "%s", err.message);
  bk_mesh_free(&a);
  bk_mesh_free(&b);
  bk_mesh_free(&both);
}

// Four default materials with these names (sources 0 and 3 are the boxes').
static void name_materials(bk_gltf_material list[4], const char* const names[4]) {
  for (int i = 0; i < 4; ++i) {
    list[i] = bk_default_gltf_material();
    list[i].name = names[i];
  }
}

static void test_two_materials(void) {
  bk_mesh_tree tree = {0};
  build_two_material_tree(24, &tree);
  uint32_t caps[2] = {0, 0}; // cut-face triangles of sources 0 and 3
  for (uint32_t l = 0; l < tree.leaf_count; ++l) {
    const bk_mesh* m = &bk_mesh_tree_leaf(&tree, l)->mesh;
    bool right = m->positions[0].x > 0.0;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      ENSURE_MSG(bk_material_source(m->materials[t]) == (right ? 3u : 0u), "leaf %u triangle %u: material %u",
                 l, t, m->materials[t]);
      if (bk_material_is_interior(m->materials[t])) caps[right]++;
    }
  }
  ENSURE(caps[0] > 0 && caps[1] > 0);

  // Exported with four materials, the image of the first written in once
  // though two materials use it; with one, source 3 falls back to source 0.
  size_t png_size = 0;
  uint8_t* png = read_all(BK_ASSET_DIR "/textures/stone_albedo.png", &png_size);
  bk_gltf_material list[4];
  name_materials(list, (const char* const[4]){"left", "unused", "spare", "right"});
  list[0].texture = (bk_gltf_image){.data = png, .size = png_size};
  list[3].texture = list[0].texture;
  list[3].interior_texture = (bk_gltf_image){.uri = "right_interior.png"};
  list[3].base_color[1] = 0.5f;
  bk_gltf_def def = bk_default_gltf_def();
  def.materials = list;
  def.material_count = 4;
  bk_error err = {{0}};
  for (int glb = 0; glb < 2; ++glb) {
    const char* path = glb ? BK_TEST_TMP "/two.glb" : BK_TEST_TMP "/two.gltf";
    ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, &def, &err), "%s", err.message);
    check_export(&tree, path, glb, def.levels, 4);
    round_trip(&tree, path);
    parsed p;
    parse_export(path, glb, &p);
    uint32_t materials = get(&p, 0, "materials");
    ENSURE(bk_json_string_is(&p.doc, get(&p, bk_json_at(&p.doc, materials, 6), "name"), "right"));
    ENSURE(bk_json_string_is(&p.doc, get(&p, bk_json_at(&p.doc, materials, 7), "name"), "right_interior"));
    uint32_t color =
        get(&p, get(&p, bk_json_at(&p.doc, materials, 6), "pbrMetallicRoughness"), "baseColorFactor");
    ENSURE(number_at(&p, color, 1) == 0.5);
    uint32_t images = get(&p, 0, "images");
    ENSURE(bk_json_count(&p.doc, images) == 2);
    uint32_t image = bk_json_at(&p.doc, images, 0);
    ENSURE(bk_json_string_is(&p.doc, get(&p, image, "mimeType"), "image/png"));
    uint32_t view =
        bk_json_at(&p.doc, get(&p, 0, "bufferViews"), (uint32_t)get_uint(&p, image, "bufferView"));
    uint64_t offset = get_uint(&p, view, "byteOffset");
    ENSURE(get_uint(&p, view, "byteLength") == png_size && offset % 4 == 0 &&
           offset + png_size <= p.bin_size);
    ENSURE_MSG(memcmp(p.bin + offset, png, png_size) == 0, "%s: the image bytes differ from the file", path);
    parsed_free(&p);
  }
  def.material_count = 1;
  ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/two_one.glb", &def, &err), "%s", err.message);
  check_export(&tree, BK_TEST_TMP "/two_one.glb", true, def.levels, 1);
  free(png);
  bk_mesh_tree_free(&tree);
}

// A refusal: false, one line naming the file, the output zeroed.
static void expect_refused(const void* data, size_t size, const char* name, const char* needle) {
  bk_mesh_tree out;
  memset(&out, 0xab, sizeof out);
  bk_error err = {{0}};
  ENSURE_MSG(!bk_mesh_tree_load_gltf_memory(data, size, name, &out, &err), "%s was accepted", name);
  static const bk_mesh_tree zero = {0};
  ENSURE(memcmp(&out, &zero, sizeof out) == 0);
  ENSURE(err.message[0] && !strchr(err.message, '\n'));
  ENSURE_MSG(strncmp(err.message, name, strlen(name)) == 0, "%s", err.message);
  ENSURE_MSG(!needle || strstr(err.message, needle), "'%s' lacks '%s'", err.message, needle);
}

static void test_damaged(void) {
  bk_mesh_tree tree = {0};
  build_tree(4, &tree);
  const char* glb_path = BK_TEST_TMP "/damaged.glb";
  const char* gltf_path = BK_TEST_TMP "/damaged.gltf";
  bk_error err = {{0}};
  ENSURE(bk_mesh_tree_save_gltf(&tree, glb_path, NULL, &err) &&
         bk_mesh_tree_save_gltf(&tree, gltf_path, NULL, &err));
  size_t size = 0, text_size = 0;
  uint8_t* glb = read_all(glb_path, &size);
  uint8_t* text = read_all(gltf_path, &text_size);
  // Every truncation of the GLB is refused.
  for (size_t cut = 0; cut < size; cut += (cut < 64 ? 1 : 97))
    expect_refused(glb, cut, "cut.glb", NULL);
  expect_refused(glb, 11, "cut.glb", "truncated GLB header");
  expect_refused(glb, size - 1, "cut.glb", "truncated");
  for (size_t cut = 0; cut < text_size; cut += 1 + text_size / 200)
    expect_refused(text, cut, "cut.gltf", NULL);
  uint8_t* copy = bk_alloc(size);
  // A flipped byte in the embedded tree (the buffer's end) fails its checksum.
  memcpy(copy, glb, size);
  copy[size - 8] ^= 0x40;
  expect_refused(copy, size, "flip.glb", "checksum");
  // The header's length, version and chunk type.
  memcpy(copy, glb, size);
  copy[8] ^= 4;
  expect_refused(copy, size, "length.glb", "GLB header says");
  memcpy(copy, glb, size);
  copy[4] = 1;
  expect_refused(copy, size, "version.glb", "GLB version 1");
  memcpy(copy, glb, size);
  copy[16] = 'X';
  expect_refused(copy, size, "chunk.glb", "not JSON");
  // The JSON without our extras, with a wrong view or buffer index, nested too deeply.
  const char* foreign = "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[]}";
  expect_refused(
      foreign, strlen(foreign), "model.glb",
      "model.glb: not a Breakables export (no asset.extras.breakables); fracture it with --mesh instead");
  const char* old = "{\"asset\":{\"version\":\"1.0\"}}";
  expect_refused(old, strlen(old), "old.gltf", "not a glTF 2.0 file");
  const char* bad_view =
      "{\"asset\":{\"version\":\"2.0\",\"extras\":{\"breakables\":{\"version\":1,\"mtree\":{"
      "\"bufferView\":7}}}},\"bufferViews\":[]}";
  expect_refused(bad_view, strlen(bad_view), "view.gltf", "bufferView 7 is not among the 0");
  const char* big_view =
      "{\"asset\":{\"version\":\"2.0\",\"extras\":{\"breakables\":{\"version\":1,\"mtree\":{"
      "\"bufferView\":0}}}},\"bufferViews\":[{\"buffer\":0,\"byteOffset\":4,\"byteLength\":"
      "18446744073709551615}],\"buffers\":[{\"byteLength\":8,\"uri\":\"" BK_GLTF_DATA_URI "AAAAAAAAAAA=\"}]}";
  expect_refused(big_view, strlen(big_view), "span.gltf", "spans bytes");
  const char* bad_b64 =
      "{\"asset\":{\"version\":\"2.0\",\"extras\":{\"breakables\":{\"version\":1,\"mtree\":{"
      "\"bufferView\":0}}}},\"bufferViews\":[{\"buffer\":0,\"byteLength\":1}],\"buffers\":[{"
      "\"byteLength\":1,\"uri\":\"" BK_GLTF_DATA_URI "A*==\"}]}";
  expect_refused(bad_b64, strlen(bad_b64), "b64.gltf", "not valid base64");
  char deep[4000];
  memset(deep, '[', sizeof deep);
  memcpy(deep, "{\"a\":", 5);
  expect_refused(deep, sizeof deep, "deep.gltf", "nested too deeply");
  expect_refused("{\"a\":1,}", 8, "comma.gltf", "expected a key at byte 7");
  expect_refused("\x01\x02", 2, "junk.glb", "not glTF");
  // Counts in the JSON that are not the embedded tree's.
  char* edited = bk_alloc(text_size + 1);
  memcpy(edited, text, text_size);
  edited[text_size] = '\0';
  char* count = strstr(edited, "\"leaf_count\":4");
  ENSURE(count);
  count[strlen("\"leaf_count\":")] = '5';
  expect_refused(edited, text_size, "counts.gltf", "are not the embedded tree's");
  // A missing file.
  bk_mesh_tree out = {0};
  ENSURE(!bk_mesh_tree_load_gltf(BK_TEST_TMP "/no_such.glb", &out, &err) &&
         strstr(err.message, "no_such.glb"));
  free(edited);
  free(copy);
  free(glb);
  free(text);
  bk_mesh_tree_free(&tree);
}

static void test_save_errors(void) {
  bk_mesh_tree tree = {0};
  build_tree(2, &tree);
  bk_error err = {{0}};
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.obj", NULL, &err) && strstr(err.message, ".glb"));
  bk_gltf_def def = bk_default_gltf_def();
  bk_gltf_material material = bk_default_gltf_material();
  def.materials = &material;
  def.material_count = 1;
  material.name = "";
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.glb", &def, &err) &&
         strstr(err.message, "materials[0].name must be 1 to 63 bytes"));
  material = bk_default_gltf_material();
  material.base_color[2] = NAN;
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.glb", &def, &err) &&
         strstr(err.message, "materials[0].base_color[2] must be in [0, 1]"));
  material = bk_default_gltf_material();
  material.interior_texture = (bk_gltf_image){.data = "GIF89a..", .size = 8};
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.glb", &def, &err) &&
         strstr(err.message, "materials[0].interior_texture.data is neither PNG nor JPEG"));
  material.interior_texture = (bk_gltf_image){.data = "\xff\xd8\xff", .size = 3, .uri = "a.jpg"};
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.glb", &def, &err) &&
         strstr(err.message, "materials[0].interior_texture has both data and uri"));
  def.materials = NULL;
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.glb", &def, &err) &&
         strstr(err.message, "material_count is 1 but materials is NULL"));
  def.material_count = BK_MATERIAL_SOURCES_MAX + 1;
  def.materials = &material;
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.glb", &def, &err) &&
         strstr(err.message, "material_count is 129, more than 128"));
  def = bk_default_gltf_def();
  def.density = 0;
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.glb", &def, &err) && strstr(err.message, "density"));
  def = bk_default_gltf_def();
  def.levels = (bk_gltf_levels)7;
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.glb", &def, &err) && strstr(err.message, "levels"));
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/no_dir/x.glb", NULL, &err) &&
         strstr(err.message, "no_dir"));
  tree.nodes[0].parent = 3; // an invalid tree is never written
  ENSURE(!bk_mesh_tree_save_gltf(&tree, BK_TEST_TMP "/x.glb", NULL, &err) &&
         strstr(err.message, "invalid mesh tree"));
  tree.nodes[0].parent = BK_NULL_INDEX;
  bk_mesh_tree_free(&tree);
}

// ---------------------------------------------------------------- the CLI
#ifdef BK_BREAKABLES_EXE
#define RUN_STDERR_PATH BK_TEST_TMP "/test_gltf.stderr"
#include "run_exe.h"

static void test_cli(void) {
  run_result* r =
      run("fracture --mesh cube --pieces 8 --export-gltf '" BK_TEST_TMP "/cli.glb' --gltf-levels leaves "
          "--json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(strstr(r->out, "\"export_gltf\": \"" BK_TEST_TMP "/cli.glb\", \"tree_hash\": \""));
  bk_mesh_tree tree = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_load_gltf(BK_TEST_TMP "/cli.glb", &tree, &err), "%s", err.message);
  ENSURE(tree.leaf_count == 8);
  bk_mesh_tree_free(&tree);
  r = run("fracture --mesh cube --pieces 2 --json");
  ENSURE(r->status == 0 && strstr(r->out, "\"export_gltf\": null, \"tree_hash\": \""));
  r = run("fracture --mesh cube --pieces 2 --export-gltf '" BK_TEST_TMP "/cli.gltf'");
  ENSURE(r->status == 0 && strstr(r->out, "exported " BK_TEST_TMP "/cli.gltf"));
  r = run("fracture --mesh cube --pieces 2 --export-gltf '" BK_TEST_TMP "/cli.gltf' --gltf-levels some");
  ENSURE(r->status == 2 && strstr(r->err, "--gltf-levels must be 'hierarchy', 'leaves' or 'all'") &&
         count_lines(r->err) == 1);
  r = run("fracture --mesh cube --pieces 2 --export-gltf");
  ENSURE(r->status == 2 && strstr(r->err, "--export-gltf needs a value"));
  r = run("fracture --mesh cube --pieces 2 --export-gltf '" BK_TEST_TMP "/cli.fbx'");
  ENSURE(r->status == 1 && strstr(r->err, "must end in .glb") && count_lines(r->err) == 1);
  r = run("fracture --help");
  ENSURE(strstr(r->out, "--export-gltf FILE.glb|FILE.gltf") &&
         strstr(r->out, "--gltf-levels hierarchy|leaves|all") && strstr(r->out, "--gltf-no-tree"));
  // A shipped game's file: no tree inside, so it does not load back (one line saying why).
  r = run("fracture --mesh cube --pieces 8 --export-gltf '" BK_TEST_TMP "/cli_shipped.glb' --gltf-no-tree");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(!bk_mesh_tree_load_gltf(BK_TEST_TMP "/cli_shipped.glb", &tree, &err) &&
         strstr(err.message, "exported without its mesh tree"));
}
#endif

// ---------------------------------------------------------------- exports for the JS checks

static void copy_file(const char* from, const char* to) {
  size_t size = 0;
  uint8_t* data = read_all(from, &size);
  write_all(to, data, size);
  free(data);
}

// The JS checks' expected counts of an export: glTF nodes, fragments, meshes
// and the triangles an importer draws (the object once: its fragments'
// triangles; every level's with BK_GLTF_LEVELS_ALL).
static void print_expected(const char* path, const bk_mesh_tree* tree, bk_gltf_levels levels) {
  uint64_t leaf_triangles = 0, all_triangles = 0;
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    all_triangles += tree->nodes[i].mesh.triangle_count;
    if (!tree->nodes[i].child_count) leaf_triangles += tree->nodes[i].mesh.triangle_count;
  }
  bool all = levels == BK_GLTF_LEVELS_ALL;
  printf("%s --nodes %u --leaves %u --meshes %u --triangles %llu", path,
         levels == BK_GLTF_LEVELS_LEAVES ? tree->leaf_count : tree->node_count, tree->leaf_count,
         all ? tree->node_count : tree->leaf_count,
         (unsigned long long)(all ? all_triangles : leaf_triangles));
}

static int export_for_js(const char* dir) {
  bk_mesh_tree tree = {0};
  build_tree(16, &tree);
  char path[1024];
  static const char* const names[3] = {"hierarchy", "leaves", "all"};
  static const bk_gltf_levels levels[3] = {BK_GLTF_LEVELS_HIERARCHY, BK_GLTF_LEVELS_LEAVES,
                                           BK_GLTF_LEVELS_ALL};
  for (int l = 0; l < 3; ++l)
    for (int glb = 0; glb < 2; ++glb) {
      snprintf(path, sizeof path, "%s/cube16_%s.%s", dir, names[l], glb ? "glb" : "gltf");
      bk_gltf_def def = bk_default_gltf_def();
      def.levels = levels[l];
      bk_error err = {{0}};
      ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, &def, &err), "%s", err.message);
      print_expected(path, &tree, def.levels);
      printf(" --materials 2\n");
    }
  {
    snprintf(path, sizeof path, "%s/cube16_shipped.glb", dir);
    bk_gltf_def def = bk_default_gltf_def();
    def.embed_tree = false;
    bk_error err = {{0}};
    ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, &def, &err), "%s", err.message);
    print_expected(path, &tree, def.levels);
    printf(" --materials 2 --tree 0\n");
  }
  {
    snprintf(path, sizeof path, "%s/cube16_meshopt.glb", dir);
    bk_gltf_def def = bk_default_gltf_def();
    def.meshopt_compression = true;
    bk_error err = {{0}};
    ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, &def, &err), "%s", err.message);
    print_expected(path, &tree, def.levels);
    printf(" --materials 2 --meshopt 1\n");
  }
  // Textured, with a material name and a path that needs escaping.
  snprintf(path, sizeof path, "%s/textures", dir);
  mkdir(path, 0777);
  snprintf(path, sizeof path, "%s/textures/stone albedo.png", dir);
  copy_file(BK_ASSET_DIR "/textures/stone_albedo.png", path);
  snprintf(path, sizeof path, "%s/textures/stone_interior.png", dir);
  copy_file(BK_ASSET_DIR "/textures/stone_interior.png", path);
  bk_gltf_def def = bk_default_gltf_def();
  bk_gltf_material stone = bk_default_gltf_material();
  stone.name = "stone";
  stone.texture.uri = "textures/stone albedo.png";
  stone.interior_texture.uri = "textures/stone_interior.png";
  def.materials = &stone;
  def.material_count = 1;
  snprintf(path, sizeof path, "%s/cube16_textured.glb", dir);
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, &def, &err), "%s", err.message);
  print_expected(path, &tree, def.levels);
  printf(" --materials 2 --material stone --textures 2\n");
  bk_mesh_tree_free(&tree);
  // Two source materials, the images inside the file (both kinds of file).
  build_two_material_tree(24, &tree);
  size_t png_size = 0, jpeg_size = 0;
  uint8_t* png = read_all(BK_ASSET_DIR "/textures/brick_albedo.png", &png_size);
  uint8_t* interior = read_all(BK_ASSET_DIR "/textures/brick_interior.png", &jpeg_size);
  bk_gltf_material list[4];
  name_materials(list, (const char* const[4]){"plaster", "unused", "spare", "brick"});
  list[3].texture = (bk_gltf_image){.data = png, .size = png_size};
  list[3].interior_texture = (bk_gltf_image){.data = interior, .size = jpeg_size};
  def.materials = list;
  def.material_count = 4;
  // three.js sees the materials the meshes use: a source's surface and its cut faces.
  bool used[8] = {false};
  for (uint32_t n = 0; n < tree.node_count; ++n)
    for (uint32_t t = 0; t < tree.nodes[n].mesh.triangle_count && !tree.nodes[n].child_count; ++t)
      used[export_material(tree.nodes[n].mesh.materials[t], 4)] = true;
  uint32_t used_count = 0;
  for (int i = 0; i < 8; ++i)
    used_count += used[i];
  for (int glb = 0; glb < 2; ++glb) {
    snprintf(path, sizeof path, "%s/two_materials.%s", dir, glb ? "glb" : "gltf");
    ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, &def, &err), "%s", err.message);
    print_expected(path, &tree, def.levels);
    printf(" --materials %u --material plaster,brick --textures 2\n", used_count);
  }
  free(png);
  free(interior);
  bk_mesh_tree_free(&tree);
  // A noisy Voronoi tree: inner nodes are groups of cells, cut faces curved.
  build_noisy_voronoi_tree(48, &tree);
  snprintf(path, sizeof path, "%s/voronoi48.glb", dir);
  ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, NULL, &err), "%s", err.message);
  print_expected(path, &tree, BK_GLTF_LEVELS_HIERARCHY);
  printf(" --materials 2\n");
  bk_mesh_tree_free(&tree);
  // A tree refined at run time, as a saved game keeps it.
  build_refined_tree(&tree);
  snprintf(path, sizeof path, "%s/refined.glb", dir);
  ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, NULL, &err), "%s", err.message);
  print_expected(path, &tree, BK_GLTF_LEVELS_HIERARCHY);
  printf(" --materials 2\n");
  bk_mesh_tree_free(&tree);
  return 0;
}

// A refined tree saves to .glb and loads back whole: every node, leaf and
// bond, valid.
static void test_refined(void) {
  bk_mesh_tree tree = {0}, back = {0};
  build_refined_tree(&tree);
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_validate(&tree, &err), "%s", err.message);
  const char* path = BK_TEST_TMP "/refined.glb";
  ENSURE_MSG(bk_mesh_tree_save_gltf(&tree, path, NULL, &err), "%s", err.message);
  ENSURE_MSG(bk_mesh_tree_load_gltf(path, &back, &err), "%s", err.message);
  ENSURE(back.node_count == tree.node_count && back.leaf_count == tree.leaf_count &&
         back.bond_count == tree.bond_count && back.max_depth == tree.max_depth);
  for (uint32_t j = 0; j < tree.bond_count; ++j)
    ENSURE(back.bonds[j].leaf_a == tree.bonds[j].leaf_a && back.bonds[j].leaf_b == tree.bonds[j].leaf_b &&
           back.bonds[j].area == tree.bonds[j].area);
  for (uint32_t i = 0; i < tree.node_count; ++i)
    ENSURE(back.nodes[i].mesh.triangle_count == tree.nodes[i].mesh.triangle_count &&
           back.nodes[i].parent == tree.nodes[i].parent);
  bk_mesh_tree_free(&back);
  bk_mesh_tree_free(&tree);
}

int main(int argc, char** argv) {
  if (argc == 3 && strcmp(argv[1], "--export") == 0) return export_for_js(argv[2]);
  RUN(test_exports);
  RUN(test_refined);
  RUN(test_damaged);
  RUN(test_save_errors);
  RUN(test_two_materials);
  RUN(test_meshopt);
#ifdef BK_BREAKABLES_EXE
  RUN(test_cli);
#endif
  return 0;
}
