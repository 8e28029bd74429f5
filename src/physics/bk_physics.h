// physics: a C interface over Bullet. Opaque world, typed ids with a
// generation (zero = null), C types only. After each step, contacts are
// pulled as an array; no callbacks cross from the physics engine into C.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "bk_geom.h"

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

/// World parameters. Zero fields mean the default.
typedef struct bk_physics_desc {
  bk_vec3 gravity;           ///< default (0, -9.81, 0) when all zero and use_zero_gravity is false
  bool use_zero_gravity;     ///< true to really have no gravity
  double fixed_dt;           ///< internal substep; default 1/60 s
  uint32_t contact_capacity; ///< contacts kept per step (more are counted, not stored); default 65536
  double default_margin;     ///< collision margin of hulls; default 0.004 m
} bk_physics_desc;

/// Defaults: gravity -9.81 y, 60 Hz substeps.
bk_physics_desc bk_default_physics_desc(void);
/// Creates a world (split impulse on, so penetration recovery adds no
/// contact impulse). Returns NULL with err set on a bad description.
bk_physics* bk_physics_create(const bk_physics_desc* desc, bk_error* err);
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
/// principal moments. Zero fields mean the default.
typedef struct bk_body_desc {
  bk_shape_id shape;
  double mass;            ///< 0 = static body
  bk_vec3 inertia;        ///< principal moments of inertia (dynamic bodies)
  bk_transform transform; ///< zero rotation means identity
  bk_vec3 linear_velocity, angular_velocity;
  double friction;    ///< default 0.6
  double restitution; ///< default 0.1
  /// Resistance to rolling and spinning on a contact (torque per normal
  /// force, in metres); 0 = none. Debris needs it to come to rest: a rounded
  /// shard otherwise rolls on for seconds and keeps its whole pile awake.
  double rolling_friction;
  double linear_damping, angular_damping;
  bool ccd;          ///< continuous collision detection, for fast small bodies
  double ccd_radius; ///< swept sphere radius for CCD (default: from the shape's bounds)
  bool disable_sleep;
  uint64_t user_data;
} bk_body_desc;

bk_body_desc bk_default_body_desc(void);
/// Creates a body; returns null with err naming the bad field (non-finite
/// values, negative mass, zero inertia on a dynamic body, invalid shape).
bk_body_id bk_physics_create_body(bk_physics* world, const bk_body_desc* desc, bk_error* err);
void bk_physics_destroy_body(bk_physics* world, bk_body_id body);
bool bk_physics_body_valid(const bk_physics* world, bk_body_id body);
uint32_t bk_physics_body_count(const bk_physics* world);
bk_transform bk_physics_body_transform(const bk_physics* world, bk_body_id body);
void bk_physics_body_set_transform(bk_physics* world, bk_body_id body, bk_transform transform);
bk_vec3 bk_physics_body_linear_velocity(const bk_physics* world, bk_body_id body);
bk_vec3 bk_physics_body_angular_velocity(const bk_physics* world, bk_body_id body);
void bk_physics_body_set_velocity(bk_physics* world, bk_body_id body, bk_vec3 linear, bk_vec3 angular);
/// Changes mass and principal inertia (density edits); mass 0 is not allowed here.
void bk_physics_body_set_mass(bk_physics* world, bk_body_id body, double mass, bk_vec3 inertia);
double bk_physics_body_mass(const bk_physics* world, bk_body_id body);
/// Principal moments of inertia of a dynamic body (zero for static ones).
bk_vec3 bk_physics_body_inertia(const bk_physics* world, bk_body_id body);
void bk_physics_body_apply_impulse(bk_physics* world, bk_body_id body, bk_vec3 impulse, bk_vec3 world_point);
bool bk_physics_body_awake(const bk_physics* world, bk_body_id body);
uint64_t bk_physics_body_user_data(const bk_physics* world, bk_body_id body);

// ---------------------------------------------------------------- queries

/// One contact point from one substep of the last bk_physics_step.
typedef struct bk_contact {
  bk_body_id a, b;
  bk_vec3 point;  ///< world position (midpoint of the two witness points)
  bk_vec3 normal; ///< world normal pointing from b towards a
  double impulse; ///< normal impulse the solver applied (N s)
  double
      approach_speed; ///< closing speed along the normal before that substep's solve (m/s; > 0 = approaching)
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

#ifdef __cplusplus
}
#endif
