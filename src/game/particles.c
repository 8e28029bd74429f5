// Dust and debris. At a bond a hit broke, a few chips of the material fly
// off with the body's motion, tumbling, bounce on the ground and come to
// rest, then fade; a soft puff or two of its dust (glass: a few glints)
// rises and spreads slowly from the break and fades. At a bond the load
// broke a faint puff of grains sinks from the crack and a crumb drops off.
// Few particles, capped per bond and per step: each puff is a large soft
// billboard and each chip a lit mesh. A fixed-size pool keeps the count
// bounded; the oldest particle gives way to a new one.
#include <string.h>

#include "particles.h"

const char* const debris_materials[BK_DEBRIS_MATERIALS] = {"stone", "brick",    "concrete", "porcelain",
                                                           "glass", "eggshell", "wood"};

// Dust colours are albedos (linear), lit in the shader: brick dust reddish,
// concrete grey, wood light brown, porcelain and eggshell pale and thin,
// glass none (it glints). Chips take the interior texture, tinted a little.
static const app_debris_look looks[BK_DEBRIS_MATERIALS] = {
    {.dust = {0.42f, 0.39f, 0.35f}, .dust_opacity = 0.8f, .dust_size = 0.13f, .chip = {1, 1, 1}},
    {.dust = {0.46f, 0.23f, 0.15f},
     .dust_opacity = 0.85f,
     .dust_size = 0.15f,
     .chip = {1, 1, 1},
     .material = 1},
    {.dust = {0.5f, 0.5f, 0.48f},
     .dust_opacity = 0.85f,
     .dust_size = 0.16f,
     .chip = {1, 1, 1},
     .material = 2},
    {.dust = {0.80f, 0.79f, 0.76f},
     .dust_opacity = 0.5f,
     .dust_size = 0.08f,
     .chip = {1, 1, 1},
     .material = 3},
    {.chip = {0.9f, 0.97f, 1.0f}, .glints = 3, .material = 4},
    {.dust = {0.75f, 0.70f, 0.60f},
     .dust_opacity = 0.45f,
     .dust_size = 0.07f,
     .chip = {1, 1, 1},
     .material = 5},
    {.dust = {0.55f, 0.40f, 0.24f},
     .dust_opacity = 0.7f,
     .dust_size = 0.11f,
     .chip = {1, 1, 1},
     .material = 6},
};

app_debris_look debris_look_of(const char* material) {
  for (int i = 0; i < BK_DEBRIS_MATERIALS; ++i)
    if (material && strcmp(material, debris_materials[i]) == 0) return looks[i];
  return looks[0];
}

void particles_init(app_particles* p, uint32_t capacity, uint64_t seed) {
  memset(p, 0, sizeof *p);
  p->capacity = capacity;
  p->items = bk_calloc(capacity, sizeof(app_particle));
  p->instances = bk_calloc(capacity, sizeof(particle_instance));
  p->chips = bk_calloc(capacity, sizeof(chip_instance));
  p->rng = bk_rng_seed(seed, 7);
  for (int i = 0; i < BK_DEBRIS_MATERIALS; ++i)
    p->renderer_material[i] = i;
}

void particles_free(app_particles* p) {
  bk_free(p->items);
  bk_free(p->instances);
  bk_free(p->chips);
  memset(p, 0, sizeof *p);
}

static app_particle* next_slot(app_particles* p) {
  app_particle* slot = &p->items[p->next];
  p->next = (p->next + 1) % p->capacity;
  if (p->count < p->capacity) p->count++;
  p->emitted++;
  return slot;
}

static double jitter(bk_rng* rng, double amount) { return (bk_rng_unit(rng) * 2.0 - 1.0) * amount; }

static bk_vec3 jitter3(bk_rng* rng, double amount) {
  return bk_v3(jitter(rng, amount), jitter(rng, amount), jitter(rng, amount));
}

// The body's velocity, at most `most` m/s: a fast piece must not carry dust
// metres away from where it broke.
static bk_vec3 carried(bk_vec3 velocity, double share, double most) {
  double speed = bk_v3_length(velocity) * share;
  return speed > most ? bk_v3_scale(velocity, most / bk_v3_length(velocity)) : bk_v3_scale(velocity, share);
}

static void emit_chip(app_particles* p, const bk_break_event* e, const app_debris_look* look, double scale,
                      bk_vec3 velocity, float life) {
  bk_rng* rng = &p->rng;
  app_particle* c = next_slot(p);
  bk_vec3 axis = bk_v3_normalize(bk_v3_add(jitter3(rng, 1.0), bk_v3(0.0, 0.0, 1e-3)));
  *c = (app_particle){
      .position = bk_v3_add(e->position, jitter3(rng, 0.02)),
      .velocity = velocity,
      .spin = bk_v3_scale(axis, 6.0 + 12.0 * bk_rng_unit(rng)),
      .rotation = {(float)jitter(rng, 1.0), (float)jitter(rng, 1.0), (float)jitter(rng, 1.0), 1.0f},
      .size = (float)((0.012 + 0.018 * bk_rng_unit(rng)) * scale),
      .life = life,
      .gravity = 1.0f,
      .kind = BK_PARTICLE_CHIP,
      .material = look->material,
      .shape = (uint32_t)(bk_rng_unit(rng) * 1024.0)};
  float shade = 0.85f + 0.25f * (float)bk_rng_unit(rng);
  for (int k = 0; k < 3; ++k)
    c->color[k] = look->chip[k] * shade;
  c->color[3] = 1.0f;
  c->max_life = c->life;
}

static void emit_puff(app_particles* p, const bk_break_event* e, const app_debris_look* look, double scale) {
  bk_rng* rng = &p->rng;
  app_particle* d = next_slot(p);
  bk_vec3 spread = bk_v3(jitter(rng, 0.2), 0.1 + 0.15 * bk_rng_unit(rng), jitter(rng, 0.2));
  *d = (app_particle){.position = bk_v3_add(e->position, jitter3(rng, 0.04)),
                      .velocity = bk_v3_add(carried(e->velocity, 0.15, 0.8), spread),
                      .size = (float)(look->dust_size * scale * (0.8 + 0.4 * bk_rng_unit(rng))),
                      .growth = (float)(look->dust_size * (0.6 + 0.4 * bk_rng_unit(rng))),
                      .life = 2.2f + (float)bk_rng_unit(rng),
                      .gravity = -0.015f, // warm dust rises, slowly
                      .seed = (float)(bk_rng_unit(rng) * 1000.0),
                      .kind = BK_PARTICLE_DUST};
  float shade = 0.9f + 0.2f * (float)bk_rng_unit(rng);
  for (int k = 0; k < 3; ++k)
    d->color[k] = look->dust[k] * shade;
  d->color[3] = look->dust_opacity;
  d->max_life = d->life;
}

static void emit_glint(app_particles* p, const bk_break_event* e) {
  bk_rng* rng = &p->rng;
  app_particle* g = next_slot(p);
  *g =
      (app_particle){.position = bk_v3_add(e->position, jitter3(rng, 0.05)),
                     .velocity = bk_v3_add(carried(e->velocity, 0.4, 2.0),
                                           bk_v3(jitter(rng, 1.0), 0.5 + bk_rng_unit(rng), jitter(rng, 1.0))),
                     .size = (float)(0.025 + 0.02 * bk_rng_unit(rng)),
                     .life = 0.4f + 0.5f * (float)bk_rng_unit(rng),
                     .gravity = 1.0f,
                     .kind = BK_PARTICLE_GLINT,
                     .color = {1.0f, 1.0f, 1.0f, 0.9f}};
  g->max_life = g->life;
}

// Bigger bonds, bigger bits, within limits.
static double bond_scale(const bk_break_event* e) { return fmin(fmax(sqrt(e->area) * 8.0, 0.6), 1.4); }

void particles_emit_break(app_particles* p, const bk_break_event* e, const app_debris_look* look, int chips,
                          bool dust) {
  double scale = bond_scale(e);
  int n = chips < BK_CHIPS_PER_BREAK ? chips : BK_CHIPS_PER_BREAK;
  for (int i = 0; i < n; ++i) {
    bk_vec3 kick = bk_v3(jitter(&p->rng, 1.5), 0.8 + 1.5 * bk_rng_unit(&p->rng), jitter(&p->rng, 1.5));
    emit_chip(p, e, look, scale, bk_v3_add(carried(e->velocity, 0.35, 4.0), kick),
              5.0f + 2.0f * (float)bk_rng_unit(&p->rng));
  }
  if (!dust) return;
  for (int i = 0; i < look->glints && i < BK_GLINTS_PER_BREAK; ++i)
    emit_glint(p, e);
  if (look->dust_opacity <= 0.0f) return;
  emit_puff(p, e, look, scale);
  emit_puff(p, e, look, scale * 0.7); // a second, smaller: one billboard reads flat
}

void particles_emit_crumble(app_particles* p, const bk_break_event* e, const app_debris_look* look) {
  // A crack opening under load, not a blow: nothing is thrown. A faint
  // puff, a little darker than an impact's, sinks slowly from the crack
  // (the colour of the broken stone rather than a light cloud), and a crumb
  // drops off with a share of its body's motion.
  double scale = bond_scale(e);
  if (look->dust_opacity > 0.0f) {
    emit_puff(p, e, look, scale * 0.6);
    app_particle* d = &p->items[(p->next + p->capacity - 1) % p->capacity];
    d->velocity =
        bk_v3_add(carried(e->velocity, 0.2, 0.5), bk_v3(jitter(&p->rng, 0.05), -0.08, jitter(&p->rng, 0.05)));
    d->gravity = 0.01f;
    d->growth *= 0.4f;
    d->life = d->max_life = 3.0f + (float)bk_rng_unit(&p->rng);
    for (int k = 0; k < 3; ++k)
      d->color[k] *= 0.8f;
    d->color[3] *= 0.7f;
  }
  emit_chip(p, e, look, scale * 0.7, carried(e->velocity, 0.5, 2.0), 4.0f + (float)bk_rng_unit(&p->rng));
}

uint32_t particles_emit_step(app_particles* p, const bk_break_event* events, uint32_t count,
                             debris_look_fn look_of, void* context) {
  uint32_t loaded = 0;
  uint64_t before = p->emitted;
  for (uint32_t i = 0; i < count; ++i)
    loaded += events[i].cause == BK_BREAK_STRESS;
  // Every so many events, evenly over the step's bonds, so that a big hit
  // is dusty all over and not just at the first bonds it reports.
  uint32_t hits = count - loaded;
  uint32_t dust_every = hits / (BK_PUFFS_PER_STEP / BK_PUFFS_PER_BREAK) + 1;
  uint32_t chip_every = hits / (BK_CHIPS_PER_STEP / BK_CHIPS_PER_BREAK) + 1;
  uint32_t crumble_every = loaded / BK_CRUMBLES_PER_STEP + 1;
  for (uint32_t i = 0, hit = 0, load = 0; i < count; ++i) {
    app_debris_look look = look_of(context, events[i].breakable);
    if (events[i].cause == BK_BREAK_STRESS) {
      if (load++ % crumble_every == 0) particles_emit_crumble(p, &events[i], &look);
      continue;
    }
    bool dust = hit % dust_every == 0;
    int chips = hit % chip_every == 0 ? BK_CHIPS_PER_BREAK : 0;
    hit++;
    if (dust || chips) particles_emit_break(p, &events[i], &look, chips, dust);
  }
  return (uint32_t)(p->emitted - before);
}

// A chip's orientation after dt of its spin: q += dt/2 (spin, 0) q.
static void turn(float q[4], bk_vec3 w, double dt) {
  float h = (float)(0.5 * dt), wx = (float)w.x * h, wy = (float)w.y * h, wz = (float)w.z * h;
  float x = q[0], y = q[1], z = q[2], s = q[3];
  q[0] += wx * s + wy * z - wz * y;
  q[1] += wy * s + wz * x - wx * z;
  q[2] += wz * s + wx * y - wy * x;
  q[3] -= wx * x + wy * y + wz * z;
  float length = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (int k = 0; k < 4; ++k)
    q[k] /= length;
}

// Chips fall, bounce on the ground (y = 0) losing most of their speed,
// slide to a stop and lie still.
static void move_chip(app_particle* c, double dt) {
  c->velocity.y -= 9.81 * dt;
  c->position = bk_v3_add(c->position, bk_v3_scale(c->velocity, dt));
  double rest = c->size * 0.5;
  if (c->position.y > rest) {
    turn(c->rotation, c->spin, dt);
    return;
  }
  c->position.y = rest;
  if (c->velocity.y < -0.5) { // a bounce
    c->velocity = bk_v3(c->velocity.x * 0.6, -c->velocity.y * 0.35, c->velocity.z * 0.6);
    c->spin = bk_v3_scale(c->spin, 0.5);
  } else { // sliding: friction stops it within a fraction of a second
    double keep = fmax(0.0, 1.0 - 8.0 * dt);
    c->velocity = bk_v3(c->velocity.x * keep, 0.0, c->velocity.z * keep);
    c->spin = bk_v3_scale(c->spin, keep);
    if (bk_v3_length(c->velocity) < 0.02) c->velocity = c->spin = bk_v3(0.0, 0.0, 0.0);
  }
  turn(c->rotation, c->spin, dt);
}

uint32_t particles_update(app_particles* p, double dt) {
  uint32_t n = 0;
  p->chip_count = 0;
  for (uint32_t i = 0; i < p->count; ++i) {
    app_particle* q = &p->items[i];
    if (q->life <= 0.0f) continue;
    q->life -= (float)dt;
    if (q->life <= 0.0f) continue;
    float left = q->life / q->max_life, age = q->max_life - q->life;
    if (q->kind == BK_PARTICLE_CHIP) {
      move_chip(q, dt);
      chip_instance* out = &p->chips[p->chip_count++];
      *out = (chip_instance){.position = {(float)q->position.x, (float)q->position.y, (float)q->position.z},
                             .size = q->size,
                             .rotation = {q->rotation[0], q->rotation[1], q->rotation[2], q->rotation[3]},
                             .tint = {q->color[0], q->color[1], q->color[2]},
                             .fade = q->life < 0.8f ? 1.0f - q->life / 0.8f : 0.0f, // the last 0.8 s
                             .material = p->renderer_material[q->material],
                             .shape = q->shape};
      continue;
    }
    q->velocity.y -= 9.81 * q->gravity * dt;
    if (q->kind == BK_PARTICLE_DUST) { // dust drags to a stop and spreads, ever more slowly
      q->velocity = bk_v3_scale(q->velocity, fmax(0.0, 1.0 - 2.5 * dt));
      q->size += q->growth * (float)dt;
      q->growth *= fmaxf(0.0f, 1.0f - 0.7f * (float)dt);
    }
    q->position = bk_v3_add(q->position, bk_v3_scale(q->velocity, dt));
    if (q->position.y < q->size * 0.3) q->position.y = q->size * 0.3; // resting on the ground, half sunk
    particle_instance* out = &p->instances[n++];
    // Puffs come in quickly (no pop) and thin out as they spread; glints flicker out.
    float opacity = q->kind == BK_PARTICLE_DUST ? fminf(1.0f, age / 0.12f) * left * sqrtf(left) : left;
    *out = (particle_instance){.position = {(float)q->position.x, (float)q->position.y, (float)q->position.z},
                               .size = q->size,
                               .color = {q->color[0], q->color[1], q->color[2], q->color[3] * opacity},
                               .kind = q->kind == BK_PARTICLE_GLINT ? 1.0f : 0.0f,
                               .seed = q->seed};
  }
  return n;
}
