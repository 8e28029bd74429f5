// The source's surface inside each cell: every source triangle that may meet
// the cell is clipped by the cell's bisectors (a convex polygon clip). New
// vertices are named by what made them (a source edge and two seeds, or a
// triangle and three seeds), so the neighbour cell that clips the same
// triangle from the other side makes the very same vertices.
#include <stdlib.h>
#include <string.h>

#include "cell_complex.h"

typedef struct poly {
  uint32_t* v;
  int32_t* sup; // edge k: >= 0 the bisector with that seed, -1 - e along triangle edge e
  uint32_t count, capacity;
} poly;

static void poly_push(poly* p, uint32_t v, int32_t sup) {
  if (p->count == p->capacity) {
    p->capacity = bk_grow_capacity(p->capacity, p->count + 1);
    p->v = bk_realloc(p->v, sizeof(uint32_t) * p->capacity);
    p->sup = bk_realloc(p->sup, sizeof(int32_t) * p->capacity);
  }
  p->v[p->count] = v;
  p->sup[p->count] = sup;
  p->count++;
}

static void sort3(int32_t* s) {
  for (int i = 1; i < 3; ++i)
    for (int j = i; j > 0 && s[j - 1] > s[j]; --j) {
      int32_t t = s[j];
      s[j] = s[j - 1];
      s[j - 1] = t;
    }
}

// The vertex where edge k of the polygon (of triangle t) crosses the bisector
// of `cell` and m.
static uint32_t edge_crossing(bk_cell_complex* cx, uint32_t t, int32_t sup, uint32_t cell, int32_t m) {
  bk_cell_key k = {0};
  if (sup < 0) {
    int e = -1 - sup;
    uint32_t pa = bk_mesh_tri_position(cx->source, t, e),
             pb = bk_mesh_tri_position(cx->source, t, (e + 1) % 3);
    k.kind = BK_CELL_CROSSING;
    k.a = pa < pb ? pa : pb;
    k.b = pa < pb ? pb : pa;
    k.s[0] = (int32_t)cell < m ? (int32_t)cell : m;
    k.s[1] = (int32_t)cell < m ? m : (int32_t)cell;
  } else {
    k.kind = BK_CELL_PIERCING;
    k.a = t;
    k.s[0] = (int32_t)cell, k.s[1] = sup, k.s[2] = m;
    sort3(k.s);
  }
  return bk_cell_vertex(cx, &k);
}

void bk_cell_clip_surface(bk_cell_complex* cx, uint32_t cell, const bk_cell_polytope* cp,
                          const uint32_t* triangles, uint32_t triangle_count, bk_cell_surface* out) {
  poly a = {0}, b = {0};
  uint8_t* inside = NULL;
  uint32_t inside_capacity = 0;
  // The cell's bisectors, and its bounds to skip triangles that miss it.
  bk_cell_side* sides = bk_alloc(sizeof(bk_cell_side) * (cp->faces ? cp->faces : 1));
  for (uint32_t f = 0; f < cp->faces; ++f)
    if (cp->planes[f] >= 0) sides[f] = bk_cell_side_of(cx, (int32_t)cell, cp->planes[f]);
  bk_aabb bounds = {cx->points[cp->loop[0]], cx->points[cp->loop[0]]};
  for (uint32_t i = 1; i < cp->loop_count; ++i) {
    bounds.min = bk_v3_min(bounds.min, cx->points[cp->loop[i]]);
    bounds.max = bk_v3_max(bounds.max, cx->points[cp->loop[i]]);
  }
  for (uint32_t ti = 0; ti < triangle_count; ++ti) {
    uint32_t t = triangles[ti];
    bk_vec3 p0 = cx->source->positions[bk_mesh_tri_position(cx->source, t, 0)];
    bk_vec3 p1 = cx->source->positions[bk_mesh_tri_position(cx->source, t, 1)];
    bk_vec3 p2 = cx->source->positions[bk_mesh_tri_position(cx->source, t, 2)];
    bk_vec3 lo = bk_v3_min(p0, bk_v3_min(p1, p2)), hi = bk_v3_max(p0, bk_v3_max(p1, p2));
    if (lo.x > bounds.max.x || lo.y > bounds.max.y || lo.z > bounds.max.z || hi.x < bounds.min.x ||
        hi.y < bounds.min.y || hi.z < bounds.min.z)
      continue;
    a.count = 0;
    for (int k = 0; k < 3; ++k)
      poly_push(&a, bk_cell_source_vertex(cx, bk_mesh_tri_position(cx->source, t, k)), -1 - k);
    for (uint32_t f = 0; f < cp->faces && a.count; ++f) {
      int32_t m = cp->planes[f];
      if (m < 0) continue; // box planes lie outside the source
      if (inside_capacity < a.count) {
        inside_capacity = a.count;
        inside = bk_realloc(inside, inside_capacity);
      }
      bool any_out = false, any_in = false;
      for (uint32_t k = 0; k < a.count; ++k) {
        inside[k] = bk_cell_side_keeps(&sides[f], cx->points[a.v[k]]);
        any_out |= !inside[k];
        any_in |= inside[k];
      }
      if (!any_out) continue;
      if (!any_in) {
        a.count = 0;
        break;
      }
      b.count = 0;
      for (uint32_t k = 0; k < a.count; ++k) {
        uint32_t next = (k + 1) % a.count;
        if (inside[k] && inside[next]) {
          poly_push(&b, a.v[k], a.sup[k]);
        } else if (inside[k]) { // leaving: this edge ends at the crossing, then runs along m
          poly_push(&b, a.v[k], a.sup[k]);
          poly_push(&b, edge_crossing(cx, t, a.sup[k], cell, m), m);
        } else if (inside[next]) { // entering: from the crossing on along this edge
          poly_push(&b, edge_crossing(cx, t, a.sup[k], cell, m), a.sup[k]);
        }
      }
      poly tmp = a;
      a = b;
      b = tmp;
      if (a.count < 3) a.count = 0;
    }
    if (a.count < 3) continue;
    if (out->polygon_count == out->polygon_capacity) {
      out->polygon_capacity = bk_grow_capacity(out->polygon_capacity, out->polygon_count + 1);
      out->polygons = bk_realloc(out->polygons, sizeof(bk_cell_polygon) * out->polygon_capacity);
    }
    if (out->vertex_count + a.count > out->vertex_capacity) {
      out->vertex_capacity = bk_grow_capacity(out->vertex_capacity, out->vertex_count + a.count);
      out->vertices = bk_realloc(out->vertices, sizeof(uint32_t) * out->vertex_capacity);
      out->supports = bk_realloc(out->supports, sizeof(int32_t) * out->vertex_capacity);
    }
    out->polygons[out->polygon_count++] = (bk_cell_polygon){t, out->vertex_count, a.count};
    memcpy(out->vertices + out->vertex_count, a.v, sizeof(uint32_t) * a.count);
    memcpy(out->supports + out->vertex_count, a.sup, sizeof(int32_t) * a.count);
    out->vertex_count += a.count;
  }
  bk_free(sides);
  bk_free(a.v);
  bk_free(a.sup);
  bk_free(b.v);
  bk_free(b.sup);
  bk_free(inside);
}

void bk_cell_surface_free(bk_cell_surface* s) {
  bk_free(s->polygons);
  bk_free(s->vertices);
  bk_free(s->supports);
  memset(s, 0, sizeof *s);
}

// ---------------------------------------------------------------- inside test

// Parity of the crossings of a ray from each point towards +z. The
// triangles are binned once on an x-y grid, so each point only meets the
// triangles over its bin. A point exactly on a projected edge counts for one
// side only (the half-open rule), so shared edges are not counted twice.
static bool covers(double ax, double ay, double bx, double by, double px, double py) {
  double e = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
  if (e != 0.0) return e > 0.0;
  return bx < ax || (bx == ax && by < ay);
}

typedef struct inside_triangle {
  bk_vec3 p[3]; // counter-clockwise seen from +z
  double area;  // twice the projected area, > 0
} inside_triangle;

struct bk_inside_test {
  bk_aabb box;
  int n;
  double sx, sy; // bin size; not > 0 for a flat source (nothing is inside)
  inside_triangle* triangles;
  uint32_t *start, *items; // per bin, the triangles over it
};

static int inside_bin(double v, double lo, double size, int n) {
  double c = floor((v - lo) / size);
  return c >= 0.0 ? (c < n ? (int)c : n - 1) : 0;
}

bk_inside_test* bk_inside_test_create(const bk_mesh* m) {
  bk_inside_test* t = bk_calloc(1, sizeof *t);
  t->box = bk_mesh_bounds(m);
  // About two triangles per bin.
  t->n = (int)fmin(fmax(sqrt((double)m->triangle_count / 2.0), 1.0), 512.0);
  t->sx = (t->box.max.x - t->box.min.x) / t->n, t->sy = (t->box.max.y - t->box.min.y) / t->n;
  t->triangles = bk_alloc(sizeof(inside_triangle) * (m->triangle_count ? m->triangle_count : 1));
  t->start = bk_calloc((size_t)t->n * t->n + 1, sizeof(uint32_t));
  if (!(t->sx > 0.0) || !(t->sy > 0.0)) return t;
  uint32_t kept = 0;
  for (uint32_t i = 0; i < m->triangle_count; ++i) {
    inside_triangle* tri = &t->triangles[kept];
    for (int k = 0; k < 3; ++k)
      tri->p[k] = m->positions[bk_mesh_tri_position(m, i, k)];
    bk_vec3* p = tri->p;
    tri->area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
    if (tri->area == 0.0) continue; // seen edge-on: no ray goes through it
    if (tri->area < 0.0) {
      bk_vec3 swap = p[1];
      p[1] = p[2];
      p[2] = swap;
      tri->area = -tri->area;
    }
    kept++;
  }
  // Two passes over the triangles' bins: count, then fill.
  for (int pass = 0; pass < 2; ++pass) {
    uint32_t* fill = NULL;
    if (pass == 1) {
      for (int b = 0; b < t->n * t->n; ++b)
        t->start[b + 1] += t->start[b];
      t->items = bk_alloc(sizeof(uint32_t) * (t->start[t->n * t->n] ? t->start[t->n * t->n] : 1));
      fill = bk_alloc(sizeof(uint32_t) * ((size_t)t->n * t->n));
      memcpy(fill, t->start, sizeof(uint32_t) * (size_t)t->n * t->n);
    }
    for (uint32_t i = 0; i < kept; ++i) {
      const bk_vec3* p = t->triangles[i].p;
      double minx = fmin(p[0].x, fmin(p[1].x, p[2].x)), maxx = fmax(p[0].x, fmax(p[1].x, p[2].x));
      double miny = fmin(p[0].y, fmin(p[1].y, p[2].y)), maxy = fmax(p[0].y, fmax(p[1].y, p[2].y));
      int x0 = inside_bin(minx, t->box.min.x, t->sx, t->n), x1 = inside_bin(maxx, t->box.min.x, t->sx, t->n);
      int y0 = inside_bin(miny, t->box.min.y, t->sy, t->n), y1 = inside_bin(maxy, t->box.min.y, t->sy, t->n);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          if (pass == 0)
            t->start[y * t->n + x + 1]++;
          else
            t->items[fill[y * t->n + x]++] = i;
        }
    }
    bk_free(fill);
  }
  return t;
}

void bk_inside_test_destroy(bk_inside_test* t) {
  if (!t) return;
  bk_free(t->triangles);
  bk_free(t->start);
  bk_free(t->items);
  bk_free(t);
}

void bk_inside_test_run(const bk_inside_test* t, const bk_vec3* pts, uint32_t count, uint8_t* inside) {
  memset(inside, 0, count);
  if (!count || !(t->sx > 0.0) || !(t->sy > 0.0)) return;
  // Points outside the grid a batch of `count` points was binned on are
  // outside, as they always were (compared as doubles: a point far away or
  // not finite has no bin).
  int n = (int)fmin(fmax(sqrt((double)count) / 2.0, 1.0), 512.0);
  double sx = (t->box.max.x - t->box.min.x) / n, sy = (t->box.max.y - t->box.min.y) / n;
  for (uint32_t i = 0; i < count; ++i) {
    double px = pts[i].x, py = pts[i].y;
    double fx = floor((px - t->box.min.x) / sx), fy = floor((py - t->box.min.y) / sy);
    if (!(fx >= 0.0 && fy >= 0.0 && fx < n && fy < n)) continue;
    int b = inside_bin(py, t->box.min.y, t->sy, t->n) * t->n + inside_bin(px, t->box.min.x, t->sx, t->n);
    for (uint32_t k = t->start[b]; k < t->start[b + 1]; ++k) {
      const inside_triangle* tri = &t->triangles[t->items[k]];
      const bk_vec3* p = tri->p;
      if (!covers(p[0].x, p[0].y, p[1].x, p[1].y, px, py) ||
          !covers(p[1].x, p[1].y, p[2].x, p[2].y, px, py) || !covers(p[2].x, p[2].y, p[0].x, p[0].y, px, py))
        continue;
      double w0 = ((p[1].x - px) * (p[2].y - py) - (p[1].y - py) * (p[2].x - px)) / tri->area;
      double w1 = ((p[2].x - px) * (p[0].y - py) - (p[2].y - py) * (p[0].x - px)) / tri->area;
      double z = w0 * p[0].z + w1 * p[1].z + (1.0 - w0 - w1) * p[2].z;
      if (z > pts[i].z) inside[i] ^= 1;
    }
  }
}

void bk_points_inside(const bk_mesh* m, const bk_vec3* pts, uint32_t count, uint8_t* inside) {
  bk_inside_test* t = bk_inside_test_create(m);
  bk_inside_test_run(t, pts, count, inside);
  bk_inside_test_destroy(t);
}
