// The simplest caller of the runtime, for its tests: a body per cluster,
// left where its created event put it, answered from a table the created
// events fill.
#pragma once

#include <stdint.h>
#include <stdlib.h>

#include <breakables/runtime.h>

#include "ensure.h"

typedef struct bodies {
  bk_body_state state[8192];
} bodies;

static inline bk_body_state body_state(bk_cluster_id cluster, void* context) {
  return ((bodies*)context)->state[cluster.index];
}

/// Takes the created clusters' bodies into `b`, then clears the events: the
/// next calls' events start afresh.
static inline void take_created(bk_runtime* rt, bodies* b) {
  uint32_t n = bk_runtime_created_clusters(rt, NULL, 0);
  bk_cluster_created* created = calloc(n + 1u, sizeof *created);
  bk_runtime_created_clusters(rt, created, n);
  for (uint32_t i = 0; i < n; ++i)
    b->state[created[i].cluster.id.index] = created[i].body;
  free(created);
  bk_runtime_clear_events(rt);
}
