// Overlapping closed shells: two solids of one source that interpenetrate
// or nest (a cube exported inside a cube). A plane through both crosses them
// in cross-sections that overlap, which no cap can close, so such shells are
// fractured each on its own (see bk_mesh_tree_build).
//
// Two closed shells overlap when (a) their surfaces cross, or (b) one lies
// inside the other without crossing. (a) is found by an edge of one crossing
// a triangle of the other strictly: its ends more than a tolerance on either
// side of the triangle's plane and the crossing point more than the tolerance
// inside all three edges. (b), once (a) found nothing, is decided by a
// vertex of a shell: either all of it is inside the other or none is, and
// the winding number of the other (cavities included, so a solid inside an
// eggshell's cavity is outside it) tells which; vertices on the other's
// surface (winding about 1/2) do not count, so up to 32 are tried (which also
// catches crossings (a) skipped as degenerate, such as two cubes whose edges
// cross each other's faces exactly on a face's diagonal, when a corner of one
// lies inside the other). The strict tolerances mean shells
// that only touch (coincident faces, an edge on a face) never count as
// overlapping: a cut through them still caps. Only exactly degenerate
// overlaps (every crossing through an edge or a vertex of the other, and no
// vertex strictly inside) escape; the build then cuts them together as
// before and its shortfall reports what could not be capped.
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

// (a): some triangle of one crosses a triangle of the other. Triangles
// outside the other shell's box are dropped, the rest swept along x.
static bool surfaces_cross(const bk_mesh* const shell[2], const bk_aabb box[2], double eps, bk_vec3* at) {
  sweep_item* items =
      bk_alloc(sizeof(sweep_item) * ((size_t)shell[0]->triangle_count + shell[1]->triangle_count + 1));
  uint32_t count = 0;
  for (uint32_t s = 0; s < 2; ++s)
    for (uint32_t t = 0; t < shell[s]->triangle_count; ++t) {
      bk_aabb tb = triangle_box(shell[s], t);
      if (boxes_overlap(tb, box[1 - s])) items[count++] = (sweep_item){tb, s, t};
    }
  qsort(items, count, sizeof *items, compare_items);
  bool crossed = false;
  for (uint32_t i = 0; i < count && !crossed; ++i)
    for (uint32_t j = i + 1; j < count && items[j].box.min.x <= items[i].box.max.x; ++j) {
      if (items[j].shell == items[i].shell || !boxes_overlap(items[i].box, items[j].box)) continue;
      const sweep_item* a = items[i].shell == 0 ? &items[i] : &items[j];
      const sweep_item* b = items[i].shell == 0 ? &items[j] : &items[i];
      if (triangles_cross(shell[0], a->triangle, shell[1], b->triangle, eps, at)) {
        crossed = true;
        break;
      }
    }
  free(items);
  return crossed;
}

// (b): is a vertex of `inner` inside `outer`? Up to 32 of its vertices,
// spread over its position list, are tried: after (a) found no crossing one
// would do, but a crossing (a) missed as degenerate often leaves some vertex
// inside, and any vertex strictly inside means the solids overlap.
static bool vertex_inside(const bk_mesh* inner, const bk_mesh* outer, bk_aabb outer_box, bk_vec3* at) {
  uint32_t n = inner->position_count, tries = n < 32 ? n : 32;
  for (uint32_t k = 0; k < tries; ++k) {
    bk_vec3 p = inner->positions[(uint32_t)((uint64_t)k * n / tries)];
    bk_aabb point = {p, p};
    if (!boxes_overlap(point, outer_box)) continue;
    if (bk_mesh_winding_number(outer, NULL, 0, p) > 0.75) {
      *at = p;
      return true;
    }
  }
  return false;
}

static bool shells_overlap(const bk_mesh* a, const bk_mesh* b, bk_aabb box_a, bk_aabb box_b, bk_vec3* at) {
  bk_aabb both = {bk_v3_min(box_a.min, box_b.min), bk_v3_max(box_a.max, box_b.max)};
  double eps = 1e-9 * bk_v3_length(bk_v3_sub(both.max, both.min));
  const bk_mesh* const shell[2] = {a, b};
  const bk_aabb box[2] = {box_a, box_b};
  return surfaces_cross(shell, box, eps, at) || vertex_inside(b, a, box_a, at) ||
         vertex_inside(a, b, box_b, at);
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
  shell_order* order = bk_alloc(sizeof(shell_order) * count);
  uint8_t* overlapping = bk_calloc(count, 1);
  for (uint32_t s = 0; s < count; ++s) {
    box[s] = bk_mesh_bounds(&shells[s]);
    order[s] = (shell_order){box[s].min.x, s};
  }
  // Shell pairs whose boxes meet, swept along x; the first overlapping pair
  // in shell order is the one named.
  qsort(order, count, sizeof *order, compare_shells);
  for (uint32_t i = 0; i < count; ++i)
    for (uint32_t j = i + 1; j < count && order[j].min_x <= box[order[i].shell].max.x; ++j) {
      uint32_t a = order[i].shell, b = order[j].shell;
      if (a > b) a = order[j].shell, b = order[i].shell;
      if (!boxes_overlap(box[a], box[b])) continue;
      bk_vec3 at;
      if (!shells_overlap(&shells[a], &shells[b], box[a], box[b], &at)) continue;
      overlapping[a] = overlapping[b] = 1;
      overlap->pairs++;
      if (overlap->pairs == 1 || a + 1 < overlap->shell_a ||
          (a + 1 == overlap->shell_a && b + 1 < overlap->shell_b)) {
        overlap->shell_a = a + 1;
        overlap->shell_b = b + 1;
        overlap->volume_a = bk_mesh_volume(&shells[a]);
        overlap->volume_b = bk_mesh_volume(&shells[b]);
        overlap->point = at;
      }
    }
  uint32_t part_count = 0;
  if (overlap->pairs) {
    // Each overlapping shell is a part of its own, in shell order; all the
    // others together are one more part, last.
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
  free(shells);
  free(box);
  free(order);
  free(overlapping);
  return part_count;
}
