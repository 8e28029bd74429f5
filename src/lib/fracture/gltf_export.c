// glTF 2.0 export of a mesh tree (bk_mesh_tree_save_gltf); the layout and the
// extras are described in docs/gltf.md.
//
// One binary buffer holds, in order: every exported node's POSITION, NORMAL,
// TEXCOORD_0 and TANGENT (four buffer views, one per attribute, each node's
// vertices a run within them), the indices (one view; a node's runs per
// material, uint16 when its vertices fit, each run padded to 4 bytes) and the
// tree's .mtree bytes (one view, named by asset.extras.breakables.mtree),
// then the images written into the file (one view each; gltf_materials.c).
// A vertex is a mesh corner, placed relative to its node's centre of mass.
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "bk_fracture.h"
#include "gltf_internal.h"

bk_gltf_def bk_default_gltf_def(void) {
  return (bk_gltf_def){
      .levels = BK_GLTF_LEVELS_ALL,
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

// The triangles of one export material in one node: one primitive.
typedef struct out_run {
  uint32_t material; // glTF material index
  uint32_t triangles;
  uint64_t index_offset; // bytes, into the index view
} out_run;

// One exported glTF node.
typedef struct out_node {
  uint32_t tree_node;
  bk_vec3 centroid;      // in the tree frame
  uint64_t vertex_first; // in vertices, into each attribute view
  uint32_t vertex_count;
  uint32_t first_run, run_count; // its primitives, by material index
  bool wide;                     // uint32 indices
  uint32_t first_accessor;       // attributes, then the index accessor of each run
  float min[3], max[3];
} out_node;

static void put_u32le(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

static void normalize3(float v[3], const float fallback[3]) {
  double l = sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
  if (!(l > 1e-20)) {
    memcpy(v, fallback, 3 * sizeof(float));
    return;
  }
  for (int k = 0; k < 3; ++k)
    v[k] = (float)(v[k] / l);
}

// Fills one node's vertices and index runs in the binary buffer.
static void write_node_data(const bk_mesh* m, out_node* o, const out_run* runs,
                            const gltf_materials* materials, uint8_t* views[ATTR_COUNT], uint8_t* indices) {
  for (int k = 0; k < 3; ++k) {
    o->min[k] = INFINITY;
    o->max[k] = -INFINITY;
  }
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    const bk_corner* c = &m->corners[i];
    bk_vec3 p = bk_v3_sub(m->positions[c->position], o->centroid);
    float pos[3] = {(float)p.x, (float)p.y, (float)p.z};
    for (int k = 0; k < 3; ++k) {
      if (pos[k] < o->min[k]) o->min[k] = pos[k];
      if (pos[k] > o->max[k]) o->max[k] = pos[k];
    }
    float normal[3] = {c->normal[0], c->normal[1], c->normal[2]};
    static const float up[3] = {0, 0, 1}, right[3] = {1, 0, 0};
    normalize3(normal, up);
    float tangent[4] = {c->tangent[0], c->tangent[1], c->tangent[2], c->tangent[3] < 0 ? -1.0f : 1.0f};
    normalize3(tangent, fabsf(normal[0]) < 0.9f ? right : up);
    uint64_t v = o->vertex_first + i;
    memcpy(views[ATTR_POSITION] + v * 12, pos, 12);
    memcpy(views[ATTR_NORMAL] + v * 12, normal, 12);
    memcpy(views[ATTR_TEXCOORD] + v * 8, c->uv, 8);
    memcpy(views[ATTR_TANGENT] + v * 16, tangent, 16);
  }
  for (uint32_t r = o->first_run; r < o->first_run + o->run_count; ++r) {
    uint8_t* out = indices + runs[r].index_offset;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      if (bk_gltf_material_index(materials, m->materials[t]) != runs[r].material) continue;
      for (int k = 0; k < 3; ++k) {
        uint32_t index = m->indices[3 * t + k];
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
  uint32_t node_count;
  out_run* runs;
  uint32_t run_count;
  uint64_t vertex_count, index_bytes, mtree_offset, mtree_size, binary_size;
  uint32_t accessor_count;
} export_state;

static uint32_t gltf_node_of_tree_node(const export_state* s, uint32_t tree_node) {
  return s->def->levels == BK_GLTF_LEVELS_LEAVES ? s->tree->nodes[tree_node].leaf_begin : tree_node;
}

static void write_node_json(text_buffer* t, const export_state* s, uint32_t i) {
  const out_node* o = &s->nodes[i];
  const bk_mesh_tree_node* n = &s->tree->nodes[o->tree_node];
  bool leaf = n->child_count == 0;
  bk_vec3 translation = o->centroid;
  if (s->def->levels == BK_GLTF_LEVELS_ALL && n->parent != BK_NULL_INDEX)
    translation = bk_v3_sub(o->centroid, s->nodes[n->parent].centroid);
  if (leaf)
    bk_tb_fmt(t, "{\"name\":\"fragment_%u\"", n->leaf_begin);
  else
    bk_tb_fmt(t, "{\"name\":\"node_%u\"", o->tree_node);
  bk_tb_fmt(t, ",\"mesh\":%u,\"translation\":", i);
  bk_tb_doubles(t, (const double[3]){translation.x, translation.y, translation.z}, 3);
  if (s->def->levels == BK_GLTF_LEVELS_ALL && n->child_count) {
    bk_tb_raw(t, ",\"children\":[");
    for (uint32_t c = 0; c < n->child_count; ++c)
      bk_tb_fmt(t, c ? ",%u" : "%u", gltf_node_of_tree_node(s, n->first_child + c));
    bk_tb_raw(t, "]");
  }
  const bk_moments* m = &n->moments;
  bk_tb_fmt(t, ",\"extras\":{\"breakables\":{\"node\":%u,\"leaves\":[%u,%u],\"volume\":", o->tree_node,
            n->leaf_begin, n->leaf_end);
  bk_tb_double(t, m->v);
  bk_tb_raw(t, ",\"moments\":");
  bk_tb_doubles(t, (const double[10]){m->v, m->x, m->y, m->z, m->xx, m->yy, m->zz, m->xy, m->yz, m->zx}, 10);
  bk_tb_raw(t, ",\"bounds\":");
  bk_aabb b = n->bounds;
  bk_tb_doubles(t, (const double[6]){b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}, 6);
  bk_tb_raw(t, "}}}");
}

static void write_mesh_json(text_buffer* t, const export_state* s, uint32_t i) {
  const out_node* o = &s->nodes[i];
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
    for (int a = 0; a < ATTR_COUNT; ++a) {
      bk_tb_fmt(
          t, "%s{\"bufferView\":%d,\"byteOffset\":%llu,\"componentType\":5126,\"count\":%u,\"type\":\"%s\"",
          first ? "" : ",", a, (unsigned long long)(o->vertex_first * attr_bytes[a]), o->vertex_count,
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
          ATTR_COUNT, (unsigned long long)s->runs[r].index_offset, o->wide ? 5125 : 5123,
          (unsigned long long)s->runs[r].triangles * 3u);
  }
}

static void write_asset_extras(text_buffer* t, const export_state* s) {
  const bk_mesh_tree* tree = s->tree;
  const bk_gltf_def* def = s->def;
  bk_vec3 origin = bk_mesh_tree_origin(tree);
  bk_tb_fmt(t, "\"extras\":{\"breakables\":{\"version\":%d,\"mtree\":{\"bufferView\":%d,\"version\":%u},",
            BK_GLTF_EXTRAS_VERSION, ATTR_COUNT + 1, BK_MTREE_VERSION);
  bk_tb_fmt(t, "\"levels\":\"%s\",\"node_count\":%u,\"leaf_count\":%u,\"max_depth\":%u,\"origin\":",
            def->levels == BK_GLTF_LEVELS_LEAVES ? "leaves" : "all", tree->node_count, tree->leaf_count,
            tree->max_depth);
  bk_tb_doubles(t, (const double[3]){origin.x, origin.y, origin.z}, 3);
  bk_tb_fmt(t, ",\"fracture\":{\"pattern\":\"%s\",\"pieces\":%u,\"seed\":%llu,\"texture_scale\":",
            bk_fracture_pattern_name(tree->desc.pattern), tree->desc.pieces,
            (unsigned long long)tree->desc.seed);
  bk_tb_double(t, tree->desc.texture_scale);
  bk_tb_raw(t, ",\"jitter\":");
  bk_tb_double(t, tree->desc.jitter);
  bk_tb_raw(t, ",\"aspect_bias\":");
  bk_tb_double(t, tree->desc.aspect_bias);
  bk_tb_raw(t, "},\"material\":{\"name\":");
  bk_tb_string(t, s->materials.list[0].name);
  bk_tb_raw(t, ",\"density\":");
  bk_tb_double(t, def->density);
  bk_tb_raw(t, ",\"frailty\":");
  bk_tb_double(t, def->frailty);
  bk_tb_raw(t, ",\"bond_strength\":");
  bk_tb_double(t, def->bond_strength);
  bk_tb_raw(t, "},\"bonds\":[");
  for (uint32_t i = 0; i < tree->bond_count; ++i) {
    const bk_bond* b = &tree->bonds[i];
    bk_tb_fmt(t, "%s[%u,%u,", i ? "," : "", b->leaf_a, b->leaf_b);
    const double v[7] = {b->area,     b->centroid.x, b->centroid.y, b->centroid.z,
                         b->normal.x, b->normal.y,   b->normal.z};
    for (int k = 0; k < 7; ++k) {
      if (k) bk_tb_raw(t, ",");
      bk_tb_double(t, v[k]);
    }
    bk_tb_raw(t, "]");
  }
  bk_tb_raw(t, "]}}");
}

static void write_document(text_buffer* t, const export_state* s, bool glb, const uint8_t* binary) {
  const bk_gltf_def* def = s->def;
  bk_tb_raw(t, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"Breakables (bk_mesh_tree_save_gltf)\",");
  write_asset_extras(t, s);
  bk_tb_raw(t, "},\"scene\":0,\"scenes\":[{\"name\":\"breakables\",\"nodes\":[");
  if (def->levels == BK_GLTF_LEVELS_ALL)
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
  for (uint32_t i = 0; i < s->node_count; ++i) {
    if (i) bk_tb_raw(t, ",");
    write_mesh_json(t, s, i);
  }
  bk_tb_raw(t, "]");
  bk_gltf_write_materials_json(t, &s->materials);
  bk_tb_raw(t, ",\"accessors\":[");
  write_accessors_json(t, s);
  bk_tb_raw(t, "],\"bufferViews\":[");
  for (int a = 0; a < ATTR_COUNT; ++a)
    bk_tb_fmt(t,
              "%s{\"buffer\":0,\"byteOffset\":%llu,\"byteLength\":%llu,\"byteStride\":%u,\"target\":34962,"
              "\"name\":\"%s\"}",
              a ? "," : "", (unsigned long long)(s->vertex_count * attr_offset[a]),
              (unsigned long long)(s->vertex_count * attr_bytes[a]), attr_bytes[a], attr_names[a]);
  bk_tb_fmt(t,
            ",{\"buffer\":0,\"byteOffset\":%llu,\"byteLength\":%llu,\"target\":34963,\"name\":\"indices\"}",
            (unsigned long long)(s->vertex_count * VERTEX_BYTES), (unsigned long long)s->index_bytes);
  bk_tb_fmt(t, ",{\"buffer\":0,\"byteOffset\":%llu,\"byteLength\":%llu,\"name\":\"breakables_mtree\"}",
            (unsigned long long)s->mtree_offset, (unsigned long long)s->mtree_size);
  bk_gltf_write_image_views_json(t, &s->materials);
  bk_tb_fmt(t, "],\"buffers\":[{\"byteLength\":%llu", (unsigned long long)s->binary_size);
  if (!glb) {
    bk_tb_raw(t, ",\"uri\":\"data:application/octet-stream;base64,");
    bk_tb_base64(t, binary, (size_t)s->binary_size);
    bk_tb_raw(t, "\"");
  }
  bk_tb_raw(t, "}]}");
}

// ---------------------------------------------------------------- saving

static bool check_def(const bk_gltf_def* def, const char* path, bk_error* err) {
  if (def->levels != BK_GLTF_LEVELS_ALL && def->levels != BK_GLTF_LEVELS_LEAVES)
    return bk_error_set(err,
                        "%s: gltf def: levels must be BK_GLTF_LEVELS_ALL or BK_GLTF_LEVELS_LEAVES, got %d",
                        path, (int)def->levels);
  if (!bk_gltf_check_materials(def, path, err)) return false;
  if (!(isfinite(def->density) && def->density > 0))
    return bk_error_set(err, "%s: gltf def: density must be finite and > 0, got %g", path, def->density);
  if (!(isfinite(def->frailty) && def->frailty >= 0))
    return bk_error_set(err, "%s: gltf def: frailty must be finite and >= 0, got %g", path, def->frailty);
  if (!(isfinite(def->bond_strength) && def->bond_strength > 0))
    return bk_error_set(err, "%s: gltf def: bond_strength must be finite and > 0, got %g", path,
                        def->bond_strength);
  return true;
}

// True for a path ending in `ext` (ASCII, any case).
static bool has_extension(const char* path, const char* ext) {
  size_t n = strlen(path), e = strlen(ext);
  return n > e && strcasecmp(path + n - e, ext) == 0;
}

// Lays the export out: which tree nodes, their centroids, where their data goes.
static void plan(export_state* s) {
  const bk_mesh_tree* tree = s->tree;
  bool leaves = s->def->levels == BK_GLTF_LEVELS_LEAVES;
  s->node_count = leaves ? tree->leaf_count : tree->node_count;
  s->nodes = bk_calloc(s->node_count, sizeof(out_node));
  uint64_t vertices = 0, index_bytes = 0;
  uint32_t accessors = 0, run_capacity = 0;
  uint32_t material_count = 2u * s->materials.source_count;
  uint32_t* triangles = bk_alloc(sizeof(uint32_t) * material_count); // per material, of one node
  for (uint32_t i = 0; i < s->node_count; ++i) {
    out_node* o = &s->nodes[i];
    o->tree_node = leaves ? tree->leaf_nodes[i] : i;
    const bk_mesh_tree_node* n = &tree->nodes[o->tree_node];
    const bk_mesh* m = &n->mesh;
    o->centroid = bk_mesh_tree_mass(tree, n->moments).centroid;
    o->vertex_first = vertices;
    o->vertex_count = m->corner_count;
    vertices += m->corner_count;
    // uint16 indices when every vertex index fits below 65535 (the primitive-restart value).
    o->wide = m->corner_count > 65535;
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
      index_bytes += ((uint64_t)triangles[mat] * 3u * (o->wide ? 4u : 2u) + 3u) & ~(uint64_t)3;
      accessors++;
    }
    o->run_count = s->run_count - o->first_run;
  }
  free(triangles);
  s->vertex_count = vertices;
  s->index_bytes = index_bytes;
  s->accessor_count = accessors;
  s->mtree_offset = vertices * VERTEX_BYTES + index_bytes;
  // The images follow the tree; their offsets were planned from 0.
  uint64_t images_offset = s->mtree_offset + ((s->mtree_size + 3u) & ~(uint64_t)3);
  for (uint32_t i = 0; i < s->materials.image_count; ++i)
    s->materials.images[i].offset += images_offset;
  s->binary_size = images_offset + s->materials.bytes;
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

  uint8_t* mtree = NULL;
  size_t mtree_size = 0;
  if (!bk_mesh_tree_save_memory(tree, path, &mtree, &mtree_size, err)) return false;

  export_state s = {.tree = tree, .def = def, .mtree_size = mtree_size};
  bk_gltf_material fallback = bk_default_gltf_material();
  bk_gltf_plan_materials(def, &fallback, 0, ATTR_COUNT + 2, &s.materials);
  plan(&s);
  // GLB lengths are 32-bit; a .gltf's base64 text is a third larger still.
  const uint64_t limit = (uint64_t)3 << 30;
  if (s.binary_size > limit) {
    free(mtree);
    free(s.nodes);
    free(s.runs);
    bk_gltf_materials_free(&s.materials);
    return bk_error_set(
        err, "%s: the export would hold %llu bytes of binary data, more than glTF's 3 GiB limit here", path,
        (unsigned long long)s.binary_size);
  }
  uint8_t* binary = bk_calloc((size_t)s.binary_size, 1);
  uint8_t* views[ATTR_COUNT];
  for (int a = 0; a < ATTR_COUNT; ++a)
    views[a] = binary + s.vertex_count * attr_offset[a];
  for (uint32_t i = 0; i < s.node_count; ++i)
    write_node_data(&tree->nodes[s.nodes[i].tree_node].mesh, &s.nodes[i], s.runs, &s.materials, views,
                    binary + s.vertex_count * VERTEX_BYTES);
  memcpy(binary + s.mtree_offset, mtree, mtree_size);
  bk_gltf_write_image_data(&s.materials, binary);
  free(mtree);

  text_buffer json = {0};
  bk_c_locale c_locale = bk_c_locale_begin(); // JSON numbers need '.'
  write_document(&json, &s, glb, binary);
  bk_c_locale_end(&c_locale);
  free(s.nodes);
  free(s.runs);
  bk_gltf_materials_free(&s.materials);

  uint64_t json_padded = ((uint64_t)json.size + 3u) & ~(uint64_t)3;
  uint64_t total = 12u + 8u + json_padded + 8u + s.binary_size;
  if (glb && total > UINT32_MAX) {
    free(json.data);
    free(binary);
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
  free(json.data);
  free(binary);
  return ok;
}
