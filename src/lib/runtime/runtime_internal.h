// runtime (private): the data layout its files share.
#pragma once

#include <breakables/runtime.h>

#include "bk_base.h"
#include "stress_system.h"

/// A breakable: the BCRB graph over its tree's leaves.
typedef struct rt_breakable {
  const bk_mesh_tree* tree;
  const bk_mesh_tree* source; // the caller's (tree is own_tree once refined)
  uint32_t generation;        // kept across reuse of the slot
  bool alive;
  void* user_data;
  bk_material material; // name points at material_name
  char material_name[BK_MATERIAL_NAME_MAX + 1];
  // Graph in CSR form: bonds incident to each leaf.
  uint32_t* adjacency_start; // leaf_count + 1
  uint32_t* adjacency;       // bond indices
  double* bond_hp;           // remaining hit points
  double* bond_hp_initial;
  uint8_t* bond_broken;
  uint32_t* leaf_cluster; // cluster slot of each leaf (UINT32_MAX: none)
  uint8_t* leaf_anchored;
  // Stress (stress.c), made at the first solve: each leaf's centroid and
  // volume, its last solved motion (6 values: the next solve's warm start)
  // and each bond's last solved stress (compression, tension, shear, ratio;
  // ratio < 0: not solved).
  bk_vec3* leaf_centroid;
  double* leaf_volume;
  double* leaf_motion;
  double* bond_stress;
  // Refinement (refine.c): the breakable's own copy of its tree once a
  // fragment was refined (its first `shared_nodes` nodes' meshes are the
  // caller's tree's), how, and where anchoring puts the support plane.
  bk_mesh_tree* own_tree;
  uint32_t shared_nodes;
  bk_refine_def refine;
  bool anchored;
  double anchor_height;
  bk_transform placement;
  bk_vec3 up;             // the runtime's up when it was added
  uint8_t* leaf_refining; // per leaf: marked, its pieces not landed yet
} rt_breakable;

/// A hit waiting for a fragment's pieces (refine.c): tree frame, as it was.
typedef struct rt_refine_hit {
  uint64_t sequence; // order of hits over the runtime
  bk_vec3 local;
  double impulse, frailty;
} rt_refine_hit;

/// A fragment being refined: marked by a hit, fractured (on a worker or at
/// landing), landed refine_latency calls later.
typedef struct rt_refine_job {
  uint32_t breakable, generation;
  uint32_t node;     // the leaf's node (node indices never change)
  uint32_t due_call; // the bk_runtime_refine call that lands it
  rt_refine_hit* hits;
  uint32_t hit_count, hit_capacity;
  bk_mesh mesh; // the leaf's (borrowed: a node's mesh never changes)
  bk_aabb tree_bounds;
  bk_fracture_def def;
  bk_piece_neighbour* neighbours; // the leaf's bonded neighbours when marked
  uint32_t neighbour_count;
  bk_mesh_tree pieces;        // the result
  bk_piece_contacts contacts; // how the pieces touch the neighbours' faces
  void* prepared;             // refine_prepare's, until handed over in the event
  void* (*prepare)(const bk_mesh_tree* pieces, void* context); // the def's, read on the worker
  void* context;
  bool built, ok;
  struct rt_refine_batch* batch; // the worker building it (refine_jobs.c), or NULL
  bk_error err;
} rt_refine_job;

/// A force on one leaf of a cluster for the stress solve (stress_loads.c),
/// tree frame: the force at the leaf's centroid and its moment about it.
typedef struct rt_leaf_load {
  uint32_t slot, leaf;
  double force[3], torque[3];
} rt_leaf_load;

/// A created event: the cluster (live: one removed before the clear takes
/// its event back), the parent as the caller knows it, where its body starts.
typedef struct rt_created {
  uint32_t slot;
  bk_cluster_id parent;
  bk_body_state body;
} rt_created;

/// A connected cluster of fragments.
typedef struct rt_cluster {
  uint32_t breakable;
  uint32_t generation; // kept across reuse of the slot
  bool alive, is_static, dirty, queued;
  void* user_data;
  // 1 + its record among the created events not yet cleared (0: none): the
  // caller has no body for it yet, so the runtime answers where it is.
  uint32_t created_event;
  uint32_t* leaves; // ascending
  uint32_t leaf_count;
  uint32_t* nodes; // minimal node set
  uint32_t node_count;
  bk_transform principal; // body frame in the tree frame
  bk_vec3 inertia;
  double mass, volume;
  // Stress (stress.c): the system (NULL until first solved), whether its
  // bonds or masses changed since it was made (stale), whether its load was
  // solved and its bonds checked (settled: nothing to do until a change),
  // and the leaves a moving cluster rests on (sorted, gathered over its rest).
  rt_stress* stress;
  bool stress_stale, stress_settled;
  uint32_t* stress_held;
  uint32_t stress_held_count;
  uint32_t stress_rest_calls; // calls in a row a moving cluster has rested
  // The loads (things resting on it) its current solve carries, by leaf,
  // and those of the calls since, summed, to be averaged (contact forces
  // flicker from step to step).
  rt_leaf_load* stress_loads;
  uint32_t stress_load_count;
  rt_leaf_load* stress_window;
  uint32_t stress_window_count, stress_window_calls;
  // What a split left waiting for the budget: its leaves' components
  // (indexed like leaves, numbered as label_components numbers them) and
  // how many, so that the next split need not search it again; NULL once a
  // bond of it breaks.
  uint32_t* split_labels;
  uint32_t split_components;
} rt_cluster;

struct bk_runtime {
  bk_runtime_def def;
  rt_breakable* breakables;
  uint32_t breakable_count, breakable_capacity;
  rt_cluster* clusters;
  uint32_t cluster_count, cluster_capacity;
  uint32_t* free_clusters;
  uint32_t free_cluster_count;
  uint32_t live_count;
  uint32_t* split_queue; // clusters with broken bonds, oldest first
  uint32_t split_queue_count, split_queue_capacity;
  uint32_t live_breakables;
  bk_vec3 up; // the opposite of gravity, unit
  // Events since the last clear.
  rt_created* created;
  uint32_t created_count, created_capacity;
  bk_cluster_removed* removed;
  uint32_t removed_count, removed_capacity;
  bk_bond_break* broken;
  uint32_t broken_count, broken_capacity;
  uint32_t bonds_broken, splits;
  uint32_t stress_bonds_broken, stress_clusters_solved, stress_iterations;
  uint32_t stress_cursor; // the cluster slot the next stress call starts at
  void* stress_scratch;   // the held leaves of a stress call (stress.c)
  uint32_t stress_scratch_capacity;
  rt_leaf_load* stress_load_scratch; // the loads of a stress call, by cluster and leaf
  uint32_t stress_load_scratch_capacity;
  bk_fracture_command* stress_commands; // what bk_runtime_solve_stress applies (stress.c)
  uint32_t stress_command_capacity;
  // Scratch for splitting.
  uint32_t* scratch_component;
  uint32_t* scratch_stack;
  uint32_t scratch_capacity;
  uint32_t* scratch_position; // a split cluster's leaf -> its index in the cluster's leaves
  uint32_t scratch_position_capacity;
  // Refinement (refine.c, refine_jobs.c).
  rt_refine_job** refine_jobs; // oldest first
  uint32_t refine_job_count, refine_job_capacity;
  uint32_t refine_calls;   // bk_runtime_refine calls so far
  uint32_t refine_marked;  // fragments marked since the last call
  uint32_t refine_threads; // workers running
  uint64_t hit_sequence;
  bk_leaf_refined* refined; // events since the last clear
  uint32_t refined_count, refined_capacity;
  uint32_t refined_leaves, refine_failed;
  // The journal (journal.c): the entries since the last clear.
  uint8_t* journal;
  size_t journal_size, journal_capacity;
};

/// The id of a live cluster slot.
bk_cluster_id rt_cluster_id(const bk_runtime* rt, uint32_t slot);
/// The cluster of a live id, or NULL.
rt_cluster* rt_find_cluster(const bk_runtime* rt, bk_cluster_id id);
/// The breakable of a live id, or NULL.
rt_breakable* rt_find_breakable(const bk_runtime* rt, bk_breakable_id id);
/// A new cluster slot (arrays empty, alive).
uint32_t rt_cluster_alloc(bk_runtime* rt, uint32_t breakable_index);
/// Takes a live cluster out: its leaves point nowhere, its removal is
/// recorded, its slot freed.
void rt_remove_cluster(bk_runtime* rt, uint32_t slot);
/// Frees a breakable's arrays (the slot stays, not alive).
void rt_breakable_free(rt_breakable* b);
/// Frees a cluster's arrays and slot (its leaves keep pointing at it until reassigned).
void rt_cluster_free(bk_runtime* rt, uint32_t slot);
/// Computes a cluster's node set, static flag and mass properties from its
/// leaves, and makes its leaves point at it.
void rt_cluster_finish(bk_runtime* rt, uint32_t slot);
/// Mass properties of a cluster from its nodes' moments and the density.
void rt_cluster_mass(const bk_runtime* rt, rt_cluster* c);
/// Records a created cluster whose body starts in the state of `motion`'s
/// body (parent) at tree_to_world.
void rt_record_created(bk_runtime* rt, uint32_t slot, bk_cluster_id parent, bk_transform tree_to_world,
                       const bk_body_state* parent_state);
/// Records a cluster's removal before its slot is freed; one created since
/// the last clear has its created event taken back instead (false).
bool rt_record_removed(bk_runtime* rt, uint32_t slot);
/// The parent a cluster's parts name: itself, or, for one created since the
/// last clear (the caller never saw it), its own parent as the caller knows it.
bk_cluster_id rt_known_parent(const bk_runtime* rt, uint32_t slot);
/// True once per intact bond inside cluster `slot`, seen from `leaf` (its
/// lower leaf) among the leaf's bonds.
static inline bool rt_bond_inside(const rt_breakable* b, uint32_t bond, uint32_t leaf, uint32_t slot) {
  const bk_bond* bd = &b->tree->bonds[bond];
  return bd->leaf_a == leaf && !b->bond_broken[bond] && b->leaf_cluster[bd->leaf_b] == slot;
}
/// Damages a bond (accumulating or discrete, by its material); true when it breaks.
bool rt_bond_damage(rt_breakable* b, uint32_t bond, double damage);
/// Breaks a bond of cluster `slot` as a hit does: the event at the bond's
/// centroid where the cluster's body is now.
void rt_break_bond_by_hit(bk_runtime* rt, uint32_t slot, uint32_t bond);
/// A hit on a cluster (tree frame): marks the fragments it refines and
/// records it for every fragment of the cluster waiting for its pieces
/// (refine_jobs.c).
void rt_refine_hit_cluster(bk_runtime* rt, uint32_t slot, bk_vec3 local, double impulse);
/// Whether a bond waits for a fragment's pieces (either leaf marked).
static inline bool rt_bond_waits(const rt_breakable* b, const bk_bond* bd) {
  return b->leaf_refining && (b->leaf_refining[bd->leaf_a] || b->leaf_refining[bd->leaf_b]);
}
/// Builds a breakable's graph from its tree: the bonds incident to each leaf (CSR).
void rt_breakable_build_adjacency(rt_breakable* b);
/// Frees a breakable's own tree (the meshes it made, never the caller's).
void rt_breakable_free_tree(rt_breakable* b);
/// Checks a refine def; err names the field ("breakable: refine.pieces ...").
bool rt_refine_def_validate(const bk_refine_def* def, bk_error* err);
/// Waits for and frees every job (of one breakable, or all: UINT32_MAX).
void rt_refine_cancel(bk_runtime* rt, uint32_t breakable_index);
/// Shares the jobs not due at `call` and not started out among the free
/// workers (refine_jobs.c).
void rt_refine_start(bk_runtime* rt, uint32_t call);
/// Finishes a job's work (joins its worker, or does it here).
void rt_refine_finish(bk_runtime* rt, rt_refine_job* job);
/// A saved job made again (state_load.c) as mark made it: its leaf's node,
/// due call, the tree's bounds and neighbours (nodes and bond areas) when it
/// was marked, and its hits (the first is the marking one). Takes `hits`.
void rt_refine_restore(bk_runtime* rt, uint32_t breakable_index, uint32_t node, uint32_t due_call,
                       bk_aabb tree_bounds, const uint32_t* neighbour_nodes, const double* neighbour_areas,
                       uint32_t neighbour_count, rt_refine_hit* hits, uint32_t hit_count);
/// Frees a job (what refine_prepare made for it and was not handed over goes to refine_discard).
void rt_refine_job_free(const bk_runtime* rt, rt_refine_job* job);
/// Marks a bond broken and records it (position: world; velocity: of the body there).
void rt_break_bond(bk_runtime* rt, uint32_t slot, uint32_t bond, bk_vec3 position, bk_vec3 velocity,
                   bk_break_cause cause);
// The stress state kept with each cluster (stress_state.c); the stress stage
// that fills it (stress.c) is above the core and only reads it.
/// Frees a cluster's stress state (its system, held leaves and loads).
void rt_stress_release(rt_cluster* c);
/// Frees a breakable's per-leaf and per-bond stress state (made again at the
/// next solve): its leaves or bonds changed.
void rt_stress_forget_leaves(rt_breakable* b);
/// Drops a cluster's loads and window.
void rt_stress_drop_loads(rt_cluster* c);
/// Clusters whose load has not been solved and checked yet.
uint32_t rt_stress_pending(const bk_runtime* rt);
/// After a material change: every cluster of the breakable is solved again.
void rt_stress_material_changed(bk_runtime* rt, uint32_t breakable_index);
/// Queues a cluster for a connectivity check (once).
void rt_queue_split(bk_runtime* rt, uint32_t slot);
/// The state of a cluster's body from the caller (zero velocity when static).
bk_body_state rt_body_state(const bk_runtime* rt, uint32_t slot);
/// Where a cluster's tree frame is in the world, given its body state.
bk_transform rt_tree_to_world(const rt_cluster* c, const bk_body_state* state);
// The journal (journal.c): each call that changes the destruction state
// writes its entry when def.journal is on (nothing otherwise).
/// A hit as the damage formula takes it: cluster, tree-frame point, impulse.
void rt_journal_hit(bk_runtime* rt, uint32_t slot, bk_vec3 local, double impulse);
/// A fracture command applied (cluster, bond, cause).
void rt_journal_break(bk_runtime* rt, uint32_t slot, uint32_t bond, bk_break_cause cause);
/// A split with this budget (only when clusters wait for one).
void rt_journal_split(bk_runtime* rt, uint32_t budget);
/// A cluster removed by the caller.
void rt_journal_remove(bk_runtime* rt, uint32_t slot);
/// A call of bk_runtime_refine.
void rt_journal_refine(bk_runtime* rt);
/// A breakable's material as it is now (after any of its setters).
void rt_journal_material(bk_runtime* rt, uint32_t breakable_index);
/// A breakable removed, or added (which a follower cannot follow).
void rt_journal_breakable(bk_runtime* rt, uint32_t breakable_index, bool added);
/// Damages the bonds of cluster `slot` from a hit at `local` (tree frame):
/// what a contact's hit does once its point is in the tree frame (damage.c).
void rt_damage_local(bk_runtime* rt, uint32_t slot, bk_vec3 local, double impulse);
/// Splits the queued clusters, making at most `budget` new ones (split.c).
uint32_t rt_split(bk_runtime* rt, uint32_t budget);
