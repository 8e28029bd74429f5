// The leaves of a mesh tree as OBJ objects, for fracture's and sim's
// --export-obj (the one writer, so the two files read alike).
#include "tree_export.h"

#include "app.h"

bool tree_export_obj(const bk_mesh_tree* tree, const char* path, bk_error* err) {
  bk_mesh* leaves = bk_alloc(sizeof(bk_mesh) * (tree->leaf_count + 1u));
  for (uint32_t i = 0; i < tree->leaf_count; ++i)
    leaves[i] = bk_mesh_tree_leaf(tree, i)->mesh;
  bool saved = bk_obj_save(path, leaves, tree->leaf_count, err);
  bk_free(leaves);
  return saved;
}
