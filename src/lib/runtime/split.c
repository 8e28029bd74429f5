// Splitting (thesis 5.2.1-5.2.3, improved): only the cluster whose bonds
// broke is searched for connected components, over its own leaves and its
// surviving bonds; the rest of the graph is untouched (the thesis rebuilt the
// whole graph and measured that as half its break cost). Each component
// becomes a cluster with its minimal node set, exact mass properties, and the
// old body's motion at its new centre of mass (v + w x r). A budget of new
// clusters per call keeps one huge hit from stalling a frame: what does not
// fit waits for the next call, in order.
#include <stdlib.h>
#include <string.h>

#include "runtime_internal.h"

static void reserve_scratch(bk_runtime* w, uint32_t n) {
  if (n <= w->scratch_capacity) return;
  w->scratch_capacity = bk_grow_capacity(w->scratch_capacity, n);
  w->scratch_component = bk_realloc(w->scratch_component, sizeof(uint32_t) * w->scratch_capacity);
  w->scratch_stack = bk_realloc(w->scratch_stack, sizeof(uint32_t) * w->scratch_capacity);
}

// Labels the cluster's leaves by connected component (flood fill over the
// CSR graph); returns the component count. Labels go to scratch_component,
// indexed like c->leaves; leaf -> position through scratch_position (a
// cluster left over from a split budget is searched again every step, and a
// binary search per bond was most of that).
static uint32_t label_components(bk_runtime* w, const rt_cluster* c, uint32_t slot) {
  const rt_breakable* b = &w->breakables[c->breakable];
  uint32_t leaves = b->tree->leaf_count;
  if (leaves > w->scratch_position_capacity) {
    w->scratch_position_capacity = bk_grow_capacity(w->scratch_position_capacity, leaves);
    w->scratch_position = bk_realloc(w->scratch_position, sizeof(uint32_t) * w->scratch_position_capacity);
  }
  uint32_t* label = w->scratch_component;
  for (uint32_t i = 0; i < c->leaf_count; ++i) {
    label[i] = UINT32_MAX;
    w->scratch_position[c->leaves[i]] = i;
  }
  uint32_t components = 0;
  for (uint32_t start = 0; start < c->leaf_count; ++start) {
    if (label[start] != UINT32_MAX) continue;
    uint32_t top = 0;
    w->scratch_stack[top++] = start;
    label[start] = components;
    while (top) {
      uint32_t i = w->scratch_stack[--top];
      uint32_t leaf = c->leaves[i];
      for (uint32_t k = b->adjacency_start[leaf]; k < b->adjacency_start[leaf + 1]; ++k) {
        uint32_t bond = b->adjacency[k];
        if (b->bond_broken[bond]) continue;
        const bk_bond* bd = &b->tree->bonds[bond];
        uint32_t other = bd->leaf_a == leaf ? bd->leaf_b : bd->leaf_a;
        if (b->leaf_cluster[other] != slot) continue;
        uint32_t j = w->scratch_position[other]; // other is in this cluster: set above
        if (label[j] != UINT32_MAX) continue;
        label[j] = components;
        w->scratch_stack[top++] = j;
      }
    }
    components++;
  }
  return components;
}

// Replaces cluster `slot` by one cluster per component, creating at most
// max_bodies bodies. Over that, the components beyond the budget stay
// together with the largest one as a single body (for a step, invisibly)
// that is queued to split further next step. Returns the bodies created.
static uint32_t split_cluster(bk_runtime* w, uint32_t slot, uint32_t components, uint32_t max_bodies) {
  rt_cluster old = w->clusters[slot];
  bk_cluster_id known_parent = rt_known_parent(w, slot);
  bk_body_state state = rt_body_state(w, slot);
  bk_transform tree_to_world = rt_tree_to_world(&old, &state);
  const uint32_t* label = w->scratch_component;
  uint32_t* sizes = bk_calloc(components, sizeof(uint32_t));
  for (uint32_t i = 0; i < old.leaf_count; ++i)
    sizes[label[i]]++;
  // Which part each component goes to: its own, or the remainder (part 0,
  // always holding the largest component).
  uint32_t largest = 0;
  for (uint32_t k = 1; k < components; ++k)
    if (sizes[k] > sizes[largest]) largest = k;
  uint32_t* part_of = bk_alloc(sizeof(uint32_t) * components);
  uint32_t parts = 1;
  for (uint32_t k = 0; k < components; ++k)
    part_of[k] = k == largest || parts >= max_bodies || components <= 1 ? 0 : parts++;
  bool remainder_split = parts < components;
  uint32_t* part_sizes = bk_calloc(parts, sizeof(uint32_t));
  for (uint32_t k = 0; k < components; ++k)
    part_sizes[part_of[k]] += sizes[k];
  // The remainder's components, numbered in the same order (by their first
  // leaf): its next split starts from them instead of searching it again,
  // each step of a long wait (half the cost of a split step of a wall).
  uint32_t* remainder_labels = NULL;
  uint32_t* renumber = NULL; // a component's number in the remainder
  uint32_t remainder_components = 0;
  if (remainder_split) {
    remainder_labels = bk_alloc(sizeof(uint32_t) * part_sizes[0]);
    renumber = bk_alloc(sizeof(uint32_t) * components);
    for (uint32_t k = 0; k < components; ++k)
      renumber[k] = part_of[k] == 0 ? remainder_components++ : UINT32_MAX;
  }
  uint32_t** part_leaves = bk_alloc(sizeof(uint32_t*) * parts);
  for (uint32_t p = 0; p < parts; ++p) {
    part_leaves[p] = bk_alloc(sizeof(uint32_t) * part_sizes[p]);
    part_sizes[p] = 0;
  }
  for (uint32_t i = 0; i < old.leaf_count; ++i) {
    uint32_t p = part_of[label[i]];
    if (p == 0 && renumber) remainder_labels[part_sizes[0]] = renumber[label[i]];
    part_leaves[p][part_sizes[p]++] = old.leaves[i]; // stays ascending
  }
  bk_free(renumber);
  uint32_t breakable_index = old.breakable;
  rt_record_removed(w, slot);
  rt_cluster_free(w, slot);
  for (uint32_t p = 0; p < parts; ++p) {
    uint32_t s = rt_cluster_alloc(w, breakable_index);
    rt_cluster* c = &w->clusters[s];
    c->leaves = part_leaves[p];
    c->leaf_count = part_sizes[p];
    c->user_data = old.user_data; // the parent's, until the caller says otherwise
    rt_cluster_finish(w, s);
    if (p == 0 && remainder_split) {
      rt_queue_split(w, s); // before the record: it says so
      c->split_labels = remainder_labels;
      c->split_components = remainder_components;
    }
    rt_record_created(w, s, known_parent, tree_to_world, &state);
  }
  bk_free(part_leaves);
  bk_free(part_sizes);
  bk_free(part_of);
  bk_free(sizes);
  w->splits++;
  return parts;
}

uint32_t bk_runtime_split(bk_runtime* w) {
  if (w->split_queue_count) rt_journal_split(w, w->def.max_new_clusters_per_split);
  return rt_split(w, w->def.max_new_clusters_per_split);
}

uint32_t rt_split(bk_runtime* w, uint32_t budget) {
  uint32_t done = 0, created = 0;
  while (done < w->split_queue_count && budget >= 2) {
    uint32_t slot = w->split_queue[done++];
    rt_cluster* c = &w->clusters[slot];
    if (!c->alive || !c->dirty) continue;
    c->dirty = c->queued = false;
    reserve_scratch(w, c->leaf_count);
    uint32_t components = 0;
    if (c->split_labels) {
      memcpy(w->scratch_component, c->split_labels, sizeof(uint32_t) * c->leaf_count);
      components = c->split_components;
      bk_free(c->split_labels);
      c->split_labels = NULL;
    } else {
      components = label_components(w, c, slot);
    }
    if (components > 1) {
      uint32_t parts = split_cluster(w, slot, components, budget);
      budget -= parts;
      created += parts;
    }
  }
  if (done == 0) return 0;
  memmove(w->split_queue, w->split_queue + done, sizeof(uint32_t) * (w->split_queue_count - done));
  w->split_queue_count -= done;
  return created;
}
