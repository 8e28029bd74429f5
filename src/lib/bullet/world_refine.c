// Refinement in the world: once a step, after its hits and before its split,
// the runtime lands the fragments it has fractured again around a hit
// (bk_runtime_refine). Each refined fragment's node becomes an inner node of
// the breakable's own grown tree and keeps its hull, so its body does not
// change; the world's per-node arrays grow here, and the new nodes get
// their hulls when the split that follows (the bonds the waiting hits
// broke), or a later one, first makes a body of them. Nothing of the world holds leaf
// numbers, which a refinement moves up: views, colliders and retired records
// name nodes, whose numbers never change, and read leaves from the runtime.
#include <string.h>
#include <time.h>

#include "world_internal.h"

// CPU time of this thread (ms): the refinement's fracture runs on a worker,
// and what the step pays for is the landing and the hulls.
static double thread_cpu_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

/// The hulls of a refinement's pieces, nodes 1.. of its pieces tree.
typedef struct refine_hulls {
  uint32_t count;
  bk_hull_prepared hulls[];
} refine_hulls;

void* bk_world_refine_prepare(const bk_mesh_tree* pieces, void* context) {
  const bk_world* w = context;
  if (pieces->node_count < 2) return NULL;
  double margin = w->hull_margin; // set once the physics world exists; never changes
  uint32_t count = pieces->node_count - 1;
  refine_hulls* r = bk_alloc(sizeof *r + sizeof(bk_hull_prepared) * count);
  r->count = count;
  bk_vec3 points[BK_WORLD_HULL_POINTS];
  for (uint32_t j = 0; j < count; ++j) {
    uint32_t n = bk_world_hull_points(&pieces->nodes[j + 1].mesh, points);
    bk_physics_prepare_hull(points, n, 64, margin, &r->hulls[j]);
  }
  return r;
}

void bk_world_refine_discard(void* prepared, void* context) {
  (void)context;
  bk_free(prepared);
}

// The new nodes' hulls from what the worker prepared (microseconds each).
static void take_hulls(bk_world* w, world_breakable* wb, const bk_leaf_refined* event) {
  const refine_hulls* r = event->prepared;
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(w->runtime, wb->id);
  for (uint32_t j = 0; r && tree && j < r->count && j < event->splice.node_count; ++j) {
    uint32_t node = event->splice.first_node + j;
    if (node >= wb->node_count || wb->hull_fits[node] != HULL_LATER) continue;
    const bk_mesh_tree_node* n = &tree->nodes[node];
    wb->node_hull[node] = bk_physics_create_prepared_hull(w->physics, &r->hulls[j]);
    // As bk_world_prepare_hulls judges a node's hull (world_bodies.c).
    bool fits = wb->convex_colliders || n->child_count == 0 ||
                (!bk_shape_is_null(wb->node_hull[node]) &&
                 r->hulls[j].volume <= (1.0 + wb->convexity_tolerance) * n->moments.v);
    wb->hull_fits[node] = fits ? 1 : 0;
  }
}

void bk_world_take_refined(bk_world* w) {
  uint32_t count = bk_runtime_refined_leaves(w->runtime, NULL, 0);
  if (count > w->refined_capacity) {
    w->refined_capacity = bk_grow_capacity(w->refined_capacity, count);
    w->refined = bk_realloc(w->refined, sizeof(bk_leaf_refined) * w->refined_capacity);
  }
  bk_runtime_refined_leaves(w->runtime, w->refined, w->refined_capacity);
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t index = w->refined[i].breakable.index;
    // The new nodes' places, for every refinement of the breakable at once
    // (nodes are appended, so those past its node_count are the new ones).
    if (index < w->breakable_count &&
        w->breakables[index].id.generation == w->refined[i].breakable.generation) {
      bk_world_prepare_hulls(w, index);
      take_hulls(w, &w->breakables[index], &w->refined[i]);
    }
    bk_free(w->refined[i].prepared);
    w->refined[i].prepared = NULL;
  }
}

void bk_world_refine(bk_world* w) {
  // Nothing marked, nothing to land: the step had no refinement (0 ms).
  bool pending = bk_runtime_get_stats(w->runtime).refine_pending > 0;
  double start = thread_cpu_ms();
  bk_runtime_refine(w->runtime);
  // The refinements are taken before bk_world_collect_breaks clears the
  // runtime's events (they come only from bk_runtime_refine, so none is
  // lost): the bonds the waiting hits broke become break events as a
  // hit's do.
  bool refined = bk_runtime_refined_leaves(w->runtime, NULL, 0) > 0;
  bk_world_take_refined(w);
  bk_world_collect_breaks(w);
  w->refine_ms = pending || refined ? thread_cpu_ms() - start : 0.0;
}
