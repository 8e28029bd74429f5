// The weight of the shots at a user's model. A bond breaks when
//   frailty x impulse / max(s, s_min)^3 > bond_strength x area
// (runtime damage), s its distance from the hit. A fixed ball scales as the
// model's mass (size^3) while what breaks a bond near the hit scales as its
// area times the cube of its distance (size^5): a shot that breaks a 5 m
// rock shatters a pebble, one that chips a pebble bounces off the rock. So
// the shot is weighed on the model itself: the impulse that breaks every
// bond of the piece it lands on. With the default 256 pieces of stone that
// holds from about 1.5 cm (smaller, every bond is within the runtime's
// s_min of the hit: the first shot shatters it) to about 25 m across
// (bigger, even a ball of a tenth of its mass at 2,000 m/s shoves it away
// before a piece comes loose).
#include <math.h>

#include "app.h"
#include "scene_run.h"

/// The shot carries this many times what they need: it may land beside the
/// aim, at a slant, its impulse comes in two or three contacts (Bullet
/// stops a fast ball over steps), and the object gives a little under it.
#define SHOT_MARGIN 4.0
/// The ball weighs this share of the object at least and at most (below,
/// it would look like a grain; above, it would shove the object away
/// instead of breaking it).
#define SHOT_MASS_MIN 0.001
#define SHOT_MASS_MAX 0.1
/// The fastest shot (m/s), for a model too big for the heaviest ball.
#define SHOT_SPEED_MAX 2000.0

// How far p lies outside box (0 inside).
static double box_distance(bk_aabb box, bk_vec3 p) {
  bk_vec3 out = bk_v3(fmax(fmax(box.min.x - p.x, p.x - box.max.x), 0.0),
                      fmax(fmax(box.min.y - p.y, p.y - box.max.y), 0.0),
                      fmax(fmax(box.min.z - p.z, p.z - box.max.z), 0.0));
  return bk_v3_length(out);
}

// The leaf the shot lands on: of those whose bounds hold `hit` (or come
// nearest to it), the one whose centroid is nearest.
static uint32_t hit_leaf(const bk_mesh_tree* tree, bk_vec3 hit) {
  uint32_t best = 0;
  double best_box = INFINITY, best_centroid = INFINITY;
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    const bk_mesh_tree_node* leaf = bk_mesh_tree_leaf(tree, l);
    double box = box_distance(leaf->bounds, hit);
    double centroid = bk_v3_length(bk_v3_sub(bk_mesh_tree_mass(tree, leaf->moments).centroid, hit));
    if (box < best_box || (box == best_box && centroid < best_centroid))
      best = l, best_box = box, best_centroid = centroid;
  }
  return best;
}

// The impulse that breaks every bond of the leaf the shot lands on with one
// hit (so that it comes loose), or 0 when nothing can break.
static double breaking_impulse(const bk_mesh_tree* tree, const bk_material* material, double s_min,
                               bk_vec3 hit) {
  if (tree->bond_count == 0 || !(material->frailty > 0.0)) return 0.0;
  uint32_t leaf = hit_leaf(tree, hit);
  double impulse = 0.0;
  for (uint32_t i = 0; i < tree->bond_count; ++i) {
    const bk_bond* b = &tree->bonds[i];
    if (b->leaf_a != leaf && b->leaf_b != leaf) continue;
    double s = fmax(bk_v3_length(bk_v3_sub(b->centroid, hit)), s_min);
    impulse = fmax(impulse, material->bond_strength * b->area * s * s * s / material->frailty);
  }
  return impulse;
}

void scene_fit_shots(app_scene* scene, const bk_mesh_tree* tree, const bk_material* material,
                     bk_world_def* world) {
  double mass = tree->nodes[0].moments.v * material->density;
  if (!(mass > 0.0) || !isfinite(mass)) return;
  // Where the first shot lands, in the tree's frame (the object is placed
  // by a translation alone).
  bk_vec3 offset = scene->objects[0].position;
  bk_vec3 eye = bk_v3_sub(scene->eye, offset), target = bk_v3_sub(scene->target, offset), hit = target;
  scene_first_hit(&tree->nodes[0].mesh, eye, bk_v3_sub(target, eye), &hit);
  double impulse = SHOT_MARGIN * breaking_impulse(tree, material, world->runtime.damage_min_distance, hit);
  double speed = scene->projectile_speed;
  double ball = impulse > 0.0 ? impulse / speed : SHOT_MASS_MIN * 10.0 * mass;
  ball = fmin(fmax(ball, SHOT_MASS_MIN * mass), SHOT_MASS_MAX * mass);
  if (impulse > ball * speed) speed = fmin(impulse / ball, SHOT_SPEED_MAX);
  scene->projectile_mass = ball;
  scene->projectile_speed = speed;
  // The thresholds are sized for objects a person's size: below them a
  // pebble's shots would do nothing at all. Resting contact still breaks
  // nothing (it closes far slower than any shot).
  world->runtime.impulse_threshold = fmin(world->runtime.impulse_threshold, 0.25 * ball * speed);
  world->runtime.impact_speed = fmin(world->runtime.impact_speed, 0.25 * speed);
}
