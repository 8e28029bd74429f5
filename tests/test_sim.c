// Breakable bodies on Bullet: one body per cluster, exact mass, colliders
// from the minimal node set, damage and splits, resting stability,
// determinism, and no leaks over many breaks.
#include <stdlib.h>
#include <string.h>

#include "ensure.h"
#include <breakables/bullet.h>

static bk_mesh_tree make_tree(bk_shape shape, uint32_t pieces, uint64_t seed) {
  bk_mesh mesh = {0};
  bk_shape_build(shape, &mesh);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = seed;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &desc, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

static bk_world* make_world(void) {
  bk_world_def desc = bk_default_world_def();
  bk_error err = {0};
  bk_world* world = bk_world_create(&desc, &err);
  ENSURE_MSG(world != NULL, "%s", err.message);
  return world;
}

static bk_breakable_id add(bk_world* world, const bk_mesh_tree* tree, bk_world_breakable_def desc) {
  desc.breakable.tree = tree;
  bk_error err = {0};
  bk_breakable_id id = bk_world_add_breakable(world, &desc, &err);
  ENSURE_MSG(id.generation != 0, "%s", err.message);
  return id;
}

// An unbroken object is one body using the root's collider, with the source
// mesh's exact mass and principal inertia.
static void test_unbroken_is_one_body(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 64, 1);
  bk_world* world = make_world();
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  desc.breakable.material.density = 1000.0;
  desc.breakable.transform.position = bk_v3(0, 3, 0);
  add(world, &tree, desc);
  bk_world_step(world);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE(s.bodies == 1 && s.colliders == 1 && s.colliders_naive == 64);
  bk_body_view view = {0};
  ENSURE(bk_world_body_view(world, 0, &view));
  ENSURE(view.node_count == 1 && view.nodes[0] == 0 && view.leaf_count == 64);
  uint32_t colliders[4];
  ENSURE(bk_world_body_colliders(world, 0, colliders, 4) == 1 && colliders[0] == 0);
  // Unit cube: mass 1000 kg, inertia m/6 about every axis, centred at its centroid.
  ENSURE_REL(bk_physics_body_mass(bk_world_physics(world), view.body), 1000.0, 1e-12);
  bk_vec3 inertia = bk_physics_body_inertia(bk_world_physics(world), view.body);
  ENSURE_REL(inertia.x, 1000.0 / 6.0, 1e-5); // Bullet stores the inverse in single precision
  ENSURE_REL(inertia.y, 1000.0 / 6.0, 1e-5);
  ENSURE_REL(inertia.z, 1000.0 / 6.0, 1e-5);
  ENSURE_REL(s.total_mass, 1000.0, 1e-12);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// A hollow eggshell is not a solid egg for collisions: with convex colliders
// off its hull overestimates it, so its children stand in.
// A lopsided shape's body frame is its principal frame: the inertia Bullet
// holds equals the eigenvalues of the exact inertia tensor of the mesh.
static void test_torus_principal_inertia(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_TORUS, 16, 3);
  bk_world* world = make_world();
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  desc.breakable.material.density = 500.0;
  desc.breakable.transform.position = bk_v3(0, 2, 0);
  desc.breakable.transform.rotation = bk_quat_axis_angle(bk_v3_normalize(bk_v3(1, 2, 3)), 0.7);
  add(world, &tree, desc);
  bk_body_view view = {0};
  ENSURE(bk_world_body_view(world, 0, &view));
  bk_mass_properties exact = bk_moments_to_mass(bk_mesh_moments(&tree.nodes[0].mesh));
  double values[3], axes[3][3];
  bk_sym3_eigen(exact.inertia, values, axes);
  bk_vec3 held = bk_physics_body_inertia(bk_world_physics(world), view.body);
  double sorted_held[3] = {held.x, held.y, held.z};
  for (int i = 0; i < 3; ++i) {
    bool found = false;
    for (int k = 0; k < 3 && !found; ++k)
      found = fabs(sorted_held[k] - 500.0 * values[i]) <= 1e-5 * 500.0 * values[i];
    ENSURE_MSG(found, "principal moment %g not held by the body", 500.0 * values[i]);
  }
  ENSURE_REL(bk_physics_body_mass(bk_world_physics(world), view.body), 500.0 * exact.volume, 1e-12);
  // The tree frame comes back where it was put.
  ENSURE_SMALL(bk_v3_length(bk_v3_sub(view.tree_to_world.position, desc.breakable.transform.position)), 0.0,
               1e-6);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

static void test_eggshell_not_solid(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_EGGSHELL, 64, 2);
  bk_world* world = make_world();
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  add(world, &tree, desc);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE_MSG(s.colliders > 1 && s.colliders <= 64, "%u colliders", s.colliders);
  desc.convex_colliders = true;
  desc.breakable.transform.position = bk_v3(3, 0, 0);
  add(world, &tree, desc);
  ENSURE(bk_world_get_stats(world).colliders == s.colliders + 1); // the convex one is the root's hull
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

typedef struct outcome {
  uint32_t bodies, bonds_broken, colliders, colliders_naive;
  double mass;
  bk_vec3 sum_positions;
} outcome;

// A wall anchored on the ground, hit by a projectile.
static outcome shoot_wall(const bk_mesh_tree* tree, bool naive, double speed) {
  bk_world* world = make_world();
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  desc.breakable.anchored = true;
  desc.naive = naive;
  add(world, tree, desc);
  double mass_before = bk_world_get_stats(world).total_mass;
  bk_projectile_def shot = {
      .position = bk_v3(0.1, 0.7, 3.0), .velocity = bk_v3(0, 0, -speed), .radius = 0.1, .mass = 8};
  bk_world_fire(world, &shot, NULL);
  for (int i = 0; i < 90; ++i)
    bk_world_step(world);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE(!s.nan);
  ENSURE_REL(s.total_mass, mass_before, 1e-9);
  outcome o = {s.bodies, s.bonds_broken, s.colliders, s.colliders_naive, s.total_mass, {0, 0, 0}};
  for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
    bk_body_view v = {0};
    ENSURE(bk_world_body_view(world, i, &v));
    o.sum_positions = bk_v3_add(o.sum_positions, v.tree_to_world.position);
  }
  bk_world_destroy(world);
  return o;
}

static void test_wall_breaks(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 128, 3000);
  outcome a = shoot_wall(&tree, false, 40.0);
  ENSURE_MSG(a.bodies >= 3 && a.bonds_broken > 0, "%u bodies, %u bonds broken", a.bodies, a.bonds_broken);
  // Far fewer colliders than one per fragment.
  ENSURE_MSG(a.colliders < a.colliders_naive, "%u vs %u", a.colliders, a.colliders_naive);
  // Deterministic: the same run gives the same result, bit for bit.
  outcome b = shoot_wall(&tree, false, 40.0);
  ENSURE(a.bodies == b.bodies && a.bonds_broken == b.bonds_broken);
  ENSURE(memcmp(&a.sum_positions, &b.sum_positions, sizeof(bk_vec3)) == 0);
  fprintf(stderr, "    wall x128 hit at 40 m/s: %u bodies, %u bonds broken, colliders %u (plain BCRB %u)\n",
          a.bodies, a.bonds_broken, a.colliders, a.colliders_naive);
  bk_mesh_tree_free(&tree);
}

// The same impact in naive mode makes the same clusters with more colliders.
static void test_naive_same_clusters(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 128, 5);
  uint32_t counts[2] = {0, 0}, colliders[2] = {0, 0}, naive_colliders[2] = {0, 0};
  uint32_t* leaf_body[2] = {calloc(tree.leaf_count, sizeof(uint32_t)),
                            calloc(tree.leaf_count, sizeof(uint32_t))};
  for (int mode = 0; mode < 2; ++mode) {
    bk_world* world = make_world();
    bk_world_breakable_def desc = bk_default_world_breakable_def();
    desc.breakable.anchored = true;
    desc.naive = mode == 1;
    add(world, &tree, desc);
    bk_world_impact(world, bk_v3(0.2, 0.6, 0.1), 300.0);
    bk_world_step(world);
    bk_world_stats s = bk_world_get_stats(world);
    counts[mode] = s.bodies;
    colliders[mode] = s.colliders;
    naive_colliders[mode] = s.colliders_naive;
    // Label each leaf with the smallest leaf of its body: comparable across runs.
    for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
      bk_body_view v = {0};
      ENSURE(bk_world_body_view(world, i, &v));
      for (uint32_t k = 0; k < v.leaf_count; ++k)
        leaf_body[mode][v.leaves[k]] = v.leaves[0];
    }
    bk_world_destroy(world);
  }
  ENSURE_MSG(counts[0] > 2, "the impact should break the wall (%u bodies)", counts[0]);
  ENSURE(counts[0] == counts[1]);
  ENSURE(memcmp(leaf_body[0], leaf_body[1], sizeof(uint32_t) * tree.leaf_count) == 0);
  ENSURE(colliders[1] == naive_colliders[1] && colliders[0] < colliders[1]);
  free(leaf_body[0]);
  free(leaf_body[1]);
  bk_mesh_tree_free(&tree);
}

// Two weak hits: an accumulating bond breaks, a discrete one does not.
static void test_discrete_vs_accumulating(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 2, 4);
  ENSURE(tree.bond_count == 1);
  const bk_bond* bond = &tree.bonds[0];
  for (int accumulate = 0; accumulate < 2; ++accumulate) {
    bk_world* world = make_world();
    bk_world_breakable_def desc = bk_default_world_breakable_def();
    desc.breakable.material.accumulate = accumulate == 1;
    desc.breakable.transform.position = bk_v3(0, 0.5, 0);
    bk_breakable_id id = add(world, &tree, desc);
    double initial = 0.0;
    bk_world_bond_health(world, id, 0, &initial);
    // Damage at the bond centroid is frailty x impulse / s_min^3: aim for 60% of its hit points.
    double s_min = bk_default_world_def().runtime.damage_min_distance;
    double impulse = 0.6 * initial * s_min * s_min * s_min / desc.breakable.material.frailty;
    bk_vec3 at = bk_v3_add(bond->centroid, bk_v3(0, 0.5, 0));
    bk_world_impact(world, at, impulse);
    bk_world_step(world);
    ENSURE(bk_world_get_stats(world).bodies == 1);
    bk_world_impact(world, at, impulse);
    bk_world_step(world);
    double left = bk_world_bond_health(world, id, 0, NULL);
    if (accumulate) {
      ENSURE(left == 0.0 && bk_world_get_stats(world).bodies == 2);
    } else {
      ENSURE_REL(left, initial, 1e-12);
      ENSURE(bk_world_get_stats(world).bodies == 1);
    }
    bk_world_destroy(world);
  }
  bk_mesh_tree_free(&tree);
}

// Live parameters matter: doubling frailty turns a hit of 60% of a bond's hit
// points into a break, and density scales a body's mass and inertia.
static void test_live_frailty_and_density(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 2, 4);
  ENSURE(tree.bond_count == 1);
  for (int doubled = 0; doubled < 2; ++doubled) {
    bk_world* world = make_world();
    bk_world_breakable_def desc = bk_default_world_breakable_def();
    desc.breakable.transform.position = bk_v3(0, 0.5, 0);
    bk_breakable_id id = add(world, &tree, desc);
    bk_body_view view = {0};
    ENSURE(bk_world_body_view(world, 0, &view));
    const bk_physics* physics = bk_world_physics(world);
    double mass = bk_physics_body_mass(physics, view.body);
    bk_vec3 inertia = bk_physics_body_inertia(physics, view.body);
    ENSURE_REL(mass, desc.breakable.material.density * tree.nodes[0].moments.v, 1e-9);
    if (doubled) {
      bk_world_set_frailty(world, id, 2.0 * desc.breakable.material.frailty);
      bk_world_set_density(world, id, 2.0 * desc.breakable.material.density);
      ENSURE(bk_world_body_view(world, 0, &view));
      ENSURE_REL(bk_physics_body_mass(physics, view.body), 2.0 * mass, 1e-9);
      ENSURE_REL(bk_physics_body_inertia(physics, view.body).x, 2.0 * inertia.x, 1e-9);
    }
    double initial = 0.0;
    bk_world_bond_health(world, id, 0, &initial);
    double s_min = bk_default_world_def().runtime.damage_min_distance;
    double impulse = 0.6 * initial * s_min * s_min * s_min / desc.breakable.material.frailty;
    bk_world_impact(world, bk_v3_add(tree.bonds[0].centroid, bk_v3(0, 0.5, 0)), impulse);
    bk_world_step(world);
    ENSURE_MSG(bk_world_get_stats(world).bodies == (doubled ? 2u : 1u), "frailty x%d: %u bodies", 1 + doubled,
               bk_world_get_stats(world).bodies);
    bk_world_destroy(world);
  }
  bk_mesh_tree_free(&tree);
}

// Structural stress is a live switch, and its limits live material values:
// a wall whose limits drop to 1 Pa keeps every bond while stress is off, and
// sheds bonds under its own weight once it is back on.
static void test_live_stress(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 64, 6);
  bk_world* world = make_world();
  ENSURE(bk_world_stress(world));
  bk_world_set_stress(world, false);
  ENSURE(!bk_world_stress(world));
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  desc.breakable.anchored = true;
  bk_breakable_id id = add(world, &tree, desc);
  bk_material m = bk_world_material(world, id);
  m.compression_limit = m.tension_limit = m.shear_limit = 1.0;
  ENSURE(bk_world_set_material(world, id, &m) == BK_OK);
  bk_material back = bk_world_material(world, id);
  ENSURE(back.compression_limit == 1.0 && back.tension_limit == 1.0 && back.shear_limit == 1.0);
  for (int i = 0; i < 60; ++i)
    bk_world_step(world);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE(s.bonds_broken == 0 && s.stress_iterations == 0 && s.bodies == 1);
  bk_world_set_stress(world, true);
  ENSURE(bk_world_stress(world));
  for (int i = 0; i < 60; ++i)
    bk_world_step(world);
  s = bk_world_get_stats(world);
  ENSURE_MSG(s.stress_bonds_broken > 0 && s.bodies > 1, "%u bonds broken by stress, %u bodies",
             s.stress_bonds_broken, s.bodies);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// Left alone for two simulated minutes, a standing object keeps every bond.
static void test_resting_keeps_bonds(void) {
  bk_mesh_tree wall = make_tree(BK_SHAPE_WALL, 64, 6), pillar = make_tree(BK_SHAPE_PILLAR, 64, 7);
  bk_world* world = make_world();
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  desc.breakable.anchored = true;
  add(world, &wall, desc);
  desc.breakable.anchored = false;
  desc.breakable.transform.position = bk_v3(3, 0, 0);
  add(world, &pillar, desc);
  for (int i = 0; i < 120 * 60; ++i)
    bk_world_step(world);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE_MSG(s.bonds_broken == 0 && s.bodies == 2 && !s.nan, "%u bonds broke, %u bodies", s.bonds_broken,
             s.bodies);
  // The pillar still stands where it was.
  bk_body_view v = {0};
  ENSURE(bk_world_body_view(world, 1, &v));
  ENSURE_SMALL(v.tree_to_world.position.x, 3.0, 0.01);
  ENSURE_SMALL(v.tree_to_world.position.y, 0.0, 0.01);
  bk_world_destroy(world);
  bk_mesh_tree_free(&wall);
  bk_mesh_tree_free(&pillar);
}

// Splits keep the motion: a body spinning freely breaks into pieces moving
// with v + w x r at their own centres of mass.
static void test_split_keeps_motion(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 8, 8);
  bk_world_def wd = bk_default_world_def();
  wd.ground = false;
  wd.gravity = bk_v3(0, 0, 0); // no g dt added by the split step
  bk_world* world = bk_world_create(&wd, NULL);
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  desc.breakable.transform.position = bk_v3(0, 10, 0);
  add(world, &tree, desc);
  bk_body_view v = {0};
  ENSURE(bk_world_body_view(world, 0, &v));
  bk_vec3 omega = bk_v3(0, 2.0, 0), velocity = bk_v3(1, 0, 0);
  bk_physics_body_set_velocity(bk_world_physics(world), v.body, velocity, omega);
  bk_world_impact(world, bk_v3(0, 10, 0), 1e9); // shatter everything
  bk_world_step(world);
  uint32_t bodies = bk_world_body_count(world);
  ENSURE(bodies == 8);
  double momentum_x = 0.0, total = 0.0;
  for (uint32_t i = 0; i < bodies; ++i) {
    ENSURE(bk_world_body_view(world, i, &v));
    bk_physics* p = bk_world_physics(world);
    double m = bk_physics_body_mass(p, v.body);
    bk_vec3 lv = bk_physics_body_linear_velocity(p, v.body), av = bk_physics_body_angular_velocity(p, v.body);
    bk_vec3 r = bk_v3_sub(bk_physics_body_transform(p, v.body).position, bk_v3(0, 10, 0));
    bk_vec3 expected = bk_v3_add(velocity, bk_v3_cross(omega, r));
    ENSURE_SMALL(bk_v3_length(bk_v3_sub(lv, expected)), 0.0, 0.05);
    ENSURE_SMALL(bk_v3_length(bk_v3_sub(av, omega)), 0.0, 1e-6);
    momentum_x += m * lv.x;
    total += m;
  }
  ENSURE_REL(momentum_x / total, 1.0, 0.02); // linear momentum preserved
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// The split budget: a shattering hit creates at most `budget` bodies a step;
// the rest follows over the next steps until every fragment is free.
static void test_split_budget(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_SLAB, 32, 9);
  bk_world_def wd = bk_default_world_def();
  wd.runtime.max_new_clusters_per_split = 4;
  bk_world* world = bk_world_create(&wd, NULL);
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  desc.breakable.transform.position = bk_v3(-2, 0, 0);
  add(world, &tree, desc);
  desc.breakable.transform.position = bk_v3(2, 0, 0);
  add(world, &tree, desc);
  bk_world_impact(world, bk_v3(0, 0, 0), 1e12); // shatter both
  uint32_t bodies = 2, steps = 0;
  double mass = bk_world_get_stats(world).total_mass;
  do {
    bk_world_step(world);
    bk_world_stats s = bk_world_get_stats(world);
    // Each split removes one body and creates its parts: at most budget - 1 more.
    ENSURE_MSG(s.bodies <= bodies + 3, "step %u: %u -> %u bodies", steps, bodies, s.bodies);
    ENSURE_REL(s.total_mass, mass, 1e-9);
    if (steps == 0) ENSURE(s.bodies == 5 && s.pending_splits == 2);
    bodies = s.bodies;
  } while (++steps < 100 && bk_world_get_stats(world).pending_splits > 0);
  ENSURE_MSG(bodies == 64 && steps >= 20, "%u bodies after %u steps", bodies, steps);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// Small loose fragments retire after their time; their mass is accounted for.
static void test_retirement(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 32, 12);
  bk_world_def wd = bk_default_world_def();
  wd.retire_volume = 1.0; // every single fragment qualifies
  wd.retire_after = 0.5;
  bk_world* world = bk_world_create(&wd, NULL);
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  desc.breakable.transform.position = bk_v3(0, 0.5, 0);
  add(world, &tree, desc);
  double mass = bk_world_get_stats(world).total_mass;
  bk_world_impact(world, bk_v3(0, 0.5, 0), 1e12);
  bk_world_step(world);
  ENSURE(bk_world_get_stats(world).bodies == 32 && bk_world_get_stats(world).fragments_retired == 0);
  for (int i = 0; i < 25; ++i)
    bk_world_step(world); // 0.42 s: not yet
  ENSURE(bk_world_get_stats(world).fragments_retired == 0);
  for (int i = 0; i < 10; ++i)
    bk_world_step(world);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE_MSG(s.fragments_retired == 32 && s.bodies == 0, "%u retired, %u bodies", s.fragments_retired,
             s.bodies);
  ENSURE_REL(s.total_mass + s.retired_mass, mass, 1e-9);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

static void test_bad_input(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 4, 10);
  bk_world* world = make_world();
  bk_world_breakable_def desc = bk_default_world_breakable_def();
  desc.breakable.tree = &tree;
  desc.breakable.material.density = NAN;
  bk_error err = {0};
  ENSURE(bk_world_add_breakable(world, &desc, &err).generation == 0);
  ENSURE_MSG(strstr(err.message, "density") != NULL, "%s", err.message);
  desc = bk_default_world_breakable_def();
  desc.breakable.tree = &tree;
  desc.breakable.material.frailty = -1.0;
  ENSURE(bk_world_add_breakable(world, &desc, &err).generation == 0);
  ENSURE_MSG(strstr(err.message, "frailty") != NULL, "%s", err.message);
  desc = bk_default_world_breakable_def();
  ENSURE(bk_world_add_breakable(world, &desc, &err).generation == 0);
  ENSURE_MSG(strstr(err.message, "tree") != NULL, "%s", err.message);
  bk_world_def wd = bk_default_world_def();
  wd.fixed_dt = -1.0;
  ENSURE(bk_world_create(&wd, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "fixed_dt") != NULL, "%s", err.message);
  // The runtime's def inside the world's: a bad field of it is named by its
  // place in the world's def, with the runtime's own check and code.
  wd = bk_default_world_def();
  wd.runtime.max_new_clusters_per_split = 1;
  ENSURE(bk_world_create(&wd, &err) == NULL);
  ENSURE_MSG(strcmp(err.message, "world: runtime.max_new_clusters_per_split must be at least 2 (got 1)") == 0,
             "%s", err.message);
  ENSURE(err.code == BK_ERROR_INVALID_ARGUMENT);
  wd = bk_default_world_def();
  wd.runtime.stress_tolerance = 0.5;
  ENSURE(bk_world_create(&wd, &err) == NULL);
  ENSURE_MSG(strcmp(err.message, "world: runtime.stress_tolerance must be in (0, 0.1] (got 0.5)") == 0, "%s",
             err.message);
  // What the world sets itself is not the caller's to get wrong.
  wd = bk_default_world_def();
  wd.runtime.body_state = NULL;
  wd.runtime.gravity = bk_v3(NAN, 0, 0);
  bk_world* set_by_world = bk_world_create(&wd, &err);
  ENSURE_MSG(set_by_world != NULL, "%s", err.message);
  bk_world_destroy(set_by_world);
  bk_projectile_def shot = bk_default_projectile_def();
  shot.position = bk_v3(NAN, 0, 0);
  ENSURE(bk_body_is_null(bk_world_fire(world, &shot, &err)));
  ENSURE_MSG(strstr(err.message, "position") != NULL, "%s", err.message);
  // Zero means zero: a zero radius is refused by name, not replaced by a default.
  shot = bk_default_projectile_def();
  shot.radius = 0.0;
  ENSURE(bk_body_is_null(bk_world_fire(world, &shot, &err)));
  ENSURE_MSG(strstr(err.message, "radius") != NULL, "%s", err.message);
  // while zero friction and restitution are real values, kept as given.
  desc = bk_default_world_breakable_def();
  desc.breakable.tree = &tree;
  desc.breakable.material.friction = 0.0;
  desc.breakable.material.restitution = 0.0;
  bk_breakable_id slippery = bk_world_add_breakable(world, &desc, &err);
  ENSURE_MSG(slippery.generation != 0, "%s", err.message);
  ENSURE(bk_world_material(world, slippery).friction == 0.0);
  ENSURE(bk_world_material(world, slippery).restitution == 0.0);
  desc.breakable.transform.rotation = (bk_quat){0, 0, 0, 0};
  ENSURE(bk_world_add_breakable(world, &desc, &err).generation == 0);
  ENSURE_MSG(strstr(err.message, "rotation") != NULL, "%s", err.message);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// Many worlds, many breaks: LeakSanitizer checks nothing is left behind.
static void test_many_breaks(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_CUBE, 16, 11);
  uint32_t breaks = 0;
  for (int round = 0; round < 60 && breaks < 100; ++round) {
    bk_world* world = make_world();
    bk_world_breakable_def desc = bk_default_world_breakable_def();
    desc.breakable.transform.position = bk_v3(0, 0.5, 0);
    add(world, &tree, desc);
    // Knock out every bond, one at a time from a different one each round:
    // 30 times a bond's hit points at s_min from its centroid.
    double s_min = bk_default_world_def().runtime.damage_min_distance;
    for (uint32_t k = 0; k < tree.bond_count; ++k) {
      uint32_t bond = (k + 7u * (uint32_t)round) % tree.bond_count;
      double initial = 0.0;
      bk_world_bond_health(world, (bk_breakable_id){0, 1}, bond, &initial);
      bk_world_impact(world, bk_v3_add(tree.bonds[bond].centroid, bk_v3(0, 0.5, 0)),
                      30.0 * initial * s_min * s_min * s_min);
      bk_world_step(world);
    }
    breaks += bk_world_get_stats(world).break_events;
    bk_world_destroy(world);
  }
  ENSURE_MSG(breaks >= 100, "only %u breaks", breaks);
  bk_mesh_tree_free(&tree);
}

// A projectile leaves after the world's projectile_lifetime, or its own;
// one with an infinite lifetime (a weight) stays; a bad lifetime is named.
static void test_projectile_lifetime(void) {
  bk_world* world = make_world();
  double world_life = bk_default_world_def().projectile_lifetime;
  bk_projectile_def shot = bk_default_projectile_def();
  shot.position = bk_v3(0, 5, 0);
  ENSURE(shot.lifetime == 0.0);
  ENSURE(!bk_body_is_null(bk_world_fire(world, &shot, NULL)));
  shot.position = bk_v3(2, 5, 0);
  shot.lifetime = 1.0;
  ENSURE(!bk_body_is_null(bk_world_fire(world, &shot, NULL)));
  shot.position = bk_v3(4, 5, 0);
  shot.lifetime = INFINITY;
  ENSURE(!bk_body_is_null(bk_world_fire(world, &shot, NULL)));
  const double lifetimes[] = {-1.0, NAN};
  for (int i = 0; i < 2; ++i) {
    bk_error err = {0};
    shot.lifetime = lifetimes[i];
    ENSURE(bk_body_is_null(bk_world_fire(world, &shot, &err)));
    ENSURE_MSG(strstr(err.message, "lifetime") != NULL, "%s", err.message);
  }
  int steps_per_second = (int)(1.0 / bk_default_world_def().fixed_dt + 0.5);
  for (int i = 0; i < 2 * steps_per_second; ++i)
    bk_world_step(world);
  ENSURE(bk_world_projectile_count(world) == 2); // its own second is over
  for (int i = 0; i < (int)(world_life * steps_per_second); ++i)
    bk_world_step(world);
  ENSURE(bk_world_projectile_count(world) == 1); // the world's lifetime too; the weight stays
  bk_world_destroy(world);
}

int main(void) {
  RUN(test_unbroken_is_one_body);
  RUN(test_torus_principal_inertia);
  RUN(test_eggshell_not_solid);
  RUN(test_discrete_vs_accumulating);
  RUN(test_live_frailty_and_density);
  RUN(test_live_stress);
  RUN(test_naive_same_clusters);
  RUN(test_split_keeps_motion);
  RUN(test_split_budget);
  RUN(test_retirement);
  RUN(test_bad_input);
  RUN(test_many_breaks);
  RUN(test_wall_breaks);
  RUN(test_resting_keeps_bonds);
  RUN(test_projectile_lifetime);
  return 0;
}
