// Breakables on Bullet (breakables::bullet): the physics extension of the
// runtime. Two layers:
//   - bk_physics: a C interface over Bullet. Opaque world, typed ids with a
//     generation (zero = null), C types only. After each step, contacts are
//     pulled as an array; no callbacks cross from the physics engine into C.
//   - bk_world: breakables as Breakable Composite Rigid Bodies on bk_physics,
//     built on <breakables/runtime.h>: one Bullet body per cluster, its
//     compound made of the hulls of the cluster's mesh-tree nodes, contacts
//     fed to the runtime as damage, splits turned into new bodies. Plus
//     projectiles and the statistics the demo and benchmarks report.
// Every *_def is filled completely by its bk_default_*_def(); create calls
// take the values as given (zero friction is zero friction) and name the bad
// field when one is wrong.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "runtime.h"

#ifdef __cplusplus
extern "C" {
#endif

/// The physics world (owns every shape and body created in it).
typedef struct bk_physics bk_physics;

/// A rigid body: index + generation; {0, 0} is null. A destroyed body's id
/// stops being valid (its slot's generation moves on).
typedef struct bk_body_id {
  uint32_t index, generation;
} bk_body_id;

/// A collision shape, same scheme as bodies.
typedef struct bk_shape_id {
  uint32_t index, generation;
} bk_shape_id;

static inline bool bk_body_is_null(bk_body_id id) { return id.generation == 0; }
static inline bool bk_shape_is_null(bk_shape_id id) { return id.generation == 0; }
static inline bool bk_body_equal(bk_body_id a, bk_body_id b) {
  return a.index == b.index && a.generation == b.generation;
}

/// World parameters (bk_default_physics_def() fills every field).
typedef struct bk_physics_def {
  bk_vec3 gravity;           ///< default (0, -9.81, 0)
  double fixed_dt;           ///< internal substep, in (0, 0.1] s; default 1/60 s
  uint32_t contact_capacity; ///< contacts kept per step (more are counted, not stored); default 65536
  double default_margin;     ///< collision margin of hulls (>= 0); default 0.004 m
} bk_physics_def;

/// Defaults: gravity -9.81 y, 60 Hz substeps.
bk_physics_def bk_default_physics_def(void);
/// Creates a world (split impulse on, so penetration recovery adds no
/// contact impulse). It also sets two of Bullet's process-wide globals,
/// gDeactivationTime (0.5 s: a body still that long falls asleep) and
/// gDbvtMargin (1 cm), the same values every
/// time: other Bullet worlds in the process share them, so create worlds
/// from one thread, not while another world steps. Returns NULL with err naming the bad field.
bk_physics* bk_physics_create(const bk_physics_def* def, bk_error* err);
/// Destroys the world with every shape and body left in it.
void bk_physics_destroy(bk_physics* world);
void bk_physics_set_gravity(bk_physics* world, bk_vec3 gravity);
bk_vec3 bk_physics_gravity(const bk_physics* world);
/// What the last step worked on (for statistics and tuning).
typedef struct bk_physics_stats {
  uint32_t bodies;         ///< rigid bodies in the world
  uint32_t awake_bodies;   ///< dynamic bodies that were simulated (not asleep)
  uint32_t pairs;          ///< broadphase pairs (bounding boxes overlapping)
  uint32_t manifolds;      ///< narrowphase pairs with a contact manifold
  uint32_t contact_points; ///< points in those manifolds
  /// Pairs the last step tested in the narrowphase (their boxes touch and a
  /// body is awake); the other pairs cost a box test each.
  uint32_t narrow_pairs;
  /// Box overlaps the broadphase found in the last step (new pairs, and
  /// those its filter groups turned down): the work of boxes moving among
  /// others.
  uint32_t box_overlaps;
} bk_physics_stats;

bk_physics_stats bk_physics_get_stats(const bk_physics* world);
/// Advances by dt in fixed substeps (at most max_substeps); returns the
/// substeps taken. Contacts of every substep are collected for bk_physics_contacts.
int bk_physics_step(bk_physics* world, double dt, int max_substeps);

// ---------------------------------------------------------------- shapes

/// Convex hull of points, simplified to at most max_vertices (<= 64; 0 = 64).
/// Returns null if fewer than 4 non-coplanar points are given.
bk_shape_id bk_physics_create_hull(bk_physics* world, const bk_vec3* points, uint32_t count,
                                   uint32_t max_vertices);
/// What bk_physics_create_hull computes before it makes a shape: the hull's
/// core (simplified, shrunk by the margin) and its measures.
#define BK_HULL_PREPARED_MAX 128
typedef struct bk_hull_prepared {
  bk_vec3 vertices[BK_HULL_PREPARED_MAX]; ///< the core's vertices
  uint32_t vertex_count;                  ///< 0: no hull (fewer than 4 non-coplanar points)
  double margin;                          ///< the shrink applied (the shape's margin)
  double volume;                          ///< the hull's volume before shrinking
  double inner_radius;
} bk_hull_prepared;
/// Computes a hull as bk_physics_create_hull does, for a world whose hull
/// margin is `margin` (bk_physics_hull_margin), without touching a world: it
/// may run on any thread (a refinement worker prepares its pieces' hulls).
/// False (vertex_count 0) when there is no hull.
bool bk_physics_prepare_hull(const bk_vec3* points, uint32_t count, uint32_t max_vertices, double margin,
                             bk_hull_prepared* out);
/// The hull shape of prepared data (microseconds): the same shape
/// bk_physics_create_hull makes of the same points. Null if it has no hull.
bk_shape_id bk_physics_create_prepared_hull(bk_physics* world, const bk_hull_prepared* prepared);
/// The margin hulls are shrunk by (bk_physics_def.default_margin).
double bk_physics_hull_margin(const bk_physics* world);
/// A hull's copy moved by `transform` (its core vertices moved, its margin and
/// volume kept): the same solid in another frame, made without computing a
/// hull again (microseconds, where bk_physics_create_hull takes tens of them).
/// Returns null if `hull` is not a live hull or the transform is not finite.
bk_shape_id bk_physics_copy_hull(bk_physics* world, bk_shape_id hull, bk_transform transform);
bk_shape_id bk_physics_create_sphere(bk_physics* world, double radius);
bk_shape_id bk_physics_create_box(bk_physics* world, bk_vec3 half_extents);
/// Infinite static plane dot(normal, x) = offset.
bk_shape_id bk_physics_create_plane(bk_physics* world, bk_vec3 normal, double offset);
/// Empty compound; add children (they are referenced, not copied: a child may
/// be shared by many compounds and must outlive them).
bk_shape_id bk_physics_create_compound(bk_physics* world, uint32_t expected_children);
void bk_physics_compound_add(bk_physics* world, bk_shape_id compound, bk_shape_id child, bk_transform local);
/// Destroys a shape; it must not be in use by a body or a compound.
void bk_physics_destroy_shape(bk_physics* world, bk_shape_id shape);
bool bk_physics_shape_valid(const bk_physics* world, bk_shape_id shape);
/// Vertices of a hull shape's core after simplification: the hull is shrunk
/// by its collision margin, so its surface is these vertices grown by the
/// margin. Returns the vertex count (writes at most capacity).
uint32_t bk_physics_hull_vertices(const bk_physics* world, bk_shape_id hull, bk_vec3* out, uint32_t capacity);
/// Volume of the convex hull of the points the shape was made from (exact,
/// before simplification is applied to the core).
double bk_physics_hull_volume(const bk_physics* world, bk_shape_id hull);
/// Number of shapes alive (for leak checks and statistics).
uint32_t bk_physics_shape_count(const bk_physics* world);

// ---------------------------------------------------------------- bodies

/// A rigid body. The body frame is its centre of mass with principal axes:
/// `transform` places that frame in the world and `inertia` holds the
/// principal moments. bk_default_body_def() fills every field.
typedef struct bk_body_def {
  bk_shape_id shape;
  double mass;            ///< 0 = static body
  bk_vec3 inertia;        ///< principal moments of inertia (dynamic bodies)
  bk_transform transform; ///< rotation a unit quaternion; default identity
  bk_vec3 linear_velocity, angular_velocity;
  double friction;    ///< >= 0; default 0.6
  double restitution; ///< in [0, 1]; default 0.1
  /// Resistance to rolling and spinning on a contact (torque per normal
  /// force, in metres); 0 = none. Debris needs it to come to rest: a rounded
  /// shard otherwise rolls on for seconds and keeps its whole pile awake.
  double rolling_friction;
  double linear_damping, angular_damping;
  bool ccd;          ///< continuous collision detection, for fast small bodies
  double ccd_radius; ///< swept sphere radius for CCD; 0 (default) = the largest sphere inside the shape
  bool disable_sleep;
  /// Debris collides with everything but other debris (Bullet's collision
  /// filter groups: its pairs with debris are never made); default false
  bool debris;
  uint64_t user_data;
} bk_body_def;

bk_body_def bk_default_body_def(void);
/// Creates a body; returns null with err naming the bad field (non-finite
/// values, negative mass, zero inertia on a dynamic body, invalid shape).
bk_body_id bk_physics_create_body(bk_physics* world, const bk_body_def* def, bk_error* err);
/// Removes a body from the world (its shape stays; see bk_physics_destroy_shape).
void bk_physics_destroy_body(bk_physics* world, bk_body_id body);
/// Removes `count` bodies at once (invalid or repeated ids are skipped): one
/// walk over the broadphase's pairs for all of them, where a body at a time
/// costs three each. For removing many bodies in one step (retiring debris).
/// The pairs left are the same, in another order, so later steps differ
/// from removing the bodies one at a time by the solver's order.
void bk_physics_destroy_bodies(bk_physics* world, const bk_body_id* bodies, uint32_t count);
bool bk_physics_body_valid(const bk_physics* world, bk_body_id body);
uint32_t bk_physics_body_count(const bk_physics* world);
bk_transform bk_physics_body_transform(const bk_physics* world, bk_body_id body);
void bk_physics_body_set_transform(bk_physics* world, bk_body_id body, bk_transform transform);
bk_vec3 bk_physics_body_linear_velocity(const bk_physics* world, bk_body_id body);
bk_vec3 bk_physics_body_angular_velocity(const bk_physics* world, bk_body_id body);
void bk_physics_body_set_velocity(bk_physics* world, bk_body_id body, bk_vec3 linear, bk_vec3 angular);
/// Changes mass and principal inertia (density edits); mass 0 is not allowed here.
void bk_physics_body_set_mass(bk_physics* world, bk_body_id body, double mass, bk_vec3 inertia);
/// Changes friction (>= 0) and restitution ([0, 1]); bad values change nothing.
void bk_physics_body_set_surface(bk_physics* world, bk_body_id body, double friction, double restitution);
double bk_physics_body_mass(const bk_physics* world, bk_body_id body);
/// Principal moments of inertia of a dynamic body (zero for static ones).
bk_vec3 bk_physics_body_inertia(const bk_physics* world, bk_body_id body);
void bk_physics_body_apply_impulse(bk_physics* world, bk_body_id body, bk_vec3 impulse, bk_vec3 world_point);
bool bk_physics_body_awake(const bk_physics* world, bk_body_id body);
uint64_t bk_physics_body_user_data(const bk_physics* world, bk_body_id body);
/// Moves a body into or out of debris (bk_body_def.debris). Its pairs with
/// other debris go, or are found again, before the next step.
void bk_physics_body_set_debris(bk_physics* world, bk_body_id body, bool debris);
/// Whether a body is debris now.
bool bk_physics_body_debris(const bk_physics* world, bk_body_id body);
/// Gives a body another collision shape, keeping its mass, inertia and
/// motion (a cheaper stand-in for a far piece, say). The old shape stays
/// alive, no longer used by this body. False for a stale id or a plane on a
/// dynamic body.
bool bk_physics_body_set_shape(bk_physics* world, bk_body_id body, bk_shape_id shape);
/// The shape a body collides with now.
bk_shape_id bk_physics_body_shape(const bk_physics* world, bk_body_id body);
/// Pins a dynamic body where it is (frozen: zero velocity, static to the
/// solver and the narrowphase, as the ground is) until unpinned; touches do
/// not wake it, and velocity changes and impulses are ignored meanwhile.
/// Unpinned, it is awake, and falls if what held it has gone. Static bodies ignore it.
void bk_physics_body_set_pinned(bk_physics* world, bk_body_id body, bool pinned);
/// Whether a body is pinned now.
bool bk_physics_body_pinned(const bk_physics* world, bk_body_id body);
/// Unpins a body where it lies, asleep rather than awake: it stays frozen
/// until a moving body touches it or what it rests on is removed (for a
/// piece known to be at rest, whose waking would wake what it touches).
void bk_physics_body_unpin_at_rest(bk_physics* world, bk_body_id body);
/// Parks bodies (invalid, repeated or parked ids are skipped): they leave
/// Bullet's world (no box, pair, contact or integration: they cost nothing
/// per step) and keep their shape, transform and mass; velocities are
/// zeroed and pinning is undone. For bodies at rest that a static compound
/// now stands in for (bk_world_def.settle_cell). One walk over the
/// broadphase's pairs for all of them; what touched them is not woken.
void bk_physics_park_bodies(bk_physics* world, const bk_body_id* bodies, uint32_t count);
/// Brings parked bodies back where they were, in the order given, at rest:
/// `moving`, awake (they fall if nothing holds them, and sleep again after
/// a moment if something does); else calm, as frozen bodies are (asleep
/// unless a moving body touches them).
void bk_physics_unpark_bodies(bk_physics* world, const bk_body_id* bodies, uint32_t count, bool moving);
/// Whether a body is parked now.
bool bk_physics_body_parked(const bk_physics* world, bk_body_id body);
/// Removes bodies as bk_physics_destroy_bodies does, without waking what
/// touched them (a static stand-in replaced by what it stood for).
void bk_physics_destroy_bodies_quietly(bk_physics* world, const bk_body_id* bodies, uint32_t count);
/// Watches a static body: its box in the broadphase grows by margin (m), and
/// it is disturbed when a body moving faster than speed (m/s) comes that
/// near, or a body whose box overlapped it is destroyed.
void bk_physics_body_watch(bk_physics* world, bk_body_id body, double margin, double speed);
/// How a watched body was disturbed since the last call (which clears it):
/// 0 not, 1 a fast body came near, 2 a body it touched was removed.
int bk_physics_body_take_disturbed(bk_physics* world, bk_body_id body);
/// The world box of a body's shape where the body is now (parked or not).
void bk_physics_body_bounds(const bk_physics* world, bk_body_id body, bk_vec3* lo, bk_vec3* hi);

// ---------------------------------------------------------------- queries

/// One contact point from one substep of the last bk_physics_step.
typedef struct bk_contact {
  bk_body_id a, b;
  bk_vec3 point;  ///< world position (midpoint of the two witness points)
  bk_vec3 normal; ///< world normal pointing from b towards a
  double impulse; ///< normal impulse the solver applied (N s)
  double
      approach_speed; ///< closing speed along the normal before that substep's solve (m/s; > 0 = approaching)
  int32_t child_a, child_b; ///< the child of a's (b's) compound shape touched; -1 if not a compound
} bk_contact;

/// Copies the contacts of the last step (all substeps, only points with a
/// positive impulse) into out; returns how many there were in total (may
/// exceed capacity; the rest are dropped).
uint32_t bk_physics_contacts(const bk_physics* world, bk_contact* out, uint32_t capacity);

typedef struct bk_ray_hit {
  bk_body_id body;
  bk_vec3 point, normal;
  double fraction; ///< along the ray, 0..1
} bk_ray_hit;

/// Closest hit along the segment from -> to; false if none.
bool bk_physics_ray_cast(const bk_physics* world, bk_vec3 from, bk_vec3 to, bk_ray_hit* hit);

// ---------------------------------------------------------------- world

typedef struct bk_world bk_world;

/// World parameters; bk_default_world_def() fills every field and
/// bk_world_create takes them as given (zero gravity is zero gravity).
typedef struct bk_world_def {
  bk_vec3 gravity; ///< default (0, -9.81, 0)
  double fixed_dt; ///< one bk_world_step, in (0, 0.1] s; default 1/60 s
  bool ground;     ///< a static ground plane at y = 0; default true
  /// The runtime the world drives (bk_default_runtime_def's values): its
  /// damage thresholds, its split budget (max_new_clusters_per_split: the
  /// new bodies one step may make), its stress budget and its refinement
  /// (refine_latency, refine_threads, max_refinements_per_call). The world sets its
  /// gravity (from gravity above), body_state and context; bk_world_create
  /// names a bad field as "runtime.<field>".
  bk_runtime_def runtime;
  /// Hits (contacts that damage) one step may apply, as the fragments they
  /// sweep: a hit on a cluster of n fragments weighs every bond of it and
  /// costs n. Past it, the later hits wait for the next steps, oldest
  /// first, at the same place on their object (which keeps its body and
  /// moves with it). While hits wait, steps take turns: one applies hits
  /// and splits nothing, the next splits (up to runtime.max_new_clusters_per_split)
  /// and applies no hit, so damage and new bodies never add up in one
  /// step. A hit turn applies at least one hit; a waiting hit whose cluster
  /// has split meanwhile is dropped. Any value is valid; 0 = no limit.
  /// Default 1024: one 1,024-fragment wall a step, about 0.75 ms on this
  /// project's 2-core machine when most of its bonds break
  uint32_t max_hit_fragments_per_step;
  double projectile_lifetime; ///< seconds before a projectile is removed (> 0); default 8
  /// Loose single fragments smaller than this volume (m^3) are removed after
  /// retire_after seconds, to keep long sessions bounded, and handed to
  /// bk_world_retired_bodies for the renderer to fade out (as Chaos removes
  /// pieces on sleep); 0 = never. Default 2e-5 (chips under 20 cm^3)
  double retire_volume;
  double retire_after; ///< seconds a small fragment lives once free (> 0); default 10
  /// Structural stress each step (bk_runtime_solve_stress): what has lost
  /// its support breaks off and falls; default true. Its work per step is
  /// runtime.stress_budget (16,000 bond evaluations, about 0.35 ms on this
  /// project's 2-core machine)
  bool stress;
  /// What the physics of a step may cost, in ms (>= 0; 0 = no budget). Over
  /// it, the least important loose pieces get cheaper, tier by tier (see
  /// bk_budget_tier); at less than half of it, they get their fidelity back
  /// (debris lying still stays debris until it moves again).
  /// Default 8, half a 60 Hz frame, leaving the other half to drawing on
  /// this project's 2-core machine; 0 turns it off (every piece fully
  /// simulated, as a physics engine alone does). Retired pieces are handed
  /// to bk_world_retired_bodies for the renderer to fade out.
  double physics_budget_ms;
  /// How the cost is known: false (default) an estimate from what Bullet
  /// worked on in the step (awake bodies, pairs, manifolds; calibrated on
  /// this project's 2-core machine), so the same inputs make the same
  /// decisions; true the measured time, which follows the machine but
  /// is not reproducible.
  bool physics_budget_measured;
  /// Pieces of this volume (m^3) or more are never made cheaper (> 0);
  /// default 0.008 (a 20 cm cube)
  double budget_large_volume;
  /// Pieces within this distance (m) of the focus (bk_world_set_focus) are
  /// never made cheaper (>= 0); default 2
  double budget_focus_radius;
  /// For this long (s, >= 0) after a piece comes loose, the budget keeps
  /// what the player sees of it: it becomes debris only while it flies
  /// apart (not while it presses on another loose piece at under 1 m/s,
  /// where it would fall through the pile), is frozen only once asleep, and
  /// is never retired. The budget may then stay over physics_budget_ms
  /// while a large pile settles. 0 makes every piece fair game at once
  /// (cheaper, but piles collapse through themselves); default 1
  double budget_fidelity_time;
  /// budget_fidelity_time holds for pieces within this distance (m, >= 0)
  /// of the focus, what the player sees up close; farther ones are fair game
  /// at once (and everywhere, with no focus set, it holds). Default 8: 16
  /// walls shot at once then cost 14 ms a step at the 95th percentile under
  /// an 8 ms budget (160 ms without one, 76 with every new piece kept),
  /// the debris within it moving as without a budget
  double budget_fidelity_radius;
  /// Within that radius, budget_fidelity_time holds only for pieces that
  /// look at least this large from the focus: their size (the cube root of
  /// their volume) over their distance, in radians (0..1; 0 keeps every
  /// piece). Smaller ones are a few pixels on screen, too small to see how
  /// they move, and are fair game at once. Default 0.006: four pixels of a
  /// 720-line picture with a 60 degree field of view
  double budget_visible_angle;
  /// Keeping young pieces' first second, a step may cost up to this many
  /// times physics_budget_ms; over it, the least important young pieces
  /// give up theirs (as many as it takes, back when the cost falls), so that
  /// a fresh pile in front of the camera costs a bounded time, not what it
  /// costs without a budget. >= 1, or 0 for no bound (the first second kept
  /// whatever it costs). Default 2: 16 ms at the default budget, a 60 Hz
  /// frame (a glass cube of 4,096 shattered in front of the camera then
  /// costs 18 ms a step at p95 instead of 200, and its debris keeps 82% of
  /// its mass and 35% of its momentum over the first second)
  double budget_fidelity_factor;
  /// Settled debris costs nothing: every quarter second (up to 512 pieces a
  /// time, and while the physics budget is on, once its level is under 1),
  /// loose pieces at rest (asleep or frozen, not anchored, not about to
  /// split) leave Bullet's world, and one static compound per cell of this
  /// size (m) stands in for those whose centre is in it, made of their own
  /// hulls where they lie. Their clusters stay, and views report them where
  /// they lie. Shots and falling pieces hit the compound; a hit on it
  /// damages the piece hit. When a body moving faster than
  /// settle_wake_speed comes near one of its pieces (a shot, a falling
  /// piece, a support moving away), a projectile will reach it within two
  /// steps, a body it rests on is removed, or one of its pieces breaks or
  /// retires, the whole cell's pieces become bodies again, at rest where they
  /// were. >= 0; 0 turns it off (every piece stays a body); default 2
  double settle_cell;
  /// The speed (m/s, > 0) of a body near a cell's compound that wakes its
  /// pieces; slower ones rest on it as on the ground. Default 2 (a piece
  /// dropped 20 cm; at 1, pieces still settling nearby woke cells again
  /// and again)
  double settle_wake_speed;
} bk_world_def;

bk_world_def bk_default_world_def(void);
/// NULL with err naming the bad field.
bk_world* bk_world_create(const bk_world_def* def, bk_error* err);
void bk_world_destroy(bk_world* world);
/// The underlying physics world (for rendering and queries).
bk_physics* bk_world_physics(bk_world* world);
/// The runtime the world drives (for queries: clusters, bond health, materials).
const bk_runtime* bk_world_runtime(const bk_world* world);

/// A breakable on Bullet: the runtime's breakable plus how its clusters
/// collide. bk_default_world_breakable_def() fills every field.
typedef struct bk_world_breakable_def {
  bk_breakable_def breakable; ///< tree, placement, material, anchoring (see runtime.h)
  bool convex_colliders;      ///< one hull per chosen node even when it is concave; default false
  /// A node's hull stands for it if hull volume <= (1 + tol) x volume (> 0); default 0.1
  double convexity_tolerance;
  bool naive; ///< plain BCRB: one collider per fragment (for comparison); default false
} bk_world_breakable_def;

bk_world_breakable_def bk_default_world_breakable_def(void);
/// Adds a breakable as one body (static if anchored). Null id with err naming
/// the bad field, its code the runtime's (BK_ERROR_BAD_TREE for a tree that
/// fails validation) or BK_ERROR_PHYSICS when Bullet refused a body.
bk_breakable_id bk_world_add_breakable(bk_world* world, const bk_world_breakable_def* def, bk_error* err);
/// Removes a breakable: its bodies leave Bullet's world and its id goes
/// stale (bk_world_breakable_at gives a null id at its index until a new
/// breakable takes the slot). BK_ERROR_STALE_ID for a stale id.
bk_result bk_world_remove_breakable(bk_world* world, bk_breakable_id id);
/// Live parameters, owned by the world's runtime: frailty applies to the next
/// hits; density recomputes every body's mass and inertia; bond strength
/// scales the hit points of intact bonds; a material sets all of them plus
/// friction and restitution. Setters return the runtime's result: BK_OK, or
/// (changing nothing) BK_ERROR_STALE_ID or BK_ERROR_INVALID_ARGUMENT.
bk_result bk_world_set_material(bk_world* world, bk_breakable_id id, const bk_material* material);
bk_result bk_world_set_frailty(bk_world* world, bk_breakable_id id, double frailty);
bk_result bk_world_set_density(bk_world* world, bk_breakable_id id, double density);
bk_result bk_world_set_bond_strength(bk_world* world, bk_breakable_id id, double bond_strength);
/// Getters (read the live values back instead of keeping copies).
bk_material bk_world_material(const bk_world* world, bk_breakable_id id);
double bk_world_frailty(const bk_world* world, bk_breakable_id id);
double bk_world_density(const bk_world* world, bk_breakable_id id);
double bk_world_bond_strength(const bk_world* world, bk_breakable_id id);
/// Structural stress on or off (bk_world_def.stress) from the next step.
/// Off, whatever is bonded to an anchor stays up however little holds it;
/// back on, the steps that follow solve what changed meanwhile (new pieces,
/// new limits) and break what can no longer hold.
void bk_world_set_stress(bk_world* world, bool stress);
/// Whether the world solves structural stress each step.
bool bk_world_stress(const bk_world* world);
/// bk_world_def.max_hit_fragments_per_step: the fragments the hits of one
/// step may sweep (0: no limit).
uint32_t bk_world_max_hit_fragments_per_step(const bk_world* world);

/// How far the physics budget has made a body cheaper, from the least to
/// the most (each tier keeps what the ones before it did).
typedef enum bk_budget_tier {
  BK_TIER_FULL = 0,       ///< fully simulated
  BK_TIER_DEBRIS = 1,     ///< no contacts with other debris (only large bodies and the world)
  BK_TIER_SIMPLIFIED = 2, ///< also a sphere or box fitted to it for a shape (same mass and inertia)
  /// also frozen where it lies (only a piece at rest: asleep, or calm a
  /// moment); set free when a moving body touches it or one presses on it
  /// with more than four times its weight
  BK_TIER_FROZEN = 3,
  /// removed: a simplified piece still moving, of one mesh-tree node, handed
  /// to bk_world_retired_bodies (its mass goes to retired_mass)
  BK_TIER_RETIRED = 4,
} bk_budget_tier;

/// Sets the physics budget (bk_world_def.physics_budget_ms) from the next
/// step; 0 turns it off and gives every piece its full fidelity back at once
/// (debris that came to rest inside other debris is pushed out of it).
/// False (nothing changed) for a negative or non-finite value.
bool bk_world_set_physics_budget(bk_world* world, double ms);
/// The physics budget the steps are held to, in ms (0: none).
double bk_world_physics_budget(const bk_world* world);
/// bk_world_def.budget_fidelity_radius: how far from the focus a new piece
/// keeps its first budget_fidelity_time.
double bk_world_budget_fidelity_radius(const bk_world* world);
/// bk_world_def.budget_visible_angle: how large (size over distance, in
/// radians) a piece near the focus must look to keep its first second.
double bk_world_budget_visible_angle(const bk_world* world);
/// bk_world_def.settle_cell: the cell size (m) settled pieces merge by; 0: off.
double bk_world_settle_cell(const bk_world* world);
/// Where the player looks from (the camera, say): the budget keeps pieces
/// near it fully simulated, and makes far ones cheaper first. Ignored when
/// not finite. Until it is set, distance plays no part.
void bk_world_set_focus(bk_world* world, bk_vec3 point);
/// The focus, if one was set.
bool bk_world_focus(const bk_world* world, bk_vec3* point);
/// Breakable slots (the runtime's indices: a removed breakable's is used
/// again), and the id of the one at index (null past the end, or removed).
uint32_t bk_world_breakable_count(const bk_world* world);
bk_breakable_id bk_world_breakable_at(const bk_world* world, uint32_t index);

/// A projectile: a sphere with continuous collision detection.
/// bk_default_projectile_def() fills every field.
typedef struct bk_projectile_def {
  bk_vec3 position, velocity;
  double radius; ///< > 0; default 0.08 m
  double mass;   ///< > 0; default 4 kg
  /// Seconds before it is removed, >= 0: 0 (the default) takes the world's
  /// projectile_lifetime; INFINITY keeps it (a weight set on a structure)
  double lifetime;
} bk_projectile_def;

bk_projectile_def bk_default_projectile_def(void);
/// Null id with err naming the bad field.
bk_body_id bk_world_fire(bk_world* world, const bk_projectile_def* def, bk_error* err);

/// Damages every breakable body as if a contact with this impulse (N s) had
/// happened at a world point (explosions, scripted destruction), without the
/// contact thresholds; the split happens in the next bk_world_step.
void bk_world_impact(bk_world* world, bk_vec3 point, double impulse);

/// Advances one fixed step (dt = the world's fixed_dt): physics, damage from
/// this step's contacts, refinement (bk_runtime_refine; see
/// bk_material.refine_strength and bk_breakable_def.refine: a refined
/// fragment's new nodes get their hulls when a body first needs them),
/// then splits within the step's budget.
void bk_world_step(bk_world* world);

/// A bond broken in the last step or by bk_world_impact since (pulled after
/// bk_world_step, e.g. for dust).
typedef struct bk_break_event {
  bk_breakable_id breakable;
  uint32_t bond;
  bk_vec3 position; ///< world position of the bond centroid
  bk_vec3 velocity; ///< velocity of the body it belonged to, at that point
  double area;
  bk_break_cause cause; ///< a hit, or the load it carried (stress)
  void* user_data;      ///< the breakable's (bk_breakable_def.user_data)
} bk_break_event;

/// Copies the last step's break events; returns the total count.
uint32_t bk_world_break_events(const bk_world* world, bk_break_event* out, uint32_t capacity);

/// A body the physics budget removed in the last step, for a renderer to
/// fade out: one mesh-tree node where the body was, and how it moved.
typedef struct bk_retired_body {
  bk_breakable_id breakable;  ///< the breakable it was part of
  uint32_t node;              ///< its one mesh-tree node (only one-node bodies retire)
  bk_transform tree_to_world; ///< the tree frame's placement when it left
  bk_vec3 linear_velocity;    ///< of its centre of mass
  bk_vec3 angular_velocity;   ///< rad/s, in the world
  bk_vec3 center;             ///< its centre of mass in the world
  double mass;                ///< kg (added to bk_world_stats.retired_mass)
} bk_retired_body;

/// Copies the bodies the budget retired in the last step; returns their count.
uint32_t bk_world_retired_bodies(const bk_world* world, bk_retired_body* out, uint32_t capacity);

/// Where each fragment of a breakable is now: its centroid in the world
/// (NaN for a fragment whose cluster was removed, e.g. retired). Writes at
/// most capacity; returns the breakable's fragment count now (0 for a stale
/// id), which grows as its fragments are refined (leaves after a refined
/// one move up: see bk_splice_info).
uint32_t bk_world_fragment_centroids(const bk_world* world, bk_breakable_id id, bk_vec3* out,
                                     uint32_t capacity);

/// Counters and timings.
typedef struct bk_world_stats {
  uint32_t bodies; ///< rigid bodies of breakables
  uint32_t dynamic_bodies;
  uint32_t colliders;       ///< convex children over all breakable bodies
  uint32_t colliders_naive; ///< what one-collider-per-fragment would use for the same clusters
  uint32_t fragments_free;  ///< fragments in clusters of one fragment
  uint32_t projectiles;
  uint32_t bonds_broken;      ///< since creation
  uint32_t break_events;      ///< bodies split since creation
  uint32_t pending_splits;    ///< clusters waiting for the budget
  uint32_t pending_hits;      ///< hits waiting for max_hit_fragments_per_step
  uint32_t fragments_retired; ///< small fragments removed (retire_volume)
  double total_mass;          ///< kg over all breakable bodies
  double retired_mass;        ///< kg removed with retired fragments (total_mass + retired_mass is conserved)
  double step_ms;             ///< last step, all of it
  double physics_ms;          ///< last step, the physics engine alone
  double break_ms;            ///< last step: damage, stress, components, minimal sets, body rebuild
  double stress_ms;           ///< last step, the stress solve alone (part of break_ms)
  uint32_t stress_bonds_broken;     ///< by stress, since creation (part of bonds_broken)
  uint32_t stress_iterations;       ///< last step's stress iterations
  uint32_t stress_clusters_pending; ///< clusters whose load is not solved yet (0: at rest, costs nothing)
  bool nan;                         ///< a body has a non-finite transform or velocity
  /// The physics budget. Bodies now at each tier (bk_budget_tier): without
  /// contacts with debris, also simplified, also frozen.
  uint32_t budget_debris, budget_simplified, budget_frozen;
  uint32_t budget_retired;      ///< bodies retired since creation (their fragments are in fragments_retired)
  uint32_t budget_demotions;    ///< tier steps down (cheaper) since creation, retirements included
  uint32_t budget_restorations; ///< tier steps back up since creation
  double budget_level;          ///< 0 (nothing made cheaper) to 4 (retiring): how far the budget reaches
  double budget_cost_ms;        ///< last step's physics cost as the budget saw it (estimated or measured)
  /// Last step's break handling and body creation, in CPU time of the
  /// calling thread (ms): damage from contacts, splits, and the bodies they
  /// removed and made (the stress solve is apart: stress_ms)
  double fracture_ms;
  double physics_cpu_ms;   ///< last step's physics engine alone, in CPU time of the calling thread (ms)
  uint32_t settled_bodies; ///< bodies merged into their cell's static compound now (bk_world_def.settle_cell)
  uint32_t settled_areas;  ///< cells' static compounds now
  uint32_t settle_wakes;   ///< cells woken (their pieces bodies again) since creation
  /// CPU time (ms) of the last step that merged pieces: their bodies parked
  /// and their cells' compounds rebuilt
  double settle_batch_ms;
  /// Last step's refinement (bk_world_step calls bk_runtime_refine after
  /// its hits), in CPU time of the calling thread (ms): starting and
  /// landing the pieces (the fracture runs on runtime.refine_threads
  /// workers; a fragment beyond them is fractured on this thread when it
  /// lands). Their hulls are made when a body first needs them, in
  /// fracture_ms
  double refine_ms;
  uint32_t refined_leaves; ///< fragments refined since creation (bk_material.refine_strength)
} bk_world_stats;

bk_world_stats bk_world_get_stats(const bk_world* world);

/// The precision bk_world_state_hash rounds bodies' positions (m), rotation
/// components, and velocities (m/s, rad/s) to.
#define BK_WORLD_HASH_PRECISION 1e-6
/// 64 bits over the runtime's state hash (bk_runtime_state_hash), the step
/// count, every breakable body (cluster id, budget tier, transform and
/// velocities rounded to BK_WORLD_HASH_PRECISION) and the projectiles in
/// flight: two worlds given the same calls hash alike.
uint64_t bk_world_state_hash(const bk_world* world);

/// Bytes bk_world_save_state would write for the world as it is now.
size_t bk_world_state_size(const bk_world* world);
/// Writes the world's state into out[0..capacity): the runtime's
/// (bk_runtime_save_state), the step count, every breakable body (cluster,
/// tier, transform, velocities) and the projectiles in flight. Returns the
/// bytes written, or 0 with err set.
size_t bk_world_save_state(const bk_world* world, void* out, size_t capacity, bk_error* err);
/// Replaces the world's state with a saved one (the same breakables and trees,
/// as bk_runtime_load_state checks; refused in one line and nothing changes
/// otherwise). Every body and projectile is made again where it was saved:
/// bk_world_state_hash then equals the saved world's. Bullet's contact caches
/// and solver warm start are not saved, so steps after a load drift from the
/// saved run's by rounding (the destruction state stays the same until a
/// contact differs).
bool bk_world_load_state(bk_world* world, const void* data, size_t size, bk_error* err);

// ---------------------------------------------------------------- following

/// A server-authoritative game sends its world's destruction to watching
/// clients as two byte strings a step: its runtime's journal (every hit,
/// break, split, removal and refinement; see bk_runtime_journal) and the
/// motion of its moving bodies. A client world holding the same breakables
/// (the same scene, or a saved state loaded: bk_world_load_state) applies
/// both and is not stepped itself: it has the same clusters, bonds and
/// runtime state hash as the server after every step, and its bodies are
/// where the server's are, to the motion's precision (positions as floats:
/// 0.01 mm at 100 m; rotations to 3e-5 rad).
/// The journal switch of the world's runtime (off by default; switch it on
/// once the scene is set up: adding a breakable cannot be followed).
bk_result bk_world_set_journal(bk_world* world, bool journal);
/// The runtime's journal since the last clear (see bk_runtime_journal).
const void* bk_world_journal(const bk_world* world, size_t* size);
void bk_world_clear_journal(bk_world* world);
/// Applies a leader's journal to the world's runtime (bk_runtime_apply_journal)
/// and makes, removes and grows bodies as its calls did; the break events
/// (bk_world_break_events) are then the journal's. False with err naming
/// the entry when it does not apply (the worlds diverged: load a state).
bool bk_world_apply_journal(bk_world* world, const void* data, size_t size, bk_error* err);
/// Room bk_world_motion needs now (an upper bound).
size_t bk_world_motion_size(const bk_world* world);
/// Writes the place of every body that is new or has moved (by more than a
/// micrometre or 1e-6 rad) since the last call placed it, about 22 bytes a
/// body, and remembers those places: call it once a step and send what it
/// writes to every client (one that joins later gets the world's state, in
/// which every body is where it is). Returns the bytes written, or 0 when
/// capacity is below bk_world_motion_size.
size_t bk_world_motion(bk_world* world, void* out, size_t capacity);
/// Places the bodies a leader's motion names (each drawn moving from where
/// it was: bk_body_view interpolates). Malformed bytes move nothing; a body
/// of a cluster this world does not have is skipped and reported (false).
bool bk_world_apply_motion(bk_world* world, const void* data, size_t size, bk_error* err);

/// A breakable body for drawing: which mesh-tree nodes it shows, where.
typedef struct bk_body_view {
  bk_breakable_id breakable;
  bk_cluster_id cluster;
  const bk_mesh_tree* tree;
  bk_transform tree_to_world;          ///< the tree frame's placement now
  bk_transform tree_to_world_previous; ///< and at the start of the last step (interpolate between them)
  const uint32_t* nodes;               ///< minimal node set
  uint32_t node_count;
  const uint32_t* leaves; ///< its fragments, ascending
  uint32_t leaf_count;
  bk_body_id body;
  bool is_static;
  bk_budget_tier tier; ///< what the physics budget made of it
  void* user_data;     ///< the breakable's (bk_breakable_def.user_data)
} bk_body_view;

/// Number of breakable bodies; views are indexed 0..count-1 until the next step.
uint32_t bk_world_body_count(const bk_world* world);
bool bk_world_body_view(const bk_world* world, uint32_t index, bk_body_view* out);
/// Colliders (convex children) the body at index uses and their nodes.
uint32_t bk_world_body_colliders(const bk_world* world, uint32_t index, uint32_t* nodes_out,
                                 uint32_t capacity);

/// Number of live projectiles and where one is (false if index is out of range).
uint32_t bk_world_projectile_count(const bk_world* world);
bool bk_world_projectile(const bk_world* world, uint32_t index, bk_vec3* position, double* radius);

/// Hit points left of a bond (0 when broken) and its initial hit points.
double bk_world_bond_health(const bk_world* world, bk_breakable_id id, uint32_t bond, double* initial);

#ifdef __cplusplus
}
#endif
