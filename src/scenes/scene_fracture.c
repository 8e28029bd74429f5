// How a scene's object is fractured: the pattern it or the options choose,
// with the pattern's parameters fitted to the object (a brick bond on its
// texture, a radial pattern round where the shots land).
#include <math.h>
#include <string.h>

#include "app.h"
#include "scene_run.h"

// Moller-Trumbore on every triangle.
bool scene_first_hit(const bk_mesh* mesh, bk_vec3 origin, bk_vec3 direction, bk_vec3* hit) {
  double nearest = INFINITY;
  for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
    bk_vec3 a = mesh->positions[bk_mesh_tri_position(mesh, t, 0)];
    bk_vec3 e1 = bk_v3_sub(mesh->positions[bk_mesh_tri_position(mesh, t, 1)], a);
    bk_vec3 e2 = bk_v3_sub(mesh->positions[bk_mesh_tri_position(mesh, t, 2)], a);
    bk_vec3 p = bk_v3_cross(direction, e2);
    double det = bk_v3_dot(e1, p);
    if (fabs(det) < 1e-300) continue; // parallel to the triangle
    bk_vec3 s = bk_v3_sub(origin, a), q = bk_v3_cross(s, e1);
    double u = bk_v3_dot(s, p) / det, v = bk_v3_dot(direction, q) / det, along = bk_v3_dot(e2, q) / det;
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && along > 0.0 && along < nearest) nearest = along;
  }
  if (!isfinite(nearest)) return false;
  *hit = bk_v3_add(origin, bk_v3_scale(direction, nearest));
  return true;
}

bk_fracture_def scene_fracture_def(const app_scene* scene, uint32_t object, const scene_options* options,
                                   const bk_mesh* source) {
  const scene_object* o = &scene->objects[object];
  bk_fracture_def fd = bk_default_fracture_def();
  fd.pieces = options->pieces ? options->pieces : scene->pieces;
  fd.seed = options->seed;
  fd.texture_scale = options->texture_scale > 0.0 ? options->texture_scale : fd.texture_scale;
  fd.aspect_bias = scene->aspect_bias;
  fd.progress = options->progress;
  fd.progress_user = options->progress_user;
  fd.pattern = options->pattern >= 0 && options->pattern < BK_PATTERN_COUNT
                   ? (bk_fracture_pattern)options->pattern
                   : o->pattern;
  if (options->clusters) fd.clusters = options->clusters;
  if (options->cluster_border > 0.0) fd.cluster_border = options->cluster_border;
  if (options->radial_falloff >= 0.0) fd.radial_falloff = options->radial_falloff;
  if (options->noise > 0.0 && fd.pattern != BK_PATTERN_BRICK && source) {
    bk_aabb box = bk_mesh_bounds(source);
    double size = bk_v3_length(bk_v3_sub(box.max, box.min));
    if (size > 0.0) fd.noise_amplitude = options->noise * size, fd.noise_frequency = 4.0 / size;
  }
  // The tree is cut from the mesh scaled by the object's scale, while its
  // uvs stay those of the unscaled mesh: a scaled wall's texture bricks are
  // scaled too, and so must the bond's be to stay on them. Where the object
  // stands or how it is turned moves its texture with it, so neither matters.
  double scale = o->scale > 0.0 ? o->scale : 1.0;
  fd.brick_size = bk_v3_scale(fd.brick_size, scale);
  fd.brick_origin = bk_v3_scale(fd.brick_origin, scale);
  if (fd.pattern == BK_PATTERN_CUTOUT) {
    uint32_t size = 0;
    fd.cutout_pixels = app_cutout_map(&size);
    fd.cutout_width = fd.cutout_height = size;
  }

  // The breakable's world transform is the object's position and rotation
  // over the scaled mesh: its inverse takes the aim point into the tree's frame.
  bk_transform place = {o->position, bk_quat_identity()};
  if (bk_v3_length(o->axis) > 0.0) place.rotation = bk_quat_axis_angle(bk_v3_normalize(o->axis), o->angle);
  bk_vec3 aim = scene_object_aim(scene, object), eye = scene->eye;
  if (scene->fit_to_mesh && source) {
    // A user's model is placed and aimed at by its bounds when it is loaded:
    // aim as the fitted scene will.
    app_scene fitted = {0};
    scene_fit(scene, bk_mesh_bounds(source), &fitted);
    place.position = fitted.objects[object].position;
    aim = scene_object_aim(&fitted, object);
    eye = fitted.eye;
  }
  bk_transform to_tree = bk_transform_inverse(place);
  fd.impact = bk_transform_point(to_tree, aim);
  // Aim points lie inside their objects (the middle of the bunny): centred
  // there, the finest pieces would all be inside and the surface the shot
  // hits would break no finer than the rest. The shot flies from the eye
  // through the aim point, so it lands where that line meets the surface.
  bk_vec3 from = bk_transform_point(to_tree, eye), hit = fd.impact;
  if (source && scene_first_hit(source, from, bk_v3_sub(fd.impact, from), &hit)) fd.impact = hit;
  return fd;
}

bool scene_object_source(const scene_object* object, bk_mesh* out) {
  memset(out, 0, sizeof *out);
  size_t length = strlen(object->mesh);
  if (length > 6 && strcmp(object->mesh + length - 6, ".mtree") == 0) return false;
  bk_error err = {{0}};
  if (!app_load_mesh(object->mesh, out, &err)) return false;
  // As app_load_tree scales it before cutting.
  if (object->scale > 0.0 && object->scale != 1.0)
    for (uint32_t i = 0; i < out->position_count; ++i)
      out->positions[i] = bk_v3_scale(out->positions[i], object->scale);
  return true;
}
