// Internal to the executable: the interactive game and editor.
#pragma once

#include <stdlib.h>

#include "app.h"
#include "bk_render.h"

/// One dust puff or debris chip, simulated on the CPU.
typedef struct bk_particle {
  bk_vec3 position, velocity;
  float size, growth, life, max_life, kind, gravity;
  float color[4];
} bk_particle;

/// A bounded pool of particles and their per-frame instance data.
typedef struct bk_particles {
  bk_particle* items;
  bk_particle_instance* instances;
  uint32_t count, capacity, next;
  bk_rng rng;
} bk_particles;

void bk_particles_init(bk_particles* particles, uint32_t capacity, uint64_t seed);
void bk_particles_free(bk_particles* particles);
/// `chips` debris chips and optionally a dust puff at one broken bond, tinted like the material.
void bk_particles_emit_break(bk_particles* particles, const bk_break_event* event, const float tint[3],
                             int chips, bool dust);
/// What a bond broken by the load it carried sheds: a few fine, slow grains
/// and a crumb trickling down from it, not an impact's burst.
void bk_particles_emit_crumble(bk_particles* particles, const bk_break_event* event, const float tint[3]);
/// Advances by dt; fills `instances` with the live ones and returns their count.
uint32_t bk_particles_update(bk_particles* particles, double dt);

/// A thread that runs one job at a time (the game's physics steps, while the
/// driver draws the frame). Touch nothing the job uses until bk_worker_wait.
typedef struct bk_worker bk_worker;
/// NULL if no thread can be started (the caller then runs jobs itself).
bk_worker* bk_worker_create(void);
/// Waits for the job in progress, then ends the thread.
void bk_worker_destroy(bk_worker* worker);
/// Runs job(argument) on the worker, after waiting for the previous job.
void bk_worker_start(bk_worker* worker, void (*job)(void*), void* argument);
/// Returns once no job is running.
void bk_worker_wait(bk_worker* worker);

/// Options shared by `play` and `editor`.
typedef struct bk_window_options {
  int width, height;
  uint32_t frames;        ///< 0 = run until closed
  uint32_t autofire;      ///< projectiles fired at the target over the run
  const char* screenshot; ///< PNG of the last frame
} bk_window_options;

/// Parses the options both windowed commands share; returns 0 if `arg` was
/// one of them (consuming its value), 1 if not ours, or 2 on a bad value.
int bk_parse_window_option(const char* command, int argc, char** argv, int* i, bk_window_options* options);

/// Opens a window with a GL 3.3 core context and the renderer.
bool bk_window_open(const char* title, const bk_window_options* options, void** window,
                    bk_renderer** renderer, bk_error* err);
void bk_window_close(void* window, bk_renderer* renderer);
/// Shader directory next to the executable (or in the source tree).
const char* bk_app_shader_dir(void);
