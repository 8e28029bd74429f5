// sim --save-state F.bkstate [--at STEP] and sim --load-state F.bkstate: a
// world's state written after some steps, and a run started from one.
#pragma once

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <breakables/bullet.h>

typedef struct sim_state {
  const char* save_path; ///< --save-state
  const char* load_path; ///< --load-state
  uint64_t at;           ///< --at: steps before the save
  bool at_given;
  size_t bytes;            ///< the saved state's size (0: not saved yet)
  bool failed;             ///< the save failed (its line printed): the run exits 1
  double save_ms, load_ms; ///< CPU time of the save (with its size) and of the load, without the file
} sim_state;

/// The options' help lines.
extern const char* const sim_state_help;
/// Nothing saved or loaded.
sim_state sim_state_default(void);
/// Parses argv[*i]: 0 when it was --save-state, --load-state or --at (its
/// value consumed), 1 when not, 2 on a bad or missing value (one line printed).
int sim_state_parse(int argc, char** argv, int* i, sim_state* s);
/// After the command line: --at without --save-state, --at past the run's
/// steps, and --steps 0 without --load-state are refused. Returns 0, or the
/// exit code (one line printed).
int sim_state_check(sim_state* s, uint64_t steps);
/// Before the first step: loads --load-state into the world. False (one
/// line printed: "breakables sim: --load-state F: state: ...") on failure.
bool sim_state_load(sim_state* s, bk_world* world);
/// After `done` steps (0: before the first): saves when it is the step to.
/// False (one line printed, failed set) when the file could not be written.
bool sim_state_after(sim_state* s, const bk_world* world, uint64_t done);
/// The JSON fields of a save ("state_bytes": N, "state_save_ms": T, ) and
/// of a load ("state_load_ms": T, ), nothing otherwise.
void sim_state_json(const sim_state* s, FILE* out);
