// geom: indexed triangle meshes, procedural shapes, OBJ I/O, exact mass
// properties and the small utilities the other layers share. No GL, no physics.
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "bk_math.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- errors

/// A failed call fills one line naming the problem (file, line, field).
typedef struct bk_error {
  char message[512];
} bk_error;

/// printf-style fill of an error; err may be NULL. Always returns false so a
/// failing function can `return bk_error_set(err, ...)`.
bool bk_error_set(bk_error* err, const char* fmt, ...) __attribute__((format(printf, 2, 3)));

// ---------------------------------------------------------------- meshes

/// Material ids stored per triangle.
enum {
  BK_MATERIAL_OUTER = 0,    ///< the source mesh's own surface
  BK_MATERIAL_INTERIOR = 1, ///< faces created by cuts (caps)
};

/// One triangle corner's attributes. Corners index welded positions, so two
/// corners at a UV or normal seam share the position and topology stays closed.
typedef struct bk_corner {
  uint32_t position; ///< index into bk_mesh.positions: this carries topology
  float normal[3];
  float uv[2];
  float tangent[4]; ///< xyz along +u, w = handedness of the bitangent (+1/-1)
} bk_corner;

/// Indexed triangle mesh. Triangles index corners; corners index positions.
/// Everything is owned; capacities let builders grow arrays in place.
typedef struct bk_mesh {
  bk_vec3* positions;
  bk_corner* corners;
  uint32_t* indices;  ///< 3 corner indices per triangle, counter-clockwise seen from outside
  uint8_t* materials; ///< per triangle: BK_MATERIAL_*
  uint32_t* tags;     ///< per triangle, copied through slicing (fracture: which cut made a cap; 0 = none)
  uint32_t position_count, position_capacity;
  uint32_t corner_count, corner_capacity;
  uint32_t triangle_count, triangle_capacity;
} bk_mesh;

/// Releases every array and zeroes the mesh; safe on a zeroed mesh.
void bk_mesh_free(bk_mesh* mesh);
/// Ensures room for at least the given counts (existing data kept).
void bk_mesh_reserve(bk_mesh* mesh, uint32_t positions, uint32_t corners, uint32_t triangles);
/// Appends a position and returns its index.
uint32_t bk_mesh_add_position(bk_mesh* mesh, bk_vec3 p);
/// Appends a corner and returns its index.
uint32_t bk_mesh_add_corner(bk_mesh* mesh, const bk_corner* c);
/// Appends a triangle of three corner indices.
void bk_mesh_add_triangle(bk_mesh* mesh, uint32_t a, uint32_t b, uint32_t c, uint8_t material, uint32_t tag);
/// Deep copy (dst is overwritten, not freed first).
void bk_mesh_copy(bk_mesh* dst, const bk_mesh* src);
/// Appends src to dst as separate geometry (indices offset). Used to export many fragments as one.
void bk_mesh_append(bk_mesh* dst, const bk_mesh* src);
/// Position index of corner k (0..2) of triangle t.
static inline uint32_t bk_mesh_tri_position(const bk_mesh* m, uint32_t t, uint32_t k) {
  return m->corners[m->indices[3 * t + k]].position;
}
/// Bounds of the positions; an empty mesh gives min > max.
bk_aabb bk_mesh_bounds(const bk_mesh* mesh);
/// Total surface area.
double bk_mesh_area(const bk_mesh* mesh);
/// Checks internal consistency: indices in range, finite positions and
/// attributes. Fills err naming the first problem.
bool bk_mesh_validate(const bk_mesh* mesh, bk_error* err);
/// Merges positions with bit-identical coordinates (after -0 == +0). Returns
/// how many positions were merged away.
uint32_t bk_mesh_weld(bk_mesh* mesh);
/// Computes smooth corner normals (area-weighted per position) for every corner.
void bk_mesh_compute_normals(bk_mesh* mesh);
/// Computes corner tangents from uvs and normals (falls back to any
/// direction orthogonal to the normal where the uv mapping is degenerate).
void bk_mesh_compute_tangents(bk_mesh* mesh);
/// A lighter copy of a closed mesh for drawing it small: edges collapse while
/// each survivor stays within `tolerance` of every original triangle plane it
/// stands for, never pinching the surface or turning a triangle over, and the
/// border between materials stays put. Corners keep their
/// attributes. Positions where the mesh is open or non-manifold never move.
/// `out` is overwritten (not freed first); returns its triangle count.
uint32_t bk_mesh_decimate(const bk_mesh* mesh, double tolerance, bk_mesh* out);
/// Stable 64-bit hash of the mesh's geometry and attributes (identifies cache files).
uint64_t bk_mesh_hash(const bk_mesh* mesh);

// ---------------------------------------------------------------- closure

/// Result of checking that every directed edge has exactly one opposite.
typedef struct bk_closure {
  uint32_t open_edges;     ///< directed edges with no opposite edge
  uint32_t overused_edges; ///< directed edges used by more than one triangle (bad orientation / non-manifold)
  uint32_t degenerate_edges; ///< triangles using one position twice
} bk_closure;

/// Counts the edges that break closure; all zero means watertight and consistently oriented.
bk_closure bk_mesh_check_closure(const bk_mesh* mesh);
/// True when bk_mesh_check_closure finds nothing wrong.
bool bk_mesh_is_closed(const bk_mesh* mesh);

// ---------------------------------------------------------------- mass properties

/// Raw volume moments of a closed mesh: integrals over the solid of
/// 1, x, y, z, x^2, y^2, z^2, xy, yz, zx. They add up across pieces, so any
/// set of mesh-tree nodes combines in O(nodes).
typedef struct bk_moments {
  double v;
  double x, y, z;
  double xx, yy, zz, xy, yz, zx;
} bk_moments;

/// Mass properties per unit density.
typedef struct bk_mass_properties {
  double volume;
  bk_vec3 centroid;
  double inertia[3][3]; ///< inertia tensor about the centroid (per unit density)
} bk_mass_properties;

/// Exact moments by the divergence theorem (double precision).
bk_moments bk_mesh_moments(const bk_mesh* mesh);
/// Sum of two sets of moments.
bk_moments bk_moments_add(bk_moments a, bk_moments b);
/// Volume, centroid and central inertia tensor from moments.
bk_mass_properties bk_moments_to_mass(bk_moments m);
/// Convenience: volume of a closed mesh.
double bk_mesh_volume(const bk_mesh* mesh);
/// Eigenvalues and eigenvectors (columns of `vectors`, a right-handed
/// rotation) of a symmetric 3x3 matrix: principal moments and axes of inertia.
void bk_sym3_eigen(const double m[3][3], double values[3], double vectors[3][3]);
/// Quaternion of a rotation matrix.
bk_quat bk_quat_from_matrix(const double r[3][3]);

// ---------------------------------------------------------------- shapes

/// Procedural test meshes, named as on the command line. All are closed.
typedef enum bk_shape {
  BK_SHAPE_CUBE,     ///< unit cube centred at the origin: 8 positions, 24 corners, 12 triangles
  BK_SHAPE_TORUS,    ///< ring torus: 20x20 segments, 441 corners, 800 triangles
  BK_SHAPE_EGGSHELL, ///< hollow egg: outer surface + inward-facing inner surface
  BK_SHAPE_WALL,     ///< thin brick-proportioned wall standing on y = 0
  BK_SHAPE_SLAB,     ///< flat stone slab lying on y = 0
  BK_SHAPE_PILLAR,   ///< tall octagonal pillar standing on y = 0
  BK_SHAPE_COUNT
} bk_shape;

/// Name used on the command line ("cube", "torus", ...).
const char* bk_shape_name(bk_shape shape);
/// Looks a shape up by name; false if unknown.
bool bk_shape_from_name(const char* name, bk_shape* out);
/// Builds a shape (out is overwritten).
void bk_shape_build(bk_shape shape, bk_mesh* out);

// ---------------------------------------------------------------- OBJ files

/// Parses OBJ text (v, vt, vn, f with negative indices; polygons fanned; o/g/s/usemtl
/// ignored). Positions are welded. Missing normals are computed, missing uvs
/// get a box projection, tangents are derived. `name` prefixes error messages.
bool bk_obj_parse(const char* text, size_t length, const char* name, bk_mesh* out, bk_error* err);
/// Reads and parses an OBJ file.
bool bk_obj_load(const char* path, bk_mesh* out, bk_error* err);
/// Writes meshes as one OBJ file with one `o fragment_<i>` object per mesh.
bool bk_obj_save(const char* path, const bk_mesh* meshes, uint32_t mesh_count, bk_error* err);

// ---------------------------------------------------------------- utilities

/// PCG32 random generator: deterministic across platforms for a given seed.
typedef struct bk_rng {
  uint64_t state, inc;
} bk_rng;

/// Seeds a generator.
bk_rng bk_rng_seed(uint64_t seed, uint64_t stream);
/// Next 32 random bits.
uint32_t bk_rng_next(bk_rng* rng);
/// Uniform double in [0, 1).
double bk_rng_unit(bk_rng* rng);
/// Uniformly distributed unit vector.
bk_vec3 bk_rng_direction(bk_rng* rng);

/// Open-addressing map from 64-bit keys to 32-bit values, for index-based
/// topology lookups (edge -> new vertex, directed edge -> triangle).
/// UINT64_MAX marks empty slots and is not a valid key.
typedef struct bk_index_map {
  uint64_t* keys;
  uint32_t* values;
  uint32_t count, capacity; ///< capacity is a power of two
} bk_index_map;

/// Prepares a map for about `expected` keys (may be 0).
void bk_index_map_init(bk_index_map* map, uint32_t expected);
/// Releases the map.
void bk_index_map_free(bk_index_map* map);
/// Removes every key (shrinking storage that the last use left mostly empty).
void bk_index_map_clear(bk_index_map* map);
/// Returns a pointer to the value of key, inserting `value` first if absent;
/// *inserted tells which happened. The pointer is valid until the next insert.
uint32_t* bk_index_map_insert(bk_index_map* map, uint64_t key, uint32_t value, bool* inserted);
/// Returns the value of key or NULL.
uint32_t* bk_index_map_find(const bk_index_map* map, uint64_t key);

/// Key of the undirected edge {a, b}.
static inline uint64_t bk_edge_key(uint32_t a, uint32_t b) {
  return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}
/// Key of the directed edge a -> b.
static inline uint64_t bk_directed_edge_key(uint32_t a, uint32_t b) { return ((uint64_t)a << 32) | b; }

/// 64-bit FNV-1a over bytes, continuing from `hash` (start with BK_FNV_OFFSET).
uint64_t bk_hash_bytes(uint64_t hash, const void* data, size_t size);
#define BK_FNV_OFFSET 0xcbf29ce484222325ull

/// One entry of a bk_heap.
typedef struct bk_heap_item {
  double key;
  uint32_t value;
} bk_heap_item;

/// Binary min-heap: smallest key first, equal keys by smallest value (so the
/// order is deterministic). Zero-initialised is empty.
typedef struct bk_heap {
  bk_heap_item* items;
  uint32_t count, capacity;
} bk_heap;

/// Adds a pair.
void bk_heap_push(bk_heap* heap, double key, uint32_t value);
/// Removes and returns the first pair; the heap must not be empty.
bk_heap_item bk_heap_pop(bk_heap* heap);
/// Releases the heap's storage and empties it.
void bk_heap_free(bk_heap* heap);

/// Growth helper: returns a capacity >= need (doubling), aborting on overflow.
uint32_t bk_grow_capacity(uint32_t current, uint32_t need);
/// malloc/realloc that abort with a message on exhaustion (geometry code has no partial states to recover).
void* bk_alloc(size_t size);
void* bk_realloc(void* ptr, size_t size);
void* bk_calloc(size_t count, size_t size);

/// Reads a whole file into a fresh buffer (free it with free()). Files over
/// max_bytes are refused with "<path>: file larger than <limit_text>, refusing
/// to load"; limit_text lets each caller name its limit ("1 GiB"). max_bytes
/// must be a power of two of at least 64 KiB, the granularity the buffer grows by.
bool bk_file_read(const char* path, uint64_t max_bytes, const char* limit_text, void** data, size_t* size,
                  bk_error* err);

/// Wording of atomic-write failures; each message reads "<path>: <text>: <reason>".
typedef struct bk_atomic_messages {
  const char* open_failed;   ///< the temporary file could not be created
  const char* write_failed;  ///< writing, flushing, syncing or closing failed
  const char* rename_failed; ///< the temporary could not replace the target
} bk_atomic_messages;

/// A file being written beside its target, to replace the target atomically.
typedef struct bk_atomic_file {
  FILE* stream;   ///< write the new contents here
  char* tmp_path; ///< the temporary's name (owned; released by bk_file_commit_atomic)
} bk_atomic_file;

/// Starts replacing `path` atomically: creates a temporary file with a new,
/// unique name in the same directory, exclusively (a file or symlink already
/// there is never opened or followed), with the permissions a new file gets
/// (0666 less the umask). Readers see either the old file or the complete new
/// one, never a partial write, and concurrent writers never share a
/// temporary. Returns false (err filled, nothing created) on failure.
bool bk_file_begin_atomic(const char* path, const bk_atomic_messages* messages, bk_atomic_file* out,
                          bk_error* err);
/// Finishes a write begun by bk_file_begin_atomic: checks the stream, flushes,
/// syncs, closes and renames over `path`. Always consumes the file; on any
/// failure the temporary is removed and the target left as it was.
bool bk_file_commit_atomic(bk_atomic_file* file, const char* path, const bk_atomic_messages* messages,
                           bk_error* err);

#ifdef __cplusplus
}
#endif
