// fracture: plane slicing with triangulated caps, hull separation, the mesh
// tree (root = source mesh, leaves = fragments), bonds between touching
// fragments, and the .mtree cache file. Pure C: no GL context, no physics.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "bk_geom.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- slicing

/// Reusable scratch state for slicing (buffers and the cap tessellator).
/// One per thread; create once and slice many meshes with it.
typedef struct bk_slicer bk_slicer;

/// Creates a slicer.
bk_slicer* bk_slicer_create(void);
/// Destroys a slicer; NULL is allowed.
void bk_slicer_destroy(bk_slicer* slicer);

/// How to slice one mesh.
typedef struct bk_slice_desc {
  bk_plane plane;       ///< unit normal points from `below` to `above`
  double tolerance;     ///< vertices closer than this count as on the plane; 0 = 1e-9 x mesh size
  double texture_scale; ///< cap uv = plane coordinates / texture_scale (world size of one tile); 0 = 0.1
  uint32_t cap_tag;     ///< tag written on the cap triangles (identifies the cut)
} bk_slice_desc;

/// Splits a closed mesh by a plane into the part below (signed distance < 0)
/// and above, each closed with a triangulated cap (ODD winding: holes and
/// islands in holes are handled). Topology is carried by indices: every cut
/// edge gets one new vertex shared by both sides. `below`/`above` are
/// overwritten; a side the plane misses comes back empty. Fails (with the
/// meshes freed) only if a cap cannot be closed.
bool bk_slicer_slice(bk_slicer* slicer, const bk_mesh* mesh, const bk_slice_desc* desc, bk_mesh* below,
                     bk_mesh* above, bk_error* err);

/// Triangulates simple boundary loops of an open mesh (a repair for
/// almost-closed inputs). Returns the number of loops filled, or -1 with err
/// set if the mesh cannot be closed this way (non-manifold edges, failed loop).
int bk_mesh_fill_holes(bk_mesh* mesh, bk_error* err);

// ---------------------------------------------------------------- hulls

/// Separates a closed mesh into its connected solids. Cavities (inward-facing
/// closed components, e.g. the inside of an eggshell) stay with the solid that
/// contains them. Takes ownership of `mesh` (it is zeroed on return; a mesh
/// that is one hull is moved, not copied). Returns the number of meshes
/// written to *out (allocated; free each mesh and the array).
uint32_t bk_mesh_split_hulls(bk_mesh* mesh, bk_mesh** out);

// ---------------------------------------------------------------- mesh tree

/// Parameters of a fracture. Zero-initialised fields mean "default".
typedef struct bk_fracture_desc {
  uint32_t pieces; ///< target leaf count (at least this many, exactly when every split gives two); 0 = 256
  uint64_t seed;   ///< random seed; the same seed gives the same tree
  double texture_scale; ///< world size of one interior texture tile; 0 = 0.1
  double jitter; ///< plane offset jitter, fraction of the piece's extent (0 = exactly through the centroid)
  /// Tilts each cut's normal towards the piece's longest principal axis:
  /// normal = normalize(uniform direction + aspect_bias x axis). 0 (the
  /// default) gives uniformly distributed directions, as in the thesis; about
  /// 1.5 gives chunky fragments instead of plates and shards on thin or long
  /// shapes (walls, slabs, pillars), which also stack and collide far better.
  double aspect_bias;
  /// Optional progress report, called from the building thread with the leaf
  /// count so far; returning false cancels the build.
  bool (*progress)(void* user, uint32_t leaves, uint32_t target);
  void* progress_user;
} bk_fracture_desc;

/// Default fracture parameters (the thesis's: 256 pieces, seed 3000, texture scale 0.1).
bk_fracture_desc bk_default_fracture_desc(void);
/// Checks a description; err names the wrong field.
bool bk_fracture_desc_validate(const bk_fracture_desc* desc, bk_error* err);

#define BK_NULL_INDEX UINT32_MAX

/// One node: the mesh of one intermediate piece. Children are contiguous in
/// the node array; leaves are numbered so every subtree covers the contiguous
/// leaf range [leaf_begin, leaf_end).
typedef struct bk_mesh_tree_node {
  bk_mesh mesh;
  bk_aabb bounds;
  bk_moments moments; ///< raw volume moments (additive across nodes)
  bk_plane plane;     ///< the plane that split this node (meaningless for leaves)
  uint32_t parent;    ///< BK_NULL_INDEX for the root
  uint32_t first_child, child_count;
  uint32_t leaf_begin, leaf_end;
  uint32_t depth;
} bk_mesh_tree_node;

/// A bond between two truly touching leaves, measured on their shared cut.
typedef struct bk_bond {
  uint32_t leaf_a, leaf_b; ///< leaf indices, leaf_a < leaf_b
  double area;             ///< contact area
  bk_vec3 centroid;        ///< centroid of the contact region
  bk_vec3 normal;          ///< unit normal of the contact, pointing from leaf_a to leaf_b
} bk_bond;

/// The whole fracture result.
typedef struct bk_mesh_tree {
  bk_mesh_tree_node* nodes; ///< nodes[0] is the root (the source mesh)
  uint32_t node_count;
  uint32_t* leaf_nodes; ///< node index of each leaf
  uint32_t leaf_count;
  bk_bond* bonds;
  uint32_t bond_count;
  uint32_t max_depth;
  uint64_t source_hash;  ///< bk_mesh_hash of the source
  bk_fracture_desc desc; ///< the parameters that made it (callbacks cleared)
} bk_mesh_tree;

/// Builds the mesh tree of a closed mesh: repeatedly splits the largest-volume
/// leaf by a random plane through its centroid; every piece is kept. Computes
/// bonds. Fails with a clear message on an open mesh or a bad description.
bool bk_mesh_tree_build(const bk_mesh* source, const bk_fracture_desc* desc, bk_mesh_tree* out,
                        bk_error* err);
/// Releases everything; safe on a zeroed tree.
void bk_mesh_tree_free(bk_mesh_tree* tree);
/// Node index of leaf i.
static inline const bk_mesh_tree_node* bk_mesh_tree_leaf(const bk_mesh_tree* tree, uint32_t leaf) {
  return &tree->nodes[tree->leaf_nodes[leaf]];
}

/// Computes the bonds of a tree's leaves from their coplanar, opposite-facing
/// cap triangles (replaces tree->bonds). Called by bk_mesh_tree_build.
void bk_mesh_tree_compute_bonds(bk_mesh_tree* tree);

/// Statistics for reports and tests.
typedef struct bk_mesh_tree_stats {
  uint32_t leaf_triangles;    ///< triangles over all leaves
  uint32_t open_nodes;        ///< nodes whose mesh is not closed (0 when all is well)
  double source_volume;       ///< root volume
  double leaf_volume_sum;     ///< sum of leaf volumes
  double max_child_rel_error; ///< worst |sum(children) - parent| / parent over inner nodes
  double min_leaf_volume, max_leaf_volume;
} bk_mesh_tree_stats;

/// Checks every node (closure, volumes). O(total triangles).
bk_mesh_tree_stats bk_mesh_tree_measure(const bk_mesh_tree* tree);

// ---------------------------------------------------------------- cache file

/// Current .mtree format version.
#define BK_MTREE_VERSION 2u

/// Writes the tree to a versioned, checksummed binary file (via a temporary
/// file and rename, so an existing file is never half-written).
bool bk_mesh_tree_save(const bk_mesh_tree* tree, const char* path, bk_error* err);
/// Loads a tree; verifies magic, version, sizes, checksum and every index.
/// On failure *out stays zeroed and err says what is wrong.
bool bk_mesh_tree_load(const char* path, bk_mesh_tree* out, bk_error* err);

#ifdef __cplusplus
}
#endif
