// Clusters: connected sets of fragments, each one rigid body of the caller's
// physics. Its node set is the minimal mesh-tree node set; its mass
// properties come from those nodes' exact volume moments; its body frame is
// the principal frame of inertia.
#include <stdlib.h>
#include <string.h>

#include "runtime_internal.h"

uint32_t rt_cluster_alloc(bk_runtime* rt, uint32_t breakable_index) {
  uint32_t slot = 0;
  if (rt->free_cluster_count) {
    slot = rt->free_clusters[--rt->free_cluster_count];
  } else {
    if (rt->cluster_count == rt->cluster_capacity) {
      rt->cluster_capacity = bk_grow_capacity(rt->cluster_capacity, rt->cluster_count + 1);
      rt->clusters = bk_realloc(rt->clusters, sizeof(rt_cluster) * rt->cluster_capacity);
      rt->free_clusters = bk_realloc(rt->free_clusters, sizeof(uint32_t) * rt->cluster_capacity);
    }
    slot = rt->cluster_count++;
    rt->clusters[slot].generation = 0;
  }
  uint32_t generation = rt->clusters[slot].generation + 1;
  if (generation == 0) generation = 1; // after 2^32 reuses; 0 stays the null id
  memset(&rt->clusters[slot], 0, sizeof(rt_cluster));
  rt->clusters[slot].generation = generation;
  rt->clusters[slot].breakable = breakable_index;
  rt->clusters[slot].alive = true;
  rt->live_count++;
  return slot;
}

void rt_cluster_free(bk_runtime* rt, uint32_t slot) {
  rt_cluster* c = &rt->clusters[slot];
  uint32_t generation = c->generation;
  bk_free(c->leaves);
  bk_free(c->nodes);
  bk_free(c->split_labels);
  rt_stress_release(c);
  memset(c, 0, sizeof *c);
  c->generation = generation;
  rt->free_clusters[rt->free_cluster_count++] = slot;
  rt->live_count--;
}

void rt_cluster_mass(const bk_runtime* rt, rt_cluster* c) {
  const rt_breakable* b = &rt->breakables[c->breakable];
  double density = b->material.density;
  bk_moments sum = {0};
  for (uint32_t i = 0; i < c->node_count; ++i)
    sum = bk_moments_add(sum, b->tree->nodes[c->nodes[i]].moments);
  bk_mass_properties mp = bk_mesh_tree_mass(b->tree, sum);
  double values[3] = {0}, axes[3][3] = {{0}};
  bk_sym3_eigen(mp.inertia, values, axes);
  c->volume = mp.volume;
  c->mass = density * mp.volume;
  c->principal = (bk_transform){mp.centroid, bk_quat_from_matrix(axes)};
  // Thin slivers can have a vanishing moment; keep a solver well-posed.
  double floor_value = 1e-9 * fmax(values[0], fmax(values[1], values[2]));
  c->inertia = bk_v3(density * fmax(values[0], floor_value), density * fmax(values[1], floor_value),
                     density * fmax(values[2], floor_value));
}

void rt_cluster_finish(bk_runtime* rt, uint32_t slot) {
  rt_cluster* c = &rt->clusters[slot];
  rt_breakable* b = &rt->breakables[c->breakable];
  c->nodes = bk_realloc(c->nodes, sizeof(uint32_t) * (c->leaf_count ? c->leaf_count : 1u));
  c->node_count = bk_minimal_nodes(b->tree, c->leaves, c->leaf_count, c->nodes);
  c->is_static = false;
  for (uint32_t i = 0; i < c->leaf_count && !c->is_static; ++i)
    c->is_static = b->leaf_anchored[c->leaves[i]];
  for (uint32_t i = 0; i < c->leaf_count; ++i)
    b->leaf_cluster[c->leaves[i]] = slot;
  rt_cluster_mass(rt, c);
}
