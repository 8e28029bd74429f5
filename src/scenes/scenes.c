// The scene table: what stands where, made of what, and where shots aim.
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "scenes.h"

static const app_scene scenes[] = {
    {.name = "wall",
     .aspect_bias = 1.5,
     .description = "a brick wall anchored to the ground",
     // One piece per brick of its texture (2 x 1.2 m of 0.25 x 0.125 m bricks:
     // ten courses, five of 8 bricks and five of 7 and two halves), so the
     // brick pattern cuts along the mortar only and a hole opens brick by
     // brick. The showcase's wall has the showcase's 256: its bricks break too.
     .pieces = 85,
     .objects = {{.mesh = "wall",
                  .material = "stone",
                  .look = "brick",
                  .anchored = true,
                  .pattern = BK_PATTERN_BRICK}},
     .object_count = 1,
     .eye = {1.3, 1.2, 3.1},
     .target = {0.0, 0.6, 0.0},
     // Nearer and more head on than the shots, so that the hole fills the
     // middle of the picture.
     .camera = {0.5, 1.0, 2.3},
     // A 40 kg stone ball: an 8 kg one frees a brick or three a shot, which
     // stay seated in the wall (three shots left one gap); three of these
     // free about 16 and knock 5 clean out (tests/test_scenes.c).
     .projectile_speed = 40.0,
     .projectile_radius = 0.14,
     .projectile_mass = 40.0},
    {.name = "eggshell",
     .description = "a porcelain eggshell resting on the ground",
     .pieces = 128,
     .objects = {{.mesh = "eggshell", .material = "porcelain", .pattern = BK_PATTERN_VORONOI}},
     .object_count = 1,
     .eye = {0.0, 0.5, 1.8},
     .target = {0.0, 0.3, 0.0},
     .camera = {0.45, 0.6, 1.1}, // near: the egg is 0.6 m tall
     .projectile_speed = 15.0,
     .projectile_radius = 0.04,
     .projectile_mass = 0.3},
    {.name = "pillar",
     .aspect_bias = 1.5,
     .description = "a free-standing stone pillar",
     .pieces = 128,
     .objects = {{.mesh = "pillar", .material = "stone", .pattern = BK_PATTERN_CLUSTERED}},
     .object_count = 1,
     .eye = {0.0, 1.5, 4.0},
     .target = {0.0, 1.2, 0.0},
     .camera = {1.1, 1.4, 2.4}, // the notch the shots bite, from a little aside
     .projectile_speed = 40.0,
     .projectile_radius = 0.1,
     .projectile_mass = 8.0},
    {.name = "slab",
     .aspect_bias = 1.5,
     .description = "a concrete slab lying on the ground",
     .pieces = 128,
     .objects = {{.mesh = "slab", .material = "concrete"}},
     .object_count = 1,
     // From above, into its top: shots along the ground at its 15 cm edge
     // glanced off and bounced over it, leaving a crack.
     .eye = {0.0, 2.6, 1.6},
     .target = {0.0, 0.1, 0.0},
     .camera = {1.1, 0.85, 1.6}, // near enough to see the crater (from 2.9 m it was a speck)
     .projectile_speed = 35.0,
     // A 40 kg steel ball: three of the 8 kg ones freed chips round one
     // crater and left the slab whole (one body), its crack hidden in the
     // dust; three of these split it into two to five parts for each
     // fracture seed tried (3000, 1, 2).
     .projectile_radius = 0.11,
     .projectile_mass = 40.0},
    {.name = "bunny",
     .description = "a glass Stanford bunny",
     .pieces = 128,
     .objects = {{.mesh = "bunny", .material = "glass", .pattern = BK_PATTERN_RADIAL}},
     .object_count = 1,
     .eye = {0.0, 0.6, 2.2},
     .target = {0.0, 0.45, 0.0},
     .projectile_speed = 25.0,
     .projectile_radius = 0.06,
     .projectile_mass = 1.0},
    {.name = "torus",
     .description = "a porcelain ring standing on its rim",
     .pieces = 128,
     .objects = {{.mesh = "torus",
                  .position = {0.0, 1.35, 0.0},
                  .axis = {1, 0, 0},
                  .angle = 1.5707963267948966,
                  .material = "porcelain",
                  .anchored = true,
                  // Small pieces round the aim point: with the planes' 128
                  // even slices (27 cm across) two shots freed one piece.
                  .pattern = BK_PATTERN_RADIAL}},
     .object_count = 1,
     .eye = {0.0, 1.4, 4.0},
     .target = {0.0, 2.3, 0.0},
     .camera = {1.5, 1.7, 3.3}, // from aside, so the broken top shows its depth
     .projectile_speed = 50.0,
     .projectile_radius = 0.14,
     .projectile_mass = 20.0},
    {.name = "showcase",
     .description = "a brick wall, a pillar, a slab, a glass bunny, a porcelain eggshell and a stone tower",
     .aspect_bias = 1.5,
     .pieces = 256,
     .objects = {{.mesh = "wall",
                  .position = {0.0, 0.0, -1.0},
                  .material = "stone",
                  .look = "brick",
                  .anchored = true,
                  .pattern = BK_PATTERN_BRICK},
                 {.mesh = "pillar",
                  .position = {-2.2, 0.0, 0.2},
                  .material = "stone",
                  .pattern = BK_PATTERN_CLUSTERED},
                 {.mesh = "slab", .position = {2.0, 0.0, 0.6}, .material = "concrete"},
                 {.mesh = "bunny",
                  .position = {1.6, 0.15, 0.5},
                  .scale = 0.8,
                  .material = "glass",
                  .pattern = BK_PATTERN_RADIAL},
                 {.mesh = "eggshell",
                  .position = {-0.9, 0.0, 1.0},
                  .material = "porcelain",
                  .pattern = BK_PATTERN_VORONOI},
                 // Back right, clear of the wall and behind the low slab, so
                 // that nothing hides it and it has room to topple; 3.2 m
                 // tall, so that its top stays clear of the picture's edge.
                 {.mesh = "tower",
                  .position = {3.0, 0.0, -1.5},
                  .scale = 0.8,
                  .material = "stone",
                  .anchored = true,
                  .pattern = BK_PATTERN_RADIAL}},
     .object_count = 6,
     .eye = {0.0, 1.6, 5.5},
     .target = {0.0, 0.7, -0.6},
     // Volleys go round the objects: the wall, the pillar, the bunny, the
     // egg, the slab, the tower's base.
     .extra_targets =
         {{-2.2, 1.1, 0.2}, {1.6, 0.45, 0.5}, {-0.9, 0.35, 1.0}, {2.4, 0.1, 0.9}, {3.0, 0.4, -1.5}},
     .extra_target_count = 5,
     // 8 kg at 40 m/s: at 35 m/s and 6 kg the freed bricks of the wall
     // stayed seated in it, and the wall looked unhurt. (20 kg shots open a
     // wide hole and topple the tower, but leave so much moving debris that
     // the last second of a 480-frame, 20-shot volley cost 3x the physics.)
     .projectile_speed = 40.0,
     .projectile_radius = 0.09,
     .projectile_mass = 8.0},
    // The structures: each anchored where it stands on the ground, so that
    // a part whose support is shot away is held by nothing else. Wrecking
    // shots of 100 kg at 40 m/s (the showcase's 8 kg ones chip them). They break
    // radially round where those shots land (the base, the deck's middle,
    // the slab's root), coarser away from it: a 0.25 m Voronoi cell of
    // stone or concrete is too strong for them (`sim --shots 6` freed no
    // fragment of the bridge in even Voronoi cells or clustered chunks, at
    // 192 or 256 pieces; radially, 29 and 41), and what stands away from
    // the hole falls in large pieces.
    {.name = "tower",
     .aspect_bias = 1.5, // a planes override (--pattern) cuts chunks, not slivers
     .description = "a stone tower anchored to the ground, to topple by its base",
     .pieces = 192,
     .objects = {{.mesh = "tower", .material = "stone", .anchored = true, .pattern = BK_PATTERN_RADIAL}},
     .object_count = 1,
     // Straight in front, so that each shot bites into the same face: the
     // notch goes past the middle of the base, the weight above it hangs
     // off the stone left behind, bends it past what stone holds in tension
     // and the tower tips into the notch, towards the eye. From off to the
     // side, at (3, 1.2, 7.8), the same shots toppled it for none of six
     // fracture seeds.
     .eye = {0.0, 1.6, 8.0},
     .target = {0.0, 0.4, 0.0}, // the base: what holds the rest up
     // Off to the side, so that the tower is seen falling, not coming head on.
     .camera = {6.0, 2.0, 6.0},
     .projectile_speed = 40.0,
     // A wrecking shot: three of the wall's 8 kg balls leave a shallow
     // crater and the tower standing, the stress in what is left far below
     // stone's limits. Three 100 kg shots topple it for every fracture seed
     // tried (3000 and 1 to 11; the first shot alone for 7 of them; three
     // 60 kg shots for 3).
     .projectile_radius = 0.15,
     .projectile_mass = 100.0},
    {.name = "bridge",
     .aspect_bias = 1.5,
     .description = "a concrete bridge, a deck on two legs anchored to the ground",
     .pieces = 256,
     // Old concrete, its limits at 22%: the bridge still carries itself
     // and 500 kg on its deck (1 t breaks it; at 18% it falls under its own
     // weight for seeds 3000 and 1 to 3, at 20% for seed 3, and at 22% seed
     // 2 cracks 5 bonds and stands), but not once the shots have cut its
     // deck through (it falls for seeds 3000 and 1 to 5). At concrete's own
     // limits each half of a deck cut at mid-span stands on its leg as a
     // cantilever, and at 24% seed 4 still stood.
     .objects = {{.mesh = "bridge",
                  .material = "concrete",
                  .stress_scale = 0.22,
                  .anchored = true,
                  .pattern = BK_PATTERN_RADIAL}},
     .object_count = 1,
     // From high over the deck, so that the shots spread across its 1.2 m
     // width (the spiral lies across the line of fire): from the front,
     // at (2, 3.4, 5), they holed its front half and the back half held.
     .eye = {0.5, 6.0, 1.0},
     .target = {0.0, 1.65, 0.0}, // the deck's middle, half-way between the legs
     .camera = {2.0, 3.4, 5.0},  // from the front and above: the whole span and both legs
     .shot_spread = 0.4,
     .projectile_speed = 40.0,
     // The tower's wrecking shot: three 8 kg balls chipped the deck (14
     // fragments fell) and left it whole.
     .projectile_radius = 0.15,
     .projectile_mass = 100.0},
    {.name = "balcony",
     .aspect_bias = 1.5,
     .description = "a concrete balcony: a slab reaching out of a wall anchored to the ground",
     .pieces = 256,
     // Old concrete, its limits at 40%: the slab's root still carries the
     // slab (it gives way at 30% for seed 3000, holds at 35% for 3000 and
     // 1 to 3), but not once the shots have cut into it. At concrete's own
     // limits the slab stands on what the shots leave of its root.
     .objects = {{.mesh = "balcony",
                  .material = "concrete",
                  .stress_scale = 0.4,
                  .anchored = true,
                  .pattern = BK_PATTERN_RADIAL}},
     .object_count = 1,
     .eye = {3.4, 3.4, 3.6},
     .target = {0.0, 1.9, 0.15}, // the slab's root, where it leaves the wall's face
     // Over the slab's outer part: straight over its root is the wall's top.
     .drop_over = {0.0, 2.0, 1.0},
     .projectile_speed = 40.0,
     // The tower's wrecking shot: 8 kg balls raised dust at the root and
     // freed a few chips (no fragment fell).
     .projectile_radius = 0.15,
     .projectile_mass = 100.0},
};

enum { BUILT_IN = sizeof scenes / sizeof *scenes, USER_SCENES_MAX = 8, USER_PATH_MAX = 4096 };

// Scenes of users' models, added at run time (--mesh, the editor).
static struct {
  app_scene scene;
  char path[USER_PATH_MAX];
  char name[64];
  char material[BK_MATERIAL_NAME_MAX + 1];
} user_scenes[USER_SCENES_MAX];
static uint32_t user_scene_count;

uint32_t scene_count(void) { return BUILT_IN + user_scene_count; }

const app_scene* scene_at(uint32_t index) {
  if (index < BUILT_IN) return &scenes[index];
  return index < scene_count() ? &user_scenes[index - BUILT_IN].scene : NULL;
}

bool scene_check_material(const char* material, bk_error* err) {
  if (bk_material_find(material)) return true;
  char names[200] = {0};
  for (uint32_t i = 0; i < bk_material_count(); ++i)
    snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? ", " : "",
             bk_material_at(i)->name);
  return bk_error_set(err, "unknown material '%s': use %s", material, names);
}

bool scene_pattern_from_name(const char* name, bk_fracture_pattern* pattern, bk_error* err) {
  if (bk_fracture_pattern_from_name(name, pattern)) return true;
  char names[200] = {0};
  size_t used = 0;
  for (uint32_t i = 0; i < BK_PATTERN_COUNT; ++i)
    used = append_name(names, sizeof names, used, i, BK_PATTERN_COUNT,
                       bk_fracture_pattern_name((bk_fracture_pattern)i));
  return bk_error_set(err, "unknown pattern '%s': use %s", name, names);
}

bk_vec3 scene_object_aim(const app_scene* scene, uint32_t object) {
  // Each aim point stands over its object (a volley goes round the objects),
  // at whatever height: the one nearest in plan view is the object's own.
  bk_vec3 at = scene->objects[object].position, best = scene->target;
  double nearest = hypot(best.x - at.x, best.z - at.z);
  for (uint32_t i = 0; i < scene->extra_target_count; ++i) {
    bk_vec3 aim = scene->extra_targets[i];
    double d = hypot(aim.x - at.x, aim.z - at.z);
    if (d < nearest) nearest = d, best = aim;
  }
  return best;
}

uint32_t scene_resolve(const char* scene_name, bool scene_given, const char* mesh, const char* material,
                       bk_error* err) {
  if (mesh && scene_given) return bk_error_set(err, "--mesh and --scene cannot be used together"), UINT32_MAX;
  if (material && !scene_check_material(material, err)) return UINT32_MAX;
  if (mesh) return scene_add_mesh(mesh, material ? material : "stone", err);
  for (uint32_t i = 0; i < BUILT_IN; ++i)
    if (strcmp(scenes[i].name, scene_name) == 0) return i;
  char names[200] = {0};
  size_t used = 0;
  for (uint32_t i = 0; i < BUILT_IN; ++i)
    used = append_name(names, sizeof names, used, i, BUILT_IN, scenes[i].name);
  return bk_error_set(err, "unknown scene '%s': use %s", scene_name, names), UINT32_MAX;
}

uint32_t scene_add_mesh(const char* path, const char* material, bk_error* err) {
  if (!scene_check_material(material, err)) return UINT32_MAX;
  if (strlen(path) >= USER_PATH_MAX) return bk_error_set(err, "mesh path too long"), UINT32_MAX;
  if (user_scene_count == USER_SCENES_MAX)
    return bk_error_set(err, "at most %d models at once", USER_SCENES_MAX), UINT32_MAX;
  uint32_t i = user_scene_count++;
  snprintf(user_scenes[i].path, USER_PATH_MAX, "%s", path);
  const char* base = strrchr(path, '/');
  snprintf(user_scenes[i].name, sizeof user_scenes[i].name, "%s", base ? base + 1 : path);
  snprintf(user_scenes[i].material, sizeof user_scenes[i].material, "%s", material);
  user_scenes[i].scene =
      (app_scene){.name = user_scenes[i].name,
                  .description = "a model of yours",
                  .pieces = 256,
                  .aspect_bias = 1.5,
                  .objects = {{.mesh = user_scenes[i].path, .material = user_scenes[i].material}},
                  .object_count = 1,
                  .fit_to_mesh = true};
  // Until it is loaded: a unit object at the origin.
  scene_fit(&user_scenes[i].scene, (bk_aabb){{-0.5, 0, -0.5}, {0.5, 1, 0.5}}, &user_scenes[i].scene);
  return BUILT_IN + i;
}

void scene_fit(const app_scene* scene, bk_aabb bounds, app_scene* out) {
  *out = *scene;
  bk_vec3 size = bk_v3_sub(bounds.max, bounds.min);
  double extent = fmax(size.x, fmax(size.y, size.z));
  if (!(extent > 0.0) || !isfinite(extent)) extent = 1.0;
  // Centred over the origin, standing on y = 0.
  bk_vec3 offset =
      bk_v3(-0.5 * (bounds.min.x + bounds.max.x), -bounds.min.y, -0.5 * (bounds.min.z + bounds.max.z));
  out->objects[0].position = offset;
  out->objects[0].scale = 0.0;
  out->target = bk_v3(0.0, 0.5 * size.y, 0.0);
  out->eye = bk_v3_add(out->target, bk_v3_scale(bk_v3(0.35, 0.3, 1.0), 2.2 * extent));
  // A ball a twentieth of the object, as heavy as steel of that size until
  // scene_fit_shots weighs it. Its speed grows with the root of the
  // size, so that its flight takes the same share of the object's own
  // time to fall and its drop under gravity the same share of the object
  // (30 m/s at 1 m: it drops 3% of the object on the way), and the later
  // shots spread in proportion.
  out->projectile_radius = fmin(fmax(0.05 * extent, 0.002), 10.0);
  double r = out->projectile_radius;
  out->projectile_mass = 4.0 / 3.0 * 3.14159265358979 * r * r * r * 7800.0;
  out->projectile_speed = fmin(fmax(30.0 * sqrt(extent), 3.0), 300.0);
  out->shot_spread = 0.03 * extent;
}

const app_scene* scene_find(const char* name) {
  // Through scene_at: past the built-in table come the users' scenes.
  for (uint32_t i = 0; i < scene_count(); ++i)
    if (strcmp(scene_at(i)->name, name) == 0) return scene_at(i);
  return NULL;
}
