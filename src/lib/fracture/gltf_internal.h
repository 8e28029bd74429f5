// Internal: what the glTF writer and reader share (see docs/gltf.md).
#pragma once

/// Version of the asset.extras.breakables schema.
#define BK_GLTF_EXTRAS_VERSION 2

/// GLB container: "glTF", version 2, then chunks of (length, type, data).
#define BK_GLB_MAGIC 0x46546C67u
#define BK_GLB_VERSION 2u
#define BK_GLB_CHUNK_JSON 0x4E4F534Au
#define BK_GLB_CHUNK_BIN 0x004E4942u

/// The prefix of a .gltf buffer's data URI.
#define BK_GLTF_DATA_URI "data:application/octet-stream;base64,"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <breakables/authoring.h>

// ---------------------------------------------------------------- JSON text (gltf_text.c)

/// A growing NUL-terminated text.
typedef struct text_buffer {
  char* data;
  size_t size, capacity;
} text_buffer;

/// Makes room for `extra` more bytes (and the NUL).
void bk_tb_reserve(text_buffer* t, size_t extra);
/// Appends text as it is.
void bk_tb_raw(text_buffer* t, const char* s);
/// Appends formatted text.
__attribute__((format(printf, 2, 3))) void bk_tb_fmt(text_buffer* t, const char* fmt, ...);
/// Appends a finite double with 17 significant digits (reads back exactly).
void bk_tb_double(text_buffer* t, double v);
/// Appends a JSON array of n doubles.
void bk_tb_doubles(text_buffer* t, const double* v, int n);
/// Appends a JSON string (quotes, backslashes and control characters escaped).
void bk_tb_string(text_buffer* t, const char* s);
/// Appends a path as a quoted URI reference (all but letters, digits and -._~/ percent-encoded).
void bk_tb_uri(text_buffer* t, const char* path);
/// Appends bytes as base64.
void bk_tb_base64(text_buffer* t, const uint8_t* data, size_t size);

// ---------------------------------------------------------------- materials (gltf_materials.c)

/// One image of the export: bytes in the binary buffer (own buffer view) or a URI.
typedef struct gltf_image_slot {
  const bk_gltf_image* image;
  uint64_t offset; ///< of the bytes in the binary buffer (data images)
  uint32_t view;   ///< their buffer view (data images)
} gltf_image_slot;

/// The export's materials (2 per source material), textures and images.
typedef struct gltf_materials {
  const bk_gltf_material* list; ///< the def's, or the one default
  uint32_t source_count;        ///< source materials written (>= 1)
  int32_t* texture_of;          ///< per export material: its texture (= image) index, or -1
  gltf_image_slot* images;
  uint32_t image_count;
  uint64_t bytes; ///< image bytes in the binary buffer, each image padded to 4
} gltf_materials;

/// Checks the def's materials; the message names the field.
bool bk_gltf_check_materials(const bk_gltf_def* def, const char* path, bk_error* err);
/// Lays the materials and images out: data images go at `binary_offset`
/// onwards in the binary buffer, with buffer views from `first_view`. `fallback`
/// is used when the def lists none.
void bk_gltf_plan_materials(const bk_gltf_def* def, const bk_gltf_material* fallback, uint64_t binary_offset,
                            uint32_t first_view, gltf_materials* out);
/// The export material (glTF material index) of a triangle material id.
uint32_t bk_gltf_material_index(const gltf_materials* m, uint8_t id);
/// Copies the data images into the binary buffer.
void bk_gltf_write_image_data(const gltf_materials* m, uint8_t* binary);
/// Writes `"materials":[...]` and, when there are images, the samplers,
/// images and textures arrays (each preceded by a comma).
void bk_gltf_write_materials_json(text_buffer* t, const gltf_materials* m);
/// Writes the images' buffer views (each preceded by a comma).
void bk_gltf_write_image_views_json(text_buffer* t, const gltf_materials* m);
/// Frees what the plan allocated.
void bk_gltf_materials_free(gltf_materials* m);

// ---------------------------------------------------------------- vertices (gltf_vertices.c)

/// Floats per exported vertex: POSITION (3), NORMAL (3), TEXCOORD_0 (2), TANGENT (4).
#define BK_GLTF_VERTEX_FLOATS 12

/// A node's mesh as the export's vertices: corners whose exported attributes
/// are bit-identical share one vertex.
typedef struct gltf_vertices {
  float* data;         ///< BK_GLTF_VERTEX_FLOATS per vertex
  uint32_t count;      ///< vertices
  uint32_t* of_corner; ///< the vertex of each corner of the mesh
} gltf_vertices;

/// Welds a mesh's corners into vertices: the position relative to `centroid`
/// (as floats), the unit normal, the UV and the unit tangent with w = +1 or -1.
void bk_gltf_weld(const bk_mesh* m, bk_vec3 centroid, gltf_vertices* out);
/// Frees what bk_gltf_weld allocated.
void bk_gltf_vertices_free(gltf_vertices* v);

// ---------------------------------------------------------------- extras (gltf_extras.c)

/// Bytes of one node record of the `nodes` buffer view: f64 moments[10],
/// f64 bounds[6], u32 parent, leaf_begin, leaf_end, depth.
#define BK_GLTF_NODE_RECORD_BYTES 144u
/// Bytes of one bond record of the `bonds` buffer view: u32 leaf_a, leaf_b,
/// f64 area, f64 centroid[3], f64 normal[3].
#define BK_GLTF_BOND_RECORD_BYTES 64u

/// Writes every tree node's record (in tree-node order).
void bk_gltf_write_node_records(const bk_mesh_tree* tree, uint8_t* out);
/// Writes every bond's record.
void bk_gltf_write_bond_records(const bk_mesh_tree* tree, uint8_t* out);

/// Where the records and the tree went (buffer view indices; -1 for none).
typedef struct gltf_extras_views {
  int32_t nodes, bonds, mtree;
} gltf_extras_views;

/// Writes `"extras":{"breakables":{...}}` of the asset. `material_name` is
/// the first source material's.
void bk_gltf_write_asset_extras(text_buffer* t, const bk_mesh_tree* tree, const bk_gltf_def* def,
                                const char* material_name, const gltf_extras_views* views);
/// The `levels` name of asset.extras.breakables ("hierarchy", "leaves", "all").
const char* bk_gltf_levels_name(bk_gltf_levels levels);

// ---------------------------------------------------------------- compression (gltf_meshopt.c)

/// Most bytes meshoptimizer's vertex codec writes for count vertices of `stride` bytes
/// (0 in a build without meshoptimizer, BK_NO_MESHOPT: gltf_meshopt_none.c).
size_t bk_gltf_meshopt_bound(size_t count, size_t stride);
/// Encodes count vertices of `stride` bytes (a multiple of 4, at most 256)
/// into out; returns the bytes written (0 when capacity is too small).
size_t bk_gltf_meshopt_encode(const uint8_t* vertices, size_t count, size_t stride, uint8_t* out,
                              size_t capacity);
