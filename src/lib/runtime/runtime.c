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
                          .gravity = {0.0, -9.81, 0.0},
                          .refine_latency = 1,
                          .refine_threads = 1,
                          .max_refinements_per_call = 4,
                          .journal = false,
                          .body_state = NULL,
                          .context = NULL};
}

bk_runtime* bk_runtime_create(const bk_runtime_def* def, bk_error* err) {
  if (!def) return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "runtime: def is NULL"), NULL;
  if (!bk_runtime_def_validate(def, "runtime: ", err)) return NULL;
  // An allocator that runs out makes creation fail with an error, not abort.
  bk_runtime* rt = bk_try_calloc(1, sizeof *rt);
  if (!rt) return bk_error_set_code(err, BK_ERROR_OUT_OF_MEMORY, "runtime: out of memory"), NULL;
  rt->def = *def;
  bk_runtime_set_gravity(rt, def->gravity);
  return rt;
}

bk_result bk_runtime_set_gravity(bk_runtime* rt, bk_vec3 gravity) {
  if (!bk_v3_is_finite(gravity)) return BK_ERROR_INVALID_ARGUMENT;
  rt->def.gravity = gravity;
  // Scaled first, so that a huge finite gravity's length does not overflow.
  double largest = fmax(fabs(gravity.x), fmax(fabs(gravity.y), fabs(gravity.z)));
  if (largest > 1e100) gravity = bk_v3_scale(gravity, 1.0 / largest);
  double g = bk_v3_length(gravity);
  rt->up = g > 0.0 ? bk_v3_scale(gravity, -1.0 / g) : bk_v3(0, 1, 0);
  return BK_OK;
}

bk_vec3 bk_runtime_gravity(const bk_runtime* rt) { return rt->def.gravity; }

void bk_runtime_destroy(bk_runtime* rt) {
  if (!rt) return;
  rt_refine_cancel(rt, UINT32_MAX); // workers read the trees' meshes
  bk_free(rt->refine_jobs);
  bk_free(rt->refined);
  bk_free(rt->journal);
  for (uint32_t i = 0; i < rt->cluster_count; ++i) {
    bk_free(rt->clusters[i].leaves);
    bk_free(rt->clusters[i].nodes);
    bk_free(rt->clusters[i].split_labels);
    rt_stress_release(&rt->clusters[i]);
  }
  for (uint32_t i = 0; i < rt->breakable_count; ++i)
    rt_breakable_free(&rt->breakables[i]);
  bk_free(rt->breakables);
  bk_free(rt->clusters);
  bk_free(rt->free_clusters);
  bk_free(rt->split_queue);
  bk_free(rt->created);
  bk_free(rt->removed);
  bk_free(rt->broken);
  bk_free(rt->scratch_component);
  bk_free(rt->scratch_stack);
  bk_free(rt->scratch_position);
  bk_free(rt->stress_scratch);
  bk_free(rt->stress_load_scratch);
  bk_free(rt->stress_commands);
  bk_free(rt);
}

void bk_runtime_clear_events(bk_runtime* rt) {
  for (uint32_t i = 0; i < rt->created_count; ++i)
    rt->clusters[rt->created[i].slot].created_event = 0; // the caller has its body now
  rt->created_count = 0;
  rt->removed_count = 0;
  rt->broken_count = 0;
  rt->refined_count = 0;
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

uint32_t bk_runtime_cluster_capacity(const bk_runtime* rt) { return rt->cluster_count; }

void* bk_runtime_cluster_user_data(const bk_runtime* rt, bk_cluster_id id) {
  const rt_cluster* c = rt_find_cluster(rt, id);
  return c ? c->user_data : NULL;
}

bk_result bk_runtime_set_cluster_user_data(bk_runtime* rt, bk_cluster_id id, void* user_data) {
  rt_cluster* c = rt_find_cluster(rt, id);
  if (!c) return BK_ERROR_STALE_ID;
  c->user_data = user_data;
  return BK_OK;
}

bk_result bk_runtime_remove_cluster(bk_runtime* rt, bk_cluster_id id) {
  if (!rt_find_cluster(rt, id)) return BK_ERROR_STALE_ID;
  rt_journal_remove(rt, id.index);
  rt_remove_cluster(rt, id.index);
  return BK_OK;
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
  return (bk_runtime_stats){.breakables = rt->live_breakables,
                            .clusters = rt->live_count,
                            .bonds_broken = rt->bonds_broken,
                            .splits = rt->splits,
                            .pending_splits = rt->split_queue_count,
                            .stress_bonds_broken = rt->stress_bonds_broken,
                            .stress_clusters_solved = rt->stress_clusters_solved,
                            .stress_iterations = rt->stress_iterations,
                            .stress_clusters_pending = rt_stress_pending(rt),
                            .refined_leaves = rt->refined_leaves,
                            .refine_pending = rt->refine_job_count,
                            .refine_failed = rt->refine_failed};
}
