// glTF 2.0 export of a mesh tree (bk_mesh_tree_save_gltf); the layout and the
// extras are described in docs/gltf.md.
//
// One binary buffer holds, in order: every exported node's POSITION, NORMAL,
// TEXCOORD_0 and TANGENT (four buffer views, one per attribute, each node's
// vertices a run within them), the indices (one view; a node's runs per
// material, uint16 when its vertices fit, each run padded to 4 bytes) and the
// tree's .mtree bytes (one view, named by asset.extras.breakables.mtree).
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
      .material_name = "surface",
      .base_color_texture = NULL,
      .interior_texture = NULL,
      .density = 2400.0,
      .frailty = 1.0,
      .bond_strength = 2e5,
  };
}

// ---------------------------------------------------------------- the JSON text

typedef struct text_buffer {
  char* data;
  size_t size, capacity;
} text_buffer;

static void tb_reserve(text_buffer* t, size_t extra) {
  if (t->size + extra + 1 <= t->capacity) return;
  size_t capacity = t->capacity ? t->capacity : 65536;
  while (capacity < t->size + extra + 1)
    capacity *= 2;
  t->data = bk_realloc(t->data, capacity);
  t->capacity = capacity;
}

static void tb_raw(text_buffer* t, const char* s) {
  size_t n = strlen(s);
  tb_reserve(t, n);
  memcpy(t->data + t->size, s, n + 1);
  t->size += n;
}

__attribute__((format(printf, 2, 3))) static void tb_fmt(text_buffer* t, const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  tb_reserve(t, 64);
  int n = vsnprintf(t->data + t->size, t->capacity - t->size, fmt, args);
  va_end(args);
  if (n >= 0 && (size_t)n >= t->capacity - t->size) {
    tb_reserve(t, (size_t)n);
    va_start(args, fmt);
    n = vsnprintf(t->data + t->size, t->capacity - t->size, fmt, args);
    va_end(args);
  }
  if (n > 0) t->size += (size_t)n;
}

// Doubles with %.17g read back exactly; the values written are finite (the
// tree and the def are checked first). A float is written as its exact double.
static void tb_double(text_buffer* t, double v) { tb_fmt(t, "%.17g", v); }

static void tb_doubles(text_buffer* t, const double* v, int n) {
  tb_raw(t, "[");
  for (int i = 0; i < n; ++i) {
    if (i) tb_raw(t, ",");
    tb_double(t, v[i]);
  }
  tb_raw(t, "]");
}

static void tb_string(text_buffer* t, const char* s) {
  tb_raw(t, "\"");
  for (const unsigned char* c = (const unsigned char*)s; *c; ++c) {
    if (*c == '"' || *c == '\\')
      tb_fmt(t, "\\%c", *c);
    else if (*c < 0x20)
      tb_fmt(t, "\\u%04x", *c);
    else {
      tb_reserve(t, 1);
      t->data[t->size++] = (char)*c;
      t->data[t->size] = '\0';
    }
  }
  tb_raw(t, "\"");
}

// A path as a URI reference: letters, digits and -._~/ stay, the rest is %XX.
static void tb_uri(text_buffer* t, const char* path) {
  tb_raw(t, "\"");
  for (const unsigned char* c = (const unsigned char*)path; *c; ++c) {
    if ((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ||
        strchr("-._~/", *c))
      tb_fmt(t, "%c", *c);
    else
      tb_fmt(t, "%%%02X", *c);
  }
  tb_raw(t, "\"");
}

static void tb_base64(text_buffer* t, const uint8_t* data, size_t size) {
  static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  tb_reserve(t, (size + 2) / 3 * 4);
  char* out = t->data + t->size;
  size_t i = 0;
  for (; i + 3 <= size; i += 3) {
    uint32_t v = (uint32_t)data[i] << 16 | (uint32_t)data[i + 1] << 8 | data[i + 2];
    *out++ = alphabet[v >> 18];
    *out++ = alphabet[(v >> 12) & 63];
    *out++ = alphabet[(v >> 6) & 63];
    *out++ = alphabet[v & 63];
  }
  if (i < size) {
    uint32_t v = (uint32_t)data[i] << 16 | (i + 1 < size ? (uint32_t)data[i + 1] << 8 : 0);
    *out++ = alphabet[v >> 18];
    *out++ = alphabet[(v >> 12) & 63];
    *out++ = i + 1 < size ? alphabet[(v >> 6) & 63] : '=';
    *out++ = '=';
  }
  t->size = (size_t)(out - t->data);
  t->data[t->size] = '\0';
}

// ---------------------------------------------------------------- layout

enum { ATTR_POSITION, ATTR_NORMAL, ATTR_TEXCOORD, ATTR_TANGENT, ATTR_COUNT };
static const uint32_t attr_bytes[ATTR_COUNT] = {12, 12, 8, 16};
// Where each attribute's view starts, in bytes per vertex of the whole export.
static const uint32_t attr_offset[ATTR_COUNT] = {0, 12, 24, 32};
enum { VERTEX_BYTES = 48 };
static const char* const attr_names[ATTR_COUNT] = {"POSITION", "NORMAL", "TEXCOORD_0", "TANGENT"};
static const char* const attr_types[ATTR_COUNT] = {"VEC3", "VEC3", "VEC2", "VEC4"};

// One exported glTF node.
typedef struct out_node {
  uint32_t tree_node;
  bk_vec3 centroid;      // in the tree frame
  uint64_t vertex_first; // in vertices, into each attribute view
  uint32_t vertex_count;
  uint32_t triangles[2];    // per material
  uint64_t index_offset[2]; // bytes, into the index view
  bool wide;                // uint32 indices
  uint32_t first_accessor;  // attributes, then the index accessors of the non-empty materials
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
static void write_node_data(const bk_mesh* m, out_node* o, uint8_t* views[ATTR_COUNT], uint8_t* indices) {
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
  for (int mat = 0; mat < 2; ++mat) {
    uint8_t* out = indices + o->index_offset[mat];
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      if ((m->materials[t] == BK_MATERIAL_INTERIOR) != (mat == 1)) continue;
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
  out_node* nodes;
  uint32_t node_count;
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
    tb_fmt(t, "{\"name\":\"fragment_%u\"", n->leaf_begin);
  else
    tb_fmt(t, "{\"name\":\"node_%u\"", o->tree_node);
  tb_fmt(t, ",\"mesh\":%u,\"translation\":", i);
  tb_doubles(t, (const double[3]){translation.x, translation.y, translation.z}, 3);
  if (s->def->levels == BK_GLTF_LEVELS_ALL && n->child_count) {
    tb_raw(t, ",\"children\":[");
    for (uint32_t c = 0; c < n->child_count; ++c)
      tb_fmt(t, c ? ",%u" : "%u", gltf_node_of_tree_node(s, n->first_child + c));
    tb_raw(t, "]");
  }
  const bk_moments* m = &n->moments;
  tb_fmt(t, ",\"extras\":{\"breakables\":{\"node\":%u,\"leaves\":[%u,%u],\"volume\":", o->tree_node,
         n->leaf_begin, n->leaf_end);
  tb_double(t, m->v);
  tb_raw(t, ",\"moments\":");
  tb_doubles(t, (const double[10]){m->v, m->x, m->y, m->z, m->xx, m->yy, m->zz, m->xy, m->yz, m->zx}, 10);
  tb_raw(t, ",\"bounds\":");
  bk_aabb b = n->bounds;
  tb_doubles(t, (const double[6]){b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}, 6);
  tb_raw(t, "}}}");
}

static void write_mesh_json(text_buffer* t, const export_state* s, uint32_t i) {
  const out_node* o = &s->nodes[i];
  const bk_mesh_tree_node* n = &s->tree->nodes[o->tree_node];
  if (n->child_count == 0)
    tb_fmt(t, "{\"name\":\"fragment_%u\",\"primitives\":[", n->leaf_begin);
  else
    tb_fmt(t, "{\"name\":\"node_%u\",\"primitives\":[", o->tree_node);
  uint32_t index_accessor = o->first_accessor + ATTR_COUNT;
  bool first = true;
  for (int mat = 0; mat < 2; ++mat) {
    if (!o->triangles[mat]) continue;
    tb_fmt(t,
           "%s{\"attributes\":{\"POSITION\":%u,\"NORMAL\":%u,\"TEXCOORD_0\":%u,\"TANGENT\":%u},"
           "\"indices\":%u,\"material\":%d}",
           first ? "" : ",", o->first_accessor, o->first_accessor + 1, o->first_accessor + 2,
           o->first_accessor + 3, index_accessor++, mat);
    first = false;
  }
  tb_raw(t, "]}");
}

static void write_accessors_json(text_buffer* t, const export_state* s) {
  bool first = true;
  for (uint32_t i = 0; i < s->node_count; ++i) {
    const out_node* o = &s->nodes[i];
    for (int a = 0; a < ATTR_COUNT; ++a) {
      tb_fmt(t,
             "%s{\"bufferView\":%d,\"byteOffset\":%llu,\"componentType\":5126,\"count\":%u,\"type\":\"%s\"",
             first ? "" : ",", a, (unsigned long long)(o->vertex_first * attr_bytes[a]), o->vertex_count,
             attr_types[a]);
      first = false;
      if (a == ATTR_POSITION) {
        tb_raw(t, ",\"min\":");
        tb_doubles(t, (const double[3]){o->min[0], o->min[1], o->min[2]}, 3);
        tb_raw(t, ",\"max\":");
        tb_doubles(t, (const double[3]){o->max[0], o->max[1], o->max[2]}, 3);
      }
      tb_raw(t, "}");
    }
    for (int mat = 0; mat < 2; ++mat) {
      if (!o->triangles[mat]) continue;
      tb_fmt(
          t,
          ",{\"bufferView\":%d,\"byteOffset\":%llu,\"componentType\":%d,\"count\":%llu,\"type\":\"SCALAR\"}",
          ATTR_COUNT, (unsigned long long)o->index_offset[mat], o->wide ? 5125 : 5123,
          (unsigned long long)o->triangles[mat] * 3u);
    }
  }
}

static void write_material_json(text_buffer* t, const char* name, const char* suffix, int texture,
                                double roughness) {
  tb_raw(t, "{\"name\":");
  char full[96];
  snprintf(full, sizeof full, "%s%s", name, suffix);
  tb_string(t, full);
  tb_raw(
      t,
      ",\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,1,1,1],\"metallicFactor\":0,\"roughnessFactor\":");
  tb_double(t, roughness);
  if (texture >= 0) tb_fmt(t, ",\"baseColorTexture\":{\"index\":%d}", texture);
  tb_raw(t, "}}");
}

static void write_asset_extras(text_buffer* t, const export_state* s) {
  const bk_mesh_tree* tree = s->tree;
  const bk_gltf_def* def = s->def;
  bk_vec3 origin = bk_mesh_tree_origin(tree);
  tb_fmt(t, "\"extras\":{\"breakables\":{\"version\":%d,\"mtree\":{\"bufferView\":%d,\"version\":%u},",
         BK_GLTF_EXTRAS_VERSION, ATTR_COUNT + 1, BK_MTREE_VERSION);
  tb_fmt(t, "\"levels\":\"%s\",\"node_count\":%u,\"leaf_count\":%u,\"max_depth\":%u,\"origin\":",
         def->levels == BK_GLTF_LEVELS_LEAVES ? "leaves" : "all", tree->node_count, tree->leaf_count,
         tree->max_depth);
  tb_doubles(t, (const double[3]){origin.x, origin.y, origin.z}, 3);
  tb_fmt(t, ",\"fracture\":{\"pattern\":\"planes\",\"pieces\":%u,\"seed\":%llu,\"texture_scale\":",
         tree->desc.pieces, (unsigned long long)tree->desc.seed);
  tb_double(t, tree->desc.texture_scale);
  tb_raw(t, ",\"jitter\":");
  tb_double(t, tree->desc.jitter);
  tb_raw(t, ",\"aspect_bias\":");
  tb_double(t, tree->desc.aspect_bias);
  tb_raw(t, "},\"material\":{\"name\":");
  tb_string(t, def->material_name);
  tb_raw(t, ",\"density\":");
  tb_double(t, def->density);
  tb_raw(t, ",\"frailty\":");
  tb_double(t, def->frailty);
  tb_raw(t, ",\"bond_strength\":");
  tb_double(t, def->bond_strength);
  tb_raw(t, "},\"bonds\":[");
  for (uint32_t i = 0; i < tree->bond_count; ++i) {
    const bk_bond* b = &tree->bonds[i];
    tb_fmt(t, "%s[%u,%u,", i ? "," : "", b->leaf_a, b->leaf_b);
    const double v[7] = {b->area,     b->centroid.x, b->centroid.y, b->centroid.z,
                         b->normal.x, b->normal.y,   b->normal.z};
    for (int k = 0; k < 7; ++k) {
      if (k) tb_raw(t, ",");
      tb_double(t, v[k]);
    }
    tb_raw(t, "]");
  }
  tb_raw(t, "]}}");
}

static void write_document(text_buffer* t, const export_state* s, bool glb, const uint8_t* binary) {
  const bk_gltf_def* def = s->def;
  tb_raw(t, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"Breakables (bk_mesh_tree_save_gltf)\",");
  write_asset_extras(t, s);
  tb_raw(t, "},\"scene\":0,\"scenes\":[{\"name\":\"breakables\",\"nodes\":[");
  if (def->levels == BK_GLTF_LEVELS_ALL)
    tb_raw(t, "0");
  else
    for (uint32_t i = 0; i < s->node_count; ++i)
      tb_fmt(t, i ? ",%u" : "%u", i);
  tb_raw(t, "]}],\"nodes\":[");
  for (uint32_t i = 0; i < s->node_count; ++i) {
    if (i) tb_raw(t, ",");
    write_node_json(t, s, i);
  }
  tb_raw(t, "],\"meshes\":[");
  for (uint32_t i = 0; i < s->node_count; ++i) {
    if (i) tb_raw(t, ",");
    write_mesh_json(t, s, i);
  }
  tb_raw(t, "],\"materials\":[");
  int textures = 0, surface_texture = -1, interior_texture = -1;
  if (def->base_color_texture) surface_texture = textures++;
  if (def->interior_texture) interior_texture = textures++;
  write_material_json(t, def->material_name, "", surface_texture, 0.8);
  tb_raw(t, ",");
  write_material_json(t, def->material_name, "_interior", interior_texture, 0.9);
  tb_raw(t, "]");
  if (textures) {
    tb_raw(t, ",\"samplers\":[{\"magFilter\":9729,\"minFilter\":9987,\"wrapS\":10497,\"wrapT\":10497}],"
              "\"images\":[");
    if (def->base_color_texture) {
      tb_raw(t, "{\"uri\":");
      tb_uri(t, def->base_color_texture);
      tb_raw(t, "}");
    }
    if (def->interior_texture) {
      tb_raw(t, textures == 2 ? ",{\"uri\":" : "{\"uri\":");
      tb_uri(t, def->interior_texture);
      tb_raw(t, "}");
    }
    tb_raw(t, "],\"textures\":[{\"sampler\":0,\"source\":0}");
    if (textures == 2) tb_raw(t, ",{\"sampler\":0,\"source\":1}");
    tb_raw(t, "]");
  }
  tb_raw(t, ",\"accessors\":[");
  write_accessors_json(t, s);
  tb_raw(t, "],\"bufferViews\":[");
  for (int a = 0; a < ATTR_COUNT; ++a)
    tb_fmt(t,
           "%s{\"buffer\":0,\"byteOffset\":%llu,\"byteLength\":%llu,\"byteStride\":%u,\"target\":34962,"
           "\"name\":\"%s\"}",
           a ? "," : "", (unsigned long long)(s->vertex_count * attr_offset[a]),
           (unsigned long long)(s->vertex_count * attr_bytes[a]), attr_bytes[a], attr_names[a]);
  tb_fmt(t, ",{\"buffer\":0,\"byteOffset\":%llu,\"byteLength\":%llu,\"target\":34963,\"name\":\"indices\"}",
         (unsigned long long)(s->vertex_count * VERTEX_BYTES), (unsigned long long)s->index_bytes);
  tb_fmt(t, ",{\"buffer\":0,\"byteOffset\":%llu,\"byteLength\":%llu,\"name\":\"breakables_mtree\"}",
         (unsigned long long)s->mtree_offset, (unsigned long long)s->mtree_size);
  tb_fmt(t, "],\"buffers\":[{\"byteLength\":%llu", (unsigned long long)s->binary_size);
  if (!glb) {
    tb_raw(t, ",\"uri\":\"data:application/octet-stream;base64,");
    tb_base64(t, binary, (size_t)s->binary_size);
    tb_raw(t, "\"");
  }
  tb_raw(t, "}]}");
}

// ---------------------------------------------------------------- saving

static bool check_def(const bk_gltf_def* def, const char* path, bk_error* err) {
  if (def->levels != BK_GLTF_LEVELS_ALL && def->levels != BK_GLTF_LEVELS_LEAVES)
    return bk_error_set(err,
                        "%s: gltf def: levels must be BK_GLTF_LEVELS_ALL or BK_GLTF_LEVELS_LEAVES, got %d",
                        path, (int)def->levels);
  size_t name_length = def->material_name ? strlen(def->material_name) : 0;
  if (name_length < 1 || name_length > 63)
    return bk_error_set(err, "%s: gltf def: material_name must be 1 to 63 bytes, got %zu", path, name_length);
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
  uint32_t accessors = 0;
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
    for (uint32_t t = 0; t < m->triangle_count; ++t)
      o->triangles[m->materials[t] == BK_MATERIAL_INTERIOR ? 1 : 0]++;
    o->first_accessor = accessors;
    accessors += ATTR_COUNT;
    for (int mat = 0; mat < 2; ++mat) {
      if (!o->triangles[mat]) continue;
      o->index_offset[mat] = index_bytes;
      index_bytes += ((uint64_t)o->triangles[mat] * 3u * (o->wide ? 4u : 2u) + 3u) & ~(uint64_t)3;
      accessors++;
    }
  }
  s->vertex_count = vertices;
  s->index_bytes = index_bytes;
  s->accessor_count = accessors;
  s->mtree_offset = vertices * VERTEX_BYTES + index_bytes;
  s->binary_size = s->mtree_offset + ((s->mtree_size + 3u) & ~(uint64_t)3);
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
  plan(&s);
  // GLB lengths are 32-bit; a .gltf's base64 text is a third larger still.
  const uint64_t limit = (uint64_t)3 << 30;
  if (s.binary_size > limit) {
    free(mtree);
    free(s.nodes);
    return bk_error_set(
        err, "%s: the export would hold %llu bytes of binary data, more than glTF's 3 GiB limit here", path,
        (unsigned long long)s.binary_size);
  }
  uint8_t* binary = bk_calloc((size_t)s.binary_size, 1);
  uint8_t* views[ATTR_COUNT];
  for (int a = 0; a < ATTR_COUNT; ++a)
    views[a] = binary + s.vertex_count * attr_offset[a];
  for (uint32_t i = 0; i < s.node_count; ++i)
    write_node_data(&tree->nodes[s.nodes[i].tree_node].mesh, &s.nodes[i], views,
                    binary + s.vertex_count * VERTEX_BYTES);
  memcpy(binary + s.mtree_offset, mtree, mtree_size);
  free(mtree);

  text_buffer json = {0};
  bk_c_locale c_locale = bk_c_locale_begin(); // JSON numbers need '.'
  write_document(&json, &s, glb, binary);
  bk_c_locale_end(&c_locale);
  free(s.nodes);

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
