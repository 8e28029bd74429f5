// Internal: the cell complex behind the cell patterns (Voronoi, clustered,
// radial, cut-out). The source is divided by the Voronoi cells of seed
// points. Every vertex of the result is named by what made it (a source
// position, a source edge crossing a bisector, a source triangle pierced by a
// Voronoi edge, a Voronoi vertex) and its coordinates are computed once from
// that name, so two cells that share a vertex share it exactly: every cell,
// and every union of cells, is closed by topology, and neighbours' faces are
// the same triangles.
#pragma once

#include "bk_fracture.h"

/// Ids of the six planes of the bounding box that encloses all cells (seeds
/// are ids >= 0): -1/-2 = x min/max, -3/-4 = y, -5/-6 = z.
#define BK_CELL_BOX_PLANES 6

/// What a vertex of the complex is; its name fixes its coordinates.
typedef enum bk_cell_vertex_kind {
  BK_CELL_SOURCE,      ///< a source position: a = position
  BK_CELL_CROSSING,    ///< source edge (a < b, positions) crossing the bisector of seeds s[0] < s[1]
  BK_CELL_PIERCING,    ///< source triangle a pierced by the Voronoi edge of seeds s[0] < s[1] < s[2]
  BK_CELL_CORNER,      ///< a Voronoi vertex: four ids s[0] < ... < s[3] (seeds or box planes)
  BK_CELL_NOISE_POINT, ///< point b of noisy cut face a (placed, not computed)
} bk_cell_vertex_kind;

typedef struct bk_cell_key {
  uint32_t kind, a, b;
  int32_t s[4];
} bk_cell_key;

/// The seeds, the source (in the local frame) and every named vertex.
typedef struct bk_cell_complex {
  const bk_mesh* source;
  const bk_vec3* seeds;
  uint32_t seed_count;
  bk_aabb box;     ///< encloses the source and every seed with a margin
  int planar_axis; ///< -1, or the axis all seeds share one coordinate on (distances ignore it)
  bk_cell_key* keys;
  bk_vec3* points;
  uint32_t count, capacity;
  uint32_t* slots; ///< open addressing: vertex index + 1, 0 = empty
  uint32_t slot_mask;
  uint32_t* source_vertex; ///< per source position: its vertex, or UINT32_MAX before first use
} bk_cell_complex;

void bk_cell_complex_init(bk_cell_complex* cx, const bk_mesh* source, const bk_vec3* seeds,
                          uint32_t seed_count);
void bk_cell_complex_free(bk_cell_complex* cx);
/// The vertex with this name (ids sorted by the caller as documented),
/// computed and added on first use. Returns its index.
uint32_t bk_cell_vertex(bk_cell_complex* cx, const bk_cell_key* key);
/// The vertex of source position `position` (bk_cell_vertex without the
/// hashing: every cell's surface asks for these again and again).
uint32_t bk_cell_source_vertex(bk_cell_complex* cx, uint32_t position);
/// Adds a vertex whose coordinates are given (a noisy face's point).
uint32_t bk_cell_vertex_at(bk_cell_complex* cx, const bk_cell_key* key, bk_vec3 point);
/// The index of a named vertex, or UINT32_MAX.
uint32_t bk_cell_vertex_find(const bk_cell_complex* cx, const bk_cell_key* key);

/// The side of point p relative to the bisector of seeds a and b (a != b):
/// true when p belongs to a's cell (nearer a; on the bisector it belongs to
/// the lower id). The same arithmetic serves both cells, so they never both
/// claim a point.
bool bk_cell_belongs(const bk_cell_complex* cx, bk_vec3 p, int32_t a, int32_t b);

/// bk_cell_belongs for one pair of seeds, precomputed: the same arithmetic,
/// so the same answers bit for bit.
typedef struct bk_cell_side {
  double row[4]; ///< the bisector of the lower and higher seed: row . p - row[3] > 0 is nearer the higher
  bool low;      ///< the cell is the lower seed
} bk_cell_side;

/// The side test of `cell` against seed `other` (>= 0).
bk_cell_side bk_cell_side_of(const bk_cell_complex* cx, int32_t cell, int32_t other);
/// The bisector function of a side (the value whose sign decides).
static inline double bk_cell_side_value(const bk_cell_side* s, bk_vec3 p) {
  return s->row[0] * p.x + s->row[1] * p.y + s->row[2] * p.z - s->row[3];
}
/// True when p is on the cell's side.
static inline bool bk_cell_side_keeps(const bk_cell_side* s, bk_vec3 p) {
  double f = bk_cell_side_value(s, p);
  return s->low ? f <= 0.0 : f > 0.0;
}

/// One cell's convex polytope: faces with counter-clockwise (seen from
/// outside) loops of vertex indices; a face's plane is a neighbour seed id or
/// a box plane id.
typedef struct bk_cell_polytope {
  int32_t* planes;      ///< per face
  uint32_t* face_first; ///< per face: start in `loop`
  uint32_t* face_count; ///< per face: loop length
  uint32_t faces, face_capacity;
  uint32_t* loop;
  uint32_t loop_count, loop_capacity;
} bk_cell_polytope;

/// Scratch for building polytopes (one per thread).
typedef struct bk_cell_builder bk_cell_builder;
bk_cell_builder* bk_cell_builder_create(void);
void bk_cell_builder_destroy(bk_cell_builder* b);
/// Starts the Voronoi cell of seed `cell`: the whole of cx->box.
void bk_cell_polytope_begin(bk_cell_builder* b, bk_cell_complex* cx, uint32_t cell);
/// Clips the cell begun by the bisectors of the seeds in `near`, in order
/// (nearest first), until no farther seed can cut it. Called again with
/// seeds farther than all before, it goes on where it stopped, so the cell
/// is the same however its seeds were listed. Fails only when the cell
/// degenerates (coincident seeds).
bool bk_cell_polytope_clip(bk_cell_builder* b, bk_cell_complex* cx, const uint32_t* near,
                           uint32_t near_count);
/// How far the cell reaches from its seed (within the seeds' plane when
/// they share one): no seed farther than twice this can cut it.
double bk_cell_builder_reach(const bk_cell_builder* b, const bk_cell_complex* cx);
/// Copies the cell into `out` (freed first), its vertices added to cx.
void bk_cell_polytope_store(bk_cell_builder* b, bk_cell_complex* cx, bk_cell_polytope* out);
void bk_cell_polytope_free(bk_cell_polytope* p);
/// Distance between two points as the reach counts it.
double bk_cell_distance(const bk_cell_complex* cx, bk_vec3 a, bk_vec3 b);

/// A uniform grid over the seeds for nearest-first neighbour lists.
typedef struct bk_seed_grid bk_seed_grid;
bk_seed_grid* bk_seed_grid_create(const bk_vec3* seeds, uint32_t count, bk_aabb box);
void bk_seed_grid_destroy(bk_seed_grid* g);
/// The typical distance between seeds around seed `cell` (from the seed
/// density of the bins around it).
double bk_seed_grid_spacing(const bk_seed_grid* g, uint32_t cell);
/// A seed and its squared distance, as the near lists sort them.
typedef struct bk_near_entry {
  double d;
  uint32_t index;
} bk_near_entry;
/// A near list and its scratch (one per thread, reused).
typedef struct bk_seed_near {
  uint32_t* seeds; ///< nearest first
  uint32_t count;
  bk_near_entry* entries; ///< 2 x capacity: the list and the sort's buffer
  uint32_t capacity;
} bk_seed_near;
/// Seeds farther than `inner` (< 0: any) and within `radius` of seed `cell`
/// (itself excluded), nearest first (ties: the lower id), into out->seeds.
/// Returns the count. The seeds within a larger radius are those within a
/// smaller one followed by those between the two.
uint32_t bk_seed_grid_near(const bk_seed_grid* g, uint32_t cell, double inner, double radius,
                           bk_seed_near* out);
void bk_seed_near_free(bk_seed_near* n);

/// One piece of one source triangle inside one cell: a convex polygon.
/// Edge k runs from vertex k to k + 1; its `support` is the bisector's other
/// seed when the edge lies on a cell face, else -1 (along the triangle's
/// own edge).
typedef struct bk_cell_polygon {
  uint32_t triangle;
  uint32_t first, count; ///< range in the surface's vertex/support arrays
} bk_cell_polygon;

typedef struct bk_cell_surface {
  bk_cell_polygon* polygons;
  uint32_t polygon_count, polygon_capacity;
  uint32_t* vertices; ///< complex vertex indices
  int32_t* supports;
  uint32_t vertex_count, vertex_capacity;
} bk_cell_surface;

/// Clips the source triangles that may meet the cell (`triangles`) by the
/// cell's planes and appends the pieces to `out`.
void bk_cell_clip_surface(bk_cell_complex* cx, uint32_t cell, const bk_cell_polytope* poly,
                          const uint32_t* triangles, uint32_t triangle_count, bk_cell_surface* out);
void bk_cell_surface_free(bk_cell_surface* s);

/// Seeds of a pattern in the local frame (`to_local` maps the caller's
/// points). Returns the count written to *seeds (allocated), or 0 with err
/// set. Clustered: *cluster_of gives each seed's chunk and *labels each
/// seed's piece (a chunk's core cells share one); NULL otherwise.
uint32_t bk_cell_seeds(const bk_mesh* local_source, const bk_fracture_def* d, bk_vec3 origin, int exponent,
                       bk_vec3** seeds, uint32_t** cluster_of, uint32_t** labels, bk_error* err);

/// Flags, per point, whether it lies inside the closed mesh (ray parity).
void bk_points_inside(const bk_mesh* mesh, const bk_vec3* points, uint32_t count, uint8_t* inside);
/// bk_points_inside for many batches of points: the mesh is binned once.
typedef struct bk_inside_test bk_inside_test;
bk_inside_test* bk_inside_test_create(const bk_mesh* mesh);
void bk_inside_test_run(const bk_inside_test* t, const bk_vec3* points, uint32_t count, uint8_t* inside);
void bk_inside_test_destroy(bk_inside_test* t);

/// The cut faces between cells: each the part of a Voronoi face inside the
/// source, triangulated once and used by both cells (reversed for b).
typedef struct bk_cell_face {
  uint32_t a, b;            ///< cells, a < b
  uint32_t first, count;    ///< triangles (3 vertex indices each) in bk_cell_faces.triangles
  uint32_t source_triangle; ///< a source triangle along its border (its material), or UINT32_MAX
  bk_vec3 normal;           ///< unit, from a towards b; triangles wind counter-clockwise around it
} bk_cell_face;

typedef struct bk_cell_faces {
  bk_cell_face* faces;
  uint32_t count, capacity;
  uint32_t* triangles;
  uint32_t triangle_count, triangle_capacity;
  /// Pairs of cells (a < b, 2 ids each, in increasing order) whose cut face
  /// could not be made: their loops cross where the source's surface
  /// crosses itself. Such a face is left out of both cells, which must then
  /// be one piece: their union is closed without it.
  uint32_t* joined;
  uint32_t joined_count;
} bk_cell_faces;

/// Builds every cut face from the cells' polytopes and surfaces, on up to
/// `threads` threads (the same faces for any count). Fails when the complex
/// is inconsistent (rounding in a near-degenerate seed layout), or, unless
/// `join` is set, when a face cannot be triangulated; with `join` such a
/// face is listed in out->joined instead.
bool bk_cell_build_faces(bk_cell_complex* cx, const bk_cell_polytope* polytopes,
                         const bk_cell_surface* surfaces, uint32_t cells, uint32_t threads, bool join,
                         bk_cell_faces* out, bk_error* err);
void bk_cell_faces_free(bk_cell_faces* f);

/// Refinement levels of a noisy cut face at most (each splits the face
/// triangles' inner edges).
#define BK_CELL_NOISE_MAX_LEVELS 3
/// The refined faces may have at most this many times the triangles of the
/// flat ones, or BK_CELL_NOISE_EXTRA more, however fine the noise (fewer
/// levels are taken for every face until they fit). memory_estimate.c
/// follows these three.
#define BK_CELL_NOISE_BUDGET 8.0
#define BK_CELL_NOISE_EXTRA 100000.0

/// Refines every cut face and pushes its inner points along its normal by
/// coherent noise (amplitude and frequency in local units), tapered to zero
/// at the face's border, which stays put.
void bk_cell_faces_add_noise(bk_cell_complex* cx, bk_cell_faces* faces, double amplitude, double frequency,
                             uint64_t seed);
