// Trees that grow while the game runs. The runtime lands a refinement inside
// a world step (bk_runtime_refine): the refined fragment becomes an inner
// node and its pieces are appended as new nodes, numbered after every node
// the tree had, which keep their numbers and meshes. So the renderer's copy
// of a tree is brought up to date by its node count alone, whatever copy of
// the tree the runtime holds now (its pointer changes at the first
// refinement and may change at each one after). Decimating the new nodes'
// coarse copies costs about 0.1 ms a node: it is done on the worker that
// steps the world, right after the steps, and the GL thread only copies
// the result into its buffers.
#include "grown_trees.h"

#include <string.h>

void grown_trees_reset(app_grown_trees* grown, const bk_mesh_tree* trees, uint32_t count) {
  for (uint32_t i = 0; i < GROWN_TREES_MAX; ++i)
    renderer_free_nodes(grown->pending[i]);
  memset(grown, 0, sizeof *grown);
  for (uint32_t i = 0; i < count && i < GROWN_TREES_MAX; ++i)
    grown->built[i] = trees[i].node_count;
}

uint32_t grown_trees_build(app_grown_trees* grown, const bk_world* world, const bk_breakable_id* ids,
                           uint32_t count) {
  const bk_runtime* runtime = bk_world_runtime(world);
  uint32_t made = 0;
  for (uint32_t i = 0; i < count && i < GROWN_TREES_MAX; ++i) {
    const bk_mesh_tree* tree = bk_runtime_breakable_tree(runtime, ids[i]);
    if (!tree || tree->node_count <= grown->built[i]) continue;
    // Not uploaded since the last build: made again with the new nodes, in
    // one piece, so that what is pending always follows what was uploaded.
    uint32_t first = grown->pending[i] ? grown->pending_first[i] : grown->built[i];
    render_nodes* nodes = renderer_build_nodes(tree, first, tree->node_count);
    if (!nodes) continue;
    renderer_free_nodes(grown->pending[i]);
    grown->pending[i] = nodes;
    grown->pending_first[i] = first;
    made += tree->node_count - grown->built[i];
    grown->built[i] = tree->node_count;
  }
  return made;
}

uint32_t grown_trees_upload(app_grown_trees* grown, app_renderer* renderer, const bk_world* world,
                            const bk_breakable_id* ids, const app_render_tree* trees, uint32_t count) {
  const bk_runtime* runtime = bk_world_runtime(world);
  uint32_t added = 0;
  for (uint32_t i = 0; i < count && i < GROWN_TREES_MAX; ++i) {
    if (grown->pending[i]) added += renderer_append_nodes(renderer, trees[i], grown->pending[i]);
    grown->pending[i] = NULL;
    // Whatever was not made ready on the worker (or could not be appended).
    const bk_mesh_tree* tree = bk_runtime_breakable_tree(runtime, ids[i]);
    uint32_t uploaded = renderer_tree_node_count(renderer, trees[i]);
    if (tree && uploaded > 0 && tree->node_count > uploaded)
      added += renderer_grow_tree(renderer, trees[i], tree);
    uploaded = renderer_tree_node_count(renderer, trees[i]);
    if (uploaded > 0) grown->built[i] = uploaded;
  }
  return added;
}
