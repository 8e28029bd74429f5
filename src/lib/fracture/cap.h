// Internal: triangulation of the planar polygons that close a cut.
#pragma once

#include "bk_fracture.h"

/// Scratch state and the GLU tessellator; reused across caps.
typedef struct bk_cap bk_cap;

bk_cap* bk_cap_create(void);
void bk_cap_destroy(bk_cap* cap);

/// bk_slicer_slice into meshes whose storage is kept and reused (their
/// contents are replaced; free them with bk_mesh_free when done).
bool bk_slicer_slice_reuse(bk_slicer* slicer, const bk_mesh* mesh, const bk_slice_def* def, bk_mesh* below,
                           bk_mesh* above, bk_error* err);

/// Triangulates the region bounded by closed loops given as directed edges
/// between local vertices 0..vertex_count-1 (2D coordinates in `xy`). Loops
/// may be nested (polygons, holes, islands in holes: ODD winding). The
/// triangles use only the given vertices and are oriented so that their
/// outer edges are exactly the input edges; this is verified. On success
/// *triangles points to 3 * *triangle_count local indices owned by `cap`,
/// valid until its next use.
bool bk_cap_triangulate(bk_cap* cap, const uint32_t* edges, uint32_t edge_count, const double* xy,
                        uint32_t vertex_count, const uint32_t** triangles, uint32_t* triangle_count,
                        bk_error* err);

/// Grid spacing of a noisy cap in noise waves (about three points per wave).
#define BK_CAP_NOISE_SPACING (1.0 / 3.0)
/// Grid nodes a noisy cap may take at most: a larger cap gets a coarser grid.
/// (memory_estimate.c counts the points a fracture's caps get by these two.)
#define BK_CAP_NOISE_MAX_NODES 2500.0

/// How a cap is made noisy (see cap_noise.c); all in the cap's units.
typedef struct bk_cap_noise_def {
  bk_vec3 normal;   ///< the cap's plane normal: points move along it
  double amplitude; ///< > 0; 0 leaves the cap as it is
  double frequency; ///< waves per unit
  double limit;     ///< no point moves further (the pieces' depth behind the cap)
  uint64_t seed;
} bk_cap_noise_def;

/// A noisy cap: the input points first (unchanged), then the new ones.
typedef struct bk_cap_noise {
  bk_vec3* points;
  uint32_t point_count, point_capacity;
  uint32_t* triangles; ///< 3 per triangle, indices into points
  uint32_t* parents;   ///< per triangle: the input triangle it came from (gives its material)
  uint32_t triangle_count, triangle_capacity;
} bk_cap_noise;

/// Meshes a cap triangulation (`triangles` over `points`, all in the plane)
/// at the noise's resolution, keeping its border, and pushes the new points
/// along the normal by coherent noise, tapered to zero at the border; `out`
/// keeps its storage between calls.
void bk_cap_noise_make(const bk_cap_noise_def* def, const uint32_t* triangles, uint32_t triangle_count,
                       const bk_vec3* points, uint32_t point_count, bk_cap_noise* out);
void bk_cap_noise_free(bk_cap_noise* noise);

/// Coherent noise in [-1, 1] (stb_perlin, under our own name).
double bk_noise3(bk_vec3 p, int seed);

/// Re-triangulates planar faces over their true corners (see simplify.c).
typedef struct bk_face_simplifier bk_face_simplifier;

bk_face_simplifier* bk_face_simplifier_create(void);
void bk_face_simplifier_destroy(bk_face_simplifier* fs);
/// Leaves the faces of cuts (tags below BK_SOURCE_FACE_TAG) as they are:
/// noisy cut faces are not planar (default: false, every face is redone).
void bk_face_simplifier_keep_cuts(bk_face_simplifier* fs, bool keep);
/// Writes `mesh` to `out` (overwritten; its arrays allocated to the sizes it
/// needs) with the triangles of each planar face replaced by a
/// triangulation of the face's outline, dropping vertices inside faces and
/// on straight edges between two faces. Returns false, writing `mesh` as it
/// is, when a face cannot be re-triangulated.
bool bk_face_simplifier_run(bk_face_simplifier* fs, const bk_mesh* mesh, bk_mesh* out);

/// Tags of source-mesh faces start here, above any cut id (cut ids are node
/// index + 1), so a tag names either one cut or one planar source face.
#define BK_SOURCE_FACE_TAG 0x80000000u

/// Labels each planar region of a source mesh (adjacent coplanar triangles
/// sharing corners and material) with its own tag from BK_SOURCE_FACE_TAG.
void bk_label_planar_faces(bk_mesh* mesh);
