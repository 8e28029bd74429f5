// Settled debris in the Bullet world (bk_world_def.settle_cell): pieces at
// rest merge into one static compound per cell, so a settled heap is a few
// collision objects and pairs; merging moves nothing; a shot into a merged
// heap still hits and moves its pieces; taking away what holds a merged
// heap up makes it fall; the same inputs give the same run; 0 turns it off.
// Also the small fragments retire_volume removes, handed over to be faded.
#include <stdlib.h>
#include <string.h>

#include "budget_cubes.h"

static bk_world* make_world(double settle_cell) {
  bk_world_def wd = bk_default_world_def();
  wd.physics_budget_ms = 0.0; // the merge works with or without the budget
  wd.retire_volume = 0.0;     // nothing leaves but what the tests remove
  wd.settle_cell = settle_cell;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  return world;
}

static void run(bk_world* world, int steps) {
  for (int i = 0; i < steps; ++i)
    bk_world_step(world);
}

// Bodies of the world that are parked now (merged).
static uint32_t parked_bodies(bk_world* world) {
  uint32_t n = 0;
  bk_body_view view;
  for (uint32_t i = 0; i < bk_world_body_count(world); ++i)
    if (bk_world_body_view(world, i, &view) && bk_physics_body_parked(bk_world_physics(world), view.body))
      n++;
  return n;
}

// A shattered cube left to settle: 8 s, enough for its heap to sleep and merge.
static bk_world* settled_cube(const bk_mesh_tree* tree, double settle_cell, bk_breakable_id* id) {
  bk_world* world = make_world(settle_cell);
  *id = add_cube(world, tree, 0.0);
  shoot(world, 0.0);
  run(world, 480);
  return world;
}

static void test_fewer_objects(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  bk_breakable_id id = {0, 0};
  bk_world* off = settled_cube(&tree, 0.0, &id);
  bk_world* on = settled_cube(&tree, 2.0, &id);
  bk_physics_stats p_off = bk_physics_get_stats(bk_world_physics(off));
  bk_physics_stats p_on = bk_physics_get_stats(bk_world_physics(on));
  bk_world_stats s_off = bk_world_get_stats(off), s_on = bk_world_get_stats(on);
  printf("settled heap: %u bodies %u pairs off; %u bodies %u pairs on (%u merged in %u areas, last batch "
         "%.3f ms)\n",
         p_off.bodies, p_off.pairs, p_on.bodies, p_on.pairs, s_on.settled_bodies, s_on.settled_areas,
         s_on.settle_batch_ms);
  ENSURE(s_off.settled_bodies == 0 && s_off.settled_areas == 0);
  ENSURE_MSG(s_on.settled_bodies > 100, "%u merged", s_on.settled_bodies);
  ENSURE(s_on.settled_bodies == parked_bodies(on));
  ENSURE(s_on.settled_areas >= 1 && s_on.settled_areas <= 8);
  // Every fragment still exists and draws; a few objects stand in for them.
  ENSURE(s_on.bodies == bk_world_body_count(on) && s_on.bodies > 100);
  ENSURE_MSG(p_on.bodies * 4 < p_off.bodies, "%u objects vs %u", p_on.bodies, p_off.bodies);
  ENSURE_MSG(p_on.pairs * 4 < p_off.pairs, "%u pairs vs %u", p_on.pairs, p_off.pairs);
  ENSURE_REL(s_on.total_mass, s_off.total_mass, 1e-9);
  bk_world_destroy(off);
  bk_world_destroy(on);
  bk_mesh_tree_free(&tree);
}

// Merging and waking keep every piece exactly where it lay.
static void test_positions_kept(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  bk_world* world = make_world(2.0);
  bk_breakable_id id = add_cube(world, &tree, 0.0);
  shoot(world, 0.0);
  static bk_vec3 before[256], after[256];
  uint32_t checked = 0;
  // Over several batches: what was asleep before a step and is merged
  // after it lies where it did.
  for (int step = 0; step < 480; ++step) {
    ENSURE(bk_world_fragment_centroids(world, id, before, 256) == 256);
    uint32_t count = bk_world_body_count(world);
    bool* asleep = calloc(count + 1u, sizeof(bool));
    bk_body_view view;
    for (uint32_t i = 0; i < count; ++i)
      asleep[i] =
          bk_world_body_view(world, i, &view) && !bk_physics_body_awake(bk_world_physics(world), view.body);
    uint32_t merged_before = bk_world_get_stats(world).settled_bodies;
    bk_world_step(world);
    ENSURE(bk_world_fragment_centroids(world, id, after, 256) == 256);
    if (bk_world_get_stats(world).settled_bodies > merged_before) {
      for (uint32_t leaf = 0; leaf < 256; ++leaf) {
        bk_cluster_id cluster = bk_runtime_leaf_cluster(bk_world_runtime(world), id, leaf);
        for (uint32_t i = 0; i < bk_world_body_count(world) && i < count; ++i) {
          if (!bk_world_body_view(world, i, &view) || !bk_cluster_equal(view.cluster, cluster)) continue;
          if (!asleep[i] || !bk_physics_body_parked(bk_world_physics(world), view.body)) continue;
          ENSURE_MSG(memcmp(&before[leaf], &after[leaf], sizeof(bk_vec3)) == 0, "leaf %u moved by %g", leaf,
                     bk_v3_length(bk_v3_sub(after[leaf], before[leaf])));
          checked++;
        }
      }
    }
    free(asleep);
  }
  ENSURE_MSG(checked > 100, "%u pieces checked", checked);
  // A merged piece stays put while merged, and wakes where it lay.
  ENSURE(bk_world_get_stats(world).settled_bodies > 100);
  ENSURE(bk_world_fragment_centroids(world, id, before, 256) == 256);
  run(world, 30);
  ENSURE(bk_world_fragment_centroids(world, id, after, 256) == 256);
  ENSURE(memcmp(before, after, sizeof before) == 0);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// A second shot into the heap: how many pieces it moves 5 cm or more, and
// how many areas it woke.
static uint32_t shot_into_heap(double settle_cell, uint32_t* woken) {
  bk_mesh_tree tree = make_cube_tree(256);
  bk_breakable_id id = {0, 0};
  bk_world* world = settled_cube(&tree, settle_cell, &id);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE(settle_cell == 0.0 || s.settled_bodies > 100);
  static bk_vec3 before[256], after[256];
  ENSURE(bk_world_fragment_centroids(world, id, before, 256) == 256);
  bk_projectile_def shot = bk_default_projectile_def();
  shot.position = bk_v3(0.0, 0.4, 4.0);
  shot.velocity = bk_v3(0.0, -2.0, -40.0);
  shot.radius = 0.15;
  shot.mass = 8.0;
  bk_error err = {0};
  ENSURE_MSG(!bk_body_is_null(bk_world_fire(world, &shot, &err)), "%s", err.message);
  run(world, 60);
  ENSURE(bk_world_fragment_centroids(world, id, after, 256) == 256);
  uint32_t moved = 0;
  for (uint32_t leaf = 0; leaf < 256; ++leaf)
    moved += isfinite(before[leaf].x) && bk_v3_length(bk_v3_sub(after[leaf], before[leaf])) > 0.05;
  *woken = bk_world_get_stats(world).settle_wakes - s.settle_wakes;
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
  return moved;
}

// A shot into the merged heap wakes it and moves its pieces about as a
// shot into the heap of bodies does.
static void test_shot_into_merged(void) {
  uint32_t woken_off = 0, woken_on = 0;
  uint32_t off = shot_into_heap(0.0, &woken_off), on = shot_into_heap(2.0, &woken_on);
  printf("shot into the heap: %u pieces moved 5 cm or more (%u merged, %u areas woken)\n", off, on, woken_on);
  ENSURE(woken_off == 0 && woken_on > 0);
  ENSURE_MSG(on >= 5 && 2 * on >= off, "%u moved, %u unmerged", on, off);
}

// A cube broken on a table, its heap merged; the table goes: the heap falls.
static void test_undermined_falls(void) {
  bk_mesh_tree tree = make_cube_tree(64);
  bk_world* world = make_world(2.0);
  bk_physics* physics = bk_world_physics(world);
  bk_body_def table = bk_default_body_def();
  table.shape = bk_physics_create_box(physics, bk_v3(1.0, 0.1, 1.0));
  table.transform.position = bk_v3(0.0, 1.4, 0.0);
  bk_error err = {0};
  bk_body_id table_body = bk_physics_create_body(physics, &table, &err);
  ENSURE_MSG(!bk_body_is_null(table_body), "%s", err.message);
  bk_world_breakable_def bd = bk_default_world_breakable_def();
  bd.breakable.tree = &tree;
  bd.breakable.material = *bk_material_find("glass");
  bd.breakable.material.frailty *= 16.0;
  bd.breakable.transform.position = bk_v3(0.0, 2.0, 0.0);
  bk_breakable_id id = bk_world_add_breakable(world, &bd, &err);
  ENSURE_MSG(!bk_breakable_is_null(id), "%s", err.message);
  run(world, 30);
  bk_world_impact(world, bk_v3(0.0, 2.0, 0.0), 60.0);
  run(world, 480);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE_MSG(s.settled_bodies >= 10, "%u merged", s.settled_bodies);
  static bk_vec3 c[64];
  ENSURE(bk_world_fragment_centroids(world, id, c, 64) == 64);
  double high = 0.0;
  for (uint32_t i = 0; i < 64; ++i)
    high += c[i].y > 1.45;
  ENSURE_MSG(high > 32, "%g of 64 on the table", high);
  bk_physics_destroy_body(physics, table_body);
  run(world, 120);
  ENSURE(bk_world_fragment_centroids(world, id, c, 64) == 64);
  double still_high = 0.0;
  for (uint32_t i = 0; i < 64; ++i)
    still_high += c[i].y > 1.0;
  printf("undermined heap: %g of 64 pieces on the table, %g still above 1 m once it went\n", high,
         still_high);
  ENSURE_MSG(still_high == 0.0, "%g pieces hang in the air", still_high);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// The same shots twice: the same merges, wakes and places, bit for bit.
static void record(const bk_mesh_tree* tree, bk_vec3* out, bk_world_stats* stats) {
  bk_breakable_id id = {0, 0};
  bk_world* world = settled_cube(tree, 2.0, &id);
  shoot(world, 0.0);
  run(world, 240);
  ENSURE(bk_world_fragment_centroids(world, id, out, 256) == 256);
  *stats = bk_world_get_stats(world);
  bk_world_destroy(world);
}

static void test_deterministic(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  static bk_vec3 a[256], b[256];
  bk_world_stats sa, sb;
  record(&tree, a, &sa);
  record(&tree, b, &sb);
  ENSURE(memcmp(a, b, sizeof a) == 0);
  ENSURE(sa.settled_bodies == sb.settled_bodies && sa.settle_wakes == sb.settle_wakes);
  ENSURE(sa.settle_wakes > 0 && sa.bonds_broken == sb.bonds_broken);
  bk_mesh_tree_free(&tree);
}

// 0: no piece is ever parked, every body stays in Bullet's world.
static void test_off(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  bk_breakable_id id = {0, 0};
  bk_world* world = settled_cube(&tree, 0.0, &id);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE(s.settled_bodies == 0 && s.settled_areas == 0 && s.settle_wakes == 0 && parked_bodies(world) == 0);
  // Every breakable body, the ground and nothing else (the shot has gone).
  ENSURE(bk_physics_get_stats(bk_world_physics(world)).bodies == s.bodies + 1 + s.projectiles);
  ENSURE(bk_world_settle_cell(world) == 0.0);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

static void test_defs(void) {
  bk_world_def wd = bk_default_world_def();
  ENSURE(wd.settle_cell == 2.0 && wd.settle_wake_speed == 2.0 && wd.retire_volume == 2e-5);
  wd.settle_cell = -1.0;
  expect_refused(wd, "world: settle_cell must be finite and >= 0 (got -1)");
  wd.settle_cell = INFINITY;
  expect_refused(wd, "world: settle_cell must be finite and >= 0 (got inf)");
  wd = bk_default_world_def();
  wd.settle_wake_speed = 0.0;
  expect_refused(wd, "world: settle_wake_speed must be a positive finite number (got 0)");
  wd.settle_wake_speed = NAN;
  expect_refused(wd, "world: settle_wake_speed must be a positive finite number (got nan)");
  wd = bk_default_world_def();
  wd.settle_cell = 3.5;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  ENSURE(bk_world_settle_cell(world) == 3.5);
  bk_world_destroy(world);
}

// Small fragments past retire_after leave, handed to the renderer to fade
// (bk_world_retired_bodies) rather than vanishing, their mass accounted for.
static void test_aged_fragments_fade(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  bk_world_def wd = bk_default_world_def();
  wd.physics_budget_ms = 0.0;
  wd.retire_volume = 1.0; // every single fragment
  wd.retire_after = 2.0;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  add_cube(world, &tree, 0.0);
  shoot(world, 0.0);
  uint32_t handed = 0;
  double handed_mass = 0.0;
  bk_retired_body bodies[512];
  for (int step = 0; step < 360; ++step) {
    bk_world_step(world);
    uint32_t n = bk_world_retired_bodies(world, bodies, 512);
    ENSURE(n <= 512);
    for (uint32_t i = 0; i < n; ++i) {
      ENSURE(bodies[i].mass > 0.0 && bk_v3_is_finite(bodies[i].center));
      handed_mass += bodies[i].mass;
    }
    handed += n;
  }
  bk_world_stats s = bk_world_get_stats(world);
  printf("aged fragments: %u retired, %u handed over to fade\n", s.fragments_retired, handed);
  ENSURE(s.fragments_retired > 50);
  ENSURE(handed == s.fragments_retired);
  ENSURE_REL(handed_mass, s.retired_mass, 1e-9);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// A body (not a projectile: nothing looks ahead for it) set down onto a
// merged heap touches the compound before the cell wakes: the contact
// names the compound's child it touched, and the world turns it into
// damage to that piece's cluster, which breaks in the same step.
static void test_contact_names_child(void) {
  bk_mesh_tree tree = make_cube_tree(64);
  bk_world* world = make_world(2.0);
  // In the middle of a cell (cells are 2 m, from the origin).
  bk_world_breakable_def bd = bk_default_world_breakable_def();
  bd.breakable.tree = &tree;
  bd.breakable.material = *bk_material_find("glass");
  bd.breakable.material.frailty *= 16.0;
  bd.breakable.transform.position = bk_v3(1.0, 0.5, 1.0);
  bk_error err = {0};
  ENSURE_MSG(!bk_breakable_is_null(bk_world_add_breakable(world, &bd, &err)), "%s", err.message);
  bk_world_impact(world, bk_v3(1.0, 0.5, 1.0), 25.0); // cracked into a few clusters
  run(world, 480);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE_MSG(s.settled_bodies >= 2 && s.settled_areas == 1, "%u merged in %u", s.settled_bodies,
             s.settled_areas);
  bk_physics* physics = bk_world_physics(world);
  // Just into the heap's top (a ray finds it on the compound), falling fast.
  bk_ray_hit top = {0};
  ENSURE(bk_physics_ray_cast(physics, bk_v3(1.0, 3.0, 1.0), bk_v3(1.0, 0.01, 1.0), &top));
  bk_body_def ball = bk_default_body_def();
  ball.shape = bk_physics_create_sphere(physics, 0.15);
  ball.mass = 200.0;
  ball.inertia = bk_v3(1.8, 1.8, 1.8);
  ball.transform.position = bk_v3(1.0, top.point.y + 0.15 - 0.01, 1.0);
  ball.linear_velocity = bk_v3(0.0, -20.0, 0.0);
  bk_body_id ball_body = bk_physics_create_body(physics, &ball, &err);
  ENSURE_MSG(!bk_body_is_null(ball_body), "%s", err.message);
  bk_world_step(world);
  static bk_contact contacts[1024];
  uint32_t n = bk_physics_contacts(physics, contacts, 1024), on_compound = 0;
  for (uint32_t i = 0; i < n && i < 1024; ++i) {
    const bk_contact* c = &contacts[i];
    bool ball_a = bk_body_equal(c->a, ball_body), ball_b = bk_body_equal(c->b, ball_body);
    if (!ball_a && !ball_b) continue;
    ENSURE(bk_body_equal(ball_a ? c->a : c->b, top.body) == false);
    ENSURE(bk_body_equal(ball_a ? c->b : c->a, top.body)); // the compound, nothing else
    ENSURE((ball_a ? c->child_a : c->child_b) == -1);      // a sphere is no compound
    ENSURE((ball_a ? c->child_b : c->child_a) >= 0);       // the piece touched
    on_compound++;
  }
  ENSURE_MSG(on_compound > 0, "%u contacts", n);
  // The hit on the compound broke bonds of the piece it touched, in this
  // step (the cell wakes as that piece splits).
  bk_world_stats t = bk_world_get_stats(world);
  printf("hit on the compound: %u bonds broken in its step\n", t.bonds_broken - s.bonds_broken);
  ENSURE(t.bonds_broken > s.bonds_broken && t.settle_wakes == s.settle_wakes + 1);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

int main(void) {
  test_defs();
  test_fewer_objects();
  test_positions_kept();
  test_shot_into_merged();
  test_undermined_falls();
  test_contact_names_child();
  test_deterministic();
  test_off();
  test_aged_fragments_fade();
  puts("test_settle: ok");
  return 0;
}
