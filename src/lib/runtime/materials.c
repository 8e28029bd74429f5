// Material presets. Bond strength is hit points per m^2 of contact, so large
// contacts hold better than slivers; frailty scales the damage formula. The
// damage of a hit with impulse J reaches bonds within s = (f J / (strength x
// area))^(1/3). Measured with `breakables sim --scene wall --shots 1`: an
// 8 kg ball at 40 m/s frees ~16 fragments of a 256-fragment stone wall and
// ~150 of a 1024-fragment one (finer fragments have smaller, weaker bonds).
#include <string.h>

#include "runtime_internal.h"

// clang-format off
static const bk_material materials[] = {
    {.name = "stone",     .density = 2400, .frailty = 1.0, .bond_strength = 7.0e5, .friction = 0.7, .restitution = 0.05,
     .compression_limit = 1.0e7, .tension_limit = 4.0e5, .shear_limit = 8.0e5},
    {.name = "concrete",  .density = 2300, .frailty = 0.8, .bond_strength = 1.0e6, .friction = 0.8, .restitution = 0.05,
     .compression_limit = 2.0e7, .tension_limit = 1.5e6, .shear_limit = 2.5e6},
    {.name = "glass",     .density = 2500, .frailty = 4.0, .bond_strength = 3.5e5, .friction = 0.3, .restitution = 0.2,
     .compression_limit = 2.0e6, .tension_limit = 5.0e5, .shear_limit = 1.0e6},
    {.name = "porcelain", .density = 2400, .frailty = 3.0, .bond_strength = 5.0e5, .friction = 0.4, .restitution = 0.2,
     .compression_limit = 1.0e7, .tension_limit = 1.0e6, .shear_limit = 1.5e6},
    {.name = "eggshell",  .density = 1200, .frailty = 8.0, .bond_strength = 2.0e5, .friction = 0.5, .restitution = 0.1,
     .accumulate = true, .compression_limit = 5.0e5, .tension_limit = 1.0e5, .shear_limit = 2.0e5},
    {.name = "wood",      .density = 700,  .frailty = 0.5, .bond_strength = 5.0e5, .friction = 0.6, .restitution = 0.1,
     .accumulate = true, .compression_limit = 5.0e6, .tension_limit = 1.0e7, .shear_limit = 1.0e6},
};
// clang-format on

uint32_t bk_material_count(void) { return sizeof materials / sizeof *materials; }

const bk_material* bk_material_at(uint32_t index) {
  return index < bk_material_count() ? &materials[index] : NULL;
}

const bk_material* bk_material_find(const char* name) {
  for (uint32_t i = 0; i < bk_material_count(); ++i)
    if (strcmp(materials[i].name, name) == 0) return &materials[i];
  return NULL;
}

bool bk_material_validate(const bk_material* m, bk_error* err) {
  if (!m) return bk_error_set(err, "material is NULL");
  if (m->name && strlen(m->name) > BK_MATERIAL_NAME_MAX)
    return bk_error_set(err, "material.name must be at most %d bytes (got %zu)", BK_MATERIAL_NAME_MAX,
                        strlen(m->name));
  if (!(m->density >= BK_MATERIAL_DENSITY_MIN && m->density <= BK_MATERIAL_DENSITY_MAX))
    return bk_error_set(err, "material.density must be in [%g, %g] kg/m^3 (got %g)", BK_MATERIAL_DENSITY_MIN,
                        BK_MATERIAL_DENSITY_MAX, m->density);
  if (!(m->frailty >= 0.0) || !isfinite(m->frailty))
    return bk_error_set(err, "material.frailty must be finite and >= 0 (got %g)", m->frailty);
  if (!(m->bond_strength >= BK_MATERIAL_BOND_STRENGTH_MIN &&
        m->bond_strength <= BK_MATERIAL_BOND_STRENGTH_MAX))
    return bk_error_set(err, "material.bond_strength must be in [%g, %g] per m^2 of bond (got %g)",
                        BK_MATERIAL_BOND_STRENGTH_MIN, BK_MATERIAL_BOND_STRENGTH_MAX, m->bond_strength);
  if (!(m->friction >= 0.0) || !isfinite(m->friction))
    return bk_error_set(err, "material.friction must be finite and >= 0 (got %g)", m->friction);
  if (!(m->restitution >= 0.0 && m->restitution <= 1.0))
    return bk_error_set(err, "material.restitution must be in [0, 1] (got %g)", m->restitution);
  const char* limit_names[3] = {"compression_limit", "tension_limit", "shear_limit"};
  double limits[3] = {m->compression_limit, m->tension_limit, m->shear_limit};
  for (int i = 0; i < 3; ++i)
    if (!(limits[i] > 0.0)) // INFINITY is allowed: never fails that way
      return bk_error_set(err, "material.%s must be positive, in Pa (got %g)", limit_names[i], limits[i]);
  if (!(m->refine_strength >= 0.0) || !isfinite(m->refine_strength))
    return bk_error_set(err, "material.refine_strength must be finite and >= 0 (got %g)", m->refine_strength);
  return true;
}
