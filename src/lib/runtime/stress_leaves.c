// The per-leaf data of a breakable that stress solves are made of: each
// leaf's centroid and volume, its last solved motion (the next solve's warm
// start) and each bond's last solved stress, made at the breakable's first
// solve; and the leaf of a cluster a point (a support, a load) is on.
#include "stress_leaves.h"

// A leaf's motion in a solve (its system's unknowns per node).
enum { DOF = RT_STRESS_DOF };

void rt_stress_prepare_breakable(rt_breakable* b) {
  if (b->leaf_centroid) return;
  const bk_mesh_tree* tree = b->tree;
  b->leaf_centroid = bk_alloc(sizeof(bk_vec3) * tree->leaf_count);
  b->leaf_volume = bk_alloc(sizeof(double) * tree->leaf_count);
  b->leaf_motion = bk_calloc((size_t)DOF * tree->leaf_count, sizeof(double));
  b->bond_stress = bk_alloc(sizeof(double) * 4u * (tree->bond_count ? tree->bond_count : 1u));
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    bk_mass_properties mp = bk_mesh_tree_mass(tree, bk_mesh_tree_leaf(tree, l)->moments);
    b->leaf_centroid[l] = mp.centroid;
    b->leaf_volume[l] = mp.volume;
  }
  for (uint32_t k = 0; k < tree->bond_count; ++k)
    b->bond_stress[4 * k + 3] = -1.0;
}

static double box_distance_squared(bk_aabb box, bk_vec3 p) {
  double dx = fmax(fmax(box.min.x - p.x, p.x - box.max.x), 0.0);
  double dy = fmax(fmax(box.min.y - p.y, p.y - box.max.y), 0.0);
  double dz = fmax(fmax(box.min.z - p.z, p.z - box.max.z), 0.0);
  return dx * dx + dy * dy + dz * dz;
}

// The leaf of a cluster a contact point (tree frame) is on: the one whose
// bounds are nearest, then whose centroid is.
static uint32_t leaf_at_scan(const rt_breakable* b, const rt_cluster* c, bk_vec3 point) {
  uint32_t best = c->leaves[0];
  double best_box = INFINITY, best_centre = INFINITY;
  for (uint32_t i = 0; i < c->leaf_count; ++i) {
    uint32_t leaf = c->leaves[i];
    double box = box_distance_squared(bk_mesh_tree_leaf(b->tree, leaf)->bounds, point);
    double centre = bk_v3_length(bk_v3_sub(b->leaf_centroid[leaf], point));
    if (box < best_box || (box == best_box && centre < best_centre))
      best = leaf, best_box = box, best_centre = centre;
  }
  return best;
}

// Down the mesh tree from the cluster's node set (which covers exactly its
// leaves), skipping every node whose bounds are farther than the best leaf's:
// a few dozen boxes for a point on a 1,024-fragment wall, where trying every
// leaf made a step with a few hundred contacts cost milliseconds. Should the
// search outgrow its stack, every leaf is tried.
uint32_t rt_stress_leaf_at(const rt_breakable* b, const rt_cluster* c, bk_vec3 point) {
  enum { STACK = 512 };
  const bk_mesh_tree* tree = b->tree;
  uint32_t stack[STACK];
  uint32_t top = 0, best = c->leaves[0];
  double best_box = INFINITY, best_centre = INFINITY;
  if (c->node_count > STACK) return leaf_at_scan(b, c, point);
  for (uint32_t i = 0; i < c->node_count; ++i)
    stack[top++] = c->nodes[i];
  while (top) {
    const bk_mesh_tree_node* node = &tree->nodes[stack[--top]];
    double box = box_distance_squared(node->bounds, point);
    if (box > best_box) continue;
    if (node->child_count == 0) {
      uint32_t leaf = node->leaf_begin;
      double centre = bk_v3_length(bk_v3_sub(b->leaf_centroid[leaf], point));
      if (box < best_box || (box == best_box && centre < best_centre))
        best = leaf, best_box = box, best_centre = centre;
      continue;
    }
    if (top + node->child_count > STACK) return leaf_at_scan(b, c, point);
    for (uint32_t k = 0; k < node->child_count; ++k)
      stack[top++] = node->first_child + k;
  }
  return best;
}
