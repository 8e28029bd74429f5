// The game's dust and debris pool (src/game/particles.c), without a window:
// emission is capped per break and per step, every particle fades to
// nothing, colours follow the material, and everything stays near the break.
#include <math.h>
#include <string.h>

#include "ensure.h"
#include "particles.h"

static bk_break_event hit_at(bk_vec3 position, bk_vec3 velocity) {
  return (bk_break_event){.position = position, .velocity = velocity, .area = 0.01, .cause = BK_BREAK_DAMAGE};
}

static const char* step_material = "brick";
static app_debris_look look_of(void* context, bk_breakable_id id) {
  (void)context, (void)id;
  return debris_look_of(step_material);
}

static uint32_t live_dust(const app_particles* p) {
  uint32_t n = 0;
  for (uint32_t i = 0; i < p->count; ++i)
    n += p->items[i].life > 0.0f && p->items[i].kind == BK_PARTICLE_DUST;
  return n;
}

static void emission_is_capped(void) {
  app_particles p;
  particles_init(&p, 4096, 1);
  // One break, however many chips are asked for.
  bk_break_event e = hit_at(bk_v3(0, 1, 0), bk_v3(0, 0, 0));
  app_debris_look brick = debris_look_of("brick");
  particles_emit_break(&p, &e, &brick, 100, true);
  ENSURE(p.count == BK_CHIPS_PER_BREAK + BK_PUFFS_PER_BREAK);
  ENSURE(live_dust(&p) == BK_PUFFS_PER_BREAK);
  particles_free(&p);
  // A step of a thousand broken bonds, hits and loads mixed.
  static bk_break_event events[1000];
  for (int i = 0; i < 1000; ++i) {
    events[i] = hit_at(bk_v3(0.01 * i, 1, 0), bk_v3(1, 0, 0));
    if (i % 3 == 0) events[i].cause = BK_BREAK_STRESS;
  }
  const char* materials[3] = {"brick", "glass", "wood"};
  for (int m = 0; m < 3; ++m) {
    step_material = materials[m];
    particles_init(&p, 4096, 2);
    uint32_t made = particles_emit_step(&p, events, 1000, look_of, NULL);
    uint32_t chips = 0, dust = 0, glints = 0;
    for (uint32_t i = 0; i < p.count; ++i) {
      chips += p.items[i].kind == BK_PARTICLE_CHIP;
      dust += p.items[i].kind == BK_PARTICLE_DUST;
      glints += p.items[i].kind == BK_PARTICLE_GLINT;
    }
    ENSURE(made == p.count);
    ENSURE_MSG(chips <= BK_CHIPS_PER_STEP + BK_CRUMBLES_PER_STEP && chips >= BK_CHIPS_PER_STEP / 2,
               "%s: %u chips", materials[m], chips);
    ENSURE_MSG(dust <= BK_PUFFS_PER_STEP + BK_CRUMBLES_PER_STEP, "%s: %u puffs", materials[m], dust);
    ENSURE_MSG(glints <= BK_GLINTS_PER_STEP, "%s: %u glints", materials[m], glints);
    if (m == 1) ENSURE_MSG(dust == 0 && glints > 0, "glass glints (%u) and has no dust (%u)", glints, dust);
    if (m != 1) ENSURE_MSG(dust >= BK_PUFFS_PER_STEP / 2 && glints == 0, "%s: %u puffs", materials[m], dust);
    ENSURE(made <= 60); // fewer, better
    particles_free(&p);
  }
}

static void everything_fades_to_nothing(void) {
  app_particles p;
  particles_init(&p, 256, 3);
  app_debris_look looks[2] = {debris_look_of("concrete"), debris_look_of("glass")};
  for (int i = 0; i < 2; ++i) {
    bk_break_event e = hit_at(bk_v3(0, 1.5, 0), bk_v3(3, 1, -2));
    particles_emit_break(&p, &e, &looks[i], 3, true);
    particles_emit_crumble(&p, &e, &looks[i]);
  }
  uint32_t first = particles_update(&p, 1.0 / 60.0);
  ENSURE(first > 0 && p.chip_count > 0);
  // Puffs thin out as they age: opacity falls after the first fraction of a second.
  float early = 0.0f, later = 0.0f;
  for (int frame = 0; frame < 60; ++frame) {
    uint32_t n = particles_update(&p, 1.0 / 60.0);
    float sum = 0.0f;
    for (uint32_t i = 0; i < n; ++i)
      if (p.instances[i].kind == 0.0f) sum += p.instances[i].color[3];
    if (frame == 10) early = sum;
    if (frame == 59) later = sum;
  }
  ENSURE_MSG(later < early, "puff opacity %.3f at 1 s, %.3f at 0.2 s", later, early);
  // Chips fade in their last moments (dither), and after ten seconds nothing is left.
  bool chip_fading = false;
  uint32_t n = 1;
  for (int frame = 0; frame < 600; ++frame) {
    n = particles_update(&p, 1.0 / 60.0);
    for (uint32_t i = 0; i < p.chip_count; ++i) {
      ENSURE(p.chips[i].fade >= 0.0f && p.chips[i].fade <= 1.0f);
      chip_fading |= p.chips[i].fade > 0.5f;
    }
    for (uint32_t i = 0; i < n; ++i)
      ENSURE(p.instances[i].color[3] >= 0.0f && p.instances[i].color[3] <= 1.0f);
  }
  ENSURE(chip_fading);
  ENSURE_MSG(n == 0 && p.chip_count == 0, "%u particles and %u chips left", n, p.chip_count);
  particles_free(&p);
}

static void colours_follow_the_material(void) {
  app_debris_look brick = debris_look_of("brick"), concrete = debris_look_of("concrete");
  app_debris_look wood = debris_look_of("wood"), glass = debris_look_of("glass");
  ENSURE_MSG(brick.dust[0] > 1.5f * brick.dust[2], "brick dust is reddish");
  ENSURE_MSG(fabsf(concrete.dust[0] - concrete.dust[2]) < 0.05f, "concrete dust is grey");
  ENSURE_MSG(wood.dust[0] > wood.dust[1] && wood.dust[1] > wood.dust[2] && wood.dust[0] > 0.4f,
             "wood dust is light brown");
  ENSURE_MSG(glass.dust_opacity == 0.0f && glass.glints > 0, "glass has no dust but glints");
  ENSURE(debris_look_of("no such material").material == 0 && debris_look_of(NULL).material == 0);
  // The instances carry it: a brick break's puffs are reddish, its chips brick's.
  app_particles p;
  particles_init(&p, 64, 4);
  p.renderer_material[1] = 5; // the renderer's own index for brick, whatever it is
  bk_break_event e = hit_at(bk_v3(0, 1, 0), bk_v3(0, 0, 0));
  particles_emit_break(&p, &e, &brick, 3, true);
  uint32_t n = particles_update(&p, 0.2);
  ENSURE(n == BK_PUFFS_PER_BREAK && p.chip_count == BK_CHIPS_PER_BREAK);
  for (uint32_t i = 0; i < n; ++i)
    ENSURE(p.instances[i].kind == 0.0f && p.instances[i].color[0] > 1.5f * p.instances[i].color[2]);
  for (uint32_t i = 0; i < p.chip_count; ++i)
    ENSURE(p.chips[i].material == 5 && p.chips[i].size > 0.0f);
  particles_free(&p);
}

static void positions_stay_near_the_break(void) {
  app_particles p;
  particles_init(&p, 512, 5);
  bk_vec3 at = bk_v3(2, 1.2, -1);
  const char* materials[3] = {"brick", "concrete", "porcelain"};
  for (int m = 0; m < 3; ++m) {
    app_debris_look look = debris_look_of(materials[m]);
    // A piece flying off at 15 m/s must not carry the dust metres away.
    bk_break_event e = hit_at(at, bk_v3(15, 2, 0));
    for (int i = 0; i < 4; ++i)
      particles_emit_break(&p, &e, &look, 3, true);
  }
  double farthest_dust = 0.0, lowest_chip = 1e9, farthest_chip = 0.0;
  for (int frame = 0; frame < 240; ++frame) {
    uint32_t n = particles_update(&p, 1.0 / 60.0);
    for (uint32_t i = 0; i < n; ++i) {
      bk_vec3 q = bk_v3(p.instances[i].position[0], p.instances[i].position[1], p.instances[i].position[2]);
      farthest_dust = fmax(farthest_dust, bk_v3_length(bk_v3_sub(q, at)));
    }
    for (uint32_t i = 0; i < p.chip_count; ++i) {
      lowest_chip = fmin(lowest_chip, p.chips[i].position[1] - 0.5 * p.chips[i].size);
      bk_vec3 q = bk_v3(p.chips[i].position[0], 0.0, p.chips[i].position[2]);
      farthest_chip = fmax(farthest_chip, bk_v3_length(bk_v3_sub(q, bk_v3(at.x, 0.0, at.z))));
    }
  }
  ENSURE_MSG(farthest_dust < 1.0, "dust %.2f m from the break", farthest_dust);
  ENSURE_MSG(lowest_chip > -1e-6, "a chip sank %.4f m into the ground", -lowest_chip);
  ENSURE_MSG(farthest_chip < 8.0, "a chip %.2f m away", farthest_chip);
  // After four seconds the chips lie still on the ground.
  for (uint32_t i = 0; i < p.count; ++i)
    if (p.items[i].kind == BK_PARTICLE_CHIP && p.items[i].life > 0.0f) {
      ENSURE_MSG(bk_v3_length(p.items[i].velocity) == 0.0 && bk_v3_length(p.items[i].spin) == 0.0,
                 "chip %u still moving at %.3f m/s", i, bk_v3_length(p.items[i].velocity));
      ENSURE(fabs(p.items[i].position.y - 0.5 * p.items[i].size) < 1e-6);
    }
  particles_free(&p);
}

int main(void) {
  emission_is_capped();
  everything_fades_to_nothing();
  colours_follow_the_material();
  positions_stay_near_the_break();
  printf("test_particles: ok\n");
  return 0;
}
