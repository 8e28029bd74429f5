// The world on Bullet: breakables through the runtime, their cluster bodies,
// projectiles, the fixed step, and what the layers above pull out of it
// (stats, views, events).
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "world_internal.h"

static double now_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

// CPU time of this thread: what a step's parts cost on a shared machine,
// where the wall clock also counts other processes' turns.
static double cpu_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

bk_world_def bk_default_world_def(void) {
  return (bk_world_def){.gravity = {0.0, -9.81, 0.0},
                        .fixed_dt = 1.0 / 60.0,
                        .ground = true,
                        .runtime = bk_default_runtime_def(),
                        .max_hit_fragments_per_step = 1024,
                        .projectile_lifetime = 8.0,
                        .retire_volume = 2e-5,
                        .retire_after = 10.0,
                        .stress = true,
                        .physics_budget_ms = 8.0,
                        .physics_budget_measured = false,
                        .budget_large_volume = 0.008,
                        .budget_focus_radius = 2.0,
                        .budget_fidelity_time = 1.0,
                        .budget_fidelity_radius = 8.0,
                        .budget_visible_angle = 0.006,
                        .budget_fidelity_factor = 2.0,
                        .settle_cell = 2.0,
                        .settle_wake_speed = 2.0};
}

// The runtime asks where a cluster's body is; Bullet knows.
static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  const bk_world* w = context;
  bk_body_id body = w->bodies[cluster.index].body;
  return (bk_body_state){bk_physics_body_transform(w->physics, body),
                         bk_physics_body_linear_velocity(w->physics, body),
                         bk_physics_body_angular_velocity(w->physics, body)};
}

bk_world* bk_world_create(const bk_world_def* def, bk_error* err) {
  if (!def) return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "world: def is NULL"), NULL;
  bk_world_def d = *def;
  if (!(d.retire_volume >= 0.0) || !isfinite(d.retire_volume))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: retire_volume must be finite and >= 0 (got %g)", d.retire_volume),
           NULL;
  if (!(d.retire_after > 0.0) || !isfinite(d.retire_after))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "world: retire_after must be positive (got %g)",
                             d.retire_after),
           NULL;
  if (!(d.projectile_lifetime > 0.0) || !isfinite(d.projectile_lifetime))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: projectile_lifetime must be positive (got %g)", d.projectile_lifetime),
           NULL;
  if (!bk_v3_is_finite(d.gravity))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "world: gravity must be finite"), NULL;
  if (!(d.fixed_dt > 0.0 && d.fixed_dt <= 0.1))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "world: fixed_dt must be in (0, 0.1] s (got %g)",
                             d.fixed_dt),
           NULL;
  if (!(d.physics_budget_ms >= 0.0) || !isfinite(d.physics_budget_ms))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: physics_budget_ms must be finite and >= 0 (got %g)",
                             d.physics_budget_ms),
           NULL;
  if (!(d.budget_large_volume > 0.0) || !isfinite(d.budget_large_volume))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: budget_large_volume must be a positive finite number (got %g)",
                             d.budget_large_volume),
           NULL;
  if (!(d.budget_focus_radius >= 0.0) || !isfinite(d.budget_focus_radius))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: budget_focus_radius must be finite and >= 0 (got %g)",
                             d.budget_focus_radius),
           NULL;
  if (!(d.budget_fidelity_time >= 0.0) || !isfinite(d.budget_fidelity_time))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: budget_fidelity_time must be finite and >= 0 (got %g)",
                             d.budget_fidelity_time),
           NULL;
  if (!(d.budget_fidelity_factor == 0.0 ||
        (d.budget_fidelity_factor >= 1.0 && isfinite(d.budget_fidelity_factor))))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: budget_fidelity_factor must be 0 (no bound) or finite and >= 1 (got %g)",
                             d.budget_fidelity_factor),
           NULL;
  if (!(d.budget_visible_angle >= 0.0 && d.budget_visible_angle <= 1.0))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: budget_visible_angle must be within 0..1 radians (got %g)",
                             d.budget_visible_angle),
           NULL;
  if (!(d.budget_fidelity_radius >= 0.0) || !isfinite(d.budget_fidelity_radius))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: budget_fidelity_radius must be finite and >= 0 (got %g)",
                             d.budget_fidelity_radius),
           NULL;

  if (!(d.settle_cell >= 0.0) || !isfinite(d.settle_cell))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: settle_cell must be finite and >= 0 (got %g)", d.settle_cell),
           NULL;
  if (!(d.settle_wake_speed > 0.0) || !isfinite(d.settle_wake_speed))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "world: settle_wake_speed must be a positive finite number (got %g)",
                             d.settle_wake_speed),
           NULL;

  // The runtime's fields as the world sets them, checked as its own.
  d.runtime.gravity = d.gravity; // up, for anchoring, is its opposite
  d.runtime.body_state = body_state;
  d.runtime.context = NULL;
  d.runtime.refine_prepare = bk_world_refine_prepare; // the pieces' hulls, on the refinement worker
  d.runtime.refine_discard = bk_world_refine_discard;
  if (!bk_runtime_def_validate(&d.runtime, "world: runtime.", err)) return NULL;

  // An allocator that runs out makes creation fail with an error, not abort.
  bk_world* w = bk_try_calloc(1, sizeof *w);
  if (!w) return bk_error_set_code(err, BK_ERROR_OUT_OF_MEMORY, "world: out of memory"), NULL;
  d.runtime.context = w;
  w->runtime = bk_runtime_create(&d.runtime, err);
  if (!w->runtime) {
    bk_free(w);
    return NULL;
  }
  bk_physics_def pd = bk_default_physics_def();
  pd.gravity = d.gravity;
  pd.fixed_dt = d.fixed_dt;
  w->physics = bk_physics_create(&pd, err);
  if (!w->physics) {
    bk_runtime_destroy(w->runtime);
    bk_free(w);
    return NULL;
  }
  w->def = d;
  w->hull_margin = bk_physics_hull_margin(w->physics); // read by the refinement workers
  w->contact_capacity = 65536;
  w->contacts = bk_alloc(sizeof(bk_contact) * w->contact_capacity);
  if (d.ground) {
    w->ground = bk_physics_create_plane(w->physics, bk_v3(0, 1, 0), 0.0);
    bk_body_def gd = bk_default_body_def();
    gd.shape = w->ground;
    gd.friction = 0.8;
    w->ground_body = bk_physics_create_body(w->physics, &gd, err);
  }
  return w;
}

void bk_world_destroy(bk_world* w) {
  if (!w) return;
  // The runtime first: it waits for its refinement workers, which prepare
  // hulls for this world. Destroying the physics world then releases every
  // body and shape in it.
  bk_runtime_destroy(w->runtime);
  bk_physics_destroy(w->physics);
  for (uint32_t i = 0; i < w->body_capacity; ++i)
    bk_free(w->bodies[i].colliders);
  for (uint32_t i = 0; i < w->breakable_count; ++i) {
    bk_free(w->breakables[i].node_hull);
    bk_free(w->breakables[i].node_body_hull);
    bk_free(w->breakables[i].hull_fits);
  }
  bk_free(w->breakables);
  bk_free(w->bodies);
  bk_free(w->live);
  bk_free(w->projectiles);
  bk_free(w->projectile_radius);
  bk_free(w->projectile_shape);
  bk_free(w->projectile_expires);
  bk_free(w->contacts);
  bk_free(w->damage);
  bk_free(w->hits);
  bk_free(w->hit_batch);
  bk_free(w->created);
  bk_free(w->removed);
  bk_free(w->broken);
  bk_free(w->events);
  bk_free(w->supports);
  bk_free(w->stress_loads);
  bk_world_budget_free(w);
  bk_world_settle_free(w);
  bk_free(w->refined);
  bk_free(w);
}

bk_physics* bk_world_physics(bk_world* w) { return w->physics; }
const bk_runtime* bk_world_runtime(const bk_world* w) { return w->runtime; }

bk_world_breakable_def bk_default_world_breakable_def(void) {
  return (bk_world_breakable_def){.breakable = bk_default_breakable_def(),
                                  .convex_colliders = false,
                                  .convexity_tolerance = 0.1,
                                  .naive = false};
}

bk_breakable_id bk_world_add_breakable(bk_world* w, const bk_world_breakable_def* def, bk_error* err) {
  bk_breakable_id null_id = {0, 0};
  if (!def) return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "breakable: def is NULL"), null_id;
  if (!(def->convexity_tolerance > 0.0) || !isfinite(def->convexity_tolerance))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "breakable: convexity_tolerance must be a positive finite number (got %g)",
                             def->convexity_tolerance),
           null_id;
  // Validate everything before the runtime records anything.
  bk_breakable_id id = bk_runtime_add_breakable(w->runtime, &def->breakable, err);
  if (bk_breakable_is_null(id)) return null_id;
  // The world's breakables are indexed like the runtime's (which reuses a
  // removed one's slot).
  uint32_t index = id.index;
  if (index >= w->breakable_count) {
    if (index >= w->breakable_capacity) {
      w->breakable_capacity = bk_grow_capacity(w->breakable_capacity, index + 1);
      w->breakables = bk_realloc(w->breakables, sizeof(world_breakable) * w->breakable_capacity);
    }
    w->breakable_count = index + 1;
  }
  w->breakables[index] = (world_breakable){.id = id,
                                           .convex_colliders = def->convex_colliders,
                                           .naive = def->naive,
                                           .convexity_tolerance = def->convexity_tolerance,
                                           .node_hull = NULL,
                                           .node_body_hull = NULL,
                                           .hull_fits = NULL,
                                           .node_count = 0};
  bk_world_prepare_hulls(w, index); // every node's, as node_count is 0
  w->breakables[index].source_nodes = w->breakables[index].node_count;
  bool made = bk_world_apply_results(w, err);
  bk_world_refresh_live(w);
  return made ? id : null_id;
}

bk_result bk_world_remove_breakable(bk_world* w, bk_breakable_id id) {
  bk_result result = bk_runtime_remove_breakable(w->runtime, id);
  if (result != BK_OK) return result;
  bk_world_apply_results(w, NULL); // releases its bodies (nothing is created)
  bk_world_refresh_live(w);
  // Its hulls go once no body uses them (a shape in use is left alone). Its
  // tree is not read: a refined breakable's own tree went with it.
  world_breakable* wb = &w->breakables[id.index];
  for (uint32_t i = 0; i < wb->node_count; ++i) {
    if (!bk_shape_is_null(wb->node_hull[i])) bk_physics_destroy_shape(w->physics, wb->node_hull[i]);
    if (!bk_shape_is_null(wb->node_body_hull[i])) bk_physics_destroy_shape(w->physics, wb->node_body_hull[i]);
  }
  bk_free(wb->node_hull);
  bk_free(wb->node_body_hull);
  bk_free(wb->hull_fits);
  *wb = (world_breakable){.id = {0, 0}};
  return BK_OK;
}

uint32_t bk_world_breakable_count(const bk_world* w) { return w->breakable_count; }

bk_breakable_id bk_world_breakable_at(const bk_world* w, uint32_t index) {
  return index < w->breakable_count ? w->breakables[index].id : (bk_breakable_id){0, 0};
}

// Bodies follow the runtime's masses after a density change.
static void refresh_masses(bk_world* w, bk_breakable_id id) {
  for (uint32_t i = 0; i < w->live_count; ++i) {
    world_body* wbody = &w->bodies[w->live[i]];
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(w->runtime, wbody->cluster, &info) || info.breakable.index != id.index) continue;
    if (!info.is_static) bk_physics_body_set_mass(w->physics, wbody->body, info.mass, info.inertia);
  }
}

bk_result bk_world_set_material(bk_world* w, bk_breakable_id id, const bk_material* material) {
  bk_result result = bk_runtime_set_material(w->runtime, id, material);
  if (result != BK_OK) return result;
  refresh_masses(w, id);
  for (uint32_t i = 0; i < w->live_count; ++i) {
    world_body* wbody = &w->bodies[w->live[i]];
    if (w->breakables[wbody->breakable].id.index == id.index)
      bk_physics_body_set_surface(w->physics, wbody->body, material->friction, material->restitution);
  }
  return BK_OK;
}

bk_result bk_world_set_frailty(bk_world* w, bk_breakable_id id, double frailty) {
  return bk_runtime_set_frailty(w->runtime, id, frailty);
}

bk_result bk_world_set_density(bk_world* w, bk_breakable_id id, double density) {
  bk_result result = bk_runtime_set_density(w->runtime, id, density);
  if (result != BK_OK) return result;
  refresh_masses(w, id);
  return BK_OK;
}

bk_result bk_world_set_bond_strength(bk_world* w, bk_breakable_id id, double bond_strength) {
  return bk_runtime_set_bond_strength(w->runtime, id, bond_strength);
}

bk_material bk_world_material(const bk_world* w, bk_breakable_id id) {
  return bk_runtime_material(w->runtime, id);
}
double bk_world_frailty(const bk_world* w, bk_breakable_id id) { return bk_runtime_frailty(w->runtime, id); }
double bk_world_density(const bk_world* w, bk_breakable_id id) { return bk_runtime_density(w->runtime, id); }
double bk_world_bond_strength(const bk_world* w, bk_breakable_id id) {
  return bk_runtime_bond_strength(w->runtime, id);
}

// The runtime keeps what each cluster's last solve found; while stress is
// off nothing is solved, and clusters made or changed meanwhile are solved
// when it is back on.
void bk_world_set_stress(bk_world* w, bool stress) { w->def.stress = stress; }
bool bk_world_stress(const bk_world* w) { return w->def.stress; }
uint32_t bk_world_max_hit_fragments_per_step(const bk_world* w) { return w->def.max_hit_fragments_per_step; }

void bk_world_impact(bk_world* w, bk_vec3 point, double impulse) {
  bk_runtime_damage_at(w->runtime, point, impulse);
  bk_world_collect_breaks(w);
}

// Contacts on cluster bodies become the runtime's damage contacts (a body's
// user data holds its cluster index).
static bool cluster_of(const bk_world* w, bk_body_id body, bk_cluster_id* out) {
  uint64_t user = bk_physics_body_user_data(w->physics, body);
  if (!(user & BK_USER_CLUSTER)) return false;
  uint32_t index = (uint32_t)user;
  if (index >= w->body_capacity || !w->bodies[index].alive || !bk_body_equal(w->bodies[index].body, body))
    return false;
  *out = w->bodies[index].cluster;
  return true;
}

static void apply_contacts(bk_world* w, uint32_t contact_count) {
  uint32_t n = contact_count < w->contact_capacity ? contact_count : w->contact_capacity;
  if (w->damage_capacity < 2u * n) {
    w->damage_capacity = bk_grow_capacity(w->damage_capacity, 2u * n);
    w->damage = bk_realloc(w->damage, sizeof(bk_damage_contact) * w->damage_capacity);
  }
  uint32_t count = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const bk_contact* ct = &w->contacts[i];
    bk_cluster_id cluster = {0, 0};
    // A hit on a settle area's compound damages the piece it touched.
    if (cluster_of(w, ct->a, &cluster) || bk_world_settle_cluster(w, ct->a, ct->child_a, &cluster))
      w->damage[count++] = (bk_damage_contact){cluster, ct->point, ct->impulse, ct->approach_speed};
    if (cluster_of(w, ct->b, &cluster) || bk_world_settle_cluster(w, ct->b, ct->child_b, &cluster))
      w->damage[count++] = (bk_damage_contact){cluster, ct->point, ct->impulse, ct->approach_speed};
  }
  w->hits_hold_splits = false;
  if (w->def.max_hit_fragments_per_step == 0)
    bk_runtime_apply_contacts(w->runtime, w->damage, count);
  else
    bk_world_apply_hits(w, count);
  bk_world_collect_breaks(w);
}

// Where moving clusters rest on something static (the ground, a static
// cluster, anything of zero mass): their weight goes down there. What rests
// on a cluster (a slow contact with a body of some mass: a weight on a
// bridge, debris on a balcony) loads it with the contact's force; a fast
// contact is an impact, whose damage the contacts already did.
static bool body_is_static(const bk_world* w, bk_body_id body) {
  return bk_body_equal(body, w->ground_body) || bk_physics_body_mass(w->physics, body) == 0.0;
}

static void solve_stress(bk_world* w, uint32_t contact_count) {
  uint32_t n = contact_count < w->contact_capacity ? contact_count : w->contact_capacity;
  if (w->support_capacity < 2u * n) {
    w->support_capacity = bk_grow_capacity(w->support_capacity, 2u * n);
    w->supports = bk_realloc(w->supports, sizeof(bk_stress_support) * w->support_capacity);
  }
  if (w->stress_load_capacity < 2u * n) {
    w->stress_load_capacity = bk_grow_capacity(w->stress_load_capacity, 2u * n);
    w->stress_loads = bk_realloc(w->stress_loads, sizeof(bk_stress_load) * w->stress_load_capacity);
  }
  uint32_t count = 0, loads = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const bk_contact* ct = &w->contacts[i];
    bool a_static = body_is_static(w, ct->a), b_static = body_is_static(w, ct->b);
    bk_cluster_id cluster = {0, 0};
    if (cluster_of(w, ct->a, &cluster) && b_static && !a_static)
      w->supports[count++] = (bk_stress_support){cluster, ct->point};
    if (cluster_of(w, ct->b, &cluster) && a_static && !b_static)
      w->supports[count++] = (bk_stress_support){cluster, ct->point};
    if (ct->approach_speed >= w->def.runtime.impact_speed) continue;
    // The normal points from b to a: the contact pushes a along it.
    bk_vec3 force = bk_v3_scale(ct->normal, ct->impulse / w->def.fixed_dt);
    if (!b_static && cluster_of(w, ct->a, &cluster))
      w->stress_loads[loads++] = (bk_stress_load){cluster, ct->point, force};
    if (!a_static && cluster_of(w, ct->b, &cluster))
      w->stress_loads[loads++] = (bk_stress_load){cluster, ct->point, bk_v3_scale(force, -1.0)};
  }
  bk_runtime_solve_stress(w->runtime, w->def.gravity, w->supports, count, w->stress_loads, loads);
  bk_world_collect_breaks(w);
}

// Small loose fragments leave after a while: each was a body the solver kept
// paying for, and one to draw. Their mass is accounted for, and they are
// handed to bk_world_retired_bodies for the renderer to fade out.
static void retire_fragments(bk_world* w) {
  w->aged_count = 0;
  if (w->def.retire_volume <= 0.0) return;
  uint64_t max_age = (uint64_t)(w->def.retire_after / w->def.fixed_dt);
  for (uint32_t i = 0; i < w->live_count; ++i) {
    uint32_t index = w->live[i];
    world_body* wbody = &w->bodies[index];
    bk_cluster_info info = {0};
    if (!bk_runtime_cluster(w->runtime, wbody->cluster, &info)) continue;
    if (info.leaf_count != 1 || info.is_static || info.split_pending ||
        w->step_count - wbody->born <= max_age)
      continue;
    const bk_mesh_tree* tree = bk_runtime_breakable_tree(w->runtime, info.breakable);
    if (bk_mesh_tree_leaf(tree, info.leaves[0])->moments.v >= w->def.retire_volume) continue;
    w->retired_mass += info.mass;
    w->fragments_retired++;
    if (w->aged_count == w->aged_capacity) {
      w->aged_capacity = bk_grow_capacity(w->aged_capacity, w->aged_count + 1);
      w->aged = bk_realloc(w->aged, sizeof(bk_retired_body) * w->aged_capacity);
    }
    w->aged[w->aged_count++] = bk_world_retired_record(w, index, &info);
    bk_runtime_remove_cluster(w->runtime, wbody->cluster);
    bk_runtime_clear_events(w->runtime); // the world removes the body itself
    bk_world_release_body(w, index);
  }
}

void bk_world_step(bk_world* w) {
  double start = now_ms();
  // Drop the last step's events; keep those of impacts made since.
  uint32_t kept = w->event_count - w->events_of_last_step;
  if (kept) memmove(w->events, w->events + w->events_of_last_step, sizeof(bk_break_event) * kept);
  w->event_count = kept;
  for (uint32_t i = 0; i < w->live_count; ++i)
    w->bodies[w->live[i]].previous = bk_world_tree_to_world(w, w->live[i]);
  bk_world_retire_projectiles(w);
  bk_world_settle_before_physics(w);
  w->step_count++;
  double cpu_start = cpu_ms();
  bk_physics_step(w->physics, w->def.fixed_dt, 1);
  double after_physics = now_ms(), cpu_after_physics = cpu_ms();
  w->physics_ms = after_physics - start; // the budget may go by it
  w->physics_cpu_ms = cpu_after_physics - cpu_start;
  uint32_t contacts = bk_physics_contacts(w->physics, w->contacts, w->contact_capacity);
  w->contact_count = contacts < w->contact_capacity ? contacts : w->contact_capacity;
  apply_contacts(w, contacts);
  double cpu_damage = cpu_ms() - cpu_after_physics;
  // Fragments the hits marked are fractured around them (on a worker),
  // those due land, and the hits that waited for them break the pieces'
  // bonds: before the stress solve and the split, which see the grown tree.
  bk_world_refine(w);
  double before_stress = now_ms();
  if (w->def.stress) solve_stress(w, contacts);
  w->stress_ms = now_ms() - before_stress;
  double cpu_before_split = cpu_ms();
  // A step that leaves hits waiting splits nothing: the next one will (no
  // step pays for both).
  if (!w->hits_hold_splits) {
    bk_runtime_split(w->runtime);
    bk_error err = {0};
    bk_world_apply_results(w, &err); // a body Bullet refuses stays without one: never a crash
  }
  w->fracture_ms = cpu_damage + (cpu_ms() - cpu_before_split);
  bk_world_refresh_live(w);
  retire_fragments(w);
  bk_world_refresh_live(w);
  bk_world_budget_step(w);
  bk_world_refresh_live(w);
  bk_world_settle_step(w);
  w->events_of_last_step = w->event_count;
  double end = now_ms();
  w->break_ms = end - after_physics;
  w->step_ms = end - start;
}

uint32_t bk_world_break_events(const bk_world* w, bk_break_event* out, uint32_t capacity) {
  uint32_t n = w->event_count < capacity ? w->event_count : capacity;
  if (n) memcpy(out, w->events, sizeof(bk_break_event) * n);
  return w->event_count;
}
