// What the physics budget changes, measured the same way by `sim` and
// `bench`: the debris the player sees (its mass and momentum) over the
// first second after each hit, when the pieces fly and the budget has the
// most to do (the step times' percentiles are app_percentile, app_util.c).
#include <math.h>
#include <stdlib.h>

#include "app.h"
#include "scene_run.h"

// The debris now: all of it, or (near) what is within `radius` of `focus`
// and looks at least `angle` large from there (size over distance, radians:
// what the player can see move).
static debris_sample measure(bk_world* world, const bk_vec3* focus, double radius, double angle) {
  debris_sample s = {0.0, 0.0, 0.0};
  const bk_physics* physics = bk_world_physics(world);
  bk_vec3 net = {0.0, 0.0, 0.0};
  uint32_t count = bk_world_body_count(world);
  for (uint32_t i = 0; i < count; ++i) {
    bk_body_view view = {0};
    if (!bk_world_body_view(world, i, &view) || view.is_static) continue;
    if (focus) {
      double distance =
          bk_v3_length(bk_v3_sub(bk_physics_body_transform(physics, view.body).position, *focus));
      double volume = 0.0;
      for (uint32_t n = 0; n < view.node_count; ++n)
        volume += view.tree->nodes[view.nodes[n]].moments.v;
      if (distance > radius || cbrt(volume) < angle * distance) continue;
    }
    double mass = bk_physics_body_mass(physics, view.body);
    bk_vec3 p = bk_v3_scale(bk_physics_body_linear_velocity(physics, view.body), mass);
    s.mass += mass;
    s.momentum += bk_v3_length(p);
    net = bk_v3_add(net, p);
  }
  s.net_momentum = bk_v3_length(net);
  return s;
}

debris_sample debris_measure(bk_world* world) { return measure(world, NULL, 0.0, 0.0); }

static void add_sample(debris_sample* sum, uint32_t weight, debris_sample now) {
  sum->mass += weight * now.mass;
  sum->momentum += weight * now.momentum;
  sum->net_momentum += weight * now.net_momentum;
}

static debris_sample mean(debris_sample sum, double weight) {
  if (weight <= 0.0) return (debris_sample){0.0, 0.0, 0.0};
  return (debris_sample){sum.mass / weight, sum.momentum / weight, sum.net_momentum / weight};
}

void fidelity_step(app_fidelity* f, bk_world* world, uint64_t step, uint32_t hits) {
  // A hit's second is the BK_FIDELITY_STEPS steps from the one after it was
  // fired; it ends when the step count comes round to the same slot.
  uint32_t slot = (uint32_t)(step % BK_FIDELITY_STEPS);
  f->open -= f->ending[slot];
  f->ending[slot] = hits;
  f->open += hits;
  if (f->open == 0) return;
  add_sample(&f->sum, f->open, debris_measure(world));
  // Near the focus: within the radius the budget keeps a new piece's first
  // second in, the pieces large enough to see (everything, with no focus set).
  bk_vec3 focus = {0.0, 0.0, 0.0};
  bool has_focus = bk_world_focus(world, &focus);
  add_sample(&f->near_sum, f->open,
             measure(world, has_focus ? &focus : NULL, bk_world_budget_fidelity_radius(world),
                     bk_world_budget_visible_angle(world)));
  f->weight += f->open;
}

debris_sample fidelity_mean(const app_fidelity* f) { return mean(f->sum, f->weight); }

debris_sample fidelity_near_mean(const app_fidelity* f) { return mean(f->near_sum, f->weight); }

bool break_step(const bk_world_stats* before, const bk_world_stats* now) {
  return now->bonds_broken != before->bonds_broken || now->break_events != before->break_events ||
         before->pending_splits > 0 || before->pending_hits > 0;
}
