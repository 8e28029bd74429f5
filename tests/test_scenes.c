// The demo's scene table.
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "ensure.h"
#include "scene_run.h"

// Scene data: every scene is findable by name, and a scene's extra aim
// points each lie by a different one of its objects (so a volley in the
// showcase goes round all of them).
static void test_scene_targets(void) {
  ENSURE(scene_count() >= 10);
  for (uint32_t i = 0; i < scene_count(); ++i) {
    const app_scene* scene = scene_at(i);
    ENSURE(scene_find(scene->name) == scene);
    ENSURE(scene->extra_target_count <= 7);
    bool used[8] = {false};
    for (uint32_t t = 0; t < scene->extra_target_count; ++t) {
      bk_vec3 aim = scene->extra_targets[t];
      int nearest = -1;
      double best = 1e30;
      for (uint32_t o = 0; o < scene->object_count; ++o) {
        bk_vec3 d = bk_v3_sub(aim, scene->objects[o].position);
        double horizontal = sqrt(d.x * d.x + d.z * d.z);
        if (horizontal < best) best = horizontal, nearest = (int)o;
      }
      ENSURE_MSG(nearest >= 0 && best < 0.6, "%s: aim point %u is %g m from any object", scene->name, t,
                 best);
      ENSURE_MSG(!used[nearest], "%s: two aim points at object %d", scene->name, nearest);
      used[nearest] = true;
    }
  }
  const app_scene* showcase = scene_find("showcase");
  ENSURE(showcase && showcase->extra_target_count + 1 == showcase->object_count);
}

// ---------------------------------------------------------------- structures

/// An object's mesh where it stands in the world (the scenes' structures are not turned).
static bk_mesh placed_source(const scene_object* object) {
  bk_mesh m = {0};
  ENSURE_MSG(scene_object_source(object, &m), "cannot load %s", object->mesh);
  ENSURE(bk_v3_length(object->axis) == 0.0);
  for (uint32_t i = 0; i < m.position_count; ++i)
    m.positions[i] = bk_v3_add(m.positions[i], object->position);
  return m;
}

/// Where the line from `origin` through `through` first meets the mesh
/// (Moller-Trumbore on every triangle); false when it misses.
static bool first_hit(const bk_mesh* m, bk_vec3 origin, bk_vec3 through, bk_vec3* hit) {
  bk_vec3 direction = bk_v3_sub(through, origin);
  double nearest = INFINITY;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
    bk_vec3 e1 = bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 1)], a);
    bk_vec3 e2 = bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 2)], a);
    bk_vec3 p = bk_v3_cross(direction, e2);
    double det = bk_v3_dot(e1, p);
    if (fabs(det) < 1e-300) continue;
    bk_vec3 s = bk_v3_sub(origin, a), q = bk_v3_cross(s, e1);
    double u = bk_v3_dot(s, p) / det, v = bk_v3_dot(direction, q) / det, along = bk_v3_dot(e2, q) / det;
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && along > 0.0 && along < nearest) nearest = along;
  }
  *hit = bk_v3_add(origin, bk_v3_scale(direction, nearest));
  return isfinite(nearest);
}

/// Where the game's camera starts: the scene's camera when it has one, else its eye.
static bk_vec3 camera_of(const app_scene* scene) {
  return bk_v3_length(scene->camera) > 0.0 ? scene->camera : scene->eye;
}

/// Whether every corner of the mesh is in the picture the scene opens
/// with, `margin` (a fraction of the half-size) inside its border: the
/// renderer's default camera, 60 degrees high, in the default 1280x720 window.
static bool in_view(const app_scene* scene, const bk_mesh* m, double margin) {
  bk_vec3 eye = camera_of(scene);
  bk_vec3 forward = bk_v3_normalize(bk_v3_sub(scene->target, eye));
  bk_vec3 right = bk_v3_normalize(bk_v3_cross(forward, bk_v3(0, 1, 0))), up = bk_v3_cross(right, forward);
  double half_height = tan(30.0 * 3.14159265358979 / 180.0), half_width = half_height * 1280.0 / 720.0;
  for (uint32_t i = 0; i < m->position_count; ++i) {
    bk_vec3 d = bk_v3_sub(m->positions[i], eye);
    double depth = bk_v3_dot(d, forward);
    if (!(depth > 0.0)) return false;
    if (fabs(bk_v3_dot(d, right)) / depth > (1.0 - margin) * half_width) return false;
    if (fabs(bk_v3_dot(d, up)) / depth > (1.0 - margin) * half_height) return false;
  }
  return true;
}

static bool box_contains(bk_aabb box, bk_vec3 p) {
  return p.x >= box.min.x && p.x <= box.max.x && p.y >= box.min.y && p.y <= box.max.y && p.z >= box.min.z &&
         p.z <= box.max.z;
}

/// The structures' shot: 8 kg at 40 m/s, 0.1 m across. (The wall scene's
/// are heavier: the bricks an 8 kg shot frees stay seated in the wall.)
static const double cannon_speed = 40.0, cannon_mass = 8.0, cannon_radius = 0.1;

/// One structure's scene: the structure alone, anchored, made of `material`,
/// broken radially round its aim point into 128 to 256 pieces by shots at
/// least as heavy as the cannon's; the whole of it in the opening
/// picture with room to spare; its aim point inside it and the first shot's
/// line landing on it.
static bk_vec3 check_structure(const char* name, const char* material) {
  const app_scene* scene = scene_find(name);
  ENSURE_MSG(scene != NULL, "no scene %s", name);
  ENSURE(scene->object_count == 1 && scene->extra_target_count == 0 && !scene->fit_to_mesh);
  const scene_object* o = &scene->objects[0];
  ENSURE(strcmp(o->mesh, name) == 0 && strcmp(o->material, material) == 0);
  ENSURE(o->anchored && o->pattern == BK_PATTERN_RADIAL);
  ENSURE(scene->pieces >= 128 && scene->pieces <= 256);
  ENSURE(scene->projectile_speed == cannon_speed && scene->projectile_radius >= cannon_radius &&
         scene->projectile_mass >= cannon_mass);
  bk_mesh m = placed_source(o);
  bk_aabb box = bk_mesh_bounds(&m);
  ENSURE_SMALL(box.min.y, 0.0, 1e-12); // stands on the ground, where it is anchored
  bk_vec3 camera = camera_of(scene);
  ENSURE_MSG(in_view(scene, &m, 0.1), "%s: not all in view from (%g, %g, %g)", name, camera.x, camera.y,
             camera.z);
  ENSURE(box_contains(box, scene->target) && !box_contains(box, scene->eye) && !box_contains(box, camera));
  bk_vec3 hit = {0};
  ENSURE_MSG(first_hit(&m, scene->eye, scene->target, &hit), "%s: the shots miss", name);
  fprintf(stderr, "    %s: the first shot's line lands at (%.2f, %.2f, %.2f)\n", name, hit.x, hit.y, hit.z);
  bk_mesh_free(&m);
  return hit;
}

static void test_structures(void) {
  // Each is shot by wrecking shots heavy enough to bring it down (the
  // cannon's leave the tower standing and only chip the bridge and the
  // balcony): the tower at its base at stone's own limits, the bridge and
  // the balcony in old concrete, whose limits they still stand at
  // untouched (tests/test_cli.c runs them).
  bk_vec3 tower = check_structure("tower", "stone");
  ENSURE(scene_find("tower")->target.y <= 0.5 && tower.y < 0.6);
  const char* structures[] = {"tower", "bridge", "balcony"};
  for (int i = 0; i < 3; ++i) {
    const app_scene* scene = scene_find(structures[i]);
    ENSURE(scene->projectile_mass >= 10.0 * cannon_mass);
    double scale = scene->objects[0].stress_scale;
    ENSURE_MSG(i == 0 ? scale == 0.0 : scale > 0.1 && scale < 1.0, "%s: limits x %g", structures[i], scale);
  }
  // The bridge on its deck (1.5 to 1.8 m up) half-way between its legs (inner faces at x = +-1.8).
  bk_vec3 bridge = check_structure("bridge", "concrete");
  ENSURE(bridge.y >= 1.5 - 1e-9 && fabs(bridge.x) < 0.5);
  // The balcony on its slab (1.8 to 2 m up), near the wall's face (z = 0.15): its root.
  bk_vec3 balcony = check_structure("balcony", "concrete");
  ENSURE(balcony.y >= 1.8 - 1e-9 && balcony.y <= 2.0 + 1e-9 && balcony.z >= 0.15 && balcony.z < 0.6);
}

// The showcase's tower: anchored, aimed at by its base, overlapping no
// other object (their bounds apart in plan view) and all in the picture.
static void test_showcase_tower(void) {
  const app_scene* showcase = scene_find("showcase");
  uint32_t tower = UINT32_MAX;
  for (uint32_t i = 0; i < showcase->object_count; ++i)
    if (strcmp(showcase->objects[i].mesh, "tower") == 0) tower = i;
  ENSURE(tower != UINT32_MAX && showcase->objects[tower].anchored);
  ENSURE(scene_object_aim(showcase, tower).y <= 0.5);
  bk_aabb boxes[8] = {{{0}}};
  for (uint32_t i = 0; i < showcase->object_count; ++i) {
    bk_mesh m = placed_source(&showcase->objects[i]);
    boxes[i] = bk_mesh_bounds(&m);
    if (i == tower) ENSURE(in_view(showcase, &m, 0.1));
    bk_mesh_free(&m);
  }
  for (uint32_t i = 0; i < showcase->object_count; ++i) {
    if (i == tower) continue;
    bool apart = boxes[i].max.x < boxes[tower].min.x || boxes[tower].max.x < boxes[i].min.x ||
                 boxes[i].max.z < boxes[tower].min.z || boxes[tower].max.z < boxes[i].min.z;
    ENSURE_MSG(apart, "the showcase's tower overlaps its %s", showcase->objects[i].mesh);
  }
}

// ---------------------------------------------------------------- framing

/// The game's scripted run of `frames` frames firing `shots` (as
/// `play --frames N --autofire K` times them, one step a frame); returns the
/// fragments freed, and in *out those knocked out of where they stood: more
/// than `out_distance` m from the plane z = 0 or fallen below y = `fallen_y`.
static uint32_t scripted_run(const char* name, uint32_t frames, uint32_t shots, double out_distance,
                             double fallen_y, uint32_t* out) {
  scene_options options = default_scene_options();
  loaded_scene loaded = {0};
  bk_error err = {0};
  ENSURE_MSG(loaded_scene_create(scene_find(name), &options, &loaded, &err), "%s", err.message);
  uint32_t fired = 0;
  for (uint32_t frame = 0; frame < frames; ++frame) {
    while (fired < shots && frame >= (fired + 1) * frames / (shots + 1)) {
      bk_projectile_def shot = scene_shot(loaded.scene, fired++, 0.0);
      bk_world_fire(loaded.world, &shot, NULL);
    }
    bk_world_step(loaded.world);
  }
  *out = 0;
  for (uint32_t i = 0; i < bk_world_body_count(loaded.world); ++i) {
    bk_body_view v = {0};
    if (!bk_world_body_view(loaded.world, i, &v) || v.leaf_count != 1) continue;
    bk_vec3 centroid = bk_mesh_tree_mass(v.tree, bk_mesh_tree_leaf(v.tree, v.leaves[0])->moments).centroid;
    bk_vec3 at = bk_transform_point(v.tree_to_world, centroid);
    *out += fabs(at.z) > out_distance || at.y < fallen_y;
  }
  uint32_t freed = bk_world_get_stats(loaded.world).fragments_free;
  loaded_scene_destroy(&loaded);
  return freed;
}

// The README's `play --scene wall --frames 82 --autofire 3` opens a hole:
// bricks are knocked out of the wall (0.2 m thick, centred on z = 0), not
// only loosened in place; and the game's camera is close enough for the
// wall to fill a good part of the picture.
static void test_wall_hole(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/scenes_cache", 1);
  uint32_t out = 0, freed = scripted_run("wall", 82, 3, 0.25, -1.0, &out);
  fprintf(stderr, "    wall, 3 shots: %u bricks freed, %u knocked out\n", freed, out);
  ENSURE_MSG(freed >= 10 && out >= 4, "%u bricks freed, %u knocked out", freed, out);
  const app_scene* wall = scene_find("wall");
  ENSURE(bk_v3_length(bk_v3_sub(camera_of(wall), wall->target)) < 2.6);
  bk_mesh m = placed_source(&wall->objects[0]);
  ENSURE(in_view(wall, &m, 0.3)); // all of it in view, well inside the border
  bk_mesh_free(&m);
}

// The slab (15 cm thick, on the ground) is shot from above into its top,
// not along the ground at its edge (those shots glanced off and bounced
// over it), and seen from near enough to make out the crater.
static void test_slab_framing(void) {
  const app_scene* slab = scene_find("slab");
  bk_mesh m = placed_source(&slab->objects[0]);
  bk_vec3 hit = {0};
  ENSURE(first_hit(&m, slab->eye, slab->target, &hit));
  bk_vec3 down = bk_v3_normalize(bk_v3_sub(slab->target, slab->eye));
  ENSURE_MSG(fabs(hit.y - 0.15) < 1e-9 && down.y < -0.7, "lands at y %g, coming down at %g", hit.y, down.y);
  ENSURE(bk_v3_length(bk_v3_sub(camera_of(slab), slab->target)) < 2.2 && in_view(slab, &m, 0.3));
  bk_mesh_free(&m);
}

int main(void) {
  RUN(test_scene_targets);
  RUN(test_wall_hole);
  RUN(test_slab_framing);
  RUN(test_structures);
  RUN(test_showcase_tower);
  return 0;
}
