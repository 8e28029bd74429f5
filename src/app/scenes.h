// scenes: the demo's scene table (what stands where, made of what, where
// shots aim). Data, not code paths.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/bullet.h>

// ---------------------------------------------------------------- scenes

/// One object of a scene.
typedef struct bk_scene_object {
  const char* mesh;     ///< a mesh name for bk_app-style loading (cube, wall, bunny, ...)
  bk_vec3 position;     ///< where the mesh's origin goes
  bk_vec3 axis;         ///< rotation axis (zero = none)
  double angle;         ///< radians
  double scale;         ///< uniform scale of the mesh (0 = 1)
  const char* material; ///< material preset name (physics)
  const char* look;     ///< how it is drawn (render material); NULL = same as material
  bool anchored;
} bk_scene_object;

/// A scene: data, not code paths.
typedef struct bk_scene {
  const char* name;
  const char* description;
  uint32_t pieces;    ///< default fragment count
  double aspect_bias; ///< fracture: tilt cuts across the long axis (bk_fracture_def.aspect_bias)
  bk_scene_object objects[8];
  uint32_t object_count;
  bk_vec3 eye, target; ///< camera and the point projectiles aim at
  /// More aim points (optional): a volley goes round target, then these, in turn.
  bk_vec3 extra_targets[7];
  uint32_t extra_target_count;
  double projectile_speed, projectile_radius, projectile_mass;
} bk_scene;

uint32_t bk_scene_count(void);
const bk_scene* bk_scene_at(uint32_t index);
const bk_scene* bk_scene_find(const char* name);
