// fracture (private): the authoring API plus geom's shared utilities, for
// the fracture files. Not installed: the public API is <breakables/authoring.h>.
#pragma once

#include <breakables/authoring.h>

#include <unistd.h>

#include "bk_geom.h"

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

/// Face-level repairs (repair_faces.c). Removes every triangle listed again
/// with the same positions in the same turn (from any corner); returns how
/// many were removed.
uint32_t bk_mesh_remove_duplicate_triangles(bk_mesh* mesh);
/// Turns every patch of triangles wound against the surface around it
/// (patches meet across edges of two triangles both using them the same
/// way; in each group of patches the lesser area is turned); edges of one
/// or of three or more triangles are left alone. Returns the triangles turned.
uint32_t bk_mesh_turn_flipped_patches(bk_mesh* mesh);
/// Whether volume moments (their centroid moved by `offset` into the frame
/// of `bounds`) are a solid's: volume positive, centre of mass inside the
/// bounds, principal moments positive, within volume x diagonal^2 and
/// satisfying the triangle inequality, and with `frame`, principal axes
/// orthonormal (the eigen decomposition; without it a quick test of the
/// same moments decides unless it fails). A surface that crosses itself or
/// is partly inside out fails it; `why` then names `name` and the quantity.
bool bk_solid_mass_check(const bk_moments* moments, bk_vec3 offset, bk_aabb bounds, bool frame,
                         const char* name, bk_error* why);
/// The part of bk_mesh_tree_validate a tree just built can fail (its
/// structure and volumes hold by construction): every leaf's mass a solid's
/// (bk_solid_mass_check) and every bond's area, centroid and normal.
bool bk_mesh_tree_check_built(const bk_mesh_tree* tree, bk_error* err);
/// The length of a box's diagonal.
double bk_aabb_diagonal(bk_aabb b);
/// The largest absolute coordinate of a box's corners.
double bk_aabb_largest_coordinate(bk_aabb b);
/// How far a point may lie outside bounds and still count as inside them
/// (a millionth of the diagonal plus rounding of the coordinates).
double bk_inside_slack(bk_aabb bounds);
/// Whether p lies within bounds grown by slack.
bool bk_point_inside(bk_aabb bounds, bk_vec3 p, double slack);
/// True when `volume` (the mesh's, however measured) is no more than
/// BK_FRACTURE_MIN_THICKNESS x its area x its size: the mesh encloses
/// nothing, as a face closed against its own back (and as a NaN volume).
bool bk_mesh_encloses_no_volume(const bk_mesh* mesh, double volume);
/// Removes the shells that enclose no volume (bk_mesh_encloses_no_volume,
/// e.g. a face closed against its own back) when
/// some shell does enclose volume; returns how many were removed (0 when
/// none was, or every shell is such a sheet) and *where the first one's
/// middle.
uint32_t bk_mesh_remove_sheets(bk_mesh* mesh, bk_vec3* where);

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
