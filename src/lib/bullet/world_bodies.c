// Cluster bodies: one Bullet body per runtime cluster. Its compound is made
// of the hulls of the cluster's collider nodes (the minimal node set, with a
// node whose hull would overestimate it replaced by its children); its mass
// properties and body frame (the principal frame) come from the runtime.
#include <stdlib.h>
#include <string.h>

#include "world_internal.h"

// The node's hull in its own principal frame, for a body that is that node alone.
static bk_shape_id make_body_hull(bk_world* w, const bk_mesh_tree* tree, uint32_t node) {
  bk_mass_properties mp = bk_mesh_tree_mass(tree, tree->nodes[node].moments);
  double values[3] = {0}, axes[3][3] = {{0}};
  bk_sym3_eigen(mp.inertia, values, axes);
  bk_transform to_body = bk_transform_inverse((bk_transform){mp.centroid, bk_quat_from_matrix(axes)});
  const bk_mesh* mesh = &tree->nodes[node].mesh;
  bk_vec3* local = bk_alloc(sizeof(bk_vec3) * (mesh->position_count + 1u));
  for (uint32_t i = 0; i < mesh->position_count; ++i)
    local[i] = bk_transform_point(to_body, mesh->positions[i]);
  bk_shape_id hull = bk_physics_create_hull(w->physics, local, mesh->position_count, 64);
  bk_free(local);
  return hull;
}

// Grows a per-node array from `from` to `to` elements of `size`, the new ones zero.
static void* grow_nodes(void* array, uint32_t from, uint32_t to, size_t size) {
  array = bk_realloc(array, size * (to + 1u));
  memset((char*)array + size * from, 0, size * (to + 1u - from));
  return array;
}

// A node's hull in the tree frame, and whether it may stand for the node.
static void make_node_hull(bk_world* w, world_breakable* wb, const bk_mesh_tree* tree, uint32_t i) {
  const bk_mesh_tree_node* n = &tree->nodes[i];
  const bk_mesh* mesh = &n->mesh;
  if (wb->hull_fits[i] == HULL_LATER) {
    // A refined node: its hull from its support points (hull_points.c),
    // made in the step a body needs it.
    bk_vec3 points[BK_WORLD_HULL_POINTS];
    uint32_t count = bk_world_hull_points(mesh, points);
    wb->node_hull[i] = bk_physics_create_hull(w->physics, points, count, 64);
  } else {
    wb->node_hull[i] = bk_physics_create_hull(w->physics, mesh->positions, mesh->position_count, 64);
  }
  // A node's hull may stand for it when it hardly overestimates the node
  // (a hollow egg's hull is a solid egg, so its children are used instead).
  if (wb->convex_colliders || n->child_count == 0) {
    wb->hull_fits[i] = 1;
  } else {
    double hull_volume =
        bk_shape_is_null(wb->node_hull[i]) ? INFINITY : bk_physics_hull_volume(w->physics, wb->node_hull[i]);
    wb->hull_fits[i] = hull_volume <= (1.0 + wb->convexity_tolerance) * n->moments.v;
  }
}

void bk_world_prepare_hulls(bk_world* w, uint32_t breakable_index) {
  world_breakable* wb = &w->breakables[breakable_index];
  // Re-read: a refinement may have grown the tree into the runtime's own copy.
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(w->runtime, wb->id);
  uint32_t first = wb->node_count;
  if (!tree || tree->node_count <= first) return;
  wb->node_hull = grow_nodes(wb->node_hull, first, tree->node_count, sizeof(bk_shape_id));
  wb->node_body_hull = grow_nodes(wb->node_body_hull, first, tree->node_count, sizeof(bk_shape_id));
  wb->hull_fits = grow_nodes(wb->hull_fits, first, tree->node_count, 1);
  wb->node_count = tree->node_count;
  // Existing nodes keep their hulls: a refined fragment's node, now an
  // inner one, keeps the hull (and hull_fits) it had as a leaf, which
  // stands for exactly its pieces' union, so its body does not change.
  // A refinement's new nodes get theirs when a body first needs them
  // (ensure_hulls): the same hulls, but only those used. Made at once they
  // cost 14 ms a refinement of 32 pieces (62 nodes, on this project's
  // 2-core machine) in the step it lands, and the pieces' inner nodes,
  // most of it, are seldom colliders: the hits that refined the fragment
  // break most of its pieces' bonds.
  wb->grown = wb->grown || first > 0;
  for (uint32_t i = first; i < tree->node_count; ++i) {
    if (first > 0)
      wb->hull_fits[i] = HULL_LATER;
    else
      make_node_hull(w, wb, tree, i);
  }
  // And a piece's body hull when it becomes a body alone, moved from its
  // node hull (build_body): microseconds, where making one costs as much.
  if (first > 0) return;
  for (uint32_t l = 0; l < tree->leaf_count; ++l)
    wb->node_body_hull[tree->leaf_nodes[l]] = make_body_hull(w, tree, tree->leaf_nodes[l]);
}

static void reserve_bodies(bk_world* w, uint32_t index) {
  if (index < w->body_capacity) return;
  uint32_t capacity = bk_grow_capacity(w->body_capacity, index + 1u);
  w->bodies = bk_realloc(w->bodies, sizeof(world_body) * capacity);
  memset(w->bodies + w->body_capacity, 0, sizeof(world_body) * (capacity - w->body_capacity));
  w->body_capacity = capacity;
}

// Makes the hulls bk_collider_nodes visits from `node` (it stops at a node
// whose hull fits) that a refinement left for later.
static void ensure_hulls(bk_world* w, world_breakable* wb, const bk_mesh_tree* tree, uint32_t node) {
  if (wb->hull_fits[node] == HULL_LATER) make_node_hull(w, wb, tree, node);
  const bk_mesh_tree_node* n = &tree->nodes[node];
  if (n->child_count == 0 || wb->hull_fits[node]) return;
  for (uint32_t c = 0; c < n->child_count; ++c)
    ensure_hulls(w, wb, tree, n->first_child + c);
}

static void choose_colliders(bk_world* w, world_breakable* wb, const bk_cluster_info* info,
                             world_body* wbody) {
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(w->runtime, info->breakable);
  uint32_t count = 0;
  if (wb->grown) {
    for (uint32_t i = 0; wb->naive && i < info->leaf_count; ++i)
      ensure_hulls(w, wb, tree, tree->leaf_nodes[info->leaves[i]]);
    for (uint32_t i = 0; !wb->naive && i < info->node_count; ++i)
      ensure_hulls(w, wb, tree, info->nodes[i]);
  }
  if (wb->naive) {
    // Plain BCRB: every fragment is a collider.
    wbody->colliders = bk_realloc(wbody->colliders, sizeof(uint32_t) * (info->leaf_count + 1u));
    for (uint32_t i = 0; i < info->leaf_count; ++i)
      wbody->colliders[count++] = tree->leaf_nodes[info->leaves[i]];
  } else {
    uint32_t needed = bk_collider_nodes(tree, info->nodes, info->node_count, wb->hull_fits, NULL, 0);
    wbody->colliders = bk_realloc(wbody->colliders, sizeof(uint32_t) * (needed + 1u));
    count = bk_collider_nodes(tree, info->nodes, info->node_count, wb->hull_fits, wbody->colliders, needed);
  }
  // Nodes too flat for a hull have none and add nothing.
  uint32_t kept = 0;
  for (uint32_t i = 0; i < count; ++i)
    if (!bk_shape_is_null(wb->node_hull[wbody->colliders[i]])) wbody->colliders[kept++] = wbody->colliders[i];
  wbody->collider_count = kept;
}

// `loose_since`: the step its bonds broke, earlier than now when the split
// waited for the split budget; the budget's first second counts from it.
static bool build_body(bk_world* w, const bk_cluster_created* created, uint64_t loose_since, bk_error* err) {
  const bk_cluster_info* info = &created->cluster;
  uint32_t index = info->id.index;
  reserve_bodies(w, index);
  world_body* wbody = &w->bodies[index];
  uint32_t* colliders = wbody->colliders;
  memset(wbody, 0, sizeof *wbody);
  wbody->colliders = colliders;
  wbody->alive = true;
  wbody->cluster = info->id;
  wbody->breakable = info->breakable.index; // the world adds breakables in the runtime's order
  world_breakable* wb = &w->breakables[wbody->breakable];
  choose_colliders(w, wb, info, wbody);

  bk_material material = bk_runtime_material(w->runtime, info->breakable);
  bk_transform child_local = bk_transform_inverse(info->principal);
  bk_body_def def = bk_default_body_def();
  def.shape = (bk_shape_id){0, 0};
  if (wbody->collider_count == 1 && info->node_count == 1 && wbody->colliders[0] == info->nodes[0]) {
    // One node, one hull (every loose fragment): its principal frame is the
    // body frame, so a hull made in that frame needs no compound. That keeps
    // fragment pairs off Bullet's costly compound-compound path. A fragment's
    // was made at load time; a larger node's is its tree-frame hull moved
    // into that frame, once: computing a hull here cost 40-80 us a body,
    // half the break work of the step that needed a few.
    uint32_t node = info->nodes[0];
    if (bk_shape_is_null(wb->node_body_hull[node]))
      wb->node_body_hull[node] = bk_physics_copy_hull(w->physics, wb->node_hull[node], child_local);
    def.shape = wb->node_body_hull[node];
  }
  if (bk_shape_is_null(def.shape)) {
    // Children are hulls in the tree frame; the body frame is the principal frame.
    wbody->compound = bk_physics_create_compound(w->physics, wbody->collider_count);
    for (uint32_t i = 0; i < wbody->collider_count; ++i)
      bk_physics_compound_add(w->physics, wbody->compound, wb->node_hull[wbody->colliders[i]], child_local);
    def.shape = wbody->compound;
  }
  def.mass = info->is_static ? 0.0 : info->mass;
  def.inertia = info->inertia;
  def.transform = created->body.transform;
  if (!info->is_static) {
    def.linear_velocity = created->body.linear_velocity;
    def.angular_velocity = created->body.angular_velocity;
  }
  def.friction = material.friction;
  def.restitution = material.restitution;
  // A tenth of the body's size: shards stop rolling within a second, while
  // a wall section still topples as it should.
  def.rolling_friction = 0.1 * cbrt(info->mass / material.density);
  def.user_data = BK_USER_CLUSTER | index;
  // Once the budget reaches every piece, a new one is debris from its
  // birth: added to the broadphase, it would pair at once with every box it
  // overlaps, and in a shattering hit that is every neighbour.
  wbody->tier = bk_world_budget_birth_tier(w, info, created->body.transform.position);
  def.debris = wbody->tier == BK_TIER_DEBRIS;
  w->budget.demotions += def.debris;
  wbody->shape = def.shape;
  wbody->previous = bk_transform_mul(created->body.transform, child_local);
  wbody->made = w->step_count;
  wbody->born = loose_since;
  wbody->split_waiting = loose_since < w->step_count; // the rest of a split that waits keeps its start
  wbody->split_since = loose_since;
  wbody->piled = 0;
  wbody->shaken = 0;
  wbody->body = bk_physics_create_body(w->physics, &def, err);
  return !bk_body_is_null(wbody->body);
}

bool bk_world_make_body(bk_world* w, const bk_cluster_created* created, uint64_t loose_since, bk_error* err) {
  w->live_dirty = true;
  return build_body(w, created, loose_since, err);
}

void bk_world_release_body(bk_world* w, uint32_t index) {
  world_body* wbody = &w->bodies[index];
  if (!wbody->alive) return;
  bk_world_settle_forget(w, index); // its settle area wakes: a piece under it may be going
  if (!bk_body_is_null(wbody->body)) bk_physics_destroy_body(w->physics, wbody->body);
  if (!bk_shape_is_null(wbody->compound)) bk_physics_destroy_shape(w->physics, wbody->compound);
  if (!bk_shape_is_null(wbody->simple)) bk_physics_destroy_shape(w->physics, wbody->simple);
  wbody->simple = (bk_shape_id){0, 0};
  wbody->tier = BK_TIER_FULL;
  wbody->calm_steps = 0;
  wbody->alive = false;
  wbody->body = (bk_body_id){0, 0};
  wbody->compound = (bk_shape_id){0, 0};
  wbody->collider_count = 0;
  w->live_dirty = true;
}

bk_transform bk_world_tree_to_world(const bk_world* w, uint32_t index) {
  const world_body* wbody = &w->bodies[index];
  bk_cluster_info info = {0};
  if (!bk_runtime_cluster(w->runtime, wbody->cluster, &info)) return wbody->previous;
  bk_transform body = bk_physics_body_transform(w->physics, wbody->body);
  return bk_transform_mul(body, bk_transform_inverse(info.principal));
}

static void reserve(void** array, uint32_t* capacity, uint32_t need, size_t size) {
  if (need <= *capacity) return;
  *capacity = bk_grow_capacity(*capacity, need);
  *array = bk_realloc(*array, size * *capacity);
}

bool bk_world_apply_results(bk_world* w, bk_error* err) {
  uint32_t removed = bk_runtime_removed_clusters(w->runtime, NULL, 0);
  uint32_t created = bk_runtime_created_clusters(w->runtime, NULL, 0);
  reserve((void**)&w->removed, &w->removed_capacity, removed, sizeof(bk_cluster_removed));
  reserve((void**)&w->created, &w->created_capacity, created, sizeof(bk_cluster_created));
  bk_runtime_removed_clusters(w->runtime, w->removed, w->removed_capacity);
  bk_runtime_created_clusters(w->runtime, w->created, w->created_capacity);
  // The world takes the runtime's events after each of its calls: the
  // bodies below are made from these copies (their info's pointers stay
  // valid until the runtime's next change of clusters).
  bk_runtime_clear_events(w->runtime);
  // Same order as the runtime made them: Bullet's results depend on the order
  // bodies enter and leave its world.
  bool ok = true;
  uint32_t next = 0, failed = 0;
  bk_cluster_id* failed_ids = NULL;
  for (uint32_t r = 0; r <= removed; ++r) {
    uint64_t loose_since = w->step_count;
    if (r < removed) {
      const world_body* parent = &w->bodies[w->removed[r].cluster.index];
      if (parent->alive && parent->split_waiting && parent->split_since < loose_since)
        loose_since = parent->split_since;
      bk_world_release_body(w, w->removed[r].cluster.index);
    }
    while (next < created &&
           (r == removed || bk_cluster_equal(w->created[next].parent, w->removed[r].cluster))) {
      w->live_dirty = true;
      if (!build_body(w, &w->created[next], loose_since, err)) {
        ok = false;
        if (!failed_ids) failed_ids = bk_alloc(sizeof(bk_cluster_id) * created);
        failed_ids[failed++] = w->created[next].cluster.id;
        if (err) err->code = BK_ERROR_PHYSICS;
      }
      next++;
    }
  }
  // A cluster Bullet refused a body (cannot happen for a valid tree) leaves
  // the simulation rather than stay half-made.
  for (uint32_t i = 0; i < failed; ++i) {
    bk_world_release_body(w, failed_ids[i].index);
    bk_runtime_remove_cluster(w->runtime, failed_ids[i]);
  }
  bk_runtime_clear_events(w->runtime); // their removals: the world made them
  bk_free(failed_ids);
  return ok;
}

void bk_world_collect_breaks(bk_world* w) {
  bk_world_copy_breaks(w);
  bk_runtime_clear_events(w->runtime); // hits and loads only break bonds: nothing else is waiting
}

void bk_world_copy_breaks(bk_world* w) {
  uint32_t count = bk_runtime_broken_bonds(w->runtime, NULL, 0);
  reserve((void**)&w->broken, &w->broken_capacity, count, sizeof(bk_bond_break));
  bk_runtime_broken_bonds(w->runtime, w->broken, w->broken_capacity);
  reserve((void**)&w->events, &w->event_capacity, w->event_count + count, sizeof(bk_break_event));
  for (uint32_t i = 0; i < count; ++i) {
    const bk_bond_break* b = &w->broken[i];
    w->events[w->event_count++] = (bk_break_event){.breakable = b->breakable,
                                                   .bond = b->bond,
                                                   .position = b->position,
                                                   .velocity = b->velocity,
                                                   .area = b->area,
                                                   .cause = b->cause,
                                                   .user_data = b->breakable_user_data};
  }
}

void bk_world_refresh_live(bk_world* w) {
  if (!w->live_dirty) return;
  if (w->live_capacity < w->body_capacity) {
    w->live_capacity = bk_grow_capacity(w->live_capacity, w->body_capacity);
    w->live = bk_realloc(w->live, sizeof(uint32_t) * w->live_capacity);
  }
  w->live_count = 0;
  for (uint32_t i = 0; i < w->body_capacity; ++i)
    if (w->bodies[i].alive) w->live[w->live_count++] = i;
  w->live_dirty = false;
}
