// What the layers above pull out of the world after a step: statistics,
// body views for drawing, colliders, projectiles and bond health.
#include <string.h>

#include "world_internal.h"

static bool body_has_nan(const bk_world* w, bk_body_id body) {
  bk_transform t = bk_physics_body_transform(w->physics, body);
  bk_vec3 v = bk_physics_body_linear_velocity(w->physics, body),
          a = bk_physics_body_angular_velocity(w->physics, body);
  return !bk_v3_is_finite(t.position) ||
         !isfinite(t.rotation.x + t.rotation.y + t.rotation.z + t.rotation.w) || !bk_v3_is_finite(v) ||
         !bk_v3_is_finite(a);
}

bk_world_stats bk_world_get_stats(const bk_world* w) {
  bk_world_stats s = {0};
  for (uint32_t i = 0; i < w->body_capacity; ++i) {
    const world_body* wbody = &w->bodies[i];
    bk_cluster_info info = {0};
    if (!wbody->alive || !bk_runtime_cluster(w->runtime, wbody->cluster, &info)) continue;
    s.bodies++;
    s.dynamic_bodies += !info.is_static;
    s.colliders += wbody->collider_count;
    s.colliders_naive += info.leaf_count;
    s.fragments_free += info.leaf_count == 1;
    s.total_mass += info.mass;
    s.nan = s.nan || body_has_nan(w, wbody->body);
    s.budget_debris += wbody->tier == BK_TIER_DEBRIS;
    s.budget_simplified += wbody->tier == BK_TIER_SIMPLIFIED;
    s.budget_frozen += wbody->tier == BK_TIER_FROZEN;
  }
  bk_runtime_stats rs = bk_runtime_get_stats(w->runtime);
  s.projectiles = w->projectile_count;
  s.bonds_broken = rs.bonds_broken;
  s.break_events = rs.splits;
  s.pending_splits = rs.pending_splits;
  s.pending_hits = w->hit_count;
  s.fragments_retired = w->fragments_retired;
  s.retired_mass = w->retired_mass;
  s.step_ms = w->step_ms;
  s.physics_ms = w->physics_ms;
  s.break_ms = w->break_ms;
  s.fracture_ms = w->fracture_ms;
  s.physics_cpu_ms = w->physics_cpu_ms;
  s.stress_ms = w->stress_ms;
  s.stress_bonds_broken = rs.stress_bonds_broken;
  s.stress_iterations = rs.stress_iterations;
  s.stress_clusters_pending = rs.stress_clusters_pending;
  s.budget_retired = w->budget.retired;
  s.budget_demotions = w->budget.demotions;
  s.budget_restorations = w->budget.restorations;
  s.budget_level = w->budget.level;
  s.budget_cost_ms = w->budget.cost_ms;
  s.settled_bodies = w->settle.merged;
  s.settled_areas = w->settle.live_areas;
  s.settle_wakes = w->settle.wakes;
  s.settle_batch_ms = w->settle.batch_ms;
  s.refine_ms = w->refine_ms;
  s.refined_leaves = rs.refined_leaves;
  for (uint32_t i = 0; i < w->projectile_count; ++i)
    s.nan = s.nan || body_has_nan(w, w->projectiles[i]);
  return s;
}

uint32_t bk_world_fragment_centroids(const bk_world* w, bk_breakable_id id, bk_vec3* out, uint32_t capacity) {
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(w->runtime, id);
  if (!tree) return 0;
  for (uint32_t leaf = 0; leaf < tree->leaf_count && leaf < capacity; ++leaf) {
    bk_cluster_id cluster = bk_runtime_leaf_cluster(w->runtime, id, leaf);
    if (bk_cluster_is_null(cluster) || cluster.index >= w->body_capacity || !w->bodies[cluster.index].alive) {
      out[leaf] = bk_v3(NAN, NAN, NAN);
      continue;
    }
    bk_vec3 centroid = bk_mesh_tree_mass(tree, bk_mesh_tree_leaf(tree, leaf)->moments).centroid;
    out[leaf] = bk_transform_point(bk_world_tree_to_world(w, cluster.index), centroid);
  }
  return tree->leaf_count;
}

uint32_t bk_world_body_count(const bk_world* w) { return w->live_dirty ? 0 : w->live_count; }

bool bk_world_body_view(const bk_world* w, uint32_t index, bk_body_view* out) {
  if (w->live_dirty || index >= w->live_count) return false;
  const world_body* wbody = &w->bodies[w->live[index]];
  bk_cluster_info info = {0};
  if (!bk_runtime_cluster(w->runtime, wbody->cluster, &info)) return false;
  bk_transform body = bk_physics_body_transform(w->physics, wbody->body);
  *out = (bk_body_view){.breakable = info.breakable,
                        .cluster = info.id,
                        .tree = bk_runtime_breakable_tree(w->runtime, info.breakable),
                        .tree_to_world = bk_transform_mul(body, bk_transform_inverse(info.principal)),
                        .tree_to_world_previous = wbody->previous,
                        .nodes = info.nodes,
                        .node_count = info.node_count,
                        .leaves = info.leaves,
                        .leaf_count = info.leaf_count,
                        .body = wbody->body,
                        .is_static = info.is_static,
                        .tier = wbody->tier,
                        .user_data = info.breakable_user_data};
  return true;
}

uint32_t bk_world_body_colliders(const bk_world* w, uint32_t index, uint32_t* nodes_out, uint32_t capacity) {
  if (w->live_dirty || index >= w->live_count) return 0;
  const world_body* wbody = &w->bodies[w->live[index]];
  uint32_t n = wbody->collider_count < capacity ? wbody->collider_count : capacity;
  if (n) memcpy(nodes_out, wbody->colliders, sizeof(uint32_t) * n);
  return wbody->collider_count;
}

double bk_world_bond_health(const bk_world* w, bk_breakable_id id, uint32_t bond, double* initial) {
  return bk_runtime_bond_health(w->runtime, id, bond, initial);
}
