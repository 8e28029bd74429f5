// Internal: the helpers over a mesh tree's data (tree_data.c) that the
// builders (plane_tree.c, the cell patterns' files) and the dispatcher
// (mesh_tree.c) share; the public ones (bk_mesh_tree_free, _mass, _origin,
// _measure, ...) are declared in <breakables/authoring.h>.
#pragma once

#include "bk_fracture.h"

/// Numbers the leaves depth first (each subtree covers a contiguous range)
/// and fills leaf_nodes, leaf_count and every node's leaf range.
void bk_mesh_tree_number_leaves(bk_mesh_tree* tree);
