// Trees that grow while the game runs: a breakable whose fragments are
// refined where they are hit (--refine) is drawn from the runtime's grown
// copy of its tree, whose new nodes the renderer must have before a body
// names them.
#pragma once

#include <stdint.h>

#include <breakables/bullet.h>

#include "render.h"

/// The scene objects whose trees are followed (loaded_scene.trees).
enum { GROWN_TREES_MAX = 8 };

/// New nodes of the scene's trees on their way to the renderer: made ready
/// on the thread that steps the world (the costly part), uploaded on the
/// GL thread between steps.
typedef struct app_grown_trees {
  uint32_t built[GROWN_TREES_MAX];         ///< nodes of each object's tree made ready or uploaded
  render_nodes* pending[GROWN_TREES_MAX];  ///< made ready, not uploaded yet
  uint32_t pending_first[GROWN_TREES_MAX]; ///< the first node of each pending
} app_grown_trees;

/// Starts over for a loaded scene of `count` objects whose render trees
/// were uploaded from `trees` (none: count 0); frees what was pending.
void grown_trees_reset(app_grown_trees* grown, const bk_mesh_tree* trees, uint32_t count);
/// On the thread that steps the world, after its steps: makes ready
/// (renderer_build_nodes) the nodes each object's tree gained, breakable
/// ids[i] being object i. Returns the nodes it made ready.
uint32_t grown_trees_build(app_grown_trees* grown, const bk_world* world, const bk_breakable_id* ids,
                           uint32_t count);
/// On the GL thread, between steps: uploads to render tree trees[i] what
/// was made ready of object i's tree, then anything it still lacks of the
/// tree the runtime has now (bk_runtime_breakable_tree: the tree it was
/// made from, or the runtime's own copy grown by appending nodes). Stale
/// ids and released render trees are skipped. Returns the nodes uploaded.
uint32_t grown_trees_upload(app_grown_trees* grown, app_renderer* renderer, const bk_world* world,
                            const bk_breakable_id* ids, const app_render_tree* trees, uint32_t count);
