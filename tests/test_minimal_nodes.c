// Minimal mesh-tree node sets against a brute-force reference: a node is in
// the minimal cover of a leaf set S exactly when its subtree lies inside S
// and its parent's does not.
#include <stdlib.h>
#include <string.h>

#include <breakables/runtime.h>

#include "bk_geom.h"
#include "ensure.h"

static bool range_inside(const uint8_t* in_set, uint32_t begin, uint32_t end) {
  for (uint32_t l = begin; l < end; ++l)
    if (!in_set[l]) return false;
  return true;
}

static void check_tree(const bk_mesh_tree* tree, uint64_t seed, uint32_t trials) {
  bk_rng rng = bk_rng_seed(seed, 1);
  uint32_t* leaves = malloc(sizeof(uint32_t) * tree->leaf_count);
  uint32_t* out = malloc(sizeof(uint32_t) * tree->leaf_count);
  uint8_t* in_set = malloc(tree->leaf_count);
  uint8_t* covered = malloc(tree->leaf_count);
  for (uint32_t trial = 0; trial < trials; ++trial) {
    // Mix of sparse sets, dense sets, contiguous runs and the full set.
    double density = trial % 4 == 0 ? 1.0 : bk_rng_unit(&rng);
    uint32_t count = 0;
    uint32_t run_start = bk_rng_next(&rng) % tree->leaf_count,
             run_length = bk_rng_next(&rng) % tree->leaf_count;
    for (uint32_t l = 0; l < tree->leaf_count; ++l) {
      bool in_run = trial % 4 == 1 && l >= run_start && l < run_start + run_length;
      in_set[l] = trial % 4 == 1 ? in_run : bk_rng_unit(&rng) < density;
      if (in_set[l]) leaves[count++] = l;
    }
    uint32_t n = bk_minimal_nodes(tree, leaves, count, out);
    // Reference: maximal nodes inside the set.
    uint32_t expected = 0;
    for (uint32_t i = 0; i < tree->node_count; ++i) {
      const bk_mesh_tree_node* node = &tree->nodes[i];
      if (!range_inside(in_set, node->leaf_begin, node->leaf_end)) continue;
      if (node->parent != BK_NULL_INDEX) {
        const bk_mesh_tree_node* parent = &tree->nodes[node->parent];
        if (range_inside(in_set, parent->leaf_begin, parent->leaf_end)) continue;
      }
      expected++;
      bool found = false;
      for (uint32_t k = 0; k < n && !found; ++k)
        found = out[k] == i;
      ENSURE_MSG(found, "trial %u: node %u missing from the minimal set", trial, i);
    }
    ENSURE_MSG(n == expected, "trial %u: %u nodes, reference %u", trial, n, expected);
    // The chosen subtrees cover exactly the set, without overlap.
    memset(covered, 0, tree->leaf_count);
    for (uint32_t k = 0; k < n; ++k)
      for (uint32_t l = tree->nodes[out[k]].leaf_begin; l < tree->nodes[out[k]].leaf_end; ++l) {
        ENSURE(!covered[l] && in_set[l]);
        covered[l] = 1;
      }
    for (uint32_t l = 0; l < tree->leaf_count; ++l)
      ENSURE(covered[l] == in_set[l]);
    if (count == tree->leaf_count) ENSURE(n == 1 && out[0] == 0); // unbroken: the root alone
  }
  free(leaves);
  free(out);
  free(in_set);
  free(covered);
}

static void test_trees(void) {
  const bk_shape shapes[] = {BK_SHAPE_CUBE, BK_SHAPE_TORUS, BK_SHAPE_EGGSHELL, BK_SHAPE_WALL};
  const uint32_t pieces[] = {64, 100, 128, 300};
  for (int i = 0; i < 4; ++i) {
    bk_mesh mesh = {0};
    bk_shape_build(shapes[i], &mesh);
    bk_fracture_def desc = bk_default_fracture_def();
    desc.pieces = pieces[i];
    desc.seed = 17 + (uint64_t)i;
    bk_mesh_tree tree = {0};
    bk_error err = {0};
    ENSURE_MSG(bk_mesh_tree_build(&mesh, &desc, &tree, &err), "%s", err.message);
    check_tree(&tree, 99 + (uint64_t)i, 200);
    bk_mesh_tree_free(&tree);
    bk_mesh_free(&mesh);
  }
}

static void test_empty_and_single(void) {
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_CUBE, &mesh);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = 8;
  bk_mesh_tree tree = {0};
  ENSURE(bk_mesh_tree_build(&mesh, &desc, &tree, NULL));
  uint32_t out[8];
  ENSURE(bk_minimal_nodes(&tree, NULL, 0, out) == 0);
  uint32_t one = 3;
  ENSURE(bk_minimal_nodes(&tree, &one, 1, out) == 1 && out[0] == tree.leaf_nodes[3]);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&mesh);
}

int main(void) {
  RUN(test_empty_and_single);
  RUN(test_trees);
  return 0;
}
