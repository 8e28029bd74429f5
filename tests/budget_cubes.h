// Shared by the physics budget's tests: free glass cubes on the ground, as
// the benchmark's, the shot that shatters one, and a world definition that
// must be refused.
#ifndef BK_TESTS_BUDGET_CUBES_H
#define BK_TESTS_BUDGET_CUBES_H

#include <breakables/bullet.h>

#include <string.h>

#include "ensure.h"

static inline bk_mesh_tree make_cube_tree(uint32_t pieces) {
  bk_mesh mesh = {0};
  bk_shape_build(BK_SHAPE_CUBE, &mesh);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = 7;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &desc, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

// A free glass cube resting on the ground at x, as the benchmark's, made
// frail enough for one shot to shatter most of its 256 pieces.
static inline bk_breakable_id add_cube(bk_world* world, const bk_mesh_tree* tree, double x) {
  bk_world_breakable_def bd = bk_default_world_breakable_def();
  bd.breakable.tree = tree;
  bd.breakable.material = *bk_material_find("glass");
  bd.breakable.material.frailty *= 16.0;
  bd.breakable.transform.position = bk_v3(x, 0.5, 0.0);
  bk_error err = {0};
  bk_breakable_id id = bk_world_add_breakable(world, &bd, &err);
  ENSURE_MSG(!bk_breakable_is_null(id), "%s", err.message);
  return id;
}

// An 8 kg ball at 40 m/s into the cube at x, from the front and above.
static inline void shoot(bk_world* world, double x) {
  bk_projectile_def shot = bk_default_projectile_def();
  shot.position = bk_v3(x + 0.8, 1.1, 3.0);
  shot.velocity = bk_v3_scale(bk_v3_normalize(bk_v3(-0.8, -0.6, -3.0)), 40.0);
  shot.radius = 0.1;
  shot.mass = 8.0;
  bk_error err = {0};
  ENSURE_MSG(!bk_body_is_null(bk_world_fire(world, &shot, &err)), "%s", err.message);
}

// bk_world_create refuses wd with exactly this message.
static inline void expect_refused(bk_world_def wd, const char* message) {
  bk_error err = {0};
  bk_world* world = bk_world_create(&wd, &err);
  ENSURE_MSG(!world && strcmp(err.message, message) == 0, "got '%s'", err.message);
}

#endif
