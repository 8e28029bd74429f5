// The simulation world: breakables, their cluster bodies, projectiles, the
// fixed step, and what the layers above pull out of it (stats, views, events).
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sim_internal.h"

static double now_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

bk_world_desc bk_default_world_desc(void) {
  return (bk_world_desc){.gravity = {0.0, -9.81, 0.0},
                         .fixed_dt = 1.0 / 60.0,
                         .impact_speed = 1.0,
                         .impulse_threshold = 0.5,
                         .damage_min_distance = 0.05,
                         .max_new_bodies_per_step = 48,
                         .projectile_lifetime = 8.0,
                         .retire_after = 10.0};
}

bk_world* bk_world_create(const bk_world_desc* desc_in, bk_error* err) {
  bk_world_desc d = *desc_in, def = bk_default_world_desc();
  if (d.gravity.x == 0.0 && d.gravity.y == 0.0 && d.gravity.z == 0.0) d.gravity = def.gravity;
  if (d.fixed_dt == 0.0) d.fixed_dt = def.fixed_dt;
  if (d.impact_speed == 0.0) d.impact_speed = def.impact_speed;
  if (d.impulse_threshold == 0.0) d.impulse_threshold = def.impulse_threshold;
  if (d.damage_min_distance == 0.0) d.damage_min_distance = def.damage_min_distance;
  if (d.max_new_bodies_per_step == 0) d.max_new_bodies_per_step = def.max_new_bodies_per_step;
  if (d.projectile_lifetime == 0.0) d.projectile_lifetime = def.projectile_lifetime;
  if (d.retire_after == 0.0) d.retire_after = def.retire_after;
  if (!(d.retire_volume >= 0.0) || !isfinite(d.retire_volume) || !(d.retire_after > 0.0) ||
      !isfinite(d.retire_after))
    return bk_error_set(err, "world: retire_volume must be >= 0 and retire_after positive"), NULL;
  if (!(d.projectile_lifetime > 0.0) || !isfinite(d.projectile_lifetime))
    return bk_error_set(err, "world: projectile_lifetime must be positive (got %g)", d.projectile_lifetime),
           NULL;
  if (!bk_v3_is_finite(d.gravity)) return bk_error_set(err, "world: gravity must be finite"), NULL;
  if (!(d.fixed_dt > 0.0 && d.fixed_dt <= 0.1))
    return bk_error_set(err, "world: fixed_dt must be in (0, 0.1] s (got %g)", d.fixed_dt), NULL;
  if (!(d.impact_speed >= 0.0) || !isfinite(d.impact_speed) || !(d.impulse_threshold >= 0.0) ||
      !isfinite(d.impulse_threshold))
    return bk_error_set(err, "world: impact_speed and impulse_threshold must be finite and >= 0"), NULL;
  if (d.max_new_bodies_per_step < 2)
    return bk_error_set(err, "world: max_new_bodies_per_step must be at least 2 (got %u)",
                        d.max_new_bodies_per_step),
           NULL;
  if (!(d.damage_min_distance > 0.0) || !isfinite(d.damage_min_distance))
    return bk_error_set(err, "world: damage_min_distance must be positive (got %g)", d.damage_min_distance),
           NULL;

  bk_physics_desc pd = bk_default_physics_desc();
  pd.gravity = d.gravity;
  pd.fixed_dt = d.fixed_dt;
  bk_physics* physics = bk_physics_create(&pd, err);
  if (!physics) return NULL;
  bk_world* w = bk_calloc(1, sizeof *w);
  w->desc = d;
  w->physics = physics;
  w->contact_capacity = 65536;
  w->contacts = bk_alloc(sizeof(bk_contact) * w->contact_capacity);
  if (!d.no_ground) {
    w->ground = bk_physics_create_plane(physics, bk_v3(0, 1, 0), 0.0);
    bk_body_desc gd = bk_default_body_desc();
    gd.shape = w->ground;
    gd.friction = 0.8;
    w->ground_body = bk_physics_create_body(physics, &gd, err);
  }
  return w;
}

static void free_breakable(breakable* b) {
  free(b->adjacency_start);
  free(b->adjacency);
  free(b->bond_hp);
  free(b->bond_hp_initial);
  free(b->bond_broken);
  free(b->leaf_cluster);
  free(b->leaf_anchored);
  free(b->node_hull);
  free(b->node_body_hull);
  free(b->node_convex);
}

void bk_world_destroy(bk_world* w) {
  if (!w) return;
  // Destroying the physics world releases every body and shape in it.
  bk_physics_destroy(w->physics);
  for (uint32_t i = 0; i < w->cluster_count; ++i) {
    free(w->clusters[i].leaves);
    free(w->clusters[i].nodes);
    free(w->clusters[i].colliders);
  }
  for (uint32_t i = 0; i < w->breakable_count; ++i)
    free_breakable(&w->breakables[i]);
  free(w->breakables);
  free(w->clusters);
  free(w->free_clusters);
  free(w->live);
  free(w->split_queue);
  free(w->projectiles);
  free(w->projectile_radius);
  free(w->projectile_shape);
  free(w->projectile_born);
  free(w->contacts);
  free(w->events);
  free(w->scratch_leaves);
  free(w->scratch_component);
  free(w->scratch_stack);
  free(w);
}

bk_physics* bk_world_physics(bk_world* w) { return w->physics; }

bk_breakable_desc bk_default_breakable_desc(void) {
  return (bk_breakable_desc){.transform = {{0, 0, 0}, {0, 0, 0, 1}},
                             .density = 2400.0,
                             .frailty = 1.0,
                             .bond_strength = 2.0e5,
                             .convexity_tolerance = 0.1,
                             .friction = 0.6,
                             .restitution = 0.1};
}

static breakable* find_breakable(const bk_world* w, bk_breakable_id id) {
  if (id.generation == 0 || id.index >= w->breakable_count) return NULL;
  breakable* b = &w->breakables[id.index];
  return b->generation == id.generation ? b : NULL;
}

#define CHECK_POSITIVE(field)                                                                                \
  if (!(d.field > 0.0) || !isfinite(d.field))                                                                \
    return bk_error_set(err, "breakable: " #field " must be a positive finite number (got %g)", d.field),    \
           null_id;

bk_breakable_id bk_world_add_breakable(bk_world* w, const bk_breakable_desc* desc, bk_error* err) {
  bk_breakable_id null_id = {0, 0};
  bk_breakable_desc d = *desc, def = bk_default_breakable_desc();
  if (!d.tree || d.tree->node_count == 0 || d.tree->leaf_count == 0)
    return bk_error_set(err, "breakable: tree is missing or empty"), null_id;
  bk_quat q = d.transform.rotation;
  if (q.x == 0.0 && q.y == 0.0 && q.z == 0.0 && q.w == 0.0) d.transform.rotation = bk_quat_identity();
  if (d.density == 0.0) d.density = def.density;
  if (d.frailty == 0.0) d.frailty = def.frailty;
  if (d.bond_strength == 0.0) d.bond_strength = def.bond_strength;
  if (d.convexity_tolerance == 0.0) d.convexity_tolerance = def.convexity_tolerance;
  if (d.friction == 0.0) d.friction = def.friction;
  if (d.restitution == 0.0) d.restitution = def.restitution;
  CHECK_POSITIVE(density)
  CHECK_POSITIVE(frailty)
  CHECK_POSITIVE(bond_strength)
  CHECK_POSITIVE(convexity_tolerance)
  if (!bk_v3_is_finite(d.transform.position) || !isfinite(d.transform.rotation.x + d.transform.rotation.y +
                                                          d.transform.rotation.z + d.transform.rotation.w))
    return bk_error_set(err, "breakable: transform must be finite"), null_id;
  if (!isfinite(d.anchor_height) || !(d.friction >= 0.0) || !(d.restitution >= 0.0))
    return bk_error_set(err, "breakable: anchor_height, friction and restitution must be finite and >= 0"),
           null_id;
  d.transform.rotation = bk_quat_normalize(d.transform.rotation);

  if (w->breakable_count == w->breakable_capacity) {
    w->breakable_capacity = bk_grow_capacity(w->breakable_capacity, w->breakable_count + 1);
    w->breakables = bk_realloc(w->breakables, sizeof(breakable) * w->breakable_capacity);
  }
  uint32_t index = w->breakable_count++;
  breakable* b = &w->breakables[index];
  memset(b, 0, sizeof *b);
  const bk_mesh_tree* tree = d.tree;
  b->tree = tree;
  b->generation = 1;
  b->density = d.density;
  b->frailty = d.frailty;
  b->accumulate = d.accumulate;
  b->convex_colliders = d.convex_colliders;
  b->convexity_tolerance = d.convexity_tolerance;
  b->naive = d.naive;
  b->friction = d.friction;
  b->restitution = d.restitution;

  // The BCRB graph: bonds incident to each leaf (CSR), hit points by area.
  uint32_t leaves = tree->leaf_count, bonds = tree->bond_count;
  b->adjacency_start = bk_calloc(leaves + 1u, sizeof(uint32_t));
  b->adjacency = bk_alloc(sizeof(uint32_t) * (2u * bonds + 1u));
  for (uint32_t i = 0; i < bonds; ++i) {
    b->adjacency_start[tree->bonds[i].leaf_a + 1]++;
    b->adjacency_start[tree->bonds[i].leaf_b + 1]++;
  }
  for (uint32_t i = 0; i < leaves; ++i)
    b->adjacency_start[i + 1] += b->adjacency_start[i];
  uint32_t* fill = bk_alloc(sizeof(uint32_t) * (leaves + 1u));
  memcpy(fill, b->adjacency_start, sizeof(uint32_t) * leaves);
  for (uint32_t i = 0; i < bonds; ++i) {
    b->adjacency[fill[tree->bonds[i].leaf_a]++] = i;
    b->adjacency[fill[tree->bonds[i].leaf_b]++] = i;
  }
  free(fill);
  b->bond_hp = bk_alloc(sizeof(double) * (bonds + 1u));
  b->bond_hp_initial = bk_alloc(sizeof(double) * (bonds + 1u));
  b->bond_broken = bk_calloc(bonds + 1u, 1);
  for (uint32_t i = 0; i < bonds; ++i)
    b->bond_hp[i] = b->bond_hp_initial[i] = d.bond_strength * tree->bonds[i].area;
  b->leaf_cluster = bk_alloc(sizeof(uint32_t) * leaves);
  b->leaf_anchored = bk_calloc(leaves, 1);
  b->node_hull = bk_calloc(tree->node_count, sizeof(bk_shape_id));
  b->node_body_hull = bk_calloc(tree->node_count, sizeof(bk_shape_id));
  b->node_convex = bk_alloc(tree->node_count);
  memset(b->node_convex, 0xff, tree->node_count);
  if (d.anchored) {
    // Fragments with a vertex on the support plane are bonded to the world.
    double tolerance =
        1e-6 + 1e-6 * bk_v3_length(bk_v3_sub(tree->nodes[0].bounds.max, tree->nodes[0].bounds.min));
    for (uint32_t l = 0; l < leaves; ++l) {
      const bk_mesh* mesh = &bk_mesh_tree_leaf(tree, l)->mesh;
      for (uint32_t p = 0; p < mesh->position_count && !b->leaf_anchored[l]; ++p)
        b->leaf_anchored[l] =
            bk_transform_point(d.transform, mesh->positions[p]).y <= d.anchor_height + tolerance;
    }
  }

  bk_breakable_prepare_hulls(w, index);
  uint32_t slot = bk_cluster_alloc(w, index);
  cluster* c = &w->clusters[slot];
  c->leaves = bk_alloc(sizeof(uint32_t) * leaves);
  for (uint32_t l = 0; l < leaves; ++l)
    c->leaves[l] = l;
  c->leaf_count = leaves;
  bk_motion still = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  if (!bk_cluster_build(w, slot, d.transform, still, err)) {
    bk_cluster_release(w, slot);
    free_breakable(b);
    w->breakable_count--;
    return null_id;
  }
  bk_world_refresh_live(w);
  return (bk_breakable_id){index, b->generation};
}

void bk_world_set_frailty(bk_world* w, bk_breakable_id id, double frailty) {
  breakable* b = find_breakable(w, id);
  if (b && frailty > 0.0 && isfinite(frailty)) b->frailty = frailty;
}

void bk_world_set_density(bk_world* w, bk_breakable_id id, double density) {
  breakable* b = find_breakable(w, id);
  if (!b || !(density > 0.0) || !isfinite(density)) return;
  b->density = density;
  for (uint32_t i = 0; i < w->cluster_count; ++i) {
    cluster* c = &w->clusters[i];
    if (!c->alive || &w->breakables[c->breakable] != b) continue;
    bk_transform principal = {0};
    bk_vec3 inertia = {0};
    bk_cluster_mass(w, c, &c->mass, &principal, &inertia);
    if (!c->is_static) bk_physics_body_set_mass(w->physics, c->body, c->mass, inertia);
  }
}

bk_body_id bk_world_fire(bk_world* w, const bk_projectile_desc* desc) {
  double radius = desc->radius > 0.0 ? desc->radius : 0.08;
  double mass = desc->mass > 0.0 ? desc->mass : 4.0;
  bk_body_id null_id = {0, 0};
  if (!bk_v3_is_finite(desc->position) || !bk_v3_is_finite(desc->velocity) || !isfinite(radius) ||
      !isfinite(mass))
    return null_id;
  bk_shape_id sphere = bk_physics_create_sphere(w->physics, radius);
  bk_body_desc bd = bk_default_body_desc();
  bd.shape = sphere;
  bd.mass = mass;
  double moment = 0.4 * mass * radius * radius;
  bd.inertia = bk_v3(moment, moment, moment);
  bd.transform.position = desc->position;
  bd.linear_velocity = desc->velocity;
  bd.ccd = true;
  bd.ccd_radius = radius;
  bd.user_data = BK_USER_PROJECTILE;
  bk_body_id body = bk_physics_create_body(w->physics, &bd, NULL);
  if (bk_body_is_null(body)) {
    bk_physics_destroy_shape(w->physics, sphere);
    return body;
  }
  if (w->projectile_count == w->projectile_capacity) {
    w->projectile_capacity = bk_grow_capacity(w->projectile_capacity, w->projectile_count + 1);
    w->projectiles = bk_realloc(w->projectiles, sizeof(bk_body_id) * w->projectile_capacity);
    w->projectile_radius = bk_realloc(w->projectile_radius, sizeof(double) * w->projectile_capacity);
    w->projectile_shape = bk_realloc(w->projectile_shape, sizeof(bk_shape_id) * w->projectile_capacity);
    w->projectile_born = bk_realloc(w->projectile_born, sizeof(uint64_t) * w->projectile_capacity);
  }
  w->projectile_radius[w->projectile_count] = radius;
  w->projectile_shape[w->projectile_count] = sphere;
  w->projectile_born[w->projectile_count] = w->step_count;
  w->projectiles[w->projectile_count++] = body;
  return body;
}

void bk_world_refresh_live(bk_world* w) {
  if (!w->live_dirty) return;
  if (w->live_capacity < w->cluster_count) {
    w->live_capacity = bk_grow_capacity(w->live_capacity, w->cluster_count);
    w->live = bk_realloc(w->live, sizeof(uint32_t) * w->live_capacity);
  }
  w->live_count = 0;
  for (uint32_t i = 0; i < w->cluster_count; ++i)
    if (w->clusters[i].alive) w->live[w->live_count++] = i;
  w->live_dirty = false;
}

// Old projectiles go (with their sphere shapes) so a long session stays bounded.
static void retire_projectiles(bk_world* w) {
  uint64_t max_age = (uint64_t)(w->desc.projectile_lifetime / w->desc.fixed_dt);
  uint32_t kept = 0;
  for (uint32_t i = 0; i < w->projectile_count; ++i) {
    if (w->step_count - w->projectile_born[i] > max_age) {
      bk_physics_destroy_body(w->physics, w->projectiles[i]);
      bk_physics_destroy_shape(w->physics, w->projectile_shape[i]);
      continue;
    }
    w->projectiles[kept] = w->projectiles[i];
    w->projectile_radius[kept] = w->projectile_radius[i];
    w->projectile_shape[kept] = w->projectile_shape[i];
    w->projectile_born[kept] = w->projectile_born[i];
    kept++;
  }
  w->projectile_count = kept;
}

// Small loose fragments leave after a while: each was a body the solver kept
// paying for. Their leaves stay unowned; their mass is accounted for.
static void retire_fragments(bk_world* w) {
  if (w->desc.retire_volume <= 0.0) return;
  uint64_t max_age = (uint64_t)(w->desc.retire_after / w->desc.fixed_dt);
  for (uint32_t i = 0; i < w->live_count; ++i) {
    uint32_t slot = w->live[i];
    cluster* c = &w->clusters[slot];
    if (c->leaf_count != 1 || c->is_static || c->queued || w->step_count - c->born <= max_age) continue;
    breakable* b = &w->breakables[c->breakable];
    if (bk_mesh_tree_leaf(b->tree, c->leaves[0])->moments.v >= w->desc.retire_volume) continue;
    b->leaf_cluster[c->leaves[0]] = UINT32_MAX;
    w->retired_mass += c->mass;
    w->fragments_retired++;
    bk_cluster_release(w, slot);
  }
}

void bk_world_step(bk_world* w) {
  double start = now_ms();
  w->event_count = 0;
  for (uint32_t i = 0; i < w->live_count; ++i) {
    cluster* c = &w->clusters[w->live[i]];
    c->previous = bk_cluster_tree_to_world(w, c);
  }
  retire_projectiles(w);
  w->step_count++;
  bk_physics_step(w->physics, w->desc.fixed_dt, 1);
  double after_physics = now_ms();
  uint32_t contacts = bk_physics_contacts(w->physics, w->contacts, w->contact_capacity);
  bk_world_apply_damage(w, contacts);
  bk_world_split(w);
  bk_world_refresh_live(w);
  retire_fragments(w);
  bk_world_refresh_live(w);
  double end = now_ms();
  w->physics_ms = after_physics - start;
  w->break_ms = end - after_physics;
  w->step_ms = end - start;
}

uint32_t bk_world_break_events(const bk_world* w, bk_break_event* out, uint32_t capacity) {
  uint32_t n = w->event_count < capacity ? w->event_count : capacity;
  if (n) memcpy(out, w->events, sizeof(bk_break_event) * n);
  return w->event_count;
}

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
  for (uint32_t i = 0; i < w->cluster_count; ++i) {
    const cluster* c = &w->clusters[i];
    if (!c->alive) continue;
    s.bodies++;
    s.dynamic_bodies += !c->is_static;
    s.colliders += c->collider_count;
    s.colliders_naive += c->leaf_count;
    s.fragments_free += c->leaf_count == 1;
    s.total_mass += c->mass;
    s.nan = s.nan || body_has_nan(w, c->body);
  }
  s.projectiles = w->projectile_count;
  s.bonds_broken = w->bonds_broken;
  s.break_events = w->break_events;
  s.pending_splits = w->split_queue_count;
  s.fragments_retired = w->fragments_retired;
  s.retired_mass = w->retired_mass;
  s.step_ms = w->step_ms;
  s.physics_ms = w->physics_ms;
  s.break_ms = w->break_ms;
  for (uint32_t i = 0; i < w->projectile_count; ++i)
    s.nan = s.nan || body_has_nan(w, w->projectiles[i]);
  return s;
}

uint32_t bk_world_body_count(const bk_world* w) { return w->live_dirty ? 0 : w->live_count; }

bool bk_world_body_view(const bk_world* w, uint32_t index, bk_body_view* out) {
  if (w->live_dirty || index >= w->live_count) return false;
  const cluster* c = &w->clusters[w->live[index]];
  const breakable* b = &w->breakables[c->breakable];
  *out = (bk_body_view){.breakable = {c->breakable, b->generation},
                        .tree = b->tree,
                        .tree_to_world = bk_cluster_tree_to_world(w, c),
                        .tree_to_world_previous = c->previous,
                        .nodes = c->nodes,
                        .node_count = c->node_count,
                        .leaves = c->leaves,
                        .leaf_count = c->leaf_count,
                        .body = c->body,
                        .is_static = c->is_static};
  return true;
}

uint32_t bk_world_body_colliders(const bk_world* w, uint32_t index, uint32_t* nodes_out, uint32_t capacity) {
  if (w->live_dirty || index >= w->live_count) return 0;
  const cluster* c = &w->clusters[w->live[index]];
  uint32_t n = c->collider_count < capacity ? c->collider_count : capacity;
  if (n) memcpy(nodes_out, c->colliders, sizeof(uint32_t) * n);
  return c->collider_count;
}

double bk_world_bond_health(const bk_world* w, bk_breakable_id id, uint32_t bond, double* initial) {
  const breakable* b = find_breakable(w, id);
  if (!b || bond >= b->tree->bond_count) {
    if (initial) *initial = 0.0;
    return 0.0;
  }
  if (initial) *initial = b->bond_hp_initial[bond];
  return b->bond_broken[bond] ? 0.0 : b->bond_hp[bond];
}

uint32_t bk_world_projectile_count(const bk_world* w) { return w->projectile_count; }

bool bk_world_projectile(const bk_world* w, uint32_t index, bk_vec3* position, double* radius) {
  if (index >= w->projectile_count) return false;
  *position = bk_physics_body_transform(w->physics, w->projectiles[index]).position;
  *radius = w->projectile_radius[index];
  return true;
}
