// Hits over steps: a step applies the damage of its contacts (and of those
// that waited) up to max_hit_fragments_per_step fragments swept, oldest
// first; the rest wait. A hit weighs every bond of its cluster, so sixteen
// 1,024-fragment walls shot in one step cost 16 x 0.75 ms in that step
// alone: spread, each step pays for one. A hit that waits keeps its place
// on the object (its point in the tree frame), not in the world.
#include <stdlib.h>
#include <string.h>

#include "world_internal.h"

static void reserve_hits(bk_world* w, uint32_t need) {
  if (need > w->hit_capacity) {
    w->hit_capacity = bk_grow_capacity(w->hit_capacity, need);
    w->hits = bk_realloc(w->hits, sizeof(world_hit) * w->hit_capacity);
  }
  if (need > w->hit_batch_capacity) {
    w->hit_batch_capacity = bk_grow_capacity(w->hit_batch_capacity, need);
    w->hit_batch = bk_realloc(w->hit_batch, sizeof(bk_damage_contact) * w->hit_batch_capacity);
  }
}

// Keeps the hits from `from` on waiting, each placed on its object.
static void keep_waiting(bk_world* w, uint32_t from) {
  for (uint32_t i = from; i < w->hit_count; ++i) {
    world_hit* hit = &w->hits[i];
    if (hit->step != w->step_count) continue; // placed when it first waited
    bk_transform to_tree = bk_transform_inverse(bk_world_tree_to_world(w, hit->cluster.index));
    hit->local = bk_transform_point(to_tree, hit->point);
  }
  w->hit_count -= from;
  if (w->hit_count) memmove(w->hits, w->hits + from, sizeof(world_hit) * w->hit_count);
}

uint32_t bk_world_apply_hits(bk_world* w, uint32_t count) {
  // Hits waited and held the last step's splits: if splits wait too, this
  // step is theirs (neither queue starves the other).
  bool split_turn =
      w->hit_count > 0 && w->hits_held_last && bk_runtime_get_stats(w->runtime).pending_splits > 0;
  reserve_hits(w, w->hit_count + count);
  // The step's hits join the queue: those the runtime would apply (past its
  // thresholds) on clusters with bonds to break (a single fragment has
  // none) or that may be refined (a single fragment too).
  for (uint32_t i = 0; i < count; ++i) {
    const bk_damage_contact* ct = &w->damage[i];
    const bk_runtime_def* rd = &w->def.runtime;
    if (!(ct->impulse >= rd->impulse_threshold) || !(ct->closing_speed >= rd->impact_speed) ||
        !isfinite(ct->impulse) || !bk_v3_is_finite(ct->point))
      continue;
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(w->runtime, ct->cluster, &info)) continue;
    if (info.leaf_count < 2 && !(bk_runtime_material(w->runtime, info.breakable).refine_strength > 0.0))
      continue;
    w->hits[w->hit_count++] = (world_hit){.cluster = ct->cluster,
                                          .point = ct->point,
                                          .local = ct->point,
                                          .impulse = ct->impulse,
                                          .closing_speed = ct->closing_speed,
                                          .step = w->step_count};
  }
  if (split_turn) {
    w->hits_held_last = false;
    keep_waiting(w, 0);
    return w->hit_count;
  }
  // Oldest first, as far as the budget goes (at least one a step). Within
  // a call no cluster changes, so one batch applies them in order.
  uint64_t budget = w->def.max_hit_fragments_per_step, used = 0;
  uint32_t next = 0, batch = 0;
  for (; next < w->hit_count; ++next) {
    const world_hit* hit = &w->hits[next];
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(w->runtime, hit->cluster, &info)) continue; // split meanwhile: dropped
    if (used > 0 && used + info.leaf_count > budget) break;
    used += info.leaf_count;
    bk_vec3 point = hit->point;
    if (hit->step != w->step_count)
      point = bk_transform_point(bk_world_tree_to_world(w, hit->cluster.index), hit->local);
    w->hit_batch[batch++] = (bk_damage_contact){hit->cluster, point, hit->impulse, hit->closing_speed};
  }
  bk_runtime_apply_contacts(w->runtime, w->hit_batch, batch);
  keep_waiting(w, next);
  // Hits left waiting hold this step's splits: damage and new bodies do not add up in one step.
  w->hits_hold_splits = w->hits_held_last = w->hit_count > 0;
  return w->hit_count;
}
