// Fragment quality metrics (bk_mesh_tree_measure_quality): aspects of known
// boxes along their principal axes, turned or not, the sliver threshold,
// nearest-rank volume percentiles on known volumes, and a real fracture.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"

// A box of these sides centred at `at`, turned by `turn`.
static void box(bk_vec3 size, bk_quat turn, bk_vec3 at, bk_mesh* out) {
  bk_shape_build(BK_SHAPE_CUBE, out);
  for (uint32_t i = 0; i < out->position_count; ++i) {
    bk_vec3* p = &out->positions[i];
    bk_vec3 scaled = bk_v3(p->x * size.x, p->y * size.y, p->z * size.z);
    *p = bk_v3_add(bk_quat_rotate(turn, scaled), at);
  }
}

// Moments of a mesh about `origin`, as a tree keeps them.
static bk_moments moments_about(const bk_mesh* mesh, bk_vec3 origin) {
  bk_mesh shifted = {0};
  bk_mesh_copy(&shifted, mesh);
  for (uint32_t i = 0; i < shifted.position_count; ++i)
    shifted.positions[i] = bk_v3_sub(shifted.positions[i], origin);
  bk_moments m = bk_mesh_moments(&shifted);
  bk_mesh_free(&shifted);
  return m;
}

// A tree made by hand: a root (the first leaf's mesh, unused by the metrics;
// its bounds those of all leaves) over one leaf per mesh given (taken over),
// in the order given, with moments about the tree's origin as a built tree has.
static bk_mesh_tree hand_tree(bk_mesh* leaves, uint32_t count) {
  bk_mesh_tree tree = {0};
  tree.node_count = count + 1;
  tree.nodes = bk_calloc(tree.node_count, sizeof(bk_mesh_tree_node));
  tree.leaf_count = count;
  tree.leaf_nodes = bk_calloc(count, sizeof(uint32_t));
  bk_mesh_tree_node* root = &tree.nodes[0];
  bk_mesh_copy(&root->mesh, &leaves[0]);
  root->parent = BK_NULL_INDEX;
  root->first_child = 1;
  root->child_count = count;
  root->leaf_end = count;
  root->bounds = bk_mesh_bounds(&leaves[0]);
  for (uint32_t i = 0; i < count; ++i) {
    bk_aabb b = bk_mesh_bounds(&leaves[i]);
    root->bounds.min = bk_v3(fmin(root->bounds.min.x, b.min.x), fmin(root->bounds.min.y, b.min.y),
                             fmin(root->bounds.min.z, b.min.z));
    root->bounds.max = bk_v3(fmax(root->bounds.max.x, b.max.x), fmax(root->bounds.max.y, b.max.y),
                             fmax(root->bounds.max.z, b.max.z));
  }
  bk_vec3 origin = bk_mesh_tree_origin(&tree);
  for (uint32_t i = 0; i < count; ++i) {
    bk_mesh_tree_node* n = &tree.nodes[i + 1];
    n->mesh = leaves[i];
    n->moments = moments_about(&n->mesh, origin);
    n->bounds = bk_mesh_bounds(&n->mesh);
    n->parent = 0;
    n->first_child = BK_NULL_INDEX;
    n->leaf_begin = i;
    n->leaf_end = i + 1;
    n->depth = 1;
    root->moments = bk_moments_add(root->moments, n->moments);
    tree.leaf_nodes[i] = i + 1;
  }
  memset(leaves, 0, sizeof(bk_mesh) * count);
  return tree;
}

// The quality of a tree whose only leaf is one box.
static bk_mesh_tree_quality one_box(bk_vec3 size, bk_quat turn, bk_vec3 at) {
  bk_mesh mesh = {0};
  box(size, turn, at, &mesh);
  bk_mesh_tree tree = hand_tree(&mesh, 1);
  bk_mesh_tree_quality q = bk_mesh_tree_measure_quality(&tree);
  bk_mesh_tree_free(&tree);
  ENSURE(q.leaves == 1);
  ENSURE_SMALL(q.min_aspect, q.median_aspect, 0.0);
  ENSURE(q.volume_ratio_p95_p5 == 1.0); // one leaf: both percentiles are its volume
  return q;
}

static void test_boxes(void) {
  bk_quat none = bk_quat_identity();
  bk_vec3 origin = bk_v3(0, 0, 0);
  bk_mesh_tree_quality q = one_box(bk_v3(1, 1, 1), none, origin);
  ENSURE_SMALL(q.min_aspect, 1.0, 1e-12);
  ENSURE(q.slivers == 0 && q.sliver_fraction == 0.0);
  ENSURE_SMALL(q.volume_p5, 1.0, 1e-12);
  // A 1 x 1 x 0.1 plate is a sliver; 1 x 1 x 0.2 is not (the threshold is 0.15).
  q = one_box(bk_v3(1, 1, 0.1), none, origin);
  ENSURE_SMALL(q.min_aspect, 0.1, 1e-12);
  ENSURE(q.slivers == 1 && q.sliver_fraction == 1.0);
  q = one_box(bk_v3(1, 1, 0.2), none, origin);
  ENSURE(q.slivers == 0);
  // Measured along the principal axes, not the world's: a turned plate far
  // from the origin is as thin as it is, where its world bounds are chunky.
  bk_quat turn = bk_quat_normalize((bk_quat){0.3, -0.5, 0.7, 0.9});
  bk_vec3 far = bk_v3(1e4, -2e4, 3e4);
  q = one_box(bk_v3(2, 1, 0.2), turn, far);
  ENSURE_SMALL(q.min_aspect, 0.1, 1e-9);
  ENSURE(q.slivers == 1);
  bk_mesh plate = {0};
  box(bk_v3(2, 1, 0.2), turn, far, &plate);
  bk_aabb b = bk_mesh_bounds(&plate);
  bk_vec3 extent = bk_v3_sub(b.max, b.min);
  ENSURE(fmin(extent.x, fmin(extent.y, extent.z)) / fmax(extent.x, fmax(extent.y, extent.z)) > 0.3);
  bk_mesh_free(&plate);
  // A needle is a sliver too.
  q = one_box(bk_v3(0.12, 0.08, 1), turn, origin);
  ENSURE_SMALL(q.min_aspect, 0.08, 1e-9);
  ENSURE(q.slivers == 1);
  // A cube's principal moments are equal, so its axes are whatever rounding
  // gives: turned and far away it measures between 1 / sqrt(3) and 1.
  q = one_box(bk_v3(1, 1, 1), turn, far);
  ENSURE_MSG(q.min_aspect >= 1.0 / sqrt(3.0) - 1e-12 && q.min_aspect <= 1.0 + 1e-12, "%.17g", q.min_aspect);
  ENSURE(q.slivers == 0);
}

// Leaves of volumes 1..count (cubes), in a scrambled order.
static bk_mesh_tree_quality volumes_1_to(uint32_t count) {
  bk_mesh* leaves = bk_calloc(count, sizeof(bk_mesh));
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t volume = 1 + (i * 7919u) % count; // 7919 is prime: a permutation for these counts
    double side = cbrt((double)volume);
    box(bk_v3(side, side, side), bk_quat_identity(), bk_v3(3.0 * i, 0, 0), &leaves[i]);
  }
  bk_mesh_tree tree = hand_tree(leaves, count);
  free(leaves);
  bk_mesh_tree_quality q = bk_mesh_tree_measure_quality(&tree);
  bk_mesh_tree_free(&tree);
  ENSURE(q.leaves == count && q.slivers == 0);
  ENSURE(q.min_aspect >= 1.0 / sqrt(3.0) - 1e-12); // cubes away from the origin: see test_boxes
  return q;
}

static void test_percentiles(void) {
  // Nearest rank k = ceil(p / 100 x n): n = 20 gives ranks 1 and 19.
  bk_mesh_tree_quality q = volumes_1_to(20);
  ENSURE_SMALL(q.volume_p5, 1.0, 1e-12);
  ENSURE_SMALL(q.volume_p95, 19.0, 1e-11);
  ENSURE_SMALL(q.volume_ratio_p95_p5, 19.0, 1e-11);
  // n = 10: ranks 1 and 10 (9.5 rounds up).
  q = volumes_1_to(10);
  ENSURE_SMALL(q.volume_p95, 10.0, 1e-11);
  ENSURE_SMALL(q.volume_ratio_p95_p5, 10.0, 1e-11);
  // n = 100: ranks 5 and 95.
  q = volumes_1_to(100);
  ENSURE_SMALL(q.volume_p5, 5.0, 1e-11);
  ENSURE_SMALL(q.volume_p95, 95.0, 1e-10);
  ENSURE_SMALL(q.volume_ratio_p95_p5, 19.0, 1e-11);
  // n = 21: ranks 2 and 20.
  q = volumes_1_to(21);
  ENSURE_SMALL(q.volume_ratio_p95_p5, 10.0, 1e-11);

  // No leaves: all zero.
  bk_mesh_tree empty = {0};
  q = bk_mesh_tree_measure_quality(&empty);
  ENSURE(q.leaves == 0 && q.slivers == 0 && q.sliver_fraction == 0.0 && q.volume_ratio_p95_p5 == 0.0);
}

// Median of odd and even counts: three plates and a chunk, then without the
// chunk. Their sides differ, so their axes are fixed away from the origin too.
static void test_median(void) {
  bk_mesh leaves[4] = {{0}};
  double thin[4] = {0.1, 0.3, 0.5, 0.9};
  for (int i = 0; i < 4; ++i)
    box(bk_v3(1, 0.95, thin[i]), bk_quat_identity(), bk_v3(3.0 * i, 0, 0), &leaves[i]);
  bk_mesh_tree tree = hand_tree(leaves, 4);
  bk_mesh_tree_quality q = bk_mesh_tree_measure_quality(&tree);
  bk_mesh_tree_free(&tree);
  ENSURE_SMALL(q.median_aspect, 0.4, 1e-9);
  ENSURE_SMALL(q.min_aspect, 0.1, 1e-9);
  ENSURE(q.slivers == 1 && q.sliver_fraction == 0.25);
  for (int i = 0; i < 3; ++i)
    box(bk_v3(1, 0.95, thin[i]), bk_quat_identity(), bk_v3(3.0 * i, 0, 0), &leaves[i]);
  tree = hand_tree(leaves, 3);
  q = bk_mesh_tree_measure_quality(&tree);
  bk_mesh_tree_free(&tree);
  ENSURE_SMALL(q.median_aspect, 0.3, 1e-9);
}

// The planes pattern on the cube at 256 pieces makes some slivers, not only
// slivers, and the same numbers every time. The per-leaf count is checked
// against the definition on the leaves' own meshes.
static void test_planes_cube(void) {
  bk_mesh cube = {0};
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  bk_fracture_def def = bk_default_fracture_def();
  def.pieces = 256;
  bk_mesh_tree_quality runs[2] = {{0}};
  for (int run = 0; run < 2; ++run) {
    bk_mesh_tree tree = {0};
    bk_error err = {0};
    ENSURE_MSG(bk_mesh_tree_build(&cube, &def, &tree, &err), "%s", err.message);
    runs[run] = bk_mesh_tree_measure_quality(&tree);
    ENSURE(runs[run].leaves == tree.leaf_count && tree.leaf_count == 256);
    // Each leaf alone, from moments recomputed on its mesh: the same verdicts.
    uint32_t slivers = 0;
    for (uint32_t i = 0; i < tree.leaf_count; ++i) {
      bk_mesh copy = {0};
      bk_mesh_copy(&copy, &bk_mesh_tree_leaf(&tree, i)->mesh);
      bk_mesh_tree single = hand_tree(&copy, 1);
      slivers += bk_mesh_tree_measure_quality(&single).slivers;
      bk_mesh_tree_free(&single);
    }
    ENSURE_MSG(slivers == runs[run].slivers, "%u slivers leaf by leaf, %u in the tree", slivers,
               runs[run].slivers);
    bk_mesh_tree_free(&tree);
  }
  bk_mesh_tree_quality q = runs[0];
  fprintf(stderr, "    cube, 256 planes: %u slivers (%.3f), p95/p5 %.3f, aspect min %.3f median %.3f\n",
          q.slivers, q.sliver_fraction, q.volume_ratio_p95_p5, q.min_aspect, q.median_aspect);
  ENSURE_MSG(q.sliver_fraction > 0.0 && q.sliver_fraction < 1.0, "sliver fraction %g", q.sliver_fraction);
  ENSURE(q.sliver_fraction == (double)q.slivers / q.leaves);
  ENSURE(q.volume_ratio_p95_p5 > 1.0 && isfinite(q.volume_ratio_p95_p5));
  ENSURE(q.volume_p5 > 0.0 && q.volume_p5 < q.volume_p95);
  ENSURE(q.min_aspect > 0.0 && q.min_aspect < BK_SLIVER_ASPECT && q.median_aspect > q.min_aspect &&
         q.median_aspect <= 1.0);
  ENSURE(memcmp(&runs[0], &runs[1], sizeof q) == 0);
  bk_mesh_free(&cube);
}

int main(void) {
  RUN(test_boxes);
  RUN(test_percentiles);
  RUN(test_median);
  RUN(test_planes_cube);
  return 0;
}
