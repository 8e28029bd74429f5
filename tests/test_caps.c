// Caps with holes and islands: the eggshell's annulus, the torus's two
// discs, an island inside a cavity; hull separation of the cut sides; direct
// cap triangulation of polygons with holes, islands, collinear and touching
// loops, and its failure on open chains.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../src/lib/fracture/cap.h"
#include "bk_fracture.h"
#include "ensure.h"

#define PI 3.14159265358979323846

static bk_slicer* slicer;

// ---------------------------------------------------------------- helpers

static bk_plane plane_eq(double a, double b, double c, double d) {
  double len = sqrt(a * a + b * b + c * c);
  return (bk_plane){bk_v3(a / len, b / len, c / len), d / len};
}

static double triangle_area(const bk_mesh* m, uint32_t t) {
  bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
  bk_vec3 b = m->positions[bk_mesh_tri_position(m, t, 1)];
  bk_vec3 c = m->positions[bk_mesh_tri_position(m, t, 2)];
  return 0.5 * bk_v3_length(bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a)));
}

static double cap_area(const bk_mesh* m, uint32_t tag) {
  double area = 0.0;
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    if (m->materials[t] == BK_MATERIAL_INTERIOR && m->tags[t] == tag) area += triangle_area(m, t);
  return area;
}

static void ensure_closed(const bk_mesh* m, const char* what) {
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_validate(m, &err), "%s: %s", what, err.message);
  bk_closure c = bk_mesh_check_closure(m);
  ENSURE_MSG(bk_mesh_is_closed(m), "%s: open %u overused %u degenerate %u", what, c.open_edges,
             c.overused_edges, c.degenerate_edges);
}

/// Slices and checks what every cut must satisfy: both sides non-empty and
/// closed, volumes adding up, cap areas equal, caps in the plane with the
/// side's normal.
static void slice(const bk_mesh* m, bk_plane plane, uint32_t tag, bk_mesh* below, bk_mesh* above,
                  const char* what) {
  bk_slice_def d = {0};
  d.plane = plane;
  d.cap_tag = tag;
  bk_error err = {{0}};
  ENSURE_MSG(bk_slicer_slice(slicer, m, &d, below, above, &err), "%s: %s", what, err.message);
  ENSURE_MSG(below->triangle_count > 0 && above->triangle_count > 0, "%s: a side is empty", what);
  ensure_closed(below, what);
  ensure_closed(above, what);
  ENSURE_REL(bk_mesh_volume(below) + bk_mesh_volume(above), bk_mesh_volume(m), 1e-12);
  ENSURE_REL(cap_area(below, tag), cap_area(above, tag), 1e-12);
  const bk_mesh* sides[2] = {below, above};
  for (int s = 0; s < 2; ++s) {
    bk_vec3 expected = bk_v3_scale(plane.normal, s == 0 ? 1.0 : -1.0);
    for (uint32_t t = 0; t < sides[s]->triangle_count; ++t) {
      if (sides[s]->materials[t] != BK_MATERIAL_INTERIOR || sides[s]->tags[t] != tag) continue;
      for (int k = 0; k < 3; ++k) {
        const bk_corner* c = &sides[s]->corners[sides[s]->indices[3 * t + k]];
        ENSURE(fabs(bk_plane_distance(plane, sides[s]->positions[c->position])) <= 1e-12);
        ENSURE(fabs(c->normal[0] - expected.x) <= 1e-6 && fabs(c->normal[1] - expected.y) <= 1e-6 &&
               fabs(c->normal[2] - expected.z) <= 1e-6);
      }
    }
  }
}

/// The boundary of a side's cap (cap-triangle edges without an opposite cap
/// edge) as loops: returns the loop count and writes each loop's signed area
/// in the plane's (u, v) basis (positive = counter-clockwise about +n).
static uint32_t cap_loops(const bk_mesh* m, uint32_t tag, bk_plane plane, double* areas, uint32_t max_loops) {
  bk_index_map edges = {0};
  bk_index_map_init(&edges, 3u * m->triangle_count);
  bool inserted = false;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    if (m->materials[t] != BK_MATERIAL_INTERIOR || m->tags[t] != tag) continue;
    for (int k = 0; k < 3; ++k) {
      uint32_t a = bk_mesh_tri_position(m, t, k), b = bk_mesh_tri_position(m, t, (k + 1) % 3);
      bk_index_map_insert(&edges, bk_directed_edge_key(a, b), 0, &inserted);
      ENSURE_MSG(inserted, "cap uses the directed edge %u -> %u twice", a, b);
    }
  }
  uint32_t* next = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  memset(next, 0xff, sizeof(uint32_t) * m->position_count);
  for (uint32_t s = 0; s < edges.capacity; ++s) {
    uint64_t key = edges.keys[s];
    if (key == UINT64_MAX) continue;
    uint32_t a = (uint32_t)(key >> 32), b = (uint32_t)key;
    if (bk_index_map_find(&edges, bk_directed_edge_key(b, a))) continue;
    ENSURE_MSG(next[a] == UINT32_MAX, "two boundary edges leave position %u", a);
    next[a] = b;
  }
  bk_vec3 u, v;
  bk_plane_basis(plane.normal, &u, &v);
  uint32_t loops = 0;
  for (uint32_t start = 0; start < m->position_count; ++start) {
    if (next[start] == UINT32_MAX) continue;
    double area = 0.0;
    uint32_t a = start, steps = 0;
    while (next[a] != UINT32_MAX) {
      uint32_t b = next[a];
      next[a] = UINT32_MAX;
      bk_vec3 pa = m->positions[a], pb = m->positions[b];
      area += 0.5 * (bk_v3_dot(pa, u) * bk_v3_dot(pb, v) - bk_v3_dot(pb, u) * bk_v3_dot(pa, v));
      a = b;
      ENSURE(++steps <= m->position_count);
    }
    ENSURE_MSG(a == start, "cap boundary is not a closed loop");
    if (loops < max_loops) areas[loops] = area;
    loops++;
  }
  free(next);
  bk_index_map_free(&edges);
  return loops;
}

/// A mesh made of the triangles [t0, t1) of m (positions and corners kept in
/// their original order).
static void extract(const bk_mesh* m, uint32_t t0, uint32_t t1, bk_mesh* out) {
  memset(out, 0, sizeof *out);
  uint32_t* pos_map = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  uint32_t* corner_map = bk_alloc(sizeof(uint32_t) * (m->corner_count + 1u));
  memset(pos_map, 0xff, sizeof(uint32_t) * m->position_count);
  memset(corner_map, 0xff, sizeof(uint32_t) * m->corner_count);
  for (uint32_t t = t0; t < t1; ++t)
    for (int k = 0; k < 3; ++k) {
      corner_map[m->indices[3 * t + k]] = 0;
      pos_map[bk_mesh_tri_position(m, t, k)] = 0;
    }
  for (uint32_t i = 0; i < m->position_count; ++i)
    if (pos_map[i] == 0) pos_map[i] = bk_mesh_add_position(out, m->positions[i]);
  for (uint32_t i = 0; i < m->corner_count; ++i)
    if (corner_map[i] == 0) {
      bk_corner c = m->corners[i];
      c.position = pos_map[c.position];
      corner_map[i] = bk_mesh_add_corner(out, &c);
    }
  for (uint32_t t = t0; t < t1; ++t)
    bk_mesh_add_triangle(out, corner_map[m->indices[3 * t]], corner_map[m->indices[3 * t + 1]],
                         corner_map[m->indices[3 * t + 2]], m->materials[t], m->tags[t]);
  free(pos_map);
  free(corner_map);
}

/// Appends the box [lo, hi] (outward, or inward-facing as a cavity).
static void add_box(bk_mesh* m, bk_vec3 lo, bk_vec3 hi, bool inward) {
  bk_mesh box;
  bk_shape_build(BK_SHAPE_CUBE, &box);
  for (uint32_t i = 0; i < box.position_count; ++i) {
    bk_vec3* p = &box.positions[i];
    *p = bk_v3(p->x < 0 ? lo.x : hi.x, p->y < 0 ? lo.y : hi.y, p->z < 0 ? lo.z : hi.z);
  }
  if (inward) {
    for (uint32_t t = 0; t < box.triangle_count; ++t) {
      uint32_t tmp = box.indices[3 * t + 1];
      box.indices[3 * t + 1] = box.indices[3 * t + 2];
      box.indices[3 * t + 2] = tmp;
    }
    for (uint32_t i = 0; i < box.corner_count; ++i)
      for (int k = 0; k < 3; ++k)
        box.corners[i].normal[k] = -box.corners[i].normal[k];
  }
  bk_mesh_append(m, &box);
  bk_mesh_free(&box);
}

static int compare_double(const void* a, const void* b) {
  double x = *(const double*)a, y = *(const double*)b;
  return x < y ? -1 : x > y;
}

/// Splits into hulls, checks each is closed with positive volume and that
/// they add up to the mesh; writes the sorted hull volumes.
static uint32_t split(const bk_mesh* m, double* volumes, uint32_t max, const char* what) {
  bk_mesh* hulls = NULL;
  bk_mesh consumed = {0};
  bk_mesh_copy(&consumed, m);
  uint32_t count = bk_mesh_split_hulls(&consumed, &hulls);
  ENSURE(consumed.triangle_count == 0 && consumed.positions == NULL);
  ENSURE(count >= 1 && hulls != NULL);
  double sum = 0.0;
  for (uint32_t i = 0; i < count; ++i) {
    ensure_closed(&hulls[i], what);
    double v = bk_mesh_volume(&hulls[i]);
    ENSURE_MSG(v > 0.0, "%s: hull %u volume %g", what, i, v);
    if (i < max) volumes[i] = v;
    sum += v;
    bk_mesh_free(&hulls[i]);
  }
  free(hulls);
  ENSURE_REL(sum, bk_mesh_volume(m), 1e-12);
  qsort(volumes, count < max ? count : max, sizeof(double), compare_double);
  return count;
}

// ---------------------------------------------------------------- eggshell

// The eggshell cut horizontally: the cap is an annulus between the outer and
// inner surfaces' sections. y = 0.3 holds the outer equator ring exactly
// (loop through existing vertices); the others cross both surfaces' edges.
static void check_egg_cut(bk_plane plane, uint32_t tag) {
  bk_mesh egg, below, above;
  bk_shape_build(BK_SHAPE_EGGSHELL, &egg);
  char what[96];
  snprintf(what, sizeof what, "eggshell plane (%g %g %g) %g", plane.normal.x, plane.normal.y, plane.normal.z,
           plane.offset);
  slice(&egg, plane, tag, &below, &above, what);
  double annulus = cap_area(&below, tag);
  ENSURE(annulus > 0.0);
  const bk_mesh* sides[2] = {&below, &above};
  for (int s = 0; s < 2; ++s) {
    double areas[4];
    uint32_t loops = cap_loops(sides[s], tag, plane, areas, 4);
    ENSURE_MSG(loops == 2, "%s side %d: %u cap loops", what, s, loops);
    // One loop each way; outer minus inner is the cap area (positive about the
    // cap's own normal: +n below, -n above).
    ENSURE(areas[0] * areas[1] < 0.0);
    double sign = s == 0 ? 1.0 : -1.0;
    double outer = fmax(sign * areas[0], sign * areas[1]), inner = fmin(sign * areas[0], sign * areas[1]);
    ENSURE(outer > 0.0 && inner < 0.0 && outer > -inner);
    ENSURE_REL(outer + inner, cap_area(sides[s], tag), 1e-12);
    double volume = 0.0;
    ENSURE(split(sides[s], &volume, 1, what) == 1);
  }
  // The same cut of each surface alone: outer disc minus inner disc.
  uint32_t half = egg.triangle_count / 2;
  bk_mesh outer, inner, ob, oa, ib, ia;
  extract(&egg, 0, half, &outer);
  extract(&egg, half, egg.triangle_count, &inner);
  ENSURE(bk_mesh_is_closed(&outer) && bk_mesh_is_closed(&inner));
  ENSURE(bk_mesh_volume(&outer) > 0.0 && bk_mesh_volume(&inner) < 0.0);
  bk_slice_def d = {0};
  d.plane = plane;
  d.cap_tag = tag;
  bk_error err = {{0}};
  ENSURE_MSG(bk_slicer_slice(slicer, &outer, &d, &ob, &oa, &err), "outer surface: %s", err.message);
  ENSURE_MSG(bk_slicer_slice(slicer, &inner, &d, &ib, &ia, &err), "inner surface: %s", err.message);
  ensure_closed(&ob, "outer surface below");
  ensure_closed(&ib, "inner surface below");
  ENSURE_REL(cap_area(&ob, tag) - cap_area(&ib, tag), annulus, 1e-12);
  ENSURE_REL(bk_mesh_volume(&ob) + bk_mesh_volume(&ib), bk_mesh_volume(&below), 1e-12);
  bk_mesh* meshes[] = {&egg, &below, &above, &outer, &inner, &ob, &oa, &ib, &ia};
  for (size_t i = 0; i < sizeof meshes / sizeof meshes[0]; ++i)
    bk_mesh_free(meshes[i]);
}

static void test_eggshell_annulus(void) {
  check_egg_cut(plane_eq(0, 1, 0, 0.3), 1);
  check_egg_cut(plane_eq(0, 1, 0, 0.2), 2);
  check_egg_cut(plane_eq(0, 1, 0, 0.45), 3);
  check_egg_cut(plane_eq(0.2, 1, -0.1, 0.3), 4);
  check_egg_cut(plane_eq(0, -1, 0, -0.3), 5);
}

// The whole eggshell is one hull: its cavity stays with the shell.
static void test_eggshell_one_hull(void) {
  bk_mesh egg;
  bk_shape_build(BK_SHAPE_EGGSHELL, &egg);
  bk_mesh* hulls = NULL;
  bk_mesh consumed = {0};
  bk_mesh_copy(&consumed, &egg);
  ENSURE(bk_mesh_split_hulls(&consumed, &hulls) == 1);
  ENSURE(bk_mesh_hash(&hulls[0]) == bk_mesh_hash(&egg));
  ENSURE_REL(bk_mesh_volume(&hulls[0]), bk_mesh_volume(&egg), 1e-15);
  bk_mesh_free(&hulls[0]);
  free(hulls);
  bk_mesh_free(&egg);
}

// ---------------------------------------------------------------- torus

// The torus ring lies in the xz plane around +y. A plane through the axis
// (x = 0) cuts the tube twice: two disc islands, each a regular 24-gon of
// radius 0.35 (tube rings 12 and 36 of 48 lie in the plane), and each side is one
// C-shaped hull. Cutting the x < 0 half again at x = -0.5 leaves its two arms
// as separate pieces above.
static void test_torus_islands(void) {
  bk_mesh torus, below, above;
  bk_shape_build(BK_SHAPE_TORUS, &torus);
  bk_plane plane = {bk_v3(1, 0, 0), 0.0};
  slice(&torus, plane, 1, &below, &above, "torus x = 0");
  const double disc = 12.0 * sin(PI / 12.0) * 0.35 * 0.35;
  const bk_mesh* sides[2] = {&below, &above};
  for (int s = 0; s < 2; ++s) {
    double areas[4];
    ENSURE(cap_loops(sides[s], 1, plane, areas, 4) == 2);
    double sign = s == 0 ? 1.0 : -1.0;
    ENSURE_REL(sign * areas[0], disc, 1e-12);
    ENSURE_REL(sign * areas[1], disc, 1e-12);
    ENSURE_REL(cap_area(sides[s], 1), 2.0 * disc, 1e-12);
    double volume = 0.0;
    ENSURE(split(sides[s], &volume, 1, "torus half") == 1);
  }
  // Off the rings: still two islands.
  bk_mesh b2, a2;
  bk_plane off = {bk_v3(1, 0, 0), 0.1};
  slice(&torus, off, 2, &b2, &a2, "torus x = 0.1");
  double areas[4];
  ENSURE(cap_loops(&b2, 2, off, areas, 4) == 2);
  ENSURE(areas[0] > 0.0 && areas[1] > 0.0);
  ENSURE(cap_loops(&a2, 2, off, areas, 4) == 2);
  bk_mesh_free(&b2);
  bk_mesh_free(&a2);

  // Second cut of the x < 0 half.
  bk_mesh far, near;
  bk_plane second = {bk_v3(1, 0, 0), -0.5};
  slice(&below, second, 3, &far, &near, "torus half x = -0.5");
  ENSURE(cap_loops(&near, 3, second, areas, 4) == 2);
  ENSURE(cap_loops(&far, 3, second, areas, 4) == 2);
  double volumes[4] = {0};
  ENSURE(split(&far, volumes, 4, "torus far part") == 1);
  ENSURE(split(&near, volumes, 4, "torus arms") == 2);
  // The two arms mirror each other (z -> -z) up to the quads' diagonals.
  ENSURE_REL(volumes[0], volumes[1], 1e-2);
  // A direct cut of the torus at x = -0.5 gives one C-shaped piece above.
  bk_mesh b3, a3;
  slice(&torus, second, 4, &b3, &a3, "torus x = -0.5");
  ENSURE(split(&a3, volumes, 4, "torus C") == 1);
  ENSURE(split(&b3, volumes, 4, "torus cap piece") == 1);
  bk_mesh* meshes[] = {&torus, &below, &above, &far, &near, &b3, &a3};
  for (size_t i = 0; i < sizeof meshes / sizeof meshes[0]; ++i)
    bk_mesh_free(meshes[i]);
}

// ---------------------------------------------------------------- island in a hole

// Outer box [-1, 1]^3 (outward), cavity [-0.7, 0.7]^3 (inward) and a solid
// island [-0.3, 0.3]^3 inside the cavity.
static void build_island_in_hole(bk_mesh* m) {
  memset(m, 0, sizeof *m);
  add_box(m, bk_v3(-1, -1, -1), bk_v3(1, 1, 1), false);
  add_box(m, bk_v3(-0.7, -0.7, -0.7), bk_v3(0.7, 0.7, 0.7), true);
  add_box(m, bk_v3(-0.3, -0.3, -0.3), bk_v3(0.3, 0.3, 0.3), false);
}

/// Volume of the island-in-hole solid with z < h.
static double island_volume_below(double h) {
  double outer = 4.0 * fmin(fmax(h + 1.0, 0.0), 2.0);
  double cavity = 1.96 * fmin(fmax(h + 0.7, 0.0), 1.4);
  double island = 0.36 * fmin(fmax(h + 0.3, 0.0), 0.6);
  return outer - cavity + island;
}

static void test_island_in_hole(void) {
  bk_mesh m, below, above;
  build_island_in_hole(&m);
  ensure_closed(&m, "island in hole");
  ENSURE_REL(bk_mesh_volume(&m), 8.0 - 2.744 + 0.216, 1e-12);
  // Uncut: the shell (outer + cavity) and the island.
  double volumes[4] = {0};
  ENSURE(split(&m, volumes, 4, "island in hole") == 2);
  ENSURE_REL(volumes[0], 0.216, 1e-12);
  ENSURE_REL(volumes[1], 8.0 - 2.744, 1e-12);

  // Through all three boxes: cap = (outer square - cavity square) + island square.
  bk_plane plane = {bk_v3(0, 0, 1), 0.1};
  slice(&m, plane, 7, &below, &above, "island in hole z = 0.1");
  ENSURE_REL(bk_mesh_volume(&below), island_volume_below(0.1), 1e-12);
  ENSURE_REL(bk_mesh_volume(&above), island_volume_below(1.0) - island_volume_below(0.1), 1e-12);
  const double cap = 4.0 - 1.96 + 0.36;
  ENSURE_REL(cap_area(&below, 7), cap, 1e-12);
  ENSURE_REL(cap_area(&above, 7), cap, 1e-12);
  double areas[4];
  ENSURE(cap_loops(&below, 7, plane, areas, 4) == 3);
  ENSURE(cap_loops(&above, 7, plane, areas, 4) == 3);
  // Below: the shell (joined to its cavity by the annular cap) and the island.
  ENSURE(split(&below, volumes, 4, "island in hole below") == 2);
  ENSURE_REL(volumes[0], 0.36 * 0.4, 1e-12);
  ENSURE_REL(volumes[1], 4.0 * 1.1 - 1.96 * 0.8, 1e-12);
  ENSURE(split(&above, volumes, 4, "island in hole above") == 2);
  ENSURE_REL(volumes[0], 0.36 * 0.2, 1e-12);
  ENSURE_REL(volumes[1], 4.0 * 0.9 - 1.96 * 0.6, 1e-12);
  bk_mesh_free(&below);
  bk_mesh_free(&above);

  // In the plane of the island's top (bottom) face: the island goes whole to
  // the side its face closes, and the cap is only the annulus.
  const double planes[2] = {0.3, -0.3};
  for (int i = 0; i < 2; ++i) {
    bk_plane p = {bk_v3(0, 0, 1), planes[i]};
    slice(&m, p, 8, &below, &above, "island in hole, plane on the island's face");
    ENSURE_REL(bk_mesh_volume(&below), island_volume_below(planes[i]), 1e-12);
    ENSURE_REL(cap_area(&below, 8), 4.0 - 1.96, 1e-12);
    ENSURE(cap_loops(&below, 8, p, areas, 4) == 2);
    ENSURE(cap_loops(&above, 8, p, areas, 4) == 2);
    ENSURE(split(&below, volumes, 4, "below") == (planes[i] > 0 ? 2u : 1u));
    ENSURE(split(&above, volumes, 4, "above") == (planes[i] > 0 ? 1u : 2u));
    bk_mesh_free(&below);
    bk_mesh_free(&above);
  }
  bk_mesh_free(&m);
}

// Two hollow boxes side by side: each cavity stays with its own shell.
static void test_two_shells(void) {
  bk_mesh m = {0};
  add_box(&m, bk_v3(-3, -1, -1), bk_v3(-1, 1, 1), false);                // 8
  add_box(&m, bk_v3(1, -0.5, -0.5), bk_v3(2, 0.5, 0.5), false);          // 1
  add_box(&m, bk_v3(1.25, -0.25, -0.25), bk_v3(1.75, 0.25, 0.25), true); // 0.125
  add_box(&m, bk_v3(-2.5, -0.5, -0.5), bk_v3(-1.5, 0.5, 0.5), true);     // 1
  ensure_closed(&m, "two shells");
  double volumes[4] = {0};
  ENSURE(split(&m, volumes, 4, "two shells") == 2);
  ENSURE_REL(volumes[0], 0.875, 1e-12);
  ENSURE_REL(volumes[1], 7.0, 1e-12);
  bk_mesh_free(&m);
}

// ---------------------------------------------------------------- direct triangulation

typedef struct cap_case {
  uint32_t edges[64];
  uint32_t edge_count;
  double xy[64];
  uint32_t vertex_count;
} cap_case;

static uint32_t add_vertex(cap_case* c, double x, double y) {
  c->xy[2 * c->vertex_count] = x;
  c->xy[2 * c->vertex_count + 1] = y;
  return c->vertex_count++;
}

/// Adds a closed loop through the given points (counter-clockwise when ccw).
static void add_square(cap_case* c, double x0, double y0, double x1, double y1, bool ccw) {
  uint32_t v[4] = {add_vertex(c, x0, y0), add_vertex(c, x1, y0), add_vertex(c, x1, y1),
                   add_vertex(c, x0, y1)};
  for (int k = 0; k < 4; ++k) {
    uint32_t a = v[k], b = v[(k + 1) % 4];
    c->edges[2 * c->edge_count] = ccw ? a : b;
    c->edges[2 * c->edge_count + 1] = ccw ? b : a;
    c->edge_count++;
  }
}

static double signed_area(const double* xy, const uint32_t* t) {
  double ax = xy[2 * t[0]], ay = xy[2 * t[0] + 1];
  double bx = xy[2 * t[1]], by = xy[2 * t[1] + 1];
  double cx = xy[2 * t[2]], cy = xy[2 * t[2] + 1];
  return 0.5 * ((bx - ax) * (cy - ay) - (cx - ax) * (by - ay));
}

/// Triangulates and checks: indices in range, no triangle wound against the
/// expected way (sign of `expected_area`; with `strict`, none of zero area
/// either), total signed area as expected, outer edges exactly the input edges.
static void check_cap(bk_cap* cap, const cap_case* c, double expected_area, bool strict, const char* what) {
  const uint32_t* tris = NULL;
  uint32_t count = 0;
  bk_error err = {{0}};
  ENSURE_MSG(bk_cap_triangulate(cap, c->edges, c->edge_count, c->xy, c->vertex_count, &tris, &count, &err),
             "%s: %s", what, err.message);
  ENSURE(tris != NULL && count > 0);
  double total = 0.0;
  bk_index_map edges = {0};
  bk_index_map_init(&edges, 3u * count);
  for (uint32_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k)
      ENSURE(tris[3 * t + k] < c->vertex_count);
    double a = signed_area(c->xy, &tris[3 * t]);
    ENSURE_MSG(a * expected_area >= 0.0, "%s: triangle %u has signed area %g", what, t, a);
    ENSURE_MSG(!strict || a != 0.0, "%s: triangle %u (%u %u %u) has zero area", what, t, tris[3 * t],
               tris[3 * t + 1], tris[3 * t + 2]);
    total += a;
    for (int k = 0; k < 3; ++k) {
      bool inserted = false;
      bk_index_map_insert(&edges, bk_directed_edge_key(tris[3 * t + k], tris[3 * t + (k + 1) % 3]), 0,
                          &inserted);
      ENSURE_MSG(inserted, "%s: a directed edge is used twice", what);
    }
  }
  ENSURE_REL(total, expected_area, 1e-12);
  uint32_t outer = 0;
  for (uint32_t s = 0; s < edges.capacity; ++s) {
    uint64_t key = edges.keys[s];
    if (key != UINT64_MAX &&
        !bk_index_map_find(&edges, bk_directed_edge_key((uint32_t)key, (uint32_t)(key >> 32))))
      outer++;
  }
  ENSURE_MSG(outer == c->edge_count, "%s: %u outer edges for %u input edges", what, outer, c->edge_count);
  for (uint32_t e = 0; e < c->edge_count; ++e)
    ENSURE(bk_index_map_find(&edges, bk_directed_edge_key(c->edges[2 * e], c->edges[2 * e + 1])));
  bk_index_map_free(&edges);
}

static void test_direct_triangulation(void) {
  bk_cap* cap = bk_cap_create();
  ENSURE(cap);
  // 4 x 4 square with a 2 x 2 hole (wound the other way).
  cap_case c = {0};
  add_square(&c, 0, 0, 4, 4, true);
  add_square(&c, 1, 1, 3, 3, false);
  check_cap(cap, &c, 12.0, false, "square with hole");
  // Loops the other way round: triangles wound the other way.
  cap_case r = {0};
  add_square(&r, 0, 0, 4, 4, false);
  add_square(&r, 1, 1, 3, 3, true);
  check_cap(cap, &r, -12.0, false, "reversed square with hole");
  // An island in the hole.
  add_square(&c, 1.5, 1.5, 2.5, 2.5, true);
  check_cap(cap, &c, 13.0, false, "island in hole");
  // Edges listed in a scrambled order link by index all the same.
  cap_case s = c;
  for (uint32_t e = 0; e < s.edge_count; ++e) {
    uint32_t f = (e * 7u + 3u) % s.edge_count;
    uint32_t a = s.edges[2 * e], b = s.edges[2 * e + 1];
    s.edges[2 * e] = s.edges[2 * f], s.edges[2 * e + 1] = s.edges[2 * f + 1];
    s.edges[2 * f] = a, s.edges[2 * f + 1] = b;
  }
  check_cap(cap, &s, 13.0, false, "scrambled edges");
  // Two squares touching at one vertex (shared index).
  cap_case t = {0};
  add_square(&t, 0, 0, 1, 1, true);
  uint32_t shared = 2; // (1, 1)
  uint32_t p = add_vertex(&t, 2, 1), q = add_vertex(&t, 2, 2), w = add_vertex(&t, 1, 2);
  const uint32_t loop[4] = {shared, p, q, w};
  for (int k = 0; k < 4; ++k) {
    t.edges[2 * t.edge_count] = loop[k];
    t.edges[2 * t.edge_count + 1] = loop[(k + 1) % 4];
    t.edge_count++;
  }
  check_cap(cap, &t, 2.0, false, "squares touching at a vertex");
  // An open chain is refused.
  cap_case o = {0};
  for (int k = 0; k < 4; ++k)
    add_vertex(&o, k == 1 || k == 2, k >= 2);
  for (uint32_t k = 0; k < 3; ++k) {
    o.edges[2 * k] = k;
    o.edges[2 * k + 1] = k + 1;
  }
  o.edge_count = 3;
  const uint32_t* tris = NULL;
  uint32_t count = 0;
  bk_error err = {{0}};
  ENSURE(!bk_cap_triangulate(cap, o.edges, o.edge_count, o.xy, o.vertex_count, &tris, &count, &err));
  ENSURE_MSG(strstr(err.message, "closed loops") != NULL, "message: %s", err.message);
  ENSURE(count == 0);
  // The tessellator is reusable after a failure.
  check_cap(cap, &c, 13.0, false, "after a failure");
  bk_cap_destroy(cap);
  bk_cap_destroy(NULL);
}

// Zero-area triangles are not harmless in a cap: their long edge runs through
// a third vertex (a T-junction), and the next cut crossing it creates two
// positions at one point, which that cut's cap cannot close. Three vertices can
// be collinear across the interior of a concave polygon, or along a side where
// a cut face diagonal left a point.
static void test_direct_no_zero_area(void) {
  bk_cap* cap = bk_cap_create();
  ENSURE(cap);
  // L shape: (0, 2), (1, 1) and (2, 0) are collinear.
  cap_case l = {0};
  const double lx[6] = {0, 2, 2, 1, 1, 0}, ly[6] = {0, 0, 1, 1, 2, 2};
  for (int k = 0; k < 6; ++k)
    add_vertex(&l, lx[k], ly[k]);
  for (uint32_t k = 0; k < 6; ++k) {
    l.edges[2 * k] = k;
    l.edges[2 * k + 1] = (k + 1) % 6;
  }
  l.edge_count = 6;
  check_cap(cap, &l, 3.0, true, "L shape");
  // Collinear points on the sides (as cut face diagonals leave them).
  cap_case m = {0};
  const double mx[8] = {0, 1, 2, 2, 2, 1, 0, 0}, my[8] = {0, 0, 0, 1, 2, 2, 2, 1};
  for (int k = 0; k < 8; ++k)
    add_vertex(&m, mx[k], my[k]);
  for (uint32_t k = 0; k < 8; ++k) {
    m.edges[2 * k] = k;
    m.edges[2 * k + 1] = (k + 1) % 8;
  }
  m.edge_count = 8;
  check_cap(cap, &m, 4.0, true, "square with side midpoints");
  bk_cap_destroy(cap);
}

int main(void) {
  slicer = bk_slicer_create();
  ENSURE(slicer);
  RUN(test_eggshell_annulus);
  RUN(test_eggshell_one_hull);
  RUN(test_torus_islands);
  RUN(test_island_in_hole);
  RUN(test_two_shells);
  RUN(test_direct_triangulation);
  RUN(test_direct_no_zero_area);
  bk_slicer_destroy(slicer);
  return 0;
}
