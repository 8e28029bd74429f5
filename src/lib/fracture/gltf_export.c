// glTF 2.0 export of a mesh tree (bk_mesh_tree_save_gltf); the layout and the
// extras are described in docs/gltf.md.
//
// One binary buffer holds, in order: the vertices of every node that has a
// mesh (POSITION, NORMAL, TEXCOORD_0 and TANGENT: four buffer views, one per
// attribute, each node's vertices a run within them), the indices (one view;
// a node's runs per material, uint16 when its vertices fit, each run padded
// to 4 bytes), the node records and the bond records (gltf_extras.c), the
// tree's .mtree bytes when embedded (one view, named by
// asset.extras.breakables.mtree), then the images written into the file
// (one view each; gltf_materials.c). A vertex is a welded mesh corner,
// placed relative to its node's centre of mass (gltf_vertices.c).
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "bk_fracture.h"
#include "gltf_internal.h"

bk_gltf_def bk_default_gltf_def(void) {
  return (bk_gltf_def){
      .levels = BK_GLTF_LEVELS_HIERARCHY,
      .embed_tree = true,
      .meshopt_compression = false,
      .materials = NULL,
      .material_count = 0,
      .density = 2400.0,
      .frailty = 1.0,
      .bond_strength = 2e5,
  };
}

// ---------------------------------------------------------------- layout

enum { ATTR_POSITION, ATTR_NORMAL, ATTR_TEXCOORD, ATTR_TANGENT, ATTR_COUNT };
static const uint32_t attr_bytes[ATTR_COUNT] = {12, 12, 8, 16};
// Where each attribute's view starts, in bytes per vertex of the whole export.
static const uint32_t attr_offset[ATTR_COUNT] = {0, 12, 24, 32};
enum { VERTEX_BYTES = 48 };
static const char* const attr_names[ATTR_COUNT] = {"POSITION", "NORMAL", "TEXCOORD_0", "TANGENT"};
static const char* const attr_types[ATTR_COUNT] = {"VEC3", "VEC3", "VEC2", "VEC4"};
// Buffer views: the attributes, the indices, the node records, then (when
// present) the bond records and the tree, then the images.
enum { VIEW_INDICES = ATTR_COUNT, VIEW_NODES };

// The triangles of one export material in one node: one primitive.
typedef struct out_run {
  uint32_t material; // glTF material index
  uint32_t triangles;
  uint64_t index_offset; // bytes, into the index view
} out_run;

// One exported glTF node.
typedef struct out_node {
  uint32_t tree_node;
  bk_vec3 centroid;              // in the tree frame
  bool has_mesh;                 // by the def's levels
  uint32_t mesh;                 // its glTF mesh, when it has one
  gltf_vertices vertices;        // welded, while the export is planned and written
  uint64_t vertex_first;         // in vertices, into each attribute view
  uint32_t first_run, run_count; // its primitives, by material index
  bool wide;                     // uint32 indices
  uint32_t first_accessor;       // attributes, then the index accessor of each run
  float min[3], max[3];
} out_node;

static uint64_t align(uint64_t v, uint64_t to) { return (v + to - 1) / to * to; }

static void put_u32le(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

// Fills one node's vertices and index runs in the binary buffer.
static void write_node_data(const bk_mesh* m, out_node* o, const out_run* runs,
                            const gltf_materials* materials, uint8_t* views[ATTR_COUNT], uint8_t* indices) {
  for (int k = 0; k < 3; ++k) {
    o->min[k] = INFINITY;
    o->max[k] = -INFINITY;
  }
  for (uint32_t i = 0; i < o->vertices.count; ++i) {
    const float* vertex = o->vertices.data + (size_t)i * BK_GLTF_VERTEX_FLOATS;
    for (int k = 0; k < 3; ++k) {
      if (vertex[k] < o->min[k]) o->min[k] = vertex[k];
      if (vertex[k] > o->max[k]) o->max[k] = vertex[k];
    }
    uint64_t v = o->vertex_first + i;
    memcpy(views[ATTR_POSITION] + v * 12, vertex, 12);
    memcpy(views[ATTR_NORMAL] + v * 12, vertex + 3, 12);
    memcpy(views[ATTR_TEXCOORD] + v * 8, vertex + 6, 8);
    memcpy(views[ATTR_TANGENT] + v * 16, vertex + 8, 16);
  }
  for (uint32_t r = o->first_run; r < o->first_run + o->run_count; ++r) {
    uint8_t* out = indices + runs[r].index_offset;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      if (bk_gltf_material_index(materials, m->materials[t]) != runs[r].material) continue;
      for (int k = 0; k < 3; ++k) {
        uint32_t index = o->vertices.of_corner[m->indices[3 * t + k]];
        if (o->wide) {
          put_u32le(out, index);
          out += 4;
        } else {
          out[0] = (uint8_t)index;
          out[1] = (uint8_t)(index >> 8);
          out += 2;
        }
      }
    }
  }
}

// ---------------------------------------------------------------- the document

typedef struct export_state {
  const bk_mesh_tree* tree;
  const bk_gltf_def* def;
  gltf_materials materials;
  out_node* nodes;
  uint32_t node_count, mesh_count;
  out_run* runs;
  uint32_t run_count;
  uint64_t vertex_count, index_bytes, binary_size;
  uint64_t node_records_offset, bond_records_offset, mtree_offset, mtree_size;
  gltf_extras_views views;
  uint32_t accessor_count;
  // Compressed (EXT_meshopt_compression): the attribute views decode into
  // buffer 1 (a fallback without data) from these streams in buffer 0, and
  // everything after the vertices moved by `shift` in buffer 0.
  bool meshopt;
  uint64_t packed_offset[ATTR_COUNT], packed_length[ATTR_COUNT];
  int64_t shift;
} export_state;

static uint32_t gltf_node_of_tree_node(const export_state* s, uint32_t tree_node) {
  return s->def->levels == BK_GLTF_LEVELS_LEAVES ? s->tree->nodes[tree_node].leaf_begin : tree_node;
}

static void write_node_json(text_buffer* t, const export_state* s, uint32_t i) {
  const out_node* o = &s->nodes[i];
  const bk_mesh_tree_node* n = &s->tree->nodes[o->tree_node];
  bool leaf = n->child_count == 0, flat = s->def->levels == BK_GLTF_LEVELS_LEAVES;
  bk_vec3 translation = o->centroid;
  if (!flat && n->parent != BK_NULL_INDEX) translation = bk_v3_sub(o->centroid, s->nodes[n->parent].centroid);
  if (leaf)
    bk_tb_fmt(t, "{\"name\":\"fragment_%u\"", n->leaf_begin);
  else
    bk_tb_fmt(t, "{\"name\":\"node_%u\"", o->tree_node);
  if (o->has_mesh) bk_tb_fmt(t, ",\"mesh\":%u", o->mesh);
  bk_tb_raw(t, ",\"translation\":");
  bk_tb_doubles(t, (const double[3]){translation.x, translation.y, translation.z}, 3);
  if (!flat && n->child_count) {
    bk_tb_raw(t, ",\"children\":[");
    for (uint32_t c = 0; c < n->child_count; ++c)
      bk_tb_fmt(t, c ? ",%u" : "%u", gltf_node_of_tree_node(s, n->first_child + c));
    bk_tb_raw(t, "]");
  }
  bk_tb_fmt(t, ",\"extras\":{\"breakables\":{\"node\":%u,\"leaves\":[%u,%u],\"volume\":", o->tree_node,
            n->leaf_begin, n->leaf_end);
  bk_tb_double(t, n->moments.v);
  bk_tb_raw(t, "}}}");
}

static void write_mesh_json(text_buffer* t, const export_state* s, const out_node* o) {
  const bk_mesh_tree_node* n = &s->tree->nodes[o->tree_node];
  if (n->child_count == 0)
    bk_tb_fmt(t, "{\"name\":\"fragment_%u\",\"primitives\":[", n->leaf_begin);
  else
    bk_tb_fmt(t, "{\"name\":\"node_%u\",\"primitives\":[", o->tree_node);
  uint32_t index_accessor = o->first_accessor + ATTR_COUNT;
  for (uint32_t r = 0; r < o->run_count; ++r)
    bk_tb_fmt(t,
              "%s{\"attributes\":{\"POSITION\":%u,\"NORMAL\":%u,\"TEXCOORD_0\":%u,\"TANGENT\":%u},"
              "\"indices\":%u,\"material\":%u}",
              r ? "," : "", o->first_accessor, o->first_accessor + 1, o->first_accessor + 2,
              o->first_accessor + 3, index_accessor++, s->runs[o->first_run + r].material);
  bk_tb_raw(t, "]}");
}

static void write_accessors_json(text_buffer* t, const export_state* s) {
  bool first = true;
  for (uint32_t i = 0; i < s->node_count; ++i) {
    const out_node* o = &s->nodes[i];
    if (!o->has_mesh) continue;
    for (int a = 0; a < ATTR_COUNT; ++a) {
      bk_tb_fmt(
          t, "%s{\"bufferView\":%d,\"byteOffset\":%llu,\"componentType\":5126,\"count\":%u,\"type\":\"%s\"",
          first ? "" : ",", a, (unsigned long long)(o->vertex_first * attr_bytes[a]), o->vertices.count,
          attr_types[a]);
      first = false;
      if (a == ATTR_POSITION) {
        bk_tb_raw(t, ",\"min\":");
        bk_tb_doubles(t, (const double[3]){o->min[0], o->min[1], o->min[2]}, 3);
        bk_tb_raw(t, ",\"max\":");
        bk_tb_doubles(t, (const double[3]){o->max[0], o->max[1], o->max[2]}, 3);
      }
      bk_tb_raw(t, "}");
    }
    for (uint32_t r = o->first_run; r < o->first_run + o->run_count; ++r)
      bk_tb_fmt(
          t,
          ",{\"bufferView\":%d,\"byteOffset\":%llu,\"componentType\":%d,\"count\":%llu,\"type\":\"SCALAR\"}",
          VIEW_INDICES, (unsigned long long)s->runs[r].index_offset, o->wide ? 5125 : 5123,
          (unsigned long long)s->runs[r].triangles * 3u);
  }
}

// A buffer view of our own records in buffer 0 (no target: no accessor reads it).
static void write_view_json(text_buffer* t, uint64_t offset, uint64_t length, const char* name) {
  bk_tb_fmt(t, ",{\"buffer\":0,\"byteOffset\":%llu,\"byteLength\":%llu,\"name\":\"%s\"}",
            (unsigned long long)offset, (unsigned long long)length, name);
}

static void write_document(text_buffer* t, const export_state* s, bool glb, const uint8_t* binary) {
  const bk_gltf_def* def = s->def;
  bk_tb_raw(t, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"Breakables (bk_mesh_tree_save_gltf)\",");
  bk_gltf_write_asset_extras(t, s->tree, def, s->materials.list[0].name, &s->views);
  bk_tb_raw(t, "},");
  if (s->meshopt)
    bk_tb_raw(t, "\"extensionsUsed\":[\"EXT_meshopt_compression\"],"
                 "\"extensionsRequired\":[\"EXT_meshopt_compression\"],");
  bk_tb_raw(t, "\"scene\":0,\"scenes\":[{\"name\":\"breakables\",\"nodes\":[");
  if (def->levels != BK_GLTF_LEVELS_LEAVES)
    bk_tb_raw(t, "0");
  else
    for (uint32_t i = 0; i < s->node_count; ++i)
      bk_tb_fmt(t, i ? ",%u" : "%u", i);
  bk_tb_raw(t, "]}],\"nodes\":[");
  for (uint32_t i = 0; i < s->node_count; ++i) {
    if (i) bk_tb_raw(t, ",");
    write_node_json(t, s, i);
  }
  bk_tb_raw(t, "],\"meshes\":[");
  for (uint32_t i = 0, written = 0; i < s->node_count; ++i) {
    if (!s->nodes[i].has_mesh) continue;
    if (written++) bk_tb_raw(t, ",");
    write_mesh_json(t, s, &s->nodes[i]);
  }
  bk_tb_raw(t, "]");
  bk_gltf_write_materials_json(t, &s->materials);
  bk_tb_raw(t, ",\"accessors\":[");
  write_accessors_json(t, s);
  bk_tb_raw(t, "],\"bufferViews\":[");
  for (int a = 0; a < ATTR_COUNT; ++a) {
    bk_tb_fmt(t,
              "%s{\"buffer\":%d,\"byteOffset\":%llu,\"byteLength\":%llu,\"byteStride\":%u,\"target\":34962,"
              "\"name\":\"%s\"",
              a ? "," : "", s->meshopt ? 1 : 0, (unsigned long long)(s->vertex_count * attr_offset[a]),
              (unsigned long long)(s->vertex_count * attr_bytes[a]), attr_bytes[a], attr_names[a]);
    if (s->meshopt)
      bk_tb_fmt(t,
                ",\"extensions\":{\"EXT_meshopt_compression\":{\"buffer\":0,\"byteOffset\":%llu,"
                "\"byteLength\":%llu,"
                "\"byteStride\":%u,\"mode\":\"ATTRIBUTES\",\"count\":%llu}}",
                (unsigned long long)s->packed_offset[a], (unsigned long long)s->packed_length[a],
                attr_bytes[a], (unsigned long long)s->vertex_count);
    bk_tb_raw(t, "}");
  }
  uint64_t shift = (uint64_t)s->shift; // modulo 2^64: adding it moves an offset back or forth
  bk_tb_fmt(t,
            ",{\"buffer\":0,\"byteOffset\":%llu,\"byteLength\":%llu,\"target\":34963,\"name\":\"indices\"}",
            (unsigned long long)(s->vertex_count * VERTEX_BYTES + shift), (unsigned long long)s->index_bytes);
  write_view_json(t, s->node_records_offset + shift,
                  (uint64_t)s->tree->node_count * BK_GLTF_NODE_RECORD_BYTES, "breakables_nodes");
  if (s->views.bonds >= 0)
    write_view_json(t, s->bond_records_offset + shift,
                    (uint64_t)s->tree->bond_count * BK_GLTF_BOND_RECORD_BYTES, "breakables_bonds");
  if (s->views.mtree >= 0) write_view_json(t, s->mtree_offset + shift, s->mtree_size, "breakables_mtree");
  bk_gltf_write_image_views_json(t, &s->materials);
  bk_tb_fmt(t, "],\"buffers\":[{\"byteLength\":%llu", (unsigned long long)s->binary_size);
  if (!glb) {
    bk_tb_raw(t, ",\"uri\":\"data:application/octet-stream;base64,");
    bk_tb_base64(t, binary, (size_t)s->binary_size);
    bk_tb_raw(t, "\"");
  }
  bk_tb_raw(t, "}");
  if (s->meshopt)
    bk_tb_fmt(t, ",{\"byteLength\":%llu,\"extensions\":{\"EXT_meshopt_compression\":{\"fallback\":true}}}",
              (unsigned long long)(s->vertex_count * VERTEX_BYTES));
  bk_tb_raw(t, "]}");
}

// ---------------------------------------------------------------- saving

// Replaces the binary buffer by the compressed one: the four attribute
// views' streams (each 4-byte aligned), then everything that followed the
// vertices, moved to an 8-byte boundary (the records stay aligned).
static uint8_t* compress_vertices(export_state* s, uint8_t* binary) {
  uint64_t vertex_bytes = s->vertex_count * VERTEX_BYTES, capacity = 0;
  for (int a = 0; a < ATTR_COUNT; ++a)
    capacity += align(bk_gltf_meshopt_bound((size_t)s->vertex_count, attr_bytes[a]), 4);
  uint64_t rest = s->binary_size - vertex_bytes;
  uint8_t* packed = bk_calloc((size_t)(align(capacity, 8) + rest), 1);
  uint64_t at = 0;
  for (int a = 0; a < ATTR_COUNT; ++a) {
    size_t bound = bk_gltf_meshopt_bound((size_t)s->vertex_count, attr_bytes[a]);
    s->packed_offset[a] = at;
    s->packed_length[a] = bk_gltf_meshopt_encode(binary + s->vertex_count * attr_offset[a],
                                                 (size_t)s->vertex_count, attr_bytes[a], packed + at, bound);
    at = align(at + s->packed_length[a], 4);
  }
  at = align(at, 8);
  memcpy(packed + at, binary + vertex_bytes, (size_t)rest);
  s->shift = (int64_t)at - (int64_t)vertex_bytes;
  for (uint32_t i = 0; i < s->materials.image_count; ++i)
    s->materials.images[i].offset += (uint64_t)s->shift;
  s->binary_size = at + rest;
  s->meshopt = true;
  bk_free(binary);
  return packed;
}

static bool check_def(const bk_gltf_def* def, const char* path, bk_error* err) {
  if (def->levels != BK_GLTF_LEVELS_HIERARCHY && def->levels != BK_GLTF_LEVELS_LEAVES &&
      def->levels != BK_GLTF_LEVELS_ALL)
    return bk_error_set(err,
                        "%s: gltf def: levels must be BK_GLTF_LEVELS_HIERARCHY, BK_GLTF_LEVELS_LEAVES or "
                        "BK_GLTF_LEVELS_ALL, got %d",
                        path, (int)def->levels);
  if (!bk_gltf_check_materials(def, path, err)) return false;
  if (!(isfinite(def->density) && def->density > 0))
    return bk_error_set(err, "%s: gltf def: density must be finite and > 0, got %g", path, def->density);
  if (!(isfinite(def->frailty) && def->frailty >= 0))
    return bk_error_set(err, "%s: gltf def: frailty must be finite and >= 0, got %g", path, def->frailty);
  if (!(isfinite(def->bond_strength) && def->bond_strength > 0))
    return bk_error_set(err, "%s: gltf def: bond_strength must be finite and > 0, got %g", path,
                        def->bond_strength);
  if (def->meshopt_compression && bk_gltf_meshopt_bound(1, 4) == 0)
    return bk_error_set(
        err, "%s: gltf def: meshopt_compression needs meshoptimizer, which this build leaves out", path);
  return true;
}

// True for a path ending in `ext` (ASCII, any case).
static bool has_extension(const char* path, const char* ext) {
  size_t n = strlen(path), e = strlen(ext);
  return n > e && strcasecmp(path + n - e, ext) == 0;
}

// Lays the export out: which tree nodes, which of them have meshes (welded
// here), their centroids, where their data goes.
static void plan(export_state* s) {
  const bk_mesh_tree* tree = s->tree;
  bk_gltf_levels levels = s->def->levels;
  s->node_count = levels == BK_GLTF_LEVELS_LEAVES ? tree->leaf_count : tree->node_count;
  s->nodes = bk_calloc(s->node_count, sizeof(out_node));
  uint64_t vertices = 0, index_bytes = 0;
  uint32_t accessors = 0, run_capacity = 0;
  uint32_t material_count = 2u * s->materials.source_count;
  uint32_t* triangles = bk_alloc(sizeof(uint32_t) * material_count); // per material, of one node
  for (uint32_t i = 0; i < s->node_count; ++i) {
    out_node* o = &s->nodes[i];
    o->tree_node = levels == BK_GLTF_LEVELS_LEAVES ? tree->leaf_nodes[i] : i;
    const bk_mesh_tree_node* n = &tree->nodes[o->tree_node];
    const bk_mesh* m = &n->mesh;
    o->centroid = bk_mesh_tree_mass(tree, n->moments).centroid;
    o->has_mesh = levels == BK_GLTF_LEVELS_ALL || n->child_count == 0;
    if (!o->has_mesh) continue;
    o->mesh = s->mesh_count++;
    bk_gltf_weld(m, o->centroid, &o->vertices);
    o->vertex_first = vertices;
    vertices += o->vertices.count;
    // uint16 indices when every vertex index fits below 65535 (the primitive-restart value).
    o->wide = o->vertices.count > 65535;
    memset(triangles, 0, sizeof(uint32_t) * material_count);
    for (uint32_t t = 0; t < m->triangle_count; ++t)
      triangles[bk_gltf_material_index(&s->materials, m->materials[t])]++;
    o->first_accessor = accessors;
    accessors += ATTR_COUNT;
    o->first_run = s->run_count;
    for (uint32_t mat = 0; mat < material_count; ++mat) {
      if (!triangles[mat]) continue;
      if (s->run_count == run_capacity) {
        run_capacity = bk_grow_capacity(run_capacity, s->run_count + 1);
        s->runs = bk_realloc(s->runs, sizeof(out_run) * run_capacity);
      }
      s->runs[s->run_count++] = (out_run){mat, triangles[mat], index_bytes};
      index_bytes += align((uint64_t)triangles[mat] * 3u * (o->wide ? 4u : 2u), 4);
      accessors++;
    }
    o->run_count = s->run_count - o->first_run;
  }
  bk_free(triangles);
  s->vertex_count = vertices;
  s->index_bytes = index_bytes;
  s->accessor_count = accessors;
  // The records are 8-byte aligned, so a reader may map their doubles in place.
  s->node_records_offset = align(vertices * VERTEX_BYTES + index_bytes, 8);
  s->bond_records_offset = s->node_records_offset + (uint64_t)tree->node_count * BK_GLTF_NODE_RECORD_BYTES;
  s->mtree_offset = s->bond_records_offset + (uint64_t)tree->bond_count * BK_GLTF_BOND_RECORD_BYTES;
  // The images follow the tree; their offsets were planned from 0.
  uint64_t images_offset = align(s->mtree_offset + s->mtree_size, 4);
  for (uint32_t i = 0; i < s->materials.image_count; ++i)
    s->materials.images[i].offset += images_offset;
  s->binary_size = images_offset + s->materials.bytes;
}

static void free_state(export_state* s) {
  for (uint32_t i = 0; i < s->node_count; ++i)
    bk_gltf_vertices_free(&s->nodes[i].vertices);
  bk_free(s->nodes);
  bk_free(s->runs);
  bk_gltf_materials_free(&s->materials);
}

static const bk_atomic_messages gltf_write_messages = {"cannot open for writing", "write failed",
                                                       "cannot replace file"};

bool bk_mesh_tree_save_gltf(const bk_mesh_tree* tree, const char* path, const bk_gltf_def* def,
                            bk_error* err) {
  bk_gltf_def defaults = bk_default_gltf_def();
  if (!def) def = &defaults;
  if (!check_def(def, path, err)) return false;
  bool glb = has_extension(path, ".glb");
  if (!glb && !has_extension(path, ".gltf"))
    return bk_error_set(err, "%s: the file name must end in .glb (binary glTF) or .gltf (glTF JSON)", path);

  // Saving to memory validates the tree, embedded or not: an invalid tree is never written.
  uint8_t* mtree = NULL;
  size_t mtree_size = 0;
  if (!bk_mesh_tree_save_memory(tree, path, &mtree, &mtree_size, err)) return false;
  if (!def->embed_tree) {
    bk_free(mtree);
    mtree = NULL;
    mtree_size = 0;
  }

  export_state s = {.tree = tree, .def = def, .mtree_size = mtree_size};
  int32_t view = VIEW_NODES + 1;
  s.views.nodes = VIEW_NODES;
  s.views.bonds = tree->bond_count ? view++ : -1;
  s.views.mtree = def->embed_tree ? view++ : -1;
  bk_gltf_material fallback = bk_default_gltf_material();
  bk_gltf_plan_materials(def, &fallback, 0, (uint32_t)view, &s.materials);
  plan(&s);
  // GLB lengths are 32-bit; a .gltf's base64 text is a third larger still.
  const uint64_t limit = (uint64_t)3 << 30;
  if (s.binary_size > limit) {
    bk_free(mtree);
    free_state(&s);
    return bk_error_set(
        err, "%s: the export would hold %llu bytes of binary data, more than glTF's 3 GiB limit here", path,
        (unsigned long long)s.binary_size);
  }
  uint8_t* binary = bk_calloc((size_t)s.binary_size, 1);
  uint8_t* views[ATTR_COUNT];
  for (int a = 0; a < ATTR_COUNT; ++a)
    views[a] = binary + s.vertex_count * attr_offset[a];
  for (uint32_t i = 0; i < s.node_count; ++i)
    if (s.nodes[i].has_mesh)
      write_node_data(&tree->nodes[s.nodes[i].tree_node].mesh, &s.nodes[i], s.runs, &s.materials, views,
                      binary + s.vertex_count * VERTEX_BYTES);
  bk_gltf_write_node_records(tree, binary + s.node_records_offset);
  bk_gltf_write_bond_records(tree, binary + s.bond_records_offset);
  if (mtree) memcpy(binary + s.mtree_offset, mtree, mtree_size);
  bk_gltf_write_image_data(&s.materials, binary);
  bk_free(mtree);
  if (def->meshopt_compression) binary = compress_vertices(&s, binary);

  text_buffer json = {0};
  bk_c_locale c_locale = bk_c_locale_begin(); // JSON numbers need '.'
  write_document(&json, &s, glb, binary);
  bk_c_locale_end(&c_locale);
  free_state(&s);

  uint64_t json_padded = ((uint64_t)json.size + 3u) & ~(uint64_t)3;
  uint64_t total = 12u + 8u + json_padded + 8u + s.binary_size;
  if (glb && total > UINT32_MAX) {
    bk_free(json.data);
    bk_free(binary);
    return bk_error_set(err, "%s: the export is %llu bytes, more than a .glb can hold (4 GiB)", path,
                        (unsigned long long)total);
  }
  bk_atomic_file file = {0};
  bool ok = bk_file_begin_atomic(path, &gltf_write_messages, &file, err);
  if (ok && glb) {
    uint8_t header[20];
    put_u32le(header, BK_GLB_MAGIC);
    put_u32le(header + 4, BK_GLB_VERSION);
    put_u32le(header + 8, (uint32_t)total);
    put_u32le(header + 12, (uint32_t)json_padded);
    put_u32le(header + 16, BK_GLB_CHUNK_JSON);
    fwrite(header, 1, sizeof header, file.stream);
    fwrite(json.data, 1, json.size, file.stream);
    fwrite("   ", 1, (size_t)(json_padded - json.size), file.stream); // the JSON chunk is padded with spaces
    put_u32le(header, (uint32_t)s.binary_size);
    put_u32le(header + 4, BK_GLB_CHUNK_BIN);
    fwrite(header, 1, 8, file.stream);
    fwrite(binary, 1, (size_t)s.binary_size, file.stream);
  } else if (ok) {
    fwrite(json.data, 1, json.size, file.stream);
    fputc('\n', file.stream);
  }
  if (ok) ok = bk_file_commit_atomic(&file, path, &gltf_write_messages, err); // reports any short write
  bk_free(json.data);
  bk_free(binary);
  return ok;
}
