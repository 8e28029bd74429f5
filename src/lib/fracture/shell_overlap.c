// Overlapping or touching closed shells: two solids of one source that
// interpenetrate or nest (a cube exported inside a cube), or whose surfaces
// meet along a line or over an area (a box standing on a plinth, each its
// own closed shell). A plane through both crosses them in cross-sections
// that overlap, or that share edges or parts of them; no cap can close
// those, so such shells are fractured each on its own (see
// bk_mesh_tree_build).
//
// Two closed shells overlap when (a) their surfaces cross, or (b) one lies
// inside the other without crossing. (a) is found by an edge of one crossing
// a triangle of the other strictly: its ends more than a tolerance on either
// side of the triangle's plane and the crossing point more than the tolerance
// inside all three edges. (b), once (a) found nothing, is decided by a
// vertex of a shell: either all of it is inside the other or none is, and
// the winding number of the other (cavities included, so a solid inside an
// eggshell's cavity is outside it) tells which; vertices on the other's
// surface (within the tolerance of one of its triangles: their winding
// number is 1/2 only up to rounding) do not count, so up to 32 are tried
// (which also catches crossings (a) skipped as degenerate, such as two cubes
// whose edges cross each other's faces exactly on a face's diagonal, when a
// corner of one lies inside the other). (c), once (a) and (b) found
// nothing, looks for surfaces in contact: an edge of one lying in a triangle
// of the other (both ends within the tolerance of its plane) over a length
// of more than 1e-6 of the pair's size. That finds faces coincident in
// whole or in part (an edge of each runs over the other's face) and edges
// lying on faces or edges; shells touching at single points are left alone,
// since a plane meets such a point only by chance. Coincident triangles facing the same way with an
// area in common are still an overlap (the solids share the volume behind
// them); otherwise the shells only touch. Only exactly degenerate overlaps
// escape all three (every crossing through an edge or a vertex of the
// other, no vertex strictly inside, no faces in common); the build then cuts
// them together as before and its shortfall reports what could not be
// capped.
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"

static bool boxes_overlap(bk_aabb a, bk_aabb b) {
  return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
         a.min.z <= b.max.z && b.min.z <= a.max.z;
}

static bk_aabb triangle_box(const bk_mesh* m, uint32_t t) {
  bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
  bk_vec3 b = m->positions[bk_mesh_tri_position(m, t, 1)];
  bk_vec3 c = m->positions[bk_mesh_tri_position(m, t, 2)];
  return (bk_aabb){bk_v3_min(a, bk_v3_min(b, c)), bk_v3_max(a, bk_v3_max(b, c))};
}

// Does segment pq cross triangle abc strictly (see the top)? `eps` is a length.
static bool segment_crosses(bk_vec3 p, bk_vec3 q, bk_vec3 a, bk_vec3 b, bk_vec3 c, double eps, bk_vec3* at) {
  bk_vec3 n = bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a));
  double len = bk_v3_length(n);
  if (!(len > 0.0)) return false;
  double dp = bk_v3_dot(n, bk_v3_sub(p, a)), dq = bk_v3_dot(n, bk_v3_sub(q, a));
  double tol = eps * len;
  if (!((dp > tol && dq < -tol) || (dp < -tol && dq > tol))) return false;
  bk_vec3 x = bk_v3_add(p, bk_v3_scale(bk_v3_sub(q, p), dp / (dp - dq)));
  const bk_vec3 corner[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    bk_vec3 e0 = corner[k], e1 = corner[(k + 1) % 3];
    bk_vec3 edge = bk_v3_sub(e1, e0);
    // n . (edge x (x - e0)) = |n| |edge| (distance of x inside the edge's line)
    if (!(bk_v3_dot(n, bk_v3_cross(edge, bk_v3_sub(x, e0))) > tol * bk_v3_length(edge))) return false;
  }
  *at = x;
  return true;
}

static bool triangles_cross(const bk_mesh* ma, uint32_t ta, const bk_mesh* mb, uint32_t tb, double eps,
                            bk_vec3* at) {
  bk_vec3 a[3], b[3];
  for (uint32_t k = 0; k < 3; ++k) {
    a[k] = ma->positions[bk_mesh_tri_position(ma, ta, k)];
    b[k] = mb->positions[bk_mesh_tri_position(mb, tb, k)];
  }
  for (int k = 0; k < 3; ++k) {
    if (segment_crosses(a[k], a[(k + 1) % 3], b[0], b[1], b[2], eps, at)) return true;
    if (segment_crosses(b[k], b[(k + 1) % 3], a[0], a[1], a[2], eps, at)) return true;
  }
  return false;
}

// What a pair of shells, or of their triangles, turned out to be.
typedef enum contact_kind { CONTACT_NONE = 0, CONTACT_TOUCH, CONTACT_OVERLAP } contact_kind;

// The length a contact must have to count (edges through a single point are
// clipped to about the tolerance), and the area coincident triangles facing
// the same way must share to be an overlap, in units of the tolerance.
#define CONTACT_LENGTH 1000.0

// The part of segment pq lying in triangle abc (within `eps` of its plane and
// of its edges), as parameters [*t0, *t1] along pq: false when pq is not in
// the plane or misses the triangle.
static bool segment_in_triangle(bk_vec3 p, bk_vec3 q, const bk_vec3 corner[3], double eps, double* t0,
                                double* t1) {
  bk_vec3 n = bk_v3_cross(bk_v3_sub(corner[1], corner[0]), bk_v3_sub(corner[2], corner[0]));
  double len = bk_v3_length(n);
  if (!(len > 0.0)) return false;
  double tol = eps * len;
  if (!(fabs(bk_v3_dot(n, bk_v3_sub(p, corner[0]))) <= tol &&
        fabs(bk_v3_dot(n, bk_v3_sub(q, corner[0]))) <= tol))
    return false;
  *t0 = 0.0, *t1 = 1.0;
  for (int k = 0; k < 3; ++k) {
    bk_vec3 e0 = corner[k], edge = bk_v3_sub(corner[(k + 1) % 3], e0);
    // Inside the edge's line, plus the tolerance, at either end (as in segment_crosses).
    double slack = tol * bk_v3_length(edge);
    double sp = bk_v3_dot(n, bk_v3_cross(edge, bk_v3_sub(p, e0))) + slack;
    double sq = bk_v3_dot(n, bk_v3_cross(edge, bk_v3_sub(q, e0))) + slack;
    if (sp < 0.0 && sq < 0.0) return false;
    if (sp < 0.0) *t0 = fmax(*t0, sp / (sp - sq));
    if (sq < 0.0) *t1 = fmin(*t1, sp / (sp - sq));
  }
  return *t1 > *t0;
}

// Area of the part of triangle `a` inside triangle `b`, both in b's plane
// (Sutherland-Hodgman: each of b's edges clips the polygon, which stays
// convex and gains at most one corner per edge).
static double common_area(const bk_vec3 a[3], const bk_vec3 b[3]) {
  bk_vec3 n = bk_v3_cross(bk_v3_sub(b[1], b[0]), bk_v3_sub(b[2], b[0]));
  bk_vec3 polygon[2][8];
  uint32_t count = 3;
  memcpy(polygon[0], a, sizeof(bk_vec3) * 3);
  for (int k = 0; k < 3; ++k) {
    const bk_vec3* in = polygon[k % 2];
    bk_vec3* out = polygon[(k + 1) % 2];
    bk_vec3 e0 = b[k], edge = bk_v3_sub(b[(k + 1) % 3], e0);
    uint32_t kept = 0;
    for (uint32_t i = 0; i < count; ++i) {
      bk_vec3 p = in[i], q = in[(i + 1) % count];
      double sp = bk_v3_dot(n, bk_v3_cross(edge, bk_v3_sub(p, e0)));
      double sq = bk_v3_dot(n, bk_v3_cross(edge, bk_v3_sub(q, e0)));
      if (sp >= 0.0) out[kept++] = p;
      if ((sp >= 0.0) != (sq >= 0.0))
        out[kept++] = bk_v3_add(p, bk_v3_scale(bk_v3_sub(q, p), sp / (sp - sq)));
    }
    count = kept;
  }
  const bk_vec3* clipped = polygon[1]; // after three clips
  bk_vec3 twice = {0, 0, 0};
  for (uint32_t i = 1; i + 1 < count; ++i)
    twice = bk_v3_add(twice,
                      bk_v3_cross(bk_v3_sub(clipped[i], clipped[0]), bk_v3_sub(clipped[i + 1], clipped[0])));
  double len = bk_v3_length(n);
  return len > 0.0 ? 0.5 * fabs(bk_v3_dot(twice, n)) / len : 0.0;
}

// (c) for one pair of triangles: does an edge of either lie in the other
// over more than CONTACT_LENGTH tolerances? *at is the middle of that part.
static contact_kind triangles_touch(const bk_mesh* ma, uint32_t ta, const bk_mesh* mb, uint32_t tb,
                                    double eps, bk_vec3* at) {
  bk_vec3 a[3], b[3];
  for (uint32_t k = 0; k < 3; ++k) {
    a[k] = ma->positions[bk_mesh_tri_position(ma, ta, k)];
    b[k] = mb->positions[bk_mesh_tri_position(mb, tb, k)];
  }
  bool touch = false;
  for (int k = 0; k < 6 && !touch; ++k) {
    const bk_vec3* edge_of = k < 3 ? a : b;
    const bk_vec3* other = k < 3 ? b : a;
    bk_vec3 p = edge_of[k % 3], q = edge_of[(k + 1) % 3];
    double t0 = 0.0, t1 = 0.0;
    if (!segment_in_triangle(p, q, other, eps, &t0, &t1)) continue;
    if ((t1 - t0) * bk_v3_length(bk_v3_sub(q, p)) <= CONTACT_LENGTH * eps) continue;
    *at = bk_v3_add(p, bk_v3_scale(bk_v3_sub(q, p), 0.5 * (t0 + t1)));
    touch = true;
  }
  if (!touch) return CONTACT_NONE;
  // In one plane, facing the same way, with an area in common, the solids
  // behind them overlap. (A triangle meeting the other only along an edge,
  // even facing about the same way, such as a wedge's slope rising from a
  // face, is a touch.)
  bk_vec3 na = bk_v3_cross(bk_v3_sub(a[1], a[0]), bk_v3_sub(a[2], a[0]));
  bk_vec3 nb = bk_v3_cross(bk_v3_sub(b[1], b[0]), bk_v3_sub(b[2], b[0]));
  double tol = eps * bk_v3_length(nb);
  bool coplanar = true;
  for (uint32_t k = 0; k < 3; ++k)
    coplanar = coplanar && fabs(bk_v3_dot(nb, bk_v3_sub(a[k], b[0]))) <= tol;
  double length = CONTACT_LENGTH * eps;
  if (coplanar && bk_v3_dot(na, nb) > 0.0 && common_area(a, b) > length * length) return CONTACT_OVERLAP;
  return CONTACT_TOUCH;
}

static contact_kind triangles_cross_kind(const bk_mesh* ma, uint32_t ta, const bk_mesh* mb, uint32_t tb,
                                         double eps, bk_vec3* at) {
  return triangles_cross(ma, ta, mb, tb, eps, at) ? CONTACT_OVERLAP : CONTACT_NONE;
}

typedef contact_kind (*triangle_test)(const bk_mesh* ma, uint32_t ta, const bk_mesh* mb, uint32_t tb,
                                      double eps, bk_vec3* at);

typedef struct sweep_item {
  bk_aabb box;
  uint32_t shell; // 0 or 1
  uint32_t triangle;
} sweep_item;

static int compare_items(const void* pa, const void* pb) {
  const sweep_item *a = pa, *b = pb;
  if (a->box.min.x != b->box.min.x) return a->box.min.x < b->box.min.x ? -1 : 1;
  if (a->shell != b->shell) return a->shell < b->shell ? -1 : 1;
  return a->triangle < b->triangle ? -1 : (a->triangle > b->triangle);
}

static bk_aabb grown(bk_aabb box, double by) {
  bk_vec3 d = {by, by, by};
  return (bk_aabb){bk_v3_sub(box.min, d), bk_v3_add(box.max, d)};
}

// `test` on every pair of triangles, one of each shell, whose boxes grown by
// `grow` meet: triangles outside the other shell's box are dropped, the rest
// swept along x. Returns the first overlap found, else whether any pair
// touched (*at the first place found).
static contact_kind sweep_pairs(const bk_mesh* const shell[2], const bk_aabb box[2], double eps, double grow,
                                triangle_test test, bk_vec3* at) {
  sweep_item* items =
      bk_alloc(sizeof(sweep_item) * ((size_t)shell[0]->triangle_count + shell[1]->triangle_count + 1));
  uint32_t count = 0;
  for (uint32_t s = 0; s < 2; ++s)
    for (uint32_t t = 0; t < shell[s]->triangle_count; ++t) {
      bk_aabb tb = grown(triangle_box(shell[s], t), grow);
      if (boxes_overlap(tb, box[1 - s])) items[count++] = (sweep_item){tb, s, t};
    }
  bk_sort(items, count, sizeof *items, compare_items);
  contact_kind found = CONTACT_NONE;
  for (uint32_t i = 0; i < count && found != CONTACT_OVERLAP; ++i)
    for (uint32_t j = i + 1; j < count && items[j].box.min.x <= items[i].box.max.x; ++j) {
      if (items[j].shell == items[i].shell || !boxes_overlap(items[i].box, items[j].box)) continue;
      const sweep_item* a = items[i].shell == 0 ? &items[i] : &items[j];
      const sweep_item* b = items[i].shell == 0 ? &items[j] : &items[i];
      bk_vec3 where = {0, 0, 0};
      contact_kind kind = test(shell[0], a->triangle, shell[1], b->triangle, eps, &where);
      if (kind == CONTACT_NONE || (kind == CONTACT_TOUCH && found == CONTACT_TOUCH)) continue;
      found = kind;
      *at = where;
      if (found == CONTACT_OVERLAP) break;
    }
  bk_free(items);
  return found;
}

// Is p on a triangle of `mesh` (within `eps` of it)?
static bool on_surface(const bk_mesh* mesh, bk_vec3 p, double eps) {
  bk_aabb point = grown((bk_aabb){p, p}, eps);
  for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
    if (!boxes_overlap(point, triangle_box(mesh, t))) continue;
    bk_vec3 corner[3];
    for (uint32_t k = 0; k < 3; ++k)
      corner[k] = mesh->positions[bk_mesh_tri_position(mesh, t, k)];
    double t0 = 0.0, t1 = 0.0;
    if (segment_in_triangle(p, p, corner, eps, &t0, &t1)) return true;
  }
  return false;
}

// (b): is a vertex of `inner` inside `outer`? Up to 32 of its vertices,
// spread over its position list, are tried: after (a) found no crossing one
// would do, but a crossing (a) missed as degenerate often leaves some vertex
// inside, and any vertex strictly inside means the solids overlap. A vertex
// on outer's surface is not inside, whatever its winding number says (on a
// face it is 1/2 only up to the sign of a zero: 0 or 1 as often).
static bool vertex_inside(const bk_mesh* inner, const bk_mesh* outer, bk_aabb outer_box, double eps,
                          bk_vec3* at) {
  uint32_t n = inner->position_count, tries = n < 32 ? n : 32;
  for (uint32_t k = 0; k < tries; ++k) {
    bk_vec3 p = inner->positions[(uint32_t)((uint64_t)k * n / tries)];
    bk_aabb point = {p, p};
    if (!boxes_overlap(point, outer_box)) continue;
    if (bk_mesh_winding_number(outer, NULL, 0, p) > 0.75 && !on_surface(outer, p, eps)) {
      *at = p;
      return true;
    }
  }
  return false;
}

// Overlap (a, b), else touch (c), else neither; *at where.
static contact_kind shells_meet(const bk_mesh* a, const bk_mesh* b, bk_aabb box_a, bk_aabb box_b,
                                bk_vec3* at) {
  bk_aabb both = {bk_v3_min(box_a.min, box_b.min), bk_v3_max(box_a.max, box_b.max)};
  double eps = 1e-9 * bk_v3_length(bk_v3_sub(both.max, both.min));
  const bk_mesh* const shell[2] = {a, b};
  const bk_aabb box[2] = {box_a, box_b};
  if (sweep_pairs(shell, box, eps, 0.0, triangles_cross_kind, at) == CONTACT_OVERLAP ||
      vertex_inside(b, a, box_a, eps, at) || vertex_inside(a, b, box_b, eps, at))
    return CONTACT_OVERLAP;
  // Surfaces within the tolerance of each other count: grown by it, the boxes meet.
  const bk_aabb box_grown[2] = {grown(box_a, eps), grown(box_b, eps)};
  return sweep_pairs(shell, box_grown, eps, eps, triangles_touch, at);
}

typedef struct shell_order {
  double min_x;
  uint32_t shell;
} shell_order;

static int compare_shells(const void* pa, const void* pb) {
  const shell_order *a = pa, *b = pb;
  if (a->min_x != b->min_x) return a->min_x < b->min_x ? -1 : 1;
  return a->shell < b->shell ? -1 : (a->shell > b->shell);
}

uint32_t bk_mesh_split_overlapping_shells(const bk_mesh* mesh, bk_mesh** parts,
                                          bk_fracture_overlap* overlap) {
  *parts = NULL;
  memset(overlap, 0, sizeof *overlap);
  bk_mesh copy = {0};
  bk_mesh_copy(&copy, mesh);
  bk_mesh* shells = NULL;
  uint32_t count = bk_mesh_split_hulls(&copy, &shells);
  bk_aabb* box = bk_alloc(sizeof(bk_aabb) * count);
  bk_aabb* reach = bk_alloc(sizeof(bk_aabb) * count);
  shell_order* order = bk_alloc(sizeof(shell_order) * count);
  uint8_t* overlapping = bk_calloc(count, 1);
  // Shells within a pair's tolerance of each other may touch (c): their
  // boxes grown by the largest such tolerance (the whole mesh's) must meet.
  bk_aabb whole = bk_mesh_bounds(mesh);
  double reach_by = 1e-9 * bk_v3_length(bk_v3_sub(whole.max, whole.min));
  for (uint32_t s = 0; s < count; ++s) {
    box[s] = bk_mesh_bounds(&shells[s]);
    reach[s] = grown(box[s], reach_by);
    order[s] = (shell_order){reach[s].min.x, s};
  }
  // Shell pairs whose grown boxes meet, swept along x; the first pair (in
  // shell order) that overlaps or touches is the one named.
  bk_sort(order, count, sizeof *order, compare_shells);
  for (uint32_t i = 0; i < count; ++i)
    for (uint32_t j = i + 1; j < count && order[j].min_x <= reach[order[i].shell].max.x; ++j) {
      uint32_t a = order[i].shell, b = order[j].shell;
      if (a > b) a = order[j].shell, b = order[i].shell;
      if (!boxes_overlap(reach[a], reach[b])) continue;
      bk_vec3 at = {0, 0, 0};
      contact_kind kind = shells_meet(&shells[a], &shells[b], box[a], box[b], &at);
      if (kind == CONTACT_NONE) continue;
      overlapping[a] = overlapping[b] = 1;
      overlap->pairs++;
      overlap->touching_pairs += kind == CONTACT_TOUCH;
      if (overlap->pairs == 1 || a + 1 < overlap->shell_a ||
          (a + 1 == overlap->shell_a && b + 1 < overlap->shell_b)) {
        overlap->shell_a = a + 1;
        overlap->shell_b = b + 1;
        overlap->touching = kind == CONTACT_TOUCH;
        overlap->volume_a = bk_mesh_volume(&shells[a]);
        overlap->volume_b = bk_mesh_volume(&shells[b]);
        overlap->point = at;
      }
    }
  uint32_t part_count = 0;
  if (overlap->pairs) {
    // Each shell that overlaps or touches another is a part of its own, in
    // shell order; all the others together are one more part, last.
    *parts = bk_calloc(count, sizeof(bk_mesh));
    bk_mesh rest = {0};
    for (uint32_t s = 0; s < count; ++s) {
      if (overlapping[s]) {
        overlap->shells++;
        (*parts)[part_count++] = shells[s];
        memset(&shells[s], 0, sizeof shells[s]);
      } else {
        bk_mesh_append(&rest, &shells[s]);
      }
    }
    if (rest.triangle_count)
      (*parts)[part_count++] = rest;
    else
      bk_mesh_free(&rest);
  }
  for (uint32_t s = 0; s < count; ++s)
    bk_mesh_free(&shells[s]);
  bk_free(shells);
  bk_free(box);
  bk_free(reach);
  bk_free(order);
  bk_free(overlapping);
  return part_count;
}
