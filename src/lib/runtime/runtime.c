// The runtime object: parameters, the results each call leaves to be pulled,
// and the queries over breakables and clusters.
#include <stdlib.h>
#include <string.h>

#include "runtime_internal.h"

bk_runtime_def bk_default_runtime_def(void) {
  return (bk_runtime_def){.impact_speed = 1.0,
                          .impulse_threshold = 0.5,
                          .damage_min_distance = 0.05,
                          .max_new_clusters_per_split = 48,
                          .stress_budget = 16000,
                          .stress_tolerance = 1e-3,
                          .stress_rest_speed = 0.25,
                          .body_state = NULL,
                          .context = NULL};
}

bk_runtime* bk_runtime_create(const bk_runtime_def* def, bk_error* err) {
  if (!def) return bk_error_set(err, "runtime: def is NULL"), NULL;
  if (!def->body_state)
    return bk_error_set(err, "runtime: body_state must be set (the runtime asks it where clusters are)"),
           NULL;
  if (!(def->impact_speed >= 0.0) || !isfinite(def->impact_speed))
    return bk_error_set(err, "runtime: impact_speed must be finite and >= 0 (got %g)", def->impact_speed),
           NULL;
  if (!(def->impulse_threshold >= 0.0) || !isfinite(def->impulse_threshold))
    return bk_error_set(err, "runtime: impulse_threshold must be finite and >= 0 (got %g)",
                        def->impulse_threshold),
           NULL;
  if (!(def->damage_min_distance > 0.0) || !isfinite(def->damage_min_distance))
    return bk_error_set(err, "runtime: damage_min_distance must be positive (got %g)",
                        def->damage_min_distance),
           NULL;
  if (def->max_new_clusters_per_split < 2)
    return bk_error_set(err, "runtime: max_new_clusters_per_split must be at least 2 (got %u)",
                        def->max_new_clusters_per_split),
           NULL;
  if (def->stress_budget < 1)
    return bk_error_set(err, "runtime: stress_budget must be at least 1 (got %u)", def->stress_budget), NULL;
  if (!(def->stress_tolerance > 0.0 && def->stress_tolerance <= 0.1))
    return bk_error_set(err, "runtime: stress_tolerance must be in (0, 0.1] (got %g)", def->stress_tolerance),
           NULL;
  if (!(def->stress_rest_speed >= 0.0) || !isfinite(def->stress_rest_speed))
    return bk_error_set(err, "runtime: stress_rest_speed must be finite and >= 0 (got %g)",
                        def->stress_rest_speed),
           NULL;
  bk_runtime* rt = bk_calloc(1, sizeof *rt);
  rt->def = *def;
  return rt;
}

void bk_runtime_destroy(bk_runtime* rt) {
  if (!rt) return;
  for (uint32_t i = 0; i < rt->cluster_count; ++i) {
    free(rt->clusters[i].leaves);
    free(rt->clusters[i].nodes);
    free(rt->clusters[i].split_labels);
    rt_stress_release(&rt->clusters[i]);
  }
  for (uint32_t i = 0; i < rt->breakable_count; ++i) {
    rt_breakable* b = &rt->breakables[i];
    free(b->adjacency_start);
    free(b->adjacency);
    free(b->bond_hp);
    free(b->bond_hp_initial);
    free(b->bond_broken);
    free(b->leaf_cluster);
    free(b->leaf_anchored);
    free(b->leaf_centroid);
    free(b->leaf_volume);
    free(b->leaf_motion);
    free(b->bond_stress);
  }
  free(rt->breakables);
  free(rt->clusters);
  free(rt->free_clusters);
  free(rt->split_queue);
  free(rt->created);
  free(rt->removed);
  free(rt->broken);
  free(rt->scratch_component);
  free(rt->scratch_stack);
  free(rt->scratch_position);
  free(rt->stress_scratch);
  free(rt->stress_load_scratch);
  free(rt);
}

void rt_begin_call(bk_runtime* rt) {
  rt->created_count = 0;
  rt->removed_count = 0;
  rt->broken_count = 0;
}

bk_cluster_id rt_cluster_id(const bk_runtime* rt, uint32_t slot) {
  return (bk_cluster_id){slot, rt->clusters[slot].generation};
}

rt_cluster* rt_find_cluster(const bk_runtime* rt, bk_cluster_id id) {
  if (id.generation == 0 || id.index >= rt->cluster_count) return NULL;
  rt_cluster* c = &rt->clusters[id.index];
  return c->alive && c->generation == id.generation ? c : NULL;
}

rt_breakable* rt_find_breakable(const bk_runtime* rt, bk_breakable_id id) {
  if (id.generation == 0 || id.index >= rt->breakable_count) return NULL;
  rt_breakable* b = &rt->breakables[id.index];
  return b->generation == id.generation ? b : NULL;
}

bk_body_state rt_body_state(const bk_runtime* rt, uint32_t slot) {
  bk_body_state state = rt->def.body_state(rt_cluster_id(rt, slot), rt->def.context);
  if (rt->clusters[slot].is_static) {
    state.linear_velocity = bk_v3(0, 0, 0);
    state.angular_velocity = bk_v3(0, 0, 0);
  }
  return state;
}

bk_transform rt_tree_to_world(const rt_cluster* c, const bk_body_state* state) {
  return bk_transform_mul(state->transform, bk_transform_inverse(c->principal));
}

void rt_record_removed(bk_runtime* rt, bk_cluster_id id) {
  if (rt->removed_count == rt->removed_capacity) {
    rt->removed_capacity = bk_grow_capacity(rt->removed_capacity, rt->removed_count + 1);
    rt->removed = bk_realloc(rt->removed, sizeof(bk_cluster_id) * rt->removed_capacity);
  }
  rt->removed[rt->removed_count++] = id;
}

static void fill_info(const bk_runtime* rt, uint32_t slot, bk_cluster_info* out) {
  const rt_cluster* c = &rt->clusters[slot];
  *out = (bk_cluster_info){.id = rt_cluster_id(rt, slot),
                           .breakable = {c->breakable, rt->breakables[c->breakable].generation},
                           .is_static = c->is_static,
                           .split_pending = c->dirty,
                           .leaves = c->leaves,
                           .leaf_count = c->leaf_count,
                           .nodes = c->nodes,
                           .node_count = c->node_count,
                           .mass = c->mass,
                           .volume = c->volume,
                           .principal = c->principal,
                           .inertia = c->inertia};
}

void rt_record_created(bk_runtime* rt, uint32_t slot, bk_cluster_id parent, bk_transform tree_to_world,
                       const bk_body_state* parent_state) {
  if (rt->created_count == rt->created_capacity) {
    rt->created_capacity = bk_grow_capacity(rt->created_capacity, rt->created_count + 1);
    rt->created = bk_realloc(rt->created, sizeof(bk_cluster_created) * rt->created_capacity);
  }
  bk_cluster_created* record = &rt->created[rt->created_count++];
  memset(record, 0, sizeof *record); // padding too: records compare equal bytewise run to run
  const rt_cluster* c = &rt->clusters[slot];
  fill_info(rt, slot, &record->cluster);
  record->parent = parent;
  record->body = (bk_body_state){.transform = bk_transform_mul(tree_to_world, c->principal)};
  if (!c->is_static && parent_state) {
    // A rigid body's velocity field evaluated at the new centre of mass.
    bk_vec3 r = bk_v3_sub(record->body.transform.position, parent_state->transform.position);
    record->body.linear_velocity =
        bk_v3_add(parent_state->linear_velocity, bk_v3_cross(parent_state->angular_velocity, r));
    record->body.angular_velocity = parent_state->angular_velocity;
  }
}

bool bk_runtime_cluster(const bk_runtime* rt, bk_cluster_id id, bk_cluster_info* out) {
  if (!rt_find_cluster(rt, id)) return false;
  fill_info(rt, id.index, out);
  return true;
}

uint32_t bk_runtime_clusters(const bk_runtime* rt, bk_cluster_id* out, uint32_t capacity) {
  uint32_t count = 0;
  for (uint32_t i = 0; i < rt->cluster_count; ++i) {
    if (!rt->clusters[i].alive) continue;
    if (out && count < capacity) out[count] = rt_cluster_id(rt, i);
    count++;
  }
  return count;
}

bk_cluster_id bk_runtime_leaf_cluster(const bk_runtime* rt, bk_breakable_id id, uint32_t leaf) {
  const rt_breakable* b = rt_find_breakable(rt, id);
  if (!b || leaf >= b->tree->leaf_count || b->leaf_cluster[leaf] == UINT32_MAX) return (bk_cluster_id){0, 0};
  return rt_cluster_id(rt, b->leaf_cluster[leaf]);
}

bool bk_runtime_remove_cluster(bk_runtime* rt, bk_cluster_id id) {
  rt_cluster* c = rt_find_cluster(rt, id);
  if (!c) return false;
  rt_begin_call(rt);
  rt_breakable* b = &rt->breakables[c->breakable];
  for (uint32_t i = 0; i < c->leaf_count; ++i)
    b->leaf_cluster[c->leaves[i]] = UINT32_MAX;
  rt_record_removed(rt, id);
  rt_cluster_free(rt, id.index);
  return true;
}

uint32_t bk_runtime_created_clusters(const bk_runtime* rt, bk_cluster_created* out, uint32_t capacity) {
  uint32_t n = rt->created_count < capacity ? rt->created_count : capacity;
  if (n && out) memcpy(out, rt->created, sizeof(bk_cluster_created) * n);
  return rt->created_count;
}

uint32_t bk_runtime_removed_clusters(const bk_runtime* rt, bk_cluster_id* out, uint32_t capacity) {
  uint32_t n = rt->removed_count < capacity ? rt->removed_count : capacity;
  if (n && out) memcpy(out, rt->removed, sizeof(bk_cluster_id) * n);
  return rt->removed_count;
}

uint32_t bk_runtime_broken_bonds(const bk_runtime* rt, bk_bond_break* out, uint32_t capacity) {
  uint32_t n = rt->broken_count < capacity ? rt->broken_count : capacity;
  if (n && out) memcpy(out, rt->broken, sizeof(bk_bond_break) * n);
  return rt->broken_count;
}

double bk_runtime_bond_health(const bk_runtime* rt, bk_breakable_id id, uint32_t bond, double* initial) {
  const rt_breakable* b = rt_find_breakable(rt, id);
  if (!b || bond >= b->tree->bond_count) {
    if (initial) *initial = 0.0;
    return 0.0;
  }
  if (initial) *initial = b->bond_hp_initial[bond];
  return b->bond_broken[bond] ? 0.0 : b->bond_hp[bond];
}

bk_runtime_stats bk_runtime_get_stats(const bk_runtime* rt) {
  return (bk_runtime_stats){.breakables = rt->breakable_count,
                            .clusters = rt->live_count,
                            .bonds_broken = rt->bonds_broken,
                            .splits = rt->splits,
                            .pending_splits = rt->split_queue_count,
                            .stress_bonds_broken = rt->stress_bonds_broken,
                            .stress_clusters_solved = rt->stress_clusters_solved,
                            .stress_iterations = rt->stress_iterations,
                            .stress_clusters_pending = rt_stress_pending(rt)};
}
