// The runtime's registry: finding a breakable or a cluster by its id, a
// cluster's body where the caller keeps it, and the event lists every call
// that changes clusters adds to (created, removed). The core's files and the
// stress stage use these; the runtime object (runtime.c) only creates and
// destroys.
#include <string.h>

#include "runtime_internal.h"

bk_cluster_id rt_cluster_id(const bk_runtime* rt, uint32_t slot) {
  return (bk_cluster_id){slot, rt->clusters[slot].generation};
}

rt_cluster* rt_find_cluster(const bk_runtime* rt, bk_cluster_id id) {
  if (id.generation == 0 || id.index >= rt->cluster_count) return NULL;
  rt_cluster* c = &rt->clusters[id.index];
  return c->alive && c->generation == id.generation ? c : NULL;
}

rt_breakable* rt_find_breakable(const bk_runtime* rt, bk_breakable_id id) {
  if (id.generation == 0 || id.index >= rt->breakable_count) return NULL;
  rt_breakable* b = &rt->breakables[id.index];
  return b->alive && b->generation == id.generation ? b : NULL;
}

bk_body_state rt_body_state(const bk_runtime* rt, uint32_t slot) {
  // The caller has no body for a cluster whose created event it has not
  // taken: it is where that event puts it.
  uint32_t event = rt->clusters[slot].created_event;
  if (event) return rt->created[event - 1].body;
  bk_body_state state = rt->def.body_state(rt_cluster_id(rt, slot), rt->def.context);
  if (rt->clusters[slot].is_static) {
    state.linear_velocity = bk_v3(0, 0, 0);
    state.angular_velocity = bk_v3(0, 0, 0);
  }
  return state;
}

bk_transform rt_tree_to_world(const rt_cluster* c, const bk_body_state* state) {
  return bk_transform_mul(state->transform, bk_transform_inverse(c->principal));
}

bk_cluster_id rt_known_parent(const bk_runtime* rt, uint32_t slot) {
  uint32_t event = rt->clusters[slot].created_event;
  return event ? rt->created[event - 1].parent : rt_cluster_id(rt, slot);
}

bool rt_record_removed(bk_runtime* rt, uint32_t slot) {
  rt_cluster* c = &rt->clusters[slot];
  if (c->created_event) {
    // Never given to the caller: its created event goes, in order (a
    // rare case, between two clears, so the shift's cost does not matter).
    uint32_t at = c->created_event - 1;
    memmove(rt->created + at, rt->created + at + 1, sizeof(rt_created) * (rt->created_count - at - 1));
    rt->created_count--;
    for (uint32_t i = at; i < rt->created_count; ++i)
      rt->clusters[rt->created[i].slot].created_event = i + 1;
    c->created_event = 0;
    return false;
  }
  if (rt->removed_count == rt->removed_capacity) {
    rt->removed_capacity = bk_grow_capacity(rt->removed_capacity, rt->removed_count + 1);
    rt->removed = bk_realloc(rt->removed, sizeof(bk_cluster_removed) * rt->removed_capacity);
  }
  const rt_breakable* b = &rt->breakables[c->breakable];
  rt->removed[rt->removed_count++] = (bk_cluster_removed){.cluster = rt_cluster_id(rt, slot),
                                                          .breakable = {c->breakable, b->generation},
                                                          .user_data = c->user_data,
                                                          .breakable_user_data = b->user_data};
  return true;
}

// Member by member over a zeroed struct: a compound literal's padding is
// unspecified, and records must compare equal bytewise run to run.
static void fill_info(const bk_runtime* rt, uint32_t slot, bk_cluster_info* out) {
  const rt_cluster* c = &rt->clusters[slot];
  memset(out, 0, sizeof *out);
  out->id = rt_cluster_id(rt, slot);
  out->breakable = (bk_breakable_id){c->breakable, rt->breakables[c->breakable].generation};
  out->is_static = c->is_static;
  out->split_pending = c->dirty;
  out->leaves = c->leaves;
  out->leaf_count = c->leaf_count;
  out->nodes = c->nodes;
  out->node_count = c->node_count;
  out->mass = c->mass;
  out->volume = c->volume;
  out->principal = c->principal;
  out->inertia = c->inertia;
  out->user_data = c->user_data;
  out->breakable_user_data = rt->breakables[c->breakable].user_data;
}

void rt_record_created(bk_runtime* rt, uint32_t slot, bk_cluster_id parent, bk_transform tree_to_world,
                       const bk_body_state* parent_state) {
  if (rt->created_count == rt->created_capacity) {
    rt->created_capacity = bk_grow_capacity(rt->created_capacity, rt->created_count + 1);
    rt->created = bk_realloc(rt->created, sizeof(rt_created) * rt->created_capacity);
  }
  rt_created* record = &rt->created[rt->created_count++];
  memset(record, 0, sizeof *record);
  rt_cluster* c = &rt->clusters[slot];
  c->created_event = rt->created_count;
  record->slot = slot;
  record->parent = parent;
  record->body = (bk_body_state){.transform = bk_transform_mul(tree_to_world, c->principal)};
  if (!c->is_static && parent_state) {
    // A rigid body's velocity field evaluated at the new centre of mass.
    bk_vec3 r = bk_v3_sub(record->body.transform.position, parent_state->transform.position);
    record->body.linear_velocity =
        bk_v3_add(parent_state->linear_velocity, bk_v3_cross(parent_state->angular_velocity, r));
    record->body.angular_velocity = parent_state->angular_velocity;
  }
}

bool bk_runtime_cluster(const bk_runtime* rt, bk_cluster_id id, bk_cluster_info* out) {
  if (!rt_find_cluster(rt, id)) return false;
  fill_info(rt, id.index, out);
  return true;
}

void rt_remove_cluster(bk_runtime* rt, uint32_t slot) {
  rt_cluster* c = &rt->clusters[slot];
  rt_breakable* b = &rt->breakables[c->breakable];
  for (uint32_t i = 0; i < c->leaf_count; ++i)
    b->leaf_cluster[c->leaves[i]] = UINT32_MAX;
  rt_record_removed(rt, slot);
  rt_cluster_free(rt, slot);
}

uint32_t bk_runtime_created_clusters(const bk_runtime* rt, bk_cluster_created* out, uint32_t capacity) {
  uint32_t n = rt->created_count < capacity ? rt->created_count : capacity;
  for (uint32_t i = 0; out && i < n; ++i) {
    const rt_created* record = &rt->created[i];
    memset(&out[i], 0, sizeof out[i]); // padding too: records compare equal bytewise run to run
    fill_info(rt, record->slot, &out[i].cluster);
    out[i].parent = record->parent;
    out[i].body = record->body;
  }
  return rt->created_count;
}

uint32_t bk_runtime_removed_clusters(const bk_runtime* rt, bk_cluster_removed* out, uint32_t capacity) {
  uint32_t n = rt->removed_count < capacity ? rt->removed_count : capacity;
  if (n && out) memcpy(out, rt->removed, sizeof(bk_cluster_removed) * n);
  return rt->removed_count;
}

uint32_t bk_runtime_broken_bonds(const bk_runtime* rt, bk_bond_break* out, uint32_t capacity) {
  uint32_t n = rt->broken_count < capacity ? rt->broken_count : capacity;
  if (n && out) memcpy(out, rt->broken, sizeof(bk_bond_break) * n);
  return rt->broken_count;
}
