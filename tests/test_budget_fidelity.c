// What the player sees under the physics budget: for budget_fidelity_time
// after a piece comes loose, within budget_fidelity_radius of the focus,
// the mass and momentum of the loose pieces stay within 5% of the run
// without a budget; with no fidelity time, or beyond the radius, the budget
// may take them at once (and what they do changes). A frozen piece gives
// way under a heavy body.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "budget_cubes.h"

// What the player sees of the loose pieces over the first second after a
// hit, summed over its 60 steps, for each of the two cubes (by the side of
// x = 0 a body is on): the mass of every dynamic (non-projectile) body still
// simulated (frozen ones count), the sum of |m v| over them and the length
// of the sum of m v.
typedef struct seen {
  double mass, speed, momentum;
} seen;

typedef struct run {
  seen side[2];       // x < 0, x >= 0
  uint32_t demotions; // the budget did something
  double level;       // the highest it reached
} run;

typedef struct setup {
  double budget_ms, fidelity_time, fidelity_radius;
  double x[2];   // the cubes
  bk_vec3 focus; // where the player looks from
} setup;

static run watch_first_second(const bk_mesh_tree* tree, setup s) {
  bk_world_def wd = bk_default_world_def();
  wd.physics_budget_ms = s.budget_ms;
  wd.budget_large_volume = 0.008;
  wd.budget_fidelity_time = s.fidelity_time;
  wd.budget_fidelity_radius = s.fidelity_radius;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  ENSURE(bk_world_budget_fidelity_radius(world) == s.fidelity_radius);
  bk_world_set_focus(world, s.focus);
  for (int i = 0; i < 2; ++i)
    add_cube(world, tree, s.x[i]);
  for (int i = 0; i < 2; ++i)
    shoot(world, s.x[i]);
  run out = {0};
  for (int step = 0; step < 60; ++step) {
    bk_world_step(world);
    bk_vec3 sum[2] = {bk_v3(0, 0, 0), bk_v3(0, 0, 0)};
    for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
      bk_body_view view = {0};
      ENSURE(bk_world_body_view(world, i, &view));
      bk_cluster_info info = {0};
      ENSURE(bk_runtime_cluster(bk_world_runtime(world), view.cluster, &info));
      if (info.is_static) continue;
      bk_vec3 v = bk_physics_body_linear_velocity(bk_world_physics(world), view.body);
      int side = bk_physics_body_transform(bk_world_physics(world), view.body).position.x >= 0.0;
      out.side[side].mass += info.mass;
      out.side[side].speed += info.mass * bk_v3_length(v);
      sum[side] = bk_v3_add(sum[side], bk_v3_scale(v, info.mass));
    }
    for (int side = 0; side < 2; ++side)
      out.side[side].momentum += bk_v3_length(sum[side]);
    bk_world_stats st = bk_world_get_stats(world);
    out.level = fmax(out.level, st.budget_level);
    out.demotions = st.budget_demotions;
  }
  bk_world_destroy(world);
  return out;
}

// The largest relative difference of the three from the run without a budget.
static double seen_error(seen a, seen off) {
  return fmax(fabs(a.mass / off.mass - 1.0),
              fmax(fabs(a.speed / off.speed - 1.0), fabs(a.momentum / off.momentum - 1.0)));
}

static seen both(run r) {
  return (seen){r.side[0].mass + r.side[1].mass, r.side[0].speed + r.side[1].speed,
                r.side[0].momentum + r.side[1].momentum};
}

// Two glass cubes shattered side by side in front of the player: with
// budgets from far below the cost to about it, what the player sees over
// the first second stays within 5% of the run without a budget, and a
// bigger budget never makes it worse (within a percent: the runs are chaotic
// in their details). Without the fidelity time, the same budget lets the
// pile fall through itself.
static void test_fidelity_first_second(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  setup s = {.fidelity_time = 1.0, .fidelity_radius = 8.0, .x = {-0.6, 0.6}, .focus = bk_v3(0.8, 1.1, 3.0)};
  seen off = both(watch_first_second(&tree, s));
  ENSURE(off.mass > 0.0 && off.speed > 0.0 && off.momentum > 0.0);
  double budgets[3] = {0.05, 0.3, 1.0};
  double last_error = INFINITY;
  for (int i = 0; i < 3; ++i) {
    s.budget_ms = budgets[i];
    run r = watch_first_second(&tree, s);
    seen on = both(r);
    double error = seen_error(on, off);
    ENSURE_MSG(r.demotions > 0 && r.level > 0.0, "budget %g never engaged", budgets[i]);
    ENSURE_MSG(error < 0.05, "budget %g: mass %.3f, sum |mv| %.3f, |sum mv| %.3f of the run without",
               budgets[i], on.mass / off.mass, on.speed / off.speed, on.momentum / off.momentum);
    ENSURE_MSG(error <= last_error + 0.01, "budget %g: %.3f off, worse than %.3f at a smaller one",
               budgets[i], error, last_error);
    last_error = error;
  }
  s.budget_ms = 0.05;
  s.fidelity_time = 0.0;
  seen fair_game = both(watch_first_second(&tree, s));
  ENSURE_MSG(seen_error(fair_game, off) > 0.05, "without the fidelity time: %.3f",
             seen_error(fair_game, off));
  bk_mesh_tree_free(&tree);
}

// The player in front of one cube, another 10 m away: at a radius of 5 m
// the near cube keeps its first second and the far one does not; at 20 m
// both keep it.
static void test_fidelity_radius(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  setup s = {.fidelity_time = 1.0, .fidelity_radius = 5.0, .x = {-5.0, 5.0}, .focus = bk_v3(-4.2, 1.1, 3.0)};
  run off = watch_first_second(&tree, s);
  s.budget_ms = 0.05;
  run near_only = watch_first_second(&tree, s);
  ENSURE(near_only.demotions > 0);
  double near_error = seen_error(near_only.side[0], off.side[0]);
  double far_error = seen_error(near_only.side[1], off.side[1]);
  ENSURE_MSG(near_error < 0.05, "the cube near the focus is %.3f off", near_error);
  ENSURE_MSG(far_error > 0.05, "the cube beyond the radius is only %.3f off: it kept its first second",
             far_error);
  s.fidelity_radius = 20.0;
  run everywhere = watch_first_second(&tree, s);
  for (int side = 0; side < 2; ++side)
    ENSURE_MSG(seen_error(everywhere.side[side], off.side[side]) < 0.05,
               "cube %d is %.3f off at a 20 m radius", side,
               seen_error(everywhere.side[side], off.side[side]));
  bk_mesh_tree_free(&tree);
}

static void test_bad_radius(void) {
  bk_world_def wd = bk_default_world_def();
  ENSURE(wd.budget_fidelity_radius == 8.0);
  wd.budget_fidelity_radius = -1.0;
  expect_refused(wd, "world: budget_fidelity_radius must be finite and >= 0 (got -1)");
  wd.budget_fidelity_radius = NAN;
  expect_refused(wd, "world: budget_fidelity_radius must be finite and >= 0 (got nan)");
  wd.budget_fidelity_radius = INFINITY;
  expect_refused(wd, "world: budget_fidelity_radius must be finite and >= 0 (got inf)");
}

// A frozen piece is pinned, of no mass to Bullet: a heavy ball set down
// gently on it (too slowly to shake it) must push it, not rest on it as on
// rock; pressed harder than a few times its own weight, it thaws. A ball as
// light as the piece, set down the same way, leaves it frozen. Returns
// whether the piece thawed within a third of a second.
static bool frozen_thaws_under(const bk_mesh_tree* tree, double weights) {
  bk_world_def wd = bk_default_world_def();
  wd.physics_budget_ms = 0.001;
  wd.budget_large_volume = 0.008;
  wd.budget_fidelity_time = 0.0;
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(world, "%s", err.message);
  bk_world_set_focus(world, bk_v3(100.0, 0.0, 0.0));
  add_cube(world, tree, 0.0);
  shoot(world, 0.0);
  for (int step = 0; step < 240; ++step)
    bk_world_step(world);
  // The heaviest frozen piece with nothing on it, and its top above its
  // centre.
  const bk_physics* physics = bk_world_physics(world);
  bk_body_id piece = {0, 0};
  double mass = 0.0;
  bk_ray_hit top = {0};
  for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
    bk_body_view view = {0};
    ENSURE(bk_world_body_view(world, i, &view));
    double m = bk_physics_body_mass(physics, view.body);
    if (view.tier != BK_TIER_FROZEN || m <= mass) continue;
    bk_vec3 center = bk_physics_body_transform(physics, view.body).position;
    bk_ray_hit hit = {0};
    if (!bk_physics_ray_cast(physics, bk_v3_add(center, bk_v3(0, 2, 0)), center, &hit) ||
        !bk_body_equal(hit.body, view.body))
      continue;
    piece = view.body, mass = m, top = hit;
  }
  ENSURE_MSG(mass > 0.0, "no frozen piece is uncovered");
  bk_projectile_def ball = bk_default_projectile_def();
  ball.radius = 0.1;
  ball.mass = weights * mass;
  ball.lifetime = INFINITY;
  ball.position = bk_v3_add(top.point, bk_v3(0, ball.radius + 0.001, 0));
  ENSURE_MSG(!bk_body_is_null(bk_world_fire(world, &ball, &err)), "%s", err.message);
  bool thawed = false;
  for (int step = 0; step < 20 && !thawed; ++step) {
    bk_world_step(world);
    for (uint32_t i = 0; i < bk_world_body_count(world); ++i) {
      bk_body_view view = {0};
      ENSURE(bk_world_body_view(world, i, &view));
      if (bk_body_equal(view.body, piece)) thawed = view.tier != BK_TIER_FROZEN;
    }
  }
  bk_world_destroy(world);
  return thawed;
}

static void test_frozen_gives_way(void) {
  bk_mesh_tree tree = make_cube_tree(256);
  ENSURE_MSG(frozen_thaws_under(&tree, 50.0), "a frozen piece held up a ball 50 times as heavy");
  ENSURE_MSG(!frozen_thaws_under(&tree, 1.0), "a ball as heavy as a frozen piece set it free");
  bk_mesh_tree_free(&tree);
}

int main(void) {
  RUN(test_bad_radius);
  RUN(test_fidelity_first_second);
  RUN(test_fidelity_radius);
  RUN(test_frozen_gives_way);
  fprintf(stderr, "test_budget_fidelity: all passed\n");
  return 0;
}
