// A tree's bonds against a brute-force measure of every pair of its leaves
// (bk_mesh_contact): the refinement tests' check that bonds are exact.
#pragma once

#include <stdlib.h>

#include <breakables/authoring.h>

#include "ensure.h"

// Every pair of leaves whose boxes touch, measured by brute force: a bond
// for each pair that touches (its area within 1e-9 of the measure, relative
// to the larger), none for a pair that does not.
static inline void check_bonds_brute_force(const bk_mesh_tree* tree, double relative) {
  bk_aabb root = tree->nodes[0].bounds;
  double tolerance = 1e-9 * bk_v3_length(bk_v3_sub(root.max, root.min));
  uint32_t n = tree->leaf_count;
  double* bonded = calloc((size_t)n * n, sizeof(double));
  for (uint32_t j = 0; j < tree->bond_count; ++j) {
    const bk_bond* b = &tree->bonds[j];
    ENSURE(b->leaf_a < b->leaf_b && b->leaf_b < n);
    ENSURE_MSG(bonded[(size_t)b->leaf_a * n + b->leaf_b] == 0.0, "two bonds for leaves %u and %u", b->leaf_a,
               b->leaf_b);
    bonded[(size_t)b->leaf_a * n + b->leaf_b] = b->area;
  }
  double total = 0.0;
  for (uint32_t j = 0; j < tree->bond_count; ++j)
    total += tree->bonds[j].area;
  uint32_t pairs = 0;
  for (uint32_t a = 0; a < n; ++a)
    for (uint32_t b = a + 1; b < n; ++b) {
      bk_contact_measure m =
          bk_mesh_contact(&bk_mesh_tree_leaf(tree, a)->mesh, &bk_mesh_tree_leaf(tree, b)->mesh, tolerance);
      double have = bonded[(size_t)a * n + b];
      if (have == 0.0) {
        // Rounding at a rim may touch with no area to speak of.
        ENSURE_MSG(m.area <= 1e-9 * total, "leaves %u and %u touch (area %g) with no bond", a, b, m.area);
        continue;
      }
      pairs++;
      ENSURE_MSG(fabs(m.area - have) <= relative * fmax(m.area, have),
                 "leaves %u and %u: bond %.17g, measured %.17g", a, b, have, m.area);
    }
  ENSURE(pairs == tree->bond_count);
  free(bonded);
}
