// Material presets. Bond strength is hit points per m^2 of contact, so large
// contacts hold better than slivers; frailty scales the damage formula. The
// damage of a hit with impulse J reaches bonds within s = (f J / (strength x
// area))^(1/3). Measured with `breakables sim --scene wall --shots 1`: an
// 8 kg ball at 40 m/s frees ~16 fragments of a 256-fragment stone wall and
// ~150 of a 1024-fragment one (finer fragments have smaller, weaker bonds).
#include <string.h>

#include "bk_sim.h"

// clang-format off
static const bk_material materials[] = {
    {.name = "stone",     .density = 2400, .frailty = 1.0, .bond_strength = 7.0e5, .friction = 0.7, .restitution = 0.05},
    {.name = "concrete",  .density = 2300, .frailty = 0.8, .bond_strength = 1.0e6, .friction = 0.8, .restitution = 0.05},
    {.name = "glass",     .density = 2500, .frailty = 4.0, .bond_strength = 3.5e5, .friction = 0.3, .restitution = 0.2},
    {.name = "porcelain", .density = 2400, .frailty = 3.0, .bond_strength = 5.0e5, .friction = 0.4, .restitution = 0.2},
    {.name = "eggshell",  .density = 1200, .frailty = 8.0, .bond_strength = 2.0e5, .friction = 0.5, .restitution = 0.1,
     .accumulate = true},
    {.name = "wood",      .density = 700,  .frailty = 0.5, .bond_strength = 5.0e5, .friction = 0.6, .restitution = 0.1,
     .accumulate = true},
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
