// sim --record F.bkrec and sim --replay F.bkrec: a run's shots, weights and
// per-step hashes into a file, and a run made again from it, checked step by step.
#pragma once

#include <stdio.h>

#include "recording.h"
#include "scene_args.h"

typedef struct sim_record {
  const char* record_path; ///< --record
  const char* replay_path; ///< --replay
  bool hashes;             ///< record the hashes of every step (default; --record-no-hashes: not)
  recording rec;           ///< being recorded, or replayed
  uint32_t next;           ///< replay: the next event to apply
  uint64_t checked;        ///< replay: steps whose hashes were compared
  bool diverged, failed;
} sim_record;

/// The options' help lines.
extern const char* const sim_record_help;
/// Zeroed, recording hashes.
sim_record sim_record_default(void);
/// Parses argv[*i]: 0 when it was --record, --replay or --record-no-hashes
/// (its value consumed), 1 when not, 2 on a missing value (one line printed).
int sim_record_parse(int argc, char** argv, int* i, sim_record* r);
/// After the command line. A replay reads its file and takes the scene, its
/// options and the steps from it (no scripted shots or weight); other scene
/// options with it are refused. Returns 0, or the exit code (one line printed).
int sim_record_setup(sim_record* r, int argc, char** argv, scene_args* args, uint64_t* steps,
                     uint64_t* shots);
/// Once the scene is loaded and its focus set: a recording's first events.
void sim_record_start(sim_record* r, loaded_scene* scene, const char* mesh, const scene_options* options);
/// Fires shot `shot` of the volley at every copy before step `step`, as
/// loaded_scene_fire does, recording each projectile; returns how many.
uint32_t sim_record_fire(sim_record* r, loaded_scene* scene, uint64_t step, uint32_t shot, double speed);
/// Records a weight set down before step `step`.
void sim_record_weight(sim_record* r, uint64_t step, bk_vec3 surface, double kg, double radius);
/// A replay's events before step `step`; returns the projectiles fired.
uint32_t sim_record_step(sim_record* r, loaded_scene* scene, uint64_t step);
/// After step `step`: its hashes recorded, or compared with the recording's
/// (the first that differs printed in one line).
void sim_record_after(sim_record* r, loaded_scene* scene, uint64_t step);
/// At the end of `steps` steps: writes the recording, or says whether the
/// replay held; frees. False (one line printed) on a failure.
bool sim_record_finish(sim_record* r, uint64_t steps);
/// A replay's JSON field ("replay_steps_checked": N, ), nothing otherwise.
void sim_record_json(const sim_record* r, FILE* out);
/// Frees what it holds (an early exit).
void sim_record_free(sim_record* r);
