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
/// their solid) overlap another: each overlapping shell alone, in the shells'
/// order, then all the other shells together (if any). Returns the number of
/// parts written to *parts (allocated; free each mesh and the array), or 0
/// (and *parts NULL) when no two shells overlap. *overlap says which did, in
/// the mesh's coordinates.
uint32_t bk_mesh_split_overlapping_shells(const bk_mesh* mesh, bk_mesh** parts, bk_fracture_overlap* overlap);
