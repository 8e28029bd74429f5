// Breakables runtime (breakables::runtime): Breakable Composite Rigid Bodies
// without a physics engine. A breakable is an instance of a mesh tree; its
// fragments (the tree's leaves) are the nodes of a graph whose edges are the
// tree's bonds. Each connected cluster of fragments is one rigid body of the
// caller's physics engine, whose collider is the smallest set of mesh-tree
// nodes covering exactly its fragments.
//
// The runtime owns no bodies. The caller:
//   1. creates one body per cluster the runtime reports as created, removes
//      the body of each cluster it reports as removed;
//   2. answers where a cluster's body is and how it moves (bk_body_state_fn);
//   3. feeds it contacts (bk_runtime_apply_contacts) or blasts
//      (bk_runtime_damage_at), and, for structures, the weights they carry
//      (bk_runtime_solve_stress: bonds also break under load), then calls
//      bk_runtime_refine (fragments hit hard enough are fractured again
//      around the hit: bk_refine_def) and bk_runtime_split.
// Events are never lost: every call that changes clusters, bonds or trees
// (add_breakable, apply_contacts, damage_at, solve_stress,
// apply_fracture_commands, refine, split, remove_cluster, remove_breakable)
// adds to four lists (created clusters, removed clusters, broken bonds,
// refined fragments) that accumulate until you call
// bk_runtime_clear_events. Read them as often as you like into buffers you
// own (capacity in, count out), act on them (make and remove bodies), then
// clear: once a step, after the runtime's calls of
// that step, is the usual rule (Box2D's events likewise live until the next
// step). A cluster created and removed between two clears appears in neither
// list; until you clear, the runtime answers itself where a cluster you have
// not been given yet is (its created event's body), and asks
// bk_body_state_fn only about the others.
// Setters, queries and calls that fail add nothing.
// Same calls with the same inputs give the same results, bit for bit.
// A runtime is not thread-safe: call it from one thread at a time (its own
// refinement workers touch nothing of it but the meshes they fracture).
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "authoring.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- ids

/// A breakable: index + generation; {0, 0} is null.
typedef struct bk_breakable_id {
  uint32_t index, generation;
} bk_breakable_id;

/// A cluster (one rigid body's worth of fragments): index + generation;
/// {0, 0} is null. A removed cluster's id stops being valid.
typedef struct bk_cluster_id {
  uint32_t index, generation;
} bk_cluster_id;

static inline bool bk_breakable_is_null(bk_breakable_id id) { return id.generation == 0; }
static inline bool bk_cluster_is_null(bk_cluster_id id) { return id.generation == 0; }
static inline bool bk_cluster_equal(bk_cluster_id a, bk_cluster_id b) {
  return a.index == b.index && a.generation == b.generation;
}

// ---------------------------------------------------------------- minimal node sets

/// Writes the smallest set of mesh-tree nodes whose subtrees hold exactly the
/// given leaves (sorted ascending, no duplicates) into out, in depth-first
/// order; returns the count (at most leaf_count). An unbroken object gives the
/// root alone.
uint32_t bk_minimal_nodes(const bk_mesh_tree* tree, const uint32_t* leaves, uint32_t leaf_count,
                          uint32_t* out);

/// The nodes whose convex hulls make a cluster's collider: each node of
/// `nodes` whose hull may stand for it (hull_fits[node] != 0, or a leaf) is
/// kept, any other is replaced by its children, recursively (a hollow egg's
/// hull is a solid egg, so its halves stand in). Writes at most capacity
/// nodes to out; returns how many there are.
uint32_t bk_collider_nodes(const bk_mesh_tree* tree, const uint32_t* nodes, uint32_t node_count,
                           const uint8_t* hull_fits, uint32_t* out, uint32_t capacity);

// ---------------------------------------------------------------- materials

/// What a breakable is made of: the thesis's parameters plus the surface
/// properties a physics engine needs (the runtime keeps those for it).
typedef struct bk_material {
  const char* name;     ///< at most BK_MATERIAL_NAME_MAX bytes; the runtime keeps its own copy
  double density;       ///< kg/m^3, in [BK_MATERIAL_DENSITY_MIN, BK_MATERIAL_DENSITY_MAX]
  double frailty;       ///< damage = frailty x impulse / distance^3; >= 0 (0: unbreakable)
  double bond_strength; ///< hit points per m^2 of bond area, in [BK_MATERIAL_BOND_STRENGTH_MIN, _MAX]
  bool accumulate;      ///< bonds lose hit points over hits (else discrete: one hit must exceed them)
  double friction;      ///< >= 0
  double restitution;   ///< in [0, 1]
  /// Stress limits (Pa, > 0; INFINITY: never fails that way): the stress a
  /// bond carries before it breaks under the load of what it holds up
  /// (bk_runtime_solve_stress). Per bond area, so they do not depend on the
  /// fragment count: stone holds much in compression and little in tension.
  double compression_limit;
  double tension_limit;
  double shear_limit;
  /// Refinement (bk_breakable_def.refine): hit points per m^2 of a
  /// fragment's cross-section (its volume^(2/3)) that a hit's damage at the
  /// fragment (frailty x impulse / distance^3, the distance to its bounds)
  /// must pass for the fragment to be fractured again around the hit;
  /// >= 0, finite; 0 (the presets' and the default): never
  double refine_strength;
} bk_material;

#define BK_MATERIAL_NAME_MAX 31
/// The densities (kg/m^3) and bond strengths (per m^2) a material may have.
/// Far outside any material's, a fragment's mass, inertia or hit points
/// would underflow to 0 or overflow (a denormal density gives bodies no
/// inertia, which no physics engine can move).
#define BK_MATERIAL_DENSITY_MIN 1e-6
#define BK_MATERIAL_DENSITY_MAX 1e9
#define BK_MATERIAL_BOND_STRENGTH_MIN 1e-6
#define BK_MATERIAL_BOND_STRENGTH_MAX 1e15

/// Presets: stone, concrete, glass, porcelain, eggshell, wood.
const bk_material* bk_material_find(const char* name);
uint32_t bk_material_count(void);
const bk_material* bk_material_at(uint32_t index);
/// Checks a material; err names the bad field ("material.frailty must be ...").
bool bk_material_validate(const bk_material* material, bk_error* err);

// ---------------------------------------------------------------- the runtime

/// Where a cluster's body is and how it moves, as the caller's physics has it.
/// The body frame is the cluster's centre of mass with its principal axes
/// (bk_cluster_info.principal places it in the tree frame).
typedef struct bk_body_state {
  bk_transform transform;   ///< body frame in the world
  bk_vec3 linear_velocity;  ///< of the centre of mass (the body frame's origin), m/s, in world axes
  bk_vec3 angular_velocity; ///< rad/s, in world axes (not the body frame's)
} bk_body_state;

/// Asked for the state of a live cluster's body whenever the runtime needs it
/// (to bring a contact point into the tree frame, to give new clusters their
/// parent's motion). A static cluster's velocities are taken as zero
/// whatever is reported, so the pieces a static (anchored) object loses start
/// at rest, and fall.
typedef bk_body_state bk_body_state_fn(bk_cluster_id cluster, void* context);

typedef struct bk_runtime bk_runtime;

/// Runtime parameters; bk_default_runtime_def() fills every field and
/// bk_runtime_create takes them as given.
typedef struct bk_runtime_def {
  double impact_speed;                 ///< contacts closing slower (m/s) do no damage; default 1
  double impulse_threshold;            ///< contacts with less impulse (N s) do no damage; default 0.5
  double damage_min_distance;          ///< s_min of the damage formula (m), > 0; default 0.05
  uint32_t max_new_clusters_per_split; ///< clusters one bk_runtime_split may create, >= 2; default 48
  /// Work one bk_runtime_solve_stress may do, in bond evaluations (an
  /// iteration over a cluster costs about one per bond and two per
  /// fragment: 9,800 for a sound 1,024-fragment wall of 6,060 bonds; making
  /// a cluster's system about ten iterations, a level per step): a solve
  /// that needs more goes on next call, warm. The step that reaches the
  /// budget is finished, so every call makes progress; >= 1; default
  /// 16,000 (about 0.35 ms a call on this project's 2-core machine)
  uint32_t stress_budget;
  /// A solve has converged when the unbalanced force is below this fraction
  /// of the load, in (0, 0.1]; default 1e-3
  double stress_tolerance;
  /// Clusters on the ground (supports) moving faster than this (m/s, at
  /// any point within their size) are not loaded: their weight is not at
  /// rest on anything; >= 0; default 0.25
  double stress_rest_speed;
  /// World gravity (m/s^2, finite): its opposite is "up" for anchoring (a
  /// breakable's anchor plane is perpendicular to it); +Y when zero. The
  /// stress solve takes its own gravity per call. Default (0, -9.81, 0)
  bk_vec3 gravity;
  /// Refinement (bk_runtime_refine): the calls of bk_runtime_refine between
  /// a hit and its pieces landing (0: the next call fractures and lands
  /// them; 1: the next call starts them, the one after lands them, the
  /// work in between on a worker), in [0, 8]; default 1. The result does
  /// not depend on the threads, only on this
  uint32_t refine_latency;
  /// Worker threads refinement may use: 0 does the work on the calling
  /// thread (at the call that lands it); default 1
  uint32_t refine_threads;
  /// Fragments that may start refining per call of bk_runtime_refine (hits
  /// beyond it damage those fragments' bonds as they are), >= 1; default 4
  uint32_t max_refinements_per_call;
  /// Optional: called with a fragment's pieces as soon as they are made, on
  /// the refinement worker (refine_threads > 0) or the thread landing them,
  /// so your own work on them (a physics engine's hulls) is off the
  /// stepping thread; thread-safe, reading nothing the step changes. What it
  /// returns comes back in the refined event (bk_leaf_refined.prepared,
  /// yours then), or goes to refine_discard if the pieces never land (their
  /// breakable removed, the splice refused). Pieces node j >= 1 becomes the
  /// tree's node splice.first_node + j - 1. Default NULL
  void* (*refine_prepare)(const bk_mesh_tree* pieces, void* context);
  void (*refine_discard)(void* prepared, void* context); ///< default NULL
  /// Keep a journal of every call that changes the destruction state
  /// (bk_runtime_journal), for another runtime to follow; default false
  bool journal;
  bk_body_state_fn* body_state; ///< required
  void* context;                ///< passed to body_state
} bk_runtime_def;

bk_runtime_def bk_default_runtime_def(void);
/// Creates a runtime; NULL with err naming the bad field (code
/// BK_ERROR_INVALID_ARGUMENT).
bk_runtime* bk_runtime_create(const bk_runtime_def* def, bk_error* err);
/// Checks a def as bk_runtime_create does: false with err naming the bad
/// field after `prefix` (code BK_ERROR_INVALID_ARGUMENT). bk_runtime_create's
/// prefix is "runtime: "; a def that contains one names it as its field
/// (bk_world_create: "world: runtime.").
bool bk_runtime_def_validate(const bk_runtime_def* def, const char* prefix, bk_error* err);
void bk_runtime_destroy(bk_runtime* runtime);
/// Changes the gravity whose opposite is up for the anchoring of the
/// breakables added from now on (those added keep their anchors).
/// BK_ERROR_INVALID_ARGUMENT (nothing changed) when not finite.
bk_result bk_runtime_set_gravity(bk_runtime* runtime, bk_vec3 gravity);
bk_vec3 bk_runtime_gravity(const bk_runtime* runtime);

/// How a breakable's fragments are fractured again where they are hit
/// (bk_material.refine_strength decides when). The refined fragment becomes
/// an inner node of this breakable's own copy of the tree (other instances
/// of the tree are not changed), its pieces the new leaves, exact as the
/// offline tree's: closed, volumes adding up to the fragment's, bonds from
/// their shared faces, its bonds with its neighbours divided among them.
typedef struct bk_refine_def {
  /// BK_PATTERN_RADIAL (the default: dense small pieces at the hit),
  /// BK_PATTERN_VORONOI (uniform) or BK_PATTERN_PLANES
  bk_fracture_pattern pattern;
  uint32_t pieces; ///< pieces per refinement, in [2, 1024]; default 32
  /// A fragment is refined only while its pieces would be at least this
  /// large on average ((volume / pieces)^(1/3), tree units), > 0; default 0.02
  double min_size;
  double radial_falloff; ///< radial: as bk_fracture_def.radial_falloff; default 1
} bk_refine_def;

/// A breakable: an instance of a mesh tree. bk_default_breakable_def() fills
/// every field; the add call takes them as given.
typedef struct bk_breakable_def {
  const bk_mesh_tree* tree; ///< borrowed: must outlive the runtime; required
  bk_transform transform;   ///< places the tree frame in the world; default identity
  bk_material material;     ///< default: density 2400, frailty 1, bond strength 2e5, discrete
  /// Fragments touching the support plane are bonded to the world (static):
  /// those with a vertex at most anchor_height up (up: the opposite of the
  /// runtime's gravity), the plane perpendicular to up through anchor_height
  bool anchored;
  double anchor_height; ///< height of that plane along up (m); default 0
  /// Yours: handed back in views and events (bk_cluster_info and the
  /// events' breakable_user_data); its first cluster's user data too.
  /// Default NULL
  void* user_data;
  bk_refine_def refine; ///< used when material.refine_strength > 0
} bk_breakable_def;

bk_breakable_def bk_default_breakable_def(void);
/// Adds a breakable as one cluster, reported as created: its body frame
/// starts at def.transform x the cluster's principal frame, at rest. Null id
/// with err naming the bad field (BK_ERROR_INVALID_ARGUMENT); def.tree is
/// checked by bk_mesh_tree_validate on every call (it is the caller's, and
/// may have changed since the last), before anything is allocated:
/// "breakable: tree: leaf 12 (node 40): volume -0.003 is not positive"
/// (BK_ERROR_BAD_TREE).
bk_breakable_id bk_runtime_add_breakable(bk_runtime* runtime, const bk_breakable_def* def, bk_error* err);
/// Removes a breakable and every cluster of it, each reported removed (in
/// index order); its id and theirs become stale, and its slot may be reused
/// (with a new generation). BK_ERROR_STALE_ID for a stale id.
bk_result bk_runtime_remove_breakable(bk_runtime* runtime, bk_breakable_id id);
/// The tree a breakable is made of now (NULL for a stale id): the one it was
/// made from, or once refined the runtime's own grown copy (valid until the
/// next call that lands a refinement or removes the breakable; save it with
/// bk_mesh_tree_save or bk_mesh_tree_save_gltf; never free it).
const bk_mesh_tree* bk_runtime_breakable_tree(const bk_runtime* runtime, bk_breakable_id id);
/// A breakable's user data (NULL for a stale id) and its setter (the
/// events recorded from now on carry the new one; BK_ERROR_STALE_ID).
void* bk_runtime_breakable_user_data(const bk_runtime* runtime, bk_breakable_id id);
bk_result bk_runtime_set_breakable_user_data(bk_runtime* runtime, bk_breakable_id id, void* user_data);

/// Live parameters. Frailty and the damage mode apply to the next hits; a new
/// bond strength scales every intact bond's hit points (their fraction left
/// is kept); density changes every cluster's mass and inertia (read them back
/// with bk_runtime_cluster and give them to your bodies). Setters return
/// BK_OK, or (and change nothing) BK_ERROR_STALE_ID for a stale id,
/// BK_ERROR_INVALID_ARGUMENT for a bad value.
bk_result bk_runtime_set_material(bk_runtime* runtime, bk_breakable_id id, const bk_material* material);
bk_result bk_runtime_set_frailty(bk_runtime* runtime, bk_breakable_id id, double frailty);
bk_result bk_runtime_set_density(bk_runtime* runtime, bk_breakable_id id, double density);
bk_result bk_runtime_set_bond_strength(bk_runtime* runtime, bk_breakable_id id, double bond_strength);
/// The material as it is now (name points into the runtime; zeroed for a stale id).
bk_material bk_runtime_material(const bk_runtime* runtime, bk_breakable_id id);
double bk_runtime_frailty(const bk_runtime* runtime, bk_breakable_id id);
double bk_runtime_density(const bk_runtime* runtime, bk_breakable_id id);
double bk_runtime_bond_strength(const bk_runtime* runtime, bk_breakable_id id);

/// A cluster as it is now. Pointers stay valid until the next call that
/// changes clusters (split, remove, add).
typedef struct bk_cluster_info {
  bk_cluster_id id;
  bk_breakable_id breakable;
  bool is_static;         ///< holds an anchored fragment: keep its body fixed
  bool split_pending;     ///< has broken bonds not yet split (bk_runtime_split)
  const uint32_t* leaves; ///< its fragments, ascending
  uint32_t leaf_count;
  const uint32_t* nodes; ///< minimal node set, depth-first
  uint32_t node_count;
  double mass;            ///< kg
  double volume;          ///< m^3
  bk_transform principal; ///< body frame (centre of mass, principal axes) in the tree frame
  bk_vec3 inertia;        ///< principal moments of inertia (kg m^2)
  /// Yours (bk_runtime_set_cluster_user_data). A new cluster starts with
  /// its parent's (the cluster it split from), a breakable's first with the
  /// breakable's: set your own when you take its created event.
  void* user_data;
  void* breakable_user_data; ///< its breakable's (bk_breakable_def.user_data)
} bk_cluster_info;

/// False for a stale id.
bool bk_runtime_cluster(const bk_runtime* runtime, bk_cluster_id id, bk_cluster_info* out);
/// Live clusters in index order; writes at most capacity (none to NULL),
/// returns how many live.
uint32_t bk_runtime_clusters(const bk_runtime* runtime, bk_cluster_id* out, uint32_t capacity);
/// A bound on cluster indices, to size a table by index: every live
/// cluster's index is below it, and it never shrinks (slots are reused).
uint32_t bk_runtime_cluster_capacity(const bk_runtime* runtime);
/// A cluster's user data (NULL for a stale id), and its setter
/// (BK_ERROR_STALE_ID for a stale id).
void* bk_runtime_cluster_user_data(const bk_runtime* runtime, bk_cluster_id id);
bk_result bk_runtime_set_cluster_user_data(bk_runtime* runtime, bk_cluster_id id, void* user_data);
/// The cluster a fragment belongs to (null once its cluster was removed).
bk_cluster_id bk_runtime_leaf_cluster(const bk_runtime* runtime, bk_breakable_id id, uint32_t leaf);

/// A contact on a cluster's body, from the caller's physics.
typedef struct bk_damage_contact {
  bk_cluster_id cluster;
  bk_vec3 point;  ///< world position
  double impulse; ///< normal impulse (N s)
  /// Speed at which the two surfaces approached along the normal before the
  /// contact (m/s): positive when closing, the sign damage needs; contacts
  /// slower than impact_speed do no damage
  double closing_speed;
} bk_damage_contact;

/// Damages bonds from contacts that pass the thresholds; stale clusters are
/// skipped; contacts may be NULL with count 0 (NULL applies none). Results:
/// broken bonds.
void bk_runtime_apply_contacts(bk_runtime* runtime, const bk_damage_contact* contacts, uint32_t count);
/// Damages every live cluster as if a contact with this impulse happened at
/// the world point (explosions, scripted destruction), without the
/// thresholds. Results: broken bonds. It breaks bonds only and pushes
/// nothing: the pieces keep their body's motion, and a blast that should
/// throw them is the caller's impulse on the new bodies.
void bk_runtime_damage_at(bk_runtime* runtime, bk_vec3 point, double impulse);
/// Splits clusters with broken bonds into connected clusters, creating at
/// most max_new_clusters_per_split; what does not fit waits for the next
/// call, in order. Results: removed clusters, then created ones (each split
/// removes its parent and creates its parts). Returns the clusters this call
/// created.
uint32_t bk_runtime_split(bk_runtime* runtime);
/// Takes a cluster out (its fragments leave the simulation, e.g. retired
/// debris). Results: that cluster removed. BK_ERROR_STALE_ID for a stale id.
bk_result bk_runtime_remove_cluster(bk_runtime* runtime, bk_cluster_id id);

/// A cluster created since the last clear, live (one created and removed
/// since is in neither list). The info is the cluster as it is now.
typedef struct bk_cluster_created {
  bk_cluster_info cluster;
  /// The cluster it split from as you know it: one you were given before
  /// (reported removed by now), never one created and removed since the
  /// last clear; null for a breakable's first
  bk_cluster_id parent;
  bk_body_state body; ///< where its body starts and how it moves (its parent's v + w x r)
} bk_cluster_created;

/// A cluster removed since the last clear (one you were given).
typedef struct bk_cluster_removed {
  bk_cluster_id cluster;
  bk_breakable_id breakable;
  void* user_data; ///< the cluster's, as it was when removed
  void* breakable_user_data;
} bk_cluster_removed;

/// What broke a bond.
typedef enum bk_break_cause {
  BK_BREAK_DAMAGE, ///< a hit (contacts, bk_runtime_damage_at)
  BK_BREAK_STRESS, ///< the load it carried passed its material's limit
} bk_break_cause;

/// A bond broken since the last clear.
typedef struct bk_bond_break {
  bk_breakable_id breakable;
  /// The cluster it was inside (one created and removed since the last
  /// clear, which you never see, may be named)
  bk_cluster_id cluster;
  uint32_t bond;    ///< index into the tree's bonds
  bk_vec3 position; ///< world position of the bond centroid
  bk_vec3 velocity; ///< velocity of the cluster's body at that point
  double area;      ///< m^2
  bk_break_cause cause;
  void* user_data;           ///< its cluster's, when it broke
  void* breakable_user_data; ///< its breakable's, when it broke
} bk_bond_break;

/// The events since the last clear, oldest first: each writes at most
/// capacity entries and returns the total (out may be NULL: it writes
/// none); reading takes nothing away. What is written is a copy; the
/// pointers of a created cluster's info stay valid until the next call that
/// changes clusters (split, remove, add).
uint32_t bk_runtime_created_clusters(const bk_runtime* runtime, bk_cluster_created* out, uint32_t capacity);
uint32_t bk_runtime_removed_clusters(const bk_runtime* runtime, bk_cluster_removed* out, uint32_t capacity);
uint32_t bk_runtime_broken_bonds(const bk_runtime* runtime, bk_bond_break* out, uint32_t capacity);
/// Empties the three lists: call it once you have acted on them (made the
/// created clusters' bodies, removed the removed ones'). From then on the
/// runtime asks bk_body_state_fn where every live cluster is.
void bk_runtime_clear_events(bk_runtime* runtime);

// ---------------------------------------------------------------- refinement

/// Lands and starts refinements; call it once a step, after the step's hits
/// and before bk_runtime_split. A hit whose damage at a fragment passes its
/// breakable's material.refine_strength (fragments large enough for
/// bk_refine_def.min_size, at most max_refinements_per_call starting per
/// call) marks it to be fractured again around the hit; the damage of that
/// hit, and of later hits, to the fragment's bonds waits for its pieces.
/// The refine_latency-th call after the mark lands them: the fragment
/// becomes an inner node with the pieces its leaves (leaf numbers after it
/// move up, see bk_splice_info), its cluster keeps its node set, body and
/// mass, and the waiting hits damage the pieces' bonds as if they had been
/// there all along. A fragment that cannot be fractured stays whole and
/// takes its waiting damage. Results: refined leaves, broken bonds. Returns
/// how many fragments it refined.
uint32_t bk_runtime_refine(bk_runtime* runtime);

/// A fragment refined since the last clear: its breakable's tree grew
/// (bk_runtime_breakable_tree) by these nodes and leaves.
typedef struct bk_leaf_refined {
  bk_breakable_id breakable;
  bk_cluster_id cluster; ///< the cluster holding the pieces (its node set is unchanged)
  bk_splice_info splice; ///< what changed in the tree
  void* breakable_user_data;
  void* prepared; ///< what bk_runtime_def.refine_prepare returned for these pieces (yours), or NULL
} bk_leaf_refined;

/// The refinements since the last clear, oldest first (as the other events:
/// at most capacity written, the total returned).
uint32_t bk_runtime_refined_leaves(const bk_runtime* runtime, bk_leaf_refined* out, uint32_t capacity);

// ---------------------------------------------------------------- stress

/// Where a moving cluster's body rests on something static (the ground, a
/// static cluster, a fixed world object): a point of a contact, from the
/// caller's physics. The fragment there carries the load down.
typedef struct bk_stress_support {
  bk_cluster_id cluster;
  bk_vec3 point; ///< world position
} bk_stress_support;

/// A force on a cluster beyond its own weight: something resting on it (a
/// weight on a bridge, debris on a balcony), e.g. a resting contact's
/// impulse over the step. The fragment under the point carries it.
typedef struct bk_stress_load {
  bk_cluster_id cluster;
  bk_vec3 point; ///< world position
  bk_vec3 force; ///< N, world
} bk_stress_load;

/// Loads clusters with their weight (gravity, world m/s^2) and the given
/// loads (may be NULL with load_count 0) and solves the forces their bonds
/// carry down to their supports: a static cluster's anchored fragments, and
/// the fragments of a slow cluster at the given support points. Bonds whose
/// stress passes their material's limits break. Results: broken bonds
/// (cause BK_BREAK_STRESS); split next. The same as bk_runtime_stress_commands
/// with room for every command, then bk_runtime_apply_fracture_commands.
///
/// Costs nothing for a cluster whose solve converged and whose bonds,
/// supports, loads (within a tenth of its weight and loads) and limits did
/// not change since (a structure at rest); clusters that changed share
/// stress_budget per call, each warm-started from its last solution, and
/// break bonds only once their solve has converged (never from a
/// half-solved load).
void bk_runtime_solve_stress(bk_runtime* runtime, bk_vec3 gravity, const bk_stress_support* supports,
                             uint32_t support_count, const bk_stress_load* loads, uint32_t load_count);

/// A bond to break, as the stress solve reports it (as Blast's stress
/// extension emits bond fracture commands instead of breaking bonds itself).
typedef struct bk_fracture_command {
  bk_cluster_id cluster; ///< the cluster the bond is inside
  uint32_t bond;         ///< index into its breakable's tree bonds
  bk_vec3 position;      ///< world position of the bond centroid (for the break event)
  bk_vec3 velocity;      ///< velocity of the cluster's body there (for the break event)
  bk_break_cause cause;  ///< BK_BREAK_STRESS from the stress solve
} bk_fracture_command;

/// Solves as bk_runtime_solve_stress does but breaks nothing: writes the
/// bonds the solve finds past their limits to `commands` (at most capacity;
/// commands may be NULL with capacity 0) and returns how many it wrote, so
/// you can inspect, filter or defer them (apply them with
/// bk_runtime_apply_fracture_commands). A cluster whose commands do not all
/// fit writes none and is checked again on the next call; one whose commands
/// were written counts as solved: commands you do not apply are not
/// reported again until the cluster changes (a break, a new support or load,
/// a material change).
uint32_t bk_runtime_stress_commands(bk_runtime* runtime, bk_vec3 gravity, const bk_stress_support* supports,
                                    uint32_t support_count, const bk_stress_load* loads, uint32_t load_count,
                                    bk_fracture_command* commands, uint32_t capacity);

/// Breaks the bonds the commands name, in order, and returns how many broke.
/// A command is skipped when its cluster is stale, its bond index is out of
/// range, its bond is broken already or not inside that cluster, or its
/// cause is not a bk_break_cause. Results: broken bonds (with the command's
/// position, velocity and cause; cause BK_BREAK_STRESS counts in
/// stress_bonds_broken); split next.
uint32_t bk_runtime_apply_fracture_commands(bk_runtime* runtime, const bk_fracture_command* commands,
                                            uint32_t count);

/// The stress a bond carried at its cluster's last converged solve.
typedef struct bk_bond_stress {
  double compression; ///< Pa (normal push plus bending), >= 0
  double tension;     ///< Pa (normal pull plus bending), >= 0
  double shear;       ///< Pa (sliding plus twisting), >= 0
  double ratio;       ///< the largest of the three over its limit: 1 breaks
} bk_bond_stress;

/// False (out zeroed) for a stale id, a bad bond index, or a bond whose
/// cluster has not been solved; a broken bond reports zero.
bool bk_runtime_bond_stress(const bk_runtime* runtime, bk_breakable_id id, uint32_t bond,
                            bk_bond_stress* out);

/// Hit points left of a bond (0 when broken) and its initial hit points.
double bk_runtime_bond_health(const bk_runtime* runtime, bk_breakable_id id, uint32_t bond, double* initial);

/// Totals since creation.
typedef struct bk_runtime_stats {
  uint32_t breakables;              ///< live
  uint32_t clusters;                ///< live
  uint32_t bonds_broken;            ///< since creation
  uint32_t splits;                  ///< clusters split since creation
  uint32_t pending_splits;          ///< clusters waiting for the split budget
  uint32_t stress_bonds_broken;     ///< by stress, since creation (part of bonds_broken)
  uint32_t stress_clusters_solved;  ///< clusters the last bk_runtime_solve_stress iterated on
  uint32_t stress_iterations;       ///< iterations it spent, over all clusters
  uint32_t stress_clusters_pending; ///< clusters whose solve has not converged yet
  uint32_t refined_leaves;          ///< fragments refined since creation
  uint32_t refine_pending;          ///< fragments marked and not landed yet
  uint32_t refine_failed;           ///< fragments that could not be fractured (left whole)
} bk_runtime_stats;

bk_runtime_stats bk_runtime_get_stats(const bk_runtime* runtime);

/// 64 bits over the destruction state: every breakable's tree as it stands
/// (a refined one's grown shape and bonds), material, bonds' hit points and
/// breaks, anchors; every cluster's id and leaves; the splits and
/// refinements waiting, with their hits. Two runtimes given the same calls
/// have the same hash, on any machine and compiler that computes the same
/// doubles (XXH3 over the fields in a fixed order, little endian; a double
/// by its bits, -0 as +0). It does not cover user data, events not cleared
/// or where bodies are (bk_world_state_hash adds those).
uint64_t bk_runtime_state_hash(const bk_runtime* runtime);

// ---------------------------------------------------------------- save and load

/// Bytes bk_runtime_save_state would write for the runtime as it is now.
size_t bk_runtime_state_size(const bk_runtime* runtime);
/// Writes the destruction state (what bk_runtime_state_hash covers, plus a
/// refined breakable's grown tree and the refinements waiting) into
/// out[0..capacity), versioned and checksummed: returns the bytes written, or
/// 0 with err set ("state: buffer of N bytes is too small, the state needs M";
/// out's bytes are then unspecified).
/// The stress solver's warm start is not saved: a loaded runtime's stress
/// solves start cold. User data and events not cleared are not state.
size_t bk_runtime_save_state(const bk_runtime* runtime, void* out, size_t capacity, bk_error* err);
/// Replaces the destruction state with a saved one. The runtime must hold the
/// same breakables in the same slots with the same trees as when saved
/// (checked: source hash, node/leaf/bond counts), else refused in one line
/// naming what differs, and nothing changes (all-or-nothing; a damaged or
/// hostile state is refused the same way). On success bk_runtime_state_hash
/// equals the saved runtime's, the refinements waiting are made again, every
/// event is cleared and the clusters are new: the caller's bodies are stale,
/// and it makes a body for every cluster of bk_runtime_clusters (at the
/// transforms it saved with them; bk_world_load_state does this itself).
/// A load is not a journal entry (bk_runtime_journal): a follower loads the
/// same state to follow on.
bool bk_runtime_load_state(bk_runtime* runtime, const void* data, size_t size, bk_error* err);

// ---------------------------------------------------------------- journal

/// The journal: a compact byte record of every call that changed the
/// destruction state, in order, which a second runtime holding the same
/// breakables (a watching client, a replay) applies to reach the same state
/// hash after each call, with no damage of its own. It records the hits as
/// the damage formula took them (cluster, the point in the tree frame, the
/// impulse: 36 bytes or so, each breaking any number of bonds), the
/// fracture commands applied (the stress stage's breaks), the splits, the
/// refinement calls, cluster and breakable removals and material changes.
/// Adding a breakable cannot be followed this way (a follower needs the
/// tree): the entry it writes makes bk_runtime_apply_journal refuse, and
/// the follower needs a saved state. The entries, byte by byte:
/// docs/embedding.md, "Following a runtime".
bk_result bk_runtime_set_journal(bk_runtime* runtime, bool journal);
bool bk_runtime_journal_enabled(const bk_runtime* runtime);
/// The journal since the last clear (size bytes; valid until the runtime's
/// next call that changes state), or NULL and 0 when empty.
const void* bk_runtime_journal(const bk_runtime* runtime, size_t* size);
/// Empties the journal: call it once the bytes are sent or kept.
void bk_runtime_clear_journal(bk_runtime* runtime);
/// Applies another runtime's journal, entry by entry. The bytes are checked
/// whole first (a malformed journal changes nothing); an entry that does
/// not apply (its cluster is not live here, its bond is broken already: the
/// two runtimes have diverged) stops there with err naming the entry, the
/// entries before it applied. Results: as the calls recorded make them
/// (broken bonds, created and removed clusters, refined leaves); a hit's
/// events are placed where this runtime's bodies are.
bool bk_runtime_apply_journal(bk_runtime* runtime, const void* data, size_t size, bk_error* err);

#ifdef __cplusplus
}
#endif
