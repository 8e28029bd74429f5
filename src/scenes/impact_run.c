// A measured impact: a scene's first object (or several side by side) hit by
// one projectile each, with step times before, during and after the break.
// Shared by `breakables bench` and the game panel's benchmark.
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "scene_run.h"

bool app_load_scene_tree(uint64_t seed, const app_scene* scene, uint32_t pieces, bk_mesh_tree* tree,
                         bk_error* err) {
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = seed;
  desc.aspect_bias = scene->aspect_bias;
  bool cached = false;
  return app_load_tree(scene->objects[0].mesh, scene->objects[0].scale, &desc, tree, &cached, err);
}

/// Adds the object as a breakable with its material, moved along x.
static bool add_object(bk_world* world, const scene_object* object, const bk_mesh_tree* tree, double x,
                       bool naive, bk_error* err) {
  bk_world_breakable_def desc = scene_object_def(object, tree, NULL);
  desc.breakable.transform.position.x += x;
  desc.naive = naive;
  return bk_world_add_breakable(world, &desc, err).generation != 0;
}

bool impact_run(const app_impact* setup, impact_result* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  bk_world_def world_desc = bk_default_world_def();
  // Every piece fully simulated, whatever the world's default: these runs
  // measure the cost of the breaks and of all they leave.
  world_desc.physics_budget_ms = 0.0;
  bk_world* world = bk_world_create(&world_desc, err);
  if (!world) return false;
  for (uint32_t i = 0; i < setup->copies; ++i) {
    if (!add_object(world, &setup->scene->objects[0], setup->tree,
                    copy_offset(i, setup->copies, BK_IMPACT_SPACING), setup->naive, err)) {
      bk_world_destroy(world);
      return false;
    }
  }
  uint32_t after = setup->steps_after > BK_IMPACT_STEADY_STEPS ? setup->steps_after : BK_IMPACT_STEADY_STEPS;
  uint32_t total = BK_IMPACT_STEADY_STEPS + after;
  double* step_ms = bk_alloc(sizeof(double) * total);
  for (uint32_t s = 0; s < total; ++s) {
    for (uint32_t i = 0; s == BK_IMPACT_STEADY_STEPS && i < setup->copies; ++i) {
      bk_projectile_def shot = scene_shot(setup->scene, 0, 0.0);
      shot.position.x += copy_offset(i, setup->copies, BK_IMPACT_SPACING);
      bk_world_fire(world, &shot, NULL);
    }
    bk_world_step(world);
    bk_world_stats st = bk_world_get_stats(world);
    step_ms[s] = st.step_ms;
    out->nan = out->nan || st.nan;
    if (s < BK_IMPACT_STEADY_STEPS) continue;
    out->hit_step_ms = fmax(out->hit_step_ms, st.step_ms);
    out->hit_physics_ms = fmax(out->hit_physics_ms, st.physics_ms);
    out->hit_break_ms = fmax(out->hit_break_ms, st.break_ms);
  }
  bk_world_stats end = bk_world_get_stats(world);
  out->bodies = end.bodies;
  out->colliders = end.colliders;
  // Each median sorts its range: the last steps first, then everything from the shot on.
  out->after_ms = app_median(step_ms + total - BK_IMPACT_STEADY_STEPS, BK_IMPACT_STEADY_STEPS);
  out->hit_median_ms = app_median(step_ms + BK_IMPACT_STEADY_STEPS, after);
  out->before_ms = app_median(step_ms, BK_IMPACT_STEADY_STEPS);
  free(step_ms);
  bk_world_destroy(world);
  return true;
}
