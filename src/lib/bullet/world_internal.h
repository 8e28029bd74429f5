// bullet world (private): the data layout its files share. The runtime owns
// breakables and clusters; the world owns what Bullet needs for them: node
// hulls per breakable, and per cluster a body, its compound and colliders.
#pragma once

#include <breakables/bullet.h>

#include "bk_base.h"

/// Bullet's view of one breakable: collision proxies, made once per node at
/// load time and shared by every body of it.
typedef struct world_breakable {
  bk_breakable_id id;
  bool convex_colliders, naive;
  double convexity_tolerance;
  bk_shape_id* node_hull;      // in the tree frame
  bk_shape_id* node_body_hull; // a leaf's hull in its own principal frame, for one-fragment bodies
  uint8_t* hull_fits;          // per node: its hull may stand for it (bk_collider_nodes), or HULL_LATER
  // Nodes the arrays above hold (their hulls made): the tree's node count,
  // which grows as fragments are refined (world_refine.c)
  uint32_t node_count;
  bool grown;            // refined: some nodes' hulls may be HULL_LATER
  uint32_t source_nodes; // the caller's tree's node count (a grown tree's first nodes)
} world_breakable;

/// hull_fits of a node a refinement added whose hull is not made yet
/// (world_bodies.c makes it when a body first needs it).
#define HULL_LATER 2
/// bk_runtime_def.refine_prepare and refine_discard of the world's runtime
/// (world_refine.c): a refinement's pieces' hulls prepared on its worker.
void* bk_world_refine_prepare(const bk_mesh_tree* pieces, void* context);
void bk_world_refine_discard(void* prepared, void* context);
/// Room bk_world_hull_points needs.
#define BK_WORLD_HULL_POINTS 96
/// A refined node's hull points (hull_points.c): its mesh's extreme vertices
/// along 96 fixed directions (all of them for a mesh of no more); `out`
/// holds BK_WORLD_HULL_POINTS. Returns the count.
uint32_t bk_world_hull_points(const bk_mesh* mesh, bk_vec3* out);

/// The body of one runtime cluster, indexed by the cluster's index.
typedef struct world_body {
  bool alive;
  bk_cluster_id cluster;
  uint32_t breakable; // index into world breakables
  bk_body_id body;
  bk_shape_id compound;
  uint32_t* colliders; // nodes whose hulls are the compound's children
  uint32_t collider_count;
  bk_transform previous; // tree frame at the start of the last step (for interpolated drawing)
  uint64_t made;         // step the body was made
  uint64_t born;         // step it came loose: made, or its parent's bonds broke if that waited to split
  bool split_waiting;    // its cluster has broken bonds waiting for the split budget (world_budget.c)
  uint64_t split_since;  // since this step
  bk_shape_id shape;     // its own shape (a hull or the compound), which a simplified body gives back
  bk_shape_id simple;    // the sphere or box standing in for it while simplified (owned)
  bk_budget_tier tier;   // what the physics budget made of it
  uint32_t calm_steps;   // steps in a row it has moved slower than the budget's calm speed
  uint64_t piled;        // last step it pressed on another loose body at a low relative speed
  uint64_t shaken;       // last step a moving body pressed on it while it was frozen
  double pressed;        // normal impulse (N s) dynamic bodies pressed on it in the last step, frozen
  uint32_t area;         // 1 + the settle area it is merged into (world_settle.c); 0: not merged
  bk_transform sent;     // where bk_world_motion last placed it (world_follow.c)
  bool sent_valid;       // it has been placed (false: a new body)
} world_body;

/// Settled pieces of one cell, parked behind one static compound (world_settle.c).
typedef struct settle_area {
  int64_t cell[3];
  bool used;
  bk_body_id body;      // static, watched; null while empty
  bk_shape_id compound; // children: the members' hulls where they lie
  uint32_t* members;    // world body indices, ascending
  uint32_t member_count, member_capacity;
  uint32_t* child_member; // per compound child: its member's body index
  uint32_t child_count, child_capacity;
  bk_vec3 lo, hi; // the members' box
} settle_area;

/// The settle state: areas, and counters for the stats.
typedef struct world_settle {
  settle_area* areas;
  uint32_t area_count, area_capacity;
  uint32_t merged, live_areas, wakes;
  double batch_ms;
  void* candidates; // scratch: the pieces a batch merges, with their cells
  uint32_t candidate_capacity;
  bk_body_id* ids; // scratch: bodies to park or unpark at once
  uint32_t id_capacity;
  uint32_t* wake; // scratch: the areas a step wakes
  uint32_t wake_capacity;
} world_settle;

/// A hit waiting for the step's hit budget (world_hits.c).
typedef struct world_hit {
  bk_cluster_id cluster;
  bk_vec3 point; // in the world, as its contact gave it (applied in its own step)
  bk_vec3 local; // in the tree frame (applied in a later step, where the object is then)
  double impulse, closing_speed;
  uint64_t step; // the step it happened in
} world_hit;

/// The physics budget's state (world_budget.c).
typedef struct world_budget {
  double level;       // 0..4: tier k reaches the least important (level - k + 1) of the pieces
  double young_share; // 0..1: the least important young pieces that give up their first second
  double cost_ms;     // last step's cost as compared with the budget
  double smoothed_ms; // its average over recent steps (relaxing waits for it)
  uint32_t top_steps; // steps in a row with the level past 3 (retiring waits for some)
  bool engaged;       // a body may be below full fidelity
  bool has_focus;
  bk_vec3 focus;
  uint32_t retired, demotions, restorations;
  struct budget_candidate* candidates;
  uint32_t candidate_capacity;
  bk_retired_body* retired_bodies; // the last step's
  uint32_t* retired_index;         // and their bodies' indices (released together, at the step's end)
  uint32_t retired_count, retired_capacity;
} world_budget;

struct bk_world {
  bk_world_def def;
  bk_physics* physics;
  double hull_margin; // the physics world's, for hulls prepared on refinement workers
  bk_runtime* runtime;
  bk_shape_id ground;
  bk_body_id ground_body;
  world_breakable* breakables;
  uint32_t breakable_count, breakable_capacity;
  world_body* bodies; // by cluster index
  uint32_t body_capacity;
  uint32_t* live; // live cluster indices, ascending (views index this)
  uint32_t live_count, live_capacity;
  bool live_dirty;
  bk_body_id* projectiles;
  bk_shape_id* projectile_shape;
  double* projectile_radius;
  uint64_t* projectile_expires; // the step after which it is removed
  uint32_t projectile_count, projectile_capacity;
  uint64_t step_count;
  bk_contact* contacts;
  uint32_t contact_capacity;
  uint32_t contact_count; // the last step's, at most contact_capacity
  bk_damage_contact* damage;
  uint32_t damage_capacity;
  world_hit* hits; // waiting hits, oldest first, then the step's
  uint32_t hit_count, hit_capacity;
  bk_damage_contact* hit_batch; // what the step applies
  uint32_t hit_batch_capacity;
  bool hits_hold_splits; // hits wait after this step's: no split in it
  bool hits_held_last;   // the last step that applied hits held the splits
  bk_cluster_created* created;
  uint32_t created_capacity;
  bk_cluster_removed* removed;
  uint32_t removed_capacity;
  bk_bond_break* broken;
  uint32_t broken_capacity;
  bk_break_event* events;
  uint32_t event_count, event_capacity;
  uint32_t events_of_last_step; // events before this index belong to the last step
  uint32_t fragments_retired;
  double retired_mass;
  double step_ms, physics_ms, break_ms, stress_ms;
  double fracture_ms, physics_cpu_ms; // thread CPU time (bk_world_stats)
  bk_stress_support* supports;
  uint32_t support_capacity;
  bk_stress_load* stress_loads; // what rests on clusters, from the step's slow contacts
  uint32_t stress_load_capacity;
  world_budget budget;
  world_settle settle;
  bk_retired_body* aged; // small fragments retire_volume removed in the last step
  uint32_t aged_count, aged_capacity;
  bk_leaf_refined* refined; // the last step's refinements (world_refine.c)
  uint32_t refined_capacity;
  double refine_ms; // thread CPU time of the last step's refinement
};

/// User data tags on physics bodies.
#define BK_USER_CLUSTER 0x100000000ull
#define BK_USER_PROJECTILE 0x200000000ull
#define BK_USER_AREA 0x400000000ull

/// Makes every node's hull (and each fragment's body-frame hull) now, at load
/// time, so breaking later only creates bodies: a shattering hit must not
/// compute hulls inside a step. Its per-node arrays grow to the tree's node
/// count (from world_breakable.node_count on: all nodes at load time); the
/// nodes a refinement added are marked HULL_LATER, their hulls made when a
/// body first needs them (choose_colliders).
void bk_world_prepare_hulls(bk_world* world, uint32_t breakable_index);
/// The step's refinement, after its hits and before its split: lands and
/// starts the runtime's refinements (bk_runtime_refine), collects the bonds
/// the hits that waited for the pieces broke, and grows the per-node arrays
/// of the trees that grew (the new nodes' hulls are made when a body first
/// needs them), so that the split that follows can make bodies of them.
void bk_world_refine(bk_world* world);
/// Takes the runtime's refined events: grows the per-node arrays of the
/// trees that grew and makes the new nodes' hulls from what the workers
/// prepared (leaves the runtime's events as they are).
void bk_world_take_refined(bk_world* world);
/// Appends the runtime's broken bonds to the world's break events, leaving
/// the runtime's events as they are (bk_world_collect_breaks clears them).
void bk_world_copy_breaks(bk_world* world);
/// Applies what the runtime's last call reported, in order: each removed
/// cluster's body goes, then the bodies of the clusters made from it.
/// Returns false (err set) if a body could not be made.
bool bk_world_apply_results(bk_world* world, bk_error* err);
/// Appends the runtime's last broken bonds to the world's break events.
void bk_world_collect_breaks(bk_world* world);
/// Makes the body of a created cluster where its record says (as a split
/// does); `loose_since` as bk_world_apply_results gives it. False (err set)
/// when the physics refused it.
bool bk_world_make_body(bk_world* world, const bk_cluster_created* created, uint64_t loose_since,
                        bk_error* err);
/// A body's rotation as the physics keeps it, a 3x3 matrix by rows
/// (physics_bodies.cpp), and set back exactly (a quaternion is not: its
/// round trip through the matrix rounds).
void bk_physics_body_basis(const bk_physics* physics, bk_body_id body, double out[9]);
void bk_physics_body_set_basis(bk_physics* physics, bk_body_id body, const double basis[9]);
/// Moves a body to a budget tier (below BK_TIER_RETIRED) one tier at a time,
/// as the budget does (world_budget.c).
void bk_world_budget_set_tier(bk_world* world, uint32_t index, bk_budget_tier tier);
/// Removes a cluster's body and compound.
void bk_world_release_body(bk_world* world, uint32_t index);
/// Where the tree frame of a cluster is in the world now.
bk_transform bk_world_tree_to_world(const bk_world* world, uint32_t index);
/// Rebuilds the list of live clusters after bodies changed.
void bk_world_refresh_live(bk_world* world);
/// Applies the step's damage contacts (damage[0..count)) after the hits
/// that wait, as far as max_hit_fragments_per_step allows; the rest wait.
/// While hits wait and splits wait too, steps take turns: one applies hits
/// (and sets hits_hold_splits: no split in it), the next splits (and
/// applies no hit). Returns the hits left waiting.
uint32_t bk_world_apply_hits(bk_world* world, uint32_t count);
/// Removes projectiles older than projectile_lifetime.
void bk_world_retire_projectiles(bk_world* world);
/// Whether the budget may make a cluster's body cheaper at all: a loose
/// piece, smaller than budget_large_volume, away from the focus.
bool bk_world_budget_candidate(const bk_world* world, const bk_cluster_info* info, bk_vec3 center);
/// The tier a new body starts at: debris once the budget reaches every
/// piece, so it never pairs with other debris; else full.
bk_budget_tier bk_world_budget_birth_tier(const bk_world* world, const bk_cluster_info* info, bk_vec3 center);
/// After a step: compares the step's physics cost with the budget and
/// moves bodies between tiers.
void bk_world_budget_step(bk_world* world);
/// What a renderer needs of a one-node body leaving the world (retired by
/// the budget or by retire_volume) to carry it on and fade it out.
bk_retired_body bk_world_retired_record(const bk_world* world, uint32_t index, const bk_cluster_info* info);
/// Frees the budget's buffers.
void bk_world_budget_free(bk_world* world);
/// A body about to be merged (world_settle.c): unpinned at rest if frozen,
/// its own shape back if simplified; debris stays debris (debris that came
/// to rest inside other debris would be pushed out of it once woken).
void bk_world_budget_settle(bk_world* world, uint32_t index);
/// Before the physics of a step: wakes the settle areas that were disturbed
/// (a fast body came near, a body under them went) or that a projectile
/// will reach within two steps.
void bk_world_settle_before_physics(bk_world* world);
/// After a step: every batch's steps, merges the pieces at rest.
void bk_world_settle_step(bk_world* world);
/// A body about to be released: its area, if merged, wakes first.
void bk_world_settle_forget(bk_world* world, uint32_t index);
/// The cluster whose piece a contact touched on a settle area's compound.
bool bk_world_settle_cluster(const bk_world* world, bk_body_id body, int32_t child, bk_cluster_id* out);
/// Frees the settle state's buffers.
void bk_world_settle_free(bk_world* world);
