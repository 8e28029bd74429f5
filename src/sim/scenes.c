// The scene table: what stands where, made of what, and where shots aim.
#include <string.h>

#include "bk_sim.h"

static const bk_scene scenes[] = {
    {.name = "wall",
     .aspect_bias = 1.5,
     .description = "a stone wall anchored to the ground",
     .pieces = 256,
     .objects = {{.mesh = "wall", .material = "stone", .anchored = true}},
     .object_count = 1,
     .eye = {0.0, 1.2, 5.0},
     .target = {0.0, 0.6, 0.0},
     .projectile_speed = 40.0,
     .projectile_radius = 0.1,
     .projectile_mass = 8.0},
    {.name = "eggshell",
     .description = "a porcelain eggshell resting on the ground",
     .pieces = 128,
     .objects = {{.mesh = "eggshell", .material = "porcelain"}},
     .object_count = 1,
     .eye = {0.0, 0.5, 1.8},
     .target = {0.0, 0.3, 0.0},
     .projectile_speed = 15.0,
     .projectile_radius = 0.04,
     .projectile_mass = 0.3},
    {.name = "pillar",
     .aspect_bias = 1.5,
     .description = "a free-standing stone pillar",
     .pieces = 128,
     .objects = {{.mesh = "pillar", .material = "stone"}},
     .object_count = 1,
     .eye = {0.0, 1.5, 4.0},
     .target = {0.0, 1.2, 0.0},
     .projectile_speed = 40.0,
     .projectile_radius = 0.1,
     .projectile_mass = 8.0},
    {.name = "slab",
     .aspect_bias = 1.5,
     .description = "a concrete slab lying on the ground",
     .pieces = 128,
     .objects = {{.mesh = "slab", .material = "concrete"}},
     .object_count = 1,
     .eye = {0.0, 1.5, 2.5},
     .target = {0.0, 0.1, 0.0},
     .projectile_speed = 35.0,
     .projectile_radius = 0.1,
     .projectile_mass = 8.0},
    {.name = "bunny",
     .description = "a glass Stanford bunny",
     .pieces = 128,
     .objects = {{.mesh = "bunny", .material = "glass"}},
     .object_count = 1,
     .eye = {0.0, 0.6, 2.2},
     .target = {0.0, 0.45, 0.0},
     .projectile_speed = 25.0,
     .projectile_radius = 0.06,
     .projectile_mass = 1.0},
    {.name = "torus",
     .description = "a stone ring standing on its rim",
     .pieces = 128,
     .objects = {{.mesh = "torus",
                  .position = {0.0, 1.35, 0.0},
                  .axis = {1, 0, 0},
                  .angle = 1.5707963267948966,
                  .material = "stone",
                  .anchored = true}},
     .object_count = 1,
     .eye = {0.0, 1.4, 4.0},
     .target = {0.0, 2.3, 0.0},
     .projectile_speed = 40.0,
     .projectile_radius = 0.1,
     .projectile_mass = 8.0},
};

uint32_t bk_scene_count(void) { return sizeof scenes / sizeof *scenes; }

const bk_scene* bk_scene_at(uint32_t index) { return index < bk_scene_count() ? &scenes[index] : NULL; }

const bk_scene* bk_scene_find(const char* name) {
  for (uint32_t i = 0; i < bk_scene_count(); ++i)
    if (strcmp(scenes[i].name, name) == 0) return &scenes[i];
  return NULL;
}
