// Turns a scene description into a running world: mesh trees (cached),
// breakables with their materials, and aimed shots.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "scene_run.h"

scene_options default_scene_options(void) {
  return (scene_options){.seed = 3000,
                         .texture_scale = 0.1,
                         .accumulate = -1,
                         .pattern = -1,
                         .radial_falloff = -1.0,
                         .stress = true,
                         .stress_scale = 1.0,
                         .physics_budget_ms = bk_default_world_def().physics_budget_ms,
                         .budget_fidelity_time = bk_default_world_def().budget_fidelity_time,
                         .budget_fidelity_factor = bk_default_world_def().budget_fidelity_factor,
                         .copies = 1,
                         .refine = false,
                         .refine_pieces = BK_REFINE_PIECES_DEFAULT};
}

void scene_refine(bk_breakable_def* b, const scene_options* options) {
  if (!options || !options->refine) return;
  // A hit refines a fragment when its damage there would break a bond of an
  // eighth of the fragment's cross-section (a bond's hit points are
  // bond_strength x its area; the threshold is refine_strength x
  // volume^(2/3)). A fragment of the 1,024-fragment wall is a sixteenth of
  // one of the 64-fragment wall's, its bonds about 16^(-2/3) = 1/6.3 of
  // that cross-section: near a 64-fragment wall's hits, fragments refine
  // where the 1,024-fragment wall's bonds would break. Weaker hits damage
  // the fragment's bonds as they are. Pieces stay at least 6 cm across on
  // average: the 64-fragment wall's fragments (about 30 cm) refine once,
  // into pieces of about 10 cm like the 1,024-fragment wall's, and those
  // are not refined again when they land or are hit (without the floor, a
  // hit's pieces shattered again on the ground: three shots made 1,242
  // leaves and 627 bodies instead of 529 and 382).
  b->material.refine_strength = b->material.bond_strength / 8.0;
  b->refine = (bk_refine_def){.pattern = BK_PATTERN_RADIAL,
                              .pieces = options->refine_pieces,
                              .min_size = 0.06,
                              .radial_falloff = 1.0};
}

bool app_parse_budget_ms(const char* command, const char* text, scene_options* options) {
  return option_double(command, "--budget-ms", text, 0.0, BK_BUDGET_MS_MAX, &options->physics_budget_ms);
}

double copy_offset(uint32_t copy, uint32_t copies, double spacing) {
  return ((double)copy - 0.5 * (copies - 1)) * spacing;
}

bk_breakable_id loaded_scene_id(const loaded_scene* s, uint32_t copy, uint32_t object) {
  if (object >= s->tree_count) return (bk_breakable_id){0, 0};
  if (copy == 0) return s->ids[object];
  return copy < s->copies ? s->copy_ids[(copy - 1) * s->tree_count + object] : (bk_breakable_id){0, 0};
}

uint32_t loaded_scene_fire(loaded_scene* s, uint32_t shot, double speed) {
  uint32_t copies = s->copies ? s->copies : 1;
  for (uint32_t c = 0; c < copies; ++c) {
    bk_projectile_def p = scene_shot(s->scene, shot, speed);
    p.position.x += copy_offset(c, copies, s->copy_spacing);
    bk_world_fire(s->world, &p, NULL);
  }
  return copies;
}

// Centre to centre along x, so that copies side by side leave a gap as wide
// as the spacing of impact_run's walls between them (at least that
// spacing: a wall is narrower). Measured on the objects as placed.
static double copy_spacing(const loaded_scene* s) {
  double lo = INFINITY, hi = -INFINITY;
  for (uint32_t i = 0; i < s->tree_count; ++i) {
    bk_world_breakable_def def = scene_object_def(&s->scene->objects[i], &s->trees[i], NULL);
    bk_aabb b = s->trees[i].nodes[0].bounds;
    for (int corner = 0; corner < 8; ++corner) {
      bk_vec3 p = {corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y,
                   corner & 4 ? b.max.z : b.min.z};
      double x = bk_transform_point(def.breakable.transform, p).x;
      lo = fmin(lo, x), hi = fmax(hi, x);
    }
  }
  double width = hi > lo ? hi - lo : 0.0;
  return fmax(BK_IMPACT_SPACING, width + BK_IMPACT_SPACING);
}

bk_world_breakable_def scene_object_def(const scene_object* object, const bk_mesh_tree* tree,
                                        const scene_options* options) {
  bk_world_breakable_def def = bk_default_world_breakable_def();
  bk_breakable_def* b = &def.breakable;
  b->tree = tree;
  b->transform.position = object->position;
  if (bk_v3_length(object->axis) > 0.0)
    b->transform.rotation = bk_quat_axis_angle(bk_v3_normalize(object->axis), object->angle);
  const bk_material* material = options && options->material ? bk_material_find(options->material) : NULL;
  // The object's own limits go with its own material: a preset chosen for
  // every object is that preset as it is.
  double own_scale = material || !(object->stress_scale > 0.0) ? 1.0 : object->stress_scale;
  if (!material) material = bk_material_find(object->material);
  if (material) {
    b->material = *material;
    b->material.compression_limit *= own_scale;
    b->material.tension_limit *= own_scale;
    b->material.shear_limit *= own_scale;
  }
  if (options) {
    if (options->frailty > 0.0) b->material.frailty = options->frailty;
    if (options->density > 0.0) b->material.density = options->density;
    if (options->bond_strength > 0.0) b->material.bond_strength = options->bond_strength;
    if (options->accumulate >= 0) b->material.accumulate = options->accumulate == 1;
    if (options->stress_scale > 0.0) {
      b->material.compression_limit *= options->stress_scale;
      b->material.tension_limit *= options->stress_scale;
      b->material.shear_limit *= options->stress_scale;
    }
    if (options->compression_limit > 0.0) b->material.compression_limit = options->compression_limit;
    if (options->tension_limit > 0.0) b->material.tension_limit = options->tension_limit;
    if (options->shear_limit > 0.0) b->material.shear_limit = options->shear_limit;
    def.naive = options->naive;
    def.convex_colliders = options->convex_colliders;
  }
  scene_refine(b, options); // after the bond strength it follows
  b->anchored = object->anchored;
  return def;
}

void loaded_scene_apply_material(loaded_scene* s, scene_options* options, const bk_material* material) {
  // The preset now replaces every override, in the world at once and for
  // the next reload: the world's runtime owns the values, the options only
  // say what to build next time.
  options->material = material->name;
  options->frailty = options->density = options->bond_strength = 0.0;
  options->accumulate = -1;
  options->stress_scale = 1.0;
  options->compression_limit = options->tension_limit = options->shear_limit = 0.0;
  // Refinement stays as the options have it: its strength follows the
  // preset's bond strength.
  bk_breakable_def refined = {.material = *material};
  scene_refine(&refined, options);
  for (uint32_t c = 0; c < (s->copies ? s->copies : 1); ++c)
    for (uint32_t i = 0; i < s->tree_count; ++i)
      bk_world_set_material(s->world, loaded_scene_id(s, c, i), &refined.material);
}

bool loaded_scene_load_trees(const app_scene* scene, const scene_options* options, loaded_scene* out,
                             bk_error* err) {
  memset(out, 0, sizeof *out);
  out->scene = scene;
  out->copies = options->copies > 1 ? options->copies : 1;
  for (uint32_t i = 0; i < scene->object_count; ++i) {
    const scene_object* object = &scene->objects[i];
    bk_fracture_def fd = scene_fracture_def(scene, i, options, NULL);
    bk_mesh source = {0};
    // A radial pattern centres where the shot meets the object, and noise
    // is sized by the object: those take its mesh.
    if ((fd.pattern == BK_PATTERN_RADIAL || (options->noise > 0.0 && fd.pattern != BK_PATTERN_BRICK)) &&
        scene_object_source(object, &source))
      fd = scene_fracture_def(scene, i, options, &source);
    bk_mesh_free(&source);
    bool cached = false;
    if (!app_load_tree(object->mesh, object->scale, &fd, &out->trees[i], &cached, err)) {
      loaded_scene_destroy(out);
      return false;
    }
    out->tree_count = i + 1;
    out->from_cache = out->from_cache || cached;
    if (scene->fit_to_mesh && i == 0) {
      // A user's model: stand it on the ground and aim at it, by its size.
      scene_fit(scene, out->trees[0].nodes[0].bounds, &out->fitted);
      out->scene = &out->fitted;
    }
  }
  return true;
}

bool loaded_scene_create(const app_scene* scene, const scene_options* options, loaded_scene* out,
                         bk_error* err) {
  if (!loaded_scene_load_trees(scene, options, out, err)) return false;
  // The world once the trees are known: a user's model's shots are weighed
  // on its tree and material, and the world's damage thresholds follow them.
  bk_world_def wd = bk_default_world_def();
  wd.retire_volume = options->retire_volume;
  wd.stress = options->stress;
  wd.physics_budget_ms = options->physics_budget_ms;
  wd.budget_fidelity_time = options->budget_fidelity_time;
  wd.budget_fidelity_factor = options->budget_fidelity_factor;
  if (scene->fit_to_mesh && out->tree_count) {
    bk_world_breakable_def object = scene_object_def(&out->fitted.objects[0], &out->trees[0], options);
    scene_fit_shots(&out->fitted, &out->trees[0], &object.breakable.material, &wd);
  }
  out->world = bk_world_create(&wd, err);
  if (!out->world) {
    loaded_scene_destroy(out);
    return false;
  }
  // Every tree first: the copies' spacing is measured on all of them.
  out->copy_spacing = out->copies > 1 ? copy_spacing(out) : 0.0;
  if (out->copies > 1)
    out->copy_ids = bk_calloc((size_t)(out->copies - 1) * out->tree_count, sizeof(bk_breakable_id));
  for (uint32_t c = 0; c < out->copies; ++c) {
    for (uint32_t i = 0; i < out->tree_count; ++i) {
      bk_world_breakable_def bd = scene_object_def(&out->scene->objects[i], &out->trees[i], options);
      bd.breakable.transform.position.x += copy_offset(c, out->copies, out->copy_spacing);
      bk_breakable_id id = bk_world_add_breakable(out->world, &bd, err);
      if (id.generation == 0) {
        loaded_scene_destroy(out);
        return false;
      }
      if (c == 0)
        out->ids[i] = id;
      else
        out->copy_ids[(c - 1) * out->tree_count + i] = id;
    }
  }
  return true;
}

void loaded_scene_destroy(loaded_scene* s) {
  bk_world_destroy(s->world);
  free(s->copy_ids);
  for (uint32_t i = 0; i < s->tree_count; ++i)
    bk_mesh_tree_free(&s->trees[i]);
  memset(s, 0, sizeof *s);
}

bk_projectile_def scene_shot(const app_scene* scene, uint32_t shot, double speed) {
  // Later shots land around the target on a golden-angle spiral, so a volley
  // spreads its damage instead of hitting one hole.
  // With several aim points the shots take them in turn, each one keeping
  // its own spiral.
  uint32_t targets = 1 + scene->extra_target_count;
  bk_vec3 target = shot % targets == 0 ? scene->target : scene->extra_targets[shot % targets - 1];
  uint32_t round = shot / targets;
  bk_vec3 forward = bk_v3_normalize(bk_v3_sub(target, scene->eye)), right, up;
  bk_plane_basis(forward, &right, &up);
  double spread = scene->shot_spread > 0.0 ? scene->shot_spread : 0.12;
  double radius = spread * sqrt((double)round), angle = 2.39996322972865332 * round;
  bk_vec3 aim = bk_v3_add(
      target, bk_v3_add(bk_v3_scale(right, radius * cos(angle)), bk_v3_scale(up, radius * sin(angle))));
  bk_vec3 direction = bk_v3_normalize(bk_v3_sub(aim, scene->eye));
  return (bk_projectile_def){.position = scene->eye,
                             .velocity =
                                 bk_v3_scale(direction, speed > 0.0 ? speed : scene->projectile_speed),
                             .radius = scene->projectile_radius,
                             .mass = scene->projectile_mass};
}
