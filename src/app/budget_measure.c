// What the physics budget changes, measured the same way by `sim` and
// `bench`: the debris the player sees (its mass and momentum) over the
// first second after each hit, when the pieces fly and the budget has the
// most to do (the step times' percentiles are bk_percentile, app_util.c).
#include <stdlib.h>

#include "app.h"

bk_debris_sample bk_debris_measure(bk_world* world) {
  bk_debris_sample s = {0.0, 0.0, 0.0};
  const bk_physics* physics = bk_world_physics(world);
  bk_vec3 net = {0.0, 0.0, 0.0};
  uint32_t count = bk_world_body_count(world);
  for (uint32_t i = 0; i < count; ++i) {
    bk_body_view view = {0};
    if (!bk_world_body_view(world, i, &view) || view.is_static) continue;
    double mass = bk_physics_body_mass(physics, view.body);
    bk_vec3 p = bk_v3_scale(bk_physics_body_linear_velocity(physics, view.body), mass);
    s.mass += mass;
    s.momentum += bk_v3_length(p);
    net = bk_v3_add(net, p);
  }
  s.net_momentum = bk_v3_length(net);
  return s;
}

void bk_fidelity_step(bk_fidelity* f, bk_world* world, uint64_t step, uint32_t hits) {
  // A hit's second is the BK_FIDELITY_STEPS steps from the one after it was
  // fired; it ends when the step count comes round to the same slot.
  uint32_t slot = (uint32_t)(step % BK_FIDELITY_STEPS);
  f->open -= f->ending[slot];
  f->ending[slot] = hits;
  f->open += hits;
  if (f->open == 0) return;
  bk_debris_sample now = bk_debris_measure(world);
  f->sum.mass += f->open * now.mass;
  f->sum.momentum += f->open * now.momentum;
  f->sum.net_momentum += f->open * now.net_momentum;
  f->weight += f->open;
}

bk_debris_sample bk_fidelity_mean(const bk_fidelity* f) {
  if (f->weight <= 0.0) return (bk_debris_sample){0.0, 0.0, 0.0};
  return (bk_debris_sample){f->sum.mass / f->weight, f->sum.momentum / f->weight,
                            f->sum.net_momentum / f->weight};
}
