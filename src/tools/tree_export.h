// A mesh tree written for other programs, as `fracture --export-obj` and
// `sim --export-obj` write it: one OBJ object per leaf.
#pragma once

#include <stdbool.h>

#include <breakables/authoring.h>

/// Writes the tree's leaves to `path` as OBJ, one object 'fragment_<i>' per
/// leaf in leaf order, in the tree's frame; false with err set when it
/// cannot be written.
bool tree_export_obj(const bk_mesh_tree* tree, const char* path, bk_error* err);
