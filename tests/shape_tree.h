// A tree to break in the runtime's tests: a built-in shape, fractured.
#pragma once

#include <stdint.h>

#include <breakables/runtime.h>

#include "ensure.h"

/// A built-in shape cut into `pieces` by `pattern`.
static inline bk_mesh_tree make_tree_pattern(bk_shape shape, bk_fracture_pattern pattern, uint32_t pieces,
                                             uint64_t seed) {
  bk_mesh mesh = {0};
  bk_shape_build(shape, &mesh);
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = pattern;
  def.pieces = pieces;
  def.seed = seed;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &def, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

/// A built-in shape cut into `pieces` by the default pattern.
static inline bk_mesh_tree make_tree(bk_shape shape, uint32_t pieces, uint64_t seed) {
  return make_tree_pattern(shape, bk_default_fracture_def().pattern, pieces, seed);
}
