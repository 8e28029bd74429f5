// The minimal mesh-tree node set of a cluster (thesis 5.2.2): the fewest
// nodes whose subtrees hold exactly the cluster's fragments. Leaves are
// numbered so every subtree is a contiguous range, so "does this subtree hold
// only cluster fragments" is a count over a range of the sorted leaf list.
#include <breakables/runtime.h>

// First index in [lo, hi) with leaves[i] >= value.
static uint32_t lower_bound(const uint32_t* leaves, uint32_t lo, uint32_t hi, uint32_t value) {
  while (lo < hi) {
    uint32_t mid = lo + (hi - lo) / 2;
    if (leaves[mid] < value)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

static uint32_t collect(const bk_mesh_tree* tree, uint32_t node, const uint32_t* leaves, uint32_t lo,
                        uint32_t hi, uint32_t* out, uint32_t count) {
  const bk_mesh_tree_node* n = &tree->nodes[node];
  uint32_t begin = lower_bound(leaves, lo, hi, n->leaf_begin);
  uint32_t end = lower_bound(leaves, begin, hi, n->leaf_end);
  if (begin == end) return count;
  if (end - begin == n->leaf_end - n->leaf_begin) {
    out[count++] = node; // the whole subtree belongs to the cluster
    return count;
  }
  for (uint32_t c = 0; c < n->child_count; ++c)
    count = collect(tree, n->first_child + c, leaves, begin, end, out, count);
  return count;
}

uint32_t bk_minimal_nodes(const bk_mesh_tree* tree, const uint32_t* leaves, uint32_t leaf_count,
                          uint32_t* out) {
  if (tree->node_count == 0 || leaf_count == 0) return 0;
  return collect(tree, 0, leaves, 0, leaf_count, out, 0);
}

static uint32_t expand(const bk_mesh_tree* tree, uint32_t node, const uint8_t* hull_fits, uint32_t* out,
                       uint32_t capacity, uint32_t count) {
  const bk_mesh_tree_node* n = &tree->nodes[node];
  if (n->child_count == 0 || (hull_fits && hull_fits[node])) {
    if (count < capacity) out[count] = node;
    return count + 1;
  }
  for (uint32_t c = 0; c < n->child_count; ++c)
    count = expand(tree, n->first_child + c, hull_fits, out, capacity, count);
  return count;
}

uint32_t bk_collider_nodes(const bk_mesh_tree* tree, const uint32_t* nodes, uint32_t node_count,
                           const uint8_t* hull_fits, uint32_t* out, uint32_t capacity) {
  uint32_t count = 0;
  for (uint32_t i = 0; i < node_count; ++i)
    if (nodes[i] < tree->node_count) count = expand(tree, nodes[i], hull_fits, out, capacity, count);
  return count;
}
