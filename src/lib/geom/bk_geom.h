// geom (private): what authoring's files share above base (half-edge
// topology, exact mesh copies, OBJ materials, images, extruded shapes).
// Not installed: the public API is <breakables/authoring.h>.
#pragma once

#include <locale.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <breakables/authoring.h>

#include "bk_base.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- utilities

/// A copy of `src` into `dst` (overwritten, not freed) whose arrays hold
/// exactly its contents: for meshes that are kept (a tree's nodes) but
/// built in storage that is reused.
void bk_mesh_copy_exact(bk_mesh* dst, const bk_mesh* src);

/// Half-edges: h = 3t + k runs from corner k of triangle t to corner k + 1.
static inline uint32_t bk_half_next(uint32_t h) { return h % 3u == 2u ? h - 2u : h + 1u; }
static inline uint32_t bk_half_prev(uint32_t h) { return h % 3u == 0u ? h + 2u : h - 1u; }

/// A mesh's half-edges grouped by the position they start at, for topology
/// tests that scan a vertex's few neighbours instead of hashing edges.
/// Reused between meshes; zero-initialised is empty.
typedef struct bk_topology_scratch {
  uint32_t* start;  ///< per position + 1: first entry of its group in `around`
  uint32_t* mark;   ///< per position, free for the caller between groupings
  uint32_t* from;   ///< per half-edge: its start position
  uint32_t* around; ///< half-edges by start position, each group in increasing h
  uint32_t position_capacity, half_capacity;
} bk_topology_scratch;

/// Fills `from`, `start` and `around` for `mesh`.
void bk_topology_group(bk_topology_scratch* scratch, const bk_mesh* mesh);
/// bk_mesh_is_closed with reused storage.
bool bk_mesh_is_closed_with(const bk_mesh* mesh, bk_topology_scratch* scratch);
void bk_topology_scratch_free(bk_topology_scratch* scratch);

/// Longest material name an OBJ file's `usemtl` keeps (with the NUL).
#define BK_OBJ_MATERIAL_NAME 64
/// The materials an OBJ file names.
typedef struct bk_obj_materials {
  char names[BK_MATERIAL_SOURCES_MAX][BK_OBJ_MATERIAL_NAME]; ///< by source id ("" = faces before any usemtl)
  uint32_t count;                                            ///< 0 when the file has no usemtl
  uint32_t merged;                                           ///< usemtl names past the limit, given id 0
  char library[512];                                         ///< the first `mtllib` file, as written
} bk_obj_materials;
/// bk_obj_parse that also reports the `usemtl` names (their ids are the
/// triangles' source materials) and the `mtllib` file.
bool bk_obj_parse_materials(const char* text, size_t length, const char* name, bk_mesh* out,
                            bk_obj_materials* materials, bk_error* err);
/// Reads an MTL file's text into `list` (one entry per name in `materials`,
/// zeroed or filled before): each named material's `Kd` (and `d` or `Tr`)
/// colour and `map_Kd` file name, as written. Unknown statements and values
/// that are not finite numbers in [0, 1] are skipped, as a renderer would.
void bk_mtl_parse(const char* text, size_t length, const bk_obj_materials* materials,
                  bk_import_material* list);

/// Encodes `width` x `height` RGBA pixels as a PNG file's bytes (*png,
/// released with bk_free); false if they cannot be.
bool bk_png_encode_rgba(const uint8_t* rgba, uint32_t width, uint32_t height, uint8_t** png, size_t* size);
/// The most pixels an image converted or drawn may have (256 MiB as RGBA).
#define BK_IMAGE_MAX_PIXELS ((uint64_t)1 << 26)

// ---------------------------------------------------------------- shapes

/// Most corners an extruded polygon may have (the caps' ears are kept on the stack).
#define BK_EXTRUSION_MAX_CORNERS 64

/// A prism: a simple polygon in the plane of x_axis and y_axis, extruded
/// along depth = x_axis x y_axis from depth_from to depth_to.
typedef struct bk_extrusion {
  const double (*profile)[2];  ///< the polygon's corners (x, y), counter-clockwise, edges not crossing
  uint32_t corner_count;       ///< 3 to BK_EXTRUSION_MAX_CORNERS
  bk_vec3 x_axis, y_axis;      ///< orthonormal world directions of the profile's coordinates
  double depth_from, depth_to; ///< the prism's extent along depth; depth_to > depth_from
} bk_extrusion;

/// Appends the prism to `m`: 2n positions, a flat quad (4 corners) per edge
/// and two caps of n - 2 ear triangles on the polygon's own corners, so
/// 6n corners and 4n - 4 triangles, closed by topology and facing out. uvs
/// are in metres like the boxes' (world coordinates along each face, v up
/// on vertical faces); tangents are left for bk_mesh_compute_tangents.
/// False (nothing added) when the polygon has too few or too many corners,
/// the depth is empty, or ear clipping finds no ear (a clockwise polygon,
/// most that cross themselves: a simple counter-clockwise one always has one).
bool bk_shape_extrude(bk_mesh* m, const bk_extrusion* def);

#ifdef __cplusplus
}
#endif
