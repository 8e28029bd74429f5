// fracture (private): the authoring API plus geom's shared utilities, for
// the fracture files. Not installed: the public API is <breakables/authoring.h>.
#pragma once

#include <breakables/authoring.h>

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
