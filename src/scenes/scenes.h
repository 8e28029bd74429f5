// scenes: the demo's scene table (what stands where, made of what, where
// shots aim). Data, not code paths.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/bullet.h>

// ---------------------------------------------------------------- scenes

/// One object of a scene.
typedef struct scene_object {
  const char* mesh;     ///< a mesh name for app_app-style loading (cube, wall, bunny, ...)
  bk_vec3 position;     ///< where the mesh's origin goes
  bk_vec3 axis;         ///< rotation axis (zero = none)
  double angle;         ///< radians
  double scale;         ///< uniform scale of the mesh (0 = 1)
  const char* material; ///< material preset name (physics)
  const char* look;     ///< how it is drawn (render material); NULL = same as material
  /// Its material's three stress limits times this (0 = 1, as the preset
  /// has them): a structure that stands at its limits but gives way once
  /// the scene's shots cut into it. A --material preset replaces it.
  double stress_scale;
  bool anchored;
  /// How it breaks (zero = BK_PATTERN_PLANES). The parameters follow from the
  /// object: a brick bond lines up with its texture, a radial pattern centres
  /// on its aim point (scene_fracture_def).
  bk_fracture_pattern pattern;
} scene_object;

/// A scene: data, not code paths.
typedef struct app_scene {
  const char* name;
  const char* description;
  uint32_t pieces;    ///< default fragment count
  double aspect_bias; ///< fracture: tilt cuts across the long axis (bk_fracture_def.aspect_bias)
  scene_object objects[8];
  uint32_t object_count;
  bk_vec3 eye, target; ///< where projectiles come from (and the camera), and the point they aim at
  /// Where the game's camera starts instead, looking at the target (zero:
  /// at the eye): a view from the side of what the shots from the eye do.
  bk_vec3 camera;
  /// Where a weight (--drop, scene_drop_point) is set: on the top surface
  /// over this point (zero: over the first object's aim point, which may lie
  /// under some other part of it).
  bk_vec3 drop_over;
  /// More aim points (optional): a volley goes round target, then these, in turn.
  bk_vec3 extra_targets[7];
  uint32_t extra_target_count;
  double projectile_speed, projectile_radius, projectile_mass;
  /// How far apart later shots land round the target (m, the step of their
  /// spiral); 0: 0.12, the built-in scenes' (a user's model: by its size).
  double shot_spread;
  /// A user's model: its one object is placed centred on the ground and the
  /// camera, aim and projectiles are fitted to its size when it is loaded.
  bool fit_to_mesh;
} app_scene;

uint32_t scene_count(void);
const app_scene* scene_at(uint32_t index);
const app_scene* scene_find(const char* name);
/// Adds a scene of one user model (a path to any model file, an .mtree or
/// one of our .glb exports) made of `material` (a preset name), named after
/// the file; returns its index, or UINT32_MAX (err set) if the material is
/// unknown, the path too long or the table of user scenes full.
uint32_t scene_add_mesh(const char* path, const char* material, bk_error* err);
/// True for a preset name; else err lists the presets.
bool scene_check_material(const char* material, bk_error* err);
/// The fracture pattern called `name` (as bk_fracture_pattern_name spells
/// it); false with err saying "unknown pattern 'NAME': use planes, ..." (one line).
bool scene_pattern_from_name(const char* name, bk_fracture_pattern* pattern, bk_error* err);
/// The aim point of object `object`: of the scene's target and extra
/// targets, the one nearest to where the object stands (world coordinates).
bk_vec3 scene_object_aim(const app_scene* scene, uint32_t object);
/// What a command's --scene NAME (scene_given: it was on the command line),
/// --mesh PATH and --material NAME choose: a scene's index, or UINT32_MAX
/// with err saying which option is wrong (one line, for the command to print).
uint32_t scene_resolve(const char* scene_name, bool scene_given, const char* mesh, const char* material,
                       bk_error* err);
/// Fits a fit_to_mesh scene to its loaded object's bounds (in the tree frame)
/// into `out`: the object stands centred on the ground, the camera looks at
/// it from the front, projectiles are sized to it (their radius, speed and
/// spread; scene_fit_shots gives them their mass).
void scene_fit(const app_scene* scene, bk_aabb bounds, app_scene* out);
/// Gives a fitted scene's shots the weight to break its object, whatever its
/// size: the impulse that breaks the bonds nearest where the first shot
/// lands (the damage formula's own terms: `material`, the bonds' areas and
/// distances, `world`'s damage_min_distance), twice over, from a ball of
/// 0.1% to 10% of the object's mass (faster than scene_fit's speed when
/// even 10% is too light). Lowers `world`'s impulse threshold and impact
/// speed to a quarter of such a shot's where they would ignore it (a
/// pebble's shots carry less than the defaults).
void scene_fit_shots(app_scene* scene, const bk_mesh_tree* tree, const bk_material* material,
                     bk_world_def* world);
/// The nearest point where the ray from `origin` along `direction` enters
/// or leaves the mesh; false when it misses.
bool scene_first_hit(const bk_mesh* mesh, bk_vec3 origin, bk_vec3 direction, bk_vec3* hit);
