// Dust and debris: what a material sheds where a bond breaks, a bounded
// pool of particles simulated on the CPU, and their per-frame instances.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/bullet.h>

#include "render.h"

/// What a material sheds when it breaks (debris_look_of).
typedef struct app_debris_look {
  float dust[3];      ///< linear albedo of its dust (lit in the shader)
  float dust_opacity; ///< of a fresh puff; 0 = no dust
  float dust_size;    ///< a fresh puff's radius, metres
  float chip[3];      ///< multiplies the interior texture on its chips
  int glints;         ///< sparkles a broken bond throws instead of dust (glass)
  int material;       ///< row of debris_materials
} app_debris_look;

/// The materials debris_look_of knows, in the renderer's order.
enum { BK_DEBRIS_MATERIALS = 7 };
extern const char* const debris_materials[BK_DEBRIS_MATERIALS];
/// The look of a material by name (stone, brick, concrete, porcelain, glass, eggshell, wood; any
/// other name or NULL: stone).
app_debris_look debris_look_of(const char* material);

/// Caps that keep the count low and spend it on quality: a broken bond gives at most this many
/// puffs, glints and chips, and a step at most the per-step numbers over all its bonds.
enum {
  BK_PUFFS_PER_BREAK = 2,
  BK_GLINTS_PER_BREAK = 3,
  BK_CHIPS_PER_BREAK = 3,
  BK_PUFFS_PER_STEP = 8,
  BK_GLINTS_PER_STEP = 12,
  BK_CHIPS_PER_STEP = 24,
  BK_CRUMBLES_PER_STEP = 4, ///< bonds the load broke that shed anything (a grain puff and a crumb each)
};

typedef enum particle_kind { BK_PARTICLE_DUST, BK_PARTICLE_GLINT, BK_PARTICLE_CHIP } particle_kind;

/// One dust puff, glint or debris chip, simulated on the CPU.
typedef struct app_particle {
  bk_vec3 position, velocity, spin; ///< spin: a chip's angular velocity, rad/s
  float rotation[4];                ///< a chip's quaternion (x, y, z, w)
  float size, growth, life, max_life, gravity, seed;
  float color[4];
  particle_kind kind;
  int material; ///< a chip's row of debris_materials
  uint32_t shape;
} app_particle;

/// A bounded pool of particles (the oldest gives way to a new one) and their per-frame instances.
typedef struct app_particles {
  app_particle* items;
  particle_instance* instances; ///< puffs and glints of the last update
  chip_instance* chips;         ///< chips of the last update (chip_count of them)
  uint32_t count, capacity, next, chip_count;
  uint64_t emitted; ///< particles made since init
  /// The renderer's material index of each row of debris_materials (app_renderer_material);
  /// init sets the row itself, the renderer's own order.
  int renderer_material[BK_DEBRIS_MATERIALS];
  bk_rng rng;
} app_particles;

void particles_init(app_particles* particles, uint32_t capacity, uint64_t seed);
void particles_free(app_particles* particles);
/// Up to `chips` chips (at most BK_CHIPS_PER_BREAK) and, with `dust`, the material's dust (puffs, or
/// glints for glass) at one broken bond, within centimetres of it.
void particles_emit_break(app_particles* particles, const bk_break_event* event, const app_debris_look* look,
                          int chips, bool dust);
/// What a bond broken by the load it carried sheds: a faint puff of grains
/// sinking from the crack and a crumb dropping off, not an impact's burst.
void particles_emit_crumble(app_particles* particles, const bk_break_event* event,
                            const app_debris_look* look);
/// The material of a break event's breakable.
typedef app_debris_look (*debris_look_fn)(void* context, bk_breakable_id breakable);
/// A step's break events: dust and chips spread evenly over the bonds hits broke, crumbles over those
/// the load broke, within the per-step caps whatever the number of events. Returns the particles made.
uint32_t particles_emit_step(app_particles* particles, const bk_break_event* events, uint32_t count,
                             debris_look_fn look_of, void* context);
/// Advances by dt; fills `instances` with the live puffs and glints and returns their count, and
/// `chips` with the live chips (chip_count).
uint32_t particles_update(app_particles* particles, double dt);
