// Plane slicing: both sides closed, exact volumes and cap areas for the cube
// cut by axis planes, planes through vertices, edges and faces and random
// planes; one shared position per cut edge; caps in the plane with the right
// normals and tags; attribute interpolation on cut edges; the procedural
// shapes; recursive cuts; faces lying in the plane; failure on an open mesh.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"

#define PI 3.14159265358979323846

static bk_slicer* slicer;

// ---------------------------------------------------------------- helpers

/// Deterministic 64-bit LCG (Knuth's MMIX constants); uniform double in [0, 1).
static uint64_t lcg_state = 0x9e3779b97f4a7c15ull;
static double lcg_unit(void) {
  lcg_state = lcg_state * 6364136223846793005ull + 1442695040888963407ull;
  return (double)(lcg_state >> 11) * 0x1.0p-53;
}
static double lcg_range(double lo, double hi) { return lo + (hi - lo) * lcg_unit(); }
static bk_vec3 lcg_direction(void) {
  for (;;) {
    bk_vec3 d = bk_v3(lcg_range(-1, 1), lcg_range(-1, 1), lcg_range(-1, 1));
    double len2 = bk_v3_dot(d, d);
    if (len2 > 1e-2 && len2 <= 1.0) return bk_v3_normalize(d);
  }
}

/// The plane a x + b y + c z = d with its normal normalised.
static bk_plane plane_eq(double a, double b, double c, double d) {
  double len = sqrt(a * a + b * b + c * c);
  return (bk_plane){bk_v3(a / len, b / len, c / len), d / len};
}

static bk_plane plane_through(bk_vec3 normal, bk_vec3 point) {
  bk_vec3 n = bk_v3_normalize(normal);
  return (bk_plane){n, bk_v3_dot(n, point)};
}

static bk_slice_def make_desc(bk_plane plane, uint32_t tag) {
  bk_slice_def d = {0};
  d.plane = plane;
  d.cap_tag = tag;
  return d;
}

static double triangle_area(const bk_mesh* m, uint32_t t, bk_vec3* cross) {
  bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
  bk_vec3 b = m->positions[bk_mesh_tri_position(m, t, 1)];
  bk_vec3 c = m->positions[bk_mesh_tri_position(m, t, 2)];
  *cross = bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a));
  return 0.5 * bk_v3_length(*cross);
}

static bk_vec3 corner_normal(const bk_corner* c) { return bk_v3(c->normal[0], c->normal[1], c->normal[2]); }

typedef struct side_report {
  double volume;
  double cap_area;  ///< triangles of this cut (INTERIOR with the cut's tag)
  double kept_area; ///< every other triangle
  uint32_t cap_triangles;
} side_report;

/// Checks one non-empty side (0 = below, 1 = above) of a cut. Source meshes
/// have OUTER triangles with tag 0 and caps of earlier cuts with smaller tags.
static side_report check_side(const bk_mesh* m, const bk_slice_def* d, int side, const char* what) {
  side_report r = {0};
  const char* name = side == 0 ? "below" : "above";
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_validate(m, &err), "%s %s: %s", what, name, err.message);
  bk_closure closure = bk_mesh_check_closure(m);
  ENSURE_MSG(bk_mesh_is_closed(m), "%s %s: open %u overused %u degenerate %u", what, name, closure.open_edges,
             closure.overused_edges, closure.degenerate_edges);
  const bk_vec3 n = d->plane.normal;
  const double sign = side == 0 ? -1.0 : 1.0;       // sign of the signed distance on this side
  const bk_vec3 cap_normal = bk_v3_scale(n, -sign); // below: +n, above: -n
  const double scale = d->texture_scale > 0.0 ? d->texture_scale : 0.1;
  bk_vec3 u, v;
  bk_plane_basis(n, &u, &v);
  for (uint32_t i = 0; i < m->position_count; ++i) {
    double dist = bk_plane_distance(d->plane, m->positions[i]);
    ENSURE_MSG(sign * dist >= -1e-12, "%s %s: position %u on the wrong side (distance %.17g)", what, name, i,
               dist);
  }
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    const bk_corner* c = &m->corners[i];
    ENSURE_MSG(fabs(bk_v3_length(corner_normal(c)) - 1.0) <= 1e-5, "%s %s: corner %u normal not unit", what,
               name, i);
    double tangent =
        sqrt(c->tangent[0] * c->tangent[0] + c->tangent[1] * c->tangent[1] + c->tangent[2] * c->tangent[2]);
    ENSURE_MSG(fabs(tangent - 1.0) <= 1e-4, "%s %s: corner %u tangent length %g", what, name, i, tangent);
  }
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 cross;
    double area = triangle_area(m, t, &cross);
    bool cap = m->materials[t] == BK_MATERIAL_INTERIOR && m->tags[t] == d->cap_tag;
    if (!cap) {
      if (m->materials[t] == BK_MATERIAL_OUTER)
        ENSURE_MSG(m->tags[t] == 0, "%s %s: outer triangle %u has tag %u", what, name, t, m->tags[t]);
      else
        ENSURE_MSG(m->tags[t] < d->cap_tag, "%s %s: interior triangle %u has tag %u (cut tag %u)", what, name,
                   t, m->tags[t], d->cap_tag);
      r.kept_area += area;
      continue;
    }
    r.cap_triangles++;
    r.cap_area += area;
    ENSURE_MSG(bk_v3_dot(cross, cap_normal) >= -1e-14, "%s %s: cap triangle %u is wound against its normal",
               what, name, t);
    for (int k = 0; k < 3; ++k) {
      const bk_corner* c = &m->corners[m->indices[3 * t + k]];
      bk_vec3 p = m->positions[c->position];
      double dist = bk_plane_distance(d->plane, p);
      ENSURE_MSG(fabs(dist) <= 1e-12, "%s %s: cap triangle %u corner %d off the plane by %.17g", what, name,
                 t, k, dist);
      bk_vec3 cn = corner_normal(c);
      ENSURE_MSG(bk_v3_length(bk_v3_sub(cn, cap_normal)) <= 1e-6,
                 "%s %s: cap triangle %u normal (%g %g %g), expected (%g %g %g)", what, name, t, cn.x, cn.y,
                 cn.z, cap_normal.x, cap_normal.y, cap_normal.z);
      // Planar texture coordinates: the same point gets the same uv on both sides.
      ENSURE_SMALL(c->uv[0] * scale, bk_v3_dot(p, u), 1e-6);
      ENSURE_SMALL(c->uv[1] * scale, bk_v3_dot(p, v), 1e-6);
    }
  }
  r.volume = bk_mesh_volume(m);
  ENSURE_MSG(r.volume > 0.0, "%s %s: volume %g", what, name, r.volume);
  return r;
}

static int compare_vec3(const void* a, const void* b) { return memcmp(a, b, sizeof(bk_vec3)); }

/// Number of distinct position-index edges of `m` whose ends lie strictly on
/// opposite sides of the plane (with the slicer's default tolerance).
static uint32_t crossed_edges(const bk_mesh* m, const bk_slice_def* d) {
  bk_aabb box = bk_mesh_bounds(m);
  double tol = d->tolerance > 0.0 ? d->tolerance : 1e-9 * bk_v3_length(bk_v3_sub(box.max, box.min));
  bk_index_map seen = {0};
  bk_index_map_init(&seen, 3u * m->triangle_count);
  uint32_t count = 0;
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = bk_mesh_tri_position(m, t, k), b = bk_mesh_tri_position(m, t, (k + 1) % 3);
      double da = bk_plane_distance(d->plane, m->positions[a]),
             db = bk_plane_distance(d->plane, m->positions[b]);
      if (!((da < -tol && db > tol) || (da > tol && db < -tol))) continue;
      bool inserted = false;
      bk_index_map_insert(&seen, bk_edge_key(a, b), 0, &inserted);
      count += inserted;
    }
  bk_index_map_free(&seen);
  return count;
}

/// Positions of `side` that are not (bitwise) source positions, sorted. Also
/// checks that the side has no two bitwise-equal positions.
static uint32_t new_positions(const bk_vec3* sorted_source, uint32_t source_count, const bk_mesh* side,
                              bk_vec3* out, const char* what) {
  bk_vec3* all = bk_alloc(sizeof(bk_vec3) * (side->position_count + 1u));
  memcpy(all, side->positions, sizeof(bk_vec3) * side->position_count);
  qsort(all, side->position_count, sizeof(bk_vec3), compare_vec3);
  for (uint32_t i = 1; i < side->position_count; ++i)
    ENSURE_MSG(compare_vec3(&all[i - 1], &all[i]) != 0, "%s: a side holds the same position twice", what);
  uint32_t count = 0;
  for (uint32_t i = 0; i < side->position_count; ++i)
    if (!bsearch(&all[i], sorted_source, source_count, sizeof(bk_vec3), compare_vec3)) out[count++] = all[i];
  free(all);
  return count;
}

/// Every cut edge adds exactly one position, the same bits on both sides.
static void check_new_positions(const bk_mesh* src, const bk_slice_def* d, const bk_mesh* below,
                                const bk_mesh* above, const char* what) {
  bk_vec3* source = bk_alloc(sizeof(bk_vec3) * (src->position_count + 1u));
  memcpy(source, src->positions, sizeof(bk_vec3) * src->position_count);
  qsort(source, src->position_count, sizeof(bk_vec3), compare_vec3);
  bk_vec3* fresh_below = bk_alloc(sizeof(bk_vec3) * (below->position_count + 1u));
  bk_vec3* fresh_above = bk_alloc(sizeof(bk_vec3) * (above->position_count + 1u));
  uint32_t nb = new_positions(source, src->position_count, below, fresh_below, what);
  uint32_t na = new_positions(source, src->position_count, above, fresh_above, what);
  uint32_t expected = crossed_edges(src, d);
  ENSURE_MSG(nb == expected && na == expected, "%s: %u crossed edges, new positions below %u above %u", what,
             expected, nb, na);
  ENSURE_MSG(nb == 0 || memcmp(fresh_below, fresh_above, sizeof(bk_vec3) * nb) == 0,
             "%s: new positions differ between the sides", what);
  free(source);
  free(fresh_below);
  free(fresh_above);
}

/// Slices with the shared slicer and runs every generic check: each
/// non-empty side valid and closed, caps correct, volumes and surface area
/// conserved, cap areas equal on both sides, an untouched side empty and the
/// other an exact copy, one new position per cut edge.
static void slice_checked(const bk_mesh* src, const bk_slice_def* d, const char* what, bk_mesh* below,
                          bk_mesh* above, side_report r[2]) {
  bk_error err = {{0}};
  bool ok = bk_slicer_slice(slicer, src, d, below, above, &err);
  ENSURE_MSG(ok, "%s: slice failed: %s", what, err.message);
  bk_mesh* sides[2] = {below, above};
  memset(r, 0, 2 * sizeof *r);
  int nonempty = 0;
  double total = 0.0;
  for (int s = 0; s < 2; ++s) {
    if (sides[s]->triangle_count == 0) {
      ENSURE_MSG(sides[s]->position_count == 0 && sides[s]->corner_count == 0, "%s: empty side has data",
                 what);
      continue;
    }
    r[s] = check_side(sides[s], d, s, what);
    total += r[s].volume;
    nonempty++;
  }
  ENSURE_MSG(nonempty >= 1, "%s: both sides empty", what);
  ENSURE_REL(total, bk_mesh_volume(src), 1e-12);
  ENSURE_REL(r[0].kept_area + r[1].kept_area, bk_mesh_area(src), 1e-12);
  if (nonempty == 1) {
    const bk_mesh* whole = below->triangle_count ? below : above;
    ENSURE_MSG(bk_mesh_hash(whole) == bk_mesh_hash(src), "%s: the untouched side is not a copy", what);
    ENSURE(r[0].cap_triangles + r[1].cap_triangles == 0);
  } else {
    ENSURE_REL(r[0].cap_area, r[1].cap_area, 1e-12);
    check_new_positions(src, d, below, above, what);
  }
}

// ---------------------------------------------------------------- cube analytics

/// Volume of the part of the cube [-0.5, 0.5]^3 where n.x < offset, by
/// inclusion-exclusion over the vertices (needs every |n_i| well above 0).
static double cube_volume_below(bk_plane p) {
  double nn[3] = {p.normal.x, p.normal.y, p.normal.z}, m[3];
  double d = p.offset + 0.5 * (nn[0] + nn[1] + nn[2]); // shift to [0, 1]^3
  for (int i = 0; i < 3; ++i) {
    m[i] = fabs(nn[i]);
    if (nn[i] < 0.0) d -= nn[i]; // mirror negative axes
  }
  double sum = 0.0;
  for (int v = 0; v < 8; ++v) {
    double s = d;
    int bits = 0;
    for (int i = 0; i < 3; ++i)
      if (v & (1 << i)) s -= m[i], bits++;
    if (s > 0.0) sum += (bits & 1 ? -1.0 : 1.0) * s * s * s;
  }
  return sum / (6.0 * m[0] * m[1] * m[2]);
}

/// Area of the cross-section of the cube [-0.5, 0.5]^3 with a plane (convex
/// polygon of the edge crossings and the vertices in the plane).
static double cube_section_area(bk_plane p) {
  bk_vec3 pts[20];
  int count = 0;
  for (int a = 0; a < 8; ++a) {
    bk_vec3 pa = bk_v3(a & 1 ? 0.5 : -0.5, a & 2 ? 0.5 : -0.5, a & 4 ? 0.5 : -0.5);
    double da = bk_plane_distance(p, pa);
    if (fabs(da) <= 1e-12) pts[count++] = pa;
    for (int bit = 1; bit < 8; bit <<= 1) {
      if (a & bit) continue;
      int b = a | bit;
      bk_vec3 pb = bk_v3(b & 1 ? 0.5 : -0.5, b & 2 ? 0.5 : -0.5, b & 4 ? 0.5 : -0.5);
      double db = bk_plane_distance(p, pb);
      if ((da < -1e-12 && db > 1e-12) || (da > 1e-12 && db < -1e-12))
        pts[count++] = bk_v3_lerp(pa, pb, da / (da - db));
    }
  }
  if (count < 3) return 0.0;
  bk_vec3 u, v, c = bk_v3(0, 0, 0);
  bk_plane_basis(p.normal, &u, &v);
  for (int i = 0; i < count; ++i)
    c = bk_v3_add(c, bk_v3_scale(pts[i], 1.0 / count));
  double x[20], y[20], angle[20];
  for (int i = 0; i < count; ++i) {
    x[i] = bk_v3_dot(bk_v3_sub(pts[i], c), u);
    y[i] = bk_v3_dot(bk_v3_sub(pts[i], c), v);
    angle[i] = atan2(y[i], x[i]);
  }
  for (int i = 1; i < count; ++i) // insertion sort by angle
    for (int j = i; j > 0 && angle[j - 1] > angle[j]; --j) {
      double t = angle[j], tx = x[j], ty = y[j];
      angle[j] = angle[j - 1], x[j] = x[j - 1], y[j] = y[j - 1];
      angle[j - 1] = t, x[j - 1] = tx, y[j - 1] = ty;
    }
  double area = 0.0;
  for (int i = 0; i < count; ++i)
    area += x[i] * y[(i + 1) % count] - x[(i + 1) % count] * y[i];
  return 0.5 * fabs(area);
}

/// Cuts the unit cube; below_volume < 0 means "use the analytic formula",
/// cap_area < 0 "use the analytic cross-section".
static void check_cube_cut(bk_plane plane, double below_volume, double cap_area, uint32_t tag,
                           const char* what) {
  bk_mesh cube, below, above;
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  bk_slice_def d = make_desc(plane, tag);
  side_report r[2];
  slice_checked(&cube, &d, what, &below, &above, r);
  if (below_volume < 0.0) below_volume = cube_volume_below(plane);
  if (below_volume <= 0.0) {
    ENSURE_MSG(below.triangle_count == 0, "%s: below should be empty", what);
  } else {
    ENSURE_MSG(below.triangle_count > 0, "%s: below is empty", what);
    ENSURE_REL(r[0].volume, below_volume, 1e-12);
  }
  if (below_volume >= 1.0) {
    ENSURE_MSG(above.triangle_count == 0, "%s: above should be empty", what);
  } else {
    ENSURE_MSG(above.triangle_count > 0, "%s: above is empty", what);
    ENSURE_REL(r[1].volume, 1.0 - below_volume, 1e-12);
  }
  if (below.triangle_count && above.triangle_count) {
    if (cap_area < 0.0) cap_area = cube_section_area(plane);
    ENSURE_REL(r[0].cap_area, cap_area, 1e-12);
    ENSURE_REL(r[1].cap_area, cap_area, 1e-12);
  }
  bk_mesh_free(&cube);
  bk_mesh_free(&below);
  bk_mesh_free(&above);
}

// ---------------------------------------------------------------- cube tests

static void test_analytics_self_check(void) {
  // The reference formulas agree with known cases.
  ENSURE_REL(cube_volume_below(plane_eq(1, 1, 1, 0)), 0.5, 1e-14);
  ENSURE_REL(cube_volume_below(plane_eq(1, 1, 1, 0.5)), 5.0 / 6.0, 1e-14);
  ENSURE_REL(cube_volume_below(plane_eq(-1, -1, -1, -0.5)), 1.0 / 6.0, 1e-14);
  ENSURE_REL(cube_section_area(plane_eq(1, 0, 0, 0.2)), 1.0, 1e-14);
  ENSURE_REL(cube_section_area(plane_eq(1, 1, 1, 0)), 3.0 * sqrt(3.0) / 4.0, 1e-14);
  ENSURE_REL(cube_section_area(plane_eq(1, 1, 0, 0)), sqrt(2.0), 1e-14);
}

static void test_axis_planes(void) {
  const double offsets[] = {0.0, 0.2, -0.37, 0.45};
  uint32_t tag = 100;
  for (int axis = 0; axis < 3; ++axis)
    for (int o = 0; o < 4; ++o)
      for (int s = -1; s <= 1; s += 2) {
        double c = offsets[o];
        double n[3] = {0, 0, 0};
        n[axis] = s;
        bk_plane plane = {bk_v3(n[0], n[1], n[2]), s * c};
        char what[96];
        snprintf(what, sizeof what, "cube axis %d sign %d at %g", axis, s, c);
        double below = s > 0 ? c + 0.5 : 0.5 - c;
        check_cube_cut(plane, below, 1.0, tag++, what);
      }
}

// Cube cut at x = 0.2: the 4 edges along x and the 4 face diagonals of the
// y and z faces cross the plane, so each side holds its 4 original corners
// plus 8 cut positions, bitwise the same on both sides.
static void test_cut_shares_positions(void) {
  bk_mesh cube, below, above;
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  bk_slice_def d = make_desc(plane_eq(1, 0, 0, 0.2), 7);
  side_report r[2];
  slice_checked(&cube, &d, "cube x = 0.2", &below, &above, r);
  ENSURE(crossed_edges(&cube, &d) == 8);
  ENSURE(below.position_count == 12 && above.position_count == 12);
  uint32_t below_original = 0, above_original = 0, below_cut = 0, above_cut = 0;
  for (uint32_t i = 0; i < 12; ++i) {
    below_original += below.positions[i].x == -0.5;
    above_original += above.positions[i].x == 0.5;
    below_cut += fabs(below.positions[i].x - 0.2) <= 1e-15;
    above_cut += fabs(above.positions[i].x - 0.2) <= 1e-15;
  }
  ENSURE(below_original == 4 && above_original == 4 && below_cut == 8 && above_cut == 8);
  // Cap: one planar region of area 1 on each side, tagged with the cut.
  ENSURE_REL(r[0].cap_area, 1.0, 1e-12);
  ENSURE_REL(r[1].cap_area, 1.0, 1e-12);
  ENSURE_REL(r[0].volume, 0.7, 1e-12);
  ENSURE_REL(r[1].volume, 0.3, 1e-12);
  // Outer surface kept: 1 + 4 * 0.7 below and 1 + 4 * 0.3 above.
  ENSURE_REL(r[0].kept_area, 3.8, 1e-12);
  ENSURE_REL(r[1].kept_area, 2.2, 1e-12);
  bk_mesh_free(&cube);
  bk_mesh_free(&below);
  bk_mesh_free(&above);
}

static void test_vertex_planes(void) {
  // Diagonal plane x + y = 0 holds 4 vertices (two vertical edges).
  check_cube_cut(plane_eq(1, 1, 0, 0), 0.5, sqrt(2.0), 200, "cube x + y = 0");
  check_cube_cut(plane_eq(-1, -1, 0, 0), 0.5, sqrt(2.0), 201, "cube -x - y = 0");
  // x + y + z = 0.5 passes through 3 vertices: the corner tetrahedron is cut off
  // along an equilateral triangle of side sqrt(2).
  check_cube_cut(plane_eq(1, 1, 1, 0.5), 5.0 / 6.0, sqrt(3.0) / 2.0, 202, "cube x + y + z = 0.5");
  check_cube_cut(plane_eq(-1, -1, -1, -0.5), 1.0 / 6.0, sqrt(3.0) / 2.0, 203, "cube -x - y - z = -0.5");
  check_cube_cut(plane_eq(1, -1, 1, -0.5), 1.0 / 6.0, sqrt(3.0) / 2.0, 204, "cube x - y + z = -0.5");
  // Through the centre, no vertex: a regular hexagon of side sqrt(2) / 2.
  check_cube_cut(plane_eq(1, 1, 1, 0), 0.5, 3.0 * sqrt(3.0) / 4.0, 205, "cube x + y + z = 0");
  // Touching a single corner: the whole cube on one side.
  check_cube_cut(plane_eq(1, 1, 1, 1.5), 1.0, 0.0, 206, "cube x + y + z = 1.5");
  check_cube_cut(plane_eq(-1, -1, -1, -1.5), 0.0, 0.0, 207, "cube -x - y - z = -1.5");
  check_cube_cut(plane_eq(1, 1, 1, -1.5), 0.0, 0.0, 208, "cube x + y + z = -1.5");
}

static void test_edge_planes(void) {
  // x + y = 1 touches the edge x = y = 0.5 only.
  check_cube_cut(plane_eq(1, 1, 0, 1), 1.0, 0.0, 300, "cube x + y = 1");
  check_cube_cut(plane_eq(-1, -1, 0, -1), 0.0, 0.0, 301, "cube -x - y = -1");
  // x - y = 0 contains the two opposite edges x = y = +-0.5.
  check_cube_cut(plane_eq(1, -1, 0, 0), 0.5, sqrt(2.0), 302, "cube x - y = 0");
  // x - 2y = -0.5 contains the edge x = y = 0.5 and leaves the x = -0.5 face
  // at y = 0: a 1 x sqrt(1.25) rectangle; below it is a prism of volume 1/4.
  check_cube_cut(plane_eq(1, -2, 0, -0.5), 0.25, sqrt(1.25), 303, "cube x - 2y = -0.5");
  check_cube_cut(plane_eq(-1, 2, 0, 0.5), 0.75, sqrt(1.25), 304, "cube -x + 2y = 0.5");
  // y + z = 0.5 runs parallel to the edge y = z = 0.5 and crosses the faces
  // y = 0.5 and z = 0.5 along their centre lines, cutting off a prism of 1/8.
  check_cube_cut(plane_eq(0, 1, 1, 0.5), 1.0 - 0.125, sqrt(0.5), 305, "cube y + z = 0.5");
}

static void test_face_planes(void) {
  uint32_t tag = 400;
  for (int axis = 0; axis < 3; ++axis)
    for (int face = -1; face <= 1; face += 2)
      for (int s = -1; s <= 1; s += 2) {
        double n[3] = {0, 0, 0};
        n[axis] = s;
        // Plane coordinate[axis] == face * 0.5, normal s * e_axis.
        bk_plane plane = {bk_v3(n[0], n[1], n[2]), s * face * 0.5};
        // Everything lies on the side away from the face plane.
        double below = (s * face > 0) ? 1.0 : 0.0;
        char what[96];
        snprintf(what, sizeof what, "cube face plane axis %d at %g, normal sign %d", axis, face * 0.5, s);
        check_cube_cut(plane, below, 0.0, tag++, what);
        // Within the tolerance of the face it is still the face plane.
        bk_plane near = plane;
        near.offset += 1e-12 * s * face;
        snprintf(what, sizeof what, "cube near-face plane axis %d at %g, normal sign %d", axis, face * 0.5,
                 s);
        check_cube_cut(near, below, 0.0, tag++, what);
      }
}

static void test_random_planes(void) {
  for (int i = 0; i < 200; ++i) {
    bk_vec3 point = bk_v3(lcg_range(-0.5, 0.5), lcg_range(-0.5, 0.5), lcg_range(-0.5, 0.5));
    bk_plane plane = plane_through(lcg_direction(), point);
    char what[96];
    snprintf(what, sizeof what, "cube random plane %d", i);
    bk_mesh cube, below, above;
    bk_shape_build(BK_SHAPE_CUBE, &cube);
    bk_slice_def d = make_desc(plane, 1000 + (uint32_t)i);
    d.texture_scale = i % 2 ? 0.25 : 0.0;
    side_report r[2];
    slice_checked(&cube, &d, what, &below, &above, r);
    // A plane through an interior point always cuts.
    ENSURE_MSG(below.triangle_count > 0 && above.triangle_count > 0, "%s: a side is empty", what);
    ENSURE_REL(r[0].volume + r[1].volume, 1.0, 1e-12);
    double section = cube_section_area(plane);
    ENSURE_REL(r[0].cap_area, section, 1e-12);
    ENSURE_REL(r[1].cap_area, section, 1e-12);
    bk_vec3 n = plane.normal;
    if (fmin(fabs(n.x), fmin(fabs(n.y), fabs(n.z))) >= 0.05) {
      // The formula loses digits to cancellation: absolute check.
      double expected = cube_volume_below(plane);
      ENSURE_SMALL(r[0].volume, expected, 1e-10);
      ENSURE_SMALL(r[1].volume, 1.0 - expected, 1e-10);
    }
    bk_mesh_free(&cube);
    bk_mesh_free(&below);
    bk_mesh_free(&above);
  }
}

// ---------------------------------------------------------------- attributes

// Unit-uv cube cut at x = 0.2: side faces whose u runs along +x get u = 0.7 at
// the cut, the -z face (u along -x) gets 0.3; v is 0 or 1 on cube edges and
// 0.7 or 0.3 on face diagonals; normals stay the flat face normals.
static void test_cube_attributes(void) {
  bk_mesh cube, below, above;
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  bk_slice_def d = make_desc(plane_eq(1, 0, 0, 0.2), 9);
  side_report r[2];
  slice_checked(&cube, &d, "cube x = 0.2 attributes", &below, &above, r);
  const bk_mesh* sides[2] = {&below, &above};
  for (int s = 0; s < 2; ++s) {
    const bk_mesh* m = sides[s];
    uint32_t seen = 0;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      if (m->materials[t] != BK_MATERIAL_OUTER) continue;
      for (int k = 0; k < 3; ++k) {
        const bk_corner* c = &m->corners[m->indices[3 * t + k]];
        if (fabs(m->positions[c->position].x - 0.2) > 1e-12) continue;
        seen++;
        bk_vec3 n = corner_normal(c);
        ENSURE(n.x == 0.0f);
        ENSURE((fabs(n.y) == 1.0 && n.z == 0.0) || (fabs(n.z) == 1.0 && n.y == 0.0));
        double expected_u = n.z == -1.0 ? 0.3 : 0.7;
        ENSURE_SMALL(c->uv[0], expected_u, 1e-6);
        double v = c->uv[1];
        ENSURE_MSG(fabs(v) <= 1e-6 || fabs(v - 1.0) <= 1e-6 || fabs(v - 0.3) <= 1e-6 || fabs(v - 0.7) <= 1e-6,
                   "cut corner v = %g", v);
      }
    }
    ENSURE(seen >= 8);
  }
  bk_mesh_free(&cube);
  bk_mesh_free(&below);
  bk_mesh_free(&above);
}

// Pillar cut at y = 0.5: side uvs are (perimeter length, height), so every cut
// corner on a side face has v = 0.5 and u within its face's range, and keeps
// the flat face normal.
static void test_pillar_attributes(void) {
  bk_mesh pillar, below, above;
  bk_shape_build(BK_SHAPE_PILLAR, &pillar);
  bk_slice_def d = make_desc(plane_eq(0, 1, 0, 0.5), 11);
  side_report r[2];
  slice_checked(&pillar, &d, "pillar y = 0.5 attributes", &below, &above, r);
  const double radius = 0.25, edge = 2.0 * radius * sin(PI / 8.0), start = PI / 8.0;
  const bk_mesh* sides[2] = {&below, &above};
  for (int s = 0; s < 2; ++s) {
    const bk_mesh* m = sides[s];
    uint32_t seen = 0;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      if (m->materials[t] != BK_MATERIAL_OUTER) continue;
      for (int k = 0; k < 3; ++k) {
        const bk_corner* c = &m->corners[m->indices[3 * t + k]];
        if (fabs(m->positions[c->position].y - 0.5) > 1e-12) continue;
        seen++;
        bk_vec3 n = corner_normal(c);
        ENSURE_SMALL(n.y, 0.0, 1e-6);
        // Face j has its normal at angle start + (j + 0.5) * 45 degrees.
        double angle = atan2(-n.z, n.x) - start;
        if (angle < 0.0) angle += 2.0 * PI;
        int j = (int)lround(angle / (PI / 4.0) - 0.5);
        ENSURE(j >= 0 && j < 8);
        double mid = start + (j + 0.5) * PI / 4.0;
        ENSURE_SMALL(n.x, cos(mid), 1e-6);
        ENSURE_SMALL(n.z, -sin(mid), 1e-6);
        ENSURE_SMALL(c->uv[1], 0.5, 1e-6);
        ENSURE(c->uv[0] >= edge * j - 1e-6 && c->uv[0] <= edge * (j + 1) + 1e-6);
      }
    }
    ENSURE(seen >= 16);
  }
  bk_mesh_free(&pillar);
  bk_mesh_free(&below);
  bk_mesh_free(&above);
}

// Torus cut at y = 0.1 (between tube rings 0 and 1 outside, 9 and 10 inside):
// the cut corners' v lies between those rings' v, their u matches the angle
// around the ring within one segment, and the normal's y is between the
// endpoint normals' (0 and sin 18 degrees).
static void test_torus_attributes(void) {
  bk_mesh torus, below, above;
  bk_shape_build(BK_SHAPE_TORUS, &torus);
  bk_slice_def d = make_desc(plane_eq(0, 1, 0, 0.1), 12);
  side_report r[2];
  slice_checked(&torus, &d, "torus y = 0.1 attributes", &below, &above, r);
  const bk_mesh* sides[2] = {&below, &above};
  for (int s = 0; s < 2; ++s) {
    const bk_mesh* m = sides[s];
    uint32_t seen = 0;
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      if (m->materials[t] != BK_MATERIAL_OUTER) continue;
      for (int k = 0; k < 3; ++k) {
        const bk_corner* c = &m->corners[m->indices[3 * t + k]];
        bk_vec3 p = m->positions[c->position];
        if (fabs(p.y - 0.1) > 1e-12) continue;
        seen++;
        double rho = sqrt(p.x * p.x + p.z * p.z);
        bool outside = rho > 1.0;
        double v = c->uv[1];
        if (outside)
          ENSURE_MSG(v >= -1e-6 && v <= 1.0 / 20.0 + 1e-6, "outside cut corner v = %g", v);
        else
          ENSURE_MSG(v >= 9.0 / 20.0 - 1e-6 && v <= 10.0 / 20.0 + 1e-6, "inside cut corner v = %g", v);
        double ny = c->normal[1];
        ENSURE_MSG(ny >= -1e-6 && ny <= sin(PI / 10.0) + 1e-6, "cut corner normal y = %g", ny);
        double phi = atan2(-p.z, p.x), from_u = c->uv[0] * 2.0 * PI / 3.0;
        double diff = remainder(phi - from_u, 2.0 * PI);
        ENSURE_MSG(fabs(diff) <= 2.0 * PI / 20.0 + 1e-5, "cut corner u = %g at angle %g", c->uv[0], phi);
      }
    }
    ENSURE(seen >= 40);
  }
  bk_mesh_free(&torus);
  bk_mesh_free(&below);
  bk_mesh_free(&above);
}

// ---------------------------------------------------------------- other shapes

static void check_shape_cut(bk_shape shape, bk_plane plane, double below_volume, double above_volume,
                            double cap_area, uint32_t tag) {
  bk_mesh mesh, below, above;
  bk_shape_build(shape, &mesh);
  char what[128];
  snprintf(what, sizeof what, "%s plane (%g %g %g) %g", bk_shape_name(shape), plane.normal.x, plane.normal.y,
           plane.normal.z, plane.offset);
  bk_slice_def d = make_desc(plane, tag);
  side_report r[2];
  slice_checked(&mesh, &d, what, &below, &above, r);
  if (below_volume > 0.0) ENSURE_REL(r[0].volume, below_volume, 1e-12);
  if (above_volume > 0.0) ENSURE_REL(r[1].volume, above_volume, 1e-12);
  if (cap_area > 0.0) {
    ENSURE_REL(r[0].cap_area, cap_area, 1e-12);
    ENSURE_REL(r[1].cap_area, cap_area, 1e-12);
  }
  bk_mesh_free(&mesh);
  bk_mesh_free(&below);
  bk_mesh_free(&above);
}

static void test_shapes(void) {
  // Pillar: regular octagon of radius 0.25 (flat faces along x and z), 2 tall.
  const double r = 0.25, octagon = 4.0 * r * r * sin(PI / 4.0);
  check_shape_cut(BK_SHAPE_PILLAR, plane_eq(0, 1, 0, 1.0), octagon, octagon, octagon, 1);
  check_shape_cut(BK_SHAPE_PILLAR, plane_eq(0, -1, 0, -0.3), 1.7 * octagon, 0.3 * octagon, octagon, 2);
  // Through the axis (and the cap centres): two equal halves, a rectangle of
  // the octagon's width across flats by the height.
  check_shape_cut(BK_SHAPE_PILLAR, plane_eq(1, 0, 0, 0.0), octagon, octagon, 2.0 * 2.0 * r * cos(PI / 8.0),
                  3);
  check_shape_cut(BK_SHAPE_PILLAR, plane_eq(1, 1, 0.3, 0.4), 0, 0, 0, 4);
  check_shape_cut(BK_SHAPE_PILLAR, plane_eq(0.1, 1, -0.2, 1.9), 0, 0, 0, 5);
  // Wall [-1, 1] x [0, 1.2] x [-0.1, 0.1].
  check_shape_cut(BK_SHAPE_WALL, plane_eq(1, 0, 0, 0.3), 1.3 * 1.2 * 0.2, 0.7 * 1.2 * 0.2, 1.2 * 0.2, 6);
  check_shape_cut(BK_SHAPE_WALL, plane_eq(0, 1, 0, 0.5), 2.0 * 0.5 * 0.2, 2.0 * 0.7 * 0.2, 2.0 * 0.2, 7);
  check_shape_cut(BK_SHAPE_WALL, plane_eq(0, 0, 1, 0.0), 2.0 * 1.2 * 0.1, 2.0 * 1.2 * 0.1, 2.0 * 1.2, 8);
  check_shape_cut(BK_SHAPE_WALL, plane_eq(1, 1, 0.2, 0.6), 0, 0, 0, 9);
  // Slab [-0.6, 0.6] x [0, 0.15] x [-0.4, 0.4].
  check_shape_cut(BK_SHAPE_SLAB, plane_eq(0, 0, 1, 0.1), 1.2 * 0.15 * 0.5, 1.2 * 0.15 * 0.3, 1.2 * 0.15, 10);
  check_shape_cut(BK_SHAPE_SLAB, plane_eq(0.3, 1, 0.1, 0.07), 0, 0, 0, 11);
  // Torus (ring in the xz plane around +y): y = 0 holds the outer and inner
  // equator rings, so the cap is the annulus between two regular 48-gons.
  const double sector = 24.0 * sin(PI / 24.0); // 48-gon area / r^2
  check_shape_cut(BK_SHAPE_TORUS, plane_eq(0, 1, 0, 0.0), 0, 0, sector * (1.35 * 1.35 - 0.65 * 0.65), 12);
  // x = 0 holds two tube rings: two 24-gons of radius 0.35.
  const double tube = 12.0 * sin(PI / 12.0); // 24-gon area / r^2
  check_shape_cut(BK_SHAPE_TORUS, plane_eq(1, 0, 0, 0.0), 0, 0, 2.0 * tube * 0.35 * 0.35, 13);
  check_shape_cut(BK_SHAPE_TORUS, plane_eq(1, 0, 0, 0.1), 0, 0, 0, 14);
  check_shape_cut(BK_SHAPE_TORUS, plane_eq(1, 0, 0, 1.2), 0, 0, 0, 15);
  check_shape_cut(BK_SHAPE_TORUS, plane_eq(0.3, 1, -0.5, 0.05), 0, 0, 0, 16);
  check_shape_cut(BK_SHAPE_TORUS, plane_eq(0, 1, 0, 0.3), 0, 0, 0, 17);
  // Eggshell (hollow, y from 0 to 0.6): through the equator ring, through the
  // poles, and oblique.
  check_shape_cut(BK_SHAPE_EGGSHELL, plane_eq(0, 1, 0, 0.3), 0, 0, 0, 18);
  check_shape_cut(BK_SHAPE_EGGSHELL, plane_eq(0, 1, 0, 0.2), 0, 0, 0, 19);
  check_shape_cut(BK_SHAPE_EGGSHELL, plane_eq(1, 0, 0, 0.0), 0, 0, 0, 20);
  check_shape_cut(BK_SHAPE_EGGSHELL, plane_eq(1, 0.7, 0.2, 0.25), 0, 0, 0, 21);
  check_shape_cut(BK_SHAPE_EGGSHELL, plane_eq(0, 1, 0, 0.59), 0, 0, 0, 22);
  // Random planes through points near the middle of each shape.
  const bk_shape shapes[] = {BK_SHAPE_TORUS, BK_SHAPE_EGGSHELL, BK_SHAPE_PILLAR, BK_SHAPE_WALL,
                             BK_SHAPE_SLAB};
  for (int s = 0; s < 5; ++s) {
    bk_mesh mesh;
    bk_shape_build(shapes[s], &mesh);
    bk_aabb box = bk_mesh_bounds(&mesh);
    bk_mesh_free(&mesh);
    for (int i = 0; i < 20; ++i) {
      bk_vec3 p = bk_v3(lcg_range(box.min.x, box.max.x), lcg_range(box.min.y, box.max.y),
                        lcg_range(box.min.z, box.max.z));
      p = bk_v3_lerp(bk_v3_scale(bk_v3_add(box.min, box.max), 0.5), p, 0.8);
      check_shape_cut(shapes[s], plane_through(lcg_direction(), p), 0, 0, 0, 100 + (uint32_t)i);
    }
  }
}

// ---------------------------------------------------------------- recursion, planar faces, errors

// Three axis cuts in turn give 8 octants of volume 1/8, each closed, with a
// 1/4 cap from each cut (tags preserved through later cuts) and 3/4 of outer
// surface.
static void test_recursive_octants(void) {
  bk_mesh pieces[8], next[8];
  uint32_t count = 1;
  bk_shape_build(BK_SHAPE_CUBE, &pieces[0]);
  for (uint32_t axis = 0; axis < 3; ++axis) {
    double n[3] = {0, 0, 0};
    n[axis] = 1.0;
    bk_slice_def d = make_desc((bk_plane){bk_v3(n[0], n[1], n[2]), 0.0}, axis + 1);
    for (uint32_t i = 0; i < count; ++i) {
      side_report r[2];
      char what[64];
      snprintf(what, sizeof what, "octant cut %u piece %u", axis, i);
      slice_checked(&pieces[i], &d, what, &next[2 * i], &next[2 * i + 1], r);
      ENSURE_REL(r[0].volume, 0.5 * bk_mesh_volume(&pieces[i]), 1e-12);
      bk_mesh_free(&pieces[i]);
    }
    count *= 2;
    memcpy(pieces, next, sizeof(bk_mesh) * count);
  }
  for (uint32_t i = 0; i < 8; ++i) {
    ENSURE(bk_mesh_is_closed(&pieces[i]));
    ENSURE_REL(bk_mesh_volume(&pieces[i]), 0.125, 1e-12);
    double by_tag[4] = {0, 0, 0, 0};
    for (uint32_t t = 0; t < pieces[i].triangle_count; ++t) {
      bk_vec3 cross;
      double area = triangle_area(&pieces[i], t, &cross);
      uint32_t tag = pieces[i].tags[t];
      ENSURE(tag <= 3);
      ENSURE((tag == 0) == (pieces[i].materials[t] == BK_MATERIAL_OUTER));
      by_tag[tag] += area;
    }
    ENSURE_REL(by_tag[0], 0.75, 1e-12);
    for (int k = 1; k <= 3; ++k)
      ENSURE_REL(by_tag[k], 0.25, 1e-12);
    bk_mesh_free(&pieces[i]);
  }
}

static void add_box(bk_mesh* m, bk_vec3 lo, bk_vec3 hi) {
  bk_mesh box;
  bk_shape_build(BK_SHAPE_CUBE, &box);
  for (uint32_t i = 0; i < box.position_count; ++i) {
    bk_vec3* p = &box.positions[i];
    *p = bk_v3(p->x < 0 ? lo.x : hi.x, p->y < 0 ? lo.y : hi.y, p->z < 0 ? lo.z : hi.z);
  }
  bk_mesh_append(m, &box);
  bk_mesh_free(&box);
}

// Two separate boxes touching along part of the plane z = 0: every triangle
// lies on one side or in the plane, the in-plane faces go with the solid they
// bound, and no cap is needed.
static void test_faces_in_plane(void) {
  bk_mesh two = {0}, below, above;
  add_box(&two, bk_v3(-1, -1, -1), bk_v3(1, 1, 0));
  add_box(&two, bk_v3(-0.5, -0.5, 0), bk_v3(0.5, 0.5, 1));
  for (int s = -1; s <= 1; s += 2) {
    bk_slice_def d = make_desc((bk_plane){bk_v3(0, 0, s), 0.0}, 5);
    side_report r[2];
    slice_checked(&two, &d, "touching boxes", &below, &above, r);
    double big = 4.0, small = 1.0;
    ENSURE_REL(r[0].volume, s > 0 ? big : small, 1e-12);
    ENSURE_REL(r[1].volume, s > 0 ? small : big, 1e-12);
    ENSURE(r[0].cap_triangles == 0 && r[1].cap_triangles == 0);
    ENSURE(below.triangle_count == 12 && above.triangle_count == 12);
    bk_mesh_free(&below);
    bk_mesh_free(&above);
  }
  bk_mesh_free(&two);
}

// A cube with one triangle missing cannot be capped where the cut crosses the
// hole: the slice fails with a message and leaves both outputs empty; the
// slicer keeps working afterwards.
static void test_open_mesh_fails(void) {
  bk_mesh cube, below, above;
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  // Find a triangle crossing x = 0.2 and drop it (swap with the last).
  bk_slice_def d = make_desc(plane_eq(1, 0, 0, 0.2), 3);
  uint32_t victim = UINT32_MAX;
  for (uint32_t t = 0; t < cube.triangle_count && victim == UINT32_MAX; ++t) {
    double lo = 1, hi = -1;
    for (int k = 0; k < 3; ++k) {
      double x = cube.positions[bk_mesh_tri_position(&cube, t, k)].x;
      lo = fmin(lo, x), hi = fmax(hi, x);
    }
    if (lo < 0.2 && hi > 0.2) victim = t;
  }
  ENSURE(victim != UINT32_MAX);
  uint32_t last = cube.triangle_count - 1;
  memcpy(&cube.indices[3 * victim], &cube.indices[3 * last], 3 * sizeof(uint32_t));
  cube.triangle_count--;
  ENSURE(!bk_mesh_is_closed(&cube));
  bk_error err = {{0}};
  ENSURE(!bk_slicer_slice(slicer, &cube, &d, &below, &above, &err));
  ENSURE_MSG(strstr(err.message, "closed loops") != NULL, "message: %s", err.message);
  ENSURE(below.triangle_count == 0 && below.positions == NULL && below.corners == NULL);
  ENSURE(above.triangle_count == 0 && above.positions == NULL && above.corners == NULL);
  bk_mesh_free(&cube);
  check_cube_cut(plane_eq(1, 0, 0, 0.2), 0.7, 1.0, 4, "cube after a failed slice");
}

// The same input sliced by the shared slicer and by a fresh one gives
// bit-identical sides.
static void test_deterministic(void) {
  bk_mesh torus, b1, a1, b2, a2;
  bk_shape_build(BK_SHAPE_TORUS, &torus);
  bk_slice_def d = make_desc(plane_eq(0.3, 0.9, -0.2, 0.05), 17);
  bk_error err = {{0}};
  ENSURE(bk_slicer_slice(slicer, &torus, &d, &b1, &a1, &err));
  bk_slicer* fresh = bk_slicer_create();
  ENSURE(fresh);
  ENSURE(bk_slicer_slice(fresh, &torus, &d, &b2, &a2, &err));
  bk_slicer_destroy(fresh);
  bk_slicer_destroy(NULL);
  ENSURE(bk_mesh_hash(&b1) == bk_mesh_hash(&b2));
  ENSURE(bk_mesh_hash(&a1) == bk_mesh_hash(&a2));
  bk_mesh_free(&torus);
  bk_mesh_free(&b1);
  bk_mesh_free(&a1);
  bk_mesh_free(&b2);
  bk_mesh_free(&a2);
}

// Caps may only use the loop vertices, and cut points on a face boundary are
// collinear with the face's corners (the cube cut at x = 0 has the four face
// diagonal midpoints on the cap square's sides). A zero-area cap triangle
// spanning such a straight-angle vertex is a geometric T-junction: the next
// cut through its long edge creates a second position at the same point.
static void test_caps_have_no_slivers(void) {
  bk_mesh cube, below, above;
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  for (int axis = 0; axis < 3; ++axis) {
    double n[3] = {0, 0, 0};
    n[axis] = 1.0;
    bk_slice_def d = make_desc((bk_plane){bk_v3(n[0], n[1], n[2]), 0.0}, 1);
    side_report r[2];
    slice_checked(&cube, &d, "cube through the centre", &below, &above, r);
    const bk_mesh* sides[2] = {&below, &above};
    for (int s = 0; s < 2; ++s)
      for (uint32_t t = 0; t < sides[s]->triangle_count; ++t) {
        if (sides[s]->materials[t] != BK_MATERIAL_INTERIOR) continue;
        bk_vec3 cross;
        double area = triangle_area(sides[s], t, &cross);
        ENSURE_MSG(area > 1e-6, "axis %d side %d: cap triangle %u has area %g", axis, s, t, area);
      }
    bk_mesh_free(&below);
    bk_mesh_free(&above);
  }
  bk_mesh_free(&cube);
}

// Recursive cutting: each side of a random cut of the cube cut again through
// its centroid by random planes; every slice succeeds and conserves volume.
static void test_random_recursive(void) {
  for (int i = 0; i < 50; ++i) {
    bk_vec3 point = bk_v3(lcg_range(-0.4, 0.4), lcg_range(-0.4, 0.4), lcg_range(-0.4, 0.4));
    bk_mesh cube, halves[2];
    bk_shape_build(BK_SHAPE_CUBE, &cube);
    bk_slice_def d = make_desc(plane_through(lcg_direction(), point), 1);
    side_report r[2];
    char what[96];
    snprintf(what, sizeof what, "random recursive %d", i);
    slice_checked(&cube, &d, what, &halves[0], &halves[1], r);
    for (int h = 0; h < 2; ++h)
      for (int j = 0; j < 4; ++j) {
        bk_vec3 centroid = bk_moments_to_mass(bk_mesh_moments(&halves[h])).centroid;
        bk_slice_def d2 = make_desc(plane_through(lcg_direction(), centroid), 2);
        bk_mesh below, above;
        snprintf(what, sizeof what, "random recursive %d half %d cut %d", i, h, j);
        slice_checked(&halves[h], &d2, what, &below, &above, r);
        bk_mesh_free(&below);
        bk_mesh_free(&above);
      }
    bk_mesh_free(&cube);
    bk_mesh_free(&halves[0]);
    bk_mesh_free(&halves[1]);
  }
}

int main(void) {
  slicer = bk_slicer_create();
  ENSURE(slicer);
  RUN(test_analytics_self_check);
  RUN(test_axis_planes);
  RUN(test_cut_shares_positions);
  RUN(test_vertex_planes);
  RUN(test_edge_planes);
  RUN(test_face_planes);
  RUN(test_random_planes);
  RUN(test_cube_attributes);
  RUN(test_pillar_attributes);
  RUN(test_torus_attributes);
  RUN(test_shapes);
  RUN(test_faces_in_plane);
  RUN(test_open_mesh_fails);
  RUN(test_deterministic);
  RUN(test_caps_have_no_slivers);
  RUN(test_recursive_octants);
  RUN(test_random_recursive);
  bk_slicer_destroy(slicer);
  return 0;
}
