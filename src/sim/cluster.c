// Clusters: one rigid body per connected set of fragments. Its compound is
// built from the minimal mesh-tree node set; its mass properties come from
// the chosen nodes' exact volume moments; its body frame is the principal
// frame of inertia.
#include <stdlib.h>
#include <string.h>

#include "sim_internal.h"

uint32_t bk_cluster_alloc(bk_world* w, uint32_t breakable_index) {
  uint32_t slot = 0;
  if (w->free_cluster_count) {
    slot = w->free_clusters[--w->free_cluster_count];
  } else {
    if (w->cluster_count == w->cluster_capacity) {
      w->cluster_capacity = bk_grow_capacity(w->cluster_capacity, w->cluster_count + 1);
      w->clusters = bk_realloc(w->clusters, sizeof(cluster) * w->cluster_capacity);
      w->free_clusters = bk_realloc(w->free_clusters, sizeof(uint32_t) * w->cluster_capacity);
    }
    slot = w->cluster_count++;
  }
  memset(&w->clusters[slot], 0, sizeof(cluster));
  w->clusters[slot].breakable = breakable_index;
  w->clusters[slot].alive = true;
  w->live_dirty = true;
  return slot;
}

void bk_cluster_release(bk_world* w, uint32_t slot) {
  cluster* c = &w->clusters[slot];
  if (!bk_body_is_null(c->body)) bk_physics_destroy_body(w->physics, c->body);
  if (!bk_shape_is_null(c->compound)) bk_physics_destroy_shape(w->physics, c->compound);
  free(c->leaves);
  free(c->nodes);
  free(c->colliders);
  memset(c, 0, sizeof *c);
  w->free_clusters[w->free_cluster_count++] = slot;
  w->live_dirty = true;
}

bk_transform bk_cluster_tree_to_world(const bk_world* w, const cluster* c) {
  bk_transform body = bk_physics_body_transform(w->physics, c->body);
  return bk_transform_mul(body, bk_transform_inverse(c->principal));
}

void bk_cluster_mass(const bk_world* w, const cluster* c, double* mass, bk_transform* principal,
                     bk_vec3* inertia) {
  const breakable* b = &w->breakables[c->breakable];
  bk_moments sum = {0};
  for (uint32_t i = 0; i < c->node_count; ++i)
    sum = bk_moments_add(sum, b->tree->nodes[c->nodes[i]].moments);
  bk_mass_properties mp = bk_mesh_tree_mass(b->tree, sum);
  double values[3], axes[3][3];
  bk_sym3_eigen(mp.inertia, values, axes);
  *mass = b->density * mp.volume;
  *principal = (bk_transform){mp.centroid, bk_quat_from_matrix(axes)};
  // Thin slivers can have a vanishing moment; keep the solver well-posed.
  double floor_value = 1e-9 * fmax(values[0], fmax(values[1], values[2]));
  *inertia = bk_v3(b->density * fmax(values[0], floor_value), b->density * fmax(values[1], floor_value),
                   b->density * fmax(values[2], floor_value));
}

// The node's hull in its own principal frame, for a body that is that node alone.
static bk_shape_id node_body_hull(bk_world* w, breakable* b, uint32_t node) {
  if (bk_shape_is_null(b->node_body_hull[node])) {
    bk_moments moments = b->tree->nodes[node].moments;
    bk_mass_properties mp = bk_mesh_tree_mass(b->tree, moments);
    double values[3], axes[3][3];
    bk_sym3_eigen(mp.inertia, values, axes);
    bk_transform to_body = bk_transform_inverse((bk_transform){mp.centroid, bk_quat_from_matrix(axes)});
    const bk_mesh* mesh = &b->tree->nodes[node].mesh;
    bk_vec3* local = bk_alloc(sizeof(bk_vec3) * mesh->position_count);
    for (uint32_t i = 0; i < mesh->position_count; ++i)
      local[i] = bk_transform_point(to_body, mesh->positions[i]);
    b->node_body_hull[node] = bk_physics_create_hull(w->physics, local, mesh->position_count, 64);
    free(local);
  }
  return b->node_body_hull[node];
}

static bk_shape_id node_hull(bk_world* w, breakable* b, uint32_t node) {
  if (bk_shape_is_null(b->node_hull[node])) {
    const bk_mesh* mesh = &b->tree->nodes[node].mesh;
    b->node_hull[node] = bk_physics_create_hull(w->physics, mesh->positions, mesh->position_count, 64);
    b->node_convex[node] = -1;
  }
  return b->node_hull[node];
}

// Whether a node's hull may stand for it: always with convex colliders on;
// otherwise only when the hull hardly overestimates the node (a hollow egg's
// hull is a solid egg, so its children are used instead).
static bool hull_stands_for(bk_world* w, breakable* b, uint32_t node) {
  const bk_mesh_tree_node* n = &b->tree->nodes[node];
  if (b->convex_colliders || n->child_count == 0) return true;
  if (b->node_convex[node] < 0) {
    bk_shape_id hull = node_hull(w, b, node);
    double hull_volume = bk_shape_is_null(hull) ? INFINITY : bk_physics_hull_volume(w->physics, hull);
    b->node_convex[node] = hull_volume <= (1.0 + b->convexity_tolerance) * n->moments.v ? 1 : 0;
  }
  return b->node_convex[node] == 1;
}

static void push_collider(cluster* c, uint32_t* capacity, uint32_t node) {
  if (c->collider_count == *capacity) {
    *capacity = bk_grow_capacity(*capacity, c->collider_count + 1);
    c->colliders = bk_realloc(c->colliders, sizeof(uint32_t) * *capacity);
  }
  c->colliders[c->collider_count++] = node;
}

static void add_proxies(bk_world* w, breakable* b, cluster* c, uint32_t* capacity, uint32_t node) {
  if (hull_stands_for(w, b, node)) {
    if (!bk_shape_is_null(node_hull(w, b, node))) push_collider(c, capacity, node);
    return;
  }
  const bk_mesh_tree_node* n = &b->tree->nodes[node];
  for (uint32_t i = 0; i < n->child_count; ++i)
    add_proxies(w, b, c, capacity, n->first_child + i);
}

void bk_breakable_prepare_hulls(bk_world* w, uint32_t breakable_index) {
  breakable* b = &w->breakables[breakable_index];
  for (uint32_t i = 0; i < b->tree->node_count; ++i) {
    node_hull(w, b, i);
    hull_stands_for(w, b, i);
  }
  for (uint32_t l = 0; l < b->tree->leaf_count; ++l)
    node_body_hull(w, b, b->tree->leaf_nodes[l]);
}

bool bk_cluster_build(bk_world* w, uint32_t slot, bk_transform tree_to_world, bk_motion motion,
                      bk_error* err) {
  cluster* c = &w->clusters[slot];
  breakable* b = &w->breakables[c->breakable];
  c->nodes = bk_realloc(c->nodes, sizeof(uint32_t) * c->leaf_count);
  c->node_count = bk_minimal_nodes(b->tree, c->leaves, c->leaf_count, c->nodes);
  // Colliders: plain BCRB uses every fragment; otherwise each chosen node's proxies.
  uint32_t capacity = 0;
  c->collider_count = 0;
  if (b->naive) {
    for (uint32_t i = 0; i < c->leaf_count; ++i)
      if (!bk_shape_is_null(node_hull(w, b, b->tree->leaf_nodes[c->leaves[i]])))
        push_collider(c, &capacity, b->tree->leaf_nodes[c->leaves[i]]);
  } else {
    for (uint32_t i = 0; i < c->node_count; ++i)
      add_proxies(w, b, c, &capacity, c->nodes[i]);
  }
  c->is_static = false;
  for (uint32_t i = 0; i < c->leaf_count && !c->is_static; ++i)
    c->is_static = b->leaf_anchored[c->leaves[i]];
  for (uint32_t i = 0; i < c->leaf_count; ++i)
    b->leaf_cluster[c->leaves[i]] = slot;

  bk_vec3 inertia = {0};
  bk_cluster_mass(w, c, &c->mass, &c->principal, &inertia);
  bk_transform child_local = bk_transform_inverse(c->principal);
  bk_body_desc desc = bk_default_body_desc();
  if (c->collider_count == 1 && c->node_count == 1 && c->colliders[0] == c->nodes[0]) {
    // One node, one hull (every loose fragment): its principal frame is the
    // body frame, so a hull made in that frame needs no compound. That keeps
    // fragment pairs off Bullet's costly compound-compound path.
    desc.shape = node_body_hull(w, b, c->nodes[0]);
  }
  if (bk_shape_is_null(desc.shape)) {
    // Children are hulls in the tree frame; the body frame is the principal frame.
    c->compound = bk_physics_create_compound(w->physics, c->collider_count);
    for (uint32_t i = 0; i < c->collider_count; ++i)
      bk_physics_compound_add(w->physics, c->compound, b->node_hull[c->colliders[i]], child_local);
    desc.shape = c->compound;
  }
  desc.mass = c->is_static ? 0.0 : c->mass;
  desc.inertia = inertia;
  desc.transform = bk_transform_mul(tree_to_world, c->principal);
  if (!c->is_static) {
    bk_vec3 r = bk_v3_sub(desc.transform.position, motion.origin);
    desc.linear_velocity = bk_v3_add(motion.linear, bk_v3_cross(motion.angular, r));
    desc.angular_velocity = motion.angular;
  }
  desc.friction = b->friction;
  desc.restitution = b->restitution;
  // A tenth of the body's size: shards stop rolling within a second, while
  // a wall section still topples as it should.
  desc.rolling_friction = 0.1 * cbrt(c->mass / b->density);
  desc.user_data = BK_USER_CLUSTER | slot;
  c->previous = tree_to_world;
  c->born = w->step_count;
  c->body = bk_physics_create_body(w->physics, &desc, err);
  return !bk_body_is_null(c->body);
}
