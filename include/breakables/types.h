// Breakables: the types every library shares: double-precision vectors,
// quaternions, rigid transforms, bounding boxes and the one-line error.
// Header-only math so it inlines in hot loops (slicing, mass properties).
#pragma once

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

/// A value of a struct type in an expression: a compound literal in C, an
/// aggregate in C++ (which has no compound literals), so every header of the
/// project can be included from C++ too.
#ifdef __cplusplus
#define BK_LITERAL(type) type
#else
#define BK_LITERAL(type) (type)
#endif

/// A point or direction in double precision: geometry is processed in doubles
/// so volumes stay exact to ~1e-12 through many recursive cuts.
typedef struct bk_vec3 {
  double x, y, z;
} bk_vec3;

/// Axis-aligned bounding box.
typedef struct bk_aabb {
  bk_vec3 min, max;
} bk_aabb;

/// Plane of points p with dot(normal, p) == offset; normal has unit length.
typedef struct bk_plane {
  bk_vec3 normal;
  double offset;
} bk_plane;

static inline bk_vec3 bk_v3(double x, double y, double z) { return BK_LITERAL(bk_vec3){x, y, z}; }
static inline bk_vec3 bk_v3_add(bk_vec3 a, bk_vec3 b) {
  return BK_LITERAL(bk_vec3){a.x + b.x, a.y + b.y, a.z + b.z};
}
static inline bk_vec3 bk_v3_sub(bk_vec3 a, bk_vec3 b) {
  return BK_LITERAL(bk_vec3){a.x - b.x, a.y - b.y, a.z - b.z};
}
static inline bk_vec3 bk_v3_scale(bk_vec3 a, double s) {
  return BK_LITERAL(bk_vec3){a.x * s, a.y * s, a.z * s};
}
static inline double bk_v3_dot(bk_vec3 a, bk_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline bk_vec3 bk_v3_cross(bk_vec3 a, bk_vec3 b) {
  return BK_LITERAL(bk_vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline double bk_v3_length(bk_vec3 a) { return sqrt(bk_v3_dot(a, a)); }
static inline bk_vec3 bk_v3_lerp(bk_vec3 a, bk_vec3 b, double t) {
  return BK_LITERAL(bk_vec3){a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t};
}
static inline bk_vec3 bk_v3_normalize(bk_vec3 a) {
  double len = bk_v3_length(a);
  return len > 0.0 ? bk_v3_scale(a, 1.0 / len) : a;
}
static inline bk_vec3 bk_v3_min(bk_vec3 a, bk_vec3 b) {
  return BK_LITERAL(bk_vec3){fmin(a.x, b.x), fmin(a.y, b.y), fmin(a.z, b.z)};
}
static inline bk_vec3 bk_v3_max(bk_vec3 a, bk_vec3 b) {
  return BK_LITERAL(bk_vec3){fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z)};
}
static inline bool bk_v3_is_finite(bk_vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static inline double bk_plane_distance(bk_plane p, bk_vec3 x) { return bk_v3_dot(p.normal, x) - p.offset; }

/// Two unit vectors u, v completing n to a right-handed orthonormal basis (u x v = n).
static inline void bk_plane_basis(bk_vec3 n, bk_vec3* u, bk_vec3* v) {
  // Pick the axis least aligned with n so the cross product is well conditioned.
  bk_vec3 a = fabs(n.x) < 0.57735 ? bk_v3(1, 0, 0) : (fabs(n.y) < 0.57735 ? bk_v3(0, 1, 0) : bk_v3(0, 0, 1));
  *u = bk_v3_normalize(bk_v3_cross(a, n));
  *v = bk_v3_cross(n, *u);
}

/// Unit quaternion (x, y, z, w) for rotations.
typedef struct bk_quat {
  double x, y, z, w;
} bk_quat;

/// A rigid transform: rotate, then translate.
typedef struct bk_transform {
  bk_vec3 position;
  bk_quat rotation;
} bk_transform;

static inline bk_quat bk_quat_identity(void) { return BK_LITERAL(bk_quat){0, 0, 0, 1}; }
static inline bk_transform bk_transform_identity(void) {
  return BK_LITERAL(bk_transform){{0, 0, 0}, {0, 0, 0, 1}};
}
static inline bk_quat bk_quat_mul(bk_quat a, bk_quat b) {
  return BK_LITERAL(bk_quat){
      a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
      a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}
static inline bk_quat bk_quat_conjugate(bk_quat q) { return BK_LITERAL(bk_quat){-q.x, -q.y, -q.z, q.w}; }
static inline bk_vec3 bk_quat_rotate(bk_quat q, bk_vec3 v) {
  // v + 2w (q x v) + 2 q x (q x v)
  bk_vec3 u = bk_v3(q.x, q.y, q.z);
  bk_vec3 t = bk_v3_scale(bk_v3_cross(u, v), 2.0);
  return bk_v3_add(bk_v3_add(v, bk_v3_scale(t, q.w)), bk_v3_cross(u, t));
}
static inline bk_quat bk_quat_normalize(bk_quat q) {
  double n = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  return n > 0.0 ? BK_LITERAL(bk_quat){q.x / n, q.y / n, q.z / n, q.w / n} : bk_quat_identity();
}
/// Rotation of `angle` radians about unit `axis`.
static inline bk_quat bk_quat_axis_angle(bk_vec3 axis, double angle) {
  double s = sin(0.5 * angle);
  return BK_LITERAL(bk_quat){axis.x * s, axis.y * s, axis.z * s, cos(0.5 * angle)};
}
static inline bk_vec3 bk_transform_point(bk_transform t, bk_vec3 p) {
  return bk_v3_add(bk_quat_rotate(t.rotation, p), t.position);
}
static inline bk_transform bk_transform_mul(bk_transform a, bk_transform b) {
  return BK_LITERAL(bk_transform){bk_transform_point(a, b.position), bk_quat_mul(a.rotation, b.rotation)};
}
static inline bk_transform bk_transform_inverse(bk_transform t) {
  bk_quat r = bk_quat_conjugate(t.rotation);
  return BK_LITERAL(bk_transform){bk_v3_scale(bk_quat_rotate(r, t.position), -1.0), r};
}

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- errors

/// What went wrong, for a program to act on (the message is for people).
/// Setters return it; a call that fills a bk_error sets its code. 0 is
/// success, so `if (bk_runtime_set_density(...) != BK_OK)` tests a result.
typedef enum bk_result {
  BK_OK = 0,
  /// A failure the library does not classify further: read the message
  BK_ERROR_FAILED,
  /// A NULL pointer, or a field or value out of its range (the message names it)
  BK_ERROR_INVALID_ARGUMENT,
  /// An id whose object was removed, or that this runtime or world never made
  BK_ERROR_STALE_ID,
  /// A mesh tree that fails bk_mesh_tree_validate (indices, masses, bonds)
  BK_ERROR_BAD_TREE,
  /// A file could not be opened, read or written
  BK_ERROR_IO,
  /// The physics engine refused something (a body, a shape)
  BK_ERROR_PHYSICS,
  /// The allocator (bk_set_allocator's, or malloc) gave no memory
  BK_ERROR_OUT_OF_MEMORY,
} bk_result;

/// A failed call fills one line naming the problem (file, line, field) and
/// its code. A zeroed bk_error has code BK_OK and an empty message.
typedef struct bk_error {
  char message[512];
  bk_result code;
} bk_error;

/// printf-style fill of an error with code BK_ERROR_FAILED; err may be NULL.
/// Always returns false so a failing function can `return bk_error_set(err, ...)`.
bool bk_error_set(bk_error* err, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
/// The same with a code.
bool bk_error_set_code(bk_error* err, bk_result code, const char* fmt, ...)
    __attribute__((format(printf, 3, 4)));
/// A short name of a code ("invalid argument", "stale id", ...).
const char* bk_result_name(bk_result code);

// ---------------------------------------------------------------- version

/// A version of the libraries: the project's VERSION, major.minor.revision.
typedef struct bk_version {
  int major;
  int minor;
  int revision;
} bk_version;

/// The version of the libraries linked or loaded (all three are built
/// together). A program that loads the shared libraries at run time checks
/// it against the one it was written for; the soname changes with the minor
/// version while the major is 0, then with the major.
bk_version bk_get_version(void);

#ifdef __cplusplus
}
#endif
