// Refinement in the Bullet world (bk_world_step calls bk_runtime_refine):
// a shot at a 64-fragment wall whose fragments refine breaks it where it
// was hit into the pieces of the fragments it struck, every new node with a
// hull and every body made of new nodes with colliders; without refinement
// the same shot breaks it into its own fragments; a loose fragment hit hard
// refines too; the same shots give the same result; a refined breakable is
// removed cleanly.
#include <stdlib.h>
#include <string.h>

#include "ensure.h"
#include <breakables/bullet.h>

static bk_mesh_tree make_wall(uint32_t pieces) {
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_WALL, &mesh);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = 3000;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &desc, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

static bk_mesh_tree make_cube(void) {
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_CUBE, &mesh);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = 1;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &desc, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

// Stone, refining as sim --refine sets it: a hit that would break a bond
// an eighth of a fragment's cross-section refines it into 32 radial pieces.
static bk_world_breakable_def wall_def(const bk_mesh_tree* tree, bool refine) {
  bk_world_breakable_def def = bk_default_world_breakable_def();
  def.breakable.tree = tree;
  def.breakable.anchored = true;
  def.breakable.material = *bk_material_find("stone");
  if (refine) {
    def.breakable.material.refine_strength = def.breakable.material.bond_strength / 8.0;
    def.breakable.refine =
        (bk_refine_def){.pattern = BK_PATTERN_RADIAL, .pieces = 32, .min_size = 0.02, .radial_falloff = 1.0};
  }
  return def;
}

static bk_world* make_world(void) {
  bk_world_def def = bk_default_world_def();
  def.physics_budget_ms = 0.0; // every piece stays a full body: the test counts them
  bk_error err = {0};
  bk_world* world = bk_world_create(&def, &err);
  ENSURE_MSG(world != NULL, "%s", err.message);
  return world;
}

static bk_breakable_id add(bk_world* world, const bk_world_breakable_def* def) {
  bk_error err = {0};
  bk_breakable_id id = bk_world_add_breakable(world, def, &err);
  ENSURE_MSG(id.generation != 0, "%s", err.message);
  return id;
}

// The wall scene's shot: a 40 kg stone ball at 40 m/s into the middle.
static void shoot(bk_world* world, double x) {
  bk_projectile_def shot = {
      .position = bk_v3(x, 0.7, 2.0), .velocity = bk_v3(0, 0, -40.0), .radius = 0.14, .mass = 40.0};
  bk_error err = {0};
  ENSURE_MSG(!bk_body_is_null(bk_world_fire(world, &shot, &err)), "%s", err.message);
}

typedef struct run_result {
  bk_world_stats stats;
  uint32_t leaves, nodes;
  bool tree_replaced;
  uint32_t new_node_bodies; // bodies whose node set names a node the refinement added
  bk_vec3 position_sum;     // of every body: a bit-for-bit fingerprint
} run_result;

// Every body: its colliders are nodes of the tree as it is now, with a
// hull each, and one whose node set names new nodes has colliders.
static run_result look(bk_world* world, bk_breakable_id id, const bk_mesh_tree* first) {
  run_result r = {.stats = bk_world_get_stats(world)};
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(bk_world_runtime(world), id);
  r.leaves = tree->leaf_count;
  r.nodes = tree->node_count;
  r.tree_replaced = tree != first;
  uint32_t colliders[4096];
  for (uint32_t b = 0; b < bk_world_body_count(world); ++b) {
    bk_body_view view = {0};
    ENSURE(bk_world_body_view(world, b, &view));
    ENSURE(view.tree == tree);
    r.position_sum = bk_v3_add(r.position_sum, view.tree_to_world.position);
    bool names_new = false;
    for (uint32_t k = 0; k < view.node_count; ++k) {
      ENSURE(view.nodes[k] < tree->node_count);
      names_new = names_new || view.nodes[k] >= first->node_count;
    }
    for (uint32_t k = 0; k < view.leaf_count; ++k)
      ENSURE(view.leaves[k] < tree->leaf_count && (k == 0 || view.leaves[k] > view.leaves[k - 1]));
    uint32_t count = bk_world_body_colliders(world, b, colliders, 4096);
    ENSURE(count <= 4096);
    for (uint32_t k = 0; k < count; ++k)
      ENSURE(colliders[k] < tree->node_count);
    if (!names_new) continue;
    r.new_node_bodies++;
    ENSURE_MSG(count > 0, "a body of %u new-node pieces has no collider", view.leaf_count);
    // Its shape is a hull (one piece) or a compound of them: never nothing.
    ENSURE(bk_physics_shape_valid(bk_world_physics(world),
                                  bk_physics_body_shape(bk_world_physics(world), view.body)));
  }
  return r;
}

static run_result shoot_wall(const bk_mesh_tree* tree, bool refine, uint32_t steps) {
  bk_world* world = make_world();
  bk_world_breakable_def def = wall_def(tree, refine);
  bk_breakable_id id = add(world, &def);
  for (uint32_t step = 0; step < steps; ++step) {
    if (step == 5) shoot(world, 0.1);
    bk_world_step(world);
  }
  run_result r = look(world, id, tree);
  ENSURE(!r.stats.nan);
  bk_world_destroy(world);
  return r;
}

static void test_shot_refines(void) {
  bk_mesh_tree tree = make_wall(64);
  run_result coarse = shoot_wall(&tree, false, 60);
  run_result fine = shoot_wall(&tree, true, 60);
  // Without refinement: the tree as it was, broken into its own fragments.
  ENSURE(coarse.stats.refined_leaves == 0 && coarse.leaves == 64 && coarse.nodes == tree.node_count);
  ENSURE(!coarse.tree_replaced && coarse.new_node_bodies == 0);
  ENSURE_MSG(coarse.stats.bonds_broken > 0 && coarse.stats.bodies > 1, "%u bodies", coarse.stats.bodies);
  // With it: fragments refined, the tree grew (the breakable's own copy),
  // and the split made bodies of the pieces, each with colliders.
  ENSURE_MSG(fine.stats.refined_leaves > 0, "nothing refined");
  ENSURE(fine.tree_replaced && fine.leaves > 64 && fine.nodes > tree.node_count);
  ENSURE_MSG(fine.leaves - 64 >= fine.stats.refined_leaves, "%u leaves after %u refinements", fine.leaves,
             fine.stats.refined_leaves);
  ENSURE_MSG(fine.new_node_bodies > 0, "no body names a new node");
  ENSURE_MSG(fine.stats.bodies > coarse.stats.bodies, "refined %u bodies, coarse %u", fine.stats.bodies,
             coarse.stats.bodies);
  ENSURE_REL(fine.stats.total_mass + fine.stats.retired_mass,
             coarse.stats.total_mass + coarse.stats.retired_mass, 1e-9);
  // Same shots, same result, bit for bit.
  run_result again = shoot_wall(&tree, true, 60);
  ENSURE(again.leaves == fine.leaves && again.nodes == fine.nodes && again.stats.bodies == fine.stats.bodies);
  ENSURE(again.stats.bonds_broken == fine.stats.bonds_broken);
  ENSURE(memcmp(&again.position_sum, &fine.position_sum, sizeof(bk_vec3)) == 0);
  fprintf(stderr,
          "    wall x64, a shot: coarse %u bodies, %u bonds broken; refined %u fragments into %u leaves, %u "
          "bodies (%u of new nodes), %u bonds broken\n",
          coarse.stats.bodies, coarse.stats.bonds_broken, fine.stats.refined_leaves, fine.leaves,
          fine.stats.bodies, fine.new_node_bodies, fine.stats.bonds_broken);
  bk_mesh_tree_free(&tree);
}

// Every piece loose, one body each: every new leaf has a hull of its own
// (its body's shape, with vertices), and the world's stats agree.
static void test_every_new_leaf_has_a_hull(void) {
  bk_mesh_tree tree = make_wall(64);
  bk_world* world = make_world();
  bk_world_breakable_def def = wall_def(&tree, true);
  bk_breakable_id id = add(world, &def);
  shoot(world, 0.1);
  for (int step = 0; step < 40; ++step)
    bk_world_step(world);
  ENSURE(bk_world_get_stats(world).refined_leaves > 0);
  // No more refinement (what is marked still lands), to keep the count down.
  bk_material material = bk_world_material(world, id);
  material.refine_strength = 0.0;
  ENSURE(bk_world_set_material(world, id, &material) == BK_OK);
  // Break every bond left: a blow no bond survives, then steps until
  // nothing waits (a split, a refinement).
  bk_world_set_stress(world, false);
  for (int round = 0; round < 200; ++round) {
    bk_world_impact(world, bk_v3(0.0, 0.6, 0.0), 1e12);
    bk_world_step(world);
    bk_world_stats s = bk_world_get_stats(world);
    bk_runtime_stats rs = bk_runtime_get_stats(bk_world_runtime(world));
    if (s.pending_splits == 0 && s.pending_hits == 0 && rs.refine_pending == 0 &&
        s.bodies == s.fragments_free)
      break;
  }
  bk_world_stats s = bk_world_get_stats(world);
  const bk_mesh_tree* grown = bk_runtime_breakable_tree(bk_world_runtime(world), id);
  ENSURE_MSG(s.bodies == s.fragments_free, "%u bodies, %u of one fragment", s.bodies, s.fragments_free);
  ENSURE_MSG(s.bodies + s.fragments_retired == grown->leaf_count, "%u bodies + %u retired, %u leaves",
             s.bodies, s.fragments_retired, grown->leaf_count);
  bk_physics* physics = bk_world_physics(world);
  uint32_t new_leaves = 0;
  for (uint32_t b = 0; b < bk_world_body_count(world); ++b) {
    bk_body_view view = {0};
    ENSURE(bk_world_body_view(world, b, &view) && view.leaf_count == 1 && view.node_count == 1);
    if (view.nodes[0] < tree.node_count) continue;
    new_leaves++;
    uint32_t collider = 0;
    ENSURE_MSG(bk_world_body_colliders(world, b, &collider, 1) == 1 && collider == view.nodes[0],
               "new leaf %u has no hull", view.leaves[0]);
    bk_vec3 vertices[64];
    ENSURE(bk_physics_hull_vertices(physics, bk_physics_body_shape(physics, view.body), vertices, 64) >= 4);
  }
  ENSURE_MSG(new_leaves > 32, "%u new leaves loose", new_leaves);
  // Removing the refined breakable frees what it made (its own tree went
  // with it in the runtime: the world must not read it).
  uint32_t shapes = bk_physics_shape_count(physics);
  ENSURE(bk_world_remove_breakable(world, id) == BK_OK);
  ENSURE_MSG(bk_physics_shape_count(physics) + new_leaves <= shapes, "%u shapes before, %u after", shapes,
             bk_physics_shape_count(physics));
  ENSURE(bk_world_get_stats(world).bodies == 0);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
  fprintf(stderr, "    every bond broken: %u new leaves loose, each a body with its own hull\n", new_leaves);
}

// A loose fragment (a cluster of one) hit hard refines and breaks: the
// world's hit queue keeps hits on single fragments that may refine.
static void test_single_fragment_refines(void) {
  bk_mesh_tree tree = make_cube(); // one leaf: no bond to break
  for (int refine = 0; refine < 2; ++refine) {
    bk_world* world = make_world();
    bk_world_breakable_def def = wall_def(&tree, refine == 1);
    def.breakable.anchored = false;
    def.breakable.transform.position = bk_v3(0, 0.5, 0);
    add(world, &def);
    for (int step = 0; step < 20; ++step)
      bk_world_step(world); // at rest on the ground
    bk_projectile_def shot = {
        .position = bk_v3(0.0, 0.5, 2.0), .velocity = bk_v3(0, 0, -60.0), .radius = 0.14, .mass = 40.0};
    bk_world_fire(world, &shot, NULL);
    for (int step = 0; step < 60; ++step)
      bk_world_step(world);
    bk_world_stats s = bk_world_get_stats(world);
    if (refine == 0) {
      ENSURE(s.refined_leaves == 0 && s.bodies == 1);
    } else {
      ENSURE_MSG(s.refined_leaves > 0 && s.bodies > 1, "%u refined, %u bodies", s.refined_leaves, s.bodies);
    }
    bk_world_destroy(world);
  }
  bk_mesh_tree_free(&tree);
}

int main(void) {
  test_shot_refines();
  test_every_new_leaf_has_a_hull();
  test_single_fragment_refines();
  return 0;
}
