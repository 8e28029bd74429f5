// The physics budget of the Bullet world. Off (0) or never reached, it
// changes nothing. Over it, a shattered glass cube's debris gets cheaper tier
// by tier in order (debris, simplified, frozen, retired), never a large piece
// or one near the focus; mass is kept (simulated + retired); the same inputs
// make the same decisions; fidelity comes back when the budget is raised,
// turned off, or the load drops. Also the physics layer's tools it uses:
// debris filtering, a body's shape swapped, pinning.
#include <stdlib.h>
#include <string.h>

#include "budget_cubes.h"

// Without the fidelity time (every piece fair game at once), so that the
// tiers are all reached within these tests' few seconds;
// test_fidelity_first_second has it.
static bk_world* make_world(double budget_ms, double large_volume) {
  bk_world_def wd = bk_default_world_def();
  wd.physics_budget_ms = budget_ms;
  wd.budget_large_volume = large_volume;
  wd.budget_fidelity_time = 0.0;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  return world;
}

static uint32_t demoted(bk_world_stats s) { return s.budget_debris + s.budget_simplified + s.budget_frozen; }

// Off, and on but never reached: the same run, bit for bit, as each other,
// with nothing counted. (The budget reads the world only; a run it never
// touches is the run without it.)
static void test_off_changes_nothing(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  double budgets[3] = {0.0, 1e6, 0.0};
  bk_world* worlds[3] = {NULL, NULL, NULL};
  bk_breakable_id ids[3] = {{0, 0}, {0, 0}, {0, 0}};
  for (int i = 0; i < 3; ++i) {
    worlds[i] = make_world(budgets[i], 0.008);
    ids[i] = add_cube(worlds[i], &tree, 0.0);
    shoot(worlds[i], 0.0);
  }
  bk_world_set_focus(worlds[2], bk_v3(0.0, 0.5, 0.0)); // a focus alone decides nothing
  static bk_vec3 centroids[3][256];                    // zeroed, and too large for the stack under ASan
  for (int step = 0; step < 150; ++step) {
    bk_world_stats s[3] = {{0}, {0}, {0}};
    for (int i = 0; i < 3; ++i) {
      bk_world_step(worlds[i]);
      s[i] = bk_world_get_stats(worlds[i]);
      ENSURE(bk_world_fragment_centroids(worlds[i], ids[i], centroids[i], 256) == 256);
      ENSURE(demoted(s[i]) == 0 && s[i].budget_retired == 0 && s[i].budget_demotions == 0);
      ENSURE(s[i].budget_level == 0.0 && s[i].fragments_retired == 0);
    }
    ENSURE(s[0].budget_cost_ms == 0.0 && s[1].budget_cost_ms > 0.0); // measured only when on
    for (int i = 1; i < 3; ++i) {
      ENSURE(s[i].bodies == s[0].bodies && s[i].colliders == s[0].colliders);
      ENSURE(s[i].bonds_broken == s[0].bonds_broken && s[i].total_mass == s[0].total_mass);
      ENSURE(memcmp(centroids[i], centroids[0], sizeof centroids[0]) == 0);
    }
  }
  ENSURE(bk_world_get_stats(worlds[0]).bodies > 50); // it did shatter
  for (int i = 0; i < 3; ++i)
    bk_world_destroy(worlds[i]);
  bk_mesh_tree_free(&tree);
}

// The step at which something first reached each tier (-1: never).
typedef struct first_steps {
  int debris, simplified, frozen, retired;
} first_steps;

static void note_tiers(bk_world_stats s, int step, first_steps* first) {
  if (first->debris < 0 && demoted(s) + s.budget_retired > 0) first->debris = step;
  if (first->simplified < 0 && s.budget_simplified + s.budget_frozen + s.budget_retired > 0)
    first->simplified = step;
  if (first->frozen < 0 && s.budget_frozen > 0) first->frozen = step;
  if (first->retired < 0 && s.budget_retired > 0) first->retired = step;
  // A tier is reached only once the level has passed the ones before it.
  ENSURE(s.budget_simplified == 0 || s.budget_level > 1.0);
  ENSURE(s.budget_frozen == 0 || s.budget_level > 2.0);
}

// A cube shattered and settled, then a tiny budget: its pieces become
// debris, then simplified, then the settled ones frozen; a second cube shot
// then throws moving pieces, which retire (frozen ones cost nothing more).
static void test_tiers_in_order(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  bk_world* world = make_world(0.0, 0.008);
  add_cube(world, &tree, -1.5);
  add_cube(world, &tree, 1.5);
  shoot(world, -1.5);
  for (int step = 0; step < 180; ++step)
    bk_world_step(world);
  ENSURE(bk_world_set_physics_budget(world, 0.001) && bk_world_physics_budget(world) == 0.001);
  first_steps first = {-1, -1, -1, -1};
  uint32_t levels_over_3 = 0;
  for (int step = 0; step < 120; ++step) {
    if (step == 30) shoot(world, 1.5);
    bk_world_step(world);
    bk_world_stats s = bk_world_get_stats(world);
    note_tiers(s, step, &first);
    levels_over_3 += s.budget_level > 3.0;
    if (s.budget_retired > 0) ENSURE(levels_over_3 > 0);
  }
  ENSURE_MSG(first.debris == 0 && first.simplified == 1 && first.frozen == 2 && first.retired > 2,
             "first steps: debris %d, simplified %d, frozen %d, retired %d", first.debris, first.simplified,
             first.frozen, first.retired);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// Neither a piece at least budget_large_volume in size nor one within
// budget_focus_radius of the focus is ever made cheaper; there are both kinds
// at full fidelity while the others are demoted.
static void test_large_and_near_kept(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  double large = 0.01, radius = 0.5;
  bk_vec3 focus = bk_v3(0.3, 0.3, 0.3);
  bk_world_def wd = bk_default_world_def();
  wd.physics_budget_ms = 0.001;
  wd.budget_large_volume = large;
  wd.budget_focus_radius = radius;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  bk_world_set_focus(world, focus);
  bk_vec3 got = bk_v3(0, 0, 0);
  ENSURE(bk_world_focus(world, &got) && got.x == focus.x && got.z == focus.z);
  add_cube(world, &tree, 0.0);
  shoot(world, 0.0);
  uint32_t near_full = 0, large_full = 0, cheaper = 0;
  for (int step = 0; step < 120; ++step) {
    bk_world_step(world);
    for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
      bk_body_view view = {0};
      ENSURE(bk_world_body_view(world, i, &view));
      bk_cluster_info info = {0};
      ENSURE(bk_runtime_cluster(bk_world_runtime(world), view.cluster, &info));
      bk_vec3 center = bk_physics_body_transform(bk_world_physics(world), view.body).position;
      bool near = bk_v3_length(bk_v3_sub(center, focus)) <= radius;
      bool is_large = info.volume >= large;
      if (view.tier != BK_TIER_FULL) {
        ENSURE_MSG(!near && !is_large, "a %s piece at tier %d", near ? "near" : "large", (int)view.tier);
        cheaper++;
      } else if (!info.is_static && bk_world_get_stats(world).budget_level >= 1.0) {
        near_full += near && !is_large;
        large_full += is_large;
      }
    }
  }
  ENSURE_MSG(near_full > 0 && large_full > 0 && cheaper > 0, "near %u, large %u, cheaper %u", near_full,
             large_full, cheaper);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// Simulated plus retired mass stays the cube's; each retired body is handed
// over with its mass, its one node and where it was.
static void test_mass_kept(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  bk_world* world = make_world(0.001, 0.008);
  bk_breakable_id id = add_cube(world, &tree, 0.0);
  double mass = bk_world_get_stats(world).total_mass;
  shoot(world, 0.0);
  double retired_before = 0.0;
  uint32_t handed = 0;
  for (int step = 0; step < 150; ++step) {
    bk_world_step(world);
    bk_world_stats s = bk_world_get_stats(world);
    ENSURE_REL(s.total_mass + s.retired_mass, mass, 1e-9);
    static bk_retired_body retired[512]; // zeroed
    uint32_t n = bk_world_retired_bodies(world, retired, 512);
    ENSURE(n <= 512);
    double sum = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
      ENSURE(retired[i].breakable.index == id.index && retired[i].node < tree.node_count);
      ENSURE(retired[i].mass > 0.0 && bk_v3_is_finite(retired[i].tree_to_world.position));
      // Its node's centroid, placed by tree_to_world, is the centre reported.
      bk_vec3 centroid = bk_mesh_tree_mass(&tree, tree.nodes[retired[i].node].moments).centroid;
      bk_vec3 placed = bk_transform_point(retired[i].tree_to_world, centroid);
      ENSURE(bk_v3_length(bk_v3_sub(placed, retired[i].center)) < 1e-6);
      sum += retired[i].mass;
    }
    ENSURE_REL(s.retired_mass - retired_before, sum, 1e-9);
    retired_before = s.retired_mass;
    handed += n;
    ENSURE(s.budget_retired == handed && s.fragments_retired >= handed);
  }
  ENSURE(handed > 0);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

typedef struct run_record {
  bk_world_stats stats[200];
  bk_vec3 centroids[200][256];
} run_record;

static void record_run(const bk_mesh_tree* tree, double budget_ms, run_record* out) {
  bk_world* world = make_world(budget_ms, 0.008);
  bk_world_set_focus(world, bk_v3(0.8, 1.1, 3.0));
  bk_breakable_id id = add_cube(world, tree, 0.0);
  shoot(world, 0.0);
  for (int step = 0; step < 200; ++step) {
    bk_world_step(world);
    out->stats[step] = bk_world_get_stats(world);
    ENSURE(bk_world_fragment_centroids(world, id, out->centroids[step], 256) == 256);
  }
  bk_world_destroy(world);
}

// Two runs of the same inputs make the same decisions at the same steps, and
// so the same motion. The budget is set where all four tiers are used.
static void test_deterministic(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  run_record* a = calloc(1, sizeof *a);
  run_record* b = calloc(1, sizeof *b);
  record_run(&tree, 0.2, a);
  record_run(&tree, 0.2, b);
  uint32_t most_frozen = 0;
  for (int step = 0; step < 200; ++step) {
    bk_world_stats x = a->stats[step], y = b->stats[step];
    ENSURE_MSG(x.budget_debris == y.budget_debris && x.budget_simplified == y.budget_simplified &&
                   x.budget_frozen == y.budget_frozen && x.budget_retired == y.budget_retired &&
                   x.budget_demotions == y.budget_demotions && x.budget_restorations == y.budget_restorations,
               "step %d", step);
    ENSURE(x.budget_level == y.budget_level && x.budget_cost_ms == y.budget_cost_ms);
    ENSURE(x.bodies == y.bodies && x.total_mass == y.total_mass && x.retired_mass == y.retired_mass);
    ENSURE(memcmp(a->centroids[step], b->centroids[step], sizeof a->centroids[step]) == 0);
    most_frozen = x.budget_frozen > most_frozen ? x.budget_frozen : most_frozen;
  }
  bk_world_stats end = a->stats[199];
  ENSURE_MSG(end.budget_retired > 0 && most_frozen > 0 && end.budget_demotions > end.budget_retired,
             "retired %u, frozen %u", end.budget_retired, most_frozen);
  free(a);
  free(b);
  bk_mesh_tree_free(&tree);
}

// Every live body has its own shape and no pin, and no debris filter unless
// `resting_debris` allows one on a body at rest.
static void ensure_full_fidelity(bk_world* world, bool resting_debris) {
  bk_physics* physics = bk_world_physics(world);
  uint32_t debris = 0;
  for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
    bk_body_view view = {0};
    ENSURE(bk_world_body_view(world, i, &view));
    ENSURE(!bk_physics_body_pinned(physics, view.body));
    ENSURE((view.tier == BK_TIER_DEBRIS) == bk_physics_body_debris(physics, view.body));
    if (view.tier == BK_TIER_DEBRIS) {
      ENSURE(resting_debris && !bk_physics_body_awake(physics, view.body));
      debris++;
    } else {
      ENSURE(view.tier == BK_TIER_FULL);
    }
    // A one-node body collides with its node's hull again, not a box or sphere.
    if (view.node_count == 1)
      ENSURE(bk_physics_hull_vertices(physics, bk_physics_body_shape(physics, view.body), NULL, 0) > 0);
  }
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE(s.budget_simplified == 0 && s.budget_frozen == 0 && s.budget_debris == debris);
  ENSURE(s.budget_level == 0.0 && s.budget_restorations > 0);
}

// Raised well over the cost, the budget gives every tier back (a tier a
// second), but for debris lying still; turned off, everything at once; and
// a budget the shattering goes over but the settled heap does not lets go
// of its own.
static void test_fidelity_comes_back(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  for (int way = 0; way < 2; ++way) {
    bk_world* world = make_world(0.001, 0.008);
    add_cube(world, &tree, 0.0);
    shoot(world, 0.0);
    for (int step = 0; step < 60; ++step)
      bk_world_step(world);
    bk_world_stats s = bk_world_get_stats(world);
    ENSURE(s.budget_simplified + s.budget_frozen > 0 && s.budget_level > 3.0);
    ENSURE(!bk_world_set_physics_budget(world, -1.0) && !bk_world_set_physics_budget(world, NAN));
    ENSURE(bk_world_set_physics_budget(world, way == 0 ? 1000.0 : 0.0));
    int steps = way == 0 ? 300 : 1;
    for (int step = 0; step < steps; ++step)
      bk_world_step(world);
    ensure_full_fidelity(world, way == 0);
    bk_world_destroy(world);
  }
  bk_world* world = make_world(1.0, 0.008);
  add_cube(world, &tree, 0.0);
  shoot(world, 0.0);
  double highest = 0.0;
  for (int step = 0; step < 600; ++step) {
    bk_world_step(world);
    highest = fmax(highest, bk_world_get_stats(world).budget_level);
  }
  ENSURE_MSG(highest > 3.0, "level %g", highest);
  ensure_full_fidelity(world, true);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

// Measured time instead of the estimate: it follows the clock, so no
// equality between runs, but a budget no step can meet is engaged all the same.
static void test_measured(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  bk_world_def wd = bk_default_world_def();
  wd.physics_budget_ms = 1e-6;
  wd.physics_budget_measured = true;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  add_cube(world, &tree, 0.0);
  shoot(world, 0.0);
  for (int step = 0; step < 60; ++step)
    bk_world_step(world);
  bk_world_stats s = bk_world_get_stats(world);
  ENSURE(s.budget_cost_ms == s.physics_ms && s.budget_level > 3.0 && demoted(s) + s.budget_retired > 0);
  bk_world_destroy(world);
  bk_mesh_tree_free(&tree);
}

static void test_bad_defs(void) {
  bk_world_def wd = bk_default_world_def();
  ENSURE(wd.physics_budget_ms == 8.0 && !wd.physics_budget_measured);
  ENSURE(wd.budget_large_volume == 0.008 && wd.budget_focus_radius == 2.0);
  wd.physics_budget_ms = -1.0;
  expect_refused(wd, "world: physics_budget_ms must be finite and >= 0 (got -1)");
  wd.physics_budget_ms = INFINITY;
  expect_refused(wd, "world: physics_budget_ms must be finite and >= 0 (got inf)");
  wd = bk_default_world_def();
  wd.budget_large_volume = 0.0;
  expect_refused(wd, "world: budget_large_volume must be a positive finite number (got 0)");
  wd = bk_default_world_def();
  wd.budget_focus_radius = NAN;
  expect_refused(wd, "world: budget_focus_radius must be finite and >= 0 (got nan)");
  wd = bk_default_world_def();
  ENSURE(wd.budget_fidelity_time == 1.0);
  wd.budget_fidelity_time = -0.5;
  expect_refused(wd, "world: budget_fidelity_time must be finite and >= 0 (got -0.5)");
  bk_world* world = make_world(8.0, 0.008);
  bk_vec3 focus = bk_v3(0, 0, 0);
  ENSURE(!bk_world_focus(world, &focus));
  bk_world_set_focus(world, bk_v3(NAN, 0, 0));
  ENSURE(!bk_world_focus(world, &focus));
  bk_world_destroy(world);
}

// ---------------------------------------------------------------- physics layer

static bk_body_id add_box(bk_physics* physics, bk_shape_id box, bk_vec3 at, bool debris) {
  bk_body_def bd = bk_default_body_def();
  ENSURE(bd.debris == false);
  bd.shape = box;
  bd.mass = 1.0;
  bd.inertia = bk_v3(0.01, 0.01, 0.01);
  bd.transform.position = at;
  bd.debris = debris;
  // Awake at rest: the broadphase then finds no new pair for a body unless
  // its box moves, which a body leaving debris must not wait for.
  bd.disable_sleep = debris;
  bk_error err = {0};
  bk_body_id body = bk_physics_create_body(physics, &bd, &err);
  ENSURE_MSG(!bk_body_is_null(body), "%s", err.message);
  return body;
}

static void run(bk_physics* physics, int steps) {
  for (int i = 0; i < steps; ++i)
    bk_physics_step(physics, 1.0 / 60.0, 1);
}

// Debris falls through debris but rests on the ground and on other bodies;
// taken out of debris while overlapping, the pair is found again and pushed apart.
static void test_debris_filter(void) {
  bk_physics_def pd = bk_default_physics_def();
  bk_physics* physics = bk_physics_create(&pd, NULL);
  bk_body_def gd = bk_default_body_def();
  gd.shape = bk_physics_create_plane(physics, bk_v3(0, 1, 0), 0.0);
  ENSURE(!bk_body_is_null(bk_physics_create_body(physics, &gd, NULL)));
  bk_shape_id box = bk_physics_create_box(physics, bk_v3(0.1, 0.1, 0.1));
  // Two stacks: debris on debris (x = 0), debris on a plain body (x = 1).
  bk_body_id low = add_box(physics, box, bk_v3(0, 0.1, 0), true);
  bk_body_id high = add_box(physics, box, bk_v3(0, 0.35, 0), true);
  bk_body_id base = add_box(physics, box, bk_v3(1, 0.1, 0), false);
  bk_body_id top = add_box(physics, box, bk_v3(1, 0.35, 0), true);
  ENSURE(bk_physics_body_debris(physics, high) && !bk_physics_body_debris(physics, base));
  run(physics, 120);
  double y_low = bk_physics_body_transform(physics, low).position.y;
  double y_high = bk_physics_body_transform(physics, high).position.y;
  ENSURE_MSG(fabs(y_low - 0.1) < 0.01 && fabs(y_high - 0.1) < 0.01, "%g %g", y_low, y_high);
  ENSURE(fabs(bk_physics_body_transform(physics, top).position.y - 0.3) < 0.01);
  (void)base;
  // The two debris boxes now sit inside each other: one leaves debris.
  bk_physics_body_set_debris(physics, high, false);
  ENSURE(!bk_physics_body_debris(physics, high));
  run(physics, 60);
  bk_vec3 a = bk_physics_body_transform(physics, low).position;
  bk_vec3 b = bk_physics_body_transform(physics, high).position;
  double apart = fmax(fabs(a.x - b.x), fmax(fabs(a.y - b.y), fabs(a.z - b.z)));
  ENSURE_MSG(apart > 0.15, "still %g apart", apart);
  bk_physics_destroy(physics);
}

// Pinned, a body stays where it is under gravity and impulses; unpinned, it
// falls. Given a sphere for a shape, it rests at the sphere's radius.
static void test_pin_and_shape(void) {
  bk_physics_def pd = bk_default_physics_def();
  bk_physics* physics = bk_physics_create(&pd, NULL);
  bk_body_def gd = bk_default_body_def();
  gd.shape = bk_physics_create_plane(physics, bk_v3(0, 1, 0), 0.0);
  bk_physics_create_body(physics, &gd, NULL);
  bk_shape_id box = bk_physics_create_box(physics, bk_v3(0.1, 0.1, 0.1));
  bk_body_id body = add_box(physics, box, bk_v3(0, 2, 0), false);
  bk_body_id pusher = add_box(physics, box, bk_v3(0.15, 2.5, 0), false);
  bk_physics_body_set_pinned(physics, body, true);
  ENSURE(bk_physics_body_pinned(physics, body) && !bk_physics_body_awake(physics, body));
  bk_physics_body_apply_impulse(physics, body, bk_v3(0, 5, 0), bk_v3(0, 2, 0));
  bk_physics_body_set_velocity(physics, body, bk_v3(1, 0, 0), bk_v3(0, 0, 0));
  run(physics, 60); // the other box lands on it and slides off
  ENSURE(bk_physics_body_transform(physics, body).position.y == 2.0);
  ENSURE(bk_physics_body_transform(physics, pusher).position.y < 2.0);
  ENSURE(bk_physics_body_mass(physics, body) == 1.0);
  bk_physics_body_set_pinned(physics, body, false);
  ENSURE(!bk_physics_body_pinned(physics, body));
  bk_shape_id sphere = bk_physics_create_sphere(physics, 0.25);
  ENSURE(bk_physics_body_set_shape(physics, body, sphere));
  ENSURE(bk_physics_body_shape(physics, body).index == sphere.index);
  ENSURE(!bk_physics_body_set_shape(physics, body, bk_physics_create_plane(physics, bk_v3(0, 1, 0), 1.0)));
  run(physics, 180);
  ENSURE_MSG(fabs(bk_physics_body_transform(physics, body).position.y - 0.25) < 0.01, "%g",
             bk_physics_body_transform(physics, body).position.y);
  // The box, no longer used by it, can be given back.
  ENSURE(bk_physics_body_set_shape(physics, body, box));
  run(physics, 120);
  ENSURE(fabs(bk_physics_body_transform(physics, body).position.y - 0.1) < 0.01);
  bk_physics_destroy(physics);
}

// A body resting on the ground as a compound, given a sphere inside its old
// bounds (so the broadphase sees no change): the pair's compound algorithm
// goes with the old shape, and the sphere rests on its radius (Bullet picks
// a pair's algorithm by its shapes' kinds when they meet, and a compound's
// would read the sphere as a compound).
static void test_compound_to_sphere(void) {
  bk_physics_def pd = bk_default_physics_def();
  bk_physics* physics = bk_physics_create(&pd, NULL);
  bk_body_def gd = bk_default_body_def();
  gd.shape = bk_physics_create_plane(physics, bk_v3(0, 1, 0), 0.0);
  bk_physics_create_body(physics, &gd, NULL);
  bk_shape_id compound = bk_physics_create_compound(physics, 2);
  bk_shape_id box = bk_physics_create_box(physics, bk_v3(0.2, 0.05, 0.2));
  bk_physics_compound_add(physics, compound, box, (bk_transform){bk_v3(0, 0.05, 0), {0, 0, 0, 1}});
  bk_physics_compound_add(physics, compound, box, (bk_transform){bk_v3(0, -0.05, 0), {0, 0, 0, 1}});
  bk_body_id body = add_box(physics, compound, bk_v3(0, 0.1, 0), true); // awake: its pair keeps its algorithm
  run(physics, 30);
  ENSURE(fabs(bk_physics_body_transform(physics, body).position.y - 0.1) < 0.01);
  ENSURE(bk_physics_body_set_shape(physics, body, bk_physics_create_sphere(physics, 0.08)));
  bk_physics_body_set_velocity(physics, body, bk_v3(0, 0, 0), bk_v3(0, 0, 0)); // awake
  run(physics, 120);
  ENSURE_MSG(fabs(bk_physics_body_transform(physics, body).position.y - 0.08) < 0.005, "%g",
             bk_physics_body_transform(physics, body).position.y);
  bk_physics_destroy(physics);
}

int main(void) {
  RUN(test_debris_filter);
  RUN(test_pin_and_shape);
  RUN(test_compound_to_sphere);
  RUN(test_bad_defs);
  RUN(test_off_changes_nothing);
  RUN(test_tiers_in_order);
  RUN(test_large_and_near_kept);
  RUN(test_mass_kept);
  RUN(test_deterministic);
  RUN(test_fidelity_comes_back);
  RUN(test_measured);
  return 0;
}
