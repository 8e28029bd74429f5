// A weight set down on a structure (--drop, the game's X key): a heavy ball
// put at rest on the top surface under a point, so that the structure
// carries it as a load (the world passes slow contacts to the stress solve)
// rather than taking it as a hit.
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "scene_run.h"

app_drop default_drop(void) { return (app_drop){.radius = BK_DROP_RADIUS_DEFAULT, .at = BK_DROP_AT_DEFAULT}; }

int parse_drop_option(const char* command, int argc, char** argv, int* i, app_drop* drop) {
  static const char* const names[] = {"--drop", "--drop-radius", "--drop-at"};
  const char* arg = argv[*i];
  const char* value = NULL;
  int which = take_option(command, argc, argv, i, names, 3, &value);
  if (which < 0) return which == -1 ? 1 : 2;
  bool ok = false;
  if (which == 0) {
    ok = option_double(command, arg, value, BK_DROP_KG_MIN, BK_DROP_KG_MAX, &drop->kg);
  } else if (which == 1) {
    drop->radius_given = true;
    ok = option_double(command, arg, value, BK_DROP_RADIUS_MIN, BK_DROP_RADIUS_MAX, &drop->radius);
  } else {
    drop->at_given = true;
    ok = option_u64(command, arg, value, 0, BK_DROP_AT_MAX, &drop->at);
  }
  return ok ? 0 : 2;
}

bool check_drop(const char* command, const app_drop* drop, uint64_t last, const char* last_option) {
  // Where and when mean nothing without a weight: refused, as a pattern's
  // options are without that pattern, so that a forgotten --drop is noticed.
  const char* orphan = drop->kg > 0.0       ? NULL
                       : drop->radius_given ? "--drop-radius"
                       : drop->at_given     ? "--drop-at"
                                            : NULL;
  if (orphan) {
    fprintf(stderr, "breakables %s: %s needs --drop KG (see 'breakables %s --help')\n", command, orphan,
            command);
    return false;
  }
  // A weight set after the run has ended would be silently missing from it.
  if (drop->kg > 0.0 && last > 0 && drop->at >= last) {
    fprintf(stderr, "breakables %s: --drop-at %llu%s is past the run's end (%s %llu)\n", command,
            (unsigned long long)drop->at, drop->at_given ? "" : " (the default)", last_option,
            (unsigned long long)last);
    return false;
  }
  return true;
}

// True when `body` is one of the breakables' bodies (not the ground, a shot
// or a weight).
static bool is_breakable_body(const bk_world* world, bk_body_id body) {
  uint32_t bodies = bk_world_body_count(world);
  for (uint32_t i = 0; i < bodies; ++i) {
    bk_body_view view = {0};
    if (bk_world_body_view(world, i, &view) && bk_body_equal(view.body, body)) return true;
  }
  return false;
}

bool app_top_surface(bk_world* world, bk_vec3 point, double height, bool breakables_only, bk_vec3* out) {
  // Straight down from high above the point: what a weight let go there
  // would land on first, whatever stands over the point itself.
  bk_vec3 from = {point.x, point.y + height, point.z}, to = {point.x, -1.0, point.z};
  bk_ray_hit hit = {0};
  if (!bk_physics_ray_cast(bk_world_physics(world), from, to, &hit)) return false;
  if (breakables_only && !is_breakable_body(world, hit.body)) return false;
  *out = hit.point;
  return true;
}

bool scene_drop_point(loaded_scene* s, bk_vec3* out) {
  if (s->tree_count == 0) return false;
  const scene_object* object = &s->scene->objects[0];
  bk_aabb box = s->trees[0].nodes[0].bounds;
  // From as far above the aim point as the object could reach, so that the
  // ray starts clear of it.
  double height = 2.0 * bk_v3_length(bk_v3_sub(box.max, box.min)) + 1.0;
  bk_vec3 aim = bk_v3_length(s->scene->drop_over) > 0.0 ? s->scene->drop_over : scene_object_aim(s->scene, 0);
  if (app_top_surface(s->world, aim, height, true, out)) return true;
  // An aim point beside the object (the showcase's is in front of the wall):
  // the object's middle in plan view instead.
  bk_transform placement = scene_object_def(object, &s->trees[0], NULL).breakable.transform;
  bk_vec3 middle = bk_transform_point(placement, bk_v3_scale(bk_v3_add(box.min, box.max), 0.5));
  return app_top_surface(s->world, (bk_vec3){middle.x, aim.y, middle.z}, height, true, out);
}

bool app_drop_weight(bk_world* world, bk_vec3 surface, double kg, double radius, bk_error* err) {
  // A few mm of air below it: a ball set into the surface would be pushed
  // out of it at speed, and one set higher would land as a hit.
  bk_projectile_def weight = {.position = {surface.x, surface.y + radius + 0.005, surface.z},
                              .velocity = {0.0, 0.0, 0.0},
                              .radius = radius,
                              .mass = kg,
                              .lifetime = INFINITY}; // it stays, as a weight does
  return !bk_body_is_null(bk_world_fire(world, &weight, err));
}
