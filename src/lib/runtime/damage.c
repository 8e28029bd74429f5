// Damage (thesis 5.2.1): a contact whose impulse and closing speed pass the
// thresholds damages every bond of the cluster it hit by
//   damage = frailty x impulse / max(s, s_min)^3,
// s = distance from the contact to the bond's centroid. The impulse is the
// one the caller's solver applied; resting contact closes at ~g dt, so with
// penetration recovery kept out of the impulse (split impulse) resting breaks
// nothing.
#include <stdlib.h>

#include "runtime_internal.h"

void rt_break_bond(bk_runtime* rt, uint32_t slot, uint32_t bond, bk_vec3 position, bk_vec3 velocity,
                   bk_break_cause cause) {
  if (rt->broken_count == rt->broken_capacity) {
    rt->broken_capacity = bk_grow_capacity(rt->broken_capacity, rt->broken_count + 1);
    rt->broken = bk_realloc(rt->broken, sizeof(bk_bond_break) * rt->broken_capacity);
  }
  rt_cluster* c = &rt->clusters[slot];
  rt_breakable* b = &rt->breakables[c->breakable];
  bk_free(c->split_labels); // its components change
  c->split_labels = NULL;
  b->bond_hp[bond] = 0.0;
  b->bond_broken[bond] = 1;
  rt->bonds_broken++;
  rt->broken[rt->broken_count++] = (bk_bond_break){.breakable = {c->breakable, b->generation},
                                                   .cluster = rt_cluster_id(rt, slot),
                                                   .bond = bond,
                                                   .position = position,
                                                   .velocity = velocity,
                                                   .area = b->tree->bonds[bond].area,
                                                   .cause = cause,
                                                   .user_data = c->user_data,
                                                   .breakable_user_data = b->user_data};
}

void rt_queue_split(bk_runtime* rt, uint32_t slot) {
  rt_cluster* c = &rt->clusters[slot];
  c->dirty = true;
  c->stress_stale = true; // its bonds changed
  if (c->queued) return;
  c->queued = true;
  if (rt->split_queue_count == rt->split_queue_capacity) {
    rt->split_queue_capacity = bk_grow_capacity(rt->split_queue_capacity, rt->split_queue_count + 1);
    rt->split_queue = bk_realloc(rt->split_queue, sizeof(uint32_t) * rt->split_queue_capacity);
  }
  rt->split_queue[rt->split_queue_count++] = slot;
}

bool rt_bond_damage(rt_breakable* b, uint32_t bond, double damage) {
  if (b->material.accumulate) {
    b->bond_hp[bond] -= damage;
    return b->bond_hp[bond] <= 0.0;
  }
  return damage > b->bond_hp[bond];
}

void rt_break_bond_by_hit(bk_runtime* rt, uint32_t slot, uint32_t bond) {
  rt_cluster* c = &rt->clusters[slot];
  const bk_bond* bd = &rt->breakables[c->breakable].tree->bonds[bond];
  bk_body_state state = rt_body_state(rt, slot);
  bk_transform tree_to_world = rt_tree_to_world(c, &state);
  bk_vec3 world_point = bk_transform_point(tree_to_world, bd->centroid);
  bk_vec3 r = bk_v3_sub(world_point, state.transform.position);
  bk_vec3 velocity = bk_v3_add(state.linear_velocity, bk_v3_cross(state.angular_velocity, r));
  rt_break_bond(rt, slot, bond, world_point, velocity, BK_BREAK_DAMAGE);
}

void rt_damage_local(bk_runtime* rt, uint32_t slot, bk_vec3 local, double impulse) {
  rt_cluster* c = &rt->clusters[slot];
  rt_breakable* b = &rt->breakables[c->breakable];
  const bk_mesh_tree* tree = b->tree;
  bk_body_state state = rt_body_state(rt, slot);
  bk_transform tree_to_world = rt_tree_to_world(c, &state);
  rt_journal_hit(rt, slot, local, impulse);
  double s_min = rt->def.damage_min_distance;
  // Fragments this hit refines, and those already waiting for their
  // pieces, take its damage when their pieces land.
  rt_refine_hit_cluster(rt, slot, local, impulse);
  bool broke = false;
  for (uint32_t i = 0; i < c->leaf_count; ++i) {
    uint32_t leaf = c->leaves[i];
    for (uint32_t k = b->adjacency_start[leaf]; k < b->adjacency_start[leaf + 1]; ++k) {
      uint32_t bond = b->adjacency[k];
      const bk_bond* bd = &tree->bonds[bond];
      if (!rt_bond_inside(b, bond, leaf, slot) || rt_bond_waits(b, bd)) continue;
      double s = fmax(bk_v3_length(bk_v3_sub(local, bd->centroid)), s_min);
      double damage = b->material.frailty * impulse / (s * s * s);
      if (!rt_bond_damage(b, bond, damage)) continue;
      broke = true;
      bk_vec3 world_point = bk_transform_point(tree_to_world, bd->centroid);
      bk_vec3 r = bk_v3_sub(world_point, state.transform.position);
      bk_vec3 velocity = bk_v3_add(state.linear_velocity, bk_v3_cross(state.angular_velocity, r));
      rt_break_bond(rt, slot, bond, world_point, velocity, BK_BREAK_DAMAGE);
    }
  }
  if (broke) rt_queue_split(rt, slot);
}

static void damage_cluster(bk_runtime* rt, uint32_t slot, bk_vec3 point, double impulse) {
  rt_cluster* c = &rt->clusters[slot];
  bk_body_state state = rt_body_state(rt, slot);
  bk_transform tree_to_world = rt_tree_to_world(c, &state);
  bk_vec3 local = bk_transform_point(bk_transform_inverse(tree_to_world), point);
  // A body the caller's physics has lost (NaN or overflowed state) puts the
  // hit nowhere: every distance would be NaN, read as s_min, and every bond
  // would break.
  if (!bk_v3_is_finite(local)) return;
  rt_damage_local(rt, slot, local, impulse);
}

void bk_runtime_damage_at(bk_runtime* rt, bk_vec3 point, double impulse) {
  if (!bk_v3_is_finite(point) || !(impulse > 0.0) || !isfinite(impulse)) return;
  for (uint32_t slot = 0; slot < rt->cluster_count; ++slot)
    if (rt->clusters[slot].alive) damage_cluster(rt, slot, point, impulse);
}

void bk_runtime_apply_contacts(bk_runtime* rt, const bk_damage_contact* contacts, uint32_t count) {
  if (!contacts) count = 0; // no array: nothing to index into
  for (uint32_t i = 0; i < count; ++i) {
    const bk_damage_contact* ct = &contacts[i];
    if (!(ct->impulse >= rt->def.impulse_threshold) || !(ct->closing_speed >= rt->def.impact_speed) ||
        !isfinite(ct->impulse) || !bk_v3_is_finite(ct->point))
      continue;
    if (rt_find_cluster(rt, ct->cluster)) damage_cluster(rt, ct->cluster.index, ct->point, ct->impulse);
  }
}
