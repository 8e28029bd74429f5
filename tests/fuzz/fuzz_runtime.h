// fuzz_runtime's parts (fuzz_runtime.c plays the program, fuzz_runtime_check.c
// builds the trees and checks the runtime after each call): what they share.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/runtime.h>

#include "fuzz_util.h"

enum {
  TREE_COUNT = 4,
  MAX_BREAKABLES = 8,
  MAX_OPS = 400,
  STALE_IDS = 16,
  MAX_CLUSTERS = 4096, // more than 8 breakables of 27 leaves can make
  MAX_LEAVES = 64,     // of a tree
};
#define REL_TOLERANCE 1e-9

/// The trees breakables are made of: a cube in 8 and in 27 pieces, a tower
/// in 12 standing on y = 0, a cube left whole (one leaf, no bonds).
extern bk_mesh_tree bk_fuzz_trees[TREE_COUNT];
/// Builds them, once per process.
void bk_fuzz_build_trees(void);

// ---------------------------------------------------------------- the caller's side

typedef struct tracked {
  bk_breakable_id id;
  uint32_t tree;
  uint8_t retired[MAX_LEAVES]; // leaves whose cluster was removed
  double removed_volume;
} tracked;

typedef struct session {
  bk_runtime* rt;
  bk_body_state bodies[MAX_CLUSTERS]; // by cluster index, as the caller's physics has them
  tracked breakables[MAX_BREAKABLES];
  uint32_t breakable_count;
  bk_cluster_id stale[STALE_IDS]; // removed clusters, for stale ids
  uint32_t stale_count;
  bk_cluster_id live[MAX_CLUSTERS]; // after the last check
  uint32_t live_count;
  // The results and totals after the last call.
  uint32_t created, removed, broken, bonds_broken;
} session;

/// BK_FUZZ_TRACE=1 in the environment: each call and its results are
/// printed on stderr (to read what an input does).
extern bool bk_fuzz_trace;

/// The tracked breakable of an id, or NULL (stale, forged, refused).
tracked* bk_fuzz_find_tracked(session* s, bk_breakable_id id);
/// Checks every invariant of the runtime's state (see fuzz_runtime.c) and
/// refreshes the list of live clusters; `call` names the call for messages.
void bk_fuzz_check_state(session* s, const char* call);
/// Pulls the results of the last call and checks them against what it may
/// have done: the live count moved by created - removed (their bodies are
/// made), broken bonds are dead and were counted (none unless may_break).
void bk_fuzz_check_results(session* s, const char* call, uint32_t live_before, uint32_t bonds_before,
                           bool may_break);
/// A call that failed, a setter or a query: the results are the last call's.
void bk_fuzz_check_results_kept(session* s, const char* call);
