// Internal to sim/: the world's data layout, shared by its files.
#pragma once

#include "bk_sim.h"

/// Per-breakable state: the BCRB graph over the tree's leaves and caches.
typedef struct breakable {
  const bk_mesh_tree* tree;
  uint32_t generation; // 0 = free slot
  double density, frailty;
  bool accumulate, convex_colliders, naive;
  double convexity_tolerance;
  double friction, restitution;
  // Graph in CSR form: bonds incident to each leaf.
  uint32_t* adjacency_start; // leaf_count + 1
  uint32_t* adjacency;       // bond indices
  double* bond_hp;           // remaining hit points
  double* bond_hp_initial;
  uint8_t* bond_broken;
  uint32_t* leaf_cluster; // cluster slot of each leaf
  uint8_t* leaf_anchored;
  // Collision proxies, computed once per node and shared by every body.
  bk_shape_id* node_hull;      // null until first needed
  bk_shape_id* node_body_hull; // the hull in the node's own principal frame, for one-node bodies
  int8_t* node_convex;         // -1 unknown, 0 its hull overestimates it, 1 its hull stands for it
} breakable;

/// One connected cluster of fragments = one rigid body.
typedef struct cluster {
  uint32_t breakable;
  bool alive, is_static, dirty, queued;
  bk_body_id body;
  bk_shape_id compound;
  uint32_t* leaves; // ascending
  uint32_t leaf_count;
  uint32_t* nodes; // minimal node set
  uint32_t node_count;
  uint32_t* colliders; // nodes whose hulls are the compound's children
  uint32_t collider_count;
  bk_transform principal; // body frame in the tree frame
  bk_transform previous;  // tree frame at the start of the last step (for interpolated drawing)
  uint64_t born;          // step the body was made
  double mass;
} cluster;

struct bk_world {
  bk_world_desc desc;
  bk_physics* physics;
  bk_shape_id ground;
  bk_body_id ground_body;
  breakable* breakables;
  uint32_t breakable_count, breakable_capacity;
  cluster* clusters;
  uint32_t cluster_count, cluster_capacity;
  uint32_t* free_clusters;
  uint32_t free_cluster_count;
  uint32_t* live; // live cluster slots, in creation order (views index this)
  uint32_t live_count, live_capacity;
  bool live_dirty;
  uint32_t* split_queue; // clusters with broken bonds, oldest first
  uint32_t split_queue_count, split_queue_capacity;
  bk_body_id* projectiles;
  bk_shape_id* projectile_shape;
  double* projectile_radius;
  uint64_t* projectile_born; // step number
  uint32_t projectile_count, projectile_capacity;
  uint64_t step_count;
  bk_contact* contacts;
  uint32_t contact_capacity;
  bk_break_event* events;
  uint32_t event_count, event_capacity;
  uint32_t bonds_broken, break_events, fragments_retired;
  double retired_mass;
  double step_ms, physics_ms, break_ms;
  // Scratch for splitting.
  uint32_t* scratch_leaves;
  uint32_t* scratch_component;
  uint32_t* scratch_stack;
  uint32_t scratch_capacity;
};

/// User data tags on physics bodies.
#define BK_USER_CLUSTER 0x100000000ull
#define BK_USER_PROJECTILE 0x200000000ull

/// A rigid velocity field: v(x) = linear + angular x (x - origin).
typedef struct bk_motion {
  bk_vec3 linear, angular, origin;
} bk_motion;

/// Builds the physics body of a cluster from its leaves (sorted) with the
/// tree frame at tree_to_world, moving with `motion` (evaluated at the new
/// centre of mass).
bool bk_cluster_build(bk_world* world, uint32_t slot, bk_transform tree_to_world, bk_motion motion,
                      bk_error* err);
/// Makes every node's hull (and each fragment's body-frame hull) now, at load
/// time, so breaking later only creates bodies: a shattering hit must not
/// compute hulls inside a step.
void bk_breakable_prepare_hulls(bk_world* world, uint32_t breakable_index);
/// Removes a cluster's body and compound and frees its arrays.
void bk_cluster_release(bk_world* world, uint32_t slot);
/// A new cluster slot (its arrays empty).
uint32_t bk_cluster_alloc(bk_world* world, uint32_t breakable_index);
/// Where the tree frame of a cluster is in the world now.
bk_transform bk_cluster_tree_to_world(const bk_world* world, const cluster* c);
/// Applies damage from the last step's contacts; queues clusters with broken bonds.
void bk_world_apply_damage(bk_world* world, uint32_t contact_count);
/// Marks a cluster for a connectivity check and queues it (once).
void bk_world_queue_split(bk_world* world, uint32_t slot);
/// Splits queued clusters within the step's budget.
void bk_world_split(bk_world* world);
/// Rebuilds the list of live clusters after slots changed.
void bk_world_refresh_live(bk_world* world);
/// Mass properties (per the breakable's density) of a cluster from its nodes' moments.
void bk_cluster_mass(const bk_world* world, const cluster* c, double* mass, bk_transform* principal,
                     bk_vec3* inertia);
