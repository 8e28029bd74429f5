// Our data in a glTF export (docs/gltf.md, "Extras"): asset.extras.breakables
// in JSON, and the per-node and per-bond numbers as little-endian records in
// buffer views (64 bytes a bond instead of about 170 of JSON text), with the
// doubles' exact bits.
#include <string.h>

#include "bk_fracture.h"
#include "gltf_internal.h"

static void put_u32le(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

static void put_f64le(uint8_t* p, double d) {
  uint64_t v = 0;
  memcpy(&v, &d, sizeof v);
  for (int i = 0; i < 8; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

void bk_gltf_write_node_records(const bk_mesh_tree* tree, uint8_t* out) {
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    const bk_mesh_tree_node* n = &tree->nodes[i];
    uint8_t* r = out + (size_t)i * BK_GLTF_NODE_RECORD_BYTES;
    const bk_moments* m = &n->moments;
    const double values[16] = {m->v,
                               m->x,
                               m->y,
                               m->z,
                               m->xx,
                               m->yy,
                               m->zz,
                               m->xy,
                               m->yz,
                               m->zx,
                               n->bounds.min.x,
                               n->bounds.min.y,
                               n->bounds.min.z,
                               n->bounds.max.x,
                               n->bounds.max.y,
                               n->bounds.max.z};
    for (int k = 0; k < 16; ++k)
      put_f64le(r + 8 * k, values[k]);
    put_u32le(r + 128, n->parent);
    put_u32le(r + 132, n->leaf_begin);
    put_u32le(r + 136, n->leaf_end);
    put_u32le(r + 140, n->depth);
  }
}

void bk_gltf_write_bond_records(const bk_mesh_tree* tree, uint8_t* out) {
  for (uint32_t i = 0; i < tree->bond_count; ++i) {
    const bk_bond* b = &tree->bonds[i];
    uint8_t* r = out + (size_t)i * BK_GLTF_BOND_RECORD_BYTES;
    put_u32le(r, b->leaf_a);
    put_u32le(r + 4, b->leaf_b);
    const double values[7] = {b->area,     b->centroid.x, b->centroid.y, b->centroid.z,
                              b->normal.x, b->normal.y,   b->normal.z};
    for (int k = 0; k < 7; ++k)
      put_f64le(r + 8 + 8 * k, values[k]);
  }
}

const char* bk_gltf_levels_name(bk_gltf_levels levels) {
  switch (levels) {
  case BK_GLTF_LEVELS_LEAVES:
    return "leaves";
  case BK_GLTF_LEVELS_ALL:
    return "all";
  case BK_GLTF_LEVELS_HIERARCHY:
  default:
    return "hierarchy";
  }
}

// `"key":{"bufferView":k,"count":n,"byteStride":s}`, or the count alone
// without a view (a tree without bonds: glTF has no empty buffer views).
static void write_records(text_buffer* t, const char* key, int32_t view, uint32_t count, uint32_t stride) {
  bk_tb_fmt(t, ",\"%s\":{", key);
  if (view >= 0) bk_tb_fmt(t, "\"bufferView\":%d,", view);
  bk_tb_fmt(t, "\"count\":%u,\"byteStride\":%u}", count, stride);
}

void bk_gltf_write_asset_extras(text_buffer* t, const bk_mesh_tree* tree, const bk_gltf_def* def,
                                const char* material_name, const gltf_extras_views* views) {
  bk_vec3 origin = bk_mesh_tree_origin(tree);
  bk_tb_fmt(t, "\"extras\":{\"breakables\":{\"version\":%d", BK_GLTF_EXTRAS_VERSION);
  if (views->mtree >= 0)
    bk_tb_fmt(t, ",\"mtree\":{\"bufferView\":%d,\"version\":%u}", views->mtree, BK_MTREE_VERSION);
  bk_tb_fmt(t, ",\"levels\":\"%s\",\"node_count\":%u,\"leaf_count\":%u,\"max_depth\":%u,\"origin\":",
            bk_gltf_levels_name(def->levels), tree->node_count, tree->leaf_count, tree->max_depth);
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
  bk_tb_string(t, material_name);
  bk_tb_raw(t, ",\"density\":");
  bk_tb_double(t, def->density);
  bk_tb_raw(t, ",\"frailty\":");
  bk_tb_double(t, def->frailty);
  bk_tb_raw(t, ",\"bond_strength\":");
  bk_tb_double(t, def->bond_strength);
  bk_tb_raw(t, "}");
  write_records(t, "nodes", views->nodes, tree->node_count, BK_GLTF_NODE_RECORD_BYTES);
  write_records(t, "bonds", views->bonds, tree->bond_count, BK_GLTF_BOND_RECORD_BYTES);
  bk_tb_raw(t, "}}");
}
