// A run's recording (.bkrec): everything that changes a run of a scene,
// each tagged with the step it applies before, so that a replay gives the
// same state at every step (sim --record/--replay, play --record-input/--replay).
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <breakables/bullet.h>

#include "scene_run.h"

/// What an event does.
typedef enum recording_kind {
  RECORDING_SCENE = 1,    ///< the scene (re)loaded with its options; the first event, at step 0
  RECORDING_FIRE = 2,     ///< bk_world_fire of a projectile
  RECORDING_WEIGHT = 3,   ///< app_drop_weight: a weight set down on a surface
  RECORDING_FOCUS = 4,    ///< bk_world_set_focus (the physics budget spares what is near it)
  RECORDING_MATERIAL = 5, ///< a breakable's material changed (the game's panel)
  RECORDING_STRESS = 6,   ///< bk_world_set_stress
  RECORDING_BUDGET = 7,   ///< bk_world_set_physics_budget
  RECORDING_KIND_END
} recording_kind;

/// Which world setter a material change went through: the one-field setters
/// touch less than bk_world_set_material (stress is not looked at again).
typedef enum recording_setter {
  RECORDING_SET_MATERIAL = 0,
  RECORDING_SET_FRAILTY = 1,
  RECORDING_SET_DENSITY = 2,
  RECORDING_SET_BOND_STRENGTH = 3,
  RECORDING_SET_END
} recording_setter;

enum {
  RECORDING_NAME_MAX = 63,   ///< a scene's or material's name, a unit's
  RECORDING_PATH_MAX = 1023, ///< a model's path
  /// Objects of a scene times its copies: the breakable a material change names
  RECORDING_BREAKABLES_MAX = 8 * BK_COPIES_MAX,
  RECORDING_STEPS_MAX = 10000000, ///< play's --frames at most
  RECORDING_EVENTS_MAX = 1 << 22, ///< 19 hours of a camera moving every frame in the game
};
/// Anything larger is not one of ours (a recording of the most steps, with
/// hashes, is 160 MB).
#define RECORDING_MAX_FILE_BYTES ((uint64_t)256 << 20)

/// A scene as loaded: which one, and every option that shapes its run.
typedef struct recording_scene {
  char name[RECORDING_NAME_MAX + 1];     ///< the scene's (a user's model's: its file's)
  char mesh[RECORDING_PATH_MAX + 1];     ///< a user's model (--mesh), or ""
  char material[RECORDING_NAME_MAX + 1]; ///< --material, or "" (options.material points here when set)
  char units[RECORDING_NAME_MAX + 1];    ///< --units, or ""
  double model_scale;                    ///< --scale
  scene_options options;                 ///< progress and material as recording_scene_options gives them
} recording_scene;

typedef struct recording_event {
  uint64_t step; ///< applies before this step (0: the first)
  recording_kind kind;
  union {
    uint32_t scene; ///< RECORDING_SCENE: index into recording.scenes
    bk_projectile_def fire;
    struct {
      bk_vec3 surface;
      double kg, radius;
    } weight;
    bk_vec3 focus;
    struct {
      uint32_t breakable; ///< the breakable's index in the world
      recording_setter setter;
      char name[RECORDING_NAME_MAX + 1];
      bk_material material; ///< name points nowhere: the name is above
    } material;
    bool stress;
    double budget_ms;
  };
} recording_event;

/// A whole recording, as written or read.
typedef struct recording {
  char program[RECORDING_NAME_MAX + 1]; ///< "breakables 0.1.0 sim"
  uint64_t steps;                       ///< the run's end: steps run in all
  bool has_hashes;                      ///< hashes[2 * s], [2 * s + 1]: state and world hash after step s
  recording_event* events;
  uint32_t event_count, event_capacity;
  recording_scene* scenes;
  uint32_t scene_count, scene_capacity;
  uint64_t* hashes;
  uint64_t hash_capacity; ///< in steps
} recording;

/// Frees what a recording holds and zeroes it.
void recording_free(recording* rec);
/// Appends an event (scene events: recording_add_scene).
void recording_add(recording* rec, const recording_event* event);
/// Appends a scene event at `step`: `scene` copied.
void recording_add_scene(recording* rec, uint64_t step, const recording_scene* scene);
/// Appends a material event at `step` for breakable `index`.
void recording_add_material(recording* rec, uint64_t step, uint32_t index, recording_setter setter,
                            const bk_material* material);
/// Keeps the hashes after step `step` (steps in order from 0).
void recording_add_hashes(recording* rec, uint64_t step, uint64_t state_hash, uint64_t world_hash);
/// The options of a scene event, ready for loaded_scene_create: material
/// pointing into the event's name (or NULL), no progress callback.
scene_options recording_scene_options(const recording_scene* scene);
/// A material event's material, its name pointing into the event.
bk_material recording_material(const recording_event* event);

/// The file's bytes (bk_free them); the same recording always gives the same bytes.
uint8_t* recording_encode(const recording* rec, size_t* size);
/// Reads a file's bytes into `out` (zeroed first; recording_free it). False
/// with one line in err->message, "NAME: what is wrong", for anything that is
/// not a whole, valid recording.
bool recording_decode(const uint8_t* data, size_t size, const char* name, recording* out, bk_error* err);
/// Writes a recording to `path` (whole, or not at all); false with err set.
bool recording_write(const recording* rec, const char* path, bk_error* err);
/// Reads `path`; false with err set ("PATH: ...").
bool recording_read(const char* path, recording* out, bk_error* err);
