// Projectiles: spheres with continuous collision detection, removed (with
// their shapes) after their lifetime (the world's projectile_lifetime unless
// they have their own) so a long session stays bounded.
#include <string.h>

#include "world_internal.h"

bk_projectile_def bk_default_projectile_def(void) {
  return (bk_projectile_def){
      .position = {0, 0, 0}, .velocity = {0, 0, 0}, .radius = 0.08, .mass = 4.0, .lifetime = 0.0};
}

bk_body_id bk_world_fire(bk_world* w, const bk_projectile_def* def, bk_error* err) {
  bk_body_id null_id = {0, 0};
  if (!def) return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "projectile: def is NULL"), null_id;
  if (!bk_v3_is_finite(def->position))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "projectile: position must be finite"), null_id;
  if (!bk_v3_is_finite(def->velocity))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "projectile: velocity must be finite"), null_id;
  if (!(def->radius > 0.0) || !isfinite(def->radius))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "projectile: radius must be a positive finite number (got %g)", def->radius),
           null_id;
  if (!(def->mass > 0.0) || !isfinite(def->mass))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT,
                             "projectile: mass must be a positive finite number (got %g)", def->mass),
           null_id;
  if (!(def->lifetime >= 0.0))
    return bk_error_set_code(err, BK_ERROR_INVALID_ARGUMENT, "projectile: lifetime must be >= 0 (got %g)",
                             def->lifetime),
           null_id;
  double radius = def->radius, mass = def->mass;
  bk_shape_id sphere = bk_physics_create_sphere(w->physics, radius);
  bk_body_def bd = bk_default_body_def();
  bd.shape = sphere;
  bd.mass = mass;
  double moment = 0.4 * mass * radius * radius;
  bd.inertia = bk_v3(moment, moment, moment);
  bd.transform.position = def->position;
  bd.linear_velocity = def->velocity;
  bd.ccd = true;
  bd.ccd_radius = radius;
  bd.user_data = BK_USER_PROJECTILE;
  bk_body_id body = bk_physics_create_body(w->physics, &bd, err);
  if (bk_body_is_null(body)) {
    bk_physics_destroy_shape(w->physics, sphere);
    return body;
  }
  if (w->projectile_count == w->projectile_capacity) {
    w->projectile_capacity = bk_grow_capacity(w->projectile_capacity, w->projectile_count + 1);
    w->projectiles = bk_realloc(w->projectiles, sizeof(bk_body_id) * w->projectile_capacity);
    w->projectile_radius = bk_realloc(w->projectile_radius, sizeof(double) * w->projectile_capacity);
    w->projectile_shape = bk_realloc(w->projectile_shape, sizeof(bk_shape_id) * w->projectile_capacity);
    w->projectile_expires = bk_realloc(w->projectile_expires, sizeof(uint64_t) * w->projectile_capacity);
  }
  w->projectile_radius[w->projectile_count] = radius;
  w->projectile_shape[w->projectile_count] = sphere;
  double lifetime = def->lifetime > 0.0 ? def->lifetime : w->def.projectile_lifetime;
  double steps = lifetime / w->def.fixed_dt;
  w->projectile_expires[w->projectile_count] =
      steps < 1e18 ? w->step_count + (uint64_t)steps : UINT64_MAX; // INFINITY: never
  w->projectiles[w->projectile_count++] = body;
  return body;
}

void bk_world_retire_projectiles(bk_world* w) {
  uint32_t kept = 0;
  for (uint32_t i = 0; i < w->projectile_count; ++i) {
    if (w->step_count > w->projectile_expires[i]) {
      bk_physics_destroy_body(w->physics, w->projectiles[i]);
      bk_physics_destroy_shape(w->physics, w->projectile_shape[i]);
      continue;
    }
    w->projectiles[kept] = w->projectiles[i];
    w->projectile_radius[kept] = w->projectile_radius[i];
    w->projectile_shape[kept] = w->projectile_shape[i];
    w->projectile_expires[kept] = w->projectile_expires[i];
    kept++;
  }
  w->projectile_count = kept;
}

uint32_t bk_world_projectile_count(const bk_world* w) { return w->projectile_count; }

bool bk_world_projectile(const bk_world* w, uint32_t index, bk_vec3* position, double* radius) {
  if (index >= w->projectile_count) return false;
  *position = bk_physics_body_transform(w->physics, w->projectiles[index]).position;
  *radius = w->projectile_radius[index];
  return true;
}
