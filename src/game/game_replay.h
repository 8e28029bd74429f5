// play --record-input F.bkrec and play --replay F.bkrec: what changes the
// game's run (shots, weights, the panel's changes, scene switches and
// resets, the budget's focus) recorded by the step it applies before, and
// played back at the same steps with every step's hashes compared.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "recording.h"
#include "scene_run.h"

typedef struct game_replay {
  const char* record_path; ///< --record-input
  const char* replay_path; ///< --replay
  recording rec;
  uint64_t step;    ///< steps run since the start, over every scene loaded
  uint32_t next;    ///< replay: the next event
  uint64_t checked; ///< replay: steps whose hashes were compared
  bool diverged, failed;
  // What the last frame left, to record only changes (recording).
  bool focus_set, stress;
  bk_vec3 focus;
  double budget_ms;
  uint32_t material_count;
  bk_material materials[RECORDING_BREAKABLES_MAX];
  char names[RECORDING_BREAKABLES_MAX][RECORDING_NAME_MAX + 1];
} game_replay;

/// What a frame's steps do with a replay's events (game_replay_frame).
typedef struct game_replay_frame_io {
  int pending_steps;       ///< in: the steps the frame's time asks for; out: as many as reach the next event
  uint32_t shots, weights; ///< out: added by the events applied
  bool load;               ///< out: load scene `index` with `options` now, then call again
  uint32_t index;
  scene_options options;
  bool ended; ///< out: the recording is over (the game closes)
} game_replay_frame_io;

/// The options' help lines.
extern const char* const game_replay_help;
/// Parses argv[*i]: 0 when it was --record-input or --replay (its value
/// consumed), 1 when not, 2 on a missing value (one line printed).
int game_replay_parse(int argc, char** argv, int* i, game_replay* r);
/// After the command line: checks the files, reads a replay's recording and
/// takes its first scene (*scene_index) and its options. Other scene
/// options, --autofire and --benchmark with a replay are refused. Returns 0,
/// or the exit code (one line printed).
int game_replay_setup(game_replay* r, int argc, char** argv, const char* mesh, uint32_t* scene_index,
                      scene_options* options);
/// A scene was loaded (scene `index` with `options`): recorded, and what it starts with kept.
void game_replay_loaded(game_replay* r, const loaded_scene* scene, uint32_t index,
                        const scene_options* options);
/// Whether the player's own shots, weights, panel and reloads are ignored (a replay).
bool game_replay_playing(const game_replay* r);
/// Records a projectile fired (nothing when not recording).
void game_replay_fired(game_replay* r, const bk_projectile_def* shot);
/// Records a weight set down.
void game_replay_weight(game_replay* r, bk_vec3 surface, double kg, double radius);
/// Before the frame's steps, on the main thread: the camera `eye` made the
/// budget's focus and what changed since the last frame recorded, or a
/// replay's events due applied (see game_replay_frame_io).
void game_replay_frame(game_replay* r, loaded_scene* scene, bk_vec3 eye, game_replay_frame_io* io);
/// After each step, on the worker: its hashes recorded or compared.
void game_replay_step(game_replay* r, loaded_scene* scene);
/// At the end: writes the recording, prints the final hashes (stdout).
/// False (one line printed) on a failure: a replay that parted from its
/// recording, or a recording not written.
bool game_replay_finish(game_replay* r, loaded_scene* scene);
