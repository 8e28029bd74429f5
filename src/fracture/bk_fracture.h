// fracture (private): the authoring API plus geom's shared utilities, for
// the fracture files. Not installed: the public API is <breakables/authoring.h>.
#pragma once

#include <breakables/authoring.h>

#include <unistd.h>

#include "bk_geom.h"

/// The .mtree file's bytes in memory (what bk_mesh_tree_save writes): *data
/// is allocated (free() it). `name` prefixes error messages.
bool bk_mesh_tree_save_memory(const bk_mesh_tree* tree, const char* name, uint8_t** data, size_t* size,
                              bk_error* err);
/// Loads a tree from .mtree bytes in memory, with every check of
/// bk_mesh_tree_load; `name` prefixes error messages.
bool bk_mesh_tree_load_memory(const void* data, size_t size, const char* name, bk_mesh_tree* out,
                              bk_error* err);

/// Winding number of a closed mesh around a point (sum of signed solid
/// angles, Van Oosterom-Strackee): ~1 inside, ~0 outside, 1/2 on the
/// surface. With tri_component, only the triangles labelled `component` count.
double bk_mesh_winding_number(const bk_mesh* mesh, const uint32_t* tri_component, uint32_t component,
                              bk_vec3 q);

/// True when the triangles of `mesh` form one connected piece (then
/// bk_mesh_split_hulls would return it as it is); `scratch` is reused storage.
bool bk_mesh_is_connected_with(const bk_mesh* mesh, bk_topology_scratch* scratch);

/// Splits a closed mesh into the parts bk_mesh_tree_build fractures on their
/// own when some of its solid shells (bk_mesh_split_hulls: cavities stay with
/// their solid) overlap or touch another (along a line or over an area):
/// each such shell alone, in the shells' order, then all the other shells
/// together (if any). Returns the number of parts written to *parts
/// (allocated; free each mesh and the array), or 0 (and *parts NULL) when no
/// two shells overlap or touch. *overlap says which did, in the mesh's
/// coordinates.
uint32_t bk_mesh_split_overlapping_shells(const bk_mesh* mesh, bk_mesh** parts, bk_fracture_overlap* overlap);

/// Merges the pieces of one split until `target` remain (when there are more):
/// the smallest piece by volume (ties: lower index) joins its nearest piece
/// (bk_mesh_append) on the same side of the cut, else one across the cut
/// whose caps (triangles tagged cap_tag; 0: none) meet its own, else the
/// nearest; nearest by centroid distance, ties by lower index. Pieces
/// [0, below_count) lie below the cut, the rest above. Merged meshes stay
/// closed and their moments are summed; the remaining pieces keep their
/// order. Returns the new count.
uint32_t bk_merge_pieces(bk_mesh* pieces, bk_moments* moments, uint32_t count, uint32_t below_count,
                         uint32_t cap_tag, uint32_t target);

/// Builds the tree of the cell patterns (Voronoi, clustered, radial,
/// cut-out): the source is divided into convex cells, every piece's faces
/// come from one shared cell complex (so every node is closed by topology
/// and neighbours share their faces exactly), and inner nodes are groups of
/// adjacent cells. `def` is validated and the source checked.
bool bk_cell_tree_build(const bk_mesh* source, const bk_fracture_def* def, bk_mesh_tree* tree, bk_error* err);
/// Builds the tree of the planes and brick patterns (leaves, nodes, planes
/// and shortfall; the caller numbers the leaves and computes the bonds).
/// `def` is validated and the source checked.
bool bk_plane_tree_build(const bk_mesh* source, const bk_fracture_def* def, bk_mesh_tree* tree,
                         bk_error* err);
/// Numbers the leaves depth first (each subtree covers a contiguous range)
/// and fills leaf_nodes, leaf_count and every node's leaf range.
void bk_mesh_tree_number_leaves(bk_mesh_tree* tree);
/// Bonds of a cell-pattern tree: leaves that share cut-face triangles of one
/// face (tagged with the face) are bonded with the area, centroid and
/// area-weighted normal of what they share.
void bk_cell_tree_compute_bonds(bk_mesh_tree* tree);
/// True for the patterns whose trees bk_cell_tree_build makes.
static inline bool bk_fracture_pattern_is_cellular(bk_fracture_pattern p) {
  return p == BK_PATTERN_VORONOI || p == BK_PATTERN_CLUSTERED || p == BK_PATTERN_RADIAL ||
         p == BK_PATTERN_CUTOUT;
}
/// Threads for `jobs` units of work: def->threads (0: every core), at most
/// one per `jobs_per_thread` units (small jobs are not worth a thread) and
/// at most 64; at least 1.
static inline uint32_t bk_fracture_thread_count(const bk_fracture_def* d, uint64_t jobs,
                                                uint64_t jobs_per_thread) {
  long cores = sysconf(_SC_NPROCESSORS_ONLN);
  uint64_t n = d->threads ? d->threads : (cores > 0 ? (uint64_t)cores : 1u);
  uint64_t most = jobs / jobs_per_thread > 1 ? jobs / jobs_per_thread : 1;
  n = n < most ? n : most;
  return (uint32_t)(n < 64 ? n : 64);
}
/// Runs work(jobs + j * job_size) for every j < count: job 0 on the calling
/// thread, each other on a thread of its own (or on the calling thread when
/// none can be started); returns when all are done.
void bk_fracture_run_jobs(void* (*work)(void*), void* jobs, size_t job_size, uint32_t count);
/// Clears what a tree's desc must not keep (callbacks, borrowed arrays).
static inline void bk_fracture_def_clear_borrowed(bk_fracture_def* d) {
  d->progress = NULL;
  d->progress_user = NULL;
  d->seed_points = NULL;
  d->cutout_pixels = NULL;
}
