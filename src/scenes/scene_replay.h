// What a recording's events do to a loaded scene, the same in sim and play.
#pragma once

#include "recording.h"
#include "scene_run.h"

/// A scene event of what is loaded now: `scene` (a user's model: its file
/// `mesh`) with `options`, and the model units of the command line.
recording_scene replay_scene_of(const app_scene* scene, const char* mesh, const scene_options* options);
/// The scene index a scene event names (a user's model is added again, and
/// its units and scale set as the recording had them); UINT32_MAX with err set.
uint32_t replay_scene_index(const recording_scene* scene, bk_error* err);
/// Applies an event other than a scene's to the loaded scene before its next
/// step; returns the projectiles it fired (a weight is none). False in
/// *applied (err set) when the world refused it.
uint32_t replay_apply(loaded_scene* scene, const recording_event* event, bool* applied, bk_error* err);
/// The setter a change of material from `before` to `after` goes through
/// (one field changed: its own setter), and whether anything changed.
bool replay_material_change(const bk_material* before, const bk_material* after, recording_setter* setter);
/// The state and world hashes of a scene now.
void replay_hashes(loaded_scene* scene, uint64_t* state_hash, uint64_t* world_hash);
/// Whether the hashes after step `step` (0: the first) are the recording's;
/// when not, prints the one line that says which differs ("breakables
/// COMMAND: replay: step S differs: ...", S counted as --hash-every counts:
/// the state after S steps).
bool replay_check(const recording* rec, uint64_t step, uint64_t state_hash, uint64_t world_hash,
                  const char* command);
