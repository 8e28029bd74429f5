// sim: breakable objects as Breakable Composite Rigid Bodies. Fragments are
// the nodes of a graph whose edges are the mesh tree's bonds; each connected
// cluster is one rigid body whose compound shape comes from the smallest set
// of mesh-tree nodes that covers exactly its fragments. Collisions damage the
// bonds near the contact; a cluster that falls apart becomes one body per
// piece. Projectiles, scenes and per-step statistics live here too.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "bk_fracture.h"
#include "bk_physics.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- minimal node sets

/// Writes the smallest set of mesh-tree nodes whose subtrees hold exactly the
/// given leaves (sorted ascending, no duplicates) into out, in depth-first
/// order; returns the count (at most leaf_count). An unbroken object gives the
/// root alone.
uint32_t bk_minimal_nodes(const bk_mesh_tree* tree, const uint32_t* leaves, uint32_t leaf_count,
                          uint32_t* out);

// ---------------------------------------------------------------- materials

/// A material preset: the thesis's parameters plus surface properties.
typedef struct bk_material {
  const char* name;
  double density;       ///< kg/m^3
  double frailty;       ///< damage = frailty x impulse / distance^3
  double bond_strength; ///< hit points per m^2 of bond area
  bool accumulate;      ///< bonds lose hit points over hits (else discrete: one hit must exceed them)
  double friction, restitution;
} bk_material;

/// Presets: stone, glass, porcelain, concrete, eggshell, wood.
const bk_material* bk_material_find(const char* name);
uint32_t bk_material_count(void);
const bk_material* bk_material_at(uint32_t index);

// ---------------------------------------------------------------- world

typedef struct bk_world bk_world;

/// Zero fields mean the default.
typedef struct bk_world_desc {
  bk_vec3 gravity;                  ///< default (0, -9.81, 0)
  double fixed_dt;                  ///< one bk_world_step; default 1/60 s
  bool no_ground;                   ///< default: a static ground plane at y = 0
  double impact_speed;              ///< contacts closing slower than this (m/s) do no damage; default 1.0
  double impulse_threshold;         ///< contacts with less impulse (N s) do no damage; default 0.5
  double damage_min_distance;       ///< s_min of the damage formula (m); default 0.05
  uint32_t max_new_bodies_per_step; ///< split budget (at least 2); default 48
  double projectile_lifetime;       ///< seconds before a projectile is removed; default 8
  /// Loose single fragments smaller than this volume (m^3) are removed after
  /// retire_after seconds, to keep long sessions bounded; 0 = never (default).
  double retire_volume;
  double retire_after; ///< seconds a small fragment lives once free; default 10
} bk_world_desc;

bk_world_desc bk_default_world_desc(void);
bk_world* bk_world_create(const bk_world_desc* desc, bk_error* err);
void bk_world_destroy(bk_world* world);
/// The underlying physics world (for rendering and queries).
bk_physics* bk_world_physics(bk_world* world);

/// A breakable object, id with a generation ({0,0} = null).
typedef struct bk_breakable_id {
  uint32_t index, generation;
} bk_breakable_id;

/// How a breakable behaves. Zero fields mean the default.
typedef struct bk_breakable_desc {
  const bk_mesh_tree* tree; ///< borrowed: must outlive the world
  bk_transform transform;   ///< places the tree's frame in the world (zero rotation = identity)
  double density;           ///< kg/m^3 (default 2400)
  double frailty;           ///< default 1
  double bond_strength;     ///< hit points per m^2 of bond area (default 2e5)
  bool accumulate;          ///< accumulating bonds (default: discrete)
  bool convex_colliders;    ///< one hull per chosen node even when it is concave
  double
      convexity_tolerance; ///< a node's hull stands for it if hull volume <= (1 + tol) x volume; default 0.1
  bool anchored;           ///< fragments touching the ground are bonded to the world
  double anchor_height;    ///< world height of the support plane (default 0)
  bool naive;              ///< plain BCRB: one collider per fragment (for comparison)
  double friction, restitution; ///< defaults 0.6, 0.1
} bk_breakable_desc;

bk_breakable_desc bk_default_breakable_desc(void);
/// Adds a breakable as one body (or static if anchored). err names a bad field.
bk_breakable_id bk_world_add_breakable(bk_world* world, const bk_breakable_desc* desc, bk_error* err);
/// Live parameter changes: frailty applies to the next hits; density
/// recomputes every body's mass and inertia.
void bk_world_set_frailty(bk_world* world, bk_breakable_id id, double frailty);
void bk_world_set_density(bk_world* world, bk_breakable_id id, double density);

/// A projectile: a sphere with continuous collision detection.
typedef struct bk_projectile_desc {
  bk_vec3 position, velocity;
  double radius; ///< default 0.08 m
  double mass;   ///< default 4 kg
} bk_projectile_desc;

bk_body_id bk_world_fire(bk_world* world, const bk_projectile_desc* desc);

/// Damages every breakable body as if a contact with this impulse (N s) had
/// happened at a world point (explosions, scripted destruction), without the
/// contact thresholds; the split happens in the next bk_world_step.
void bk_world_impact(bk_world* world, bk_vec3 point, double impulse);

/// Advances one fixed step (dt = the world's fixed_dt): physics, damage from
/// this step's contacts, then splits within the step's budget.
void bk_world_step(bk_world* world);

/// A bond broken in the last step (pulled after bk_world_step, e.g. for dust).
typedef struct bk_break_event {
  bk_breakable_id breakable;
  uint32_t bond;
  bk_vec3 position; ///< world position of the bond centroid
  bk_vec3 velocity; ///< velocity of the body it belonged to, at that point
  double area;
} bk_break_event;

/// Copies the last step's break events; returns the total count.
uint32_t bk_world_break_events(const bk_world* world, bk_break_event* out, uint32_t capacity);

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
  uint32_t fragments_retired; ///< small fragments removed (retire_volume)
  double total_mass;          ///< kg over all breakable bodies
  double retired_mass;        ///< kg removed with retired fragments (total_mass + retired_mass is conserved)
  double step_ms;             ///< last step, all of it
  double physics_ms;          ///< last step, the physics engine alone
  double break_ms;            ///< last step: damage, components, minimal sets, body rebuild
  bool nan;                   ///< a body has a non-finite transform or velocity
} bk_world_stats;

bk_world_stats bk_world_get_stats(const bk_world* world);

/// A breakable body for drawing: which mesh-tree nodes it shows, where.
typedef struct bk_body_view {
  bk_breakable_id breakable;
  const bk_mesh_tree* tree;
  bk_transform tree_to_world;          ///< the tree frame's placement now
  bk_transform tree_to_world_previous; ///< and at the start of the last step (interpolate between them)
  const uint32_t* nodes;               ///< minimal node set
  uint32_t node_count;
  const uint32_t* leaves; ///< its fragments, ascending
  uint32_t leaf_count;
  bk_body_id body;
  bool is_static;
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

// ---------------------------------------------------------------- scenes

/// One object of a scene.
typedef struct bk_scene_object {
  const char* mesh;     ///< a mesh name for bk_app-style loading (cube, wall, bunny, ...)
  bk_vec3 position;     ///< where the mesh's origin goes
  bk_vec3 axis;         ///< rotation axis (zero = none)
  double angle;         ///< radians
  double scale;         ///< uniform scale of the mesh (0 = 1)
  const char* material; ///< material preset name (physics)
  const char* look;     ///< how it is drawn (render material); NULL = same as material
  bool anchored;
} bk_scene_object;

/// A scene: data, not code paths.
typedef struct bk_scene {
  const char* name;
  const char* description;
  uint32_t pieces;    ///< default fragment count
  double aspect_bias; ///< fracture: tilt cuts across the long axis (bk_fracture_desc.aspect_bias)
  bk_scene_object objects[8];
  uint32_t object_count;
  bk_vec3 eye, target; ///< camera and the point projectiles aim at
  /// More aim points (optional): a volley goes round target, then these, in turn.
  bk_vec3 extra_targets[7];
  uint32_t extra_target_count;
  double projectile_speed, projectile_radius, projectile_mass;
} bk_scene;

uint32_t bk_scene_count(void);
const bk_scene* bk_scene_at(uint32_t index);
const bk_scene* bk_scene_find(const char* name);

#ifdef __cplusplus
}
#endif
