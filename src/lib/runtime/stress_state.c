// The stress state the core keeps with each cluster (filled by the stress
// stage, stress.c): freed with the cluster, made stale when its material
// changes, and counted while its solve is pending. The stage reads the core;
// the core never calls the stage.
#include "runtime_internal.h"

void rt_stress_drop_loads(rt_cluster* c) {
  bk_free(c->stress_loads);
  bk_free(c->stress_window);
  c->stress_loads = NULL;
  c->stress_window = NULL;
  c->stress_load_count = c->stress_window_count = c->stress_window_calls = 0;
}

void rt_stress_release(rt_cluster* c) {
  rt_stress_destroy(c->stress);
  bk_free(c->stress_held);
  c->stress = NULL;
  c->stress_held = NULL;
  c->stress_held_count = 0;
  rt_stress_drop_loads(c);
}

uint32_t rt_stress_pending(const bk_runtime* rt) {
  uint32_t pending = 0;
  for (uint32_t slot = 0; slot < rt->cluster_count; ++slot) {
    const rt_cluster* c = &rt->clusters[slot];
    // A static cluster always has a load; a moving one once it rested. A
    // bond broken since its last solve makes it pending too.
    bool loaded = c->is_static || c->stress;
    if (c->alive && loaded && c->leaf_count >= 2 && (!c->stress_settled || c->stress_stale)) pending++;
  }
  return pending;
}

void rt_stress_material_changed(bk_runtime* rt, uint32_t breakable_index) {
  for (uint32_t slot = 0; slot < rt->cluster_count; ++slot) {
    rt_cluster* c = &rt->clusters[slot];
    if (c->alive && c->breakable == breakable_index) c->stress_stale = true;
  }
}

void rt_stress_forget_leaves(rt_breakable* b) {
  bk_free(b->leaf_centroid);
  bk_free(b->leaf_volume);
  bk_free(b->leaf_motion);
  bk_free(b->bond_stress);
  b->leaf_centroid = NULL;
  b->leaf_volume = NULL;
  b->leaf_motion = NULL;
  b->bond_stress = NULL;
}
