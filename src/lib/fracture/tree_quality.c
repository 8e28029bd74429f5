// Fragment quality of a mesh tree: how many leaves are slivers (thin plates
// or needles, measured along their principal axes of inertia) and how widely
// leaf volumes spread. Definitions are in authoring.h (bk_mesh_tree_quality).
#include <math.h>
#include <stdlib.h>

#include "bk_fracture.h"

// Thinnest over longest extent of a leaf's positions along its principal axes.
static double leaf_aspect(const bk_mesh_tree_node* leaf) {
  if (leaf->mesh.position_count == 0) return 0.0;
  // The inertia tensor is central, so the point the moments were taken about
  // (the tree's origin) does not change it; its eigenvectors are the axes.
  bk_mass_properties mass = bk_moments_to_mass(leaf->moments);
  double values[3] = {0.0, 0.0, 0.0};
  double axes[3][3] = {{0.0}};
  bk_sym3_eigen(mass.inertia, values, axes);
  double low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
  // Relative to one of its own positions, so a leaf far from the world
  // origin keeps the precision of its size, not of its place.
  bk_vec3 base = leaf->mesh.positions[0];
  for (uint32_t i = 0; i < leaf->mesh.position_count; ++i) {
    bk_vec3 p = bk_v3_sub(leaf->mesh.positions[i], base);
    for (int k = 0; k < 3; ++k) {
      // Columns of `axes` are the eigenvectors.
      double along = p.x * axes[0][k] + p.y * axes[1][k] + p.z * axes[2][k];
      low[k] = fmin(low[k], along);
      high[k] = fmax(high[k], along);
    }
  }
  double thinnest = INFINITY, longest = 0.0;
  for (int k = 0; k < 3; ++k) {
    double extent = high[k] - low[k];
    thinnest = fmin(thinnest, extent);
    longest = fmax(longest, extent);
  }
  // A leaf of zero size, or with non-finite positions, has no shape to rate.
  if (!(longest > 0.0) || !isfinite(longest)) return 0.0;
  return thinnest / longest;
}

static int compare_double(const void* a, const void* b) {
  double x = *(const double*)a, y = *(const double*)b;
  return x < y ? -1 : x > y;
}

// Nearest-rank percentile of sorted values: the k-th smallest with
// k = ceil(percent / 100 x count), in integers so 95% of 20 is exactly rank 19.
static double nearest_rank(const double* sorted, uint32_t count, uint32_t percent) {
  uint64_t rank = ((uint64_t)percent * count + 99) / 100;
  if (rank < 1) rank = 1;
  return sorted[rank - 1];
}

bk_mesh_tree_quality bk_mesh_tree_measure_quality(const bk_mesh_tree* tree) {
  bk_mesh_tree_quality q = {0};
  uint32_t count = tree ? tree->leaf_count : 0;
  if (count == 0) return q;
  q.leaves = count;
  double* volumes = bk_alloc(sizeof(double) * count);
  double* aspects = bk_alloc(sizeof(double) * count);
  for (uint32_t i = 0; i < count; ++i) {
    const bk_mesh_tree_node* leaf = bk_mesh_tree_leaf(tree, i);
    volumes[i] = leaf->moments.v;
    aspects[i] = leaf_aspect(leaf);
    if (aspects[i] < BK_SLIVER_ASPECT) q.slivers++;
  }
  q.sliver_fraction = (double)q.slivers / count;
  bk_sort(volumes, count, sizeof(double), compare_double);
  bk_sort(aspects, count, sizeof(double), compare_double);
  q.volume_p5 = nearest_rank(volumes, count, 5);
  q.volume_p95 = nearest_rank(volumes, count, 95);
  q.volume_ratio_p95_p5 = q.volume_p5 > 0.0 ? q.volume_p95 / q.volume_p5 : INFINITY;
  q.min_aspect = aspects[0];
  q.median_aspect = count % 2 ? aspects[count / 2] : 0.5 * (aspects[count / 2 - 1] + aspects[count / 2]);
  bk_free(volumes);
  bk_free(aspects);
  return q;
}
