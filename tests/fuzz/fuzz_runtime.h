// fuzz_runtime's parts (fuzz_runtime.c plays the program, fuzz_runtime_check.c
// builds the trees and checks the runtime after each call): what they share.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/runtime.h>

#include "fuzz_util.h"

enum {
  TREE_COUNT = 4,
  MAX_BREAKABLES = 16, // added over a program (at most 8 live)
  MAX_LIVE_BREAKABLES = 8,
  MAX_OPS = 400,
  STALE_IDS = 16,
  MAX_CLUSTERS = 4096, // more than 8 breakables of 27 leaves can make
  MAX_LEAVES = 4096,   // of a tree, refined ones included
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
  char tag;                    // its user data is &tag
  bool removed;                // by bk_runtime_remove_breakable: its id is stale
  bool refined;                // a fragment of it was refined: its tree is the runtime's copy
  uint8_t retired[MAX_LEAVES]; // leaves whose cluster was removed
  double removed_volume;
} tracked;

typedef struct session {
  bk_runtime* rt;
  bk_body_state bodies[MAX_CLUSTERS]; // by cluster index, as the caller's physics has them
  tracked breakables[MAX_BREAKABLES];
  uint32_t breakable_count;       // added, the removed included
  bk_cluster_id stale[STALE_IDS]; // removed clusters, for stale ids
  uint32_t stale_count;
  bk_cluster_id live[MAX_CLUSTERS]; // after the last check
  uint32_t live_count;
  // The caller's mirror: the clusters whose created events it took (and
  // not their removal yet), each with the user data it gave it.
  bk_cluster_id known[MAX_CLUSTERS];
  void* user_data[MAX_CLUSTERS];
  // The events since the last take (they accumulate), the totals then.
  uint32_t created, removed, broken, bonds_broken;
  uint32_t live_at_take, bonds_at_take;
} session;

/// BK_FUZZ_TRACE=1 in the environment: each call and its results are
/// printed on stderr (to read what an input does).
extern bool bk_fuzz_trace;

/// The tracked breakable of an id, or NULL (stale, forged, refused).
tracked* bk_fuzz_find_tracked(session* s, bk_breakable_id id);
/// Checks every invariant of the runtime's state (see fuzz_runtime.c) and
/// refreshes the list of live clusters; `call` names the call for messages.
void bk_fuzz_check_state(session* s, const char* call);
/// Reads the events after a call and checks them against what happened since
/// the last take: the live count moved by created - removed, the bonds broken
/// are those counted (none from this call unless may_break), the call's new
/// broken bonds are dead; created clusters are live and unknown to the
/// caller, removed ones known.
void bk_fuzz_check_results(session* s, const char* call, uint32_t live_before, uint32_t bonds_before,
                           bool may_break);
/// A call that failed, a setter or a query: the events are unchanged.
void bk_fuzz_check_results_kept(session* s, const char* call);
/// Reads the events into buffers of `capacity` (< 4) entries: the totals come
/// back, nothing is written past them, and what is written is what a full
/// read gives first; the events are unchanged.
void bk_fuzz_check_short_pulls(session* s, uint32_t capacity);
/// Takes the events as a caller does (bodies made and dropped, user data
/// checked: inherited from the parent the caller knew, the breakable's on
/// its first cluster and on every event), clears them, and checks the
/// caller's mirror is the live set.
void bk_fuzz_take(session* s);
