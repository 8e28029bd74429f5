// Damage (thesis 5.2.1): a contact whose impulse and closing speed pass the
// thresholds damages every bond of the body it hit by
//   damage = frailty x impulse / max(s, s_min)^3,
// s = distance from the contact to the bond's centroid. The impulse is the
// one Bullet's solver applied. Resting contact closes at ~g dt and split
// impulse keeps penetration recovery out of the impulse, so neither breaks
// anything.
#include "sim_internal.h"

static void record_event(bk_world* w, uint32_t breakable_index, uint32_t bond, bk_vec3 position,
                         bk_vec3 velocity, double area) {
  if (w->event_count == w->event_capacity) {
    w->event_capacity = bk_grow_capacity(w->event_capacity, w->event_count + 1);
    w->events = bk_realloc(w->events, sizeof(bk_break_event) * w->event_capacity);
  }
  const breakable* b = &w->breakables[breakable_index];
  w->events[w->event_count++] =
      (bk_break_event){{breakable_index, b->generation}, bond, position, velocity, area};
}

void bk_world_queue_split(bk_world* w, uint32_t slot) {
  cluster* c = &w->clusters[slot];
  c->dirty = true;
  if (c->queued) return;
  c->queued = true;
  if (w->split_queue_count == w->split_queue_capacity) {
    w->split_queue_capacity = bk_grow_capacity(w->split_queue_capacity, w->split_queue_count + 1);
    w->split_queue = bk_realloc(w->split_queue, sizeof(uint32_t) * w->split_queue_capacity);
  }
  w->split_queue[w->split_queue_count++] = slot;
}

static void damage_cluster(bk_world* w, uint32_t slot, bk_vec3 point, double impulse) {
  cluster* c = &w->clusters[slot];
  breakable* b = &w->breakables[c->breakable];
  const bk_mesh_tree* tree = b->tree;
  bk_transform tree_to_world = bk_cluster_tree_to_world(w, c);
  bk_vec3 local = bk_transform_point(bk_transform_inverse(tree_to_world), point);
  double s_min = w->desc.damage_min_distance;
  bool broke = false;
  for (uint32_t i = 0; i < c->leaf_count; ++i) {
    uint32_t leaf = c->leaves[i];
    for (uint32_t k = b->adjacency_start[leaf]; k < b->adjacency_start[leaf + 1]; ++k) {
      uint32_t bond = b->adjacency[k];
      const bk_bond* bd = &tree->bonds[bond];
      // Each bond once (from its lower leaf), and only bonds inside this body.
      if (bd->leaf_a != leaf || b->bond_broken[bond] || b->leaf_cluster[bd->leaf_b] != slot) continue;
      double s = fmax(bk_v3_length(bk_v3_sub(local, bd->centroid)), s_min);
      double damage = b->frailty * impulse / (s * s * s);
      bool breaks = false;
      if (b->accumulate) {
        b->bond_hp[bond] -= damage;
        breaks = b->bond_hp[bond] <= 0.0;
      } else {
        breaks = damage > b->bond_hp[bond];
      }
      if (!breaks) continue;
      b->bond_hp[bond] = 0.0;
      b->bond_broken[bond] = 1;
      w->bonds_broken++;
      broke = true;
      bk_vec3 world_point = bk_transform_point(tree_to_world, bd->centroid);
      bk_vec3 velocity = {0};
      if (!c->is_static) {
        bk_vec3 v = bk_physics_body_linear_velocity(w->physics, c->body);
        bk_vec3 omega = bk_physics_body_angular_velocity(w->physics, c->body);
        bk_vec3 r = bk_v3_sub(world_point, bk_physics_body_transform(w->physics, c->body).position);
        velocity = bk_v3_add(v, bk_v3_cross(omega, r));
      }
      record_event(w, c->breakable, bond, world_point, velocity, bd->area);
    }
  }
  if (broke) bk_world_queue_split(w, slot);
}

static bool cluster_of(const bk_world* w, bk_body_id body, uint32_t* slot) {
  uint64_t user = bk_physics_body_user_data(w->physics, body);
  if (!(user & BK_USER_CLUSTER)) return false;
  *slot = (uint32_t)user;
  return *slot < w->cluster_count && w->clusters[*slot].alive && bk_body_equal(w->clusters[*slot].body, body);
}

void bk_world_impact(bk_world* w, bk_vec3 point, double impulse) {
  if (!bk_v3_is_finite(point) || !(impulse > 0.0) || !isfinite(impulse)) return;
  uint32_t count = w->cluster_count; // clusters made by this call's splits come later
  for (uint32_t slot = 0; slot < count; ++slot)
    if (w->clusters[slot].alive) damage_cluster(w, slot, point, impulse);
}

void bk_world_apply_damage(bk_world* w, uint32_t contact_count) {
  uint32_t n = contact_count < w->contact_capacity ? contact_count : w->contact_capacity;
  for (uint32_t i = 0; i < n; ++i) {
    const bk_contact* ct = &w->contacts[i];
    if (ct->impulse < w->desc.impulse_threshold || ct->approach_speed < w->desc.impact_speed) continue;
    uint32_t slot = 0;
    if (cluster_of(w, ct->a, &slot)) damage_cluster(w, slot, ct->point, ct->impulse);
    if (cluster_of(w, ct->b, &slot)) damage_cluster(w, slot, ct->point, ct->impulse);
  }
}
