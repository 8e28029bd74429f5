// Dust and debris: at a bond a hit broke a few chips fly off with the body's
// motion and a soft dust puff drifts and fades; at one the load broke fine
// grains crumble and trickle down. A fixed-size pool keeps the count
// bounded; the oldest particle gives way to a new one.
#include <string.h>

#include "game.h"

void bk_particles_init(bk_particles* p, uint32_t capacity, uint64_t seed) {
  memset(p, 0, sizeof *p);
  p->capacity = capacity;
  p->items = bk_calloc(capacity, sizeof(bk_particle));
  p->instances = bk_calloc(capacity, sizeof(bk_particle_instance));
  p->rng = bk_rng_seed(seed, 7);
}

void bk_particles_free(bk_particles* p) {
  free(p->items);
  free(p->instances);
  memset(p, 0, sizeof *p);
}

static bk_particle* next_slot(bk_particles* p) {
  bk_particle* slot = &p->items[p->next];
  p->next = (p->next + 1) % p->capacity;
  if (p->count < p->capacity) p->count++;
  return slot;
}

static double jitter(bk_rng* rng, double amount) { return (bk_rng_unit(rng) * 2.0 - 1.0) * amount; }

void bk_particles_emit_break(bk_particles* p, const bk_break_event* e, const float tint[3], int chips,
                             bool dust) {
  double size = sqrt(e->area);
  // Chips: small, quick, ballistic, coloured like the material.
  for (int i = 0; i < chips; ++i) {
    bk_particle* c = next_slot(p);
    bk_vec3 kick = bk_v3(jitter(&p->rng, 2.0), 1.0 + bk_rng_unit(&p->rng) * 2.5, jitter(&p->rng, 2.0));
    *c = (bk_particle){.position = e->position,
                       .velocity = bk_v3_add(e->velocity, kick),
                       .size = (float)(0.012 + 0.02 * bk_rng_unit(&p->rng) * fmin(size * 8.0, 1.0)),
                       .life = 1.4f + (float)bk_rng_unit(&p->rng),
                       .kind = 1.0f,
                       .gravity = 1.0f};
    float shade = 0.7f + 0.3f * (float)bk_rng_unit(&p->rng);
    for (int k = 0; k < 3; ++k)
      c->color[k] = tint[k] * shade;
    c->color[3] = 1.0f;
    c->max_life = c->life;
  }
  // Dust: a soft puff, growing and fading.
  if (!dust) return;
  bk_particle* d = next_slot(p);
  *d = (bk_particle){.position = e->position,
                     .velocity = bk_v3_add(bk_v3_scale(e->velocity, 0.3),
                                           bk_v3(jitter(&p->rng, 0.3), 0.25, jitter(&p->rng, 0.3))),
                     .size = (float)(0.05 + 0.5 * size),
                     .growth = 0.2f,
                     .life = 1.2f + (float)bk_rng_unit(&p->rng) * 0.8f,
                     .kind = 0.0f,
                     .gravity = 0.0f};
  for (int k = 0; k < 3; ++k)
    d->color[k] = 0.55f + 0.35f * tint[k];
  d->color[3] = 0.35f;
  d->max_life = d->life;
}

void bk_particles_emit_crumble(bk_particles* p, const bk_break_event* e, const float tint[3]) {
  // A crack opening under load, not a blow: nothing is thrown. Fine grains
  // leave the bond with a fraction of its body's motion and fall slowly
  // (a tenth of gravity against the dust's drag settles them at about
  // 0.65 m/s), spreading a little, for a few seconds; they are darker than
  // impact dust, the colour of the broken stone rather than a light cloud.
  double size = sqrt(e->area);
  for (int i = 0; i < 4; ++i) {
    bk_particle* d = next_slot(p);
    bk_vec3 offset = bk_v3(jitter(&p->rng, 0.5), jitter(&p->rng, 0.5), jitter(&p->rng, 0.5));
    *d = (bk_particle){.position = bk_v3_add(e->position, bk_v3_scale(offset, size)),
                       .velocity = bk_v3_add(
                           bk_v3_scale(e->velocity, 0.2),
                           bk_v3(jitter(&p->rng, 0.08), -0.1 * bk_rng_unit(&p->rng), jitter(&p->rng, 0.08))),
                       .size = (float)(0.025 + 0.025 * bk_rng_unit(&p->rng)),
                       .growth = 0.04f,
                       .life = 2.5f + 1.5f * (float)bk_rng_unit(&p->rng),
                       .kind = 0.0f,
                       .gravity = 0.1f};
    float shade = 0.75f + 0.15f * (float)bk_rng_unit(&p->rng);
    for (int k = 0; k < 3; ++k)
      d->color[k] = tint[k] * shade;
    d->color[3] = 0.6f;
    d->max_life = d->life;
  }
  // One crumb: a small hard fleck that drops straight off.
  bk_particle* c = next_slot(p);
  *c = (bk_particle){.position = e->position,
                     .velocity = bk_v3_scale(e->velocity, 0.5),
                     .size = (float)(0.006 + 0.008 * bk_rng_unit(&p->rng)),
                     .life = 2.0f + (float)bk_rng_unit(&p->rng),
                     .kind = 1.0f,
                     .gravity = 1.0f};
  for (int k = 0; k < 3; ++k)
    c->color[k] = tint[k] * 0.8f;
  c->color[3] = 1.0f;
  c->max_life = c->life;
}

uint32_t bk_particles_update(bk_particles* p, double dt) {
  uint32_t n = 0;
  for (uint32_t i = 0; i < p->count; ++i) {
    bk_particle* q = &p->items[i];
    if (q->life <= 0.0f) continue;
    q->life -= (float)dt;
    if (q->life <= 0.0f) continue;
    q->velocity.y -= 9.81 * q->gravity * dt;
    q->velocity = bk_v3_scale(q->velocity, q->kind < 0.5f ? 1.0 - 1.5 * dt : 1.0); // dust drags to a stop
    q->position = bk_v3_add(q->position, bk_v3_scale(q->velocity, dt));
    if (q->position.y < q->size * 0.5) { // chips bounce and settle on the ground
      q->position.y = q->size * 0.5;
      q->velocity = bk_v3(q->velocity.x * 0.5, -q->velocity.y * 0.25, q->velocity.z * 0.5);
    }
    q->size += q->growth * (float)dt;
    float fade = q->life / q->max_life;
    bk_particle_instance* out = &p->instances[n++];
    out->position[0] = (float)q->position.x, out->position[1] = (float)q->position.y;
    out->position[2] = (float)q->position.z;
    out->size = q->size;
    memcpy(out->color, q->color, sizeof out->color);
    out->color[3] = q->color[3] * (q->kind < 0.5f ? fade : fminf(1.0f, fade * 3.0f));
    out->kind = q->kind;
  }
  return n;
}
